"""Translation quality on the test set: our converter against MaterialX's own translation chain.

    python tests/benchmarks/bench_translation.py --output translation.json
        [--set tests/data/translation_set] [--no-gl] [--no-chain] [--size 96] [--bake-size 64]
        [--worst 5] [--keep FOLDER]

For every material of ``tests/data/translation_set`` (one OpenPBR 1.1.1 material per ``.mtlx``) and
every target (``standard_surface``, ``gltf_pbr``, ``UsdPreviewSurface``):

* **ours**: ``openpbr_tools.convert.convert_file`` writes the target (``.mtlx --to`` for
  Standard Surface and UsdPreviewSurface, ``.gltf`` for glTF, as ``openpbr convert`` does), the
  result is read back with ``read_asset``, and the loss report is kept;
* **MaterialX chain**: what MaterialX's own ``translateshader.py`` does, ``ShaderTranslator`` then
  ``TextureBaker`` (GLSL, float images; the baker writes a constant wherever a translated output is
  uniform), OpenPBR -> Standard Surface, then that baked Standard Surface -> glTF PBR and ->
  UsdPreviewSurface (the chain MaterialX offers: it has no OpenPBR -> glTF/USD graphs);
* **evaluator**: ``openpbr_tools.evaluate.verify.compare_materials`` between the source and the
  result: CIEDE2000 over the lit-sphere preview (mean over the sphere's pixels is the figure used);
* **GLSL** (constant-valued materials only): the source, our result and the chain's result rendered
  by MaterialX's GLSL renderer (``tests/glsupport.py``: same sphere, camera and lights as the
  evaluator) and compared pixel by pixel (CIEDE2000, silhouette band excluded).

The evaluator does not sample textures: a textured input is evaluated at its ``fallback``. So that
textured materials (source, ours and the chain's baked result alike) are evaluated at a
representative value, this script sets every texture's fallback to its mean texel value
(colour textures averaged in linear light), and reports textured materials in separate rows.

To run the chain on this set, four things MaterialX 1.39.5 gets wrong are worked around (each is
reported in the JSON under ``materialx_workarounds``):

1. ``ShaderTranslator`` raises "Shader input has no associated output or value" for an input
   connected with ``nodename`` to a top-level node (the usual way to author a textured material):
   the top-level nodes are moved into a node graph whose outputs feed the shader, unchanged;
2. ``TextureBaker`` bakes a single texel (a constant) for an ``image`` fed by a ``place2d`` whose
   ``texcoord`` is left to its default geometric property: an explicit ``texcoord`` node is added;
3. the translated shader keeps the source's ``version="1.1.1"``, which names no ``gltf_pbr`` /
   ``standard_surface`` node definition, so nothing can be generated: the attribute is removed;
4. ``TextureBaker`` writes ``value=""`` for boolean and integer outputs (``thin_walled``,
   ``alpha_mode``): each is evaluated by baking a float ``convert`` of that output through a probe
   material, with MaterialX's own generator and renderer; and chaining two ``ShaderTranslator``
   passes on one document drops the ``output`` of multi-output connections, so the chain bakes
   after each pass, as ``translateshader.py`` does.

Needs an X display or Xvfb and Mesa for the chain and the GLSL renders (``--no-chain`` and
``--no-gl`` skip them). Takes a few minutes; run it with ``nice``.
"""

from __future__ import annotations

import argparse
import contextlib
import copy
import fnmatch
import glob
import json
import os
import statistics
import sys
import tempfile
import time
import traceback

HERE = os.path.dirname(os.path.abspath(__file__))
TESTS = os.path.dirname(HERE)
DEFAULT_SET = os.path.join(TESTS, "data", "translation_set")
sys.path.insert(0, TESTS)

TARGETS = ("standard_surface", "gltf_pbr", "UsdPreviewSurface")
OUTPUT_SUFFIX = {"standard_surface": ".mtlx", "gltf_pbr": ".gltf", "UsdPreviewSurface": ".mtlx"}
ISSUE_TARGET = {"standard_surface": 1.0, "gltf_pbr": 1.0}  # median mean-ΔE2000 (issue 5)


