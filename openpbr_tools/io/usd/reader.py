"""Read the materials of a USD stage (``.usda``, ``.usdc``, ``.usd``, ``.usdz``) into an
:class:`~openpbr_tools.model.Asset`.

usd-core has no MaterialX plug-in, so the prims are read here. The stage is opened with composition resolved
(sublayers, references, payloads loaded, variants as selected) by :class:`~.guard.StageGuard`, which refuses files
that would crash usd-core and never opens a layer outside the asset's folder (such arcs are reported,
``usd_arc_outside``); every ``Material`` prim is visited and each of its surface outputs (``outputs:surface``,
``outputs:mtlx:surface``, ``outputs:<context>:surface``) is followed, through node graphs, to a shader (a shader two
Materials share is a material of each). Shaders with the id of a model the toolkit knows become
:class:`~openpbr_tools.model.Material` objects: OpenPBR (``ND_open_pbr_surface_surfaceshader`` and versioned ids),
Standard Surface, glTF PBR and UsdPreviewSurface (USD's ``UsdPreviewSurface`` and MaterialX's
``ND_UsdPreviewSurface_surfaceshader``).

Each shader input becomes an :class:`~openpbr_tools.model.Input`:

* ``type`` is the MaterialX type its USD type reads as (``color3f`` -> ``color3``, ``float3`` ->
  ``vector3``; a ``float3`` where the parameter is a ``color3`` reads as ``color3`` so its values are
  still checked, and OPBR1002 reports the role), ``source_type`` the USD type;
* the value (followed by :mod:`.network`) is a :class:`Constant`, read through Material and
  NodeGraph interface inputs (``interface_name`` remembers which); a
  :class:`Texture` for MaterialX image chains (``ND_image_*``/``ND_tiledimage_*`` through
  ``extract``, ``separate``, ``convert``, ``normalmap``, and ``multiply``/``add`` by a constant as
  scale and bias, with ``place2d``/``texcoord``/``geompropvalue`` on the coordinates) and for
  ``UsdUVTexture`` (output channel, ``sourceColorSpace``, scale/bias, wrap, fallback,
  ``UsdTransform2d`` and the primvar reader's name); a :class:`Connection` otherwise (``dangling``
  when the target does not exist); ``None`` for an input declared without a value (UsdMtlx's
  interface inputs look like that);
* ``authored_colorspace`` is the attribute's ``colorSpace`` metadata, ``colorspace`` that or the nearest
  ``Usd.ColorSpaceAPI`` ancestor's name. ``Material.colorspace`` is the Material prim's ColorSpaceAPI space under its
  MaterialX name (``lin_ap1_scene`` -> ``acescg``) so colour maths elsewhere can use it; ``Asset.colorspace`` is the
  default prim's, as authored.

The version: a versioned id (``..._surfaceshader_05``) or the writer's ``customData`` (``openpbr:version``); an
unversioned id only says "whatever was current", so it is inferred from the input names as for MaterialX.
``Asset.meters_per_unit`` is ``None`` when the stage does not author ``metersPerUnit`` (USD then means 0.01).

One module because it is one pass over the stage: the Material, surface-output, shader and input readers share the
stage, the render contexts marked and the observations made on the way.

A :class:`Location` is the prim path plus the attribute name (USD has no reliable line numbers). Facts the USD rules
judge are observations (``usd_*``); usd-core's validators' findings: ``asset.extra["usd_core_findings"]``.
"""

from __future__ import annotations

import copy
import os

from ... import colorspaces, gltf_state, tables, versioning
from ...model import Asset, Constant, Input, Location, Material
from ...resources import load_json
from .. import ReadError
from .network import MAX_DEPTH, NetworkReader
from .observations import observe_layer_units, observe_structure, observe_variant_values, scene_length_inputs
from .primvars import observe_textured_uvs, primvar_problem, primvar_type_problem
from .errors import quiet, tf_error_text, usd_error_message
from .guard import StageGuard
from ..mtlx.library import declared_enum
from .sdr import materialx_nodedef
from .validators import usd_core_findings
from .types import (
    MATERIALX_CONTEXT,
    UNIVERSAL_CONTEXTS,
    OPACITY_MODE_TOKENS,
    materialx_type_of,
    surface_shader_ids,
)

CUSTOM_DATA_VERSION_KEY = "openpbr:version"


