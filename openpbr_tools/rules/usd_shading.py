"""USD shading structure: what UsdShade itself ignores or refuses, so that a stage loads without a complaint
and still renders another material than the one authored.

- A direct ``material:binding`` (any purpose) must target an active ``Material`` prim:
  ``UsdShade.MaterialBindingAPI`` resolves a binding to a missing prim, an inactive one or a prim of another
  type (a Shader picked in an outliner) to no material, and the geometry renders unbound (OPBR1017).
- A shader's inputs are attributes: ``rel inputs:base_color = <...>`` is a relationship UsdShade does not
  read as an input at all, so the input keeps its default (OPBR1018).
- ``UsdShade.ConnectableAPI.CanConnect`` is the anchor for connections: an input whose connectability is
  ``interfaceOnly`` takes only interface inputs (a Material's or NodeGraph's), and a Material's output only
  sources inside that Material (encapsulation). Hydra does not check either and follows the connection, so
  this is a warning: tools that author through UsdShade refuse to make or keep such a connection, and a
  Material whose output reaches into another Material renders that one's shader while its own is orphaned
  (OPBR1019). A shader's input fed from outside its Material is not reported: OpenUSD's own
  preview-surface tests (testPreviewSurfaceOpacityThreshold.usda) do it and Storm renders them.

A composed layer that authors another ``metersPerUnit`` than the stage keeps its numbers: USD does not
rescale them, and where they are a material's lengths no transform on the referencing prim corrects them
(OPBR1020; a layer of geometry only is no finding).

A binding UsdShade does not read as written: a purpose that is no material purpose (``material:binding:render``,
OPBR1021), a ``bindMaterialAs`` that is no strength (read as weaker than descendants, OPBR1022), a collection
binding whose collection includes only paths to no prim (OPBR1023). A Material whose only surface output is
in a misspelt render context (``outputs:materialx:surface``) is found by no renderer (OPBR1024).

Bindings to a material composed from a MaterialX document that this usd-core cannot open (OPBR1013) are
not judged: with usdMtlx the target would exist.
"""

from __future__ import annotations

from ..diagnostics import Severity
from . import Rule
from .usd import MTLX_REFERENCE, set_aside, under
from .usd_examples import stage_example

_MESH = ('def Mesh "Plane" (\n    prepend apiSchemas = ["MaterialBindingAPI"]\n)\n{\n'
         "    int[] faceVertexCounts = [3]\n    int[] faceVertexIndices = [0, 1, 2]\n"
         "    point3f[] points = [(0, 0, 0), (1, 0, 0), (0, 0, 1)]\n"
         "    rel material:binding = <TARGET>\n}\n\n")
_MATERIAL = ('def Material "M"\n{\n    token outputs:mtlx:surface.connect = </M/S.outputs:out>\n\n'
             '    def Shader "S"\n    {\n        uniform token info:id = "ND_open_pbr_surface_surfaceshader"\n'
             "INPUTS        token outputs:out\n    }\nEXTRA}")
_IMAGE = ('\n    def Shader "albedo"\n    {\n        uniform token info:id = "ND_image_color3"\n'
          '        asset inputs:file = @albedo.png@\n        color3f outputs:out\n    }\n')

def _stage(target: str = "/M", inputs: str = "", extra: str = "") -> str:
    return stage_example(_MESH.replace("TARGET", target) + _MATERIAL.replace("INPUTS", inputs).replace("EXTRA", extra),
                         metadata='defaultPrim = "M"\n    metersPerUnit = 1\n    upAxis = "Y"')


def _collection(includes: str) -> str:
    """The example stage with the mesh bound through a collection (on the mesh, CollectionAPI applied) of ``includes``."""
    return _stage().replace('["MaterialBindingAPI"]', '["MaterialBindingAPI", "CollectionAPI:c"]', 1).replace(
        "rel material:binding = </M>", 'uniform token collection:c:expansionRule = "expandPrims"\n'
        f"    rel collection:c:includes = {includes}\n"
        "    rel material:binding:collection:c = [</Plane.collection:c>, </M>]", 1)


