"""usd-core's own validators (``UsdValidation``), run over a composed stage.

The MaterialX node definitions the stage uses are registered in Sdr first (:mod:`.sdr`), so known
MaterialX shaders raise no "not found in sdrRegistry" error; a validator that breaks is one
warning, never an unreadable stage.
"""

from __future__ import annotations

from .errors import quiet, tf_error_text, usd_error_message
from .sdr import register_materialx_nodes


def usd_core_findings(stage) -> list[dict]:
    """usd-core's ``UsdValidation`` results for ``stage`` (every registered validator), with the
    MaterialX node definitions the stage uses registered in Sdr first so that known MaterialX
    shaders raise no "not found in sdrRegistry" errors. Each finding is a dict: ``identifier``,
    ``name``, ``severity`` (``error``/``warning``/``info``), ``message``, ``sites`` (paths)."""
    from pxr import Sdr, Usd, UsdShade, UsdValidation  # lazy: pxr (0.1-0.2 s) only once a stage has been opened

    ids = set()
    # every shader the validators visit: also under class prims and in the prototypes of instances
    for prim in stage.Traverse(Usd.TraverseInstanceProxies(Usd.PrimAllPrimsPredicate)):
        if prim.IsA(UsdShade.Shader):
            shader_id = UsdShade.Shader(prim).GetShaderId()
            if shader_id:
                ids.add(str(shader_id))
    from pxr import Tf  # lazy: as above

    try:
        register_materialx_nodes(ids)
        context = UsdValidation.ValidationContext(_all_validators())
        with quiet():
            errors = context.Validate(stage)
    except Tf.ErrorException as error:  # a validator that breaks must not make the stage unreadable
        message, _ = usd_error_message(tf_error_text(error), "")
        return [{"identifier": "usdValidation", "name": "ValidatorFailed", "severity": "warning",
                 "message": f"usd-core's validators failed: {message}", "sites": []}]
    findings = []
    for error in errors:
        kind = str(error.GetType()).rsplit(".", 1)[-1].lower()
        try:
            sites = [str(site.GetProperty().GetPath()) if site.IsProperty() else str(site.GetPrim().GetPath())
                     for site in error.GetSites() if site.IsProperty() or site.IsPrim()]
            message = str(error.GetMessage())
        except UnicodeDecodeError:  # a name or value from a crate file that is not UTF-8
            sites, message = [], "(a message quoting text that is not valid UTF-8)"
        finding = {
            "identifier": str(error.GetIdentifier()),
            "name": str(error.GetName()),
            "severity": {"error": "error", "warn": "warning", "info": "info"}.get(kind, "warning"),
            "message": message,
            "sites": sites,
        }
        if finding["name"] == "InvalidFamilyType" and sites:
            finding["authored"] = _family_type_authored(stage, sites[0])
        if finding["name"] == "MissingSourceTypeInRegistry":  # a fact of this machine: no parser plugin for the type
            finding["parsed_source_types"] = sorted(str(t) for t in Sdr.Registry().GetAllShaderNodeSourceTypes())
        findings.append(finding)
    return findings


def _family_type_authored(stage, prim_path: str) -> bool:
    """Whether the prim authors its materialBind family's type (``subsetFamily:materialBind:familyType``): an
    unauthored one reads as 'unrestricted' (UsdGeomSubset's fallback) though UsdShade documents materialBind
    subsets as nonOverlapping by default; an authored 'unrestricted' is a declaration no UsdShade API makes
    (SetMaterialBindSubsetsFamilyType refuses it)."""
    prim = stage.GetPrimAtPath(prim_path)
    attribute = prim.GetAttribute("subsetFamily:materialBind:familyType") if prim else None
    return bool(attribute and attribute.HasAuthoredValue())


def _all_validators():
    from pxr import UsdValidation  # lazy: as in usd_core_findings

    return UsdValidation.ValidationRegistry().GetOrLoadAllValidators()
