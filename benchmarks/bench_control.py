"""The critical control-packet arrival rate (symkf.control) against the LMI bisection a user would run.

Rows (each in a fresh interpreter: CPU seconds, peak RSS, the bracket's width):

* ``certified-N``: ``critical_arrival_rate`` at tolerance 1e-12 on the 4-state two-input plant of
  the tests (``N = 4``) and on seeded random controllable integer plants with n = N states and
  two inputs (N = 6, 8);
* ``lmi-N``: the baseline, Schenato et al.'s quasi-convex LMI (the Schur form of
  ``Y > (1 - nu) A Y A' + nu (AY + BZ) Y^-1 (AY + BZ)'``) bisected in ``nu`` with cvxpy/Clarabel
  to width 1e-6 (solver tolerance: 1e-12 is out of reach of an interior-point float), the same
  plant; its answer is a float with no certificate, and the summary says whether its bracket
  holds the certified value (near the threshold the solver's feasibility verdicts drift).

Usage: python bench_control.py [ROW ...]      (default: every row)
Child mode: python bench_control.py --child ROW
"""

import json
import sys
import time

from timing import peak_rss_mb, run_child_rows

FOUR = ([[1, 2, 0, -1], [0, 2, 1, 0], [1, 0, -3, 1], [0, 1, 1, 2]], [[1, 0], [0, 0], [0, 1], [1, 1]])


def _plant(n: int):
    import numpy as np
    if n == 4:
        return FOUR
    rng = np.random.default_rng(n)
    while True:
        A, B = rng.integers(-3, 4, (n, n)), rng.integers(-2, 3, (n, 2))
        ctrb = np.hstack([np.linalg.matrix_power(A.astype(float), k) @ B for k in range(n)])
        if np.linalg.matrix_rank(ctrb) == n and max(abs(np.linalg.eigvals(A.astype(float)))) > 1.01:
            return A.tolist(), B.tolist()


def _lmi(A, B, width=1e-6):
    import cvxpy as cp
    import numpy as np
    A, B = np.array(A, float), np.array(B, float)
    n, m = B.shape

    def feasible(nu):
        Y, Z, t = cp.Variable((n, n), symmetric=True), cp.Variable((m, n)), cp.Variable()
        M = cp.bmat([[Y - (1 - nu) * A @ Y @ A.T, np.sqrt(nu) * (A @ Y + B @ Z)],
                     [np.sqrt(nu) * (A @ Y + B @ Z).T, Y]])
        cp.Problem(cp.Maximize(t), [(M + M.T) / 2 >> t * np.eye(2 * n), Y << np.eye(n)]).solve(solver=cp.CLARABEL)
        return t.value is not None and t.value > 1e-9

    lo, hi = 0.0, 1.0
    while hi - lo > width:
        mid = (lo + hi) / 2
        lo, hi = (lo, mid) if feasible(mid) else (mid, hi)
    return lo, hi


def child(row: str) -> None:
    import sympy as sp
    import symkf as sk
    kind, n = row.rsplit("-", 1)
    A, B = _plant(int(n))
    t = time.process_time()
    if kind == "certified":
        S = sk.System(A=A, sensors=[sk.Sensor(C=sp.eye(len(A)))], actuators=[sk.Actuator(B=B)])
        r = sk.control.critical_arrival_rate(S, "1e-12")
        answer = {"lower": float(r.lower), "width": float(r.width), "reached": r.reached}
    else:
        lo, hi = _lmi(A, B)
        answer = {"lower": lo, "width": hi - lo, "reached": False}
    cpu = time.process_time() - t
    print(json.dumps({"row": row, "cpu": cpu, "rss_mb": peak_rss_mb(), **answer}))


ROWS = ["certified-4", "lmi-4", "certified-6", "lmi-6", "certified-8", "lmi-8"]


def main(rows: list[str]) -> None:
    found = run_child_rows(__file__, rows)
    cpu = {row: res["cpu"] for row, res in found.items()}
    for row in rows:
        if row.startswith("certified") and f"lmi-{row.split('-')[1]}" in cpu and row in cpu:
            lmi = f"lmi-{row.split('-')[1]}"
            lo, w, exact = found[lmi]["lower"], found[lmi]["width"], found[row]["lower"]
            holds = ("holds the certified value" if lo <= exact <= lo + w else
                     f"misses the certified value by {min(abs(exact - lo), abs(exact - lo - w)):.1e}")
            print(f"n = {row.split('-')[1]}: LMI bisection to 1e-6 / certified bracket to 1e-12 = "
                  f"{cpu[lmi] / cpu[row]:.1f}x CPU; the LMI's bracket {holds}")


if __name__ == "__main__":
    if sys.argv[1:2] == ["--child"]:
        child(sys.argv[2])
    else:
        main(sys.argv[1:] or ROWS)
