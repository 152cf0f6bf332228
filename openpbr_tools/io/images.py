"""Images, format-neutral: finding the file a texture names, decoding it to float pixels, channel
counts, and resampling.

:class:`ImageLocator` finds the image of a :class:`~openpbr_tools.model.Texture` for every consumer
that reads texels or copies image files (the glTF writer, the baker): a file resolved through the
one path guard (:mod:`openpbr_tools.io.paths`), so only files inside the source asset's folder or an
allowed folder are ever read and URLs are never fetched, or an image packaged inside the source
(a glTF's ``#/images/N``, read through :func:`openpbr_tools.io.packaged_image`). It raises
:class:`ImageRefused` for a texture that must not be read at all (the caller refuses the whole
output) and :class:`ImageUnavailable` for one that cannot be (empty path, missing file, unreadable
package entry, a file that is no readable image, :func:`.image_files.damage`: the caller reports it and goes on).

Every reader of texels (the glTF writer's channel packing, the baker) decodes here: Pillow for PNG,
JPEG, TIFF, TGA, WebP and BMP, OpenImageIO for what Pillow cannot open (EXR, HDR). Both are imported on first use (Pillow ~15 ms, OpenImageIO ~30 ms), so a
command that never reads a texel never pays for them. Colour decoding is
:mod:`openpbr_tools.colorspaces`; which files may be read at all, :mod:`openpbr_tools.io.paths`.
"""

from __future__ import annotations

import io
import os
import sys
import threading
import warnings

from . import ReadError, packaged_image
from .image_files import damage, openimageio_size
from ..model import Texture
from .paths import Kind, PathGuard, classify


class ImageRefused(ValueError):
    """A texture that must never be read: outside the allowed folders, a URL, or not a path (NUL)."""


class ImageUnavailable(ValueError):
    """A texture that cannot be read: an empty path, a missing file, an unreadable package entry."""


class ImageUndecodable(ValueError):
    """An image whose pixels cannot be decoded (an OpenEXR cut short, texels that are not finite, a format
    no decoder here reads): the caller leaves the texture out, with a note."""


class ImageSource:
    """One located image: ``key`` identifies it (a real path, or container and member), ``image`` is
    its path or bytes, ``name`` the file name to give a copy, ``mime`` its type when known."""

    __slots__ = ("key", "image", "name", "mime", "_channels")

    def __init__(self, key, image, name, mime):
        self.key, self.image, self.name, self.mime, self._channels = key, image, name, mime, None

    @property
    def channels(self) -> int:
        if self._channels is None:
            try:
                self._channels = channel_count(self.image)
            except Exception:  # noqa: BLE001 - not an image Pillow opens (EXR...): decided when baking
                self._channels = 4
        return self._channels

    @property
    def passes_through(self) -> bool:
        return self.mime in ("image/png", "image/jpeg")

    def gltf_ready(self, colour: bool) -> bool:
        """Whether a glTF may reference the image's bytes as they are: a PNG or JPEG (:attr:`passes_through`), not a
        four-component (CMYK) JPEG, nor a 16-bit PNG in a colour slot (glTF 2.0 3.9.2: 8-bit sRGB), nor a PNG with
        what glTF says it SHOULD NOT hold (an ICC profile, gamma, chromaticities, non-square pixels): OPBR1219 and
        OPBR1233 on the output otherwise. The others are re-encoded as 8-bit PNG."""
        if not self.passes_through:
            return False
        from .gltf.image_features import png_features, png_header_chunks  # lazy: the glTF writer's question only
        from .image_files import head_of, png_bit_depth  # lazy: as above

        # (headers only: the writer reads the bytes it copies once, after this)
        image = memoryview(self.image) if isinstance(self.image, bytes) else self.image
        if self.mime == "image/png":
            head = bytes(image[:32]) if isinstance(image, memoryview) else head_of(image, 32)
            return not ((colour and (png_bit_depth(head) or 8) > 8) or png_features(png_header_chunks(image)))
        try:
            from PIL import Image  # lazy: as channel_count's

            with Image.open(io.BytesIO(self.image) if isinstance(self.image, bytes) else self.image) as opened:
                return opened.mode != "CMYK"
        except Exception:  # noqa: BLE001 - not decodable: the writer's bake says so
            return False

    def data(self) -> bytes:
        if isinstance(self.image, bytes):
            return self.image
        with open(self.image, "rb") as handle:
            return handle.read()


