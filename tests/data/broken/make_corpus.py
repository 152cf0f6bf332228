"""Writes the broken-file corpus (every file beside this script) and EXPECTED.json.

Each case is (file name, expected code, defect sentence, content[, extra entry fields]). The
expected severity is the rule's default severity, read from the rule table, so EXPECTED.json
always states "the right severity". Run from anywhere: ``python tests/data/broken/make_corpus.py``.
"""

from __future__ import annotations

import base64
import io
import json
import os
import struct
import sys
import zipfile

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.abspath(os.path.join(HERE, "..", "..", "..")))

from openpbr_tools.rules import all_rules  # noqa: E402  (needs the repository on the path)

CASES: list[tuple] = []


def case(name, code, defect, content, **extra):
    CASES.append((name, code, defect, content, extra))


# ---------------------------------------------------------------- builders

def mtlx(body: str, colorspace: str | None = "lin_rec709", version: str = "1.39", material: bool = True,
         shader: str = "S") -> str:
    cs = f' colorspace="{colorspace}"' if colorspace else ""
    mat = (f'  <surfacematerial name="M" type="material">\n'
           f'    <input name="surfaceshader" type="surfaceshader" nodename="{shader}" />\n'
           f'  </surfacematerial>\n') if material else ""
    inner = "".join("  " + line + "\n" for line in body.strip("\n").splitlines())
    return f'<?xml version="1.0"?>\n<materialx version="{version}"{cs}>\n{inner}{mat}</materialx>\n'


def opbr(inputs: str, category: str = "open_pbr_surface", attrs: str = "", before: str = "", **kw) -> str:
    lines = "".join("  " + line.strip() + "\n" for line in inputs.strip("\n").splitlines() if line.strip())
    body = f'{before}\n<{category} name="S" type="surfaceshader"{attrs}>\n{lines}</{category}>'
    return mtlx(body, **kw)


def image(name: str, file: str, type_: str = "color3", colorspace: str | None = "srgb_texture") -> str:
    cs = f' colorspace="{colorspace}"' if colorspace is not None else ""
    return (f'<image name="{name}" type="{type_}">\n'
            f'  <input name="file" type="filename" value="{file}"{cs} />\n'
            f'</image>')


USD_HEAD = '#usda 1.0\n(\n    defaultPrim = "M"\n    metersPerUnit = 0.01\n    upAxis = "Y"\n)\n\n'


def usda(shader_body: str, extra_prims: str = "", material_body: str = "", head: str = USD_HEAD,
         shader_id: str | None = "ND_open_pbr_surface_surfaceshader", output: str = "mtlx:surface") -> str:
    ident = f'        uniform token info:id = "{shader_id}"\n' if shader_id else ""
    body = "".join("        " + l.strip() + "\n" for l in shader_body.strip("\n").splitlines() if l.strip())
    extra = "".join(("    " + l if l.strip() else l) + "\n" for l in extra_prims.strip("\n").splitlines())
    mbody = "".join("    " + l.strip() + "\n" for l in material_body.strip("\n").splitlines() if l.strip())
    return (f'{head}def Material "M"\n{{\n    token outputs:{output}.connect = </M/S.outputs:surface>\n{mbody}\n'
            f'    def Shader "S"\n    {{\n{ident}{body}        token outputs:surface\n    }}\n'
            + (f"\n{extra}" if extra else "") + "}\n")


def preview(shader_body: str, extra_prims: str = "", **kw) -> str:
    return usda(shader_body, extra_prims, shader_id="UsdPreviewSurface", output="surface", **kw)


def uvtex(name: str, file: str, out: str = "rgb", out_type: str = "float3", cs: str | None = "sRGB",
          extra: str = "") -> str:
    csl = f'    token inputs:sourceColorSpace = "{cs}"\n' if cs else ""
    return (f'def Shader "{name}"\n{{\n    uniform token info:id = "UsdUVTexture"\n'
            f'    asset inputs:file = @{file}@\n{csl}{extra}    {out_type} outputs:{out}\n}}\n')


def mximage(name: str, file: str, type_: str = "color3", cs: str | None = None, node: str | None = None) -> str:
    node = node or f"ND_image_{type_}"
    usd_type = {"color3": "color3f", "float": "float", "vector3": "float3"}[type_]
    meta = f' (\n        colorSpace = "{cs}"\n    )' if cs else ""
    return (f'def Shader "{name}"\n{{\n    uniform token info:id = "{node}"\n'
            f'    asset inputs:file = @{file}@{meta}\n    {usd_type} outputs:out\n}}\n')


PNG_URI = ("data:image/png;base64,iVBORw0KGgoAAAANSUhEUgAAAAQAAAAECAIAAAAmkwkpAAAAFElEQVR42mM8kWLEAANMDEgA"
           "NwcARfYBZsiXQosAAAAASUVORK5CYII=")


def gltf(materials, extensions_used=(), **top) -> dict:
    doc = {"asset": {"version": "2.0", "generator": "broken-corpus"}}
    if extensions_used:
        doc["extensionsUsed"] = list(extensions_used)
    doc.update(top)
    doc["materials"] = materials
    return doc


def textured(material: dict, uri: str = "textures/albedo.png", **top) -> dict:
    return gltf([material], images=[{"uri": uri}], textures=[{"source": 0}], **top)


def glb(document: dict, binary: bytes | None = None) -> bytes:
    data = json.dumps(document, separators=(",", ":")).encode("utf-8")
    data += b" " * (-len(data) % 4)
    chunks = struct.pack("<II", len(data), 0x4E4F534A) + data
    if binary is not None:
        binary += b"\0" * (-len(binary) % 4)
        chunks += struct.pack("<II", len(binary), 0x004E4942) + binary
    return struct.pack("<III", 0x46546C67, 2, 12 + len(chunks)) + chunks


def png(mode: str, size=(4, 4), value=128) -> bytes:
    from PIL import Image  # Pillow only when writing the corpus
    buffer = io.BytesIO()
    Image.new(mode, size, value if mode == "L" else (value,) * len(mode)).save(buffer, "PNG")
    return buffer.getvalue()


def tiff_rgb() -> bytes:
    from PIL import Image  # Pillow only when writing the corpus
    buffer = io.BytesIO()
    Image.new("RGB", (4, 4), (128, 128, 255)).save(buffer, "TIFF")
    return buffer.getvalue()


def jpeg_whole() -> bytes:
    """A 64 x 64 JPEG of noise (so its scan data is long)."""
    import random

    from PIL import Image  # Pillow only when writing the corpus
    generator = random.Random(7)
    buffer = io.BytesIO()
    Image.frombytes("RGB", (64, 64), bytes(generator.randrange(256) for _ in range(64 * 64 * 3))).save(buffer, "JPEG", quality=90)
    return buffer.getvalue()