BINDING_TARGET = Rule(
    "OPBR1017", "usd-binding-target-invalid", Severity.ERROR,
    "A direct material binding targets a prim that does not exist, is inactive, is not a Material (a "
    "Shader, a Scope), is a Material only ever authored as an 'over' (never defined), or is abstract (a class).",
    "UsdShade.MaterialBindingAPI resolves such a binding to no material, so the geometry renders with the "
    "renderer's fallback; nothing fails to load. Typical of a Material renamed or deactivated after binding, a "
    "variant naming a material that was never added, or a Shader picked instead of its Material. An 'over' that "
    "no layer defines is resolved by ComputeBoundMaterial but is no defined prim: stage traversal, and so Hydra "
    "and every renderer, skip it (an override whose layer with the 'def' was left out).",
    passing=_stage(), failing=_stage(target="/M/S"),
    passing_name="example.usda", failing_name="example.usda", formats=("usd",),
)

INPUT_RELATIONSHIP = Rule(
    "OPBR1018", "usd-input-is-relationship", Severity.ERROR,
    "A shader or node graph authors an input as a relationship (rel inputs:name = <...>) instead of an "
    "attribute connection (type inputs:name.connect = <...>).",
    "A UsdShade input is an attribute; a relationship of the same name is no input, so the value it "
    "points to is never connected and the input renders its default.",
    passing=_stage(inputs="        color3f inputs:base_color.connect = </M/albedo.outputs:out>\n", extra=_IMAGE),
    failing=_stage(inputs="        rel inputs:base_color = </M/albedo.outputs:out>\n", extra=_IMAGE),
    passing_name="example.usda", failing_name="example.usda", formats=("usd",),
    example_files=("albedo.png",),
)

CONNECTION_REFUSED = Rule(
    "OPBR1019", "usd-connection-refused", Severity.WARNING,
    "A connection UsdShade's ConnectableAPI.CanConnect refuses: an input whose connectability is "
    "interfaceOnly fed by a node's output, or a Material's output fed from a shader outside that Material.",
    "UsdShade's connectability and encapsulation rules: an interfaceOnly input takes only interface "
    "inputs, and a Material's outputs only sources inside it. Hydra does not check them and follows the "
    "connection, so the stage renders; but tools authoring through UsdShade refuse it, and a Material "
    "whose output reaches into another (a duplicate still wired to its original) renders that one's shader.",
    passing=_stage(inputs="        color3f inputs:base_color.connect = </M/albedo.outputs:out>\n", extra=_IMAGE),
    failing=_stage(inputs='        color3f inputs:base_color (\n            connectability = "interfaceOnly"\n'
                          "        )\n        color3f inputs:base_color.connect = </M/albedo.outputs:out>\n",
                   extra=_IMAGE),
    passing_name="example.usda", failing_name="example.usda", formats=("usd",),
    example_files=("albedo.png",),
)

LAYER_UNITS = Rule(
    "OPBR1020", "usd-layer-units-differ", Severity.WARNING,
    "A layer the stage composes (a reference, payload or sublayer) authors another metersPerUnit than the stage, "
    "and a material length (a transmission depth, a subsurface radius).",
    "USD does not rescale what it composes (UsdGeom's metersPerUnit is stage metadata, read from the root layer "
    "only): a transmission depth of 2.5 authored in a metre layer is read as 2.5 centimetres in a centimetre "
    "stage. An assembler corrects the layer's geometry with a scale on the referencing prim (OpenUSD's linear-units "
    "guidance, NVIDIA's asset requirement UN.004), which is no finding; no transform corrects a material's "
    "lengths. Convert them, or author the layer's unit to match.",
    passing=_stage(inputs="        float inputs:transmission_depth = 2.5\n"),
    failing=_stage().replace("    metersPerUnit = 1\n", "    metersPerUnit = 1\n    subLayers = [@looks.usda@]\n", 1),
    passing_name="example.usda", failing_name="example.usda", formats=("usd",),
    failing_files=(("looks.usda", b'#usda 1.0\n(\n    metersPerUnit = 0.01\n)\nover "M"\n{\n    over "S"\n    {\n'
                                  b'        float inputs:transmission_depth = 2.5\n    }\n}\n'),), example_files=("looks.usda",),
)

