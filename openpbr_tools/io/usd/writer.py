"""Write :class:`~openpbr_tools.model.Material` objects as USD: ``.usda``, ``.usdc``, ``.usd`` or a
``.usdz`` package that carries its textures.

Layout: a ``Scope "Looks"`` (the default prim) holds one ``Material`` prim per material name. An
OpenPBR (or Standard Surface, glTF PBR) shader is a ``Shader`` with its MaterialX node-definition id
on ``outputs:mtlx:surface``; a UsdPreviewSurface material becomes a ``UsdPreviewSurface`` shader on
the universal ``outputs:surface`` of the same ``Material`` when both share a material name (so an
OpenPBR material with a preview fallback is one prim). Inputs get the USD types UsdMtlx gives their
MaterialX types (``color3f``, ``float3``, ``bool``...; UsdPreviewSurface's own types for it), colour
spaces go to ``colorSpace`` metadata in the scheme each shader wants (MaterialX names on MaterialX
shaders, USD names on USD ones) and the material's colour space to ``Usd.ColorSpaceAPI``. The OpenPBR
version is recorded on the shader as ``customData = {dictionary openpbr = {string version}}``.

Textures (:mod:`.texture_networks`) become MaterialX image chains under ``mtlx`` (``ND_image_*``/``ND_tiledimage_*``, then
``ND_convert``/``ND_extract``, ``ND_multiply``/``ND_add`` for scale and bias, ``ND_normalmap``;
``ND_place2d``, ``ND_texcoord`` or ``ND_geompropvalue`` on the coordinates) and ``UsdUVTexture``
(+ ``UsdTransform2d``, ``UsdPrimvarReader_float2``) under UsdPreviewSurface. Constants that came
through a material interface input are written through one again. Stage ``metersPerUnit`` and
``upAxis`` are always authored; lengths carrying a MaterialX distance unit are converted to stage units.

:func:`write_usd` returns typed notes (OPBR11xx diagnostics at the source material and input, with the
output prim and input) about anything it could not carry exactly (an opaque procedural
connection, a texture missing from a package...).
"""

from __future__ import annotations

import os
import shutil
import tempfile
import time

from ... import colorspaces, gltf_state, tables
from ...atomic import default_mode
from ...diagnostics import Diagnostic
from ...model import Asset, Connection, Constant, Input, Location, Material, Texture
from ...resources import load_json
from ...rules.translation import APPROXIMATED, NOT_CARRIED
from ...workers import raise_if_stopped
from ..paths import PathGuard
from .reader import CUSTOM_DATA_VERSION_KEY
from .errors import quiet, require_pxr
from .graph_networks import GraphNetworkWriter
from .texture_files import TextureFiles
from .texture_networks import TextureNetworkWriter, identifier
from .types import MATERIALX_TO_USD, OPACITY_MODE_TOKENS, PREVIEW_SURFACE_USD_TYPES

LOOKS = "/Looks"


