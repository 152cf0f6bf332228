"""Seeded materials that sweep every parameter of a shading model over its whole legal range, for
tests that must hold on the input space rather than on examples.

Each parameter is absent (the model's default applies) about a third of the time; when present it is
drawn from its table's range (schemas/models): uniformly inside a hard range, from the soft range or
a generous span where the hard range is open-ended, exactly on a closed bound now and then (odd but
legal: a roughness of exactly 0, a weight of exactly 1), any value of an enum, either boolean.
Geometry vectors (normals, tangents) are left to the geometry. The document colour space is one of
``lin_rec709``, ``acescg`` and ``lin_displayp3``.
"""

from __future__ import annotations

import random

from openpbr_tools import tables
from openpbr_tools.values import format_value

COLORSPACES = ("lin_rec709", "acescg", "lin_displayp3")
OPEN_ENDED_SPAN = 10.0  # upper end drawn for a parameter bounded only below (no soft maximum either)


def _component(rng: random.Random, low, high, exclusive: bool) -> float:
    if low is None and high is None:
        low, high = -OPEN_ENDED_SPAN, OPEN_ENDED_SPAN
    elif high is None:
        high = low + OPEN_ENDED_SPAN
    elif low is None:
        low = high - OPEN_ENDED_SPAN
    roll = rng.random()
    if roll < 0.07 and not exclusive:
        return float(low)
    if roll < 0.14:
        return float(high)
    value = rng.uniform(low, high)
    return value if value != low or not exclusive else (low + high) / 2.0


def _range(parameter):
    low = parameter.hard_min
    high = parameter.hard_max if parameter.hard_max is not None else parameter.soft_max
    return low, high


def value_for(parameter, rng: random.Random):
    """A legal value of ``parameter`` (see the module docstring)."""
    if parameter.type == "boolean":
        return rng.random() < 0.5
    if parameter.enum is not None:
        return rng.choice(list(parameter.enum))
    low, high = _range(parameter)
    if parameter.type == "integer":
        return int(round(_component(rng, low, high, parameter.hard_min_exclusive)))
    if parameter.type == "float":
        return _component(rng, low, high, parameter.hard_min_exclusive)
    width = {"color3": 3, "vector3": 3, "color4": 4, "vector2": 2}[parameter.type]
    pick = lambda bound, i: bound[i] if isinstance(bound, tuple) else bound  # noqa: E731
    return tuple(_component(rng, pick(low, i), pick(high, i), parameter.hard_min_exclusive) for i in range(width))


def material_values(model: str, rng: random.Random) -> dict:
    """Parameter -> value for one material of ``model``; absent parameters take the default."""
    table = tables.table(model)
    values = {}
    for name, parameter in table.parameters.items():
        if parameter.role in ("normal", "tangent") or parameter.type in ("string", "filename"):
            continue
        if rng.random() < 0.35:
            continue
        values[name] = value_for(parameter, rng)
    return values


def document(model: str, colorspace: str, seed: int, count: int) -> str:
    """A .mtlx document with ``count`` materials of ``model`` drawn from ``seed``."""
    rng = random.Random(f"{model}/{colorspace}/{seed}")
    return _mtlx(model, colorspace, [material_values(model, rng) for _ in range(count)])


def _mtlx(model: str, colorspace: str, materials: list[dict]) -> str:
    """A .mtlx document of ``model`` shaders ``S<i>`` with these values, each in a material ``M<i>``."""
    table = tables.table(model)
    version = f' version="{table.version}"' if model == "open_pbr_surface" else ""
    parts = [f'<?xml version="1.0"?>\n<materialx version="1.39" colorspace="{colorspace}">']
    for index, values in enumerate(materials):
        shader = f"S{index}"
        parts.append(f'  <{model} name="{shader}" type="surfaceshader"{version}>')
        for name, value in values.items():
            type_name = table[name].type
            parts.append(f'    <input name="{name}" type="{type_name}" value="{format_value(value, type_name)}" />')
        parts.append(f"  </{model}>")
        parts.append(f'  <surfacematerial name="M{index}" type="material">\n'
                     f'    <input name="surfaceshader" type="surfaceshader" nodename="{shader}" />\n  </surfacematerial>')
    parts.append("</materialx>\n")
    return "\n".join(parts)


