"""glTF images: whether an image's encoding is one glTF allows for the slot that reads it, and whether
it has the channel the slot reads.

* glTF 2.0, 3.9.2 and 3.9.3: the base colour and emissive textures "MUST contain 8-bit values encoded
  with the sRGB opto-electronic transfer function" (the metallic-roughness texture, by contrast, "MAY use
  more than 8 bits per channel"); and "JPEG images MUST be compatible with JPEG File Interchange Format"
  (section 2, File Extensions and Media Types), whose images have one (Y) or three (YCbCr) components, so a
  four-component CMYK or YCCK JPEG is not a glTF image (the Khronos glTF-Validator's IMAGE_DATA_INVALID).
* A slot that reads a channel the image does not have reads its default there (A = 1): an RGB
  ``specularTexture`` (strength in A, KHR_materials_specular), ``sheenRoughnessTexture`` (KHR_materials_sheen) or
  ``diffuseTransmissionTexture`` (KHR_materials_diffuse_transmission), each read from A alone (:data:`ALPHA_ONLY_READS`,
  from the slot tables), changes nothing, and an ``anisotropyTexture``
  whose blue channel (the strength, KHR_materials_anisotropy) is 0 everywhere turns the anisotropy off. These
  are OPBR1211, the glTF family's "no effect", reported from here because only the image says so. An RGB
  base colour texture under ``alphaMode`` MASK (nothing is cut out) is not reported: Khronos' CompareIor
  sample does it and renders as its author meant, so it is no defect there.

* 3.9.2 and 3.9.3: metalness is read from B and roughness from G of the metallicRoughnessTexture, occlusion from R
  of the occlusionTexture (0: no indirect light). A one-channel greyscale image (a roughness map alone) in the packed
  slot reads its grey as both, so the surface is metal wherever it is rough (OPBR1238, under metallicFactor > 0); an
  occlusion image black in R leaves the surface without indirect light (OPBR1239, under a strength above 0).

One module because every rule here reads the same per-image decode (``decoded``, each image once: the anisotropy's
blue, the alpha maxima, the flat data channels) and the same texture-to-image map; split, each would decode again.

Every fact but the last is the reader's, from the image header (Pillow's mode and transparency, a PNG's
IHDR bit depth): nothing is decoded. The anisotropy texture's blue channel is decoded once per image, a
JPEG at 1/8 scale, and only up to :data:`MAX_INSPECTED_PIXELS`.
"""

from __future__ import annotations

from ..diagnostics import Severity
from ..io.gltf import drafts, slots
from ..io.gltf.animation_pointers import POINTER as ANIMATION_POINTER
from ..io.image_content import channel_maxima, channel_statistics
from ..model import Location, Texture
from . import Rule, constant_or_default
from .gltf import NO_EFFECT, _one_image
from .textures import image_of

_PNG_16BIT = ("data:image/png;base64,iVBORw0KGgoAAAANSUhEUgAAAAQAAAAEEAIAAAB2A9VqAAAAEElEQVR4nGMoNcAOGagnAQASFh7xh7LOv"
              "gAAAABJRU5ErkJggg==")
_PNG_8BIT = ("data:image/png;base64,iVBORw0KGgoAAAANSUhEUgAAAAQAAAAECAIAAAAmkwkpAAAAFElEQVR42mM8kWLEAANMDEgANwcA"
             "RfYBZsiXQosAAAAASUVORK5CYII=")


def _emissive(uri: str) -> str:
    return _one_image(uri, '{"name": "M", "emissiveFactor": [1, 1, 1], "emissiveTexture": {"index": 0}}')


IMAGE_ENCODING = Rule(
    "OPBR1219", "gltf-image-encoding-not-allowed", Severity.ERROR,
    "An image is encoded as glTF forbids: a base colour or emissive texture with 16 bits per channel, or a "
    "JPEG that is not JFIF (four components: CMYK or YCCK).",
    "glTF 2.0 requires base colour and emissive textures to \"contain 8-bit values encoded with the sRGB "
    "opto-electronic transfer function\" (3.9.2, 3.9.3; data textures such as metallicRoughness and normal "
    "maps may use more bits), and every JPEG to be compatible with JFIF (section 2), which has one or three "
    "components. Loaders truncate or reject a 16-bit colour image (WebGL uploads it as 8-bit sRGB, or not at "
    "all), and decode a CMYK JPEG with inverted or wrong colours where they decode it at all (the Khronos "
    "glTF-Validator: IMAGE_DATA_INVALID). Re-export the image as 8-bit RGB(A).",
    passing=_emissive(_PNG_8BIT), failing=_emissive(_PNG_16BIT),
    passing_name="example.gltf", failing_name="example.gltf", formats=("gltf",),
)

