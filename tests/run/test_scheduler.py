"""A Dask scheduler that cannot be used is one line naming it, exit status 2, within the timeout.
Loopback addresses only: fake listeners, a LocalCluster without
workers, a scheduler killed mid-run."""

from __future__ import annotations

import contextlib
import json
import socket
import subprocess
import sys
import threading
import time

import pytest

from symkf import budget, cli
from symkf.errors import SchedulerError
from symkf.run.sweep import sweep

pytest.importorskip("distributed")

#: the timeout of these tests (the default is 20 s)
TIMEOUT = 1
FAMILY_TEXT = '[family]\n[grid]\na = ["2", "3"]\n[system]\nA = [["a"]]\n[[sensors]]\nC = [["1"]]\n'


@contextlib.contextmanager
def listener(answer: bytes | None):
    """A TCP server on 127.0.0.1 that accepts, sends ``answer`` (None: never a byte) and stays silent."""
    server = socket.socket()
    server.bind(("127.0.0.1", 0))
    server.listen()
    server.settimeout(0.2)
    accepted, stop = [], threading.Event()

    def serve() -> None:
        while not stop.is_set():
            try:
                conn, _ = server.accept()
            except OSError:
                continue
            accepted.append(conn)
            if answer is not None:
                conn.sendall(answer)
    thread = threading.Thread(target=serve, daemon=True)
    thread.start()
    try:
        yield f"tcp://127.0.0.1:{server.getsockname()[1]}"
    finally:
        stop.set()
        thread.join()
        for conn in accepted:
            conn.close()
        server.close()


def refused(address: str, match: str, within: float = TIMEOUT + 3, function=abs, tasks=(-1, -2)) -> None:
    start = time.monotonic()
    with budget.limits(scheduler_timeout=TIMEOUT), pytest.raises(SchedulerError, match=match) as info:
        sweep(function, tasks, scheduler=address, progress=False)
    assert time.monotonic() - start < within
    message = str(info.value)
    assert address in message and "\n" not in message


def test_a_listener_that_never_answers():
    """Hung past 120 s although the client's timeout was 20 s."""
    with listener(None) as address:
        refused(address, f"accepts connections but did not answer within {TIMEOUT} s; is it a Dask scheduler")


def test_a_listener_that_answers_garbage():
    """Was reported as "out of memory" (its bytes read as a frame of exabytes)."""
    with listener(b"HTTP/1.1 400 Bad Request\r\n\r\n" * 8) as address:
        refused(address, "answers, but not in Dask's protocol")


def test_a_closed_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        address = f"tcp://127.0.0.1:{s.getsockname()[1]}"
    refused(address, "cannot connect to the Dask scheduler at .*ConnectionRefusedError", within=1)


@pytest.mark.parametrize("address, match", [("tls://127.0.0.1:8786", "tls:// needs TLS certificates"),
                                            ("wss://127.0.0.1:8786", "wss:// needs TLS certificates"),
                                            ("ucx://127.0.0.1:8786", "ucx:// needs UCX communication")])
def test_protocols_that_need_more_than_an_address(address, match):
    """Raised TypeError (exit 70)."""
    refused(address, match, within=1)


def test_a_scheduler_without_workers():
    """Hung silently."""
    import distributed
    with distributed.LocalCluster(n_workers=0, processes=False, protocol="tcp://", host="127.0.0.1",
                                  dashboard_address=None) as cluster:
        refused(cluster.scheduler_address, f"has no workers \\(none joined within {TIMEOUT} s\\)")


def test_the_command_line_says_it_in_one_line(capsys, tmp_path):
    family = tmp_path / "fam.toml"
    family.write_text(FAMILY_TEXT)
    with listener(None) as address:
        status = cli.main(["table", str(family), "--scheduler", address, "--scheduler-timeout", str(TIMEOUT)])
    out, err = capsys.readouterr()
    assert status == 2 and out == "" and err.count("\n") == 1
    assert err.startswith(f"symkf table: {family}: --scheduler: the Dask scheduler at {address} accepts connections "
                          "but did not answer within 1 s")


