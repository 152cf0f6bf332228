"""The translation test set (``tests/data/translation_set``): every material converts, glTF output is
valid, units, dispersion, thin film, emission, normal maps and UV transforms reach glTF as the
Khronos extensions define them, and the evaluator's median colour difference meets issue 5's
target.

Expected numbers come from the specifications, not from the converter:

* ``KHR_materials_volume``: ``attenuationDistance`` is the distance (metres) at which light reaches
  ``attenuationColor``, which is what OpenPBR's ``transmission_depth`` / ``transmission_color`` mean,
  so the distance is the depth times the metres of its MaterialX ``unit``;
* ``KHR_materials_dispersion``: ``dispersion = 20 / V`` for an Abbe number V (OpenPBR's
  ``transmission_dispersion_scale`` 1 gives the full ``20 / abbe``);
* ``KHR_materials_iridescence``: thickness in nanometres (OpenPBR 1.1.1: micrometres);
* emitted radiance: ``emissiveFactor * emissive_strength`` equals ``emission_luminance *
  emission_color`` at one nit per unit (``openpbr convert``'s default ``--nits-per-unit``).

The full comparison against MaterialX's own translation chain and its GLSL renderer is
``tests/benchmarks/bench_translation.py`` (minutes); this module stays within a few seconds.
"""

from __future__ import annotations

import glob
import json
import os
import statistics
import subprocess

import pytest
from gltf_support import require_validator

from openpbr_tools.evaluate.preview import Rig
from openpbr_tools.evaluate.verify import compare_materials
from openpbr_tools.io import read_asset
from openpbr_tools.model import Constant, Texture
from openpbr_tools.convert import convert_file
from openpbr_tools.translate.convert import MODELS, convert
from openpbr_tools.validate import validate_file

SET = os.path.join(os.path.dirname(os.path.abspath(__file__)), "data", "translation_set")
FILES = sorted(glob.glob(os.path.join(SET, "*.mtlx")))
TARGETS = ("standard_surface", "gltf_pbr", "UsdPreviewSurface")
#: Issue 5: median mean-ΔE2000 over the set, OpenPBR -> glTF and -> Standard Surface.
MEDIAN_TARGET = {"standard_surface": 1.0, "gltf_pbr": 1.0}
METRES = {"meter": 1.0, "centimeter": 0.01, "millimeter": 0.001}


def stem(path: str) -> str:
    return os.path.splitext(os.path.basename(path))[0]


@pytest.fixture(scope="module")
def materials():
    return {stem(path): read_asset(path).materials[0] for path in FILES}


@pytest.fixture(scope="module")
def gltf_files(tmp_path_factory):
    """Every file of the set converted to .gltf as ``openpbr convert`` does."""
    folder = tmp_path_factory.mktemp("translation_set_gltf")
    written = {}
    for path in FILES:
        output = folder / f"{stem(path)}.gltf"
        convert_file(path, str(output))
        written[stem(path)] = output
    return written


def gltf_material(gltf_files, name: str) -> dict:
    document = json.loads(gltf_files[name].read_text(encoding="utf-8"))
    assert len(document["materials"]) == 1
    return document["materials"][0]


def authored(material, name):
    entry = material.inputs.get(name)
    return entry.value.value if entry is not None and isinstance(entry.value, Constant) else None


# -- the set itself -------------------------------------------------------------------------------

def test_the_set_has_at_least_40_materials_spanning_the_issues_list(materials):
    """At least 40 materials, and each family issue 5 names is present."""
    assert len(materials) >= 40

    def having(**conditions):
        return [n for n, m in materials.items() if all(test(m) for test in conditions.values())]

    def value(name, default=0.0):
        return lambda m: authored(m, name) if authored(m, name) is not None else default

    def metal(m):
        return value("base_metalness")(m) == 1.0

    families = {
        "metal with edge tint": having(metal=metal, tint=lambda m: authored(m, "specular_color") not in (None, (1.0, 1.0, 1.0))),
        "coated metal": having(metal=metal, coat=lambda m: value("coat_weight")(m) > 0),
        "anisotropic metal": having(metal=metal, aniso=lambda m: value("specular_roughness_anisotropy")(m) > 0),
        "clear glass": having(t=lambda m: value("transmission_weight")(m) == 1.0, clear=lambda m: authored(m, "transmission_color") is None),
        "tinted thick glass with a unit": having(depth=lambda m: value("transmission_depth")(m) > 0,
                                                 unit=lambda m: m.inputs["transmission_depth"].unit in METRES),
        "dispersion": having(d=lambda m: value("transmission_dispersion_scale")(m) > 0),
        "thin-walled translucent": having(thin=lambda m: authored(m, "geometry_thin_walled") is True,
                                          sss=lambda m: value("subsurface_weight")(m) > 0),
        "velvet (fuzz)": having(f=lambda m: value("fuzz_weight")(m) == 1.0),
        "subsurface": having(sss=lambda m: value("subsurface_weight")(m) == 1.0, thick=lambda m: not authored(m, "geometry_thin_walled")),
        "car paint (coat + thin film)": having(c=lambda m: value("coat_weight")(m) == 1.0, f=lambda m: value("thin_film_weight")(m) > 0),
        "emissive": having(e=lambda m: value("emission_luminance")(m) > 0),
        "coloured coat": having(c=lambda m: authored(m, "coat_color") not in (None, (1.0, 1.0, 1.0))),
        "textured with a normal map and a UV transform": having(
            n=lambda m: isinstance(m.inputs.get("geometry_normal") and m.inputs["geometry_normal"].value, Texture),
            uv=lambda m: any(t.uv is not None for _, t in m.textures())),
    }
    missing = [family for family, names in families.items() if not names]
    assert not missing, f"families without a material: {missing}"


