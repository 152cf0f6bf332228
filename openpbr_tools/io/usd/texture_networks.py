"""The texture networks of the USD writer: what an input fed by a texture becomes.

:class:`TextureNetworkWriter` (a base of the writer's ``_Writer``) writes a
:class:`~openpbr_tools.model.Texture` as a MaterialX image chain for a MaterialX shader
(``ND_image_*``/``ND_tiledimage_*``, then ``ND_convert``/``ND_extract``, ``ND_multiply``/``ND_add``
for scale and bias, ``ND_normalmap``; ``ND_place2d``, ``ND_texcoord`` or ``ND_geompropvalue`` on the
coordinates) or as a ``UsdUVTexture`` (+ ``UsdTransform2d``, ``UsdPrimvarReader_float2``) for
UsdPreviewSurface, and returns the output to connect. Materials, shaders, input values and where a
texture file is referenced from are :mod:`.writer`'s.
"""

from __future__ import annotations

import math

from ...model import Texture, UVTransform, normal_decode, normal_encoding
from ...rules.translation import APPROXIMATED, CONVERTED
from ...values import COMPONENTS
from .types import ADDRESS_MODE_TO_WRAP, MATERIALX_TO_USD, WRAP_TO_ADDRESS_MODE


def identifier(name: str) -> str:
    """A valid prim name from the last segment of ``name`` (``material`` when empty)."""
    from pxr import Tf  # lazy: pxr (0.1-0.2 s) only once write_usd has required it

    return Tf.MakeValidIdentifier(name.rstrip("/").rsplit("/", 1)[-1] or "material")


