"""glTF plausibility: extension values that are legal by the schemas but that the extension texts show
render nothing like what was meant, usually a unit or a field mixed up on export.

* KHR_materials_transmission, "Blend Mode": alpha is coverage ("whether the physical surface is there or
  not"), not transparency; "if alpha-as-coverage is not being used, the blend mode of the material should be
  set to OPAQUE even though it is transparent". Glass with alphaMode BLEND and one alpha everywhere is
  transparent twice: its reflections and tint fade with the alpha (an alpha texture is coverage, and legal).
* KHR_materials_iridescence: the film thicknesses are nanometres (defaults 100 and 400); thin-film
  interference needs films of tens to thousands of nanometres, so a maximum below 1 nm is a thickness
  written in micrometres. With a thickness texture the thickness is
  ``mix(iridescenceThicknessMinimum, iridescenceThicknessMaximum, G)``: a minimum above the maximum inverts
  the texture.
* KHR_materials_volume: ``thicknessFactor`` is "given in the coordinate space of the mesh" and should
  "represent the actual thickness as accurate as possible", so one many times the size of every mesh using
  the material (glTF requires POSITION's ``min`` and ``max``) is a length in centimetres or millimetres.
  Light crossing the thickness ``t`` keeps ``attenuationColor ^ (t / attenuationDistance)`` per channel
  (Beer-Lambert, as the README defines the colour "white light turns into ... when reaching the attenuation
  distance"): a black colour, or a ratio that leaves less than :data:`TRANSMITTANCE_FLOOR` in every channel,
  makes the glass black.

* glTF 2.0 (3.9.3): the emission, ``emissiveFactor`` times the emissive texture, is added to the reflected light; a
  factor of [1, 1, 1] without a texture on a material whose base colour is textured makes the surface flat white and
  the texture invisible (an exporter's default emission colour, its strength of 0 lost).

Only constants are judged (a textured thickness varies, and a textured alpha is coverage).
"""

from __future__ import annotations

import math

from ..diagnostics import Severity
from ..io.gltf import slots
from ..model import Location, Texture
from . import Rule, constant_or_default
from .gltf import _gltf

_GLASS = '"pbrMetallicRoughness": {"metallicFactor": 0.0, "baseColorFactor": [1, 1, 1, ALPHA]}'


def _glass(alpha_mode: str, alpha: float) -> str:
    return _gltf('"extensionsUsed": ["KHR_materials_transmission"]',
                 '"materials": [{"name": "M", "alphaMode": "' + alpha_mode + '", ' + _GLASS.replace("ALPHA", str(alpha))
                 + ', "extensions": {"KHR_materials_transmission": {"transmissionFactor": 1.0}}}]')


def _iridescent(low: float, high: float) -> str:
    return _gltf('"extensionsUsed": ["KHR_materials_iridescence"]',
                 '"images": [{"uri": "data:image/png;base64,iVBORw0KGgoAAAANSUhEUgAAAAQAAAAECAIAAAAmkwkpAAAAFElEQVR42mM8kW'
                 'LEAANMDEgANwcARfYBZsiXQosAAAAASUVORK5CYII="}]', '"textures": [{"source": 0}]',
                 '"materials": [{"name": "M", "extensions": {"KHR_materials_iridescence": {"iridescenceFactor": 1.0, '
                 f'"iridescenceThicknessTexture": {{"index": 0}}, "iridescenceThicknessMinimum": {low}, '
                 f'"iridescenceThicknessMaximum": {high}}}}}}}]')


def _volume(volume: str) -> str:
    return _gltf('"extensionsUsed": ["KHR_materials_transmission", "KHR_materials_volume"]',
                 '"materials": [{"name": "M", "pbrMetallicRoughness": {"metallicFactor": 0.0}, "extensions": '
                 '{"KHR_materials_transmission": {"transmissionFactor": 1.0}, "KHR_materials_volume": ' + volume + '}}]')


