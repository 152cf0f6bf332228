"""A pre-pass over MaterialX XML with the standard library's expat parser.

MaterialX's Python API keeps no line numbers and silently keeps the first of two same-named
children. This pass records, for every named element, its name path (as ``Element.getNamePath()``
spells it) and line, and collects same-named siblings, so diagnostics can point at lines and
duplicate inputs can be reported. It also rejects malformed XML with expat's line and column.
expat does not fetch external entities, and Python's expat has amplification limits against
entity-expansion bombs.
"""

from __future__ import annotations

import codecs
import re
from dataclasses import dataclass, field
from xml.parsers import expat

# Inline suppression: ``<!-- openpbr-ignore: OPBR301, OPBR302 -->`` before an element applies to
# it (and what it contains); ``openpbr-ignore-file:`` applies to the whole document. The same
# marker in an element's ``doc`` attribute applies to that element.
SUPPRESSION = re.compile(r"openpbr-ignore(-file)?\s*:\s*((?:all|OPBR\d+)(?:\s*,\s*(?:all|OPBR\d+))*)")


_DECLARED_ENCODING = re.compile(rb"""^<\?xml[^>]*?\sencoding\s*=\s*["']([A-Za-z][A-Za-z0-9._-]*)["']""")
_BOMS = ((codecs.BOM_UTF32_LE, "utf-32"), (codecs.BOM_UTF32_BE, "utf-32"), (codecs.BOM_UTF8, "utf-8-sig"),
         (codecs.BOM_UTF16_LE, "utf-16"), (codecs.BOM_UTF16_BE, "utf-16"))


def decode_document(data: bytes) -> str:
    """The text of an XML document in the encoding XML 1.0 (4.3.3, Appendix F) gives it: a byte-order mark's
    (UTF-8, UTF-16, UTF-32), else the declaration's ``encoding`` (ISO-8859-1, windows-1252), else UTF-8, as
    MaterialX's parser (pugixml) reads a file. The declaration in the result says UTF-8: the text is handed
    to MaterialX as a string, which it reads as UTF-8 (a Latin-1 declaration would make it decode twice).
    Raises UnicodeDecodeError (or LookupError for an encoding Python does not know)."""
    encoding = next((name for bom, name in _BOMS if data.startswith(bom)), None)
    if encoding is None:
        declared = _DECLARED_ENCODING.match(data)
        encoding = declared.group(1).decode("ascii") if declared else "utf-8"
    text = data.decode(encoding)
    return re.sub(r"""^(<\?xml[^>]*?\sencoding\s*=\s*["'])[^"']*(["'])""", r"\g<1>UTF-8\g<2>", text, count=1)


def parse_suppression(text: str) -> tuple[bool, frozenset[str]] | None:
    """``(whole_file, codes)`` of a suppression marker in ``text``, or ``None``."""
    match = SUPPRESSION.search(text)
    if match is None:
        return None
    return bool(match.group(1)), frozenset(c.strip() for c in match.group(2).split(","))


@dataclass(slots=True)
class XmlScan:
    root_tag: str | None = None
    root_attributes: dict[str, str] = field(default_factory=dict)
    lines: dict[str, int] = field(default_factory=dict)
    # name path -> list of (line, attributes) for second and later same-named siblings
    duplicates: dict[str, list[tuple[int, dict[str, str]]]] = field(default_factory=dict)
    has_doctype: bool = False
    xincludes: list[tuple[int, str]] = field(default_factory=list)
    suppressions: dict[str, frozenset[str]] = field(default_factory=dict)


class XmlSyntaxError(ValueError):
    """Malformed XML. ``fatal`` marks input refused on principle (a DOCTYPE, hostile nesting),
    which must not be handed to MaterialX's lenient parser either."""

    def __init__(self, message: str, line: int | None, column: int | None, fatal: bool = False):
        super().__init__(message)
        self.line = line
        self.column = column
        self.fatal = fatal


class _Refused(Exception):
    pass


# MaterialX documents are a few levels deep; MaterialX builds its tree recursively, so a hostile
# file nested thousands deep could exhaust the stack. Deeper than this is refused.
MAX_DEPTH = 64


