"""Document: can the file be read at all, and does it hold anything to check.

These rules fire before any material is looked at. OPBR001 and OPBR002 make ``openpbr validate``
exit with code 2 (unreadable input), whatever ``--fail-on`` says.
"""

from __future__ import annotations

import os

from ..diagnostics import Diagnostic, Severity
from ..model import Connection, Location
from . import Rule

UNREADABLE = Rule(
    "OPBR001", "unreadable-file", Severity.ERROR,
    "The file cannot be opened or decoded.",
    "The file does not exist, cannot be read (permissions, a folder), or is not text in its encoding (a "
    "MaterialX document's byte-order mark or XML declaration names it, as XML 1.0 section 4.3.3 says; UTF-8 "
    "without either: a UTF-16 or Latin-1 document that says so is read as MaterialX's own parser reads it). "
    "Nothing else can be checked; the exit code is 2.",
    passing='<open_pbr_surface name="S" type="surfaceshader" />',
    failing=b'<?xml version="1.0"?>\n<materialx version="1.39">\n  <!-- Ch\xeane -->\n</materialx>\n',
)
NOT_MATERIALX = Rule(
    "OPBR002", "malformed-document", Severity.ERROR,
    "The file is not a well-formed document of its format (MaterialX, USD or glTF).",
    "MaterialX: the XML is malformed (truncated, unbalanced tags: the message gives expat's line and "
    "column), the root element is not <materialx>, it declares a DOCTYPE or nests absurdly deep, or "
    "MaterialX itself refuses it. USD: a layer usd-core cannot open (a syntax error with its line, a "
    "corrupt crate file, a USDZ that is not a package, a missing sublayer, reference or payload; arcs that "
    "form a cycle, which usd-core's composition reports as an error and composes without). "
    "glTF: invalid JSON or GLB, broken buffers or data URIs. The exit code is 2.",
    passing='<open_pbr_surface name="S" type="surfaceshader" />',
    failing='<?xml version="1.0"?>\n<materialx version="1.39">\n  <open_pbr_surface name="S" type="surfaceshader">\n',
)
NO_MATERIAL = Rule(
    "OPBR003", "no-material", Severity.INFO,
    "The file contains no surface shader of a supported model.",
    "No open_pbr_surface, standard_surface, gltf_pbr or UsdPreviewSurface node (or USD/glTF "
    "material) was found, so nothing was validated. Often a library of node definitions, a geometry "
    "layer or a look file found in a folder: info, since holding no material is not a defect.",
    passing='<open_pbr_surface name="S" type="surfaceshader" />',
    failing='<?xml version="1.0"?>\n<materialx version="1.39">\n  <nodegraph name="NG" />\n</materialx>\n',
)
MATERIALX_INVALID = Rule(
    "OPBR004", "materialx-validate", Severity.ERROR,
    "MaterialX's own Document.validate() rejects the document.",
    "The message is MaterialX's, passed through (it covers structure MaterialX knows about, such as "
    "invalid port connections or a node no definition declares): an error, so `openpbr validate` is "
    "never more lenient than `mxvalidate`. Messages about shader inputs that another rule judges more "
    "precisely (unknown or legacy inputs, dangling connections, unparsable values) are left to that rule. "
    "MaterialX's check is lenient otherwise: a clean result here says little about values.",
    passing='<open_pbr_surface name="S" type="surfaceshader" />',
    failing='<image name="albedo" type="color3">\n  <input name="texcoord" type="vector2" nodename="nowhere" />\n</image>\n<open_pbr_surface name="S" type="surfaceshader" />',
)
OLD_DOCUMENT = Rule(
    "OPBR005", "old-document-version", Severity.WARNING,
    "The MaterialX document has no version, or holds open_pbr_surface with a version older than 1.39 "
    "(the first with open_pbr_surface).",
    "MaterialX upgrades older documents when it reads them (MaterialX's Document::upgradeVersion), "
    "which renames nodes and inputs; other readers do not, and a document without a version is "
    "upgraded from 1.0. A document that holds open_pbr_surface cannot be older than 1.39. Re-save it as 1.39. "
    "Where the upgrade changes nothing but the version, it is OPBR012 (info).",
    passing='<open_pbr_surface name="S" type="surfaceshader" />',
    failing='<?xml version="1.0"?>\n<materialx version="1.38">\n  <swizzle name="sw" type="float">\n'
            '    <input name="in" type="color3" value="1, 0, 0" />\n    <input name="channels" type="string" value="r" />\n'
            '  </swizzle>\n  <open_pbr_surface name="S" type="surfaceshader">\n'
            '    <input name="base_weight" type="float" nodename="sw" />\n  </open_pbr_surface>\n</materialx>\n',
)
UNSUPPORTED = Rule(
    "OPBR006", "unsupported-file", Severity.ERROR,
    "No reader handles this kind of file.",
    "The file was named explicitly but its suffix is not one the toolkit reads "
    "(.mtlx; .usda/.usdc/.usd/.usdz and .gltf/.glb where those readers are installed). The exit code is 2.",
    passing='<open_pbr_surface name="S" type="surfaceshader" />',
    failing='<open_pbr_surface name="S" type="surfaceshader" />',
    failing_name="example.xml",
)

