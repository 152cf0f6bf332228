"""Conversion between any two of the four shading models, through OpenPBR.

A legacy OpenPBR material is upgraded first; a non-OpenPBR source is translated to OpenPBR and then,
if the target is not OpenPBR, on to the target. The loss reports of every step are concatenated.
"""

from __future__ import annotations

from .. import tables
from ..model import Material
from .common import Settings, Translation
from .gltf import gltf_to_openpbr, openpbr_to_gltf
from .standard_surface import openpbr_to_standard_surface, standard_surface_to_openpbr
from .usd_preview import openpbr_to_usd_preview, usd_preview_to_openpbr

MODELS = ("open_pbr_surface", "standard_surface", "gltf_pbr", "UsdPreviewSurface")
TO_OPENPBR = {"standard_surface": standard_surface_to_openpbr, "gltf_pbr": gltf_to_openpbr,
              "UsdPreviewSurface": usd_preview_to_openpbr}
FROM_OPENPBR = {"standard_surface": openpbr_to_standard_surface, "gltf_pbr": openpbr_to_gltf,
                "UsdPreviewSurface": openpbr_to_usd_preview}


def convert(material: Material, target: str, settings: Settings | None = None) -> Translation:
    if target not in MODELS:
        raise ValueError(f"unknown shading model {target!r} (known: {', '.join(MODELS)})")
    if material.model not in MODELS:
        raise ValueError(f"cannot convert a {material.model} material")
    settings = settings or Settings()
    diagnostics = []
    current = material
    if current.model == "open_pbr_surface":
        if current.version and current.version != tables.latest("open_pbr_surface"):
            from .upgrade import upgrade

            upgraded = upgrade(current, context=settings.context)
            diagnostics += upgraded.diagnostics
            current = upgraded.material
    elif current.model != target:
        step = TO_OPENPBR[current.model](current, settings)
        diagnostics += step.diagnostics
        current = step.material
    if current.model != target:
        step = FROM_OPENPBR[target](current, settings)
        diagnostics += step.diagnostics
        current = step.material
    return Translation(current, diagnostics, material)


# -- files ---------------------------------------------------------------------------------------

import os  # noqa: E402
from dataclasses import dataclass, field  # noqa: E402

from ..diagnostics import Diagnostic  # noqa: E402
from ..model import Asset, Location  # noqa: E402
from ..rules.translation import APPROXIMATED, CONVERTED, NOT_CARRIED  # noqa: E402

OUTPUT_KINDS = {".mtlx": "mtlx", ".usda": "usd", ".usdc": "usd", ".usd": "usd", ".usdz": "usd",
                ".gltf": "gltf", ".glb": "gltf"}


@dataclass(slots=True)
class Conversion:
    """What ``convert_file`` did: the written materials, the loss report, and the source asset."""

    asset: Asset
    materials: list[Material] = field(default_factory=list)
    diagnostics: list[Diagnostic] = field(default_factory=list)
    pairs: list[tuple[Material, Material]] = field(default_factory=list)  # (source, result) per material


def output_kind(path: str) -> str | None:
    return OUTPUT_KINDS.get(os.path.splitext(path)[1].lower())


def _meters_per_unit(material: Material, asset: Asset) -> tuple[float, str | None]:
    """The scene unit of the material's lengths: a MaterialX ``unit`` on a length input, else the
    asset's (USD ``metersPerUnit``; glTF metres), else metres with a warning."""
    from ..resources import load_json

    distance = load_json("units.json")["distance"]
    for name in ("transmission_depth", "subsurface_radius", "attenuation_distance", "thickness"):
        entry = material.inputs.get(name)
        if entry is not None and entry.unit in distance:
            return distance[entry.unit], None
    if asset.meters_per_unit:
        return asset.meters_per_unit, None
    if asset.format == "gltf":
        return 1.0, None
    if asset.format == "usd":
        return load_json("units.json")["usd_default_meters_per_unit"], None
    lengths = [n for n in ("transmission_depth", "subsurface_radius") if n in material.inputs]
    if lengths:
        return 1.0, f"{', '.join(lengths)} carry no unit; taken as metres"
    return 1.0, None


