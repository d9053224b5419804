"""Scenes from the user's own code: :func:`define_scene`.

A user writes the right-hand side of ``x' = f(x, p)`` in a module of their own and calls
``define_scene``. It checks the definition (each mistake is one line saying what is wrong and
how to mend it), writes the scene's kernels into the disk cache of the member loops
(:func:`stability.engine.cache.load_module`, keyed on the user's module, so an edit compiles
again): classical RK4 of the right-hand side (:func:`stability.integrators.rk4.rk4_source`) and,
unless the user gives one, an ``observe`` that tracks components by number. It compiles each of
the user's functions there once (cached like the loops; what Numba cannot compile is one line
too) and returns a :class:`~stability.engine.scene.Scene` that runs wherever a registered one
does: :func:`stability.engine.propagate_groups`, and
:class:`~stability.ensemble.plan.Plan` run by
:func:`~stability.ensemble.chunks.run_plan` (chunks in a store, resume, dask workers,
which import the user's module to find the scene).
"""

from __future__ import annotations

import inspect
import numbers
import re
import sys
import types
import warnings
from dataclasses import dataclass, replace
from typing import Callable, Mapping

import numpy as np
from numba.core.dispatcher import Dispatcher
from numba.core.errors import NumbaError

from .cache import load_module
from ..integrators.rk4 import RK4, rk4_source
from ..integrators.spec import MethodSpec, body_params
from ..util.checks import real_array, real_number
from .scene import Scene
from .tangent import Linearisation

#: Names :func:`define_scene` refuses: those of the package's own scenes, added by
#: :mod:`stability.registry` as it reads the families (the engine knows no family).
RESERVED_NAMES: set[str] = set()

#: The step at which a method's ``params`` and kernels are tried at definition time.
PROBE_H = 0.01

_NAME = re.compile(r"[a-z][a-z0-9_]*\Z")
_ANSI = re.compile(r"\x1b\[[0-9;]*m")

_KERNELS = '''\
"""Kernels of scene {scene!r} (defined in {caller}): classical RK4 of {rhs}{observe_note}.

Written by stability.engine.user_scene.define_scene; do not edit (sources {{digest}}).
"""

from numba import njit

{imports}

SOURCES = "{{digest}}"

{rhs_line}
{jacobian_line}

{rk4}

@njit(forceinline=True, error_model="numpy")
def pick({state}, i):
    """Component i of the state (the last one for any larger i)."""
    return {pick}


@njit(inline="always")
def observe({state}, p, ia, ib, ic):
    """Components ia, ib and ic: the tracked spin-axis component and two across it."""
    return pick({state}, ia), pick({state}, ib), pick({state}, ic)

{checks}
'''

_CHECK = '''
@njit
def check_{role}(x, h, p, axes):
    """{function} once, so that what Numba cannot compile is found at definition time."""
    return {call}
'''


@dataclass(frozen=True)
class ParameterRow:
    """``params(values, h)`` of a user scene's methods: the kernels' parameter row.

    ``values`` is a parameter set: a mapping of every name to its number, or the numbers in the
    order of the names (one number alone for one name). The row is those numbers, or what the
    user's ``make(values, h)`` makes of them (float array of the numbers in order).

    Parameters
    ----------
    scene : str
        The scene's name (for messages).
    names : tuple of str
        The parameters' names, in row order.
    make : callable or None, default None
        ``make(values, h) -> row``; None: the row is the values.
    """

    scene: str
    names: tuple
    make: Callable | None = None

    def values(self, values) -> np.ndarray:
        """The parameter set ``values`` as floats in the order of ``names``."""
        if isinstance(values, Mapping):
            unknown = sorted(set(values) - set(self.names))
            missing = [n for n in self.names if n not in values]
            if unknown or missing:
                raise ValueError(
                    f"scene {self.scene!r}: the parameter set must name exactly "
                    f"{', '.join(self.names) or 'nothing'} (or give those numbers in that "
                    "order)"
                    + (f"; unknown: {', '.join(map(str, unknown))}" if unknown else "")
                    + (f"; missing: {', '.join(missing)}" if missing else "")
                )
            out = np.array([real_number(f"scene {self.scene!r}: parameter {n}", values[n])
                            for n in self.names], dtype=float)
        else:
            out = real_array(f"scene {self.scene!r}: a parameter set", values).reshape(-1)
        if out.size != len(self.names):
            count = len(self.names)
            raise ValueError(
                f"scene {self.scene!r}: a parameter set has {count} number{'s' * (count != 1)} "
                f"({', '.join(self.names) or 'none'}), got {out.size}"
            )
        for name, value in zip(self.names, out):
            if not np.isfinite(value):
                raise ValueError(f"scene {self.scene!r}: parameter {name} must be finite, "
                                 f"got {value}")
        return out

    def __call__(self, values, h=0.0) -> np.ndarray:
        values = self.values(values)
        if self.make is None:
            return values
        return np.ascontiguousarray(self.make(values, h), dtype=float).reshape(-1)