DOUBLE_TRANSPARENCY = Rule(
    "OPBR1221", "gltf-transmission-with-alpha-blend", Severity.WARNING,
    "A transmissive material (KHR_materials_transmission) also uses alphaMode BLEND with one alpha everywhere: "
    "transparent twice.",
    "KHR_materials_transmission (Blend Mode): alphaMode is alpha-as-coverage, whether the surface is there at "
    "all, and transmission is the transparency of a surface that is there; \"if alpha-as-coverage is not being "
    "used, the blend mode of the material should be set to OPAQUE even though it is transparent\". Blending "
    "glass by a uniform alpha fades its reflections and its tint with it, so it almost disappears (and is "
    "sorted as a blended surface for nothing). An alpha texture is coverage (holes in a surface), which the "
    "README allows beside transmission: not reported.",
    passing=_glass("OPAQUE", 1.0), failing=_glass("BLEND", 0.25),
    passing_name="example.gltf", failing_name="example.gltf", formats=("gltf",),
)
LENGTH_UNIT = Rule(
    "OPBR1222", "gltf-length-in-wrong-unit", Severity.WARNING,
    "A length is off by the factor of a unit: an iridescence film thinner than 1 nm (micrometres written where "
    "glTF wants nanometres), or a volume thicknessFactor more than 10 times the largest mesh using the material.",
    "KHR_materials_iridescence gives iridescenceThicknessMinimum/Maximum in nanometres (defaults 100 and 400); a "
    "film below 1 nm shows no interference colour, and 0.1-0.4 is the usual range typed in micrometres. "
    "KHR_materials_volume gives thicknessFactor \"in the coordinate space of the mesh\" (metres), to be \"the "
    "actual thickness as accurate as possible\"; a thickness ten times the largest extent of every mesh that "
    "uses the material (from POSITION's min and max, which glTF requires) is centimetres or millimetres, and "
    "refraction and absorption are computed through an object that large.",
    passing=_iridescent(100, 400), failing=_iridescent(0.1, 0.4),
    passing_name="example.gltf", failing_name="example.gltf", formats=("gltf",),
)
OPAQUE_VOLUME = Rule(
    "OPBR1223", "gltf-volume-absorbs-everything", Severity.WARNING,
    "A KHR_materials_volume absorbs all light over its thickness: attenuationColor black with a finite "
    "attenuationDistance, or thicknessFactor / attenuationDistance so large that less than 1e-4 of every "
    "channel gets through.",
    "KHR_materials_volume: attenuationColor is \"the color that white light turns into due to absorption when "
    "reaching the attenuation distance\", so light crossing the thickness t keeps attenuationColor ^ "
    "(t / attenuationDistance) of each channel. Black (often \"no tint\" exported as [0, 0, 0]; the default "
    "is [1, 1, 1]) or a distance thousands of times shorter than the thickness turns the glass black.",
    passing=_volume('{"thicknessFactor": 0.01, "attenuationDistance": 0.5, "attenuationColor": [0.9, 0.95, 0.9]}'),
    failing=_volume('{"thicknessFactor": 0.01, "attenuationDistance": 0.5, "attenuationColor": [0, 0, 0]}'),
    passing_name="example.gltf", failing_name="example.gltf", formats=("gltf",),
)
INVERTED_RANGE = Rule(
    "OPBR1224", "gltf-iridescence-thickness-range-inverted", Severity.WARNING,
    "iridescenceThicknessMinimum is larger than iridescenceThicknessMaximum while a thickness texture maps between "
    "them.",
    "KHR_materials_iridescence: the film thickness is mix(iridescenceThicknessMinimum, iridescenceThicknessMaximum, "
    "G of iridescenceThicknessTexture). The schema has no ordering rule (and the Khronos glTF-Validator adds none), "
    "but a minimum above the maximum inverts the texture: thin where it was painted thick. Usually the two fields "
    "swapped on export.",
    passing=_iridescent(100, 800), failing=_iridescent(800, 100),
    passing_name="example.gltf", failing_name="example.gltf", formats=("gltf",),
)


#: A volume letting less than this fraction of every channel through its thickness is black.
TRANSMITTANCE_FLOOR = 1e-4
#: A volume thickness more than this many times the largest mesh using the material is in the wrong unit.
THICKNESS_TO_EXTENT = 10.0
_FILM_MINIMUM_NM = 1.0


def _emitting(factor: str) -> str:
    return _gltf('"images": [{"uri": "data:image/png;base64,iVBORw0KGgoAAAANSUhEUgAAAAQAAAAECAIAAAAmkwkpAAAAFElEQVR42mM8'
                 'kWLEAANMDEgANwcARfYBZsiXQosAAAAASUVORK5CYII="}]', '"textures": [{"source": 0}]',
                 '"materials": [{"name": "M", "pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}, '
                 f'"emissiveFactor": {factor}}}]')


