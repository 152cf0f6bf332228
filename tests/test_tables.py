"""The parameter tables in ``schemas/models/``: schema validity, agreement with MaterialX's node
definitions, and the OpenPBR version history.

Expectations come from outside the JSON files: the JSON schema, the nodedefs shipped in the installed
``materialx`` wheel, and the version history in DESIGN.md ("OpenPBR versions"), written out here as
literal values.
"""

from __future__ import annotations

import copy
import math

import jsonschema
import MaterialX as mx
import pytest

from openpbr_tools import tables
from openpbr_tools.resources import load_json

OPENPBR = "open_pbr_surface"
OPENPBR_VERSIONS = ("0.2", "0.3", "0.4", "0.5", "1.0", "1.1", "1.1.1")

# Tables that MaterialX 1.39.5 ships a nodedef for, with the nodedef that defines each.
CURRENT = {
    (OPENPBR, "1.1.1"): "ND_open_pbr_surface_surfaceshader",
    ("standard_surface", "1.0.1"): "ND_standard_surface_surfaceshader",
    ("standard_surface", "1.0.0"): "ND_standard_surface_surfaceshader_100",
    ("gltf_pbr", "2.0.1"): "ND_gltf_pbr_surfaceshader",
    ("UsdPreviewSurface", "2.6"): "ND_UsdPreviewSurface_surfaceshader",
}

EXPECTED_TABLES = {(OPENPBR, v) for v in OPENPBR_VERSIONS} | set(CURRENT)

# nodedef attribute -> table field
RANGE_ATTRIBUTES = (("uimin", "hard_min"), ("uimax", "hard_max"), ("uisoftmin", "soft_min"), ("uisoftmax", "soft_max"))


def all_tables():
    return [(m, v) for m in tables.MODELS for v in tables.versions(m)]


# ------------------------------------------------------------------------------------------------
# 1. schema validity


def test_every_expected_table_exists():
    assert set(all_tables()) == EXPECTED_TABLES


def test_every_table_validates_against_the_schema():
    assert tables.check_tables() == []


def _schema_errors(raw: dict) -> list[str]:
    schema = load_json("parameter_table.schema.json")
    validator = jsonschema.Draft202012Validator(schema)
    return [e.message for e in validator.iter_errors(raw)]


def _raw(model: str, version: str) -> dict:
    return copy.deepcopy(load_json(f"models/{model}/{version}.json"))


@pytest.mark.parametrize(
    "breakage",
    [
        "unknown role",
        "missing default",
        "unknown field",
        "bad type",
        "bad unit",
        "no sources",
        "bad version string",
        "range is a string",
    ],
)
def test_schema_rejects_a_broken_table(breakage):
    raw = _raw(OPENPBR, "1.1.1")
    assert _schema_errors(raw) == []
    param = raw["parameters"]["base_color"]
    if breakage == "unknown role":
        param["role"] = "colour"
    elif breakage == "missing default":
        del param["default"]
    elif breakage == "unknown field":
        param["minimum"] = 0
    elif breakage == "bad type":
        param["type"] = "colour3"
    elif breakage == "bad unit":
        raw["parameters"]["transmission_depth"]["unit"] = "metre"
    elif breakage == "no sources":
        raw["sources"] = []
    elif breakage == "bad version string":
        raw["version"] = "v1.1"
    elif breakage == "range is a string":
        param["hard_max"] = "1"
    assert _schema_errors(raw), breakage


def test_check_tables_reports_a_broken_file(monkeypatch):
    real = tables.load_json

    def broken(relative):
        raw = copy.deepcopy(real(relative))
        if relative == "models/gltf_pbr/2.0.1.json":
            raw["parameters"]["metallic"]["role"] = "metal"
            raw["version"] = "2.0.0"
        return raw

    monkeypatch.setattr(tables, "load_json", broken)
    errors = tables.check_tables()
    assert any("gltf_pbr/2.0.1.json#/parameters/metallic/role" in e for e in errors)
    assert any("do not match the file name" in e for e in errors)


# ------------------------------------------------------------------------------------------------
# 2. agreement with the MaterialX nodedefs


@pytest.fixture(scope="module")
def library():
    lib = mx.createDocument()
    mx.loadLibraries(mx.getDefaultDataLibraryFolders(), mx.getDefaultDataSearchPath(), lib)
    return lib


