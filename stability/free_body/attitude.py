"""The attitude: a unit quaternion per member, advanced with m by the method's own update.

Convention: ``q = (q0, q1, q2, q3)``, scalar first, Hamilton product; ``R(q)`` is the
*body-to-space* rotation (space components of a body vector x are ``R(q) x``), and the attitude
obeys ``R' = R hat(w)``, i.e. ``q' = q (0, w) / 2``. The spatial angular momentum ``R(q) m`` is
constant for the free body.

Each method advances q by its own rule (``MethodSpec.attitude_step``): the Lie-Poisson sub-flows
turn the attitude by the same angles as m, ``Q <- Q R_k(+theta)``, and the Casimir part by
``Q <- Q exp(h hat(m) / I2)``; DMV, the LGVI and the implicit midpoint rule multiply by their
Cayley rotation F; RKMK4 by ``exp(-hat v)``; RK4 integrates the kinematics. Every one of these is a
right multiplication ``q <- q r_n`` by a quaternion r_n that depends on m only, so the
*direction* of q (the rotation) never depends on its norm. Renormalisation policy, therefore:
none inside the loop; q is carried with compensated summation like m, normalised only on output,
and its norm error ``|q| - 1`` is reported. For the methods whose r_n is a unit quaternion (all
but RK4) that error is round-off (at most 1.5e-14 after 1e5 steps in the tests); for RK4 it is
its truncation error, O((h |w|)^6) per step.

A run without attitude stays 3 numbers per member (scene ``free_body``); ``propagate_attitude``
runs scene ``free_body_attitude``, 7 numbers per member, on the same member loop
(:mod:`stability.engine`).

Reference used by the tests: scipy ``solve_ivp`` DOP853 on (m, q) at rtol = atol = 1e-13, a
very-high-accuracy numerical reference (the exact attitude of Celledoni, Fasso, Safstrom & Zanna,
SIAM J. Sci. Comput. 30, 2084 (2008) is not implemented here).
"""

from __future__ import annotations

import numpy as np

from ..core.body import canonical_frame, from_canonical, to_canonical
from ..util.checks import positive_int, real_array
from ..engine import propagate_groups
from .methods import method_spec
from ..core.quaternions import canonical_quaternion, quaternion_conjugate, quaternion_multiply
from ..ensemble.chunks import run_plan
from ..ensemble.plan import Plan
from .scene import FREE_BODY
from .scene_attitude import FREE_BODY_ATTITUDE

# --- which methods carry the attitude ----------------------------------------------------------


def attitude_methods() -> tuple[str, ...]:
    """Names of the registered methods that can carry the attitude."""
    return tuple(FREE_BODY_ATTITUDE.methods)


#: The free body's scenes, picked by name (``run_ensemble``, ``integrate``, the tennis study):
#: w alone, or w and the body-to-space attitude q.
FREE_BODY_SCENES = {"free_body": FREE_BODY, "free_body_attitude": FREE_BODY_ATTITUDE}


def carries_attitude(scene) -> bool:
    """Whether the free-body scene ``scene`` carries the attitude; ValueError if it is none.

    Parameters
    ----------
    scene : str
        A name of :data:`FREE_BODY_SCENES`.

    Returns
    -------
    bool
        True for ``"free_body_attitude"``.
    """
    if scene not in FREE_BODY_SCENES:
        raise ValueError(
            f"scene must be one of {', '.join(map(repr, FREE_BODY_SCENES))} (the free body "
            f"without and with its attitude; the torqued and struck bodies are run by their own "
            f"functions and studies), got {scene!r}")
    return scene == "free_body_attitude"


def attitude_spec(method):
    """The MethodSpec of ``method``; ValueError naming the others if it cannot carry q.

    Parameters
    ----------
    method : str or MethodSpec

    Returns
    -------
    MethodSpec
    """
    spec = method_spec(method)
    if not spec.attitude:
        raise ValueError(
            f"method {spec.name!r} cannot carry the attitude; methods that can: "
            + ", ".join(attitude_methods())
        )
    return spec


# --- the run -----------------------------------------------------------------------------------


