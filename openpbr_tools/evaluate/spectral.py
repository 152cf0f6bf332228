"""The visible spectrum the thin-film evaluator samples, and its projection to linear Rec.709.

Kept apart from :mod:`.thinfilm` so that :mod:`.albedo`, which stores these weights with its
tables, and :mod:`.thinfilm`, which reads them from the tables, do not import each other.
"""

from __future__ import annotations

import warnings

import numpy as np

#: Wavelengths (nm) at which the film is evaluated.
WAVELENGTHS_NM = np.arange(380.0, 781.0, 5.0)


def spectral_to_rgb_weights():
    """Weights W (3 x len(WAVELENGTHS_NM)) with RGB = W @ R(lambda): CIE 1931 2-degree CMFs times
    the D65 spectrum, normalised so that sum(ybar D65) = 1, then XYZ -> linear Rec.709 (sRGB
    primaries, D65 white). Each row is finally rescaled to sum to 1 (a correction of about 1e-4:
    the 5 nm sampled white differs that much from the nominal D65 chromaticity), so a spectrally
    flat reflectance maps to equal RGB. Computed with colour-science, stored with the tables."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        import colour  # lazy: colour-science costs ~0.5 s to import (only when the tables are rebuilt)

    shape = colour.SpectralShape(float(WAVELENGTHS_NM[0]), float(WAVELENGTHS_NM[-1]), 5.0)
    cmfs = colour.MSDS_CMFS["CIE 1931 2 Degree Standard Observer"].copy().align(shape)
    d65 = colour.SDS_ILLUMINANTS["D65"].copy().align(shape)
    xyz_weights = cmfs.values * d65.values[:, None]
    xyz_weights = xyz_weights / np.sum(xyz_weights[:, 1])
    m = colour.RGB_COLOURSPACES["sRGB"].matrix_XYZ_to_RGB
    weights = m @ xyz_weights.T
    return weights / np.sum(weights, axis=1, keepdims=True)