class ImageLocator:
    """Finds texture images for one conversion. Relative files resolve against the source asset's
    folder (``source_path``), else the folder of the file the texture was read from, else
    ``fallback_folder``; ``allow_outside`` lists further folders images may be read from."""

    def __init__(self, source_path: str | None, fallback_folder: str, allow_outside=()):
        self.source_path = source_path
        self.fallback_folder = fallback_folder
        self.allow_outside = tuple(allow_outside)
        self.guards: dict[str, PathGuard] = {}
        self.containers: dict = {}

    def folder_of(self, texture: Texture) -> str:
        anchor = self.source_path or (texture.location.file if texture.location and texture.location.file else None)
        return os.path.dirname(os.path.abspath(anchor)) if anchor else self.fallback_folder

    def guard(self, folder: str) -> PathGuard:
        """The guard of ``folder`` and the allowed folders (one per folder: their real paths are
        resolved once)."""
        if folder not in self.guards:
            self.guards[folder] = PathGuard(folder, self.allow_outside)
        return self.guards[folder]

    def locate(self, texture: Texture, owner: str) -> ImageSource:
        """The image of ``texture``; ``owner`` (``material.parameter``) starts every message."""
        file = texture.file
        if not file.strip():
            raise ImageUnavailable(f"{owner}: empty texture path, not written")
        if texture.packaged:
            return self._packaged(texture, owner)
        kind = classify(file)
        if kind is Kind.URL:
            raise ImageRefused(f"{owner}: texture {file!r} is a URL; the writer never fetches URLs")
        if kind is Kind.NUL:
            raise ImageRefused(f"{owner}: texture {file!r} contains a NUL character, which no file name can; "
                               "it is neither read nor embedded")
        guard = self.guard(self.folder_of(texture))
        resolved = guard.resolve(file)
        if not resolved.inside:
            raise ImageRefused(
                f"{owner}: texture {file!r} resolves to {resolved.real or file}, outside the source asset's folder "
                f"{guard.own_root}; it is neither read nor embedded unless its folder is allowed (allow_outside / "
                "--allow-outside)")
        real = resolved.real
        if not os.path.isfile(real):
            raise ImageUnavailable(f"{owner}: texture {file!r} does not exist, not written")
        try:
            mime = _mime_of_file(real)
        except OSError as error:  # permission denied, an I/O error: the texture's fault, not the output's
            raise ImageUnavailable(f"{owner}: texture {file!r} cannot be read ({error.strerror or error}), "
                                   "not written") from None
        found = damage(real)
        if found is not None:
            raise ImageUnavailable(f"{owner}: texture {file!r} is {found.detail}, not written")
        name = resolved.relative if resolved.root == guard.own_root else f"textures/{os.path.basename(real)}"
        return ImageSource(key=("file", real), image=real, name=name, mime=mime)

    def _packaged(self, texture: Texture, owner: str) -> ImageSource:
        container = texture.location.file if texture.location else self.source_path
        try:
            data, mime = packaged_image(container or "", texture.file, self.containers)
        except ReadError as error:
            if error.kind == "unsupported":
                raise ImageUnavailable(f"{owner}: {texture.file!r} is inside a package that cannot be opened here, "
                                       "not read") from None
            raise ImageUnavailable(f"{owner}: {texture.file!r} cannot be loaded ({error.message}), not written") from None
        found = damage(data)
        if found is not None:
            raise ImageUnavailable(f"{owner}: {texture.file!r} is {found.detail}, not written")
        stem = os.path.splitext(os.path.basename(container))[0]
        extension = {"image/png": ".png", "image/jpeg": ".jpg"}.get(sniff(data) or mime or "", ".png")
        if texture.file.startswith("#/images/"):  # a glTF's image N
            name = f"{stem}_image{texture.file.rsplit('/', 1)[1]}{extension}"
        else:  # a member of a USDZ package
            name = f"{stem}_{os.path.splitext(os.path.basename(texture.file))[0]}{extension}"
        return ImageSource(key=("packaged", os.path.abspath(container), texture.file), image=data,
                           name=name, mime=sniff(data) or mime)


def sniff(data: bytes) -> str | None:
    """The MIME type of PNG or JPEG bytes, from their signature."""
    if data.startswith(b"\x89PNG\r\n\x1a\n"):
        return "image/png"
    if data.startswith(b"\xff\xd8\xff"):
        return "image/jpeg"
    return None


def _mime_of_file(path: str) -> str | None:
    with open(path, "rb") as handle:
        return sniff(handle.read(8))



