"""Appearance fit: where the best candidate for a constant material still renders visibly different
from the source (the target has no lobe for the source's fuzz or subsurface, no volume for its
tinted glass, another diffuse model for its rough diffuse, a conductor that ignores OpenPBR's
``specular_weight``, ...), a few of the target's inputs are adjusted so that its lit sphere looks
like the source's, and the result is kept only when it renders closer by more than the candidate
search's margin.

Two steps, both on the evaluator's lit sphere in linear Rec.709 (where the targets render):

1. **A shape search** (:data:`SEARCHES`), where the target has an input for what differs in shape: the
   diffuse roughness (Standard Surface's qualitative Oren-Nayar and OpenPBR's energy-preserving EON
   flatten a sphere differently: the roughness that looks alike is not the same number), and a
   UsdPreviewSurface's opacity for a transmitting source, up to 0.5 (the preview cannot tint what it
   lets through; a less transparent surface coloured like the glass looks closer, and at most half
   opaque it stays a glass: the sample bottle 13.7 -> 4.4 mean ΔE at 0.5). Each value of a
   grid is rendered (one stacked evaluation), the base colour of each rescaled per channel by the
   ratio of the source's mean radiance to its own, rendered again, and the closest kept.
2. **A colour fit** of the base colour (:data:`KNOB`): Newton steps on each channel's mean radiance
   over the sphere (the candidate and a copy with the colour perturbed rendered together, the
   slope of each channel's mean taken from the pair, the component moved to the value that matches
   the source's mean, within the input's range). The first step's candidate render is the search's
   own; the second step's is of the material as written, judged, and where its mean is already within
   :data:`CONVERGED` of the source's the fit ends there with that figure (no step, no render to score
   it again). (A secant second step, one render fewer, cost 4% less on the archetypes but fitted two
   Standard Surface materials that MaterialX's GLSL renders worse by more than 0.5.)

Not where the judges disagree (:func:`untrusted`): an interface of relative IOR below 1 (a specular or
coat IOR under 1) totally reflects beyond its critical angle in the evaluator, as physics has it,
while MaterialX's GLSL renders it by its F0 (the source alone: 10-17 mean CIEDE2000 apart at IOR
0.34-0.62, under 0.3 from 1.1 up, tests/benchmarks/bench_glsl_sample.py): a base colour fitted to the
evaluator's rim made such materials 10 ΔE worse under GLSL. Likewise a thin film on a metal base: the
evaluator's exact spectral interference and MaterialX's GLSL film are 11-15 mean CIEDE2000 apart on
such a source alone, and a fitted preview metal was 8 ΔE worse under GLSL; and a film whose IOR exceeds
its dielectric base's by more than :data:`FILM_IOR_AGREEMENT` (:data:`FILMS`): MaterialX's pearl (film
IOR 2 on 1.5, under a coat) renders 9.6 apart in the two, and its fitted glTF colour was 13.2 mean
CIEDE2000 off in GLSL where the unfitted mapping is 3.2.

Values are written back in the target input's own colour space and range. A colour with no effect
on the mean (a zero base weight) is left alone. Every adjusted input carries its own note (OPBR1103)
with what it became and both figures, so no value changes silently.
"""

from __future__ import annotations

import copy
from dataclasses import dataclass
from typing import Callable

import numpy as np

from .. import tables
from ..colorspaces import from_lin_rec709, to_lin_rec709
from ..model import Constant, Input, Material
from .judging import CLAMPED_IN_FILE, as_written, constant_values, figures_many, figures_of
from .target import inside

#: the colour each target's fit adjusts: the one that carries the base's diffuse and metal colour
KNOB = {"standard_surface": "base_color", "gltf_pbr": "base_color", "UsdPreviewSurface": "diffuseColor",
        "open_pbr_surface": "base_color"}
#: Each target's metal weight: where it is above 0 the fitted colour is also a conductor's reflectivity, held to
#: [0, 1] in linear Rec.709 where the target is shaded (MaterialX renders Standard Surface's and a preview's metal
#: by an artistic IOR, which takes none above 1; a preview metal fitted to (1.09, 0.83, 1.02) in an ACEScg
#: document was 1.5 mean CIEDE2000 closer on the evaluator's Schlick and 3.9 farther in MaterialX's GLSL).
METALNESS = {"standard_surface": "metalness", "gltf_pbr": "metallic", "UsdPreviewSurface": "metallic",
             "open_pbr_surface": "base_metalness"}
