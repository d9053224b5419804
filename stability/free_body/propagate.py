"""The free body's angular momentum, advanced by the engine: ``propagate``.

``propagate`` converts body-frame momenta to the canonical frame (moments ascending), runs the
``free_body`` scene's member loop (:mod:`stability.engine`) for one ensemble, optionally
tracking flips, crossings and amplitude levels, and converts back; ``propagate_many`` does the
same for many ensembles (bodies, steps, horizons) in one parallel call.
"""

from __future__ import annotations

import numpy as np

from ..util.conventions import perpendicular_axes
from ..core.quaternions import canonical_quaternion, quaternion_conjugate, quaternion_multiply
from ..core.body import canonical_frame, from_canonical, to_canonical
from ..util.checks import real_array, real_number
from ..engine import BLOCK, CHECK_EVERY, Propagation, propagate_groups, untrusted
from ..ensemble.plan import Plan
from .scene import FREE_BODY
from .scene_attitude import FREE_BODY_ATTITUDE

__all__ = ["BLOCK", "CHECK_EVERY", "Propagation", "propagate", "propagate_many", "loop_plan",
           "tracking_axes", "untrusted"]


def propagate(
    method, moments, m0, h, n_steps, save_every=0, progress=None, chunk_steps=None,
    track_axis=None, levels=None, partial=False,
):
    """Advance an ensemble of body angular momenta with a registered method.

    Parameters
    ----------
    method : str or MethodSpec
        Registry name (see ``stability.METHODS``).
    moments : array_like, shape (3,)
        Principal moments (I1, I2, I3) in kg m^2, any order.
    m0 : array_like, shape (N, 3)
        Initial body angular momenta m = I w, body frame.
    h : float
        Step in s, > 0.
    n_steps : int
        Number of steps.
    save_every : int, default 0
        Store the state every ``save_every`` steps; 0 stores nothing but the final state.
    progress : bool or None
        Show a progress bar; ``None`` shows one when the run is expected to take > 2 s.
    chunk_steps : int, optional
        Steps per kernel call (rounded to a multiple of ``save_every``); by default chosen so a
        call takes about 0.25 s.
    track_axis : int, optional
        Body axis (0-based) of the spin; turns on tracking, returned in ``extras``:
        ``axis_crossings``, ``first_axis_crossing``, ``last_axis_crossing`` (sign changes of
        w_a: count, and times in s by linear interpolation, NaN if none); ``perp_crossings``,
        ``first_perp_crossing``, ``last_perp_crossing`` (the same for the first perpendicular
        component, the lowest body axis other than ``track_axis``); ``max_perp_amplitude``
        (rad/s, the start included); ``passage_time`` (N, len(levels)): first time
        sqrt(w_b^2 + w_c^2) reaches each level (0 for levels the start reaches, NaN if never).
    levels : array_like, optional
        Ascending perpendicular-amplitude levels in rad/s for ``passage_time``.
    partial : bool, default False
        On Ctrl-C, return the steps done (``interrupted`` True) instead of raising
        KeyboardInterrupt (:func:`stability.engine.propagate_groups`).

    Returns
    -------
    Propagation
        Body frame: ``m_final`` (N, 3), ``saved`` (N, n_saved, 3); ``steps_done`` an int.
    """
    moments = real_array("moments", moments, "kg m^2")
    m0 = real_array("m0", m0, "kg m2/s")
    run = propagate_many(
        method, moments[None, :], m0, [np.shape(np.atleast_2d(m0))[0]],
        real_number("h", h, "s"), n_steps, save_every=save_every, progress=progress,
        chunk_steps=chunk_steps, track_axes=None if track_axis is None else [track_axis],
        levels=None if levels is None else real_array("levels", levels, "rad/s")[None, :],
        partial=partial,
    )
    run.steps_done = int(run.steps_done[0])
    return run


