"""Converting many files in one call: ``openpbr convert PATH... -o OUTDIR --output-format F``.

:func:`plan` expands files, folders (recursively) and globs as ``validate`` does, maps each input to
one output under ``OUTDIR`` that mirrors the input's place below the argument that named it (a
folder argument is the root of its tree; a file argument's folder; a glob's fixed leading folders),
and refuses the whole run, before anything is written, when two inputs map to one output, an output
is an input, the output folder holds an input folder (every output would land among the inputs), or an
output exists without ``force`` or ``skip_existing``. Inputs keep the spelling of the argument that named
them (``bt/a.mtlx`` for ``bt``), so reports are the same from any checkout, as ``validate``'s are. ``skip_existing`` skips an
output newer than its input and than the installed toolkit (its newest module), so a run that was
interrupted resumes where it stopped; outputs are written atomically, so an interrupted run leaves
complete files or none (at most a ``.openpbr-*.tmp`` beside them).

:func:`run` converts the planned jobs with the machinery ``validate`` uses (``--jobs`` process pool,
``--shard``, ``--changed-since``, a Dask scheduler; :func:`openpbr_tools.validate.run_chunks`) and
returns one :class:`~openpbr_tools.validate.Report` in input order, so every report format and exit
code works as for one file. Each conversion is :func:`openpbr_tools.convert.convert_file`, so
outputs are byte-identical to single calls whatever the parallelism. Textures are baked per
conversion (a texture shared by many files is baked once per output that needs it).
"""

from __future__ import annotations

import glob
import os
from dataclasses import dataclass, field

from .diagnostics import Diagnostic, Severity
from .io.paths import PathGuard
from .model import Location
from .outputs import NEVER_MODIFIED, overwritten_input
from .rules.document import READ_ERROR_RULES, UNREADABLE, internal_error
from .selection import SelectionError, changed_since, shard
from .validate import FileResult, Options, Report, discover, run_chunks, unreadable

OUTPUT_SUFFIXES = {"gltf": ".gltf", "glb": ".glb", "usda": ".usda", "usdc": ".usdc", "usdz": ".usdz", "mtlx": ".mtlx"}
INPUT_SUFFIXES = (".mtlx", ".usda", ".usdc", ".usd", ".usdz", ".gltf", ".glb")
BATCH_POOL_THRESHOLD = 4  # a conversion costs far more than a pool's start-up


@dataclass(frozen=True, slots=True)
class Job:
    """One conversion: plain data, so it travels to pool workers and Dask workers."""

    source: str
    output: str
    target: str | None = None
    nits_per_unit: float = 1.0
    mesh: str | None = None
    allow_outside: tuple[str, ...] = ()
    verify: bool = False
    threshold: float = 2.0
    gltf_drafts: bool = False
    candidates: bool = True


@dataclass(slots=True)
class Plan:
    jobs: list[Job] = field(default_factory=list)
    skipped: list[str] = field(default_factory=list)  # inputs whose output is up to date
    problems: list[Diagnostic] = field(default_factory=list)  # arguments naming nothing: reported, the rest runs
    refusals: list[Diagnostic] = field(default_factory=list)  # collisions, existing outputs: nothing is written
    unselected: int = 0  # inputs left out by --changed-since / --shard


def _root(argument: str) -> str:
    """The folder an argument's files are mirrored from."""
    if os.path.isdir(argument):
        return argument
    if glob.has_magic(argument):
        fixed = []
        for part in argument.replace(os.sep, "/").split("/"):
            if glob.has_magic(part):
                break
            fixed.append(part)
        return "/".join(fixed) or "."
    return os.path.dirname(argument) or "."


def _toolkit_stamp() -> float:
    """The newest modification time among the toolkit's modules and data: an output older than it
    was written by another version and is converted again."""
    package = os.path.dirname(os.path.abspath(__file__))
    newest = 0.0
    for folder, _, names in os.walk(package):
        for name in names:
            if name.endswith((".py", ".json", ".mtlx")):
                newest = max(newest, os.stat(os.path.join(folder, name)).st_mtime)
    return newest


def _problem(message: str, where: str) -> Diagnostic:
    return Diagnostic(UNREADABLE.code, Severity.ERROR, message, Location(where))


