"""Following USD shading connections: from a shader input to a constant (through Material and
NodeGraph interfaces), a texture lookup, or a node the toolkit does not interpret.

Part of the USD reader (:mod:`.usd_reader`), kept apart because it is its own idea: how UsdShade
networks encode what the model calls a :class:`~openpbr_tools.model.Texture`.

* MaterialX image chains: ``ND_image_*``/``ND_tiledimage_*`` reached through ``extract``,
  ``separate*``, ``convert``/``dot``, ``normalmap``, and ``multiply``/``add`` by a constant (taken
  as the texture's scale and bias); ``place2d`` (and ``tiledimage`` tiling), ``texcoord`` or
  ``geompropvalue`` on the coordinates.
* ``UsdUVTexture``: the output used (``r``, ``g``, ``b``, ``a``, ``rgb``) gives the channel;
  ``sourceColorSpace``, ``scale``, ``bias``, ``fallback``, ``wrapS``/``wrapT``; ``UsdTransform2d``
  and ``UsdPrimvarReader_float2`` on ``st``.

Values come back as plain Python (floats, ints, bools, strings, tuples); single-precision floats as
the shortest decimal that is the same float32.
"""

from __future__ import annotations

import math
import os
import struct

from ...model import Connection, Constant, Input, Texture, UVTransform
from ..paths import Kind, classify
from .sdr import materialx_nodedef
from .types import (
    MATERIALX_TO_USD,
    PRIMVAR_READER_PREFIX,
    TRANSFORM_2D_ID,
    USD_TO_MATERIALX,
    UV_TEXTURE_ID,
    UV_TEXTURE_OUTPUTS,
)

DEFAULT_UV_PRIMVAR = "st"  # the conventional UV primvar: read as the default UV set (texcoord None)
MAX_DEPTH = 32
_CHANNEL_OUTPUTS = {"outr": 0, "outg": 1, "outb": 2, "outa": 3, "outx": 0, "outy": 1, "outz": 2, "outw": 3}


