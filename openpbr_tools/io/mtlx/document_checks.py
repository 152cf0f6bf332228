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
  only green flipped: a vector2 scale of (1, -1)).
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
