"""Conversion between any two of the four shading models, through OpenPBR.

A legacy OpenPBR material is upgraded first; a non-OpenPBR source is translated to OpenPBR and then,
if the target is not OpenPBR, on to the target. The loss reports of every step are concatenated.
"""

from __future__ import annotations

import copy
import dataclasses

from .. import tables
from ..model import Material
from ..rules.translation import CONVERTED, NOT_CARRIED
from . import spec_gloss
from .common import Settings, Translation, with_folded_notes
from .gltf import gltf_to_openpbr, openpbr_to_gltf, unlit_restored, unlit_state
from .standard_surface import openpbr_to_standard_surface, standard_surface_to_openpbr
from .upgrade import upgrade
from .usd_preview import openpbr_to_usd_preview, usd_preview_to_openpbr

MODELS = ("open_pbr_surface", "standard_surface", "gltf_pbr", "UsdPreviewSurface")
TO_OPENPBR = {"standard_surface": standard_surface_to_openpbr, "gltf_pbr": gltf_to_openpbr,
              "UsdPreviewSurface": usd_preview_to_openpbr}
FROM_OPENPBR = {"standard_surface": openpbr_to_standard_surface, "gltf_pbr": openpbr_to_gltf,
                "UsdPreviewSurface": openpbr_to_usd_preview}


def convert(material: Material, target: str, settings: Settings | None = None) -> Translation:
    if target not in MODELS:
        raise ValueError(f"unknown shading model {target!r} (known: {', '.join(MODELS)})")
    if material.model not in MODELS:
        raise ValueError(f"cannot convert a {material.model} material")
    settings = settings or Settings()
    diagnostics = []
    current = material
    state = material.gltf_state()
    if material.model == target == "gltf_pbr" and state.get("drafts"):
        # a glTF material with draft extensions goes through OpenPBR (where the drafts' values live) and
        # comes back with them: they reference the source's textures, so they cannot be copied as JSON
        step = _step(gltf_to_openpbr, material, settings)
        back = _step(openpbr_to_gltf, step.material, dataclasses.replace(settings, gltf_drafts=True))
        return Translation(back.material, step.diagnostics + back.diagnostics, material)
    if material.model == target == "gltf_pbr" and settings.gltf_file and (restored := unlit_restored(material)):
        return Translation(restored, [settings.context.diagnostic(
            CONVERTED, f"{material.name}: the unlit reading (emission over a black base) is KHR_materials_unlit again",
            material.location)], material)
    if material.model == target == "gltf_pbr" and spec_gloss.state_of(material) is not None and \
            (not settings.gltf_file or spec_gloss.textured(material)):
        # MaterialX's gltf_pbr has no specular-glossiness mode, and a glTF output cannot copy an extension that
        # references the source's textures: the extension read as OpenPBR, as metal-rough (textures per texel)
        step = _step(gltf_to_openpbr, material, settings)
        back = _step(openpbr_to_gltf, step.material, settings)
        return Translation(back.material, step.diagnostics + back.diagnostics, material)
    if material.model == target == "gltf_pbr" and unlit_state(state) and not settings.gltf_file:
        # MaterialX's gltf_pbr has no unlit mode: the unlit reading (emission over a black base) renders as one
        step = _step(gltf_to_openpbr, material, settings)
        back = _step(openpbr_to_gltf, step.material, settings)
        return Translation(back.material, step.diagnostics + back.diagnostics, material)
    if current.model == "open_pbr_surface":
        if current.version and current.version != tables.latest("open_pbr_surface"):
            upgraded = upgrade(current, context=settings.context)
            diagnostics += upgraded.diagnostics
            current = upgraded.material
    elif current.model != target:
        step = _step(TO_OPENPBR[current.model], current, settings)
        diagnostics += step.diagnostics
        current = step.material
    if current.model != target:
        step = _step(FROM_OPENPBR[target], current, settings)
        diagnostics += step.diagnostics
        current = step.material
    if current is material:  # nothing to translate: a copy, so that what happens to the result (textures
        current = copy.copy(material)  # rebased beside the output, say) never reaches the source
        current.inputs = dict(material.inputs)
        current.extra = {k: dict(v) if isinstance(v, dict) else v for k, v in material.extra.items()}  # written into
        diagnostics += _without_unknown_inputs(current, settings)
    return Translation(current, diagnostics, material)


def _step(translator, material: Material, settings: Settings) -> Translation:
    """One translator's result, with a note at each input its mappings folded into another (common.with_folded_notes)."""
    return with_folded_notes(translator(material, settings))


def _unknown_names(material: Material) -> list[str]:
    """The inputs of ``material`` its model (at its version, where that is known) does not define."""
    table = tables.table(material.model, material.version if material.version in tables.versions(material.model) else None)
    return [name for name in material.inputs if table.get(name) is None]


def unknown_inputs_translated(material: Material, target: str, settings: Settings) -> list:
    """A note at each input the source's model does not define (a typo, OPBR101 on the source) when the
    material goes to another model: no mapping reads it, so it reaches no output (the red team's F6: such
    inputs vanished unannounced). A material carried as is says so in :func:`_without_unknown_inputs`. Kept
    apart from :func:`convert`'s notes, which decide whether a material's candidates are searched."""
    if material.model == target:
        return []
    return [settings.context.diagnostic(
        NOT_CARRIED, f"{material.name}: {name} is no input of {material.model}, so no mapping to {target} reads it; "
        "it is not carried", material.inputs[name].location or material.location.with_input(name))
        for name in _unknown_names(material)]


def _without_unknown_inputs(material: Material, settings: Settings) -> list:
    """Inputs the model does not define (a typo, OPBR101 on the source) are left out of a material carried
    as is, each with a note: written back, MaterialX rejects the whole document ("Node interface error")."""
    notes = []
    for name in _unknown_names(material):
        entry = material.inputs.pop(name)
        notes.append(settings.context.diagnostic(
            NOT_CARRIED, f"{material.name}: {name} is no input of {material.model}, so it is not written",
            entry.location or material.location.with_input(name)))
    return notes
