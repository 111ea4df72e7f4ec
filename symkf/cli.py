"""The ``symkf`` command: plain text for people, ``--json`` for machines.

Exit status 0 on success, 2 on bad input or usage (one line, no traceback),
3 when a theorem's assumptions fail for the given system.
"""

from __future__ import annotations

import argparse
import importlib
import json
import sys
from pathlib import Path
from typing import Any, Callable, Sequence

import sympy as sp

from .errors import SymkfError
from .exact.algebraic import AlgebraicNumber

EXAMPLES = Path(__file__).resolve().parent.parent / "examples" / "systems"

# name -> (module, function); each returns {"example", "source", "results", "checks"}
REPRODUCE: dict[str, tuple[str, str]] = {
    "quevedo-example3": ("symkf.network.reproduce", "reproduce_quevedo_example3"),
    "quevedo-robot": ("symkf.network.reproduce", "reproduce_quevedo_robot"),
    "quevedo-semi-markov": ("symkf.network.reproduce", "reproduce_quevedo_semi_markov"),
    "yang-example1": ("symkf.capacity", "reproduce_yang_example1"),
    "fusion-pendulum": ("symkf.fusion", "reproduce_fusion_pendulum"),
}


class UsageError(SymkfError):
    """Bad command-line usage."""


def _number(a: AlgebraicNumber, digits: int) -> dict[str, Any]:
    lo, hi = a.refine(sp.Rational(1, 10 ** (digits + 2))).interval
    return {"exact": str(a.exact), "decimal": str(a.evalf(digits)), "interval": [str(lo), str(hi)],
            "minpoly": str(a.minpoly.as_expr())}


def _blocks_json(A: Any) -> list[dict[str, Any]]:
    from .spectral import eigen_blocks
    return [{"modulus": str(b.modulus), "eigenvalues": [str(e) for e in b.eigenvalues],
             "period": b.period, "governing_period": b.governing_period, "proof": b.proof}
            for b in eigen_blocks(A)]


def cmd_demo(args: argparse.Namespace) -> dict[str, Any]:
    from . import files
    from .stability import critical_loss_rate
    out = []
    for path in sorted(EXAMPLES.glob("*.toml")):
        system, _ = files.load(path)
        entry = {"system": path.stem, "A": str(system.A.tolist()), "blocks": _blocks_json(system.A)}
        entry["critical_loss_rate"] = _number(critical_loss_rate(system), 12)
        out.append(entry)
    return {"examples": out}


def _print_demo(res: dict[str, Any]) -> None:
    for e in res["examples"]:
        print(f"== {e['system']}: A = {e['A']}")
        for i, b in enumerate(e["blocks"]):
            print(f"   block {i}: |lambda| = {b['modulus']}, eigenvalues {b['eigenvalues']}")
            print(f"            period tau = {b['period']}, governing period = {b['governing_period']}")
            if b["period"] is None or b["governing_period"] is None:
                print(f"            proof: {b['proof']}")
        c = e["critical_loss_rate"]
        print(f"   critical common i.i.d. loss rate = {c['exact']} ~ {c['decimal']}")


def cmd_analyze(args: argparse.Namespace) -> dict[str, Any]:
    from . import files
    from .stability import stability
    system, loss = files.load(args.file)
    res: dict[str, Any] = {"system": str(args.file), "blocks": _blocks_json(system.A)}
    if loss is not None:
        v = stability(system, loss)
        res["loss"] = repr(loss)
        res["verdict"] = {"stable": v.stable, "theorem": v.theorem,
                          "margins": [_number(m, 12) for m in v.margins], "limiting_block": v.limiting_block,
                          "assumptions": list(v.assumptions),
                          "certificate": [{"modulus": str(c.modulus), "period": c.period,
                                           "decisive_received": [list(e) for e in c.decisive_elements],
                                           "alpha^(2g) rho^g": str(c.margin_power)} for c in v.certificate]}
        res["_text"] = str(v)
    return res


