"""Validation of files and folders: discovery, reading, rules, and the exit status.

``validate_paths`` is the library entry point behind ``openpbr validate``: it returns a
:class:`Report` and never prints. A file that cannot be read yields one diagnostic (OPBR001,
OPBR002, OPBR006) and marks the report ``unreadable``, which the command maps to exit code 2.
"""

from __future__ import annotations

import glob
import os
from dataclasses import dataclass, field, replace
from typing import Callable

from . import io as readers
from .config import ConfigError, context_for, find_config, matching_overrides
from .diagnostics import Diagnostic, Severity
from .distributed import run_on_cluster
from .io.paths import PathGuard
from .model import Asset, Location
from .outputs import files_read
from .rules import Context, check_asset
from .rules.document import INTERNAL_ERROR, INVALID_CONFIG, NO_MATERIAL, READ_ERROR_RULES, UNREADABLE, internal_error
from .selection import SelectionError, changed_since, shard


@dataclass(slots=True)
class FileResult:
    path: str
    diagnostics: list[Diagnostic]
    materials: int = 0
    unreadable: bool = False
    asset: Asset | None = None
    documents: tuple[tuple[str, int], ...] = ()  # (document, its materials): composed, their findings among its own
    reads: tuple[str, ...] = ()  # the files the asset reads (openpbr_tools.outputs.files_read): never an output


@dataclass(slots=True)
class Report:
    files: list[FileResult] = field(default_factory=list)
    problems: list[Diagnostic] = field(default_factory=list)  # about the arguments, not a file
    unselected: int = 0  # files found but left out by --changed-since / --shard (a note when none is left)

    @property
    def diagnostics(self) -> list[Diagnostic]:
        found = list(self.problems)
        for result in self.files:
            found.extend(result.diagnostics)
        return found

    @property
    def unreadable(self) -> bool:
        return bool(self.problems) or any(r.unreadable for r in self.files)

    def count(self, severity: Severity) -> int:
        return sum(1 for d in self.diagnostics if d.severity == severity)

    def exit_code(self, fail_on: Severity | None = Severity.ERROR) -> int:
        """0 clean, 1 a finding at or above ``fail_on`` (``None``: never), 2 unreadable input."""
        if self.unreadable:
            return 2
        if fail_on is not None and any(d.severity >= fail_on for d in self.diagnostics):
            return 1
        return 0


def discover(paths, suffixes: tuple[str, ...] | None = None) -> tuple[list[str], list[Diagnostic]]:
    """Expand files, folders (recursively) and glob patterns into a sorted list of files.

    A path that does not exist, a pattern that matches nothing and a folder without supported files
    each give an OPBR001 diagnostic. Explicitly named files are kept whatever their suffix (the
    reader reports an unsupported one).
    """
    suffixes = suffixes or readers.available_suffixes()
    files: set[str] = set()
    problems: list[Diagnostic] = []
    for raw in paths:
        path = os.fspath(raw)
        if os.path.isdir(path):
            before = len(problems)
            found = _walk(path, suffixes, problems)
            if not found and len(problems) == before:
                problems.append(Diagnostic(
                    UNREADABLE.code, Severity.ERROR,
                    f"no {', '.join(suffixes)} files in folder", Location(path),
                ))
            files.update(found)
        elif os.path.exists(path) or os.path.islink(path):
            files.add(path)
        elif glob.has_magic(path):
            matched = [m for m in glob.glob(path, recursive=True) if os.path.isfile(m) and m.lower().endswith(suffixes)]
            if not matched:
                problems.append(Diagnostic(UNREADABLE.code, Severity.ERROR, "pattern matches no file", Location(path)))
            files.update(matched)
        else:
            problems.append(Diagnostic(UNREADABLE.code, Severity.ERROR, "no such file or folder", Location(path)))
    # one file named twice (``a.mtlx`` and ``./a.mtlx``, or a file and its folder) is checked and reported once
    unique = {os.path.normpath(os.path.abspath(f)): f for f in sorted(files, key=len, reverse=True)}
    return sorted(unique.values()), problems