def read_usd(path: str, *, usd_core: bool = True, allow_outside=()) -> Asset:
    """Read the stage at ``path``. ``usd_core=False`` skips usd-core's own validators;
    ``allow_outside`` lists folders besides the asset's own that sublayers, references and payloads
    may be read from (:class:`~.guard.StageGuard`)."""
    asset = Asset(path=path, format="usd")
    guard = StageGuard(path, asset.observe, allow_outside)
    _read_stage(asset, guard.open_stage(), guard, usd_core)
    return asset


def _read_stage(asset: Asset, stage, guard: StageGuard, usd_core: bool) -> None:
    from pxr import Tf  # lazy: pxr (0.1-0.2 s) only once the guard has required it and opened the stage
    if guard.package_files:  # a USDZ: its entries, as usd-core reads them
        asset.extra["package_files"] = guard.package_files
    asset.extra["layer_files"] = tuple(layer.realPath for layer in stage.GetUsedLayers() if layer.realPath)  # never outputs
    try:
        with quiet():  # usd-core would print its warnings about odd scene description to stderr
            _Reader(asset, stage).run()
        if usd_core:
            asset.extra["usd_core_findings"] = usd_core_findings(stage)
    except Tf.ErrorException as error:
        message, line = usd_error_message(tf_error_text(error), os.path.abspath(asset.path))
        raise ReadError("not_usd", f"USD cannot read the stage: {message}", Location(asset.path, line)) from None
    except UnicodeDecodeError:  # names, tokens and strings of a crate file are bytes usd-core does not check
        raise ReadError("not_usd", "the stage holds names or text that are not valid UTF-8", Location(asset.path)) from None


