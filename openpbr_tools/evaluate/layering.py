"""Albedo-scaling layering and mixing of lobes, and the base class of the model evaluators.

A :class:`Scatter` carries, for one lobe or a combination of lobes evaluated for one set of
directions, the BSDF value f(wi, wo) (RGB; None when only albedos were asked for), the
directional reflectance and transmittance of ``wo`` (RGB; None while BSDF values alone are
evaluated) and the *throughput* 1 - E_top(wo) that a layer lets through to what lies below it.

Layering follows the albedo-scaling approximation used by the OpenPBR specification's
"reduction to a mixture of lobes" and by MaterialX's ``layer`` node:

    f = f_top + f_base * throughput_top(wo),   E = E_top + E_base * throughput_top(wo)

(Kelemen & Szirmay-Kalos, "A Microfacet Based Coupled Specular-Matte BRDF Model with Importance
Sampling", Eurographics 2001; Conty Estevez & Kulla 2017, section 4; OpenPBR Surface 1.1,
section "Reduction to a mixture of lobes"). The scaling depends on wo only, which makes the
layered BSDF non-reciprocal but gives the exact albedo of the combination from the lobes'
albedos. Mixing is statistical: f = (1 - w) f_a + w f_b.
"""

from __future__ import annotations

from contextlib import contextmanager
from contextvars import ContextVar
from dataclasses import dataclass

import numpy as np

_EPS = 1e-7


def as_colour(x) -> np.ndarray:
    """A scalar array of shape S as a colour of shape S + (1,) (broadcasts against RGB)."""
    return np.asarray(x, dtype=float)[..., None]


#: Whether lobes keep their albedos; BSDF evaluation (values only) switches it off, which spares
#: the layering arithmetic on them (throughputs are always kept).
_track_albedo: ContextVar[bool] = ContextVar("track_albedo", default=True)


def _mul(x, w):
    return None if x is None else x * w


def _sum(a, b):
    if a is None:
        return b
    if b is None:
        return a
    return a + b


@dataclass
class Scatter:
    value: np.ndarray | None
    reflect: np.ndarray | None
    transmit: np.ndarray | None
    throughput: np.ndarray

    @staticmethod
    def lobe(value, reflect, transmit=0.0, throughput=None) -> "Scatter":
        """A lobe; ``throughput`` defaults to 1 - (reflect + transmit)."""
        reflect = np.asarray(reflect, dtype=float)
        transmit = np.asarray(transmit, dtype=float)
        if transmit.ndim == 0:
            transmit = np.full(3, float(transmit))
        if throughput is None:
            throughput = 1.0 - reflect - transmit
        if not _track_albedo.get():
            reflect = transmit = None
        return Scatter(value, reflect, transmit, np.asarray(throughput, dtype=float))

    def scaled(self, weight) -> "Scatter":
        """Multiply the response (value and albedos) by ``weight`` (colour-shaped); the
        throughput is unchanged, as for MaterialX's ``multiply`` of a BSDF."""
        w = np.asarray(weight, dtype=float)
        return Scatter(_mul(self.value, w), _mul(self.reflect, w), _mul(self.transmit, w), self.throughput)

    def weighted(self, weight) -> "Scatter":
        """A lobe's presence ``weight``: scales the response and the albedo the lobe takes
        away from what lies below (throughput = 1 - weight (1 - throughput))."""
        w = np.asarray(weight, dtype=float)
        return Scatter(
            _mul(self.value, w), _mul(self.reflect, w), _mul(self.transmit, w), 1.0 - w * (1.0 - self.throughput)
        )


def add(a: Scatter, b: Scatter) -> Scatter:
    """Sum of two lobes (throughputs combine as t_a + t_b - 1, MaterialX ``add``)."""
    return Scatter(
        _sum(a.value, b.value),
        _sum(a.reflect, b.reflect),
        _sum(a.transmit, b.transmit),
        np.maximum(a.throughput + b.throughput - 1.0, 0.0),
    )


def mix(a: Scatter, b: Scatter, weight) -> Scatter:
    """Statistical mixture (1 - weight) a + weight b; ``weight`` colour-shaped (as_colour)."""
    w = np.asarray(weight, dtype=float)
    v = 1.0 - w
    return Scatter(
        _sum(_mul(a.value, v), _mul(b.value, w)),
        _sum(_mul(a.reflect, v), _mul(b.reflect, w)),
        _sum(_mul(a.transmit, v), _mul(b.transmit, w)),
        a.throughput * v + b.throughput * w,
    )


