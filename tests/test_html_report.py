"""The visual HTML report of ``convert --report`` and ``compare --report``: self-contained, readable
without JavaScript, and shown by a real browser (headless Chromium renders it to a PNG, in which the
embedded previews and the heat-map legend must appear)."""

from __future__ import annotations

import base64
import io
import re
import shutil
import subprocess

import numpy as np
import pytest
from click.testing import CliRunner
from PIL import Image

from cli.group import cli
from openpbr_tools.resources import data_dir

WOOD = str(data_dir("samples") / "textured_wood.mtlx")


def _report(tmp_path):
    out = tmp_path / "report.html"
    result = CliRunner().invoke(cli, ["convert", WOOD, "-o", str(tmp_path / "wood.gltf"), "--report", str(out),
                                      "--delta-e-images", str(tmp_path / "images")])
    assert result.exit_code == 0, result.output
    return out.read_text(encoding="utf-8")


def test_report_is_self_contained_without_scripts(tmp_path):
    page = _report(tmp_path)
    assert "<script" not in page.lower()
    sources = re.findall(r'(?:src|href)="([^"]*)"', page)
    assert sources and all(s.startswith(("data:image/png;base64,", "#")) for s in sources), sources
    images = [s for s in sources if s.startswith("data:")]
    assert len(images) >= 7  # legend + original, converted, ΔE on the sphere and on the swatch
    for uri in images:
        Image.open(io.BytesIO(base64.b64decode(uri.split(",", 1)[1]))).verify()
    assert 'id="summary"' in page and "VarnishedWood" in page
    assert re.search(r"<td>\d+\.\d\d</td>", page)  # the numbers
    assert "OPBR1103" in page  # the loss report, grouped by severity
    assert page.index("Warnings (") < page.index("Infos (")
    strips = sorted(p.name for p in (tmp_path / "images").iterdir())
    assert strips == ["VarnishedWood_material_sphere.png", "VarnishedWood_material_sphere_delta_e.png",
                      "VarnishedWood_material_swatch.png", "VarnishedWood_material_swatch_delta_e.png"]
    with Image.open(tmp_path / "images" / "VarnishedWood_material_sphere.png") as side, \
            Image.open(tmp_path / "images" / "VarnishedWood_material_sphere_delta_e.png") as heat:
        assert side.size == (2 * heat.size[0] + 4, heat.size[1])


def test_report_is_deterministic(tmp_path):
    (tmp_path / "a").mkdir()
    (tmp_path / "b").mkdir()
    assert _report(tmp_path / "a") == _report(tmp_path / "b")


def test_chromium_shows_the_images_and_the_table(tmp_path):
    browser = shutil.which("chromium") or shutil.which("chromium-browser")
    if browser is None:
        pytest.skip("headless Chromium is not installed (Debian package chromium; .ci/run installs it)")
    page = _report(tmp_path)
    shot = tmp_path / "shot.png"
    subprocess.run([browser, "--headless", "--no-sandbox", "--disable-gpu", "--disable-javascript",
                    "--hide-scrollbars", f"--screenshot={shot}", "--window-size=1000,1600",
                    (tmp_path / "report.html").as_uri()], check=True, capture_output=True, timeout=120)
    pixels = np.asarray(Image.open(shot).convert("RGB")).reshape(-1, 3).astype(int)
    # The converted sphere's centre colour (decoded from the page's own embedded image) is on screen.
    uri = re.findall(r'src="data:image/png;base64,([^"]+)" alt="converted \(sphere\)"', page)[0]
    preview = np.asarray(Image.open(io.BytesIO(base64.b64decode(uri))).convert("RGB")).astype(int)
    centre = preview[preview.shape[0] // 2 + 10, preview.shape[1] // 2 + 10]
    assert np.any(np.abs(pixels - centre).max(axis=1) <= 3), centre
    # The heat-map legend's red stop (ΔE 10: 220, 40, 30) is on screen.
    assert np.any(np.abs(pixels - [220, 40, 30]).max(axis=1) <= 6)
    # The table was laid out: its header background (#eee) covers a band of pixels.
    assert np.sum(np.all(pixels == [238, 238, 238], axis=1)) > 2000
    dom = subprocess.run([browser, "--headless", "--no-sandbox", "--disable-gpu", "--disable-javascript",
                          "--dump-dom", (tmp_path / "report.html").as_uri()], check=True, capture_output=True,
                         timeout=120, text=True).stdout
    assert dom.count("<tr") >= 5 and "sphere" in dom
