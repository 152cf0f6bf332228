"""Texture lookups for the evaluator: a material's texture references read at the preview
geometry's UV coordinates, so previews and ``--verify`` see the textures, not their fallbacks.

Conventions (every reader stores textures in MaterialX's, see :mod:`openpbr_tools.io.gltf.uv`):

* UV space has its origin at the image's bottom-left corner with V up: texel row 0 (the top of
  the file) is at v = 1. A texel's centre is at ``((i + 0.5) / W, 1 - (j + 0.5) / H)``.
* ``Texture.uv`` is a ``place2d`` (operation order SRT, MaterialX ``NG_place2d_vector2``):
  ``uv' = rotate2d((uv - pivot) / scale, rotate) - offset + pivot``, where ``rotate2d`` maps
  ``(x, y)`` to ``(c x + s y, -s x + c y)`` with the angle in degrees (MaterialX stdlib). glTF's
  ``KHR_texture_transform`` and USD's ``UsdTransform2d`` arrive converted to it by their readers.
* Wrap modes: MaterialX ``periodic``, ``clamp``, ``mirror``, ``constant`` (outside [0, 1] the
  lookup gives 0, the ``image`` node's default); UsdUVTexture's ``repeat``, ``clamp``, ``mirror``,
  ``black`` and ``useMetadata`` (taken as ``repeat``, what Storm does without metadata); glTF's
  arrive as MaterialX names. Unset means periodic (MaterialX and glTF defaults).
* Filtering: bilinear between texel centres on a mip-map pyramid (2 x 2 box reduction), with the
  level chosen per pixel from the UV footprint of the pixel (the larger of its two screen-space
  derivatives, as OpenGL's ``GL_LINEAR_MIPMAP_LINEAR``, MaterialX's GLSL texture handler's mode)
  and two levels blended linearly. Colours are decoded to linear Rec.709 before filtering (the
  document's colour management, :mod:`openpbr_tools.colorspaces`, through the baker's
  :meth:`~openpbr_tools.bake.Baker.texels`: channels, colour space, ``scale``/``bias``).
* UDIM sets: tile ``1001 + floor(u) + 10 floor(v)`` is read at ``frac(u), frac(v)``; a missing
  tile reads 0 and is reported.
* Normal maps (``Texture.normal_map`` set): a MaterialX ``normalmap`` or glTF ``normalTexture``
  decodes ``n = 2 t - 1`` and scales ``n.xy`` by the strength (MaterialX ``NG_normalmap``; glTF 2.0
  section 3.9.3); a UsdUVTexture feeding UsdPreviewSurface's ``normal``, or MaterialX multiply/add
  nodes feeding it (``Texture.decoded_by_scale_bias``), is used as ``t * scale + bias``
  (UsdPreviewSurface specification: the texture's scale and bias do the decode). The
  result is a tangent-space vector (x along the tangent, y along the bitangent, z along the
  normal), normalised by the caller's frame.

Images are located through the baker's :class:`~openpbr_tools.io.images.ImageLocator`, so the one
path guard decides which files may be read. :class:`TextureUnavailable` carries the reason a
texture could not be sampled; the caller falls back to the texture's fallback value and says so.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

import numpy as np

from .. import colorspaces
from ..model import Texture

LINEAR_REC709 = "lin_rec709"
WRAP_NAMES = {"periodic": "periodic", "repeat": "periodic", "useMetadata": "periodic", "clamp": "clamp",
              "mirror": "mirror", "constant": "constant", "black": "constant"}
UV_TEXTURE = "UsdUVTexture"


class TextureUnavailable(ValueError):
    """A texture the sampler cannot read (missing, refused by the path guard, undecodable, a
    procedural input); the message says which and why."""


@dataclass
class UVs:
    """Texture coordinates of N shading points, and their screen-space derivatives (per pixel
    step in x and in y), from which the sampler picks a mip level."""

    uv: np.ndarray  # (N, 2)
    dx: np.ndarray  # (N, 2)
    dy: np.ndarray  # (N, 2)


def place2d(uv: np.ndarray, transform) -> np.ndarray:
    """Apply a :class:`~openpbr_tools.model.UVTransform` (``place2d``, see the module docstring)
    to ``(N, 2)`` coordinates."""
    if transform is None:
        return uv
    p = np.asarray(transform.pivot, dtype=float)
    s = np.asarray(transform.scale, dtype=float)
    with np.errstate(divide="ignore", invalid="ignore"):
        q = (uv - p) / s
    c, sn = math.cos(math.radians(transform.rotate)), math.sin(math.radians(transform.rotate))
    rotated = np.stack([c * q[:, 0] + sn * q[:, 1], -sn * q[:, 0] + c * q[:, 1]], axis=-1)
    return rotated - np.asarray(transform.offset, dtype=float) + p


def _linear_part(transform, d: np.ndarray) -> np.ndarray:
    """Derivatives through place2d: only its linear part (scale, rotation) acts on them."""
    if transform is None:
        return d
    s = np.asarray(transform.scale, dtype=float)
    with np.errstate(divide="ignore", invalid="ignore"):
        q = d / s
    c, sn = math.cos(math.radians(transform.rotate)), math.sin(math.radians(transform.rotate))
    return np.stack([c * q[:, 0] + sn * q[:, 1], -sn * q[:, 0] + c * q[:, 1]], axis=-1)


def _wrap_index(index: np.ndarray, size: int, mode: str) -> np.ndarray:
    if mode == "periodic":
        return np.mod(index, size)
    if mode == "mirror":
        period = np.mod(index, 2 * size)
        return np.where(period >= size, 2 * size - 1 - period, period)
    return np.clip(index, 0, size - 1)  # clamp, and constant (whose outside is zeroed by the caller)


def _pyramid(image: np.ndarray) -> list[np.ndarray]:
    """Mip levels of ``image`` (H, W, C), each a 2 x 2 box reduction of the one before (an odd
    edge repeats its last row or column), down to 1 x 1."""
    levels = [np.ascontiguousarray(image)]
    while max(levels[-1].shape[:2]) > 1:
        level = levels[-1]
        h, w, c = level.shape
        if h % 2 and h > 1:
            level = np.concatenate([level, level[-1:]], axis=0)
        if w % 2 and w > 1:
            level = np.concatenate([level, level[:, -1:]], axis=1)
        h, w = level.shape[:2]
        if h > 1:  # pairs of rows, then pairs of columns: contiguous sums, the fastest NumPy way
            rows = level.reshape(h // 2, 2, w, c)
            level = (rows[:, 0] + rows[:, 1]) * np.float32(0.5)
        if w > 1:
            columns = level.reshape(level.shape[0], w // 2, 2, c)
            level = (columns[:, :, 0] + columns[:, :, 1]) * np.float32(0.5)
        levels.append(np.ascontiguousarray(level, dtype=np.float32))
    return levels


def _bilinear(image: np.ndarray, uv: np.ndarray, wrap: tuple[str, str]) -> np.ndarray:
    h, w = image.shape[:2]
    x = uv[:, 0] * w - 0.5
    y = (1.0 - uv[:, 1]) * h - 0.5
    x0, y0 = np.floor(x), np.floor(y)
    fx, fy = (x - x0)[:, None], (y - y0)[:, None]
    x0, y0 = x0.astype(np.int64), y0.astype(np.int64)
    xa, xb = _wrap_index(x0, w, wrap[0]), _wrap_index(x0 + 1, w, wrap[0])
    ya, yb = _wrap_index(y0, h, wrap[1]), _wrap_index(y0 + 1, h, wrap[1])
    top = image[ya, xa] * (1.0 - fx) + image[ya, xb] * fx
    bottom = image[yb, xa] * (1.0 - fx) + image[yb, xb] * fx
    return top * (1.0 - fy) + bottom * fy


def filtered(levels: list[np.ndarray], uvs: UVs, wrap: tuple[str, str]) -> np.ndarray:
    """Trilinear lookup of a mip pyramid at ``uvs`` (see the module docstring)."""
    h, w = levels[0].shape[:2]
    fx = np.hypot(uvs.dx[:, 0] * w, uvs.dx[:, 1] * h)
    fy = np.hypot(uvs.dy[:, 0] * w, uvs.dy[:, 1] * h)
    footprint = np.maximum(np.maximum(fx, fy), 1e-12)
    lod = np.clip(np.log2(footprint), 0.0, len(levels) - 1)
    lod = np.where(np.isfinite(lod), lod, 0.0)
    base = np.floor(lod).astype(np.int64)
    frac = (lod - base)[:, None]
    out = np.zeros((uvs.uv.shape[0], levels[0].shape[2]))
    for level in np.unique(base):
        sel = base == level
        low = _bilinear(levels[level], uvs.uv[sel], wrap)
        if level + 1 < len(levels) and np.any(frac[sel] > 0):
            high = _bilinear(levels[level + 1], uvs.uv[sel], wrap)
            low = low * (1.0 - frac[sel]) + high * frac[sel]
        out[sel] = low
    for axis, mode in enumerate(wrap):
        if mode == "constant":
            outside = (uvs.uv[:, axis] < 0.0) | (uvs.uv[:, axis] > 1.0)
            out[outside] = 0.0
    return out


class TextureSampler:
    """Reads texture references at UV coordinates (see the module docstring).

    ``readers`` are :class:`~openpbr_tools.bake.Baker` instances able to locate and decode images
    (the first that can read a texture is used): a conversion passes its own (source folder and
    images it baked) and one anchored at its output. Decoded, colour-managed images and their
    pyramids are cached for the sampler's life.
    """

    def __init__(self, readers):
        self.readers = list(readers)
        self._cache: dict = {}
        self.notes: list[tuple[str, str]] = []  # (owner, what was approximated), e.g. a missing UDIM tile

    @classmethod
    def for_asset(cls, path: str, allow_outside: tuple[str, ...] = ()) -> "TextureSampler":
        import tempfile  # lazy: only for the anchor folder of a reader that never writes

        from ..bake import Baker  # lazy: the baker imports the translators

        return cls([Baker(path, tempfile.gettempdir(), tuple(allow_outside))])

    def _prepared(self, texture: Texture, type_name: str, owner: str) -> list[np.ndarray]:
        """The mip pyramid of ``texture`` for a parameter of ``type_name``: a colour's selected
        channels in linear Rec.709; for anything else every channel of the image as decoded (the
        channels are picked after filtering, so the parameters reading one packed image share it)."""
        colour = type_name == "color3"
        key = (texture.file, texture.packaged, texture.location.file if texture.location else None,
               (texture.channels, texture.colorspace) if colour else None)
        if key in self._cache:
            cached = self._cache[key]
            if isinstance(cached, TextureUnavailable):
                raise cached
            return cached
        from ..translate.common import BakeError  # lazy: the translators load only when a texture is read

        errors = []
        for reader in self.readers:
            try:
                values = _decoded(reader, texture, colour, owner)
                break
            except BakeError as error:
                errors.append(str(error))
        else:
            failure = TextureUnavailable(errors[0] if errors else f"{owner}: {texture.file!r} cannot be read")
            self._cache[key] = failure
            raise failure
        self._cache[key] = levels = _pyramid(values)
        return levels

    def resolution(self, texture: Texture) -> tuple[int, int] | None:
        """(width, height) of ``texture``'s image, or None when it cannot be read (or is a UDIM set)."""
        if texture.is_udim:
            return None
        from ..translate.common import BakeError  # lazy: as in _prepared

        for reader in self.readers:
            try:
                return reader.size(texture, texture.file)
            except BakeError:
                continue
        return None

    def _tiles(self, texture: Texture, type_name: str, owner: str, tile_numbers) -> dict:
        tiles = {}
        for number in tile_numbers:
            file = texture.file.replace("<UDIM>", str(number))
            try:
                tiles[number] = self._prepared(dataclasses.replace(texture, file=file), type_name, owner)
            except TextureUnavailable:
                tiles[number] = None
        return tiles

    def sample(self, texture: Texture, type_name: str, uvs: UVs, owner: str) -> np.ndarray:
        """``texture``'s values at ``uvs`` for a parameter of ``type_name``: ``(N, 3)`` for colours
        and vectors (colours in linear Rec.709), ``(N,)`` otherwise; normal maps as tangent-space
        vectors ``(N, 3)``. Channels are those the texture names (else R for a float, RGB for a
        colour or vector; a single channel read by a colour is grey), then ``scale`` and ``bias``
        apply, as :meth:`~openpbr_tools.bake.Baker.texels` defines them. Raises
        :class:`TextureUnavailable`."""
        normal = texture.normal_map is not None
        wide = type_name in ("color3", "color4", "vector3") or normal
        read_as = "color3" if type_name in ("color3", "color4") and not normal else "data"
        wrap = tuple(WRAP_NAMES.get(m, "periodic") for m in (texture.wrap or ("periodic", "periodic")))
        uv = place2d(uvs.uv, texture.uv)
        moved = UVs(uv, _linear_part(texture.uv, uvs.dx), _linear_part(texture.uv, uvs.dy))
        if texture.is_udim:
            values = self._udim(texture, read_as, moved, wrap, owner)
        else:
            values = filtered(self._prepared(texture, read_as, owner), moved, wrap)
        if read_as == "data":
            values = np.stack([values[:, c] if c < values.shape[1] else np.ones(len(values))
                               for c in texture.selected_channels(3 if wide else 1)], axis=-1)
        if texture.scale is not None:
            values = values * np.asarray(_width(texture.scale, values.shape[1]), dtype=float)
        if texture.bias is not None:
            values = values + np.asarray(_width(texture.bias, values.shape[1]), dtype=float)
        if normal:
            if texture.node_category != UV_TEXTURE and not texture.decoded_by_scale_bias:
                values = 2.0 * values - 1.0
                values[:, :2] *= float(texture.normal_map)
            return values
        return values if wide else values[:, 0]

    def _udim(self, texture: Texture, type_name: str, uvs: UVs, wrap, owner: str) -> np.ndarray:
        tile_u, tile_v = np.floor(uvs.uv[:, 0]).astype(np.int64), np.floor(uvs.uv[:, 1]).astype(np.int64)
        numbers = 1001 + tile_u + 10 * tile_v
        valid = (tile_u >= 0) & (tile_u < 10) & (tile_v >= 0)
        tiles = self._tiles(texture, type_name, owner, sorted(set(numbers[valid].tolist())))
        found = [t for t in tiles.values() if t is not None]
        if not found:
            raise TextureUnavailable(f"{owner}: no tile of the UDIM set {texture.file!r} can be read")
        out = np.zeros((uvs.uv.shape[0], found[0][0].shape[2]))
        local = uvs.uv - np.stack([tile_u, tile_v], axis=-1)
        for number, levels in tiles.items():
            if levels is None:
                continue
            sel = valid & (numbers == number)
            out[sel] = filtered(levels, UVs(local[sel], uvs.dx[sel], uvs.dy[sel]), ("clamp", "clamp"))
        missing = sorted(n for n, t in tiles.items() if t is None)
        if missing:
            self.notes.append((owner, f"UDIM tile(s) {', '.join(map(str, missing))} of {texture.file!r} missing, read as 0"))
        return out


