"""Opening a USD stage without trusting it: :class:`StageGuard`.

usd-core is not hardened against hostile files, so :class:`StageGuard` checks every layer before usd-core parses
it and every arc before usd-core follows it (limits below, all refusals are read errors, exit code 2):

* size: a stage file (and every layer it composes) above ``OPENPBR_MAX_FILE_MB`` (64 MiB) is not
  read; a USDZ whose entries declare more than that uncompressed is refused (a zip bomb);
* text layers: brackets nested deeper than :data:`~.text_layer.MAX_TEXT_NESTING` (1,000), outside
  strings, asset paths and comments, are refused: usd-core's parser would overflow the stack and
  crash (:mod:`.text_layer`);
* crate layers: every count and size in the table of contents and the structural sections must fit
  the section holding it (:func:`~.crate.crate_problem`): usd-core allocates what a file declares first;
* packages: read as usd-core reads them (local file headers, :mod:`.package`); more than
  :data:`~.package.MAX_PACKAGE_ENTRIES` entries, or a stored entry declaring a size it does not
  store, is refused; entry names that are absolute or climb out, and compressed entries, are reported;
* composition: at most :data:`MAX_LAYERS` layers; sublayers, references and payloads that are URLs, absolute
  paths, variable expressions or that climb (``..``, a symbolic link, the resolver's search path) out of the
  asset's folder are deleted from the in-memory layers before usd-core composes the stage, and reported (a '..'
  to a layer that is there as a shared folder): a file outside the folder is never opened. Value clips are
  always deleted (usd-core opens them lazily from anywhere, and enumerates a template's files).

What a reference is (URL, drive, UNC, absolute, NUL) and whether a path is inside the asset's folder (or an
allowed one) is decided by :mod:`openpbr_tools.io.paths`, nowhere else. ``pxr`` is imported inside the functions
only (``from pxr import Usd`` costs 0.2-0.5 s).
"""

from __future__ import annotations

import os
import re
import stat

from ...model import Location
from .. import ReadError, read_bytes
from ..paths import Kind, PathGuard, classify, climbs
from .crate import CRATE_MAGIC, crate_problem, crate_tokens
from .errors import quiet, require_pxr, strip_stage_suffix, tf_error_text, usd_error_message
from .package import ZIP_MAGIC, disallowed_entry_type, package_entries, read_layer_bytes, unsafe_entry_name
from .text_layer import text_nesting_problem

# Pcp errors that mean "a layer of this stage could not be opened".
_MISSING_LAYER_ERRORS = ("ErrorInvalidSublayerPath", "ErrorInvalidAssetPath", "ErrorInvalidExternalTargetPath")
#: At most this many layers (sublayers, references, payloads, followed recursively) per stage.
MAX_LAYERS = 1000
_LAYER_SUFFIXES = (".usd", ".usda", ".usdc")
_CLIMBS = "climbs out of the asset's folder with '..'"


