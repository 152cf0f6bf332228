"""What UsdShade and UsdGeom ignore or refuse in a composed stage, observed for the rules (``rules/usd_shading``):
bindings to no active Material, ``inputs:`` relationships, connections ``ConnectableAPI.CanConnect`` refuses,
and composed layers authored in another unit than the stage."""

from __future__ import annotations

from functools import lru_cache

from ... import tables
from .attributes import python_value, single_precision


@lru_cache(maxsize=1)
def scene_length_inputs() -> frozenset[str]:
    """``inputs:<name>`` of every shader input in scene units (a transmission depth, a subsurface radius) of the
    models the toolkit reads, in their latest versions."""
    names = set()
    for model in ("open_pbr_surface", "standard_surface", "gltf_pbr", "UsdPreviewSurface"):
        table = tables.table(model)
        names.update(f"inputs:{name}" for name in tables.names(model, tables.latest(model))
                     if table[name].unit == "scene_length")
    return frozenset(names)


def observe_layer_units(stage, observe, location, length_inputs) -> None:
    """A layer the stage composes (a reference, payload or sublayer) that authors another metersPerUnit than
    the stage's and a material length (``length_inputs``: shader inputs in scene units, a transmission depth, a
    subsurface radius): USD does not rescale what it composes, and while an assembler corrects geometry with a
    scale on the referencing prim (OpenUSD's and NVIDIA's recommended layout, no finding), no transform corrects
    a material's lengths, which are read in the stage's unit."""
    from pxr import Sdf, UsdGeom  # lazy: pxr only once the reader has opened a stage

    stage_unit = float(UsdGeom.GetStageMetersPerUnit(stage))
    for layer in stage.GetUsedLayers():
        if layer in (stage.GetRootLayer(), stage.GetSessionLayer()) or layer.anonymous:
            continue
        unit = layer.pseudoRoot.GetInfo("metersPerUnit") if layer.pseudoRoot.HasInfo("metersPerUnit") else None
        if not (isinstance(unit, (int, float)) and unit > 0 and abs(unit - stage_unit) > 1e-9 * stage_unit):
            continue
        found: list[str] = []

        def visit(path, found=found):
            if path.IsPropertyPath() and path.name in length_inputs and not found:
                found.append(str(path))

        layer.Traverse(Sdf.Path.absoluteRootPath, visit)
        if found:
            observe("usd_layer_units", location(found[0].split(".", 1)[0], found[0].split(".", 1)[1].removeprefix("inputs:")),
                    layer=layer.GetDisplayName(), layer_unit=float(unit), stage_unit=stage_unit, attribute=found[0])


