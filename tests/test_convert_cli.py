"""`openpbr convert` as a user runs it: outputs that validate, loss reports, safety of outputs."""

from __future__ import annotations

import hashlib
import json

import pytest
from click.testing import CliRunner

from cli.group import cli
from openpbr_tools.io import read_asset
from openpbr_tools.resources import data_dir
from openpbr_tools.validate import validate_file

SAMPLES = data_dir("samples")


def run(*args):
    result = CliRunner().invoke(cli, [str(a) for a in args])
    assert result.exception is None or isinstance(result.exception, SystemExit), result.output
    assert "Traceback" not in result.output
    return result


@pytest.mark.parametrize("model", ["standard_surface", "gltf_pbr", "UsdPreviewSurface", "open_pbr_surface"])
def test_mtlx_to_each_model_writes_a_document_without_errors(tmp_path, model):
    out = tmp_path / "out" / f"{model}.mtlx"
    out.parent.mkdir()
    result = run("convert", SAMPLES / "textured_wood.mtlx", "-o", out, "--to", model)
    assert result.exit_code == 0
    (material,) = read_asset(out).materials
    assert material.model == model
    errors = [d for d in validate_file(str(out)).diagnostics if d.severity.name == "ERROR"]
    assert errors == []  # textures still resolve from the new folder, values in range


def test_usd_output_carries_openpbr_and_a_preview_fallback(tmp_path):
    out = tmp_path / "wood.usda"
    assert run("convert", SAMPLES / "car_paint.mtlx", "-o", out).exit_code == 0
    models = sorted(m.model for m in read_asset(out).materials)
    assert models == ["UsdPreviewSurface", "open_pbr_surface"]
    assert not [d for d in validate_file(str(out)).diagnostics if d.severity.name == "ERROR"]


def test_loss_report_in_json_and_fail_on(tmp_path):
    out = tmp_path / "preview.mtlx"
    result = run("convert", SAMPLES / "car_paint.mtlx", "-o", out, "--to", "UsdPreviewSurface", "--format", "json",
                 "--fail-on", "error")
    report = json.loads(result.stdout)
    assert result.exit_code == 1  # the thin film cannot be carried
    assert any(d["code"] == "OPBR1104" and "thin film" in d["message"] for d in report["diagnostics"])


def test_legacy_input_is_upgraded_on_the_way(tmp_path):
    out = tmp_path / "ss.mtlx"
    assert run("convert", SAMPLES / "broken" / "legacy_openpbr_0_2.mtlx", "-o", out, "--to", "standard_surface").exit_code == 0
    bubble = next(m for m in read_asset(out).materials if m.name == "OldSoapBubble")
    assert bubble.inputs["thin_film_thickness"].constant == pytest.approx(380.0)  # nm in 0.2 and in Standard Surface


def test_output_is_deterministic_and_the_input_untouched(tmp_path):
    source = SAMPLES / "brushed_aluminium.mtlx"
    before = hashlib.sha256(source.read_bytes()).hexdigest()
    first, second = tmp_path / "a.mtlx", tmp_path / "b.mtlx"
    run("convert", source, "-o", first, "--to", "gltf_pbr")
    run("convert", source, "-o", second, "--to", "gltf_pbr")
    assert first.read_bytes() == second.read_bytes()
    assert hashlib.sha256(source.read_bytes()).hexdigest() == before


def test_existing_output_needs_force_and_input_is_never_the_output(tmp_path):
    out = tmp_path / "o.mtlx"
    out.write_text("keep")
    assert run("convert", SAMPLES / "car_paint.mtlx", "-o", out).exit_code == 2
    assert out.read_text() == "keep"
    copy = tmp_path / "copy.mtlx"
    copy.write_bytes((SAMPLES / "car_paint.mtlx").read_bytes())
    assert run("convert", copy, "-o", copy, "--force").exit_code == 2


def test_unreadable_input_exits_two_and_writes_nothing(tmp_path):
    bad = tmp_path / "bad.mtlx"
    bad.write_bytes(b"<materialx")
    out = tmp_path / "o.mtlx"
    assert run("convert", bad, "-o", out).exit_code == 2
    assert not out.exists()


def test_unknown_output_suffix_is_a_usage_error(tmp_path):
    assert run("convert", SAMPLES / "car_paint.mtlx", "-o", tmp_path / "x.fbx").exit_code == 2


