"""The proof that per-texel verification sees texture mistakes: a textured OpenPBR material (sRGB
base colour, an occlusion/roughness/metalness packed texture, a tangent-space normal map, a
rotated and scaled UV transform) is converted to .gltf, .glb, .usdz and a Standard Surface .mtlx;
verification of each correct output passes (mean CIEDE2000 of the worse view below the default
threshold, 2), and after each of six corruptions of the written output it fails:

* the packed texture's G and B channels swapped (roughness <-> metalness);
* the roughness channel decoded as if it were sRGB;
* V flipped (every image upside down);
* the normal map dropped;
* the UV transform applied twice;
* every image at half resolution.

Image corruptions rewrite the output's images (read through the output's own path rules, written
beside it); the others edit the materials read back from the output.
"""

from __future__ import annotations

import dataclasses
import math
import os

import numpy as np
import pytest
from PIL import Image

from openpbr_tools.bake import Baker
from openpbr_tools.convert import convert_file, display_name
from openpbr_tools.verification import compare
from openpbr_tools.evaluate.textures import TextureSampler
from openpbr_tools.evaluate.verify import compare_materials
from openpbr_tools.io import read_asset
from openpbr_tools.model import UVTransform
from openpbr_tools.translate.common import Settings

THRESHOLD = 2.0
ROUGHNESS = ("specular_roughness", "roughness")
NORMALS = ("geometry_normal", "normal")