class StageGuard:
    """Opens one stage for reading: judges every layer before usd-core parses it and every arc
    before usd-core follows it.

    ``observe(kind, location, **detail)`` receives ``usd_arc_outside`` (a sublayer, reference,
    payload or value clip pointing outside the asset's folder: deleted before composition, so never
    opened), ``usd_mtlx_reference`` (an arc to a ``.mtlx`` document this usd-core cannot open) and
    ``usd_package_entry`` (a USDZ entry with an unsafe name, or compressed).
    ``allow_outside`` lists folders arcs may point into besides the asset's own. Layers are edited
    in memory only; a layer already open elsewhere in the process is never edited (the stage is
    refused instead), and the edited ones die with the stage.
    """

    def __init__(self, path: str, observe, allow_outside=()):
        self.shown = path  # as the caller named it: diagnostics say it that way
        self.path = os.path.abspath(path)
        self.observe = observe
        # where arcs may lead: the asset's folder and the allowed ones, symbolic links resolved
        self.paths = PathGuard.for_asset(self.path, allow_outside)
        # how diagnostics name a file: relative to the stage when it lies in the stage's folder as
        # written (no symbolic link resolved: a name, not a permission)
        self.names = PathGuard.for_asset(self.path, real_path=os.path.normpath)
        self.layers: dict[str, object] = {}  # identifier -> layer: held until composition is done
        self.root_identifier = ""
        self.preexisting: set[str] = set()
        self.without_clips: set[str] = set()  # layers whose text or token table cannot hold value clips
        self.crate_layers: set[str] = set()
        self.package_files: frozenset[str] = frozenset()

    def open_stage(self):
        """The composed stage (payloads loaded, variants as authored); raises :class:`ReadError`."""
        require_pxr(self.path)
        from pxr import Tf, Usd  # lazy: pxr (0.1-0.2 s) loads once require_pxr has found it

        _regular_file(self.path)
        with quiet():
            try:
                self.check_bytes(self.path, read_bytes(self.path), self.path)
                root = self.open_layer(self.path)
                if root is None:
                    raise ReadError("not_usd", "USD cannot open the file", self.where(self.path))
                self.root_identifier = root.identifier
                self.follow(root)
                stage = Usd.Stage.Open(root, Usd.Stage.LoadAll)
            except Tf.ErrorException as error:
                message, line = usd_error_message(tf_error_text(error), self.path)
                raise ReadError("not_usd", f"USD cannot open the file: {message}", self.where(self.path, line)) from None
            except UnicodeDecodeError:  # an asset path or name in a crate file that is not UTF-8
                raise ReadError("not_usd", "the stage holds names or paths that are not valid UTF-8",
                                self.where(self.path)) from None
            if stage is None:
                raise ReadError("not_usd", "USD cannot open the file", self.where(self.path))
            missing = [e for e in stage.GetCompositionErrors() if type(e).__name__ in _MISSING_LAYER_ERRORS]
        self.layers.clear()
        for reason in sorted({strip_stage_suffix(str(e)) for e in missing}):  # (USD composes the rest: rules.usd_stage)
            layer = re.search(r"@([^@]+)@", reason)
            self.observe("usd_layer_missing", self.where(self.path), reason=reason, layer=layer.group(1) if layer else None)
        return stage

    def where(self, file: str, line: int | None = None, prim: str | None = None) -> Location:
        """A location in ``file`` (absolute), named relative to the stage as the caller named it."""
        if file != self.path:
            inside = self.names.resolve(os.path.abspath(file)).relative
            if inside is not None:
                file = os.path.join(os.path.dirname(self.shown), inside.replace("/", os.sep))
        return Location(self.shown if file == self.path else file, line, prim)

    # -- layers --------------------------------------------------------------------------------
    def open_layer(self, identifier: str):
        from pxr import Sdf  # lazy: pxr only once open_stage has required it

        if Sdf.Layer.Find(identifier):
            self.preexisting.add(identifier)
        return Sdf.Layer.FindOrOpen(identifier)

    def check_bytes(self, identifier: str, data: bytes, file: str) -> None:
        """Refuse a layer whose bytes would crash usd-core; note unsafe package entries."""
        if data.startswith(b"PK") or (identifier == self.path and identifier.lower().endswith(".usdz")):
            data = self.check_package(data, file)
        if data.startswith(CRATE_MAGIC):
            problem = crate_problem(data)
            if problem:
                raise ReadError("not_usd", f"USD cannot open the file safely (refused before parsing): a corrupt crate "
                                f"file: {problem}", self.where(file))
            self.crate_layers.add(identifier)
            tokens = crate_tokens(data)
            if tokens is not None and b"clips" not in tokens:
                self.without_clips.add(identifier)
            return
        problem = text_nesting_problem(data)
        if problem:
            raise ReadError("not_usd", f"USD cannot open the file safely (refused before parsing): {problem[0]}",
                            self.where(file, problem[1]))
        if b"clips" not in data:
            self.without_clips.add(identifier)

    def check_package(self, data: bytes, file: str) -> bytes:
        """Check a USDZ; returns its root layer's bytes."""
        if not data.startswith(ZIP_MAGIC) and not data.startswith(b"PK\x05\x06"):
            raise ReadError("not_usd", "not a USDZ package (a zip archive)", self.where(file))
        try:
            entries = package_entries(data)
        except ValueError as error:
            raise ReadError("not_usd", f"not a usable USDZ package: {error}", self.where(file)) from None
        if not entries or not entries[0].name.lower().endswith(_LAYER_SUFFIXES):
            raise ReadError("not_usd", "the package's first file is not a USD layer (a USDZ's root layer must come "
                            "first)", self.where(file))
        for entry in entries:
            reason = unsafe_entry_name(entry.name) or (
                "is compressed (USDZ entries must be stored uncompressed)" if entry.method != 0 else None)
            if reason:
                self.observe("usd_package_entry", self.where(file), entry=entry.name, reason=reason)
            elif (reason := disallowed_entry_type(entry.name)) is not None:
                self.observe("usd_package_entry", self.where(file), entry=entry.name, reason=reason, file_type=True)
        if file == self.path and not self.package_files:  # the root package (checked first; a nested one
            self.package_files = frozenset(_member_names(entries))  # opened later is listed inside it)
        return bytes(entries[0].data) if entries[0].method == 0 else CRATE_MAGIC  # compressed: usd-core cannot read it

    def follow(self, root) -> None:
        """Walk the layers ``root`` depends on, deleting the arcs and value clips that must not be
        followed and opening (after checking) the others, so usd-core finds them already open."""
        from pxr import Tf  # lazy: pxr only once open_stage has required it

        queue = [root]
        self.layers[root.identifier] = root
        while queue:
            layer = queue.pop()
            if layer.identifier in self.crate_layers and _prim_paths(layer, verify=True) is None:
                raise ReadError("not_usd", "USD cannot open the file safely: a corrupt crate file lists a prim or "
                                "property it does not hold (usd-core would abort)", self.where(self.layer_file(layer)))
            if layer.identifier not in self.without_clips:
                self.drop_value_clips(layer)
            for asset_path in layer.GetCompositionAssetDependencies():
                reason = self.outside(layer, asset_path)
                if reason:
                    self.refuse(layer, asset_path, reason)
                    continue
                if asset_path.lower().endswith(".mtlx") and not _reads_materialx():
                    self.mtlx_reference(layer, asset_path)
                    continue
                identifier = layer.ComputeAbsolutePath(asset_path)
                resolved = _resolve(identifier)
                if identifier in self.layers or not resolved:
                    continue  # a missing layer is reported by composition, in usd-core's words
                if len(self.layers) >= MAX_LAYERS:
                    raise ReadError("not_usd", f"the stage needs more than {MAX_LAYERS} layers", self.where(self.path))
                self.check_bytes(identifier, read_layer_bytes(resolved), _file_of(resolved))
                try:
                    found = self.open_layer(identifier)
                except Tf.ErrorException:  # composition reports the broken layer, in usd-core's words
                    found = None
                if found is not None:
                    for judged in (self.crate_layers, self.without_clips):  # keyed as usd-core names it
                        if identifier in judged:
                            judged.add(found.identifier)
                    self.layers[identifier] = found
                    queue.append(found)

    def outside(self, layer, asset_path: str) -> str | None:
        """Why ``asset_path`` (an arc of ``layer``) must not be followed, or ``None``."""
        from pxr import Ar  # lazy: pxr only once open_stage has required it

        kind = classify(asset_path)
        if kind is Kind.NUL:
            return "is not a path (it holds a NUL byte)"
        if asset_path.startswith("`"):
            return "is a variable expression (where it leads is only known once evaluated)"
        if kind is Kind.URL:
            return "is a URL"
        if kind in (Kind.ABSOLUTE, Kind.DRIVE, Kind.UNC):
            return "is an absolute path"
        identifier = layer.ComputeAbsolutePath(asset_path)
        if Ar.IsPackageRelativePath(identifier):
            outer, inner = Ar.SplitPackageRelativePathOuter(identifier)
            if climbs(os.path.normpath(inner)):
                return "climbs out of its package with '..'"
            return None if self.paths.contains(outer) else "leads out of the asset's folder"
        if classify(identifier) in (Kind.ABSOLUTE, Kind.DRIVE, Kind.UNC):
            # where usd-core anchored it, before any symbolic link is followed
            if self.paths.root_of(os.path.normpath(identifier)) is None:
                return _CLIMBS
        elif climbs(os.path.normpath(identifier)):
            return "climbs out with '..'"  # usd-core would look it up from the working folder
        resolved = _resolve(identifier)
        if resolved and not self.paths.contains(resolved):
            return "leads out of the asset's folder (through a symbolic link or the resolver's search path)"
        return None

    def editable(self, layer):
        if layer.identifier in self.preexisting:
            raise ReadError("unreadable", f"{_file_of(layer.identifier)} is already open in this process and would have "
                            "to be changed to read it safely", self.where(self.path))
        return layer

    def layer_file(self, layer) -> str:
        return self.path if layer.identifier == self.root_identifier else _file_of(layer.identifier)

    def refuse(self, layer, asset_path: str, reason: str) -> None:
        file = self.layer_file(layer)
        shared = reason == _CLIMBS and os.path.isfile(os.path.normpath(layer.ComputeAbsolutePath(asset_path)))  # a stat
        if asset_path in layer.subLayerPaths:
            self.observe("usd_arc_outside", self.where(file), arc="sublayer", asset=asset_path, reason=reason,
                         shared=shared, layer=layer.identifier, spec=None)
        for prim_path, arc in _arcs_to(layer, asset_path):
            self.observe("usd_arc_outside", self.where(file, None, prim_path), arc=arc, asset=asset_path, reason=reason,
                         shared=shared, layer=layer.identifier, spec=prim_path)
        self.editable(layer).UpdateCompositionAssetDependency(asset_path, "")

    def mtlx_reference(self, layer, asset_path: str) -> None:
        """An arc to a MaterialX document (UsdMtlx) that this usd-core cannot open (PyPI's usd-core has
        no usdMtlx plugin): noted (``usd_mtlx_reference``, with the ``document``'s path, named as the stage is) and
        deleted in memory, so the rest of the stage composes; the document is MaterialX, validated with
        the stage (:func:`openpbr_tools.validate.validate_file`). A document that does not exist fails
        the stage as a missing layer does."""
        file = self.layer_file(layer)
        target = os.path.normpath(os.path.join(os.path.dirname(file), asset_path))
        arcs = ([(None, "sublayer")] if asset_path in layer.subLayerPaths else []) + list(_arcs_to(layer, asset_path))
        # a document inside a package is no file on disk: neither checked nor validated here
        packaged = "[" in layer.identifier or self.path.lower().endswith(".usdz") or file.lower().endswith(".usdz")
        exists = packaged or os.path.isfile(target)
        # only an arc the stage composes fails it (usd-core only warns about one inside a variant it does not select)
        if not exists and any(path is None or "{" not in path for path, _ in arcs):
            # as a missing .usda layer does (usd-core would fail to compose it with the usdMtlx plugin too)
            where = ", ".join(f"{arc} of <{prim_path}>" if prim_path else arc for prim_path, arc in arcs)
            raise ReadError("not_usd", f"a layer the stage needs cannot be opened: the MaterialX document "
                            f"@{asset_path}@ ({where or 'composition arc'}) does not exist", self.where(file))
        for prim_path, arc in arcs:
            namespace = _VARIANT_SELECTION.sub("/", prim_path) if prim_path else None  # /World{look=a}M: /World/M
            self.observe("usd_mtlx_reference", self.where(file, None, namespace), arc=arc, asset=asset_path,
                         document=self.where(target).file if exists and not packaged else None,
                         layer=layer.identifier, spec=prim_path)  # (the prim spec that held the arc, for bindings)
        self.editable(layer).UpdateCompositionAssetDependency(asset_path, "")

    def drop_value_clips(self, layer) -> None:
        """Delete every value clip: clips hold animation, not materials, usd-core opens their
        layers lazily from anywhere, and a template can name millions of files (all enumerated)."""
        for spec in [spec for spec in _prim_specs(layer) if spec.HasInfo("clips")]:
            clips = spec.GetInfo("clips")
            for clip_set in (clips.values() if isinstance(clips, dict) else ()):
                template = clip_set.get("templateAssetPath") if isinstance(clip_set, dict) else None
                for asset_path in _clip_asset_paths(clip_set):
                    reason = self.outside(layer, asset_path)
                    where = self.where(self.layer_file(layer), None, str(spec.path))
                    if reason:
                        self.observe("usd_arc_outside", where, arc="value clip", asset=asset_path, reason=reason)
                    elif asset_path != template and "[" not in layer.identifier and not os.path.isfile(
                            layer.ComputeAbsolutePath(asset_path)):
                        # (a published clip layer left behind: usd-core composes the prim without its values)
                        self.observe("dangling_reference", where, attribute="value clip", target=asset_path,
                                     ends="does not exist: usd-core composes the prim without the clip's values")
            self.editable(layer)
            spec.ClearInfo("clips")


