"""Compare a glTF material with what came back from a round trip, factor by factor, for the
round-trip tests and the before/after counts (tests/benchmarks/gltf_round_trip_counts.py).

:func:`effective` reads a material as a viewer does: every factor of the core material and of every
ratified extension with glTF's default filled in, and the drafts where present (they take precedence
over their fallbacks). Render-equivalent forms are compared, each stated here, from the glTF
specification and the extensions' READMEs:

* a property without effect is not compared: alpha and ``alphaCutoff`` of an OPAQUE material
  (specification 3.9.4), ``alphaCutoff`` unless MASK; a clearcoat's roughness at factor 0, a sheen's
  roughness with a black colour, a specular colour at factor 0; the dielectric-only terms
  (transmission, volume, IOR, specular, dispersion, diffuse transmission) of a fully metallic
  material (``metallicFactor`` 1); a volume without transmission; attenuation and dispersion of a
  thin-walled volume (thickness 0); the attenuation colour at an infinite attenuation distance; iridescence IOR and thickness at factor 0, and the minimum
  thickness without a thickness texture; a coat's other properties at weight 0; an alpha BLEND of
  alpha 1 and an alpha MASK the alpha passes are OPAQUE (without a base colour texture);
* roughness and anisotropy are compared as the alphas they render with: alpha_b = r^2 and
  alpha_t = mix(r^2, 1, s^2) (KHR_materials_anisotropy), or OpenPBR's r^2 sqrt(2 / (1 + (1 - a)^2))
  and (1 - a) alpha_t under EXT_materials_anisotropy_openpbr, alpha_t capped at 1 as glTF's is; the
  rotation only where the alphas differ and alpha_b is inside (0, 1);
* the emission is ``emissiveFactor * emissiveStrength`` (what renders; the split is free);

:func:`classify` then says, per factor, ``exact`` (within 1e-5), ``noted`` (differs, and a note of
OPBR1103/1104 names that material and a related input) or ``silent``.
"""

from __future__ import annotations

import json
import math

import numpy as np

from openpbr_tools.model import Constant

TOLERANCE = 1e-5

# (container, property, default); container "" is the material, "pbr" pbrMetallicRoughness
FACTORS = (
    ("pbr", "baseColorFactor", [1.0, 1.0, 1.0, 1.0]), ("pbr", "metallicFactor", 1.0), ("pbr", "roughnessFactor", 1.0),
    ("", "emissiveFactor", [0.0, 0.0, 0.0]), ("", "alphaMode", "OPAQUE"), ("", "alphaCutoff", 0.5),
    ("", "doubleSided", False),
    ("KHR_materials_clearcoat", "clearcoatFactor", 0.0), ("KHR_materials_clearcoat", "clearcoatRoughnessFactor", 0.0),
    ("KHR_materials_sheen", "sheenColorFactor", [0.0, 0.0, 0.0]), ("KHR_materials_sheen", "sheenRoughnessFactor", 0.0),
    ("KHR_materials_specular", "specularFactor", 1.0), ("KHR_materials_specular", "specularColorFactor", [1.0, 1.0, 1.0]),
    ("KHR_materials_transmission", "transmissionFactor", 0.0),
    ("KHR_materials_volume", "thicknessFactor", 0.0), ("KHR_materials_volume", "attenuationDistance", math.inf),
    ("KHR_materials_volume", "attenuationColor", [1.0, 1.0, 1.0]),
    ("KHR_materials_ior", "ior", 1.5),
    ("KHR_materials_iridescence", "iridescenceFactor", 0.0), ("KHR_materials_iridescence", "iridescenceIor", 1.3),
    ("KHR_materials_iridescence", "iridescenceThicknessMaximum", 400.0),
    ("KHR_materials_anisotropy", "anisotropyStrength", 0.0), ("KHR_materials_anisotropy", "anisotropyRotation", 0.0),
    ("KHR_materials_emissive_strength", "emissiveStrength", 1.0),
    ("KHR_materials_dispersion", "dispersion", 0.0),
    ("KHR_materials_diffuse_transmission", "diffuseTransmissionFactor", 0.0),
    ("KHR_materials_diffuse_transmission", "diffuseTransmissionColorFactor", [1.0, 1.0, 1.0]),
)

