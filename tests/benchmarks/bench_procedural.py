"""Procedural inputs kept by conversion: the seeded procedural corpus of tests/test_procedural_corpus.py
(Standard Surface, glTF PBR, UsdPreviewSurface and OpenPBR materials in three colour spaces, one to
three inputs each driven by a node graph) converted to .mtlx in every other model; prints, per target,
the share of procedural inputs whose graph reaches the output (as is, or with the mapping's nodes after
it), and of those not kept, how many are reported lost (OPBR1104) rather than of no effect on the
result (OPBR1102). Every one is reported at its input (the test checks that).

    python tests/benchmarks/bench_procedural.py [--seeds 4]
"""

from __future__ import annotations

import argparse
import collections
import os
import sys
import tempfile

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))

from generated_materials import COLORSPACES  # noqa: E402
from test_procedural_corpus import MODELS, TARGETS, procedural_document  # noqa: E402
from openpbr_tools.convert import convert_file  # noqa: E402
from openpbr_tools.io import read_asset  # noqa: E402
from openpbr_tools.model import Connection  # noqa: E402
from openpbr_tools.translate.common import Settings  # noqa: E402


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seeds", type=int, default=4)
    arguments = parser.parse_args()
    folder = tempfile.mkdtemp(prefix="openpbr-procedural-")
    kept = collections.Counter()
    total = collections.Counter()
    lost = collections.Counter()  # reported not carried (OPBR1104) at the input
    for seed in range(arguments.seeds):
        for model in MODELS:
            for space in COLORSPACES:
                text, driven = procedural_document(model, space, seed)
                source = os.path.join(folder, "source.mtlx")
                with open(source, "w", encoding="utf-8") as handle:
                    handle.write(text)
                for target in TARGETS:
                    if target == model:
                        continue
                    out = os.path.join(folder, f"out_{target}.mtlx")
                    conversion = convert_file(source, out, target, Settings(candidates=False))
                    errors = {(d.location.path, d.location.input) for d in conversion.diagnostics if d.code == "OPBR1104"}
                    results = {m.name: m for m in read_asset(out).materials}
                    for shader, names in driven.items():
                        graphs = " ".join(e.value.graph_xml or "" for e in results[shader].inputs.values()
                                          if isinstance(e.value, Connection))
                        for name in names:
                            total[target] += 1
                            kept[target] += f"{shader}_{name}_" in graphs
                            lost[target] += f"{shader}_{name}_" not in graphs and (shader, name) in errors
    for target in TARGETS:
        print(f"{target:18s} kept {kept[target]:4d} of {total[target]:4d} procedural inputs "
              f"({kept[target] / max(total[target], 1):.1%}); reported lost (OPBR1104) {lost[target]:4d}; the rest "
              "have no effect on the result and say so (OPBR1102)")


if __name__ == "__main__":
    main()
