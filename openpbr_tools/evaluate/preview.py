"""Lit-sphere previews: a unit sphere under a uniform environment plus one directional key light,
rendered deterministically to a linear Rec.709 image, and contact sheets of several materials.

The rig (:class:`Rig`) is the one the MaterialX GLSL comparison uses (tests/glsupport.py):

* camera: orthographic, looking down -z, the image spanning [-1.05, 1.05] in x and y, one sample
  at each pixel centre, row 0 at the top; the view direction is +z everywhere;
* sphere: radius 1 at the origin; the tangent follows the longitude (the direction of
  increasing u of a latitude-longitude UV sphere, u = atan2(x, z) / 2 pi), bitangent = N x T;
* key light: a directional light of irradiance ``key_irradiance`` (on a surface facing it)
  arriving from ``key_direction`` (the direction *towards* the light);
* environment: uniform radiance ``environment_radiance`` from every direction; its reflection is
  the material's directional albedo times that radiance, its transmission the energy
  transmittance times the radiance attenuated by the volume over ``volume_path_length`` scene
  units (glTF: ``thickness``), so a clear, non-absorbing sphere disappears (white furnace);
* the key light is not refracted through closed transmissive spheres (no caustics); it does
  reach thin-walled transmission and translucency from behind;
* emission is added; coverage (opacity) blends the shaded sphere with the environment seen
  through it.

Radiance units are those of the rig: an ideal white diffuser facing the key light has radiance
``environment_radiance + key_irradiance / pi`` (:meth:`Rig.white`), the reference white of the
colour differences. Emission (OpenPBR ``emission_luminance`` in nits, glTF ``emissive`` times
strength, ...) is added as radiance in these units, one unit per nit, as MaterialX's renderer
adds it to its lighting.
"""

from __future__ import annotations

import dataclasses
import warnings
from contextlib import nullcontext
from dataclasses import dataclass, field
from functools import lru_cache

import numpy as np

from .layering import BSDFModel
from .textures import UVs


@dataclass(frozen=True)
class Rig:
    size: int = 128
    extent: float = 1.05
    key_direction: tuple[float, float, float] = (-0.45, 0.55, 0.70)
    key_irradiance: float = 2.0
    environment_radiance: float = 0.2
    volume_path_length: float = 1.0

    @property
    def key(self) -> np.ndarray:
        d = np.asarray(self.key_direction, dtype=float)
        return d / np.linalg.norm(d)

    def white(self) -> float:
        """Radiance of an ideal white diffuser facing the key light (the reference white)."""
        return self.environment_radiance + self.key_irradiance / np.pi


@dataclass
class Geometry:
    """Shading points of a preview: the image pixels they cover, their frames and their texture
    coordinates (with screen-space derivatives, for mip-mapped lookups)."""

    mask: np.ndarray  # (H, W) bool: pixel centre on the surface
    normal: np.ndarray  # (N, 3) world normals of the masked pixels
    tangent: np.ndarray  # (N, 3)
    bitangent: np.ndarray  # (N, 3)
    shape: tuple[int, int] = field(default=(0, 0))
    uvs: UVs | None = None


SHAPES = ("sphere", "swatch")


def sphere_geometry(rig: Rig) -> Geometry:
    """The preview sphere. Its texture coordinates are those of a latitude-longitude UV sphere
    with the seam at the back: ``u = 1/2 + atan2(x, z) / 2 pi`` (increasing along the tangent),
    ``v = 1/2 + asin(y) / pi`` (0 at the south pole, V up as in MaterialX). Derivatives per pixel
    step: ``du/dx = 1 / (2 pi z)``, ``du/dy = x y / (2 pi z (x^2 + z^2))``, ``dv/dy = 1 / (pi
    sqrt(1 - y^2))``, ``dv/dx = 0``, times the pixel size."""
    n = rig.size
    c = -rig.extent + (np.arange(n) + 0.5) * (2.0 * rig.extent / n)
    x, y = np.meshgrid(c, -c)  # row 0 at the top (+y)
    r2 = x * x + y * y
    mask = r2 < 1.0
    xs, ys = x[mask], y[mask]
    zs = np.sqrt(1.0 - r2[mask])
    normal = np.stack([xs, ys, zs], axis=-1)
    t = np.stack([zs, np.zeros_like(zs), -xs], axis=-1)
    t_len = np.linalg.norm(t, axis=-1, keepdims=True)
    t = np.where(t_len > 1e-6, t / np.maximum(t_len, 1e-12), np.array([1.0, 0.0, 0.0]))
    b = np.cross(normal, t)
    u = 0.5 + np.arctan2(xs, zs) / (2.0 * np.pi)
    v = 0.5 + np.arcsin(np.clip(ys, -1.0, 1.0)) / np.pi
    step = 2.0 * rig.extent / n
    z = np.maximum(zs, 1e-3)
    ring = np.maximum(xs * xs + zs * zs, 1e-6)
    dx = np.stack([step / (2.0 * np.pi * z), np.zeros_like(z)], axis=-1)
    dy = np.stack([step * xs * ys / (2.0 * np.pi * z * ring), step / (np.pi * np.sqrt(ring))], axis=-1)
    return Geometry(mask, normal, t, b, (n, n), UVs(np.stack([u, v], axis=-1), dx, dy))


