"""Red team session 21, set M: bounded resources and unreadable inputs.

M-12 a texture too large to decode is refused from its header (a 0.5 MB 13000 x 13000 PNG grew a conversion to
22.7 GB), and Pillow's warning about it never reaches stderr; M-13 a USDZ member is never inflated past a limit (a
1 MB zip bomb was embedded as a 1 GiB .glb); M-08 a batch's workers end with it (SIGTERM to the parent left them
writing outputs, then waiting forever); M-01..M-03 a texture that exists but cannot be read is a finding and a
note naming it, never a traceback or an error blamed on the output.
"""

from __future__ import annotations

import os
import shutil
import signal
import struct
import subprocess
import sys
import textwrap
import time
import zipfile
import zlib
from pathlib import Path

import pytest

from redteam_support import textured_preview

ROOT = Path(__file__).resolve().parents[1]
SAMPLES = ROOT / "openpbr_tools" / "samples"
ENVIRONMENT = {**os.environ, "PYTHONPATH": str(ROOT)}


def _chunk(kind: bytes, data: bytes) -> bytes:
    return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data))


def _blank_png(width: int, height: int) -> bytes:
    """A whole 1-bit greyscale PNG of ``width`` x ``height`` black pixels: a few kilobytes on disk for any size."""
    row = b"\x00" + bytes((width + 7) // 8)
    compressor = zlib.compressobj(9)
    data = b"".join(compressor.compress(row) for _ in range(height)) + compressor.flush()
    return (b"\x89PNG\r\n\x1a\n" + _chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 1, 0, 0, 0, 0))
            + _chunk(b"IDAT", data) + _chunk(b"IEND", b""))


def _wood(folder: Path, albedo: bytes | None = None) -> Path:
    """The sample textured_wood.mtlx and its textures in ``folder`` (its albedo replaced by ``albedo``)."""
    shutil.copytree(SAMPLES / "textures", folder / "textures")
    shutil.copy(SAMPLES / "textured_wood.mtlx", folder / "textured_wood.mtlx")
    if albedo is not None:
        (folder / "textures" / "wood_albedo.png").write_bytes(albedo)
    return folder / "textured_wood.mtlx"


def _capped(script: str, cwd: Path, limit: int = 2 << 30) -> subprocess.CompletedProcess:
    """``script`` in a new interpreter whose address space is capped at ``limit`` bytes: an image decoded whole
    fails there instead of taking the machine's memory."""
    prelude = f"import resource; resource.setrlimit(resource.RLIMIT_AS, ({limit}, {limit}))\n"
    return subprocess.run([sys.executable, "-c", prelude + textwrap.dedent(script)], capture_output=True, text=True,
                          cwd=cwd, env=ENVIRONMENT, timeout=300)


# -- M-12: one texel budget, checked from the header before decoding ---------------------------------------------

def test_an_image_above_the_texel_budget_is_refused_before_a_texel_is_decoded(tmp_path):
    """169 million pixels, under Pillow's error limit (179 MP), so Pillow only warned and decoded it: 4 GB of float
    texels per copy. Refused from its header now, in a process that could not hold one such copy."""
    from openpbr_tools.io.images import MAX_DECODED_TEXELS

    (tmp_path / "big.png").write_bytes(_blank_png(13000, 13000))
    assert 13000 * 13000 > MAX_DECODED_TEXELS
    done = _capped("""
        from openpbr_tools.io.images import ImageUndecodable, load_pixels
        try:
            load_pixels("big.png")
        except ImageUndecodable as error:
            print("refused:", error)
    """, tmp_path)
    assert "refused:" in done.stdout and "13000 x 13000" in done.stdout, done.stdout + done.stderr
    assert "DecompressionBombWarning" not in done.stderr  # the library never prints


def test_a_texture_above_the_texel_budget_is_a_note_at_its_material_and_input_not_a_bake(tmp_path):
    path = _wood(tmp_path, _blank_png(13000, 13000))
    done = _capped(f"""
        from openpbr_tools.convert import convert_file
        from openpbr_tools.translate.common import Settings
        conversion = convert_file({str(path)!r}, "out.glb", None, Settings())
        for d in conversion.diagnostics:
            print(d.code, d.location.material, d.location.input, d.message)
    """, tmp_path)
    assert done.returncode == 0, done.stderr
    refused = [line for line in done.stdout.splitlines() if "13000 x 13000" in line]
    assert refused and all(line.split()[1:3] == ["VarnishedWood_material", "base_color"] for line in refused), done.stdout
    assert "wood_albedo.png" in refused[0] and "Unable to allocate" not in done.stdout
    assert "DecompressionBombWarning" not in done.stderr