@dataclass(frozen=True)
class OnValues:
    """``f(x, parameters)`` given the parameter set as :meth:`ParameterRow.values` makes it:
    the user's invariants and exact solution see the numbers in the order of the names."""

    row: ParameterRow
    function: Callable

    def __call__(self, x, parameters, *args):
        return self.function(x, self.row.values(parameters), *args)


def tracked_components(x, p, axes):
    """The default ``tracked``: components ``axes`` of states ``x`` (N, n), the last one for
    any larger number (as the default ``observe``)."""
    last = x.shape[1] - 1
    return tuple(x[:, min(int(axes[k]), last)] for k in range(3))


def define_scene(name, components, units, rhs, parameters=(), *, parameter_units=None,
                 params=None, title=None, equations=None, methods=(), observe=None,
                 tracked=None, tracked_units=None, invariants=None, exact=None,
                 example=None, jacobian=None) -> Scene:
    """A scene from the user's own right-hand side ``x' = rhs(x, p)``, run as registered ones.

    Call it at the top level of a module of yours and bind the result to a name there
    (``SCENE = define_scene(...)``): that module is the scene's home, which dask workers import
    to find it (put its folder on their ``PYTHONPATH``). ``rhs`` (and any kernel, ``observe``)
    must be top-level functions of an importable module too: the compiled kernels import
    them. The kernels are compiled on the first run and kept in the disk cache
    (``$STABILITY_CACHE_DIR``) under a digest of the modules that define the scene and its
    functions: the next process loads them, an edit of those modules compiles again. Numba
    reads global variables as constants, so keep numbers that change in the parameters.

    Parameters
    ----------
    name : str
        Lowercase name (letters, digits, ``_``), not one of the registered scenes.
    components : sequence of str
        Names of the state's numbers, in order (identifiers).
    units : sequence of str
        UDUNITS unit of each component (``"rad s-1"``, ``"1"``...).
    rhs : function
        ``rhs(x_0, ..., x_{n-1}, p) -> (dx_0, ..., dx_{n-1})``: one float per component, then
        the parameter row ``p`` (float64 array), returning a tuple of n floats. A plain
        function is compiled with ``numba.njit(inline="always")``; an ``@njit`` one is used as
        it is. The scene's method ``"rk4"`` is classical RK4 of it.
    parameters : sequence of str, default ()
        Names of the numbers of a parameter set. A method's ``params(values, h)`` takes a set
        as a mapping by name or a sequence in this order.
    parameter_units : sequence of str, optional
        UDUNITS unit of each parameter, for the Dataset of a run (:func:`stability.run_scene`);
        without them the parameters are labelled ``"1"``.
    params : callable, optional
        ``params(values, h) -> row``: the kernels' row from the set's numbers (float array in
        the order of ``parameters``) and the step; by default the row is the numbers.
    title, equations : str, optional
        Human name (default ``name``) and the equations in one line (default: the first line
        of ``rhs``'s docstring).
    methods : sequence of MethodSpec, optional
        More methods, each with its own stage kernel
        ``step(x_0, ..., x_{n-1}, h, p, s) -> (d_0, ..., d_{n-1}, iterations)``
        (``njit(inline="always")``, returning increments). One whose ``params`` is the default
        takes the scene's.
    observe, tracked : optional
        What the loop tracks when a run asks for it (give both or neither):
        ``observe(x_0, ..., x_{n-1}, p, ia, ib, ic) -> (a, b, c)`` (``@njit``) and the same in
        NumPy, ``tracked(x, p, axes)`` over states ``x`` (N, n). By default components ``ia``,
        ``ib``, ``ic`` by number.
    tracked_units : str, optional
        UDUNITS unit of the amplitude across the spin axis that ``observe`` tracks (``b`` and
        ``c``), for the Dataset of a tracked run, which then needs no ``tracked_units=``; by
        default those of the components read, where the default ``observe`` tracks them.
    invariants : mapping of str to callable, optional
        ``f(x, values) -> ndarray (N,)`` of states ``x`` (N, n) and a parameter set's numbers.
    exact : callable, optional
        ``exact(x0, values, t) -> ndarray (N, n)``: the exact state at time ``t`` from ``x0``.
    example : callable, optional
        ``example(n, seed=0) -> (x0, sets)``: ``n`` starts (n, n_components) and a list of
        parameter sets. Its first start and set are where the functions are tried at
        definition time (else a state and a set of ones).
    jacobian : function, optional
        ``jacobian(x_0, ..., x_{n-1}, v_0, ..., v_{n-1}, p) -> ((J v)_0, ..., (J v)_{n-1})``,
        the Jacobian of ``rhs`` applied to ``v`` (plain or ``@njit``, top level), for the
        scene's tangent equations (:func:`stability.engine.tangent.tangent_scene`). Without
        it, ``J v`` comes from a complex step of ``rhs``, which needs ``rhs`` to compile for
        complex numbers (arithmetic, ``cmath``; not ``math.sqrt``, ``abs`` or comparisons).

    Returns
    -------
    Scene
        Methods ``"rk4"`` and those of ``methods``; ``source`` names the digest of its sources.

    Raises
    ------
    TypeError, ValueError
        A mistake in the definition, in one line naming the scene, what is wrong and how to
        mend it: names and units, a function's arguments or what it returns, a call that
        raises, or what Numba cannot compile.
    """
    caller = sys._getframe(1).f_globals.get("__name__", "")
    _check_name(name)
    components = _names(name, "components", components, empty=False)
    width = len(components)
    units = _units(name, units, components)
    parameters = _names(name, "parameters", parameters, empty=True)
    parameter_units = (() if parameter_units is None else
                       _units(name, parameter_units, parameters, "parameter"))
    if params is not None and not callable(params):
        raise TypeError(f"scene {name!r}: params must be a function params(values, h), "
                        f"got {type(params).__name__}")
    row = ParameterRow(name, parameters, params)
    rhs_function = _top_level(name, "rhs", rhs, njit_only=False)
    _check_arguments(name, "rhs", rhs_function, [*components, "p"])
    extra = _methods(name, methods, width, row)
    if (observe is None) != (tracked is None):
        raise ValueError(f"scene {name!r}: give observe and tracked together (the loop's "
                         "tracking and the same in NumPy), or neither")
    if observe is not None:
        _check_arguments(name, "observe", _top_level(name, "observe", observe),
                         [*components, "p", "ia", "ib", "ic"])
    if tracked_units is not None and (not isinstance(tracked_units, str)
                                      or not tracked_units.strip()):
        raise TypeError(f"scene {name!r}: tracked_units must be a UDUNITS string such as "
                        f"'rad s-1' or '1', got {tracked_units!r}")
    try:
        invariants = dict(invariants or {})
    except (TypeError, ValueError):
        raise TypeError(f"scene {name!r}: invariants must be a dict of name: function(x, "
                        f"values), got {type(invariants).__name__}") from None
    for label, function in [*invariants.items(), ("exact", exact), ("example", example),
                            ("tracked", tracked)]:
        if function is not None and not callable(function):
            raise TypeError(f"scene {name!r}: {label} must be a function, "
                            f"got {type(function).__name__}")

    if jacobian is not None:
        _check_arguments(name, "jacobian", _top_level(name, "jacobian", jacobian,
                                                      njit_only=False),
                         [*components, *(f"v_{c}" for c in components), "p"])
    x, values, where = _probe(name, example, width, row)
    p = _row(name, row, values)
    _returned(name, "rhs", rhs_function, (*x, p), width, where)
    if jacobian is not None:
        _returned(name, "jacobian", getattr(jacobian, "py_func", jacobian), (*x, *x, p), width,
                  where)
    for spec in extra.values():
        _returned(name, f"method {spec.name!r}'s kernel", spec.step.py_func,
                  (*x, PROBE_H, p, 0), width + 1, where)
    if observe is not None:
        _returned(name, "observe", observe.py_func, (*x, p, 0, 1, 2), 3, where)
    for label, function in invariants.items():
        _shaped(name, f"invariant {label!r}", function, (x[None, :], values), (1,), where)
    if exact is not None:
        _shaped(name, "exact", exact, (x[None, :], values, 0.0), (1, width), where)

    kernels = _kernels(name, caller, rhs, extra, observe, width, jacobian)
    _compiles(name, kernels, rhs_function, extra, observe, x, p, where, jacobian)
    rk4 = MethodSpec(
        name="rk4", title=RK4.title, order=4, step=kernels.rk4_step, params=row,
        family=RK4.family, evaluations=4, reference=RK4.reference,
        note=f"classical RK4 of {rhs_function.__qualname__}, written for this scene",
    )
    doc = (rhs_function.__doc__ or "").strip().splitlines()
    return Scene(
        name=name,
        title=title or name,
        equations=equations or (doc[0] if doc else f"x' = {rhs_function.__qualname__}(x, p)"),
        components=components,
        units=units,
        methods={"rk4": rk4, **extra},
        observe=observe if observe is not None else kernels.observe,
        tracked=tracked if tracked is not None else tracked_components,
        invariants={label: OnValues(row, f) for label, f in invariants.items()},
        exact=None if exact is None else OnValues(row, exact),
        example=example,
        parameters=parameters,
        parameter_units=parameter_units,
        module=caller,
        source=kernels.SOURCES,
        tracked_units=tracked_units or "",
        linearisation=Linearisation(kernels.rhs, None if jacobian is None else kernels.jacobian,
                                    row, module=kernels.__name__),
    )


