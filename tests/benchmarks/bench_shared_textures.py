"""Textures shared by many files of one batch run: decoded and encoded once (the run cache in
openpbr_tools/bake_cache.py) against once per file, side by side in one process.

    python tests/benchmarks/bench_shared_textures.py [--files 40] [--size 1024]

Every file is an OpenPBR material with a coat whose base colour texture (one shared sRGB image)
must be baked for glTF (the coat's colour folds into the base colour).
"""

from __future__ import annotations

import argparse
import shutil
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
from PIL import Image

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
sys.path.insert(0, str(Path(__file__).resolve().parents[2]))

from test_bake_shared import DOC  # noqa: E402

from openpbr_tools import bake_cache  # noqa: E402
from openpbr_tools.batch import Job, convert_jobs  # noqa: E402


class _NoSharing(bake_cache.RunCache):
    def pixels(self, path, levels):
        return bake_cache.load_pixels(path, levels)

    def encoded(self, values, how, encode):
        return encode()


def run(folder: Path, files: int, cache) -> float:
    bake_cache.RUN = cache
    out = folder / "out"
    shutil.rmtree(out, ignore_errors=True)
    jobs = [Job(str(folder / "in" / f"m{i}.mtlx"), str(out / f"m{i}.gltf")) for i in range(files)]
    start = time.perf_counter()
    convert_jobs(jobs)
    return time.perf_counter() - start


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--files", type=int, default=40)
    parser.add_argument("--size", type=int, default=1024)
    args = parser.parse_args()
    folder = Path(tempfile.mkdtemp(prefix="openpbr-shared-"))
    (folder / "in" / "textures").mkdir(parents=True)
    low = np.random.default_rng(0).integers(0, 256, size=(64, 64, 3), dtype=np.uint8)
    Image.fromarray(low).resize((args.size, args.size), Image.BILINEAR).save(folder / "in" / "textures" / "shared.png")
    for i in range(args.files):
        (folder / "in" / f"m{i}.mtlx").write_text(DOC.format(i=i))
    run(folder, 1, _NoSharing())  # warm-up: imports and tables load outside the timings
    shared, separate = run(folder, args.files, bake_cache.RunCache()), run(folder, args.files, _NoSharing())
    print(f"{args.files} files sharing one {args.size}x{args.size} texture -> .gltf: {shared:.2f} s decoded and "
          f"encoded once, {separate:.2f} s once per file ({separate / shared:.1f}x)")
    shutil.rmtree(folder, ignore_errors=True)


if __name__ == "__main__":
    main()