BINDING_PURPOSE = Rule(
    "OPBR1021", "usd-binding-purpose-unknown", Severity.ERROR,
    "A material binding names a purpose that is no material purpose (material:binding:render, :proxy): "
    "UsdShade's purposes are all-purpose (material:binding), preview and full.",
    "UsdShade.MaterialBindingAPI computes bindings for the purpose a renderer asks for (Storm: preview; final "
    "renderers: full; either falls back to the all-purpose binding). render and proxy are geometry purposes "
    "(UsdGeom's purpose attribute), so material:binding:render is read by no renderer and the geometry keeps "
    "whatever else is bound, or renders unbound.",
    passing=_stage(), failing=_stage().replace("rel material:binding =", "rel material:binding:render =", 1),
    passing_name="example.usda", failing_name="example.usda", formats=("usd",),
)

BINDING_STRENGTH = Rule(
    "OPBR1022", "usd-binding-strength-invalid", Severity.WARNING,
    "A material binding's bindMaterialAs is not one of UsdShade's strengths (weakerThanDescendants, "
    "strongerThanDescendants).",
    "UsdShade reads any other token as the fallback, weakerThanDescendants: an override meant to win over the "
    "descendants' own bindings (a whole-asset look, a review material) silently loses to them.",
    passing=_stage(), failing=_stage().replace("rel material:binding = </M>", 'rel material:binding = </M> (\n'
                                               '        bindMaterialAs = "strongest"\n    )', 1),
    passing_name="example.usda", failing_name="example.usda", formats=("usd",),
)

COLLECTION_EMPTY = Rule(
    "OPBR1023", "usd-binding-collection-matches-nothing", Severity.WARNING,
    "A collection-based material binding's collection includes only paths that name no prim (under scopes the "
    "stage holds).",
    "Usd.CollectionAPI matches prims by path: after the geometry is renamed or moved, a collection still "
    "listing the old paths matches nothing, so the binding binds nothing and the geometry renders with "
    "whatever else is bound, or unbound. Nothing fails to load. A look layer whose geometry is composed in later "
    "(the included paths' parent prims are not on the stage either, as in OpenUSD's usdMtlx baselines) is no finding.",
    passing=_collection("</Plane>"), failing=_collection("</Plane_old>"),
    passing_name="example.usda", failing_name="example.usda", formats=("usd",),
)

_PLANKS = """#usda 1.0
(
    defaultPrim = "Deck"
    metersPerUnit = 1
    upAxis = "Y"
)
def Xform "Deck" (
    prepend apiSchemas = ["MaterialBindingAPI", "CollectionAPI:planks"]
)
{
    uniform token collection:planks:expansionRule = "explicitOnly"
    rel collection:planks:includes = INCLUDES
    rel material:binding:collection:planks = [</Deck.collection:planks>, </Deck/Oak>]
    def Material "Oak"
    {
    }
    def Mesh "Plank"
    {
        int[] faceVertexCounts = [3]
        int[] faceVertexIndices = [0, 1, 2]
        point3f[] points = [(0, 0, 0), (1, 0, 0), (1, 1, 0)]
    }
}
"""
COLLECTION_NO_GEOMETRY = Rule(
    "OPBR1026", "usd-binding-collection-binds-no-geometry", Severity.ERROR,
    "A collection-based material binding's collection includes prims, but no geometry (no Gprim, no GeomSubset): an "
    "explicitOnly collection that lists the parent Xform of the meshes meant, which it then leaves out.",
    "Usd.CollectionAPI with expansionRule explicitOnly includes exactly the listed prims, not their descendants, and "
    "UsdShade.MaterialBindingAPI binds a collection's material only to the prims the collection includes: listing "
    "the group instead of its meshes binds nothing that renders (ComputeBoundMaterial on the meshes finds nothing "
    "through it). With expandPrims (the default) the same list would include the meshes. A collection of GeomSubsets "
    "binds their faces (ComputeBoundMaterial on the subset finds the material) and is no finding.",
    passing=_PLANKS.replace("INCLUDES", "</Deck/Plank>"), failing=_PLANKS.replace("INCLUDES", "</Deck>"),
    passing_name="example.usda", failing_name="example.usda", formats=("usd",),
)

