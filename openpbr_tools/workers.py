"""Process-pool workers that end with the run that started them.

A batch (``validate -j N``, ``convert DIR -o OUT -j N``) runs in a :class:`~concurrent.futures.ProcessPoolExecutor`.
Left alone, a worker outlives its parent: SIGTERM to the parent killed it at once, and its workers, re-parented
to PID 1, went on writing outputs after the command had failed and then waited forever on a queue nobody
writes, holding the parent's stdout and stderr (a CI job reading them hung). Here:

- :func:`pool` makes a pool whose workers ask Linux to send them SIGTERM when their parent dies
  (``prctl(PR_SET_PDEATHSIG)``; elsewhere each task first checks that the parent is still the one that
  started it), and ignore SIGINT (Ctrl-C reaches the whole process group: the parent decides);
- in a worker, SIGTERM raises :class:`Stopped` inside the task, so a write in progress removes its
  temporary file (:mod:`openpbr_tools.atomic`, the writers' ``except BaseException``) and nothing is
  renamed into place, and the worker then exits; between tasks it exits at once. Where the signal lands
  in code whose exceptions Python drops (a weakref callback such as importlib's module-lock ``cb``: "Exception
  ignored in ...", printed with a traceback), the stop is remembered: the drop is silent, the next rename into
  place raises :class:`Stopped` again (:func:`raise_if_stopped`), and the worker exits when the task ends;
- :func:`interruptible` turns SIGTERM to the parent into :class:`SystemExit` (status 143, as a shell
  reports a process ended by SIGTERM) while the pool runs, and :func:`stop` terminates the workers and
  waits for them before the interrupt goes on.
"""

from __future__ import annotations

import contextlib
import os
import signal
import sys
import threading

_PR_SET_PDEATHSIG = 1  # <linux/prctl.h>
_parent: int | None = None  # the process that started this worker


class Stopped(BaseException):
    """Raised in a worker by SIGTERM: not an ``Exception``, so no per-file handler reports it and goes on."""


_in_task = False  # whether this worker is inside run_task (a write may be in progress)
_stopping = False  # whether SIGTERM has reached this worker (its Stopped may have been dropped)


def _on_terminate(signum, frame):
    global _stopping
    if not _in_task:  # idle, waiting on the pool's queue: nothing to clean up, and no traceback to print
        os._exit(143)
    _stopping = True
    raise Stopped()


_interrupted = False  # whether the command was interrupted (SIGINT, said by the command line: note_interrupt)


def note_interrupt() -> None:
    """The command was interrupted: an error met on the way out (an import SIGINT broke: ImportError,
    "initialization failed") is then the interrupt, not a defect for a file's report (internal_error)."""
    global _interrupted
    _interrupted = True


def interrupted() -> bool:
    return _interrupted


def raise_if_stopped() -> None:
    """Raise :class:`Stopped` if this process is a worker that SIGTERM has reached: called before an output is
    renamed into place, so a stop Python dropped (see the module docstring) still writes nothing."""
    if _stopping:
        raise Stopped()


def _unraisable(unraisable) -> None:
    """A worker's ``sys.unraisablehook``: a :class:`Stopped` Python dropped is remembered (``_stopping``), not
    printed; anything else as Python reports it."""
    if not isinstance(unraisable.exc_value, Stopped):
        sys.__unraisablehook__(unraisable)


def _start_worker(parent: int | None) -> None:
    """The pool's initializer: die with ``parent`` (``None``: whichever process started this one, a
    fork server), leave SIGINT to it, stop cleanly on SIGTERM."""
    global _parent
    _parent = os.getppid() if parent is None else parent
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    signal.signal(signal.SIGTERM, _on_terminate)
    sys.unraisablehook = _unraisable
    if sys.platform.startswith("linux"):
        try:
            import ctypes  # lazy: only a pool worker on Linux needs it

            ctypes.CDLL(None, use_errno=True).prctl(_PR_SET_PDEATHSIG, signal.SIGTERM, 0, 0, 0)
        except (OSError, AttributeError):  # no libc prctl (a static or unusual runtime): the parent check below
            pass
    if os.getppid() != _parent:  # the parent died before the request above was made
        os._exit(1)


def run_task(work, argument):
    """``work(argument)`` in a worker; the worker ends when it is stopped or has lost its parent."""
    global _in_task
    if _parent is not None and os.getppid() != _parent:
        os._exit(1)
    _in_task = True
    try:
        result = work(argument)
    except Stopped:  # the writes in progress have removed their temporary files on the way here
        os._exit(1)
    finally:
        _in_task = False
    if _stopping:  # stopped where the exception was dropped: the task went on, but ends here
        os._exit(1)
    return result


def pool(jobs: int):
    """A process pool of ``jobs`` workers started as the module docstring says."""
    import multiprocessing  # lazy: only a pool needs it (validate's start-up does without)
    from concurrent.futures import ProcessPoolExecutor  # lazy: as the line above (~4 ms)

    direct = multiprocessing.get_start_method() in ("fork", "spawn")  # a fork server starts workers itself
    return ProcessPoolExecutor(max_workers=jobs, initializer=_start_worker, initargs=(os.getpid() if direct else None,))


def stop(executor) -> None:
    """Terminate ``executor``'s workers (each removes its temporary file) and wait for them to end."""
    processes = list((getattr(executor, "_processes", None) or {}).values())
    executor.shutdown(wait=False, cancel_futures=True)
    for process in processes:
        with contextlib.suppress(Exception):
            process.terminate()
    for process in processes:
        with contextlib.suppress(Exception):
            process.join(timeout=10)
            if process.is_alive():
                process.kill()
    # the pool's manager thread closes its wake-up pipe once it sees the workers gone; joined here, so that
    # concurrent.futures' exit hook finds the pipe closed instead of racing the close (Python 3.11 prints
    # "Exception ignored ... Bad file descriptor" when it loses)
    manager = getattr(executor, "_executor_manager_thread", None)
    if manager is not None:
        with contextlib.suppress(Exception):
            manager.join(timeout=10)


def _on_parent_terminate(signum, frame):
    raise SystemExit(128 + signum)


@contextlib.contextmanager
def interruptible():
    """While the block runs (in the main thread), SIGTERM raises :class:`SystemExit` instead of killing the
    process outright, so the caller can stop its workers; the previous handler is restored after."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    previous = signal.signal(signal.SIGTERM, _on_parent_terminate)
    try:
        yield
    finally:
        signal.signal(signal.SIGTERM, previous)