# --- the checks, each one line ------------------------------------------------------------------


def _check_name(name):
    if not isinstance(name, str) or not _NAME.match(name):
        raise ValueError(f"define_scene: the name must be lowercase letters, digits and _ "
                         f"(starting with a letter), got {name!r}")
    if name in RESERVED_NAMES:
        raise ValueError(f"define_scene: {name!r} is a registered scene's name; give yours "
                         "another")


def _names(scene, what, names, empty):
    if isinstance(names, str) or not isinstance(names, (list, tuple)):
        raise TypeError(f"scene {scene!r}: {what} must be a list of names, got {names!r}")
    bad = [n for n in names if not isinstance(n, str) or not n.isidentifier()]
    if bad:
        raise ValueError(f"scene {scene!r}: {what} must be identifiers (letters, digits, _), "
                         f"got {bad[0]!r}")
    twice = sorted({n for n in names if names.count(n) > 1})
    if twice:
        raise ValueError(f"scene {scene!r}: {what} must differ; {', '.join(twice)} comes twice")
    if not names and not empty:
        raise ValueError(f"scene {scene!r}: {what} must name at least one number")
    return tuple(names)


def _units(scene, units, components, what="component"):
    key = "units" if what == "component" else f"{what}_units"
    if isinstance(units, str) or not isinstance(units, (list, tuple)):
        raise TypeError(f"scene {scene!r}: {key} must be a list of strings, one per {what}, "
                        f"got {units!r}")
    if len(units) != len(components):
        raise ValueError(f"scene {scene!r}: {len(units)} units for {len(components)} {what}s "
                         f"({', '.join(components)}); give one unit per {what}")
    bad = [u for u in units if not isinstance(u, str) or not u.strip()]
    if bad:
        raise TypeError(f"scene {scene!r}: a unit must be a UDUNITS string such as 'rad s-1' "
                        f"or '1', got {bad[0]!r}")
    return tuple(units)