def _parse(type_name: str, text: str):
    """A MaterialX value string as the plain Python value the tables use."""
    if text is None or text == "":
        return None
    if type_name == "boolean":
        return text.strip() == "true"
    if type_name == "integer":
        return int(text)
    if type_name == "float":
        return float(text)
    if type_name in ("color3", "color4", "vector2", "vector3", "vector4"):
        return tuple(float(x) for x in text.split(","))
    return text


def _parse_bound(type_name: str, text: str):
    if not text:
        return None
    if type_name == "integer":
        return float(text)
    return _parse(type_name, text)


def _same(a, b) -> bool:
    """Equal values: floats within tolerance, vectors componentwise, a scalar broadcast over a vector."""
    if a is None or b is None:
        return a is None and b is None
    if isinstance(a, bool) or isinstance(b, bool):
        return a is b
    if isinstance(a, str) or isinstance(b, str):
        return a == b
    if isinstance(a, (tuple, list)) or isinstance(b, (tuple, list)):
        av = list(a) if isinstance(a, (tuple, list)) else None
        bv = list(b) if isinstance(b, (tuple, list)) else None
        if av is None:
            av = [a] * len(bv)
        if bv is None:
            bv = [b] * len(av)
        return len(av) == len(bv) and all(_same(x, y) for x, y in zip(av, bv))
    return math.isclose(float(a), float(b), rel_tol=1e-6, abs_tol=1e-7)


def _range_mismatches(param: tables.Parameter, nodedef_input) -> list[str]:
    """Bounds where the table differs from the nodedef's ui ranges (absent on one side counts)."""
    out = []
    for attribute, field in RANGE_ATTRIBUTES:
        theirs = _parse_bound(nodedef_input.getType(), nodedef_input.getAttribute(attribute))
        ours = getattr(param, field)
        if not _same(theirs, ours):
            out.append(f"{param.name}: {field}={ours!r} but nodedef {attribute}={theirs!r}")
    return out


@pytest.fixture(scope="module", params=sorted(CURRENT), ids=lambda key: f"{key[0]}-{key[1]}")
def current(request, library):
    model, version = request.param
    nodedef = library.getNodeDef(CURRENT[request.param])
    assert nodedef is not None, CURRENT[request.param]
    inputs = {i.getName(): i for i in nodedef.getActiveInputs()}
    return tables.table(model, version), nodedef, inputs


def test_table_names_its_nodedef_and_version(current):
    table, nodedef, _ = current
    assert table.nodedef == nodedef.getName()
    assert table.version == nodedef.getVersionString()
    assert table.node == nodedef.getNodeString()


def test_same_input_names_as_nodedef(current):
    table, _, inputs = current
    assert set(table.parameters) == set(inputs)


def test_same_types_as_nodedef(current):
    table, _, inputs = current
    wrong = {n: (p.type, inputs[n].getType()) for n, p in table.parameters.items() if p.type != inputs[n].getType()}
    assert wrong == {}


def test_same_defaults_as_nodedef(current):
    table, _, inputs = current
    wrong = {}
    for name, param in table.parameters.items():
        expected = None if inputs[name].hasDefaultGeomPropString() else _parse(param.type, inputs[name].getValueString())
        if not _same(param.default, expected):
            wrong[name] = (param.default, expected)
    assert wrong == {}


def test_same_defaultgeomprop_as_nodedef(current):
    table, _, inputs = current
    for name, param in table.parameters.items():
        expected = inputs[name].getDefaultGeomPropString() or None
        assert param.default_geomprop == expected, name
        if expected:
            assert param.default is None, name


def test_same_uniform_flags_as_nodedef(current):
    table, _, inputs = current
    wrong = {n: p.uniform for n, p in table.parameters.items() if p.uniform != (inputs[n].getAttribute("uniform") == "true")}
    assert wrong == {}


def test_same_enums_as_nodedef(current):
    table, _, inputs = current
    for name, param in table.parameters.items():
        values = inputs[name].getAttribute("enumvalues")
        if values:
            assert param.enum is not None, name
            assert [_parse(param.type, v) for v in values.split(",")] == list(param.enum), name


def test_groups_are_the_nodedef_folders(current):
    table, _, inputs = current
    for name, param in table.parameters.items():
        folder = inputs[name].getAttribute("uifolder")
        if folder:
            assert param.group == folder.lower(), name


def test_ranges_match_nodedef_or_explain_why_not(current):
    table, _, inputs = current
    unexplained = []
    for name, param in table.parameters.items():
        mismatches = _range_mismatches(param, inputs[name])
        if mismatches and not (param.range_note and param.range_note.strip()):
            unexplained.extend(mismatches)
    assert unexplained == []


