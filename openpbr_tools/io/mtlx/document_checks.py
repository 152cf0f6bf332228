"""Facts about a MaterialX document's own elements that its materials' values do not show (the red team's round six),
observed once per document for the rules of :mod:`openpbr_tools.rules.mtlx_document`:

* ``mtlx_channel_out_of_range``: an ``extract`` whose index names a channel its input's type does not have (index 3 of
  a color3: the generated GLSL indexes past the vector);
* ``mtlx_implementation_missing``: a custom node's ``<implementation file=...>`` that is not beside the document
  (MaterialX's shader generation fails: "Failed to get source code from file");
* ``mtlx_default_versions``: two nodedefs of one node and signature that both say ``isdefaultversion="true"`` (the
  specification allows one; MaterialX binds one silently);
* ``mtlx_look_geometry``: a look assignment whose geom names a path with ``|`` (Maya's DAG separator), which no
  MaterialX geometry name matches (they use ``/``);
* ``mtlx_colorspace_on_connection``: a ``colorspace`` on a connected input, which applies to an input's value only:
  the connected texture is not converted;
* ``mtlx_normalmap_negative``: a normalmap whose float scale is negative, which flips x and y (a DirectX map needs
  only green flipped: a vector2 scale of (1, -1));
* ``mtlx_output_unnamed``: an input connected to a node graph (or a multi-output node) with several outputs without
  naming one (``output``, which the specification requires there); MaterialX connects the first;
* ``mtlx_normal_space``: a shader's normal or tangent input fed by a ``normal``/``tangent``/``bitangent`` node in object
  or model space, where the shading models take world space (their nodedefs' Nworld/Tworld defaults);
* ``mtlx_hextiled_normal``: a ``normalmap`` reading a ``hextiledimage``, whose random per-tile rotation turns the
  lookup without turning the encoded vectors (MaterialX has ``hextilednormalmap`` for this);
* ``mtlx_assign_geom_and_collection``: a look assignment naming both ``geom`` and ``collection``, which the
  specification allows one of;
* ``mtlx_normalmap_uv_set``: a ``normalmap`` without a tangent whose image reads a UV set other than 0, while its
  default tangent frame (Tworld) follows the mesh's first UV set;
* ``mtlx_image_file``: every file a node upstream of a material reads (a ``filename`` input's value, resolved as
  MaterialX resolves it: the enclosing ``fileprefix`` and tokens applied), so the texture family checks the files
  of images the graph follower does not turn into textures (an image whose texcoord is computed, as every
  GPUOpen-library material's is) as it checks the others;
* ``mtlx_normalmap_image``: the file of an image a ``normalmap`` decodes (through ``convert``/``dot`` nodes), so the
  texture family judges it as a normal map where the graph follower does not make it a texture (a computed
  texcoord);
* ``mtlx_image_colorspace``: a float or vector image a material reads (a displacement's height as well as a shader
  input) whose file input or node itself carries a colour space, which MaterialX does not apply to such an image.
"""

from __future__ import annotations

import os

from ...model import Asset, Location
from ...values import ValueSyntaxError, parse_value

#: channels of each MaterialX type an extract takes
_CHANNELS = {"float": 1, "color3": 3, "color4": 4, "vector2": 2, "vector3": 3, "vector4": 4}


