"""Accessor data: the few vertex values the glTF rules need, read through the document's buffers.

glTF 2.0, 3.6.2 Accessors: an accessor's elements start ``byteOffset`` bytes into its bufferView and lie
``byteStride`` bytes apart (the element's own size when the view has no stride); a FLOAT component is a
little-endian IEEE 754 single, a normalised SHORT ``max(c / 32767, -1)`` and a normalised BYTE
``max(c / 127, -1)`` (3.11, the ``KHR_mesh_quantization`` formats). An accessor without a bufferView is
zeros, and a sparse one replaces some of them; neither is read here (the caller then knows nothing).

What is read: a TANGENT's w (:func:`tangent_signs`), and for a primitive with a material (:func:`primitive_problems`)
its POSITION, NORMAL, TANGENT, TEXCOORD_n and COLOR_n values (finite? NORMAL and TANGENT xyz of unit length?) and
its indices (below the vertex count?); :mod:`.geometry` reads whole attributes (:func:`vectors`) and triangle
indices (:func:`indices`).

Cost is bounded: at most :data:`MAX_ELEMENTS` elements of one accessor are read, as one strided NumPy
view of the buffer (no copy of the buffer, no Python loop over vertices).
"""

from __future__ import annotations

import math

from .document import GltfDocument, ResourceError
from .textures import json_float, json_index, json_numbers

#: The elements of one accessor read at most (a 64 MiB buffer holds about four million VEC4 floats).
MAX_ELEMENTS = 1 << 22

SIGN_TOLERANCE = 1e-5  # a TANGENT w further than this from +1 or -1 is no sign (float32 rounding aside)
#: A NORMAL or TANGENT xyz whose length is further than this from 1 is no unit vector: the Khronos glTF-Validator's
#: threshold (ACCESSOR_VECTOR3_NON_UNIT), loose enough for normals quantised to bytes (KHR_mesh_quantization).
UNIT_TOLERANCE = 0.00674
#: The vertex attributes whose values a material's look depends on, read for NaN and infinity (glTF 2.0, 3.6.2.2:
#: "Values of NaN, +Infinity, and -Infinity MUST NOT be present"); skinning weights and joints are not the material's.
MATERIAL_ATTRIBUTES = ("POSITION", "NORMAL", "TANGENT", "TEXCOORD_", "COLOR_")

_COMPONENTS = {"SCALAR": 1, "VEC2": 2, "VEC3": 3, "VEC4": 4}
_FORMATS = {5126: ("<f4", None), 5122: ("<i2", 32767.0), 5120: ("i1", 127.0)}  # dtype, normalisation divisor
_FLOATS = {5126: ("<f4", None)}
_INDICES = {5121: ("u1", None), 5123: ("<u2", None), 5125: ("<u4", None)}  # 3.7.2.1: indices are unsigned integers
#: FLOAT, and the normalised integers glTF 2.0 (3.11) maps to [0, 1] (unsigned: ``c / 255``, ``c / 65535``, COLOR_n and
#: TEXCOORD_n) or [-1, 1] (signed, the KHR_mesh_quantization formats): every attribute format whose values are fractions.
_FRACTIONS = {**_FORMATS, 5121: ("u1", 255.0), 5123: ("<u2", 65535.0)}


def component(document: GltfDocument, index, which: int):
    """The ``which``-th component of every element (up to :data:`MAX_ELEMENTS`) of accessor ``index`` as a
    float64 NumPy array, dequantised when the accessor is normalised; ``None`` when it cannot be read
    (no such accessor, no bufferView, sparse, a format other than FLOAT or normalised (SHORT, BYTE), a
    view or buffer that cannot be loaded or is too short: those are other rules' findings)."""
    found = _elements(document, index, _FORMATS)
    if found is None or not 0 <= which < found[0].shape[1]:
        return None
    values, divisor = found[0][:, which].astype("float64"), found[1]
    return values if divisor is None else _dequantised(values, divisor)


def vectors(document: GltfDocument, index):
    """Every element (up to :data:`MAX_ELEMENTS`) of accessor ``index`` as a float64 ``(count, width)`` NumPy array,
    dequantised when it is a normalised integer accessor; ``None`` when it cannot be read so (as :func:`component`;
    unnormalised integers too, whose meaning depends on KHR_mesh_quantization's node transform)."""
    found = _elements(document, index, _FRACTIONS)
    if found is None:
        return None
    values = found[0].astype("float64")
    return values if found[1] is None else _dequantised(values, found[1])


def indices(document: GltfDocument, index):
    """The vertex indices of accessor ``index`` (up to :data:`MAX_ELEMENTS`) as an int64 array, ``None`` unreadable."""
    found = _elements(document, index, _INDICES)
    return None if found is None else found[0][:, 0].astype("int64")


def _dequantised(values, divisor: float):
    import numpy  # lazy: only reached once NumPy has read the data

    return numpy.maximum(values / divisor, -1.0)


