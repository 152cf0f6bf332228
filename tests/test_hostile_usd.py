"""Hostile and broken USD stages: each yields a diagnostic with a code and a location and the right
exit code, quickly, without a traceback, without crashing the process, and without opening any file
outside the asset's folder (the validator deletes such arcs before usd-core composes the stage)."""

from __future__ import annotations

import json
import os
import struct
import subprocess
import sys
import time
import zlib

import pytest
from click.testing import CliRunner

from cli.group import cli
from openpbr_tools.io.usd.text_layer import MAX_TEXT_NESTING

MATERIAL = """def Material "M"
{
    token outputs:mtlx:surface.connect = </M/S.outputs:surface>

    def Shader "S"
    {
        uniform token info:id = "ND_open_pbr_surface_surfaceshader"
        color3f inputs:base_color = (0.5, 0.4, 0.3)
        token outputs:surface
    }
}
"""
HEADER = '#usda 1.0\n(\n    defaultPrim = "M"\n    metersPerUnit = 0.01\n    upAxis = "Y"\n{metadata})\n\n'
GOOD = HEADER.format(metadata="") + MATERIAL
# What an outside layer would contribute if it were composed: a value no test stage authors.
SECRET = ('#usda 1.0\n\ndef Material "Secret"\n{\n    token outputs:mtlx:surface.connect = </Secret/S.outputs:surface>\n'
          '    def Shader "S"\n    {\n        uniform token info:id = "ND_open_pbr_surface_surfaceshader"\n'
          "        float inputs:coat_weight = 0.123\n        token outputs:surface\n    }\n}\n")


def validate(*paths, env=None):
    start = time.perf_counter()
    result = CliRunner().invoke(cli, ["validate", "--format", "json", "--no-config", *map(str, paths)], env=env)
    assert time.perf_counter() - start < 5, "validation took too long"
    assert result.exception is None or isinstance(result.exception, SystemExit), result.output
    assert "Traceback" not in result.output
    return result


def diagnostics(result, code=None) -> list[dict]:
    found = json.loads(result.stdout)["diagnostics"]
    return [d for d in found if code is None or d["code"] == code]


def codes(result) -> list[str]:
    return [d["code"] for d in diagnostics(result)]


def arc_findings(result) -> list[dict]:
    """The arcs left unopened: OPBR1011, or OPBR1039 for a relative '..' to a layer that is there (a shared folder,
    information; usd-wg's ../_common), which is just as unopened."""
    return diagnostics(result, "OPBR1011") + diagnostics(result, "OPBR1039")


@pytest.fixture
def never_parsed(monkeypatch):
    """Records every layer usd-core is asked to open or compose: a refused file must leave it empty."""
    from pxr import Sdf, Usd

    calls = []
    open_layer, open_stage = Sdf.Layer.FindOrOpen, Usd.Stage.Open
    monkeypatch.setattr(Sdf.Layer, "FindOrOpen", staticmethod(lambda *a, **k: calls.append(a) or open_layer(*a, **k)))
    monkeypatch.setattr(Usd.Stage, "Open", staticmethod(lambda *a, **k: calls.append(a) or open_stage(*a, **k)))
    return calls


def crate(text: str, path) -> bytes:
    from pxr import Sdf

    layer = Sdf.Layer.CreateAnonymous(".usda")
    layer.ImportFromString(text)
    layer.Export(str(path))
    return path.read_bytes()


# -- files that are not stages ---------------------------------------------------------------------

@pytest.mark.parametrize("name, content", [
    ("empty.usda", b""),
    ("empty.usdc", b""),
    ("garbage.usda", bytes(range(256)) * 4),
    ("garbage.usdc", b"PXR-USDC" + bytes(range(256)) * 4),
    ("garbage.usdz", b"PK\x03\x04" + bytes(range(256))),
    ("nul.usd", b"\x00" * 64),
    ("bom.usda", b"\xef\xbb\xbf" + GOOD.encode()),
    ("utf16.usda", GOOD.encode("utf-16")),
    ("latin1.usda", GOOD.replace("0.5, 0.4", "0.5, 0.4) # caf\u00e9\n(").encode("latin-1")),
], ids=lambda value: value if isinstance(value, str) else None)
def test_files_that_are_not_stages_exit_two_with_a_diagnostic(tmp_path, name, content):
    path = tmp_path / name
    path.write_bytes(content)
    result = validate(path)
    found = diagnostics(result)
    assert result.exit_code == 2 and found[0]["code"] in ("OPBR001", "OPBR002")
    assert found[0]["location"]["file"] == str(path)


