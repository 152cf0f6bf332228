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

A file's materials are evaluated together (:func:`chain_many`): every node once, on arrays with a row per
material, a graph's outputs handed to the next as such arrays; both branches of a conditional are
computed and each row takes its own. The numbers are each material's alone through the same code, bit for
bit (a test); against session 11's one-material interpreter they differ by at most one float32 ulp (the
dot products now sum in order). On the generated archetypes this took the candidate search's graph step
from 0.14 s to 0.04 s per 300 materials.
"""

from __future__ import annotations

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

    from ..io.mtlx.library import standard_library  # lazy: as MaterialX above

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


#: the width of each vector type a graph node may have
WIDTHS = {"color3": 3, "vector3": 3, "color4": 4, "vector4": 4, "vector2": 2}


class _Value:
    """A value for every material of a batch: ``array`` of shape (materials, width), float64 holding what
    the graph computes in 32 bits; ``kind`` "boolean", "integer", "float", "vector" or "none" (an input
    nobody sets and nothing defaults: not an output, NaN in arithmetic, as NumPy reads None)."""
    __slots__ = ("array", "kind")

    def __init__(self, array, kind: str):
        self.array, self.kind = array, kind


def _kind_of(value) -> str:
    if isinstance(value, (bool, np.bool_)):
        return "boolean"
    if isinstance(value, (int, np.integer)):
        return "integer"
    return "float" if np.ndim(value) == 0 else "vector"


def _column(values: list) -> _Value:
    """Per-material Python values (floats, booleans, tuples) as one :class:`_Value`."""
    if all(value is None for value in values):  # (an unset input without a default: a geometric one)
        return _Value(np.full((len(values), 1), np.nan), "none")
    types = {type(value) for value in values}
    kinds = {_kind_of(value) for value in (values if len(types) > 1 else values[:1])}
    if len(kinds) != 1 or any(value is None for value in values):
        raise GraphError("an interface value differs in type between the materials or is missing in some")
    kind = kinds.pop()
    array = np.asarray(values, dtype=float)
    return _Value(array.reshape(len(values), -1) if kind == "vector" else array.reshape(-1, 1), kind)


class _Interface:
    """The interface values of a batch of materials, column by column (:func:`_column`), from each
    material's dict or from the previous graph's outputs (:func:`chain_many`)."""

    def __init__(self, value_sets: list[dict] | None = None, columns: dict | None = None, count: int = 0):
        self.value_sets, self.columns = value_sets, dict(columns or {})
        self.count = len(value_sets) if value_sets is not None else count

    def get(self, name: str, default) -> _Value:
        if name not in self.columns:
            if self.value_sets is not None:
                self.columns[name] = _column([values.get(name, default) for values in self.value_sets])
            else:
                self.columns[name] = _column([default] * self.count)
        return self.columns[name]


class _Evaluation:
    """One graph evaluated for a batch of materials (``values``: each material's interface values): every
    node once, on arrays with a row per material, the same arithmetic (32-bit, as the GLSL MaterialX
    renders the graphs with) as for each material alone."""

    def __init__(self, nodes: dict, interface: _Interface):
        self.nodes, self.interface, self.memo, self.count = nodes, interface, {}, interface.count

    def port(self, node: _Node, name: str) -> _Value:
        """The value of input ``name`` of ``node``: what it is connected to or set to, else its node
        definition's default (an interface input the caller does not give: the translation nodedef's)."""
        source = node.sources.get(name)
        if source is None:
            raise GraphError(f"{node.name}.{name} has no value and no default")
        if source[0] == "interface":
            return self.interface.get(source[1], source[2])
        if source[0] == "node":
            return self.node(self.nodes[source[1]], source[2])
        return _column([source[1]] * self.count)

    def node(self, node: _Node, output: str = "") -> _Value:
        key = (node.name, output)
        if key not in self.memo:
            self.memo[key] = self.compute(node, output)
        return self.memo[key]

    def compute(self, node: _Node, output: str) -> _Value:
        category = node.category

        def get(name) -> _Value:
            return self.port(node, name)

        def arr(name):  # 32-bit, as the GLSL MaterialX renders the graphs with
            return get(name).array.astype(np.float32)

        def scalar(array) -> _Value:
            return _Value(np.asarray(array, dtype=float).reshape(self.count, 1), "float")

        kind = node.type
        if category == "dot":
            return get("in")
        if category == "constant":
            return get("value")
        if category in ("add", "subtract", "multiply", "divide", "power"):
            a, b = arr("in1"), arr("in2")
            with np.errstate(all="ignore"):
                result = {"add": np.add, "subtract": np.subtract, "multiply": np.multiply, "divide": np.divide,
                          "power": np.power}[category](a, b)
            return self.typed(result, kind)
        if category == "sqrt":
            with np.errstate(all="ignore"):
                return self.typed(np.sqrt(arr("in")), kind)
        if category == "mix":
            m = arr("mix")
            return self.typed(arr("bg") * (np.float32(1.0) - m) + arr("fg") * m, kind)
        if category == "dotproduct":
            return scalar(_dot32(arr("in1"), arr("in2")))
        if category in ("ifgreater", "ifgreatereq", "ifequal"):
            v1, v2 = get("value1").array, get("value2").array
            if v1.shape[1] != 1 or v2.shape[1] != 1:
                raise GraphError(f"translation graph node {node.name!r}: a comparison of vectors")
            holds = {"ifgreater": np.greater, "ifgreatereq": np.greater_equal, "ifequal": np.equal}[category](v1, v2)
            in1, in2 = get("in1"), get("in2")
            kinds = {in1.kind, in2.kind}
            if len(kinds) > 1 and kinds != {"integer", "float"}:  # (an integer given for a float: a number)
                raise GraphError(f"translation graph node {node.name!r}: branches of different types")
            return _Value(np.where(holds, in1.array, in2.array), "float" if len(kinds) > 1 else in1.kind)
        if category == "convert":
            return self.typed(get("in").array.astype(np.float32), kind)
        if category == "extract":
            index = get("index").array
            if np.any(index != index[0, 0]):
                raise GraphError(f"translation graph node {node.name!r}: an index that differs between materials")
            return scalar(arr("in")[:, int(index[0, 0])])
        if category == "separate2":
            return scalar(arr("in")[:, 0 if output == "outx" else 1])
        if category == "luminance":
            return self.typed(np.repeat(_dot32(arr("in"), arr("lumacoeffs"))[:, None], 3, axis=1), kind)
        if category == "roughness_anisotropy":  # in 64 bits (MaterialX: 32), as the interpreter always has
            r, a = get("roughness").array[:, 0], get("anisotropy").array[:, 0]
            alpha = np.minimum(np.maximum(r * r, FLOAT_EPS), 1.0)
            aspect = np.sqrt(1.0 - np.minimum(np.maximum(a, 0.0), 0.98))
            anisotropic = a > 0.0
            return _Value(np.stack([np.where(anisotropic, np.minimum(alpha / aspect, 1.0), alpha),
                                    np.where(anisotropic, alpha * aspect, alpha)], axis=1), "vector")
        raise GraphError(f"translation graph node {node.name!r}: category {category!r} is not interpreted")

    def typed(self, array, kind: str) -> _Value:
        """``array`` (a row per material) as a value of the node type ``kind``: a boolean or a number is
        each row's first component, a vector each row's components (a number spread over them)."""
        array = np.asarray(array).reshape(self.count, -1).astype(float)
        if kind == "boolean":
            return _Value((array[:, :1] != 0).astype(float), "boolean")
        if kind in ("float", "integer"):
            return _Value(array[:, :1], "float")
        return _Value(np.broadcast_to(array, (self.count, WIDTHS[kind])).copy(), "vector")


def _dot32(a, b):
    """Each row's dot product in 32 bits, summed in order."""
    products = np.broadcast_arrays(a, b)
    terms = (products[0] * products[1]).astype(np.float32)
    total = terms[:, 0]
    for column in range(1, terms.shape[1]):
        total = total + terms[:, column]
    return total.astype(float)


