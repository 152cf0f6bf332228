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

import warnings
from dataclasses import dataclass, field

import numpy as np

from .layering import BSDFModel


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
class SphereGeometry:
    mask: np.ndarray  # (H, W) bool: pixel centre on the sphere
    normal: np.ndarray  # (N, 3) world normals of the masked pixels
    tangent: np.ndarray  # (N, 3)
    bitangent: np.ndarray  # (N, 3)
    shape: tuple[int, int] = field(default=(0, 0))


def sphere_geometry(rig: Rig) -> SphereGeometry:
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
    return SphereGeometry(mask, normal, t, b, (n, n))


def _to_local(v, geo: SphereGeometry) -> np.ndarray:
    v = np.asarray(v, dtype=float)
    return np.stack([np.sum(v * geo.tangent, -1), np.sum(v * geo.bitangent, -1), np.sum(v * geo.normal, -1)], axis=-1)


def shade_sphere(model: BSDFModel, rig: Rig = Rig(), background: bool = True) -> tuple[np.ndarray, np.ndarray]:
    """Render ``model`` on the preview sphere. Returns ``(image, mask)``: linear Rec.709 RGB of
    shape (size, size, 3) and the boolean mask of sphere pixels. With ``background`` the
    environment radiance fills the pixels off the sphere, otherwise they are 0."""
    geo = sphere_geometry(rig)
    wo = _to_local(np.array([0.0, 0.0, 1.0]), geo)
    wi = _to_local(rig.key, geo)
    cos_i = wi[:, 2]
    f = model.evaluate(wi, wo)
    lit = np.where(cos_i > 0.0, cos_i, 0.0)
    if model.thin_walled:
        lit = np.abs(cos_i)
    direct = f * (lit * rig.key_irradiance)[:, None]
    albedo = model.albedo(wo)
    transmit = np.asarray(albedo.transmit)
    if model.volume_absorption is not None and np.any(transmit):
        path = getattr(model, "volume_path_length", None)
        path = rig.volume_path_length if path is None else np.asarray(path, dtype=float)
        transmit = transmit * np.exp(-np.asarray(model.volume_absorption) * np.asarray(path)[..., None])
    radiance = direct + rig.environment_radiance * (np.asarray(albedo.reflect) + transmit)
    radiance = radiance + model.emission(wo)
    coverage = np.asarray(model.opacity, dtype=float)
    radiance = coverage[..., None] * radiance + (1.0 - coverage[..., None]) * rig.environment_radiance
    image = np.full(geo.shape + (3,), rig.environment_radiance if background else 0.0)
    image[geo.mask] = radiance
    return image, geo.mask


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
