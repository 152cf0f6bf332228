"""Long fuzzing run of the MaterialX path: structure-aware documents and raw byte mutations.

    python tests/benchmarks/fuzz_long.py [--structured 100000] [--raw 100000] [--seed 1]

Every input is validated, rendered in every report format and, when readable, upgraded; any
exception, or an input taking longer than --hang seconds, is a failure and is saved under
--failures for a regression test. Prints the counts as JSON.
"""

from __future__ import annotations

import argparse
import json
import os
import random
import sys
import tempfile
import time
import traceback

sys.path.insert(0, os.path.join(os.path.dirname(__file__), ".."))

from fuzzgen import mtlx_documents  # noqa: E402
from hypothesis import HealthCheck, given, settings  # noqa: E402

from openpbr_tools.reports import FORMATS, render  # noqa: E402
from openpbr_tools.rules import Context  # noqa: E402
from openpbr_tools.translate.upgrade import upgrade_mtlx_file  # noqa: E402
from openpbr_tools.validate import Report, validate_file  # noqa: E402

CONTEXT = Context(file_exists=lambda path: False, list_dir=lambda path: [])
SEED_DOCUMENTS = [os.path.join(root, name) for root, _, names in os.walk(os.path.join(os.path.dirname(__file__), "..", "..", "openpbr_tools", "samples"))
                  for name in names if name.endswith(".mtlx")]


class Run:
    def __init__(self, folder: str, failures: str, hang: float):
        self.path = os.path.join(folder, "input.mtlx")
        self.failures, self.hang = failures, hang
        self.tried = self.failed = self.hangs = 0
        self.slowest = 0.0

    def __call__(self, data: bytes) -> None:
        self.tried += 1
        with open(self.path, "wb") as handle:
            handle.write(data)
        start = time.perf_counter()
        try:
            result = validate_file(self.path, CONTEXT)
            for output_format in FORMATS:
                render(Report(files=[result]), output_format)
            if not result.unreadable:
                upgrade_mtlx_file(self.path)
        except Exception:  # noqa: BLE001 - any exception is a finding
            self.failed += 1
            self.save(data, traceback.format_exc())
        elapsed = time.perf_counter() - start
        self.slowest = max(self.slowest, elapsed)
        if elapsed > self.hang:
            self.hangs += 1
            self.save(data, f"took {elapsed:.2f} s")

    def save(self, data: bytes, why: str) -> None:
        os.makedirs(self.failures, exist_ok=True)
        stem = os.path.join(self.failures, f"failure_{self.failed + self.hangs:04d}")
        with open(stem + ".mtlx", "wb") as handle:
            handle.write(data)
        with open(stem + ".txt", "w", encoding="utf-8") as handle:
            handle.write(why)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--structured", type=int, default=100_000)
    parser.add_argument("--raw", type=int, default=100_000)
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--hang", type=float, default=5.0)
    parser.add_argument("--failures", default="fuzz-failures")
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as folder:
        structured = Run(folder, args.failures, args.hang)
        start = time.perf_counter()

        @settings(max_examples=args.structured, deadline=None, database=None, derandomize=False,
                  suppress_health_check=list(HealthCheck))
        @given(mtlx_documents())
        def fuzz(data):
            structured(data)

        if args.structured:
            fuzz()
        structured_seconds = time.perf_counter() - start

        raw = Run(folder, args.failures, args.hang)
        rng = random.Random(args.seed)
        seeds = [open(p, "rb").read() for p in sorted(SEED_DOCUMENTS)]
        start = time.perf_counter()
        for _ in range(args.raw):
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
            raw(bytes(data))
        raw_seconds = time.perf_counter() - start
    print(json.dumps({
        "structured": {"inputs": structured.tried, "failures": structured.failed, "hangs": structured.hangs,
                       "slowest_s": round(structured.slowest, 3), "seconds": round(structured_seconds, 1)},
        "raw_bytes": {"inputs": raw.tried, "failures": raw.failed, "hangs": raw.hangs,
                      "slowest_s": round(raw.slowest, 3), "seconds": round(raw_seconds, 1)},
    }, indent=2))


if __name__ == "__main__":
    main()