def propagate_many(
    method, moments, m0, sizes, h, n_steps, save_every=0, progress=None, chunk_steps=None,
    track_axes=None, levels=None, q0=None, partial=False, propagator=propagate_groups,
):
    """Advance several ensembles, each of its own body, step and length, in one parallel call.

    The arguments are those of :func:`propagate`, one per ensemble (group) where the shapes say
    so; each group's members are bitwise what :func:`propagate` gives them alone.

    Parameters
    ----------
    method : str or MethodSpec
    moments : array_like, shape (G, 3)
        Principal moments of each group's body, any order.
    m0 : array_like, shape (N, 3)
        Initial body angular momenta, group 0's members first.
    sizes : array_like of int, shape (G,)
        Members per group.
    h, n_steps : array_like, shape (G,) or scalars
        Step (s) and step count of each group.
    save_every, progress, chunk_steps, partial
        As in :func:`propagate` (one value for all groups).
    track_axes : array_like of int, shape (G,), optional
        Body axis (0-based) of each group's spin; turns on tracking.
    levels : array_like, shape (G, L), optional
        Each group's amplitude levels (rad/s) for the passage times.
    q0 : array_like, shape (N, 4), optional
        Carry the attitude too (scene ``free_body_attitude``): each member's initial
        body-to-space unit quaternion, scalar first.

    Returns
    -------
    Propagation
        Body frame; ``steps_done`` per group. With ``q0`` the states are (m, q), q the carried
        (unnormalised) body-to-space quaternion.
    """
    grouped, groups = loop_plan(method, moments, m0, sizes, h, n_steps, save_every,
                                  chunk_steps, track_axes, levels, q0)
    run = propagator(
        grouped.scene, grouped.method, grouped.x0, grouped.params, grouped.sizes, grouped.h,
        grouped.n_steps, save_every=save_every, axes=grouped.axes, levels=grouped.levels,
        progress=progress, chunk_steps=chunk_steps, partial=partial,
    )
    return groups.from_kernels(run)


def loop_plan(method, moments, m0, sizes, h, n_steps, save_every=0, chunk_steps=None,
                track_axes=None, levels=None, q0=None, device="cpu"):
    """Several ensembles as one :class:`~stability.ensemble.plan.Plan` of the
    ``free_body`` scene (``free_body_attitude`` with ``q0``), in the kernels' canonical frame.

    The arguments are :func:`propagate_many`'s, and ``device`` the run's. Returns the run and
    its :class:`CanonicalGroups`, whose :meth:`CanonicalGroups.from_kernels` turns the run's
    :class:`~stability.engine.Propagation` back into the bodies' frames.
    """
    scene = FREE_BODY if q0 is None else FREE_BODY_ATTITUDE
    spec = scene.method(method)
    moments = np.atleast_2d(np.asarray(moments, dtype=float))
    sizes = np.asarray(sizes, dtype=np.int64).reshape(-1)
    n_groups = sizes.size
    hs = np.broadcast_to(np.asarray(h, dtype=float), (n_groups,))
    groups = CanonicalGroups(spec, moments, sizes, hs)
    x0 = groups.to_canonical(np.atleast_2d(np.asarray(m0, dtype=float)))
    if q0 is not None:
        x0 = np.concatenate([x0, groups.attitudes(q0, to_canonical=True)], axis=1)
    axes = None  # levels count only with the tracking axes
    if track_axes is not None:
        axes = groups.tracking_axes(track_axes)
        levels = group_levels(np.zeros((n_groups, 0)) if levels is None else levels, n_groups)
    else:
        levels = None
    registered = scene.methods.get(spec.name) is spec
    run = Plan(scene, spec.name if registered else spec, x0, groups.params, sizes, hs, n_steps,
               save_every=save_every, axes=axes, levels=levels, device=device,
               chunk_steps=chunk_steps)
    return run, groups


