"""Long fuzzing run of the glTF read path: structure-aware documents, raw .gltf and raw .glb mutations.

    nice -n 10 python tests/benchmarks/fuzz_long_gltf.py [--structured 40000] [--raw-gltf 30000]
        [--raw-glb 30000] [--workers 2] [--seed 1] [--hang 10] [--failures fuzz-failures-gltf]

Every input is validated (``validate_file``, with the real file system: inputs sit beside the
seeds' textures and buffers, a symbolic link out of the folder and a FIFO), rendered in every
report format and, when readable, each material is converted in-process to open_pbr_surface
(``translate.convert.convert``). An exception, or an input taking longer than --hang seconds, is a
failure, saved under --failures for a regression fixture (tests/fixtures/fuzz_gltf/); see
fuzz_long.py for the harness. Generators: tests/fuzzgen_gltf.py.
"""

from __future__ import annotations

import argparse
import json
import os
import random
import sys
import tempfile

sys.path.insert(0, os.path.join(os.path.dirname(__file__), ".."))
sys.path.insert(0, os.path.dirname(__file__))

from fuzz_long import (
    Harness,
    memoise_rule_pages,
    raise_internal_errors,
    run_workers,
    structured_batches,
    summarise,
)

KINDS = ("structured", "raw_gltf", "raw_glb")


def gltf_exercise():
    from openpbr_tools.reports import FORMATS, render
    from openpbr_tools.translate.convert import MODELS, convert
    from openpbr_tools.validate import Report, validate_file

    memoise_rule_pages()
    raise_internal_errors()

    def exercise(path: str) -> None:
        result = validate_file(path, keep_asset=True)
        for diagnostic in result.diagnostics:
            assert diagnostic.code and diagnostic.location.file, diagnostic
        report = Report(files=[result])
        for output_format in FORMATS:
            render(report, output_format).encode("utf-8")  # what the CLI writes to stdout
        if result.asset is not None:
            for material in result.asset.materials:
                if material.model in MODELS:
                    convert(material, "open_pbr_surface")
        return {d.code for d in result.diagnostics}

    return exercise


def gltf_worker(arguments) -> dict:
    index, counts, seed, hang, failures, batch = arguments
    from fuzzgen_gltf import build_seeds, gltf_inputs, mutate_bytes

    with tempfile.TemporaryDirectory(prefix=f"openpbr-fuzz-gltf-{index}-") as root:
        seeds = build_seeds(os.path.join(root, "asset"))
        harness = Harness(gltf_exercise(), seeds.folder, failures, hang, index)
        structured_batches(harness, "structured", gltf_inputs(seeds), counts["structured"], seed * 101 + index, batch)
        rng = random.Random(seed * 7919 + index)
        for kind, pool, suffix in (("raw_gltf", seeds.gltf_bytes, ".gltf"), ("raw_glb", seeds.glb_bytes, ".glb")):
            originals = [pool[name] for name in sorted(pool)]
            for _ in range(counts[kind]):
                harness(kind, suffix, mutate_bytes(rng, rng.choice(originals), glb=suffix == ".glb"))
        return harness.figures()


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--structured", type=int, default=40_000)
    parser.add_argument("--raw-gltf", type=int, default=30_000)
    parser.add_argument("--raw-glb", type=int, default=30_000)
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--hang", type=float, default=10.0)
    parser.add_argument("--batch", type=int, default=2000)
    parser.add_argument("--failures", default="fuzz-failures-gltf")
    args = parser.parse_args()
    totals = {"structured": args.structured, "raw_gltf": args.raw_gltf, "raw_glb": args.raw_glb}
    results, wall = run_workers(gltf_worker, totals, args.workers,
                                (args.seed, args.hang, os.path.abspath(args.failures), args.batch))
    print(json.dumps(summarise(results, KINDS, wall, args.workers, args.seed), indent=2))


if __name__ == "__main__":
    main()
