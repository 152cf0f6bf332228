"""glTF schema: what Khronos' JSON schema for glTF 2.0 and its extensions forbids, found anywhere in the document
(:mod:`openpbr_tools.io.gltf.json_schema`), where no other rule says it already.

The other glTF families read what a material is drawn with and say what it does to the render; a property they do
not read (an accessor's ``type`` that is a list, a ``TEXCOORD_0`` that is a string, a bufferView without its
buffer) still makes the Khronos glTF-Validator reject the file (TYPE_MISMATCH, UNDEFINED_PROPERTY,
VALUE_NOT_IN_RANGE...) and a strict loader refuse it. This family is their floor: ``check_asset`` keeps its findings
only at properties no finding of a rule judging the same names (:data:`ONLY_WHERE_UNSAID`), so a texture index that
is no integer is still OPBR1210 with its effect, said once.
"""

from __future__ import annotations

from ..diagnostics import Severity
from ..model import Location
from . import Rule
from .gltf import _gltf

#: check_asset keeps this family's findings only where no finding of these codes, which judge a property's value or
#: type too, stands at the same property: an invalid property (OPBR1210), a value out of its range or list (OPBR301,
#: OPBR303), of the wrong type, beyond a float or not finite (OPBR201, OPBR202, OPBR203), an accessor's layout
#: (OPBR1228), a buffer's (OPBR1209), a reference to nothing (OPBR802).
ONLY_WHERE_UNSAID = frozenset({"OPBR1210", "OPBR301", "OPBR303", "OPBR201", "OPBR202", "OPBR203", "OPBR1228",
                               "OPBR1209", "OPBR802"})

SCHEMA = Rule(
    "OPBR1253", "gltf-schema", Severity.ERROR,
    "A property anywhere in the glTF breaks the glTF 2.0 JSON schema or a Khronos extension's (a value of the wrong "
    "JSON type, a required property missing, a number out of its range, a string outside its list, an array of the "
    "wrong length), where no more specific rule reports it.",
    "The Khronos glTF-Validator checks the whole document against Khronos' schema and rejects the file "
    "(TYPE_MISMATCH, UNDEFINED_PROPERTY, VALUE_NOT_IN_RANGE, INVALID_INDEX...); strict loaders refuse it, lenient "
    "ones skip the property, and the mesh a material is drawn on loses its coordinates or disappears. The schema "
    "files are Khronos' own, checked with jsonschema.",
    passing=_gltf('"materials": [{"name": "M", "alphaMode": "MASK"}]'),
    failing=_gltf('"materials": [{"name": "M"}]', '"samplers": [{"wrapS": "REPEAT"}]'),
    passing_name="example.gltf", failing_name="example.gltf", formats=("gltf",),
)

RULES = (SCHEMA,)


def check(asset, context):
    """Runs on glTF assets only (rules.FAMILY_FORMATS)."""
    for pointer, name, keyword, message in asset.extra.get("gltf", {}).get("schema_errors", ()):
        where = f"{pointer}/{name}" if name is not None else pointer or "/"
        said = (f"{pointer or 'the root'} has no {name}, which the glTF schema requires" if keyword == "required"
                else f"{where}: {message}")
        yield context.diagnostic(SCHEMA, f"{said} (glTF 2.0 JSON schema, '{keyword}')",
                                 Location(asset.path, None, pointer, name),
                                 hint="write the property as the glTF 2.0 schema defines it (the Khronos "
                                      "glTF-Validator names the same place)")
