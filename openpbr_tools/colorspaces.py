"""Colour-space names and conversions.

Names are data (``schemas/colorspaces.json``); conversions go through colour-science, which is
imported only when a conversion is asked for (it costs ~0.5 s to import).
"""

from __future__ import annotations

import difflib
import warnings
from functools import lru_cache

from .resources import load_json

DEFAULT_MATERIALX = "lin_rec709"


def _data() -> dict:
    return load_json("colorspaces.json")


@lru_cache(maxsize=None)
def materialx_names() -> frozenset[str]:
    return frozenset(_data()["materialx"])


@lru_cache(maxsize=None)
def usd_names() -> frozenset[str]:
    return frozenset(_data()["usd"]["names"]) | frozenset(_data()["usd"]["aliases"])


def usd_uvtexture_names() -> tuple[str, ...]:
    return tuple(_data()["usd_uvtexture_source"])


def transfer(name: str | None):
    """The transfer function of a MaterialX colour space ("linear", "data", "space" for its own curve, or a gamma);
    ``None`` for a name that is not a MaterialX one."""
    spec = _data()["materialx"].get(name) if name else None
    return spec["transfer"] if spec is not None else None


def encoded(name: str | None) -> bool:
    """Whether a MaterialX colour space has a non-linear transfer (srgb_texture, g22_rec709): values read through
    it are bent; ``False`` for a linear or data space and for a name that is not a MaterialX one."""
    return transfer(name) not in (None, "linear", "data")


def materialx_remapped(name: str | None) -> str | None:
    """The cmlib name MaterialX's own colour management maps ``name`` to (a legacy name such as ``lin_ap1`` or
    ``gamma22``, an ASWF colour-interop name such as ``lin_p3d65_scene``); ``name`` itself otherwise."""
    remapped = _data()["materialx_remapped"]
    return remapped.get(name, name) if name and not name.startswith("_") else name


def materialx_name(name: str | None) -> str | None:
    """The MaterialX name of a colour-space name from any scheme: a MaterialX name as it is, a USD
    name (``lin_rec709_scene``) by equivalence, a UsdUVTexture ``sourceColorSpace`` token as Storm
    decodes it (``raw`` -> ``none``, ``sRGB``/``auto`` -> ``srgb_texture``); anything else unchanged
    (the validator reports it)."""
    if name is None or name in materialx_names():
        return name
    tokens = {k: v for k, v in _data()["usd_uvtexture_source_as_materialx"].items() if not k.startswith("_")}
    return materialx_equivalent(name) or tokens.get(name, name)


def is_data(name: str | None, scheme: str = "materialx") -> bool:
    """True for the names that mean 'no colour management' (raw numbers)."""
    if name is None:
        return False
    if scheme == "usd":
        return name in _data()["usd"]["data"]
    if scheme == "usd_uvtexture":
        return name == "raw"
    return name == "none"


def suggest(name: str, scheme: str = "materialx") -> str | None:
    """The known name ``name`` most likely means: a case-insensitive match, a vendor/OCIO alias,
    or the closest spelling. ``None`` when nothing is close."""
    known = sorted(materialx_names() if scheme == "materialx" else usd_names())
    lowered = {k.lower(): k for k in known}
    if name.lower() in lowered:
        return lowered[name.lower()]
    aliases = _data()["vendor_aliases"]
    if scheme == "materialx" and name in aliases:
        return aliases[name]
    if scheme == "usd":
        for alias, target in aliases.items():
            if alias.lower() == name.lower():
                spec = _data()["materialx"].get(target)
                if spec and spec["usd"]:
                    return spec["usd"]
    close = difflib.get_close_matches(name.lower(), list(lowered), n=1, cutoff=0.75)
    return lowered[close[0]] if close else None


def usd_equivalent(materialx_name: str) -> str | None:
    spec = _data()["materialx"].get(materialx_name)
    return spec["usd"] if spec else None


def materialx_equivalent(usd_name: str) -> str | None:
    usd_name = _data()["usd"]["aliases"].get(usd_name, usd_name)
    for name, spec in _data()["materialx"].items():
        if spec["usd"] == usd_name:
            return name
    return None


