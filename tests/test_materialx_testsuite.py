"""MaterialX's own unit-test documents (tests/data/published/materialx/resources/Materials/TestSuite, verbatim;
SOURCES.md) read as MaterialX reads them, and converted to documents MaterialX accepts: each holds a construct
the example library does not (a vector2 normalmap scale, multi-output nodes, graph-to-graph connections,
nodedef-wrapped shaders whose file is an interface input, UsdUVTexture on tiled coordinates, definitions
built of definitions, a default geometric property on an interface, looks on collections). Before these
were handled the reader raised on one, reported existing nodes as missing on three, read image files as
empty on three, dropped a UV tiling without a word, and five converted outputs failed MaterialX's own
Document.validate()."""

from __future__ import annotations

from pathlib import Path

import pytest

from glsupport import shader_generator, validated
from openpbr_tools.convert import convert_file
from openpbr_tools.io import ReadError, read_asset
from openpbr_tools.model import Connection, Texture
from openpbr_tools.translate.common import Settings
from openpbr_tools.validate import Options, validate_paths

SUITE = Path(__file__).resolve().parent / "data" / "published" / "materialx" / "resources" / "Materials" / "TestSuite"
FILES = sorted(p.relative_to(SUITE).as_posix() for p in SUITE.rglob("*.mtlx"))
TARGETS = ("open_pbr_surface", "standard_surface", "gltf_pbr", "UsdPreviewSurface")


def _codes(path) -> list[str]:
    return sorted(d.code for d in validate_paths([str(path)], options=Options(use_config=False, jobs=1)).diagnostics)


def test_the_suite_is_vendored():
    assert len(FILES) == 12


@pytest.mark.parametrize("name", FILES)
@pytest.mark.parametrize("target", TARGETS)
def test_every_conversion_validates_and_generates_a_shader_in_materialx(tmp_path, name, target):
    out = tmp_path / "out.mtlx"
    if name.endswith("definition_reduced_interface.mtlx"):
        # its one shader is of a category no nodedef declares: nothing to convert, so nothing is written
        with pytest.raises(ReadError) as refused:
            convert_file(str(SUITE / name), str(out), target, Settings())
        assert refused.value.kind == "no_material" and not out.exists()
        return
    convert_file(str(SUITE / name), str(out), target, Settings())
    _, generator, context = shader_generator()
    document = validated(out)
    import MaterialX.PyMaterialXGenShader as gs  # lazy: as glsupport.shader_generator

    renderable = gs.findRenderableElements(document)
    assert renderable
    for element in renderable:
        assert generator.generate("check", element, context).getSourceCode(gs.PIXEL_STAGE)


def test_a_vector2_normalmap_scale_is_read_as_its_strength():
    # normalmapped_surfaceshader.mtlx: ND_normalmap_vector2's scale "1.1, 1.1" (it raised a TypeError)
    materials = read_asset(str(SUITE / "pbrlib/surfaceshader/normalmapped_surfaceshader.mtlx")).materials
    strengths = sorted(m.inputs["normal"].texture.normal_map for m in materials)
    assert strengths == [1.1, 1.1]


def test_a_non_uniform_vector2_normalmap_scale_keeps_the_graph(write_mtlx):
    path = write_mtlx('''<image name="n" type="vector3">
  <input name="file" type="filename" value="n.png" colorspace="none" />
</image>
<normalmap name="d" type="vector3">
  <input name="in" type="vector3" nodename="n" />
  <input name="scale" type="vector2" value="1, 0.5" />
</normalmap>
<open_pbr_surface name="S" type="surfaceshader">
  <input name="geometry_normal" type="vector3" nodename="d" />
</open_pbr_surface>''', files=("n.png",))
    entry = read_asset(str(path)).materials[0].inputs["geometry_normal"]
    assert isinstance(entry.value, Connection) and entry.value.graph_xml  # not read as one strength


@pytest.mark.parametrize("name", ["stdlib/procedural/flake.mtlx", "pbrlib/surfaceshader/flake_surfaceshader.mtlx",
                                  "stdlib/nodegraphs/nodegraph_nodegraph.mtlx"])
def test_a_connection_to_a_multi_output_nodes_own_output_is_not_dangling(name):
    # <input nodename="flake2d" output="flakenormal"/>: the output is the node's child, not a graph's
    assert "OPBR802" not in _codes(SUITE / name)


def test_an_image_file_bound_to_a_graph_input_is_read_from_it():
    # nodegraph_nodegraph.mtlx: <input name="file" interfacename="file"/> inside upstream_graph
    materials = read_asset(str(SUITE / "stdlib/nodegraphs/nodegraph_nodegraph.mtlx")).materials
    files = sorted({m.inputs["base_color"].texture.file for m in materials
                    if isinstance(m.inputs.get("base_color") and m.inputs["base_color"].value, Texture)})
    assert files == ["resources/Images/cloth.png", "resources/Images/grid.png"]
    assert "OPBR705" not in _codes(SUITE / "stdlib/nodegraphs/nodegraph_nodegraph.mtlx")


