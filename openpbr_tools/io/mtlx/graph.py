"""Following a MaterialX node graph upstream of a shader input: what a connection means.

:class:`GraphFollower` (a base of the reader's ``_Reader``) resolves a connected input through
``nodegraph``/``output`` and ``interfacename`` indirections to the node feeding it, and interprets that
node: an ``image``/``tiledimage`` chain (through ``extract``, ``convert``, ``normalmap``, ``separate``;
``place2d`` and ``texcoord`` on its coordinates) becomes a :class:`~openpbr_tools.model.Texture`;
anything else a :class:`~openpbr_tools.model.Connection`, with the procedural graph captured as a
MaterialX document so a read-write round trip keeps it. The reader reads documents and materials
(:mod:`.reader`); this module only walks from an input upstream.

One module because the walk is one recursion: how an image's coordinates, channels and decode are read
decides whether it is a Texture or the graph is kept whole, and each step calls back into the others.
"""

from __future__ import annotations

import dataclasses
import math

from ...model import Connection, Constant, Location, Texture, UVTransform, graph_key, normal_strength, texture_key
from ...values import ValueSyntaxError, parse_value
from . import gltf_nodes
from .arithmetic import ScaleBias, connected as _connected
from .capture import capture_graph, capture_nodegraph, interface_input, read_output, select_output
from .library import standard_library

#: The geometric node categories whose world-space output is a shading model's default (defaultgeomprop).
_WORLD_GEOMETRY = {"normal": "Nworld", "tangent": "Tworld", "bitangent": "Bworld"}
#: Node categories whose output changes over a surface (geometric properties, the view) or in time.
VARYING_CATEGORIES = frozenset({"texcoord", "position", "normal", "tangent", "bitangent", "geomcolor", "geompropvalue",
                                "viewdirection", "time", "frame"})
IMAGE_CATEGORIES = ("image", "tiledimage", "gltf_image", "gltf_colorimage", "gltf_normalmap", "UsdUVTexture")
PASS_THROUGH = ("convert", "dot")


