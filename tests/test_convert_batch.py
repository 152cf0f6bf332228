"""`openpbr convert PATH... -o OUTDIR --output-format F`: many files in one call, one output per
input mirroring the input tree, one report, refusals before anything is written, resumable, and
the same bytes however it runs (one process, a pool, shards, a Dask cluster)."""

from __future__ import annotations

import hashlib
import json
import os
import shutil
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest
from click.testing import CliRunner

from cli.group import cli
from openpbr_tools.resources import data_dir

DOC = """<?xml version="1.0"?>
<materialx version="1.39" colorspace="lin_rec709">
  <open_pbr_surface name="S{i}" type="surfaceshader" version="1.1.1">
    <input name="base_color" type="color3" value="0.{a}, 0.3, 0.2" />
    <input name="specular_roughness" type="float" value="0.{b}" />
    <input name="coat_weight" type="float" value="0.{a}" />
  </open_pbr_surface>
  <surfacematerial name="M{i}" type="material">
    <input name="surfaceshader" type="surfaceshader" nodename="S{i}" />
  </surfacematerial>
</materialx>
"""


def _library(folder: Path, count: int) -> Path:
    for i in range(count):
        sub = folder / f"group{i % 3}" / ("deep" if i % 2 else "")
        sub.mkdir(parents=True, exist_ok=True)
        (sub / f"m{i:03d}.mtlx").write_text(DOC.format(i=i, a=1 + i % 8, b=1 + i % 9))
    return folder


def _tree(folder: Path) -> dict[str, str]:
    return {p.relative_to(folder).as_posix(): hashlib.sha256(p.read_bytes()).hexdigest()
            for p in sorted(folder.rglob("*")) if p.is_file() and not p.name.startswith(".openpbr-")}


def run(*args):
    return CliRunner().invoke(cli, [str(a) for a in args])


def test_outputs_mirror_the_input_tree(tmp_path):
    source = _library(tmp_path / "in", 6)
    result = run("convert", source, "-o", tmp_path / "out", "--output-format", "usda", "--jobs", "1", "--format", "json")
    assert result.exit_code == 0, result.output
    expected = {p.relative_to(source).with_suffix(".usda").as_posix() for p in source.rglob("*.mtlx")}
    assert set(_tree(tmp_path / "out")) == expected
    report = json.loads(result.stdout)
    assert [os.path.relpath(f["path"], source) for f in report["files"]] == sorted(
        os.path.relpath(p, source) for p in map(str, source.rglob("*.mtlx")))


def test_a_folder_a_file_and_a_glob_each_mirror_from_their_own_root(tmp_path):
    source = _library(tmp_path / "in", 6)
    result = run("convert", source / "group0", source / "group1" / "deep" / "m001.mtlx",
                 str(source / "group2") + "/**/*.mtlx", "-o", tmp_path / "out", "--output-format", "gltf", "--jobs", "1")
    assert result.exit_code == 0, result.output
    # group0/ -> its tree; group1/deep/m001.mtlx -> beside its folder's root; group2/**/*.mtlx -> below group2
    assert {"m000.gltf", "deep/m003.gltf", "m001.gltf", "m002.gltf", "deep/m005.gltf"} == {
        f for f in _tree(tmp_path / "out") if f.endswith(".gltf")}


def test_two_inputs_for_one_output_are_refused_before_anything_is_written(tmp_path):
    source = _library(tmp_path / "in", 2)
    gltf = json.dumps({"asset": {"version": "2.0"}, "materials": [{"name": "G"}]})
    (source / "group0" / "m000.gltf").write_text(gltf)  # m000.mtlx and m000.gltf both -> m000.glb
    result = run("convert", source, "-o", tmp_path / "out", "--output-format", "glb", "--jobs", "1")
    assert result.exit_code == 2 and "would both be written to" in result.output
    assert not (tmp_path / "out").exists() or _tree(tmp_path / "out") == {}


