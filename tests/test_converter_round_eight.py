"""Session 21's converter red team (set L: OpenPBR to glTF and UsdPreviewSurface, real output files, round trips):
each test builds the case and checks the written values against a closed form or the glTF specification, and the
report against the rule that every value that does not survive exactly is named at its material and input."""

from __future__ import annotations

import json

import MaterialX as mx
import numpy as np
import pytest
from PIL import Image

from openpbr_tools import colorspaces
from openpbr_tools.convert import convert_file

HEAD = '<?xml version="1.0"?>\n<materialx version="1.39" colorspace="{space}">\n'
MATERIAL = '''  <surfacematerial name="M" type="material">
    <input name="surfaceshader" type="surfaceshader" nodename="S" />
  </surfacematerial>
</materialx>
'''


def _openpbr(tmp_path, inputs: str, space: str = "lin_rec709", name: str = "m.mtlx", extra: str = ""):
    path = tmp_path / name
    path.write_text(HEAD.format(space=space) + extra + '  <open_pbr_surface name="S" type="surfaceshader">\n'
                    + inputs + "  </open_pbr_surface>\n" + MATERIAL, encoding="utf-8")
    return path


def _convert(source, output, **options):
    report = convert_file(str(source), str(output), **options)
    return [(d.code, str(d.severity), d.location.input, d.message) for d in report.diagnostics]


def _values(path) -> dict:
    document = mx.createDocument()
    mx.readFromXmlFile(document, str(path))
    (shader,) = [n for n in document.getNodes() if n.getType() == "surfaceshader"]
    return {port.getName(): port.getValue() for port in shader.getInputs() if port.hasValueString()}


_METAL = '''    <input name="base_metalness" type="float" value="1" />
    <input name="base_color" type="color3" value="0.95, 0.5, 0.2" />
'''


def test_a_wide_gamut_metal_keeps_its_colour_in_a_gltf_pbr_node_and_is_clamped_in_a_gltf_file(tmp_path):
    """L-01: glTF's metal takes its base colour as F0 (Schlick); OpenPBR's untinted metal (white specular colour,
    weight 1) is the same F0, so the colour maps as it is (fit_metal: "the identity for a white tint and weight
    1"). In an acescg document (0.95, 0.5, 0.2) is (1.19, 0.43, 0.15) in linear Rec.709, which a gltf_pbr node in
    that document renders unclamped; only a glTF file's baseColorFactor must lie in [0, 1] (glTF 3.9.2)."""
    source = _openpbr(tmp_path, _METAL, space="acescg")
    assert colorspaces.to_lin_rec709(np.array([0.95, 0.5, 0.2]), "acescg")[0] > 1.1
    notes = _convert(source, tmp_path / "node.mtlx", target="gltf_pbr")
    assert np.allclose(_values(tmp_path / "node.mtlx")["base_color"].asTuple(), (0.95, 0.5, 0.2), atol=1e-6)
    assert not [n for n in notes if n[2] == "base_color" and "clipped" in n[3]]
    file_notes = _convert(source, tmp_path / "file.gltf")
    factor = json.loads((tmp_path / "file.gltf").read_text())["materials"][0]["pbrMetallicRoughness"]["baseColorFactor"]
    assert factor[0] == 1.0 and max(factor[:3]) <= 1.0
    assert [n for n in file_notes if n[2] == "base_color" and n[1] == "warning" and "clipped" in n[3]]


def _gltf(tmp_path, extensions: dict, name="g.gltf"):
    path = tmp_path / name
    path.write_text(json.dumps({"asset": {"version": "2.0"}, "extensionsUsed": sorted(extensions),
                                "materials": [{"name": "M", "extensions": extensions}]}), encoding="utf-8")
    return path


def test_gltf_extension_defaults_are_not_written_where_the_extension_is_absent(tmp_path):
    """L-03: without KHR_materials_iridescence or KHR_materials_sheen a glTF material has no film and no sheen, so
    their parameters are OpenPBR's defaults (thin_film_ior 1.4, thin_film_thickness 0.5 um, fuzz_roughness 0.5),
    not the extensions' (iridescenceIor 1.3, iridescenceThicknessMinimum 100 nm, sheenRoughnessFactor 0)."""
    _convert(_gltf(tmp_path, {}), tmp_path / "plain.mtlx")
    assert not {"thin_film_ior", "thin_film_thickness", "fuzz_roughness"} & set(_values(tmp_path / "plain.mtlx"))
    filmed = _gltf(tmp_path, {"KHR_materials_iridescence": {"iridescenceFactor": 1.0},
                              "KHR_materials_sheen": {"sheenColorFactor": [0.5, 0.5, 0.5]}}, "filmed.gltf")
    _convert(filmed, tmp_path / "filmed.mtlx")
    values = _values(tmp_path / "filmed.mtlx")
    assert values["thin_film_ior"] == pytest.approx(1.3) and values["thin_film_thickness"] == pytest.approx(0.4)
    assert "fuzz_roughness" in values  # (fitted from sheenRoughnessFactor 0)


