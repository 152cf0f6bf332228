"""Images of a comparison: a side-by-side (A | B) and a ΔE2000 heat map per shape,
as PNG bytes for ``--delta-e-images`` and the HTML report. Needs Pillow.

Heat-map scale (fixed, so maps of different materials read alike): black at 0, blue at 1, green
at 2.3 (the usual just-noticeable difference), yellow at 5, red at 10, white at 20 and above;
linear between the stops. Pixels off the shape are dark grey.
"""

from __future__ import annotations

import io

import numpy as np

from .preview import encode_srgb

#: (ΔE2000, sRGB 8-bit colour) stops of the heat map.
HEAT_STOPS = ((0.0, (0, 0, 0)), (1.0, (30, 60, 200)), (2.3, (40, 180, 60)), (5.0, (240, 220, 40)),
              (10.0, (220, 40, 30)), (20.0, (255, 255, 255)))
OFF_SHAPE = (48, 48, 48)


def heat_map(delta_e: np.ndarray) -> np.ndarray:
    """8-bit sRGB (H, W, 3) heat map of a ΔE map (NaN: off the shape)."""
    values = np.asarray(delta_e, dtype=float)
    stops = np.array([s for s, _ in HEAT_STOPS])
    colours = np.array([c for _, c in HEAT_STOPS], dtype=float)
    finite = np.isfinite(values)
    clipped = np.clip(np.where(finite, values, 0.0), 0.0, stops[-1])
    out = np.stack([np.interp(clipped, stops, colours[:, k]) for k in range(3)], axis=-1)
    out[~finite] = OFF_SHAPE
    return np.round(out).astype(np.uint8)


def png(pixels: np.ndarray) -> bytes:
    """PNG bytes of an 8-bit (H, W, 3) image."""
    from PIL import Image  # lazy: Pillow is needed only when images are written

    buffer = io.BytesIO()
    Image.fromarray(np.ascontiguousarray(pixels), "RGB").save(buffer, format="PNG")
    return buffer.getvalue()


def view_images(view) -> dict[str, bytes]:
    """PNGs of one :class:`~.verify.View`: ``a``, ``b`` (sRGB previews), ``delta_e`` (heat map) and
    ``side_by_side`` (A and B in a row, a 4-pixel gap between)."""
    a, b, heat = encode_srgb(view.image_a), encode_srgb(view.image_b), heat_map(view.delta_e)
    gap = np.full((a.shape[0], 4, 3), 32, dtype=np.uint8)
    return {"a": png(a), "b": png(b), "delta_e": png(heat), "side_by_side": png(np.concatenate([a, gap, b], axis=1))}


def legend() -> bytes:
    """A 256 x 16 PNG of the heat-map scale from 0 to 20."""
    ramp = np.tile(np.linspace(0.0, 20.0, 256), (16, 1))
    return png(heat_map(ramp))