class TextureNetworkWriter:
    """Texture networks for a writer with ``stage``, ``Sdf``, ``UsdShade``, ``unique_child``,
    ``texture_path``, ``colorspace_name``, ``set_value`` and ``note``."""

    # -- MaterialX image chains --------------------------------------------------------------
    def node(self, material, name: str, node_id: str, output_type: str):
        shader = self.UsdShade.Shader.Define(self.stage, self.unique_child(str(material.GetPath()), name))
        shader.CreateIdAttr(node_id)
        return shader, shader.CreateOutput("out", self.Sdf.ValueTypeNames.Find(MATERIALX_TO_USD[output_type]))

    def constant_input(self, shader, name: str, materialx_type: str, value) -> None:
        usd_type = MATERIALX_TO_USD[materialx_type]
        self.set_value(shader.CreateInput(name, self.Sdf.ValueTypeNames.Find(usd_type)).GetAttr(), usd_type, value)

    def materialx_image(self, material, entry, texture: Texture, usd_type: str):
        owner = f"{entry.location.path}.{entry.name}"
        image_type = texture.image_type if texture.image_type in MATERIALX_TO_USD else "color3"
        category = "tiledimage" if texture.node_category == "tiledimage" else "image"
        base = identifier(texture.node or f"{entry.name}_image")
        image, output = self.node(material, base, f"ND_{category}_{image_type}", image_type)
        file_input = image.CreateInput("file", self.Sdf.ValueTypeNames.Asset)
        file_input.Set(self.Sdf.AssetPath(self.texture_path(texture, owner)))
        space = self.colorspace_name(texture.colorspace, "materialx")
        if space:
            file_input.GetAttr().SetColorSpace(space)
        if texture.fallback is not None:
            self.constant_input(image, "default", image_type, _fit(texture.fallback, image_type))
        if texture.wrap:
            for name, mode in zip(("uaddressmode", "vaddressmode"), texture.wrap):
                mode = WRAP_TO_ADDRESS_MODE.get(mode, mode)
                if mode != "useMetadata":
                    self.constant_input(image, name, "string", mode)
        if texture.filter:
            self.constant_input(image, "filtertype", "string", texture.filter)
        self.coordinates(material, image, texture, category, base)
        current = image_type
        if texture.normal_map is not None and current != "vector3":
            node, converted = self.node(material, f"{base}_vector", f"ND_convert_{current}_vector3", "vector3")
            node.CreateInput("in", output.GetTypeName()).ConnectToSource(output)
            output, current = converted, "vector3"
        if texture.channels is not None and len(texture.channels) == 1 and current != "float":
            node, extracted = self.node(material, f"{base}_channel", f"ND_extract_{current}", "float")
            node.CreateInput("in", output.GetTypeName()).ConnectToSource(output)
            self.constant_input(node, "index", "integer", int(texture.channels[0]))
            output, current = extracted, "float"
        elif texture.channels is not None and len(texture.channels) == 3 and current[-1:] == "4":
            three = current[:-1] + "3"  # a four-channel image read as three: alpha dropped
            node, converted = self.node(material, f"{base}_convert", f"ND_convert_{current}_{three}", three)
            node.CreateInput("in", output.GetTypeName()).ConnectToSource(output)
            output, current = converted, three
        scale, bias, strength = texture.scale, texture.bias, None
        if texture.normal_map is not None:  # before the normalmap node, which decodes 2 t - 1 itself
            scale, bias, strength = normal_encoding(texture)
        for operation, value, identity in (("multiply", scale, 1.0), ("add", bias, 0.0)):
            factor = _per_output(value, texture.channels, current)
            if factor is None or all(v == identity for v in _components(factor)):
                continue
            node, result = self.node(material, f"{base}_{operation}", f"ND_{operation}_{current}", current)
            node.CreateInput("in1", output.GetTypeName()).ConnectToSource(output)
            self.constant_input(node, "in2", current, factor)
            output = result
        if texture.normal_map is not None:
            node, decoded = self.node(material, f"{base}_normalmap", "ND_normalmap_float", "vector3")
            node.CreateInput("in", output.GetTypeName()).ConnectToSource(output)
            self.constant_input(node, "scale", "float", float(strength))
            output = decoded
        return output

    def coordinates(self, material, image, texture: Texture, category: str, base: str) -> None:
        transform = texture.uv
        upstream = None
        if isinstance(texture.texcoord, int) and texture.texcoord != 0:
            node, upstream = self.node(material, f"{base}_texcoord", "ND_texcoord_vector2", "vector2")
            self.constant_input(node, "index", "integer", texture.texcoord)
        elif isinstance(texture.texcoord, str) and texture.texcoord not in ("", "st"):
            node, upstream = self.node(material, f"{base}_texcoord", "ND_geompropvalue_vector2", "vector2")
            self.constant_input(node, "geomprop", "string", texture.texcoord)
        if transform is not None and category == "tiledimage" and transform.rotate == 0 and transform.pivot == (0.0, 0.0):
            self.constant_input(image, "uvtiling", "vector2", transform.scale)
            self.constant_input(image, "uvoffset", "vector2", transform.offset)
            transform = None
        if transform is not None:
            node, placed = self.node(material, f"{base}_place2d", "ND_place2d_vector2", "vector2")
            for name, value in (("scale", transform.scale), ("offset", transform.offset), ("pivot", transform.pivot)):
                self.constant_input(node, name, "vector2", value)
            self.constant_input(node, "rotate", "float", float(transform.rotate))
            if upstream is not None:
                node.CreateInput("texcoord", upstream.GetTypeName()).ConnectToSource(upstream)
            upstream = placed
        if upstream is not None:
            image.CreateInput("texcoord", upstream.GetTypeName()).ConnectToSource(upstream)

    # -- UsdUVTexture ------------------------------------------------------------------------
    def uv_texture(self, material, entry, texture: Texture, usd_type: str):
        Sdf = self.Sdf
        owner = f"{entry.location.path}.{entry.name}"
        base = identifier(texture.node or f"{entry.name}_texture")
        reader = self.UsdShade.Shader.Define(self.stage, self.unique_child(str(material.GetPath()), base))
        reader.CreateIdAttr("UsdUVTexture")
        reader.CreateInput("file", Sdf.ValueTypeNames.Asset).Set(Sdf.AssetPath(self.texture_path(texture, owner)))
        source = self.colorspace_name(texture.colorspace, "usd_uvtexture")
        if source:
            reader.CreateInput("sourceColorSpace", Sdf.ValueTypeNames.Token).Set(source)
        scale, bias = texture.scale, texture.bias
        if texture.normal_map is not None:
            # UsdUVTexture's scale and bias are the whole decode (UsdPreviewSurface spec, "normal"): a MaterialX
            # normalmap's 2 t - 1 and strength (x, y) folded into any scale and bias before it
            decoded_scale, decoded_bias = normal_decode(texture)
            scale, bias = decoded_scale + (1.0,), decoded_bias + (0.0,)  # alpha untouched
            if tuple(decoded_scale) != (2.0, 2.0, 2.0) or tuple(decoded_bias) != (-1.0, -1.0, -1.0):
                self.note(CONVERTED, f"{owner}: the normal map is decoded by the UsdUVTexture's scale "
                                     f"{_shown(decoded_scale)} and bias {_shown(decoded_bias)} (its strength or axis "
                                     "convention: Storm renders it); usd-core's NormalMapTextureValidator takes only "
                                     "(2, 2, 2) and (-1, -1, -1) for an 8-bit image and warns")
            if not source and texture.scale is None and texture.bias is None:
                reader.CreateInput("sourceColorSpace", Sdf.ValueTypeNames.Token).Set("raw")
        for name, value in (("scale", scale), ("bias", bias), ("fallback", texture.fallback)):
            if value is not None:
                reader.CreateInput(name, Sdf.ValueTypeNames.Float4).Set(_float4(value, name))
        if texture.wrap:
            for name, mode in zip(("wrapS", "wrapT"), texture.wrap):
                reader.CreateInput(name, Sdf.ValueTypeNames.Token).Set(ADDRESS_MODE_TO_WRAP.get(mode, mode))
        if texture.filter in ("closest", "cubic"):  # (UsdUVTexture has no filter input: renderers filter linearly)
            self.note(APPROXIMATED, f"{owner}: filter type {texture.filter!r} has no UsdUVTexture input; the preview "
                                    "filters linearly")
        primvar = self.UsdShade.Shader.Define(self.stage, self.unique_child(str(material.GetPath()), f"{base}_st"))
        primvar.CreateIdAttr("UsdPrimvarReader_float2")
        name = texture.texcoord if isinstance(texture.texcoord, str) and texture.texcoord else "st"
        if isinstance(texture.texcoord, int) and texture.texcoord != 0:
            name = f"st{texture.texcoord}"
            self.note(CONVERTED, f"{owner}: UV set {texture.texcoord} written as primvar {name!r}")
        primvar.CreateInput("varname", Sdf.ValueTypeNames.String).Set(name)
        coordinates = primvar.CreateOutput("result", Sdf.ValueTypeNames.Float2)
        if texture.uv is not None:
            transform = self.UsdShade.Shader.Define(self.stage, self.unique_child(str(material.GetPath()), f"{base}_transform"))
            transform.CreateIdAttr("UsdTransform2d")
            scale, rotation, translation = _place2d_as_transform2d(texture.uv)
            transform.CreateInput("scale", Sdf.ValueTypeNames.Float2).Set(scale)
            transform.CreateInput("rotation", Sdf.ValueTypeNames.Float).Set(rotation)
            transform.CreateInput("translation", Sdf.ValueTypeNames.Float2).Set(translation)
            transform.CreateInput("in", Sdf.ValueTypeNames.Float2).ConnectToSource(coordinates)
            coordinates = transform.CreateOutput("result", Sdf.ValueTypeNames.Float2)
        reader.CreateInput("st", Sdf.ValueTypeNames.Float2).ConnectToSource(coordinates)
        if texture.channels is not None and len(texture.channels) == 1:
            return reader.CreateOutput("rgba"[texture.channels[0]], Sdf.ValueTypeNames.Float)
        if usd_type == "float":  # a single-channel image feeding a float input: its value is R (and G, B)
            return reader.CreateOutput("r", Sdf.ValueTypeNames.Float)
        return reader.CreateOutput("rgb", Sdf.ValueTypeNames.Float3)


