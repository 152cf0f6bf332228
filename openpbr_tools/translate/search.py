"""Parameter search (``--verify``): where a constant material's kept result (the mapping's or MaterialX's
graphs', after the appearance fit) still renders more than :data:`FROM` mean CIEDE2000 off on the evaluator's
sphere, the target's own colours and [0, 1] weights and roughnesses (:data:`FREE`) are searched for a closer
render, and the result kept only when it wins by more than the candidate search's margin.

Why: the mapping carries each source parameter to its nearest equivalent, but where the target cannot hold a
feature (an OpenPBR metal dimmed by ``specular_weight``, which Standard Surface's and glTF's conductors
reach 1 at grazing regardless; a fuzz over a glass; an F82 tint out of the artistic IOR's reach) another
combination of the target's parameters can look closer: less metalness and more of a dark dielectric, a
rougher lobe for a dimmed rim. On 600 generated materials of the kinds artists author
(tests/benchmarks/bench_fidelity_oracle.py, a Nelder-Mead oracle over the same parameters), such a
combination brings 26 of the 47 Standard Surface and 33 of the 82 glTF conversions still above 2.3 under it.
Judged by MaterialX's GLSL renderer instead (bench_glsl_sample.py --verify, 82 materials), the searched
Standard Surface results went from 10.20 to 6.08 mean CIEDE2000 (5 better by more than 0.5, 1 worse by 0.62)
and the glTF ones from 6.79 to 5.74 (8 better, 1 worse by 1.21).

The search is a compass search (Torczon, "On the convergence of pattern search algorithms", SIAM J. Optim.
1997): from the kept result, each free parameter is moved up and down by a step, all of those candidates
rendered in one stacked evaluation (:func:`~.judging.Judge.scores`), the best taken when it improves, the step
halved when none does; at most :data:`ITERATIONS` rounds from a step of :data:`STEP` down to
:data:`MIN_STEP`. Colours move per component, in the colour space the output holds them (a glTF file's
linear Rec.709, clamped to [0, 1] as written). It runs only with ``--verify`` (``Settings.search``): a few
hundred milliseconds per material it searches, which the default conversion's budget does not have. Not where
the evaluator is an untrusted judge (:func:`.appearance.untrusted`). Every changed input gets a note
(OPBR1103) with its old and new value and both figures.
"""

from __future__ import annotations

import copy

import numpy as np

from .. import tables
from ..model import Constant, Input, Material
from ..rules.translation import APPROXIMATED
from .appearance import shown, untrusted
from .common import Settings, Translation
from .judging import RIG_SIZE, Judge, constant_values

FROM = 2.3  # mean CIEDE2000 above which the kept result is searched (just noticeable)
MARGIN = 0.25  # as the candidate search's: a smaller win does not pay for moving the values
STEP = 0.2
MIN_STEP = 0.02
ITERATIONS = 10
GOOD_ENOUGH = 0.5  # the search ends once the result renders this close

#: Per target model: (colour inputs, [0, 1] float inputs) the search may move. Not IORs, thicknesses,
#: lengths or flags: those carry the source's physics one to one, and the weights and colours are where the
#: targets' lobes differ. Not UsdPreviewSurface: judged by MaterialX's GLSL on 82 generated materials
#: (tests/benchmarks/bench_glsl_sample.py --corpus archetypes --verify) its searched results were no closer
#: (mean 6.22 -> 6.13, three worse by more than 0.5, up to 2.95), where Standard Surface's (10.20 -> 6.08) and
#: glTF's (6.79 -> 5.74) were.
FREE = {
    "standard_surface": (("base_color", "specular_color", "coat_color"),
                         ("base", "metalness", "specular", "specular_roughness", "coat", "coat_roughness")),
    "gltf_pbr": (("base_color", "specular_color"),
                 ("metallic", "roughness", "specular", "clearcoat", "clearcoat_roughness")),
    "open_pbr_surface": (("base_color", "specular_color"),
                         ("base_weight", "base_metalness", "specular_weight", "specular_roughness")),
}


def _vector(material: Material) -> tuple[np.ndarray, list[tuple[str, int | None]]]:
    """The free values of ``material`` (absent inputs at their defaults) and, per position, (input, component)."""
    colours, floats = FREE[material.model]
    table = tables.table(material.model, material.version) if material.version else tables.table(material.model)
    values, layout = [], []
    for name in colours + floats:
        if name not in table:
            continue
        entry = material.inputs.get(name)
        value = entry.value.value if entry is not None and isinstance(entry.value, Constant) else table[name].default
        if name in colours:
            values += [float(v) for v in value]
            layout += [(name, i) for i in range(3)]
        else:
            values.append(float(value))
            layout.append((name, None))
    return np.clip(np.array(values), 0.0, 1.0), layout


def _material(material: Material, x: np.ndarray, layout) -> Material:
    changed = copy.copy(material)
    changed.inputs = dict(material.inputs)
    grouped: dict[str, list] = {}
    for value, (name, component) in zip(x, layout):
        grouped.setdefault(name, []).append(float(value))
    for name, values in grouped.items():
        old = material.inputs.get(name)
        value = tuple(values) if len(values) == 3 else values[0]
        kind = old.type if old is not None else ("color3" if len(values) == 3 else "float")
        changed.inputs[name] = Input(name, kind, Constant(value), old.location if old is not None else material.location)
    return changed


def search(source: Material, translation: Translation, judge: Judge, start: float, settings: Settings) -> Translation:
    """``translation`` with its free parameters searched (module docstring) when it renders ``start`` (its
    figure on ``judge``) above :data:`FROM` and the search wins by more than :data:`MARGIN`; else as it is."""
    material = translation.material
    if start <= FROM or material.model not in FREE or constant_values(material) is None or untrusted(source):
        return translation
    try:
        x, layout = _vector(material)
        best = start
        step = STEP
        for _ in range(ITERATIONS):
            if step < MIN_STEP or best < GOOD_ENOUGH:
                break
            trials = []
            for i in range(len(x)):
                for sign in (1.0, -1.0):
                    moved = x.copy()
                    moved[i] = np.clip(moved[i] + sign * step, 0.0, 1.0)
                    if moved[i] != x[i]:
                        trials.append(moved)
            scores = judge.scores([_material(material, t, layout) for t in trials]) if trials else []
            found = int(np.argmin(scores)) if scores else -1
            if found >= 0 and scores[found] < best - 1e-3:
                x, best = trials[found], float(scores[found])
            else:
                step *= 0.5
    except (ValueError, KeyError, TypeError, IndexError, FloatingPointError):
        return translation
    if not best < start - MARGIN:
        return translation
    searched = _material(material, x, layout)
    notes = list(translation.diagnostics)
    for name in dict.fromkeys(name for name, _ in layout):
        old, new = material.inputs.get(name), searched.inputs[name]
        before = old.value.value if old is not None and isinstance(old.value, Constant) else None
        after = new.value.value
        if before is not None and np.allclose(np.asarray(before, float), np.asarray(after, float), atol=1e-6):
            searched.inputs[name] = old
            continue
        where = next((d.location for d in translation.diagnostics if d.location.input), source.location)
        notes.append(settings.context.diagnostic(
            APPROXIMATED, f"{source.name}: {material.model} {name} searched"
                          + (f" from {shown(before)}" if before is not None else "") + f" to {shown(after)}, so that "
                          f"the lit sphere looks like the source's (what the target cannot hold): mean CIEDE2000 on the "
                          f"evaluator's {RIG_SIZE}-pixel sphere {start:.2f} -> {best:.2f}", where))
    translation.material.inputs = searched.inputs
    return Translation(translation.material, notes, translation.source)
