"""Hostile references through the USD callers of the one path guard (openpbr_tools.io.paths).

Every sublayer, reference and payload arc, and every UsdUVTexture ``inputs:file``, is set to a
reference that must not be followed out of the asset's folder: ``..``, an absolute path, a symbolic
link leading out, a symbolic link loop, a Windows drive, a UNC share, ``file:``, ``http:`` and
``data:`` URLs and a 5,000-character path. The reader reports each (OPBR1011 for arcs; the texture
rules for textures) or refuses the file as unreadable, the ``.usdz`` writer refuses to package an
outside texture and never copies a URL; nothing outside is opened and nothing raises a traceback.
"""

from __future__ import annotations

import json
import os
import zipfile

import pytest
from click.testing import CliRunner

from cli.group import cli

HEADER = '#usda 1.0\n(\n    defaultPrim = "M"\n    metersPerUnit = 0.01\n    upAxis = "Y"\n{metadata})\n\n'
MATERIAL = """def Material "M"
{{
    token outputs:surface.connect = </M/P.outputs:surface>

    def Shader "P"
    {{
        uniform token info:id = "UsdPreviewSurface"
        color3f inputs:diffuseColor.connect = </M/T.outputs:rgb>
        token outputs:surface
    }}

    def Shader "T"
    {{
        uniform token info:id = "UsdUVTexture"
        asset inputs:file = @{file}@
        float3 outputs:rgb
    }}
}}
"""
# What an outside layer would contribute if it were composed: a value no test stage authors.
SECRET = ('#usda 1.0\n\ndef Material "Secret"\n{\n    token outputs:mtlx:surface.connect = </Secret/S.outputs:surface>\n'
          '    def Shader "S"\n    {\n        uniform token info:id = "ND_open_pbr_surface_surfaceshader"\n'
          "        float inputs:coat_weight = 0.123\n        token outputs:surface\n    }\n}\n")
LONG_OUTSIDE = "../" + "a/" * 2498 + "x"  # 5,000 characters with the suffix, climbing out
LONG_INSIDE = "b" * 4995  # 5,000 characters with the suffix, a name no file system accepts

# name -> (reference without suffix, or with {root}; is it a URL)
REFERENCES = {
    "climbs": ("../outside/secret", False),
    "absolute": ("{root}/outside/secret", False),
    "symlink": ("./link", False),
    "symlink_loop": ("./loop_a", False),
    "drive": ("C:\\x", False),
    "unc": ("\\\\server\\share\\x", False),
    "file_url": ("file:///etc/passwd", True),
    "http_url": ("http://example.com/x", True),
    "data_url": ("data:text/plain;base64,AAAA", True),
    "long_outside": (LONG_OUTSIDE, False),
    "long_inside": (LONG_INSIDE, False),
}


@pytest.fixture
def root(tmp_path):
    """tmp/asset (the asset's folder) and tmp/outside (files an asset must not reach)."""
    (tmp_path / "asset").mkdir()
    (tmp_path / "outside").mkdir()
    (tmp_path / "asset" / "inside.png").write_bytes(b"\x89PNG\r\n\x1a\n")
    for suffix, data in ((".usda", SECRET.encode()), (".png", b"\x89PNG\r\n\x1a\nsecret")):
        (tmp_path / "outside" / f"secret{suffix}").write_bytes(data)
        os.symlink(tmp_path / "outside" / f"secret{suffix}", tmp_path / "asset" / f"link{suffix}")
        os.symlink(tmp_path / "asset" / f"loop_b{suffix}", tmp_path / "asset" / f"loop_a{suffix}")
        os.symlink(tmp_path / "asset" / f"loop_a{suffix}", tmp_path / "asset" / f"loop_b{suffix}")
    return tmp_path


def reference(root, name: str, suffix: str) -> str:
    text, url = REFERENCES[name]
    return text if url else text.format(root=root) + suffix


def stage_with_arc(root, arc: str, target: str):
    if arc == "sublayer":
        text = HEADER.format(metadata=f"    subLayers = [@{target}@]\n") + MATERIAL.format(file="inside.png")
    else:
        keyword = "references" if arc == "reference" else "payload"
        text = (HEADER.format(metadata="") + MATERIAL.format(file="inside.png")
                + f'\ndef "Ref" (\n    {keyword} = @{target}@</Secret>\n)\n{{\n}}\n')
    path = root / "asset" / f"{arc}.usda"
    path.write_text(text)
    return path


def stage_with_texture(root, target: str):
    path = root / "asset" / "textured.usda"
    path.write_text(HEADER.format(metadata="") + MATERIAL.format(file=target))
    return path


def run(*arguments):
    result = CliRunner().invoke(cli, [str(a) for a in arguments])
    assert result.exception is None or isinstance(result.exception, SystemExit), result.output
    assert "Traceback" not in result.output
    return result


@pytest.fixture
def opened(monkeypatch):
    """Every layer usd-core is asked to open: an outside one must never be among them."""
    from pxr import Sdf

    calls: list[str] = []
    find_or_open = Sdf.Layer.FindOrOpen
    monkeypatch.setattr(Sdf.Layer, "FindOrOpen", staticmethod(lambda *a, **k: calls.append(str(a[0])) or find_or_open(*a, **k)))
    return calls


def diagnostics_of(found: list[dict], code: str) -> list[dict]:
    return [d for d in found if d["code"] == code]