def test_existing_outputs_need_force_or_skip_existing(tmp_path):
    source = _library(tmp_path / "in", 3)
    out = tmp_path / "out"
    assert run("convert", source, "-o", out, "--output-format", "gltf", "--jobs", "1").exit_code == 0
    first = _tree(out)
    refused = run("convert", source, "-o", out, "--output-format", "gltf", "--jobs", "1")
    assert refused.exit_code == 2 and "--force" in refused.output
    assert run("convert", source, "-o", out, "--output-format", "gltf", "--jobs", "1", "--force").exit_code == 0
    assert _tree(out) == first  # deterministic


def test_parallel_runs_and_shards_write_the_same_bytes(tmp_path):
    source = _library(tmp_path / "in", 12)
    assert run("convert", source, "-o", tmp_path / "one", "--output-format", "gltf", "--jobs", "1").exit_code == 0
    assert run("convert", source, "-o", tmp_path / "two", "--output-format", "gltf", "--jobs", "2").exit_code == 0
    for index in (1, 2, 3):
        assert run("convert", source, "-o", tmp_path / "sharded", "--output-format", "gltf", "--jobs", "1",
                   "--shard", f"{index}/3").exit_code == 0
    assert _tree(tmp_path / "one") == _tree(tmp_path / "two") == _tree(tmp_path / "sharded")


def test_a_killed_run_resumes_with_skip_existing(tmp_path):
    source = _library(tmp_path / "in", 60)
    clean, resumed = tmp_path / "clean", tmp_path / "resumed"
    command = [sys.executable, "-m", "cli.main", "convert", str(source), "-o", str(resumed), "--output-format", "gltf",
               "--jobs", "1", "--no-progress"]
    process = subprocess.Popen(command, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
                               cwd=Path(__file__).resolve().parents[1])
    deadline = time.time() + 60
    while time.time() < deadline and (not resumed.exists() or len(list(resumed.rglob("*.gltf"))) < 15):
        time.sleep(0.05)
    process.send_signal(signal.SIGKILL)
    process.wait()
    done_before = {p: p.stat().st_mtime_ns for p in resumed.rglob("*.gltf")}
    assert 15 <= len(done_before) < 60, "the run was not interrupted half-way"
    time.sleep(0.01)
    result = run("convert", source, "-o", resumed, "--output-format", "gltf", "--jobs", "1", "--skip-existing")
    assert result.exit_code == 0, result.output
    assert all(p.stat().st_mtime_ns == stamp for p, stamp in done_before.items())  # not rewritten
    assert run("convert", source, "-o", clean, "--output-format", "gltf", "--jobs", "1").exit_code == 0
    assert _tree(resumed) == _tree(clean)


def test_every_report_format_renders_the_combined_report(tmp_path):
    source = _library(tmp_path / "in", 2)
    shutil.copy(data_dir("samples") / "broken" / "vendor_export.mtlx", source / "vendor_export.mtlx")
    for index, name in enumerate(("text", "json", "jsonl", "sarif", "junit", "github")):
        result = run("convert", source, "-o", tmp_path / f"out{index}", "--output-format", "usda", "--jobs", "1",
                     "--format", name)
        assert result.exit_code == 0 and "vendor_export" in result.stdout, (name, result.output)


def test_an_unreadable_input_is_reported_and_the_others_are_converted(tmp_path):
    source = _library(tmp_path / "in", 2)
    (source / "broken.mtlx").write_text("<materialx")
    result = run("convert", source, "-o", tmp_path / "out", "--output-format", "gltf", "--jobs", "1")
    assert result.exit_code == 2 and "Traceback" not in result.output
    assert len(list((tmp_path / "out").rglob("*.gltf"))) == 2


