"""What a texture's pixels hold that no header says (the red team's round seven): a normal map whose decoded
normals point into the surface (its blue channel inverted with the green), a 16-bit image holding 8-bit values
(an exporter that changed the container's depth without rescaling), NaN or infinite texels in a floating-point
bake, and an OpenEXR whose data window is a crop of its display window.

Pixels are decoded as little as answers: 8-bit images through Pillow's histograms (a JPEG at 1/8 scale), OpenEXR
and Radiance files through OpenImageIO (the images extra; without it those are not judged), each image once and
only up to :data:`MAX_INSPECTED_PIXELS`.
"""

from __future__ import annotations

import base64
import zlib

from ..diagnostics import Severity
from ..io.image_content import channel_statistics, sixteen_bit_peak
from . import Rule, for_each_input
from .texture_content import _format, _readable
from .textures import image_of

#: Images up to this many pixels (4096 x 4096) are inspected; a larger one is not.
MAX_INSPECTED_PIXELS = 4096 * 4096

_NORMAL = ('<image name="nmap" type="vector3">\n  <input name="file" type="filename" value="{file}" />\n</image>\n'
           '<normalmap name="nm" type="vector3">\n  <input name="in" type="vector3" nodename="nmap" />\n</normalmap>\n'
           '<open_pbr_surface name="S" type="surfaceshader">\n  <input name="geometry_normal" type="vector3" '
           'nodename="nm" />\n</open_pbr_surface>')
_INWARD_NORMAL = bytes.fromhex("89504e470d0a1a0a0000000d4948445200000002000000020802000000fdd49a7300000016494441547"
                               "89c636c68606060606062606060606000000caa0104955b793c0000000049454e44ae426082")
NORMALS_INWARD = Rule(
    "OPBR724", "normal-map-points-inward", Severity.ERROR,
    "A tangent-space normal map whose blue channel is mostly below one half: decoded, its normals point into the "
    "surface.",
    "A normal map's blue channel holds the normal's z, along the surface normal: 2b - 1 is 0 at mid-grey and +1 for "
    "an unperturbed surface, so a tangent-space map is bluish (b near 1). Below one half the decoded normals face "
    "into the surface and the shading is lit from behind: an 'invert' applied to the whole image instead of its "
    "green channel (a DirectX to OpenGL conversion), a height map's channels in the wrong order, or another image "
    "(the base colour) plugged into the normal slot. MaterialX's normalmap and glTF's normalTexture decode it as "
    "written: glTF 2.0 (3.9.3, material.normalTexture) reads \"the XYZ components of a normal vector in tangent "
    "space\" (\"+Z points toward the viewer\"), unpacked as 2 texel - 1; so is KHR_materials_clearcoat's "
    "clearcoatNormalTexture.",
    passing=_NORMAL.format(file="normal.png"), failing=_NORMAL.format(file="normal.png"),
    example_files=("normal.png",), failing_files=(("normal.png", _INWARD_NORMAL),),
)
_ROUGH = ('<image name="rough" type="float">\n  <input name="file" type="filename" value="rough.png" />\n</image>\n'
          '<open_pbr_surface name="S" type="surfaceshader">\n  <input name="specular_roughness" type="float" '
          'nodename="rough" />\n</open_pbr_surface>')
_GREY16_LOW = bytes.fromhex("89504e470d0a1a0a0000000d4948445200000002000000021000000000074d8ebb0000001249444154789c"
                            "6360486138c1c0f08fc108000b06025dbc6e051a0000000049454e44ae426082")