def scan(data: bytes) -> XmlScan:
    result = XmlScan()
    parser = expat.ParserCreate()
    stack: list[str | None] = []
    seen_lines = result.lines
    pending: list[frozenset[str]] = []

    def suppress(path: str, codes: frozenset[str]) -> None:
        result.suppressions[path] = result.suppressions.get(path, frozenset()) | codes

    def comment(text: str) -> None:
        found = parse_suppression(text)
        if found is None:
            return
        whole_file, codes = found
        if whole_file or result.root_tag is None:
            suppress("", codes)
        else:
            pending.append(codes)

    def start(tag: str, attributes: dict[str, str]) -> None:
        line = parser.CurrentLineNumber
        if len(stack) >= MAX_DEPTH:
            raise _Refused(f"elements nested deeper than {MAX_DEPTH} levels", line)
        claimed = frozenset().union(*pending) if pending else None
        pending.clear()
        if result.root_tag is None:
            result.root_tag = tag
            result.root_attributes = dict(attributes)
            stack.append("")
            return
        if tag.endswith("include") and ("href" in attributes):
            result.xincludes.append((line, attributes["href"]))
        name = attributes.get("name")
        parent = stack[-1]
        if name is None or parent is None:
            stack.append(None)
            return
        path = f"{parent}/{name}" if parent else name
        if path in seen_lines:
            result.duplicates.setdefault(path, []).append((line, dict(attributes)))
            stack.append(None)
            return
        seen_lines[path] = line
        if claimed:
            suppress(path, claimed)
        stack.append(path)

    def end(tag: str) -> None:
        stack.pop()

    def doctype(*_args) -> None:
        # MaterialX has no DTD; a DOCTYPE can only declare entities (expansion bombs, external files).
        result.has_doctype = True
        raise _Refused("DOCTYPE declarations are not allowed in MaterialX documents (entity expansion)",
                       parser.CurrentLineNumber)

    parser.StartElementHandler = start
    parser.EndElementHandler = end
    parser.StartDoctypeDeclHandler = doctype
    parser.CommentHandler = comment
    try:
        parser.Parse(_escape_tile_tokens(data), True)
    except expat.ExpatError as error:
        raise XmlSyntaxError(expat.ErrorString(error.code), error.lineno, error.offset) from None
    except (LookupError, ValueError) as error:  # an XML declaration naming an unknown or multi-byte encoding
        raise XmlSyntaxError(f"unusable encoding in the XML declaration: {error}", 1, None, fatal=True) from None
    except _Refused as refused:
        message, line = refused.args
        raise XmlSyntaxError(message, line, None, fatal=True) from None
    return result


def _escape_tile_tokens(data: bytes) -> bytes:
    """MaterialX writes ``<UDIM>`` and ``<UVTILE>`` unescaped inside attribute values, which XML
    forbids and pugixml tolerates; escape them for expat (same length in lines, so line numbers hold)."""
    if b"<UDIM>" not in data and b"<UVTILE>" not in data:
        return data
    return data.replace(b"<UDIM>", b"&lt;UDIM&gt;").replace(b"<UVTILE>", b"&lt;UVTILE&gt;")


def message_sites(document, message: str) -> dict[str, tuple[str, str | None]]:
    """Where each line of MaterialX's ``Document.validate()`` message points: a line ends with the
    offending element as ``Element.asString()`` prints it (``Cycle in upstream path: <output name="out"
    ...>``), given as (name path, ``None``), or for an input (its node's name path, its name). Lines
    naming no element, or an element printed the same as another (two graphs' ``in1`` inputs), are left
    out: a place is given only when it is certain."""
    printed: dict[str, tuple[str, str | None] | None] = {}
    for element in document.traverseTree():
        site = (element.getParent().getNamePath(), element.getName()) if element.getCategory() == "input" \
            else (element.getNamePath(), None)
        text = element.asString()
        printed[text] = None if text in printed else site
    sites = {}
    for line in message.strip().splitlines():
        at = line.find(": <")
        if at >= 0 and printed.get(line[at + 2:]) is not None:
            sites[line] = printed[line[at + 2:]]
    return sites


def upgrade_changes_nothing(data: bytes, document, version: str | None) -> bool:
    """Whether ``data``, a document of ``version`` older than 1.39, came through MaterialX's upgrade
    (``Document::upgradeVersion``, run when it was read into ``document``) with nothing changed but the
    version attribute: the same elements with the same attributes, in the same order. ``False`` for a
    current (or unparsable) version and for documents with XIncludes (not compared)."""
    try:
        if tuple(int(p) for p in (version or "").split(".")[:2]) >= (1, 39):
            return False
    except ValueError:
        return False
    import xml.etree.ElementTree as ElementTree  # lazy: only old documents are compared

    import MaterialX as mx  # lazy: as the reader's

    def shape(element, root: bool = False):
        attributes = {k: v for k, v in element.attrib.items() if not (root and k == "version")}
        return element.tag, attributes, [shape(child) for child in element]

    try:
        before = ElementTree.fromstring(_escape_tile_tokens(data))  # a raw <UDIM> in a value, as scan() reads it
        after = ElementTree.fromstring(_escape_tile_tokens(mx.writeToXmlString(document).encode("utf-8")))
    except (ElementTree.ParseError, ValueError):
        return False
    if any(child.tag.endswith("}include") or child.tag == "xi:include" for child in before.iter()):
        return False
    return shape(before, root=True) == shape(after, root=True)


def scan_with_materialx(text: str) -> XmlScan | None:
    """A scan without line numbers from a document only MaterialX can parse, or ``None``."""
    import MaterialX as mx  # lazy: MaterialX loads only when a document is read

    document = mx.createDocument()
    options = mx.XmlReadOptions()
    options.readXIncludeFunction = None
    try:
        mx.readFromXmlString(document, text, mx.FileSearchPath(), options)
    except Exception:  # MaterialX raises its own exception types for parse failures
        return None
    attributes = {name: document.getAttribute(name) for name in document.getAttributeNames()}
    return XmlScan(root_tag="materialx", root_attributes=attributes)
