"""`openpbr validate` has two ways in: the click-free fast path (cli.validate_run.fast_validate) and the
click command. Whatever the fast path takes must give the bytes and exit code the click command gives;
whatever it does not take must reach click."""

from __future__ import annotations

import os
import shutil
import subprocess
import sys

import pytest

from cli.validate_run import fast_arguments
from openpbr_tools.resources import data_dir

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
FAST = [sys.executable, "-m", "cli.main"]
CLICK = [sys.executable, "-c", "from cli.group import cli; cli(prog_name='openpbr')"]


def _run(launcher, arguments, cwd):
    environment = {**os.environ, "PYTHONPATH": ROOT}
    return subprocess.run([*launcher, *arguments], capture_output=True, text=True, cwd=cwd, env=environment,
                          check=False)


@pytest.fixture()
def library(tmp_path):
    """The shipped samples (clean and broken) plus an unreadable file and a project configuration."""
    shutil.copytree(data_dir("samples"), tmp_path / "lib")
    (tmp_path / "lib" / "garbage.mtlx").write_text("<materialx version=", encoding="utf-8")
    (tmp_path / ".openpbr.toml").write_text('fail-on = "warning"\nignore = ["OPBR9"]\n', encoding="utf-8")
    return tmp_path


CASES = [
    ["lib/car_paint.mtlx"],
    ["lib/car_paint.mtlx", "--no-config"],
    ["lib/broken/vendor_export.mtlx", "--no-config"],
    ["lib/broken/vendor_export.mtlx"],  # the configuration's fail-on and ignore
    ["lib", "--format", "json", "--no-config"],
    ["lib", "--format=sarif", "--no-config", "--fail-on", "never"],
    ["lib", "--format", "junit", "--min-severity", "error"],
    ["lib", "--format", "jsonl", "--fail-on=info", "--no-progress"],
    ["lib", "--format", "github", "--no-config"],
    ["lib/broken", "lib/tinted_glass.mtlx", "--min-severity=warning", "--no-config", "--no-progress"],
    ["lib/garbage.mtlx", "--no-config"],  # unreadable: exit 2
    ["lib/missing.mtlx", "--no-config"],  # no such file
    ["lib/*.mtlx", "--no-config"],  # a glob
    ["lib", "-o", "report.json", "--format", "json", "--no-config"],
    ["lib", "--output=report.txt"],
    ["lib", "--no-config", "--progress"],
]


@pytest.mark.parametrize("arguments", CASES, ids=[" ".join(c) for c in CASES])
def test_fast_path_gives_what_click_gives(library, arguments):
    assert fast_arguments(arguments) is not None, "this case should take the fast path"
    fast = _run(FAST, ["validate", *arguments], library)
    written_fast = {name: (library / name).read_bytes() for name in ("report.json", "report.txt")
                    if (library / name).exists()}
    for name in written_fast:
        (library / name).unlink()
    slow = _run(CLICK, ["validate", *arguments], library)
    written_slow = {name: (library / name).read_bytes() for name in ("report.json", "report.txt")
                    if (library / name).exists()}
    assert (fast.returncode, fast.stdout, fast.stderr) == (slow.returncode, slow.stdout, slow.stderr)
    assert written_fast == written_slow
    assert "Traceback" not in fast.stderr


def test_fast_path_exit_codes_are_the_documented_ones(library):
    assert _run(FAST, ["validate", "lib/car_paint.mtlx", "--no-config"], library).returncode == 0
    assert _run(FAST, ["validate", "lib/broken/vendor_export.mtlx", "--no-config"], library).returncode == 1
    assert _run(FAST, ["validate", "lib/garbage.mtlx", "--no-config"], library).returncode == 2


def test_fast_path_does_not_import_click(library):
    script = ("import sys\nsys.argv = ['openpbr', 'validate', 'lib/car_paint.mtlx', '--no-config']\n"
              "from cli.main import main\ntry:\n    main()\nexcept SystemExit as done:\n"
              "    print(done.code, 'click' in sys.modules)\n")
    done = _run([sys.executable, "-c", script], [], library)
    assert done.stdout.splitlines()[-1] == "0 False"


@pytest.mark.parametrize("arguments", [
    [],  # click's "missing argument"
    ["-h"], ["--help"], ["lib", "--help"],
    ["lib", "--select", "OPBR1"], ["lib", "--ignore=OPBR9"], ["lib", "--shard", "1/2"], ["lib", "-j", "1"],
    ["lib", "--format", "yaml"], ["lib", "--format"], ["lib", "--format="], ["lib", "--fail-on", "fatal"],
    ["lib", "--min-severity", "never"],  # never is a fail-on value only
    ["lib", "-o", "lib"],  # a folder: click.Path(dir_okay=False) refuses it
    ["lib", "-o=report.txt"], ["lib", "-oreport.txt"], ["lib", "--output", "--no-config"],
    ["lib", "--no-config=yes"], ["-", "lib"], ["--", "lib"], ["lib", "--unknown"],
])
def test_what_the_fast_path_does_not_take_goes_to_click(library, arguments, monkeypatch):
    monkeypatch.chdir(library)
    assert fast_arguments(arguments) is None


@pytest.mark.parametrize("arguments, message", [
    (["--format", "yaml", "lib"], "Invalid value for '--format'"),
    (["lib", "--select", "NOPE1"], "unknown rule code(s): NOPE1"),
    (["lib", "-o", "lib"], "is a directory"),
    ([], "Missing argument 'PATHS...'"),
])
def test_declined_arguments_get_clicks_usage_errors(library, arguments, message):
    done = _run(FAST, ["validate", *arguments], library)
    assert done.returncode == 2 and message in done.stderr and "Traceback" not in done.stderr
