"""The version steps of an OpenPBR upgrade: one function per release, each emitting *edits* (rename,
set a constant, remove, connect a node graph) and diagnostics, applied to the model-neutral
:class:`Material` as they are made. :mod:`openpbr_tools.translate.upgrade` chains the steps and
applies the same edits to a MaterialX document.

Exact:
  * renames (0.3 ``transmission_dispersion`` -> scale + Abbe number; 0.4 ``base_roughness``;
    0.5 ``*_anisotropy`` -> ``*_roughness_anisotropy``, ``subsurface_anisotropy``);
  * 0.4 ``specular_ior_level`` / ``coat_ior_level`` folded into the IOR with the same reflectance
    at normal incidence: the v0.2 specification describes the level as scaling F0 from 0 (level 0)
    through unchanged (0.5) to double (1); F0' = 2 * level * F0 is taken as linear between those
    anchors, and n' = (1 + sqrt(F0')) / (1 - sqrt(F0')) (kept below 1 for an IOR below 1);
  * 0.5 thin-film thickness nanometres -> micrometres (/1000) and ``thin_film_weight`` = 1 where a
    film was set, taking the unit of each version from the parameter tables;
  * 0.5 ``*_rotation`` carried by rotating the tangent about the normal (a ``rotate3d`` graph on
    ``geometry_tangent`` / ``geometry_coat_tangent``); the rotation's [0, 1] maps to 0-360 degrees;
  * 1.1 ``thin_film_ior`` default 1.5 -> 1.4: an unset value is written as 1.5 where a film exists.

Approximated or not carried (reported):
  * a colour ``geometry_opacity`` (0.2-0.4) becomes the mean of its channels (exact for grey);
  * textured IOR levels, textured rotations and textured nanometre thicknesses need baking and are
    reported as not carried;
  * 1.0 changed the Abbe number default from the reference node's 0 to the specification's 20;
  * 1.1.1 stopped scaling the metal edge tint by ``specular_weight``: reported, not compensated.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

from .. import tables
from ..diagnostics import Diagnostic
from ..io.mtlx.writer import document_text
from ..model import Connection, Constant, Input, Material
from ..rules import Context
from ..values import COMPONENTS
from ..rules.translation import (APPROXIMATED, CONVERTED, DEFAULT_PINNED, GRAPH_INSERTED, LOOK_CHANGED,
                                 NOT_CARRIED, RENAMED)

MODEL = "open_pbr_surface"


@dataclass(frozen=True, slots=True)
class GraphNode:
    """A node to insert: ``inputs`` maps an input name to ``(type, value)`` or ``(type, "@node")``
    for a connection to another inserted node."""

    category: str
    name: str
    type: str
    inputs: tuple[tuple[str, str, str], ...] = ()


@dataclass(frozen=True, slots=True)
class Edit:
    """One change to a shader's inputs. ``kind`` is ``rename``, ``set``, ``remove``, ``graph`` or
    ``channels`` (read one channel / the mean of a texture)."""

    kind: str
    name: str
    new_name: str | None = None
    value: Any = None
    type: str | None = None
    graph: tuple[GraphNode, ...] = ()


@dataclass(slots=True)
class Upgrade:
    material: Material
    edits: list[Edit] = field(default_factory=list)
    diagnostics: list[Diagnostic] = field(default_factory=list)
    from_version: str | None = None


class Step:
    """Edits and diagnostics of one version step, applied to the material as they are made."""

    def __init__(self, upgrade: Upgrade, source: str, target: str, context: Context):
        self.upgrade = upgrade
        self.material = upgrade.material
        self.source = tables.table(MODEL, source)
        self.target = tables.table(MODEL, target)
        self.context = context
        self.label = f"{source} -> {target}"

    # -- reading --------------------------------------------------------------------------
    def authored(self, name: str) -> bool:
        return name in self.material.inputs

    def entry(self, name: str) -> Input | None:
        return self.material.inputs.get(name)

    def constant(self, name: str):
        """The authored constant, the source version's default when unset; ``None`` when the input
        is textured, connected, unparsable or of another type than the version defines."""
        entry = self.material.inputs.get(name)
        parameter = self.source.get(name)
        if entry is None:
            return parameter.default if parameter is not None else None
        value = entry.constant
        if parameter is None or value is None or (entry.type and entry.type != parameter.type):
            return None
        expected = COMPONENTS.get(parameter.type, 1)
        if expected == 1:
            return float(value) if isinstance(value, (int, float)) and not isinstance(value, bool) else \
                (value if isinstance(value, bool) and parameter.type == "boolean" else None)
        return value if isinstance(value, tuple) and len(value) == expected else None

    # -- reporting ------------------------------------------------------------------------
    def report(self, rule, message: str, name: str | None = None) -> None:
        entry = self.material.inputs.get(name) if name else None
        location = entry.location if entry is not None else self.material.location.with_input(name)
        location = location.with_material(self.material.material_name or self.material.name)
        self.upgrade.diagnostics.append(
            self.context.diagnostic(rule, f"{self.material.name} ({self.label}): {message}", location)
        )

    # -- editing --------------------------------------------------------------------------
    def edit(self, edit: Edit) -> None:
        self.upgrade.edits.append(edit)
        apply_edit(self.material, edit)

    def rename(self, old: str, new: str) -> None:
        if not self.authored(old):
            return
        if self.authored(new):
            self.report(NOT_CARRIED, f"both {old} and its successor {new} are set: kept {new}, dropped {old}", old)
            self.remove(old)
            return
        self.edit(Edit("rename", old, new_name=new))
        self.report(RENAMED, f"{old} renamed {new}", new)

    def set(self, name: str, value, type_name: str | None = None) -> None:
        type_name = type_name or self.target[name].type
        self.edit(Edit("set", name, value=value, type=type_name))

    def remove(self, name: str) -> None:
        if self.authored(name):
            self.edit(Edit("remove", name))


def apply_edit(material: Material, edit: Edit) -> None:
    """Apply one edit to the model-neutral material."""
    inputs = material.inputs
    if edit.kind == "rename":
        entry = inputs.pop(edit.name)
        entry.name = edit.new_name
        entry.location = entry.location.with_input(edit.new_name)
        inputs[edit.new_name] = entry
    elif edit.kind == "set":
        old = inputs.get(edit.name)
        location = old.location if old is not None else material.location.with_input(edit.name)
        inputs[edit.name] = Input(edit.name, edit.type, Constant(edit.value), location,
                                  colorspace=old.colorspace if old is not None else material.colorspace,
                                  unit=old.unit if old is not None else None,
                                  unittype=old.unittype if old is not None else None)
    elif edit.kind == "remove":
        inputs.pop(edit.name, None)
    elif edit.kind == "graph":
        output = edit.graph[-1]
        inputs[edit.name] = Input(edit.name, edit.type, Connection(output.name, output.category, "inserted by upgrade",
                                                                   graph_xml=graph_document(edit.graph), output=output.name),
                                  material.location.with_input(edit.name))
    elif edit.kind == "channels":
        entry = inputs[edit.name]
        entry.value.channels = edit.value
        entry.type = edit.type
    else:  # pragma: no cover - a programming error
        raise ValueError(edit.kind)


def graph_document(nodes: tuple[GraphNode, ...]) -> str:
    import MaterialX as mx  # lazy: MaterialX's bindings (~8 ms) load only when a graph edit is made

    document = mx.createDocument()
    for node in nodes:
        element = document.addNode(node.category, node.name, node.type)
        for name, type_name, value in node.inputs:
            port = element.addInput(name, type_name)
            if value.startswith("@"):
                port.setNodeName(value[1:])
            else:
                port.setValueString(value)
    return document_text(document)


# -- the steps ----------------------------------------------------------------------------------

def _to_0_3(step: Step) -> None:
    if not step.authored("transmission_dispersion"):
        return
    abbe = step.constant("transmission_dispersion")
    if abbe is None:
        step.report(NOT_CARRIED, "a textured or mistyped transmission_dispersion (an Abbe number) cannot become "
                    "transmission_dispersion_abbe_number without baking; dropped", "transmission_dispersion")
    elif abbe > 0:
        step.set("transmission_dispersion_abbe_number", float(abbe))
        step.set("transmission_dispersion_scale", 1.0)
        step.report(CONVERTED, f"transmission_dispersion {abbe:g} (Abbe number) became "
                    f"transmission_dispersion_abbe_number {abbe:g} with transmission_dispersion_scale 1",
                    "transmission_dispersion_abbe_number")
    step.remove("transmission_dispersion")


def fold_ior_level(ior: float, level: float) -> float:
    """The IOR with the normal-incidence reflectance that ``level`` gave ``ior`` in OpenPBR 0.2-0.3."""
    f0 = ((ior - 1.0) / (ior + 1.0)) ** 2
    scaled = min(2.0 * level * f0, 0.999999)
    root = math.sqrt(max(scaled, 0.0))
    folded = (1.0 + root) / (1.0 - root)
    return 1.0 / folded if ior < 1.0 else folded


def _to_0_4(step: Step) -> None:
    step.rename("base_roughness", "base_diffuse_roughness")
    for level_name, ior_name in (("specular_ior_level", "specular_ior"), ("coat_ior_level", "coat_ior")):
        if not step.authored(level_name):
            continue
        level, ior = step.constant(level_name), step.constant(ior_name)
        if level is None or ior is None:
            step.report(NOT_CARRIED, f"{level_name} or {ior_name} is textured or mistyped: folding the level into the IOR "
                        "needs a baked IOR texture; the level was dropped", level_name)
        elif level != 0.5:
            folded = fold_ior_level(float(ior), float(level))
            step.set(ior_name, folded)
            step.report(CONVERTED, f"{level_name} {level:g} folded into {ior_name}: {ior:g} -> {folded:.6g} "
                        "(same reflectance at normal incidence)", ior_name)
        step.remove(level_name)


def _rotation_graph(prefix: str, turns: float, tangent_space: str = "world") -> tuple[GraphNode, ...]:
    degrees = f"{(turns % 1.0) * 360.0:.10g}"
    return (
        GraphNode("tangent", f"{prefix}_tangent", "vector3", (("space", "string", tangent_space),)),
        GraphNode("normal", f"{prefix}_normal", "vector3", (("space", "string", tangent_space),)),
        GraphNode("rotate3d", f"{prefix}_rotated_tangent", "vector3",
                  (("in", "vector3", f"@{prefix}_tangent"), ("amount", "float", degrees),
                   ("axis", "vector3", f"@{prefix}_normal"))),
    )


def _to_0_5(step: Step) -> None:
    for old, new in (("specular_anisotropy", "specular_roughness_anisotropy"),
                     ("coat_anisotropy", "coat_roughness_anisotropy"),
                     ("subsurface_anisotropy", "subsurface_scatter_anisotropy")):
        step.rename(old, new)
    for rotation, anisotropy, tangent in (("specular_rotation", "specular_roughness_anisotropy", "geometry_tangent"),
                                          ("coat_rotation", "coat_roughness_anisotropy", "geometry_coat_tangent")):
        if not step.authored(rotation):
            continue
        turns, amount = step.constant(rotation), step.constant(anisotropy)
        if turns is None:
            step.report(NOT_CARRIED, f"a textured or mistyped {rotation} needs a baked tangent map; dropped", rotation)
        elif turns % 0.5 != 0 and amount != 0:
            if step.authored(tangent):
                step.report(NOT_CARRIED, f"{rotation} {turns:g} cannot be applied: {tangent} is already set", rotation)
            else:
                prefix = f"{step.material.name}_{tangent}"
                step.edit(Edit("graph", tangent, type="vector3", graph=_rotation_graph(prefix, float(turns))))
                step.report(GRAPH_INSERTED, f"{rotation} {turns:g} ({(turns % 1.0) * 360:g} degrees) carried by "
                            f"rotating {tangent} about the normal", tangent)
        step.remove(rotation)
    _thin_film_units(step)
    if step.authored("geometry_opacity"):
        entry = step.entry("geometry_opacity")
        value = step.constant("geometry_opacity")
        if isinstance(value, tuple):
            mean = sum(value) / len(value)
            step.set("geometry_opacity", mean, "float")
            rule = CONVERTED if max(value) == min(value) else APPROXIMATED
            step.report(rule, f"colour geometry_opacity {value} became the float {mean:.6g} (mean of the channels)",
                        "geometry_opacity")
        elif entry.texture is not None and entry.texture.channels is None and entry.texture.image_type in ("color3", "color4"):
            step.edit(Edit("channels", "geometry_opacity", value=(0,), type="float"))
            step.report(APPROXIMATED, "colour opacity texture: its first channel now drives the float "
                        "geometry_opacity (exact for a grey map)", "geometry_opacity")


def _thin_film_units(step: Step) -> None:
    source_unit = step.source["thin_film_thickness"].unit
    target_unit = step.target["thin_film_thickness"].unit
    if not step.authored("thin_film_thickness"):
        return
    thickness = step.constant("thin_film_thickness")
    if thickness is None:
        step.report(NOT_CARRIED, "a textured or mistyped thin_film_thickness in nanometres needs a baked texture "
                    "in micrometres; the connection was kept unscaled", "thin_film_thickness")
        return
    if source_unit == "nanometer" and target_unit == "micrometer":
        step.set("thin_film_thickness", float(thickness) / 1000.0)
        step.report(CONVERTED, f"thin_film_thickness {thickness:g} nm -> {thickness / 1000:g} µm", "thin_film_thickness")
    if thickness > 0 and "thin_film_weight" in step.target and not step.authored("thin_film_weight"):
        step.set("thin_film_weight", 1.0)
        step.report(CONVERTED, "thin_film_weight set to 1: a film thicker than 0 was on in this version",
                    "thin_film_weight")


def _to_1_0(step: Step) -> None:
    scale = step.constant("transmission_dispersion_scale")
    if not step.authored("transmission_dispersion_abbe_number") and (scale is None or scale > 0):
        step.report(APPROXIMATED, "transmission_dispersion_abbe_number was unset: the reference node "
                    f"defaulted to {step.source['transmission_dispersion_abbe_number'].default:g}, the "
                    f"specification and 1.0 to {step.target['transmission_dispersion_abbe_number'].default:g}",
                    "transmission_dispersion_abbe_number")


def _to_1_1(step: Step) -> None:
    weight = step.constant("thin_film_weight")
    old_default = step.source["thin_film_ior"].default
    if not step.authored("thin_film_ior") and (weight is None or weight > 0) and old_default != step.target["thin_film_ior"].default:
        step.set("thin_film_ior", float(old_default))
        step.report(DEFAULT_PINNED, f"thin_film_ior written as {old_default:g}: its default changed to "
                    f"{step.target['thin_film_ior'].default:g}", "thin_film_ior")


def _to_1_1_1(step: Step) -> None:
    metalness, weight, tint = step.constant("base_metalness"), step.constant("specular_weight"), step.constant("specular_color")
    metallic = metalness is None or metalness > 0
    weighted = weight is None or weight != 1.0
    tinted = tint is None or tint != (1.0, 1.0, 1.0)
    if metallic and weighted and tinted:
        step.report(LOOK_CHANGED, "OpenPBR 1.1.1 no longer scales the metal edge tint (specular_color) by "
                    "specular_weight; this metal's edge colour changes and is not compensated", "specular_color")


STEPS = (("0.2", "0.3", _to_0_3), ("0.3", "0.4", _to_0_4), ("0.4", "0.5", _to_0_5),
         ("0.5", "1.0", _to_1_0), ("1.0", "1.1", _to_1_1), ("1.1", "1.1.1", _to_1_1_1))
