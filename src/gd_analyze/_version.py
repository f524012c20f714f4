"""The tool's version, from the installed package's metadata."""

from importlib import metadata as _metadata

try:
    __version__ = _metadata.version("gd-analyze")
except _metadata.PackageNotFoundError:  # running from a source tree that is not installed
    __version__ = "0.0.0+unknown"

#: The version under a public name (what the other modules import).
VERSION = __version__
