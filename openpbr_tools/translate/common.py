"""The machinery every model-to-model translation shares.

A translation is a list of :class:`Mapping` objects: a target parameter, the source parameters it
reads, and a vectorised NumPy function of those (``None`` for a plain copy). The same function
serves a constant (arrays of shape ``()`` or ``(3,)``), a whole texture baked texel by texel, and
the evaluator. :func:`translate` applies the mappings:

* every source parameter constant: the formula gives the target constant;
* one textured source and a plain copy: the texture passes through unchanged (resolution, texels,
  colour space, UV transform all kept);
* a texture the formula would have to transform: with a :class:`~.bake.Baker` in the settings,
  the same formula is evaluated on every texel into a new image (reported as OPBR1102); without
  one (a translation in memory, with nowhere to put images), or when the textures cannot be baked
  (UDIM sets, different UV transforms, unreadable images), it is reported (OPBR1104) and the
  target keeps its default;
* a procedural connection (a node graph the reader captured): rewired as is through a plain copy;
  through a formula, written after the graph as MaterialX nodes where the formula is affine or a
  polynomial per channel there (:mod:`.expressed`); otherwise reported, never dropped silently.

Each mapping says whether it is exact; an inexact one reports OPBR1103 with its ``note`` when the
source values are not at the defaults where the approximation is harmless (``matters``).

One module because :func:`translate` is one pass: a mapping's constant, textured and procedural branches share
its bookkeeping (which inputs were reported, which failed, where a note stands), and the :class:`Mapping` and
:class:`Dropped` vocabulary the translators write is what that pass reads.
"""

from __future__ import annotations

import copy
from dataclasses import dataclass, field
from typing import Any, Callable

import numpy as np

from .. import tables
from ..diagnostics import Diagnostic
from ..io.gltf.slots import SLOT_BY_PARAMETER
from ..model import Connection, Constant, Input, Material, Texture
from ..rules.translation import APPROXIMATED, CONVERTED, NOT_CARRIED
from . import expressed as expressed_module, normal_graphs, probes
from .settings import Settings
from .target import WorkingSpace, inside


class BakeError(ValueError):
    """Raised by a baker (``Settings.baker``, :class:`openpbr_tools.bake.Baker` in the convert
    pipeline) for a texture it cannot bake, with the reason; the translation reports it (OPBR1104)."""


@dataclass(frozen=True, slots=True)
class Mapping:
    """``target`` = ``formula(*sources)``; ``formula=None`` copies the single source."""

    target: str
    sources: tuple[str, ...]
    formula: Callable[..., Any] | None = None
    exact: bool = True
    note: str = ""
    matters: Callable[..., bool] | None = None  # given the source values: is the approximation visible?
    converted: str = ""  # for exact conversions worth reporting (units, folded parameters)
    when: Callable[..., bool] | None = None  # given the source values: does the target need this at all?
    converted_to_default: bool = False  # say ``converted`` also where the value lands on the target's default
    keep: str | None = None  # where the formula cannot be applied per texel: this source's texture or graph, as is
    clips: bool = True  # the formula holds its colours to [0, 1] in linear Rec.709 (a wide-gamut source is noted)
    site: str | None = None  # the source an approximation's note stands at, where authored (default: the first)
    # where a source is procedural and the formula can be neither baked nor written as nodes: (a constant the target
    # then takes, why it is exact there), e.g. a film's weight 1 over a graph-driven thickness (0 is no film)
    otherwise: tuple[float, str] | None = None


@dataclass(frozen=True, slots=True)
class Dropped:
    """A source parameter with no equivalent in the target. ``matters`` decides, from the source
    values, whether dropping it changes the look (then OPBR1104 is reported)."""

    source: str
    why: str
    matters: Callable[..., bool] | None = None
    needs: tuple[str, ...] = ()


