"""UV transforms and texels survive a chain of conversions through every format:
MaterialX place2d -> glTF KHR_texture_transform -> USD UsdTransform2d -> MaterialX place2d.

The expected mapping is MaterialX's place2d (stdlib NG_place2d_vector2, as tests/gltf_support.py
computes it); the expected texels are the source image's.
"""

from __future__ import annotations

import numpy as np
import pytest
from click.testing import CliRunner
from PIL import Image

from cli.group import cli
from gltf_support import place2d
from openpbr_tools.io import read_asset
from openpbr_tools.model import UVTransform

DOCUMENT = """<?xml version="1.0"?>
<materialx version="1.39" colorspace="lin_rec709">
  <place2d name="p" type="vector2">
    <input name="scale" type="vector2" value="3, 1.5"/>
    <input name="rotate" type="float" value="30"/>
    <input name="offset" type="vector2" value="0.1, 0.2"/>
    <input name="pivot" type="vector2" value="0.5, 0.5"/>
  </place2d>
  <image name="c" type="color3">
    <input name="file" type="filename" value="albedo.png" colorspace="srgb_texture"/>
    <input name="texcoord" type="vector2" nodename="p"/>
  </image>
  <open_pbr_surface name="S" type="surfaceshader"><input name="base_color" type="color3" nodename="c"/></open_pbr_surface>
  <surfacematerial name="M" type="material"><input name="surfaceshader" type="surfaceshader" nodename="S"/></surfacematerial>
</materialx>
"""


def convert(source, output):
    result = CliRunner().invoke(cli, ["convert", str(source), "-o", str(output)])
    assert result.exit_code == 0, result.output


@pytest.mark.parametrize("gltf", ["chain.gltf", "chain.glb"])
def test_a_uv_transform_and_its_texels_survive_mtlx_gltf_usd_mtlx(tmp_path, gltf):
    rng = np.random.default_rng(5)
    texels = rng.integers(0, 256, (6, 10, 3), dtype=np.uint8)
    Image.fromarray(texels).save(tmp_path / "albedo.png")
    (tmp_path / "start.mtlx").write_text(DOCUMENT)
    convert(tmp_path / "start.mtlx", tmp_path / gltf)
    convert(tmp_path / gltf, tmp_path / "chain.usda")
    convert(tmp_path / "chain.usda", tmp_path / "end.mtlx")
    material = read_asset(str(tmp_path / "end.mtlx")).materials[0]
    texture = material.inputs["base_color"].value
    original = UVTransform(scale=(3.0, 1.5), rotate=30.0, offset=(0.1, 0.2), pivot=(0.5, 0.5))
    for corner in ((0.0, 0.0), (1.0, 0.0), (0.3, 0.9), (1.0, 1.0)):
        assert place2d(corner, texture.uv) == pytest.approx(place2d(corner, original), abs=1e-6)
    with Image.open(tmp_path / texture.file) as image:
        assert np.array_equal(np.asarray(image.convert("RGB")), texels)
    assert texture.colorspace == "srgb_texture"