@lru_cache(maxsize=8)
def _shared_sphere(rig: Rig) -> Geometry:
    """:func:`sphere_geometry`, built once per rig and read-only: the candidate search renders many
    small spheres, and building the geometry was a tenth of each render."""
    geo = sphere_geometry(rig)
    for array in (geo.mask, geo.normal, geo.tangent, geo.bitangent, geo.uvs.uv, geo.uvs.dx, geo.uvs.dy):
        array.flags.writeable = False
    return geo


def swatch_geometry(rig: Rig) -> Geometry:
    """A flat square facing the camera that fills the image with UV space [0, 1]^2 (u to the
    right, v up): one pixel per ``1 / size`` of UV. Tangent +x, bitangent +y, normal +z."""
    n = rig.size
    centres = (np.arange(n) + 0.5) / n
    u, v = np.meshgrid(centres, 1.0 - centres)
    count = n * n
    ones = np.ones(count)
    zeros = np.zeros(count)
    normal = np.stack([zeros, zeros, ones], axis=-1)
    tangent = np.stack([ones, zeros, zeros], axis=-1)
    bitangent = np.stack([zeros, ones, zeros], axis=-1)
    step = np.full(count, 1.0 / n)
    uvs = UVs(np.stack([u.ravel(), v.ravel()], axis=-1), np.stack([step, zeros], axis=-1),
              np.stack([zeros, step], axis=-1))
    return Geometry(np.ones((n, n), dtype=bool), normal, tangent, bitangent, (n, n), uvs)


def geometry(shape: str, rig: Rig) -> Geometry:
    if shape not in SHAPES:
        raise ValueError(f"unknown preview shape {shape!r} (one of {', '.join(SHAPES)})")
    return sphere_geometry(rig) if shape == "sphere" else swatch_geometry(rig)


def perturbed(geo: Geometry, normal_ts: np.ndarray | None) -> Geometry:
    """``geo`` with its shading normals replaced by tangent-space ``normal_ts`` (N, 3): n =
    normalize(x T + y B + z N), the tangent re-orthogonalised against it (Gram-Schmidt) and
    B = n x T, as MaterialX's ``normalmap`` and glTF's normal textures define the frame. A zero
    or non-finite vector keeps the surface normal."""
    if normal_ts is None:
        return geo
    ts = np.asarray(normal_ts, dtype=float)
    n = ts[:, :1] * geo.tangent + ts[:, 1:2] * geo.bitangent + ts[:, 2:3] * geo.normal
    length = np.linalg.norm(n, axis=-1, keepdims=True)
    ok = np.isfinite(length) & (length > 1e-8)
    n = np.where(ok, n / np.where(ok, length, 1.0), geo.normal)
    t = geo.tangent - n * np.sum(n * geo.tangent, -1, keepdims=True)
    t_len = np.linalg.norm(t, axis=-1, keepdims=True)
    t = np.where(t_len > 1e-6, t / np.maximum(t_len, 1e-12), geo.tangent)
    return dataclasses.replace(geo, normal=n, tangent=t, bitangent=np.cross(n, t))


