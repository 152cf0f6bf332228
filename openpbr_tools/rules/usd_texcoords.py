"""USD texture coordinates: does a texture read UVs that the meshes it is bound to have.

A UsdUVTexture is placed by its ``st`` input, usually connected (through a UsdTransform2d or not) to a
UsdPrimvarReader_float2 whose ``varname`` names a primvar of the mesh, ``st`` by convention, and often
set through the Material's interface (``inputs:frame:stPrimvarName``); a MaterialX image is placed by a
``geompropvalue`` naming the primvar (Hydra reads that primvar; a ``texcoord`` node's primvar is the
renderer's choice, USDMTLX_PRIMARY_UV_NAME, and is not judged). A reader whose primvar a bound
mesh does not have returns its fallback, (0, 0), and so does an ``st`` left unconnected (the
UsdPreviewSurface specification gives both that fallback): the texture shows as the one colour of
its corner texel, the USD counterpart of a glTF texCoord the mesh lacks (OPBR1205). Which meshes a
Material is bound to is usd-core's answer (``UsdShade.MaterialBindingAPI.ComputeBoundMaterials``, in
every purpose, inherited bindings and collections included); a Material bound to no mesh is not
judged. Only a texture whose image is read and varies is judged: one flat colour (every texel within
2/255 of the others) looks the same at any coordinate (usd-wg's USD_Mini_Car_Kit colours its parts
with such images and no st), and an image that cannot be read shows nothing either way.
"""

from __future__ import annotations

from ..diagnostics import Severity
from ..io.image_content import varies
from ..model import Location
from . import Rule, for_each_input
from .textures import image_of
from .usd_examples import stage_example


def _stage(reader: str, primvar: str) -> str:
    return stage_example(
        'def Mesh "Plane" (\n    prepend apiSchemas = ["MaterialBindingAPI"]\n)\n{\n'
        "    int[] faceVertexCounts = [4]\n    int[] faceVertexIndices = [0, 1, 2, 3]\n"
        "    point3f[] points = [(-1, 0, -1), (1, 0, -1), (1, 0, 1), (-1, 0, 1)]\n"
        f'    texCoord2f[] primvars:{primvar} = [(0, 0), (1, 0), (1, 1), (0, 1)] (\n        interpolation = "vertex"\n    )\n'
        "    rel material:binding = </M>\n}\n\n"
        'def Material "M"\n{\n    token outputs:surface.connect = </M/P.outputs:surface>\n\n'
        '    def Shader "P"\n    {\n        uniform token info:id = "UsdPreviewSurface"\n'
        "        color3f inputs:diffuseColor.connect = </M/albedo.outputs:rgb>\n        token outputs:surface\n    }\n\n"
        '    def Shader "albedo"\n    {\n        uniform token info:id = "UsdUVTexture"\n'
        '        asset inputs:file = @albedo.png@\n        token inputs:sourceColorSpace = "sRGB"\n'
        f"{reader}        float3 outputs:rgb\n    }}\n\n"
        '    def Shader "uv"\n    {\n        uniform token info:id = "UsdPrimvarReader_float2"\n'
        '        string inputs:varname = "st"\n        float2 outputs:result\n    }\n}',
        metadata='defaultPrim = "M"\n    metersPerUnit = 1\n    upAxis = "Y"')


_READS = "        float2 inputs:st.connect = </M/uv.outputs:result>\n"
_CHECKER = (("albedo.png", bytes.fromhex(  # a 2 x 2 black and white checker: an image whose texels differ
    "89504e470d0a1a0a0000000d4948445200000002000000020802000000fdd49a73000000124"
    "944415478da63f8ffff3f0304fcffff1f0029e405fba0d855520000000049454e44ae426082")),)