@dataclass(slots=True)
class Translation:
    material: Material
    diagnostics: list[Diagnostic] = field(default_factory=list)
    source: Material | None = None
    # (source input, note) for each input a noted mapping folded in: added by :func:`with_folded_notes` where
    # nothing else the translator reported stands at that input
    folded: list[tuple[str, Diagnostic]] = field(default_factory=list)
    # what :func:`translate` applied: the source inputs its mappings and drops read (None: no mapping table ran),
    # and for each target input the source inputs its mappings read (where a later step's note belongs)
    read: frozenset[str] | None = None
    origins: dict[str, tuple[str, ...]] = field(default_factory=dict)
    quiet_drops: tuple = ()  # drops whose value is lost but renders nothing here (unread_notes says so)
    about: dict[int, str] = field(default_factory=dict)  # id(note) -> the source input it concerns (translate's own)
    # ids of the notes that only describe the mapping's own result (how a mapping rewrote a value; a pointer at
    # another note, "see the note at X", :func:`_companions`): a result MaterialX's graphs give instead drops them
    # (translate.candidates), as it drops the mapping's approximations
    mapping_only: frozenset[int] = frozenset()


def with_folded_notes(translation: Translation) -> Translation:
    """``translation`` with a note at each source input a mapping folded into another and nothing else names
    (:func:`_companions`), judged once the translator has added its own notes (a preview's presence note at
    geometry_opacity, say)."""
    sites = {d.location.input for d in translation.diagnostics}  # (as located: a glTF property, thicknessFactor)
    for _, note in translation.folded:
        if note.location.input not in sites:
            sites.add(note.location.input)
            translation.diagnostics.append(note)
    translation.folded = []
    translation.diagnostics.sort(key=Diagnostic.sort_key)
    translation.mapping_only = translation.mapping_only & {id(d) for d in translation.diagnostics}  # (those left out are gone)
    return translation


class Values:
    """Source parameter values for formulas: authored constants, else the source table's default."""

    def __init__(self, material: Material, table):
        self.material, self.table = material, table
        self.reported: set[str] = set()

    def entry(self, name: str) -> Input | None:
        return self.material.inputs.get(name)

    def authored(self, name: str) -> bool:
        return name in self.material.inputs

    def constant(self, name: str):
        entry = self.material.inputs.get(name)
        parameter = self.table.get(name)
        if entry is None or entry.value is None:
            default = parameter.default if parameter is not None else None
            if default is None and parameter is not None and parameter.type == "float":
                return np.asarray(np.inf)  # an unset float without a default is unbounded (attenuation_distance)
            return None if default is None else np.asarray(default, dtype=np.float64)
        if isinstance(entry.value, Constant):
            value = entry.value.value
            if isinstance(value, str) or not self.fits(name):
                return None
            return np.asarray(value, dtype=np.float64)
        return None  # textured or connected

    def fits(self, name: str) -> bool:
        """Whether an authored constant has the parameter's number of components (a colour4 or a
        vector on a float input, as hostile files carry, is not used: it is reported instead)."""
        entry, parameter = self.material.inputs.get(name), self.table.get(name)
        if entry is None or parameter is None or not isinstance(entry.value, Constant):
            return True
        value = entry.value.value
        if isinstance(value, str):
            return True
        size = len(value) if isinstance(value, (tuple, list)) else 1
        expected = {"color3": 3, "vector3": 3, "color4": 4, "vector4": 4, "vector2": 2}.get(parameter.type, 1)
        return size == expected

    def is_constant(self, name: str) -> bool:
        entry = self.material.inputs.get(name)
        return entry is None or isinstance(entry.value, Constant) or entry.value is None


def as_value(array, type_name: str):
    """A NumPy result as the Python value of a MaterialX type."""
    values = np.asarray(array, dtype=np.float64)
    if type_name == "boolean":
        return bool(values.reshape(-1)[0] >= 0.5)
    if type_name == "integer":
        return int(round(float(values.reshape(-1)[0])))
    if type_name in ("float",):
        return float(values.reshape(-1)[0]) if values.size else 0.0
    count = {"color3": 3, "vector3": 3, "color4": 4, "vector4": 4, "vector2": 2}[type_name]
    flat = np.broadcast_to(values.reshape(-1) if values.size > 1 else values.reshape(()), (count,))
    return tuple(float(v) for v in flat)