def turned(frame: Geometry, surface: Geometry, vectors: np.ndarray | None, tangent_space: bool) -> Geometry:
    """``frame`` with its tangent turned towards ``vectors`` (N, 3): a tangent-space direction in
    ``surface``'s (the unperturbed geometry's) frame, as a ``normalmap`` decode gives it, or a
    world-space vector. The tangent is the vector's projection on the frame's tangent plane,
    normalised (where it vanishes the frame's own tangent stays), the bitangent n x t."""
    if vectors is None:
        return frame
    v = np.asarray(vectors, dtype=float)
    if tangent_space:
        v = v[:, :1] * surface.tangent + v[:, 1:2] * surface.bitangent + v[:, 2:3] * surface.normal
    t = v - frame.normal * np.sum(frame.normal * v, -1, keepdims=True)
    length = np.linalg.norm(t, axis=-1, keepdims=True)
    ok = np.isfinite(length) & (length > 1e-6)
    t = np.where(ok, t / np.where(ok, length, 1.0), frame.tangent)
    return dataclasses.replace(frame, tangent=t, bitangent=np.cross(frame.normal, t))


def _to_local(v, geo: Geometry) -> np.ndarray:
    v = np.asarray(v, dtype=float)
    return np.stack([np.sum(v * geo.tangent, -1), np.sum(v * geo.bitangent, -1), np.sum(v * geo.normal, -1)], axis=-1)


def _view(geo: Geometry) -> np.ndarray:
    """The view direction (+z) in ``geo``'s frames; where a perturbed normal put it below the
    surface, lifted just above it."""
    local = _to_local(np.array([0.0, 0.0, 1.0]), geo)
    if not np.any(local[:, 2] < 1e-4):
        return local
    local[:, 2] = np.maximum(local[:, 2], 1e-4)
    return local / np.linalg.norm(local, axis=-1, keepdims=True)


def shade_sphere(model: BSDFModel, rig: Rig = Rig(), background: bool = True) -> tuple[np.ndarray, np.ndarray]:
    """Render ``model`` on the preview sphere. Returns ``(image, mask)``: linear Rec.709 RGB of
    shape (size, size, 3) and the boolean mask of sphere pixels. With ``background`` the
    environment radiance fills the pixels off the sphere, otherwise they are 0."""
    return shade(model, _shared_sphere(rig), rig, background)


#: Per model, the float parameters whose being zero or not switches an evaluator's code path for the
#: whole render: glTF's thickness makes it thin-walled or a volume; a film's tables are built for every
#: pixel's film, weighted or not (OpenPBR's also rescales the transmission where it is off). Parameter sets
#: that differ in one are not stacked. The other lobes (transmission, subsurface, diffuse transmission,
#: attenuation, a preview's opacity) are exact no-ops at weight 0 (the same pixels to 1e-12 stacked as
#: alone: tests/test_evaluate_models.py), so sets with and without them are stacked together: on the
#: generated all-lobes materials the candidate search cost 3.8x the plain conversion with them as
#: switches, 3.5x without (tests/benchmarks/bench_candidates.py --count 600).
STACK_SWITCHES = {
    "gltf_pbr": ("thickness", "iridescence"),
    "open_pbr_surface": ("thin_film_weight",),
    "standard_surface": ("thin_film_thickness",),
    "UsdPreviewSurface": (),
}


def stack_key(model: str, values: dict) -> tuple:
    """What parameter sets of ``model`` must share to be rendered in one stacked evaluation with the
    same pixels as one by one: their names, their booleans and integers (uniform switches), and
    whether each of :data:`STACK_SWITCHES` is zero (for an unbounded length: finite)."""
    key = [model, tuple(values)]
    for name, value in values.items():
        if isinstance(value, float) or (type(value) is np.ndarray and value.dtype.kind == "f"):
            continue  # (most values: a quick way past them)
        array = np.asarray(value)
        if array.dtype.kind in "biu":
            key.append((name, array.shape, array.tobytes()))
    for name in STACK_SWITCHES.get(model, ()):
        if name in values:
            array = np.asarray(values[name], dtype=float)
            key.append((name, bool(((array != 0) & np.isfinite(array)).any()), bool((array == 1).all())))
    return tuple(key)


