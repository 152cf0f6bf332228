"""USD: checks that only make sense for USD stages (shader ids, USD types, colour-space naming
schemes, metersPerUnit, usd-core's own validators). UsdPreviewSurface's own conventions are the
``usd_preview`` family's.

The USD reader fills the same model as the MaterialX reader, so the generic families (names,
values, ranges, version, textures, structure, plausibility) judge USD materials too. This family
adds what USD needs, and re-uses a MaterialX rule's code where the meaning is the same: an unknown
colour-space name is OPBR502 here as well, a colour texture read raw OPBR503, a data texture that is
colour-managed OPBR504, a length without unit information OPBR603 (in USD: ``metersPerUnit`` not
authored, so the 0.01 default applies), an invalid enumerated token OPBR303, a Material without a
connected surface output OPBR801, the project's colour-space policies OPBR505/OPBR506 (compared
through MaterialX names). Texture paths leaving the asset's folder are the generic OPBR704's. OPBR501 (no document colour space) does not apply: USD defines its
default, lin_rec709_scene.

Colour-space names come in three schemes and each place wants one: ``Usd.ColorSpaceAPI`` and
USD-native shaders (UsdPreviewSurface, UsdUVTexture's file) want USD names (``srgb_rec709_scene``,
``lin_ap1_scene``, ``raw``); the inputs of MaterialX shaders want MaterialX names (``srgb_texture``,
``acescg``, ``none``), because UsdMtlx writes them there and Hydra's hdMtlx hands them to MaterialX
unchanged; UsdUVTexture's ``sourceColorSpace`` wants ``raw``, ``sRGB`` or ``auto``. USD stores any
name and treats an unknown one as identity, so a name from the wrong scheme silently disables the
conversion (OPBR1004).

UsdUVTexture's ``sourceColorSpace`` defaults to ``auto``, which decodes 8-bit RGB(A) images (PNG,
JPEG, ...) as sRGB: a roughness or normal map left on ``auto`` is bent by the sRGB curve (OPBR504).
The file's bit depth is judged from its suffix; the image is not opened.

Reading a stage never opens a file outside the asset's folder: sublayers, references, payloads and
value clips pointing outside are deleted before usd-core composes the stage and reported (OPBR1011),
and a USDZ's entries are checked as usd-core sees them (OPBR1012). Files that would crash or hang
usd-core (brackets nested deeper than 1,000 levels, a package whose entries lie about their size)
are refused as unreadable (OPBR002) before usd-core parses them.

One module because its rules are reported from one pass over the reader's observations, and usd-core's own
findings (OPBR1010) are filtered against what those rules already report; split, each half would import the
other's.
"""

from __future__ import annotations

import difflib
import io
import os
import re

from ..diagnostics import Severity
from ..io.usd.types import (
    OPACITY_MODE_TOKENS,
    UV_TEXTURE_ID,
    UV_TEXTURE_WRAP_TOKENS,
    expected_usd_type,
    surface_shader_ids,
)
from ..model import Location
from ..resources import load_json
from . import Rule, for_each_input
from .ranges import ENUM_VALUE
from .document import NOT_MATERIALX
from .structure import NO_SHADER
from .textures import MISSING_TEXTURE
from .units import LENGTH_WITHOUT_UNIT
from .values import TYPE_MISMATCH
from .usd_colorspaces import COLORSPACE_SCHEME, REMAPPED_NAME, colorspace_name, colour_managed_textures, colour_policies
from .usd_examples import openpbr_example
from .usd_normal_maps import other_normal_encodings