def _walk(folder: str, suffixes: tuple[str, ...], problems: list[Diagnostic]) -> list[str]:
    """The files of ``suffixes`` below ``folder``, following links to folders that stay inside it (a link to a
    parent would walk what was not named); a subfolder that cannot be listed is an OPBR001 error in ``problems``
    (its files are not checked, and the run must not pass for a check of them)."""
    found = []
    seen_dirs: set[tuple[int, int]] = set()
    guard = PathGuard(folder)

    def unlisted(error: OSError) -> None:
        problems.append(Diagnostic(UNREADABLE.code, Severity.ERROR, f"cannot list folder: {error.strerror or error}",
                                   Location(error.filename or folder)))

    for root, dirs, names in os.walk(folder, followlinks=True, onerror=unlisted):
        try:
            stat = os.stat(root)
        except OSError:
            dirs[:] = []
            continue
        key = (stat.st_dev, stat.st_ino)
        if key in seen_dirs:  # a symlink loop: do not walk the same folder twice
            dirs[:] = []
            continue
        seen_dirs.add(key)
        dirs[:] = sorted(d for d in dirs if not os.path.islink(os.path.join(root, d))
                         or guard.resolve(os.path.abspath(os.path.join(root, d))).inside)
        found.extend(os.path.join(root, n) for n in names if n.lower().endswith(suffixes))
    return found


def read_error(error: readers.ReadError | OSError, path: str) -> Diagnostic:
    """The diagnostic for input that cannot be read at all (every command reports it this way):
    the rule of the :class:`~openpbr_tools.io.ReadError`'s kind, or OPBR001 for an operating-system
    error, always an error."""
    if isinstance(error, readers.ReadError):
        return Diagnostic(READ_ERROR_RULES[error.kind].code, Severity.ERROR, error.message, error.location)
    return Diagnostic(UNREADABLE.code, Severity.ERROR, f"cannot read file: {error}", Location(path))


def unreadable(path: str, error: readers.ReadError | OSError) -> FileResult:
    """The result for a file that cannot be read (exit code 2)."""
    return FileResult(path, [read_error(error, path)], unreadable=True)


def validate_file(path: str, context: Context | None = None, keep_asset: bool = False,
                  composing: frozenset = frozenset(), included_by: str | None = None) -> FileResult:
    """The findings of one file. A defect of the toolkit on it (an exception other than a
    :class:`~openpbr_tools.io.ReadError`) is OPBR011 at the file, and the file counts as not checked
    (exit code 2), so one file never stops a folder's report. ``composing``: the documents whose composition
    led here (an include cycle is the includer's finding, not a recursion); ``included_by``: the MaterialX document
    that XIncludes this one, in whose composition it is read."""
    try:
        asset = readers.read_asset(path, context.allow_outside if context is not None else (), included_by=included_by)
    except readers.ReadError as error:
        return unreadable(path, error)
    except Exception as error:  # noqa: BLE001 - a defect of a reader: reported at the file, the batch goes on
        return FileResult(path, [internal_error(path, "reading", error)], unreadable=True)
    diagnostics = check_asset(asset, context)
    reads = files_read(asset)
    # a USD preview fallback is not another material, nor an included document's shader (counted in its document)
    count = sum(1 for m in asset.materials if not m.extra.get("fallback_of") and not m.extra.get("included_from"))
    documents = []
    within = composing | {os.path.abspath(path)}
    included = set(asset.extra.get("included_documents", ()))
    for document in composed_documents(asset):  # (each composed document's own with it)
        if os.path.abspath(document) in within:
            continue
        own = context.for_document(document) if context is not None and context.for_document is not None else None
        inner = own or context
        if document in included:  # read from the includer's folder too, as MaterialX composes it (its ../ includes)
            inner = replace(inner or Context(), allow_outside=tuple(dict.fromkeys(
                (*(inner.allow_outside if inner else ()), *(context.allow_outside if context else ()),
                 os.path.dirname(os.path.abspath(path))))))
        composed = validate_file(document, inner, composing=within,
                                 included_by=path if document in included else None)
        diagnostics += composed.diagnostics
        reads += composed.reads
        count += composed.materials
        # each document with its own materials, those it composes after it: a listed one's findings and
        # materials are dropped once (_drop_listed_documents), at any depth
        documents.append((document, composed.materials - sum(m for _, m in composed.documents)))
        documents += composed.documents
    if documents and count:  # the stage's materials are in its documents
        diagnostics = [d for d in diagnostics if not (d.code == NO_MATERIAL.code and d.location.file == path)]
    failed = any(d.code == INTERNAL_ERROR.code for d in diagnostics)
    return FileResult(path, diagnostics, count, unreadable=failed, asset=asset if keep_asset else None,
                      documents=tuple(documents), reads=tuple(dict.fromkeys(reads)))


