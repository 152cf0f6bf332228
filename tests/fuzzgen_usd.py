"""Hypothesis strategies that build hostile-but-plausible USD stages, and byte mutations of
``.usda``, ``.usdc`` and ``.usdz`` files.

Shared by the quick fuzz tests (tests/test_fuzz_usd.py) and the long run
(tests/benchmarks/fuzz_long_usd.py). Text stages are assembled from the pieces real files are made
of (a Material with its surface outputs, OpenPBR, UsdPreviewSurface and MaterialX shaders, texture
nodes, node graphs, interface inputs, composition arcs, variants, value clips, colour-space
metadata), every part drawn from a mix of valid values, near misses and garbage, then re-encoded
(UTF-16, byte-order marks, invalid UTF-8), truncated or corrupted byte by byte. Binary seeds
(crate files and packages) come from the samples converted by ``openpbr convert`` and from the
USD rules' own examples; :func:`mutate_bytes` corrupts them the way a broken disk or a hostile
author would: flipped bytes, overwritten integers (sizes, offsets, counts), deletions and
truncation.
"""

from __future__ import annotations

import io
import os
import random
import tempfile
import zipfile

import fuzzgen
from hypothesis import strategies as st

from openpbr_tools import tables

SHADER_IDS = [
    "ND_open_pbr_surface_surfaceshader", "ND_open_pbr_surface_surfaceshader", "ND_open_pbr_surface_surfaceshader",
    "ND_open_pbr_surface_surfaceshader_05", "ND_open_pbr_surface_surfaceshader_02", "ND_standard_surface_surfaceshader",
    "ND_gltf_pbr_surfaceshader", "UsdPreviewSurface", "UsdPreviewSurface", "ND_UsdPreviewSurface_surfaceshader",
    "UsdUVTexture", "UsdUVTexture", "UsdTransform2d", "UsdPrimvarReader_float2", "ND_image_color3", "ND_image_float",
    "ND_image_vector3", "ND_tiledimage_color3", "ND_extract_color3", "ND_separate3_color3", "ND_normalmap_float",
    "ND_multiply_color3FA", "ND_multiply_float", "ND_add_float", "ND_convert_color3_vector3", "ND_dot_float",
    "ND_place2d_vector2", "ND_texcoord_vector2", "ND_geompropvalue_vector2", "ND_noise2d_color3",
    "ND_open_pbr_surface_surfaceshdr", "PxrSurface", "", "ND_", "UsdUVTextur",
]
PRIM_TYPES = ["Material", "Shader", "Shader", "NodeGraph", "Scope", "Xform", "", "Mesh", "GeomSubset", "Materia"]
SPECIFIERS = ["def", "def", "def", "over", "class"]
PRIM_NAMES = ["M", "S", "P", "img", "tex", "NG", "Looks", "st", "xf", "M2", "S2", "_a", "x" * 120, "a1", "nrm"]
USD_TYPES = [
    "float", "double", "half", "int", "uint", "int64", "uchar", "bool", "string", "token", "asset", "color3f",
    "color3d", "color3h", "color4f", "float2", "float3", "float4", "double3", "normal3f", "vector3f", "point3f",
    "texCoord2f", "matrix3d", "matrix4d", "float[]", "color3f[]", "token[]", "asset[]", "timecode", "quatf",
    "frame4d", "opaque", "colour3f",
]
PARAMETERS = sorted(set().union(*(tables.table(m).parameters for m in tables.MODELS))) + [
    "base_roughness", "specular_ior_level", "file", "in", "in1", "in2", "index", "texcoord", "scale", "bias",
    "fallback", "sourceColorSpace", "wrapS", "wrapT", "varname", "rotation", "translation", "uaddressmode",
    "vaddressmode", "default", "uvtiling", "uvoffset", "st", "opacityMode", "useSpecularWorkflow", "", "a:b:c",
]
OUTPUTS = ["out", "surface", "rgb", "r", "g", "a", "outr", "outx", "displacement", "", "mtlx:surface"]
ASSET_PATHS = ["tex/albedo.png", "albedo.png", "normal.png", "wood_<UDIM>.png", "../../etc/passwd", "/abs/path.png",
               "http://example.com/a.png", "", "a b.png", "tex\\win.png", "C:/x.png", "`${X}.png`", "\u00e9t\u00e9.jpg",
               "pkg.usdz[inner.png]", "./x.exr"]
