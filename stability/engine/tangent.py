r"""Tangent scenes: a scene's state carried with tangent vectors under the derivative of its
computed flow, :func:`tangent_scene`.

A scene that declares its :class:`Linearisation` (its vector field ``f(x, p)`` and the
Jacobian-vector product ``J(x, p) v``, as ``@njit`` kernels) has a tangent scene: the state
``(x, v_1, ..., v_k)`` of ``n (k + 1)`` numbers integrated by classical RK4 on the augmented
system

.. math::

    \dot x = f(x), \qquad \dot v_j = J(x)\, v_j \quad (j = 1 \dots k).

A Runge-Kutta method commutes with linearisation (Hairer, Norsett & Wanner, *Solving ODEs I*,
II.6; Hairer, Lubich & Wanner, *Geometric Numerical Integration*, VI.4): differentiating the
stages of one RK4 step of ``x`` with respect to ``x`` gives, stage by stage, the RK4 stages of
the variational equation. So the ``v_j`` carried here are the exact derivative of the computed
RK4 map applied to the start's tangents, to round-off, not an approximation of the exact flow's
derivative to the method's order; and the ``x`` part is the same arithmetic as the scene's own
``rk4`` written by :func:`~stability.integrators.rk4.rk4_source` (bitwise the same run where the
scene's ``rk4`` is that kernel of the same ``f``). With ``k = n`` and ``V(0) = Id`` the tangents
are the columns of the state-transition matrix.

A scene of the user's own (:func:`stability.define_scene`) gets ``J v`` by complex-step
differentiation of its right-hand side (Squire & Trapp, SIAM Rev. 40, 110 (1998)):
``J v = Im f(x + i t v) / t`` with ``t |v| = 1e-20 max(1, |x|)``, exact to round-off (no
difference is taken) where ``f`` is made of arithmetic and analytic functions; Numba compiles
the user's function for complex numbers. Where it cannot (``math.sqrt`` of a complex number, a
comparison) or where ``f`` is not analytic (``abs``, ``min``: caught by a finite-difference check
at the probe state), :func:`tangent_scene` refuses in one line, and ``define_scene(...,
jacobian=)`` takes the product written by hand.
"""

from __future__ import annotations

import functools
import sys
from dataclasses import dataclass, field
from typing import Callable

import numpy as np
from numba.core.errors import NumbaError

from ..integrators.rk4 import RK4, rk4_source
from ..integrators.spec import MethodSpec
from .cache import load_module
from .scene import Scene

#: The size of the imaginary step of the complex-step derivative, relative to max(1, |x|).
COMPLEX_STEP = 1e-20
#: The most positional arguments CPython passes one by one (its compiler's
#: STACK_USE_GUIDELINE); a call with more builds a tuple.
CALL_ARGUMENTS = 30


@dataclass(frozen=True)
class Linearisation:
    """A scene's vector field and its Jacobian-vector product: what its tangent equations are.

    Parameters
    ----------
    rhs : numba dispatcher
        ``rhs(x_0, ..., x_{n-1}, p) -> (f_0, ..., f_{n-1})``, a module-level ``@njit`` function
        bound to its own name.
    jvp : numba dispatcher or None
        ``jvp(x_0, ..., x_{n-1}, v_0, ..., v_{n-1}, p) -> ((J v)_0, ..., (J v)_{n-1})``, the
        same kind of function; None: by complex-step differentiation of ``rhs``.
    params : callable
        ``params(values, h) -> row``: the row ``rhs`` and ``jvp`` read from a parameter set.
    module : str, default ""
        The module where ``rhs`` and ``jvp`` are bound to names, where it is not their own
        functions' (a user scene's kernels module).
    """

    rhs: object
    jvp: object
    params: Callable
    module: str = ""


@dataclass(frozen=True, eq=False)
class TangentScene(Scene):
    """A :class:`Scene` of a state and its tangents (:func:`tangent_scene`); pickled as the
    base scene and the number of tangents, built again where it is unpickled.

    ``base`` is the scene, ``vectors`` the tangents carried and ``rate(x, rows, group)`` the
    instantaneous rate ``v_1 . J v_1 / |v_1|^2`` of each member's first tangent (states
    ``x`` (N, n (k + 1)), parameter rows (G, p), each member's group (N,))."""

    base: Scene | None = None
    vectors: int = 1
    rate: object = field(repr=False, default=None)

    def __reduce_ex__(self, protocol):
        return tangent_scene, (self.base, self.vectors)


