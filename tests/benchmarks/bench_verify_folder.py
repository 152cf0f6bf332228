"""Conversion fidelity over a folder of .mtlx files, judged by the lobe evaluator (`convert --verify`).

    python tests/benchmarks/bench_verify_folder.py FOLDER SUFFIX [MODEL]
    e.g. python tests/benchmarks/bench_verify_folder.py tests/data/published/openpbr mtlx standard_surface
         python tests/benchmarks/bench_verify_folder.py tests/data/published/openpbr gltf

Converts every material of every .mtlx in FOLDER to SUFFIX (with --to MODEL for .mtlx), prints the
median mean CIEDE2000, how many materials stay under 2.3 (just noticeable), and the eight worst.
"""

from __future__ import annotations

import os
import statistics
import sys
import tempfile

from openpbr_tools.convert import convert_file
from openpbr_tools.verification import measure
from openpbr_tools.translate.common import Settings


def main() -> None:
    folder, suffix = sys.argv[1], sys.argv[2]
    target = sys.argv[3] if len(sys.argv) > 3 else None
    rows = []
    for name in sorted(os.listdir(folder)):
        if not name.endswith(".mtlx"):
            continue
        out = os.path.join(tempfile.mkdtemp(prefix="openpbr-fidelity-"), f"out.{suffix}")
        try:
            conversion = convert_file(os.path.join(folder, name), out, target, Settings())
        except Exception as error:  # noqa: BLE001 - a benchmark reports and goes on
            print(f"failed: {name}: {error}")
            continue
        rows += [(delta.mean, name) for _, delta in measure(conversion)]
    rows.sort()
    means = [mean for mean, _ in rows]
    print(f"{len(rows)} materials: median {statistics.median(means):.2f}, under 2.3: {sum(m < 2.3 for m in means)}/{len(means)}")
    for mean, name in rows[-8:]:
        print(f"  {mean:6.2f} {name}")


if __name__ == "__main__":
    main()
