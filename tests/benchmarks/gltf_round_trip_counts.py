"""Before/after figures for glTF round trips: generated glTF materials (tests/generated_gltf_materials.py,
every factor of the core material, every ratified extension and the drafts) through .mtlx or .usda and
back to glTF, each factor classified by tests/gltf_round_trip.py as exact (within 1e-5), noted (it
differs and a note names its material and a related input), silent (differs without a note) or
dropped (the factor is gone from the returned material without a note). Draft-carried values are
counted under the draft's name.

    python tests/benchmarks/gltf_round_trip_counts.py --count 2000 --route mtlx [--drafts]

Runs against whatever openpbr_tools is importable (run it from an old checkout for "before").
"""

from __future__ import annotations

import argparse
import collections
import json
import os
import sys
import tempfile

sys.path.insert(0, os.path.join(os.path.dirname(__file__), ".."))

from generated_gltf_materials import document  # noqa: E402
from gltf_round_trip import round_trip  # noqa: E402

from openpbr_tools.convert import convert_file  # noqa: E402
from openpbr_tools.translate.common import Settings  # noqa: E402

EXTENSION_OF = {"clearcoat": "KHR_materials_clearcoat", "sheen": "KHR_materials_sheen", "specular": "KHR_materials_specular",
                "transmission": "KHR_materials_transmission", "volume": "KHR_materials_volume", "dispersion": "KHR_materials_dispersion",
                "ior": "KHR_materials_ior", "iridescence": "KHR_materials_iridescence", "anisotropy": "KHR_materials_anisotropy",
                "diffuseTransmission": "KHR_materials_diffuse_transmission"}
DRAFT_OF = {"coat": "KHR_materials_coat (+clearcoat subs)", "fuzz": "KHR_materials_fuzz",
            "diffuse": "KHR_materials_diffuse_roughness", "specular": "EXT_materials_specular_openpbr"}


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--count", type=int, default=2000)
    parser.add_argument("--route", choices=["mtlx", "usda"], default="mtlx")
    parser.add_argument("--drafts", action="store_true", help="convert back with --gltf-drafts (if the code has it)")
    args = parser.parse_args()
    counts: dict = collections.defaultdict(collections.Counter)
    settings = Settings()
    if args.drafts:
        try:
            settings = Settings(gltf_drafts=True)
        except TypeError:
            print("this checkout has no --gltf-drafts", file=sys.stderr)
    with tempfile.TemporaryDirectory() as folder:
        for seed in range(max(1, args.count // 500)):
            source = os.path.join(folder, f"c{seed}.gltf")
            with open(source, "w") as handle:
                json.dump(document(seed, min(500, args.count)), handle)
            middle = os.path.join(folder, f"c{seed}.{args.route}")
            back = os.path.join(folder, f"b{seed}.gltf")
            there = convert_file(source, middle)
            again = convert_file(middle, back, settings=settings)
            before = json.load(open(source))["materials"]
            after = json.load(open(back))["materials"]
            counts["material count"]["exact" if len(before) == len(after) else "silent"] += 1
            for index, found in enumerate(round_trip(before, after, there, again)):
                counts["material name"]["exact" if before[index]["name"] == after[index]["name"] else "silent"] += 1
                for key, status, value, got in found:
                    if status == "silent" and got is None:
                        status = "dropped"
                    group = key[0]
                    name = DRAFT_OF[group[6:]] if group.startswith("draft ") else EXTENSION_OF.get(group, "core")
                    counts[name][status] += 1
    print(f"{'':40s} {'exact':>7s} {'noted':>7s} {'silent':>7s} {'dropped':>7s}")
    for name in sorted(counts):
        c = counts[name]
        print(f"{name:40s} {c['exact']:7d} {c['noted']:7d} {c['silent']:7d} {c['dropped']:7d}")


if __name__ == "__main__":
    main()
