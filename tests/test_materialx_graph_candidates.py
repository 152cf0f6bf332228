"""MaterialX's translation graphs as a candidate (#13): the interpreter of
``openpbr_tools/translate/materialx_graphs.py`` against MaterialX itself (ShaderTranslator +
TextureBaker, rendered with GLSL: the values MaterialX's chain really produces), and the choice
``convert --verify`` makes between the toolkit's mapping and the graphs.
"""

from __future__ import annotations

import os
import random
import sys
from pathlib import Path

import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).resolve().parent))
sys.path.insert(0, str(Path(__file__).resolve().parent / "benchmarks"))
from glsupport import require_gl  # noqa: E402

from openpbr_tools.convert import convert_file  # noqa: E402
from openpbr_tools.translate import materialx_graphs  # noqa: E402
from openpbr_tools.translate.common import Settings  # noqa: E402

FLOATS = ("base_weight", "base_metalness", "specular_weight", "specular_roughness", "specular_roughness_anisotropy",
          "transmission_weight", "subsurface_weight", "fuzz_weight", "fuzz_roughness", "coat_weight",
          "coat_roughness", "coat_darkening", "thin_film_weight", "emission_luminance", "geometry_opacity")
COLOURS = ("base_color", "specular_color", "transmission_color", "subsurface_color", "fuzz_color", "coat_color",
           "emission_color")


def _material(rng: random.Random) -> dict:
    values = {name: round(rng.random(), 4) for name in FLOATS if rng.random() < 0.6}
    values.update({name: tuple(round(rng.random(), 4) for _ in range(3)) for name in COLOURS if rng.random() < 0.6})
    if rng.random() < 0.5:
        values["coat_ior"] = round(1.2 + rng.random(), 4)
    if rng.random() < 0.5:
        values["specular_ior"] = round(1.2 + rng.random(), 4)
    return values


def _document(path: Path, values: dict) -> None:
    def text(value):
        return ", ".join(str(v) for v in value) if isinstance(value, tuple) else str(value)

    inputs = "".join(f'<input name="{k}" type="{"color3" if isinstance(v, tuple) else "float"}" value="{text(v)}" />'
                     for k, v in values.items())
    path.write_text('<?xml version="1.0"?>\n<materialx version="1.39" colorspace="lin_rec709">\n'
                    f'<open_pbr_surface name="S" type="surfaceshader">{inputs}</open_pbr_surface>\n'
                    '<surfacematerial name="M" type="material"><input name="surfaceshader" type="surfaceshader" '
                    'nodename="S" /></surfacematerial>\n</materialx>\n')


@pytest.mark.gl
@pytest.mark.parametrize("target", ["standard_surface", "gltf_pbr", "UsdPreviewSurface"])
def test_the_graph_interpreter_gives_the_values_materialx_bakes(tmp_path, target):
    require_gl()
    import MaterialX as mx
    from bench_translation import MaterialXChain

    chain = MaterialXChain(4)
    rng = random.Random(sum(map(ord, target)))  # (str hash() is salted per process)
    for index in range(4 if target == "standard_surface" else 2):
        values = _material(rng)
        source = tmp_path / f"m{index}.mtlx"
        _document(source, values)
        baked_path = str(source)
        for graph in materialx_graphs.CHAINS[target]:
            model = {"standard_surface": "standard_surface", "gltf_pbr": "gltf_pbr",
                     "usd": "UsdPreviewSurface"}[graph.split("_to_")[1]]
            baked_path, _ = chain.translate(baked_path, model, str(tmp_path / f"m{index}_{model}"))
        document = mx.createDocument()
        mx.readFromXmlFile(document, baked_path)
        document.setDataLibrary(chain.library)
        (shader,) = [n for n in document.getNodes() if n.getCategory() == target]
        ours = materialx_graphs.chain(target, values)
        compared = 0
        for definition in shader.getNodeDef().getActiveInputs():  # the baker omits values at their default
            port = shader.getInput(definition.getName())
            port = port if port is not None and port.hasValueString() else definition
            if not port.hasValueString() or port.getType() not in ("float", "color3") or port.getName() not in ours:
                continue
            value = port.getValue()
            expected = tuple(value) if port.getType() == "color3" else value
            assert ours[port.getName()] == pytest.approx(expected, abs=2e-5), (index, port.getName(), values)
            compared += 1
        assert compared >= 5


@pytest.fixture
def without_the_fit(monkeypatch):
    """The graphs' mechanism on its own: the appearance fit (which would let the fitted mapping win
    these) off."""
    from openpbr_tools.translate import appearance

    monkeypatch.setattr(appearance, "FIT_FROM", float("inf"))


