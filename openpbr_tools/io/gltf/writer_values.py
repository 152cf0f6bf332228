"""Python values as glTF JSON values, for the material writer and its draft mixin."""

from __future__ import annotations

import math


def finite(value) -> bool:
    """Whether every component of a constant is a finite number (glTF has no NaN or infinity)."""
    values = value if isinstance(value, tuple) else (value,)
    return all(isinstance(v, (int, float)) and math.isfinite(v) for v in values)


def json_value(value):
    """A constant as JSON: tuples become lists of floats, numbers floats, booleans stay."""
    if isinstance(value, tuple):
        return [float(v) for v in value]
    if isinstance(value, bool):
        return value
    return float(value) if isinstance(value, (int, float)) else value


def json_finite(value) -> bool:
    """Whether a JSON value (from a source file, possibly hostile) holds only finite numbers."""
    if isinstance(value, float):
        return math.isfinite(value)
    if isinstance(value, dict):
        return all(json_finite(v) for v in value.values())
    if isinstance(value, list):
        return all(json_finite(v) for v in value)
    return True


def clamp(value, lows, highs):
    """``value`` (a number or a list of them) inside per-component bounds ``lows``/``highs`` (a
    ``None`` bound is open); the same shape back."""
    values = value if isinstance(value, list) else [value]
    fixed = []
    for v, low, high in zip(values, lows, highs):
        v = v if low is None else max(v, low)
        fixed.append(v if high is None else min(v, high))
    return fixed if isinstance(value, list) else fixed[0]
