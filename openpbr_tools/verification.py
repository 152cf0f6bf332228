"""Verifying a conversion (``openpbr convert --verify``): the written output read back and each of
its materials rendered beside its source by the lobe evaluator, textures read per pixel, on the lit
sphere and, where textured, on the texture-space swatch (:mod:`openpbr_tools.evaluate.verify`);
the report's OPBR1108 / OPBR1109 notes.
"""

from __future__ import annotations

import collections
import os
import tempfile

from .bake import Baker
from .convert import Conversion, display_name
from .translate.convert import judged_as
from .diagnostics import Diagnostic
from .model import Material
from .rules import Context
from .rules.translation import VERIFIED, VERIFY_THRESHOLD


def measure(conversion: Conversion) -> list[tuple[Material, object]]:
    """(source material, CIEDE2000 statistics of the view that differs most: the lit sphere or, for a
    textured material, the texture-space swatch) for every converted material; see :func:`compare`."""
    return [(source, comparison.worst) for source, comparison in compare(conversion)]


def compare(conversion: Conversion, keep_images: bool = False) -> list[tuple[Material, object]]:
    """(source material, :class:`~openpbr_tools.evaluate.verify.MaterialComparison`) for every
    converted material, rendered by the lobe evaluator with textures read per pixel on the lit
    sphere and, where textured, on the texture-space swatch.

    What is judged is the output as written: the output file is read back and each source is
    compared with the materials written for it (same material name; a USD output's OpenPBR shader
    and its UsdPreviewSurface fallback each get a comparison, named ``material (model)``), their
    textures read from the output's folder (and the source's, which .mtlx outputs reference). When
    the output cannot be read back, the in-memory result is compared and a note says so. Colours are
    compared in each material's own colour space converted to linear Rec.709, so a glTF result
    (linear Rec.709 factors) and an ACEScg source are compared fairly."""
    from .evaluate.textures import TextureSampler  # lazy: the evaluator loads its albedo tables
    from .evaluate.verify import compare_materials  # lazy: as above

    source_reader = conversion.baker or Baker(conversion.asset.path, tempfile.gettempdir(), conversion.allow_outside)
    source_sampler = TextureSampler([source_reader])
    output_reader = _output_reader(conversion)
    written, why = _written(conversion)
    output_sampler = TextureSampler([output_reader]) if output_reader is not None else None
    # the in-memory result's textures: the conversion's baker (the source's folder, the images it baked), the output's
    in_memory = TextureSampler([r for r in (conversion.baker, output_reader) if r is not None])
    found = []
    repeated = collections.Counter(display_name(result) for _, result in conversion.pairs)
    seen: collections.Counter = collections.Counter()
    for source, result in conversion.pairs:
        judged = judged_as(source, result.model)  # (a draft-extension glTF: its OpenPBR reading)
        name = display_name(result)
        targets = _own(written.get(name, []) if written is not None else [], repeated[name], seen[name])
        seen[name] += 1
        if not targets:
            comparison = compare_materials(judged, result, sampler=source_sampler, keep_images=keep_images,
                                           sampler_b=in_memory)
            comparison.notes.append(f"the output {why or 'has no material ' + repr(display_name(result))}: "
                                    "the in-memory result was compared")
            found.append((source, comparison))
            continue
        for target in targets:
            comparison = compare_materials(judged, target, sampler=source_sampler, sampler_b=output_sampler,
                                           keep_images=keep_images)
            if len(targets) > 1:
                comparison.name_b = f"{display_name(target)} ({target.model})"
            found.append((source, comparison))
    return found


def _own(targets: list[Material], repeats: int, occurrence: int) -> list[Material]:
    """Of the written materials sharing a result's name, those written for it: where ``repeats`` results
    share the name (glTF allows that: Khronos' IridescenceSuzanne names all three "Material"), the
    ``occurrence``-th of each model written, in order; otherwise all of them (a USD output's OpenPBR shader
    and its preview fallback)."""
    if repeats < 2:
        return targets
    by_model: dict[str, list[Material]] = {}
    for target in targets:
        by_model.setdefault(target.model, []).append(target)
    own = [found[occurrence] for found in by_model.values() if len(found) == repeats]
    return own or targets


def _output_reader(conversion: Conversion) -> Baker | None:
    """A reader anchored at the output (rebased or packaged textures), allowed to read the source's
    folder too (a .mtlx output references the source's textures); None when nothing was written."""
    if not conversion.output:
        return None
    source_folder = os.path.dirname(os.path.abspath(conversion.asset.path))
    return Baker(conversion.output, tempfile.gettempdir(), conversion.allow_outside + (source_folder,))


def _written(conversion: Conversion):
    """(materials of the written output by material name, or None and why not)."""
    from .io import ReadError, read_asset  # lazy: the readers load with the formats they read

    if not conversion.output or not os.path.exists(conversion.output):
        return None, "was not written"
    try:
        asset = read_asset(conversion.output)
    except (ReadError, OSError, ValueError) as error:
        return None, f"cannot be read back ({error})"
    by_name: dict[str, list[Material]] = {}
    for material in asset.materials:
        by_name.setdefault(display_name(material), []).append(material)
    return by_name, None


def verify(conversion: Conversion, threshold: float = 2.0, context: Context | None = None,
           measured: list | None = None) -> list[Diagnostic]:
    """The report of :func:`compare` (or of ``measured``, its result): OPBR1108 per material, OPBR1109
    where the mean CIEDE2000 of the sphere or of the texture-space swatch exceeds ``threshold``."""
    context = context or Context()
    found = []
    for source, comparison in (measured if measured is not None else compare(conversion)):
        delta = comparison.preview
        written = f" ({comparison.name_b})" if comparison.name_b not in (comparison.name_a, display_name(source)) else ""
        message = (f"{source.name}: {source.model} -> {comparison.model_b}{written}, CIEDE2000 mean {delta.mean:.2f}, "
                   f"p95 {delta.p95:.2f}, max {delta.max:.2f} (lit sphere)")
        if comparison.swatch is not None:
            flat = comparison.swatch
            message += f"; mean {flat.mean:.2f}, p95 {flat.p95:.2f}, max {flat.max:.2f} (texture swatch, per texel)"
        rule = VERIFY_THRESHOLD if comparison.worst.exceeds(threshold) and not comparison.unread \
            and not comparison.stand_ins else VERIFIED
        if comparison.stand_ins:  # (the red team's E#2, E#4: a graph of interface inputs, a UV set other than st)
            one = len(comparison.stand_ins) == 1
            message += (f"; not a measure of the conversion: {', '.join(comparison.stand_ins)} "
                        f"{'is a procedural graph' if one else 'are procedural graphs'} the evaluator renders as a "
                        "stand-in on that side only (textures read per texel, or a rotation rendered, on the other)")
        if comparison.unread:  # (the red team's C6: a correct conversion was reported 22-29 apart, each side's
            # unreadable texture rendered at its fallback)
            message += (f"; not a measure of the conversion: the textures of {', '.join(comparison.unread)} could not "
                        "be read, so each side renders at its fallback there (--allow-outside lets a folder be read)")
        found.append(context.diagnostic(rule, message, source.location.with_material(display_name(source))))
    return found