def _equal(a, b) -> bool:
    if b is None and isinstance(a, float):
        return a == float("inf")  # an unset unbounded float (attenuation_distance) is infinite
    if a is None or b is None:
        return a is b
    return bool(np.allclose(np.asarray(a, dtype=np.float64), np.asarray(b, dtype=np.float64), rtol=0, atol=1e-9))


#: Models whose normal and tangent inputs are world-space vectors (MaterialX's geometry defaults: Nworld,
#: Tworld), so an authored constant means the same in both; a UsdPreviewSurface's normal is tangent-space and
#: glTF's come from the mesh.
WORLD_SPACE_VECTORS = frozenset({"open_pbr_surface", "standard_surface"})


def translate(material: Material, target_model: str, mappings: tuple[Mapping, ...], dropped: tuple[Dropped, ...],
              settings: Settings, label: str) -> Translation:
    """Apply ``mappings`` to ``material``; returns the target material and the loss report."""
    source_table = tables.table(material.model, material.version or tables.latest(material.model))
    target_table = tables.table(target_model)
    values = Values(material, source_table)
    context = settings.context
    result = Material(
        name=material.name, model=target_model, location=material.location, version=target_table.version,
        version_basis="written by openpbr convert", material_name=material.material_name,
        material_location=material.material_location, colorspace=material.colorspace)
    if isinstance(material.extra.get("gltf"), dict):  # glTF state travels with the material (gltf_state)
        result.extra["gltf"] = copy.deepcopy(material.extra["gltf"])
    report: list[Diagnostic] = []
    about: dict[int, str] = {}  # id(note) -> the source input it concerns
    working = WorkingSpace(material, source_table)

    noted: list[tuple[Any, Mapping, str | None]] = []  # (rule, mapping, input) of each note a mapping made
    current: list[Mapping | None] = [None]  # the mapping being applied

    own: set[int] = set()  # (Translation.mapping_only)

    def say(rule, message: str, name: str | None, describes: bool = False) -> None:
        entry = material.inputs.get(name) if name else None
        location = entry.location if entry is not None else material.location.with_input(name)
        report.append(context.diagnostic(rule, f"{material.name} ({label}): {message}", location))
        if describes:
            own.add(id(report[-1]))
        if name:
            about[id(report[-1])] = name
        if current[0] is not None:
            noted.append((rule, current[0], name))

    def say_note(mapping: Mapping, name: str) -> None:  # a texture or graph carried: ``matters`` at the defaults
        if not mapping.exact and _matters(mapping, _at_defaults(mapping, values, source_table)):
            say(APPROXIMATED, f"{mapping.target}: {mapping.note}", name)

    for name in sorted(material.inputs):
        if not values.fits(name):
            say(NOT_CARRIED, f"{name} holds a value of another shape than its type "
                             f"({source_table[name].type}) and is not carried", name)
    handled: set[str] = set()  # textured sources carried, baked, expressed, or reported at their own input
    failed: dict[str, str] = {}  # textured source -> a target that could not take it (reported at another input)

    def keep_as_is(mapping: Mapping, parameter, textured: list, why: str) -> bool:
        """``mapping.keep``'s texture or graph carried as is where the formula cannot be applied (``why``), or
        ``mapping.otherwise``'s constant."""
        if mapping.otherwise is not None:
            value, reason = mapping.otherwise
            result.inputs[mapping.target] = _constant_input(material, mapping, as_value(value, parameter.type),
                                                            parameter.type)
            handled.update(textured)
            say(CONVERTED, f"{mapping.target}: {why}; written as {value:g}: {reason}", textured[0])
            return True
        entry = material.inputs.get(mapping.keep) if mapping.keep else None
        if not _carriable(entry):
            return False
        result.inputs[mapping.target] = _carried(entry, mapping.target, parameter.type)
        handled.update(textured)
        say(APPROXIMATED, f"{mapping.target}: {why}; {mapping.keep} is kept as it is ({mapping.note or mapping.converted})",
            mapping.keep)
        return True

    # sources a mapping without a condition always writes (glTF's base_color, also the colour a transmission takes
    # when there is one): never "not written" because another mapping's condition is off (the red team's E#11)
    carried_always = {m.sources[0] for m in mappings if m.when is None and m.sources}
    for mapping in mappings:
        current[0] = mapping
        parameter = target_table[mapping.target]
        authored = any(values.authored(s) for s in mapping.sources)
        textured = list(dict.fromkeys(s for s in mapping.sources if not values.is_constant(s)))
        # a textured source the formula ignores here (a metal-only term of a dielectric) leaves it constant
        ignored = {name: probe for name in textured if (probe := probes.ignored_probe(mapping, name, values)) is not None}
        textured = [name for name in textured if name not in ignored]
        if textured and parameter.type == "boolean":  # a flag (uniform in MaterialX) holds no texture: decided
            for name in textured:  # where the textures reach their largest (glTF's thin wall: transmission at all)
                ignored[name] = probes.probe_value(values, name, probes.largest(material.inputs[name].value))
            say(CONVERTED, f"{mapping.target}: a flag, which holds no texture: decided where "
                           f"{', '.join(textured)} reach{'es its' if len(textured) == 1 else ' their'} largest"
                           + (f" ({mapping.converted})" if mapping.converted else ""), textured[0])
            textured = []
        if not textured:
            arrays = [ignored[s] if s in ignored else values.constant(s) for s in mapping.sources]
            if any(a is None for a in arrays):
                continue
            sources_valid = all(inside(a, source_table[s])[1] == "" for a, s in zip(arrays, mapping.sources)
                                if s in source_table)
            if mapping.formula is not None:
                arrays = [working.into(s, a) for s, a in zip(mapping.sources, arrays)]
                for name in working.out_of_gamut(mapping.sources, arrays) if mapping.clips else ():
                    say(APPROXIMATED, f"{name} lies outside linear Rec.709's gamut, where the target is shaded: "
                                      "its formulas see it clipped", name)
            if mapping.when is not None and not mapping.when(*arrays):
                primary = mapping.sources[0]
                if values.authored(primary) and primary in source_table and primary not in handled \
                        and primary not in carried_always \
                        and not _equal(arrays[0], np.asarray(working.into(primary, source_table[primary].default))):
                    handled.add(primary)  # (once, though several mappings read it)
                    current[0] = None  # (the target is not written: nothing is folded into it)
                    say(CONVERTED, f"{primary}: not written (as {mapping.target}): it has no effect with the other "
                                   "inputs at their values", primary)
                continue
            with np.errstate(all="ignore"):  # nan/inf from hostile files propagate quietly, as values
                value = arrays[0] if mapping.formula is None else mapping.formula(*arrays)
            if mapping.formula is not None:
                value = working.out_of(value, parameter, material.inputs.get(mapping.sources[0]))
            if parameter.role in ("normal", "tangent") and not (
                    {material.model, target_model} <= WORLD_SPACE_VECTORS and values.authored(mapping.sources[0])):
                if values.authored(mapping.sources[0]) and not _equal(arrays[0], source_table[mapping.sources[0]].default):
                    say(NOT_CARRIED, f"{mapping.sources[0]}: a constant {parameter.role} is a fixed vector in the "
                                     f"source's space, which {mapping.target} does not hold (the mesh's own is used)",
                        mapping.sources[0])
                continue  # a constant normal is the geometry's own (each model's default means "unperturbed")
            typed = as_value(value, parameter.type)
            plain_copy = mapping.formula is None and values.authored(mapping.sources[0])
            if _equal(typed, parameter.default) and not plain_copy:
                # the target's default already says it (source defaults can differ: then written); an
                # approximation that lands on the default is still one
                if not mapping.exact and _matters(mapping, arrays):
                    say(APPROXIMATED, f"{mapping.target}: {mapping.note}", _site(mapping, values))
                elif mapping.converted_to_default and authored and _changed(arrays[0], value):
                    say(CONVERTED, f"{mapping.target}: {mapping.converted}", mapping.sources[0], True)  # folded elsewhere
                continue
            clamped = ""
            if sources_valid:  # a source already out of range is the validator's to report
                typed, clamped = inside(typed, parameter)
            result.inputs[mapping.target] = _constant_input(material, mapping, typed, parameter.type)
            if clamped:
                say(APPROXIMATED, f"{mapping.target}: {clamped}", mapping.sources[0])
            if not mapping.exact and _matters(mapping, arrays):
                say(APPROXIMATED, f"{mapping.target}: {mapping.note}", _site(mapping, values))
            elif mapping.converted and authored and _changed(arrays[0], value):
                say(CONVERTED, f"{mapping.target}: {mapping.converted}", mapping.sources[0], True)
            continue
        if mapping.when is not None and not probes.needed(mapping, textured, values):
            continue  # not needed whatever the textures hold (an emission colour without luminance)
        source_name = textured[0]
        entry = material.inputs[source_name]
        if _carriable(entry) and len(textured) == 1 and probes.is_identity(mapping, source_name, values):
            carried, done = _carried(entry, mapping.target, parameter.type), None  # rewired as is, but a normal
            if parameter.role == "normal":  # graph between tangent- and world-space normals: re-expressed
                carried, done = normal_graphs.carried_normal(carried, material.model, target_model)
            if done:
                say(CONVERTED if carried is not None else NOT_CARRIED, f"{mapping.target}: {done}", source_name)
            if carried is not None:
                result.inputs[mapping.target] = carried
            handled.add(source_name)
            continue
        if settings.node_graphs and mapping.formula is not None and expressed_module.one_graph(material, textured):
            expressed = expressed_module.express(material, mapping, textured, values, working, parameter, ignored)
            if expressed is not None:
                result.inputs[mapping.target], expression = expressed
                handled.update(textured)
                say(CONVERTED if expression.exact else APPROXIMATED,
                    f"{mapping.target}: {expressed_module.described(expression, textured)}", source_name)
                say_note(mapping, source_name)
                continue
        if settings.baker is not None and mapping.formula is not None:
            try:
                baked = settings.baker.bake(material, mapping, values, parameter.type, f"{label} {mapping.target}",
                                            texturable=_texturable(target_model, mapping.target), ignored=ignored)
            except BakeError as error:
                kept = expressed_module.scaled_texture(material, mapping, textured, values, working, parameter, ignored,
                                                      settings.gltf_file)
                if kept is not None:
                    result.inputs[mapping.target] = kept
                    handled.add(source_name)
                    say(CONVERTED, f"{mapping.target}: the texture is not baked ({error}); it is kept, and the "
                                   "mapping, with the other inputs at their values, becomes its scale and bias "
                                   "(exact: an affine map per channel)", source_name)
                    say_note(mapping, source_name)
                    continue
                if keep_as_is(mapping, parameter, textured, f"cannot be baked ({error})"):
                    continue
                say(NOT_CARRIED, f"{mapping.target} cannot be baked: {error}; the target keeps its default", source_name)
                handled.add(source_name)
                failed.update((name, mapping.target) for name in textured[1:])
                continue
            handled.update(textured)
            if isinstance(baked.input.value, Constant):  # every texel gave the same value
                baked.input.value.value, clamped = inside(baked.input.value.value, parameter)
                if clamped:
                    say(APPROXIMATED, f"{mapping.target}: {clamped}", source_name)
                elif not baked.clipped and _equal(as_value(baked.input.value.value, parameter.type), parameter.default):
                    continue  # the target's default already says it (as for constants above)
            result.inputs[mapping.target] = baked.input
            say(APPROXIMATED if baked.clipped else CONVERTED, baked.message, source_name)
            if not mapping.exact and _matters_on_average(mapping, values, baked.averages):
                say(APPROXIMATED, f"{mapping.target}: {mapping.note}", _site(mapping, values, source_name))
            continue
        if keep_as_is(mapping, parameter, textured, "nothing to bake the formula into"):
            continue
        what = f"texture {entry.value.file!r}" if isinstance(entry.value, Texture) else \
            f"procedural input ({getattr(entry.value, 'category', None) or 'graph'})"
        say(NOT_CARRIED, f"{mapping.target} needs {what} transformed per texel "
                         f"({mapping.note or 'a formula of ' + ', '.join(mapping.sources)}); nothing to bake into "
                         "(a conversion without an output), so the target keeps its default", source_name)
        handled.add(source_name)
        failed.update((name, mapping.target) for name in textured[1:])
    current[0] = None
    folded: list[tuple[str, Diagnostic]] = []

    def fold(rule, message: str, name: str) -> None:
        start = len(report)
        say(rule, message, name)
        folded.append((name, report.pop(start)))

    dropped_lobes = []
    quiet_drops: list[Dropped] = []
    for drop in dropped:
        if not values.authored(drop.source):
            continue
        if lobe_off(drop.source, values, source_table):  # its value is lost, but renders nothing: a note, no error
            if _off_default(drop.source, values, source_table) and settings.unseen_notes:
                say(CONVERTED, f"{drop.source} has no equivalent ({drop.why}), so it is not carried: it has no "
                               f"effect while {source_table.lobe_switch(drop.source)} is 0", drop.source)
                handled.add(drop.source)
            continue
        arrays = [values.constant(s) for s in (drop.source, *drop.needs)]
        if not values.is_constant(drop.source) or drop.matters is None or \
                (all(a is not None for a in arrays) and drop.matters(*arrays)):
            say(NOT_CARRIED, f"{drop.source} has no equivalent: {drop.why}", drop.source)
            handled.add(drop.source)
            dropped_lobes.append(drop.source)
        elif _off_default(drop.source, values, source_table):  # lost, but invisible here: said (as an info) by
            quiet_drops.append(drop)  # unread_notes, once the translator's own notes are in (one may stand there)
    probes.unreached(material, mappings, handled, failed, source_table, say)
    read = {name for mapping in mappings for name in mapping.sources} | {drop.source for drop in dropped}
    for switch in dropped_lobes:  # a lobe dropped whole: its other inputs go with it (fuzz_color with fuzz_weight)
        for name, parameter in source_table.parameters.items():
            if source_table.lobe_switch(name) == switch and name not in read and name not in handled \
                    and values.authored(name) and _off_default(name, values, source_table):
                fold(NOT_CARRIED, f"{name}: not carried: it goes with its lobe ({switch} has no equivalent)", name)
    def shown(name: str | None) -> str:  # where the report shows the note at ``name`` (a hub's: the source's input)
        if not name:
            return "the material"
        at = located_input(material.inputs.get(name), name)
        return settings.hub_sites.get(at, at)

    start = len(folded)
    _companions(noted, mappings, values, source_table, fold, shown, result)
    own.update(id(note) for _, note in folded[start:])
    report.sort(key=Diagnostic.sort_key)
    origins: dict[str, tuple[str, ...]] = {}
    for mapping in mappings:
        origins[mapping.target] = tuple(dict.fromkeys(origins.get(mapping.target, ()) + mapping.sources))
    return Translation(result, report, material, folded, frozenset(read), origins, tuple(quiet_drops), about,
                       frozenset(own))