def test_range_comparison_detects_a_difference(library):
    """The range check above must be able to fail: a table bound that differs, or is missing, is reported."""
    nodedef = library.getNodeDef("ND_open_pbr_surface_surfaceshader")
    base_weight = nodedef.getActiveInput("base_weight")
    good = tables.table(OPENPBR, "1.1.1")["base_weight"]
    assert _range_mismatches(good, base_weight) == []
    fields = {f: getattr(good, f) for f in good.__slots__}
    widened = tables.Parameter(**{**fields, "hard_max": 2.0})
    missing = tables.Parameter(**{**fields, "hard_min": None})
    assert _range_mismatches(widened, base_weight) == ["base_weight: hard_max=2.0 but nodedef uimax=1.0"]
    assert len(_range_mismatches(missing, base_weight)) == 1
    colour = nodedef.getActiveInput("base_color")
    as_scalar = tables.Parameter(**{**{f: getattr(tables.table(OPENPBR, "1.1.1")["base_color"], f) for f in good.__slots__},
                                    "hard_min": 0.0, "hard_max": 1.0})
    assert _range_mismatches(as_scalar, colour) == []


def test_standard_surface_1_0_1_changes_only_base_defaults():
    old, new = tables.table("standard_surface", "1.0.0"), tables.table("standard_surface", "1.0.1")
    assert set(old.parameters) == set(new.parameters)
    changed = {n for n in old.parameters if not _same(old[n].default, new[n].default)}
    assert changed == {"base", "base_color"}
    assert _same(old["base"].default, 0.8) and _same(new["base"].default, 1.0)
    assert _same(old["base_color"].default, (1, 1, 1)) and _same(new["base_color"].default, (0.8, 0.8, 0.8))


# ------------------------------------------------------------------------------------------------
# 3. OpenPBR version history (DESIGN.md, "OpenPBR versions")


def opbr(version: str) -> tables.ParameterTable:
    return tables.table(OPENPBR, version)


def test_openpbr_versions_are_listed_oldest_first():
    assert tables.versions(OPENPBR) == OPENPBR_VERSIONS
    assert tables.latest(OPENPBR) == "1.1.1"


def test_legacy_openpbr_tables_name_no_shipped_nodedef():
    for version in OPENPBR_VERSIONS[:-1]:
        assert opbr(version).nodedef is None, version
    assert opbr("1.1.1").nodedef == "ND_open_pbr_surface_surfaceshader"


def test_base_roughness_in_0_2_and_0_3_renamed_base_diffuse_roughness_in_0_4():
    for version in ("0.2", "0.3"):
        assert "base_roughness" in opbr(version) and "base_diffuse_roughness" not in opbr(version)
    for version in ("0.4", "0.5", "1.0", "1.1", "1.1.1"):
        assert "base_roughness" not in opbr(version) and "base_diffuse_roughness" in opbr(version)


def test_ior_levels_default_half_in_0_2_and_removed_in_0_4():
    for name in ("specular_ior_level", "coat_ior_level"):
        assert opbr("0.2")[name].default == pytest.approx(0.5)
        assert opbr("0.3")[name].default == pytest.approx(0.5)
        for version in ("0.4", "0.5", "1.0", "1.1", "1.1.1"):
            assert name not in opbr(version), (name, version)


def test_transmission_dispersion_split_into_scale_and_abbe_number_in_0_3():
    assert "transmission_dispersion" in opbr("0.2")
    assert "transmission_dispersion_scale" not in opbr("0.2")
    assert "transmission_dispersion_abbe_number" not in opbr("0.2")
    for version in ("0.3", "0.4", "0.5", "1.0", "1.1", "1.1.1"):
        assert "transmission_dispersion" not in opbr(version)
        assert "transmission_dispersion_scale" in opbr(version)
        assert "transmission_dispersion_abbe_number" in opbr(version)


def test_specular_weight_bounded_by_one_before_0_4_and_soft_max_one_from_0_4():
    for version in ("0.2", "0.3"):
        assert opbr(version)["specular_weight"].hard_max == pytest.approx(1.0)
    for version in ("0.4", "0.5", "1.0", "1.1", "1.1.1"):
        weight = opbr(version)["specular_weight"]
        assert weight.hard_min == pytest.approx(0.0)
        assert weight.hard_max is None
        assert weight.soft_max == pytest.approx(1.0)


