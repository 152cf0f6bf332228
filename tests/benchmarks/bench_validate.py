"""Benchmark `openpbr validate` against MaterialX's `mxvalidate` on the same machine, same run.

    python tests/benchmarks/bench_validate.py [--files 1000] [--repeat 15]

Measures, on generated small OpenPBR documents:
1. one file: median wall time of `openpbr validate F` and `mxvalidate F` (process start included);
2. N files: one `openpbr validate DIR` call vs N `mxvalidate` calls;
3. in process: documents per second through `openpbr_tools.validate.validate_file`.
Targets (issue 2): (1) within 1.5x of mxvalidate, (2) at least 20x faster, (3) >= 500 docs/s.
"""

from __future__ import annotations

import argparse
import json
import os
import shutil
import statistics
import subprocess
import sys
import tempfile
import time

DOCUMENT = """<?xml version="1.0"?>
<materialx version="1.39" colorspace="lin_rec709">
  <open_pbr_surface name="S{i}" type="surfaceshader" version="1.1.1">
    <input name="base_color" type="color3" value="0.{a}, 0.4, 0.3" />
    <input name="base_metalness" type="float" value="0" />
    <input name="specular_roughness" type="float" value="0.{b}" />
    <input name="specular_ior" type="float" value="1.5" />
    <input name="coat_weight" type="float" value="0.{a}" />
    <input name="coat_roughness" type="float" value="0.1" />
  </open_pbr_surface>
  <surfacematerial name="M{i}" type="material">
    <input name="surfaceshader" type="surfaceshader" nodename="S{i}" />
  </surfacematerial>
</materialx>
"""


def generate(folder: str, count: int) -> list[str]:
    paths = []
    for i in range(count):
        path = os.path.join(folder, f"material_{i:05d}.mtlx")
        with open(path, "w", encoding="utf-8") as handle:
            handle.write(DOCUMENT.format(i=i, a=1 + i % 8, b=1 + i % 9))
        paths.append(path)
    return paths


def wall(command: list[str]) -> float:
    start = time.perf_counter()
    subprocess.run(command, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, check=False)
    return time.perf_counter() - start


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--files", type=int, default=1000)
    parser.add_argument("--repeat", type=int, default=15)
    args = parser.parse_args()
    openpbr = shutil.which("openpbr") or sys.exit("openpbr is not on PATH (pip install -e .)")
    mxvalidate = shutil.which("mxvalidate") or sys.exit("mxvalidate is not on PATH (pip install materialx)")
    results = {}
    with tempfile.TemporaryDirectory() as folder:
        paths = generate(folder, args.files)
        one = paths[0]
        for command in ([openpbr, "validate", one], [mxvalidate, one]):
            wall(command)  # warm the page cache
        ours, theirs = [], []
        for _ in range(args.repeat):  # alternating, so that the machine's drift falls on both
            ours.append(wall([openpbr, "validate", one]))
            theirs.append(wall([mxvalidate, one]))
        results["one_file_openpbr_s"] = statistics.median(ours)
        results["one_file_mxvalidate_s"] = statistics.median(theirs)
        results["one_file_ratio"] = results["one_file_openpbr_s"] / results["one_file_mxvalidate_s"]

        results["batch_openpbr_s"] = wall([openpbr, "validate", folder])
        start = time.perf_counter()
        for path in paths:
            subprocess.run([mxvalidate, path], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, check=False)
        results["batch_mxvalidate_s"] = time.perf_counter() - start
        results["batch_speedup"] = results["batch_mxvalidate_s"] / results["batch_openpbr_s"]

        from openpbr_tools.validate import validate_file

        validate_file(one)  # load libraries and tables once, as a long-running process would have
        start = time.perf_counter()
        for path in paths:
            validate_file(path)
        results["in_process_docs_per_s"] = len(paths) / (time.perf_counter() - start)
    results["files"] = args.files
    results["cpu_count"] = os.cpu_count()
    print(json.dumps(results, indent=2))


if __name__ == "__main__":
    main()
