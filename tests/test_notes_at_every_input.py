"""Every value that does not survive a translation as itself has a note at its own input (set T, session 22):
a value a formula folds into another input (Standard Surface's ``coat_affect_roughness`` into OpenPBR's
``specular_roughness``; a preview's constant ``diffuseColor`` baked with a textured ``metallic``; a constant
``sheen`` baked with a textured ``sheen_roughness``) was named only in the note at another input. What is lost is
a fact of the models: OpenPBR has no ``coat_affect_roughness`` (its node definition, read from MaterialX's library
here), and a baked image holds the formula's result, not the constant it folded in."""

from __future__ import annotations

import MaterialX as mx
from PIL import Image

from openpbr_tools.convert import convert_file
from openpbr_tools.translate.common import Settings
from redteam_support import mtlx, preview_stage, uv_texture


def _notes(conversion) -> dict[str, list[tuple[str, str]]]:
    """Input -> [(code, severity)] of the conversion's notes."""
    found: dict[str, list[tuple[str, str]]] = {}
    for d in conversion.diagnostics:
        found.setdefault(d.location.input, []).append((d.code, str(d.severity)))
    return found


def _inputs_of(nodedef: str = "ND_open_pbr_surface_surfaceshader") -> set[str]:
    """The inputs MaterialX's node definition declares."""
    document = mx.createDocument()
    mx.loadLibraries(mx.getDefaultDataLibraryFolders(), mx.getDefaultDataSearchPath(), document)
    return {i.getName() for i in document.getNodeDef(nodedef).getActiveInputs()}


def _material(tmp_path, category: str, inputs: str, before: str = ""):
    return mtlx(tmp_path, f'''
        {before}
        <{category} name="S" type="surfaceshader">
          {inputs}
        </{category}>
        <surfacematerial name="M" type="material">
          <input name="surfaceshader" type="surfaceshader" nodename="S" />
        </surfacematerial>
        ''')


def _standard_surface(tmp_path, inputs: str):
    return _material(tmp_path, "standard_surface", inputs, before='''<image name="rough" type="float">
          <input name="file" type="filename" value="rough.png" />
        </image>''')


def _ramp(path, start=0, step=4):
    image = Image.new("L", (8, 8))
    image.putdata([min(255, start + i * step) for i in range(64)])
    image.save(path)


def test_coat_affect_roughness_has_a_note_of_its_own(tmp_path):
    assert "coat_affect_roughness" not in _inputs_of()  # OpenPBR has no such input: it cannot survive as itself
    source = _standard_surface(tmp_path, '''<input name="coat" type="float" value="0.5" />
          <input name="coat_affect_roughness" type="float" value="0.7" />
          <input name="specular_roughness" type="float" value="0.3" />''')
    conversion = convert_file(str(source), str(tmp_path / "out.mtlx"), "open_pbr_surface", Settings())
    notes = _notes(conversion)
    assert ("OPBR1102", "info") in notes["coat_affect_roughness"]
    assert notes["specular_roughness"]  # the conversion's own note stays where it was


def test_an_input_at_its_default_needs_no_note(tmp_path):
    source = _standard_surface(tmp_path, '''<input name="coat" type="float" value="0.5" />
          <input name="coat_affect_roughness" type="float" value="0" />
          <input name="specular_roughness" type="float" value="0.3" />''')
    conversion = convert_file(str(source), str(tmp_path / "out.mtlx"), "open_pbr_surface", Settings())
    assert "coat_affect_roughness" not in _notes(conversion)


def test_a_colour_read_only_by_a_metal_term_gets_no_stray_note(tmp_path):
    # base_color feeds specular_weight's formula, but has its own counterpart (OpenPBR's base_color): no note there
    source = _standard_surface(tmp_path, '''<input name="base_color" type="color3" value="0.3, 0.05, 0.1" />
          <input name="coat" type="float" value="0.5" />''')
    conversion = convert_file(str(source), str(tmp_path / "out.mtlx"), "open_pbr_surface", Settings())
    assert "base_color" not in _notes(conversion)