def layer(top: Scatter, base: Scatter) -> Scatter:
    """Albedo-scaling layering of ``top`` over ``base`` (see the module docstring)."""
    t = np.clip(top.throughput, 0.0, 1.0)
    return Scatter(
        _sum(top.value, _mul(base.value, t)),
        _sum(top.reflect, _mul(base.reflect, t)),
        _sum(top.transmit, _mul(base.transmit, t)),
        top.throughput * base.throughput,
    )


def any_nonzero(x) -> bool:
    """True when any element of ``x`` is non-zero (used to skip absent lobes)."""
    return bool((np.asarray(x) != 0.0).any())


def mirror_frame(wi, wo):
    """Return ``(wi, wo, inside)`` with both directions mirrored through the surface where
    ``wo`` is below it, so the model sees the viewer above; ``inside`` marks those entries."""
    inside = wo[..., 2] < 0.0
    if not np.any(inside):
        return wi, wo, inside
    sign = np.where(inside, -1.0, 1.0)
    wo = np.concatenate([wo[..., :2], (wo[..., 2] * sign)[..., None]], axis=-1)
    if wi is not None:
        wi_b, sign_b = np.broadcast_arrays(wi[..., 2], sign)
        wi = np.concatenate([np.broadcast_to(wi[..., :2], wi_b.shape + (2,)), (wi_b * sign_b)[..., None]], axis=-1)
    return wi, wo, inside


@dataclass
class Albedo:
    """Directional albedo of a whole material for a view direction: ``reflect`` and
    ``transmit`` (energy transmittance), RGB."""

    reflect: np.ndarray
    transmit: np.ndarray

    @property
    def total(self) -> np.ndarray:
        return self.reflect + self.transmit


