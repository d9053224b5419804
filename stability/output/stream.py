"""Ensembles streamed to disk chunk by chunk: resumable, and runnable on a dask cluster.

The machinery is generic over a *chunk job*: a picklable callable ``job(lo, hi, progress,
threads) -> xarray.Dataset`` that runs members ``lo ... hi - 1`` of a run with the Numba threads
of the process it is in. :func:`stream_chunks` runs the chunks of a
:class:`~stability.output.store.ChunkStore` that are not done, here or as dask tasks, with progress,
``progress.json`` and the Ctrl-C message. The jobs are defined above this module, which imports
none of them: every scene's grouped runs, raw or measured, the free body's ensembles among them
(:class:`~stability.ensemble.chunks.ChunkJob`), and the stability map's batches.

``run_ensemble(..., options=RunOptions(store=DIR))`` streams this way
(:func:`stability.free_body.streamed.run_streamed`): the members are cut into chunks of
``chunk_members``; each chunk is run exactly as
:func:`stability.run_ensemble` runs its members (its random starts are drawn for that chunk
alone, from the same seed streams) and written as soon as it is finished into a
:class:`~stability.output.store.ChunkStore`. Memory is one chunk's, so
a summaries-only run of 1e8 members needs well under 2 GB. A run stopped at any point is
resumed with ``resume=True`` (``stability run --resume``): the chunks that are not on disk are
run, and the Dataset is bitwise the one of an uninterrupted run (members are independent, and
a member's start does not depend on its chunk).

With ``scheduler`` each chunk is one task of a ``dask.distributed`` cluster: ``"dask"`` starts
a :class:`~distributed.LocalCluster` on this machine (one single-threaded worker process per
core), any other string is a scheduler address (``tcp://host:8786``), and a
:class:`~distributed.Client` is used as it is. A worker runs its chunk with as many Numba threads as it has threads,
loads the compiled member loop from the disk cache (:mod:`stability.engine.cache`; share that
folder, ``STABILITY_CACHE_DIR``, between the workers) and writes the chunk file itself, so the
store must be on a file system all workers see. Tasks of a worker that dies are run again on
another (dask's own scheduling), and a chunk is done only when its file and checksum are.
"""

from __future__ import annotations

import logging
import pickle
import time
from pathlib import Path
from typing import NamedTuple

from .store import ChunkStore, chunk_name, write_chunk
from ..util.threads import checked_threads, numba_threads
from ..util.scripts import unguarded_script

log = logging.getLogger(__name__)


class RunInterrupted(KeyboardInterrupt):
    """Ctrl-C or SIGTERM stopped a stored run; the finished chunks are kept.

    ``str(exc)`` says what was kept and how to continue.
    """


class Streamed(NamedTuple):
    """What :func:`stream_chunks` ran: the chunks' indices, and the seconds from the start of
    the first to the end of the last (0.0 for none), however many ran side by side."""

    todo: list
    elapsed: float


def stream_chunks(job, chunks: ChunkStore, *, scheduler=None, threads=None, progress=None,
                  compress=True, payload: bytes | None = None, kept=None) -> Streamed:
    """Run the chunks of ``chunks`` that are not done with ``job``.

    Parameters
    ----------
    job : callable
        ``job(lo, hi, progress, threads) -> xarray.Dataset``, members ``lo ... hi - 1``;
        picklable when ``scheduler`` is given (each chunk is then a dask task).
    chunks : ChunkStore
        The store; each finished chunk is written into it at once.
    scheduler, threads, progress, compress
        As in :func:`stability.free_body.streamed.run_streamed`.
    payload : bytes, optional
        ``job`` already pickled by :func:`sendable` (a caller that checked it so before making
        the store), so that it is not pickled again for the scheduler.
    kept : callable, optional
        ``kept(lo, ds)``, given each chunk run in this process once it is written (its first
        member and its Dataset): a caller that joins measured chunks as they come, without
        reading their files back.

    Returns
    -------
    Streamed
        The chunks run and the seconds they took (a cluster's start excluded).

    Raises
    ------
    RunInterrupted
        Ctrl-C or SIGTERM; the finished chunks are kept.
    """
    todo = chunks.missing()
    elapsed = 0.0
    if todo:
        if scheduler is None:
            elapsed = _run_here(job, chunks, todo, threads, progress, compress, kept)
        else:
            elapsed = _run_on_dask(job, chunks, todo, scheduler, progress, compress, payload)
    return Streamed(todo, elapsed)