def shade_sphere_many(model: str, parameter_sets: list[dict], rig: Rig = Rig(),
                      grouped: bool = False) -> list[np.ndarray] | None:
    """Render several constant parameter sets of one shading ``model`` (``ResolvedParameters.values``
    of each) on the preview sphere in one evaluation: the spheres are stacked into one tall image
    whose per-pixel parameters are each set's values, and cut apart again. The same pixels as
    :func:`shade_sphere` (background included) for a fraction of the cost when the sets are many
    (the evaluator's cost is mostly per call, not per pixel). ``None`` when the sets differ in a
    uniform switch (:func:`stack_key`: a boolean such as thin-walled, or a lobe one has and another
    has not), which cannot vary per pixel; ``grouped``: the caller has grouped the sets by that key."""
    from . import model_class  # lazy: the package imports this module

    geo = _shared_sphere(rig)
    count, pixels = len(parameter_sets), int(geo.mask.sum())
    stacked = {}
    if not grouped:
        first = stack_key(model, parameter_sets[0])
        if any(stack_key(model, values) != first for values in parameter_sets[1:]):
            return None  # a uniform switch differs (or a parameter without a default is set in one only)
    for name in parameter_sets[0]:
        values = [values[name] for values in parameter_sets]
        if np.asarray(values[0]).dtype.kind in "biu":
            stacked[name] = parameter_sets[0][name]
            continue
        try:  # each set's value repeated for its pixels, set after set
            stacked[name] = np.repeat(np.asarray(values, dtype=float), pixels, axis=0)
        except ValueError:  # (shapes differ: a scalar beside a colour) broadcast one by one
            arrays = [np.asarray(v, dtype=float) for v in values]
            shape = max((a.shape for a in arrays), key=len)
            stacked[name] = np.concatenate([np.broadcast_to(a, (pixels,) + shape) for a in arrays])
    tall = Geometry(np.tile(geo.mask, (count, 1)), np.tile(geo.normal, (count, 1)), np.tile(geo.tangent, (count, 1)),
                    np.tile(geo.bitangent, (count, 1)), (count * rig.size, rig.size))
    image, _ = shade(model_class(model)(stacked), tall, rig)
    return [image[i * rig.size:(i + 1) * rig.size] for i in range(count)]


def shade(model: BSDFModel, geo: Geometry, rig: Rig = Rig(), background: bool = True,
          environment: "Environment | None" = None, coat_geo: Geometry | None = None) -> tuple[np.ndarray, np.ndarray]:
    """Render ``model`` (constant or per-pixel parameters, one per masked pixel of ``geo``) on
    ``geo``, lit by the rig or by ``environment``; with ``coat_geo`` (the same points, the coat's
    frames) the coat is shaded in its own frame. Returns ``(image, mask)`` as :func:`shade_sphere`."""
    wo = _view(geo)
    coat_wo = _view(coat_geo) if coat_geo is not None else None

    def coat_frame(direction):  # the coat's own frame for the block, when it has one
        if coat_geo is None:
            return nullcontext()
        return model.coat_frame(None if direction is None else _to_local(direction, coat_geo), coat_wo)

    ambient = rig.environment_radiance if environment is None else environment.mean
    lights = [(rig.key, rig.key_irradiance)] if environment is None else environment.lights
    direct = 0.0
    albedo = None
    for direction, irradiance in lights:
        wi = _to_local(direction, geo)
        cos_i = wi[:, 2]
        lit = np.abs(cos_i) if model.thin_walled else np.where(cos_i > 0.0, cos_i, 0.0)
        if not np.any(lit):
            continue
        with coat_frame(direction):
            if len(lights) == 1:  # the one light's pass over the lobes gives the albedos too
                f, albedo = model.evaluate_and_albedo(wi, wo)
            else:
                f = model.evaluate(wi, wo)
        direct = direct + f * lit[:, None] * np.asarray(irradiance, dtype=float)
    if albedo is None:
        with coat_frame(None):
            albedo = model.albedo(wo)
    transmit = np.asarray(albedo.transmit)
    if model.volume_absorption is not None and np.any(transmit):
        path = getattr(model, "volume_path_length", None)
        path = rig.volume_path_length if path is None else np.asarray(path, dtype=float)
        transmit = transmit * np.exp(-np.asarray(model.volume_absorption) * np.asarray(path)[..., None])
    radiance = direct + ambient * (np.asarray(albedo.reflect) + transmit)
    radiance = radiance + model.emission(wo)
    coverage = np.asarray(model.opacity, dtype=float)
    radiance = coverage[..., None] * radiance + (1.0 - coverage[..., None]) * ambient
    image = np.zeros(geo.shape + (3,))
    if background:
        image[:] = ambient
    image[geo.mask] = np.broadcast_to(radiance, (int(geo.mask.sum()), 3))
    return image, geo.mask


