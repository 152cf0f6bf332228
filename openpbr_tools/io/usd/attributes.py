"""USD attribute values as the toolkit's model holds them: plain Python, read once.

A value comes back as a float, int, bool, string or flat tuple of numbers (vectors, matrices and
arrays of them flattened, as MaterialX writes them); single-precision floats as the shortest decimal
that is the same float32; an attribute with only time samples gives its first sample. Shared by the
connection walk (:mod:`.network`) and the texture-node interpretation (:mod:`.texture_nodes`).
"""

from __future__ import annotations

import math
import struct

from ...model import Constant
from ...values import COMPONENTS
from .types import USD_TO_MATERIALX


def unconnected(attribute) -> bool:
    """An authored input with a value of its own (a constant operand), not a connection."""
    return bool(attribute) and not attribute.GetConnections()


def value_shape(usd_type: str | None) -> tuple:
    """What must match for a connection to carry values unchanged: component count and kind
    (number, integer, boolean, text); roles (color3f vs float3) and precision do not matter."""
    materialx = USD_TO_MATERIALX.get(usd_type or "", usd_type)
    kind = "text" if materialx in ("string", "filename") else materialx if materialx in ("boolean", "integer") else "number"
    return COMPONENTS.get(materialx or ""), kind


def read_constant(attribute):
    """The attribute's value as a :class:`Constant`, or ``None`` when it has none."""
    if attribute is None:
        return None
    value = attribute.Get()
    if value is None:
        if not attribute.GetNumTimeSamples():
            return None
        from pxr import Usd  # lazy: pxr (0.1-0.2 s) only once the reader has required it and opened a stage

        value = attribute.Get(Usd.TimeCode.EarliestTime())  # the first sample, without listing them all
    return Constant(python_value(value, single_precision(attribute.GetTypeName())))


#: Time samples of an animated input checked against its range (a longer animation: its first ones)
MAX_SAMPLES = 10000


def read_constant_at(attribute, time: float):
    """The attribute's value at the time sample ``time``, as Python numbers (None when there is none)."""
    value = attribute.Get(time)
    return None if value is None else python_value(value, single_precision(attribute.GetTypeName()))


def single_precision(type_name) -> bool:
    """Whether an Sdf value type holds single- (or half-) precision floats (float, color3f, half3)."""
    scalar = str(type_name.scalarType)
    return scalar.startswith(("float", "half")) or scalar.endswith(("f", "h"))


def constant_of(prim, input_name: str):
    attribute = prim.GetAttribute(f"inputs:{input_name}")
    if not attribute:
        return None
    constant = read_constant(attribute)
    return constant.value if constant is not None else None


#: Array values longer than this are summarised, not converted (no OpenPBR input is an array).
MAX_ARRAY_VALUES = 64


def python_value(value, single_precision: bool):
    """A pxr value as plain Python: float, int, bool, str, or a flat tuple of numbers (vectors,
    matrices and arrays of them flattened, as MaterialX writes them). Single-precision floats come
    back as the shortest decimal that is the same float32 (0.8, not 0.800000011920929); arrays of
    text are joined with ", "; arrays longer than :data:`MAX_ARRAY_VALUES` are summarised."""
    if isinstance(value, bool):
        return value
    if isinstance(value, float):
        return shortest_float32(value) if single_precision else value
    if isinstance(value, int):
        return value
    if isinstance(value, str):
        return value
    path = getattr(value, "path", None)
    if isinstance(path, str):
        return path
    try:
        count = len(value)
    except TypeError:
        count = None
    if count is not None and count > MAX_ARRAY_VALUES:
        return f"({count} values)"
    try:
        items = list(value)
    except TypeError:
        return str(value)
    flat = []
    for item in items:
        converted = python_value(item, single_precision)
        if isinstance(converted, tuple):
            flat.extend(converted)
        else:
            flat.append(converted)
    if any(isinstance(item, str) for item in flat):
        return ", ".join(str(item) for item in flat)
    return tuple(flat)


_FLOAT32 = struct.Struct("f")


def shortest_float32(x: float) -> float:
    if not math.isfinite(x):
        return x
    try:
        target = _FLOAT32.unpack(_FLOAT32.pack(x))[0]
    except OverflowError:
        return x
    for digits in range(6, 10):
        candidate = float(f"{target:.{digits}g}")
        if _FLOAT32.unpack(_FLOAT32.pack(candidate))[0] == target:
            return candidate
    return target


def input_name(attribute) -> str:
    name = str(attribute.GetName())
    return name.removeprefix("inputs:")
