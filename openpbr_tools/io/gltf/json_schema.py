"""The glTF 2.0 JSON schema over the whole document: Khronos' own schema files (``schemas/gltf_schema``, vendored
unmodified from KhronosGroup/glTF ``specification/2.0/schema`` and the Khronos extensions' ``schema`` folders; see
the NOTICE there), checked with ``jsonschema`` (:func:`errors`).

The Khronos glTF-Validator checks every property of a document against this schema (TYPE_MISMATCH,
UNDEFINED_PROPERTY, VALUE_NOT_IN_RANGE, INVALID_INDEX...); the toolkit's own rules check what they read with more to
say (a texture's index, a factor's range with the effect on the render, an extension object). This is the floor
under them: whatever the schema forbids is found, and OPBR1253 says it where no other rule already does
(:mod:`openpbr_tools.rules.gltf_schema`). An extension object is checked against its own schema, found by its
name and the object it extends (``material.KHR_materials_clearcoat.schema.json`` under a material's
``extensions``); an extension with no schema here (a vendor's, a draft's) is checked as an object only, as the
core schema says.
"""

from __future__ import annotations

import json
import os
from functools import lru_cache

from ...resources import data_folder

FOLDER = "gltf_schema"
#: What an ``extensions`` object extends, by the pointer of the object that holds it (most specific first).
_EXTENDED = (("/primitives/", "mesh.primitive"), ("Texture/", "textureInfo"), ("/nodes/", "node"),
             ("/materials/", "material"), ("/textures/", "texture"), ("/meshes/", "mesh"),
             ("/buffers/", "buffer"), ("/bufferViews/", "bufferView"), ("/images/", "image"))
MAX_REPORTED = 200  # errors kept per document (a generated file can break thousands of elements alike)


@lru_cache(maxsize=1)
def _registry():
    """(the referencing registry of every schema file by its file name, the files by name)."""
    from referencing import Registry, Resource  # lazy: jsonschema and referencing (~60-90 ms), for a glTF only
    from referencing.jsonschema import DRAFT4, DRAFT202012  # lazy: as above

    folder = os.path.join(data_folder("schemas"), FOLDER)
    resources = {}
    for name in sorted(os.listdir(folder)):
        if name.endswith(".schema.json"):
            with open(os.path.join(folder, name), encoding="utf-8") as handle:
                contents = json.load(handle)
            draft = DRAFT4 if "draft-04" in str(contents.get("$schema", "")) else DRAFT202012
            resources[name] = Resource(contents=contents, specification=draft)
    return Registry().with_resources(resources.items()), frozenset(resources)


@lru_cache(maxsize=64)
def _validator(name: str):
    import jsonschema  # lazy: as in _registry

    registry, _ = _registry()
    return jsonschema.Draft202012Validator({"$ref": name}, registry=registry)


def _extension_schema(name: str, holder: str) -> str | None:
    """The schema file of extension ``name`` on the object at pointer ``holder`` ('' for the root)."""
    extended = "glTF" if holder == "" else next((kind for marker, kind in _EXTENDED if marker in holder + "/"), None)
    return _schema_file(name, extended)


@lru_cache(maxsize=256)
def _schema_file(name: str, extended: str | None) -> str | None:
    """The schema file of extension ``name`` on an object of kind ``extended`` (its only one, when it has one)."""
    _, files = _registry()
    candidates = [f for f in files if f.endswith(f".{name}.schema.json")]
    if len(candidates) <= 1:
        return candidates[0] if candidates else None
    return f"{extended}.{name}.schema.json" if f"{extended}.{name}.schema.json" in files else None


def _escape(token) -> str:
    return str(token).replace("~", "~0").replace("/", "~1")


def _said(error):
    """The error to say for one schema error: among alternatives (anyOf: an enum of integers or any integer; an
    image's uri or bufferView), the alternative's own complaint that fits best."""
    from jsonschema.exceptions import best_match  # lazy: as in _registry

    while error.validator in ("anyOf", "oneOf") and error.context:
        typed = [e for e in error.context if e.validator == "type"]  # (a list where a string is: its type first)
        error = typed[0] if typed else best_match(error.context)
    return error


def errors(document: dict) -> list[tuple[str, str | None, str, str]]:
    """(pointer of the object, property or None, schema keyword, message) for each place ``document`` breaks the
    glTF 2.0 schema or an extension's, in document order; a missing required property is said at the object,
    with the property named; at most :data:`MAX_REPORTED`."""
    found: list[tuple[str, str | None, str, str]] = []

    def collect(validator, value, prefix: str) -> None:
        for error in sorted(validator.iter_errors(value), key=lambda e: [str(p) for p in e.absolute_path]):
            error = _said(error)
            tokens = [_escape(p) for p in error.absolute_path]
            keyword, message = error.validator, error.message
            if keyword == "required" and isinstance(error.instance, dict):
                missing = next((name for name in error.validator_value if name not in error.instance), None)
                found.append((prefix + "".join(f"/{t}" for t in tokens), missing, keyword, message))
                continue
            if tokens:
                found.append((prefix + "".join(f"/{t}" for t in tokens[:-1]), tokens[-1], keyword, message))
            else:
                found.append((prefix, None, keyword, message))

    collect(_validator("glTF.schema.json"), document, "")
    stack = [("", document)]
    while stack:  # every extensions object, checked against its extension's schema
        pointer, value = stack.pop()
        if isinstance(value, dict):
            extensions = value.get("extensions")
            if isinstance(extensions, dict):
                for name, extension in extensions.items():
                    schema = _extension_schema(name, pointer)
                    if schema is not None and isinstance(extension, dict):
                        collect(_validator(schema), extension, f"{pointer}/extensions/{_escape(name)}")
            stack.extend((f"{pointer}/{_escape(k)}", v) for k, v in value.items() if k != "extras")
        elif isinstance(value, list):
            stack.extend((f"{pointer}/{i}", v) for i, v in enumerate(value))
    found.sort(key=lambda e: (e[0], e[1] or ""))
    return found[:MAX_REPORTED]
