"""Write :class:`~openpbr_tools.model.Material` objects as a MaterialX 1.39 document.

Each material becomes a shader node plus a ``surfacematerial``; a :class:`Texture` becomes an
``image`` node (with ``extract`` for a single channel, ``normalmap`` for a normal map, and
``place2d``/``texcoord`` for a UV transform or set); an uninterpreted :class:`Connection` is written
back from the node graph the reader captured with it. Output is deterministic: elements in a fixed
order, values in the shortest text that reads back to the same number.
"""

from __future__ import annotations

import os

import MaterialX as mx

from ... import colorspaces, gltf_state, tables
from ...atomic import write_text
from ...model import Connection, Constant, Material, Texture, graph_key, kept, normal_decode, normal_encoding
from ...values import COMPONENTS, format_value
from ..usd.types import MATERIALX_ADDRESS_MODES, WRAP_TO_ADDRESS_MODE
from .looks import add_look

COLOUR_TYPES = ("color3", "color4")


def to_mtlx_string(materials: list[Material], colorspace: str | None = "lin_rec709", looks=()) -> str:
    """``materials`` as a MaterialX document; ``looks``: (MaterialX text of a look or look group, {source material
    name: written name}, names of its material assignments to leave out), added after the materials."""
    document = mx.createDocument()
    if colorspace:
        document.setColorSpace(colorspace)
    # material names first, as given (convert made them unique): shader and texture nodes take the rest
    names: list[str] = []
    taken: set[str] = set()
    for material in materials:
        names.append(_unique(material.material_name or f"{material.name}_material", taken))
    used = set(taken)
    written: dict[str, tuple[str, str | None]] = {}  # graphs written, by what they are (_write_connection)
    for material, name in zip(materials, names):
        _write_material(document, material, colorspace, used, name, written)
    for text, renames, left_out in looks:
        add_look(document, text, renames, left_out)
    return document_text(document)


def document_text(document) -> str:
    """A MaterialX document as text: XIncludes inlined rather than referenced, and the UDIM/UVTILE
    tokens escaped (MaterialX leaves them raw in attributes, which strict XML tools reject)."""
    options = mx.XmlWriteOptions()
    options.writeXIncludeEnable = False
    text = mx.writeToXmlString(document, options)
    return text.replace("<UDIM>", "&lt;UDIM&gt;").replace("<UVTILE>", "&lt;UVTILE&gt;")


def write_mtlx(materials: list[Material], path: str | os.PathLike, colorspace: str | None = "lin_rec709",
               looks=()) -> None:
    write_text(path, to_mtlx_string(materials, colorspace, looks))


def _unique(name: str, used: set[str]) -> str:
    candidate = mx.createValidName(name)
    base, index = candidate, 1
    while candidate in used:
        index += 1
        candidate = f"{base}_{index}"
    used.add(candidate)
    return candidate