def _top_level(scene, role, function, njit_only=True):
    """The Python function of ``function``, which must be bound to its own name at the top level
    of its module (the kernels' module imports it from there)."""
    python = getattr(function, "py_func", function)
    if not isinstance(python, types.FunctionType) or (
            njit_only and not isinstance(function, Dispatcher)):
        kind = '@njit(inline="always") function' if njit_only else "function (plain or @njit)"
        raise TypeError(f"scene {scene!r}: {role} must be a {kind}, "
                        f"got {type(function).__name__}")
    home = sys.modules.get(python.__module__)
    if python.__qualname__ != python.__name__ or getattr(home, python.__name__, None) is not \
            function:
        raise ValueError(f"scene {scene!r}: {role} {python.__qualname__} must be defined at "
                         f"the top level of its module ({python.__module__}) under its own "
                         "name, so the compiled kernels can import it")
    return python


def _check_arguments(scene, role, python, expected):
    """``python`` takes exactly the positional arguments ``expected`` (their number)."""
    taken = inspect.signature(python).parameters.values()
    plain = all(a.kind in (a.POSITIONAL_ONLY, a.POSITIONAL_OR_KEYWORD) for a in taken)
    if not plain or len(taken) != len(expected):
        got = ", ".join(str(a) for a in taken)
        raise TypeError(f"scene {scene!r}: {role}({got}) takes {len(taken)} arguments; it is "
                        f"called as {role}({', '.join(expected)}): give it those "
                        f"{len(expected)}")


