"""Red team session 21, set M: every file a command writes is refused (exit 2, one line) when it would
replace an input or a file the input reads; ``--changed-since`` never reaches git as an option; batch
reports name files as the user did; a batch into its own input folder, an input with nothing to convert
and an interrupted run each say so with their documented exit code.

The expectations come from the promises: inputs are never modified (their bytes and modification time
stay), exit 2 is usage or unreadable input, 1 is findings only, 130 is the shell's code for SIGINT."""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest
from click.testing import CliRunner

from cli.group import cli
from openpbr_tools.resources import data_dir

NEVER = "openpbr never modifies its input"

PLAIN = """<?xml version="1.0"?>
<materialx version="1.39" colorspace="lin_rec709">
  <open_pbr_surface name="S" type="surfaceshader" version="1.1.1">
    <input name="base_color" type="color3" value="0.6, 0.3, 0.2" />
  </open_pbr_surface>
  <surfacematerial name="M" type="material">
    <input name="surfaceshader" type="surfaceshader" nodename="S" />
  </surfacematerial>
</materialx>
"""


def _invoke(*args):
    return CliRunner().invoke(cli, [str(a) for a in args])


def _state(path: Path) -> tuple[bytes, int]:
    return path.read_bytes(), path.stat().st_mtime_ns


@pytest.fixture
def plain(tmp_path) -> Path:
    path = tmp_path / "a.mtlx"
    path.write_text(PLAIN, encoding="utf-8")
    return path


@pytest.fixture
def wood(tmp_path) -> Path:
    """The textured sample with its textures folder, in tmp_path."""
    samples = Path(data_dir("samples"))
    shutil.copy(samples / "textured_wood.mtlx", tmp_path / "w.mtlx")
    shutil.copytree(samples / "textures", tmp_path / "textures")
    return tmp_path / "w.mtlx"


def _refused(result, option: str = "") -> None:
    assert result.exit_code == 2, result.output
    assert NEVER in result.output and "Traceback" not in result.output
    if option:
        assert option in result.output


# -- M-04, M-05: validate's --output and --write-baseline ----------------------------------------------

def test_validate_output_naming_the_input_is_refused(plain):
    before = _state(plain)
    _refused(_invoke("validate", plain, "-o", plain, "--format", "json"), "--output")
    assert _state(plain) == before


def test_validate_output_through_the_click_free_path_is_refused_too(plain, capsys):
    from cli.validate_run import fast_validate

    before = _state(plain)
    assert fast_validate(["validate", str(plain), "-o", str(plain), "--format", "json"]) == 2
    assert NEVER in capsys.readouterr().err
    assert _state(plain) == before


def test_validate_output_naming_an_input_found_in_a_folder_is_refused(plain):
    before = _state(plain)
    _refused(_invoke("validate", plain.parent, "-o", plain))
    assert _state(plain) == before


def test_validate_output_naming_a_texture_the_input_reads_is_refused(wood):
    texture = wood.parent / "textures" / "wood_albedo.png"
    before = _state(texture)
    _refused(_invoke("validate", wood, "-o", texture), "a file the input reads")
    assert _state(texture) == before


def test_write_baseline_naming_the_input_is_refused(plain):
    before = _state(plain)
    _refused(_invoke("validate", plain, "--write-baseline", plain), "--write-baseline")
    assert _state(plain) == before


def test_write_baseline_through_a_hard_link_to_the_input_is_refused(plain):
    link = plain.parent / "linked.json"
    os.link(plain, link)
    before = _state(plain)
    _refused(_invoke("validate", plain, "--write-baseline", link))
    assert _state(plain) == before


# -- M-06: preview -o ---------------------------------------------------------------------------------

def test_preview_output_naming_the_input_is_refused(plain):
    before = _state(plain)
    _refused(_invoke("preview", plain, "-o", plain, "--size", "16"))
    assert _state(plain) == before


def test_preview_output_naming_a_texture_the_input_reads_is_refused(wood):
    texture = wood.parent / "textures" / "wood_albedo.png"
    before = _state(texture)
    _refused(_invoke("preview", wood, "-o", texture, "--size", "16"), "a file the input reads")
    assert _state(texture) == before


@pytest.mark.parametrize("name", ["out.jpg", "noextension"])
def test_preview_writes_only_png_names(plain, name):
    result = _invoke("preview", plain, "-o", plain.parent / name, "--size", "16")
    assert result.exit_code == 2 and ".png" in result.output
    assert not (plain.parent / name).exists()


