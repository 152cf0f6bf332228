"""Unit and plausibility data against their sources."""

from __future__ import annotations

import os
import re

import numpy as np
import pytest

from openpbr_tools.resources import load_json


def test_distance_units_match_materialx_stdlib():
    import MaterialX as mx

    path = os.path.join(os.path.dirname(mx.__file__), "libraries", "stdlib", "stdlib_defs.mtlx")
    with open(path, encoding="utf-8") as handle:
        text = handle.read()
    block = text[text.index('unittype="distance"'):text.index("</unitdef>", text.index('unittype="distance"'))]
    stdlib = {name: float(scale) for name, scale in re.findall(r'<unit name="(\w+)" scale="([0-9.e-]+)"', block)}
    assert load_json("units.json")["distance"] == pytest.approx(stdlib)


def test_usd_default_meters_per_unit_is_usd_cores():
    from pxr import Usd, UsdGeom

    stage = Usd.Stage.CreateInMemory()
    assert UsdGeom.GetStageMetersPerUnit(stage) == load_json("units.json")["usd_default_meters_per_unit"]


def test_plausibility_thresholds_are_srgb_decodings_of_filaments_code_values():
    from openpbr_tools.colorspaces import to_lin_rec709

    limits = load_json("plausibility.json")["thresholds"]
    for name in ("dielectric_base_color_min", "dielectric_base_color_max", "metal_base_color_min"):
        encoded = limits[f"{name}_srgb"] / 255.0
        assert to_lin_rec709(np.array([encoded] * 3), "srgb_texture")[0] == pytest.approx(limits[f"{name}_linear"], abs=1e-6)


def test_luminance_weights_are_the_y_row_of_rec709():
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        import colour
    row = colour.RGB_COLOURSPACES["sRGB"].matrix_RGB_to_XYZ[1]
    assert load_json("plausibility.json")["luminance_weights_lin_rec709"] == pytest.approx(row, abs=1e-4)
