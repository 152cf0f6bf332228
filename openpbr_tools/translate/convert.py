"""Conversion between any two of the four shading models, through OpenPBR.

A legacy OpenPBR material is upgraded first; a non-OpenPBR source is translated to OpenPBR and then,
if the target is not OpenPBR, on to the target. The loss reports of every step are concatenated.
"""

from __future__ import annotations

import copy
import dataclasses

from .. import tables
from ..diagnostics import Diagnostic, Severity
from ..model import Material
from ..rules.translation import CONVERTED, NOT_CARRIED
from . import spec_gloss
from .common import Settings, Translation, Values, _off_default, located_input, unread_notes, with_folded_notes
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
        return _through_openpbr(material, settings, dataclasses.replace(settings, gltf_drafts=True))
    if material.model == target == "gltf_pbr" and settings.gltf_file and (restored := unlit_restored(material)):
        return Translation(restored, [settings.context.diagnostic(
            CONVERTED, f"{material.name}: the unlit reading (emission over a black base) is KHR_materials_unlit again",
            material.location)], material)
    if material.model == target == "gltf_pbr" and spec_gloss.state_of(material) is not None and \
            (not settings.gltf_file or spec_gloss.textured(material)):
        # MaterialX's gltf_pbr has no specular-glossiness mode, and a glTF output cannot copy an extension that
        # references the source's textures: the extension read as OpenPBR, as metal-rough (textures per texel)
        return _through_openpbr(material, settings)
    if material.model == target == "gltf_pbr" and unlit_state(state) and not settings.gltf_file:
        # MaterialX's gltf_pbr has no unlit mode: the unlit reading (emission over a black base) renders as one
        return _through_openpbr(material, settings)
    if current.model == "open_pbr_surface":
        if current.version and current.version != tables.latest("open_pbr_surface"):
            upgraded = upgrade(current, context=settings.context)
            diagnostics += upgraded.diagnostics
            current = upgraded.material
    first, about = None, {}  # about: a one-step translation's (what each of its notes concerns)
    own: frozenset[int] = frozenset()  # (Translation.mapping_only)
    if current.model not in ("open_pbr_surface", target):
        first = step = _step(TO_OPENPBR[current.model], current, settings)
        diagnostics += step.diagnostics
        own |= step.mapping_only
        current = step.material
    if current.model != target:
        step = _step(FROM_OPENPBR[target], current, settings if first is None else
                     dataclasses.replace(settings, hub_sites=hub_sites(material, first)))
        if first is None:
            diagnostics += step.diagnostics
            own |= step.mapping_only
        else:
            moved, moved_own = _relocated(step.diagnostics, material, first, settings.context, step.about,
                                          step.mapping_only)
            diagnostics += moved
            own |= moved_own
        about = step.about if first is None else {}
        current = step.material
    if current is material:  # nothing to translate: a copy, so that what happens to the result (textures
        current = copy.copy(material)  # rebased beside the output, say) never reaches the source
        current.inputs = dict(material.inputs)
        current.extra = {k: dict(v) if isinstance(v, dict) else v for k, v in material.extra.items()}  # written into
        diagnostics += _without_unknown_inputs(current, settings)
    return Translation(current, diagnostics, material, origins=first.origins if first is not None else {},
                       about=about, mapping_only=own)


def judged_as(material: Material, target: str, settings: Settings | None = None) -> Material:
    """The material a conversion of ``material`` to ``target`` is judged against (the candidate search, --verify):
    itself, but for a glTF material with draft extensions (KHR_materials_fuzz, _coat...) to another model, its OpenPBR
    reading, where the drafts' values live and glTF's shading model does not render them (the red team's I/F4: a fuzz
    judged absent, the appearance fit turned a grey cloth's base blue, and --verify said 4.59 where MaterialX's GLSL
    measures 1.07)."""
    if material.model != "gltf_pbr" or target == "gltf_pbr" or not material.gltf_state().get("drafts"):
        return material
    settings = settings or Settings()
    return convert(material, "open_pbr_surface", dataclasses.replace(settings, candidates=False, search=False)).material


def _through_openpbr(material: Material, settings: Settings, back: Settings | None = None) -> Translation:
    """A glTF material to OpenPBR and back to glTF (``back``: the second step's settings), both steps' notes."""
    step = _step(gltf_to_openpbr, material, settings)
    again = _step(openpbr_to_gltf, step.material, back or settings)
    return Translation(again.material, step.diagnostics + again.diagnostics, material,
                       mapping_only=step.mapping_only | again.mapping_only)


def at_source_inputs(notes: list, source: Material, first: Translation, context, about: dict | None = None) -> list:
    """The second step's notes of a conversion through the OpenPBR hub, at the source's inputs (the audit's F2: they
    stood at OpenPBR names the source does not have, such as a Standard Surface's ``fuzz_roughness``). A note at a hub
    input made from an authored source input already stands there (its entry keeps the source's location); one at a
    hub input the first step made from the source's defaults goes to the first authored source input its mapping
    read, else to the material; an info there is dropped (it concerns no value the source holds). ``about``: for each
    note (by id), the hub input it concerns, where the second step recorded it (:attr:`.common.Translation.about`)."""
    return _relocated(notes, source, first, context, about)[0]


