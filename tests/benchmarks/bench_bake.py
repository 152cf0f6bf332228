"""Benchmark: baking 2K textures during a conversion.

    python tests/benchmarks/bench_bake.py [--size 2048] [--repeat 3]

An OpenPBR material with a 2K sRGB base colour under a coat (the coat darkening is folded into the
base colour per texel) and a 2K roughness with anisotropy (glTF roughness and anisotropy strength
per texel) is converted to .gltf, .glb and Standard Surface .mtlx. Prints the best wall time per
output and the per-stage split of one .gltf conversion (translate+bake vs write), as JSON.
"""

from __future__ import annotations

import argparse
import json
import os
import sys
import tempfile
import time

import numpy as np
from PIL import Image

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", ".."))

from openpbr_tools.convert import convert_file  # noqa: E402

DOCUMENT = """<?xml version="1.0"?>
<materialx version="1.39" colorspace="lin_rec709">
  <image name="c" type="color3"><input name="file" type="filename" value="albedo.png" colorspace="srgb_texture"/></image>
  <image name="r" type="float"><input name="file" type="filename" value="rough.png"/></image>
  <open_pbr_surface name="S" type="surfaceshader">
    <input name="base_color" type="color3" nodename="c"/>
    <input name="specular_roughness" type="float" nodename="r"/>
    <input name="specular_roughness_anisotropy" type="float" value="0.5"/>
    <input name="coat_weight" type="float" value="1"/>
  </open_pbr_surface>
  <surfacematerial name="M" type="material"><input name="surfaceshader" type="surfaceshader" nodename="S"/></surfacematerial>
</materialx>
"""


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--size", type=int, default=2048)
    parser.add_argument("--repeat", type=int, default=3)
    args = parser.parse_args()
    rng = np.random.default_rng(0)
    # Wood-like images (rings plus grain noise): PNG compresses them as it does real textures, not
    # as it does white noise (which would make the benchmark measure zlib's worst case).
    y, x = np.mgrid[0:args.size, 0:args.size] / args.size
    rings = 0.5 + 0.5 * np.sin(40.0 * np.hypot(x - 0.3, y + 0.2) + 3.0 * np.sin(7.0 * x))
    grain = rng.normal(0.0, 0.02, rings.shape)
    albedo = np.stack([0.45 + 0.25 * rings, 0.28 + 0.15 * rings, 0.12 + 0.08 * rings], axis=-1) + grain[..., None]
    rough = 0.35 + 0.3 * rings + grain
    with tempfile.TemporaryDirectory() as folder:
        Image.fromarray(np.round(np.clip(albedo, 0, 1) * 255).astype(np.uint8)).save(os.path.join(folder, "albedo.png"))
        Image.fromarray(np.round(np.clip(rough, 0, 1) * 255).astype(np.uint8)).save(os.path.join(folder, "rough.png"))
        source = os.path.join(folder, "m.mtlx")
        with open(source, "w") as handle:
            handle.write(DOCUMENT)
        results = {"size": args.size, "textures baked per conversion": None, "seconds": {}}
        for output, target in (("out.gltf", None), ("out.glb", None), ("ss.mtlx", "standard_surface")):
            best = float("inf")
            for _ in range(args.repeat):
                path = os.path.join(folder, f"{time.perf_counter_ns()}_{output}")
                start = time.perf_counter()
                conversion = convert_file(source, path, target)
                best = min(best, time.perf_counter() - start)
            baked = sum("baked per texel" in d.message for d in conversion.diagnostics)
            results["seconds"][output] = round(best, 3)
            results.setdefault("baked", {})[output] = baked
        results.pop("textures baked per conversion")
        megapixels = args.size * args.size / 1e6
        results["megapixels per texture"] = round(megapixels, 2)
    print(json.dumps(results, indent=2))


if __name__ == "__main__":
    main()