def observe_structure(prim, stage, observe, location, set_aside=None) -> bool:
    """What UsdShade refuses or ignores in ``prim``'s scene description: a direct material binding
    whose target is no active (defined, concrete) Material (USD renders the prim unbound), an ``inputs:``
    relationship on a shading prim (a relationship is no input: the value is never connected), a connection
    ``UsdShade.ConnectableAPI.CanConnect`` refuses (an interfaceOnly input fed by a node, a Material
    output fed from outside the Material; not a shader input fed across a Material's boundary, which
    OpenUSD's own preview-surface tests do and Storm renders), opinions below an instance, and a variant
    selection that names no variant. Returns whether the prim has a material binding with a target (convert
    notes the bindings an output does not hold). ``set_aside`` maps (layer identifier, prim spec path) of each
    reference or payload to a MaterialX document the guard deleted to the document's path: a binding target
    missing below such a prim is one the document would compose (usdMtlx), noted with it."""
    from pxr import UsdShade  # lazy: as in observe_layer_units

    if prim.IsInstance():
        _observe_instance_overrides(prim, stage, observe, location)
    if prim.HasVariantSets():
        variant_sets = prim.GetVariantSets()
        for set_name in variant_sets.GetNames():
            variant_set = variant_sets.GetVariantSet(set_name)
            selection, names = variant_set.GetVariantSelection(), variant_set.GetVariantNames()
            if selection and names and selection not in names:  # usd-core composes none of the set's variants
                meant = next((n for n in names if n.lower() == selection.lower()), None)
                observe("dangling_reference", location(prim.GetPath(), None), attribute=f"variant selection {set_name}",
                        target=selection, ends=f"names no variant of the set ({', '.join(names)}): none of them applies"
                        + (f" (variant names are case-sensitive: {meant!r}?)" if meant else ""))
    bound = False
    for relationship in prim.GetRelationships():
        name = relationship.GetName()
        if name.startswith("material:binding"):
            _observe_binding_form(prim, relationship, name, stage, observe, location)
            targets = relationship.GetTargets()
            bound = bound or bool(targets)
            if ":collection:" in name:  # (the collection, the Material)
                targets = targets[1:2] if len(targets) == 2 else []
            for target in targets:
                bound = stage.GetPrimAtPath(target.GetPrimPath())
                reason = ("is a property, not a Material prim" if target.IsPropertyPath() else
                          "does not exist" if not bound else "is inactive" if not bound.IsActive()
                          else "is only an 'over' of a Material, never defined (def): stage traversal and renderers "
                               "skip it" if not bound.IsDefined()
                          else "is abstract (a class, or under one): stage traversal and renderers skip it"
                          if bound.IsAbstract()
                          else None if bound.IsA(UsdShade.Material) else f"is a {bound.GetTypeName() or 'typeless prim'}, "
                          "not a Material")
                if reason is not None:
                    kind, document = (_composed_from_materialx(stage, target, set_aside) if not bound else None) \
                        or (None, None)
                    observe("usd_binding_invalid", location(prim.GetPath(), None), relationship=name, target=str(target),
                            reason=reason, mtlx_document=document if kind == "usd_mtlx_reference" else None,
                            outside_layer=document if kind == "usd_arc_outside" else None)
        elif name.startswith("inputs:") and (prim.IsA(UsdShade.Shader) or prim.IsA(UsdShade.NodeGraph)):
            observe("usd_input_relationship", location(prim.GetPath(), name[len("inputs:"):]),
                    input=name, targets=[str(t) for t in relationship.GetTargets()])
    if prim.IsA(UsdShade.Material):
        _observe_render_contexts(prim, observe, location)
    if prim.IsA(UsdShade.Shader) or prim.IsA(UsdShade.NodeGraph):  # (a Material is a NodeGraph)
        _observe_connections(prim, observe, location)
    return bound


def _composed_from_materialx(stage, target, set_aside) -> tuple[str, str] | None:
    """The MaterialX document (set aside: this usd-core has no usdMtlx plugin) that would compose the missing
    prim ``target``: the one referenced by a prim spec in the nearest existing ancestor's prim stack, wherever
    composition placed that spec (usd-wg's OpenChessSet references Bishop_look.usd's /Bishop, whose Materials
    reference Bishop_mat.mtlx, as /ChessSet/Black/BishopL). ``None`` when no such arc is behind it."""
    if not set_aside:
        return None
    ancestor = stage.GetPrimAtPath(target.GetPrimPath().GetParentPath())
    path = target.GetPrimPath().GetParentPath()
    while not ancestor and path.pathElementCount > 1:
        path = path.GetParentPath()
        ancestor = stage.GetPrimAtPath(path)
    if not ancestor:
        return None
    for spec in ancestor.GetPrimStack():
        found = set_aside.get((spec.layer.identifier, str(spec.path)))
        if found is not None:
            return found  # (the observation kind that set it aside, the arc's asset path)
    return None


def _observe_connections(prim, observe, location) -> None:
    from pxr import UsdShade  # lazy: as in observe_layer_units

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
                source_prim = origin.GetAttr().GetPrim()
                observe("usd_connection_refused", location(prim.GetPath(), port.GetBaseName()),
                        port=str(port.GetAttr().GetPath()), source=str(origin.GetAttr().GetPath()), side=side,
                        interface_only=side == "input" and port.GetConnectability() == UsdShade.Tokens.interfaceOnly,
                        source_is_interface=UsdShade.Input.IsInput(origin.GetAttr()),
                        source_inside=str(source_prim.GetPath()).startswith(f"{prim.GetPath()}/"))


