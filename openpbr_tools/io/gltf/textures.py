"""The texture half of the glTF reader: images, textures, samplers, texture transforms.

:class:`TextureReading` (a base of the reader's ``_Reader``) records each image (its file or
``#/images/N`` inside the asset, MIME type, width and height measured from the header, and whether
its data is damaged, :func:`openpbr_tools.io.image_files.damage`), and turns a ``textureInfo`` into a :class:`~openpbr_tools.model.Texture`: the
image it reads (through ``EXT_texture_webp``/``KHR_texture_basisu`` sources too), the sampler's wrap
modes as MaterialX address modes, ``KHR_texture_transform`` as ``place2d`` parameters, the UV set,
and the factor, normal scale, occlusion strength or iridescence thickness range folded into
``scale`` and ``bias``. Materials and their factors are :mod:`.reader`'s; the JSON value checks at
the bottom serve both.
"""

from __future__ import annotations

import json
import math
import os
import struct
import warnings
from urllib.parse import unquote

from ...model import Connection, Texture
from ..image_files import ALPHA_MODES, ResourceFile, damage, head_of, is_webp, pillow_format, png_bit_depth
from . import slots
from .image_features import png_features, png_header_chunks, webp_features
from .document import ResourceError, data_uri_mime
from .schema import TEXTURE_OBJECT_PROPERTIES, uri_syntax_error
from .uv import from_texture_transform

KTX2, KTX2_IDENTIFIER = "image/ktx2", b"\xabKTX 20\xbb\r\n\x1a\n"
#: The bytes of a KTX2 file read for its header and data format descriptor (which follows the level index).
KTX2_HEAD = 4096
#: The data format descriptor colour models of Basis Universal (KHR_texture_basisu): ETC1S (with BasisLZ) and UASTC.
BASIS_COLOR_MODELS = {163: "ETC1S", 166: "UASTC"}
SNIFF = ((b"\x89PNG\r\n\x1a\n", "image/png"), (b"\xff\xd8\xff", "image/jpeg"),
         (KTX2_IDENTIFIER, KTX2), (b"v/1\x01", "image/x-exr"), (b"#?RADIANCE", "image/vnd.radiance"))
SUFFIX_MIME = {".png": "image/png", ".jpg": "image/jpeg", ".jpeg": "image/jpeg", ".webp": "image/webp",
               ".ktx2": "image/ktx2", ".exr": "image/x-exr", ".hdr": "image/vnd.radiance", ".tif": "image/tiff",
               ".tiff": "image/tiff", ".tga": "image/x-tga", ".bmp": "image/bmp"}


