"""Tasks on a Dask distributed scheduler, whose failures are symkf errors naming it.

:func:`symkf.run.sweep.sweep` with ``scheduler=`` comes here (the optional ``dask`` extra is
imported only here).  Before any task is sent, the address is checked:

* its form (``[protocol://]host:port``): anything else is refused before distributed sees it
  (a Client that fails half-built can deadlock the next one when the garbage collector closes it);
* its protocol: ``tls://`` and ``wss://`` need certificates from Dask's configuration, ``ucx://``
  its communication package;
* that it answers Dask's ``identity`` request as a scheduler within the timeout (a listener
  that accepts and never answers, or answers with anything else, is refused: distributed itself
  waits past its own timeout on the first, and reads the second as a frame of exabytes);
* that it has a worker, or gets one within the timeout.

During the run, a scheduler lost midway, or left without workers, (its futures cancelled with "scheduler-connection-lost",
a closed connection) ends the sweep with the same error.  Every one of these is a
:class:`~symkf.errors.SchedulerError` (exit status 2 on the command line).  The timeout is the
cap ``scheduler_timeout`` of :mod:`symkf.budget` (seconds; ``--scheduler-timeout``).
"""

from __future__ import annotations

import asyncio
import concurrent.futures
import contextlib
import importlib.util
import logging
import re
import socket
import threading
from importlib.metadata import PackageNotFoundError, version
from typing import Any, Callable, Iterator, Sequence

from .. import budget
from ..arguments import check_public
from ..errors import InputError, SchedulerError, require_extra
from .progress import progress as progress_bar

#: a scheduler address, ``[protocol://]host:port`` (a DNS name, IPv4 or bracketed IPv6 host)
_ADDRESS = re.compile(r"(?:(?:tcp|tls|ucx|ws|wss)://)?"
                      r"(?:[A-Za-z0-9](?:[A-Za-z0-9-]*[A-Za-z0-9])?(?:\.[A-Za-z0-9](?:[A-Za-z0-9-]*[A-Za-z0-9])?)*"
                      r"|\[[0-9A-Fa-f:.]+\]):\d{1,5}")

#: what the client raises when the scheduler went away: its futures cancelled
#: (distributed's FutureCancelledError, "scheduler-connection-lost"), the connection closed
#: (CommClosedError is an OSError), the loop's own cancellation
_LOST = (concurrent.futures.CancelledError, asyncio.CancelledError, OSError)


def run_on_scheduler(function: Callable, tasks: Sequence, scheduler: Any, progress: bool | None,
                     desc: str, finished: Callable[[int], str]) -> list:
    """``[function(t) for t in tasks]`` on the Dask ``scheduler`` (an address or a
    ``distributed.Client``), checked first (module docstring)."""
    distributed = require_extra("distributed", "dask", "scheduler: running on a Dask cluster")
    timeout = budget.LIMITS.scheduler_timeout
    if isinstance(scheduler, distributed.Client):
        name = f"the Dask scheduler at {getattr(scheduler.scheduler, 'address', scheduler)}"
        return _on_client(scheduler, name, function, tasks, timeout, progress, desc, finished)
    if not isinstance(scheduler, str) or not _ADDRESS.fullmatch(scheduler) or \
            not 0 < int(scheduler.rpartition(":")[2]) < 65536:
        raise InputError(f"scheduler: expected a Dask scheduler address such as 'tcp://host:8786' "
                         f"or a distributed.Client, got {scheduler!r}")
    name = f"the Dask scheduler at {scheduler}"
    security = _security(scheduler, name)
    _listening(scheduler, name, timeout)
    _identify(scheduler, name, timeout, security)
    try:
        client = distributed.Client(scheduler, timeout=f"{timeout}s", security=security)
    except Exception as exc:  # noqa: BLE001 -- the probe answered: any failure now is the scheduler's
        raise SchedulerError(f"scheduler: cannot connect to {name} ({_why(exc)})") from None
    with _quiet_distributed(), client:
        return _on_client(client, name, function, tasks, timeout, progress, desc, finished)


def _security(address: str, name: str) -> Any:
    """The TLS set-up of Dask's configuration for a ``tls://`` or ``wss://`` address (None otherwise)."""
    protocol = address.partition("://")[0] if "://" in address else "tcp"
    if protocol == "ucx" and importlib.util.find_spec("distributed_ucxx") is None:
        raise SchedulerError(f"scheduler: {name}: ucx:// needs UCX communication (the distributed-ucxx "
                             "package), which is not installed; give a tcp:// address")
    if protocol not in ("tls", "wss"):
        return None
    from distributed import Security
    security = Security()
    if security.get_connection_args("client").get("ssl_context") is None:
        raise SchedulerError(f"scheduler: {name}: {protocol}:// needs TLS certificates, and Dask's configuration "
                             "(distributed.comm.tls) gives none; configure them, or pass a distributed.Client "
                             "created with security=...")
    return security


def _listening(address: str, name: str, timeout: int) -> None:
    """Something accepts TCP connections at ``address`` (distributed would retry a refused
    connection until its timeout, and then say only that it timed out); UCX is not checked."""
    if address.startswith("ucx://"):
        return
    host, _, port = address.rpartition("://")[2].rpartition(":")
    try:
        socket.create_connection((host.strip("[]"), int(port)), timeout=timeout).close()
    except TimeoutError:
        raise SchedulerError(f"scheduler: cannot connect to {name} (no answer within {timeout} s; "
                             "the timeout is --scheduler-timeout)") from None
    except OSError as exc:
        raise SchedulerError(f"scheduler: cannot connect to {name} ({_why(exc)})") from None


