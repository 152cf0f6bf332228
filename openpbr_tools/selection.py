"""Narrowing a file list for CI: files changed in git since a ref, and deterministic shards."""

from __future__ import annotations

import os
import zlib


class SelectionError(ValueError):
    pass


def check_ref(ref: str) -> None:
    """Refuse a ``--changed-since`` value git would parse as an option (``--output=FILE`` makes ``git diff``
    write FILE): a ref never starts with ``-``."""
    if not ref or ref.startswith("-"):
        raise SelectionError(f"--changed-since takes a git commit (a branch, tag or hash), not {ref!r}")


def changed_since(files: list[str], ref: str, cwd: str | None = None) -> list[str]:
    """The ``files`` that git reports added, copied, modified, renamed or untracked since ``ref``.

    ``ref`` is resolved to a commit hash first (``rev-parse --verify --end-of-options``), and only the hash
    reaches ``git diff``: nothing the user typed is ever read by git as an option."""
    check_ref(ref)
    cwd = cwd or os.getcwd()

    import subprocess  # lazy: ~6 ms of every validate's start-up, needed only with --changed-since

    def git(*args: str) -> str:
        try:
            done = subprocess.run(["git", *args], cwd=cwd, capture_output=True, text=True, check=False)
        except OSError as error:
            raise SelectionError(f"cannot run git: {error}") from None
        if done.returncode != 0:
            raise SelectionError(f"git {' '.join(args)}: {done.stderr.strip() or 'failed'}")
        return done.stdout

    top = git("rev-parse", "--show-toplevel").strip()
    try:
        commit = git("rev-parse", "--verify", "--quiet", "--end-of-options", f"{ref}^{{commit}}").strip()
    except SelectionError:
        raise SelectionError(f"--changed-since {ref}: not a commit of the git repository at {top}") from None
    changed = git("diff", "--name-only", "--diff-filter=ACMRT", commit, "--").splitlines()
    changed += git("ls-files", "--others", "--exclude-standard").splitlines()
    wanted = {os.path.realpath(os.path.join(top, name)) for name in changed}
    return [f for f in files if os.path.realpath(f) in wanted]


def parse_shard(text: str) -> tuple[int, int]:
    try:
        index, count = (int(part) for part in text.split("/"))
    except ValueError:
        raise SelectionError(f"--shard takes I/N (e.g. 2/8), not {text!r}") from None
    if not 1 <= index <= count:
        raise SelectionError(f"--shard {text}: I must be between 1 and N")
    return index, count


def shard(files: list[str], index: int, count: int) -> list[str]:
    """Shard ``index`` (1-based) of ``count``: a file belongs to the shard its path's CRC-32 picks, so
    the split is the same in every CI job and adding a file does not move the others."""
    return [f for f in files if zlib.crc32(f.replace(os.sep, "/").encode("utf-8")) % count == index - 1]
