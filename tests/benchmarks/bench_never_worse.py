"""The toolkit's translations against MaterialX's own chain (its translation graphs, as
openpbr_tools/translate/materialx_graphs.py reproduces them) on generated OpenPBR materials that sweep
every parameter (tests/generated_materials.py) in lin_rec709, acescg and lin_displayp3 documents.

    python tests/benchmarks/bench_never_worse.py [--count 40] [--seed 11] [--source standard_surface]

Per target (Standard Surface, glTF, UsdPreviewSurface), judged by the lobe evaluator (mean CIEDE2000
over a 48-pixel lit sphere): the medians of the mapping alone, of ``convert``'s result (the
candidate search, on by default), of ``convert --verify``'s (which also fits thin-film thicknesses)
and of the chain; how many materials each leaves worse than the chain by more than 0.3, and the
worst such gap; how many the default makes better than the chain by more than 0.3. ``--count`` materials per colour space. ``--source standard_surface``:
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
from openpbr_tools.translate import anchor, candidates  # noqa: E402
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
                chain = anchor.graph_candidate(material, target)
                if chain is None:
                    continue
                plain = convert(material, target, Settings(context=Context())).material  # the mapping alone
                chosen = []
                for settings in (Settings(context=Context()), Settings(context=Context(), fit_films=True)):
                    translation = convert(material, target, settings)
                    chosen.append(candidates.choose(material, translation, target, settings).material)
                rows[target].append([compare_materials(material, m, rig).preview.mean
                                     for m in (plain, *chosen, chain)])
    for target in TARGETS[args.source]:
        a = np.asarray(rows[target])
        gaps = [a[:, column] - a[:, 3] for column in range(3)]
        print(f"{target:18s} n={len(a)}  median mapping / default / --verify / chain "
              f"{' / '.join(f'{np.median(a[:, c]):.2f}' for c in range(4))};  worse than the chain by >0.3: "
              + ", ".join(f"{label} {int(np.sum(gap > 0.3))} (worst {gap.max():+.2f})"
                          for label, gap in zip(("mapping", "default", "--verify"), gaps))
              + f";  default better by >0.3: {int(np.sum(gaps[1] < -0.3))}")

if __name__ == "__main__":
    main()
