"""The draft glTF extensions that align glTF with OpenPBR (KHR_materials_coat, _fuzz,
_diffuse_roughness, KHR_materials_clearcoat_ior, EXT_materials_specular_openpbr,
EXT_materials_clearcoat_darkening, EXT_materials_anisotropy_openpbr): read exactly, written with
``--gltf-drafts`` beside the ratified fallbacks, and round trips that return every value they carry.

Expected values come from the drafts' texts (KhronosGroup/glTF pull requests #2534, #2538, #2481,
#2488, #2518, #2521; see openpbr_tools/io/gltf/drafts.py): a property maps to its OpenPBR parameter
one to one, except the coat's anisotropy, which uses KHR_materials_anisotropy's convention
(alpha_t = mix(r^2, 1, s^2), alpha_b = r^2), computed here by hand.
"""

from __future__ import annotations

import collections
import json
import math
import random

import numpy as np
import pytest
from click.testing import CliRunner

from cli.group import cli
from generated_materials import COLORSPACES
from generated_materials import document as openpbr_document
import gltf_round_trip
from gltf_support import describe_issues, validate_with_khronos
from openpbr_tools import colorspaces, tables
from openpbr_tools.convert import convert_file
from openpbr_tools.io import read_asset
from openpbr_tools.model import Constant
from openpbr_tools.translate.common import Settings

MATERIAL = {
    "name": "red_varnish",
    "pbrMetallicRoughness": {"baseColorFactor": [0.5, 0.4, 0.3, 1.0], "roughnessFactor": 0.4, "metallicFactor": 0.0},
    "extensions": {
        "KHR_materials_coat": {"coatFactor": 1.0, "coatRoughnessFactor": 0.1, "coatIor": 1.4,
                               "coatColorFactor": [0.9, 0.3, 0.3], "coatDarkeningFactor": 0.8,
                               "coatAnisotropyStrength": 0.2},
        "KHR_materials_clearcoat": {"clearcoatFactor": 0.5, "clearcoatRoughnessFactor": 0.7},
        "KHR_materials_fuzz": {"fuzzFactor": 0.7, "fuzzColorFactor": [0.1, 0.2, 0.3], "fuzzRoughnessFactor": 0.8},
        "KHR_materials_sheen": {"sheenColorFactor": [1.0, 1.0, 1.0]},
        "KHR_materials_diffuse_roughness": {"diffuseRoughnessFactor": 0.6},
        "KHR_materials_specular": {"specularFactor": 0.7, "specularColorFactor": [1.0, 0.9, 0.8],
                                   "extensions": {"EXT_materials_specular_openpbr": {}}},
    },
}
#: OpenPBR parameter -> the glTF properties that carry it (the drafts' tables): a note on the way
#: back is located at the glTF property.
DRAFT_PARAMETERS = {
    "coat_weight": ("coatFactor",), "coat_color": ("coatColorFactor",), "coat_ior": ("coatIor",),
    "coat_darkening": ("coatDarkeningFactor",), "coat_roughness": ("coatRoughnessFactor", "coatAnisotropyStrength"),
    "coat_roughness_anisotropy": ("coatRoughnessFactor", "coatAnisotropyStrength"), "fuzz_weight": ("fuzzFactor",),
    "fuzz_color": ("fuzzColorFactor",), "fuzz_roughness": ("fuzzRoughnessFactor",),
    "base_diffuse_roughness": ("diffuseRoughnessFactor",), "specular_weight": ("specularFactor", "specular", "specularColorFactor"),
    "specular_color": ("specularColorFactor",),
}


def _gltf(path, materials, used=None):
    names = set()
    for material in materials:
        for name, value in material.get("extensions", {}).items():
            names.add(name)
            names.update(value.get("extensions", {}))
    path.write_text(json.dumps({"asset": {"version": "2.0"}, "extensionsUsed": sorted(used or names),
                                "materials": materials}))
    return path


def _inputs(path):
    return {m.material_name: {n: (e.value.value if isinstance(e.value, Constant) else e.value) for n, e in m.inputs.items()}
            for m in read_asset(str(path)).materials}


