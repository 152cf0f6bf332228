"""Atomic output: write to a temporary file beside the target, then rename over it.

A reader of the target sees either the old file or the complete new one, never a partial write,
and a failure leaves no partial file behind. A target's folder that does not exist yet is made
(every command's output: ``-o new/folder/file`` works as the batch form's output tree does).
"""

from __future__ import annotations

import os
import tempfile

from .workers import raise_if_stopped


def default_mode() -> int:
    """The permissions a newly created file gets (0666 minus the umask); ``mkstemp`` creates 0600."""
    mask = os.umask(0)
    os.umask(mask)
    return 0o666 & ~mask


def write_bytes(path: str | os.PathLike, data: bytes) -> None:
    target = os.fspath(path)
    folder = os.path.dirname(os.path.abspath(target))
    os.makedirs(folder, exist_ok=True)
    handle, temporary = tempfile.mkstemp(prefix=".openpbr-", suffix=".tmp", dir=folder)
    try:
        os.fchmod(handle, default_mode())
        with os.fdopen(handle, "wb") as stream:
            stream.write(data)
            stream.flush()
            os.fsync(stream.fileno())
        raise_if_stopped()  # (a pool worker SIGTERM reached: nothing is renamed into place)
        os.replace(temporary, target)
    except BaseException:
        try:
            os.unlink(temporary)
        except OSError:
            pass
        raise


def write_text(path: str | os.PathLike, text: str) -> None:
    write_bytes(path, text.encode("utf-8"))
