"""OpenPBR's geometry_opacity is presence (the surface, reflections and emission included, partly
absent); UsdPreviewSurface's default "transparent" opacity keeps reflections and emission (a glass).
A cut-out leaf or a half-present emitter used to become a see-through glass in USD without a note
(22 mean CIEDE2000 on the evaluator for opacity 0.3), and came back as transmission_weight 0.7."""

from __future__ import annotations

import numpy as np
import pytest

from openpbr_tools.evaluate import build_model
from openpbr_tools.evaluate.preview import Rig, shade_sphere
from openpbr_tools.evaluate.verify import compare_materials
from openpbr_tools.model import Constant, Input, Location, Material
from openpbr_tools.translate.common import Settings
from openpbr_tools.translate.convert import convert

LOCATION = Location("m.mtlx", 1, "S")


def material(**values) -> Material:
    inputs = {name: Input(name, "color3" if isinstance(v, tuple) else "float", Constant(v), LOCATION.with_input(name))
              for name, v in values.items()}
    return Material("S", "open_pbr_surface", LOCATION, inputs, version="1.1.1", colorspace="lin_rec709")


def test_presence_mode_is_coverage_in_the_evaluator():
    """Spec 2.6: in presence mode opacity is the surface's coverage, so the render is opacity x the
    opaque surface + (1 - opacity) x the background, emission included (closed form)."""
    rig = Rig(size=24)
    values = {"diffuseColor": np.array([0.2, 0.6, 0.1]), "emissiveColor": np.array([2.0, 1.0, 0.5]), "roughness": 0.3}
    opaque, mask = shade_sphere(build_model("UsdPreviewSurface", values), rig)
    present, _ = shade_sphere(build_model("UsdPreviewSurface", {**values, "opacity": 0.3, "opacityMode": 1}), rig)
    expected = 0.3 * opaque + 0.7 * rig.environment_radiance
    np.testing.assert_allclose(present[mask], expected[mask], atol=1e-9)
    glass, _ = shade_sphere(build_model("UsdPreviewSurface", {**values, "opacity": 0.3}), rig)
    assert np.abs(glass[mask] - expected[mask]).mean() > 0.1  # transparent mode is another thing


def test_geometry_opacity_becomes_presence_and_comes_back():
    source = material(base_color=(0.2, 0.6, 0.1), geometry_opacity=0.3, emission_luminance=2.0)
    there = convert(source, "UsdPreviewSurface", Settings(candidates=False))
    assert there.material.inputs["opacityMode"].value.value == 1
    assert there.material.inputs["opacity"].value.value == pytest.approx(0.3)
    assert [d for d in there.diagnostics if d.location.input == "geometry_opacity" and "presence" in d.message]
    assert compare_materials(source, there.material).preview.mean < 0.5  # was 22
    back = convert(there.material, "open_pbr_surface", Settings(candidates=False)).material
    assert back.inputs["geometry_opacity"].value.value == pytest.approx(0.3)
    assert "transmission_weight" not in back.inputs


def test_presence_and_transmission_together_are_reported_where_one_opacity_cannot_hold_both():
    """A mostly present glass (o t = 0.64 of the surface transmits, 1 - o = 0.2 is absent): the
    transparent product o (1 - t) is the smaller error."""
    source = material(geometry_opacity=0.8, transmission_weight=0.8)
    there = convert(source, "UsdPreviewSurface", Settings(candidates=False))
    assert "opacityMode" not in there.material.inputs
    assert there.material.inputs["opacity"].value.value == pytest.approx(0.8 * (1 - 0.8))
    notes = [d for d in there.diagnostics if d.location.input == "geometry_opacity"]
    assert notes and notes[0].code == "OPBR1103"


def test_an_opaque_material_gets_no_opacity_mode():
    there = convert(material(base_color=(0.5, 0.5, 0.5)), "UsdPreviewSurface", Settings(candidates=False))
    assert "opacityMode" not in there.material.inputs


def test_a_mostly_absent_transmitter_keeps_presence():
    """geometry_opacity 0 with a little transmission (and emission): the transparent product would show
    the emitter the source hides (75 mean CIEDE2000 on a generated material); presence misshows only
    the transmitting share of what is present, here nothing."""
    source = material(geometry_opacity=0.0, transmission_weight=0.08, emission_luminance=9.0)
    there = convert(source, "UsdPreviewSurface", Settings(candidates=False))
    assert there.material.inputs["opacityMode"].value.value == 1
    assert there.material.inputs["opacity"].value.value == 0.0
    # one note, the presence one: not also the transparent reading's ("transmission becomes transparency")
    assert len([d for d in there.diagnostics if d.location.input == "geometry_opacity" and d.code == "OPBR1103"]) == 1
    assert compare_materials(source, there.material).preview.mean < 0.5
