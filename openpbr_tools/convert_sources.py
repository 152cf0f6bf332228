"""Notes a conversion makes of the source as a whole, before any material is mapped: what the reader observed
that no output holds (a USD input's animation, its values in variants that are not selected, texture coordinates
from a network no output carries, a shader of a model the toolkit does not convert)."""

from __future__ import annotations

from .diagnostics import Diagnostic
from .model import Asset, Material
from .rules.translation import APPROXIMATED, NOT_CARRIED


def display_name(material: Material) -> str:
    """The name a note gives a material: its material's, else its shader's."""
    return material.material_name or material.name


def source_notes(asset: Asset, context) -> list[Diagnostic]:
    """The notes the module docstring lists, in the order the reader observed them."""
    notes: list[Diagnostic] = []
    for observation in asset.observations:
        if observation.kind in ("usd_time_samples", "usd_graph_time_samples") and (
                observation.detail.get("samples") or observation.detail.get("attributes")):
            what = observation.detail.get("what") or observation.detail.get("input") or \
                "the graph on " + (observation.location.input or "an input")
            notes.append(context.diagnostic(  # (the red team's G-F5: an animation vanished unannounced)
                APPROXIMATED, f"{what} is animated (time samples); the output holds one value, its value at the "
                              "default time, else its first sample", _at_material(observation, asset)))
        if observation.kind == "usd_other_values":  # (the red team's E#8: a variant's values vanished unannounced)
            detail = observation.detail
            variants = ", ".join(sorted({str(w).removeprefix("in variant ").removesuffix(" (not selected)")
                                         for w, _ in detail.get("values", ()) if str(w).startswith("in variant")}))
            notes.append(context.diagnostic(
                NOT_CARRIED, f"{detail.get('input')} takes other values in variants that are not selected ({variants}): "
                             "only the selected variant is converted; select another (usdview, or the layer's "
                             "variant selection) to convert it", _at_material(observation, asset)))
        if observation.kind == "texture_coordinates_dropped":  # (the review's second)
            notes.append(context.diagnostic(
                NOT_CARRIED, f"the coordinates of {observation.detail.get('node')} come from a network that neither a "
                             "texture's UV transform nor a kept graph holds (a packaged image is not kept in a graph): "
                             "the image is carried with the placement read up to it", observation.location))
        if observation.kind == "unsupported_shader":  # a custom or renderer-specific shader: never silent
            detail = observation.detail
            notes.append(context.diagnostic(
                NOT_CARRIED, f"{detail.get('material')}: its {detail.get('category')} shader is none of the shading "
                             "models the toolkit converts; the material is not written", observation.location))
    return notes


def _at_material(observation, asset: Asset):
    """The observation's location, naming the material read at its prim where there is one."""
    owner = next((m for m in asset.materials if m.location.path == observation.location.path), None)
    return observation.location if owner is None else observation.location.with_material(display_name(owner))