#: factor -> inputs a note about it may be located at: its glTF property, the gltf_pbr parameter and
#: the OpenPBR parameters it is made from or turns into (the translations' mapping tables).
RELATED = {
    "baseColor": {"baseColorFactor", "base_color", "base_weight", "alpha", "geometry_opacity"},
    "alpha": {"baseColorFactor", "alpha", "geometry_opacity", "alphaMode", "alpha_mode"},
    "metallic": {"metallicFactor", "metallic", "base_metalness"},
    "roughness": {"roughnessFactor", "roughness", "specular_roughness", "specular_roughness_anisotropy"},
    "emission": {"emissiveFactor", "emissive", "emission_color", "emission_luminance", "emissiveStrength",
                 "emissive_strength"},
    "alphaMode": {"alphaMode", "alpha_mode", "geometry_opacity"},
    "alphaCutoff": {"alphaCutoff", "alpha_cutoff", "geometry_opacity"},
    "doubleSided": {"doubleSided"},
    "clearcoat": {"clearcoatFactor", "clearcoatRoughnessFactor", "clearcoat", "clearcoat_roughness", "coat_weight",
                  "coat_roughness", "coat_roughness_anisotropy"},
    "sheen": {"sheenColorFactor", "sheenRoughnessFactor", "sheen_color", "sheen_roughness", "fuzz_weight", "fuzz_color",
              "fuzz_roughness"},
    "specular": {"specularFactor", "specularColorFactor", "specular", "specular_color", "specular_weight"},
    "transmission": {"transmissionFactor", "transmission", "transmission_weight"},
    "volume": {"thicknessFactor", "attenuationDistance", "attenuationColor", "thickness", "attenuation_distance",
               "attenuation_color", "transmission_depth", "transmission_color", "geometry_thin_walled"},
    "ior": {"ior", "specular_ior"},
    "iridescence": {"iridescenceFactor", "iridescenceIor", "iridescenceThicknessMaximum", "iridescence",
                    "iridescence_ior", "iridescence_thickness", "thin_film_weight", "thin_film_ior", "thin_film_thickness"},
    "anisotropy": {"anisotropyStrength", "anisotropyRotation", "anisotropy_strength", "anisotropy_rotation",
                   "specular_roughness_anisotropy", "roughnessFactor", "roughness", "specular_roughness"},
    "dispersion": {"dispersion", "transmission_dispersion_scale", "transmission_dispersion_abbe_number", "thicknessFactor"},
    "diffuseTransmission": {"diffuseTransmissionFactor", "diffuseTransmissionColorFactor"},
}


def _read(material: dict):
    extensions = material.get("extensions") if isinstance(material.get("extensions"), dict) else {}
    containers = {"": material, "pbr": material.get("pbrMetallicRoughness") or {}}
    containers.update(extensions)
    values = {}
    for container, prop, default in FACTORS:
        holder = containers.get(container)
        values[prop] = holder.get(prop, default) if isinstance(holder, dict) else default
    return values, extensions


