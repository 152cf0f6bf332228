"""The one path guard (openpbr_tools.io.paths), fed hostile references from a table.

Every row states what the security policy demands (not what the code happened to answer): the
reference's kind, by its form alone, and whether it names a file inside the asset's folder (or a
folder the user allowed with --allow-outside). URLs, NUL paths and empty paths name no file; drive
and UNC paths name nothing on a POSIX system; ``..`` that leaves the folder, symbolic links out and
symbolic-link loops are outside; ``~`` and ``%VAR%`` are never expanded (they are plain names).

The layout built in ``tmp_path`` (placeholders in the table in capitals)::

    b/              ROOT: the asset's folder
      a.png, sub/x.png
      file_link     -> ../secret/private.png   (a symbolic link out, to a file)
      dir_link      -> ../secret               (a symbolic link out, to a folder)
      deep_link     -> ../secret/deep          (deep_link/../private.png is secret/private.png)
      in_link       -> sub                     (a symbolic link that stays inside)
      abs_in_link   -> ROOT/sub                (absolute, stays inside)
      loop          -> loop                    (a loop)
      ping          -> ../pong, ../pong -> b/ping   (a loop through a folder outside)
    bc/             SIBLING: a folder whose name extends the root's
    secret/private.png, secret/deep/
    shared/         ALLOWED: a folder allowed with --allow-outside
    sharedx/        ALLOWED_SIBLING
"""

from __future__ import annotations

import os

import pytest

from openpbr_tools.io import paths
from openpbr_tools.io.paths import Kind, PathGuard, classify, climbs, is_url

R, A, D, U, URL, NUL, E = Kind.RELATIVE, Kind.ABSOLUTE, Kind.DRIVE, Kind.UNC, Kind.URL, Kind.NUL, Kind.EMPTY
IN, OUT = True, False