ARC_PATHS = ["./missing.usda", "../outside.usda", "/etc/passwd", "http://example.com/x.usda", "`${W}`", "", "self.usda",
             "./input.usda", "a.usdz[b.usda]", "./lib/looks.usdc"]
COLOR_SPACES = ["lin_rec709_scene", "srgb_rec709_scene", "lin_ap1_scene", "ACEScg", "raw", "data", "srgb_texture",
                "acescg", "lin_rec709", "none", "sRGB", "auto", "g22_rec709", "srgb_tx", "", "\u2603"]
NUMBERS = ["0", "1", "-1", "0.5", "1e400", "-1e400", "inf", "-inf", "nan", "-0", "3.4e38", "1e-45", "2147483648",
           "-9223372036854775809", "0x10", "1.", ".5", "1e", "00012", "1_000"]
TEXT = st.text(alphabet=st.characters(blacklist_categories=("Cs",)), max_size=24)
CLIPS = ('clips = {\n    dictionary default = {\n        asset[] assetPaths = [@./clip.usda@]\n'
         '        string primPath = "/S"\n        double2[] active = [(0, 0)]\n    }\n}')
TEMPLATE_CLIPS = ('clips = {\n    dictionary default = {\n        string templateAssetPath = "clip.#.usda"\n'
                  '        double templateStartTime = 0\n        double templateEndTime = 3\n'
                  '        double templateStride = 1\n        string primPath = "/S"\n    }\n}')
SHADER_CUSTOM_DATA = ' (\n        customData = { dictionary openpbr = { string version = "0.2" } }\n    )'


def _quoted(text: str) -> str:
    return '"' + text.replace("\\", "\\\\").replace('"', '\\"').replace("\n", "\\n").replace("\r", "\\r") + '"'


CLEAN_USD_TYPES = [t for t in USD_TYPES if t not in ("opaque", "colour3f")]
CLEAN_NUMBERS = ["0", "1", "-1", "0.5", "0.04", "1.5", "1e400", "-1e400", "inf", "-inf", "nan", "-0", "3.4e38",
                 "1e-45", "2", "100", "-0.25", "1e-7"]
CLEAN_PATH_SUFFIXES = [".outputs:out", ".outputs:surface", ".outputs:rgb", ".outputs:r", ".outputs:a", ".inputs:coat",
                       ".inputs:albedo", ".outputs:outr", ""]


@st.composite
def numbers(draw, clean: bool = False) -> str:
    if clean:
        return draw(st.one_of(st.sampled_from(CLEAN_NUMBERS), st.floats(allow_nan=False, allow_infinity=False).map(repr),
                              st.integers(-2**31, 2**31).map(str)))
    return draw(st.one_of(st.sampled_from(NUMBERS), st.floats(allow_nan=True, allow_infinity=True).map(repr),
                          st.integers(-2**70, 2**70).map(str)))


@st.composite
def values(draw, usd_type: str, clean: bool = False) -> str:
    """A value for ``usd_type``: of the right shape when ``clean``, otherwise sometimes of another
    shape or garbage."""
    if not clean and draw(st.integers(0, 9)) == 0:
        return draw(st.sampled_from(["None", "(", "[]", "()", "[1, 2", '"unterminated', "@a@b@", "</path>", "{}",
                                     "((1, 2), (3, 4))", "(1, 2, 3, 4, 5)", "1 2 3", "true", "@@@a@@@"]))
    if clean and draw(st.integers(0, 19)) == 0:
        return "None"
    base = usd_type.removesuffix("[]")
    width = next((int(c) for c in base if c.isdigit()), 1)
    if base.startswith("matrix"):
        width = 3 if base.startswith("matrix3") else 4
        row = "(" + ", ".join(draw(numbers(clean)) for _ in range(width)) + ")"
        item = "(" + ", ".join([row] * width) + ")"
    elif base in ("string", "token"):
        item = _quoted(draw(st.one_of(st.sampled_from(COLOR_SPACES + ["transparent", "presence", "repeat", "black",
                                                                       "periodic", "st", "UV0"]), TEXT)))
    elif base == "asset":
        item = "@" + draw(st.sampled_from(ASSET_PATHS)) + "@"
    elif base == "bool":
        item = draw(st.sampled_from(["0", "1", "true", "false"] if clean else ["0", "1", "true", "false", "2", "-1"]))
    elif base in ("quatf", "frame4d") or width > 1:
        count = 4 if base in ("quatf",) else 16 if base == "frame4d" else width
        if base == "frame4d":
            item = "(" + ", ".join("(" + ", ".join(draw(numbers(clean)) for _ in range(4)) + ")" for _ in range(4)) + ")"
        else:
            if not clean:
                count = draw(st.sampled_from([count, count, count, 1, 5]))
            item = "(" + ", ".join(draw(numbers(clean)) for _ in range(count)) + ")"
    elif clean and base in ("int", "uint", "int64", "uchar", "timecode"):
        item = str(draw(st.integers(0 if base in ("uint", "uchar") else -2**31, 255 if base == "uchar" else 2**31 - 1)))
    else:
        item = draw(numbers(clean))
    if usd_type.endswith("[]"):
        return "[" + ", ".join([item] * draw(st.integers(0, 4))) + "]"
    return item


