"""A mapping of a procedural input written as arithmetic on top of its graph, so that a ``.mtlx``
output keeps the graph instead of dropping it.

A procedural input (a node graph the reader captured: :class:`~openpbr_tools.model.Connection` with
``graph_xml``) cannot be baked: nothing here evaluates MaterialX's nodes. Where a mapping passes it
through unchanged it is rewired as is (:mod:`.common`); where the mapping transforms it (a
UsdPreviewSurface ``diffuseColor`` is OpenPBR's ``base_weight * base_color``, a Standard Surface
metal's colour goes through OpenPBR's specular weight), the transform, with every other source at
its constant value, is a function g of the graph's output alone. g is sampled here with the
mapping's own NumPy formula (the one every other path uses: constants, baked texels, the
evaluator) over the source parameter's range, and written as nodes
(:func:`openpbr_tools.io.mtlx.expression.append`). MaterialX evaluates a graph in its working space,
linear Rec.709 (every colour constant and image converted into it: the document's colour space is
where values are authored, not where nodes compute), which is where the formulas run
(:class:`~.target.WorkingSpace`); so g runs on the graph's output as it is, and the written nodes'
colour constants are declared ``lin_rec709`` so that no colour management touches them:

* **affine**, g(x) = A x + b to 1e-7 of the output's scale (every linear map and colour-space
  conversion is): exact, so the graph renders as the mapping would have baked it;
* else **a polynomial per channel** (a cubic, else a quintic: each output channel a polynomial of its
  own input channel in linear Rec.709, or of the single float), least squares over the range: written
  when its largest error over the samples is at most :data:`TOLERANCE`, and reported with that error
  (OPBR1103);
* else nothing is written and the input is reported as not carried, as before.

A result outside the target parameter's hard range over the samples gets a ``clamp`` node. Only
float and colour inputs are expressed (a normal or an integer switch is not a formula of values).

A **texture** that cannot be baked (a UDIM set, an image outside the asset's folder; :mod:`openpbr_tools.bake`)
is kept the same way where the map is affine with no channel mixing: as the texture's own scale and
bias (:func:`scaled_texture`), which the .mtlx writer writes as multiply/add nodes and the USD writer
as a UsdUVTexture's scale and bias.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass

import numpy as np

from ..model import Connection, Input, Material, Texture

AFFINE_TOLERANCE = 1e-7  # relative to the output's scale: below this g is affine (exact)
TOLERANCE = 0.01  # largest error of a polynomial over the range for it to be written (in the input's units)
DEGREES = (3, 5)  # a cubic, else a quintic
_SAMPLES = 96
_WIDTH = {"float": 1, "color3": 3}


@dataclass(frozen=True)
class Expression:
    """g(x) as data: ``kind`` "affine" (``matrix`` target x source, ``offset`` target) or
    "polynomial" (``coefficients`` (degree + 1) x target, highest power first, channel c a polynomial of
    input channel c, or of the float); ``clamp`` (low, high) or None; ``error``: largest error over
    the samples (0 for affine)."""

    kind: str
    source_type: str
    target_type: str
    matrix: np.ndarray | None = None
    offset: np.ndarray | None = None
    coefficients: np.ndarray | None = None
    clamp: tuple[float, float] | None = None
    error: float = 0.0

    @property
    def exact(self) -> bool:
        return self.kind == "affine" and self.clamp is None


def described(expression: Expression, textured: list[str]) -> str:
    """What was written, for the report (OPBR1102 when exact, else OPBR1103)."""
    how = "exactly (an affine map)" if expression.kind == "affine" else \
        f"as a polynomial per channel (degree {len(expression.coefficients) - 1}), within {expression.error:.2g} " \
        "of the formula over the input's range"
    clamp = "" if expression.clamp is None else f", clamped to [{expression.clamp[0]:g}, {expression.clamp[1]:g}]"
    return (f"the procedural graph on {', '.join(textured)} is kept and the mapping, with the other inputs at their "
            f"values, is written after it as MaterialX nodes, {how}{clamp}")


def _domain(parameter) -> tuple[float, float]:
    """The range the graph's output is sampled over: the parameter's soft range, else its hard range,
    else [0, 1] (a bound per component is reduced to its widest)."""
    low = _scalar_bound(parameter.soft_min if parameter.soft_min is not None else parameter.hard_min, min)
    high = _scalar_bound(parameter.soft_max if parameter.soft_max is not None else parameter.hard_max, max)
    low = 0.0 if low is None else low
    high = low + 1.0 if high is None or high <= low else high
    return low, high


def samples(width: int, low: float, high: float) -> np.ndarray:
    """(N, width) sample points: the corners of the range and a fixed pseudo-random spread inside."""
    rng = np.random.default_rng(1103)
    corners = np.array(np.meshgrid(*[[low, high]] * width, indexing="ij")).reshape(width, -1).T
    inner = low + (high - low) * rng.random((_SAMPLES, width))
    return np.concatenate([corners, inner])


def fit(g, source_type: str, target_type: str, low: float, high: float, target_range=None) -> Expression | None:
    """``g`` ((N, source width) -> (N, target width), vectorised) as an :class:`Expression` over
    [low, high], or None where neither form holds (module docstring). ``target_range``: the target's
    (low, high) hard bounds, either None."""
    s, t = _WIDTH.get(source_type), _WIDTH.get(target_type)
    if s is None or t is None:
        return None
    x = samples(s, low, high)
    try:
        with np.errstate(all="ignore"):
            y = np.asarray(g(x), dtype=np.float64)
    except (ValueError, TypeError, IndexError):  # a formula written for other shapes: not expressed
        return None
    try:
        y = np.broadcast_to(y if y.ndim == 2 else y.reshape(len(x), -1), (len(x), t)) if y.shape[-1] in (1, t) \
            else None
    except ValueError:
        y = None
    if y is None or not np.all(np.isfinite(y)):
        return None
    clamp = _clamp(y, target_range)
    design = np.concatenate([x, np.ones((len(x), 1))], axis=1)
    solution, *_ = np.linalg.lstsq(design, y, rcond=None)
    scale = max(1.0, float(np.abs(y).max()))
    if np.abs(design @ solution - y).max() <= AFFINE_TOLERANCE * scale:
        matrix, offset = solution[:-1].T, solution[-1]
        matrix = np.where(np.abs(matrix) < 1e-12, 0.0, matrix)
        offset = np.where(np.abs(offset) < 1e-12, 0.0, offset)
        return Expression("affine", source_type, target_type, matrix=matrix, offset=offset, clamp=clamp)
    if s != 1 and s != t:
        return None
    for degree in DEGREES:
        coefficients = np.empty((degree + 1, t))
        for channel in range(t):
            own = x[:, 0 if s == 1 else channel]
            coefficients[:, channel] = np.polyfit(own, y[:, channel], degree)
        found = Expression("polynomial", source_type, target_type, coefficients=coefficients, clamp=clamp)
        error = float(np.abs(evaluate(dataclasses.replace(found, clamp=None), x) - y).max())
        if error <= TOLERANCE:
            return dataclasses.replace(found, error=error)
    return None


def _clamp(y: np.ndarray, target_range) -> tuple[float, float] | None:
    if target_range is None:
        return None
    low, high = target_range
    below = low is not None and float(y.min()) < low - 1e-9
    above = high is not None and float(y.max()) > high + 1e-9
    if not (below or above):
        return None
    return (float(low) if low is not None else float(y.min()), float(high) if high is not None else float(y.max()))


def evaluate(expression: Expression, x: np.ndarray) -> np.ndarray:
    """The expression at (N, source width) points: what the written nodes compute (for tests)."""
    x = np.asarray(x, dtype=np.float64)
    if expression.kind == "affine":
        y = x @ expression.matrix.T + expression.offset
    else:
        t = expression.coefficients.shape[1]
        own = x if x.shape[1] == t else np.repeat(x[:, :1], t, axis=1)
        y = np.stack([np.polyval(expression.coefficients[:, c], own[:, c]) for c in range(t)], axis=1)
    return y if expression.clamp is None else np.clip(y, *expression.clamp)


def _scalar_bound(bound, pick):
    return None if bound is None else (pick(bound) if isinstance(bound, tuple) else float(bound))


def _hard_range(parameter) -> tuple[float | None, float | None]:
    """The parameter's hard (low, high), a bound per component reduced to its narrowest."""
    return _scalar_bound(parameter.hard_min, max), _scalar_bound(parameter.hard_max, min)