_ROTATED_JPEG = "data:image/jpeg;base64,/9j/4AAQSkZJRgABAQAAAQABAAD/4QAiRXhpZgAATU0AKgAAAAgAAQESAAMAAAABAAYAAAAAAAD/2wBDABALDA4MChAODQ4SERATGCgaGBYWGDEjJR0oOjM9PDkzODdASFxOQERXRTc4UG1RV19iZ2hnPk1xeXBkeFxlZ2P/2wBDARESEhgVGC8aGi9jQjhCY2NjY2NjY2NjY2NjY2NjY2NjY2NjY2NjY2NjY2NjY2NjY2NjY2NjY2NjY2NjY2NjY2P/wAARCAACAAIDASIAAhEBAxEB/8QAHwAAAQUBAQEBAQEAAAAAAAAAAAECAwQFBgcICQoL/8QAtRAAAgEDAwIEAwUFBAQAAAF9AQIDAAQRBRIhMUEGE1FhByJxFDKBkaEII0KxwRVS0fAkM2JyggkKFhcYGRolJicoKSo0NTY3ODk6Q0RFRkdISUpTVFVWV1hZWmNkZWZnaGlqc3R1dnd4eXqDhIWGh4iJipKTlJWWl5iZmqKjpKWmp6ipqrKztLW2t7i5usLDxMXGx8jJytLT1NXW19jZ2uHi4+Tl5ufo6erx8vP09fb3+Pn6/8QAHwEAAwEBAQEBAQEBAQAAAAAAAAECAwQFBgcICQoL/8QAtREAAgECBAQDBAcFBAQAAQJ3AAECAxEEBSExBhJBUQdhcRMiMoEIFEKRobHBCSMzUvAVYnLRChYkNOEl8RcYGRomJygpKjU2Nzg5OkNERUZHSElKU1RVVldYWVpjZGVmZ2hpanN0dXZ3eHl6goOEhYaHiImKkpOUlZaXmJmaoqOkpaanqKmqsrO0tba3uLm6wsPExcbHyMnK0tPU1dbX2Nna4uPk5ebn6Onq8vP09fb3+Pn6/9oADAMBAAIRAxEAPwCSiiivGPWP/9k="
_PLAIN_JPEG = "data:image/jpeg;base64,/9j/4AAQSkZJRgABAQAAAQABAAD/2wBDABALDA4MChAODQ4SERATGCgaGBYWGDEjJR0oOjM9PDkzODdASFxOQERXRTc4UG1RV19iZ2hnPk1xeXBkeFxlZ2P/2wBDARESEhgVGC8aGi9jQjhCY2NjY2NjY2NjY2NjY2NjY2NjY2NjY2NjY2NjY2NjY2NjY2NjY2NjY2NjY2NjY2NjY2P/wAARCAACAAIDASIAAhEBAxEB/8QAHwAAAQUBAQEBAQEAAAAAAAAAAAECAwQFBgcICQoL/8QAtRAAAgEDAwIEAwUFBAQAAAF9AQIDAAQRBRIhMUEGE1FhByJxFDKBkaEII0KxwRVS0fAkM2JyggkKFhcYGRolJicoKSo0NTY3ODk6Q0RFRkdISUpTVFVWV1hZWmNkZWZnaGlqc3R1dnd4eXqDhIWGh4iJipKTlJWWl5iZmqKjpKWmp6ipqrKztLW2t7i5usLDxMXGx8jJytLT1NXW19jZ2uHi4+Tl5ufo6erx8vP09fb3+Pn6/8QAHwEAAwEBAQEBAQEBAQAAAAAAAAECAwQFBgcICQoL/8QAtREAAgECBAQDBAcFBAQAAQJ3AAECAxEEBSExBhJBUQdhcRMiMoEIFEKRobHBCSMzUvAVYnLRChYkNOEl8RcYGRomJygpKjU2Nzg5OkNERUZHSElKU1RVVldYWVpjZGVmZ2hpanN0dXZ3eHl6goOEhYaHiImKkpOUlZaXmJmaoqOkpaanqKmqsrO0tba3uLm6wsPExcbHyMnK0tPU1dbX2Nna4uPk5ebn6Onq8vP09fb3+Pn6/9oADAMBAAIRAxEAPwCSiiivGPWP/9k="

IMAGE_ORIENTATION = Rule(
    "OPBR1232", "gltf-image-exif-orientation", Severity.WARNING,
    "A JPEG texture carries an EXIF Orientation other than 1 (a phone photo turned 90 degrees in its metadata).",
    "glTF says nothing about EXIF: browsers decode a JPEG with its orientation applied (the HTML image decoding "
    "and createImageBitmap's default), most engines and native loaders ignore it, so the texture lands rotated "
    "or mirrored differently per viewer. Re-export the image with its pixels rotated and the tag removed.",
    passing=_emissive(_PLAIN_JPEG), failing=_emissive(_ROTATED_JPEG),
    passing_name="example.gltf", failing_name="example.gltf", formats=("gltf",),
)

_PNG_TALL_PIXELS = ("data:image/png;base64,iVBORw0KGgoAAAANSUhEUgAAAAIAAAACCAIAAAD91JpzAAAACXBIWXMAAAsTAAAWJQGdeD1OAAAAFklE"
                    "QVR4nGNsaPjPwMDAxMDAwMDAAAAXnwIDVqKEkwAAAABJRU5ErkJggg==")
_PNG_SQUARE_PIXELS = ("data:image/png;base64,iVBORw0KGgoAAAANSUhEUgAAAAIAAAACCAIAAAD91JpzAAAACXBIWXMAAAsTAAALEwEAmpwYAAAAFk"
                      "lEQVR4nGNsaPjPwMDAxMDAwMDAAAAXnwIDVqKEkwAAAABJRU5ErkJggg==")

