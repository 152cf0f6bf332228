"""Texture tile sets: the files a ``<UDIM>`` or ``<UVTILE>`` file name names.

MaterialX (``UDIM_TOKEN``, ``UV_TILE_TOKEN``) and OpenUSD (``UsdShadeUdimUtils``, ``<UDIM>`` only)
substitute the token, case-sensitively: ``<UDIM>`` by the four-digit tile number 1001 + u + 10 v, and
``<UVTILE>`` by ``u<U>_v<V>`` with one-based U = u + 1 and V = v + 1 (the Mari convention), so that
``u1_v1`` is tile 1001 and ``u2_v1`` is 1002. A glTF URI names one file, tokens and all.
"""

from __future__ import annotations

import re

TILE_TOKENS = re.compile(r"<UDIM>|<UVTILE>")


def name_regex(pattern: str) -> re.Pattern:
    """The file names ``pattern`` (a file name) names: each token a group, ``<UDIM>`` four digits and ``<UVTILE>``
    ``u<U>_v<V>``; the names themselves for a pattern without a token."""
    parts, tokens = TILE_TOKENS.split(pattern), TILE_TOKENS.findall(pattern)
    return re.compile("^" + re.escape(parts[0]) + "".join(
        (r"(\d{4})" if token == "<UDIM>" else r"(u\d+_v\d+)") + re.escape(part)
        for token, part in zip(tokens, parts[1:])) + "$")


def matching_tiles(pattern: str, names) -> list[tuple[str, int]]:
    """The names among ``names`` that ``pattern`` (a file name holding exactly one tile token) names, each
    with its UDIM tile number, in name order; ``[]`` for a pattern with no token or several."""
    tokens = TILE_TOKENS.findall(pattern)
    if len(tokens) != 1:
        return []
    regex = name_regex(pattern)
    found = []
    for name in sorted(names):
        match = regex.match(name)
        if not match:
            continue
        if tokens[0] == "<UDIM>":
            found.append((name, int(match.group(1))))
            continue
        u, v = (int(n) for n in match.group(1)[1:].split("_v"))
        if 1 <= u <= 10 and v >= 1:  # (u11_v1 has no UDIM number: UDIM holds ten tiles a row)
            found.append((name, 1000 + u + 10 * (v - 1)))
    return found


def tile_name(pattern: str, number: int) -> str:
    """The ``<UDIM>`` name of tile ``number`` of ``pattern`` (a ``<UVTILE>`` pattern named as UDIM)."""
    return TILE_TOKENS.sub(str(number), pattern)
