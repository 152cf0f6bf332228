"""The one path guard (openpbr_tools/io/paths.py) against a table of hostile references.

Each row states what the security policy demands: the kind of the reference and whether it may be
read from an asset whose folder is ``root`` (with ``allowed`` passed as --allow-outside). Nothing in
a row comes from running the code."""

from __future__ import annotations

import os

import pytest

from openpbr_tools.io.paths import Kind, PathGuard, classify, climbs

LONG = "a" * 5000
LONG_COMPONENT = "b" * 300 + ".png"
NOT_UTF8 = os.fsdecode(b"\xff\xfe.png")

# (reference, kind, inside the asset's folder)
TABLE = [
    ("albedo.png", Kind.RELATIVE, True),
    ("textures/albedo.png", Kind.RELATIVE, True),
    ("./textures/albedo.png", Kind.RELATIVE, True),
    ("textures/../albedo.png", Kind.RELATIVE, True),
    ("../albedo.png", Kind.RELATIVE, False),
    ("a/../../b.png", Kind.RELATIVE, False),
    ("./../a.png", Kind.RELATIVE, False),
    ("../../../../../../etc/passwd", Kind.RELATIVE, False),
    ("..\\a.png", Kind.RELATIVE, True),  # on POSIX one file named '..\\a.png' inside the folder
    ("/etc/passwd", Kind.ABSOLUTE, False),
    ("\\etc\\passwd", Kind.ABSOLUTE, False),
    ("C:\\textures\\a.png", Kind.DRIVE, False),
    ("c:/textures/a.png", Kind.DRIVE, False),
    ("C:a.png", Kind.DRIVE, False),
    ("\\\\server\\share\\a.png", Kind.UNC, False),
    ("//server/share/a.png", Kind.UNC, False),
    ("file:///etc/passwd", Kind.URL, False),
    ("file:a.png", Kind.URL, False),
    ("http://example.com/a.png", Kind.URL, False),
    ("https:a.png", Kind.URL, False),
    ("HTTPS://EXAMPLE.COM/A.PNG", Kind.URL, False),
    ("data:image/png;base64,iVBORw0KGgo=", Kind.URL, False),
    ("s3+https://bucket/a.png", Kind.URL, False),
    ("a\x00.png", Kind.NUL, False),
    ("\x00", Kind.NUL, False),
    ("", Kind.EMPTY, False),
    ("   ", Kind.EMPTY, False),
    (LONG, Kind.RELATIVE, True),  # names a file inside (that cannot exist): inside, never outside
    (LONG_COMPONENT, Kind.RELATIVE, True),
    ("../" + LONG, Kind.RELATIVE, False),
    (NOT_UTF8, Kind.RELATIVE, True),
    ("~/a.png", Kind.RELATIVE, True),  # no shell expansion: a folder named '~' inside
    ("%TEMP%\\a.png", Kind.RELATIVE, True),  # no variable expansion on POSIX
    ("a.png?raw=1", Kind.RELATIVE, True),
    ("a.png#frag", Kind.RELATIVE, True),
]


@pytest.fixture
def root(tmp_path):
    folder = tmp_path / "asset"
    folder.mkdir()
    (tmp_path / "outside").mkdir()
    (tmp_path / "assetsibling").mkdir()
    return folder


@pytest.mark.parametrize("reference, kind, inside", TABLE, ids=[repr(r[0])[:40] for r in TABLE])
def test_hostile_reference(root, reference, kind, inside):
    assert classify(reference) is kind
    resolved = PathGuard(root).resolve(reference)
    assert resolved.inside is inside
    if kind in (Kind.URL, Kind.NUL, Kind.EMPTY):
        assert resolved.path is None  # never resolved to a file


def test_an_absolute_path_inside_the_folder_is_inside(root):
    assert PathGuard(root).resolve(str(root / "a.png")).inside


def test_a_symlink_inside_pointing_outside_is_outside(root):
    (root / "escape").symlink_to(root.parent / "outside")
    assert not PathGuard(root).resolve("escape/a.png").inside


def test_a_symlink_inside_pointing_inside_is_inside(root):
    (root / "textures").mkdir()
    (root / "alias").symlink_to(root / "textures")
    assert PathGuard(root).resolve("alias/a.png").inside


def test_symlink_loops_are_outside(root):
    (root / "loop").symlink_to(root / "loop")
    assert not PathGuard(root).resolve("loop").inside
    (root / "l1").symlink_to(root.parent / "outside" / "l2")
    (root.parent / "outside" / "l2").symlink_to(root / "l1")
    assert not PathGuard(root).resolve("l1").inside
    assert not PathGuard(root).contains(str(root / "l1"))


def test_a_sibling_whose_name_extends_the_folder_is_outside(root):
    assert not PathGuard(root).resolve("../assetsibling/a.png").inside
    assert not PathGuard(root).contains(str(root.parent / "assetsibling" / "a.png"))


def test_an_allowed_folder_is_inside_and_its_sibling_is_not(root):
    guard = PathGuard(root, allow_outside=[root.parent / "outside"])
    assert guard.resolve("../outside/a.png").inside
    assert guard.resolve("../outside/a.png").root == os.path.realpath(root.parent / "outside")
    assert not guard.resolve("../assetsibling/a.png").inside


def test_a_relative_reference_resolves_against_its_own_base(root):
    (root / "sub").mkdir()
    guard = PathGuard(root)
    assert guard.resolve("../a.png", base=root / "sub").inside
    assert not guard.resolve("../../a.png", base=root / "sub").inside


def test_relative_spelling_is_against_the_holding_folder(root):
    assert PathGuard(root).resolve("textures/../a.png").relative == "a.png"


def test_climbs_sees_both_separators():
    assert climbs("../a.png") and climbs("a\\..\\..\\b.png") and not climbs("a..b/c.png")