def composed_documents(asset: Asset) -> tuple[str, ...]:
    """The MaterialX documents a USD stage references, sublayers or loads as a payload (UsdMtlx), which
    this usd-core cannot compose, and the documents a MaterialX document XIncludes (whose materials, shaders and
    graphs MaterialX reads as its own): their findings are the asset's too. Only documents the asset's path guard
    let through (inside the asset's folder), each once."""
    found = [o.detail["document"] for o in asset.observations  # named as the stage is (the guard's where())
             if o.kind == "usd_mtlx_reference" and o.detail.get("document")]
    return tuple(dict.fromkeys(found + list(asset.extra.get("included_documents", ()))))


@dataclass(slots=True)
class Options:
    """How ``validate_paths`` runs: rule selection on top of the configuration, parallelism, and
    the CI narrowing of the file list."""

    select: tuple[str, ...] = ()
    ignore: tuple[str, ...] = ()
    use_config: bool = True
    jobs: int = 1
    changed_since: str | None = None
    shard: tuple[int, int] | None = None
    scheduler: str | None = None
    scheduler_timeout: float = 30.0
    allow_outside: tuple[str, ...] = ()  # folders besides each asset's own it may read from


def contexts_for(files: list[str], options: Options, problems: list[Diagnostic]) -> dict[str, Context] | None:
    """The context of every file from its nearest configuration; ``None`` if a configuration is bad
    (the problem is appended to ``problems``)."""
    contexts = {}
    shared: dict[tuple, Context] = {}  # one context per (configuration, matching overrides)
    for path in files:
        config = None
        if options.use_config:
            try:
                config = find_config(os.path.dirname(os.path.abspath(path)))
            except ConfigError as error:
                problems.append(Diagnostic(INVALID_CONFIG.code, Severity.ERROR, error.message, error.location))
                return None
        overrides = matching_overrides(path, config)
        key = (config.path if config else None, overrides)
        if key not in shared:
            shared[key] = context_for(path, config, options.select, options.ignore, overrides=overrides,
                                      allow_outside=options.allow_outside)
            shared[key].for_document = DocumentContexts(options)
        contexts[path] = shared[key]
    return contexts


@dataclass(frozen=True, slots=True)
class DocumentContexts:
    """The context of a document a file composes, made as a listed file's is: its own nearest
    configuration and matching overrides, and the command's options (a value, so worker processes get it)."""

    options: Options

    def __call__(self, path: str) -> Context | None:
        found = contexts_for([path], self.options, [])
        return found[path] if found else None  # a bad configuration there: the composing file's context


def _validate_chunk(tasks: list[tuple[str, Context]]) -> list[FileResult]:
    return [validate_file(path, context) for path, context in tasks]


