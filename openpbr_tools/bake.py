"""Baking: a translation formula applied texel by texel to the textures that feed it.

When a target parameter is a function of a textured source parameter that is not the identity
(glTF's roughness from OpenPBR's roughness and anisotropy, a base colour mixed with a transmission
colour, a coat darkening folded into the base colour...), :class:`Baker` evaluates the *same*
vectorised NumPy formula the constant path uses on every texel and encodes the result as a new
image. What happens, in order:

1. every textured source is located with the writers' path rules (inside the source asset's folder
   or a folder the caller allowed; never a URL; images inside a glTF are extracted from it) and
   decoded (Pillow; OpenImageIO for EXR/HDR);
2. its channels are selected (``Texture.channels``, else R for a float and RGB for a colour), a
   colour is converted from the texture's colour space to linear Rec.709, where the target shades
   and every formula runs (colour-science), then ``scale``/``bias`` apply;
3. all textured sources must share their UV transform and texture coordinates (a texel of one is
   then a texel of the other); sources of different sizes are resampled (bilinear) to the largest;
4. constant sources broadcast (colours converted to linear Rec.709 too): floats arrive as
   ``(H, W, 1)`` or ``()``, colours as ``(H, W, 3)`` or ``(3,)``;
5. the result is encoded: a colour in linear Rec.709 as an 8-bit sRGB PNG (``srgb_texture``), in
   another working space as a 16-bit linear PNG in that space (OpenImageIO), a float as a 16-bit
   greyscale PNG (raw). Values outside [0, 1] go to a half-float OpenEXR (OpenImageIO) unless the
   output can only hold PNG (glTF), where they are clipped and the clipping is reported.

Baked images keep the UV transform, texture coordinates and wrap modes of their sources, and a
resolution equal to the largest source. UDIM sets, normal maps under a formula and procedural
graphs are not baked (the caller reports them). The images live in :attr:`Baker.images` until the
caller writes them; nothing is written here.
"""

from __future__ import annotations

import io
import os
import re
import tempfile
import warnings
from dataclasses import dataclass, field

import numpy as np

from . import bake_cache, colorspaces
from .io.images import ImageLocator, ImageRefused, ImageUnavailable, load_pixels, resample
from .model import Connection, Constant, Input, Texture
from .translate.common import BakeError
from .translate.target import WorkingSpace

LINEAR_REC709 = "lin_rec709"


@dataclass(slots=True)
class Baked:
    """What :meth:`Baker.bake` produced: an input (a texture or, where every texel agrees, a
    constant) and a sentence for the report."""

    input: Input
    message: str
    clipped: float = 0.0  # fraction of texels clipped to [0, 1] by a PNG-only output
    averages: dict = field(default_factory=dict)  # each textured source's mean value


