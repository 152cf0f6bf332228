"""Never worse than the anchor: for an OpenPBR material the toolkit's mapping can only approximate in
the target (and for a Standard Surface material converted to OpenPBR, glTF or UsdPreviewSurface),
MaterialX's own translation graphs (:mod:`.materialx_graphs`) give a second candidate, and the lobe
evaluator keeps the one that renders closer to the source.

On by default (``Settings.candidates``; ``openpbr convert --no-candidates`` turns it off), not with
``--gltf-drafts`` nor for a material that came from glTF (whose point is the mapping's exact
inverses: a glTF round trip stays exact). On 360 generated OpenPBR materials in three document colour
spaces the mapping alone was up to 5.6 mean CIEDE2000 worse than MaterialX's chain; with the search
no material is worse by more than 0.3 (tests/test_never_worse_than_chain.py,
tests/benchmarks/bench_never_worse.py). Only constant-valued materials have a graph candidate; a
value the graphs put outside the target's range is brought inside it, as the toolkit's own results
are (an ``attenuation_distance`` of 0, the graphs' "no attenuation", is left unset) (the graphs are
evaluated on values; a textured material keeps the toolkit's mapping, which bakes per texel). An
exact mapping (no OPBR1103 note) is kept without a search. The candidates are rendered together in
one stacked evaluation on the evaluator's lit sphere at a small size (:data:`RIG_SIZE` pixels, films
on a coarse cosine table: a few milliseconds; ``--verify`` measures the result at full size), CIEDE2000
mean against the source; the graph's result wins only by more than :data:`MARGIN`, since it drops
structure the mapping keeps (a thin-walled flag, a subsurface lobe) for small gains. A graphs' result that wins
keeps the mapping's roughnesses and anisotropies (:func:`mapping_sharpness`, :data:`.judging.SHARPNESS`) where that
costs it no more than :data:`MARGIN` on the sphere, whose uniform surroundings cannot show how sharply a lobe
reflects or refracts (the graphs give a coated base its coat's roughness). The report says
which was kept and both figures (OPBR1102); when the graph's is kept, the mapping's approximation
notes are replaced by one naming the graph and one at every authored input the graph's result does
not carry exactly (:func:`read_back_notes`). ``Settings.fit_films`` (``--verify``) also fits a thin
film's thickness (:func:`refine_thin_film`), which costs a render of 26 thicknesses, and ``Settings.search``
(``--verify``) searches the target's parameters where the kept result still renders visibly off (:mod:`.search`).

Where the toolkit has two readings of a source (a specular-workflow UsdPreviewSurface: split into metal
and dielectric shares, or its F0 colour's luminance with a tint; a full metal's ``specular_weight`` to Standard
Surface: its coat's tint, or folded into its base colour; :func:`alternative_reading`), both are
rendered in the same evaluation and the second kept only when it wins by more than :data:`MARGIN`, reported
with both figures, before the graphs' candidate is weighed.

The search also runs where the mapping only dropped inputs (OPBR1104: a fuzz to UsdPreviewSurface),
and, whichever candidate is kept, the appearance fit (:mod:`.appearance`) adjusts its base colour (a
diffuse roughness, a preview's opacity) where it still renders more than
:data:`.appearance.FIT_FROM` off, kept only when it wins by more than :data:`MARGIN`, with a note at
each adjusted input. On 1,000 generated materials of the kinds artists author
(``tests/benchmarks/bench_fidelity.py --corpus archetypes``) this is what lifts the shares under 2.3
(see the closing notes); the fit is chosen on the evaluator, so ``bench_glsl_sample.py`` also says
whether MaterialX's GLSL agrees.
"""

from __future__ import annotations

import copy
import dataclasses

import numpy as np

