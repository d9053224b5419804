"""What a compiled loop is made of: the digest naming it in the cache covers the user's helper
modules and the plain globals the user's functions read, and nothing else the process holds;
a stored run of a user's scene resumed after a change of either is refused, on a cold cache."""

import importlib
import json
import os
import subprocess
import sys
import textwrap
from pathlib import Path

import numpy as np

from stability.engine.sources import digest, globals_fingerprint, source_files

ROOT = Path(__file__).resolve().parents[2]

#: The user's scene module: a damped spin whose damping law sits in a helper module.
SCENE = '''
"""A spin damped by a law of the user's own (law.py)."""
import law
from law import pull
from stability import define_scene


def rhs(w1, w2, w3, p):
    """w' = -c g w"""
    return pull(w1, p) * law.GAIN, pull(w2, p) * law.GAIN, pull(w3, p) * law.GAIN


DAMPED = define_scene("user_damped_spin", ["w1", "w2", "w3"], ["rad s-1"] * 3, rhs, ["c"])
'''

#: The helper: its constant is set from the environment at start-up, as a configuration is.
LAW = '''
import os
from numba import njit

GAIN = float(os.environ.get("USER_GAIN", "1.0"))


@njit(inline="always")
def pull(w, p):
    return -{scale} * p[0] * w
'''


def write_user_code(folder: Path, scale="1.0"):
    folder.mkdir(exist_ok=True)
    (folder / "damped.py").write_text(SCENE)
    (folder / "law.py").write_text(LAW.format(scale=scale))
    return folder


def import_fresh(folder: Path, monkeypatch, gain="1.0"):
    """The scene module and its helper imported anew from ``folder`` (functions only: no
    define_scene, which would compile), and their digest as the scene's kernels take it."""
    monkeypatch.setenv("USER_GAIN", gain)
    monkeypatch.syspath_prepend(str(folder))
    for name in ("law", "damped_functions"):
        sys.modules.pop(name, None)
    (folder / "damped_functions.py").write_text(SCENE.split("\n\nDAMPED")[0])
    importlib.invalidate_caches()
    module = importlib.import_module("damped_functions")
    return digest("", ("damped_functions",), (module.rhs,))


def test_an_edited_helper_module_or_a_global_read_changes_the_digest(tmp_path, monkeypatch):
    """The digest of the user's functions changes with the text of a helper module they import
    (law.py, not named anywhere but in the scene's module) and with the value of a plain
    global they read there (set from the environment); it stays the same when nothing
    changed. Both gave the old digest, hence the old machine code from the cache."""
    folder = write_user_code(tmp_path / "mine")
    first = import_fresh(folder, monkeypatch)
    assert import_fresh(folder, monkeypatch) == first
    write_user_code(folder, scale="2.0")
    assert import_fresh(folder, monkeypatch) != first
    write_user_code(folder)
    assert import_fresh(folder, monkeypatch) == first
    assert import_fresh(folder, monkeypatch, gain="3.0") != first


def test_the_files_followed_are_the_users_and_the_packages_not_installed_ones(tmp_path,
                                                                              monkeypatch):
    import_fresh(write_user_code(tmp_path / "mine"), monkeypatch)
    files = source_files("damped_functions")
    names = {Path(f).name for f in files}
    assert {"damped_functions.py", "law.py"} <= names
    assert all("site-packages" not in f and not f.startswith(sys.base_prefix) for f in files)
    assert any(Path(f).is_relative_to(ROOT / "stability") for f in files)  # define_scene's


def test_plain_globals_are_read_through_modules_and_called_functions(tmp_path, monkeypatch):
    """A number, an array and a tuple read as ``module.NAME`` or as a name, by the function or
    one it calls; a module, a function or a class is no plain value."""
    folder = tmp_path / "g"
    folder.mkdir()
    (folder / "consts.py").write_text("import numpy as np\nTABLE = np.arange(3.0)\nPAIR = (1, 2.5)\n")
    (folder / "user_globals.py").write_text(textwrap.dedent("""
        import consts
        SCALE = 2.0

        def inner(x):
            return x * consts.TABLE[0] + consts.PAIR[1]

        def outer(x):
            return inner(x) * SCALE
    """))
    monkeypatch.syspath_prepend(str(folder))
    import user_globals
    before = globals_fingerprint([user_globals.outer])
    user_globals.consts.TABLE[0] = 5.0
    assert globals_fingerprint([user_globals.outer]) != before
    user_globals.consts.TABLE[0] = 0.0
    assert globals_fingerprint([user_globals.outer]) == before
    monkeypatch.setattr(user_globals, "SCALE", 2.5)
    assert globals_fingerprint([user_globals.outer]) != before
    monkeypatch.setattr(user_globals.consts, "PAIR", (1, 2.5))
    monkeypatch.setattr(user_globals, "SCALE", 2.0)
    assert globals_fingerprint([user_globals.outer]) == before


#: A new process: imports the user's scene from argv[1] and runs it in a store, in chunks,
#: resumed; prints the members' final w1, or the one line of a refusal.
RUN = '''
import json, sys
import numpy as np
sys.path.insert(0, sys.argv[1])
from damped import DAMPED
import stability
x0 = np.tile([1.0, 0.5, 0.25], (8, 1))
try:
    ds = stability.run_scene(DAMPED, "rk4", x0, {"c": 0.5}, h=0.01, n_steps=100,
                             options=stability.RunOptions(store=sys.argv[2], chunk_members=2,
                                                          resume=True, progress=False))
except ValueError as exc:
    print(json.dumps({"refused": str(exc)}))
else:
    print(json.dumps({"w1": np.asarray(ds["w1_final"]).ravel().tolist()}))
'''


def run_user_code(folder, store, cache, gain="1.0"):
    env = {**os.environ, "STABILITY_CACHE_DIR": str(cache), "USER_GAIN": gain,
           "PYTHONPATH": str(ROOT)}
    done = subprocess.run([sys.executable, "-c", RUN, str(folder), str(store)], env=env,
                          capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, done.stderr
    return json.loads(done.stdout.strip().splitlines()[-1])


def test_a_stored_run_resumed_after_the_model_changed_is_refused(tmp_path):
    """A stored run of the user's scene, stopped with a chunk to go, then resumed in a new
    process on a cold cache after the helper module's constant changed (another environment):
    refused in one line saying the settings changed, where before the last chunk ran the new
    model and the run was accepted, half the members each."""
    folder = write_user_code(tmp_path / "mine")
    store = tmp_path / "store"
    whole = run_user_code(folder, store, tmp_path / "cache")
    assert np.allclose(whole["w1"], np.exp(-0.5))  # w1 = e^{-c t}, t = 1 s
    for name in ("chunk-000003.nc", "chunk-000003.nc.sha256"):  # as a stopped run leaves it
        (store / name).unlink()
    again = run_user_code(folder, store, tmp_path / "cold", gain="2.0")
    assert "refused" in again, again
    assert "the settings changed" in again["refused"] and "\n" not in again["refused"]
