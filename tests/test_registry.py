"""Every registered scene's methods, tested alike from what the scene and the method declare.

Each (scene, method) of the registry runs the scene's own ``example`` to ``T_END`` with steps
``T_END / n``, n = 1, 2, 4, ... (:func:`convergence`), and

- where the scene has an exact solution, the error at ``T_END`` falls at the method's declared
  order (the slope of log error over log h on the three finest steps above round-off);
- each invariant is kept as the scene's ``kept_by`` says: to round-off by the methods that keep
  it, at no less than their order by the others.

A new scene or method is picked up from ``SCENES`` and its ``methods``. Bitwise reproducibility
over groups, chunks and thread counts is ``tests/engine/test_driver.py``'s; over member chunks,
resumes and dask, ``tests/ensemble/test_chunks.py``'s.
"""

import dataclasses
import functools
import math

import numpy as np
import pytest

from stability.util.conventions import STATUS_OK
from stability.engine import propagate_groups
from stability.integrators.spec import MethodSpec
from stability.registry import SCENES

#: Horizon (s, in the examples' scaled units) and the step counts tried, h = T_END / n.
T_END = 4.0
STEPS = tuple(2**k for k in range(13))  # 1 ... 4096
#: The runs go on at least this far, for the invariants kept to round-off.
MIN_STEPS = 16
#: Starts per parameter set.
MEMBERS = 6
#: Relative errors and drifts below this are round-off: the slopes are fitted above it.
FLOOR = 1e-13
#: The finest steps above the floor must have errors below this (the asymptotic range).
CEILING = 1e-2
#: Measured order within this of the declared one.
ORDER_TOLERANCE = 0.3
#: Kept to round-off: a drift of at most this per step, relative to the invariant's size...
ROUND_OFF_PER_STEP = 1e-15
#: ... plus this (the rolling body's energy is a sum of terms larger than itself).
ROUND_OFF = 1e-13

CASES = [(scene, name) for scene in SCENES.values() for name in scene.methods]
EXACT_CASES = [(scene, name) for scene, name in CASES if scene.exact is not None]


def ids(cases):
    return [f"{scene.name}-{name}" for scene, name in cases]


@dataclasses.dataclass
class Convergence:
    """What the runs of one (scene, method) at the steps ``hs`` measured."""

    hs: list
    #: Largest error at T_END against the exact solution (inf where a member failed), per step;
    #: empty without an exact solution.
    errors: list
    #: Per invariant, its largest relative drift over the run, per step.
    drifts: dict
    #: Steps per run.
    steps: list


def _error(x, exact):
    """Largest error of states ``x`` against ``exact``, relative to each component's size
    (absolute below 1)."""
    return float(np.max(np.abs(x - exact) / (1.0 + np.abs(exact))))