MISSING_SHADER_ID = Rule(
    "OPBR1001", "usd-missing-shader-id", Severity.ERROR,
    "A USD Shader prim has no info:id (and no sourceAsset or sourceCode implementation, or a sourceAsset that does "
    "not resolve).",
    "Without info:id no renderer knows which node the prim is: a surface shader without one renders "
    "as the fallback material, a texture node without one as its input's default. usd-core's "
    "validators do not report it.",
    passing=openpbr_example("color3f inputs:base_color = (0.5, 0.4, 0.3)"),
    failing=openpbr_example("color3f inputs:base_color = (0.5, 0.4, 0.3)", shader_id=""),
    passing_name="example.usda", failing_name="example.usda", formats=("usd",),
)
TYPE_ROLE_MISMATCH = Rule(
    "OPBR1002", "usd-type-role-mismatch", Severity.ERROR,
    "An input's USD type has the right shape but the wrong role or precision (float3 where the "
    "node declares color3f, normal3f for float3, double for float, int for a token).",
    "UsdMtlx types a MaterialX color3 as color3f and a vector3 as float3; UsdPreviewSurface declares "
    "normal as normal3f and opacityMode as a token. Hydra builds the MaterialX network from the "
    "authored USD type, so a float3 base_color becomes a vector3 input the OpenPBR node does not "
    "declare. The values are still checked as the parameter's type. UsdPreviewSurface is not affected "
    "by a role alone: its readers (Storm, UsdImaging) take any float3 role for a color3f or normal3f "
    "input, and UsdMtlx itself writes float3 inputs:normal, so a role-only difference there is not "
    "reported.",
    passing=openpbr_example("color3f inputs:base_color = (0.5, 0.4, 0.3)"),
    failing=openpbr_example("float3 inputs:base_color = (0.5, 0.4, 0.3)"),
    passing_name="example.usda", failing_name="example.usda", formats=("usd",),
)
UNKNOWN_SHADER_ID = Rule(
    "OPBR1003", "usd-unknown-shader-id", Severity.ERROR,
    "A shader's info:id names no known node: a misspelling of a known id, or an id under a MaterialX "
    "surface output that is no MaterialX node definition.",
    "Renderers look the id up in their shader registry and drop the node when it is missing. The "
    "hint names the closest known id (MaterialX node definitions, usd-core's registry, the "
    "toolkit's legacy OpenPBR definitions). Ids of other renderers' nodes outside MaterialX networks "
    "(PxrSurface, ...) are left to usd-core's validators.",
    passing=openpbr_example("color3f inputs:base_color = (0.5, 0.4, 0.3)"),
    failing=openpbr_example("color3f inputs:base_color = (0.5, 0.4, 0.3)", shader_id="ND_open_pbr_surface_surfaceshdr"),
    passing_name="example.usda", failing_name="example.usda", formats=("usd",),
)
CONNECTION_TYPE_MISMATCH = Rule(
    "OPBR1005", "usd-connection-type-mismatch", Severity.ERROR,
    "A connection joins attributes whose values cannot line up (a float output into a color3f "
    "input, a float3 interface input into a float).",
    "USD does not convert connected values: renderers read the wrong number of components or fall "
    "back to the input's default. Roles may differ (float3 into color3f is fine); component counts "
    "may not. Texture lookups are judged by OPBR702 instead.",
    passing=openpbr_example(
        "color3f inputs:base_color.connect = </M.inputs:albedo>",
        extra="\n    color3f inputs:albedo = (0.5, 0.4, 0.3)\n",
    ),
    failing=openpbr_example(
        "color3f inputs:base_color.connect = </M.inputs:albedo>",
        extra="\n    float inputs:albedo = 0.5\n",
    ),
    passing_name="example.usda", failing_name="example.usda", formats=("usd",),
)
_PRIMVAR_COLOUR = (
    "color3f inputs:base_color.connect = </M/Colour.outputs:result>",
)
_PRIMVAR_READER = ('\n    def Shader "Colour"\n    {\n        uniform token info:id = "UsdPrimvarReader_float3"\n'
                   '        string inputs:varname = "displayColor"\n        TYPE outputs:result\n    }\n')
