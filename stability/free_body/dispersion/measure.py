"""A dispersed free-body ensemble: each member its own moments, axes, spin and start, and its
flip interval and growth rate, in closed form for every design point and integrated for some.

A member is tossed about the design's middle axis b with spin W and a nudge of size epsilon in
the direction phi across it: w = W (e_b + epsilon (cos(phi) e_a + sin(phi) e_c)) in the design's
axes, a, b, c the axes of the smallest, middle and largest nominal moments. With the axes
dispersed, the body's principal axes are those of R diag(I) R^T
(:func:`stability.uncertainty.inertia.dispersed_tensor`), and the start is taken into them,
w_p = A^T w: a misalignment is a further nudge. Outputs per member:

- the exact flip interval 2K/nu (:func:`stability.free_body.exact.motion`, Jacobi's complete
  integral K and the frequency nu of the elliptic solution), in s;
- the linear growth rate lambda = W sqrt((Ib - Ia)(Ic - Ib) / (Ia Ic))
  (:func:`stability.free_body.model.growth_rate`, sqrt(-Omega^2) of the middle axis), in s-1;
- for the first members asked, the flip interval of the integrated motion
  (:func:`stability.run_scene`, one group per member: each member's moments are its group's
  parameter set), the mean spacing of the middle component's sign changes.
"""

from __future__ import annotations

import math

import numpy as np
import xarray as xr
from numba import njit

from ...ensemble.options import RunOptions
from ...ensemble.scene_run import run_scene
from ...uncertainty.dispersions import AXES, Dispersions
from ...uncertainty.inertia import dispersed_tensor
from ..exact import Q_K, Q_KIND, Q_RATE, SEPARATRIX, STEADY, motion
from ..model import growth_rate
from ..scene import FREE_BODY
from .schema import DISPERSION

#: The parameters of a tossed free body a dispersion may name (with the moments and axes).
TOSS = ("rate", "epsilon", "direction")


def nominal(moments, rate: float, epsilon: float, direction: float = 0.0) -> dict:
    """The undispersed values: moments (kg m2), spin W (rad/s), nudge epsilon (1) and its
    direction phi (rad)."""
    I1, I2, I3 = (float(x) for x in moments)
    return {"I1": I1, "I2": I2, "I3": I3, "rate": float(rate), "epsilon": float(epsilon),
            "direction": float(direction)}


def members(disp: Dispersions, unit) -> dict:
    """Each member's draws, and the body and start its kernel runs with.

    Returns
    -------
    dict
        The draws (:meth:`Dispersions.draw`), and ``moments`` (N, 3): the principal moments
        (column k nearest design axis k), ``axes`` (N, 3, 3) and ``tensor`` (N, 3, 3) (with
        the axes dispersed), ``w0`` (N, 3): the start in the principal axes, rad/s, and
        ``spin_axis``: b (0-based).
    """
    out = disp.draw(unit)
    n = out["rate"].size
    design = np.column_stack([out["I1"], out["I2"], out["I3"]])
    a, b, c = np.argsort([disp.nominal[m] for m in ("I1", "I2", "I3")], kind="stable")
    w = np.zeros((n, 3))
    w[:, b] = out["rate"]
    w[:, a] = out["rate"] * out["epsilon"] * np.cos(out["direction"])
    w[:, c] = out["rate"] * out["epsilon"] * np.sin(out["direction"])
    if AXES in disp.distributions:
        out["tensor"], out["moments"], out["axes"] = dispersed_tensor(
            design, out["axes_angle"], out["axes_axis"])
        w = np.einsum("nij,ni->nj", out["axes"], w)  # A^T w
    else:
        out["moments"] = design
    out["w0"], out["spin_axis"] = w, int(b)
    return out


@njit(cache=True, error_model="numpy")
def _flip_intervals(I, w, out):
    """2K/nu of each member (moments ``I`` (N, 3), any order; start ``w`` (N, 3))."""
    for j in range(I.shape[0]):
        a, b, c = 0, 1, 2
        if I[j, a] > I[j, b]:
            a, b = b, a
        if I[j, b] > I[j, c]:
            b, c = c, b
        if I[j, a] > I[j, b]:
            a, b = b, a
        q = motion(I[j, a], I[j, b], I[j, c], w[j, a], w[j, b], w[j, c])
        kind, rate = int(q[Q_KIND]), abs(q[Q_RATE])
        out[j] = math.inf if (kind == STEADY or kind == SEPARATRIX or rate == 0.0) else (
            2.0 * q[Q_K] / rate)