class GraphFollower:
    """Upstream walks for a reader that has ``path`` (the file) and ``asset`` (its ``line_of``)."""

    def upstream_node(self, port):
        """The node feeding ``port`` (through a node graph output or an interface input), or None."""
        if port.hasAttribute("interfacename"):
            graph_input = port.getInterfaceInput()
            if graph_input is None:
                return None
            if graph_input.hasAttribute("nodename") or graph_input.hasAttribute("nodegraph"):
                return self.upstream_node(graph_input)
            return None
        output = port.getConnectedOutput()
        if output is not None and output.getParent().getCategory() in ("nodegraph", "materialx"):
            return output.getConnectedNode()  # a node graph's (or the document's) output
        # a multi-output node's own output (an <output> child of the node or of its nodedef): the node
        # itself feeds the port
        return port.getConnectedNode()

    def default_geometry(self, port) -> bool:
        """Whether a shader input reads the geometric property its node definition defaults to anyway: a ``normal``,
        ``tangent`` or ``bitangent`` node in world space on an input whose nodedef has ``defaultgeomprop`` Nworld,
        Tworld or Bworld (as MaterialX's own exports and GPUOpen's materials write them). Such an input is read as
        unauthored: it changes nothing, and a conversion that cannot hold the node loses nothing."""
        node = self.upstream_node(port) if port.hasAttribute("nodename") else None
        default = _WORLD_GEOMETRY.get(node.getCategory()) if node is not None else None
        if default is None or any(i.getName() != "space" for i in node.getInputs()):
            return False
        space = node.getInput("space")
        if space is None or space.getValueString() != "world":
            return False  # (the nodes default to object space)
        nodedef = port.getParent().getNodeDef()
        declared = nodedef.getActiveInput(port.getName()) if nodedef is not None else None
        return declared is not None and declared.getDefaultGeomPropString() == default

    def follow_shader_input(self, port):
        """:meth:`follow` for an input of a shader node: a texture on a UsdPreviewSurface's ``normal`` is a
        tangent-space vector decoded by its scale and bias (multiply/add nodes; MaterialX's
        implementation re-encodes it for its own normalmap), as the USD reader reads a UsdUVTexture's."""
        value = self.follow(port)
        if isinstance(value, Texture) and value.normal_map is None and port.getName() == "normal" \
                and port.getParent().getCategory() == "UsdPreviewSurface":
            value.normal_map, value.decoded_by_scale_bias = 1.0, True
        return value

    def follow(self, port):
        """Interpret what feeds ``port``: a :class:`Texture` for an image chain, else a
        :class:`Connection` (dangling when the reference does not resolve)."""
        self.followed_space = self.followed_unit = None
        if port.hasAttribute("interfacename"):
            graph_input = port.getInterfaceInput()
            if graph_input is None:
                return Connection(port.getInterfaceName(), None, "interface input not found", dangling=True)
            if not (graph_input.hasAttribute("nodename") or graph_input.hasAttribute("nodegraph")):
                if graph_input.hasAttribute("value"):
                    try:
                        self.followed_space = graph_input.getActiveColorSpace() or None
                        self.followed_unit = (graph_input.getUnitType() or None, graph_input.getUnit() or None)
                        return Constant(parse_value(graph_input.getValueString(), graph_input.getType()))
                    except ValueSyntaxError as error:
                        return Connection(graph_input.getNamePath(), None, str(error))
                return Connection(graph_input.getNamePath(), None, "interface input has no value")
            return self.follow(graph_input)
        target = port.getNodeName() or port.getNodeGraphString()
        node = self.upstream_node(port)
        if node is None:
            output = port.getOutputString()
            named = f"{target}.{output}" if target and output else target or output  # a graph's missing output too
            return Connection(named, None, "connection target not found", dangling=True)
        constant = _constant_value(self, node, port.getType(), port.getOutputString() if port.getNodeName() else "")
        if constant is not None:
            constant, held = constant
            self.followed_space = held.getActiveColorSpace() or None  # the colour space the value is in
            self.followed_unit = (held.getUnitType() or None, held.getUnit() or None)  # and the unit MaterialX converts
            return constant
        read = read_output(port)
        texture = self.texture_chain(node, read)
        if texture is not None:
            graph = capture_nodegraph(port) if self.binding is None else None
            if graph is None:
                return texture
            texture = dataclasses.replace(texture, kept_graph=graph[0], kept_output=graph[1])
            return dataclasses.replace(texture, kept_for=texture_key(texture))
        graph_xml, output = capture_graph(node, binding=self.binding), node.getName()
        if graph_xml and node.getType() == "multioutput" and read:  # (which output: a dot reads it)
            graph_xml, output = select_output(graph_xml, output, read, port.getType())
        kept = capture_nodegraph(port) if graph_xml and self.binding is None else None
        return Connection(
            node.getNamePath(), node.getCategory(), f"{node.getCategory()} node is not a texture lookup",
            graph_xml=graph_xml, output=output, varying=self.varies(node, read, self.binding),
            kept_graph=kept[0] if kept else None, kept_output=kept[1] if kept else None,
            kept_for=graph_key(graph_xml, output) if kept else None,
        )

    def varies(self, node, output_name: str = "", binding=None, depth: int = 0) -> bool:
        """Whether output ``output_name`` of ``node`` can change over a surface: a node on its way reads a file (an
        image), a geometric property (:data:`VARYING_CATEGORIES`), or leaves an input unconnected whose definition
        defaults to one (``defaultgeomprop``: a noise's position, a ramp's texture coordinates). A node a graph
        implements is followed from the output read through its implementation, so only the inputs that output
        depends on count (MaterialX's standard_surface_to_gltf_pbr passes the normal through, which its
        attenuation colour does not read). Constants and arithmetic do not vary; an unknown node does."""
        if depth > 64 or node.getCategory() in VARYING_CATEGORIES or any(p.getType() == "filename" for p in node.getInputs()):
            return True
        try:
            nodedef = node.getNodeDef()
        except Exception:  # noqa: BLE001 - MaterialX raises on some broken definitions (reported elsewhere)
            return True
        if nodedef is None:
            return True
        inner = _implementation_output(node, output_name) or _library_implementation_output(node, nodedef, output_name)
        if inner is not None:
            return self.varies(inner[0], "", inner[1], depth + 1)
        for declared in nodedef.getActiveInputs():
            held, held_binding = _held_by_interface(node.getInput(declared.getName()), binding)
            if held is None or not _connected(held):
                # an authored value holds; else the default of the definition the port (or the interface) reads: an
                # outer nodedef's input reached through interfacename, or this node's own
                sources = [held] if held is not None and held.hasAttribute("value") else \
                    [s for s in (held, declared) if s is not None]
                if any(s.getType() == "filename" or s.hasDefaultGeomPropString() for s in sources):
                    return True
                continue
            upstream = self.upstream_node(held)
            if upstream is None or self.varies(upstream, read_output(held), held_binding, depth + 1):
                return True
        return False

    def texture_chain(self, node, output_name: str = "") -> Texture | None:
        """Walk ``extract``/``convert``/``normalmap``/``separate`` to an image node; ``multiply`` and
        ``add`` by a constant before any ``normalmap`` are the texture's scale and bias (as a
        UsdUVTexture's: the writer puts them there)."""
        channels = None
        normal_scale = None
        arithmetic = ScaleBias()
        if output_name in ("outr", "outg", "outb", "outa", "outx", "outy", "outz", "outw") and node.getCategory().startswith("separate"):
            channels = ("rgba".find(output_name[-1]) if output_name[-1] in "rgba" else "xyzw".find(output_name[-1]),)
            node = self.upstream_node(node.getInput("in")) if node.getInput("in") else None
        for _ in range(8):
            if node is None:
                return None
            category = node.getCategory()
            if category in IMAGE_CATEGORIES:
                break
            if category == "extract":
                index = _number(node.getInput("index"))
                channels = (int(index) if index is not None else 0,)
            elif category in ("multiply", "add"):
                if not arithmetic.take(node, channels):
                    return None
            elif category == "mix":
                if not arithmetic.take_mix(node):
                    return None
            elif category == "normalmap":
                if arithmetic.seen:  # arithmetic after the decode: not a texture's scale and bias
                    return None
                normal_scale = _normal_scale(node.getInput("scale"))
                if normal_scale is None:  # a connected scale, or a vector2 one with different x and y
                    return None
            elif category not in PASS_THROUGH:
                return None
            elif category == "convert" and node.getType().startswith("color") and \
                    (source := node.getInput("in")) is not None and source.getType().startswith("vector"):
                return None  # a vector image read as a colour: no Texture holds that (nor its colour management)
            elif category == "convert" and channels is None and node.getType()[-1:] == "3" and \
                    (source := node.getInput("in")) is not None and source.getType() == node.getType()[:-1] + "4":
                channels = (0, 1, 2)  # color4 to color3 (vector4 to vector3): the fourth channel dropped
            upstream = node.getInput("in1" if category in ("multiply", "add") else "mix" if category == "mix" else "in")
            node = self.upstream_node(upstream) if upstream is not None else None
            # which output of the next node this step reads (a multi-output UsdUVTexture's rgb, say)
            output_name = read_output(upstream) if upstream is not None else ""
        else:
            return None
        image_type = None
        if node.getCategory() == "gltf_normalmap":  # an image and its tangent-space decode in one node
            if normal_scale is not None or arithmetic.seen:
                return None
            normal_scale, image_type = 1.0, "vector3"
        if node.getType() == "multioutput":  # e.g. gltf_colorimage: outcolor (color3) and outa (float)
            image_type, channel = _multioutput_type(node, output_name)
            if channel is not None and channels is None:
                channels = (channel,)
        own_transform = gltf_nodes.transform(node)  # (a glTF image node's own inputs)
        if not self.plain_coordinates(node) or own_transform is False or gltf_nodes.connected_factor(node) \
                or own_transform and self.uv_tiling(self.upstream_node(_coordinates(node)) if _coordinates(node) is not None
                                                    else None) is not None:
            # coordinates a Texture cannot hold (also a tiling multiply under a glTF image's own transform, which one
            # transform cannot compose with): the graph is kept whole, not read without them
            return None
        texture = self.image(node, channels, normal_scale, image_type)
        arithmetic.multiply(gltf_nodes.factor(node, channels if node.getType() == "multioutput" else None))
        texture.scale, texture.bias = arithmetic.values()
        texture.uv = own_transform or texture.uv
        return texture

    #: (instance, nodedef) while a custom shader node's implementation graph is read for that instance
    binding = None
    #: the colour space of the constant :meth:`follow` last returned (a constant node's or an interface
    #: input's value is in its own, which may not be the shader input's)
    followed_space = None
    #: (unittype, unit) of that constant's value, which MaterialX's unit system converts as the shader input's
    followed_unit = None

    def bound_file(self, file_input):
        """The element holding an image's file name: its ``file`` input or, where that is bound to an
        interface input (``interfacename``), the input it is bound to, whose value, file prefix and
        colour space the file then takes: the node graph's own input, or in a graph implementing a
        nodedef, the instance's input being read (:attr:`binding`), else the nodedef's default."""
        if file_input is None or not file_input.hasAttribute("interfacename"):
            return file_input
        bound, _ = interface_input(file_input, self.binding)
        if bound is None or not bound.hasAttribute("value"):
            return file_input
        return bound

    def image(self, node, channels, normal_scale, image_type: str | None = None) -> Texture:
        file_input = self.bound_file(node.getInput("file"))
        # MaterialX's string resolver: the enclosing elements' fileprefix and [token] substitutions
        # (<token name="resolution" value="1k"/> makes wood_[resolution].png wood_1k.png); <UDIM> stays
        file_value = file_input.getResolvedValueString() if file_input is not None else ""
        texture = Texture(
            file=file_value,
            image_type=image_type or node.getType(),
            channels=channels,
            colorspace=(file_input.getActiveColorSpace() if file_input is not None else node.getActiveColorSpace()) or None,
            colorspace_on_image=(file_input is not None and file_input.hasColorSpace()) or node.hasColorSpace(),
            normal_map=normal_scale,
            node=node.getNamePath(),
            node_category=node.getCategory(),
            location=Location(self.path, self.asset.line_of.get(node.getNamePath()), node.getNamePath(), "file"),
        )
        layer = node.getInput("layer")
        if layer is not None and layer.getValueString():
            texture.layer = layer.getValueString()
        filtering = node.getInput("filtertype")
        if filtering is not None and filtering.getValueString():
            texture.filter = filtering.getValueString()
        default = node.getInput("default")
        if default is not None and default.hasAttribute("value"):
            try:
                texture.fallback = parse_value(default.getValueString(), default.getType())
            except ValueSyntaxError:
                pass
        wrap_u, wrap_v = node.getInput("uaddressmode"), node.getInput("vaddressmode")
        if wrap_u is not None or wrap_v is not None:
            texture.wrap = (
                wrap_u.getValueString() if wrap_u is not None else "periodic",
                wrap_v.getValueString() if wrap_v is not None else "periodic",
            )
        texture.uv, texture.texcoord = self.uv_transform(node)
        texture.constant_uv = self.constant_placement(node)
        return texture

    def resolved_vector2(self, port) -> tuple[float, float] | None:
        """A vector2 input's constant value, followed through what only passes a constant on: a node graph's
        interface input with a value (or the custom node instance's), a ``convert`` or ``constant`` node (a
        float broadcast, as ND_convert_float_vector2 does): MaterialX's brick example tiles every map by a graph
        input ``uvtiling`` (float, 3) through a convert node. ``None`` for anything else."""
        for _ in range(8):
            if port is None:
                return None
            if port.hasAttribute("value"):
                return _vector2(port) if port.getType() == "vector2" else _broadcast(port)
            if port.hasAttribute("interfacename"):
                bound, _ = interface_input(port, self.binding)
                if bound is None or bound is port:
                    return None
                port = bound
                continue
            node = self.upstream_node(port)
            if node is None or node.getCategory() not in ("convert", "constant"):
                return None
            port = node.getInput("in" if node.getCategory() == "convert" else "value")
        return None

    def plain_coordinates(self, node) -> bool:
        """Whether the image reads coordinates a :class:`Texture` holds: the default UVs, a ``texcoord``
        node (its set), a ``place2d`` of constants on one (its transform) or on nothing (a constant
        placement, OPBR706), a ``tiledimage`` whose tiling and offset are constants (also through a graph
        input: :meth:`resolved_vector2`). Anything else -- UVs multiplied by a tiling, a constant or procedural
        coordinate, a tiling computed by nodes -- would be dropped by reading the image alone."""
        if node.getCategory() == "tiledimage":
            for name in ("uvtiling", "uvoffset", "realworldimagesize", "realworldtilesize"):
                port = node.getInput(name)
                if port is not None and not port.hasAttribute("value") and (
                        name.startswith("realworld") or self.resolved_vector2(port) is None):
                    return False
        port = _coordinates(node)
        if port is None:
            return True
        place = self.upstream_node(port)
        if place is None:
            return not port.hasAttribute("value") and not _connected(port)
        if self.uv_tiling(place) is not None:
            return True
        if place.getCategory() == "place2d":
            if any(_connected(p) for p in place.getInputs() if p.getName() != "texcoord"):
                return False
            if node.getCategory() == "tiledimage" and any(
                    p.getName() in ("rotate", "offset", "pivot") and p.hasAttribute("value") for p in place.getInputs()):
                return False  # a place2d's rotation or offset under a tiling: no one transform holds both (kept whole)
            inner = place.getInput("texcoord")
            if inner is None:
                return True
            place = self.upstream_node(inner)
            if place is None:
                return not _connected(inner)
        if _uv_primvar(place) is not None:
            return True
        return place.getCategory() == "texcoord" and not any(_connected(p) for p in place.getInputs())

    def uv_tiling(self, node):
        """((k_u, k_v), the ``texcoord`` node) where ``node`` multiplies texture coordinates by a constant (a value,
        a ``constant`` node or a graph input holding one; a float scales both): the UV tiling exporters write as
        ``texcoord * 2`` instead of a ``place2d``, which a Texture holds as a transform. ``None`` otherwise."""
        if node is None or node.getCategory() != "multiply" or node.getType() != "vector2":
            return None
        ports = [node.getInput("in1"), node.getInput("in2")]
        for uv_port, k_port in (ports, ports[::-1]):
            uv = self.upstream_node(uv_port) if uv_port is not None else None
            if uv is None or uv.getCategory() != "texcoord" or any(_connected(p) for p in uv.getInputs()):
                continue
            held, _ = _held_by_interface(k_port, self.binding) if k_port is not None else (None, None)
            if held is None:
                continue
            if _connected(held):
                upstream = self.upstream_node(held)
                constant = _constant_value(self, upstream, held.getType()) if upstream is not None else None
                value = constant[0].value if constant is not None else None
                k = (float(value), float(value)) if isinstance(value, (int, float)) and not isinstance(value, bool) \
                    else tuple(float(v) for v in value) if isinstance(value, tuple) and len(value) == 2 else None
            else:
                k = _broadcast(held) if held.hasAttribute("value") else None
            if k is not None and all(v != 0.0 and math.isfinite(v) for v in k):
                return k, uv
        return None

    def constant_placement(self, node) -> bool:
        """Whether the image's coordinates come from a ``place2d`` whose own ``texcoord`` is not
        connected: MaterialX 1.39's ``ND_place2d_vector2`` gives that input no default geometric
        property (unlike ``image``'s, which defaults to UV0), so its renderers read one texel, at
        (0, 0) or the authored value, everywhere."""
        texcoord = _coordinates(node)
        place = self.upstream_node(texcoord) if texcoord is not None else None
        if place is None or place.getCategory() != "place2d":
            return False
        inner = place.getInput("texcoord")
        return inner is None or self.upstream_node(inner) is None

    def uv_transform(self, node) -> tuple[UVTransform | None, int | None]:
        """The UV transform (``tiledimage`` tiling/offset, an upstream ``place2d``) and the UV
        set index (an upstream ``texcoord`` node; ``None`` for the default set 0)."""
        transform = UVTransform()
        uv_set = None
        if node.getCategory() == "tiledimage":
            tiling = self.resolved_vector2(node.getInput("uvtiling"))
            offset = self.resolved_vector2(node.getInput("uvoffset"))
            # NG_tiledimage: ((uv * tiling - offset) / realworldimagesize) * realworldtilesize, each size in its unit
            # (MaterialX converts both to the renderer's): a tiling and an offset times tilesize / imagesize
            ratio = _real_world_ratio(node)
            if tiling or ratio != (1.0, 1.0):
                tiling = tuple(t * r for t, r in zip(tiling or (1.0, 1.0), ratio))
                transform.scale = tuple(1.0 / v if v else float("inf") for v in tiling)
            if offset:
                transform.offset = tuple(o * r for o, r in zip(offset, ratio))
        texcoord = _coordinates(node)
        place = self.upstream_node(texcoord) if texcoord is not None else None
        tiling = self.uv_tiling(place)
        if tiling is not None:  # UVs times k: place2d's scale 1 / k (composed with a tiledimage's own tiling)
            (k_u, k_v), place = tiling
            transform.scale = (transform.scale[0] / k_u, transform.scale[1] / k_v)
        if place is not None and place.getCategory() == "place2d":
            # a tiledimage tiles the place2d's output: (uv / s) * tiling, so the scales compose (a product)
            placed = _vector2(place.getInput("scale"))
            transform.scale = (placed[0] * transform.scale[0], placed[1] * transform.scale[1]) if placed \
                else transform.scale
            transform.offset = _vector2(place.getInput("offset")) or transform.offset
            transform.pivot = _vector2(place.getInput("pivot")) or transform.pivot
            rotate = _number(place.getInput("rotate"))
            if rotate is not None:  # (text MaterialX cannot parse, "-nan(ind)": its default, 0, as MaterialX reads it)
                # place2d's rotate is in degrees (its nodedef's unit); MaterialX converts an input in radians (the
                # red team's D1: read as degrees, 1.5708 radians was a rotation of 1.57 degrees, and OPBR719 fired)
                radians = place.getInput("rotate").getUnit() == "radian"
                transform.rotate = math.degrees(rotate) if radians else rotate
            texcoord = place.getInput("texcoord")
            place = self.upstream_node(texcoord) if texcoord is not None else None
        if place is not None and place.getCategory() == "texcoord":
            index = _number(place.getInput("index"))
            if index is not None and int(index) != 0:
                uv_set = int(index)
        elif _uv_primvar(place) not in (None, *DEFAULT_UV_NAMES):
            uv_set = _uv_primvar(place)  # a UV set named by its primvar, as the USD reader keeps one
        return (None if transform.is_identity else transform), uv_set


