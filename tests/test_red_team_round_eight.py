"""Session 21's red team, set J: the basic defects (a value out of range, a missing texture) written the way pipelines
write them, behind one indirection: a node graph interface read through a ``dot`` node, a custom node's default, an
XIncluded material, a USD NodeGraph interface through ``ND_dot_float``, a texture path on a USD Material's interface,
a data-URI JPEG that is no JPEG. Each test asks the anchor what the renderer gets (MaterialX's node definitions and
its API, usd-core's value resolution, the Khronos glTF-Validator) and checks the tool reports it, and that the same
indirection carrying a good value is quiet."""

from __future__ import annotations

import base64
import json
from pathlib import Path

import MaterialX as mx
import pytest

from gltf_support import validate_many_with_khronos
from redteam_support import findings, report

HEAD = '<?xml version="1.0"?>\n<materialx version="1.39" colorspace="lin_rec709">\n'


def _mtlx(tmp_path: Path, body: str, name: str = "m.mtlx") -> Path:
    path = tmp_path / name
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(HEAD + body + "</materialx>\n", encoding="utf-8")
    return path


def _soft_range(nodedef: str, name: str) -> tuple[float, float]:
    """The range MaterialX's own node definition gives an input (uimin/uisoftmin, uimax/uisoftmax)."""
    library = mx.createDocument()
    mx.loadLibraries(mx.getDefaultDataLibraryFolders(), mx.getDefaultDataSearchPath(), library)
    port = library.getNodeDef(nodedef).getActiveInput(name)
    low = port.getAttribute("uimin") or port.getAttribute("uisoftmin")
    high = port.getAttribute("uimax") or port.getAttribute("uisoftmax")
    return float(low), float(high)


_GRAPH_INTERFACE = '''  <nodegraph name="NG_params">
    <input name="metal_amt" type="float" value="{value}" />
    <dot name="m" type="float">
      <input name="in" type="float" interfacename="metal_amt" />
    </dot>
    <output name="metal_out" type="float" nodename="m" />
  </nodegraph>
  <standard_surface name="SR_gold" type="surfaceshader">
    <input name="metalness" type="float" nodegraph="NG_params" output="metal_out" />
  </standard_surface>
  <surfacematerial name="M" type="material">
    <input name="surfaceshader" type="surfaceshader" nodename="SR_gold" />
  </surfacematerial>
'''


@pytest.mark.parametrize("value, expected", [(1.7, True), (0.9, False)])
def test_a_graph_interface_value_read_through_a_dot_node_is_range_checked(tmp_path, value, expected):
    """jm_b08: MaterialX binds the interface input's value to the dot node (interfacename), which hands it to the
    shader; an <output> cannot carry interfacename, so this is how a graph exposes a parameter."""
    low, high = _soft_range("ND_standard_surface_surfaceshader", "metalness")
    path = _mtlx(tmp_path, _GRAPH_INTERFACE.format(value=value))
    document = mx.createDocument()
    mx.readFromXmlFile(document, str(path))
    dot = document.getNodeGraph("NG_params").getNode("m")
    assert dot.getInput("in").getInterfaceInput().getValue() == pytest.approx(value)
    assert (not low <= value <= high) is expected
    assert (("OPBR301", "error", "SR_gold", "metalness") in findings(path)) is expected


_CUSTOM_NODE = '''  <nodedef name="ND_studio_metal_float" node="studio_metal">
    <input name="amount" type="float" value="{default}" />
    <output name="out" type="float" />
  </nodedef>
  <nodegraph name="NG_studio_metal_float" nodedef="ND_studio_metal_float">
    <dot name="pass" type="float">
      <input name="in" type="float" interfacename="amount" />
    </dot>
    <output name="out" type="float" nodename="pass" />
  </nodegraph>
  <studio_metal name="metal_src" type="float">{instance}</studio_metal>
  <open_pbr_surface name="SR_steel" type="surfaceshader">
    <input name="base_metalness" type="float" nodename="metal_src" />
  </open_pbr_surface>
  <surfacematerial name="M" type="material">
    <input name="surfaceshader" type="surfaceshader" nodename="SR_steel" />
  </surfacematerial>
'''