def test_each_draft_property_is_read_into_its_openpbr_parameter(tmp_path):
    result = convert_file(str(_gltf(tmp_path / "in.gltf", [MATERIAL])), str(tmp_path / "out.mtlx"))
    values = _inputs(tmp_path / "out.mtlx")["red_varnish"]
    # coat anisotropy by hand: alpha_b = 0.1^2, alpha_t = 0.01 + (1 - 0.01) * 0.2^2
    alpha_b, alpha_t = 0.01, 0.01 + 0.99 * 0.04
    anisotropy = 1.0 - alpha_b / alpha_t
    roughness = math.sqrt(alpha_t * math.sqrt((1.0 + (1.0 - anisotropy) ** 2) / 2.0))
    assert values["coat_weight"] == 1.0  # the draft's 1.0, not the clearcoat fallback's 0.5
    assert values["coat_ior"] == 1.4 and values["coat_darkening"] == 0.8
    assert values["coat_color"] == pytest.approx((0.9, 0.3, 0.3))
    assert values["coat_roughness"] == pytest.approx(roughness, abs=1e-12)
    assert values["coat_roughness_anisotropy"] == pytest.approx(anisotropy, abs=1e-12)
    assert values["fuzz_weight"] == 0.7 and values["fuzz_roughness"] == 0.8  # not the sheen fit
    assert values["fuzz_color"] == pytest.approx((0.1, 0.2, 0.3))
    assert values["base_diffuse_roughness"] == 0.6
    assert values["specular_weight"] == 0.7 and values["specular_color"] == pytest.approx((1.0, 0.9, 0.8))
    assert values["base_color"] == pytest.approx((0.5, 0.4, 0.3))
    read = [d for d in result.diagnostics if d.code == "OPBR1102" and "(draft) read exactly" in d.message]
    assert len(read) == 4  # one note per draft: coat, fuzz, diffuse roughness, specular


def test_only_a_tinted_metal_gets_ext_materials_specular_openpbr(tmp_path):
    tinted = MATERIAL | {"name": "tinted", "pbrMetallicRoughness": {"metallicFactor": 0.5}}
    convert_file(str(_gltf(tmp_path / "in.gltf", [tinted])), str(tmp_path / "mid.mtlx"))
    convert_file(str(tmp_path / "mid.mtlx"), str(tmp_path / "out.gltf"), settings=Settings(gltf_drafts=True))
    written = json.loads((tmp_path / "out.gltf").read_text())["materials"][0]
    assert written["extensions"]["KHR_materials_specular"]["extensions"] == {"EXT_materials_specular_openpbr": {}}
    assert written["extensions"]["KHR_materials_specular"]["specularFactor"] == 0.7  # OpenPBR's, raw
    assert written["pbrMetallicRoughness"].get("baseColorFactor", [1.0] * 4)[:3] == [1.0, 1.0, 1.0]  # the F0, not a fit


def test_a_metal_under_ext_materials_specular_openpbr_keeps_its_f0_and_edge_tint(tmp_path):
    gold = {"name": "gold", "pbrMetallicRoughness": {"baseColorFactor": [1.0, 0.78, 0.34, 1.0], "metallicFactor": 1.0},
            "extensions": {"KHR_materials_specular": {"specularColorFactor": [0.9, 0.7, 0.5],
                                                      "extensions": {"EXT_materials_specular_openpbr": {}}}}}
    plain = json.loads(json.dumps(gold))
    del plain["extensions"]["KHR_materials_specular"]["extensions"]
    plain["name"] = "gold_ratified"
    convert_file(str(_gltf(tmp_path / "in.gltf", [gold, plain])), str(tmp_path / "out.mtlx"))
    values = _inputs(tmp_path / "out.mtlx")
    assert values["gold"]["base_color"] == pytest.approx((1.0, 0.78, 0.34))  # F0 as is (EXT: OpenPBR's metal)
    assert values["gold"]["specular_color"] == pytest.approx((0.9, 0.7, 0.5))
    # without the EXT the specular colour has no effect on glTF's metal (Schlick's, F0 = base colour): read from
    # another tool's file, OpenPBR's edge tint is left white and the base colour is the F0 as is, which renders
    # as glTF does
    assert values["gold_ratified"]["base_color"] == pytest.approx((1.0, 0.78, 0.34))
    assert values["gold_ratified"].get("specular_color", (1.0, 1.0, 1.0)) == pytest.approx((1.0, 1.0, 1.0))
    # from this toolkit's own file the colour is the F82 tint it carries for the round trip: glTF's Schlick
    # metal is inverted for that tint, a different base colour
    ours = json.loads((tmp_path / "in.gltf").read_text())
    ours["asset"]["generator"] = "openpbr-tools 0.1.0"
    (tmp_path / "ours.gltf").write_text(json.dumps(ours))
    convert_file(str(tmp_path / "ours.gltf"), str(tmp_path / "ours.mtlx"))
    assert _inputs(tmp_path / "ours.mtlx")["gold_ratified"]["base_color"] != pytest.approx((1.0, 0.78, 0.34), abs=1e-3)


