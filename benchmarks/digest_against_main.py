"""Exact results of this checkout against a checkout of main, case by case (no exact value may change).

Each side runs in its own interpreter with its tree on ``PYTHONPATH`` (this checkout, and
``--main-tree`` run by ``--main-python``, default this interpreter), and the child names the tree it
imported symkf from (a script's own directory heads ``sys.path``, not the working directory: without
the path both sides would import the installed symkf).  The cases: Perron roots of non-negative matrices
over Q(sqrt 2, sqrt 3, sqrt 5) (:func:`engine_cases.radical_matrix`, small enough for main's
sympy path), over Q(sqrt 2), and critical loss rates and verdicts of the engine rows' systems
(rotations in two to four cyclotomic fields among them: the cylinders and their fibres),
among them Gilbert-Elliott losses with algebraic probabilities (Perron roots of restricted
transfers over Q(sqrt 2)).  Prints one line per case and exits 1 on any difference.

Usage: python digest_against_main.py [--main-python PATH] [--main-tree DIR]
"""

from __future__ import annotations

import argparse
import json
import subprocess
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent

CASES = ([("perron", "radical", seed, 2) for seed in range(6)] + [("perron", "radical", seed, 3) for seed in range(3)]
         + [("perron", "sqrt2", k, 0) for k in range(4)]
         + [("critical", "cyclotomic_fields", 2, 0), ("critical", "cyclotomic_fields", 3, 0),
            ("critical", "cyclotomic_fields", 4, 0), ("stability", "cyclotomic_fields", 3, 0),
            ("stability", "cyclotomic_fields", 4, 0), ("critical", "rotation_block", 2, 2),
            ("critical", "prime_rotation", 23, 0), ("critical", "dense", 8, 0),
            ("stability", "gilbert_elliott", 2, 0), ("stability", "rotation_stack", 3, 0),
            ("stability_ge_sqrt2", "gilbert_elliott", 2, 0), ("stability_ge_sqrt2", "gilbert_elliott", 3, 1)])


def _child() -> None:
    sys.path.insert(0, str(HERE))
    import sympy as sp
    import engine_cases
    import symkf as sk
    try:
        from symkf.engine.rates import perron_root
    except ImportError:   # a checkout from before the layers were folders
        from symkf.decay import perron_root
    out = {}
    for what, case, a, b in CASES:
        if what == "perron":
            q = sp.sqrt(2) / 2
            M = (engine_cases.radical_matrix(a, b) if case == "radical" else
                 [sp.Matrix([[q, q], [q, 0]]), sp.Matrix([[0, 1], [1 - q, 0]]), sp.Matrix([[q, 1 - q, 0], [0, q, 1 - q], [1 - q, 0, q]]),
                  sp.Matrix([[0, q, 0, 1], [1 - q, 0, q, 0], [0, 1, 0, q], [q, 0, 1 - q, 0]])][a])
            r = sk.AlgebraicNumber.from_expr(perron_root(M))
            value = f"{r.minpoly.as_expr()} ~ {r.evalf(30)}"
        elif what == "critical":
            system, _ = getattr(engine_cases, case)(a, *([b] if b else []))
            value = str(sk.critical_loss_rate(system).exact)
        else:
            system, loss = getattr(engine_cases, case)(a, b)
            if what == "stability_ge_sqrt2":
                loss = sk.GilbertElliott([sp.sqrt(2) / 4] * system.d, [1 - sp.sqrt(2) / 2] * system.d)
            v = sk.stability(system, loss)
            value = f"{v.stable} {[str(m.exact) for m in v.margins]}"
        out[f"{what} {case} {a} {b}"] = value
    print(json.dumps({"tree": str(Path(sk.__file__).resolve().parent.parent), "results": out}))


def _run(python: str, tree: str) -> dict:
    env = {"PATH": "/usr/bin:/bin", "OPENBLAS_NUM_THREADS": "1", "PYTHONPATH": tree}
    res = subprocess.run([python, __file__, "--child"], env=env, capture_output=True, text=True, check=True, cwd=tree)
    out = json.loads(res.stdout)
    if Path(out["tree"]) != Path(tree).resolve():
        raise SystemExit(f"the child for {tree} imported symkf from {out['tree']}")
    return out["results"]


def main() -> int:
    ap = argparse.ArgumentParser()
    ap.add_argument("--main-python", default=sys.executable)
    ap.add_argument("--main-tree", default="/work/main")
    args = ap.parse_args()
    ours, theirs = _run(sys.executable, str(HERE.parent)), _run(args.main_python, args.main_tree)
    bad = 0
    for key in ours:
        same = ours[key] == theirs.get(key)
        bad += not same
        print(f"{'same' if same else 'DIFFERENT'}  {key}: {ours[key][:90]}" + ("" if same else f"\n    main: {theirs.get(key)}"))
    print(f"{len(ours) - bad} same, {bad} different")
    return 1 if bad else 0


if __name__ == "__main__":
    if sys.argv[1:2] == ["--child"]:
        _child()
    else:
        sys.exit(main())