def in_definition(element) -> bool:
    """Whether ``element`` lies in a node graph that implements a node definition."""
    parent = element.getParent()
    while parent is not None and parent.getCategory() != "materialx":
        if parent.getCategory() == "nodegraph" and parent.getAttribute("nodedef"):
            return True
        parent = parent.getParent()
    return False


#: The geometric properties a ``geompropvalue`` names for the default UV set: USD's conventional primvar (UsdMtlx,
#: Houdini and Omniverse read UVs so: the red team's G/F6, every Shader Playground material) and MaterialX's UV0.
DEFAULT_UV_NAMES = ("st", "UV0")


def _uv_primvar(node) -> str | None:
    """The primvar a ``geompropvalue`` of type vector2 reads as texture coordinates, where it names one constant
    (not connected) and has no default of its own (which a missing primvar would show); ``None`` otherwise."""
    if node is None or node.getCategory() != "geompropvalue" or node.getType() != "vector2":
        return None
    name, default = node.getInput("geomprop"), node.getInput("default")
    if name is None or _connected(name) or not name.getValueString() or default is not None:
        return None
    return name.getValueString()


def _coordinates(node):
    """An image node's coordinates input: UsdUVTexture's ``st``, the others' ``texcoord``."""
    return node.getInput("st" if node.getCategory() == "UsdUVTexture" else "texcoord")


