"""Design queries (symkf.design) at the sizes users ask for, against enumerating subsets.

Rows (each in a fresh interpreter: CPU seconds of the query, peak RSS, the engine verdicts it
took, and the answer):

* the 4-dim eigen-block diag(2R(pi/6), 2R(pi/4)) (modulus 2, governing period 24) with 32
  candidate sensors (``engine_cases.two_rotations``): the cheapest stable set under i.i.d. losses
  1/2, the fewest sensors with a critical i.i.d. loss rate of at least 9/10, the same under
  Gilbert-Elliott channels (fail 1/10, recover 1/2) and with a critical recovery rate of at most
  1/10; targets <= 60 CPU-s (i.i.d.) and <= 120 CPU-s (Gilbert-Elliott), peak <= 1 GB;
* dense random 8- and 12-state systems with 24 candidates (``engine_cases.dense``), i.i.d. 1/2;
* the Pareto front and the channel allocation of the 32 candidates;
* the baseline a user would write: every subset decided by ``stability`` on its own system, in
  order of cost, at d = 8 and 10 of the same block (all 2^d subsets; the query beside it on the
  same candidates), and the per-subset time this implies for 2^32 subsets.

Usage: python bench_design.py [ROW ...]      (default: every row)
Child mode: python bench_design.py --child ROW
"""

import itertools
import json
import sys
import time

from timing import peak_rss_mb, run_child_rows


def _query(row: str):
    import symkf as sk
    from engine_cases import dense, two_rotations
    if row.startswith("dense"):
        S, _ = dense(int(row[5:]), d=24)
        return sk.design.select_sensors(S, sk.IID("1/2", d=24))
    if row.startswith("enumerate") or row.startswith("query"):
        d = int(row.split("-")[1])
        S, _ = two_rotations(d)
        if row.startswith("query"):
            return sk.design.select_sensors(S, sk.IID("1/2", d=d))
        from symkf.design.selection import subsystem
        best = None
        for r in range(1, d + 1):
            for keep in itertools.combinations(range(d), r):
                try:
                    ok = sk.stability(subsystem(S, list(keep)), sk.IID("1/2", d=r)).stable
                except sk.SymkfError:
                    ok = False
                if ok and best is None:
                    best = keep
        return best
    S, _ = two_rotations(32)
    ge = sk.GilbertElliott("1/10", "1/2", d=32)
    return {"iid": lambda: sk.design.select_sensors(S, sk.IID("1/2", d=32)),
            "iid-rate": lambda: sk.design.select_sensors(S, critical_rate="9/10"),
            "ge": lambda: sk.design.select_sensors(S, ge),
            "ge-recovery": lambda: sk.design.select_sensors(S, ge, recovery_rate="1/10"),
            "pareto": lambda: sk.design.pareto_front(S),
            "allocate": lambda: sk.design.allocate_channels(S)}[row]()


def child(row: str) -> None:
    import symkf  # noqa: F401  (imported before the clock: the query is timed, not the import)
    t = time.process_time()
    result = _query(row)
    cpu = time.process_time() - t
    if hasattr(result, "certificate"):
        answer = {"sensors": len(result.indices or ()), "decisions": result.certificate.decisions}
    elif hasattr(result, "points"):
        answer = {"points": len(result.points), "decisions": result.decisions}
    elif hasattr(result, "gap"):
        answer = {"cost": round(result.cost, 6), "gap": result.gap, "rows": result.rows}
    else:
        answer = {"sensors": len(result or ())}
    print(json.dumps({"row": row, "cpu": cpu, "rss_mb": peak_rss_mb(), **answer}))


ROWS = ["iid", "iid-rate", "ge", "ge-recovery", "dense8", "dense12", "pareto", "allocate",
        "enumerate-8", "query-8", "enumerate-10", "query-10"]


def main(rows: list[str]) -> None:
    run_child_rows(__file__, rows)


if __name__ == "__main__":
    if sys.argv[1:2] == ["--child"]:
        child(sys.argv[2])
    else:
        main(sys.argv[1:] or ROWS)