#: UsdShade's material purposes besides allPurpose (UsdShadeTokens: preview, full)
MATERIAL_PURPOSES = ("preview", "full")
#: bindMaterialAs tokens (UsdShadeTokens: weakerThanDescendants, strongerThanDescendants; "" is the fallback)
BINDING_STRENGTHS = ("", "weakerThanDescendants", "strongerThanDescendants", "fallbackStrength")


def _observe_binding_form(prim, relationship, name, stage, observe, location) -> None:
    """A binding UsdShade.MaterialBindingAPI never reads as written: a purpose that is no material purpose
    (``material:binding:render``: a geometry purpose), or a ``bindMaterialAs`` that is no strength token
    (read as the fallback, weaker than descendants); a collection binding whose collection includes only
    paths that name no prim (the collection matches nothing)."""
    parts = name.split(":")[2:]  # material:binding[:purpose][:collection:name]
    if parts and parts[0] != "collection" and parts[0] not in MATERIAL_PURPOSES:
        observe("usd_binding_purpose", location(prim.GetPath(), None), relationship=name, purpose=parts[0])
    strength = relationship.GetMetadata("bindMaterialAs")
    if strength is not None and str(strength) not in BINDING_STRENGTHS:
        observe("usd_binding_strength", location(prim.GetPath(), None), relationship=name, strength=str(strength))
    if "collection" in parts:
        targets = relationship.GetTargets()
        if targets and targets[0].IsPropertyPath():
            _observe_collection(targets[0], name, stage, observe, location(prim.GetPath(), None))


def _observe_instance_overrides(prim, stage, observe, location) -> None:
    """Opinions a layer of the stage's own layer stack authors under an instance (below the instanceable prim):
    the instance shares its prototype's subtree, so usd-core ignores them (a material:binding override on one
    instance's mesh does nothing). The instance prim's own properties are kept and not reported."""
    path = prim.GetPath()
    ignored = []
    for layer in stage.GetLayerStack(includeSessionLayers=False):
        spec = layer.GetPrimAtPath(path)
        if spec is None:
            continue
        for child in spec.nameChildren:
            ignored.append(str(child.path))
    if ignored:
        observe("usd_instance_override", location(path, None), instance=str(path), ignored=sorted(set(ignored)))


def _observe_collection(path, binding, stage, observe, where) -> None:
    from pxr import Usd  # lazy: as in observe_layer_units

    owner = stage.GetPrimAtPath(path.GetPrimPath())
    if not owner:
        return  # a missing collection owner is the binding-target check's concern
    collection = Usd.CollectionAPI(owner, path.name.split(":", 1)[1] if ":" in path.name else path.name)
    includes = collection.GetIncludesRel().GetTargets() if collection.GetIncludesRel() else []
    if not includes or collection.GetIncludeRootAttr().Get():
        return
    missing = [str(p) for p in includes if not stage.GetPrimAtPath(p.GetPrimPath())]
    # only where the included prims' parents are on the stage: a look layer whose geometry is composed in
    # later names prims under scopes it does not hold itself (OpenUSD's usdMtlx test baselines do)
    present = all(stage.GetPrimAtPath(p.GetPrimPath().GetParentPath()) for p in includes)
    if len(missing) == len(includes) and present:
        observe("usd_collection_empty", where, relationship=binding, collection=str(path), missing=missing)
    elif not missing:
        from pxr import UsdGeom  # lazy: as above

        included = Usd.CollectionAPI.ComputeIncludedPaths(collection.ComputeMembershipQuery(), stage)
        # a GeomSubset is geometry too: ComputeBoundMaterial binds a collection's material to a subset it includes
        if not any(stage.GetPrimAtPath(p).IsA(UsdGeom.Gprim) or stage.GetPrimAtPath(p).IsA(UsdGeom.Subset)
                   for p in included[:100_000]):
            observe("usd_collection_no_geometry", where, relationship=binding, collection=str(path),
                    includes=[str(p) for p in includes], rule=str(collection.GetExpansionRuleAttr().Get() or "expandPrims"))


