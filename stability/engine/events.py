"""Events a user defines: a function ``g(x, t, p)`` whose sign changes are located and kept.

An :class:`Event` names the function, which crossings count (``direction``: ``"up"``, g from
negative to non-negative; ``"down"``, the reverse; ``"both"``), what a crossing does (``action``:
``"record"`` its time, or ``"stop"`` the member there) and how many times are kept (``count``; a
stop event stops the member at its ``count``-th crossing). The adaptive loop
(:mod:`stability.engine.adaptive`) compares ``g`` at the ends of each accepted step, and where its
sign changed locates the root on the step's continuous extension (the Dormand-Prince dense output,
Hairer, Norsett & Wanner, *Solving ODEs I*, II.6) with the Anderson-Björck variant of regula falsi
(Anderson & Björck, BIT 13, 253 (1973)) down to round-off in ``t``; several crossings in one step
are taken in the order of their times (Shampine & Thompson, *Event location for ordinary
differential equations*, Comput. Math. Appl. 39, 43 (2000)). The fixed-step loop
(:func:`stability.engine.loop.event_source`) does the same at the end of every step, on the method's
own step from the state before it (the exact flow for an exact method). As there, a function that
changes sign twice within one step is not seen; a tighter ``rtol`` (a smaller ``h``) gives shorter
steps. Both loops locate with :func:`bracketed_root` and take a step's crossings with
:func:`taken_in_order`.

:func:`checked_events` checks a run's events before any work: each mistake is one line.
"""

from __future__ import annotations

import importlib
import numbers
import sys
import types
import warnings
from dataclasses import dataclass

import numpy as np
from numba import njit
from numba.core.dispatcher import Dispatcher
from numba.core.errors import NumbaError

#: Direction codes the compiled loop reads.
DIRECTIONS = {"up": 1, "down": -1, "both": 0}
#: Actions, and whether they stop the member.
ACTIONS = {"record": False, "stop": True}


@dataclass(frozen=True)
class Event:
    """One event: the sign changes of ``g(x, t, p)`` along each member's motion.

    Parameters
    ----------
    g : function
        ``g(x, t, p) -> float``: the state ``x`` (float64 array, shape (n,)), the time ``t`` and
        the member's parameter row ``p``; a top-level function of an importable module, plain
        or ``@njit`` (compiled by Numba either way).
    direction : {"up", "down", "both"}, default "both"
        Which crossings count: ``"up"`` where g goes from negative to >= 0, ``"down"`` the
        reverse.
    action : {"record", "stop"}, default "record"
        Keep the crossing's time, or also stop the member there (at its ``count``-th crossing).
    count : int, default 1
        Crossing times kept per member (all crossings are counted).
    name : str, optional
        The event's name in the Dataset (default: ``g``'s own).
    """

    g: object
    direction: str = "both"
    action: str = "record"
    count: int = 1
    name: str = ""

    def __post_init__(self):
        if self.direction not in DIRECTIONS:
            raise ValueError(f"event direction must be one of {', '.join(DIRECTIONS)}, got "
                             f"{self.direction!r}")
        if self.action not in ACTIONS:
            raise ValueError(f"event action must be one of {', '.join(ACTIONS)}, got "
                             f"{self.action!r}")
        if isinstance(self.count, bool) or not isinstance(self.count, numbers.Integral) or \
                self.count < 1:
            raise ValueError(f"event count must be a whole number >= 1, got {self.count!r}")
        python = getattr(self.g, "py_func", self.g)
        if not isinstance(python, types.FunctionType):
            raise TypeError(f"event g must be a function g(x, t, p), got "
                            f"{type(self.g).__name__}")
        if not self.name:
            object.__setattr__(self, "name", python.__name__)

    @property
    def python(self):
        """The Python function of ``g``."""
        return getattr(self.g, "py_func", self.g)

    def __reduce__(self):
        """Pickled by reference to ``g`` (its module and name), as the compiled loop imports
        it: a dask worker then holds its own module's ``g``, the one :func:`located` finds
        there, not a copy rebuilt from the pickle; a ``g`` the loop could not import is the
        one-line ValueError of :func:`located`."""
        module, name = located(self.g)
        return _by_reference, (module, name, self.direction, self.action, self.count,
                               self.name)


def _by_reference(module: str, name: str, direction: str, action: str, count: int,
                  label: str) -> Event:
    """The :class:`Event` of ``g`` = ``module.name``, imported (see :meth:`Event.__reduce__`)."""
    return Event(getattr(importlib.import_module(module), name), direction, action, count, label)