_BOLTS = """#usda 1.0
(
    defaultPrim = "Asset"
    metersPerUnit = 1
    upAxis = "Y"
)
def Xform "Asset"
{
    def Material "Steel"
    {
    }
    def Material "Gold"
    {
    }
    def Xform "Proto"
    {
        def Mesh "Geo" (
            prepend apiSchemas = ["MaterialBindingAPI"]
        )
        {
            int[] faceVertexCounts = [3]
            int[] faceVertexIndices = [0, 1, 2]
            point3f[] points = [(0, 0, 0), (1, 0, 0), (1, 1, 0)]
            rel material:binding = </Asset/Steel>
        }
    }
    def "Bolt" (
        instanceable = INSTANCEABLE
        prepend references = </Asset/Proto>
    )
    {
        over "Geo" (
            prepend apiSchemas = ["MaterialBindingAPI"]
        )
        {
            rel material:binding = </Asset/Gold>
        }
    }
}
"""
INSTANCE_OVERRIDE = Rule(
    "OPBR1027", "usd-override-inside-instance", Severity.WARNING,
    "A layer authors opinions below an instanceable prim (a material binding override on one instance's mesh).",
    "An instance shares its prototype's subtree: usd-core composes the prims below an instanceable prim from the "
    "prototype only and ignores the stage's opinions there, so the override does nothing (ComputeBoundMaterial "
    "on the instance's mesh still finds the prototype's material). Bind on the instance prim itself, make that "
    "one prim not instanceable, or override through a variant of the prototype.",
    passing=_BOLTS.replace("INSTANCEABLE", "false"), failing=_BOLTS.replace("INSTANCEABLE", "true"),
    passing_name="example.usda", failing_name="example.usda", formats=("usd",),
)

_PREVIEW_AS_MTLX = ('def Material "M"\n{\n    token outputs:OUTPUT.connect = </M/P.outputs:surface>\n\n'
                    '    def Shader "P"\n    {\n        uniform token info:id = "UsdPreviewSurface"\n'
                    '        color3f inputs:diffuseColor = (0.5, 0.4, 0.3)\n        token outputs:surface\n    }\n}\n')
PREVIEW_IN_MTLX_CONTEXT = Rule(
    "OPBR1029", "usd-preview-in-materialx-context", Severity.WARNING,
    "A Material's MaterialX surface output (outputs:mtlx:surface) is fed by a UsdPreviewSurface shader (info:id "
    "UsdPreviewSurface), the glslfx node, not a MaterialX node definition.",
    "Renderers that read the mtlx render context look the node up among MaterialX's node definitions, where the "
    "preview surface is ND_UsdPreviewSurface_surfaceshader: an id of UsdPreviewSurface names none, so a "
    "MaterialX-only renderer finds no surface. Storm, which also knows the glslfx node, can hide the mistake. Wire "
    "the preview to the universal outputs:surface, or give the shader the MaterialX id.",
    passing=stage_example(_PREVIEW_AS_MTLX.replace("OUTPUT", "surface"), metadata='defaultPrim = "M"\n    metersPerUnit = 1\n    upAxis = "Y"'),
    failing=stage_example(_PREVIEW_AS_MTLX.replace("OUTPUT", "mtlx:surface"), metadata='defaultPrim = "M"\n    metersPerUnit = 1\n    upAxis = "Y"'),
    passing_name="example.usda", failing_name="example.usda", formats=("usd",),
)

