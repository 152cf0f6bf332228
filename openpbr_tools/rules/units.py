"""Units: are lengths given in a known unit, and are fixed-unit inputs plausible.

``transmission_depth`` and ``subsurface_radius`` are lengths in scene units: without a ``unit``
attribute (MaterialX) or ``metersPerUnit`` (USD) their meaning depends on whoever reads the file.
MaterialX converts them only when the input carries ``unittype="distance"`` and a ``unit`` from its
distance unit definition. ``thin_film_thickness`` is always micrometres (nanometres before OpenPBR
0.5) and ``emission_luminance`` nits: a unit attribute on them is ignored by renderers.
"""

from __future__ import annotations

import difflib

from ..diagnostics import Severity
from ..resources import load_json
from . import Rule, for_each_input

WRONG_UNITTYPE = Rule(
    "OPBR601", "wrong-unittype", Severity.ERROR,
    "A length input carries a unittype other than distance.",
    "MaterialX converts units only within a unit type; unittype=\"angle\" on a depth makes the "
    "conversion undefined.",
    passing='<open_pbr_surface name="S" type="surfaceshader">\n  <input name="transmission_depth" type="float" value="2" unittype="distance" unit="centimeter" />\n</open_pbr_surface>',
    failing='<open_pbr_surface name="S" type="surfaceshader">\n  <input name="transmission_depth" type="float" value="2" unittype="angle" unit="degree" />\n</open_pbr_surface>',
)
UNKNOWN_UNIT = Rule(
    "OPBR602", "unknown-unit", Severity.ERROR,
    "A unit name MaterialX's distance unit definition does not have.",
    "Known distance units: nanometer, micron, millimeter, centimeter, inch, foot, yard, meter, "
    "kilometer, mile. 'cm' or 'meters' are not converted.",
    passing='<open_pbr_surface name="S" type="surfaceshader">\n  <input name="subsurface_radius" type="float" value="0.5" unittype="distance" unit="centimeter" />\n</open_pbr_surface>',
    failing='<open_pbr_surface name="S" type="surfaceshader">\n  <input name="subsurface_radius" type="float" value="0.5" unittype="distance" unit="cm" />\n</open_pbr_surface>',
)
LENGTH_WITHOUT_UNIT = Rule(
    "OPBR603", "length-without-unit", Severity.INFO,
    "A length input is set without unit information.",
    "transmission_depth = 2 means 2 cm in a centimetre scene and 2 m in a metre scene. Add "
    "unittype=\"distance\" unit=\"...\" so converters and renderers can scale it. A style choice "
    "rather than a defect (MaterialX's own example materials set lengths without units, and renderers "
    "read them in scene units), so it is info by default: a project that wants units opts in with "
    "units = \"require\" (error) or \"warn\" in its configuration.",
    passing='<open_pbr_surface name="S" type="surfaceshader">\n  <input name="transmission_depth" type="float" value="2" unittype="distance" unit="centimeter" />\n</open_pbr_surface>',
    failing='<open_pbr_surface name="S" type="surfaceshader">\n  <input name="transmission_depth" type="float" value="2" />\n</open_pbr_surface>',
)
UNIT_IGNORED = Rule(
    "OPBR604", "unit-ignored", Severity.WARNING,
    "A unit attribute on an input whose unit is fixed or that has none.",
    "thin_film_thickness is in micrometres and emission_luminance in nits by definition; weights "
    "have no unit. MaterialX's shader generation converts any input carrying unittype=\"distance\" and a "
    "unit to the renderer's distance unit (metres in its viewer: 500 nanometer becomes 5e-07, where the "
    "input expects micrometres; a roughness of 0.4 centimeter becomes 0.004); renderers without unit "
    "conversion ignore the attribute. Either way the value is misread somewhere.",
    passing='<open_pbr_surface name="S" type="surfaceshader">\n  <input name="thin_film_thickness" type="float" value="0.5" />\n</open_pbr_surface>',
    failing='<open_pbr_surface name="S" type="surfaceshader">\n  <input name="thin_film_thickness" type="float" value="500" unittype="distance" unit="nanometer" />\n</open_pbr_surface>',
)
UNIT_ON_DIMENSIONLESS = Rule(
    "OPBR607", "unit-converted-into-range", Severity.INFO,
    "A dimensionless input is written as a distance that MaterialX's unit system converts into its range "
    "(specular_roughness 250 millimeter: 0.25).",
    "MaterialX's shader generation converts an input carrying unittype=\"distance\" and a unit to the "
    "renderer's distance unit, metres in its viewer and test suite (MaterialX's own "
    "stdlib/units/standard_surface_unit.mtlx writes specular_roughness 250 millimeter), so there it renders as "
    "meant; a renderer that does no unit conversion (or works in another unit) reads the number as written, "
    "out of range. The range checks judge the converted value.",
    passing='<open_pbr_surface name="S" type="surfaceshader">\n  <input name="specular_roughness" type="float" value="0.25" />\n</open_pbr_surface>',
    failing='<open_pbr_surface name="S" type="surfaceshader">\n  <input name="specular_roughness" type="float" value="250" unittype="distance" unit="millimeter" />\n</open_pbr_surface>',
)
THICKNESS_IN_NM = Rule(
    "OPBR605", "thin-film-thickness-nanometres", Severity.WARNING,
    "A thin-film thickness that looks like nanometres in a micrometre input.",
    "Since OpenPBR 0.5 thin_film_thickness is in micrometres (0 to 1 typical: soap bubbles and "
    "oil films are 0.1 to 1 µm). A value like 400 was almost certainly meant as 400 nm = 0.4 µm.",
    passing='<open_pbr_surface name="S" type="surfaceshader">\n  <input name="thin_film_weight" type="float" value="1" />\n  <input name="thin_film_thickness" type="float" value="0.4" />\n</open_pbr_surface>',
    failing='<open_pbr_surface name="S" type="surfaceshader">\n  <input name="thin_film_weight" type="float" value="1" />\n  <input name="thin_film_thickness" type="float" value="400" />\n</open_pbr_surface>',
)