def unread_notes(translation: Translation, target_model: str, context, unseen: bool = True) -> list[Diagnostic]:
    """A note at each authored source input, off its default, that no mapping of the translator read, no drop
    named and no note of the whole translation stands at (the audit's F1: OpenPBR's transmission_depth, Abbe
    number, coat anisotropy and scatter vanished on their way to UsdPreviewSurface without a word): an error where
    its lobe is on, an info where its lobe's switch is 0 (its value renders nothing; ``unseen`` False: nothing), as
    for a drop whose value renders nothing (``quiet_drops``). Run on a translator's final report (:func:`translate`
    records what it read; a translator that ran none records nothing)."""
    material = translation.source
    if translation.read is None or material is None:
        return []
    table = tables.table_known(material.model, material.version)
    values = Values(material, table)
    sites = {d.location.input for d in translation.diagnostics}
    notes = []
    for drop in translation.quiet_drops if unseen else ():
        entry = material.inputs.get(drop.source)
        where = entry.location if entry is not None and entry.location is not None else \
            material.location.with_input(drop.source)
        if drop.source not in sites and where.input not in sites:
            notes.append(context.diagnostic(CONVERTED, f"{material.name}: {drop.source} has no equivalent ({drop.why}), "
                                            "so it is not carried: it has no effect with the other inputs at their "
                                            "values", where))
            translation.about[id(notes[-1])] = drop.source
    for name in sorted(material.inputs):
        if name in translation.read or name in sites or table.get(name) is None or not values.authored(name) \
                or not _off_default(name, values, table):
            continue
        entry = material.inputs[name]
        where = entry.location if entry.location is not None else material.location.with_input(name)
        if where.input in sites:  # (an input a first step made stands at its source's input: a note is there)
            continue
        if lobe_off(name, values, table):
            if not unseen:
                continue
            notes.append(context.diagnostic(CONVERTED, f"{material.name}: {name} has no equivalent in {target_model}, "
                                            f"so it is not carried: it has no effect while {table.lobe_switch(name)} "
                                            "is 0", where))
        else:
            notes.append(context.diagnostic(NOT_CARRIED, f"{material.name}: {name} has no equivalent in "
                                            f"{target_model}; no mapping reads it, so it is not carried", where))
        translation.about[id(notes[-1])] = name
    return notes