def _reads_materialx() -> bool:
    """Whether this usd-core can open ``.mtlx`` layers (built with the usdMtlx plugin)."""
    from pxr import Sdf  # lazy: pxr only once open_stage has required it

    return Sdf.FileFormat.FindByExtension("mtlx") is not None


def _resolve(identifier: str) -> str:
    from pxr import Ar  # lazy: pxr only once open_stage has required it

    return str(Ar.GetResolver().Resolve(identifier) or "")


def _regular_file(path: str):
    try:
        info = os.stat(path)
    except OSError as error:
        raise ReadError("unreadable", f"cannot read file: {error.strerror or error}", Location(path)) from None
    if not stat.S_ISREG(info.st_mode):  # a folder, or a FIFO/device that would block or never end
        raise ReadError("unreadable", "not a regular file", Location(path))
    if not os.access(path, os.R_OK):
        raise ReadError("unreadable", "cannot read file: permission denied", Location(path))
    return info


def _file_of(identifier: str) -> str:
    from pxr import Ar  # lazy: pxr only once open_stage has required it

    return Ar.SplitPackageRelativePathOuter(identifier)[0] if Ar.IsPackageRelativePath(identifier) else identifier


def _prim_paths(layer, *, verify: bool = False) -> list | None:
    """The paths of every prim spec of ``layer`` (variants included). With ``verify``, ``None`` when
    the layer lists a prim it does not hold (a corrupt crate file): asking usd-core about such a
    layer (its composition dependencies) dereferences the missing spec and aborts the process.
    ``Sdf.Layer.Traverse`` and ``GetPrimAtPath`` (which checks the spec's type) only look the data up,
    so they are safe; ``GetObjectAtPath`` is not (a property whose spec type is corrupt crashes it)."""
    paths, missing = [], []

    def visit(path) -> None:
        if path.isEmpty or verify and path.IsPrimPath() and not layer.GetPrimAtPath(path):
            missing.append(path)
        elif path.IsPrimPath() or path.IsPrimVariantSelectionPath():
            paths.append(path)

    from pxr import Sdf  # lazy: pxr only once open_stage has required it

    layer.Traverse(Sdf.Path.absoluteRootPath, visit)
    return None if missing else paths


