"""The procedural networks of the USD writer: a kept MaterialX graph (``Connection.graph_xml``, as the
MaterialX reader or :mod:`.graph_capture` captured it) written as the UsdShade network UsdMtlx would make
of it, so that a USD output keeps a noise, a ramp or a pattern the toolkit cannot evaluate instead of dropping
it with a note.

Each node becomes a ``Shader`` prim beside the material's shader, with its MaterialX node definition as
``info:id`` (``ND_noise2d_float``); values take the USD types UsdMtlx gives their MaterialX types, colour
spaces go to ``colorSpace`` metadata, files are referenced (or packaged) as textures are, connections become
UsdShade connections to the upstream prim's ``outputs:out`` (a multi-output node's named output). Only a
graph of MaterialX's standard nodes is written (a custom nodedef has no definition a USD renderer finds);
anything else keeps the old behaviour: the connection is left pointing at the source's prim, with a note.
Only a MaterialX shader reads such a network; a UsdPreviewSurface fallback cannot.
"""

from __future__ import annotations

import MaterialX as mx

from ...model import Texture
from ...values import parse_value
from ..mtlx.library import standard_library
from .sdr import materialx_nodedef
from .types import MATERIALX_TO_USD


class GraphNetworkWriter:
    """Kept graphs for a writer with ``stage``, ``Sdf``, ``UsdShade``, ``unique_child``, ``texture_path``,
    ``colorspace_name`` and ``set_value``."""

    def materialx_graph(self, usd_material, entry, connection):
        """The USD output that feeds ``entry`` once ``connection``'s graph is written under ``usd_material``,
        or ``None`` (nothing written) when the graph holds a node or value USD cannot carry."""
        document = mx.createDocument()
        try:
            mx.readFromXmlString(document, connection.graph_xml)
        except mx.Exception:
            return None
        document.setDataLibrary(standard_library())
        nodes = {node.getName(): node for node in document.getNodes()}
        definitions = {}
        for name, node in nodes.items():
            nodedef = node.getNodeDef()
            if nodedef is None or materialx_nodedef(nodedef.getName()) is None:
                return None  # a custom definition: no USD renderer has it
            outputs = [(o.getName(), o.getType()) for o in nodedef.getActiveOutputs()]
            if any(t not in OUTPUT_TYPES for _, t in outputs):
                return None
            definitions[name] = (nodedef, outputs)
        if connection.output not in nodes:
            return None
        values = {}  # checked before any prim is made: a graph is written whole or not at all
        for name, node in nodes.items():
            for port in node.getInputs():
                if port.getNodeName():
                    if port.getNodeName() not in nodes:
                        return None
                    continue
                if port.getType() not in MATERIALX_TO_USD or not port.hasAttribute("value"):
                    if port.hasAttribute("value"):
                        return None
                    continue
                if port.getType() != "filename":
                    try:
                        values[(name, port.getName())] = _value(port.getValueString(), port.getType())
                    except ValueError:
                        return None
        prims = {}
        parent = str(usd_material.GetPath())
        for name, node in nodes.items():
            nodedef, outputs = definitions[name]
            shader = self.UsdShade.Shader.Define(self.stage, self.unique_child(parent, f"{entry.name}_{name}"))
            shader.CreateIdAttr(nodedef.getName())
            for output_name, output_type in outputs:
                shader.CreateOutput(output_name, self.Sdf.ValueTypeNames.Find(OUTPUT_TYPES[output_type]))
            prims[name] = shader
        for name, node in nodes.items():
            shader = prims[name]
            for port in node.getInputs():
                usd_type = MATERIALX_TO_USD.get(port.getType())
                if usd_type is None:
                    continue
                if not port.getNodeName() and not port.hasAttribute("value"):
                    continue  # declared without a value (MaterialX calls that invalid): the definition's default
                target = shader.CreateInput(port.getName(), self.Sdf.ValueTypeNames.Find(usd_type))
                if port.getNodeName():
                    upstream = nodes[port.getNodeName()]
                    output = port.getOutputString() or definitions[upstream.getName()][1][0][0]
                    target.ConnectToSource(prims[upstream.getName()].GetOutput(output))
                    continue
                if port.getType() == "filename":
                    file = port.getValueString()
                    target.Set(self.Sdf.AssetPath(self.texture_path(Texture(file=file), f"{entry.location.path}."
                                                                     f"{entry.name}")))
                elif port.getType() in ("matrix33", "matrix44"):  # (set_value takes flat tuples)
                    from pxr import Gf  # lazy: pxr only once write_usd has required it

                    matrix = Gf.Matrix3d if port.getType() == "matrix33" else Gf.Matrix4d
                    target.Set(matrix(*[v for row in values[(name, port.getName())] for v in row]))
                else:
                    self.set_value(target.GetAttr(), usd_type, values[(name, port.getName())])
                space = self.colorspace_name(port.getColorSpace(), "materialx") if port.getColorSpace() else None
                if space:
                    target.GetAttr().SetColorSpace(space)
        final = connection.output
        return prims[final].GetOutput(definitions[final][1][0][0])


#: the USD types of node outputs: MaterialX's value types, and a displacement shader's result (a token, as UsdMtlx gives
#: it: a material's outputs:mtlx:displacement connects to it)
OUTPUT_TYPES = {**MATERIALX_TO_USD, "displacementshader": "token"}


def _value(text: str, type_name: str):
    """``text`` as the Python value usd-core sets on a ``type_name`` input (a matrix by rows); ``ValueError``
    when it does not read as one."""
    if type_name in ("matrix33", "matrix44"):
        size = 3 if type_name == "matrix33" else 4
        numbers = [float(x) for x in text.split(",")]
        if len(numbers) != size * size:
            raise ValueError(f"{text!r} is no {type_name}")
        return tuple(tuple(numbers[row * size:(row + 1) * size]) for row in range(size))
    return parse_value(text, type_name)
