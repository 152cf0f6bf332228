"""Benchmark `openpbr validate` on one USD stage with many OpenPBR materials, against usd-core's own
validators on the same stage.

    python tests/benchmarks/bench_usd.py [--materials 1000] [--repeat 5] [--format usdc|usda]

The stage is generated with the pxr API: each Material holds an OpenPBR shader with eight
constants, a base-colour image (``ND_image_color3``, colour space ``srgb_texture``) and a roughness
channel extracted from a second image (colour space ``none``); the images exist on disk. Measured:

1. ``openpbr validate STAGE`` as a process (start-up and ``import pxr`` included), median wall time;
2. in process, median of ``validate_file``: total, and its parts (reading the stage, the toolkit's
   rules, usd-core's validators as folded into OPBR1010);
3. usd-core alone: ``UsdValidation`` with every registered validator on the same open stage, with
   and without the MaterialX node definitions registered in Sdr (without them every shader raises
   MissingShaderIdInRegistry).

Target (issue 3): validating the 1,000-material stage takes under 2 s.
"""

from __future__ import annotations

import argparse
import json
import os
import shutil
import statistics
import subprocess
import sys
import tempfile
import time


def generate(path: str, count: int) -> None:
    from pxr import Gf, Sdf, Usd, UsdGeom, UsdShade

    stage = Usd.Stage.CreateNew(path)
    UsdGeom.SetStageMetersPerUnit(stage, 0.01)
    UsdGeom.SetStageUpAxis(stage, UsdGeom.Tokens.y)
    looks = stage.DefinePrim("/Looks", "Scope")
    stage.SetDefaultPrim(looks)
    types = Sdf.ValueTypeNames
    for i in range(count):
        root = f"/Looks/M{i:04d}"
        material = UsdShade.Material.Define(stage, root)
        shader = UsdShade.Shader.Define(stage, f"{root}/S")
        shader.CreateIdAttr("ND_open_pbr_surface_surfaceshader")
        shader.GetPrim().SetCustomDataByKey("openpbr:version", "1.1.1")
        constants = {
            "base_weight": (types.Float, 1.0), "base_metalness": (types.Float, 0.0),
            "specular_weight": (types.Float, 1.0), "specular_ior": (types.Float, 1.5),
            "coat_weight": (types.Float, 0.1 * (i % 10)), "coat_roughness": (types.Float, 0.1),
            "specular_color": (types.Color3f, Gf.Vec3f(1, 1, 1)), "transmission_depth": (types.Float, 1.0),
        }
        for name, (type_name, value) in constants.items():
            shader.CreateInput(name, type_name).Set(value)
        albedo = UsdShade.Shader.Define(stage, f"{root}/albedo")
        albedo.CreateIdAttr("ND_image_color3")
        albedo.CreateInput("file", types.Asset).Set(Sdf.AssetPath("albedo.png"))
        albedo.GetInput("file").GetAttr().SetColorSpace("srgb_texture")
        shader.CreateInput("base_color", types.Color3f).ConnectToSource(albedo.CreateOutput("out", types.Color3f))
        orm = UsdShade.Shader.Define(stage, f"{root}/orm")
        orm.CreateIdAttr("ND_image_color3")
        orm.CreateInput("file", types.Asset).Set(Sdf.AssetPath("orm.png"))
        orm.GetInput("file").GetAttr().SetColorSpace("none")
        extract = UsdShade.Shader.Define(stage, f"{root}/roughness")
        extract.CreateIdAttr("ND_extract_color3")
        extract.CreateInput("in", types.Color3f).ConnectToSource(orm.CreateOutput("out", types.Color3f))
        extract.CreateInput("index", types.Int).Set(1)
        shader.CreateInput("specular_roughness", types.Float).ConnectToSource(extract.CreateOutput("out", types.Float))
        material.CreateSurfaceOutput("mtlx").ConnectToSource(shader.CreateOutput("surface", types.Token))
    stage.GetRootLayer().Save()
    folder = os.path.dirname(path)
    for name in ("albedo.png", "orm.png"):
        open(os.path.join(folder, name), "wb").close()


