"""OPBR1034: a UsdPreviewSurface whose opacity reads a mask that never reaches opacityThreshold is cut away
whole. The UsdPreviewSurface specification: with a threshold above 0, "rendering of the surface is limited to
the areas where the opacity is greater or equal to that value". The texel values are the ones the tests write;
glTF's counterpart (OPBR1249) was added in session 22, and the published-conversions test relied on an exemption
for Pixar's opacityThreshold test until the USD side had this rule."""

from __future__ import annotations

import pytest
from PIL import Image

from redteam_support import codes, messages, preview_stage, uv_texture

PIXAR = ("data/published/usd/openusd/pxr/usdImaging/usdImagingGL/testenv/testUsdImagingGLPreviewSurface/"
         "testPreviewSurfaceOpacityThreshold.usda")


def _stage(tmp_path, threshold: float, output: str = "a", scale: str = "", file: str = "mask.png"):
    return preview_stage(tmp_path, f"float inputs:opacity.connect = </M/T.outputs:{output}>",
                         f"float inputs:opacityThreshold = {threshold}", name="mask.usda",
                         extra=uv_texture("T", file, output, "float", *([scale] if scale else [])))
def _mask(tmp_path, alpha: int, mode: str = "RGBA", name: str = "mask.png", bright: tuple | None = None):
    image = Image.new(mode, (16, 16), (200, 120, 40, alpha)[:len(mode)] if mode != "L" else 20)
    if bright is not None:
        image.putpixel(bright, (255,) * len(mode))
    image.save(tmp_path / name)


@pytest.mark.parametrize("threshold, cut", [(0.6, True), (0.5, False), (0.3, False)])
def test_a_mask_below_the_threshold_everywhere_is_an_error(tmp_path, threshold, cut):
    _mask(tmp_path, 128)  # 128/255 = 0.502: drawn at or below 0.502, cut above
    assert ("OPBR1034" in codes(_stage(tmp_path, threshold))) is cut


def test_an_image_without_alpha_reads_alpha_one(tmp_path):
    _mask(tmp_path, 0, mode="RGB")
    assert "OPBR1034" not in codes(_stage(tmp_path, 1.0))
    # its blue (40/255) is the wrong channel for a 0.5 mask: cut everywhere
    assert "OPBR1034" in codes(_stage(tmp_path, 0.5, output="b"))


def test_the_scale_applies(tmp_path):
    _mask(tmp_path, 255)
    scaled = _stage(tmp_path, 0.6, scale="float4 inputs:scale = (1, 1, 1, 0.5)")
    assert "OPBR1034" in codes(scaled)
    assert "times scale 0.5" in messages(scaled, "OPBR1034")[0]


def test_one_bright_texel_of_a_jpeg_is_seen(tmp_path):
    # decoded at full resolution: at 1/8 scale one white texel in dark grey averages to about 30/255
    _mask(tmp_path, 0, mode="L", name="mask.jpg", bright=(5, 5))
    reduced = Image.open(tmp_path / "mask.jpg")
    reduced.draft("L", (2, 2))
    assert reduced.getextrema()[1] < 128  # what a reduced decode would have judged by
    assert Image.open(tmp_path / "mask.jpg").getextrema()[1] > 128
    assert "OPBR1034" not in codes(_stage(tmp_path, 0.5, output="r", file="mask.jpg"))
    _mask(tmp_path, 0, mode="L", name="mask.jpg")  # and without the texel, cut
    assert "OPBR1034" in codes(_stage(tmp_path, 0.5, output="r", file="mask.jpg"))


def test_pixars_threshold_test_cuts_two_materials_away():
    from pathlib import Path

    path = Path(__file__).resolve().parent / PIXAR
    found = messages(path, "OPBR1034")
    # its texture's alpha is 128/255 everywhere: thresholds 0, 0.1, 0.3 and 0.5 draw it, 0.9 and 1 cut it away
    assert len(found) == 2 and all("0.502" in m for m in found)
    assert {m.split(":")[0] for m in found} == {"/Scene/Looks/Material_0_4/PbrPreview", "/Scene/Looks/Material_0_5/PbrPreview"}
