"""One-file start-up: `openpbr validate F` against MaterialX's `mxvalidate F`, side by side.

    python tests/benchmarks/bench_startup.py [--runs 10] [--python PYTHON]

Runs the commands alternately (10 times each by default) on the same small OpenPBR document (ours with
``--no-config`` and as a pre-commit hook runs it, looking for a configuration),
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
    commands = {
        "openpbr": [*launcher, "validate", document, "--no-config"],
        "openpbr (looking for a configuration)": [*launcher, "validate", document],
        "mxvalidate": [arguments.python, script, document],
    }
    for command in commands.values():
        _time(command)  # warm the caches (library extract, page cache)
    timings = {name: [] for name in commands}
    for _ in range(arguments.runs):
        for name, command in commands.items():
            timings[name].append(_time(command))
    medians = {name: statistics.median(values) for name, values in timings.items()}
    for name, value in medians.items():
        print(f"{name:>38}: median {value * 1000:.0f} ms over {arguments.runs} runs")
    for name in commands:
        if name != "mxvalidate":
            print(f"ratio {name} / mxvalidate: {medians[name] / medians['mxvalidate']:.2f}")


if __name__ == "__main__":
    main()