def effective(material: dict, drafts: set | None = None) -> dict:
    """(group, name) -> value: the factors that change how ``material`` renders (module docstring).
    ``drafts``: the draft extensions that take precedence over their fallbacks (default: those the
    material has; for a returned material, those its source had, so fallbacks compare with fallbacks)."""
    v, extensions = _read(material)
    drafts = set(extensions) if drafts is None else drafts
    out = {}
    metal = v["metallicFactor"] >= 1.0
    out[("baseColor", "rgb")] = v["baseColorFactor"][:3]
    alpha, mode = v["baseColorFactor"][3], v["alphaMode"]
    textured_alpha = "baseColorTexture" in (material.get("pbrMetallicRoughness") or {})
    if not textured_alpha and ((mode == "BLEND" and alpha >= 1.0) or (mode == "MASK" and alpha >= v["alphaCutoff"])):
        mode = "OPAQUE"  # every fragment is drawn, fully opaque
    if mode != "OPAQUE":
        out[("alpha", "alpha")] = alpha
    out[("alphaMode", "mode")] = mode
    if mode == "MASK":
        out[("alphaCutoff", "cutoff")] = v["alphaCutoff"]
    out[("metallic", "metallic")] = v["metallicFactor"]
    strength = v["emissiveStrength"]
    out[("emission", "radiance")] = [c * strength for c in v["emissiveFactor"]]
    out[("doubleSided", "doubleSided")] = bool(v["doubleSided"])
    if "KHR_materials_coat" not in drafts:  # a draft takes precedence: its fallback is not the material
        out[("clearcoat", "weight")] = v["clearcoatFactor"]
        if v["clearcoatFactor"] > 0:
            out[("clearcoat", "roughness")] = v["clearcoatRoughnessFactor"]
    if "KHR_materials_fuzz" not in drafts:
        out[("sheen", "color")] = v["sheenColorFactor"]
        if max(v["sheenColorFactor"]) > 0:
            out[("sheen", "roughness")] = v["sheenRoughnessFactor"]
    specular = extensions.get("KHR_materials_specular") if isinstance(extensions.get("KHR_materials_specular"), dict) else {}
    openpbr_specular = "EXT_materials_specular_openpbr" in (specular.get("extensions") or {}) and \
        "EXT_materials_specular_openpbr" in drafts
    if not metal:
        if not openpbr_specular:  # the draft's meaning is the drafts test's
            out[("specular", "weight")] = v["specularFactor"]
            if v["specularFactor"] > 0:
                out[("specular", "color")] = v["specularColorFactor"]
        out[("ior", "ior")] = v["ior"]
        out[("transmission", "weight")] = v["transmissionFactor"]
        transmits = v["transmissionFactor"] > 0 or v["diffuseTransmissionFactor"] > 0
        if transmits:
            out[("volume", "thickness")] = v["thicknessFactor"]
            if v["thicknessFactor"] > 0:
                out[("volume", "attenuationDistance")] = v["attenuationDistance"]
                if math.isfinite(v["attenuationDistance"]):
                    out[("volume", "attenuationColor")] = v["attenuationColor"]
                out[("dispersion", "dispersion")] = v["dispersion"]
        out[("diffuseTransmission", "weight")] = v["diffuseTransmissionFactor"]
        if v["diffuseTransmissionFactor"] > 0:
            out[("diffuseTransmission", "color")] = v["diffuseTransmissionColorFactor"]
    out[("iridescence", "weight")] = v["iridescenceFactor"]
    if v["iridescenceFactor"] > 0:
        out[("iridescence", "ior")] = v["iridescenceIor"]
        out[("iridescence", "thickness")] = v["iridescenceThicknessMaximum"]
    anisotropy = extensions.get("KHR_materials_anisotropy") if isinstance(extensions.get("KHR_materials_anisotropy"), dict) else {}
    if (anisotropy.get("extensions") or {}).get("EXT_materials_anisotropy_openpbr", {}).get("openPbrAnisotropyEnabled") \
            is True and "EXT_materials_anisotropy_openpbr" in drafts:
        # OpenPBR's convention: compared as the alphas it renders with, in glTF's form (alpha_t capped at 1)
        r, a = v["roughnessFactor"], v["anisotropyStrength"]
        alpha_t = r * r * math.sqrt(2.0 / (1.0 + (1.0 - a) ** 2))
        alpha_b = (1.0 - a) * alpha_t
    else:
        alpha_b = v["roughnessFactor"] ** 2
        alpha_t = alpha_b + (1.0 - alpha_b) * v["anisotropyStrength"] ** 2
    out[("roughness", "roughness")] = math.sqrt(alpha_b)  # glTF's roughness, alpha_b = r^2
    out[("anisotropy", "alpha_t")] = min(alpha_t, 1.0)
    if alpha_t > alpha_b and 0 < alpha_b < 1:
        out[("anisotropy", "rotation")] = v["anisotropyRotation"]
    return out


def _equal(a, b) -> bool:
    if isinstance(a, (str, bool)) or isinstance(b, (str, bool)):
        return a == b
    a, b = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
    if a.shape != b.shape:
        return False
    with np.errstate(invalid="ignore"):  # inf - inf: equal infinities compare equal through a == b
        return bool(np.all((a == b) | (np.abs(a - b) <= TOLERANCE)))


