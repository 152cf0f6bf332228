"""`openpbr validate`, `rules` and `info` as a user runs them: exit codes, formats, bad input."""

from __future__ import annotations

import json
import os
import subprocess
import sys

import jsonschema
import pytest
from click.testing import CliRunner

from cli.group import cli
from openpbr_tools.resources import load_json

CLEAN = '<open_pbr_surface name="S" type="surfaceshader" version="1.1.1">\n  <input name="base_color" type="color3" value="0.5, 0.4, 0.3" />\n</open_pbr_surface>'
BROKEN = '<open_pbr_surface name="S" type="surfaceshader" version="1.1.1">\n  <input name="base_weight" type="float" value="1.5" />\n</open_pbr_surface>'
WARNING_ONLY = '<open_pbr_surface name="S" type="surfaceshader" version="1.1.1">\n  <input name="specular_ior" type="float" value="4.5" />\n</open_pbr_surface>'


def run(*args):
    result = CliRunner().invoke(cli, list(map(str, args)))
    assert result.exception is None or isinstance(result.exception, SystemExit), result.output
    return result


def test_clean_file_exits_zero(write_mtlx):
    result = run("validate", write_mtlx(CLEAN))
    assert result.exit_code == 0, result.output


def test_error_exits_one_and_names_the_line(write_mtlx):
    path = write_mtlx(BROKEN)
    result = run("validate", path)
    assert result.exit_code == 1
    line = next(i for i, text in enumerate(path.read_text().splitlines(), 1) if "base_weight" in text)
    assert f"{line}:S.base_weight" in result.output and "OPBR301" in result.output


def test_fail_on_warning_and_never(write_mtlx):
    path = write_mtlx(WARNING_ONLY)
    assert run("validate", path).exit_code == 0
    assert run("validate", "--fail-on", "warning", path).exit_code == 1
    assert run("validate", "--fail-on", "never", write_mtlx(BROKEN, name="b.mtlx")).exit_code == 0


def test_ignore_and_select(write_mtlx):
    path = write_mtlx(BROKEN)
    assert run("validate", "--ignore", "OPBR301", path).exit_code == 0
    result = run("validate", "--select", "OPBR302", "--format", "json", path)
    assert {d["code"] for d in json.loads(result.output)["diagnostics"]} <= {"OPBR302"}
    assert run("validate", "--ignore", "OPBR999", path).exit_code == 2


def test_json_report_matches_its_schema(write_mtlx):
    result = run("validate", "--format", "json", write_mtlx(BROKEN))
    report = json.loads(result.output)
    jsonschema.validate(report, load_json("report.schema.json"))
    diagnostic = next(d for d in report["diagnostics"] if d["code"] == "OPBR301")
    assert diagnostic["severity"] == "error"
    assert diagnostic["location"]["path"] == "S" and diagnostic["location"]["input"] == "base_weight"
    assert report["summary"]["exit_code"] == 1


def test_report_schema_rejects_a_malformed_report():
    with pytest.raises(jsonschema.ValidationError):
        jsonschema.validate({"diagnostics": [{"code": "X"}]}, load_json("report.schema.json"))


@pytest.mark.parametrize(
    "content",
    [b"", os.urandom(256), b'<?xml version="1.0"?>\n<materialx version="1.39">\n  <open_pbr_surface name="S"'],
    ids=["empty", "random-bytes", "truncated"],
)
def test_unreadable_input_exits_two_without_traceback(tmp_path, content):
    path = tmp_path / "bad.mtlx"
    path.write_bytes(content)
    result = run("validate", path)
    assert result.exit_code == 2
    assert "Traceback" not in result.output
    assert "OPBR001" in result.output or "OPBR002" in result.output


def test_missing_path_and_empty_folder_exit_two(tmp_path):
    result = run("validate", tmp_path / "nope.mtlx")
    assert result.exit_code == 2 and "no such file" in result.output
    (tmp_path / "empty").mkdir()
    result = run("validate", tmp_path / "empty")
    assert result.exit_code == 2 and "no .mtlx" in result.output


def test_folder_and_glob_are_searched_recursively(tmp_path, write_mtlx):
    write_mtlx(CLEAN, name="a/one.mtlx")
    write_mtlx(BROKEN, name="a/b/two.mtlx")
    result = run("validate", "--format", "json", tmp_path / "a")
    paths = [f["path"] for f in json.loads(result.output)["files"]]
    assert paths == sorted(paths) and [os.path.basename(p) for p in paths] == ["two.mtlx", "one.mtlx"]
    result = run("validate", "--format", "json", str(tmp_path / "a" / "**" / "*.mtlx"))
    assert len(json.loads(result.output)["files"]) == 2


def test_reports_are_byte_identical_across_runs(write_mtlx):
    path = write_mtlx(BROKEN)
    assert run("validate", "--format", "json", path).output == run("validate", "--format", "json", path).output


def test_rules_lists_every_code_and_documents_one():
    from openpbr_tools.rules import all_rules

    listing = run("rules").output
    for code in all_rules():
        assert code in listing
    page = run("rules", "OPBR301").output
    assert "Passes" in page and "Fails" in page and 'value="1.5"' in page
    assert run("rules", "NOPE").exit_code == 2


def test_info_lists_materials_versions_and_textures(write_mtlx):
    fragment = ('<image name="img" type="color3">\n  <input name="file" type="filename" value="albedo.png" colorspace="srgb_texture" />\n</image>\n'
                '<open_pbr_surface name="S" type="surfaceshader">\n  <input name="base_roughness" type="float" value="0.2" />\n'
                '  <input name="base_color" type="color3" nodename="img" />\n</open_pbr_surface>')
    result = run("info", "--format", "json", write_mtlx(fragment))
    entry = json.loads(result.output)[0]
    material = entry["materials"][0]
    assert material["model"] == "open_pbr_surface" and material["material"] == "M"
    assert material["version"] == "0.3" and "inferred" in material["version_basis"]
    assert material["textures"][0]["file"] == "albedo.png"


def test_console_script_runs_as_a_process(write_mtlx):
    """The installed entry point, in a real process: no traceback, the documented exit code."""
    path = write_mtlx(BROKEN)
    done = subprocess.run([sys.executable, "-m", "cli.main", "validate", str(path)], capture_output=True, text=True)
    assert done.returncode == 1 and "OPBR301" in done.stdout and not done.stderr