from ..model import Connection, Constant, Input, Material
from ..rules.translation import APPROXIMATED, CONVERTED, NOT_CARRIED
from .. import tables
from . import appearance, spec_gloss, ss_metal_weight, ss_rotation
from .anchor import graph_candidates_of, read_back_notes
from .judging import RIG_SIZE, Figure, Judge, constant_values, figures_many, scores_many
from .sharpness import mapping_sharpness, sharpness_note
from .search import search as parameter_search
from .common import Settings, Translation, Values

#: a graphs' result that wins keeps the mapping's roughnesses (:func:`mapping_sharpness`); off only to measure it
#: (tests/benchmarks/bench_glsl_environment.py)
KEEP_MAPPING_SHARPNESS = True
VISIBLE = 2.3  # mean CIEDE2000, just noticeable: a kept result further off is reported as a warning
MARGIN = 0.25  # mean CIEDE2000: a smaller win does not pay for what the graphs drop (thin-walled, subsurface)


#: the thickness parameter of each target's thin film, in nanometres
FILM_THICKNESS = {"gltf_pbr": "iridescence_thickness", "standard_surface": "thin_film_thickness"}
FILM_SCALES = tuple(0.5 * 4.0 ** (i / 24) for i in range(25))  # 0.5x to 2x, geometric steps
FILM_RIG_SIZE = 16


def refine_thin_film(source: Material, translation: Translation, target: str, settings: Settings) -> Translation:
    """A thin film on a metal interferes differently in the targets' models (MaterialX's OpenPBR puts
    it on the dielectric of the metal's F0, its Standard Surface on a conductor of artistic n, k): the
    same thickness can show another colour (measured anodised titanium to Standard Surface: mean
    CIEDE2000 24.6). Where the mapping is approximated, the film's thickness is searched over 0.5-2x
    the mapped one (25 geometric steps, the evaluator's 16-pixel sphere) and the best kept when it wins
    by more than :data:`MARGIN`, reported with both figures."""
    name = FILM_THICKNESS.get(target)
    entry = translation.material.inputs.get(name) if name else None
    film = source.inputs.get("thin_film_weight")
    if entry is None or not isinstance(entry.value, Constant) or film is None or \
            not isinstance(film.value, Constant) or not film.value.value > 0 or constant_values(source) is None:
        return translation
    base = float(entry.value.value)

    def trial(thickness):
        material = copy.copy(translation.material)
        material.inputs = dict(material.inputs)
        material.inputs[name] = Input(name, entry.type, Constant(thickness), entry.location)
        return material

    thicknesses = [base] + [base * scale for scale in FILM_SCALES]
    try:
        scores = score_candidates(source, [trial(t) for t in thicknesses], FILM_RIG_SIZE)
    except (ValueError, KeyError, TypeError, FloatingPointError):
        return translation
    mapped = scores[0]
    found = min(zip(scores[1:], thicknesses[1:]))
    if not found[0] < mapped - MARGIN:
        return translation
    translation.material.inputs[name] = Input(name, entry.type, Constant(float(found[1])), entry.location)
    translation.diagnostics.append(settings.context.diagnostic(
        APPROXIMATED, f"{source.name}: {name} fitted to {found[1]:.1f} nm (the mapped {base:.1f} nm interferes "
                      f"differently in {target}'s film model): mean CIEDE2000 on the evaluator's "
                      f"{FILM_RIG_SIZE}-pixel sphere {mapped:.2f} -> {found[0]:.2f}",
        source.location.with_input("thin_film_thickness")))
    return translation


def score_candidates(source: Material, materials: list[Material], size: int = RIG_SIZE) -> list[float]:
    """Mean CIEDE2000 of each of ``materials`` (one shading model) against ``source`` on the
    evaluator's lit sphere of ``size`` pixels: the candidates are rendered together in one stacked
    evaluation where their switches agree (:func:`~openpbr_tools.evaluate.preview.shade_sphere_many`;
    the same pixels), and their differences computed in one call (:class:`Judge`)."""
    return Judge(source, size).scores(materials)


