"""What checking texture files costs `validate` (OPBR707/708 read every texture's data, OPBR709 its
header): generated textured materials (a 2K JPEG base colour, a 2K PNG packed roughness and a 2K PNG
normal map each), validated in process with the checks and with them switched off, side by side.

    python tests/benchmarks/bench_texture_checks.py [--materials 10] [--size 2048] [--repeat 5]

Prints the median seconds of each and their ratio.
"""

from __future__ import annotations

import argparse
import os
import statistics
import sys
import tempfile
import time

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", ".."))

DOCUMENT = """<?xml version="1.0"?>
<materialx version="1.39" colorspace="lin_rec709">
  <image name="a" type="color3"><input name="file" type="filename" value="albedo{i}.jpg" colorspace="srgb_texture" /></image>
  <image name="o" type="color3"><input name="file" type="filename" value="orm{i}.png" /></image>
  <extract name="r" type="float"><input name="in" type="color3" nodename="o" /><input name="index" type="integer" value="1" /></extract>
  <image name="n" type="vector3"><input name="file" type="filename" value="normal{i}.png" /></image>
  <normalmap name="nm" type="vector3"><input name="in" type="vector3" nodename="n" /></normalmap>
  <open_pbr_surface name="s" type="surfaceshader">
    <input name="base_color" type="color3" nodename="a" />
    <input name="specular_roughness" type="float" nodename="r" />
    <input name="geometry_normal" type="vector3" nodename="nm" />
  </open_pbr_surface>
  <surfacematerial name="m" type="material"><input name="surfaceshader" type="surfaceshader" nodename="s" /></surfacematerial>
</materialx>
"""


def _corpus(folder: str, materials: int, size: int) -> None:
    import numpy as np
    from PIL import Image

    generator = np.random.default_rng(0)
    for i in range(materials):
        blocks = np.kron(generator.integers(0, 255, (size // 32, size // 32, 3)), np.ones((32, 32, 1)))
        base = (blocks + generator.integers(-8, 8, (size, size, 3))).clip(0, 255).astype("uint8")
        Image.fromarray(base).save(os.path.join(folder, f"albedo{i}.jpg"), quality=90)
        Image.fromarray(base[..., ::-1].copy()).save(os.path.join(folder, f"orm{i}.png"))
        normal = np.zeros((size, size, 3), "uint8")
        normal[..., 0], normal[..., 1], normal[..., 2] = 128 + generator.integers(-20, 20, (size, size)), 128, 255
        Image.fromarray(normal).save(os.path.join(folder, f"normal{i}.png"))
        with open(os.path.join(folder, f"m{i}.mtlx"), "w", encoding="utf-8") as handle:
            handle.write(DOCUMENT.format(i=i))


def _seconds(folder: str, repeat: int) -> float:
    from openpbr_tools.io import image_files
    from openpbr_tools.validate import Options, validate_paths

    times = []
    for _ in range(repeat):
        image_files._damage_of_file.cache_clear()
        start = time.perf_counter()
        validate_paths([folder], options=Options(use_config=False, jobs=1))
        times.append(time.perf_counter() - start)
    return statistics.median(times)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--materials", type=int, default=10)
    parser.add_argument("--size", type=int, default=2048)
    parser.add_argument("--repeat", type=int, default=5)
    arguments = parser.parse_args()
    from openpbr_tools.rules import textures

    folder = tempfile.mkdtemp(prefix="openpbr-texture-checks-")
    _corpus(folder, arguments.materials, arguments.size)
    _seconds(folder, 1)  # imports and the library index, once
    checked = _seconds(folder, arguments.repeat)
    real_damage, real_channels = textures.damage, textures._channels
    textures.damage, textures._channels = (lambda image: None), (lambda *args: None)
    try:
        unchecked = _seconds(folder, arguments.repeat)
    finally:
        textures.damage, textures._channels = real_damage, real_channels
    print(f"{arguments.materials} materials, {3 * arguments.materials} textures of {arguments.size}^2: "
          f"with the file checks {checked:.3f} s, without {unchecked:.3f} s, ratio {checked / unchecked:.2f}x "
          f"({(checked - unchecked) / (3 * arguments.materials) * 1000:.1f} ms per texture)")


if __name__ == "__main__":
    main()