def observe_document(document, asset: Asset, path: str, guard) -> None:
    def where(element, input_name=None):
        name = element.getNamePath()
        return Location(path, asset.line_of.get(name), name, input_name)

    import MaterialX as mx  # lazy: as the reader imports it

    nodes = [element for element in document.traverseTree() if element.isA(mx.Node)]
    if asset.extra.get("included_by"):  # read in its includer's composition: the includer's nodes are its own
        nodes = [node for node in nodes if not node.getActiveSourceUri()]
    used_categories = {node.getCategory() for node in nodes}
    for node in nodes:
        category = node.getCategory()
        if category == "extract":
            _extract(node, asset, where)
        elif category == "normalmap":
            scale = node.getInput("scale")
            if scale is not None and scale.getType() == "float" and scale.hasValueString():
                try:
                    value = parse_value(scale.getValueString(), "float")
                except ValueSyntaxError:
                    value = 0.0  # (OPBR202 reports the value)
                if value < 0:
                    asset.observe("mtlx_normalmap_negative", where(node, "scale"), node=node.getNamePath(), scale=value)
        for port in node.getInputs():
            if port.hasColorSpace() and (port.getNodeName() or port.getNodeGraphString() or port.getOutputString()) \
                    and not port.hasValueString():
                asset.observe("mtlx_colorspace_on_connection", where(node, port.getName()), input=port.getName(),
                              colorspace=port.getColorSpace(), node=node.getNamePath())
    _image_files(document, nodes, asset, where)
    _connections(nodes, asset, where)
    for look in document.getLooks():
        for assignment in look.getMaterialAssigns():
            if assignment.getGeom() and assignment.getCollectionString():
                asset.observe("mtlx_assign_geom_and_collection", where(assignment), look=look.getName(),
                              geom=assignment.getGeom(), collection=assignment.getCollectionString())
    defaults: dict[tuple, list[str]] = {}
    for nodedef in document.getNodeDefs():
        if nodedef.getDefaultVersion():
            signature = (nodedef.getNodeString(), tuple(o.getType() for o in nodedef.getOutputs()),
                         tuple((i.getName(), i.getType()) for i in nodedef.getInputs()))
            defaults.setdefault(signature, []).append(nodedef.getName())
    for (node_name, _, _), names in defaults.items():
        if len(names) > 1:
            first = document.getNodeDef(names[1])
            asset.observe("mtlx_default_versions", where(first), node=node_name, nodedefs=names)
    for implementation in document.getImplementations():
        file = implementation.getFile()
        nodedef = implementation.getNodeDef()
        if not file or nodedef is None or nodedef.getNodeString() not in used_categories or not implementation.getTarget():
            continue  # (an implementation without a target names no generator: OpenUSD's usdMtlx test documents)
        # MaterialX looks for it beside the document that declares it (an included library's own folder), then on
        # its data search path (its libraries)
        source = implementation.getActiveSourceUri() or path
        folder = os.path.dirname(os.path.abspath(source))
        resolved = guard.resolve(file, folder)
        if not resolved.inside:
            continue  # outside the asset's folder: never opened
        if not os.path.isfile(resolved.real or os.path.join(folder, file)) and \
                not mx.getDefaultDataSearchPath().find(file).exists():
            asset.observe("mtlx_implementation_missing", where(implementation), file=file,
                          target=implementation.getTarget(), node=nodedef.getNodeString())
    for look in document.getLooks():
        for assignment in list(look.getMaterialAssigns()) + list(look.getPropertyAssigns()) + list(look.getVisibilities()):
            geom = assignment.getGeom()
            if "|" in geom:
                asset.observe("mtlx_look_geometry", where(assignment), look=look.getName(), geom=geom)


_SHADER_NORMALS = ("geometry_normal", "geometry_coat_normal", "geometry_tangent", "geometry_coat_tangent", "normal",
                   "coat_normal", "tangent")  # (OpenPBR's, Standard Surface's)
_GEOMETRIC_VECTORS = ("normal", "tangent", "bitangent")


def _upstream(port):
    """The node ``port`` reads through a node graph's output (its connected node), or None."""
    try:
        return port.getConnectedNode()
    except Exception:  # noqa: BLE001 - MaterialX raises on some broken references (reported elsewhere)
        return None


def _connections(nodes, asset, where) -> None:
    for node in nodes:
        for port in node.getInputs():
            if not (port.getNodeGraphString() or port.getNodeName()) or port.getOutputString():
                continue
            target = port.getConnectedOutput()
            owner = target.getParent() if target is not None else None
            if owner is not None and owner.getCategory() == "nodegraph" and len(owner.getOutputs()) > 1:
                asset.observe("mtlx_output_unnamed", where(node, port.getName()), input=port.getName(),
                              node=node.getNamePath(), graph=owner.getNamePath(), chosen=target.getName(),
                              outputs=[o.getName() for o in owner.getOutputs()])
        if node.getType() == "surfaceshader":
            for port in node.getInputs():
                source = _upstream(port) if port.getName() in _SHADER_NORMALS else None
                space = source.getInput("space") if source is not None and source.getCategory() in _GEOMETRIC_VECTORS \
                    else None
                if space is not None and space.getValueString() in ("object", "model"):
                    asset.observe("mtlx_normal_space", where(node, port.getName()), input=port.getName(),
                                  node=source.getNamePath(), category=source.getCategory(), space=space.getValueString())
        if node.getCategory() == "normalmap":
            image = _image_behind(node.getInput("in"))
            if image is not None and image.getCategory() == "hextiledimage":
                asset.observe("mtlx_hextiled_normal", where(node, "in"), node=node.getNamePath(), image=image.getNamePath())
            file = image.getInput("file") if image is not None else None
            if file is not None and file.hasValueString() and file.getValueString().strip():
                asset.observe("mtlx_normalmap_image", where(image, "file"), node=image.getNamePath(),
                              file=file.getResolvedValueString(), normalmap=node.getNamePath())
            tangent = node.getInput("tangent")
            texcoord = image.getInput("texcoord") if image is not None else None
            reader = _upstream(texcoord) if texcoord is not None else None
            index = reader.getInput("index") if reader is not None and reader.getCategory() == "texcoord" else None
            if index is not None and index.getValueString().strip() not in ("", "0") and (
                    tangent is None or not (tangent.getNodeName() or tangent.getNodeGraphString()
                                            or tangent.getInterfaceName())):
                asset.observe("mtlx_normalmap_uv_set", where(node), node=node.getNamePath(), image=image.getNamePath(),
                              index=index.getValueString().strip())


