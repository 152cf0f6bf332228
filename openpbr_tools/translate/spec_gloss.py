"""glTF's archived KHR_materials_pbrSpecularGlossiness as OpenPBR.

The extension (Khronos, archived, superseded by KHR_materials_specular) gives a diffuse colour D, an F0
colour S and a glossiness g, each a factor times a texture (the RGB of both textures sRGB-encoded, the
glossiness in the specular texture's linear alpha; the diffuse alpha is the coverage), and defines the
BRDF inputs as ``c_diff = D (1 - max(S))``, ``F0 = S`` and ``alpha = (1 - g)^2``. A viewer that reads the
extension renders those and ignores the material's metallic-roughness fallback, so a conversion does too
(the fallback of a file that authors none is glTF's default, a white rough metal).

That is the specular workflow of :mod:`.specular_workflow` with the extension's strength, the maximum of
S (the share of light its lobe takes from the diffuse): OpenPBR's base colour, metalness and dielectric
IOR come from the published spec-gloss -> metal-rough solve (Babylon.js, Microsoft's glTF-Toolkit, which
use the same ``1 - max(S)``) applied to the extension's BRDF input ``c_diff``, not to D: its diffuse is
``c_diff`` under a Fresnel lobe that takes light again, as OpenPBR's dielectric base is under its
specular layer (on the evaluator, a grey F0 of 0.04 / 0.25 over D (0.5, 0.4, 0.3) measured 0.77 / 4.16 with
D, 0.28 / 0.33 with c_diff). A grey S is a dielectric of F0 S over c_diff, up to the two Fresnel curves; a
black diffuse is the metal of F0 S. ``specular_roughness`` is
``1 - g`` exactly (both are alpha's square root); the diffuse alpha is the material's alpha, read with its
alphaMode as glTF's. With textures the solve runs per texel (the baker; the diffuse and specular textures
must share their UVs). Everything else on the material (normal, occlusion, emission, alpha mode, double
sidedness) is the glTF translation's as for any glTF material. The extension stays in the glTF state, so
that a glTF written back has it again.
"""

from __future__ import annotations

import copy
import dataclasses

import numpy as np

from ..io.gltf.slots import SPECULAR_GLOSSINESS, SPECULAR_GLOSSINESS_SLOTS
from ..model import Constant, Input, Material, Texture
from ..rules.translation import CONVERTED
from . import specular_workflow
from .common import Mapping, Settings, Translation, translate
from .fit import ior_from_f0

#: The extension's specular strength: its diffuse is D (1 - max(S)).
STRENGTH = "max"
#: The extension's defaults (its schema), which the preview's inputs the solve reads them by do not share.
DEFAULTS = {name: slot.default for name, slot in SPECULAR_GLOSSINESS_SLOTS}
#: OpenPBR inputs the extension decides (the metallic-roughness fallback's are not read).
DECIDED = ("base_color", "base_metalness", "specular_ior", "specular_roughness", "specular_color")
#: glTF inputs of the fallback a reader of the extension ignores (its alpha: the diffuse alpha's).
FALLBACK = ("base_color", "alpha", "metallic", "roughness")
NOTE = ("the extension's diffuse colour and F0 colour become a metal share and a dielectric one (one base colour, one "
        "metalness: the spec-gloss -> metal-rough solve of Babylon.js and glTF-Toolkit on the extension's "
        "c_diff = diffuse (1 - max(specular)), dielectric F0 the specular colour's smallest channel; a grey specular "
        "colour splits exactly)")


def state_of(material: Material) -> dict | None:
    """The extension's inputs the glTF reader found (``extra["gltf"]["spec_gloss"]``: diffuseColor, opacity,
    specularColor, glossiness), or None for a material without the extension."""
    if material.model != "gltf_pbr":
        return None
    state = material.gltf_state()
    found = state.get("spec_gloss")
    return found if isinstance(found, dict) else None


