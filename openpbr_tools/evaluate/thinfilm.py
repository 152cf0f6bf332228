"""Thin-film interference: exact Airy reflectance of a film on a substrate, integrated over the
visible spectrum.

This is the documented simpler alternative to Belcour & Barla's Fourier-space approximation
("A Practical Extension to Microfacet Theory for the Modeling of Varying Iridescence",
SIGGRAPH 2017) that MaterialX and KHR_materials_iridescence use: instead of approximating the
spectral integral, it evaluates the film's reflectance at 81 wavelengths (380-780 nm, 5 nm) and
integrates it against the CIE 1931 2-degree colour matching functions under illuminant D65,
giving linear Rec.709 RGB (a spectrally flat reflectance of 1 maps to RGB 1). For the film
thicknesses these models allow (up to a few micrometres) 5 nm sampling resolves the fringes;
Belcour & Barla's anti-aliasing of much thicker films is not reproduced.
"""

from __future__ import annotations

from contextlib import contextmanager
from functools import lru_cache

import numpy as np

from .albedo import tables
from .spectral import WAVELENGTHS_NM

#: Wavelengths (nm) assigned to the R, G, B channels when an RGB substrate IOR is spread over the
#: spectrum (linear interpolation between them, constant beyond).
CHANNEL_WAVELENGTHS_NM = np.array([465.0, 550.0, 610.0])  # B, G, R (increasing)


def airy_reflectance(cos_theta, thickness_nm, film_ior, substrate_ior, wavelength_nm):
    """Reflectance of a dielectric film (index ``film_ior``, ``thickness_nm``) on a substrate
    of complex index ``substrate_ior`` (n + ik), seen from a medium of index 1, averaged over s
    and p polarisations.

    r = (r12 + r23 exp(2i delta)) / (1 + r12 r23 exp(2i delta)), delta = 2 pi n2 d cos(t2) / lambda,
    with r12, r23 the Fresnel amplitude coefficients of the two interfaces (Born & Wolf,
    *Principles of Optics*, 7th ed., section 1.6.4, eq. 58 and 1.5.2 eq. 21). Multiple
    reflections inside the film are summed exactly (the Airy series). Broadcasting: the result
    has the broadcast shape of all arguments; pass ``wavelength_nm`` with a trailing axis.
    """
    # exact grazing (cos 0) with an index-1 film or substrate makes every coefficient 0/0; a cosine
    # of 1e-7 gives the limits instead (no interface: 0; an interface: total reflection)
    c1 = np.clip(np.abs(np.asarray(cos_theta, dtype=float)), 1e-7, 1.0)
    n2 = np.maximum(np.asarray(film_ior, dtype=float), 1.0).astype(complex)
    n3 = np.asarray(substrate_ior, dtype=complex)
    n3 = np.where(np.abs(n3) < 1e-4, 1e-4, n3)  # an index of 0 (legal in Standard Surface): total reflection, finite
    sin2 = 1.0 - c1 * c1
    c2 = np.sqrt(1.0 - sin2 / (n2 * n2))
    c3 = np.sqrt(1.0 - sin2 / (n3 * n3))
    c3 = np.where((n3 * c3).imag < 0.0, -c3, c3)  # the transmitted wave must decay
    r12s = (c1 - n2 * c2) / (c1 + n2 * c2)
    r12p = (n2 * c1 - c2) / (n2 * c1 + c2)
    r23s = (n2 * c2 - n3 * c3) / (n2 * c2 + n3 * c3)
    r23p = (n3 * c2 - n2 * c3) / (n3 * c2 + n2 * c3)
    delta = 2.0 * np.pi * n2 * np.asarray(thickness_nm, dtype=float) * c2 / np.asarray(wavelength_nm)
    phase = np.exp(2j * delta)
    rs = (r12s + r23s * phase) / (1.0 + r12s * r23s * phase)
    rp = (r12p + r23p * phase) / (1.0 + r12p * r23p * phase)
    return 0.5 * (np.abs(rs) ** 2 + np.abs(rp) ** 2)


def spectral_ior(rgb_ior):
    """Spread a per-channel (RGB, last axis) IOR over :data:`WAVELENGTHS_NM` by linear
    interpolation between :data:`CHANNEL_WAVELENGTHS_NM`. Works for complex IORs."""
    rgb = np.asarray(rgb_ior)
    bgr = rgb[..., ::-1]
    lam = WAVELENGTHS_NM
    t = np.clip((lam - CHANNEL_WAVELENGTHS_NM[0]) / (CHANNEL_WAVELENGTHS_NM[1] - CHANNEL_WAVELENGTHS_NM[0]), 0.0, 1.0)
    u = np.clip((lam - CHANNEL_WAVELENGTHS_NM[1]) / (CHANNEL_WAVELENGTHS_NM[2] - CHANNEL_WAVELENGTHS_NM[1]), 0.0, 1.0)
    low = bgr[..., 0:1] + (bgr[..., 1:2] - bgr[..., 0:1]) * t
    high = bgr[..., 1:2] + (bgr[..., 2:3] - bgr[..., 1:2]) * u
    return np.where(lam < CHANNEL_WAVELENGTHS_NM[1], low, high)


