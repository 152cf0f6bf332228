"""The absorption coefficient of a transmitting medium, as OpenPBR and Autodesk Standard Surface
define it (both take it from Arnold's ``standard_surface``): ``transmission_color`` reached at
``transmission_depth`` gives the extinction coefficient, ``transmission_scatter / depth`` is the
scattering coefficient, and the absorption is their difference; where a component comes out
negative, all three are shifted up by it (OpenPBR 1.1, "Translucent base"; MaterialX 1.39.5's
``open_pbr_surface`` graph: ``absorption_coeff_shifted``). The previews do not scatter in the volume,
so the light it scatters is taken to leave in the direction it travelled, and only the absorption
dims it. Shared by the evaluators and by the translators that write a volume (glTF's attenuation).
"""

from __future__ import annotations

import numpy as np

COLOUR_FLOOR = 1e-6  # a transmission colour of 0 absorbs everything: -log clipped here


def with_channel_axis(x) -> np.ndarray:
    """``x`` (one value per colour: 0-d, per pixel or per texel) shaped to broadcast against colours
    (last axis RGB): a trailing axis of 1 added unless it has one already or is 0-d."""
    x = np.asarray(x, dtype=float)
    return x if x.ndim == 0 or x.shape[-1] == 1 else x[..., None]


def absorption_coefficient(color, depth, scatter):
    """Absorption per unit length (per channel, the last axis of ``color`` and ``scatter``) of the
    medium; 0 where ``depth`` is not positive. ``depth`` has one value per colour (or per pixel or
    texel beside a constant colour), with or without a trailing channel axis of 1."""
    color = np.asarray(color, dtype=float)
    depth = with_channel_axis(depth)
    has_depth = depth > 0.0
    safe = np.where(has_depth, depth, 1.0)
    absorption = (-np.log(np.maximum(color, COLOUR_FLOOR)) - np.asarray(scatter, dtype=float)) / safe
    lowest = np.min(absorption, axis=-1, keepdims=True)
    absorption = np.where(lowest < 0.0, absorption - lowest, absorption)
    return np.where(has_depth, absorption, 0.0)
