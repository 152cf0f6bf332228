"""usd-core's diagnostics: importing it, keeping its warnings and errors off stderr, and reading the
text of its errors.

usd-core reports problems as ``Tf`` diagnostics (printed to stderr unless trapped) and raises
``Tf.ErrorException`` whose text stacks every error with its C++ function, line and file.
:func:`quiet` traps them for a block; :func:`usd_error_message` picks the most specific message out
of an error report and the line of the file it names; :func:`tf_error_text` and
:func:`strip_stage_suffix` cope with usd-core's quirks (invalid UTF-8 quoted from a file, the
"instantiating stage" suffix of composition errors).

``pxr`` is imported inside the functions only (``from pxr import Usd`` costs 0.2-0.5 s).
"""

from __future__ import annotations

import contextlib
import io
import re
import threading
from contextlib import contextmanager

from ...model import Location
from .. import ReadError

_TF_MESSAGE = re.compile(r"Error in '[^']*' at line \d+ in file [^\n]*? : '(.*?)'\s*(?=\n\s*Error in |\Z)", re.DOTALL)
_TEXT_POSITION = re.compile(r":(\d+):(\d+): ")


def require_pxr(path: str = "") -> None:
    """Import usd-core, or say how to install it."""
    try:
        from pxr import Usd  # noqa: F401
    except ImportError:
        raise ReadError(
            "unsupported", "reading or writing USD needs usd-core: pip install usd-core", Location(path)
        ) from None


@contextmanager
def quiet():
    """Capture usd-core's warnings and errors (which it otherwise prints to stderr) for the block;
    yields the list they are collected into. Python errors usd-core swallows (text in a crate file
    that is not UTF-8 becomes ``None``) are printed to ``sys.stderr`` by Python itself: captured too,
    in the main thread (``sys.stderr`` is global: threads swapping it would leave it swapped)."""
    from pxr import Tf  # lazy: see the module docstring

    collected: list[str] = []
    printed = io.StringIO()
    capture = contextlib.redirect_stderr(printed) if threading.current_thread() is threading.main_thread() \
        else contextlib.nullcontext()
    with Tf.DiagnosticTrap() as trap, capture:
        try:
            yield collected
        finally:
            collected.extend(_commentary(w) for w in trap.GetWarnings())
            collected.extend(_commentary(e) for e in trap.GetErrors())
            collected.extend(line for line in printed.getvalue().splitlines() if line.strip())
            trap.Clear()


def _commentary(diagnostic) -> str:
    try:
        return str(diagnostic.commentary)
    except UnicodeDecodeError:  # usd-core quotes the offending bytes of a file that is not UTF-8
        return "(a message about text that is not valid UTF-8)"


def tf_error_text(error) -> str:
    """``str()`` of a ``Tf.ErrorException``, which itself raises when usd-core quotes invalid UTF-8."""
    try:
        return str(error)
    except UnicodeDecodeError:
        return "\n".join(_commentary(e) for e in error.args) or "(an error about text that is not valid UTF-8)"


def usd_error_message(text: str, path: str) -> tuple[str, int | None]:
    """The most specific message in a Tf error report, and the line it names in ``path``."""
    messages = [" ".join(m.split()) for m in _TF_MESSAGE.findall(text.strip())]
    message = messages[0] if messages else (text.strip().splitlines() or ["unknown error"])[-1]
    line = None
    if message.startswith(path):
        position = _TEXT_POSITION.match(message[len(path):])
        if position:
            line = int(position.group(1))
            message = message[len(path) + position.end():]
    message = message.replace(f"layer @{path}@", "the file").replace(f"@{path}@", "the file")
    return message.strip(), line


def strip_stage_suffix(message: str) -> str:
    return re.sub(r"\s*\(instantiating stage on stage @[^@]*@ <[^>]*>\)$", "", message).strip()
