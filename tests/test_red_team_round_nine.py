"""Session 22's red team, set S: defects as real exporters write them (a Houdini displacement, a Maya look, a Maya
XInclude of its own library, a USDZ packaging its MaterialX document, a UsdPreviewSurface glass fallback). Each test
asks the anchor what a renderer gets (MaterialX's reader and shader generation, usd-core's validators, the
UsdPreviewSurface specification) and checks the tool reports it, and that the legal neighbour stays quiet."""

from __future__ import annotations

import os

import MaterialX as mx
import pytest

from openpbr_tools.rules.usd import _package
from openpbr_tools.rules.usd_examples import stage_example
from glsupport import shader_generator
from redteam_support import findings, mtlx, png

HEAD = '<?xml version="1.0"?>\n<materialx version="1.39" colorspace="lin_rec709">\n'


_DISPLACED = '''  <nodegraph name="NG">
    <image name="height" type="float">
      <input name="file" type="filename" value="height.png"{space} />
    </image>
    <output name="out" type="float" nodename="height" />
  </nodegraph>
  <open_pbr_surface name="S" type="surfaceshader" />
  <displacement name="D" type="displacementshader">
    <input name="displacement" type="float" nodegraph="NG" output="out" />
  </displacement>
  <surfacematerial name="M" type="material">
    <input name="surfaceshader" type="surfaceshader" nodename="S" />
    <input name="displacementshader" type="displacementshader" nodename="D" />
  </surfacematerial>
'''


def _glsl_transforms_colour(document_path) -> bool:
    """Whether MaterialX's GLSL generation emits an sRGB decode for the document's material."""
    import MaterialX.PyMaterialXGenGlsl as mx_glsl
    import MaterialX.PyMaterialXGenShader as mx_gen

    document = mx.createDocument()
    mx.readFromXmlFile(document, str(document_path))
    library = shader_generator()[0]  # (its own generator: a colour management system is set on it below)
    document.importLibrary(library)
    generator = mx_glsl.GlslShaderGenerator.create()
    context = mx_gen.GenContext(generator)
    context.registerSourceCodeSearchPath(mx.getDefaultDataSearchPath())
    color_system = mx_gen.DefaultColorManagementSystem.create(generator.getTarget())
    color_system.loadLibrary(library)
    generator.setColorManagementSystem(color_system)
    shader = generator.generate("M", document.getChild("M"), context)
    return "srgb_texture_to_lin_rec709" in shader.getSourceCode(mx_gen.PIXEL_STAGE)


@pytest.mark.parametrize("space, expected", [(' colorspace="srgb_texture"', True), (' colorspace="none"', False),
                                             ("", False), (' colorspace="Raw"', False)])
def test_a_displacement_height_image_tagged_with_a_colour_space_is_reported(tmp_path, space, expected):
    """mb10: a float image read only by a displacement shader (no shader input of the surface) with an sRGB tag.
    MaterialX colour-manages color3/color4 images only: its GLSL applies no decode, other renderers do. An OCIO
    config's Raw role (MaterialX's TestSuite brass_wire_mesh.mtlx writes colorspace="Raw") asks for none."""
    png(tmp_path / "height.png", mode="L", colour=128)
    path = mtlx(tmp_path, _DISPLACED.format(space=space))
    assert not _glsl_transforms_colour(path)  # the anchor: MaterialX ignores the tag on a float image
    assert (("OPBR507", "warning", "NG/height", "file") in findings(path)) is expected


_LOOK = '''  <open_pbr_surface name="SR_glass" type="surfaceshader" version="1.1" />
  <surfacematerial name="M_glass" type="material">
    <input name="surfaceshader" type="surfaceshader" nodename="SR_glass" />
  </surfacematerial>
  <nodegraph name="NG_material">
    <open_pbr_surface name="S2" type="surfaceshader" />
    <surfacematerial name="M2" type="material">
      <input name="surfaceshader" type="surfaceshader" nodename="S2" />
    </surfacematerial>
    <output name="out" type="material" nodename="M2" />
  </nodegraph>
  <look name="L">
    <materialassign name="MA" material="{target}" geom="/Vase" />
  </look>
'''


@pytest.mark.parametrize("target, expected", [("SR_glass", True), ("M_glass", False), ("NG_material", False)])
def test_a_materialassign_naming_a_shader_is_a_dangling_reference(tmp_path, target, expected):
    """mb11: MaterialX's materialassign connects a material node (Geometry Extensions, MaterialAssign); naming the
    shader binds nothing: getReferencedMaterial() is not a material. A node graph whose output is a material binds
    (MaterialX's own TestSuite/stdlib/materials/material_node_discovery.mtlx assigns one)."""
    path = mtlx(tmp_path, _LOOK.format(target=target))
    document = mx.createDocument()
    mx.readFromXmlFile(document, str(path))
    named = document.getChild(target)
    is_material = named.getType() == "material" or any(o.getType() == "material" for o in named.getOutputs()) \
        if isinstance(named, mx.NodeGraph) else named.getType() == "material"
    assert (not is_material) is expected  # the anchor: what MaterialX's API says the name refers to
    assert any(code == "OPBR802" and severity == "error" for code, severity, *_ in findings(path)) is expected