def draft_names(material: dict) -> set:
    extensions = material.get("extensions") if isinstance(material.get("extensions"), dict) else {}
    names = set(extensions)
    for value in extensions.values():
        if isinstance(value, dict) and isinstance(value.get("extensions"), dict):
            names |= set(value["extensions"])
    return names


def classify(source: dict, returned: dict, noted_inputs: set, expected: dict | None = None):
    """[(factor, status, source value, returned value)], status ``exact``, ``noted`` or ``silent``;
    ``expected`` overrides what the source leads to expect for some factors."""
    drafts = draft_names(source)
    before, after = effective(source, drafts), effective(returned, drafts)
    before.update(expected or {})
    found = []
    for key, value in before.items():
        got = after.get(key)
        if got is not None and _equal(value, got):
            found.append((key, "exact", value, got))
        elif noted_inputs & RELATED[key[0]]:
            found.append((key, "noted", value, got))
        else:
            found.append((key, "silent", value, got))
    return found


# -- what the drafts carry ---------------------------------------------------------------------

def coat_of(material) -> dict:
    """The coat a draft-aware reader sees: KHR_materials_coat, else the clearcoat with its
    sub-extensions (no darkening and IOR 1.5 unless they say otherwise: glTF's clearcoat does not
    darken), with the drafts' defaults filled."""
    extensions = material.get("extensions", {})
    if "KHR_materials_coat" in extensions:
        coat = extensions["KHR_materials_coat"]
        return {"weight": coat.get("coatFactor", 0.0), "roughness": coat.get("coatRoughnessFactor", 0.0),
                "ior": coat.get("coatIor", 1.5), "color": coat.get("coatColorFactor", [1.0, 1.0, 1.0]),
                "darkening": coat.get("coatDarkeningFactor", 1.0), "anisotropy": coat.get("coatAnisotropyStrength", 0.0)}
    clearcoat = extensions.get("KHR_materials_clearcoat", {})
    subs = clearcoat.get("extensions", {})
    return {"weight": clearcoat.get("clearcoatFactor", 0.0), "roughness": clearcoat.get("clearcoatRoughnessFactor", 0.0),
            "ior": subs.get("KHR_materials_clearcoat_ior", {}).get("clearcoatIor", 1.5), "color": [1.0, 1.0, 1.0],
            "darkening": subs["EXT_materials_clearcoat_darkening"].get("clearcoatDarkeningFactor", 1.0)
            if "EXT_materials_clearcoat_darkening" in subs else 0.0,
            "anisotropy": 0.0}


def draft_values(material) -> dict:
    """(group, key) -> value for what the drafts carry, render-equivalent where stated: a coat of
    weight 0 has no other property, nor a fuzz of weight 0; a coat's anisotropy needs a roughness
    strictly between 0 and 1 (alpha_t = mix(r^2, 1, s^2) is r^2 whatever s at r = 0 and 1 at r = 1).
    The coat's roughness is compared as alpha = r^2, what renders: .mtlx and USD store 32-bit floats,
    which do not resolve r near 1e-3 under strong anisotropy (1 - a near 1e-6)."""
    values = {}
    coat = coat_of(material)
    values[("coat", "weight")] = coat["weight"]
    if coat["weight"] > 0:
        for key in ("ior", "color", "darkening"):
            values[("coat", key)] = coat[key]
        values[("coat", "alpha")] = coat["roughness"] ** 2
        if 0 < coat["roughness"] < 1:
            values[("coat", "anisotropy")] = coat["anisotropy"]
    extensions = material.get("extensions", {})
    fuzz = extensions.get("KHR_materials_fuzz")
    if fuzz is not None:
        values[("fuzz", "weight")] = fuzz.get("fuzzFactor", 0.0)
        if values[("fuzz", "weight")] > 0:
            values[("fuzz", "color")] = fuzz.get("fuzzColorFactor", [1.0, 1.0, 1.0])
            values[("fuzz", "roughness")] = fuzz.get("fuzzRoughnessFactor", 0.5)
    values[("diffuse", "roughness")] = extensions.get("KHR_materials_diffuse_roughness", {}).get("diffuseRoughnessFactor", 0.0)
    specular = extensions.get("KHR_materials_specular", {})
    if "EXT_materials_specular_openpbr" in specular.get("extensions", {}):
        values[("specular", "weight")] = specular.get("specularFactor", 1.0)
        values[("specular", "color")] = specular.get("specularColorFactor", [1.0, 1.0, 1.0])
    return values