#: The most texels (width x height) an image may have to be decoded for baking, evaluation or packing: 4096 x
#: 4096. Decoding and baking cost about 220 bytes of peak memory per texel (measured on ``convert`` to ``.glb`` of a
#: material whose base colour is an RGB PNG: 1.1 GB peak at 2048 x 2048, 3.9 GB at 4096 x 4096; float64 copies
#: of the image, its colour decoding and each formula's intermediates), so this keeps one bake under about 4 GB.
#: Pillow's own limit (179 MP) let a 0.5 MB 13000 x 13000 PNG grow a conversion to 22.7 GB before it was killed.
#: Textures that pass through unchanged are copied, never decoded, and have no such limit. A machine with the
#: memory for 8K bakes (about 15 GB each) raises it with OPENPBR_MAX_DECODED_MEGATEXELS (67.1 for 8192 x 8192).
MAX_DECODED_TEXELS = 4096 * 4096


def max_decoded_texels() -> int:
    """:data:`MAX_DECODED_TEXELS`, or OPENPBR_MAX_DECODED_MEGATEXELS million where set (as OPENPBR_MAX_FILE_MB);
    ``inf`` lifts the limit, and a value that is no positive number is ignored."""
    try:
        megatexels = float(os.environ.get("OPENPBR_MAX_DECODED_MEGATEXELS", MAX_DECODED_TEXELS / 1e6))
    except ValueError:
        return MAX_DECODED_TEXELS
    if megatexels == float("inf"):
        return sys.maxsize
    return int(megatexels * 1e6) if megatexels > 0 else MAX_DECODED_TEXELS


def _refuse_huge(width: int, height: int, image) -> None:
    """An image above :func:`max_decoded_texels` is refused from its header, before a byte is decoded (by Pillow or
    the OpenImageIO fallback). The validator reports the size of anything beyond what GPUs load (OPBR713)."""
    limit = max_decoded_texels()
    if width * height > limit:
        name = repr(image) if isinstance(image, str) else "the embedded image"
        raise ImageUndecodable(f"{name} is {width} x {height} pixels, above the {limit:,} texels that are decoded "
                               "for baking or evaluation (OPENPBR_MAX_DECODED_MEGATEXELS raises it): not read")


def load_pixels(image: str | bytes, levels: bool = False):
    """Pixels as float64 ``(height, width, channels)`` in [0, 1] (greyscale expanded to RGB). With
    ``levels``, an 8-bit image comes as its uint8 levels instead (``levels / 255`` is the float
    image). An image above :data:`MAX_DECODED_TEXELS` is refused from its header (:class:`ImageUndecodable`)."""
    import numpy as np  # lazy: numpy ~60 ms, Pillow ~15 ms; every conversion imports this module (the baker)

    size = image_size(image)
    if size is not None:
        _refuse_huge(*size, image)
    try:
        from PIL import Image  # lazy: as numpy above

        with warnings.catch_warnings():  # DecompressionBombWarning: the library never prints
            warnings.simplefilter("ignore")
            opened = Image.open(io.BytesIO(image) if isinstance(image, bytes) else image)
        with opened:
            mode = opened.mode
            if mode in ("I;16", "I;16B", "I;16L", "I"):
                scale = 65535.0 if mode.startswith("I;16") else float(max(1, np.asarray(opened).max()))
                values = np.asarray(opened, dtype=np.float64) / scale
            elif mode == "F":
                values = np.asarray(opened, dtype=np.float64)
            else:
                target = {"L": "L", "LA": "LA", "RGB": "RGB", "RGBA": "RGBA"}.get(mode, "RGBA" if "A" in mode or mode == "P" else "RGB")
                values = np.asarray(opened.convert(target))
                values = values if levels else values.astype(np.float64) / 255.0
    except Exception:  # Pillow raises many exception types for formats it does not know
        values = _load_with_openimageio(image)  # (an image too large was refused above, by its header)
    if values.ndim == 2:
        values = values[:, :, None]
    if values.shape[2] in (1, 2):  # L / LA: grey is every colour channel
        grey = np.repeat(values[:, :, :1], 3, axis=2)
        values = np.concatenate([grey, values[:, :, 1:]], axis=2)
    return values


def _load_with_openimageio(image: str | bytes):
    import numpy as np  # lazy: as in load_pixels

    if isinstance(image, bytes):
        raise ImageUndecodable("image format not recognised")
    import OpenImageIO as oiio  # lazy: ~30 ms, and optional (the images extra); only EXR, HDR... need it

    buffer = oiio.ImageBuf(image)
    if buffer.has_error:
        raise ImageUndecodable(f"cannot read {image!r}: {_one_line(buffer.geterror())}")
    pixels = buffer.get_pixels(oiio.FLOAT)  # (load_pixels refused an image too large by its header first)
    if buffer.has_error:  # read, but with chunks missing (a file cut short); retrieving the error also keeps
        raise ImageUndecodable(f"cannot read {image!r}: {_one_line(buffer.geterror())}")  # OpenImageIO from printing it
    values = np.asarray(pixels, dtype=np.float64)
    if not np.isfinite(values).all():
        raise ImageUndecodable(f"{image!r} holds texels that are not finite numbers (NaN or infinity)")
    return values