OUTPUT_TYPE_DIFFERS = Rule(
    "OPBR1030", "usd-output-type-differs-from-definition", Severity.INFO,
    "A shader's output is authored with another type than its node definition gives it (a "
    "UsdPrimvarReader_float3's result authored as float2).",
    "Renderers build the network from the node's definition, not from the type authored on the prim: Storm takes "
    "Sdr's (usd-core's shaderDefs.usda gives UsdPrimvarReader_float3 a float3 result), hdMtlx MaterialX's. So a "
    "connection is judged on the definition's type (OPBR1005 only where the definition's shape differs from the "
    "input's), and the stage renders as meant (OpenUSD's testUsdImagingGLGeomSubsets authors float2 on a float3 "
    "reader and its baseline renders the colours). What remains is a mistyped declaration that tools reading the "
    "authored types (UsdShade's connection API, exporters) see wrong: an info. Where the id names no known "
    "definition, the authored type is all there is, and connections are judged on it.",
    passing=openpbr_example(*_PRIMVAR_COLOUR, extra=_PRIMVAR_READER.replace("TYPE", "float3")),
    failing=openpbr_example(*_PRIMVAR_COLOUR, extra=_PRIMVAR_READER.replace("TYPE", "float2")),
    passing_name="example.usda", failing_name="example.usda", formats=("usd",),
)
USD_CORE = Rule(
    "OPBR1010", "usd-core-validation", Severity.WARNING,
    "usd-core's own validators (UsdValidation) report a problem the other rules do not cover.",
    "The message is usd-core's, passed through: composition errors, unresolvable references, "
    "material-binding and geometry checks, wrong types on nodes this toolkit does not model. Findings about "
    "shader types, ids, normal maps and texture files that OPBR201/OPBR1002/OPBR1003/OPBR1006/OPBR701 already "
    "report more precisely are left out, and the stage conventions that do not change how materials render "
    "are OPBR1040. The MaterialX node definitions are registered with usd-core first, so OpenPBR shaders raise "
    "no 'not found in sdrRegistry' error; the nodes of other renderers' render contexts (PxrSurface under "
    "outputs:ri:surface, arnold:standard_surface under outputs:arnold:surface, arnold:standard_volume under "
    "outputs:arnold:volume) raise none either, as usd-core on PyPI ships no renderer's plugin to define them.",
    passing=openpbr_example("color3f inputs:base_color = (0.5, 0.4, 0.3)"),
    failing=openpbr_example("color3f inputs:base_color = (0.5, 0.4, 0.3)").rstrip("\n")
    + '\n\ndef Mesh "Ball"\n{\n    rel material:binding = </M>\n}\n',
    passing_name="example.usda", failing_name="example.usda", formats=("usd",),
)
USD_CORE_CONVENTION = Rule(
    "OPBR1040", "usd-core-convention", Severity.INFO,
    "usd-core's validators report a stage convention that does not change how the materials render: "
    "metersPerUnit, upAxis or defaultPrim not authored (StageMetadataChecker), a primvar reader's varname "
    "authored as a token (USD 21.08 and earlier), a UsdPreviewSurface input authored in another float3 role "
    "than declared (float3 for color3f or normal3f); or a finding about the machine, not the file: a shader source "
    "type this usd-core has no parser for (MDL, OSL: MissingSourceTypeInRegistry) and an MDL module named without a "
    "folder (OmniPBR.mdl), which MDL renderers find on their module search path (UnresolvableDependency).",
    "usd-core calls these errors, and they matter where the stage is referenced or placed in a scene (a "
    "reference without a target prim needs defaultPrim; units and axis default to centimetres and Y). Every "
    "material still resolves and binds; a length a material reads without a stage unit is OPBR603's; varname "
    "has been a string since USD 21.11, but readers convert the older token form; and the preview's readers "
    "(Storm, UsdImaging) take the float3 value whatever its role (OPBR1002 says so for MaterialX nodes, where the "
    "role matters). Passed through as notes, so published material libraries and test scenes (the USD working "
    "group's McUsd writes every normal as float3) stay quiet.",
    passing=openpbr_example("color3f inputs:base_color = (0.5, 0.4, 0.3)"),
    failing=openpbr_example("color3f inputs:base_color = (0.5, 0.4, 0.3)").replace('    upAxis = "Y"\n', ""),
    passing_name="example.usda", failing_name="example.usda", formats=("usd",),
)
_SUBSET_MESH = """#usda 1.0
(
    defaultPrim = "Asset"
    metersPerUnit = 1
    upAxis = "Y"
)
def Xform "Asset"
{
    def Material "Oak"
    {
    }
    def Material "Steel"
    {
    }
    def Mesh "Crate" (
        prepend apiSchemas = ["MaterialBindingAPI"]
    )
    {
        int[] faceVertexCounts = [3, 3]
        int[] faceVertexIndices = [0, 1, 2, 0, 2, 3]
        point3f[] points = [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0)]
        rel material:binding = </Asset/Oak>
        uniform token subsetFamily:materialBind:familyType = "nonOverlapping"
        def GeomSubset "band" (
            prepend apiSchemas = ["MaterialBindingAPI"]
        )
        {
            uniform token elementType = "face"
FAMILY            int[] indices = [1]
            rel material:binding = </Asset/Steel>
        }
    }
}
"""
#: usd-core validators whose errors mean a material is bound to other geometry than the file says, or to none:
#: ComputeBoundMaterial and Hydra skip the binding (a GeomSubset outside the materialBind family, a family whose
#: subsets overlap, a binding left with no target).
BINDING_VALIDATORS = frozenset(("SubsetMaterialBindFamilyName", "SubsetFamilies", "MaterialBindingCollectionValidator",
                                "MaterialBindingRelationships"))
#: usd-core validators whose errors break a package (an entry not aligned to 64 bytes, which usd-core cannot read in
#: place) or the composition itself (a cycle of arcs): reported as OPBR1012 and OPBR002, errors as usd-core's are.
PACKAGE_VALIDATORS = frozenset(("RootPackageValidator", "UsdzPackageValidator"))
COMPOSITION_VALIDATORS = frozenset(("CompositionErrorTest",))
USD_CORE_BINDING = Rule(
    "OPBR1025", "usd-core-binding-error", Severity.ERROR,
    "usd-core's validators report an error in how materials are bound: a GeomSubset with a material binding but "
    "no familyName \"materialBind\", subsets of that family that share a face, a materialBind family authored as "
    "'unrestricted', a binding whose target composition dropped (outside the scope of a reference), a binding that "
    "is no relationship.",
    "UsdShadeMaterialBindingAPI only honours a GeomSubset's binding when the subset is in the materialBind family "
    "(GetMaterialBindSubsets returns nothing otherwise), and a family whose subsets overlap is invalid "
    "(UsdGeomSubset.ValidateFamily); a target outside the referenced prim's scope is ignored by composition "
    "(\"outside the scope of the reference\"), which leaves the binding empty. usd-core's validators (the anchor) "
    "call each an error, and the geometry renders with another material than the file says, or with none. A "
    "materialBind family whose familyType is authored 'unrestricted' declares that its subsets may overlap, which "
    "UsdShade forbids (SetMaterialBindSubsetsFamilyType refuses the token; SubsetsMaterialBindFamily is an error); "
    "one whose familyType is not authored reads as 'unrestricted' through UsdGeomSubset's fallback, but UsdShade "
    "documents materialBind subsets as nonOverlapping by default and OpenUSD's own GeomSubsets render test authors "
    "none, so that stays usd-core's OPBR1010 warning. Other usd-core findings are OPBR1010.",
    passing=_SUBSET_MESH.replace("FAMILY", '            uniform token familyName = "materialBind"\n'),
    failing=_SUBSET_MESH.replace("FAMILY", ""),
    passing_name="example.usda", failing_name="example.usda", formats=("usd",),
)


