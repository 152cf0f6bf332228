"""glTF values are judged against glTF's own schemas, not OpenPBR's soft ranges: values the
extension schemas allow and Khronos' sample models use are not warned (OPBR302)."""

from __future__ import annotations

import json

import pytest

from openpbr_tools.validate import validate_paths


def _gltf(tmp_path, extensions: dict) -> str:
    document = {"asset": {"version": "2.0"}, "extensionsUsed": sorted(extensions),
                "materials": [{"name": "M", "extensions": extensions}]}
    path = tmp_path / "m.gltf"
    path.write_text(json.dumps(document), encoding="utf-8")
    return str(path)


@pytest.mark.parametrize("extensions", [
    {"KHR_materials_dispersion": {"dispersion": 5.0},  # DispersionTest: Abbe number 4
     "KHR_materials_volume": {"thicknessFactor": 1.0}, "KHR_materials_transmission": {"transmissionFactor": 1.0}},
    {"KHR_materials_specular": {"specularColorFactor": [10.0, 10.0, 10.0]}},  # SpecularTest
    {"KHR_materials_iridescence": {"iridescenceFactor": 1.0, "iridescenceThicknessMinimum": 600,
                                   "iridescenceThicknessMaximum": 1200}},  # IridescenceLamp
], ids=["dispersion-5", "specular-color-10", "iridescence-600-1200-nm"])
def test_values_the_extension_schemas_allow_are_not_warned(tmp_path, extensions):
    codes = {d.code for d in validate_paths([_gltf(tmp_path, extensions)]).diagnostics}
    assert "OPBR302" not in codes and "OPBR301" not in codes


def test_a_negative_dispersion_is_still_an_error(tmp_path):
    path = _gltf(tmp_path, {"KHR_materials_dispersion": {"dispersion": -1.0},
                            "KHR_materials_volume": {"thicknessFactor": 1.0},
                            "KHR_materials_transmission": {"transmissionFactor": 1.0}})
    assert "OPBR301" in {d.code for d in validate_paths([path]).diagnostics}