def _methods(scene, methods, width, row):
    specs = list(methods.values()) if isinstance(methods, Mapping) else list(methods or ())
    out = {}
    for spec in specs:
        if not isinstance(spec, MethodSpec):
            raise TypeError(f"scene {scene!r}: methods must be MethodSpecs, "
                            f"got {type(spec).__name__}")
        if spec.name == "rk4" or spec.name in out:
            raise ValueError(f"scene {scene!r}: method name {spec.name!r} is taken (rk4 is the "
                             "scene's own RK4); give the method another name")
        _check_arguments(scene, f"method {spec.name!r}'s kernel",
                         _top_level(scene, f"method {spec.name!r}'s kernel", spec.step),
                         [*(f"x_{i}" for i in range(width)), "h", "p", "s"])
        out[spec.name] = replace(spec, params=row) if spec.params is body_params else spec
    return out


def _probe(scene, example, width, row):
    """A state and a parameter set to try the functions on, and how to say where that is."""
    if example is None:
        return (np.ones(width), np.ones(len(row.names)),
                "a state and parameters of ones (give example= to try it elsewhere)")
    try:
        x0, sets = example(1)
        x0 = np.asarray(x0, dtype=float)
        sets = list(sets)
    except Exception as exc:
        raise ValueError(f"scene {scene!r}: example(1) raised {type(exc).__name__}: {exc}; "
                         "it must return (x0, parameter sets)") from None
    if x0.shape != (1, width) or not sets:
        raise ValueError(f"scene {scene!r}: example(n) must return n starts of shape "
                         f"(n, {width}) and a non-empty list of parameter sets; example(1) gave "
                         f"starts of shape {x0.shape} and {len(sets)} sets")
    return x0[0], row.values(sets[0]), "example's first start and parameter set"


def _row(scene, row, values):
    try:
        p = row(values, PROBE_H)
    except Exception as exc:
        raise ValueError(f"scene {scene!r}: params(values, h) raised {type(exc).__name__}: "
                         f"{exc}") from None
    if not np.all(np.isfinite(p)):
        raise ValueError(f"scene {scene!r}: the parameter row is not finite: {p.tolist()}")
    return p


def _call(scene, role, function, args, where):
    try:
        with np.errstate(all="ignore"), warnings.catch_warnings():
            warnings.simplefilter("ignore")
            return function(*args)
    except Exception as exc:
        size = args[-1].size if role == "rhs" else 0
        hint = (f" (p has {size} number{'s' * (size != 1)})"
                if isinstance(exc, IndexError) and role == "rhs" else "")
        raise ValueError(f"scene {scene!r}: {role} raised {type(exc).__name__}: "
                         f"{_reason(exc)}{hint}, tried on {where}") from None


def _returned(scene, role, function, args, count, where):
    """``function(*args)`` must return a tuple of ``count`` numbers."""
    out = _call(scene, role, function, args, where)
    numbers_only = isinstance(out, tuple) and all(
        isinstance(v, numbers.Real) and not isinstance(v, bool) for v in out)
    if isinstance(out, tuple) and len(out) == count and not numbers_only:
        k, bad = next((k, v) for k, v in enumerate(out)
                      if not isinstance(v, numbers.Real) or isinstance(v, bool))
        raise ValueError(f"scene {scene!r}: {role} returned {type(bad).__name__} {bad!r:.40} "
                         f"as its number {k}; it must return a tuple of {count} numbers, "
                         f"tried on {where}")
    if not numbers_only or len(out) != count:
        got = (f"a tuple of {len(out)}" if isinstance(out, tuple) else type(out).__name__)
        raise ValueError(f"scene {scene!r}: {role} returned {got}; it must return a tuple of "
                         f"{count} numbers, tried on {where}")


def _shaped(scene, role, function, args, shape, where):
    out = np.shape(_call(scene, role, function, args, where))
    if out != shape:
        raise ValueError(f"scene {scene!r}: {role} returned shape {out} for one state; it must "
                         f"return one {'number' if len(shape) == 1 else 'state'} per state, "
                         f"shape {shape} here, tried on {where}")


