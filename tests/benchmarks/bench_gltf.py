"""Benchmark the glTF reader, rules and writer on one file with many textured materials.

    python tests/benchmarks/bench_gltf.py [--materials 500] [--repeat 5] [--format glb|gltf]

Each material has eight factors, a base-colour texture, a metallic-roughness texture with a
KHR_texture_transform and a clearcoat extension; the two 64 x 64 PNGs exist beside the file (or in
the GLB's binary chunk). Measured (median wall time): ``read_asset``, ``validate_file`` (reading and
every rule), and ``write_gltf`` of what was read to a GLB with the preview spheres (images passed
through, not baked).
"""

from __future__ import annotations

import argparse
import os
import statistics
import sys
import tempfile
import time


def generate(folder: str, count: int, fmt: str) -> str:
    import numpy as np
    from PIL import Image

    from openpbr_tools.io.gltf.writer import write_gltf
    from openpbr_tools.model import Texture, UVTransform

    sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
    from gltf_support import gltf_pbr_material

    rng = np.random.default_rng(1)
    Image.fromarray(rng.integers(0, 256, (64, 64, 3), dtype=np.uint8)).save(os.path.join(folder, "albedo.png"))
    Image.fromarray(rng.integers(0, 256, (64, 64, 3), dtype=np.uint8)).save(os.path.join(folder, "orm.png"))
    uv = UVTransform(scale=(2.0, 2.0), pivot=(0.0, 1.0))
    materials = [
        gltf_pbr_material(
            f"M{i:04d}", base_color=Texture("albedo.png", channels=(0, 1, 2), colorspace="srgb_texture"),
            metallic=Texture("orm.png", channels=(2,), colorspace="none", uv=uv),
            roughness=Texture("orm.png", channels=(1,), colorspace="none", uv=uv, scale=0.8),
            emissive=(0.0, 0.0, 0.1), alpha_cutoff=0.5, clearcoat=0.5, clearcoat_roughness=0.1, ior=1.5,
            specular=1.0, sheen_color=(0.1, 0.1, 0.1), sheen_roughness=0.3,
        )
        for i in range(count)
    ]
    path = os.path.join(folder, f"bench.{fmt}")
    write_gltf(materials, path, source=os.path.join(folder, "bench.mtlx"))
    return path


def median_time(function, repeat: int) -> float:
    times = []
    for _ in range(repeat):
        start = time.perf_counter()
        function()
        times.append(time.perf_counter() - start)
    return statistics.median(times)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--materials", type=int, default=500)
    parser.add_argument("--repeat", type=int, default=5)
    parser.add_argument("--format", choices=("glb", "gltf"), default="glb")
    options = parser.parse_args()

    from openpbr_tools.io import read_asset
    from openpbr_tools.io.gltf.writer import write_gltf
    from openpbr_tools.validate import validate_file

    with tempfile.TemporaryDirectory() as folder:
        path = generate(folder, options.materials, options.format)
        asset = read_asset(path)
        out = os.path.join(folder, "out", "copy.glb")
        os.makedirs(os.path.dirname(out))
        print(f"{options.materials} materials, {os.path.getsize(path) / 1024:.0f} KiB {options.format}")
        print(f"  read_asset      {median_time(lambda: read_asset(path), options.repeat) * 1000:8.1f} ms")
        print(f"  validate_file   {median_time(lambda: validate_file(path), options.repeat) * 1000:8.1f} ms")
        print(f"  write_gltf glb  {median_time(lambda: write_gltf(asset.materials, out, mesh='sphere', source=asset), options.repeat) * 1000:8.1f} ms")


if __name__ == "__main__":
    main()