def _number(port) -> float | None:
    """A float or integer input's authored value, or None where it has none or MaterialX cannot parse it (its
    ``getValue`` gives None; the validator reports the text: OPBR004)."""
    if port is None or not port.hasAttribute("value"):
        return None
    value = port.getValue()
    return float(value) if isinstance(value, (int, float)) and not isinstance(value, bool) else None


def _normal_scale(port) -> float | None:
    """A ``normalmap`` node's strength (:func:`normal_strength`), or None where it is connected or
    unreadable: a texture chain through it is then not one the model can hold."""
    if port is None:
        return 1.0
    if _connected(port):
        return None
    if not port.hasAttribute("value"):
        return 1.0
    try:
        return normal_strength(parse_value(port.getValueString(), port.getType()))
    except ValueSyntaxError:
        return None


def _constant_value(follower, node, type_name: str, output_name: str = ""):
    """A ``constant`` node (through ``dot`` nodes) with an authored value of the port's type: its
    value, as :class:`Constant` (MaterialX renders the same; UsdMtlx keeps such networks), and the port
    holding it (whose colour space the value is in), which may be a node graph interface input the node's port is
    bound to. A custom node (a nodedef implemented by a node graph in the document) is followed into its
    implementation, where ``interfacename`` reads the instance's input or the nodedef's default. A constant fed by a connection, or of another type,
    stays a connection."""
    binding = follower.binding
    for _ in range(8):
        if node is None:
            return None
        category = node.getCategory()
        if category not in ("dot", "constant"):
            inner = _implementation_output(node, output_name)
            if inner is None:
                return None
            node, binding, output_name = inner[0], inner[1], ""
            continue
        port, binding = _held_by_interface(node.getInput("in" if category == "dot" else "value"), binding)
        if port is None:
            return None
        if _connected(port):
            if category == "constant":
                return None
            node = follower.upstream_node(port)
            continue
        if not port.hasAttribute("value") or port.getType() != type_name:
            return None
        try:
            return Constant(parse_value(port.getValueString(), type_name)), port
        except ValueSyntaxError:
            return None
    return None