def test_a_gltf_dispersion_read_as_an_abbe_number_is_named(tmp_path):
    """L-04: KHR_materials_dispersion's dispersion is 20 / V_d; OpenPBR's V_d is abbe_number / scale. Read back,
    dispersion 55.3 is scale 1 and Abbe number 20 / 55.3, and both are named in the report."""
    source = _gltf(tmp_path, {"KHR_materials_transmission": {"transmissionFactor": 1.0},
                              "KHR_materials_volume": {"thicknessFactor": 0.01},
                              "KHR_materials_dispersion": {"dispersion": 55.3}})
    notes = _convert(source, tmp_path / "d.mtlx")
    values = _values(tmp_path / "d.mtlx")
    assert values["transmission_dispersion_abbe_number"] == pytest.approx(20 / 55.3)
    assert values.get("transmission_dispersion_scale", 1.0) == pytest.approx(1.0)
    named = " ".join(n[3] for n in notes)
    assert "transmission_dispersion_abbe_number" in named and "transmission_dispersion_scale" in named


_SKIN = '''    <input name="subsurface_weight" type="float" value="1" />
    <input name="subsurface_color" type="color3" value="0.545, 0.445, 0.359" />
    <input name="subsurface_radius_scale" type="color3" value="0.482, 0.169, 0.109" />
'''


@pytest.mark.parametrize("output, options", [("s.gltf", {}), ("s.mtlx", {"target": "gltf_pbr"}),
                                             ("s.mtlx", {"target": "UsdPreviewSurface"})])
def test_subsurface_lost_to_a_model_without_it_is_named_at_its_inputs(tmp_path, output, options):
    """L-02: glTF and UsdPreviewSurface have no subsurface scattering; the colour is mixed into the base colour,
    the scattering is gone, and the report says so at subsurface_weight and subsurface_radius_scale."""
    notes = _convert(_openpbr(tmp_path, _SKIN), tmp_path / output, **options)
    lost = {n[2] for n in notes if n[0] == "OPBR1104"}
    assert {"subsurface_weight", "subsurface_radius_scale"} <= lost


def test_transmission_turned_into_opacity_is_reported_at_transmission_weight(tmp_path):
    """L-05: UsdPreviewSurface has no transmission; a glass becomes transparent (opacity), and the note stands at
    the input the material authored, not at the unauthored geometry_opacity."""
    notes = _convert(_openpbr(tmp_path, '    <input name="transmission_weight" type="float" value="1" />\n'),
                     tmp_path / "g.mtlx", target="UsdPreviewSurface")
    assert _values(tmp_path / "g.mtlx")["opacity"] == pytest.approx(0.0)
    sites = {n[2] for n in notes if n[0] in ("OPBR1103", "OPBR1104")}
    assert "transmission_weight" in sites and "geometry_opacity" not in sites


@pytest.mark.parametrize("space, lost", [("world", False), ("object", True)])
def test_a_world_space_normal_node_on_a_normal_input_is_its_default(tmp_path, space, lost):
    """The red team's Oliana observation: a ``normal`` node in world space on geometry_coat_normal is the nodedef's
    default (defaultgeomprop Nworld), so a glTF output loses nothing there; in object space it is another vector."""
    node = f'  <normal name="n" type="vector3">\n    <input name="space" type="string" value="{space}" />\n  </normal>\n'
    source = _openpbr(tmp_path, '    <input name="coat_weight" type="float" value="1" />\n'
                                '    <input name="geometry_coat_normal" type="vector3" nodename="n" />\n', extra=node)
    library = mx.createDocument()
    mx.loadLibraries(mx.getDefaultDataLibraryFolders(), mx.getDefaultDataSearchPath(), library)
    declared = library.getNodeDef("ND_open_pbr_surface_surfaceshader").getActiveInput("geometry_coat_normal")
    assert declared.getDefaultGeomPropString() == "Nworld"
    notes = _convert(source, tmp_path / "n.gltf")
    assert bool([n for n in notes if n[2] == "geometry_coat_normal" and n[0] == "OPBR1104"]) is lost


def test_a_packed_texture_is_named_by_the_file_written(tmp_path):
    """The red team's report-names observation: roughness baked and packed into glTF's metallicRoughnessTexture
    (G channel) is named by the file the output references, which exists."""
    Image.new("L", (8, 8), 128).save(tmp_path / "rough.png")
    source = _openpbr(tmp_path, '    <input name="specular_roughness" type="float" nodename="r" />\n',
                      extra='  <image name="r" type="float">\n    <input name="file" type="filename" '
                            'value="rough.png" />\n  </image>\n')
    notes = _convert(source, tmp_path / "out" / "p.gltf")
    gltf = json.loads((tmp_path / "out" / "p.gltf").read_text())
    texture = gltf["materials"][0]["pbrMetallicRoughness"]["metallicRoughnessTexture"]["index"]
    uri = gltf["images"][gltf["textures"][texture]["source"]]["uri"]
    assert (tmp_path / "out" / uri).is_file()
    assert [n for n in notes if "packed" in n[3] and n[3].endswith(f"into {uri}")]


def test_an_authored_value_with_no_effect_is_named_when_it_is_not_written(tmp_path):
    """L's round trips: a film's thickness and IOR authored while thin_film_weight is 0 have no effect, and glTF
    writes no iridescence; reading the file back gives OpenPBR's defaults. The report says which values were not
    written and why, so a round trip changes nothing silently (263 unreported changes over L's 82 materials before
    this and L-03, 8 after)."""
    source = _openpbr(tmp_path, '    <input name="thin_film_thickness" type="float" value="0.3" />\n'
                                '    <input name="thin_film_ior" type="float" value="1.6" />\n')
    notes = _convert(source, tmp_path / "f.gltf")
    assert "KHR_materials_iridescence" not in (tmp_path / "f.gltf").read_text()
    inert = {n[2] for n in notes if n[0] == "OPBR1102" and "no effect" in n[3]}
    assert inert == {"thin_film_thickness", "thin_film_ior"}
