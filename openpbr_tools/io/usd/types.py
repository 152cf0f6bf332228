"""What the toolkit knows about OpenPBR and UsdPreviewSurface in USD, without importing ``pxr``.

The USD reader, the writer and the USD rules share these facts, and the rules must stay importable
(and cheap) when no USD file is involved, so nothing here touches ``pxr``.

* Types follow UsdMtlx (OpenUSD ``pxr/usd/usdMtlx/utils.cpp``, ``UsdMtlxGetUsdType``): a MaterialX
  ``color3`` input is ``color3f`` in USD, ``vector3`` is ``float3``, ``boolean`` is ``bool``,
  ``integer`` is ``int``, ``filename`` is ``asset``. USD-native shaders (``UsdPreviewSurface``)
  declare their own types in usd-core's ``usdShaders/shaderDefs.usda``: there ``normal`` is
  ``normal3f`` and ``opacityMode`` a ``token``.
* Shader ids: MaterialX node definitions are named ``ND_<node>_<type>`` (versioned ones end in the
  version's digits, ``ND_standard_surface_surfaceshader_100`` is 1.0.0); USD-native nodes are
  ``UsdPreviewSurface``, ``UsdUVTexture``, ``UsdTransform2d``, ``UsdPrimvarReader_<type>``.
* Colour-space names come in three schemes (see ``schemas/colorspaces.json``): MaterialX names on
  the inputs of MaterialX shaders (UsdMtlx writes them there and Hydra's hdMtlx hands them to
  MaterialX unchanged), USD (Gf) names in ``Usd.ColorSpaceAPI`` and on USD-native shaders, and
  UsdUVTexture's ``sourceColorSpace`` tokens.
"""

from __future__ import annotations

import re
from functools import cache

from ... import tables, versioning

#: MaterialX type -> the USD type UsdMtlx gives it.
MATERIALX_TO_USD = {
    "float": "float",
    "integer": "int",
    "boolean": "bool",
    "string": "string",
    "filename": "asset",
    "color3": "color3f",
    "color4": "color4f",
    "vector2": "float2",
    "vector3": "float3",
    "vector4": "float4",
    "matrix33": "matrix3d",
    "matrix44": "matrix4d",
}

#: USD value type -> the MaterialX type its values read as (roles and precisions collapse).
USD_TO_MATERIALX = {
    "float": "float", "double": "float", "half": "float",
    "int": "integer", "uint": "integer", "int64": "integer", "uchar": "integer",
    "bool": "boolean",
    "string": "string", "token": "string",
    "asset": "filename",
    "color3f": "color3", "color3d": "color3", "color3h": "color3",
    "color4f": "color4", "color4d": "color4", "color4h": "color4",
    "float2": "vector2", "double2": "vector2", "half2": "vector2", "texCoord2f": "vector2",
    "texCoord2d": "vector2", "texCoord2h": "vector2",
    "float3": "vector3", "double3": "vector3", "half3": "vector3", "vector3f": "vector3",
    "vector3d": "vector3", "vector3h": "vector3", "normal3f": "vector3", "normal3d": "vector3",
    "normal3h": "vector3", "point3f": "vector3", "point3d": "vector3", "point3h": "vector3",
    "texCoord3f": "vector3", "texCoord3d": "vector3", "texCoord3h": "vector3",
    "float4": "vector4", "double4": "vector4", "half4": "vector4",
    "matrix3d": "matrix33", "matrix4d": "matrix44",
}

#: MaterialX types that differ only in role (USD may carry either; the nodedef decides).
SAME_SHAPE = {"color3": "vector3", "vector3": "color3", "color4": "vector4", "vector4": "color4"}

#: UsdPreviewSurface inputs whose USD type is not the UsdMtlx image of the MaterialX nodedef's
#: type (usd-core usdShaders/shaderDefs.usda; tests/test_usd_types.py checks against Sdr).
PREVIEW_SURFACE_USD_TYPES = {"normal": "normal3f", "opacityMode": "token"}
#: opacityMode is a token in USD and an integer enum in the MaterialX nodedef.
OPACITY_MODE_TOKENS = ("transparent", "presence")