RENDER_CONTEXT = Rule(
    "OPBR1024", "usd-render-context-misspelt", Severity.ERROR,
    "A Material's surface output is only in a render context no renderer reads under that name "
    "(outputs:materialx:surface where MaterialX's context is mtlx), with no universal outputs:surface.",
    "UsdShade.Material.ComputeSurfaceSource looks up outputs:<context>:surface for the renderer's own context "
    "(mtlx for MaterialX, glslfx for Storm, ri for RenderMan) and then the universal outputs:surface: a misspelt "
    "context matches neither, so no renderer finds the surface and the geometry renders with the fallback.",
    passing=_stage(), failing=_stage().replace("outputs:mtlx:surface", "outputs:materialx:surface", 1),
    passing_name="example.usda", failing_name="example.usda", formats=("usd",),
)

RULES = (BINDING_TARGET, INPUT_RELATIONSHIP, CONNECTION_REFUSED, LAYER_UNITS, BINDING_PURPOSE, BINDING_STRENGTH,
         COLLECTION_EMPTY, COLLECTION_NO_GEOMETRY, INSTANCE_OVERRIDE, PREVIEW_IN_MTLX_CONTEXT, RENDER_CONTEXT)


def check(asset, context):
    """Runs on USD assets only (rules.FAMILY_FORMATS)."""
    composed_elsewhere = set_aside(asset)
    unchecked: dict[str, list] = {}  # MaterialX document -> bindings to materials it would compose
    yield from _observed(asset, context, composed_elsewhere, unchecked)
    for document, bindings in unchecked.items():  # one note per document, at its first binding
        first = bindings[0].detail
        others = f" and {len(bindings) - 1} more binding{'s' if len(bindings) > 2 else ''}" if len(bindings) > 1 else ""
        yield context.diagnostic(
            MTLX_REFERENCE, f"{first['relationship']} targets <{first['target']}>{others}, which the MaterialX document "
            f"@{document}@ would compose: {'they' if others else 'it'} cannot be checked without the usdMtlx plugin",
            bindings[0].location,
            hint="validate the .mtlx file itself: openpbr validate reads MaterialX")