def convert_file(input_path: str, output_path: str, target: str | None = None, settings: Settings | None = None,
                 mesh: str | None = None, allow_outside: tuple[str, ...] = ()) -> Conversion:
    """Read ``input_path``, translate every material for the output's format, and write ``output_path``.

    ``.mtlx`` output takes ``target`` (default OpenPBR); USD output gets OpenPBR on
    ``outputs:mtlx:surface`` plus a translated UsdPreviewSurface fallback on ``outputs:surface``;
    glTF output gets glTF PBR. Raises :class:`openpbr_tools.io.ReadError` for unreadable input and
    ``ValueError`` for an unsupported output.
    """
    import shutil
    import tempfile

    from ..io import read_asset
    from .bake import Baker

    kind = output_kind(output_path)
    if kind is None:
        raise ValueError(f"cannot write {os.path.splitext(output_path)[1] or 'files without a suffix'}")
    settings = settings or Settings()
    asset = read_asset(input_path)
    target = {"mtlx": target or "open_pbr_surface", "usd": "open_pbr_surface", "gltf": "gltf_pbr"}[kind]
    result = Conversion(asset)
    # Baked images go beside a .mtlx/.usda/.usdc output (<stem>_textures/); a glTF or USDZ output
    # embeds or copies them, so they wait in a temporary folder that is removed afterwards.
    packaged = kind == "gltf" or output_path.lower().endswith(".usdz")
    staging = tempfile.mkdtemp(prefix="openpbr-bake-") if packaged else None
    baker = Baker(asset.path, staging or os.path.abspath(os.path.splitext(output_path)[0] + "_textures"),
                  tuple(allow_outside), png_only=kind == "gltf")
    try:
        for material in asset.materials:
            if material.model not in MODELS:
                continue
            meters, warning = _meters_per_unit(material, asset)
            step_settings = Settings(settings.nits_per_unit, meters, settings.context, baker)
            if warning:
                result.diagnostics.append(settings.context.diagnostic(APPROXIMATED, f"{material.name}: {warning}",
                                                                      material.location))
            translation = convert(material, target, step_settings)
            result.diagnostics += translation.diagnostics
            translated = translation.material
            translated.material_name = material.material_name or material.name
            result.materials.append(translated)
            result.pairs.append((material, translated))
            if kind == "usd":
                preview = convert(translated, "UsdPreviewSurface", step_settings)
                result.diagnostics += preview.diagnostics
                preview.material.name = f"{translated.name}_preview"
                preview.material.material_name = translated.material_name
                result.materials.append(preview.material)
        written = _write_baked(baker, result.materials)
        try:
            allowed = tuple(allow_outside) + ((staging,) if staging else ())
            notes = _write(kind, result, output_path, mesh, allowed)
        except BaseException:
            for path in written:  # a failed conversion leaves no partial output behind
                if os.path.exists(path):
                    os.unlink(path)
            raise
    finally:
        if staging:
            shutil.rmtree(staging, ignore_errors=True)
    for note in notes:
        result.diagnostics.append(settings.context.diagnostic(_note_rule(note), note, Location(output_path)))
    result.diagnostics.sort(key=Diagnostic.sort_key)
    return result


LOST = ("not written", "dropped", "not packaged", "not copied", "unconverted", "as they are", "clamped", "cannot")
APPROXIMATE = (" used", "resampled", "approximat")


def _note_rule(note: str):
    """How much a writer's note matters: something lost (OPBR1104), approximated (OPBR1103), or a
    faithful change of form such as channel packing or an sRGB re-encoding (OPBR1102)."""
    if any(word in note for word in LOST):
        return NOT_CARRIED
    if any(word in note for word in APPROXIMATE):
        return APPROXIMATED
    return CONVERTED


def _write_baked(baker, materials: list[Material]) -> list[str]:
    """Write the baked images the written materials still use (atomically); returns their paths."""
    from ..atomic import write_bytes
    from ..model import Texture

    used = sorted({entry.value.file for material in materials for entry in material.inputs.values()
                   if isinstance(entry.value, Texture) and entry.value.file in baker.images})
    written = []
    for path in used:
        os.makedirs(os.path.dirname(path), exist_ok=True)
        write_bytes(path, baker.images[path])
        written.append(path)
    return written


def _rebase_textures(materials: list[Material], source_path: str, output_path: str) -> None:
    """Re-express relative texture paths relative to the output's folder, so they still resolve."""
    import copy

    from ..model import Texture

    source_dir = os.path.dirname(os.path.abspath(source_path))
    output_dir = os.path.dirname(os.path.abspath(output_path))
    for material in materials:
        for name, entry in list(material.inputs.items()):
            texture = entry.value
            if isinstance(texture, Texture) and not texture.packaged and "://" not in texture.file:
                absolute = texture.file if os.path.isabs(texture.file) else os.path.join(source_dir, texture.file)
                if os.path.isabs(texture.file) and not absolute.startswith(output_dir):
                    continue  # an absolute path the user authored stays as it is
                moved = copy.copy(texture)
                moved.file = os.path.relpath(absolute, output_dir).replace(os.sep, "/")
                entry.value = moved


