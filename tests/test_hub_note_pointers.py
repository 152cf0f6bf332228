"""A note that points at another ("see the note at X") names a place where a note stands in the same report (session
25's review, tenth finding: through the OpenPBR hub the pointed-at note was moved to the source's input, while the
pointer still named the OpenPBR input; and where MaterialX's translation graphs' result was kept, the pointers outlived
the mapping's notes they pointed at)."""

from __future__ import annotations

import collections
import re

import pytest

from openpbr_tools.convert import convert_file
from openpbr_tools.translate.common import Settings

PREVIEW = """#usda 1.0
(
    metersPerUnit = 1
    upAxis = "Y"
)
def Material "M"
{
    token outputs:surface.connect = </M/P.outputs:surface>
    def Shader "P"
    {
        uniform token info:id = "UsdPreviewSurface"
        color3f inputs:diffuseColor = (0.8, 0.1, 0.1)
        int inputs:useSpecularWorkflow = 1
        color3f inputs:specularColor = (0.9, 0.6, 0.2)
        float inputs:clearcoat = 0.5
        float inputs:opacityThreshold = 0.5
        token outputs:surface
    }
}
"""

STANDARD_SURFACE = """<?xml version="1.0"?>
<materialx version="1.39" colorspace="lin_rec709">
  <standard_surface name="P" type="surfaceshader">
    <input name="base_color" type="color3" value="1, 0.48496205210448684, 0.19689986628604078" />
    <input name="coat" type="float" value="0.5" />
    <input name="coat_IOR" type="float" value="1.5" />
    <input name="coat_affect_roughness" type="float" value="7.999999063201813e-06" />
    <input name="coat_roughness" type="float" value="0.01" />
    <input name="metalness" type="float" value="0.7201554645461152" />
    <input name="specular" type="float" value="0.9294695362283877" />
    <input name="specular_IOR" type="float" value="3.1416407864998734" />
    <input name="specular_color" type="color3" value="1, 0.9471456754510225, 0.7461703257600047" />
    <input name="specular_roughness" type="float" value="0.5" />
  </standard_surface>
  <surfacematerial name="M" type="material">
    <input name="surfaceshader" type="surfaceshader" nodename="P" />
  </surfacematerial>
</materialx>
"""

OUTPUTS = [("mtlx", "open_pbr_surface"), ("mtlx", "standard_surface"), ("mtlx", "gltf_pbr"),
           ("mtlx", "UsdPreviewSurface"), ("gltf", None), ("usda", None)]


@pytest.mark.parametrize("name, text", [("prev.usda", PREVIEW), ("ss.mtlx", STANDARD_SURFACE)])
@pytest.mark.parametrize("suffix, model", OUTPUTS)
def test_every_pointer_names_a_note(tmp_path, name, text, suffix, model):
    source = tmp_path / name
    source.write_text(text)
    conversion = convert_file(str(source), str(tmp_path / f"out.{suffix}"), model, Settings())
    where = collections.defaultdict(set)
    for note in conversion.diagnostics:
        where[(note.location.file, note.location.path)].add(note.location.input)
    pointers = 0
    for note in conversion.diagnostics:
        for found in re.finditer(r"see the note at ([A-Za-z_0-9 ]+?)\)", note.message):
            pointers += 1
            sites = where[(note.location.file, note.location.path)]
            pointed = found.group(1)
            assert (None in sites) if pointed == "the material" else (pointed in sites), note.message
    if (name, suffix, model) in (("prev.usda", "gltf", None), ("ss.mtlx", "mtlx", "UsdPreviewSurface")):
        assert pointers  # (the cases the review found: the test looks at pointers that exist)
