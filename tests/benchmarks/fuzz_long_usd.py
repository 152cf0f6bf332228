"""Long fuzzing run of the USD path: structure-aware stages and raw byte mutations of text, crate
and package files.

    nice -n 10 python tests/benchmarks/fuzz_long_usd.py [--structured 50000] [--raw-usda 15000] \
        [--raw-usdc 20000] [--raw-usdz 15000] [--jobs 2] [--seed 1] [--hang 5] [--kill-after 60]

Every input is validated (``validate_file``), rendered in every report format and, when readable,
each of its materials is converted in-process to glTF PBR. A failure is any exception, a layer left
behind in usd-core's registry, an input taking more than --hang CPU seconds or taking the worker's
resident memory above --max-rss-mb, and a worker that dies on an input (usd-core can abort or crash
the process) or stays on one longer than --kill-after seconds (counted while this script runs: a
suspended machine is no hang). The input is saved under --failures with the reason (at most three
inputs per distinct exception site), for a regression fixture in tests/fixtures/fuzz_usd/.
Exceptions raised in the translators (openpbr_tools/translate/) are counted apart
(``failed_in_translate``). Workers are separate processes with a 12 GiB address-space limit, each
reusing one temporary file per suffix; a crashed or killed worker is restarted with a new seed and
the rest of its share. Prints the counts as JSON (``slowest_s`` in CPU seconds).
"""

from __future__ import annotations

import argparse
import json
import multiprocessing
import os
import random
import resource
import shutil
import sys
import tempfile
import time
import traceback

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, ".."))

KINDS = ("structured", "raw-usda", "raw-usdc", "raw-usdz")
COUNTERS = ("tried", "failed", "failed_in_translate", "hangs", "crashes")
ADDRESS_SPACE_LIMIT = 12 << 30


class Shared:
    """Counters in shared memory, so a worker that crashes loses nothing it counted."""

    def __init__(self, jobs: int):
        self.counts = multiprocessing.Array("q", jobs * len(KINDS) * len(COUNTERS), lock=False)
        self.slowest = multiprocessing.Array("d", jobs * len(KINDS), lock=False)
        self.started = multiprocessing.Array("d", jobs, lock=False)  # 0: idle
        self.kind = multiprocessing.Array("i", jobs, lock=False)
        self.suffix = multiprocessing.Array("c", jobs * 8, lock=False)

    def add(self, job: int, kind: int, counter: str, amount: int = 1) -> None:
        self.counts[(job * len(KINDS) + kind) * len(COUNTERS) + COUNTERS.index(counter)] += amount

    def get(self, job: int, kind: int, counter: str) -> int:
        return self.counts[(job * len(KINDS) + kind) * len(COUNTERS) + COUNTERS.index(counter)]


def save(failures: str, data: bytes, suffix: str, why: str, signature: str = "") -> None:
    os.makedirs(failures, exist_ok=True)
    stem = os.path.join(failures, f"failure_{time.time_ns()}")
    with open(stem + suffix, "wb") as handle:
        handle.write(data)
    with open(stem + ".txt", "w", encoding="utf-8") as handle:
        handle.write(f"signature: {signature or why.splitlines()[0]}\n{why}")


def signature_of(error: BaseException) -> str:
    """Where an exception comes from: its type and the innermost frame in the toolkit."""
    frames = [f for f in traceback.extract_tb(error.__traceback__) if f"{os.sep}openpbr_tools{os.sep}" in f.filename]
    where = f"{frames[-1].filename.split(os.sep + 'openpbr_tools' + os.sep)[-1]}:{frames[-1].name}" if frames else "?"
    return f"{type(error).__name__} in {where}"


SAVED_PER_SIGNATURE = 3


