"""A full metal's OpenPBR ``specular_weight`` to Standard Surface as its coat's tint (translate/ss_metal_weight.py).

The expectations come from MaterialX's node graphs, not from the module: open_pbr_surface.mtlx weights its metal BSDF
(``metal_bsdf``) by ``specular_weight``, whole; standard_surface.mtlx multiplies what lies under its coat by
``mix(1, coat_color, coat)`` (``coat_attenuation``), and its coat reflects by a dielectric Fresnel of ``coat_IOR``,
((n - 1) / (n + 1))^2 = 0 at n = 1. The graphs are read here from the MaterialX wheel, so a MaterialX whose graphs
change fails the test that relies on them. MaterialX's GLSL judges one material of each kind (skipped without GL).
"""

from __future__ import annotations

import os
import re
import sys
from pathlib import Path

import MaterialX as mx
import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).resolve().parent))
sys.path.insert(0, str(Path(__file__).resolve().parent / "benchmarks"))

from openpbr_tools import tables  # noqa: E402
from openpbr_tools.convert import convert_file  # noqa: E402
from openpbr_tools.evaluate.verify import compare_materials  # noqa: E402
from openpbr_tools.model import Constant, Input, Location, Material, Texture  # noqa: E402
from openpbr_tools.rules import Context  # noqa: E402
from openpbr_tools.translate import candidates  # noqa: E402
from openpbr_tools.translate.common import Settings  # noqa: E402
from openpbr_tools.translate.convert import convert  # noqa: E402

L = Location("m.mtlx", 1, "S")


def _material(**values) -> Material:
    table = tables.table("open_pbr_surface")
    inputs = {}
    for name, value in values.items():
        inputs[name] = Input(name, table[name].type, value if isinstance(value, Texture) else Constant(value),
                             L.with_input(name))
    return Material("S", "open_pbr_surface", L, inputs, version=table.version)


def _ss(material: Material, **settings) -> tuple[Material, list]:
    s = Settings(context=Context(), **settings)
    translation = candidates.choose(material, convert(material, "standard_surface", s), "standard_surface", s)
    return translation.material, translation.diagnostics


def _value(material: Material, name: str):
    entry = material.inputs.get(name)
    return None if entry is None else entry.value.value


def _graph_input(graph: str, node: str, port: str) -> mx.Input:
    library = mx.createDocument()
    mx.loadLibraries(mx.getDefaultDataLibraryFolders(), mx.getDefaultDataSearchPath(), library)
    return library.getNodeGraph(graph).getNode(node).getInput(port)


def test_materialx_graphs_say_what_the_tint_relies_on():
    """OpenPBR's metal BSDF is weighted by specular_weight; Standard Surface's metal is multiplied by the coat's
    attenuation, mix(1, coat_color, coat); its coat reflects with coat_IOR."""
    assert _graph_input("NG_open_pbr_surface_surfaceshader", "metal_bsdf", "weight").getInterfaceName() == \
        "specular_weight"
    attenuation = _graph_input("NG_standard_surface_surfaceshader_100", "coat_attenuation", "fg")
    assert attenuation.getInterfaceName() == "coat_color"
    layered = _graph_input("NG_standard_surface_surfaceshader_100", "thin_film_layer_attenuated", "in2")
    assert layered.getNodeName() == "coat_attenuation"
    assert _graph_input("NG_standard_surface_surfaceshader_100", "coat_bsdf", "ior").getInterfaceName() == "coat_IOR"


@pytest.mark.parametrize("weight", [0.0, 0.1, 0.5, 0.9])
def test_an_uncoated_full_metal_gets_a_reflectionless_grey_coat(weight):
    source = _material(base_metalness=1.0, base_color=(0.9, 0.6, 0.3), specular_weight=weight, specular_roughness=0.3)
    result, notes = _ss(source)
    assert _value(result, "coat") == 1.0 and _value(result, "coat_IOR") == 1.0
    assert _value(result, "coat_color") == pytest.approx((weight,) * 3)
    assert _value(result, "base_color") == pytest.approx((0.9, 0.6, 0.3))  # not folded: the tint dims it
    assert any(n.location.input == "specular_weight" and n.code == "OPBR1102" for n in notes)
    # exact: the two render alike (the fold's edge reaches 1 where OpenPBR's reaches the weight)
    assert compare_materials(source, result).preview.mean < 0.05
    folded, _ = _ss(source, metal_weight_tint=False)
    if weight <= 0.5:
        assert compare_materials(source, folded).preview.mean > 0.3


def test_under_a_coat_the_coat_colour_carries_the_weight():
    """mix(1, C', c) = w mix(1, C, c): C' = w C - (1 - w)(1 - c)/c; a full coat's w C."""
    full = _material(base_metalness=1.0, base_color=(0.8, 0.8, 0.8), specular_weight=0.5, coat_weight=1.0,
                     coat_color=(0.9, 0.8, 0.7), coat_darkening=0.0)
    result, _ = _ss(full)
    assert _value(result, "coat") == 1.0 and _value(result, "coat_color") == pytest.approx((0.45, 0.4, 0.35))
    assert _value(result, "coat_IOR") == pytest.approx(1.6)  # the source's coat (OpenPBR's default IOR) still reflects
    partial = _material(base_metalness=1.0, base_color=(0.8, 0.8, 0.8), specular_weight=0.9, coat_weight=0.8,
                        coat_color=(0.9, 0.8, 0.7), coat_darkening=0.0)
    result, _ = _ss(partial)
    expected = tuple(0.9 * c - 0.1 * 0.2 / 0.8 for c in (0.9, 0.8, 0.7))
    assert _value(result, "coat_color") == pytest.approx(expected)
    assert compare_materials(partial, result).preview.mean < 0.3


