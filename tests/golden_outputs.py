"""Byte-for-byte record of what the toolkit writes: every output format and every report format.

``produce(folder)`` copies the shipped samples and the translation set into ``folder`` and, working
there with relative paths (so no absolute path of this machine enters a file), runs the command line
in-process:

* ``openpbr validate`` over all inputs, in every report format;
* ``openpbr convert`` of every input into every output format in rotation (``.mtlx`` with each of the
  four ``--to`` models, ``.usda``, ``.usdc``, ``.usdz``, ``.gltf``, ``.glb``), the loss report in
  every report format in rotation, with ``--verify`` on every third conversion;
* the glTF, USD and Standard Surface outputs of the samples converted back to OpenPBR ``.mtlx``
  (the reverse directions and the non-MaterialX readers).

It returns ``{relative name: sha256}`` of every output file, every image written beside one, and
every report (stdout) with its exit code. Each decimal number in a text output, a report or a GLB's
JSON chunk is hashed as the float32 a renderer reads (``_float32``): a value a fit computes differs
in its last bits between CPUs (NumPy's AVX-512 and AVX2 exp and power: 0.029840055505346068 on one,
...078 on another), which no renderer sees and this record must not. ``tests/data/golden_outputs.json`` holds the record made
before the architecture change (issue 11); ``test_golden_outputs.py`` compares against it.

Regenerate (only when a change of output is intended, and say why in the commit):
``python tests/golden_outputs.py``.
"""

from __future__ import annotations

import hashlib
import json
import os
import re
import shutil
import struct
import sys
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
RECORD = HERE / "data" / "golden_outputs.json"
OUTPUTS = ("mtlx:open_pbr_surface", "usda", "gltf", "mtlx:standard_surface", "glb", "usdz",
           "mtlx:gltf_pbr", "usdc", "mtlx:UsdPreviewSurface")
REPORTS = ("json", "text", "sarif", "junit", "github", "jsonl")


_ROOTS: list[bytes] = []  # the working folder as it may appear in messages, replaced by "<root>"


_DECIMAL = re.compile(rb"-?\d+\.\d+(?:[eE][-+]?\d+)?")
_FLOAT32_MAX = float(np.finfo(np.float32).max)


def _as_float32(match: re.Match) -> bytes:
    value = float(match.group())
    return match.group() if abs(value) > _FLOAT32_MAX else str(np.float32(value)).encode()


def _float32(data: bytes) -> bytes:
    """``data`` with every decimal number at the shortest text of its nearest float32; a GLB's JSON chunk
    likewise (its binary chunk, images and packed USD are left as they are: they hold float32 already)."""
    if data[:4] == b"glTF" and len(data) >= 20:
        length, kind = struct.unpack_from("<I4s", data, 12)
        if kind == b"JSON":
            return data[:20] + _DECIMAL.sub(_as_float32, data[20:20 + length]) + data[20 + length:]
        return data
    try:
        data.decode("utf-8")
    except UnicodeDecodeError:
        return data
    return _DECIMAL.sub(_as_float32, data)


def _digest(data: bytes) -> str:
    for root in _ROOTS:
        data = data.replace(root, b"<root>")
    return hashlib.sha256(_float32(data)).hexdigest()


def _inputs(folder: Path) -> list[str]:
    from openpbr_tools.resources import data_dir

    samples = Path(str(data_dir("samples")))
    shutil.copytree(samples, folder / "samples")
    shutil.copytree(HERE / "data" / "translation_set", folder / "set")
    return sorted(str(p.relative_to(folder)).replace(os.sep, "/")
                  for p in folder.rglob("*.mtlx"))


def _run(runner, args: list[str]) -> tuple[int, bytes]:
    from cli.group import cli

    result = runner.invoke(cli, args, catch_exceptions=False)
    return result.exit_code, result.stdout_bytes


def produce(folder: Path) -> dict[str, str]:
    from click.testing import CliRunner

    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    inputs = _inputs(folder)
    _ROOTS[:] = sorted({os.fsencode(str(folder.absolute())), os.fsencode(os.path.realpath(folder))}, key=len, reverse=True)
    record: dict[str, str] = {}
    previous = os.getcwd()
    os.chdir(folder)
    try:
        runner = CliRunner()
        for report in REPORTS:
            code, out = _run(runner, ["validate", "--no-config", "--jobs", "1", "--format", report, *inputs])
            record[f"validate.{report}"] = f"{code}:{_digest(out)}"
        before = {str(p) for p in Path(".").rglob("*")}
        jobs = []
        for index, source in enumerate(inputs):
            for step in range(2):
                output = OUTPUTS[(2 * index + step) % len(OUTPUTS)]
                report = REPORTS[(index + step) % len(REPORTS)]
                jobs.append((source, output, report, (index + step) % 3 == 0))
        for source in inputs:
            if source.startswith("samples/"):
                for output in ("gltf", "usda", "mtlx:standard_surface", "usdz", "glb"):
                    jobs.append((source, output, "json", False))
        written = []
        for source, output, report, verify in jobs:
            suffix, _, model = output.partition(":")
            stem = source.replace("/", "__").removesuffix(".mtlx")
            target = f"out/{stem}.{model or 'default'}.{suffix}"
            args = ["convert", source, "-o", target, "--format", report]
            if model:
                args += ["--to", model]
            if verify:
                args.append("--verify")
            os.makedirs("out", exist_ok=True)
            code, out = _run(runner, args)
            record[f"{target}.report.{report}"] = f"{code}:{_digest(out)}"
            if source.startswith("samples/") and suffix in ("gltf", "glb", "usda", "usdz") or model == "standard_surface":
                written.append(target)
        os.makedirs("back", exist_ok=True)
        for source in sorted(set(written)):
            if not os.path.exists(source):
                continue
            target = "back/" + os.path.basename(source).replace(".", "_") + ".mtlx"
            code, out = _run(runner, ["convert", source, "-o", target, "--format", "json"])
            record[f"{target}.report.json"] = f"{code}:{_digest(out)}"
        for path in sorted(Path(".").rglob("*")):
            name = str(path).replace(os.sep, "/")
            if path.is_file() and name not in before and (name.startswith("out/") or name.startswith("back/")):
                record[name] = _digest(path.read_bytes())
    finally:
        os.chdir(previous)
    return dict(sorted(record.items()))


def main() -> int:
    import tempfile

    sys.path.insert(0, str(HERE.parent))
    with tempfile.TemporaryDirectory(prefix="openpbr-golden-") as folder:
        record = produce(Path(folder))
    RECORD.write_text(json.dumps(record, indent=1, sort_keys=True) + "\n", encoding="utf-8")
    print(f"{len(record)} entries -> {RECORD}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
