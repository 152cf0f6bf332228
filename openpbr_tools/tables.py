"""Parameter tables: the knowledge of each shading model, read from ``schemas/models/``.

One JSON file per model and version (``schemas/models/<model>/<version>.json``), in the shape of
``schemas/parameter_table.schema.json``. Tables are validated against that schema by the test
suite (and by :func:`check_tables`), not on every load, so that ``openpbr validate`` on one file
stays as quick as ``mxvalidate``.
"""

from __future__ import annotations

from dataclasses import dataclass
import os
from functools import lru_cache
from typing import Any

from .resources import data_folder, load_json

MODELS = ("open_pbr_surface", "standard_surface", "gltf_pbr", "UsdPreviewSurface")


def version_key(version: str) -> tuple[int, ...]:
    """``"1.1.1"`` -> ``(1, 1, 1)``; ``"1.1"`` sorts before ``"1.1.1"``."""
    return tuple(int(part) for part in version.split("."))


@dataclass(frozen=True, slots=True)
class Parameter:
    name: str
    type: str
    default: Any
    role: str
    hard_min: Any = None
    hard_max: Any = None
    hard_min_exclusive: bool = False  # the bound itself is invalid: (0, inf) for an IOR
    special_value: float | None = None  # one value outside the range with a defined meaning (glTF's ior 0)
    soft_min: Any = None
    soft_max: Any = None
    unit: str | None = None
    uniform: bool = False
    enum: tuple | None = None
    group: str | None = None
    doc: str | None = None
    range_note: str | None = None
    soft_max_exceedable: bool = False  # the spec allows values above soft_max as such: no finding there
    default_geomprop: str | None = None

    def inside_low(self) -> float:
        """The nearest value inside an open lower bound (``hard_min_exclusive``): an IOR of 0 becomes 1e-6,
        whose F0 is 0.999996."""
        return self.hard_min + 1e-6 * max(1.0, abs(self.hard_min))


#: parameter groups whose first parameter (a weight, Standard Surface's thin film thickness) switches the whole
#: lobe off at 0: the others then have no effect
SWITCHED_GROUPS = ("transmission", "subsurface", "fuzz", "sheen", "coat", "thin film", "emission")


@dataclass(frozen=True, slots=True)
class ParameterTable:
    model: str
    version: str
    node: str
    nodedef: str | None
    parameters: dict[str, Parameter]
    notes: tuple[str, ...]
    sources: tuple[str, ...]

    def __contains__(self, name: str) -> bool:
        return name in self.parameters

    def __getitem__(self, name: str) -> Parameter:
        return self.parameters[name]

    def get(self, name: str) -> Parameter | None:
        return self.parameters.get(name)

    def lobe_switch(self, name: str) -> str | None:
        """The parameter that switches ``name``'s lobe on, where ``name`` is another parameter of a lobe that does
        nothing at a switch of 0 (its group's first parameter: transmission_weight for transmission_depth, coat for
        Standard Surface's coat_affect_color, thin_film_thickness for its thin_film_IOR), else ``None``."""
        parameter = self.parameters.get(name)
        if parameter is None or parameter.group not in SWITCHED_GROUPS:
            return None
        first = next(n for n, p in self.parameters.items() if p.group == parameter.group)
        return None if first == name else first


def _relative(model: str, version: str) -> str:
    return f"models/{model}/{version}.json"


@lru_cache(maxsize=None)
def versions(model: str) -> tuple[str, ...]:
    """Every version of ``model`` with a table, oldest first."""
    folder = os.path.join(data_folder("schemas"), "models", model)
    if not os.path.isdir(folder):
        return ()
    found = [name[:-5] for name in os.listdir(folder) if name.endswith(".json")]
    return tuple(sorted(found, key=version_key))


@lru_cache(maxsize=None)
def names(model: str, version: str) -> frozenset[str]:
    """The parameter names of ``model`` at ``version`` (read from its table file without building
    the table: version inference asks every version)."""
    return frozenset(load_json(_relative(model, version))["parameters"])


def latest(model: str) -> str:
    return versions(model)[-1]


@lru_cache(maxsize=None)
def table(model: str, version: str | None = None) -> ParameterTable:
    """The table of ``model`` at ``version`` (the latest when ``None``)."""
    version = version or latest(model)
    raw = load_json(_relative(model, version))
    params = {
        name: Parameter(
            name=name,
            type=entry["type"],
            default=_freeze(entry["default"]),
            role=entry["role"],
            hard_min=_freeze(entry.get("hard_min")),
            hard_max=_freeze(entry.get("hard_max")),
            hard_min_exclusive=entry.get("hard_min_exclusive", False),
            special_value=entry.get("special_value"),
            soft_min=_freeze(entry.get("soft_min")),
            soft_max=_freeze(entry.get("soft_max")),
            unit=entry.get("unit"),
            uniform=entry.get("uniform", False),
            enum=tuple(entry["enum"]) if "enum" in entry else None,
            group=entry.get("group"),
            doc=entry.get("doc"),
            range_note=entry.get("range_note"),
            soft_max_exceedable=entry.get("soft_max_exceedable", False),
            default_geomprop=entry.get("default_geomprop"),
        )
        for name, entry in raw["parameters"].items()
    }
    return ParameterTable(
        model=raw["model"],
        version=raw["version"],
        node=raw["node"],
        nodedef=raw.get("nodedef"),
        parameters=params,
        notes=tuple(raw.get("notes", ())),
        sources=tuple(raw["sources"]),
    )


def table_known(model: str, version: str | None) -> ParameterTable:
    """The table of ``model`` at ``version`` where the toolkit has one for it, else the latest (a material whose
    version is unknown or has no table is read against the current inputs)."""
    return table(model, version if version in versions(model) else None)


def _freeze(value: Any) -> Any:
    return tuple(value) if isinstance(value, list) else value


def check_tables() -> list[str]:
    """Validate every table file against ``parameter_table.schema.json``; returns error messages."""
    import jsonschema  # lazy: jsonschema costs ~60-90 ms to import; only the table check uses it

    schema = load_json("parameter_table.schema.json")
    validator = jsonschema.Draft202012Validator(schema)
    errors = []
    for model in MODELS:
        for version in versions(model):
            raw = load_json(_relative(model, version))
            for error in validator.iter_errors(raw):
                pointer = "/".join(str(p) for p in error.absolute_path)
                errors.append(f"{model}/{version}.json#/{pointer}: {error.message}")
            if raw.get("model") != model or raw.get("version") != version:
                errors.append(f"{model}/{version}.json: model/version fields do not match the file name")
    return errors
