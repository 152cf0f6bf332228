"""The shipped legacy OpenPBR node definitions: generated from the tables, loadable by MaterialX."""

from __future__ import annotations

from openpbr_tools import legacy_defs, tables
from openpbr_tools.resources import data_dir


def test_shipped_library_is_what_the_tables_generate():
    shipped = (data_dir("libraries") / legacy_defs.LIBRARY_FILE).read_text(encoding="utf-8")
    assert shipped == legacy_defs.generate(), "regenerate libraries/ with openpbr_tools.legacy_defs.generate()"


def test_materialx_loads_every_legacy_definition_beside_the_current_one():
    import MaterialX as mx

    library = mx.createDocument()
    mx.loadLibraries(mx.getDefaultDataLibraryFolders(), mx.getDefaultDataSearchPath(), library)
    mx.loadLibrary(str(data_dir("libraries") / legacy_defs.LIBRARY_FILE), library)
    versions = {nd.getVersionString() for nd in library.getMatchingNodeDefs("open_pbr_surface")}
    assert versions == set(tables.versions("open_pbr_surface"))
    valid, message = library.validate()
    assert valid, message


def test_legacy_definition_interfaces_match_their_tables():
    import MaterialX as mx

    document = mx.createDocument()
    mx.readFromXmlString(document, legacy_defs.generate())
    nodedef = document.getNodeDef("ND_open_pbr_surface_surfaceshader_02")
    assert nodedef.getInput("specular_ior_level").getValue() == 0.5  # DESIGN.md version table: 0.2 default
    assert nodedef.getInput("thin_film_thickness").getValue() == 0.0
    assert nodedef.getInput("geometry_opacity").getType() == "color3"


def test_versioned_nodedef_name_settles_the_version(write_mtlx):
    from openpbr_tools.io import read_asset

    path = write_mtlx('<open_pbr_surface name="S" type="surfaceshader" nodedef="ND_open_pbr_surface_surfaceshader_05" />')
    (material,) = read_asset(path).materials
    assert material.version == "0.5" and "nodedef" in material.version_basis