@st.composite
def prim_paths(draw, clean: bool = False) -> str:
    parts = draw(st.lists(st.sampled_from(PRIM_NAMES[:11]), min_size=1 if clean else 0, max_size=4))
    path = "/" + "/".join(parts)
    suffixes = CLEAN_PATH_SUFFIXES if clean else CLEAN_PATH_SUFFIXES + [".outputs:", "{v=a}", ".outputs:out[/x]"]
    return path + draw(st.sampled_from(suffixes))


@st.composite
def attributes(draw, owner: str, clean: bool = False) -> str:
    """One attribute line of a Shader, Material or NodeGraph."""
    usd_type = draw(st.sampled_from(CLEAN_USD_TYPES if clean else USD_TYPES))
    if owner == "Material" and draw(st.booleans()):
        name = "outputs:" + draw(st.sampled_from(["surface", "mtlx:surface", "ri:surface", "displacement", "volume"]))
        usd_type = draw(st.sampled_from(["token", "token", "float"]))
    else:
        prefix = draw(st.sampled_from(["inputs:", "inputs:", "inputs:", "outputs:", "", "primvars:"]))
        names = PARAMETERS if prefix != "outputs:" else OUTPUTS
        name = prefix + draw(st.sampled_from([n for n in names if n] if clean else names))
        if clean and name.endswith(":"):
            name += "x"
    uniform = draw(st.sampled_from(["", "", "uniform ", "custom "]))
    kind = draw(st.sampled_from(["value", "value", "connect", "connect", "bare", "samples", "metadata"]))
    if kind == "value":
        line = f"{uniform}{usd_type} {name} = {draw(values(usd_type, clean))}"
    elif kind == "connect":
        targets = draw(st.lists(prim_paths(clean), min_size=1 if clean else 0, max_size=2))
        target = f"<{targets[0]}>" if len(targets) == 1 else "[" + ", ".join(f"<{t}>" for t in targets) + "]"
        line = f"{uniform}{usd_type} {name}.connect = {target}"
    elif kind == "samples":
        times = sorted({draw(numbers(clean=True)) for _ in range(draw(st.integers(0, 3)))} - {"nan", "inf", "-inf"})
        samples = ",\n        ".join(f"{time}: {draw(values(usd_type, clean))}" for time in times)
        line = f"{usd_type} {name}.timeSamples = {{\n        {samples}\n    }}"
    elif kind == "metadata":
        metadata = draw(st.sampled_from([f"colorSpace = {_quoted(draw(st.sampled_from(COLOR_SPACES)))}",
                                         'customData = {\n    string a = "b"\n}', 'interpolation = "vertex"',
                                         'doc = """multi\nline"""', 'connectability = "interfaceOnly"']))
        line = f"{uniform}{usd_type} {name} = {draw(values(usd_type, clean))} (\n    {metadata}\n)"
    else:
        line = f"{uniform}{usd_type} {name}"
    return line


@st.composite
def prim_metadata(draw) -> str:
    chosen = draw(st.lists(st.sampled_from([
        'prepend apiSchemas = ["ColorSpaceAPI"]', 'apiSchemas = ["MaterialBindingAPI", "ColorSpaceAPI"]',
        'customData = {\n    dictionary openpbr = {\n        string version = "1.0"\n    }\n}',
        'customData = {\n    dictionary openpbr = {\n        string version = "banana"\n    }\n}',
        "references = </M>", "references = </Nowhere>", "inherits = </Base>", "specializes = </M/S>",
        f"references = @{draw(st.sampled_from(ARC_PATHS))}@</M>", f"payload = @{draw(st.sampled_from(ARC_PATHS))}@",
        'variants = {\n    string look = "red"\n}\nprepend variantSets = "look"', "active = false", "instanceable = true",
        'kind = "component"', CLIPS, TEMPLATE_CLIPS, 'doc = "a \\" quote"',
    ]), max_size=3, unique=True))
    return "(\n    " + "\n    ".join(c.replace("\n", "\n    ") for c in chosen) + "\n)" if chosen else ""