def _colour():
    """colour-science, imported on first use with its optional-dependency warnings silenced."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        import colour  # lazy: colour-science costs 0.5-1 s to import
    return colour


@lru_cache(maxsize=None)
def _space(name: str):
    """colour-science's colour space ``name`` with matrices derived from its primaries and white
    point (the published sRGB matrices are rounded to 4 decimals, so they neither invert each other
    nor map white to white), as MaterialX's cmlib does."""
    space = _colour().RGB_COLOURSPACES[name].copy()
    space.use_derived_transformation_matrices(True)
    return space


@lru_cache(maxsize=None)
def _matrix(source: str, target: str):
    """The 3x3 linear-RGB conversion between two colour spaces, Bradford-adapted where the white
    points differ: MaterialX 1.39's cmlib matrices (e.g. ND_acescg_to_lin_rec709) to ~1e-12."""
    return _colour().matrix_RGB_to_RGB(_space(source), _space(target), chromatic_adaptation_transform="Bradford")


def _conversion(colorspace: str | None):
    """The colour-space entry to convert with, or ``None`` when no conversion applies (the default
    working space, ``none`` data). Raises ``KeyError`` for a name that is not a MaterialX one."""
    name = colorspace or DEFAULT_MATERIALX
    spec = _data()["materialx"].get(name)
    if spec is None:
        raise KeyError(f"unknown MaterialX colour space {name!r}")
    if spec["transfer"] == "data" or name == DEFAULT_MATERIALX:
        return None
    return spec


def to_lin_rec709(rgb, colorspace: str | None):
    """Convert colour values (array ``(..., 3)``) from a MaterialX colour space to linear Rec.709.

    Encoded spaces are decoded with their transfer function first (sRGB piecewise curve for
    ``srgb_texture``, a pure power for the ``g22_``/``g18_`` names), then the primaries are adapted
    with colour-science's derived matrices, Bradford-adapted where white points differ (MaterialX's
    cmlib matrices). ``None`` and ``lin_rec709`` return the values unchanged; ``none`` (data) is
    returned unchanged too.
    """
    import numpy as np  # lazy: numpy (~70 ms) stays off validate's start-up until a conversion is asked for

    values = np.asarray(rgb, dtype=np.float64)
    spec = _conversion(colorspace)
    if spec is None:
        return values
    values = _decode(spec, values, _per_level)
    if spec["space"] == "sRGB":
        return np.asarray(values, dtype=np.float64)
    return values @ _matrix(spec["space"], "sRGB").T


def to_lin_rec709_as_materialx(rgb, colorspace: str | None):
    """:func:`to_lin_rec709`, except that a USD colour-space name (a ``Usd.ColorSpaceAPI`` space such as
    ``lin_ap1_scene``, which a USD reader gives an input that inherits it) converts as its MaterialX equivalent, as
    UsdMtlx hands it to MaterialX (the audit's F6: an ACEScg material written to USD and read back was judged 2.4
    CIEDE2000 off itself), and a name neither knows (a vendor or OCIO name: the validator reports it, OPBR502)
    converts nothing, as MaterialX's colour management applies no transform for it."""
    try:
        return to_lin_rec709(rgb, colorspace)
    except KeyError:
        equivalent = materialx_equivalent(colorspace) if colorspace else None
        if equivalent is not None:
            return to_lin_rec709(rgb, equivalent)
        import numpy as np  # lazy: as in to_lin_rec709

        return np.asarray(rgb, dtype=np.float64)


def levels_to_lin_rec709(levels, colorspace: str | None, dtype=None):
    """:func:`to_lin_rec709` of ``levels / 255`` for 8-bit ``levels`` (uint8 ``(..., 3)``, what an
    8-bit image stores): the transfer function tabulated over the 256 levels (the same numbers as
    :func:`to_lin_rec709`), then the primaries. ``dtype`` (default float64) is that of the result."""
    import numpy as np  # lazy: as in to_lin_rec709

    dtype = dtype or np.float64
    spec = _conversion(colorspace)
    table = np.arange(256, dtype=np.float64) / 255.0
    if spec is not None:
        table = _decode(spec, table, lambda transfer, v: transfer(v))
    values = np.asarray(table, dtype=dtype)[np.asarray(levels)]
    if spec is None or spec["space"] == "sRGB":
        return values
    return values @ np.asarray(_matrix(spec["space"], "sRGB").T, dtype=dtype)


