"""Measure per chunk, combine the measurements: what an ensemble keeps of its members.

A study that measures while it runs keeps, for each chunk of members, the chunk's per-member
summaries (variables along ``member``), the time series of the members in its *series sample*
(along ``series_member``, :func:`series_sample`) and additive reductions (histograms over
members, :func:`log_histogram`), never every member's series. :func:`combine_chunks` joins the
chunks of a store into one Dataset in memory: per-member variables in member order, the sampled
series in member order, the reductions summed. Its memory is that of the summaries, whatever
the length of the series.

Quantiles over members of a quantity sampled in time (the median amplitude at each time, say)
come from the summed histograms (:func:`histogram_quantiles`): with log-spaced bins of
relative width ``10**width - 1`` a quantile is found to within one bin, whatever the member
count.
"""

from __future__ import annotations

import math

import numba
import numpy as np
import xarray as xr
from numba import njit, prange

from ..output.io import load
from ..util import conventions as cv

#: Dimension of the members whose time series are kept (:func:`series_sample`).
SERIES_MEMBER = cv.SERIES_MEMBER

#: Members whose time series a study keeps by default: enough for its figures and a look, few
#: enough that the Dataset stays small at any member count.
DEFAULT_SERIES_MEMBERS = 256

#: Width of a log histogram's bins in decades: 0.002 is a relative width of 0.46 %.
LOG_BIN_WIDTH = 0.002

#: The attribute that marks a variable as an additive reduction: summed over chunks.
SUMMED = "summed_over_chunks"

__all__ = ["SERIES_MEMBER", "DEFAULT_SERIES_MEMBERS", "series_count", "series_sample", "sampled_in",
           "log_edges", "log_histogram", "histogram_quantiles", "combine_chunks"]


def series_count(members: int, count) -> int:
    """How many of ``members`` members keep their series for ``[output] series_members =
    count``: ``count`` (at most ``members``), or every member for ``"all"``.

    Raises
    ------
    ValueError
        For a word other than ``"all"`` or a negative count.
    """
    if isinstance(count, str):
        if count != "all":
            raise ValueError(f"series_members must be a count of members >= 0 or 'all', "
                             f"got {count!r}")
        return members
    if count < 0:
        raise ValueError(f"series_members must be a count of members >= 0 or 'all', "
                         f"got {count!r}")
    return min(int(count), members)


def series_sample(members: int, count) -> np.ndarray:
    """The members whose time series are kept: ``count`` of ``members``, evenly spread.

    Members ``round(k (members - 1) / (count - 1))`` for k = 0 ... count - 1 (member 0 alone
    for a count of 1): the same members however the run is cut into chunks, on whatever worker
    each runs; ``"all"`` (or a count of at least ``members``) keeps every member.

    Returns
    -------
    ndarray of int64, ascending, unique
    """
    count = series_count(members, count)
    if count == members:
        return np.arange(members, dtype=np.int64)
    if count == 0:
        return np.empty(0, dtype=np.int64)
    if count == 1:
        return np.zeros(1, dtype=np.int64)
    return np.unique(np.rint(np.linspace(0.0, members - 1.0, count)).astype(np.int64))


def sampled_in(sample: np.ndarray, lo: int, hi: int) -> np.ndarray:
    """The members of ``sample`` among ``lo ... hi - 1``, as offsets from ``lo``."""
    inside = sample[(sample >= lo) & (sample < hi)]
    return inside - lo


def log_edges(low: float, high: float, width: float = LOG_BIN_WIDTH) -> np.ndarray:
    """Bin edges ``10**(log10(low) + k width)`` from ``low`` up to at least ``high`` (both > 0).

    Values below the first edge or at or above the last fall in the first and last bin
    (:func:`log_histogram`), so the edges should span every value the quantiles are taken over.
    """
    if not (0.0 < low < high and math.isfinite(high)):
        raise ValueError(f"log histogram edges need 0 < low < high, got {low!r}, {high!r}")
    n = max(1, math.ceil(math.log10(high / low) / width))
    return 10.0 ** (math.log10(low) + width * np.arange(n + 1))


