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
    table = tables.table(model)
    parts = [f'<?xml version="1.0"?>\n<materialx version="1.39" colorspace="{colorspace}">']
    for index in range(count):
        shader = f"S{index}"
        version = f' version="{table.version}"' if model == "open_pbr_surface" else ""
        parts.append(f'  <{model} name="{shader}" type="surfaceshader"{version}>')
        for name, value in material_values(model, rng).items():
            type_name = table[name].type
            parts.append(f'    <input name="{name}" type="{type_name}" value="{format_value(value, type_name)}" />')
        parts.append(f"  </{model}>")
        parts.append(f'  <surfacematerial name="M{index}" type="material">\n'
                     f'    <input name="surfaceshader" type="surfaceshader" nodename="{shader}" />\n  </surfacematerial>')
    parts.append("</materialx>\n")
    return "\n".join(parts)