def test_a_constant_sheen_baked_with_a_textured_roughness_is_noted_at_sheen(tmp_path):
    _ramp(tmp_path / "rough.png")
    source = _standard_surface(tmp_path, '''<input name="base_color" type="color3" value="0.3, 0.05, 0.1" />
          <input name="sheen" type="float" value="0.8" />
          <input name="sheen_roughness" type="float" nodename="rough" />''')
    conversion = convert_file(str(source), str(tmp_path / "out" / "out.mtlx"), "open_pbr_surface", Settings())
    notes = _notes(conversion)
    assert ("OPBR1103", "warning") in notes["sheen"]  # the fit's approximation, at the sheen it describes
    assert ("OPBR1102", "info") in notes["sheen_roughness"]  # the bake, at the texture baked


def test_a_preview_diffuse_colour_baked_with_a_textured_metallic_is_noted_at_diffuse_colour(tmp_path):
    _ramp(tmp_path / "metal.png", start=255, step=-3)
    source = preview_stage(tmp_path, "color3f inputs:diffuseColor = (0.7, 0.3, 0.1)",
                           "float inputs:metallic.connect = </M/T.outputs:r>", name="preview.usda",
                           extra=uv_texture("T", "metal.png", "r", "float"))
    out = tmp_path / "out" / "out.mtlx"
    conversion = convert_file(str(source), str(out), "open_pbr_surface", Settings())
    notes = _notes(conversion)
    assert "diffuseColor" in notes and "metallic" in notes
    # and the baked base colour is not the constant: diffuseColor does not survive as itself
    document = mx.createDocument()
    mx.readFromXmlFile(document, str(out))
    shader = next(n for n in document.getNodes() if n.getCategory() == "open_pbr_surface")
    assert shader.getInput("base_color").getValueString() == ""  # a connection to the baked image


# Set V (session 23), a black-box audit: each input changed in turn, outputs and notes compared.

def _openpbr(tmp_path, inputs: str):
    return _material(tmp_path, "open_pbr_surface", inputs)


def test_a_dropped_lobe_takes_a_note_at_each_of_its_inputs(tmp_path):
    """V1/V2: the preview has no fuzz and no film; fuzz_color and thin_film_thickness had no note of their own."""
    assert not {"fuzz_color", "fuzz_roughness", "thin_film_thickness"} & _inputs_of("ND_UsdPreviewSurface_surfaceshader")
    source = _openpbr(tmp_path, '''<input name="fuzz_weight" type="float" value="0.8" />
          <input name="fuzz_color" type="color3" value="0.9, 0.3, 0.2" />
          <input name="fuzz_roughness" type="float" value="0.8" />
          <input name="thin_film_weight" type="float" value="1" />
          <input name="thin_film_thickness" type="float" value="0.4" />''')
    notes = _notes(convert_file(str(source), str(tmp_path / "out.mtlx"), "UsdPreviewSurface", Settings()))
    for name in ("fuzz_weight", "fuzz_color", "fuzz_roughness", "thin_film_weight", "thin_film_thickness"):
        assert ("OPBR1104", "error") in notes[name], name


def test_an_input_of_a_switched_off_lobe_is_noted_not_an_error(tmp_path):
    """V10: Standard Surface's transmission_extra_roughness with transmission 0 renders nothing (OpenPBR has no such
    input): an info note that it is not written, not an error."""
    source = _standard_surface(tmp_path, '''<input name="transmission_extra_roughness" type="float" value="0.3" />
          <input name="coat_affect_color" type="float" value="0.5" />''')
    notes = _notes(convert_file(str(source), str(tmp_path / "out.mtlx"), "open_pbr_surface", Settings()))
    assert notes["transmission_extra_roughness"] == [("OPBR1102", "info")]
    assert notes["coat_affect_color"] == [("OPBR1102", "info")]
    on = _standard_surface(tmp_path, '''<input name="transmission" type="float" value="1" />
          <input name="transmission_extra_roughness" type="float" value="0.3" />''')
    notes = _notes(convert_file(str(on), str(tmp_path / "on.mtlx"), "open_pbr_surface", Settings()))
    assert ("OPBR1104", "error") in notes["transmission_extra_roughness"]