class NetworkReader:
    """Connection-following half of the USD reader. Expects ``stage``, ``asset``, ``path``,
    ``root_layer``, ``root_dir``, ``UsdShade``, ``Usd``, ``colorspace_of_prim``,
    ``observed_colorspaces`` and ``location()``."""

    # -- colour spaces ----------------------------------------------------------------------
    def authored_prim_colorspace(self, prim) -> str | None:
        attribute = prim.GetAttribute("colorSpace:name")
        if attribute and attribute.HasAuthoredValue():
            return str(attribute.Get())
        return None

    def inherited_colorspace(self, prim) -> str | None:
        """The ``Usd.ColorSpaceAPI`` name in effect at ``prim`` (its own or the nearest ancestor's).
        Walks up without recursion: prims may nest deeper than Python's stack."""
        walked = []
        name = None
        while prim and not prim.IsPseudoRoot():
            key = prim.GetPath()
            if key in self.colorspace_of_prim:
                name = self.colorspace_of_prim[key]
                break
            walked.append(key)
            if prim.HasAPI(self.Usd.ColorSpaceAPI):
                name = self.authored_prim_colorspace(prim)
                if name is not None:
                    break
            prim = prim.GetParent()
        for key in walked:
            self.colorspace_of_prim[key] = name
        return name

    def attribute_colorspace(self, attribute, scheme: str) -> str | None:
        """The attribute's ``colorSpace`` metadata, observed for the naming-scheme check."""
        if not attribute.HasColorSpace():
            return None
        name = str(attribute.GetColorSpace())
        self.observe_colorspace(self.location(attribute.GetPrim().GetPath(), input_name(attribute)), name, scheme,
                                "colorSpace metadata")
        return name

    def observe_colorspace(self, where, name: str, scheme: str, owner: str) -> None:
        """Record a colour-space name and the scheme its place wants, once per place (a texture
        node read by two inputs is one place)."""
        key = (where.path, where.input, name)
        if key not in self.observed_colorspaces:
            self.observed_colorspaces.add(key)
            self.asset.observe("usd_colorspace", where, name=name, scheme=scheme, owner=owner)

    # -- connections ------------------------------------------------------------------------
    def source(self, attribute):
        """Follow ``attribute``'s connection through node-graph and material interfaces.

        Returns ``("shader", prim, output_name, interface_name)``, ``("value", attribute,
        interface_name)`` for an attribute that is not connected (its own value, if any, applies),
        or ``("dangling", target, reason)``.
        """
        interface = None
        for _ in range(MAX_DEPTH):
            targets = attribute.GetConnections()
            if not targets:
                return ("value", attribute, interface)
            target = targets[0]
            prim = self.stage.GetPrimAtPath(target.GetPrimPath())
            if not prim:
                return ("dangling", str(target), f"no prim at {target.GetPrimPath()}")
            property_name = str(target.name)
            if prim.IsA(self.UsdShade.Shader):
                if not property_name.startswith("outputs:"):
                    return ("dangling", str(target), "a connection must name a shader output")
                return ("shader", prim, property_name[len("outputs:"):], interface)
            if prim.IsA(self.UsdShade.NodeGraph):
                upstream = prim.GetAttribute(property_name)
                if not upstream:
                    return ("dangling", str(target), f"{prim.GetPath()} has no {property_name}")
                if property_name.startswith("inputs:") and interface is None:
                    interface = property_name[len("inputs:"):]
                attribute = upstream
                continue
            return ("dangling", str(target), f"{prim.GetPath()} is a {prim.GetTypeName() or 'typeless prim'}, not a shader or node graph")
        return ("dangling", str(attribute.GetPath()), "connection cycle")

    def interpret(self, attribute, entry: Input, consumer):
        kind, *found = self.source(attribute)
        if kind == "dangling":
            target, reason = found
            return Connection(target, None, reason, dangling=True)
        if kind == "value":
            origin, interface = found
            entry.interface_name = interface
            if origin is not attribute:
                if not self.check_connection_type(entry, origin, str(origin.GetTypeName())):
                    return None  # OPBR1005: the value cannot be read as the input's type
                if origin.HasColorSpace() and not entry.authored_colorspace:
                    entry.authored_colorspace = self.attribute_colorspace(
                        origin, "materialx" if consumer[1] == "mtlx" else "usd")
                    entry.colorspace = entry.authored_colorspace
            return _constant(origin)
        prim, output_name, interface = found
        entry.interface_name = interface
        value = self.texture_chain(prim, output_name, entry, consumer)
        if not isinstance(value, Texture):
            self.check_connection_type(entry, prim.GetAttribute(f"outputs:{output_name}"),
                                       self.declared_output_type(prim, output_name))
        return value

    def check_connection_type(self, entry: Input, origin, origin_type: str | None) -> bool:
        """Record a connection between attributes whose values cannot line up (a ``float`` source
        for a ``color3f`` input): USD does not convert, renderers read garbage or the default.
        Returns whether the types line up."""
        if origin_type is None:
            return True
        if _shape(origin_type) == _shape(entry.source_type):
            return True
        self.asset.observe(
            "usd_connection_type_mismatch", entry.location, input=entry.name,
            source=str(origin.GetPath()) if origin else None, source_type=origin_type, input_type=entry.source_type,
        )
        return False

    def declared_output_type(self, prim, output_name: str) -> str | None:
        attribute = prim.GetAttribute(f"outputs:{output_name}")
        if attribute:
            return str(attribute.GetTypeName())
        shader_id = str(self.UsdShade.Shader(prim).GetShaderId() or "")
        if shader_id == UV_TEXTURE_ID:
            return {"rgb": "float3"}.get(output_name, "float") if output_name in UV_TEXTURE_OUTPUTS else None
        nodedef = materialx_nodedef(shader_id)
        if nodedef is not None:
            port = nodedef.getActiveOutput(output_name)
            if port is not None:
                return MATERIALX_TO_USD.get(port.getType())
        return None

    def upstream(self, prim, input_name: str):
        attribute = prim.GetAttribute(f"inputs:{input_name}")
        if not attribute:
            return ("value", None, None)
        return self.source(attribute)

    def texture_chain(self, prim, output_name: str, entry: Input, consumer):
        """Walk ``extract``/``separate``/``convert``/``normalmap``/``multiply``/``add`` to an image
        node (MaterialX) or a UsdUVTexture; anything else is a :class:`Connection`."""
        channels = normal_scale = scale = bias = None
        first = (prim, output_name)
        for _ in range(8):
            shader_id = str(self.UsdShade.Shader(prim).GetShaderId() or "")
            if shader_id == UV_TEXTURE_ID:
                return self.uv_texture(prim, output_name, entry, consumer)
            nodedef = materialx_nodedef(shader_id)
            category = nodedef.getNodeString() if nodedef is not None else None
            if category in ("image", "tiledimage"):
                return self.materialx_image(prim, nodedef, channels, normal_scale, scale, bias)
            if category is not None and category.startswith("separate") and output_name in _CHANNEL_OUTPUTS:
                channels = (_CHANNEL_OUTPUTS[output_name],)
                step = "in"
            elif category == "extract":
                index = _constant_of(prim, "index")
                channels = (int(index) if isinstance(index, (int, float)) else 0,)
                step = "in"
            elif category == "normalmap":
                strength = _constant_of(prim, "scale")
                normal_scale = float(strength) if isinstance(strength, (int, float)) else 1.0
                step = "in"
            elif category in ("convert", "dot"):
                step = "in"
            elif category in ("multiply", "add") and _unconnected(prim.GetAttribute("inputs:in2")):
                factor = _constant_of(prim, "in2")
                if factor is None:
                    break
                if category == "multiply":
                    scale = factor
                else:
                    bias = factor
                step = "in1"
            else:
                break
            kind, *found = self.upstream(prim, step)
            if kind != "shader":
                break
            prim, output_name, _ = found
        node, out = first
        shader_id = str(self.UsdShade.Shader(node).GetShaderId() or "") or None
        return Connection(f"{node.GetPath()}.outputs:{out}", shader_id,
                          f"{shader_id or 'a shader without info:id'} is not a texture lookup")

    def materialx_image(self, prim, nodedef, channels, normal_scale, scale, bias) -> Texture:
        path = str(prim.GetPath())
        file_attribute = prim.GetAttribute("inputs:file")
        file, packaged = self.file_of(file_attribute)
        colorspace = None
        if file_attribute:
            colorspace = self.attribute_colorspace(file_attribute, "materialx") or self.inherited_colorspace(prim)
        texture = Texture(
            file=file, image_type=nodedef.getType(), channels=channels, colorspace=colorspace,
            normal_map=normal_scale, scale=scale, bias=bias, node=path,
            node_category=nodedef.getNodeString(), location=self.location(path, "file"), packaged=packaged,
        )
        texture.fallback = _constant_of(prim, "default")
        wrap_u, wrap_v = _constant_of(prim, "uaddressmode"), _constant_of(prim, "vaddressmode")
        if wrap_u is not None or wrap_v is not None:
            texture.wrap = (wrap_u or "periodic", wrap_v or "periodic")
        transform = UVTransform()
        if texture.node_category == "tiledimage":
            tiling, offset = _constant_of(prim, "uvtiling"), _constant_of(prim, "uvoffset")
            if tiling is not None:
                transform.scale = (float(tiling[0]), float(tiling[1]))
            if offset is not None:
                transform.offset = (float(offset[0]), float(offset[1]))
        kind, *found = self.upstream(prim, "texcoord")
        for _ in range(4):
            if kind != "shader":
                break
            node = found[0]
            nodedef_upstream = materialx_nodedef(str(self.UsdShade.Shader(node).GetShaderId() or ""))
            category = nodedef_upstream.getNodeString() if nodedef_upstream is not None else None
            if category == "place2d":
                for field, key in (("scale", "scale"), ("offset", "offset"), ("pivot", "pivot")):
                    value = _constant_of(node, key)
                    if value is not None:
                        setattr(transform, field, (float(value[0]), float(value[1])))
                rotate = _constant_of(node, "rotate")
                if rotate is not None:
                    transform.rotate = float(rotate)
                kind, *found = self.upstream(node, "texcoord")
                continue
            if category == "texcoord":
                index = _constant_of(node, "index")
                if isinstance(index, int) and index != 0:
                    texture.texcoord = index
            elif category == "geompropvalue":
                texture.texcoord = _constant_of(node, "geomprop")
            break
        texture.uv = None if transform.is_identity and transform.pivot == (0.0, 0.0) else transform
        return texture

    def uv_texture(self, prim, output_name: str, entry: Input, consumer) -> Texture | Connection:
        path = str(prim.GetPath())
        if output_name not in UV_TEXTURE_OUTPUTS:
            return Connection(f"{path}.outputs:{output_name}", UV_TEXTURE_ID,
                              f"UsdUVTexture has no output {output_name!r} (r, g, b, a, rgb)", dangling=True)
        channels = UV_TEXTURE_OUTPUTS[output_name]
        file_attribute = prim.GetAttribute("inputs:file")
        file, packaged = self.file_of(file_attribute)
        source = prim.GetAttribute("inputs:sourceColorSpace")
        colorspace = None
        if source and source.HasAuthoredValue():
            colorspace = str(source.Get())
            self.observe_colorspace(self.location(path, "sourceColorSpace"), colorspace, "usd_uvtexture",
                                    "sourceColorSpace")
        if file_attribute:
            metadata = self.attribute_colorspace(file_attribute, "usd")
            colorspace = colorspace or metadata
        model, _, parameter = consumer
        wants = entry.type if entry.type in ("color3", "vector3") else "color3"
        texture = Texture(
            file=file, image_type=wants if channels is None else "color4", channels=channels, colorspace=colorspace,
            scale=_constant_of(prim, "scale"), bias=_constant_of(prim, "bias"), fallback=_constant_of(prim, "fallback"),
            node=path, node_category=UV_TEXTURE_ID, location=self.location(path, "file"), packaged=packaged,
        )
        if parameter is not None and parameter.role == "normal" and model == "UsdPreviewSurface":
            texture.normal_map = 1.0  # the preview surface consumes tangent-space normals directly
        wrap_s, wrap_t = _constant_of(prim, "wrapS"), _constant_of(prim, "wrapT")
        if wrap_s is not None or wrap_t is not None:
            texture.wrap = (wrap_s or "useMetadata", wrap_t or "useMetadata")
        kind, *found = self.upstream(prim, "st")
        for _ in range(4):
            if kind != "shader":
                break
            node = found[0]
            node_id = str(self.UsdShade.Shader(node).GetShaderId() or "")
            if node_id == TRANSFORM_2D_ID:
                texture.uv = _transform2d_as_place2d(node)
                kind, *found = self.upstream(node, "in")
                continue
            if node_id.startswith(PRIMVAR_READER_PREFIX):
                varname = _constant_of(node, "varname")
                texture.texcoord = None if varname == DEFAULT_UV_PRIMVAR else varname
            break
        return texture

    def file_of(self, attribute) -> tuple[str, bool]:
        """The texture path relative to the asset's folder (or inside its package), and whether it
        is packaged. A path authored in another layer is re-anchored at the root layer's folder."""
        if not attribute:
            return "", False
        value = attribute.Get()
        authored = getattr(value, "path", None) if value is not None else None
        if not authored:
            return "", False
        # No file name holds a NUL, and path functions raise on one: shown as U+FFFD (still not found)
        authored = authored.replace("\0", "\ufffd")
        layer = self.root_layer
        for spec in attribute.GetPropertyStack():
            if spec.HasDefaultValue():
                layer = spec.layer
                break
        packaged = ".usdz" in layer.identifier.lower()
        if packaged or layer.identifier == self.root_layer.identifier or classify(authored) is not Kind.RELATIVE:
            return authored, packaged  # as authored: a URL, an absolute, drive or UNC path is not re-anchored
        if not layer.realPath:
            return authored, False
        # USD's resolver looks a relative path up beside the layer that authored it first; spelled
        # relative to the root layer's folder (whether that stays inside is the texture rules' call)
        anchored = os.path.normpath(os.path.join(os.path.dirname(layer.realPath), authored))
        return os.path.relpath(anchored, self.root_dir).replace(os.sep, "/"), False


