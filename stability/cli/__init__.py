"""The ``stability`` command: :mod:`.main` (the parser and its subcommands) and :mod:`.bench`
(``stability bench``)."""

from .main import console, main

__all__ = ["console", "main"]
