"""One-file start-up: `openpbr validate F` against MaterialX's `mxvalidate F`, side by side.

    python tests/benchmarks/bench_startup.py [--runs 10] [--python PYTHON]

Runs the two commands alternately (10 times each by default) on the same small OpenPBR document,
with the interpreter given (default: this one; use a non-editable install: an editable install's
import finder adds ~15 ms to every start-up), and prints the median wall times and their ratio. The
MaterialX library index is built once before timing (it is cached per MaterialX version).
"""

from __future__ import annotations

import argparse
import os
import statistics
import subprocess
import sys
import tempfile
import time

from bench_validate import DOCUMENT

MXVALIDATE = "import sys\nfrom MaterialX._scripts.mxvalidate import main\nsys.argv[0] = 'mxvalidate'\nmain()\n"


def _time(command: list[str]) -> float:
    start = time.perf_counter()
    subprocess.run(command, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, check=False)
    return time.perf_counter() - start


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=int, default=10)
    parser.add_argument("--python", default=sys.executable)
    arguments = parser.parse_args()
    folder = tempfile.mkdtemp(prefix="openpbr-startup-")
    document = os.path.join(folder, "one.mtlx")
    with open(document, "w", encoding="utf-8") as handle:
        handle.write(DOCUMENT.format(i=0, a=5, b=3))
    script = os.path.join(folder, "mxvalidate.py")
    with open(script, "w", encoding="utf-8") as handle:
        handle.write(MXVALIDATE)
    script_path = os.path.join(os.path.dirname(arguments.python), "openpbr")  # the console script users run
    launcher = [script_path] if os.path.exists(script_path) else [arguments.python, "-m", "cli.main"]
    ours = [*launcher, "validate", document, "--no-config"]
    theirs = [arguments.python, script, document]
    _time(ours), _time(theirs)  # warm the caches (library index, page cache)
    timings = {"openpbr": [], "mxvalidate": []}
    for _ in range(arguments.runs):
        timings["openpbr"].append(_time(ours))
        timings["mxvalidate"].append(_time(theirs))
    medians = {name: statistics.median(values) for name, values in timings.items()}
    for name, value in medians.items():
        print(f"{name:>10}: median {value * 1000:.0f} ms over {arguments.runs} runs")
    print(f"ratio openpbr / mxvalidate: {medians['openpbr'] / medians['mxvalidate']:.2f}")


if __name__ == "__main__":
    main()
