"""Runner of issue 18's exact-engine benchmark rows: this checkout against git ``main``.

Each measurement is a fresh interpreter (cold caches) that builds one system of
:mod:`engine_cases`, runs one computation and prints its CPU seconds
(``time.process_time``) and a digest of the exact result.  The baseline is the ``main``
branch of the same repository, exported with ``git archive`` to a temporary directory and
run the same way in the same process (so load on the shared machine hits both alike); a
baseline that exceeds its time cap is reported as ``> cap`` and the ratio as a lower bound.
Medians over ``repeats`` runs; the digests must agree (no exact result changes).

Child mode: ``python engine_rows.py --child WHAT CASE ARG...``.
"""

from __future__ import annotations

import hashlib
import json
import os
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
    try:  # every row runs within symkf.budget's defaults; a baseline older than the cost model
        from symkf import budget  # (max_cyclotomic_degree) refused prime rotations: raise its caps
        if not hasattr(budget.LIMITS, "max_cyclotomic_degree"):
            budget.LIMITS.max_degree, budget.LIMITS.max_sensors = 10 ** 6, 128
    except ImportError:  # a baseline older than symkf.budget
        pass
    import engine_cases
    system, loss = getattr(engine_cases, case)(*[int(a) for a in args])
    start = time.process_time()
    if what == "critical":
        from symkf.stability import critical_loss_rate
        result = str(critical_loss_rate(system).exact)
    elif what == "stability":
        from symkf.stability import stability
        v = stability(system, loss)
        result = f"{v.stable} {[str(m.exact) for m in v.margins]}"
    elif what == "analyze":  # the CLI command on a TOML file of the system (JSON output captured)
        result = _analyze(system, loss)
    else:
        raise SystemExit(f"unknown computation {what}")
    cpu = time.process_time() - start
    print(cpu, hashlib.sha1(result.encode()).hexdigest()[:12])


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
    """``git archive main`` of this repository, unpacked: the reference implementation."""
    data = subprocess.run(["git", "-C", str(ROOT), "archive", "main", "symkf"], capture_output=True,
                          check=True).stdout
    tarfile.open(fileobj=BytesIO(data)).extractall(tmp)
    return tmp


def _run(tree: str, what: str, case: str, args: list, cap: float) -> tuple[float | None, str]:
    env = {**os.environ, "PYTHONPATH": tree, "OPENBLAS_NUM_THREADS": "1"}
    try:
        out = subprocess.run([sys.executable, __file__, "--child", what, case, *map(str, args)], env=env,
                             capture_output=True, text=True, timeout=cap, check=True, cwd=tree).stdout.split()
    except subprocess.TimeoutExpired:
        return None, "timeout"
    return float(out[0]), out[1]


def compare(title: str, what: str, cases: list[tuple[str, list, float]], repeats: int = 3,
            baseline_cap: float = 120, baseline_repeats: int = 1) -> None:
    """Print one line per case: CPU medians of this checkout and of main, the ratio, the target."""
    print(f"{title}\n  CPU seconds (time.process_time of the computation, fresh interpreter each), "
          f"medians; baseline = git main (cap {baseline_cap:.0f} s), load {os.getloadavg()[0]:.1f}")
    with tempfile.TemporaryDirectory() as tmp:
        main_tree = _baseline_tree(tmp)
        for case, args, target in cases:
            runs = [_run(str(ROOT), what, case, args, 600) for _ in range(repeats)]
            new = statistics.median(t for t, _ in runs)
            base = [_run(main_tree, what, case, args, baseline_cap) for _ in range(baseline_repeats)]
            done = [t for t, _ in base if t is not None]
            same = {d for _, d in runs} | {d for t, d in base if t is not None}
            if done:
                old = statistics.median(done)
                vs = f"main {old:8.2f}   ratio {old / new:7.1f}x"
            else:
                vs = f"main > {baseline_cap:6.0f}   ratio > {baseline_cap / new:5.1f}x"
            print(f"  {case}{tuple(args)}: {new:7.2f}   {vs}   target <= {target} "
                  f"{'met' if new <= target else 'NOT met'}   same exact result: "
                  f"{len(same) == 1 if done else 'baseline did not finish'}")


if __name__ == "__main__":
    if sys.argv[1:2] == ["--child"]:
        _child(sys.argv[2], sys.argv[3], sys.argv[4:])