@dataclass
class Environment:
    """A latitude-longitude environment reduced for the evaluator: its mean radiance lights every
    point through the directional albedo (exact for a uniform environment, as the rig's), and the
    brightest cells of a 16 x 32 grid, where they exceed that mean, act as directional lights
    carrying their excess irradiance (radiance above the mean times the cell's solid angle).
    Deterministic; no ray tracing, no GL."""

    mean: np.ndarray  # (3,) mean radiance (solid-angle weighted)
    lights: list  # [(direction (3,), irradiance (3,))]

    @classmethod
    def from_latlong(cls, radiance: np.ndarray, count: int = 24) -> "Environment":
        """``radiance``: (H, W, 3) linear Rec.709 in MaterialX's latitude-longitude layout
        (``mx_latlong_projection``: ``u = 1/2 + atan2(x, -z) / 2 pi``, ``v = 1/2 - asin(y) / pi``,
        row 0 up), i.e. the direction of (u, v) is ``(-sin(2 pi u) sin(pi v), cos(pi v),
        cos(2 pi u) sin(pi v))``."""
        rows, cols = 16, 32
        h, w = radiance.shape[:2]
        grid = np.zeros((rows, cols, 3))
        for j in range(rows):
            for i in range(cols):
                block = radiance[j * h // rows:max(j * h // rows + 1, (j + 1) * h // rows),
                                 i * w // cols:max(i * w // cols + 1, (i + 1) * w // cols), :3]
                grid[j, i] = block.reshape(-1, 3).mean(axis=0)
        theta = np.pi * (np.arange(rows) + 0.5) / rows
        phi = 2.0 * np.pi * (np.arange(cols) + 0.5) / cols
        solid = (2.0 * np.pi / cols) * (np.cos(np.pi * np.arange(rows) / rows) - np.cos(np.pi * (np.arange(rows) + 1) / rows))
        weights = np.repeat(solid[:, None], cols, axis=1)
        mean = (grid * weights[..., None]).sum(axis=(0, 1)) / (4.0 * np.pi)
        excess = np.clip(grid - mean, 0.0, None) * weights[..., None]
        order = np.argsort(-excess.sum(axis=-1), axis=None, kind="stable")[:count]
        lights = []
        for index in order:
            j, i = divmod(int(index), cols)
            if not np.any(excess[j, i] > 0):
                continue
            d = np.array([-np.sin(phi[i]) * np.sin(theta[j]), np.cos(theta[j]), np.cos(phi[i]) * np.sin(theta[j])])
            lights.append((d, excess[j, i]))
        return cls(mean, lights)


def encode_srgb(linear: np.ndarray) -> np.ndarray:
    """sRGB-encode linear Rec.709 values (IEC 61966-2-1 via colour-science), clipped to [0, 1],
    as 8-bit integers."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        import colour  # lazy: colour-science costs ~0.5 s to import
    encoded = colour.models.eotf_inverse_sRGB(np.clip(linear, 0.0, 1.0))
    return np.round(np.clip(encoded, 0.0, 1.0) * 255.0).astype(np.uint8)


def contact_sheet(swatches: list[tuple[str, np.ndarray]], columns: int | None = None, label_height: int = 18):
    """Lay out (name, linear image) swatches in a grid with each name under its swatch; returns a
    ``PIL.Image`` (sRGB-encoded). Needs Pillow (the ``images`` extra)."""
    from PIL import Image, ImageDraw, ImageFont  # lazy: Pillow is optional (the ``images`` extra)

    if not swatches:
        raise ValueError("no swatches")
    size = swatches[0][1].shape[0]
    columns = columns or min(len(swatches), 6)
    rows = (len(swatches) + columns - 1) // columns
    sheet = Image.new("RGB", (columns * size, rows * (size + label_height)), (32, 32, 32))
    draw = ImageDraw.Draw(sheet)
    font = ImageFont.load_default()
    for k, (name, image) in enumerate(swatches):
        col, row = k % columns, k // columns
        x0, y0 = col * size, row * (size + label_height)
        sheet.paste(Image.fromarray(encode_srgb(image), "RGB"), (x0, y0))
        label = name
        if draw.textlength(label, font=font) > size - 4:
            while len(label) > 1 and draw.textlength(label + "...", font=font) > size - 4:
                label = label[:-1]
            label += "..."
        width = draw.textlength(label, font=font)
        draw.text((x0 + (size - width) / 2, y0 + size + 3), label, fill=(230, 230, 230), font=font)
    return sheet
