"""Baking texture channels into the images glTF wants: channel packing and re-encoding.

glTF reads fixed channels of fixed images (metallic from B and roughness from G of one
``metallicRoughnessTexture``, alpha from A of ``baseColorTexture``, ...), only PNG or JPEG, colour
textures sRGB-encoded and data textures linear. When a material's textures do not already have that
shape, :func:`pack` builds a new 8-bit PNG from channels of source images (and constants for the
channels nothing feeds). A channel copied from an 8-bit source keeps its texel values exactly
(``round(k / 255 * 255) = k``); sources of different sizes are resampled (bilinear) to the largest,
and 16-bit or float sources are quantised to 8 bits. Decoding uses Pillow (PNG, JPEG, TIFF, TGA,
WebP, BMP) and OpenImageIO for what Pillow cannot open (EXR, HDR); both are imported on first use.
"""

from __future__ import annotations

import io
from dataclasses import dataclass
from typing import Callable


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


def load_pixels(image: str | bytes):
    """Pixels as float64 ``(height, width, channels)`` in [0, 1] (greyscale expanded to RGB)."""
    import numpy as np

    try:
        from PIL import Image

        with Image.open(io.BytesIO(image) if isinstance(image, bytes) else image) as opened:
            mode = opened.mode
            if mode in ("I;16", "I;16B", "I;16L", "I"):
                scale = 65535.0 if mode.startswith("I;16") else float(max(1, np.asarray(opened).max()))
                values = np.asarray(opened, dtype=np.float64) / scale
            elif mode == "F":
                values = np.asarray(opened, dtype=np.float64)
            else:
                target = {"L": "L", "LA": "LA", "RGB": "RGB", "RGBA": "RGBA"}.get(mode, "RGBA" if "A" in mode or mode == "P" else "RGB")
                values = np.asarray(opened.convert(target), dtype=np.float64) / 255.0
    except Exception:  # Pillow raises many exception types for formats it does not know
        values = _load_with_openimageio(image)
    if values.ndim == 2:
        values = values[:, :, None]
    if values.shape[2] in (1, 2):  # L / LA: grey is every colour channel
        grey = np.repeat(values[:, :, :1], 3, axis=2)
        values = np.concatenate([grey, values[:, :, 1:]], axis=2)
    return values


def _load_with_openimageio(image: str | bytes):
    import numpy as np

    if isinstance(image, bytes):
        raise ValueError("image format not recognised")
    import OpenImageIO as oiio

    buffer = oiio.ImageBuf(image)
    if buffer.has_error:
        raise ValueError(f"cannot read {image!r}: {buffer.geterror()}")
    return np.asarray(buffer.get_pixels(oiio.FLOAT), dtype=np.float64)


def channel_count(image: str | bytes) -> int:
    """How many channels the image has (greyscale 1, greyscale+alpha 2, RGB 3, RGBA 4)."""
    from PIL import Image

    with Image.open(io.BytesIO(image) if isinstance(image, bytes) else image) as opened:
        return len(opened.getbands()) if opened.mode != "P" else (4 if "transparency" in opened.info else 3)


def pack(channels: list[ChannelSource | float], note: Callable[[str], None] | None = None, label: str = "") -> bytes:
    """An 8-bit PNG whose channel ``i`` is ``channels[i]`` (a source channel or a constant in [0, 1]).

    One or two entries make a greyscale (+ alpha) PNG: glTF expands grey to R = G = B."""
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


def resample(plane, height: int, width: int):
    """A ``(h, w)`` float plane resized to ``(height, width)``, bilinear (Pillow's 32-bit float mode)."""
    import numpy as np
    from PIL import Image

    return np.asarray(Image.fromarray(plane.astype(np.float32), mode="F").resize((width, height), Image.BILINEAR),
                      dtype=np.float64)


def _channel(pixels, source: ChannelSource):
    import numpy as np

    from ... import colorspaces

    channel = source.channel  # load_pixels expands greyscale, so R, G and B always exist
    if channel >= pixels.shape[2]:
        return np.ones(pixels.shape[:2])  # no alpha channel: opaque
    if source.decode is None and not source.encode_srgb or channel == 3:
        return pixels[:, :, channel]
    rgb = pixels[:, :, :3]
    linear = colorspaces.to_lin_rec709(rgb, source.decode) if source.decode else rgb
    if source.encode_srgb:
        linear = colorspaces.from_lin_rec709(np.clip(linear, 0.0, None), "srgb_texture")
    return np.asarray(linear)[:, :, channel]