# -- values -------------------------------------------------------------------------------------

def _unconnected(attribute) -> bool:
    """An authored input with a value of its own (a constant operand), not a connection."""
    return bool(attribute) and not attribute.GetConnections()


def _shape(usd_type: str | None) -> tuple:
    """What must match for a connection to carry values unchanged: component count and kind
    (number, integer, boolean, text); roles (color3f vs float3) and precision do not matter."""
    from ...values import COMPONENTS

    materialx = USD_TO_MATERIALX.get(usd_type or "", usd_type)
    kind = "text" if materialx in ("string", "filename") else materialx if materialx in ("boolean", "integer") else "number"
    return COMPONENTS.get(materialx or ""), kind


def _constant(attribute):
    """The attribute's value as a :class:`Constant`, or ``None`` when it has none."""
    if attribute is None:
        return None
    value = attribute.Get()
    if value is None:
        if not attribute.GetNumTimeSamples():
            return None
        from pxr import Usd

        value = attribute.Get(Usd.TimeCode.EarliestTime())  # the first sample, without listing them all
    scalar = str(attribute.GetTypeName().scalarType)
    single = scalar.startswith(("float", "half")) or scalar.endswith(("f", "h"))
    return Constant(_python(value, single))


def _constant_of(prim, input_name: str):
    attribute = prim.GetAttribute(f"inputs:{input_name}")
    if not attribute:
        return None
    constant = _constant(attribute)
    return constant.value if constant is not None else None