def _companions(noted, mappings, values: Values, source_table, say, shown, result: Material | None = None) -> None:
    """A note at each other source a noted mapping folded in: every authored source off its default that no other
    mapping leads (its own counterpart, which speaks for it) and no note names gets one there, pointing at the
    mapping's most severe note (``coat_affect_roughness`` folded into specular_roughness; a preview's constant
    ``diffuseColor`` baked with a textured ``metallic`` into base_color), so a value that does not survive as itself
    is never without a note at its input (:func:`with_folded_notes` keeps those nothing else names). Info, as the
    loss is reported once at its own note, but for a value not carried at all. A counterpart speaks for its source
    only where it was written (a glass's ``transmission_color`` leads glTF's attenuation colour, which a volume of
    depth 0 does not write: folded into the base colour, it had no note; session 25's audit). The pointer names
    where the report shows that note (``shown``): through the OpenPBR hub, the source's input it was moved to."""
    sites = {name for _, _, name in noted}
    leads = {}
    for mapping in mappings:
        if result is None or mapping.target in result.inputs:
            leads.setdefault(mapping.sources[0], set()).add(id(mapping))
    strongest: dict[int, tuple[Any, Mapping, str | None]] = {}
    for rule, mapping, name in noted:
        held = strongest.get(id(mapping))
        if held is None or rule.severity >= held[0].severity:  # (the last: the mapping's own note, after a gamut note)
            strongest[id(mapping)] = (rule, mapping, name)
    for rule, mapping, name in strongest.values():
        for source in dict.fromkeys(mapping.sources):
            if source in sites or leads.get(source, {id(mapping)}) - {id(mapping)} or source not in source_table \
                    or not values.authored(source):
                continue
            if not _off_default(source, values, source_table):
                continue  # at its default: nothing of it to lose
            sites.add(source)
            how = {NOT_CARRIED: "not carried", APPROXIMATED: "approximated"}.get(rule, "converted")
            say(NOT_CARRIED if rule is NOT_CARRIED else CONVERTED,  # the loss's severity stands at its own note
                f"{source}: folded into {mapping.target} with the other inputs ({how}: see the note at {shown(name)})", source)