IMAGE_FEATURES = Rule(
    "OPBR1233", "gltf-png-unsupported-features", Severity.WARNING,
    "A PNG image holds what glTF says it should not: an embedded ICC profile (iCCP), chromaticities other than "
    "sRGB's (cHRM), a gamma other than sRGB's or linear (gAMA), non-square pixels (pHYs); or a WebP an ICC profile or "
    "an animation.",
    "glTF 2.0, section 2: \"PNG images SHOULD NOT contain animations, non-square pixel ratios, or embedded ICC "
    "profiles. Such features, if present, MUST be ignored by client implementations\", and 3.8.4: \"any "
    "colorspace information (such as ICC profiles ...) MUST be ignored\". Clients that decode through the "
    "browser's image pipeline without UNPACK_COLORSPACE_CONVERSION_WEBGL = NONE (or colorSpaceConversion "
    "'none') apply the profile anyway, which bends a normal map's or a metallic-roughness map's values; image "
    "tools that honour pHYs resample the texture on the next save. Likewise a gAMA other than sRGB's 45455 "
    "(1/2.2) or linear's 100000 and a cHRM other than sRGB's primaries, which browsers apply when they colour-manage "
    "the PNG, unless an sRGB chunk came first; an ICC profile or an animation in a WebP (EXT_texture_webp): "
    "glTF plays no animation, viewers show one frame. The Khronos glTF-Validator reports each "
    "(IMAGE_FEATURES_UNSUPPORTED; which gAMA and cHRM values it accepts was probed against it, version "
    "2.0.0-dev.3.10). An APNG (acTL) is left alone, as there: clients show its default image. Re-save the image "
    "without the chunk.",
    passing=_emissive(_PNG_SQUARE_PIXELS), failing=_emissive(_PNG_TALL_PIXELS),
    passing_name="example.gltf", failing_name="example.gltf", formats=("gltf",),
)

_ROUGHNESS_IN_G = ("data:image/png;base64,iVBORw0KGgoAAAANSUhEUgAAAAIAAAACCAIAAAD91JpzAAAAFklEQVR4nGOIimI4cYKBiYGBgYGBAQ"
                   "AXvgJHnRWZRQAAAABJRU5ErkJggg==")
_ROUGHNESS_IN_R = ("data:image/png;base64,iVBORw0KGgoAAAANSUhEUgAAAAIAAAACCAIAAAD91JpzAAAAFklEQVR4nGOIYmA4wcDAxMDAwMDAAA"
                   "AMfgElBp7S3gAAAABJRU5ErkJggg==")


def _clearcoat(uri: str) -> str:
    return _one_image(uri, '{"name": "M", "extensions": {"KHR_materials_clearcoat": {"clearcoatFactor": 1, '
                           '"clearcoatRoughnessTexture": {"index": 0}}}}', '"extensionsUsed": ["KHR_materials_clearcoat"]')


DATA_IN_UNREAD_CHANNEL = Rule(
    "OPBR1234", "gltf-data-in-unread-channel", Severity.WARNING,
    "A data texture's channels that glTF reads are flat while a channel no slot reads carries the data "
    "(roughness painted in R of a clearcoatRoughnessTexture, which reads G), or its metalness channel (B) is "
    "0 everywhere while an unread channel holds a black-and-white mask (a metal mask packed in R).",
    "glTF reads each data texture from fixed channels (2.0 section 3.9: metalness B, roughness G, occlusion R; "
    "KHR_materials_clearcoat: clearcoat R, clearcoat roughness G; transmission R, thickness G, sheen roughness and "
    "specular A...). Engines pack differently (Unity's mask maps put metal in R, others grey images in R), and "
    "an image written for another packing renders the flat channel: a mirror coat, a dielectric where the mask "
    "says metal. Neither the schema nor the Khronos glTF-Validator looks at texel content. Repack the image (or "
    "point the slot at the right one).",
    passing=_clearcoat(_ROUGHNESS_IN_G), failing=_clearcoat(_ROUGHNESS_IN_R),
    passing_name="example.gltf", failing_name="example.gltf", formats=("gltf",),
)

_GREY_ROUGHNESS = "data:image/png;base64,iVBORw0KGgoAAAANSUhEUgAAAAIAAAACCAAAAABX3VL4AAAADklEQVR4nGNgcGBo+A8AAwUBwE4zW+kAAAAASUVORK5CYII="
_RGB_ROUGHNESS = "data:image/png;base64,iVBORw0KGgoAAAANSUhEUgAAAAIAAAACCAIAAAD91JpzAAAAFklEQVR4nGNgYGBgcGBgYGhgYPjPAAAGzAHAgjF6XgAAAABJRU5ErkJggg=="


def _metal_rough(uri: str) -> str:
    return _one_image(uri, '{"name": "M", "pbrMetallicRoughness": {"metallicFactor": 1.0, '
                           '"metallicRoughnessTexture": {"index": 0}}}')


