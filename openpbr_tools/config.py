"""Project configuration: ``[tool.openpbr]`` in ``pyproject.toml`` or the top level of ``.openpbr.toml``.

The configuration that applies to a file is the nearest one found walking up from the file's
folder (``.openpbr.toml`` wins over ``pyproject.toml`` in the same folder; a ``pyproject.toml``
without ``[tool.openpbr]`` is passed over). It is validated against
``schemas/config.schema.json``; a bad configuration raises :class:`ConfigError` with its location,
which ``openpbr validate`` reports as OPBR008 (exit code 2). Command-line options override it:
``--select`` replaces the configured selection, ``--ignore`` adds to it.

Precedence inside a configuration: the top-level settings, then each matching entry of
``overrides`` in order (paths are globs relative to the configuration's folder). ``allow-outside`` is honoured
only from the project the command runs in (:func:`invoking_project`).
"""

from __future__ import annotations

import fnmatch
import os
import re
from dataclasses import dataclass, field
from functools import lru_cache


from .diagnostics import Severity
from .model import Location
from .resources import load_json
from .rules import Context, all_rules

CONFIG_NAMES = (".openpbr.toml", "pyproject.toml")


class ConfigError(Exception):
    def __init__(self, message: str, location: Location):
        super().__init__(message)
        self.message = message
        self.location = location


@dataclass(frozen=True, slots=True)
class Config:
    path: str | None
    settings: dict = field(default_factory=dict)

    @property
    def folder(self) -> str:
        return os.path.dirname(self.path) if self.path else os.getcwd()


def _tomllib():
    """The TOML parser, imported when a configuration file is found (~3 ms a validate without one
    does not pay)."""
    try:
        import tomllib  # lazy: only a found configuration file is parsed
    except ModuleNotFoundError:  # Python 3.10
        import tomli as tomllib  # lazy: as above
    return tomllib


def load_config_file(path: str) -> Config | None:
    """Parse and validate one configuration file; ``None`` for a pyproject.toml without the table."""
    tomllib = _tomllib()
    try:
        with open(path, "rb") as handle:
            data = tomllib.load(handle)
    except OSError as error:
        raise ConfigError(f"cannot read configuration: {error.strerror or error}", Location(path)) from None
    except UnicodeDecodeError as error:  # TOML is UTF-8 (toml.io: "A TOML file must be a valid UTF-8 encoded document")
        raise ConfigError(f"not UTF-8 text (byte {error.start}): a TOML file must be UTF-8", Location(path)) from None
    except tomllib.TOMLDecodeError as error:
        line = re.search(r"line (\d+)", str(error))
        number = int(line.group(1)) if line else None
        if number is None and "end of document" in str(error):
            with open(path, "rb") as handle:
                number = max(1, handle.read().count(b"\n"))
        raise ConfigError(f"invalid TOML: {error}", Location(path, number)) from None
    if os.path.basename(path) == "pyproject.toml":
        settings = data.get("tool", {}).get("openpbr")
        if settings is None:
            return None
        prefix = "tool.openpbr"
    else:
        settings, prefix = data, ""
    _check(settings, path, prefix)
    return Config(path, settings)


def _check(settings: dict, path: str, prefix: str) -> None:
    import jsonschema  # lazy: jsonschema costs ~60-90 ms to import; only a configuration file is checked with it

    validator = jsonschema.Draft202012Validator(load_json("config.schema.json"))
    errors = sorted(validator.iter_errors(settings), key=lambda e: list(map(str, e.absolute_path)))
    if errors:
        error = errors[0]
        key = ".".join([prefix] + [str(p) for p in error.absolute_path] if prefix else [str(p) for p in error.absolute_path])
        raise ConfigError(f"invalid configuration at {key or '(top level)'}: {error.message}",
                          Location(path, _line_of(path, error.absolute_path), key or None))
    known = all_rules()
    for scope in [settings] + list(settings.get("overrides", [])):
        for code in list(scope.get("severity", {})):
            if code not in known:
                raise ConfigError(f"unknown rule code {code!r} in severity", Location(path, _line_of(path, [code]), code))
        for key in ("select", "ignore"):
            for code in scope.get(key, []):
                if not any(c.startswith(code) for c in known):
                    raise ConfigError(f"{key} names no rule: {code!r}", Location(path, _line_of(path, [key]), key))


