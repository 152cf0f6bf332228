"""Hypothesis strategies that build hostile-but-plausible MaterialX documents, and byte mutations.

Shared by the quick fuzz tests (tests/test_fuzz_mtlx.py) and the long run
(tests/benchmarks/fuzz_long.py). Documents are assembled from the pieces real files are made of
(shader nodes, inputs, images, node graphs, materials, looks) with every attribute drawn from a mix
of valid values, near misses and garbage, then optionally truncated or corrupted byte by byte.
"""

from __future__ import annotations

from xml.sax.saxutils import quoteattr

from hypothesis import strategies as st

from openpbr_tools import tables

CATEGORIES = ["open_pbr_surface", "standard_surface", "gltf_pbr", "UsdPreviewSurface", "open_pbr_surfce",
              "image", "tiledimage", "extract", "normalmap", "place2d", "texcoord", "convert", "noise3d",
              "surfacematerial", "multiply", "separate3", "nodegraph_like", "", "xi:include"]
TYPES = ["float", "color3", "color4", "vector2", "vector3", "vector4", "boolean", "integer", "string",
         "filename", "surfaceshader", "material", "BSDF", "", "colour3", "float[]"]
NAMES = sorted(set().union(*(tables.table(m).parameters for m in tables.MODELS))) + [
    "base_roughness", "specular_ior_level", "file", "in", "index", "texcoord", "scale", "surfaceshader",
    "default", "uaddressmode", "base_colour", "", "a" * 300, "S", "M", "img"]
ELEMENT_NAMES = ["S", "M", "img", "NG", "out", "place", "g", "missing", "S2", "x" * 100]
TEXT = st.text(alphabet=st.characters(blacklist_categories=("Cs",)), max_size=40)
VALUES = st.one_of(
    st.floats(allow_nan=True, allow_infinity=True).map(repr),
    st.lists(st.floats(width=32, allow_nan=True), min_size=1, max_size=5).map(lambda v: ", ".join(map(repr, v))),
    st.sampled_from(["1,5", "0.5", "true", "false", "1e400", "-0", "nan", "inf", "", " ", "0.5abc", "1,2,3",
                     "wood_<UDIM>.png", "../../etc/passwd", "/abs/path.png", "http://x/y.png", "tex/a.png"]),
    TEXT,
)
ATTRIBUTE = st.tuples(
    st.sampled_from(["value", "colorspace", "unit", "unittype", "nodename", "nodegraph", "output",
                     "interfacename", "version", "nodedef", "doc", "fileprefix", "uniform", "type"]),
    st.one_of(VALUES, st.sampled_from(ELEMENT_NAMES + ["srgb_tx", "acescg", "none", "meter", "cm", "distance",
                                                       "openpbr-ignore: OPBR301", "openpbr-ignore-file: all"])),
)


@st.composite
def inputs(draw) -> str:
    attributes = {"name": draw(st.sampled_from(NAMES)), "type": draw(st.sampled_from(TYPES))}
    attributes.update(dict(draw(st.lists(ATTRIBUTE, max_size=4))))
    return "<input " + " ".join(f"{k}={quoteattr(v)}" for k, v in attributes.items()) + " />"


@st.composite
def nodes(draw, depth: int = 0) -> str:
    category = draw(st.sampled_from(CATEGORIES))
    attributes = {"name": draw(st.sampled_from(ELEMENT_NAMES)), "type": draw(st.sampled_from(TYPES))}
    attributes.update(dict(draw(st.lists(ATTRIBUTE, max_size=2))))
    children = draw(st.lists(inputs(), max_size=6))
    if depth < 2 and draw(st.booleans()):
        children.append(draw(nodes(depth + 1)))
    tag = category if category and " " not in category else "node"
    opening = f"<{tag} " + " ".join(f"{k}={quoteattr(v)}" for k, v in attributes.items())
    if not children:
        return opening + " />"
    return opening + ">" + "".join(children) + f"</{tag}>"


SHADERS = ["open_pbr_surface", "open_pbr_surface", "open_pbr_surface", "standard_surface", "gltf_pbr", "UsdPreviewSurface"]


@st.composite
def shader_inputs(draw, model: str) -> str:
    parameter = draw(st.sampled_from(sorted(tables.table(model).parameters.values(), key=lambda p: p.name)))
    attributes = {"name": parameter.name, "type": draw(st.one_of(st.just(parameter.type), st.sampled_from(TYPES)))}
    attributes["value"] = draw(VALUES)
    attributes.update(dict(draw(st.lists(ATTRIBUTE, max_size=2))))
    return "<input " + " ".join(f"{k}={quoteattr(v)}" for k, v in attributes.items()) + " />"


@st.composite
def shaders(draw) -> str:
    model = draw(st.sampled_from(SHADERS))
    version = draw(st.sampled_from(["", ' version="1.1.1"', ' version="0.2"', ' version="9"']))
    body = draw(st.lists(st.one_of(shader_inputs(model), inputs()), min_size=1, max_size=10))
    return f'<{model} name="S" type="surfaceshader"{version}>' + "".join(body) + f"</{model}>" + \
        '<surfacematerial name="M" type="material"><input name="surfaceshader" type="surfaceshader" nodename="S" /></surfacematerial>'


@st.composite
def mtlx_documents(draw) -> bytes:
    root = {"version": draw(st.sampled_from(["1.39", "1.38", "1.37", "", "2.0", "abc"]))}
    if draw(st.booleans()):
        root["colorspace"] = draw(st.sampled_from(["lin_rec709", "acescg", "srgb_tx", "", "ACEScg"]))
    body = draw(st.lists(st.one_of(shaders(), shaders(), nodes(), st.just('<look name="L"><materialassign name="a" material="M" /></look>'),
                                   st.just("<!-- openpbr-ignore: OPBR101 -->")), max_size=8))
    text = ('<?xml version="1.0"?>\n<materialx ' + " ".join(f"{k}={quoteattr(v)}" for k, v in root.items()) + ">\n"
            + "\n".join(body) + "\n</materialx>\n")
    data = text.encode("utf-8", "surrogatepass")
    return draw(byte_edits(data, XML_INSERTS))


@st.composite
def byte_edits(draw, data: bytes, inserts: list[bytes], unchanged: int = 2, edits: int = 8) -> bytes:
    """Leave ``data`` alone (``unchanged`` chances in ``unchanged + 2``), truncate it, or make 1 to
    ``edits`` byte flips, insertions (of one of ``inserts``) and deletions. Shared by the MaterialX,
    glTF and USD generators, each with the tokens its parser cares about."""
    kind = draw(st.sampled_from(["none"] * unchanged + ["truncate", "bytes"]))
    if kind == "truncate" and data:
        return data[: draw(st.integers(0, len(data) - 1))]
    if kind == "bytes" and data:
        buffer = bytearray(data)
        for _ in range(draw(st.integers(1, edits))):
            position = draw(st.integers(0, len(buffer) - 1))
            operation = draw(st.sampled_from(["flip", "insert", "delete"]))
            if operation == "flip":
                buffer[position] = draw(st.integers(0, 255))
            elif operation == "insert":
                buffer[position:position] = draw(st.sampled_from(inserts))
            elif len(buffer) > 1:
                del buffer[position]
        return bytes(buffer)
    return data


XML_INSERTS = [b"<", b">", b'"', b"&", b"\x00", b"\xff", b"<a>", b"&x;"]
