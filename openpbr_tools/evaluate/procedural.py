"""A procedural input's value for the evaluator: the arithmetic at the end of its captured graph,
evaluated on a stand-in for everything upstream.

Nothing here evaluates MaterialX's procedural nodes (noise, patterns, images inside a graph). A graph
the reader captured (:class:`~openpbr_tools.model.Connection` ``graph_xml``) is walked from its
output through the arithmetic nodes :data:`EVALUATED` (``constant``, ``multiply``, ``add``,
``subtract``, ``clamp``, ``convert``, ``extract``, ``combine3``, ``mix``), in MaterialX's working
space, linear Rec.709 (a colour constant converted from its colour space, as MaterialX's colour
management does); any other node stands for :data:`STAND_IN` in each component. A conversion that keeps a
graph and writes its mapping after it as arithmetic (:mod:`openpbr_tools.translate.expressed`) is
then judged as the mapping of the same stand-in the source is judged at, so the verifier compares the
two at one common value of the procedural (reported as such) instead of two unrelated defaults.
"""

from __future__ import annotations

from functools import lru_cache

import numpy as np

from ..colorspaces import to_lin_rec709_as_materialx
from ..values import COMPONENTS, ValueSyntaxError, parse_value

STAND_IN = 0.5  # each component of an upstream node this module does not evaluate
EVALUATED = ("constant", "multiply", "add", "subtract", "clamp", "convert", "extract", "combine3", "mix")
_DEFAULTS = {"multiply": {"in1": 0.0, "in2": 1.0}, "add": {"in1": 0.0, "in2": 0.0},
             "subtract": {"in1": 0.0, "in2": 0.0}, "clamp": {"in": 0.0, "low": 0.0, "high": 1.0},
             "convert": {"in": 0.0}, "extract": {"in": 0.0, "index": 0.0}, "constant": {"value": 0.0},
             "mix": {"fg": 0.0, "bg": 0.0, "mix": 0.0}, "combine3": {"in1": 0.0, "in2": 0.0, "in3": 0.0}}


def value(graph_xml: str, output: str | None, type_name: str, colorspace: str | None) -> np.ndarray | None:
    """The graph's output as a value of ``type_name`` (0-d for a float, (n,) otherwise) in MaterialX's
    working space, linear Rec.709 (colour constants converted from their colour space, else
    ``colorspace``, the document's), or None when the graph cannot be read or gives another width."""
    found = _value(graph_xml, output or "", type_name, colorspace)
    return None if found is None else np.array(found)


def stand_in(connection, type_name: str, colorspace: str | None, into: str | None = None):
    """The one value an output that holds no graph writes for a float or colour input ``connection`` (a
    :class:`~openpbr_tools.model.Connection`) drives (glTF, a UsdPreviewSurface fallback: session 27's E#15, where the
    output's default stood in for a marble): :func:`value` of its captured graph (``colorspace``: the document's, for
    the graph's colour constants), a colour in linear Rec.709 or converted ``into`` another space, as a float or a
    tuple; ``None`` for a dangling connection, one with no graph, or a graph that gives no finite value."""
    if type_name not in ("float", "color3") or connection.dangling or not connection.graph_xml:
        return None
    found = value(connection.graph_xml, connection.output, type_name, colorspace)
    if found is None or not np.all(np.isfinite(found)):
        return None
    if type_name == "float":
        return float(found)
    if into not in (None, "lin_rec709"):
        from ..colorspaces import from_lin_rec709  # lazy: colour-science, only for a colour in another space

        found = from_lin_rec709(found, into)
    return tuple(float(v) for v in found)


def said(name: str, category: str | None, written) -> str:
    """The note of :func:`stand_in`'s value written for input ``name``."""
    shown = ", ".join(f"{v:.4g}" for v in written) if isinstance(written, tuple) else f"{written:.4g}"
    return (f"{name}: its procedural graph ({category or 'nodes'}), which this output cannot hold, is written as one "
            f"value, {shown}: the graph's arithmetic with its procedural nodes (noise, patterns, images) at "
            f"{STAND_IN}, their midpoint")


@lru_cache(maxsize=256)
def _value(graph_xml: str, output: str, type_name: str, colorspace: str | None):
    # lazy: MaterialX (~10 ms) is loaded only for a material with a procedural input
    import MaterialX as mx

    document = mx.createDocument()
    try:
        mx.readFromXmlString(document, graph_xml)
    except mx.Exception:
        return None
    node = document.getNode(output)
    if node is None:
        return None
    result = _node(document, node, 0, colorspace)
    width = COMPONENTS.get(type_name)
    if result is None or width is None or result.size not in (1, width):
        return None
    result = np.broadcast_to(result.reshape(-1) if result.size > 1 else result.reshape(()), () if width == 1 else
                             (width,)).copy()
    return result if np.all(np.isfinite(result)) else None


def _stand_in(type_name: str) -> np.ndarray:
    width = COMPONENTS.get(type_name, 1)
    return np.asarray(STAND_IN) if width == 1 else np.full(width, STAND_IN)


def _node(document, node, depth: int, colorspace: str | None) -> np.ndarray | None:
    category, type_name = node.getCategory(), node.getType()
    if category not in EVALUATED or depth > 64 or type_name not in COMPONENTS:
        return _stand_in(type_name)
    operands = {}
    for name, default in _DEFAULTS[category].items():
        port = node.getInput(name)
        if port is None:
            operands[name] = np.asarray(default)
            continue
        upstream = port.getConnectedNode()
        if upstream is not None:
            operands[name] = _node(document, upstream, depth + 1, colorspace)
        elif port.hasAttribute("value"):
            try:
                parsed = np.asarray(parse_value(port.getValueString(), port.getType()), dtype=np.float64)
            except ValueSyntaxError:
                return _stand_in(type_name)
            if port.getType() in ("color3", "color4"):  # a colour: converted into the working space
                rgb = to_lin_rec709_as_materialx(parsed[:3], port.getColorSpace() or colorspace)
                parsed = np.concatenate([rgb, parsed[3:]])
            operands[name] = parsed
        else:
            operands[name] = _stand_in(port.getType())
        if operands[name] is None:
            return None
    return _apply(category, type_name, operands)


def _apply(category: str, type_name: str, o: dict) -> np.ndarray | None:
    width = COMPONENTS[type_name]
    with np.errstate(all="ignore"):
        if category == "constant":
            return o["value"]
        if category == "multiply":
            return o["in1"] * o["in2"]
        if category == "add":
            return o["in1"] + o["in2"]
        if category == "subtract":
            return o["in1"] - o["in2"]
        if category == "clamp":
            return np.minimum(np.maximum(o["in"], o["low"]), o["high"])
        if category == "mix":
            return o["fg"] * o["mix"] + o["bg"] * (1.0 - o["mix"])
        if category == "convert":
            source = np.asarray(o["in"]).reshape(-1)
            return np.broadcast_to(source[:width] if source.size >= width else source[:1], (width,)).copy() \
                if width > 1 else np.asarray(source[0])
        if category == "extract":
            source, index = np.asarray(o["in"]).reshape(-1), int(o["index"])
            return np.asarray(source[index]) if 0 <= index < source.size else None
        if category == "combine3":
            return np.array([float(np.asarray(o[k]).reshape(-1)[0]) for k in ("in1", "in2", "in3")])
    return None
