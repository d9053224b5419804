"""What a scene is: the state it integrates, its kernels, invariants and exact solution.

A scene is one physical problem run by the one member loop (:mod:`stability.engine`). Checklist
for a new scene (copy ``stability/free_body/scene.py``):

1. Name the state's numbers and their units (``components``, ``units``), in the frame the
   kernels use.
2. Give the methods that suit it: ``methods`` maps a name to a
   :class:`~stability.integrators.spec.MethodSpec`, and ``kernel(spec)`` picks this scene's stage
   kernel from a spec, ``step(x_0, ..., x_{n-1}, h, p, s) -> (d_0, ..., d_{n-1}, iterations)``
   with ``p = spec.params(parameters, h)``; kernels are ``njit(inline="always")`` module-level
   functions and never raise.
3. Write ``observe(x_0, ..., x_{n-1}, p, ia, ib, ic) -> (a, b, c)``: what the loop tracks (the
   component along the spin axis and two across it), ``tracked``, the same in NumPy, and
   ``tracked_units``, the units of the amplitude across the axis.
4. Give its invariants (NumPy functions of the state and the parameters) and, in
   ``kept_by``, which methods keep each one to round-off (the others keep it to their order);
   its exact solution where one exists, ``exact(x0, parameters, t) -> x`` (the states at time
   ``t`` in the kernels' frame, or None for a parameter set or starts it does not cover); and
   ``example(n, seed) -> (x0, parameters)``: starts and a few parameter sets (what
   ``spec.params`` takes) for the generic tests, in units where the motion takes about a
   second, with at least one set the exact solution covers. The order test runs them to
   ``t = 4`` with steps ``4 / 2^k``: put anything that happens at a set time (the end of a
   contact) on a dyadic time, where a step ends.
5. Name it in its family's ``SCENES`` (the family's ``__init__.py``, which
   :mod:`stability.registry` reads). The generic tests then check
   every method of it: ``tests/test_registry.py`` the order against the exact solution
   and the invariants as declared, ``tests/engine/test_driver.py`` bitwise reproducibility across
   groups, chunks and thread counts. Tests of what is particular to the scene go in a file of
   its own.

6. Optionally, its linearisation (:class:`~stability.engine.tangent.Linearisation`: the vector
   field ``f(x, p)`` and the product ``J(x, p) v`` as ``@njit`` kernels, and the parameter row
   they read): the scene then has tangent equations, :func:`stability.engine.tangent.
   tangent_scene`, and finite-time Lyapunov exponents (:mod:`stability.tangents`). Test the
   product against the scene's own linear theory or a complex step.

A scene of the user's own, in a module outside the package, comes from
:func:`stability.define_scene` (``stability/engine/user_scene.py``), which writes its RK4 kernel.
"""

from __future__ import annotations

import importlib
import pickle
import sys
from dataclasses import dataclass, field
from typing import Callable, Mapping

from numba import njit

from ..integrators.spec import P_I1, P_INV1


@njit(forceinline=True, error_model="numpy")
def component(x1, x2, x3, index):
    """Component ``index`` (0, 1, 2) of a 3-vector, as a select (branch-free in the loop): what
    a scene's ``observe`` reads the spin axis and the two across it with."""
    return x1 if index == 0 else (x2 if index == 1 else x3)


@njit(forceinline=True, error_model="numpy")
def angular_velocity_components(m1, m2, m3, p, ia, ib, ic):
    """The angular velocity along the spin axis ``ia`` and the axes ``ib``, ``ic`` across it,
    of a body angular momentum ``m`` whose parameters begin with the body's
    (:func:`stability.integrators.spec.body_params`): what a scene of ``m`` observes.

    Parameters
    ----------
    m1, m2, m3 : float
        The body angular momentum (kg m^2/s), canonical frame.
    p : ndarray
        The member's parameter row, beginning with the body's.
    ia, ib, ic : int
        The spin axis and the two across it (0, 1, 2).

    Returns
    -------
    w_a, w_b, w_c : float
        ``m_k / I_k`` along ``ia``, ``ib``, ``ic`` (rad/s).
    """
    return (
        component(m1, m2, m3, ia) * p[P_INV1 + ia],
        component(m1, m2, m3, ib) * p[P_INV1 + ib],
        component(m1, m2, m3, ic) * p[P_INV1 + ic],
    )