def _unpack_gltf_images(materials: list[Material], asset: Asset, output_path: str) -> list[str]:
    """Images embedded in a glTF (``#/images/N``) written beside a .mtlx or USD output, which can only
    reference files: ``<output stem>_textures/image_N.<ext>``."""
    from ..atomic import write_bytes
    from ..io.gltf.document import load_document
    from ..model import Texture

    extensions = {"image/png": ".png", "image/jpeg": ".jpg", "image/webp": ".webp", "image/ktx2": ".ktx2"}
    folder = os.path.splitext(output_path)[0] + "_textures"
    document, written, notes = None, {}, []
    for material in materials:
        for entry in material.inputs.values():
            texture = entry.value
            if not (isinstance(texture, Texture) and texture.packaged and texture.file.startswith("#/images/")):
                continue
            if texture.file not in written:
                document = document or load_document(asset.path)
                index = int(texture.file.rsplit("/", 1)[1])
                data, mime = document.image_bytes(index)
                os.makedirs(folder, exist_ok=True)
                target = os.path.join(folder, f"image_{index}{extensions.get(mime or '', '.bin')}")
                write_bytes(target, data)
                written[texture.file] = os.path.abspath(target)
            texture.file, texture.packaged = written[texture.file], False
    if written:
        notes.append(f"{len(written)} image(s) embedded in {os.path.basename(asset.path)} written to {folder}")
    return notes


def _tag_length_units(materials: list[Material], asset: Asset) -> None:
    """Lengths from glTF (metres) or USD (``metersPerUnit``) get a MaterialX distance unit, so the
    written document says what its numbers mean."""
    from ..resources import load_json

    if asset.format not in ("gltf", "usd"):
        return
    scale = 1.0 if asset.format == "gltf" else (asset.meters_per_unit or load_json("units.json")["usd_default_meters_per_unit"])
    names = [name for name, factor in load_json("units.json")["distance"].items() if abs(factor - scale) <= 1e-12 * max(1, scale)]
    if not names:
        return
    for material in materials:
        table = tables.table(material.model)
        for name, entry in material.inputs.items():
            parameter = table.get(name)
            if parameter is not None and parameter.unit == "scene_length" and not entry.unit:
                entry.unit, entry.unittype = names[0], "distance"


def _write(kind: str, result: Conversion, output_path: str, mesh, allow_outside) -> list[str]:
    asset = result.asset
    if kind != "gltf" and asset.format == "gltf":
        _unpack_gltf_images(result.materials, asset, output_path)
    if kind == "mtlx":
        from ..io.mtlx.writer import write_mtlx

        _rebase_textures(result.materials, asset.path, output_path)
        _tag_length_units(result.materials, asset)
        write_mtlx(result.materials, output_path, colorspace=asset.colorspace or "lin_rec709")
        return []
    if kind == "usd":
        from ..io.usd.writer import write_usd

        return write_usd(result.materials, output_path, source=asset, allow_outside=allow_outside)
    try:
        from ..io.gltf.writer import write_gltf
    except ImportError:
        raise ValueError("glTF output needs the glTF writer, which this installation lacks") from None
    return write_gltf(result.materials, output_path, mesh=mesh, allow_outside=allow_outside, source=asset) or []


def verify(conversion: Conversion, threshold: float = 2.0, context=None) -> list[Diagnostic]:
    """CIEDE2000 between each source material and its conversion, rendered by the lobe evaluator.

    Colours are compared in each material's own colour space converted to linear Rec.709, so a
    glTF result (linear Rec.709 factors) and an ACEScg source are compared fairly."""
    from ..evaluate.verify import compare_materials
    from ..rules import Context
    from ..rules.translation import VERIFIED, VERIFY_THRESHOLD

    context = context or Context()
    found = []
    for source, result in conversion.pairs:
        comparison = compare_materials(source, result)
        delta = comparison.preview
        message = (f"{source.name}: {source.model} -> {result.model}, CIEDE2000 mean {delta.mean:.2f}, "
                   f"p95 {delta.p95:.2f}, max {delta.max:.2f} (lit sphere)")
        rule = VERIFY_THRESHOLD if delta.mean > threshold else VERIFIED
        found.append(context.diagnostic(rule, message, source.location))
    return found