def _textures(folder):
    rng = np.random.default_rng(7)
    n = 64
    blocks = rng.integers(30, 230, size=(8, 8, 3))
    base = np.kron(blocks, np.ones((8, 8, 1))) + rng.integers(-25, 25, size=(n, n, 3))
    base[: n // 4] = base[: n // 4] * [1.0, 0.4, 0.3]  # a red band at the top: V matters
    Image.fromarray(np.clip(base, 0, 255).astype(np.uint8)).save(folder / "base.png")
    orm = np.zeros((n, n, 3))
    orm[..., 0] = 255
    orm[..., 1] = np.kron(rng.uniform(0.15, 0.9, size=(8, 8)), np.ones((8, 8))) * 255 + rng.integers(-20, 20, size=(n, n))
    orm[..., 2] = np.kron(rng.integers(0, 2, size=(4, 4)), np.ones((16, 16))) * 255
    Image.fromarray(np.clip(orm, 0, 255).astype(np.uint8)).save(folder / "orm.png")
    tilt = np.kron(rng.uniform(-0.8, 0.8, size=(8, 8, 2)), np.ones((8, 8, 1)))
    normal = np.concatenate([tilt, np.sqrt(np.clip(1 - (tilt ** 2).sum(-1, keepdims=True), 0.05, 1))], axis=-1)
    Image.fromarray(np.round((normal * 0.5 + 0.5) * 255).astype(np.uint8)).save(folder / "normal.png")


SOURCE = """<?xml version="1.0"?>
<materialx version="1.39" colorspace="lin_rec709">
  <place2d name="uv" type="vector2">
    <input name="scale" type="vector2" value="0.8, 0.8" />
    <input name="rotate" type="float" value="30" />
    <input name="offset" type="vector2" value="0.1, 0.05" />
  </place2d>
  <image name="base_img" type="color3">
    <input name="file" type="filename" value="base.png" colorspace="srgb_texture" />
    <input name="texcoord" type="vector2" nodename="uv" />
  </image>
  <image name="orm_img" type="color3">
    <input name="file" type="filename" value="orm.png" colorspace="none" />
    <input name="texcoord" type="vector2" nodename="uv" />
  </image>
  <extract name="rough" type="float"><input name="in" type="color3" nodename="orm_img" /><input name="index" type="integer" value="1" /></extract>
  <extract name="metal" type="float"><input name="in" type="color3" nodename="orm_img" /><input name="index" type="integer" value="2" /></extract>
  <image name="normal_img" type="vector3">
    <input name="file" type="filename" value="normal.png" colorspace="none" />
    <input name="texcoord" type="vector2" nodename="uv" />
  </image>
  <normalmap name="nmap" type="vector3"><input name="in" type="vector3" nodename="normal_img" /></normalmap>
  <open_pbr_surface name="Tiles" type="surfaceshader">
    <input name="base_color" type="color3" nodename="base_img" />
    <input name="specular_roughness" type="float" nodename="rough" />
    <input name="base_metalness" type="float" nodename="metal" />
    <input name="geometry_normal" type="vector3" nodename="nmap" />
  </open_pbr_surface>
  <surfacematerial name="Tiles_material" type="material">
    <input name="surfaceshader" type="surfaceshader" nodename="Tiles" />
  </surfacematerial>
</materialx>
"""

OUTPUTS = {"gltf": ("out.gltf", None), "glb": ("out.glb", None), "usdz": ("out.usdz", None),
           "mtlx-standard-surface": ("out.mtlx", "standard_surface")}


@pytest.fixture(scope="module")
def converted(tmp_path_factory):
    source_folder = tmp_path_factory.mktemp("source")
    _textures(source_folder)
    (source_folder / "tiles.mtlx").write_text(SOURCE)
    found = {}
    for key, (name, target) in OUTPUTS.items():
        out_folder = tmp_path_factory.mktemp(key)
        conversion = convert_file(str(source_folder / "tiles.mtlx"), str(out_folder / name), target, Settings())
        found[key] = conversion
    return found


def _output_sampler(conversion):
    import tempfile

    source_folder = os.path.dirname(conversion.asset.path)
    return TextureSampler([Baker(conversion.output, tempfile.gettempdir(), (source_folder,))])


def _written(conversion):
    """The materials the output holds for its one source material (a USD output: the OpenPBR
    shader and its UsdPreviewSurface fallback)."""
    back = read_asset(conversion.output)
    name = display_name(conversion.pairs[0][1])
    return [m for m in back.materials if display_name(m) == name]


def _source_sampler(conversion):
    return TextureSampler.for_asset(conversion.asset.path)


@pytest.mark.parametrize("output", sorted(OUTPUTS))
def test_correct_conversion_passes(converted, output):
    conversion = converted[output]
    comparisons = compare(conversion)
    assert comparisons and all(c.swatch is not None for _, c in comparisons)  # textured: the swatch is compared
    for _, comparison in comparisons:
        assert not any("not evaluated" in note for note in comparison.notes), comparison.notes
        if comparison.model_b == "UsdPreviewSurface":
            # The USD output's fallback: its textures line up texel for texel (swatch), but its metal
            # lobe under the tilted normals misses OpenPBR's highlights on the sphere (mean 3.3,
            # reported by --verify as OPBR1109): a fidelity limit of the preview surface, not of the
            # textures. The primary OpenPBR shader is held to the threshold below.
            assert comparison.swatch.mean < THRESHOLD, (output, comparison.swatch)
            continue
        assert comparison.worst.mean < THRESHOLD, (output, comparison.name_b, comparison.preview, comparison.swatch)


# -- corruptions ----------------------------------------------------------------------------------
def _rewrite_images(material, conversion, folder, edit, only=None):
    """``material`` with each texture (or those of the parameters in ``only``) replaced by an edited
    copy of its image written into ``folder`` (the output's): ``edit(pixels, texture, name)``."""
    reader = Baker(conversion.output, folder, (os.path.dirname(conversion.asset.path),))
    inputs = dict(material.inputs)
    done = {}
    for name, entry in material.inputs.items():
        texture = entry.texture
        if texture is None or (only is not None and name not in only):
            continue
        key = (texture.file, texture.packaged)
        if key not in done:
            pixels = reader._load(texture, f"{material.name}.{name}")
            edited = np.clip(edit(np.array(pixels), texture, name), 0.0, 1.0)
            path = os.path.join(folder, f"corrupt_{len(done)}_{os.path.basename(texture.file).replace('#', '')}.png")
            Image.fromarray(np.round(edited[..., :4] * 255).astype(np.uint8)).save(path)
            done[key] = path
        inputs[name] = dataclasses.replace(entry, value=dataclasses.replace(texture, file=done[key], packaged=False))
    return dataclasses.replace(material, inputs=inputs)


def swap_gb(material, conversion, folder):
    def edit(pixels, texture, name):
        pixels[..., [1, 2]] = pixels[..., [2, 1]]
        return pixels
    packed = [n for n, t in material.textures() if t.channels in ((1,), (2,))]
    assert packed, "the output has no packed texture"
    return _rewrite_images(material, conversion, folder, edit, only=packed)


def roughness_as_srgb(material, conversion, folder):
    def edit(pixels, texture, name):
        channel = texture.channels[0] if texture.channels else 0
        c = pixels[..., channel]
        pixels[..., channel] = np.where(c <= 0.04045, c / 12.92, ((c + 0.055) / 1.055) ** 2.4)  # IEC 61966-2-1
        return pixels
    return _rewrite_images(material, conversion, folder, edit, only=[n for n in ROUGHNESS if n in material.inputs])


def flip_v(material, conversion, folder):
    return _rewrite_images(material, conversion, folder, lambda p, t, n: p[::-1].copy())


def half_resolution(material, conversion, folder):
    def edit(pixels, texture, name):
        h, w = pixels.shape[:2]
        image = Image.fromarray(np.round(np.clip(pixels, 0, 1) * 255).astype(np.uint8)[..., : min(4, pixels.shape[2])])
        return np.asarray(image.resize((w // 2, h // 2), Image.BILINEAR), dtype=float) / 255.0
    return _rewrite_images(material, conversion, folder, edit)


def drop_normal_map(material, conversion, folder):
    names = [n for n in NORMALS if n in material.inputs]
    assert names, "the output has no normal map"
    return dataclasses.replace(material, inputs={k: v for k, v in material.inputs.items() if k not in names})


def uv_twice(material, conversion, folder):
    """place2d T(uv) = M (uv - p) - o + p with M = R(rotate) / scale; T(T(uv)) = M^2 (uv - p) - M o - o
    + p: with a uniform scale, place2d(scale^2, 2 rotate, offset o + M o, pivot p)."""
    inputs = dict(material.inputs)
    changed = 0
    for name, entry in material.inputs.items():
        texture = entry.texture
        if texture is None or texture.uv is None:
            continue
        t = texture.uv
        assert abs(t.scale[0] - t.scale[1]) < 1e-9
        angle = math.radians(t.rotate)
        c, s = math.cos(angle), math.sin(angle)
        m = np.array([[c, s], [-s, c]]) / t.scale[0]
        mo = m @ np.asarray(t.offset)
        twice = UVTransform(scale=(t.scale[0] ** 2, t.scale[1] ** 2), rotate=2 * t.rotate,
                            offset=(t.offset[0] + mo[0], t.offset[1] + mo[1]), pivot=t.pivot)
        inputs[name] = dataclasses.replace(entry, value=dataclasses.replace(texture, uv=twice))
        changed += 1
    assert changed, "the output has no UV transform"
    return dataclasses.replace(material, inputs=inputs)


CORRUPTIONS = {"swap-gb": swap_gb, "roughness-as-srgb": roughness_as_srgb, "flip-v": flip_v,
               "drop-normal-map": drop_normal_map, "uv-transform-twice": uv_twice, "half-resolution": half_resolution}


@pytest.mark.parametrize("corruption", sorted(CORRUPTIONS))
@pytest.mark.parametrize("output", sorted(OUTPUTS))
def test_every_corruption_is_flagged(converted, output, corruption, tmp_path):
    conversion = converted[output]
    source = conversion.pairs[0][0]
    folder = os.path.dirname(conversion.output)
    for written in _written(conversion):
        if corruption == "roughness-as-srgb" and not any(n in written.inputs for n in ROUGHNESS):
            continue
        corrupted = CORRUPTIONS[corruption](written, conversion, folder)
        comparison = compare_materials(source, corrupted, sampler=_source_sampler(conversion),
                                       sampler_b=_output_sampler(conversion))
        assert not any("not evaluated" in note for note in comparison.notes), comparison.notes
        assert comparison.worst.mean > THRESHOLD, (output, written.model, corruption, comparison.preview, comparison.swatch)


def test_compare_cli_flags_a_corrupted_gltf_on_disk(converted, tmp_path):
    """End to end: the packed texture of the written .gltf swapped in place; `openpbr compare`
    with the default metric exits 1 at threshold 2, and 0 on the intact output."""
    import shutil

    from click.testing import CliRunner

    from cli.group import cli

    conversion = converted["gltf"]
    copy = tmp_path / "copy"
    shutil.copytree(os.path.dirname(conversion.output), copy)
    output = copy / os.path.basename(conversion.output)
    source = conversion.asset.path
    intact = CliRunner().invoke(cli, ["compare", source, str(output), "--threshold", "2"])
    assert intact.exit_code == 0, intact.output
    material = read_asset(str(output)).materials[0]
    packed = {t.file for _, t in material.textures() if t.channels in ((1,), (2,))}
    assert len(packed) == 1
    path = copy / packed.pop()
    pixels = np.array(Image.open(path))
    pixels[..., [1, 2]] = pixels[..., [2, 1]]
    Image.fromarray(pixels).save(path)
    broken = CliRunner().invoke(cli, ["compare", source, str(output), "--threshold", "2"])
    assert broken.exit_code == 1, broken.output
    assert "FAIL" in broken.output