def test_anisotropy_renamed_roughness_anisotropy_and_rotation_removed_in_0_5():
    for prefix in ("specular", "coat"):
        for version in ("0.2", "0.3", "0.4"):
            assert f"{prefix}_anisotropy" in opbr(version)
            assert f"{prefix}_rotation" in opbr(version)
            assert f"{prefix}_roughness_anisotropy" not in opbr(version)
        for version in ("0.5", "1.0", "1.1", "1.1.1"):
            assert f"{prefix}_anisotropy" not in opbr(version)
            assert f"{prefix}_rotation" not in opbr(version)
            assert f"{prefix}_roughness_anisotropy" in opbr(version)


def test_subsurface_anisotropy_renamed_subsurface_scatter_anisotropy_in_0_5():
    assert "subsurface_anisotropy" in opbr("0.4") and "subsurface_scatter_anisotropy" not in opbr("0.4")
    assert "subsurface_anisotropy" not in opbr("0.5") and "subsurface_scatter_anisotropy" in opbr("0.5")


def test_coat_darkening_absent_in_0_4_and_default_one_from_0_5():
    assert "coat_darkening" not in opbr("0.4")
    for version in ("0.5", "1.0", "1.1", "1.1.1"):
        assert opbr(version)["coat_darkening"].default == pytest.approx(1.0)


def test_thin_film_weight_added_in_0_5_with_default_zero():
    assert "thin_film_weight" not in opbr("0.4")
    assert opbr("0.5")["thin_film_weight"].default == pytest.approx(0.0)


def test_geometry_coat_tangent_added_in_0_5():
    assert "geometry_coat_tangent" not in opbr("0.4")
    tangent = opbr("0.5")["geometry_coat_tangent"]
    assert tangent.default is None and tangent.default_geomprop == "Tworld" and tangent.role == "tangent"


def test_thin_film_thickness_in_nanometres_default_zero_until_0_4():
    for version in ("0.2", "0.3", "0.4"):
        thickness = opbr(version)["thin_film_thickness"]
        assert thickness.unit == "nanometer", version
        assert thickness.default == pytest.approx(0.0), version


def test_thin_film_thickness_in_micrometres_default_half_from_0_5():
    for version in ("0.5", "1.0", "1.1", "1.1.1"):
        thickness = opbr(version)["thin_film_thickness"]
        assert thickness.unit == "micrometer", version
        assert thickness.default == pytest.approx(0.5), version


def test_geometry_opacity_color3_in_0_2_and_float_from_0_5():
    assert opbr("0.2")["geometry_opacity"].type == "color3"
    assert _same(opbr("0.2")["geometry_opacity"].default, (1, 1, 1))
    for version in ("0.5", "1.0", "1.1", "1.1.1"):
        assert opbr(version)["geometry_opacity"].type == "float"
        assert opbr(version)["geometry_opacity"].default == pytest.approx(1.0)


def test_abbe_number_default_twenty_from_1_0():
    for version in ("1.0", "1.1", "1.1.1"):
        assert opbr(version)["transmission_dispersion_abbe_number"].default == pytest.approx(20.0)


def test_thin_film_ior_default_1_5_in_1_0_and_1_4_from_1_1():
    for version in ("0.2", "0.5", "1.0"):
        assert opbr(version)["thin_film_ior"].default == pytest.approx(1.5), version
    for version in ("1.1", "1.1.1"):
        assert opbr(version)["thin_film_ior"].default == pytest.approx(1.4), version


def test_geometry_thin_walled_uniform_only_in_1_1_1():
    assert opbr("1.1.1")["geometry_thin_walled"].uniform is True
    for version in OPENPBR_VERSIONS[:-1]:
        assert opbr(version)["geometry_thin_walled"].uniform is False, version


def test_emission_color_may_exceed_one_only_in_1_1_1():
    """The v1.1.1 specification's emission table: [0, inf)^3 and an empty Norm column (CHANGELOG #260)."""
    latest = opbr("1.1.1")["emission_color"]
    assert latest.hard_max is None
    assert latest.soft_max is None
    assert _same(latest.hard_min, 0.0)
    assert latest.range_note
    assert _same(opbr("1.1")["emission_color"].hard_max, 1.0)


def test_openpbr_length_and_luminance_units_in_every_version():
    for version in OPENPBR_VERSIONS:
        table = opbr(version)
        assert table["transmission_depth"].unit == "scene_length", version
        assert table["subsurface_radius"].unit == "scene_length", version
        assert table["emission_luminance"].unit == "nit", version


# ------------------------------------------------------------------------------------------------
# 4. roles, units and internal consistency