def choose(source: Material, translation: Translation, target: str, settings: Settings) -> Translation:
    """``translation`` (OpenPBR ``source`` -> ``target``) or MaterialX's graph result, whichever the
    evaluator renders closer to the source, then the appearance fit of the kept one
    (:mod:`.appearance`) where it still differs visibly (module docstring)."""
    return choose_many([(source, translation, target, settings)])[0]


def _searched(source: Material, translation: Translation, target: str, settings: Settings) -> bool:
    # a glTF source (or one that came from glTF) to OpenPBR or glTF: the mapping's exact inverses are the point;
    # not for a specular-glossiness material of constants, which the solve only approximates (spec_gloss.py)
    exact_inverse = settings.gltf_drafts or (isinstance(source.extra.get("gltf"), dict) and
                                             target in ("open_pbr_surface", "gltf_pbr") and
                                             not spec_gloss.constant(source))
    return settings.candidates and not exact_inverse and constant_values(source) is not None and \
        not tangent_graph(translation.material) and \
        any(d.code in (APPROXIMATED.code, NOT_CARRIED.code) for d in translation.diagnostics)


def tangent_graph(material: Material) -> bool:
    """Whether ``material`` takes its tangent from a node graph (a Standard Surface rotation written exactly as a
    rotated tangent: ss_rotation), which the evaluator does not render: the mapping would be judged unrotated, and a
    candidate without the rotation, searched besides, would win (the red team's E#5: roughness 0.4 -> 0.15, metalness
    and base weight moved, the rotation lost, GLSL 8.79 against 0.17 for the rotated tangent)."""
    from ..evaluate.parameters import TANGENT_ANISOTROPY  # lazy: as Judge imports the evaluator

    for name, entry in material.inputs.items():
        if name in ("geometry_tangent", "geometry_coat_tangent") and isinstance(entry.value, Connection):
            turned = material.inputs.get(TANGENT_ANISOTROPY[name][0])
            value = turned.value.value if turned is not None and isinstance(turned.value, Constant) else None
            if turned is not None and (value is None or np.any(np.asarray(value, dtype=float) > 0)):
                return True  # (an anisotropy it turns, textured or above 0)
    return False


def choose_many(items: list[tuple[Material, Translation, str, Settings]]) -> list[Translation]:
    """:func:`choose` for each (source, translation, target, settings) of ``items``, the sources'
    references and the candidates rendered together (:func:`render_many`, :func:`scores_many`): the
    same choices as one by one, for a fraction of the cost (a file's materials are weighed at once)."""
    out = [translation for _, translation, _, _ in items]
    searched = []
    for index, (source, translation, target, settings) in enumerate(items):
        if not _searched(source, translation, target, settings):
            continue
        if settings.fit_films:
            translation = out[index] = refine_thin_film(source, translation, target, settings)
        searched.append(index)
    graphs = graph_candidates_of([items[index] for index in searched])
    work = [(index, candidate, alternative_reading(items[index][0], items[index][2], items[index][3]))
            for index, candidate in zip(searched, graphs)]
    if not work:
        return out
    sharp = [mapping_sharpness(candidate, out[index].material) if KEEP_MAPPING_SHARPNESS else None
             for index, candidate, _ in work]
    try:
        judges = Judge.many([items[index][0] for index, *_ in work])
        figures = figures_many(judges, [[out[index].material] + ([a.material] if a is not None else [])
                                        + ([c] if c is not None else []) + ([s[0]] if s is not None else [])
                                        for (index, c, a), s in zip(work, sharp)])
    except (ValueError, KeyError, TypeError, IndexError, FloatingPointError):
        for index, candidate, _ in work:  # one by one: a material the evaluator cannot take loses only its own search
            source, _, target, settings = items[index]
            out[index] = _choose_one(source, out[index], target, settings, candidate)
        return out
    kept_sharpness = {}
    for position, (index, candidate, alternative) in enumerate(work):
        if alternative is not None:
            out[index], figures[position] = _reading(items[index][0], out[index], alternative, figures[position],
                                                     items[index][3])
        if sharp[position] is not None:
            ours, theirs, kept = figures[position]
            if theirs.score < ours.score - MARGIN and kept.score <= theirs.score + MARGIN:
                candidate = sharp[position][0]
                kept_sharpness[index] = (sharp[position][1], theirs.score, kept.score)
                figures[position] = [ours, kept]
            else:
                figures[position] = [ours, theirs]
        work[position] = (index, candidate)
    decided = _decide_many([(items[index][0], out[index], items[index][2], items[index][3], candidate, judge, score)
                            for (index, candidate), judge, score in zip(work, judges, figures)])
    for position, ((index, candidate), translation) in enumerate(zip(work, decided)):
        if index in kept_sharpness and translation.material is candidate:
            translation.diagnostics.append(sharpness_note(items[index][0], translation, *kept_sharpness[index],
                                                          items[index][3]))
        out[index] = translation
        source, _, _, settings = items[index]
        if settings.search:  # --verify: the target's parameters searched where the result is still visibly off
            try:
                start = judges[position].scores([translation.material])[0]
            except (ValueError, KeyError, TypeError, IndexError, FloatingPointError):
                continue
            out[index] = parameter_search(source, translation, judges[position], start, settings)
    return out


