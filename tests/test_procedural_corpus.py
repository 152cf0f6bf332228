"""A seeded generated corpus of procedural materials: Standard Surface, glTF PBR, UsdPreviewSurface and
OpenPBR materials (tests/generated_materials.py: every parameter over its range, absent-means-default,
three document colour spaces) with some colour and float inputs driven by node graphs (noise, a
checkerboard, a ramp, arithmetic on them), converted to .mtlx in every model.

Every output loads, passes MaterialX's Document.validate() and generates a GLSL shader, and no
procedural input is lost silently: each one the target has a mapping for either reaches the output as
a connection (its graph kept, with the mapping's nodes after it where the mapping transforms it) or is
reported at that input (OPBR1104).
"""

from __future__ import annotations

import random

import MaterialX as mx
import MaterialX.PyMaterialXGenShader as gs
import pytest

from generated_materials import COLORSPACES, document
from glsupport import shader_generator
from openpbr_tools import tables
from openpbr_tools.convert import convert_file
from openpbr_tools.io import read_asset
from openpbr_tools.model import Connection
from openpbr_tools.translate.common import Settings

MODELS = ("standard_surface", "gltf_pbr", "UsdPreviewSurface", "open_pbr_surface")
TARGETS = ("open_pbr_surface", "standard_surface", "gltf_pbr", "UsdPreviewSurface")
PER_DOCUMENT = 6


def _graph(doc, rng: random.Random, prefix: str, type_name: str) -> str:
    """A small procedural graph of ``type_name`` at the document's top level; returns its output node."""
    kind = rng.choice(("noise", "checker", "ramp", "scaled noise"))
    if kind == "checker" and type_name == "color3":
        node = doc.addNode("checkerboard", f"{prefix}_checker", "color3")
        node.setInputValue("color1", mx.Color3(rng.random(), rng.random(), rng.random()))
        node.setInputValue("color2", mx.Color3(rng.random(), rng.random(), rng.random()))
        return node.getName()
    if kind == "ramp":
        node = doc.addNode("ramplr", f"{prefix}_ramp", type_name)
        low, high = (mx.Color3(rng.random(), rng.random(), rng.random()), mx.Color3(rng.random(), rng.random(), rng.random())) \
            if type_name == "color3" else (rng.random(), rng.random())
        node.setInputValue("valuel", low)
        node.setInputValue("valuer", high)
        return node.getName()
    noise = doc.addNode("noise3d", f"{prefix}_noise", type_name)
    noise.setInputValue("amplitude", mx.Vector3(0.5, 0.5, 0.5) if type_name == "color3" else 0.5)
    noise.setInputValue("pivot", 0.5)
    if kind != "scaled noise":
        return noise.getName()
    scaled = doc.addNode("multiply", f"{prefix}_scaled", type_name)
    scaled.addInput("in1", type_name).setNodeName(noise.getName())
    scaled.setInputValue("in2", mx.Color3(0.9, 0.7, 0.5) if type_name == "color3" else 0.8)
    return scaled.getName()


def procedural_document(model: str, colorspace: str, seed: int) -> tuple[str, dict]:
    """A generated document of ``model`` with one to three inputs per shader driven by a graph; also
    {shader: [procedural input names]}."""
    text = document(model, colorspace, seed, PER_DOCUMENT)
    doc = mx.createDocument()
    mx.readFromXmlString(doc, text)
    rng = random.Random(f"procedural/{model}/{colorspace}/{seed}")
    table = tables.table(model)
    driven = {}
    for shader in [n for n in doc.getNodes() if n.getType() == "surfaceshader"]:
        candidates = sorted(name for name, p in table.parameters.items()
                            if p.type in ("color3", "float") and p.role not in ("normal", "tangent") and not p.uniform)
        names = rng.sample(candidates, rng.randint(1, 3))
        for name in names:
            port = shader.getInput(name) or shader.addInput(name, table[name].type)
            port.removeAttribute("value")
            port.setNodeName(_graph(doc, rng, f"{shader.getName()}_{name}", table[name].type))
        driven[shader.getName()] = names
    return mx.writeToXmlString(doc), driven


@pytest.fixture(scope="module")
def generator():
    return shader_generator()


@pytest.mark.parametrize("colorspace", COLORSPACES)
@pytest.mark.parametrize("model", MODELS)
def test_procedural_inputs_are_kept_or_reported_and_every_output_renders(tmp_path, generator, model, colorspace):
    library, glsl, context = generator
    text, driven = procedural_document(model, colorspace, seed=29)
    source = tmp_path / "source.mtlx"
    source.write_text(text)
    for target in TARGETS:
        out = tmp_path / f"out_{target}.mtlx"
        conversion = convert_file(str(source), str(out), target, Settings())
        written = mx.createDocument()
        mx.readFromXmlFile(written, str(out))
        written.importLibrary(library)
        valid, message = written.validate()
        assert valid, f"{target}: {message}"
        for element in gs.findRenderableElements(written):
            assert glsl.generate("check", element, context).getSourceCode(gs.PIXEL_STAGE)
        results = {m.name: m for m in read_asset(str(out)).materials}
        reported = {(d.location.path, d.location.input) for d in conversion.diagnostics
                    if d.code == "OPBR1104" or (d.code == "OPBR1102" and "not carried" in d.message)}
        for shader, names in driven.items():
            graphs = " ".join(e.value.graph_xml or "" for e in results[shader].inputs.values()
                              if isinstance(e.value, Connection))
            for name in names:
                kept = f"{shader}_{name}_" in graphs
                assert kept or (shader, name) in reported, f"{model} -> {target}: {shader}.{name} neither kept nor reported"