@pytest.mark.parametrize("why, values", [
    ("a partial coat whose colour would go below 0", dict(specular_weight=0.2, coat_weight=0.3, coat_darkening=0.0)),
    ("a coat that darkens by the base's albedo", dict(specular_weight=0.5, coat_weight=1.0)),
    ("an emission the coat would tint", dict(specular_weight=0.5, emission_luminance=1.0)),
    ("a dielectric share the tint would dim", dict(specular_weight=0.5, base_metalness=0.7)),
    ("a textured weight", dict(specular_weight=Texture("w.png"))),
    ("a weight of 1", dict(specular_weight=1.0)),
])
def test_the_tint_only_where_exact(why, values):
    source = _material(**{"base_metalness": 1.0, "base_color": (0.8, 0.7, 0.6), **values})
    result, notes = _ss(source)
    assert not any(n.location.input == "specular_weight" and "coat of IOR 1" in n.message for n in notes), why
    assert _value(result, "coat_IOR") != 1.0, why


def test_a_coat_of_weight_0_says_its_inputs_are_not_carried():
    source = _material(base_metalness=1.0, specular_weight=0.4, coat_roughness=0.6, coat_color=(0.2, 0.3, 0.4))
    _, notes = _ss(source)
    said = {n.location.input for n in notes if n.code == "OPBR1102" and "coat_weight is 0" in n.message}
    assert said == {"coat_roughness", "coat_color"}


def test_the_fold_is_kept_where_it_renders_closer():
    """An ACEScg metal whose base colour lies outside Rec.709's gamut: undimmed, MaterialX clips its reflectivity at
    its conductor's 1; dimmed by the fold, it fits (the fidelity corpus's set004 S26). The candidate search renders
    both and keeps the fold, saying so with both figures."""
    source = _material(base_metalness=1.0, base_color=(0.19364316666275017, 1.0, 0.9849335972173878),
                       specular_weight=0.34104730374250436, specular_roughness_anisotropy=0.07330704501436414,
                       specular_color=(0.3113260327486286, 0.2925587328470063, 1.0))
    source.colorspace = "acescg"
    result, notes = _ss(source)
    tint, _ = _ss(source, candidates=False)
    assert _value(tint, "coat_IOR") == 1.0
    assert _value(result, "coat_IOR") != 1.0
    kept = [n for n in notes if n.location.input == "specular_weight" and n.code == "OPBR1103"]
    assert kept and re.search(r"as the coat's tint \d+\.\d\d, folded into the base colour", kept[0].message)
    assert compare_materials(source, result).preview.mean < compare_materials(source, tint).preview.mean


@pytest.mark.gl
def test_materialx_glsl_agrees(tmp_path):
    """MaterialX's GLSL renders the source and both results: the tint within 1 mean CIEDE2000 of the source, the
    fold more than 1 further (bench_ss_metal_weight_glsl.py: 0.21 against 2.30 for such a metal)."""
    from glsupport import comparison_mask, materialx_renderer
    from bench_glsl_sample import values_of as _values

    from openpbr_tools.evaluate.difference import compare_images
    from openpbr_tools.evaluate.preview import Rig

    rig = Rig(size=64)
    renderer = materialx_renderer(rig)
    source = _material(base_metalness=1.0, base_color=(0.95, 0.64, 0.54), specular_weight=0.1, specular_roughness=0.3)
    reference = renderer.render("open_pbr_surface", _values(source))
    mask = comparison_mask(rig) & np.isfinite(reference).all(axis=-1)
    figures = [compare_images(reference, renderer.render("standard_surface", _values(_ss(source, **s)[0])), mask,
                              rig.white()).mean for s in ({}, {"metal_weight_tint": False})]
    assert figures[0] < 1.0 and figures[1] > figures[0] + 1.0, figures


def test_a_converted_file_keeps_the_tint(tmp_path):
    source = tmp_path / "m.mtlx"
    source.write_text("""<?xml version="1.0"?>
<materialx version="1.39" colorspace="lin_rec709">
  <open_pbr_surface name="S" type="surfaceshader" version="1.1.1">
    <input name="base_metalness" type="float" value="1" />
    <input name="base_color" type="color3" value="0.9, 0.6, 0.3" />
    <input name="specular_weight" type="float" value="0.25" />
  </open_pbr_surface>
  <surfacematerial name="M" type="material">
    <input name="surfaceshader" type="surfaceshader" nodename="S" />
  </surfacematerial>
</materialx>
""")
    out = tmp_path / "out.mtlx"
    convert_file(str(source), str(out), "standard_surface", Settings())
    document = mx.createDocument()
    mx.readFromXmlFile(document, str(out))
    shader = document.getNode("S")
    assert shader.getInputValue("coat") == 1.0 and shader.getInputValue("coat_IOR") == 1.0
    assert list(shader.getInputValue("coat_color").asTuple()) == pytest.approx([0.25] * 3)
    assert os.path.getsize(out) > 0