#: The regula falsi both compiled loops locate a crossing with, as source for their templates
#: (``bracketed_root``): ``_root(k, {extension}, t0, h, ga, gb, p,
#: {state})`` is the time of event k's sign change in [t0, t0 + h], where g is ga at t0 and gb at
#: t0 + h, the state at a time c made into ``{state}`` by ``{evaluate}``; the estimate with the
#: smallest |g| is returned once the bracket is down to round-off, ``4 eps max(|a|, |b|)``. An
#: estimate closer than half of that to an end of the bracket is taken at that distance instead:
#: once the secant has converged onto a root beside one end, the next evaluation closes the
#: bracket, where the far end's g was otherwise scaled down (as slowly as bisection) until the
#: bracket closed. On the free body's flips, RK4 at h = 0.002 to 0.05 s, a crossing took 3.0 to
#: 3.9 evaluations of g on average (at most 4) instead of 12 to 20 (up to 39), and the times
#: located moved by at most 0.54 of the tolerance. An end kept twice in a row has its g scaled
#: by Anderson & Björck's ``1 - g(c) / g(end replaced)`` (by 1/2 where that is not positive),
#: where the Illinois variant (Dowell & Jarratt, BIT 11, 168 (1971)) halved it: on the heavy
#: top's crossings (g = g1, RK4 at h = 0.002) 4.0 evaluations instead of 5.0, the times within
#: 0.25 of the tolerance of Illinois's, and no more on the free body's flips.
_BRACKETED_ROOT = '''\
@njit(error_model="numpy")
def _root(k, {extension}, t0, h, ga, gb, p, {state}):
    """The time of event k's sign change in [t0, t0 + h], by Anderson-Björck on {along}."""
    a = t0
    b = t0 + h
    side = 0
    best, gbest = (a, ga) if abs(ga) < abs(gb) else (b, gb)
    for _ in range(200):
        tol = 4.0 * 2.220446049250313e-16 * max(abs(a), abs(b))
        if b - a <= tol:
            break
        c = b - gb * (b - a) / (gb - ga)
        if not (a <= c <= b):
            c = 0.5 * (a + b)
        c = min(max(c, a + 0.5 * tol), b - 0.5 * tol)
        {evaluate}
        gc = _g(k, {state}, c, p)
        if abs(gc) < abs(gbest):
            best, gbest = c, gc
        if gc == 0.0:
            break
        if (gc < 0.0) == (gb < 0.0):
            if side == -1:
                scale = 1.0 - gc / gb
                ga *= scale if scale > 0.0 else 0.5
            b, gb = c, gc
            side = -1
        else:
            if side == 1:
                scale = 1.0 - gc / ga
                gb *= scale if scale > 0.0 else 0.5
            a, ga = c, gc
            side = 1
    return best'''


def bracketed_root(extension: str, state: str, evaluate: str, along: str) -> str:
    """The source of a loop's ``_root`` (:data:`_BRACKETED_ROOT`) for its continuous extension.

    Parameters
    ----------
    extension : str
        The argument the state at a time is made from.
    state : str
        The array that state is written into (and ``_g`` reads).
    evaluate : str
        The line that writes it, at time ``c``.
    along : str
        What the extension is, for the docstring.

    Returns
    -------
    str
    """
    return _BRACKETED_ROOT.format(extension=extension, state=state, evaluate=evaluate,
                                 along=along)


@njit(error_model="numpy")
def taken_in_order(order, hits, t_hit, count, times, keep, stops) -> int:
    """The crossings of one step, ``order[:hits]`` (event numbers) at the located times
    ``t_hit``, taken in the order of their times (then of the events): each counted in
    ``count[k]``, its time kept in ``times[k]`` while its count is at most ``keep[k]``. Returns
    the event whose ``count``-th crossing stops the member (``stops[k]``; later crossings of the
    step are not taken), or -1. The compiled loops, fixed-step and adaptive, finish a step with
    it."""
    for q in range(1, hits):
        k = order[q]
        w = q
        while w > 0 and t_hit[order[w - 1]] > t_hit[k]:
            order[w] = order[w - 1]
            w -= 1
        order[w] = k
    for q in range(hits):
        k = order[q]
        count[k] += 1
        if count[k] <= keep[k]:
            times[k, count[k] - 1] = t_hit[k]
        if stops[k] and count[k] == keep[k]:
            return k
    return -1


def located(function) -> tuple[str, str]:
    """``(module, name)`` where ``function`` is bound at the top level, so that a compiled
    loop can import it; a one-line ValueError where it is not."""
    python = getattr(function, "py_func", function)
    home = sys.modules.get(python.__module__)
    if python.__qualname__ != python.__name__ or getattr(home, python.__name__, None) is not \
            function:
        raise ValueError(f"event g {python.__qualname__} must be defined at the top level of "
                         f"its module ({python.__module__}) under its own name, so the "
                         "compiled loop can import it")
    return python.__module__, python.__name__