WHITE_EMISSION = Rule(
    "OPBR1240", "gltf-emissive-white-without-texture", Severity.WARNING,
    "A material with a base colour texture has emissiveFactor [1, 1, 1] and no emissiveTexture (nor emissive "
    "strength): the whole surface glows white and the texture never shows.",
    "glTF 2.0 (3.9.3): the emission is emissiveFactor times the emissive texture, default [0, 0, 0], added to the "
    "reflected light; [1, 1, 1] without a texture adds full white at every texel, so the surface renders a flat white "
    "(display-referred viewers clip it) whatever its base colour texture holds. Exporters write it when a "
    "DCC's emission colour defaults to white with a strength of 0 that glTF core cannot carry. The Khronos "
    "glTF-Validator does not judge values. Not reported with an emissiveTexture (the factor lets it through), with "
    "KHR_materials_emissive_strength or KHR_materials_unlit (a deliberate emitter), or on an untextured material (a "
    "white lamp). Remove emissiveFactor, or give it the colour meant.",
    passing=_emitting("[0, 0, 0]"), failing=_emitting("[1, 1, 1]"),
    passing_name="example.gltf", failing_name="example.gltf", formats=("gltf",),
)

def _normal(scale: float) -> str:
    return _gltf('"images": [{"uri": "data:image/png;base64,iVBORw0KGgoAAAANSUhEUgAAAAQAAAAECAIAAAAmkwkpAAAAFElEQVR42mM8'
                 'kWLEAANMDEgANwcARfYBZsiXQosAAAAASUVORK5CYII="}]', '"textures": [{"source": 0}]',
                 f'"materials": [{{"name": "M", "normalTexture": {{"index": 0, "scale": {scale}}}}}]')


NORMAL_SCALE_NEGATIVE = Rule(
    "OPBR1252", "gltf-normal-scale-negative", Severity.WARNING,
    "A normalTexture's scale is negative (-1 to \"fix\" a DirectX normal map).",
    "glTF 2.0 (normalTextureInfo): scaledNormal = normalize((sampled * 2 - 1) * vec3(scale, scale, 1)), so a negative "
    "scale flips red as well as green: the relief turns inside out instead of becoming glTF's convention (+Y up, "
    "OpenGL's). A DirectX map needs only its green channel inverted in the image. The Khronos glTF-Validator checks "
    "no sign. MaterialX's ND_normalmap_float -1 is the same mistake (OPBR720).",
    passing=_normal(1.0), failing=_normal(-1.0), passing_name="example.gltf", failing_name="example.gltf",
    formats=("gltf",),
)

RULES = (DOUBLE_TRANSPARENCY, LENGTH_UNIT, OPAQUE_VOLUME, INVERTED_RANGE, WHITE_EMISSION, NORMAL_SCALE_NEGATIVE)


def check(asset, context):
    """Runs on glTF assets only (rules.FAMILY_FORMATS)."""
    facts = asset.extra.get("gltf", {})
    extents: dict[int, float] = {}
    for primitive in facts.get("primitives", ()):
        material, extent = primitive.get("material"), primitive.get("extent")
        if isinstance(material, int) and not isinstance(material, bool) and isinstance(extent, float) and extent > 0:
            extents[material] = max(extents.get(material, 0.0), extent)
    for material in asset.materials:
        present = set((material.extra.get("gltf") or {}).get("material_extensions") or ())
        yield from _double_transparency(material, present, context)
        yield from _white_emission(material, present, context)
        normal = material.inputs.get("normal")
        texture = normal.value if normal is not None and isinstance(normal.value, Texture) else None
        if texture is not None and isinstance(texture.normal_map, float) and texture.normal_map < 0:
            yield context.diagnostic(
                NORMAL_SCALE_NEGATIVE, f"{material.name}: normalTexture scale {texture.normal_map:g} flips red as well "
                "as green (glTF scales x and y by it): the relief turns inside out", normal.location,
                hint="for a DirectX normal map, invert the image's green channel and keep a positive scale")
        if slots.IRIDESCENCE in present:
            yield from _iridescence(material, context)
        if slots.VOLUME in present:
            yield from _volume_checks(material, extents.get(material.extra.get("gltf", {}).get("index")), context)


def _factor(material, name: str):
    """The factor of ``name``: its constant, the scale of its texture (1 when unscaled), the glTF default."""
    entry = material.inputs.get(name)
    if entry is not None and isinstance(entry.value, Texture):
        scale = entry.value.scale
        return 1.0 if scale is None else scale
    return constant_or_default(material, name)


def _at(material, extension: str, name: str | None = None) -> Location:
    return Location(material.location.file, None, f"{material.location.path}/extensions/{extension}", name)


def _double_transparency(material, present, context):
    transmission = _factor(material, "transmission")
    alpha = material.inputs.get("alpha")
    if slots.TRANSMISSION not in present or constant_or_default(material, "alpha_mode") != 2 or \
            not isinstance(transmission, float) or transmission <= 0 or (alpha is not None and alpha.texture is not None):
        return
    shown = constant_or_default(material, "alpha")
    if not isinstance(shown, (int, float)) or isinstance(shown, bool):  # (an alpha that is no number: OPBR201/202's)
        return
    yield context.diagnostic(
        DOUBLE_TRANSPARENCY, f"{material.name}: transmission {transmission:g} and alphaMode BLEND with alpha "
        f"{shown:g} everywhere: the glass is transparent twice, and its reflections fade with the alpha",
        Location(material.location.file, None, material.location.path, "alphaMode"),
        hint="set alphaMode OPAQUE and baseColorFactor's alpha to 1: transmission alone makes the glass transparent")