# -- textures at their mean texel ------------------------------------------------------------------

def _read_pixels(path: str):
    """Float pixels (H, W, C) of an image file: OpenImageIO when installed, else Pillow."""
    import numpy as np

    try:
        import OpenImageIO as oiio

        image = oiio.ImageInput.open(path)
        if image is not None:
            pixels = image.read_image("float")
            image.close()
            if pixels is not None:
                return np.asarray(pixels, dtype=float).reshape(image.spec().height, image.spec().width, -1)
    except ImportError:
        pass
    from PIL import Image

    with Image.open(path) as handle:
        array = np.asarray(handle, dtype=float)
        scale = 65535.0 if handle.mode.startswith("I;16") or array.max() > 255 else 255.0
    array = array / scale
    return array[..., None] if array.ndim == 2 else array


def texture_mean(texture, folder: str):
    """The mean value the texture feeds to its parameter (channels selected, scale and bias
    applied), expressed in the texture's colour encoding so the evaluator decodes it as it would a
    texel; ``None`` when the image cannot be read."""
    import numpy as np

    path = texture.file if os.path.isabs(texture.file) else os.path.join(folder, texture.file)
    try:
        pixels = _read_pixels(path)
    except (OSError, ValueError):
        return None
    srgb = (texture.colorspace or "").lower() in ("srgb_texture", "srgb", "srgb_rec709_scene")
    if srgb:
        pixels = np.where(pixels <= 0.04045, pixels / 12.92, ((pixels + 0.055) / 1.055) ** 2.4)
    if texture.channels is not None:
        pixels = pixels[..., [min(c, pixels.shape[-1] - 1) for c in texture.channels]]
    elif texture.image_type == "float":
        pixels = pixels[..., :1]
    else:
        pixels = pixels[..., :3] if pixels.shape[-1] >= 3 else np.repeat(pixels[..., :1], 3, axis=-1)
    mean = pixels.reshape(-1, pixels.shape[-1]).mean(axis=0)
    if srgb:
        mean = np.where(mean <= 0.0031308, mean * 12.92, 1.055 * np.power(np.maximum(mean, 0.0), 1 / 2.4) - 0.055)
    if texture.scale is not None:
        mean = mean * np.asarray(texture.scale, dtype=float)
    if texture.bias is not None:
        mean = mean + np.asarray(texture.bias, dtype=float)
    values = [float(v) for v in np.ravel(mean)]
    return values[0] if len(values) == 1 else tuple(values)


def at_mean_texels(material):
    """A copy of ``material`` whose textures fall back to their mean texel value."""
    from openpbr_tools.model import Texture

    result = copy.deepcopy(material)
    for entry in result.inputs.values():
        texture = entry.value
        if isinstance(texture, Texture) and texture.normal_map is None and texture.image_type != "vector3":
            anchor = (texture.location.file if texture.location else None) or material.location.file
            mean = texture_mean(texture, os.path.dirname(os.path.abspath(anchor)))
            if mean is not None:
                texture.fallback = mean
    return result


def shader_doc(path: str) -> str:
    """The ``doc`` attribute of the file's first OpenPBR shader (what the material represents)."""
    import MaterialX as mx

    document = mx.createDocument()
    mx.readFromXmlFile(document, path)
    shaders = [n for n in document.getNodes() if n.getCategory() == "open_pbr_surface"]
    return shaders[0].getDocString() if shaders else ""


def is_constant(material) -> bool:
    from openpbr_tools.model import Constant

    return all(isinstance(entry.value, Constant) for entry in material.inputs.values())


# -- ours -----------------------------------------------------------------------------------------

def convert_ours(path: str, target: str, folder: str):
    """(result material, loss report lines, seconds) from ``convert_file`` and a read-back."""
    from openpbr_tools.io import read_asset
    from openpbr_tools.convert import convert_file

    stem = os.path.splitext(os.path.basename(path))[0]
    output = os.path.join(folder, target, stem + OUTPUT_SUFFIX[target])
    os.makedirs(os.path.dirname(output), exist_ok=True)
    start = time.perf_counter()
    conversion = convert_file(path, output, None if target == "gltf_pbr" else target)
    seconds = time.perf_counter() - start
    report = [f"{d.code} {d.severity}: {d.message}" for d in conversion.diagnostics]
    back = read_asset(output).materials
    if not back:
        raise RuntimeError(f"{output}: no material read back")
    return back[0], report, seconds, output


