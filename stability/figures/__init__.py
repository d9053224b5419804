"""Figures, one module per figure family, built on the helpers in :mod:`.style`.

- :mod:`.tennis`: the tennis-racket study (flips against the exact solution, polhodes,
  ensemble growth, flip intervals).

Every function returns a ``matplotlib.figure.Figure`` (no ``pyplot`` state) whose axes are all
labelled ``"quantity (unit)"``; :func:`.style.save` writes it as PNG and PDF.
"""

from ..plotting.style import label, missing_units, save

__all__ = ["label", "missing_units", "save"]
