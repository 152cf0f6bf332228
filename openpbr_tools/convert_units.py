"""The scene unit of a converted material's lengths (:func:`meters_per_unit`) and the MaterialX distance unit the
written lengths are tagged with (:func:`tag_length_units`), so that a USD writer converts them to its stage's unit."""

from __future__ import annotations

from . import tables
from .model import Asset, Constant, Input, Material
from .resources import load_json
from .translate.common import Values, lobe_off


def meters_per_unit(material: Material, asset: Asset) -> tuple[float, list[str]]:
    """The scene unit of the material's lengths: a MaterialX ``unit`` on a length input, else the
    asset's (USD ``metersPerUnit``; glTF metres), else metres, with the lengths taken so."""
    distance = load_json("units.json")["distance"]
    for name in ("transmission_depth", "subsurface_radius", "attenuation_distance", "thickness"):
        entry = material.inputs.get(name)
        if entry is not None and entry.unit in distance:
            return distance[entry.unit], []
    if asset.meters_per_unit:
        return asset.meters_per_unit, []
    if asset.format == "gltf":
        return 1.0, []
    if asset.format == "usd":
        return load_json("units.json")["usd_default_meters_per_unit"], []
    table = tables.table_known(material.model, material.version)
    values = Values(material, table)  # (a length of a lobe switched off renders nothing: no unit to assume)
    return 1.0, [n for n in ("transmission_depth", "subsurface_radius") if n in material.inputs
                 and not lobe_off(n, values, table)]


def tag_length_units(pairs: list[tuple[Material, Material]], asset: Asset, defaults: bool = False) -> None:
    """Each written material's lengths without a unit get the MaterialX distance unit the conversion took them
    in (:func:`meters_per_unit` of its source: glTF's metres, USD's ``metersPerUnit``, a MaterialX length's
    own unit, else metres), so the written document says what its numbers mean and a USD writer converts
    them to its stage's unit. With ``defaults`` (a USD output, whose stage has a unit of its own), a length left
    at a default other than 0 on a lobe that is on is written too, in that unit: unwritten, it would read as the
    default in the stage's unit (OpenPBR's subsurface_radius 1 became 1 cm where an authored 1 became 100: the
    red team's I/F3)."""
    distance = load_json("units.json")["distance"]
    for source, material in pairs:
        scale, _ = meters_per_unit(source, asset)
        names = [name for name, factor in distance.items() if abs(factor - scale) <= 1e-12 * max(1, scale)]
        table = tables.table(material.model)
        for name, entry in material.inputs.items():
            parameter = table.get(name)
            if names and parameter is not None and parameter.unit == "scene_length" and not entry.unit:
                entry.unit, entry.unittype = names[0], "distance"
        if not (defaults and names) or material.model not in ("open_pbr_surface", "standard_surface"):
            continue
        values = Values(material, table)
        for name, parameter in table.parameters.items():
            if parameter.unit == "scene_length" and name not in material.inputs and parameter.type == "float" and \
                    parameter.default not in (None, 0.0) and not lobe_off(name, values, table):
                material.inputs[name] = Input(name, parameter.type, Constant(float(parameter.default)),
                                              material.location.with_input(name), unit=names[0], unittype="distance")
