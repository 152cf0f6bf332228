"""Relative texture paths are re-expressed from the output's folder; an absolute path stays as
authored unless it lies inside the output's folder, decided by path component (io/paths.py)."""

from __future__ import annotations

import copy

from openpbr_tools.convert import _rebase_textures
from openpbr_tools.model import Input, Location, Material, Texture


def _material(file: str) -> Material:
    texture = Texture(file=file, colorspace="srgb_texture")
    material = Material("M", "open_pbr_surface", Location("src/m.mtlx"))
    material.inputs["base_color"] = Input("base_color", "color3", texture, Location("src/m.mtlx"))
    return material


def _rebased(file: str, source: str, output: str) -> str:
    material = _material(file)
    _rebase_textures([material], source, output)
    return material.inputs["base_color"].value.file


def test_a_relative_path_is_spelt_from_the_output_folder(tmp_path):
    assert _rebased("tex/a.png", str(tmp_path / "src" / "m.mtlx"), str(tmp_path / "out" / "m.mtlx")) == "../src/tex/a.png"


def test_an_absolute_path_in_a_folder_whose_name_extends_the_output_folder_stays_as_authored(tmp_path):
    authored = str(tmp_path / "outer" / "a.png")
    assert _rebased(authored, str(tmp_path / "src" / "m.mtlx"), str(tmp_path / "out" / "m.mtlx")) == authored


def test_an_absolute_path_inside_the_output_folder_becomes_relative(tmp_path):
    authored = str(tmp_path / "out" / "tex" / "a.png")
    assert _rebased(authored, str(tmp_path / "src" / "m.mtlx"), str(tmp_path / "out" / "m.mtlx")) == "tex/a.png"


def test_urls_and_drive_paths_are_written_as_authored(tmp_path):
    for file in ("http://example.com/a.png", "C:\\tex\\a.png", "\\\\server\\share\\a.png"):
        assert _rebased(file, str(tmp_path / "src" / "m.mtlx"), str(tmp_path / "out" / "m.mtlx")) == file


def test_the_source_material_is_not_modified(tmp_path):
    material = _material("tex/a.png")
    before = copy.deepcopy(material.inputs["base_color"].value)
    texture = material.inputs["base_color"].value
    _rebase_textures([material], str(tmp_path / "src" / "m.mtlx"), str(tmp_path / "out" / "m.mtlx"))
    assert texture == before
