"""MaterialX's GLSL as the judge of the metal split (translate/fit_metal.split_metal): partly metallic OpenPBR materials
whose metal specular_weight dims (some also tinted at the edge) converted to glTF (gltf_pbr) and UsdPreviewSurface with
the split and with the colours mixed at OpenPBR's metalness (as before session 22), each rendered by MaterialX's GLSL
on the lit sphere (Xvfb + Mesa), mean CIEDE2000 against the source's render; the evaluator's figure beside it.

    xvfb-run -a python tests/benchmarks/bench_metal_split_glsl.py [--count 30] [--target gltf_pbr|UsdPreviewSurface]

Session 22, 30 materials: glTF GLSL mean 1.51 -> 0.40 (under 2.3: 24 -> 30; better by >0.5: 21, worse by >0.5: 0).
"""
import argparse
import os
import random
import sys
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import numpy as np
from glsupport import comparison_mask, materialx_renderer
from bench_glsl_sample import values_of as _values
from openpbr_tools.evaluate.difference import compare_images
from openpbr_tools.evaluate.preview import Rig
from openpbr_tools.evaluate.verify import compare_materials
from openpbr_tools.rules import Context
from openpbr_tools.translate import candidates
from openpbr_tools.translate.common import Settings
from openpbr_tools.translate.convert import convert
from openpbr_tools.translate import fit
from openpbr_tools import tables
from openpbr_tools.model import Constant, Input, Location, Material
L = Location("m.mtlx", 1, "S")
def mat(**values):
    t = tables.table("open_pbr_surface")
    return Material("S", "open_pbr_surface", L, {n: Input(n, t[n].type, Constant(v), L.with_input(n)) for n, v in values.items()}, version=t.version)
parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
parser.add_argument("--count", type=int, default=30)
parser.add_argument("--target", default="gltf_pbr", choices=("gltf_pbr", "UsdPreviewSurface"))
arguments = parser.parse_args()
target = arguments.target
split = fit.split_metal


def mix(dielectric, metal, metalness, alpha, target="schlick", clip=True):
    mixed = np.asarray(dielectric) + metalness * (np.asarray(metal) - np.asarray(dielectric))
    return np.asarray(metalness, dtype=np.float64), (np.clip(mixed, 0.0, 1.0) if clip else mixed)


rig = Rig(size=64); renderer = materialx_renderer(rig)
rng = random.Random(7)
rows = []
for i in range(arguments.count):
    v = dict(base_metalness=rng.uniform(0.1, 0.95), specular_weight=rng.choice((rng.uniform(0, 1), 0.0, 0.5)),
             base_color=tuple(rng.uniform(0.05, 1) for _ in range(3)), specular_roughness=rng.uniform(0, 1))
    if rng.random() < 0.4:
        v["specular_color"] = tuple(rng.uniform(0, 1) for _ in range(3))
    source = mat(**v)
    reference = renderer.render("open_pbr_surface", _values(source))
    mask = comparison_mask(rig) & np.isfinite(reference).all(axis=-1)
    out = []
    for way in (split, mix):
        fit.split_metal = way
        s = Settings(context=Context())
        r = candidates.choose(source, convert(source, target, s), target, s).material
        fit.split_metal = split
        out.append((compare_images(reference, renderer.render(target, _values(r)), mask, rig.white()).mean,
                    compare_materials(source, r).preview.mean))
    rows.append((out[0], out[1]))
    print(f"{i:2d} m={v['base_metalness']:.2f} w={v['specular_weight']:.2f} tint={'specular_color' in v} "
          f"GLSL split {out[0][0]:.2f} mix {out[1][0]:.2f} | evaluator split {out[0][1]:.2f} mix {out[1][1]:.2f}", flush=True)
g = np.array([[r[0][0], r[1][0], r[0][1], r[1][1]] for r in rows])
print("GLSL mean split %.2f mix %.2f; under 2.3 split %d mix %d; split better by >0.5: %d, worse by >0.5: %d" % (
    g[:, 0].mean(), g[:, 1].mean(), (g[:, 0] < 2.3).sum(), (g[:, 1] < 2.3).sum(), (g[:, 0] < g[:, 1] - 0.5).sum(), (g[:, 0] > g[:, 1] + 0.5).sum()))
print("evaluator mean split %.2f mix %.2f; under 2.3 split %d mix %d" % (g[:, 2].mean(), g[:, 3].mean(), (g[:, 2] < 2.3).sum(), (g[:, 3] < 2.3).sum()))