@pytest.mark.parametrize("path", FILES, ids=[stem(p) for p in FILES])
def test_every_file_is_one_valid_openpbr_1_1_1_material_with_a_description(path):
    result = validate_file(path)
    errors = [f"{d.code} {d.message}" for d in result.diagnostics if str(d.severity) == "error"]
    assert not errors
    (material,) = read_asset(path).materials
    assert (material.model, material.version) == ("open_pbr_surface", "1.1.1")
    import MaterialX as mx

    document = mx.createDocument()
    mx.readFromXmlFile(document, path)
    (shader,) = [n for n in document.getNodes() if n.getCategory() == "open_pbr_surface"]
    assert len(shader.getDocString()) > 20


def test_textures_of_the_set_are_tiny_and_present(materials):
    from PIL import Image

    used = set()
    for material in materials.values():
        for _, texture in material.textures():
            path = os.path.join(SET, texture.file)
            assert os.path.isfile(path), texture.file
            with Image.open(path) as image:
                assert image.size[0] <= 16 and image.size[1] <= 16
            used.add(os.path.normpath(path))
    assert used, "the set has no textured material"
    on_disk = {os.path.normpath(p) for p in glob.glob(os.path.join(SET, "textures", "*"))}
    assert on_disk == used, f"unused files: {sorted(on_disk - used)}"


# -- conversion ----------------------------------------------------------------------------------

@pytest.mark.parametrize("target", TARGETS)
def test_every_material_converts_to_every_target(materials, target):
    assert target in MODELS
    failures = {}
    for name, material in materials.items():
        try:
            result = convert(material, target).material
        except Exception as error:  # noqa: BLE001 - collected so one run names every failure
            failures[name] = f"{type(error).__name__}: {error}"
            continue
        if result.model != target:
            failures[name] = f"model {result.model}"
    assert not failures, failures


def test_every_gltf_written_from_the_set_passes_the_khronos_validator(gltf_files, tmp_path):
    node, folder = require_validator()
    script = tmp_path / "validate_many.js"
    # One node process for the whole set (gltf_support.SCRIPT validates one file per process).
    script.write_text(r"""
const fs = require("fs"), path = require("path");
const validator = require(process.argv[2]);
(async () => {
  const reports = {};
  for (const file of process.argv.slice(3)) {
    const folder = path.dirname(file);
    const report = await validator.validateBytes(new Uint8Array(fs.readFileSync(file)), {
      uri: path.basename(file), maxIssues: 0, writeTimestamp: false,
      externalResourceFunction: (uri) => new Promise((resolve, reject) => fs.readFile(
        path.resolve(folder, decodeURIComponent(uri)), (e, d) => e ? reject(e.toString()) : resolve(new Uint8Array(d)))),
    });
    reports[file] = report.issues;
  }
  process.stdout.write(JSON.stringify(reports));
})().catch((e) => { process.stderr.write(String(e)); process.exit(3); });
""", encoding="utf-8")
    files = [str(p) for p in gltf_files.values()]
    completed = subprocess.run([node, str(script), os.path.abspath(folder), *files], capture_output=True, text=True,
                               timeout=120, check=False)
    assert completed.returncode == 0, completed.stderr
    reports = json.loads(completed.stdout)
    assert len(reports) == len(FILES)
    bad = {os.path.basename(f): [f"{m['code']} {m.get('pointer', '')}: {m['message']}" for m in issues["messages"] if m["severity"] == 0]
           for f, issues in reports.items() if issues["numErrors"]}
    assert not bad, bad