def textured(material: Material) -> bool:
    """Whether the extension reads a texture (then a glTF output cannot copy it as it was)."""
    return any(isinstance(entry, Input) and isinstance(entry.value, Texture) for entry in (state_of(material) or {}).values())


def _readable(entry: Input | None) -> bool:
    """Whether the reader could read ``entry`` (a finite constant or a texture): another (a value of the
    wrong type, a dangling texture; reported by validation) is read as the extension's default."""
    if entry is None:
        return False
    if isinstance(entry.value, Texture):
        return True
    return isinstance(entry.value, Constant) and bool(np.all(np.isfinite(np.asarray(entry.value.value, dtype=float))))


def constant(material: Material) -> bool:
    """Whether ``material`` has the extension with constant factors only (what the candidate search and the
    appearance fit weigh)."""
    found = state_of(material)
    return found is not None and all(isinstance(entry.value, Constant) for entry in found.values())


def without_fallback(material: Material) -> Material:
    """``material`` (a glTF material with the extension) without its metallic-roughness fallback, its alpha
    the diffuse alpha: what the glTF translation reads before :func:`read` decides the rest."""
    found = state_of(material) or {}
    source = copy.copy(material)
    source.inputs = {name: entry for name, entry in material.inputs.items() if name not in FALLBACK}
    opacity = found.get("opacity")
    if opacity is not None:
        source.inputs["alpha"] = dataclasses.replace(opacity, name="alpha")
    return source


def read(result: Translation, material: Material, settings: Settings) -> None:
    """Set the :data:`DECIDED` OpenPBR inputs of ``result`` (the glTF translation of
    :func:`without_fallback`, without its mappings of those inputs) from the extension's diffuse, specular
    and glossiness (module docstring), with the notes of how they were read."""
    found = state_of(material) or {}
    workflow = Material(name=material.name, model="UsdPreviewSurface", location=material.location,
                        material_name=material.material_name, material_location=material.material_location,
                        colorspace=material.colorspace)
    for name in ("diffuseColor", "specularColor"):  # (unauthored: the extension's default, white; not the preview's)
        workflow.inputs[name] = dataclasses.replace(found[name], name=name) if _readable(found.get(name)) else \
            Input(name, "color3", Constant(DEFAULTS[name]), material.location, colorspace="lin_rec709")
    workflow.inputs["roughness"] = _roughness(found.get("glossiness") if _readable(found.get("glossiness")) else None,
                                              material)
    split = translate(workflow, "open_pbr_surface", _mappings() if settings.specular_split else _tinted(), (),
                      settings, "glTF KHR_materials_pbrSpecularGlossiness -> OpenPBR")
    result.material.inputs.update({name: entry for name, entry in split.material.inputs.items() if name in DECIDED})
    result.diagnostics += split.diagnostics
    state = result.material.extra.get("gltf")
    if isinstance(state, dict):  # the result is no specular-glossiness material: judged by its own values
        state.pop("spec_gloss", None)  # and the extension is not kept to be written back beside them
        kept = {k: v for k, v in (state.get("extensions") or {}).items() if k != SPECULAR_GLOSSINESS}
        if kept:
            state["extensions"] = kept
        else:
            state.pop("extensions", None)
    where = next((entry.location for entry in found.values()), material.location)
    result.diagnostics.append(settings.context.diagnostic(
        CONVERTED, f"{material.name} (glTF -> OpenPBR): KHR_materials_pbrSpecularGlossiness read as a viewer that "
                   "supports it renders it (its metallic-roughness fallback is not used): specular_roughness is "
                   "1 - glossiness, the base colour, metalness and IOR the spec-gloss -> metal-rough solve", where))


def c_diff(diffuse, specular):
    """The extension's diffuse BRDF input, ``D (1 - max(S))``: what the solve splits (the dielectric's share
    of it is under a lobe that takes its own light again, as OpenPBR's dielectric is)."""
    return np.asarray(diffuse, dtype=np.float64) * (1.0 - np.max(np.clip(specular, 0.0, 1.0), axis=-1, keepdims=True))