PRIMVAR_MISSING = Rule(
    "OPBR1015", "usd-primvar-missing", Severity.ERROR,
    "A primvar reader (or a MaterialX geompropvalue) feeding a texture's coordinates reads a primvar that a mesh "
    "bound to its Material does not have (or has with the wrong number of values for its interpolation, which "
    "renderers drop), or reads none: its varname is connected to an interface input with no value.",
    "The reader returns its fallback, (0, 0), on that mesh, so the texture shows as the one colour of its "
    "corner texel. Typical of a mesh exported with its UVs named after the tool (UVMap, map1) while the "
    "material reads st. Bindings are resolved as usd-core resolves them (inherited, collections, every "
    "purpose); the primvar may be the mesh's own or inherited from an ancestor.",
    passing=_stage(_READS, "st"), failing=_stage(_READS, "UVMap"),
    passing_name="example.usda", failing_name="example.usda", formats=("usd",), example_files=("albedo.png",),
    failing_files=_CHECKER,
)
ST_UNCONNECTED = Rule(
    "OPBR1016", "usd-uvtexture-without-st", Severity.ERROR,
    "A UsdUVTexture's st input (or the in input of the UsdTransform2d that feeds it) is neither connected nor "
    "set, so every point reads the texel at (0, 0).",
    "UsdUVTexture's st and UsdTransform2d's in default to (0, 0) (UsdPreviewSurface specification); neither "
    "falls back to the mesh's UVs, so the texture renders as one flat colour: the texture the author painted "
    "does not show. Connect st (or the transform's in) to a UsdPrimvarReader_float2 reading the mesh's UV "
    "primvar (st). Only reported for an image that is more than one colour.",
    passing=_stage(_READS, "st"), failing=_stage("", "st"),
    passing_name="example.usda", failing_name="example.usda", formats=("usd",), example_files=("albedo.png",),
    failing_files=_CHECKER,
)


def _board(uvs: str, mesh: str = "", subdivision: str = "") -> str:
    """A textured board: the UVs (``uvs``) on the parent Xform, or (``mesh``) on the mesh itself."""
    return stage_example(
        'def Xform "Board"\n{\n' + uvs +
        '    def Mesh "Geo" (\n        prepend apiSchemas = ["MaterialBindingAPI"]\n    )\n    {\n' + subdivision +
        "        int[] faceVertexCounts = [4, 4]\n        int[] faceVertexIndices = [0, 1, 4, 3, 1, 2, 5, 4]\n"
        "        point3f[] points = [(-1, 0, 0), (0, 0, 0), (1, 0, 0), (-1, 0, 1), (0, 0, 1), (1, 0, 1)]\n" + mesh +
        "        rel material:binding = </M>\n    }\n}\n\n"
        'def Material "M"\n{\n    token outputs:mtlx:surface.connect = </M/S.outputs:out>\n\n'
        '    def Shader "S"\n    {\n        uniform token info:id = "ND_open_pbr_surface_surfaceshader"\n'
        "        color3f inputs:base_color.connect = </M/albedo.outputs:out>\n        token outputs:out\n    }\n\n"
        '    def Shader "albedo"\n    {\n        uniform token info:id = "ND_image_color3"\n'
        '        asset inputs:file = @albedo.png@\n        color3f outputs:out\n    }\n}',
        metadata='defaultPrim = "Board"\n    metersPerUnit = 1\n    upAxis = "Y"')


_UVS = ("texCoord2f[] primvars:st = [(0, 0), (1, 0), (1, 1), (0, 1), (0, 0), (1, 0), (1, 1), (0, 1)] (\n"
        '    interpolation = "faceVarying"\n)\n')
_UV_INDICES = "int[] primvars:st:indices = [0, 1, 2, 3, 4, 5, 6, 7]\n"


def _indent(text: str, depth: int) -> str:
    return "".join(" " * depth + line + "\n" for line in text.splitlines())


