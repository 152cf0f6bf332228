"""An :class:`~openpbr_tools.translate.expressed.Expression` written as MaterialX standard nodes on
top of a captured graph (``Connection.graph_xml``): the graph's output feeds ``multiply``/``add``
(an affine map: a float or colour scale, or, for a colour matrix, ``extract`` per channel and a
weighted sum of colour columns), Horner's scheme for a polynomial, and a ``clamp`` when the result leaves the
target's range. Every node is a standard library node of the types involved (``ND_multiply_color3``,
``ND_multiply_color3FA``, ``ND_add_color3``, ``ND_extract_color3``, ``ND_convert_float_color3``,
``ND_clamp_color3FA`` and their float forms), so the document validates and generates a shader
wherever the graph did. Colour constants are declared ``lin_rec709``: they are numbers of the
arithmetic MaterialX does in its working space, not colours of the document's space.
"""

from __future__ import annotations

import MaterialX as mx
import numpy as np

from ...values import format_value
from .writer import document_text

WORKING_SPACE = "lin_rec709"  # where MaterialX evaluates a graph (and the mappings' formulas run)


class ExpressionError(ValueError):
    """The graph cannot be extended (its output node is missing or of another type)."""


def append(graph_xml: str, output: str, expression) -> tuple[str, str]:
    """(the graph with ``expression``'s nodes after ``output``, the name of the last node)."""
    document = mx.createDocument()
    mx.readFromXmlString(document, graph_xml)
    node = document.getNode(output)
    if node is None or node.getType() != expression.source_type or len(node.getOutputs()) > 1:
        raise ExpressionError(f"the graph's output {output!r} is not a single {expression.source_type} node")
    builder = _Builder(document, output)
    last = builder.expression(output, expression)
    return document_text(document), last


class _Builder:
    def __init__(self, document, base: str):
        self.document, self.base = document, base
        self.used = {n.getName() for n in document.getNodes()}

    def _name(self, what: str) -> str:
        stem = f"{self.base}_{what}"
        name, count = stem, 1
        while name in self.used:
            count += 1
            name = f"{stem}{count}"
        self.used.add(name)
        return name

    def node(self, category: str, type_name: str, **inputs) -> str:
        """A node of ``category``; each input is a node name (str) or (value, type)."""
        node = self.document.addNode(category, self._name(category), type_name)
        for port, value in inputs.items():
            if isinstance(value, str):
                node.addInput(port, self.document.getNode(value).getType()).setNodeName(value)
            else:
                number, kind = value
                written = node.addInput(port, kind)
                written.setValueString(format_value(number, kind))
                if kind == "color3":  # numbers of the working space's arithmetic, not a colour to convert
                    written.setColorSpace(WORKING_SPACE)
        return node.getName()

    def expression(self, x: str, e) -> str:
        t = e.target_type
        if e.kind == "affine":
            y = self.linear(x, e.matrix, e.source_type, t)
            y = self.offset(y, e.offset, t)
        else:
            if e.source_type == "float" and t == "color3":
                x = self.node("convert", "color3", **{"in": x})
            y = self.horner(x, e.coefficients, t)
        if e.clamp is not None:
            y = self.node("clamp", t, **{"in": y, "low": (e.clamp[0], "float"), "high": (e.clamp[1], "float")})
        return y

    def linear(self, x: str, matrix: np.ndarray, s: str, t: str) -> str:
        """A x (``matrix``: target width x source width)."""
        if s == "float":
            column = matrix[:, 0]
            if t == "float":
                return x if column[0] == 1.0 else self.node("multiply", t, in1=x, in2=(float(column[0]), "float"))
            if np.all(column == 1.0):
                return self.node("convert", t, **{"in": x})
            return self.node("multiply", t, in1=(tuple(column), "color3"), in2=x)  # ND_multiply_color3FA
        if t == "color3" and np.all(matrix == np.diag(np.diag(matrix))):
            diagonal = np.diag(matrix)
            return x if np.all(diagonal == 1.0) else self.node("multiply", t, in1=x, in2=(tuple(diagonal), "color3"))
        total = None
        for j in range(3):
            column = matrix[:, j]
            if np.all(column == 0.0):
                continue
            channel = self.node("extract", "float", **{"in": x, "index": (j, "integer")})
            if t == "float":
                term = self.node("multiply", t, in1=channel, in2=(float(column[0]), "float"))
            else:
                term = self.node("multiply", t, in1=(tuple(column), "color3"), in2=channel)
            total = term if total is None else self.node("add", t, in1=total, in2=term)
        if total is None:  # A = 0: the result is the offset alone
            total = self.node("constant", t, value=(0.0 if t == "float" else (0.0, 0.0, 0.0), t))
        return total

    def offset(self, y: str, offset: np.ndarray, t: str) -> str:
        if np.all(offset == 0.0):
            return y
        return self.node("add", t, in1=y, in2=_constant(offset, t))

    def horner(self, x: str, coefficients: np.ndarray, t: str) -> str:
        """Horner's scheme, ((c0 x + c1) x + c2) x + c3 for a cubic, channel by channel."""
        y = self.node("multiply", t, in1=x, in2=_constant(coefficients[0], t))
        for row in coefficients[1:-1]:
            y = self.node("add", t, in1=y, in2=_constant(row, t))
            y = self.node("multiply", t, in1=y, in2=x)
        return self.node("add", t, in1=y, in2=_constant(coefficients[-1], t))


