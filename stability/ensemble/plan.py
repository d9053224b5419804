"""A run's plan: :class:`Plan`, the one small frozen object every run of the package is.

A plan says what is run (a scene and one of its methods), on which members (their starts, as
states or as a rule that makes any members' alone), with what (each group of members its own
parameter row, step and step count) and what the member loop keeps (a time series every
``save_every`` steps, tracking of an axis and amplitude levels). It holds no run options: how
and where it runs (:class:`~stability.ensemble.options.RunOptions`) never changes its result.
:func:`stability.ensemble.chunks.run_plan` runs it.
"""

from __future__ import annotations

import hashlib
import inspect
from dataclasses import dataclass, replace

import numpy as np

from ..engine import propagate_groups
from ..engine.events import located
from ..engine.driver import Propagation
from ..engine.scene import Scene, checked_scene


@dataclass(eq=False, frozen=True)
class Plan:
    """What a run is: members of one scene and method in groups, each group with its own
    parameter row, step and step count, their starts and what the member loop keeps.

    A frozen object (its arrays normalised once, here), run by
    :func:`stability.ensemble.chunks.run_plan` in this process or chunk by chunk
    (:meth:`part`), and the same result wherever its chunks run. The fields are the
    constructor's parameters and the instance's attributes.

    Parameters
    ----------
    scene : Scene
        A family's scene or one of the user's own (pickled by reference: its module is
        imported where a chunk runs).
    method : str or MethodSpec
        A method of the scene (a spec it does not register is taken as it is).
    x0 : ndarray, shape (N, n), or None
        Initial states, group after group; None with ``starts``.
    params : ndarray, shape (G, p)
        Each group's parameter row.
    sizes : ndarray of int, shape (G,)
        Members per group.
    h : ndarray, shape (G,)
        Each group's step.
    n_steps : ndarray of int, shape (G,)
        Each group's step count.
    save_every : int, default 0
        Keep the state every ``save_every`` steps (0: only the final state).
    axes, levels : ndarray, optional
        Tracking, as :func:`propagate_groups` takes it.
    label : str, optional
        The progress bar's label.
    device : {"cpu", "gpu"}, default "cpu"
        Where the member loop runs: ``"gpu"`` on a CUDA GPU
        (:func:`stability.engine.gpu.propagate_groups_gpu`; the results agree with the CPU's to
        round-off, not bitwise, so the device is part of a stored run's identity).
    chunk_steps : int, optional
        Steps per call of the loop (:func:`propagate_groups`); never changes the result.
    events : tuple of Event, default ()
        User events the member loop locates (:func:`propagate_groups`, on the CPU or the GPU;
        checked by the caller, :func:`stability.engine.events.checked_events`).
    starts : callable, optional
        The start rule, instead of ``x0``: ``starts(lo, hi)`` gives the initial states of
        members ``lo ... hi - 1`` alone (the same whichever members are asked with them);
        picklable where the chunks run on dask, and with ``identity()`` (a dict) for a store's
        fingerprint unless a measurement gives the run's identity.
    """

    scene: Scene
    method: object
    x0: np.ndarray
    params: np.ndarray
    sizes: np.ndarray
    h: np.ndarray
    n_steps: np.ndarray
    save_every: int = 0
    axes: np.ndarray | None = None
    levels: np.ndarray | None = None
    label: str | None = None
    device: str = "cpu"
    chunk_steps: int | None = None
    starts: object = None
    events: tuple = ()

    def __post_init__(self):
        checked_scene(self.scene, "Plan")
        if self.device not in ("cpu", "gpu"):
            raise ValueError(f"device must be 'cpu' or 'gpu', got {self.device!r}")
        if (self.x0 is None) == (self.starts is None):
            raise ValueError("give the starts as x0 or as a rule, starts=, not both")
        normalised = object.__setattr__  # frozen: the arrays are set once, here
        if self.x0 is not None:
            normalised(self, "x0", np.ascontiguousarray(self.x0, dtype=float))
        normalised(self, "params", np.ascontiguousarray(np.atleast_2d(self.params), dtype=float))
        sizes = np.asarray(self.sizes, dtype=np.int64).reshape(-1)
        normalised(self, "sizes", sizes)
        groups = sizes.size
        normalised(self, "h", np.broadcast_to(np.asarray(self.h, dtype=float), (groups,)).copy())
        normalised(self, "n_steps", np.broadcast_to(np.asarray(self.n_steps, dtype=np.int64),
                                                    (groups,)).copy())
        if self.axes is not None:
            normalised(self, "axes", np.broadcast_to(np.asarray(self.axes, dtype=np.int64),
                                                     (groups, 3)).copy())
        if self.levels is not None:
            levels = np.atleast_2d(np.asarray(self.levels, dtype=float))
            normalised(self, "levels", np.broadcast_to(levels, (groups, levels.shape[-1])).copy())

    @property
    def members(self) -> int:
        return int(self.sizes.sum())

    @property
    def width(self) -> int:
        """Numbers per member in the scene's state."""
        return self.scene.width

    @property
    def n_saved(self) -> int:
        """Samples kept per member in the whole run (NaN past a group's own last one)."""
        return int(self.n_steps.max()) // self.save_every if self.save_every > 0 else 0

    def identity(self) -> dict:
        """What makes the run what it is, for a store's fingerprint: names and array digests."""
        arrays = {name: getattr(self, name) for name in
                  ("x0", "params", "sizes", "h", "n_steps", "axes", "levels")}
        if self.starts is not None:
            rule = getattr(self.starts, "identity", None)
            if rule is None:
                raise ValueError("a run whose starts come from a rule needs the rule's "
                                 "identity() for its store's fingerprint")
            arrays.pop("x0")
        source = self.scene.source  # the user's code; the version stands for the package's
        return {"scene": self.scene.name, **({"scene_source": source} if source else {}),
                **({"starts": rule()} if self.starts is not None else {}),
                **({"device": self.device} if self.device != "cpu" else {}),
                **({"events": [_event_identity(e) for e in self.events]} if self.events
                   else {}),
                "method": getattr(self.method, "name", self.method),
                "save_every": self.save_every,
                "arrays": {name: None if a is None else _digest(a) for name, a in arrays.items()}}

    def part(self, lo: int, hi: int) -> "Plan":
        """Members ``lo ... hi - 1``: the groups they fall in, each with its own row and step."""
        ends = np.cumsum(self.sizes)
        starts = ends - self.sizes
        sizes = np.clip(np.minimum(ends, hi) - np.maximum(starts, lo), 0, None)
        keep = sizes > 0
        pick = (lambda a: None if a is None else a[keep])
        x0 = self.x0[lo:hi] if self.starts is None else self.starts(lo, hi)
        return replace(self, x0=x0, params=self.params[keep], sizes=sizes[keep],
                       h=self.h[keep], n_steps=self.n_steps[keep], axes=pick(self.axes),
                       levels=pick(self.levels), starts=None)

    def propagate(self, progress=None, partial=False) -> Propagation:
        """The run in this process (:func:`propagate_groups`, or its GPU twin); with
        ``partial``, Ctrl-C returns the steps done (``interrupted``) instead of raising."""
        if self.starts is not None:
            return self.part(0, self.members).propagate(progress, partial)
        propagator = propagate_groups
        if self.device == "gpu":
            from ..engine.gpu import propagate_groups_gpu as propagator  # numba-cuda: optional

        return propagator(self.scene, self.method, self.x0, self.params, self.sizes, self.h,
                          self.n_steps, save_every=self.save_every, axes=self.axes,
                          levels=self.levels, progress=progress, chunk_steps=self.chunk_steps,
                          label=self.label, partial=partial,
                          **({"events": self.events} if self.events else {}))




def _event_identity(event) -> dict:
    """An event as a store's fingerprint holds it: where its g is and a digest of its source
    (an edited g is another run), and what it keeps."""
    module, name = located(event.g)
    try:
        source = inspect.getsource(event.python)
    except (OSError, TypeError):  # no source file: its compiled code stands for it
        source = event.python.__code__.co_code.hex()
    return {"g": f"{module}.{name}", "g_source": hashlib.sha256(source.encode()).hexdigest(),
            "direction": event.direction, "action": event.action, "count": event.count,
            "name": event.name}


def _digest(a: np.ndarray) -> str:
    a = np.ascontiguousarray(a)
    h = hashlib.sha256(f"{a.dtype.str}{a.shape}".encode())
    h.update(a.tobytes())
    return h.hexdigest()