def _chunks(tasks: list, count: int) -> list[list]:
    size = max(1, min(64, len(tasks) // max(1, count)))
    return [tasks[i:i + size] for i in range(0, len(tasks), size)]


# Below this many files a process pool costs more (start-up, a MaterialX library load per worker)
# than it saves.
POOL_THRESHOLD = 48


def validate_paths(paths, context: Context | None = None, options: Options | None = None,
                   progress: Callable[[int, int], None] | None = None) -> Report:
    """Validate files, folders and globs. With ``context`` every file uses it; otherwise each file
    gets the context of its nearest configuration plus ``options``."""
    options = options or Options()
    files, problems = discover(paths)
    # a folder named on the command line is the tree its files may read from (a USD asset's ../_common layers,
    # a MaterialX library's ../../../Images), as --allow-outside names one: nothing outside it
    folders = tuple(os.path.abspath(os.fspath(p)) for p in paths if os.path.isdir(os.fspath(p)))
    if folders:
        options = replace(options, allow_outside=tuple(dict.fromkeys(options.allow_outside + folders)))
    report = Report(problems=problems)
    found = len(files)
    try:
        if options.changed_since:
            files = changed_since(files, options.changed_since)
        validated = files  # by this run or, under --shard, by the shard that holds it
        if options.shard:
            files = shard(files, *options.shard)
    except SelectionError as error:
        report.problems.append(Diagnostic(UNREADABLE.code, Severity.ERROR, str(error), Location(".")))
        return report
    report.unselected = found - len(files)
    if context is not None:
        tasks = [(path, context) for path in files]
    else:
        contexts = contexts_for(files, options, report.problems)
        if contexts is None:
            return report
        tasks = [(path, contexts[path]) for path in files]
    report.files = _run(tasks, options, progress)
    _drop_listed_documents(report.files, validated)
    return report


def _drop_listed_documents(results: list[FileResult], files: list[str]) -> None:
    """Each composed document's findings and materials are reported once: with the document, when it is
    validated as a file of its own too (by this run or, under --shard, by another shard's), else with the
    first file that composes it (under --shard, once per shard holding such a file)."""
    reported = {os.path.abspath(f) for f in files}
    for result in results:
        dropped = set()
        for document, materials in result.documents:
            key = os.path.abspath(document)
            if key in reported:
                dropped.add(key)
                result.materials -= materials
            reported.add(key)
        if dropped:
            result.diagnostics = [d for d in result.diagnostics if os.path.abspath(d.location.file) not in dropped]


def _run(tasks, options: Options, progress) -> list[FileResult]:
    return run_chunks(tasks, _validate_chunk, options, progress)


def run_chunks(tasks: list, work_chunk, options: Options, progress, threshold: int = POOL_THRESHOLD,
               on_result: Callable | None = None) -> list:
    """``work_chunk`` (a module-level function of a list of tasks, returning one result per task)
    over ``tasks``: in this process, in a process pool of ``options.jobs`` (from ``threshold`` tasks
    on), or on the Dask cluster at ``options.scheduler``. Results keep the tasks' order whichever
    way they ran; ``progress(done, total)`` is called as they arrive. ``on_result``, when given,
    receives each result in the tasks' order as soon as it and those before it are done, and what it
    returns is kept instead (a caller streaming a report keeps a slim result: memory stays flat).
    Shared by validate and the batch form of convert."""
    total = len(tasks)
    keep = on_result or (lambda result: result)
    if options.scheduler:
        return [keep(r) for r in run_on_cluster(tasks, options.scheduler, work_chunk, _chunks,
                                                timeout=options.scheduler_timeout)]
    if options.jobs <= 1 or total < threshold:
        results = []
        for done, task in enumerate(tasks, 1):
            results += [keep(r) for r in work_chunk([task])]
            if progress:
                progress(done, total)
        return results
    # lazy: concurrent.futures (~4 ms) is needed only for a process pool; kept off validate's start-up
    from concurrent.futures import as_completed

    from . import workers  # lazy: as the line above

    chunks = _chunks(tasks, options.jobs * 8)
    ordered: list[list[FileResult] | None] = [None] * len(chunks)
    released = 0  # chunks handed to on_result, in order
    done = 0
    with workers.interruptible(), workers.pool(options.jobs) as pool:
        try:
            futures = {pool.submit(workers.run_task, work_chunk, chunk): i for i, chunk in enumerate(chunks)}
            for future in as_completed(futures):
                ordered[futures[future]] = future.result()
                done += len(chunks[futures[future]])
                while released < len(chunks) and ordered[released] is not None:
                    ordered[released] = [keep(r) for r in ordered[released]]
                    released += 1
                if progress:
                    progress(done, total)
        except BaseException:  # SIGTERM, Ctrl-C, a failure: no worker goes on writing once the run has ended
            workers.stop(pool)
            raise
    return [result for chunk in ordered for result in chunk]