# -- MaterialX's chain ------------------------------------------------------------------------------

@contextlib.contextmanager
def native_stdout_silenced():
    """Send file descriptor 1 (where MaterialX's C++ code prints) to /dev/null for a while."""
    sys.stdout.flush()
    saved = os.dup(1)
    with open(os.devnull, "w") as null:
        os.dup2(null.fileno(), 1)
    try:
        yield
    finally:
        os.dup2(saved, 1)
        os.close(saved)


class MaterialXChain:
    """``ShaderTranslator`` + ``TextureBaker`` (see the module docstring for the workarounds)."""

    SHADERS = ("open_pbr_surface", "standard_surface", "gltf_pbr", "UsdPreviewSurface")

    def __init__(self, bake_size: int):
        import MaterialX as mx
        import MaterialX.PyMaterialXGenShader as gs
        import MaterialX.PyMaterialXRender as mr
        import MaterialX.PyMaterialXRenderGlsl as rg

        self.mx, self.gs, self.mr, self.rg = mx, gs, mr, rg
        self.bake_size = bake_size
        self.library = mx.createDocument()
        self.search_path = mx.getDefaultDataSearchPath()
        mx.loadLibraries(mx.getDefaultDataLibraryFolders(), self.search_path, self.library)

    def _bake(self, document, material_path: str, folder: str, source_folder: str, size: int):
        mx = self.mx
        search = mx.FileSearchPath(self.search_path.asString())
        search.append(mx.FilePath(source_folder))
        with native_stdout_silenced():  # the baker prints a line per material and per image
            baker = self.rg.TextureBaker.create(size, size, self.mr.BaseType.FLOAT)
            baker.setOptimizeConstants(True)
            baker.setOutputImagePath(mx.FilePath(folder))
            return baker.bakeMaterialToDoc(document, search, material_path, [], os.path.join(folder, "baked"))

    def _wrap_top_level_nodes(self, document) -> list[str]:
        """Workaround 1 and 2: top-level nodes into a node graph; explicit ``texcoord`` on place2d."""
        notes = []
        loose = [n for n in document.getNodes() if n.getType() not in ("surfaceshader", "material")]
        if loose:
            graph = document.addNodeGraph(document.createValidChildName("NG_source_nodes"))
            for node in loose:
                graph.addNode(node.getCategory(), node.getName(), node.getType()).copyContentFrom(node)
            for node in loose:
                document.removeNode(node.getName())
            for shader in (n for n in document.getNodes() if n.getCategory() in self.SHADERS):
                for port in shader.getInputs():
                    if port.getNodeName() and graph.getNode(port.getNodeName()) is not None:
                        output = graph.addOutput(f"out_{port.getName()}", port.getType())
                        output.setNodeName(port.getNodeName())
                        port.removeAttribute("nodename")
                        port.setNodeGraphString(graph.getName())
                        port.setOutputString(output.getName())
            notes.append(f"moved {len(loose)} top-level node(s) into a node graph (ShaderTranslator needs graph outputs)")
        for graph in document.getNodeGraphs():
            for node in graph.getNodes():
                if node.getCategory() == "place2d" and node.getInput("texcoord") is None:
                    uv = graph.addNode("texcoord", graph.createValidChildName(f"{node.getName()}_uv"), "vector2")
                    node.addInput("texcoord", "vector2").setConnectedNode(uv)
                    notes.append(f"explicit texcoord on place2d {node.getName()} (TextureBaker samples one texel otherwise)")
        return notes

    def _probe_uniform_outputs(self, document, shader, folder: str, source_folder: str) -> list[str]:
        """Workaround 4: boolean/integer inputs fed by the translation graph, evaluated by baking a
        float ``convert`` of the same output through a probe ``standard_surface.base``."""
        notes = []
        for port in shader.getInputs():
            if port.getType() not in ("boolean", "integer") or not port.getNodeGraphString():
                continue
            graph = document.getNodeGraph(port.getNodeGraphString())
            source = graph.getOutput(port.getOutputString())
            convert = graph.addNode("convert", graph.createValidChildName(f"probe_{port.getName()}"), "float")
            into = convert.addInput("in", port.getType())
            into.setConnectedNode(graph.getNode(source.getNodeName()))
            if source.getOutputString():
                into.setOutputString(source.getOutputString())
            probe_output = graph.addOutput(graph.createValidChildName(f"probe_{port.getName()}_out"), "float")
            probe_output.setConnectedNode(convert)
            probe = document.addNode("standard_surface", document.createValidChildName("probe_shader"), "surfaceshader")
            base = probe.addInput("base", "float")
            base.setNodeGraphString(graph.getName())
            base.setOutputString(probe_output.getName())
            material = document.addMaterialNode(document.createValidChildName("probe_material"), probe)
            baked = self._bake(document, material.getNamePath(), folder, source_folder, 4)
            value = 1.0  # the baker omits a constant equal to the nodedef default (base = 1)
            for node in baked.getNodes():
                found = node.getInput("base") if node.getCategory() == "standard_surface" else None
                if found is not None and found.hasValueString() and found.getValueString():
                    value = float(found.getValueString())
            for name in (material.getName(), probe.getName()):
                document.removeNode(name)
            graph.removeOutput(probe_output.getName())
            graph.removeNode(convert.getName())
            port.removeAttribute("nodegraph")
            port.removeAttribute("output")
            port.setValueString(("true" if value > 0.5 else "false") if port.getType() == "boolean" else str(round(value)))
            notes.append(f"{port.getName()} = {port.getValueString()} (probed; TextureBaker writes an empty value)")
        return notes

    def translate(self, source_path: str, target: str, folder: str) -> tuple[str, list[str]]:
        """Translate every material of ``source_path`` to ``target`` and bake; returns the baked
        document's path and the workarounds applied."""
        mx = self.mx
        os.makedirs(folder, exist_ok=True)
        document = mx.createDocument()
        mx.readFromXmlFile(document, source_path)
        document.setDataLibrary(self.library)
        notes = self._wrap_top_level_nodes(document)
        self.gs.ShaderTranslator.create().translateAllMaterials(document, target)
        shaders = [n for n in document.getNodes() if n.getCategory() == target]
        if not shaders:
            raise RuntimeError(f"ShaderTranslator produced no {target} shader")
        source_folder = os.path.dirname(os.path.abspath(source_path))
        for shader in shaders:
            if shader.hasAttribute("version"):
                notes.append(f"removed version={shader.getAttribute('version')} left on the translated {target}")
                shader.removeAttribute("version")
            notes += self._probe_uniform_outputs(document, shader, folder, source_folder)
        valid, message = document.validate()
        if not valid:
            notes.append(f"translated document does not validate: {message.strip()}")
        materials = document.getMaterialNodes()
        if len(materials) != 1:
            raise RuntimeError(f"expected one material, found {len(materials)}")
        baked = self._bake(document, materials[0].getNamePath(), folder, source_folder, self.bake_size)
        if baked is None:
            raise RuntimeError("TextureBaker returned no document")
        output = os.path.join(folder, os.path.splitext(os.path.basename(source_path))[0] + f"_{target}.mtlx")
        mx.writeToXmlFile(baked, output)
        return output, notes

    def chain(self, source_path: str, folder: str) -> dict:
        """target -> (baked path, notes) or an ``Exception``: OpenPBR -> Standard Surface, then
        from the baked Standard Surface to glTF PBR and UsdPreviewSurface."""
        results = {}
        try:
            standard, notes = self.translate(source_path, "standard_surface", os.path.join(folder, "standard_surface"))
            results["standard_surface"] = (standard, notes)
        except Exception as error:  # noqa: BLE001 - a failure of MaterialX is a result here
            for target in TARGETS:
                results[target] = error
            return results
        for target in ("gltf_pbr", "UsdPreviewSurface"):
            try:
                path, more = self.translate(standard, target, os.path.join(folder, target))
                results[target] = (path, notes + more)
            except Exception as error:  # noqa: BLE001
                results[target] = error
        return results