def _held_by_interface(port, binding):
    """(``port``, or the interface input it reads through ``interfacename`` (and that one's, in turn): a node graph's
    input, or in a graph implementing a nodedef the custom node instance's input or the nodedef's default; the
    binding its own connections are read with). ``None`` when an interface input named is missing."""
    for _ in range(8):
        if port is None or not port.hasAttribute("interfacename"):
            return port, binding
        port, binding = interface_input(port, binding)
    return None, None


def _implementation_output(node, output_name: str):
    """(the node behind the output of a custom node's implementation graph, the binding (instance, nodedef) the
    graph is read with) for a node whose nodedef a node graph implements; ``None`` for any other node."""
    try:
        nodedef = node.getNodeDef()
    except Exception:  # noqa: BLE001 - MaterialX raises on some broken definitions (reported elsewhere)
        return None
    return _graph_output(node, nodedef, output_name)


def _library_implementation_output(node, nodedef, output_name: str):
    """:func:`_implementation_output` through MaterialX's standard libraries, for a standard node whose graph the
    reader's document does not hold (it imports node definitions only: MaterialX's translation graphs)."""
    return _graph_output(node, standard_library().getNodeDef(nodedef.getName()), output_name)


def _graph_output(node, nodedef, output_name: str):
    """(the node behind ``output_name`` of ``nodedef``'s implementation graph, the binding (``node``, ``nodedef``)),
    or ``None`` where no node graph implements it or the output is not found."""
    try:
        implementation = nodedef.getImplementation() if nodedef is not None else None
    except Exception:  # noqa: BLE001 - as in _implementation_output
        return None
    if implementation is None or implementation.getCategory() != "nodegraph":
        return None
    outputs = implementation.getOutputs()
    output = implementation.getOutput(output_name) if output_name else (outputs[0] if len(outputs) == 1 else None)
    inner = output.getConnectedNode() if output is not None else None
    return (inner, (node, nodedef)) if inner is not None else None


