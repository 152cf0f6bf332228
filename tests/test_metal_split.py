"""A partly metallic OpenPBR material whose metal is dimmed by specular_weight (or tinted at the edge) in glTF, whose
metal and dielectric share one colour: metalness and colour fitted together (translate/fit_metal.split_metal), not
the colours mixed by OpenPBR's metalness (MaterialX's GLSL agrees: tests/benchmarks/bench_metal_split_glsl.py,
30 materials 1.51 -> 0.40 mean CIEDE2000, none worse by more than 0.5).

The expected values are closed forms: with specular_weight 0, OpenPBR's metal reflects nothing (the spec: the
metal's Fresnel is scaled by specular_weight) and its dielectric neither reflects, so the material is a Lambertian
of albedo (1 - metalness) * base_weight * base_color, which glTF writes exactly as a dielectric (metallic 0) of that
base colour with KHR_materials_specular's factor 0."""

from __future__ import annotations

import numpy as np
import pytest

from openpbr_tools import tables
from openpbr_tools.evaluate.verify import compare_materials
from openpbr_tools.model import Constant, Input, Location, Material
from openpbr_tools.translate.common import Settings
from openpbr_tools.translate.convert import convert
from openpbr_tools.translate.fit_metal import fitted_metal, split_metal

LOCATION = Location("m.mtlx", 1, "S")


def _openpbr(**values) -> Material:
    table = tables.table("open_pbr_surface")
    inputs = {name: Input(name, table[name].type, Constant(value), LOCATION.with_input(name))
              for name, value in values.items()}
    return Material("S", "open_pbr_surface", LOCATION, inputs, version=table.version)


def _value(material: Material, name: str, default):
    entry = material.inputs.get(name)
    return np.asarray(entry.constant if entry is not None else default, dtype=np.float64)


@pytest.mark.parametrize("target, metallic, colour", [("gltf_pbr", "metallic", "base_color")])
def test_a_metal_dimmed_to_nothing_becomes_the_dielectric_it_leaves(target, metallic, colour):
    source = _openpbr(base_metalness=0.73, specular_weight=0.0, base_color=(0.8, 0.6, 0.4))
    result = convert(source, target, Settings(candidates=False)).material
    expected = 0.27 * np.array([0.8, 0.6, 0.4])  # (1 - metalness) base_weight base_color, the closed form above
    assert float(_value(result, metallic, 0.0)) <= 0.01
    np.testing.assert_allclose(_value(result, colour, (0, 0, 0)), expected, atol=0.004)
    assert compare_materials(source, result).preview.mean < 0.6  # was 8.5 with the colours mixed by 0.73


@pytest.mark.parametrize("target", ["gltf_pbr", "UsdPreviewSurface"])
def test_an_undimmed_untinted_partial_metal_keeps_its_metalness_and_colour(target):
    """(The preview always mixes: usd_preview.preview_diffuse_color.)"""
    """The mix is exact where the fitted metal equals the shared colour: nothing moves."""
    source = _openpbr(base_metalness=0.4, base_color=(0.8, 0.5, 0.2))
    result = convert(source, target, Settings(candidates=False)).material
    assert float(_value(result, "metallic", 0.0)) == pytest.approx(0.4, abs=1e-12)
    if target == "gltf_pbr":
        np.testing.assert_allclose(_value(result, "base_color", (0, 0, 0)), (0.8, 0.5, 0.2), atol=1e-12)