def _row(value: _Value, row: int):
    """One material's value as the graphs' outputs are given: a bool, a float or a tuple of floats."""
    if value.kind == "none":
        return None
    if value.kind == "boolean":
        return bool(value.array[row, 0] != 0)
    if value.kind == "integer":
        return int(value.array[row, 0])
    if value.kind == "float":
        return float(value.array[row, 0])
    return tuple(float(v) for v in value.array[row])


def _evaluate_columns(name: str, interface: _Interface) -> dict[str, _Value]:
    """Graph ``name``'s outputs (by parameter name) for the batch of ``interface``."""
    nodes, graph_outputs = _compiled(name)
    evaluation = _Evaluation(nodes, interface)
    outputs = {}
    for output, source, output_string in graph_outputs:
        if source:
            value = evaluation.node(nodes[source], output_string)
            if value.kind != "none":
                outputs[output.removesuffix("_out")] = value
    return outputs


def _rows(columns: dict[str, _Value], count: int) -> list[dict]:
    return [{name: _row(value, row) for name, value in columns.items()} for row in range(count)]


def chain(target: str, values: dict, source: str = "open_pbr_surface") -> dict:
    """``values`` of a ``source`` material through MaterialX's graphs to ``target`` (from OpenPBR:
    :data:`CHAINS`; from Standard Surface: :data:`FROM_STANDARD_SURFACE`): the target's parameter values."""
    return chain_many(target, [values], source)[0]


def chain_many(target: str, value_sets: list[dict], source: str = "open_pbr_surface") -> list[dict]:
    """:func:`chain` for each of ``value_sets``, each graph evaluated once for all of them (the same
    numbers as one by one), a graph's outputs handed to the next as columns."""
    interface = _Interface(value_sets)
    columns: dict = {}
    for name in graphs(source, target):
        columns = _evaluate_columns(name, interface)
        interface = _Interface(columns=columns, count=len(value_sets))
    return _rows(columns, len(value_sets)) if graphs(source, target) else [dict(v) for v in value_sets]


def graphs(source: str, target: str) -> tuple[str, ...]:
    """The translation graphs from ``source`` to ``target``, in order; () when MaterialX has none."""
    if source == "open_pbr_surface":
        return CHAINS.get(target, ())
    return FROM_STANDARD_SURFACE.get(target, ()) if source == "standard_surface" else ()
