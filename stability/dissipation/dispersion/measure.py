"""A dispersed Explorer-like ensemble: each member its own cylinder, spin, damper and start, and
its growth rate and time to the flat spin, by the linear eigenvalue for every design point and
integrated for some.

Member k is a uniform solid cylinder (length L, diameter d, mass M: moments
``I_s = M r^2 / 2``, ``I_t = M (3 r^2 + L^2) / 12``, :class:`~stability.dissipation.model.
Cylinder`) spun at W about its long axis with a spherical damper (J, c), its angular momentum
tilted by theta0 from that axis (:func:`~stability.dissipation.model.tilted_rotation`). The
damping is dispersed as the viscous coefficient c itself, about the nominal
``damping c*``, c* = J W I_s / I_t of the nominal body. Outputs per member:

- the growth rate lambda of the nutation, the leading real part of the linear eigenvalues
  about the long axis (:func:`~stability.dissipation.model.sphere_eigenvalues`, at the spin
  ``|H| / A_s`` the run starts from, as :func:`~stability.dissipation.measure.run_damped`
  takes it), s-1;
- the time to the flat spin at that rate, ``ln(tan(theta_f) / tan(theta0)) / lambda`` (the
  Explorer study's ``flat_time_linear``; the integrated time is within 1.1 % of it there), s;
- for the first members asked, both integrated: the growth rate fitted in the linear regime
  and the time the nutation angle passes theta_f.
"""

from __future__ import annotations

import math

import numpy as np
import xarray as xr

from ...ensemble.options import RunOptions
from ..measure import SPHERE, run_damped, tilted_start
from ..model import RPM, Cylinder, energy_sink_optimum, equivalent_transverse_moment
from .schema import EXPLORER_DISPERSION

#: The parameters a dispersion may name, in the study file's units: L (m), d (m), M (kg), the
#: spin (rpm), the sphere's J (kg m2), its c (N m s) and the initial nutation angle (degree).
PARAMETERS = ("length", "diameter", "mass", "spin", "inertia", "damping", "angle")


def nominal(length, diameter, mass, spin_rpm, inertia, damping_factor, angle) -> dict:
    """The undispersed values, the damping as the coefficient c = ``damping_factor`` c* of
    the nominal body (N m s)."""
    I = Cylinder(length, diameter, mass, spin_rpm * RPM).moments
    c_sink = energy_sink_optimum(I[0], equivalent_transverse_moment(I), inertia,
                                 spin_rpm * RPM)
    return {"length": float(length), "diameter": float(diameter), "mass": float(mass),
            "spin": float(spin_rpm), "inertia": float(inertia),
            "damping": float(damping_factor * c_sink), "angle": float(angle)}


def members(disp, unit) -> dict:
    """Each member's draws (:meth:`~stability.uncertainty.dispersions.Dispersions.draw`), and
    what its run takes: ``values`` (N, 5), the scene's parameter set (I_s, I_t, I_t, J, c);
    ``W`` (N,) the spin, rad/s; ``theta0`` (N,) the angle, rad."""
    out = disp.draw(unit)
    out["W"] = out["spin"] * RPM
    # the cylinder's moments, member by member (its formulas work on arrays as on numbers)
    shell = Cylinder(out["length"], out["diameter"], out["mass"], out["W"]).moments.T
    out["values"] = np.column_stack([shell, out["inertia"], out["damping"]])
    out["theta0"] = np.radians(out["angle"])
    return out


def linear(draws: dict, flat_angle: float) -> dict:
    """``growth_rate`` (s-1) and ``flat_time`` (s) of every member by the linear eigenvalue."""
    n = draws["W"].size
    growth = np.empty(n)
    for k in range(n):
        values = draws["values"][k]
        _, H = tilted_start(SPHERE, values, draws["W"][k], draws["theta0"][k:k + 1],
                            np.zeros(1))
        growth[k] = SPHERE.eigenvalues(values, 0, H[0] / SPHERE.moments(values)[0])[0].real
    flat = np.log(math.tan(flat_angle) / np.tan(draws["theta0"])) / growth
    return {"growth_rate": growth, "flat_time": flat}


def integrated(draws: dict, count: int, *, flat_angle: float, method="lp2", step_angle=0.5,
               tail=8.0, samples=2000, fit_top=0.02, options=None) -> dict:
    """The first ``count`` members integrated, each alone
    (:func:`~stability.dissipation.measure.run_damped`; with a store, each in its folder
    ``member_k``, resumable): ``growth_rate`` fitted, ``flat_time``, ``status``, and
    ``start_angle``, the nutation angle of the state the run started from (degree)."""
    options = options if options is not None else RunOptions(progress=False)
    keys = ("growth_rate", "flat_time", "status", "start_angle")
    out = {key: np.empty(count, dtype=np.int8 if key == "status" else float) for key in keys}
    for k in range(count):
        run = run_damped(SPHERE, method, [draws["values"][k]], draws["theta0"][k:k + 1],
                         spin=float(draws["W"][k]), step_angle=step_angle, tail=tail,
                         samples=samples, fit_top=fit_top, flat_angle=flat_angle,
                         label=f"member {k} of {count}", options=options.within(f"member_{k}"))
        out["growth_rate"][k] = run["growth_rate_measured"][0, 0]
        out["flat_time"][k] = run["flat_time"][0, 0]
        out["status"][k] = run["status"][0, 0]
        out["start_angle"][k] = run["theta"][0, 0, 0]
    return out


def dispersion_dataset(disp, draws: dict, outputs: dict, run=None,
                       indices=None) -> xr.Dataset:
    """The study's Dataset (:data:`~.schema.EXPLORER_DISPERSION`): each member's draws and
    parameter set, its outputs by the linear eigenvalue; the integrated members'; the
    analysis."""
    values = {name: draws[name] for name in PARAMETERS if name != "spin"}
    values.update({"spin": draws["W"], "moments": draws["values"][:, :3], **outputs})
    if run is not None:
        values.update({f"run_{key}": value for key, value in run.items()})
    ds = xr.Dataset(EXPLORER_DISPERSION.entries(values))
    ds = ds.assign_coords(EXPLORER_DISPERSION.entries({"member": np.arange(draws["W"].size)}))
    if indices is not None:
        ds = ds.merge(indices, combine_attrs="override")
        ds.attrs.update(indices.attrs)
    ds.attrs["dispersions"] = "; ".join(f"{k}: {d.describe()}"
                                        for k, d in disp.distributions.items())
    return ds
