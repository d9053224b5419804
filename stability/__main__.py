"""``python -m stability``: the same command as the ``stability`` console script."""

from .cli import console

raise SystemExit(console())