@pytest.mark.parametrize("sample", ["textured_wood", "car_paint", "tinted_glass", "brushed_aluminium"])
def test_gltf_output_passes_the_khronos_validator(tmp_path, sample):
    from gltf_support import describe_issues, require_validator, validate_with_khronos

    require_validator()
    out = tmp_path / f"{sample}.glb"
    assert run("convert", SAMPLES / f"{sample}.mtlx", "-o", out, "--mesh", "sphere").exit_code == 0
    report = validate_with_khronos(out, tmp_path)
    assert report["issues"]["numErrors"] == 0, describe_issues(report)
    (material,) = read_asset(out).materials
    assert material.model == "gltf_pbr"


def test_gltf_round_trip_back_to_openpbr_mtlx(tmp_path):
    glb, back = tmp_path / "glass.glb", tmp_path / "glass.mtlx"
    run("convert", SAMPLES / "tinted_glass.mtlx", "-o", glb)
    assert run("convert", glb, "-o", back).exit_code == 0
    (material,) = read_asset(back).materials
    assert material.inputs["transmission_weight"].constant == pytest.approx(1.0)
    assert material.inputs["specular_ior"].constant == pytest.approx(1.52)
    # 2 cm in the source became 0.02 m in glTF and comes back as 0.02, now labelled metres
    depth = material.inputs["transmission_depth"]
    assert depth.constant == pytest.approx(0.02, rel=1e-6) and (depth.unit, depth.unittype) == ("meter", "distance")


def test_verify_reports_delta_e_per_material(tmp_path):
    out = tmp_path / "paint.mtlx"
    result = run("convert", SAMPLES / "car_paint.mtlx", "-o", out, "--to", "standard_surface", "--verify",
                 "--format", "json")
    verified = [d for d in json.loads(result.stdout)["diagnostics"] if d["code"] in ("OPBR1108", "OPBR1109")]
    assert len(verified) == 1 and "CIEDE2000 mean" in verified[0]["message"]


def test_verify_flags_a_lossy_conversion_above_the_threshold(tmp_path):
    # A thick green glass has no transmission in UsdPreviewSurface: it cannot look the same.
    out = tmp_path / "glass.mtlx"
    result = run("convert", SAMPLES / "tinted_glass.mtlx", "-o", out, "--to", "UsdPreviewSurface", "--verify",
                 "--threshold", "1", "--format", "json")
    codes = [d["code"] for d in json.loads(result.stdout)["diagnostics"]]
    assert "OPBR1109" in codes


def test_a_constant_of_the_wrong_shape_is_reported_not_a_crash(tmp_path):
    """Found by fuzzing: a colour4 on a colour3 input made the NumPy formulas raise."""
    source = tmp_path / "c4.mtlx"
    source.write_text('<?xml version="1.0"?>\n<materialx version="1.39">\n'
                      '  <open_pbr_surface name="S" type="surfaceshader">\n'
                      '    <input name="transmission_color" type="color4" value="1, 0.5, 0.5, 1"/>\n'
                      '    <input name="transmission_depth" type="float" value="1"/>\n'
                      '    <input name="base_weight" type="color3" value="1, 0.5, 0.5"/>\n'
                      '  </open_pbr_surface>\n</materialx>\n')
    for name, extra in (("o.gltf", []), ("o.mtlx", ["--to", "standard_surface"]), ("o.usda", [])):
        result = run("convert", source, "-o", tmp_path / name, "--format", "json", *extra)
        assert result.exit_code == 0, result.output
        lost = {d["location"]["input"] for d in json.loads(result.stdout)["diagnostics"] if d["code"] == "OPBR1104"}
        assert {"transmission_color", "base_weight"} <= lost


def test_max_delta_e_fails_the_command_and_names_the_material(tmp_path, write_mtlx):
    # a fuzz layer has no glTF equivalent but sheen: the evaluator sees a difference well above 0
    source = write_mtlx('<open_pbr_surface name="S" type="surfaceshader">\n'
                        '  <input name="fuzz_weight" type="float" value="1" />\n'
                        '  <input name="thin_film_weight" type="float" value="1" />\n</open_pbr_surface>')
    strict = CliRunner().invoke(cli, ["convert", str(source), "-o", str(tmp_path / "a.gltf"), "--max-delta-e", "0"])
    assert strict.exit_code == 1 and "above --max-delta-e 0: M" in strict.stderr
    assert "OPBR1109" in strict.stdout  # the report carries the number at the material
    lenient = CliRunner().invoke(cli, ["convert", str(source), "-o", str(tmp_path / "b.gltf"), "--max-delta-e", "100"])
    assert lenient.exit_code == 0 and "OPBR1108" in lenient.stdout


