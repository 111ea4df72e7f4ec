"""Runner of the exact-engine benchmark rows: this checkout against git ``main``.

Each measurement is a fresh interpreter (cold caches) that builds one system of
:mod:`engine_cases`, runs one computation and prints its CPU seconds
(``time.process_time``) and a digest of the exact result.  The baseline is the ``main``
branch of the same repository, exported with ``git archive`` to a temporary directory and
run the same way in the same process (so load on the shared machine hits both alike); a
baseline that exceeds its time cap is reported as ``> cap`` and the ratio as a lower bound.
Medians over ``repeats`` runs; the digests must agree (no exact result changes).  Peak RSS is
the child's ``ru_maxrss``.  ``SYMKF_BASELINE=DIR`` takes the baseline from a checkout of main
(e.g. a worktree fixed at the day's main) instead of exporting ``main``; ``caps`` of a row are
:func:`symkf.budget.limits` keywords raised in both children (main refuses rows past its defaults).

Child mode: ``python engine_rows.py --child WHAT CASE ARG...``.
"""

from __future__ import annotations

import hashlib
import json
import os
import resource
import signal
import statistics
import subprocess
import sys
import tarfile
import tempfile
import time
from io import BytesIO
from pathlib import Path

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent


def _child(what: str, case: str, args: list[str]) -> None:
    sys.path.insert(0, str(HERE))
    try:  # rows run within symkf.budget's defaults unless they name caps; a baseline older than the cost model
        from symkf import budget  # (max_cyclotomic_degree) refused prime rotations: raise its caps
        if not hasattr(budget.LIMITS, "max_cyclotomic_degree"):
            budget.LIMITS.max_degree, budget.LIMITS.max_sensors = 10 ** 6, 128
    except ImportError:  # a baseline older than symkf.budget
        pass
    import contextlib
    import engine_cases
    from symkf.errors import BudgetError
    # a row names the caps of every tree it runs in: each tree takes the ones it knows
    caps = {k: v for k, v in json.loads(os.environ.get("BENCH_CAPS", "{}")).items() if k in budget.OPTIONS}
    with (budget.limits(**caps) if caps else contextlib.nullcontext()):
        start = time.process_time()
        try:  # a system refused at its construction (main's max_dimension) is a refusal too
            system, loss = getattr(engine_cases, case)(*[int(a) for a in args])
            start = time.process_time()
            result = _compute(what, system, loss)
        except BudgetError as exc:  # a refusal is a result of its own: the row says which cap and when
            print("refused", time.process_time() - start, str(exc).replace("\n", " "))
            return
        cpu = time.process_time() - start
    print(cpu, hashlib.sha1(result.encode()).hexdigest()[:12], resource.getrusage(resource.RUSAGE_SELF).ru_maxrss)


def _compute(what: str, system, loss) -> str:
    if what == "critical":
        from symkf.engine.stability import critical_loss_rate
        result = str(critical_loss_rate(system).exact)
    elif what == "stability":
        from symkf.engine.stability import stability
        v = stability(system, loss)
        result = f"{v.stable} {[str(m.exact) for m in v.margins]}"
    elif what == "recovery":  # the case's loss is Gilbert-Elliott: its fail rates, a common recovery rate
        from symkf.engine.recovery import critical_recovery_rate
        result = str(critical_recovery_rate(system, fail=loss.fail).exact)
    elif what == "perron":  # the case is a non-negative matrix: its exact Perron root
        from symkf.engine.rates import perron_root
        result = str(perron_root(system))
    elif what == "bounds":  # the atlas of published bounds beside the exact value, with its LMI bisection
        from symkf import bounds
        atlas = bounds(system, loss)
        result = " ".join(f"{r.key}:{r.relation}:{r.value}:{r.bracket}" for r in atlas.rows)
    elif what == "analyze":  # the CLI command on a TOML file of the system (JSON output captured)
        result = _analyze(system, loss)
    else:
        raise SystemExit(f"unknown computation {what}")
    return result


def _analyze(system, loss) -> str:
    import contextlib
    import io
    from symkf.cli import main
    rows = lambda M: "[" + ", ".join("[" + ", ".join(f'"{v}"' for v in M.row(i)) + "]"  # noqa: E731
                                     for i in range(M.shape[0])) + "]"
    text = f"[system]\nA = {rows(system.A)}\n" + "".join(
        f'\n[[sensors]]\nname = "{s.name}"\nC = {rows(s.C)}\n' for s in system.sensors)
    text += "\n[loss]\nkind = \"iid\"\nloss = [" + ", ".join(f'"{e}"' for e in loss.loss) + "]\n"
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "system.toml"
        path.write_text(text)
        out = io.StringIO()
        with contextlib.redirect_stdout(out):
            status = main(["analyze", str(path), "--json"])
    if status != 0:
        raise SystemExit(f"analyze exited with {status}")
    verdict = json.loads(out.getvalue())["verdict"]  # the exact part (main's JSON layout moves on)
    return f"{verdict['stable']} {[m['exact'] for m in verdict['margins']]}"


