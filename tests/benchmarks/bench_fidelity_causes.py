"""Why generated materials miss 2.3 mean CIEDE2000: for every archetype (tests/generated_materials.py) a
conversion renders more than 2.3 off on the evaluator (where the evaluator is a trusted judge:
translate/appearance.untrusted), each source feature is switched off in turn (a coat, a film, a fuzz,
emission, anisotropy, a diffuse roughness, a specular colour or weight, an IOR, a transmission colour,
depth, scatter or dispersion, a subsurface) and the material converted again; the features whose removal
alone brings it under 2.3 are its causes.

    python tests/benchmarks/bench_fidelity_causes.py [--target gltf_pbr|standard_surface|UsdPreviewSurface] [--documents 12]

Prints the failures per kind, each failure with the ablation that helps most, and a count per (kind,
cause); "none" where no single feature explains it. A cause that is a feature the target model has no
place for (an F82 edge tint on a glTF metal, a thin-walled translucency in UsdPreviewSurface) is a limit
of the target, not of the conversion.
"""

from __future__ import annotations

import argparse
import collections
import os
import random
import sys
import tempfile

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))

import generated_materials as generated  # noqa: E402
from openpbr_tools.convert import convert_file  # noqa: E402
from openpbr_tools.translate.appearance import untrusted  # noqa: E402
from openpbr_tools.translate.common import Settings  # noqa: E402
from openpbr_tools.verification import measure  # noqa: E402

TARGETS = {"standard_surface": ("mtlx", "standard_surface"), "gltf_pbr": ("gltf", None),
           "UsdPreviewSurface": ("mtlx", "UsdPreviewSurface")}
WHITE, BLACK = (1.0, 1.0, 1.0), (0.0, 0.0, 0.0)
ABLATIONS = {"coat": {"coat_weight": 0.0}, "film": {"thin_film_weight": 0.0}, "fuzz": {"fuzz_weight": 0.0},
             "emission": {"emission_luminance": 0.0}, "anisotropy": {"specular_roughness_anisotropy": 0.0},
             "diffuse roughness": {"base_diffuse_roughness": 0.0}, "specular colour": {"specular_color": WHITE},
             "specular weight": {"specular_weight": 1.0}, "ior": {"specular_ior": 1.5},
             "transmission colour": {"transmission_color": WHITE}, "depth": {"transmission_depth": 0.0},
             "scatter": {"transmission_scatter": BLACK}, "dispersion": {"transmission_dispersion_scale": 0.0},
             "subsurface": {"subsurface_weight": 0.0}, "roughness": {"specular_roughness": 0.3}}
JUST_NOTICEABLE = 2.3
PER_DOCUMENT = 50  # materials per generated document, as bench_fidelity.py draws them


def _converted(folder: str, space: str, materials: list[dict], target: str) -> dict:
    """Material name -> (mean CIEDE2000, source material) of ``materials`` converted to ``target``."""
    suffix, model = TARGETS[target]
    path = os.path.join(folder, f"{space}.mtlx")
    with open(path, "w", encoding="utf-8") as handle:
        handle.write(generated._mtlx("open_pbr_surface", space, materials))
    conversion = convert_file(path, os.path.join(folder, f"out.{suffix}"), model, Settings())
    return {source.name: (delta.mean, source) for source, delta in measure(conversion)}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--target", default="gltf_pbr", choices=tuple(TARGETS))
    parser.add_argument("--documents", type=int, default=12)
    parser.add_argument("--seed", type=int, default=11)
    arguments = parser.parse_args()
    folder = tempfile.mkdtemp(prefix="openpbr-causes-")
    failures, totals = [], collections.Counter()
    for index in range(arguments.documents):
        space = generated.COLORSPACES[index % len(generated.COLORSPACES)]
        rng = random.Random(f"archetypes/{space}/{arguments.seed * 1000 + index}")
        drawn = [generated.archetype_values(rng) for _ in range(PER_DOCUMENT)]
        results = _converted(folder, space, [values for _, values in drawn], arguments.target)
        for position, (kind, values) in enumerate(drawn):
            mean, source = results[f"S{position}"]
            if untrusted(source) is not None:
                continue
            totals[kind] += 1
            if mean > JUST_NOTICEABLE:
                failures.append((space, kind, values, mean, f"document {index} S{position}"))
    print(f"{arguments.target}: failures over {JUST_NOTICEABLE} (trusted judge) per kind: "
          + ", ".join(f"{kind} {sum(f[1] == kind for f in failures)}/{count}" for kind, count in sorted(totals.items())))
    causes = collections.Counter()
    for space in generated.COLORSPACES:
        mine = [f for f in failures if f[0] == space]
        variants = [(which, name, dict(values, **change)) for which, (_, _, values, _, _) in enumerate(mine)
                    for name, change in ABLATIONS.items()
                    if any(key in values for key in change) and any(values.get(k) != v for k, v in change.items())]
        results = _converted(folder, space, [values for _, _, values in variants], arguments.target) if variants else {}
        ablated = collections.defaultdict(list)
        for position, (which, name, _) in enumerate(variants):
            ablated[which].append((results[f"S{position}"][0], name))
        for which, (_, kind, _, mean, where) in enumerate(mine):
            options = sorted(ablated[which])
            helped = [name for value, name in options if value < JUST_NOTICEABLE]
            causes[(kind, helped[0] if helped else "none")] += 1
            best = f"{options[0][1]} -> {options[0][0]:.2f}" if options else "-"
            print(f"  {mean:6.2f} {space:13s} {where:16s} {kind:15s} best ablation {best}; under 2.3 without: "
                  f"{', '.join(helped[:4]) or 'none'}")
    print("causes (kind, the feature whose removal alone helps most):")
    for (kind, cause), count in sorted(causes.items(), key=lambda item: -item[1]):
        print(f"  {count:4d}  {kind:15s} {cause}")


if __name__ == "__main__":
    main()