def timed(function, *args, **kwargs):
    start = time.perf_counter()
    result = function(*args, **kwargs)
    return time.perf_counter() - start, result


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--materials", type=int, default=1000)
    parser.add_argument("--repeat", type=int, default=5)
    parser.add_argument("--format", choices=("usdc", "usda"), default="usdc")
    args = parser.parse_args()
    openpbr = shutil.which("openpbr") or sys.exit("openpbr is not on PATH (pip install -e .)")
    results: dict[str, object] = {"materials": args.materials, "format": args.format, "cpu_count": os.cpu_count()}
    with tempfile.TemporaryDirectory() as folder:
        path = os.path.join(folder, f"looks.{args.format}")
        generate(path, args.materials)

        runs = []
        for _ in range(args.repeat):
            seconds, _ = timed(subprocess.run, [openpbr, "validate", path], stdout=subprocess.DEVNULL)
            runs.append(seconds)
        results["process_openpbr_validate_s"] = statistics.median(runs)

        from pxr import Usd, UsdValidation

        from openpbr_tools.io.usd.reader import read_usd
        from openpbr_tools.io.usd.errors import quiet
        from openpbr_tools.io.usd.sdr import register_materialx_nodes
        from openpbr_tools.io.usd.validators import usd_core_findings
        from openpbr_tools.rules import check_asset
        from openpbr_tools.validate import validate_file

        validate_file(path)  # warm: pxr, MaterialX libraries, tables, Sdr registrations
        totals, reads, rules, cores = [], [], [], []
        for _ in range(args.repeat):
            seconds, result = timed(validate_file, path)
            totals.append(seconds)
            seconds, asset = timed(read_usd, path, usd_core=False)
            reads.append(seconds)
            rules.append(timed(check_asset, asset)[0])
            stage = Usd.Stage.Open(path)
            cores.append(timed(usd_core_findings, stage)[0])
        results["in_process_validate_file_s"] = statistics.median(totals)
        results["in_process_read_s"] = statistics.median(reads)
        results["in_process_rules_s"] = statistics.median(rules)
        results["in_process_usd_core_folded_s"] = statistics.median(cores)
        results["diagnostics"] = len(result.diagnostics)
        results["materials_read"] = result.materials

        # usd-core on its own, same stage: (a) as shipped, (b) with the MaterialX nodes registered.
        def usd_core_alone():
            stage = Usd.Stage.Open(path)
            context = UsdValidation.ValidationContext(UsdValidation.ValidationRegistry().GetOrLoadAllValidators())
            with quiet():
                return context.Validate(stage)

        code = ("import time, statistics, sys\nfrom pxr import Usd, UsdValidation, Tf\n"
                "context = UsdValidation.ValidationContext(UsdValidation.ValidationRegistry().GetOrLoadAllValidators())\n"
                "times = []\nfor _ in range(int(sys.argv[2])):\n    stage = Usd.Stage.Open(sys.argv[1])\n"
                "    start = time.perf_counter()\n    with Tf.DiagnosticTrap() as trap:\n        errors = context.Validate(stage)\n"
                "        trap.Clear()\n    times.append(time.perf_counter() - start)\n"
                "print(statistics.median(times), len(errors))\n")
        done = subprocess.run([sys.executable, "-c", code, path, str(args.repeat)], capture_output=True, text=True, check=True)
        seconds, count = done.stdout.split()
        results["usd_core_validate_unregistered_s"] = float(seconds)
        results["usd_core_validate_unregistered_findings"] = int(count)
        register_materialx_nodes(["ND_open_pbr_surface_surfaceshader", "ND_image_color3", "ND_extract_color3"])
        alone = []
        for _ in range(args.repeat):
            seconds, errors = timed(usd_core_alone)
            alone.append(seconds)
        results["usd_core_validate_registered_s"] = statistics.median(alone)
        results["usd_core_validate_registered_findings"] = len(errors)
    print(json.dumps(results, indent=2))


if __name__ == "__main__":
    main()