@functools.cache
def convergence(scene_name: str, method: str) -> Convergence:
    """The example run to T_END with steps T_END / n, n = 1, 2, 4, ..., until what converges
    at the method's order is at round-off (or n = 4096), and at least to n = MIN_STEPS."""
    scene = SCENES[scene_name]
    spec = scene.method(method)
    sets = scene.example(MEMBERS)[1]
    x0 = np.concatenate([scene.example(MEMBERS, seed=g)[0] for g in range(len(sets))])
    groups = [slice(g * MEMBERS, (g + 1) * MEMBERS) for g in range(len(sets))]
    exact = {}
    if scene.exact is not None:
        for g, values in enumerate(sets):
            x = scene.exact(x0[groups[g]], values, T_END)
            if x is not None:
                exact[g] = x
        assert exact, f"{scene.name}: the example has no parameter set the exact solution covers"
    converging = [name for name in scene.invariants if scene.keeps(name, spec) is False]
    out = Convergence([], [], {name: [] for name in scene.invariants}, [])
    for n in STEPS:
        h = T_END / n
        params = np.array([spec.params(values, h) for values in sets])
        run = propagate_groups(scene, spec, x0, params, [MEMBERS] * len(sets), h, n,
                               save_every=max(n // 8, 1), progress=False)
        ok = run.status == STATUS_OK
        out.hs.append(h)
        out.steps.append(n)
        if exact:
            out.errors.append(max(_error(run.x_final[groups[g]], x) if ok[groups[g]].all()
                                  else math.inf for g, x in exact.items()))
        for name, invariant in scene.invariants.items():
            drift = 0.0  # of the members that did not fail (some blow up at the coarsest h)
            for g, values in enumerate(sets):
                rows = np.flatnonzero(ok[groups[g]]) + groups[g].start
                start = invariant(x0[rows], values)
                scale = np.abs(start).max(initial=0.0) or 1.0
                for k in range(run.saved.shape[1]):
                    with np.errstate(all="ignore"):
                        change = np.abs(invariant(run.saved[rows, k], values) - start) / scale
                    drift = max(drift, float(change.max(initial=0.0)))
            out.drifts[name].append(drift if np.isfinite(drift) else math.inf)
        settled = all(values[-1] < FLOOR for values in
                      [out.errors] * bool(exact) + [out.drifts[name] for name in converging])
        if n >= MIN_STEPS and (settled or not spec.order > 0 or math.isinf(spec.order)):
            break
    return out


def finest_above_floor(hs, values, count=3):
    """The ``count`` finest (h, value) pairs with value above FLOOR (finite)."""
    pairs = [(h, v) for h, v in zip(hs, values) if FLOOR <= v < math.inf]
    return pairs[-count:]


def slope(pairs):
    h, v = np.log(np.array(pairs)).T
    return float(np.polyfit(h, v, 1)[0])


@pytest.mark.parametrize("scene,name", EXACT_CASES, ids=ids(EXACT_CASES))
def test_error_falls_at_the_declared_order_against_the_exact_solution(scene, name):
    spec = scene.method(name)
    c = convergence(scene.name, name)
    table = ", ".join(f"h={h:.3g}: {e:.2e}" for h, e in zip(c.hs, c.errors))
    if spec.is_exact:
        assert max(c.errors) < 1e-12, table
        return
    if not spec.order > 0:
        pytest.skip(f"{name} declares no convergence (order {spec.order})")
    pairs = finest_above_floor(c.hs, c.errors)
    assert len(pairs) == 3, f"too few steps with errors above {FLOOR}: {table}"
    assert max(e for _, e in pairs) < CEILING, f"not asymptotic by h = {c.hs[-1]}: {table}"
    measured = slope(pairs)
    assert abs(measured - spec.order) <= ORDER_TOLERANCE, (
        f"measured order {measured:.2f}, declared {spec.order}: {table}")


@pytest.mark.parametrize("scene,name", CASES, ids=ids(CASES))
def test_invariants_are_kept_as_declared(scene, name):
    """To round-off by the methods that keep an invariant; by the others at no less than
    their order, where their drift is above round-off."""
    spec = scene.method(name)
    c = convergence(scene.name, name)
    for invariant, drifts in c.drifts.items():
        kept = scene.keeps(invariant, spec)
        table = ", ".join(f"h={h:.3g}: {d:.2e}" for h, d in zip(c.hs, drifts))
        if kept:
            bounds = [ROUND_OFF + ROUND_OFF_PER_STEP * n for n in c.steps]
            assert all(d <= b for d, b in zip(drifts, bounds)), f"{invariant}: {table}"
        elif kept is False and spec.order > 0 and not spec.is_exact:
            pairs = finest_above_floor(c.hs, drifts)
            if len(pairs) >= 2:  # else at round-off from the coarsest steps on
                measured = slope(pairs)
                assert measured >= spec.order - ORDER_TOLERANCE, (
                    f"{invariant} drifts at order {measured:.2f}, below the method's "
                    f"{spec.order}: {table}")


@pytest.mark.parametrize("scene", list(SCENES.values()), ids=list(SCENES))
def test_declarations_name_what_exists(scene):
    """``kept_by`` names the scene's invariants and MethodSpec flags or its methods; the exact
    solution returns the starts at t = 0, in the scene's width."""
    flags = {f.name for f in dataclasses.fields(MethodSpec) if f.type in ("bool", bool)}
    for invariant, kept in scene.kept_by.items():
        assert invariant in scene.invariants, invariant
        if isinstance(kept, str):
            assert kept in flags, kept
        elif kept is not None and not isinstance(kept, bool):
            assert set(kept) <= set(scene.methods), kept
    if scene.exact is not None:
        x0, sets = scene.example(3)
        for values in sets:
            x = scene.exact(x0, values, 0.0)
            if x is not None:
                assert x.shape == x0.shape
                np.testing.assert_allclose(x, x0, rtol=1e-15, atol=1e-15)