def tangent_scene(scene: Scene, vectors: int = 1) -> TangentScene:
    """The tangent scene of ``scene``: its state and ``vectors`` tangents, integrated by RK4.

    Parameters
    ----------
    scene : Scene
        A scene with a ``linearisation`` (every scene of :func:`stability.define_scene`, and the
        registered scenes that declare one: ``free_body``, ``heavy_top``, ``sphere_damper``,
        ``gyrostat``).
    vectors : int, default 1
        Tangents carried, ``1 <= vectors <= n``; ``n``: the state-transition matrix.

    Returns
    -------
    TangentScene
        Named ``<scene>_tangent<k>``; components the scene's, then ``d<component>_<j>`` for
        tangent ``j`` (vector after vector), in the components' units; one method, ``"rk4"``,
        whose ``params`` is the linearisation's; ``observe`` and ``tracked`` the scene's, of
        the state part.

    Raises
    ------
    ValueError, TypeError
        One line: no linearisation, ``vectors`` out of range, or a right-hand side that cannot
        be differentiated by complex step.
    """
    if not isinstance(scene, Scene) or isinstance(scene, TangentScene):
        raise TypeError(f"tangent_scene takes a Scene (not a tangent one), got "
                        f"{type(scene).__name__}")
    n = scene.width
    if isinstance(vectors, bool) or not isinstance(vectors, (int, np.integer)) or not (
            1 <= vectors <= n):
        raise ValueError(f"scene {scene.name!r}: vectors must be a whole number from 1 to its "
                         f"{n} components (n: the state-transition matrix), got {vectors!r}")
    if scene.linearisation is None:
        raise ValueError(f"scene {scene.name!r} declares no linearisation (its right-hand side "
                         "and Jacobian), so it has no tangent equations; scenes that do: "
                         "free_body, heavy_top, sphere_damper, gyrostat and every scene of "
                         "define_scene")
    return _built(scene, int(vectors))


@functools.lru_cache(maxsize=None)
def _built(scene: Scene, k: int) -> TangentScene:
    n = scene.width
    lin = scene.linearisation
    kernels = _kernels(scene, k)
    if lin.jvp is None:
        _check_complex_step(scene, kernels)
    spec = MethodSpec(
        name="rk4", title=RK4.title, order=4, step=kernels.rk4_step, params=lin.params,
        family=RK4.family, evaluations=4, reference=RK4.reference + "; tangents: the RK4 of "
        "the variational equations, the exact derivative of the RK4 map",
        note=f"classical RK4 of {scene.name} and {k} tangent vector{'s' * (k > 1)}")
    names = tuple(f"d{c}_{j + 1}" for j in range(k) for c in scene.components)
    width = n

    def tracked(x, p, axes):
        return scene.tracked(x[:, :width], p, axes)

    return TangentScene(
        name=f"{scene.name}_tangent{k}", title=f"{scene.title}, with {k} tangent vector"
        f"{'s' * (k > 1)}", equations=f"{scene.equations}; v' = J(x) v",
        components=scene.components + names, units=tuple(scene.units) * (k + 1),
        methods={"rk4": spec}, observe=kernels.observe, tracked=tracked,
        parameters=scene.parameters, parameter_units=scene.parameter_units,
        source=scene.source, tracked_units=scene.tracked_units, base=scene, vectors=k,
        rate=kernels.leading_rate)