def _run_here(job, chunks, todo, threads, progress, compress, kept=None) -> float:
    """The missing chunks in this process, on all its Numba threads; the seconds taken. Each
    chunk's Dataset goes to ``kept(lo, ds)`` too, when given, once it is written."""
    tracker = _Tracker(chunks, todo, progress)
    try:
        with numba_threads(checked_threads(threads)):
            for k in todo:
                lo, hi = chunks.bounds(k)
                ds = job(lo, hi, tracker.inner_progress, threads)
                chunks.write(k, ds, compress)
                if kept is not None:
                    kept(lo, ds)
                tracker.finished(k, hi - lo)
    except KeyboardInterrupt:  # Ctrl-C between chunks, or while compiling or writing
        tracker.stopped()
    finally:
        tracker.close()
    return tracker.elapsed


def run_chunk(job, directory, k: int, lo: int, hi: int, compress: bool,
              fingerprint: str) -> int:
    """One chunk on a dask worker: run it with the worker's threads, write it; returns ``k``.

    Parameters
    ----------
    job : callable
        The run's chunk job (:func:`stream_chunks`).
    directory : str or path-like
        The store's folder, on a file system the worker shares.
    k : int
        Index of the chunk.
    lo, hi : int
        The chunk's members are ``lo ... hi - 1`` of the whole run.
    compress : bool
        zlib-compress the chunk file.
    fingerprint : str
        The store's fingerprint, recorded beside the chunk's checksum.

    Returns
    -------
    int
        ``k``.
    """
    import numba
    from distributed import get_worker

    try:
        nthreads = get_worker().state.nthreads
    except (ValueError, AttributeError):  # not on a worker (a test calling it directly)
        nthreads = numba.config.NUMBA_NUM_THREADS
    with numba_threads(max(1, min(nthreads, numba.config.NUMBA_NUM_THREADS))):
        ds = job(lo, hi, False, None)
    write_chunk(ds, Path(directory) / chunk_name(k), compress, fingerprint)
    return k


def _run_on_dask(job, chunks, todo, scheduler, progress, compress, payload=None) -> float:
    """The missing chunks as tasks of a dask.distributed cluster; the seconds from their
    submission to the last one's end."""
    try:
        from distributed import Client, LocalCluster, as_completed
    except ImportError:
        raise ValueError("scheduler needs dask.distributed: pip install 'stability[distributed]'"
                         ) from None
    payload = payload or sendable(job)  # before a cluster is started
    cluster = None
    own = True
    if hasattr(scheduler, "submit"):  # a distributed.Client the caller made
        client, own = scheduler, False
    elif scheduler == "dask":
        if (problem := unguarded_script()) is not None:
            raise ValueError(problem)
        cluster = LocalCluster(processes=True, threads_per_worker=1, dashboard_address=None)
        client = Client(cluster)
    else:
        if not isinstance(scheduler, str) or "://" not in scheduler:
            raise ValueError(f"scheduler must be 'dask' (a local cluster) or a scheduler "
                             f"address such as 'tcp://host:8786', got {scheduler!r}")
        client = scheduler_client(scheduler)
    try:
        _check_loadable(client, payload)
    except BaseException:
        if own:
            client.close()
        if cluster is not None:
            cluster.close()
        raise
    tracker = _Tracker(chunks, todo, progress)
    try:
        futures = []
        for k in todo:
            lo, hi = chunks.bounds(k)
            futures.append(client.submit(
                run_chunk, job, str(chunks.dir.resolve()), k, lo, hi, compress,
                chunks.fingerprint, key=f"stability-chunk-{k}-{chunks.fingerprint[:12]}",
                retries=2, pure=False))
        for future in as_completed(futures):
            k = future.result()
            lo, hi = chunks.bounds(k)
            if not chunks.verify(k):
                raise OSError(f"chunk {k} written by a worker is not readable here "
                              f"({chunks.path(k)}); the store must be on a file system every "
                              "worker and this process share")
            tracker.finished(k, hi - lo)
    except KeyboardInterrupt:
        tracker.stopped()
    finally:
        tracker.close()
        if own:
            client.close()
        if cluster is not None:
            cluster.close()
    return tracker.elapsed


