"""The vendored USD test assets (tests/data/published/usd: OpenUSD's testUsdImagingGLPreviewSurface
scenes, the USD-WG AlphaBlendSortTest, the MaterialX-in-USD usd_preview_surface_gold) converted by
``openpbr_tools.convert.convert_file`` to each .mtlx target, judged by MaterialX's GLSL renderer
against an independent reference per UsdPreviewSurface material (Xvfb + Mesa; tests/glsupport.py).

    python tests/benchmarks/bench_glsl_usd_assets.py [--only SUBSTR] [--targets open_pbr_surface ...] [--size 64]

The reference (usd_reference.py) is MaterialX's own ``UsdPreviewSurface`` node (with
``UsdUVTexture``, ``UsdTransform2d`` and ``texcoord`` for the texture networks) built with usd-core
(``pxr.UsdShade``) straight from the stage, not through the toolkit's reader. Its choices, where
the UsdPreviewSurface specification leaves the renderer room or one sphere cannot show a material:
opacityMode unauthored is ``transparent``, MaterialX 1.39.5's default (the "presence" reading, alpha
blending as Storm does, is printed beside rows with partial opacity but not judged); an unset
sourceColorSpace is ``auto``, which decodes 8-bit RGB(A) images as sRGB (others raw); wrap
``useMetadata`` is ``black`` per the specification; an input driven by a UsdPrimvarReader (a
per-prim value) is read at the reader's fallback, and the row says so. Stages whose
UsdPreviewSurface lives in a referenced .mtlx file (MaterialXTest, TextureCoordinateTest) have no
material usd-core can read without its usdMtlx file-format plugin, and are listed as skipped.

The vendored tree is copied to a temporary folder first (its stages reference across folders, e.g.
../_common/teapot.usda); references, conversions and renders stay there and are removed at the end.
Each converted document is written with one surfacematerial per USD material; each is rendered on
its own. Prints one line per material and target (mean CIEDE2000 over the lit sphere; FAIL when
the conversion, or MaterialX's shader generation for its output, fails: reported, and the run goes
on), then per target the count rendered, the failures, the median and how many are over 2.3, then
every row over 2.3 or failed, worst first.

Read the rows over 2.3 knowing the reference's limits. The vendored textures are 4x4 placeholders,
so textured materials are judged on near-constant images: texture wiring and colour spaces are
checked, texture detail is not. MaterialX's GLSL UsdPreviewSurface specular workflow
(useSpecularWorkflow 1) is not energy conserving: its generalized_schlick_bsdf layer passes a grey
1 - average albedo as the throughput to the diffuse base, so a coloured specularColor does not
darken the base by its colour. Coloured-specular rows to OpenPBR and Standard Surface (which do
conserve energy) are judged against that reference (testPreviewSurfaceSpecular: the reference's
red base stays brighter than OpenPBR's or Standard Surface's under the same coloured specular).
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

from glsupport import comparison_mask, materialx_renderer, mean_delta_e, single_material  # noqa: E402
from openpbr_tools.convert import convert_file  # noqa: E402
from openpbr_tools.evaluate.preview import Rig  # noqa: E402
from openpbr_tools.translate.common import Settings  # noqa: E402
from usd_reference import UsdReference  # noqa: E402

ASSETS = os.path.join(HERE, "..", "data", "published", "usd")
TARGETS = ("open_pbr_surface", "standard_surface", "gltf_pbr", "UsdPreviewSurface")
LIMIT = 2.3
FAIL = float("inf")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--only", metavar="SUBSTR", help="stages whose path below tests/data/published/usd contains SUBSTR")
    parser.add_argument("--targets", nargs="+", choices=TARGETS, default=list(TARGETS))
    parser.add_argument("--size", type=int, default=64, help="rig pixels")
    arguments = parser.parse_args()
    stages = sorted(os.path.relpath(p, ASSETS) for p in glob.glob(os.path.join(ASSETS, "**", "*.usd*"), recursive=True))
    if arguments.only:
        stages = [s for s in stages if arguments.only in s]
        if not stages:
            parser.error(f"--only: no stage below {os.path.normpath(ASSETS)} matches {arguments.only!r}")
    rig = Rig(size=arguments.size)
    renderer = materialx_renderer(rig)
    mask = comparison_mask(rig)

    def mean_delta(image: np.ndarray, reference: np.ndarray) -> float:
        return mean_delta_e(image, reference, mask, rig.white())

    rows, skipped = [], []

    def fail(stem: str, name: str, target: str, why: str) -> None:
        rows.append((stem, name, target, FAIL))
        print(f"{stem:34s} {name:14s} {target:18s} {'FAIL':>6s}  {why}", flush=True)

    with tempfile.TemporaryDirectory(prefix="openpbr-usd-assets-") as scratch:
        shutil.copytree(ASSETS, os.path.join(scratch, "assets"))
        for number, relative in enumerate(stages):
            source = os.path.join(scratch, "assets", relative)
            usd = UsdReference(source)
            if not usd.materials:
                skipped.append(relative)
                continue
            stem = os.path.splitext(os.path.basename(source))[0]
            work = os.path.join(scratch, f"{number:02d}-{stem}")
            for sub in ("reference", *arguments.targets):
                os.makedirs(os.path.join(work, sub))
            references = []
            for index, (name, _, _) in enumerate(usd.materials):
                path = os.path.join(work, "reference", f"{name}.mtlx")
                notes = usd.write(index, path)
                presence = None
                if usd.has_partial_opacity(index):
                    usd.write(index, os.path.join(work, "reference", f"{name}__presence.mtlx"), presence=True)
                    presence = renderer.render_document(os.path.join(work, "reference", f"{name}__presence.mtlx"))
                references.append((name, renderer.render_document(path), presence, notes))
            for target in arguments.targets:
                converted = os.path.join(work, target, f"{stem}.mtlx")
                doc = mx.createDocument()
                try:
                    convert_file(source, converted, target, Settings())
                    mx.readFromXmlFile(doc, converted)
                except Exception as error:  # a failed conversion is a finding: report it, go on
                    for name, *_ in references:
                        fail(stem, name, target, f"conversion failed: {error!r}")
                    continue
                names = [m.getName() for m in doc.getMaterialNodes()]
                for name, reference, presence, notes in references:
                    if name not in names:
                        fail(stem, name, target, f"not in the converted document (it has {', '.join(names) or 'no material'})")
                        continue
                    alone = single_material(converted, name, os.path.join(work, target, f"{name}.mtlx"))
                    try:
                        image = renderer.render_document(alone)
                    except Exception as error:  # shader generation refused the output: a finding
                        fail(stem, name, target, f"render failed: {error!r}")
                        continue
                    delta = mean_delta(image, reference)
                    rows.append((stem, name, target, delta))
                    extra = f"  (presence reading {mean_delta(image, presence):.2f})" if presence is not None else ""
                    print(f"{stem:34s} {name:14s} {target:18s} {delta:6.2f}{extra}"
                          + (f"  ({'; '.join(notes)})" if notes else ""), flush=True)
    if skipped:
        print(f"\nstages skipped (no UsdPreviewSurface material usd-core can read): "
              f"{', '.join(os.path.basename(s) for s in skipped)}")
    print()
    for target in arguments.targets:
        found = [row[3] for row in rows if row[2] == target]
        failed = sum(d == FAIL for d in found)
        rendered = [d for d in found if d != FAIL]
        finite = [d for d in rendered if np.isfinite(d)]
        median = f"{statistics.median(finite):.2f}" if finite else "-"
        print(f"{target}: {len(rendered)} rendered; {failed} failed; median {median}; "
              f"over {LIMIT}: {sum(d > LIMIT for d in finite)}"
              + (f"; not finite: {len(rendered) - len(finite)}" if len(finite) != len(rendered) else ""))
    over = sorted((row for row in rows if row[3] > LIMIT), key=lambda row: -row[3])
    if over:
        print(f"\nover {LIMIT} or failed, worst first:")
        for stem, name, target, delta in over:
            print(f"    {'FAIL' if delta == FAIL else f'{delta:6.2f}':>6s}  {target:18s} {stem} {name}")


if __name__ == "__main__":
    main()