def _package(*entries: tuple[str, str]) -> bytes:
    """A USDZ's bytes: entries stored uncompressed, the root layer first, each entry's data starting at a
    multiple of 64 bytes (the USDZ specification; usd-core's package validators' ByteMisalignment) through
    padding in its local header's extra field."""
    import zipfile  # lazy: only a USDZ example package needs it

    buffer = io.BytesIO()
    with zipfile.ZipFile(buffer, "w", zipfile.ZIP_STORED) as package:
        for name, text in entries:
            info = zipfile.ZipInfo(name)
            start = buffer.tell() + 30 + len(name.encode("utf-8"))  # where the data would start without padding
            padding = (-(start + 4)) % 64
            info.extra = (0x1986).to_bytes(2, "little") + padding.to_bytes(2, "little") + b"\0" * padding
            package.writestr(info, text)
    return buffer.getvalue()


ARC_OUTSIDE = Rule(
    "OPBR1011", "usd-arc-outside-asset", Severity.ERROR,
    "A sublayer, reference, payload or value clip points outside the asset's folder (an absolute "
    "path, '..', a URL, a variable expression, or a symbolic link leading out); it is not opened.",
    "Validating a file never reads files outside its folder: such an arc is deleted (in memory) before "
    "usd-core composes the stage, so whatever the layer it names would contribute is not checked, and "
    "the asset does not survive being copied, checked out elsewhere or packaged. Arcs inside the folder "
    "are followed. Value clips are never read (they hold animation, usd-core opens them lazily, and a "
    "template can name millions of files); only those pointing outside are reported. Texture paths "
    "are OPBR704's concern.",
    passing=openpbr_example("color3f inputs:base_color = (0.5, 0.4, 0.3)"),
    failing=openpbr_example("color3f inputs:base_color = (0.5, 0.4, 0.3)").replace(
        'defaultPrim = "M"\n', 'defaultPrim = "M"\n    subLayers = [@../shared/looks.usda@]\n'),
    passing_name="example.usda", failing_name="example.usda", formats=("usd",),
)
ARC_SHARED_FOLDER = Rule(
    "OPBR1039", "usd-arc-shared-folder", Severity.INFO,
    "A sublayer, reference or payload climbs out of the asset's folder with '..' to a layer that is there (a shared "
    "folder: usd-wg's ../_common); it is not opened.",
    "Relative arcs into a shared folder are how USD asset repositories are laid out (the USD working group's assets "
    "reference ../_common; its Vehicles kit ../materials), and they resolve wherever the tree is checked out, so "
    "this is no defect. The validator still reads nothing outside the asset's folder: what the layer brings is not "
    "checked, and a binding to a material it would compose is not reported as missing. Validate the folder that "
    "holds both (a folder named on the command line is the tree its files may read from) or pass --allow-outside. "
    "An absolute path, a URL, a variable expression, a symbolic link or a '..' to nothing stays OPBR1011.",
    passing=openpbr_example("color3f inputs:base_color = (0.5, 0.4, 0.3)"),
    failing=openpbr_example("color3f inputs:base_color = (0.5, 0.4, 0.3)").replace(
        'defaultPrim = "M"\n', 'defaultPrim = "M"\n    subLayers = [@../shared/looks.usda@]\n'),
    passing_name="assets/example.usda", failing_name="assets/example.usda", formats=("usd",),
    example_files=("shared/looks.usda",),
)
PACKAGE_ENTRY = Rule(
    "OPBR1012", "usdz-unsafe-entry", Severity.ERROR,
    "A USDZ package holds an entry whose name is absolute, climbs out with '..' or contains a "
    "backslash, an entry that is compressed or not aligned to 64 bytes (usd-core's package validators' error), "
    "or an image in a format a package may not hold (a TGA texture) or a MaterialX document.",
    "A tool that extracts the package writes such an entry outside the folder it extracts to (over "
    "/etc/..., or beside the package); the USDZ specification allows only relative names inside the "
    "package and stored (uncompressed) entries, which usd-core reads in place: a compressed texture "
    "does not load. It allows layers, PNG, JPEG, EXR and AVIF images and audio only (usd-core's "
    "FileExtensionValidator): a viewer that conforms does not load a TGA, nor compose the materials of a packaged "
    ".mtlx (usd-core reports both as errors; another file, a LICENSE.txt, renders "
    "nothing either way and stays usd-core's OPBR1010 warning). The names are usd-core's view "
    "of the archive (its local file headers, not the central directory).",
    passing=_package(("root.usda", openpbr_example("color3f inputs:base_color = (0.5, 0.4, 0.3)")), ("albedo.png", "")),
    failing=_package(("root.usda", openpbr_example("color3f inputs:base_color = (0.5, 0.4, 0.3)")), ("../albedo.png", "")),
    passing_name="example.usdz", failing_name="example.usdz", formats=("usd",),
)
MTLX_REFERENCE = Rule(
    "OPBR1013", "usd-references-materialx", Severity.INFO,
    "A sublayer, reference or payload names a MaterialX document (UsdMtlx), which the installed "
    "usd-core cannot open.",
    "UsdMtlx lets a stage reference a .mtlx file directly (`references = @./look.mtlx@`); it is a "
    "plug-in that OpenUSD builds with MaterialX, and the usd-core wheel on PyPI is built without it. "
    "Renderers built with it (usdview, Houdini, Omniverse) compose these materials; this validator cannot, "
    "so it deletes the arc in memory, validates the rest of the stage, and says so here. The MaterialX "
    "document (inside the asset's folder) is validated with the stage: its findings are reported under its "
    "own name, once (a folder that holds it reports them with the document). Not a defect of the file: an "
    "info. A document that does not exist fails the stage as a missing USD layer does (OPBR002).",
    passing=openpbr_example("color3f inputs:base_color = (0.5, 0.4, 0.3)"),
    failing=openpbr_example("color3f inputs:base_color = (0.5, 0.4, 0.3)").replace(
        'defaultPrim = "M"\n', 'defaultPrim = "M"\n    subLayers = [@./look.mtlx@]\n'),
    passing_name="example.usda", failing_name="example.usda", formats=("usd",), example_files=("look.mtlx",),
    failing_files=(("look.mtlx", b'<?xml version="1.0"?>\n<materialx version="1.39">\n  <open_pbr_surface '
                                 b'name="S" type="surfaceshader" />\n</materialx>\n'),),
)


