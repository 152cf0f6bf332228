"""Never worse than the anchor: for an OpenPBR material the toolkit's mapping can only approximate in
the target (and for a Standard Surface material converted to OpenPBR, glTF or UsdPreviewSurface), MaterialX's own translation
graphs (:mod:`.materialx_graphs`) give a second candidate, and the lobe evaluator keeps the one that
renders closer to the source.

Weighed when asked (``Settings.candidates``: ``openpbr convert --verify``, which renders with the
evaluator anyway), not with ``--gltf-drafts`` nor for a material that came from glTF (whose point is
the mapping's exact inverses: a glTF round trip stays exact). On 72 generated materials in three
document colour spaces the mapping alone was up to 13.6 mean CIEDE2000 worse than MaterialX's chain,
with the search at most 0.05 (tests/test_never_worse_than_chain.py). Only
constant-valued materials have a graph candidate; a value the graphs put outside the target's range
is brought inside it, as the toolkit's own results are (an ``attenuation_distance`` of 0, the
graphs' "no attenuation", is left unset) (the graphs are evaluated on values; a textured
material keeps the toolkit's mapping, which bakes per texel). An exact mapping (no OPBR1103 note) is
kept without a search. The two are rendered on the evaluator's lit sphere at a small size
(:data:`RIG_SIZE`, 32 pixels: a few milliseconds per candidate; ``--verify`` measures the result at full
size), CIEDE2000 mean against the source; the graph's result wins only by more than
:data:`MARGIN`. The report says which was kept and both figures (OPBR1102); when the graph's is
kept, the mapping's approximation notes are replaced by one naming the graph.
"""

from __future__ import annotations

import copy

from .. import tables
from ..values import is_finite
from ..model import Constant, Input, Material
from ..rules.translation import APPROXIMATED, CONVERTED
from . import materialx_graphs
from .common import Settings, Translation
from .target import inside

RIG_SIZE = 32  # pixels of the evaluator's sphere for the candidate search
MARGIN = 0.05  # mean CIEDE2000: a smaller win is noise at this size


def _constant_values(material: Material) -> dict | None:
    values = {}
    for name, entry in material.inputs.items():
        if not isinstance(entry.value, Constant):
            return None
        values[name] = entry.value.value
    return values


def graph_candidate(source: Material, target: str) -> Material | None:
    """The target material MaterialX's graphs make of ``source`` (constant OpenPBR or Standard Surface),
    or None."""
    values = _constant_values(source)
    if values is None or not materialx_graphs.graphs(source.model, target):
        return None
    try:
        produced = materialx_graphs.chain(target, values, source.model)
    except (materialx_graphs.GraphError, TypeError, ValueError, KeyError, IndexError):
        return None
    table = tables.table(target)
    candidate = Material(name=source.name, model=target, location=source.location, version=table.version,
                         version_basis="written by openpbr convert", material_name=source.material_name,
                         material_location=source.material_location, colorspace=source.colorspace)
    for name, value in produced.items():
        parameter = table.get(name)
        if parameter is None or parameter.role in ("normal", "tangent"):
            continue
        if parameter.type == "integer":
            value = int(round(float(value)))
        if parameter.default is None and isinstance(value, float) and value <= 0:
            continue  # an unbounded length (attenuation_distance) of 0: the graphs' "none", the default
        value, moved = inside(value, parameter)
        if moved and not is_finite(value):
            return None
        entry = source.inputs.get(name)
        candidate.inputs[name] = Input(name, parameter.type, Constant(value),
                                       entry.location if entry is not None else source.location.with_input(name),
                                       colorspace=source.colorspace if parameter.role == "color" else None)
    return candidate


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
            not isinstance(film.value, Constant) or not film.value.value > 0 or _constant_values(source) is None:
        return translation
    # lazy: the evaluator (NumPy, albedo tables) loads only for an approximated constant film
    from ..evaluate import model_for_material
    from ..evaluate.difference import compare_images  # lazy: as above
    from ..evaluate.preview import Rig, shade_sphere  # lazy: as above

    FILM_RIG = Rig(size=FILM_RIG_SIZE)
    base = float(entry.value.value)

    def score(thickness, reference, mask):
        trial = copy.copy(translation.material)
        trial.inputs = dict(trial.inputs)
        trial.inputs[name] = Input(name, entry.type, Constant(thickness), entry.location)
        return compare_images(reference, shade_sphere(model_for_material(trial)[0], FILM_RIG)[0], mask,
                              FILM_RIG.white()).mean

    try:
        reference, mask = shade_sphere(model_for_material(source)[0], FILM_RIG)
        mapped = score(base, reference, mask)
        found = min((score(base * scale, reference, mask), base * scale) for scale in FILM_SCALES)
    except (ValueError, KeyError, TypeError, FloatingPointError):
        return translation
    if not found[0] < mapped - MARGIN:
        return translation
    translation.material.inputs[name] = Input(name, entry.type, Constant(float(found[1])), entry.location)
    translation.diagnostics.append(settings.context.diagnostic(
        APPROXIMATED, f"{source.name}: {name} fitted to {found[1]:.1f} nm (the mapped {base:.1f} nm interferes "
                      f"differently in {target}'s film model): mean CIEDE2000 on the evaluator's "
                      f"{FILM_RIG.size}-pixel sphere {mapped:.2f} -> {found[0]:.2f}",
        source.location.with_input("thin_film_thickness")))
    return translation


