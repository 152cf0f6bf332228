"""usd-core plumbing shared by the USD reader and writer: opening a stage without noise, teaching
Sdr the MaterialX node definitions, and asking usd-core's own validators.

``pxr`` is imported inside the functions only (``from pxr import Usd`` costs 0.2-0.5 s).

usd-core on PyPI has no MaterialX plug-in, so its shader registry (Sdr) does not know
``ND_open_pbr_surface_surfaceshader`` and its ``ShaderSdrCompliance`` validator reports every
MaterialX shader as "not found in sdrRegistry". :func:`register_materialx_nodes` fills that gap: it
describes each MaterialX node definition as a USD shader definition (inputs typed as UsdMtlx types
them) in an in-memory layer and hands it to Sdr through UsdShade's own shader-definition parser,
the same route usd-core uses for ``UsdPreviewSurface``.
"""

from __future__ import annotations

import os
import re
from contextlib import contextmanager
from functools import lru_cache

from ..model import Location
from . import ReadError
from .usd_types import MATERIALX_TO_USD

# Pcp errors that mean "a layer of this stage could not be opened".
_MISSING_LAYER_ERRORS = ("ErrorInvalidSublayerPath", "ErrorInvalidAssetPath", "ErrorInvalidExternalTargetPath")
_TF_MESSAGE = re.compile(r"Error in '[^']*' at line \d+ in file [^\n]*? : '(.*?)'\s*(?=\n\s*Error in |\Z)", re.DOTALL)
_TEXT_POSITION = re.compile(r":(\d+):(\d+): ")


def require_pxr(path: str = "") -> None:
    """Import usd-core, or say how to install it."""
    try:
        from pxr import Usd  # noqa: F401
    except ImportError:
        raise ReadError(
            "unsupported", "reading or writing USD needs usd-core: pip install usd-core", Location(path)
        ) from None


@contextmanager
def quiet():
    """Capture usd-core's warnings and errors (which it otherwise prints to stderr) for the block;
    yields the list they are collected into."""
    from pxr import Tf

    collected: list[str] = []
    with Tf.DiagnosticTrap() as trap:
        try:
            yield collected
        finally:
            collected.extend(str(w.commentary) for w in trap.GetWarnings())
            collected.extend(str(e.commentary) for e in trap.GetErrors())
            trap.Clear()


def open_stage(path: str):
    """Open ``path`` with composition resolved (payloads loaded, variants as authored).

    Raises :class:`ReadError`: ``unreadable`` when the file cannot be read, ``not_usd`` when usd-core
    cannot parse it (the message carries usd-core's own reason, and the line for ``.usda``) or when
    a layer it needs (sublayer, reference, payload) cannot be opened.
    """
    require_pxr(path)
    from pxr import Tf, Usd

    import stat

    try:
        info = os.stat(path)
    except OSError as error:
        raise ReadError("unreadable", f"cannot read file: {error.strerror or error}", Location(path)) from None
    if not stat.S_ISREG(info.st_mode):  # a folder, or a FIFO/device that would block or never end
        raise ReadError("unreadable", "not a regular file", Location(path))
    if not os.access(path, os.R_OK):
        raise ReadError("unreadable", "cannot read file: permission denied", Location(path))
    if path.lower().endswith(".usdz"):
        problem = _package_problem(path)
        if problem:
            raise ReadError("not_usd", problem, Location(path))
    with quiet():
        try:
            stage = Usd.Stage.Open(path, Usd.Stage.LoadAll)
        except Tf.ErrorException as error:
            message, line = usd_error_message(str(error), path)
            raise ReadError("not_usd", f"USD cannot open the file: {message}", Location(path, line)) from None
        if stage is None:
            raise ReadError("not_usd", "USD cannot open the file", Location(path))
        missing = [e for e in stage.GetCompositionErrors() if type(e).__name__ in _MISSING_LAYER_ERRORS]
    if missing:
        reasons = "; ".join(sorted({_strip_stage_suffix(str(e)) for e in missing}))
        raise ReadError("not_usd", f"a layer the stage needs cannot be opened: {reasons}", Location(path))
    return stage


def usd_error_message(text: str, path: str) -> tuple[str, int | None]:
    """The most specific message in a Tf error report, and the line it names in ``path``."""
    messages = [" ".join(m.split()) for m in _TF_MESSAGE.findall(text.strip())]
    message = messages[0] if messages else (text.strip().splitlines() or ["unknown error"])[-1]
    line = None
    if message.startswith(path):
        position = _TEXT_POSITION.match(message[len(path):])
        if position:
            line = int(position.group(1))
            message = message[len(path) + position.end():]
    message = message.replace(f"layer @{path}@", "the file").replace(f"@{path}@", "the file")
    return message.strip(), line


def _package_problem(path: str) -> str | None:
    """Why a ``.usdz`` cannot be a package (usd-core only says it failed to open), or ``None``."""
    import zipfile

    try:
        with zipfile.ZipFile(path) as package:
            names = package.namelist()
    except (OSError, zipfile.BadZipFile) as error:
        return f"not a USDZ package (a zip archive): {error}"
    if not names or not names[0].lower().endswith((".usd", ".usda", ".usdc")):
        return "the package's first file is not a USD layer (a USDZ's root layer must come first)"
    return None


def _strip_stage_suffix(message: str) -> str:
    return re.sub(r"\s*\(instantiating stage on stage @[^@]*@ <[^>]*>\)$", "", message).strip()


# -- Sdr ----------------------------------------------------------------------------------------

_registered: set[str] = set()
_definition_layers: list = []  # Sdr parses lazily: the in-memory layers must stay alive


