"""What OpenPBR's coat does to the base under it: roughening, the base's IOR relative to the
coat's, darkening by internal reflection and absorption by the coat's colour.

The evaluator (:mod:`.openpbr`) and the translators (:mod:`openpbr_tools.translate`) both call
these functions, so the physics is written once. Every function is vectorised: arguments are
NumPy arrays (or numbers) that broadcast against each other; colours carry a trailing RGB axis,
and scalar parameters mixed with colours must already carry a trailing axis of length 1 (the
evaluator's ``as_colour``).
"""

from __future__ import annotations

import numpy as np

from .fresnel import ior_to_f0


def coat_roughened(roughness, coat_weight, coat_roughness):
    """The base's roughness under a coat: the coat's microfacets spread the base's lobe,
    r' = min(1, (r^4 + 2 r_c^4)^(1/4)), mixed with r by the coat's weight.

    Reference: OpenPBR Surface 1.1, section "Coat" (roughening of the base by the coat); MaterialX
    ``open_pbr_surface`` graph (``coat_affected_specular_roughness``).
    """
    target = np.minimum(1.0, (roughness ** 4 + 2.0 * coat_roughness ** 4) ** 0.25)
    return roughness + coat_weight * (target - roughness)


def coat_relative_ior(specular_ior, coat_ior, coat_weight):
    """The IOR of the base's specular interface under a coat: the ratio n_b / n_c, inverted when
    below 1 (the specification's fix against total internal reflection), mixed with n_b by the
    coat's weight.

    Reference: OpenPBR Surface 1.1, section "Coat" (the base's Fresnel under the coat uses the
    relative IOR); MaterialX ``open_pbr_surface`` graph. IORs are used as given: callers floor
    them where 0 is possible.
    """
    ratio = specular_ior / coat_ior
    ratio = np.where(ratio > 1.0, ratio, coat_ior / specular_ior)
    return specular_ior + (ratio - specular_ior) * coat_weight


def coat_darkening_factor(base_color, base_metalness, specular_weight, subsurface_weight, subsurface_color,
                          coat_weight, coat_darkening, coat_ior):
    """The view-independent darkening of the base under a coat, by internal reflection at the
    coat's top: K = 1 - (1 - F0(n_c)) / n_c^2 (the coat's internal diffuse reflectance),
    factor = (1 - K) / (1 - E_base K) with the base's albedo estimated as
    E_base = mix(mix(base_color, subsurface_color, subsurface_weight), base_color * specular_weight,
    base_metalness), blended with 1 by coat_weight x coat_darkening.

    Reference: OpenPBR Surface 1.1, section "Coat" ("Coat darkening"); MaterialX
    ``open_pbr_surface`` graph, which evaluates it view-independently as here.
    """
    amount = np.asarray(coat_weight) * np.asarray(coat_darkening)
    if not np.any(amount):  # no coat, or no darkening: 1 everywhere (a texture's worth of arithmetic saved)
        shapes = [np.shape(v) for v in (base_color, base_metalness, specular_weight, subsurface_weight,
                                        subsurface_color, coat_weight, coat_darkening, coat_ior)]
        return np.ones(np.broadcast_shapes(*shapes))
    f0 = ior_to_f0(coat_ior)
    k = 1.0 - (1.0 - f0) / (coat_ior * coat_ior)
    dielectric = base_color + subsurface_weight * (subsurface_color - base_color)
    metal = base_color * specular_weight
    e_base = dielectric + base_metalness * (metal - dielectric)
    factor = (1.0 - k) / (1.0 - e_base * k)
    return 1.0 + (factor - 1.0) * amount


def coat_absorption(coat_color, coat_weight):
    """The coat's absorption of the light reaching the base, mix(1, coat_color, coat_weight): a
    view-independent factor on everything under the coat.

    Reference: OpenPBR Surface 1.1, section "Coat" (coat_color as the coat's transmittance);
    Autodesk Standard Surface 1.0.1, section "Coat" (the same mix by ``coat``).
    """
    return 1.0 + (coat_color - 1.0) * coat_weight


#: The projected-hemisphere mean of Schlick's transmission shape 1 - (1 - mu)^5:
#: integral of (1 - (1 - mu)^5) 2 mu dmu over [0, 1] = 1 - 2 B(2, 6) = 20 / 21.
SCHLICK_TRANSMISSION_MEAN = 20.0 / 21.0


def coat_emission_factor(coat_color, coat_weight, coat_ior):
    """What OpenPBR's coat does to the emission beneath it, as one view-independent colour:
    mix(1, coat_color (1 - F0(coat_ior)) T, coat_weight) with T the projected-hemisphere mean of
    the Schlick transmission 1 - (1 - mu)^5 (:data:`SCHLICK_TRANSMISSION_MEAN`), for targets whose
    clear coat leaves emission alone (glTF, UsdPreviewSurface: MaterialX's ``gltf_pbr`` and
    ``UsdPreviewSurface`` graphs add their emission on top).

    Reference: OpenPBR Surface 1.1, section "Emission" (the coat tints and Fresnel-attenuates the
    emission); MaterialX ``open_pbr_surface`` graph (``coat_tinted_emission_edf`` through
    ``generalized_schlick_edf`` with color0 = 1 - F0, mixed by coat_weight), which the evaluator's
    :meth:`~.openpbr.OpenPBRSurface.emission` follows per view angle.
    """
    through = np.asarray(coat_color) * ((1.0 - ior_to_f0(coat_ior)) * SCHLICK_TRANSMISSION_MEAN)
    return 1.0 + (through - 1.0) * coat_weight