def _write_material(document, material: Material, colorspace: str | None, used: set[str], material_name: str,
                    written: dict) -> None:
    table = tables.table(material.model, material.version) if material.version and tables.versions(material.model) else None
    short = material.name.rsplit("/", 1)[-1] or material.name  # a USD shader's prim path: its name
    if short == material.material_name:  # a USD shader named as its Material: the Material keeps the name
        short = f"{short}_shader"
    if short.startswith(("ND_", "NG_", "IM_")):  # UsdMtlx names shaders after their nodedef: MaterialX then confuses the two
        short = f"SR_{short}"
    shader_name = _unique(short, used)
    shader = document.addNode(material.model, shader_name, "surfaceshader")
    if material.declared_version:
        shader.setVersionString(material.declared_version)
    if material.nodedef:
        shader.setNodeDefString(material.nodedef)
    if material.colorspace and material.colorspace != colorspace:
        shader.setColorSpace(material.colorspace)
    for name in sorted(material.inputs):
        entry = material.inputs[name]
        parameter = table.get(name) if table else None
        type_name = entry.type or (parameter.type if parameter else "float")
        port = shader.addInput(name, type_name)
        value = entry.value
        if value is None and entry.raw is None:
            shader.removeInput(name)  # declared without a value (a USD interface input left unset): the default
            continue
        if isinstance(value, Constant):
            port.setValueString(format_value(value.value, type_name))
            if entry.authored_colorspace:
                port.setColorSpace(colorspaces.materialx_name(entry.authored_colorspace))
            elif type_name in COLOUR_TYPES and entry.colorspace and entry.colorspace != (material.colorspace or colorspace):
                port.setColorSpace(colorspaces.materialx_name(entry.colorspace))
        elif isinstance(value, Texture):
            tangent_vector = material.model == "UsdPreviewSurface" and parameter is not None and parameter.role == "normal"
            if tangent_vector or not _write_kept(document, port, value, used, written):  # (a graph gives world space)
                port.setNodeName(_write_texture(document, shader_name, name, type_name, value, used, tangent_vector))
        elif isinstance(value, Connection):
            if _write_kept(document, port, value, used, written):
                pass
            elif not _connect(port, _write_connection(document, shader_name, name, value, used, written)):
                shader.removeInput(name)  # nothing to connect (convert reported the dangling connection)
                continue
        elif entry.raw is not None:
            port.setValueString(entry.raw)
        if entry.unit:
            port.setUnit(entry.unit)
        if entry.unittype:
            port.setUnitType(entry.unittype)
    node = document.addMaterialNode(material_name, shader)
    node.setType("material")
    displacement = material.extra.get("displacement_graph")  # the source material's, kept whole (.mtlx to .mtlx)
    if isinstance(displacement, Connection):
        displaced = _write_connection(document, material_name, "displacement", displacement, used, written)
        if displaced:
            _connect(node.addInput("displacementshader", "displacementshader"), displaced)
    state = gltf_state.travelling(material)
    if state:
        node.setAttribute(gltf_state.MTLX_ATTRIBUTE, gltf_state.encode(state))


def _components(value, width: int) -> list[float]:
    flat = [float(v) for v in value] if isinstance(value, (tuple, list)) else [float(value)]
    return (flat * width)[:width] if len(flat) == 1 else flat[:width]


