"""Every caller of the path guard, fed hostile references: the textures rule (a MaterialX image's
``file`` through ``validate_paths``, and any texture path through the rules), the glTF reader (an
image URI through ``openpbr validate``), the glTF writer (``openpbr convert x.mtlx -o y.gltf``, and
``write_gltf`` for paths XML cannot carry) and the baker. Whatever the reference, the file it names
outside the asset is never opened nor embedded, the reference is reported (OPBR704, or OPBR701 when
it stays inside but names no file) or refused with a message, and nothing raises a traceback.

Expected verdicts come from the table (the security policy), as in tests/test_paths.py:

* ``OUT``: the reference leaves the asset's folder, is a URL, a drive or a UNC path;
* ``MISSING``: it stays inside but no such file exists;
* ``NUL``: it holds U+0000, which no file name can.
"""

from __future__ import annotations

import json
import os
from xml.sax.saxutils import quoteattr

import pytest
from click.testing import CliRunner

from cli.group import cli
from openpbr_tools.io import read_asset
from openpbr_tools.io.paths import is_url
from openpbr_tools.model import Texture
from openpbr_tools.rules import Context, check_asset
from openpbr_tools.validate import validate_paths

from gltf_support import gltf_pbr_material
from test_hostile_gltf import PNG, PNG_URI, findings, opened_files, textured, write
from test_hostile_gltf import validate as validate_gltf

OUT, MISSING, NUL, SHARED = "out", "missing", "nul", "shared"
# in a MaterialX (or USD) document a relative '..' to an image that is there is a shared folder (OPBR723, information;
# MaterialX's own examples read ../../../Images), still never opened; a glTF's is OPBR704
SHARED_IN_MATERIALX = ("dot-dot",)

# (id, reference, verdict); SECRET is replaced by the absolute path of a real PNG outside the asset.
CALLERS = [
    ("dot-dot", "../secret/private.png", OUT),
    ("dot-dot-backslash", "..\\secret\\private.png", OUT),
    ("absolute-outside", "SECRET", OUT),
    ("symlink-out", "linked.png", OUT),
    ("symlink-folder-out", "linked_folder/private.png", OUT),
    ("symlink-then-dot-dot", "deep_link/../private.png", OUT),
    ("symlink-loop", "loop", OUT),
    ("symlink-loop-below", "loop/x.png", OUT),
    ("drive", "C:\\secret\\private.png", OUT),
    ("drive-relative", "C:private.png", OUT),
    ("unc", "\\\\server\\share\\private.png", OUT),
    ("unc-slash", "//server/share/private.png", OUT),
    ("file-url", "file://SECRET", OUT),
    ("http", "http://example.com/private.png", OUT),
    ("https-without-slashes", "https:private.png", OUT),
    ("data", PNG_URI, OUT),
    ("nul", "a\x00.png", NUL),
    ("very-long-climbing", "../" * 1667 + "x.png", OUT),
    ("very-long", "a/" * 2498 + "x.png", MISSING),
    ("long-component", "a" * 300 + ".png", MISSING),
    ("non-utf8", os.fsdecode(b"\xff\xfe.png"), MISSING),
]
IDS = [row[0] for row in CALLERS]
XML_CANNOT_CARRY = ("nul", "non-utf8")  # XML 1.0 has no U+0000; lone surrogates are no UTF-8


@pytest.fixture
def layout(tmp_path):
    """tmp_path/asset (the asset's folder, with links out and a loop) and tmp_path/secret/private.png."""
    secret = tmp_path / "secret" / "private.png"
    (tmp_path / "secret" / "deep").mkdir(parents=True)
    secret.write_bytes(PNG)
    asset = tmp_path / "asset"
    asset.mkdir()
    os.symlink(secret, asset / "linked.png")
    os.symlink(secret.parent, asset / "linked_folder")
    os.symlink(secret.parent / "deep", asset / "deep_link")
    os.symlink("loop", asset / "loop")
    return asset, secret


def fill(reference: str, secret) -> str:
    return reference.replace("SECRET", str(secret))


def mtlx(file: str) -> str:
    return ('<?xml version="1.0"?>\n<materialx version="1.39" colorspace="lin_rec709">\n'
            f'  <image name="c" type="color3"><input name="file" type="filename" value={quoteattr(file)} '
            'colorspace="srgb_texture"/></image>\n'
            '  <open_pbr_surface name="S" type="surfaceshader"><input name="base_color" type="color3" nodename="c"/>'
            '</open_pbr_surface>\n'
            '  <surfacematerial name="M" type="material"><input name="surfaceshader" type="surfaceshader" nodename="S"/>'
            '</surfacematerial>\n</materialx>\n')


