"""A .usdz output carries its textures (session 21's red team, M-10 and M-11): a texture named by a ``file://`` URL
or by an absolute path outside the asset's folder is refused, as the glTF writers refuse it, rather than written into
a package that then reads a file outside itself; nothing is written. A web URL stays a name (never fetched)."""

from __future__ import annotations

import zipfile

from click.testing import CliRunner
from PIL import Image

from cli.group import cli

_MTLX = '''<?xml version="1.0"?>
<materialx version="1.39" colorspace="lin_rec709">
  <image name="albedo" type="color3">
    <input name="file" type="filename" value="{file}" colorspace="srgb_texture" />
  </image>
  <open_pbr_surface name="S" type="surfaceshader">
    <input name="base_color" type="color3" nodename="albedo" />
  </open_pbr_surface>
  <surfacematerial name="M" type="material">
    <input name="surfaceshader" type="surfaceshader" nodename="S" />
  </surfacematerial>
</materialx>
'''
_USDA = '''#usda 1.0
def Material "M"
{
    token outputs:surface.connect = </M/S.outputs:surface>
    def Shader "S"
    {
        uniform token info:id = "UsdPreviewSurface"
        color3f inputs:diffuseColor.connect = </M/T.outputs:rgb>
        token outputs:surface
    }
    def Shader "T"
    {
        uniform token info:id = "UsdUVTexture"
        asset inputs:file = @%s@
        float3 outputs:rgb
    }
}
'''


def _outside(tmp_path):
    (tmp_path / "outside").mkdir()
    (tmp_path / "asset").mkdir()
    secret = tmp_path / "outside" / "secret.png"
    Image.new("RGB", (4, 4), (200, 10, 10)).save(secret)
    return secret


def test_a_file_url_texture_is_refused_for_a_usdz_as_for_a_glb(tmp_path):
    secret = _outside(tmp_path)
    source = tmp_path / "asset" / "m.mtlx"
    source.write_text(_MTLX.format(file=secret.as_uri()), encoding="utf-8")
    for output in ("x.glb", "x.usdz"):
        result = CliRunner().invoke(cli, ["convert", str(source), "-o", str(tmp_path / output)])
        assert result.exit_code == 2 and "URL" in result.output and not (tmp_path / output).exists(), output


def test_a_web_url_texture_stays_a_name_in_a_usdz(tmp_path):
    """A web URL is never fetched and names nothing on this disk: the package keeps the reference (unpackaged),
    as before; only a file URL, a local file outside by another name, is refused."""
    source = tmp_path / "asset" / "m.mtlx"
    (tmp_path / "asset").mkdir()
    source.write_text(_MTLX.format(file="https://example.com/albedo.png"), encoding="utf-8")
    result = CliRunner().invoke(cli, ["convert", str(source), "-o", str(tmp_path / "x.usdz")])
    assert result.exit_code == 0, result.output
    with zipfile.ZipFile(tmp_path / "x.usdz") as package:
        assert package.namelist() == ["root.usdc"]


def test_an_absolute_outside_texture_in_a_usdz_is_not_called_packaged_nor_kept(tmp_path):
    secret = _outside(tmp_path)
    package = tmp_path / "asset" / "z.usdz"
    with zipfile.ZipFile(package, "w", zipfile.ZIP_STORED) as archive:  # (usdz members are stored, 64-byte aligned
        archive.writestr("root.usda", _USDA % secret)  # only matters for data usd-core maps; a text layer reads)
    result = CliRunner().invoke(cli, ["convert", str(package), "-o", str(tmp_path / "out.usdz")])
    assert result.exit_code == 2 and "outside the source asset's folder" in result.output
    assert "inside the source package" not in result.output and not (tmp_path / "out.usdz").exists()
