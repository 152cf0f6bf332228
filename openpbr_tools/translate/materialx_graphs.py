"""MaterialX's own translation graphs (``libraries/bxdf/translation/*.mtlx`` in the ``materialx``
wheel: OpenPBR -> Standard Surface, Standard Surface -> OpenPBR, glTF PBR and UsdPreviewSurface),
evaluated
on constant inputs: the anchor's answer as a candidate beside the toolkit's own mapping (#13: never
worse than the anchor).

The graphs are read with MaterialX and interpreted node by node, each node as its definition in
MaterialX's standard library says (an input a node leaves unset takes its node definition's default,
an interface input the caller does not give takes the translation nodedef's default):
arithmetic (``add``, ``subtract``, ``multiply``, ``divide``, ``power``, ``sqrt``, ``mix`` = bg (1 - mix)
+ fg mix, ``dotproduct``), channels (``convert``, ``extract``, ``separate2``), conditionals
(``ifgreater``, ``ifgreatereq``, ``ifequal``: in1 when the comparison holds, else in2), ``dot``,
``constant``, ``luminance`` (the dot product with ``lumacoeffs``) and ``roughness_anisotropy``
(MaterialX's ``mx_roughness_anisotropy``: alpha = clamp(r^2, eps, 1); with anisotropy a > 0, aspect =
sqrt(1 - clamp(a, 0, 0.98)), (min(alpha / aspect, 1), alpha aspect)). A node of any other category
raises :class:`GraphError` (the caller then has no anchor candidate). The values it produces are
checked against MaterialX's ShaderTranslator + TextureBaker (GLSL) in the tests.
"""

from __future__ import annotations

import math
import os
from functools import lru_cache

import numpy as np

FLOAT_EPS = 1e-8  # MaterialX's M_FLOAT_EPS
CHAINS = {  # target model -> the graphs from OpenPBR, in order
    "standard_surface": ("open_pbr_to_standard_surface",),
    "gltf_pbr": ("open_pbr_to_standard_surface", "standard_surface_to_gltf_pbr"),
    "UsdPreviewSurface": ("open_pbr_to_standard_surface", "standard_surface_to_usd"),
}
FROM_STANDARD_SURFACE = {  # target model -> the graph from Standard Surface
    "open_pbr_surface": ("standard_surface_to_open_pbr",),
    "gltf_pbr": ("standard_surface_to_gltf_pbr",),
    "UsdPreviewSurface": ("standard_surface_to_usd",),
}


class GraphError(ValueError):
    """A translation graph this interpreter cannot evaluate (a node category it does not know)."""


@lru_cache(maxsize=8)
def _graph(name: str):
    import MaterialX as mx  # lazy: only a conversion that weighs candidates needs it

    from ..io.mtlx.reader import standard_library  # lazy: as MaterialX above

    folder = os.path.join(os.path.dirname(mx.__file__), "libraries", "bxdf", "translation")
    document = mx.createDocument()
    mx.readFromXmlFile(document, os.path.join(folder, f"{name}.mtlx"))
    (graph,) = document.getNodeGraphs()  # the file's own (before the library's join the document)
    document.setDataLibrary(standard_library())
    return document, graph, graph.getNodeDef()  # the document too: its elements die with it


def _python(value):
    if isinstance(value, (bool, int, float)):
        return value
    try:
        return tuple(float(v) for v in value)
    except TypeError:
        return value


@lru_cache(maxsize=8)
def _compiled(name: str):
    """Graph ``name`` read once into plain Python: per node, its category, type and a source for every
    input it sets or its node definition declares (``("interface", name, default)``, ``("node", node,
    output)``, ``("value", value)``), and the graph's outputs; so that evaluating it per material
    makes no MaterialX call (~5x faster than walking the elements, which the candidate search did per
    material)."""
    _, graph, nodedef = _graph(name)
    nodes = {}
    for node in graph.getNodes():
        sources = {}
        definition = node.getNodeDef()
        for default in (definition.getActiveInputs() if definition is not None else ()):
            if default.hasValueString():
                sources[default.getName()] = ("value", _python(default.getValue()))
        for port in node.getInputs():
            if port.getInterfaceName():
                interface = port.getInterfaceName()
                declared = nodedef.getActiveInput(interface)
                sources[port.getName()] = ("interface", interface,
                                           _python(declared.getValue()) if declared is not None else None)
            elif port.getNodeName():
                sources[port.getName()] = ("node", port.getNodeName(), port.getOutputString())
            elif port.hasValueString():
                sources[port.getName()] = ("value", _python(port.getValue()))
        nodes[node.getName()] = _Node(node.getName(), node.getCategory(), node.getType(), sources)
    outputs = [(output.getName(), output.getNodeName(), output.getOutputString()) for output in graph.getOutputs()]
    return nodes, outputs


class _Node:
    __slots__ = ("name", "category", "type", "sources")

    def __init__(self, name, category, kind, sources):
        self.name, self.category, self.type, self.sources = name, category, kind, sources