GREY_METAL_ROUGH = Rule(
    "OPBR1238", "gltf-greyscale-metallic-roughness", Severity.ERROR,
    "A metallicRoughnessTexture is a one-channel greyscale image and metallicFactor is above 0: metalness (B) equals "
    "roughness (G) at every texel.",
    "glTF 2.0 (3.9.2): \"The metalness values are sampled from the B channel. The roughness values are sampled from "
    "the G channel\", and a greyscale image is read with its one channel in R, G and B alike. A roughness map exported "
    "alone and plugged into the packed slot therefore makes the surface metallic exactly where it is rough: a "
    "dielectric (wood, plastic) renders as patchy rough metal, dark and tinted by its base colour. Neither the schema "
    "nor the Khronos glTF-Validator looks at it. Not reported when metallicFactor is 0 (metalness off: the grey is "
    "roughness only) or the grey is 0 everywhere. Pack roughness in G and metalness in B of an RGB image, or set "
    "metallicFactor 0 for a dielectric.",
    passing=_metal_rough(_RGB_ROUGHNESS), failing=_metal_rough(_GREY_ROUGHNESS),
    passing_name="example.gltf", failing_name="example.gltf", formats=("gltf",),
)

_BLACK = "data:image/png;base64,iVBORw0KGgoAAAANSUhEUgAAAAIAAAACCAAAAABX3VL4AAAADklEQVR4nGNgYGBgYAAAAAYAAXKCmeoAAAAASUVORK5CYII="
_GREY = "data:image/png;base64,iVBORw0KGgoAAAANSUhEUgAAAAIAAAACCAAAAABX3VL4AAAADklEQVR4nGM8wcDEwAAAA/oAzIAKlEUAAAAASUVORK5CYII="


def _occluded(uri: str) -> str:
    return _one_image(uri, '{"name": "M", "occlusionTexture": {"index": 0}}')


OCCLUSION_BLACK = Rule(
    "OPBR1239", "gltf-occlusion-texture-black", Severity.WARNING,
    "An occlusionTexture's red channel is 0 everywhere (and its strength above 0, at most 1): the surface gets no "
    "indirect light at all.",
    "glTF 2.0 (3.9.3): occlusion is sampled from R, \"0.0 means fully-occluded area (no indirect lighting)\", and "
    "the strength scales it as 1 + strength (R - 1). An image black in R (a failed ambient-occlusion bake, or one "
    "whose occlusion sits in another channel) leaves the object lit only by direct lights: near black under image-"
    "based lighting, the usual glTF viewer set-up. The Khronos glTF-Validator does not read texels. Re-bake the "
    "occlusion (or set the strength to 0, or remove the texture).",
    passing=_occluded(_GREY), failing=_occluded(_BLACK),
    passing_name="example.gltf", failing_name="example.gltf", formats=("gltf",),
)

_ALPHA_NONE = ("data:image/png;base64,iVBORw0KGgoAAAANSUhEUgAAAAIAAAACCAYAAABytg0kAAAAFElEQVR42mM8MS2FgYGBgYGJAQoAHL"
               "oBxn84q34AAAAASUVORK5CYII=")
_ALPHA_ONE_TEXEL = ("data:image/png;base64,iVBORw0KGgoAAAANSUhEUgAAAAIAAAACCAYAAABytg0kAAAAFklEQVR42mM8MS2FgYGBgYGJAQL+"
                    "AwAduQLFYmgq4gAAAABJRU5ErkJggg==")


def _cut_out(uri: str) -> str:
    return _one_image(uri, '{"name": "M", "alphaMode": "MASK", "alphaCutoff": 0.5, '
                           '"pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}}')


ALPHA_CUTS_EVERYTHING = Rule(
    "OPBR1249", "gltf-alpha-texture-hides-everything", Severity.ERROR,
    "Under alphaMode MASK, no texel of the base colour texture reaches alphaCutoff (its alpha times baseColorFactor's "
    "alpha is below the cutoff everywhere), or under BLEND that product is 0 everywhere: the whole material is cut "
    "away.",
    "glTF 2.0 (3.9.4, material.alphaCutoff): in MASK mode a fragment is \"rendered as fully opaque\" if its alpha is "
    "greater than or equal to alphaCutoff, \"otherwise, it is rendered as fully transparent\"; alpha is the base "
    "colour texture's A times baseColorFactor's fourth component (3.9.2), and in BLEND mode it is coverage, 0 drawing "
    "nothing. Filtering and mipmaps average texels, so no sample exceeds the largest one: when that one is below the "
    "cutoff, the surface is invisible from every angle and at every distance (no base, no reflection, no shadow). "
    "Usually an exporter that wrote an empty opacity channel into the PNG (or a cut-out mask inverted). Neither the "
    "schema nor the Khronos glTF-Validator reads texels. Not claimed where vertex colours with alpha (a VEC4 COLOR_n) "
    "or KHR_animation_pointer may change the product; an untextured material is OPBR908. Repaint the alpha (opaque "
    "where the surface is), or set alphaMode OPAQUE.",
    passing=_cut_out(_ALPHA_ONE_TEXEL), failing=_cut_out(_ALPHA_NONE),
    passing_name="example.gltf", failing_name="example.gltf", formats=("gltf",),
)

_RGB_ONLY = "data:image/png;base64,iVBORw0KGgoAAAANSUhEUgAAAAIAAAACCAIAAAD91JpzAAAAFklEQVR42mOsWGDDwMDAxMDAwMDAAAAQVgFYyFCc/gAAAABJRU5ErkJggg=="

