"""The textures of a conversion's written materials, beside its output (split from :mod:`openpbr_tools.convert`):
relative paths rebased from the source's folder to the output's, and a USDZ source's packaged images unpacked
beside a .mtlx or .usda output that cannot reference inside the package."""

from __future__ import annotations

import copy
import dataclasses
import os

from .atomic import write_bytes
from .diagnostics import Diagnostic
from .io import ReadError, package_member, packaged_image
from .io.image_files import suffix_of
from .io.gltf.document import load_document
from .io.paths import Kind, PathGuard, classify
from .model import Asset, Connection, Material, Texture, graph_key, kept, texture_key
from .rules.translation import NOT_CARRIED

def rebase_textures(materials: list[Material], source_path: str, output_path: str) -> None:
    """Re-express relative texture paths relative to the output's folder, so they still resolve: a
    texture's file, and the filename inputs of a kept procedural graph."""
    source_dir = os.path.dirname(os.path.abspath(source_path))
    output_dir = os.path.dirname(os.path.abspath(output_path))
    output_folder = PathGuard(output_dir, real_path=os.path.normpath)  # where the output's own files are, as spelt
    def rebased(file: str) -> str | None:
        kind = classify(file)
        if kind in (Kind.URL, Kind.NUL, Kind.EMPTY, Kind.DRIVE, Kind.UNC):
            return None  # names no file here: written as authored
        absolute = file if kind is Kind.ABSOLUTE else os.path.join(source_dir, file)
        if kind is Kind.ABSOLUTE and not output_folder.contains(absolute):
            return None  # an absolute path the user authored stays as it is
        return os.path.relpath(absolute, output_dir).replace(os.sep, "/")

    for material in materials:
        displacement = material.extra.get("displacement_graph")
        if isinstance(displacement, Connection) and displacement.graph_xml:
            from .io.mtlx.capture import rewrite_files  # lazy: as below

            material.extra = dict(material.extra, displacement_graph=dataclasses.replace(
                displacement, graph_xml=rewrite_files(displacement.graph_xml, rebased)))
        for name, entry in list(material.inputs.items()):
            value = entry.value
            if isinstance(value, Connection) and value.graph_xml:
                # lazy: MaterialX is loaded for a .mtlx output anyway (this runs only for one)
                from .io.mtlx.capture import rewrite_files

                moved = copy.copy(value)
                moved.graph_xml = rewrite_files(value.graph_xml, rebased)
                if kept(value):  # (the graph kept whole is rebased alike: still the capture it stands for)
                    moved.kept_graph = rewrite_files(value.kept_graph, rebased)
                    moved.kept_for = graph_key(moved.graph_xml, moved.output)
            elif isinstance(value, Texture) and not value.packaged and (file := rebased(value.file)) is not None:
                moved = copy.copy(value)
                moved.file = file
                if kept(value):
                    from .io.mtlx.capture import rewrite_files  # lazy: as above

                    moved.kept_graph = rewrite_files(value.kept_graph, rebased)
                    moved.kept_for = texture_key(moved)
            else:
                continue
            rebased_entry = copy.copy(entry)  # the entry may be the source's own (a value copied through): never mutated
            rebased_entry.value = moved
            material.inputs[name] = rebased_entry


