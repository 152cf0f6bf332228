"""A normal carried as a captured node graph between UsdPreviewSurface and the models with world-space normals.

UsdPreviewSurface's ``normal`` is a tangent-space vector in [-1, 1] (its specification: "Expects normal in tangent
space [(-1,-1,-1), (1,1,1)]"; MaterialX's ND_UsdPreviewSurface_surfaceshader graph applies its own ``normalmap``
to it), where OpenPBR's ``geometry_normal`` and Standard Surface's ``normal`` take a world-space vector (a
``normalmap`` node's output). Rewired as it is, a graph is decoded twice on the way to the preview (the red team's
K-01: a GPUOpen wood's normal map, 7.5 mean CIEDE2000 in MaterialX's renderer where MaterialX's own chain gave 0.4)
or not at all on the way back (K-07: 12.4). :func:`carried_normal` re-expresses it with MaterialX nodes
(:mod:`openpbr_tools.io.mtlx.expression`); a world-space graph that does not end in a ``normalmap`` has no
tangent-space form and is reported as not carried. Textures are the writers' concern (``Texture.normal_map``).
"""

from __future__ import annotations

import dataclasses

from ..model import Connection, Input

TANGENT_SPACE_MODELS = ("UsdPreviewSurface",)


def carried_normal(entry: Input, source_model: str, target_model: str) -> tuple[Input | None, str | None]:
    """(``entry`` as the target's normal takes it, or None where it cannot be, and what was done) for a normal
    input fed by a captured graph; ``entry`` unchanged, with no note, where both models agree on the space."""
    connection = entry.value
    to_tangent = target_model in TANGENT_SPACE_MODELS
    if to_tangent == (source_model in TANGENT_SPACE_MODELS) or not isinstance(connection, Connection) \
            or not connection.graph_xml:
        return entry, None
    # lazy: MaterialX (~10 ms) is loaded only for a normal graph that changes space
    from ..io.mtlx.expression import ExpressionError, normal_to_tangent, normal_to_world

    try:
        graph_xml, output = (normal_to_tangent if to_tangent else normal_to_world)(connection.graph_xml,
                                                                                connection.output or "")
    except ExpressionError as error:
        return None, f"its graph has no tangent-space form ({error})"
    carried = dataclasses.replace(entry, value=dataclasses.replace(connection, graph_xml=graph_xml, output=output))
    what = ("the graph's normalmap input decoded to a tangent-space vector (t * 2 - 1), the normalmap left out"
            if to_tangent else "the tangent-space normal decoded by a normalmap node (x * 0.5 + 0.5 into normalmap)")
    return carried, what