def value_of(material, name, default):
    entry = material.inputs.get(name)
    return entry.value.value if entry is not None and isinstance(entry.value, Constant) else default


#: Where a note about each group may be located: glTF properties and OpenPBR parameters.
GROUP_INPUTS = {
    "coat": {"coatFactor", "coatRoughnessFactor", "coatIor", "coatColorFactor", "coatDarkeningFactor",
             "coatAnisotropyStrength", "clearcoatFactor", "clearcoatRoughnessFactor", "clearcoatIor",
             "clearcoatDarkeningFactor", "coat_weight", "coat_roughness", "coat_ior", "coat_color", "coat_darkening",
             "coat_roughness_anisotropy"},
    "fuzz": {"fuzzFactor", "fuzzColorFactor", "fuzzRoughnessFactor", "fuzz_weight", "fuzz_color", "fuzz_roughness"},
    "diffuse": {"diffuseRoughnessFactor", "base_diffuse_roughness"},
    "specular": {"specularFactor", "specularColorFactor", "specular_weight", "specular_color"},
}


def round_trip(before: list, after: list, there, back) -> list:
    """Per material of a round trip (``there`` and ``back`` the two conversions' results): the
    classified factors (:func:`classify`) and draft values (:func:`draft_values`). A material that
    gained EXT_materials_specular_openpbr (a metal with a tint or a specular weight) has OpenPBR's
    own base colour, checked against the OpenPBR the intermediate file holds; a dielectric's
    KHR_materials_specular comes back as glTF's own (fitted; what a viewer without the draft reads
    right), so the draft's values are checked in that OpenPBR too (the fit's round trip is
    test_gltf_drafts' OpenPBR -> glTF -> OpenPBR test)."""
    noted: dict = {}
    for d in there.diagnostics + back.diagnostics:
        if d.code in ("OPBR1103", "OPBR1104"):
            noted.setdefault(d.location.material, set()).add(d.location.input)
    results = []
    for index, (a, b) in enumerate(zip(before, after)):
        middle = there.pairs[index][1]
        unique = middle.material_name
        inputs = noted.get(a["name"], set()) | noted.get(unique, set()) | noted.get(f"{unique}_shader", set())
        override = {}
        gained = "EXT_materials_specular_openpbr" in json.dumps(b) and "EXT_materials_specular_openpbr" not in json.dumps(a)
        # (a thin-walled subsurface scattered forward only is glTF's diffuse transmission: the base colour stays)
        forward_only = value_of(middle, "geometry_thin_walled", False) and \
            value_of(middle, "subsurface_scatter_anisotropy", 0.0) == 1.0
        if gained and not value_of(middle, "transmission_weight", 0.0) and \
                (not value_of(middle, "subsurface_weight", 0.0) or forward_only):
            weight = value_of(middle, "base_weight", 1.0)
            override[("baseColor", "rgb")] = [weight * c for c in value_of(middle, "base_color", (0.8, 0.8, 0.8))]
        found = classify(a, b, inputs, override)
        expected, returned = draft_values(a), draft_values(b)
        if ("specular", "weight") in expected and ("specular", "weight") not in returned:
            returned[("specular", "weight")] = value_of(middle, "specular_weight", 1.0)
            returned[("specular", "color")] = value_of(middle, "specular_color", (1.0, 1.0, 1.0))
        for key, value in expected.items():
            got = returned.get(key, {"weight": 0.0}.get(key[1]))
            if got is not None and _equal(value, got):
                found.append((("draft " + key[0], key[1]), "exact", value, got))
            elif inputs & GROUP_INPUTS[key[0]]:
                found.append((("draft " + key[0], key[1]), "noted", value, got))
            else:
                found.append((("draft " + key[0], key[1]), "silent", value, got))
        results.append(found)
    return results