# The kinds of OpenPBR material artists author, each with its own parameters drawn over their whole
# range (value_for) and everything else absent: a metal with or without an edge tint, an opaque
# dielectric (plastic, paint, stone), a subsurface material (skin, wax), a glass or liquid (with or
# without a tinted volume), a thin-walled sheet (paper, leaf, soap bubble), a cut-out. Layers a
# material of any kind may carry: coat, thin film, fuzz, emission. The fidelity benchmark runs on
# these as well as on material_values, whose materials switch every lobe on at once.
KINDS = ("dielectric", "metal", "metal_edge_tint", "subsurface", "glass", "thin_walled", "cutout")
LAYERS = {"coat": 0.35, "thin_film": 0.15, "fuzz": 0.15, "emission": 0.1}
_KIND_PARAMETERS = {
    "dielectric": ("base_weight", "base_color", "base_diffuse_roughness", "specular_weight", "specular_color",
                   "specular_roughness", "specular_ior", "specular_roughness_anisotropy"),
    "metal": ("base_weight", "base_color", "specular_weight", "specular_roughness", "specular_roughness_anisotropy"),
    "subsurface": ("base_color", "specular_roughness", "specular_ior", "subsurface_color", "subsurface_radius",
                   "subsurface_radius_scale", "subsurface_scatter_anisotropy"),
    "glass": ("specular_roughness", "specular_ior", "specular_weight", "transmission_color", "transmission_depth",
              "transmission_scatter", "transmission_scatter_anisotropy", "transmission_dispersion_scale",
              "transmission_dispersion_abbe_number"),
    "cutout": ("base_color", "specular_roughness", "base_metalness"),
}
_KIND_PARAMETERS["metal_edge_tint"] = _KIND_PARAMETERS["metal"] + ("specular_color",)
_KIND_PARAMETERS["thin_walled"] = ("base_color", "specular_roughness", "specular_ior", "transmission_color",
                                   "subsurface_color")
_LAYER_PARAMETERS = {
    "coat": ("coat_color", "coat_roughness", "coat_roughness_anisotropy", "coat_ior", "coat_darkening"),
    "thin_film": ("thin_film_thickness", "thin_film_ior"),
    "fuzz": ("fuzz_color", "fuzz_roughness"),
    "emission": ("emission_color",),
}


def archetype_values(rng: random.Random) -> tuple[str, dict]:
    """(kind, parameter -> value) for one OpenPBR material of a kind artists author (see KINDS)."""
    table = tables.table("open_pbr_surface")
    kind = rng.choice(KINDS)
    values = {name: value_for(table[name], rng) for name in _KIND_PARAMETERS[kind] if rng.random() >= 0.35}
    unit = lambda: rng.choice((1.0, rng.uniform(0.0, 1.0)))  # noqa: E731 - a full weight half the time
    if kind.startswith("metal"):
        values["base_metalness"] = unit()
    elif kind == "subsurface":
        values["subsurface_weight"] = unit()
    elif kind == "glass":
        values["transmission_weight"] = unit()
    elif kind == "thin_walled":
        values["geometry_thin_walled"] = True
        values[rng.choice(("transmission_weight", "subsurface_weight"))] = unit()
    elif kind == "cutout":
        values["geometry_opacity"] = value_for(table["geometry_opacity"], rng)
    for layer, probability in LAYERS.items():
        if rng.random() < probability:
            weight = "emission_luminance" if layer == "emission" else f"{layer}_weight"
            values[weight] = value_for(table[weight], rng) if layer != "emission" else 10 ** rng.uniform(-1.0, 3.0)
            values.update((name, value_for(table[name], rng)) for name in _LAYER_PARAMETERS[layer]
                          if rng.random() >= 0.35)
    return kind, values


def archetype_document(colorspace: str, seed: int, count: int) -> tuple[str, list[str]]:
    """A .mtlx document of ``count`` OpenPBR materials of the KINDS, and each material's kind."""
    rng = random.Random(f"archetypes/{colorspace}/{seed}")
    kinds, materials = zip(*(archetype_values(rng) for _ in range(count))) if count else ((), ())
    return _mtlx("open_pbr_surface", colorspace, list(materials)), list(kinds)