def cmd_critical(args: argparse.Namespace) -> dict[str, Any]:
    from . import files
    from .stability import critical_alpha, critical_loss_rate
    system, loss = files.load(args.file)
    vary = args.vary
    if vary == "common":
        key, value, how = "critical_loss_rate", critical_loss_rate(system), "common i.i.d. loss of all sensors"
    elif vary.startswith("sensor="):
        from .losses import IID
        if not isinstance(loss, IID):
            raise UsageError(f"{args.file}: --vary sensor=NAME needs an i.i.d. [loss] giving the other sensors' rates")
        name = vary.split("=", 1)[1]
        key, value = "critical_loss_rate", critical_loss_rate(system, name, others=list(loss.loss))
        how = f"loss of sensor {name}, others fixed at the file's rates"
    elif vary == "alpha":
        from .losses import IID
        if not isinstance(loss, IID):
            raise UsageError(f"{args.file}: --vary alpha needs an i.i.d. [loss]")
        key, value, how = "critical_alpha", critical_alpha(system, loss), "modulus alpha, losses fixed"
    else:
        raise UsageError(f"--vary {vary!r}: expected common, sensor=NAME or alpha "
                         "(recovery is not implemented yet)")
    return {key: _number(value, args.digits), "varied": how,
            "theorem": "Sui-You-Fu Theorems 4/7 with eq. (36), hyperplane form"}


def cmd_reproduce(args: argparse.Namespace) -> dict[str, Any]:
    if args.name not in REPRODUCE:
        raise UsageError(f"reproduce: unknown example {args.name!r}; known: {', '.join(sorted(REPRODUCE))}")
    module, func = REPRODUCE[args.name]
    try:
        fn: Callable[..., dict] = getattr(importlib.import_module(module), func)
    except (ImportError, AttributeError):
        raise UsageError(f"reproduce: {args.name} is not available in this version") from None
    return fn(args.outdir)


def _parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(prog="symkf", description="Exact stability of multi-sensor Kalman filtering "
                                "over lossy networks (Sui-You-Fu; Quevedo et al.; Yang et al.).")
    sub = p.add_subparsers(dest="command", required=True)
    d = sub.add_parser("demo", help="eigen-blocks, periods and critical loss rates of the example systems")
    d.set_defaults(run=cmd_demo, show=_print_demo)
    a = sub.add_parser("analyze", help="eigen-blocks, periods and, with a [loss] table, the exact verdict")
    a.add_argument("file")
    a.set_defaults(run=cmd_analyze)
    c = sub.add_parser("critical", help="an exact critical value with its isolating interval")
    c.add_argument("file")
    c.add_argument("--vary", default="common", help="common | sensor=NAME | alpha")
    c.add_argument("--digits", type=int, default=15)
    c.set_defaults(run=cmd_critical)
    r = sub.add_parser("reproduce", help="reproduce a paper's example: " + ", ".join(sorted(REPRODUCE)))
    r.add_argument("name")
    r.add_argument("--outdir", default=None, help="directory for figures")
    r.set_defaults(run=cmd_reproduce)
    for s in (d, a, c, r):
        s.add_argument("--json", action="store_true", help="machine-readable output")
    return p


def _print_plain(res: dict[str, Any]) -> None:
    if "_text" in res:
        for b in res.get("blocks", []):
            print(f"block: |lambda| = {b['modulus']}, eigenvalues {b['eigenvalues']}, "
                  f"tau = {b['period']}, governing period = {b['governing_period']}")
        print(res["_text"])
        return
    for k, v in res.items():
        if isinstance(v, dict) and "exact" in v:
            print(f"{k} = {v['exact']}\n  ~ {v['decimal']}\n  in [{v['interval'][0]}, {v['interval'][1]}]"
                  f"\n  minimal polynomial {v['minpoly']}")
        else:
            print(f"{k}: {json.dumps(v, default=str) if isinstance(v, (dict, list)) else v}")


def main(argv: Sequence[str] | None = None) -> int:
    parser = _parser()
    try:
        args = parser.parse_args(argv)
    except SystemExit as exc:
        return int(exc.code or 0)
    if getattr(args, "digits", 15) is not None and getattr(args, "digits", 15) < 1:
        print("symkf: --digits must be at least 1", file=sys.stderr)
        return 2
    try:
        res = args.run(args)
    except SymkfError as exc:
        print(f"symkf: {str(exc).splitlines()[0]}", file=sys.stderr)
        return exc.exit_status
    except RecursionError:
        print("symkf: input too deeply nested", file=sys.stderr)
        return 2
    if args.json:
        print(json.dumps({k: v for k, v in res.items() if not k.startswith("_")}, indent=2, default=str))
    else:
        getattr(args, "show", _print_plain)(res)
    return 0


if __name__ == "__main__":  # pragma: no cover
    raise SystemExit(main())