#: Array values longer than this are summarised, not converted (no OpenPBR input is an array).
MAX_ARRAY_VALUES = 64


def _python(value, single_precision: bool):
    """A pxr value as plain Python: float, int, bool, str, or a flat tuple of numbers (vectors,
    matrices and arrays of them flattened, as MaterialX writes them). Single-precision floats come
    back as the shortest decimal that is the same float32 (0.8, not 0.800000011920929); arrays of
    text are joined with ", "; arrays longer than :data:`MAX_ARRAY_VALUES` are summarised."""
    if isinstance(value, bool):
        return value
    if isinstance(value, float):
        return _shortest_float32(value) if single_precision else value
    if isinstance(value, int):
        return value
    if isinstance(value, str):
        return value
    path = getattr(value, "path", None)
    if isinstance(path, str):
        return path
    try:
        count = len(value)
    except TypeError:
        count = None
    if count is not None and count > MAX_ARRAY_VALUES:
        return f"({count} values)"
    try:
        items = list(value)
    except TypeError:
        return str(value)
    flat = []
    for item in items:
        converted = _python(item, single_precision)
        if isinstance(converted, tuple):
            flat.extend(converted)
        else:
            flat.append(converted)
    if any(isinstance(item, str) for item in flat):
        return ", ".join(str(item) for item in flat)
    return tuple(flat)