MALFORMED_XML = Rule(
    "OPBR007", "malformed-xml", Severity.WARNING,
    "The document is not well-formed XML, although MaterialX's lenient parser reads it.",
    "MaterialX (pugixml) accepts, for instance, a raw '<' in an attribute value; standard XML tools, "
    "linters and other DCCs' readers refuse the file. The message gives the line and column.",
    passing='<open_pbr_surface name="S" type="surfaceshader">\n  <input name="base_weight" type="float" value="1" />\n</open_pbr_surface>',
    failing='<open_pbr_surface name="S" type="surfaceshader">\n  <input name="base_weight" type="float" value="1" doc="a<b" />\n</open_pbr_surface>',
)

INVALID_CONFIG = Rule(
    "OPBR008", "invalid-config", Severity.ERROR,
    "The project configuration ([tool.openpbr] or .openpbr.toml) is invalid.",
    "Invalid TOML, a key the configuration schema (schemas/config.schema.json) does not define, a "
    "wrong value type, or an unknown rule code. Nothing is validated; the exit code is 2.",
    passing='<open_pbr_surface name="S" type="surfaceshader" />',
    failing='<open_pbr_surface name="S" type="surfaceshader" />',
    failing_config='fail-on = "sometimes"\n',
)

XINCLUDE = Rule(
    "OPBR009", "xinclude-not-followed", Severity.WARNING,
    "The document includes another file (XInclude) that is not followed: outside the asset's "
    "folder, or nested deeper than 8 levels (a missing, unreadable or circular include is OPBR010).",
    "Includes inside the asset's folder are followed as MaterialX follows them (their definitions and "
    "materials resolve this document's references; they are validated as their own files). An include "
    "that leads out of the folder is never opened (the one path guard), so whatever it defines is "
    "missing here: renderers that follow it may see a different document, and the asset does not "
    "survive being copied.",
    passing='<open_pbr_surface name="S" type="surfaceshader" />',
    failing='<?xml version="1.0"?>\n<materialx version="1.39" colorspace="lin_rec709">\n  <xi:include href="../shared_defs.mtlx" />\n  <open_pbr_surface name="S" type="surfaceshader" />\n</materialx>\n',
)

XINCLUDE_BROKEN = Rule(
    "OPBR010", "xinclude-broken", Severity.ERROR,
    "The document includes a file (XInclude) that does not exist, cannot be read, or includes the "
    "document back (a cycle).",
    "MaterialX cannot read such a document at all (readFromXmlFile fails), so no renderer loads it: "
    "an error, where an include that is only refused here (outside the asset's folder) is OPBR009.",
    passing='<open_pbr_surface name="S" type="surfaceshader" />',
    failing='<?xml version="1.0"?>\n<materialx version="1.39" colorspace="lin_rec709">\n  <xi:include href="missing_defs.mtlx" />\n  <open_pbr_surface name="S" type="surfaceshader" />\n</materialx>\n',
)

