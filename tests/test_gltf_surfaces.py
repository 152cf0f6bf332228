"""Surfaces lit from the wrong side, tangent frames that do not flip on mirrored UVs, volumes with no inside (session
20's red team, I: gb03, gb11, gb14), judged by :mod:`openpbr_tools.rules.gltf_surfaces`.

The expected facts are closed forms of the meshes built here: a cube of side 1 encloses a volume of 1 (-1 wound
inside out), a cube without one face has 4 edges used by one triangle, a quad 4 of its 5; three of six faces
mirrored in u are half the triangles. Every broken file and its repaired twin also goes through the Khronos
glTF-Validator, which must report no error or warning on either (so the toolkit is the only one to say it)."""

from __future__ import annotations

import json

import numpy as np
import pytest

from gltf_support import describe_issues, validate_many_with_khronos
from openpbr_tools.io.gltf import surfaces
from openpbr_tools.io.gltf.document import load_document
from redteam_support import findings
from test_gltf_geometry_round_seven import _FACES, _FLOAT, data_uri, document, png


def mesh(mirrored=(), flip_w=True, normal_sign=1.0, reverse_winding=False, drop_face=None, smooth=False):
    """A unit cube of 24 vertices (one quad per face, each face's UVs the unit square) with NORMAL and TANGENT.
    ``mirrored`` faces run u the other way, with the tangent along +u and, when ``flip_w``, w = -1 there."""
    positions, normals, tangents, uvs, indices = [], [], [], [], []
    for face, (n, t) in enumerate(_FACES):
        if face == drop_face:
            continue
        n, t = np.array(n, float), np.array(t, float)
        b = np.cross(n, t)
        base = len(positions) // 3
        mirror = face in mirrored
        for s, r in ((0, 0), (1, 0), (1, 1), (0, 1)):
            corner = 0.5 * n + (s - 0.5) * t + (r - 0.5) * b
            positions += list(corner)
            normals += list(normal_sign * (corner / np.linalg.norm(corner) if smooth else n))
            tangents += [*(-t if mirror else t), -1.0 if mirror and flip_w else 1.0]
            uvs += [1 - s if mirror else s, 1 - r]
        quad = [base, base + 1, base + 2, base, base + 2, base + 3]
        indices += quad[::-1] if reverse_winding else quad
    return positions, normals, tangents, uvs, indices


def gltf(material, **options) -> dict:
    positions, normals, tangents, uvs, indices = mesh(**options)
    vertices = {"POSITION": ("VEC3", positions, _FLOAT), "NORMAL": ("VEC3", normals, _FLOAT),
                "TANGENT": ("VEC4", tangents, _FLOAT), "TEXCOORD_0": ("VEC2", uvs, _FLOAT)}
    used = sorted({k for k in material.get("extensions", {})})
    return document(vertices, indices, material, images=[{"uri": data_uri(png(4, (128, 128, 255)))}],
                    **({"extensionsUsed": used} if used else {}))


_NORMAL_MAPPED = {"name": "M", "normalTexture": {"index": 0}}
_GLASS = {"name": "Glass", "pbrMetallicRoughness": {"metallicFactor": 0.0},
          "extensions": {"KHR_materials_transmission": {"transmissionFactor": 1.0},
                         "KHR_materials_volume": {"thicknessFactor": 0.02}}}
_PLAIN = {"name": "M", "pbrMetallicRoughness": {"metallicFactor": 0.0}}


def quad(material, normal_z=1.0) -> dict:
    vertices = {"POSITION": ("VEC3", [-1, -1, 0, 1, -1, 0, 1, 1, 0, -1, 1, 0], _FLOAT),
                "NORMAL": ("VEC3", [0, 0, normal_z] * 4, _FLOAT)}
    used = sorted(material.get("extensions", {}))
    return document(vertices, [0, 1, 2, 0, 2, 3], material, **({"extensionsUsed": used} if used else {}))


def surface_of(tmp_path, root: dict, wants_closed=True, normal_sets=(0,)) -> dict:
    path = tmp_path / "facts.gltf"
    path.write_text(json.dumps(root), encoding="utf-8")
    loaded = load_document(str(path))
    return surfaces.primitive_surface(loaded, root["meshes"][0]["primitives"][0], wants_closed, normal_sets)


