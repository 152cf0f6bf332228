"""Inputs that glTF's and UsdPreviewSurface's models share and OpenPBR lacks, carried past the OpenPBR hub.

Every conversion goes through OpenPBR (:mod:`.convert`), which has no ambient occlusion, so a glTF material's
``occlusionTexture`` was lost on its way to a UsdPreviewSurface, and the reverse, although both ends hold it:

* glTF 2.0, 3.9.4 (``occlusionTexture``): "areas that receive less indirect lighting", read from the red
  channel, ``1.0 + strength * (sampled - 1.0)``; MaterialX's ``gltf_pbr`` has it as the float input
  ``occlusion``, default 1.
* UsdPreviewSurface (2.5, ``occlusion``): "extracted from ambient occlusion map; 1 means no occlusion, 0 means
  full occlusion", float, default 1; MaterialX's ``ND_UsdPreviewSurface_surfaceshader`` the same.

**Base roughness under a coat** (the red team's H-02). OpenPBR's coat roughens the base beneath it; Standard
Surface's, glTF's and UsdPreviewSurface's clear coats do not (each target's MaterialX graph, and the glTF and
preview specifications). A textured base roughness under a coat therefore goes to OpenPBR less the roughening, clamped
at 0 (all of it, for a rough coat), and back out with the roughening put back: what the clamp took is lost, and a
brass under a rough coat came out of Standard Surface as a mirror-smooth UsdPreviewSurface. Between two of those
models, with no anisotropy (where all three take alpha = roughness squared), the base roughness texture is the
same quantity and is carried as it is (:func:`carry_roughness`).

One quantity with one meaning and one default: the source's input reaches a target of either model as it is
(a constant, or its texture with the source's channel, scale and bias, coordinates, transform and wrap, which
both writers carry), and the hub's "no equivalent" note (OPBR1104) is taken back. Where only a USD output's
UsdPreviewSurface fallback holds it (the primary shader is OpenPBR, which renderers reading MaterialX use),
the note says so instead (OPBR1103).
"""

from __future__ import annotations

import copy
import dataclasses

from .. import tables
from ..diagnostics import Diagnostic
from ..model import Connection, Material, Texture
from ..rules.translation import APPROXIMATED, CONVERTED, NOT_CARRIED
from .common import Translation, Values

SHARED = ("occlusion",)
#: sources whose own notes are a USD output's fallback's: an OpenPBR one (the fallback is its only translation), and a
#: UsdPreviewSurface one (the fallback is the source itself)
OWN_FALLBACK = ("open_pbr_surface", "UsdPreviewSurface")
HOLDERS = frozenset(("gltf_pbr", "UsdPreviewSurface"))


def past_the_hub(source: Material, result: Material, fallback: Material | None, notes: list[Diagnostic],
                 context) -> list[Diagnostic]:
    """What a conversion through OpenPBR loses and ``result`` (and a USD output's UsdPreviewSurface ``fallback``)
    can hold, put back from ``source``: the :data:`SHARED` inputs and a textured base roughness under a coat;
    returns ``notes`` settled to say so."""
    carried = carry(source, result)
    fallback_only = carry(source, fallback) if fallback is not None else ()
    notes = settle_notes(notes, source, carried, fallback_only, context)
    for target in (result, fallback) if fallback is not None else (result,):
        notes = carry_roughness(source, target, notes, context)
    return notes


def carry(source: Material, result: Material) -> tuple[str, ...]:
    """Copies ``source``'s :data:`SHARED` inputs onto ``result`` where both models hold them (and the
    result has none of its own); returns the names carried."""
    if source.model not in HOLDERS or result.model not in HOLDERS or source.model == result.model:
        return ()
    carried = []
    for name in SHARED:
        entry = source.inputs.get(name)
        if entry is None or name in result.inputs:
            continue
        result.inputs[name] = copy.copy(entry)  # the writers rebase a copy; the source's entry is never changed
        carried.append(name)
    return tuple(carried)


def _is_hub_note(note: Diagnostic, source: Material, names) -> bool:
    return note.code == NOT_CARRIED.code and any(
        source.inputs.get(name) is not None and note.location == source.inputs[name].location for name in names)


def settle_notes(notes: list[Diagnostic], source: Material, carried: tuple[str, ...], fallback_only: tuple[str, ...],
                 context) -> list[Diagnostic]:
    """``notes`` without the hub's OPBR1104 at an input the result holds (``carried``); at one only a
    UsdPreviewSurface fallback holds (``fallback_only``), an OPBR1103 that says so instead."""
    kept = [note for note in notes if not _is_hub_note(note, source, carried + fallback_only)]
    for name in fallback_only:
        if name in carried:
            continue
        kept.append(context.diagnostic(
            APPROXIMATED, f"{source.name}: {name} is written on the UsdPreviewSurface fallback only: the OpenPBR "
                          "shader, which renderers reading MaterialX use, has no ambient occlusion input",
            source.inputs[name].location))
    return kept


