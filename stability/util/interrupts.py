"""Ctrl-C as a request: a flag the work checks at points where stopping loses nothing.

A long run checks its flag between chunks; a study's writing between figures; an animation
between frames. Raised at any instruction instead, Ctrl-C would cut a chunk in half or, inside
compiled code (matplotlib's drawing), come out as another error.
"""

from __future__ import annotations

import contextlib
import signal
import threading


class _Interrupt:
    """A stop request: ``requested`` turns True at Ctrl-C (or :func:`request_stop`)."""

    requested = False


#: The flags of the runs in progress in the main thread, innermost last.
_RUNNING: list = []


@contextlib.contextmanager
def deferred_interrupt():
    """Turn Ctrl-C into a flag the caller checks where stopping loses nothing (between chunks).

    A process that was started with Ctrl-C ignored (a background job of a script) keeps it
    ignored; :func:`request_stop` still reaches the run. A run started inside another whose
    stop was already requested (a member chunk set up after a Ctrl-C) starts stopped.
    """
    flag = _Interrupt()
    if threading.current_thread() is not threading.main_thread():
        yield flag
        return
    flag.requested = any(outer.requested for outer in _RUNNING)
    previous = signal.getsignal(signal.SIGINT)
    _RUNNING.append(flag)  # before the handler, so no Ctrl-C finds the list without it
    try:
        if previous is not signal.SIG_IGN:
            signal.signal(signal.SIGINT, lambda signum, frame: request_stop())
        yield flag
    finally:
        if previous is not signal.SIG_IGN:
            signal.signal(signal.SIGINT, previous)
        _RUNNING.remove(flag)


def request_stop() -> bool:
    """Stop the work in progress as Ctrl-C does, at its next check (a signal handler calls
    this); False when nothing is in progress."""
    if not _RUNNING:
        return False
    _RUNNING[-1].requested = True
    return True