@pytest.mark.parametrize("arc", ["sublayer", "reference", "payload"])
@pytest.mark.parametrize("name", sorted(REFERENCES))
def test_hostile_arcs_are_reported_and_never_opened(root, opened, arc, name):
    target = reference(root, name, ".usda")
    path = stage_with_arc(root, arc, target)
    result = run("validate", "--format", "json", "--no-config", path)
    assert "coat_weight" not in result.stdout and "Secret" not in result.stdout.replace(target, "")
    assert not [c for c in opened if "outside" in c or c.startswith(("file:", "http:", "data:", "C:", "\\\\"))]
    found = [d for d in json.loads(result.stdout)["diagnostics"]]
    if name == "long_inside":
        # no such file: usd-core composes the stage without it, a missing layer (OPBR1042; it used to be exit 2)
        assert result.exit_code == 1 and "OPBR1042" in {d["code"] for d in found} and not diagnostics_of(
            found, "OPBR002"), result.stdout
        return
    if name == "climbs":  # a relative '..' to a layer that is there: a shared folder (OPBR1039, an info), not opened
        arcs = [d for d in found if d["code"] == "OPBR1039"]
        assert len(arcs) == 1 and arcs[0]["severity"] == "info" and not diagnostics_of(found, "OPBR1011"), result.stdout
    else:
        arcs = [d for d in found if d["code"] == "OPBR1011"]
        assert result.exit_code == 1 and len(arcs) == 1, result.stdout
    assert arc in arcs[0]["message"] and target in arcs[0]["message"]


@pytest.mark.parametrize("name", sorted(REFERENCES))
def test_hostile_arcs_through_read_asset(root, name):
    from openpbr_tools.io import read_asset

    target = reference(root, name, ".usda")
    path = stage_with_arc(root, "reference", target)
    asset = read_asset(str(path))
    if name == "long_inside":  # no such file: a missing layer, the rest composed
        assert [o.kind for o in asset.observations if o.kind == "usd_layer_missing"] == ["usd_layer_missing"]
        return
    refused = [o for o in asset.observations if o.kind == "usd_arc_outside"]
    assert [o.detail["asset"] for o in refused] == [target]
    assert [m.name for m in asset.materials] == ["/M/P"]  # the outside layer's material is not there


@pytest.mark.parametrize("name", sorted(REFERENCES))
def test_hostile_texture_paths_are_reported_by_the_reader(root, name):
    from openpbr_tools.validate import validate_paths

    target = reference(root, name, ".png")
    path = stage_with_texture(root, target)
    result = run("validate", "--format", "json", "--no-config", path)
    # (a relative '..' to an image that is there is OPBR723, a shared folder: information, the image never opened)
    texture = [d for d in json.loads(result.stdout)["diagnostics"] if d["code"] in ("OPBR701", "OPBR704", "OPBR723")]
    assert texture and all(repr(target)[1:61] in d["message"] for d in texture), result.stdout  # quoted with !r
    report = validate_paths([str(path)])
    assert {d.code for d in report.diagnostics} >= {d["code"] for d in texture}


@pytest.mark.parametrize("name", sorted(REFERENCES))
def test_hostile_texture_paths_are_never_packaged_into_a_usdz(root, name, monkeypatch):
    import shutil

    copied: list[str] = []
    copy = shutil.copyfile
    monkeypatch.setattr(shutil, "copyfile", lambda source, *a, **k: copied.append(str(source)) or copy(source, *a, **k))
    target = reference(root, name, ".png")
    path = stage_with_texture(root, target)
    output = root / "out" / "packaged.usdz"
    output.parent.mkdir()
    result = run("convert", path, "-o", output)
    assert not [c for c in copied if "outside" in c or "secret" in c]
    if name in ("climbs", "absolute", "symlink", "symlink_loop", "drive", "unc", "long_outside", "file_url"):
        # (a file URL names a file outside as an absolute path does: session 21's red team, M-10)
        assert result.exit_code == 2 and "outside the source asset's folder" in result.output, result.output
        assert not output.exists() and os.listdir(output.parent) == []
        return
    assert result.exit_code in (0, 1), result.output
    with zipfile.ZipFile(output) as package:
        assert package.namelist() == ["root.usdc"]  # a URL or a missing file is referenced, not packaged
    if not REFERENCES[name][1]:
        assert "does not exist and is not packaged" in result.output


@pytest.mark.parametrize("name", sorted(REFERENCES))
def test_hostile_texture_paths_are_only_referenced_by_a_usda(root, name):
    from pxr import Sdf

    target = reference(root, name, ".png")
    path = stage_with_texture(root, target)
    output = root / "out" / "written.usda"
    output.parent.mkdir()
    result = run("convert", path, "-o", output)
    assert result.exit_code in (0, 1) and output.exists(), result.output
    layer = Sdf.Layer.OpenAsAnonymous(str(output))
    files = [spec.default.path for spec in _attributes(layer) if spec.name == "inputs:file"]
    if name in ("climbs", "symlink", "symlink_loop", "long_outside", "long_inside"):
        expected = os.path.relpath(os.path.normpath(root / "asset" / target), output.parent).replace(os.sep, "/")
    elif name == "absolute":
        expected = target  # outside the output's folder: kept as written
    else:
        expected = target  # URLs, drive and UNC paths are never re-anchored
    assert expected in files, files


def _attributes(layer):
    found = []

    def visit(path):
        if path.IsPropertyPath():
            spec = layer.GetPropertyAtPath(path)
            if spec is not None and hasattr(spec, "default") and spec.default is not None:
                found.append(spec)

    layer.Traverse(layer.pseudoRoot.path, visit)
    return found