def _decode(spec: dict, values, apply):
    """The transfer function of a colour-space entry applied through ``apply(transfer, values)``."""
    import numpy as np  # lazy: as in to_lin_rec709

    transfer = spec["transfer"]
    if transfer == "space":
        return apply(_space(spec["space"]).cctf_decoding, values)
    if isinstance(transfer, dict):
        return apply(lambda v: np.sign(v) * np.abs(v) ** transfer["gamma"], values)
    return values


def _per_level(transfer, values):
    """``transfer(values)``; for a large array of 8-bit levels (``k / 255``, what an 8-bit texture
    decodes to), the transfer of the 256 levels looked up instead: the same numbers, much faster."""
    import numpy as np  # lazy: numpy (~70 ms) stays off validate's start-up until a conversion is asked for

    if values.size >= 1 << 16:
        levels = np.rint(values * 255.0)
        if np.all(np.abs(values * 255.0 - levels) <= 1e-7) and levels.min() >= 0 and levels.max() <= 255:
            table = np.asarray(transfer(np.arange(256, dtype=np.float64) / 255.0), dtype=np.float64)
            return table[levels.astype(np.intp)]
    return transfer(values)


def from_lin_rec709(rgb, colorspace: str | None):
    """Inverse of :func:`to_lin_rec709`."""
    import numpy as np  # lazy: numpy (~70 ms) stays off validate's start-up until a conversion is asked for

    values = np.asarray(rgb, dtype=np.float64)
    spec = _conversion(colorspace)
    if spec is None:
        return values
    target = _space(spec["space"])
    if spec["space"] != "sRGB":
        values = values @ _matrix("sRGB", spec["space"]).T
    transfer = spec["transfer"]
    if transfer == "space":
        values = target.cctf_encoding(values)
    elif isinstance(transfer, dict):
        values = np.sign(values) * np.abs(values) ** (1.0 / transfer["gamma"])
    return np.asarray(values, dtype=np.float64)


#: Linear Rec.709's luminance weights (ITU-R BT.709-6, item 3.2), by which :func:`into_gamut` keeps a colour's luminance.
REC709_LUMINANCE = (0.2126, 0.7152, 0.0722)
#: How far :func:`into_gamut` may pull a colour towards its grey, in steps (0: the colour clipped as it is).
GAMUT_STEPS = 20


def into_gamut(rgb, low: float = 0.0, high: float | None = 1.0) -> tuple[float, ...]:
    """A linear Rec.709 colour brought inside [``low``, ``high``] per channel (``high`` None: no upper bound, an
    emission's), where a target's file can hold only that: of the colours on the way from ``rgb`` to the grey of its
    luminance (clipped into the range itself), each clipped, the one closest to ``rgb`` in CIEDE2000. Clipping alone
    adds light and turns the hue where a wide-gamut colour (an ACEScg or Display P3 document's) is negative in
    Rec.709; a little desaturation first keeps both (its luminance in the weights :data:`REC709_LUMINANCE`). A colour
    already inside is returned as it is."""
    import numpy as np  # lazy: as in to_lin_rec709

    from .evaluate.difference import delta_e_2000  # lazy: colour-science is imported only for a colour outside

    colour = np.asarray(rgb, dtype=np.float64)
    top = np.inf if high is None else high
    if colour.shape != (3,) or not np.all(np.isfinite(colour)) or (np.all(colour >= low) and np.all(colour <= top)):
        return tuple(float(c) for c in colour)
    grey = float(np.clip(colour @ np.asarray(REC709_LUMINANCE), low, top))
    steps = np.linspace(1.0, 0.0, GAMUT_STEPS + 1)[:, None]
    candidates = np.clip(grey + steps * (colour - grey), low, top)
    white = max(1.0, float(np.max(np.abs(colour))))
    differences = delta_e_2000(np.broadcast_to(colour, candidates.shape), candidates, white)
    return tuple(float(c) for c in candidates[int(np.argmin(differences))])
