"""Throughput of ``openpbr convert`` to glTF on 1,000 constant-valued OpenPBR materials.

    python tests/benchmarks/bench_convert_many.py [--materials 1000] [--seed 7] [--cli-files 100] [--keep FOLDER]

Generates ``--materials`` random but valid OpenPBR 1.1.1 materials (seeded; every parameter of the
table authored with probability 1/2, drawn uniformly within its soft range, else its hard range;
lengths carry ``unit="centimeter"``; each document validates without errors) written twice: as
**one** ``.mtlx`` holding every material, and as **one file per material**. Then measures, each in
a fresh process so that peak RSS belongs to the conversion alone:

1. ``openpbr convert many.mtlx -o many.gltf``: one CLI call, one document -> one .gltf holding
   every material (the CLI takes one input file; a folder is refused with exit code 2);
2. the same in-process: ``convert_file`` timed around the call, imports excluded;
3. the 1,000 files converted in one process (``convert_file`` in a loop);
4. the 1,000 files through the CLI, one call per file: ``--cli-files`` of them (default 100; the
   figure for all is extrapolated and marked so), since each call pays the interpreter start.

Reported: wall time, materials per second, peak resident set size (``ru_maxrss`` of that child,
read by a small launcher process, since a forked child's peak starts at its parent's RSS; the
launcher adds about 20 ms of interpreter start to each wall time).
"""

from __future__ import annotations

import argparse
import json
import math
import os
import resource
import shutil
import subprocess
import sys
import tempfile
import time

#: Parameters the generator does not author (geometric inputs; no constant value to draw).
SKIPPED_ROLES = ("normal", "tangent", "filename", "string")
#: Upper bound for parameters with neither a soft nor a hard maximum (lengths, specular_weight).
UNBOUNDED_MAX = {"scene_length": 5.0}


def _fmt(value) -> str:
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, (tuple, list)):
        return ", ".join(f"{v:.4g}" for v in value)
    return f"{value:.4g}"


def random_material_inputs(rng, table) -> list[str]:
    """``<input>`` lines for one random material: each parameter with probability 1/2."""
    lines = []
    for name, parameter in table.parameters.items():
        if parameter.role in SKIPPED_ROLES or parameter.default_geomprop or rng.random() < 0.5:
            continue
        if parameter.type == "boolean":
            value = bool(rng.random() < 0.5)
        else:
            low = parameter.soft_min if parameter.soft_min is not None else parameter.hard_min
            high = parameter.soft_max if parameter.soft_max is not None else parameter.hard_max
            low = 0.0 if low is None else low
            high = UNBOUNDED_MAX.get(parameter.unit or "", 1.0) if high is None else high
            if parameter.type == "color3":
                lows = low if isinstance(low, (tuple, list)) else (low,) * 3
                highs = high if isinstance(high, (tuple, list)) else (high,) * 3
                value = tuple(float(rng.uniform(lo, hi)) for lo, hi in zip(lows, highs))
            else:
                value = float(rng.uniform(float(low), float(high)))
        unit = ' unittype="distance" unit="centimeter"' if parameter.unit == "scene_length" else ""
        lines.append(f'    <input name="{name}" type="{parameter.type}" value="{_fmt(value)}"{unit} />')
    return lines


def material_xml(index: int, inputs: list[str]) -> str:
    name = f"M{index:04d}"
    return "\n".join([
        f'  <open_pbr_surface name="{name}" type="surfaceshader" version="1.1.1">', *inputs, "  </open_pbr_surface>",
        f'  <surfacematerial name="{name}_material" type="material">',
        f'    <input name="surfaceshader" type="surfaceshader" nodename="{name}" />', "  </surfacematerial>",
    ])


def document(bodies: list[str]) -> str:
    return '<?xml version="1.0"?>\n<materialx version="1.39" colorspace="lin_rec709">\n' + "\n".join(bodies) + "\n</materialx>\n"