@pytest.mark.parametrize("default, instance, expected", [
    ("1.7", "", True),  # jm_b02: the nodedef's default reaches the shader
    ("0.5", '<input name="amount" type="float" value="1.7" />', True),  # the instance sets it
    ("1.7", '<input name="amount" type="float" value="0.5" />', False),  # the instance overrides a bad default
    ("1", "", False),
])
def test_a_custom_node_is_followed_into_its_implementation(tmp_path, default, instance, expected):
    low, high = _soft_range("ND_open_pbr_surface_surfaceshader", "base_metalness")
    path = _mtlx(tmp_path, _CUSTOM_NODE.format(default=default, instance=instance))
    document = mx.createDocument()
    mx.readFromXmlFile(document, str(path))
    node = document.getNode("metal_src")
    assert node.getImplementation().getName() == "NG_studio_metal_float"  # MaterialX renders the graph
    reaching = float((node.getInput("amount") or node.getNodeDef().getInput("amount")).getValueString())
    assert (not low <= reaching <= high) is expected
    assert (("OPBR301", "error", "SR_steel", "base_metalness") in findings(path)) is expected


@pytest.mark.parametrize("present", [False, True])
def test_a_custom_nodes_default_texture_is_looked_for(tmp_path, present):
    """jm_b14: the implementation's image reads the nodedef's default file, which the instance does not set."""
    if present:
        (tmp_path / "tex").mkdir()
        (tmp_path / "tex" / "brick.png").write_bytes(base64.b64decode(_PNG))
    path = _mtlx(tmp_path, '''  <nodedef name="ND_studio_brick_color3" node="studio_brick">
    <input name="file" type="filename" value="tex/brick.png" colorspace="srgb_texture" />
    <output name="out" type="color3" />
  </nodedef>
  <nodegraph name="NG_studio_brick_color3" nodedef="ND_studio_brick_color3">
    <image name="img" type="color3">
      <input name="file" type="filename" interfacename="file" />
    </image>
    <output name="out" type="color3" nodename="img" />
  </nodegraph>
  <studio_brick name="brick" type="color3" />
  <open_pbr_surface name="SR" type="surfaceshader">
    <input name="base_color" type="color3" nodename="brick" />
  </open_pbr_surface>
  <surfacematerial name="M" type="material">
    <input name="surfaceshader" type="surfaceshader" nodename="SR" />
  </surfacematerial>
''')
    missing = [f for f in findings(path) if f[0] == "OPBR701"]
    assert missing == ([] if present else [("OPBR701", "error", "ND_studio_brick_color3", "file")])


_PNG = ("iVBORw0KGgoAAAANSUhEUgAAAAQAAAAECAIAAAAmkwkpAAAAFElEQVR42mNsaPjPAANMDEgANwcAZFMCBygXkuMAAAAASUVORK5CYII=")
_INCLUDER = '''<?xml version="1.0"?>
<materialx xmlns:xi="http://www.w3.org/2001/XInclude" version="1.39" colorspace="lin_rec709">
  <xi:include href="lib/materials.mtlx" />
  <look name="L">
    <materialassign name="MA" material="M_lib" geom="/obj" />
  </look>
</materialx>
'''
_LIBRARY = '''  <open_pbr_surface name="SR_lib" type="surfaceshader">
    <input name="coat_weight" type="float" value="{value}" />
  </open_pbr_surface>
  <surfacematerial name="M_lib" type="material">
    <input name="surfaceshader" type="surfaceshader" nodename="SR_lib" />
  </surfacematerial>
'''


def test_an_included_material_is_validated_with_the_file_that_includes_it(tmp_path):
    """jm_b17: MaterialX reads an XIncluded document's elements as the includer's own (the look assigns M_lib); the
    finding is located in the included file, and reported once when both files are validated together."""
    library = _mtlx(tmp_path, _LIBRARY.format(value=-0.5), "lib/materials.mtlx")
    path = tmp_path / "look.mtlx"
    path.write_text(_INCLUDER, encoding="utf-8")
    document = mx.createDocument()
    mx.readFromXmlFile(document, str(path))
    assert document.getNode("SR_lib").getInputValue("coat_weight") == pytest.approx(-0.5)
    found = report(path)
    assert [(d.code, d.location.file) for d in found.diagnostics if str(d.severity) == "error"] \
        == [("OPBR301", str(library))]
    assert found.exit_code() == 1 and sum(f.materials for f in found.files) == 1
    both = report(tmp_path)
    assert [d.code for d in both.diagnostics if str(d.severity) == "error"] == ["OPBR301"]
    library.write_text(HEAD + _LIBRARY.format(value=0.5) + "</materialx>\n", encoding="utf-8")
    assert report(path).exit_code() == 0