def _constant(components: np.ndarray, t: str) -> tuple:
    """(value, type) of a constant operand of type ``t`` from its per-channel ``components``."""
    return (float(components[0]), "float") if t == "float" else (tuple(float(v) for v in components), "color3")


def normal_to_world(graph_xml: str, output: str) -> tuple[str, str]:
    """A UsdPreviewSurface ``normal`` graph (a tangent-space vector in [-1, 1]) as the world-space normal
    OpenPBR's and Standard Surface's normal inputs take: re-encoded to [0, 1] (``x * 0.5 + 0.5``) and decoded by a
    ``normalmap`` node (ND_normalmap_float: the mesh's tangent frame), as MaterialX's own
    ND_UsdPreviewSurface_surfaceshader graph treats its normal input."""
    document = mx.createDocument()
    mx.readFromXmlString(document, graph_xml)
    node = document.getNode(output)
    if node is None or node.getType() != "vector3" or len(node.getOutputs()) > 1:
        raise ExpressionError(f"the graph's output {output!r} is not a single vector3 node")
    builder = _Builder(document, output)
    half = builder.node("multiply", "vector3", in1=output, in2=(0.5, "float"))
    encoded = builder.node("add", "vector3", in1=half, in2=(0.5, "float"))
    decoded = builder.node("normalmap", "vector3", **{"in": encoded})
    return document_text(document), decoded


def normal_to_tangent(graph_xml: str, output: str) -> tuple[str, str]:
    """A world-space normal graph that ends in a ``normalmap`` (its tangent frame the mesh's) as the tangent-space
    vector in [-1, 1] UsdPreviewSurface's ``normal`` takes: the normalmap's input decoded (``t * 2 - 1``, x and y
    scaled by its strength), the normalmap itself left out. Any other graph raises :class:`ExpressionError`."""
    document = mx.createDocument()
    mx.readFromXmlString(document, graph_xml)
    node = document.getNode(output)
    if node is None or node.getCategory() != "normalmap":
        raise ExpressionError(f"the graph's output {output!r} is not a normalmap node")
    source = node.getInput("in")
    if source is None or not source.getNodeName() or any(
            node.getInput(name) is not None and (node.getInput(name).getNodeName() or node.getInput(name).hasValueString())
            for name in ("normal", "tangent", "bitangent")):
        raise ExpressionError("the normalmap decodes in a tangent frame of its own")
    scale = node.getInput("scale")
    strength = scale.getValue() if scale is not None and scale.hasValueString() else 1.0
    if not isinstance(strength, (int, float)) or isinstance(strength, bool):  # (text MaterialX cannot parse: OPBR004)
        raise ExpressionError(f"the normalmap's scale {scale.getValueString()!r} is no number")
    builder = _Builder(document, output)
    doubled = builder.node("multiply", "vector3", in1=source.getNodeName(), in2=(2.0, "float"))
    decoded = builder.node("subtract", "vector3", in1=doubled, in2=(1.0, "float"))
    if strength != 1.0:
        factor = (strength, strength, 1.0) if isinstance(strength, float) else (strength[0], strength[1], 1.0)
        decoded = builder.node("multiply", "vector3", in1=decoded, in2=(factor, "vector3"))
    return document_text(document), decoded