UV_NOT_INHERITED = Rule(
    "OPBR1031", "usd-primvar-not-inherited", Severity.ERROR,
    "A texture-coordinate primvar of a textured mesh is authored on a parent prim (an Xform) with an interpolation "
    "other than constant, and not on the mesh: the mesh has no UVs.",
    "Only constant primvars inherit down the namespace (UsdGeomPrimvarsAPI: FindPrimvarWithInheritance, "
    "FindInheritablePrimvars): a faceVarying or vertex st on the transform above a mesh, as an exporter that writes "
    "attributes on the transform leaves it, belongs to no geometry, so the textures bound to the mesh are sampled at "
    "the reader's fallback coordinate. Move the primvar onto the mesh.",
    passing=_board("", mesh=_indent(_UVS, 8)), failing=_board(_indent(_UVS, 4)),
    passing_name="example.usda", failing_name="example.usda", formats=("usd",), example_files=("albedo.png",),
)
UV_INDICES_TYPE = Rule(
    "OPBR1032", "usd-primvar-indices-type", Severity.ERROR,
    "A textured mesh's texture-coordinate primvar has its indices (primvars:st:indices) authored as another type "
    "than int[] (uint[], int64[]).",
    "UsdGeomPrimvar reads indices as int[] only: with another type the primvar reports itself indexed (IsIndexed) "
    "but GetIndices reads nothing and ComputeFlattened fails ('No indices authored'), so renderers drop the UVs and "
    "the textures are sampled at the fallback coordinate. Author the indices as int[].",
    passing=_board("", mesh=_indent(_UVS + _UV_INDICES, 8)),
    failing=_board("", mesh=_indent(_UVS + "u" + _UV_INDICES, 8)),
    passing_name="example.usda", failing_name="example.usda", formats=("usd",), example_files=("albedo.png",),
)
UV_SMOOTHED = Rule(
    "OPBR1033", "usd-facevarying-uvs-smoothed", Severity.WARNING,
    "A subdivided textured mesh with faceVarying UVs sets faceVaryingLinearInterpolation = \"none\": its UVs are "
    "smoothed everywhere, borders and corners included.",
    "UsdGeomMesh: faceVaryingLinearInterpolation \"none\" means 'No linear constraints or sharpening, smooth "
    "everywhere', so subdivision moves the UV corners and borders inward like positions, and the texture shrinks and "
    "swims at the mesh's boundary and UV seams. The fallback, cornersPlus1, keeps them pinned (\"all\" keeps the "
    "UVs linear). subdivisionScheme's fallback is catmullClark, so a mesh is subdivided unless it says none. A stage "
    "that sets several values side by side (a comparison of the settings) is not reported.",
    passing=_board("", mesh=_indent(_UVS, 8)),
    failing=_board("", mesh=_indent(_UVS, 8), subdivision='        uniform token faceVaryingLinearInterpolation = "none"\n'),
    passing_name="example.usda", failing_name="example.usda", formats=("usd",), example_files=("albedo.png",),
)

RULES = (PRIMVAR_MISSING, ST_UNCONNECTED, UV_NOT_INHERITED, UV_INDICES_TYPE, UV_SMOOTHED)

_SHOWN = 3  # meshes named in a message


