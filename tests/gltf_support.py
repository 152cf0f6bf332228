"""Helpers for the glTF tests: the Khronos glTF-Validator, run through node.

The validator is the npm package ``gltf-validator`` (CI installs it and exports
``OPENPBR_GLTF_VALIDATOR`` with its folder). :func:`validate_with_khronos` runs its JavaScript API
(``validateBytes`` with an ``externalResourceFunction`` that reads files beside the asset) and
returns the report's ``issues`` object; :func:`require_validator` skips the calling test, saying why,
when node or the package is missing.
"""

from __future__ import annotations

import json
import os
import shutil
import subprocess

import pytest

DEFAULT_VALIDATOR = os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), ".ci-node", "node_modules",
                                 "gltf-validator")

SCRIPT = r"""
const fs = require("fs");
const path = require("path");
const validator = require(process.argv[2]);
const file = process.argv[3];
const folder = path.dirname(file);
validator.validateBytes(new Uint8Array(fs.readFileSync(file)), {
    uri: path.basename(file),
    maxIssues: 0,
    writeTimestamp: false,
    externalResourceFunction: (uri) => new Promise((resolve, reject) => {
        fs.readFile(path.resolve(folder, decodeURIComponent(uri)), (error, data) => error ? reject(error.toString()) : resolve(new Uint8Array(data)));
    }),
}).then((report) => {
    process.stdout.write(JSON.stringify({version: validator.version(), issues: report.issues, info: report.info}));
}, (error) => {
    process.stderr.write(String(error));
    process.exit(3);
});
"""


def validator_folder() -> str:
    return os.environ.get("OPENPBR_GLTF_VALIDATOR") or DEFAULT_VALIDATOR


def require_validator() -> tuple[str, str]:
    """(node executable, validator folder), or skip the test with the reason."""
    node = shutil.which("node")
    if node is None:
        pytest.skip("node is not on PATH: the Khronos glTF-Validator (npm gltf-validator) cannot run")
    folder = validator_folder()
    if not os.path.isfile(os.path.join(folder, "package.json")):
        pytest.skip(f"the Khronos glTF-Validator is not installed at {folder} (set OPENPBR_GLTF_VALIDATOR or "
                    "run `npm install --prefix .ci-node gltf-validator`)")
    return node, folder


MANY_SCRIPT = r"""
const fs = require("fs");
const path = require("path");
const validator = require(process.argv[2]);
(async () => {
    const out = {};
    for (const file of process.argv.slice(3)) {
        const folder = path.dirname(file);
        const report = await validator.validateBytes(new Uint8Array(fs.readFileSync(file)), {
            uri: path.basename(file), maxIssues: 0, writeTimestamp: false,
            externalResourceFunction: (uri) => new Promise((resolve, reject) => {
                fs.readFile(path.resolve(folder, decodeURIComponent(uri)), (error, data) => error ? reject(error.toString()) : resolve(new Uint8Array(data)));
            }),
        });
        out[file] = {version: validator.version(), issues: report.issues, info: report.info};
    }
    process.stdout.write(JSON.stringify(out));
})().catch((error) => { process.stderr.write(String(error)); process.exit(3); });
"""


def validate_many_with_khronos(paths, tmp_path) -> dict:
    """:func:`validate_with_khronos` for several files in one node process (node and the validator's
    JavaScript take seconds to start): absolute path -> report."""
    node, folder = require_validator()
    script = os.path.join(str(tmp_path), "run_gltf_validator_many.js")
    with open(script, "w", encoding="utf-8") as handle:
        handle.write(MANY_SCRIPT)
    completed = subprocess.run([node, script, os.path.abspath(folder), *(os.path.abspath(str(p)) for p in paths)],
                               capture_output=True, text=True, timeout=120)
    if completed.returncode != 0:
        raise AssertionError(f"glTF-Validator failed to run: {completed.stderr.strip()}")
    return json.loads(completed.stdout)


def validate_with_khronos(path, tmp_path) -> dict:
    """The validator's report for ``path``: ``{"version", "issues": {"numErrors", ..., "messages"}, "info"}``."""
    node, folder = require_validator()
    script = os.path.join(str(tmp_path), "run_gltf_validator.js")
    with open(script, "w", encoding="utf-8") as handle:
        handle.write(SCRIPT)
    completed = subprocess.run([node, script, os.path.abspath(folder), os.path.abspath(str(path))],
                               capture_output=True, text=True, timeout=60)
    if completed.returncode != 0:
        raise AssertionError(f"glTF-Validator failed to run on {path}: {completed.stderr.strip()}")
    return json.loads(completed.stdout)


def describe_issues(report: dict) -> str:
    """All messages, one a line, for an assertion message."""
    issues = report["issues"]
    lines = [f"glTF-Validator {report['version']}: {issues['numErrors']} errors, {issues['numWarnings']} warnings, "
             f"{issues['numInfos']} infos, {issues['numHints']} hints"]
    severities = {0: "error", 1: "warning", 2: "info", 3: "hint"}
    for message in issues["messages"]:
        lines.append(f"  {severities.get(message['severity'], message['severity'])} {message['code']} "
                     f"{message.get('pointer', '')}: {message['message']}")
    return "\n".join(lines)


def place2d(uv, transform):
    """MaterialX ``place2d`` with operation order 0 (stdlib ``NG_place2d_vector2``: subtract pivot,
    divide by scale, ``rotate2d`` as ``mx_rotate_vector2.glsl`` computes it, subtract offset, add pivot)."""
    import math

    x, y = uv[0] - transform.pivot[0], uv[1] - transform.pivot[1]
    x, y = x / transform.scale[0], y / transform.scale[1]
    angle = math.radians(transform.rotate)
    x, y = math.cos(angle) * x + math.sin(angle) * y, -math.sin(angle) * x + math.cos(angle) * y
    return x - transform.offset[0] + transform.pivot[0], y - transform.offset[1] + transform.pivot[1]


def gltf_pbr_material(name: str = "M", **values):
    """A gltf_pbr 2.0.1 Material with the given inputs (a Texture or a constant per parameter)."""
    from openpbr_tools import tables
    from openpbr_tools.model import Constant, Input, Location, Material, Texture

    table = tables.table("gltf_pbr", "2.0.1")
    material = Material(name=name, model="gltf_pbr", location=Location("memory", path=name), version="2.0.1",
                        material_name=name)
    for parameter, value in values.items():
        wrapped = value if isinstance(value, Texture) else Constant(value)
        material.inputs[parameter] = Input(parameter, table[parameter].type, wrapped, Location("memory", path=name, input=parameter))
    return material