def located_input(entry: Input | None, name: str) -> str:
    """The input name a note at ``entry`` (the input ``name``) stands at: its location's (a glTF property,
    ``baseColorFactor``), else ``name``."""
    return entry.location.input if entry is not None and entry.location is not None and entry.location.input else name


def _off_default(name: str, values: Values, source_table) -> bool:
    """Whether ``name`` holds something other than its default: a texture or graph, or another constant."""
    if not values.is_constant(name):
        return True
    value = values.constant(name)
    return value is not None and not _equal(value, source_table[name].default)


def lobe_off(name: str, values: Values, source_table) -> bool:
    """Whether ``name`` belongs to a lobe whose switch (tables.ParameterTable.lobe_switch) is a constant 0 (unset: its
    default)."""
    switch = source_table.lobe_switch(name)
    value = values.constant(switch) if switch is not None and values.is_constant(switch) else None
    return value is not None and not bool(np.any(np.asarray(value) > 0))


def _site(mapping: Mapping, values: Values, textured: str | None = None) -> str:
    """Where an approximation's note stands: the mapping's ``site`` (the source whose loss it describes:
    transmission_weight for UsdPreviewSurface's opacity, not the geometry_opacity that leads its sources) where the
    material authors it, else the first source (the target's counterpart: specular_weight's note at glTF's specular
    even where that is unauthored). For a bake, ``textured``, its texture, stands in for an unauthored first source
    (a sheen's fit at ``sheen``, authored, though its roughness texture is what was baked)."""
    if mapping.site is not None and values.authored(mapping.site):
        return mapping.site
    return mapping.sources[0] if textured is None or values.authored(mapping.sources[0]) else textured


