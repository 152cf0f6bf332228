"""Teaching usd-core's shader registry (Sdr) the MaterialX node definitions.

usd-core on PyPI has no MaterialX plug-in, so Sdr does not know ``ND_open_pbr_surface_surfaceshader``
and its ``ShaderSdrCompliance`` validator reports every MaterialX shader as "not found in
sdrRegistry". :func:`register_materialx_nodes` fills that gap: it describes each MaterialX node
definition as a USD shader definition (inputs typed as UsdMtlx types them) in an in-memory layer and
hands it to Sdr through UsdShade's own shader-definition parser, the same route usd-core uses for
``UsdPreviewSurface``. :func:`materialx_nodedef` looks a definition up (MaterialX's standard
libraries plus the toolkit's legacy OpenPBR definitions); :func:`defined_output_type` says what type a
node's definition gives one of its outputs.
"""

from __future__ import annotations

import os
from functools import lru_cache

import MaterialX as mx

from ...resources import data_dir, load_json
from ..mtlx.library import standard_library
from .errors import quiet
from .types import MATERIALX_TO_USD

_registered: set[str] = set()
_definition_layers: list = []  # Sdr parses lazily: the in-memory layers must stay alive


@lru_cache(maxsize=1)
def _materialx_nodedefs():
    """Name -> nodedef for MaterialX's libraries plus the toolkit's legacy OpenPBR definitions."""
    found = {nd.getName(): nd for nd in standard_library().getNodeDefs()}
    try:
        legacy = data_dir("libraries")
        for name in sorted(os.listdir(legacy)):
            if name.endswith(".mtlx"):
                document = mx.createDocument()
                mx.readFromXmlFile(document, str(legacy / name))
                for nodedef in document.getNodeDefs():
                    found.setdefault(nodedef.getName(), nodedef)
    except (FileNotFoundError, OSError):
        pass
    return found


def materialx_nodedef_names() -> list[str]:
    return sorted(_materialx_nodedefs())


def materialx_nodedef(name: str):
    """The MaterialX node definition called ``name`` (standard libraries or the toolkit's legacy
    OpenPBR definitions), or ``None``. A definition MaterialX renamed is found by its earlier name too
    (schemas/materialx_nodedef_renames.json: ``ND_normalmap``, 1.38's, is ``ND_normalmap_float``), as OpenUSD's
    hdMtlx finds it (the red team's P-F2: OpenUSD's own mxNormalMap.usda was reported as an unknown id, and its
    normal maps were dropped on conversion)."""
    definitions = _materialx_nodedefs()
    return definitions.get(name) or definitions.get(load_json("materialx_nodedef_renames.json")["renamed"].get(name))


def defined_output_type(shader_id: str, output_name: str) -> str | None:
    """The USD type a shader node's definition gives its output ``output_name`` (a MaterialX node definition, as
    UsdMtlx types it, else the Sdr registry's, where UsdPreviewSurface's nodes are defined), or ``None`` when no
    definition is known. Renderers build the network from the definition (Storm from Sdr, hdMtlx from MaterialX),
    not from the type authored on the prim's output."""
    nodedef = materialx_nodedef(shader_id)
    if nodedef is not None:
        port = nodedef.getActiveOutput(output_name)
        return MATERIALX_TO_USD.get(port.getType()) if port is not None else None
    if not shader_id:
        return None
    from pxr import Sdr  # lazy: as in register_materialx_nodes

    with quiet():
        node = Sdr.Registry().GetShaderNodeByIdentifier(shader_id)
    output = node.GetShaderOutput(output_name) if node else None
    if output is None:
        return None
    indicator = output.GetTypeAsSdfType()
    return str(indicator.GetSdfType()) if indicator.HasSdfType() else None


def register_materialx_nodes(ids) -> list[str]:
    """Make Sdr know the MaterialX node definitions among ``ids``; returns the ids registered now.

    Ids that are not MaterialX node definitions, and ids Sdr already knows (from an earlier call,
    or from a usd build that has the MaterialX plug-in), are left alone.
    """
    from pxr import Sdf, Sdr  # lazy: pxr (0.1-0.2 s) only after require_pxr; the USD reader imports this first

    registry = Sdr.Registry()
    wanted = []
    for shader_id in sorted(set(ids) - _registered):
        nodedef = materialx_nodedef(shader_id)
        _registered.add(shader_id)
        if nodedef is None:
            continue
        with quiet():
            known = registry.GetShaderNodeByIdentifier(shader_id)
        if not known:
            wanted.append((shader_id, nodedef))  # (an earlier name of a renamed definition: under that name)
    if not wanted:
        return []
    layer = Sdf.Layer.CreateAnonymous("openpbr_tools_materialx_defs.usda")
    for shader_id, nodedef in wanted:
        _define_shader(layer, shader_id, nodedef)
    _definition_layers.append(layer)
    for shader_id, nodedef in wanted:
        result = Sdr.NodeDiscoveryResult(
            shader_id, Sdr.Version(1).GetAsDefault(), shader_id, nodedef.getNodeString(),
            "usda", "mtlx", layer.identifier, layer.identifier,
        )
        registry.AddDiscoveryResult(result)
    return [shader_id for shader_id, _ in wanted]


def _define_shader(layer, name: str, nodedef) -> None:
    from pxr import Sdf  # lazy: as in register_materialx_nodes

    prim = Sdf.PrimSpec(layer, name, Sdf.SpecifierDef, "Shader")
    uniform = Sdf.VariabilityUniform

    def attribute(name: str, type_name, value=None, variability=Sdf.VariabilityVarying):
        spec = Sdf.AttributeSpec(prim, name, type_name, variability)
        if value is not None:
            spec.default = value
        return spec

    attribute("info:id", Sdf.ValueTypeNames.Token, nodedef.getName(), uniform)
    attribute("info:implementationSource", Sdf.ValueTypeNames.Token, "sourceAsset", uniform)
    attribute("info:mtlx:sourceAsset", Sdf.ValueTypeNames.Asset,
              Sdf.AssetPath(nodedef.getSourceUri() or os.devnull), uniform)
    for port in nodedef.getActiveInputs():
        usd_type = MATERIALX_TO_USD.get(port.getType(), "token")
        name = port.getName().replace(":", "__")
        attribute(f"inputs:{name}", Sdf.ValueTypeNames.Find(usd_type),
                  variability=uniform if port.getIsUniform() else Sdf.VariabilityVarying)
    for port in nodedef.getActiveOutputs():
        usd_type = MATERIALX_TO_USD.get(port.getType(), "token")
        attribute(f"outputs:{port.getName()}", Sdf.ValueTypeNames.Find(usd_type))