def generate(folder: str, count: int, seed: int) -> tuple[str, list[str]]:
    """Write ``many.mtlx`` and ``files/M0000.mtlx`` ...; returns their paths."""
    import numpy as np

    from openpbr_tools import tables

    rng = np.random.default_rng(seed)
    table = tables.table("open_pbr_surface")
    bodies = [material_xml(i, random_material_inputs(rng, table)) for i in range(count)]
    many = os.path.join(folder, "many.mtlx")
    with open(many, "w", encoding="utf-8") as handle:
        handle.write(document(bodies))
    os.makedirs(os.path.join(folder, "files"), exist_ok=True)
    singles = []
    for index, body in enumerate(bodies):
        path = os.path.join(folder, "files", f"M{index:04d}.mtlx")
        with open(path, "w", encoding="utf-8") as handle:
            handle.write(document([body]))
        singles.append(path)
    return many, singles


#: Runs argv[2:] and writes its exit code and peak RSS to argv[1]. A small launcher, because a
#: child's ru_maxrss starts from the RSS of the process that forked it (this benchmark's is large).
LAUNCHER = (
    "import json, os, subprocess, sys\n"
    "process = subprocess.Popen(sys.argv[2:])\n"
    "_, status, usage = os.wait4(process.pid, 0)\n"
    "json.dump({'returncode': os.waitstatus_to_exitcode(status), 'peak_rss_mib': usage.ru_maxrss / 1024.0},"
    " open(sys.argv[1], 'w'))\n"
)


def run_measured(argv: list[str]) -> dict:
    """Run ``argv``: wall time, exit code, the child's own peak RSS in MiB, stdout and stderr."""
    with tempfile.TemporaryDirectory() as folder:
        usage_file = os.path.join(folder, "usage.json")
        start = time.perf_counter()
        completed = subprocess.run([sys.executable, "-c", LAUNCHER, usage_file, *argv], capture_output=True, text=True,
                                   check=False)
        wall = time.perf_counter() - start
        with open(usage_file, encoding="utf-8") as handle:
            usage = json.load(handle)
    return {"wall_s": wall, "returncode": usage["returncode"], "peak_rss_mib": usage["peak_rss_mib"],
            "stdout": completed.stdout, "stderr": completed.stderr}


def openpbr_command() -> list[str]:
    executable = shutil.which("openpbr")
    return [executable] if executable else [sys.executable, "-m", "cli.main"]


def in_process(mode: str, paths: list[str], output_folder: str) -> None:
    """Child entry point: time ``convert_file`` (imports done first) and print JSON."""
    from openpbr_tools.io import read_asset  # noqa: F401 - imported before timing
    from openpbr_tools.convert import convert_file

    os.makedirs(output_folder, exist_ok=True)
    start = time.perf_counter()
    materials = 0
    for path in paths:
        result = convert_file(path, os.path.join(output_folder, os.path.splitext(os.path.basename(path))[0] + ".gltf"))
        materials += len(result.materials)
    seconds = time.perf_counter() - start
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0
    print(json.dumps({"mode": mode, "seconds": seconds, "materials": materials, "peak_rss_mib": peak}))


