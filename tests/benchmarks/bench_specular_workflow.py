"""Specular-workflow UsdPreviewSurface materials (``useSpecularWorkflow`` 1: a diffuse colour and an F0
colour with a white edge) converted to OpenPBR, Standard Surface and glTF, three readings side by side:
the luminance reading alone (an IOR of the F0 colour's luminance, ``S / max(S)`` as ``specular_color``;
``Settings(specular_split=False, candidates=False)``, the reading before session 11), the split into metal
and dielectric shares alone (translate/specular_workflow.py; ``candidates=False``) and the default (the
split, the luminance reading weighed beside it by the candidate search, then the appearance fit).

    python tests/benchmarks/bench_specular_workflow.py [--count 120] [--seed 5] [--glsl]

The corpus (seeded) draws four kinds in equal shares: dielectrics (a grey F0 of 0-0.12 over any diffuse
colour), metals (a dark diffuse under a bright coloured F0, as a specular-workflow asset authors copper or
gold), mixed (any diffuse colour under any coloured F0 up to 0.6) and extremes (saturated F0 and diffuse
colours, OpenUSD's testPreviewSurfaceSpecular's kind); roughness 0.05-0.95; a clear coat on a fifth.
Judged by the evaluator (``openpbr_tools.verification.measure``: the output read back, mean CIEDE2000
over the lit sphere) and, with ``--glsl``, by MaterialX's GLSL renderer (Xvfb + Mesa): the converted
.mtlx (for glTF, a gltf_pbr .mtlx) against MaterialX's own ``UsdPreviewSurface`` with the source's values.
Prints per target and reading the median, p95, share under 2.3 and worst, per kind.
"""

from __future__ import annotations

import argparse
import os
import statistics
import sys
import tempfile

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, ".."))

from openpbr_tools.convert import convert_file  # noqa: E402
from openpbr_tools.translate.common import Settings  # noqa: E402
from openpbr_tools.verification import measure  # noqa: E402

KINDS = ("dielectric", "metal", "mixed", "extreme")
READINGS = {"luminance": Settings(specular_split=False, candidates=False), "split": Settings(candidates=False),
            "default": Settings()}
TARGETS = {"open_pbr_surface": "mtlx", "standard_surface": "mtlx", "gltf_pbr": "gltf"}


def corpus(count: int, seed: int) -> list[tuple[str, dict]]:
    """(kind, UsdPreviewSurface values) for ``count`` materials."""
    rng = np.random.default_rng(seed)
    out = []
    for index in range(count):
        kind = KINDS[index % len(KINDS)]
        if kind == "dielectric":
            diffuse, specular = rng.uniform(0, 1, 3), np.full(3, rng.uniform(0, 0.12))
        elif kind == "metal":
            diffuse, specular = rng.uniform(0, 0.06, 3), rng.uniform(0.35, 1.0, 3)
        elif kind == "mixed":
            diffuse, specular = rng.uniform(0, 1, 3), rng.uniform(0, 1, 3) * rng.uniform(0.05, 0.6)
        else:
            diffuse, specular = np.eye(3)[rng.integers(3)] * rng.uniform(0.5, 1), np.eye(3)[rng.integers(3)] * rng.uniform(0.5, 1)
        values = {"useSpecularWorkflow": 1, "diffuseColor": tuple(map(float, diffuse)),
                  "specularColor": tuple(map(float, specular)), "roughness": float(rng.uniform(0.05, 0.95))}
        if rng.uniform() < 0.2:
            values.update(clearcoat=float(rng.uniform(0.3, 1.0)), clearcoatRoughness=float(rng.uniform(0.0, 0.3)))
        out.append((kind, values))
    return out