def test_a_length_of_a_switched_off_lobe_is_not_warned_about(tmp_path):
    """V11: "carry no unit; taken as metres" on a transmission_depth whose transmission is 0."""
    off = _openpbr(tmp_path, '<input name="transmission_depth" type="float" value="0.5" />')
    notes = _notes(convert_file(str(off), str(tmp_path / "off.mtlx"), "standard_surface", Settings()))
    assert "transmission_depth" not in notes
    on = _openpbr(tmp_path, '''<input name="transmission_weight" type="float" value="1" />
          <input name="transmission_depth" type="float" value="0.5" />''')
    notes = _notes(convert_file(str(on), str(tmp_path / "on.mtlx"), "standard_surface", Settings()))
    assert ("OPBR1103", "warning") in notes["transmission_depth"]


def test_a_film_on_a_metal_is_an_approximation(tmp_path):
    """V6: a Standard Surface film on a metal was reported as an exact unit change; the evaluator puts the OpenPBR
    result 9.3 mean CIEDE2000 off (0.6 without the film), MaterialX's GLSL 6.2 (1.4)."""
    metal = _standard_surface(tmp_path, '''<input name="base_color" type="color3" value="0.41, 0.879, 0.708" />
          <input name="metalness" type="float" value="1" />
          <input name="specular_roughness" type="float" value="0.174" />
          <input name="thin_film_thickness" type="float" value="430" />''')
    conversion = convert_file(str(metal), str(tmp_path / "metal.mtlx"), "open_pbr_surface", Settings())
    assert ("OPBR1103", "warning") in _notes(conversion)["thin_film_thickness"]
    # the candidates' note says the material stays visibly off, as a warning
    assert any(d.code == "OPBR1103" and "still visibly off" in d.message for d in conversion.diagnostics)
    plastic = _standard_surface(tmp_path, '''<input name="thin_film_thickness" type="float" value="430" />''')
    conversion = convert_file(str(plastic), str(tmp_path / "plastic.mtlx"), "open_pbr_surface", Settings())
    assert _notes(conversion)["thin_film_thickness"] == [("OPBR1102", "info")]  # nanometres to micrometres, exact


# A review of the session's diff (session 23).

def test_nothing_is_folded_into_a_target_that_is_not_written(tmp_path):
    """A glTF volume without transmission: transmission_color is not written (it has no effect), so attenuation
    colour and thickness were not 'folded into' it."""
    source = tmp_path / "volume.gltf"
    source.write_text('{"asset": {"version": "2.0"}, "extensionsUsed": ["KHR_materials_volume"], "materials": [{"name": '
                      '"Glass", "pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.2, 0.1, 1]}, "extensions": '
                      '{"KHR_materials_volume": {"thicknessFactor": 0.5, "attenuationColor": [0.5, 0.7, 0.9], '
                      '"attenuationDistance": 0.2}}}]}', encoding="utf-8")
    conversion = convert_file(str(source), str(tmp_path / "out.mtlx"), "open_pbr_surface", Settings())
    assert not [d for d in conversion.diagnostics if "folded into transmission_color" in d.message]


def test_a_folded_input_already_noted_under_its_own_name_gets_no_second_note(tmp_path):
    """glTF notes stand at the JSON property (thicknessFactor): a companion for 'thickness' must see them."""
    source = tmp_path / "leaf.gltf"
    source.write_text('{"asset": {"version": "2.0"}, "extensionsUsed": ["KHR_materials_volume", '
                      '"KHR_materials_diffuse_transmission"], "materials": [{"name": "Leaf", "extensions": '
                      '{"KHR_materials_diffuse_transmission": {"diffuseTransmissionFactor": 0.5}, "KHR_materials_volume": '
                      '{"thicknessFactor": 0.01, "attenuationDistance": 0.5}}}]}', encoding="utf-8")
    conversion = convert_file(str(source), str(tmp_path / "out.mtlx"), "open_pbr_surface", Settings())
    at_thickness = [d for d in conversion.diagnostics if d.location.input == "thicknessFactor"]
    assert len(at_thickness) == 1, [d.message for d in at_thickness]