def test_preview_keeps_an_existing_output_unless_forced(plain):
    sheet = plain.parent / "sheet.png"
    sheet.write_bytes(b"not yours")
    result = _invoke("preview", plain, "-o", sheet, "--size", "16")
    assert result.exit_code == 2 and "--force" in result.output
    assert sheet.read_bytes() == b"not yours"
    assert _invoke("preview", plain, "-o", sheet, "--size", "16", "--force").exit_code == 0
    assert sheet.read_bytes()[:4] == b"\x89PNG"


def test_preview_into_an_unwritable_folder_names_the_output_not_the_temporary_file(plain, monkeypatch):
    from openpbr_tools import atomic

    folder = plain.parent / "locked"

    def denied(path, data):  # what the atomic writer meets in a read-only folder (root ignores chmod)
        raise PermissionError(13, "Permission denied", str(folder / ".openpbr-abcd1234.tmp"))

    monkeypatch.setattr(atomic, "write_bytes", denied)
    target = folder / "p.png"
    result = _invoke("preview", plain, "-o", target, "--size", "16")
    assert result.exit_code == 2
    assert f"cannot write {target}: Permission denied" in result.output
    assert ".openpbr-" not in result.output


# -- M-07: --report and --delta-e-images ------------------------------------------------------------------

def test_compare_report_naming_an_input_is_refused(plain):
    before = _state(plain)
    _refused(_invoke("compare", plain, plain, "--report", plain, "--size", "16"), "--report")
    assert _state(plain) == before


def test_convert_report_naming_the_input_is_refused_before_anything_is_written(plain):
    before = _state(plain)
    output = plain.parent / "a.usda"
    _refused(_invoke("convert", plain, "-o", output, "--report", plain), "--report")
    assert _state(plain) == before and not output.exists()


def test_convert_report_naming_a_texture_the_input_reads_is_refused(wood):
    texture = wood.parent / "textures" / "wood_normal.png"
    before = _state(texture)
    _refused(_invoke("convert", wood, "-o", wood.parent / "w.usda", "--report", texture), "a file the input reads")
    assert _state(texture) == before


def test_delta_e_images_never_replace_a_texture_the_input_reads(wood):
    # the side-by-side of material VarnishedWood's sphere view is VarnishedWood_sphere.png: make it a texture
    textures = wood.parent / "textures"
    shutil.copy(textures / "wood_albedo.png", textures / "VarnishedWood_sphere.png")
    wood.write_text(wood.read_text(encoding="utf-8").replace("textures/wood_albedo.png",
                                                              "textures/VarnishedWood_sphere.png"), encoding="utf-8")
    before = _state(textures / "VarnishedWood_sphere.png")
    _refused(_invoke("compare", wood, wood, "--delta-e-images", textures, "--size", "16"), "--delta-e-images")
    assert _state(textures / "VarnishedWood_sphere.png") == before
    assert not (textures / "VarnishedWood_sphere_delta_e.png").exists()  # nothing written before the refusal


def test_convert_output_naming_an_included_document_is_refused(tmp_path):
    (tmp_path / "defs.mtlx").write_text(PLAIN, encoding="utf-8")
    look = tmp_path / "look.mtlx"
    look.write_text('<?xml version="1.0"?>\n<materialx version="1.39" xmlns:xi="http://www.w3.org/2001/XInclude">\n'
                    '  <xi:include href="defs.mtlx" />\n</materialx>\n', encoding="utf-8")
    before = _state(tmp_path / "defs.mtlx")
    _refused(_invoke("convert", look, "-o", tmp_path / "defs.mtlx", "--force"), "a file the input reads")
    assert _state(tmp_path / "defs.mtlx") == before


def test_convert_output_naming_a_sublayer_of_the_stage_is_refused(tmp_path):
    pytest.importorskip("pxr")
    layer = tmp_path / "layer.usda"
    layer.write_text('#usda 1.0\ndef Material "M"\n{\n    token outputs:surface.connect = </M/P.outputs:surface>\n'
                     '    def Shader "P"\n    {\n        uniform token info:id = "UsdPreviewSurface"\n'
                     '        color3f inputs:diffuseColor = (0.5, 0.2, 0.1)\n        token outputs:surface\n    }\n}\n',
                     encoding="utf-8")
    stage = tmp_path / "stage.usda"
    stage.write_text("#usda 1.0\n(\n    subLayers = [@./layer.usda@]\n)\n", encoding="utf-8")
    before = _state(layer)
    _refused(_invoke("convert", stage, "-o", layer, "--force"), "a file the input reads")
    assert _state(layer) == before