def sendable(job) -> bytes:
    """``job`` pickled, as dask sends it to the scheduler and the workers.

    Parameters
    ----------
    job : object
        What each task runs (a chunk job: the run and its measurement).

    Returns
    -------
    bytes
        Its pickle.

    Raises
    ------
    ValueError
        In one line, where it cannot be pickled (a scene defined in ``__main__``, a function
        that is not at the top level of its module).
    """
    try:
        return pickle.dumps(job)
    except pickle.PicklingError as exc:  # says what cannot be sent, and why
        raise ValueError(" ".join(str(exc).split())) from None
    except (TypeError, AttributeError) as exc:
        raise ValueError("the run cannot be sent to dask workers: "
                         + " ".join(str(exc).split())) from None


def loading_problem(payload: bytes):
    """Why ``payload`` cannot be unpickled in this process; run on the scheduler and on each
    worker before a run's tasks go there.

    Parameters
    ----------
    payload : bytes
        A job pickled by :func:`sendable`.

    Returns
    -------
    tuple or None
        ``(module, reason)`` for a module it cannot import, ``(None, reason)`` for another
        failure, None if it loads.
    """
    try:
        pickle.loads(payload)
    except ImportError as exc:
        root = exc  # the first error, under the one that named the scene
        while isinstance(root.__context__, ImportError):
            root = root.__context__
        return root.name or exc.name, " ".join(str(root).split())
    except Exception as exc:
        return None, f"{type(exc).__name__}: {' '.join(str(exc).split())}"
    return None


def _check_loadable(client, payload: bytes) -> None:
    """ValueError in one line unless the scheduler and every worker can load the run's job: a
    worker that cannot import the user's module fails to read each task it is sent, dies and
    is started again, and the run waits for good."""
    try:
        found = {"scheduler": client.run_on_scheduler(loading_problem, payload)}
        found.update((f"worker {address}", problem)
                     for address, problem in client.run(loading_problem, payload).items())
    except Exception as exc:
        raise ValueError(f"the dask cluster cannot run stability ({type(exc).__name__}: "
                         f"{' '.join(str(exc).split())}); install it on the scheduler and on "
                         "every worker") from None
    for where, problem in found.items():
        if problem is None:
            continue
        module, reason = problem
        if module is not None:
            raise ValueError(
                f"the dask {where} cannot import module {module!r} ({reason}), which the run "
                "needs: it must be importable on the scheduler and on every worker; put its "
                "folder on their PYTHONPATH, or install it there")
        raise ValueError(f"the dask {where} cannot load the run ({reason}); the scheduler and "
                         "every worker need the same code as this process")


#: Seconds to reach a dask scheduler (its connection is retried that long) ...
CONNECT_TIMEOUT = 10.0
#: ... and at most these more for its answer to the handshake.
_ANSWER = 2.0


