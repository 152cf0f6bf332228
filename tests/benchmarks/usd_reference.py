"""An independent MaterialX reference for each UsdPreviewSurface material of a USD stage, read
straight from the stage with usd-core's ``pxr.UsdShade`` (no openpbr_tools code), for
bench_glsl_usd_assets.py: MaterialX's own ``UsdPreviewSurface`` node with the shader's resolved
input values (connections through Material interface inputs followed), textures as MaterialX
``UsdUVTexture`` nodes (file, scale, bias, fallback, wrapS/wrapT, sourceColorSpace),
``UsdTransform2d`` as MaterialX's ``UsdTransform2d`` and a ``UsdPrimvarReader_float2`` as
``texcoord`` (the sphere's one UV set).

Choices (what the UsdPreviewSurface specification leaves to the renderer, or what one sphere
cannot show):

* opacityMode: an authored token is kept; unauthored is ``transparent`` (0), MaterialX 1.39.5's
  default and the specification's "even a fully transparent object still receives lighting ...
  specular response". ``presence=True`` asks for the other reading (1, alpha blending as Storm).
* sourceColorSpace ``auto`` (or unset): sRGB when the image is 8-bit RGB(A) (or palette), or
  tagged sRGB; otherwise raw. ``raw`` -> ``lin_rec709`` (no transform). MaterialX converts a
  colour-managed UsdUVTexture's rgb only, never its alpha.
* wrapS/wrapT ``useMetadata`` (or unset) -> ``black`` per the specification (only matters outside
  [0, 1]; the sphere's UVs stay inside); ``repeat`` -> ``periodic``.
* A ``UsdPrimvarReader_*`` feeding a shader input has no single value per material: the reference
  uses the reader's fallback (specification default 0) and returns a note saying so.

Anything else the reference cannot express (a shader it does not know feeding an input) is
returned as a note and left at the node's default, never approximated.
"""

from __future__ import annotations

import os
from functools import lru_cache

import MaterialX as mx
from PIL import Image
from pxr import Sdf, Usd, UsdShade

PREVIEW_IDS = ("UsdPreviewSurface", "ND_UsdPreviewSurface_surfaceshader")
WRAP = {"repeat": "periodic", "periodic": "periodic", "clamp": "clamp", "mirror": "mirror", "black": "black",
        "useMetadata": "black"}
OPACITY_MODE = {"transparent": 0, "presence": 1}


@lru_cache(maxsize=1)
def _preview_nodedef():
    library = mx.createDocument()
    mx.loadLibraries(mx.getDefaultDataLibraryFolders(), mx.getDefaultDataSearchPath(), library)
    return library, library.getNodeDef("ND_UsdPreviewSurface_surfaceshader")


def resolve(inp) -> tuple:
    """How a shader input is driven: ``("value", v)``, ``("output", shader prim, output name)`` or
    ``("default",)`` (nothing authored)."""
    attributes = inp.GetValueProducingAttributes(False)
    for attribute in attributes:
        if UsdShade.Output.IsOutput(attribute):
            return ("output", attribute.GetPrim(), UsdShade.Output(attribute).GetBaseName())
        value = attribute.Get()
        if value is not None:
            return ("value", value)
    if not attributes:
        value = inp.Get()
        if value is not None and not inp.HasConnectedSource():
            return ("value", value)
    return ("default",)


def _authored(shader, name: str, default=None):
    """The value authored (or connected from an interface input) on ``shader``'s input ``name``."""
    inp = shader.GetInput(name)
    how = resolve(inp) if inp else ("default",)
    return how[1] if how[0] == "value" else default


def _mx_value(kind: str, value):
    if kind == "color3":
        return mx.Color3(*[float(v) for v in value])
    if kind == "color4":
        return mx.Color4(*[float(v) for v in value])
    if kind == "vector3":
        return mx.Vector3(*[float(v) for v in value])
    if kind == "vector2":
        return mx.Vector2(*[float(v) for v in value])
    if kind == "float":
        return float(value)
    if kind == "integer":
        return int(value)
    return value


def _auto_colorspace(path: str | None) -> str:
    """sourceColorSpace ``auto``: sRGB for an 8-bit RGB(A) image or one tagged sRGB, else raw."""
    try:
        image = Image.open(path)
    except (OSError, TypeError, AttributeError):
        return "lin_rec709"
    with image:
        info = image.info
        if "srgb" in info or abs(float(info.get("gamma", 0)) - 1 / 2.2) < 0.01:
            return "srgb_texture"
        return "srgb_texture" if image.mode in ("RGB", "RGBA", "P") else "lin_rec709"


