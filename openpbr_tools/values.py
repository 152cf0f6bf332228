"""Strict parsing and formatting of MaterialX value strings.

MaterialX's own parser reads ``"1,5"`` for a float as 1.0 and ignores trailing text; a validator
cannot. These functions accept exactly the MaterialX 1.39 value syntax for each type and say
precisely what is wrong otherwise.
"""

from __future__ import annotations

import math
import re

COMPONENTS = {
    "float": 1,
    "integer": 1,
    "boolean": 1,
    "color3": 3,
    "color4": 4,
    "vector2": 2,
    "vector3": 3,
    "vector4": 4,
}
STRING_TYPES = ("string", "filename")


#: The largest finite IEEE 754 single-precision float: MaterialX stores float values as 32-bit floats, and a
#: string beyond it fails to convert (std::stof: out of range), so validate() says 'Invalid value'.
FLOAT32_MAX = 3.4028234663852886e38


class ValueSyntaxError(ValueError):
    """A value string that does not parse as its declared type."""


def parse_value(text: str, type_name: str):
    """Parse ``text`` as a MaterialX value of ``type_name``.

    Returns a float, int, bool, str or a tuple of floats. Raises :class:`ValueSyntaxError` with a
    message naming the problem. Non-finite numbers (``nan``, ``inf``) parse; judging them is a rule's job.
    """
    if type_name in STRING_TYPES:
        return text
    count = COMPONENTS.get(type_name)
    if count is None:
        raise ValueSyntaxError(f"values of type {type_name!r} cannot be checked")
    stripped = text.strip()
    if not stripped:
        raise ValueSyntaxError(f"empty value for a {type_name}")
    if type_name == "boolean":
        if stripped in ("true", "false"):
            return stripped == "true"
        raise ValueSyntaxError(f"{text!r} is not a boolean (expected 'true' or 'false')")
    # MaterialX splits a vector on commas and spaces alike, dropping empty pieces (Types.cpp: splitString with
    # ARRAY_VALID_SEPARATORS ", "): "1 0 1" and "1, 0, 1" are both a color3; a scalar is read up to its first
    # separator, so "0,5" reads 0 (the decimal comma this reports)
    parts = [p for p in re.split(r"[,\s]+", stripped) if p] if count > 1 else [p.strip() for p in stripped.split(",")]
    if len(parts) != count:
        if count == 1:
            raise ValueSyntaxError(
                f"{text!r} is not a single {type_name}: MaterialX separates components with commas, "
                f"so this reads as {len(parts)} values (a decimal comma?)"
            )
        raise ValueSyntaxError(f"{text!r} has {len(parts)} components; a {type_name} has {count}")
    if type_name == "integer":
        try:
            return int(parts[0])
        except ValueError:
            raise ValueSyntaxError(f"{text!r} is not an integer") from None
    numbers = []
    for part in parts:
        try:
            numbers.append(float(part))
        except ValueError:
            raise ValueSyntaxError(f"{part!r} in {text!r} is not a number") from None
        if math.isfinite(numbers[-1]) and abs(numbers[-1]) > FLOAT32_MAX:  # (nan and inf as written parse)
            raise ValueSyntaxError(f"{part!r}{'' if count == 1 else f' in {text!r}'} is beyond a 32-bit float (at most {FLOAT32_MAX:.7g}), which "
                                   "MaterialX's values are: it reads no value (validate(): 'Invalid value')")
    return numbers[0] if count == 1 else tuple(numbers)


def is_finite(value) -> bool:
    if isinstance(value, bool) or value is None or isinstance(value, str):
        return True
    if isinstance(value, (int, float)):
        return math.isfinite(value)
    return all(math.isfinite(v) for v in value)


def format_value(value, type_name: str) -> str:
    """The MaterialX text of a value: shortest round-tripping decimal, ``", "`` between components."""
    if type_name in STRING_TYPES:
        return str(value)
    if type_name == "boolean":
        return "true" if value else "false"
    if type_name == "integer":
        return str(int(value))
    if isinstance(value, (tuple, list)):
        return ", ".join(_number(v) for v in value)
    return _number(value)


def _number(v: float) -> str:
    v = float(v)
    if math.isfinite(v) and abs(v) < 1e15 and v == int(v):  # nan and inf (from hostile files) stay as written
        return f"{int(v)}" if v != 0 else "0"
    return repr(v)
