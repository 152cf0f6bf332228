"""Batch conversion: `openpbr convert DIR -o OUT --output-format gltf` against one call per file.

    python tests/benchmarks/bench_convert_batch.py [--files 1000] [--large 10000] [--singles 30]

Measures, side by side in one run, on generated small OpenPBR documents:
1. one batch call over --files documents (--jobs 1) against single `openpbr convert` calls (a sample
   of --singles calls, extrapolated to --files: the per-call time does not depend on the file);
2. the same batch with --jobs 2 against --jobs 1;
3. peak resident memory (/usr/bin/time's maximum RSS) of --jobs 1 batches over --files and --large
   documents with a streamed report (--format text, the default, and jsonl: written file by file): it
   must stay flat. (A document format, json, sarif or junit, holds the combined report until the end.)
"""

from __future__ import annotations

import argparse
import os
import shutil
import statistics
import subprocess
import sys
import tempfile
import time

from bench_validate import DOCUMENT


def _library(folder: str, count: int) -> None:
    for i in range(count):
        sub = os.path.join(folder, f"group{i % 10}")
        os.makedirs(sub, exist_ok=True)
        with open(os.path.join(sub, f"m{i:05d}.mtlx"), "w", encoding="utf-8") as handle:
            handle.write(DOCUMENT.format(i=i, a=1 + i % 8, b=1 + i % 9))


def _openpbr() -> list[str]:
    script = os.path.join(os.path.dirname(sys.executable), "openpbr")
    return [script] if os.path.exists(script) else [sys.executable, "-m", "cli.main"]


def _timed(command: list[str]) -> tuple[float, int]:
    """(wall seconds, peak RSS in KiB) of a command, through /usr/bin/time when present."""
    wrapper = ["/usr/bin/time", "-f", "%M"] if os.path.exists("/usr/bin/time") else []
    start = time.perf_counter()
    done = subprocess.run(wrapper + command, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True, check=False)
    seconds = time.perf_counter() - start
    if done.returncode != 0:
        raise SystemExit(f"failed: {' '.join(command)}\n{done.stderr[-2000:]}")
    peak = int(done.stderr.strip().splitlines()[-1]) if wrapper else 0
    return seconds, peak


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--files", type=int, default=1000)
    parser.add_argument("--large", type=int, default=10000)
    parser.add_argument("--singles", type=int, default=30)
    arguments = parser.parse_args()
    work = tempfile.mkdtemp(prefix="openpbr-bench-batch-")
    small, large = os.path.join(work, "small"), os.path.join(work, "large")
    _library(small, arguments.files)
    _library(large, arguments.large)
    base = _openpbr()
    batch = lambda source, out, jobs: base + ["convert", source, "-o", out, "--output-format", "gltf",  # noqa: E731
                                              "--jobs", str(jobs), "--no-progress", "--format", "json"]
    one, one_peak = _timed(batch(small, os.path.join(work, "one"), 1))
    two, _ = _timed(batch(small, os.path.join(work, "two"), 2))
    files = sorted(os.path.join(root, n) for root, _, names in os.walk(small) for n in names)[: arguments.singles]
    singles = [_timed(base + ["convert", f, "-o", os.path.join(work, f"single{i}.gltf")])[0] for i, f in enumerate(files)]
    per_call = statistics.median(singles)
    streamed = lambda source, out, name: [*batch(source, out, 1)[:-1], name]  # noqa: E731
    peaks = {}
    for name in ("text", "jsonl"):
        _, one_peak = _timed(streamed(small, os.path.join(work, f"one_{name}"), name))
        big, big_peak = _timed(streamed(large, os.path.join(work, f"big_{name}"), name))
        peaks[name] = (one_peak, big_peak, big)
    print(f"{arguments.files} files, one call --jobs 1: {one:.1f} s ({one / arguments.files * 1000:.1f} ms/file)")
    print(f"{arguments.files} single calls (median of {len(singles)} x {arguments.files}): {per_call * arguments.files:.1f} s"
          f" -> one call is {per_call * arguments.files / one:.1f}x faster")
    print(f"--jobs 2: {two:.1f} s -> {one / two:.2f}x over --jobs 1")
    for name, (one_peak, big_peak, big) in peaks.items():
        print(f"peak RSS --jobs 1, --format {name}: {one_peak / 1024:.0f} MiB ({arguments.files} files), "
              f"{big_peak / 1024:.0f} MiB ({arguments.large} files, {big:.1f} s)")
    shutil.rmtree(work, ignore_errors=True)


if __name__ == "__main__":
    main()
