"""KHR_texture_transform <-> :class:`~openpbr_tools.model.UVTransform` (MaterialX ``place2d``).

The two conventions differ in three ways, all accounted for here:

* **Origin and V direction.** glTF UV space has its origin at the image's top-left corner with V
  pointing down (specification 3.8.4.4: "the origin of the UV coordinates (0, 0) corresponds to the
  upper left corner of a texture image"); MaterialX's has it bottom-left with V up. A consumer
  flips V (``v_mx = 1 - v_gltf``) on the mesh's coordinates and the image reads the same texel.
* **Direction of the transform.** glTF transforms the coordinates forwards:
  ``uv' = T(offset) R(rotation) S(scale) uv``; ``place2d`` (operation order 0, SRT) computes
  ``uv' = R_mx(rotate) (uv - pivot) / scale - offset + pivot``: scale divides, offset subtracts.
* **Rotation sense.** glTF's rotation matrix, as every implementation and the extension's own
  example apply it (KhronosGroup/glTF issue #1563: the GLSL listing in the README is the transposed
  matrix), is ``[[cos, sin], [-sin, cos]]`` in glTF's V-down space. MaterialX's ``rotate2d`` (and so
  ``place2d``) turns ``(x, y)`` into ``(c x + s y, -s x + c y)`` with the angle in degrees.

Conjugating glTF's map by the V flip ``F(u, v) = (u, 1 - v)`` gives, in MaterialX space,
``uv' = R(θ) S (uv - (0, 1)) + (0, 1) + (offset_u, -offset_v)``, which is ``place2d`` with
``pivot = (0, 1)``, ``scale = 1 / S``, ``rotate = -degrees(θ)`` and ``offset = (-offset_u, offset_v)``:
exactly the parameters MaterialX's own ``gltf_image`` node (``libraries/bxdf/gltf_pbr.mtlx``) feeds
its ``place2d``. The conversion is exact both ways except where a glTF scale component is 0 (the
image collapses to a line; ``place2d`` cannot divide by 0).
"""

from __future__ import annotations

import math

from ...model import UVTransform

GLTF_PIVOT = (0.0, 1.0)


def from_texture_transform(offset=(0.0, 0.0), rotation: float = 0.0, scale=(1.0, 1.0)) -> UVTransform:
    """The ``place2d`` parameters equivalent to a KHR_texture_transform (see the module docstring)."""
    if scale[0] == 0 or scale[1] == 0:
        raise ZeroDivisionError("a KHR_texture_transform scale of 0 has no place2d equivalent")
    return UVTransform(
        scale=(1.0 / scale[0], 1.0 / scale[1]),
        rotate=_clean(-math.degrees(rotation)),
        offset=(_clean(-offset[0]), _clean(offset[1])),
        pivot=GLTF_PIVOT,
    )


def to_texture_transform(uv: UVTransform) -> tuple[tuple[float, float], float, tuple[float, float]]:
    """(offset, rotation in radians, scale) of the KHR_texture_transform equal to ``uv``, for any pivot.

    With ``M = R_mx(rotate) diag(1/scale)``, place2d maps ``y`` to ``M y + p - offset - M p``; glTF's
    map in MaterialX space is ``M y + c + (o_u, -o_v) - M c`` with ``c = (0, 1)``, so
    ``(o_u, -o_v) = (p - c) - M (p - c) - offset``.
    """
    if uv.scale[0] == 0 or uv.scale[1] == 0:
        raise ZeroDivisionError("a place2d scale of 0 has no KHR_texture_transform equivalent")
    theta = math.radians(-uv.rotate)
    scale = (1.0 / uv.scale[0], 1.0 / uv.scale[1])
    cos, sin = math.cos(theta), math.sin(theta)
    # place2d's linear part R_mx(rotate) / scale equals glTF's R(θ) S conjugated by the V flip,
    # which is the standard counter-clockwise rotation by θ: [[cos, -sin], [sin, cos]].
    du, dv = uv.pivot[0] - GLTF_PIVOT[0], uv.pivot[1] - GLTF_PIVOT[1]
    mu = cos * scale[0] * du - sin * scale[1] * dv
    mv = sin * scale[0] * du + cos * scale[1] * dv
    shift_u = du - mu - uv.offset[0]
    shift_v = dv - mv - uv.offset[1]
    return (_clean(shift_u), _clean(-shift_v)), _clean(theta), scale


def _clean(value: float) -> float:
    """-0.0 -> 0.0, so identical transforms print identically."""
    return value + 0.0
