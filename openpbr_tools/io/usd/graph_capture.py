"""A USD shading network of MaterialX nodes kept whole: the shader prims upstream of an input that are
no texture lookup (a ``ND_noise2d_float``, a ``ND_ramplr_color3`` fed by ``ND_texcoord_vector2``...) captured as
one flat MaterialX document, the form :mod:`openpbr_tools.io.mtlx.capture` gives a MaterialX source's graphs
(``Connection.graph_xml``), so that a .mtlx output rewires the graph instead of dropping it (the red team's F4:
it was dropped even for a .mtlx output, with a note).

Each prim becomes the node its ``info:id`` names (``ND_multiply_color3FA`` -> a ``multiply`` of type color3
with that ``nodedef``); an input connected to another prim's output (through node-graph and material
interfaces, as the reader follows them) becomes a ``nodename`` connection (with ``output`` for a
multi-output node), an unconnected authored value its MaterialX value string, a file its path relative to
the asset's folder (as the reader gives a texture's) with the colour space authored on it. A network that
holds anything else (a ``UsdUVTexture``, a shader without a MaterialX definition, a packaged image, a
dangling connection, a value that does not read as its type) is not captured: the caller keeps its
:class:`~openpbr_tools.model.Connection` without a graph, reported as not carried.
"""

from __future__ import annotations

import MaterialX as mx

from ... import colorspaces
from ...values import format_value, parse_value
from ..mtlx.library import standard_library
from .attributes import python_value, single_precision
from .sdr import materialx_nodedef

LIMIT = 256  # nodes: a larger network is not captured (as capture_graph's limit)


class _Uncapturable(Exception):
    pass


def capture_network(reader, prim, output_name: str, consumer_type: str | None = None,
                    where=None) -> tuple[str, str] | None:
    """(the flat MaterialX document, the name of the node that feeds the input) for the network upstream of
    ``prim``'s output ``output_name``, or ``None`` when it cannot be captured whole. ``reader`` is the USD
    network reader (``UsdShade``, ``source``, ``file_of``, ``attribute_colorspace``, ``inherited_colorspace``).
    ``consumer_type``: the MaterialX type of the input it feeds; an output of another type UsdShade connects
    (a ``float3`` noise to a ``color3f`` colour) ends in MaterialX's ``convert`` node, which MaterialX requires.
    An animated value is captured at its first time sample, observed (``usd_graph_time_samples``) at ``where``, the
    input the graph feeds, so a conversion can say the animation is not carried."""
    document = mx.createDocument()
    names: dict[str, str] = {}
    pending = []

    def enqueue(node_prim) -> str:
        path = str(node_prim.GetPath())
        if path not in names:
            name = mx.createValidName(node_prim.GetName())
            while document.getChild(name) is not None or name in names.values():
                name = document.createValidChildName(name + "_")
            names[path] = name
            pending.append(node_prim)
            if len(names) > LIMIT:
                raise _Uncapturable("too many nodes")
        return names[path]

    try:
        first = enqueue(prim)
        animated: list[str] = []
        while pending:
            _capture_node(reader, document, pending.pop(), names, enqueue, animated)
        final = document.getNode(first)
        if final.getType() == "multioutput":  # a dot reads the output the input read (see capture.select_output)
            output = materialx_nodedef(final.getNodeDefString()).getOutput(output_name)
            if output is None:
                raise _Uncapturable(f"no output {output_name}")
            dot = document.addNode("dot", document.createValidChildName(f"{first}_{output_name}"), output.getType())
            port = dot.addInput("in", output.getType())
            port.setNodeName(first)
            port.setOutputString(output_name)
            first = dot.getName()
        final = document.getNode(first)
        if consumer_type and final.getType() != consumer_type:
            convert = materialx_nodedef(f"ND_convert_{final.getType()}_{consumer_type}")
            if convert is None:
                raise _Uncapturable(f"no conversion from {final.getType()} to {consumer_type}")
            node = document.addNode("convert", document.createValidChildName(f"{first}_{consumer_type}"), consumer_type)
            node.setNodeDefString(convert.getName())
            node.addInput("in", final.getType()).setNodeName(first)
            first = node.getName()
        if _cyclic(document):  # (UsdShade lets a network loop; MaterialX's graphs are acyclic)
            if where is not None:  # (the red team's B5: reported as MaterialX reports a .mtlx's, an error)
                reader.asset.observe("dangling_reference", where, attribute=where.input, target=str(prim.GetPath()),
                                     ends="leads into a cycle: a node upstream feeds itself, which no renderer evaluates "
                                          "(MaterialX: \"Cycle in upstream path\")")
            raise _Uncapturable("a cycle")
    except (_Uncapturable, LookupError, ValueError, TypeError, mx.Exception):
        return None
    document.setDataLibrary(standard_library())  # (validated with the definitions, as a renderer reads it)
    valid, _ = document.validate()
    if not valid:
        return None
    from ..mtlx.writer import document_text  # lazy: io.mtlx.writer is not needed by a reader otherwise

    document.setDataLibrary(None)
    if animated and where is not None:
        reader.asset.observe("usd_graph_time_samples", where, attributes=sorted(animated))
    return document_text(document), first


