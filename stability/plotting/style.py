"""Shared figure helpers: one look for every figure, labels that carry units, PNG + PDF output.

Figures are built on ``matplotlib.figure.Figure`` directly (no ``pyplot``), so making them never
opens a window, needs no display and leaves no global state behind. Every axis label is written
``"quantity (unit)"`` by :func:`label`; :func:`missing_units` lists the axes that break that rule
(the tests call it on every figure).
"""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
from matplotlib.figure import Figure

from ..output.publish import disk_error

#: Colours of body axes 1, 2, 3 in every figure (colour-blind safe, from matplotlib's tab10).
AXIS_COLORS = ("#1f77b4", "#ff7f0e", "#2ca02c")
#: Colour of exact / analytic curves drawn over numerical results.
EXACT_COLOR = "black"
#: Colour of an ensemble's median and its spread band.
ENSEMBLE_COLOR = "#1f77b4"

#: UDUNITS strings (as stored in Datasets) written the way a reader expects on an axis.
_PRETTY_UNITS = {
    "rad s-1": "rad/s",
    "s-1": "1/s",
    "s-2": "1/s²",
    "kg m2": "kg m²",
    "kg m2 s-1": "kg m²/s",
    "1": "dimensionless",
    "": "dimensionless",
}

FORMATS = ("png", "pdf", "svg")

_STYLE = {
    "font.size": 10,
    "axes.titlesize": 10,
    "axes.labelsize": 10,
    "legend.fontsize": 8.5,
    "axes.grid": True,
    "grid.alpha": 0.3,
    "axes.spines.top": False,
    "axes.spines.right": False,
    "savefig.dpi": 150,
}


def pretty_unit(unit: str) -> str:
    """A UDUNITS unit string (``"rad s-1"``) as shown on an axis (``"rad/s"``)."""
    return _PRETTY_UNITS.get(unit, unit)


def label(quantity: str, unit: str) -> str:
    """Axis label ``"quantity (unit)"``; ``unit`` in UDUNITS spelling or as shown."""
    return f"{quantity} ({pretty_unit(unit)})"


def new_figure(width: float = 7.0, height: float = 4.5) -> Figure:
    """An empty figure with constrained layout; size in inches. Build it inside :func:`styled`."""
    return Figure(figsize=(width, height), layout="constrained")


def plain_log_ticks(ax, axis="both"):
    """Label a log axis spanning a few decades with plain numbers at 1, 2 and 5 times the
    powers of ten (0.5, 1, 2, 5, 10, ...), instead of overlapping powers of ten."""
    from matplotlib.ticker import LogLocator, NullFormatter, StrMethodFormatter

    for which in ("x", "y") if axis == "both" else (axis,):
        target = ax.xaxis if which == "x" else ax.yaxis
        target.set_major_locator(LogLocator(base=10.0, subs=(1.0, 2.0, 5.0)))
        target.set_major_formatter(StrMethodFormatter("{x:g}"))
        target.set_minor_formatter(NullFormatter())


def styled(function):
    """Decorator: build the figure inside the package's rc style (fonts, grid, spines)."""
    import functools

    import matplotlib as mpl

    @functools.wraps(function)
    def wrapper(*args, **kwargs):
        with mpl.rc_context(_STYLE):
            return function(*args, **kwargs)

    return wrapper


def save(fig: Figure, out_dir, stem: str, formats=("png", "pdf"), dpi: int = 150) -> list[Path]:
    """Write ``fig`` as ``out_dir/stem.<format>`` for each format; return the paths written.

    The file is written under a temporary name and renamed, so an interrupted run never leaves
    a truncated figure behind. The layout is worked out once, by the first format drawn, and
    kept for the others (constrained layout takes about half of each drawing); the figure's
    layout engine is given back afterwards.
    """
    out_dir = Path(out_dir)
    for fmt in formats:
        if fmt not in FORMATS:
            raise ValueError(f"figure format must be one of {', '.join(FORMATS)}, got {fmt!r}")
    engine = fig.get_layout_engine()
    paths = []
    try:
        for k, fmt in enumerate(formats):
            if k == 1 and engine is not None:
                fig.set_layout_engine("none")  # keep the positions the first drawing settled
            path = out_dir / f"{stem}.{fmt}"
            partial = out_dir / f".{stem}.{fmt}.part"
            try:
                fig.savefig(partial, format=fmt, dpi=dpi)
                partial.replace(path)
            except OSError as exc:  # a full disk, a vanished folder: one line naming both
                partial.unlink(missing_ok=True)
                raise disk_error(exc, path) from exc
            paths.append(path)
    finally:
        if engine is not None:
            fig.set_layout_engine(engine)
    return paths


_UNIT_IN_LABEL = re.compile(r"\(([^()]+)\)\s*$")


