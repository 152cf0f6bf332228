"""Custom node definitions and constant networks in MaterialX documents (OpenUSD's UsdMtlx test files
are full of both): a custom shader node whose definition wraps a shader the toolkit reads is read as
that shader with the node's values, a constant network as its value, and any other shader is
reported, by validate (OPBR805) and by convert (OPBR1104), never left out in silence.

The anchor for the expansion is MaterialX's own ``NodeGraph.flattenSubgraphs``: the values it puts
on the wrapped shader are the ones expected here.
"""

from __future__ import annotations

import json
import random

import MaterialX as mx
import pytest
from click.testing import CliRunner

from cli.group import cli
from openpbr_tools.convert import convert_file
from openpbr_tools.io import ReadError, read_asset
from openpbr_tools.model import Constant

WRAPPER = """<?xml version="1.0"?>
<materialx version="1.39" colorspace="lin_rec709">
  <nodedef name="ND_paint" node="paint">
    <input name="tint" type="color3" value="1, 0, 0" />
    <input name="gloss" type="float" value="0.25" />
    <input name="metal" type="float" value="0" />
    <output name="out" type="surfaceshader" />
  </nodedef>
  <nodegraph name="NG_paint" nodedef="ND_paint">
    <open_pbr_surface name="inner" type="surfaceshader">
      <input name="base_color" type="color3" interfacename="tint" />
      <input name="specular_roughness" type="float" interfacename="gloss" />
      <input name="base_metalness" type="float" interfacename="metal" />
      <input name="coat_weight" type="float" value="0.5" />
    </open_pbr_surface>
    <output name="out" type="surfaceshader" nodename="inner" />
  </nodegraph>
{instances}
</materialx>
"""


def _instances(rng: random.Random, count: int) -> str:
    lines = []
    for i in range(count):
        inputs = []
        if rng.random() < 0.7:
            inputs.append(f'<input name="tint" type="color3" value="{rng.random():.6f}, {rng.random():.6f}, {rng.random():.6f}" />')
        if rng.random() < 0.7:
            inputs.append(f'<input name="gloss" type="float" value="{rng.random():.6f}" />')
        if rng.random() < 0.5:
            inputs.append(f'<input name="metal" type="float" value="{rng.random():.6f}" />')
        lines.append(f'  <paint name="P{i}" type="surfaceshader">{"".join(inputs)}</paint>')
        lines.append(f'  <surfacematerial name="M{i}" type="material"><input name="surfaceshader" '
                     f'type="surfaceshader" nodename="P{i}" /></surfacematerial>')
    return "\n".join(lines)


def _flattened(text: str, instance: str) -> dict:
    """MaterialX's expansion of ``instance``: flattenSubgraphs on a graph holding a copy of it."""
    document = mx.createDocument()
    mx.readFromXmlString(document, text)
    node = document.getNode(instance)
    graph = document.addNodeGraph("anchor_" + instance)
    copy = graph.addNode(node.getCategory(), instance, "surfaceshader")
    copy.copyContentFrom(node)
    graph.addOutput("out", "surfaceshader").setNodeName(instance)
    graph.flattenSubgraphs()
    (shader,) = [n for n in graph.getNodes() if n.getCategory() == "open_pbr_surface"]
    return {i.getName(): i.getValue() for i in shader.getInputs() if i.hasAttribute("value")}


def test_a_custom_shader_wrapping_openpbr_is_read_with_the_values_materialx_flattens_to(tmp_path):
    text = WRAPPER.format(instances=_instances(random.Random(3), 40))
    path = tmp_path / "paint.mtlx"
    path.write_text(text)
    materials = {m.material_name: m for m in read_asset(str(path)).materials}
    assert sorted(materials) == sorted(f"M{i}" for i in range(40))  # the graph's own shader is no material
    for i in range(40):
        expected = _flattened(text, f"P{i}")
        got = materials[f"M{i}"]
        assert got.model == "open_pbr_surface" and got.name == f"P{i}"
        for name, value in expected.items():
            value = tuple(value) if isinstance(value, mx.Color3) else value
            assert got.inputs[name].value.value == pytest.approx(value, abs=1e-6), (i, name)


