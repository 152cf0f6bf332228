"""MaterialX reading and writing: what the reader sees, and that a round trip keeps it."""

from __future__ import annotations

import pytest

from openpbr_tools.io import ReadError, read_asset
from openpbr_tools.io.mtlx.writer import to_mtlx_string, write_mtlx
from openpbr_tools.model import Connection, Constant, Texture

RICH = """<?xml version="1.0"?>
<materialx version="1.39" colorspace="acescg">
  <nodegraph name="NG" colorspace="srgb_texture">
    <texcoord name="uv1" type="vector2">
      <input name="index" type="integer" value="1" />
    </texcoord>
    <place2d name="placement" type="vector2">
      <input name="texcoord" type="vector2" nodename="uv1" />
      <input name="scale" type="vector2" value="2, 3" />
      <input name="rotate" type="float" value="45" />
      <input name="offset" type="vector2" value="0.25, 0.5" />
    </place2d>
    <image name="albedo" type="color3">
      <input name="file" type="filename" value="tex/wood_<UDIM>.png" />
      <input name="texcoord" type="vector2" nodename="placement" />
    </image>
    <output name="albedo_out" type="color3" nodename="albedo" />
  </nodegraph>
  <image name="orm" type="color3">
    <input name="file" type="filename" value="tex/orm.png" colorspace="none" />
  </image>
  <extract name="roughness" type="float">
    <input name="in" type="color3" nodename="orm" />
    <input name="index" type="integer" value="1" />
  </extract>
  <image name="normal_image" type="vector3">
    <input name="file" type="filename" value="tex/normal.png" />
  </image>
  <normalmap name="normal_decode" type="vector3">
    <input name="in" type="vector3" nodename="normal_image" />
    <input name="scale" type="float" value="0.5" />
  </normalmap>
  <noise3d name="grain" type="float">
    <input name="amplitude" type="float" value="0.3" />
  </noise3d>
  <open_pbr_surface name="Wood" type="surfaceshader" version="1.1.1">
    <input name="base_color" type="color3" nodegraph="NG" output="albedo_out" />
    <input name="specular_roughness" type="float" nodename="roughness" />
    <input name="geometry_normal" type="vector3" nodename="normal_decode" />
    <input name="coat_weight" type="float" nodename="grain" />
    <input name="coat_color" type="color3" value="0.9, 0.8, 0.7" colorspace="lin_rec709" />
    <input name="specular_ior" type="float" value="1.45" />
    <input name="transmission_depth" type="float" value="2.5" unittype="distance" unit="centimeter" />
    <input name="geometry_thin_walled" type="boolean" value="false" />
  </open_pbr_surface>
  <surfacematerial name="WoodMaterial" type="material">
    <input name="surfaceshader" type="surfaceshader" nodename="Wood" />
  </surfacematerial>
  <standard_surface name="Legacy" type="surfaceshader">
    <input name="base" type="float" value="0.9" />
    <input name="metalness" type="float" value="1" />
  </standard_surface>
  <look name="Default">
    <materialassign name="assign" material="WoodMaterial" geom="/root/plank" />
  </look>
</materialx>
"""


@pytest.fixture
def rich(tmp_path):
    path = tmp_path / "rich.mtlx"
    path.write_text(RICH, encoding="utf-8")
    return read_asset(path)


def test_reader_finds_every_shader_and_its_material(rich):
    by_name = {m.name: m for m in rich.materials}
    assert set(by_name) == {"Wood", "Legacy"}
    assert by_name["Wood"].model == "open_pbr_surface"
    assert by_name["Wood"].material_name == "WoodMaterial"
    assert by_name["Legacy"].model == "standard_surface"
    assert by_name["Legacy"].material_name is None


def test_reader_records_document_facts(rich):
    assert rich.format == "mtlx"
    assert rich.format_version == "1.39"
    assert rich.colorspace == "acescg"


def test_texture_through_nodegraph_output_with_placement_and_uv_set(rich):
    texture = next(m for m in rich.materials if m.name == "Wood").inputs["base_color"].value
    assert isinstance(texture, Texture)
    assert texture.file == "tex/wood_<UDIM>.png" and texture.is_udim
    assert texture.colorspace == "srgb_texture"  # inherited from the node graph, not the document
    assert texture.uv.scale == (2.0, 3.0) and texture.uv.rotate == 45.0 and texture.uv.offset == (0.25, 0.5)
    assert texture.texcoord == 1


