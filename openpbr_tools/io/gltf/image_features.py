"""What an image holds that glTF says it should not, read from its header bytes for the Khronos glTF-Validator's
IMAGE_FEATURES_UNSUPPORTED (rules/gltf_images.py, OPBR1233): a PNG's colour-space and pixel-aspect chunks before its
image data, a WebP's VP8X flags. Nothing is decoded; damage is :func:`openpbr_tools.io.image_files.damage`'s question.
"""

from __future__ import annotations

import io
import struct

from ..image_files import ResourceFile


def png_header_chunks(image: str | memoryview, largest: int = 64) -> list[tuple[bytes, bytes | None]]:
    """A PNG's chunks before its image data (IDAT), each ``(type, data)``, the data only of those up to ``largest``
    bytes (``None`` for larger ones: an ICC profile is not read); at most 256 chunks. Empty for anything else."""
    found: list[tuple[bytes, bytes | None]] = []
    try:
        handle = ResourceFile(image) if isinstance(image, memoryview) else open(image, "rb")
    except OSError:
        return found
    with handle:
        if handle.read(8) != b"\x89PNG\r\n\x1a\n":
            return found
        while len(found) < 256:
            header = handle.read(8)
            if len(header) < 8 or header[4:8] in (b"IDAT", b"IEND"):
                break
            length = int.from_bytes(header[:4], "big")
            data = handle.read(length) if length <= largest else None
            if data is not None and len(data) < length:
                break
            if data is None:
                handle.seek(length, io.SEEK_CUR)
            handle.seek(4, io.SEEK_CUR)  # the CRC (the damage checks judge it)
            found.append((header[4:8], data))
    return found


#: cHRM of sRGB (ITU-R BT.709 primaries, D65 white) in the PNG's units of 1/100000, as the PNG specification's sRGB
#: chunk section gives them; gAMA of sRGB (1/2.2, 45455) and of linear data (100000).
SRGB_CHROMATICITIES = (31270, 32900, 64000, 33000, 30000, 60000, 15000, 6000)
PLAIN_GAMMAS = (45455, 100000)


def png_features(chunks) -> list[str]:
    """What a PNG holds that glTF 2.0 says it SHOULD NOT (section 2: "embedded ICC profiles", "non-square pixel
    ratios"; 3.8.4: colour-space information, "gamma values", MUST be ignored) and the Khronos glTF-Validator reports
    (IMAGE_FEATURES_UNSUPPORTED), from the chunks before the image data (nothing is decoded), judged as the validator
    judges them: an ICC profile ("icc_profile", iCCP), chromaticities other than sRGB's ("chromaticities", cHRM) and a
    gamma other than sRGB's or linear ("gamma", gAMA), each unless an sRGB chunk (or, before it, an iCCP) states the
    colour space, as decoders that know sRGB then ignore them; non-square pixels ("non_square_pixels", pHYs). An animation (acTL), which the spec names too, is left
    alone as the validator leaves it: clients show its default image, which is the PNG's first."""
    icc, non_square = False, False
    gamma = primaries = None  # what states each: b"sRGB", b"iCCP", or the cHRM / gAMA feature ("" when plain)
    for kind, data in chunks:
        if kind == b"iCCP":
            icc, gamma, primaries = True, kind, kind
        elif kind == b"sRGB":  # (the PNG specification: decoders that know sRGB ignore gAMA and cHRM)
            gamma = primaries = kind
        elif kind == b"cHRM" and data is not None and len(data) == 32 and primaries is None:
            primaries = "" if struct.unpack(">8I", data) == SRGB_CHROMATICITIES else "chromaticities"
        elif kind == b"gAMA" and data is not None and len(data) == 4 and gamma is None:
            gamma = "" if struct.unpack(">I", data)[0] in PLAIN_GAMMAS else "gamma"
        elif kind == b"pHYs" and data is not None and len(data) == 9:
            non_square = non_square or data[:4] != data[4:8]
    return ((["icc_profile"] if icc else []) + [state for state in (primaries, gamma) if isinstance(state, str) and state]
            + (["non_square_pixels"] if non_square else []))


def webp_features(head: bytes) -> list[str]:
    """What an extended WebP states in its VP8X flags that the Khronos glTF-Validator reports as unsupported
    (IMAGE_FEATURES_UNSUPPORTED): an ICC profile ("icc_profile", flag 0x20) or an animation ("animation", 0x02), whose
    frames glTF has no way to play (viewers show the first or nothing)."""
    if head[12:16] != b"VP8X" or len(head) < 21:
        return []
    flags = head[20]
    return [name for bit, name in ((0x20, "icc_profile"), (0x02, "animation")) if flags & bit]