MASK_WITHOUT_ALPHA = Rule(
    "OPBR1250", "gltf-mask-without-alpha", Severity.INFO,
    "Under alphaMode MASK the base colour texture has no alpha channel (an RGB JPEG or PNG) and baseColorFactor's "
    "alpha reaches alphaCutoff: every fragment is kept, so the cut-out cuts nothing.",
    "glTF 2.0 (3.9.2): an image without alpha reads alpha 1, so the material's alpha is baseColorFactor's fourth "
    "component everywhere; at or above alphaCutoff nothing is discarded (3.9.4) and the leaves, grilles or lace "
    "the mask was meant to cut render as solid quads. Usually the opacity was exported as a separate image, or "
    "the base colour re-saved as JPEG (which has no alpha). The Khronos glTF-Validator does not read texels. "
    "(The converse, alpha below the cutoff everywhere, is OPBR1249.) An info, not a warning: Khronos' own "
    "CompareIor sample sets MASK over a JPEG logo, where the solid quad is what it shows. Put the mask in the base "
    "colour texture's alpha, or set alphaMode OPAQUE.",
    passing=_cut_out(_ALPHA_ONE_TEXEL), failing=_cut_out(_RGB_ONLY),
    passing_name="example.gltf", failing_name="example.gltf", formats=("gltf",),
)

RULES = (IMAGE_ENCODING, IMAGE_ORIENTATION, IMAGE_FEATURES, DATA_IN_UNREAD_CHANNEL, GREY_METAL_ROUGH, OCCLUSION_BLACK,
         ALPHA_CUTS_EVERYTHING, MASK_WITHOUT_ALPHA)

#: What each feature of the reader's (io/gltf/image_features.py) is called, per format.
_FEATURE_WORDS = {"image/png": {"icc_profile": "an embedded ICC profile (iCCP)", "non_square_pixels": "non-square pixels (pHYs)",
                                "chromaticities": "chromaticities other than sRGB's (cHRM)",
                                "gamma": "a gamma other than sRGB's 1/2.2 or linear (gAMA)"},
                  "image/webp": {"icc_profile": "an embedded ICC profile (VP8X's ICC flag)",
                                 "animation": "an animation (VP8X's animation flag)"}}
_FORMAT_NAMES = {"image/png": "PNG", "image/webp": "WebP"}

#: The channel content of an image is inspected up to this many pixels (4096 x 4096); a larger image is not.
MAX_INSPECTED_PIXELS = 4096 * 4096
_COLOUR_TEXTURES = ("/pbrMetallicRoughness/baseColorTexture", "/emissiveTexture")


def check(asset, context):
    """Runs on glTF assets only (rules.FAMILY_FORMATS)."""
    facts = asset.extra.get("gltf", {})
    images = facts.get("images", ())
    if not images:
        return
    yield from _encodings(asset, facts, images, context)
    image_by_texture = {use["pointer"]: images[use["image"]] for use in facts.get("texture_uses", ())
                        if isinstance(use.get("image"), int) and 0 <= use["image"] < len(images)}
    decoded: dict = {}
    reads = alpha_reads(asset, facts)
    # materials whose alpha vertex colours (a VEC4 COLOR_n) multiply: a primitive's alpha is not the texture's alone
    coloured = {p.get("material") for p in facts.get("primitives", ()) if any(
        name.startswith("COLOR_") and form and form[0] == "VEC4" for name, form in p.get("attribute_formats", {}).items())}
    animated = ANIMATION_POINTER in facts.get("extensions_used", ())
    for material in asset.materials:
        yield from _missing_channels(asset, material, reads, decoded, context)
        yield from _flat_data(asset, material, image_by_texture, decoded, context)
        if not animated and _material_index(material) not in coloured:
            yield from _alpha_hides_everything(asset, material, image_by_texture, decoded, context)
    yield from _unread_channels(asset, facts, images, context)


def _encodings(asset, facts, images, context):
    for image in images:
        if image.get("mode") == "CMYK" and image.get("detected_mime") == "image/jpeg" and image.get("damage") is None:
            yield context.diagnostic(
                IMAGE_ENCODING, f"image {image['index']} ({image['file']}) is a four-component (CMYK) JPEG, which is not "
                "JFIF: glTF viewers decode it with wrong colours or not at all", Location(asset.path, None, image["pointer"]),
                hint="re-export it as an RGB JPEG or a PNG")
    for image in images:
        orientation = image.get("orientation")
        if isinstance(orientation, int) and orientation not in (0, 1):
            yield context.diagnostic(
                IMAGE_ORIENTATION, f"image {image['index']} ({image['file']}) is a JPEG with EXIF Orientation "
                f"{orientation}: browsers rotate it, most engines do not", Location(asset.path, None, image["pointer"]),
                hint="re-export it with the rotation applied to the pixels and no Orientation tag")
    for image in images:
        kind = image.get("detected_mime") or image.get("mime")
        words = _FEATURE_WORDS.get(kind, {})
        features = [words[f] for f in image.get("features", ()) if f in words]
        if features and image.get("damage") is None:
            colour = {"icc_profile", "chromaticities", "gamma"}.intersection(image["features"])
            yield context.diagnostic(
                IMAGE_FEATURES, f"image {image['index']} ({image['file']}) is a {_FORMAT_NAMES[kind]} with "
                f"{' and '.join(features)}, which glTF says a texture image SHOULD NOT hold" +
                ("; a browser that decodes it with colour conversion on applies that colour space to the values (a no-op only "
                 "where it is sRGB's)" if colour else "") +
                ("; viewers show one frame of it" if "animation" in image["features"] else ""),
                Location(asset.path, None, image["pointer"]),
                hint="re-save the image without the colour-space, pixel-aspect or animation data")
    for use in facts.get("texture_uses", ()):
        image = images[use["image"]] if isinstance(use.get("image"), int) and 0 <= use["image"] < len(images) else None
        if image is None or image.get("bit_depth") != 16 or not use["pointer"].endswith(_COLOUR_TEXTURES):
            continue
        slot = use["pointer"].rsplit("/", 1)[-1]
        yield context.diagnostic(
            IMAGE_ENCODING, f"{slot} reads image {image['index']} ({image['file']}), a 16-bit PNG: glTF requires 8-bit "
            "sRGB values in a colour texture", Location(asset.path, None, use["pointer"], "index"),
            hint="re-export the image with 8 bits per channel (sRGB)")