def test_clearcoat_darkening_clearcoat_ior_and_openpbr_anisotropy_sub_extensions(tmp_path):
    material = {"name": "M", "pbrMetallicRoughness": {"roughnessFactor": 0.3, "metallicFactor": 0.0},
                "extensions": {
                    "KHR_materials_clearcoat": {"clearcoatFactor": 1.0, "extensions": {
                        "EXT_materials_clearcoat_darkening": {"clearcoatDarkeningFactor": 0.25},
                        "KHR_materials_clearcoat_ior": {"clearcoatIor": 1.8}}},
                    "KHR_materials_anisotropy": {"anisotropyStrength": 0.6, "extensions": {
                        "EXT_materials_anisotropy_openpbr": {"openPbrAnisotropyEnabled": True}}}}}
    convert_file(str(_gltf(tmp_path / "in.gltf", [material])), str(tmp_path / "out.mtlx"))
    values = _inputs(tmp_path / "out.mtlx")["M"]
    assert values["coat_darkening"] == 0.25 and values["coat_ior"] == 1.8
    assert values["specular_roughness_anisotropy"] == 0.6  # OpenPBR's, not converted from glTF's convention


def test_unknown_nested_and_vendor_extensions_are_reported_by_convert_and_validate(tmp_path):
    material = {"name": "M", "extensions": {
        "KHR_materials_clearcoat": {"clearcoatFactor": 1.0, "extensions": {"VENDOR_clearcoat_magic": {"x": 1}}},
        "VENDOR_materials_sparkle": {"amount": 0.5}}}
    path = _gltf(tmp_path / "in.gltf", [material])
    result = convert_file(str(path), str(tmp_path / "out.mtlx"))
    lost = [d for d in result.diagnostics if d.code == "OPBR1104" and "VENDOR_clearcoat_magic" in d.message]
    kept = [d for d in result.diagnostics if "VENDOR_materials_sparkle" in d.message]
    assert lost and lost[0].location.material == "M" and kept
    report = CliRunner().invoke(cli, ["validate", str(path), "--format", "json"])
    found = {(d["code"], d["location"]["path"]) for d in json.loads(report.output)["diagnostics"]}
    assert ("OPBR1212", "/materials/0/extensions/KHR_materials_clearcoat/extensions/VENDOR_clearcoat_magic") in found
    assert ("OPBR1212", "/materials/0/extensions/VENDOR_materials_sparkle") in found
    info = CliRunner().invoke(cli, ["info", str(path)])
    assert "KHR_materials_clearcoat/VENDOR_clearcoat_magic (not converted)" in info.output


