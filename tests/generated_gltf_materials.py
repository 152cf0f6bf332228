"""Seeded glTF documents whose materials draw every factor of the core material, of every ratified
``KHR_materials_*`` extension and of the draft extensions the toolkit reads (``KHR_materials_coat``,
``_fuzz``, ``_diffuse_roughness``, ``KHR_materials_clearcoat_ior`` and the
``EXT_materials_*_openpbr`` sub-extensions) over its whole schema range, for the round-trip tests.

Each property is absent (glTF's default applies) about a third of the time; when present it is drawn
from its schema range, exactly on a closed bound now and then. Names repeat now and then (glTF allows
it). A textured variant adds a PNG on base colour, metallic-roughness, normal, clearcoat and coat
weight, with ``KHR_texture_transform`` on some of them. Ranges are the extensions' schemas
(KhronosGroup/glTF ``extensions/2.0/Khronos/*/schema``; the drafts' READMEs for the drafts).
"""

from __future__ import annotations

import json
import math
import random

# property -> (low, high, width); None high: drawn up to the given span
CORE = {"metallicFactor": (0, 1, 1), "roughnessFactor": (0, 1, 1), "emissiveFactor": (0, 1, 3),
        "alphaCutoff": (0, 1, 1)}
RATIFIED = {
    "KHR_materials_clearcoat": {"clearcoatFactor": (0, 1, 1), "clearcoatRoughnessFactor": (0, 1, 1)},
    "KHR_materials_sheen": {"sheenColorFactor": (0, 1, 3), "sheenRoughnessFactor": (0, 1, 1)},
    "KHR_materials_specular": {"specularFactor": (0, 1, 1), "specularColorFactor": (0, 1, 3)},
    "KHR_materials_transmission": {"transmissionFactor": (0, 1, 1)},
    "KHR_materials_volume": {"thicknessFactor": (0, 4, 1), "attenuationDistance": (0.01, 50, 1),
                             "attenuationColor": (0, 1, 3)},
    "KHR_materials_ior": {"ior": (1, 3, 1)},
    "KHR_materials_iridescence": {"iridescenceFactor": (0, 1, 1), "iridescenceIor": (1, 2.5, 1),
                                  "iridescenceThicknessMinimum": (0, 400, 1), "iridescenceThicknessMaximum": (100, 1200, 1)},
    "KHR_materials_anisotropy": {"anisotropyStrength": (0, 1, 1), "anisotropyRotation": (-math.pi, math.pi, 1)},
    "KHR_materials_emissive_strength": {"emissiveStrength": (0, 20, 1)},
    "KHR_materials_dispersion": {"dispersion": (0, 1, 1)},
    "KHR_materials_diffuse_transmission": {"diffuseTransmissionFactor": (0, 1, 1),
                                           "diffuseTransmissionColorFactor": (0, 1, 3)},
}
DRAFTS = {
    "KHR_materials_coat": {"coatFactor": (0, 1, 1), "coatRoughnessFactor": (0, 1, 1), "coatIor": (1, 2.5, 1),
                           "coatColorFactor": (0, 1, 3), "coatDarkeningFactor": (0, 1, 1),
                           "coatAnisotropyStrength": (0, 1, 1)},
    "KHR_materials_fuzz": {"fuzzFactor": (0, 1, 1), "fuzzColorFactor": (0, 1, 3), "fuzzRoughnessFactor": (0, 1, 1)},
    "KHR_materials_diffuse_roughness": {"diffuseRoughnessFactor": (0, 1, 1)},
}
SUB_DRAFTS = {  # parent -> (sub-extension, its properties)
    "KHR_materials_specular": ("EXT_materials_specular_openpbr", {}),
    "KHR_materials_clearcoat": ("EXT_materials_clearcoat_darkening", {"clearcoatDarkeningFactor": (0, 1, 1)}),
    "KHR_materials_anisotropy": ("EXT_materials_anisotropy_openpbr", {}),
}
NAMES = ("Paint", "Metal", "Glass", "Fabric")  # drawn now and then: duplicate names


def _number(rng: random.Random, low, high):
    roll = rng.random()
    if roll < 0.06:
        return float(low)
    if roll < 0.12:
        return float(high)
    return round(rng.uniform(low, high), 6)


def _value(rng, spec):
    low, high, width = spec
    return _number(rng, low, high) if width == 1 else [_number(rng, low, high) for _ in range(width)]