#: Texture properties read from the alpha channel alone, by (extension, property): each slot table's (io/gltf/slots.py,
#: io/gltf/drafts.py) whose channels are A only. sheenRoughnessTexture (KHR_materials_sheen: "stored in the alpha (A)
#: channel"), specularTexture (KHR_materials_specular: "stored in the alpha (A) channel"), diffuseTransmissionTexture
#: (KHR_materials_diffuse_transmission: "stored in the alpha (A) channel"), the draft KHR_materials_fuzz's
#: fuzzRoughnessTexture. (The base colour's alpha is read with its RGB, and an RGB base colour is opaque by intent.)
_ALL_SLOTS = slots.SLOTS + slots.DIFFUSE_TRANSMISSION_SLOTS + tuple(s for group in drafts.SLOTS.values() for s in group)
ALPHA_ONLY_READS = {(slot.container, slot.texture): slot for slot in _ALL_SLOTS
                    if slot.texture and slot.channels == (3,) and not any(
                        other.texture == slot.texture and other.channels != (3,) for other in _ALL_SLOTS)}
#: (what the extension calls the value in A, what the hint calls it) per slot
_QUANTITIES = {"specular": ("strength", "specular strength"), "sheen_roughness": ("roughness", "sheen roughness"),
               "diffuse_transmission": ("strength", "diffuse transmission strength"),
               "fuzz_roughness": ("roughness", "fuzz roughness")}


def alpha_reads(asset, facts) -> dict:
    """Material index -> ``(pointer, extension, slot, image)`` for every texture read from alpha alone: the reader's
    texture uses (each looked at once), and KHR_materials_diffuse_transmission's from the JSON the material keeps (the
    gltf_pbr node does not carry it, so the reader records no use of its textures)."""
    images, found = facts.get("images", ()), {}
    for use in facts.get("texture_uses", ()):
        parts = use["pointer"].split("/")
        slot = ALPHA_ONLY_READS.get(tuple(parts[-2:])) if len(parts) > 3 and parts[-3] == "extensions" else None
        if slot is not None and isinstance(use.get("image"), int) and 0 <= use["image"] < len(images):
            found.setdefault(use["material"], []).append((use["pointer"], slot.container, slot, images[use["image"]]))
    sources = facts.get("texture_sources", ())
    for material in asset.materials:
        kept = ((material.extra.get("gltf") or {}).get("extensions") or {}).get(slots.DIFFUSE_TRANSMISSION)
        index = _material_index(material)
        for slot in slots.DIFFUSE_TRANSMISSION_SLOTS if isinstance(kept, dict) and index is not None else ():
            info = kept.get(slot.texture) if slot.channels == (3,) else None
            texture = info.get("index") if isinstance(info, dict) else None
            source = sources[texture] if isinstance(texture, int) and not isinstance(texture, bool) and \
                0 <= texture < len(sources) else None
            if source is not None and source < len(images):
                found.setdefault(index, []).append((f"/materials/{index}/extensions/{slots.DIFFUSE_TRANSMISSION}/"
                                                    f"{slot.texture}", slots.DIFFUSE_TRANSMISSION, slot, images[source]))
    return found


def _material_index(material):
    """The index of a glTF material (its location's JSON pointer, /materials/N), or ``None``."""
    parts = (material.location.path or "").split("/") if material.location is not None else []
    return int(parts[2]) if len(parts) > 2 and parts[1] == "materials" and parts[2].isdigit() else None


