"""Image files as bytes: whether a file (or the bytes of an embedded image) is a readable image at
all (:func:`damage`), and :class:`ResourceFile`, a file over bytes or a view that copies only what is read.

Pillow reads PNG and JPEG (their data checked, not only their header: a PNG's chunks and the lengths the PNG
specification fixes, a JPEG's marker segments); a WebP's header is checked by its bytes; formats Pillow does not open
are known by their signature. Which files may be read at all is :mod:`openpbr_tools.io.paths`'s
decision; decoding pixels is :mod:`openpbr_tools.io.images`'. One module because every check here reads the same
few bytes of a container (its signature, header and chunk layout) through :class:`ResourceFile`, and what a
file is named by (:func:`suffix_of`) is the same signature question.
"""

from __future__ import annotations

import functools
import io
import os
import re
import stat
import warnings
import zlib
from typing import NamedTuple

#: An SVG document's opening: ``<svg`` after an XML declaration, comments or a DOCTYPE.
_SVG = re.compile(r"(\s*(<\?xml[^>]*\?>|<!--.*?-->|<!DOCTYPE[^>]*>))*\s*<svg[\s>]", re.S | re.I)


class ResourceFile(io.RawIOBase):
    """A read-only, seekable file over bytes or a view that copies only what is read: Pillow reads an
    image's header, so measuring an image inside a large glTF buffer costs the header."""

    def __init__(self, data) -> None:
        super().__init__()
        self.data, self.position = memoryview(data), 0

    def readable(self) -> bool:
        return True

    def seekable(self) -> bool:
        return True

    def tell(self) -> int:
        return self.position

    def seek(self, offset: int, whence: int = io.SEEK_SET) -> int:
        base = {io.SEEK_SET: 0, io.SEEK_CUR: self.position, io.SEEK_END: len(self.data)}[whence]
        self.position = max(0, base + offset)
        return self.position

    def readinto(self, buffer) -> int:
        chunk = self.data[self.position:self.position + len(buffer)]
        buffer[:len(chunk)] = chunk
        self.position += len(chunk)
        return len(chunk)

    def read(self, size: int = -1) -> bytes:
        end = len(self.data) if size is None or size < 0 else self.position + size
        chunk = bytes(self.data[self.position:end])
        self.position += len(chunk)
        return chunk


class Damage(NamedTuple):
    """Why a file is not a readable image. ``kind``: ``"empty"``, ``"text"`` (a Git LFS pointer, an
    HTML page...), ``"corrupt"`` (a PNG or JPEG cut short or with damaged data), ``"unrecognised"``
    (bytes in no image format this machine knows) or ``"unreadable"`` (a file that exists but cannot be
    opened: permission denied, an I/O error); ``detail`` says what was found."""

    kind: str
    detail: str


#: Signatures of image formats Pillow does not open (checked by signature only): OpenEXR, Radiance,
#: KTX 1 and 2, Ptex, JPEG 2000 (codestream and box), JPEG XL (codestream and box), DPX, Cineon,
#: Softimage PIC, Basis Universal, Maya IFF, PFM. A file matching none is also asked of OpenImageIO,
#: when installed, before it is called unrecognised.
OTHER_SIGNATURES = (b"v/1\x01", b"#?RADIANCE", b"#?RGBE", b"\xabKTX 20\xbb", b"\xabKTX 11\xbb", b"Ptex",
                    b"\xffO\xffQ", b"\x00\x00\x00\x0cjP  ", b"\xff\x0a", b"\x00\x00\x00\x0cJXL ",
                    b"SDPX", b"XPDS", b"\x80\x2a\x5f\xd7", b"\x53\x80\xf6\x34", b"sB", b"FOR4", b"FORM",
                    b"PF\n", b"Pf\n", b"PF\r", b"Pf\r")
