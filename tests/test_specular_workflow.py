"""A specular-workflow UsdPreviewSurface (diffuse colour D, F0 colour S with a white edge) read as OpenPBR's
metal-dielectric mix (translate/specular_workflow.py), and the candidate search's second reading (the F0
colour's luminance with a tint) where the split loses.

Expected values come from closed forms (a grey F0 is a dielectric of that F0; a black diffuse under S is
the metal of F0 S, whose white F82 edge is Schlick's), from the published spec-gloss -> metal-rough solve
as Babylon.js writes it (the quadratic formula, the m^2 blend of the two colours), and from MaterialX's
GLSL renderer: the converted .mtlx against MaterialX's own UsdPreviewSurface with the source's values."""

from __future__ import annotations

import shutil
from pathlib import Path

import numpy as np
import pytest

from glsupport import comparison_mask, materialx_renderer, mean_delta_e, single_material
from openpbr_tools.convert import convert_file
from openpbr_tools.evaluate.preview import Rig
from openpbr_tools.io import read_asset
from openpbr_tools.translate.common import Settings
from openpbr_tools.translate.convert import convert
from openpbr_tools.translate.specular_workflow import split

PREVIEW_TESTS = (Path(__file__).parent / "data" / "published" / "usd" / "openusd" / "pxr" / "usdImaging" /
                 "usdImagingGL" / "testenv" / "testUsdImagingGLPreviewSurface")
RNG = np.random.default_rng(20261126)


@pytest.mark.parametrize("trial", range(20))
def test_a_grey_f0_is_a_dielectric_of_that_f0_over_the_diffuse_colour(trial):
    diffuse, grey = RNG.uniform(0, 1, 3), RNG.uniform(0, 0.9)
    for strength in ("mean", "max"):
        m, base, a = split(diffuse, np.full(3, grey), strength)
        assert float(m[0]) == 0.0
        np.testing.assert_allclose(base, diffuse, atol=1e-12)
        assert float(a[0]) == pytest.approx(grey, abs=1e-12)


@pytest.mark.parametrize("trial", range(20))
def test_a_black_diffuse_under_a_coloured_f0_is_the_metal_of_that_f0(trial):
    specular = RNG.uniform(0.05, 1.0, 3)
    m, base, _ = split(np.zeros(3), specular, "mean")
    assert float(m[0]) == pytest.approx(1.0, abs=1e-12)
    np.testing.assert_allclose(base, specular, atol=1e-12)


def _published_solve(diffuse, specular):
    """Babylon.js / glTF-Toolkit's spec-gloss -> metal-rough conversion, written as published (dielectric
    F0 0.04, specular strength max(S), the quadratic formula, the m^2 blend of the two colours)."""
    dielectric = 0.04

    def perceived(c):
        return np.sqrt(0.299 * c[0] ** 2 + 0.587 * c[1] ** 2 + 0.114 * c[2] ** 2)

    one_minus = 1 - max(specular)
    pd, ps = perceived(diffuse), perceived(specular)
    if ps < dielectric:
        metallic = 0.0
    else:
        a = dielectric
        b = pd * one_minus / (1 - dielectric) + ps - 2 * dielectric
        c = dielectric - ps
        metallic = min(max((-b + np.sqrt(b * b - 4 * a * c)) / (2 * a), 0.0), 1.0)
    from_diffuse = diffuse * one_minus / (1 - dielectric) / max(1 - metallic, 1e-6)
    from_specular = (specular - dielectric * (1 - metallic)) / max(metallic, 1e-6)
    return metallic, np.clip(from_diffuse + (from_specular - from_diffuse) * metallic ** 2, 0, 1)


@pytest.mark.parametrize("trial", range(30))
def test_the_split_is_the_published_solve_where_its_dielectric_f0_is_0_04(trial):
    diffuse = RNG.uniform(0, 1, 3)
    specular = np.append(RNG.uniform(0.04, 1.0, 2), 0.04)
    RNG.shuffle(specular)
    metallic, base = _published_solve(diffuse, specular)
    m, colour, a = split(diffuse, specular, "max")
    assert float(a[0]) == pytest.approx(0.04)
    assert float(m[0]) == pytest.approx(metallic, abs=1e-9)
    if 1e-3 < metallic < 1 - 1e-3:  # the published form divides by m and 1 - m
        np.testing.assert_allclose(colour, base, atol=1e-9)


def _stage(path: Path, diffuse, specular, roughness, extra: str = "") -> Path:
    path.write_text(f"""#usda 1.0
def Scope "Looks" {{
    def Material "M" {{
        token outputs:surface.connect = </Looks/M/Preview.outputs:surface>
        def Shader "Preview" {{
            uniform token info:id = "UsdPreviewSurface"
            int inputs:useSpecularWorkflow = 1
            color3f inputs:diffuseColor = ({', '.join(map(str, diffuse))})
            color3f inputs:specularColor = ({', '.join(map(str, specular))})
            float inputs:roughness = {roughness}
            {extra}
            token outputs:surface
        }}
    }}
}}
""")
    return path


