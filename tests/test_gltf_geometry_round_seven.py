"""glTF geometry and animation defects the Khronos glTF-Validator is silent on (session 20's red team, I: gb01, gb06,
gb10, gb13, gb15), judged by the rules of :mod:`openpbr_tools.rules.gltf_geometry`.

Each case is a small document built here, a broken one and its repaired twin. All of them run through the validator in
one node process; each test asserts that the validator reports no error and no warning on either file (so the toolkit
is the only one to say it) and that the toolkit reports the code, at its severity, on the broken file and not on the
twin. Further tests pin the edges of each rule: what the specification allows must pass (a tiling layout, an atlas of
transforms, a pointer to a property defined by its default)."""

from __future__ import annotations

import base64
import io
import json
import struct
from pathlib import Path

import numpy as np
import pytest
from PIL import Image

from gltf_support import describe_issues, validate_many_with_khronos
from redteam_support import findings

_FLOAT, _UNSIGNED_BYTE = 5126, 5121


def png(size: int = 4, colour=(180, 120, 60)) -> bytes:
    handle = io.BytesIO()
    Image.new("RGB", (size, size), colour).save(handle, "PNG")
    return handle.getvalue()


def data_uri(data: bytes, mime: str = "image/png") -> str:
    return f"data:{mime};base64," + base64.b64encode(data).decode("ascii")