FIT_FROM = 1.0  # mean CIEDE2000 below which the candidate is left as it is (the fit costs renders)
STEPS = 2  # Newton steps; each renders the candidate and its perturbed copy together
PERTURBATION = 0.05  # of the colour component (absolute), for the slope
FLAT = 1e-4  # a channel whose mean moves less than this per unit of colour does not depend on it
#: A step that brings every channel's mean within this fraction of the source's (of 0.01 for a darker one)
#: ends the fit: the next step would move the colour by no more (58% of the glTF fits of the archetypes
#: converge in one step, as the mean is affine in the base colour of a dielectric); its render, which the
#: convergence test needs anyway, is the fit's figure.
CONVERGED = 1e-3


@dataclass(frozen=True)
class Search:
    """A target input searched over ``grid`` when ``applies(source values, candidate values)``; the
    source input named ``source_input`` is where the note goes."""
    target_input: str
    grid: tuple[float, ...]
    source_input: str
    applies: Callable[[dict, dict], bool]


def _positive(name: str) -> Callable[[dict, dict], bool]:
    return lambda source, candidate: float(source.get(name, 0.0)) > 0.0


#: The transmission weight's name in each source model (a glTF or Standard Surface glass is fitted too).
TRANSMISSION = {"open_pbr_surface": "transmission_weight", "standard_surface": "transmission", "gltf_pbr": "transmission"}


def _transparent_transmitter(source: dict, candidate: dict) -> bool:
    """A transmitting source written as the preview's transparency (opacityMode 0, "transparent")."""
    weight = max(float(source.get(name, 0.0)) for name in set(TRANSMISSION.values()))
    return weight > 0.0 and candidate.get("opacityMode", 0) in (0, "transparent") \
        and float(candidate.get("opacity", 1.0)) < 1.0


ROUGHNESS_GRID = tuple(i / 5 for i in range(6))
#: A transmitting material stays at least half see-through in the preview: an opaque tinted surface can
#: score closer on the lit sphere, but what a glass is for (seeing through it) would be gone.
OPACITY_GRID = tuple(i / 8 for i in range(5))
SEARCHES = {
    "standard_surface": (Search("diffuse_roughness", ROUGHNESS_GRID, "base_diffuse_roughness",
                                _positive("base_diffuse_roughness")),),
    "open_pbr_surface": (Search("base_diffuse_roughness", ROUGHNESS_GRID, "diffuse_roughness",
                                _positive("diffuse_roughness")),),
    "UsdPreviewSurface": (Search("opacity", OPACITY_GRID, "transmission_weight",
                                 _transparent_transmitter),),
}


@dataclass
class Fitted:
    """The adjusted material and, for each adjusted target input, the source input it stands for; and
    its :class:`~.judging.Figure` when the fit rendered it as written (a fit that converged)."""
    material: Material
    changed: dict[str, str]
    figure: object = None


def _in_range(space: str | None, rec709_file: bool) -> Callable[[np.ndarray], np.ndarray]:
    """Clips a linear Rec.709 colour to [0, 1] in the colour space the input is written in (a wide-gamut
    document's colours may lie outside [0, 1] in Rec.709, and that is where the fit works), and, for a
    colour the target's file holds in Rec.709 (:data:`.judging.CLAMPED_IN_FILE`), there as well: a fitted gold written to
    glTF was clipped by the writer after the fit had scored it unclipped (0.28 on the search's sphere,
    1.47 in the file)."""
    def clip(colour):
        inside = to_lin_rec709(np.clip(from_lin_rec709(colour, space), 0.0, 1.0), space)
        return np.clip(inside, 0.0, 1.0) if rec709_file else inside
    return clip


#: Per source model: (IOR input, the weight that switches it on or None) pairs below 1 of which the
#: evaluator and MaterialX's GLSL disagree (module docstring).
IORS = {"open_pbr_surface": (("specular_ior", None), ("coat_ior", "coat_weight")),
        "standard_surface": (("specular_IOR", None), ("coat_IOR", "coat")),
        "gltf_pbr": (), "UsdPreviewSurface": ()}


#: Per source model: (film input, metal input, film IOR input, base IOR input) of a thin film, which the
#: judges render apart on a metal, or where the film is optically much denser than its base (module docstring).
FILMS = {"open_pbr_surface": ("thin_film_weight", "base_metalness", "thin_film_ior", "specular_ior"),
         "standard_surface": ("thin_film_thickness", "metalness", "thin_film_IOR", "specular_IOR"),
         "gltf_pbr": ("iridescence", "metallic", "iridescence_ior", "ior")}