def scalar_form(function, width: int):
    """``g(x, t, p)`` rewritten as ``g(x_0, ..., x_{width-1}, t, p)``, or None where it cannot be.

    A g that reads its state only as ``x[i]`` with constant ``i`` (``return x[1]``, ``x[0] -
    0.4``) is the same arithmetic on the numbers themselves: the fixed-step loop then evaluates
    it on the member's row of the block with no array view per member (on the bench's free
    body, RK4 on one thread, one event costs +16 to +18 % over the run without it so, about
    +60 % with a view per member: ``stability bench``'s row "rk4, one event"). Any other
    use of ``x`` (a loop over it, ``len(x)``, passing it on), a closure, or a source that cannot
    be read, gives None, and the loop keeps the view. The new function has ``g``'s module
    globals, so it sees what ``g`` sees.
    """
    import ast
    import inspect
    import textwrap

    python = getattr(function, "py_func", function)
    try:
        tree = ast.parse(textwrap.dedent(inspect.getsource(python)))
    except (OSError, TypeError, SyntaxError):
        return None
    node = tree.body[0] if tree.body else None
    if not isinstance(node, ast.FunctionDef) or python.__code__.co_freevars:
        return None
    args = node.args
    if args.posonlyargs or args.vararg or args.kwonlyargs or args.kwarg or args.defaults or \
            len(args.args) != 3:
        return None
    state = args.args[0].arg
    names = [f"_x{i}" for i in range(width)]
    reads = {id(n.value) for n in ast.walk(node) if isinstance(n, ast.Subscript)
             and isinstance(n.value, ast.Name) and n.value.id == state
             and isinstance(n.slice, ast.Constant) and type(n.slice.value) is int
             and 0 <= n.slice.value < width and isinstance(n.ctx, ast.Load)}
    uses = [n for n in ast.walk(node) if isinstance(n, ast.Name) and n.id == state]
    if any(id(n) not in reads for n in uses) or any(
            isinstance(n, ast.Name) and n.id in names for n in ast.walk(node)):
        return None

    class Scalars(ast.NodeTransformer):
        def visit_Subscript(self, n):
            if id(n.value) in reads:
                return ast.copy_location(ast.Name(names[n.slice.value], ast.Load()), n)
            return self.generic_visit(n)

    node = Scalars().visit(node)
    node.decorator_list = []
    node.args.args = [ast.arg(name) for name in names] + node.args.args[1:]
    module = ast.fix_missing_locations(ast.Module([node], []))
    code = compile(module, python.__code__.co_filename, "exec")
    inner = next(c for c in code.co_consts if isinstance(c, types.CodeType))
    return types.FunctionType(inner, python.__globals__, python.__name__)


def checked_events(events, x, p) -> tuple:
    """``events`` as a tuple of :class:`Event`, each ``g`` compiled and tried on the state
    ``x`` (n,) at ``t = 0`` with the row ``p``: one line where it does not compile, raises, or
    returns anything but one real number.

    Parameters
    ----------
    events : Event or sequence of Event
    x, p : ndarray
        A member's start and its parameter row (the run's first).

    Returns
    -------
    tuple of Event
    """
    if isinstance(events, Event):
        events = (events,)
    try:
        events = tuple(events or ())
    except TypeError:
        raise TypeError(f"events must be Events, got {type(events).__name__}") from None
    names = []
    for event in events:
        if not isinstance(event, Event):
            raise TypeError(f"events must be stability.engine.events.Event, got "
                            f"{type(event).__name__}")
        if event.name in names:
            raise ValueError(f"two events are named {event.name!r}; give them names of their own")
        names.append(event.name)
        located(event.g)
        _tried(event, np.ascontiguousarray(x, dtype=float), np.ascontiguousarray(p, dtype=float))
    return events


def _tried(event: Event, x, p) -> None:
    compiled = event.g if isinstance(event.g, Dispatcher) else njit(event.python)
    try:
        with np.errstate(all="ignore"), warnings.catch_warnings():
            warnings.simplefilter("ignore")
            out = compiled(x.copy(), 0.0, p)
    except NumbaError as exc:
        lines = [line.strip() for line in str(exc).splitlines() if line.strip()]
        reason = next((line for line in lines if not line.startswith(
            ("Failed in", "During:", "File ", "^"))), type(exc).__name__)
        raise TypeError(f"event {event.name!r}: Numba cannot compile g(x, t, p): "
                        f"{reason:.160}") from None
    except Exception as exc:
        raise ValueError(f"event {event.name!r}: g(x, t, p) raised {type(exc).__name__}: "
                         f"{exc} at the first member's start") from None
    if isinstance(out, (bool, np.bool_)) or not isinstance(out, (numbers.Real, np.floating,
                                                                  np.integer)):
        raise TypeError(f"event {event.name!r}: g(x, t, p) must return one real number, got "
                        f"{type(out).__name__}")


__all__ = ["ACTIONS", "DIRECTIONS", "Event", "bracketed_root", "checked_events", "located",
           "taken_in_order"]