# (id, reference, kind, inside)
HOSTILE = [
    # controls
    ("plain", "a.png", R, IN),
    ("subfolder", "sub/x.png", R, IN),
    ("dot-slash", "./a.png", R, IN),
    ("climbs-and-returns", "a/../a.png", R, IN),
    ("climbs-out-and-back-in", "../b/a.png", R, IN),
    # ..
    ("dot-dot", "../a.png", R, OUT),
    ("dot-dot-nested", "a/../../b.png", R, OUT),
    ("dot-dot-backslash", "..\\a.png", R, OUT),
    ("dot-dot-backslash-nested", "sub\\..\\..\\secret\\private.png", R, OUT),
    ("dot-slash-dot-dot", "./../a", R, OUT),
    ("dot-dot-many", "../" * 50 + "etc/passwd", R, OUT),
    ("dot-dot-after-fragment", "#/../../etc/passwd", R, OUT),
    # absolute
    ("absolute-posix", "/etc/passwd", A, OUT),
    ("absolute-inside", "ROOT/a.png", A, IN),
    ("absolute-inside-climbing-out", "ROOT/../secret/private.png", A, OUT),
    ("absolute-backslash", "\\etc\\passwd", A, OUT),
    # Windows drives and network paths
    ("drive-backslash", "C:\\x", D, OUT),
    ("drive-slash-lowercase", "c:/x", D, OUT),
    ("drive-relative", "C:x", D, OUT),
    ("single-letter-scheme", "a:b", D, OUT),
    ("unc-backslash", "\\\\server\\share\\x", U, OUT),
    ("unc-slash", "//server/share/x", U, OUT),
    ("unc-mixed", "/\\server\\share\\x", U, OUT),
    ("unc-extended-length", "\\\\?\\C:\\x", U, OUT),
    # URLs: never fetched, never a file
    ("file-url", "file:///etc/passwd", URL, OUT),
    ("file-relative-url", "file:a.png", URL, OUT),
    ("http", "http://x/a.png", URL, OUT),
    ("http-uppercase", "HTTP://X/A.PNG", URL, OUT),
    ("https-without-slashes", "https:a", URL, OUT),
    ("data", "data:image/png;base64,iVBORw0KGgoAAAANSUhEUg==", URL, OUT),
    ("two-letter-scheme", "ab:c", URL, OUT),
    # NUL: no file system takes it
    ("nul", "a\x00.png", NUL, OUT),
    ("nul-after-dot-dot", "../\x00", NUL, OUT),
    ("nul-absolute", "/etc/passwd\x00.png", NUL, OUT),
    # very long, non-UTF-8
    ("very-long", "a/" * 2498 + "x.png", R, IN),
    ("very-long-climbing", "../" * 1667, R, OUT),
    ("long-component", "a" * 300 + ".png", R, IN),
    ("non-utf8", os.fsdecode(b"\xff\xfe.png"), R, IN),
    ("non-utf8-climbing", os.fsdecode(b"../\xff\xfe.png"), R, OUT),
    # symbolic links
    ("symlink-out-file", "file_link", R, OUT),
    ("symlink-out-folder", "dir_link/private.png", R, OUT),
    ("symlink-then-dot-dot", "deep_link/../private.png", R, OUT),
    ("symlink-inside", "in_link/x.png", R, IN),
    ("symlink-inside-absolute-target", "abs_in_link/x.png", R, IN),
    ("symlink-loop", "loop", R, OUT),
    ("symlink-loop-below", "loop/x.png", R, OUT),
    ("symlink-loop-through-outside", "ping", R, OUT),
    # a sibling whose name extends the root's (/a/bc is not inside /a/b)
    ("sibling-extending-name", "../bc/a.png", R, OUT),
    ("sibling-extending-name-absolute", "SIBLING/a.png", A, OUT),
    # --allow-outside
    ("allowed-folder", "ALLOWED/a.png", A, IN),
    ("allowed-folder-relative", "../shared/a.png", R, IN),
    ("allowed-folder-sibling", "ALLOWED_SIBLING/a.png", A, OUT),
    # empty
    ("empty", "", E, OUT),
    ("space", " ", E, OUT),
    ("whitespace", "\t\r\n", E, OUT),
    # never expanded: plain names inside the folder
    ("tilde", "~/x", R, IN),
    ("percent-variable", "%TEMP%\\x", R, IN),
    ("dollar-variable", "$HOME/x", R, IN),
    ("query", "a.png?x=1", R, IN),
    ("fragment", "a.png#frag", R, IN),
    ("udim", "a.<UDIM>.png", R, IN),
]


@pytest.fixture
def layout(tmp_path):
    root = tmp_path / "b"
    (root / "sub").mkdir(parents=True)
    (root / "a.png").write_bytes(b"png")
    (root / "sub" / "x.png").write_bytes(b"png")
    (tmp_path / "bc").mkdir()
    (tmp_path / "secret" / "deep").mkdir(parents=True)
    (tmp_path / "secret" / "private.png").write_bytes(b"secret")
    (tmp_path / "shared").mkdir()
    (tmp_path / "sharedx").mkdir()
    os.symlink("../secret/private.png", root / "file_link")
    os.symlink("../secret", root / "dir_link")
    os.symlink("../secret/deep", root / "deep_link")
    os.symlink("sub", root / "in_link")
    os.symlink(root / "sub", root / "abs_in_link")
    os.symlink("loop", root / "loop")
    os.symlink("../pong", root / "ping")
    os.symlink(root / "ping", tmp_path / "pong")
    return {"ROOT": str(root), "SIBLING": str(tmp_path / "bc"), "ALLOWED_SIBLING": str(tmp_path / "sharedx"),
            "ALLOWED": str(tmp_path / "shared")}


def fill(reference: str, layout: dict) -> str:
    for name in sorted(layout, key=len, reverse=True):  # ALLOWED_SIBLING before ALLOWED
        reference = reference.replace(name, layout[name])
    return reference


def test_the_table_is_large_enough():
    assert len(HOSTILE) >= 30
    assert len({row[0] for row in HOSTILE}) == len(HOSTILE)