def _block(head: str, lines: list[str]) -> str:
    body = "".join("    " + line.replace("\n", "\n    ") + "\n" for line in lines)
    return f"{head}\n{{\n{body}}}"


@st.composite
def prims(draw, depth: int = 0, clean: bool = False, name: str | None = None) -> str:
    specifier = draw(st.sampled_from(SPECIFIERS))
    prim_type = draw(st.sampled_from(PRIM_TYPES[:-1] if clean else PRIM_TYPES))
    name = name or draw(st.sampled_from(PRIM_NAMES))
    lines = []
    if prim_type == "Shader" or draw(st.integers(0, 5)) == 0:
        lines.append(f'uniform token info:id = "{draw(st.sampled_from(SHADER_IDS))}"')
    lines += draw(st.lists(attributes(prim_type, clean), max_size=5, unique_by=lambda a: a.split(" = ")[0]
                           if clean else a))
    metadata = draw(prim_metadata())
    if "ColorSpaceAPI" in metadata or draw(st.integers(0, 6)) == 0:
        lines.append(f"uniform token colorSpace:name = {_quoted(draw(st.sampled_from(COLOR_SPACES)))}")
    count = draw(st.integers(0, 2 if depth < 2 else 0))
    names = draw(st.lists(st.sampled_from(PRIM_NAMES), min_size=count, max_size=count, unique=clean))
    lines += [draw(prims(depth + 1, clean, child)) for child in names]
    if "variantSets" in metadata:
        lines.append('variantSet "look" = {\n    "red" {\n        float inputs:base_weight = 0.5\n    }\n'
                     '    "blue" (\n        references = @./blue.usda@\n    ) {\n    }\n}')
    head = f'{specifier} {prim_type} "{name}"' if prim_type else f'{specifier} "{name}"'
    return _block(f"{head} {metadata}", lines)


@st.composite
def texture_nodes(draw, clean: bool = False, name: str | None = None) -> str:
    shader_id = draw(st.sampled_from(["UsdUVTexture", "ND_image_color3", "ND_tiledimage_color3", "ND_image_float",
                                      "UsdTransform2d", "UsdPrimvarReader_float2", "ND_extract_color3",
                                      "ND_normalmap_float", "ND_multiply_color3FA", "ND_place2d_vector2"]))
    name = name or draw(st.sampled_from(["img", "tex", "st", "nrm", "xf"]))
    file = draw(st.sampled_from(ASSET_PATHS))
    colour = draw(st.sampled_from(COLOR_SPACES))
    lines = [f'uniform token info:id = "{shader_id}"', f'asset inputs:file = @{file}@ (\n    colorSpace = "{colour}"\n)']
    lines += draw(st.lists(attributes("Shader", clean), max_size=4, unique_by=lambda a: a.split(" = ")[0]
                           if clean else a))
    lines.append(f"{draw(st.sampled_from(['color3f', 'float3', 'float', 'float2']))} outputs:"
                 f"{draw(st.sampled_from(OUTPUTS[:-2] if clean else OUTPUTS))}")
    return _block(f'def Shader "{name}"', lines)


