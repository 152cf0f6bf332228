"""A graphs' result that wins the candidate search keeps the mapping's roughnesses and anisotropies
(:data:`.judging.SHARPNESS`): the lit sphere the candidates are judged on has uniform surroundings, so it cannot see how
sharply a lobe reflects or refracts, and MaterialX's open_pbr_to_standard_surface gives a coated base its coat's
roughness (``specRoughness = mix(specular_roughness, coat_roughness, coat_weight)``). Judged by MaterialX's GLSL under a
structured environment (tests/benchmarks/bench_glsl_environment.py): the OpenPBR Shader Playground's bubbles, a frosted
transmission the graphs made clear, 6.63 -> 2.79 mean CIEDE2000 (the mapping alone 3.14)."""

from __future__ import annotations

import copy

import numpy as np

from .. import tables
from ..model import Constant, Material
from ..rules.translation import APPROXIMATED
from . import appearance
from .common import Settings, Translation
from .judging import RIG_SIZE, SHARPNESS


def mapping_sharpness(candidate: Material | None, mapped: Material) -> tuple[Material, dict] | None:
    """The graphs' ``candidate`` with the mapping's constants at every input that sets a lobe's sharpness
    (:data:`.judging.SHARPNESS`: roughnesses, anisotropies), and the graphs' values it replaced; None when there
    is no candidate or they already agree (1e-6). The lit sphere the candidates are judged on cannot see those
    inputs (its environment is uniform), so a win of the graphs' result must not come with a sharper or blurrier
    lobe than the mapping's, which carries the source's roughness by the physics (judging.SHARPNESS: the graphs
    give a coated material's base its coat's roughness)."""
    if candidate is None or candidate.model != mapped.model:
        return None
    changed, inputs = {}, dict(candidate.inputs)
    for name in SHARPNESS.get(candidate.model, ()):
        ours, theirs = mapped.inputs.get(name), candidate.inputs.get(name)
        if any(entry is not None and not isinstance(entry.value, Constant) for entry in (ours, theirs)):
            continue
        default = tables.table(candidate.model)[name].default  # (an input left unset holds its default)
        theirs_value = theirs.value.value if theirs is not None else default
        try:
            if np.allclose(np.asarray(theirs_value, dtype=float),
                           np.asarray(ours.value.value if ours is not None else default, dtype=float), atol=1e-6):
                continue
        except (TypeError, ValueError):
            continue
        changed[name] = theirs_value
        if ours is not None:
            inputs[name] = copy.copy(ours)
        else:
            del inputs[name]
    if not changed:
        return None
    kept = copy.copy(candidate)
    kept.inputs = inputs
    return kept, changed


def sharpness_note(source: Material, translation: Translation, changed: dict, theirs: float, kept: float,
                    settings: Settings):
    where = next((d.location for d in translation.diagnostics if d.code == APPROXIMATED.code), source.location)
    table = tables.table(translation.material.model)

    def now(name):
        entry = translation.material.inputs.get(name)
        return appearance.shown(entry.value.value if entry is not None else table[name].default)

    listed = ", ".join(f"{name} {now(name)} (the graphs' {appearance.shown(value)})" for name, value in changed.items())
    return settings.context.diagnostic(
        APPROXIMATED, f"{source.name}: the translation graphs' result keeps the toolkit's mapping's {listed}: the "
                      f"evaluator's lit sphere, whose surroundings are uniform, does not show how sharply a lobe "
                      f"reflects or refracts (mean CIEDE2000 on its {RIG_SIZE}-pixel sphere: the graphs' values "
                      f"{theirs:.2f}, with the mapping's {kept:.2f})", where)