def _line_of(path: str, keys) -> int | None:
    """The first line of ``path`` that mentions the last key of ``keys`` (TOML parsers keep no lines)."""
    names = [str(k) for k in keys if not isinstance(k, int)]
    if not names:
        return None
    try:
        with open(path, encoding="utf-8") as handle:
            for number, line in enumerate(handle, 1):
                if re.search(rf"(^|[\s\[.\"']){re.escape(names[-1])}([\s\]=.\"']|$)", line):
                    return number
    except OSError:
        return None
    return None


@lru_cache(maxsize=4096)
def find_config(folder: str) -> Config | None:
    """The configuration in effect for files in ``folder`` (absolute), or ``None``."""
    for name in CONFIG_NAMES:
        candidate = os.path.join(folder, name)
        if os.path.isfile(candidate):
            config = load_config_file(candidate)
            if config is not None:
                return config
    parent = os.path.dirname(folder)
    if parent == folder:
        return None
    return find_config(parent)


def _expand(codes, known) -> frozenset[str]:
    return frozenset(c for c in known if any(c.startswith(prefix) for prefix in codes))


def matching_overrides(file: str, config: Config | None) -> tuple[int, ...]:
    """Indices of the configuration's ``overrides`` whose paths match ``file``."""
    if config is None:
        return ()
    relative = os.path.relpath(os.path.abspath(file), config.folder).replace(os.sep, "/")
    return tuple(
        i for i, override in enumerate(config.settings.get("overrides", []))
        if any(fnmatch.fnmatch(relative, pattern) or fnmatch.fnmatch(relative, pattern.replace("**/", ""))
               for pattern in override["paths"])
    )


def context_for(file: str, config: Config | None, select=None, ignore=None, base: Context | None = None,
                overrides: tuple[int, ...] | None = None, allow_outside: tuple[str, ...] = ()) -> Context:
    """The :class:`Context` for one file: configuration, matching overrides, then CLI options.
    Files with the same configuration and matching overrides get equal contexts (callers cache)."""
    # all_rules() (cached) loads every rule family: it is called only where codes are selected or ignored
    context = Context() if base is None else Context(file_exists=base.file_exists, list_dir=base.list_dir)
    scopes = []
    if config is not None:
        scopes.append(config.settings)
        if overrides is None:
            overrides = matching_overrides(file, config)
        scopes.extend(config.settings["overrides"][i] for i in overrides)
    selected: frozenset[str] | None = None
    ignored: frozenset[str] = frozenset()
    severity: dict[str, Severity] = {}
    thresholds: dict[str, float] = {}
    for scope in scopes:
        if "select" in scope:
            selected = _expand(scope["select"], all_rules())
        if scope.get("ignore"):
            ignored |= _expand(scope["ignore"], all_rules())
        severity.update({code: Severity.parse(level) for code, level in scope.get("severity", {}).items()})
        thresholds.update(scope.get("thresholds", {}))
        units = scope.get("units")
        if units == "require":
            severity["OPBR603"] = Severity.ERROR
        elif units == "off":
            ignored |= {"OPBR603"}
        elif units == "warn":
            severity["OPBR603"] = Severity.WARNING
            ignored -= {"OPBR603"}
    if select:
        selected = _expand(select, all_rules())
    if ignore:
        ignored |= _expand(ignore, all_rules())
    disabled = ignored | (frozenset(all_rules()) - selected if selected is not None else frozenset())
    settings = config.settings if config is not None else {}
    context.severity = severity
    context.disabled = frozenset(disabled)
    context.thresholds = thresholds
    context.required_version = settings.get("required-version")
    context.required_colorspace = settings.get("required-colorspace")
    allowed = settings.get("allowed-texture-colorspaces")
    context.allowed_texture_colorspaces = frozenset(allowed) if allowed is not None else None
    folders = [os.path.normpath(os.path.join(config.folder, f)) for f in settings.get("allow-outside", ())] \
        if config is not None and invoking_project(config) else []
    context.allow_outside = tuple(dict.fromkeys([*folders, *(os.path.abspath(f) for f in allow_outside)]))
    return context


def invoking_project(config: Config) -> bool:
    """Whether ``config`` belongs to the project the command runs in: its folder holds the working directory. Only
    such a configuration may widen what assets read (``allow-outside``): one shipped inside a downloaded asset's
    own folder, validated from anywhere above or beside it, would otherwise let the asset grant itself the disk."""
    from .io.paths import PathGuard  # lazy: only a configuration that allows folders asks

    return PathGuard(os.path.abspath(config.folder)).contains(os.path.abspath(os.getcwd()))


def configured_fail_on(config: Config | None) -> str | None:
    return config.settings.get("fail-on") if config is not None else None
