"""Standard Surface's anisotropy rotations carried to OpenPBR as a rotated tangent (the red team's F-03: they were
dropped without a note).

Standard Surface turns its anisotropy by ``specular_rotation`` (and the coat's by ``coat_rotation``), in turns about
the normal: MaterialX's NG_standard_surface_surfaceshader_100 computes the tangent it shades with as
``normalize(rotate3d(tangent, 360 * rotation, normal))`` (the coat's about ``coat_normal``) where the anisotropy is
above 0. OpenPBR has no rotation input: it takes the tangent itself (``geometry_tangent``, ``geometry_coat_tangent``,
world space, default Tworld). A .mtlx output holds MaterialX nodes, so the same three nodes (``tangent``, ``normal``
in world space, ``rotate3d``, then ``normalize``) are written as the OpenPBR tangent: the same vector, exactly. Other
outputs, a textured rotation and a material whose tangent is already authored keep the "no equivalent" note
(:data:`~.standard_surface.DROPPED_FROM_SS`).
"""

from __future__ import annotations

from ..model import Connection, Constant, Input, Material
from ..rules.translation import APPROXIMATED, CONVERTED

#: (Standard Surface rotation, its anisotropy, its tangent, its normal; OpenPBR's tangent)
ROTATIONS = (("specular_rotation", "specular_anisotropy", "tangent", "normal", "geometry_tangent"),
             ("coat_rotation", "coat_anisotropy", "tangent", "coat_normal", "geometry_coat_tangent"))

_GRAPH = """<?xml version="1.0"?>
<materialx version="1.39">
  <tangent name="tangent" type="vector3">
    <input name="space" type="string" value="world" />
  </tangent>
  <normal name="normal" type="vector3">
    <input name="space" type="string" value="world" />
  </normal>
  <rotate3d name="rotated" type="vector3">
    <input name="in" type="vector3" nodename="tangent" />
    <input name="amount" type="float" value="{degrees!r}" />
    <input name="axis" type="vector3" nodename="normal" />
  </rotate3d>
  <normalize name="rotated_tangent" type="vector3">
    <input name="in" type="vector3" nodename="rotated" />
  </normalize>
</materialx>
"""


def _constant(material: Material, name: str, default: float = 0.0):
    entry = material.inputs.get(name)
    if entry is None:
        return default
    return float(entry.value.value) if isinstance(entry.value, Constant) and isinstance(entry.value.value, (int, float)) \
        else None


def carried(material: Material, node_graphs: bool) -> dict[str, tuple[str, float, bool]]:
    """OpenPBR tangent -> (Standard Surface rotation, turns, axis mapped) for the rotations written as a rotated
    tangent: a constant rotation that turns (not a whole or half turn, which leaves an anisotropy as it is) an
    anisotropy above 0, with the tangent left at its default, where the output holds node graphs. ``axis mapped``:
    the normal it turns about is authored (a normal map), where the written tangent turns about the geometric
    normal instead (an approximation, noted)."""
    if not node_graphs or material.model != "standard_surface":
        return {}
    found = {}
    for rotation, anisotropy, tangent, normal, target in ROTATIONS:
        turns, amount = _constant(material, rotation), _constant(material, anisotropy)
        if turns is None or amount is None or turns % 0.5 == 0 or amount <= 0:
            continue
        if tangent in material.inputs:
            continue
        found[target] = (rotation, turns, normal in material.inputs)
    return found


def apply(material: Material, result: Material, rotations: dict[str, tuple[str, float]], context, label: str) -> list:
    """Writes each rotated tangent into ``result``; returns the notes (OPBR1102: exact)."""
    notes = []
    for target, (rotation, turns, mapped) in rotations.items():
        degrees = round(turns * 360.0, 9) + 0.0
        where = material.inputs[rotation].location
        result.inputs[target] = Input(target, "vector3", Connection(
            target, "rotate3d", f"Standard Surface's {rotation} as a rotated tangent",
            graph_xml=_GRAPH.format(degrees=degrees), output="rotated_tangent"), where)
        notes.append(context.diagnostic(
            APPROXIMATED if mapped else CONVERTED,
            f"{label}: {rotation} {turns:g} ({degrees % 360:g} degrees) written as {target}: the world tangent turned "
            "about the normal by MaterialX nodes, as Standard Surface's own graph turns it"
            + (" (about the geometric normal: Standard Surface turns it about its mapped normal)" if mapped else ""),
            where))
    return notes


def onto_candidate(mapped: Material, candidate: Material) -> set[str]:
    """Where MaterialX's translation graphs' result (``candidate``, which turns no tangent) is kept instead of the
    mapping's (``mapped``): the mapping's rotated tangents copied onto it; returns the rotations so carried."""
    carried_rotations = set()
    for rotation, _, _, _, target in ROTATIONS:
        entry = mapped.inputs.get(target)
        if entry is not None and isinstance(entry.value, Connection) and entry.value.category == "rotate3d" \
                and target not in candidate.inputs:
            candidate.inputs[target] = entry
            carried_rotations.add(rotation)
    return carried_rotations
