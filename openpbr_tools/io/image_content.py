"""Image content, read as little as answers the question: whether an image is more than one flat colour
(:func:`varies`), each channel's largest value (:func:`channel_maxima`; one channel's at full resolution:
:func:`channel_largest`) and each channel's range and mask signature (:func:`channel_statistics`). Pillow decodes (a JPEG at 1/8 scale, nothing past a pixel limit);
OpenImageIO answers :func:`varies` for files Pillow does not open. Whether a file is an image at all is
:mod:`openpbr_tools.io.image_files`' question.
"""

from __future__ import annotations

import io
import warnings
from dataclasses import dataclass

from .image_files import MAX_DECODED_PIXELS, head_of, openimageio, pillow_format, png_bit_depth, utf8

_FLAT_LEVELS = 2  # 8-bit levels: "one flat colour" allows JPEG noise


def opened_reduced(image, max_pixels: int):
    """``image`` (a path or bytes) opened by Pillow, a JPEG set to decode at 1/8 scale (Pillow's ``draft``), or
    ``None`` (closed) when it has more than ``max_pixels`` pixels: nothing is decoded yet. Raises what Pillow
    raises for data it does not open."""
    from PIL import Image  # lazy: as in load_pixels

    with warnings.catch_warnings():  # DecompressionBombWarning: the library never prints
        warnings.simplefilter("ignore")
        opened = Image.open(io.BytesIO(image) if isinstance(image, (bytes, bytearray, memoryview)) else image)
    width, height = opened.size
    if width * height > max_pixels:
        opened.close()
        return None
    if pillow_format(opened) == "JPEG":
        opened.draft("RGB", (max(1, width // 8), max(1, height // 8)))
    return opened


def varies(image: str | bytes) -> bool:
    """Whether ``image`` (a path or bytes) is more than one flat colour (every texel within 2/255 of the
    others); ``False`` when that cannot be told (undecodable, larger than :data:`MAX_DECODED_PIXELS`).
    Pillow's extrema of the image in its own mode (a JPEG decoded at 1/8 scale), never a float copy of
    it; OpenImageIO's ``isConstantColor`` for a file Pillow does not open (OpenEXR, Radiance HDR), when
    it is installed."""
    try:
        opened = opened_reduced(image, MAX_DECODED_PIXELS)
        if opened is None:
            return False
        with opened:
            plane = opened.convert("RGBA") if opened.mode in ("P", "PA", "1") else opened
            extrema = plane.getextrema()
            mode = plane.mode
    except Exception:  # noqa: BLE001 - not an image Pillow opens (EXR, HDR...): OpenImageIO, else not told
        return isinstance(image, str) and _varies_openimageio(image)
    bands = extrema if isinstance(extrema[0], tuple) else (extrema,)
    limit = _FLAT_LEVELS * 257 if mode.startswith("I;16") else _FLAT_LEVELS / 255.0 if mode == "F" else _FLAT_LEVELS
    return any(high - low > limit for low, high in bands)


def _varies_openimageio(path: str) -> bool:
    """:func:`varies` for a file only OpenImageIO reads, when it is installed: ``ImageBufAlgo.isConstantColor``
    at the same 2/255, up to the same size; ``False`` when it cannot tell."""
    oiio = openimageio()
    if oiio is None or not utf8(path):
        return False
    try:
        buffer = oiio.ImageBuf(path)
        spec = buffer.spec()
        if buffer.has_error or not buffer.initialized or not 0 < spec.width * spec.height <= MAX_DECODED_PIXELS:
            buffer.geterror()  # retrieved, so OpenImageIO does not print it
            return False
        constant = oiio.ImageBufAlgo.isConstantColor(buffer, _FLAT_LEVELS / 255.0)
        failed = buffer.has_error
        buffer.geterror()
        return not failed and constant is None
    except (TypeError, ValueError, RuntimeError):
        return False


def channel_maxima(image: str | bytes, max_pixels: int = MAX_DECODED_PIXELS) -> tuple[int, ...] | None:
    """The largest 8-bit value of each channel of ``image`` (a path or bytes) as RGB(A) (a palette or
    greyscale image converted first; a 16-bit one scaled to 8 bits, so only a channel that is 0 everywhere
    reads 0), or ``None`` when it cannot be told: undecodable, not an image Pillow opens, or larger than
    ``max_pixels``. A JPEG is decoded at 1/8 scale (Pillow's ``draft``); nothing larger than the limit is
    decoded."""
    try:
        opened = opened_reduced(image, max_pixels)
        if opened is None:
            return None
        with opened:
            if opened.mode.startswith("I;16") or opened.mode in ("I", "F"):
                extrema = opened.getextrema()
                high = extrema[1] if not isinstance(extrema[0], tuple) else max(b[1] for b in extrema)
                return (1 if high > 0 else 0,) * 3  # grey: one channel read as R, G and B
            plane = opened.convert("RGBA" if "A" in opened.mode or "transparency" in opened.info else "RGB")
            return tuple(int(high) for _, high in plane.getextrema())
    except Exception:  # noqa: BLE001 - Pillow raises many exception types for data it cannot decode
        return None


def channel_largest(image: str | bytes, channel: int, max_pixels: int = MAX_DECODED_PIXELS) -> float | None:
    """The largest value in [0, 1] of RGBA channel ``channel`` of ``image`` (a path or bytes), decoded at full
    resolution (a JPEG too: a one-texel highlight must not be averaged away), as a texture lookup reads it: a
    greyscale image's grey in R, G and B, alpha 1 where the image has none; a 16-bit grey at its full depth. A
    16-bit colour PNG, which Pillow decodes to 8 bits, gives an upper bound: its 8-bit largest plus one level.
    ``None`` when it cannot be told: undecodable, a float image, larger than ``max_pixels``."""
    from PIL import Image  # lazy: as in load_pixels

    try:
        with warnings.catch_warnings():  # DecompressionBombWarning: the library never prints
            warnings.simplefilter("ignore")
            opened = Image.open(io.BytesIO(image) if isinstance(image, (bytes, bytearray, memoryview)) else image)
        with opened:
            width, height = opened.size
            if width * height > max_pixels or opened.mode == "F":
                return None
            has_alpha = "A" in opened.mode or "transparency" in opened.info
            if opened.mode.startswith("I;16") or opened.mode == "I":  # a 16-bit grey
                if channel == 3:
                    return 1.0
                high = opened.getextrema()[1]
                return min(1.0, high / 65535.0)
            if channel == 3 and not has_alpha:
                return 1.0
            head = image[:32] if isinstance(image, (bytes, bytearray, memoryview)) else head_of(image, 32)
            truncated = png_bit_depth(bytes(head)) == 16  # (16 bits per sample read as 8: a level of doubt)
            plane = opened.convert("RGBA" if has_alpha else "RGB")
            return min(1.0, (plane.getextrema()[channel][1] + truncated) / 255.0)
    except Exception:  # noqa: BLE001 - Pillow raises many exception types for data it cannot decode
        return None


@dataclass(frozen=True, slots=True)
class ChannelStatistics:
    """One 8-bit channel's range and how much of it sits at the two ends (a mask's signature)."""
    low: int
    high: int
    at_ends: float  # share of texels within 8 levels of 0 or 255
    ends_both: bool  # both ends hold at least 2% of the texels
    mean: float = 0.0  # the mean level, 0-255

    @property
    def flat(self) -> bool:
        return self.high - self.low <= _FLAT_LEVELS

    @property
    def mask(self) -> bool:
        """Two-valued, black and white: a metal or cut-out mask, not a gradient such as ambient occlusion."""
        return self.ends_both and self.at_ends >= 0.95


def channel_statistics(image: str | bytes, max_pixels: int = MAX_DECODED_PIXELS) -> tuple[ChannelStatistics, ...] | None:
    """:class:`ChannelStatistics` of each channel of an 8-bit ``image`` (a path or bytes) read as RGB(A), or
    ``None`` when it cannot be told (not an 8-bit image Pillow opens, larger than ``max_pixels``). A JPEG is
    decoded at 1/8 scale; only Pillow's per-channel histograms are computed."""
    try:
        opened = opened_reduced(image, max_pixels)
        if opened is None:
            return None
        with opened:
            if opened.mode.startswith("I") or opened.mode == "F":
                return None
            plane = opened.convert("RGBA" if "A" in opened.mode or "transparency" in opened.info else "RGB")
            histogram = plane.histogram()
    except Exception:  # noqa: BLE001 - Pillow raises many exception types for data it cannot decode
        return None
    found = []
    for band in range(len(histogram) // 256):
        counts = histogram[band * 256:(band + 1) * 256]
        total = sum(counts) or 1
        used = [level for level, count in enumerate(counts) if count]
        dark, bright = sum(counts[:9]), sum(counts[247:])
        found.append(ChannelStatistics(used[0] if used else 0, used[-1] if used else 0, (dark + bright) / total,
                                       dark >= 0.02 * total and bright >= 0.02 * total,
                                       sum(level * count for level, count in enumerate(counts)) / total))
    return tuple(found)


def sixteen_bit_peak(image: str | bytes, max_pixels: int = MAX_DECODED_PIXELS) -> int | None:
    """The largest sample of a 16-bit single-channel image (Pillow's I;16 modes: a 16-bit greyscale PNG), or
    ``None`` for any other image or one that cannot be told. Decoded only up to ``max_pixels``."""
    try:
        opened = opened_reduced(image, max_pixels)
        if opened is None:
            return None
        with opened:
            if not opened.mode.startswith("I;16"):
                return None
            return int(opened.getextrema()[1])
    except Exception:  # noqa: BLE001 - Pillow raises many exception types for data it cannot decode
        return None
