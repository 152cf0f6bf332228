"""A texture shared by many files of a batch run is decoded once, and a baked image that comes out
the same is encoded once (issue: textures shared by many materials are baked once per run)."""

from __future__ import annotations

import numpy as np
from PIL import Image

from openpbr_tools import bake, bake_cache
from openpbr_tools.batch import Job, convert_jobs

DOC = """<?xml version="1.0"?>
<materialx version="1.39" colorspace="lin_rec709">
  <image name="albedo" type="color3"><input name="file" type="filename" value="textures/shared.png" colorspace="srgb_texture" /></image>
  <open_pbr_surface name="S{i}" type="surfaceshader">
    <input name="base_color" type="color3" nodename="albedo" />
    <input name="coat_weight" type="float" value="0.7" />
    <input name="coat_color" type="color3" value="0.9, 0.8, 0.7" />
  </open_pbr_surface>
  <surfacematerial name="M{i}" type="material"><input name="surfaceshader" type="surfaceshader" nodename="S{i}" /></surfacematerial>
</materialx>
"""


def test_shared_texture_is_decoded_and_encoded_once_per_run(tmp_path, monkeypatch):
    (tmp_path / "in" / "textures").mkdir(parents=True)
    pixels = np.random.default_rng(0).integers(0, 256, size=(64, 64, 3), dtype=np.uint8)
    Image.fromarray(pixels).save(tmp_path / "in" / "textures" / "shared.png")
    for i in range(4):
        (tmp_path / "in" / f"m{i}.mtlx").write_text(DOC.format(i=i))
    monkeypatch.setattr(bake_cache, "RUN", bake_cache.RunCache())
    decodes, encodes = [], []
    real_load, real_encode = bake_cache.load_pixels, bake.Baker._encode
    monkeypatch.setattr(bake_cache, "load_pixels", lambda image, levels=False: decodes.append(image) or real_load(image, levels))
    monkeypatch.setattr(bake.Baker, "_encode", lambda self, *a: encodes.append(a[1]) or real_encode(self, *a))
    jobs = [Job(str(tmp_path / "in" / f"m{i}.mtlx"), str(tmp_path / "out" / f"m{i}.gltf")) for i in range(4)]
    results = convert_jobs(jobs)
    assert all(not r.unreadable for r in results)
    assert len([d for d in decodes if str(d).endswith("shared.png")]) == 1  # one decode for four files
    assert len(encodes) == len(set(encodes)) and len(encodes) <= 2  # base colour (and specular) once each
    baked = sorted((tmp_path / "out" / "textures").glob("*_base_color.png"))
    assert len(baked) == 4  # every output still gets its own copy
    assert len({p.read_bytes() for p in baked}) == 1  # and they are identical