def alternative_reading(source: Material, target: str, settings: Settings) -> Translation | None:
    """The toolkit's second reading of ``source`` where it has one: a specular-workflow UsdPreviewSurface read
    with the F0 colour's luminance and a tint (``Settings.specular_split`` off) beside the default split into
    metal and dielectric shares (:mod:`.specular_workflow`), which a source that is not energy-conserving can
    defeat (a red F0 of 1 over a red diffuse); a glTF KHR_materials_pbrSpecularGlossiness material of
    constants read as a dielectric of its F0 colour's largest channel tinted by the colour (:mod:`.spec_gloss`)."""
    from .convert import convert  # lazy: translate.convert imports the translators, which this module serves

    if source.model == "open_pbr_surface":
        if target != "standard_surface" or not settings.metal_weight_tint or ss_metal_weight.coat_tint(
                source, Values(source, tables.table_known(source.model, source.version))) is None:
            return None
        return convert(source, target, dataclasses.replace(settings, metal_weight_tint=False, candidates=False))
    entry = source.inputs.get("useSpecularWorkflow") if source.model == "UsdPreviewSurface" else None
    glossy = spec_gloss.constant(source)  # glTF's KHR_materials_pbrSpecularGlossiness
    if not settings.specular_split or (not glossy and (entry is None or not isinstance(entry.value, Constant))):
        return None
    try:
        if not glossy and not float(entry.value.value) >= 1:
            return None
        return convert(source, target, dataclasses.replace(settings, specular_split=False, candidates=False))
    except (ValueError, KeyError, TypeError, IndexError):
        return None


#: Per source model: the input the readings concern, what they are about, the first reading and its short name, the
#: second (:func:`alternative_reading`), and what is said where the second is kept.
SECOND_READING = {
    "UsdPreviewSurface": ("specularColor", "specular workflow", "split into metal and dielectric shares", "the split",
                          "the F0 colour's luminance with a tint",
                          "the specular workflow read by its F0 colour's luminance with a tint"),
    "gltf_pbr": (None, "specular workflow", "split into metal and dielectric shares", "the split",
                 "a dielectric of the F0 colour's largest channel tinted by the colour",
                 "the specular workflow read as a dielectric of its F0 colour's largest channel tinted by the colour"),
    "open_pbr_surface": ("specular_weight", "a full metal's specular_weight", "as the coat's tint", "the coat's tint",
                         "folded into the base colour and the edge colour's target",
                         "the metal's specular_weight folded into the base colour and the edge colour's target")}


