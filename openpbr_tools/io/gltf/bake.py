"""Baking texture channels into the images glTF wants: channel packing and re-encoding.

glTF reads fixed channels of fixed images (metallic from B and roughness from G of one
``metallicRoughnessTexture``, alpha from A of ``baseColorTexture``, ...), only PNG or JPEG, colour
textures sRGB-encoded and data textures linear. When a material's textures do not already have that
shape, :func:`pack` builds a new 8-bit PNG from channels of source images (and constants for the
channels nothing feeds). A channel copied from an 8-bit source keeps its texel values exactly
(``round(k / 255 * 255) = k``); sources of different sizes are resampled (bilinear) to the largest,
and 16-bit or float sources are quantised to 8 bits. Decoding and resampling are
:mod:`openpbr_tools.io.images`.
"""

from __future__ import annotations

import io
from dataclasses import dataclass
from typing import Callable

from ... import colorspaces
from ..images import load_pixels, resample


@dataclass(frozen=True, slots=True)
class ChannelSource:
    """Channel ``channel`` of an image given as a file path or encoded bytes; ``decode`` names a
    MaterialX colour space to convert from (``None``: copy the values as they are); ``encode_srgb``
    re-encodes the (linear Rec.709) result with the sRGB curve."""

    image: str | bytes
    channel: int
    decode: str | None = None
    encode_srgb: bool = False
    rgb_channels: tuple[int, int, int] | None = None  # the image's RGB, when decode needs a triple
    scale: float = 1.0  # value * scale + bias, after decoding (an affine map no glTF factor holds where there is
    bias: float = 0.0   # a bias: 1 - glossiness as a roughness, a UsdUVTexture's bias on a linear colour)


def pack(channels: list[ChannelSource | float], note: Callable[[str], None] | None = None, label: str = "") -> bytes:
    """An 8-bit PNG whose channel ``i`` is ``channels[i]`` (a source channel or a constant in [0, 1]).

    One or two entries make a greyscale (+ alpha) PNG: glTF expands grey to R = G = B."""
    # lazy: numpy (~60 ms) and Pillow (~15 ms) only when channels are packed; a glTF without textures needs neither
    import numpy as np
    from PIL import Image

    loaded: dict = {}
    sources = [c for c in channels if isinstance(c, ChannelSource)]
    for source in sources:
        if source.image not in loaded:
            loaded[source.image] = load_pixels(source.image)
    if loaded:
        height = max(p.shape[0] for p in loaded.values())
        width = max(p.shape[1] for p in loaded.values())
    else:
        height = width = 1
    planes = []
    for entry in channels:
        if not isinstance(entry, ChannelSource):
            planes.append(np.full((height, width), float(entry)))
            continue
        pixels = loaded[entry.image]
        plane = _channel(pixels, entry)
        if note is not None and (entry.scale != 1.0 or entry.bias != 0.0):
            outside = int(np.count_nonzero((plane < -0.5 / 255.0) | (plane > 1.0 + 0.5 / 255.0)))
            if outside:
                note(f"{label}: the texture's scale {entry.scale:g} and bias {entry.bias:g} take {outside} of "
                     f"{plane.size} texels of channel {entry.channel} outside [0, 1], where the 8-bit PNG clips them")
        if plane.shape != (height, width):
            if note is not None:
                note(f"{label}: a {plane.shape[1]} x {plane.shape[0]} source is resampled to {width} x {height}")
            plane = resample(plane, height, width)
        planes.append(plane)
    stacked = np.clip(np.stack(planes, axis=-1), 0.0, 1.0)
    quantised = np.round(stacked * 255.0).astype(np.uint8)
    mode = {1: "L", 2: "LA", 3: "RGB", 4: "RGBA"}[len(planes)]
    image = Image.fromarray(quantised[:, :, 0] if len(planes) == 1 else quantised, mode=mode)
    out = io.BytesIO()
    image.save(out, format="PNG", compress_level=6)
    return out.getvalue()


def _channel(pixels, source: ChannelSource):
    import numpy as np  # lazy: numpy costs ~60 ms; only packing channels needs it

    channel = source.channel  # load_pixels expands greyscale, so R, G and B always exist
    if channel >= pixels.shape[2]:
        return np.ones(pixels.shape[:2]) * source.scale + source.bias  # no alpha channel: opaque
    if source.decode is None and not source.encode_srgb or channel == 3:
        return pixels[:, :, channel] * source.scale + source.bias
    rgb = pixels[:, :, :3]
    linear = colorspaces.to_lin_rec709(rgb, source.decode) if source.decode else rgb
    if source.scale != 1.0 or source.bias != 0.0:  # (a colour texture's scale and bias: on the linear colour)
        linear = np.array(linear, dtype=np.float64)
        linear[:, :, channel] = linear[:, :, channel] * source.scale + source.bias
    if source.encode_srgb:
        linear = colorspaces.from_lin_rec709(np.clip(linear, 0.0, None), "srgb_texture")
    return np.asarray(linear)[:, :, channel]