_ISO_MEDIA_BRANDS = (b"avif", b"avis", b"heic", b"heix", b"mif1", b"msf1")  # AVIF / HEIF: "ftyp" at byte 4
_SIGNATURES = ((b"\x89PNG", "PNG"), (b"\xff\xd8\xff", "JPEG"))  # enough of each to know a file cut short
#: The chunks whose length the PNG specification fixes (11.2.2 IHDR, 11.3.3.2 cHRM, 11.3.3.3 gAMA, 11.3.3.5 sRGB,
#: 11.3.5.3 pHYs): decoders refuse the image (IHDR) or drop the chunk, and the Khronos glTF-Validator calls the image
#: invalid (IMAGE_DATA_INVALID).
PNG_CHUNK_LENGTHS = {b"IHDR": 13, b"cHRM": 32, b"gAMA": 4, b"sRGB": 1, b"pHYs": 9}
#: The first chunk of a WebP file (RIFF container, "WEBP" form): lossy, lossless or extended; and the bytes a header
#: needs (the extended header's canvas size ends at byte 30; a lossless one's at 25).
WEBP_FIRST_CHUNKS = (b"VP8 ", b"VP8L", b"VP8X")
_WEBP_HEADER = {b"VP8L": 25}
_WEBP_HEADER_DEFAULT = 30


def pillow_format(opened) -> str | None:
    """The format of an image Pillow opened, a camera's multi-picture JPEG ("MPO") being the JPEG it is."""
    return {"MPO": "JPEG"}.get(opened.format, opened.format)


#: Pillow modes that carry an alpha channel (a palette or greyscale PNG's tRNS shows in ``info["transparency"]``).
ALPHA_MODES = frozenset({"RGBA", "RGBa", "LA", "La", "PA"})


def head_of(path: str, size: int = 32) -> bytes:
    """The first ``size`` bytes of the file at ``path`` (empty when it cannot be read)."""
    try:
        with open(path, "rb") as handle:
            return handle.read(size)
    except OSError:
        return b""


def png_bit_depth(head: bytes) -> int | None:
    """A PNG's bits per sample (1, 2, 4, 8 or 16), read from its IHDR chunk in the first 26 bytes (PNG
    specification, 11.2.2); ``None`` for anything else."""
    if head[:8] != b"\x89PNG\r\n\x1a\n" or head[12:16] != b"IHDR" or len(head) < 25:
        return None
    return head[24]


def damage(image: str | bytes) -> Damage | None:
    """Why ``image`` (a path or the bytes of an image) cannot be read as an image, or ``None``.

    A PNG's chunks are walked and their CRCs checked as libpng checks them (:func:`_png_chunks`: a bad
    CRC in an ancillary chunk passes, as libpng drops the chunk; one in a critical chunk fails); one
    without its closing ``IEND`` is decoded, so a file that only lacks it passes (decoders show it whole)
    and one cut between its data chunks does not; a JPEG that does not end with its end-of-image marker has its
    entropy-coded data decoded at 1/8 scale (Pillow's ``draft``), so a file cut short is found without
    decoding its pixels at full size, and a whole one costs a look at its last bytes. Another
    format Pillow identifies is trusted from its header (so is an image above Pillow's decompression-bomb
    limit, about 179 million pixels, which Pillow refuses to open), and one Pillow does not open
    (:data:`OTHER_SIGNATURES`, or OpenImageIO's header reader for a file) from its signature. ``None``
    too for a path that does not exist or is not a regular file: whether it exists is OPBR701's question; a regular
    file that cannot be opened (permission denied) is ``"unreadable"``: no renderer reads it either."""
    if isinstance(image, (bytes, bytearray, memoryview)):
        return _damage(memoryview(image))
    try:
        status = os.stat(image)
    except (OSError, ValueError):
        return None
    if not stat.S_ISREG(status.st_mode):
        return None  # a FIFO or a device is never opened (reading one blocks); a folder is no texture
    return _damage_of_file(image, status.st_size, status.st_mtime_ns)


@functools.lru_cache(maxsize=1024)
def _damage_of_file(path: str, size: int, mtime_ns: int) -> Damage | None:  # size and time: the cache key
    return _damage(path)


