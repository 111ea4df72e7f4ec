"""Independent tasks evaluated serially, across local processes, or on a Dask cluster.

``sweep(function, tasks)`` returns ``[function(t) for t in tasks]`` in the order
of ``tasks`` whichever way it runs:

* ``jobs=1`` (default): in this process;
* ``jobs=N``: ``N`` local worker processes (:class:`concurrent.futures.ProcessPoolExecutor`);
* ``scheduler="tcp://host:port"`` or a ``distributed.Client``: on a Dask
  distributed cluster (:mod:`symkf.run.scheduler`, the optional ``dask`` extra).

Ctrl-C or SIGTERM (which the command line raises as an exception) cancels the queued tasks and
stops the workers before it propagates; workers ignore Ctrl-C themselves and die with their
parent, so a killed parent leaves no orphan computing.

Values are exact, so the three modes return equal results (tested).  Tasks and
results cross process boundaries by plain pickle (symkf's algebraic numbers, systems
and errors pickle; a task's symkf error is re-raised in the caller with its type,
message and attributes).  ``function`` must be
importable by the workers (a module-level function, or a ``functools.partial``
of one).  Progress (:mod:`symkf.run.progress`): one bar, the caller's; with workers, each finished
task is a plain line above it, and the workers draw nothing.
"""

from __future__ import annotations

import contextlib
import ctypes
import dataclasses
import os
import signal
import sys
import threading
import time
from concurrent.futures import FIRST_COMPLETED, ProcessPoolExecutor, wait
from dataclasses import dataclass
from typing import Any, Callable, Iterable, Iterator, Sequence, TypeVar

from ..arguments import check_public
from .. import budget
from ..errors import InputError
from .progress import progress as progress_bar, silenced

T = TypeVar("T")
R = TypeVar("R")


def sweep(function: Callable[[T], R], tasks: Iterable[T], *, jobs: int = 1, scheduler: Any = None,
          progress: bool | None = None, desc: str = "symkf sweep",
          cost: Callable[[T], float] | None = None, label: Callable[[T], str] | None = None) -> list[R]:
    """``[function(t) for t in tasks]``, serially, on ``jobs`` local processes, or on Dask.

    ``scheduler`` is a Dask scheduler address (``"tcp://host:8786"``) or a
    ``distributed.Client``; it excludes ``jobs > 1``.  ``progress`` forces the
    bar on or off (default: on when stderr is a terminal).

    Parameters
    ----------
    function : callable
        Applied to each task; with ``jobs > 1`` or ``scheduler`` it must be importable by the
        workers (a module-level function or a ``functools.partial`` of one).
    tasks : iterable
        The arguments, one call each; they and the results must pickle across processes.
    jobs : int, default 1
        Number of local worker processes.
    scheduler : str or distributed.Client, optional
        A Dask scheduler address or client (the ``dask`` extra).
    progress : bool, optional
        Show the bar (default: on a terminal or in a Jupyter kernel, unless the environment
        sets ``TQDM_DISABLE``; :func:`symkf.run.progress.progress`).  Inside another reporter,
        the sweep moves that one instead.
    desc : str, default "symkf sweep"
        The bar's label.
    cost : callable, optional
        An estimate of each task's work: local processes start the costliest first (longest
        processing time first, so no worker is left with one long task at the end) and the bar
        moves by each task's estimate; the results keep the order of ``tasks``.
    label : callable, optional
        A task's name in the line printed when a worker finishes it (default ``task N``).

    Returns
    -------
    list
        ``[function(t) for t in tasks]``, in the order of ``tasks``.

    Raises
    ------
    InputError
        ``jobs`` is not a positive integer, or both ``jobs > 1`` and ``scheduler`` are given.
    SymkfError
        A task's symkf error, re-raised with its type, message and attributes.

    Examples
    --------
    Critical common loss rates of ``A = 2`` with one sensor (``4 eps < 1``, by hand) and of
    ``A = 2R(pi/2)`` with sensors ``[1, 0]``, ``[1, 1]`` (``16 eps^3 < 1``, see
    :func:`symkf.engine.stability.critical_loss_rate`); ``jobs=2`` returns the same list:

    >>> import symkf as sk
    >>> systems = [sk.System(A=[[2]], sensors=[sk.Sensor(C=[[1]])]),
    ...            sk.System(A=[[0, -2], [2, 0]], sensors=[sk.Sensor(C=[[1, 0]]), sk.Sensor(C=[[1, 1]])])]
    >>> [eps.exact for eps in sk.sweep(sk.critical_loss_rate, systems, progress=False)]
    [1/4, 2**(2/3)/4]
    """
    tasks = list(tasks)
    if isinstance(jobs, bool) or not isinstance(jobs, int) or jobs < 1:
        raise InputError(f"jobs: expected a positive integer number of processes, got {jobs!r}")
    if scheduler is not None and jobs != 1:
        raise InputError("jobs and scheduler: give one of them (local processes or a Dask cluster), not both")
    if scheduler is not None:
        from .scheduler import run_on_scheduler
        return run_on_scheduler(_Limited(function, dataclasses.asdict(budget.LIMITS)), tasks, scheduler, progress,
                                desc, _named(tasks, label))
    work = [cost(t) for t in tasks] if cost else [1] * len(tasks)
    if jobs == 1 or len(tasks) <= 1:
        out = []
        with progress_bar(sum(work), desc, enabled=progress) as bar:
            for t, w in zip(tasks, work):
                out.append(function(t))
                bar.update(w)
        return out
    order = sorted(range(len(tasks)), key=lambda i: -work[i])
    return _processes(_Limited(function, dataclasses.asdict(budget.LIMITS)), tasks, order, jobs, progress, desc,
                      _named(tasks, label), work)


