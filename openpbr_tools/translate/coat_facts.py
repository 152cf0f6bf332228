"""What the translators share about OpenPBR's coat: the inputs its darkening of the base and its effect on
emission read (in the order of :func:`openpbr_tools.evaluate.coat.coat_darkening_factor` and
:func:`~openpbr_tools.evaluate.coat.coat_emission_factor`), and the notes where a target's clear coat does
neither."""

#: The sources of an emission a coat covers, and the note where a target's clear coat leaves emission
#: alone (glTF, UsdPreviewSurface) so the coat's effect is folded into it (evaluate.coat.coat_emission_factor).
EMISSION_UNDER_COAT = ("emission_color", "emission_luminance", "coat_weight", "coat_color", "coat_ior")
COAT_EMISSION_NOTE = ("the coat's tint and Fresnel transmission over the emission are folded into it, averaged over "
                      "view angles (the target's clear coat leaves emission alone)")
COAT_EMISSION_UNDONE = "divided by what OpenPBR's coat does to emission (the source's clear coat leaves it alone)"

#: The OpenPBR inputs besides base_color that evaluate.coat.coat_darkening_factor reads, in its order.
DARKENING_SOURCES = ("base_metalness", "specular_weight", "subsurface_weight", "subsurface_color", "coat_weight",
                     "coat_darkening", "coat_ior")
