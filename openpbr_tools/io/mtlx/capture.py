"""A procedural graph kept whole: the nodes upstream of a shader input the reader cannot interpret,
captured as one flat MaterialX document (:func:`capture_graph`, ``Connection.graph_xml``) so that a
.mtlx output rewires it instead of dropping it, and the file names in such a capture rewritten for an
output's folder (:func:`rewrite_files`). The walk follows connections wherever MaterialX does: within a
graph, through its interface (values, connections to other graphs, a nodedef instance's inputs, default
geometric properties) and into other graphs' outputs, so the capture validates on its own.
"""

from __future__ import annotations


def capture_graph(node, limit: int = 256, binding=None) -> str | None:
    """The nodes upstream of ``node`` (itself included) as one flat MaterialX document, so a procedural
    input survives a read-write round trip. Connections are followed wherever they lead: to a node of
    the same scope, through the enclosing graph's interface (an input bound to a value takes the value,
    one connected upstream -- a graph fed by another graph or a node outside -- brings that node along),
    and to another node graph's output; a nodedef's implementation graph reads the instance's inputs
    (``binding``: (instance, nodedef)). Names that repeat across scopes are made unique. ``None`` past
    ``limit`` nodes."""
    # lazy: the rules import the reader (so this module) at every start-up; MaterialX (~10 ms) waits for a .mtlx
    import MaterialX as mx

    captured = mx.createDocument()
    names: dict[str, str] = {}  # original node path -> name in the captured document
    pending = []

    def enqueue(upstream) -> str:
        path = upstream.getNamePath()
        if path not in names:
            name = upstream.getName()
            while captured.getChild(name) is not None or name in names.values():
                name = captured.createValidChildName(name + "_")
            names[path] = name
            pending.append(upstream)
        return names[path]

    enqueue(node)
    while pending:
        current = pending.pop()
        if len(names) > limit:
            return None
        copy = captured.addNode(current.getCategory(), names[current.getNamePath()], current.getType())
        copy.copyContentFrom(current)
        _resolve_files(copy, current)
        for port in current.getInputs():
            target = copy.getInput(port.getName())
            feed = _feed(port, binding)
            if feed is None:
                continue  # a value of its own
            for attribute in ("nodename", "nodegraph", "output", "interfacename"):
                target.removeAttribute(attribute)
            kind, found, output = feed
            if kind == "value":  # an interface input's value, with what it says of its colour space or unit
                target.setValueString(found.getValueString())
                for attribute in ("colorspace", "unit", "unittype"):
                    if found.hasAttribute(attribute) and not target.hasAttribute(attribute):
                        target.setAttribute(attribute, found.getAttribute(attribute))
                space = found.getActiveColorSpace()  # (one its graph or document gives it: the review's seventh)
                if target.getType() in ("color3", "color4") and not target.hasAttribute("colorspace") and space \
                        and space != current.getDocument().getColorSpace():
                    target.setColorSpace(space)
            elif kind == "node":
                target.setNodeName(enqueue(found))
                if output:
                    target.setOutputString(output)
            elif kind == "geomprop":  # the interface's default geometric property: a node that reads it
                reader = captured.addNode(found.getGeomProp(), captured.createValidChildName(f"{found.getName()}_geomprop"),
                                          found.getType())
                if found.getSpace():
                    reader.setInputValue("space", found.getSpace(), "string")
                if found.getIndex():
                    reader.setInputValue("index", int(found.getIndex()), "integer")
                target.setNodeName(reader.getName())
            else:  # an interface input with neither value nor connection: the node's own default
                copy.removeInput(port.getName())
    _add_definitions(captured, [node.getDocument().getDescendant(path) for path in names])
    from .writer import document_text  # lazy: the writer imports MaterialX at load (see above)

    return document_text(captured)