def thin_film_rgb(cos_theta, thickness_nm, film_ior, substrate_n, substrate_k=None):
    """Linear Rec.709 reflectance of a thin film on a substrate, for cosines ``cos_theta``.

    ``substrate_n`` (and ``substrate_k`` for conductors) are per-channel RGB arrays spread over
    the spectrum with :func:`spectral_ior`; the scalar parameters broadcast against
    ``cos_theta``. Returns an array of shape ``broadcast(cos_theta, ...) + (3,)``. A single film
    seen from many directions is evaluated on 1024 cosines and interpolated linearly.
    """
    weights = tables().spectral_weights
    n = np.asarray(substrate_n, dtype=float)
    ior = n if substrate_k is None else n + 1j * np.asarray(substrate_k, dtype=float)
    cos_theta = np.asarray(cos_theta, dtype=float)
    if _COARSE and cos_theta.size > _COARSE[-1]:
        coarse = _by_distinct_film(cos_theta, thickness_nm, film_ior, ior, _COARSE[-1])
        if coarse is not None:
            return coarse
    if cos_theta.size > COSINE_GRID and np.size(thickness_nm) == 1 and np.size(film_ior) == 1 and ior.size <= 3:
        # One film, many directions: evaluate on a fine grid of cosines and interpolate.
        key = (float(np.reshape(thickness_nm, -1)[0]), float(np.reshape(film_ior, -1)[0]), tuple(np.broadcast_to(ior, (3,)).tolist()))
        grid, slope = _cosine_grid_rgb(*key)
        mu = np.minimum(np.abs(cos_theta), 1.0) * (COSINE_GRID - 1)
        i = mu.astype(np.intp)
        return grid[i] + slope[i] * (mu - i)[..., None]
    return _thin_film_rgb_direct(cos_theta, thickness_nm, film_ior, ior, weights)


#: Cosine samples of the interpolation grid used for a single film seen from many directions.
COSINE_GRID = 1024
_COARSE: list[int] = []  # the grid of the innermost coarse_films(), if any


@contextmanager
def coarse_films(grid: int = 64):
    """Within the block, films are evaluated on ``grid`` cosines per distinct film (thickness, film
    IOR, substrate) and interpolated, whatever the number of directions or of films per call: a
    ranking aid for renders that only compare candidates (``translate.candidates`` stacks several
    materials, with their films, into one render), about 3x cheaper there; previews and verification
    keep the exact evaluation."""
    _COARSE.append(grid)
    try:
        yield
    finally:
        _COARSE.pop()


def _by_distinct_film(cos_theta, thickness_nm, film_ior, ior, grid: int):
    """:func:`thin_film_rgb` on a ``grid``-cosine table per distinct film, or None when the films are
    so many that the tables would cost more than the direct evaluation."""
    shape = cos_theta.shape
    mu = (np.minimum(np.abs(cos_theta), 1.0) * (grid - 1)).reshape(-1)
    i = mu.astype(np.intp)
    if np.size(thickness_nm) == 1 and np.size(film_ior) == 1 and np.size(ior) in (1, 3):  # one film: no sorting
        n = np.broadcast_to(np.reshape(ior, -1), (3,))
        table, slope = _cosine_grid_rgb(float(np.reshape(thickness_nm, -1)[0]), float(np.reshape(film_ior, -1)[0]),
                                        tuple(n.tolist()), grid)
        return (table[i] + slope[i] * (mu - i)[:, None]).reshape(shape + (3,))
    columns = [np.broadcast_to(np.asarray(thickness_nm, dtype=float), shape).reshape(-1, 1),
               np.broadcast_to(np.asarray(film_ior, dtype=float), shape).reshape(-1, 1)]
    substrate = np.broadcast_to(ior, shape + (3,)).reshape(-1, 3)
    columns += [substrate.real, substrate.imag] if np.iscomplexobj(substrate) else [substrate]
    keys = np.concatenate(columns, axis=1)
    # stacked renders repeat each material's film over its block of pixels: sort the runs, not the pixels
    change = np.ones(len(keys), dtype=bool)
    change[1:] = np.any(keys[1:] != keys[:-1], axis=1)
    starts = np.flatnonzero(change)
    distinct, which_run = np.unique(keys[starts], axis=0, return_inverse=True)
    which = np.repeat(np.reshape(which_run, -1), np.diff(np.append(starts, len(keys))))
    if len(distinct) * grid >= cos_theta.size:
        return None
    out = np.empty((cos_theta.size, 3))
    which = which.reshape(-1)
    for index, row in enumerate(distinct):
        n = row[2:5] + (1j * row[5:8] if len(row) > 5 else 0.0)
        table, slope = _cosine_grid_rgb(float(row[0]), float(row[1]), tuple(np.asarray(n).tolist()), grid)
        at = which == index
        out[at] = table[i[at]] + slope[i[at]] * (mu[at] - i[at])[:, None]
    return out.reshape(shape + (3,))


@lru_cache(maxsize=64)
def _cosine_grid_rgb(thickness_nm: float, film_ior: float, ior: tuple, grid: int = COSINE_GRID) -> tuple[np.ndarray, np.ndarray]:
    """Film colour at ``grid`` cosines and the slope to the next node (last row repeated)."""
    cos = np.linspace(0.0, 1.0, grid)
    grid = _thin_film_rgb_direct(cos, thickness_nm, film_ior, np.asarray(ior), tables().spectral_weights)
    slope = np.diff(grid, axis=0, append=grid[-1:])
    return grid, slope


def _thin_film_rgb_direct(cos_theta, thickness_nm, film_ior, ior, weights):
    ior_spec = spectral_ior(ior)
    cos_t = np.asarray(cos_theta, dtype=float)[..., None]
    d = np.asarray(thickness_nm, dtype=float)[..., None]
    n2 = np.asarray(film_ior, dtype=float)[..., None]
    refl = airy_reflectance(cos_t, d, n2, ior_spec, WAVELENGTHS_NM)
    return np.clip(refl @ weights.T, 0.0, 1.0)