def _prim_specs(layer):
    """Every prim spec of ``layer``, variants' included."""
    for path in _prim_paths(layer) or ():
        spec = layer.GetPrimAtPath(path)  # a variant's prim spec for a variant path; None for a variant set
        if spec:
            yield spec


_VARIANT_SELECTION = re.compile(r"\{[^}]*\}")


def _arcs_to(layer, asset_path: str):
    """(prim path, "reference"/"payload") for every arc of ``layer`` naming ``asset_path``."""
    for spec in _prim_specs(layer):
        for arc, items in (("reference", spec.referenceList), ("payload", spec.payloadList)):
            names = {item.assetPath for kind in ("explicitItems", "addedItems", "prependedItems", "appendedItems",
                                                  "orderedItems", "deletedItems") for item in getattr(items, kind)}
            if asset_path in names:
                yield str(spec.path), arc


def _clip_asset_paths(clip_set) -> list[str]:
    if not isinstance(clip_set, dict):
        return []
    found = [getattr(a, "path", str(a)) for a in clip_set.get("assetPaths", ()) or ()]
    manifest = clip_set.get("manifestAssetPath")
    if manifest is not None:
        found.append(getattr(manifest, "path", str(manifest)))
    template = clip_set.get("templateAssetPath")
    if template:
        found.append(str(template))
    return [f for f in found if f]


def _member_names(entries, depth: int = 0) -> list[str]:
    """The names of a package's entries and, for a nested package (a stored .usdz entry), of its own as
    ``parts/b.usdz[textures/a.png]``, as usd-core's package resolver addresses them (four levels at most)."""
    names = []
    for entry in entries:
        names.append(entry.name)
        if depth < 4 and entry.name.lower().endswith(".usdz") and entry.method == 0:
            try:
                nested = package_entries(bytes(entry.data))
            except ValueError:
                continue  # the nested package is not readable: its members are found nowhere
            names += [f"{entry.name}[{name}]" for name in _member_names(nested, depth + 1)]
    return names
