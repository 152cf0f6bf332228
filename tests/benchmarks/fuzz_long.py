"""Long fuzzing run of the MaterialX path: structure-aware documents and raw byte mutations.

    nice -n 10 python tests/benchmarks/fuzz_long.py [--structured 50000] [--raw 50000] [--workers 2]
        [--seed 1] [--hang 10] [--failures fuzz-failures]

Every input is validated, rendered in every report format and, when readable, upgraded. An
exception, or an input taking longer than --hang seconds (interrupted by an alarm, so a real
infinite loop is caught too), is a failure: the input is saved under --failures with its traceback
(at most 5 inputs per distinct failure) for a regression fixture (tests/fixtures/fuzz_*.mtlx).
Python warnings raised by the library are counted per source line and reported, not failed. The
work is split over --workers processes, each with its own hypothesis seed; the counts are printed
as JSON. The harness (:class:`Harness`, :func:`run_workers`) is shared with fuzz_long_gltf.py.
"""

from __future__ import annotations

import argparse
import json
import multiprocessing
import os
import random
import signal
import sys
import tempfile
import time
import traceback
import warnings
from collections import Counter

sys.path.insert(0, os.path.join(os.path.dirname(__file__), ".."))
sys.path.insert(0, os.path.dirname(__file__))


class Hang(BaseException):  # not an Exception: code under test that catches Exception cannot swallow it
    pass


def _alarm(signum, frame):
    raise Hang()


class Harness:
    """Runs inputs through ``exercise(path)`` in ``folder``, one at a time, with a time limit;
    counts inputs, failures and hangs per kind and saves the failing inputs."""

    def __init__(self, exercise, folder: str, failures: str, hang: float, worker: int):
        self.exercise, self.folder, self.failures, self.hang, self.worker = exercise, folder, failures, hang, worker
        self.tried: Counter = Counter()
        self.failed: Counter = Counter()
        self.hangs: Counter = Counter()
        self.signatures: Counter = Counter()
        self.warnings: Counter = Counter()
        self.slowest = (0.0, "")
        self.seconds: Counter = Counter()
        self.codes: Counter = Counter()  # diagnostic codes the inputs produced: which checks the run reached
        self.started = time.perf_counter()
        signal.signal(signal.SIGALRM, _alarm)

    def __call__(self, kind: str, suffix: str, data: bytes) -> None:
        self.tried[kind] += 1
        path = os.path.join(self.folder, "input" + suffix)
        with open(path, "wb") as handle:
            handle.write(data)
        start = time.perf_counter()
        signal.setitimer(signal.ITIMER_REAL, self.hang)
        try:
            with warnings.catch_warnings(record=True) as caught:
                warnings.simplefilter("always")
                codes = self.exercise(path)
            signal.setitimer(signal.ITIMER_REAL, 0)
            self.codes.update(codes or ())
            for warning in caught:
                self.warnings[f"{warning.category.__name__} {os.path.relpath(warning.filename)}:{warning.lineno}"] += 1
        except Hang:
            self.hangs[kind] += 1
            self.save(kind, suffix, data, f"hang: more than {self.hang} s", "hang")
        except Exception:  # noqa: BLE001 - any exception is a finding
            signal.setitimer(signal.ITIMER_REAL, 0)
            self.failed[kind] += 1
            text = traceback.format_exc()
            self.save(kind, suffix, data, text, _signature(text))
        elapsed = time.perf_counter() - start
        self.seconds[kind] += elapsed
        if sum(self.tried.values()) % 5000 == 0:  # progress, on stderr
            print(f"worker {self.worker}: {dict(self.tried)} tried, {sum(self.failed.values())} failures, "
                  f"{sum(self.hangs.values())} hangs, {time.perf_counter() - self.started:.0f} s", file=sys.stderr, flush=True)
        if elapsed > self.slowest[0]:
            self.slowest = (elapsed, f"{kind} input #{self.tried[kind]} of worker {self.worker} ({len(data)} bytes)")

    def save(self, kind: str, suffix: str, data: bytes, why: str, signature: str) -> None:
        self.signatures[signature] += 1
        if self.signatures[signature] > 5:
            return
        os.makedirs(self.failures, exist_ok=True)
        stem = os.path.join(self.failures, f"w{self.worker}_{kind}_{sum(self.signatures.values()):05d}")
        with open(stem + suffix, "wb") as handle:
            handle.write(data)
        with open(stem + ".txt", "w", encoding="utf-8") as handle:
            handle.write(why)

    def figures(self) -> dict:
        return {"tried": dict(self.tried), "failed": dict(self.failed), "hangs": dict(self.hangs),
                "signatures": dict(self.signatures), "warnings": dict(self.warnings),
                "slowest": list(self.slowest), "seconds": dict(self.seconds), "codes": dict(self.codes)}