@njit(cache=True, error_model="numpy")
def log_bin(v, log_low, width, n_bins):
    """The bin of a finite ``v > 0`` among ``n_bins`` log bins from ``10**log_low`` of
    ``width`` decades, those below and above in the first and the last (:func:`log_bins`)."""
    k = int(math.floor((math.log10(v) - log_low) / width))
    return min(max(k, 0), n_bins - 1)


def log_bins(edges: np.ndarray) -> tuple[float, float, int]:
    """``(log_low, width, n_bins)`` of the log bins ``edges`` (:func:`log_edges`), for
    :func:`log_bin`."""
    n_bins = edges.size - 1
    log_low = math.log10(edges[0])
    return log_low, (math.log10(edges[-1]) - log_low) / n_bins, n_bins


@njit(cache=True, parallel=True, error_model="numpy")
def _log_counts(values, log_low, width, n_bins, n_blocks):
    n_members, n_times = values.shape
    counts = np.zeros((n_blocks, n_times, n_bins), dtype=np.int32)
    size = (n_members + n_blocks - 1) // n_blocks
    for block in prange(n_blocks):  # each block of members into its own counts: no races
        for i in range(block * size, min(n_members, (block + 1) * size)):
            for t in range(n_times):
                v = values[i, t]
                if math.isfinite(v) and v > 0.0:
                    counts[block, t, log_bin(v, log_low, width, n_bins)] += 1
    return counts.sum(axis=0).astype(np.int32)


def log_histogram(values: np.ndarray, edges: np.ndarray) -> np.ndarray:
    """Counts over members of ``values`` (members, times) in the log bins ``edges``, per time.

    NaN values (members left out) are not counted; values outside the edges are counted in the
    first or the last bin. Additive: the counts of two sets of members sum to those of both.
    Compiled, the members split among Numba's threads.

    Returns
    -------
    ndarray of int32, shape (times, len(edges) - 1)
    """
    values = np.ascontiguousarray(values, dtype=np.float64)
    blocks = max(1, min(numba.get_num_threads(), values.shape[0]))
    return _log_counts(values, *log_bins(edges), blocks)


def histogram_quantiles(counts: np.ndarray, edges: np.ndarray, q) -> np.ndarray:
    """Quantiles ``q`` (in [0, 1]) per time from log-histogram ``counts`` (times, bins).

    As numpy's default quantile ("linear"): the value at rank ``r = q (n - 1)`` of the n
    counted values, interpolated linearly between the values of ranks ``floor(r)`` and
    ``floor(r) + 1``. Each of those is placed inside its bin as the values of a bin are spread
    evenly over it in ``log10``, so each is within one bin of the exact one, and so is the
    quantile. NaN where no value was counted.

    Returns
    -------
    ndarray, shape (times, len(q))
    """
    q = np.atleast_1d(np.asarray(q, dtype=float))
    counts = np.asarray(counts, dtype=np.int64)
    cumulative = np.cumsum(counts, axis=1)
    total = cumulative[:, -1]
    log_e = np.log10(edges)
    out = np.full((counts.shape[0], q.size), np.nan)

    def ranked(t, rank):  # the value of integer rank ``rank`` (0-based) at time t
        k = np.searchsorted(cumulative[t], rank, side="right")  # its bin
        below = np.where(k > 0, cumulative[t][np.maximum(k - 1, 0)], 0)
        place = (rank - below + 0.5) / counts[t][k]
        return 10.0 ** (log_e[k] + place * (log_e[k + 1] - log_e[k]))

    for t in np.flatnonzero(total > 0):
        rank = q * (total[t] - 1)
        j = np.floor(rank)
        lower = ranked(t, j)
        upper = ranked(t, np.minimum(j + 1, total[t] - 1))
        out[t] = lower + (rank - j) * (upper - lower)
    return out