def _missing_channels(asset, material, reads, decoded, context):
    for pointer, extension, slot, image in reads.get(_material_index(material), ()):
        if image.get("alpha") is False:
            quantity, named = _QUANTITIES.get(slot.parameter, (slot.parameter.replace("_", " "),) * 2)
            yield context.diagnostic(
                NO_EFFECT, f"{material.name}: {slot.texture} (image {image['index']}) has no alpha channel, where "
                f"{extension} reads the {quantity}: it reads 1 everywhere, so the texture has no effect",
                Location(asset.path, None, pointer, "index"), hint=f"store the {named} in the image's alpha channel")
    strength = material.inputs.get("anisotropy_strength")
    if strength is not None and isinstance(strength.value, Texture) and strength.value.scale != 0.0:
        texture = strength.value
        maxima = _maxima(asset, texture, decoded, context)
        if maxima is not None and len(maxima) >= 3 and maxima[2] == 0:
            yield context.diagnostic(
                NO_EFFECT, f"{material.name}: the anisotropyTexture's blue channel, the anisotropy strength, is 0 "
                "everywhere, so the material has no anisotropy", Location(asset.path, None, texture.node, "index"),
                hint="store the strength in the blue channel (1 where the full anisotropyStrength applies)")


#: The channels each data texture property reads (the slots' own, io/gltf/slots.py); an image any other
#: property reads (a colour, a normal map, the anisotropy direction, an extension the toolkit does not
#: interpret) is left alone: every channel may be read there.
_COLOUR_READS = {_slot.texture for _slot in slots.SLOTS if _slot.texture and _slot.colour}
_DATA_READS: dict[str, set[int]] = {}
for _slot in slots.SLOTS:  # (baseColorTexture is a colour one, though alpha's slot reads its A as data)
    if _slot.texture and _slot.channels and not _slot.colour and _slot.texture not in _COLOUR_READS \
            and _slot.texture != "anisotropyTexture":
        _DATA_READS.setdefault(_slot.texture, set()).update(_slot.channels)
_CHANNEL_NAMES = "RGBA"
_SUBSTANTIAL = 64  # 8-bit levels: a channel that spans a quarter of the range carries data


def _unread_channels(asset, facts, images, context):
    """OPBR1234: per image read only by data textures, the read channels flat while an unread one carries
    data, or metalness (B) 0 everywhere beside an unread black-and-white mask."""
    uses: dict[int, list[str]] = {}
    for use in facts.get("texture_uses", ()):
        if isinstance(use.get("image"), int) and 0 <= use["image"] < len(images):
            uses.setdefault(use["image"], []).append(use["pointer"])
    textures = {entry.value.node: entry.value for material in asset.materials for entry in material.inputs.values()
                if isinstance(entry.value, Texture)}
    for index, pointers in uses.items():
        properties = [pointer.rsplit("/", 1)[-1] for pointer in pointers]
        texture = next((textures[p] for p in pointers if p in textures), None)
        if texture is None or any(p not in _DATA_READS for p in properties):
            continue
        source = image_of(asset, texture, context, {})
        statistics = channel_statistics(source, MAX_INSPECTED_PIXELS) if source is not None else None
        read = set().union(*(_DATA_READS[p] for p in properties))
        if statistics is None or max(read) >= len(statistics):
            continue  # undecodable, too large, or a channel the image lacks (OPBR1211 says so)
        unread = [c for c in range(len(statistics)) if c not in read]
        carrying = [c for c in unread if statistics[c].high - statistics[c].low >= _SUBSTANTIAL]
        masks = [c for c in unread if statistics[c].mask]
        names = " and ".join(sorted(set(properties)))
        where = Location(asset.path, None, pointers[0], "index")
        image = images[index]
        if carrying and all(statistics[c].flat for c in sorted(read)):
            flat = ", ".join(f"{_CHANNEL_NAMES[c]} = {statistics[c].low}" for c in sorted(read))
            spread = ", ".join(f"{_CHANNEL_NAMES[c]} {statistics[c].low}-{statistics[c].high}" for c in carrying)
            yield context.diagnostic(
                DATA_IN_UNREAD_CHANNEL, f"{names} reads image {index} ({image['file']}) where every channel it reads is "
                f"flat ({flat} of 255) while a channel no slot reads carries data ({spread}): the data is probably "
                "packed in the wrong channel", where, hint="repack the image into the channels glTF reads")
        elif "metallicRoughnessTexture" in properties and statistics[2].flat and statistics[2].high <= 2 and masks:
            yield context.diagnostic(
                DATA_IN_UNREAD_CHANNEL, f"metallicRoughnessTexture reads metalness from image {index} ({image['file']})'s "
                f"blue channel, 0 everywhere, while its {_CHANNEL_NAMES[masks[0]]} channel, which no slot reads, is a "
                "black-and-white mask: a metal mask packed in another channel (Unity's mask maps put it in R) renders "
                "as a dielectric", where, hint="move the metal mask into the blue channel")


#: Pillow modes of a one-channel greyscale image (with or without alpha, 8 or 16 bits).
# 8-bit greyscale only: a 16-bit greyscale data map (glTF 3.9.2: the metallic-roughness texture "MAY use more than 8
# bits per channel") is a deliberate precision export, and the red team's round-one good core_16bit_grayscale_metal_rough
# is one; an 8-bit grey in the packed slot is a roughness map dropped there (round seven's gb05)
GREY_MODES = frozenset({"L", "LA", "La"})


def _maxima(asset, texture, decoded, context):
    if texture.file not in decoded:
        source = image_of(asset, texture, context, {})
        decoded[texture.file] = channel_maxima(source, MAX_INSPECTED_PIXELS) if source is not None else None
    return decoded[texture.file]


