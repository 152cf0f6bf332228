"""The vendored Khronos glTF sample models (tests/data/published/gltf/*/) converted by
``openpbr_tools.convert.convert_file`` to each target, judged by MaterialX's GLSL renderer against an
independent reference per glTF material (Xvfb + Mesa; tests/glsupport.py).

    python tests/benchmarks/bench_glsl_gltf_samples.py [--only FOLDER] [--targets open_pbr_surface ...] [--size 64]

The reference (gltf_reference.py) is a MaterialX ``gltf_pbr`` document (``surface_unlit`` for
KHR_materials_unlit) built straight from the glTF JSON, not through the toolkit's reader. Each
sample folder is copied to a temporary folder first; references, conversions and renders stay
there and are removed at the end. A converted document holds one surfacematerial per glTF
material, in the glTF's order; each is rendered on its own. Prints one line per material and
target (mean CIEDE2000 over the lit sphere; notes on what the reference leaves out), then per
target the count, the median and how many are over 2.3, then every row over 2.3.

Read the rows over 2.3 knowing what MaterialX 1.39.5's GLSL gltf_pbr does not render, so that a
difference there is the renderer's or the reference's limit, not the conversion's:
KHR_materials_volume attenuation (attenuation_color / attenuation_distance are ignored: tinted
thick glass renders untinted), KHR_materials_dispersion, KHR_materials_diffuse_transmission (no
gltf_pbr input: the reference renders those materials opaque), and transmission beyond the uniform
environment (no refraction of the scene: transmissive materials show the environment colour
through the surface). The vendored textures are 4x4 placeholders, so textured materials are judged
on near-constant images: texture wiring is checked, texture detail is not.
"""

from __future__ import annotations

import argparse
import glob
import os
import shutil
import statistics
import sys
import tempfile

import MaterialX as mx
import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, ".."))
sys.path.insert(0, HERE)

from gltf_reference import GltfReference  # noqa: E402
from glsupport import comparison_mask, materialx_renderer, mean_delta_e, single_material  # noqa: E402
from openpbr_tools.convert import convert_file  # noqa: E402
from openpbr_tools.evaluate.preview import Rig  # noqa: E402
from openpbr_tools.translate.common import Settings  # noqa: E402

SAMPLES = os.path.join(HERE, "..", "data", "published", "gltf")
TARGETS = ("open_pbr_surface", "standard_surface", "UsdPreviewSurface", "gltf_pbr")
LIMIT = 2.3


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--only", metavar="FOLDER", help="one sample folder, e.g. ClearCoatTest")
    parser.add_argument("--samples", default=SAMPLES,
                        help="the folder of sample folders (tests/data/published/gltf_samples: 60 more models)")
    parser.add_argument("--targets", nargs="+", choices=TARGETS, default=list(TARGETS))
    parser.add_argument("--size", type=int, default=64, help="rig pixels")
    arguments = parser.parse_args()
    folders = sorted(os.path.basename(p) for p in glob.glob(os.path.join(arguments.samples, "*")) if os.path.isdir(p))
    if arguments.only:
        if arguments.only not in folders:
            parser.error(f"--only: no sample folder {arguments.only!r} (have {', '.join(folders)})")
        folders = [arguments.only]
    rig = Rig(size=arguments.size)
    renderer = materialx_renderer(rig)
    mask = comparison_mask(rig)

    def mean_delta(image: np.ndarray, reference: np.ndarray) -> float:
        return mean_delta_e(image, reference, mask, rig.white())

    rows = []
    with tempfile.TemporaryDirectory(prefix="openpbr-gltf-samples-") as scratch:
        for target in arguments.targets:
            os.makedirs(os.path.join(scratch, target))
        os.makedirs(os.path.join(scratch, "reference"))
        for folder in folders:
            shutil.copytree(os.path.join(arguments.samples, folder), os.path.join(scratch, "samples", folder))
            for source in sorted(glob.glob(os.path.join(scratch, "samples", folder, "*.gltf"))):
                stem = os.path.splitext(os.path.basename(source))[0]
                gltf = GltfReference(source)
                references = []
                for index in range(len(gltf.materials)):
                    path = os.path.join(scratch, "reference", f"{stem}__{index:02d}.mtlx")
                    notes = gltf.write(index, path)
                    references.append((renderer.render_document(path), notes))
                for target in arguments.targets:
                    converted = os.path.join(scratch, target, f"{stem}.mtlx")
                    try:
                        convert_file(source, converted, target, Settings())
                    except Exception as error:  # a failed conversion is a finding: report it, go on
                        print(f"{stem:24s} {target}: conversion failed: {error!r}")
                        continue
                    doc = mx.createDocument()
                    mx.readFromXmlFile(doc, converted)
                    names = [m.getName() for m in doc.getMaterialNodes()]
                    if len(names) != len(gltf.materials):
                        print(f"{stem:24s} {target}: {len(names)} materials written for {len(gltf.materials)}")
                        continue
                    for index, (name, (reference, notes)) in enumerate(zip(names, references)):
                        alone = single_material(converted, name, os.path.join(scratch, target, f"{stem}__{index:02d}.mtlx"))
                        delta = mean_delta(renderer.render_document(alone), reference)
                        label = str(gltf.materials[index].get("name", name))
                        rows.append((stem, index, label, target, delta))
                        print(f"{stem:24s} {index:2d} {label[:30]:30s} {target:18s} {delta:6.2f}"
                              + (f"  ({'; '.join(notes)})" if notes else ""), flush=True)
    print()
    for target in arguments.targets:
        found = [row[4] for row in rows if row[3] == target]
        finite = [d for d in found if np.isfinite(d)]
        if not finite:
            continue
        not_finite = len(found) - len(finite)
        print(f"{target}: {len(found)} materials; median {statistics.median(finite):.2f}; "
              f"over {LIMIT}: {sum(d > LIMIT for d in finite)}" + (f"; not finite: {not_finite}" if not_finite else ""))
    over = [row for row in rows if row[4] > LIMIT]
    if over:
        print(f"\nover {LIMIT}:")
        for stem, index, label, target, delta in over:
            print(f"    {delta:6.2f}  {target:18s} {stem} {index}: {label}")


if __name__ == "__main__":
    main()