def plan(paths, outdir: str, output_format: str, *, force: bool = False, skip_existing: bool = False,
         options: Options | None = None, **job) -> Plan:
    """The jobs converting every input under ``paths`` into ``outdir`` (see the module docstring);
    ``job`` holds :class:`Job`'s remaining fields."""
    options = options or Options()
    suffix = OUTPUT_SUFFIXES[output_format]
    found = Plan()
    outputs: dict[str, str] = {}  # input as named (the argument's spelling: reports stay relative) -> output
    named: set[str] = set()  # inputs' absolute paths: a file named twice is converted once
    written = PathGuard(outdir)
    for argument in paths:
        files, problems = discover([argument], INPUT_SUFFIXES)
        found.problems += problems
        root = _root(os.fspath(argument))
        if files and written.contains(root):
            # every output would land among the inputs (-o IN, or -o . for a folder below it), and every input
            # would be taken for an earlier run's output: refused, where it used to convert nothing and exit 0
            found.refusals.append(_problem(f"the output folder {outdir} holds the input folder {root}: a batch never "
                                           "writes among its inputs; choose an output folder outside it", root))
            continue
        for file in files:
            relative = os.path.relpath(os.path.abspath(file), os.path.abspath(root))
            if os.path.abspath(file) not in named:
                named.add(os.path.abspath(file))
                outputs[file] = os.path.join(outdir, os.path.splitext(relative)[0] + suffix)
    if found.refusals:
        return found
    # outputs of an earlier run inside an input folder are not inputs (out/ below in/ with -o in/out)
    sources = eligible = sorted(source for source in outputs if not written.contains(source))
    try:
        if options.changed_since:
            sources = changed_since(sources, options.changed_since)
        if options.shard:
            sources = shard(sources, *options.shard)
    except SelectionError as error:
        found.refusals.append(_problem(str(error), "."))
        return found
    found.unselected = len(eligible) - len(sources)
    by_output: dict[str, list[str]] = {}
    for source in sources:
        by_output.setdefault(os.path.normcase(os.path.abspath(outputs[source])), []).append(source)
    for target, claimants in sorted(by_output.items()):
        if len(claimants) > 1:
            found.refusals.append(_problem(f"{' and '.join(claimants)} would both be written to {outputs[claimants[0]]}; "
                                           "rename one or convert them separately", claimants[0]))
    stamp = _toolkit_stamp() if skip_existing else 0.0
    for source in sources:
        output = outputs[source]
        replaced = overwritten_input(output, [source, *eligible])  # its own input first, then any other one
        if replaced is not None:
            found.refusals.append(_problem(f"the output {output} is the input {replaced}: {NEVER_MODIFIED}", source))
        elif os.path.exists(output) and skip_existing and \
                os.stat(output).st_mtime >= max(os.stat(source).st_mtime, stamp):
            found.skipped.append(source)
        elif os.path.exists(output) and not force:
            found.refusals.append(_problem(f"{output} exists; pass --force to overwrite or --skip-existing to keep it",
                                           source))
        else:
            found.jobs.append(Job(source, output, **job))
    return found


def convert_jobs(jobs: list[Job]) -> list[FileResult]:
    """Run ``jobs`` in this process (the unit a pool or Dask worker executes)."""
    return [_convert(job) for job in jobs]


def _convert(job: Job) -> FileResult:
    # lazy: the conversion pipeline loads NumPy and the translators; planning and reporting do not need them
    from .convert import convert_file
    from .verification import verify  # lazy: as the line above
    from .io import ReadError
    from .translate.common import Settings

    try:
        os.makedirs(os.path.dirname(job.output), exist_ok=True)
        result = convert_file(job.source, job.output, job.target, Settings(nits_per_unit=job.nits_per_unit, gltf_drafts=job.gltf_drafts,
                                                                                  candidates=job.candidates,
                                                                                  fit_films=job.verify, search=job.verify),
                              mesh=job.mesh, allow_outside=job.allow_outside)
    except ReadError as error:
        if error.kind == "no_material":  # a library of node definitions in the folder: skipped, said, not a failure
            return FileResult(job.source, [Diagnostic(READ_ERROR_RULES[error.kind].code, Severity.INFO, error.message, error.location)])
        return unreadable(job.source, error)
    except (ValueError, OSError) as error:  # a refused texture, an unwritable folder
        return FileResult(job.source, [_problem(f"not converted: {error}", job.source)], unreadable=True)
    except Exception as error:  # noqa: BLE001 - a defect of the toolkit on this file: reported, the batch goes on
        return internal_failure(job.source, "converting", error)
    diagnostics = result.diagnostics
    if job.verify:
        try:
            diagnostics = sorted(diagnostics + verify(result, job.threshold), key=Diagnostic.sort_key)
        except Exception as error:  # noqa: BLE001 - as above; the output is written, its verification is not
            return internal_failure(job.source, "verifying", error, diagnostics, len(result.pairs))
    return FileResult(job.source, diagnostics, materials=len(result.pairs))


def internal_failure(path: str, step: str, error: Exception, diagnostics=(), materials: int = 0) -> FileResult:
    """The result of a file whose ``step`` (converting, verifying) met a defect of the toolkit: OPBR011 beside
    what is known (:func:`~openpbr_tools.rules.document.internal_error` re-raises under the test suite)."""
    return FileResult(path, [*diagnostics, internal_error(path, step, error)], materials=materials, unreadable=True)


def run(found: Plan, options: Options | None = None, progress=None, on_result=None) -> Report:
    """Convert the planned jobs; one report in input order (problems and refusals exit 2).
    ``on_result``: see :func:`openpbr_tools.validate.run_chunks` (a streamed report)."""
    options = options or Options()
    report = Report(problems=found.problems + found.refusals, unselected=found.unselected)
    if found.refusals:
        return report  # refused before anything is written
    report.files = run_chunks(found.jobs, convert_jobs, options, progress, threshold=BATCH_POOL_THRESHOLD,
                              on_result=on_result)
    return report
