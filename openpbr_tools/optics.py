"""Optics facts of the shading models that the validator needs as well as the evaluator, kept free
of NumPy so that validating never loads it."""

#: Cosine at which the F82 tint is specified: theta = 82 degrees, cos = 1/7 (Hoffman 2023;
#: OpenPBR 1.1, "Metal", mu-bar).
F82_COSINE = 1.0 / 7.0