@lru_cache(maxsize=1)
def _materialx_nodedefs():
    """Name -> nodedef for MaterialX's libraries plus the toolkit's legacy OpenPBR definitions."""
    import MaterialX as mx

    from .mtlx_reader import standard_library

    found = {nd.getName(): nd for nd in standard_library().getNodeDefs()}
    try:
        from ..resources import data_dir

        legacy = data_dir("libraries")
        for name in sorted(os.listdir(legacy)):
            if name.endswith(".mtlx"):
                document = mx.createDocument()
                mx.readFromXmlFile(document, str(legacy / name))
                for nodedef in document.getNodeDefs():
                    found.setdefault(nodedef.getName(), nodedef)
    except (FileNotFoundError, OSError):
        pass
    return found


def materialx_nodedef_names() -> list[str]:
    return sorted(_materialx_nodedefs())


def materialx_nodedef(name: str):
    """The MaterialX node definition called ``name`` (standard libraries or the toolkit's legacy
    OpenPBR definitions), or ``None``."""
    return _materialx_nodedefs().get(name)


def register_materialx_nodes(ids) -> list[str]:
    """Make Sdr know the MaterialX node definitions among ``ids``; returns the ids registered now.

    Ids that are not MaterialX node definitions, and ids Sdr already knows (from an earlier call,
    or from a usd build that has the MaterialX plug-in), are left alone.
    """
    from pxr import Sdf, Sdr

    registry = Sdr.Registry()
    wanted = []
    for shader_id in sorted(set(ids) - _registered):
        nodedef = materialx_nodedef(shader_id)
        _registered.add(shader_id)
        if nodedef is None:
            continue
        with quiet():
            known = registry.GetShaderNodeByIdentifier(shader_id)
        if not known:
            wanted.append(nodedef)
    if not wanted:
        return []
    layer = Sdf.Layer.CreateAnonymous("openpbr_tools_materialx_defs.usda")
    for nodedef in wanted:
        _define_shader(layer, nodedef)
    _definition_layers.append(layer)
    for nodedef in wanted:
        result = Sdr.NodeDiscoveryResult(
            nodedef.getName(), Sdr.Version(1).GetAsDefault(), nodedef.getName(), nodedef.getNodeString(),
            "usda", "mtlx", layer.identifier, layer.identifier,
        )
        registry.AddDiscoveryResult(result)
    return [nd.getName() for nd in wanted]


def _define_shader(layer, nodedef) -> None:
    from pxr import Sdf

    prim = Sdf.PrimSpec(layer, nodedef.getName(), Sdf.SpecifierDef, "Shader")
    uniform = Sdf.VariabilityUniform

    def attribute(name: str, type_name, value=None, variability=Sdf.VariabilityVarying):
        spec = Sdf.AttributeSpec(prim, name, type_name, variability)
        if value is not None:
            spec.default = value
        return spec

    attribute("info:id", Sdf.ValueTypeNames.Token, nodedef.getName(), uniform)
    attribute("info:implementationSource", Sdf.ValueTypeNames.Token, "sourceAsset", uniform)
    attribute("info:mtlx:sourceAsset", Sdf.ValueTypeNames.Asset,
              Sdf.AssetPath(nodedef.getSourceUri() or os.devnull), uniform)
    for port in nodedef.getActiveInputs():
        usd_type = MATERIALX_TO_USD.get(port.getType(), "token")
        name = port.getName().replace(":", "__")
        attribute(f"inputs:{name}", Sdf.ValueTypeNames.Find(usd_type),
                  variability=uniform if port.getIsUniform() else Sdf.VariabilityVarying)
    for port in nodedef.getActiveOutputs():
        usd_type = MATERIALX_TO_USD.get(port.getType(), "token")
        attribute(f"outputs:{port.getName()}", Sdf.ValueTypeNames.Find(usd_type))


# -- usd-core's validators ------------------------------------------------------------------------

def usd_core_findings(stage) -> list[dict]:
    """usd-core's ``UsdValidation`` results for ``stage`` (every registered validator), with the
    MaterialX node definitions the stage uses registered in Sdr first so that known MaterialX
    shaders raise no "not found in sdrRegistry" errors. Each finding is a dict: ``identifier``,
    ``name``, ``severity`` (``error``/``warning``/``info``), ``message``, ``sites`` (paths)."""
    from pxr import UsdShade, UsdValidation

    ids = set()
    for prim in stage.Traverse():
        if prim.IsA(UsdShade.Shader):
            shader_id = UsdShade.Shader(prim).GetShaderId()
            if shader_id:
                ids.add(str(shader_id))
    from pxr import Tf

    try:
        register_materialx_nodes(ids)
        context = UsdValidation.ValidationContext(_all_validators())
        with quiet():
            errors = context.Validate(stage)
    except Tf.ErrorException as error:  # a validator that breaks must not make the stage unreadable
        message, _ = usd_error_message(str(error), "")
        return [{"identifier": "usdValidation", "name": "ValidatorFailed", "severity": "warning",
                 "message": f"usd-core's validators failed: {message}", "sites": []}]
    findings = []
    for error in errors:
        kind = str(error.GetType()).rsplit(".", 1)[-1].lower()
        sites = []
        for site in error.GetSites():
            if site.IsProperty():
                sites.append(str(site.GetProperty().GetPath()))
            elif site.IsPrim():
                sites.append(str(site.GetPrim().GetPath()))
        findings.append({
            "identifier": str(error.GetIdentifier()),
            "name": str(error.GetName()),
            "severity": {"error": "error", "warn": "warning", "info": "info"}.get(kind, "warning"),
            "message": str(error.GetMessage()),
            "sites": sites,
        })
    return findings


def _all_validators():
    from pxr import UsdValidation

    return UsdValidation.ValidationRegistry().GetOrLoadAllValidators()