def flip_intervals(moments, w0) -> np.ndarray:
    """The exact flip interval 2K/nu (s) of each member: moments (N, 3) kg m2, start (N, 3)
    rad/s in the same axes; bitwise :func:`stability.free_body.exact.flip_interval` of the
    sorted body."""
    moments = np.ascontiguousarray(moments, dtype=float)
    w0 = np.ascontiguousarray(w0, dtype=float)
    out = np.empty(moments.shape[0])
    _flip_intervals(moments, w0, out)
    return out


def closed_form(draws: dict) -> dict:
    """``flip_interval`` (s) and ``growth_rate`` (s-1) of every member, in closed form."""
    moments = draws["moments"]
    return {"flip_interval": flip_intervals(moments, draws["w0"]),
            "growth_rate": growth_rate(moments, draws["spin_axis"] + 1, draws["rate"])}


def integrated(draws: dict, count: int, *, method="lp4", steps_per_flip=400, flips=3,
               options=None) -> xr.Dataset:
    """The first ``count`` members integrated (:func:`stability.run_scene`, one group each,
    over ``flips`` + 1/2 of their exact flip intervals at ``steps_per_flip`` steps each), with
    ``flip_interval_run``: the mean spacing of the middle component's sign changes (s).

    ``options`` (:class:`~stability.ensemble.options.RunOptions`; default: in one piece here,
    no progress bar) go to :func:`stability.run_scene`: a run chunk by chunk into a folder,
    resumed, on dask, which never changes the result."""
    moments = draws["moments"][:count]
    w0 = draws["w0"][:count]
    exact_t = flip_intervals(moments, w0)
    if not np.all(np.isfinite(exact_t)):
        raise ValueError("a member to integrate does not flip (spin on the separatrix or a "
                         "symmetric body); nudge it")
    b = draws["spin_axis"]
    others = [k for k in range(3) if k != b]
    ds = run_scene(FREE_BODY, method, w0 * moments, list(moments), h=exact_t / steps_per_flip,
                   n_steps=int(steps_per_flip * (flips + 0.5)), sizes=np.ones(count, int),
                   axes=[b, *others],
                   options=options if options is not None else RunOptions(progress=False))
    crossings = ds.axis_crossings.values
    with np.errstate(invalid="ignore", divide="ignore"):
        run_t = np.where(crossings >= 2, (ds.last_axis_crossing.values
                                          - ds.first_axis_crossing.values) / (crossings - 1),
                         np.nan)
    return ds.assign(flip_interval_run=("member", run_t))


def dispersion_dataset(disp: Dispersions, draws: dict, outputs: dict, run=None,
                       indices=None) -> xr.Dataset:
    """The study's Dataset (:data:`stability.free_body.dispersion.schema.DISPERSION`): each
    member's draws, body and start and its closed-form outputs; the integrated members' outputs
    and what their runs report back; the indices."""
    values = {"moments": draws["moments"], "w0": draws["w0"], "rate": draws["rate"],
              "epsilon": draws["epsilon"], "direction": draws["direction"], **outputs}
    if AXES in disp.distributions:
        values.update({"axes_angle": draws["axes_angle"], "axes_axis": draws["axes_axis"],
                       "principal_axes": draws["axes"], "inertia_tensor": draws["tensor"]})
    if run is not None:
        values.update({"run_flip_interval": run.flip_interval_run.values,
                       "run_status": run.status.values,
                       "run_parameters": run.parameters.values,
                       "run_m_start": np.column_stack([run[f"m{k}_start"].values
                                                       for k in (1, 2, 3)])})
    ds = xr.Dataset(DISPERSION.entries(values))
    ds = ds.assign_coords(DISPERSION.entries({"member": np.arange(draws["rate"].size)}))
    if indices is not None:
        ds = ds.merge(indices, combine_attrs="override")
        ds.attrs.update(indices.attrs)
    ds.attrs.update({"dispersions": "; ".join(f"{k}: {d.describe()}"
                                              for k, d in disp.distributions.items()),
                     "truncated": disp.truncated or "", "spin_axis": draws["spin_axis"] + 1})
    return ds