def check(asset, context):
    """Runs on USD assets only (rules.FAMILY_FORMATS)."""
    yield from _authored_uvs(asset, context)
    reads = asset.extra.get("usd_uv_reads", {})
    if not reads:
        return
    bound = asset.extra.get("usd_bound_primvars", {})
    judged: set[tuple[str, str]] = set()
    containers: dict = {}
    for material, _table, entry in for_each_input(asset):
        texture = entry.texture
        if texture is None or texture.node not in reads:  # a UsdUVTexture, or a MaterialX image read through geompropvalue
            continue
        read = reads[texture.node]
        material_path = material.material_location.path if material.material_location else None
        key = (texture.node, material_path or "")
        if key in judged:
            continue
        judged.add(key)
        if read["st"] == "unconnected":
            if not _varies(asset, texture, context, containers):
                continue
            through = read.get("through")
            yield context.diagnostic(
                ST_UNCONNECTED, f"{entry.name}: " + (
                    f"{texture.node} reads its coordinates through {through}, whose in is neither connected nor set"
                    if through else f"{texture.node} has no st connection") + ", so it reads the texel at (0, 0) "
                "everywhere", Location(asset.path, None, through or texture.node, "in" if through else "st"),
                hint=f"connect {'in' if through else 'st'} to a UsdPrimvarReader_float2 whose varname is the mesh's UV "
                     "primvar (st)")
            continue
        if read["st"] == "no_varname":
            if not _varies(asset, texture, context, containers):
                continue
            said = "varname is empty" if read.get("empty") else \
                f"varname is connected to {read.get('source') or 'an input'}, which has no value"
            yield context.diagnostic(
                PRIMVAR_MISSING, f"{entry.name}: {texture.node} reads its coordinates through {read['reader']}, whose "
                f"{said}: no primvar is read, so it reads the texel at (0, 0) everywhere",
                Location(asset.path, None, read["reader"], "varname"),
                hint="give the interface input the mesh's UV primvar name (st), or set varname itself")
            continue
        name = read.get("primvar")
        lacking = [(mesh, names) for mesh, names in bound.get(material_path, ()) if name and name not in names]
        if not lacking or not _varies(asset, texture, context, containers):
            continue
        sizes = asset.extra.get("usd_primvar_sizes", {})
        shown = ", ".join(mesh + (f" (its {name} {sizes[mesh][name]})" if name in sizes.get(mesh, {})
                                  else "") for mesh, _ in lacking[:_SHOWN]) + \
            (f" and {len(lacking) - _SHOWN} more" if len(lacking) > _SHOWN else "")
        has = sorted({n for _, names in lacking for n in names if not n.startswith(("displayColor", "displayOpacity"))})
        yield context.diagnostic(
            PRIMVAR_MISSING, f"{entry.name}: {texture.node} reads primvar {name!r} through {read['reader']}, which "
            f"{'mesh' if len(lacking) == 1 else 'meshes'} {shown} bound to {material_path} "
            f"{'does' if len(lacking) == 1 else 'do'} not have, so it reads the texel at (0, 0) there"
            + (f" (primvars there: {', '.join(has)})" if has else ""),
            Location(asset.path, None, read["reader"], read.get("input", "varname")),
            hint=f"set {read.get('input', 'varname')} to the mesh's UV primvar{' (' + has[0] + ')' if len(has) == 1 else ''}, or rename the primvar to {name!r}")


def _varies(asset, texture, context, containers: dict) -> bool:
    """Whether the image ``texture`` reads is more than one flat colour; ``False`` when it cannot be read
    (outside the asset's folder, missing, undecodable: nothing then shows that the coordinates matter)."""
    image = image_of(asset, texture, context, containers)
    return image is not None and varies(image)


def _authored_uvs(asset, context):
    for observation in asset.observations:
        detail, where = observation.detail, observation.location
        if observation.kind == "usd_uv_not_inherited":
            meshes = detail["meshes"]
            shown = ", ".join(meshes[:_SHOWN]) + (f" and {len(meshes) - _SHOWN} more" if len(meshes) > _SHOWN else "")
            yield context.diagnostic(
                UV_NOT_INHERITED, f"primvars:{detail['primvar']} is {detail['interpolation']} on {detail['owner']}, "
                f"not on the textured {'mesh' if len(meshes) == 1 else 'meshes'} {shown} below it: only constant "
                f"primvars inherit, so {'it has' if len(meshes) == 1 else 'they have'} no {detail['primvar']} and the "
                "textures read the fallback coordinate", where,
                hint=f"author primvars:{detail['primvar']} on each mesh")
        elif observation.kind == "usd_uv_indices_type":
            yield context.diagnostic(
                UV_INDICES_TYPE, f"{detail['mesh']}: primvars:{detail['primvar']}:indices is {detail['type']}, not "
                "int[]: the primvar reads as indexed with no indices, so renderers drop its UVs", where,
                hint=f"author int[] primvars:{detail['primvar']}:indices")
        elif observation.kind == "usd_uv_smoothed":
            yield context.diagnostic(
                UV_SMOOTHED, f"{detail['mesh']} is subdivided ({detail['scheme']}) with faceVaryingLinearInterpolation "
                f"\"none\": its faceVarying {detail['primvar']} is smoothed at borders and corners too, so the texture "
                "shrinks and swims there", where,
                hint="remove it (the fallback cornersPlus1 pins UV corners), or use \"all\" for linear UVs")