def write_stage(path: str, materials: list[tuple[str, dict]]) -> None:
    from pxr import Gf, Sdf, Usd, UsdShade

    stage = Usd.Stage.CreateNew(path)
    for index, (_, values) in enumerate(materials):
        material = UsdShade.Material.Define(stage, f"/Looks/M{index:03d}")
        shader = UsdShade.Shader.Define(stage, f"/Looks/M{index:03d}/Preview")
        shader.CreateIdAttr("UsdPreviewSurface")
        for name, value in values.items():
            if isinstance(value, tuple):
                shader.CreateInput(name, Sdf.ValueTypeNames.Color3f).Set(Gf.Vec3f(*value))
            elif isinstance(value, int):
                shader.CreateInput(name, Sdf.ValueTypeNames.Int).Set(value)
            else:
                shader.CreateInput(name, Sdf.ValueTypeNames.Float).Set(value)
        material.CreateSurfaceOutput().ConnectToSource(shader.ConnectableAPI(), "surface")
    stage.GetRootLayer().Save()


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--count", type=int, default=120)
    parser.add_argument("--seed", type=int, default=5)
    parser.add_argument("--glsl", action="store_true", help="also judge with MaterialX's GLSL renderer")
    arguments = parser.parse_args()
    materials = corpus(arguments.count, arguments.seed)
    folder = tempfile.mkdtemp(prefix="openpbr-specular-workflow-")
    source = os.path.join(folder, "corpus.usda")
    write_stage(source, materials)
    kind_of = {f"M{i:03d}": kind for i, (kind, _) in enumerate(materials)}
    glsl = _GlslJudge(materials) if arguments.glsl else None
    for target, suffix in TARGETS.items():
        for reading, settings in READINGS.items():
            out = os.path.join(folder, f"{target}_{reading}.{suffix}")
            conversion = convert_file(source, out, None if target == "gltf_pbr" else target, settings)
            rows = {source_material.material_name: delta.mean for source_material, delta in measure(conversion)}
            _print(target, reading, "evaluator", rows, kind_of)
            if glsl is not None:  # a glTF target is judged as MaterialX's gltf_pbr node
                if suffix != "mtlx":
                    out = os.path.join(folder, f"{target}_{reading}.mtlx")
                    convert_file(source, out, target, settings)
                _print(target, reading, "GLSL", glsl.judge(out), kind_of)


def _print(target: str, reading: str, judge: str, rows: dict, kind_of: dict) -> None:
    values = sorted(rows.values())
    worst = max(rows, key=rows.get)
    print(f"{target:17s} {reading:9s} {judge:9s} median {statistics.median(values):5.2f}  "
          f"p95 {values[int(0.95 * (len(values) - 1))]:5.2f}  under 2.3 {sum(v < 2.3 for v in values) / len(values):6.1%}  "
          f"worst {rows[worst]:5.2f} ({worst}, {kind_of[worst]})")
    for kind in KINDS:
        of_kind = [v for name, v in rows.items() if kind_of[name] == kind]
        print(f"    {kind:10s} median {statistics.median(of_kind):5.2f}  under 2.3 {sum(v < 2.3 for v in of_kind):3d} "
              f"of {len(of_kind)}  worst {max(of_kind):5.2f}")


class _GlslJudge:
    """MaterialX's GLSL renders: each converted material against MaterialX's UsdPreviewSurface with the
    source's values."""

    def __init__(self, materials):
        from glsupport import comparison_mask, materialx_renderer
        from openpbr_tools.evaluate.preview import Rig

        self.rig = Rig(size=64)
        self.renderer = materialx_renderer(self.rig)
        self.mask = comparison_mask(self.rig)
        self.references = {f"M{i:03d}": self.renderer.render("UsdPreviewSurface", values)
                           for i, (_, values) in enumerate(materials)}

    def judge(self, path: str) -> dict:
        """Each material of the .mtlx at ``path`` (constant values, in linear Rec.709 as the evaluator resolves
        them) rendered through the model's one shader with its values as uniforms."""
        from glsupport import mean_delta_e
        from openpbr_tools.evaluate import resolve
        from openpbr_tools.io import read_asset

        rows = {}
        for material in read_asset(path).materials:
            image = self.renderer.render(material.model, resolve(material).values)
            rows[material.material_name] = mean_delta_e(image, self.references[material.material_name], self.mask,
                                                        self.rig.white())
        return rows


if __name__ == "__main__":
    main()