_MODULE = '''\
"""Tangent kernels of scene {scene!r}: RK4 of its state and {k} tangent vectors.

Written by stability.engine.tangent.tangent_scene; do not edit (sources {{digest}}).
"""

import math

import numpy as np
from numba import njit

from {rhs_module} import {rhs_name} as base_rhs
{jvp_import}
from {observe_module} import {observe_name} as base_observe

{jvp_def}

@njit(forceinline=True, error_model="numpy")
def augmented_rhs({state}, p):
    """x' = f(x) and v_j' = J(x) v_j."""
    {f_names}, = base_rhs({xs}, p)
{tangent_lines}
    return {returned}


{rk4}

@njit(inline="always")
def observe({state}, p, ia, ib, ic):
    """The scene's own observe, of the state part."""
    return base_observe({xs}, p, ia, ib, ic)


@njit(error_model="numpy")
def leading_rate(x, rows, group):
    """d log|v_1| / dt = v_1 . J v_1 / |v_1|^2 of each member's first tangent (N,)."""
    out = np.empty(x.shape[0])
    for i in range(x.shape[0]):
        p = rows[group[i]]
        {unpack}
        {jv}, = jvp({xs}, {v1}, p)
        out[i] = ({dot}) / ({norm})
    return out


@njit(error_model="numpy")
def jvp_at(x, v, p):
    """J(x) v at one state and one vector (n,), for the checks."""
    {unpack_x}
    {unpack_v}
    return np.array(jvp({xs}, {vs}, p))
'''

_COMPLEX_JVP = '''\
@njit(forceinline=True, error_model="numpy")
def jvp({xs}, {vs}, p):
    """J v by complex step: Im f(x + i t v) / t, t |v| = COMPLEX_STEP max(1, |x|)."""
    scale = max({abs_v})
    if scale == 0.0:
        return {zeros}
    t = {step!r} * max(1.0, {abs_x}) / scale
    {g_names}, = base_rhs({shifted}, p)
    return {imag}
'''


def _kernels(scene: Scene, k: int):
    """Write and import the tangent scene's module (:func:`load_module`): the augmented
    right-hand side, its RK4 step, the observe of the state part and the rate of the first
    tangent. The state is ``x0 ... x{n-1}`` and tangent ``j`` is ``x{n (j + 1)} ...``."""
    n = scene.width
    lin = scene.linearisation
    names = [f"x{i}" for i in range(n * (k + 1))]
    xs = names[:n]
    vs = [names[n * (j + 1):n * (j + 2)] for j in range(k)]
    one = "," if n == 1 else ""
    rhs_module, rhs_name = _located(lin.rhs, lin.module)
    observe_module, observe_name = _located(scene.observe, "")
    plain_v = [f"u{i}" for i in range(n)]
    if lin.jvp is None:
        jvp_def = _COMPLEX_JVP.format(
            xs=", ".join(xs), vs=", ".join(plain_v),
            abs_v=", ".join(f"abs({u})" for u in plain_v) + (", 0.0" if n == 1 else ""),
            zeros=", ".join(["0.0"] * n) + one,
            step=COMPLEX_STEP, abs_x=", ".join(f"abs({x})" for x in xs),
            g_names=", ".join(f"g{i}" for i in range(n)),
            shifted=", ".join(f"complex({x}, t * {u})" for x, u in zip(xs, plain_v)),
            imag=", ".join(f"g{i}.imag / t" for i in range(n)) + one)
        jvp_import = ""
    else:
        jvp_def = ""
        jvp_module, jvp_name = _located(lin.jvp, lin.module)
        jvp_import = f"from {jvp_module} import {jvp_name} as jvp"
    tangent_lines = "\n".join(
        f"    {', '.join(f'a{j}_{i}' for i in range(n))}, = jvp({', '.join(xs)}, "
        f"{', '.join(vs[j])}, p)" for j in range(k))
    returned = ", ".join([f"f{i}" for i in range(n)]
                         + [f"a{j}_{i}" for j in range(k) for i in range(n)])
    source = _MODULE.format(
        scene=scene.name, k=k, rhs_module=rhs_module, rhs_name=rhs_name,
        jvp_import=jvp_import, observe_module=observe_module, observe_name=observe_name,
        jvp_def=jvp_def, state=", ".join(names),
        f_names=", ".join(f"f{i}" for i in range(n)), xs=", ".join(xs),
        tangent_lines=tangent_lines, returned=returned,
        rk4=rk4_source(n * (k + 1), rhs="augmented_rhs"),
        unpack=("; ".join(f"x{i} = x[i, {i}]" for i in range(n)) + "; "
                + "; ".join(f"{v} = x[i, {n + i}]" for i, v in enumerate(plain_v))),
        jv=", ".join(f"a{i}" for i in range(n)), v1=", ".join(plain_v),
        dot=" + ".join(f"a{i} * u{i}" for i in range(n)),
        norm=" + ".join(f"u{i} * u{i}" for i in range(n)),
        unpack_x="; ".join(f"x{i} = x[{i}]" for i in range(n)),
        unpack_v="; ".join(f"u{i} = v[{i}]" for i in range(n)),
        vs=", ".join(plain_v))
    if n * (k + 1) + 4 > CALL_ARGUMENTS:
        # CPython passes more than CALL_ARGUMENTS arguments as one tuple (CALL_FUNCTION_EX),
        # which Numba's inliner refuses ("Calling a closure with *args"): the loop's calls of
        # the step and observe go through typing instead, and LLVM inlines them
        source = source.replace('@njit(inline="always")',
                                '@njit(forceinline=True, error_model="numpy")')
    functions = [lin.rhs.py_func, scene.observe.py_func]
    functions += [lin.jvp.py_func] if lin.jvp is not None else []
    roots = tuple(dict.fromkeys([rhs_module, observe_module]
                                + [f.__module__ for f in functions]))
    return load_module(f"{scene.name}__tangent{k}", source, roots, tuple(functions))


