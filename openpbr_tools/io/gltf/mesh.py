"""A UV sphere for previewing materials in any glTF viewer: positions, normals, tangents and UVs.

Longitude ``phi = 2 pi u`` and colatitude ``theta = pi v``, with ``v = 0`` at the north pole (+Y),
because glTF's V axis points down the image (specification 3.8.4.4): the top of a texture lands on
the top of the sphere, and ``u = 0`` faces +Z, the default camera. Tangents follow increasing U,
``(cos phi, 0, -sin phi)``, well defined at the poles too; with ``w = +1`` the bitangent
``cross(N, T) * w`` points to decreasing V, the +Y (green-up) direction glTF normal maps use.
Triangles wind counter-clockwise seen from outside (glTF front faces); the degenerate half of each
quad touching a pole is left out.
"""

from __future__ import annotations

import numpy as np


def uv_sphere(rings: int = 16, segments: int = 32, radius: float = 1.0) -> dict:
    """``{"POSITION", "NORMAL", "TANGENT", "TEXCOORD_0", "indices"}`` as little-endian NumPy arrays
    (float32 attributes, uint16 indices)."""
    v = np.linspace(0.0, 1.0, rings + 1)
    u = np.linspace(0.0, 1.0, segments + 1)
    vv, uu = np.meshgrid(v, u, indexing="ij")
    theta, phi = np.pi * vv, 2.0 * np.pi * uu
    normal = np.stack([np.sin(theta) * np.sin(phi), np.cos(theta), np.sin(theta) * np.cos(phi)], axis=-1)
    normal[0, :] = (0.0, 1.0, 0.0)  # exact poles: sin(pi) is not 0 in floating point
    normal[-1, :] = (0.0, -1.0, 0.0)
    tangent = np.stack([np.cos(phi), np.zeros_like(phi), -np.sin(phi), np.ones_like(phi)], axis=-1)
    normal = normal.reshape(-1, 3).astype("<f4")
    normal /= np.linalg.norm(normal, axis=1, keepdims=True)
    tangent = tangent.reshape(-1, 4).astype("<f4")
    tangent[:, :3] /= np.linalg.norm(tangent[:, :3], axis=1, keepdims=True)
    position = (normal * np.float32(radius)).astype("<f4")
    texcoord = np.stack([uu, vv], axis=-1).reshape(-1, 2).astype("<f4")
    indices = []
    width = segments + 1
    for i in range(rings):
        for j in range(segments):
            a, b, c, d = i * width + j, (i + 1) * width + j, (i + 1) * width + j + 1, i * width + j + 1
            if i != rings - 1:
                indices += (a, b, c)
            if i != 0:
                indices += (a, c, d)
    return {"POSITION": position, "NORMAL": normal, "TANGENT": tangent, "TEXCOORD_0": texcoord,
            "indices": np.asarray(indices, dtype="<u2")}