#: How far a film's IOR may exceed its base's before the fit is left out. MaterialX's GLSL film and the
#: evaluator's spectral interference, on a base of 1.5 (0.1-0.8 micrometres): 0.2-1.2 mean CIEDE2000
#: apart at film IOR 1.4-1.6, 1.6-3.4 at 1.8, 2.4-4.7 at 2.0, 4-8 at 2.5. On the generated archetypes
#: (bench_glsl_sample.py, 126 judged) the fits of such films still helped in GLSL (leaving out every film
#: more than 0.2 from its base cost 8 fits that were better by more than 0.5, and saved none); MaterialX's
#: pearl (film 2.0 on 1.5 under a coat) is where a fit hurt: 3.2 -> 13.2 to glTF. From 0.4 up, a film
#: denser than its base: 3 of those 8 fits lost, the pearl kept unfitted.
FILM_IOR_AGREEMENT = 0.4


def untrusted(source: Material) -> str | None:
    """The source input that makes the evaluator an untrusted judge of this material, or None."""
    values = constant_values(source) or {}
    table = tables.table(source.model)

    def value(name):
        return float(values.get(name, table[name].default))

    for name, switch in IORS.get(source.model, ()):
        if (switch is None or value(switch) > 0) and value(name) < 1.0:
            return name
    film, metal, film_ior, base_ior = FILMS.get(source.model, (None, None, None, None))
    if film is not None and value(film) > 0 and \
            (value(metal) > 0 or value(film_ior) - value(base_ior) > FILM_IOR_AGREEMENT):
        return film
    return None


@dataclass
class _Job:
    """One material's fit in progress (:func:`fit_many`)."""
    source: Material
    judge: object
    knob: str
    clip: Callable
    material: Material
    values: dict
    changed: dict
    mean: np.ndarray | None = None  # the mean radiance of ``values``' render, when it has been rendered
    figure: object = None  # the Figure of ``material`` as written, when it has been rendered so


def _job(source: Material, candidate: Material, judge, mean: np.ndarray | None = None) -> _Job | None:
    knob = KNOB.get(candidate.model)
    if knob is None or constant_values(candidate) is None or untrusted(source) is not None:
        return None
    values = as_written(candidate)
    if np.asarray(values.get(knob)).shape != (3,):
        return None
    entry = candidate.inputs.get(knob)
    metal = float(np.max(values.get(METALNESS.get(candidate.model, ""), 0.0))) > 0.0
    clip = _in_range((entry.colorspace if entry is not None else None) or candidate.colorspace,
                     knob in CLAMPED_IN_FILE.get(candidate.model, ()) or metal)
    return _Job(source, judge, knob, clip, candidate, values, {}, mean)


def _figures(renders: list[tuple[_Job, str, dict, bool]]) -> list:
    """The :class:`~.judging.Figure` of each (job, model, values, scored) render, all rendered together
    (:func:`.judging.figures_of`; the judges share one rig); compared with the source only where scored."""
    return figures_of([(job.judge, model, values) for job, model, values, _ in renders],
                      [scored for *_, scored in renders]) if renders else []


def fit_many(items: list[tuple]) -> list[Fitted | None]:
    """For each (source, candidate, judge[, mean]) of ``items``: ``candidate`` (constant-valued, of a model
    in :data:`KNOB`) adjusted to look like ``source`` (module docstring), or None. ``judge`` is the
    candidate search's :class:`~.judging.Judge` (the source's render: its mask, ``goal``, ``scores``);
    ``mean``, when given, the candidate's mean radiance on it (from the search's render, not rendered
    again); the shape search keeps the value it scores best. Every step's renders of all of them are
    stacked together (a file's materials are fitted at once, as the candidate search weighs them)."""
    jobs = [_job(*item) for item in items]
    active = [job for job in jobs if job is not None]
    _shape_search(active)
    for _ in range(STEPS):
        active = _colour_step(active)
    out: list[Fitted | None] = []
    for job in jobs:
        out.append(Fitted(job.material, job.changed, job.figure) if job is not None and job.changed else None)
    return out