def _real_world_ratio(node) -> tuple[float, float]:
    """A tiledimage's realworldtilesize / realworldimagesize per axis, each size in metres where it carries a
    distance unit (ND_tiledimage's defaults are (1, 1) both); (1, 1) where either is unusable."""
    from ...resources import load_json  # lazy: only for a tiledimage

    metres = load_json("units.json")["distance"]
    sizes = []
    for name in ("realworldimagesize", "realworldtilesize"):
        port = node.getInput(name)
        value = _vector2(port) if port is not None else (1.0, 1.0)
        if value is None:
            return (1.0, 1.0)
        unit = port.getUnit() if port is not None and port.getUnitType() == "distance" else ""
        factor = metres.get(unit, 1.0) if unit else 1.0
        sizes.append(tuple(v * factor for v in value))
    image, tile = sizes
    if not all(image) or not all(tile):
        return (1.0, 1.0)
    return (tile[0] / image[0], tile[1] / image[1])


def _broadcast(port) -> tuple[float, float] | None:
    """A float input's value as a vector2 (both components), or a vector2's."""
    try:
        value = parse_value(port.getValueString(), port.getType())
    except ValueSyntaxError:
        return None
    if isinstance(value, (int, float)) and not isinstance(value, bool):
        return (float(value), float(value))
    if isinstance(value, tuple) and len(value) == 2:
        return (float(value[0]), float(value[1]))
    return None