INTERNAL_ERROR = Rule(
    "OPBR011", "internal-error", Severity.ERROR,
    "The toolkit failed while reading or checking this file: a defect of the toolkit, reported at the file "
    "so that the other files, and the other checks of this one, still run.",
    "The message names the step that failed (reading, a family of checks, converting or verifying) and the "
    "exception. The file "
    "was not fully checked, so the exit code is 2, as for a file that cannot be read. No file is meant to "
    "trigger it: each one found is a defect, fixed with a test. Please report it with the file.",
    passing='<open_pbr_surface name="S" type="surfaceshader" />',
    failing="(no document triggers it on purpose; the test suite makes a check fail to prove the report)",
    formats=(),
)

STALE_VERSION = Rule(
    "OPBR012", "stale-document-version", Severity.INFO,
    "The document holds open_pbr_surface with a version older than 1.39, but MaterialX's upgrade of it "
    "changes nothing else.",
    "As OPBR005, except that upgrading the document (Document::upgradeVersion, which MaterialX runs when it "
    "reads it) leaves every element and attribute as written: the document means the same to MaterialX and "
    "to readers that do not upgrade, and only its version header is out of date (as early 1.39 development "
    "documents were, MaterialX's own open_pbr_carpaint among them). Re-save it as 1.39.",
    passing='<open_pbr_surface name="S" type="surfaceshader" />',
    failing='<?xml version="1.0"?>\n<materialx version="1.38">\n  <open_pbr_surface name="S" type="surfaceshader" />\n</materialx>\n',
)

RULES = (UNREADABLE, NOT_MATERIALX, NO_MATERIAL, MATERIALX_INVALID, OLD_DOCUMENT, UNSUPPORTED, MALFORMED_XML,
         INVALID_CONFIG, XINCLUDE, XINCLUDE_BROKEN, INTERNAL_ERROR, STALE_VERSION)

#: Set (to anything) to make the OPBR011 safety net re-raise instead of reporting: the test suite and the
#: fuzz runs set it, so a defect fails the test or the input that meets it (worker processes inherit it).
RAISE_INTERNAL_ERRORS = "OPENPBR_RAISE_INTERNAL_ERRORS"


def internal_error(path: str, step: str, error: Exception) -> Diagnostic:
    """OPBR011 at ``path``: ``step`` failed with ``error`` (not subject to selection or suppression: it
    says the file was not fully checked). Re-raises ``error`` when :data:`RAISE_INTERNAL_ERRORS` is set."""
    if os.environ.get(RAISE_INTERNAL_ERRORS):
        raise error
    from ..workers import interrupted  # lazy: the worker machinery, only on this rare path

    if interrupted():  # (the error is how an interrupt surfaced: the command says it was interrupted)
        raise KeyboardInterrupt from error
    detail = str(error).strip().splitlines()[0][:200] if str(error).strip() else ""
    return Diagnostic(INTERNAL_ERROR.code, INTERNAL_ERROR.severity,
                      f"{step} failed on this file ({type(error).__name__}{': ' + detail if detail else ''}); "
                      "the file is not fully checked", Location(path), "a defect of the toolkit: please report it with the file")


READ_ERROR_RULES = {
    "unreadable": UNREADABLE,
    "not_materialx": NOT_MATERIALX,
    "not_usd": NOT_MATERIALX,
    "not_gltf": NOT_MATERIALX,
    "unsupported": UNSUPPORTED,
    "no_material": NO_MATERIAL,  # convert: nothing to write (an error there, where validate notes it)
    "xinclude_broken": XINCLUDE_BROKEN,  # convert: nothing to write because MaterialX cannot read the document
}