def test_extracted_channel_and_normal_map(rich):
    wood = next(m for m in rich.materials if m.name == "Wood")
    roughness = wood.inputs["specular_roughness"].value
    assert roughness.file == "tex/orm.png" and roughness.channels == (1,) and roughness.colorspace == "none"
    normal = wood.inputs["geometry_normal"].value
    assert normal.normal_map == 0.5 and normal.image_type == "vector3"


def test_procedural_input_is_kept_as_connection(rich):
    coat = next(m for m in rich.materials if m.name == "Wood").inputs["coat_weight"].value
    assert isinstance(coat, Connection) and coat.category == "noise3d" and not coat.dangling


def test_constants_units_and_colorspaces(rich):
    wood = next(m for m in rich.materials if m.name == "Wood")
    assert wood.inputs["coat_color"].constant == (0.9, 0.8, 0.7)
    assert wood.inputs["coat_color"].colorspace == "lin_rec709"
    assert wood.inputs["transmission_depth"].unit == "centimeter"
    assert wood.inputs["transmission_depth"].unittype == "distance"
    assert wood.inputs["geometry_thin_walled"].constant is False
    assert wood.version == "1.1.1" and wood.version_basis == "node version attribute"


def test_line_numbers_point_at_the_element(rich, tmp_path):
    wood = next(m for m in rich.materials if m.name == "Wood")
    lines = RICH.splitlines()
    assert "specular_ior" in lines[wood.inputs["specular_ior"].location.line - 1]
    assert 'name="Wood"' in lines[wood.location.line - 1]


def _snapshot(asset):
    """Every value and connection of every material, in comparable form."""
    result = {}
    for material in asset.materials:
        for name, entry in material.inputs.items():
            value = entry.value
            if isinstance(value, Constant):
                shown = ("constant", value.value, entry.colorspace if entry.type == "color3" else None, entry.unit)
            elif isinstance(value, Texture):
                shown = ("texture", value.file, value.image_type, value.channels, value.colorspace,
                         value.uv.scale if value.uv else None, value.uv.rotate if value.uv else None,
                         value.uv.offset if value.uv else None, value.texcoord, value.normal_map)
            else:
                shown = ("connection", value.category, value.dangling)
            result[(material.model, material.name, name)] = shown
    return result


def test_round_trip_keeps_every_value_and_connection(rich, tmp_path):
    out = tmp_path / "out.mtlx"
    write_mtlx(rich.materials, out, colorspace=rich.colorspace)
    again = read_asset(out)
    assert _snapshot(again) == _snapshot(rich)


def test_round_trip_output_is_deterministic(rich):
    assert to_mtlx_string(rich.materials, "acescg") == to_mtlx_string(rich.materials, "acescg")


def test_written_document_is_valid_materialx(rich, tmp_path):
    import MaterialX as mx

    from openpbr_tools.io.mtlx.library import standard_library

    document = mx.createDocument()
    mx.readFromXmlString(document, to_mtlx_string(rich.materials, "acescg"))
    document.setDataLibrary(standard_library())
    valid, message = document.validate()
    assert valid, message


@pytest.mark.parametrize(
    "content, kind",
    [
        (b"", "not_materialx"),
        (b"\x00\x01\x02\xff\xfe garbage", "unreadable"),
        (b'<?xml version="1.0"?>\n<materialx version="1.39">\n  <open_pbr_surface name="S"', "not_materialx"),
        (b'<?xml version="1.0"?>\n<html><body/></html>\n', "not_materialx"),
    ],
    ids=["empty", "binary", "truncated", "not-materialx-root"],
)
def test_unreadable_documents_raise_read_error(tmp_path, content, kind):
    path = tmp_path / "bad.mtlx"
    path.write_bytes(content)
    with pytest.raises(ReadError) as caught:
        read_asset(path)
    assert caught.value.kind == kind


def test_truncated_document_reports_the_line(tmp_path):
    path = tmp_path / "bad.mtlx"
    path.write_bytes(b'<?xml version="1.0"?>\n<materialx version="1.39">\n  <open_pbr_surface name="S" type="surfaceshader">\n')
    with pytest.raises(ReadError) as caught:
        read_asset(path)
    assert caught.value.location.line == 4  # expat reports the end of input, after the last line
