"""``multiply``/``add`` by constants, and a float ``mix`` of two constants by the image (bg + (fg - bg) * t: an
affine map, as GPUOpen's MaterialX library writes a roughness range over a mask), between an image and the input
it feeds, read as the texture's scale and bias (as a UsdUVTexture's: the writer puts them there)."""

from __future__ import annotations

from ...values import ValueSyntaxError, parse_value


def connected(port) -> bool:
    """Whether ``port`` is connected (to a node, a graph, an interface input or an output)."""
    return any(port.hasAttribute(a) for a in ("nodename", "nodegraph", "interfacename", "output"))


class ScaleBias:
    """``multiply``/``add`` nodes met walking up from the input, composed into one value * scale + bias
    (moving up past ``+ c`` adds c * scale to the bias; past ``* k`` multiplies the scale by k). An
    operation on the whole colour above an ``extract`` is reduced to the extracted channel."""

    def __init__(self):
        self.scale, self.bias, self.seen = None, None, False

    def take(self, node, channels) -> bool:
        first, second = node.getInput("in1"), node.getInput("in2")
        if second is not None and second.hasAttribute("interfacename") and not any(
                second.hasAttribute(a) for a in ("nodename", "nodegraph", "output")):
            second = _interface_value(node, second)  # a published graph's control ('tint'): its value
        if first is None or second is None or not second.hasAttribute("value") or connected(second):
            return False
        try:
            value = parse_value(second.getValueString(), second.getType())
        except ValueSyntaxError:
            return False
        operand = [float(v) for v in value] if isinstance(value, (tuple, list)) else [float(value)]
        if channels is not None and len(operand) > 1:
            if channels[0] >= len(operand):
                return False
            operand = [operand[channels[0]]]
        self.seen = True
        scale = self.scale if self.scale is not None else [1.0]
        if node.getCategory() == "add":
            bias = self.bias if self.bias is not None else [0.0]
            self.bias = combine(bias, combine(operand, scale, lambda a, b: a * b), lambda a, b: a + b)
        else:
            self.scale = combine(scale, operand, lambda a, b: a * b)
        return True

    def take_mix(self, node) -> bool:
        """A float ``mix`` whose ``fg`` and ``bg`` are constants (values, ``constant`` nodes or a graph's controls) and
        whose ``mix`` is the walk's path: bg + (fg - bg) * t, composed as a multiply by fg - bg then an add of bg."""
        ends = [constant_operand(node.getInput(name)) for name in ("fg", "bg")]
        if node.getType() != "float" or any(end is None or len(end) != 1 for end in ends) or node.getInput("mix") is None:
            return False  # (a colour mix by a float mask makes a colour of a float image: no Texture holds that)
        fg, bg = ends
        self.seen = True
        scale = self.scale if self.scale is not None else [1.0]
        bias = self.bias if self.bias is not None else [0.0]
        self.bias = combine(bias, combine(bg, scale, lambda a, b: a * b), lambda a, b: a + b)
        self.scale = combine(scale, combine(fg, bg, lambda a, b: a - b), lambda a, b: a * b)
        return True

    def multiply(self, operand: list[float] | None) -> None:
        """An image's own factor, which applies before every operation met above it."""
        if operand is not None and operand != [1.0] * len(operand):
            self.scale = combine(self.scale if self.scale is not None else [1.0], operand, lambda a, b: a * b)

    def values(self):
        def shown(v):
            return None if v is None else (v[0] if len(v) == 1 else tuple(v))
        return shown(self.scale), shown(self.bias)


def _interface_value(node, port):
    """The interface input of a document-level node graph that ``port`` reads, where it holds a value of its own
    (not connected); ``None`` otherwise, and inside a nodedef's implementation (whose instance gives the value)."""
    graph = node.getParent()
    if graph is None or graph.getCategory() != "nodegraph" or graph.getNodeDefString():
        return None
    interface = graph.getInput(port.getInterfaceName())
    return interface if interface is not None and not connected(interface) else None


def constant_operand(port) -> list[float] | None:
    """The numbers ``port`` holds as a constant: its own value, a graph control's (:func:`_interface_value`) or a
    ``constant`` node's; None where it is connected to anything else, holds a colour in a colour space of its own, or
    cannot be parsed."""
    if port is None:
        return None
    holder = port
    if port.hasAttribute("interfacename") and not any(port.hasAttribute(a) for a in ("nodename", "nodegraph", "output")):
        holder = _interface_value(port.getParent(), port)
    elif port.hasAttribute("nodename") and not any(port.hasAttribute(a) for a in ("nodegraph", "output")):
        node = port.getConnectedNode()
        holder = node.getInput("value") if node is not None and node.getCategory() == "constant" else None
    if holder is None or not holder.hasAttribute("value") or connected(holder) or holder.hasAttribute("colorspace"):
        return None
    try:
        value = parse_value(holder.getValueString(), holder.getType())
    except ValueSyntaxError:
        return None
    if isinstance(value, bool) or not isinstance(value, (int, float, tuple, list)):
        return None
    return [float(v) for v in value] if isinstance(value, (tuple, list)) else [float(value)]


def combine(a: list[float], b: list[float], operation) -> list[float]:
    width = max(len(a), len(b))
    a, b = (a * width)[:width] if len(a) == 1 else a, (b * width)[:width] if len(b) == 1 else b
    return [operation(x, y) for x, y in zip(a, b)]
