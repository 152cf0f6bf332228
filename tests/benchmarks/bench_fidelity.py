"""Translation fidelity over the OpenPBR parameter space: generated constant materials (every
parameter over its legal range, absent-means-default; tests/generated_materials.py) in lin_rec709,
acescg and lin_displayp3 documents, converted to Standard Surface, glTF and UsdPreviewSurface, judged
by the lobe evaluator (mean CIEDE2000 over the lit sphere).

    python tests/benchmarks/bench_fidelity.py [--count 1000] [--seed 11] [--corpus archetypes] [--verify]

``--corpus all-lobes`` (the default) draws every parameter independently, so most materials switch
every lobe on at once; ``--corpus archetypes`` draws materials of the kinds artists author (metals
with and without edge tint, dielectrics, subsurface, glass and liquids, thin-walled sheets, cut-outs,
each possibly coated, filmed, fuzzy or emissive; generated_materials.KINDS) with the same full ranges,
and breaks the figures down by kind.

Prints, per target: the share of materials under 2.3 (just noticeable), the median, p95 and the
worst with their file and index; the shares again where the evaluator is a trusted judge (sources
with an IOR below 1, a film on a metal or a film much denser than its base, which MaterialX's GLSL renders 2-17 ΔE apart from the
evaluator, left out: translate/appearance.untrusted). The materials are random over the whole space, so many are
combinations no artist authors (a glass that is also a metal with fuzz); the tail says where the
models differ, not only where the converter errs.
"""

from __future__ import annotations

import argparse
import os
import statistics
import sys
import tempfile
import time

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))

from generated_materials import COLORSPACES, archetype_document, document  # noqa: E402
from openpbr_tools.convert import convert_file  # noqa: E402
from openpbr_tools.verification import measure  # noqa: E402
from openpbr_tools.translate.appearance import untrusted  # noqa: E402
from openpbr_tools.translate.common import Settings  # noqa: E402

TARGETS = {"standard_surface": ("mtlx", "standard_surface"), "gltf_pbr": ("gltf", None),
           "UsdPreviewSurface": ("mtlx", "UsdPreviewSurface")}
PER_DOCUMENT = 50


def _opaque(material) -> bool:
    """No transmission and full geometry opacity (absent means default)."""
    def value(name, default):
        entry = material.inputs.get(name)
        return entry.value.value if entry is not None and hasattr(entry.value, "value") else default

    opacity = value("geometry_opacity", 1.0)
    return not value("transmission_weight", 0.0) > 0 and float(min(opacity if isinstance(opacity, tuple) else
                                                                   (opacity,))) >= 1.0


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--count", type=int, default=1000)
    parser.add_argument("--seed", type=int, default=11)
    parser.add_argument("--worst", type=int, default=5)
    parser.add_argument("--corpus", choices=("all-lobes", "archetypes"), default="all-lobes")
    parser.add_argument("--verify", action="store_true",
                        help="convert as openpbr convert --verify does: also fit films and search the target's "
                             "parameters where the result is still visibly off (translate/search.py)")
    arguments = parser.parse_args()
    folder = tempfile.mkdtemp(prefix="openpbr-fidelity-")
    sources, kinds = [], {}
    for index in range(max(1, arguments.count // PER_DOCUMENT)):
        space = COLORSPACES[index % len(COLORSPACES)]
        path = os.path.join(folder, f"set{index:03d}_{space}.mtlx")
        seed = arguments.seed * 1000 + index
        if arguments.corpus == "archetypes":
            text, file_kinds = archetype_document(space, seed, PER_DOCUMENT)
            kinds.update(((os.path.basename(path), f"S{i}"), kind) for i, kind in enumerate(file_kinds))
        else:
            text = document("open_pbr_surface", space, seed, PER_DOCUMENT)
        with open(path, "w", encoding="utf-8") as handle:
            handle.write(text)
        sources.append(path)
    start = time.perf_counter()
    for target, (suffix, model) in TARGETS.items():
        rows = []
        for path in sources:
            conversion = convert_file(path, os.path.join(folder, f"out.{suffix}"), model,
                                      Settings(fit_films=arguments.verify, search=arguments.verify))
            rows += [(delta.mean, os.path.basename(path), source.name, _opaque(source), untrusted(source) is None)
                     for source, delta in measure(conversion)]
        means = sorted(r[0] for r in rows)
        p95 = means[int(0.95 * (len(means) - 1))]
        opaque = [r[0] for r in rows if r[3]]
        print(f"{target}: {len(means)} materials, under 2.3: {sum(m < 2.3 for m in means) / len(means):.1%} "
              f"(opaque ones: {sum(m < 2.3 for m in opaque) / max(len(opaque), 1):.1%} of {len(opaque)}), "
              f"median {statistics.median(means):.2f}, p95 {p95:.2f}")
        trusted = [r for r in rows if r[4]]
        print(f"    where the evaluator is a trusted judge (no IOR below 1, no film on a metal or much denser than its base: "
              f"appearance.untrusted): {sum(r[0] < 2.3 for r in trusted) / max(len(trusted), 1):.1%} of {len(trusted)} "
              f"(opaque: {sum(r[0] < 2.3 for r in trusted if r[3]) / max(sum(r[3] for r in trusted), 1):.1%} "
              f"of {sum(r[3] for r in trusted)})")
        for space in COLORSPACES:
            of_space = [r[0] for r in rows if r[1].endswith(f"_{space}.mtlx")]
            print(f"    {space + ' document':16s} {len(of_space):4d}  under 2.3: "
                  f"{sum(m < 2.3 for m in of_space) / max(len(of_space), 1):6.1%}")
        for kind in sorted(set(kinds.values())):
            of_kind = [r[0] for r in rows if kinds.get((r[1], r[2])) == kind]
            print(f"    {kind:16s} {len(of_kind):4d}  under 2.3: {sum(m < 2.3 for m in of_kind) / len(of_kind):6.1%}"
                  f"  median {statistics.median(of_kind):5.2f}  worst {max(of_kind):6.2f}")
        for mean, file, name, *_ in sorted(rows)[-arguments.worst:]:
            print(f"    {mean:6.2f}  {file} {name} {kinds.get((file, name), '')}")
    print(f"{time.perf_counter() - start:.0f} s")


if __name__ == "__main__":
    main()