def _decoded(reader, texture: Texture, colour: bool, owner: str) -> np.ndarray:
    """The image of ``texture`` as float32 ``(H, W, C)``: a colour's channels (its own, else RGB; one
    channel is grey) converted to linear Rec.709 from its colour space (the baker's rules), anything
    else every channel as decoded (greyscale expanded to RGB, alpha last, as the baker reads it)."""
    pixels = reader.pixels(texture, owner)  # greyscale already expanded to RGB (io.images.load_pixels)
    eight_bit = pixels.dtype == np.uint8
    if not colour:
        return pixels.astype(np.float32) * np.float32(1.0 / 255.0) if eight_bit else pixels.astype(np.float32)
    channels = list(texture.channels) if texture.channels else [0, 1, 2]
    channels = (channels * 3)[:3]
    if all(c < pixels.shape[2] for c in channels) and channels != [0, 1, 2]:
        pixels = pixels[:, :, channels]
    elif channels != [0, 1, 2] or pixels.shape[2] != 3:
        full = 255 if eight_bit else 1.0
        pixels = np.stack([pixels[:, :, c] if c < pixels.shape[2] else np.full(pixels.shape[:2], full, pixels.dtype)
                           for c in channels], axis=-1)
    space = reader.source_space(texture, LINEAR_REC709, owner)
    if eight_bit:
        return colorspaces.levels_to_lin_rec709(pixels, space, np.float32)
    values = colorspaces.to_lin_rec709(pixels, space) if space is not None else pixels
    return np.asarray(values, dtype=np.float32)


def _width(value, width: int):
    """A scale or bias in the width of the values it applies to (UsdUVTexture's float4 by channel
    is already selected by the reader; a longer tuple is cut, a number broadcasts)."""
    if isinstance(value, (list, tuple)):
        return tuple(value[:width]) if len(value) >= width else value
    return value

