"""Text (``.usda``) layers judged before usd-core parses them: bracket nesting.

usd-core's text parser recurses once per nested bracket and overflows the stack (a segmentation
fault, not an error) between 30,000 and 70,000 levels on an 8 MiB stack. :func:`text_nesting_problem`
finds brackets nested deeper than :data:`MAX_TEXT_NESTING` outside strings, asset paths and comments,
so :class:`~.guard.StageGuard` refuses such a layer first.
"""

from __future__ import annotations

import re

#: Brackets nested deeper than this in a text layer are refused before usd-core parses it. Its
#: parser overflows an 8 MiB stack between 30,000 and 70,000 levels (less on smaller thread
#: stacks); real files stay far below 100.
MAX_TEXT_NESTING = 1000

_TEXT_SKIPPED = re.compile(  # what usd-core's text grammar reads as strings, asset paths or comments
    rb"'''(?:\\.|[^\\])*?'''|\"\"\"(?:\\.|[^\\])*?\"\"\""
    rb"|'(?:\\[^\r\n]|[^'\\\r\n])*'|\"(?:\\[^\r\n]|[^\"\\\r\n])*\""
    rb"|@@@(?:\\@@@|[^\r\n])*?@@@@?@?|@[^@\r\n]*@"
    rb"|#[^\r\n]*|//[^\r\n]*|/\*.*?\*/",
    re.DOTALL,
)
_UNTERMINATED = (b"'", b'"', b"@", b"/*")


def text_nesting_problem(data: bytes) -> tuple[str, int] | None:
    """(message, line) when brackets nest deeper than :data:`MAX_TEXT_NESTING` in a text layer,
    outside strings, asset paths and comments, else ``None``."""
    if sum(data.count(c) for c in (b"(", b"[", b"{")) <= MAX_TEXT_NESTING:
        return None  # cannot nest deeper than it opens
    code = _TEXT_SKIPPED.sub(lambda m: b"\n" * m.group().count(b"\n"), data)
    # an unterminated string, asset path or comment is a syntax error: usd-core stops there
    stops = [i for i in (code.find(token) for token in _UNTERMINATED) if i >= 0]
    if stops:
        code = code[: min(stops)]
    position = _deeper_than(code, MAX_TEXT_NESTING)
    if position is None:
        return None
    return f"brackets nest deeper than {MAX_TEXT_NESTING} levels", code.count(b"\n", 0, position) + 1


def _deeper_than(code: bytes, limit: int) -> int | None:
    import numpy as np  # lazy: numpy (~60 ms) only for a layer with more brackets than the limit

    step = np.zeros(256, dtype=np.int8)
    step[list(b"([{")] = 1
    step[list(b")]}")] = -1
    depth, chunk = 0, 1 << 22
    for start in range(0, len(code), chunk):
        running = np.cumsum(step[np.frombuffer(code, np.uint8, min(chunk, len(code) - start), start)], dtype=np.int64)
        running += depth
        over = np.flatnonzero(running > limit)
        if over.size:
            return start + int(over[0])
        depth = int(running[-1]) if running.size else depth
    return None