# -- M-18: --changed-since ------------------------------------------------------------------------------

def _git(folder: Path, *args: str) -> None:
    subprocess.run(["git", "-c", "user.email=t@example.com", "-c", "user.name=t", *args], cwd=folder, check=True,
                   capture_output=True)


@pytest.fixture
def repository(plain, monkeypatch):
    if shutil.which("git") is None:
        pytest.skip("needs git")
    _git(plain.parent, "init", "-q")
    _git(plain.parent, "add", ".")
    _git(plain.parent, "commit", "-qm", "first")
    monkeypatch.chdir(plain.parent)
    return plain.parent


@pytest.mark.parametrize("command", ["validate", "convert"])
def test_changed_since_never_reaches_git_as_an_option(repository, plain, command):
    victim = repository / "victim.txt"
    victim.write_text("keep me\n", encoding="utf-8")
    before = _state(plain)
    extra = ["--output-format", "usda", "-o", "out"] if command == "convert" else []
    result = _invoke(command, "a.mtlx", *extra, "--changed-since=--output=victim.txt")
    assert result.exit_code == 2 and "--changed-since" in result.output and "Traceback" not in result.output
    assert victim.read_text(encoding="utf-8") == "keep me\n"
    assert _state(plain) == before


def test_changed_since_resolves_the_ref_before_git_diff_sees_it(repository, monkeypatch):
    from openpbr_tools import selection

    seen = []
    real_run = subprocess.run

    def recording(command, *args, **kwargs):
        seen.append(command)
        return real_run(command, *args, **kwargs)

    monkeypatch.setattr(subprocess, "run", recording)
    assert selection.changed_since(["a.mtlx"], "HEAD") == []
    diff = next(c for c in seen if c[1] == "diff")
    assert all(len(part) == 40 and int(part, 16) >= 0 for part in diff[4:-1])  # only a commit hash, then --
    with pytest.raises(selection.SelectionError):
        selection.changed_since(["a.mtlx"], "-p")


def test_a_selection_that_leaves_no_file_says_so_and_keeps_exit_zero(repository):
    result = _invoke("validate", "a.mtlx", "--changed-since", "HEAD")
    assert result.exit_code == 0
    assert "--changed-since HEAD left none of the 1 file(s)" in result.stderr


# -- M-19, M-20: the batch form ---------------------------------------------------------------------------

@pytest.fixture
def batch_folder(tmp_path, monkeypatch) -> Path:
    folder = tmp_path / "bt"
    folder.mkdir()
    for name in ("brushed_aluminium", "car_paint"):  # their UsdPreviewSurface fallbacks have notes
        shutil.copy(Path(data_dir("samples")) / f"{name}.mtlx", folder)
    monkeypatch.chdir(tmp_path)
    return folder


@pytest.mark.parametrize("output_format", ["json", "sarif", "github"])
def test_batch_reports_name_files_as_the_user_did(batch_folder, output_format):
    result = CliRunner().invoke(cli, ["convert", "bt", "--output-format", "usda", "-o", "out",
                                      "--format", output_format])
    assert result.exit_code == 0, result.output
    if output_format == "json":
        assert [f["path"] for f in json.loads(result.stdout)["files"]] == ["bt/brushed_aluminium.mtlx", "bt/car_paint.mtlx"]
    elif output_format == "sarif":
        uris = {location["physicalLocation"]["artifactLocation"]["uri"]
                for run in json.loads(result.stdout)["runs"] for r in run["results"] for location in r.get("locations", [])}
        assert uris and all(u.startswith("bt/") for u in uris), uris
    else:
        assert "file=bt/" in result.stdout and str(batch_folder.parent) not in result.stdout


def test_batch_into_its_own_input_folder_is_refused_with_a_reason(batch_folder):
    before = {p.name: _state(p) for p in batch_folder.iterdir()}
    result = _invoke("convert", "bt", "--output-format", "mtlx", "-o", "bt", "--force")
    assert result.exit_code == 2
    assert "holds the input folder" in result.output
    assert {p.name: _state(p) for p in batch_folder.iterdir()} == before


# -- M-21: SIGINT -----------------------------------------------------------------------------------------

def test_an_interrupted_command_exits_130_not_the_findings_code(plain, monkeypatch):
    import openpbr_tools.convert

    def interrupt(*args, **kwargs):
        raise KeyboardInterrupt

    monkeypatch.setattr(openpbr_tools.convert, "convert_file", interrupt)
    result = _invoke("convert", plain, "-o", plain.parent / "a.usda")
    assert result.exit_code == 130
    assert "Aborted" not in result.output


