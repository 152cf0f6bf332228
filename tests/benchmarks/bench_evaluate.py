"""Throughput of the lobe evaluator: full OpenPBR BSDF evaluations per second on one core, and
the time of a 128 x 128 lit-sphere preview.

Run as a script (one core is enforced through the BLAS/OpenMP thread variables, set before NumPy
is imported)::

    python tests/benchmarks/bench_evaluate.py

or with pytest-benchmark (excluded from the default test run)::

    OMP_NUM_THREADS=1 OPENBLAS_NUM_THREADS=1 python -m pytest -n 0 tests/benchmarks/bench_evaluate.py

Targets: at least 1 million evaluations per second, a preview under 0.5 s.
"""

from __future__ import annotations

import os

for _name in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS", "NUMEXPR_NUM_THREADS"):
    os.environ.setdefault(_name, "1")

import time  # noqa: E402

import numpy as np  # noqa: E402

from openpbr_tools.evaluate import albedo, build_model  # noqa: E402
from openpbr_tools.evaluate.preview import Rig, shade_sphere  # noqa: E402

EVALUATIONS = 1_000_000

MATERIALS = {
    "default (EON diffuse + GGX dielectric)": {},
    "metal (F82 tint)": {"base_metalness": 1.0, "specular_color": [0.8, 0.9, 1.0]},
    "every lobe but thin film": {
        "base_diffuse_roughness": 0.5, "base_metalness": 0.3, "specular_roughness_anisotropy": 0.4,
        "transmission_weight": 0.3, "subsurface_weight": 0.3, "fuzz_weight": 0.5, "coat_weight": 0.6,
    },
    "every lobe with thin film": {
        "base_diffuse_roughness": 0.5, "base_metalness": 0.3, "specular_roughness_anisotropy": 0.4,
        "transmission_weight": 0.3, "subsurface_weight": 0.3, "fuzz_weight": 0.5, "coat_weight": 0.6,
        "thin_film_weight": 1.0,
    },
}


def random_directions(n: int, seed: int) -> np.ndarray:
    rng = np.random.default_rng(seed)
    v = rng.normal(size=(n, 3))
    v /= np.linalg.norm(v, axis=1, keepdims=True)
    v[:, 2] = np.abs(v[:, 2])
    return v


def evaluations_per_second(values: dict, n: int = EVALUATIONS, repeats: int = 3) -> float:
    model = build_model("open_pbr_surface", values)
    wi, wo = random_directions(n, 1), random_directions(n, 2)
    best = np.inf
    for _ in range(repeats):
        start = time.perf_counter()
        model.evaluate(wi, wo)
        best = min(best, time.perf_counter() - start)
    return n / best


def preview_seconds(values: dict, repeats: int = 5) -> float:
    model = build_model("open_pbr_surface", values)
    best = np.inf
    for _ in range(repeats):
        start = time.perf_counter()
        shade_sphere(model, Rig(size=128))
        best = min(best, time.perf_counter() - start)
    return best


# ---------------------------------------------------------------- pytest-benchmark


def test_bsdf_throughput(benchmark):
    albedo.tables()
    model = build_model("open_pbr_surface", MATERIALS["every lobe but thin film"])
    wi, wo = random_directions(EVALUATIONS, 1), random_directions(EVALUATIONS, 2)
    benchmark(model.evaluate, wi, wo)


def test_preview_128(benchmark):
    albedo.tables()
    model = build_model("open_pbr_surface", MATERIALS["every lobe with thin film"])
    benchmark(shade_sphere, model, Rig(size=128))


if __name__ == "__main__":
    albedo.tables()
    print(f"{'material':42s} {'BSDF evals/s (1 core)':>22s} {'128x128 preview':>16s}")
    for label, values in MATERIALS.items():
        rate = evaluations_per_second(values)
        seconds = preview_seconds(values)
        print(f"{label:42s} {rate / 1e6:19.2f} M {seconds * 1000:13.1f} ms")