@pytest.fixture(scope="module")
def gl():
    rig = Rig(size=64)
    return rig, materialx_renderer(rig), comparison_mask(rig)


@pytest.mark.parametrize("diffuse, specular, roughness, bound, before", [
    ((0.05, 0.05, 0.05), (0.95, 0.64, 0.54), 0.2, 0.6, 6.62),   # a copper: F0 colour over a dark diffuse
    ((0.02, 0.02, 0.03), (1.0, 0.78, 0.34), 0.5, 0.6, 5.81),    # a gold
    ((0.5, 0.5, 0.5), (0.2, 0.6, 0.9), 0.2, 2.3, 5.74),         # a coloured F0 over a grey diffuse
    ((0.8, 0.2, 0.1), (0.04, 0.04, 0.04), 0.5, 0.5, 0.22),       # a plastic: exact but for Schlick's curve
])
def test_a_specular_workflow_material_renders_in_materialx_like_its_source(tmp_path, gl, diffuse, specular,
                                                                           roughness, bound, before):
    """MaterialX's GLSL: the converted OpenPBR against MaterialX's UsdPreviewSurface with the source's values
    (``before``: the luminance reading's figure, measured the same way)."""
    rig, renderer, mask = gl
    source = _stage(tmp_path / "s.usda", diffuse, specular, roughness)
    out = tmp_path / "out.mtlx"
    convert_file(str(source), str(out), "open_pbr_surface", Settings())
    image = renderer.render_document(single_material(str(out), "M", str(tmp_path / "M.mtlx")))
    reference = renderer.render("UsdPreviewSurface", {"useSpecularWorkflow": 1, "diffuseColor": diffuse,
                                                      "specularColor": specular, "roughness": roughness})
    assert mean_delta_e(image, reference, mask, rig.white()) < bound


def test_the_luminance_reading_is_kept_where_the_split_renders_further_off(tmp_path):
    """OpenUSD's testPreviewSurfaceSpecular: a red F0 of 1 over a red diffuse, which MaterialX's grey
    layering shows brighter than any energy-conserving material; the F0 colour's luminance with a tint
    renders closer there, the candidate search says so with both figures, and the result is that reading's
    (an IOR with a red specular_color)."""
    folder = tmp_path / "asset"
    shutil.copytree(PREVIEW_TESTS, folder)
    out = tmp_path / "out.mtlx"
    result = convert_file(str(folder / "testPreviewSurfaceSpecular.usda"), str(out), "open_pbr_surface", Settings())
    kept = [d for d in result.diagnostics if "read by its F0 colour's luminance" in d.message]
    assert len(kept) == 10, [d.message for d in result.diagnostics]
    written = read_asset(str(out)).materials
    assert len(written) == 10
    for material in written:
        assert "base_metalness" not in material.inputs
        np.testing.assert_allclose(material.inputs["specular_color"].value.value, (1.0, 0.0, 0.0))


def test_without_the_search_the_split_is_written_and_reported_at_both_colours(tmp_path):
    source = _stage(tmp_path / "s.usda", (0.3, 0.1, 0.05), (0.5, 0.3, 0.1), 0.4)
    out = tmp_path / "out.mtlx"
    result = convert_file(str(source), str(out), "open_pbr_surface", Settings(candidates=False))
    m, base, a = split((0.3, 0.1, 0.05), (0.5, 0.3, 0.1), "mean")
    material, = read_asset(str(out)).materials
    assert material.inputs["base_metalness"].value.value == pytest.approx(float(m[0]), abs=1e-6)
    np.testing.assert_allclose(material.inputs["base_color"].value.value, base, atol=1e-6)
    where = {str(d.location).rsplit(".", 1)[-1] for d in result.diagnostics if "metal share" in d.message}
    assert where == {"diffuseColor", "specularColor"}


def test_a_transparent_specular_workflow_metal_keeps_its_opacity_on_the_way_back(tmp_path):
    """The preview's transparency covers its metal share too, OpenPBR's transmission only the dielectric:
    the split's metalness m gives transmission (1 - opacity) / (1 - m), which the writer turns back into
    the preview's opacity."""
    source = _stage(tmp_path / "s.usda", (0.3, 0.2, 0.2), (0.6, 0.4, 0.3), 0.3, "float inputs:opacity = 0.8")
    preview, = read_asset(str(source)).materials
    openpbr = convert(preview, "open_pbr_surface", Settings(candidates=False)).material
    m, _, _ = split((0.3, 0.2, 0.2), (0.6, 0.4, 0.3), "mean")
    assert 0.0 < float(m[0]) < 1.0
    assert openpbr.inputs["transmission_weight"].value.value == pytest.approx(0.2 / (1.0 - float(m[0])), abs=1e-6)
    back = convert(openpbr, "UsdPreviewSurface", Settings(candidates=False)).material
    assert back.inputs["opacity"].value.value == pytest.approx(0.8, abs=1e-6)