class TextureReading:
    """Images and textures for a reader with ``document``, ``asset``, ``facts``, ``images``,
    ``package_files``, ``texture_pointers``, ``wrap_modes``, ``filters``, ``bad_samplers``, ``index`` and the
    ``invalid``/``broken``/``observe_once``/``location`` reporters."""

    def read_image(self, index: int) -> dict:
        pointer = f"/images/{index}"
        image = self.document.item("images", index) or {}
        uri = image.get("uri")
        declared = image.get("mimeType")
        info = {"index": index, "pointer": pointer, "file": f"#/images/{index}", "packaged": True,
                "mime": declared if isinstance(declared, str) else None, "width": None, "height": None}
        if "bufferView" in image and "uri" in image:  # the schema's oneOf; loaders differ on which they read
            self.invalid(pointer, "an image has a uri or a bufferView, not both")
        elif "bufferView" in image and not isinstance(declared, str):
            self.invalid(pointer, "an image stored in a bufferView needs a mimeType", "bufferView")
        view = self.document.item("bufferViews", image["bufferView"]) if "bufferView" in image else None
        if isinstance(view, dict) and "byteStride" in view:  # 3.6.1.1: only vertex attribute views are strided
            self.invalid(pointer, f"the image's bufferView {image['bufferView']} has a byteStride, which a view of "
                         "image data must not have (only vertex attributes are strided)", "bufferView")
        if isinstance(uri, str) and not uri.startswith("data:"):
            info["file"], info["packaged"] = unquote(uri), False
            syntax = uri_syntax_error(uri)
            if syntax is not None:
                self.invalid(pointer, f"uri {json_text(uri)} is no valid URI: {syntax}; loaders cannot resolve it", "uri")
            if "\x00" in info["file"]:  # no file system takes it; path functions raise ValueError on it
                info["file"] = info["file"].replace("\x00", "\ufffd")
                self.invalid(pointer, "uri holds a NUL character (U+0000), which no file name can; read as U+FFFD", "uri")
            info["mime"] = info["mime"] or SUFFIX_MIME.get(os.path.splitext(info["file"])[1].lower())
            try:
                local = self.document.resolve(uri, pointer + "/uri")
            except ResourceError as error:
                if error.outside:
                    info["outside"] = error.message  # never opened; the rules report it
                return info
            if os.path.isfile(local):  # the header is read, and the data checked (io.image_files.damage)
                _measure(local, info, head_of(local))
                info["damage"] = damage(local)
                if info["mime"] == KTX2:
                    _basis_universal(info, head_of(local, KTX2_HEAD))
                _declared_type(info, declared if isinstance(declared, str) else None, "uri")
            return info
        try:
            data, mime = self.document.image_view(index)
        except ResourceError as error:
            self.broken(error)
            return info
        info["mime"] = info["mime"] or (mime if isinstance(mime, str) else None) or data_uri_mime(uri or "")
        self.package_files.add(info["file"])
        _measure(ResourceFile(data), info, bytes(data[:32]))
        info["damage"] = damage(data)
        if info["mime"] == KTX2:
            _basis_universal(info, bytes(data[:KTX2_HEAD]))
        where = "bufferView" if "bufferView" in image else "uri"  # where the bytes are, as the Khronos validator points
        _declared_type(info, declared if isinstance(declared, str) else data_uri_mime(uri or ""), where,
                       data_uri=isinstance(uri, str) and uri.startswith("data:"))
        return info

    def unexpected_texture_properties(self) -> None:
        """Properties of images, textures and samplers that their schemas do not define (UNEXPECTED_PROPERTY)."""
        for array, names in TEXTURE_OBJECT_PROPERTIES.items():
            for index, found in enumerate(self.document.array(array)):
                if isinstance(found, dict):
                    self.unexpected(found, names + slots.COMMON_PROPERTIES, f"/{array}/{index}", array[:-1])

    def texture(self, slot: slots.Slot, info, pointer: str, factor, container: dict):
        if not isinstance(info, dict) or isinstance(info.get("index"), bool) or not isinstance(info.get("index"), int):
            self.invalid(pointer, "textureInfo needs an integer index", "index")
            return Connection(pointer, None, "textureInfo has no valid index", dangling=True)
        index = info["index"]
        texture = self.document.item("textures", index)
        if texture is None:
            return Connection(f"/textures/{index}", None, f"texture {index} does not exist", dangling=True)
        source, via_extension = texture.get("source"), None
        for extension in slots.EXTENSION_MIME_TYPES.values():
            alternative = (texture.get("extensions") or {}).get(extension) if isinstance(texture.get("extensions"), dict) else None
            if isinstance(alternative, dict) and isinstance(alternative.get("source"), int):
                source, via_extension = alternative["source"], extension
        if source is None or self.document.item("images", source) is None:
            if source is not None and ("dangling_texture", index) not in self.observed:  # (once per texture; one
                self.observed.add(("dangling_texture", index))  # without a source is said at each input that reads it)
                self.asset.observe("dangling_reference", self.location(f"/textures/{index}", "source"),
                                   attribute="source", target=source)
            why = f"names image {source}, which does not exist" if source is not None else "has no image source"
            return Connection(f"/textures/{index}", None, f"texture {index} {why}", dangling=True)
        image = self.images[source]
        if via_extension and via_extension not in image.setdefault("via_extensions", []):
            image["via_extensions"].append(via_extension)
        texcoord = info.get("texCoord", 0)
        result = Texture(
            file=image["file"], image_type=slot.image_type, channels=slot.channels, colorspace=slot.colorspace,
            node=pointer, node_category="gltf_texture", location=self.location(pointer, "index"),
            packaged=image["packaged"],
        )
        sampler = texture.get("sampler")
        result.wrap = self.sampler(sampler, index)
        result.filter = _magnification_filter(self.document.item("samplers", sampler)) if sampler is not None else None
        result.minification = _minification_filter(self.document.item("samplers", sampler)) if sampler is not None else None
        self.other_texture_extensions(info, pointer)
        transform = _transform(info)
        if transform is not None:
            texcoord = transform.get("texCoord", texcoord)
            try:
                result.uv = _uv(transform)
            except (TypeError, ValueError, ZeroDivisionError) as error:
                self.invalid(f"{pointer}/extensions/{slots.TEXTURE_TRANSFORM}", f"KHR_texture_transform ignored: {error}")
        if not isinstance(texcoord, int) or isinstance(texcoord, bool) or texcoord < 0:
            self.invalid(pointer, f"texCoord must be a non-negative integer, not {json_text(texcoord)}", "texCoord")
            texcoord = 0
        result.texcoord = texcoord or None
        if pointer not in self.texture_pointers:
            self.texture_pointers.add(pointer)
            self.facts["texture_uses"].append({"pointer": pointer, "material": self.index, "texcoord": texcoord,
                                               "image": source})
        self.apply_factor(slot, result, info, factor, container, pointer)
        return result

    def other_texture_extensions(self, info: dict, pointer: str) -> None:
        """Extensions of a textureInfo other than KHR_texture_transform (KHR_texture_procedurals: a procedural graph
        whose texture's own image is only its fallback) are not read: observed for validate (OPBR1212) and listed
        in the material's state (``texture_extensions``: [pointer, name]), which convert reports as not carried."""
        extensions = info.get("extensions")
        for name in sorted(extensions) if isinstance(extensions, dict) else ():
            if name == slots.TEXTURE_TRANSFORM or [pointer, name] in self.reading.get("texture_extensions", []):
                continue
            self.reading.setdefault("texture_extensions", []).append([pointer, name])
            self.asset.observe("gltf_not_converted", self.location(f"{pointer}/extensions/{name}"), extension=name,
                               material=self.reading_name)

    def apply_factor(self, slot: slots.Slot, texture: Texture, info: dict, factor, container: dict, pointer: str) -> None:
        if slot.texture_kind in ("normalTextureInfo", "occlusionTextureInfo"):
            name = "scale" if slot.texture_kind == "normalTextureInfo" else "strength"
            if name in info and not json_numbers([info[name]], 1):
                self.invalid(pointer, f"{name} must be a number, not {json_text(info[name])}", name)
        if slot.texture_kind == "normalTextureInfo":
            texture.normal_map = json_float(info["scale"]) if json_numbers([info.get("scale")], 1) else 1.0
            texture.channels = None
            return
        if slot.texture_kind == "occlusionTextureInfo":
            strength = json_float(info["strength"]) if json_numbers([info.get("strength")], 1) else 1.0
            if not 0.0 <= strength <= 1.0:  # (the schema's range; read as it is)
                self.invalid(pointer, f"strength must be in [0, 1], not {json_text(info['strength'])}", "strength")
            if strength != 1.0:
                texture.scale, texture.bias = strength, 1.0 - strength
            return
        if slot.parameter == "iridescence_thickness":
            low_name, low_default = slots.IRIDESCENCE_THICKNESS_MINIMUM
            low = container.get(low_name, low_default)
            high = factor if isinstance(factor, float) else slot.default
            low = json_float(low) if json_numbers([low], 1) else low_default
            texture.scale, texture.bias = high - low, low
            return
        if factor is None:
            return
        identity = tuple(1.0 for _ in factor) if isinstance(factor, tuple) else 1.0
        if factor != identity:
            texture.scale = factor

    def sampler(self, index, texture_index: int) -> tuple[str, str] | None:
        if index is None:
            return None
        sampler = self.document.item("samplers", index)
        if sampler is None:
            self.asset.observe("dangling_reference", self.location(f"/textures/{texture_index}", "sampler"),
                               attribute="sampler", target=index)
            return None
        modes = []
        for name in ("wrapS", "wrapT"):
            value = sampler.get(name, 10497)  # REPEAT, the schema's default
            if not isinstance(value, int) or isinstance(value, bool) or value not in self.wrap_modes:
                if (index, name) not in self.bad_samplers:
                    self.bad_samplers.add((index, name))
                    self.invalid(f"/samplers/{index}", f"{name} must be 33071, 33648 or 10497, not {json_text(value)}", name)
                value = 10497
            modes.append(self.wrap_modes[value])
        for name, allowed in self.filters.items():  # (checked; magFilter is carried as Texture.filter)
            value = sampler.get(name)
            if value is not None and (isinstance(value, bool) or value not in allowed) \
                    and (index, name) not in self.bad_samplers:
                self.bad_samplers.add((index, name))
                self.invalid(f"/samplers/{index}", f"{name} must be {' or '.join(map(str, allowed))}, not "
                                                   f"{json_text(value)}", name)
        return modes[0], modes[1]