def unpack_packaged_images(materials: list[Material], asset: Asset, output_path: str,
                           folder: str | None = None) -> list[Diagnostic]:
    """Images inside the source's own container written beside an output that can only reference files
    (``<output stem>_textures/``): a glTF's embedded ``#/images/N`` as ``image_N.<ext>`` (for a .mtlx or
    USD output), a USDZ's members, nested packages' too, under their own file names (for a .mtlx, .usda or
    .usdc output; a .usdz output copies them from the source package itself), or in ``folder`` (a .usdz output's
    staging folder, from which it packages them). A member that cannot be read stays as it is, with a note."""
    extensions = {"image/png": ".png", "image/jpeg": ".jpg", "image/webp": ".webp", "image/ktx2": ".ktx2"}
    folder = folder or os.path.splitext(output_path)[0] + "_textures"
    document, written, notes, taken = None, {}, [], set()
    for material in materials:
        for name, entry in material.inputs.items():
            texture = entry.value
            if not (isinstance(texture, Texture) and texture.packaged):
                continue
            if texture.file not in written:
                if texture.file.startswith("#/images/"):
                    document = document or load_document(asset.path)
                    index = int(texture.file.rsplit("/", 1)[1])
                    data, mime = document.image_bytes(index)
                    # (named by its bytes: a declared mimeType may be wrong, OPBR1214)
                    file_name = f"image_{index}{suffix_of(bytes(data[:16])) or extensions.get(mime or '', '.bin')}"
                else:
                    try:
                        data, _ = packaged_image(asset.path, texture.file)
                    except ReadError as error:
                        notes.append(NOT_CARRIED.note(f"{material.name}: {texture.file!r} cannot be taken out of "
                                                      f"the package ({error.message})",
                                                      entry.location.with_material(material.name)))
                        written[texture.file] = None
                        continue
                    file_name = os.path.basename(package_member(texture.file.rstrip("]"))) or "image"
                stem, suffix = os.path.splitext(file_name)
                count = 1
                while file_name in taken:
                    count += 1
                    file_name = f"{stem}_{count}{suffix}"
                taken.add(file_name)
                os.makedirs(folder, exist_ok=True)
                target = os.path.join(folder, file_name)
                write_bytes(target, data)
                written[texture.file] = os.path.abspath(target)
            if written[texture.file] is not None:
                texture.file, texture.packaged = written[texture.file], False
    return notes


def missing_textures(materials: list[Material], source_path: str) -> list[Diagnostic]:
    """A note at each texture a .mtlx or USD output references (the reference is written to the same file,
    rebased against the output's folder) whose file is not on disk: the output names an image no renderer can read, as the source did
    (validate: OPBR701), and a glTF output, which embeds or copies images, says the same of the same
    texture. URLs, UDIM/UVTILE sets (their tiles are other files) and packaged images are not looked up."""
    source_dir = os.path.dirname(os.path.abspath(source_path))
    notes, said = [], set()
    for material in materials:
        for name, entry in material.inputs.items():
            value = entry.value
            if isinstance(value, Texture) and not value.packaged:
                files, what = [value.file], f"{name} reads"
            elif isinstance(value, Connection) and value.graph_xml:  # a kept graph's images (the red team's F10)
                from .io.mtlx.capture import rewrite_files  # lazy: MaterialX, for a graph only

                files, what = [], f"the graph on {name} reads"
                rewrite_files(value.graph_xml, lambda file: files.append(file))
            else:
                continue
            for file in files:
                if any(token in file for token in ("<UDIM>", "<UVTILE>", "%")):  # tiles, or a token filled in later
                    continue
                kind = classify(file)
                if kind not in (Kind.RELATIVE, Kind.ABSOLUTE):
                    continue
                absolute = file if kind is Kind.ABSOLUTE else os.path.join(source_dir, file)
                key = (entry.location, file)  # (a USD output's preview fallback reads the same file: said once)
                if os.path.isfile(absolute) or key in said:
                    continue
                said.add(key)
                notes.append(NOT_CARRIED.note(
                    f"{material.name}: {what} {file!r}, which does not exist beside the source: the reference is "
                    "written to the same place (rebased against the output's folder), where renderers find no image "
                    "either (one found through an application's search path, as MaterialX's test suite's are, "
                    "is not looked up)", entry.location.with_material(material.material_name or material.name)))
    return notes


def graph_fallbacks(material: Material, context) -> tuple[Material, list[Diagnostic]]:
    """``material`` for an output that holds no graph (glTF), with each input whose kept graph is an image on
    coordinates only the graph holds (a USD ``ND_image`` behind a ``rotate2d``: ``Connection.fallback``) read as that
    image with the placement read up to the network, and a note at each (the review of session 25: such a texture was
    dropped whole from glTF, where before the graph was kept it was written without its coordinates, silently). The
    source is never modified: a copy is returned when anything is swapped."""
    swapped = {name: entry for name, entry in material.inputs.items()
               if isinstance(entry.value, Connection) and entry.value.fallback is not None}
    if not swapped:
        return material, []
    result = copy.copy(material)
    result.inputs = dict(material.inputs)
    notes = []
    for name, entry in swapped.items():
        carried = copy.copy(entry)
        carried.value = entry.value.fallback
        result.inputs[name] = carried
        notes.append(context.diagnostic(
            NOT_CARRIED, f"{material.name}: {name}: the coordinates of its image come from a network no texture "
                         "transform holds (a .mtlx or USD output keeps it as a graph); the image is written with the "
                         "placement read up to that network", entry.location))
    return result, notes
