"""The toolkit's translations against MaterialX's own chain (its translation graphs, as
openpbr_tools/translate/materialx_graphs.py reproduces them) on generated OpenPBR materials that sweep
every parameter (tests/generated_materials.py) in lin_rec709, acescg and lin_displayp3 documents.

    python tests/benchmarks/bench_never_worse.py [--count 40] [--seed 11] [--source standard_surface]

Per target (Standard Surface, glTF, UsdPreviewSurface), judged by the lobe evaluator (mean CIEDE2000
over a 48-pixel lit sphere): the medians of the mapping alone, of ``convert --verify``'s result (the
candidate search) and of the chain; how many materials the mapping alone, and the search, leave
worse than the chain by more than 0.3, and the worst such gap; how many the search makes better
than the chain by more than 0.3. ``--count`` materials per colour space. ``--source standard_surface``:
the other direction, generated Standard Surface materials to OpenPBR, glTF and UsdPreviewSurface
against MaterialX's graphs from Standard Surface.
"""

from __future__ import annotations

import argparse
import collections
import os
import sys
import tempfile

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))

from generated_materials import COLORSPACES, document  # noqa: E402
from openpbr_tools.evaluate.preview import Rig  # noqa: E402
from openpbr_tools.evaluate.verify import compare_materials  # noqa: E402
from openpbr_tools.io import read_asset  # noqa: E402
from openpbr_tools.rules import Context  # noqa: E402
from openpbr_tools.translate import candidates  # noqa: E402
from openpbr_tools.translate.common import Settings  # noqa: E402
from openpbr_tools.translate.convert import convert  # noqa: E402

TARGETS = {"open_pbr_surface": ("standard_surface", "gltf_pbr", "UsdPreviewSurface"),
           "standard_surface": ("open_pbr_surface", "gltf_pbr", "UsdPreviewSurface")}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--count", type=int, default=40)
    parser.add_argument("--seed", type=int, default=11)
    parser.add_argument("--source", default="open_pbr_surface", choices=sorted(TARGETS))
    args = parser.parse_args()
    rig = Rig(size=48)
    rows = collections.defaultdict(list)
    for space in COLORSPACES:
        path = os.path.join(tempfile.mkdtemp(prefix="openpbr-chain-"), "generated.mtlx")
        with open(path, "w", encoding="utf-8") as handle:
            handle.write(document(args.source, space, args.seed, args.count))
        for material in read_asset(path).materials:
            for target in TARGETS[args.source]:
                chain = candidates.graph_candidate(material, target)
                if chain is None:
                    continue
                plain = convert(material, target, Settings(context=Context())).material
                searched = Settings(context=Context(), candidates=True)
                best = candidates.choose(material, convert(material, target, searched), target, searched).material
                rows[target].append([compare_materials(material, m, rig).preview.mean for m in (plain, best, chain)])
    for target in TARGETS[args.source]:
        a = np.asarray(rows[target])
        gap_plain, gap_best = a[:, 0] - a[:, 2], a[:, 1] - a[:, 2]
        print(f"{target:18s} n={len(a)}  median mapping / --verify / chain {np.median(a[:, 0]):.2f} / "
              f"{np.median(a[:, 1]):.2f} / {np.median(a[:, 2]):.2f};  worse than the chain by >0.3: mapping "
              f"{int(np.sum(gap_plain > 0.3))} (worst {gap_plain.max():+.2f}), --verify {int(np.sum(gap_best > 0.3))} "
              f"(worst {gap_best.max():+.2f});  --verify better by >0.3: {int(np.sum(gap_best < -0.3))}")


if __name__ == "__main__":
    main()