def structured_batches(harness: Harness, kind: str, strategy, count: int, seed: int, batch: int) -> None:
    """Feed ``count`` examples of ``strategy`` (each a (suffix, bytes) pair) to the harness, ``batch``
    per hypothesis run (each run seeded from ``seed``), so the engine's memory stays bounded however
    long the run."""
    from hypothesis import HealthCheck, Phase, given, settings
    from hypothesis import seed as hypothesis_seed

    done, run = 0, 0
    while done < count:
        size = min(batch, count - done)

        @hypothesis_seed(seed * 1_000_003 + run)
        @settings(max_examples=size, deadline=None, database=None, phases=[Phase.generate],
                  suppress_health_check=list(HealthCheck))
        @given(strategy)
        def fuzz(case):
            harness(kind, *case)

        before = harness.tried[kind]
        fuzz()
        done += max(1, harness.tried[kind] - before)
        run += 1


def raise_internal_errors() -> None:
    """Make the OPBR011 safety net re-raise in this process: it turns an exception on one file into a
    finding, which would hide every defect a fuzz run exists to find (tests/conftest.py does the same)."""
    from openpbr_tools.rules.document import RAISE_INTERNAL_ERRORS

    os.environ[RAISE_INTERNAL_ERRORS] = "1"


def memoise_rule_pages() -> None:
    """Every SARIF report embeds each rule's documentation page, which depends on the rule alone;
    formatting all of them for every input is most of a run's time, so it is done once per process."""
    import functools

    from openpbr_tools.reports import sarif

    if not hasattr(sarif.rule_page, "cache_info"):
        sarif.rule_page = functools.lru_cache(maxsize=None)(sarif.rule_page)


def _signature(text: str) -> str:
    """The exception type and the innermost frame in the toolkit: one failure, however many inputs hit it."""
    lines = text.strip().splitlines()
    frames = [line.strip() for line in lines if line.strip().startswith("File ") and "openpbr_tools" in line]
    return f"{lines[-1].split(':', 1)[0]} at {frames[-1] if frames else '?'}"


