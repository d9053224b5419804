"""``python -m stability``: the same command as the ``stability`` console script."""

from .cli.main import console

raise SystemExit(console())