EIGHT_BIT_IN_SIXTEEN = Rule(
    "OPBR725", "eight-bit-values-in-16-bit-image", Severity.ERROR,
    "A 16-bit greyscale image whose largest sample is at most 255 of 65535: 8-bit values written into a 16-bit "
    "file.",
    "A 16-bit image's samples are read over 0-65535, so a value of 254 meant as 254/255 reads as 0.004: a rough "
    "concrete renders as a mirror, a mask as black. Exporters that change the container's bit depth without "
    "rescaling write such files. Re-export the image at 8 bits, or scale its values by 257.",
    passing=_ROUGH, failing=_ROUGH, example_files=("rough.png",),
    failing_files=(("rough.png", _GREY16_LOW),),
)
# 2 x 2 half-float OpenEXR files (zlib, base64): with a NaN and an infinity; a crop of an 8 x 8 frame
_EXR_NOT_FINITE = ("eNqFT01LAzEQfZEePHgQ/AP9B3YDtmUv4gd4FHrpOSZTdyAmIRlqBRHBP+52u9KtPXSGGYY3771h1teVOgNgTXo0QiiSObziqoX0"
                   "RE/rqqr1bDzR9Y2uq6ltTAjkC2zjuQhmLe0eCrtQfT0dIYsjBDa+pUylcAwHc7d0RsySg4vveIkbzbjEPv4sHJfkzcdJnudAz9lR"
                   "HkzdlcQb8nclkZWFEY5Y+WgEo079fVtsJgo7+wcK0srWeoXzwYkhZclOmn8WiP3fP2ovuti2eZ9fmKtD7HPbfwHOQ07c")
_EXR_CROP = ("eNptT01LAzEQfWsLevBQ8A/4D+wGbGUv4gd4FHrpOSZTdyAmIRlqvQn+cbfbiKvbGR55vLy8mWyv6uoEgNHxUQshS2L/iotOUnO1"
             "aOq6UcvLuWquVVMvTKu9J5dhWsdZsOxs96hwqKrgaaSsRgpMeIuJcubg//D+0mrRa/Y2vOMl7BRj1omTgmmB5Ryd/hj5fuq0wLGn"
             "52QpDVg/JfKO3F2OZGSlhQM2Lmjps4HP22wSkT/EP5CX7tlWbXA2GDG0rNlK+y8Cofz7q5z7/c/35Oa3p0e0b9rZTnA=")


def _exr(text: str) -> bytes:
    return zlib.decompress(base64.b64decode(text))


_EXR = ('<image name="albedo" type="color3">\n  <input name="file" type="filename" value="albedo.exr" '
        'colorspace="lin_rec709" />\n</image>\n<open_pbr_surface name="S" type="surfaceshader">\n  <input '
        'name="base_color" type="color3" nodename="albedo" />\n</open_pbr_surface>')
NON_FINITE = Rule(
    "OPBR726", "texture-not-finite", Severity.ERROR,
    "A floating-point texture (OpenEXR, Radiance HDR) holds NaN or infinite texels.",
    "A NaN or an infinity spreads through texture filtering (every mipmap level above it, every bilinear lookup "
    "that touches it) and through the shading into the image: black or white speckles that grow with distance, "
    "and fireflies that never converge in a path tracer. Usually a bake that divided by zero. Clamp or fill the "
    "texels.",
    passing=_EXR, failing=_EXR, example_files=("albedo.exr",), failing_files=(("albedo.exr", _exr(_EXR_NOT_FINITE)),),
)
DATA_WINDOW_CROP = Rule(
    "OPBR727", "exr-data-window-crop", Severity.WARNING,
    "An OpenEXR texture's data window is smaller than its display window (an auto-cropped render).",
    "OpenEXR lets a file store only a crop (its data window) of the full image (its display window). Texture "
    "loaders differ on it: some place the crop in the full frame with black around it, others read the crop alone "
    "and stretch it over the UVs, so the texture is misplaced or scaled per renderer. Write the full frame.",
    passing=_EXR, failing=_EXR, example_files=("albedo.exr",), failing_files=(("albedo.exr", _exr(_EXR_CROP)),),
)

RULES = (NORMALS_INWARD, EIGHT_BIT_IN_SIXTEEN, NON_FINITE, DATA_WINDOW_CROP)