def test_an_image_file_bound_to_a_nodedef_input_is_read_from_the_instance():
    # network_surfaceshader.mtlx: the instance sets base_color_filename (and its colour space)
    (material,) = read_asset(str(SUITE / "pbrlib/surfaceshader/network_surfaceshader.mtlx")).materials
    texture = material.inputs["base_color"].texture
    assert (texture.file, texture.colorspace) == ("resources/Images/grid.png", "srgb_texture")


def test_tiled_coordinates_are_the_textures_transform_not_dropped():
    # usd_normal_map.mtlx: UsdUVTexture's st is texcoord * 16; read as a plain texture the tiling was lost, so the
    # graph was kept; since session 24 the multiply is the texture's UV transform (place2d's scale 1/16)
    (material,) = read_asset(str(SUITE / "pbrlib/surfaceshader/usd_normal_map.mtlx")).materials
    entry = material.inputs["normal"]
    assert isinstance(entry.value, Texture) and entry.value.uv is not None
    assert entry.value.uv.scale == (1 / 16, 1 / 16)


def test_a_usd_uv_texture_rgb_normal_map_is_written_as_a_vector3_image(write_mtlx, tmp_path):
    path = write_mtlx('''<UsdUVTexture name="T" type="multioutput">
  <input name="file" type="filename" value="n.png" colorspace="none" />
</UsdUVTexture>
<convert name="C" type="vector3">
  <input name="in" type="color3" nodename="T" output="rgb" />
</convert>
<normalmap name="D" type="vector3">
  <input name="in" type="vector3" nodename="C" />
</normalmap>
<standard_surface name="S" type="surfaceshader">
  <input name="normal" type="vector3" nodename="D" />
</standard_surface>''', files=("n.png",))
    texture = read_asset(str(path)).materials[0].inputs["normal"].texture
    assert texture.image_type == "color3" and texture.channels is None  # the rgb output, not the first (r)
    out = tmp_path / "o.mtlx"
    convert_file(str(path), str(out), "open_pbr_surface", Settings())
    assert [n.getType() for n in validated(out).getNodes() if n.getCategory() == "image"] == ["vector3"]


def test_a_material_node_of_its_own_definition_is_not_a_material_without_shader():
    # material_node_discovery.mtlx: <material_def type="material"/>, a nodedef implemented by a graph
    codes = _codes(SUITE / "stdlib/materials/material_node_discovery.mtlx")
    assert "OPBR801" not in codes and codes.count("OPBR805") == 2


def test_a_nodedef_that_declares_no_node_is_reported():
    # definition_reduced_interface.mtlx's nodedef says nodename="pattern_shader" where node= is meant
    assert "OPBR104" in _codes(SUITE / "stdlib/definition/definition_reduced_interface.mtlx")


def test_looks_carry_the_collections_they_assign_to(tmp_path):
    out = tmp_path / "o.mtlx"
    convert_file(str(SUITE / "stdlib/materials/material_node_discovery.mtlx"), str(out), "open_pbr_surface", Settings())
    assert validated(out).getCollection("collection1") is not None


def test_verify_takes_a_colour_space_materialx_does_not_know(tmp_path):
    # color_management.mtlx: constant colours in OCIO's gamma18/22/24 inside node graphs; `convert --verify`
    # raised KeyError evaluating them (MaterialX applies no transform to a name it does not know: nor does this)
    from click.testing import CliRunner

    from cli.group import cli

    result = CliRunner().invoke(cli, ["convert", str(SUITE / "stdlib/color_management/color_management.mtlx"),
                                      "-o", str(tmp_path / "o.gltf"), "--verify"])
    assert result.exception is None or isinstance(result.exception, SystemExit), result.output
    assert "Traceback" not in result.output and (tmp_path / "o.gltf").is_file()


def test_a_constant_nodes_colour_is_read_in_its_own_colour_space(write_mtlx, tmp_path):
    # color_management.mtlx feeds shaders from <constant> nodes whose value carries its colour space; the value
    # was read in the shader input's (a glTF output got 0.5 for an sRGB 0.5, not 0.214)
    import json

    import colour

    path = write_mtlx('''<constant name="k" type="color3">
  <input name="value" type="color3" value="0.5, 0.2, 0.1" colorspace="srgb_texture" />
</constant>
<open_pbr_surface name="S" type="surfaceshader">
  <input name="base_color" type="color3" nodename="k" />
</open_pbr_surface>''')
    entry = read_asset(str(path)).materials[0].inputs["base_color"]
    assert (entry.value.value, entry.colorspace) == ((0.5, 0.2, 0.1), "srgb_texture")
    out = tmp_path / "o.gltf"
    convert_file(str(path), str(out), "gltf_pbr", Settings())
    factor = json.loads(out.read_text())["materials"][0]["pbrMetallicRoughness"]["baseColorFactor"][:3]
    expected = colour.cctf_decoding([0.5, 0.2, 0.1], function="sRGB")
    assert max(abs(a - b) for a, b in zip(factor, expected)) < 1e-6
