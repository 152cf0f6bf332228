"""USD stage: what the stage as a whole is read by, before any material: its unit and the layers it composes.

- ``metersPerUnit`` (UsdGeom's linear units) is the length of a scene unit in metres, by which every length in scene
  units is read (geometry, ``transmission_depth``, ``subsurface_radius``): 0, a negative, infinite or NaN unit makes
  them meaningless (OPBR1041). usd-core opens such a stage without a word.
- A sublayer, reference or payload that cannot be found: usd-core composes the rest of the stage and reports a
  composition error, and whatever the missing layer held (materials, bindings, opinions) is missing from every
  renderer (OPBR1042). The rest of the stage is checked as composed (the red team's F#7: the whole file was refused
  as unreadable, exit 2, and a root layer's own out-of-range roughness went unreported).
"""

from __future__ import annotations

import math

from ..diagnostics import Severity
from ..model import Location
from . import Rule
from .usd_shading import _stage

STAGE_UNITS = Rule(
    "OPBR1041", "usd-meters-per-unit-invalid", Severity.ERROR,
    "The stage's metersPerUnit is not a positive number of metres (0, negative, infinite or NaN).",
    "UsdGeom's linear units: metersPerUnit is the length of one scene unit in metres, by which every length in "
    "scene units (geometry, a transmission depth, a subsurface radius) is read; 0 or a negative unit makes them all "
    "meaningless, and a converter dividing by it fails or writes nonsense. usd-core opens the stage without a word "
    "(its StageMetadataChecker asks only that the value is authored). Author the unit meant: 0.01 for centimetres, 1 "
    "for metres.",
    passing=_stage(inputs="        float inputs:transmission_depth = 2.5\n"),
    failing=_stage(inputs="        float inputs:transmission_depth = 2.5\n").replace("metersPerUnit = 1", "metersPerUnit = 0", 1),
    passing_name="example.usda", failing_name="example.usda", formats=("usd",),
)

LAYER_MISSING = Rule(
    "OPBR1042", "usd-layer-missing", Severity.ERROR,
    "A sublayer, reference or payload the stage composes cannot be found.",
    "usd-core composes the rest of the stage and reports a composition error (ErrorInvalidSublayerPath, "
    "ErrorInvalidAssetPath): whatever the missing layer held (its materials, bindings and opinions) is missing from "
    "every renderer, and the stage renders otherwise than authored. Ship the layer with the asset, or remove the arc.",
    passing=_stage(inputs="        float inputs:specular_roughness = 0.5\n"),
    failing=_stage(inputs="        float inputs:specular_roughness = 0.5\n").replace(
        "    metersPerUnit = 1\n", "    metersPerUnit = 1\n    subLayers = [@missing_looks.usda@]\n", 1),
    passing_name="example.usda", failing_name="example.usda", formats=("usd",),
)

RULES = (STAGE_UNITS, LAYER_MISSING)


def check(asset, context):
    """Runs on USD assets only (rules.FAMILY_FORMATS)."""
    unit = asset.meters_per_unit
    if unit is not None and not (math.isfinite(unit) and unit > 0):
        yield context.diagnostic(
            STAGE_UNITS, f"metersPerUnit = {unit:g} is not a length in metres: every length in scene units "
            "(geometry, transmission_depth, subsurface_radius) is meaningless", Location(asset.path, None, "/", None),
            hint="author the unit meant in the root layer's metadata: metersPerUnit = 0.01 (centimetres) or 1 (metres)")
    for observation in asset.observations:
        if observation.kind == "usd_layer_missing":
            yield context.diagnostic(
                LAYER_MISSING, f"a layer the stage composes cannot be found: {observation.detail['reason']}; USD "
                "composes the rest without it", observation.location,
                hint="ship the layer with the asset (a path relative to the layer that names it), or remove the arc")