RULES = (MISSING_SHADER_ID, TYPE_ROLE_MISMATCH, UNKNOWN_SHADER_ID, COLORSPACE_SCHEME, CONNECTION_TYPE_MISMATCH,
         OUTPUT_TYPE_DIFFERS, USD_CORE, USD_CORE_BINDING, ARC_OUTSIDE, ARC_SHARED_FOLDER, PACKAGE_ENTRY, MTLX_REFERENCE,
         REMAPPED_NAME, USD_CORE_CONVENTION)

# usd-core's findings on a normal map's scale and bias: said by OPBR1006 where it judges the encoding wrong, by usd-core
# where OPBR1006 accepts an encoding usd-core's validator does not (usd_preview.other_normal_encodings)
_NORMAL_ENCODING = {"NonCompliantBiasAndScale", "NonCompliantScaleValues", "NonCompliantBiasValues"}
# usd-core findings the rules above (or generic ones) report more precisely.
_COVERED_USD_CORE = {
    "NonCompliantBiasAndScale", "NonCompliantScaleValues", "NonCompliantBiasValues", "InvalidSourceColorSpace",
}


def check(asset, context):
    """Runs on USD assets only (rules.FAMILY_FORMATS)."""
    yield from _observations(asset, context)
    yield from _types(asset, context)
    yield from colour_managed_textures(asset, context)
    yield from colour_policies(asset, context)
    yield from _lengths(asset, context)
    yield from _tokens(asset, context)
    yield from _usd_core(asset, context)


# -- structure, ids, connections (colour-space names: usd_colorspaces.py) --------------------------

def set_aside(asset) -> set[str]:
    """The prims whose MaterialX arc was set aside (OPBR1013), as their layers name them; a sublayered
    document's prims sit under /MaterialX (UsdMtlx's root)."""
    arcs = [o for o in asset.observations if o.kind == "usd_mtlx_reference"]
    shared = [o for o in asset.observations if o.kind == "usd_arc_outside" and o.detail.get("shared") and o.location.path]
    return {o.location.path or "/MaterialX" for o in arcs} | {o.location.path for o in shared}


def under(path: str, prims: set[str]) -> bool:
    """Whether ``path`` is one of ``prims`` or below one, also where the prim's layer is referenced below
    another prim of the stage (/Looks/M in looks.usda, /World/Looks/M on the stage)."""
    return any(f"{path}/".startswith(f"{prim}/") or f"/{prim.strip('/')}/" in f"{path}/" for prim in prims)