def _reading(source: Material, translation: Translation, alternative: Translation, figures: list, settings: Settings):
    """(the kept translation, its figures followed by the graphs'): the default reading, or ``alternative``
    where it renders closer by more than :data:`MARGIN`; reported with both figures."""
    ours, theirs = figures[0].score, figures[1].score
    where = next((d.location for d in translation.diagnostics if d.code in (APPROXIMATED.code, NOT_CARRIED.code)),
                 source.location)
    concerns, about, first, short, second, read = SECOND_READING[source.model]
    entry = source.inputs.get(concerns) if concerns else None
    if entry is not None and entry.location is not None:  # the reading concerns that input (the audit's F5)
        where = entry.location
    both = f"mean CIEDE2000 on the evaluator's {RIG_SIZE}-pixel sphere: {first} {ours:.2f}, {second} {theirs:.2f}"
    if theirs < ours - MARGIN:
        alternative.diagnostics.append(settings.context.diagnostic(
            APPROXIMATED, f"{source.name}: {read}, which renders closer than {short} ({both})", where))
        return alternative, [figures[1]] + figures[2:]
    translation.diagnostics.append(settings.context.diagnostic(
        CONVERTED, f"{source.name}: {about}: {both}; kept {short}", where))
    return translation, [figures[0]] + figures[2:]


def _decide_many(cases: list[tuple]) -> list[Translation]:
    """:func:`_decide` for each (source, translation, target, settings, candidate, judge, figures: the
    :class:`~.judging.Figure` of the mapping's result and of the candidate's), the appearance fits of all of
    them run together (:func:`.appearance.fit_many`): first the mappings', then the graphs' where one can
    change the choice."""
    ours = _fitted_many([(c[0], c[1].material, c[6][0], c[5]) for c in cases])
    wanted = []
    for case, ours_fit in zip(cases, ours):
        source, _, _, _, candidate, judge, figures = case
        scores = [figure.score for figure in figures]
        best_ours = ours_fit[1] if ours_fit else scores[0]
        # the graphs' result is fitted where it can change the choice or is kept: it already wins, or the
        # mapping, fitted, still renders visibly off (below FIT_FROM a fitted graph result could only tie)
        if candidate is not None and (scores[1] < best_ours - MARGIN or best_ours > appearance.FIT_FROM):
            wanted.append((source, candidate, figures[1], judge))
        else:
            wanted.append(None)
    theirs = iter(_fitted_many([w for w in wanted if w is not None]))
    return [_decide(*case[:6], [figure.score for figure in case[6]], ours_fit, next(theirs) if want is not None else None)
            for case, ours_fit, want in zip(cases, ours, wanted)]


def _choose_one(source, translation, target, settings, candidate) -> Translation:
    """One material's choice with its own renders (when a stacked evaluation of several failed)."""
    try:
        judge = Judge(source)
        figures, = figures_many([judge], [[translation.material] + ([candidate] if candidate is not None else [])])
    except (ValueError, KeyError, TypeError, IndexError, FloatingPointError):
        return translation
    return _decide_many([(source, translation, target, settings, candidate, judge, figures)])[0]