def test_default_output_is_ratified_only_and_drafts_come_on_request(tmp_path):
    source = _gltf(tmp_path / "in.gltf", [MATERIAL])
    convert_file(str(source), str(tmp_path / "mid.mtlx"))
    convert_file(str(tmp_path / "mid.mtlx"), str(tmp_path / "plain.gltf"))
    convert_file(str(tmp_path / "mid.mtlx"), str(tmp_path / "drafts.gltf"), settings=Settings(gltf_drafts=True))
    plain = json.loads((tmp_path / "plain.gltf").read_text())
    drafts = json.loads((tmp_path / "drafts.gltf").read_text())
    assert not [n for n in plain["extensionsUsed"] if "coat" in n and n != "KHR_materials_clearcoat"]
    assert "KHR_materials_fuzz" not in plain["extensionsUsed"]
    for name in ("KHR_materials_coat", "KHR_materials_fuzz", "KHR_materials_diffuse_roughness",
                 "KHR_materials_clearcoat", "KHR_materials_sheen"):
        assert name in drafts["extensionsUsed"]
    extensions = drafts["materials"][0]["extensions"]
    # a dielectric keeps glTF's own KHR_materials_specular (fitted; read right without the draft)
    assert "extensions" not in extensions["KHR_materials_specular"]
    assert extensions["KHR_materials_coat"] == MATERIAL["extensions"]["KHR_materials_coat"] | {
        "coatRoughnessFactor": pytest.approx(0.1, abs=1e-12)}
    assert extensions["KHR_materials_fuzz"] == MATERIAL["extensions"]["KHR_materials_fuzz"]
    for path in (tmp_path / "plain.gltf", tmp_path / "drafts.gltf"):
        report = validate_with_khronos(path, tmp_path)
        assert (report["issues"]["numErrors"], report["issues"]["numWarnings"]) == (0, 0), describe_issues(report)


@pytest.mark.parametrize("colorspace", COLORSPACES)
def test_openpbr_to_gltf_with_drafts_to_openpbr_returns_every_parameter_the_drafts_carry(tmp_path, colorspace):
    """Generated OpenPBR materials (every parameter over its legal range): each draft-carried
    parameter comes back within 1e-5 (colours compared in linear Rec.709, glTF's space), or the
    report has a note (OPBR1103/1104) at that material and parameter (or the glTF property carrying
    it). Parameters that have no effect are not compared: the coat's when coat_weight is 0, the fuzz's
    when fuzz_weight is 0, the coat's anisotropy when its roughness is 0 (both alphas are 0)."""
    source = tmp_path / "source.mtlx"
    source.write_text(openpbr_document("open_pbr_surface", colorspace, seed=1200 + COLORSPACES.index(colorspace), count=150))
    there = convert_file(str(source), str(tmp_path / "there.gltf"), settings=Settings(gltf_drafts=True))
    back = convert_file(str(tmp_path / "there.gltf"), str(tmp_path / "back.mtlx"))
    noted = {(d.location.material, d.location.input) for d in there.diagnostics + back.diagnostics
             if d.code in ("OPBR1103", "OPBR1104")}
    before = {m.material_name: m for m in read_asset(str(source)).materials}
    after = {m.material_name: m for m in read_asset(str(tmp_path / "back.mtlx")).materials}
    table = tables.table("open_pbr_surface")
    compared = exact = 0
    silent = []
    for name, material in before.items():
        shaders = {material.name, returned_name := after[name].name}
        returned = after[name]

        def value(m, parameter, space):
            entry = m.inputs.get(parameter)
            v = entry.value.value if entry is not None else table[parameter].default
            if table[parameter].type == "color3" and space not in (None, "lin_rec709"):
                v = tuple(colorspaces.to_lin_rec709(v, space))
            return np.asarray(v, dtype=float)

        coat = float(value(material, "coat_weight", None)) > 0
        fuzz = float(value(material, "fuzz_weight", None)) > 0
        smooth_coat = float(value(material, "coat_roughness", None)) == 0
        for parameter, properties in DRAFT_PARAMETERS.items():
            if (parameter.startswith("coat_") and parameter != "coat_weight" and not coat) or \
                    (parameter.startswith("fuzz_") and parameter != "fuzz_weight" and not fuzz) or \
                    (parameter == "coat_roughness_anisotropy" and smooth_coat):
                continue
            space = material.colorspace
            a, b = value(material, parameter, space), value(returned, parameter, returned.colorspace)
            compared += 1
            if np.allclose(a, b, atol=1e-5, rtol=0):
                exact += 1
            elif not any((who, where) in noted for who in shaders | {name, returned_name}
                         for where in (parameter,) + properties):
                silent.append((name, parameter, a.tolist(), b.tolist()))
    assert compared > 600 and exact / compared > 0.8, (compared, exact)  # the rest: noted clamps
    assert silent == []