def choose(source: Material, translation: Translation, target: str, settings: Settings) -> Translation:
    """``translation`` (OpenPBR ``source`` -> ``target``) or MaterialX's graph result, whichever the
    evaluator renders closer to the source (module docstring)."""
    if not settings.candidates or settings.gltf_drafts or not materialx_graphs.graphs(source.model, target) or \
            isinstance(source.extra.get("gltf"), dict) or \
            not any(d.code == APPROXIMATED.code for d in translation.diagnostics):
        return translation  # (with the drafts, or for a material read from glTF, the mapping's exact inverses are the point)
    translation = refine_thin_film(source, translation, target, settings)
    candidate = graph_candidate(source, target)
    if candidate is None:
        return translation
    # lazy: the evaluator loads its albedo tables; only an approximated constant material needs it
    from ..evaluate import model_for_material
    from ..evaluate.difference import compare_images  # lazy: as above
    from ..evaluate.preview import Rig, shade_sphere  # lazy: as above

    RIG = Rig(size=RIG_SIZE)

    try:
        reference, mask = shade_sphere(model_for_material(source)[0], RIG)
        ours = compare_images(reference, shade_sphere(model_for_material(translation.material)[0], RIG)[0], mask,
                              RIG.white()).mean
        theirs = compare_images(reference, shade_sphere(model_for_material(candidate)[0], RIG)[0], mask,
                                RIG.white()).mean
    except (ValueError, KeyError, TypeError, FloatingPointError):
        return translation
    context = settings.context
    # the choice concerns the whole material; it is reported at the first input the mapping approximated
    where = next(d.location for d in translation.diagnostics if d.code == APPROXIMATED.code)
    figures = (f"mean CIEDE2000 on the evaluator's {RIG.size}-pixel sphere: the toolkit's mapping {ours:.2f}, "
               f"MaterialX's translation graphs {theirs:.2f}")
    if not theirs < ours - MARGIN:
        translation.diagnostics.append(context.diagnostic(
            CONVERTED, f"{source.name}: candidates for {target}: {figures}; kept the toolkit's", where))
        return translation
    candidate.extra = dict(translation.material.extra)  # glTF state, drafts: the material's, not the mapping's
    kept = [d for d in translation.diagnostics if d.code != APPROXIMATED.code]
    kept.append(context.diagnostic(
        APPROXIMATED, f"{source.name}: converted to {target} by MaterialX's translation graphs, which render closer "
                      f"than the toolkit's mapping ({figures})", where))
    return Translation(candidate, kept, translation.source)
