"""Published OpenPBR and Standard Surface materials (MaterialX's and OpenPBR's examples, the measured set)
converted to each other model by ``openpbr convert``'s default path and by MaterialX's chain, both judged
by MaterialX's GLSL renderer against the source (Xvfb + Mesa; constant, fully present materials).

    python tests/benchmarks/bench_glsl_published.py [--every 3]

``--every N`` takes every N-th measured material (the set is large). Prints per target: count, medians,
shares under 2.3, how many the toolkit renders better / worse than the chain by more than 0.5, and
each one worse.
"""

from __future__ import annotations

import argparse
import glob
import os
import statistics
import sys

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, ".."))
sys.path.insert(0, HERE)

from bench_glsl_sample import values_of as _values  # noqa: E402
from glsupport import comparison_mask, materialx_renderer  # noqa: E402
from openpbr_tools.evaluate.difference import compare_images  # noqa: E402
from openpbr_tools.evaluate.preview import Rig  # noqa: E402
from openpbr_tools.io import read_asset  # noqa: E402
from openpbr_tools.rules import Context  # noqa: E402
from openpbr_tools.translate import anchor, candidates  # noqa: E402
from openpbr_tools.translate.common import Settings  # noqa: E402
from openpbr_tools.translate.convert import convert  # noqa: E402
from openpbr_tools.translate.judging import constant_values  # noqa: E402

PUBLISHED = os.path.join(HERE, "..", "data", "published")
TARGETS = ("open_pbr_surface", "standard_surface", "gltf_pbr", "UsdPreviewSurface")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--every", type=int, default=3)
    arguments = parser.parse_args()
    rig = Rig(size=64)
    renderer = materialx_renderer(rig)
    files = sorted(glob.glob(os.path.join(PUBLISHED, "materialx/resources/Materials/Examples/OpenPbr/*.mtlx")))
    files += sorted(glob.glob(os.path.join(PUBLISHED, "materialx/resources/Materials/Examples/StandardSurface/*.mtlx")))
    files += sorted(glob.glob(os.path.join(PUBLISHED, "openpbr/*.mtlx")))
    files += sorted(glob.glob(os.path.join(PUBLISHED, "measured/*.mtlx")))[::arguments.every]
    rows = {target: [] for target in TARGETS}
    for path in files:
        for material in read_asset(path).materials:
            if material.model not in ("open_pbr_surface", "standard_surface") or constant_values(material) is None:
                continue  # textured or connected: the chain's arithmetic takes constants
            values = _values(material)
            if values.get("geometry_opacity", 1.0) != 1.0 or values.get("opacity", [1.0] * 3) != [1.0] * 3:
                continue
            reference = renderer.render(material.model, values)
            mask = comparison_mask(rig) & np.isfinite(reference).all(axis=-1)
            for target in TARGETS:
                if target == material.model:
                    continue
                settings = Settings(context=Context())
                ours = candidates.choose(material, convert(material, target, settings), target, settings).material
                chain = anchor.graph_candidate(material, target)
                if chain is None:
                    continue
                found = [compare_images(reference, renderer.render(target, _values(m)), mask, rig.white()).mean
                         for m in (ours, chain)]
                rows[target].append((*found, f"{os.path.basename(path)}:{material.name}"))
    for target, found in rows.items():
        if not found:
            continue
        ours, chain = [r[0] for r in found], [r[1] for r in found]
        print(f"{target}: {len(found)} materials; median toolkit {statistics.median(ours):.2f} / chain "
              f"{statistics.median(chain):.2f}; under 2.3: {sum(o < 2.3 for o in ours)} / {sum(c < 2.3 for c in chain)}; "
              f"toolkit better by >0.5: {sum(o < c - 0.5 for o, c in zip(ours, chain))}, worse by >0.5: "
              f"{sum(o > c + 0.5 for o, c in zip(ours, chain))}")
        for o, c, name in found:
            if o > c + 0.5:
                print(f"    worse: toolkit {o:.2f} chain {c:.2f}  {name}")


if __name__ == "__main__":
    main()
