"""Every material of the published corpus's files (default: tests/data/published/gltf_samples, Khronos' sample
models) converted to each target and judged on the toolkit's evaluator (``verification.measure``: the output
read back, mean CIEDE2000 over the lit sphere or the texture swatch, whichever differs more).

    python tests/benchmarks/sweep_published_fidelity.py [--root FOLDER] [--suffixes .gltf,.mtlx] [--worst 40]

Prints per target the count, the median and how many are over 2.3 and the maximum, then the worst rows. The
vendored textures are 4x4 grey stand-ins, so textured materials are judged on near-constant images.
UsdPreviewSurface cannot hold sheen, transmission, coats or films: its tail is mostly the target's limit.
"""

from __future__ import annotations

import argparse
import os
import statistics
import sys
import tempfile
from pathlib import Path

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", ".."))

from openpbr_tools.convert import convert_file  # noqa: E402
from openpbr_tools.io import ReadError  # noqa: E402
from openpbr_tools.io.gltf.images import GltfWriteError  # noqa: E402
from openpbr_tools.translate.common import Settings  # noqa: E402
from openpbr_tools.verification import measure  # noqa: E402

TARGETS = (("mtlx", "open_pbr_surface"), ("mtlx", "standard_surface"), ("gltf", "gltf_pbr"),
           ("mtlx", "UsdPreviewSurface"))
ROOT = Path(__file__).resolve().parents[1] / "data" / "published" / "gltf_samples"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--root", default=str(ROOT))
    parser.add_argument("--suffixes", default=".gltf")
    parser.add_argument("--worst", type=int, default=40)
    args = parser.parse_args()
    suffixes = tuple(args.suffixes.split(","))
    files = sorted(p for p in Path(args.root).rglob("*") if p.suffix in suffixes)
    rows = []
    with tempfile.TemporaryDirectory() as folder:
        for path in files:
            for suffix, model in TARGETS:
                try:
                    conversion = convert_file(str(path), os.path.join(folder, f"out.{suffix}"), model, Settings(),
                                              allow_outside=(str(Path(args.root).resolve()),))
                except (ReadError, GltfWriteError) as error:  # unreadable, or a texture outside --root
                    print(f"skipped {path.relative_to(args.root)} -> {model}: {error}")
                    continue
                rows += [(delta.mean, model, str(path.relative_to(args.root)), source.name)
                         for source, delta in measure(conversion)]
    for _, model in TARGETS:
        values = [mean for mean, target, _, _ in rows if target == model]
        print(f"{model:18s} n {len(values):4d}  median {statistics.median(values):5.2f}  "
              f"over 2.3 {sum(v > 2.3 for v in values):3d}  max {max(values):5.1f}")
    for mean, model, file, name in sorted(rows, reverse=True)[:args.worst]:
        print(f"{mean:6.2f}  {model:18s} {file} :: {name}")


if __name__ == "__main__":
    main()
