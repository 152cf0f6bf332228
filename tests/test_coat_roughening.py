"""Standard Surface <-> OpenPBR under a coat. OpenPBR's coat roughens the base it covers (OpenPBR 1.1,
"Coat": r_b = mix(r, min(1, (r^4 + 2 r_c^4)^(1/4)), coat)); Standard Surface's base under its coat is
mix(r, 1, coat_affect_roughness coat coat_roughness) (MaterialX's standard_surface graph). Expected values
come from those two formulas and from MaterialX's GLSL renderer."""

from __future__ import annotations

import shutil
from pathlib import Path

import pytest

from glsupport import comparison_mask, materialx_renderer, mean_delta_e, single_material
from openpbr_tools.convert import convert_file
from openpbr_tools.evaluate.preview import Rig
from openpbr_tools.io import read_asset
from openpbr_tools.model import Texture
from openpbr_tools.translate.common import Settings

RESOURCES = Path(__file__).parent / "data" / "published" / "materialx" / "resources"


def _openpbr_roughened(r, c, rc):
    return r + c * (min(1.0, (r ** 4 + 2 * rc ** 4) ** 0.25) - r)


def _document(path: Path, **inputs) -> Path:
    body = "\n".join(f'    <input name="{k}" type="{"color3" if isinstance(v, tuple) else "float"}" '
                     f'value="{", ".join(map(str, v)) if isinstance(v, tuple) else v}" />' for k, v in inputs.items())
    path.write_text(f'<?xml version="1.0"?>\n<materialx version="1.39" colorspace="lin_rec709">\n'
                    f'  <standard_surface name="S" type="surfaceshader">\n{body}\n  </standard_surface>\n'
                    f'  <surfacematerial name="M" type="material">\n'
                    f'    <input name="surfaceshader" type="surfaceshader" nodename="S" />\n'
                    f'  </surfacematerial>\n</materialx>\n')
    return path


@pytest.mark.parametrize("r, c, rc", [(0.5, 1.0, 0.3), (0.3, 0.6, 0.25), (0.7, 1.0, 0.5)])
def test_the_openpbr_base_roughens_into_standard_surfaces(tmp_path, r, c, rc):
    source = _document(tmp_path / "s.mtlx", specular_roughness=r, coat=c, coat_roughness=rc)
    convert_file(str(source), str(tmp_path / "o.mtlx"), "open_pbr_surface", Settings(candidates=False))
    material, = read_asset(str(tmp_path / "o.mtlx")).materials
    base = material.inputs["specular_roughness"].value.value
    assert base < r
    assert _openpbr_roughened(base, c, rc) == pytest.approx(r, abs=1e-6)


def test_a_base_smoother_than_openpbrs_coat_allows_is_its_smoothest_and_reported(tmp_path):
    source = _document(tmp_path / "s.mtlx", specular_roughness=0.2, coat=1.0, coat_roughness=0.4)
    result = convert_file(str(source), str(tmp_path / "o.mtlx"), "open_pbr_surface", Settings(candidates=False))
    material, = read_asset(str(tmp_path / "o.mtlx")).materials
    assert "specular_roughness" not in material.inputs or material.inputs["specular_roughness"].value.value == 0.0
    assert any(d.code == "OPBR1103" and "smoother than OpenPBR's coat allows" in d.message for d in result.diagnostics)


def test_a_coated_standard_surface_metal_renders_in_materialx_closer_than_a_copied_roughness(tmp_path):
    """MaterialX's GLSL: the converted OpenPBR against the Standard Surface source; a roughness copied as it
    was (OpenPBR's coat roughening it again) is rendered beside it as the figure to beat."""
    rig = Rig(size=64)
    renderer, mask = materialx_renderer(rig), comparison_mask(rig)
    values = dict(base=1.0, base_color=(0.9, 0.6, 0.3), metalness=1.0, specular_roughness=0.5, coat=1.0,
                  coat_roughness=0.35)
    source = _document(tmp_path / "s.mtlx", **values)
    convert_file(str(source), str(tmp_path / "o.mtlx"), "open_pbr_surface", Settings(candidates=False))
    reference = renderer.render("standard_surface", values)
    converted = renderer.render_document(single_material(str(tmp_path / "o.mtlx"), "M", str(tmp_path / "one.mtlx")))
    material, = read_asset(str(tmp_path / "o.mtlx")).materials
    copied = {name: entry.value.value for name, entry in material.inputs.items()}
    copied["specular_roughness"] = values["specular_roughness"]
    before = renderer.render("open_pbr_surface", copied)
    now, then = (mean_delta_e(image, reference, mask, rig.white()) for image in (converted, before))
    assert now < then - 0.5 and now < 2.0, (now, then)  # measured 1.58 against 2.37


def test_a_roughness_texture_that_cannot_be_baked_is_kept_as_it_is(tmp_path):
    """MaterialX's tiled brass: its roughness textures are in resources/Images, outside the example's
    folder. Not allowed there, the formula cannot be baked, and the texture is kept (before Mapping.keep, the
    roughness was lost to the default); allowed, it is evaluated per texel: the base is as rough as the coat
    (one texture for both), everywhere smoother than OpenPBR's coat allows, so the smoothest base, 0."""
    shutil.copytree(RESOURCES, tmp_path / "resources")
    source = tmp_path / "resources" / "Materials" / "Examples" / "StandardSurface" / "standard_surface_brass_tiled.mtlx"
    result = convert_file(str(source), str(tmp_path / "kept.mtlx"), "open_pbr_surface", Settings())
    material, = read_asset(str(tmp_path / "kept.mtlx")).materials
    kept = material.inputs["specular_roughness"].value
    assert isinstance(kept, Texture) and kept.file.endswith("brass_roughness.jpg")
    assert any("kept as it is" in d.message and d.location.input == "specular_roughness" for d in result.diagnostics)
    convert_file(str(source), str(tmp_path / "baked.mtlx"), "open_pbr_surface", Settings(),
                 allow_outside=(str(tmp_path / "resources"),))
    material, = read_asset(str(tmp_path / "baked.mtlx")).materials
    assert material.inputs["specular_roughness"].value.value == 0.0
    assert isinstance(material.inputs["coat_roughness"].value, Texture)
