"""usd-core plumbing shared by the USD reader and writer: opening a stage safely and without noise,
teaching Sdr the MaterialX node definitions, and asking usd-core's own validators.

``pxr`` is imported inside the functions only (``from pxr import Usd`` costs 0.2-0.5 s).

usd-core is not hardened against hostile files, so :class:`StageGuard` checks every layer before
usd-core parses it and every arc before usd-core follows it (limits below, all refusals are
read errors, exit code 2):

* size: a stage file (and every layer it composes) above ``OPENPBR_MAX_FILE_MB`` (64 MiB) is not
  read; a USDZ whose entries declare more than that uncompressed is refused (a zip bomb);
* text layers: brackets nested deeper than :data:`MAX_TEXT_NESTING` (1,000), outside strings,
  asset paths and comments, are refused: usd-core's parser would overflow the stack and crash;
* crate layers: every count and size in the table of contents and the structural sections must fit
  the section holding it (:func:`crate_problem`): usd-core allocates what a file declares first;
* packages: read as usd-core reads them (local file headers); more than
  :data:`MAX_PACKAGE_ENTRIES` entries, or a stored entry declaring a size it does not store, is
  refused; entry names that are absolute or climb out, and compressed entries, are reported;
* composition: at most :data:`MAX_LAYERS` layers; sublayers, references and payloads that are
  URLs, absolute paths, variable expressions or that climb (``..``, a symbolic link, the resolver's
  search path) out of the asset's folder are deleted from the in-memory layers before usd-core
  composes the stage, and reported: a file outside the folder is never opened. Value clips are
  always deleted (usd-core opens them lazily from anywhere, and enumerates a template's files).

usd-core on PyPI has no MaterialX plug-in, so its shader registry (Sdr) does not know
``ND_open_pbr_surface_surfaceshader`` and its ``ShaderSdrCompliance`` validator reports every
MaterialX shader as "not found in sdrRegistry". :func:`register_materialx_nodes` fills that gap: it
describes each MaterialX node definition as a USD shader definition (inputs typed as UsdMtlx types
them) in an in-memory layer and hands it to Sdr through UsdShade's own shader-definition parser,
the same route usd-core uses for ``UsdPreviewSurface``.
"""

from __future__ import annotations

import os
import re
import struct
from contextlib import contextmanager
from dataclasses import dataclass
from functools import lru_cache

from ...model import Location
from .. import ReadError, max_file_bytes, read_bytes
from .types import MATERIALX_TO_USD

# Pcp errors that mean "a layer of this stage could not be opened".
_MISSING_LAYER_ERRORS = ("ErrorInvalidSublayerPath", "ErrorInvalidAssetPath", "ErrorInvalidExternalTargetPath")
_TF_MESSAGE = re.compile(r"Error in '[^']*' at line \d+ in file [^\n]*? : '(.*?)'\s*(?=\n\s*Error in |\Z)", re.DOTALL)
_TEXT_POSITION = re.compile(r":(\d+):(\d+): ")


def require_pxr(path: str = "") -> None:
    """Import usd-core, or say how to install it."""
    try:
        from pxr import Usd  # noqa: F401
    except ImportError:
        raise ReadError(
            "unsupported", "reading or writing USD needs usd-core: pip install usd-core", Location(path)
        ) from None


@contextmanager
def quiet():
    """Capture usd-core's warnings and errors (which it otherwise prints to stderr) for the block;
    yields the list they are collected into. Python errors usd-core swallows (text in a crate file
    that is not UTF-8 becomes ``None``) are printed to ``sys.stderr`` by Python itself: captured too,
    in the main thread (``sys.stderr`` is global: threads swapping it would leave it swapped)."""
    import contextlib
    import io
    import threading

    from pxr import Tf

    collected: list[str] = []
    printed = io.StringIO()
    capture = contextlib.redirect_stderr(printed) if threading.current_thread() is threading.main_thread() \
        else contextlib.nullcontext()
    with Tf.DiagnosticTrap() as trap, capture:
        try:
            yield collected
        finally:
            collected.extend(_commentary(w) for w in trap.GetWarnings())
            collected.extend(_commentary(e) for e in trap.GetErrors())
            collected.extend(line for line in printed.getvalue().splitlines() if line.strip())
            trap.Clear()


# -- opening a stage without trusting it ------------------------------------------------------------
#
# usd-core is not hardened against hostile files: its text parser recurses once per nested bracket
# and overflows the stack (a segmentation fault, not an error), a value-clip template can make
# Usd.Stage.Open enumerate millions of file names, and composition opens whatever sublayers,
# references and payloads name, wherever they are. So before usd-core composes a stage, every
# layer it would open is found and judged here: its size, its nesting (text layers), its package
# (USDZ), and where each of its arcs points. Arcs leaving the asset's folder are deleted from the
# in-memory layers (never saved) and reported; value clips are always deleted.

#: Brackets nested deeper than this in a text layer are refused before usd-core parses it. Its
#: parser overflows an 8 MiB stack between 30,000 and 70,000 levels (less on smaller thread
#: stacks); real files stay far below 100.
MAX_TEXT_NESTING = 1000
#: A USDZ with more entries than this is refused.
MAX_PACKAGE_ENTRIES = 10_000
#: At most this many layers (sublayers, references, payloads, followed recursively) per stage.
MAX_LAYERS = 1000

_TEXT_SKIPPED = re.compile(  # what usd-core's text grammar reads as strings, asset paths or comments
    rb"'''(?:\\.|[^\\])*?'''|\"\"\"(?:\\.|[^\\])*?\"\"\""
    rb"|'(?:\\[^\r\n]|[^'\\\r\n])*'|\"(?:\\[^\r\n]|[^\"\\\r\n])*\""
    rb"|@@@(?:\\@@@|[^\r\n])*?@@@@?@?|@[^@\r\n]*@"
    rb"|#[^\r\n]*|//[^\r\n]*|/\*.*?\*/",
    re.DOTALL,
)
_UNTERMINATED = (b"'", b'"', b"@", b"/*")
_CRATE_MAGIC = b"PXR-USDC"
_ZIP_MAGIC = b"PK\x03\x04"
_LOCAL_HEADER = struct.Struct("<IHHHHHIIIHH")
_URL = re.compile(r"^[A-Za-z][A-Za-z0-9+.-]+:")
_DRIVE = re.compile(r"^[A-Za-z]:")
_LAYER_SUFFIXES = (".usd", ".usda", ".usdc")