def check(asset, context):
    # each file judged once as an image, and once more as a normal map if some input reads it as one (a glTF
    # normalTexture pointing at the base colour image: the base colour came first, and its file was then seen)
    seen: set = set()
    for material, table, entry in for_each_input(asset):
        texture = entry.texture
        if texture is None or not texture.file.strip():
            continue
        as_normal = (texture.file, "normal") if texture.normal_map is not None else None
        if texture.file in seen and (as_normal is None or as_normal in seen):
            continue
        again = texture.file in seen  # the file's own checks are done: only the normal map's is left
        seen.update(key for key in (texture.file, as_normal) if key is not None)
        where = texture.location or entry.location
        if texture.packaged or texture.node_category == "gltf_texture":
            source = image_of(asset, texture, context, {})
            name, real = texture.file, source
        else:
            files = _readable(asset, texture, context)
            if not files:
                continue
            name, real = files[0]
        if real is None:
            continue
        found = _format(real) if isinstance(real, str) else None
        if found in ("OpenEXR", "Radiance HDR"):
            if not again:
                yield from _floating_point(name, real, found, where, context)
            continue
        if texture.normal_map is not None:
            statistics = channel_statistics(real, MAX_INSPECTED_PIXELS)
            if statistics is not None and len(statistics) >= 3 and statistics[2].mean < 127.5 - 2:
                z = 2 * statistics[2].mean / 255 - 1
                yield context.diagnostic(
                    NORMALS_INWARD, f"{entry.name}: the normal map {name!r} has a mean blue of "
                    f"{statistics[2].mean / 255:.2f}, so its decoded normals point into the surface (mean z {z:.2f})",
                    where, hint="invert only the green channel (DirectX to OpenGL), or restore the blue channel")
        peak = sixteen_bit_peak(real, MAX_INSPECTED_PIXELS) if not again else None
        if peak is not None and 0 < peak <= 255:
            yield context.diagnostic(
                EIGHT_BIT_IN_SIXTEEN, f"{entry.name}: {name!r} is a 16-bit image whose largest sample is {peak} of 65535 "
                f"({peak / 65535:.4f}): 8-bit values in a 16-bit file", where,
                hint="re-export it at 8 bits, or scale its values by 257")


def _floating_point(name, path, found, where, context):
    try:
        import OpenImageIO as oiio  # lazy: the images extra; only for a floating-point texture
    except ImportError:
        return
    opened = oiio.ImageInput.open(path)
    if opened is None:
        oiio.geterror()
        return
    spec = opened.spec()
    opened.close()
    if found == "OpenEXR" and (spec.width, spec.height, spec.x, spec.y) != \
            (spec.full_width, spec.full_height, spec.full_x, spec.full_y) and spec.width * spec.height < \
            spec.full_width * spec.full_height:
        yield context.diagnostic(
            DATA_WINDOW_CROP, f"{name!r} stores a {spec.width} x {spec.height} crop at ({spec.x}, {spec.y}) of a "
            f"{spec.full_width} x {spec.full_height} image: loaders place or stretch the crop differently", where,
            hint="write the full frame (no data-window crop)")
    if spec.width * spec.height > MAX_INSPECTED_PIXELS:
        return
    buffer = oiio.ImageBuf(path)
    statistics = oiio.ImageBufAlgo.computePixelStats(buffer)
    failed = buffer.has_error
    buffer.geterror()
    if failed or statistics is None:
        return
    nans, infinities = sum(statistics.nancount), sum(statistics.infcount)
    if nans or infinities:
        what = " and ".join(part for part in (f"{nans} NaN" if nans else "", f"{infinities} infinite" if infinities
                                              else "") if part)
        yield context.diagnostic(
            NON_FINITE, f"{name!r} holds {what} sample{'s' if nans + infinities > 1 else ''}: they spread through "
            "filtering and shading", where, hint="clamp or fill the texels (a bake that divided by zero)")

