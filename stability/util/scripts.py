"""Whether starting worker processes now would run the user's script again.

A dask ``LocalCluster`` starts its workers as new Python processes (multiprocessing's *spawn*),
and each imports the script being run, as ``__mp_main__``, to find what the tasks refer to: the
script's top-level code runs again in every worker, which starts the run again (and another
cluster) there. Python's advice is the guard ``if __name__ == "__main__":`` around the code that
runs things; :func:`unguarded_script` says where it is missing.
"""

from __future__ import annotations

import ast
import sys


#: What to do, said by each refusal.
_GUARD = 'put the code that runs it under `if __name__ == "__main__":`'


def unguarded_script() -> str | None:
    """Why a local cluster started now would run the user's script again, or None.

    Two cases: this process is itself a worker importing the script (run as ``__mp_main__``);
    or the call comes from the top level of the script being run, outside an
    ``if __name__ == "__main__":`` block (read from the script's source), directly or through
    functions it calls. A notebook, ``python -c`` or ``python -m package`` (the command line
    ``stability``) is never in the way.
    """
    modules = []  # the frames running a module's top level, innermost first
    frame = sys._getframe(1)
    while frame is not None:
        if frame.f_code.co_name == "<module>":
            modules.append(frame)
        frame = frame.f_back
    for frame in modules:  # the script run again by multiprocessing, as __mp_main__
        if frame.f_globals.get("__name__") == "__mp_main__":
            return (f"this process is a worker importing the script {frame.f_code.co_filename} "
                    f"again, and reached its run: {_GUARD}")
    main = sys.modules.get("__main__")
    script = getattr(main, "__file__", None)
    if not isinstance(script, str) or not script.endswith(".py"):
        return None
    spec = getattr(main, "__spec__", None)
    if spec is not None and (spec.name == "__main__" or spec.name.endswith(".__main__")):
        return None  # python -m package: multiprocessing never runs a package's __main__ again
    top = next((f for f in reversed(modules) if f.f_globals is main.__dict__), None)
    if top is None:  # the statement the script runs now
        return None
    try:
        with open(script, "rb") as f:
            tree = ast.parse(f.read(), script)
    except (OSError, SyntaxError, ValueError):
        return None
    if _guarded(tree, top.f_lineno):
        return None
    return (f"the worker processes of a local dask cluster import the script {script} again, "
            f"so its top-level code (line {top.f_lineno}) would start this run again in each: "
            f"{_GUARD}")


def _guarded(tree: ast.Module, line: int) -> bool:
    """Whether ``line`` of the module lies inside an ``if __name__ == "__main__":`` block."""
    for node in ast.walk(tree):
        if isinstance(node, ast.If) and _is_main_test(node.test) and node.body and (
                node.body[0].lineno <= line <= max(getattr(n, "end_lineno", n.lineno)
                                                   for n in node.body)):
            return True
    return False


def _is_main_test(test) -> bool:
    if not (isinstance(test, ast.Compare) and len(test.ops) == 1
            and isinstance(test.ops[0], ast.Eq)):
        return False
    sides = [test.left, test.comparators[0]]
    names = [s for s in sides if isinstance(s, ast.Name) and s.id == "__name__"]
    mains = [s for s in sides if isinstance(s, ast.Constant) and s.value == "__main__"]
    return len(names) == 1 and len(mains) == 1


__all__ = ["unguarded_script"]
