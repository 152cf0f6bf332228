"""Verifying translations: render materials on the preview sphere, pair the materials of two
assets and measure their CIEDE2000 differences.

A pair's difference is measured on the lit-sphere previews (every sphere pixel, the same rig for
both; see :mod:`.preview` and :mod:`.difference` for the lighting, exposure and white point) and,
as a second number, on the directional-albedo curves E(mu) at 16 view angles.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from . import model_for_material
from .difference import DeltaE, compare_albedo, compare_images
from .measure import directional_albedo
from .preview import Rig, shade_sphere

#: View cosines at which albedo curves are compared.
ALBEDO_COSINES = np.linspace(0.05, 1.0, 16)


@dataclass
class Swatch:
    name: str
    model: str
    image: np.ndarray
    mask: np.ndarray
    notes: list[str] = field(default_factory=list)


def render_material(material, rig: Rig = Rig()) -> Swatch:
    """Preview of one :class:`~openpbr_tools.model.Material` with notes on what was not evaluated."""
    model, resolved = model_for_material(material)
    image, mask = shade_sphere(model, rig)
    return Swatch(material.name, material.model, image, mask, resolved.notes())


@dataclass
class MaterialComparison:
    name_a: str
    name_b: str
    model_a: str
    model_b: str
    preview: DeltaE
    albedo: DeltaE
    notes: list[str] = field(default_factory=list)

    def as_dict(self) -> dict:
        return {
            "a": {"name": self.name_a, "model": self.model_a},
            "b": {"name": self.name_b, "model": self.model_b},
            "preview": self.preview.as_dict(),
            "albedo": self.albedo.as_dict(),
            "notes": list(self.notes),
        }


def compare_materials(material_a, material_b, rig: Rig = Rig()) -> MaterialComparison:
    """CIEDE2000 between the previews and the albedo curves of two materials."""
    model_a, resolved_a = model_for_material(material_a)
    model_b, resolved_b = model_for_material(material_b)
    image_a, mask = shade_sphere(model_a, rig)
    image_b, _ = shade_sphere(model_b, rig)
    preview = compare_images(image_a, image_b, mask, rig.white())
    albedo_a = directional_albedo(model_a, ALBEDO_COSINES)
    albedo_b = directional_albedo(model_b, ALBEDO_COSINES)
    albedo = compare_albedo(albedo_a[0] + albedo_a[1], albedo_b[0] + albedo_b[1])
    notes = [f"A {material_a.name}: {n}" for n in resolved_a.notes()]
    notes += [f"B {material_b.name}: {n}" for n in resolved_b.notes()]
    return MaterialComparison(material_a.name, material_b.name, material_a.model, material_b.model, preview, albedo, notes)


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