def test_verify_evaluates_textures_at_their_mean_texel(tmp_path):
    # A uniform sRGB texture (level 128 decodes to 0.2158 linear, IEC 61966-2-1) against the constant
    # it stands for: the evaluator shades constants, so --verify must read the texture, not its fallback
    # (absent here: OpenPBR's default base colour 0.8 would be 20+ CIEDE2000 away).
    from PIL import Image

    Image.new("RGB", (8, 8), (128, 128, 128)).save(tmp_path / "grey.png")
    source = tmp_path / "textured.mtlx"
    source.write_text(
        '<?xml version="1.0"?>\n<materialx version="1.39" colorspace="lin_rec709">\n'
        '  <image name="img" type="color3"><input name="file" type="filename" value="grey.png" colorspace="srgb_texture" /></image>\n'
        '  <open_pbr_surface name="S" type="surfaceshader"><input name="base_color" type="color3" nodename="img" /></open_pbr_surface>\n'
        '  <surfacematerial name="M" type="material"><input name="surfaceshader" type="surfaceshader" nodename="S" /></surfacematerial>\n'
        '</materialx>\n')
    result = CliRunner().invoke(cli, ["convert", str(source), "-o", str(tmp_path / "out.gltf"), "--verify",
                                      "--format", "json"])
    (verified,) = [d for d in json.loads(result.stdout)["diagnostics"] if d["code"] in ("OPBR1108", "OPBR1109")]
    assert verified["code"] == "OPBR1108" and float(verified["message"].split("mean ")[1].split(",")[0]) < 0.5


@pytest.mark.parametrize("suffix", [".gltf", ".glb", ".usda", ".usdz", ".mtlx"])
def test_output_in_a_folder_that_does_not_exist_yet(tmp_path, suffix):
    """The output's folder is made, as the batch form makes its tree (before: a traceback from the
    atomic writer's temporary file)."""
    output = tmp_path / "new" / "deeper" / f"wood{suffix}"
    result = run("convert", data_dir("samples") / "textured_wood.mtlx", "-o", output)
    assert result.exit_code == 0, result.output
    assert output.is_file()


def test_output_that_cannot_be_written_exits_two_with_a_message(tmp_path):
    blocker = tmp_path / "file"
    blocker.write_text("not a folder")
    result = run("convert", data_dir("samples") / "textured_wood.mtlx", "-o", blocker / "out.gltf")
    assert result.exit_code == 2 and "cannot write" in result.output and "Traceback" not in result.output


@pytest.mark.parametrize("command", [
    ["upgrade", "{samples}/broken/legacy_openpbr_0_2.mtlx", "-o", "{out}/a.mtlx"],
    ["validate", "{samples}", "--output", "{out}/r.json", "--format", "json"],
    ["preview", "{samples}/car_paint.mtlx", "-o", "{out}/p.png"],
    ["compare", "{samples}/car_paint.mtlx", "{samples}/car_paint.mtlx", "--report", "{out}/r.html"],
])
def test_every_command_writes_into_a_new_folder_and_never_tracebacks(tmp_path, command):
    """Outputs are written atomically (openpbr_tools.atomic), which makes a missing folder; a path
    that cannot be a folder exits 2 with a message."""
    samples = str(data_dir("samples"))
    args = [a.format(samples=samples, out=tmp_path / "new" / "deeper") for a in command]
    result = run(*args)
    assert result.exit_code in (0, 1), result.output
    assert (tmp_path / "new" / "deeper").is_dir() and any((tmp_path / "new" / "deeper").iterdir())
    (tmp_path / "blocker").write_text("a file")
    blocked = run(*[a.format(samples=samples, out=tmp_path / "blocker") for a in command])
    assert blocked.exit_code == 2 and "Traceback" not in blocked.output, blocked.output