# -- glTF -> .mtlx / .usda -> glTF over a generated corpus ---------------------------------------

@pytest.mark.parametrize("route, drafts", [("mtlx", True), ("usda", True), ("mtlx", False)],
                         ids=["mtlx-drafts", "usda-drafts", "mtlx-ratified"])
def test_gltf_round_trips_a_generated_corpus_through_mtlx_and_usd(tmp_path, route, drafts):
    """2,000 generated glTF materials through .mtlx with the drafts, 1,000 on the two other routes (the same
    generator, whose every seed sweeps each factor over its range; halved to keep the suite's time:
    tests/generated_gltf_materials.py: every factor of the core material, every ratified extension and every
    draft over its schema range, duplicate names; textures with KHR_texture_transform are the next test's corpus)
    through ``route`` and back, with ``--gltf-drafts`` or ratified-only: material count and names come back; every
    factor and every value a draft carries (tests/gltf_round_trip.py, render-equivalences stated
    there) returns within 1e-5 or has a note (OPBR1103/1104) at its material and a related input;
    the Khronos validator finds no error or warning."""
    from generated_gltf_materials import document

    statuses = collections.Counter()
    silent = []
    seeds = 4 if (route, drafts) == ("mtlx", True) else 2
    for seed in range(seeds):
        source = tmp_path / f"corpus{seed}.gltf"
        source.write_text(json.dumps(document(seed, 500)))  # textures: the textured test below
        there = convert_file(str(source), str(tmp_path / f"corpus{seed}.{route}"))
        back_path = tmp_path / f"back{seed}.gltf"
        back = convert_file(str(tmp_path / f"corpus{seed}.{route}"), str(back_path), settings=Settings(gltf_drafts=drafts))
        before = json.loads(source.read_text())["materials"]
        after = json.loads(back_path.read_text())["materials"]
        assert [m["name"] for m in after] == [m["name"] for m in before]
        for index, found in enumerate(gltf_round_trip.round_trip(before, after, there, back)):
            for key, status, value, got in found:
                statuses[status] += 1
                if status == "silent":
                    silent.append((seed, index, key, value, got))
        report = validate_with_khronos(back_path, tmp_path)
        assert (report["issues"]["numErrors"], report["issues"]["numWarnings"]) == (0, 0), describe_issues(report)
    assert statuses["exact"] > 7500 * seeds and statuses["exact"] / sum(statuses.values()) > (0.9 if drafts else 0.85), statuses
    assert silent == [], silent[:10]


def test_the_cli_flag_writes_the_drafts_in_single_and_batch_form(tmp_path):
    source = _gltf(tmp_path / "in.gltf", [MATERIAL])
    (tmp_path / "lib").mkdir()
    convert_file(str(source), str(tmp_path / "lib" / "mid.mtlx"))
    single = CliRunner().invoke(cli, ["convert", str(tmp_path / "lib" / "mid.mtlx"), "-o", str(tmp_path / "one.gltf"),
                                      "--gltf-drafts"])
    assert single.exit_code == 0, single.output
    batch = CliRunner().invoke(cli, ["convert", str(tmp_path / "lib"), "-o", str(tmp_path / "out"), "--output-format",
                                     "gltf", "--gltf-drafts", "--jobs", "1"])
    assert batch.exit_code == 0, batch.output
    for path in (tmp_path / "one.gltf", tmp_path / "out" / "mid.gltf"):
        assert "KHR_materials_coat" in json.loads(path.read_text())["extensionsUsed"]


TEXTURE_SLOTS = (("pbrMetallicRoughness", "baseColorTexture", "baseColor"),
                 ("pbrMetallicRoughness", "metallicRoughnessTexture", "metallic"),
                 ("", "normalTexture", None), ("KHR_materials_clearcoat", "clearcoatTexture", "clearcoat"),
                 ("KHR_materials_coat", "coatTexture", "coat"))