def _iridescence(material, context):
    strength = _factor(material, "iridescence")
    entry = material.inputs.get("iridescence_thickness")
    if entry is None or not isinstance(strength, float) or strength <= 0:
        return
    if isinstance(entry.value, Texture) and isinstance(entry.value.scale, float) and isinstance(entry.value.bias, float):
        low, high = entry.value.bias, entry.value.bias + entry.value.scale
        if low > high:
            yield context.diagnostic(
                INVERTED_RANGE, f"{material.name}: iridescenceThicknessMinimum {low:g} nm is larger than "
                f"iridescenceThicknessMaximum {high:g} nm, so the thickness texture is inverted",
                _at(material, slots.IRIDESCENCE, "iridescenceThicknessMinimum"), hint="swap the two values")
        thickest = max(low, high)
    elif isinstance(entry.constant, float):
        thickest = entry.constant
    else:
        return
    if 0 < thickest < _FILM_MINIMUM_NM:
        yield context.diagnostic(
            LENGTH_UNIT, f"{material.name}: the iridescence film is at most {thickest:g} nm thick, too thin for any "
            "interference colour: micrometres written where glTF wants nanometres?",
            _at(material, slots.IRIDESCENCE, "iridescenceThicknessMaximum"),
            hint=f"multiply the thicknesses by 1000 ({thickest:g} um is {thickest * 1000:g} nm)")


def _volume_checks(material, extent: float | None, context):
    thickness = _factor(material, "thickness")
    if not isinstance(thickness, float) or thickness <= 0:
        return  # thin-walled: no volume to judge
    if extent is not None and thickness > THICKNESS_TO_EXTENT * extent:
        yield context.diagnostic(
            LENGTH_UNIT, f"{material.name}: thicknessFactor {thickness:g} is {thickness / extent:.0f} times the largest "
            f"mesh using the material ({extent:g} across): a length in centimetres or millimetres?",
            _at(material, slots.VOLUME, "thicknessFactor"),
            hint="give the thickness in the mesh's units (metres), about the object's real wall or body thickness")
    distance, colour = constant_or_default(material, "attenuation_distance"), constant_or_default(material, "attenuation_color")
    if not isinstance(distance, float) or not math.isfinite(distance) or distance <= 0 or not isinstance(colour, tuple):
        return
    if not any(colour):
        yield context.diagnostic(
            OPAQUE_VOLUME, f"{material.name}: attenuationColor is black with attenuationDistance {distance:g}: the volume "
            "absorbs all light and the glass renders black", _at(material, slots.VOLUME, "attenuationColor"),
            hint="use [1, 1, 1] (or leave it out) for no tint; the colour is what white light turns into at the distance")
        return
    entry = material.inputs.get("thickness")
    if entry is not None and entry.texture is not None:
        return  # the thickness varies: judged by its colour only
    ratio = thickness / distance
    if all(0 <= c < 1 and (c == 0 or ratio * math.log(c) < math.log(TRANSMITTANCE_FLOOR)) for c in colour):
        kept = max(c ** ratio for c in colour)
        yield context.diagnostic(
            OPAQUE_VOLUME, f"{material.name}: through thicknessFactor {thickness:g} at attenuationDistance {distance:g}, "
            f"at most {kept:.1e} of any colour gets through: the glass renders black",
            _at(material, slots.VOLUME, "attenuationDistance"),
            hint="attenuationDistance is the distance at which white light has turned into attenuationColor: "
                 "about the object's size for a tint")


def _white_emission(material, present: set, context):
    """OPBR1240: emissiveFactor [1, 1, 1], untextured, on a material whose base colour is textured."""
    emissive, base = material.inputs.get("emissive"), material.inputs.get("base_color")
    if emissive is None or emissive.texture is not None or emissive.constant != (1.0, 1.0, 1.0) or base is None \
            or base.texture is None or present & {slots.EMISSIVE_STRENGTH, slots.UNLIT}:
        return
    yield context.diagnostic(
        WHITE_EMISSION, f"{material.name}: emissiveFactor [1, 1, 1] without an emissiveTexture adds full white at every "
        "texel: the surface renders flat white and its baseColorTexture never shows (an exporter's default emission "
        "colour?)", emissive.location, hint="remove emissiveFactor (default [0, 0, 0]), or set the emission colour meant")