def carry(entry: Input, formula_of, source_parameter, target_parameter) -> tuple[Input, Expression] | None:
    """``entry`` (a procedural input) carried to ``target_parameter`` through ``formula_of`` (the
    mapping's g, :func:`fit`'s argument) as a new connection whose graph ends in the expression's
    nodes; None where g is not expressible or the graph cannot be extended."""
    # lazy: MaterialX (~10 ms) is loaded only for a procedural input a mapping transforms
    from ..io.mtlx.expression import ExpressionError, append

    connection = entry.value
    if not isinstance(connection, Connection) or not connection.graph_xml or source_parameter is None:
        return None
    source_type, target_type = source_parameter.type, target_parameter.type
    if source_parameter.role in ("normal", "tangent") or target_parameter.role in ("normal", "tangent"):
        return None
    low, high = _domain(source_parameter)
    expression = fit(formula_of, source_type, target_type, low, high, _hard_range(target_parameter))
    if expression is None:
        return None
    try:
        graph_xml, output = append(connection.graph_xml, connection.output or "", expression)
    except ExpressionError:
        return None
    carried = Input(target_parameter.name, target_type,
                    Connection(connection.target, connection.category, connection.reason, graph_xml=graph_xml,
                               output=output),
                    entry.location, colorspace=entry.colorspace)
    return carried, expression


