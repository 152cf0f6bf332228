"""Textured evaluator benchmark and the corruption table (issue #14).

    python tests/benchmarks/bench_textured.py [--runs 5]

Prints:

* the time of a 256 x 256 textured sphere preview of the shipped ``textured_wood.mtlx`` (median of
  ``--runs`` after one warm-up that decodes its textures), and of the same with the textures
  decoded each time (a fresh sampler);
* the time of ``convert --verify`` (conversion to .gltf plus per-texel verification, sphere and
  swatch) of a material with four 2048 x 2048 textures (base colour, packed roughness/metalness,
  normal map, specular weight), in process, median of ``--runs``;
* the mean CIEDE2000 (worse of sphere and swatch) of the correct conversions and of every
  corruption of tests/test_texture_corruption.py, per output format.

Single core: set OMP_NUM_THREADS=1 etc. before running for the one-core figure.
"""

from __future__ import annotations

import argparse
import statistics
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
from PIL import Image

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent))
sys.path.insert(0, str(HERE.parent.parent))


def preview_times(runs: int) -> tuple[float, float]:
    from openpbr_tools.evaluate.preview import Rig
    from openpbr_tools.evaluate.textures import TextureSampler
    from openpbr_tools.evaluate.verify import render_material
    from openpbr_tools.io import read_asset
    from openpbr_tools.resources import data_dir

    asset = read_asset(str(data_dir("samples") / "textured_wood.mtlx"))
    rig = Rig(size=256)
    sampler = TextureSampler.for_asset(asset.path)
    render_material(asset.materials[0], rig, sampler)
    warm, cold = [], []
    for _ in range(runs):
        start = time.perf_counter()
        render_material(asset.materials[0], rig, sampler)
        warm.append(time.perf_counter() - start)
        start = time.perf_counter()
        render_material(asset.materials[0], rig, TextureSampler.for_asset(asset.path))
        cold.append(time.perf_counter() - start)
    return statistics.median(warm), statistics.median(cold)


FOUR_2K = """<?xml version="1.0"?>
<materialx version="1.39" colorspace="lin_rec709">
  <image name="b" type="color3"><input name="file" type="filename" value="base.png" colorspace="srgb_texture" /></image>
  <image name="o" type="color3"><input name="file" type="filename" value="orm.png" colorspace="none" /></image>
  <extract name="r" type="float"><input name="in" type="color3" nodename="o" /><input name="index" type="integer" value="1" /></extract>
  <extract name="m" type="float"><input name="in" type="color3" nodename="o" /><input name="index" type="integer" value="2" /></extract>
  <image name="n" type="vector3"><input name="file" type="filename" value="normal.png" colorspace="none" /></image>
  <normalmap name="nm" type="vector3"><input name="in" type="vector3" nodename="n" /></normalmap>
  <image name="s" type="float"><input name="file" type="filename" value="spec.png" colorspace="none" /></image>
  <open_pbr_surface name="Big" type="surfaceshader">
    <input name="base_color" type="color3" nodename="b" />
    <input name="specular_roughness" type="float" nodename="r" />
    <input name="base_metalness" type="float" nodename="m" />
    <input name="geometry_normal" type="vector3" nodename="nm" />
    <input name="specular_weight" type="float" nodename="s" />
  </open_pbr_surface>
  <surfacematerial name="Big_material" type="material"><input name="surfaceshader" type="surfaceshader" nodename="Big" /></surfacematerial>
</materialx>
"""


def verify_time(runs: int) -> tuple[float, float]:
    from openpbr_tools.convert import convert_file
    from openpbr_tools.verification import compare
    from openpbr_tools.translate.common import Settings

    folder = Path(tempfile.mkdtemp(prefix="openpbr-bench-"))
    rng = np.random.default_rng(1)
    n = 2048
    low = rng.integers(0, 256, size=(64, 64, 3), dtype=np.uint8)
    for name in ("base", "orm", "normal", "spec"):
        image = Image.fromarray(low).resize((n, n), Image.BILINEAR)
        if name == "normal":
            pixels = np.asarray(image).copy()
            pixels[..., 2] = 230
            image = Image.fromarray(pixels)
        image.save(folder / f"{name}.png")
    (folder / "big.mtlx").write_text(FOUR_2K)
    converting, verifying = [], []
    for k in range(runs):
        output = folder / f"out{k}.gltf"
        start = time.perf_counter()
        conversion = convert_file(str(folder / "big.mtlx"), str(output), None, Settings(candidates=True))
        middle = time.perf_counter()
        compare(conversion)
        converting.append(middle - start)
        verifying.append(time.perf_counter() - middle)
    return statistics.median(converting), statistics.median(verifying)


def corruption_table() -> list[tuple[str, str, float]]:
    import test_texture_corruption as t

    from openpbr_tools.convert import convert_file
    from openpbr_tools.verification import compare
    from openpbr_tools.evaluate.verify import compare_materials
    from openpbr_tools.translate.common import Settings

    folder = Path(tempfile.mkdtemp(prefix="openpbr-corrupt-"))
    t._textures(folder)
    (folder / "tiles.mtlx").write_text(t.SOURCE)
    rows = []
    for key, (name, target) in sorted(t.OUTPUTS.items()):
        out = folder / key
        out.mkdir()
        conversion = convert_file(str(folder / "tiles.mtlx"), str(out / name), target, Settings())
        for _, comparison in compare(conversion):
            rows.append((f"{key} {comparison.model_b}", "correct", comparison.worst.mean))
        source = conversion.pairs[0][0]
        for corruption, function in sorted(t.CORRUPTIONS.items()):
            for written in t._written(conversion):
                if corruption == "roughness-as-srgb" and not any(n in written.inputs for n in t.ROUGHNESS):
                    continue
                corrupted = function(written, conversion, str(out))
                comparison = compare_materials(source, corrupted, sampler=t._source_sampler(conversion),
                                               sampler_b=t._output_sampler(conversion))
                rows.append((f"{key} {written.model}", corruption, comparison.worst.mean))
    return rows


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=int, default=5)
    args = parser.parse_args()
    warm, cold = preview_times(args.runs)
    print(f"256x256 textured sphere preview (textured_wood.mtlx): {warm * 1000:.0f} ms (textures cached), "
          f"{cold * 1000:.0f} ms (decoded each time)")
    converting, verifying = verify_time(max(1, args.runs // 2))
    print(f"four 2048x2048 textures -> .gltf: conversion {converting:.2f} s, verification (read back, per-texel "
          f"sphere and swatch) {verifying:.2f} s")
    print("mean CIEDE2000 (worse of sphere and swatch), threshold 2:")
    for output, case, value in corruption_table():
        print(f"  {output:40s} {case:20s} {value:7.2f}")


if __name__ == "__main__":
    main()