def missing_units(fig: Figure) -> list[str]:
    """Axis labels of ``fig`` that do not end in ``(unit)``; empty when every axis is labelled.

    Checks the x and y (and, for 3-D axes, z) labels of every visible axes; an axis whose tick
    labels are hidden (the upper panels of a shared x axis) is labelled by its neighbour and
    skipped; colour bars count as axes too.
    """
    problems = []
    for k, ax in enumerate(fig.axes):
        if not ax.get_visible() or not ax.axison:
            continue
        getters = {"x": ax.get_xlabel, "y": ax.get_ylabel}
        if hasattr(ax, "get_zlabel"):
            getters["z"] = ax.get_zlabel
        title = ax.get_title() or f"axes {k}"
        for name, get in getters.items():
            if name in ("x", "y") and _colorbar_side(ax) not in (None, name):
                continue
            if not _shows_tick_labels(ax, name):
                continue  # e.g. the upper panels of a shared x axis: labelled below
            text = get()
            if not _UNIT_IN_LABEL.search(text or ""):
                problems.append(f"{title}: {name} label {text!r} has no unit")
    return problems


def _shows_tick_labels(ax, name) -> bool:
    axis = {"x": ax.xaxis, "y": ax.yaxis}.get(name)
    if axis is None:
        return True
    ticks = axis.get_major_ticks()
    return not ticks or any(t.label1.get_visible() or t.label2.get_visible() for t in ticks)


def _colorbar_side(ax):
    """For a colour bar's axes, the side ("x" or "y") that carries its label; else None."""
    if getattr(ax, "_colorbar", None) is None:
        return None
    return "y" if ax._colorbar.orientation == "vertical" else "x"


#: Where :func:`place_legend` tries a legend, in order, before putting it beside the axes.
LEGEND_PLACES = ("best", "upper right", "upper left", "lower left", "lower right",
                 "center left", "center right", "upper center", "lower center")


def place_legend(ax, **kwargs):
    """A legend on ``ax`` where it covers none of the data (:func:`covered_data`).

    Tries :data:`LEGEND_PLACES` inside the axes and puts the legend beside the axes, on the
    right, when none is clear. ``kwargs`` go to ``ax.legend``. The figure is laid out once: a
    legend inside the axes moves nothing else, and each place's box is measured with that
    layout's renderer.
    """
    if ax.get_legend() is not None:  # one beside the axes would shrink them in that layout
        ax.get_legend().remove()
    renderer = _drawn(ax.get_figure(root=True))
    for place in LEGEND_PLACES:
        legend = ax.legend(loc=place, **kwargs)
        if not _legend_hits(ax, renderer):
            return legend
    return ax.legend(loc="upper left", bbox_to_anchor=(1.02, 1.0), borderaxespad=0.0, **kwargs)


def covered_data(fig: Figure) -> list[str]:
    """Legends of ``fig`` drawn over its data; empty when every legend is clear of it.

    Lays the figure out (as saving does), then follows every line of every axes in display
    coordinates, :data:`SAMPLES_PER_SEGMENT` points along each segment between its vertices
    (so a line that crosses a legend between two markers counts), and every scatter point, and
    names each axes whose legend box holds any of them, with how many.
    """
    renderer = _drawn(fig)
    problems = []
    for k, ax in enumerate(fig.axes):
        hits = _legend_hits(ax, renderer)
        if hits:
            problems.append(f"{ax.get_title() or f'axes {k}'}: the legend covers {hits} "
                            "points of data")
    return problems


#: Points per segment between a line's vertices that :func:`covered_data` looks at.
SAMPLES_PER_SEGMENT = 24


def _drawn(fig):
    """Lay ``fig`` out as drawing it would, without rendering pixels (on an Agg canvas if it
    has none); the renderer to measure it with."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    if not hasattr(fig.canvas, "get_renderer"):
        FigureCanvasAgg(fig)
    fig.draw_without_rendering()
    return fig.canvas.get_renderer()


def _legend_hits(ax, renderer) -> int:
    """Data points of ``ax`` (lines followed along their segments, scatter points) that its
    legend box covers; 0 without a legend."""
    legend = ax.get_legend()
    if legend is None or not legend.get_visible():
        return 0
    box = legend.get_window_extent(renderer)
    clip = ax.get_window_extent(renderer)
    hits = 0
    for line in ax.get_lines():
        if not line.get_visible():
            continue
        xy = line.get_transform().transform(np.column_stack(line.get_data()).astype(float))
        xy = xy[np.all(np.isfinite(xy), axis=1)]
        if len(xy) > 1:
            steps = np.linspace(0.0, 1.0, SAMPLES_PER_SEGMENT, endpoint=False)[None, :, None]
            xy = np.concatenate([(xy[:-1, None] + steps * (xy[1:] - xy[:-1])[:, None])
                                 .reshape(-1, 2), xy[-1:]])
        hits += _inside(xy, box, clip)
    for collection in ax.collections:
        offsets = collection.get_offsets()
        if collection.get_visible() and len(offsets):
            xy = collection.get_offset_transform().transform(np.asarray(offsets, float))
            hits += _inside(xy[np.all(np.isfinite(xy), axis=1)], box, clip)
    return hits


def _inside(xy, box, clip) -> int:
    """Points of ``xy`` (display coordinates) inside ``box`` and within the axes ``clip``."""
    if not len(xy):
        return 0
    x, y = xy[:, 0], xy[:, 1]
    shown = (x >= clip.x0) & (x <= clip.x1) & (y >= clip.y0) & (y <= clip.y1)
    return int(np.sum(shown & (x >= box.x0) & (x <= box.x1) & (y >= box.y0) & (y <= box.y1)))
