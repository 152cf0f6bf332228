"""The parameter search of ``openpbr convert --verify`` (translate/search.py): where the kept result still
renders visibly off, the target's own colours and weights are searched for a closer render. Judged by the
lobe evaluator at full size (verification.measure), not by the search's own 16-pixel sphere."""

from __future__ import annotations

import random

import pytest

from generated_materials import COLORSPACES, _mtlx, archetype_values
from openpbr_tools.convert import convert_file
from openpbr_tools.rules.translation import APPROXIMATED
from openpbr_tools.translate.common import Settings
from openpbr_tools.verification import measure

#: An OpenPBR metal dimmed by specular_weight: Standard Surface's and glTF's conductors still reach 1 at
#: grazing, so the mapped metal shows a bright rim the source does not have.
DIMMED_METAL = {"base_color": (0.993, 0.41, 0.81), "base_metalness": 0.772, "specular_roughness": 0.511,
                "specular_weight": 0.105}
# glTF carries a partly metallic dimmed metal by its metalness now (fit_metal.split_metal: 0.35 mean CIEDE2000
# before any search); a whole metal keeps glTF's rim at 1 whatever its colour, which only the search trades
DIMMED_WHOLE_METAL = dict(DIMMED_METAL, base_metalness=1.0, specular_weight=0.02)


def _convert(tmp_path, materials, target, suffix, space="lin_displayp3", search=True):
    path = tmp_path / f"{space}.mtlx"
    path.write_text(_mtlx("open_pbr_surface", space, materials), encoding="utf-8")
    output = tmp_path / f"out_{'search' if search else 'plain'}.{suffix}"
    return convert_file(str(path), str(output), target, Settings(fit_films=search, search=search))


@pytest.mark.parametrize("target, suffix, metal", [("standard_surface", "mtlx", DIMMED_METAL),
                                                   (None, "gltf", DIMMED_WHOLE_METAL)])
def test_a_dimmed_metal_is_searched_closer_and_every_moved_input_has_a_note(tmp_path, target, suffix, metal):
    plain = {s.name: d.mean for s, d in measure(_convert(tmp_path, [metal], target, suffix, search=False))}
    conversion = _convert(tmp_path, [metal], target, suffix)
    searched = {s.name: d.mean for s, d in measure(conversion)}
    assert plain["S0"] > 2.3
    assert searched["S0"] < plain["S0"] - 0.25
    notes = [d for d in conversion.diagnostics if d.code == APPROXIMATED.code and " searched " in d.message]
    result = conversion.pairs[0][1]
    moved = {d.message.split(" searched")[0].split()[-1] for d in notes}
    assert moved and moved <= set(result.inputs)
    for name in moved:  # the note states the value the output holds
        value = result.inputs[name].value.value
        shown = f"{value:.4g}" if isinstance(value, float) else "(" + ", ".join(f"{v:.4g}" for v in value) + ")"
        assert any(f"{name} searched" in d.message and f"to {shown}" in d.message for d in notes), name


@pytest.mark.parametrize("target, suffix, space", [("standard_surface", "mtlx", COLORSPACES[0]), (None, "gltf", COLORSPACES[1]),
                                                   ("standard_surface", "mtlx", COLORSPACES[2])])
def test_the_search_never_makes_a_material_measurably_worse(tmp_path, target, suffix, space):
    rng = random.Random(f"search/never-worse/{space}")
    materials = [archetype_values(rng)[1] for _ in range(16)]
    plain = {s.name: d.mean for s, d in measure(_convert(tmp_path, materials, target, suffix, space, search=False))}
    searched = {s.name: d.mean for s, d in measure(_convert(tmp_path, materials, target, suffix, space))}
    worse = {name: (plain[name], searched[name]) for name in plain if searched[name] > plain[name] + 0.3}
    assert not worse
    assert any(searched[name] < plain[name] - 0.25 for name in plain)  # the sample has materials the search moves
    assert sum(searched.values()) < sum(plain.values())


def test_the_default_conversion_does_not_search_nor_does_a_preview(tmp_path):
    conversion = _convert(tmp_path, [DIMMED_METAL], "standard_surface", "mtlx", search=False)
    assert not [d for d in conversion.diagnostics if " searched " in d.message]
    # UsdPreviewSurface's searched results did not look closer in MaterialX's GLSL (translate/search.py)
    conversion = _convert(tmp_path, [DIMMED_METAL], "UsdPreviewSurface", "mtlx")
    assert not [d for d in conversion.diagnostics if " searched " in d.message]