@dataclass(slots=True)
class Baker:
    """Bakes formulas over textures for one conversion.

    ``source_path``: the asset textures resolve against. ``folder``: where the caller will write the
    baked images (their ``Texture.file`` is an absolute path there). ``allow_outside``: folders
    outside the asset's from which textures may be read. ``png_only``: the output takes only PNG
    and JPEG (glTF).
    """

    source_path: str
    folder: str
    allow_outside: tuple[str, ...] = ()
    png_only: bool = False
    images: dict[str, bytes] = field(default_factory=dict)  # absolute path -> encoded image
    _pixels: dict = field(default_factory=dict)
    _locator: ImageLocator | None = None

    # -- reading ----------------------------------------------------------------------------
    def _resolve(self, texture: Texture, owner: str):
        if self._locator is None:
            self._locator = ImageLocator(self.source_path, self.folder, self.allow_outside)
        try:
            return self._locator.locate(texture, owner)
        except (ImageRefused, ImageUnavailable) as error:
            raise BakeError(str(error)) from None

    def _load(self, texture: Texture, owner: str, levels: bool = False):
        key = ("baked", texture.file)
        if key in self._pixels:  # baked by an earlier step of this conversion: decoded on first use
            if isinstance(self._pixels[key], tuple):
                self._pixels[key] = _as_read(*self._pixels[key])
            return self._pixels[key]
        located = self._resolve(texture, owner)
        key = located.key + ("levels",) if levels else located.key
        if key not in self._pixels:
            try:
                self._pixels[key] = bake_cache.decoded(located, levels)
            except Exception as error:  # noqa: BLE001 - Pillow and OpenImageIO raise many types for undecodable data
                raise BakeError(f"{owner}: {texture.file!r} cannot be decoded ({error})") from None
        return self._pixels[key]

    def pixels(self, texture: Texture, owner: str):
        """The decoded image of ``texture``, read once per conversion, with no channel selection, colour
        management, scale or bias: uint8 levels ``(H, W, C)`` for an 8-bit image, else float ``(H, W, C)``
        in [0, 1] as :meth:`texels` reads it (greyscale expanded to RGB in both).
        ``BakeError`` when it cannot be read."""
        return self._load(texture, owner, levels=True)

    def size(self, texture: Texture, owner: str) -> tuple[int, int]:
        """(width, height) of ``texture``'s image, from its header where Pillow reads it (no decode)."""
        located = self._resolve(texture, owner)
        try:
            from PIL import Image  # lazy: as in load_pixels

            with warnings.catch_warnings():  # DecompressionBombWarning: the library never prints
                warnings.simplefilter("ignore")
                opened = Image.open(io.BytesIO(located.image) if isinstance(located.image, bytes) else located.image)
            with opened:
                return opened.size
        except Exception:  # noqa: BLE001 - not an image Pillow opens (EXR...): decode it
            pixels = self._load(texture, owner)
            return pixels.shape[1], pixels.shape[0]

    def source_space(self, texture: Texture, working_space: str, owner: str) -> str | None:
        """The colour space a colour texture's texels are converted from (``None``: used as they are,
        the working space or data); ``BakeError`` for a name that is not a known colour space."""
        space = colorspaces.materialx_name(texture.colorspace)
        if space is None or space == working_space or colorspaces.is_data(space):
            return None
        if space not in colorspaces.materialx_names():
            raise BakeError(f"{owner}: colour space {texture.colorspace!r} of {texture.file!r} is unknown, "
                            "so its texels cannot be decoded")
        return space

    def texels(self, texture: Texture, type_name: str, working_space: str, owner: str):
        """The texture's values for a parameter of ``type_name``: ``(H, W, 1)`` or ``(H, W, 3)``,
        in the working space, after scale and bias."""
        if texture.is_udim:
            raise BakeError(f"{owner}: UDIM set {texture.file!r} is not baked")
        if texture.normal_map is not None:
            raise BakeError(f"{owner}: normal map {texture.file!r} cannot go through a formula")
        pixels = self._load(texture, owner)
        width = 3 if type_name in ("color3", "vector3") else 1
        planes = [pixels[:, :, c] if c < pixels.shape[2] else np.ones(pixels.shape[:2])
                  for c in texture.selected_channels(width)]
        values = np.stack(planes, axis=-1)
        if width == 3 and type_name == "color3":
            space = self.source_space(texture, working_space, owner)
            if space is not None:
                values = colorspaces.from_lin_rec709(colorspaces.to_lin_rec709(values, space), working_space)
        if texture.scale is not None:
            values = values * np.asarray(texture.scale, dtype=np.float64)
        if texture.bias is not None:
            values = values + np.asarray(texture.bias, dtype=np.float64)
        return np.asarray(values, dtype=np.float64)

    def mean(self, texture: Texture, type_name: str, owner: str):
        """The texture's mean value for a parameter of ``type_name`` in linear Rec.709 (a float, or a
        3-tuple for a colour or vector), averaged over its texels after channels, colour space, scale
        and bias: what ``convert --verify`` evaluates a textured input at. ``BakeError`` when the
        image cannot be read or is not a plain lookup (UDIM set, normal map)."""
        values = self.texels(texture, type_name, LINEAR_REC709, owner)
        flat = values.reshape(-1, values.shape[-1]).mean(axis=0)
        return float(flat[0]) if flat.size == 1 else tuple(float(v) for v in flat)

    # -- baking -----------------------------------------------------------------------------
    @staticmethod
    def _bakeable(entry) -> bool:
        """Whether ``entry`` is a texture this baker reads per texel (one file, not a UDIM set)."""
        texture = entry.value if entry is not None else None
        return isinstance(texture, Texture) and not texture.is_udim and "<UVTILE>" not in texture.file

    def bake(self, material, mapping, values, target_type: str, label: str, texturable: bool = True,
             ignored: dict | None = None) -> Baked:
        """``mapping.formula`` over the textured sources of ``mapping`` (see the module docstring); a textured source
        in ``ignored`` (one the formula does not read with the other inputs at their values: translate.probes) that
        cannot be baked (UDIM tiles, a procedural graph) is held at its probe value instead (a cut-out's opacity beside
        a diffuse colour of UDIM tiles, which its threshold decides alone: the red team's E#1)."""
        working = LINEAR_REC709  # where the target shades (translate.target.WorkingSpace): every formula runs there
        space = WorkingSpace(material, values.table)
        ignored = {name: probe for name, probe in (ignored or {}).items() if not self._bakeable(values.entry(name))}
        textured = [s for s in mapping.sources if not values.is_constant(s) and s not in ignored]
        entries = [values.entry(s) for s in textured]
        for name, entry in zip(textured, entries):
            if isinstance(entry.value, Connection) and entry.value.dangling:  # (not a graph: nothing is there)
                raise BakeError(f"{name} is connected to {entry.value.target}, which cannot be followed "
                                f"({entry.value.reason or 'connection target not found'})")
            if not isinstance(entry.value, Texture):
                raise BakeError(f"{name} is a procedural input, which is not baked")
        first = entries[0].value
        for name, entry in zip(textured[1:], entries[1:]):
            other = entry.value
            if (other.uv or None) != (first.uv or None) or _texcoord(other) != _texcoord(first):
                raise BakeError(f"{textured[0]} and {name} use different texture coordinates or UV transforms, "
                                "so their texels do not line up")
        loaded = {}
        for name, entry in zip(textured, entries):
            parameter = values.table.get(name)
            type_name = parameter.type if parameter is not None else (entry.type or "float")
            loaded[name] = self.texels(entry.value, type_name, working, f"{material.name}.{name}")
        height = max(v.shape[0] for v in loaded.values())
        width = max(v.shape[1] for v in loaded.values())
        resampled = [n for n, v in loaded.items() if v.shape[:2] != (height, width)]
        for name in resampled:
            loaded[name] = _resample(loaded[name], height, width)
        arguments = []
        for name in mapping.sources:
            if name in loaded:
                arguments.append(loaded[name])
            elif name in ignored:
                arguments.append(space.into(name, ignored[name]))
            else:
                constant = values.constant(name)
                if constant is None:
                    raise BakeError(f"{name} has no value to bake with")
                arguments.append(space.into(name, constant))
        with np.errstate(all="ignore"):
            result = np.asarray(mapping.formula(*arguments), dtype=np.float64)
        channels = 3 if target_type in ("color3", "vector3") else 1
        try:
            if result.ndim == 3 and result.shape[2] != channels:
                result = result[:, :, :1] if channels == 1 else np.broadcast_to(result[:, :, :1], (height, width, 3))
            result = np.broadcast_to(result, (height, width, channels)).copy()
        except ValueError:
            raise BakeError(f"the formula for {mapping.target} does not give one value per texel") from None
        if not np.all(np.isfinite(result)):
            raise BakeError(f"the formula for {mapping.target} gives non-finite values on some texels")
        averages = {name: _average(loaded[name]) for name in textured}
        sources = ", ".join(f"{n} ({os.path.basename(values.entry(n).value.file)})" for n in textured)
        entry = values.entry(textured[0])
        same = next((n for n in textured if n not in resampled and _same_texels(loaded[n], result, target_type)), None)
        if same is not None:  # (the red team's E#14: a copy of the artist's texture replaced the reference to it)
            kept = values.entry(same)
            made = Input(mapping.target, target_type, kept.value, kept.location, colorspace=kept.colorspace)
            return Baked(made, f"{mapping.target}: from {sources} evaluated per texel; every texel is {same}'s own "
                               "(to the 8-bit level), so its texture is kept", averages=averages)
        if np.ptp(result, axis=(0, 1)).max() <= 1e-7 or not texturable:
            # A mode or switch (glTF alpha_mode, a boolean) takes the largest per-texel value: one
            # translucent texel needs blending. Anything else takes the mean.
            discrete = target_type in ("integer", "boolean")
            flat = result.reshape(-1, channels)
            value = flat.max(axis=0) if discrete else flat.mean(axis=0)
            constant = float(value[0]) if channels == 1 else tuple(float(v) for v in value)
            why = "every texel gives the same value" if texturable else f"{label} takes a single value here"
            made = Input(mapping.target, target_type, Constant(constant), entry.location,
                         colorspace=working if channels == 3 else None)
            which = "the largest" if discrete else "the mean"
            return Baked(made, f"{mapping.target}: from {sources} evaluated per texel; {why}, so {which} is written",
                         averages=averages)
        data, space, clipped, kind = bake_cache.RUN.encoded(result, (target_type, working, self.png_only),
                                                  lambda: self._encode(result, target_type, working))
        name = self._name(material, mapping.target, kind, data)
        path = os.path.join(self.folder, name)
        self.images[path] = data
        self._pixels[("baked", path)] = (data, result, kind)
        # The fallback (MaterialX image ``default``) is the mean baked value: what a renderer shows
        # without the file, and the value the lobe evaluator (--verify) uses for a texture.
        # MaterialX applies the file's colour space to the default too: it is encoded like the texels.
        mean = result.reshape(-1, channels).mean(axis=0)
        if space == "srgb_texture":
            linear = mean if working == LINEAR_REC709 else colorspaces.to_lin_rec709(mean, working)
            mean = colorspaces.from_lin_rec709(np.clip(linear, 0.0, 1.0), "srgb_texture")
        elif kind == ".png":
            mean = np.clip(mean, 0.0, 1.0)
        fallback = float(mean[0]) if channels == 1 else tuple(float(v) for v in mean)
        texture = Texture(file=path, image_type=target_type if channels == 3 else "float", channels=None,
                          colorspace=space, uv=first.uv, texcoord=first.texcoord, wrap=first.wrap,
                          fallback=fallback, node=None, location=first.location)
        made = Input(mapping.target, target_type, texture, entry.location, colorspace=space)
        note = f" ({', '.join(resampled)} resampled to {width} x {height})" if resampled else ""
        message = f"{mapping.target}: baked per texel from {sources} into {name}, {width} x {height}{note}"
        if clipped:
            message += f"; {clipped:.1%} of texels clipped to [0, 1] (this output takes PNG only)"
        return Baked(made, message, clipped, averages)

    def _name(self, material, target: str, suffix: str, data: bytes) -> str:
        """A file name in the bake folder for ``data``: not one this bake already uses, nor a different file already
        there (the input's own texture, say: never written over; the same bytes, a re-run's, are kept)."""
        stem = re.sub(r"[^A-Za-z0-9_.-]", "_", f"{material.name}_{target}")
        name, count = f"{stem}{suffix}", 1
        while os.path.join(self.folder, name) in self.images or _occupied(os.path.join(self.folder, name), data):
            count += 1
            name = f"{stem}_{count}{suffix}"
        return name

    def _encode(self, values, target_type: str, working: str):
        """(bytes, colour space, clipped fraction, file suffix) for baked values."""
        in_range = bool(np.all(values >= -1e-6) and np.all(values <= 1.0 + 1e-6))
        colour = target_type == "color3"
        if not in_range and not self.png_only and _has_openimageio():
            return _exr(values), (working if colour else None), 0.0, ".exr"
        clipped = 0.0 if in_range else float(np.mean(np.any((values < 0) | (values > 1), axis=-1)))
        values = np.clip(values, 0.0, 1.0)
        if colour and (working == LINEAR_REC709 or self.png_only or not _has_openimageio()):
            linear = values if working == LINEAR_REC709 else np.clip(colorspaces.to_lin_rec709(values, working), 0, 1)
            encoded = colorspaces.from_lin_rec709(linear, "srgb_texture")
            return _png8(encoded), "srgb_texture", clipped, ".png"
        if colour:
            return _png16_oiio(values), working, clipped, ".png"
        return _png16_grey(values[:, :, 0]), None, clipped, ".png"