def _observed(asset, context, composed_elsewhere, unchecked):
    for observation in asset.observations:
        detail, where = observation.detail, observation.location
        if observation.kind == "usd_binding_invalid":
            if detail.get("mtlx_document"):  # a reference to the document sits behind the missing target's parent
                unchecked.setdefault(detail["mtlx_document"], []).append(observation)
                continue
            if detail.get("outside_layer"):  # a layer in a shared folder, not opened (OPBR1039 says so), would
                continue                    # compose it
            if under(detail["target"], composed_elsewhere):
                continue  # with usdMtlx the MaterialX document would provide it
            yield context.diagnostic(
                BINDING_TARGET, f"{detail['relationship']} targets <{detail['target']}>, which {detail['reason']}: "
                "the prim renders unbound", where,
                hint="bind the Material prim itself" if "not a Material" in detail["reason"]
                else "bind an existing, active Material")
        elif observation.kind == "usd_binding_purpose":
            yield context.diagnostic(
                BINDING_PURPOSE, f"{detail['relationship']}: {detail['purpose']!r} is no material purpose (UsdShade's "
                "are all-purpose, preview and full; render and proxy are geometry purposes), so no renderer reads "
                "this binding", where, hint="bind with material:binding (all purposes), material:binding:preview or "
                                            "material:binding:full")
        elif observation.kind == "usd_binding_strength":
            yield context.diagnostic(
                BINDING_STRENGTH, f"{detail['relationship']} has bindMaterialAs = {detail['strength']!r}, which is no "
                "binding strength: UsdShade reads it as weakerThanDescendants, so the descendants' own bindings win",
                where, hint="use \"strongerThanDescendants\" (or \"weakerThanDescendants\")")
        elif observation.kind == "usd_collection_empty":
            missing = ", ".join(f"<{m}>" for m in detail["missing"][:4])
            yield context.diagnostic(
                COLLECTION_EMPTY, f"{detail['relationship']} binds through {detail['collection']}, whose includes "
                f"({missing}) name no prim: the collection matches nothing and binds nothing", where,
                hint="include the geometry's current paths")
        elif observation.kind == "usd_collection_no_geometry":
            listed = ", ".join(f"<{m}>" for m in detail["includes"][:4])
            yield context.diagnostic(
                COLLECTION_NO_GEOMETRY, f"{detail['relationship']} binds through {detail['collection']}, which "
                f"({detail['rule']}) includes {listed} but no geometry: the binding reaches nothing that renders", where,
                hint="include the meshes themselves, or set the collection's expansionRule to expandPrims")
        elif observation.kind == "usd_instance_override":
            ignored = ", ".join(f"<{m}>" for m in detail["ignored"][:4])
            yield context.diagnostic(
                INSTANCE_OVERRIDE, f"{detail['instance']} is instanceable, so usd-core ignores what this stage authors "
                f"below it ({ignored}): the override does nothing", where,
                hint="author it on the instance prim, or make this prim not instanceable")
        elif observation.kind == "usd_preview_in_mtlx_context":
            yield context.diagnostic(
                PREVIEW_IN_MTLX_CONTEXT, f"{detail['shader']} (info:id {detail['id']}) feeds the MaterialX surface "
                "output: MaterialX names that node ND_UsdPreviewSurface_surfaceshader, so a MaterialX-only renderer "
                "finds no surface", where,
                hint="connect it to outputs:surface instead, or set info:id = \"ND_UsdPreviewSurface_surfaceshader\"")
        elif observation.kind == "usd_render_context":
            yield context.diagnostic(
                RENDER_CONTEXT, f"the Material's only surface output is {detail['output']}: no renderer reads the "
                f"context {detail['context']!r}, so none finds the surface (meant: {detail['meant']!r}?)", where,
                hint=f"rename it outputs:{detail['meant']}:surface")
        elif observation.kind == "usd_input_relationship":
            targets = ", ".join(f"<{t}>" for t in detail["targets"]) or "nothing"
            yield context.diagnostic(
                INPUT_RELATIONSHIP, f"{detail['input']} is a relationship (to {targets}), not an input: it is never "
                "connected and the input renders its default", where,
                hint=f"author it as an attribute connection: <type> {detail['input']}.connect = <...>")
        elif observation.kind == "usd_layer_units":
            ratio = detail["layer_unit"] / detail["stage_unit"]
            size = f"{ratio:g}x too short" if ratio > 1 else f"{1 / ratio:g}x too long"
            yield context.diagnostic(
                LAYER_UNITS, f"{detail['attribute']} is authored in {detail['layer']}, whose metersPerUnit is "
                f"{detail['layer_unit']:g} where the stage's is {detail['stage_unit']:g}: USD does not rescale it, and "
                f"no transform corrects a material's length, so it is read {size}", where,
                hint="convert the layer's lengths to the stage's unit, or author the same metersPerUnit")
        elif observation.kind == "usd_connection_refused":
            if detail["interface_only"] and detail.get("source_is_interface"):
                why = ("its connectability is interfaceOnly, and an interfaceOnly input takes only an interface input "
                       "that is interfaceOnly itself")
                hint = "mark the interface input interfaceOnly too (or the shader input fully connectable)"
            elif detail["interface_only"]:
                why = "its connectability is interfaceOnly, so only a Material's or NodeGraph's interface input may feed it"
                hint = "connect the input through the Material's interface"
            elif detail.get("source_inside"):
                why = ("the source is not a shader or node graph directly inside the Material (UsdShade's "
                       "encapsulation: a Material's outputs connect to its children)")
                hint = "move the shader directly under the Material, or connect through a NodeGraph"
            else:
                why = "the source is outside the Material (UsdShade's encapsulation)"
                hint = "connect a shader inside the Material"
            yield context.diagnostic(
                CONNECTION_REFUSED, f"{detail['port']} is connected to {detail['source']}, which UsdShade refuses: {why}",
                where, hint=hint)