def write_usd(materials: list[Material], path: str, *, source: Asset | str | None = None,
              meters_per_unit: float | None = None, up_axis: str | None = None,
              allow_outside: tuple[str, ...] = ()) -> list[Diagnostic]:
    """Write ``materials`` to ``path``; the suffix picks the format.

    ``source`` is the :class:`Asset` (or the path of the file) the materials were read from:
    relative texture paths are resolved against its folder (and re-expressed relative to ``path``,
    or copied into a ``.usdz``), and its scene unit is the unit of lengths without a unit of their
    own. ``meters_per_unit`` defaults to the source's (a USD stage's ``metersPerUnit``, 1 for glTF)
    and otherwise to USD's 0.01; lengths are converted when it differs. ``up_axis`` defaults to
    the source stage's, else ``"Y"``.

    A ``.usdz`` reads and packages texture files only from inside the source's folder (after
    resolving symlinks) or a folder in ``allow_outside``; any other raises :class:`UsdWriteError`
    before anything is written. Other outputs only reference textures (never read them).
    """
    require_pxr(os.fspath(path))
    from pxr import Sdf, Usd, UsdGeom  # lazy: pxr (0.1-0.2 s) once require_pxr has found it

    path = os.fspath(path)
    suffix = os.path.splitext(path)[1].lower()
    notes: list[Diagnostic] = []
    source_path = source.path if isinstance(source, Asset) else source
    source_unit = _scene_unit(source) if isinstance(source, Asset) else None
    meters_per_unit = meters_per_unit or source_unit or load_json("units.json")["usd_default_meters_per_unit"]
    source_dir = os.path.dirname(os.path.abspath(source_path or path))
    if up_axis is None:
        up_axis = (source.extra.get("up_axis") if isinstance(source, Asset) else None) or "Y"
    package = suffix == ".usdz"
    folder = os.path.dirname(os.path.abspath(path))
    stage = Usd.Stage.CreateInMemory()
    UsdGeom.SetStageMetersPerUnit(stage, meters_per_unit)
    UsdGeom.SetStageUpAxis(stage, UsdGeom.Tokens.z if up_axis.upper() == "Z" else UsdGeom.Tokens.y)
    stage.SetDefaultPrim(stage.DefinePrim(LOOKS, "Scope"))
    writer = _Writer(stage, notes, source_dir, folder, package, meters_per_unit, source_unit)
    writer.output_path = path
    writer.guard = PathGuard(source_dir, allow_outside)
    for material in materials:
        writer.write(material)
    # Atomically, as openpbr_tools.atomic does: a temporary file beside the target, renamed over it.
    os.makedirs(folder, exist_ok=True)  # as openpbr_tools.atomic does for every other output
    handle, temporary = tempfile.mkstemp(prefix=".openpbr-", suffix=suffix, dir=folder)
    os.fchmod(handle, default_mode())
    os.close(handle)
    staging = tempfile.mkdtemp(prefix="openpbr-usdz-") if package else None
    try:
        if package:
            layer_path = os.path.join(staging, "root.usdc")
            stage.GetRootLayer().Export(layer_path)
            _package(temporary, layer_path, writer.packaged_files)
        else:
            stage.GetRootLayer().Export(temporary)
        raise_if_stopped()  # (a pool worker SIGTERM reached: nothing is renamed into place)
        os.replace(temporary, path)
    except BaseException:
        if os.path.exists(temporary):
            os.unlink(temporary)
        raise
    finally:
        if staging:
            shutil.rmtree(staging, ignore_errors=True)
    cached = Sdf.Layer.Find(path)  # a layer this process already opened from ``path`` is stale now
    if cached:
        cached.Reload(force=True)
    return notes


def _package(path: str, layer_path: str, files: dict[str, str]) -> None:
    """A USDZ: an uncompressed, 64-byte aligned zip whose first file is the root layer.

    Sdf's zip writer stamps each entry with its file's modification time in local time; every
    file is staged beside the root layer with one fixed local time (2000-01-01 00:00), so the same
    input gives the same bytes on any machine, in any time zone, at any time."""
    from pxr import Sdf  # lazy: pxr only once write_usd has required it

    stamp = time.mktime((2000, 1, 1, 0, 0, 0, 0, 0, -1))
    staged = []
    for index, (inside, outside) in enumerate(sorted(files.items())):
        copy = os.path.join(os.path.dirname(layer_path), f"file{index}")
        shutil.copyfile(outside, copy)
        staged.append((inside, copy))
    for file in [layer_path] + [copy for _, copy in staged]:
        os.utime(file, (stamp, stamp))
    writer = Sdf.ZipFileWriter.CreateNew(path)
    writer.AddFile(layer_path, os.path.basename(layer_path))
    for inside, copy in staged:
        writer.AddFile(copy, inside)
    writer.Save()