# -- GLSL ------------------------------------------------------------------------------------------

class GlslComparison:
    """Renders collected per model (one shader program per model), then compared."""

    def __init__(self, size: int):
        from glsupport import MaterialXRenderer, comparison_mask

        from openpbr_tools.evaluate.preview import Rig

        self.rig = Rig(size=size)
        self.renderer = MaterialXRenderer(self.rig)
        self.mask = comparison_mask(self.rig)
        self.jobs: list[tuple[str, str, dict]] = []  # (key, model, values)
        self.images: dict[str, object] = {}

    def add(self, key: str, material) -> None:
        from openpbr_tools.evaluate import resolve

        self.jobs.append((key, material.model, resolve(material).values))

    def render_all(self) -> None:
        for key, model, values in sorted(self.jobs, key=lambda job: job[1]):
            self.images[key] = self.renderer.render(model, values)

    def delta(self, key_a: str, key_b: str):
        import numpy as np

        from openpbr_tools.evaluate.difference import compare_images
        from openpbr_tools.evaluate.preview import sphere_geometry

        mask = sphere_geometry(self.rig).mask & self.mask
        a, b = self.images.get(key_a), self.images.get(key_b)
        if a is None or b is None or not np.all(np.isfinite(a[mask])) or not np.all(np.isfinite(b[mask])):
            return None
        return compare_images(a, b, mask, self.rig.white())


