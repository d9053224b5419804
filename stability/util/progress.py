"""A progress bar for long loops over runs, shown on a terminal and silent elsewhere."""

from __future__ import annotations

import sys


class _NoBar:
    """The bar's interface, doing nothing."""

    def update(self, n=1):
        pass

    def set_postfix_str(self, text):
        pass

    def close(self):
        pass


def progress_bar(total: int, progress=None, desc: str = "", unit: str = "it"):
    """A ``tqdm`` bar over ``total`` items, or one that does nothing.

    Parameters
    ----------
    total : int
    progress : bool or None
        True: show it; False: never; None (default): only when stderr is a terminal.
    desc, unit : str
        Label of the bar and of its items.

    Returns
    -------
    object
        With ``update(n)``, ``set_postfix_str(text)`` and ``close()``.
    """
    if progress is False or (progress is None and not sys.stderr.isatty()):
        return _NoBar()
    from tqdm.auto import tqdm

    return tqdm(total=total, desc=desc, unit=unit, leave=False)
