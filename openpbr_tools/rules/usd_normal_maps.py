"""The encodings of an 8-bit normal map a UsdUVTexture's scale and bias may decode (:func:`decodes_unit_normals`:
OPBR1006's judgement), and the ones among them usd-core's NormalMapTextureValidator warns on
(:func:`other_normal_encodings`)."""

from __future__ import annotations

from ..io.usd.types import UV_TEXTURE_ID, is_eight_bit
from ..model import rgb_components


def other_normal_encodings(asset) -> set[str]:
    """The UsdUVTexture prims whose 8-bit normal map a read preview decodes with an encoding this family accepts
    (:func:`decodes_unit_normals`) other than the specification's scale 2 and bias -1: a strength, a flipped axis.
    usd-core's NormalMapTextureValidator warns on them (NonCompliantScaleValues, NonCompliantBiasValues), and where
    OPBR1006 is silent that warning is reported as usd-core's (usd.py), not dropped as one OPBR1006 says better."""
    out = set()
    for material in asset.materials:
        normal = material.inputs.get("normal")
        texture = normal.texture if normal is not None else None
        if texture is None or texture.node_category != UV_TEXTURE_ID or not texture.node or \
                not is_eight_bit(texture.file):
            continue
        scale, bias = rgb_components(texture.scale, 1.0), rgb_components(texture.bias, 0.0)
        if decodes_unit_normals(scale, bias) and (tuple(scale[:3]) != (2.0, 2.0, 2.0) or
                                                   tuple(bias[:3]) != (-1.0, -1.0, -1.0)):
            out.add(texture.node)
    return out


def decodes_unit_normals(scale: tuple, bias: tuple) -> bool:
    """Whether scale and bias map an image's [0, 1] to tangent-space normal components: x and y
    symmetrically about 0 (0.5 -> 0) in either direction, so -2 and 1 reverse an axis (a normal map
    authored with the other green convention) and 2s and -s carry a strength s (glTF's
    normalTexture.scale, MaterialX's normalmap scale: Storm normalises the result); z onto [-1, 1]
    or [0, 1] (a tangent-space normal never points inwards; some encoders store z so), or z scaled as x
    (all three 2s and -s: Adobe's USD writer's glTF strength, (2c - 1) s, which Storm's normalisation turns
    back into the unit decode, its strength lost but no normal bent). A valid encoding passes, not only the
    specification's (2, -1)."""
    def symmetric(i):
        return scale[i] != 0.0 and abs(bias[i] + scale[i] / 2.0) < 1e-6

    z = sorted((round(bias[2], 6), round(bias[2] + scale[2], 6)))
    uniform = symmetric(2) and scale[2] > 0 and abs(scale[2] - scale[0]) < 1e-6 and abs(scale[2] - scale[1]) < 1e-6
    return symmetric(0) and symmetric(1) and (z in ([-1.0, 1.0], [0.0, 1.0]) or uniform)