def _same_texels(texels, result, target_type: str) -> bool:
    """Whether the formula left ``texels`` (one source's, in linear Rec.709) as they were: the same shape, and the
    same 8-bit level in every texel as the baked image would encode it (a colour sRGB-encoded, a float linear)."""
    if texels.shape != result.shape or target_type not in ("color3", "float"):
        return False
    if target_type == "color3":
        texels, result = (colorspaces.from_lin_rec709(np.clip(v, 0.0, 1.0), "srgb_texture") for v in (texels, result))
    return bool(np.array_equal(np.round(np.clip(texels, 0.0, 1.0) * 255), np.round(np.clip(result, 0.0, 1.0) * 255)))


def _occupied(path: str, data: bytes) -> bool:
    """Whether ``path`` holds something other than ``data`` (a file with other bytes, a folder, a link)."""
    if not os.path.lexists(path):
        return False
    if os.path.islink(path) or not os.path.isfile(path) or os.path.getsize(path) != len(data):
        return True
    with open(path, "rb") as handle:
        return handle.read() != data


def _average(values):
    mean = values.reshape(-1, values.shape[-1]).mean(axis=0)
    return np.asarray(mean[0]) if mean.size == 1 else mean


def _as_read(data: bytes, values, suffix: str):
    """The pixels a later step reads back from a baked image (as :func:`load_pixels` gives them)."""
    if suffix == ".exr":
        return values if values.shape[2] >= 3 else np.repeat(values, 3, axis=2)
    return load_pixels(data)


