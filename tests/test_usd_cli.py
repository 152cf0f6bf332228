"""`openpbr validate` and `openpbr info` on USD files and on folders mixing MaterialX and USD, as a
user runs them; and USD costs nothing when no USD file is involved."""

from __future__ import annotations

import json
import os
import subprocess
import sys
import zipfile

import pytest
from click.testing import CliRunner

from cli.group import cli

GOOD = ('#usda 1.0\n(\n    defaultPrim = "M"\n    metersPerUnit = 0.01\n    upAxis = "Y"\n)\n\n'
        'def Material "M"\n{\n    token outputs:mtlx:surface.connect = </M/S.outputs:surface>\n'
        '    def Shader "S" (\n        customData = {\n            dictionary openpbr = {\n'
        '                string version = "1.1.1"\n            }\n        }\n    )\n    {\n'
        '        uniform token info:id = "ND_open_pbr_surface_surfaceshader"\n'
        "        color3f inputs:base_color = (0.5, 0.4, 0.3)\n        token outputs:surface\n    }\n}\n")
BROKEN = GOOD.replace("color3f inputs:base_color = (0.5, 0.4, 0.3)", "float inputs:base_weight = 1.5")
MTLX = ('<?xml version="1.0"?>\n<materialx version="1.39" colorspace="lin_rec709">\n'
        '  <open_pbr_surface name="S" type="surfaceshader" version="1.1.1">\n'
        '    <input name="base_color" type="color3" value="0.5, 0.4, 0.3" />\n  </open_pbr_surface>\n'
        '  <surfacematerial name="M" type="material">\n    <input name="surfaceshader" type="surfaceshader" nodename="S" />\n'
        "  </surfacematerial>\n</materialx>\n")


def run(*args):
    result = CliRunner().invoke(cli, list(map(str, args)))
    assert result.exception is None or isinstance(result.exception, SystemExit), result.output
    return result


def usdc(source, target):
    from pxr import Sdf

    layer = Sdf.Layer.FindOrOpen(str(source))
    layer.Export(str(target))


def test_clean_stage_exits_zero_and_an_error_exits_one_with_its_prim_path(tmp_path):
    (tmp_path / "good.usda").write_text(GOOD)
    (tmp_path / "bad.usda").write_text(BROKEN)
    assert run("validate", tmp_path / "good.usda").exit_code == 0
    result = run("validate", tmp_path / "bad.usda")
    assert result.exit_code == 1 and "OPBR301" in result.output and "/M/S.base_weight" in result.output


def test_folder_mixing_materialx_and_usd_is_validated_together(tmp_path):
    (tmp_path / "a.mtlx").write_text(MTLX)
    (tmp_path / "sub").mkdir()
    (tmp_path / "sub" / "b.usda").write_text(BROKEN)
    usdc(tmp_path / "sub" / "b.usda", tmp_path / "sub" / "c.usdc")
    result = run("validate", "--format", "json", tmp_path)
    report = json.loads(result.output)
    names = sorted(os.path.basename(f["path"]) for f in report["files"])
    assert names == ["a.mtlx", "b.usda", "c.usdc"] and result.exit_code == 1
    assert report["summary"]["materials"] == 3


def test_info_lists_usd_materials_with_prim_paths_and_textures(tmp_path):
    stage = GOOD.replace("color3f inputs:base_color = (0.5, 0.4, 0.3)", "color3f inputs:base_color.connect = </M/img.outputs:out>")
    stage = stage.replace("\n}\n", '\n    def Shader "img"\n    {\n        uniform token info:id = "ND_image_color3"\n'
                                   '        asset inputs:file = @albedo.png@ (colorSpace = "srgb_texture")\n'
                                   "        color3f outputs:out\n    }\n}\n")
    (tmp_path / "look.usda").write_text(stage)
    (tmp_path / "other.mtlx").write_text(MTLX)
    result = run("info", "--format", "json", tmp_path)
    entries = {os.path.basename(e["file"]): e for e in json.loads(result.output)}
    (material,) = entries["look.usda"]["materials"]
    assert entries["look.usda"]["format"] == "usd" and entries["look.usda"]["meters_per_unit"] == 0.01
    assert material["name"] == "/M/S" and material["material"] == "/M" and material["version"] == "1.1.1"
    assert material["textures"][0]["file"] == "albedo.png" and material["textures"][0]["colorspace"] == "srgb_texture"
    assert entries["other.mtlx"]["materials"][0]["model"] == "open_pbr_surface"


def _broken_files(folder):
    (folder / "corrupt.usdc").write_bytes(b"PXR-USDC" + os.urandom(200))
    (folder / "syntax.usda").write_text('#usda 1.0\ndef Material "M"\n{\n    float inputs:x = \n')
    with zipfile.ZipFile(folder / "missing.usdz", "w", zipfile.ZIP_STORED) as package:
        package.writestr("root.usda", '#usda 1.0\n(\n    subLayers = [@looks.usda@]\n)\n')
    return ["corrupt.usdc", "syntax.usda", "missing.usdz"]


@pytest.mark.parametrize("name", ["corrupt.usdc", "syntax.usda"])
def test_files_usd_cannot_open_exit_two_with_a_diagnostic(tmp_path, name):
    _broken_files(tmp_path)
    result = run("validate", tmp_path / name)
    assert result.exit_code == 2 and "Traceback" not in result.output
    assert "OPBR002" in result.output and ("USD cannot open" in result.output or "cannot be opened" in result.output)


def test_a_missing_layer_is_a_finding_and_the_rest_is_checked(tmp_path):
    """usd-core opens a stage whose sublayer is missing and composes the rest (a composition error): the missing layer
    is an error (OPBR1042, exit 1), not an unreadable stage (the red team's F#7: exit 2 hid every other finding)."""
    _broken_files(tmp_path)
    result = run("validate", tmp_path / "missing.usdz")
    assert result.exit_code == 1 and "Traceback" not in result.output
    assert "OPBR1042" in result.output and "looks.usda" in result.output and "OPBR002" not in result.output


def test_broken_usd_in_a_real_process_prints_no_usd_noise(tmp_path):
    """usd-core prints its own warnings and errors to stderr; the command must not."""
    names = _broken_files(tmp_path)
    done = subprocess.run([sys.executable, "-m", "cli.main", "validate", *[str(tmp_path / n) for n in names]],
                          capture_output=True, text=True)
    assert done.returncode == 2 and "Traceback" not in done.stdout + done.stderr
    assert "Warning" not in done.stderr and "Error in" not in done.stderr and "Error in" not in done.stdout
    assert done.stdout.count("OPBR002") == 2 and done.stdout.count("OPBR1042") == 1


def test_validating_only_materialx_never_imports_pxr(tmp_path):
    (tmp_path / "a.mtlx").write_text(MTLX)
    code = ("import sys\nfrom openpbr_tools.validate import validate_paths\n"
            f"report = validate_paths([{str(tmp_path)!r}])\n"
            "assert report.files and not report.unreadable, report.diagnostics\n"
            "print(sorted(m for m in sys.modules if m == 'pxr' or m.startswith('pxr.')))\n")
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert done.stdout.strip() == "[]"


def test_validating_usd_does_import_pxr(tmp_path):
    """The converse, so the test above cannot pass for the wrong reason."""
    (tmp_path / "a.usda").write_text(GOOD)
    code = ("import sys\nfrom openpbr_tools.validate import validate_paths\n"
            f"validate_paths([{str(tmp_path)!r}])\nprint('pxr' in sys.modules)\n")
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert done.stdout.strip() == "True"