MINIFICATION_FILTERS = {9728: "NEAREST", 9729: "LINEAR", 9984: "NEAREST_MIPMAP_NEAREST", 9985: "LINEAR_MIPMAP_NEAREST",
                        9986: "NEAREST_MIPMAP_LINEAR", 9987: "LINEAR_MIPMAP_LINEAR"}  # sampler.schema.json


def _magnification_filter(sampler) -> str | None:
    """A sampler's magFilter in MaterialX's words (9728 NEAREST: closest, 9729 LINEAR: linear); None when unset."""
    value = sampler.get("magFilter") if isinstance(sampler, dict) else None
    return {9728: "closest", 9729: "linear"}.get(value) if isinstance(value, int) and not isinstance(value, bool) else None


def _minification_filter(sampler) -> int | None:
    """A sampler's minFilter when it is one the schema allows (9728, 9729, 9984-9987); None when unset."""
    value = sampler.get("minFilter") if isinstance(sampler, dict) else None
    return value if isinstance(value, int) and not isinstance(value, bool) and value in MINIFICATION_FILTERS else None


def _transform(info: dict) -> dict | None:
    extensions = info.get("extensions")
    if not isinstance(extensions, dict):
        return None
    found = extensions.get(slots.TEXTURE_TRANSFORM)
    return found if isinstance(found, dict) else None