def _named(tasks: Sequence, label: Callable | None) -> Callable[[int], str]:
    """The line for task ``i`` finished by a worker: its label, and how many are done."""
    done = iter(range(1, len(tasks) + 1))
    return lambda i: f"{label(tasks[i]) if label else f'task {i + 1}'} done ({next(done)} of {len(tasks)})"


@dataclass(frozen=True)
class _Limited:
    """``function`` under the caller's resource caps: :mod:`symkf.budget` is per process, and a
    worker would otherwise run with the defaults whatever ``--max-*`` or ``limits(...)`` said."""

    function: Callable
    caps: dict

    def __call__(self, task: Any) -> Any:
        # a worker draws nothing: its parent owns the terminal and reports the finished task
        with budget.limits(**self.caps), silenced():
            return self.function(task)


def _processes(function: Callable, tasks: Sequence, order: Iterable[int], jobs: int, progress: bool | None,
               desc: str, finished: Callable[[int], str], work: Sequence[float]) -> list:
    """The tasks submitted in ``order`` (workers take them first come, first served).  Whatever
    ends the wait early (Ctrl-C, SIGTERM raised as an exception, a task's error) cancels the
    queued tasks and kills the workers before it propagates: none is left computing."""
    results: list[Any] = [None] * len(tasks)
    pool = ProcessPoolExecutor(max_workers=min(jobs, len(tasks)), initializer=_worker_started,
                               initargs=(os.getpid(),))
    try:
        with progress_bar(sum(work), desc, enabled=progress) as bar:
            futures = {pool.submit(function, tasks[i]): i for i in order}
            pending = set(futures)
            while pending:
                # a short wait, not one until a task ends: Ctrl-C delivered to another thread of this
                # process (the kernel picks any) runs its handler only when the main thread wakes,
                # which would otherwise be when the running tasks finish
                done, pending = wait(pending, timeout=WAKE, return_when=FIRST_COMPLETED)
                for f in done:
                    results[futures[f]] = f.result()
                    bar.note(f"{desc}: {finished(futures[f])}")
                    bar.update(work[futures[f]])
    except BaseException:
        _stop(pool)
        raise
    pool.shutdown()
    return results


#: seconds between the main thread's wake-ups while it waits for workers (how late Ctrl-C can be)
WAKE = 0.25


def _stop(pool: ProcessPoolExecutor) -> None:
    """Cancel the queued tasks and kill the workers (SIGKILL: they write no files and hold nothing
    the parent needs).  The executor has no public call for this before Python 3.14
    (``kill_workers``); its process table is read directly."""
    workers = list((getattr(pool, "_processes", None) or {}).values())
    with _interrupts_ignored():
        pool.shutdown(wait=False, cancel_futures=True)
        for worker in workers:
            worker.kill()
        for worker in workers:
            worker.join(5)


@contextlib.contextmanager
def _interrupts_ignored() -> Iterator[None]:
    """A second Ctrl-C (or SIGTERM) while the workers are being stopped is dropped: the run is
    ending already, and the clean-up must not be cut short (signal handlers belong to the main
    thread; elsewhere nothing is changed)."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    saved = {s: signal.getsignal(s) for s in (signal.SIGINT, signal.SIGTERM)}
    saved = {s: h for s, h in saved.items() if h is not None}   # None: a handler not set from Python
    for s in saved:
        signal.signal(s, signal.SIG_IGN)
    try:
        yield
    finally:
        for s, handler in saved.items():
            signal.signal(s, handler)


#: prctl(2) option: the signal a process receives when its parent dies
_PR_SET_PDEATHSIG = 1


def _worker_started(parent: int) -> None:
    """A worker leaves shutdown to its parent: it ignores Ctrl-C (which the terminal sends to the
    whole process group), takes SIGTERM's default action (not a handler inherited by fork), and
    dies with its parent, so that a parent killed by SIGKILL leaves no orphan computing."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    signal.signal(signal.SIGTERM, signal.SIG_DFL)
    if os.getppid() == parent and _kill_on_parent_death():
        if os.getppid() != parent:  # the parent died before prctl took effect
            os._exit(1)
        return
    if os.name != "posix":  # os.kill(pid, 0) would terminate the parent on Windows
        return
    threading.Thread(target=_watch_parent, args=(parent,), name="symkf parent watch", daemon=True).start()


def _kill_on_parent_death() -> bool:
    """Linux: ask the kernel for SIGKILL when the parent dies; False where that is not available."""
    if not sys.platform.startswith("linux"):
        return False
    try:
        libc = ctypes.CDLL(None, use_errno=True)
        return libc.prctl(_PR_SET_PDEATHSIG, signal.SIGKILL, 0, 0, 0) == 0
    except (OSError, AttributeError):
        return False


def _watch_parent(parent: int) -> None:
    """Elsewhere (or under a fork server, whose child this worker is): poll for the parent, which
    is gone when this process is reparented or the parent's process id is free."""
    ppid = os.getppid()
    while True:
        try:
            os.kill(parent, 0)
        except ProcessLookupError:
            os._exit(1)
        except PermissionError:
            pass
        if os.getppid() != ppid:
            os._exit(1)
        time.sleep(1)


check_public(globals())