class _Writer(TextureNetworkWriter, GraphNetworkWriter, TextureFiles):
    def __init__(self, stage, notes, source_dir, target_dir, package, meters_per_unit, source_unit):
        from pxr import Sdf, UsdShade  # lazy: pxr only once write_usd has required it

        self.Sdf, self.UsdShade = Sdf, UsdShade
        self.stage, self.notes = stage, notes
        self.at: tuple[Location, Location | None] = (Location(""), None)  # where notes of the input being written go
        self.output_path = ""
        self.source_dir, self.target_dir, self.package = source_dir, target_dir, package
        self.meters_per_unit, self.source_unit = meters_per_unit, source_unit
        self.material_prims: dict[str, object] = {}
        self.packaged_files: dict[str, str] = {}
        self.written_graphs: set[str] = set()  # kept graphs written as networks (a fallback's loss is its own)
        # what a .usdz may read and package: the source's folder (and allowed ones), links resolved
        self.guard = PathGuard(source_dir)
        # how a reference is spelled from the output's folder: as written, no link resolved
        self.target = PathGuard(target_dir, real_path=os.path.normpath)

    def unique_child(self, parent_path: str, name: str) -> str:
        base, candidate, n = identifier(name), identifier(name), 1
        while self.stage.GetPrimAtPath(f"{parent_path}/{candidate}"):
            candidate, n = f"{base}_{n}", n + 1
        return f"{parent_path}/{candidate}"

    # -- materials ---------------------------------------------------------------------------
    def write(self, material: Material) -> None:
        key = material.material_name or material.name
        usd_material = self.material_prims.get(key)
        if usd_material is None:
            usd_material = self.UsdShade.Material.Define(self.stage, self.unique_child(LOOKS, key))
            self.material_prims[key] = usd_material
            state = gltf_state.travelling(material)
            if state:
                usd_material.GetPrim().SetCustomDataByKey(gltf_state.USD_CUSTOM_DATA_KEY, gltf_state.encode(state))
            if material.colorspace:
                self.set_material_colorspace(usd_material.GetPrim(), material.colorspace)
        preview = material.model == "UsdPreviewSurface"
        shader_path = self.unique_child(str(usd_material.GetPath()), material.name)
        shader = self.UsdShade.Shader.Define(self.stage, shader_path)
        if preview:
            shader.CreateIdAttr("UsdPreviewSurface")
        else:
            shader.CreateIdAttr(self.shader_id(material))
            if material.model == "open_pbr_surface" and material.version:
                shader.GetPrim().SetCustomDataByKey(CUSTOM_DATA_VERSION_KEY, material.version)
        output = shader.CreateOutput("surface", self.Sdf.ValueTypeNames.Token)
        usd_material.CreateSurfaceOutput("" if preview else "mtlx").ConnectToSource(output)
        table = tables.table(material.model, material.version) if material.version else None
        for name, entry in material.inputs.items():
            parameter = table.get(name) if table is not None else None
            self.write_input(material, usd_material, shader, entry, parameter, preview)
        if not preview:
            self.write_displacement(material, usd_material)

    def write_displacement(self, material: Material, usd_material) -> None:
        """A MaterialX source's displacement shader, kept whole (its graph: reader.capture_graph), written as the
        UsdShade network of its MaterialX nodes on the material's ``outputs:mtlx:displacement`` (UsdMtlx's
        terminal), beside the OpenPBR shader; a graph USD cannot carry is noted, not written."""
        graph = material.extra.get("displacement_graph")
        if not isinstance(graph, Connection) or not graph.graph_xml:
            return
        where = material.material_location or material.location
        self.at = (where, None)
        entry = Input("displacement", "displacementshader", graph, where)
        output = self.materialx_graph(usd_material, entry, graph)
        if output is None:
            self.note(NOT_CARRIED, f"{material.material_name or material.name}: its displacement shader is not "
                                   "written: its graph holds a node or value USD cannot carry")
            return
        usd_material.CreateDisplacementOutput("mtlx").ConnectToSource(output)

    def shader_id(self, material: Material) -> str:
        current = tables.table(material.model).nodedef
        if material.version is None or material.version == tables.latest(material.model):
            return current or f"ND_{material.model}_surfaceshader"
        return f"ND_{material.model}_surfaceshader_{material.version.replace('.', '')}"

    def set_material_colorspace(self, prim, name: str) -> None:
        from pxr import Usd  # lazy: pxr only once write_usd has required it

        usd_name = name if name in colorspaces.usd_names() else colorspaces.usd_equivalent(name)
        if usd_name:
            Usd.ColorSpaceAPI.Apply(prim).CreateColorSpaceNameAttr(usd_name)

    # -- inputs ------------------------------------------------------------------------------
    def usd_type(self, entry, parameter, preview: bool) -> str:
        """The type the node declares; an input authored with another type (OPBR201) keeps its
        own, so its value is written as it was rather than refused."""
        if parameter is not None and entry.type not in (None, parameter.type):
            return MATERIALX_TO_USD.get(entry.type or "", entry.source_type or "token")
        if preview and entry.name in PREVIEW_SURFACE_USD_TYPES:
            return PREVIEW_SURFACE_USD_TYPES[entry.name]
        materialx_type = parameter.type if parameter is not None else entry.type
        return MATERIALX_TO_USD.get(materialx_type or "", entry.source_type or "token")

    def note(self, rule, message: str) -> None:
        """A note of ``rule`` at the source of the input being written (and its attribute in the output)."""
        self.notes.append(rule.note(message, *self.at))

    def write_input(self, material, usd_material, shader, entry, parameter, preview: bool) -> None:
        value = entry.value
        if value is None:
            return
        self.at = (entry.location.with_material(material.material_name or material.name),
                   Location(self.output_path, path=str(shader.GetPath()), input=entry.name))
        usd_type = self.usd_type(entry, parameter, preview)
        type_name = self.Sdf.ValueTypeNames.Find(usd_type)
        shader_input = shader.CreateInput(entry.name, type_name)
        if isinstance(value, Constant):
            constant = self.convert_length(entry, parameter, value.value, material)
            if preview and entry.name == "opacityMode" and isinstance(constant, int) and 0 <= constant < len(OPACITY_MODE_TOKENS):
                constant = OPACITY_MODE_TOKENS[constant]
            target = shader_input
            if entry.interface_name:
                target = usd_material.CreateInput(entry.interface_name, type_name)
                shader_input.ConnectToSource(target)
            self.set_value(target.GetAttr(), usd_type, constant)
            if entry.authored_colorspace:
                name = self.colorspace_name(entry.authored_colorspace, "usd" if preview else "materialx")
                if name:
                    target.GetAttr().SetColorSpace(name)
        elif isinstance(value, Texture):
            output = (self.uv_texture if preview else self.materialx_image)(usd_material, entry, value, usd_type)
            shader_input.ConnectToSource(output)
        elif isinstance(value, Connection):
            kept = self.materialx_graph(usd_material, entry, value) if value.graph_xml and not preview else None
            if kept is not None:  # the graph written as the UsdShade network of its MaterialX nodes
                shader_input.ConnectToSource(kept)
                self.written_graphs.add(value.graph_xml)
                return
            written = self.stand_in(material, entry, value, usd_type) if preview else None
            if written is not None:  # (its midpoint, not the shader's default: session 27's E#15)
                from ...evaluate.procedural import said  # lazy: as in stand_in

                self.set_value(shader_input.GetAttr(), usd_type, written)
                held = value.graph_xml in self.written_graphs
                self.note(APPROXIMATED, f"{material.name}.{said(entry.name, value.category, written)}"
                          + (" (in the UsdPreviewSurface fallback only: the output's MaterialX shader holds the graph)"
                             if held else ""))
                return
            # kept only where it names a prim of the output (a USD source's own path, once its network is
            # written there): a connection to a path the output lacks would dangle
            pointed = not preview and value.target.startswith("/") and self.Sdf.Path.IsValidPathString(value.target) \
                and bool(self.stage.GetPrimAtPath(self.Sdf.Path(value.target).GetPrimPath()))
            if pointed:
                shader_input.GetAttr().AddConnection(self.Sdf.Path(value.target))
            why = " (a UsdPreviewSurface reads no MaterialX graph)" if preview and value.graph_xml else ""
            held = preview and value.graph_xml in self.written_graphs  # the output's MaterialX shader holds it
            self.note(APPROXIMATED if held else NOT_CARRIED,
                      f"{material.name}.{entry.name}: the {value.category or 'procedural'} network at "
                      f"{value.target!r} is not written{why}; " + (
                          "the connection points at it" if pointed else
                          "the input has no value, so the shader's default applies")
                      + (" (in the UsdPreviewSurface fallback only: the output's MaterialX shader holds it)"
                         if held else ""))

    def stand_in(self, material: Material, entry, connection: Connection, usd_type: str):
        """A preview input's value for the graph that drives it (evaluate.procedural.stand_in), in the material's
        colour space, or None."""
        if usd_type not in ("float", "color3f"):
            return None
        from ...evaluate.procedural import stand_in  # lazy: only for a graph-driven input of a preview

        found = stand_in(connection, "float" if usd_type == "float" else "color3", material.colorspace,
                         into=colorspaces.materialx_name(material.colorspace))
        # (a colour outside the material's gamut has negative components: the preview's colours are 0 to 1)
        return tuple(min(max(v, 0.0), 1.0) for v in found) if isinstance(found, tuple) else found

    def convert_length(self, entry, parameter, value, material):
        """A length in the stage's unit: from its own MaterialX unit, else from the source's scene
        unit; unchanged when neither is known."""
        if parameter is None or parameter.unit != "scene_length" or not isinstance(value, (int, float)):
            return value
        if entry.unit:
            scale = load_json("units.json")["distance"].get(entry.unit)
            if scale is None:
                self.note(NOT_CARRIED, f"{material.name}.{entry.name}: unknown unit {entry.unit!r}; written unconverted")
                return value
        elif self.source_unit:
            scale = self.source_unit
        else:
            return value
        return value * scale / self.meters_per_unit

    def set_value(self, attribute, usd_type: str, value) -> None:
        from pxr import Tf  # lazy: pxr only once write_usd has required it

        if usd_type == "asset":
            value = self.Sdf.AssetPath(str(value))
        elif isinstance(value, tuple):
            value = tuple(float(v) for v in value)
        try:
            with quiet():
                written = attribute.Set(value)
        except Tf.ErrorException:
            written = False
        if not written:
            self.note(NOT_CARRIED, f"{attribute.GetPath()}: the value {value!r} does not fit {usd_type}; not written")

    @staticmethod
    def colorspace_name(name: str | None, scheme: str) -> str | None:
        """``name`` in the scheme a place wants: MaterialX or USD names, or UsdUVTexture tokens."""
        if not name:
            return None
        uv_tokens = {"raw": ("none", "raw"), "sRGB": ("srgb_texture", "srgb_rec709_scene"), "auto": (None, None)}
        if name in uv_tokens and scheme != "usd_uvtexture":
            return uv_tokens[name][0 if scheme == "materialx" else 1]
        if scheme == "materialx":
            name = colorspaces.materialx_remapped(name)  # a legacy name MaterialX renames (gamma18: g18_rec709)
            if name in colorspaces.materialx_names():
                return name
            return colorspaces.materialx_equivalent(name) or ("none" if colorspaces.is_data(name, "usd") else name)
        if scheme == "usd":
            if name in colorspaces.usd_names():
                return name
            return colorspaces.usd_equivalent(name) or name
        if name in colorspaces.usd_uvtexture_names():
            return name
        if colorspaces.is_data(name) or colorspaces.is_data(name, "usd"):
            return "raw"
        return "sRGB" if colorspaces.encoded(colorspaces.materialx_equivalent(name) or name) else "raw"


def _scene_unit(asset: Asset) -> float | None:
    """Metres per scene unit of the asset the materials came from, when its format defines one."""
    units = load_json("units.json")
    if asset.format == "usd":
        return asset.meters_per_unit or units["usd_default_meters_per_unit"]
    if asset.format == "gltf":
        return units["gltf_meters_per_unit"]
    return asset.meters_per_unit