def test_an_image_within_the_texel_budget_is_still_decoded(tmp_path):
    from openpbr_tools.io.images import load_pixels

    (tmp_path / "small.png").write_bytes(_blank_png(64, 32))
    assert load_pixels(str(tmp_path / "small.png")).shape == (32, 64, 3)


# -- M-13: a USDZ member is never inflated past a limit ------------------------------------------------------------

def _bomb(path: Path, inflated: int) -> Path:
    """A USDZ whose texture ``t.png`` is a PNG signature and ``inflated`` zero bytes, deflated (a zip bomb)."""
    layer = textured_preview("t.png")
    member = zipfile.ZipInfo("t.png", (2000, 1, 1, 0, 0, 0))
    member.compress_type = zipfile.ZIP_DEFLATED
    with zipfile.ZipFile(path, "w") as package:
        package.writestr("root.usda", layer)
        with package.open(member, "w", force_zip64=True) as stream:
            stream.write(b"\x89PNG\r\n\x1a\n")
            for _ in range(inflated >> 20):
                stream.write(bytes(1 << 20))
    with zipfile.ZipFile(path) as package:
        assert package.getinfo("t.png").compress_size < inflated // 100
    return path


def test_a_packaged_member_inflating_a_hundredfold_is_refused_unread(tmp_path):
    from openpbr_tools.io import ReadError, packaged_image

    path = _bomb(tmp_path / "bomb.usdz", 16 << 20)
    with pytest.raises(ReadError, match="zip bomb"):
        packaged_image(str(path), "t.png")


def test_a_packaged_member_above_the_file_limit_is_refused_unread(tmp_path, monkeypatch):
    from openpbr_tools.io import ReadError, packaged_image

    path = tmp_path / "big.usdz"
    with zipfile.ZipFile(path, "w") as package:
        package.writestr("root.usda", "#usda 1.0\n")
        package.writestr("t.png", b"\x89PNG\r\n\x1a\n" + os.urandom(3 << 20))  # stored: no ratio to judge
    monkeypatch.setenv("OPENPBR_MAX_FILE_MB", "2")
    with pytest.raises(ReadError, match="OPENPBR_MAX_FILE_MB"):
        packaged_image(str(path), "t.png")


def test_a_zip_bomb_texture_is_not_embedded_in_a_converted_glb(tmp_path):
    from openpbr_tools.convert import convert_file
    from openpbr_tools.translate.common import Settings

    path = _bomb(tmp_path / "bomb.usdz", 96 << 20)
    conversion = convert_file(str(path), str(tmp_path / "out.glb"), None, Settings())
    assert (tmp_path / "out.glb").stat().st_size < 1 << 20  # was the whole inflated member
    assert any("'t.png'" in d.message and "not read" in d.message for d in conversion.diagnostics)


def test_a_small_packaged_texture_is_still_read(tmp_path):
    from openpbr_tools.io import packaged_image

    png = _blank_png(8, 8)
    path = tmp_path / "fine.usdz"
    with zipfile.ZipFile(path, "w") as package:
        package.writestr("root.usda", "#usda 1.0\n")
        package.writestr("t.png", png)
    assert packaged_image(str(path), "t.png") == (png, "image/png")


# -- M-08: a batch's workers end with it ---------------------------------------------------------------------------

def _children(pid: int) -> list[int]:
    """The live (not zombie) child processes of ``pid``, from /proc."""
    found = []
    for entry in os.listdir("/proc"):
        if entry.isdigit():
            try:
                fields = Path(f"/proc/{entry}/stat").read_text().rsplit(")", 1)[1].split()
            except OSError:
                continue
            if int(fields[1]) == pid and fields[0] != "Z":
                found.append(int(entry))
    return found


def _alive(pid: int) -> bool:
    try:
        return Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()[0] != "Z"
    except OSError:
        return False


def _tree(folder: Path) -> set[str]:
    return {str(p.relative_to(folder)) for p in folder.rglob("*") if p.is_file()} if folder.exists() else set()