def _flat_data(asset, material, image_by_texture, decoded, context):
    """OPBR1238 (a greyscale metallicRoughnessTexture under metallicFactor > 0) and OPBR1239 (an occlusion texture
    black in R under a strength above 0)."""
    metallic = material.inputs.get("metallic")
    texture = metallic.texture if metallic is not None else None
    factor = 1.0 if texture is None or texture.scale is None else texture.scale
    if texture is not None and isinstance(factor, float) and factor > 0 and \
            image_by_texture.get(texture.node, {}).get("mode") in GREY_MODES:
        maxima = _maxima(asset, texture, decoded, context)
        if maxima is not None and maxima[0] > 0:
            image = image_by_texture[texture.node]
            yield context.diagnostic(
                GREY_METAL_ROUGH, f"{material.name}: metallicRoughnessTexture reads image {image['index']} "
                f"({image['file']}), a one-channel greyscale image, under metallicFactor {factor:g}: its grey is read as "
                "roughness (G) and as metalness (B) alike, so the surface is metallic wherever it is rough",
                Location(asset.path, None, texture.node, "index"),
                hint="pack roughness in G and metalness in B of an RGB image, or set metallicFactor 0 for a dielectric")
    occlusion = material.inputs.get("occlusion")
    texture = occlusion.texture if occlusion is not None else None
    strength = 1.0 if texture is None or texture.scale is None else texture.scale
    if texture is not None and isinstance(strength, float) and 0 < strength <= 1:  # (outside [0, 1]: OPBR1210's)
        maxima = _maxima(asset, texture, decoded, context)
        if maxima is not None and maxima[0] == 0:
            image = image_by_texture.get(texture.node, {})
            yield context.diagnostic(
                OCCLUSION_BLACK, f"{material.name}: occlusionTexture (image {image.get('index')}, {image.get('file')}) is "
                f"0 everywhere in R, the occlusion: with strength {strength:g} the surface receives "
                f"{'no' if strength == 1 else f'{1 - strength:.0%} of its'} indirect light",
                Location(asset.path, None, texture.node, "index"),
                hint="re-bake the ambient occlusion (white where unoccluded), or remove the texture")


_ALPHA_TOLERANCE = 1e-6  # an alpha equal to the cutoff is drawn (3.9.4: "greater than or equal"): never claimed


def _alpha_hides_everything(asset, material, image_by_texture, decoded, context):
    """OPBR1249: the largest texel alpha of the base colour texture (1 for an image without alpha) times
    baseColorFactor's alpha, below alphaCutoff under MASK, 0 under BLEND. (Not asked when a primitive drawn with
    the material has vertex colours with alpha, or the file animates material properties: KHR_animation_pointer.)"""
    mode = constant_or_default(material, "alpha_mode")
    alpha = material.inputs.get("alpha")
    texture = alpha.texture if alpha is not None else None
    if mode not in (1, 2) or texture is None:
        return
    factor = 1.0 if texture.scale is None else texture.scale
    cutoff = constant_or_default(material, "alpha_cutoff") if mode == 1 else None
    image = image_by_texture.get(texture.node)
    if not isinstance(factor, float) or image is None or (mode == 1 and not isinstance(cutoff, float)):
        return
    if image.get("alpha") is False:
        largest = 255  # no alpha channel: every texel's alpha is 1
        if mode == 1 and factor >= cutoff - _ALPHA_TOLERANCE:
            yield context.diagnostic(
                MASK_WITHOUT_ALPHA, f"{material.name}: alphaMode MASK, but the base colour texture, image "
                f"{image['index']} ({image['file']}), has no alpha channel and baseColorFactor's alpha is {factor:g}: "
                f"alpha is {factor:g} everywhere, at or above alphaCutoff {cutoff:g}, so nothing is cut out",
                Location(asset.path, None, texture.node, "index"),
                hint="put the cut-out mask in the texture's alpha (a PNG with alpha), or set alphaMode OPAQUE")
            return
    else:
        maxima = _maxima(asset, texture, decoded, context)
        if maxima is None or len(maxima) < 4:
            return  # undecodable, too large, a 16-bit image (read without its alpha here)
        largest = maxima[3]
    product = largest / 255 * factor
    where = Location(asset.path, None, texture.node, "index")
    texels = f"the largest alpha of image {image['index']} ({image['file']}) is {largest} of 255" + (
        f", times baseColorFactor's alpha {factor:g}" if factor != 1.0 else "")
    if mode == 1 and product < cutoff - _ALPHA_TOLERANCE:
        yield context.diagnostic(
            ALPHA_CUTS_EVERYTHING, f"{material.name}: alphaMode MASK with alphaCutoff {cutoff:g}, but {texels}: every "
            "fragment is below the cutoff and discarded, so the material is invisible", where,
            hint="repaint the texture's alpha (opaque where the surface is: an empty or inverted opacity channel?), "
                 "or set alphaMode OPAQUE")
    elif mode == 2 and product == 0:
        yield context.diagnostic(
            ALPHA_CUTS_EVERYTHING, f"{material.name}: alphaMode BLEND, but {texels}: alpha is 0 everywhere, so the "
            "material draws nothing", where,
            hint="repaint the texture's alpha (opaque where the surface is), or set alphaMode OPAQUE")
