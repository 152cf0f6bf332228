"""The lobes of the evaluator in one namespace: GGX microfacet (:mod:`.microfacet`), diffuse
(:mod:`.diffuse`), sheen (:mod:`.sheen`), Fresnel (:mod:`.fresnel`) and thin film
(:mod:`.thinfilm`). Each function's docstring names the publication and equation it implements.
"""

from __future__ import annotations

from .diffuse import (
    eon_albedo,
    eon_diffuse,
    fujii_oren_nayar,
    fujii_oren_nayar_albedo,
    fujii_oren_nayar_average_albedo,
    lambert,
    oren_nayar,
    translucent,
)
from .fresnel import artistic_ior, f0_to_ior, f82_tint, fresnel_conductor, fresnel_dielectric, fresnel_schlick, ior_to_f0
from .microfacet import (
    ggx_lambda,
    ggx_ndf,
    ggx_reflection,
    ggx_transmission,
    sample_ggx_vnormal,
    smith_g1,
    smith_g2_height_correlated,
)
from .sheen import (
    ashikhmin_visibility,
    charlie_lambda,
    charlie_ndf,
    conty_kulla_sheen,
    zeltner_ltc_distribution,
    zeltner_sheen,
    zeltner_sheen_albedo,
)
from .thinfilm import airy_reflectance, thin_film_rgb

__all__ = [
    "airy_reflectance",
    "artistic_ior",
    "ashikhmin_visibility",
    "charlie_lambda",
    "charlie_ndf",
    "conty_kulla_sheen",
    "eon_albedo",
    "eon_diffuse",
    "f0_to_ior",
    "f82_tint",
    "fresnel_conductor",
    "fresnel_dielectric",
    "fresnel_schlick",
    "fujii_oren_nayar",
    "fujii_oren_nayar_albedo",
    "fujii_oren_nayar_average_albedo",
    "ggx_lambda",
    "ggx_ndf",
    "ggx_reflection",
    "ggx_transmission",
    "ior_to_f0",
    "lambert",
    "oren_nayar",
    "sample_ggx_vnormal",
    "smith_g1",
    "smith_g2_height_correlated",
    "thin_film_rgb",
    "translucent",
    "zeltner_ltc_distribution",
    "zeltner_sheen",
    "zeltner_sheen_albedo",
]