def text_nesting_problem(data: bytes) -> tuple[str, int] | None:
    """(message, line) when brackets nest deeper than :data:`MAX_TEXT_NESTING` in a text layer,
    outside strings, asset paths and comments, else ``None``."""
    if sum(data.count(c) for c in (b"(", b"[", b"{")) <= MAX_TEXT_NESTING:
        return None  # cannot nest deeper than it opens
    code = _TEXT_SKIPPED.sub(lambda m: b"\n" * m.group().count(b"\n"), data)
    # an unterminated string, asset path or comment is a syntax error: usd-core stops there
    stops = [i for i in (code.find(token) for token in _UNTERMINATED) if i >= 0]
    if stops:
        code = code[: min(stops)]
    position = _deeper_than(code, MAX_TEXT_NESTING)
    if position is None:
        return None
    return f"brackets nest deeper than {MAX_TEXT_NESTING} levels", code.count(b"\n", 0, position) + 1


def _deeper_than(code: bytes, limit: int) -> int | None:
    import numpy as np

    step = np.zeros(256, dtype=np.int8)
    step[list(b"([{")] = 1
    step[list(b")]}")] = -1
    depth, chunk = 0, 1 << 22
    for start in range(0, len(code), chunk):
        running = np.cumsum(step[np.frombuffer(code, np.uint8, min(chunk, len(code) - start), start)], dtype=np.int64)
        running += depth
        over = np.flatnonzero(running > limit)
        if over.size:
            return start + int(over[0])
        depth = int(running[-1]) if running.size else depth
    return None


def crate_problem(data: bytes) -> str | None:
    """Why usd-core must not be handed these crate (``.usdc``) bytes, or ``None``.

    usd-core's crate reader checks every read against the file's end, but sizes its buffers from
    counts and sizes the file declares before reading them: a 1 KiB file declaring a 6 GB token
    table makes it allocate and touch 6 GB, and compressed integers longer than their count
    allows overrun its buffer. So every count and size in the table of contents and the structural
    sections (tokens, strings, fields, field sets, paths, specs) is checked against the section
    that must hold it: a compressed block cannot expand more than LZ4 can (255 times), and no
    buffer may exceed 64 times the file's size (real files expand less than 10 times)."""
    if len(data) < 88 or data[8] != 0:
        return None  # usd-core reports a bootstrap or version it cannot read, without reading further
    version = (data[9], data[10])
    (toc,) = struct.unpack_from("<q", data, 16)
    if not 0 <= toc <= len(data) - 8:
        return "its table of contents lies outside the file"
    (count,) = struct.unpack_from("<Q", data, toc)
    if count > (len(data) - toc - 8) // 32:
        return f"its table of contents declares {count} sections, more than the file holds"
    sections = {}
    for index in range(count):
        name, start, size = struct.unpack_from("<16sqq", data, toc + 8 + 32 * index)
        if start < 0 or size < 0 or start + size > len(data):
            return f"section {name.rstrip(bytes(1)).decode('latin-1')!r} lies outside the file"
        sections.setdefault(name.rstrip(bytes(1)).decode("latin-1"), (start, size))
    budget = 64 * len(data) + (1 << 20)
    for name, (start, size) in sections.items():
        problem = _crate_section_problem(name, data[start:start + size], version >= (4,), budget)
        if problem:
            return f"section {name}: {problem}"
    if "SPECS" in sections and version >= (4,):
        problem = _spec_types_problem(data, *sections["SPECS"])
        if problem:
            return f"section SPECS: {problem}"
    if "FIELDS" in sections:
        return _CrateValues(data, version, budget).problem(*sections["FIELDS"])
    return None


def _spec_types_problem(data: bytes, start: int, size: int) -> str | None:
    """A spec type outside usd-core's enum (1-11): usd-core range-checks only the values above it,
    so a negative one passes and later indexes its tables out of bounds (a segmentation fault)."""
    try:
        (count,) = struct.unpack_from("<Q", data, start)
        offset = start + 8
        for _ in range(2):  # path indexes, field set indexes: skipped
            offset += 8 + struct.unpack_from("<Q", data, offset)[0]
        types = _compressed_ints(data, offset, count)
    except (struct.error, ValueError, IndexError):
        return None  # usd-core reports it
    if types is None:
        return None
    bad = next((t for t in types if not 1 <= t <= 11), None)
    return None if bad is None else f"a spec type {bad - (1 << 32) if bad >= 1 << 31 else bad} is not one usd-core defines"