def test_an_include_cycle_ends(tmp_path):
    """A includes B, which includes A: MaterialX refuses the cycle; the validation reports it and finishes."""
    first = tmp_path / "a.mtlx"
    second = tmp_path / "b.mtlx"
    include = '<?xml version="1.0"?>\n<materialx xmlns:xi="http://www.w3.org/2001/XInclude" version="1.39">\n' \
              '  <xi:include href="{}" />\n</materialx>\n'
    first.write_text(include.format("b.mtlx"), encoding="utf-8")
    second.write_text(include.format("a.mtlx"), encoding="utf-8")
    with pytest.raises(mx.ExceptionParseError):
        mx.readFromXmlFile(mx.createDocument(), str(first))
    assert "OPBR010" in {d.code for d in report(first).diagnostics}


_USD_GRAPH = '''#usda 1.0
(
    metersPerUnit = 1
)
def Material "Mat"
{
    token outputs:mtlx:surface.connect = </Mat/SR.outputs:surface>
    def NodeGraph "Params"
    {
        float inputs:rough = %s
        float outputs:rough_out.connect = </Mat/Params/pass.outputs:out>
        def Shader "pass"
        {
            uniform token info:id = "ND_dot_float"
            float inputs:in.connect = </Mat/Params.inputs:rough>
            float outputs:out
        }
    }
    def Shader "SR"
    {
        uniform token info:id = "ND_open_pbr_surface_surfaceshader"
        float inputs:specular_roughness.connect = </Mat/Params.outputs:rough_out>
        token outputs:surface
    }
}
'''


@pytest.mark.parametrize("value, expected", [("2.0", True), ("0.0", False)])
def test_a_usd_node_graph_interface_through_a_dot_node_is_range_checked(tmp_path, value, expected):
    """ju_b05: MaterialX's ND_dot_float hands its input on (stdlib_defs.mtlx), so the shader gets the interface's
    value; usd-core resolves the dot's input to the NodeGraph input holding it."""
    from pxr import Usd, UsdShade

    path = tmp_path / "m.usda"
    path.write_text(_USD_GRAPH % value, encoding="utf-8")
    stage = Usd.Stage.Open(str(path))
    held = UsdShade.Shader(stage.GetPrimAtPath("/Mat/Params/pass")).GetInput("in").GetValueProducingAttributes()
    assert [str(a.GetPath()) for a in held] == ["/Mat/Params.inputs:rough"] and held[0].Get() == float(value)
    low, high = _soft_range("ND_open_pbr_surface_surfaceshader", "specular_roughness")
    assert (not low <= float(value) <= high) is expected
    assert (("OPBR301", "error", "/Mat/SR", "specular_roughness") in findings(path)) is expected


_USD_INTERFACE_FILE = '''#usda 1.0
def Material "Mat"
{
    token outputs:surface.connect = </Mat/PBR.outputs:surface>
    asset inputs:albedo_tex = @./tex/albedo.png@
    def Shader "PBR"
    {
        uniform token info:id = "UsdPreviewSurface"
        color3f inputs:diffuseColor.connect = </Mat/Tex.outputs:rgb>
        token outputs:surface
    }
    def Shader "Tex"
    {
        uniform token info:id = "UsdUVTexture"
        asset inputs:file.connect = </Mat.inputs:albedo_tex>
        token inputs:sourceColorSpace = "sRGB"
        float3 outputs:rgb
    }
}
'''


@pytest.mark.parametrize("present", [True, False])
def test_a_texture_path_on_a_usd_material_interface_is_followed(tmp_path, present):
    """ju_g11 / ju_b14: the UsdUVTexture's file is connected to the Material's interface input, which usd-core
    resolves to its path; an existing file is no finding ("has no file" was an error), a missing one OPBR701."""
    from pxr import Usd, UsdShade

    if present:
        (tmp_path / "tex").mkdir()
        (tmp_path / "tex" / "albedo.png").write_bytes(base64.b64decode(_PNG))
    path = tmp_path / "m.usda"
    path.write_text(_USD_INTERFACE_FILE, encoding="utf-8")
    stage = Usd.Stage.Open(str(path))
    held = UsdShade.Shader(stage.GetPrimAtPath("/Mat/Tex")).GetInput("file").GetValueProducingAttributes()
    assert held[0].Get().path == "./tex/albedo.png" and bool(held[0].Get().resolvedPath) is present
    codes = {f[0] for f in findings(path) if f[1] == "error"}
    assert "OPBR705" not in codes
    assert ("OPBR701" in codes) is not present