def _image_behind(port, depth: int = 0):
    """The image-like node (a node with a ``file`` input) behind ``port`` through ``convert``/``dot``/``extract``
    nodes, or None."""
    node = _upstream(port) if port is not None else None
    if node is None or depth > 4:
        return None
    if node.getInput("file") is not None:
        return node
    if node.getCategory() in ("convert", "dot", "extract", "swizzle"):
        return _image_behind(node.getInput("in"), depth + 1)
    return None


def _image_files(document, nodes, asset, where) -> None:
    """``mtlx_image_file`` for each filename input with a value on a node a material reads (none in a document
    without materials: a library of graphs renders nothing by itself, and its file names may be placeholders)."""
    materials = [node for node in nodes if node.getType() == "material"]
    upstream: set[str] = set()
    for material in materials:
        try:
            for edge in material.traverseGraph():
                element = edge.getUpstreamElement()
                if element is not None:
                    upstream.add(element.getNamePath())
                graph = element.getParent() if element is not None else None
                if graph is not None and graph.getCategory() == "nodegraph":
                    upstream.update(node.getNamePath() for node in graph.getNodes())  # (interface-fed nodes)
        except LookupError:  # a cycle (MaterialX: "Encountered cycle"; OPBR004 reports it): what was reached so far
            continue
    for node in nodes:
        if node.getNamePath() not in upstream:
            continue
        for port in node.getInputs():
            if port.getType() == "filename" and port.hasValueString() and port.getValueString().strip():
                asset.observe("mtlx_image_file", where(node, port.getName()), file=port.getResolvedValueString(),
                              node=node.getNamePath())
                space = port.getAttribute("colorspace") or node.getAttribute("colorspace")
                if space and port.getName() == "file" and node.getType() in ("float", "vector2", "vector3", "vector4"):
                    asset.observe("mtlx_image_colorspace", where(node, port.getName()), node=node.getNamePath(),
                                  colorspace=space, type=node.getType(), file=port.getValueString())
        for port in _defaulted_files(document, node):
            asset.observe("mtlx_image_file", where(port.getParent(), port.getName()), file=port.getResolvedValueString(),
                          node=node.getNamePath())


def _defaulted_files(document, node) -> list:
    """The filename inputs of a custom node's nodedef (defined in the document or its includes, not MaterialX's
    libraries) that the instance does not set: its implementation graph reads their defaults."""
    try:
        nodedef = node.getNodeDef()
    except Exception:  # noqa: BLE001 - MaterialX raises on some broken definitions (reported elsewhere)
        return []
    if nodedef is None or document.getChild(nodedef.getName()) is None:
        return []
    return [port for port in nodedef.getInputs() if port.getType() == "filename" and port.hasValueString()
            and port.getValueString().strip() and node.getInput(port.getName()) is None]


def _extract(node, asset, where) -> None:
    source = node.getInput("in")
    index = node.getInput("index")
    if source is None or index is None or not index.hasValueString():
        return
    try:
        value = int(index.getValueString())
    except ValueError:
        return
    channels = _CHANNELS.get(source.getType())
    if channels is not None and not 0 <= value < channels:
        asset.observe("mtlx_channel_out_of_range", where(node, "index"), node=node.getNamePath(), index=value,
                      type=source.getType(), channels=channels)