class UsdReference:
    """The USD stage at ``stage_path``; ``materials`` lists its UsdPreviewSurface materials as
    ``(name, path, shader)``; :meth:`write` makes one material's reference document."""

    def __init__(self, stage_path: str):
        self.path = stage_path
        self.stage = Usd.Stage.Open(stage_path)
        self.materials = []
        for prim in self.stage.Traverse():
            if not prim.IsA(UsdShade.Material):
                continue
            material = UsdShade.Material(prim)
            for context in ("mtlx", ""):  # MaterialX-in-USD (ND_UsdPreviewSurface_...) or universal
                source = material.ComputeSurfaceSource(context)
                if source and source[0] and source[0].GetPrim().IsValid() \
                        and str(source[0].GetShaderId() or "") in PREVIEW_IDS:
                    self.materials.append((prim.GetName(), str(prim.GetPath()), source[0]))
                    break
        self._doc = mx.createDocument()
        self._notes: list[str] = []
        self._out_dir = ""
        self._count = 0

    def write(self, index: int, out_path: str, presence: bool = False) -> list[str]:
        """Write material ``index``'s reference to ``out_path`` (texture paths relative to its
        folder), opacityMode ``presence`` if asked; returns notes on what the reference leaves out."""
        shader = self.materials[index][2]
        library, nodedef = _preview_nodedef()
        self._doc = mx.createDocument()
        self._doc.setColorSpace("lin_rec709")
        self._notes = []
        self._out_dir = os.path.dirname(os.path.abspath(out_path))
        self._count = 0
        node = self._doc.addNode("UsdPreviewSurface", "SR_ref", "surfaceshader")
        for nd_input in nodedef.getActiveInputs():
            name, kind = nd_input.getName(), nd_input.getType()
            inp = shader.GetInput(name)
            if name == "opacityMode" or not inp:
                continue
            how = resolve(inp)
            if how[0] == "value":
                node.setInputValue(name, _mx_value(kind, how[1]), kind)
            elif how[0] == "output":
                self._connect(node, name, kind, how[1], how[2])
        mode = 1 if presence else OPACITY_MODE.get(str(_authored(shader, "opacityMode", "transparent")), 0)
        node.setInputValue("opacityMode", mode, "integer")
        self._doc.addMaterialNode("M_ref", node)
        mx.writeToXmlFile(self._doc, out_path)
        return self._notes

    def has_partial_opacity(self, index: int) -> bool:
        """Whether opacity can be below 1 without a threshold (where the transparent and presence
        readings differ)."""
        shader = self.materials[index][2]
        inp = shader.GetInput("opacity")
        if not inp or float(_authored(shader, "opacityThreshold", 0.0) or 0.0) > 0.0:
            return False
        how = resolve(inp)
        return how[0] == "output" or (how[0] == "value" and float(how[1]) < 1.0)

    def _name(self, stem: str) -> str:
        self._count += 1
        return f"{stem}_{self._count}"

    def _connect(self, node, name: str, kind: str, prim, output: str) -> None:
        source = UsdShade.Shader(prim)
        sid = str(source.GetShaderId() or "")
        if sid == "UsdUVTexture":
            port = node.addInput(name, kind)
            port.setConnectedNode(self._uvtexture(source))
            port.setOutputString(output)
        elif sid.startswith("UsdPrimvarReader"):
            value = _authored(source, "fallback")
            if value is None:
                value = 0.0 if kind == "float" else [0.0] * (3 if kind in ("color3", "vector3") else 2)
            node.setInputValue(name, _mx_value(kind, value), kind)
            self._notes.append(f"{name} <- primvar {_authored(source, 'varname')!r} (varies per prim): "
                               f"reference uses the fallback {value}")
        else:
            self._notes.append(f"{name} <- unsupported node {sid}: left at the default")

    def _uvtexture(self, shader):
        tex = self._doc.addNode("UsdUVTexture", self._name("tex"), "multioutput")
        tex.setNodeDefString("ND_UsdUVTexture_23")
        asset = _authored(shader, "file")
        path = None
        if isinstance(asset, Sdf.AssetPath):
            path = asset.resolvedPath or None
            if path is None:
                path = os.path.join(os.path.dirname(shader.GetPrim().GetStage().GetRootLayer().realPath), asset.path)
                self._notes.append(f"texture {asset.path} did not resolve")
        source = str(_authored(shader, "sourceColorSpace", "auto"))
        colorspace = {"sRGB": "srgb_texture", "raw": "lin_rec709"}.get(source) or _auto_colorspace(path)
        if path is not None:
            tex.setInputValue("file", os.path.relpath(path, self._out_dir), "filename")
            tex.getInput("file").setColorSpace(colorspace)
        else:
            self._notes.append("UsdUVTexture without a file: its fallback")
        for key in ("wrapS", "wrapT"):
            tex.setInputValue(key, WRAP.get(str(_authored(shader, key, "useMetadata")), "periodic"), "string")
        for key in ("scale", "bias", "fallback"):
            value = _authored(shader, key)
            if value is not None:
                tex.setInputValue(key, _mx_value("color4", value), "color4")
        st = shader.GetInput("st")
        how = resolve(st) if st else ("default",)
        if how[0] == "output":
            tex.addInput("st", "vector2").setConnectedNode(self._uv(UsdShade.Shader(how[1])))
        return tex

    def _uv(self, shader):
        sid = str(shader.GetShaderId() or "")
        if sid == "UsdTransform2d":
            node = self._doc.addNode("UsdTransform2d", self._name("xf"), "vector2")
            for key, kind in (("rotation", "float"), ("scale", "vector2"), ("translation", "vector2")):
                value = _authored(shader, key)
                if value is not None:
                    node.setInputValue(key, _mx_value(kind, value), kind)
            inp = shader.GetInput("in")
            how = resolve(inp) if inp else ("default",)
            if how[0] == "output":
                node.addInput("in", "vector2").setConnectedNode(self._uv(UsdShade.Shader(how[1])))
            else:
                self._notes.append("UsdTransform2d.in unconnected: (0, 0) per the nodedef")
            return node
        if sid.startswith("UsdPrimvarReader"):
            varname = _authored(shader, "varname")
            if varname != "st":
                self._notes.append(f"UV primvar {varname!r} read as the sphere's only UV set")
        else:
            self._notes.append(f"st <- unsupported {sid}: texcoord")
        return self._doc.addNode("texcoord", self._name("uv"), "vector2")