def _interrupted(arguments, cwd: Path, outputs: Path, signum: int):
    """Start ``openpbr ARGUMENTS``, send ``signum`` once its two pool workers run, and return the ended process, its
    workers, the outputs at the signal and its stderr (the caller kills what is left of its process group)."""
    process = subprocess.Popen([sys.executable, "-m", "cli.main", *arguments], cwd=ROOT, env=ENVIRONMENT,
                               stdout=subprocess.PIPE, stderr=subprocess.PIPE, start_new_session=True)
    try:
        deadline = time.time() + 60
        while time.time() < deadline and len(_children(process.pid)) < 2 and process.poll() is None:
            time.sleep(0.05)
        workers = _children(process.pid)
        assert len(workers) >= 2, "the pool did not start"
        time.sleep(1.0)  # the workers are converting
        process.send_signal(signum)
        before = _tree(outputs)
        try:
            _, stderr = process.communicate(timeout=30)  # returns only once no process holds its pipes
        except subprocess.TimeoutExpired:
            raise AssertionError("the command's pipes stayed open: a worker outlived it") from None
    except BaseException:
        _kill_group(process)
        raise
    return process, workers, before, stderr.decode("utf-8", "replace")


def _kill_group(process) -> None:
    """Whatever is left of the command's process group (the workers of a failed run)."""
    try:
        os.killpg(process.pid, signal.SIGKILL)
    except ProcessLookupError:
        pass
    if process.poll() is None:
        process.wait()


def _slow_library(folder: Path, count: int) -> Path:
    """``count`` materials whose 1024 x 1024 noise textures take a conversion seconds to bake."""
    import numpy as np
    from PIL import Image

    noise = np.random.default_rng(0).integers(0, 255, (1024, 1024, 3), dtype=np.uint8)
    for index in range(count):
        _wood(folder / f"m{index}")
        for name in ("wood_albedo", "wood_orm", "wood_normal"):
            Image.fromarray(noise).save(folder / f"m{index}" / "textures" / f"{name}.png", compress_level=1)
    return folder


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="reads /proc")
@pytest.mark.parametrize("signum", [signal.SIGTERM, signal.SIGINT], ids=["SIGTERM", "SIGINT"])
def test_a_signalled_batch_convert_leaves_no_worker_and_writes_nothing_after(tmp_path, signum):
    source, outputs = _slow_library(tmp_path / "in", 6), tmp_path / "out"
    process, workers, before, stderr = _interrupted(
        ["convert", str(source), "-o", str(outputs), "--output-format", "glb", "-j", "2", "--no-progress"],
        tmp_path, outputs, signum)
    try:
        assert process.returncode != 0 and "Traceback" not in stderr, stderr
        deadline = time.time() + 5
        while time.time() < deadline and any(_alive(pid) for pid in workers):
            time.sleep(0.1)
        assert not any(_alive(pid) for pid in workers), "a worker outlived the command"
        time.sleep(3)  # a surviving worker wrote its output seconds later
        assert _tree(outputs) == before, "written after the signal"
        assert not any(name.endswith(".tmp") for name in _tree(outputs))
    finally:
        _kill_group(process)


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="reads /proc")
def test_a_terminated_batch_validate_leaves_no_worker(tmp_path):
    from openpbr_tools.validate import POOL_THRESHOLD

    source = _slow_library(tmp_path / "in", 1)
    for index in range(1, 3 * POOL_THRESHOLD):
        shutil.copytree(source / "m0", source / f"m{index}")
    process, workers, _, stderr = _interrupted(["validate", str(source), "-j", "2"], tmp_path, tmp_path / "none",
                                               signal.SIGTERM)
    try:
        assert process.returncode != 0 and "Traceback" not in stderr, stderr
        deadline = time.time() + 5
        while time.time() < deadline and any(_alive(pid) for pid in workers):
            time.sleep(0.1)
        assert not any(_alive(pid) for pid in workers), "a worker outlived the command"
    finally:
        _kill_group(process)


# -- M-01..M-03: a texture that exists but cannot be read ----------------------------------------------------------

SETPRIV = ["setpriv", "--bounding-set", "-dac_override,-dac_read_search", "--inh-caps", "-dac_override,-dac_read_search"]


