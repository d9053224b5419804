"""What a study writes into its output folder: the files it names, written so that a stopped
run leaves each whole or absent."""

from __future__ import annotations

import time

from ..output.dataset import append_history, config_toml, software_attrs
from ..output.io import saving
from ..plotting.style import save
from ..util import conventions as cv
from ..util.interrupts import deferred_interrupt
from ..util.ledger import book
from ..util.threads import numba_threads

from .config import to_toml


def output_files(config: dict, figures, extra=()) -> list[str]:
    """The files a run of ``config`` writes into its folder: the Dataset, the files named by the
    ``extra`` keys of ``[output]``, ``config.toml`` and the ``figures`` in every format."""
    out = config["output"]
    names = [out["dataset"], *(out[key] for key in extra), "config.toml"]
    if out["figures"]:
        names += [f"{stem}.{fmt}" for stem in figures for fmt in out["formats"]]
    return names


def write_outputs(ds, config: dict, out_dir, name: str, figures: dict, *, overwrite=False,
                  history=None, attrs=None, threads=None, texts=None, timings=None):
    """Label ``ds`` and write what ``[output]`` asks for: the Dataset, ``config.toml`` and the
    figures, published together (:func:`stability.output.io.saving`: the write runs while the
    figures draw; an interruption publishes nothing).

    Ctrl-C (and SIGTERM) take effect between two figures, as KeyboardInterrupt: raised inside
    matplotlib's compiled drawing code, an interrupt came out as another error ("Invalid
    affine transformation matrix") or crashed the process.

    Parameters
    ----------
    ds : xarray.Dataset
        The study's result; gets ``Conventions`` (the CF version every study's Dataset
        follows), the title, the study kind, the configuration (``config_toml``), ``attrs``, a
        history line, and the software versions and threads where it does not record them
        already (a run records them where it ran).
    config : dict
        The resolved configuration.
    out_dir : Path
        The output folder (it exists).
    name : str
        The study kind.
    figures : dict
        ``{stem: draw}``, ``draw(ds) -> Figure`` for each figure the study draws.
    history : str or False, optional
        The command to record (default ``stability run (<name>)``); False where ``ds`` already
        records the run that made it (a streamed ensemble does).
    threads : int, optional
        The Numba threads the run used (``stability run --threads``), recorded where ``ds``
        does not record them.
    texts : dict, optional
        ``{file name: text}``: more files written beside ``config.toml`` (a report, say).
    timings : dict, optional
        Filled with the seconds spent: ``figures`` (drawn and saved, while the Dataset is
        written beside them) and ``dataset`` (the wait for the write after the figures).

    Returns
    -------
    ds : xarray.Dataset
        As written.
    files : list of Path
    """

    with numba_threads(threads):  # what the run recorded where it ran is kept
        software = {k: v for k, v in software_attrs().items() if k not in ds.attrs}
    ds.attrs.update({"Conventions": cv.CONVENTIONS, "title": config["title"], "study": name,
                     **(attrs or {}),
                     "config_toml": config_toml(config), **software})
    if history is not False:
        ds = append_history(ds, history or f"stability run ({name})")
    out = config["output"]
    files = [out_dir / out["dataset"]]
    spent = timings if timings is not None else {}
    with deferred_interrupt() as stop, saving(ds, files[0], overwrite=overwrite,
                                              compress=out.get("compression", "zlib")):
        started = time.perf_counter()
        for file, text in {**(texts or {}), "config.toml": to_toml(config)}.items():
            (out_dir / file).write_text(text, encoding="utf-8")
            files.append(out_dir / file)
        for stem, draw in figures.items() if out["figures"] else ():
            if stop.requested:
                break
            files += save(draw(ds), out_dir, stem, out["formats"])
        if stop.requested:  # the Dataset's write ends first (leaving the block waits for it)
            raise KeyboardInterrupt
        drawn = time.perf_counter()
        spent["figures"] = drawn - started
    spent["dataset"] = time.perf_counter() - drawn
    book("figures", spent["figures"])
    book("write", spent["dataset"])
    return ds, files