def one_graph(material: Material, names: list[str]) -> bool:
    """Whether ``names`` are all fed by the same captured procedural graph and output (a marble's one
    graph on both its base and its subsurface colour), of one type."""
    entries = [material.inputs[name] for name in names]
    first = entries[0].value
    return isinstance(first, Connection) and bool(first.graph_xml) and all(
        isinstance(e.value, Connection) and e.value.graph_xml == first.graph_xml and e.value.output == first.output
        and e.type == entries[0].type and e.colorspace == entries[0].colorspace for e in entries)


def express(material: Material, mapping, textured: list[str], values, working, parameter,
            ignored: dict) -> tuple[Input, Expression] | None:
    """The procedural graph feeding ``textured`` carried through ``mapping`` as MaterialX nodes
    (module docstring): the formula with every other source at its constant (one the formula ignores,
    ``ignored``, at its probe value), as a function of the graph's output. MaterialX renders a graph in
    its working space, linear Rec.709 (colour constants and images converted into it), which is where
    the formulas run: the graph's colour enters them as it is, and the result leaves as it is."""
    others = {name: ignored[name] if name in ignored else values.constant(name) for name in mapping.sources
              if name not in textured}
    if any(v is None for v in others.values()):
        return None
    entry = material.inputs[textured[0]]
    source_parameter = values.table.get(textured[0])
    if source_parameter is None or any(values.table.get(name) is None or values.table[name].type != source_parameter.type
                                       for name in textured):
        return None
    arguments = {name: working.into(name, value) for name, value in others.items()}

    def g(x):  # x: (N, width); the formula sees an N x 1 image, as a baked texture's texels (H, W, C)
        probe = x.reshape(len(x), 1, -1)
        produced = mapping.formula(*[probe if name in textured else arguments[name] for name in mapping.sources])
        produced = np.asarray(produced, dtype=np.float64)
        produced = produced.reshape((1,) * max(0, 3 - produced.ndim) + produced.shape)
        return np.broadcast_to(produced, (len(x), 1, produced.shape[-1])).reshape(len(x), -1)

    if isinstance(entry.value, Texture):
        return _scaled(entry, g, source_parameter, parameter)
    return carry(entry, g, source_parameter, parameter)


def _scaled(entry: Input, g, source_parameter, target_parameter) -> tuple[Input, Expression] | None:
    """A texture carried through an affine map with no channel mixing (a scale and an offset per
    channel) as its own scale and bias, composed after those it has (``t * s' + b'`` then ``* a + c``):
    MaterialX applies them after the lookup, in its working space, where the formulas run (the writer's
    multiply/add nodes). For a texture that cannot be baked (a UDIM set, an image outside the asset's
    folder): it stays the same file, resolution and tiles."""
    width = _WIDTH.get(source_parameter.type)
    texture = entry.value
    if width is None or target_parameter.type != source_parameter.type or texture.normal_map is not None \
            or source_parameter.role in ("normal", "tangent"):
        return None
    low, high = _domain(source_parameter)
    expression = fit(g, source_parameter.type, target_parameter.type, low, high, _hard_range(target_parameter))
    if expression is None or expression.kind != "affine" or \
            not np.allclose(expression.matrix, np.diag(np.diag(expression.matrix)), atol=1e-12):
        return None
    if expression.clamp is not None:
        return None  # the result would leave the target's range, where a bake clamps per texel
    scale, offset = np.diag(expression.matrix), expression.offset
    old_scale, old_bias = _wide(texture.scale, 1.0, width), _wide(texture.bias, 0.0, width)
    new_scale, new_bias = old_scale * scale, old_bias * scale + offset
    shown = (lambda v: float(v[0])) if width == 1 else (lambda v: tuple(float(x) for x in v))  # noqa: E731
    moved = dataclasses.replace(texture, scale=None if np.all(new_scale == 1.0) else shown(new_scale),
                                bias=None if np.all(new_bias == 0.0) else shown(new_bias))
    return Input(target_parameter.name, target_parameter.type, moved, entry.location, colorspace=entry.colorspace), \
        expression


def _wide(value, identity: float, width: int) -> np.ndarray:
    """A texture's scale or bias (None: ``identity``) as ``width`` components."""
    flat = np.asarray(identity if value is None else value, dtype=np.float64).reshape(-1)
    return flat[:width] if flat.size >= width else np.full(width, flat[0])


def scaled_texture(material, mapping, textured, values, working, parameter, ignored, gltf_file: bool) -> Input | None:
    """A single texture a formula maps affinely per channel, carried with that map as its scale and bias
    (:func:`express`), for an output that writes them (.mtlx, USD; a glTF texture has no bias
    and its factors are per slot); None otherwise."""
    if gltf_file or len(textured) != 1 or not isinstance(material.inputs[textured[0]].value, Texture):
        return None
    kept = express(material, mapping, textured, values, working, parameter, ignored)
    return kept[0] if kept is not None else None
