"""Open bounds: a value on an excluded bound is out of range (OPBR301, an error). The OpenPBR
specification gives the IORs and the Abbe number the range (0, inf); KHR_materials_volume's schema
gives attenuationDistance exclusiveMinimum 0."""

from __future__ import annotations

import json

import pytest

from openpbr_tools.validate import validate_paths

OPEN_AT_ZERO = ("specular_ior", "coat_ior", "thin_film_ior", "transmission_dispersion_abbe_number")


def _codes(path) -> set[str]:
    return {d.code for d in validate_paths([str(path)]).diagnostics if str(d.severity) == "error"}


@pytest.mark.parametrize("name", OPEN_AT_ZERO)
def test_zero_is_outside_an_open_range(write_mtlx, name):
    path = write_mtlx(f'<open_pbr_surface name="S" type="surfaceshader">\n'
                      f'  <input name="{name}" type="float" value="0" />\n</open_pbr_surface>')
    assert "OPBR301" in _codes(path)


@pytest.mark.parametrize("name", OPEN_AT_ZERO)
def test_just_above_zero_is_inside(write_mtlx, name):
    path = write_mtlx(f'<open_pbr_surface name="S" type="surfaceshader">\n'
                      f'  <input name="{name}" type="float" value="0.001" />\n</open_pbr_surface>')
    assert "OPBR301" not in _codes(path)


@pytest.mark.parametrize("distance, out", [(0.0, True), (0.001, False)])
def test_gltf_attenuation_distance_has_an_exclusive_minimum(tmp_path, distance, out):
    path = tmp_path / "m.gltf"
    path.write_text(json.dumps({
        "asset": {"version": "2.0"},
        "extensionsUsed": ["KHR_materials_transmission", "KHR_materials_volume"],
        "materials": [{"name": "M", "extensions": {
            "KHR_materials_transmission": {"transmissionFactor": 1.0},
            "KHR_materials_volume": {"thicknessFactor": 1.0, "attenuationDistance": distance}}}]}), encoding="utf-8")
    assert ("OPBR301" in _codes(path)) is out


@pytest.mark.parametrize("root, reported", [
    ('<materialx colorspace="lin_rec709">', "OPBR005"),
    ('<materialx version="1.38" colorspace="lin_rec709">', "OPBR012"),  # MaterialX's upgrade changes nothing else
    ('<materialx version="1.39" colorspace="lin_rec709">', None),
])
def test_a_document_without_a_version_or_older_than_open_pbr_is_reported(tmp_path, root, reported):
    path = tmp_path / "m.mtlx"
    path.write_text(f'<?xml version="1.0"?>\n{root}\n  <open_pbr_surface name="S" type="surfaceshader" />\n'
                    '  <surfacematerial name="M" type="material">\n'
                    '    <input name="surfaceshader" type="surfaceshader" nodename="S" />\n  </surfacematerial>\n'
                    '</materialx>\n', encoding="utf-8")
    found = {(d.code, str(d.severity)) for d in validate_paths([str(path)]).diagnostics if d.code in ("OPBR005", "OPBR012")}
    assert found == ({(reported, "warning" if reported == "OPBR005" else "info")} if reported else set())