def _identify(address: str, name: str, timeout: int, security: Any) -> dict:
    """Dask's ``identity`` answer of ``address``, in a thread of its own (a Jupyter kernel's
    event loop may be running in this one) and within ``timeout`` seconds."""
    from distributed.comm import connect
    args = {} if security is None else security.get_connection_args("client")

    async def ask() -> dict:
        comm = await connect(address, timeout=timeout, **args)
        try:
            await comm.write({"op": "identity", "reply": True})
            return await comm.read()
        finally:
            comm.abort()

    answer: dict[str, Any] = {}

    def probe() -> None:
        try:
            answer["reply"] = asyncio.run(asyncio.wait_for(ask(), timeout))
        except BaseException as exc:  # noqa: BLE001 -- garbage can raise anything, MemoryError included
            answer["error"] = exc

    thread = threading.Thread(target=probe, name="symkf scheduler probe", daemon=True)
    thread.start()
    thread.join(timeout + 1)
    reply, error = answer.get("reply"), answer.get("error")
    if error is None and thread.is_alive() or isinstance(error, TimeoutError):
        raise SchedulerError(f"scheduler: {name} accepts connections but did not answer within {timeout} s; "
                             "is it a Dask scheduler? (the timeout is --scheduler-timeout)")
    if isinstance(error, OSError):
        raise SchedulerError(f"scheduler: cannot connect to {name} ({_why(error)})")
    if error is not None:  # bytes that are not Dask's protocol (a header read as an exabyte frame, ...)
        raise SchedulerError(f"scheduler: {name} answers, but not in Dask's protocol ({_why(error)})")
    if not isinstance(reply, dict) or reply.get("type") != "Scheduler":
        kind = reply.get("type") if isinstance(reply, dict) else None
        raise SchedulerError(f"scheduler: {name} does not answer as a Dask scheduler"
                             f"{f' (it is a {kind})' if isinstance(kind, str) else ''}")
    return reply


def _on_client(client: Any, name: str, function: Callable, tasks: Sequence, timeout: int,
               progress: bool | None, desc: str, finished: Callable[[int], str]) -> list:
    import distributed
    try:
        client.wait_for_workers(1, timeout=timeout)
    except Exception as exc:  # noqa: BLE001 -- a timeout, or the scheduler gone meanwhile
        why = f"none joined within {timeout} s" if isinstance(exc, TimeoutError) else _why(exc)
        raise SchedulerError(f"scheduler: {name} has no workers ({why}); start some with "
                             "`dask worker ADDRESS` (the timeout is --scheduler-timeout)") from None
    futures = client.map(function, tasks, pure=False)
    try:
        with progress_bar(len(tasks), desc, enabled=progress) as bar:
            pending = futures
            while pending:
                try:
                    done, pending = distributed.wait(pending, timeout=timeout, return_when="FIRST_COMPLETED")
                except TimeoutError:  # a long task, or nobody left to run it
                    if not client.scheduler_info().get("workers"):
                        raise SchedulerError(f"scheduler: {name} lost all its workers mid-run (no result for "
                                             f"{timeout} s and no worker left); no result was kept") from None
                    continue
                for f in done:
                    bar.note(f"{desc}: {finished(futures.index(f))}")
                bar.update(len(done))
        return client.gather(futures)
    except RuntimeError as exc:
        if "deserialization" not in str(exc):
            raise
        raise SchedulerError(f"scheduler: {name}: its workers cannot unpickle symkf's tasks; they need symkf "
                             f"{_installed_version()} and its dependencies installed") from None
    except _LOST as exc:
        raise SchedulerError(f"scheduler: {name} was lost mid-run ({_reasons(exc)}); no result was kept") from None
    except BaseException:  # Ctrl-C, SIGTERM: the cluster drops the queued work
        with contextlib.suppress(Exception):
            client.cancel(futures)
        raise


def _installed_version() -> str:
    """This installation's symkf version, as the workers must have it."""
    try:
        return version("symkf")
    except PackageNotFoundError:   # run from a source tree that was never installed
        return "of this source tree"


def _reasons(exc: BaseException) -> str:
    """Why the futures were cancelled ("scheduler-connection-lost"): distributed's
    FutureCancelledError has a ``reason``, FuturesCancelledError groups of them; else the error."""
    groups = getattr(exc, "error_groups", None) or [exc]
    reasons = sorted({r for r in (getattr(g, "reason", None) for g in groups) if isinstance(r, str)})
    return ", ".join(reasons) if reasons else _why(exc)


@contextlib.contextmanager
def _quiet_distributed() -> Iterator[None]:
    """distributed logs each failed reconnection with a traceback on stderr; on symkf's own client
    the error raised here says what happened, in one line."""
    loggers = [logging.getLogger(n) for n in list(logging.root.manager.loggerDict)
               if n == "distributed" or n.startswith("distributed.")]
    levels = [logger.level for logger in loggers]
    for logger in loggers:
        logger.setLevel(logging.CRITICAL)
    try:
        yield
    finally:
        for logger, level in zip(loggers, levels):
            logger.setLevel(level)


def _why(exc: BaseException) -> str:
    text = " ".join(str(exc).split())
    return f"{type(exc).__name__}: {text[:200]}" if text else type(exc).__name__


check_public(globals())
