"""Tabulated directional albedo E(mu) of the lobes, for albedo-scaling layering, multiple-
scattering compensation and environment lighting.

E(wo) = int f(wi, wo) cos(theta_i) dwi (for transmission: the energy transmittance of light
arriving along wo). The tables are computed deterministically by quadrature of this package's
own lobe functions:

* GGX lobes: a midpoint grid on the unit square mapped through the sampling of visible normals
  (Dupuy & Benyoub 2023), whose estimator weight is F G2 / G1 (Heitz 2018, section 2; Walter et
  al. 2007 eq. 38-41 for transmission);
* other lobes: Gauss-Legendre in cos(theta_i) times a midpoint rule in phi.

They are stored in ``data/albedo_tables.npz`` (regenerate with
``python -m openpbr_tools.evaluate.albedo``); if the file is missing they are computed on first
use (about a minute) and kept in memory. Grids are uniform in mu = cos(theta) (0..1), in
r = sqrt(alpha) (0..1) and, for dielectrics, in the signed normal-incidence reflectance
y = sign(eta - 1) ((eta - 1) / (eta + 1))^2 (-0.25..0.25, i.e. eta from 1/3 to 3), in which the
reflectance is nearly linear (Schlick); look-ups interpolate linearly and clamp to the grid. Anisotropic roughness
is looked up at the geometric mean alpha = sqrt(alpha_x alpha_y), as MaterialX does.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache
from pathlib import Path

import numpy as np

from . import diffuse, fresnel, microfacet, sheen
from .spectral import spectral_to_rgb_weights

DATA_FILE = Path(__file__).resolve().parent / "data" / "albedo_tables.npz"
MU_NODES = 32
ROUGHNESS_NODES = 32
ETA_NODES = 25
MU_FLOOR = 0.002
ALPHA_FLOOR = 1e-4
TABLE_VERSION = 6


@dataclass(frozen=True)
class Tables:
    ggx_f1: np.ndarray  # [mu, r]  F = 1
    schlick_f0: np.ndarray  # [mu, r]  weight of F0 in Schlick: int (1 - (1 - c)^5) ...
    schlick_f90: np.ndarray  # [mu, r]  weight of F90: int (1 - c)^5 ...
    f82_term: np.ndarray  # [mu, r]  int c (1 - c)^6 ... (the F82 correction's shape)
    dielectric_r: np.ndarray  # [x, mu, r]  reflectance divided by the smooth Fresnel factor
    dielectric_loss: np.ndarray  # [x, mu, r]  1 - R - T: what single scattering loses
    charlie_ashikhmin: np.ndarray  # [mu, r]
    charlie_lambda: np.ndarray  # [mu, r]
    oren_nayar: np.ndarray  # [mu, sigma]
    lambert_schlick: np.ndarray  # [mu]  int (1 - wo.h)^5 cos_i / pi dwi
    spectral_weights: np.ndarray  # [3, wavelengths]


def mu_nodes() -> np.ndarray:
    return np.maximum(np.linspace(0.0, 1.0, MU_NODES), MU_FLOOR)


def roughness_nodes() -> np.ndarray:
    return np.linspace(0.0, 1.0, ROUGHNESS_NODES)


def eta_nodes() -> np.ndarray:
    y = np.linspace(-0.25, 0.25, ETA_NODES)
    x = np.sign(y) * np.sqrt(np.abs(y))
    return (1.0 + x) / (1.0 - x)


def _eta_coordinate(eta):
    """The table coordinate of an IOR ratio, rescaled to 0..1."""
    x = (eta - 1.0) / (eta + 1.0)
    return (np.sign(x) * x * x + 0.25) * 2.0


def _ggx_quadrature(mu, alpha, weight_fn, n):
    """Mean of ``weight_fn(wo, h)`` over an n x n midpoint grid mapped to visible normals."""
    u = (np.arange(n) + 0.5) / n
    u1, u2 = np.meshgrid(u, u, indexing="ij")
    u1, u2 = u1.ravel(), u2.ravel()
    mu = np.asarray(mu, dtype=float)[:, None]
    wo = np.stack(np.broadcast_arrays(np.sqrt(1.0 - mu * mu), 0.0 * mu, mu), axis=-1)
    wo = np.broadcast_to(wo, mu.shape[:1] + u1.shape + (3,))
    h = microfacet.sample_ggx_vnormal(wo, alpha, alpha, u1, u2)
    return np.mean(weight_fn(wo, h), axis=-1)


def _reflection_weights(wo, h, alpha):
    wi = microfacet.reflect(wo, h)
    ok = wi[..., 2] > 0.0
    g = microfacet.smith_g2_height_correlated(wi, wo, alpha, alpha) / microfacet.smith_g1(wo, alpha, alpha)
    return np.where(ok, g, 0.0), np.clip(microfacet.dot(wo, h), 0.0, 1.0)


def _hemisphere_quadrature(mu_o, lobe, n_mu=48, n_phi=48):
    """int lobe(wi, wo) cos_i dwi for wo = (sin, 0, mu_o), by Gauss-Legendre x midpoint phi."""
    x, w = np.polynomial.legendre.leggauss(n_mu)
    mu_i = 0.5 * (x + 1.0)
    w_mu = 0.5 * w
    phi = (np.arange(n_phi) + 0.5) * (np.pi / n_phi)
    mi, ph = np.meshgrid(mu_i, phi, indexing="ij")
    si = np.sqrt(1.0 - mi * mi)
    wi = np.stack([si * np.cos(ph), si * np.sin(ph), mi], axis=-1).reshape(-1, 3)
    weights = (w_mu[:, None] * np.full(n_phi, 2.0 * np.pi / n_phi)).reshape(-1)
    mu_o = np.asarray(mu_o, dtype=float)[:, None]
    wo = np.stack(np.broadcast_arrays(np.sqrt(1.0 - mu_o * mu_o), 0.0 * mu_o, mu_o), axis=-1)
    values = lobe(wi[None, :, :], wo)
    return np.sum(values * wi[None, :, 2] * weights[None, :], axis=-1)


def build_tables(samples: int = 64) -> dict[str, np.ndarray]:
    """Compute every table (deterministic; ``samples``^2 quadrature points per GGX entry)."""
    mus = mu_nodes()
    alphas = np.maximum(roughness_nodes() ** 2, ALPHA_FLOOR)
    shape = (MU_NODES, ROUGHNESS_NODES)
    out = {k: np.zeros(shape) for k in ("ggx_f1", "schlick_f0", "schlick_f90", "f82_term")}
    for j, alpha in enumerate(alphas):
        def w_schlick(wo, h, alpha=alpha):
            g, c = _reflection_weights(wo, h, alpha)
            x = 1.0 - c
            return np.stack([g, g * (1.0 - x**5), g * x**5, g * c * x**6], axis=0)

        res = np.stack([_ggx_quadrature(mus, alpha, lambda wo, h: w_schlick(wo, h)[k], samples) for k in range(4)])
        out["ggx_f1"][:, j], out["schlick_f0"][:, j], out["schlick_f90"][:, j], out["f82_term"][:, j] = res
    etas = eta_nodes()
    r_tab = np.zeros((ETA_NODES,) + shape)
    t_tab = np.zeros((ETA_NODES,) + shape)

    def dielectric_entries(eta, alpha):
        def w_r(wo, h):
            g, c = _reflection_weights(wo, h, alpha)
            return g * fresnel.fresnel_dielectric(c, eta)

        def w_t(wo, h):
            wt, valid = microfacet.refract(wo, h, eta)
            ok = valid & (wt[..., 2] < 0.0) & (microfacet.dot(wo, h) > 0.0)
            g = microfacet.smith_g2_height_correlated(wt, wo, alpha, alpha) / microfacet.smith_g1(wo, alpha, alpha)
            f = fresnel.fresnel_dielectric(microfacet.dot(wo, h), eta)
            return np.where(ok, g * (1.0 - f), 0.0)

        r = _ggx_quadrature(mus, alpha, w_r, samples)
        smooth = fresnel.fresnel_dielectric(mus, eta)
        return np.where(smooth > 1e-12, r / np.maximum(smooth, 1e-12), 1.0), _ggx_quadrature(mus, alpha, w_t, samples)

    for k, eta in enumerate(etas):
        for j, alpha in enumerate(alphas):
            if abs(eta - 1.0) < 1e-9:
                # eta = 1 reflects nothing; store the limit of the ratio (the mean of both sides).
                above, below = dielectric_entries(1.001, alpha), dielectric_entries(0.999, alpha)
                r_tab[k, :, j] = 0.5 * (above[0] + below[0])
                t_tab[k, :, j] = 0.5 * (above[1] + below[1])
            else:
                r_tab[k, :, j], t_tab[k, :, j] = dielectric_entries(eta, alpha)
    # Reflectance is stored relative to the smooth interface's Fresnel factor, which look-ups
    # multiply back exactly: the ratio interpolates smoothly across IORs, the critical angle and
    # grazing angles, where the reflectance itself has steps. Transmission is stored as the
    # energy single scattering loses, 1 - R - T, which vanishes for smooth interfaces.
    smooth = fresnel.fresnel_dielectric(mus[None, :], etas[:, None])[..., None]
    out["dielectric_r"] = r_tab
    out["dielectric_loss"] = 1.0 - r_tab * smooth - t_tab
    rough = roughness_nodes()
    for name, vis in (("charlie_ashikhmin", "ashikhmin"), ("charlie_lambda", "charlie")):
        out[name] = np.stack(
            [_hemisphere_quadrature(mus, lambda wi, wo, r=r, v=vis: sheen.conty_kulla_sheen(wi, wo, r, v)) for r in rough],
            axis=-1,
        )
    out["oren_nayar"] = np.stack(
        [
            _hemisphere_quadrature(
                mus, lambda wi, wo, s=s: diffuse.oren_nayar(wi[..., 2], wo[..., 2], microfacet.dot(*np.broadcast_arrays(wi, wo)), s)
            )
            for s in rough
        ],
        axis=-1,
    )

    def lambert_schlick(wi, wo):
        h = microfacet.normalize(wi + wo)
        return (1.0 - np.clip(microfacet.dot(*np.broadcast_arrays(wo, h)), 0.0, 1.0)) ** 5 / np.pi

    out["lambert_schlick"] = _hemisphere_quadrature(mus, lambert_schlick)
    out["spectral_weights"] = spectral_to_rgb_weights()
    out["version"] = np.array(TABLE_VERSION)
    return out


@lru_cache(maxsize=1)
def tables() -> Tables:
    """The albedo tables: loaded from ``data/albedo_tables.npz``, or computed once per process."""
    raw: dict
    if DATA_FILE.is_file():
        with np.load(DATA_FILE) as npz:
            raw = {k: npz[k] for k in npz.files}
        if int(raw.get("version", -1)) != TABLE_VERSION:
            raw = build_tables()
    else:
        raw = build_tables()
    return Tables(**{k: np.asarray(v, dtype=float) for k, v in raw.items() if k != "version"})


def save_tables(path: Path = DATA_FILE) -> Path:
    """Recompute the tables and write them to ``path``."""
    raw = build_tables()
    path.parent.mkdir(parents=True, exist_ok=True)
    # Tables in float32 (their quadrature error is far larger); spectral weights in float64 so a
    # flat spectrum maps to exactly 1.
    np.savez_compressed(
        path, **{k: np.asarray(v, dtype=np.float32) if v.ndim and k != "spectral_weights" else v for k, v in raw.items()}
    )
    return path


# ----------------------------------------------------------------------------- look-ups


def _coords(value, n):
    t = np.minimum(np.maximum(value, 0.0), 1.0) * (n - 1)  # (np.clip's arithmetic; its wrapper costs more)
    i0 = np.minimum(t.astype(np.int64), n - 2)
    return i0, t - i0


def _lookup1(column, mu):
    i, fi = _coords(np.asarray(mu, dtype=float), column.shape[0])
    return column[i] + (column[i + 1] - column[i]) * fi


def _slice_last(table, r):
    """Interpolate ``table`` along its last axis at the scalar ``r``."""
    j, fj = _coords(np.asarray(float(r)), table.shape[-1])
    return table[..., j] + (table[..., j + 1] - table[..., j]) * fj


def _lookup2(table, mu, r):
    """Bilinear interpolation of a [mu, r] table at arrays ``mu``, ``r`` (uniform 0..1 grids).
    A single roughness (the usual case: one material, many directions) reduces the table to a
    column first."""
    r = np.asarray(r, dtype=float)
    if r.size == 1:
        return _lookup1(_slice_last(table, r.reshape(-1)[0]), mu) * np.ones(r.shape)
    mu, r = np.broadcast_arrays(np.asarray(mu, dtype=float), r)
    i, fi = _coords(mu, table.shape[0])
    j, fj = _coords(r, table.shape[1])
    flat, row = table.reshape(-1), table.shape[1]  # (one flat index: cheaper than a pair of index arrays)
    at = i * row + j
    t00, t01 = flat[at], flat[at + 1]
    t10, t11 = flat[at + row], flat[at + row + 1]
    top = t00 + (t01 - t00) * fj
    bottom = t10 + (t11 - t10) * fj
    return top + (bottom - top) * fi


def _lookup3(table, x, mu, r):
    """Trilinear interpolation of an [x, mu, r] table; ``x`` on a uniform 0..1 grid."""
    return _lookup3_tables((table,), x, mu, r)[0]


def _lookup3_tables(tables_, x, mu, r):
    """:func:`_lookup3` of several tables of one shape at the same points (the coordinates and weights
    computed once)."""
    table = tables_[0]
    x = np.asarray(x, dtype=float)
    r = np.asarray(r, dtype=float)
    if x.size == 1 and r.size == 1:
        k, fk = _coords(np.asarray(float(x.reshape(-1)[0])), table.shape[0])
        shape = np.broadcast_shapes(x.shape, r.shape)
        out = []
        for t in tables_:
            plane = t[k] + (t[k + 1] - t[k]) * fk
            out.append(_lookup1(_slice_last(plane, r.reshape(-1)[0]), mu) * np.ones(shape))
        return out
    x, mu, r = np.broadcast_arrays(x, np.asarray(mu, dtype=float), r)
    k, fk = _coords(x, table.shape[0])
    i, fi = _coords(mu, table.shape[1])
    j, fj = _coords(r, table.shape[2])
    plane, row = table.shape[1] * table.shape[2], table.shape[2]  # (one flat index: cheaper than three)
    at = k * plane + i * row + j
    corners = [(dk * plane + di * row + dj, wk * wi * wj)
               for dk, wk in ((0, 1.0 - fk), (1, fk)) for di, wi in ((0, 1.0 - fi), (1, fi))
               for dj, wj in ((0, 1.0 - fj), (1, fj))]
    out = []
    for t in tables_:
        flat = t.reshape(-1)
        acc = 0.0
        for offset, weight in corners:
            acc = acc + flat[at + offset] * weight
        out.append(acc)
    return out


def average_alpha(alpha_x, alpha_y):
    """Geometric mean of an anisotropic alpha pair, used to index isotropic tables."""
    return np.sqrt(np.asarray(alpha_x, dtype=float) * np.asarray(alpha_y, dtype=float))


def ggx_albedo(cos_o, alpha):
    """Directional albedo of the GGX reflection lobe with F = 1 (single scattering)."""
    return _lookup2(tables().ggx_f1, cos_o, np.sqrt(np.asarray(alpha, dtype=float)))


def ggx_schlick_albedo(cos_o, alpha, f0, f90=1.0, f82_tint=None):
    """Directional albedo of a GGX lobe with Schlick (F0, F90) or F82-tint Fresnel (colours)."""
    t = tables()
    r = np.sqrt(np.asarray(alpha, dtype=float))
    a = _lookup2(t.schlick_f0, cos_o, r)[..., None]
    b = _lookup2(t.schlick_f90, cos_o, r)[..., None]
    e = a * np.asarray(f0) + b * np.asarray(f90)
    if f82_tint is not None:
        mu_bar = fresnel.F82_COSINE
        f0 = np.asarray(f0, dtype=float)
        schlick_bar = f0 + (np.asarray(f90) - f0) * (1.0 - mu_bar) ** 5
        coeff = schlick_bar * (1.0 - np.asarray(f82_tint)) / (mu_bar * (1.0 - mu_bar) ** 6)
        e = e - coeff * _lookup2(t.f82_term, cos_o, r)[..., None]
    return e


def ggx_compensation(cos_o, alpha, f0):
    """Multiple-scattering compensation factor 1 + F0 (1 - E) / E for a GGX reflection lobe.

    Reference: Turquin, "Practical multiple scattering compensation for microfacet models",
    2019, eq. 16 (E = single-scattering albedo with F = 1, ``f0`` the lobe's normal-incidence
    Fresnel; a colour). With F0 = 1 the compensated lobe reflects all light at every roughness.
    """
    e = np.maximum(ggx_albedo(cos_o, alpha), 1e-4)[..., None]
    return 1.0 + np.asarray(f0) * (1.0 - e) / e


def dielectric_albedo(cos_o, alpha, eta):
    """Single-scattering reflectance and transmittance ``(R, T)`` of a rough dielectric
    interface for light arriving along a direction with cosine ``cos_o``; ``eta`` is the index
    on the far side over the index on the near side (may be < 1)."""
    t = tables()
    eta = np.asarray(eta, dtype=float)
    # the tables span eta 1/3..3; beyond, their rough-to-smooth ratios at the edge, on the exact smooth
    # Fresnel (an IOR of 25, or OpenPBR's specular_weight raising F0 towards 1, reflects nearly all)
    x = _eta_coordinate(np.clip(eta, 1.0 / 3.0, 3.0))
    r = np.sqrt(np.asarray(alpha, dtype=float))
    smooth = fresnel.fresnel_dielectric(np.maximum(cos_o, MU_FLOOR), eta)
    reflect, loss = _lookup3_tables((t.dielectric_r, t.dielectric_loss), x, cos_o, r)
    reflect = reflect * smooth
    return reflect, np.maximum(1.0 - loss - reflect, 0.0)


def charlie_albedo(cos_o, roughness, visibility="ashikhmin"):
    """Directional albedo of :func:`sheen.conty_kulla_sheen` (per unit colour)."""
    t = tables()
    table = t.charlie_ashikhmin if visibility == "ashikhmin" else t.charlie_lambda
    return _lookup2(table, cos_o, roughness)


def lambert_schlick_albedo(cos_o):
    """int (1 - wo.h)^5 cos_i / pi dwi: the Schlick weight (1 - VdotH)^5 averaged over a
    Lambertian lobe (glTF's ``fresnel_mix`` of the diffuse base)."""
    return _lookup1(tables().lambert_schlick, cos_o)


def oren_nayar_albedo(cos_o, sigma):
    """Directional albedo of :func:`diffuse.oren_nayar` (per unit colour), sigma in [0, 1]."""
    return _lookup2(tables().oren_nayar, cos_o, sigma)


if __name__ == "__main__":  # pragma: no cover - maintenance entry point
    save_tables()