@st.composite
def materials(draw, clean: bool = False) -> str:
    """A Material whose surface output reaches a shader (the shape the reader follows), with
    texture nodes and node graphs around it."""
    shader_id = draw(st.sampled_from(SHADER_IDS[:10]))
    model = {"UsdPreviewSurface": "UsdPreviewSurface"}.get(shader_id, "open_pbr_surface")
    parameters = sorted(tables.table(model).parameters.values(), key=lambda p: p.name)
    inputs = []
    for parameter in draw(st.lists(st.sampled_from(parameters), max_size=10, unique_by=lambda p: p.name)):
        usd_type = draw(st.sampled_from([{"color3": "color3f", "float": "float", "vector3": "float3", "boolean": "bool",
                                          "integer": "int", "string": "string", "vector2": "float2"}.get(
                                              parameter.type, "float")] * 4 + (CLEAN_USD_TYPES if clean else USD_TYPES)))
        if draw(st.integers(0, 3)) == 0:
            inputs.append(f"{usd_type} inputs:{parameter.name}.connect = <{draw(prim_paths(clean))}>")
        else:
            inputs.append(f"{usd_type} inputs:{parameter.name} = {draw(values(usd_type, clean))}")
    output = draw(st.sampled_from(["surface", "surface", "out", "rgb"]))
    context = draw(st.sampled_from(["mtlx:surface", "surface", "surface", "mtlx:surface", "ri:surface"]))
    names = draw(st.lists(st.sampled_from(["img", "tex", "st", "nrm", "xf", "NG", "P", "S2"]), max_size=3,
                          unique=clean))
    extra = [draw(st.one_of(prims(2, clean, name), texture_nodes(clean, name), texture_nodes(clean, name)))
             for name in names]
    interface = draw(st.lists(attributes("NodeGraph", clean), max_size=2, unique_by=lambda a: a.split(" = ")[0]
                              if clean else a))
    shader = _block('def Shader "S"' + draw(st.sampled_from(["", SHADER_CUSTOM_DATA])),
                    [f'uniform token info:id = "{shader_id}"', *inputs, f"token outputs:{output}"])
    lines = [*interface, f"token outputs:{context}.connect = </M/S.outputs:{output}>", shader, *extra]
    return _block(f'def Material "M" {draw(prim_metadata())}', lines)


@st.composite
def layer_metadata(draw, clean: bool = False) -> str:
    valid = [
        'defaultPrim = "M"', 'defaultPrim = "Nowhere"', "metersPerUnit = 0.01", "metersPerUnit = 0",
        "metersPerUnit = -1", "metersPerUnit = nan", 'upAxis = "Y"', 'upAxis = "W"',
        f"subLayers = [@{draw(st.sampled_from(ARC_PATHS))}@]", "subLayers = []",
        'expressionVariables = {\n    string W = "/etc/passwd"\n}', "timeCodesPerSecond = 0", 'doc = """x"""',
        'customLayerData = {\n    dictionary a = {\n        dictionary b = {\n        }\n    }\n}',
        "colorConfiguration = @/etc/ocio.config@", 'colorManagementSystem = "OCIO"',
    ]
    chosen = draw(st.lists(st.sampled_from(valid if clean else valid + ['metersPerUnit = "m"']), max_size=5,
                           unique_by=lambda line: line.split(" = ")[0]))
    return "(\n    " + "\n    ".join(c.replace("\n", "\n    ") for c in chosen) + "\n)\n" if chosen else ""


@st.composite
def usda_text(draw) -> str:
    """A text stage: mostly well-formed (so the reader and the rules see it), sometimes wild."""
    clean = draw(st.integers(0, 3)) > 0
    header = "#usda 1.0" if clean else draw(st.sampled_from(
        ["#usda 1.0", "#usda 1.0", "#usda 0.1", "#usda 9.9", "#sdf 1.4.32", "#usda", "", "#usda 1.0 # comment"]))
    count = draw(st.integers(0, 2))
    names = draw(st.lists(st.sampled_from(["M", "M", "Looks", "P", "tex"]), min_size=count, max_size=count,
                          unique=clean))
    body = [draw(materials(clean)) if name == "M" else draw(st.one_of(prims(1, clean, name),
                                                                       texture_nodes(clean, name))) for name in names]
    return header + "\n" + draw(layer_metadata(clean)) + "\n" + "\n\n".join(body) + "\n"


@st.composite
def encodings(draw, text: str) -> bytes:
    """The text in UTF-8 mostly; otherwise with a byte-order mark, in UTF-16, or with invalid UTF-8."""
    choice = draw(st.sampled_from(["utf-8"] * 8 + ["bom", "utf-16", "utf-16-be", "latin-1", "invalid", "nul", "crlf"]))
    data = text.encode("utf-8", "surrogatepass")
    if choice == "bom":
        return b"\xef\xbb\xbf" + data
    if choice in ("utf-16", "utf-16-be"):
        return text.encode(choice, "surrogatepass")
    if choice == "latin-1":
        return text.encode("latin-1", "replace")
    if choice == "invalid" and data:
        position = draw(st.integers(0, len(data)))
        return data[:position] + draw(st.sampled_from([b"\xff", b"\xc3", b"\xed\xa0\x80", b"\xf8\x88\x80\x80\x80"])) \
            + data[position:]
    if choice == "nul" and data:
        position = draw(st.integers(0, len(data)))
        return data[:position] + b"\x00" + data[position:]
    if choice == "crlf":
        return data.replace(b"\n", b"\r\n")
    return data