def _at_defaults(mapping: Mapping, values: Values, source_table) -> list:
    """The mapping's sources as constants, a textured or procedural one at its default (``matters`` takes
    constants)."""
    return [values.constant(s) if values.is_constant(s) else np.asarray(source_table[s].default, dtype=np.float64)
            for s in mapping.sources]


def _matters(mapping: Mapping, arrays) -> bool:
    """``mapping.matters`` on constants (always, without one); NaN and infinities from hostile files
    pass quietly, as in the formulas."""
    if mapping.matters is None:
        return True
    with np.errstate(all="ignore"):
        return bool(mapping.matters(*arrays))


def _matters_on_average(mapping: Mapping, values: Values, averages: dict) -> bool:
    """``mapping.matters`` for a baked mapping, judged at the textures' mean values (``matters``
    takes constants); without a ``matters`` an approximation always matters."""
    if mapping.matters is None:
        return True
    arguments = [averages[name] if name in averages else values.constant(name) for name in mapping.sources]
    if any(a is None for a in arguments):
        return True
    try:
        return bool(mapping.matters(*arguments))
    except (TypeError, ValueError):
        return True


def _changed(source, value) -> bool:
    """Whether a formula changed the first source's value (a conversion worth reporting)."""
    source, value = np.asarray(source, dtype=np.float64), np.asarray(value, dtype=np.float64)
    if source.shape != value.shape:
        return True
    return not np.allclose(source, value, rtol=1e-9, atol=1e-12, equal_nan=True)