def test_a_data_uri_jpeg_that_is_no_image_is_an_error_as_khronos_says(tmp_path):
    """jg_b11: a data URI declaring image/jpeg whose bytes start with the SOI marker and then nothing of a JPEG; the
    Khronos glTF-Validator reports INVALID_URI ("The declared mediatype does not match the embedded content")."""
    broken = base64.b64encode(b"\xff\xd8" + bytes(300)).decode("ascii")
    good = _PNG
    paths = {}
    for name, uri in (("broken", f"data:image/jpeg;base64,{broken}"), ("good", f"data:image/png;base64,{good}")):
        paths[name] = tmp_path / f"{name}.gltf"
        paths[name].write_text(json.dumps({
            "asset": {"version": "2.0"}, "images": [{"uri": uri}], "textures": [{"source": 0}],
            "materials": [{"name": "M", "normalTexture": {"index": 0}}]}), encoding="utf-8")
    reports = validate_many_with_khronos(paths.values(), tmp_path)
    khronos = {name: {(m["code"], m["severity"]) for m in reports[str(p.resolve())]["issues"]["messages"]}
               for name, p in paths.items()}
    assert ("INVALID_URI", 0) in khronos["broken"] and not {c for c, s in khronos["good"] if s == 0}
    assert ("OPBR1214", "error", "/images/0", "uri") in findings(paths["broken"])
    assert not [f for f in findings(paths["good"]) if f[1] == "error"]


def test_a_library_split_across_included_files_is_read_as_its_includer_composes_it(tmp_path):
    """The red team's round-four good mg01: a studio library includes its nodedefs from one file and their
    implementation graphs from another; the implementation file alone names a nodedef it does not hold, which
    MaterialX resolves only in the composition that includes both. Checked with the file that includes it, the
    library is clean (it was an OPBR004 error of the implementation file read on its own)."""
    (tmp_path / "lib" / "defs").mkdir(parents=True)
    (tmp_path / "lib" / "impl").mkdir()
    include = '<?xml version="1.0"?>\n<materialx xmlns:xi="http://www.w3.org/2001/XInclude" version="1.39">\n{}</materialx>\n'
    (tmp_path / "lib" / "studio.mtlx").write_text(include.format(
        '  <xi:include href="defs/tint.mtlx" />\n  <xi:include href="impl/tint.mtlx" />\n'), encoding="utf-8")
    (tmp_path / "lib" / "defs" / "tint.mtlx").write_text(HEAD.replace(' colorspace="lin_rec709"', "") + '''\
  <nodedef name="ND_studio_tint_color3" node="studio_tint">
    <input name="in" type="color3" value="1, 1, 1" />
    <output name="out" type="color3" />
  </nodedef>
</materialx>
''', encoding="utf-8")
    (tmp_path / "lib" / "impl" / "tint.mtlx").write_text(HEAD.replace(' colorspace="lin_rec709"', "") + '''\
  <nodegraph name="IM_studio_tint_color3" nodedef="ND_studio_tint_color3">
    <multiply name="m" type="color3">
      <input name="in1" type="color3" interfacename="in" />
      <input name="in2" type="float" value="0.9" />
    </multiply>
    <output name="out" type="color3" nodename="m" />
  </nodegraph>
</materialx>
''', encoding="utf-8")
    path = tmp_path / "clay.mtlx"
    path.write_text(include.format('''  <xi:include href="lib/studio.mtlx" />
  <studio_tint name="tint" type="color3">
    <input name="in" type="color3" value="0.7, 0.45, 0.3" />
  </studio_tint>
  <open_pbr_surface name="SR" type="surfaceshader">
    <input name="base_color" type="color3" nodename="tint" />
  </open_pbr_surface>
  <surfacematerial name="M" type="material">
    <input name="surfaceshader" type="surfaceshader" nodename="SR" />
  </surfacematerial>
'''), encoding="utf-8")
    document = mx.createDocument()
    mx.readFromXmlFile(document, str(path))
    assert document.validate()[0]  # MaterialX: the composition is valid
    alone = mx.createDocument()
    mx.readFromXmlFile(alone, str(tmp_path / "lib" / "impl" / "tint.mtlx"))
    assert not alone.validate()[0]  # and the implementation file alone is not
    found = report(path)
    assert [d for d in found.diagnostics if str(d.severity) != "info"] == [] and found.exit_code() == 0