def propagate_attitude(
    method, moments, m0, q0, h, n_steps, save_every=0, progress=None, chunk_steps=None,
    partial=False,
):
    """Advance body angular momenta and attitudes of an ensemble with a registered method.

    Parameters
    ----------
    method : str or MethodSpec
        A name from :func:`attitude_methods`.
    moments : array_like, shape (3,)
        Principal moments (I1, I2, I3) in kg m^2, any order.
    m0 : array_like, shape (N, 3)
        Initial body angular momenta m = I w (body frame), kg m^2 s^-1.
    q0 : array_like, shape (4,) or (N, 4)
        Initial body-to-space unit quaternions, scalar first.
    h : float
        Step in s, > 0.
    n_steps : int
        Number of steps.
    save_every : int, default 0
        Store the state every ``save_every`` steps; 0 stores only the final state.
    progress : bool or None
        Progress bar; ``None`` shows one when the run is expected to take > 2 s.
    chunk_steps : int, optional
        Steps per kernel call; by default about 0.25 s of work per call.
    partial : bool, default False
        On Ctrl-C, return the steps done instead of raising KeyboardInterrupt.

    Returns
    -------
    Propagation
        As from :func:`stability.free_body.propagate.propagate` (body frame), with ``extras``:
        ``q_final`` (N, 4) and ``q_saved`` (N, n_saved, 4): unit quaternions (normalised on
        output); ``q_norm_error_final`` (N,) and ``q_norm_error_saved`` (N, n_saved): ``|q| - 1``
        of the carried, unnormalised quaternion.

    Raises
    ------
    ValueError
        If the method cannot carry the attitude, or q0 has the wrong shape.
    """
    scene = FREE_BODY_ATTITUDE
    spec = attitude_spec(method)
    moments = real_array("moments", moments, "kg m^2")
    perm, signs = canonical_frame(moments)
    m = to_canonical(np.atleast_2d(real_array("m0", m0, "kg m2/s")), perm, signs)
    n_members = m.shape[0]
    q0 = real_array("q0", q0)
    if q0.shape not in ((4,), (n_members, 4)):
        raise ValueError(f"q0 must have shape (4,) or ({n_members}, 4), got {q0.shape}")
    c = canonical_quaternion(moments)
    q = np.ascontiguousarray(
        quaternion_multiply(np.broadcast_to(q0, (n_members, 4)), quaternion_conjugate(c))
    )
    x = np.concatenate([m, q], axis=1)
    run = propagate_groups(
        scene, spec, x, spec.params(moments[perm], h)[None, :], [n_members], h, n_steps,
        save_every=save_every, progress=progress, chunk_steps=chunk_steps, partial=partial,
    )
    q, saved_q = run.x_final[:, 3:], run.saved[:, :, 3:]
    norm_final = np.linalg.norm(q, axis=-1)  # of the carried quaternion, canonical frame
    norm_saved = np.linalg.norm(saved_q, axis=-1)
    q_final = quaternion_multiply(q, c)
    q_saved = quaternion_multiply(saved_q, c)
    run.x_final = from_canonical(run.x_final[:, :3], perm, signs)
    run.saved = from_canonical(run.saved[:, :, :3], perm, signs)
    run.steps_done = int(run.steps_done[0])
    run.extras = {
        "q_final": q_final / np.linalg.norm(q_final, axis=-1, keepdims=True),
        "q_saved": q_saved / np.linalg.norm(q_saved, axis=-1, keepdims=True),
        "q_norm_error_final": norm_final - 1.0,
        "q_norm_error_saved": norm_saved - 1.0,
    }
    return run


# --- ensembles of bodies, with the run's own solution between the saved steps ------------------