def _texture_info(material, container, prop):
    if container == "":
        return material.get(prop)
    holder = material.get(container) if container == "pbrMetallicRoughness" else \
        (material.get("extensions") or {}).get(container)
    return (holder or {}).get(prop)


def _transform(info) -> list:
    transform = ((info or {}).get("extensions") or {}).get("KHR_texture_transform") or {}
    return list(transform.get("offset", [0.0, 0.0])) + list(transform.get("scale", [1.0, 1.0])) + \
        [transform.get("rotation", 0.0), transform.get("texCoord", (info or {}).get("texCoord", 0))]


def test_textures_and_their_uv_transforms_survive_a_round_trip_or_are_reported(tmp_path):
    """300 generated glTF materials with a texture on base colour, metallic-roughness, normal,
    clearcoat and coat weight, half of them with KHR_texture_transform: through .mtlx and back with
    --gltf-drafts, each texture is in the same slot with the same transform and UV set (within 1e-5),
    or a note (OPBR1103/1104) at its material names the texture or its factors."""
    from PIL import Image

    from generated_gltf_materials import document

    image = Image.new("RGBA", (4, 4))
    image.putdata([(16 * i, 255 - 16 * i, (37 * i) % 256, 200) for i in range(16)])
    image.save(tmp_path / "texture.png")
    source = tmp_path / "textured.gltf"
    before = document(7, 300, textured=True)
    source.write_text(json.dumps(before))
    there = convert_file(str(source), str(tmp_path / "textured.mtlx"))
    back = convert_file(str(tmp_path / "textured.mtlx"), str(tmp_path / "back.gltf"), settings=Settings(gltf_drafts=True))
    after = json.loads((tmp_path / "back.gltf").read_text())["materials"]
    noted: dict = {}
    for d in there.diagnostics + back.diagnostics:
        if d.code in ("OPBR1103", "OPBR1104"):
            noted.setdefault(d.location.material, set()).add(d.location.input)
    kept = 0
    silent = []
    for index, (a, b) in enumerate(zip(before["materials"], after)):
        unique = there.pairs[index][1].material_name
        inputs = noted.get(a["name"], set()) | noted.get(unique, set()) | noted.get(f"{unique}_shader", set())
        for container, prop, group in TEXTURE_SLOTS:
            if container == "KHR_materials_clearcoat" and "KHR_materials_coat" in (a.get("extensions") or {}):
                continue  # the fallback of KHR_materials_coat
            info = _texture_info(a, container, prop)
            if info is None:
                continue
            returned = _texture_info(b, container, prop)
            if returned is not None and np.allclose(_transform(info), _transform(returned), atol=1e-5, rtol=0):
                kept += 1
                continue
            related = {prop} | (gltf_round_trip.RELATED.get(group, set()) | gltf_round_trip.GROUP_INPUTS.get(group, set())
                                if group else {"normal", "geometry_normal"})
            if group == "metallic":
                related |= gltf_round_trip.RELATED["roughness"]
            if not inputs & related:
                silent.append((index, prop, _transform(info), returned and _transform(returned)))
    assert kept > 300, kept
    assert silent == [], silent[:5]
    report = validate_with_khronos(tmp_path / "back.gltf", tmp_path)
    assert (report["issues"]["numErrors"], report["issues"]["numWarnings"]) == (0, 0), describe_issues(report)


