"""The ``openpbr`` command line: a thin click front end over :mod:`openpbr_tools`."""