def run_workers(worker, totals: dict[str, int], workers: int, extra: tuple) -> tuple[list[dict], float]:
    """Split ``totals`` (kind -> count) over ``workers`` processes running ``worker((index, share, *extra))``."""
    shares = [{kind: total // workers + (1 if i < total % workers else 0) for kind, total in totals.items()}
              for i in range(workers)]
    tasks = [(i, shares[i], *extra) for i in range(workers)]
    start = time.perf_counter()
    if workers == 1:
        results = [worker(tasks[0])]
    else:
        with multiprocessing.get_context("spawn").Pool(workers) as pool:
            results = pool.map(worker, tasks)
    return results, time.perf_counter() - start


def summarise(results: list[dict], kinds, wall: float, workers: int, seed: int) -> dict:
    summary: dict = {"wall_seconds": round(wall, 1), "workers": workers, "seed": seed}
    for kind in kinds:
        tried = sum(r["tried"].get(kind, 0) for r in results)
        busy = sum(r["seconds"].get(kind, 0.0) for r in results)
        summary[kind] = {"inputs": tried, "failures": sum(r["failed"].get(kind, 0) for r in results),
                         "hangs": sum(r["hangs"].get(kind, 0) for r in results),
                         "inputs_per_second_per_worker": round(tried / busy, 1) if busy else None}
    summary["total_inputs"] = sum(summary[kind]["inputs"] for kind in kinds)
    summary["inputs_per_second"] = round(summary["total_inputs"] / wall, 1) if wall else None
    slowest = max((r["slowest"] for r in results), key=lambda s: s[0])
    summary["slowest"] = {"seconds": round(slowest[0], 3), "input": slowest[1]}
    summary["distinct_failures"] = dict(sum((Counter(r["signatures"]) for r in results), Counter()))
    summary["warnings"] = dict(sum((Counter(r["warnings"]) for r in results), Counter()))
    summary["inputs_per_code"] = dict(sorted(sum((Counter(r["codes"]) for r in results), Counter()).items()))
    return summary


# -- MaterialX -------------------------------------------------------------------------------------

SAMPLES = os.path.join(os.path.dirname(__file__), "..", "..", "openpbr_tools", "samples")


def mtlx_exercise():
    from openpbr_tools.reports import FORMATS, render
    from openpbr_tools.rules import Context
    from openpbr_tools.translate.upgrade import upgrade_mtlx_file
    from openpbr_tools.validate import Report, validate_file

    context = Context(file_exists=lambda path: False, list_dir=lambda path: [])  # never touch the disk for textures
    memoise_rule_pages()
    raise_internal_errors()

    def exercise(path: str) -> None:
        result = validate_file(path, context)
        for output_format in FORMATS:
            render(Report(files=[result]), output_format).encode("utf-8")  # what the CLI writes to stdout
        if not result.unreadable:
            upgrade_mtlx_file(path)
        return {d.code for d in result.diagnostics}

    return exercise


def mtlx_worker(arguments) -> dict:
    index, counts, seed, hang, failures, batch = arguments
    from fuzzgen import mtlx_documents

    with tempfile.TemporaryDirectory(prefix=f"openpbr-fuzz-mtlx-{index}-") as folder:
        harness = Harness(mtlx_exercise(), folder, failures, hang, index)
        structured_batches(harness, "structured", mtlx_documents().map(lambda data: (".mtlx", data)),
                           counts["structured"], seed * 101 + index, batch)
        rng = random.Random(seed * 7919 + index)
        seeds = [_read(p) for p in sorted(_sample_documents())]
        for _ in range(counts["raw_bytes"]):
            data = bytearray(rng.choice(seeds))
            for _ in range(rng.randint(1, 16)):
                position = rng.randrange(len(data))
                choice = rng.random()
                if choice < 0.4:
                    data[position] = rng.randrange(256)
                elif choice < 0.7:
                    data[position:position] = rng.choice([b"<", b">", b'"', b"&", b"\x00", b"\xc3", b"<x>", b"=", b","])
                elif choice < 0.9:
                    del data[position:position + rng.randint(1, 32)]
                else:
                    data = data[:position]
                if not data:
                    break
            harness("raw_bytes", ".mtlx", bytes(data))
        return harness.figures()


def _read(path: str) -> bytes:
    with open(path, "rb") as handle:
        return handle.read()


def _sample_documents() -> list[str]:
    return [os.path.join(root, name) for root, _, names in os.walk(SAMPLES) for name in names if name.endswith(".mtlx")]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--structured", type=int, default=50_000)
    parser.add_argument("--raw", type=int, default=50_000)
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--hang", type=float, default=10.0)
    parser.add_argument("--batch", type=int, default=2000)
    parser.add_argument("--failures", default="fuzz-failures")
    args = parser.parse_args()
    totals = {"structured": args.structured, "raw_bytes": args.raw}
    results, wall = run_workers(mtlx_worker, totals, args.workers,
                                (args.seed, args.hang, os.path.abspath(args.failures), args.batch))
    print(json.dumps(summarise(results, tuple(totals), wall, args.workers, args.seed), indent=2))


if __name__ == "__main__":
    main()