def _unprivileged(*arguments, cwd: Path) -> subprocess.CompletedProcess:
    """``openpbr ARGUMENTS`` as root without the capabilities that let root read any file."""
    return subprocess.run([*SETPRIV, sys.executable, "-m", "cli.main", *map(str, arguments)], capture_output=True,
                          text=True, cwd=ROOT, env=ENVIRONMENT, timeout=300)


@pytest.fixture
def unreadable_texture(tmp_path):
    if not hasattr(os, "geteuid") or os.geteuid() != 0 or shutil.which("setpriv") is None:
        pytest.skip("needs root and setpriv to make a file unreadable to the process (root reads any file)")
    path = _wood(tmp_path / "asset")
    texture = tmp_path / "asset" / "textures" / "wood_albedo.png"
    texture.chmod(0)
    probe = subprocess.run([*SETPRIV, "cat", str(texture)], capture_output=True)
    if probe.returncode == 0:
        pytest.skip("setpriv could not drop CAP_DAC_OVERRIDE here")
    yield path
    texture.chmod(0o644)


def test_validate_reports_an_unreadable_texture_as_opbr707(unreadable_texture):
    done = _unprivileged("validate", unreadable_texture, cwd=unreadable_texture.parent)
    assert done.returncode == 1, done.stdout + done.stderr
    assert "OPBR707" in done.stdout and "wood_albedo.png" in done.stdout and "Permission denied" in done.stdout


@pytest.mark.parametrize("suffix", [".usda", ".usdz", ".glb"])
def test_convert_names_the_unreadable_texture_not_the_output(unreadable_texture, suffix):
    output = unreadable_texture.parent.parent / f"out{suffix}"
    done = _unprivileged("convert", unreadable_texture, "-o", output, cwd=unreadable_texture.parent)
    assert "cannot write" not in done.stderr and "Traceback" not in done.stderr, done.stderr
    assert done.returncode in (0, 1) and output.exists(), done.stdout + done.stderr
    assert any("wood_albedo.png" in line and "Permission denied" in line for line in done.stdout.splitlines())


@pytest.mark.parametrize("command", ["preview", "compare"])
def test_preview_and_compare_leave_an_unreadable_texture_out_without_a_traceback(unreadable_texture, command):
    arguments = (["-o", unreadable_texture.parent.parent / "p.png"] if command == "preview"
                 else [SAMPLES / "textured_wood.mtlx"])
    done = _unprivileged(command, unreadable_texture, *arguments, cwd=unreadable_texture.parent)
    assert "Traceback" not in done.stderr and done.returncode == 0, done.stderr
    assert "wood_albedo.png" in done.stdout + done.stderr and "Permission denied" in done.stdout + done.stderr


_DROPPED_STOP = textwrap.dedent("""
    import os, signal, sys, weakref
    from openpbr_tools import atomic, workers

    workers._in_task = True  # inside a task, as run_task sets it
    signal.signal(signal.SIGTERM, workers._on_terminate)
    sys.unraisablehook = workers._unraisable

    class Held:
        pass

    def callback(_):  # Python drops what a weakref callback raises, as it does in importlib's module-lock cb
        os.kill(os.getpid(), signal.SIGTERM)
        for _ in range(1000):  # the handler runs here, between bytecodes, and its Stopped is dropped
            pass

    held = Held()
    reference = weakref.ref(held, callback)
    del held
    try:
        atomic.write_bytes(sys.argv[1], b"written after the stop")
    except workers.Stopped:
        print("stopped")
""")


def test_a_stop_python_drops_still_writes_nothing_and_prints_no_traceback(tmp_path):
    """The SIGINT/SIGTERM race of the test above (two clean-clone CI runs of session 26): SIGTERM landed in
    importlib's module-lock callback, where Python drops exceptions and prints "Exception ignored ... Traceback ...
    Stopped", and the task went on. The dropped stop is now remembered: nothing printed, and the next rename into
    place (the atomic writer) raises it again, so nothing is written."""
    target = tmp_path / "out.txt"
    result = subprocess.run([sys.executable, "-c", _DROPPED_STOP, str(target)], capture_output=True, text=True,
                            cwd=ROOT, env=ENVIRONMENT, timeout=120)
    assert result.stdout.strip() == "stopped", (result.stdout, result.stderr)
    assert "Traceback" not in result.stderr and "Exception ignored" not in result.stderr, result.stderr
    assert not target.exists() and not [p for p in tmp_path.iterdir() if p.name.endswith(".tmp")]