def _mappings() -> tuple[Mapping, ...]:
    def solved(diffuse, specular):
        return specular_workflow.split(c_diff(diffuse, specular), specular, STRENGTH)

    def base_color(diffuse, specular):
        return solved(diffuse, specular)[1]

    def metalness(diffuse, specular):
        return solved(diffuse, specular)[0]

    def specular_ior(diffuse, specular):  # (a full metal's IOR is unused: the default, not a huge number)
        m, _, a = solved(diffuse, specular)
        return np.where(m >= 1.0 - 1e-9, 1.5, ior_from_f0(a))

    def dielectric(diffuse, specular) -> bool:  # some of it is a dielectric (a black diffuse: the metal of F0 S)
        return bool(np.any(metalness(diffuse, specular) < 1.0 - 1e-9))

    def split_apart(diffuse, specular) -> bool:  # a coloured F0 over a diffuse (a grey one splits exactly)
        colour = np.asarray(specular, dtype=np.float64)
        return bool(np.any(np.ptp(colour, axis=-1) > 1e-6)) and dielectric(diffuse, specular)

    return (
        Mapping("base_color", ("diffuseColor", "specularColor"), base_color, exact=False, matters=split_apart,
                note=NOTE),
        Mapping("base_metalness", ("diffuseColor", "specularColor"), metalness, exact=False, matters=split_apart,
                note=NOTE),
        Mapping("specular_ior", ("diffuseColor", "specularColor"), specular_ior, exact=False, matters=dielectric,
                note="the dielectric share's F0 (the specular colour's smallest channel) as an IOR: OpenPBR's "
                     "dielectric follows Fresnel's curve where the extension's follows Schlick's"),
        Mapping("specular_roughness", ("roughness",), converted="1 - glossiness"),
    )


def _tinted() -> tuple[Mapping, ...]:
    """The second reading (``Settings.specular_split`` off; the candidate search weighs it beside the solve
    for constant materials): a dielectric over ``c_diff`` whose F0 is the specular colour's largest channel,
    tinted by the colour (OpenPBR's specular_color, which tints the edge as well)."""
    def peak(specular):
        return np.max(specular, axis=-1, keepdims=True)

    def tint(specular):
        top = peak(specular)
        return np.where(top > 0, specular / np.where(top > 0, top, 1.0), 1.0)

    return (
        Mapping("base_color", ("diffuseColor", "specularColor"), c_diff),
        Mapping("specular_ior", ("specularColor",), lambda specular: ior_from_f0(peak(specular)), exact=False,
                note="the specular colour's largest channel as a dielectric's F0 (Fresnel's curve, not Schlick's)"),
        Mapping("specular_color", ("specularColor",), tint, exact=False,
                note="the specular colour over its largest channel tints the dielectric's whole Fresnel curve, "
                     "the edge too (the extension's edge is white)"),
        Mapping("specular_roughness", ("roughness",), converted="1 - glossiness"),
    )


def _roughness(glossiness: Input | None, material: Material) -> Input:
    """``1 - glossiness`` (a readable factor, or the texture's alpha times it): roughness."""
    if glossiness is None:
        return Input("roughness", "float", Constant(0.0), material.location)  # glossiness 1 by default
    value = glossiness.value
    if isinstance(value, Texture):
        texture = copy.copy(value)
        scale = 1.0 if value.scale is None else float(np.reshape(value.scale, -1)[0])
        bias = 0.0 if value.bias is None else float(np.reshape(value.bias, -1)[0])
        texture.scale, texture.bias = -scale, 1.0 - bias
        return Input("roughness", "float", texture, glossiness.location)
    return Input("roughness", "float", Constant(1.0 - float(value.value)), glossiness.location)
