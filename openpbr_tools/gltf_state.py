"""glTF material state OpenPBR has no parameter for, carried through .mtlx and USD outputs so that a
glTF -> .mtlx/USD -> glTF round trip restores it.

What travels: KHR_materials_volume's ``thicknessFactor`` (OpenPBR has no thickness: a glTF
output gives the volume its source thickness again instead of one scene unit), the names of the KHR_materials_variants variants that select the material (the
mappings live on mesh primitives, which .mtlx and a material-only USD file do not have; a glTF
output without meshes reports them), the glTF ``name`` where a writer that needs unique names renamed the material (glTF
allows two materials one name: a glTF output restores it), ``doubleSided``, ``extras``, an alpha ``MASK`` with its ``alphaCutoff`` (OpenPBR keeps
the cut-out as geometry_opacity, not the mode) and the material extensions the gltf_pbr node does not
carry (KHR_materials_diffuse_transmission, KHR_materials_unlit, unknown ones), as they were in the
source (``Material.extra["gltf"]``). Where: a JSON string in the ``openpbr_gltf`` attribute of the
``surfacematerial`` element (MaterialX keeps unknown attributes and renderers ignore them), and in
the ``openpbr:gltf`` customData of the USD ``Material`` prim. Extensions that reference the source's
textures do not travel (their indices mean nothing elsewhere) and are reported.
"""

from __future__ import annotations

import json

MTLX_ATTRIBUTE = "openpbr_gltf"
USD_CUSTOM_DATA_KEY = "openpbr:gltf"
KEYS = ("doubleSided", "extras", "extensions", "alphaMode", "alphaCutoff", "name", "variants", "thickness")
MAX_TEXT = 1 << 20  # a side channel larger than this is not read (a hostile file)


def travelling(material) -> dict:
    """The part of ``material``'s glTF state that a side channel carries (empty when none)."""
    state = material.extra.get("gltf")
    if not isinstance(state, dict):
        return {}
    kept = {key: state[key] for key in KEYS if state.get(key)}
    return kept


def encode(state: dict) -> str:
    return json.dumps(state, sort_keys=True, separators=(",", ":"))


def decode(text) -> dict:
    """The state a side channel holds; ``{}`` for anything that is not a JSON object of known keys."""
    try:
        value = json.loads(text) if isinstance(text, str) and len(text) <= MAX_TEXT else None
    except (ValueError, RecursionError):
        return {}
    if not isinstance(value, dict):
        return {}
    state = {}
    thickness = value.get("thickness")
    if isinstance(thickness, (int, float)) and not isinstance(thickness, bool) and 0 < thickness < float("inf"):
        state["thickness"] = float(thickness)
    if isinstance(value.get("variants"), list) and all(isinstance(v, str) for v in value["variants"]):
        state["variants"] = value["variants"]
    if isinstance(value.get("name"), str) and value["name"]:
        state["name"] = value["name"]
    if isinstance(value.get("doubleSided"), bool):
        state["doubleSided"] = value["doubleSided"]
    if "extras" in value:
        state["extras"] = value["extras"]
    if value.get("alphaMode") == "MASK" and isinstance(value.get("alphaCutoff"), (int, float)) \
            and not isinstance(value.get("alphaCutoff"), bool) and 0.0 <= value["alphaCutoff"]:
        state["alphaMode"], state["alphaCutoff"] = "MASK", float(value["alphaCutoff"])
    extensions = value.get("extensions")
    if isinstance(extensions, dict) and all(isinstance(k, str) and isinstance(v, dict) for k, v in extensions.items()):
        state["extensions"] = extensions
    return state