# -- the run -----------------------------------------------------------------------------------------

def summary(values: list[float]) -> dict:
    if not values:
        return {"n": 0}
    ordered = sorted(values)
    p90 = ordered[min(len(ordered) - 1, round(0.9 * (len(ordered) - 1)))]
    return {"n": len(values), "median": statistics.median(values), "p90": p90, "max": ordered[-1]}


def run(options) -> dict:
    from openpbr_tools.evaluate.verify import compare_materials
    from openpbr_tools.io import read_asset

    files = sorted(glob.glob(os.path.join(options.set, "*.mtlx")))
    if options.only:
        files = [f for f in files if any(fnmatch.fnmatch(os.path.basename(f), p) for p in options.only)]
    work = options.keep or tempfile.mkdtemp(prefix="openpbr-bench-translation-")
    chain = None
    if not options.no_chain or not options.no_gl:
        from glsupport import gl_status

        ok, reason = gl_status()
        print(f"GL: {reason}", file=sys.stderr)
        if not ok:
            options.no_chain = options.no_gl = True
    if not options.no_chain:
        chain = MaterialXChain(options.bake_size)
    glsl = None if options.no_gl else GlslComparison(options.size)

    records = []
    for index, path in enumerate(files):
        stem = os.path.splitext(os.path.basename(path))[0]
        print(f"[{index + 1}/{len(files)}] {stem}", file=sys.stderr)
        source = read_asset(path).materials[0]
        record = {"file": os.path.relpath(path, options.set), "material": source.name, "constant": is_constant(source),
                  "doc": shader_doc(path), "targets": {}}
        evaluated_source = at_mean_texels(source)
        if glsl is not None and record["constant"]:
            glsl.add(f"{stem}/source", source)
        chained = chain.chain(path, os.path.join(work, "materialx", stem)) if chain else {}
        for target in TARGETS:
            entry = {"ours": {}, "materialx_chain": {}}
            try:
                result, report, seconds, output = convert_ours(path, target, os.path.join(work, "ours"))
                comparison = compare_materials(evaluated_source, at_mean_texels(result))
                entry["ours"] = {"evaluator": comparison.preview.as_dict(), "albedo": comparison.albedo.as_dict(),
                                 "loss_report": report, "seconds": seconds, "output": output,
                                 "evaluator_notes": comparison.notes}
                if glsl is not None and record["constant"]:
                    glsl.add(f"{stem}/{target}/ours", result)
            except Exception as error:  # noqa: BLE001 - reported per material
                entry["ours"] = {"error": f"{type(error).__name__}: {error}", "traceback": traceback.format_exc(limit=4)}
            outcome = chained.get(target)
            if isinstance(outcome, Exception):
                entry["materialx_chain"] = {"error": f"{type(outcome).__name__}: {outcome}"}
            elif outcome is not None:
                baked_path, notes = outcome
                try:
                    baked = read_asset(baked_path).materials[0]
                    comparison = compare_materials(evaluated_source, at_mean_texels(baked))
                    entry["materialx_chain"] = {"evaluator": comparison.preview.as_dict(), "albedo": comparison.albedo.as_dict(),
                                                "materialx_workarounds": notes, "output": baked_path,
                                                "evaluator_notes": comparison.notes}
                    if glsl is not None and record["constant"]:
                        glsl.add(f"{stem}/{target}/chain", baked)
                except Exception as error:  # noqa: BLE001
                    entry["materialx_chain"] = {"error": f"reading the baked result: {type(error).__name__}: {error}",
                                                "materialx_workarounds": notes, "output": baked_path}
            record["targets"][target] = entry
        records.append(record)

    if glsl is not None:
        print(f"GLSL: rendering {len(glsl.jobs)} images", file=sys.stderr)
        glsl.render_all()
        for record in records:
            if not record["constant"]:
                continue
            stem = os.path.splitext(record["file"])[0]
            for target, entry in record["targets"].items():
                for side, suffix in (("ours", "ours"), ("materialx_chain", "chain")):
                    delta = glsl.delta(f"{stem}/source", f"{stem}/{target}/{suffix}")
                    if delta is not None and "error" not in entry[side]:
                        entry[side]["glsl"] = delta.as_dict()
    return {"set": os.path.relpath(options.set), "materials": len(records), "work_folder": work,
            "glsl": glsl is not None, "materialx_chain": chain is not None, "bake_size": options.bake_size,
            "preview_size": options.size, "records": records}