def _properties(rng, table: dict) -> dict:
    return {name: _value(rng, spec) for name, spec in table.items() if rng.random() < 2 / 3}


def material(rng: random.Random, index: int, textured: bool = False) -> dict:
    name = rng.choice(NAMES) if rng.random() < 0.08 else f"material_{index}"
    out: dict = {"name": name}
    pbr = _properties(rng, {k: CORE[k] for k in ("metallicFactor", "roughnessFactor")})
    if rng.random() < 2 / 3:
        pbr["baseColorFactor"] = [_number(rng, 0, 1) for _ in range(4)]
    out["pbrMetallicRoughness"] = pbr
    core = _properties(rng, {"emissiveFactor": CORE["emissiveFactor"]})
    out.update(core)
    if rng.random() < 0.4:
        out["alphaMode"] = rng.choice(["OPAQUE", "MASK", "BLEND"])
        if out["alphaMode"] == "MASK" and rng.random() < 2 / 3:
            out["alphaCutoff"] = _number(rng, 0, 1)
    if rng.random() < 0.3:
        out["doubleSided"] = rng.random() < 0.5
    extensions: dict = {}
    if rng.random() < 0.03:
        extensions["KHR_materials_unlit"] = {}
    else:
        for name, table in RATIFIED.items():
            if rng.random() < 0.35:
                extensions[name] = _properties(rng, table)
        for name, table in DRAFTS.items():
            if rng.random() < 0.25:
                extensions[name] = _properties(rng, table)
        for parent, (sub, table) in SUB_DRAFTS.items():
            if parent in extensions and rng.random() < 0.4:
                extensions[parent]["extensions"] = {sub: _properties(rng, table) if table else {}}
                if sub == "EXT_materials_anisotropy_openpbr":
                    extensions[parent]["extensions"][sub] = {"openPbrAnisotropyEnabled": True}
        if "KHR_materials_clearcoat" in extensions and rng.random() < 0.2:
            extensions["KHR_materials_clearcoat"].setdefault("extensions", {})["KHR_materials_clearcoat_ior"] = \
                _properties(rng, {"clearcoatIor": (1, 2.5, 1)})
    if "KHR_materials_volume" in extensions and out.get("doubleSided"):
        out["doubleSided"] = False  # a volume on a double-sided material is valid, but the validator warns
    if textured:
        _textures(rng, out, extensions)
    if extensions:
        out["extensions"] = extensions
    return out


def _info(rng, index: int = 0) -> dict:
    info: dict = {"index": index}
    if rng.random() < 0.5:
        info["extensions"] = {"KHR_texture_transform": {
            "offset": [_number(rng, -1, 1), _number(rng, -1, 1)], "scale": [_number(rng, 0.25, 4), _number(rng, 0.25, 4)],
            "rotation": _number(rng, -math.pi, math.pi)}}
    return info


def _textures(rng, out, extensions) -> None:
    pbr = out["pbrMetallicRoughness"]
    if rng.random() < 0.6:
        pbr["baseColorTexture"] = _info(rng)
    if rng.random() < 0.6:
        pbr["metallicRoughnessTexture"] = _info(rng)
    if rng.random() < 0.5:
        out["normalTexture"] = dict(_info(rng), scale=_number(rng, 0, 2))
    if "KHR_materials_clearcoat" in extensions and rng.random() < 0.5:
        extensions["KHR_materials_clearcoat"]["clearcoatTexture"] = _info(rng)
    if "KHR_materials_coat" in extensions and rng.random() < 0.5:
        extensions["KHR_materials_coat"]["coatTexture"] = _info(rng)


def document(seed: int, count: int, textured: bool = False, image_uri: str = "texture.png") -> dict:
    """A glTF document with ``count`` generated materials (``textured``: one image, sampled by some)."""
    rng = random.Random(seed)
    materials = [material(rng, i, textured) for i in range(count)]
    used = set()
    for m in materials:
        used.update(m.get("extensions", {}))
        for value in m.get("extensions", {}).values():
            used.update(value.get("extensions", {}) if isinstance(value, dict) else {})
    text = json.dumps(materials)
    if "KHR_texture_transform" in text:
        used.add("KHR_texture_transform")
    doc: dict = {"asset": {"version": "2.0"}, "materials": materials}
    if used:
        doc["extensionsUsed"] = sorted(used)
    if textured:
        doc["images"] = [{"uri": image_uri}]
        doc["textures"] = [{"source": 0}]
    return doc