def _uv(transform: dict):
    offset = transform.get("offset", [0.0, 0.0])
    rotation = transform.get("rotation", 0.0)
    scale = transform.get("scale", [1.0, 1.0])
    if not json_numbers(offset, 2) or not json_numbers(scale, 2) or not json_numbers([rotation], 1):
        raise ValueError("offset and scale must be arrays of 2 numbers, rotation a number")
    uv = from_texture_transform((json_float(offset[0]), json_float(offset[1])), json_float(rotation), (json_float(scale[0]), json_float(scale[1])))
    return None if (offset, rotation, scale) == ([0.0, 0.0], 0.0, [1.0, 1.0]) else uv


def _declared_type(info: dict, declared: str | None, where: str, data_uri: bool = False) -> None:
    """Record in ``info["declared"]`` a declared MIME type that is not the format of the image's bytes; for a data
    URI, also bytes in no image format at all (the Khronos glTF-Validator's INVALID_URI: "The declared mediatype
    does not match the embedded content")."""
    found = info.get("detected_mime")
    if declared and found and declared != found and info.get("damage") is None:
        info["declared"] = {"type": declared, "found": found, "property": where}
    elif declared and data_uri and found is None and getattr(info.get("damage"), "kind", None) == "unrecognised":
        info["declared"] = {"type": declared, "found": "in no image format", "property": where}