def test_split_metal_is_the_mix_where_the_metal_is_the_dielectric_colour_and_never_worse_in_its_measure():
    rng = np.random.default_rng(5)
    for _ in range(200):
        colour, tint = rng.uniform(0, 1, 3), rng.uniform(0, 1, 3)
        metalness, weight, alpha = rng.uniform(0.01, 0.99), rng.uniform(0, 1), rng.uniform(0.001, 1)
        same = fitted_metal(colour, np.ones(3), 1.0, alpha)
        x, b = split_metal(colour, same, metalness, alpha)
        assert float(x) == metalness and np.allclose(b, colour)
        metal = fitted_metal(colour, tint, weight, alpha)
        x, b = split_metal(colour, metal, metalness, alpha)
        assert 0.0 <= float(x) <= 1.0 and np.all((0.0 <= b) & (b <= 1.0))
        # the diffuse albedo it gives, (1 - x) b, is never further from the source's than the mix's
        mixed = np.clip(colour + metalness * (metal - colour), 0, 1)
        source_diffuse = (1 - metalness) * colour
        split_error = np.abs((1 - x) * b - source_diffuse).max()
        mix_error = np.abs((1 - metalness) * mixed - source_diffuse).max()
        assert split_error <= mix_error + 0.35  # it trades some diffuse for the metal, within a bound


def test_a_dimmed_partial_metal_renders_closer_than_the_mix():
    """On the evaluator (the judge of #13's shares), against the same translation with the colours mixed by
    OpenPBR's metalness (what a material read from glTF still gets: translate.gltf.MIXED_METAL). On 1,000 generated
    materials 36 improved by more than 0.3 mean CIEDE2000 on glTF and 2 worsened, by at most 0.62
    (bench_fidelity --corpus archetypes, session 22)."""
    from openpbr_tools.translate.gltf import MIXED_METAL

    rng = np.random.default_rng(9)
    gains = []
    for _ in range(12):
        source = _openpbr(base_metalness=float(rng.uniform(0.2, 0.9)), specular_weight=float(rng.uniform(0, 0.6)),
                          base_color=tuple(float(c) for c in rng.uniform(0.1, 0.9, 3)))
        split = convert(source, "gltf_pbr", Settings(candidates=False)).material
        source.extra[MIXED_METAL] = True
        mixed = convert(source, "gltf_pbr", Settings(candidates=False)).material
        source.extra.pop(MIXED_METAL)
        assert float(_value(split, "metallic", 1.0)) < float(_value(mixed, "metallic", 1.0))
        gains.append(compare_materials(source, mixed).preview.mean - compare_materials(source, split).preview.mean)
    assert min(gains) > -0.3 and float(np.median(gains)) > 1.0


_PROCEDURAL = '''<?xml version="1.0"?>
<materialx version="1.39" colorspace="lin_rec709">
  <noise2d name="noise" type="color3">
    <input name="amplitude" type="vector3" value="0.5, 0.5, 0.5" />
    <input name="pivot" type="float" value="0.5" />
  </noise2d>
  <open_pbr_surface name="S" type="surfaceshader">
    <input name="base_color" type="color3" nodename="noise" />
    <input name="base_metalness" type="float" value="0.73" />
    <input name="specular_weight" type="float" value="0" />
  </open_pbr_surface>
  <surfacematerial name="M" type="material">
    <input name="surfaceshader" type="surfaceshader" nodename="S" />
  </surfacematerial>
</materialx>
'''


def test_a_partial_metal_with_a_procedural_colour_keeps_its_metalness_in_a_gltf_file(tmp_path):
    """The review's reproducer: the split's metalness depends on every base source, so a base colour that cannot be
    baked (a procedural) left metallicFactor out of the file, which glTF reads as 1, a full metal. Per texel the mix
    is kept, with the source's metalness, and no note says it was split."""
    import json

    from openpbr_tools.convert import convert_file

    source = tmp_path / "m.mtlx"
    source.write_text(_PROCEDURAL, encoding="utf-8")
    conversion = convert_file(str(source), str(tmp_path / "m.gltf"), None, Settings())
    written = json.loads((tmp_path / "m.gltf").read_text(encoding="utf-8"))["materials"][0]["pbrMetallicRoughness"]
    assert written.get("metallicFactor") == pytest.approx(0.73)
    assert not [d for d in conversion.diagnostics if "lower metallic" in d.message]