def _capture_node(reader, document, prim, names, enqueue, animated: list) -> None:
    shader_id = str(reader.UsdShade.Shader(prim).GetShaderId() or "") if prim.IsA(reader.UsdShade.Shader) else ""
    nodedef = materialx_nodedef(shader_id) if shader_id else None
    if nodedef is None or nodedef.getNodeString() in ("open_pbr_surface", "standard_surface", "gltf_pbr",
                                                      "UsdPreviewSurface", "surface", "displacement"):
        raise _Uncapturable(f"{prim.GetPath()}: {shader_id or 'no info:id'} is no MaterialX pattern node")
    node = document.addNode(nodedef.getNodeString(), names[str(prim.GetPath())], nodedef.getType())
    node.setNodeDefString(nodedef.getName())
    for attribute in prim.GetAttributes():
        full = attribute.GetName()
        if not full.startswith("inputs:"):
            continue
        name = full[len("inputs:"):]
        declared = nodedef.getActiveInput(name)
        if declared is None:
            raise _Uncapturable(f"{prim.GetPath()}: {name} is no input of {nodedef.getName()}")
        type_name = declared.getType()
        kind, *found = reader.source(attribute)
        if kind == "dangling":
            raise _Uncapturable(f"{prim.GetPath()}: {name} is dangling")
        if kind == "shader":
            upstream, output, _ = found
            port = node.addInput(name, type_name)
            port.setNodeName(enqueue(upstream))
            upstream_id = str(reader.UsdShade.Shader(upstream).GetShaderId() or "")
            upstream_def = materialx_nodedef(upstream_id)
            if upstream_def is not None and upstream_def.getType() == "multioutput":
                port.setOutputString(output)
            continue
        origin = found[0]
        if type_name == "filename":
            file, packaged = reader.file_of(attribute)
            if packaged:
                raise _Uncapturable(f"{prim.GetPath()}: a packaged image")
            if not file:
                continue
            if origin is not None and origin.GetNumTimeSamples() > 1:  # (file_of reads its first sample)
                animated.append(str(origin.GetPath()))
            port = node.addInput(name, type_name)
            port.setValueString(file)
            space = _colorspace(reader, attribute, origin, prim)
            if space:
                port.setColorSpace(space)
            continue
        value = origin.Get() if origin is not None else None
        if value is None and origin is not None and origin.GetNumTimeSamples():  # animated: its first sample, as the
            from pxr import Usd  # lazy: pxr is loaded (a stage is open)   reader takes a shader's own input's

            value = origin.Get(Usd.TimeCode.EarliestTime())
        if origin is not None and origin.GetNumTimeSamples() > 1:
            animated.append(str(origin.GetPath()))
        if value is None:
            continue  # declared without a value: the definition's default
        port = node.addInput(name, type_name)
        port.setValueString(_value_string(value, type_name, single_precision(origin.GetTypeName())))
        if type_name in ("color3", "color4"):  # MaterialX manages a colour value's space as a file's
            space = _colorspace(reader, attribute, origin, prim)
            if space:
                port.setColorSpace(space)


def _colorspace(reader, attribute, origin, prim) -> str | None:
    """The MaterialX name of the colour space a colour value or file of ``prim`` is in: ``colorSpace`` authored on
    the input, else on the interface input it reads (``origin``), else the ``Usd.ColorSpaceAPI`` space it inherits
    (the spec: a prim's colour space applies to its descendants), as the texture reader gives an image's."""
    for holder in (attribute, origin):
        if holder is not None and holder.HasColorSpace():
            name = reader.attribute_colorspace(holder, "materialx")
            break
    else:
        name = reader.inherited_colorspace(prim)
    if not name:
        return None
    return colorspaces.materialx_equivalent(name) or name


def _cyclic(document) -> bool:
    """Whether the captured nodes' connections loop."""
    edges = {node.getName(): [port.getNodeName() for port in node.getInputs() if port.getNodeName()]
             for node in document.getNodes()}
    state: dict[str, int] = {}  # 1 on the path, 2 done
    for start in edges:
        if state.get(start):
            continue
        stack = [(start, iter(edges[start]))]
        state[start] = 1
        while stack:
            name, pending = stack[-1]
            upstream = next(pending, None)
            if upstream is None:
                state[name] = 2
                stack.pop()
            elif state.get(upstream) == 1:
                return True
            elif not state.get(upstream) and upstream in edges:
                state[upstream] = 1
                stack.append((upstream, iter(edges[upstream])))
    return False


def _value_string(value, type_name: str, single: bool) -> str:
    """``value`` (as usd-core returns it; ``single``: of a single-precision type) as MaterialX writes a ``type_name``:
    the reader's plain value (:func:`.attributes.python_value`) in MaterialX's text (:func:`~openpbr_tools.values.
    format_value`); ``ValueError`` where its shape is not the type's."""
    plain = python_value(value, single)
    text = format_value(plain, type_name)
    if type_name in ("matrix33", "matrix44"):  # (parse_value does not check matrices)
        if not isinstance(plain, tuple) or len(plain) != (9 if type_name == "matrix33" else 16):
            raise ValueError(f"{value!r} is no {type_name}")
        return text
    parse_value(text, type_name)  # ValueSyntaxError (a ValueError) when the shape is not the type's
    return text