@pytest.mark.parametrize("name, reference, kind, inside", HOSTILE, ids=[row[0] for row in HOSTILE])
def test_hostile_reference(layout, name, reference, kind, inside):
    reference = fill(reference, layout)
    guard = PathGuard(layout["ROOT"], allow_outside=[layout["ALLOWED"]])
    assert classify(reference) is kind
    assert is_url(reference) is (kind is Kind.URL)
    resolved = guard.resolve(reference)
    assert resolved.kind is kind and resolved.reference == reference
    assert resolved.inside is inside, (resolved.path, resolved.real, resolved.root)
    if kind in (Kind.URL, Kind.NUL, Kind.EMPTY):
        assert resolved.path is None and resolved.real is None  # never resolved, never fetched
    if inside:
        assert resolved.root in guard.roots and resolved.relative is not None
        assert not resolved.relative.startswith("../") and resolved.relative != ".."
        assert guard.contains(resolved.real)
    else:
        assert resolved.root is None and resolved.relative is None
        if resolved.real is not None and "\\" not in reference:  # contains() takes this system's paths
            assert not guard.contains(resolved.real)


@pytest.mark.parametrize("name, reference, kind, inside", HOSTILE, ids=[row[0] for row in HOSTILE])
def test_hostile_reference_without_the_allowed_folder(layout, name, reference, kind, inside):
    """Without --allow-outside only the asset's own folder is inside."""
    reference = fill(reference, layout)
    resolved = PathGuard(layout["ROOT"]).resolve(reference)
    expected = inside and "shared" not in name and "allowed" not in name
    assert resolved.inside is expected
    if expected:
        assert resolved.root == os.path.realpath(layout["ROOT"])


def test_relative_is_anchored_at_base(layout):
    guard = PathGuard(layout["ROOT"])
    resolved = guard.resolve("x.png", base=os.path.join(layout["ROOT"], "sub"))
    assert resolved.inside and resolved.relative == "sub/x.png"
    assert not guard.resolve("../../x.png", base=os.path.join(layout["ROOT"], "sub")).inside


def test_for_asset_guards_the_assets_folder(layout):
    guard = PathGuard.for_asset(os.path.join(layout["ROOT"], "m.mtlx"))
    assert guard.own_root == os.path.realpath(layout["ROOT"])
    assert guard.resolve("a.png").relative == "a.png"
    assert not guard.resolve("../secret/private.png").inside


def test_root_of_compares_components(layout):
    guard = PathGuard(layout["ROOT"])
    assert guard.root_of(layout["ROOT"]) == guard.own_root
    assert guard.root_of(layout["ROOT"] + "/x") == guard.own_root
    assert guard.root_of(layout["SIBLING"]) is None and guard.root_of(layout["SIBLING"] + "/x") is None


def test_contains_takes_file_system_paths_only(layout):
    guard = PathGuard(layout["ROOT"])
    assert guard.contains(os.path.join(layout["ROOT"], "a.png"))
    for path in ("", "http://x/a.png", os.path.join(layout["ROOT"], "a\x00"), os.path.join(layout["ROOT"], "loop"),
                 os.path.join(layout["ROOT"], "file_link"), "/etc/passwd"):
        assert not guard.contains(path), path


def test_the_injected_real_path_decides(tmp_path):
    """Callers (the rules' Context) inject how links are resolved; the guard uses nothing else."""
    root = str(tmp_path / "asset")

    def fake(path):  # pretend "linked" is a link to /elsewhere
        path = os.path.normpath(path)
        return path.replace(os.path.join(root, "linked"), "/elsewhere")

    guard = PathGuard(root, real_path=fake)
    assert guard.resolve("plain.png").inside
    resolved = guard.resolve("linked/a.png")
    assert not resolved.inside and resolved.real == "/elsewhere/a.png"


@pytest.mark.parametrize("reference, expected", [
    ("../a", True), ("a/../b", True), ("..\\a", True), ("a\\..\\b", True), ("a..b/c", False), ("...", False),
    ("a/b", False), ("..", True),
])
def test_climbs(reference, expected):
    assert climbs(reference) is expected


def test_kinds_are_strings():
    assert Kind.URL == paths.URL == "url" and Kind.RELATIVE.value == "relative"