class CanonicalGroups:
    """Ensembles (groups of consecutive members) each turned into its body's canonical frame.

    The kernels see every body with its moments in canonical order (:func:`canonical_frame`);
    this holds each group's frame, converts the members' states into it and back, and gives
    the kernels' parameters and the tracked axes in it.

    Parameters
    ----------
    spec : MethodSpec
    moments : ndarray, shape (G, 3)
        Each group's principal moments, body order.
    sizes : ndarray, shape (G,)
        Members per group.
    hs : ndarray, shape (G,)
        Each group's step in s.
    """

    def __init__(self, spec, moments, sizes, hs):
        self.moments = moments
        self.frames = [canonical_frame(I) for I in moments]
        self.bounds = np.concatenate([[0], np.cumsum(sizes)])
        self.params = np.array([spec.params(I[perm], hs[g]) for g, (I, (perm, _)) in
                                enumerate(zip(moments, self.frames))])

    def to_canonical(self, x) -> np.ndarray:
        """States ``x`` (members first) from the body frame into each group's canonical one."""
        return self._each(x, to_canonical)

    def from_canonical(self, x) -> np.ndarray:
        """States ``x`` (members first) from each group's canonical frame to the body frame."""
        return self._each(x, from_canonical)

    def attitudes(self, q, to_canonical: bool) -> np.ndarray:
        """Body-to-space quaternions ``q`` (members first, (..., 4)) into each group's canonical
        frame (``q c*``) or back (``q c``), c the frame's quaternion."""
        out = np.empty_like(np.asarray(q, dtype=float))
        for g, moments in enumerate(self.moments):
            c = canonical_quaternion(moments)
            part = slice(self.bounds[g], self.bounds[g + 1])
            out[part] = quaternion_multiply(q[part], quaternion_conjugate(c) if to_canonical
                                            else c)
        return out

    def from_canonical_state(self, x) -> np.ndarray:
        """States (m, or m and q) from the canonical frames to the body frames."""
        m = self.from_canonical(np.ascontiguousarray(x[..., :3]))
        if x.shape[-1] == 3:
            return m
        return np.concatenate([m, self.attitudes(x[..., 3:], to_canonical=False)], axis=-1)

    def from_kernels(self, run: Propagation) -> Propagation:
        """``run`` (of :func:`loop_plan`) with its final and saved states in the body frames;
        a run cut short by Ctrl-C may hold only its first members."""
        run.x_final = self.from_canonical_state(run.x_final)
        run.saved = self.from_canonical_state(run.saved)
        return run

    def tracking_axes(self, track_axes) -> np.ndarray:
        """:func:`tracking_axes` of each group, shape (G, 3)."""
        n_groups = len(self.frames)
        return np.array([tracking_axes(perm, int(a)) for (perm, _), a in
                         zip(self.frames, np.broadcast_to(track_axes, (n_groups,)))])

    def _each(self, x, convert) -> np.ndarray:
        if len(self.frames) == 1:  # one group: converted at once, without a second copy
            perm, signs = self.frames[0]
            return convert(x, perm, signs)
        out = np.empty_like(x)
        bounds = self.bounds
        for g, (perm, signs) in enumerate(self.frames):
            out[bounds[g]:bounds[g + 1]] = convert(x[bounds[g]:bounds[g + 1]], perm, signs)
        return out


def tracking_axes(perm, track_axis) -> np.ndarray:
    """Canonical indices of the spin axis ``track_axis`` (body, 0-based) and of the other two,
    lowest body axis first, for the frame permutation ``perm``."""
    if track_axis not in (0, 1, 2):
        raise ValueError(f"track_axis must be 0, 1 or 2 (a body axis), got {track_axis}")
    b, c = perpendicular_axes(track_axis + 1)
    where = {int(body_axis): i for i, body_axis in enumerate(perm)}  # body axis -> canonical
    return np.array([where[track_axis], where[b - 1], where[c - 1]], dtype=np.int64)


def group_levels(levels, n_groups) -> np.ndarray:
    """The amplitude levels of ``n_groups`` ensembles checked, as one float array.

    Shared by the CPU driver and the GPU one (:mod:`stability.free_body.propagate_gpu`), which both
    take one row of levels per ensemble.

    Parameters
    ----------
    levels : array_like, shape (n_groups, L)
        Perpendicular-amplitude levels in rad/s, one row per ensemble (L may be 0).
    n_groups : int
        Number of ensembles.

    Returns
    -------
    ndarray, shape (n_groups, L)

    Raises
    ------
    ValueError
        Unless the levels are finite, > 0 and strictly ascending along each row, with one row
        per ensemble.
    """
    levels = np.asarray(levels, dtype=float)
    if (levels.ndim != 2 or levels.shape[0] != n_groups or np.any(levels <= 0)
            or np.any(np.diff(levels, axis=1) <= 0) or np.any(~np.isfinite(levels))):
        raise ValueError(
            "levels must be finite amplitudes > 0 in rad/s, strictly ascending (one row per "
            f"ensemble: shape ({n_groups}, L)), got shape {levels.shape}"
        )
    return levels
