"""Reflectance colours outside [0, 1]: which are defects and which are real materials.

OpenPBR's specification tables give base_color and specular_color the range [0, 1]^3, but its
authors' own example metals (OpenPBR repository, examples/) set a metal's F82 edge tint above 1,
and measured reflectances converted to linear Rec.709 leave its gamut. The expected numbers here
come from the specification's F82 formula (OpenPBR 1.1, "Metal") and from the published
linear-Rec.709-to-ACEScg matrix, not from the code under test.
"""

from __future__ import annotations

import pytest

from openpbr_tools.validate import validate_paths

#: Linear Rec.709 (D65) to ACEScg (AP1, D60), Bradford-adapted, as published with the ACES
#: colour-space conversions (e.g. OpenColorIO's ACES configs). The toolkit adapts with CAT02:
#: the two agree to about 1e-3.
REC709_TO_ACESCG = ((0.6131, 0.3395, 0.0474), (0.0702, 0.9164, 0.0134), (0.0206, 0.1096, 0.8698))


def _metal(base_color: str, specular_color: str, colorspace: str = "acescg") -> str:
    return (f'<open_pbr_surface name="S" type="surfaceshader">\n'
            f'  <input name="base_color" type="color3" value="{base_color}" colorspace="{colorspace}" />\n'
            f'  <input name="base_metalness" type="float" value="1" />\n'
            f'  <input name="specular_color" type="color3" value="{specular_color}" colorspace="{colorspace}" />\n'
            f'</open_pbr_surface>')


def _findings(path) -> dict[str, str]:
    return {d.code: str(d.severity) for d in validate_paths([str(path)]).diagnostics if d.code in ("OPBR301", "OPBR304")}


def _edge(f0: float, tint: float) -> float:
    """The edge reflectivity the F82 tint asks for: tint * F_Schlick(1/7)."""
    return tint * (f0 + (1.0 - f0) * (1.0 - 1.0 / 7.0) ** 5)


def test_openpbr_cesium_edge_tint_above_one_is_accepted(write_mtlx):
    # OpenPBR's examples/open_pbr_cesium.mtlx (acescg): the blue edge asks for 0.87 <= 1.
    assert _edge(0.299, 1.394) == pytest.approx(0.8686, abs=1e-3)
    assert _findings(write_mtlx(_metal("0.633, 0.561, 0.299", "1.128, 1.175, 1.394"))) == {}


def test_an_edge_tint_asking_for_more_than_total_reflection_is_an_error(write_mtlx):
    assert _edge(0.9, 1.5) > 1.0
    assert _findings(write_mtlx(_metal("0.9, 0.9, 0.9", "1.5, 1, 1"))) == {"OPBR301": "error"}


def test_an_edge_tint_above_one_on_a_dielectric_is_not_a_metal_allowance(write_mtlx):
    path = write_mtlx('<open_pbr_surface name="S" type="surfaceshader">\n'
                      '  <input name="specular_color" type="color3" value="1.5, 1, 1" colorspace="acescg" />\n'
                      '</open_pbr_surface>')
    assert _findings(path) == {"OPBR301": "error"}


def test_measured_gold_outside_rec709_is_a_gamut_info_with_its_acescg_value(write_mtlx):
    """Published measured metals are authored so (tests/data/published/measured/Gold.mtlx): an info, not a
    warning, which would be a false alarm on every such library."""
    rgb = (1.059, 0.773, 0.307)  # the CC0 physically-based database's gold, linear Rec.709
    acescg = [sum(m * c for m, c in zip(row, rgb)) for row in REC709_TO_ACESCG]
    assert all(0.0 <= c <= 1.0 for c in acescg)
    path = write_mtlx('<open_pbr_surface name="S" type="surfaceshader">\n'
                      '  <input name="base_color" type="color3" value="1.059, 0.773, 0.307" />\n</open_pbr_surface>')
    diagnostics = [d for d in validate_paths([str(path)]).diagnostics if d.code == "OPBR304"]
    assert [str(d.severity) for d in diagnostics] == ["info"]
    assert not any(d.code == "OPBR301" for d in validate_paths([str(path)]).diagnostics)
    shown = diagnostics[0].message.rsplit("but (", 1)[1].split(")")[0]
    assert [float(c) for c in shown.split(",")] == pytest.approx(acescg, abs=2e-3)


def test_a_value_above_one_even_in_acescg_stays_an_error(write_mtlx):
    path = write_mtlx('<open_pbr_surface name="S" type="surfaceshader">\n'
                      '  <input name="base_color" type="color3" value="1.2, 1.2, 1.2" colorspace="acescg" />\n'
                      '</open_pbr_surface>')
    assert _findings(path) == {"OPBR301": "error"}


def test_a_negative_component_stays_an_error_even_for_a_real_colour(write_mtlx):
    # (0.9, -0.05, 0.1) in linear Rec.709 is a saturated red inside ACEScg's gamut, but a
    # negative reflectance makes sampling weights negative.
    acescg = [sum(m * c for m, c in zip(row, (0.9, -0.05, 0.1))) for row in REC709_TO_ACESCG]
    assert all(c >= 0.0 for c in acescg)
    path = write_mtlx('<open_pbr_surface name="S" type="surfaceshader">\n'
                      '  <input name="base_color" type="color3" value="0.9, -0.05, 0.1" />\n</open_pbr_surface>')
    assert _findings(path) == {"OPBR301": "error"}


@pytest.mark.parametrize("scale", ["1.842, 1.044, 0.35", "3, 1, 0.25"])
def test_subsurface_radius_scale_above_one_is_a_length_ratio_not_an_error(write_mtlx, scale):
    # OpenPBR's examples/open_pbr_milk.mtlx and open_pbr_petroleum.mtlx.
    path = write_mtlx('<open_pbr_surface name="S" type="surfaceshader">\n'
                      f'  <input name="subsurface_radius_scale" type="color3" value="{scale}" />\n</open_pbr_surface>')
    assert {d.code for d in validate_paths([str(path)]).diagnostics} & {"OPBR301", "OPBR302"} == set()


def test_a_negative_subsurface_radius_scale_is_still_an_error(write_mtlx):
    path = write_mtlx('<open_pbr_surface name="S" type="surfaceshader">\n'
                      '  <input name="subsurface_radius_scale" type="color3" value="1, -0.5, 0.25" />\n</open_pbr_surface>')
    assert _findings(path) == {"OPBR301": "error"}
