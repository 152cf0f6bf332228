"""Resolve a :class:`~openpbr_tools.model.Material` into the numbers an evaluator needs.

For every parameter of the model's table (``schemas/models/``, latest version of the model):

* an authored constant is used as is (colours converted to linear Rec.709 from the input's, or
  else the material's, colour space);
* a texture contributes its ``fallback`` value when it has one, otherwise the table default,
  and the parameter is listed under ``textured`` ("textured (not evaluated)");
* a connection the reader could not interpret, or an unparsable value, falls back to the
  table default and is listed under ``not_evaluated``;
* anything unset takes the table default.

Geometric inputs (normals, tangents) are not evaluated: the evaluator works in the shading
frame. Defaults are never retyped here; they come from the tables.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from .. import tables
from ..colorspaces import to_lin_rec709
from ..model import Connection, Constant, Material, Texture

#: Parameter roles the evaluator does not consume.
_GEOMETRIC_ROLES = ("normal", "tangent", "filename", "string")


@dataclass
class ResolvedParameters:
    """Evaluator inputs of one material.

    ``values`` maps parameter names to NumPy arrays (floats and integers 0-d, colours shape
    ``(3,)``, booleans as ``bool``). ``textured`` lists textured parameters evaluated at their
    fallback or default, ``not_evaluated`` those whose authored value could not be used,
    ``ignored`` authored names the model's table does not know.
    """

    model: str
    version: str
    values: dict[str, object]
    textured: list[str] = field(default_factory=list)
    not_evaluated: list[str] = field(default_factory=list)
    ignored: list[str] = field(default_factory=list)

    def notes(self) -> list[str]:
        out = [f"{name}: textured (not evaluated)" for name in self.textured]
        out += [f"{name}: not evaluated (connection or invalid value), default used" for name in self.not_evaluated]
        out += [f"{name}: not a parameter of {self.model} {self.version}, ignored" for name in self.ignored]
        return out


def _convert(value, ptype: str, role: str, colorspace: str | None):
    if ptype == "boolean":
        if isinstance(value, str):
            return value.strip().lower() in ("true", "1")
        return bool(value)
    if ptype == "integer":
        return np.asarray(int(value))
    array = np.asarray(value, dtype=float)
    if ptype in ("color3", "color4") and array.ndim == 0:
        array = np.full(3, float(array))
    if ptype in ("color3", "color4") and role == "color":
        array = colour_to_lin_rec709(array[..., :3], colorspace)
    return array


def colour_to_lin_rec709(rgb: np.ndarray, colorspace: str | None) -> np.ndarray:
    """Convert a constant colour to linear Rec.709 (see :func:`openpbr_tools.colorspaces.to_lin_rec709`);
    unknown names are left unconverted (the validator reports them)."""
    if colorspace in (None, "lin_rec709", "none"):
        return np.asarray(rgb, dtype=float)
    try:
        return np.asarray(to_lin_rec709(rgb, colorspace), dtype=float)
    except KeyError:
        return np.asarray(rgb, dtype=float)


def defaults(model: str) -> ResolvedParameters:
    """Every parameter of ``model`` (latest table) at its default."""
    table = tables.table(model)
    values = {}
    for name, p in table.parameters.items():
        if p.role in _GEOMETRIC_ROLES or p.default is None:
            continue
        values[name] = _convert(p.default, p.type, p.role, None)
    return ResolvedParameters(model=model, version=table.version, values=values)


def with_values(model: str, overrides: dict) -> ResolvedParameters:
    """Defaults of ``model`` with ``overrides`` (linear Rec.709 numbers or arrays, which may carry
    leading batch axes) applied; unknown names raise ``KeyError``."""
    resolved = defaults(model)
    table = tables.table(model)
    for name, value in overrides.items():
        if name not in table.parameters:
            raise KeyError(f"{name!r} is not a parameter of {model} {table.version}")
        p = table.parameters[name]
        resolved.values[name] = value if p.type == "boolean" else np.asarray(value, dtype=float)
    return resolved


def resolve(material: Material) -> ResolvedParameters:
    """Resolve ``material`` (see the module docstring)."""
    resolved = defaults(material.model)
    table = tables.table(material.model)
    for name, entry in material.inputs.items():
        p = table.get(name)
        if p is None:
            resolved.ignored.append(name)
            continue
        if p.role in _GEOMETRIC_ROLES:
            if isinstance(entry.value, Texture):
                resolved.textured.append(name)
            continue
        colorspace = entry.colorspace or material.colorspace
        value = entry.value
        try:
            if isinstance(value, Constant):
                resolved.values[name] = _convert(value.value, p.type, p.role, colorspace)
            elif isinstance(value, Texture):
                resolved.textured.append(name)
                if value.fallback is not None:
                    space = value.colorspace or colorspace
                    resolved.values[name] = _convert(value.fallback, p.type, p.role, space)
            elif isinstance(value, Connection) or value is None:
                resolved.not_evaluated.append(name)
        except (TypeError, ValueError):
            resolved.not_evaluated.append(name)
    return resolved
