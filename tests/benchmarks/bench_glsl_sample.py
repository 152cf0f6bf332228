"""The candidate search judged by MaterialX's own GLSL renderer (an independent judge, not the
evaluator that made the choice): a seeded sample of generated OpenPBR materials
(tests/generated_materials.py, lin_rec709 / acescg / lin_displayp3 documents), each converted by
``openpbr convert``'s default path (mapping + candidate search) and by MaterialX's chain (its
translation graphs), the source and both results rendered with MaterialX's GLSL shaders on the
lit sphere (Xvfb + Mesa; tests/glsupport.py), mean CIEDE2000 against the source's render.

    python tests/benchmarks/bench_glsl_sample.py [--count 100] [--seed 23] [--corpus archetypes] [--verify]

``--corpus archetypes`` samples the kinds artists author (generated_materials.KINDS) instead of
materials with every lobe on. The toolkit's result is also judged without the appearance fit
(translate/appearance.py), which is chosen on the evaluator: the "fit" column says whether GLSL
agrees that the fit helps.

Per target: medians, share under 2.3, how many the toolkit leaves worse than the chain by more than
0.5 and the worst gap (#13: none beyond 0.5), the same count where neither judge is known wrong (_judges_differ), and the
three worst materials. Materials with a
geometry_opacity below 1 are left out and counted: the test harness draws without blending, so GLSL
cannot show a cut-out (measured: every gap above 2 on the first run was one). MaterialX's GLSL
gltf_pbr does not render KHR_materials_volume attenuation, so tinted thick glass is judged without
its volume on the glTF side (the evaluator, which integrates it, is the reference for volumes).
"""

from __future__ import annotations

import argparse
import os
import statistics
import sys
import tempfile

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))

from generated_materials import COLORSPACES, archetype_document, document  # noqa: E402
from glsupport import comparison_mask, materialx_renderer, uniforms  # noqa: E402
from openpbr_tools.evaluate.difference import compare_images  # noqa: E402
from openpbr_tools.evaluate.preview import Rig  # noqa: E402
from openpbr_tools.io import read_asset  # noqa: E402
from openpbr_tools.rules import Context  # noqa: E402
from openpbr_tools.translate import anchor, appearance, candidates  # noqa: E402
from openpbr_tools.translate.judging import as_written  # noqa: E402
from openpbr_tools.translate.common import Settings  # noqa: E402
from openpbr_tools.translate.convert import convert  # noqa: E402

TARGETS = ("standard_surface", "gltf_pbr", "UsdPreviewSurface")


def values_of(material) -> dict:
    """Linear Rec.709 numbers of every parameter (the document's colour space converted, defaults
    filled), as the material's file holds them (judging.as_written: a glTF writer clamps wide-gamut
    colours, for the chain's result as for the toolkit's)."""
    return uniforms(as_written(material))