PREVIEW_SURFACE_ID = "UsdPreviewSurface"
UV_TEXTURE_ID = "UsdUVTexture"
TRANSFORM_2D_ID = "UsdTransform2d"
PRIMVAR_READER_PREFIX = "UsdPrimvarReader_"
#: UsdUVTexture outputs -> channel indices (``rgb`` is all three, ``None``).
UV_TEXTURE_OUTPUTS = {"r": (0,), "g": (1,), "b": (2,), "a": (3,), "rgb": None}
UV_TEXTURE_WRAP_TOKENS = ("black", "clamp", "repeat", "mirror", "useMetadata")
MATERIALX_ADDRESS_MODES = ("constant", "clamp", "periodic", "mirror")
#: UsdUVTexture wrap token -> MaterialX address mode, and back.
WRAP_TO_ADDRESS_MODE = {"black": "constant", "clamp": "clamp", "repeat": "periodic", "mirror": "mirror"}
ADDRESS_MODE_TO_WRAP = {v: k for k, v in WRAP_TO_ADDRESS_MODE.items()}
#: Image formats stored with 8 bits per channel: UsdUVTexture's ``auto`` reads their RGB(A) as
#: sRGB, and normal maps in them need scale 2 / bias -1 (UsdPreviewSurface spec, ``normal``).
EIGHT_BIT_SUFFIXES = (".png", ".jpg", ".jpeg", ".bmp", ".tga", ".gif")

#: Surface outputs of a Material, by render context ("" is the universal one).
MATERIALX_CONTEXT = "mtlx"
#: render contexts whose nodes usd-core's own registry defines: the universal one (""), Storm's glslfx
UNIVERSAL_CONTEXTS = ("", "glslfx")

_VERSION_SUFFIX = re.compile(r"^(ND_[A-Za-z0-9_]+_surfaceshader)_(\d+)$")


@cache
def surface_shader_ids() -> dict[str, tuple[str, str | None, str]]:
    """Shader id -> (model, version or None, flavour) for every surface shader the toolkit reads.

    ``version`` is ``None`` for an unversioned MaterialX id, whose version is then inferred from
    the input names (the unversioned name is simply whatever version was current when the file
    was written). ``flavour`` is ``"mtlx"`` for MaterialX node definitions, ``"usd"`` for USD's
    own UsdPreviewSurface.
    """
    nodedef_versions = getattr(versioning, "nodedef_versions", None) or versioning._nodedef_versions
    found: dict[str, tuple[str, str | None, str]] = {}
    for model in tables.MODELS:
        for version in tables.versions(model):
            found.setdefault(f"ND_{model}_surfaceshader_{version.replace('.', '')}", (model, version, "mtlx"))
        for nodedef, version in nodedef_versions(model).items():
            found[nodedef] = (model, version if _VERSION_SUFFIX.match(nodedef) else None, "mtlx")
        current = tables.table(model).nodedef
        if current:
            found[current] = (model, None, "mtlx")
    found[PREVIEW_SURFACE_ID] = ("UsdPreviewSurface", None, "usd")
    return found


def expected_usd_type(flavour: str, model: str, name: str, materialx_type: str) -> str | None:
    """The USD type an input of ``model`` should be authored with."""
    if flavour == "usd" and model == "UsdPreviewSurface" and name in PREVIEW_SURFACE_USD_TYPES:
        return PREVIEW_SURFACE_USD_TYPES[name]
    return MATERIALX_TO_USD.get(materialx_type)


def materialx_type_of(usd_type: str, expected_materialx: str | None = None) -> str:
    """The MaterialX type an authored USD type reads as. When the parameter's own type has the same
    shape (``float3`` for a ``color3``), the parameter's type is returned: values line up and the
    role difference is judged separately (OPBR1002)."""
    base = USD_TO_MATERIALX.get(usd_type)
    if base is None:
        return usd_type  # arrays, matrices of the wrong kind...: shown as the USD name
    if expected_materialx and SAME_SHAPE.get(base) == expected_materialx:
        return expected_materialx
    return base


def is_eight_bit(file: str) -> bool:
    return file.lower().endswith(EIGHT_BIT_SUFFIXES)
