"""``python -m stability``: the same command as the ``stability`` console script."""

from .cli import main

raise SystemExit(main())