def _write_texture(document, shader_name: str, input_name: str, input_type: str, texture: Texture, used,
                   tangent_vector: bool = False) -> str:
    """The image chain of ``texture``; returns the node feeding the input. Scale and bias (a
    UsdUVTexture's, Texture.scale/bias) become ``multiply``/``add`` after the lookup. ``tangent_vector``:
    the input takes a tangent-space vector in [-1, 1] (UsdPreviewSurface's ``normal``: MaterialX's
    implementation re-encodes it and applies its own ``normalmap``), so a normal map is written as its
    decode (scale 2, bias -1, x and y by its strength) rather than through a ``normalmap`` node."""
    prefix = f"{shader_name}_{input_name}"
    image_type = texture.image_type or input_type
    if texture.normal_map is not None and texture.channels is None and image_type in ("color3", "color4", "vector4"):
        image_type = "vector3"  # (a UsdUVTexture's rgb, an RGBA image read as a normal map): what a normalmap decode takes
    if texture.channels is not None and len(texture.channels) == 1 and image_type in ("float", "integer", "boolean"):
        # one channel extracted from the image (a glTF colour image's outa): the image must have it
        image_type = "color4" if texture.channels[0] == 3 else "color3"
    image = document.addNode("tiledimage" if texture.node_category == "tiledimage" and texture.uv else "image",
                             _unique(f"{prefix}_image", used), image_type)
    file_input = image.addInput("file", "filename")
    file_input.setValueString(texture.file)
    if texture.colorspace:  # a USD name or UsdUVTexture token from a USD source, in MaterialX's words
        file_input.setColorSpace(colorspaces.materialx_name(texture.colorspace))
    if texture.layer:
        image.addInput("layer", "string").setValueString(texture.layer)
    if texture.filter:
        image.addInput("filtertype", "string").setValueString(texture.filter)
    if texture.fallback is not None:
        fallback = texture.fallback
        if isinstance(fallback, (tuple, list)):  # a UsdUVTexture's is a float4 whatever it feeds: the image's width
            width = COMPONENTS.get(image_type, 1)
            padded = [float(v) for v in fallback] + [1.0] * 4
            fallback = padded[0] if width == 1 else tuple(padded[:width])
        image.addInput("default", image_type).setValueString(format_value(fallback, image_type))
    for name, mode in zip(("uaddressmode", "vaddressmode"), texture.wrap or ()):
        mode = WRAP_TO_ADDRESS_MODE.get(mode, mode)  # a UsdUVTexture's wrap token in MaterialX's words
        if mode in MATERIALX_ADDRESS_MODES:  # (useMetadata: the image node's default, periodic, as the evaluator reads it)
            image.addInput(name, "string").setValueString(mode)
    if image.getCategory() == "tiledimage":
        tiling = tuple(1.0 / v if v else 0.0 for v in texture.uv.scale)  # place2d's scale divides (inf: a tiling of 0)
        image.addInput("uvtiling", "vector2").setValueString(format_value(tiling, "vector2"))
        image.addInput("uvoffset", "vector2").setValueString(format_value(texture.uv.offset, "vector2"))
    elif texture.uv is not None or texture.texcoord:
        _write_placement(document, image, prefix, texture, used)
    upstream = image.getName()
    if texture.channels is not None and len(texture.channels) == 1:
        extract = document.addNode("extract", _unique(f"{prefix}_extract", used), "float")
        extract.addInput("in", image_type).setNodeName(upstream)
        extract.addInput("index", "integer").setValueString(str(texture.channels[0]))
        upstream = extract.getName()
    elif texture.channels is not None and len(texture.channels) == 3 and image_type[-1:] == "4":
        convert = document.addNode("convert", _unique(f"{prefix}_convert", used), image_type[:-1] + "3")
        convert.addInput("in", image_type).setNodeName(upstream)  # a four-channel image read as three: alpha dropped
        upstream = convert.getName()
    scale, bias, strength = texture.scale, texture.bias, None
    if texture.normal_map is not None and tangent_vector:
        scale, bias = normal_decode(texture)  # the whole decode, as UsdPreviewSurface's normal takes it
    elif texture.normal_map is not None:
        # before a normalmap node, which decodes 2 t - 1 itself: a UsdUVTexture's whole decode remapped
        scale, bias, strength = normal_encoding(texture)
    delivered = document.getNode(upstream).getType()
    width = COMPONENTS.get(delivered, 1)
    for category, value, identity in (("multiply", scale, 1.0), ("add", bias, 0.0)):
        if value is None or all(v == identity for v in _components(value, width)):
            continue
        operation = document.addNode(category, _unique(f"{prefix}_{category}", used), delivered)
        operation.addInput("in1", delivered).setNodeName(upstream)
        components = _components(value, width)
        operation.addInput("in2", delivered).setValueString(format_value(components[0] if width == 1 else tuple(components),
                                                                         delivered))
        upstream = operation.getName()
    if texture.normal_map is not None and not tangent_vector:
        decode = document.addNode("normalmap", _unique(f"{prefix}_normalmap", used), "vector3")
        decode.addInput("in", "vector3").setNodeName(upstream)
        if strength != 1.0:
            decode.addInput("scale", "float").setValueString(format_value(strength, "float"))
        upstream = decode.getName()
    return upstream


