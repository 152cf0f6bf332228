"""Colour-space data against its sources: MaterialX's cmlib, usd-core's Gf, colour-science."""

from __future__ import annotations

import os
import re

import numpy as np
import pytest

from openpbr_tools import colorspaces
from openpbr_tools.resources import load_json


def test_materialx_names_are_exactly_those_cmlib_converts_plus_lin_rec709_and_none():
    import MaterialX as mx

    folder = os.path.join(os.path.dirname(mx.__file__), "libraries", "cmlib", "cmlib_defs.mtlx")
    with open(folder, encoding="utf-8") as handle:
        text = handle.read()
    converted = set(re.findall(r'name="ND_([a-z0-9_]+)_to_lin_rec709_color3"', text))
    assert colorspaces.materialx_names() == frozenset(converted | {"lin_rec709", "none"})


def test_usd_names_are_usd_cores_colorspace_names():
    from pxr import Gf

    names = {getattr(Gf.ColorSpaceNames, n) for n in dir(Gf.ColorSpaceNames) if not n.startswith("_")}
    assert set(load_json("colorspaces.json")["usd"]["names"]) == names


def test_usd_equivalents_are_real_usd_names():
    usd = set(load_json("colorspaces.json")["usd"]["names"])
    for name, spec in load_json("colorspaces.json")["materialx"].items():
        assert spec["usd"] is None or spec["usd"] in usd, name


def test_srgb_texture_decodes_with_the_srgb_curve():
    # IEC 61966-2-1: 0.5 encoded -> ((0.5 + 0.055) / 1.055) ** 2.4 = 0.21404
    assert colorspaces.to_lin_rec709([0.5, 0.5, 0.5], "srgb_texture") == pytest.approx([0.214041] * 3, abs=1e-6)


def test_acescg_primaries_map_to_rec709_with_white_preserved():
    white = colorspaces.to_lin_rec709([1.0, 1.0, 1.0], "acescg")
    assert white == pytest.approx([1.0, 1.0, 1.0], abs=1e-9)
    red = colorspaces.to_lin_rec709([1.0, 0.0, 0.0], "acescg")
    assert red[0] > 1.0 and red[1] < 0.0  # AP1 red lies outside the Rec.709 gamut


def test_gamma_22_is_a_pure_power():
    assert colorspaces.to_lin_rec709([0.5, 0.25, 1.0], "g22_rec709") == pytest.approx(np.array([0.5, 0.25, 1.0]) ** 2.2)


@pytest.mark.parametrize("name", sorted(colorspaces.materialx_names()))
def test_conversion_round_trips(name):
    rgb = np.array([0.18, 0.5, 0.9])
    # matrices derived from the primaries invert each other exactly (the published sRGB ones do not)
    assert colorspaces.from_lin_rec709(colorspaces.to_lin_rec709(rgb, name), name) == pytest.approx(rgb, abs=1e-9)


def test_every_vendor_alias_points_at_a_materialx_name():
    for alias, target in load_json("colorspaces.json")["vendor_aliases"].items():
        assert target in colorspaces.materialx_names(), alias


def _cmlib_matrices() -> dict[str, np.ndarray]:
    """MaterialX's own linear conversions: the matrix33 constant of every NG_<space>_to_lin_rec709_color3."""
    import MaterialX as mx

    document = mx.createDocument()
    mx.loadLibraries(mx.getDefaultDataLibraryFolders(), mx.getDefaultDataSearchPath(), document)
    found = {}
    for graph in document.getNodeGraphs():
        name = graph.getName()
        if name.startswith("NG_") and name.endswith("_to_lin_rec709_color3"):
            for node in graph.getNodes():
                if node.getType() == "matrix33" and node.getInput("value") is not None:
                    values = [float(v) for v in node.getInput("value").getValueString().split(",")]
                    found[name[3:-len("_to_lin_rec709_color3")]] = np.array(values).reshape(3, 3)
    return found


def test_linear_conversions_are_materialx_cmlib_matrices():
    # MaterialX's transformmatrix multiplies a row vector: out = in @ M, so row i is the image of e_i.
    matrices = _cmlib_matrices()
    linear = [n for n in colorspaces.materialx_names() if n in matrices]
    assert {"acescg", "lin_displayp3", "lin_adobergb"} <= set(linear)
    for name in linear:
        ours = np.array([colorspaces.to_lin_rec709(e, name) for e in np.eye(3)])
        # acescg agrees to ~1e-12, lin_adobergb to its 8 printed decimals; MaterialX's Display P3 matrix was derived from a
        # D65 white given to more digits than colour-science's (0.3127, 0.329): 1.6e-5 apart.
        assert ours == pytest.approx(matrices[name], abs=1e-8 if "displayp3" not in name else 2e-5), name


@pytest.mark.parametrize("name", ["acescg", "lin_displayp3", "lin_adobergb"])
def test_white_stays_white(name):
    assert colorspaces.to_lin_rec709([1.0, 1.0, 1.0], name) == pytest.approx([1.0, 1.0, 1.0], abs=1e-9)