@pytest.mark.parametrize("name", ["glass_tinted_thick_cm", "glass_tinted_amber_mm", "liquid_water"])
def test_gltf_volume_carries_transmission_depth_in_metres(materials, gltf_files, name):
    source = materials[name]
    depth = source.inputs["transmission_depth"]
    volume = gltf_material(gltf_files, name)["extensions"]["KHR_materials_volume"]
    assert volume["attenuationDistance"] == pytest.approx(depth.value.value * METRES[depth.unit], rel=1e-6)
    assert volume["attenuationColor"] == pytest.approx(list(authored(source, "transmission_color")), abs=1e-6)


@pytest.mark.parametrize("name", ["glass_flint_dispersion", "gem_diamond"])
def test_gltf_dispersion_is_20_over_the_abbe_number(materials, gltf_files, name):
    source = materials[name]
    expected = authored(source, "transmission_dispersion_scale") * 20.0 / authored(source, "transmission_dispersion_abbe_number")
    extensions = gltf_material(gltf_files, name)["extensions"]
    assert extensions["KHR_materials_dispersion"]["dispersion"] == pytest.approx(expected, rel=1e-6)
    assert extensions["KHR_materials_ior"]["ior"] == pytest.approx(authored(source, "specular_ior"), rel=1e-6)


@pytest.mark.parametrize("name", ["thin_soap_bubble", "iridescent_beetle", "car_paint_pearl_white"])
def test_gltf_iridescence_thickness_is_in_nanometres(materials, gltf_files, name):
    source = materials[name]
    iridescence = gltf_material(gltf_files, name)["extensions"]["KHR_materials_iridescence"]
    assert iridescence["iridescenceThicknessMaximum"] == pytest.approx(authored(source, "thin_film_thickness") * 1000.0, rel=1e-6)
    assert iridescence["iridescenceIor"] == pytest.approx(authored(source, "thin_film_ior"), rel=1e-6)
    assert iridescence.get("iridescenceFactor", 0.0) == pytest.approx(authored(source, "thin_film_weight"), rel=1e-6)


@pytest.mark.parametrize("name", ["emissive_led_panel", "emissive_neon_orange", "emissive_lava", "emissive_hdr_color"])
def test_gltf_emission_keeps_the_luminance_at_one_nit_per_unit(materials, gltf_files, name):
    source = materials[name]
    expected = [authored(source, "emission_luminance") * c for c in authored(source, "emission_color")]
    written = gltf_material(gltf_files, name)
    strength = written.get("extensions", {}).get("KHR_materials_emissive_strength", {}).get("emissiveStrength", 1.0)
    assert max(written["emissiveFactor"]) <= 1.0
    assert [strength * c for c in written["emissiveFactor"]] == pytest.approx(expected, rel=1e-5)


@pytest.mark.parametrize("name", [stem(p) for p in FILES if stem(p).startswith("textured_")])
def test_gltf_keeps_normal_maps_and_uv_transforms_of_textured_materials(materials, gltf_files, name):
    source = materials[name]
    written = gltf_material(gltf_files, name)
    normal = source.inputs.get("geometry_normal")
    if normal is not None and isinstance(normal.value, Texture):
        assert "normalTexture" in written
        assert written["normalTexture"].get("scale", 1.0) == pytest.approx(normal.value.normal_map, rel=1e-6)
        if normal.value.uv is not None:
            assert "KHR_texture_transform" in written["normalTexture"].get("extensions", {})
    coat_normal = source.inputs.get("geometry_coat_normal")
    if coat_normal is not None and isinstance(coat_normal.value, Texture):
        assert "clearcoatNormalTexture" in written["extensions"]["KHR_materials_clearcoat"]
    base = source.inputs.get("base_color")
    if base is not None and isinstance(base.value, Texture):
        info = written["pbrMetallicRoughness"]["baseColorTexture"]
        assert ("KHR_texture_transform" in info.get("extensions", {})) == (base.value.uv is not None)


@pytest.mark.parametrize("target", sorted(MEDIAN_TARGET))
def test_median_evaluator_delta_e_meets_the_issue_target(materials, target, record_property):
    """Issue 5: median mean-ΔE2000 ≤ 1.0 over the constant-valued materials of the set, evaluated
    on the lit sphere (a 64-pixel preview: the median moves by less than 0.01 from 128 pixels)."""
    rig = Rig(size=64)
    deltas = {}
    for name, material in materials.items():
        if material.textures():
            continue
        deltas[name] = compare_materials(material, convert(material, target).material, rig).preview.mean
    median = statistics.median(deltas.values())
    record_property("median_delta_e2000", round(median, 3))
    worst = sorted(deltas.items(), key=lambda item: -item[1])[:5]
    assert median <= MEDIAN_TARGET[target], f"median {median:.2f} over {len(deltas)} materials; worst {worst}"