def test_verify_keeps_the_graphs_result_where_it_renders_closer_and_says_so(tmp_path, without_the_fit):
    source = Path(__file__).parent / "data" / "translation_set" / "plastic_translucent_blue.mtlx"
    default = convert_file(str(source), str(tmp_path / "plain.gltf"), settings=Settings(candidates=False))
    verified = convert_file(str(source), str(tmp_path / "verified.gltf"))  # the search is on by default
    assert not [d for d in default.diagnostics if "candidates for" in d.message or "translation graphs" in d.message]
    chosen = [d for d in verified.diagnostics if "converted to gltf_pbr by MaterialX's translation graphs" in d.message]
    assert len(chosen) == 1 and chosen[0].code == "OPBR1103"
    # every authored input the graphs' result does not carry exactly has its own note: checked against
    # the written file read back and converted to OpenPBR without the search
    from openpbr_tools.translate.convert import convert

    (original,) = __import__("openpbr_tools.io", fromlist=["read_asset"]).read_asset(str(source)).materials
    (written,) = __import__("openpbr_tools.io", fromlist=["read_asset"]).read_asset(str(tmp_path / "verified.gltf")).materials
    back = convert(written, "open_pbr_surface", Settings(candidates=False)).material
    changed = {name for name, entry in original.inputs.items()
               if back.inputs.get(name) is None or
               pytest.approx(entry.value.value, abs=1e-4) != back.inputs[name].value.value}
    noted = {d.location.input for d in verified.diagnostics if "not carried exactly by MaterialX's" in d.message}
    assert changed and noted & set(original.inputs) == changed, (changed, noted)
    assert all("(default" in d.message for d in verified.diagnostics  # the others: defaults the result changes
               if "not carried exactly by MaterialX's" in d.message and d.location.input not in original.inputs)
    # the graphs' own arithmetic, not the mapping's, is what was written
    from openpbr_tools.io import read_asset

    (material,) = read_asset(str(source)).materials
    expected = materialx_graphs.chain("gltf_pbr", {k: v.value.value for k, v in material.inputs.items()})
    written = read_asset(str(tmp_path / "verified.gltf")).materials[0]
    assert written.inputs["transmission"].value.value == pytest.approx(expected["transmission"], abs=1e-6)


def test_an_exact_mapping_is_kept_without_a_search(tmp_path):
    source = tmp_path / "plain.mtlx"
    _document(source, {"base_color": (0.5, 0.2, 0.1), "specular_roughness": 0.4})
    result = convert_file(str(source), str(tmp_path / "out.gltf"))
    assert not [d for d in result.diagnostics if "candidates for" in d.message]
    assert os.path.exists(tmp_path / "out.gltf")


def _glsl_errors(source_path: Path, results: dict, target: str) -> dict:
    """Mean CIEDE2000, rendered by MaterialX's GLSL renderer (an independent judge), of each result
    file in ``results`` (label -> path, one ``target`` material) against the OpenPBR source."""
    import numpy as np
    from glsupport import comparison_mask, materialx_renderer

    from openpbr_tools.evaluate.difference import compare_images
    from openpbr_tools.evaluate.preview import Rig
    from openpbr_tools.io import read_asset

    rig = Rig(size=64)
    renderer = materialx_renderer(rig)

    def values(material):
        return {k: (list(v.value.value) if isinstance(v.value.value, tuple) else v.value.value)
                for k, v in material.inputs.items()}

    (source,) = read_asset(str(source_path)).materials
    reference = renderer.render("open_pbr_surface", values(source))
    mask = comparison_mask(rig) & np.isfinite(reference).all(axis=-1)
    errors = {}
    for label, path in results.items():
        (material,) = read_asset(str(path)).materials
        errors[label] = compare_images(reference, renderer.render(target, values(material)), mask, rig.white()).mean
    return errors


def _plain_and_searched(tmp_path, source_path: Path, target: str, label: str, settings: Settings | None = None):
    """``source_path`` converted to ``target`` without the search ("plain") and with ``settings``
    (``label``): the second conversion and both files' mean CIEDE2000 in MaterialX's GLSL renderer."""
    suffix, to = ("gltf", None) if target == "gltf_pbr" else ("mtlx", target)
    convert_file(str(source_path), str(tmp_path / f"plain.{suffix}"), to, settings=Settings(candidates=False))
    searched = convert_file(str(source_path), str(tmp_path / f"{label}.{suffix}"), to, settings=settings or Settings())
    return searched, _glsl_errors(source_path, {name: tmp_path / f"{name}.{suffix}" for name in ("plain", label)},
                                  target)


