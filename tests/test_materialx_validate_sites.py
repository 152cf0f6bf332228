"""MaterialX's own `Document.validate()` findings (OPBR004) point at the element MaterialX names: the
message ends with the element as `Element.asString()` prints it, and the finding carries that element's
line, node path and input, as every other finding does."""

from __future__ import annotations

import pytest

from openpbr_tools.validate import Options, validate_paths

from glsupport import validation

CYCLE = """<?xml version="1.0"?>
<materialx version="1.39" colorspace="lin_rec709">
  <nodegraph name="g">
    <multiply name="a" type="color3"><input name="in1" type="color3" nodename="b" /><input name="in2" type="color3" value="0.5, 0.5, 0.5" /></multiply>
    <add name="b" type="color3"><input name="in1" type="color3" nodename="a" /><input name="in2" type="color3" value="0.1, 0.1, 0.1" /></add>
    <output name="out" type="color3" nodename="b" />
  </nodegraph>
  <open_pbr_surface name="s" type="surfaceshader"><input name="base_color" type="color3" nodegraph="g" output="out" /></open_pbr_surface>
  <surfacematerial name="m" type="material"><input name="surfaceshader" type="surfaceshader" nodename="s" /></surfacematerial>
</materialx>
"""

INTERFACE = """<?xml version="1.0"?>
<materialx version="1.39" colorspace="lin_rec709">
  <nodegraph name="g">
    <input name="tint" type="color3" value="1, 0, 0" />
    <multiply name="a" type="color3">
      <input name="in1" type="color3" interfacename="tnt" />
      <input name="in2" type="color3" value="0.5, 0.5, 0.5" />
    </multiply>
    <output name="out" type="color3" nodename="a" />
  </nodegraph>
  <open_pbr_surface name="s" type="surfaceshader"><input name="base_color" type="color3" nodegraph="g" output="out" /></open_pbr_surface>
  <surfacematerial name="m" type="material"><input name="surfaceshader" type="surfaceshader" nodename="s" /></surfacematerial>
</materialx>
"""


@pytest.mark.parametrize("text,expected", [(CYCLE, (6, "g/out", None, "Cycle in upstream path")),
                                           (INTERFACE, (6, "g/a", "in1", "Interface name not found"))],
                         ids=["cycle", "interface"])
def test_materialx_findings_point_at_the_element_materialx_names(tmp_path, text, expected):
    path = tmp_path / "doc.mtlx"
    path.write_text(text, encoding="utf-8")
    _, valid, message = validation(path)
    assert not valid and expected[3] in message  # the anchor's own verdict
    [finding] = [d for d in validate_paths([str(path)], options=Options(use_config=False)).diagnostics if d.code == "OPBR004"]
    assert (finding.location.line, finding.location.path, finding.location.input) == expected[:3]
    assert expected[3] in finding.message



def test_a_message_whose_element_prints_like_another_gets_no_place_rather_than_a_wrong_one(tmp_path):
    """Two graphs with the same 'a.in1 interfacename=tint' print alike; only g2's is broken (no tint input)."""
    text = """<?xml version="1.0"?>
<materialx version="1.39" colorspace="lin_rec709">
  <nodegraph name="g1">
    <input name="tint" type="color3" value="1, 0, 0" />
    <multiply name="a" type="color3"><input name="in1" type="color3" interfacename="tint" /><input name="in2" type="color3" value="0.5, 0.5, 0.5" /></multiply>
    <output name="out" type="color3" nodename="a" />
  </nodegraph>
  <nodegraph name="g2">
    <multiply name="a" type="color3"><input name="in1" type="color3" interfacename="tint" /><input name="in2" type="color3" value="0.5, 0.5, 0.5" /></multiply>
    <output name="out" type="color3" nodename="a" />
  </nodegraph>
  <open_pbr_surface name="s" type="surfaceshader"><input name="base_color" type="color3" nodegraph="g2" output="out" /></open_pbr_surface>
  <surfacematerial name="m" type="material"><input name="surfaceshader" type="surfaceshader" nodename="s" /></surfacematerial>
</materialx>
"""
    path = tmp_path / "doc.mtlx"
    path.write_text(text, encoding="utf-8")
    [finding] = [d for d in validate_paths([str(path)], options=Options(use_config=False)).diagnostics if d.code == "OPBR004"]
    assert "Interface name not found" in finding.message
    assert (finding.location.line, finding.location.path, finding.location.input) == (None, None, None)