def worker(job: int, quota: dict, seed: int, shared: Shared, folder: str, failures: str, hang: float,
           max_rss_mb: float) -> None:
    """Run this worker's share: ``quota`` maps a kind to the number of inputs still to try."""
    from fuzzgen_usd import mutate_bytes, package, seed_documents, usda_documents
    from hypothesis import HealthCheck, Phase, given, settings
    from hypothesis import seed as hypothesis_seed
    from pxr import Sdf

    from openpbr_tools.reports import FORMATS, render
    from openpbr_tools.rules import Context
    from openpbr_tools.translate.convert import MODELS, convert
    from openpbr_tools.validate import Report, validate_file

    context = Context(file_exists=lambda path: False, list_dir=lambda path: [])
    from fuzz_long import raise_internal_errors  # the fuzz harnesses' shared helpers

    raise_internal_errors()
    # a runaway allocation fails instead of exhausting the machine; one that is touched is caught below
    resource.setrlimit(resource.RLIMIT_AS, (ADDRESS_SPACE_LIMIT, ADDRESS_SPACE_LIMIT))
    seen: dict[str, int] = {}

    def run(kind: int, data: bytes, suffix: str) -> None:
        path = os.path.join(folder, "input" + suffix)
        shared.kind[job] = kind
        shared.suffix[job * 8: job * 8 + 8] = suffix.encode().ljust(8, b"\0")
        with open(path, "wb") as handle:
            handle.write(data)
        start = time.process_time()  # CPU seconds: a machine or sandbox pausing the process does not count
        shared.started[job] = time.time()
        try:
            result = validate_file(path, context, keep_asset=True)
            for output_format in FORMATS:
                render(Report(files=[result]), output_format)
            if not result.unreadable:
                for material in result.asset.materials:
                    if material.model in MODELS:
                        convert(material, "gltf_pbr")
            result = None
            if Sdf.Layer.Find(path):
                raise AssertionError("a layer of the stage outlived the read (usd-core's registry still holds it)")
        except Exception as error:  # noqa: BLE001 - any exception is a finding
            signature = signature_of(error)
            shared.add(job, kind, "failed_in_translate" if " in translate/" in signature else "failed")
            seen[signature] = seen.get(signature, 0) + 1
            if seen[signature] <= SAVED_PER_SIGNATURE:  # the same bug a thousand times is one finding
                save(failures, data, suffix, traceback.format_exc(), signature)
        shared.started[job] = 0
        elapsed = time.process_time() - start
        shared.add(job, kind, "tried")
        slot = job * len(KINDS) + kind
        shared.slowest[slot] = max(shared.slowest[slot], elapsed)
        if elapsed > hang:
            shared.add(job, kind, "hangs")
            save(failures, data, suffix, f"took {elapsed:.2f} s")
        peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
        if peak > max_rss_mb:  # the peak never comes down: a fresh worker watches the next inputs
            shared.add(job, kind, "failed")
            save(failures, data, suffix, f"the worker's memory peaked at {peak:.0f} MiB")
            os._exit(3)

    if quota.get("structured"):
        chunk = min(500, quota["structured"])
        remaining = quota["structured"]
        round_number = 0
        while remaining > 0:
            @settings(max_examples=min(chunk, remaining), deadline=None, database=None, phases=[Phase.generate],
                      suppress_health_check=list(HealthCheck))
            @hypothesis_seed(seed * 1000 + round_number)
            @given(usda_documents())
            def fuzz(data):
                run(0, data, ".usda")

            before = shared.get(job, 0, "tried")
            fuzz()
            remaining -= max(1, shared.get(job, 0, "tried") - before)
            round_number += 1

    rng = random.Random(seed)
    seeds = seed_documents()
    for kind, suffix in ((1, ".usda"), (2, ".usdc"), (3, ".usdz")):
        for _ in range(quota.get(KINDS[kind], 0)):
            original = rng.choice(seeds[suffix])
            if suffix == ".usdz" and rng.random() < 0.5:  # corrupt the layer inside a well-formed package
                inner = rng.choice(seeds[rng.choice([".usda", ".usdc"])])
                name = rng.choice(["root.usda", "root.usdc", "root.usd", "a/../root.usda", "/root.usda", "root.png"])
                extra = rng.choice([[], [("albedo.png", b"\x89PNG")], [("../x.png", b"")], [("/etc/x.png", b"")]])
                data = package([(name, mutate_bytes(inner, rng))] + extra)
            else:
                data = mutate_bytes(original, rng)
            written = ".usd" if suffix == ".usdc" and rng.random() < 0.2 else suffix
            run(kind, data, written)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--structured", type=int, default=50_000)
    parser.add_argument("--raw-usda", type=int, default=15_000)
    parser.add_argument("--raw-usdc", type=int, default=20_000)
    parser.add_argument("--raw-usdz", type=int, default=15_000)
    parser.add_argument("--jobs", type=int, default=2)
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--hang", type=float, default=5.0, help="an input taking more CPU seconds than this is a failure")
    parser.add_argument("--kill-after", type=float, default=60.0, help="a worker stuck this long is killed")
    parser.add_argument("--max-rss-mb", type=float, default=1024.0, help="an input that takes the worker's "
                        "resident memory above this is a failure")
    parser.add_argument("--failures", default="fuzz-failures-usd")
    parser.add_argument("--progress", type=float, default=60.0, help="seconds between progress lines on stderr")
    args = parser.parse_args()
    totals = {"structured": args.structured, "raw-usda": args.raw_usda, "raw-usdc": args.raw_usdc,
              "raw-usdz": args.raw_usdz}
    context = multiprocessing.get_context("spawn")
    shared = Shared(args.jobs)
    folder = tempfile.mkdtemp(prefix="openpbr-fuzz-usd-")
    shares = [{kind: total // args.jobs + (1 if job < total % args.jobs else 0) for kind, total in totals.items()}
              for job in range(args.jobs)]
    restarts = [0] * args.jobs
    crashes: list[str] = []

    def start(job: int):
        done = {kind: shared.get(job, k, "tried") for k, kind in enumerate(KINDS)}
        quota = {kind: max(0, shares[job][kind] - done[kind]) for kind in KINDS}
        seed = args.seed * 100 + job * 10_000 + restarts[job]
        os.makedirs(os.path.join(folder, str(job)), exist_ok=True)
        process = context.Process(target=worker, args=(job, quota, seed, shared, os.path.join(folder, str(job)),
                                                       args.failures, args.hang, args.max_rss_mb), daemon=True)
        process.start()
        return process

    begin = time.perf_counter()
    processes = [start(job) for job in range(args.jobs)]
    last_progress = last_tick = time.perf_counter()
    # Seconds each worker has spent on its current input, counted only while this loop runs: a
    # suspended machine or sandbox makes wall-clock gaps that are no hang.
    on_input = [(0.0, 0.0)] * args.jobs  # (the input's start stamp, seconds spent on it)
    while any(p is not None for p in processes):
        time.sleep(0.5)
        tick = time.perf_counter()
        step, last_tick = min(tick - last_tick, 1.0), tick
        for job, process in enumerate(processes):
            if process is None:
                continue
            stamp = shared.started[job]
            spent = on_input[job][1] + step if stamp and stamp == on_input[job][0] else 0.0
            on_input[job] = (stamp, spent)
            stuck = spent > args.kill_after
            if process.is_alive() and not stuck:
                continue
            if stuck:
                process.kill()
                process.join()
            if process.exitcode == 0 and not stuck:
                processes[job] = None
                continue
            kind = shared.kind[job]
            suffix = bytes(shared.suffix[job * 8: job * 8 + 8]).rstrip(b"\0").decode() or ".usda"
            current = os.path.join(folder, str(job), "input" + suffix)
            data = b""
            if os.path.exists(current):
                with open(current, "rb") as handle:
                    data = handle.read()
            why = (f"worker killed after {args.kill_after:.0f} s on one input" if stuck
                   else f"worker died with exit code {process.exitcode} (a negative code is the signal)")
            if shared.started[job] or stuck:  # it died on an input, not in start-up
                shared.add(job, kind, "crashes")
                shared.add(job, kind, "tried")
                save(args.failures, data, suffix, why)
                crashes.append(f"{KINDS[kind]}: {why}")
            shared.started[job] = 0
            restarts[job] += 1
            if restarts[job] > 200:
                raise SystemExit(f"worker {job} keeps dying: {why}")
            processes[job] = start(job)
        if time.perf_counter() - last_progress > args.progress:
            last_progress = time.perf_counter()
            tried = sum(shared.get(j, k, "tried") for j in range(args.jobs) for k in range(len(KINDS)))
            print(f"{time.perf_counter() - begin:.0f} s: {tried} inputs", file=sys.stderr, flush=True)
    seconds = time.perf_counter() - begin
    report = {}
    for k, kind in enumerate(KINDS):
        entry = {counter: sum(shared.get(j, k, counter) for j in range(args.jobs)) for counter in COUNTERS}
        entry["slowest_s"] = round(max(shared.slowest[j * len(KINDS) + k] for j in range(args.jobs)), 3)
        report[kind] = entry
    total = sum(entry["tried"] for entry in report.values())
    signatures: dict[str, int] = {}
    for name in sorted(os.listdir(args.failures)) if os.path.isdir(args.failures) else ():
        if name.endswith(".txt"):
            with open(os.path.join(args.failures, name), encoding="utf-8") as handle:
                first = handle.readline().removeprefix("signature: ").strip()
            signatures[first] = signatures.get(first, 0) + 1
    report["total"] = {"inputs": total, "seconds": round(seconds, 1), "inputs_per_second": round(total / seconds, 1),
                       "jobs": args.jobs, "worker_restarts": sum(restarts), "crashes": crashes,
                       "saved_failures_by_signature": signatures}
    shutil.rmtree(folder, ignore_errors=True)
    print(json.dumps(report, indent=2))


if __name__ == "__main__":
    main()
