"""Resolving a Material into evaluator inputs: authored constants, table defaults, textures,
connections and colour spaces."""

import json
from pathlib import Path

import numpy as np
import pytest

from openpbr_tools.evaluate.parameters import defaults, resolve, with_values
from openpbr_tools.model import Connection, Constant, Input, Location, Material, Texture

LOC = Location("memory.mtlx")
SCHEMAS = Path(__file__).resolve().parents[1] / "schemas" / "models"


def _material(model, inputs, colorspace=None):
    return Material("m", model, LOC, {name: Input(name, kind, value, LOC) for name, kind, value in inputs}, colorspace=colorspace)


@pytest.mark.parametrize("model,version", [
    ("open_pbr_surface", "1.1.1"), ("standard_surface", "1.0.1"), ("gltf_pbr", "2.0.1"), ("UsdPreviewSurface", "2.6"),
])
def test_unset_parameters_take_the_table_defaults(model, version):
    table = json.loads((SCHEMAS / model / f"{version}.json").read_text())["parameters"]
    values = defaults(model).values
    for name, entry in table.items():
        if entry["default"] is None or entry["role"] in ("normal", "tangent", "filename", "string"):
            continue
        np.testing.assert_array_equal(np.asarray(values[name], dtype=float), np.asarray(entry["default"], dtype=float), err_msg=name)


def test_authored_constants_override_defaults():
    material = _material("open_pbr_surface", [("base_metalness", "float", Constant(0.7)), ("base_color", "color3", Constant((0.1, 0.2, 0.3)))])
    values = resolve(material).values
    assert values["base_metalness"] == pytest.approx(0.7)
    np.testing.assert_allclose(values["base_color"], [0.1, 0.2, 0.3])


def test_srgb_colours_are_decoded_to_linear_rec709():
    material = _material("open_pbr_surface", [("base_color", "color3", Constant((0.5, 0.04, 1.0)))], colorspace="srgb_texture")
    encoded = np.array([0.5, 0.04, 1.0])
    # IEC 61966-2-1 decoding, written out.
    expected = np.where(encoded <= 0.04045, encoded / 12.92, ((encoded + 0.055) / 1.055) ** 2.4)
    np.testing.assert_allclose(resolve(material).values["base_color"], expected, rtol=1e-6)


def test_data_parameters_are_not_colour_converted():
    material = _material("open_pbr_surface", [("specular_roughness", "float", Constant(0.5))], colorspace="srgb_texture")
    assert resolve(material).values["specular_roughness"] == pytest.approx(0.5)


def test_textured_inputs_use_their_fallback_and_are_listed():
    texture = Texture("base.png", image_type="color3", fallback=(0.2, 0.4, 0.6))
    material = _material("open_pbr_surface", [("base_color", "color3", texture), ("specular_roughness", "float", Texture("r.png", "float"))])
    resolved = resolve(material)
    np.testing.assert_allclose(resolved.values["base_color"], [0.2, 0.4, 0.6])
    assert resolved.values["specular_roughness"] == pytest.approx(defaults("open_pbr_surface").values["specular_roughness"])
    assert sorted(resolved.textured) == ["base_color", "specular_roughness"]
    assert "base_color: textured (not evaluated)" in resolved.notes()


def test_connections_and_unknown_names_are_reported_not_evaluated():
    material = _material("open_pbr_surface", [("coat_weight", "float", Connection("NG_x")), ("base_roughness", "float", Constant(0.3))])
    resolved = resolve(material)
    assert resolved.not_evaluated == ["coat_weight"]
    assert resolved.ignored == ["base_roughness"]
    assert resolved.values["coat_weight"] == defaults("open_pbr_surface").values["coat_weight"]


def test_with_values_rejects_unknown_parameters():
    with pytest.raises(KeyError):
        with_values("gltf_pbr", {"base_colour": [1, 0, 0]})
