"""The candidate search's cost: generated OpenPBR materials (tests/generated_materials.py, three
document colour spaces) converted to glTF in one process, with the search (the default) and without
(``Settings(candidates=False)``, the conversion before the search existed), side by side.

    python tests/benchmarks/bench_candidates.py [--count 1000] [--seed 11] [--target gltf|mtlx|usda]
    python tests/benchmarks/bench_candidates.py --library FOLDER [--target ...]
    python tests/benchmarks/bench_candidates.py --corpus archetypes [--count 1000]

``--library``: the .mtlx files of FOLDER (e.g. tests/data/translation_set, real-world-like materials
where most conversions are exact or only mildly approximated) instead of the generated corpus, where
every material is approximated and most carry a film, a coat and a volume at once; ``--corpus
archetypes``: the kinds artists author (generated_materials.KINDS). "fitted" counts the materials
whose appearance fit (translate/appearance.py) was kept.

Documents of 50 materials each; the two settings alternate document by document (the machine's drift
falls on both). Prints both totals, their ratio (#13's budget: <= 3x) and how many materials the search
evaluated, changed and left.

Session 12 (--count 1000, side by side with c2365b6 in one run): glTF archetypes 3.40x -> 2.51x, all-lobes
4.14x -> 2.91x; --target mtlx 2.21x -> 1.80x / 3.08x -> 2.24x; --target usda 6.57x -> 2.83x / 5.00x -> 2.25x
(the same materials weighed and fitted; the choices the same, bench_fidelity.py's output identical).
"""

from __future__ import annotations

import argparse
import os
import sys
import tempfile
import time

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))

from generated_materials import COLORSPACES, archetype_document, document  # noqa: E402
from openpbr_tools.convert import convert_file  # noqa: E402
from openpbr_tools.translate.common import Settings  # noqa: E402

PER_DOCUMENT = 50


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--count", type=int, default=1000)
    parser.add_argument("--seed", type=int, default=11)
    parser.add_argument("--target", default="gltf", choices=("gltf", "mtlx", "usda"))
    parser.add_argument("--library", help="convert the .mtlx files of this folder instead")
    parser.add_argument("--corpus", choices=("all-lobes", "archetypes"), default="all-lobes")
    arguments = parser.parse_args()
    folder = tempfile.mkdtemp(prefix="openpbr-candidates-")
    sources = []
    if arguments.library:
        sources = sorted(os.path.join(arguments.library, n) for n in os.listdir(arguments.library) if n.endswith(".mtlx"))
    for index in range(0 if arguments.library else max(1, arguments.count // PER_DOCUMENT)):
        space = COLORSPACES[index % len(COLORSPACES)]
        path = os.path.join(folder, f"set{index:03d}_{space}.mtlx")
        with open(path, "w", encoding="utf-8") as handle:
            seed = arguments.seed * 1000 + index
            handle.write(archetype_document(space, seed, PER_DOCUMENT)[0] if arguments.corpus == "archetypes"
                         else document("open_pbr_surface", space, seed, PER_DOCUMENT))
        sources.append(path)
    model = "standard_surface" if arguments.target == "mtlx" else None
    out = os.path.join(folder, f"out.{arguments.target}")
    convert_file(sources[0], out, model, Settings())  # load libraries and tables once, for both
    totals = {False: 0.0, True: 0.0}
    notes = {False: 0, True: 0}
    fitted = 0
    for path in sources:
        for searched in (False, True):
            start = time.perf_counter()
            result = convert_file(path, out, model, Settings(candidates=searched))
            totals[searched] += time.perf_counter() - start
            notes[searched] += sum("candidates for" in d.message or "translation graphs, which render" in d.message
                                   for d in result.diagnostics)
            if searched:
                fitted += len({d.location.path for d in result.diagnostics if "adjusted to" in d.message})
    materials = len(sources) if arguments.library else len(sources) * PER_DOCUMENT
    print(f"{materials} {'files' if arguments.library else 'materials'} to {arguments.target}: without the search {totals[False]:.1f} s, with it "
          f"{totals[True]:.1f} s -> {totals[True] / totals[False]:.2f}x; {notes[True]} materials weighed, {fitted} fitted")


if __name__ == "__main__":
    main()