def _open(image: str | memoryview):
    return ResourceFile(image) if isinstance(image, memoryview) else open(image, "rb")


def _damage(image: str | memoryview) -> Damage | None:
    try:
        if isinstance(image, memoryview):
            head, size = bytes(image[:512]), len(image)
        else:
            with open(image, "rb") as handle:
                head = handle.read(512)
            size = os.path.getsize(image)
    except OSError as error:
        return Damage("unreadable", f"not readable ({error.strerror or error})")
    except ValueError:
        return None
    if size == 0:
        return Damage("empty", "empty (0 bytes)")
    from PIL import Image  # lazy: as in load_pixels

    with warnings.catch_warnings():  # DecompressionBombWarning, truncation warnings: the library never prints
        warnings.simplefilter("ignore")
        try:
            with _open(image) as handle, Image.open(handle) as opened:
                kind = pillow_format(opened)
        except Image.DecompressionBombError:
            return None  # identified, and larger than Pillow decodes: trusted from its header
        except Exception:  # noqa: BLE001 - Pillow raises many exception types for data it cannot identify
            kind = None
        if kind in ("PNG", "JPEG"):
            return _decoded(image, kind)
    if is_webp(head):
        problem = webp_header_problem(head, size)
        if problem is not None:
            return Damage("corrupt", f"a WebP file {problem}")
        if kind is None and _pillow_reads_webp():
            return Damage("corrupt", f"a WebP file with damaged data ({size} bytes)")
        return None
    if kind is not None or head.startswith(OTHER_SIGNATURES) or (head[4:8] == b"ftyp" and head[8:12] in _ISO_MEDIA_BRANDS):
        return None
    known = next((name for signature, name in _SIGNATURES if head.startswith(signature)), None)
    if known == "PNG":  # Pillow refuses a PNG whose ancillary chunk before the data fails its CRC; libpng drops it
        problem, _ = _png_chunks(image)
        if problem is None and size > 8:
            return None
    if known:
        return Damage("corrupt", f"a {known} file cut short or damaged in its header ({size} bytes)")
    if b"\x00" not in head:
        text = head.decode("utf-8", "replace").lstrip("\ufeff \t\r\n")
        if text.startswith("version https://git-lfs"):
            return Damage("text", "a Git LFS pointer, not the image: the file was never fetched (git lfs pull)")
        if text[:15].lower().startswith(("<!doctype html", "<html")):
            return Damage("text", "an HTML page, not an image (a failed download?)")
        if _SVG.match(text):  # a browser's image decoder draws it; MaterialX's, USD's and glTF's readers decode rasters only
            return Damage("text", "an SVG drawing (vector graphics), which no MaterialX, USD or glTF image reader decodes")
        if "\ufffd" not in text:
            return Damage("text", f"text, not an image ({text.splitlines()[0][:40]!r}...)" if text.strip()
                          else "blank text, not an image")
    if _openimageio_opens(image):
        return None
    return Damage("unrecognised", f"not in any image format this machine recognises (begins {head[:8].hex(' ')})")


#: A PNG without its closing IEND is decoded to tell a file cut short from one that only lacks IEND, and
#: an image is decoded to tell whether it is one flat colour (:func:`varies`), up to this many pixels
#: (8192 x 8192); a larger one is judged by its chunks alone, or not at all, so a header claiming a huge
#: image never makes a check allocate it.
MAX_DECODED_PIXELS = 8192 * 8192


def is_webp(head: bytes) -> bool:
    """Whether ``head`` begins a WebP file: a RIFF container of form ``WEBP``."""
    return head[:4] == b"RIFF" and head[8:12] == b"WEBP"


def suffix_of(head: bytes) -> str | None:
    """The file suffix the bytes ``head`` begins say (PNG, JPEG, WebP, KTX2), or ``None``: what a file extracted
    from a container is named by, whatever MIME type the container declares."""
    if is_webp(head):
        return ".webp"
    return next((suffix for signature, suffix in ((b"\x89PNG", ".png"), (b"\xff\xd8\xff", ".jpg"),
                                                  (b"\xabKTX 20\xbb", ".ktx2")) if head.startswith(signature)), None)


