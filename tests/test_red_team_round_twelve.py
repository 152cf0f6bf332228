"""Session 25, the validator: a colour-space name inside a node graph (on an image node's file, a pattern node's
colour value, or the node graph itself) was never checked, so a typo there (``srgb_textur``), which MaterialX's
colour management cannot convert, passed silently; only a shader input's, a texture's read straight into a shader
and the document's were. A legacy name MaterialX remaps itself (``gamma18``) and ``lin_rec709_scene`` (which it
leaves unconverted, as linear Rec.709 is its working space: MaterialX's own colour-management test suite uses it)
render as meant and stay quiet."""

from __future__ import annotations

import pytest

from redteam_support import codes, messages, mtlx

_GRAPH = '''
    <nodegraph name="NG"{graph}>
      <image name="img" type="color3">
        <input name="file" type="filename" value="c.png"{image} />
      </image>
      <noise2d name="nz" type="float" />
      <mix name="m" type="color3">
        <input name="fg" type="color3" nodename="img" />
        <input name="bg" type="color3" value="0.5, 0.5, 0.5"{value} />
        <input name="mix" type="float" nodename="nz" />
      </mix>
      <output name="out" type="color3" nodename="m" />
    </nodegraph>
    <open_pbr_surface name="S" type="surfaceshader" version="1.1.1">
      <input name="base_color" type="color3" nodegraph="NG" output="out" />
    </open_pbr_surface>
    <surfacematerial name="M" type="material">
      <input name="surfaceshader" type="surfaceshader" nodename="S" />
    </surfacematerial>
'''


@pytest.mark.parametrize("where", ["graph", "image", "value"])
def test_an_unknown_colour_space_inside_a_graph_is_an_error(tmp_path, where):
    from redteam_support import png

    png(tmp_path / "c.png")
    spaces = {"graph": "", "image": "", "value": ""} | {where: ' colorspace="srgb_textur"'}
    path = mtlx(tmp_path, _GRAPH.format(**spaces))
    assert codes(path).get("OPBR502") == 1
    assert "'srgb_textur'" in messages(path, "OPBR502")[0]


@pytest.mark.parametrize("name", ["srgb_texture", "gamma18", "lin_rec709_scene", "acescg"])
def test_a_name_materialx_converts_or_leaves_as_meant_is_quiet(tmp_path, name):
    from redteam_support import png

    png(tmp_path / "c.png")
    path = mtlx(tmp_path, _GRAPH.format(graph="", image=f' colorspace="{name}"', value=f' colorspace="{name}"'))
    assert "OPBR502" not in codes(path)