def _one_line(message: str) -> str:
    """OpenImageIO's error text (one line per error, often repeated) as one line."""
    return "; ".join(dict.fromkeys(line.strip() for line in message.splitlines() if line.strip()))


def channel_count(image: str | bytes) -> int:
    """How many channels the image has (greyscale 1, greyscale+alpha 2, RGB 3, RGBA 4)."""
    from PIL import Image  # lazy: as in load_pixels

    with warnings.catch_warnings():  # DecompressionBombWarning: the library never prints
        warnings.simplefilter("ignore")
        with Image.open(io.BytesIO(image) if isinstance(image, bytes) else image) as opened:
            return len(opened.getbands()) if opened.mode != "P" else (4 if "transparency" in opened.info else 3)


_BOMB_LIMIT_LIFTED = threading.Lock()  # Pillow's limit is a module global: lifted for one header read at a time


def image_size(image: str | bytes) -> tuple[int, int] | None:
    """(width, height) of an image from its header (a PNG's IHDR, else Pillow's header read, else, for a
    file Pillow refuses as a decompression bomb or does not open, OpenImageIO's), or ``None`` when it cannot
    be told. Nothing is decoded."""
    from PIL import Image  # lazy: as in load_pixels

    head = image[:24] if isinstance(image, bytes) else None
    if head is None:
        try:
            with open(image, "rb") as handle:
                head = handle.read(24)
        except OSError:
            return None
    if head.startswith(b"\x89PNG\r\n\x1a\n") and head[12:16] == b"IHDR":
        return int.from_bytes(head[16:20], "big"), int.from_bytes(head[20:24], "big")
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            with Image.open(io.BytesIO(image) if isinstance(image, bytes) else image) as opened:
                return opened.size
    except Image.DecompressionBombError:  # the header again with Pillow's limit lifted: open() decodes nothing
        with _BOMB_LIMIT_LIFTED:
            limit, Image.MAX_IMAGE_PIXELS = Image.MAX_IMAGE_PIXELS, None
            try:
                with Image.open(io.BytesIO(image) if isinstance(image, bytes) else image) as opened:
                    return opened.size
            except Exception:  # noqa: BLE001 - as below
                return None
            finally:
                Image.MAX_IMAGE_PIXELS = limit
    except Exception:  # noqa: BLE001 - not an image Pillow opens (EXR, HDR...)
        return openimageio_size(image) if isinstance(image, str) else None


PNG_CHANNELS = {0: 1, 2: 3, 3: 3, 4: 2, 6: 4}  # PNG colour type -> channels (ISO/IEC 15948, 11.2.2 IHDR)


def image_layout(path: str) -> tuple[int, int, float | None] | None:
    """(channels, bits per channel, file gamma or ``None``) of a PNG or JPEG file, from its header
    alone; ``None`` for another format or a file that cannot be read. The gamma is PNG's ``gAMA``
    chunk (1/2.2 = 0.45455 for sRGB-encoded), which OpenUSD's stb reader consults before guessing."""
    try:
        with open(path, "rb") as handle:
            head = handle.read(1 << 16)
    except OSError:
        return None
    if head.startswith(b"\x89PNG\r\n\x1a\n") and head[12:16] == b"IHDR" and len(head) >= 26:
        bits, colour_type = head[24], head[25]
        if colour_type not in PNG_CHANNELS:
            return None
        gamma, offset = None, 8
        while offset + 8 <= len(head):  # chunks: length, type, data, CRC; gAMA precedes the first IDAT
            length, kind = int.from_bytes(head[offset:offset + 4], "big"), head[offset + 4:offset + 8]
            if kind == b"gAMA" and offset + 12 <= len(head):
                gamma = int.from_bytes(head[offset + 8:offset + 12], "big") / 100000.0
            if kind in (b"IDAT", b"IEND"):
                break
            offset += 12 + length
        return PNG_CHANNELS[colour_type], bits, gamma
    if sniff(head) == "image/jpeg":
        from PIL import Image  # lazy: as in load_pixels

        try:
            with Image.open(path) as opened:
                return len(opened.getbands()), 8, None
        except (OSError, ValueError):
            return None
    return None


def resample(plane, height: int, width: int):
    """A ``(h, w)`` float plane resized to ``(height, width)``, bilinear (Pillow's 32-bit float mode)."""
    # lazy: as in load_pixels
    import numpy as np
    from PIL import Image

    return np.asarray(Image.fromarray(plane.astype(np.float32), mode="F").resize((width, height), Image.BILINEAR),
                      dtype=np.float64)