#: per model: (its base roughness, its anisotropy, its coat weight), for models whose coat does not roughen the base
ROUGHNESS = {"standard_surface": ("specular_roughness", "specular_anisotropy", "coat"),
             "gltf_pbr": ("roughness", "anisotropy_strength", "clearcoat"),
             "UsdPreviewSurface": ("roughness", None, "clearcoat")}


def _zero_or_absent(material: Material, name: str | None) -> bool:
    entry = material.inputs.get(name) if name else None
    value = getattr(entry.value, "value", None) if entry is not None else 0.0
    return entry is None or (isinstance(value, (int, float)) and value == 0)


def carry_roughness(source: Material, result: Material, notes: list[Diagnostic], context) -> list[Diagnostic]:
    """A textured base roughness under a coat carried as it is between two models whose coats do not roughen the
    base (:data:`ROUGHNESS`), instead of through OpenPBR's unroughened, clamped one; returns ``notes`` with the
    roughness notes of the trip through OpenPBR replaced by one that says so."""
    if source.model == result.model or source.model not in ROUGHNESS or result.model not in ROUGHNESS:
        return notes
    name, anisotropy, coat = ROUGHNESS[source.model]
    target, target_anisotropy, _ = ROUGHNESS[result.model]
    entry = source.inputs.get(name)
    if entry is None or not isinstance(entry.value, Texture) or _zero_or_absent(source, coat) \
            or not _zero_or_absent(source, anisotropy) or not _zero_or_absent(result, target_anisotropy):
        return notes
    result.inputs[target] = copy.copy(entry)
    result.inputs[target].name = target
    kept = [note for note in notes if note.location != entry.location]
    kept.append(context.diagnostic(
        CONVERTED, f"{source.name}: {name} carried as it is to {result.model}'s {target}: neither model's coat roughens "
                   "the base (OpenPBR's does: through it, the roughness would be unroughened and clamped)", entry.location))
    return kept


def fallback_only(note: Diagnostic, context, source: Material) -> Diagnostic:
    """A USD output's UsdPreviewSurface fallback losing or approximating a value the file's MaterialX shader holds (the
    audit's F4: reported as an error at the source's input, as if the output had lost it): a warning that says which
    shader lost it. The MaterialX shader's own losses are reported by its translation."""
    if note.code not in (NOT_CARRIED.code, APPROXIMATED.code):
        return note
    entry = source.inputs.get(note.location.input or "")
    if entry is not None and (entry.value is None or not _fits(source, entry.name) or (
            isinstance(entry.value, Connection) and (entry.value.dangling or not entry.value.graph_xml))):
        return note  # a value the source cannot give (unreadable, of another shape, a connection to nothing the
        # writers rebuild): the MaterialX shader does not hold it either
    return dataclasses.replace(context.diagnostic(
        APPROXIMATED, f"{note.message} (in the UsdPreviewSurface fallback only: the output's MaterialX shader, which "
                      "renderers reading MaterialX use, holds it)", note.location), hint=note.hint)


def _fits(material: Material, name: str) -> bool:
    """Whether ``material``'s input ``name`` holds a value of its type's shape (an unknown input: yes)."""
    table = tables.table_known(material.model, material.version)
    return table.get(name) is None or Values(material, table).fits(name)


def fallback_jobs(done: list) -> list:
    """For each converted material of a USD output (``done``: the pipeline's (source, notes before, (notes, settings,
    translated OpenPBR, origins) or None)), the candidate search's job for its UsdPreviewSurface fallback: the OpenPBR
    translation translated on, whose notes stand at the source's inputs (:func:`.convert.hub_sites`); for a
    UsdPreviewSurface source the source itself, exactly (the red team's P: OpenUSD's nativeClearcoat, a preview written
    to .usda, came back with a roughness of 0.01 for 0.5, through OpenPBR and MaterialX's graphs)."""
    from .convert import convert, hub_sites  # lazy: translate.convert imports the translators this module serves

    jobs = []
    for material, _, state in done:
        if state is None:
            continue
        settings = dataclasses.replace(state[1], unseen_notes=False, hub_sites=hub_sites(
            material, Translation(state[2], [], material, origins=state[3])))
        source = material if material.model == "UsdPreviewSurface" else state[2]
        jobs.append((source, convert(source, "UsdPreviewSurface", settings), "UsdPreviewSurface", state[1]))
    return jobs