def webp_header_problem(head: bytes, size: int) -> str | None:
    """What is wrong with a WebP file's header (its first 30 bytes), or ``None``: cut short before its image size,
    or a first chunk that is none of ``VP8 ``, ``VP8L`` and ``VP8X`` (the WebP container specification, "Simple File
    Format" and "Extended File Format"), which decoders refuse."""
    first = head[12:16]
    if len(first) == 4 and first not in WEBP_FIRST_CHUNKS:
        return f"whose first chunk is {first.decode('latin-1')!r}, none of 'VP8 ', 'VP8L', 'VP8X'"
    if size < _WEBP_HEADER.get(first, _WEBP_HEADER_DEFAULT):
        return f"cut short in its header ({size} bytes)"
    return None


@functools.cache
def _pillow_reads_webp() -> bool:
    from PIL import features  # lazy: as in load_pixels

    return bool(features.check("webp"))


def _jpeg_segments(image: str | memoryview) -> str | None:
    """What is wrong with a JPEG's marker segments up to its first scan, or ``None``: a segment whose length is below
    2, the length field's own bytes (ITU T.81, B.1.1.4), which libjpeg refuses (JERR_BAD_LENGTH) and the Khronos
    glTF-Validator calls invalid. Read by seeking from marker to marker, never whole."""
    with _open(image) as handle:
        handle.read(2)  # SOI, already identified
        for _ in range(4096):  # a header of more segments than this is not read further
            byte = handle.read(1)
            if byte != b"\xff":
                return None  # cut short or entropy data: the decoder's question
            marker = handle.read(1)
            while marker == b"\xff":  # fill bytes
                marker = handle.read(1)
            if not marker or marker[0] in (0xD9, 0xDA):
                return None  # end of image, or the first scan: its entropy-coded data follows
            if marker[0] == 0x01 or 0xD0 <= marker[0] <= 0xD8:
                continue  # TEM, RSTn, SOI: no length
            length = handle.read(2)
            if len(length) < 2:
                return None
            value = int.from_bytes(length, "big")
            if value < 2:
                return f"with a marker segment (0xFF{marker[0]:02X}) of length {value}, less than its own 2 length bytes"
            handle.seek(value - 2, io.SEEK_CUR)
    return None


