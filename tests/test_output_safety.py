"""Output safety: the same input gives byte-identical outputs and reports in another folder and
another process; inputs are never modified; packages never take files from outside the asset's
folder unless allowed; a refused or failed conversion leaves nothing behind."""

from __future__ import annotations

import hashlib
import json
import os
import shutil
import subprocess
import sys
import zipfile
from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner
from PIL import Image

from cli.group import cli

SAMPLES = Path(__file__).resolve().parent.parent / "openpbr_tools" / "samples"
OUTPUTS = ("wood.gltf", "wood.glb", "wood.usda", "wood.usdc", "wood.usdz", "wood_ss.mtlx", "paint.glb", "paint.usdz")

SCRIPT = """
import json, sys
from click.testing import CliRunner
from cli.group import cli
runs = [("asset/textured_wood.mtlx", "out/wood.gltf", []), ("asset/textured_wood.mtlx", "out/wood.glb", ["--mesh", "sphere"]),
        ("asset/textured_wood.mtlx", "out/wood.usda", []), ("asset/textured_wood.mtlx", "out/wood.usdc", []),
        ("asset/textured_wood.mtlx", "out/wood.usdz", []), ("asset/textured_wood.mtlx", "out/wood_ss.mtlx", ["--to", "standard_surface"]),
        ("asset/car_paint.mtlx", "out/paint.glb", []), ("asset/car_paint.mtlx", "out/paint.usdz", [])]
reports = {}
for source, output, extra in runs:
    result = CliRunner().invoke(cli, ["convert", source, "-o", output, "--format", "json", "--verify", *extra])
    assert result.exit_code in (0, 1), result.output
    reports[output] = result.stdout
print(json.dumps(reports, sort_keys=True))
"""


def tree(folder: Path) -> dict[str, str]:
    return {str(p.relative_to(folder)): hashlib.sha256(p.read_bytes()).hexdigest()
            for p in sorted(folder.rglob("*")) if p.is_file()}


def run_in(folder: Path, seed: str) -> dict:
    shutil.copytree(SAMPLES, folder / "asset")
    (folder / "out").mkdir()
    environment = dict(os.environ, PYTHONHASHSEED=seed, PYTHONPATH=str(Path(__file__).resolve().parent.parent))
    completed = subprocess.run([sys.executable, "-c", SCRIPT], check=False, cwd=folder, env=environment, capture_output=True,
                               text=True, timeout=300)
    assert completed.returncode == 0, completed.stderr
    return json.loads(completed.stdout)


def test_outputs_and_reports_are_byte_identical_across_processes_and_folders(tmp_path):
    inputs_before = tree(SAMPLES)
    first = run_in(tmp_path / "first", "1")
    second = run_in(tmp_path / "elsewhere" / "second", "2")
    assert first == second  # the loss and --verify reports
    outputs = tree(tmp_path / "first" / "out")
    assert outputs == tree(tmp_path / "elsewhere" / "second" / "out")
    assert set(OUTPUTS) <= set(outputs)
    assert tree(tmp_path / "first" / "asset") == inputs_before  # inputs untouched
    assert tree(SAMPLES) == inputs_before


def convert(*args):
    result = CliRunner().invoke(cli, ["convert", *map(str, args)])
    assert "Traceback" not in result.output
    return result


@pytest.fixture
def outside_asset(tmp_path):
    library = tmp_path / "library"
    library.mkdir()
    Image.fromarray(np.arange(48, dtype=np.uint8).reshape(4, 4, 3)).save(library / "albedo.png")
    asset = tmp_path / "asset"
    asset.mkdir()
    (asset / "m.mtlx").write_text("""<?xml version="1.0"?>
<materialx version="1.39" colorspace="lin_rec709">
  <image name="c" type="color3"><input name="file" type="filename" value="../library/albedo.png" colorspace="srgb_texture"/></image>
  <open_pbr_surface name="S" type="surfaceshader"><input name="base_color" type="color3" nodename="c"/></open_pbr_surface>
  <surfacematerial name="M" type="material"><input name="surfaceshader" type="surfaceshader" nodename="S"/></surfacematerial>
</materialx>
""")
    return asset, library


@pytest.mark.parametrize("suffix", [".usdz", ".glb"])
def test_packages_refuse_textures_outside_the_asset_folder(outside_asset, suffix):
    asset, library = outside_asset
    output = asset / f"out{suffix}"
    refused = convert(asset / "m.mtlx", "-o", output)
    assert refused.exit_code == 2 and "outside the source asset's folder" in refused.output
    assert sorted(p.name for p in asset.iterdir()) == ["m.mtlx"]  # no output, no temporary file left
    allowed = convert(asset / "m.mtlx", "-o", output, "--allow-outside", library)
    assert allowed.exit_code == 0, allowed.output
    if suffix == ".usdz":
        with zipfile.ZipFile(output) as package:
            names = package.namelist()
        assert names[0].endswith(".usdc") and "textures/albedo.png" in names


@pytest.mark.parametrize("suffix", [".usdz", ".glb"])
def test_a_package_does_not_take_a_symlink_escaping_the_folder(outside_asset, suffix):
    asset, library = outside_asset
    os.symlink(library / "albedo.png", asset / "albedo.png")
    text = (asset / "m.mtlx").read_text().replace("../library/albedo.png", "albedo.png")
    (asset / "m.mtlx").write_text(text)
    result = convert(asset / "m.mtlx", "-o", asset / f"out{suffix}")
    assert result.exit_code == 2 and "outside the source asset's folder" in result.output
    assert not (asset / f"out{suffix}").exists()


def test_references_without_packaging_are_written_not_read(outside_asset):
    """A .usda or .mtlx output only names the texture; nothing outside the folder is opened."""
    asset, library = outside_asset
    os.chmod(library / "albedo.png", 0)  # unreadable: a read would fail
    try:
        for name in ("out.usda", "out.mtlx"):
            result = convert(asset / "m.mtlx", "-o", asset / name)
            assert result.exit_code == 0, result.output
            assert "../library/albedo.png" in (asset / name).read_text()
    finally:
        os.chmod(library / "albedo.png", 0o644)


@pytest.mark.parametrize("name", ["o.mtlx", "o.usda", "o.usdz", "o.gltf", "o.glb"])
def test_outputs_get_the_usual_permissions_not_the_temporary_files(tmp_path, name):
    previous = os.umask(0o022)
    try:
        assert convert(SAMPLES / "textured_wood.mtlx", "-o", tmp_path / name).exit_code == 0
    finally:
        os.umask(previous)
    written = [p for p in tmp_path.rglob("*") if p.is_file()]
    assert written and all(p.stat().st_mode & 0o777 == 0o644 for p in written)