class _Reader(NetworkReader):
    def __init__(self, asset: Asset, stage) -> None:
        from pxr import Sdr, Usd, UsdGeom, UsdShade  # lazy: as in _read_stage

        self.Usd, self.UsdShade = Usd, UsdShade
        self.asset = asset
        self.stage = stage
        self.path = asset.path
        self.root_layer = stage.GetRootLayer()
        self.root_dir = os.path.dirname(os.path.abspath(asset.path))
        self.colorspace_of_prim: dict[object, str | None] = {}  # Sdf.Path -> name
        self.observed_colorspaces: set[tuple] = set()
        self.shaders: dict[str, Material] = {}
        self.mtlx_context_shaders: set[str] = set()
        self.renderer_context_shaders: set[str] = set()  # upstream of another renderer's context (ri, arnold, ...)
        self._bound: dict[str, set] | None = None  # bound_meshes
        self.mistyped_outputs: set[tuple[str, str]] = set()  # (prim, output) observed once
        self.UsdGeom = UsdGeom
        asset.extra["usd_sdr_ids"] = tuple(sorted(str(i) for i in Sdr.Registry().GetShaderNodeIdentifiers()))

    def location(self, prim_path, name: str | None = None) -> Location:
        return Location(self.path, None, str(prim_path), name)

    # -- stage ------------------------------------------------------------------------------
    def run(self) -> None:
        stage, asset = self.stage, self.asset
        asset.format_version = self.root_layer.GetFileFormat().formatId
        if stage.HasAuthoredMetadata("metersPerUnit"):
            asset.meters_per_unit = float(self.UsdGeom.GetStageMetersPerUnit(stage))
        observe_layer_units(self.stage, self.asset.observe, self.location, scene_length_inputs())
        observe_variant_values(self.stage, self.asset.observe, self.location, surface_shader_ids())
        asset.extra["up_axis"] = str(self.UsdGeom.GetStageUpAxis(stage)) if stage.HasAuthoredMetadata("upAxis") else None
        default_prim = stage.GetDefaultPrim()
        if default_prim:
            asset.colorspace = self.inherited_colorspace(default_prim)
            if asset.colorspace:
                asset.colorspace_location = self.location(default_prim.GetPath(), "colorSpace:name")
        shader_prims, meshes = [], []
        prototypes_read: set = set()
        # arcs to MaterialX documents and to shared folders the guard set aside, by the prim spec that held them
        set_aside = {(o.detail["layer"], o.detail["spec"]): (o.kind, o.detail["asset"]) for o in asset.observations
                     if o.detail.get("spec") and (o.kind == "usd_mtlx_reference" or o.detail.get("shared"))}
        prims = iter(self.Usd.PrimRange.Stage(stage, self.Usd.TraverseInstanceProxies()))
        for prim in prims:
            if prim.IsInstance():  # an instanceable prim: its prototype's prims are read once, at its first instance
                prototype = prim.GetPrototype().GetPath()
                if prototype in prototypes_read:
                    prims.PruneChildren()
                prototypes_read.add(prototype)
            if observe_structure(prim, self.stage, self.asset.observe, self.location, set_aside):  # (a bound prim: convert notes them)
                self.asset.extra["usd_bindings"] = self.asset.extra.get("usd_bindings", 0) + 1
            if prim.HasAPI(self.Usd.ColorSpaceAPI):
                name = self.authored_prim_colorspace(prim)
                if name:
                    self.observe_colorspace(self.location(prim.GetPath(), "colorSpace:name"), name, "usd",
                                            "Usd.ColorSpaceAPI")
            if prim.IsA(self.UsdShade.Material):
                self.read_material(prim)
            elif prim.IsA(self.UsdShade.Shader):
                shader_prims.append(prim)
            elif prim.IsA(self.UsdGeom.Mesh):
                meshes.append(prim)
        for prim in shader_prims:
            self.observe_shader_id(prim)
        if not asset.materials:  # (a layer meant to be composed: its materials under an 'over' are not defined)
            undefined = [str(p.GetPath()) for p in stage.TraverseAll() if p.IsA(self.UsdShade.Material)
                         and not p.IsDefined()]
            if undefined:
                asset.extra["usd_undefined_materials"] = undefined
        asset.extra["usd_renderer_context_shaders"] = tuple(sorted(self.renderer_context_shaders))
        unit = asset.meters_per_unit or load_json("units.json")["usd_default_meters_per_unit"]
        for material in asset.materials:  # (the evaluator reads scene-unit lengths in metres: parameters.resolve)
            material.extra["meters_per_unit"] = unit
        if meshes and not self.stage.GetCompositionErrors() and not any(
                o.kind in ("usd_arc_outside", "usd_mtlx_reference") for o in asset.observations):
            # (a stage composed without some of its layers may lack the primvars they carry: not judged)
            self.bound_primvars(meshes)
            textured = {m.material_location.path for m in asset.materials
                        if m.material_location is not None and any(True for _ in m.textures())}
            if textured:
                bound = self.bound_meshes(meshes)
                observe_textured_uvs(self.UsdGeom, sorted({mesh for material in textured for mesh in bound.get(material, ())},
                                                          key=lambda prim: str(prim.GetPath())),
                                     self.asset.observe, self.location)

    def bound_meshes(self, meshes) -> dict[str, set]:
        """Material path -> the meshes bound to it in any purpose, as usd-core resolves bindings (computed once)."""
        if self._bound is None:
            from pxr import Tf  # lazy: as in _read_stage

            Tokens, Binding = self.UsdShade.Tokens, self.UsdShade.MaterialBindingAPI
            self._bound = {}
            try:
                for purpose in (Tokens.allPurpose, Tokens.full, Tokens.preview):
                    materials, _ = Binding.ComputeBoundMaterials(meshes, purpose)
                    for mesh, material in zip(meshes, materials):
                        if material:
                            self._bound.setdefault(str(material.GetPath()), set()).add(mesh)
            except Tf.ErrorException:  # a binding usd-core refuses to resolve (an attribute named material:binding):
                self._bound = {}  # its validators report it (OPBR1025), and no mesh is judged by what it binds
        return self._bound

    def bound_primvars(self, meshes) -> None:
        """For each Material whose textures read a named primvar: the meshes bound to it (in any purpose,
        as usd-core resolves bindings) and the primvars each has (its own and those inherited), in
        ``asset.extra["usd_bound_primvars"]``. Nothing is computed for a stage whose textures read none."""
        reads = self.asset.extra.get("usd_uv_reads", {})
        if not any(read.get("primvar") for read in reads.values()):
            return
        bound = self.bound_meshes(meshes)
        found, sizes = {}, {}
        read_names = {read.get("primvar") for read in reads.values() if read.get("primvar")}
        for material_path, bound_meshes in bound.items():
            entries = []
            for mesh in sorted(bound_meshes, key=lambda prim: str(prim.GetPath())):
                api = self.UsdGeom.PrimvarsAPI(mesh)
                names = {p.GetPrimvarName() for p in api.GetPrimvarsWithValues()}
                names |= {p.GetPrimvarName() for p in api.FindInheritablePrimvars() if p.HasValue()}
                for name in sorted(read_names & {str(n) for n in names}):
                    primvar = api.GetPrimvar(name) or api.FindPrimvarWithInheritance(name)
                    problem = primvar_problem(self.UsdGeom, mesh, primvar) or primvar_type_problem(primvar)
                    if problem:  # Hydra drops a primvar of the wrong size (the reader gets its fallback, as without it);
                        # a constant or uniform one gives no coordinates across a face
                        names.discard(name)
                        sizes.setdefault(str(mesh.GetPath()), {})[name] = problem
                entries.append((str(mesh.GetPath()), tuple(sorted(str(n) for n in names))))
            found[material_path] = entries
        self.asset.extra["usd_bound_primvars"] = found
        self.asset.extra["usd_primvar_sizes"] = sizes

    def observe_shader_id(self, prim) -> None:
        shader = self.UsdShade.Shader(prim)
        shader_id = str(shader.GetShaderId() or "")
        path = str(prim.GetPath())
        if not shader_id:
            source = str(shader.GetImplementationSource())
            if source == "id":
                self.asset.observe("usd_missing_shader_id", self.location(path, "info:id"),
                                   mtlx_context=path in self.mtlx_context_shaders)
            elif source in ("sourceAsset", "sourceCode") and not any(
                    a.GetName().startswith("info:") and a.GetName().endswith(f":{source}") and a.Get()
                    for a in prim.GetAttributes()):
                # info:implementationSource names a source that is not authored: Sdr finds no definition
                self.asset.observe("usd_missing_shader_id", self.location(path, "info:implementationSource"),
                                   mtlx_context=path in self.mtlx_context_shaders, implementation=source)
            return
        nodedef = materialx_nodedef(shader_id)
        if nodedef is not None:
            self.observe_enums(shader, nodedef, path)
        if shader_id in surface_shader_ids() or nodedef is not None:
            return
        if shader_id in self.asset.extra["usd_sdr_ids"]:
            return
        self.asset.observe("usd_unknown_shader_id", self.location(path, "info:id"), id=shader_id,
                           mtlx_context=path in self.mtlx_context_shaders)

    def observe_enums(self, shader, nodedef, path: str) -> None:
        """An input of a MaterialX node (an ``ND_`` id) whose value is outside the list its node definition declares,
        as the .mtlx reader observes one (library.enum_violations): hdMtlx builds the same MaterialX node, whose
        shader generation refuses it (the red team's I/F2: Adobe's USD writer authors an ND_UsdUVTexture_23 wrapS of
        'constant', MaterialX's list being black, clamp, periodic, mirror)."""
        for port in shader.GetInputs():
            declared = None if port.HasConnectedSource() else nodedef.getActiveInput(port.GetBaseName())
            allowed = declared_enum(declared)
            if allowed is None:
                continue
            value = port.Get()  # (text for a string input, a number for an integer's: another is OPBR201's)
            if isinstance(value, bool) or not isinstance(value, str if declared.getType() == "string" else int):
                continue
            if str(value).strip() not in allowed:
                self.asset.observe("node_enum_value", self.location(path, port.GetBaseName()), value=str(value),
                                   allowed=allowed)

    # -- materials --------------------------------------------------------------------------
    def read_material(self, prim) -> None:
        before = len(self.asset.materials)
        self._read_material(prim)
        self._mark_fallbacks(self.asset.materials[before:])

    def _mark_fallbacks(self, read) -> None:
        """A Material with a MaterialX shader (any model, on outputs:mtlx:surface) and a
        UsdPreviewSurface on outputs:surface is one material and its preview fallback (what
        ``openpbr convert`` writes): the preview is marked ``extra["fallback_of"]``, so conversion
        and counts see one material while the rules still check both (and OPBR1009 compares them)."""
        primary = [m for m in read if m.extra.get("usd_render_context") == MATERIALX_CONTEXT]
        for material in read:
            if primary and material.model == "UsdPreviewSurface" and not material.extra.get("usd_render_context"):
                material.extra["fallback_of"] = primary[0].name

    def _read_material(self, prim) -> None:
        material_path = str(prim.GetPath())
        location = self.location(material_path)
        for output in self.UsdShade.Material(prim).GetOutputs():  # another renderer's volume or displacement
            context, _, terminal = str(output.GetBaseName()).rpartition(":")
            if context not in (*UNIVERSAL_CONTEXTS, MATERIALX_CONTEXT) and terminal != "surface" \
                    and output.GetAttr().GetConnections():
                kind, *found = self.source(output.GetAttr())
                if kind == "shader":
                    self.mark_context(found[0], self.renderer_context_shaders)
        outputs = [o for o in self.UsdShade.Material(prim).GetOutputs()
                   if o.GetBaseName() == "surface" or o.GetBaseName().endswith(":surface")]
        if not outputs:
            others = [o for o in self.UsdShade.Material(prim).GetOutputs() if o.GetAttr().GetConnections()]
            if not others:  # a light, volume or displacement-only material is whole without a surface
                self.asset.observe("usd_material_without_surface", location, material=material_path,
                                   reason="it has no surface output")
            return
        connected = False
        for output in outputs:
            base = str(output.GetBaseName())
            context = base[: -len(":surface")] if base != "surface" else ""
            attribute = output.GetAttr()
            if not attribute.GetConnections():
                continue
            connected = True
            kind, *found = self.source(attribute)
            where = self.location(material_path, f"outputs:{base}")
            if kind == "dangling":
                target, reason = found
                self.asset.observe("dangling_reference", where, attribute=f"outputs:{base}", target=target, reason=reason)
                continue
            if kind == "value" and found[0].GetPath() != attribute.GetPath():
                # through a node graph's output that nothing feeds: ComputeSurfaceSource finds no shader
                self.asset.observe("dangling_reference", where, attribute=f"outputs:{base}", target=str(found[0].GetPath()),
                                   ends="is a node graph output connected to nothing: no shader renders")
                continue
            if kind != "shader":
                continue
            shader_prim, output_name, _ = found
            if context == MATERIALX_CONTEXT:
                self.mark_context(shader_prim, self.mtlx_context_shaders)
            elif context not in UNIVERSAL_CONTEXTS:
                self.mark_context(shader_prim, self.renderer_context_shaders)
            self.read_surface(shader_prim, output_name, prim, context, where)
        if not connected:
            self.asset.observe("usd_material_without_surface", location, material=material_path,
                               reason=f"{', '.join('outputs:' + o.GetBaseName() for o in outputs)} is not connected")

    def mark_context(self, prim, shaders: set[str], depth: int = 0) -> None:
        """Remember every shader upstream of a render context's surface output in ``shaders``: under MaterialX's
        their ids must be MaterialX node definitions; under another renderer's (ri, arnold) they are that
        renderer's nodes, which usd-core's registry knows only with the renderer's plugin."""
        path = str(prim.GetPath())
        if path in shaders or depth > MAX_DEPTH:
            return
        shaders.add(path)
        for shader_input in self.UsdShade.Shader(prim).GetInputs():
            kind, *found = self.source(shader_input.GetAttr())
            if kind == "shader":
                self.mark_context(found[0], shaders, depth + 1)

    def read_surface(self, shader_prim, output_name: str, material_prim, context: str, where: Location) -> None:
        shader = self.UsdShade.Shader(shader_prim)
        shader_id = str(shader.GetShaderId() or "")
        known = surface_shader_ids().get(shader_id)
        if known is None:
            declared = self.declared_output_type(shader_prim, output_name)
            if declared is not None and declared != "token":  # a surface output takes a shader's token output
                self.asset.observe("usd_connection_type_mismatch", where, input=where.input, input_type="token",
                                   source=f"{shader_prim.GetPath()}.outputs:{output_name}", source_type=declared)
                return
            category = shader_id or f"{shader.GetImplementationSource()} ({shader_prim.GetPath().name})"
            self.asset.observe("unsupported_shader", where, material=str(material_prim.GetPath()), category=category)
            return
        model, id_version, flavour = known
        if flavour == "usd" and context == MATERIALX_CONTEXT:  # the glslfx id under MaterialX's render context
            self.asset.observe("usd_preview_in_mtlx_context", where, id=shader_id, shader=str(shader_prim.GetPath()))
        accepted = ("surface",) if flavour == "usd" else ("out", "surface")
        # another output the shader declares (Pixar's stages connect outputs:out) still names it, as in Storm
        if output_name not in accepted and not shader_prim.GetAttribute(f"outputs:{output_name}"):
            self.asset.observe(
                "dangling_reference", where, attribute=where.input,
                target=f"{shader_prim.GetPath()}.outputs:{output_name}",
                reason=f"{shader_id} has no output {output_name!r} (expected {' or '.join('outputs:' + a for a in accepted)})",
            )
            return
        path = str(shader_prim.GetPath())
        material = self.shaders.get(path)
        if material is None:
            material = self.read_shader(shader_prim, shader_id, model, id_version, flavour)
            self.shaders[path] = material
            self.asset.materials.append(material)
        elif material.material_name is not None and material.material_location != self.location(material_prim.GetPath()):
            material = copy.deepcopy(material)  # another Material's surface too (Pixar's sphereGrid): one of its own
            material.material_name, material.extra = None, {k: v for k, v in material.extra.items() if k != "gltf"}
            self.asset.materials.append(material)
        if material.material_name is None:
            material.material_name = material_prim.GetName()  # the prim's name; its path is material_location
            material.material_location = self.location(material_prim.GetPath())
            state = gltf_state.decode(material_prim.GetCustomDataByKey(gltf_state.USD_CUSTOM_DATA_KEY))
            if state:
                material.extra["gltf"] = state
            material.extra["usd_render_context"] = context
            material.extra["usd_surface_output"] = where.input
            # a UsdPreviewSurface's own displacement input is translated (or its loss noted) with its other inputs
            displaced = [f"outputs:{o.GetBaseName()}" for o in self.UsdShade.Material(material_prim).GetOutputs()
                         if str(o.GetBaseName()).endswith("displacement")
                         and any(c.GetPrimPath() != shader_prim.GetPath() or material.model != "UsdPreviewSurface"
                                 for c in o.GetAttr().GetConnections())]
            if displaced:  # a displacement shader: no conversion carries it (convert notes it)
                material.extra["displacement"] = displaced[0]
            space = self.inherited_colorspace(material_prim)  # under MaterialX's name, for colour maths elsewhere
            material.colorspace = (colorspaces.materialx_equivalent(space) or space) if space else None

    # -- shaders ----------------------------------------------------------------------------
    def read_shader(self, prim, shader_id: str, model: str, id_version: str | None, flavour: str) -> Material:
        path = str(prim.GetPath())
        declared = prim.GetCustomDataByKey(CUSTOM_DATA_VERSION_KEY)
        material = Material(
            name=path, model=model, location=self.location(path),
            declared_version=str(declared) if declared else None,
            nodedef=shader_id if id_version is not None else None,
        )
        material.extra.update(info_id=shader_id, usd_flavour=flavour, node_path=path)
        attributes = []
        for shader_input in self.UsdShade.Shader(prim).GetInputs():
            name = str(shader_input.GetBaseName())
            attributes.append((name, shader_input.GetAttr()))
            material.inputs[name] = Input(name=name, type=None, value=None, location=self.location(path, name))
        versioning.settle(material)
        if material.declared_version and material.version_basis.startswith("node version"):
            material.version_basis = f"node version attribute (customData {CUSTOM_DATA_VERSION_KEY})"
        table = tables.table(model, material.version) if material.version else None
        for name, attribute in attributes:
            parameter = table.get(name) if table is not None else None
            self.read_input(material.inputs[name], attribute, model, flavour, parameter)
        return material

    def read_input(self, entry: Input, attribute, model: str, flavour: str, parameter) -> None:
        usd_type = str(attribute.GetTypeName())
        entry.source_type = usd_type
        entry.type = materialx_type_of(usd_type, parameter.type if parameter else None)
        scheme = "materialx" if flavour == "mtlx" else "usd"
        entry.authored_colorspace = self.attribute_colorspace(attribute, scheme)
        entry.colorspace = entry.authored_colorspace or self.inherited_colorspace(attribute.GetPrim())
        opacity_mode = flavour == "usd" and model == "UsdPreviewSurface" and entry.name == "opacityMode"
        if opacity_mode and usd_type == "token":
            entry.type = "integer"
        consumer = (model, flavour, parameter)
        value = self.interpret(attribute, entry, consumer)
        if opacity_mode and isinstance(value, Constant) and isinstance(value.value, str):
            entry.raw = value.value
            if value.value in OPACITY_MODE_TOKENS:
                value = Constant(OPACITY_MODE_TOKENS.index(value.value))
        entry.value = value