def _decide(source, translation, target, settings, candidate, judge, scores, ours_fit, theirs_fit) -> Translation:
    """Keep the mapping or the graphs' result, each after its appearance fit (``ours_fit``, ``theirs_fit``:
    :func:`_fitted_many`'s), by their figures (the graphs' must win by :data:`MARGIN`), reported with
    both; then the kept fit."""
    context = settings.context
    # the choice concerns the whole material; it is reported at the first input the mapping approximated
    where = next(d.location for d in translation.diagnostics if d.code in (APPROXIMATED.code, NOT_CARRIED.code))
    if candidate is None:
        return _with_fit(source, translation, scores[0], ours_fit, settings)
    ours, theirs = scores
    best_ours = ours_fit[1] if ours_fit else ours
    best_theirs = theirs_fit[1] if theirs_fit else theirs
    figures = (f"mean CIEDE2000 on the evaluator's {RIG_SIZE}-pixel sphere: the toolkit's mapping {ours:.2f}"
               + (f" ({best_ours:.2f} fitted)" if ours_fit else "") + f", MaterialX's translation graphs {theirs:.2f}"
               + (f" ({best_theirs:.2f} fitted)" if theirs_fit else ""))
    if not best_theirs < best_ours - MARGIN:
        visible = best_ours > VISIBLE  # the best the target holds still looks different: a warning, not a note
        translation.diagnostics.append(context.diagnostic(
            APPROXIMATED if visible else CONVERTED, f"{source.name}: candidates for {target}: {figures}; kept the "
            "toolkit's" + (f", still visibly off (above {VISIBLE:g}; the other notes say what the target cannot hold)"
                           if visible else ""), where))
        return _with_fit(source, translation, ours, ours_fit, settings)
    candidate.extra = dict(translation.material.extra)  # glTF state, drafts: the material's, not the mapping's
    notes = [d for d in translation.diagnostics if d.code != APPROXIMATED.code and id(d) not in translation.mapping_only]
    notes.append(context.diagnostic(
        APPROXIMATED, f"{source.name}: converted to {target} by MaterialX's translation graphs, which render "
                      f"closer than the toolkit's mapping ({figures})", where))
    rotated = ss_rotation.onto_candidate(translation.material, candidate)  # (the graphs turn no tangent)
    notes += [note for note in read_back_notes(source, candidate, where, context) if note.location.input not in rotated]
    return _with_fit(source, Translation(candidate, notes, translation.source), theirs, theirs_fit, settings)


def _fitted_many(cases: list[tuple[Material, Material, Figure, Judge]]) -> list:
    """For each (source, material, its :class:`~.judging.Figure`, judge): (:class:`.appearance.Fitted`,
    its score) when
    ``material`` renders more than :data:`.appearance.FIT_FROM` off and the adjusted one
    (:mod:`.appearance`) wins by more than :data:`MARGIN`, else None; all fitted and scored together
    (one by one where that fails, so a material the evaluator cannot take loses only its own fit)."""
    out: list = [None] * len(cases)
    due = [i for i, (_, _, figure, _) in enumerate(cases) if figure.score > appearance.FIT_FROM]
    if not due:
        return out
    try:
        fits = appearance.fit_many([(cases[i][0], cases[i][1], cases[i][3], cases[i][2].mean) for i in due])
        kept = [(i, f) for i, f in zip(due, fits) if f is not None]
        unscored = [(i, f) for i, f in kept if f.figure is None]  # (a fit that converged was rendered as written)
        scored = iter(scores_many([cases[i][3] for i, _ in unscored], [[f.material] for _, f in unscored]))
        figures = [(f.figure.score,) if f.figure is not None else next(scored) for _, f in kept]
    except (ValueError, KeyError, TypeError, IndexError, FloatingPointError):
        if len(due) == 1:
            return out
        for i in due:
            out[i] = _fitted_many([cases[i]])[0]
        return out
    for (i, fitted), (after,) in zip(kept, figures):
        out[i] = (fitted, after) if after < cases[i][2].score - MARGIN else None
    return out


def _with_fit(source: Material, translation: Translation, score: float, fit, settings: Settings) -> Translation:
    """``translation`` with its fit applied (when there is one), a note at each adjusted input's source
    input with both figures."""
    if fit is None:
        return translation
    fitted, after = fit
    translation.material.inputs = fitted.material.inputs
    for name, source_name in fitted.changed.items():
        entry = source.inputs.get(source_name)
        where = entry.location if entry is not None else source.location.with_input(source_name)
        translation.diagnostics.append(settings.context.diagnostic(
            APPROXIMATED, f"{source.name}: {fitted.material.model} {name} adjusted to "
                          f"{appearance.shown(fitted.material.inputs[name].value.value)} so that the lit sphere looks "
                          f"like the source's (what the target cannot hold of {source_name} and the rest): mean "
                          f"CIEDE2000 on the evaluator's {RIG_SIZE}-pixel sphere {score:.2f} -> {after:.2f}", where))
    return translation