def _mean_text(entry: dict, side: str, kind: str) -> str:
    if "error" in entry[side]:
        return "err"
    value = entry[side].get(kind, {}).get("mean")
    return "-" if value is None else f"{value:.2f}"


def tables(result: dict, worst: int) -> str:
    lines = []
    for subset, keep in (("constant-valued", lambda r: r["constant"]), ("all, textures at their mean texel", lambda r: True)):
        lines.append(f"\nMean-ΔE2000 per material ({subset}): median / p90 / max  [n]")
        lines.append(f"  {'target':18s} {'ours (evaluator)':>24s} {'MaterialX (evaluator)':>24s} {'ours (GLSL)':>24s} {'MaterialX (GLSL)':>24s}")
        for target in TARGETS:
            cells = []
            for side, kind in (("ours", "evaluator"), ("materialx_chain", "evaluator"), ("ours", "glsl"), ("materialx_chain", "glsl")):
                values = [r["targets"][target][side][kind]["mean"] for r in result["records"]
                          if keep(r) and kind in r["targets"][target][side]]
                s = summary(values)
                cells.append(f"{s['median']:6.2f} {s['p90']:6.2f} {s['max']:6.2f} [{s['n']:2d}]" if s["n"] else f"{'-':>24s}")
            lines.append(f"  {target:18s} " + " ".join(f"{c:>24s}" for c in cells))
        failures = {}
        for target in TARGETS:
            for side in ("ours", "materialx_chain"):
                n = sum(1 for r in result["records"] if keep(r) and "error" in r["targets"][target][side])
                if n:
                    failures[f"{side} -> {target}"] = n
        if failures:
            lines.append("  failed conversions: " + ", ".join(f"{k}: {v}" for k, v in failures.items()))
    lines.append("\nPer material, mean-ΔE2000 ours / MaterialX chain (evaluator; GLSL in brackets for constant-valued ones):")
    lines.append(f"  {'file':38s} " + " ".join(f"{t:>30s}" for t in TARGETS))
    for r in result["records"]:
        cells = []
        for target in TARGETS:
            entry = r["targets"][target]
            cell = f"{_mean_text(entry, 'ours', 'evaluator')}/{_mean_text(entry, 'materialx_chain', 'evaluator')}"
            if r["constant"]:
                cell += f" [{_mean_text(entry, 'ours', 'glsl')}/{_mean_text(entry, 'materialx_chain', 'glsl')}]"
            cells.append(cell)
        lines.append(f"  {r['file']:38s} " + " ".join(f"{c:>30s}" for c in cells))
    lines.append("\nIssue target (constant-valued set, evaluator): median ≤ 1.0 for glTF and Standard Surface, "
                 "and below MaterialX's chain on every target")
    for target in TARGETS:
        ours = summary([r["targets"][target]["ours"]["evaluator"]["mean"] for r in result["records"]
                        if r["constant"] and "evaluator" in r["targets"][target]["ours"]])
        theirs = summary([r["targets"][target]["materialx_chain"]["evaluator"]["mean"] for r in result["records"]
                          if r["constant"] and "evaluator" in r["targets"][target]["materialx_chain"]])
        verdicts = []
        if target in ISSUE_TARGET and ours["n"]:
            verdicts.append(f"median {ours['median']:.3f} {'≤' if ours['median'] <= ISSUE_TARGET[target] else '>'} {ISSUE_TARGET[target]}")
        if ours["n"] and theirs["n"]:
            verdicts.append(f"median {ours['median']:.3f} {'below' if ours['median'] < theirs['median'] else 'NOT below'} "
                            f"MaterialX's median {theirs['median']:.3f}")
        lines.append(f"  {target:18s} " + "; ".join(verdicts))
    for target in TARGETS:
        ranked = sorted((r for r in result["records"] if "evaluator" in r["targets"][target]["ours"]),
                        key=lambda r: -r["targets"][target]["ours"]["evaluator"]["mean"])[:worst]
        lines.append(f"\nWorst {len(ranked)} for OpenPBR -> {target} (ours, evaluator mean; MaterialX chain beside):")
        for r in ranked:
            ours = r["targets"][target]["ours"]
            chain = r["targets"][target]["materialx_chain"]
            theirs = chain.get("evaluator", {}).get("mean")
            glsl = ours.get("glsl", {}).get("mean")
            theirs_glsl = chain.get("glsl", {}).get("mean")
            lines.append(f"  {r['file']:38s} ours {ours['evaluator']['mean']:6.2f} (GLSL {'-' if glsl is None else f'{glsl:.2f}'})"
                         f"   MaterialX {'-' if theirs is None else f'{theirs:.2f}'}"
                         f" (GLSL {'-' if theirs_glsl is None else f'{theirs_glsl:.2f}'})")
            for line in ours["loss_report"]:
                if not line.startswith("OPBR1102"):  # exact conversions are not a diagnosis
                    lines.append(f"      {line}")
    return "\n".join(lines)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--set", default=DEFAULT_SET, help="folder of OpenPBR .mtlx files")
    parser.add_argument("--output", "-o", help="write per-material results to this JSON file")
    parser.add_argument("--no-gl", action="store_true", help="skip the GLSL renders")
    parser.add_argument("--no-chain", action="store_true", help="skip MaterialX's translation chain")
    parser.add_argument("--size", type=int, default=96, help="preview size in pixels for the GLSL renders")
    parser.add_argument("--bake-size", type=int, default=64, help="TextureBaker resolution for non-uniform outputs")
    parser.add_argument("--worst", type=int, default=5, help="worst materials listed per target")
    parser.add_argument("--only", action="append", help="only files matching this glob (repeatable)")
    parser.add_argument("--keep", help="write converted files here (default: a temporary folder, kept)")
    options = parser.parse_args()
    start = time.perf_counter()
    result = run(options)
    result["seconds"] = time.perf_counter() - start
    print(tables(result, options.worst))
    print(f"\n{result['materials']} materials in {result['seconds']:.0f} s; converted files in {result['work_folder']}")
    if options.output:
        with open(options.output, "w", encoding="utf-8") as handle:
            json.dump(result, handle, indent=1, default=float)
        print(f"wrote {options.output}")


if __name__ == "__main__":
    main()
