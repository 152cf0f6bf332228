"""What UsdShade and UsdGeom ignore or refuse in a composed stage, observed for the rules (``rules/usd_shading``):
bindings to no active Material, ``inputs:`` relationships, connections ``ConnectableAPI.CanConnect`` refuses,
and composed layers authored in another unit than the stage."""

from __future__ import annotations


def observe_layer_units(stage, observe, location) -> None:
    """A layer the stage composes (a reference, payload or sublayer) that authors another metersPerUnit than
    the stage's: USD does not rescale what it composes, so its lengths (a depth, a radius, points) are read
    in the stage's unit."""
    from pxr import UsdGeom  # lazy: pxr only once the reader has opened a stage

    stage_unit = float(UsdGeom.GetStageMetersPerUnit(stage))
    for layer in stage.GetUsedLayers():
        if layer in (stage.GetRootLayer(), stage.GetSessionLayer()) or layer.anonymous:
            continue
        unit = layer.pseudoRoot.GetInfo("metersPerUnit") if layer.pseudoRoot.HasInfo("metersPerUnit") else None
        if isinstance(unit, (int, float)) and unit > 0 and abs(unit - stage_unit) > 1e-9 * stage_unit:
            observe("usd_layer_units", location("/", "metersPerUnit"), layer=layer.GetDisplayName(),
                    layer_unit=float(unit), stage_unit=stage_unit)


def observe_structure(prim, stage, observe, location) -> None:
    """What UsdShade refuses or ignores in ``prim``'s scene description: a direct material binding
    whose target is no active Material (USD renders the prim unbound), an ``inputs:`` relationship on
    a shading prim (a relationship is no input: the value is never connected), and a connection
    ``UsdShade.ConnectableAPI.CanConnect`` refuses (an interfaceOnly input fed by a node, a Material
    output fed from outside the Material; not a shader input fed across a Material's boundary, which
    OpenUSD's own preview-surface tests do and Storm renders)."""
    from pxr import UsdShade  # lazy: as in observe_layer_units

    for relationship in prim.GetRelationships():
        name = relationship.GetName()
        if name.startswith("material:binding") and ":collection" not in name:
            for target in relationship.GetForwardedTargets():
                bound = stage.GetPrimAtPath(target.GetPrimPath())
                reason = ("does not exist" if not bound else "is inactive" if not bound.IsActive()
                          else None if bound.IsA(UsdShade.Material) else f"is a {bound.GetTypeName() or 'typeless prim'}, "
                          "not a Material")
                if reason is not None:
                    observe("usd_binding_invalid", location(prim.GetPath(), None),
                            relationship=name, target=str(target), reason=reason)
        elif name.startswith("inputs:") and (prim.IsA(UsdShade.Shader) or prim.IsA(UsdShade.NodeGraph)):
            observe("usd_input_relationship", location(prim.GetPath(), name[len("inputs:"):]),
                    input=name, targets=[str(t) for t in relationship.GetTargets()])
    if not (prim.IsA(UsdShade.Shader) or prim.IsA(UsdShade.NodeGraph)):  # (a Material is a NodeGraph)
        return
    connectable = UsdShade.ConnectableAPI(prim)
    for port in list(connectable.GetInputs(onlyAuthored=True)) + list(connectable.GetOutputs(onlyAuthored=True)):
        sources, _ = port.GetConnectedSources()
        for source in sources:
            if source.sourceType == UsdShade.AttributeType.Output:
                origin = source.source.GetOutput(source.sourceName)
            else:
                origin = source.source.GetInput(source.sourceName)
            if origin and not UsdShade.ConnectableAPI.CanConnect(port, origin.GetAttr()):
                side = "input" if UsdShade.Input.IsInput(port.GetAttr()) else "output"
                if side == "input" and port.GetConnectability() != UsdShade.Tokens.interfaceOnly:
                    continue  # a shader's input fed across a Material's boundary: Hydra follows it (OpenUSD's own tests)
                observe("usd_connection_refused", location(prim.GetPath(), port.GetBaseName()),
                        port=str(port.GetAttr().GetPath()), source=str(origin.GetAttr().GetPath()), side=side,
                        interface_only=side == "input" and port.GetConnectability() == UsdShade.Tokens.interfaceOnly)