def _observations(asset, context):
    composed_elsewhere = set_aside(asset)  # materials whose shader is in a MaterialX document set aside
    for observation in asset.observations:
        detail, where = observation.detail, observation.location
        if observation.kind == "usd_material_without_surface":
            if under(detail["material"], composed_elsewhere):
                continue  # its shader is in the MaterialX document set aside
            yield context.diagnostic(
                NO_SHADER, f"material {detail['material']!r} has no surface shader: {detail['reason']}", where,
                hint="connect outputs:mtlx:surface to the OpenPBR shader's outputs:surface (or outputs:surface "
                     "to a UsdPreviewSurface)",
            )
        elif observation.kind == "usd_missing_shader_id" and detail.get("implementation"):
            source = detail["implementation"]
            yield context.diagnostic(
                MISSING_SHADER_ID, f"info:implementationSource is {source!r} but no info:<type>:{source} is authored "
                "(an info:id is then ignored): no renderer knows which node it is", where,
                hint='set info:implementationSource = "id" to use info:id, or author the source',
            )
        elif observation.kind == "usd_missing_shader_id":
            yield context.diagnostic(
                MISSING_SHADER_ID, "shader has no info:id: no renderer knows which node it is", where,
                hint='author uniform token info:id (e.g. "ND_open_pbr_surface_surfaceshader")',
            )
        elif observation.kind == "usd_unknown_shader_id":
            yield from _unknown_id(asset, observation, context)
        elif observation.kind == "usd_connection_type_mismatch":
            yield context.diagnostic(
                CONNECTION_TYPE_MISMATCH,
                f"{detail['input']} ({detail['input_type']}) is connected to {detail['source']} ({detail['source_type']})",
                where, hint=f"connect a source of type {detail['input_type']}, or change the input's type",
            )
        elif observation.kind == "usd_output_type_differs":
            yield context.diagnostic(
                OUTPUT_TYPE_DIFFERS, f"{detail['output']} is authored as {detail['authored']}, but the definition of "
                f"{detail['id']} gives it {detail['defined']}: renderers use the definition's type", where,
                hint=f"author it as {detail['defined']} outputs:{where.input.removeprefix('outputs:')}",
            )
        elif observation.kind == "usd_colorspace":
            yield from colorspace_name(detail, where, context)
        elif observation.kind == "usd_arc_outside" and detail.get("shared"):
            yield context.diagnostic(
                ARC_SHARED_FOLDER, f"{detail['arc']} @{detail['asset']}@ climbs out of the asset's folder to a layer that "
                "is there: not opened, so what it brings is not validated", where,
                hint="validate the folder that holds both, or pass --allow-outside to follow it")
        elif observation.kind == "usd_arc_outside":
            yield context.diagnostic(
                ARC_OUTSIDE, f"{detail['arc']} @{detail['asset']}@ {detail['reason']}: not opened, so not validated",
                where, hint="keep the layers an asset composes inside its folder, with relative paths"
                if detail["arc"] != "value clip" else "value clips are never read by the validator",
            )
        elif observation.kind == "usd_mtlx_reference":
            yield context.diagnostic(
                MTLX_REFERENCE, f"{detail['arc']} @{detail['asset']}@ is a MaterialX document: usd-core is "
                "built without the usdMtlx plugin, so its materials are not composed here", where,
                hint="the document is validated with the stage: its findings are reported under its own name"
                if detail.get("document") else "validate the .mtlx file itself: openpbr validate reads MaterialX",
            )
        elif observation.kind == "usd_package_entry":
            yield context.diagnostic(
                PACKAGE_ENTRY, f"package entry {detail['entry']!r} {detail['reason']}", where,
                hint="convert it to PNG or JPEG and re-create the package" if detail.get("file_type")
                else "re-create the package with usdzip (relative names, stored entries)",
            )


def _unknown_id(asset, observation, context):
    judged = _judge_unknown_id(asset, observation)
    if judged is not None:
        message, guess = judged
        yield context.diagnostic(UNKNOWN_SHADER_ID, message, observation.location,
                                 hint=f"did you mean {guess!r}?" if guess else None)


def _judge_unknown_id(asset, observation) -> tuple[str, str | None] | None:
    """(message, closest known id) when an unknown id is this family's business, else ``None``."""
    shader_id = observation.detail["id"]
    guess = _closest_id(shader_id, asset.extra.get("usd_sdr_ids", ()))
    if guess:
        return f"no node is called {shader_id!r}", guess
    if observation.detail.get("mtlx_context") or shader_id.startswith("ND_"):
        return f"{shader_id!r} is in a MaterialX network but is no MaterialX node definition", None
    return None


def _closest_id(shader_id: str, sdr_ids) -> str | None:
    from ..io.usd.sdr import materialx_nodedef_names  # lazy: ~3 ms kept off validate's start-up; only an unknown id needs it

    candidates = set(surface_shader_ids()) | set(sdr_ids)
    match = difflib.get_close_matches(shader_id, sorted(candidates), n=1, cutoff=0.8)
    if not match and shader_id.startswith("ND_"):
        match = difflib.get_close_matches(shader_id, materialx_nodedef_names(), n=1, cutoff=0.8)
    return match[0] if match else None


# -- types ----------------------------------------------------------------------------------------

_FLOAT3_ROLES = {"float3", "color3f", "normal3f", "vector3f", "point3f"}


def _preview_roles(asset) -> set[str]:
    """The attribute paths of UsdPreviewSurface inputs authored with another float3 role than declared (float3 for a
    color3f), which OPBR1002 lets pass (its readers take any role) and usd-core's ShaderSdrCompliance calls a
    MismatchedPropertyType, which is then passed through as a note (OPBR1040) rather than lost."""
    found = set()
    for material, table, entry in for_each_input(asset):
        parameter = table.get(entry.name)
        if material.model != "UsdPreviewSurface" or parameter is None or entry.source_type is None:
            continue
        expected = expected_usd_type(material.extra.get("usd_flavour", "mtlx"), material.model, entry.name,
                                     parameter.type)
        if expected is not None and entry.source_type != expected and {entry.source_type, expected} <= _FLOAT3_ROLES:
            found.add(f"{material.location.path}.inputs:{entry.name}")
    return found


def _types(asset, context):
    for material, table, entry in for_each_input(asset):
        parameter = table.get(entry.name)
        if parameter is None or entry.source_type is None or entry.type != parameter.type:
            continue  # unknown inputs and real type mismatches are OPBR101/OPBR201
        flavour = material.extra.get("usd_flavour", "mtlx")
        expected = expected_usd_type(flavour, material.model, entry.name, parameter.type)
        if expected is None or entry.source_type == expected:
            continue
        if material.model == "UsdPreviewSurface" and {entry.source_type, expected} <= _FLOAT3_ROLES:
            continue  # a role of the same float3 value: UsdPreviewSurface readers take it as declared
        node = material.extra.get("info_id", material.model)
        yield context.diagnostic(
            TYPE_ROLE_MISMATCH, f"{entry.name} is {entry.source_type}; {node} declares it {expected}",
            entry.location, hint=f"author it as {expected} inputs:{entry.name}",
        )