def _carriable(entry) -> bool:
    """A texture, or a procedural graph the reader captured (a .mtlx writer rebuilds it): carried as is."""
    return entry is not None and (isinstance(entry.value, Texture) or
                                  (isinstance(entry.value, Connection) and bool(entry.value.graph_xml)))


def _carried(entry: Input, name: str, type_name: str) -> Input:
    carried = copy.deepcopy(entry)
    carried.name, carried.type = name, type_name
    return carried


def _texturable(model: str, name: str) -> bool:
    """Whether the target model can take a texture on ``name`` (glTF has factor-only parameters)."""
    if model != "gltf_pbr":
        return True
    slot = SLOT_BY_PARAMETER.get(name)
    return slot is None or slot.texture is not None


def _constant_input(material: Material, mapping: Mapping, value, type_name: str) -> Input:
    source = material.inputs.get(mapping.sources[0])
    location = source.location if source is not None else material.location.with_input(mapping.target)
    return Input(
        mapping.target, type_name, Constant(value), location,
        colorspace=source.colorspace if source is not None else material.colorspace,
        unit=source.unit if source is not None and source.unit else None,
        unittype=source.unittype if source is not None and source.unittype else None,
    )


def differs(value, reference) -> bool:
    return not np.allclose(np.asarray(value, dtype=np.float64), reference, atol=1e-6)