def angular_velocity_tracked(m, p, axes):
    """:func:`angular_velocity_components` in NumPy at the start.

    ``w = m / I`` (the division, as the caller's ``w0`` was made), which can differ from the
    loop's ``m (1 / I)`` in the last bit: the start's own amplitude decides which levels it
    already reaches, so it must be the caller's.

    Parameters
    ----------
    m : ndarray, shape (N, 3)
        Body angular momenta (kg m^2/s), canonical frame.
    p : ndarray
        A parameter row beginning with the body's
        (:func:`stability.integrators.spec.body_params`).
    axes : sequence of int
        The spin axis and the two across it.

    Returns
    -------
    tuple of ndarray, shape (N,)
        ``(w_a, w_b, w_c)`` (rad/s).
    """
    return tuple(m[:, axes[k]] / p[P_I1 + axes[k]] for k in range(3))


def _own_step(spec):
    return spec.step


@dataclass(frozen=True, eq=False)
class Scene:
    """A registered scene; see the module docstring.

    The fields are the constructor's parameters and the instance's attributes.

    Parameters
    ----------
    name : str
        Short lowercase registry key (``"free_body"``).
    title : str
        Human name.
    equations : str
        The equations integrated, in one line of plain text (a run's Dataset records it).
    components : tuple of str
        Names of the state's numbers, in kernel order.
    units : tuple of str
        UDUNITS unit of each component.
    methods : mapping of str to MethodSpec
        The methods that run this scene.
    observe : numba dispatcher
        Tracking kernel (see the module docstring).
    tracked : callable
        ``tracked(x, p, axes) -> (a, b, c)``: ``observe`` in NumPy over states ``x`` (N, n).
    kernel : callable, optional
        ``kernel(spec)``: this scene's stage kernel in a method's spec (default ``spec.step``).
    invariants : mapping of str to callable, optional
        ``f(x, parameters) -> ndarray (N,)`` for each conserved quantity, states ``x`` (N, n);
        empty by default.
    kept_by : mapping of str to bool, str, frozenset or None, optional
        Which methods keep each invariant to round-off (:meth:`keeps`): ``True`` every method,
        a ``MethodSpec`` flag's name (``"preserves_casimir"``, ``"preserves_energy"``) the
        methods that have it set, a set of method names those methods; the others, and every
        method for ``False`` or an invariant not named here, keep it to their order. ``None``:
        not conserved along a whole motion (a strike's angular momentum during the contact),
        left to the scene's own tests.
    exact : callable or None, default None
        ``exact(x0, parameters, t) -> ndarray (N, n) or None``: the exact states at time ``t``
        (a float) of the starts ``x0`` (N, n) at time 0, in the kernels' frame, for one
        parameter set (what ``spec.params`` takes); None where the solution does not cover
        that set or those starts (the heavy top's is the symmetric top's). None: no exact
        solution.
    example : callable or None, default None
        ``example(n, seed=0) -> (x0, parameters)``: ``n`` starts (n, width) and a list of
        parameter sets (each what ``spec.params`` takes), for the generic tests.
    parameters : tuple of str, default ()
        Names of the numbers of a parameter set, where the scene names them
        (:func:`stability.define_scene` does).
    parameter_units : tuple of str, default ()
        UDUNITS unit of each of ``parameters``, where the scene gives them (a run's Dataset
        labels the parameters with them; ``"1"`` where they are not given).
    module : str, default ""
        The module that binds the scene to a name: a scene with one is pickled by reference
        (that module is imported where it is unpickled, a dask worker say), else by value.
    source : str, default ""
        Digest of the sources of a scene defined outside the package, part of a stored run's
        identity (an edit of them is a changed run); the package's version stands for those
        of the registered scenes.
    latex : str, default ""
        The same equations in LaTeX, shown as mathematics on the scene's documentation page
        (``equations`` is shown as code where this is empty).
    tracked_units : str, default ""
        UDUNITS unit of the amplitude ``observe`` tracks across the spin axis (and of the
        levels): what a tracked run's Dataset labels them with unless the run says otherwise.
    linearisation : Linearisation or None, default None
        Its vector field and Jacobian-vector product (:mod:`stability.engine.tangent`), where
        it declares them: what its tangent scene integrates.
    """

    name: str
    title: str
    equations: str
    components: tuple
    units: tuple
    methods: Mapping = field(repr=False)
    observe: object = field(repr=False)
    tracked: Callable = field(repr=False)
    kernel: Callable = field(repr=False, default=_own_step)
    invariants: Mapping = field(repr=False, default_factory=dict)
    kept_by: Mapping = field(repr=False, default_factory=dict)
    exact: Callable | None = field(repr=False, default=None)
    example: Callable | None = field(repr=False, default=None)
    parameters: tuple = ()
    parameter_units: tuple = ()
    module: str = field(repr=False, default="")
    source: str = field(repr=False, default="")
    latex: str = field(repr=False, default="")
    tracked_units: str = ""
    linearisation: object = field(repr=False, default=None)

    def __reduce_ex__(self, protocol):
        """By reference, ``(module, name)``, for a scene that has a module; else by value."""
        if not self.module:
            return super().__reduce_ex__(protocol)
        home = sys.modules.get(self.module)
        names = [key for key, value in vars(home).items() if value is self] if home else []
        if self.module == "__main__":
            raise pickle.PicklingError(
                f"scene {self.name!r} cannot be sent to another process: it is defined in "
                "__main__ (the script being run), which other processes cannot import; move "
                "define_scene and the scene's functions into a module of their own and import "
                "the scene from there")
        if not names:
            raise pickle.PicklingError(
                f"scene {self.name!r} cannot be sent to another process: it is not bound to a "
                f"name at the top level of an importable module ({self.module}); define it in "
                "a module on that process's path"
            )
        return imported_scene, (self.module, names[0], self.name)

    @property
    def width(self) -> int:
        """Numbers per member in the state."""
        return len(self.components)

    def keeps(self, invariant: str, method) -> bool | None:
        """Whether ``method`` keeps ``invariant`` to round-off (True) or to its order (False);
        None where the invariant is not conserved along a whole motion (see ``kept_by``).

        Parameters
        ----------
        invariant : str
            A key of ``invariants``.
        method : str or MethodSpec
            A method of this scene.

        Returns
        -------
        bool or None
        """
        if invariant not in self.invariants:
            raise ValueError(f"scene {self.name!r} has no invariant {invariant!r}; its "
                             f"invariants: {', '.join(self.invariants) or 'none'}")
        spec = self.method(method)
        kept = self.kept_by.get(invariant, False)
        if kept is None or isinstance(kept, bool):
            return kept
        if isinstance(kept, str):
            return bool(getattr(spec, kept))
        return spec.name in kept

    def method(self, name):
        """The spec of method ``name`` in this scene; ValueError naming the known ones if none.

        A ``MethodSpec`` is taken as it is (registered or not) when it has this scene's kernel.
        """
        if not isinstance(name, str) and getattr(name, "name", None) is not None:
            if self.kernel(name) is not None:
                return name
            name = name.name
        try:
            return self.methods[name]
        except (KeyError, TypeError):
            known = ", ".join(self.methods)
            raise ValueError(
                f"method {name!r} does not run scene {self.name!r}; methods that do: {known}"
            ) from None


