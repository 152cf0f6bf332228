"""Shared fixtures: writing small MaterialX documents and running the validator on them."""

from __future__ import annotations

import os
import sys
import tempfile
from pathlib import Path

import pytest

sys.path.insert(0, os.path.dirname(__file__))

DOCUMENT = """<?xml version="1.0"?>
<materialx version="1.39" colorspace="lin_rec709">
{body}
  <surfacematerial name="M" type="material">
    <input name="surfaceshader" type="surfaceshader" nodename="S" />
  </surfacematerial>
</materialx>
"""


# The MaterialX library index (openpbr_tools.io.mtlx.library) is cached per run, not in the home folder.
os.environ.setdefault("OPENPBR_CACHE_DIR", tempfile.mkdtemp(prefix="openpbr-test-cache-"))


def document(fragment: str) -> str:
    """Place a MaterialX fragment in a lin_rec709 document with a material M bound to shader S;
    a fragment that is already a whole document is returned unchanged."""
    if fragment.lstrip().startswith(("<?xml", "<materialx")):
        return fragment
    body = "\n".join("  " + line for line in fragment.splitlines())
    return DOCUMENT.format(body=body)


@pytest.fixture(autouse=True)
def internal_errors_raise(request, monkeypatch):
    """In the test suite a defect of the toolkit fails the test that meets it: the OPBR011 safety net (which
    turns an exception on one file into a finding, so users keep the rest of their report) re-raises here,
    in worker processes too (an environment variable), or fuzzing and every other test would pass over a
    defect. Tests of the net itself are marked ``internal_errors_reported``."""
    from openpbr_tools.rules.document import RAISE_INTERNAL_ERRORS

    if request.node.get_closest_marker("internal_errors_reported"):
        monkeypatch.delenv(RAISE_INTERNAL_ERRORS, raising=False)
    else:
        monkeypatch.setenv(RAISE_INTERNAL_ERRORS, "1")


def example_image(name: str) -> bytes:
    """A 4 x 4 RGB image in the format ``name``'s suffix names (Pillow; OpenImageIO for EXR and HDR); a PNG mask
    (``mask`` in its name) RGBA, its mask in the alpha channel."""
    import io

    from PIL import Image

    suffix = os.path.splitext(name)[1].lower()
    if suffix in (".exr", ".hdr"):
        import OpenImageIO as oiio

        folder = tempfile.mkdtemp(prefix="openpbr-example-image-")
        path = os.path.join(folder, "image" + suffix)
        buffer = oiio.ImageBuf(oiio.ImageSpec(4, 4, 3, oiio.HALF if suffix == ".exr" else oiio.FLOAT))
        oiio.ImageBufAlgo.fill(buffer, (0.5, 0.25, 0.125))
        assert buffer.write(path), oiio.geterror()
        with open(path, "rb") as handle:
            return handle.read()
    buffer = io.BytesIO()
    colour = (128, 128, 255) if "normal" in os.path.basename(name).lower() else (200, 120, 40)  # a flat normal map
    if "mask" in os.path.basename(name).lower() and suffix == ".png":  # a cut-out mask: in its alpha channel
        Image.new("RGBA", (4, 4), colour + (255,)).save(buffer, format="PNG")
        return buffer.getvalue()
    Image.new("RGB", (4, 4), colour).save(buffer, format=Image.registered_extensions().get(suffix, "PNG"))
    return buffer.getvalue()


@pytest.fixture
def write_mtlx(tmp_path: Path):
    """write_mtlx(fragment, name="doc.mtlx", files=(), config="", contents=()) -> path; creates the listed
    texture files as small valid images of their suffix's format (:func:`example_image`), or with the
    bytes ``contents`` gives for their name."""

    def write(fragment: str | bytes, name: str = "doc.mtlx", files=(), config: str = "", contents=()) -> Path:
        path = tmp_path / name
        if config:
            (tmp_path / ".openpbr.toml").write_text(config, encoding="utf-8")
        path.parent.mkdir(parents=True, exist_ok=True)
        if isinstance(fragment, bytes):
            path.write_bytes(fragment)
        elif name.endswith(".mtlx"):
            path.write_text(document(fragment), encoding="utf-8")
        else:
            path.write_text(fragment, encoding="utf-8")
        for file in files:
            target = tmp_path / file
            target.parent.mkdir(parents=True, exist_ok=True)
            data = dict(contents).get(file)
            target.write_bytes(example_image(file) if data is None else data)
        return path

    return write


@pytest.fixture
def codes_of():
    """codes_of(path) -> list of rule codes the validator reports for the file, with the project
    configuration found beside it (as `openpbr validate` runs)."""
    from openpbr_tools.validate import validate_paths

    def run(path) -> list[str]:
        return [d.code for d in validate_paths([str(path)]).diagnostics]

    return run