#: render contexts of Material outputs, as their renderers name them ("" is the universal output)
KNOWN_CONTEXTS = ("mtlx", "glslfx", "ri", "arnold", "nsi", "karma", "cycles", "vray", "redshift", "omni", "mdl",
                  "osl", "prman", "riCpp")
#: names that mean a known context but no renderer reads (MaterialX's is "mtlx")
MISSPELT_CONTEXTS = {"materialx": "mtlx", "material_x": "mtlx", "mx": "mtlx", "mtl": "mtlx", "usdmtlx": "mtlx",
                     "glsl": "glslfx", "glslfx2": "glslfx", "renderman": "ri"}


def _observe_render_contexts(material, observe, location) -> None:
    """A Material whose surface output is only in a render context no renderer reads under that name
    (``outputs:materialx:surface`` for ``outputs:mtlx:surface``): UsdShade.Material.ComputeSurfaceSource
    finds no surface for any renderer."""
    from pxr import UsdShade  # lazy: as in observe_layer_units

    outputs = [o.GetBaseName() for o in UsdShade.Material(material).GetOutputs(onlyAuthored=True)]
    surfaces = [n for n in outputs if n == "surface" or n.endswith(":surface")]
    if not surfaces or "surface" in surfaces:
        return
    contexts = [n[: -len(":surface")] for n in surfaces]
    if any(c in KNOWN_CONTEXTS for c in contexts):
        return
    for context in contexts:
        meant = MISSPELT_CONTEXTS.get(context.lower()) or next(
            (k for k in KNOWN_CONTEXTS if k.lower() == context.lower()), None)
        if meant is not None:
            observe("usd_render_context", location(material.GetPath(), None), output=f"outputs:{context}:surface",
                    context=context, meant=meant)


def observe_variant_values(stage, observe, location, shader_ids) -> None:
    """Values a shader input takes in a variant that is not selected (a finish the user can switch to): the
    composed stage shows only the selected one, so each layer's variant specs are read as authored, for shaders
    of a model the toolkit reads (``shader_ids``: id -> (model, ...)), and observed as the input's other values."""
    from pxr import Sdf  # lazy: pxr only once the reader has opened a stage

    found: dict[tuple[str, str], list] = {}
    for layer in stage.GetUsedLayers():
        if layer.anonymous:
            continue
        paths: list = []
        layer.Traverse(Sdf.Path.absoluteRootPath, lambda path: paths.append(path) if path.IsPropertyPath()
                       and path.ContainsPrimVariantSelection() and path.name.startswith("inputs:") else None)
        for path in paths[:MAX_VARIANT_VALUES]:
            spec = layer.GetAttributeAtPath(path)
            if spec is None or not spec.HasDefaultValue():
                continue
            selection = _selection_of(path)
            if selection is None:
                continue
            variant_set, variant = selection.GetVariantSelection()
            owner = stage.GetPrimAtPath(selection.GetParentPath().StripAllVariantSelections())
            if owner and owner.GetVariantSets().HasVariantSet(variant_set) and \
                    owner.GetVariantSet(variant_set).GetVariantSelection() == variant:
                continue  # the selected variant: its value is the composed one, read with the material
            prim = stage.GetPrimAtPath(path.GetPrimPath().StripAllVariantSelections())
            known = shader_ids.get(str(prim.GetAttribute("info:id").Get() or "")) if prim else None
            if known is None:
                continue
            key = (str(prim.GetPath()), path.name[len("inputs:"):])
            found.setdefault(key, [known[0]]).append((f"in variant {variant_set}={variant} (not selected)",
                                                      python_value(spec.default, single_precision(spec.typeName))))
    for (prim_path, name), (model, *values) in found.items():
        observe("usd_other_values", location(prim_path, name), input=name, model=model, values=values)


MAX_VARIANT_VALUES = 10000  # attribute specs under variants read per layer


def _selection_of(path):
    """The innermost variant selection path ``path`` lies under (``/M{finish=gloss}``), or None."""
    prim = path.GetPrimPath()
    while not prim.IsPrimVariantSelectionPath():
        if not prim.ContainsPrimVariantSelection() or prim.IsAbsoluteRootPath():
            return None
        prim = prim.GetParentPath()
    return prim