def _components(value) -> tuple:
    return tuple(value) if isinstance(value, (tuple, list)) else (value,)


def _fit(value, materialx_type: str):
    """``value`` with the component count of ``materialx_type`` (a float4 fallback for a color3)."""
    count = COMPONENTS.get(materialx_type, 1)
    values = _components(value)
    if count == 1:
        return float(values[0])
    values = (values * count)[:count] if len(values) == 1 else values[:count]
    return tuple(float(v) for v in values) + (1.0,) * (count - len(values))


def _per_output(value, channels, output_type: str):
    """A UsdUVTexture-style per-channel scale/bias as the factor for the output actually used."""
    if value is None:
        return None
    values = _components(value)
    if output_type == "float":
        return float(values[channels[0]] if channels and len(values) > channels[0] else values[0])
    return _fit(values, output_type)


def _float4(value, name: str) -> tuple:
    values = _components(value)
    if len(values) == 1:
        return (float(values[0]),) * 4
    padding = {"scale": 1.0, "bias": 0.0, "fallback": 1.0}[name]
    return tuple(float(v) for v in values[:4]) + (padding,) * (4 - min(len(values), 4))


def _place2d_as_transform2d(uv: UVTransform) -> tuple[tuple, float, tuple]:
    """Inverse of the reader's ``_transform2d_as_place2d``, including a pivot:
    place2d(st) = R_cw(a)((st - p) / S) - o + p, UsdTransform2d(st) = R_ccw(r)(st * s) + t, so
    s = 1 / S, r = -a and t = p - o - R_cw(a)(p / S)."""
    angle = math.radians(uv.rotate)
    px, py = (p / s if s else 0.0 for p, s in zip(uv.pivot, uv.scale))
    rotated = (math.cos(angle) * px + math.sin(angle) * py, -math.sin(angle) * px + math.cos(angle) * py)
    translation = (uv.pivot[0] - uv.offset[0] - rotated[0], uv.pivot[1] - uv.offset[1] - rotated[1])
    scale = tuple(1.0 / s if s else 0.0 for s in uv.scale)
    return scale, -uv.rotate + 0.0, tuple(t + 0.0 for t in translation)


def _shown(values) -> str:
    return "(" + ", ".join(f"{float(v):.4g}" for v in values) + ")"