def _write_placement(document, image, prefix: str, texture: Texture, used) -> None:
    """A ``texcoord`` node (the UV set; a ``geompropvalue`` for a set named by its primvar) and, for a
    transform, a ``place2d`` on it. The ``texcoord`` node is written even for set 0 under a ``place2d``: ND_place2d_vector2's own texcoord defaults to
    the constant (0, 0), not to the mesh's UVs (rule OPBR706)."""
    coordinates = None
    named = isinstance(texture.texcoord, str) and not texture.texcoord.isdigit()
    if named:  # a UV set by its primvar name (USD's "st1", Blender's "UVMap"): MaterialX reads it as a geomprop
        coordinates = document.addNode("geompropvalue", _unique(f"{prefix}_uvset", used), "vector2")
        coordinates.addInput("geomprop", "string").setValueString(texture.texcoord)
    elif texture.texcoord or texture.uv is not None:
        coordinates = document.addNode("texcoord", _unique(f"{prefix}_texcoord", used), "vector2")
        if texture.texcoord:
            coordinates.addInput("index", "integer").setValueString(str(int(texture.texcoord)))
    target = coordinates
    if texture.uv is not None:
        place = document.addNode("place2d", _unique(f"{prefix}_place2d", used), "vector2")
        if coordinates is not None:
            place.addInput("texcoord", "vector2").setNodeName(coordinates.getName())
        uv = texture.uv
        for name, value, identity in (("scale", uv.scale, (1.0, 1.0)), ("offset", uv.offset, (0.0, 0.0)),
                                      ("pivot", uv.pivot, (0.0, 0.0))):
            if tuple(value) != identity:
                place.addInput(name, "vector2").setValueString(format_value(value, "vector2"))
        if uv.rotate:
            place.addInput("rotate", "float").setValueString(format_value(uv.rotate, "float"))
        target = place
    image.addInput("texcoord", "vector2").setNodeName(target.getName())


def _connect(port, written: tuple[str, str | None] | None) -> bool:
    """Connect ``port`` to what :func:`_write_connection` wrote: a node, or a node graph's output."""
    if written is None:
        return False
    name, graph_output = written
    if graph_output is None:
        port.setNodeName(name)
    else:
        port.setNodeGraphString(name)
        port.setOutputString(graph_output)
    return True


def _write_kept(document, port, value, used, written: dict) -> bool:
    """Connect ``port`` to the source's node graph ``value`` was read from, written whole once per document
    (:func:`openpbr_tools.model.kept`), where no mapping changed the value and the graph's output has the port's
    type; ``False`` (nothing written) otherwise."""
    found = kept(value)
    if found is None:
        return False
    text, output_name = found
    key = f"graph\n{text}"
    if key not in written:
        source = mx.createDocument()
        mx.readFromXmlString(source, text)
        graph = source.getNodeGraphs()[0]
        output = graph.getOutput(output_name)
        if output is None or output.getType() != port.getType():
            return False
        name = _unique(graph.getName(), used)
        copy = document.addNodeGraph(name)
        copy.copyContentFrom(graph)
        if copy.getColorSpace() == document.getColorSpace():  # (the space it would inherit: said once)
            copy.removeAttribute("colorspace")
        written[key] = (name, None)
    name = written[key][0]
    graph = document.getNodeGraph(name)
    if graph.getOutput(output_name) is None or graph.getOutput(output_name).getType() != port.getType():
        return False
    return _connect(port, (name, output_name))


def _write_connection(document, shader_name: str, input_name: str, connection: Connection, used,
                      written: dict) -> tuple[str, str | None] | None:
    """Re-create the procedural graph the reader captured: (the node feeding the input, None), or (a node
    graph, its output) for the source's graph kept whole (Connection.kept_graph, while the mapping left the
    capture as it was); ``None`` when there is nothing to write. A graph already written for another input
    (a marble's output read by base_color and subsurface_color) is connected again, not copied."""
    if not connection.graph_xml:
        return None
    key = graph_key(connection.graph_xml, connection.output)
    if key in written:
        return written[key]
    source = mx.createDocument()
    mx.readFromXmlString(source, connection.graph_xml)
    for definition in list(source.getNodeDefs()) + list(source.getNodeGraphs()):  # custom nodes' (capture.py)
        if document.getChild(definition.getName()) is None:
            document.addChildOfCategory(definition.getCategory(), definition.getName()).copyContentFrom(definition)
    renamed = {}
    for node in source.getNodes():
        renamed[node.getName()] = _unique(f"{shader_name}_{input_name}_{node.getName()}", used)
    for node in source.getNodes():
        copy = document.addNode(node.getCategory(), renamed[node.getName()], node.getType())
        copy.copyContentFrom(node)
        copy.setName(renamed[node.getName()])
        for port in copy.getInputs():
            if port.getNodeName() in renamed:
                port.setNodeName(renamed[port.getNodeName()])
    if renamed.get(connection.output or "") is None:
        return None
    written[key] = (renamed[connection.output], None)
    return written[key]
