"""Inputs that glTF's and UsdPreviewSurface's models share and OpenPBR lacks, carried past the OpenPBR hub.

Every conversion goes through OpenPBR (:mod:`.convert`), which has no ambient occlusion, so a glTF material's
``occlusionTexture`` was lost on its way to a UsdPreviewSurface, and the reverse, although both ends hold it:

* glTF 2.0, 3.9.4 (``occlusionTexture``): "areas that receive less indirect lighting", read from the red
  channel, ``1.0 + strength * (sampled - 1.0)``; MaterialX's ``gltf_pbr`` has it as the float input
  ``occlusion``, default 1.
* UsdPreviewSurface (2.5, ``occlusion``): "extracted from ambient occlusion map; 1 means no occlusion, 0 means
  full occlusion", float, default 1; MaterialX's ``ND_UsdPreviewSurface_surfaceshader`` the same.

One quantity with one meaning and one default: the source's input reaches a target of either model as it is
(a constant, or its texture with the source's channel, scale and bias, coordinates, transform and wrap, which
both writers carry), and the hub's "no equivalent" note (OPBR1104) is taken back. Where only a USD output's
UsdPreviewSurface fallback holds it (the primary shader is OpenPBR, which renderers reading MaterialX use),
the note says so instead (OPBR1103).
"""

from __future__ import annotations

import copy

from ..diagnostics import Diagnostic
from ..model import Material
from ..rules.translation import APPROXIMATED, NOT_CARRIED

SHARED = ("occlusion",)
HOLDERS = frozenset(("gltf_pbr", "UsdPreviewSurface"))


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
