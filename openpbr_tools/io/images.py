"""Images, format-neutral: decoding to float pixels, channel counts, and resampling.

Every reader of texels (the glTF writer's channel packing, the baker) decodes here: Pillow for PNG,
JPEG, TIFF, TGA, WebP and BMP, OpenImageIO for what Pillow cannot open (EXR, HDR). Both are imported on first use (Pillow ~0.1 s, OpenImageIO ~0.3 s), so a
command that never reads a texel never pays for them. Colour decoding is
:mod:`openpbr_tools.colorspaces`; which files may be read at all, :mod:`openpbr_tools.io.paths`.
"""

from __future__ import annotations

import io


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


def resample(plane, height: int, width: int):
    """A ``(h, w)`` float plane resized to ``(height, width)``, bilinear (Pillow's 32-bit float mode)."""
    import numpy as np
    from PIL import Image

    return np.asarray(Image.fromarray(plane.astype(np.float32), mode="F").resize((width, height), Image.BILINEAR),
                      dtype=np.float64)
