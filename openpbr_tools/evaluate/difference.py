"""CIEDE2000 colour differences between previews or albedo curves (via colour-science).

Linear Rec.709 RGB is converted to CIE XYZ with the sRGB colourspace's matrix, scaled so that
the reference white has Y = 1, then to CIELAB relative to the D65 white point as that matrix
realises it (the XYZ of RGB = 1, so equal RGB values are neutral, a* = b* = 0), CIE 1931
2-degree observer, and compared with CIEDE2000 (Sharma, Wu, Dalal, "The CIEDE2000
Color-Difference Formula: Implementation Notes, Supplementary Test Data, and Mathematical
Observations", Color Research & Application 30(1), 2005).

Exposure: for previews the reference white is the radiance of an ideal white diffuser facing the
key light under the preview rig (:meth:`.preview.Rig.white`), so L* = 100 there; for albedo
curves it is an albedo of 1. Values above the white (highlights) give L* > 100 and are compared
as they are, without clipping or tone mapping.
"""

from __future__ import annotations

import warnings
from dataclasses import asdict, dataclass

import numpy as np


def _colour():
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        import colour  # lazy: colour-science costs ~0.5 s to import
    return colour


def linear_rec709_to_lab(rgb, white: float = 1.0) -> np.ndarray:
    """CIELAB (D65) of linear Rec.709 values, with ``white`` the radiance mapped to Y = 1."""
    colour = _colour()
    matrix = np.asarray(colour.RGB_COLOURSPACES["sRGB"].matrix_RGB_to_XYZ)
    xyz = np.asarray(rgb, dtype=float) @ matrix.T / float(white)
    return colour.XYZ_to_Lab(xyz, colour.XYZ_to_xy(matrix @ np.ones(3)))


def delta_e_2000(rgb_a, rgb_b, white: float = 1.0) -> np.ndarray:
    """Per-element CIEDE2000 between two arrays of linear Rec.709 colours (last axis RGB)."""
    colour = _colour()
    return np.asarray(colour.delta_E(linear_rec709_to_lab(rgb_a, white), linear_rec709_to_lab(rgb_b, white), method="CIE 2000"))


@dataclass
class DeltaE:
    """Summary of a colour-difference map: mean, 95th percentile and maximum CIEDE2000, and how
    many samples (pixels or angles) were compared."""

    mean: float
    p95: float
    max: float
    samples: int

    def as_dict(self) -> dict:
        return asdict(self)

    def exceeds(self, threshold: float) -> bool:
        """The mean is above ``threshold`` — or is not a number: a comparison that could not be made
        never passes."""
        return not self.mean <= threshold


def summarize(values) -> DeltaE:
    v = np.asarray(values, dtype=float).ravel()
    if v.size == 0:
        return DeltaE(0.0, 0.0, 0.0, 0)
    return DeltaE(float(np.mean(v)), float(np.percentile(v, 95)), float(np.max(v)), int(v.size))


def compare_images(image_a, image_b, mask=None, white: float = 1.0) -> DeltaE:
    """CIEDE2000 summary over the pixels of ``mask`` (all pixels when None)."""
    a = np.asarray(image_a, dtype=float)
    b = np.asarray(image_b, dtype=float)
    if mask is not None:
        a, b = a[mask], b[mask]
    return summarize(delta_e_2000(a, b, white))


def compare_albedo(albedo_a, albedo_b) -> DeltaE:
    """CIEDE2000 summary between two directional-albedo curves (RGB per angle; white = 1)."""
    return summarize(delta_e_2000(albedo_a, albedo_b, 1.0))
