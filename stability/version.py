"""The package's version: the installed distribution's, or ``0.1.0`` in a source tree that was
not installed.

A module of its own, importing nothing of the package, so that the modules recording it (chunk
stores, Datasets, the command line) take it from here rather than from the package's top level,
which imports them.
"""

from importlib.metadata import PackageNotFoundError, version

try:
    __version__ = version("stability")
except PackageNotFoundError:  # running from a source tree that was not installed
    __version__ = "0.1.0"

__all__ = ["__version__"]