@pytest.mark.skipif(os.name == "nt", reason="a drive path names a file on Windows")
def test_an_xinclude_of_a_windows_drive_path_is_an_error_where_it_names_no_file(tmp_path):
    """mb12: Maya writes its own library's absolute path; on any other system MaterialX's reader fails on it."""
    body = ('  <xi:include href="C:/Program Files/Autodesk/lib/adsklib.mtlx" />\n'
            '  <open_pbr_surface name="S" type="surfaceshader" version="1.1" />\n'
            '  <surfacematerial name="M" type="material">\n'
            '    <input name="surfaceshader" type="surfaceshader" nodename="S" />\n  </surfacematerial>\n')
    path = mtlx(tmp_path, body, attributes='xmlns:xi="http://www.w3.org/2001/XInclude" colorspace="lin_rec709"')
    with pytest.raises(Exception, match="Failed to open"):  # the anchor: MaterialX cannot load the document here
        mx.readFromXmlFile(mx.createDocument(), str(path))
    assert ("OPBR010", "error") in {(code, severity) for code, severity, *_ in findings(path)}


_ROOT = stage_example('def Xform "Root" (\n    references = @./look.mtlx@</MaterialX>\n)\n{\n}\n',
                      metadata='defaultPrim = "Root"\n    metersPerUnit = 1\n    upAxis = "Y"')


@pytest.mark.parametrize("member, expected", [("look.mtlx", True), ("LICENSE.txt", False)])
def test_a_usdz_packaging_a_materialx_document_is_an_error(tmp_path, member, expected):
    """ub04: usd-core's FileExtensionValidator reports a packaged .mtlx as an error (a package holds layers,
    images and audio only); the materials it holds do not load in a conforming viewer. A stray LICENSE.txt
    renders nothing either way: usd-core's warning, not an error here."""
    from pxr import Usd, UsdValidation

    root = _ROOT if member.endswith(".mtlx") else _ROOT.replace("references = @./look.mtlx@</MaterialX>", "kind = \"component\"")
    look = HEAD + '  <open_pbr_surface name="S" type="surfaceshader" version="1.1" />\n</materialx>\n'
    path = tmp_path / "asset.usdz"
    path.write_bytes(_package(("root.usda", root), (member, look if expected else "MIT")))
    package_errors = [f for f in findings(path) if f[0] == "OPBR1012" and f[1] == "error"]
    assert bool(package_errors) is expected
    stage = Usd.Stage.Open(str(path))  # (after: the validator refuses a layer this process already holds open)
    validator = UsdValidation.ValidationRegistry().GetOrLoadValidatorByName(
        "usdUtilsValidators:FileExtensionValidator")
    errors = validator.Validate(stage)
    assert any("UnsupportedFileExtensionInPackage" in str(e.GetName()) for e in errors)  # the anchor, both cases


def _preview_pair(openpbr: tuple[str, ...], opacity: float) -> str:
    lines = "".join(f"        {line}\n" for line in openpbr)
    return stage_example(
        'def Material "M"\n{\n    token outputs:mtlx:surface.connect = </M/S.outputs:surface>\n'
        "    token outputs:surface.connect = </M/P.outputs:surface>\n\n"
        f'    def Shader "S"\n    {{\n        uniform token info:id = "ND_open_pbr_surface_surfaceshader"\n{lines}'
        "        token outputs:surface\n    }\n\n"
        f'    def Shader "P"\n    {{\n        uniform token info:id = "UsdPreviewSurface"\n'
        f"        float inputs:opacity = {opacity}\n        float inputs:ior = 1.52\n        token outputs:surface\n    }}\n}}")


@pytest.mark.parametrize("openpbr, opacity, expected", [
    (("float inputs:transmission_weight = 1",), 0.2, False),  # ug05: a glass's preview is see-through (no refraction)
    (("float inputs:transmission_weight = 0.3",), 0.1, True),  # at most 0.3 of it is see-through: 0.1 is far off
    ((), 0.2, True),  # an opaque OpenPBR material: the preview at 0.2 shows another surface
])
def test_a_glass_fallback_preview_may_be_see_through(tmp_path, openpbr, opacity, expected):
    """ug05: UsdPreviewSurface has no refraction; a glass's fallback is written with opacity below 1 and an ior
    (specification: "ior ... to be used for translucent objects"), as this toolkit's own converter writes it."""
    path = tmp_path / "m.usda"
    path.write_text(_preview_pair(openpbr, opacity), encoding="utf-8")
    assert any(code == "OPBR1009" for code, *_ in findings(path)) is expected


@pytest.mark.parametrize("uri, expected", [("../shared.bin", True), ("mesh.bin", False)])
def test_a_gltf_buffer_outside_the_asset_is_reported_not_skipped_silently(tmp_path, uri, expected):
    """A buffer beside the asset's folder is never opened (the path guard): the meshes it holds go unchecked and the
    asset does not survive being copied, so it is said, as an image there is (OPBR704); a missing one is OPBR1209."""
    import json
    import struct

    (tmp_path / "asset").mkdir()
    data = struct.pack("<9f", 0, 0, 0, 1, 0, 0, 0, 1, 0)
    (tmp_path / "shared.bin").write_bytes(data)
    (tmp_path / "asset" / "mesh.bin").write_bytes(data)
    document = {"asset": {"version": "2.0"}, "buffers": [{"uri": uri, "byteLength": 36}],
                "bufferViews": [{"buffer": 0, "byteLength": 36}],
                "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
                               "min": [0, 0, 0], "max": [1, 1, 0]}],
                "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "material": 0}]}],
                "materials": [{"name": "M"}], "nodes": [{"mesh": 0}], "scenes": [{"nodes": [0]}], "scene": 0}
    path = tmp_path / "asset" / "a.gltf"
    path.write_text(json.dumps(document), encoding="utf-8")
    assert (("OPBR704", "warning", "/buffers/0/uri", None) in findings(path)) is expected
    assert not [f for f in findings(path) if f[1] == "error"]