def texture_codes(verdict: str) -> set[str]:
    return {OUT: {"OPBR704"}, MISSING: {"OPBR701"}, NUL: {"OPBR704"}, SHARED: {"OPBR723"}}[verdict]


# -- (a) the textures rule ---------------------------------------------------------------------------

@pytest.mark.parametrize("name, reference, verdict", CALLERS, ids=IDS)
def test_a_materialx_image_file_through_validate_paths(layout, name, reference, verdict):
    folder, secret = layout
    reference = fill(reference, secret)
    path = folder / "m.mtlx"
    if name in XML_CANNOT_CARRY:  # the raw bytes: the document itself is refused, the path never used
        path.write_bytes(mtlx("PLACEHOLDER").encode().replace(b"PLACEHOLDER", os.fsencode(reference)))
    else:
        path.write_text(mtlx(reference), encoding="utf-8")
    with opened_files() as seen:
        report = validate_paths([str(path)])
    assert str(secret) not in seen
    codes = {d.code for d in report.diagnostics}
    verdict = SHARED if name in SHARED_IN_MATERIALX else verdict
    if name in XML_CANNOT_CARRY:
        assert codes & {"OPBR001", "OPBR002"}, codes
        return
    assert texture_codes(verdict) <= codes, (codes, [d.message for d in report.diagnostics])
    if verdict == OUT:
        [unsafe] = [d for d in report.diagnostics if d.code == "OPBR704"]
        assert "outside the asset's folder" in unsafe.message
    else:
        assert "OPBR704" not in codes


@pytest.mark.parametrize("name, reference, verdict", CALLERS, ids=IDS)
def test_any_texture_path_through_the_rules(layout, name, reference, verdict):
    """Paths XML cannot carry reach the rule from other readers (USD strings, glTF URIs)."""
    folder, secret = layout
    (folder / "m.mtlx").write_text(mtlx("placeholder.png"), encoding="utf-8")
    asset = read_asset(str(folder / "m.mtlx"))
    [material] = asset.materials
    texture = material.inputs["base_color"].value
    assert isinstance(texture, Texture)
    texture.file = fill(reference, secret)
    with opened_files() as seen:
        codes = [d.code for d in check_asset(asset, Context())]
    assert str(secret) not in seen
    verdict = SHARED if name in SHARED_IN_MATERIALX else verdict
    assert texture_codes(verdict) <= set(codes), codes
    assert codes.count("OPBR704") == (0 if verdict in (MISSING, SHARED) else 1)
    if is_url(texture.file):  # a URL is never probed on disk, so never "not found"
        assert "OPBR701" not in codes


def test_the_rules_injected_real_path_decides(layout):
    """The rules' Context.real_path is the guard's: a fake link is followed as the context says."""
    folder, secret = layout
    (folder / "plain.png").write_bytes(PNG)
    (folder / "m.mtlx").write_text(mtlx("plain.png"), encoding="utf-8")
    asset = read_asset(str(folder / "m.mtlx"))
    real = os.path.realpath(folder / "plain.png")
    fake = Context(real_path=lambda path: str(secret) if os.path.realpath(path) == real else os.path.realpath(path))
    diagnostics = check_asset(asset, fake)
    [unsafe] = [d for d in diagnostics if d.code == "OPBR704"]
    assert "symbolic link" in unsafe.message and str(secret) in unsafe.message
    assert "OPBR704" not in [d.code for d in check_asset(asset, Context())]


# -- (b) the glTF reader -----------------------------------------------------------------------------

def uri_of(reference: str) -> str:
    return reference.replace("\x00", "%00")


@pytest.mark.parametrize("name, reference, verdict", CALLERS, ids=IDS)
def test_a_gltf_image_uri_through_validate(layout, name, reference, verdict):
    folder, secret = layout
    path = write(folder, "asset.gltf", textured({"uri": uri_of(fill(reference, secret))}))
    with opened_files() as seen:
        result = validate_gltf(path)
    assert str(secret) not in seen
    assert result.exit_code in (0, 1)
    if name == "data":  # an embedded image: decoded from the document, no file involved
        assert not findings(result, "OPBR704") and not findings(result, "OPBR701")
    elif verdict == OUT:
        [unsafe] = findings(result, "OPBR704")
        assert unsafe["location"]["path"] == "/materials/0/pbrMetallicRoughness/baseColorTexture"
    elif verdict == NUL:
        assert [d["location"]["path"] for d in findings(result, "OPBR1210")] == ["/images/0"]
    else:
        assert findings(result, "OPBR701") and not findings(result, "OPBR704")