def checked_scene(scene, taker: str) -> Scene:
    """``scene`` if it is a Scene; else a TypeError, in one line, saying how to get one.

    The engine and the ensembles take scenes, never names: a registered scene's name is looked
    up at the door (the command line, the study runner, :func:`stability.run_scene`), or by the
    caller with :func:`stability.registry.scene`.

    Parameters
    ----------
    scene : Scene
        What was passed.
    taker : str
        The function or class it was passed to, for the message.

    Returns
    -------
    Scene
    """
    if isinstance(scene, Scene):
        return scene
    if isinstance(scene, str):
        raise TypeError(f"{taker} takes a Scene, got the name {scene!r}: "
                        f"stability.registry.scene({scene!r}) is the registered one")
    raise TypeError(f"{taker} takes a Scene, got {type(scene).__name__}")


def imported_scene(module: str, name: str, scene: str = "") -> Scene:
    """The scene bound to ``name`` in ``module``, imported: how a pickled scene comes back.

    Parameters
    ----------
    module, name : str
        Where the scene is bound.
    scene : str, optional
        Its own name, for the message when the module cannot be imported.

    Returns
    -------
    Scene
    """
    try:
        home = importlib.import_module(module)
    except ImportError as exc:
        raise ImportError(
            f"scene {scene or name!r} is defined in module {module!r}, which this process "
            f"cannot import ({exc}): put the module's folder on its path (PYTHONPATH), on "
            "every dask worker too", name=module
        ) from None
    return getattr(home, name)


__all__ = ["Scene", "angular_velocity_components", "angular_velocity_tracked", "checked_scene",
           "imported_scene"]