# --- the kernels' module ------------------------------------------------------------------------


def _kernels(name, caller, rhs, extra, observe, width, jacobian=None):
    """Write and import the scene's kernels (:func:`load_module`): the RK4 step, the default
    observe, the user's jacobian where given, and one compile check per function of the
    user's."""
    state = ", ".join(f"x{i}" for i in range(width))
    taken = ", ".join(f"x[{i}]" for i in range(width))
    functions = {"rhs": rhs, **{f"kernel_{k}": spec.step for k, spec in enumerate(
        extra.values())}}
    calls = {"rhs": f"rhs({taken}, p)"}
    calls.update({role: f"user_{role}({taken}, h, p, 0)" for role in functions if role != "rhs"})
    if observe is not None:
        functions["observe"] = observe
        calls["observe"] = f"user_observe({taken}, p, axes[0], axes[1], axes[2])"
    if jacobian is not None:
        functions["jacobian"] = jacobian
        calls["jacobian"] = f"jacobian({taken}, {taken}, p)"
    python = {role: getattr(f, "py_func", f) for role, f in functions.items()}
    imports = [f"from {f.__module__} import {f.__name__} as user_{role}"
               for role, f in python.items()]
    checks = [_CHECK.format(role=role, function=f.__qualname__, call=calls[role])
              for role, f in python.items()]
    pick = " else (".join(f"x{i} if i == {i}" for i in range(width - 1))
    pick = (f"{pick} else x{width - 1}" + ")" * (width - 2)) if width > 1 else "x0"
    source = _KERNELS.format(
        scene=name, caller=caller, rhs=python["rhs"].__qualname__,
        observe_note="" if observe is None else "; the user's observe",
        imports="\n".join(imports),
        rhs_line=("rhs = user_rhs" if isinstance(rhs, Dispatcher)
                  else 'rhs = njit(inline="always")(user_rhs)'),
        jacobian_line=("" if jacobian is None else "jacobian = user_jacobian"
                       if isinstance(jacobian, Dispatcher)
                       else 'jacobian = njit(inline="always")(user_jacobian)'),
        rk4=rk4_source(width), state=state, pick=pick, checks="\n".join(checks),
    )
    roots = dict.fromkeys([caller, *(f.__module__ for f in python.values())])
    return load_module(f"{name}__kernels", source, tuple(roots), tuple(python.values()))


def _compiles(scene, kernels, rhs, extra, observe, x, p, where, jacobian=None):
    """Compile (or load) and run each check of the kernels' module: Numba's complaint, or the
    exception the compiled function raised, in one line."""
    checks = [("rhs", "rhs", rhs)]
    checks += [(f"kernel_{k}", f"method {spec.name!r}'s kernel", spec.step.py_func)
               for k, spec in enumerate(extra.values())]
    if observe is not None:
        checks.append(("observe", "observe", observe.py_func))
    if jacobian is not None:
        checks.append(("jacobian", "jacobian", getattr(jacobian, "py_func", jacobian)))
    axes = np.array([0, 1, 2], dtype=np.int64)
    for role, label, python in checks:
        try:
            getattr(kernels, f"check_{role}")(x, PROBE_H, p, axes)
        except NumbaError as exc:
            raise TypeError(f"scene {scene!r}: Numba cannot compile {label} "
                            f"{python.__qualname__}: {_reason(exc)}") from None
        except Exception as exc:  # compiled, then raised when run
            hint = (" (compiled code raises on a division by zero, where NumPy gives inf or "
                    "nan)" if isinstance(exc, ZeroDivisionError) else "")
            raise ValueError(f"scene {scene!r}: {label} {python.__qualname__} raised "
                             f"{type(exc).__name__}: {_reason(exc)} when compiled{hint}, "
                             f"tried on {where}") from None


def _reason(exc) -> str:
    """The line of an exception's message that says what is wrong (Numba's run over many),
    and where, when it says so."""
    text = _ANSI.sub("", str(exc))
    lines = [line.strip() for line in text.splitlines() if line.strip()]
    reason = next((line for line in lines if not line.startswith(
        ("Failed in", "During:", "File ", "^"))), type(exc).__name__)
    where = (re.findall(r"at (\S+\.py) \((\d+)\)", text)
             or re.findall(r'File "([^"]+)", line (\d+)', text))
    return reason + (f" ({where[0][0]}, line {where[0][1]})" if where else "")


__all__ = ["ParameterRow", "define_scene"]