def _decoded(image: str | memoryview, kind: str) -> Damage | None:
    from PIL import Image  # lazy: as in load_pixels

    if kind == "JPEG":
        problem = _jpeg_segments(image)
        if problem is not None:
            return Damage("corrupt", f"a JPEG {problem}")
    if kind == "PNG":
        problem, ended = _png_chunks(image)
        if problem is not None:
            return Damage("corrupt", f"a PNG {problem}")
        if ended:
            return None  # every chunk whole and its CRC right, to IEND: not decoded
        # no IEND: decoded below, as decoders show a file that only lacks it whole, and one cut between IDAT chunks short
    if kind == "JPEG" and _ends_with_eoi(image):
        return None  # whole to its end-of-image marker: not decoded (libjpeg shows damage inside as blocks, no error)
    try:
        with _open(image) as handle, Image.open(handle) as opened:
            if kind == "PNG" and opened.size[0] * opened.size[1] > MAX_DECODED_PIXELS:
                return None  # not decoded: judged by its chunks alone
            if kind == "JPEG":
                opened.draft("RGB", (max(1, opened.size[0] // 8), max(1, opened.size[1] // 8)))
            opened.load()
    except Image.DecompressionBombError:
        return None
    except Exception as error:  # noqa: BLE001 - Pillow raises many exception types for damaged data
        return Damage("corrupt", f"a {kind} cut short or with damaged data ({error})")
    return None


def _png_chunks(image: str | memoryview) -> tuple[str | None, bool]:
    """(problem, whether IEND was reached) of a PNG's chunk stream, judged as libpng judges it (PNG
    specification, 5.3 and 13.2): a chunk cut short, or a CRC error in a critical chunk (IHDR, PLTE,
    IDAT, IEND: an upper-case first letter), is damage; a CRC error in an ancillary chunk (tEXt,
    gAMA...) is not, as libpng drops the chunk with a warning. Read in pieces, never whole."""
    with _open(image) as handle:
        handle.read(8)  # the signature, already identified
        first = True
        while True:
            header = handle.read(8)
            if not header:
                return None, False
            if len(header) < 8:
                return "cut short inside a chunk header", False
            length, kind = int.from_bytes(header[:4], "big"), header[4:8]
            name = kind.decode("latin-1")
            if length > 0x7FFFFFFF:
                return f"with a {name} chunk of impossible length {length}", False
            if first and kind != b"IHDR":
                return f"whose first chunk is {name}, not IHDR", False
            first = False
            if kind in PNG_CHUNK_LENGTHS and length != PNG_CHUNK_LENGTHS[kind]:
                return (f"with a {name} chunk of {length} bytes, where the PNG specification fixes "
                        f"{PNG_CHUNK_LENGTHS[kind]}"), False
            crc, left = zlib.crc32(kind), length
            while left:
                piece = handle.read(min(left, 1 << 20))
                if not piece:
                    return f"cut short inside its {name} chunk", False
                crc, left = zlib.crc32(piece, crc), left - len(piece)
            stored = handle.read(4)
            if len(stored) < 4:
                return f"cut short inside its {name} chunk", False
            if int.from_bytes(stored, "big") != crc and kind[:1].isupper():
                return f"with a CRC error in its {name} chunk (damaged data)", False
            if kind == b"IEND":
                return None, True


def openimageio():
    try:
        import OpenImageIO  # lazy: optional (the images extra), ~30 ms; asked only about files Pillow does not open

        return OpenImageIO
    except ImportError:
        return None


def _openimageio_spec(image: str | memoryview):
    """The header (``ImageSpec``) OpenImageIO, when installed, reads from the file at ``image``, or ``None``
    (not installed, not a path it can take, not a format it recognises). Nothing is decoded."""
    oiio = openimageio()
    if oiio is None or not isinstance(image, str) or not utf8(image):
        return None
    try:
        found = oiio.ImageInput.open(image)
    except (TypeError, ValueError, RuntimeError):
        return None
    if found is None:
        oiio.geterror()  # retrieved, so OpenImageIO does not print it
        return None
    spec = found.spec()
    found.close()
    return spec


def _openimageio_opens(image: str | memoryview) -> bool:
    """Whether OpenImageIO, when installed, recognises the file at ``image`` by its header."""
    return _openimageio_spec(image) is not None


def openimageio_size(image: str) -> tuple[int, int] | None:
    """(width, height) of the file at ``image`` from its header, read by OpenImageIO when it is installed
    (any format it knows: OpenEXR, a JPEG above Pillow's decompression-bomb limit), or ``None``."""
    spec = _openimageio_spec(image)
    return (spec.width, spec.height * max(1, spec.depth)) if spec is not None else None


def utf8(path: str) -> bool:
    """Whether OpenImageIO's Python API can take ``path`` (it wants UTF-8; a name from another encoding
    is held as surrogate escapes)."""
    try:
        path.encode("utf-8")
        return True
    except UnicodeEncodeError:
        return False


def _ends_with_eoi(image: str | memoryview) -> bool:
    """Whether a JPEG's last bytes (trailing NUL padding aside) are its end-of-image marker, FF D9
    (ITU T.81, B.2.1): a file cut short cannot end with it, as 0xFF inside the entropy-coded data is
    always followed by a stuffed 0x00 or a restart marker."""
    try:
        if isinstance(image, memoryview):
            tail = bytes(image[-64:])
        else:
            with open(image, "rb") as handle:
                handle.seek(0, os.SEEK_END)
                handle.seek(max(0, handle.tell() - 64))
                tail = handle.read()
    except OSError:
        return False
    return tail.rstrip(b"\0").endswith(b"\xff\xd9")