def _compressed_ints(data: bytes, offset: int, count: int) -> list[int] | None:
    """usd-core's compressed 32-bit integers (sdf/integerCoding.cpp): LZ4 over the encoding of
    each integer's difference to the previous one, as the most common difference (code 0) or an
    8-, 16- or 32-bit value (codes 1-3), the 2-bit codes first. Returns them unsigned."""
    (stored,) = struct.unpack_from("<Q", data, offset)
    block = data[offset + 8: offset + 8 + stored]
    if block[:1] != b"\0":
        return None
    codes_size = (2 * count + 7) // 8
    raw = _lz4_block(block[1:], 4 + codes_size + 4 * count)
    (common,) = struct.unpack_from("<i", raw, 0)
    codes, position, previous, found = raw[4:4 + codes_size], 4 + codes_size, 0, []
    formats = {1: ("<b", 1), 2: ("<h", 2), 3: ("<i", 4)}
    for index in range(count):
        code = codes[index // 4] >> 2 * (index % 4) & 3
        if code == 0:
            delta = common
        else:
            form, width = formats[code]
            (delta,) = struct.unpack_from(form, raw, position)
            position += width
        previous = (previous + delta + (1 << 31)) % (1 << 32) - (1 << 31)  # int32 arithmetic
        found.append(previous % (1 << 32))
    return found


# Crate value types (usd-core sdf/crateDataTypes.h) whose unpacking sizes a buffer from a count in the
# file: element sizes as stored.
_ARRAY_ELEMENT_BYTES = {
    1: 1, 2: 1, 3: 4, 4: 4, 5: 8, 6: 8, 7: 2, 8: 4, 9: 8, 10: 4, 11: 4, 12: 4, 13: 32, 14: 72, 15: 128,
    16: 32, 17: 16, 18: 8, 19: 16, 20: 8, 21: 4, 22: 8, 23: 24, 24: 12, 25: 6, 26: 12, 27: 32, 28: 16,
    29: 8, 30: 16, 56: 8, 57: 4,
}
_VECTOR_ELEMENT_BYTES = {40: 4, 41: 4, 48: 8, 49: 16, 50: 4, 58: 8}  # path, token, double, offset, string...
_LIST_OP_ITEM_BYTES = {32: 4, 33: 4, 34: 4, 36: 4, 37: 8, 38: 4, 39: 8}  # token, string, path, int...
_REFERENCE_LIST_OP, _UNREGISTERED_LIST_OP, _PAYLOAD_LIST_OP = 35, 54, 55
_DICTIONARY, _TIME_SAMPLES, _VALUE, _SPLINE = 31, 46, 52, 59


class _CrateValues:
    """Walks the value of every field of a crate file as usd-core would unpack it (vectors, list
    ops, dictionaries, time samples, arrays, nested values), checking each count against the bytes
    that must hold its items before usd-core allocates them."""

    MAX_VISITS = 1_000_000

    def __init__(self, data: bytes, version: tuple[int, int], budget: int):
        self.data, self.version, self.budget = data, version, budget
        self.seen: set[int] = set()

    def u64(self, offset: int) -> int:
        if not 0 <= offset <= len(self.data) - 8:
            raise IndexError
        return struct.unpack_from("<Q", self.data, offset)[0]

    def problem(self, start: int, size: int) -> str | None:
        try:
            for rep in self.field_reps(start, size):
                self.check(rep, 0)
        except ValueError as error:
            return f"a field value: {error}"
        except (IndexError, struct.error, RecursionError):
            return None  # a read past the end: usd-core reports it without allocating
        return None

    def field_reps(self, start: int, size: int):
        if self.version < (4,):  # Field {u32 padding; u32 token; u64 rep}
            count = self.u64(start)
            return [self.u64(start + 8 + 16 * i + 8) for i in range(min(count, (size - 8) // 16))]
        count = self.u64(start)
        offset = start + 16 + self.u64(start + 8)  # past the compressed field names
        stored = self.u64(offset)
        block = self.data[offset + 9: offset + 8 + stored]  # TfFastCompression: a 0 byte, then LZ4
        if self.data[offset + 8: offset + 9] != b"\0":
            return []
        reps = _lz4_block(block, 8 * count)
        return struct.unpack_from(f"<{len(reps) // 8}Q", reps)

    def check(self, rep: int, depth: int) -> None:
        if rep >> 62 & 1 or rep in self.seen or depth > 64 or len(self.seen) > self.MAX_VISITS:
            return  # inlined, already checked, or absurdly nested (usd-core guards recursion itself)
        self.seen.add(rep)
        kind, at = rep >> 48 & 0xFF, rep & ((1 << 48) - 1)
        if rep >> 63 & 1:
            self.array(kind, at, compressed=bool(rep >> 61 & 1))
        elif kind in _VECTOR_ELEMENT_BYTES:
            self.items(at, _VECTOR_ELEMENT_BYTES[kind], "items")
        elif kind in _LIST_OP_ITEM_BYTES or kind in (_REFERENCE_LIST_OP, _UNREGISTERED_LIST_OP, _PAYLOAD_LIST_OP):
            self.list_op(kind, at, depth)
        elif kind == _DICTIONARY:
            self.dictionary(at, depth)
        elif kind == _VALUE:
            self.value(at, depth)
        elif kind == _TIME_SAMPLES:
            times_at = at + self.signed(at)
            self.check(self.u64(times_at), depth + 1)
            values_at = times_at + 8 + self.signed(times_at + 8)
            count = self.items(values_at, 8, "time samples")
            for index in range(min(count, 4096)):  # each is unpacked when asked for
                self.check(self.u64(values_at + 8 + 8 * index), depth + 1)
        elif kind == _SPLINE:
            self.items(at, 1, "spline bytes")

    def signed(self, offset: int) -> int:
        value = self.u64(offset)
        return value - (1 << 64) if value >= 1 << 63 else value

    def items(self, at: int, size: int, what: str) -> int:
        """A u64 count of ``size``-byte items at ``at``; returns the count."""
        count = self.u64(at)
        if count * size > len(self.data) - at - 8:
            raise ValueError(f"{count} {what} do not fit in the file")
        return count

    def array(self, kind: int, at: int, compressed: bool) -> None:
        size = _ARRAY_ELEMENT_BYTES.get(kind)
        if size is None:
            return
        if self.version >= (7,):
            count, header = self.u64(at), 8
        else:
            header = 8 if self.version < (5,) else 4  # (a rank before 0.5.0) and a u32 count
            count = struct.unpack_from("<I", self.data, at + header - 4)[0]
        room = len(self.data) - at - header
        if compressed and (count > 1020 * room + 64 or count * size > self.budget):
            raise ValueError(f"a compressed array of {count} values cannot come from {room} bytes")
        if not compressed and count * size > room:
            raise ValueError(f"an array of {count} values does not fit in the file")

    def list_op(self, kind: int, at: int, depth: int) -> None:
        header, offset = self.data[at], at + 1
        for bit in (1, 2, 5, 6, 3, 4):  # explicit, added, prepended, appended, deleted, ordered
            if not header >> bit & 1:
                continue
            if kind in _LIST_OP_ITEM_BYTES:
                offset += 8 + _LIST_OP_ITEM_BYTES[kind] * self.items(offset, _LIST_OP_ITEM_BYTES[kind], "list items")
                continue
            smallest = {_REFERENCE_LIST_OP: 32, _PAYLOAD_LIST_OP: 8, _UNREGISTERED_LIST_OP: 16}[kind]
            count = self.items(offset, smallest, "list items")
            offset += 8
            for _ in range(count):
                offset = self.list_item(kind, offset, depth)

    def list_item(self, kind: int, offset: int, depth: int) -> int:
        """Check one reference, payload or value of a list op; returns where the next one starts."""
        if kind == _UNREGISTERED_LIST_OP:
            return self.value(offset, depth)
        offset += 8  # asset path and prim path indexes
        if kind == _PAYLOAD_LIST_OP:
            return offset + (16 if self.version >= (8,) else 0)
        return self.dictionary(offset + 16, depth)  # past the layer offset: the custom data

    def dictionary(self, at: int, depth: int) -> int:
        """Check a dictionary's values; returns where the bytes after it start."""
        count, offset = self.u64(at), at + 8
        for _ in range(count):  # usd-core reads entry by entry: a lie ends at the file's end
            offset = self.value(offset + 4, depth)
        return offset

    def value(self, at: int, depth: int) -> int:
        """A value stored as a jump to its rep; returns where the bytes after the rep start."""
        rep_at = at + self.signed(at)
        self.check(self.u64(rep_at), depth + 1)
        return rep_at + 8


def crate_tokens(data: bytes) -> bytes | None:
    """The token table of crate bytes (NUL-separated), or ``None`` when it cannot be read here.
    Call after :func:`crate_problem` has passed the file."""
    try:
        (toc,) = struct.unpack_from("<q", data, 16)
        (count,) = struct.unpack_from("<Q", data, toc)
        for index in range(count):
            name, start, _ = struct.unpack_from("<16sqq", data, toc + 8 + 32 * index)
            if name.rstrip(bytes(1)) != b"TOKENS":
                continue
            if data[9] < 4:  # before crate 0.4.0 the token text is stored as is
                (_, stored) = struct.unpack_from("<QQ", data, start)
                return data[start + 16: start + 16 + stored]
            _, expanded, stored = struct.unpack_from("<QQQ", data, start)
            block = data[start + 24: start + 24 + stored]
            # TfFastCompression: a 0 byte, then one LZ4 block (several chunks only above 2 GB)
            return _lz4_block(block[1:], expanded) if block[:1] == b"\0" else None
    except (struct.error, ValueError, IndexError):
        return None
    return None


def _lz4_block(source: bytes, limit: int) -> bytes:
    """Decompress one LZ4 block (lz4's block format: literal runs and back-references)."""
    out, position = bytearray(), 0
    while position < len(source):
        token = source[position]
        length, position = _lz4_length(source, position + 1, token >> 4)
        out += source[position:position + length]
        position += length
        if position >= len(source):
            break
        offset = source[position] | source[position + 1] << 8
        length, position = _lz4_length(source, position + 2, token & 15)
        length += 4
        start = len(out) - offset
        if offset == 0 or start < 0 or len(out) + length > limit:
            raise ValueError("corrupt LZ4 block")
        out += out[start:start + length] if offset >= length else (out[start:] * (length // offset + 1))[:length]
    return bytes(out)


def _lz4_length(source: bytes, position: int, length: int) -> tuple[int, int]:
    """A run length: 15 in the token means more bytes follow, each adding up to 255."""
    if length == 15:
        while True:
            length += source[position]
            position += 1
            if source[position - 1] != 255:
                break
    return length, position


def _crate_section_problem(name: str, section: bytes, compressed: bool, budget: int) -> str | None:
    offset = 0

    def number() -> int:
        nonlocal offset
        if offset + 8 > len(section):
            raise ValueError("it ends inside a count")
        (value,) = struct.unpack_from("<Q", section, offset)
        offset += 8
        return value

    def block(expanded: int, what: str) -> None:
        """A compressed block of ``expanded`` bytes once decompressed."""
        nonlocal offset
        stored = number()
        if stored > len(section) - offset:
            raise ValueError(f"{what} declares {stored} bytes, more than the section holds")
        if expanded > 255 * stored + 64 or expanded > budget:
            raise ValueError(f"{what} declares {expanded} bytes from {stored} compressed ones")
        offset += stored

    def integers(count: int, what: str) -> None:
        """usd-core's compressed integers: 2 bits of code per integer plus the values, then LZ4."""
        nonlocal offset
        stored = number()
        encoded = 4 + (2 * count + 7) // 8 + 4 * count
        if stored > len(section) - offset or (count and stored > encoded + encoded // 255 + 16) or (
                not count and stored):
            raise ValueError(f"{count} {what} cannot take {stored} compressed bytes")
        if count > 1020 * stored + 64 or 8 * count > budget:
            raise ValueError(f"{count} {what} cannot come from {stored} compressed bytes")
        offset += stored

    def vector(size: int, what: str) -> None:
        items = number()
        if items * size > len(section) - offset:
            raise ValueError(f"{items} {what} do not fit in the section")

    try:
        if name == "TOKENS":
            tokens = number()
            if compressed:
                expanded = number()
                block(expanded, "the token text")
            else:
                expanded = number()
                if expanded > len(section) - offset:
                    raise ValueError(f"the token text declares {expanded} bytes, more than the section holds")
            if tokens > expanded + 1:
                raise ValueError(f"{tokens} tokens cannot fit in {expanded} bytes")
        elif name == "STRINGS":
            vector(4, "strings")
        elif name == "FIELDS":
            if not compressed:
                return _vector_problem(vector, 16, "fields")
            fields = number()
            integers(fields, "field names")
            block(8 * fields, "the field values")
        elif name == "FIELDSETS":
            if not compressed:
                return _vector_problem(vector, 4, "field set entries")
            integers(number(), "field set entries")
        elif name == "PATHS":
            paths = number()
            if 8 * paths > budget or (not compressed and paths > len(section)):
                raise ValueError(f"{paths} paths cannot fit")
            if compressed:
                encoded = number()
                if encoded > paths:
                    raise ValueError(f"{encoded} encoded paths for {paths} paths")
                for what in ("path indexes", "path element tokens", "path jumps"):
                    integers(encoded, what)
        elif name == "SPECS":
            if not compressed:
                return _vector_problem(vector, 12, "specs")
            specs = number()
            for what in ("spec paths", "spec field sets", "spec types"):
                integers(specs, what)
    except ValueError as error:
        return str(error)
    return None


def _vector_problem(vector, size: int, what: str) -> str | None:
    try:
        vector(size, what)
    except ValueError as error:
        return str(error)
    return None


@dataclass(frozen=True, slots=True)
class PackageEntry:
    """A file in a USDZ as usd-core sees it: usd-core walks the local file headers from the start
    of the archive (it ignores the central directory), so this does too."""

    name: str
    method: int
    stored_size: int
    declared_size: int
    data: memoryview


def package_entries(data: bytes) -> list[PackageEntry]:
    """The entries of a USDZ's bytes, in order; raises :class:`ValueError` with the reason when
    the archive is one usd-core would misread or one too big to be safe."""
    entries, offset, view = [], 0, memoryview(data)
    while offset + _LOCAL_HEADER.size <= len(data):
        fields = _LOCAL_HEADER.unpack_from(data, offset)
        signature, method, stored, declared, name_length, extra_length = (fields[0], fields[3], fields[7], fields[8],
                                                                           fields[9], fields[10])
        start = offset + _LOCAL_HEADER.size + name_length + extra_length
        if signature != 0x04034B50 or start + stored > len(data):
            break  # where usd-core stops reading entries as well
        name = bytes(view[offset + _LOCAL_HEADER.size: offset + _LOCAL_HEADER.size + name_length]).decode("utf-8", "replace")
        if method == 0 and declared != stored:
            raise ValueError(f"entry {name!r} declares {declared} bytes but stores {stored}")
        entries.append(PackageEntry(name, method, stored, declared, view[start: start + stored]))
        if len(entries) > MAX_PACKAGE_ENTRIES:
            raise ValueError(f"more than {MAX_PACKAGE_ENTRIES} entries")
        offset = start + stored
    declared_total = sum(e.declared_size for e in entries)
    if declared_total > max_file_bytes():
        raise ValueError(f"its entries declare {declared_total / 2**20:.0f} MiB uncompressed, above the "
                         f"{max_file_bytes() / 2**20:.0f} MiB limit (OPENPBR_MAX_FILE_MB)")
    return entries


def unsafe_entry_name(name: str) -> str | None:
    """Why a USDZ entry name would escape a folder it is extracted to, or ``None``."""
    if name.startswith(("/", "\\")) or _DRIVE.match(name):
        return "is an absolute path"
    if ".." in re.split(r"[\\/]", name):
        return "climbs out of the package with '..'"
    if "\\" in name:
        return "contains a backslash"
    return None


def _read_limited(path: str) -> bytes:
    """The bytes of the file a layer identifier names (inside a package when package-relative)."""
    from pxr import Ar

    if Ar.IsPackageRelativePath(path):
        outer, inner = Ar.SplitPackageRelativePathOuter(path)
        try:
            entries = package_entries(_read_limited(outer))
        except ValueError as error:
            raise ReadError("not_usd", f"not a usable USDZ package: {error}", Location(outer)) from None
        for entry in entries:
            if entry.name == inner:
                return bytes(entry.data)
        raise ReadError("not_usd", f"the package has no file {inner!r}", Location(outer))
    return read_bytes(path)


class StageGuard:
    """Opens one stage for reading: judges every layer before usd-core parses it and every arc
    before usd-core follows it.

    ``observe(kind, location, **detail)`` receives ``usd_arc_outside`` (a sublayer, reference,
    payload or value clip pointing outside the asset's folder: deleted before composition, so never
    opened) and ``usd_package_entry`` (a USDZ entry with an unsafe name, or compressed).
    ``allow_outside`` lists folders arcs may point into besides the asset's own. Layers are edited
    in memory only; a layer already open elsewhere in the process is never edited (the stage is
    refused instead), and the edited ones die with the stage.
    """

    def __init__(self, path: str, observe, allow_outside=()):
        self.shown = path  # as the caller named it: diagnostics say it that way
        self.path = os.path.abspath(path)
        self.observe = observe
        self.allowed = [os.path.realpath(os.path.dirname(os.path.abspath(path)))]
        self.allowed += [os.path.realpath(folder) for folder in allow_outside]
        self.layers: dict[str, object] = {}  # identifier -> layer: held until composition is done
        self.root_identifier = ""
        self.preexisting: set[str] = set()
        self.without_clips: set[str] = set()  # layers whose text or token table cannot hold value clips
        self.crate_layers: set[str] = set()
        self.package_files: frozenset[str] = frozenset()

    def open_stage(self):
        """The composed stage (payloads loaded, variants as authored); raises :class:`ReadError`."""
        require_pxr(self.path)
        from pxr import Tf, Usd

        _regular_file(self.path)
        with quiet():
            try:
                self.check_bytes(self.path, read_bytes(self.path), self.path)
                root = self.open_layer(self.path)
                if root is None:
                    raise ReadError("not_usd", "USD cannot open the file", self.where(self.path))
                self.root_identifier = root.identifier
                self.follow(root)
                stage = Usd.Stage.Open(root, Usd.Stage.LoadAll)
            except Tf.ErrorException as error:
                message, line = usd_error_message(tf_error_text(error), self.path)
                raise ReadError("not_usd", f"USD cannot open the file: {message}", self.where(self.path, line)) from None
            except UnicodeDecodeError:  # an asset path or name in a crate file that is not UTF-8
                raise ReadError("not_usd", "the stage holds names or paths that are not valid UTF-8",
                                self.where(self.path)) from None
            if stage is None:
                raise ReadError("not_usd", "USD cannot open the file", self.where(self.path))
            missing = [e for e in stage.GetCompositionErrors() if type(e).__name__ in _MISSING_LAYER_ERRORS]
        self.layers.clear()
        if missing:
            reasons = "; ".join(sorted({_strip_stage_suffix(str(e)) for e in missing}))
            raise ReadError("not_usd", f"a layer the stage needs cannot be opened: {reasons}", self.where(self.path))
        return stage

    def where(self, file: str, line: int | None = None, prim: str | None = None) -> Location:
        """A location in ``file`` (absolute), named relative to the stage as the caller named it."""
        if file != self.path and not os.path.relpath(file, os.path.dirname(self.path)).startswith(".."):
            file = os.path.join(os.path.dirname(self.shown), os.path.relpath(file, os.path.dirname(self.path)))
        return Location(self.shown if file == self.path else file, line, prim)

    # -- layers --------------------------------------------------------------------------------
    def open_layer(self, identifier: str):
        from pxr import Sdf

        if Sdf.Layer.Find(identifier):
            self.preexisting.add(identifier)
        return Sdf.Layer.FindOrOpen(identifier)

    def check_bytes(self, identifier: str, data: bytes, file: str) -> None:
        """Refuse a layer whose bytes would crash usd-core; note unsafe package entries."""
        if data.startswith(b"PK") or (identifier == self.path and identifier.lower().endswith(".usdz")):
            data = self.check_package(data, file)
        if data.startswith(_CRATE_MAGIC):
            problem = crate_problem(data)
            if problem:
                raise ReadError("not_usd", f"USD cannot open the file safely (refused before parsing): a corrupt crate "
                                f"file: {problem}", self.where(file))
            self.crate_layers.add(identifier)
            tokens = crate_tokens(data)
            if tokens is not None and b"clips" not in tokens:
                self.without_clips.add(identifier)
            return
        problem = text_nesting_problem(data)
        if problem:
            raise ReadError("not_usd", f"USD cannot open the file safely (refused before parsing): {problem[0]}",
                            self.where(file, problem[1]))
        if b"clips" not in data:
            self.without_clips.add(identifier)

    def check_package(self, data: bytes, file: str) -> bytes:
        """Check a USDZ; returns its root layer's bytes."""
        if not data.startswith(_ZIP_MAGIC) and not data.startswith(b"PK\x05\x06"):
            raise ReadError("not_usd", "not a USDZ package (a zip archive)", self.where(file))
        try:
            entries = package_entries(data)
        except ValueError as error:
            raise ReadError("not_usd", f"not a usable USDZ package: {error}", self.where(file)) from None
        if not entries or not entries[0].name.lower().endswith(_LAYER_SUFFIXES):
            raise ReadError("not_usd", "the package's first file is not a USD layer (a USDZ's root layer must come "
                            "first)", self.where(file))
        for entry in entries:
            reason = unsafe_entry_name(entry.name) or (
                "is compressed (USDZ entries must be stored uncompressed)" if entry.method != 0 else None)
            if reason:
                self.observe("usd_package_entry", self.where(file), entry=entry.name, reason=reason)
        if file == self.path:
            self.package_files = frozenset(e.name for e in entries)
        return bytes(entries[0].data) if entries[0].method == 0 else _CRATE_MAGIC  # compressed: usd-core cannot read it

    def follow(self, root) -> None:
        """Walk the layers ``root`` depends on, deleting the arcs and value clips that must not be
        followed and opening (after checking) the others, so usd-core finds them already open."""
        from pxr import Tf

        queue = [root]
        self.layers[root.identifier] = root
        while queue:
            layer = queue.pop()
            if layer.identifier in self.crate_layers and _prim_paths(layer, verify=True) is None:
                raise ReadError("not_usd", "USD cannot open the file safely: a corrupt crate file lists a prim or "
                                "property it does not hold (usd-core would abort)", self.where(self.layer_file(layer)))
            if layer.identifier not in self.without_clips:
                self.drop_value_clips(layer)
            for asset_path in layer.GetCompositionAssetDependencies():
                reason = self.outside(layer, asset_path)
                if reason:
                    self.refuse(layer, asset_path, reason)
                    continue
                identifier = layer.ComputeAbsolutePath(asset_path)
                resolved = _resolve(identifier)
                if identifier in self.layers or not resolved:
                    continue  # a missing layer is reported by composition, in usd-core's words
                if len(self.layers) >= MAX_LAYERS:
                    raise ReadError("not_usd", f"the stage needs more than {MAX_LAYERS} layers", self.where(self.path))
                self.check_bytes(identifier, _read_limited(resolved), _file_of(resolved))
                try:
                    found = self.open_layer(identifier)
                except Tf.ErrorException:  # composition reports the broken layer, in usd-core's words
                    found = None
                if found is not None:
                    for judged in (self.crate_layers, self.without_clips):  # keyed as usd-core names it
                        if identifier in judged:
                            judged.add(found.identifier)
                    self.layers[identifier] = found
                    queue.append(found)

    def outside(self, layer, asset_path: str) -> str | None:
        """Why ``asset_path`` (an arc of ``layer``) must not be followed, or ``None``."""
        from pxr import Ar

        if "\0" in asset_path:
            return "is not a path (it holds a NUL byte)"
        if asset_path.startswith("`"):
            return "is a variable expression (where it leads is only known once evaluated)"
        if _URL.match(asset_path) and not _DRIVE.match(asset_path):
            return "is a URL"
        if asset_path.startswith(("/", "\\")) or _DRIVE.match(asset_path):
            return "is an absolute path"
        identifier = layer.ComputeAbsolutePath(asset_path)
        if Ar.IsPackageRelativePath(identifier):
            outer, inner = Ar.SplitPackageRelativePathOuter(identifier)
            if ".." in re.split(r"[\\/]", os.path.normpath(inner)):
                return "climbs out of its package with '..'"
            return None if self.within(os.path.realpath(outer)) else "leads out of the asset's folder"
        if os.path.isabs(identifier) and not self.within(os.path.normpath(identifier)):
            return "climbs out of the asset's folder with '..'"
        if not os.path.isabs(identifier) and ".." in re.split(r"[\\/]", os.path.normpath(identifier)):
            return "climbs out with '..'"  # usd-core would look it up from the working folder
        resolved = _resolve(identifier)
        if resolved and not self.within(os.path.realpath(resolved)):
            return "leads out of the asset's folder (through a symbolic link or the resolver's search path)"
        return None

    def within(self, path: str) -> bool:
        return any(path == folder or path.startswith(folder.rstrip(os.sep) + os.sep) for folder in self.allowed)

    def editable(self, layer):
        if layer.identifier in self.preexisting:
            raise ReadError("unreadable", f"{_file_of(layer.identifier)} is already open in this process and would have "
                            "to be changed to read it safely", self.where(self.path))
        return layer

    def layer_file(self, layer) -> str:
        return self.path if layer.identifier == self.root_identifier else _file_of(layer.identifier)

    def refuse(self, layer, asset_path: str, reason: str) -> None:
        file = self.layer_file(layer)
        if asset_path in layer.subLayerPaths:
            self.observe("usd_arc_outside", self.where(file), arc="sublayer", asset=asset_path, reason=reason)
        for prim_path, arc in _arcs_to(layer, asset_path):
            self.observe("usd_arc_outside", self.where(file, None, prim_path), arc=arc, asset=asset_path, reason=reason)
        self.editable(layer).UpdateCompositionAssetDependency(asset_path, "")

    def drop_value_clips(self, layer) -> None:
        """Delete every value clip: clips hold animation, not materials, usd-core opens their
        layers lazily from anywhere, and a template can name millions of files (all enumerated)."""
        for spec in [spec for spec in _prim_specs(layer) if spec.HasInfo("clips")]:
            clips = spec.GetInfo("clips")
            for clip_set in (clips.values() if isinstance(clips, dict) else ()):
                for asset_path in _clip_asset_paths(clip_set):
                    reason = self.outside(layer, asset_path)
                    if reason:
                        self.observe("usd_arc_outside", self.where(self.layer_file(layer), None, str(spec.path)),
                                     arc="value clip", asset=asset_path, reason=reason)
            self.editable(layer)
            spec.ClearInfo("clips")


def _resolve(identifier: str) -> str:
    from pxr import Ar

    return str(Ar.GetResolver().Resolve(identifier) or "")


def _regular_file(path: str):
    import stat

    try:
        info = os.stat(path)
    except OSError as error:
        raise ReadError("unreadable", f"cannot read file: {error.strerror or error}", Location(path)) from None
    if not stat.S_ISREG(info.st_mode):  # a folder, or a FIFO/device that would block or never end
        raise ReadError("unreadable", "not a regular file", Location(path))
    if not os.access(path, os.R_OK):
        raise ReadError("unreadable", "cannot read file: permission denied", Location(path))
    return info


def _file_of(identifier: str) -> str:
    from pxr import Ar

    return Ar.SplitPackageRelativePathOuter(identifier)[0] if Ar.IsPackageRelativePath(identifier) else identifier


def _prim_paths(layer, *, verify: bool = False) -> list | None:
    """The paths of every prim spec of ``layer`` (variants included). With ``verify``, ``None`` when
    the layer lists a prim it does not hold (a corrupt crate file): asking usd-core about such a
    layer (its composition dependencies) dereferences the missing spec and aborts the process.
    ``Sdf.Layer.Traverse`` and ``GetPrimAtPath`` (which checks the spec's type) only look the data up,
    so they are safe; ``GetObjectAtPath`` is not (a property whose spec type is corrupt crashes it)."""
    paths, missing = [], []

    def visit(path) -> None:
        if path.isEmpty or verify and path.IsPrimPath() and not layer.GetPrimAtPath(path):
            missing.append(path)
        elif path.IsPrimPath() or path.IsPrimVariantSelectionPath():
            paths.append(path)

    from pxr import Sdf

    layer.Traverse(Sdf.Path.absoluteRootPath, visit)
    return None if missing else paths


def _prim_specs(layer):
    """Every prim spec of ``layer``, variants' included."""
    for path in _prim_paths(layer) or ():
        spec = layer.GetPrimAtPath(path)  # a variant's prim spec for a variant path; None for a variant set
        if spec:
            yield spec


def _arcs_to(layer, asset_path: str):
    """(prim path, "reference"/"payload") for every arc of ``layer`` naming ``asset_path``."""
    for spec in _prim_specs(layer):
        for arc, items in (("reference", spec.referenceList), ("payload", spec.payloadList)):
            names = {item.assetPath for kind in ("explicitItems", "addedItems", "prependedItems", "appendedItems",
                                                  "orderedItems", "deletedItems") for item in getattr(items, kind)}
            if asset_path in names:
                yield str(spec.path), arc


def _clip_asset_paths(clip_set) -> list[str]:
    if not isinstance(clip_set, dict):
        return []
    found = [getattr(a, "path", str(a)) for a in clip_set.get("assetPaths", ()) or ()]
    manifest = clip_set.get("manifestAssetPath")
    if manifest is not None:
        found.append(getattr(manifest, "path", str(manifest)))
    template = clip_set.get("templateAssetPath")
    if template:
        found.append(str(template))
    return [f for f in found if f]


def _commentary(diagnostic) -> str:
    try:
        return str(diagnostic.commentary)
    except UnicodeDecodeError:  # usd-core quotes the offending bytes of a file that is not UTF-8
        return "(a message about text that is not valid UTF-8)"


def tf_error_text(error) -> str:
    """``str()`` of a ``Tf.ErrorException``, which itself raises when usd-core quotes invalid UTF-8."""
    try:
        return str(error)
    except UnicodeDecodeError:
        return "\n".join(_commentary(e) for e in error.args) or "(an error about text that is not valid UTF-8)"


def usd_error_message(text: str, path: str) -> tuple[str, int | None]:
    """The most specific message in a Tf error report, and the line it names in ``path``."""
    messages = [" ".join(m.split()) for m in _TF_MESSAGE.findall(text.strip())]
    message = messages[0] if messages else (text.strip().splitlines() or ["unknown error"])[-1]
    line = None
    if message.startswith(path):
        position = _TEXT_POSITION.match(message[len(path):])
        if position:
            line = int(position.group(1))
            message = message[len(path) + position.end():]
    message = message.replace(f"layer @{path}@", "the file").replace(f"@{path}@", "the file")
    return message.strip(), line


def _strip_stage_suffix(message: str) -> str:
    return re.sub(r"\s*\(instantiating stage on stage @[^@]*@ <[^>]*>\)$", "", message).strip()


# -- Sdr ----------------------------------------------------------------------------------------

_registered: set[str] = set()
_definition_layers: list = []  # Sdr parses lazily: the in-memory layers must stay alive


@lru_cache(maxsize=1)
def _materialx_nodedefs():
    """Name -> nodedef for MaterialX's libraries plus the toolkit's legacy OpenPBR definitions."""
    import MaterialX as mx

    from ..mtlx.reader import standard_library

    found = {nd.getName(): nd for nd in standard_library().getNodeDefs()}
    try:
        from ...resources import data_dir

        legacy = data_dir("libraries")
        for name in sorted(os.listdir(legacy)):
            if name.endswith(".mtlx"):
                document = mx.createDocument()
                mx.readFromXmlFile(document, str(legacy / name))
                for nodedef in document.getNodeDefs():
                    found.setdefault(nodedef.getName(), nodedef)
    except (FileNotFoundError, OSError):
        pass
    return found


def materialx_nodedef_names() -> list[str]:
    return sorted(_materialx_nodedefs())


def materialx_nodedef(name: str):
    """The MaterialX node definition called ``name`` (standard libraries or the toolkit's legacy
    OpenPBR definitions), or ``None``."""
    return _materialx_nodedefs().get(name)


def register_materialx_nodes(ids) -> list[str]:
    """Make Sdr know the MaterialX node definitions among ``ids``; returns the ids registered now.

    Ids that are not MaterialX node definitions, and ids Sdr already knows (from an earlier call,
    or from a usd build that has the MaterialX plug-in), are left alone.
    """
    from pxr import Sdf, Sdr

    registry = Sdr.Registry()
    wanted = []
    for shader_id in sorted(set(ids) - _registered):
        nodedef = materialx_nodedef(shader_id)
        _registered.add(shader_id)
        if nodedef is None:
            continue
        with quiet():
            known = registry.GetShaderNodeByIdentifier(shader_id)
        if not known:
            wanted.append(nodedef)
    if not wanted:
        return []
    layer = Sdf.Layer.CreateAnonymous("openpbr_tools_materialx_defs.usda")
    for nodedef in wanted:
        _define_shader(layer, nodedef)
    _definition_layers.append(layer)
    for nodedef in wanted:
        result = Sdr.NodeDiscoveryResult(
            nodedef.getName(), Sdr.Version(1).GetAsDefault(), nodedef.getName(), nodedef.getNodeString(),
            "usda", "mtlx", layer.identifier, layer.identifier,
        )
        registry.AddDiscoveryResult(result)
    return [nd.getName() for nd in wanted]


def _define_shader(layer, nodedef) -> None:
    from pxr import Sdf

    prim = Sdf.PrimSpec(layer, nodedef.getName(), Sdf.SpecifierDef, "Shader")
    uniform = Sdf.VariabilityUniform

    def attribute(name: str, type_name, value=None, variability=Sdf.VariabilityVarying):
        spec = Sdf.AttributeSpec(prim, name, type_name, variability)
        if value is not None:
            spec.default = value
        return spec

    attribute("info:id", Sdf.ValueTypeNames.Token, nodedef.getName(), uniform)
    attribute("info:implementationSource", Sdf.ValueTypeNames.Token, "sourceAsset", uniform)
    attribute("info:mtlx:sourceAsset", Sdf.ValueTypeNames.Asset,
              Sdf.AssetPath(nodedef.getSourceUri() or os.devnull), uniform)
    for port in nodedef.getActiveInputs():
        usd_type = MATERIALX_TO_USD.get(port.getType(), "token")
        name = port.getName().replace(":", "__")
        attribute(f"inputs:{name}", Sdf.ValueTypeNames.Find(usd_type),
                  variability=uniform if port.getIsUniform() else Sdf.VariabilityVarying)
    for port in nodedef.getActiveOutputs():
        usd_type = MATERIALX_TO_USD.get(port.getType(), "token")
        attribute(f"outputs:{port.getName()}", Sdf.ValueTypeNames.Find(usd_type))


# -- usd-core's validators ------------------------------------------------------------------------

def usd_core_findings(stage) -> list[dict]:
    """usd-core's ``UsdValidation`` results for ``stage`` (every registered validator), with the
    MaterialX node definitions the stage uses registered in Sdr first so that known MaterialX
    shaders raise no "not found in sdrRegistry" errors. Each finding is a dict: ``identifier``,
    ``name``, ``severity`` (``error``/``warning``/``info``), ``message``, ``sites`` (paths)."""
    from pxr import UsdShade, UsdValidation

    ids = set()
    for prim in stage.Traverse():
        if prim.IsA(UsdShade.Shader):
            shader_id = UsdShade.Shader(prim).GetShaderId()
            if shader_id:
                ids.add(str(shader_id))
    from pxr import Tf

    try:
        register_materialx_nodes(ids)
        context = UsdValidation.ValidationContext(_all_validators())
        with quiet():
            errors = context.Validate(stage)
    except Tf.ErrorException as error:  # a validator that breaks must not make the stage unreadable
        message, _ = usd_error_message(tf_error_text(error), "")
        return [{"identifier": "usdValidation", "name": "ValidatorFailed", "severity": "warning",
                 "message": f"usd-core's validators failed: {message}", "sites": []}]
    findings = []
    for error in errors:
        kind = str(error.GetType()).rsplit(".", 1)[-1].lower()
        try:
            sites = [str(site.GetProperty().GetPath()) if site.IsProperty() else str(site.GetPrim().GetPath())
                     for site in error.GetSites() if site.IsProperty() or site.IsPrim()]
            message = str(error.GetMessage())
        except UnicodeDecodeError:  # a name or value from a crate file that is not UTF-8
            sites, message = [], "(a message quoting text that is not valid UTF-8)"
        findings.append({
            "identifier": str(error.GetIdentifier()),
            "name": str(error.GetName()),
            "severity": {"error": "error", "warn": "warning", "info": "info"}.get(kind, "warning"),
            "message": message,
            "sites": sites,
        })
    return findings


def _all_validators():
    from pxr import UsdValidation

    return UsdValidation.ValidationRegistry().GetOrLoadAllValidators()
