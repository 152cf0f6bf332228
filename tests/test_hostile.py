"""Hostile and broken inputs: each yields a diagnostic and the right exit code, quickly, and never
makes the validator open another file or hang."""

from __future__ import annotations

import json
import os
import time

import pytest
from click.testing import CliRunner

from cli.group import cli

BOMB = b"""<?xml version="1.0"?>
<!DOCTYPE lolz [
 <!ENTITY lol "lol">
 <!ENTITY lol2 "&lol;&lol;&lol;&lol;&lol;&lol;&lol;&lol;&lol;&lol;">
 <!ENTITY lol3 "&lol2;&lol2;&lol2;&lol2;&lol2;&lol2;&lol2;&lol2;&lol2;&lol2;">
 <!ENTITY lol4 "&lol3;&lol3;&lol3;&lol3;&lol3;&lol3;&lol3;&lol3;&lol3;&lol3;">
 <!ENTITY lol5 "&lol4;&lol4;&lol4;&lol4;&lol4;&lol4;&lol4;&lol4;&lol4;&lol4;">
 <!ENTITY lol6 "&lol5;&lol5;&lol5;&lol5;&lol5;&lol5;&lol5;&lol5;&lol5;&lol5;">
 <!ENTITY lol7 "&lol6;&lol6;&lol6;&lol6;&lol6;&lol6;&lol6;&lol6;&lol6;&lol6;">
 <!ENTITY lol8 "&lol7;&lol7;&lol7;&lol7;&lol7;&lol7;&lol7;&lol7;&lol7;&lol7;">
 <!ENTITY lol9 "&lol8;&lol8;&lol8;&lol8;&lol8;&lol8;&lol8;&lol8;&lol8;&lol8;">
]>
<materialx version="1.39"><open_pbr_surface name="S" type="surfaceshader" doc="&lol9;" /></materialx>
"""

EXTERNAL_ENTITY = b"""<?xml version="1.0"?>
<!DOCTYPE m [<!ENTITY secret SYSTEM "file:///etc/passwd">]>
<materialx version="1.39"><open_pbr_surface name="S" type="surfaceshader" doc="&secret;" /></materialx>
"""


def validate(*paths, env=None):
    result = CliRunner().invoke(cli, ["validate", "--format", "json", "--no-config", *map(str, paths)], env=env)
    assert result.exception is None or isinstance(result.exception, SystemExit), result.output
    assert "Traceback" not in result.output
    return result


def codes(result) -> list[str]:
    return [d["code"] for d in json.loads(result.stdout)["diagnostics"]]


@pytest.mark.parametrize("content", [BOMB, EXTERNAL_ENTITY], ids=["billion-laughs", "external-entity"])
def test_doctype_with_entities_is_refused_quickly(tmp_path, content):
    path = tmp_path / "bomb.mtlx"
    path.write_bytes(content)
    start = time.perf_counter()
    result = validate(path)
    assert time.perf_counter() - start < 5
    assert result.exit_code == 2 and "DOCTYPE" in result.stdout and "root:" not in result.stdout


def test_deep_nesting_is_refused_without_recursion(tmp_path):
    depth = 100_000
    path = tmp_path / "deep.mtlx"
    path.write_bytes(b'<?xml version="1.0"?><materialx version="1.39">' + b"<nodegraph name='g'>" * depth
                     + b"</nodegraph>" * depth + b"</materialx>")
    result = validate(path)
    assert result.exit_code == 2 and "nested deeper" in result.stdout


def test_a_fifo_is_not_opened(tmp_path):
    path = tmp_path / "pipe.mtlx"
    os.mkfifo(path)
    result = validate(path)
    assert result.exit_code == 2 and "not a regular file" in result.stdout


def test_files_above_the_size_limit_are_refused_before_parsing(tmp_path):
    path = tmp_path / "huge.mtlx"
    path.write_bytes(b'<?xml version="1.0"?><materialx version="1.39">' + b" " * (2 * 1024 * 1024) + b"</materialx>")
    result = validate(path, env={"OPENPBR_MAX_FILE_MB": "1"})
    assert result.exit_code == 2 and "above the 1 MiB limit" in result.stdout


def test_symlink_loop_in_a_folder_terminates(tmp_path, write_mtlx):
    write_mtlx('<open_pbr_surface name="S" type="surfaceshader" version="1.1.1" />', name="assets/a.mtlx")
    os.symlink(tmp_path / "assets", tmp_path / "assets" / "loop")
    result = validate(tmp_path / "assets")
    assert result.exit_code in (0, 1) and len(json.loads(result.stdout)["files"]) >= 1


def test_xinclude_is_reported_and_never_followed(tmp_path):
    path = tmp_path / "inc.mtlx"
    path.write_text('<?xml version="1.0"?>\n<materialx version="1.39" colorspace="lin_rec709">\n'
                    '  <xi:include href="/etc/passwd" />\n'
                    '  <open_pbr_surface name="S" type="surfaceshader" version="1.1.1" />\n</materialx>\n')
    result = validate(path)
    assert "OPBR009" in codes(result) and "root:" not in result.stdout


@pytest.mark.parametrize("content", [b"", b"\x00" * 64, b"<?xml", "<materialx>\u2603".encode("utf-16")],
                         ids=["empty", "nul", "prolog-only", "utf16"])
def test_degenerate_files_exit_two(tmp_path, content):
    path = tmp_path / "x.mtlx"
    path.write_bytes(content)
    assert validate(path).exit_code == 2


def test_a_texture_escaping_through_a_symlink_is_reported(tmp_path):
    outside = tmp_path / "elsewhere"
    outside.mkdir()
    (outside / "albedo.png").write_bytes(b"\x89PNG\r\n\x1a\n")
    asset = tmp_path / "asset"
    asset.mkdir()
    (asset / "linked").symlink_to(outside, target_is_directory=True)
    (asset / "m.mtlx").write_text(
        '<?xml version="1.0"?>\n<materialx version="1.39" colorspace="lin_rec709">\n'
        '  <image name="c" type="color3"><input name="file" type="filename" value="linked/albedo.png" colorspace="srgb_texture"/></image>\n'
        '  <open_pbr_surface name="S" type="surfaceshader"><input name="base_color" type="color3" nodename="c"/></open_pbr_surface>\n'
        '</materialx>\n')
    found = json.loads(validate(asset / "m.mtlx").stdout)["diagnostics"]
    escapes = [d for d in found if d["code"] == "OPBR704"]
    assert escapes and "symbolic link" in escapes[0]["message"]
    (asset / "linked").unlink()
    (asset / "linked").mkdir()
    (asset / "linked" / "albedo.png").write_bytes(b"\x89PNG\r\n\x1a\n")
    assert "OPBR704" not in codes(validate(asset / "m.mtlx"))


def test_an_unreadable_file_is_a_diagnostic_with_exit_two(tmp_path, monkeypatch):
    import openpbr_tools.io as io_module

    path = tmp_path / "locked.mtlx"
    path.write_text('<?xml version="1.0"?><materialx version="1.39"/>')

    def refuse(*args, **kwargs):
        raise PermissionError(13, "Permission denied")

    monkeypatch.setattr(io_module, "open", refuse, raising=False)  # as root, chmod 000 would not stop a read
    result = validate(path)
    assert result.exit_code == 2
    found = json.loads(result.stdout)["diagnostics"]
    assert found and "Permission denied" in found[0]["message"] and found[0]["location"]["file"].endswith("locked.mtlx")