class _Evaluation:
    def __init__(self, nodes: dict, values: dict):
        self.nodes, self.values, self.memo = nodes, values, {}

    def port(self, node: _Node, name: str):
        """The value of input ``name`` of ``node``: what it is connected to or set to, else its node
        definition's default (an interface input the caller does not give: the translation nodedef's)."""
        source = node.sources.get(name)
        if source is None:
            raise GraphError(f"{node.name}.{name} has no value and no default")
        if source[0] == "interface":
            return self.values[source[1]] if source[1] in self.values else source[2]
        if source[0] == "node":
            return self.node(self.nodes[source[1]], source[2])
        return source[1]

    def node(self, node: _Node, output: str = ""):
        key = (node.name, output)
        if key not in self.memo:
            self.memo[key] = self.compute(node, output)
        return self.memo[key]

    def compute(self, node: _Node, output: str):
        category = node.category

        def get(name):
            return self.port(node, name)

        def arr(name):  # 32-bit, as the GLSL MaterialX renders the graphs with
            return np.asarray(get(name), dtype=np.float32)

        kind = node.type
        if category == "dot":
            return get("in")
        if category == "constant":
            return get("value")
        if category in ("add", "subtract", "multiply", "divide", "power"):
            a, b = arr("in1"), arr("in2")
            with np.errstate(all="ignore"):
                result = {"add": a + b, "subtract": a - b, "multiply": a * b, "divide": a / b,
                          "power": np.power(a, b)}[category]
            return self.typed(result, kind)
        if category == "sqrt":
            with np.errstate(all="ignore"):
                return self.typed(np.sqrt(arr("in")), kind)
        if category == "mix":
            m = arr("mix")
            return self.typed(arr("bg") * (1.0 - m) + arr("fg") * m, kind)
        if category == "dotproduct":
            return float(np.float32(np.dot(arr("in1"), arr("in2"))))
        if category in ("ifgreater", "ifgreatereq", "ifequal"):
            v1, v2 = get("value1"), get("value2")
            holds = {"ifgreater": lambda: v1 > v2, "ifgreatereq": lambda: v1 >= v2, "ifequal": lambda: v1 == v2}[category]()
            return get("in1") if holds else get("in2")
        if category == "convert":
            return self.typed(np.asarray(float(get("in")) if isinstance(get("in"), bool) else get("in"), dtype=np.float32),
                              kind)
        if category == "extract":
            return float(arr("in")[int(get("index"))])
        if category == "separate2":
            vector = arr("in")
            return float(vector[0] if output == "outx" else vector[1])
        if category == "luminance":
            return self.typed(np.full(3, np.float32(np.dot(arr("in"), arr("lumacoeffs")))), kind)
        if category == "roughness_anisotropy":
            r, a = float(get("roughness")), float(get("anisotropy"))
            alpha = min(max(r * r, FLOAT_EPS), 1.0)
            if a > 0.0:
                aspect = math.sqrt(1.0 - min(max(a, 0.0), 0.98))
                return (min(alpha / aspect, 1.0), alpha * aspect)
            return (alpha, alpha)
        raise GraphError(f"translation graph node {node.name!r}: category {category!r} is not interpreted")

    @staticmethod
    def typed(array, kind: str):
        if kind == "boolean":
            return bool(np.reshape(array, -1)[0] != 0)
        if kind in ("float", "integer"):
            return float(np.reshape(array, -1)[0])
        width = {"color3": 3, "vector3": 3, "color4": 4, "vector4": 4, "vector2": 2}[kind]
        return tuple(float(v) for v in np.broadcast_to(array, (width,)))


def evaluate(name: str, values: dict) -> dict:
    """The outputs of translation graph ``name`` for interface ``values`` (others: defaults), by
    output name without its ``_out`` suffix (the target's parameter names)."""
    nodes, graph_outputs = _compiled(name)
    evaluation = _Evaluation(nodes, values)
    outputs = {}
    for output, source, output_string in graph_outputs:
        if not source:
            continue
        value = evaluation.node(nodes[source], output_string)
        if value is not None:
            outputs[output.removesuffix("_out")] = value
    return outputs


def chain(target: str, values: dict, source: str = "open_pbr_surface") -> dict:
    """``values`` of a ``source`` material through MaterialX's graphs to ``target`` (from OpenPBR:
    :data:`CHAINS`; from Standard Surface: :data:`FROM_STANDARD_SURFACE`): the target's parameter values."""
    for name in graphs(source, target):
        values = evaluate(name, values)
    return values


def graphs(source: str, target: str) -> tuple[str, ...]:
    """The translation graphs from ``source`` to ``target``, in order; () when MaterialX has none."""
    if source == "open_pbr_surface":
        return CHAINS.get(target, ())
    return FROM_STANDARD_SURFACE.get(target, ()) if source == "standard_surface" else ()