def _texcoord(texture: Texture):
    return texture.texcoord if texture.texcoord not in (None, 0, "st", "UV0") else None


def _resample(values, height: int, width: int):
    return np.stack([resample(values[:, :, c], height, width) for c in range(values.shape[2])], axis=-1)


def _png8(values) -> bytes:
    from PIL import Image  # lazy: Pillow costs ~15 ms to import, needed only when an image is encoded

    quantised = np.round(np.clip(values, 0, 1) * 255.0).astype(np.uint8)
    out = io.BytesIO()
    Image.fromarray(quantised).save(out, format="PNG", compress_level=6)
    return out.getvalue()


def _png16_grey(values) -> bytes:
    from PIL import Image  # lazy: Pillow costs ~15 ms to import, needed only when an image is encoded

    quantised = np.round(np.clip(values, 0, 1) * 65535.0).astype(np.uint16)
    out = io.BytesIO()
    Image.fromarray(quantised).save(out, format="PNG", compress_level=6)
    return out.getvalue()


def _has_openimageio() -> bool:
    try:
        import OpenImageIO  # noqa: F401  (lazy: a probe for the optional OpenImageIO, ~30 ms to import)
    except ImportError:
        return False
    return True


def _oiio_bytes(values, suffix: str, pixel_type: str) -> bytes:
    """Encode with OpenImageIO through a temporary file (its Python API writes files)."""
    import OpenImageIO as oiio  # lazy: OpenImageIO costs ~30 ms to import and is optional (EXR, 16-bit PNG)

    height, width, channels = values.shape
    spec = oiio.ImageSpec(width, height, channels, getattr(oiio, pixel_type))
    spec.attribute("Software", "openpbr-tools")  # fixed, so the bytes do not depend on the library version
    spec.attribute("DateTime", "1970:01:01 00:00:00")  # else OpenEXR's capDate is the time of writing
    folder = tempfile.mkdtemp(prefix="openpbr-bake-")
    path = os.path.join(folder, "image" + suffix)
    try:
        output = oiio.ImageOutput.create(path)
        if output is None or not output.open(path, spec):
            raise BakeError(f"OpenImageIO cannot write {suffix} ({oiio.geterror()})")
        output.write_image(np.ascontiguousarray(values, dtype=np.float32))
        output.close()
        with open(path, "rb") as handle:
            return handle.read()
    finally:
        for name in os.listdir(folder):
            os.unlink(os.path.join(folder, name))
        os.rmdir(folder)


def _exr(values) -> bytes:
    return _oiio_bytes(values, ".exr", "HALF")


def _png16_oiio(values) -> bytes:
    return _oiio_bytes(np.clip(values, 0, 1), ".png", "UINT16")
