"""The same material authored in linear Rec.709, ACEScg or linear Display P3 converts to the same
look (issue: an ACEScg copper was 40 CIEDE2000 off where its Rec.709 twin was under 2). Each source
is written in linear Rec.709, re-expressed exactly in the other spaces (MaterialX's cmlib matrices),
converted to every target, and judged by the lobe evaluator against its own source: the three
results agree within 0.5 mean CIEDE2000."""

from __future__ import annotations

import pytest

from openpbr_tools import colorspaces
from openpbr_tools.convert import convert_file
from openpbr_tools.evaluate.verify import compare_materials
from openpbr_tools.translate.common import Settings
from openpbr_tools.values import format_value

# name: (inputs in linear Rec.709); colours are the keys ending in _color
MATERIALS = {
    "copper_f82": {"base_color": (0.955, 0.638, 0.538), "base_metalness": 1.0, "specular_color": (0.98, 0.75, 0.65),
                   "specular_roughness": 0.25},
    "gold_edge_above_one": {"base_color": (1.0, 0.766, 0.336), "base_metalness": 1.0,
                            "specular_color": (0.99, 1.02, 0.98), "specular_roughness": 0.15},
    "red_coated_plastic": {"base_color": (0.7, 0.05, 0.04), "specular_roughness": 0.4, "coat_weight": 1.0,
                           "coat_roughness": 0.05, "coat_color": (0.9, 0.85, 0.8)},
    "green_glass": {"transmission_weight": 1.0, "transmission_color": (0.3, 0.8, 0.35), "specular_roughness": 0.05},
    "blue_fabric": {"base_color": (0.05, 0.1, 0.6), "fuzz_weight": 1.0, "fuzz_color": (0.4, 0.5, 0.9),
                    "specular_roughness": 0.6},
    "emitter": {"emission_luminance": 500.0, "emission_color": (1.0, 0.55, 0.2), "base_color": (0.2, 0.2, 0.2)},
}
SPACES = ("lin_rec709", "acescg", "lin_displayp3")
TARGETS = {"standard_surface.mtlx": "standard_surface", "gltf": None, "preview.mtlx": "UsdPreviewSurface"}


def _document(inputs: dict, space: str) -> str:
    """``inputs`` (linear Rec.709) re-expressed in ``space``: every color3 input converted as MaterialX's
    colour management would read it back, the rest written as they are."""
    from openpbr_tools import tables

    table = tables.table("open_pbr_surface")
    lines = []
    for name, value in inputs.items():
        kind = table[name].type
        if kind == "color3":
            value = tuple(float(c) for c in colorspaces.from_lin_rec709(value, space))
        lines.append(f'    <input name="{name}" type="{kind}" value="{format_value(value, kind)}" />')
    body = "\n".join(lines)
    return (f'<?xml version="1.0"?>\n<materialx version="1.39" colorspace="{space}">\n'
            f'  <open_pbr_surface name="S" type="surfaceshader" version="1.1.1">\n{body}\n  </open_pbr_surface>\n'
            '  <surfacematerial name="M" type="material">\n'
            '    <input name="surfaceshader" type="surfaceshader" nodename="S" />\n  </surfacematerial>\n</materialx>\n')


@pytest.mark.parametrize("target", sorted(TARGETS))
@pytest.mark.parametrize("name", sorted(MATERIALS))
def test_the_authoring_colour_space_does_not_change_the_result(tmp_path, name, target):
    means = {}
    for space in SPACES:
        source = tmp_path / f"{space}.mtlx"
        source.write_text(_document(MATERIALS[name], space))
        conversion = convert_file(str(source), str(tmp_path / f"{space}.{target}"), TARGETS[target], Settings())
        ((original, result),) = conversion.pairs
        means[space] = compare_materials(original, result).preview.mean
    spread = max(means.values()) - min(means.values())
    assert spread <= 0.5, means


@pytest.mark.parametrize("target", sorted(TARGETS))
def test_generated_materials_do_not_depend_on_the_authoring_space(tmp_path, target):
    """The same check on seeded materials that sweep every parameter (tests/generated_materials.py),
    with the candidate search on (its choice must not flip with the document's space by more than the
    0.5 the issue allows)."""
    import random

    from generated_materials import material_values

    rng = random.Random(41)
    spreads = []
    for index in range(8):
        values = material_values("open_pbr_surface", rng)
        means = {}
        for space in SPACES:
            source = tmp_path / f"{index}_{space}.mtlx"
            source.write_text(_document(values, space))
            conversion = convert_file(str(source), str(tmp_path / f"{index}_{space}.{target}"), TARGETS[target],
                                      Settings())
            ((original, result),) = conversion.pairs
            means[space] = compare_materials(original, result).preview.mean
        spreads.append((max(means.values()) - min(means.values()), index, means))
    assert max(spreads)[0] <= 0.5, max(spreads)