def test_convert_names_the_expansion_and_writes_the_values(tmp_path):
    path = tmp_path / "paint.mtlx"
    path.write_text(WRAPPER.format(instances=_instances(random.Random(5), 3)))
    result = convert_file(str(path), str(tmp_path / "out.gltf"))
    expanded = [d for d in result.diagnostics if d.code == "OPBR1102" and "custom paint node (ND_paint)" in d.message]
    assert len(expanded) == 3
    assert [m["name"] for m in json.loads((tmp_path / "out.gltf").read_text())["materials"]] == ["M0", "M1", "M2"]


def test_a_constant_network_feeds_its_value(tmp_path):
    path = tmp_path / "constant.mtlx"
    path.write_text("""<?xml version="1.0"?>
<materialx version="1.39" colorspace="lin_rec709">
  <nodegraph name="consts">
    <constant name="c" type="color3"><input name="value" type="color3" value="0.2, 0.3, 0.4" /></constant>
    <dot name="d" type="color3"><input name="in" type="color3" nodename="c" /></dot>
    <output name="out" type="color3" nodename="d" />
  </nodegraph>
  <constant name="w" type="float"><input name="value" type="float" value="1.5" /></constant>
  <open_pbr_surface name="S" type="surfaceshader">
    <input name="base_color" type="color3" nodegraph="consts" output="out" />
    <input name="base_weight" type="float" nodename="w" />
  </open_pbr_surface>
  <surfacematerial name="M" type="material"><input name="surfaceshader" type="surfaceshader" nodename="S" /></surfacematerial>
</materialx>
""")
    (material,) = read_asset(str(path)).materials
    assert material.inputs["base_color"].value == Constant((0.2, 0.3, 0.4))
    assert material.inputs["base_weight"].value == Constant(1.5)
    report = CliRunner().invoke(cli, ["validate", str(path), "--format", "json"])
    found = {(d["code"], d["location"].get("input")) for d in json.loads(report.output)["diagnostics"]}
    assert ("OPBR301", "base_weight") in found  # now a value: range-checked (base_weight is at most 1)


def test_an_unreadable_shader_is_reported_by_validate_and_convert(tmp_path):
    path = tmp_path / "toon.mtlx"
    path.write_text("""<?xml version="1.0"?>
<materialx version="1.39" colorspace="lin_rec709">
  <nodedef name="ND_toon" node="toon"><output name="out" type="surfaceshader" /></nodedef>
  <toon name="S" type="surfaceshader" />
  <surfacematerial name="M" type="material"><input name="surfaceshader" type="surfaceshader" nodename="S" /></surfacematerial>
</materialx>
""")
    report = CliRunner().invoke(cli, ["validate", str(path), "--format", "json"])
    assert "OPBR805" in {d["code"] for d in json.loads(report.output)["diagnostics"]}
    # nothing else to write: refused (exit 2, as convert --help says of "no material to convert"), never an
    # empty output (the red team's F9), with the reason
    with pytest.raises(ReadError) as refused:
        convert_file(str(path), str(tmp_path / "out.usda"))
    assert refused.value.kind == "no_material" and "toon shader" in refused.value.message
    assert not (tmp_path / "out.usda").exists()
    beside = path.read_text().replace("</materialx>", '<open_pbr_surface name="P" type="surfaceshader" />\n'
                                      '<surfacematerial name="N" type="material"><input name="surfaceshader" '
                                      'type="surfaceshader" nodename="P" /></surfacematerial>\n</materialx>')
    path.write_text(beside)
    result = convert_file(str(path), str(tmp_path / "out.usda"))  # beside a material it converts: written, said
    assert [d.code for d in result.diagnostics if "toon shader" in d.message] == ["OPBR1104"]