def test_a_dask_cluster_writes_the_same_bytes_and_report(tmp_path):
    distributed = pytest.importorskip("distributed", reason="the dask extra is not installed")
    source = _library(tmp_path / "in", 6)
    local = run("convert", source, "-o", tmp_path / "local", "--output-format", "gltf", "--jobs", "1", "--format", "json")
    with distributed.LocalCluster(n_workers=1, threads_per_worker=1, processes=True, dashboard_address=None) as cluster:
        remote = run("convert", source, "-o", tmp_path / "remote", "--output-format", "gltf", "--format", "json",
                     "--scheduler", cluster.scheduler_address)
    assert remote.exit_code == 0, remote.output
    assert _tree(tmp_path / "local") == _tree(tmp_path / "remote")
    assert remote.stdout == local.stdout


def test_the_single_file_form_is_unchanged(tmp_path):
    sample = data_dir("samples") / "car_paint.mtlx"
    result = run("convert", sample, "-o", tmp_path / "one.gltf")
    assert result.exit_code == 0 and (tmp_path / "one.gltf").is_file()
    assert run("convert", sample, sample, "-o", tmp_path / "x").exit_code == 2  # several inputs need --output-format


def test_an_output_folder_inside_the_input_folder_is_not_read_as_input(tmp_path):
    source = _library(tmp_path / "in", 3)
    out = source / "converted"
    for _ in range(2):
        result = run("convert", source, "-o", out, "--output-format", "mtlx", "--jobs", "1", "--force")
        assert result.exit_code == 0, result.output
    assert len(list(out.rglob("*.mtlx"))) == 3 and not (out / "converted").exists()


def test_line_formats_stream_the_same_report_the_library_renders(tmp_path):
    """text, jsonl and github are written file by file as the batch runs (memory stays flat over a large
    library): the bytes equal the combined report rendered at the end."""
    from openpbr_tools import batch
    from openpbr_tools.reports import render
    from openpbr_tools.validate import Options

    source = _library(tmp_path / "in", 6)
    shutil.copy(data_dir("samples") / "broken" / "vendor_export.mtlx", source / "vendor_export.mtlx")
    for index, name in enumerate(("text", "jsonl", "github")):
        streamed = run("convert", source, "-o", tmp_path / f"out{index}", "--output-format", "gltf", "--jobs", "1",
                       "--format", name)
        plan = batch.plan([str(source)], str(tmp_path / f"again{index}"), "gltf", options=Options(jobs=1))
        report = batch.run(plan, Options(jobs=1))
        combined = render(report, name, None)
        assert streamed.exit_code == report.exit_code(None) == 2  # vendor_export's texture is outside: refused
        assert streamed.stdout.replace(str(tmp_path / f"out{index}"), "OUT") == \
            combined.replace(str(tmp_path / f"again{index}"), "OUT")
        assert streamed.stdout.count("\n") > 6
    assert "7 file(s)" in streamed_text(tmp_path, source)


def streamed_text(tmp_path, source):
    return run("convert", source, "-o", tmp_path / "text", "--output-format", "gltf", "--jobs", "1").stdout


def test_a_streamed_report_is_the_rendered_report_in_every_streamed_format(tmp_path):
    """StreamedReport over a report with an argument problem, clean files and files with findings in
    several severities: begin + add... + end is what render makes of the whole."""
    from openpbr_tools.reports import STREAMED, StreamedReport, render
    from openpbr_tools.validate import Options, validate_paths

    source = _library(tmp_path / "in", 3)
    shutil.copy(data_dir("samples") / "broken" / "vendor_export.mtlx", source / "vendor_export.mtlx")
    shutil.copy(data_dir("samples") / "broken" / "legacy_openpbr_0_2.mtlx", source / "legacy.mtlx")
    report = validate_paths([str(source), str(tmp_path / "missing.mtlx")], options=Options(jobs=1, use_config=False))
    assert report.problems and len(report.files) == 5 and {d.severity for d in report.diagnostics} >= {1, 2, 3}
    assert STREAMED == ("text", "jsonl", "github")
    for name in STREAMED:
        stream = StreamedReport(name, None)
        parts = stream.begin(report.problems) + "".join(stream.add(r) for r in report.files) + stream.end()
        assert parts == render(report, name, None), name
