"""glTF KHR_materials_pbrSpecularGlossiness materials converted to OpenPBR, judged against what a viewer of
the extension renders: MaterialX's gltf_pbr holding the extension's BRDF inputs (c_diff = D (1 - max S) as a
dielectric's base colour, F0 = S through KHR_materials_specular's colour S / 0.04, roughness 1 - g), in
MaterialX's GLSL (``--glsl``) and on the evaluator (which renders a glTF file's spec-gloss material the same
way: openpbr_tools/evaluate/parameters.py).

    python tests/benchmarks/bench_spec_gloss.py [--count 20] [--seed 11] [--glsl]

Per material: the fallback reading (what conversions did before they read the extension: glTF's default
metallic-roughness, a white rough metal, as such files author none), the solve alone (``Settings(candidates=
False)``) and the conversion (the candidate search: the second reading and the appearance fit). Six fixed
cases (a plastic, the extension's gold, a copper, ...) then random ones: D uniform, each channel of S uniform in
[0, 0.25] (strongly coloured F0s over coloured diffuse colours: harder than exporters' usual grey 0.04).
"""

from __future__ import annotations

import argparse
import json
import os
import sys
import tempfile

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))

from openpbr_tools.convert import convert_file  # noqa: E402
from openpbr_tools.evaluate.preview import Rig  # noqa: E402
from openpbr_tools.evaluate.verify import compare_materials  # noqa: E402
from openpbr_tools.io import read_asset  # noqa: E402
from openpbr_tools.model import Location, Material  # noqa: E402
from openpbr_tools.translate.common import Settings  # noqa: E402

FIXED = [((0.8, 0.2, 0.1), (0.04, 0.04, 0.04), 0.5), ((0.0, 0.0, 0.0), (1.0, 0.766, 0.336), 0.9),
         ((0.5, 0.4, 0.3), (0.1, 0.15, 0.2), 0.6), ((0.6, 0.6, 0.6), (0.2, 0.6, 0.9), 0.8),
         ((0.3, 0.5, 0.2), (0.05, 0.05, 0.02), 0.3), ((0.02, 0.02, 0.02), (0.95, 0.64, 0.54), 0.8)]


def reference(diffuse, specular, glossiness) -> dict:
    return {"base_color": tuple(np.asarray(diffuse) * (1 - max(specular))), "metallic": 0.0, "ior": 1.5, "specular": 1.0,
            "specular_color": tuple(np.asarray(specular) / 0.04), "roughness": 1.0 - glossiness}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--count", type=int, default=20)
    parser.add_argument("--seed", type=int, default=11)
    parser.add_argument("--glsl", action="store_true", help="also judge in MaterialX's GLSL (Xvfb, Mesa)")
    arguments = parser.parse_args()
    rng = np.random.default_rng(arguments.seed)
    cases = FIXED[:arguments.count]
    while len(cases) < arguments.count:
        cases.append((tuple(rng.uniform(0, 1, 3)), tuple(rng.uniform(0, 0.25, 3)), float(rng.uniform(0.2, 1.0))))
    renderer = mask = None
    rig = Rig(size=64)
    if arguments.glsl:
        from glsupport import comparison_mask, materialx_renderer  # noqa: E402  (GL only when asked)

        renderer, mask = materialx_renderer(rig), comparison_mask(rig)
    folder = tempfile.mkdtemp(prefix="openpbr-spec-gloss-")
    rows = []
    for index, (diffuse, specular, glossiness) in enumerate(cases):
        source = os.path.join(folder, f"s{index}.gltf")
        with open(source, "w", encoding="utf-8") as handle:
            json.dump({"asset": {"version": "2.0"}, "extensionsUsed": ["KHR_materials_pbrSpecularGlossiness"],
                       "materials": [{"name": "M", "extensions": {"KHR_materials_pbrSpecularGlossiness": {
                           "diffuseFactor": list(diffuse) + [1.0], "specularFactor": list(specular),
                           "glossinessFactor": glossiness}}}]}, handle)
        (material,) = read_asset(source).materials
        fallback = Material(name="M", model="gltf_pbr", location=Location(source))  # every input at glTF's default
        row = {"evaluator": [compare_materials(material, fallback).preview.mean], "glsl": []}
        if renderer is not None:
            goal = renderer.render("gltf_pbr", reference(diffuse, specular, glossiness))
            row["glsl"].append(_delta(renderer.render("gltf_pbr", {}), goal, mask, rig))
        for searched in (False, True):
            out = os.path.join(folder, f"o{index}_{searched}.mtlx")
            convert_file(source, out, "open_pbr_surface", Settings(candidates=searched))
            (written,) = read_asset(out).materials
            row["evaluator"].append(compare_materials(material, written).preview.mean)
            if renderer is not None:
                from glsupport import single_material  # noqa: E402

                image = renderer.render_document(single_material(out, "M", os.path.join(folder, f"M{index}{searched}.mtlx")))
                row["glsl"].append(_delta(image, goal, mask, rig))
        rows.append(row)
        figures = "  ".join(f"{judge} " + " / ".join(f"{v:.2f}" for v in row[judge]) for judge in ("evaluator", "glsl")
                            if row[judge])
        print(f"{index:3d} D={np.round(diffuse, 2)} S={np.round(specular, 2)} g={glossiness:.2f}: "
              f"(fallback / solve / converted) {figures}")
    for judge in ("evaluator", "glsl"):
        table = np.array([row[judge] for row in rows if row[judge]])
        if table.size:
            print(f"{judge}: medians fallback {np.median(table[:, 0]):.2f}, solve {np.median(table[:, 1]):.2f}, "
                  f"converted {np.median(table[:, 2]):.2f}; over 2.3: {(table[:, 0] > 2.3).sum()} / "
                  f"{(table[:, 1] > 2.3).sum()} / {(table[:, 2] > 2.3).sum()} of {len(table)}")


def _delta(image, goal, mask, rig) -> float:
    from glsupport import mean_delta_e  # noqa: E402

    return mean_delta_e(image, goal, mask, rig.white())


if __name__ == "__main__":
    main()