def _relocated(notes: list, source: Material, first: Translation, context, about: dict | None = None,
               own: frozenset[int] = frozenset()) -> tuple[list, frozenset[int]]:
    """:func:`at_source_inputs`, with the ids of those notes that only describe the mapping's result (``own``, the
    second step's: :attr:`.common.Translation.mapping_only`) among them, and of the companions it adds."""
    authored = _authored(source)
    about = about or {}
    kept, concerns, moved = [], {}, set()  # concerns: id(kept note) -> the hub input it is about
    for note in notes:
        name = note.location.input
        if name is None or name in authored:
            kept.append(note)
            if id(note) in about:
                concerns[id(note)] = about[id(note)]
        elif (origin := _origin(name, source, first)) is not None:
            entry = source.inputs[origin]
            kept.append(dataclasses.replace(note, location=entry.location or source.location.with_input(origin)))
            concerns[id(kept[-1])] = about.get(id(note), name)
        elif note.severity > Severity.INFO:
            kept.append(dataclasses.replace(note, location=dataclasses.replace(note.location, input=None)))
        else:
            continue
        if id(note) in own:
            moved.add(id(kept[-1]))
    companions = _hub_companions(kept, source, first, context, concerns)
    return kept + companions, frozenset(moved | {id(note) for note in companions})


def _authored(source: Material) -> set[str]:
    """The names the notes at ``source``'s authored inputs stand at: the inputs', and their locations' (a glTF
    property)."""
    return {entry.location.input for entry in source.inputs.values() if entry.location is not None} | set(source.inputs)


def _origin(name: str, source: Material, first: Translation) -> str | None:
    """The first authored source input the first step's mapping to hub input ``name`` read."""
    return next((s for s in first.origins.get(name, ()) if s in source.inputs), None)


def hub_sites(source: Material, first: Translation) -> dict[str, str]:
    """For each OpenPBR input the source does not hold, where :func:`at_source_inputs` shows a note at it: the
    source input that fed it (as its location names it), else the material. The second step names these in a note
    that points at another (the review's tenth: "see the note at specular_ior", a warning moved to
    ``useSpecularWorkflow``)."""
    if source.model == "open_pbr_surface":
        return {}  # (no hub: the notes stand where they are)
    authored = _authored(source)
    sites = {}
    for name in tables.table("open_pbr_surface").parameters:
        if name in authored:
            continue
        origin = _origin(name, source, first)
        sites[name] = located_input(source.inputs[origin], origin) if origin is not None else "the material"
    return sites


def _hub_companions(notes: list, source: Material, first: Translation, context, concerns: dict) -> list:
    """A note at each authored source input (off its default) that the first step folded into a hub input the second
    step reported, where nothing stands at that source input yet (the audit's F2: a Standard Surface's
    ``subsurface_scale``, folded into OpenPBR's ``subsurface_radius_scale``, vanished on its way to glTF while the note
    stood at ``subsurface_radius``, the hub input's first source). A note is paired with the hub input it concerns
    (``concerns``, from :attr:`.common.Translation.about`), never with another standing at the same site; the
    companion is an info pointing at it, which carries the loss's severity."""
    table = tables.table_known(source.model, source.version)
    values = Values(source, table)
    sites = {d.location.input for d in notes} | {d.location.input for d in first.diagnostics}
    strongest: dict[str, Diagnostic] = {}  # hub input -> its most severe note (paired by what the note concerns,
    for note in notes:                     # not by where it stands: the review's first)
        hub = concerns.get(id(note))
        held = strongest.get(hub) if hub is not None else None
        if hub is not None and (held is None or note.severity > held.severity):
            strongest[hub] = note
    companions = []
    for name in first.material.inputs:
        note = strongest.get(name)
        if note is None:
            continue
        site = note.location.input
        for origin in first.origins.get(name, ()):
            feeding = source.inputs.get(origin)
            where = feeding.location if feeding is not None and feeding.location is not None else None
            if feeding is None or where is None or where.input in sites or table.get(origin) is None \
                    or not _off_default(origin, values, table):
                continue
            sites.add(where.input)
            companions.append(context.diagnostic(CONVERTED, (
                f"{source.name}: {origin}: folded into OpenPBR's {name} with the other inputs, which the next step "
                f"does not carry exactly (see the note at {site})"), where))
    return companions


def _step(translator, material: Material, settings: Settings) -> Translation:
    """One translator's result, with a note at each input its mappings folded into another (common.with_folded_notes)
    and at each authored input it did not read at all (common.unread_notes)."""
    translation = with_folded_notes(translator(material, settings))
    unread = unread_notes(translation, translation.material.model, settings.context, settings.unseen_notes)
    if unread:
        translation.diagnostics = sorted(translation.diagnostics + unread, key=Diagnostic.sort_key)
    return translation


def _unknown_names(material: Material) -> list[str]:
    """The inputs of ``material`` its model (at its version, where that is known) does not define."""
    table = tables.table_known(material.model, material.version)
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
