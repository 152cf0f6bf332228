"""The lobe evaluator: NumPy BSDFs for OpenPBR Surface, Standard Surface, glTF PBR and
UsdPreviewSurface, directional albedo, lit-sphere previews and CIEDE2000 differences.

Typical use::

    from openpbr_tools.evaluate import build_model, model_for_material
    model = build_model("open_pbr_surface", {"base_metalness": 1.0})
    f = model.evaluate(wi, wo)          # BSDF values, RGB, arrays of directions (local frame)
    e = model.albedo(wo).total          # tabulated directional albedo

Modules: :mod:`.fresnel`, :mod:`.microfacet`, :mod:`.diffuse`, :mod:`.sheen`, :mod:`.thinfilm`
(the lobes, each citing its source; :mod:`.lobes` gathers them), :mod:`.coat` (what a coat does
to the base; shared with the translators), :mod:`.spectral` (the film's spectrum to RGB),
:mod:`.albedo` (tables),
:mod:`.layering` and :mod:`.closures` (mixture-of-lobes algebra), one module per model,
:mod:`.parameters` (Material -> numbers), :mod:`.measure` (albedo, tabulated or by
quadrature), :mod:`.preview` (lit sphere, contact sheet), :mod:`.difference` (CIEDE2000) and
:mod:`.verify` (pairing and comparing the materials of two assets).
"""

from __future__ import annotations

from importlib import import_module

from .layering import Albedo, BSDFModel
from .parameters import ResolvedParameters, resolve, with_values

MODEL_CLASSES = {
    "open_pbr_surface": ("openpbr", "OpenPBRSurface"),
    "standard_surface": ("standard_surface", "StandardSurface"),
    "gltf_pbr": ("gltf", "GltfPbr"),
    "UsdPreviewSurface": ("usd_preview", "UsdPreviewSurface"),
}


def model_class(model: str) -> type[BSDFModel]:
    """The evaluator class of a shading model name (as in ``Material.model``)."""
    try:
        module, name = MODEL_CLASSES[model]
    except KeyError:
        raise KeyError(f"no evaluator for shading model {model!r}") from None
    return getattr(import_module(f"{__name__}.{module}"), name)


def build_model(model: str, values: dict | None = None) -> BSDFModel:
    """An evaluator of ``model`` with table defaults overridden by ``values`` (linear Rec.709
    numbers or NumPy arrays with leading batch axes)."""
    resolved = with_values(model, values or {})
    return model_class(model)(resolved.values)


def model_for_material(material, sampler=None, uvs=None, length_scale: float = 1.0) -> tuple[BSDFModel, ResolvedParameters]:
    """An evaluator for a :class:`~openpbr_tools.model.Material` and how its inputs resolved; with a
    :class:`~.textures.TextureSampler` and ``uvs``, textures are read at those points; lengths times
    ``length_scale`` (:func:`.parameters.resolve`)."""
    resolved = resolve(material, sampler, uvs, length_scale)
    return model_class(material.model)(resolved.values), resolved


__all__ = [
    "Albedo",
    "BSDFModel",
    "MODEL_CLASSES",
    "ResolvedParameters",
    "build_model",
    "model_class",
    "model_for_material",
    "resolve",
    "with_values",
]
