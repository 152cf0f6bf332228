"""Verifying translations: render materials on the preview sphere and the texture-space swatch,
pair the materials of two assets and measure their CIEDE2000 differences.

A pair's difference is measured on the lit-sphere previews (every sphere pixel, the same rig for
both; see :mod:`.preview` and :mod:`.difference` for the lighting, exposure and white point), as a
second number on the directional-albedo curves E(mu) at 16 view angles, and, when either material
is textured and a :class:`~.textures.TextureSampler` is given, per texel on the flat swatch that
shows UV space [0, 1]^2 (one pixel per texel of the finest texture, up to
:data:`MAX_SWATCH`), where a swapped channel, a flipped V or a lost normal map shows wherever the
texture varies. Textures are read per pixel on both shapes; without a sampler they are
evaluated at their fallbacks (and listed in the notes).
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass, field

import numpy as np

from . import model_for_material
from .difference import DeltaE, compare_albedo, delta_e_2000, summarize
from .measure import directional_albedo
from .preview import Rig, geometry, perturbed, shade, turned
from .parameters import TANGENT_ANISOTROPY, scene_unit

#: View cosines at which albedo curves are compared.
ALBEDO_COSINES = np.linspace(0.05, 1.0, 16)
#: Largest texture-space swatch (pixels per side) a comparison renders.
MAX_SWATCH = 512


@dataclass
class Swatch:
    name: str
    model: str
    image: np.ndarray
    mask: np.ndarray
    notes: list[str] = field(default_factory=list)
    textured: bool = False  # some texture was read per pixel


def _render(material, rig: Rig, sampler, shape: str, environment=None, length_scale: float = 1.0):
    geo = geometry(shape, rig)
    model, resolved = model_for_material(material, sampler, geo.uvs if sampler is not None else None, length_scale)
    base_geo, coat_geo = _frames(material.model, geo, resolved)
    image, mask = shade(model, base_geo, rig, environment=environment, coat_geo=coat_geo)
    notes = resolved.notes()
    if sampler is not None:
        prefix = f"{material.name}."
        notes += [f"{owner[len(prefix):]}: {text}" for owner, text in sampler.notes if owner.startswith(prefix)]
    return image, mask, notes, resolved


#: The tangent inputs that turn the base's and the coat's frames, per model (Standard Surface's coat
#: shares the one tangent; glTF turns anisotropy by rotation instead).
TANGENTS = {"open_pbr_surface": ("geometry_tangent", "geometry_coat_tangent"), "standard_surface": ("tangent", "tangent")}


def _frames(model: str, geo, resolved):
    """(base frames, coat frames or None when the coat shares the base's) of ``geo`` after the
    material's normal and tangent maps (see :mod:`.parameters`)."""
    base_tangent, coat_tangent = TANGENTS.get(model, (None, None))
    tangents = resolved.tangents
    base = turned(perturbed(geo, resolved.normal), geo, *tangents.get(base_tangent, (None, False)))
    if resolved.normal is None and resolved.coat_normal is None and not tangents:
        return base, None
    coat = turned(perturbed(geo, resolved.coat_normal), geo, *tangents.get(coat_tangent, (None, False)))
    return base, coat


def render_material(material, rig: Rig = Rig(), sampler=None, shape: str = "sphere", environment=None) -> Swatch:
    """Preview of one :class:`~openpbr_tools.model.Material` on ``shape`` (``sphere`` or
    ``swatch``), its textures read through ``sampler`` when given, lit by the rig or by an
    :class:`~.preview.Environment`; with notes on what was not evaluated."""
    image, mask, notes, resolved = _render(material, rig, sampler, shape, environment)
    return Swatch(material.name, material.model, image, mask, list(dict.fromkeys(notes)), bool(resolved.sampled))


@dataclass
class View:
    """Both materials rendered on one shape, and the per-pixel CIEDE2000 map (NaN off the shape)."""

    shape: str
    image_a: np.ndarray
    image_b: np.ndarray
    delta_e: np.ndarray
    white: float


@dataclass
class MaterialComparison:
    name_a: str
    name_b: str
    model_a: str
    model_b: str
    preview: DeltaE
    albedo: DeltaE
    notes: list[str] = field(default_factory=list)
    swatch: DeltaE | None = None  # per texel on the texture-space swatch, when either side is textured
    views: list[View] = field(default_factory=list)  # kept when asked (images for reports)
    # the inputs, "A name" or "B name", whose textures could not be read (missing, outside the folders allowed): each
    # rendered at its fallback, so the figures say nothing of the conversion there
    unread: list[str] = field(default_factory=list)
    # the inputs, "A name" or "B name", rendered as a procedural stand-in on that side while the other side reads
    # per texel: the figures say nothing of the conversion there (the red team's E#2, E#4)
    stand_ins: list[str] = field(default_factory=list)

    @property
    def worst(self) -> DeltaE:
        """The shape whose mean CIEDE2000 is larger: what a threshold applies to."""
        if self.swatch is not None and not self.swatch.mean <= self.preview.mean:  # a NaN is the worse
            return self.swatch
        return self.preview

    def as_dict(self) -> dict:
        out = {
            "a": {"name": self.name_a, "model": self.model_a},
            "b": {"name": self.name_b, "model": self.model_b},
            "preview": self.preview.as_dict(),
            "albedo": self.albedo.as_dict(),
            "notes": list(self.notes),
            "unread": list(self.unread),
            "stand_ins": list(self.stand_ins),
        }
        if self.swatch is not None:
            out["swatch"] = self.swatch.as_dict()
        return out


def swatch_size(materials, sampler, rig: Rig) -> int:
    """Pixels per side of the texture-space swatch: one per texel of the finest texture of
    ``materials`` (its resolution divided by its place2d scale), at least the rig's size, at most
    :data:`MAX_SWATCH`."""
    size = rig.size
    for material in materials:
        for _, texture in material.textures():
            resolution = sampler.resolution(texture) if sampler is not None else None
            if resolution is None:
                continue
            scale = texture.uv.scale if texture.uv is not None else (1.0, 1.0)
            for extent, s in zip(resolution, scale):
                if s:
                    size = max(size, int(round(extent / abs(s))))
    return min(size, MAX_SWATCH)


def compare_materials(material_a, material_b, rig: Rig = Rig(), sampler=None, keep_images: bool = False,
                      swatch: bool | None = None, sampler_b=None) -> MaterialComparison:
    """CIEDE2000 between the previews and the albedo curves of two materials; with ``sampler``
    (and ``sampler_b`` for the second material, when its textures resolve elsewhere), textures
    are read per pixel and, when either material is textured (or ``swatch`` is True), the
    texture-space swatches are compared too. ``keep_images`` keeps both renders and the ΔE map
    of each shape in ``views``."""
    sampler_b = sampler if sampler_b is None else sampler_b
    scale_b = scene_unit(material_b) / scene_unit(material_a)  # (B's lengths in A's scene unit)
    image_a, mask, notes_a, resolved_a = _render(material_a, rig, sampler, "sphere")
    image_b, _, notes_b, resolved_b = _render(material_b, rig, sampler_b, "sphere", length_scale=scale_b)
    white = rig.white()
    sphere_map = _delta_map(image_a, image_b, mask, white)
    views = [View("sphere", image_a, image_b, sphere_map, white)] if keep_images else []
    textured = bool(resolved_a.sampled or resolved_b.sampled)
    swatch_delta = None
    if sampler is not None and sampler_b is not None and (swatch or (swatch is None and textured)):
        size = max(swatch_size((material_a,), sampler, rig), swatch_size((material_b,), sampler_b, rig))
        flat = dataclasses.replace(rig, size=size)
        flat_a, flat_mask, _, _ = _render(material_a, flat, sampler, "swatch")
        flat_b, _, _, _ = _render(material_b, flat, sampler_b, "swatch", length_scale=scale_b)
        flat_map = _delta_map(flat_a, flat_b, flat_mask, flat.white())
        swatch_delta = summarize(flat_map[flat_mask])
        if keep_images:
            views.append(View("swatch", flat_a, flat_b, flat_map, flat.white()))
    model_a, _ = model_for_material(material_a)
    model_b, _ = model_for_material(material_b, length_scale=scale_b)
    albedo_a = directional_albedo(model_a, ALBEDO_COSINES)
    albedo_b = directional_albedo(model_b, ALBEDO_COSINES)
    albedo = compare_albedo(albedo_a[0] + albedo_a[1], albedo_b[0] + albedo_b[1])
    notes = [f"A {material_a.name}: {n}" for n in dict.fromkeys(notes_a)]
    notes += [f"B {material_b.name}: {n}" for n in dict.fromkeys(notes_b)]
    unread = [f"A {name}" for name in sorted(resolved_a.why_not)] + [f"B {name}" for name in sorted(resolved_b.why_not)]
    stand_a, stand_b = sorted(set(resolved_a.stand_ins)), sorted(set(resolved_b.stand_ins))
    # (one side's stand-in against the other's texels, or against the value a glTF output writes for the graph:
    # convert_textures.graph_fallbacks, session 27's E#15; either way the figure measures the stand-in)
    lopsided = ([f"A {name}" for name in stand_a] if not stand_b else []) + \
        ([f"B {name}" for name in stand_b] if not stand_a else [])
    lopsided += [f"{side} {name}" for side, resolved in (("A", resolved_a), ("B", resolved_b))
                 for name in resolved.tangent_graphs if f"{side} {name}" not in lopsided and _anisotropic(resolved, name)]
    return MaterialComparison(material_a.name, material_b.name, material_a.model, material_b.model,
                              summarize(sphere_map[mask]), albedo, notes, swatch_delta, views, unread, lopsided)


def _anisotropic(resolved, tangent: str) -> bool:
    """Whether the anisotropy ``tangent`` turns is above 0 somewhere (a tangent turns nothing isotropic)."""
    return any(np.any(np.asarray(resolved.values.get(name, 0.0), dtype=float) > 0)
               for name in TANGENT_ANISOTROPY.get(tangent, ()))


def _delta_map(image_a, image_b, mask, white: float) -> np.ndarray:
    out = np.full(mask.shape, np.nan)
    out[mask] = delta_e_2000(image_a[mask], image_b[mask], white)
    return out


@dataclass
class Pairing:
    pairs: list[tuple[object, object]]
    unmatched_a: list[str]
    unmatched_b: list[str]


def pair_materials(materials_a, materials_b) -> Pairing:
    """Pair materials by name; two single-material assets are paired whatever their names."""
    if len(materials_a) == 1 and len(materials_b) == 1:
        return Pairing([(materials_a[0], materials_b[0])], [], [])
    by_name = {m.name: m for m in materials_b}
    pairs, unmatched_a = [], []
    for material in materials_a:
        other = by_name.pop(material.name, None)
        if other is None:
            unmatched_a.append(material.name)
        else:
            pairs.append((material, other))
    return Pairing(pairs, unmatched_a, sorted(by_name))
