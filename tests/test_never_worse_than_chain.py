"""Never worse than the anchor (#13): on seeded materials that sweep every OpenPBR parameter over
its whole range (tests/generated_materials.py) in lin_rec709, acescg and lin_displayp3 documents,
``convert``'s default result (the candidate search) for Standard Surface, glTF and UsdPreviewSurface
renders no further from the source than MaterialX's own translation chain (its graphs, as
openpbr_tools/translate/materialx_graphs.py reproduces them to 2e-5 of MaterialX's bakes) does,
beyond 0.3 mean CIEDE2000 on the evaluator's lit sphere (the graphs' result is kept only where it wins
by 0.25, so a gap up to that is by design; bench_never_worse.py: worst +0.25 of 360)."""

from __future__ import annotations

import pytest

from generated_materials import COLORSPACES, document
from openpbr_tools.evaluate.preview import Rig
from openpbr_tools.evaluate.verify import compare_materials
from openpbr_tools.io import read_asset
from openpbr_tools.rules import Context
from openpbr_tools.translate import anchor, candidates
from openpbr_tools.translate.common import Settings
from openpbr_tools.translate.convert import convert

TARGETS = ("standard_surface", "gltf_pbr", "UsdPreviewSurface")
RIG = Rig(size=48)
PER_SPACE = 8


def _against_the_graphs(materials, targets):
    """(how many conversions were compared, those the default conversion renders worse than MaterialX's
    graphs by more than 0.3 mean CIEDE2000)."""
    compared, worse = 0, []
    for material in materials:
        for target in targets:
            settings = Settings(context=Context())
            ours = candidates.choose(material, convert(material, target, settings), target, settings).material
            graph = anchor.graph_candidate(material, target)
            assert graph is not None and graph.model == target, (material.name, target)
            compared += 1
            if candidates.tangent_graph(ours):
                # a Standard Surface rotation written as MaterialX's rotated tangent, which the evaluator does not
                # render (it would judge the rotation lost, the graphs' unrotated result closer); MaterialX's GLSL
                # judged it: 0.17 mean CIEDE2000 against 8.79 for the search that dropped it (the red team's E#5)
                continue
            delta_ours = compare_materials(material, ours, RIG).preview.mean
            delta_graph = compare_materials(material, graph, RIG).preview.mean
            assert delta_ours == delta_ours and delta_graph == delta_graph  # finite: an IOR of 0 once gave NaN
            if delta_ours > delta_graph + 0.3:
                worse.append((material.name, target, round(delta_ours, 2), round(delta_graph, 2)))
    return compared, worse


@pytest.mark.parametrize("colorspace", COLORSPACES)
def test_no_material_is_worse_than_materialx_chain(tmp_path, colorspace):
    path = tmp_path / "generated.mtlx"
    path.write_text(document("open_pbr_surface", colorspace, 5, PER_SPACE))
    compared, worse = _against_the_graphs(read_asset(str(path)).materials, TARGETS)
    assert compared == PER_SPACE * len(TARGETS)
    assert not worse, worse


REVERSE_TARGETS = ("open_pbr_surface", "gltf_pbr", "UsdPreviewSurface")


@pytest.mark.parametrize("colorspace", COLORSPACES)
def test_no_standard_surface_material_is_worse_than_materialx_graphs(tmp_path, colorspace):
    """The other direction: generated Standard Surface materials to OpenPBR (MaterialX's
    standard_surface_to_open_pbr graph is the anchor) and to glTF and UsdPreviewSurface (its
    standard_surface_to_gltf_pbr / _to_usd graphs). Without the search the mapping was worse than the
    graph by more than 0.3 on 4 / 10 / 5 of 30 (up to 3.6); with the search (on by default), none
    (tests/benchmarks/bench_never_worse.py --source standard_surface: 0 of 360, worst +0.25)."""
    path = tmp_path / "generated.mtlx"
    path.write_text(document("standard_surface", colorspace, 21, 6))
    compared, worse = _against_the_graphs(read_asset(str(path)).materials, REVERSE_TARGETS)
    assert compared == 6 * len(REVERSE_TARGETS)
    assert not worse, worse