THICKNESS_IN_METRES = Rule(
    "OPBR606", "thin-film-thickness-metres", Severity.WARNING,
    "A thin-film thickness that looks like metres or millimetres in a micrometre input.",
    "A film thinner than a nanometre (0.001 µm, a few atoms) makes no interference colour at all. A value "
    "like 4.5e-07 was almost certainly written in metres (450 nm = 0.45 µm), one like 4.5e-04 in millimetres; "
    "either way the iridescence the author asked for does not appear.",
    passing='<open_pbr_surface name="S" type="surfaceshader">\n  <input name="thin_film_weight" type="float" value="1" />\n  <input name="thin_film_thickness" type="float" value="0.45" />\n</open_pbr_surface>',
    failing='<open_pbr_surface name="S" type="surfaceshader">\n  <input name="thin_film_weight" type="float" value="1" />\n  <input name="thin_film_thickness" type="float" value="4.5e-07" />\n</open_pbr_surface>',
)

RULES = (WRONG_UNITTYPE, UNKNOWN_UNIT, LENGTH_WITHOUT_UNIT, UNIT_IGNORED, UNIT_ON_DIMENSIONLESS, THICKNESS_IN_NM,
         THICKNESS_IN_METRES)

# Above this many micrometres a thin-film thickness is read as nanometres (interference colours
# vanish above a few micrometres; no coating a look-dev artist models is 10 µm thick).
NANOMETRE_SUSPICION_UM = 10.0
NANOMETRE_SUSPICION_KEY = "thin_film_nanometre_suspicion_um"  # the configuration threshold overriding it
# Below this many micrometres (1 nm, a few atoms) a positive thickness is read as metres or millimetres.
METRE_SUSPICION_UM = 1e-3
# Thicknesses that make interference colours (µm): the range a unit guess must land in to be offered.
FILM_RANGE_UM = (0.01, 10.0)


