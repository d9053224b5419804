"""Scripts that a local dask cluster's workers would run again: found from the script's source
before any worker starts, and in a worker that imports the script."""

import os
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]

PROBE = "from stability.util.scripts import unguarded_script\n"


def run_script(folder: Path, text: str, name="script.py") -> list[str]:
    path = folder / name
    path.write_text(textwrap.dedent(text))
    done = subprocess.run([sys.executable, str(path)], capture_output=True, text=True,
                          cwd=folder, env={**os.environ, "PYTHONPATH": str(ROOT)}, timeout=120)
    return done.stdout.splitlines() + [f"exit {done.returncode}"] + done.stderr.splitlines()


@pytest.mark.parametrize("text, line", [
    (PROBE + "print(unguarded_script())\n", 2),
    (PROBE + "def main():\n    print(unguarded_script())\n\nmain()\n", 5),
    (PROBE + "if __name__ != '__main__':\n    pass\nprint(unguarded_script())\n", 4),
], ids=["top-level", "through-a-function", "another-if"])
def test_a_run_started_from_the_top_level_of_a_script_is_named_with_its_line(tmp_path, text,
                                                                             line):
    out = run_script(tmp_path, text)
    assert f"import the script {tmp_path / 'script.py'} again" in out[0]
    assert f"(line {line})" in out[0] and 'if __name__ == "__main__":' in out[0]


@pytest.mark.parametrize("text", [
    PROBE + "if __name__ == '__main__':\n    print(unguarded_script())\n",
    PROBE + "def main():\n    print(unguarded_script())\n\nif '__main__' == __name__:\n    main()\n",
], ids=["guarded", "guarded-call"])
def test_a_guarded_script_is_not_in_the_way(tmp_path, text):
    assert run_script(tmp_path, text)[0] == "None"


def test_a_packages_main_run_with_python_m_is_not_in_the_way(tmp_path):
    """``python -m package`` (as ``python -m stability run ... --scheduler dask``): a package's
    ``__main__`` is never run again by the workers, guard or not."""
    package = tmp_path / "tool"
    package.mkdir()
    (package / "__init__.py").write_text("")
    (package / "__main__.py").write_text(PROBE + "print(unguarded_script())\n")
    env = {**os.environ, "PYTHONPATH": os.pathsep.join([str(ROOT), str(tmp_path)])}
    done = subprocess.run([sys.executable, "-m", "tool"], capture_output=True, text=True,
                          cwd=tmp_path, env=env, timeout=120)
    assert done.stdout.strip() == "None", done.stderr


def test_a_worker_process_importing_the_script_again_knows_it(tmp_path):
    """A spawned process (as a dask worker is) imports the script as ``__mp_main__`` and runs
    its top level again: there, the check says this is a worker reaching the run."""
    out = run_script(tmp_path, PROBE + textwrap.dedent("""
        import multiprocessing
        print("in", __name__, unguarded_script())

        def nothing():
            pass

        if __name__ == "__main__":
            child = multiprocessing.get_context("spawn").Process(target=nothing)
            child.start()
            child.join()
        """))
    worker = [line for line in out if line.startswith("in __mp_main__")]
    assert len(worker) == 1 and "this process is a worker importing the script" in worker[0]


def test_an_unguarded_script_on_a_local_cluster_is_refused_before_any_worker_starts(tmp_path):
    """The gallery's dask example as a script without the guard: one line saying to guard it,
    and no cluster started. The workers ran the script again and the user saw 'Nanny failed to
    start worker process' and 'store is in use by another run'."""
    pytest.importorskip("distributed")
    out = run_script(tmp_path, """
        import stability
        body = stability.RigidBody.preset("tennis_racket")
        ds = stability.run_ensemble(body, axis=2, spin=10.0, members=40, t_end=1.0,
                                    options=stability.RunOptions(
                                        chunk_members=20, store="store", scheduler="dask",
                                        progress=False))
        """)
    assert "exit 1" in out
    assert out[-1].startswith("ValueError: the worker processes of a local dask cluster import "
                              f"the script {tmp_path / 'script.py'} again"), out[-3:]
    assert not any("Nanny" in line or "distributed" in line for line in out), out