class BSDFModel:
    """Base of the per-model evaluators. Subclasses implement :meth:`_scatter` for ``wo`` above
    the surface (and ``wi`` None when only albedos are needed), :meth:`emission` and set
    ``opacity``; parameters are the resolved arrays of :mod:`.parameters`.

    ``thin_walled`` (bool) and ``volume_absorption`` (RGB absorption coefficient per scene unit,
    or None) describe the medium behind the surface for previews.
    """

    model = ""

    def __init__(self, params: dict):
        self.params = params
        self.thin_walled = False
        self.volume_absorption = None
        self.opacity = np.asarray(1.0)
        self.coat_directions = None  # (wi, wo) in the coat's own frame, while a caller sets them

    @contextmanager
    def coat_frame(self, wi, wo):
        """Within the block, the coat (OpenPBR geometry_coat_normal, Standard Surface coat_normal,
        glTF clearcoat_normal) is evaluated with ``wi``/``wo`` expressed in its own shading frame
        (one entry per entry of the directions passed to :meth:`evaluate`/:meth:`albedo`; ``wi``
        None for albedos), the rest of the material in the frame of those directions."""
        previous = self.coat_directions
        self.coat_directions = (wi, wo)
        try:
            yield
        finally:
            self.coat_directions = previous

    def coat_dirs(self, wi, wo):
        """The directions the coat lobe is evaluated with (see :meth:`coat_frame`)."""
        if self.coat_directions is None:
            return wi, wo
        cwi, cwo = self.coat_directions
        return (None if wi is None else cwi), cwo

    # -- to implement
    def _scatter(self, wi, wo, inside) -> Scatter:  # pragma: no cover - abstract
        raise NotImplementedError

    def emission(self, wo) -> np.ndarray:
        """Emitted radiance towards ``wo`` (RGB); zero by default."""
        return np.zeros(np.shape(wo)[:-1] + (3,))

    # -- public API
    def evaluate(self, wi, wo) -> np.ndarray:
        """BSDF value f(wi, wo), RGB, for arrays of unit directions (local frame; last axis xyz).
        Viewers below the surface see the mirrored configuration (inside a closed dielectric
        the relative IOR is inverted)."""
        wi, wo, shape, chunks = self._chunks(wi, wo)
        if chunks is None:
            return self._evaluate(wi, wo)
        out = np.empty((len(wi), 3))
        for part in chunks:
            out[part] = self._evaluate(wi[part], wo[part])
        return out.reshape(shape)

    chunk_size = 16384

    def _chunks(self, wi, wo):
        """(wi, wo, shape of the values, slices) where the directions are evaluated in cache-sized chunks
        (NumPy's temporaries then stay in the CPU cache: many directions, parameters without batch axes,
        no coat frame; the directions flattened), else (wi, wo, shape, None)."""
        wi = np.asarray(wi, dtype=float)
        wo = np.asarray(wo, dtype=float)
        shape = np.broadcast_shapes(wi.shape, wo.shape)[:-1] + (3,)
        count = int(np.prod(shape[:-1]))
        if count <= self.chunk_size or not self._scalar_parameters() or self.coat_directions is not None:
            return wi, wo, shape, None
        flat = (np.broadcast_to(wi, shape).reshape(-1, 3), np.broadcast_to(wo, shape).reshape(-1, 3))
        return (*flat, shape, [slice(start, min(start + self.chunk_size, count))
                               for start in range(0, count, self.chunk_size)])

    def _scalar_parameters(self) -> bool:
        """True when no parameter carries batch axes (then directions can be split freely)."""
        for value in self.params.values():
            if isinstance(value, np.ndarray) and value.ndim > 1:
                return False
            if isinstance(value, np.ndarray) and value.ndim == 1 and value.shape != (3,):
                return False
        return True

    def _evaluate(self, wi, wo) -> np.ndarray:
        wi, wo, inside = mirror_frame(wi, wo)
        token = _track_albedo.set(False)
        try:
            s = self._scatter(wi, wo, inside)
        finally:
            _track_albedo.reset(token)
        shape = np.broadcast_shapes(wi.shape, wo.shape)[:-1] + (3,)
        if s.value is None:
            return np.zeros(shape)
        return np.broadcast_to(s.value, np.broadcast_shapes(s.value.shape, shape))

    def evaluate_and_albedo(self, wi, wo) -> tuple[np.ndarray, Albedo]:
        """:meth:`evaluate` and :meth:`albedo` of ``wo`` from one pass over the lobes (a lobe's albedo
        depends on ``wo`` alone, and its value on neither the albedos nor their tracking: the same
        numbers as the two calls, for about two thirds of their cost), in chunks where :meth:`evaluate`
        would work in chunks."""
        wi, wo, shape, chunks = self._chunks(wi, wo)
        if chunks is None:
            return self._one_pass(wi, wo)
        value, reflect, transmit = (np.empty((len(wi), 3)) for _ in range(3))
        for part in chunks:
            value[part], albedo = self._one_pass(wi[part], wo[part])
            reflect[part], transmit[part] = albedo.reflect, albedo.transmit
        return value.reshape(shape), Albedo(reflect.reshape(shape), transmit.reshape(shape))

    def _one_pass(self, wi, wo) -> tuple[np.ndarray, Albedo]:
        shape = np.broadcast_shapes(wi.shape, wo.shape)[:-1] + (3,)
        wi, wo, inside = mirror_frame(wi, wo)
        s = self._scatter(wi, wo, inside)
        value = np.zeros(shape) if s.value is None else np.broadcast_to(s.value, np.broadcast_shapes(s.value.shape, shape))
        albedo_shape = np.broadcast_shapes(s.reflect.shape, wo.shape[:-1] + (3,))
        return value, Albedo(np.broadcast_to(s.reflect, albedo_shape), np.broadcast_to(s.transmit, albedo_shape))

    def albedo(self, wo) -> Albedo:
        """Tabulated directional albedo of the whole material for view directions ``wo``."""
        wo = np.asarray(wo, dtype=float)
        _, wo, inside = mirror_frame(None, wo)
        s = self._scatter(None, wo, inside)
        shape = np.broadcast_shapes(s.reflect.shape, wo.shape[:-1] + (3,))
        return Albedo(np.broadcast_to(s.reflect, shape), np.broadcast_to(s.transmit, shape))


# ----------------------------------------------------------------------------- geometry helpers


def rotate_about_normal(w, angle):
    """Express directions ``w`` in a tangent frame rotated by ``angle`` (radians, right-handed
    about +z): components along the rotated tangent and bitangent."""
    if w is None:
        return None
    angle = np.asarray(angle, dtype=float)
    if not np.any(angle):
        return w
    c, s = np.cos(angle), np.sin(angle)
    x = w[..., 0] * c + w[..., 1] * s
    y = -w[..., 0] * s + w[..., 1] * c
    x, y, z = np.broadcast_arrays(x, y, w[..., 2])
    return np.stack([x, y, z], axis=-1)


def cosines(wi, wo):
    """``(cos_i, cos_o, cos_io)`` for the diffuse lobes (cos_i/cos_io None without wi)."""
    cos_o = wo[..., 2]
    if wi is None:
        return None, cos_o, None
    return wi[..., 2], cos_o, np.sum(wi * wo, axis=-1)