_FLOAT32 = struct.Struct("f")


def _shortest_float32(x: float) -> float:
    if not math.isfinite(x):
        return x
    try:
        target = _FLOAT32.unpack(_FLOAT32.pack(x))[0]
    except OverflowError:
        return x
    for digits in range(6, 10):
        candidate = float(f"{target:.{digits}g}")
        if _FLOAT32.unpack(_FLOAT32.pack(candidate))[0] == target:
            return candidate
    return target


def _transform2d_as_place2d(prim) -> UVTransform:
    """UsdTransform2d computes ``R(rotation) (st * scale) + translation`` with R counter-clockwise
    (UsdPreviewSurface spec); MaterialX ``place2d`` (SRT, pivot 0) computes
    ``rotate2d(st / scale, rotate) - offset`` where ``rotate2d`` turns clockwise (stdlib
    ``mx_rotate_vector2``). Equal when scale = 1/scale, rotate = -rotation, offset = -translation."""
    scale = _constant_of(prim, "scale") or (1.0, 1.0)
    rotation = _constant_of(prim, "rotation") or 0.0
    translation = _constant_of(prim, "translation") or (0.0, 0.0)
    inverse = tuple(_shortest_float32(1.0 / s) if s else math.inf for s in scale)
    return UVTransform(
        scale=(inverse[0], inverse[1]), rotate=-float(rotation) + 0.0,
        offset=(-float(translation[0]) + 0.0, -float(translation[1]) + 0.0),
    )


def input_name(attribute) -> str:
    name = str(attribute.GetName())
    return name.removeprefix("inputs:")
