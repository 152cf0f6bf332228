"""MaterialX's glTF image nodes (``gltf_image``, ``gltf_colorimage``, ``gltf_normalmap``; MaterialX's
``libraries/bxdf/gltf_pbr.mtlx``) read as a :class:`~openpbr_tools.model.Texture`: their factor multiplies
the texel (``gltf_image``'s ``factor``; ``gltf_colorimage``'s ``color``, RGB on ``outcolor`` and A on
``outa``), and their texture transform inputs are ``place2d``'s own (the nodes feed them to a ``place2d``
with pivot (0, 1) by default: :mod:`openpbr_tools.io.gltf.uv`)."""

from __future__ import annotations

from ...model import UVTransform
from ...values import ValueSyntaxError, parse_value
from .arithmetic import connected

_FACTOR = {"gltf_image": "factor", "gltf_colorimage": "color"}


def _value(port, type_name: str):
    if port is None or not port.hasAttribute("value"):
        return None
    try:
        return parse_value(port.getValueString(), type_name)
    except ValueSyntaxError:
        return None


def factor(node, channels) -> list[float] | None:
    """The node's constant factor on the channels read (``channels``: None for the colour, (3,) for
    ``outa``), or None when it has none (or it is connected: then the node is not a plain lookup)."""
    name = _FACTOR.get(node.getCategory())
    port = node.getInput(name) if name else None
    value = _value(port, port.getType()) if port is not None else None
    if value is None:
        return None
    values = [float(v) for v in value] if isinstance(value, (tuple, list)) else [float(value)]
    if channels is not None and len(values) > 1:
        return [values[channels[0]]] if channels[0] < len(values) else None
    return values[:3] if node.getCategory() == "gltf_colorimage" else values


def connected_factor(node) -> bool:
    """Whether the factor is driven by a connection (the lookup is then not a plain texture)."""
    name = _FACTOR.get(node.getCategory())
    port = node.getInput(name) if name else None
    return port is not None and connected(port)


def transform(node) -> UVTransform | None | bool:
    """The node's texture transform as ``place2d`` parameters; None when it is the identity; False when it
    cannot be held (a connected input, or the offset-rotate-scale order with a rotation or scale)."""
    ports = {name: node.getInput(name) for name in ("pivot", "scale", "rotate", "offset", "operationorder")}
    if any(p is not None and connected(p) for p in ports.values()):
        return False
    definition = node.getNodeDef()

    def value(name, type_name, default):
        found = _value(ports[name], type_name)
        if found is None and definition is not None:
            found = _value(definition.getInput(name), type_name)
        return default if found is None else found

    scale, rotate, offset = value("scale", "vector2", (1.0, 1.0)), value("rotate", "float", 0.0), \
        value("offset", "vector2", (0.0, 0.0))
    if tuple(scale) == (1.0, 1.0) and rotate == 0.0 and tuple(offset) == (0.0, 0.0):
        return None
    if int(value("operationorder", "integer", 0)) != 0 and (tuple(scale) != (1.0, 1.0) or rotate != 0.0):
        return False  # offset first, then rotate and scale: not place2d's SRT order
    return UVTransform(scale=tuple(float(v) for v in scale), rotate=float(rotate),
                       offset=tuple(float(v) for v in offset),
                       pivot=tuple(float(v) for v in value("pivot", "vector2", (0.0, 1.0))))
