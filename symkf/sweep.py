"""Independent tasks evaluated serially, across local processes, or on a Dask cluster.

``sweep(function, tasks)`` returns ``[function(t) for t in tasks]`` in the order
of ``tasks`` whichever way it runs:

* ``jobs=1`` (default): in this process;
* ``jobs=N``: ``N`` local worker processes (:class:`concurrent.futures.ProcessPoolExecutor`);
* ``scheduler="tcp://host:port"`` or a ``distributed.Client``: on a Dask
  distributed cluster (the optional ``dask`` extra, imported only here).

Values are exact, so the three modes return equal results (tested).  Tasks and
results cross process boundaries by plain pickle (symkf's algebraic numbers, systems
and errors pickle; a task's symkf error is re-raised in the caller with its type,
message and attributes).  ``function`` must be
importable by the workers (a module-level function, or a ``functools.partial``
of one).  Progress is shown with tqdm when stderr is a terminal.
"""

from __future__ import annotations

import dataclasses
import re
from concurrent.futures import ProcessPoolExecutor, as_completed
from dataclasses import dataclass
from typing import Any, Callable, Iterable, Sequence, TypeVar

from .exact.arguments import check_public
from . import budget
from .errors import InputError
from .progress import progress as progress_bar

T = TypeVar("T")
R = TypeVar("R")


def sweep(function: Callable[[T], R], tasks: Iterable[T], *, jobs: int = 1, scheduler: Any = None,
          progress: bool | None = None, desc: str = "symkf sweep",
          cost: Callable[[T], float] | None = None) -> list[R]:
    """``[function(t) for t in tasks]``, serially, on ``jobs`` local processes, or on Dask.

    ``scheduler`` is a Dask scheduler address (``"tcp://host:8786"``) or a
    ``distributed.Client``; it excludes ``jobs > 1``.  ``progress`` forces the
    tqdm bar on or off (default: on when stderr is a terminal).

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
        Show the tqdm bar (default: on a terminal or in a Jupyter kernel, unless the
        environment sets ``TQDM_DISABLE``; :func:`symkf.progress.progress`).
    desc : str, default "symkf sweep"
        The bar's label.
    cost : callable, optional
        An estimate of each task's work: local processes start the costliest first (longest
        processing time first, so no worker is left with one long task at the end); the results
        keep the order of ``tasks``.

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
    :func:`symkf.stability.critical_loss_rate`); ``jobs=2`` returns the same list:

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
        return _dask(_Limited(function, dataclasses.asdict(budget.LIMITS)), tasks, scheduler, progress, desc)
    if jobs == 1 or len(tasks) <= 1:
        out = []
        with progress_bar(len(tasks), desc, enabled=progress) as bar:
            for t in tasks:
                out.append(function(t))
                bar.update()
        return out
    order = sorted(range(len(tasks)), key=lambda i: -cost(tasks[i])) if cost else range(len(tasks))
    return _processes(_Limited(function, dataclasses.asdict(budget.LIMITS)), tasks, order, jobs, progress, desc)


@dataclass(frozen=True)
class _Limited:
    """``function`` under the caller's resource caps: :mod:`symkf.budget` is per process, and a
    worker would otherwise run with the defaults whatever ``--max-*`` or ``limits(...)`` said."""

    function: Callable
    caps: dict

    def __call__(self, task: Any) -> Any:
        with budget.limits(**self.caps):
            return self.function(task)


def _processes(function: Callable, tasks: Sequence, order: Iterable[int], jobs: int, progress: bool | None,
               desc: str) -> list:
    """The tasks submitted in ``order`` (workers take them first come, first served)."""
    results: list[Any] = [None] * len(tasks)
    with ProcessPoolExecutor(max_workers=min(jobs, len(tasks))) as pool, \
            progress_bar(len(tasks), desc, enabled=progress) as bar:
        futures = {pool.submit(function, tasks[i]): i for i in order}
        for f in as_completed(futures):
            results[futures[f]] = f.result()
            bar.update()
    return results


#: a scheduler address, ``[protocol://]host:port`` (a DNS name, IPv4 or bracketed IPv6 host): anything
#: else is refused before distributed sees it (a Client that fails half-built can deadlock the next one
#: when the garbage collector closes it)
_ADDRESS = re.compile(r"(?:(?:tcp|tls|ucx|ws|wss)://)?"
                      r"(?:[A-Za-z0-9](?:[A-Za-z0-9-]*[A-Za-z0-9])?(?:\.[A-Za-z0-9](?:[A-Za-z0-9-]*[A-Za-z0-9])?)*"
                      r"|\[[0-9A-Fa-f:.]+\]):\d{1,5}")


def _dask(function: Callable, tasks: Sequence, scheduler: Any, progress: bool | None, desc: str) -> list:
    try:
        import distributed
    except ImportError:
        raise InputError("scheduler: Dask is not installed; install the extra: pip install 'symkf[dask]'") from None
    if isinstance(scheduler, distributed.Client):
        return _on_client(scheduler, function, tasks, progress, desc)
    if not isinstance(scheduler, str) or not _ADDRESS.fullmatch(scheduler):
        raise InputError(f"scheduler: expected a Dask scheduler address such as 'tcp://host:8786' "
                         f"or a distributed.Client, got {scheduler!r}")
    try:
        client = distributed.Client(scheduler, timeout="20s")
    except (OSError, TimeoutError, ValueError) as exc:
        raise InputError(f"scheduler: cannot connect to the Dask scheduler at {scheduler!r} ({exc})") from None
    with client:
        return _on_client(client, function, tasks, progress, desc)


def _on_client(client: Any, function: Callable, tasks: Sequence, progress: bool | None, desc: str) -> list:
    import distributed
    futures = client.map(function, tasks, pure=False)
    with progress_bar(len(tasks), desc, enabled=progress) as bar:
        for _ in distributed.as_completed(futures):
            bar.update()
    return client.gather(futures)

check_public(globals())