def _vector2(port) -> tuple[float, float] | None:
    if port is None or not port.hasAttribute("value"):
        return None
    try:
        value = parse_value(port.getValueString(), "vector2")
    except ValueSyntaxError:
        return None
    return (float(value[0]), float(value[1]))


def _multioutput_type(node, output_name: str) -> tuple[str, int | None]:
    """The type of output ``output_name`` of a multi-output image node, from its node definition,
    and the image channel it reads when it is one channel (``outa``: alpha). A connection without
    ``output`` reads the first output, as MaterialX does."""
    nodedef = node.getNodeDef()
    outputs = nodedef.getActiveOutputs() if nodedef is not None else []
    chosen = next((o for o in outputs if o.getName() == output_name), outputs[0] if outputs else None)
    if chosen is None:
        return "multioutput", None
    # a one-channel output: gltf_colorimage's outa, UsdUVTexture's r, g, b and a
    channel = {"outa": 3, "r": 0, "g": 1, "b": 2, "a": 3}.get(chosen.getName()) if chosen.getType() == "float" else None
    return chosen.getType(), channel


def interface_colorspace(node) -> tuple[str, str, str] | None:
    """``(interface input, its colour space, the one MaterialX applies)`` when the colour image ``node`` (in
    a node graph that implements no nodedef) takes its file name from an interface input tagged with a
    colour space that its own file input does not resolve to: MaterialX's shader generation reads the
    image's own file input's (its attribute, else the enclosing scope's), the specification the input
    that defines the file name. ``None`` otherwise."""
    port = node.getInput("file")
    scope = node.getParent()
    if port is None or not port.hasInterfaceName() or node.getType() not in ("color3", "color4") \
            or scope is None or scope.getCategory() != "nodegraph" or scope.getNodeDefString():
        return None
    interface = port.getInterfaceInput()
    if interface is None or not interface.hasColorSpace() or interface.getType() != "filename":
        return None
    applied = port.getActiveColorSpace() or "none"
    if applied == interface.getColorSpace():
        return None
    return interface.getNamePath(), interface.getColorSpace(), applied