def _elements(document: GltfDocument, index, formats: dict):
    """``(elements, divisor)``: the first :data:`MAX_ELEMENTS` elements of accessor ``index`` as a strided
    ``(count, width)`` NumPy view of its buffer in their stored type, and the normalisation divisor of its
    format in ``formats`` (``componentType`` -> (dtype, divisor or ``None``); a divisor asks for
    ``normalized: true``); ``None`` when the accessor cannot be read so (see :func:`component`)."""
    accessor = document.item("accessors", index)
    if accessor is None or "sparse" in accessor or "bufferView" not in accessor:
        return None
    kind, component_type, count = accessor.get("type"), accessor.get("componentType"), accessor.get("count")
    width = _COMPONENTS.get(kind) if isinstance(kind, str) else None
    found = formats.get(component_type) if isinstance(component_type, int) and not isinstance(component_type, bool) else None
    offset = accessor.get("byteOffset", 0)
    if width is None or found is None or not json_index(count) or not json_index(offset):
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
    stride = view.get("byteStride") if isinstance(view, dict) and json_index(view.get("byteStride")) else width * size
    count = min(count, MAX_ELEMENTS)
    if count == 0 or offset + (count - 1) * stride + width * size > len(data):
        return None
    return numpy.ndarray((count, width), dtype=dtype, buffer=data, offset=offset, strides=(stride, size)), divisor


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


def primitive_problems(document: GltfDocument, pointer: str, primitive: dict, cache: dict) -> list[dict]:
    """What the data of one mesh primitive holds that glTF forbids, as the layout facts are written
    (:func:`.layout.accessor_problems`: ``{"kind", "pointer", "property", ...}``): ``non_finite`` (a NaN or infinite
    float in a :data:`MATERIAL_ATTRIBUTES` accessor, at the accessor; a TANGENT's w is :func:`tangent_signs`'),
    ``non_unit`` (a NORMAL or TANGENT xyz not of unit length, at the attribute), ``non_clamped`` (a float COLOR_n
    outside [0, 1], at the attribute) and ``index_out_of_range`` (an index
    not below the vertex count, 3.7.2.1, at ``indices``). Each accessor's values are judged once (``cache``, by
    accessor; the indices by accessor and vertex count), and at most :data:`MAX_ELEMENTS` elements of each are read."""
    attributes = primitive.get("attributes") if isinstance(primitive.get("attributes"), dict) else {}
    found: list[dict] = []
    for name, index in attributes.items():
        if not name.startswith(MATERIAL_ATTRIBUTES) or not json_index(index) or (index, name) in cache:
            continue
        cache[(index, name)] = True
        found.extend(_vertex_values(document, index, name, f"{pointer}/attributes", cache))
    indices = primitive.get("indices")
    reference = attributes.get("POSITION", next(iter(attributes.values()), None))
    vertices = (document.item("accessors", reference) or {}).get("count")
    if json_index(indices) and json_index(vertices) and ("indices", indices, vertices) not in cache:
        cache[("indices", indices, vertices)] = True
        found.extend(_index_range(document, indices, vertices, pointer))
    return found


def _vertex_values(document: GltfDocument, index, name: str, where: str, cache: dict):
    import numpy  # lazy: NumPy (~60 ms) only for a file with mesh data

    unit = 3 if name in ("NORMAL", "TANGENT") else 0  # the xyz a unit vector
    values = _elements(document, index, _FLOATS)
    if values is not None and ("non_finite", index) not in cache:
        cache[("non_finite", index)] = True  # (an accessor two attributes share is read for NaN once)
        judged = values[0][:, :3] if name == "TANGENT" else values[0]
        bad = ~numpy.isfinite(judged).all(axis=1)
        if bad.any():
            first = int(bad.argmax())
            yield {"kind": "non_finite", "pointer": f"/accessors/{index}", "property": None, "accessor": index,
                   "attribute": name, "count": int(bad.sum()), "checked": _checked(document, index, bad.size), "first": first,
                   "value": float(judged[first][~numpy.isfinite(judged[first])][0])}
    if values is not None and name.startswith("COLOR_"):  # a multiplier of the base colour: [0, 1] (3.7.2.1)
        with numpy.errstate(invalid="ignore"):
            bad = numpy.isfinite(values[0]).all(axis=1) & ((values[0] < 0.0) | (values[0] > 1.0)).any(axis=1)
        if bad.any():
            first = int(bad.argmax())
            yield {"kind": "non_clamped", "pointer": where, "property": name, "accessor": index, "attribute": name,
                   "count": int(bad.sum()), "checked": _checked(document, index, bad.size), "first": first,
                   "value": [float(v) for v in values[0][first]]}
    if not unit:
        return
    found = _elements(document, index, _FORMATS)
    if found is None:
        return
    xyz = found[0][:, :unit].astype(numpy.float64)
    xyz = xyz if found[1] is None else _dequantised(xyz, found[1])
    with numpy.errstate(invalid="ignore", over="ignore"):
        length = numpy.sqrt((xyz * xyz).sum(axis=1))
    bad = numpy.isfinite(length) & (numpy.abs(length - 1.0) > UNIT_TOLERANCE)  # (NaN is non_finite's)
    if bad.any():
        first = int(bad.argmax())
        yield {"kind": "non_unit", "pointer": where, "property": name, "accessor": index, "attribute": name,
               "count": int(bad.sum()), "checked": _checked(document, index, bad.size), "first": first,
               "length": float(length[first])}


def _index_range(document: GltfDocument, index, vertices: int, pointer: str):
    found = _elements(document, index, _INDICES)
    if found is None:
        return
    values = found[0][:, 0]
    beyond = values >= vertices
    if beyond.any():
        first = int(beyond.argmax())
        yield {"kind": "index_out_of_range", "pointer": pointer, "property": "indices", "accessor": index,
               "count": int(beyond.sum()), "checked": _checked(document, index, values.size), "first": first,
               "value": int(values[first]), "vertices": vertices}


def _checked(document: GltfDocument, index: int, read: int) -> str:
    """How many elements of accessor ``index`` were judged, for a message: all of them, or the first ``read``."""
    count = document.item("accessors", index)["count"]
    return str(read) if read >= count else f"the first {read} (of {count})"
