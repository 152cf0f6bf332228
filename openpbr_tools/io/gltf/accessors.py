"""Accessor data: the few vertex values the glTF rules need, read through the document's buffers.

glTF 2.0, 3.6.2 Accessors: an accessor's elements start ``byteOffset`` bytes into its bufferView and lie
``byteStride`` bytes apart (the element's own size when the view has no stride); a FLOAT component is a
little-endian IEEE 754 single, a normalised SHORT ``max(c / 32767, -1)`` and a normalised BYTE
``max(c / 127, -1)`` (3.11, the ``KHR_mesh_quantization`` formats). An accessor without a bufferView is
zeros, and a sparse one replaces some of them; neither is read here (the caller then knows nothing).

Cost is bounded: at most :data:`MAX_ELEMENTS` elements of one accessor are read, as one strided NumPy
view of the buffer (no copy of the buffer, no Python loop over vertices).
"""

from __future__ import annotations

import math

from .document import GltfDocument, ResourceError
from .textures import json_float, json_numbers

#: The elements of one accessor read at most (a 64 MiB buffer holds about four million VEC4 floats).
MAX_ELEMENTS = 1 << 22

SIGN_TOLERANCE = 1e-5  # a TANGENT w further than this from +1 or -1 is no sign (float32 rounding aside)

_COMPONENTS = {"SCALAR": 1, "VEC2": 2, "VEC3": 3, "VEC4": 4}
_FORMATS = {5126: ("<f4", None), 5122: ("<i2", 32767.0), 5120: ("i1", 127.0)}  # dtype, normalisation divisor


def component(document: GltfDocument, index, which: int):
    """The ``which``-th component of every element (up to :data:`MAX_ELEMENTS`) of accessor ``index`` as a
    float64 NumPy array, dequantised when the accessor is normalised; ``None`` when it cannot be read
    (no such accessor, no bufferView, sparse, a format other than FLOAT or normalised (SHORT, BYTE), a
    view or buffer that cannot be loaded or is too short: those are other rules' findings)."""
    accessor = document.item("accessors", index)
    if accessor is None or "sparse" in accessor or "bufferView" not in accessor:
        return None
    kind, component_type, count = accessor.get("type"), accessor.get("componentType"), accessor.get("count")
    width = _COMPONENTS.get(kind) if isinstance(kind, str) else None
    found = _FORMATS.get(component_type) if isinstance(component_type, int) and not isinstance(component_type, bool) else None
    offset = accessor.get("byteOffset", 0)
    if width is None or found is None or not 0 <= which < width or not _natural(count) or not _natural(offset):
        return None
    dtype, divisor = found
    if divisor is not None and accessor.get("normalized") is not True:
        return None
    view = document.item("bufferViews", accessor["bufferView"])
    try:
        data = document.buffer_view(accessor["bufferView"])
    except ResourceError:
        return None
    import numpy  # lazy: NumPy (~60 ms) only for a file whose mesh a rule reads

    size = numpy.dtype(dtype).itemsize
    stride = view.get("byteStride") if isinstance(view, dict) and _natural(view.get("byteStride")) else width * size
    count = min(count, MAX_ELEMENTS)
    start = offset + which * size
    if count == 0 or start + (count - 1) * stride + size > len(data):
        return None
    values = numpy.ndarray((count,), dtype=dtype, buffer=data, offset=start, strides=(stride,)).astype(numpy.float64)
    return values if divisor is None else numpy.maximum(values / divisor, -1.0)


def position_extent(document: GltfDocument, index) -> float | None:
    """The largest side of the bounding box of POSITION accessor ``index``, from its ``min`` and ``max``
    (which glTF requires of POSITION, 3.7.2.1; no data is read), or ``None`` when they are missing or malformed."""
    accessor = document.item("accessors", index)
    low, high = (accessor.get("min"), accessor.get("max")) if accessor is not None else (None, None)
    if not (json_numbers(low, 3) and json_numbers(high, 3)):
        return None
    sides = [json_float(b) - json_float(a) for a, b in zip(low, high)]
    return max(sides) if all(math.isfinite(side) for side in sides) else None


def tangent_signs(document: GltfDocument, index, cache: dict) -> dict | None:
    """``{"accessor", "checked", "invalid", "value"}``: how many w components of TANGENT accessor ``index`` were
    read (:func:`component`, bounded) and how many are not +1 or -1 (NaN included), with the first such value;
    ``None`` when the data cannot be read. ``cache`` keeps each accessor's answer (primitives share accessors)."""
    if isinstance(index, bool) or not isinstance(index, int):
        return None
    if index not in cache:
        signs = component(document, index, 3)
        bad = None if signs is None else (abs(abs(signs) - 1.0) > SIGN_TOLERANCE) | (signs != signs)
        cache[index] = None if bad is None else {
            "accessor": index, "checked": int(signs.size), "invalid": int(bad.sum()),
            "value": float(signs[bad.argmax()]) if bad.any() else None}
    return cache[index]


def _natural(value) -> bool:
    return isinstance(value, int) and not isinstance(value, bool) and value >= 0
