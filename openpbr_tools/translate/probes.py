"""What a mapping's formula does with a textured or procedural source, found by evaluating it on probe
values (the other sources at their constants): whether it ignores the source (a metal-only term of a
dielectric: nothing to bake) or passes it through unchanged (then the texture or graph is rewired as
is); and, after the mappings, what became of a texture or graph none of them carried
(:func:`unreached`). Used by :func:`.common.translate`."""

from __future__ import annotations

import numpy as np

from ..model import Connection, Texture
from ..rules.translation import CONVERTED, NOT_CARRIED


def probe_value(values, name: str, level: float):
    """``level`` in every component of ``name``'s value (a colour or vector three, else one)."""
    width = _width(values, name)
    return np.full(width, level) if width > 1 else np.asarray(level)


def largest(value) -> float:
    """The largest number a textured or procedural ``value`` can give: a texture's scale plus bias at a texel of 1 (or
    of 0, for a negative scale), a graph's 1."""
    if isinstance(value, Texture):
        scale = np.atleast_1d(np.asarray(value.scale if value.scale is not None else 1.0, dtype=float))
        bias = np.atleast_1d(np.asarray(value.bias if value.bias is not None else 0.0, dtype=float))
        return float(np.max(np.maximum(scale, 0.0) + bias))
    return 1.0


#: Unequal components, probed besides the greys for a colour or vector: a formula can treat a grey
#: specially (a glTF emissive normalised by its largest component is white for every grey).
UNEQUAL = ((0.2, 0.5, 0.9), (0.9, 0.1, 0.4))


def probe_values(values, name: str, levels: tuple[float, ...]) -> list[np.ndarray]:
    """:func:`probe_value` at each of ``levels``, and for a colour or vector the :data:`UNEQUAL` ones."""
    greys = [probe_value(values, name, level) for level in levels]
    return greys + ([np.asarray(u) for u in UNEQUAL] if _width(values, name) == 3 else [])


def _width(values, name: str) -> int:
    parameter = values.table.get(name)
    return 3 if parameter is not None and parameter.type in ("color3", "vector3") else 1


def ignored_probe(mapping, textured: str, values):
    """A probe value of ``textured`` when ``mapping``'s formula, with every constant source at its
    value, gives the same result whatever ``textured`` is (then nothing needs baking); else ``None``.
    Other textured sources are held at each of a few probe values in turn (a procedural roughness
    beside a procedural colour: the dielectric's diffuse colour does not read the roughness)."""
    if mapping.formula is None or len(set(mapping.sources)) == 1:
        return None
    others = {name: values.constant(name) for name in mapping.sources if name != textured}
    varying = [name for name, value in others.items() if value is None and not values.is_constant(name)]
    if any(v is None for name, v in others.items() if name not in varying):
        return None
    for held in ((0.3,), (0.3, 0.8))[bool(varying)]:
        fixed = dict(others, **{name: probe_value(values, name, held) for name in varying})
        results = []
        for probe in probe_values(values, textured, (0.0, 0.3, 0.55, 1.0)):
            arguments = [probe if name == textured else fixed[name] for name in mapping.sources]
            with np.errstate(all="ignore"):
                results.append(np.asarray(mapping.formula(*arguments), dtype=np.float64))
        if not all(r.shape == results[0].shape and np.allclose(r, results[0], atol=1e-12) for r in results[1:]):
            return None
    return probe_value(values, textured, 0.55)


def needed(mapping, textured: list[str], values) -> bool:
    """``mapping.when`` with the textured sources at probe values (0, 0.3, 1) and the others at their
    constants: whether the target needs the value for some texel. A glTF emissive colour is not written
    without emission (``emission_luminance`` 0) whatever a textured coat colour holds."""
    constants = {name: values.constant(name) for name in mapping.sources if name not in textured}
    if any(v is None for v in constants.values()):
        return True
    for level in (0.0, 0.3, 1.0):
        arguments = [probe_value(values, name, level) if name in textured else constants[name] for name in mapping.sources]
        try:
            with np.errstate(all="ignore"):
                if bool(np.any(mapping.when(*arguments))):
                    return True
        except (TypeError, ValueError):
            return True
    return False


def is_identity(mapping, textured: str, values) -> bool:
    """Whether ``mapping``, with its other sources at their constant values, copies ``textured``:
    then a texture passes through unchanged. Checked by evaluating the formula on probe values."""
    if mapping.formula is None:
        return len(mapping.sources) == 1
    others = {name: values.constant(name) for name in mapping.sources if name != textured}
    if any(v is None for v in others.values()):
        return False
    for sample in probe_values(values, textured, (0.0, 0.2, 0.55, 1.0)):
        arguments = [sample if name == textured else others[name] for name in mapping.sources]
        with np.errstate(all="ignore"):
            produced = np.asarray(mapping.formula(*arguments), dtype=np.float64)
        if produced.shape != sample.shape or not np.allclose(produced, sample, atol=1e-9):
            return False
    return True


def unreached(material, mappings, handled: set[str], failed: dict[str, str], source_table, say) -> None:
    """A texture or procedural graph that no mapping carried and nothing reported at its input: one a
    target needed but could not take (reported at another of its sources) is not carried (OPBR1104);
    where mappings read it and ignore it (a metal's edge colour on a dielectric, a rotation without
    anisotropy), it has no effect with the other inputs at their values (OPBR1102, so the graph is not
    gone unnoticed); where none reads it, it is not carried (OPBR1104)."""
    read = {name for mapping in mappings for name in mapping.sources}
    for name in sorted(material.inputs):
        value = material.inputs[name].value
        if name in handled or name not in source_table or not isinstance(value, (Texture, Connection)):
            continue
        what = "texture" if isinstance(value, Texture) else "procedural graph"
        if name in failed:
            say(NOT_CARRIED, f"{name}: its {what} is not carried: {failed[name]}, which reads it, could not be "
                             "written from it (reported with the input it failed on)", name)
        elif name in read:
            say(CONVERTED, f"{name}: its {what} is not carried: with the other inputs at their values it has no "
                           "effect on the result", name)
        else:
            say(NOT_CARRIED, f"{name}: its {what} is not carried (no input of the target takes it)", name)