def check(asset, context):
    distance_units = load_json("units.json")["distance"]
    suspicion = context.threshold(NANOMETRE_SUSPICION_KEY, NANOMETRE_SUSPICION_UM)
    for material, table, entry in for_each_input(asset):
        parameter = table.get(entry.name)
        if parameter is None:
            continue
        if parameter.unit == "scene_length":
            if entry.unittype and entry.unittype != "distance":
                yield context.diagnostic(
                    WRONG_UNITTYPE, f"{entry.name} is a length but has unittype={entry.unittype!r}",
                    entry.location, hint="use unittype=\"distance\"",
                )
            elif entry.unit and entry.unit not in distance_units:
                guess = difflib.get_close_matches(entry.unit, list(distance_units), n=1, cutoff=0.5)
                yield context.diagnostic(
                    UNKNOWN_UNIT, f"{entry.name} has unknown distance unit {entry.unit!r}",
                    entry.location, hint=f"did you mean {guess[0]!r}?" if guess else f"known: {', '.join(distance_units)}",
                )
            elif not entry.unit and asset.format == "mtlx" and entry.value is not None and entry.error is None:
                yield context.diagnostic(
                    LENGTH_WITHOUT_UNIT, f"{entry.name} is a length in scene units but has no unit",
                    entry.location, hint="add unittype=\"distance\" unit=\"centimeter\" (or the scene's unit)",
                )
        elif entry.unit or entry.unittype:
            fixed = {"micrometer": "micrometres", "nanometer": "nanometres", "nit": "nits"}.get(parameter.unit or "")
            why = f"is always in {fixed}" if fixed else "has no unit"
            converted = materialx_converted(entry, parameter, asset.format)
            if converted is not None and not fixed and _inside(converted, parameter) and not _inside(entry.constant, parameter):
                yield context.diagnostic(
                    UNIT_ON_DIMENSIONLESS, f"{entry.name} has no unit but is written as {entry.constant:g} {entry.unit}: "
                    f"MaterialX converts it to {converted:g} (metres), renderers without unit conversion read "
                    f"{entry.constant:g}", entry.location, hint=f"author {converted:g} without the unit attribute")
            elif converted is not None:
                yield context.diagnostic(
                    UNIT_IGNORED, f"{entry.name} {why}, but its unit attribute ({entry.unit}) makes MaterialX convert "
                    f"{entry.constant:g} to {converted:g} (metres), and renderers without unit conversion ignore it",
                    entry.location, hint="remove the attribute and author the value in the input's own unit")
            else:
                yield context.diagnostic(
                    UNIT_IGNORED, f"{entry.name} {why}; its unit attribute ({entry.unit or entry.unittype}) is ignored",
                    entry.location, hint="remove the attribute and author the value in the input's own unit",
                )
        if parameter.unit == "micrometer" and isinstance(entry.constant, float) and entry.constant > suspicion:
            yield context.diagnostic(
                THICKNESS_IN_NM,
                f"{entry.name} = {entry.constant:g} µm looks like nanometres ({entry.constant / 1000:g} µm)",
                entry.location, hint=f"did you mean {entry.constant / 1000:g}?",
            )
        elif parameter.unit == "micrometer" and isinstance(entry.constant, float) and 0 < entry.constant < METRE_SUSPICION_UM:
            yield from _thickness_in_metres(entry, context)


def _thickness_in_metres(entry, context):
    """OPBR606 for a positive thickness below a nanometre, with the unit it was most likely written in."""
    guesses = [(unit, entry.constant * factor) for unit, factor in (("metres", 1e6), ("millimetres", 1e3))
               if FILM_RANGE_UM[0] <= entry.constant * factor <= FILM_RANGE_UM[1]]
    meant = f" (as {guesses[0][0]}: {guesses[0][1]:g} µm)" if guesses else ""
    yield context.diagnostic(
        THICKNESS_IN_METRES,
        f"{entry.name} = {entry.constant:g} µm is thinner than a nanometre and makes no interference colour: it looks "
        f"like metres or millimetres{meant}", entry.location,
        hint=f"did you mean {guesses[0][1]:g}?" if guesses else "write the thickness in micrometres (0.1 to 1 typical)",
    )


def materialx_converted(entry, parameter, file_format: str) -> float | None:
    """The value MaterialX's shader generation gives a float input of fixed or no unit that carries
    unittype="distance" and a known distance unit, converted to metres (its viewer's and test suite's target
    distance unit; GlslShaderGenerator emits value * scale); None for anything else (a length input in scene
    units, no or an unknown unit, a non-float value, a format without unit attributes)."""
    if file_format != "mtlx" or entry.unittype != "distance" or parameter.unit == "scene_length":
        return None
    scale = load_json("units.json")["distance"].get(entry.unit or "")
    value = entry.constant
    if scale is None or not isinstance(value, float):
        return None
    return value * scale


def _inside(value, parameter) -> bool:
    """Inside the soft range where there is one, else the hard range."""
    if not isinstance(value, float):
        return True
    low = parameter.soft_min if parameter.soft_min is not None else parameter.hard_min
    high = parameter.soft_max if parameter.soft_max is not None else parameter.hard_max
    return not ((low is not None and value < low) or (high is not None and value > high))