def gltf_material_count(path: str) -> int:
    with open(path, encoding="utf-8") as handle:
        return len(json.load(handle).get("materials", []))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--materials", type=int, default=1000)
    parser.add_argument("--seed", type=int, default=7)
    parser.add_argument("--cli-files", type=int, default=100, help="files converted by one CLI call each (sample)")
    parser.add_argument("--keep", help="generate into this folder and keep it")
    parser.add_argument("--in-process", nargs="+", help=argparse.SUPPRESS)  # child mode: MODE OUTPUT PATH...
    options = parser.parse_args()
    if options.in_process:
        mode, output, *paths = options.in_process
        in_process(mode, paths, output)
        return

    folder = options.keep or tempfile.mkdtemp(prefix="openpbr-bench-many-")
    os.makedirs(folder, exist_ok=True)
    start = time.perf_counter()
    many, singles = generate(folder, options.materials, options.seed)
    print(f"generated {options.materials} materials in {time.perf_counter() - start:.1f} s: {many} "
          f"({os.path.getsize(many) / 1024:.0f} KiB) and {len(singles)} files in {os.path.dirname(singles[0])}")

    from openpbr_tools.validate import validate_file

    errors = sum(1 for d in validate_file(many).diagnostics if str(d.severity) == "error")
    print(f"openpbr validate of many.mtlx: {errors} error(s)")
    results = {"materials": options.materials, "seed": options.seed, "folder": folder, "validate_errors": errors}

    command = openpbr_command()
    refused = run_measured(command + ["convert", os.path.dirname(singles[0]), "-o", os.path.join(folder, "dir.gltf")])
    results["cli_folder_input_exit_code"] = refused["returncode"]
    print(f"openpbr convert FOLDER -o x.gltf: exit {refused['returncode']} "
          f"({(refused['stderr'].strip().splitlines() or [''])[-1][:120]})")

    rows = []
    out = os.path.join(folder, "many.gltf")
    cli = run_measured(command + ["convert", many, "-o", out, "--force", "--format", "json"])
    count = gltf_material_count(out) if cli["returncode"] == 0 else 0
    rows.append(("CLI, one document -> one .gltf", cli["wall_s"], count, cli["peak_rss_mib"], cli["returncode"], ""))

    child = run_measured([sys.executable, os.path.abspath(__file__), "--in-process", "one-document",
                          os.path.join(folder, "inprocess_one"), many])
    report = json.loads(child["stdout"].strip().splitlines()[-1]) if child["returncode"] == 0 else {}
    rows.append(("in-process convert_file, one document", report.get("seconds", float("nan")), report.get("materials", 0),
                 child["peak_rss_mib"], child["returncode"], "imports excluded"))

    child = run_measured([sys.executable, os.path.abspath(__file__), "--in-process", "many-files",
                          os.path.join(folder, "inprocess_files"), *singles])
    report = json.loads(child["stdout"].strip().splitlines()[-1]) if child["returncode"] == 0 else {}
    rows.append((f"in-process convert_file, {len(singles)} files", report.get("seconds", float("nan")),
                 report.get("materials", 0), child["peak_rss_mib"], child["returncode"], "imports excluded"))

    sample = singles[: max(1, min(options.cli_files, len(singles)))]
    start, peak, failures = time.perf_counter(), 0.0, 0
    os.makedirs(os.path.join(folder, "cli_files"), exist_ok=True)
    for path in sample:
        one = run_measured(command + ["convert", path, "-o", os.path.join(folder, "cli_files", os.path.basename(path)[:-5] + ".gltf"),
                                      "--force"])
        peak = max(peak, one["peak_rss_mib"])
        failures += one["returncode"] != 0
    wall = time.perf_counter() - start
    note = f"{len(sample)} calls measured" + (f"; x{len(singles) / len(sample):.0f} extrapolated for all" if len(sample) < len(singles) else "")
    rows.append((f"CLI, one call per file ({len(sample)} files)", wall, len(sample) - failures, peak, failures, note))

    print(f"\n{'run':46s} {'wall s':>8s} {'materials':>9s} {'mat/s':>8s} {'peak RSS MiB':>13s}  exit  note")
    for label, seconds, materials, rss, code, note in rows:
        rate = materials / seconds if math.isfinite(seconds) and seconds > 0 else float("nan")
        print(f"{label:46s} {seconds:8.2f} {materials:9d} {rate:8.1f} {rss:13.1f}  {code:4d}  {note}")
        results.setdefault("runs", []).append({"run": label, "seconds": seconds, "materials": materials,
                                               "materials_per_second": rate, "peak_rss_mib": rss, "exit": code, "note": note})
    if len(sample) < len(singles):
        per_call = rows[-1][1] / len(sample)
        print(f"  -> all {len(singles)} files through the CLI: about {per_call * len(singles):.0f} s ({per_call:.2f} s per call)")
    with open(os.path.join(folder, "results.json"), "w", encoding="utf-8") as handle:
        json.dump(results, handle, indent=1)
    print(f"\nresults: {os.path.join(folder, 'results.json')}")


if __name__ == "__main__":
    main()