def jpeg_cut_short() -> bytes:
    """:func:`jpeg_whole` with its second half cut off."""
    data = jpeg_whole()
    return data[:len(data) // 2]


def checker() -> bytes:
    """A 4 x 4 black and white checker: an image whose texels differ."""
    from PIL import Image  # Pillow only when writing the corpus
    image = Image.new("RGB", (4, 4))
    image.putdata([(255, 255, 255) if (i + i // 4) % 2 else (0, 0, 0) for i in range(16)])
    buffer = io.BytesIO()
    image.save(buffer, "PNG")
    return buffer.getvalue()


def png16() -> bytes:
    """A 4 x 4 RGB PNG with 16 bits per channel (written by hand: Pillow saves RGB at 8 bits)."""
    import zlib

    def chunk(kind: bytes, data: bytes) -> bytes:
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data))
    rows = b"".join(b"\0" + struct.pack(">12H", *([30000, 20000, 10000] * 4)) for _ in range(4))
    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", 4, 4, 16, 2, 0, 0, 0))
            + chunk(b"IDAT", zlib.compress(rows)) + chunk(b"IEND", b""))


def encoded(mode: str, fmt: str, value) -> bytes:
    from PIL import Image  # Pillow only when writing the corpus
    buffer = io.BytesIO()
    Image.new(mode, (4, 4), value).save(buffer, fmt)
    return buffer.getvalue()


TEXTURES = {
    "textures/albedo.png": png("RGB"),
    "textures/rough.png": png("L"),
    "textures/orm.png": png("RGB"),
    "textures/normal.png": png("RGB", value=200),
    "textures/mask.png": png("L", value=255),
    "textures/odd.png": png("RGB", size=(3, 5)),
    "textures/checker.png": checker(),
    "textures/normal.tif": tiff_rgb(),
    "textures/albedo16.png": png16(),
    "textures/albedo_cmyk.jpg": encoded("CMYK", "JPEG", (0, 60, 120, 0)),
    "textures/albedo.webp": encoded("RGB", "WEBP", (120, 80, 40)),
    "textures/flow_rg.png": encoded("RGB", "PNG", (255, 128, 0)),
    "textures/normal_inward.png": encoded("RGB", "PNG", (128, 128, 0)),
}


# ================================================================ document
case("OPBR001_utf16_garbage.mtlx", "OPBR001", "An exporter wrote the document as UTF-16 with a byte-order mark and then truncated it mid-character, so it cannot be decoded.",
     b"\xff\xfe<\x00m\x00a\x00t")
case("OPBR002_gltf_not_utf8.gltf", "OPBR002", "A glTF JSON file saved in Latin-1 with a non-UTF-8 byte in the material name.",
     b'{"asset": {"version": "2.0"}, "materials": [{"name": "Mat\xe9riau"}]}')
case("OPBR002_truncated_export.mtlx", "OPBR002", "The exporter crashed mid-write: the shader element and the document are never closed.",
     '<?xml version="1.0"?>\n<materialx version="1.39" colorspace="lin_rec709">\n  <open_pbr_surface name="S" type="surfaceshader">\n    <input name="base_weight" type="float" value="1" />\n')
case("OPBR002_usda_syntax_error.usda", "OPBR002", "A hand-edited USD layer lost the closing brace of its Material prim.",
     USD_HEAD + 'def Material "M"\n{\n    def Shader "S"\n    {\n        uniform token info:id = "ND_open_pbr_surface_surfaceshader"\n        token outputs:surface\n    }\n')
case("OPBR002_gltf_trailing_comma.gltf", "OPBR002", "A glTF written by a template engine has a trailing comma, which JSON does not allow.",
     '{"asset": {"version": "2.0"}, "materials": [{"name": "M", "pbrMetallicRoughness": {"roughnessFactor": 0.5},}]}\n')
case("OPBR002_glb_bad_magic.glb", "OPBR002", "A GLB whose header magic is 'glTf' in the wrong case (a hand-rolled writer), so the container is invalid.",
     b"glTf" + glb(gltf([{"name": "M"}]))[4:])
case("OPBR002_glb_length_mismatch.glb", "OPBR002", "A GLB whose header length field claims more bytes than the file holds (a truncated download).",
     (lambda b: b[:8] + struct.pack("<I", len(b) + 400) + b[12:])(glb(gltf([{"name": "M"}]))))
case("OPBR003_only_nodegraph.mtlx", "OPBR003", "A 'material library' export that holds only a node graph and no surface shader.",
     mtlx('<nodegraph name="NG">\n  <constant name="c" type="color3">\n    <input name="value" type="color3" value="0.5, 0.5, 0.5" />\n  </constant>\n  <output name="out" type="color3" nodename="c" />\n</nodegraph>', material=False))
case("OPBR003_gltf_no_materials.gltf", "OPBR003", "A glTF exported with materials disabled: geometry only, no material at all.",
     json.dumps({"asset": {"version": "2.0"}, "scenes": [{"name": "empty"}]}, indent=2))
case("OPBR004_texcoord_to_nowhere.mtlx", "OPBR004", "An image's texcoord input is connected to a node the exporter did not write, which MaterialX's Document.validate() rejects.",
     opbr('<input name="base_color" type="color3" nodename="albedo" />',
          before='<image name="albedo" type="color3">\n  <input name="file" type="filename" value="textures/albedo.png" colorspace="srgb_texture" />\n  <input name="texcoord" type="vector2" nodename="uvset1" />\n</image>'))
case("OPBR005_materialx_138.mtlx", "OPBR005", "A document written by an older DCC plug-in with MaterialX version 1.38, whose swizzle node MaterialX's upgrade rewrites.",
     opbr('<input name="base_weight" type="float" nodename="sw" />', version="1.38",
          before='<swizzle name="sw" type="float">\n  <input name="in" type="color3" value="1, 0, 0" />\n  <input name="channels" type="string" value="r" />\n</swizzle>'))
case("OPBR012_stale_version_header.mtlx", "OPBR012", "(info) An OpenPBR document whose header still says 1.38, which MaterialX's upgrade leaves otherwise unchanged.",
     opbr('<input name="base_weight" type="float" value="1" />', version="1.38"))
case("OPBR002_usd_missing_mtlx_reference.usda", "OPBR002", "A USD material referencing a MaterialX document that was not shipped with the stage.",
     usda('color3f inputs:base_color = (0.5, 0.4, 0.3)', head='#usda 1.0\n(\n    defaultPrim = "M"\n    subLayers = [@./materials/missing_look.mtlx@]\n    metersPerUnit = 0.01\n    upAxis = "Y"\n)\n\n'))
case("OPBR006_substance_preset.xml", "OPBR006", "A material preset saved as .xml, a kind of file no reader handles.",
     '<?xml version="1.0"?>\n<preset><param name="roughness" value="0.5"/></preset>\n')
case("OPBR007_unescaped_lt_in_doc.mtlx", "OPBR007", "A doc string with an unescaped '<' that strict XML rejects but MaterialX's parser tolerates.",
     opbr('<input name="base_weight" type="float" value="1" doc="weight <1 looks dull" />'))
case("OPBR009_xinclude_outside_folder.mtlx", "OPBR009", "The document XIncludes the studio-wide legacy OpenPBR definitions through a path that climbs out of its folder ('..'), which the toolkit does not follow.",
     '<?xml version="1.0"?>\n<materialx version="1.39" colorspace="lin_rec709">\n  <xi:include href="../../../libraries/open_pbr_surface_legacy_defs.mtlx" />\n'
     '  <open_pbr_surface name="S" type="surfaceshader" />\n  <surfacematerial name="M" type="material">\n'
     '    <input name="surfaceshader" type="surfaceshader" nodename="S" />\n  </surfacematerial>\n</materialx>\n')

# ================================================================ names
case("OPBR101_base_colour_british.mtlx", "OPBR101", "British spelling base_colour instead of base_color.",
     opbr('<input name="base_colour" type="color3" value="0.5, 0.5, 0.5" />'))
case("OPBR101_specular_roughnes_typo.mtlx", "OPBR101", "A typo: specular_roughnes (one s missing).",
     opbr('<input name="specular_roughnes" type="float" value="0.4" />'))
case("OPBR101_standard_surface_name_on_openpbr.mtlx", "OPBR101", "The Standard Surface spelling specular_IOR written on an OpenPBR shader.",
     opbr('<input name="specular_IOR" type="float" value="1.5" />'))
case("OPBR101_gltf_pbr_metalic.mtlx", "OPBR101", "A gltf_pbr shader with the input misspelt 'metalic'.",
     opbr('<input name="metalic" type="float" value="1" />', category="gltf_pbr"))
case("OPBR101_standard_surface_coat_ior_case.mtlx", "OPBR101", "A standard_surface shader with coat_ior written in lower case (Standard Surface spells it coat_IOR).",
     opbr('<input name="coat_ior" type="float" value="1.5" />', category="standard_surface"))
case("OPBR101_usd_base_colour.usda", "OPBR101", "A USD OpenPBR shader with inputs:base_colour (British spelling).",
     usda('color3f inputs:base_colour = (0.5, 0.4, 0.3)'))
case("OPBR102_legacy_name_in_current_material.mtlx", "OPBR102", "A 1.1 material (coat_darkening) that also carries the 0.2-0.3 name specular_ior_level.",
     opbr('<input name="coat_darkening" type="float" value="1" />\n<input name="thin_film_weight" type="float" value="0" />\n<input name="specular_ior_level" type="float" value="0.5" />'),
     also={"OPBR403": "a legacy name beside a current one is by definition a material of mixed versions: OPBR102 names the input, OPBR403 the material"})
case("OPBR103_duplicate_input.mtlx", "OPBR103", "base_weight written twice on one shader (an exporter that appends instead of replacing).",
     opbr('<input name="base_weight" type="float" value="0.8" />\n<input name="base_weight" type="float" value="0.5" />'))
case("OPBR103_duplicate_node.mtlx", "OPBR103", "Two image nodes with the same name in one document.",
     opbr('<input name="base_color" type="color3" nodename="albedo" />',
          before=image("albedo", "textures/albedo.png") + "\n" + image("albedo", "textures/albedo.png")))
case("OPBR103_xinclude_redefines_material.mtlx", "OPBR103", "The document overrides a library material it also XIncludes: MaterialX keeps the library's and drops the override.",
     mtlx('<xi:include href="OPBR103_includes/library.mtlx" />\n' + '<open_pbr_surface name="S" type="surfaceshader">\n'
          '  <input name="specular_roughness" type="float" value="0.55" />\n</open_pbr_surface>', material=True)
     .replace('<materialx version="1.39"', '<materialx version="1.39" xmlns:xi="http://www.w3.org/2001/XInclude"', 1))
case("OPBR104_open_pbr_surfce.mtlx", "OPBR104", "The shader category is misspelt open_pbr_surfce.",
     opbr('<input name="base_weight" type="float" value="1" />', category="open_pbr_surfce"))
case("OPBR104_standard_surface_v2.mtlx", "OPBR104", "A vendor's category name standard_surface2 that no node definition declares.",
     opbr('<input name="base" type="float" value="1" />', category="standard_surface2"))
case("OPBR105_nodedef_v2.mtlx", "OPBR105", "The shader names a nodedef ND_open_pbr_surface_v2 that does not exist.",
     opbr('<input name="base_weight" type="float" value="1" />', attrs=' nodedef="ND_open_pbr_surface_v2"'))
case("OPBR106_version_1_2.mtlx", "OPBR106", "The shader claims version 1.2, an OpenPBR version that does not exist.",
     opbr('<input name="base_weight" type="float" value="1" />', attrs=' version="1.2"'))

# ================================================================ values
case("OPBR201_roughness_as_color3.mtlx", "OPBR201", "specular_roughness written as a color3 (an exporter that writes every input as a colour).",
     opbr('<input name="specular_roughness" type="color3" value="0.3, 0.3, 0.3" />'))
case("OPBR201_base_color_as_float.mtlx", "OPBR201", "base_color written as a float.",
     opbr('<input name="base_color" type="float" value="0.8" />'))
case("OPBR201_thin_walled_as_integer.mtlx", "OPBR201", "geometry_thin_walled written as integer 1 instead of boolean.",
     opbr('<input name="geometry_thin_walled" type="integer" value="1" />'))
case("OPBR202_decimal_comma_ior.mtlx", "OPBR202", "specular_ior written with a decimal comma, '1,5', by a German-locale exporter.",
     opbr('<input name="specular_ior" type="float" value="1,5" />'))
case("OPBR202_decimal_comma_color.mtlx", "OPBR202", "A colour written with decimal commas '0,8, 0,2, 0,1' (six components).",
     opbr('<input name="base_color" type="color3" value="0,8, 0,2, 0,1" />'))
case("OPBR202_two_component_color.mtlx", "OPBR202", "A color3 value with only two components.",
     opbr('<input name="base_color" type="color3" value="0.5, 0.5" />'))
case("OPBR202_trailing_f_suffix.mtlx", "OPBR202", "A float written as a C literal '0.5f'.",
     opbr('<input name="specular_roughness" type="float" value="0.5f" />'))
case("OPBR202_boolean_yes.mtlx", "OPBR202", "A boolean written as 'yes' instead of true/false.",
     opbr('<input name="geometry_thin_walled" type="boolean" value="yes" />'))
case("OPBR202_gltf_roughness_string.gltf", "OPBR202", "roughnessFactor written as the JSON string \"0.5\".",
     json.dumps(gltf([{"name": "M", "pbrMetallicRoughness": {"roughnessFactor": "0.5"}}]), indent=2))
case("OPBR202_gltf_basecolor_three.gltf", "OPBR202", "baseColorFactor with three components (RGB) where glTF requires RGBA.",
     json.dumps(gltf([{"name": "M", "pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.2, 0.1]}}]), indent=2))
case("OPBR203_base_weight_nan.mtlx", "OPBR203", "base_weight is NaN (an uninitialised value written out).",
     opbr('<input name="base_weight" type="float" value="nan" />'))
case("OPBR203_emission_inf.mtlx", "OPBR203", "emission_luminance is infinite.",
     opbr('<input name="emission_luminance" type="float" value="inf" />'))
case("OPBR203_gltf_infinite_roughness.gltf", "OPBR203", "roughnessFactor written as 1e400, beyond a double: JSON, read as infinity.",
     '{"asset": {"version": "2.0"}, "materials": [{"name": "M", "pbrMetallicRoughness": {"roughnessFactor": 1e400}}]}\n')
case("OPBR204_thin_walled_from_texture.mtlx", "OPBR204", "The uniform geometry_thin_walled is driven by a mask texture.",
     opbr('<input name="geometry_thin_walled" type="boolean" nodename="mask" />',
          before='<image name="mask" type="boolean">\n  <input name="file" type="filename" value="textures/mask.png" />\n</image>'),
     also={"OPBR004": "MaterialX has no boolean image node, so Document.validate() rejects the same connection"})

case("OPBR205_constant_geometry_normal.mtlx", "OPBR205", "(info) geometry_normal set to the constant (0, 0, 1), a tangent-space flat normal exported as a value (MaterialX ignores it; other readers may not).",
     opbr('<input name="geometry_normal" type="vector3" value="0, 0, 1" />'))

# ================================================================ ranges
case("OPBR301_base_weight_negative.mtlx", "OPBR301", "base_weight is -0.2.",
     opbr('<input name="base_weight" type="float" value="-0.2" />'))
case("OPBR301_roughness_above_one.mtlx", "OPBR301", "specular_roughness 1.2 (a glossiness-to-roughness conversion that overshot).",
     opbr('<input name="specular_roughness" type="float" value="1.2" />'))
case("OPBR301_coat_ior_zero.mtlx", "OPBR301", "coat_ior = 0, the open lower bound, written where the exporter meant 'unset'.",
     opbr('<input name="coat_weight" type="float" value="1" />\n<input name="coat_ior" type="float" value="0" />'))
case("OPBR301_specular_ior_zero.mtlx", "OPBR301", "specular_ior = 0 (an IOR of zero).",
     opbr('<input name="specular_ior" type="float" value="0" />'))
case("OPBR301_transmission_weight_percent.mtlx", "OPBR301", "transmission_weight 100, a percentage written where a 0-1 weight is expected.",
     opbr('<input name="transmission_weight" type="float" value="100" />'))
case("OPBR301_metalness_255.mtlx", "OPBR301", "base_metalness 255, an 8-bit value not normalised.",
     opbr('<input name="base_metalness" type="float" value="255" />'))
case("OPBR301_negative_base_color.mtlx", "OPBR301", "A negative base_color component from a colour-space conversion that went out of gamut.",
     opbr('<input name="base_color" type="color3" value="0.9, -0.05, 0.1" />'))
case("OPBR301_standard_surface_base_negative.mtlx", "OPBR301", "A standard_surface with base = -1.",
     opbr('<input name="base" type="float" value="-1" />', category="standard_surface"))
case("OPBR301_gltf_roughness_1_5.gltf", "OPBR301", "roughnessFactor 1.5, outside glTF's [0, 1].",
     json.dumps(gltf([{"name": "M", "pbrMetallicRoughness": {"roughnessFactor": 1.5}}]), indent=2))
case("OPBR301_gltf_metallic_negative.gltf", "OPBR301", "metallicFactor -0.1.",
     json.dumps(gltf([{"name": "M", "pbrMetallicRoughness": {"metallicFactor": -0.1}}]), indent=2))
case("OPBR301_gltf_ior_half.gltf", "OPBR301", "KHR_materials_ior ior 0.5, which the extension schema forbids (ior is 0 or >= 1).",
     json.dumps(gltf([{"name": "M", "extensions": {"KHR_materials_ior": {"ior": 0.5}}}], ["KHR_materials_ior"]), indent=2))
case("OPBR301_gltf_transmission_two.gltf", "OPBR301", "KHR_materials_transmission transmissionFactor 2.",
     json.dumps(gltf([{"name": "M", "extensions": {"KHR_materials_transmission": {"transmissionFactor": 2.0}}}], ["KHR_materials_transmission"]), indent=2))
case("OPBR301_gltf_clearcoat_negative.glb", "OPBR301", "A GLB with KHR_materials_clearcoat clearcoatRoughnessFactor -0.5.",
     glb(gltf([{"name": "M", "extensions": {"KHR_materials_clearcoat": {"clearcoatFactor": 1.0, "clearcoatRoughnessFactor": -0.5}}}], ["KHR_materials_clearcoat"])))
case("OPBR301_gltf_emissive_above_one.gltf", "OPBR301", "emissiveFactor [4, 4, 4] (HDR emission belongs in KHR_materials_emissive_strength).",
     json.dumps(gltf([{"name": "M", "emissiveFactor": [4.0, 4.0, 4.0]}]), indent=2))
case("OPBR301_usd_preview_roughness.usda", "OPBR301", "UsdPreviewSurface roughness 1.5.",
     preview('float inputs:roughness = 1.5'))
case("OPBR301_usd_openpbr_weight.usda", "OPBR301", "A USD OpenPBR shader with coat_weight -1.",
     usda('float inputs:coat_weight = -1'))
case("OPBR302_specular_ior_4_5.mtlx", "OPBR302", "specular_ior 4.5, valid but above the recommended range.",
     opbr('<input name="specular_ior" type="float" value="4.5" />'))
# (specular_weight 1.8 was a case here until session 20: OpenPBR explicitly allows it above 1, the slider's end)
case("OPBR302_abbe_number_below_soft_range.mtlx", "OPBR302", "transmission_dispersion_abbe_number 5, valid but below the recommended 9-91 (no glass disperses that much).",
     opbr('<input name="transmission_weight" type="float" value="1" />\n  <input name="transmission_dispersion_scale" type="float" value="1" />\n  <input name="transmission_dispersion_abbe_number" type="float" value="5" />'))
case("OPBR303_image_address_mode_repeat.mtlx", "OPBR303", "An image's uaddressmode 'repeat' (the OpenGL word): MaterialX's enum is constant, clamp, periodic, mirror.",
     opbr('<input name="base_color" type="color3" nodename="albedo" />',
          before='<image name="albedo" type="color3">\n  <input name="file" type="filename" value="textures/albedo.png" colorspace="srgb_texture" />\n  <input name="uaddressmode" type="string" value="repeat" />\n</image>'))
case("OPBR303_use_specular_workflow_two.mtlx", "OPBR303", "UsdPreviewSurface useSpecularWorkflow 2 (only 0 and 1 exist).",
     opbr('<input name="useSpecularWorkflow" type="integer" value="2" />', category="UsdPreviewSurface"))
case("OPBR303_gltf_alpha_mode.gltf", "OPBR303", "alphaMode 'TRANSPARENT', not one of OPAQUE, MASK, BLEND.",
     json.dumps(gltf([{"name": "M", "alphaMode": "TRANSPARENT"}]), indent=2))
case("OPBR303_usd_preview_opacity_mode.usda", "OPBR303", "UsdPreviewSurface opacityMode 'blend', not a token of the list.",
     preview('token inputs:opacityMode = "blend"'))

# ================================================================ version
case("OPBR401_coat_darkening_only.mtlx", "OPBR401", "(info) The version is inferred from coat_darkening alone; no version attribute.",
     opbr('<input name="coat_darkening" type="float" value="1" />'))
case("OPBR402_legacy_02_material.mtlx", "OPBR402", "A whole material written with OpenPBR 0.2 names (base_roughness, specular_ior_level).",
     opbr('<input name="base_roughness" type="float" value="0.2" />\n<input name="specular_ior_level" type="float" value="0.5" />'),
     also={"OPBR406": "MaterialX 1.39.5 ships only the OpenPBR 1.1.1 nodedef, so every legacy input is also one it does not declare"})
case("OPBR403_mixed_versions.mtlx", "OPBR403", "One material mixes 0.2's base_roughness with 1.1's coat_darkening.",
     opbr('<input name="base_roughness" type="float" value="0.2" />\n<input name="coat_darkening" type="float" value="1" />'))
case("OPBR404_two_versions_in_file.mtlx", "OPBR404", "Two materials in one file written for different OpenPBR versions.",
     mtlx('<open_pbr_surface name="S" type="surfaceshader">\n  <input name="base_roughness" type="float" value="0.2" />\n</open_pbr_surface>\n'
          '<open_pbr_surface name="T" type="surfaceshader">\n  <input name="coat_darkening" type="float" value="0.5" />\n</open_pbr_surface>\n'
          '<surfacematerial name="M2" type="material">\n  <input name="surfaceshader" type="surfaceshader" nodename="T" />\n</surfacematerial>'),
     also={"OPBR406": "the older material's legacy input is one the shipped 1.1.1 nodedef does not declare"})
case("OPBR406_legacy_emission_luminance.mtlx", "OPBR406", "A 0.3-era material using base_roughness, which the installed 1.1.1 nodedef does not declare.",
     opbr('<input name="base_roughness" type="float" value="0.3" />'))
case("OPBR406_version_0_2_attribute.mtlx", "OPBR406", "A shader that declares version=\"0.2\", which the installed MaterialX has no definition for.",
     opbr('<input name="base_weight" type="float" value="1" />', attrs=' version="0.2"'))

# ================================================================ colorspace
case("OPBR501_no_document_colorspace.mtlx", "OPBR501", "Colour values authored but the document states no colorspace.",
     opbr('<input name="base_color" type="color3" value="0.8, 0.2, 0.1" />', colorspace=None))
case("OPBR502_srgb_tx.mtlx", "OPBR502", "The OCIO role-style name srgb_tx instead of srgb_texture.",
     opbr('<input name="base_color" type="color3" value="0.5, 0.5, 0.5" colorspace="srgb_tx" />'))
case("OPBR502_sRGB_wrong_case_texture.mtlx", "OPBR502", "A texture colour space 'sRGB' (wrong case; MaterialX names it srgb_texture).",
     opbr('<input name="base_color" type="color3" nodename="albedo" />', before=image("albedo", "textures/albedo.png", colorspace="sRGB")))
case("OPBR502_ocio_utility_raw.mtlx", "OPBR502", "An ACES OCIO config name 'Utility - Raw' on a roughness map.",
     opbr('<input name="specular_roughness" type="float" nodename="rough" />', before=image("rough", "textures/rough.png", "float", "Utility - Raw")))
case("OPBR502_document_acescg_case.mtlx", "OPBR502", "The document colour space 'ACEScg' in OCIO's spelling instead of acescg.",
     opbr('<input name="base_color" type="color3" value="0.5, 0.5, 0.5" />', colorspace="ACEScg"))
case("OPBR502_usd_unknown_colorspace.usda", "OPBR502", "A USD image whose colorSpace metadata is the vendor name 'sRGB - Texture'.",
     usda('color3f inputs:base_color.connect = </M/albedo.outputs:out>', mximage("albedo", "textures/albedo.png", cs="sRGB - Texture")))
case("OPBR503_albedo_raw.mtlx", "OPBR503", "The base colour map is marked raw (colorspace none), so its sRGB values are used as linear.",
     opbr('<input name="base_color" type="color3" nodename="albedo" />', before=image("albedo", "textures/albedo.png", colorspace="none")))
case("OPBR504_roughness_srgb.mtlx", "OPBR504", "A roughness channel of an ORM map decoded as sRGB.",
     opbr('<input name="specular_roughness" type="float" nodename="g" />',
          before=image("orm", "textures/orm.png", colorspace="srgb_texture") + '\n<extract name="g" type="float">\n  <input name="in" type="color3" nodename="orm" />\n  <input name="index" type="integer" value="1" />\n</extract>'))
case("OPBR504_coat_roughness_srgb_channel.mtlx", "OPBR504", "coat_roughness taken from the red channel of a packed colour image decoded as sRGB.",
     opbr('<input name="coat_weight" type="float" value="1" />\n<input name="coat_roughness" type="float" nodename="r" />',
          before=image("packed", "textures/orm.png", colorspace="srgb_texture") + '\n<extract name="r" type="float">\n  <input name="in" type="color3" nodename="packed" />\n  <input name="index" type="integer" value="0" />\n</extract>'))
case("OPBR504_usd_preview_normal_srgb.usda", "OPBR504", "A UsdUVTexture normal map with sourceColorSpace sRGB (scale and bias are set correctly).",
     preview('normal3f inputs:normal.connect = </M/nrm.outputs:rgb>',
             uvtex("nrm", "textures/normal.png", cs="sRGB", extra='    float4 inputs:scale = (2, 2, 2, 1)\n    float4 inputs:bias = (-1, -1, -1, 0)\n')))
case("OPBR504_usd_preview_roughness_srgb.usda", "OPBR504", "A UsdUVTexture roughness map read with sourceColorSpace sRGB.",
     preview('float inputs:roughness.connect = </M/rough.outputs:r>', uvtex("rough", "textures/rough.png", out="r", out_type="float", cs="sRGB")))

case("OPBR508_colorspace_on_interface_only.mtlx", "OPBR508", "srgb_texture sits only on the node graph's interface input the image's file name comes through; MaterialX's shader generation reads the image's own file input and applies no decode.",
     mtlx('<nodegraph name="NG">\n  <input name="albedo_file" type="filename" value="textures/albedo.png" colorspace="srgb_texture" />\n'
          '  <image name="albedo" type="color3">\n    <input name="file" type="filename" interfacename="albedo_file" />\n  </image>\n'
          '  <output name="out" type="color3" nodename="albedo" />\n</nodegraph>\n'
          '<open_pbr_surface name="S" type="surfaceshader">\n  <input name="base_color" type="color3" nodegraph="NG" output="out" />\n</open_pbr_surface>'))

# ================================================================ units
case("OPBR601_depth_in_degrees.mtlx", "OPBR601", "transmission_depth carries unittype angle (unit degree).",
     opbr('<input name="transmission_depth" type="float" value="2" unittype="angle" unit="degree" />'))
case("OPBR601_radius_unittype_length.mtlx", "OPBR601", "subsurface_radius with unittype 'length' (MaterialX calls it distance).",
     opbr('<input name="subsurface_weight" type="float" value="1" />\n<input name="subsurface_radius" type="float" value="0.5" unittype="length" unit="centimeter" />'),
     also={"OPBR004": "MaterialX has no unittype 'length', so Document.validate() rejects the same input"})
case("OPBR602_unit_cm.mtlx", "OPBR602", "subsurface_radius with unit 'cm' (MaterialX spells it centimeter).",
     opbr('<input name="subsurface_radius" type="float" value="0.5" unittype="distance" unit="cm" />'),
     also={"OPBR004": "MaterialX has no such unit definition, so Document.validate() rejects the same input"})
case("OPBR602_unit_metre_british.mtlx", "OPBR602", "transmission_depth in 'metre' (MaterialX spells it meter).",
     opbr('<input name="transmission_depth" type="float" value="0.02" unittype="distance" unit="metre" />'),
     also={"OPBR004": "MaterialX has no such unit definition, so Document.validate() rejects the same input"})
case("OPBR602_unit_inches.mtlx", "OPBR602", "transmission_depth in 'inches' (MaterialX has inch).",
     opbr('<input name="transmission_depth" type="float" value="1" unittype="distance" unit="inches" />'),
     also={"OPBR004": "MaterialX has no such unit definition, so Document.validate() rejects the same input"})
case("OPBR603_depth_without_unit.mtlx", "OPBR603", "(info) transmission_depth set without unit information.",
     opbr('<input name="transmission_depth" type="float" value="2" />'))
case("OPBR604_thin_film_nanometer_unit.mtlx", "OPBR604", "thin_film_thickness tagged unit nanometer, but its unit is fixed (micrometres).",
     opbr('<input name="thin_film_weight" type="float" value="1" />\n<input name="thin_film_thickness" type="float" value="0.5" unittype="distance" unit="nanometer" />'))
case("OPBR604_unit_on_weight.mtlx", "OPBR604", "A unit on base_weight, an input that has no unit.",
     opbr('<input name="base_weight" type="float" value="1" unittype="distance" unit="meter" />'))
case("OPBR605_thin_film_400.mtlx", "OPBR605", "thin_film_thickness 400, nanometres written into the micrometre input.",
     opbr('<input name="thin_film_weight" type="float" value="1" />\n<input name="thin_film_thickness" type="float" value="400" />'))
case("OPBR605_usd_thin_film_550.usda", "OPBR605", "A USD OpenPBR shader with thin_film_thickness 550 (nanometres).",
     usda('float inputs:thin_film_weight = 1\nfloat inputs:thin_film_thickness = 550'))

case("OPBR606_thin_film_in_metres.mtlx", "OPBR606", "thin_film_thickness 4.5e-07, metres written into the micrometre input.",
     opbr('<input name="thin_film_weight" type="float" value="1" />\n<input name="thin_film_thickness" type="float" value="4.5e-07" />'))

# ================================================================ textures
case("OPBR701_missing_albedo.mtlx", "OPBR701", "The base colour texture was not copied with the document.",
     opbr('<input name="base_color" type="color3" nodename="albedo" />', before=image("albedo", "textures/albedo_missing.png")))
case("OPBR701_missing_udim.mtlx", "OPBR701", "A UDIM path whose tiles were never exported.",
     opbr('<input name="base_color" type="color3" nodename="albedo" />', before=image("albedo", "textures/paint.<UDIM>.png")))
case("OPBR701_udim_token_lowercase.mtlx", "OPBR701", "A UDIM path written with '<udim>' in lower case, which MaterialX does not substitute, so no tile is found.",
     opbr('<input name="base_color" type="color3" nodename="albedo" />', before=image("albedo", "textures/albedo.&lt;udim&gt;.png")))
case("OPBR701_usd_missing_texture.usda", "OPBR701", "A USD image node whose file does not exist.",
     usda('color3f inputs:base_color.connect = </M/albedo.outputs:out>', mximage("albedo", "textures/gone.png")))
case("OPBR701_gltf_missing_image.gltf", "OPBR701", "A glTF image URI pointing to a file that was not shipped.",
     json.dumps(textured({"name": "M", "pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}}, uri="textures/missing_basecolor.png"), indent=2))
case("OPBR707_lfs_pointer_texture.mtlx", "OPBR707", "The repository was cloned without `git lfs pull`: the base colour texture is a Git LFS pointer (text), not the PNG.",
     opbr('<input name="base_color" type="color3" nodename="albedo" />', before=image("albedo", "textures/lfs_albedo.png")))
case("OPBR707_truncated_jpeg.gltf", "OPBR707", "An upload cut the base colour JPEG short: its header is whole, its scan data ends half-way.",
     json.dumps(textured({"name": "M", "pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}}, uri="textures/cut.jpg"), indent=2))
case("OPBR707_usd_empty_texture.usda", "OPBR707", "The texture export failed and left a file of 0 bytes behind.",
     preview('color3f inputs:diffuseColor.connect = </M/albedo.outputs:rgb>', uvtex("albedo", "textures/empty.png")))
case("OPBR708_unknown_bytes_texture.mtlx", "OPBR708", "A roughness file whose bytes are in no image format (a mislabelled or scrambled file).",
     opbr('<input name="specular_roughness" type="float" nodename="rough" />', before=image("rough", "textures/scrambled.png", "float", "none")))
case("OPBR1214_gltf_jpeg_declared_png.gltf", "OPBR1214", "An exporter re-encoded the base colour image as JPEG but kept mimeType image/png.",
     json.dumps(gltf([{"name": "M", "pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}}],
                     images=[{"uri": "textures/photo.jpg", "mimeType": "image/png"}], textures=[{"source": 0}]), indent=2))
UV_MESH = ('def Mesh "Plane" (\n    prepend apiSchemas = ["MaterialBindingAPI"]\n)\n{\n'
           '    int[] faceVertexCounts = [4]\n    int[] faceVertexIndices = [0, 1, 2, 3]\n'
           '    point3f[] points = [(-1, 0, -1), (1, 0, -1), (1, 0, 1), (-1, 0, 1)]\n'
           '    texCoord2f[] primvars:UVMap = [(0, 0), (1, 0), (1, 1), (0, 1)] (\n        interpolation = "vertex"\n    )\n'
           '    rel material:binding = </M>\n}\n')
UV_READER = ('def Shader "uv"\n{\n    uniform token info:id = "UsdPrimvarReader_float2"\n'
             '    string inputs:varname = "st"\n    float2 outputs:result\n}\n')
case("OPBR1015_usd_uvmap_read_as_st.usda", "OPBR1015", "A Blender export named the mesh's UVs UVMap while the material's primvar reader reads st.",
     preview('color3f inputs:diffuseColor.connect = </M/albedo.outputs:rgb>',
             uvtex("albedo", "textures/checker.png", extra='    float2 inputs:st.connect = </M/uv.outputs:result>\n') + "\n" + UV_READER)
     + "\n" + UV_MESH)
case("OPBR1016_usd_st_unconnected.usda", "OPBR1016", "The UsdUVTexture's st was never connected to a primvar reader.",
     preview('color3f inputs:diffuseColor.connect = </M/albedo.outputs:rgb>', uvtex("albedo", "textures/checker.png")))
BOUND_MESH = ('def Mesh "Plane" (\n    prepend apiSchemas = ["MaterialBindingAPI"]\n)\n{\n'
              '    int[] faceVertexCounts = [3]\n    int[] faceVertexIndices = [0, 1, 2]\n'
              '    point3f[] points = [(0, 0, 0), (1, 0, 0), (0, 0, 1)]\n    rel material:binding = <TARGET>\n}\n')
case("OPBR1017_usd_binding_to_shader.usda", "OPBR1017", "The mesh's material:binding was picked in an outliner on the Shader prim instead of its Material: USD resolves it to no material.",
     usda('color3f inputs:base_color = (0.6, 0.2, 0.1)') + "\n" + BOUND_MESH.replace("TARGET", "/M/S"))
case("OPBR1017_usd_binding_to_renamed_material.usda", "OPBR1017", "The Material was renamed after the binding was made: the binding targets a prim that no longer exists.",
     usda('color3f inputs:base_color = (0.6, 0.2, 0.1)') + "\n" + BOUND_MESH.replace("TARGET", "/M_Old"))
case("OPBR806_separate3_without_output.mtlx", "OPBR806", "An ORM map's roughness is wired from a separate3 without output=\"outg\": MaterialX takes the red channel (occlusion).",
     opbr('<input name="specular_roughness" type="float" nodegraph="NG" output="rough" />',
          before='<nodegraph name="NG">\n  <image name="orm" type="color3">\n'
                 '    <input name="file" type="filename" value="textures/orm.png" colorspace="none" />\n  </image>\n'
                 '  <separate3 name="split" type="multioutput">\n    <input name="in" type="color3" nodename="orm" />\n'
                 '  </separate3>\n  <output name="rough" type="float" nodename="split" />\n</nodegraph>'))
case("OPBR1021_usd_binding_render_purpose.usda", "OPBR1021", "The mesh binds its material under material:binding:render, a geometry purpose: no renderer asks for it and the mesh renders unbound.",
     usda('color3f inputs:base_color = (0.6, 0.2, 0.1)') + "\n" + BOUND_MESH.replace("rel material:binding =", "rel material:binding:render =").replace("TARGET", "/M"))
case("OPBR1022_usd_binding_strength_token.usda", "OPBR1022", "An override binding says bindMaterialAs = \"strongest\", which is no strength: USD reads it as weaker than descendants.",
     usda('color3f inputs:base_color = (0.6, 0.2, 0.1)') + "\n" + BOUND_MESH.replace("<TARGET>", '</M> (\n        bindMaterialAs = "strongest"\n    )'))
case("OPBR1023_usd_collection_stale.usda", "OPBR1023", "A collection binding's collection still lists the meshes' old paths after they were renamed: it binds nothing.",
     usda('color3f inputs:base_color = (0.6, 0.2, 0.1)') + "\n" + BOUND_MESH.replace(
         '["MaterialBindingAPI"]', '["MaterialBindingAPI", "CollectionAPI:parts"]').replace(
         "rel material:binding = <TARGET>", 'uniform token collection:parts:expansionRule = "expandPrims"\n'
         "    rel collection:parts:includes = </Plane_old>\n"
         "    rel material:binding:collection:parts = [</Plane.collection:parts>, </M>]"))
case("OPBR1024_usd_render_context_misspelt.usda", "OPBR1024", "The Material's only surface output is outputs:materialx:surface (MaterialX's context is mtlx): no renderer finds the surface.",
     usda('color3f inputs:base_color = (0.6, 0.2, 0.1)', output="materialx:surface"))
case("OPBR1018_usd_input_relationship.usda", "OPBR1018", "A script authored the base colour connection as a relationship (rel inputs:base_color) instead of an attribute connection: the input is never connected.",
     usda('rel inputs:base_color = </M/albedo.outputs:out>', mximage("albedo", "textures/albedo.png")))
case("OPBR1019_usd_interface_only_connected.usda", "OPBR1019", "base_color carries connectability interfaceOnly (copied from an interface template) yet is connected to an image node's output, which UsdShade refuses.",
     usda('color3f inputs:base_color (\nconnectability = "interfaceOnly"\n)\ncolor3f inputs:base_color.connect = </M/albedo.outputs:out>',
          mximage("albedo", "textures/albedo.png")))
case("OPBR1001_usd_source_asset_not_authored.usda", "OPBR1001", "The shader says info:implementationSource = sourceAsset but authors no source asset, so its info:id is ignored and no definition is found.",
     usda('uniform token info:implementationSource = "sourceAsset"\ncolor3f inputs:base_color = (0.6, 0.2, 0.1)'))
case("OPBR1007_usd_threshold_cuts_everything.usda", "OPBR1007", "A 35%-opaque pane was given opacityThreshold 0.5 in its preview surface: every fragment falls below the threshold and the pane vanishes.",
     preview('float inputs:opacity = 0.35\nfloat inputs:opacityThreshold = 0.5'))
case("OPBR711_tiledimage_tiling_zero.mtlx", "OPBR711", "An unset tiling was exported as uvtiling (0, 0): every point reads the same texel.",
     opbr('<input name="base_color" type="color3" nodename="albedo" />',
          before='<tiledimage name="albedo" type="color3">\n  <input name="file" type="filename" value="textures/albedo.png" colorspace="srgb_texture" />\n'
                 '  <input name="uvtiling" type="vector2" value="0, 0" />\n</tiledimage>'))
case("OPBR712_roughness_reads_basecolor.mtlx", "OPBR712", "An auto-assign script picked the base colour file for the roughness slot: roughness is the colour's red channel.",
     opbr('<input name="base_color" type="color3" nodename="albedo" />\n<input name="specular_roughness" type="float" nodename="rough" />',
          before=image("albedo", "textures/albedo.png") + "\n" + image("rough", "textures/albedo.png", "float", None)))
case("OPBR719_place2d_rotate_in_radians.mtlx", "OPBR719", "A script copied a quarter turn from an API in radians: place2d rotate = 1.5708 (degrees), so the floor turns 1.6 degrees, not 90.",
     opbr('<input name="base_color" type="color3" nodename="albedo" />',
          before='<texcoord name="uv" type="vector2" />\n<place2d name="turned" type="vector2">\n  <input name="texcoord" type="vector2" nodename="uv" />\n'
                 '  <input name="rotate" type="float" value="1.5708" />\n</place2d>\n<image name="albedo" type="color3">\n'
                 '  <input name="file" type="filename" value="textures/albedo.png" colorspace="srgb_texture" />\n'
                 '  <input name="texcoord" type="vector2" nodename="turned" />\n</image>'))
case("OPBR807_extract_alpha_of_color3.mtlx", "OPBR807", "A Unity mask map's smoothness (alpha) read by extract index 3 from an image read as color3, which has no fourth channel.",
     opbr('<input name="specular_roughness" type="float" nodename="smooth" />',
          before=image("mask", "textures/albedo.png", "color3", None) + '\n<extract name="smooth" type="float">\n'
                 '  <input name="in" type="color3" nodename="mask" />\n  <input name="index" type="integer" value="3" />\n</extract>'))
case("OPBR909_black_metal.mtlx", "OPBR909", "A dielectric's black base colour was left on a metal: it reflects nothing at normal incidence.",
     opbr('<input name="base_metalness" type="float" value="1" />\n<input name="base_color" type="color3" value="0, 0, 0" />'))
case("OPBR1020_usd_layer_in_metres.usda", "OPBR1020", "A centimetre stage sublayers a look layer authored in metres: its transmission depth of 2.5 (m) reads as 2.5 cm.",
     usda('float inputs:transmission_weight = 1').replace(
         'metersPerUnit = 0.01\n', 'metersPerUnit = 0.01\n    subLayers = [@OPBR1020_layers/look_m.usda@]\n', 1))
case("OPBR709_height_map_as_normal.gltf", "OPBR709", "A greyscale height map was plugged into the normal texture slot.",
     json.dumps(textured({"name": "M", "normalTexture": {"index": 0}}, uri="textures/rough.png"), indent=2))
case("OPBR702_color_image_into_metalness.mtlx", "OPBR702", "A color3 image fed straight into the float base_metalness.",
     opbr('<input name="base_metalness" type="float" nodename="metal" />', before=image("metal", "textures/rough.png", "color3", "none")),
     also={"OPBR004": "Document.validate() rejects the same mismatched connection"})
case("OPBR702_float_image_into_color.mtlx", "OPBR702", "A float image fed into base_color.",
     opbr('<input name="base_color" type="color3" nodename="a" />', before=image("a", "textures/albedo.png", "float", None)),
     also={"OPBR004": "Document.validate() rejects the same mismatched connection"})
case("OPBR703_normal_without_normalmap.mtlx", "OPBR703", "The normal map image is connected directly to geometry_normal without a normalmap node.",
     opbr('<input name="geometry_normal" type="vector3" nodename="nrm" />', before=image("nrm", "textures/normal.png", "vector3", "none")))
case("OPBR710_tiff_normal_without_normalmap.mtlx", "OPBR710", "A TIFF normal map connected directly to geometry_normal: it may hold world-space normals, or be a tangent-space map missing its normalmap node.",
     opbr('<input name="geometry_normal" type="vector3" nodename="nrm" />', before=image("nrm", "textures/normal.tif", "vector3", "none")))
case("OPBR704_absolute_texture_path.mtlx", "OPBR704", "An absolute path from the artist's machine.",
     opbr('<input name="base_color" type="color3" nodename="albedo" />', before=image("albedo", os.path.join(HERE, "textures", "albedo.png").replace(os.sep, "/").replace(HERE.replace(os.sep, "/"), "/home/artist/project/tex"))),
     also={"OPBR701": "an absolute path from another machine does not exist here either"})
case("OPBR704_parent_folder_texture.mtlx", "OPBR704", "A texture path that climbs out of the asset's folder with '..' to nothing (to an image that is there, a shared folder, it is OPBR723, information).",
     opbr('<input name="base_color" type="color3" nodename="albedo" />', before=image("albedo", "../shared/textures/albedo.png")),
     also={"OPBR701": "nothing is there either"})
case("OPBR704_url_texture.mtlx", "OPBR704", "A texture referenced by an http URL.",
     opbr('<input name="base_color" type="color3" nodename="albedo" />', before=image("albedo", "https://cdn.example.com/albedo.png")))
case("OPBR704_gltf_absolute_uri.gltf", "OPBR704", "A glTF image URI that is an absolute Windows path.",
     json.dumps(textured({"name": "M", "pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}}, uri="file:///C:/Users/artist/albedo.png"), indent=2))
case("OPBR705_empty_file.mtlx", "OPBR705", "An image node whose file input is empty.",
     opbr('<input name="base_color" type="color3" nodename="albedo" />', before=image("albedo", "")))
case("OPBR705_gltf_empty_uri.gltf", "OPBR705", "A glTF image with an empty URI.",
     json.dumps(textured({"name": "M", "pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}}, uri=""), indent=2))
case("OPBR1246_gltf_normals_behind_the_faces.gltf", "OPBR1246", "A sheet whose NORMALs point down while its triangles wind up: lit from behind.",
     all_rules()["OPBR1246"].failing)
case("OPBR1247_gltf_mirrored_uvs_tangent_w_not_flipped.gltf", "OPBR1247", "The second quad's UV island is mirrored in u, but its tangents keep w = +1: its normal map reads green inverted.",
     all_rules()["OPBR1247"].failing)
case("OPBR1248_gltf_volume_on_open_sheet.gltf", "OPBR1248", "A window pane modelled as one open quad with KHR_materials_volume thickness 0.01: the volume has no inside.",
     all_rules()["OPBR1248"].failing)
case("OPBR1243_gltf_transform_on_base_colour_only.gltf", "OPBR1243", "KHR_texture_transform tiles the base colour 4 x 4 while the normal map on the same UV set stays at 1 x: the texture set slides apart.",
     all_rules()["OPBR1243"].failing)
case("OPBR724_normal_map_inward.mtlx", "OPBR724", "A normal map whose blue channel is 0 (inverted with the green): decoded, its normals face into the surface.",
     opbr('<input name="geometry_normal" type="vector3" nodename="nm" />',
          before=image("nmap", "textures/normal_inward.png", "vector3", None) + '\n<normalmap name="nm" type="vector3">\n  <input name="in" type="vector3" nodename="nmap" />\n</normalmap>'))

# ================================================================ structure
case("OPBR801_material_without_shader.mtlx", "OPBR801", "A surfacematerial with no surfaceshader input.",
     mtlx('<open_pbr_surface name="S" type="surfaceshader" />\n<surfacematerial name="M" type="material" />', material=False))
case("OPBR801_usd_material_no_output.usda", "OPBR801", "A USD Material whose surface output is not connected to any shader.",
     USD_HEAD + 'def Material "M"\n{\n    token outputs:mtlx:surface\n\n    def Shader "S"\n    {\n        uniform token info:id = "ND_open_pbr_surface_surfaceshader"\n        token outputs:surface\n    }\n}\n')
case("OPBR802_nodename_nowhere.mtlx", "OPBR802", "base_weight connected to a node 'weight_map' that was not exported.",
     opbr('<input name="base_weight" type="float" nodename="weight_map" />'))
case("OPBR802_material_to_missing_shader.mtlx", "OPBR802", "The material's surfaceshader names a shader 'S_old' that was renamed.",
     opbr('<input name="base_weight" type="float" value="1" />', shader="S_old"),
     also={"OPBR004": "Document.validate() rejects the same dangling connection"})
case("OPBR802_missing_graph_output.mtlx", "OPBR802", "An input connected to a node graph output that the graph does not have.",
     opbr('<input name="base_color" type="color3" nodegraph="NG" output="albedo_out" />',
          before='<nodegraph name="NG">\n  <image name="albedo" type="color3">\n    <input name="file" type="filename" value="textures/albedo.png" colorspace="srgb_texture" />\n  </image>\n  <output name="out" type="color3" nodename="albedo" />\n</nodegraph>'))
case("OPBR802_usd_connect_missing_prim.usda", "OPBR802", "A USD connection to a texture prim that does not exist.",
     usda('color3f inputs:base_color.connect = </M/albedo_tex.outputs:out>'))
case("OPBR802_gltf_texture_index.gltf", "OPBR802", "baseColorTexture index 3 while the file has one texture.",
     json.dumps(textured({"name": "M", "pbrMetallicRoughness": {"baseColorTexture": {"index": 3}}}), indent=2))
case("OPBR802_gltf_texture_source.glb", "OPBR802", "A GLB whose texture's source names image 2, which does not exist.",
     glb(gltf([{"name": "M", "pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}}], images=[{"uri": PNG_URI}], textures=[{"source": 2}])))
case("OPBR803_procedural_noise.mtlx", "OPBR803", "(info) base_color driven by a noise3d graph the toolkit does not interpret.",
     opbr('<input name="base_color" type="color3" nodename="n" />', before='<noise3d name="n" type="color3" />'))
case("OPBR804_orphan_shader.mtlx", "OPBR804", "(info) A shader that no material refers to (left over from an edit).",
     mtlx('<open_pbr_surface name="S" type="surfaceshader" />\n<open_pbr_surface name="Unused" type="surfaceshader" />'))

# ================================================================ plausibility
case("OPBR901_dark_metal.mtlx", "OPBR901", "(info) A metal with base colour 0.1 grey, darker than any real metal.",
     opbr('<input name="base_metalness" type="float" value="1" />\n<input name="base_color" type="color3" value="0.1, 0.1, 0.1" />'))
case("OPBR902_white_dielectric.mtlx", "OPBR902", "(info) A dielectric with base colour pure white.",
     opbr('<input name="base_color" type="color3" value="1, 1, 1" />'))
case("OPBR903_metal_with_transmission.mtlx", "OPBR903", "A fully metallic surface with transmission_weight 1.",
     opbr('<input name="base_metalness" type="float" value="1" />\n<input name="base_color" type="color3" value="0.9, 0.9, 0.9" />\n<input name="transmission_weight" type="float" value="1" />'))
case("OPBR1211_gltf_metal_transmission.gltf", "OPBR1211", "A glTF metal (metallicFactor 1) with KHR_materials_transmission 1.",
     json.dumps(gltf([{"name": "M", "pbrMetallicRoughness": {"metallicFactor": 1.0, "baseColorFactor": [0.9, 0.9, 0.9, 1.0]},
                       "extensions": {"KHR_materials_transmission": {"transmissionFactor": 1.0}}}], ["KHR_materials_transmission"]), indent=2))
case("OPBR903_usd_metal_transmission.usda", "OPBR903", "A USD OpenPBR metal with transmission_weight 0.8.",
     usda('float inputs:base_metalness = 1\ncolor3f inputs:base_color = (0.9, 0.9, 0.9)\nfloat inputs:transmission_weight = 0.8'))
case("OPBR904_thin_film_zero.mtlx", "OPBR904", "thin_film_weight 1 with thin_film_thickness 0.",
     opbr('<input name="thin_film_weight" type="float" value="1" />\n<input name="thin_film_thickness" type="float" value="0" />'))
case("OPBR1211_gltf_iridescence_zero.gltf", "OPBR1211", "KHR_materials_iridescence on with iridescenceThicknessMaximum 0.",
     json.dumps(gltf([{"name": "M", "extensions": {"KHR_materials_iridescence": {"iridescenceFactor": 1.0, "iridescenceThicknessMinimum": 0, "iridescenceThicknessMaximum": 0}}}], ["KHR_materials_iridescence"]), indent=2))
case("OPBR905_coat_ior_half.mtlx", "OPBR905", "coat_ior 0.5 (an IOR below 1, e.g. a relative IOR written as absolute).",
     opbr('<input name="coat_weight" type="float" value="1" />\n<input name="coat_ior" type="float" value="0.5" />'))
case("OPBR905_specular_ior_0_9.mtlx", "OPBR905", "specular_ior 0.9.",
     opbr('<input name="specular_ior" type="float" value="0.9" />'))
case("OPBR905_thin_film_ior_below_one.mtlx", "OPBR905", "thin_film_ior 0.8 on an active film.",
     opbr('<input name="thin_film_weight" type="float" value="1" />\n<input name="thin_film_thickness" type="float" value="0.5" />\n<input name="thin_film_ior" type="float" value="0.8" />'))
case("OPBR906_half_metal.mtlx", "OPBR906", "(info) A constant base_metalness of 0.5.",
     opbr('<input name="base_metalness" type="float" value="0.5" />'))
case("OPBR907_emission_no_luminance.mtlx", "OPBR907", "(info) emission_color set with emission_luminance 0.",
     opbr('<input name="emission_color" type="color3" value="1, 0.5, 0.2" />'))
case("OPBR908_invisible.mtlx", "OPBR908", "geometry_opacity 0 left on a material: the surface is invisible.",
     opbr('<input name="geometry_opacity" type="float" value="0" />'))

# ================================================================ usd
case("OPBR1001_shader_without_id.usda", "OPBR1001", "A USD Shader prim with no info:id.",
     usda('color3f inputs:base_color = (0.5, 0.4, 0.3)', shader_id=None))
case("OPBR1002_base_color_float3.usda", "OPBR1002", "base_color authored as float3 where the node declares color3f.",
     usda('float3 inputs:base_color = (0.5, 0.4, 0.3)'))
case("OPBR1002_roughness_double.usda", "OPBR1002", "specular_roughness authored as double instead of float.",
     usda('double inputs:specular_roughness = 0.4'))
case("OPBR1002_preview_roughness_double.usda", "OPBR1002", "UsdPreviewSurface roughness authored as double instead of float.",
     preview('double inputs:roughness = 0.4'))
case("OPBR1003_surfaceshdr_typo.usda", "OPBR1003", "info:id ND_open_pbr_surface_surfaceshdr (misspelt).",
     usda('color3f inputs:base_color = (0.5, 0.4, 0.3)', shader_id="ND_open_pbr_surface_surfaceshdr"))
case("OPBR1003_usd_preview_surface_typo.usda", "OPBR1003", "info:id 'UsdPreviewSurfce' under outputs:surface.",
     usda('color3f inputs:diffuseColor = (0.5, 0.4, 0.3)', shader_id="UsdPreviewSurfce", output="surface"))
case("OPBR1004_usd_raw_in_materialx_image.usda", "OPBR1004", "An ND_image_color3 node tagged with the USD data name 'raw' (MaterialX says 'none', and its main branch refuses to generate a shader for an unknown name on a colour image).",
     usda('color3f inputs:emission_color.connect = </M/glow.outputs:out>', mximage("glow", "textures/albedo.png", type_="color3", cs="raw")))
case("OPBR1005_surface_output_to_image.usda", "OPBR1005", "The Material's MaterialX surface output connected to an image node's colour output instead of the shader.",
     usda('color3f inputs:base_color = (0.5, 0.4, 0.3)', extra_prims=mximage("albedo", "textures/albedo.png", cs="srgb_texture")).replace(
         "token outputs:mtlx:surface.connect = </M/S.outputs:surface>", "token outputs:mtlx:surface.connect = </M/albedo.outputs:out>"))
case("OPBR1005_float_into_color.usda", "OPBR1005", "A float material interface input connected into color3f base_color.",
     usda('color3f inputs:base_color.connect = </M.inputs:albedo>', material_body='float inputs:albedo = 0.5'))
case("OPBR1010_binding_without_api.usda", "OPBR1010", "A mesh binds the material without MaterialBindingAPI applied (usd-core's MissingMaterialBindingAPI: OpenUSD is to ignore such bindings).",
     usda('color3f inputs:base_color = (0.5, 0.4, 0.3)') + 'def Mesh "Ball"\n{\n    rel material:binding = </M>\n}\n')
case("OPBR1011_sublayer_parent.usda", "OPBR1011", "A sublayer that climbs out of the asset's folder.",
     usda('color3f inputs:base_color = (0.5, 0.4, 0.3)', head='#usda 1.0\n(\n    defaultPrim = "M"\n    subLayers = [@../shared/looks.usda@]\n    metersPerUnit = 0.01\n    upAxis = "Y"\n)\n\n'))
case("OPBR1011_reference_absolute.usda", "OPBR1011", "A reference to an absolute path on a render farm.",
     usda('color3f inputs:base_color = (0.5, 0.4, 0.3)', head='#usda 1.0\n(\n    defaultPrim = "M"\n    subLayers = [@/mnt/farm/lib/looks.usda@]\n    metersPerUnit = 0.01\n    upAxis = "Y"\n)\n\n'))


def usdz_with_compressed_entry() -> bytes:
    buffer = io.BytesIO()
    with zipfile.ZipFile(buffer, "w") as archive:
        archive.writestr(zipfile.ZipInfo("root.usda"), usda('color3f inputs:base_color = (0.5, 0.4, 0.3)'))
        archive.writestr("textures/albedo.png", TEXTURES["textures/albedo.png"], compress_type=zipfile.ZIP_DEFLATED)
    return buffer.getvalue()


case("OPBR1012_usdz_compressed_entry.usdz", "OPBR1012", "A USDZ package zipped with deflate, which USDZ forbids (entries must be stored).",
     usdz_with_compressed_entry())
case("OPBR1013_sublayer_mtlx.usda", "OPBR1013", "(info) A sublayer naming a MaterialX document.",
     usda('color3f inputs:base_color = (0.5, 0.4, 0.3)', head='#usda 1.0\n(\n    defaultPrim = "M"\n    subLayers = [@./OPBR1013_look.mtlx@]\n    metersPerUnit = 0.01\n    upAxis = "Y"\n)\n\n'))

# ================================================================ usd_preview
case("OPBR1006_normal_without_scale_bias.usda", "OPBR1006", "An 8-bit normal map read raw but without scale (2,2,2) and bias (-1,-1,-1).",
     preview('normal3f inputs:normal.connect = </M/nrm.outputs:rgb>', uvtex("nrm", "textures/normal.png", cs="raw")))
case("OPBR1006_normal_scale_only.usda", "OPBR1006", "A normal map with scale 2 but the bias forgotten.",
     preview('normal3f inputs:normal.connect = </M/nrm.outputs:rgb>', uvtex("nrm", "textures/normal.png", cs="raw", extra='    float4 inputs:scale = (2, 2, 2, 1)\n')))
case("OPBR1007_threshold_with_transparent.usda", "OPBR1007", "opacityThreshold set while opacityMode is transparent.",
     preview('token inputs:opacityMode = "transparent"\nfloat inputs:opacity = 0.4\nfloat inputs:opacityThreshold = 0.5'))
case("OPBR1008_metallic_with_black_specular.usda", "OPBR1008", "A metal (metallic 0.9) in the specular workflow without a specularColor: no reflection at normal incidence.",
     preview('int inputs:useSpecularWorkflow = 1\nfloat inputs:metallic = 0.9\ncolor3f inputs:diffuseColor = (0.9, 0.6, 0.3)'))
case("OPBR1034_mask_below_threshold.usda", "OPBR1034", "opacity reads the red of a mid-grey image (128/255 everywhere) under opacityThreshold 0.6: the whole material is cut away.",
     preview('float inputs:opacity.connect = </M/mask.outputs:r>\nfloat inputs:opacityThreshold = 0.6',
             uvtex("mask", "textures/albedo.png", out="r", out_type="float", cs="raw")))
case("OPBR1008_metallic_in_specular_workflow.usda", "OPBR1008", "metallic authored with useSpecularWorkflow 1.",
     preview('int inputs:useSpecularWorkflow = 1\nfloat inputs:metallic = 1'))
case("OPBR1009_preview_disagrees.usda", "OPBR1009", "The UsdPreviewSurface fallback is blue while the OpenPBR shader is brown.",
     usda('color3f inputs:base_color = (0.5, 0.4, 0.3)',
          'def Shader "P"\n{\n    uniform token info:id = "UsdPreviewSurface"\n    color3f inputs:diffuseColor = (0.05, 0.3, 0.8)\n    token outputs:surface\n}\n',
          material_body='token outputs:surface.connect = </M/P.outputs:surface>'))
case("OPBR1041_usd_meters_per_unit_zero.usda", "OPBR1041", "A stage exported with metersPerUnit 0 (an unset unit written as zero): the transmission depth means nothing.",
     usda('float inputs:transmission_weight = 1\nfloat inputs:transmission_depth = 2',
          head='#usda 1.0\n(\n    defaultPrim = "M"\n    metersPerUnit = 0\n    upAxis = "Y"\n)\n\n'))

# ================================================================ gltf
case("OPBR1201_clearcoat_undeclared.gltf", "OPBR1201", "KHR_materials_clearcoat used but not listed in extensionsUsed.",
     json.dumps(gltf([{"name": "M", "extensions": {"KHR_materials_clearcoat": {"clearcoatFactor": 1.0}}}]), indent=2))
case("OPBR1201_texture_transform_undeclared.gltf", "OPBR1201", "KHR_texture_transform on a textureInfo but not declared in extensionsUsed.",
     json.dumps(textured({"name": "M", "pbrMetallicRoughness": {"baseColorTexture": {"index": 0, "extensions": {"KHR_texture_transform": {"scale": [2.0, 2.0]}}}}}), indent=2))
case("OPBR1201_required_not_used.glb", "OPBR1201", "A GLB listing KHR_materials_ior in extensionsRequired only, not in extensionsUsed.",
     glb(gltf([{"name": "M", "extensions": {"KHR_materials_ior": {"ior": 1.4}}}], extensionsRequired=["KHR_materials_ior"])))
case("OPBR1202_vendor_required.gltf", "OPBR1202", "A vendor extension listed as required, which the toolkit cannot interpret.",
     json.dumps(gltf([{"name": "M", "extensions": {"VENDOR_materials_magic": {"sparkle": 1}}}], ["VENDOR_materials_magic"], extensionsRequired=["VENDOR_materials_magic"]), indent=2))
case("OPBR1203_unlit_with_clearcoat.gltf", "OPBR1203", "KHR_materials_unlit combined with KHR_materials_clearcoat, which the specification forbids.",
     json.dumps(gltf([{"name": "M", "extensions": {"KHR_materials_unlit": {}, "KHR_materials_clearcoat": {"clearcoatFactor": 1.0}}}], ["KHR_materials_unlit", "KHR_materials_clearcoat"]), indent=2))
case("OPBR301_spec_gloss_glossiness_over_one.gltf", "OPBR301",
     "A KHR_materials_pbrSpecularGlossiness glossinessFactor of 1.2 (the extension's schema: [0, 1]).",
     json.dumps(gltf([{"name": "M", "extensions": {"KHR_materials_pbrSpecularGlossiness": {"diffuseFactor": [0.8, 0.8, 0.8, 1.0], "glossinessFactor": 1.2}}}], ["KHR_materials_pbrSpecularGlossiness"]), indent=2))
case("OPBR1204_spec_gloss.gltf", "OPBR1204", "A legacy KHR_materials_pbrSpecularGlossiness material.",
     json.dumps(gltf([{"name": "M", "extensions": {"KHR_materials_pbrSpecularGlossiness": {"diffuseFactor": [0.8, 0.8, 0.8, 1.0], "glossinessFactor": 0.5}}}], ["KHR_materials_pbrSpecularGlossiness"]), indent=2))
case("OPBR1205_texcoord_1_missing.gltf", "OPBR1205", "The base colour texture reads TEXCOORD_1 but the mesh only has TEXCOORD_0.",
     json.dumps(gltf([{"name": "M", "pbrMetallicRoughness": {"baseColorTexture": {"index": 0, "texCoord": 1}}}],
                     images=[{"uri": "textures/albedo.png"}], textures=[{"source": 0}],
                     accessors=[{"componentType": 5126, "count": 3, "type": "VEC3", "min": [0, 0, 0], "max": [0, 0, 0]}, {"componentType": 5126, "count": 3, "type": "VEC2"}],
                     meshes=[{"primitives": [{"attributes": {"POSITION": 0, "TEXCOORD_0": 1}, "material": 0}]}]), indent=2))
case("OPBR1206_non_power_of_two.gltf", "OPBR1206", "(info) A 3x5 image.",
     json.dumps(textured({"name": "M", "pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}}, uri="textures/odd.png"), indent=2))
case("OPBR1207_exr_image.gltf", "OPBR1207", "A glTF image that is an OpenEXR file without a texture extension.",
     json.dumps(textured({"name": "M", "pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}}, uri="textures/albedo.exr"), indent=2))
case("OPBR1208_strength_without_emissive.gltf", "OPBR1208", "KHR_materials_emissive_strength 5 with no emissiveFactor.",
     json.dumps(gltf([{"name": "M", "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": 5.0}}}], ["KHR_materials_emissive_strength"]), indent=2))
case("OPBR1209_bad_base64.gltf", "OPBR1209", "An embedded image data URI that is not valid base64.",
     json.dumps(textured({"name": "M", "pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}}, uri="data:image/png;base64,iVBORw0KGgo!!!not-base64!!!"), indent=2),
     also={"OPBR701": "the image that cannot be loaded is reported again as a texture not found in the package (the same defect twice)"})
case("OPBR1209_missing_buffer.gltf", "OPBR1209", "An image in a bufferView whose buffer file 'scene.bin' was not shipped.",
     json.dumps(gltf([{"name": "M", "pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}}],
                     buffers=[{"uri": "scene.bin", "byteLength": 64}], bufferViews=[{"buffer": 0, "byteLength": 64}],
                     images=[{"bufferView": 0, "mimeType": "image/png"}], textures=[{"source": 0}]), indent=2),
     also={"OPBR701": "the image that cannot be loaded is reported again as a texture not found in the package (the same defect twice)"})
case("OPBR1209_glb_view_outside_buffer.glb", "OPBR1209", "A GLB whose image bufferView runs past the end of the BIN chunk.",
     glb(gltf([{"name": "M", "pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}}],
              buffers=[{"byteLength": 16}], bufferViews=[{"buffer": 0, "byteOffset": 0, "byteLength": 4096}],
              images=[{"bufferView": 0, "mimeType": "image/png"}], textures=[{"source": 0}]), b"\x89PNG\r\n\x1a\n" + b"\0" * 8),
     also={"OPBR701": "the image that cannot be loaded is reported again as a texture not found in the package (the same defect twice)"})
case("OPBR1210_index_as_string.gltf", "OPBR1210", "normalTexture index written as the string \"0\".",
     json.dumps(textured({"name": "M", "normalTexture": {"index": "0"}}), indent=2),
     also={"OPBR802": "the textureInfo without an integer index is reported again as a connection to a texture that does not exist"})
case("OPBR1210_texture_transform_scale_scalar.gltf", "OPBR1210", "KHR_texture_transform scale written as a number, not a two-element array.",
     json.dumps(textured({"name": "M", "pbrMetallicRoughness": {"baseColorTexture": {"index": 0, "extensions": {"KHR_texture_transform": {"scale": 2.0}}}}}, extensionsUsed=["KHR_texture_transform"]), indent=2))
case("OPBR1210_extension_not_object.gltf", "OPBR1210", "KHR_materials_clearcoat given as an array instead of an object.",
     json.dumps(gltf([{"name": "M", "extensions": {"KHR_materials_clearcoat": [1.0]}}], ["KHR_materials_clearcoat"]), indent=2))

case("OPBR1215_spec_gloss_with_fallback.gltf", "OPBR1215", "(info) A legacy spec-gloss material that also authors its metallic-roughness fallback.",
     json.dumps(gltf([{"name": "M", "pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.8, 0.8, 1.0], "metallicFactor": 0.0},
                       "extensions": {"KHR_materials_pbrSpecularGlossiness": {"diffuseFactor": [0.8, 0.8, 0.8, 1.0], "glossinessFactor": 0.5}}}],
                     ["KHR_materials_pbrSpecularGlossiness"]), indent=2))
case("OPBR1216_extension_name_typo.gltf", "OPBR1216", "KHR_material_clearcoat (no s), consistently in extensionsUsed and on the material, so no viewer applies the coat.",
     json.dumps(gltf([{"name": "M", "extensions": {"KHR_material_clearcoat": {"clearcoatFactor": 1.0}}}], ["KHR_material_clearcoat"]), indent=2),
     also={"OPBR1212": "(info) the unknown extension is kept as data and not converted"})
_MESH_ACCESSORS = [{"componentType": 5126, "count": 3, "type": "VEC3", "min": [0, 0, 0], "max": [0, 0, 0]},
                   {"componentType": 5126, "count": 3, "type": "VEC2"}, {"componentType": 5126, "count": 3, "type": "VEC3"}]
case("OPBR1217_texcoord_ubyte_not_normalized.gltf", "OPBR1217", "TEXCOORD_0 quantised to unsigned bytes without normalized: true (and without KHR_mesh_quantization).",
     json.dumps(gltf([{"name": "M", "pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}}],
                     images=[{"uri": "textures/albedo.png"}], textures=[{"source": 0}],
                     accessors=[_MESH_ACCESSORS[0], {"componentType": 5121, "count": 3, "type": "VEC2"}],
                     meshes=[{"primitives": [{"attributes": {"POSITION": 0, "TEXCOORD_0": 1}, "material": 0}]}]), indent=2))
case("OPBR1218_clearcoat_normal_without_tangents.gltf", "OPBR1218", "A clear-coat normal map on a primitive with no TANGENT attribute and no base normalTexture.",
     json.dumps(gltf([{"name": "M", "extensions": {"KHR_materials_clearcoat": {"clearcoatFactor": 1.0, "clearcoatNormalTexture": {"index": 0}}}}],
                     ["KHR_materials_clearcoat"], images=[{"uri": "textures/normal.png"}], textures=[{"source": 0}], accessors=_MESH_ACCESSORS,
                     meshes=[{"primitives": [{"attributes": {"POSITION": 0, "NORMAL": 2, "TEXCOORD_0": 1}, "material": 0}]}]), indent=2))

def _tangent_buffer(w: float) -> str:
    """A data URI holding one triangle's positions, normals (0, 0, 1) and tangents (1, 0, 0, w)."""
    data = struct.pack("<9f", 0, 0, 0, 1, 0, 0, 0, 1, 0) + struct.pack("<9f", *[0, 0, 1] * 3) + struct.pack("<12f", *[1, 0, 0, w] * 3)
    return "data:application/octet-stream;base64," + base64.b64encode(data).decode()


_CUBE_5CM = {"componentType": 5126, "count": 3, "type": "VEC3", "min": [-0.025, -0.025, -0.025], "max": [0.025, 0.025, 0.025]}
_GLASS = {"metallicFactor": 0.0, "roughnessFactor": 0.05}


def _variants(names, mappings, materials=2) -> dict:
    return gltf([{"name": f"m{i}"} for i in range(materials)], ["KHR_materials_variants"],
                extensions={"KHR_materials_variants": {"variants": [{"name": n} for n in names]}},
                accessors=[_MESH_ACCESSORS[0]],
                meshes=[{"primitives": [{"attributes": {"POSITION": 0}, "material": 0,
                                         "extensions": {"KHR_materials_variants": {"mappings": mappings}}}]}])


case("OPBR1219_basecolor_png_16bit.gltf", "OPBR1219", "The base colour texture is a 16-bit-per-channel PNG exported from a linear paint buffer; glTF requires 8-bit sRGB.",
     json.dumps(textured({"name": "M", "pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}}, uri="textures/albedo16.png"), indent=2))
case("OPBR1219_cmyk_jpeg.gltf", "OPBR1219", "A print department's CMYK JPEG copied in as the base colour texture (not JFIF).",
     json.dumps(textured({"name": "M", "pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}}, uri="textures/albedo_cmyk.jpg"), indent=2))
case("OPBR1220_webp_core_source.gltf", "OPBR1220", "A WebP image named by texture.source without EXT_texture_webp.",
     json.dumps(textured({"name": "M", "pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}}, uri="textures/albedo.webp"), indent=2))
case("OPBR802_gltf_variant_material_missing.gltf", "OPBR802", "A KHR_materials_variants mapping names material 2 after the variant's material was deleted.",
     json.dumps(_variants(["Red", "Blue", "Green"], [{"material": 0, "variants": [0]}, {"material": 1, "variants": [1]},
                                                    {"material": 2, "variants": [2]}]), indent=2))
case("OPBR1225_variant_mapped_twice.gltf", "OPBR1225", "Variant 0 appears in two mappings (two materials) of one primitive.",
     json.dumps(_variants(["Red", "Blue"], [{"material": 0, "variants": [0]}, {"material": 1, "variants": [0, 1]}]), indent=2))
case("OPBR1226_variant_names_duplicate.gltf", "OPBR1226", "Two variants both named 'Red' (copied in a configurator, not renamed).",
     json.dumps(_variants(["Red", "Red"], [{"material": 0, "variants": [0]}, {"material": 1, "variants": [1]}]), indent=2))
case("OPBR1227_tangent_w_zero.gltf", "OPBR1227", "A triangle whose TANGENT w is 0 (an exporter left the handedness uninitialised).",
     json.dumps(gltf([{"name": "M", "pbrMetallicRoughness": {"metallicFactor": 0.0}}],
                     buffers=[{"byteLength": 120, "uri": _tangent_buffer(0.0)}],
                     bufferViews=[{"buffer": 0, "byteLength": 72}, {"buffer": 0, "byteOffset": 72, "byteLength": 48}],
                     accessors=[{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 0]},
                                {"bufferView": 0, "byteOffset": 36, "componentType": 5126, "count": 3, "type": "VEC3"},
                                {"bufferView": 1, "componentType": 5126, "count": 3, "type": "VEC4"}],
                     meshes=[{"primitives": [{"attributes": {"POSITION": 0, "NORMAL": 1, "TANGENT": 2}, "material": 0}]}]), indent=2))
_UV_DATA = struct.pack("<9f", 0, 0, 0, 1, 0, 0, 0, 1, 0) + struct.pack("<6f", 0, 0, 1, 0, 0, 1)


def _uv_triangle(texcoord: dict, data: bytes = _UV_DATA, views=None, **top) -> dict:
    """A textured triangle: positions in view 0, TEXCOORD_0 (accessor 1, ``texcoord`` merged in) in view 1."""
    return gltf([{"name": "M", "pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}}],
                images=[{"uri": "textures/albedo.png"}], textures=[{"source": 0}],
                buffers=top.pop("buffers", [{"byteLength": len(data), "uri": "data:application/octet-stream;base64,"
                                             + base64.b64encode(data).decode()}]),
                bufferViews=views or [{"buffer": 0, "byteLength": 36}, {"buffer": 0, "byteOffset": 36, "byteLength": 24}],
                accessors=[{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 0]},
                           {"bufferView": 1, "componentType": 5126, "count": 3, "type": "VEC2", **texcoord}],
                meshes=[{"primitives": [{"attributes": {"POSITION": 0, "TEXCOORD_0": 1}, "material": 0}]}], **top)


_SPARSE = _UV_DATA + struct.pack("<2H", 2, 1) + struct.pack("<4f", 0.5, 0.5, 0.25, 0.25)
case("OPBR1228_texcoord_count_differs.gltf", "OPBR1228", "TEXCOORD_0 with 2 elements for 3 positions (UVs taken from another LOD).",
     json.dumps(_uv_triangle({"count": 2}), indent=2))
case("OPBR1228_sparse_indices_swapped.gltf", "OPBR1228", "A sparse TEXCOORD_0 whose indices [2, 1] an optimiser swapped (not strictly increasing).",
     json.dumps(_uv_triangle({"sparse": {"count": 2, "indices": {"bufferView": 2, "componentType": 5123}, "values": {"bufferView": 3}}},
                             _SPARSE, [{"buffer": 0, "byteLength": 36}, {"buffer": 0, "byteOffset": 36, "byteLength": 24},
                                       {"buffer": 0, "byteOffset": 60, "byteLength": 4}, {"buffer": 0, "byteOffset": 64, "byteLength": 16}]), indent=2))
case("OPBR1228_byte_offset_unaligned.gltf", "OPBR1228", "A FLOAT TEXCOORD_0 at byteOffset 2 (not a multiple of 4).",
     json.dumps(_uv_triangle({"byteOffset": 2}, _UV_DATA[:36] + bytes(2) + _UV_DATA[36:] + bytes(2),
                             [{"buffer": 0, "byteLength": 36}, {"buffer": 0, "byteOffset": 36, "byteLength": 28}]), indent=2))
case("OPBR1209_buffer_truncated.gltf", "OPBR1209", "The external uv_short.bin holds 16 bytes fewer than buffers[0].byteLength (a truncated upload).",
     json.dumps(_uv_triangle({}, buffers=[{"byteLength": 60, "uri": "OPBR1209_buffers/uv_short.bin"}]), indent=2))
def _glb_json_unpadded() -> bytes:
    """A GLB of the textured triangle whose JSON chunk is one byte past a multiple of 4 (no space padding)."""
    text = json.dumps(_uv_triangle({}, buffers=[{"byteLength": 60}]), separators=(",", ":")).encode()
    text += b" " * ((1 - len(text)) % 4)
    chunks = struct.pack("<II", len(text), 0x4E4F534A) + text + struct.pack("<II", 60, 0x004E4942) + _UV_DATA
    return struct.pack("<III", 0x46546C67, 2, 12 + len(chunks)) + chunks


case("OPBR1209_glb_json_chunk_unpadded.glb", "OPBR1209", "A GLB whose JSON chunk length is not a multiple of 4 (no space padding).",
     _glb_json_unpadded())
case("OPBR1220_webp_extension_source_png.gltf", "OPBR1220", "EXT_texture_webp's source is a PNG (the WebP conversion was skipped, the extension written).",
     json.dumps(gltf([{"name": "M", "pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}}], ["EXT_texture_webp"],
                     images=[{"uri": "textures/albedo.png"}], textures=[{"source": 0, "extensions": {"EXT_texture_webp": {"source": 0}}}]), indent=2))
case("OPBR802_gltf_scene_missing.gltf", "OPBR802", "\"scene\": 1 in a file with one scene: loaders honouring the default scene show nothing.",
     json.dumps(_uv_triangle({}, scene=1, scenes=[{"nodes": [0]}], nodes=[{"mesh": 0}]), indent=2))
case("OPBR1210_variants_mapping_empty.gltf", "OPBR1210", "A KHR_materials_variants mapping with \"variants\": [] (left over after its variant was deleted).",
     json.dumps(_variants(["Red", "Blue"], [{"material": 0, "variants": [0]}, {"material": 1, "variants": [1]},
                                           {"material": 1, "variants": []}]), indent=2))
case("OPBR1210_variants_on_material.gltf", "OPBR1210", "KHR_materials_variants mappings written on the material instead of the mesh primitive.",
     json.dumps(gltf([{"name": "m0", "extensions": {"KHR_materials_variants": {"mappings": [{"material": 1, "variants": [0]}]}}}, {"name": "m1"}],
                     ["KHR_materials_variants"], extensions={"KHR_materials_variants": {"variants": [{"name": "Red"}]}}), indent=2))
_QUANTIZED_UV = struct.pack("<9f", 0, 0, 0, 1, 0, 0, 0, 1, 0) + struct.pack("<6h", 0, 0, 32767, 0, 0, 32767)
case("OPBR1201_mesh_quantization_optional.gltf", "OPBR1201", "UVs quantised to normalised SHORT (gltfpack) with KHR_mesh_quantization in extensionsUsed only: the extension cannot be optional.",
     json.dumps(_uv_triangle({"componentType": 5122, "normalized": True}, _QUANTIZED_UV,
                             [{"buffer": 0, "byteLength": 36}, {"buffer": 0, "byteOffset": 36, "byteLength": 12}],
                             extensionsUsed=["KHR_mesh_quantization"]), indent=2))
case("OPBR1209_buffer_data_uri_text_plain.gltf", "OPBR1209", "The embedded buffer's data URI declares text/plain (glTF: application/octet-stream or application/gltf-buffer).",
     json.dumps(_uv_triangle({}, buffers=[{"byteLength": 60, "uri": "data:text/plain;base64," + base64.b64encode(_UV_DATA).decode()}]), indent=2))
case("OPBR1210_texture_info_null.gltf", "OPBR1210", "\"normalTexture\": null, a Python exporter's None for a texture it did not have.",
     json.dumps(textured({"name": "M", "pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}, "normalTexture": None}), indent=2))
case("OPBR1210_variants_plain_strings.gltf", "OPBR1210", "The root's KHR_materials_variants variants written as [\"Red\", \"Blue\"] instead of objects with a name.",
     json.dumps(dict(_variants(["Red", "Blue"], [{"material": 0, "variants": [0]}, {"material": 1, "variants": [1]}]),
                     extensions={"KHR_materials_variants": {"variants": ["Red", "Blue"]}}), indent=2))
case("OPBR1228_texcoord_past_view_end.gltf", "OPBR1228", "TEXCOORD_0 counts 3 elements but its bufferView holds 2 (16 bytes): the last is read past the view.",
     json.dumps(_uv_triangle({}, _UV_DATA, [{"buffer": 0, "byteLength": 36}, {"buffer": 0, "byteOffset": 36, "byteLength": 16}]), indent=2))


def _indexed_triangle(last: int) -> dict:
    """The textured triangle drawn through UNSIGNED_SHORT indices (0, 1, ``last``) in view 2."""
    data = _UV_DATA + struct.pack("<3H", 0, 1, last) + bytes(2)
    document = _uv_triangle({}, data, [{"buffer": 0, "byteLength": 36}, {"buffer": 0, "byteOffset": 36, "byteLength": 24},
                                       {"buffer": 0, "byteOffset": 60, "byteLength": 6}])
    document["accessors"].append({"bufferView": 2, "componentType": 5123, "count": 3, "type": "SCALAR"})
    document["meshes"][0]["primitives"][0]["indices"] = 2
    return document


case("OPBR1228_indices_out_of_range.gltf", "OPBR1228", "The triangle's last index is 3 with 3 vertices (0 to 2): indices from another LOD.",
     json.dumps(_indexed_triangle(3), indent=2))
case("OPBR1229_webp_only_not_required.gltf", "OPBR1229", "A texture whose only image is EXT_texture_webp's (no PNG fallback), the extension in extensionsUsed only.",
     json.dumps(gltf([{"name": "M", "pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}}], ["EXT_texture_webp"],
                     images=[{"uri": "textures/albedo.webp"}], textures=[{"extensions": {"EXT_texture_webp": {"source": 0}}}]), indent=2))
case("OPBR1230_material_property_repeated.gltf", "OPBR1230", "A merge script wrote a second pbrMetallicRoughness into the material: viewers keep the first or the last.",
     json.dumps(gltf([{"name": "M", "pbrMetallicRoughness": {"metallicFactor": 0.0}}]), indent=2).replace(
         '"pbrMetallicRoughness": {', '"pbrMetallicRoughness": {"metallicFactor": 1.0, "roughnessFactor": 0.2},\n      "pbrMetallicRoughness": {', 1))
case("OPBR1231_texcoord_nan.gltf", "OPBR1231", "TEXCOORD_0 holds a NaN (a degenerate UV unwrap).",
     json.dumps(_uv_triangle({}, _UV_DATA[:36] + struct.pack("<6f", 0, 0, 1, 0, float("nan"), 1)), indent=2))
_NORMALS_SCALED = struct.pack("<9f", 0, 0, 0, 1, 0, 0, 0, 1, 0) + struct.pack("<9f", *[0, 0, 2.5] * 3)
case("OPBR1231_normals_not_unit.gltf", "OPBR1231", "NORMALs of length 2.5 (an object scale baked into them).",
     json.dumps(gltf([{"name": "M"}], buffers=[{"byteLength": 72, "uri": "data:application/octet-stream;base64," + base64.b64encode(_NORMALS_SCALED).decode()}],
                     bufferViews=[{"buffer": 0, "byteLength": 36}, {"buffer": 0, "byteOffset": 36, "byteLength": 36}],
                     accessors=[{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 0]},
                                {"bufferView": 1, "componentType": 5126, "count": 3, "type": "VEC3"}],
                     meshes=[{"primitives": [{"attributes": {"POSITION": 0, "NORMAL": 1}, "material": 0}]}]), indent=2))
case("OPBR1221_transmission_alpha_blend.gltf", "OPBR1221", "Window glass with transmission 1 and also alphaMode BLEND at alpha 0.25: transparent twice.",
     json.dumps(gltf([{"name": "M", "alphaMode": "BLEND", "pbrMetallicRoughness": {**_GLASS, "baseColorFactor": [0.9, 0.95, 1.0, 0.25]},
                       "extensions": {"KHR_materials_transmission": {"transmissionFactor": 1.0}}}], ["KHR_materials_transmission"]), indent=2))
case("OPBR1222_iridescence_micrometres.gltf", "OPBR1222", "Iridescence thicknesses written in micrometres (0.1 / 0.4) where glTF wants nanometres.",
     json.dumps(gltf([{"name": "M", "extensions": {"KHR_materials_iridescence": {"iridescenceFactor": 1.0, "iridescenceThicknessMinimum": 0.1,
                                                                                 "iridescenceThicknessMaximum": 0.4}}}], ["KHR_materials_iridescence"]), indent=2))
case("OPBR1222_volume_thickness_centimetres.gltf", "OPBR1222", "A 5 cm glass die (mesh in metres) with thicknessFactor 5: centimetres.",
     json.dumps(gltf([{"name": "M", "pbrMetallicRoughness": _GLASS, "extensions": {"KHR_materials_transmission": {"transmissionFactor": 1.0},
                                                                                     "KHR_materials_volume": {"thicknessFactor": 5.0}}}],
                     ["KHR_materials_transmission", "KHR_materials_volume"], accessors=[_CUBE_5CM],
                     meshes=[{"primitives": [{"attributes": {"POSITION": 0}, "material": 0}]}]), indent=2))
case("OPBR1223_volume_black_attenuation.gltf", "OPBR1223", "attenuationColor [0, 0, 0] ('no tint' exported as black) with attenuationDistance 0.5: black glass.",
     json.dumps(gltf([{"name": "M", "pbrMetallicRoughness": _GLASS, "extensions": {"KHR_materials_transmission": {"transmissionFactor": 1.0},
                                                                                     "KHR_materials_volume": {"thicknessFactor": 0.2, "attenuationDistance": 0.5, "attenuationColor": [0, 0, 0]}}}],
                     ["KHR_materials_transmission", "KHR_materials_volume"]), indent=2))
case("OPBR1223_volume_attenuation_distance_tiny.gltf", "OPBR1223", "attenuationDistance 1e-6 through a thickness of 1 with a pale tint: no light gets through.",
     json.dumps(gltf([{"name": "M", "pbrMetallicRoughness": _GLASS, "extensions": {"KHR_materials_transmission": {"transmissionFactor": 1.0},
                                                                                     "KHR_materials_volume": {"thicknessFactor": 1.0, "attenuationDistance": 1e-6, "attenuationColor": [0.9, 0.95, 0.9]}}}],
                     ["KHR_materials_transmission", "KHR_materials_volume"]), indent=2))
case("OPBR1224_iridescence_range_inverted.gltf", "OPBR1224", "iridescenceThicknessMinimum 800 and Maximum 100 (swapped) under a thickness texture.",
     json.dumps(textured({"name": "M", "extensions": {"KHR_materials_iridescence": {"iridescenceFactor": 1.0, "iridescenceThicknessTexture": {"index": 0},
                                                                                   "iridescenceThicknessMinimum": 800, "iridescenceThicknessMaximum": 100}}},
                         uri="textures/rough.png", extensionsUsed=["KHR_materials_iridescence"]), indent=2))
case("OPBR908_gltf_blend_alpha_zero.gltf", "OPBR908", "alphaMode BLEND with baseColorFactor alpha 0 and no texture ('transparency 1' written as alpha 0): invisible.",
     json.dumps(gltf([{"name": "M", "alphaMode": "BLEND", "pbrMetallicRoughness": {"baseColorFactor": [0.9, 0.9, 0.95, 0.0]}}]), indent=2))
case("OPBR908_gltf_mask_below_cutoff.gltf", "OPBR908", "alphaMode MASK with alpha 0.3 and no texture under the cutoff 0.5: every fragment discarded.",
     json.dumps(gltf([{"name": "M", "alphaMode": "MASK", "pbrMetallicRoughness": {"baseColorFactor": [0.9, 0.9, 0.95, 0.3]}}]), indent=2))
case("OPBR1211_transmission_empty.gltf", "OPBR1211", "\"KHR_materials_transmission\": {} beside a volume on a glass (the exporter never wrote transmissionFactor, default 0): neither acts.",
     json.dumps(gltf([{"name": "M", "pbrMetallicRoughness": _GLASS, "extensions": {"KHR_materials_transmission": {}, "KHR_materials_volume": {"thicknessFactor": 0.5}}}],
                     ["KHR_materials_transmission", "KHR_materials_volume"]), indent=2))
case("OPBR1211_diffuse_transmission_metal.gltf", "OPBR1211", "Diffuse transmission 1 on a lampshade left at metallicFactor 1 (no metallicRoughness texture): a metal has no diffuse lobe.",
     json.dumps(gltf([{"name": "M", "pbrMetallicRoughness": {"metallicFactor": 1.0},
                       "extensions": {"KHR_materials_diffuse_transmission": {"diffuseTransmissionFactor": 1.0}}}], ["KHR_materials_diffuse_transmission"]), indent=2),
     also={"OPBR1212": "(info) the toolkit does not convert diffuse transmission"})
case("OPBR1211_normal_scale_zero.gltf", "OPBR1211", "normalTexture.scale 0 (a disabled bump node exported as strength 0): the normal map is flat.",
     json.dumps(textured({"name": "M", "normalTexture": {"index": 0, "scale": 0.0}}, uri="textures/normal.png"), indent=2))
case("OPBR1211_specular_texture_rgb.gltf", "OPBR1211", "A specularTexture baked into RGB without alpha, where KHR_materials_specular reads the strength.",
     json.dumps(textured({"name": "M", "extensions": {"KHR_materials_specular": {"specularTexture": {"index": 0}}}}, uri="textures/albedo.png",
                         extensionsUsed=["KHR_materials_specular"]), indent=2))
case("OPBR1211_anisotropy_blue_zero.gltf", "OPBR1211", "An anisotropyTexture made from a two-channel flow map: direction in RG, strength (B) 0 everywhere.",
     json.dumps(textured({"name": "M", "extensions": {"KHR_materials_anisotropy": {"anisotropyStrength": 0.8, "anisotropyTexture": {"index": 0}}}},
                         uri="textures/flow_rg.png", extensionsUsed=["KHR_materials_anisotropy"]), indent=2))

# ---------------------------------------------------------------- the sixth red-team round's glTF defects
_TEXTURED = {"name": "M", "pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}}


def _attributes(*extra: tuple[str, dict]) -> dict:
    """A textured primitive: POSITION (accessor 0), TEXCOORD_0 (1), then the ``extra`` (attribute, accessor) pairs."""
    accessors = [_MESH_ACCESSORS[0], _MESH_ACCESSORS[1]] + [accessor for _, accessor in extra]
    attributes = {"POSITION": 0, "TEXCOORD_0": 1, **{name: 2 + n for n, (name, _) in enumerate(extra)}}
    return textured(_TEXTURED, accessors=accessors, meshes=[{"primitives": [{"attributes": attributes, "material": 0}]}])


def _ktx2(vk_format: int, color_model: int) -> bytes:
    """A 4 x 4 KTX v2 file of one level: header, level index, a one-sample data format descriptor, one 16-byte block."""
    header = b"\xabKTX 20\xbb\r\n\x1a\n" + struct.pack("<9I", vk_format, 1, 4, 4, 0, 0, 1, 1, 0)
    index = struct.pack("<4I2Q", 104, 44, 0, 0, 0, 0) + struct.pack("<3Q", 160, 16, 16)
    dfd = struct.pack("<I2I4B4B8B", 44, 0, (40 << 16) | 2, color_model, 1, 2, 0, 3, 3, 0, 0, 16, 0, 0, 0, 0, 0, 0, 0)
    dfd += struct.pack("<I4BII", 127 << 16, 0, 0, 0, 0, 0, 0xFFFFFFFF)
    body = header + index + dfd
    return body + bytes(160 - len(body)) + bytes(16)


def _basisu(uri: str) -> dict:
    return gltf([_TEXTURED], ["KHR_texture_basisu"], extensionsRequired=["KHR_texture_basisu"],
                images=[{"uri": uri, "mimeType": "image/ktx2"}], textures=[{"extensions": {"KHR_texture_basisu": {"source": 0}}}])


def _image_in_strided_view() -> bytes:
    image = TEXTURES["textures/albedo.png"]
    return glb(gltf([_TEXTURED], buffers=[{"byteLength": len(image)}],
                    bufferViews=[{"buffer": 0, "byteLength": len(image), "byteStride": 4}],
                    images=[{"bufferView": 0, "mimeType": "image/png"}], textures=[{"source": 0}]), image)


case("OPBR719_gltf_rotation_in_degrees.gltf", "OPBR719", "KHR_texture_transform rotation 90, a DCC's degrees, where glTF takes radians (90 rad is 14.3 turns).",
     json.dumps(textured({"name": "M", "pbrMetallicRoughness": {"baseColorTexture": {"index": 0, "extensions": {
         "KHR_texture_transform": {"rotation": 90, "scale": [2, 2]}}}}}, extensionsUsed=["KHR_texture_transform"]), indent=2))
case("OPBR1217_tangent_vec3.gltf", "OPBR1217", "TANGENT exported as VEC3, without the w handedness glTF's VEC4 tangents carry.",
     json.dumps(_attributes(("NORMAL", _MESH_ACCESSORS[2]), ("TANGENT", {"componentType": 5126, "count": 3, "type": "VEC3"})), indent=2))
case("OPBR1217_texcoord_float_normalized.gltf", "OPBR1217", "A FLOAT TEXCOORD_1 accessor with normalized: true (a quantising exporter set it on every attribute).",
     json.dumps(_attributes(("TEXCOORD_1", {"componentType": 5126, "count": 3, "type": "VEC2", "normalized": True})), indent=2))
case("OPBR1217_color_ubyte_not_normalized.gltf", "OPBR1217", "COLOR_0 as UNSIGNED_BYTE without normalized: true: vertex colours multiply the base colour by up to 255.",
     json.dumps(_attributes(("COLOR_0", {"componentType": 5121, "count": 3, "type": "VEC4"})), indent=2))
case("OPBR1218_tangent_without_normal.gltf", "OPBR1218", "TANGENT without NORMAL (normals stripped by a decimation step): loaders must ignore the tangents.",
     json.dumps(_attributes(("TANGENT", {"componentType": 5126, "count": 3, "type": "VEC4"})), indent=2))
case("OPBR1205_texcoord_sets_gap.gltf", "OPBR1205", "TEXCOORD_0 and TEXCOORD_2 without TEXCOORD_1 (a UV set deleted without renumbering).",
     json.dumps(_attributes(("TEXCOORD_2", _MESH_ACCESSORS[1])), indent=2))
case("OPBR1220_basisu_legacy_basis_file.gltf", "OPBR1220", "KHR_texture_basisu's source is a pre-ratification .basis file declared image/ktx2.",
     json.dumps(_basisu("textures/albedo.basis"), indent=2))
case("OPBR1220_basisu_ktx2_raw_texels.gltf", "OPBR1220", "KHR_texture_basisu's source is a KTX2 of raw R8G8B8A8_SRGB texels (toktx without --encode), no Basis Universal payload.",
     json.dumps(_basisu("textures/albedo_rgba8.ktx2"), indent=2))
case("OPBR1210_image_bufferview_stride.glb", "OPBR1210", "The bufferView of an embedded PNG declares byteStride 4 (set on every view by the exporter).",
     _image_in_strided_view())
case("OPBR1210_draco_without_bufferview.gltf", "OPBR1210", "KHR_draco_mesh_compression on a primitive without the bufferView of its compressed stream.",
     json.dumps(dict(_attributes(), extensionsUsed=["KHR_draco_mesh_compression"],
                     meshes=[{"primitives": [{"attributes": {"POSITION": 0, "TEXCOORD_0": 1}, "material": 0, "extensions": {
                         "KHR_draco_mesh_compression": {"attributes": {"POSITION": 0, "TEXCOORD_0": 1}}}}]}]), indent=2))
case("OPBR1253_accessor_type_list.gltf", "OPBR1253", "A TEXCOORD_0 accessor whose type is written as a list ([\"VEC2\"], a "
     "serialiser's slip): the glTF schema wants a string; the Khronos glTF-Validator: TYPE_MISMATCH.",
     json.dumps(dict(_attributes(), accessors=[dict(a, type=["VEC2"]) if a.get("type") == "VEC2" else a
                                               for a in _attributes()["accessors"]]), indent=2))

EXTRA_FILES = {
    "OPBR1209_buffers/uv_short.bin": _UV_DATA[:44],  # 16 bytes short of the 60 its buffer declares
    "OPBR1013_look.mtlx": opbr('<input name="base_weight" type="float" value="1" />'),
    "textures/albedo.exr": b"v/1\x01" + b"\0" * 60,  # an OpenEXR magic number, enough to be an EXR by signature
    "textures/lfs_albedo.png": (b"version https://git-lfs.github.com/spec/v1\n"
                                b"oid sha256:9b2f5c1d0e4a7b3c6d8e9f0a1b2c3d4e5f60718293a4b5c6d7e8f9012a3b4c5d\nsize 2097152\n"),
    "textures/cut.jpg": jpeg_cut_short(),
    "textures/photo.jpg": jpeg_whole(),
    "textures/empty.png": b"",
    "OPBR103_includes/library.mtlx": ('<?xml version="1.0"?>\n<materialx version="1.39" colorspace="lin_rec709">\n'
                             '  <open_pbr_surface name="S" type="surfaceshader">\n'
                             '    <input name="specular_roughness" type="float" value="0.1" />\n  </open_pbr_surface>\n'
                             '  <surfacematerial name="M" type="material">\n'
                             '    <input name="surfaceshader" type="surfaceshader" nodename="S" />\n'
                             '  </surfacematerial>\n</materialx>\n').encode(),
    "OPBR1020_layers/look_m.usda": b'#usda 1.0\n(\n    metersPerUnit = 1\n)\nover "M"\n{\n    over "S"\n    {\n'
                                   b'        float inputs:transmission_depth = 2.5\n    }\n}\n',
    "textures/scrambled.png": bytes((i * 73 + 41) % 256 for i in range(600)),
    "textures/albedo.basis": b"sB\x13\x00M\x00\x00\x10" + bytes(56),  # a legacy .basis header's signature
    "textures/albedo_rgba8.ktx2": _ktx2(43, 1),  # VK_FORMAT_R8G8B8A8_SRGB, colour model RGBSDA
}


def main() -> None:
    rules = all_rules()
    entries = []
    for path, data in {**TEXTURES, **EXTRA_FILES}.items():
        write(path, data)
    names = set()
    for name, code, defect, content, extra in CASES:
        assert name not in names, name
        names.add(name)
        assert name.startswith(code + "_"), name
        write(name, content)
        entries.append({"file": name, "code": code, "severity": str(rules[code].severity), "defect": defect, **extra})
    with open(os.path.join(HERE, "EXPECTED.json"), "w", encoding="utf-8") as handle:
        json.dump(entries, handle, indent=2)
        handle.write("\n")
    print(f"{len(entries)} files")


def write(name: str, content) -> None:
    path = os.path.join(HERE, name)
    os.makedirs(os.path.dirname(path), exist_ok=True)
    data = content.encode("utf-8") if isinstance(content, str) else content
    with open(path, "wb") as handle:
        handle.write(data)


if __name__ == "__main__":
    main()
