"""A long sweep of the converter's outputs through the validator (the CI test runs a small sample).

    python tests/benchmarks/sweep_convert_outputs.py [--seed 7] [--count 150]

For every model and document colour space, writes --count generated materials
(tests/generated_materials.py: every parameter over its legal range, absent-means-default, closed
bounds), converts them to USD, .mtlx in each model and glTF, validates each output and prints every
error code the source did not already have. Silence means none.
"""

from __future__ import annotations

import argparse
import collections
import os
import sys
import tempfile

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))

from generated_materials import COLORSPACES, document  # noqa: E402
from openpbr_tools import tables  # noqa: E402
from openpbr_tools.convert import convert_file  # noqa: E402
from openpbr_tools.translate.common import Settings  # noqa: E402
from openpbr_tools.validate import Options, validate_paths  # noqa: E402

OUTPUTS = {"usda": None, "mtlx": None, "standard_surface.mtlx": "standard_surface", "gltf_pbr.mtlx": "gltf_pbr",
           "preview.mtlx": "UsdPreviewSurface", "gltf": None}


def _errors(path: str) -> list:
    report = validate_paths([path], options=Options(use_config=False, jobs=1))
    return [d for d in report.diagnostics if str(d.severity) == "error"]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seed", type=int, default=7)
    parser.add_argument("--count", type=int, default=150)
    arguments = parser.parse_args()
    for model in tables.MODELS:
        for space in COLORSPACES:
            folder = tempfile.mkdtemp(prefix="openpbr-sweep-")
            source = os.path.join(folder, "source.mtlx")
            with open(source, "w", encoding="utf-8") as handle:
                handle.write(document(model, space, arguments.seed, arguments.count))
            before = collections.Counter(d.code for d in _errors(source))
            for suffix, target in OUTPUTS.items():
                out = os.path.join(folder, f"out.{suffix}")
                convert_file(source, out, target, Settings())
                found = _errors(out)
                new = collections.Counter(d.code for d in found) - before
                if new:
                    print(model, space, suffix, dict(new),
                          [(d.code, d.location.path, d.message[:120]) for d in found if d.code in new][:3])


if __name__ == "__main__":
    main()
