"""A .usdz output carries its textures (session 21's red team, M-10 and M-11): a texture named by a ``file://`` URL
or by an absolute path outside the asset's folder is refused, as the glTF writers refuse it, rather than written into
a package that then reads a file outside itself; nothing is written. A web URL stays a name (never fetched)."""

from __future__ import annotations

import zipfile

from click.testing import CliRunner
from PIL import Image

from cli.group import cli
from redteam_support import mtlx, textured_openpbr, textured_preview



def _outside(tmp_path):
    (tmp_path / "outside").mkdir()
    (tmp_path / "asset").mkdir()
    secret = tmp_path / "outside" / "secret.png"
    Image.new("RGB", (4, 4), (200, 10, 10)).save(secret)
    return secret


def test_a_file_url_texture_is_refused_for_a_usdz_as_for_a_glb(tmp_path):
    secret = _outside(tmp_path)
    source = mtlx(tmp_path / "asset", textured_openpbr(secret.as_uri()))
    for output in ("x.glb", "x.usdz"):
        result = CliRunner().invoke(cli, ["convert", str(source), "-o", str(tmp_path / output)])
        assert result.exit_code == 2 and "URL" in result.output and not (tmp_path / output).exists(), output


def test_a_web_url_texture_stays_a_name_in_a_usdz(tmp_path):
    """A web URL is never fetched and names nothing on this disk: the package keeps the reference (unpackaged),
    as before; only a file URL, a local file outside by another name, is refused."""
    (tmp_path / "asset").mkdir()
    source = mtlx(tmp_path / "asset", textured_openpbr("https://example.com/albedo.png"))
    result = CliRunner().invoke(cli, ["convert", str(source), "-o", str(tmp_path / "x.usdz")])
    assert result.exit_code == 0, result.output
    with zipfile.ZipFile(tmp_path / "x.usdz") as package:
        assert package.namelist() == ["root.usdc"]


def test_an_absolute_outside_texture_in_a_usdz_is_not_called_packaged_nor_kept(tmp_path):
    secret = _outside(tmp_path)
    package = tmp_path / "asset" / "z.usdz"
    with zipfile.ZipFile(package, "w", zipfile.ZIP_STORED) as archive:  # (usdz members are stored, 64-byte aligned
        archive.writestr("root.usda", textured_preview(secret))  # only matters for data usd-core maps; a text layer reads)
    result = CliRunner().invoke(cli, ["convert", str(package), "-o", str(tmp_path / "out.usdz")])
    assert result.exit_code == 2 and "outside the source asset's folder" in result.output
    assert "inside the source package" not in result.output and not (tmp_path / "out.usdz").exists()