def test_variant_names_travel_in_the_side_channel_and_their_loss_is_reported(tmp_path):
    source = tmp_path / "variants.gltf"
    source.write_text(json.dumps({
        "asset": {"version": "2.0"}, "extensionsUsed": ["KHR_materials_variants"],
        "extensions": {"KHR_materials_variants": {"variants": [{"name": "red"}, {"name": "blue"}]}},
        "materials": [{"name": "Red"}, {"name": "Blue"}],
        "meshes": [{"primitives": [{"attributes": {}, "material": 0, "extensions": {"KHR_materials_variants": {
            "mappings": [{"material": 0, "variants": [0]}, {"material": 1, "variants": [1]}]}}}]}]}))
    there = convert_file(str(source), str(tmp_path / "mid.mtlx"))
    assert any("KHR_materials_variants names (blue)" in d.message for d in there.diagnostics)
    assert "&quot;variants&quot;:[&quot;red&quot;]" in (tmp_path / "mid.mtlx").read_text()
    back = convert_file(str(tmp_path / "mid.mtlx"), str(tmp_path / "back.gltf"))
    lost = [d for d in back.diagnostics if d.code == "OPBR1104" and "variants red" in d.message]
    assert len(lost) == 1 and lost[0].location.material == "Red"


JUNK = [None, "x", -1, 1e309, float("nan"), [], {}, [1, 2], [1, "a", 3], True, {"index": 99}, {"index": "a"}, 1e-320,
        -0.0, 5, [0.5, 0.5, 0.5, 0.5]]
HOSTILE_PROPERTIES = {
    "KHR_materials_coat": ["coatFactor", "coatRoughnessFactor", "coatIor", "coatColorFactor", "coatDarkeningFactor",
                           "coatAnisotropyStrength", "coatAnisotropyRotation", "coatTexture", "coatNormalTexture",
                           "coatColorTexture", "coatAnisotropyTexture", "coatRoughnessTexture"],
    "KHR_materials_fuzz": ["fuzzFactor", "fuzzColorFactor", "fuzzRoughnessFactor", "fuzzTexture", "fuzzColorTexture",
                           "fuzzRoughnessTexture"],
    "KHR_materials_diffuse_roughness": ["diffuseRoughnessFactor", "diffuseRoughnessTexture"],
    "KHR_materials_diffuse_transmission": ["diffuseTransmissionFactor", "diffuseTransmissionColorFactor"],
}


def test_hostile_draft_and_side_channel_values_never_crash_a_conversion(tmp_path):
    """Seeded junk (wrong types, NaN, infinities, dangling texture indices) in every draft property,
    the sub-extensions and KHR_materials_variants: every conversion finishes (notes, no traceback)
    and every glTF it writes is JSON (no NaN or infinity)."""
    rng = random.Random(11)
    for trial in range(60):
        extensions: dict = {}
        for name, properties in HOSTILE_PROPERTIES.items():
            if rng.random() < 0.6:
                extensions[name] = {p: rng.choice(JUNK) for p in properties if rng.random() < 0.5} \
                    if rng.random() < 0.9 else rng.choice(JUNK)
        if rng.random() < 0.5:
            extensions["KHR_materials_clearcoat"] = {"clearcoatFactor": 0.5, "extensions": rng.choice([
                {"EXT_materials_clearcoat_darkening": {"clearcoatDarkeningFactor": rng.choice(JUNK)}},
                {"KHR_materials_clearcoat_ior": rng.choice(JUNK)}, rng.choice(JUNK)])}
        if rng.random() < 0.3:
            extensions["KHR_materials_anisotropy"] = {"anisotropyStrength": 0.5, "extensions": {
                "EXT_materials_anisotropy_openpbr": {"openPbrAnisotropyEnabled": rng.choice(JUNK + [True])}}}
        document = {"asset": {"version": "2.0"}, "materials": [{"name": "M", "extensions": extensions}],
                    "extensions": {"KHR_materials_variants": rng.choice(JUNK + [{"variants": rng.choice(JUNK)}])}}
        source = tmp_path / "hostile.gltf"
        source.write_text(json.dumps(document, allow_nan=True))
        convert_file(str(source), str(tmp_path / "out.mtlx"))
        convert_file(str(tmp_path / "out.mtlx"), str(tmp_path / "back.gltf"), settings=Settings(gltf_drafts=True))
        convert_file(str(source), str(tmp_path / "out.gltf"), settings=Settings(gltf_drafts=True))
        convert_file(str(source), str(tmp_path / "out.usda"))
        for written in ("back.gltf", "out.gltf"):
            json.loads((tmp_path / written).read_text(), parse_constant=lambda c: pytest.fail(f"{c} in {written}"))
