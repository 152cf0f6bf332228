"""The judge of the candidate search (:mod:`.candidates`) and of the appearance fit
(:mod:`.appearance`): a source rendered once on the evaluator's lit sphere (:class:`Judge`), and
renders of many parameter sets in as few stacked evaluations as their switches allow
(:func:`render_many`, :func:`scores_many`; the same pixels as one by one, films on the coarse cosine
table), so that a file's materials are weighed together.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from .. import colorspaces
from ..model import Constant, Material

RIG_SIZE = 16  # pixels of the evaluator's sphere for the candidate search


def constant_values(material: Material) -> dict | None:
    """Input name -> value of ``material`` when every authored input is a constant, else None (a
    textured or connected material: the candidate search and the appearance fit weigh values only)."""
    values = {}
    for name, entry in material.inputs.items():
        if not isinstance(entry.value, Constant):
            return None
        values[name] = entry.value.value
    return values


class Judge:
    """The source's render on the evaluator's lit sphere of ``size`` pixels (films on the coarse cosine
    table), rendered once, against which candidates are scored (:meth:`scores`); its mask and mean
    radiance (``goal``) are what :mod:`.appearance` fits to (on renders stacked across judges)."""

    def __init__(self, source: Material | None, size: int = RIG_SIZE, reference: np.ndarray | None = None):
        # lazy: the evaluator loads its albedo tables; only an approximated constant material needs it
        from ..evaluate import model_for_material
        from ..evaluate.preview import Rig, shade_sphere  # lazy: as above
        from ..evaluate.thinfilm import coarse_films  # lazy: as above

        self.rig = Rig(size=size)
        if reference is None:
            with coarse_films():
                reference, _ = shade_sphere(model_for_material(source)[0], self.rig)
        self.reference, self.mask = reference, _sphere_mask(self.rig)
        self.goal = self.reference[self.mask].mean(axis=0)

    @classmethod
    def many(cls, sources: list[Material], size: int = RIG_SIZE) -> list["Judge"]:
        """A judge for each of ``sources``, their references rendered in stacked evaluations
        (:func:`render_many`)."""
        from ..evaluate import resolve  # lazy: as in __init__
        from ..evaluate.preview import Rig  # lazy: as above

        rig = Rig(size=size)
        images = render_many([(s.model, resolve(s).values) for s in sources], rig)
        return [cls(None, size, image) for image in images]

    def images(self, model: str, value_sets: list[dict]) -> list[np.ndarray]:
        """Renders of ``value_sets`` (resolved values of ``model``) on this judge's sphere
        (:func:`render_many`)."""
        return render_many([(model, values) for values in value_sets], self.rig)

    def scores(self, materials: list[Material]) -> list[float]:
        """Mean CIEDE2000 of each of ``materials`` (one shading model, as written: :func:`as_written`)
        against the source."""
        from ..evaluate.difference import delta_e_2000  # lazy: as in __init__

        images = self.images(materials[0].model, [as_written(m) for m in materials])
        delta = delta_e_2000(np.concatenate([image[self.mask] for image in images]),
                             np.tile(self.reference[self.mask], (len(images), 1)), self.rig.white())
        return [float(block.mean()) for block in np.split(delta, len(images))]


#: Per model, the inputs whose effect is the sharpness of reflections and refractions: how much a lobe blurs what
#: it reflects or lets through. The judges' lit sphere sees them only in the key light's highlight and through
#: energy, since its environment is uniform: a mirror and a frosted glass of the same albedo look alike on it,
#: while any real surrounding shows the difference (red team G's F2: the OpenPBR Shader Playground's bubbles,
#: whose graphs' result sets Standard Surface's specular_roughness to its coat's 0, measured 2.15 against the
#: mapping's 2.91 on the evaluator and 8.76 against 2.66 in MaterialX's GLSL under an HDR environment). A
#: candidate is therefore not chosen for a change of these (candidates.py).
SHARPNESS = {
    "standard_surface": ("specular_roughness", "specular_anisotropy", "transmission_extra_roughness",
                         "coat_roughness", "coat_anisotropy", "coat_affect_roughness"),
    "gltf_pbr": ("roughness", "clearcoat_roughness", "anisotropy_strength"),
    "UsdPreviewSurface": ("roughness", "clearcoatRoughness"),
    "open_pbr_surface": ("specular_roughness", "specular_roughness_anisotropy", "coat_roughness",
                         "coat_roughness_anisotropy"),
}


#: Per target, the colours its files hold in linear Rec.709 within [0, 1] whatever the document's space
#: (glTF's writer converts them and brings them inside: colorspaces.into_gamut), and those it holds at or above 0
#: (its emissive goes past 1 into emissiveStrength).
CLAMPED_IN_FILE = {"gltf_pbr": ("base_color", "sheen_color", "attenuation_color")}
NON_NEGATIVE_IN_FILE = {"gltf_pbr": ("emissive",)}


def as_written(material: Material) -> dict:
    """The resolved values of ``material`` as its file will hold them (:data:`CLAMPED_IN_FILE`,
    :data:`NON_NEGATIVE_IN_FILE`): a wide-gamut colour the glTF writer brings inside glTF's range is judged so (a gold
    whose graphs' result scored 0.22 unclamped measured 1.42 in the file; an ACEScg emission, 17 mean CIEDE2000 off
    in its file, was judged as it was)."""
    from ..evaluate import resolve  # lazy: as in Judge

    values = resolve(material).values
    for names, high in ((CLAMPED_IN_FILE, 1.0), (NON_NEGATIVE_IN_FILE, None)):
        for name in names.get(material.model, ()):
            value = np.asarray(values[name], dtype=float) if name in values else None
            if value is not None and value.shape == (3,):
                values[name] = np.asarray(colorspaces.into_gamut(value, high=high))
            elif value is not None:  # (per texel: clipped)
                values[name] = np.clip(value, 0.0, np.inf if high is None else high)
    return values


def _sphere_mask(rig) -> np.ndarray:
    from ..evaluate.preview import _shared_sphere  # lazy: as in Judge

    return _shared_sphere(rig).mask


def render_many(sets: list[tuple[str, dict]], rig) -> list[np.ndarray]:
    """Renders of (model, resolved values) pairs on ``rig``'s sphere (films on the coarse table):
    those whose switches agree (:func:`~openpbr_tools.evaluate.preview.stack_key`) in one stacked evaluation each
    (:func:`~openpbr_tools.evaluate.preview.shade_sphere_many`, the same pixels as one by one)."""
    from ..evaluate import build_model  # lazy: as in Judge
    from ..evaluate.preview import shade_sphere, shade_sphere_many, stack_key  # lazy: as above
    from ..evaluate.thinfilm import coarse_films  # lazy: as above

    groups: dict = {}
    for index, (model, values) in enumerate(sets):
        groups.setdefault(stack_key(model, values), []).append(index)
    images: list = [None] * len(sets)
    with coarse_films():
        for key, indices in groups.items():
            model = key[0]
            stacked = shade_sphere_many(model, [sets[i][1] for i in indices], rig, grouped=True) \
                if len(indices) > 1 else None
            for position, index in enumerate(indices):
                images[index] = stacked[position] if stacked is not None else \
                    shade_sphere(build_model(model, sets[index][1]), rig)[0]
    return images


def scores_many(judges: list[Judge], materials: list[list[Material]]) -> list[list[float]]:
    """Mean CIEDE2000 of each material of ``materials[i]`` against ``judges[i]``'s source, all
    rendered in as few stacked evaluations as their switches allow and compared in one call."""
    return [[figure.score for figure in group] for group in figures_many(judges, materials)]


class Figure(NamedTuple):
    """A material's render judged: its mean CIEDE2000 against the source, and its mean linear Rec.709
    radiance over the sphere (what :mod:`.appearance` fits)."""
    score: float
    mean: np.ndarray


def figures_many(judges: list[Judge], materials: list[list[Material]]) -> list[list[Figure]]:
    """:func:`scores_many` with each render's mean radiance (:class:`Figure`), from the same renders."""
    flat = [(judge, material.model, as_written(material)) for judge, group in zip(judges, materials) for material in group]
    figures = figures_of(flat) if flat else []
    out, start = [], 0
    for group in materials:
        out.append(figures[start:start + len(group)])
        start += len(group)
    return out


def figures_of(renders: list[tuple[Judge, str, dict]], scored: list[bool] | None = None) -> list[Figure]:
    """The :class:`Figure` of each (judge, model, resolved values) render (the judges share one rig), all
    rendered together (:func:`render_many`) and compared in one call; with ``scored`` (a flag per render)
    only the flagged are compared with their source (the others' score is NaN: only their mean is wanted)."""
    from ..evaluate.difference import delta_e_2000  # lazy: as in Judge

    rig, mask = renders[0][0].rig, renders[0][0].mask
    images = render_many([(model, values) for _, model, values in renders], rig)
    flagged = [i for i in range(len(renders)) if scored is None or scored[i]]
    scores = [float("nan")] * len(renders)
    if flagged:
        delta = delta_e_2000(np.concatenate([images[i][mask] for i in flagged]),
                             np.concatenate([renders[i][0].reference[mask] for i in flagged]), rig.white())
        for i, block in zip(flagged, np.split(delta, len(flagged))):
            scores[i] = float(block.mean())
    return [Figure(score, image[mask].mean(axis=0)) for score, image in zip(scores, images)]