def scheduler_client(address: str, timeout: float = CONNECT_TIMEOUT):
    """A ``distributed.Client`` of the scheduler at ``address``, within about ``timeout`` s.

    ``Client(address, timeout=...)`` bounds the TCP connection but not the dask handshake that
    follows it, so a server that accepts the connection and never answers (another service on
    that port, a scheduler that hangs) would keep it waiting for good. The handshake is first
    made once under a deadline, in a thread with its own event loop (the caller may be in one,
    as a notebook is); only a scheduler that answered gets the Client.

    Parameters
    ----------
    address : str
        The scheduler's address, such as ``"tcp://host:8786"``.
    timeout : float, default :data:`CONNECT_TIMEOUT`
        Seconds to reach it; its answer to the handshake may take 2 s more.

    Raises
    ------
    OSError
        One line: the scheduler cannot be reached, or did not answer (or not as a dask
        scheduler does), within ``timeout``.
    """
    import asyncio
    from concurrent.futures import ThreadPoolExecutor

    from distributed import Client
    from distributed.comm import connect

    async def handshake():  # connect() retries a refused connection for ``timeout``
        comm = await asyncio.wait_for(connect(address, timeout=timeout), timeout + _ANSWER)
        await comm.close()

    def unreachable(why):
        return OSError(f"cannot reach the dask scheduler at {address} ({why}); start it, or "
                       "check the address")

    with ThreadPoolExecutor(max_workers=1) as pool:
        try:
            pool.submit(asyncio.run, handshake()).result()
        except (asyncio.TimeoutError, TimeoutError):
            raise unreachable("it took the connection but did not answer as a dask scheduler "
                              f"within {timeout + _ANSWER:g} s") from None
        except (OSError, ValueError) as exc:  # refused, no such host, a malformed address
            raise unreachable(" ".join(str(exc).split()) or type(exc).__name__) from None
        except Exception:  # another protocol: "HTTP/1.1" read as a frame count (3 EiB)
            raise unreachable("it answered, but not as a dask scheduler does: another "
                              "service, such as a web server, may be on that port") from None
    try:
        return Client(address, timeout=f"{timeout}s")
    except (OSError, TimeoutError) as exc:
        raise unreachable(" ".join(str(exc).split())) from None


class _Tracker:
    """Progress of a stored run: a bar over members, ``progress.json``, the interrupt message."""

    def __init__(self, chunks: ChunkStore, todo, progress):
        self.chunks = chunks
        self.started = time.time()
        self.t0 = time.perf_counter()
        self.elapsed = None  # set when the run ends
        self.done_chunks = chunks.n_chunks - len(todo)
        self.done_members = chunks.members - sum(hi - lo for lo, hi in map(chunks.bounds, todo))
        self.new_members = 0
        self.many = len(todo) > 1
        self.inner_progress = False if self.many else progress
        self.bar = None
        if self.many and progress is not False:
            from tqdm.auto import tqdm

            self.bar = tqdm(total=chunks.members, initial=self.done_members, unit="member",
                            unit_scale=True, desc=f"{len(todo)} chunks", leave=False)
        self._report("running")

    def finished(self, k, members):
        self.done_chunks += 1
        self.done_members += members
        self.new_members += members
        if self.bar is not None:
            self.bar.update(members)
        self._report("running")

    def stopped(self):
        self._report("interrupted")
        self.close()
        raise RunInterrupted(
            f"interrupted: {self.done_chunks} of {self.chunks.n_chunks} chunks are finished "
            f"and kept in {self.chunks.dir}; run again with --resume (resume=True) to finish"
        )

    def close(self):
        if self.elapsed is None:
            self.elapsed = time.perf_counter() - self.t0
        if self.bar is not None:
            self.bar.close()
            self.bar = None
        if self.done_chunks == self.chunks.n_chunks:
            self._report("finished")

    def _rate(self):
        dt = time.perf_counter() - self.t0
        return self.new_members / dt if dt > 0 and self.new_members else 0.0

    def _report(self, state):
        self.chunks.report(state, self.done_chunks, self.done_members, self._rate(),
                           self.started)
