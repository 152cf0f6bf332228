"""The candidate search judged by MaterialX's GLSL renderer under a structured environment
(tests/glsupport.studio_environment: a striped sky, a dark ground, two bright windows, beside the rig's key light),
which shows how sharply a surface reflects and refracts, what the evaluator's uniform environment cannot.

    xvfb-run -a python tests/benchmarks/bench_glsl_environment.py [--count 90] [--seed 29] [--corpus archetypes] [--verify]

A seeded sample of generated OpenPBR materials (tests/generated_materials.py; lin_rec709, acescg, lin_displayp3
documents) is converted to each target by the default path with the graphs' result keeping the mapping's
roughnesses where it wins (candidates.KEEP_MAPPING_SHARPNESS, the default), by the same path without that
(the graphs' result kept whole, as before), by the mapping alone and by MaterialX's chain; the source and the
four results are rendered on the lit sphere under the studio environment and compared (mean CIEDE2000).

With ``--verify``, also ``openpbr convert --verify``'s result (the parameter search, translate/search.py), its
roughnesses free as they are and held at the default's. Prints, per target: the mean and the share under 2.3 of each, how many materials the two choices differ on and
by how much, and how many each leaves worse than the chain by more than 0.5. Materials with a geometry_opacity
below 1 are left out (no blending in the test harness), as in bench_glsl_sample.py.
"""

from __future__ import annotations

import argparse
import os
import sys

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))

from glsupport import comparison_mask, materialx_renderer, studio_environment  # noqa: E402
from openpbr_tools.evaluate.difference import compare_images  # noqa: E402
from openpbr_tools.evaluate.preview import Rig  # noqa: E402
from openpbr_tools.rules import Context  # noqa: E402
from openpbr_tools.translate import anchor, candidates, search  # noqa: E402
from openpbr_tools.translate.common import Settings  # noqa: E402
from openpbr_tools.translate.convert import convert  # noqa: E402
from openpbr_tools.translate.judging import SHARPNESS  # noqa: E402
from bench_glsl_sample import generated_sample, values_of  # noqa: E402

TARGETS = ("standard_surface", "gltf_pbr", "UsdPreviewSurface")
COLUMNS = ("kept roughness", "graphs whole", "mapping", "chain")
VERIFY_COLUMNS = ("--verify", "--verify, roughness fixed")


def searched(material, target: str, free_sharpness: bool):
    """``openpbr convert --verify``'s result, its search free to move roughnesses (as it is) or not."""
    kept = dict(search.FREE)
    if not free_sharpness:
        search.FREE = {model: (colours, tuple(n for n in floats if n not in SHARPNESS.get(model, ())))
                       for model, (colours, floats) in kept.items()}
    try:
        settings = Settings(context=Context(), fit_films=True, search=True)
        return candidates.choose(material, convert(material, target, settings), target, settings).material
    finally:
        search.FREE = kept


def results(material, target: str, verify: bool = False) -> list:
    """The four results of :data:`COLUMNS` for ``material`` to ``target`` (None where the chain has none), then
    with ``verify`` those of :data:`VERIFY_COLUMNS`."""
    out = []
    for keep in (True, False):
        candidates.KEEP_MAPPING_SHARPNESS = keep
        try:
            settings = Settings(context=Context())
            out.append(candidates.choose(material, convert(material, target, settings), target, settings).material)
        finally:
            candidates.KEEP_MAPPING_SHARPNESS = True
    out.append(convert(material, target, Settings(context=Context(), candidates=False)).material)
    out.append(anchor.graph_candidate(material, target))
    if verify:
        out += [searched(material, target, True), searched(material, target, False)]
    return out


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--count", type=int, default=90)
    parser.add_argument("--seed", type=int, default=29)
    parser.add_argument("--corpus", choices=("all-lobes", "archetypes"), default="archetypes")
    parser.add_argument("--verify", action="store_true",
                        help="also judge --verify's parameter search, with its roughnesses free (as it is) and fixed")
    arguments = parser.parse_args()
    rig = Rig(size=64)
    renderer = materialx_renderer(rig)
    renderer.use_environment(studio_environment())
    materials = generated_sample(arguments.corpus, arguments.seed, arguments.count)
    materials = [(s, m) for s, m in materials if values_of(m)["geometry_opacity"] >= 1.0]
    print(f"{len(materials)} materials judged under the studio environment")
    rows = {target: [] for target in TARGETS}
    for space, material in materials:
        reference = renderer.render("open_pbr_surface", values_of(material))
        mask = comparison_mask(rig) & np.isfinite(reference).all(axis=-1)
        for target in TARGETS:
            found = results(material, target, arguments.verify)
            if found[-1] is None:
                continue
            deltas = [compare_images(reference, renderer.render(target, values_of(m)), mask, rig.white()).mean
                      for m in found]
            rows[target].append((deltas, f"{space}:{material.name}"))
    for target in TARGETS:
        table = np.array([deltas for deltas, _ in rows[target]])
        if not len(table):
            continue
        print(f"{target}: {len(table)} materials")
        for column, name in enumerate(COLUMNS):
            print(f"    {name:15s} mean {table[:, column].mean():6.2f}  under 2.3 {np.mean(table[:, column] < 2.3):4.0%}"
                  + (f"  worse than the chain by >0.5: {int(np.sum(table[:, column] - table[:, 3] > 0.5))}"
                     if column < 3 else ""))
        for column, name in enumerate(VERIFY_COLUMNS if arguments.verify else (), start=len(COLUMNS)):
            moved = np.abs(table[:, column] - table[:, 0]) > 1e-9
            print(f"    {name:15s} mean {table[:, column].mean():6.2f}  under 2.3 {np.mean(table[:, column] < 2.3):4.0%}"
                  f"  moved {int(moved.sum())}: better than the default by >0.5 {int(np.sum(table[:, column] - table[:, 0] < -0.5))}"
                  f", worse by >0.5 {int(np.sum(table[:, column] - table[:, 0] > 0.5))}")
        change = table[:, 0] - table[:, 1]
        moved = np.abs(change) > 1e-9
        print(f"    kept roughness vs graphs whole: {int(moved.sum())} differ; better by >0.5: "
              f"{int(np.sum(change < -0.5))}, worse by >0.5: {int(np.sum(change > 0.5))}"
              + (f" (best {change.min():+.2f}, worst {change.max():+.2f})" if moved.any() else ""))
        for index in np.argsort(change)[:3]:
            if moved[index]:
                print(f"      {change[index]:+6.2f}  {rows[target][index][1]}  "
                      + "  ".join(f"{n} {d:.2f}" for n, d in zip(COLUMNS, rows[target][index][0])))


if __name__ == "__main__":
    main()