def generated_sample(corpus: str, seed: int, count: int) -> list:
    """(document colour space, material) of ``count`` generated OpenPBR materials, a third in each of the
    colour spaces (generated_materials.COLORSPACES)."""
    materials = []
    per_space = -(-count // len(COLORSPACES))
    for space in COLORSPACES:
        path = os.path.join(tempfile.mkdtemp(prefix="openpbr-glsl-"), f"{space}.mtlx")
        with open(path, "w", encoding="utf-8") as handle:
            handle.write(archetype_document(space, seed, per_space)[0] if corpus == "archetypes"
                         else document("open_pbr_surface", space, seed, per_space))
        materials += [(space, m) for m in read_asset(path).materials]
    return materials[:count]


def _judges_differ(material) -> str | None:
    """Why one judge is known wrong on ``material``, or None: the evaluator where appearance.untrusted says so
    (an IOR below 1, a film on a metal or much denser than its base), MaterialX 1.39.5's GLSL on a thin wall
    with subsurface (it applies subsurface_color twice: tests/test_evaluate_materialx_gl.py)."""
    why = appearance.untrusted(material)
    if why is not None:
        return f"evaluator: {why}"
    values = values_of(material)
    if values.get("geometry_thin_walled") and values.get("subsurface_weight", 0.0) > 0.0:
        return "MaterialX GLSL: thin-walled subsurface"
    return None


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--count", type=int, default=100)
    parser.add_argument("--seed", type=int, default=23)
    parser.add_argument("--corpus", choices=("all-lobes", "archetypes"), default="all-lobes")
    parser.add_argument("--verify", action="store_true",
                        help="also judge --verify's parameter search (translate/search.py) against the default result")
    arguments = parser.parse_args()
    rig = Rig(size=64)
    renderer = materialx_renderer(rig)
    materials = generated_sample(arguments.corpus, arguments.seed, arguments.count)
    cut_out = [m for _, m in materials if values_of(m)["geometry_opacity"] < 1.0]
    materials = [(space, m) for space, m in materials if values_of(m)["geometry_opacity"] >= 1.0]
    print(f"{len(materials)} materials judged; {len(cut_out)} with geometry_opacity < 1 left out (no blending in GL)")
    rows = {target: [] for target in TARGETS}
    for space, material in materials:
        reference = renderer.render("open_pbr_surface", values_of(material))
        mask = comparison_mask(rig) & np.isfinite(reference).all(axis=-1)
        for target in TARGETS:
            settings = Settings(context=Context())
            ours = candidates.choose(material, convert(material, target, settings), target, settings).material
            fit_from, appearance.FIT_FROM = appearance.FIT_FROM, float("inf")
            try:
                unfitted = candidates.choose(material, convert(material, target, settings), target, settings).material
            finally:
                appearance.FIT_FROM = fit_from
            chain = anchor.graph_candidate(material, target)
            if chain is None:
                continue
            judged = [ours, chain, unfitted]
            if arguments.verify:
                searching = Settings(context=Context(), fit_films=True, search=True)
                judged.append(candidates.choose(material, convert(material, target, searching), target, searching).material)
            deltas = [compare_images(reference, renderer.render(target, values_of(m)), mask, rig.white()).mean
                      for m in judged]
            rows[target].append((*deltas[:3], f"{space}:{material.name}", *deltas[3:], _judges_differ(material)))
    for target in TARGETS:
        found = rows[target]
        ours, chain = np.array([r[0] for r in found]), np.array([r[1] for r in found])
        gap = ours - chain
        unfitted = np.array([r[2] for r in found])
        fitted = np.abs(ours - unfitted) > 1e-9
        print(f"{target}: {len(found)} materials; median toolkit {statistics.median(ours):.2f} / chain "
              f"{statistics.median(chain):.2f}; under 2.3: toolkit {np.mean(ours < 2.3):.0%}, chain {np.mean(chain < 2.3):.0%}; "
              f"toolkit worse than the chain by >0.5: {int(np.sum(gap > 0.5))} (worst {gap.max():+.2f}); "
              f"better by >0.5: {int(np.sum(gap < -0.5))}")
        known = [r[-1] for r in found]
        trusted_gap = [g for g, why in zip(gap, known) if why is None]
        print(f"    where neither judge is known wrong ({len(trusted_gap)} materials): worse than the chain by >0.5: "
              f"{sum(g > 0.5 for g in trusted_gap)}" + (f" (worst {max(trusted_gap):+.2f})" if trusted_gap else ""))
        if fitted.any():
            change = ours[fitted] - unfitted[fitted]
            print(f"    fit: {int(fitted.sum())} materials fitted; GLSL mean {unfitted[fitted].mean():.2f} -> "
                  f"{ours[fitted].mean():.2f}; better by >0.5: {int(np.sum(change < -0.5))}, worse by >0.5: "
                  f"{int(np.sum(change > 0.5))} (worst {change.max():+.2f})")
        if arguments.verify:
            searched = np.array([r[4] for r in found])
            moved = np.abs(searched - ours) > 1e-9
            if moved.any():
                change = searched[moved] - ours[moved]
                print(f"    --verify's search: {int(moved.sum())} materials changed; GLSL mean {ours[moved].mean():.2f} -> "
                      f"{searched[moved].mean():.2f}; under 2.3: {np.mean(ours < 2.3):.0%} -> {np.mean(searched < 2.3):.0%}; "
                      f"better by >0.5: {int(np.sum(change < -0.5))}, worse by >0.5: {int(np.sum(change > 0.5))} "
                      f"(worst {change.max():+.2f})")
        for row in sorted(found, key=lambda r: r[0] - r[1])[-3:]:
            print(f"    gap {row[0] - row[1]:+6.2f}  toolkit {row[0]:6.2f}  chain {row[1]:6.2f}  {row[3]}"
                  + (f"  ({row[-1]})" if row[-1] else ""))


if __name__ == "__main__":
    main()