def test_an_interrupted_click_free_validate_exits_130(plain, monkeypatch):
    import cli.main
    import openpbr_tools.validate

    def interrupt(*args, **kwargs):
        raise KeyboardInterrupt

    monkeypatch.setattr(openpbr_tools.validate, "validate_paths", interrupt)
    monkeypatch.setattr(sys, "argv", ["openpbr", "validate", str(plain)])
    with pytest.raises(SystemExit) as stopped:
        cli.main.main()
    assert stopped.value.code == 130


def test_the_exit_code_help_lists_130():
    assert "130 interrupted" in _invoke("--help").output


# -- M-14: nothing to convert -------------------------------------------------------------------------------

def test_convert_of_a_circular_include_writes_nothing_and_exits_2(tmp_path):
    include = '<?xml version="1.0"?>\n<materialx version="1.39" xmlns:xi="http://www.w3.org/2001/XInclude">' \
              '<xi:include href="{}"/></materialx>\n'
    (tmp_path / "x1.mtlx").write_text(include.format("x2.mtlx"), encoding="utf-8")
    (tmp_path / "x2.mtlx").write_text(include.format("x1.mtlx"), encoding="utf-8")
    result = _invoke("convert", tmp_path / "x1.mtlx", "-o", tmp_path / "x1.glb", "--format", "json")
    assert result.exit_code == 2
    assert "OPBR010" in [d["code"] for d in json.loads(result.stdout)["diagnostics"]]
    assert not (tmp_path / "x1.glb").exists()


def test_convert_of_a_file_without_materials_writes_nothing_and_exits_2(tmp_path):
    empty = tmp_path / "e.mtlx"
    empty.write_text('<?xml version="1.0"?>\n<materialx version="1.39"><nodegraph name="NG"/></materialx>\n',
                     encoding="utf-8")
    result = _invoke("convert", empty, "-o", tmp_path / "e.usda", "--format", "json")
    assert result.exit_code == 2
    assert "OPBR003" in [d["code"] for d in json.loads(result.stdout)["diagnostics"]]
    assert not (tmp_path / "e.usda").exists()


# -- minor: baseline read errors in the baseline's terms ----------------------------------------------------

@pytest.mark.parametrize("content", [
    '{"openpbr_baseline": 1, "findings": [{}]}',
    '[]',
    '{"openpbr_baseline": 1, "findings": 5}',
    '{"openpbr_baseline": 1, "findings": [3]}',
])
def test_a_malformed_baseline_is_named_not_a_python_error(plain, content):
    baseline = plain.parent / "b.json"
    baseline.write_text(content, encoding="utf-8")
    result = _invoke("validate", plain, "--baseline", baseline)
    assert result.exit_code == 2
    assert "baseline" in result.output
    for internal in ("'file'", "' object", "KeyError", "'code'"):  # Python's words: 'list' object has no ...
        assert internal not in result.output, result.output


def test_a_batch_over_a_folder_with_a_node_definition_library_converts_the_rest_and_passes(tmp_path):
    """M-14 refuses to write an empty output for a file with no material (exit 2 for that one file, as preview);
    a batch over a studio folder meets node-definition libraries beside the materials, which it skips with the
    same OPBR003 as an info: the run converted everything there was, so it exits 0."""
    folder = tmp_path / "in"
    folder.mkdir()
    shutil.copy(Path(data_dir("samples")) / "car_paint.mtlx", folder / "car_paint.mtlx")
    (folder / "lib.mtlx").write_text('<?xml version="1.0"?>\n<materialx version="1.39">\n  <nodedef name="ND_x_float" '
                                     'node="x">\n    <output name="out" type="float" />\n  </nodedef>\n</materialx>\n')
    result = _invoke("convert", folder, "--output-format", "gltf", "-o", tmp_path / "out", "--format", "json")
    assert result.exit_code == 0, result.output
    report = json.loads(result.stdout)
    assert [(d["code"], d["severity"]) for d in report["diagnostics"] if d["location"]["file"].endswith("lib.mtlx")] \
        == [("OPBR003", "info")]
    assert (tmp_path / "out" / "car_paint.gltf").is_file() and not (tmp_path / "out" / "lib.gltf").exists()
    assert _invoke("convert", folder / "lib.mtlx", "-o", tmp_path / "lib.gltf").exit_code == 2