@pytest.mark.gl
@pytest.mark.parametrize("name, target", [("open_pbr_pearl.mtlx", "standard_surface")])
def test_where_the_graphs_win_materialx_glsl_agrees(tmp_path, name, target, without_the_fit):
    """The evaluator's choice checked by an independent judge: MaterialX's GLSL renderer must not
    render the graphs' result further from the OpenPBR source than the mapping's (a tie within 0.05
    mean CIEDE2000 allowed). (The gold to glTF that was here won only unclamped: its graphs' base colour
    lies outside Rec.709, the glTF writer clamps it, and judged as written it ties the mapping, 1.42.)"""
    source_path = Path(__file__).parent / "data" / "published" / "openpbr" / name
    chosen, errors = _plain_and_searched(tmp_path, source_path, target, "chosen")
    assert [d for d in chosen.diagnostics if "by MaterialX's translation graphs" in d.message]
    assert errors["chosen"] < errors["plain"] + 0.05, errors


@pytest.mark.gl
def test_a_fitted_film_thickness_is_closer_in_materialx_glsl_too(tmp_path):
    """Anodised titanium (a measured thin film on a metal) to Standard Surface, whose MaterialX
    implementation puts the film on a conductor where OpenPBR's puts it on the metal's F0: the
    evaluator fits the film thickness, and MaterialX's GLSL renderer, an independent judge, must
    agree that the fitted material renders closer to the OpenPBR source than the mapped one."""
    source_path = Path(__file__).parent / "data" / "published" / "measured" / "Titanium_Anodized.mtlx"
    fitted, errors = _plain_and_searched(tmp_path, source_path, "standard_surface", "fitted",
                                         Settings(fit_films=True))  # as --verify
    assert [d for d in fitted.diagnostics if "thin_film_thickness fitted" in d.message]
    assert errors["fitted"] < errors["plain"] - 1.0, errors


@pytest.mark.gl
@pytest.mark.parametrize("folder, name, target", [("translation_set", "fabric_wool.mtlx", "UsdPreviewSurface"),
                                                  ("translation_set", "thin_paper.mtlx", "UsdPreviewSurface")])
def test_where_the_appearance_fit_is_kept_materialx_glsl_agrees(tmp_path, folder, name, target):
    """The fit is chosen on the evaluator; MaterialX's GLSL renderer, an independent judge, must not
    render the fitted material further from the OpenPBR source than the plain mapping (within 0.05).
    Not always so: the anisotropic coat to glTF, fitted 1.92 -> 1.47 on the evaluator, is 1.39 -> 1.51
    in GLSL; tests/benchmarks/bench_glsl_sample.py counts such disagreements on a seeded sample."""
    source_path = Path(__file__).parent / "data" / folder / name
    chosen, errors = _plain_and_searched(tmp_path, source_path, target, "fitted")
    assert [d for d in chosen.diagnostics if "adjusted to" in d.message]
    assert errors["fitted"] < errors["plain"] + 0.05, errors


def test_the_graphs_evaluated_for_a_file_at_once_give_each_materials_own_values(tmp_path):
    """materialx_graphs.chain_many (every node once for a file's materials, as the candidate search
    calls it) gives, bit for bit, what chain gives each material alone, for generated OpenPBR and
    Standard Surface materials through every graph; and a material the graphs cannot take (a value of
    another type) loses only its own candidate (candidates.graph_candidates)."""
    from generated_materials import COLORSPACES, document
    from openpbr_tools.io import read_asset
    from openpbr_tools.model import Constant, Input
    from openpbr_tools.translate import anchor
    from openpbr_tools.translate.judging import constant_values

    compared = 0
    for model in ("open_pbr_surface", "standard_surface"):
        path = tmp_path / f"{model}.mtlx"
        path.write_text(document(model, COLORSPACES[len(model) % 3], 5, 60))
        materials = read_asset(str(path)).materials
        values = [constant_values(m) for m in materials]
        for target in ("standard_surface", "gltf_pbr", "UsdPreviewSurface", "open_pbr_surface"):
            if not materialx_graphs.graphs(model, target):
                continue
            together = materialx_graphs.chain_many(target, values, model)
            for one, alone in zip(together, (materialx_graphs.chain(target, v, model) for v in values)):
                assert one.keys() == alone.keys()
                assert all(np.array_equal(np.asarray(one[k]), np.asarray(alone[k])) and type(one[k]) is type(alone[k])
                           for k in one)
                compared += len(one)
        broken = materials[1]
        broken.inputs["base_color"] = Input("base_color", "color3", Constant((0.5, 0.5)), broken.location)
        found = anchor.graph_candidates(materials, "gltf_pbr")
        assert found[1] is None and all(c is not None for i, c in enumerate(found) if i != 1)
        alone = anchor.graph_candidate(materials[2], "gltf_pbr")
        assert {k: v.value.value for k, v in found[2].inputs.items()} == {k: v.value.value for k, v in alone.inputs.items()}
    assert compared > 2000