class AttitudeRuns:
    """Members each with its own body and step, carried with their attitude (canonical frame).

    Made by :func:`propagate_attitudes`. ``saved[:, k]`` is each member's state (m, q) after
    ``k * save_every`` steps (``k = 0``: the start); :meth:`state_at` continues the run's own
    solution from the last saved state to any time with the same method (whole steps of the
    member's h, then one step of the remainder: a continuous function of time), so roots of
    functions of the state can be found to round-off on the discrete solution itself.

    Parameters
    ----------
    spec : MethodSpec
        The method that made the run and continues it.
    moments : ndarray, shape (N, 3)
        Each member's principal moments in kg m^2, sorted ascending (canonical frame).
    h : ndarray, shape (N,)
        Each member's step in s.
    save_every : int
        Steps between saved states.
    saved : ndarray, shape (N, n_saved + 1, 7)
        Saved states (m, q): body angular momentum in kg m^2/s and the carried, unnormalised
        quaternion, canonical frame; ``saved[:, 0]`` is the start.
    run : Propagation
        The run itself (status, wall time).
    """

    def __init__(self, spec, moments, h, save_every, saved, run):
        self.spec = spec
        self.moments = moments  # (N, 3), canonical
        self.h = h  # (N,)
        self.save_every = save_every
        self.saved = saved  # (N, n_saved + 1, 7)
        self.run = run  # the Propagation (status, wall time)

    @property
    def times(self) -> np.ndarray:
        """Times of the saved states, shape (N, n_saved + 1), s."""
        k = np.arange(self.saved.shape[1])
        return self.h[:, None] * self.save_every * k

    def state_at(self, t) -> np.ndarray:
        """Each member's state at its own time ``t`` (N,), within the run; shape (N, 7).

        Raises KeyboardInterrupt if Ctrl-C stopped the continuation.
        """
        t = np.asarray(t, dtype=float)
        interval = self.h * self.save_every
        k = np.clip(np.floor(t / interval).astype(np.int64), 0, self.saved.shape[1] - 1)
        rest = t - k * interval
        x = self.saved[np.arange(t.size), k]
        whole = np.clip(np.floor(rest / self.h).astype(np.int64), 0, self.save_every)
        last = rest - whole * self.h  # in [0, h): the step that lands on t
        ones = np.ones(t.size, np.int64)
        if whole.any():
            x = self._advance(x, self.h, whole, ones)
        return np.where((last > 0.0)[:, None],
                        self._advance(x, np.where(last > 0.0, last, self.h), ones, ones), x)

    def _advance(self, x, h, n_steps, sizes):
        params = np.array([self.spec.params(I, hh) for I, hh in zip(self.moments, h)])
        prop = propagate_groups(FREE_BODY_ATTITUDE, self.spec, x, params, sizes,
                                h, n_steps, progress=False)
        return prop.x_final


def propagate_attitudes(method, moments, m0, q0, h, n_steps, save_every=1, *, label=None,
                        options=None):
    """Advance members each of its own body and step, with their attitudes, canonical frame.

    Parameters
    ----------
    method : str or MethodSpec
        A name from :func:`attitude_methods`.
    moments : array_like, shape (N, 3)
        Each member's principal moments in kg m^2, sorted ascending (canonical frame).
    m0 : array_like, shape (N, 3)
        Initial body angular momenta, canonical frame, kg m^2/s.
    q0 : array_like, shape (N, 4)
        Initial attitudes in the canonical frame (body to space), unit quaternions.
    h : array_like, shape (N,)
        Each member's step in s.
    n_steps : int
        Steps, the same for every member; a multiple of ``save_every``.
    save_every : int, default 1
    progress : bool or None
    label : str, optional
        Progress bar label.
    options : RunOptions, optional
        How and where the members run (:class:`~stability.ensemble.options.RunOptions`): by
        default in one piece here; with a ``store``, chunk by chunk into it, resumable and on
        dask. The result is the same, bitwise.

    Returns
    -------
    AttitudeRuns

    Raises
    ------
    KeyboardInterrupt
        If Ctrl-C stopped the run (a partial run is not returned).
    """
    spec = attitude_spec(method)
    moments = np.atleast_2d(real_array("moments", moments, "kg m^2"))
    n = moments.shape[0]
    if moments.shape[1:] != (3,) or np.any(np.diff(moments, axis=1) < 0.0):
        raise ValueError("moments must have shape (N, 3), each row sorted ascending (the "
                         f"canonical frame), got shape {moments.shape}")
    h = np.broadcast_to(real_array("h", h, "s"), (n,)).copy()
    if not np.all(h > 0.0):
        raise ValueError("every step h must be a number > 0 (s)")
    n_steps = positive_int("n_steps", n_steps)
    save_every = positive_int("save_every", save_every)
    if n_steps % save_every:
        raise ValueError(f"n_steps = {n_steps} is not a multiple of save_every = {save_every}")
    m0 = np.atleast_2d(real_array("m0", m0, "kg m2/s"))
    q0 = np.atleast_2d(real_array("q0", q0))
    if m0.shape != (n, 3) or q0.shape != (n, 4):
        raise ValueError(f"m0 and q0 must have shapes ({n}, 3) and ({n}, 4), one row per "
                         f"member, got {m0.shape} and {q0.shape}")
    x = np.concatenate([m0, q0], axis=1)
    params = np.array([spec.params(I, hh) for I, hh in zip(moments, h)])
    sizes = np.ones(x.shape[0], dtype=np.int64)
    run = run_plan(Plan(FREE_BODY_ATTITUDE, spec.name, x, params, sizes, h,
                        n_steps, save_every=save_every, label=label),
                   options)
    saved = np.concatenate([x[:, None, :], run.saved], axis=1)
    return AttitudeRuns(spec, moments, h, save_every, saved, run)