def test_openpbr_color_inputs_are_colour_managed():
    for version in OPENPBR_VERSIONS:
        table = opbr(version)
        for name, param in table.parameters.items():
            if param.type == "color3" and name.endswith("_color"):
                assert param.role == "color", (version, name)
        assert table["transmission_scatter"].role == "color", version


def test_openpbr_subsurface_radius_scale_is_data_not_colour():
    for version in OPENPBR_VERSIONS:
        assert opbr(version)["subsurface_radius_scale"].role == "data", version


def test_openpbr_normals_and_tangents_roles():
    for version in OPENPBR_VERSIONS:
        table = opbr(version)
        for name in ("geometry_normal", "geometry_coat_normal"):
            assert table[name].role == "normal", (version, name)
            assert table[name].default_geomprop == "Nworld", (version, name)
        assert table["geometry_tangent"].role == "tangent", version


def test_other_models_roles_and_units():
    std = tables.table("standard_surface", "1.0.1")
    for name in ("normal", "coat_normal"):
        assert std[name].role == "normal"
    assert std["tangent"].role == "tangent"
    assert std["subsurface_radius"].role == "data" and std["subsurface_radius"].unit == "scene_length"
    assert std["transmission_depth"].unit == "scene_length"
    assert std["thin_film_thickness"].unit == "nanometer"
    for name in ("base_color", "specular_color", "coat_color", "sheen_color", "emission_color", "transmission_color", "subsurface_color"):
        assert std[name].role == "color", name
    gltf = tables.table("gltf_pbr", "2.0.1")
    assert gltf["normal"].role == "normal" and gltf["clearcoat_normal"].role == "normal"
    assert gltf["iridescence_thickness"].unit == "nanometer"
    assert gltf["thickness"].unit == "scene_length" and gltf["attenuation_distance"].unit == "scene_length"
    assert gltf["alpha_mode"].role == "enum" and gltf["alpha_mode"].enum == (0, 1, 2)
    for name in ("base_color", "emissive", "sheen_color", "specular_color", "attenuation_color"):
        assert gltf[name].role == "color", name
    usd = tables.table("UsdPreviewSurface", "2.6")
    assert usd["useSpecularWorkflow"].role == "enum" and usd["useSpecularWorkflow"].enum == (0, 1)
    assert usd["normal"].role == "normal"
    for name in ("diffuseColor", "emissiveColor", "specularColor"):
        assert usd[name].role == "color", name


def test_booleans_have_boolean_role_and_vectors_are_not_colour():
    for model, version in all_tables():
        for name, param in tables.table(model, version).parameters.items():
            if param.type == "boolean":
                assert param.role == "boolean", (model, version, name)
            if param.type == "vector3":
                assert param.role in ("normal", "tangent", "data"), (model, version, name)
            if param.role == "color":
                assert param.type in ("color3", "color4"), (model, version, name)


def _components(value):
    return list(value) if isinstance(value, tuple) else [value]


@pytest.mark.parametrize("key", sorted(EXPECTED_TABLES), ids=lambda key: f"{key[0]}-{key[1]}")
def test_defaults_and_soft_ranges_lie_within_hard_ranges(key):
    table = tables.table(*key)
    for name, param in table.parameters.items():
        lo, hi = param.hard_min, param.hard_max
        for label, value in (("default", param.default), ("soft_min", param.soft_min), ("soft_max", param.soft_max)):
            if value is None or isinstance(value, (bool, str)):
                continue
            values = _components(value)
            los = _components(lo) * (len(values) if not isinstance(lo, tuple) else 1) if lo is not None else None
            his = _components(hi) * (len(values) if not isinstance(hi, tuple) else 1) if hi is not None else None
            for i, v in enumerate(values):
                if los is not None:
                    assert v >= los[i] - 1e-9, (name, label, value, lo)
                if his is not None:
                    assert v <= his[i] + 1e-9, (name, label, value, hi)
        if param.soft_min is not None and param.soft_max is not None:
            assert all(a <= b for a, b in zip(_components(param.soft_min), _components(param.soft_max))), name


@pytest.mark.parametrize("key", sorted(EXPECTED_TABLES), ids=lambda key: f"{key[0]}-{key[1]}")
def test_every_parameter_is_documented(key):
    table = tables.table(*key)
    assert table.sources
    for name, param in table.parameters.items():
        assert param.doc and param.doc.strip(), name
        if param.range_note is not None:
            assert param.range_note.strip(), name