# -- units ----------------------------------------------------------------------------------------

def _lengths(asset, context):
    if asset.meters_per_unit is not None:
        return
    default = load_json("units.json")["usd_default_meters_per_unit"]
    for material, table, entry in for_each_input(asset):
        parameter = table.get(entry.name)
        if parameter is None or parameter.unit != "scene_length" or entry.value is None or entry.error:
            continue
        yield context.diagnostic(
            LENGTH_WITHOUT_UNIT,
            f"{entry.name} is a length in scene units but the stage does not author metersPerUnit, "
            f"so USD's default {default:g} (centimetres) applies",
            entry.location, hint="author metersPerUnit in the root layer's metadata",
        )


# -- tokens ---------------------------------------------------------------------------------------

def _tokens(asset, context):
    seen = set()
    for material, table, entry in for_each_input(asset):
        if material.model == "UsdPreviewSurface" and entry.name == "opacityMode" and isinstance(entry.constant, str):
            yield context.diagnostic(
                ENUM_VALUE, f"opacityMode = {entry.constant!r} is not one of {list(OPACITY_MODE_TOKENS)}",
                entry.location, hint="use \"transparent\" or \"presence\"",
            )
        texture = entry.texture
        # (a MaterialX image node's address modes are its node definition's enum, which the reader observes for every
        # MaterialX node of the stage: said there, once, as OPBR303)
        if texture is None or texture.wrap is None or texture.node in seen or texture.node_category != UV_TEXTURE_ID:
            continue
        seen.add(texture.node)
        for name, value in zip(("wrapS", "wrapT"), texture.wrap):
            if value not in UV_TEXTURE_WRAP_TOKENS:
                yield context.diagnostic(
                    ENUM_VALUE, f"{name} = {value!r} is not one of {list(UV_TEXTURE_WRAP_TOKENS)}",
                    Location(asset.path, None, texture.node, name),
                )


# -- usd-core -------------------------------------------------------------------------------------

_SOURCE_TYPE = re.compile(r"sourceType '([^']*)'")
_DEPENDENCY = re.compile(r"unresolvable external dependency '([^']*)'")


_IMAGE_FILE = re.compile(r"\.(png|jpe?g|exr|hdr|tiff?|tx|tga|bmp|gif|webp|ktx2?|dds|psd)$", re.IGNORECASE)
_SHADER_SOURCE = re.compile(r"\.(glslfx|osl|oso)$", re.IGNORECASE)  # (not MDL: a renderer's module search path)
_TYPES = re.compile(r"Expected '([^']+)'; got '([^']+)'")


def _as_rule(finding: dict):
    """The rule that says what a usd-core error means for the materials (the red team's D3-D5: an error of the anchor
    must not be a warning here): an image that does not resolve (a time sample's file, which the readers do not
    follow) is a missing texture, OPBR701; a shader's source file that does not resolve leaves it without a
    definition, OPBR1001; a value of another shape than its declaration (float3 for UsdUVTexture's float4 fallback),
    OPBR201. Else None."""
    found = _DEPENDENCY.search(finding["message"]) if finding["name"] == "UnresolvableDependency" else None
    if found is not None:
        return MISSING_TEXTURE if _IMAGE_FILE.search(found.group(1)) else \
            MISSING_SHADER_ID if _SHADER_SOURCE.search(found.group(1)) else None
    types = _TYPES.search(finding["message"]) if finding["name"] == "MismatchedPropertyType" else None
    if types is not None and _width(types.group(1)) != _width(types.group(2)):
        return TYPE_MISMATCH
    if types is not None and _textual(types.group(1)) != _textual(types.group(2)):
        return TYPE_MISMATCH  # (a number where a name belongs: an int varname names no primvar; the red team's F#9)
    return None


def _textual(usd_type: str) -> bool:
    return usd_type.strip("'\" ").lower() in ("string", "token", "asset")


def _width(usd_type: str) -> int:
    """How many numbers a USD value type holds (float3, color3f, texCoord2f: 3 or 2; float, int64, token: 1; matrix4d:
    16); an array's, per element."""
    name = usd_type.removesuffix("[]").lower()
    if name.startswith("matrix"):
        return int(name[6]) ** 2 if name[6:7].isdigit() else 1
    found = re.search(r"(\d)[a-z]*$", name) if not re.search(r"int64$|int$|uint$", name) else None
    return int(found.group(1)) if found else 1


def _environmental(finding: dict) -> bool:
    """A usd-core finding about the machine rather than the file: a shader's sourceType (mdl, osl) for which this
    usd-core has no parser plugin (pip's knows glslfx and USD's own definitions), or an MDL module named without a folder
    (``OmniPBR.mdl``), which an MDL renderer finds on its own module search path, not through USD's resolver."""
    name, message = finding["name"], finding["message"]
    if name == "MissingSourceTypeInRegistry":
        found = _SOURCE_TYPE.search(message)
        return found is not None and found.group(1) not in finding.get("parsed_source_types", (found.group(1),))
    if name == "UnresolvableDependency":
        found = _DEPENDENCY.search(message)
        return found is not None and found.group(1).lower().endswith(".mdl") and not re.search(r"[/\\:]", found.group(1))
    return False