class ChunkJoin:
    """The chunks of a run of ``members`` members joined in memory as they come, in any order.

    Variables along ``member`` are placed at their members (each chunk's from its first member
    ``lo``), those along ``series_member`` are joined in member order; a variable whose
    attributes mark it :data:`SUMMED` (integer counts: the sum does not depend on the order) is
    summed over the chunks; any other, and the attributes, are the lowest chunk's. A chunk is
    let go of once added (but the lowest so far): the memory is the run's summaries and one
    chunk, not twice the summaries.
    """

    def __init__(self, members: int):
        self.members = members
        self.joined: dict[str, np.ndarray] = {}
        self.series: dict[str, list] = {}
        self.summed: dict[str, np.ndarray] = {}
        self.attrs: dict[int, dict] = {}
        self.first = None  # (lo, Dataset) of the lowest chunk so far: its order, coordinates,
        self.names = None  # attributes and other variables; the first added chunk's names
        self.count = 0

    def holds(self, lo: int) -> bool:
        """Whether the chunk of members from ``lo`` is added."""
        return lo in self.attrs

    def add_file(self, lo: int, path) -> None:
        """Add the chunk file ``path`` of members from ``lo``, read as untrusted input."""
        self.add(lo, load(path, math.inf), path)  # in the order it was held

    def add(self, lo: int, ds: xr.Dataset, source="a chunk") -> None:
        """Add the chunk ``ds`` of members ``lo ... lo + n - 1`` (``source`` names it in the
        errors). ValueError if it holds other variables than the chunks before it, or members
        beyond the run's."""
        n = ds.sizes.get(cv.MEMBER, 0)
        if self.names is None:
            self.names = set(ds.variables)
        elif set(ds.variables) != self.names:
            raise ValueError(f"{source} holds other variables than the run's first chunk: "
                             "the store is damaged; run again without --resume")
        if lo + n > self.members:
            raise ValueError(f"{source} holds members beyond the run's {self.members}")
        self.attrs[lo] = dict(ds.attrs)
        for name, var in ds.variables.items():
            if cv.MEMBER in var.dims and var.dims[0] == cv.MEMBER:
                if name not in self.joined:
                    self.joined[name] = np.empty((self.members,) + var.shape[1:],
                                                 dtype=var.dtype)
                self.joined[name][lo:lo + n] = var.values
            elif SERIES_MEMBER in var.dims:
                self.series.setdefault(name, []).append((lo, var))
            elif var.attrs.get(SUMMED):
                total = self.summed.get(name)
                self.summed[name] = var.values.copy() if total is None else total + var.values
        if self.first is None or lo < self.first[0]:
            self.first = (lo, ds)
        self.count += n

    def result(self) -> tuple[xr.Dataset, list]:
        """The whole run, and each chunk's attributes in member order. ValueError if the
        chunks added do not hold the run's members."""
        if self.first is None or self.count != self.members:
            raise ValueError(f"the chunks hold {self.count} members, the run {self.members}: "
                             "the store is damaged; run again without --resume")
        first = self.first[1]
        variables = {}
        for name, var in first.variables.items():
            if name in self.joined:
                variables[name] = xr.Variable(var.dims, self.joined.pop(name), var.attrs)
            elif name in self.series:
                parts = [part for _, part in sorted(self.series[name], key=lambda p: p[0])]
                variables[name] = xr.Variable.concat(parts, SERIES_MEMBER)
            elif name in self.summed:
                variables[name] = xr.Variable(var.dims, self.summed[name], var.attrs,
                                              var.encoding)
            else:
                variables[name] = var
        coords = {name: variables.pop(name) for name in list(variables)
                  if name in first.coords}
        return (xr.Dataset(variables, coords=coords, attrs=self.attrs[min(self.attrs)]),
                [self.attrs[lo] for lo in sorted(self.attrs)])


def combine_chunks(paths, members: int) -> tuple[xr.Dataset, list]:
    """The chunks ``paths`` of a run of ``members`` members, in order, joined in memory
    (:class:`ChunkJoin`), each file read once as untrusted input
    (:func:`stability.output.io.load`).

    Returns
    -------
    ds : xarray.Dataset
    chunk_attrs : list of dict
        Each chunk's attributes, in order (its timings, for the whole run's).

    Raises
    ------
    ValueError
        If the chunks do not hold ``members`` members together, or differ in their variables.
    """
    join = ChunkJoin(members)
    lo = 0
    for path in paths:
        ds = load(path, math.inf)
        join.add(lo, ds, path)
        lo += ds.sizes.get(cv.MEMBER, 0)
    return join.result()
