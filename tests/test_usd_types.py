"""The USD type and id facts the reader, writer and rules share, checked against usd-core itself
and against OpenUSD's own MaterialX bridge."""

from __future__ import annotations

import pytest

from openpbr_tools import tables
from openpbr_tools.io.usd.types import (
    MATERIALX_TO_USD,
    PREVIEW_SURFACE_USD_TYPES,
    expected_usd_type,
    materialx_type_of,
    surface_shader_ids,
)

# OpenUSD pxr/imaging/hdMtlx/hdMtlx.cpp, _ConvertToMtlxType: the USD type -> MaterialX type table
# Hydra uses when it turns a USD shading network into a MaterialX document (copied by hand from
# the source as the independent reference; our table is its inverse).
HDMTLX_USD_TO_MATERIALX = {
    "bool": "boolean", "int": "integer", "float": "float", "color3f": "color3", "color4f": "color4",
    "float2": "vector2", "float3": "vector3", "float4": "vector4", "matrix3d": "matrix33",
    "matrix4d": "matrix44", "asset": "filename", "string": "string",
}


def test_materialx_to_usd_is_the_inverse_of_hydras_table():
    assert {usd: mx for mx, usd in MATERIALX_TO_USD.items()} == HDMTLX_USD_TO_MATERIALX


def test_preview_surface_types_match_usd_cores_shader_definition():
    from pxr import Sdr

    node = Sdr.Registry().GetShaderNodeByIdentifier("UsdPreviewSurface")
    table = tables.table("UsdPreviewSurface")
    for name, parameter in table.parameters.items():
        declared = str(node.GetShaderInput(name).GetTypeAsSdfType().GetSdfType())
        assert expected_usd_type("usd", "UsdPreviewSurface", name, parameter.type) == declared, name
    assert set(PREVIEW_SURFACE_USD_TYPES) <= set(table.parameters)


@pytest.mark.parametrize(
    "usd_type, parameter_type, read_as",
    [("color3f", "color3", "color3"), ("float3", "color3", "color3"), ("normal3f", "vector3", "vector3"),
     ("color3f", "vector3", "vector3"), ("float3", None, "vector3"), ("float", "color3", "float"),
     ("double", "float", "float"), ("bool", "boolean", "boolean"), ("float[]", "float", "float[]")],
)
def test_usd_types_read_as_materialx_types(usd_type, parameter_type, read_as):
    assert materialx_type_of(usd_type, parameter_type) == read_as


def test_shader_ids_cover_every_model_and_the_versioned_openpbr_ids():
    ids = surface_shader_ids()
    assert ids["ND_open_pbr_surface_surfaceshader"] == ("open_pbr_surface", None, "mtlx")
    assert ids["ND_open_pbr_surface_surfaceshader_111"] == ("open_pbr_surface", "1.1.1", "mtlx")
    assert ids["ND_open_pbr_surface_surfaceshader_05"] == ("open_pbr_surface", "0.5", "mtlx")
    assert ids["ND_standard_surface_surfaceshader_100"] == ("standard_surface", "1.0.0", "mtlx")
    assert ids["UsdPreviewSurface"] == ("UsdPreviewSurface", None, "usd")
    assert ids["ND_UsdPreviewSurface_surfaceshader"][0] == "UsdPreviewSurface"
