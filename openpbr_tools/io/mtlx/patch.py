"""Apply upgrade edits to a MaterialX document in place, keeping everything else in it.

``openpbr upgrade`` rewrites only the inputs of the shaders it upgrades; looks, node graphs, other
nodes, comments' neighbours and attribute order elsewhere stay as MaterialX read them.
"""

from __future__ import annotations

import MaterialX as mx

from ...values import format_value

CONNECTION_ATTRIBUTES = ("nodename", "nodegraph", "output", "interfacename")


def apply_edits(node, edits, version: str) -> None:
    """Apply :class:`~openpbr_tools.translate.upgrade.Edit` objects to a MaterialX shader node."""
    scope = node.getParent()
    for edit in edits:
        if edit.kind == "rename":
            node.getInput(edit.name).setName(edit.new_name)
        elif edit.kind == "remove":
            node.removeInput(edit.name)
        elif edit.kind == "set":
            port = node.getInput(edit.name) or node.addInput(edit.name, edit.type)
            for attribute in CONNECTION_ATTRIBUTES:
                port.removeAttribute(attribute)
            port.setType(edit.type)
            port.setValueString(format_value(edit.value, edit.type))
        elif edit.kind == "graph":
            renamed = {n.name: _unique(scope, n.name) for n in edit.graph}
            for graph_node in edit.graph:
                element = scope.addNode(graph_node.category, renamed[graph_node.name], graph_node.type)
                for name, type_name, value in graph_node.inputs:
                    port = element.addInput(name, type_name)
                    if value.startswith("@"):
                        port.setNodeName(renamed[value[1:]])
                    else:
                        port.setValueString(value)
            port = node.getInput(edit.name) or node.addInput(edit.name, edit.type)
            port.removeAttribute("value")
            port.setNodeName(renamed[edit.graph[-1].name])
        elif edit.kind == "channels":
            port = node.getInput(edit.name)
            extract = scope.addNode("extract", _unique(scope, f"{node.getName()}_{edit.name}_channel"), edit.type)
            upstream = extract.addInput("in", port.getType())
            for attribute in CONNECTION_ATTRIBUTES:
                if port.hasAttribute(attribute):
                    upstream.setAttribute(attribute, port.getAttribute(attribute))
                    port.removeAttribute(attribute)
            extract.addInput("index", "integer").setValueString(str(edit.value[0]))
            port.setType(edit.type)
            port.setNodeName(extract.getName())
        else:  # pragma: no cover - a programming error
            raise ValueError(edit.kind)
    node.setVersionString(version)
    node.removeAttribute("nodedef")


def _unique(scope, name: str) -> str:
    candidate = base = mx.createValidName(name)
    index = 1
    while scope.getChild(candidate) is not None:
        index += 1
        candidate = f"{base}_{index}"
    return candidate