@pytest.mark.parametrize("name, reference, verdict", CALLERS, ids=IDS)
def test_a_gltf_buffer_uri_is_never_read(layout, name, reference, verdict):
    folder, secret = layout
    # a buffer's data URI is application/octet-stream (glTF 2.0, 3.6.1.1: another type is OPBR1209, the Khronos
    # validator's BUFFER_DATA_URI_MIME_TYPE_INVALID)
    reference = reference.replace("data:image/png", "data:application/octet-stream", 1)
    document = textured({"bufferView": 0, "mimeType": "image/png"}, buffers=[{"uri": uri_of(fill(reference, secret)),
                                                                              "byteLength": len(PNG)}],
                        bufferViews=[{"buffer": 0, "byteLength": len(PNG)}])
    with opened_files() as seen:
        result = validate_gltf(write(folder, "asset.gltf", document))
    assert str(secret) not in seen
    broken = findings(result, "OPBR1209")
    if name == "data":  # a data URI buffer is decoded, not opened
        assert not broken
        return
    assert [d["location"]["path"] for d in broken] == ["/buffers/0/uri"]
    if verdict == OUT:
        assert "it is not opened" in broken[0]["message"]
    elif verdict == NUL:
        assert "not a usable file name" in broken[0]["message"]
    else:
        assert "not found" in broken[0]["message"]


# -- (c) the glTF writer and the baker ------------------------------------------------------------------

@pytest.mark.parametrize("name, reference, verdict", [row for row in CALLERS if row[0] not in XML_CANNOT_CARRY],
                         ids=[i for i in IDS if i not in XML_CANNOT_CARRY])
def test_a_texture_through_openpbr_convert_to_gltf(layout, tmp_path, name, reference, verdict):
    folder, secret = layout
    source = folder / "m.mtlx"
    source.write_text(mtlx(fill(reference, secret)), encoding="utf-8")
    out = tmp_path / "out" / "y.gltf"
    out.parent.mkdir()
    with opened_files() as seen:
        result = CliRunner().invoke(cli, ["convert", str(source), "-o", str(out), "--format", "json"])
    assert result.exception is None or isinstance(result.exception, SystemExit), result.output
    assert "Traceback" not in result.output
    assert str(secret) not in seen
    if verdict == OUT:
        assert result.exit_code == 2, result.output
        assert "outside the source asset's folder" in result.output or "is a URL" in result.output
        assert not out.exists()
    else:
        assert result.exit_code == 0, result.output
        assert "does not exist, not written" in result.output
        written = json.loads(out.read_text())
        assert not written.get("images")
    if out.parent.exists():
        for file in out.parent.iterdir():
            assert file.read_bytes() != PNG  # the secret was never embedded nor copied


@pytest.mark.parametrize("name, reference, verdict", CALLERS, ids=IDS)
def test_a_texture_through_write_gltf(layout, tmp_path, name, reference, verdict):
    from openpbr_tools.io.gltf.writer import GltfWriteError, write_gltf

    folder, secret = layout
    texture = Texture(file=fill(reference, secret), channels=(0, 1, 2), colorspace="srgb_texture")
    out = tmp_path / "out" / "y.glb"
    out.parent.mkdir()
    with opened_files() as seen:
        try:
            notes = write_gltf([gltf_pbr_material("M", base_color=texture)], out, source=str(folder / "m.mtlx"))
        except GltfWriteError as error:
            assert verdict in (OUT, NUL), error
            assert "outside the source asset's folder" in str(error) or "URL" in str(error) or "NUL" in str(error)
            assert not out.exists()
        else:
            assert verdict == MISSING, notes
            assert any("does not exist, not written" in note for note in (n.message for n in notes))
            assert PNG not in out.read_bytes()
    assert str(secret) not in seen


@pytest.mark.parametrize("name, reference, verdict", CALLERS, ids=IDS)
def test_a_texture_through_the_baker(layout, tmp_path, name, reference, verdict):
    from openpbr_tools.bake import BakeError, Baker

    folder, secret = layout
    baker = Baker(source_path=str(folder / "m.mtlx"), folder=str(tmp_path / "out"))
    texture = Texture(file=fill(reference, secret), channels=(0,), colorspace="none")
    with opened_files() as seen:
        with pytest.raises(BakeError) as raised:
            baker._resolve(texture, "roughness")
    assert str(secret) not in seen
    message = str(raised.value)
    if verdict == MISSING:
        assert "does not exist" in message
    else:
        assert "outside the source asset's folder" in message or "URL" in message or "NUL" in message