def document(vertices: dict, indices, material: dict, images=None, textures: int = 1, **members) -> dict:
    """A glTF drawing one indexed triangle list with ``material``. ``vertices``: attribute -> (accessor type, values,
    componentType; normalised when an integer type); ``images`` the image objects (one 4 x 4 PNG by default), each
    its own texture; ``members`` join the root. Accessors named in lower case (animation data) are not drawn."""
    data, views, accessors, named = b"", [], [], {}
    for name, (kind, values, component) in vertices.items():
        fmt = "f" if component == _FLOAT else "B"
        packed = struct.pack(f"<{len(values)}{fmt}", *values)
        width = {"SCALAR": 1, "VEC2": 2, "VEC3": 3, "VEC4": 4}[kind]
        view = {"buffer": 0, "byteOffset": len(data), "byteLength": len(packed)}
        if name.isupper():
            view["target"] = 34962
        views.append(view)
        accessor = {"bufferView": len(views) - 1, "componentType": component, "count": len(values) // width, "type": kind}
        if component != _FLOAT:
            accessor["normalized"] = True
        if name in ("POSITION", "input"):
            columns = [values[i::width] for i in range(width)]
            accessor.update({"min": [min(c) for c in columns], "max": [max(c) for c in columns]})
        named[name] = len(accessors)
        accessors.append(accessor)
        data += packed + bytes(-len(packed) % 4)
    packed = struct.pack(f"<{len(indices)}H", *indices)
    views.append({"buffer": 0, "byteOffset": len(data), "byteLength": len(packed), "target": 34963})
    accessors.append({"bufferView": len(views) - 1, "componentType": 5123, "count": len(indices), "type": "SCALAR"})
    data += packed + bytes(-len(packed) % 4)
    images = images if images is not None else [{"uri": data_uri(png())}]
    root = {"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
            "meshes": [{"primitives": [{"attributes": {k: v for k, v in named.items() if k.isupper()},
                                        "indices": len(accessors) - 1, "material": 0}]}],
            "materials": [material], "accessors": accessors, "bufferViews": views,
            "buffers": [{"byteLength": len(data), "uri": data_uri(data, "application/octet-stream")}],
            "images": images, "samplers": [{"magFilter": 9729, "minFilter": 9987, "wrapS": 10497, "wrapT": 10497}],
            "textures": [{"source": i, "sampler": 0} for i in range(len(images))], **members}
    if "animations" in members:
        root["animations"][0]["samplers"] = [{"input": named["input"], "output": named["output"]}]
    return root


# -- a unit cube of 24 vertices, one quad per face (outward, counter-clockwise), each face's UVs the unit square ------
_FACES = [((1, 0, 0), (0, 0, -1)), ((-1, 0, 0), (0, 0, 1)), ((0, 1, 0), (1, 0, 0)),
          ((0, -1, 0), (1, 0, 0)), ((0, 0, 1), (1, 0, 0)), ((0, 0, -1), (-1, 0, 0))]


def cube(face_offsets=(0,) * 6, scale: float = 1.0):
    """(positions, normals, uvs, indices) of a cube whose face f maps to the unit square shifted by face_offsets[f] in
    u and scaled by ``scale``."""
    positions, normals, uvs, indices = [], [], [], []
    for face, ((nx, ny, nz), (tx, ty, tz)) in enumerate(_FACES):
        n, t = np.array((nx, ny, nz), float), np.array((tx, ty, tz), float)
        b = np.cross(n, t)
        base = len(positions) // 3
        for s, r in ((0, 0), (1, 0), (1, 1), (0, 1)):
            positions += list(0.5 * n + (s - 0.5) * t + (r - 0.5) * b)
            normals += [nx, ny, nz]
            uvs += [(s + face_offsets[face]) * scale, (1 - r) * scale]
        indices += [base, base + 1, base + 2, base, base + 2, base + 3]
    return positions, normals, uvs, indices


def textured_cube(uvs_transform=lambda uvs: uvs, material=None, images=None, extra=None, **members):
    positions, normals, uvs, indices = cube()
    vertices = {"POSITION": ("VEC3", positions, _FLOAT), "NORMAL": ("VEC3", normals, _FLOAT),
                "TEXCOORD_0": ("VEC2", uvs_transform(uvs), _FLOAT), **(extra or {})}
    return document(vertices, indices, material or {"name": "M", "pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}},
                    images=images, **members)


# -- gb01: COLOR_0 black on every vertex -------------------------------------------------------------------------------
def _vertex_colour(kind: str, component: int, black, white, base_factor=None):
    def build(colour):
        pbr = {"baseColorTexture": {"index": 0}} | ({"baseColorFactor": base_factor} if base_factor else {})
        return textured_cube(material={"name": "M", "pbrMetallicRoughness": pbr},
                             extra={"COLOR_0": ("VEC3" if len(colour) == 3 else "VEC4", list(colour) * 24, component)})
    return lambda: (build(black), build(white))


# -- gb10: KHR_animation_pointer to an undefined material property ------------------------------------------------------
def _animated(pointer: str, material: dict, used=()):
    frames = {"input": ("SCALAR", [0.0, 1.0, 2.0], _FLOAT), "output": ("SCALAR", [0.2, 0.8, 0.2], _FLOAT)}
    channel = {"sampler": 0, "target": {"path": "pointer", "extensions": {"KHR_animation_pointer": {"pointer": pointer}}}}
    return textured_cube(material=material, extra=frames, extensionsUsed=["KHR_animation_pointer", *used],
                         animations=[{"name": "wet_cycle", "channels": [channel]}])


_PBR = {"name": "M", "pbrMetallicRoughness": {"baseColorTexture": {"index": 0}, "metallicFactor": 0.0}}
_COATED = {**_PBR, "extensions": {"KHR_materials_clearcoat": {}}}


def _pointer_case(broken_pointer, fixed_pointer, material=_PBR, fixed_material=None, used=()):
    return lambda: (_animated(broken_pointer, material, used), _animated(fixed_pointer, fixed_material or material, used))


# -- gb13: a transform on the base colour alone ------------------------------------------------------------------------
_TILED = {"KHR_texture_transform": {"scale": [4, 4]}}


def _texture_set(transformed=("base",), texcoord_other: int = 0, other_transform=_TILED):
    def info(index, key, extra=None):
        found = {"index": index, **(extra or {})}
        if key != "base" and texcoord_other:
            found["texCoord"] = texcoord_other
        if key in transformed:
            found["extensions"] = _TILED if key == "base" else other_transform
        return found
    material = {"name": "M_floor", "normalTexture": info(1, "normal"),
                "pbrMetallicRoughness": {"baseColorTexture": info(0, "base"), "metallicRoughnessTexture": info(2, "mr")}}
    images = [{"uri": data_uri(png(colour=c))} for c in ((180, 120, 60), (128, 128, 255), (0, 160, 0))]
    extra = {"TANGENT": ("VEC4", [c for (_, t) in _FACES for _ in range(4) for c in (*t, 1.0)], _FLOAT)}
    if texcoord_other:
        extra["TEXCOORD_1"] = ("VEC2", cube()[2], _FLOAT)
    return textured_cube(material=material, images=images, extra=extra, extensionsUsed=["KHR_texture_transform"])


# -- gb15: a UDIM layout ---------------------------------------------------------------------------------------------
def _udim_cube(packed: bool, image_name: str):
    """The red team's layout: faces 0-2 in tile 1001, faces 3-5 in 1002 (each a whole tile); packed: u halved."""
    positions, normals, uvs, indices = cube(face_offsets=(0, 0, 0, 1, 1, 1))
    if packed:
        uvs = [c / 2 if i % 2 == 0 else c for i, c in enumerate(uvs)]
    vertices = {"POSITION": ("VEC3", positions, _FLOAT), "NORMAL": ("VEC3", normals, _FLOAT),
                "TEXCOORD_0": ("VEC2", uvs, _FLOAT)}
    return document(vertices, indices, {"name": "M_hull", "pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}},
                    images=[{"uri": image_name}])


def _islands(tiles, width: float = 1.0):
    """Separate quads side by side in space, quad i's UV island the square at u = tiles[i] (of side ``width``) with a
    margin, as a UDIM layout keeps islands off the tiles' edges."""
    positions, uvs, indices = [], [], []
    for i, u in enumerate(tiles):
        base = len(positions) // 3
        positions += [3 * i - 1, -1, 0, 3 * i + 1, -1, 0, 3 * i + 1, 1, 0, 3 * i - 1, 1, 0]
        low, high = u + 0.05 * width, u + 0.95 * width
        uvs += [low, 0.95, high, 0.95, high, 0.05, low, 0.05]
        indices += [base, base + 1, base + 2, base, base + 2, base + 3]
    return document({"POSITION": ("VEC3", positions, _FLOAT), "TEXCOORD_0": ("VEC2", uvs, _FLOAT)}, indices,
                    {"name": "M", "pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}})


def _grid(quads: int):
    """A plane of quads x quads welded quads whose UVs run 0..quads continuously: each quad one whole tile (tiling)."""
    positions, uvs, indices = [], [], []
    for j in range(quads + 1):
        for i in range(quads + 1):
            positions += [i, 0, j]
            uvs += [i, j - quads + 1]  # v from -(quads - 1) to 1: the rows UDIM's grid would number 1001, 1011 ...
    for j in range(quads):
        for i in range(quads):
            a = j * (quads + 1) + i
            indices += [a, a + quads + 1, a + 1, a + 1, a + quads + 1, a + quads + 2]
    return document({"POSITION": ("VEC3", positions, _FLOAT), "TEXCOORD_0": ("VEC2", uvs, _FLOAT)}, indices,
                    {"name": "M", "pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}})


# -- gb06: texture coordinates far from 0 ----------------------------------------------------------------------------
def _shifted(offset: float, size: int):
    return textured_cube(lambda uvs: [c + offset if i % 2 == 0 else c for i, c in enumerate(uvs)],
                         images=[{"uri": data_uri(png(size))}])


_BLACK3, _WHITE3 = (0.0, 0.0, 0.0), (1.0, 1.0, 1.0)
#: name: (builder -> (broken, repaired), toolkit code, severity); every file is written beside a 64 x 64 PNG named
#: hull_basecolor.1001.png for the UDIM cases.
CASES = {
    "colour0_black_float": (_vertex_colour("VEC3", _FLOAT, _BLACK3, _WHITE3), "OPBR1241", "error"),
    "colour0_black_normalised_bytes": (_vertex_colour("VEC4", _UNSIGNED_BYTE, (0, 0, 0, 255), (255, 255, 255, 255)),
                                       "OPBR1241", "error"),
    "pointer_to_a_name_the_schema_lacks": (
        _pointer_case("/materials/0/pbrMetallicRoughness/roughness", "/materials/0/pbrMetallicRoughness/roughnessFactor"),
        "OPBR1242", "warning"),
    "pointer_into_an_absent_extension": (
        _pointer_case("/materials/0/extensions/KHR_materials_clearcoat/clearcoatFactor",
                      "/materials/0/extensions/KHR_materials_clearcoat/clearcoatFactor", fixed_material=_COATED,
                      used=("KHR_materials_clearcoat",)), "OPBR1242", "warning"),
    "base_colour_transform_only": (lambda: (_texture_set(("base",)), _texture_set(("base", "normal", "mr"))),
                                   "OPBR1243", "warning"),
    "udim_tiles_with_a_tile_image": (lambda: (_udim_cube(False, "hull_basecolor.1001.png"),
                                              _udim_cube(True, "hull_basecolor.1001.png")), "OPBR1244", "warning"),
    "udim_tiles_with_islands_of_their_own": (lambda: (_islands([0, 1, 2]), _islands([0, 1 / 3, 2 / 3], 1 / 3)),
                                             "OPBR1244", "warning"),
    "uv_offset_262144_on_64_pixels": (lambda: (_shifted(262144.0, 64), _shifted(0.0, 64)), "OPBR1245", "warning"),
}


def _write(path: Path, content: dict) -> Path:
    path.write_text(json.dumps(content, indent=1), encoding="utf-8")
    return path


@pytest.fixture(scope="module")
def cases(tmp_path_factory) -> dict[str, tuple[Path, Path]]:
    folder = tmp_path_factory.mktemp("geometry")
    (folder / "hull_basecolor.1001.png").write_bytes(png(64))
    written = {}
    for name, (build, *_) in CASES.items():
        broken, fixed = build()
        written[name] = (_write(folder / f"{name}.gltf", broken), _write(folder / f"{name}_fixed.gltf", fixed))
    return written


@pytest.fixture(scope="module")
def khronos(cases, tmp_path_factory) -> dict:
    return validate_many_with_khronos([p for pair in cases.values() for p in pair], tmp_path_factory.mktemp("node"))


def _errors_and_warnings(report: dict) -> list[str]:
    return [m["code"] for m in report["issues"]["messages"] if m["severity"] in (0, 1)]


@pytest.mark.parametrize("name", sorted(CASES))
def test_the_validator_is_silent_and_the_toolkit_reports_only_the_broken_file(name, cases, khronos):
    broken, fixed = cases[name]
    _, code, severity = CASES[name]
    for path in (broken, fixed):
        report = khronos[str(path.resolve())]
        assert _errors_and_warnings(report) == [], describe_issues(report)
    assert (code, severity) in {(c, s) for c, s, *_ in findings(broken)}, findings(broken)
    assert code not in {c for c, *_ in findings(fixed)}, findings(fixed)


def _codes(tmp_path, content: dict, name: str = "asset.gltf") -> set[str]:
    return {c for c, *_ in findings(_write(tmp_path / name, content))}


# -- the edges of each rule ------------------------------------------------------------------------------------------
def test_black_vertex_colour_is_not_reported_on_an_already_black_base_colour(tmp_path):
    """COLOR_0 multiplies the base colour (glTF 2.0, 3.7.2.1): on a black base it changes nothing."""
    material = {"name": "M", "pbrMetallicRoughness": {"baseColorFactor": [0, 0, 0, 1]}}
    assert "OPBR1241" not in _codes(tmp_path, textured_cube(material=material, extra={
        "COLOR_0": ("VEC3", [0.0] * 72, _FLOAT)}))


def test_a_vertex_colour_black_on_some_vertices_only_is_painted_not_empty(tmp_path):
    colours = [0.0] * 69 + [1.0, 1.0, 1.0]
    assert "OPBR1241" not in _codes(tmp_path, textured_cube(extra={"COLOR_0": ("VEC3", colours, _FLOAT)}))


@pytest.mark.parametrize("pointer", [
    "/materials/0/pbrMetallicRoughness/metallicFactor",  # the extension's own example: present explicitly
    "/materials/0/pbrMetallicRoughness/roughnessFactor",  # absent, but with a default in a present object
    "/materials/0/emissiveFactor",
    "/materials/0/alphaCutoff",
    "/materials/0/pbrMetallicRoughness/baseColorTexture/texCoord",
    "/materials/0/extras/wetness",  # "entirely application specific"
])
def test_pointers_to_properties_the_asset_defines_are_not_reported(tmp_path, pointer):
    """KHR_animation_pointer: "A property is considered defined if it is present in the asset explicitly or if it has a
    default value and its enclosing object is present"."""
    assert "OPBR1242" not in _codes(tmp_path, _animated(pointer, _PBR))


@pytest.mark.parametrize("pointer, words", [
    ("/materials/0/pbrMetallicRoughness/roughness", "no property 'roughness'"),
    ("/materials/1/emissiveFactor", "/materials/1 is not in the asset"),
    ("/materials/0/pbrMetallicRoughness/baseColorTexture/extensions/KHR_texture_transform/offset",
     "/materials/0/pbrMetallicRoughness/baseColorTexture/extensions is not in the asset"),
    ("/materials/0/extensions/KHR_materials_volume/attenuationDistance", "has no default value"),
])
def test_pointers_to_undefined_properties_say_why(tmp_path, pointer, words):
    """KHR_animation_pointer: "Pointers to the asset properties that do not have a spec-defined default value ... are
    invalid if the property is not defined in the asset explicitly"; a property of an absent object is undefined."""
    material = {**_PBR, "extensions": {"KHR_materials_volume": {"thicknessFactor": 0.1},
                                       "KHR_materials_transmission": {"transmissionFactor": 1.0}}}
    path = _write(tmp_path / "asset.gltf", _animated(pointer, material, ("KHR_materials_volume", "KHR_materials_transmission")))
    from redteam_support import messages
    found = messages(path, "OPBR1242")
    assert len(found) == 1 and words in found[0], found


def test_an_atlas_where_each_texture_has_its_own_transform_is_not_reported(tmp_path):
    offset = {"KHR_texture_transform": {"offset": [0.5, 0], "scale": [0.5, 0.5]}}
    assert "OPBR1243" not in _codes(tmp_path, _texture_set(("base", "normal", "mr"), other_transform=offset))


def test_other_maps_on_another_uv_set_are_another_texture_set(tmp_path):
    """The transform slides the colour off maps that read the same UV layout; on another set they never lined up."""
    assert "OPBR1243" not in _codes(tmp_path, _texture_set(("base",), texcoord_other=1))


def test_one_other_map_transformed_is_a_deliberate_mix_not_reported(tmp_path):
    assert "OPBR1243" not in _codes(tmp_path, _texture_set(("base", "normal")))


def test_a_tiling_grid_with_one_tile_per_quad_is_not_udim(tmp_path):
    """Every triangle of a 4 x 4 plane mapped 0..4 lies in one unit square and the squares differ, as in a UDIM layout;
    but the mapping runs continuously across them (one island): texture repetition under REPEAT, legal glTF."""
    assert "OPBR1244" not in _codes(tmp_path, _grid(4))


def test_triangles_crossing_tile_edges_are_a_tiling_layout(tmp_path):
    """The red team's good gg03: a cube whose faces map 0..8, every triangle across many squares."""
    assert "OPBR1244" not in _codes(tmp_path, textured_cube(lambda uvs: [8 * c for c in uvs]))


def test_udim_tiles_name_the_tiles_in_the_message(tmp_path):
    from redteam_support import messages
    found = messages(_write(tmp_path / "asset.gltf", _islands([0, 1, 2])), "OPBR1244")
    assert len(found) == 1 and "1001, 1002, 1003" in found[0]


@pytest.mark.parametrize("offset, size, reported", [
    # float32's step at 2^k is 2^(k - 23): at 2^14 it is 2^-9, 0.5 texel of 256 pixels, 2 texels of 1024
    (16384.0, 256, False),
    (16384.0, 1024, True),
    # at 2^18 (the red team's gb06) 2^-5: 2 texels of 64 pixels
    (262144.0, 64, True),
    (262144.0, 16, False),
])
def test_uv_precision_is_judged_in_texels_of_the_texture_read(tmp_path, offset, size, reported):
    assert float(np.spacing(np.float32(offset))) == 2.0 ** (np.log2(offset) - 23)
    assert ("OPBR1245" in _codes(tmp_path, _shifted(offset, size))) == reported


def test_uv_precision_counts_the_texture_transform_scale(tmp_path):
    """KHR_texture_transform multiplies the coordinates by its scale before sampling: 0.5 texel x 4 = 2 texels."""
    content = _shifted(16384.0, 256)
    content["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"]["extensions"] = _TILED
    content["extensionsUsed"] = ["KHR_texture_transform"]
    assert "OPBR1245" in _codes(tmp_path, content)