def _baseline_tree(tmp: str) -> str:
    """``$SYMKF_BASELINE``, else ``git archive main`` of this repository unpacked: the reference."""
    if os.environ.get("SYMKF_BASELINE"):
        return os.environ["SYMKF_BASELINE"]
    data = subprocess.run(["git", "-C", str(ROOT), "archive", "main", "symkf"], capture_output=True,
                          check=True).stdout
    tarfile.open(fileobj=BytesIO(data)).extractall(tmp)
    return tmp


def _run(tree: str, what: str, case: str, args: list, cap: float, caps: dict) -> tuple[float | None, str, int]:
    """One child run, capped at ``cap`` CPU seconds (RLIMIT_CPU: on the shared machine wall time
    overstates the work); ``(None, "timeout", 0)`` when it does not finish."""
    env = {**os.environ, "PYTHONPATH": tree, "OPENBLAS_NUM_THREADS": "1", "BENCH_CAPS": json.dumps(caps)}
    limit = lambda: resource.setrlimit(resource.RLIMIT_CPU, (int(cap) + 1, int(cap) + 2))  # noqa: E731
    try:
        out = subprocess.run([sys.executable, __file__, "--child", what, case, *map(str, args)], env=env,
                             capture_output=True, text=True, timeout=50 * cap, check=True, cwd=tree,
                             preexec_fn=limit).stdout.split()
    except (subprocess.TimeoutExpired, subprocess.CalledProcessError) as exc:
        if isinstance(exc, subprocess.CalledProcessError) and exc.returncode != -signal.SIGXCPU:
            raise
        return None, "timeout", 0
    if out[0] == "refused":
        return None, f"refused after {float(out[1]):.1f} CPU-s: {' '.join(out[2:])}", 0
    return float(out[0]), out[1], int(out[2])


def compare(title: str, what: str, cases: list[tuple], repeats: int = 3,
            baseline_cap: float = 120, baseline_repeats: int = 1, cap: float = 600) -> None:
    """Print one line per case ``(case, args, target[, caps])``: CPU medians and peak RSS of this
    checkout (each run capped at ``cap`` CPU seconds) and of main, the ratio, the target, and
    whether the exact results agree."""
    print(f"{title}\n  CPU seconds (time.process_time of the computation, fresh interpreter each), "
          f"medians; baseline = git main (cap {baseline_cap:.0f} CPU-s), load {os.getloadavg()[0]:.1f}")
    with tempfile.TemporaryDirectory() as tmp:
        main_tree = _baseline_tree(tmp)
        for case, args, target, *caps in cases:
            caps = caps[0] if caps else {}
            label = f"{case}{tuple(args)}" + (" raised caps" if caps else "")
            runs = [_run(str(ROOT), what, case, args, cap, caps) for _ in range(repeats)]
            if any(t is None for t, _, _ in runs):
                why = next(d for t, d, _ in runs if t is None)
                print(f"  {label}: " + (why if why != "timeout" else f"> {cap:.0f} s (did not finish)")
                      + f"; main not run   target <= {target} NOT met", flush=True)
                continue
            new = statistics.median(t for t, _, _ in runs)
            rss = max(m for _, _, m in runs) / 1024
            base = [_run(main_tree, what, case, args, baseline_cap, caps) for _ in range(baseline_repeats)]
            done = [(t, m) for t, _, m in base if t is not None]
            same = {d for _, d, _ in runs} | {d for t, d, _ in base if t is not None}
            if done:
                old = statistics.median(t for t, _ in done)
                vs = f"main {old:8.2f} s {max(m for _, m in done) / 1024:6.0f} MB   ratio {old / new:7.1f}x"
            elif base[0][1] != "timeout":
                vs = f"main {base[0][1]}"
            else:
                vs = f"main > {baseline_cap:6.0f} s            ratio > {baseline_cap / new:5.1f}x"
            print(f"  {label}: {new:7.2f} s {rss:6.0f} MB   {vs}   target <= {target} "
                  f"{'met' if new <= target else 'NOT met'}   same exact result: "
                  f"{len(same) == 1 if done else 'baseline did not finish'}   digest {runs[0][1]}", flush=True)


if __name__ == "__main__":
    if sys.argv[1:2] == ["--child"]:
        _child(sys.argv[2], sys.argv[3], sys.argv[4:])
