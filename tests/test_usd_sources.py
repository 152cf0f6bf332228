"""Published USD assets (OpenUSD's preview-surface test scenes, the USD working group's test assets)
converted to every MaterialX model: every output loads, passes Document.validate() and generates a
GLSL shader, and a UsdUVTexture's defaults read as the UsdPreviewSurface specification has them.
Defects found by rendering these assets in MaterialX's GLSL against a reference built with usd-core:
a wrap token written into MaterialX as it was ("repeat": no shader could be generated) and an
unauthored sourceColorSpace read as linear (its default, "auto", decodes 8-bit RGB(A) as sRGB: 16.3
mean CIEDE2000 on testPreviewSurfaceOpacityThreshold)."""

from __future__ import annotations

import shutil
from pathlib import Path

import MaterialX as mx
import MaterialX.PyMaterialXGenShader as gs
import pytest

from glsupport import shader_generator
from openpbr_tools.convert import convert_file
from openpbr_tools.io import read_asset
from openpbr_tools.translate.common import Settings

PUBLISHED = Path(__file__).parent / "data" / "published" / "usd"
TARGETS = ("open_pbr_surface", "standard_surface", "gltf_pbr", "UsdPreviewSurface")
PREVIEW_TESTS = PUBLISHED / "openusd" / "pxr" / "usdImaging" / "usdImagingGL" / "testenv" / "testUsdImagingGLPreviewSurface"
ASSETS = sorted(PREVIEW_TESTS.glob("*.usda")) + [PUBLISHED / "usd-wg" / "test_assets" / "AlphaBlendSortTest" /
                                                   "AlphaBlendSortTest.usda"]


@pytest.fixture(scope="module")
def generator():
    return shader_generator()


def _copy(asset: Path, tmp_path: Path) -> Path:
    folder = tmp_path / "asset"
    shutil.copytree(asset.parent, folder)
    return folder / asset.name


@pytest.mark.parametrize("asset", ASSETS, ids=lambda p: p.stem)
def test_every_mtlx_output_of_a_published_usd_asset_validates_and_generates(tmp_path, generator, asset):
    library, glsl, context = generator
    source = _copy(asset, tmp_path)
    assert read_asset(str(source)).materials, asset.name
    for target in TARGETS:
        out = tmp_path / f"out_{target}.mtlx"
        convert_file(str(source), str(out), target, Settings())
        written = mx.createDocument()
        mx.readFromXmlFile(written, str(out))
        written.importLibrary(library)
        valid, message = written.validate()
        assert valid, f"{asset.name} -> {target}: {message}"
        for node in written.getNodes():
            for name in ("uaddressmode", "vaddressmode"):
                port = node.getInput(name)
                assert port is None or port.getValueString() in ("constant", "clamp", "periodic", "mirror"), \
                    f"{asset.name} -> {target}: {node.getName()}.{name} = {port.getValueString()}"
        for element in gs.findRenderableElements(written):
            assert glsl.generate("check", element, context).getSourceCode(gs.PIXEL_STAGE), (asset.name, target)


@pytest.mark.parametrize("target", TARGETS)
def test_an_unauthored_source_colour_space_is_auto_and_decodes_an_8_bit_rgba_image_as_srgb(tmp_path, target):
    """testPreviewSurfaceOpacityThreshold's UsdUVTexture reads textureCutout.png (8-bit RGBA) without a
    sourceColorSpace: the default, auto, decodes it as sRGB (UsdPreviewSurface specification,
    UsdUVTexture: "auto ... mark texture as sRGB if it is 8-bit and has 3 channels or 4 channels")."""
    source = _copy(PREVIEW_TESTS / "testPreviewSurfaceOpacityThreshold.usda", tmp_path)
    out = tmp_path / "out.mtlx"
    convert_file(str(source), str(out), target, Settings())
    written = mx.createDocument()
    mx.readFromXmlFile(written, str(out))
    spaces = {node.getInput("file").getColorSpace() for node in written.getNodes()
              if node.getCategory() in ("image", "tiledimage") and node.getType() in ("color3", "color4")}
    assert spaces == {"srgb_texture"}, spaces