def _located(function, module: str):
    """(module, name) where the ``@njit`` ``function`` is bound at the top level: in
    ``module`` where given (a scene's kernels module), else its own function's module."""
    home = module or function.py_func.__module__
    found = sys.modules.get(home)
    name = next((key for key, value in vars(found).items() if value is function), None) \
        if found is not None else None
    if name is None:
        raise ValueError(f"the kernel {function.py_func.__qualname__} must be a module-level "
                         f"@njit function bound to a name in {home}, so that the tangent "
                         "kernels can import it")
    return home, name


def _check_complex_step(scene: Scene, kernels) -> None:
    """Compile the complex-step product at the probe state and hold it to a central difference
    there: one line where Numba cannot compile the right-hand side for complex numbers, or
    where it is not analytic."""
    x, p = _probe(scene)
    rng = np.random.default_rng(1)
    v = rng.standard_normal(x.size)
    try:
        jv = kernels.jvp_at(x, v, p)
    except NumbaError as exc:
        reason = str(exc).strip().splitlines()
        reason = next((line.strip() for line in reason if line.strip()
                       and not line.startswith(("Failed in", "During:"))), type(exc).__name__)
        raise TypeError(f"scene {scene.name!r}: its rhs cannot be differentiated by complex step "
                        f"(Numba cannot compile it for complex numbers: {reason:.160}); give "
                        "define_scene a jacobian=jvp(x_0, ..., v_0, ..., p) returning J v") \
            from None
    step = 1e-6 * max(1.0, float(np.max(np.abs(x))))
    f = kernels.base_rhs.py_func
    with np.errstate(all="ignore"):
        diff = (np.array(f(*(x + step * v), p)) - np.array(f(*(x - step * v), p))) / (2 * step)
    scale = max(float(np.max(np.abs(diff))), float(np.max(np.abs(jv))), 1e-300)
    if not np.all(np.isfinite(jv)) or float(np.max(np.abs(jv - diff))) > 1e-4 * scale:
        raise ValueError(f"scene {scene.name!r}: the complex-step derivative of its rhs differs "
                         "from a finite difference at the probe state (the rhs is not analytic: "
                         "abs, min, max or a branch?); give define_scene a jacobian=jvp(x_0, ..., "
                         "v_0, ..., p) returning J v")


def _probe(scene: Scene):
    """A state and a parameter row to try the tangent kernels on: the scene's example's first,
    else ones."""
    n = scene.width
    if scene.example is not None:
        x0, sets = scene.example(1)
        return np.asarray(x0, dtype=float)[0], scene.linearisation.params(sets[0], 0.01)
    return np.ones(n), scene.linearisation.params(np.ones(len(scene.parameters)), 0.01)


__all__ = ["COMPLEX_STEP", "Linearisation", "TangentScene", "tangent_scene"]