def _shape_search(jobs: list[_Job]) -> None:
    """Each job's :data:`SEARCHES` grid, base colour rescaled by the ratio of the source's mean radiance to
    the trial's, all scored together; the best kept (module docstring, step 1)."""
    plans = []
    for job in jobs:
        source_values = constant_values(job.source) or {}
        for search in SEARCHES.get(job.material.model, ()):
            if search.applies(source_values, constant_values(job.material)):
                plans.append((job, search, [dict(job.values, **{search.target_input: g}) for g in search.grid]))
    if not plans:
        return
    flat = [(job, job.material.model, values, False) for job, _, trials in plans for values in trials]
    means = iter(figure.mean for figure in _figures(flat))
    scored = []
    for job, search, trials in plans:
        recoloured = []
        for values in trials:
            mean = next(means)
            colour = np.asarray(values[job.knob], dtype=float)
            ratio = np.where(mean > FLAT, job.judge.goal / np.maximum(mean, FLAT), 1.0)
            recoloured.append(dict(values, **{job.knob: job.clip(colour * ratio)}))
        written = [_written(job.material, trial, (search.target_input, job.knob)) for trial in recoloured]
        kept = [i for i, w in enumerate(written) if w is not None]
        scored.append((job, search, recoloured, written, kept))
    judged = figures_many([job.judge for job, *_ in scored],
                          [[job.material] + [written[i] for i in kept] for job, _, _, written, kept in scored])
    for (job, search, recoloured, written, kept), figures in zip(scored, judged):
        best = int(np.argmin([figure.score for figure in figures]))
        job.mean = figures[best].mean  # (the trial as written: its render is the colour fit's start)
        if best > 0:
            chosen = kept[best - 1]
            job.material, job.values = written[chosen], as_written(written[chosen])
            job.changed[search.target_input] = TRANSMISSION.get(job.source.model, search.source_input) \
                if search.source_input == TRANSMISSION["open_pbr_surface"] else search.source_input
            job.changed[job.knob] = KNOB.get(job.source.model, "base_color")


def _colour_step(jobs: list[_Job]) -> list[_Job]:
    """One Newton step of every job's colour fit on its channels' mean radiance (module docstring, step
    2): each channel's slope from the colour and a copy with it perturbed, all rendered together (the
    colour's own render is the search's where it has one; otherwise the material as written, judged: a
    job already within :data:`CONVERGED` of the source ends there, with that figure); returns the jobs
    still moving."""
    flat = []
    for job in jobs:
        if job.mean is None:
            job.values = as_written(job.material)
            flat.append((job, job.material.model, job.values, True))
        colour = np.asarray(job.values[job.knob], dtype=float)
        flat.append((job, job.material.model, dict(job.values, **{job.knob: colour + _perturbation(job, colour)}), False))
    figures = iter(_figures(flat))
    moving = []
    for job in jobs:
        colour = np.asarray(job.values[job.knob], dtype=float)
        if job.mean is None:
            job.figure = next(figures)
            job.mean = job.figure.mean
            if np.all(np.abs(job.mean - job.judge.goal) <= CONVERGED * np.maximum(np.abs(job.judge.goal), 0.01)):
                next(figures)
                continue  # converged: the next step would not move it
        now = job.mean
        slope = (next(figures).mean - now) / _perturbation(job, colour)
        usable = np.abs(slope) > FLAT
        if not usable.any():
            continue  # the colour does not move the render: left as it is
        colour = job.clip(np.where(usable, colour + (job.judge.goal - now) / np.where(usable, slope, 1.0), colour))
        job.values = dict(job.values, **{job.knob: colour})
        job.material = _written(job.material, job.values, (job.knob,)) or job.material
        job.mean = job.figure = None
        job.changed[job.knob] = KNOB.get(job.source.model, "base_color")
        moving.append(job)
    return moving


def _perturbation(job: _Job, colour: np.ndarray) -> np.ndarray:
    """Per channel, the colour's step for the first slope: up, or down where the input's range ends."""
    return np.where(job.clip(colour + PERTURBATION)[...] > colour + PERTURBATION / 2, PERTURBATION, -PERTURBATION)


def _written(candidate: Material, values: dict, names: tuple[str, ...]) -> Material | None:
    """``candidate`` with ``names`` set from ``values`` (linear Rec.709 numbers) in each input's own
    colour space, brought inside the parameter's range; None when an input is not a constant."""
    table = tables.table(candidate.model)
    written = copy.copy(candidate)
    written.inputs = dict(candidate.inputs)
    for name in names:
        parameter = table[name]
        entry = candidate.inputs.get(name)
        if entry is not None and not isinstance(entry.value, Constant):
            return None
        value = np.asarray(values[name], dtype=float)
        if parameter.role == "color":
            space = (entry.colorspace if entry is not None else None) or candidate.colorspace
            value = from_lin_rec709(value, space)
            written_value, _ = inside(tuple(float(v) for v in value), parameter)
        else:
            written_value, _ = inside(float(value), parameter)
        location = entry.location if entry is not None else candidate.location.with_input(name)
        colorspace = (entry.colorspace if entry is not None else candidate.colorspace) if parameter.role == "color" \
            else None
        written.inputs[name] = Input(name, parameter.type, Constant(written_value), location, colorspace=colorspace)
    return written


def shown(value) -> str:
    if isinstance(value, (tuple, list)):
        return "(" + ", ".join(f"{float(v):.4g}" for v in value) + ")"
    return f"{value:.4g}" if isinstance(value, float) else str(value)
