"""MaterialX's example library (tests/data/published/materialx/resources/Materials/Examples: Standard
Surface, glTF PBR and UsdPreviewSurface materials, several textured or procedural) converted to OpenPBR,
by ``openpbr convert --to open_pbr_surface`` and by MaterialX's own ShaderTranslator (its translation
graphs, e.g. ``standard_surface_to_open_pbr``, which keeps the upstream graphs), each judged by MaterialX's
GLSL renderer against the original material (Xvfb + Mesa; tests/glsupport.py). #13's measure of the
"other direction" (78% under 2.3 when it was filed).

    python tests/benchmarks/bench_glsl_examples_to_openpbr.py [--only SUBSTR] [--size 64]

The library's layout is kept (its textures are in resources/Images, ``../../../Images`` from each example,
outside the example's folder: the conversion is allowed that folder, as ``--allow-outside`` does).
Each material is rendered on its own (its textures sampled by MaterialX, V flipped as MaterialXView does).
Prints one row per material: the toolkit's mean CIEDE2000 over the lit sphere, the chain's (``-`` where
MaterialX has no translation graph for the model or its translation fails), then the share under 2.3
and the rows where the toolkit is worse than the chain by more than 0.5.
"""

from __future__ import annotations

import argparse
import os
import shutil
import statistics
import sys
import tempfile

import MaterialX as mx
import MaterialX.PyMaterialXGenShader as gs

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, ".."))

from glsupport import comparison_mask, materialx_renderer, mean_delta_e, single_material  # noqa: E402
from openpbr_tools.convert import convert_file  # noqa: E402
from openpbr_tools.evaluate.preview import Rig  # noqa: E402
from openpbr_tools.translate.common import Settings  # noqa: E402

RESOURCES = os.path.join(HERE, "..", "data", "published", "materialx", "resources")
MODELS = ("StandardSurface", "GltfPbr", "UsdPreviewSurface")
LIMIT = 2.3


def _chain(source: str, out: str, library) -> bool:
    """MaterialX's ShaderTranslator: every material of ``source`` to open_pbr_surface, written to ``out``."""
    document = mx.createDocument()
    mx.readFromXmlFile(document, source)
    document.importLibrary(library)
    try:
        gs.ShaderTranslator.create().translateAllMaterials(document, "open_pbr_surface")
    except Exception:  # no graph for the model, or the translation fails: no chain figure
        return False
    options = mx.XmlWriteOptions()  # the document's own elements and the translator's, not the library's
    options.elementPredicate = lambda element: element.getActiveSourceUri() in ("", document.getSourceUri())
    mx.writeToXmlFile(document, out, options)
    return True


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--only", metavar="SUBSTR")
    parser.add_argument("--size", type=int, default=64)
    arguments = parser.parse_args()
    rig = Rig(size=arguments.size)
    renderer = materialx_renderer(rig)
    mask = comparison_mask(rig)
    rows = []
    with tempfile.TemporaryDirectory(prefix="openpbr-examples-") as scratch:
        resources = os.path.join(scratch, "resources")
        shutil.copytree(RESOURCES, resources)  # the examples' textures are in resources/Images (../../../Images)
        for model in MODELS:
            folder = os.path.join(resources, "Materials", "Examples", model)
            for name in sorted(os.listdir(folder)):
                if not name.endswith(".mtlx") or (arguments.only and arguments.only not in name):
                    continue
                source = os.path.join(folder, name)
                stem = name[:-5]
                document = mx.createDocument()
                mx.readFromXmlFile(document, source)
                # a look file's materials come from its XIncludes: measured with their own files
                included = [m.getName() for m in document.getMaterialNodes()
                            if m.getActiveSourceUri() != document.getSourceUri()]
                materials = [m.getName() for m in document.getMaterialNodes() if m.getName() not in included]
                if included:
                    print(f"{stem:44s} (XIncluded, measured with their files: {', '.join(included)})", flush=True)
                ours = os.path.join(folder, f"_{stem}__openpbr.mtlx")
                theirs = os.path.join(folder, f"_{stem}__chain.mtlx")
                try:
                    convert_file(source, ours, "open_pbr_surface", Settings(), allow_outside=(resources,))
                except Exception as error:  # a failed conversion is a finding: report it, go on
                    print(f"{stem:44s} FAIL conversion: {error!r}", flush=True)
                    rows += [(stem, m, float("inf"), None) for m in materials]
                    continue
                chained = _chain(source, theirs, renderer.library)
                for material in materials:
                    def render(path, label):
                        try:
                            return renderer.render_document(single_material(path, material, os.path.join(
                                folder, f"_{stem}__{material}__{label}.mtlx")))
                        except Exception as error:  # reported, the run goes on
                            print(f"    {stem} {material} {label}: render failed: {error!r}", flush=True)
                            return None
                    reference = render(source, "reference")
                    if reference is None:
                        continue
                    image = render(ours, "openpbr")
                    delta = mean_delta_e(image, reference, mask, rig.white()) if image is not None else float("inf")
                    chain_image = render(theirs, "chain") if chained else None
                    chain = mean_delta_e(chain_image, reference, mask, rig.white()) if chain_image is not None else None
                    rows.append((stem, material, delta, chain))
                    print(f"{stem:44s} {material:28s} {delta:7.2f}  chain {'-' if chain is None else f'{chain:6.2f}'}",
                          flush=True)
    finite = [r[2] for r in rows]
    print(f"\n{len(rows)} materials; toolkit under {LIMIT}: {sum(d < LIMIT for d in finite)} "
          f"({sum(d < LIMIT for d in finite) / max(len(finite), 1):.0%}), median {statistics.median(finite):.2f}")
    chained = [r for r in rows if r[3] is not None]
    if chained:
        print(f"where MaterialX's chain translates ({len(chained)}): toolkit under {LIMIT} "
              f"{sum(r[2] < LIMIT for r in chained)}, chain {sum(r[3] < LIMIT for r in chained)}")
        worse = [r for r in chained if r[2] > r[3] + 0.5]
        print(f"toolkit worse than the chain by more than 0.5: {len(worse)}")
        for stem, material, delta, chain in sorted(worse, key=lambda r: r[3] - r[2]):
            print(f"    {stem} {material}: {delta:.2f} vs {chain:.2f}")


if __name__ == "__main__":
    main()
