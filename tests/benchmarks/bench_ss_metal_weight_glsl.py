"""MaterialX's GLSL as the judge of a full metal's ``specular_weight`` written as Standard Surface's coat tint
(translate/ss_metal_weight.py) against the weight folded into the base colour and edge target (before session 26):
fully metallic OpenPBR materials with a weight below 1 (some tinted at the edge, some under a full coat), converted to
Standard Surface both ways, each rendered by MaterialX's GLSL on the lit sphere (Xvfb + Mesa), mean CIEDE2000 against
the source's render; the evaluator's figure beside it.

    xvfb-run -a python tests/benchmarks/bench_ss_metal_weight_glsl.py [--count 30]
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
from openpbr_tools import tables
from openpbr_tools.model import Constant, Input, Location, Material
L = Location("m.mtlx", 1, "S")


def mat(**values):
    t = tables.table("open_pbr_surface")
    return Material("S", "open_pbr_surface", L, {n: Input(n, t[n].type, Constant(v), L.with_input(n))
                                                 for n, v in values.items()}, version=t.version)


parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
parser.add_argument("--count", type=int, default=30)
arguments = parser.parse_args()
rig = Rig(size=64)
renderer = materialx_renderer(rig)
rng = random.Random(26)
rows = []
for i in range(arguments.count):
    v = dict(base_metalness=1.0, specular_weight=rng.choice((rng.uniform(0, 1), 0.1, 0.5)),
             base_color=tuple(rng.uniform(0.05, 1) for _ in range(3)), specular_roughness=rng.uniform(0, 1))
    if rng.random() < 0.4:
        v["specular_color"] = tuple(rng.uniform(0, 1) for _ in range(3))
    if rng.random() < 0.25:
        v.update(coat_weight=rng.choice((1.0, rng.uniform(0.5, 1))), coat_roughness=rng.uniform(0, 0.5),
                 coat_color=tuple(rng.uniform(0.5, 1) for _ in range(3)), coat_darkening=rng.choice((0.0, 1.0)))
    source = mat(**v)
    reference = renderer.render("open_pbr_surface", _values(source))
    mask = comparison_mask(rig) & np.isfinite(reference).all(axis=-1)
    out = []
    for tint in (True, False):  # the coat's tint, the fold (Settings.metal_weight_tint: the candidate search's readings)
        s = Settings(context=Context(), metal_weight_tint=tint)
        r = candidates.choose(source, convert(source, "standard_surface", s), "standard_surface", s).material
        out.append((compare_images(reference, renderer.render("standard_surface", _values(r)), mask, rig.white()).mean,
                    compare_materials(source, r).preview.mean))
    rows.append(out)
    print(f"{i:2d} w={v['specular_weight']:.2f} tint={'specular_color' in v} coat={'coat_weight' in v} "
          f"GLSL coat tint {out[0][0]:.2f} fold {out[1][0]:.2f} | evaluator tint {out[0][1]:.2f} fold {out[1][1]:.2f}",
          flush=True)
g = np.array([[r[0][0], r[1][0], r[0][1], r[1][1]] for r in rows])
print("GLSL mean tint %.2f fold %.2f; under 2.3 tint %d fold %d; tint better by >0.5: %d, worse by >0.5: %d" % (
    g[:, 0].mean(), g[:, 1].mean(), (g[:, 0] < 2.3).sum(), (g[:, 1] < 2.3).sum(), (g[:, 0] < g[:, 1] - 0.5).sum(),
    (g[:, 0] > g[:, 1] + 0.5).sum()))
print("evaluator mean tint %.2f fold %.2f; under 2.3 tint %d fold %d" % (g[:, 2].mean(), g[:, 3].mean(),
                                                                         (g[:, 2] < 2.3).sum(), (g[:, 3] < 2.3).sum()))
