"""MaterialX's own translation graphs as a candidate (#13, never worse than the anchor): the target
material the graphs make of a constant OpenPBR or Standard Surface source (:mod:`.materialx_graphs`,
every graph evaluated once for a file's materials), brought inside the target's ranges (a value the
graphs put outside a range is moved inside it, as the toolkit's own results are; an
``attenuation_distance`` of 0, the graphs' "no attenuation", is left unset); and, where the candidate
search (:mod:`.candidates`) keeps it, a note at every authored input it does not carry exactly
(:func:`read_back_notes`).
"""

from __future__ import annotations

import numpy as np

from .. import colorspaces, tables
from ..model import Constant, Input, Material
from ..rules.translation import APPROXIMATED
from ..values import is_finite
from . import materialx_graphs
from .common import Settings, differs
from .judging import constant_values
from .target import inside


def graph_candidate(source: Material, target: str) -> Material | None:
    """The target material MaterialX's graphs make of ``source`` (constant OpenPBR or Standard Surface),
    or None."""
    return graph_candidates([source], target)[0]


def graph_candidates(sources: list[Material], target: str) -> list[Material | None]:
    """:func:`graph_candidate` for each of ``sources`` (one model), the graphs evaluated once for all of
    them (:func:`.materialx_graphs.chain_many`: the same values); one by one where that fails, so a
    material the graphs cannot take has no candidate alone."""
    values = [constant_values(source) for source in sources]
    usable = [i for i, v in enumerate(values) if v is not None]
    out: list[Material | None] = [None] * len(sources)
    if not usable or not materialx_graphs.graphs(sources[0].model, target):
        return out
    try:
        produced = materialx_graphs.chain_many(target, [values[i] for i in usable], sources[0].model)
    except (materialx_graphs.GraphError, TypeError, ValueError, KeyError, IndexError):
        if len(usable) == 1:
            return out
        return [graph_candidate(source, target) for source in sources]
    for i, values_out in zip(usable, produced):
        try:
            out[i] = _graph_material(sources[i], target, values_out)
        except (TypeError, ValueError, KeyError, IndexError):
            out[i] = None
    return out


#: Per target, the colours of the graphs' result held to [0, 1] in linear Rec.709, as the toolkit's mapping holds its
#: own (Mapping.clips): beyond 1, renderers part. A UsdPreviewSurface metal's diffuseColor above 1 (the graphs pass an
#: OpenPBR gold's ACEScg base colour through: (1.059, 0.773, 0.307) in Rec.709) is Schlick's F0 above 1 in Storm and
#: the evaluator, and in MaterialX's graph an artistic-IOR conductor whose reflectivity is clamped to 0.99 and whose
#: edge colour extrapolates: the red team's J/F2, 0.08 on the evaluator and 6.03 in MaterialX's GLSL.
HELD_TO_ONE = {"UsdPreviewSurface": ("diffuseColor", "specularColor")}


def _graph_material(source: Material, target: str, produced: dict) -> Material | None:
    """The ``target`` material of the graphs' ``produced`` values for ``source``, brought inside the
    target's ranges (module docstring), or None."""
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
        if name in HELD_TO_ONE.get(target, ()) and isinstance(value, tuple) and len(value) == 3:
            value = tuple(colorspaces.from_lin_rec709(colorspaces.into_gamut(
                colorspaces.to_lin_rec709(value, source.colorspace), high=1.0), source.colorspace))
        entry = source.inputs.get(name)
        candidate.inputs[name] = Input(name, parameter.type, Constant(value),
                                       entry.location if entry is not None else source.location.with_input(name),
                                       colorspace=source.colorspace if parameter.role == "color" else None)
    return candidate


def graph_candidates_of(items: list[tuple]) -> list[Material | None]:
    """The graphs' candidate (:func:`graph_candidates`) of each (source, translation, target, settings),
    those of one source model and target evaluated together."""
    out: list[Material | None] = [None] * len(items)
    groups: dict = {}
    for position, (source, _, target, _) in enumerate(items):
        if materialx_graphs.graphs(source.model, target):
            groups.setdefault((source.model, target), []).append(position)
    for (_, target), positions in groups.items():  # (graph_candidates falls back one by one itself)
        for p, candidate in zip(positions, graph_candidates([items[p][0] for p in positions], target)):
            out[p] = candidate
    return out


def read_back_notes(source: Material, written: Material, where, context) -> list:
    """A note at every input of ``source`` (authored, or left at a default the result changes: a glTF
    clear coat does not darken) that ``written`` (the graphs' result) does not carry exactly: the written material is converted back to the source's model with the toolkit's
    inverse mapping, and each authored constant compared with what comes back (1e-5). The graphs'
    arithmetic is their own, so no input can be assumed to survive; this says which did not."""
    from .convert import convert  # lazy: translate.convert imports the translators, which this module serves

    try:
        back = convert(written, source.model, Settings(context=context, candidates=False)).material
    except (ValueError, KeyError, TypeError):
        return [context.diagnostic(APPROXIMATED, f"{source.name}: the graphs' result could not be read back to "
                                                 f"{source.model}; every input may differ", where)]
    notes = []
    table = tables.table(source.model)
    for name, parameter in table.parameters.items():
        entry = source.inputs.get(name)
        if parameter.role in ("normal", "tangent") or (entry is not None and not isinstance(entry.value, Constant)):
            continue
        if entry is None and _lobe_off(source, table, name):
            continue  # a default of a lobe the material does not have (a fuzz roughness without fuzz)
        authored = entry.value.value if entry is not None else parameter.default  # a default the result changes too
        if authored is None:
            continue
        returned = back.inputs.get(name)
        value = returned.value.value if returned is not None and isinstance(returned.value, Constant) \
            else parameter.default
        if _changed(authored, value):
            what = _shown(authored) if entry is not None else f"(default {_shown(authored)})"
            notes.append(context.diagnostic(
                APPROXIMATED, f"{source.name}: {name} {what} is not carried exactly by MaterialX's "
                              f"translation graphs' result (reads back as {_shown(value)})",
                entry.location if entry is not None else source.location.with_input(name)))
    return notes


def _lobe_off(source: Material, table, name: str) -> bool:
    """Whether ``name`` belongs to a lobe whose switch (:meth:`~openpbr_tools.tables.ParameterTable.lobe_switch`) is 0
    in ``source``."""
    weight = table.lobe_switch(name)
    if weight is None:
        return False
    entry = source.inputs.get(weight)
    value = entry.value.value if entry is not None and isinstance(entry.value, Constant) else table[weight].default
    try:
        return not float(value) > 0
    except (TypeError, ValueError):
        return False


def _changed(authored, returned) -> bool:
    """:func:`.common.differs`, the translators' own test of a changed value, for values of any type."""
    try:
        return np.shape(authored) != np.shape(returned) or differs(returned, np.asarray(authored, dtype=float))
    except (TypeError, ValueError):
        return authored != returned


def _shown(value) -> str:
    if isinstance(value, (tuple, list)):
        return "(" + ", ".join(f"{float(v):.4g}" for v in value) + ")"
    return f"{value:.4g}" if isinstance(value, float) else str(value)
