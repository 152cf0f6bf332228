"""Measurements on a model: BSDF values and directional albedo E(mu).

``directional_albedo(model, mu, method="tabulated")`` sums the lobes' tabulated albedos
(exact for the albedo-scaling layering the models use); ``method="quadrature"`` integrates the
model's BSDF values numerically over the incident sphere (Gauss-Legendre in cos(theta_i) on
each hemisphere, midpoint rule in phi), which checks the tables but cannot resolve mirror-like
lobes (alpha below ~0.01). The quadrature integrates f(wi, wo) |cos_i| over incident directions;
for refraction into a denser medium this is the radiance transmitted from inside, which is the
energy transmittance divided by eta^2.
"""

from __future__ import annotations

import numpy as np

from .layering import BSDFModel


def view_directions(cos_theta) -> np.ndarray:
    """Unit view directions with the given cosines, in the xz plane (phi = 0)."""
    mu = np.clip(np.asarray(cos_theta, dtype=float), 0.0, 1.0)
    return np.stack([np.sqrt(1.0 - mu * mu), np.zeros_like(mu), mu], axis=-1)


def hemisphere_quadrature(order: int = 64):
    """Directions and weights of a product quadrature of the upper hemisphere:
    Gauss-Legendre in cos(theta) times the midpoint rule in phi (2 * order points)."""
    x, w = np.polynomial.legendre.leggauss(order)
    mu = 0.5 * (x + 1.0)
    w_mu = 0.5 * w
    n_phi = 2 * order
    phi = (np.arange(n_phi) + 0.5) * (2.0 * np.pi / n_phi)
    m, p = np.meshgrid(mu, phi, indexing="ij")
    s = np.sqrt(1.0 - m * m)
    dirs = np.stack([s * np.cos(p), s * np.sin(p), m], axis=-1).reshape(-1, 3)
    weights = (w_mu[:, None] * np.full(n_phi, 2.0 * np.pi / n_phi)).reshape(-1)
    return dirs, weights


def directional_albedo(model: BSDFModel, cos_theta, method: str = "tabulated", order: int = 64):
    """``(reflect, transmit)`` RGB arrays of shape ``cos_theta.shape + (3,)``."""
    wo = view_directions(cos_theta)
    if method == "tabulated":
        a = model.albedo(wo)
        return np.asarray(a.reflect), np.asarray(a.transmit)
    if method != "quadrature":
        raise ValueError(f"unknown method {method!r}")
    dirs, weights = hemisphere_quadrature(order)
    below = dirs * np.array([1.0, 1.0, -1.0])
    reflect, transmit = [], []
    for w in wo.reshape(-1, 3):
        cw = (dirs[:, 2] * weights)[:, None]
        reflect.append(np.sum(model.evaluate(dirs, w[None, :]) * cw, axis=0))
        transmit.append(np.sum(model.evaluate(below, w[None, :]) * cw, axis=0))
    shape = np.shape(cos_theta) + (3,)
    return np.reshape(reflect, shape), np.reshape(transmit, shape)
