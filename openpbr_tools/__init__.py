"""openpbr-tools: read, validate, translate and verify OpenPBR Surface materials.

The library returns data and never prints; the ``openpbr`` command (package ``cli``) is the front end.
"""

__version__ = "0.1.0"