def materialx_invalid(asset, context):
    """OPBR004 for each line of MaterialX's ``Document.validate()`` message no other rule covers, at the element
    it names (``convert`` reports them too: an output read from an invalid source may carry the same defect)."""
    message = asset.extra.get("materialx_validate")
    if message:
        sites = asset.extra.get("materialx_validate_sites", {})
        for line in _not_covered(asset, message):
            path, name = sites.get(line, (None, None))  # the element the message names, where it is in the document
            line_number = asset.line_of.get(f"{path}/{name}" if name else path) if path else None
            yield context.diagnostic(MATERIALX_INVALID, f"MaterialX: {line}", Location(asset.path, line_number, path, name))


def check(asset, context):
    if not asset.materials and not asset.extra.get("included_materials"):  # a look file's come from includes
        yield context.diagnostic(NO_MATERIAL, "no supported surface shader found", Location(asset.path))
    yield from materialx_invalid(asset, context)
    for observation in asset.observations:
        if observation.kind == "xinclude":
            yield context.diagnostic(XINCLUDE, f"includes {observation.detail['href']!r}, which "
                                     f"{observation.detail['reason']}", observation.location,
                                     hint="keep included files inside the asset's folder, with relative paths")
        if observation.kind == "xinclude_broken":
            yield context.diagnostic(XINCLUDE_BROKEN, f"includes {observation.detail['href']!r}, which "
                                     f"{observation.detail['reason']}: MaterialX cannot read this document",
                                     observation.location, hint="fix or remove the xi:include")
        if observation.kind == "malformed_xml":
            yield context.diagnostic(MALFORMED_XML, f"not well-formed XML: {observation.detail['message']}",
                                     observation.location, hint="escape '<' as &lt; and '&' as &amp; in attribute values")
    version = asset.format_version
    if asset.format == "mtlx" and not version:
        yield context.diagnostic(
            OLD_DOCUMENT, "the <materialx> element has no version: MaterialX reads it as 1.0 and upgrades it",
            Location(asset.path, 1), hint="add version=\"1.39\" to <materialx>",
        )
    elif asset.format == "mtlx" and any(m.model == "open_pbr_surface" for m in asset.materials):
        try:
            old = tuple(int(p) for p in version.split(".")[:2]) < (1, 39)
        except ValueError:  # (the red team's F#14: "version latest is older than 1.39")
            yield context.diagnostic(
                OLD_DOCUMENT, f"MaterialX document version {version!r} is no version number: MaterialX reads it as "
                "unsupported", Location(asset.path, 1), hint="set version=\"1.39\" on <materialx>")
            return
        if old and asset.extra.get("upgrade_changes_nothing"):
            yield context.diagnostic(
                STALE_VERSION, f"MaterialX document version {version} is older than 1.39, but upgrading it changes "
                "nothing else", Location(asset.path, 1), hint="set version=\"1.39\" on <materialx>",
            )
        elif old:
            yield context.diagnostic(
                OLD_DOCUMENT, f"MaterialX document version {version} is older than 1.39",
                Location(asset.path, 1), hint="re-save the document with MaterialX 1.39",
            )


def _not_covered(asset, message: str):
    """MaterialX's messages, less those about shader nodes and connections the other rules judge
    more precisely (unknown inputs, dangling connections)."""
    shader_tags = [f'<{m.model} name="{m.name}"' for m in asset.materials]
    dangling = [
        f'<input name="{name}"' for m in asset.materials for name, entry in m.inputs.items()
        if isinstance(entry.value, Connection) and entry.value.dangling
    ]
    shader_inputs = {f'<input name="{name}"' for m in asset.materials for name in m.inputs}
    for line in message.splitlines():
        line = line.strip()
        if not line or any(tag in line for tag in shader_tags):
            continue
        if line.startswith("Invalid port connection") and any(tag in line for tag in dangling):
            continue
        if line.startswith("Invalid value") and any(tag in line for tag in shader_inputs):
            continue  # OPBR202/OPBR203 judge shader values strictly
        yield line