@pytest.mark.parametrize("command", ["table", "verify"])
@pytest.mark.parametrize("extra, message", [
    (["--scheduler", "nonsense"], "--scheduler: expected a Dask scheduler address such as 'tcp://host:8786'"),
    (["--scheduler", "tcp://127.0.0.1:1"], "--scheduler: cannot connect to the Dask scheduler at tcp://127.0.0.1:1"),
    (["--scheduler", "ucx://127.0.0.1:8786"], "--scheduler: the Dask scheduler at ucx://127.0.0.1:8786: ucx:// needs"),
    (["--scheduler", "tcp://127.0.0.1:1", "--jobs", "2"], "--jobs and --scheduler: give one of them"),
])
def test_scheduler_errors_name_the_file_and_the_option_in_one_line(capsys, tmp_path, command, extra, message):
    # began "symkf table: scheduler: ...", the Python keyword and no file, unlike every other error
    family = tmp_path / "fam.toml"
    family.write_text(FAMILY_TEXT + '[loss]\nkind = "iid"\nloss = ["1/2"]\n')
    status = cli.main([command, str(family), *extra, "--oversubscribe"])
    out, err = capsys.readouterr()
    assert status == 2 and out == "" and err.count("\n") == 1, err
    assert err.startswith(f"symkf {command}: {family}: {message}"), err


def test_verify_of_a_system_file_refuses_a_scheduler_it_would_not_use(capsys, tmp_path):
    # the address was ignored: the paths ran locally, whatever --scheduler said
    system = tmp_path / "s.toml"
    system.write_text('[system]\nA = [["2"]]\n[[sensors]]\nC = [["1"]]\n[loss]\nkind = "iid"\nloss = ["1/2"]\n')
    status = cli.main(["verify", str(system), "--scheduler", "tcp://127.0.0.1:1", "--paths", "100"])
    out, err = capsys.readouterr()
    assert status == 2 and out == "" and err.count("\n") == 1
    assert err.startswith(f"symkf verify: {system}: --scheduler: a system file's simulation runs in local processes")


def test_a_scheduler_losing_its_workers_mid_run():
    import distributed
    with distributed.LocalCluster(n_workers=1, threads_per_worker=1, processes=False, protocol="tcp://",
                                  host="127.0.0.1", dashboard_address=None) as cluster:
        worker = next(iter(cluster.workers.values()))
        threading.Timer(1, cluster.sync, args=(worker.close,)).start()
        refused(cluster.scheduler_address, "lost all its workers mid-run", within=1 + 3 * TIMEOUT + 3,
                function=time.sleep, tasks=[0.3] * 40)


@pytest.mark.full
def test_a_scheduler_killed_mid_run(tmp_path):
    """Gave exit 70 with a traceback ("FutureCancelledError ... scheduler-connection-lost")."""
    scheduler_file = tmp_path / "scheduler.json"
    scheduler = subprocess.Popen([sys.executable, "-m", "distributed.cli.dask_scheduler", "--host", "127.0.0.1",
                                  "--port", "0", "--no-dashboard", "--scheduler-file", str(scheduler_file)],
                                 stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    worker = None
    try:
        deadline = time.monotonic() + 60
        while not scheduler_file.exists() or not scheduler_file.read_text().strip():
            assert time.monotonic() < deadline, "the scheduler did not start"
            time.sleep(0.1)
        address = json.loads(scheduler_file.read_text())["address"]
        worker = subprocess.Popen([sys.executable, "-m", "distributed.cli.dask_worker", address, "--nthreads", "1",
                                   "--no-nanny", "--no-dashboard"], stdout=subprocess.DEVNULL,
                                  stderr=subprocess.DEVNULL)
        threading.Timer(8, scheduler.kill).start()     # the worker joins within a few seconds
        start = time.monotonic()
        with budget.limits(scheduler_timeout=20), \
                pytest.raises(SchedulerError, match="was lost mid-run \\(scheduler-connection-lost\\)") as info:
            sweep(time.sleep, [2] * 30, scheduler=address, progress=False)
        assert address in str(info.value) and time.monotonic() - start < 40
    finally:
        for p in (scheduler, worker):
            if p is not None:
                p.kill()
                p.wait()


def test_a_scheduler_answers_in_a_notebook_too():
    """The check runs in a thread of its own: a running event loop in the caller's thread (a
    Jupyter kernel's) does not stop it."""
    import asyncio
    import distributed
    with distributed.LocalCluster(n_workers=1, processes=False, protocol="tcp://", host="127.0.0.1",
                                  dashboard_address=None) as cluster:
        address = cluster.scheduler_address

        async def in_a_running_loop() -> list:
            return sweep(abs, [-1, -2], scheduler=address, progress=False)
        assert asyncio.run(in_a_running_loop()) == [1, 2]