def capture_nodegraph(port, limit: int = 256) -> tuple[str, str] | None:
    """The document-level node graph a top-level shader's ``port`` reads (``nodegraph=``, ``output=``), copied
    whole as a one-graph MaterialX document, and the name of the output read: its interface (the inputs
    artists edit, with their ``uiname``/``uifolder``/soft ranges), every output and node, so a .mtlx output
    keeps it as the source had it (the red team's E#7: a marble's six controls were inlined, and its output,
    read by two inputs, written twice). The copy stands alone: file names resolved where they stood
    (``fileprefix`` applied, then dropped) and the graph's colour space written on it, which its nodes and
    values inherit, as they did. ``None`` for a graph that does not stand alone (an interface input connected
    elsewhere, a node reading another graph or a node outside, a custom node, more than ``limit`` nodes),
    which the flat capture (:func:`capture_graph`) carries instead."""
    import MaterialX as mx  # lazy: as in capture_graph

    from .library import known_categories  # lazy: as in _add_definitions

    name, shader = port.getNodeGraphString(), port.getParent()
    document = port.getDocument()
    if not name or shader is None or shader.getParent() != document:
        return None
    graph = document.getNodeGraph(name)
    if graph is None or graph.getNodeDefString() or any(c.getCategory() == "nodegraph" for c in graph.getChildren()):
        return None
    outputs = graph.getOutputs()
    output = graph.getOutput(port.getOutputString()) if port.getOutputString() else \
        (outputs[0] if len(outputs) == 1 else None)
    nodes = graph.getNodes()
    if output is None or len(nodes) > limit:
        return None
    if any(any(i.hasAttribute(a) for a in ("nodename", "nodegraph", "interfacename")) for i in graph.getInputs()):
        return None
    standard = known_categories(complete=True)
    for node in nodes:
        if node.getCategory() not in standard:
            return None
        for inner in node.getInputs():
            if inner.hasAttribute("nodegraph") or inner.hasAttribute("nodename") and graph.getNode(inner.getNodeName()) is None:
                return None
    captured = mx.createDocument()
    copy = captured.addNodeGraph(name)
    copy.copyContentFrom(graph)
    space = graph.getActiveColorSpace()
    if space:
        copy.setColorSpace(space)
    for original, copied in [(graph, copy)] + [(node, copy.getNode(node.getName())) for node in nodes]:
        copied.removeAttribute("fileprefix")
        for inner in original.getInputs():
            if inner.getType() == "filename" and inner.hasAttribute("value"):
                copied.getInput(inner.getName()).setValueString(inner.getResolvedValueString())
    from .writer import document_text  # lazy: as in capture_graph

    return document_text(captured), output.getName()


def _add_definitions(captured, originals) -> None:
    """The document's own node definitions the captured nodes instantiate (custom nodes, not the data
    library's), each with its implementation graph, and those that graph's nodes need in turn: without
    them the capture names categories no nodedef declares (OPBR104) and does not generate."""
    from .library import known_categories  # lazy: as MaterialX above

    standard = known_categories(complete=True)
    pending = [node for node in originals if node is not None and node.getCategory() not in standard]
    while pending:
        node = pending.pop()
        nodedef = node.getNodeDef()
        document = node.getDocument()
        if nodedef is None or document.getChild(nodedef.getName()) is None or captured.getChild(nodedef.getName()):
            continue  # a library node, or one already carried
        captured.addChildOfCategory("nodedef", nodedef.getName()).copyContentFrom(nodedef)
        implementation = nodedef.getImplementation()
        if implementation is not None and implementation.getCategory() == "nodegraph" \
                and document.getChild(implementation.getName()) is not None and not captured.getChild(implementation.getName()):
            captured.addChildOfCategory("nodegraph", implementation.getName()).copyContentFrom(implementation)
            pending += [inner for inner in implementation.getNodes() if inner.getCategory() not in standard]


def interface_input(port, binding):
    """(the element a port bound by ``interfacename`` reads, the binding what that element is connected to
    is read with). In a node graph, its input (its own connections read with ``binding`` still); in a graph
    implementing a nodedef, the input of the instance being read (``binding``: (instance, nodedef)), else the
    nodedef's default, whose connections belong to the instance's scope, outside the definition (binding
    None); ``None`` there when no instance is being read."""
    scope = port.getParent().getParent()
    if scope is None or scope.getCategory() != "nodegraph" or not scope.getNodeDefString():
        return port.getInterfaceInput(), binding
    if binding is None:
        return None, None
    instance, nodedef = binding
    name = port.getInterfaceName()
    return instance.getInput(name) or nodedef.getActiveInput(name), None