def _basis_universal(info: dict, head: bytes) -> None:
    """Record in ``info["not_basis_universal"]`` why an image declared (or named) KTX2 is no KTX v2 file holding a
    Basis Universal payload, which KHR_texture_basisu requires (its README, "KTX v2 Images with Basis Universal
    Supercompression": the DFD colour model ETC1S with supercompression 1 (BasisLZ), or UASTC with 0 or 2
    (Zstandard); and ``vkFormat`` VK_FORMAT_UNDEFINED, as the KTX 2.0 specification has it for both: no Vulkan
    format holds them). Only the header is read; a file too short for one is not judged here."""
    if info.get("detected_mime") is not None:
        return  # another format: the MIME checks say so
    if not head.startswith(KTX2_IDENTIFIER):
        legacy = " (a pre-ratification .basis file)" if head.startswith(b"sB") else ""
        info["not_basis_universal"] = f"its bytes are no KTX v2 file{legacy}"
        return
    if len(head) < 80:
        return
    vk_format, scheme = struct.unpack_from("<I", head, 12)[0], struct.unpack_from("<I", head, 44)[0]
    dfd_offset, dfd_length = struct.unpack_from("<II", head, 48)
    model = head[dfd_offset + 12] if dfd_length >= 16 and dfd_offset + 12 < len(head) else None
    if vk_format != 0:
        info["not_basis_universal"] = f"it is a KTX v2 file of raw texels (vkFormat {vk_format}, not 0)"
    elif model is not None and model not in BASIS_COLOR_MODELS:
        info["not_basis_universal"] = (f"its data format descriptor's colour model is {model}, neither ETC1S (163) nor "
                                       "UASTC (166)")
    elif (model == 163 and scheme != 1) or (model == 166 and scheme not in (0, 2)):
        info["not_basis_universal"] = (f"its {BASIS_COLOR_MODELS[model]} payload has supercompression scheme {scheme}, "
                                       f"not {'1 (BasisLZ)' if model == 163 else '0 or 2 (Zstandard)'}")


def _measure(source, info: dict, head: bytes | None = None) -> None:
    """Fill ``width``, ``height``, ``mode`` (Pillow's: ``RGB``, ``RGBA``, ``CMYK``...), ``alpha`` (whether
    the image has an alpha channel, a PNG's tRNS transparency included), ``bit_depth`` (a PNG's bits per
    sample, from its IHDR) and (when undeclared) ``mime`` from the image header; nothing is decoded."""
    if head is not None and not info["mime"]:
        info["mime"] = next((mime for magic, mime in SNIFF if head.startswith(magic)), None)
        if head[:4] == b"RIFF" and head[8:12] == b"WEBP":
            info["mime"] = "image/webp"
    if head is not None:
        info["bit_depth"] = png_bit_depth(head)
    try:
        from PIL import Image  # lazy: Pillow (~15 ms) only for a file that has images

        with warnings.catch_warnings():  # DecompressionBombWarning: the library never prints
            warnings.simplefilter("ignore")
            with Image.open(source) as image:
                info["width"], info["height"] = image.size
                detected = Image.MIME.get(pillow_format(image) or "")
                info["detected_mime"] = detected
                info["mime"] = info["mime"] or detected
                info["mode"] = image.mode
                info["alpha"] = image.mode in ALPHA_MODES or "transparency" in image.info
                if detected == "image/jpeg":  # EXIF Orientation (tag 274): from the header, nothing decoded
                    info["orientation"] = image.getexif().get(0x0112)
    except Exception:  # noqa: BLE001 - Pillow raises many exception types for images it cannot identify
        pass  # (io.images.damage says why)
    if info.get("detected_mime") == "image/png":
        info["features"] = png_features(png_header_chunks(source.data if isinstance(source, ResourceFile) else source))
    elif head is not None and is_webp(head):
        info["features"] = webp_features(head)


def json_index(value) -> bool:
    """Whether a JSON value is an index or count: an integer (not a boolean) at least 0."""
    return isinstance(value, int) and not isinstance(value, bool) and value >= 0


def json_numbers(value, count: int) -> bool:
    """``value`` is a list of ``count`` JSON numbers (NaN and infinity included: the values rules judge them)."""
    return isinstance(value, list) and len(value) == count and all(
        isinstance(v, (int, float)) and not isinstance(v, bool) for v in value)


def json_float(value) -> float:
    """A JSON number as a float; integers beyond the float range become ±infinity, as a JSON
    reader that parses numbers as doubles would read them."""
    try:
        return float(value)
    except OverflowError:
        return math.inf if value > 0 else -math.inf


def json_text(value) -> str:
    return json.dumps(value)