_BINDING_TARGET = re.compile(r"targets an invalid material <([^>]*)>")


def _usd_core(asset, context):
    findings = asset.extra.get("usd_core_findings") or ()
    read_shaders = {m.location.path for m in asset.materials}
    reported_ids = {o.location.path for o in asset.observations
                    if o.kind == "usd_unknown_shader_id" and _judge_unknown_id(asset, o) is not None}
    texture_files = {t.file for m in asset.materials for _, t in m.textures()}
    renderer_nodes = set(asset.extra.get("usd_renderer_context_shaders", ()))
    # prims whose MaterialX arc was deleted (OPBR1013): usd-core finds them empty, as it would not with usdMtlx
    composed_elsewhere = set_aside(asset)
    invalid_bindings = {o.detail["target"] for o in asset.observations if o.kind == "usd_binding_invalid"}
    bound_prims = {o.location.path for o in asset.observations if o.kind == "usd_binding_invalid"}
    packaged = {o.detail["entry"] for o in asset.observations if o.kind == "usd_package_entry" and o.detail.get("file_type")}
    preview_roles = _preview_roles(asset)
    other_encodings = other_normal_encodings(asset)  # (OPBR1006 accepts them; usd-core's validator does not)
    missing_layers = [o for o in asset.observations if o.kind == "usd_layer_missing"]
    for finding in findings:
        name, sites = finding["name"], finding["sites"]
        prims = {site.split(".", 1)[0] for site in sites}
        if name in _COVERED_USD_CORE and sites and sites[0].split(".", 1)[0] in read_shaders and \
                not (name in _NORMAL_ENCODING and prims & other_encodings):
            continue  # the rules judge the read shaders' normal maps (a preview not wired to a Material's output: usd-core's)
        if name == "UnsupportedFileExtensionInPackage" and any(f"'{entry}'" in finding["message"] for entry in packaged):
            continue  # OPBR1012 reports the image
        if name == "MismatchedPropertyType" and prims and prims <= read_shaders and not set(sites) & preview_roles:
            continue  # OPBR201/OPBR1002 judge the read shaders' types, but for a preview's role, which they allow (OPBR1040)
        if name == "MissingShaderIdInRegistry" and prims and prims <= reported_ids:
            continue
        if name == "MissingShaderIdInRegistry" and prims and prims <= renderer_nodes:
            continue  # another renderer's node (PxrSurface under ri): pip usd-core ships no renderer's definitions
        bound = _BINDING_TARGET.search(finding["message"]) if name == "InvalidResourcePath" else None
        if bound and under(bound.group(1), composed_elsewhere):
            continue  # a binding to a material composed from a MaterialX document this usd-core cannot open
        if bound and (bound.group(1) in invalid_bindings or prims & bound_prims):
            continue  # OPBR1017 reports it, with why
        if name in ("UnresolvableDependency", "InvalidFile") and any(
                f"@{file}@" in finding["message"] or f"'{file}'" in finding["message"] for file in texture_files):
            continue  # OPBR701 reports missing textures
        if name in ("CompositionError", "UnresolvableDependency") and any(
                o.detail["reason"] in finding["message"] or (o.detail.get("layer") and o.detail["layer"] in
                                                             finding["message"]) for o in missing_layers):
            continue  # OPBR1042 reports the missing layer (rules.usd_stage)
        dependency = _DEPENDENCY.search(finding["message"]) if name == "UnresolvableDependency" else None
        if dependency and os.path.basename(dependency.group(1)) in {os.path.basename(f) for f in texture_files}:
            continue  # (the same texture, which usd-core names as it resolved it: OPBR701/OPBR704 report it)
        site = sites[0] if sites else ""
        prim, _, attribute = site.partition(".")
        validator = finding["identifier"].rsplit(":", 1)[-1].split(".")[0]
        rule = USD_CORE
        if validator == "StageMetadataChecker" or (name == "MismatchedPropertyType" and (
                attribute == "inputs:varname" and "'token'" in finding["message"] or set(sites) & preview_roles)) \
                or _environmental(finding):
            rule = USD_CORE_CONVENTION  # (its message names the authored type: usd-core's words, the anchor's)
        elif finding["severity"] == "error":  # usd-core's errors where the stage then renders wrong: as the anchor says
            binding = validator in BINDING_VALIDATORS or (validator == "SubsetsMaterialBindFamily" and finding.get("authored"))
            rule = (USD_CORE_BINDING if binding else PACKAGE_ENTRY if validator in PACKAGE_VALIDATORS
                    else NOT_MATERIALX if validator in COMPOSITION_VALIDATORS else _as_rule(finding) or USD_CORE)
        yield context.diagnostic(
            rule, f"usd-core {finding['identifier']}: {finding['message']}",
            Location(asset.path, None, prim or None, (attribute.removeprefix("inputs:")) or None),
        )
