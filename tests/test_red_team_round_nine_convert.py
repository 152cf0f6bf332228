"""Session 22's red team, set T: Standard Surface libraries migrated to OpenPBR with their graphs (the reverse
direction). A film whose thickness a procedural drives kept its thickness graph but lost its weight (OpenPBR's
default 0: no film), a metal's procedural edge colour was dropped, and a metal's specular 0 became a specular
weight of 0.95 with no note at ``specular``. The anchor is MaterialX's own standard_surface_to_open_pbr graph
(its nodes say what it writes) and MaterialX's reader, validator and shader generator on the output."""

from __future__ import annotations

import os

import MaterialX as mx
import pytest

from glsupport import validated
from openpbr_tools.convert import convert_file
from openpbr_tools.translate.common import Settings

HEAD = '<?xml version="1.0"?>\n<materialx version="1.39" colorspace="lin_rec709">\n'
_FILM = HEAD + '''  <texcoord name="uv" type="vector2" />
  <ramptb name="ramp" type="float">
    <input name="valuet" type="float" value="200" />
    <input name="valueb" type="float" value="800" />
    <input name="texcoord" type="vector2" nodename="uv" />
  </ramptb>
  <ramplr name="edge" type="color3">
    <input name="valuel" type="color3" value="0.9, 0.5, 0.2" />
    <input name="valuer" type="color3" value="0.2, 0.5, 0.9" />
    <input name="texcoord" type="vector2" nodename="uv" />
  </ramplr>
  <standard_surface name="S" type="surfaceshader">
    <input name="base_color" type="color3" value="0.8, 0.6, 0.3" />
    <input name="metalness" type="float" value="{metalness}" />
    <input name="specular" type="float" value="{specular}" />
    {extra}
  </standard_surface>
  <surfacematerial name="M" type="material">
    <input name="surfaceshader" type="surfaceshader" nodename="S" />
  </surfacematerial>
</materialx>
'''


def _translation_graph() -> mx.Document:
    document = mx.createDocument()
    folder = os.path.join(os.path.dirname(mx.__file__), "libraries", "bxdf", "translation")
    mx.readFromXmlFile(document, os.path.join(folder, "standard_surface_to_open_pbr.mtlx"))
    return document


def _convert(tmp_path, text: str):
    source = tmp_path / "ss.mtlx"
    source.write_text(text, encoding="utf-8")
    out = tmp_path / "out" / "openpbr.mtlx"
    conversion = convert_file(str(source), str(out), "open_pbr_surface", Settings())
    document = validated(out)  # MaterialX reads it and its own validate() passes
    shader = next(n for n in document.getNodes() if n.getCategory() == "open_pbr_surface")
    return conversion, shader, document  # (the document owns the shader: kept alive with it)


def test_a_procedural_film_thickness_keeps_its_film(tmp_path):
    """MaterialX's graph writes the film's weight as ifgreater(thickness, 0, 1, 0): on wherever there is a film.
    A constant 1 is the same (a film of thickness 0 is no film: MaterialX's thin-film BSDFs apply only a
    thickness above 0), and the thickness graph is kept, scaled from nanometres to micrometres."""
    assert any(n.getCategory() == "ifgreater" and "thin_film" in n.getName().lower() or
               n.getCategory() == "ifgreater" and "film" in n.getName().lower()
               for n in _translation_graph().getNodeGraph("NG_standard_surface_to_open_pbr_surface").getNodes())
    conversion, shader, _ = _convert(tmp_path, _FILM.format(metalness=0, specular=1, extra=(
        '<input name="thin_film_thickness" type="float" nodename="ramp" />\n'
        '    <input name="thin_film_IOR" type="float" value="1.4" />')))
    weight = shader.getInput("thin_film_weight")
    assert weight is not None and weight.getValue() == 1.0  # was absent: OpenPBR's default 0, no film
    assert shader.getInput("thin_film_thickness").getNodeName()  # the graph, rewired
    assert not [d for d in conversion.diagnostics if str(d.severity) == "error"]


def test_a_procedural_edge_colour_on_a_metal_is_kept(tmp_path):
    """MaterialX's graph passes a metal's specular_color through (ifequal on the metalness); it was dropped."""
    conversion, shader, _ = _convert(tmp_path, _FILM.format(metalness=1, specular=1, extra=(
        '<input name="specular_color" type="color3" nodename="edge" />')))
    assert shader.getInput("specular_color") is not None and shader.getInput("specular_color").getNodeName()
    assert not [d for d in conversion.diagnostics if str(d.severity) == "error"]


@pytest.mark.parametrize("metalness", [1.0, 0.5])
def test_a_metal_specular_of_zero_has_a_note_at_specular(tmp_path, metalness):
    """Standard Surface's specular does not dim its metal, OpenPBR's specular_weight does: the weight is raised
    (exact for a whole metal, an approximation of the dielectric share of a partial one) and says so at the input
    it changes."""
    conversion, shader, _ = _convert(tmp_path, _FILM.format(metalness=metalness, specular=0, extra=""))
    assert shader.getInput("specular_weight").getValue() > 0.5
    at_specular = [d for d in conversion.diagnostics if d.location.input == "specular"]
    assert at_specular
    assert any(str(d.severity) == ("warning" if metalness < 1 else "info") for d in at_specular)