def test_a_truncated_crate_file_exits_two(tmp_path):
    data = crate(GOOD, tmp_path / "whole.usdc")
    (tmp_path / "cut.usdc").write_bytes(data[: len(data) // 2])
    result = validate(tmp_path / "cut.usdc")
    assert result.exit_code == 2 and codes(result) == ["OPBR002"]


def test_a_stage_above_the_size_limit_is_refused_before_usd_core_reads_it(tmp_path, never_parsed):
    path = tmp_path / "huge.usda"
    path.write_text(GOOD + "# padding\n" * 250_000)  # 2.5 MB of a valid stage
    result = validate(path, env={"OPENPBR_MAX_FILE_MB": "1"})
    assert result.exit_code == 2 and "above the 1 MiB limit" in diagnostics(result)[0]["message"]
    assert never_parsed == []


def test_a_crate_file_declaring_huge_tables_is_refused_before_usd_core_reads_it(tmp_path, never_parsed):
    """usd-core sizes its buffers from the counts a crate file declares: a 1 KiB file asking for a
    6 GB token table would make it allocate and touch 6 GB."""
    data = bytearray(crate(GOOD, tmp_path / "good.usdc"))
    (toc,) = struct.unpack_from("<q", data, 16)
    (count,) = struct.unpack_from("<Q", data, toc)
    sections = {struct.unpack_from("<16s", data, toc + 8 + 32 * i)[0].rstrip(b"\0"):
                struct.unpack_from("<qq", data, toc + 24 + 32 * i) for i in range(count)}
    start, _ = sections[b"TOKENS"]
    struct.pack_into("<QQ", data, start, 1 << 29, 6 << 30)  # token count, uncompressed bytes
    (tmp_path / "tokens.usdc").write_bytes(data)
    never_parsed.clear()
    result = validate(tmp_path / "tokens.usdc")
    assert result.exit_code == 2 and "refused before parsing" in diagnostics(result)[0]["message"]
    assert never_parsed == []


def crate_with_bytes(tmp_path, text: str, marker: str, replacement: bytes):
    """A crate file whose ``marker`` text (kept verbatim by usd-core's compression) is replaced."""
    data = crate(text, tmp_path / "clean.usdc")
    assert data.count(marker.encode()) == 1 and len(replacement) == len(marker)
    path = tmp_path / "patched.usdc"
    path.write_bytes(data.replace(marker.encode(), replacement))
    return path


def test_a_crate_string_value_that_is_not_utf8_is_read_without_noise(tmp_path):
    """usd-core swallows the decoding error (the value reads as None) and Python prints it to stderr."""
    path = crate_with_bytes(tmp_path, GOOD.replace("color3f inputs:base_color = (0.5, 0.4, 0.3)",
                                                   'string inputs:base_color = "Kq7Xw2Zp"'), "Kq7Xw2Zp", b"K\xff7Xw\xfeZp")
    result = validate(path)
    assert result.exit_code == 1 and result.stderr == ""


def test_a_crate_arc_whose_path_is_not_utf8_makes_the_stage_unreadable(tmp_path):
    text = HEADER.format(metadata="    subLayers = [@./Kq7Xw2Zp.usda@]\n") + MATERIAL
    result = validate(crate_with_bytes(tmp_path, text, "Kq7Xw2Zp", b"K\xff7Xw\xfeZp"))
    assert result.exit_code == 2 and "not valid UTF-8" in diagnostics(result)[0]["message"]


def test_a_crate_token_that_is_not_utf8_makes_the_stage_unreadable(tmp_path):
    """Tokens (a colour-space name here) raise when Python decodes them."""
    text = GOOD.replace("(0.5, 0.4, 0.3)", '(0.5, 0.4, 0.3) (\n            colorSpace = "Zq7Xw2Kp"\n        )')
    result = validate(crate_with_bytes(tmp_path, text, "Zq7Xw2Kp", b"Z\xff7Xw\xfeKp"))
    assert result.exit_code == 2 and "not valid UTF-8" in diagnostics(result)[0]["message"]
    assert result.stderr == ""


@pytest.mark.parametrize("section", [b"TOKENS", b"STRINGS", b"FIELDS", b"FIELDSETS", b"PATHS", b"SPECS"])
def test_every_structural_section_is_checked_before_usd_core_sizes_its_buffers(tmp_path, section, never_parsed):
    data = bytearray(crate(GOOD, tmp_path / "good.usdc"))
    (toc,) = struct.unpack_from("<q", data, 16)
    (count,) = struct.unpack_from("<Q", data, toc)
    for index in range(count):
        name, start, _ = struct.unpack_from("<16sqq", data, toc + 8 + 32 * index)
        if name.rstrip(b"\0") == section:
            struct.pack_into("<Q", data, start, 1 << 40)  # the section's first count
    (tmp_path / "bad.usdc").write_bytes(data)
    never_parsed.clear()
    result = validate(tmp_path / "bad.usdc")
    assert result.exit_code == 2 and f"section {section.decode()}" in diagnostics(result)[0]["message"]
    assert never_parsed == []


def test_a_huge_array_on_an_input_is_summarised_not_converted(tmp_path):
    """No OpenPBR input is an array; converting millions of floats to Python would take seconds."""
    from openpbr_tools.io import read_asset

    path = tmp_path / "array.usda"
    path.write_text(GOOD.replace("color3f inputs:base_color = (0.5, 0.4, 0.3)",
                                 "float[] inputs:base_color = [" + ", ".join(["0.5"] * 1000) + "]"))
    entry = read_asset(path).materials[0].inputs["base_color"]
    assert entry.constant == "(1000 values)" and entry.source_type == "float[]"
    assert "OPBR201" in codes(validate(path))


# -- nesting ------------------------------------------------------------------------------------

def nested(depth: int, opening: str = 'def "p" {\n', closing: str = "}\n") -> str:
    return "#usda 1.0\n" + opening * depth + closing * depth


def test_brackets_nested_beyond_the_limit_are_refused_before_parsing(tmp_path, never_parsed):
    path = tmp_path / "deep.usda"
    path.write_text(nested(MAX_TEXT_NESTING + 10))
    result = validate(path)
    found = diagnostics(result)[0]
    assert result.exit_code == 2 and "nest deeper than" in found["message"]
    assert found["location"]["line"] == MAX_TEXT_NESTING + 2  # the line where the limit is passed
    assert never_parsed == []


@pytest.mark.parametrize("kind", ["tuples", "dictionaries"])
def test_nesting_in_values_and_metadata_counts_too(tmp_path, kind):
    depth = MAX_TEXT_NESTING + 10
    value = ("custom float3 x = " + "(" * depth + "1" + ")" * depth if kind == "tuples"
             else 'customData = {\n' + "dictionary a = {\n" * depth + "}\n" * (depth + 1))
    text = (f'#usda 1.0\ndef "p"\n{{\n{value}\n}}\n' if kind == "tuples" else f'#usda 1.0\ndef "p" (\n{value})\n{{\n}}\n')
    path = tmp_path / "deep.usda"
    path.write_text(text)
    assert validate(path).exit_code == 2


def test_brackets_in_strings_comments_and_asset_paths_do_not_count(tmp_path):
    noise = "{" * 3 * MAX_TEXT_NESTING
    text = (HEADER.format(metadata=f'    doc = """{noise}"""\n') + f"# {noise}\n/* {noise} */\n"
            + MATERIAL.replace("token outputs:surface\n", f'token outputs:surface\n        string note = "{noise}"\n'
                               f"        asset a = @{noise}.png@\n"))
    path = tmp_path / "noisy.usda"
    path.write_text(text)
    result = validate(path)
    assert result.exit_code != 2, result.stdout


def test_nesting_cannot_hide_behind_closing_brackets_in_a_string(tmp_path):
    """A string full of '}' must not make the deep nesting after it look shallow."""
    text = '#usda 1.0\n(\n    doc = "' + "}" * 5000 + '"\n)\n' + 'def "p" {\n' * (MAX_TEXT_NESTING + 5)
    path = tmp_path / "hidden.usda"
    path.write_text(text)
    result = validate(path)
    assert result.exit_code == 2 and "nest deeper than" in diagnostics(result)[0]["message"]


def test_nesting_that_would_crash_usd_core_exits_two_in_a_real_process(tmp_path):
    """usd-core's text parser overflows the stack (a segmentation fault) somewhere past 30,000 levels."""
    path = tmp_path / "deep.usda"
    path.write_text(nested(100_000))
    done = subprocess.run([sys.executable, "-m", "cli.main", "validate", "--format", "json", "--no-config", str(path)],
                          capture_output=True, text=True, timeout=60, check=False)
    assert done.returncode == 2, done.stderr
    assert json.loads(done.stdout)["diagnostics"][0]["code"] == "OPBR002"


def test_a_material_nested_hundreds_of_prims_deep_is_read(tmp_path):
    """Within the limit, deep prims are read (no recursion in the reader)."""
    depth = MAX_TEXT_NESTING - 20
    prefix = "".join(f"/p{i}" for i in range(depth))
    text = ("#usda 1.0\n" + "".join(f'def "p{i}" {{\n' for i in range(depth))
            + MATERIAL.replace("</M/S", f"<{prefix}/M/S") + "}\n" * depth)
    path = tmp_path / "deep_material.usda"
    path.write_text(text)
    result = validate(path)
    assert result.exit_code != 2 and json.loads(result.stdout)["files"][0]["materials"] == 1


# -- packages -----------------------------------------------------------------------------------

def local_entry(name: str, data: bytes, method: int = 0, declared: int | None = None) -> bytes:
    """A zip local file header and its data, as usd-core reads USDZ packages (it ignores the
    central directory)."""
    stored = data if method == 0 else zlib.compress(data)[2:-4]
    return struct.pack("<IHHHHHIIIHH", 0x04034B50, 20, 0, method, 0, 0, zlib.crc32(data), len(stored),
                       len(data) if declared is None else declared, len(name.encode()), 0) + name.encode() + stored


@pytest.mark.parametrize("entry", ["/etc/x.png", "../x.png", "textures/../../x.png", "C:/x.png", "textures\\x.png"])
def test_package_entries_that_would_escape_an_extraction_folder_are_reported(tmp_path, entry):
    path = tmp_path / "escape.usdz"
    path.write_bytes(local_entry("root.usda", GOOD.encode()) + local_entry(entry, b"\x89PNG"))
    result = validate(path)
    # (usd-core's own ByteMisalignment errors of these hand-built, unaligned packages are OPBR1012 too: set aside)
    found = [d for d in diagnostics(result, "OPBR1012") if not d["message"].startswith("usd-core")]
    assert result.exit_code == 1 and len(found) == 1 and repr(entry) in found[0]["message"]
    assert found[0]["location"]["file"] == str(path)


def test_a_compressed_entry_is_reported(tmp_path):
    path = tmp_path / "deflated.usdz"
    path.write_bytes(local_entry("root.usda", GOOD.encode()) + local_entry("albedo.png", b"\0" * 256, method=8))
    found = [d for d in diagnostics(validate(path), "OPBR1012") if not d["message"].startswith("usd-core")]
    assert len(found) == 1 and "compressed" in found[0]["message"]


def test_a_zip_bomb_is_refused_without_decompressing(tmp_path, never_parsed):
    path = tmp_path / "bomb.usdz"
    path.write_bytes(local_entry("root.usda", GOOD.encode()) + local_entry("huge.png", b"\0" * 4096, method=8,
                                                                          declared=0xFFFFFFF0))
    result = validate(path)
    assert result.exit_code == 2 and "uncompressed, above the" in diagnostics(result)[0]["message"]
    assert never_parsed == []


def test_an_entry_declaring_more_bytes_than_it_stores_is_refused(tmp_path):
    path = tmp_path / "liar.usdz"
    path.write_bytes(local_entry("root.usda", GOOD.encode(), declared=10_000_000))
    result = validate(path)
    assert result.exit_code == 2 and "declares 10000000 bytes" in diagnostics(result)[0]["message"]


def test_nesting_inside_a_package_is_refused_too(tmp_path):
    path = tmp_path / "deep.usdz"
    path.write_bytes(local_entry("root.usda", nested(MAX_TEXT_NESTING + 10).encode()))
    result = validate(path)
    assert result.exit_code == 2 and "nest deeper than" in diagnostics(result)[0]["message"]


def test_a_package_with_too_many_entries_is_refused(tmp_path, monkeypatch):
    from openpbr_tools.io.usd import package as usd_stage

    monkeypatch.setattr(usd_stage, "MAX_PACKAGE_ENTRIES", 3)
    path = tmp_path / "many.usdz"
    path.write_bytes(local_entry("root.usda", GOOD.encode()) + b"".join(local_entry(f"{i}.png", b"") for i in range(5)))
    result = validate(path)
    assert result.exit_code == 2 and "more than 3 entries" in diagnostics(result)[0]["message"]


def test_layers_inside_a_package_are_checked_before_parsing_and_may_not_climb_out(tmp_path):
    deep = tmp_path / "deep.usdz"
    deep.write_bytes(local_entry("root.usda", b'#usda 1.0\n(\n    subLayers = [@sub.usda@]\n)\n')
                     + local_entry("sub.usda", nested(MAX_TEXT_NESTING + 10).encode()))
    assert "nest deeper than" in diagnostics(validate(deep))[0]["message"]
    out = tmp_path / "out.usdz"
    out.write_bytes(local_entry("root.usda", (GOOD + '\ndef "R" (\n    references = @a/../../x.usda@\n)\n{\n}\n').encode()))
    found = diagnostics(validate(out), "OPBR1011")
    assert len(found) == 1 and "climbs out" in found[0]["message"] and found[0]["location"]["path"] == "/R"


# -- composition arcs -----------------------------------------------------------------------------

@pytest.fixture
def outside(tmp_path):
    """tmp_path/asset/ is the asset's folder; tmp_path/outside/secret.usda is a layer outside it,
    also reachable through the symbolic link asset/linked."""
    (tmp_path / "asset").mkdir()
    (tmp_path / "outside").mkdir()
    (tmp_path / "outside" / "secret.usda").write_text(SECRET)
    os.symlink(tmp_path / "outside", tmp_path / "asset" / "linked")
    return tmp_path


TARGETS = {
    "parent": ("../outside/secret.usda", "climbs out of the asset's folder"),
    "absolute": ("{root}/outside/secret.usda", "is an absolute path"),
    "url": ("https://example.com/secret.usda", "is a URL"),
    "symlink": ("./linked/secret.usda", "leads out of the asset's folder"),
    "expression": ("`${{SECRET}}`", "is a variable expression"),
}


def stage_with_arc(folder, arc: str, target: str) -> str:
    metadata = f'    expressionVariables = {{\n        string SECRET = "{folder}/outside/secret.usda"\n    }}\n'
    if arc == "sublayer":
        metadata += f"    subLayers = [@{target}@]\n"
        return HEADER.format(metadata=metadata) + MATERIAL
    keyword = "references" if arc == "reference" else "payload"
    return HEADER.format(metadata=metadata) + MATERIAL + f'\ndef "Ref" (\n    {keyword} = @{target}@</Secret>\n)\n{{\n}}\n'


@pytest.mark.parametrize("arc", ["sublayer", "reference", "payload"])
@pytest.mark.parametrize("target", sorted(TARGETS))
def test_arcs_leaving_the_asset_folder_are_reported_and_not_composed(outside, arc, target):
    asset_path, reason = TARGETS[target]
    asset_path = asset_path.format(root=outside)  # the expression's braces are doubled for format()
    path = outside / "asset" / "stage.usda"
    path.write_text(stage_with_arc(outside, arc, asset_path))
    result = validate(path)
    found = arc_findings(result)
    shared = target == "parent"  # '../outside/secret.usda' is there: OPBR1039, an info (exit 0)
    assert result.exit_code == (0 if shared else 1) and len(found) == 1, result.stdout
    assert found[0]["code"] == ("OPBR1039" if shared else "OPBR1011")
    assert arc in found[0]["message"] and reason in found[0]["message"] and asset_path in found[0]["message"]
    assert found[0]["location"]["file"] == str(path)
    assert found[0]["location"]["path"] == (None if arc == "sublayer" else "/Ref")
    report = json.loads(result.stdout)
    assert report["files"][0]["materials"] == 1  # /M only: the outside layer's material is not there
    assert "coat_weight" not in result.stdout


def test_an_arc_inside_a_variant_is_reported_at_the_variant(outside):
    variant = ('\ndef "V" (\n    variants = {\n        string look = "a"\n    }\n    prepend variantSets = "look"\n)\n{\n'
               '    variantSet "look" = {\n        "a" (\n            references = @../outside/secret.usda@</Secret>\n'
               '        ) {\n        }\n    }\n}\n')
    path = outside / "asset" / "variants.usda"
    path.write_text(GOOD + variant)
    found = arc_findings(validate(path))
    assert len(found) == 1 and found[0]["location"]["path"] == "/V{look=a}"


def test_an_arc_in_an_inside_layer_is_judged_from_that_layer(outside):
    (outside / "asset" / "lib").mkdir()
    (outside / "asset" / "lib" / "looks.usda").write_text('#usda 1.0\n(\n    subLayers = [@../../outside/secret.usda@]\n)\n')
    path = outside / "asset" / "stage.usda"
    path.write_text(HEADER.format(metadata="    subLayers = [@./lib/looks.usda@]\n") + MATERIAL)
    found = arc_findings(validate(path))
    assert len(found) == 1 and found[0]["location"]["file"] == str(outside / "asset" / "lib" / "looks.usda")


def test_arcs_inside_the_asset_folder_are_followed(outside):
    (outside / "asset" / "looks.usda").write_text(SECRET)
    path = outside / "asset" / "stage.usda"
    path.write_text(stage_with_arc(outside, "reference", "./looks.usda"))
    result = validate(path)
    assert "OPBR1011" not in codes(result) and json.loads(result.stdout)["files"][0]["materials"] == 2


def test_folders_allowed_by_the_caller_are_followed(outside):
    from openpbr_tools.io.usd.reader import read_usd

    path = outside / "asset" / "stage.usda"
    path.write_text(stage_with_arc(outside, "reference", "../outside/secret.usda"))
    asset = read_usd(str(path), usd_core=False, allow_outside=[str(outside / "outside")])
    assert len(asset.materials) == 2 and not [o for o in asset.observations if o.kind == "usd_arc_outside"]


@pytest.mark.parametrize("target", ["../outside/secret.usda", "./linked/secret.usda"])
def test_an_outside_layer_is_never_opened(outside, target):
    """The outside layer is a FIFO: opening it would block the process for ever."""
    (outside / "outside" / "secret.usda").unlink()
    os.mkfifo(outside / "outside" / "secret.usda")
    path = outside / "asset" / "stage.usda"
    path.write_text(stage_with_arc(outside, "reference", target))
    done = subprocess.run([sys.executable, "-m", "cli.main", "validate", "--format", "json", "--no-config", str(path)],
                          capture_output=True, text=True, timeout=60, check=False)
    assert done.returncode == 1 and "OPBR1011" in done.stdout, done.stderr


@pytest.mark.parametrize("suffix", [".usda", ".usdc"])
def test_value_clips_are_never_read_and_outside_ones_are_reported(outside, suffix):
    """A clip template naming a million files makes Usd.Stage.Open enumerate them all (seconds to
    minutes); clips hold animation, so the validator drops them before composing. In a crate file
    the token table tells whether any prim may hold clips."""
    clips = ('    clips = {\n        dictionary default = {\n            string templateAssetPath = "../outside/clip.#.usda"\n'
             "            double templateStartTime = 0\n            double templateEndTime = 1000000\n"
             '            double templateStride = 1\n            string primPath = "/S"\n        }\n    }\n')
    text = GOOD.replace('def Shader "S"\n', f'def Shader "S" (\n{clips})\n')
    path = outside / "asset" / f"clips{suffix}"
    if suffix == ".usda":
        path.write_text(text)
    else:
        crate(text, path)
    result = validate(path)
    found = diagnostics(result, "OPBR1011")
    assert len(found) == 1 and "value clip" in found[0]["message"] and found[0]["location"]["path"] == "/M/S"


def test_the_number_of_layers_is_bounded(tmp_path, monkeypatch):
    from openpbr_tools.io.usd import guard as usd_stage

    monkeypatch.setattr(usd_stage, "MAX_LAYERS", 3)
    for index in range(5):
        (tmp_path / f"layer{index}.usda").write_text(f"#usda 1.0\n(\n    subLayers = [@./layer{index + 1}.usda@]\n)\n")
    (tmp_path / "layer5.usda").write_text("#usda 1.0\n")
    result = validate(tmp_path / "layer0.usda")
    assert result.exit_code == 2 and "more than 3 layers" in diagnostics(result)[0]["message"]


def test_a_layer_already_open_in_the_process_is_not_changed(outside):
    from pxr import Sdf

    path = outside / "asset" / "stage.usda"
    path.write_text(stage_with_arc(outside, "sublayer", "../outside/secret.usda"))
    held = Sdf.Layer.FindOrOpen(str(path))
    result = validate(path)
    assert result.exit_code == 2 and "already open" in diagnostics(result)[0]["message"]
    assert list(held.subLayerPaths) == ["../outside/secret.usda"]


def test_the_edited_layer_does_not_outlive_the_read(outside):
    """Arcs are deleted in memory only: the next reader of the file must see it as it is on disk."""
    from pxr import Sdf

    path = outside / "asset" / "stage.usda"
    path.write_text(stage_with_arc(outside, "sublayer", "../outside/secret.usda"))
    assert arc_findings(validate(path))
    assert not Sdf.Layer.Find(str(path))
    assert arc_findings(validate(path))


# -- textures -----------------------------------------------------------------------------------

@pytest.mark.parametrize("file, says", [
    ("{root}/outside/albedo.png", "points outside"),
    ("../outside/gone.png", "points outside"),  # a '..' to nothing (to an image that is there: OPBR723, below)
    ("https://example.com/albedo.png", "points outside"),
    ("linked/albedo.png", "symbolic link"),
])
def test_texture_paths_leaving_the_asset_folder_are_reported(outside, file, says):
    (outside / "outside" / "albedo.png").write_bytes(b"\x89PNG\r\n\x1a\n")
    file = file.format(root=outside)
    path = outside / "asset" / "textured.usda"
    path.write_text(GOOD.replace(
        "color3f inputs:base_color = (0.5, 0.4, 0.3)", "color3f inputs:base_color.connect = </M/img.outputs:out>")
        .replace("        token outputs:surface\n    }\n", "        token outputs:surface\n    }\n\n"
                 f'    def Shader "img"\n    {{\n        uniform token info:id = "ND_image_color3"\n'
                 f'        asset inputs:file = @{file}@\n        color3f outputs:out\n    }}\n', 1))
    found = diagnostics(validate(path), "OPBR704")
    assert len(found) == 1 and says in found[0]["message"]
    assert (found[0]["location"]["path"], found[0]["location"]["input"]) == ("/M/img", "file")


def test_a_texture_path_into_a_shared_folder_is_information(outside):
    """A relative '..' to an image that is there (usd-wg's assets read ../_common): OPBR723, an info, and the image
    is not opened; the folder that holds both, validated, reads it."""
    (outside / "outside" / "albedo.png").write_bytes(b"\x89PNG\r\n\x1a\n")
    path = outside / "asset" / "textured.usda"
    path.write_text(GOOD.replace(
        "color3f inputs:base_color = (0.5, 0.4, 0.3)", "color3f inputs:base_color.connect = </M/img.outputs:out>")
        .replace("        token outputs:surface\n    }\n", "        token outputs:surface\n    }\n\n"
                 '    def Shader "img"\n    {\n        uniform token info:id = "ND_image_color3"\n'
                 '        asset inputs:file = @../outside/albedo.png@\n        color3f outputs:out\n    }\n', 1))
    report = validate(path)
    assert not diagnostics(report, "OPBR704")
    [shared] = diagnostics(report, "OPBR723")
    assert shared["severity"] == "info" and (shared["location"]["path"], shared["location"]["input"]) == ("/M/img", "file")
