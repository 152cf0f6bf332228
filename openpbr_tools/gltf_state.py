"""glTF material state OpenPBR has no parameter for, carried through .mtlx and USD outputs so that a
glTF -> .mtlx/USD -> glTF round trip restores it.

What travels: KHR_materials_volume's ``thicknessFactor`` (OpenPBR has no thickness: a glTF
output gives the volume its source thickness again instead of one scene unit), the names of the KHR_materials_variants variants that select the material (the
mappings live on mesh primitives, which .mtlx and a material-only USD file do not have; a glTF
output without meshes reports them), the glTF ``name`` where a writer that needs unique names renamed the material (glTF
allows two materials one name: a glTF output restores it while the material still bears the name it
was written as, ``renamed_to``; a material renamed since keeps its new name), ``doubleSided``, ``extras``, an alpha ``MASK`` with its ``alphaCutoff`` (OpenPBR keeps
the cut-out as geometry_opacity, not the mode) and the material extensions the gltf_pbr node does not
carry (KHR_materials_diffuse_transmission, KHR_materials_unlit, unknown ones), as they were in the
source (``Material.extra["gltf"]``). Where: a JSON string in the ``openpbr_gltf`` attribute of the
``surfacematerial`` element (MaterialX keeps unknown attributes and renderers ignore them), and in
the ``openpbr:gltf`` customData of the USD ``Material`` prim. Extensions that reference the source's
textures do not travel (their indices mean nothing elsewhere) and are reported. An unlit material,
read as emission of its base colour, also carries the constant factors that reading replaced
(``unlit``), so that the glTF written back is the source's.
"""

from __future__ import annotations

import json
from dataclasses import replace

from .io.gltf import slots
from .io.gltf.textures import MINIFICATION_FILTERS
from .model import Texture
from .rules.translation import APPROXIMATED, CONVERTED, NOT_CARRIED

MTLX_ATTRIBUTE = "openpbr_gltf"
USD_CUSTOM_DATA_KEY = "openpbr:gltf"
KEYS = ("doubleSided", "extras", "extensions", "alphaMode", "alphaCutoff", "name", "renamed_to", "variants",
        "thickness", "unlit")
#: What an unlit material's reading as emission replaced (translate/gltf.py), restored for a glTF output.
UNLIT_FACTORS = {"metallic": 1, "emissive": 3, "emissive_strength": 1}
#: Extensions whose look a .mtlx or USD output loses when they stay in the state (a diffuse transmission
#: OpenPBR's thin-walled subsurface cannot take: textured, or into a volume). The specular-glossiness model
#: is rendered: the translation reads it (translate/spec_gloss.py), the state keeps it for a glTF written back.
UNRENDERED = (slots.DIFFUSE_TRANSMISSION,)
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
    if isinstance(value.get("name"), str) and value["name"] and isinstance(value.get("renamed_to"), str):
        state["name"], state["renamed_to"] = value["name"], value["renamed_to"]
    if isinstance(value.get("doubleSided"), bool):
        state["doubleSided"] = value["doubleSided"]
    if "extras" in value:
        state["extras"] = value["extras"]
    if value.get("alphaMode") == "MASK" and isinstance(value.get("alphaCutoff"), (int, float)) \
            and not isinstance(value.get("alphaCutoff"), bool) and 0.0 <= value["alphaCutoff"]:
        state["alphaMode"], state["alphaCutoff"] = "MASK", float(value["alphaCutoff"])
    unlit = value.get("unlit")
    if isinstance(unlit, dict):
        state["unlit"] = {"as_emission": True} | {key: unlit[key] for key, width in UNLIT_FACTORS.items()
                                                  if _numbers(unlit.get(key), width)}
    extensions = value.get("extensions")
    if isinstance(extensions, dict) and all(isinstance(k, str) and isinstance(v, dict) for k, v in extensions.items()):
        state["extensions"] = extensions
    return state


def _numbers(value, width: int) -> bool:
    """A finite number (``width`` 1) or a list of ``width`` of them."""
    items = [value] if width == 1 else value if isinstance(value, list) and len(value) == width else None
    return items is not None and all(isinstance(v, (int, float)) and not isinstance(v, bool) and abs(v) < float("inf")
                                     for v in items)


