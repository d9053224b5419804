"""How and where a run goes, as one small frozen object: :class:`RunOptions`.

Every run of the package (a family's measurement, :func:`stability.run_scene`,
:func:`stability.run_ensemble`, a study) takes its run options together: in this process or
chunk by chunk into a store, resumed, on dask.distributed, with how many threads, in chunks of
how many members, with or without a progress bar. None of them changes a number of the result
(members are independent: the result is bitwise the same however the run is cut or wherever it
runs), except ``device="gpu"``, whose results agree with the CPU's to round-off.
"""

from __future__ import annotations

import os
from dataclasses import dataclass, replace
from pathlib import Path

from .memory import DEFAULT_MAX_MEMORY


@dataclass(frozen=True)
class RunOptions:
    """How and where a run goes; the fields are the constructor's parameters.

    Parameters
    ----------
    store : path-like, optional
        Run chunk by chunk into this folder (:class:`~stability.output.store.ChunkStore`): each
        finished chunk is kept at once, memory is one chunk's. Without it, the run is in this
        process.
    resume : bool, default False
        With ``store``: finish a run of the same members stopped earlier (only the missing
        chunks run).
    scheduler : str or distributed.Client, optional
        With ``store``: run the chunks on dask.distributed (``"dask"`` for a local cluster, a
        scheduler address such as ``"tcp://host:8786"``, or a client).
    chunk_members : int, optional
        Members per chunk (default: the run's own rule). Never changes the result.
    chunk_steps : int, optional
        Steps per call of the member loop. Never changes the result.
    threads : int, optional
        Numba threads in this process (restored afterwards).
    progress : bool, optional
        Progress bar; by default shown for runs expected to take more than a few seconds.
    device : {"cpu", "gpu"}, default "cpu"
        Where the member loop runs (``"gpu"``: a CUDA GPU, results to round-off of the CPU's).
    max_memory : float, default 4 GiB
        Refuse a run that would hold more than this many bytes (or more than the machine has).

    Examples
    --------
    >>> options = RunOptions(store="work", chunk_members=4096, progress=False)
    >>> options.within("sphere").store  # one of several runs of a study, in its own folder
    PosixPath('work/sphere')
    """

    store: object = None
    resume: bool = False
    scheduler: object = None
    chunk_members: int | None = None
    chunk_steps: int | None = None
    threads: int | None = None
    progress: bool | None = None
    device: str = "cpu"
    max_memory: float = DEFAULT_MAX_MEMORY

    def __post_init__(self):
        if self.store is not None and not isinstance(self.store, (str, os.PathLike)):
            raise ValueError(f"store must be a folder path (a str or pathlib.Path), got "
                             f"{self.store!r:.80}")
        if not isinstance(self.resume, bool):
            raise ValueError(f"resume must be True or False, got {self.resume!r:.80}")
        if self.device not in ("cpu", "gpu"):
            raise ValueError(f"device must be 'cpu' or 'gpu', got {self.device!r:.80}")

    def within(self, name: str) -> "RunOptions":
        """These options for one of several runs of a study: its own store, the folder
        ``name`` inside this one (no store if there is none).

        Raises
        ------
        ValueError
            That folder is a symbolic link (a run keeps its chunks only in a real folder).
        """
        if self.store is None:
            return self
        store = Path(self.store) / name
        if store.is_symlink():
            raise ValueError(f"{store} is a symbolic link; a run keeps its chunks only in a "
                             "real folder inside the output folder: remove the link")
        return replace(self, store=store)


def run_options(options) -> RunOptions:
    """``options`` as :class:`RunOptions` (None: the defaults); ValueError for anything else."""
    if options is None:
        return RunOptions()
    if not isinstance(options, RunOptions):
        raise ValueError(f"options must be a stability.RunOptions, got "
                         f"{type(options).__name__}; e.g. RunOptions(store='work', "
                         "progress=False)")
    return options
