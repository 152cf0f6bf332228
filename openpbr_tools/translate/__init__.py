"""Translations between shading models and versions: each direction a module whose docstring lists
what is exact, what is approximated and what is dropped, and which reports every loss."""