def notes(source, kind: str, context, state: dict | None = None) -> list:
    """What a glTF material holds beside its factors (``doubleSided``, ``extras``, extensions the
    gltf_pbr node does not carry, such as KHR_materials_diffuse_transmission and KHR_materials_unlit)
    travels to a glTF output only; anywhere else each is reported, never dropped in silence."""
    if state is None:  # ``state``: the translated material's, where the translation interpreted part of it
        state = source.extra.get("gltf") if isinstance(source.extra.get("gltf"), dict) else None
    if state is None:
        return []
    lost = [context.diagnostic(NOT_CARRIED, f"{source.name}: {sub} inside {parent} is not read by the toolkit; not "
                                            "carried", replace(
                                   source.location, path=f"{source.location.path}/extensions/{parent}/extensions/{sub}"))
            for parent, sub, read in state.get("nested_extensions") or () if not read]
    lost += [context.diagnostic(NOT_CARRIED, f"{source.name}: {name} on {pointer} is not read by the toolkit (its "
                                             "texture's own image, a fallback, stands in); not carried",
                                replace(source.location, path=f"{pointer}/extensions/{name}"))
             for pointer, name in state.get("texture_extensions") or ()]
    variants = state.get("variants") or []
    if kind == "gltf":
        lost += [context.diagnostic(NOT_CARRIED, f"{source.name}: selected by the KHR_materials_variants variants "
                                                 f"{', '.join(variants)}, whose mappings live on mesh primitives: not "
                                                 "written (the output has no meshes of the source)", source.location)
                 ] if variants else []
        return lost + [context.diagnostic(CONVERTED, f"{source.name}: {name} is not interpreted; written back as it was "
                                                     "(unless it references the source's textures)", source.location)
                       for name in sorted(state.get("extensions") or {})]
    kept = [f"doubleSided {str(state['doubleSided']).lower()}" for _ in [0] if state.get("doubleSided")]
    kept += ["extras"] if state.get("extras") else []
    kept += [f"alphaMode MASK with alphaCutoff {state.get('alphaCutoff', 0.5):g}"] if state.get("alphaMode") == "MASK" else []
    unrendered = [name for name in sorted(state.get("extensions") or {}) if name in UNRENDERED]
    kept += [name for name in sorted(state.get("extensions") or {}) if name not in UNRENDERED]
    kept += [f"KHR_materials_variants names ({', '.join(variants)})"] if variants else []
    kept += [f"KHR_materials_volume thicknessFactor {state['thickness']:g}"] if state.get("thickness") else []
    where = "attribute openpbr_gltf of its surfacematerial" if kind == "mtlx" else "customData openpbr:gltf of its Material"
    direction = state.get("anisotropy_direction")
    if direction is not None:
        lost.append(context.diagnostic(
            NOT_CARRIED, f"{source.name}: the anisotropy direction of KHR_materials_anisotropy's texture (its red and "
                         f"green channels, {getattr(direction, 'file', 'a texture')!r}) is not carried: MaterialX and "
                         "USD orient anisotropy by the tangent, so the output's runs along the mesh's tangent",
            replace(source.location, path=f"{source.location.path}/extensions/KHR_materials_anisotropy/anisotropyTexture")))
    lost += _minification_notes(source, kind, context)
    lost += [context.diagnostic(APPROXIMATED, f"{source.name}: {name} changes how the material looks and the output "
                                              f"does not render it (OpenPBR has no parameter for it); it is kept in the "
                                              f"{where} and restored when converted back to glTF",
                                source.location) for name in unrendered]
    return lost + [context.diagnostic(CONVERTED, f"{source.name}: {what} (glTF material state OpenPBR has no parameter "
                                                 f"for) is kept in the {where} and restored when converted back to glTF",
                                      source.location) for what in kept]


def _minification_notes(source, kind: str, context) -> list:
    """A glTF sampler's minFilter where the output's renderer minifies otherwise. MaterialX has no minification
    filter: its GLSL renderer (GLTextureHandler::mapFilterTypeToGL) minifies a ``closest`` image with
    NEAREST_MIPMAP_NEAREST and any other with LINEAR_MIPMAP_LINEAR; UsdUVTexture has no filter at all and Storm
    samples with LINEAR_MIPMAP_LINEAR. A minFilter equal to that survives as the renderer's own choice."""
    differing = []
    for name, entry in source.inputs.items():
        texture = entry.value
        if isinstance(texture, Texture) and texture.minification is not None:
            implied = 9984 if kind == "mtlx" and texture.filter == "closest" else 9987
            if texture.minification != implied:
                differing.append(f"{name} {MINIFICATION_FILTERS[texture.minification]} (minified with "
                                 f"{MINIFICATION_FILTERS[implied]})")
    if not differing:
        return []
    renderer = "MaterialX has no minification filter and its renderer minifies" if kind == "mtlx" else \
        "UsdUVTexture has no filter and Storm minifies"
    return [context.diagnostic(APPROXIMATED, f"{source.name}: the samplers' minFilter is not carried ({renderer} as "
                                             f"noted): {'; '.join(differing)}", source.location)]