def test_the_facts_are_the_closed_forms_of_a_cube(tmp_path):
    good = surface_of(tmp_path, gltf(_PLAIN))
    assert good["triangles"] == 12 and good["facing"]["agree"] == 1.0
    assert good["closed"]["boundary"] == 0 and good["closed"]["non_manifold"] == 0 and good["closed"]["edges"] == 18
    assert good["closed"]["volume"] == pytest.approx(1.0)  # split per face, welded: a closed unit cube
    inside_out = surface_of(tmp_path, gltf(_PLAIN, reverse_winding=True))
    assert inside_out["closed"]["volume"] == pytest.approx(-1.0) and inside_out["facing"]["agree"] == 0.0
    assert surface_of(tmp_path, gltf(_PLAIN, normal_sign=-1.0))["facing"]["agree"] == 0.0
    assert surface_of(tmp_path, gltf(_PLAIN, drop_face=0))["closed"]["boundary"] == 4
    assert surface_of(tmp_path, quad(_PLAIN))["closed"] == {"edges": 5, "boundary": 4, "non_manifold": 0,
                                                            "volume": 0.0}
    half = surface_of(tmp_path, gltf(_NORMAL_MAPPED, mirrored=(1, 3, 5), flip_w=False))["handedness"][0]
    assert half == {"checked": 12, "minority": 6, "mixed": 0.5}
    assert surface_of(tmp_path, gltf(_NORMAL_MAPPED, mirrored=(1, 3, 5)))["handedness"][0]["minority"] == 0


# (case, broken, repaired, code, severity, JSON pointer, property)
CASES = {
    "gb11_normals_inward": (lambda: gltf(_PLAIN, normal_sign=-1.0), lambda: gltf(_PLAIN),
                            "OPBR1246", "error", "/meshes/0/primitives/0/attributes", "NORMAL"),
    "cube_wound_inside_out": (lambda: gltf(_PLAIN, reverse_winding=True), lambda: gltf(_PLAIN),
                              "OPBR1246", "error", "/meshes/0/primitives/0/attributes", "NORMAL"),
    "open_sheet_normals_down": (lambda: quad(_PLAIN, -1.0), lambda: quad(_PLAIN),
                                "OPBR1246", "error", "/meshes/0/primitives/0/attributes", "NORMAL"),
    "gb14_mirrored_w_not_flipped": (lambda: gltf(_NORMAL_MAPPED, mirrored=(1, 3, 5), flip_w=False),
                                    lambda: gltf(_NORMAL_MAPPED, mirrored=(1, 3, 5)),
                                    "OPBR1247", "error", "/meshes/0/primitives/0/attributes", "TANGENT"),
    "gb03_volume_on_open_sheet": (lambda: quad(_GLASS), lambda: gltf(_GLASS),
                                  "OPBR1248", "warning", "/materials/0/extensions/KHR_materials_volume", "thicknessFactor"),
    "volume_on_cube_missing_a_face": (lambda: gltf(_GLASS, drop_face=2), lambda: gltf(_GLASS),
                                      "OPBR1248", "warning", "/materials/0/extensions/KHR_materials_volume",
                                      "thicknessFactor"),
}


@pytest.fixture(scope="module")
def written(tmp_path_factory):
    folder = tmp_path_factory.mktemp("surfaces")
    paths = {}
    for name, (broken, repaired, *_) in CASES.items():
        for kind, build in (("broken", broken), ("repaired", repaired)):
            path = folder / f"{name}_{kind}.gltf"
            path.write_text(json.dumps(build(), indent=1), encoding="utf-8")
            paths[name, kind] = path
    return folder, paths


@pytest.mark.parametrize("name", sorted(CASES))
def test_the_toolkit_reports_the_broken_file_and_not_its_repair(written, name):
    _, paths = written
    code, severity, pointer, prop = CASES[name][2:]
    assert (code, severity, pointer, prop) in findings(paths[name, "broken"])
    assert code not in {f[0] for f in findings(paths[name, "repaired"])}


def test_the_khronos_validator_passes_every_case(written, tmp_path):
    _, paths = written
    reports = validate_many_with_khronos(paths.values(), tmp_path)
    for path in paths.values():
        issues = reports[str(path.resolve())]["issues"]
        assert issues["numErrors"] == 0 and issues["numWarnings"] == 0, describe_issues(reports[str(path.resolve())])


def test_smooth_normals_and_mirrored_islands_done_right_pass(tmp_path):
    """Corner normals averaged over a cube's edges still face out (45-55 degrees off each face, not behind it); a
    thin-walled glass sheet (thickness 0) is no volume; a mirrored island whose w flips is MikkTSpace's output."""
    cases = {"smooth": gltf(_PLAIN, smooth=True), "mirrored": gltf(_NORMAL_MAPPED, mirrored=(0, 2, 4)),
             "thin": quad({**_GLASS, "extensions": {**_GLASS["extensions"],
                                                    "KHR_materials_volume": {"thicknessFactor": 0.0}}})}
    for name, root in cases.items():
        path = tmp_path / f"{name}.gltf"
        path.write_text(json.dumps(root), encoding="utf-8")
        assert not {f[0] for f in findings(path)} & {"OPBR1246", "OPBR1247", "OPBR1248"}, name
