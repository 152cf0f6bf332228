"""A defect of the toolkit on one file (an exception in a reader or a family of checks) is OPBR011 at that
file: the folder's other files are still checked, the file's other families still run, the reports are
written, and the exit code is 2 (the file was not fully checked), never a traceback or a lost report."""

from __future__ import annotations

import json

import pytest
from click.testing import CliRunner

from cli.group import cli
from openpbr_tools import io as readers
from openpbr_tools.rules import plausibility
from openpbr_tools.validate import Options, validate_paths

DOCUMENT = """<?xml version="1.0"?>
<materialx version="1.39" colorspace="lin_rec709">
  <open_pbr_surface name="S" type="surfaceshader">
    <input name="base_metalness" type="float" value="1.5" />
  </open_pbr_surface>
  <surfacematerial name="M" type="material"><input name="surfaceshader" type="surfaceshader" nodename="S" /></surfacematerial>
</materialx>
"""


pytestmark = pytest.mark.internal_errors_reported  # everywhere else the net re-raises (tests/conftest.py)


def _folder(tmp_path):
    for name in ("a.mtlx", "b.mtlx"):
        (tmp_path / name).write_text(DOCUMENT, encoding="utf-8")
    return tmp_path


def _codes(report, name):
    [result] = [r for r in report.files if r.path.endswith(name)]
    return sorted(d.code for d in result.diagnostics)


def test_a_family_that_fails_on_one_file_is_reported_there_and_everything_else_runs(tmp_path, monkeypatch):
    original = plausibility.check

    def failing(asset, context):
        if asset.path.endswith("b.mtlx"):
            raise RuntimeError("synthetic defect")
        yield from original(asset, context)

    monkeypatch.setattr(plausibility, "check", failing)
    report = validate_paths([str(_folder(tmp_path))], options=Options(use_config=False, jobs=1))
    assert "OPBR011" not in _codes(report, "a.mtlx") and "OPBR301" in _codes(report, "a.mtlx")
    codes = _codes(report, "b.mtlx")
    assert "OPBR011" in codes and "OPBR301" in codes  # the ranges family still ran on the failing file
    [internal] = [d for d in report.diagnostics if d.code == "OPBR011"]
    assert internal.location.file.endswith("b.mtlx") and "plausibility" in internal.message
    assert "RuntimeError: synthetic defect" in internal.message
    assert report.exit_code() == 2


def test_a_reader_that_fails_on_one_file_is_reported_there(tmp_path, monkeypatch):
    original = readers.read_asset

    def failing(path, *args, **kwargs):
        if str(path).endswith("b.mtlx"):
            raise KeyError("synthetic")
        return original(path, *args, **kwargs)

    monkeypatch.setattr(readers, "read_asset", failing)
    report = validate_paths([str(_folder(tmp_path))], options=Options(use_config=False, jobs=1))
    assert _codes(report, "b.mtlx") == ["OPBR011"] and "OPBR301" in _codes(report, "a.mtlx")
    [internal] = [d for d in report.diagnostics if d.code == "OPBR011"]
    assert internal.message.startswith("reading failed on this file (KeyError")
    assert report.exit_code() == 2


def test_the_cli_writes_every_report_format_with_the_internal_error_in_it(tmp_path, monkeypatch):
    def failing(asset, context):
        raise ValueError("synthetic defect")
        yield  # (a generator, as the families are)

    monkeypatch.setattr(plausibility, "check", failing)
    (tmp_path / "in").mkdir()
    folder = _folder(tmp_path / "in")
    for fmt in ("json", "sarif", "junit", "github", "text"):
        result = CliRunner().invoke(cli, ["validate", "--no-config", "--jobs", "1", "--format", fmt, str(folder)])
        assert result.exit_code == 2 and (result.exception is None or isinstance(result.exception, SystemExit)), result.output
        assert "OPBR011" in result.output, fmt
        if fmt == "json":
            document = json.loads(result.output)
            assert {d["code"] for d in document["diagnostics"]} >= {"OPBR011", "OPBR301"}


def test_a_batch_conversion_reports_a_defect_on_one_file_and_converts_the_others(tmp_path, monkeypatch):
    from openpbr_tools import convert as convert_module

    original = convert_module.convert_file

    def failing(source, *args, **kwargs):
        if str(source).endswith("b.mtlx"):
            raise IndexError("synthetic defect")
        return original(source, *args, **kwargs)

    monkeypatch.setattr(convert_module, "convert_file", failing)
    (tmp_path / "in").mkdir()
    folder = _folder(tmp_path / "in")
    result = CliRunner().invoke(cli, ["convert", "--jobs", "1", "--format", "json", str(folder / "a.mtlx"),
                                      str(folder / "b.mtlx"), "-o", str(tmp_path / "out"), "--output-format", "gltf"])
    assert result.exit_code == 2, result.output
    assert (tmp_path / "out" / "a.gltf").is_file() and not (tmp_path / "out" / "b.gltf").exists()
    [internal] = [d for d in json.loads(result.stdout)["diagnostics"] if d["code"] == "OPBR011"]
    assert internal["location"]["file"].endswith("b.mtlx") and "IndexError: synthetic defect" in internal["message"]


@pytest.mark.parametrize("step", ["converting", "verifying"])
def test_a_single_file_conversion_reports_a_defect_as_opbr011_not_a_traceback(tmp_path, monkeypatch, step):
    """One input and one output (not the batch path): a defect while converting, or while verifying the written
    output, is OPBR011 naming the step, in the report, with exit 2; it printed a Python traceback before."""
    from openpbr_tools import convert as convert_module
    from openpbr_tools import verification

    def failing(*args, **kwargs):
        raise IndexError("synthetic defect")

    monkeypatch.setattr(convert_module if step == "converting" else verification,
                        "convert_file" if step == "converting" else "compare", failing)
    folder = _folder(tmp_path)
    result = CliRunner().invoke(cli, ["convert", "--format", "json", "--verify", str(folder / "a.mtlx"),
                                      "-o", str(tmp_path / "a.gltf")])
    assert result.exit_code == 2, result.output
    [internal] = [d for d in json.loads(result.stdout)["diagnostics"] if d["code"] == "OPBR011"]
    assert internal["message"].startswith(f"{step} failed") and "IndexError: synthetic defect" in internal["message"]
    assert internal["location"]["file"].endswith("a.mtlx")
