"""What the target model can hold: the colour space its formulas run in, and its ranges.

A translation's formulas run where the target renders (linear Rec.709: MaterialX's working space,
glTF's and UsdPreviewSurface's colour space), and a constant the target's range cannot hold is moved
inside it and reported, never written out of range.
"""

from __future__ import annotations

import numpy as np

from .. import colorspaces
from ..model import Input, Material


class WorkingSpace:
    """Formulas run where the target renders: in linear Rec.709, MaterialX's working space (a
    document's colours are converted into it before shading) and glTF's and UsdPreviewSurface's
    space. Colour constants enter a mapping's formula there and colour results go back to the
    colour space they are written in, so a per-channel non-linear formula (artistic IOR, the F82
    edge tint, a peak, a clamp) gives the same material whatever space the document is authored
    in (an ``acescg`` copper's edge tint solved in AP1 was 40 CIEDE2000 off)."""

    def __init__(self, material: Material, table):
        self.material, self.table = material, table
        self.reported: set[str] = set()

    def _space(self, entry: Input | None) -> str | None:
        name = colorspaces.materialx_name(entry.colorspace if entry is not None and entry.colorspace
                                          else self.material.colorspace)
        if name in (None, "lin_rec709") or colorspaces.is_data(name) or name not in colorspaces.materialx_names():
            return None  # already linear Rec.709, data, or a name the validator reports (left as is)
        return name

    def into(self, name: str, array):
        parameter = self.table.get(name)
        space = self._space(self.material.inputs.get(name))
        if space is None or parameter is None or parameter.role != "color" or np.shape(array)[-1:] != (3,):
            return array
        return np.asarray(colorspaces.to_lin_rec709(array, space), dtype=np.float64)

    def out_of_gamut(self, names, arrays) -> list[str]:
        """The reflectance colours among ``names`` (converted ``arrays``) outside [0, 1] in linear
        Rec.709, each named once per translation."""
        found = []
        for name, array in zip(names, arrays):
            parameter = self.table.get(name)
            if name in self.reported or parameter is None or parameter.role != "color" or parameter.hard_max is None \
                    or self._space(self.material.inputs.get(name)) is None or np.shape(array)[-1:] != (3,):
                continue
            if np.any(array < -1e-6) or np.any(array > 1.0 + 1e-6):
                self.reported.add(name)
                found.append(name)
        return found

    def out_of(self, value, parameter, written_like: Input | None):
        space = self._space(written_like)
        if space is None or parameter.role != "color" or np.shape(value)[-1:] != (3,):
            return value
        back = np.asarray(colorspaces.from_lin_rec709(value, space), dtype=np.float64)
        # the round trip through linear Rec.709 leaves ~1e-16 where a component was exactly 0 or 1
        for exact in (0.0, 1.0):
            back = np.where(np.abs(back - exact) < 1e-12, exact, back)
        return back


def inside(value, parameter):
    # value: a Python constant or a NumPy array (a mapping's source); arrays are judged as tuples
    """``value`` moved inside the target parameter's hard range, and what was done ("" when nothing):
    a value the target cannot hold (Standard Surface's specular_color above 1, from glTF's
    specularColorFactor 10) is clamped and reported rather than written out of range."""
    if isinstance(value, np.ndarray):
        value = tuple(float(v) for v in value.ravel()) if value.ndim else float(value)
    if isinstance(value, (bool, str)) or not isinstance(value, (int, float, tuple)):
        return value, ""
    values = value if isinstance(value, tuple) else (value,)
    if not all(isinstance(v, (int, float)) and np.isfinite(v) for v in values):
        return value, ""

    def bound(limit, i):
        return None if limit is None else (limit[i] if isinstance(limit, tuple) else limit)

    fixed = []
    for i, v in enumerate(values):
        low, high = bound(parameter.hard_min, i), bound(parameter.hard_max, i)
        if low is not None and (v < low or (v == low and parameter.hard_min_exclusive)):
            # an open bound takes the nearest value inside: an IOR of 0 (Standard Surface allows it,
            # F0 = 1) becomes 1e-6, whose F0 is 0.999996
            v = parameter.inside_low() if parameter.hard_min_exclusive else low
        if high is not None and v > high:
            v = high
        fixed.append(type(values[i])(v) if isinstance(values[i], float) else v)
    if fixed == list(values):
        return value, ""
    moved = tuple(fixed) if isinstance(value, tuple) else fixed[0]
    return moved, f"{_shown(value)} is outside the target's range; clamped to {_shown(moved)}"


def _shown(value) -> str:
    return "(" + ", ".join(f"{v:g}" for v in value) + ")" if isinstance(value, tuple) else f"{value:g}"
