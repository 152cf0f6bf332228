"""Batch validation benchmark: a generated corpus of small .mtlx files validated in one call.

    python tests/benchmarks/bench_batch.py [--files 10000] [--small 1000]

Reports wall time for --jobs 1 and --jobs 2 on the corpus, the speed-up, and the peak resident
memory of the validating process for the small and the full corpus (--jobs 1, so one process holds
everything). Targets (issue 6): 10,000 files under 60 s on 2 cores; memory flat from 1k to 10k.
"""

from __future__ import annotations

import argparse
import json
import os
import shutil
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.dirname(__file__))
from bench_validate import generate  # noqa: E402


def measure(command: list[str]) -> tuple[float, float]:
    """Wall seconds and the peak RSS (MiB) of the largest process the command ran, in a fresh
    interpreter so earlier runs do not count."""
    probe = (
        "import resource, subprocess, sys, time\n"
        "start = time.perf_counter()\n"
        "done = subprocess.run(sys.argv[1:], stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)\n"
        "assert done.returncode in (0, 1), done.stderr\n"
        "print(time.perf_counter() - start, resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss / 1024)\n"
    )
    out = subprocess.run([sys.executable, "-c", probe, *command], capture_output=True, text=True, check=True).stdout
    wall, rss = out.split()
    return float(wall), float(rss)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--files", type=int, default=10000)
    parser.add_argument("--small", type=int, default=1000)
    args = parser.parse_args()
    openpbr = shutil.which("openpbr") or sys.exit("openpbr is not on PATH")
    results = {"cpu_count": os.cpu_count()}
    with tempfile.TemporaryDirectory() as root:
        small, full = os.path.join(root, "small"), os.path.join(root, "full")
        os.makedirs(small), os.makedirs(full)
        generate(small, args.small)
        generate(full, args.files)
        base = [openpbr, "validate", "--no-progress", "--format", "json", "--output", os.path.join(root, "r.json")]
        results["files"] = args.files
        results["jobs1_s"], results["jobs1_peak_rss_mib"] = measure(base + ["--jobs", "1", full])
        results["jobs2_s"], _ = measure(base + ["--jobs", "2", full])
        results["speedup_jobs2_over_jobs1"] = results["jobs1_s"] / results["jobs2_s"]
        results["small_files"] = args.small
        results["small_jobs1_s"], results["small_jobs1_peak_rss_mib"] = measure(base + ["--jobs", "1", small])
        results["rss_growth_small_to_full"] = results["jobs1_peak_rss_mib"] / results["small_jobs1_peak_rss_mib"]
    print(json.dumps(results, indent=2))


if __name__ == "__main__":
    main()