def _feed(port, binding, depth: int = 0):
    """What feeds a port of a node being captured: ``None`` for its own value; else ``("value", element,
    None)`` (an interface input's value), ``("node", node, output)`` (the node and, for a multi-output
    one, which output), ``("geomprop", geompropdef, None)`` (an interface input's default geometric
    property, UV0 say) or ``("default", None, None)``."""
    if depth > 16:
        return ("default", None, None)
    if port.hasAttribute("interfacename"):
        interface, binding = interface_input(port, binding)
        if interface is None:
            return ("default", None, None)
        if any(interface.hasAttribute(a) for a in ("nodename", "nodegraph", "interfacename")):
            return _feed(interface, binding, depth + 1)
        if interface.hasAttribute("value"):
            return ("value", interface, None)
        geomprop = interface.getDocument().getGeomPropDef(interface.getDefaultGeomPropString()) \
            if interface.hasAttribute("defaultgeomprop") else None
        return ("geomprop", geomprop, None) if geomprop is not None else ("default", None, None)
    if not (port.hasAttribute("nodename") or port.hasAttribute("nodegraph")):
        return None
    output = port.getConnectedOutput()
    if output is not None and output.getParent().getCategory() in ("nodegraph", "materialx"):
        upstream = output.getConnectedNode()  # a graph's output: the node behind it
        return ("node", upstream, output.getOutputString()) if upstream is not None else ("default", None, None)
    upstream = port.getConnectedNode()
    if upstream is None:
        return ("default", None, None)
    return ("node", upstream, port.getOutputString())


def rewrite_files(graph_xml: str, rewrite) -> str:
    """``graph_xml`` with each filename input's value replaced by ``rewrite(value)`` (None keeps it)."""
    # lazy: as in capture_graph
    import MaterialX as mx

    from .writer import document_text  # lazy: as in capture_graph

    document = mx.createDocument()
    mx.readFromXmlString(document, graph_xml)
    changed = False
    kept = [graph for graph in document.getNodeGraphs() if not graph.getNodeDefString()]  # capture_nodegraph's
    for node in document.getNodes() + [element for graph in kept for element in [graph] + graph.getNodes()]:
        for port in node.getInputs():
            if port.getType() == "filename" and port.hasAttribute("value"):
                new = rewrite(port.getValueString())
                if new is not None and new != port.getValueString():
                    port.setValueString(new)
                    changed = True
    return document_text(document) if changed else graph_xml


def _resolve_files(copy, original) -> None:
    """Filename inputs of a captured node as they resolve where the node stood: the enclosing
    elements' ``fileprefix`` applied (MaterialX's examples put ``../../../Images/`` on the document or
    the node graph; without it a kept marble's or brick's images would be looked up beside the output),
    and the colour space an enclosing element gives them (and colour values) written on the input itself."""
    root = original.getDocument()
    for port in original.getInputs():
        if port.getType() not in ("filename", "color3", "color4") or not port.hasAttribute("value"):
            continue
        target = copy.getInput(port.getName())
        if port.getType() == "filename":
            target.setValueString(port.getResolvedValueString())
        # a colour value is colour-managed as a file is (the MaterialX specification: colorspace applies to both,
        # inherited from the nearest enclosing element); the red team's F4: a node graph's space was dropped
        space = port.getActiveColorSpace()
        if not port.getColorSpace() and space and space != root.getColorSpace():
            target.setColorSpace(space)


def read_output(port) -> str:
    """Which output of the node feeding ``port`` it reads: the port's ``output`` (a multi-output node's
    ``outg``), or, through a node graph's (or the document's) <output>, that output's own ``output``
    attribute (``<output nodename="split" output="outg">``)."""
    output = port.getConnectedOutput()
    if output is not None and output.getParent().getCategory() in ("nodegraph", "materialx"):
        return output.getOutputString()
    return port.getOutputString() if not port.getNodeGraphString() else ""


def select_output(graph_xml: str, node_name: str, output_name: str, type_name: str) -> tuple[str, str]:
    """(the capture with a ``dot`` node of ``type_name`` reading output ``output_name`` of multi-output node
    ``node_name``, the dot's name): a kept graph then ends in one typed node, so a writer's plain ``nodename``
    connection (and an expression appended after it) reads the output the source read. Without it the connection
    to a multi-output node names no output: MaterialX validates it, and its GLSL does not compile."""
    # lazy: as in capture_graph
    import MaterialX as mx

    from .writer import document_text  # lazy: as in capture_graph

    document = mx.createDocument()
    mx.readFromXmlString(document, graph_xml)
    name, count = f"{node_name}_{output_name}", 1
    while document.getChild(name) is not None:
        count += 1
        name = f"{node_name}_{output_name}{count}"
    dot = document.addNode("dot", name, type_name)
    port = dot.addInput("in", type_name)
    port.setNodeName(node_name)
    port.setOutputString(output_name)
    return document_text(document), name
