"""Is a miss the converter's or the target model's? For every generated material (tests/generated_materials.py,
archetypes, as bench_fidelity_causes.py draws them) whose conversion renders more than 2.3 mean CIEDE2000 off
on the evaluator (where it is a trusted judge: translate/appearance.untrusted), an oracle searches the
target's own parameters for the closest render: Nelder-Mead from the conversion's values over the colour
inputs and the [0, 1] weights and roughnesses listed in FREE, judged on the evaluator's 16-pixel sphere
as the candidate search judges (translate/judging.Judge).

    python tests/benchmarks/bench_fidelity_oracle.py [--target standard_surface|gltf_pbr|UsdPreviewSurface] [--documents 12]

Prints, per failure, the conversion's figure, the oracle's, and the count the oracle brings under 2.3.
A failure the oracle cannot bring under 2.3 is a limit of the target model for that material (no
setting of those parameters renders like the source); one it can is a miss of the conversion.
The oracle is a local search (up to --evaluations renders from the conversion's values), so its count
is a lower bound of what the target could reach.
"""

from __future__ import annotations

import argparse
import collections
import copy
import os
import random
import sys
import tempfile

import numpy as np
from scipy.optimize import minimize

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))

import generated_materials as generated  # noqa: E402
from openpbr_tools.convert import convert_file  # noqa: E402
from openpbr_tools.model import Constant, Input  # noqa: E402
from openpbr_tools.translate.appearance import untrusted  # noqa: E402
from openpbr_tools.translate.common import Settings  # noqa: E402
from openpbr_tools.translate.judging import Judge  # noqa: E402
from openpbr_tools.verification import measure  # noqa: E402

TARGETS = {"standard_surface": ("mtlx", "standard_surface"), "gltf_pbr": ("gltf", None),
           "UsdPreviewSurface": ("mtlx", "UsdPreviewSurface")}
#: per target: (colour inputs, [0, 1] float inputs) the oracle may change, with the value an absent one has
FREE = {
    "standard_surface": ({"base_color": (0.8, 0.8, 0.8), "specular_color": (1.0, 1.0, 1.0),
                          "coat_color": (1.0, 1.0, 1.0)},
                         {"base": 1.0, "metalness": 0.0, "specular": 1.0, "specular_roughness": 0.2, "coat": 0.0,
                          "coat_roughness": 0.1}),
    "gltf_pbr": ({"base_color": (1.0, 1.0, 1.0), "specular_color": (1.0, 1.0, 1.0)},
                 {"metallic": 1.0, "roughness": 1.0, "specular": 1.0, "clearcoat": 0.0, "clearcoat_roughness": 0.0}),
    "UsdPreviewSurface": ({"diffuseColor": (0.18, 0.18, 0.18)},
                          {"metallic": 0.0, "roughness": 0.5, "clearcoat": 0.0, "clearcoatRoughness": 0.01}),
}
JUST_NOTICEABLE = 2.3
PER_DOCUMENT = 50


def _with(material, colours: dict, floats: dict):
    changed = copy.copy(material)
    changed.inputs = dict(material.inputs)
    for name, value in list(colours.items()) + list(floats.items()):
        old = material.inputs.get(name)
        kind = "color3" if name in colours else "float"
        value = tuple(float(x) for x in value) if kind == "color3" else float(value)
        changed.inputs[name] = Input(name, kind, Constant(value), old.location if old else material.location)
    return changed


def _start(material, defaults: dict) -> dict:
    found = {}
    for name, default in defaults.items():
        entry = material.inputs.get(name)
        found[name] = entry.value.value if entry is not None and isinstance(entry.value, Constant) else default
    return found


def oracle(source, result, target: str, evaluations: int) -> tuple[float, float]:
    """(the conversion's figure, the oracle's) on the evaluator's 16-pixel sphere."""
    colours, floats = FREE[target]
    start_colours, start_floats = _start(result, colours), _start(result, floats)
    x0 = np.concatenate([np.ravel(v) for v in start_colours.values()] + [np.ravel(list(start_floats.values()))])
    judge = Judge(source, 16)

    def unpack(x):
        x = np.clip(x, 0.0, 1.0)
        names = list(colours)
        c = {name: x[3 * i:3 * i + 3] for i, name in enumerate(names)}
        f = dict(zip(floats, x[3 * len(names):]))
        return c, f

    def score(x):
        return judge.scores([_with(result, *unpack(x))])[0]

    start = score(x0)
    found = minimize(score, x0, method="Nelder-Mead",
                     options={"maxfev": evaluations, "xatol": 1e-3, "fatol": 1e-3, "adaptive": True})
    return start, min(start, float(found.fun))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--target", default="standard_surface", choices=tuple(TARGETS))
    parser.add_argument("--documents", type=int, default=12)
    parser.add_argument("--seed", type=int, default=11)
    parser.add_argument("--evaluations", type=int, default=600)
    arguments = parser.parse_args()
    suffix, model = TARGETS[arguments.target]
    folder = tempfile.mkdtemp(prefix="openpbr-oracle-")
    reached, total = collections.Counter(), collections.Counter()
    for index in range(arguments.documents):
        space = generated.COLORSPACES[index % len(generated.COLORSPACES)]
        rng = random.Random(f"archetypes/{space}/{arguments.seed * 1000 + index}")
        drawn = [generated.archetype_values(rng) for _ in range(PER_DOCUMENT)]
        path = os.path.join(folder, f"{space}.mtlx")
        with open(path, "w", encoding="utf-8") as handle:
            handle.write(generated._mtlx("open_pbr_surface", space, [values for _, values in drawn]))
        conversion = convert_file(path, os.path.join(folder, f"out.{suffix}"), model, Settings())
        figures = {source.name: delta.mean for source, delta in measure(conversion)}
        pairs = {source.name: (source, result) for source, result in conversion.pairs}
        for position, (kind, _) in enumerate(drawn):
            source, result = pairs[f"S{position}"]
            mean = figures[f"S{position}"]
            if untrusted(source) is not None or mean <= JUST_NOTICEABLE:
                continue
            rig, best = oracle(source, result, arguments.target, arguments.evaluations)
            total[kind] += 1
            reached[kind] += best < JUST_NOTICEABLE
            print(f"  {mean:6.2f} (16 px {rig:5.2f}) oracle {best:5.2f}  {space:13s} document {index} S{position} {kind}",
                  flush=True)
    print(f"{arguments.target}: failures the oracle brings under {JUST_NOTICEABLE}: "
          f"{sum(reached.values())}/{sum(total.values())} ("
          + ", ".join(f"{kind} {reached[kind]}/{count}" for kind, count in sorted(total.items())) + ")")


if __name__ == "__main__":
    main()