def text_mutations(data: bytes):
    """:func:`fuzzgen.byte_edits` with USDA's tokens."""
    return fuzzgen.byte_edits(data, TEXT_INSERTS, unchanged=3, edits=6)


TEXT_INSERTS = [b"{", b"}", b"(", b")", b"[", b"]", b'"', b"'", b"@", b"@@@", b"<", b">", b"#", b"//", b"/*", b"=",
                b"\n", b"\x00", b"\xff", b"`", b"\\", b'"""', b".connect", b"None", b"def \"x\" {", b"1e999"]


@st.composite
def usda_documents(draw) -> bytes:
    return draw(text_mutations(draw(encodings(draw(usda_text())))))


# -- binary seeds and raw mutations ---------------------------------------------------------------

def seed_documents() -> dict[str, list[bytes]]:
    """Valid stages to corrupt, by suffix: the samples as ``openpbr convert`` writes them (text,
    crate and package) and the USD rules' examples (text, exported to crate and packaged)."""
    from pxr import Sdf

    from openpbr_tools.rules import all_rules
    from openpbr_tools.convert import convert_file

    found: dict[str, list[bytes]] = {".usda": [], ".usdc": [], ".usdz": []}
    samples = os.path.join(os.path.dirname(__file__), "..", "openpbr_tools", "samples")
    with tempfile.TemporaryDirectory() as folder:
        for name in sorted(os.listdir(samples)):
            if not name.endswith(".mtlx"):
                continue
            for suffix, documents in found.items():
                output = os.path.join(folder, name.replace(".mtlx", suffix))
                convert_file(os.path.join(samples, name), output)
                with open(output, "rb") as handle:
                    documents.append(handle.read())
        texts = [r.failing for r in all_rules().values() if r.failing_name.endswith(".usda")]
        texts += [r.passing for r in all_rules().values() if r.passing_name.endswith(".usda")]
        for number, text in enumerate(texts):
            found[".usda"].append(text.encode("utf-8"))
            layer = Sdf.Layer.CreateAnonymous(".usda")
            if not layer.ImportFromString(text):
                continue
            crate = os.path.join(folder, f"rule{number}.usdc")
            layer.Export(crate)
            with open(crate, "rb") as handle:
                found[".usdc"].append(handle.read())
            found[".usdz"].append(package([("root.usdc", found[".usdc"][-1]), ("albedo.png", b"\x89PNG\r\n\x1a\n")]))
        found[".usdz"] += [r.failing for r in all_rules().values() if r.failing_name.endswith(".usdz")]
    return found


def package(entries: list[tuple[str, bytes]]) -> bytes:
    buffer = io.BytesIO()
    with zipfile.ZipFile(buffer, "w", zipfile.ZIP_STORED) as archive:
        for name, data in entries:
            archive.writestr(zipfile.ZipInfo(name), data)
    return buffer.getvalue()


_EXTREMES = [b"\x00\x00\x00\x00", b"\xff\xff\xff\xff", b"\xff\xff\xff\x7f", b"\x00\x00\x00\x80", b"\x01\x00\x00\x00",
             b"\x00\x00\x00\x00\x00\x00\x00\x00", b"\xff\xff\xff\xff\xff\xff\xff\xff", b"\xff\xff\xff\xff\xff\xff\xff\x7f",
             b"\x00\x00\x01\x00\x00\x00\x00\x00", b"\xf0\xff\xff\xff"]


def mutate_bytes(data: bytes, rng: random.Random) -> bytes:
    """Corrupt ``data``: flip bytes, overwrite little-endian integers with extreme values (sizes,
    offsets and counts in crate files and zip headers), insert, delete, duplicate or truncate."""
    buffer = bytearray(data)
    for _ in range(rng.randint(1, 12)):
        if not buffer:
            break
        position = rng.randrange(len(buffer))
        choice = rng.random()
        if choice < 0.35:
            buffer[position] = rng.randrange(256)
        elif choice < 0.6:
            extreme = rng.choice(_EXTREMES)
            buffer[position:position + len(extreme)] = extreme
        elif choice < 0.72:
            buffer[position:position] = rng.choice(TEXT_INSERTS + [bytes([rng.randrange(256)]) * rng.randint(1, 64)])
        elif choice < 0.85:
            del buffer[position:position + rng.randint(1, 32)]
        elif choice < 0.93:
            start = rng.randrange(len(buffer))
            buffer[position:position] = buffer[start:start + rng.randint(1, 256)]
        else:
            del buffer[position:]
    return bytes(buffer)
