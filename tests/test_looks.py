"""MaterialX looks (material assignments to geometry) in a conversion: a .mtlx output carries the source's
looks and look groups, their assignments following the materials' written names; what an output cannot
hold is a note at its element (OPBR1104): an assignment of a material that is not written, every look of a
USD or glTF output, the materials of XIncluded files outside the document's folder. A look file's includes
beside it (MaterialX's example library's) are converted into the output: before session 11 such a file
converted to an empty document without a word."""

from __future__ import annotations

import shutil
from pathlib import Path

import MaterialX as mx

from openpbr_tools.convert import convert_file
from openpbr_tools.translate.common import Settings

EXAMPLES = Path(__file__).parent / "data" / "published" / "materialx" / "resources" / "Materials" / "Examples"

DOCUMENT = """<?xml version="1.0"?>
<materialx version="1.39">
  <standard_surface name="SR_red" type="surfaceshader">
    <input name="base_color" type="color3" value="0.8, 0.2, 0.1" />
  </standard_surface>
  <surfacematerial name="M_red" type="material">
    <input name="surfaceshader" type="surfaceshader" nodename="SR_red" />
  </surfacematerial>
  <surface_unlit name="SR_flat" type="surfaceshader" />
  <surfacematerial name="M_flat" type="material">
    <input name="surfaceshader" type="surfaceshader" nodename="SR_flat" />
  </surfacematerial>
  <look name="Hero">
    <materialassign name="body" geom="/hero/body" material="M_red" />
    <materialassign name="decal" geom="/hero/decal" material="M_flat" />
    <visibility name="hide" geom="/hero/proxy" visible="false" />
  </look>
  <look name="Alt">
    <materialassign name="body" geom="/hero/*" material="M_red" />
  </look>
  <lookgroup name="Looks" looks="Hero,Alt" default="Hero" />
</materialx>
"""


def _convert(tmp_path: Path, suffix: str, target: str | None = "open_pbr_surface"):
    source = tmp_path / "looks.mtlx"
    source.write_text(DOCUMENT)
    out = tmp_path / f"out.{suffix}"
    return convert_file(str(source), str(out), target if suffix == "mtlx" else None, Settings()), out


def test_a_mtlx_output_carries_the_looks_and_their_assignments(tmp_path):
    result, out = _convert(tmp_path, "mtlx")
    document = mx.createDocument()
    mx.readFromXmlFile(document, str(out))
    assert [look.getName() for look in document.getLooks()] == ["Hero", "Alt"]
    hero = document.getLook("Hero")
    assert [(a.getName(), a.getGeom(), a.getMaterial()) for a in hero.getMaterialAssigns()] == \
        [("body", "/hero/body", "M_red")]
    assert hero.getVisibility("hide") is not None and hero.getVisibility("hide").getGeom() == "/hero/proxy"
    assert [a.getMaterial() for a in document.getLook("Alt").getMaterialAssigns()] == ["M_red"]
    assert document.getLookGroup("Looks").getLooks() == "Hero,Alt"
    assert document.getNode("M_red").getInput("surfaceshader").getConnectedNode().getCategory() == "open_pbr_surface"
    valid, message = document.validate()
    assert valid, message
    # the unlit material is not converted (reported as such), so its assignment is left out, with a note there
    left_out = [d for d in result.diagnostics if d.code == "OPBR1104" and "materialassign decal" in d.message]
    assert len(left_out) == 1 and left_out[0].location.path == "Hero/decal"


def test_a_usd_or_gltf_output_says_each_look_is_not_written(tmp_path):
    for suffix in ("usda", "gltf"):
        result, _ = _convert(tmp_path, suffix)
        notes = {d.location.path: d.message for d in result.diagnostics if d.code == "OPBR1104" and "not written:" in d.message}
        assert set(notes) == {"Hero", "Alt", "Looks"}, notes
        assert "2 material assignment(s) lost" in notes["Hero"]


def test_a_look_file_converts_the_materials_of_its_includes_into_the_output(tmp_path):
    """MaterialX's standard_surface_look_brass_tiled.mtlx: two XIncludes beside it and a look. The output
    holds both materials converted and the look assigning them; a note says where they came from."""
    folder = tmp_path / "StandardSurface"
    shutil.copytree(EXAMPLES / "StandardSurface", folder)
    out = tmp_path / "out.mtlx"
    result = convert_file(str(folder / "standard_surface_look_brass_tiled.mtlx"), str(out), "open_pbr_surface", Settings())
    assert any(d.code == "OPBR1102" and "Greysphere_Calibration, Tiled_Brass" in d.message and "XIncluded" in d.message
               for d in result.diagnostics)
    assert not [d for d in result.diagnostics if d.code == "OPBR1104" and "materialassign" in d.message]
    document = mx.createDocument()
    mx.readFromXmlFile(document, str(out))
    assigned = {a.getMaterial() for a in document.getLook("Brass_Look").getMaterialAssigns()}
    assert assigned == {"Tiled_Brass", "Greysphere_Calibration"}
    for name in assigned:
        assert document.getNode(name).getInput("surfaceshader").getConnectedNode().getCategory() == "open_pbr_surface"
    valid, message = document.validate()
    assert valid, message


def test_an_include_outside_the_folder_is_not_flattened_and_says_so(tmp_path):
    """An XInclude from another folder (followed only where allowed) converts as its own file: its
    materials are not in this output, and the look's assignment of one is left out, with notes."""
    (tmp_path / "shared").mkdir()
    (tmp_path / "shared" / "red.mtlx").write_text(DOCUMENT.split("  <surface_unlit")[0] + "</materialx>\n")
    (tmp_path / "look").mkdir()
    (tmp_path / "look" / "look.mtlx").write_text(
        '<?xml version="1.0"?>\n<materialx version="1.39" xmlns:xi="http://www.w3.org/2001/XInclude">\n'
        '  <xi:include href="../shared/red.mtlx" />\n  <look name="L">\n'
        '    <materialassign name="a" geom="/x" material="M_red" />\n  </look>\n</materialx>\n')
    result = convert_file(str(tmp_path / "look" / "look.mtlx"), str(tmp_path / "out.mtlx"), "open_pbr_surface",
                          Settings(), allow_outside=(str(tmp_path),))
    messages = [d.message for d in result.diagnostics if d.code == "OPBR1104"]
    assert any("M_red" in m and "outside the document's folder" in m for m in messages), messages
    assert any("materialassign a assigns M_red" in m for m in messages), messages
