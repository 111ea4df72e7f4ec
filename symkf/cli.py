"""The ``symkf`` command: plain text for people, ``--json`` for machines.

Exit status 0 on success, 2 on bad input or usage (one line, no traceback),
3 when a theorem's assumptions fail for the given system, 130 when interrupted (Ctrl-C), 143 on SIGTERM.
Output files are checked before any work and written atomically (:mod:`symkf.output`); the
resource caps of :mod:`symkf.budget` are raised with ``--max-degree`` and friends.
"""

from __future__ import annotations

import argparse
import contextlib
import importlib
import json
import os
import re
import signal
import sys
import textwrap
import threading
import warnings
from dataclasses import dataclass
from decimal import ROUND_CEILING, ROUND_FLOOR, Decimal, localcontext
from fractions import Fraction
from typing import TYPE_CHECKING, Any, Callable, Iterator, Sequence


from .arguments import check_public
from . import __version__, budget, output
from .errors import ExtraNotInstalledError, SymkfError
from .run.progress import still_working

if TYPE_CHECKING:
    from .exact.algebraic import AlgebraicNumber
    from .model.loss import LossModel


# name -> (module, function, keyword arguments of --quick); each function returns
# {"example", "source", "results", "checks", "discrepancies"} (symkf.reproduction)
REPRODUCE: dict[str, tuple[str, str, dict[str, Any]]] = {
    "quevedo-example3": ("symkf.network.reproduce", "reproduce_quevedo_example3", {}),
    "quevedo-robot": ("symkf.network.reproduce", "reproduce_quevedo_robot", {}),
    "quevedo-semi-markov": ("symkf.network.reproduce", "reproduce_quevedo_semi_markov", {"simulate": False}),
    "yang-example1": ("symkf.capacity", "reproduce_yang_example1", {"horizon": 12, "paths": 2000}),
    "fusion-pendulum": ("symkf.fusion", "reproduce_fusion_pendulum", {"paths": 4, "horizon": 200}),
    "sui-theorem12": ("symkf.engine.second_order", "reproduce_sui_theorem12", {}),
    "you-2011-counterexample": ("symkf.bounds.counterexample", "reproduce_you_2011_counterexample", {"steps": 4}),
    "schenato-scalar": ("symkf.control.reproduce", "reproduce_schenato_scalar", {"paths": 5000, "horizon": 90}),
    "schenato-closed-forms": ("symkf.control.reproduce", "reproduce_schenato_closed_forms", {"simulate": False}),
    "schenato-claims": ("symkf.control.reproduce", "reproduce_schenato_claims", {}),
}


#: version of every ``--json`` document; raised when a field is renamed or removed
#: (1: blocks carry ``tau`` and ``governing_period``, certificates ``class_period``,
#: losses are structured objects, reproduce separates ``checks`` from ``discrepancies``)
SCHEMA_VERSION = 1

#: exit status of an unexpected exception (a symkf bug), distinct from bad input (2)
INTERNAL_ERROR = 70
#: exit status after Ctrl-C (128 + SIGINT, as shells report it)
INTERRUPTED = 130
#: exit status after SIGTERM (128 + SIGTERM)
TERMINATED = 143


class UsageError(SymkfError):
    """Bad command-line usage."""


class Terminated(KeyboardInterrupt):
    """SIGTERM, raised in the main thread like Ctrl-C so that the same clean-up runs (worker
    processes stopped, queued work cancelled, temporary files removed)."""


@dataclass(frozen=True)
class Command:
    """A subcommand: ``configure`` adds its arguments, ``run`` returns a JSON-serialisable dict
    (keys starting with ``_`` are for the plain-text display only; ``_status`` sets the exit
    status), ``show`` prints it for people (default: :func:`_print_plain`)."""

    name: str
    help: str
    configure: Callable[[argparse.ArgumentParser], None]
    run: Callable[[argparse.Namespace], dict[str, Any]]
    show: Callable[[dict[str, Any]], None] | None = None


#: the subcommands, in the order of ``symkf --help``; new commands call :func:`register`
COMMANDS: dict[str, Command] = {}


def register(command: Command) -> Command:
    COMMANDS[command.name] = command
    return command


def _number(a: AlgebraicNumber, digits: int) -> dict[str, Any]:
    from .numeric.verify import number_json
    return number_json(a, digits)


def _blocks_json(A: Any) -> list[dict[str, Any]]:
    from .exact.spectral import eigen_blocks
    return [b.to_dict() for b in eigen_blocks(A)]


def _block_words(b: Any) -> str:
    """An eigen-block for people: its modulus and distinct eigenvalues in mathematical notation
    (:meth:`~symkf.exact.spectral.EigenBlock.eigenvalue_words`) and its periods."""
    periods = _period_words(b.tau, b.governing_period)
    return f"|lambda| = {b.modulus_words}, eigenvalues {b.eigenvalue_words()}, {periods}"


def loss_json(loss: "LossModel") -> dict[str, Any]:
    """A loss model as a JSON object: ``kind`` (as in a system file's ``[loss]`` table) and its
    parameters as exact strings; a Markov or network model also gives its lifted chain
    (:meth:`symkf.model.loss.LossModel.to_dict`)."""
    return loss.to_dict()


def cmd_demo(args: argparse.Namespace) -> dict[str, Any]:
    from .io import examples, files
    from .engine.stability import critical_loss_rate
    from .exact.text import algebraic_text
    out, words = [], {}
    for path in examples.systems():
        system, _ = files.load(path)
        blocks, rate = system.eigen_blocks(), critical_loss_rate(system)
        out.append({"system": path.stem, "A": str(system.A.tolist()), "blocks": [b.to_dict() for b in blocks],
                    "critical_loss_rate": _number(rate, 12)})
        words[path.stem] = ([_block_words(b) for b in blocks], algebraic_text(rate))
    return {"examples": out, "_words": words}


def _period_words(tau: int | None, g: int | None) -> str:
    """A block's periods in words: "none" where the block has none (aperiodic), never Python's None."""
    if tau is None and g is None:
        return "aperiodic: no period tau, no governing period"
    return f"period tau = {'none' if tau is None else tau}, governing period = {'none' if g is None else g}"


def _print_demo(res: dict[str, Any]) -> None:
    for e in res["examples"]:
        print("\n".join(textwrap.wrap(f"== {e['system']}: A = {e['A']}", 100, subsequent_indent="      ")))
        blocks, rate = res["_words"][e["system"]]
        for i, (b, words) in enumerate(zip(e["blocks"], blocks)):
            print("\n".join(textwrap.wrap(f"block {i}: {words}", 100, initial_indent="   ", subsequent_indent=" " * 12,
                                           break_long_words=False, break_on_hyphens=False)))
            if b["tau"] is None or b["governing_period"] is None:
                print("\n".join(textwrap.wrap(f"proof: {b['proof']}", 100, initial_indent=" " * 12,
                                               subsequent_indent=" " * 14)))
        print(f"   critical common i.i.d. loss rate = {rate}")


def cmd_analyze(args: argparse.Namespace) -> dict[str, Any]:
    from .io import files
    from .engine.stability import stability
    system, loss, actuator_loss = files.load_loop(args.file)
    blocks = system.eigen_blocks()
    res: dict[str, Any] = {"system": str(args.file), "blocks": [b.to_dict() for b in blocks],
                           "_blocks": [_block_words(b) for b in blocks],
                           "set_aside": [{"eigenvalues": [e.label for e in b.members], "reason": why}
                                         for b, why in system.set_aside()]}
    if loss is not None:
        v = stability(system, loss)
        res["loss"] = loss_json(loss)
        res["verdict"] = v.to_dict()
        res["_text"] = f"{v}\n  loss model: {loss.words()}"
    if system.actuators:
        res["control"], res["_control"] = _control_side(system, loss, actuator_loss)
    return res


def _control_side(system: Any, loss: Any, actuator_loss: Any) -> tuple[dict[str, Any], str]:
    """The control side of a file with actuators (Schenato et al., "Foundations of control and
    estimation over lossy networks", 2007, Sections IV and V), as JSON and in words: the critical
    control-packet arrival rate (exact or a certified bracket), with ``[actuator_loss]`` that model
    and, with ``[loss]`` too, the TCP-like loop's verdict (bounded, unbounded or undecided: an
    arrival rate inside the bracket decides nothing), and the UDP-like results."""
    from .control import critical_arrival_rate, lqg_stable, udp_region
    threshold, udp = critical_arrival_rate(system), udp_region(system)
    out: dict[str, Any] = {"actuators": list(system.actuator_names), "critical_arrival_rate": threshold.to_dict()}
    words = [f"control ({', '.join(system.actuator_names)}), TCP-like (acknowledged packets, one channel for "
             f"all inputs): {threshold}"]
    if actuator_loss is not None:
        out["actuator_loss"] = loss_json(actuator_loss)
        words.append(f"  actuator loss model: {actuator_loss.words()}")
        if loss is None:
            words.append("  loop: no verdict without a [loss] table for the sensors")
        else:
            loop = lqg_stable(system, loss, actuator_loss)
            out["loop"] = loop.to_dict()
            words.append(f"  loop: {loop}")
    out["udp"] = udp.to_dict()
    return out, "\n".join([*words, str(udp)])


def _print_control(res: dict[str, Any]) -> None:
    """A result for people (:func:`_print_plain`), its control side (``"control"``) in words after it."""
    _print_plain({k: v for k, v in res.items() if k not in ("control", "_control")})
    for line in res.get("_control", "").splitlines():
        indent = " " * (len(line) - len(line.lstrip()))
        print("\n".join(textwrap.wrap(line, 100, subsequent_indent=indent + "    ", break_long_words=False,
                                       break_on_hyphens=False)))


def _vary_common(system: Any, loss: Any, value: str, file: str) -> tuple[str, AlgebraicNumber, str]:
    from .engine.stability import critical_loss_rate
    return "critical_loss_rate", critical_loss_rate(system), "common i.i.d. loss of all sensors"


def _iid(loss: Any, file: str, option: str) -> Any:
    if loss is None or loss.bernoulli is None:
        raise UsageError(f"{file}: {option} needs an i.i.d. [loss] giving the sensors' rates, not "
                         f"{'no [loss]' if loss is None else loss.words()}")
    return loss


def _vary_sensor(system: Any, loss: Any, name: str, file: str) -> tuple[str, AlgebraicNumber, str]:
    from .engine.stability import critical_loss_rate
    others = list(_iid(loss, file, "--vary sensor=NAME").bernoulli)
    return ("critical_loss_rate", critical_loss_rate(system, name, others=others),
            f"loss of sensor {name}, others fixed at the file's rates")


def _vary_alpha(system: Any, loss: Any, value: str, file: str) -> tuple[str, AlgebraicNumber, str]:
    from .engine.stability import critical_alpha
    return "critical_alpha", critical_alpha(system, _iid(loss, file, "--vary alpha")), "modulus alpha, losses fixed"


def _vary_recovery(system: Any, loss: Any, name: str, file: str) -> tuple[str, AlgebraicNumber, str]:
    from .engine.recovery import critical_recovery_rate
    option = "--vary recovery" + ("=NAME" if name else "")
    if loss is None or loss.channel_fail is None:
        raise UsageError(f"{file}: {option} needs Gilbert-Elliott channels ([loss] of kind 'gilbert-elliott' "
                         f"giving 'fail' and 'recover'), not {'no [loss]' if loss is None else loss.words()}")
    if name:
        return ("critical_recovery_rate", critical_recovery_rate(system, loss, sensor=name),
                f"Gilbert-Elliott recovery probability of sensor {name}, fail and the others' recovery fixed at "
                "the file's; stable iff above")
    return ("critical_recovery_rate", critical_recovery_rate(system, loss.channel_fail),
            "common Gilbert-Elliott recovery probability P(received | lost last), fail fixed; stable iff above")


#: ``--vary`` of ``critical``: "KIND" or "KIND=VALUE" -> handler(system, loss, VALUE, file) giving
#: (JSON key, exact value, what was varied)
VARY: dict[str, Callable[[Any, Any, str, str], tuple[str, AlgebraicNumber, str]]] = {
    "common": _vary_common, "sensor": _vary_sensor, "alpha": _vary_alpha, "recovery": _vary_recovery}


#: peak bytes per digit of ``critical --digits``, at least (the decimal, the interval endpoints'
#: numerators and denominators as integers and text, mpmath's and sympy's copies; the measured peak
#: per digit is higher at very many digits, where the conversions, quadratic in the digits, also
#: cost the most time: docs/performance.md)
DIGIT_BYTES = 64


def cmd_critical(args: argparse.Namespace) -> dict[str, Any]:
    from .io import files
    kind, named, value = args.vary.partition("=")
    if kind not in VARY or (kind == "sensor" and not value) or (kind in ("common", "alpha") and named) \
            or (named and not value):
        raise UsageError(f"--vary {args.vary!r}: expected common, sensor=NAME, alpha, recovery or recovery=NAME")
    budget.check("max_digits", args.digits, "--digits", "the number of digits asked for")
    budget.check("max_memory", DIGIT_BYTES * args.digits, "--digits", "the bytes (estimate) of the digits asked "
                 f"for, {DIGIT_BYTES} per digit")
    tolerance = None if args.tolerance is None else _tolerance(args.tolerance)   # refused before any work
    system, loss, _ = files.load_loop(args.file)
    if tolerance is not None and not system.actuators:
        raise UsageError(f"{args.file}: --tolerance bounds the bracket of the critical control-packet arrival "
                         "rate, and the file has no [[actuators]]")
    key, exact, how = VARY[kind](system, loss, value, args.file)
    res: dict[str, Any] = {key: _number(exact, args.digits), "varied": how,
                           "theorem": "Sui-You-Fu Theorems 4/7 with eq. (36), hyperplane form"}
    if system.actuators:
        region = _tcp_region(system, exact if key == "critical_loss_rate" and kind == "common" else None,
                             "1e-12" if tolerance is None else tolerance)
        res["control"], res["_control"] = region.to_dict(), str(region)
    return res


def _tcp_region(system: Any, eps_c: AlgebraicNumber | None, tolerance: Any) -> Any:
    """The TCP-like region of Schenato et al. (2007, Section IV): ``gamma_c = 1 - eps_c`` (``eps_c``
    reused when ``critical`` has just computed it) and ``nu_c`` to the bracket width ``tolerance``."""
    from .control import TcpRegion, critical_arrival_rate, tcp_region
    if eps_c is None:
        return tcp_region(system, tolerance)
    return TcpRegion(1 - eps_c, critical_arrival_rate(system, tolerance))


def _tolerance(text: str) -> Any:
    """``--tolerance`` as an exact rational in (0, 1), or a usage error naming the option."""
    from .exact.numbers import to_rational
    value = to_rational(text, "--tolerance")
    if not 0 < value < 1:
        raise UsageError(f"--tolerance: the bracket's width must lie in (0, 1), got {value}")
    return value


def _needs_loss(args: argparse.Namespace) -> tuple[Any, Any]:
    from .io import files
    system, loss = files.load(args.file)
    if loss is None:
        raise UsageError(f"{args.file}: key 'loss' missing; {args.command} needs a [loss] table")
    return system, loss


def cmd_verify(args: argparse.Namespace) -> dict[str, Any]:
    from .io.family_verification import is_family_file, verify_family
    from .numeric.verify import verify
    if is_family_file(args.file):
        family = verify_family(args.file, jobs=args.jobs, scheduler=args.scheduler, seed=args.seed,
                               paths=args.paths, horizon=args.horizon)
        return {"family": str(args.file), "members": family.to_dict()["members"], "_text": str(family),
                "_status": 1 if family.counts()["contradiction"] else 0}
    if args.scheduler is not None:   # a single system's paths run in local processes only
        raise UsageError(f"{args.file}: --scheduler: a system file's simulation runs in local processes (give "
                         "--jobs); a Dask scheduler evaluates the members of a family file")
    system, loss = _needs_loss(args)
    result = verify(system, loss, seed=args.seed, paths=args.paths, horizon=args.horizon, jobs=args.jobs)
    # exit status 1 (and "outcome": "contradiction") when simulation contradicts the theory
    return {"system": str(args.file), "loss": loss_json(loss), **result.to_dict(),
            "_text": f"{result}\nloss model: {loss.words()}", "_status": 1 if result.outcome == "contradiction" else 0}


def _args_sweep(p: argparse.ArgumentParser, scope: str = "", scheduler_scope: str = "") -> None:
    """``--jobs`` and ``--scheduler``: how the members of a family are evaluated (symkf.sweep)."""
    p.add_argument("--jobs", type=_positive_int, default=1,
                   help=f"{scope}local worker processes (default 1; at most the CPU count unless --oversubscribe)")
    p.add_argument("--oversubscribe", action="store_true", help=f"{scope}allow --jobs above the CPU count")
    p.add_argument("--scheduler", default=None, metavar="ADDRESS",
                   help=f"{scheduler_scope}a Dask distributed scheduler (tcp://host:port); needs the dask extra")


def _args_verify(p: argparse.ArgumentParser) -> None:
    _args_simulation(p, 120, 20_000)
    _args_sweep(p, "family members, or a single system's simulated paths: ", "family members: ")


def cmd_simulate(args: argparse.Namespace) -> dict[str, Any]:
    from .numeric.simulation import simulate
    target = None
    if args.plot is not None:
        from .reports.plots import require_matplotlib
        require_matplotlib()
        target = output.plan(args.plot, "--plot", inputs=[args.file], force=args.force)
    from .numeric.montecarlo import memory_estimate
    system, loss = _needs_loss(args)
    # the run and its per-step records, refused before numpy allocates them (verify's burst
    # samples are checked where their chunks are sized: montecarlo.burst_sample)
    budget.check("max_memory", memory_estimate(system, loss, args.horizon, args.paths,
                                               records="json" if args.json else "text"), "--paths x --horizon",
                 f"the bytes (estimate) of a simulation of {args.paths} paths over {args.horizon} steps")
    sim = simulate(system, loss, args.horizon, args.paths, seed=args.seed, curve=target is not None)
    res: dict[str, Any] = {"system": str(args.file), "loss": loss_json(loss), **sim.to_dict(),
                           "_text": f"{sim}\nloss model: {loss.words()}"}
    if target is not None:
        from .reports.plots import simulation_figure
        fig = simulation_figure(sim)
        res["plot"] = str(target.put_figure(fig, dpi=110))
    return res


def _print_simulate(res: dict[str, Any]) -> None:
    print(res["_text"])
    if "plot" in res:
        print(f"figure written to {res['plot']}")


def cmd_reproduce(args: argparse.Namespace) -> dict[str, Any]:
    if args.list:
        return {"examples": sorted(REPRODUCE)}
    if args.name is None:
        raise UsageError("give an example name or --list")
    fn, kwargs = resolve_reproduce(args.name)
    outdir = None if args.outdir is None else str(output.plan_directory(args.outdir, "--outdir"))
    return fn(outdir, **(kwargs if args.quick else {}))


def resolve_reproduce(name: str) -> tuple[Callable[..., dict], dict[str, Any]]:
    """The ``reproduce_*`` function of example ``name`` and its ``--quick`` keyword arguments."""
    if name not in REPRODUCE:
        raise UsageError(f"unknown example {name!r}; known: {', '.join(sorted(REPRODUCE))}")
    module, func, quick = REPRODUCE[name]
    try:
        return getattr(importlib.import_module(module), func), quick
    except ExtraNotInstalledError as exc:   # an extra is missing: say which, not that the example is
        raise ExtraNotInstalledError(f"reproduce {name}: {exc}") from None
    except (ImportError, AttributeError):
        raise UsageError(f"{name} is not available in this version") from None


def _print_reproduce(res: dict[str, Any]) -> None:
    if "examples" in res and "example" not in res:
        print("\n".join(res["examples"]))
    else:
        _print_plain(res)


def cmd_examples(args: argparse.Namespace) -> dict[str, Any]:
    from .io import examples
    if args.name is None:
        return {"examples": [{"name": e.name, "kind": e.kind, "summary": e.summary, "file": str(e.path)}
                             for e in examples.catalog()]}
    found = {e.name: e.path for e in examples.catalog()}
    if args.name not in found:
        raise UsageError(f"no shipped example {args.name!r}; known: {', '.join(found)}")
    source = found[args.name]
    # a copy is the user's to edit, not an output symkf regenerates: never replaced without --force
    target = output.plan(source.name, "NAME", inputs=[source], force=args.force, keep_existing=True)
    return {"example": source.stem, "copied": str(target.put_text(source.read_text(encoding="utf-8")))}


def _print_examples(res: dict[str, Any]) -> None:
    if "copied" in res:
        print(f"{res['example']} copied to {res['copied']}; edit it, then give its path to any command")
        return
    width = max(len(e["name"]) for e in res["examples"])
    for kind in dict.fromkeys(e["kind"] for e in res["examples"]):
        print(f"{kind} files:" if kind != "family" else "families (symkf table, symkf verify):")
        for e in res["examples"]:
            if e["kind"] == kind:
                print("\n".join(textwrap.wrap(e["summary"], 100, initial_indent=f"  {e['name']:<{width}}  ",
                                               subsequent_indent=" " * (width + 4), break_on_hyphens=False,
                                               break_long_words=False)))
    print("Every command takes these names where it takes a file; symkf examples NAME copies one here.")


def _args_examples(p: argparse.ArgumentParser) -> None:
    p.add_argument("name", nargs="?", metavar="NAME", help="copy this example into the working directory")
    p.add_argument("--force", action="store_true", help="replace an existing (perhaps edited) copy")


def _args_critical(p: argparse.ArgumentParser) -> None:
    p.add_argument("file")
    p.add_argument("--vary", default="common", help="common | sensor=NAME | alpha | recovery | recovery=NAME")
    p.add_argument("--digits", type=_positive_int, default=15)
    p.add_argument("--tolerance", default=None, metavar="WIDTH",
                   help="a file with [[actuators]]: the width aimed at by the certified bracket of the critical "
                   "control-packet arrival rate nu_c where no closed form applies (an exact number, default 1e-12)")


def _args_simulation(p: argparse.ArgumentParser, horizon: int | None, paths: int | None) -> None:
    p.add_argument("file")
    p.add_argument("--seed", type=_nonnegative_int, default=0, help="random seed (default 0)")
    p.add_argument("--horizon", type=_positive_int, default=horizon, required=horizon is None,
                   help="number of steps K" + (f" (default {horizon})" if horizon else ""))
    p.add_argument("--paths", type=_positive_int, default=paths, required=paths is None,
                   help="Monte Carlo paths M" + (f" per run (default {paths})" if paths else ""))


def _args_simulate(p: argparse.ArgumentParser) -> None:
    _args_simulation(p, None, None)
    p.add_argument("--plot", default=None, metavar="OUT.png", help="write E[tr P_k] against k (needs the plot "
                   "extra); PNG unless the extension names another image format")
    _args_force(p)


def _args_force(p: argparse.ArgumentParser) -> None:
    p.add_argument("--force", action="store_true", help="replace the output file even if it appeared or changed "
                   "while this run was computing (an existing output is replaced anyway; an input file never)")


def _args_reproduce(p: argparse.ArgumentParser) -> None:
    p.add_argument("name", nargs="?")
    p.add_argument("--list", action="store_true", help="list the example names")
    p.add_argument("--outdir", default=None, help="directory for figures (created if missing; the "
                   "example's own figure files in it are replaced)")
    p.add_argument("--quick", action="store_true", help="small sample sizes (a smoke run, not the paper's)")


def cmd_table(args: argparse.Namespace) -> dict[str, Any]:
    from . import bounds  # noqa: F401 -- registers the published bounds' family query (compute = ["bounds"])
    from .reports import tables
    target = None if args.latex is None else output.plan(args.latex, "--latex", inputs=[args.file], force=args.force)
    table = tables.family_table(args.file, jobs=args.jobs, scheduler=args.scheduler)
    res: dict[str, Any] = {"family": str(args.file), **table.to_dict(), "_text": str(table)}
    if target is not None:
        res["latex"] = str(target.put_text(table.to_latex()))
    return res


def _print_table(res: dict[str, Any]) -> None:
    print(res["_text"])
    if "latex" in res:
        print(f"LaTeX (booktabs) written to {res['latex']}")


def _args_table(p: argparse.ArgumentParser) -> None:
    p.add_argument("file", metavar="FAMILY.toml")
    p.add_argument("--latex", default=None, metavar="OUT.tex", help="write the booktabs table here")
    _args_force(p)
    _args_sweep(p)


def cmd_bounds(args: argparse.Namespace) -> dict[str, Any]:
    from .io import files
    from .bounds import bounds
    target = None if args.latex is None else output.plan(args.latex, "--latex", inputs=[args.file], force=args.force)
    system, loss = files.load(args.file)
    atlas = bounds(system, loss, lmi_steps=args.lmi_steps)
    res: dict[str, Any] = {"file": str(args.file), **atlas.to_dict(), "_text": str(atlas)}
    if target is not None:
        res["latex"] = str(target.put_text(atlas.to_latex()))
    return res


def _args_bounds(p: argparse.ArgumentParser) -> None:
    p.add_argument("file", metavar="FILE.toml")
    p.add_argument("--latex", default=None, metavar="OUT.tex", help="write the booktabs table here")
    p.add_argument("--lmi-steps", type=lambda t: _bounded_int(t, 0, 60), default=8, metavar="N",
                   help="bisection steps of Sinopoli et al.'s LMI threshold (default 8)")
    _args_force(p)


def cmd_design(args: argparse.Namespace) -> dict[str, Any]:
    from .io import files
    from . import design
    system, loss, q = files.load_design(args.file)
    query = q["query"]
    if query == "select":
        result: Any = design.select_sensors(system, loss if "critical_rate" not in q else None, costs=q.get("costs"),
                                            critical_rate=q.get("critical_rate"), recovery_rate=q.get("recovery_rate"),
                                            margin=q.get("margin"))
    elif query == "pareto":
        result = design.pareto_front(system, costs=q.get("costs"))
    elif query == "allocate" and loss is not None and loss.channel_fail is not None:
        result = design.allocate_recovery(system, loss.channel_fail, q.get("weights"))
    elif query == "allocate":
        result = design.allocate_channels(system, q.get("weights"), **({"margin": q["margin"]} if "margin" in q else {}))
    elif query == "upgrades":
        result = design.upgrades(system)
    else:
        if loss is None:
            raise UsageError(f"{args.file}: key 'loss' missing; query 'active' needs a [loss] table")
        result = design.active_constraints(system, loss)
    return {"file": str(args.file), "query": query, **result.to_dict(), "_text": str(result)}


def cmd_warm(args: argparse.Namespace) -> dict[str, Any]:
    """Compile (or load from numba's cache) the simulation's kernels for each state dimension, so
    that the first ``simulate`` or ``verify`` of a user's system does not wait for numba."""
    import time
    import sympy as sp
    from .model.iid import IID
    from .model.system import Sensor, System
    from .numeric.simulation import simulate
    out = []
    for n in args.states:
        start = time.process_time()
        system = System(A=2 * sp.eye(n), sensors=[Sensor(C=sp.eye(n))])
        simulate(system, IID(["1/10"]), 2, 2, seed=0)
        out.append({"states": n, "cpu_seconds": round(time.process_time() - start, 2)})
    return {"kernels": out, "_text": "\n".join(f"{k['states']}-state kernels ready ({k['cpu_seconds']} CPU-s)" for k in out)}


def _args_warm(p: argparse.ArgumentParser) -> None:
    p.add_argument("--states", type=lambda t: _bounded_int(t, 1, 64), nargs="+", default=list(range(1, 9)),
                   metavar="N", help="state dimensions to compile for (default 1 to 8)")


def _args_design(p: argparse.ArgumentParser) -> None:
    p.add_argument("file", metavar="FILE.toml")


def _positive_int(text: str) -> int:
    return _bounded_int(text, 1)


def _nonnegative_int(text: str) -> int:
    return _bounded_int(text, 0)


def _bounded_int(text: str, low: int, high: int = 10 ** 9) -> int:
    try:
        value = int(text) if len(text) <= 20 else None
    except ValueError:
        value = None
    if value is None:
        raise argparse.ArgumentTypeError(f"expected an integer, got {text[:40]!r}")
    if value < low or value > high:
        raise argparse.ArgumentTypeError(f"expected an integer in [{low}, {high}], got {value}")
    return value


def _args_caps(p: argparse.ArgumentParser) -> None:
    """The caps of :mod:`symkf.budget`, one option each (documented there)."""
    group = p.add_argument_group("resource caps (symkf.budget; an input above one is refused at once)")
    for name, option in budget.OPTIONS.items():
        group.add_argument(option, dest=f"cap_{name}", default=None,
                           type=lambda t, high=budget.MAX_DIGITS_CAP if name == "max_digits" else 10 ** 15:
                           _bounded_int(t, 1, high),
                           metavar="N", help=f"default {getattr(budget.Limits, name)}")


def _caps(args: argparse.Namespace) -> dict[str, int]:
    return {name: getattr(args, f"cap_{name}") for name in budget.OPTIONS
            if getattr(args, f"cap_{name}", None) is not None}


def _cap_jobs(args: argparse.Namespace, command: str) -> None:
    """--jobs beyond the CPU count only slows a shared machine down: capped unless --oversubscribe."""
    cpus = len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else (os.cpu_count() or 1)
    if getattr(args, "jobs", 1) > cpus and not args.oversubscribe:
        print(f"symkf {command}: note: --jobs {args.jobs} capped at the {cpus} available CPU(s) "
              "(pass --oversubscribe to keep it)", file=sys.stderr)
        args.jobs = cpus


register(Command("demo", "eigen-blocks, periods and critical loss rates of the example systems",
                 lambda p: None, cmd_demo, _print_demo))
register(Command("analyze", "eigen-blocks, periods and, with a [loss] table, the exact verdict; with "
                 "[[actuators]], the control side (critical control-packet arrival rate, the LQG loop's verdict "
                 "under [loss] and [actuator_loss], the UDP-like results)",
                 lambda p: p.add_argument("file"), cmd_analyze, _print_control))
register(Command("critical", "an exact critical value with its isolating interval; with [[actuators]], also "
                 "the TCP-like region (gamma_c, and nu_c exact or certified in a bracket)", _args_critical,
                 cmd_critical, _print_control))
register(Command("verify", "theory against simulation: the exact verdict beside a Monte Carlo divergence "
                 "test, for a system file or every member of a family file (in parallel with --jobs or "
                 "--scheduler); exit status 1 when they disagree",
                 _args_verify, cmd_verify))
register(Command("table", "exact critical values over a parameter family as a LaTeX (booktabs) table",
                 _args_table, cmd_table, _print_table))
register(Command("simulate", "Monte Carlo E[tr P_k] with confidence intervals", _args_simulate,
                 cmd_simulate, _print_simulate))
register(Command("examples", "the shipped example systems and families; NAME copies one into the working directory",
                 _args_examples, cmd_examples, _print_examples))
register(Command("design", "design queries of a system file's [design] table: the cheapest sensor set, the front "
                 "of cost against the critical rate, the cheapest channel qualities, the most valuable upgrade",
                 _args_design, cmd_design, lambda res: print(res["_text"])))
register(Command("warm", "compile the simulation's kernels ahead (numba; once per installation), so that the "
                 "first simulate or verify of a system does not wait for it", _args_warm, cmd_warm,
                 lambda res: print(res["_text"])))
register(Command("bounds", "every published bound and closed form for the critical rate beside the exact value",
                 _args_bounds, cmd_bounds, _print_table))
register(Command("reproduce", "reproduce a paper's example: " + ", ".join(sorted(REPRODUCE)), _args_reproduce,
                 cmd_reproduce, _print_reproduce))


class _Parser(argparse.ArgumentParser):
    """argparse that reports usage errors in one line (exit status 2) instead of the usage block."""

    def error(self, message: str) -> None:  # type: ignore[override]
        raise UsageError(f"{self.prog}: {message}")


def _parser() -> argparse.ArgumentParser:
    p = _Parser(prog="symkf", description="Exact stability of multi-sensor Kalman filtering over lossy "
                "networks (Sui-You-Fu; Quevedo et al.; Yang et al.).",
                epilog="Every command takes --json (one JSON document on stdout, errors included: "
                '{"error": {...}}) and --quiet (no progress bars); FILE is a TOML file or the name of a '
                "shipped example (symkf examples lists them). Exit status: 0 success, 1 verify: theory and "
                "simulation disagree, 2 bad input or usage, 3 a theorem's assumptions fail for the system, "
                "70 internal error (a bug)")
    p.add_argument("--version", action="version", version=f"symkf {__version__}")
    sub = p.add_subparsers(dest="command", required=True, parser_class=_Parser)
    for c in COMMANDS.values():
        s = sub.add_parser(c.name, help=c.help, description=c.help)
        c.configure(s)
        for action in s._actions:   # the input file: one help text for every command
            if action.dest == "file" and action.help is None:
                action.help = FILE_HELP
        s.add_argument("--json", action="store_true", help="machine-readable output (errors too, as {\"error\": ...})")
        s.add_argument("--quiet", action="store_true", help="no progress bars (as TQDM_DISABLE=1)")
        _args_caps(s)
        s.set_defaults(command_spec=c)
    return p


#: help of every command's input file
FILE_HELP = "a system or family file (TOML), or the name of a shipped example (symkf examples lists them)"


def _input_file(file: str) -> tuple[str, str]:
    """``file`` as :func:`symkf.io.examples.resolve` finds it (a file, the local ``file.toml``, or
    the shipped example of that name), and what was read in words, for the text output."""
    from .io import examples
    try:
        path = examples.resolve(file)
    except SymkfError:
        raise UsageError(f"{file}: no such file; shipped examples are taken by name "
                         "(symkf examples lists them)") from None
    shipped = examples.directory().resolve() in path.resolve().parents
    return str(path), (f"read: shipped example {path.stem} (`symkf examples {path.stem}` copies it here)"
                       if shipped else f"read: {path}")


def _print_plain(res: dict[str, Any]) -> None:
    """A result for people: eigen-blocks and the command's own text when it has one, else every
    key in words (:func:`_words`), never JSON."""
    for words in res.get("_blocks", []):
        print("\n".join(textwrap.wrap(f"block: {words}", 100,
                                      subsequent_indent="    ", break_long_words=False, break_on_hyphens=False)))
    if "_text" in res:
        print(res["_text"])
        return
    for k, v in res.items():
        if isinstance(v, dict) and "exact" in v and "interval" in v:
            print(_exact_number_text(k, v))
        elif not k.startswith("_") and k != "blocks":
            print("\n".join(_words(k, v)))


def _exact_number_text(key: str, v: dict[str, Any]) -> str:
    """An exact number of the JSON (``exact``, ``decimal``, ``interval``, ``minpoly``) for people:
    powers as ``^``, products as ``·``, a root without a closed form named by its polynomial, the
    certified interval in decimals rounded outward (its exact rationals are in ``--json``)."""
    from .exact.text import printed_text
    poly = printed_text(v["minpoly"])
    exact = (printed_text(v["exact"]) if "CRootOf" not in v["exact"] else
             f"the root of {poly} in the certified interval" if len(poly) <= 60 else
             "the root of the minimal polynomial below in the certified interval")
    lo, hi = (Fraction(e) for e in v["interval"])
    if lo == hi:   # a rational: its value is the certificate
        return f"{key} = {exact}" + ("" if str(lo) == v["decimal"].rstrip("0").rstrip(".") else f"\n  = {v['decimal']}")
    digits = len(v["decimal"].replace("-", "").replace(".", "").lstrip("0")) + 2
    return (f"{key} = {exact}\n  ≈ {v['decimal']}\n  certified in [{_decimal(lo, digits, ROUND_FLOOR)}, "
            f"{_decimal(hi, digits, ROUND_CEILING)}] (exact rationals: --json)\n  minimal polynomial {poly}")


def _decimal(q: Fraction, digits: int, rounding: str) -> str:
    """``q`` to ``digits`` significant digits, rounded as ``rounding`` says (outward for an interval)."""
    with localcontext() as ctx:
        ctx.prec, ctx.rounding = max(digits, 1), rounding
        return format(Decimal(q.numerator) / Decimal(q.denominator), "f")


def _words(key: str, value: Any, indent: str = "", width: int = 100) -> list[str]:
    """``key: value`` as indented lines of words: nested tables as sections, lists of tables as
    numbered items, exact numbers as ``exact ~ decimal``, true/false as yes/no; long text wrapped."""
    if isinstance(value, dict) and "exact" in value and "decimal" in value:
        value = f"{value['exact']} ~ {value['decimal']}"
    if isinstance(value, dict):
        return [f"{indent}{key}:"] + [line for k, v in value.items() for line in _words(k, v, indent + "  ", width)]
    if isinstance(value, list) and any(isinstance(v, dict) for v in value):
        return [f"{indent}{key}:"] + [line for i, v in enumerate(value, 1) for line in _words(str(i), v, indent + "  ", width)]
    text = (", ".join(_scalar(v) for v in value) or "none") if isinstance(value, list) else _scalar(value)
    return textwrap.wrap(f"{key}: {text}", width, initial_indent=indent, subsequent_indent=indent + "    ",
                         break_long_words=False, break_on_hyphens=False) or [f"{indent}{key}:"]


def _scalar(value: Any) -> str:
    if isinstance(value, bool):
        return "yes" if value else "no"
    if isinstance(value, (list, tuple)):
        return "(" + ", ".join(_scalar(v) for v in value) + ")"
    return "none" if value is None else str(value)


def main(argv: Sequence[str] | None = None, *, entry_point: bool = False) -> int:
    """Run ``symkf`` with ``argv`` (default ``sys.argv[1:]``); returns the exit status.  Ctrl-C
    (SIGINT) and SIGTERM interrupt the command once (exit 130 and 143); a second one while the
    first is cleaned up is ignored.  The caller's signal handlers are restored at the end, unless
    ``entry_point`` (``symkf``, ``python -m symkf``: the process ends with the command): then both
    signals stay ignored while Python ends it (a Ctrl-C then killed the process by the signal
    instead of the exit status 130 it had returned)."""
    with _interrupted_once(restore=not entry_point):
        return _main(argv)


def _main(argv: Sequence[str] | None) -> int:
    argv = sys.argv[1:] if argv is None else list(argv)
    if not argv:
        _parser().print_help()
        return 2
    try:
        args = _parser().parse_args(argv)
    except SystemExit as exc:   # --help, --version
        return exc.code if isinstance(exc.code, int) else 2
    except Terminated:
        print("symkf: terminated (SIGTERM)", file=sys.stderr)
        return TERMINATED
    except KeyboardInterrupt:
        print("symkf: interrupted", file=sys.stderr)
        return INTERRUPTED
    except UsageError as exc:   # one line; with --json also as a JSON error (the command line is not parsed)
        print(exc, file=sys.stderr)
        if "--json" in argv:
            print(json.dumps(_error_document("UsageError", str(exc), 2), indent=2))
        return 2
    command: Command = args.command_spec
    try:
        source = None
        if isinstance(getattr(args, "file", None), str):
            args.file, source = _input_file(args.file)
        _cap_jobs(args, command.name)
        with warnings.catch_warnings(record=True) as caught, _quiet(args.quiet), budget.limits(**_caps(args)), \
                output.run(), still_working(f"symkf {command.name}", enabled=False if args.quiet else None):
            warnings.simplefilter("always")
            res = command.run(args)
        # notes for the user (e.g. a float taken as a rational) in one line each; numerical
        # RuntimeWarnings of the simulation are handled there (halved horizons) and dropped
        for w in caught:
            if not issubclass(w.category, RuntimeWarning):
                print(f"symkf {command.name}: note: {_one_line(w.message)}", file=sys.stderr)
    except SymkfError as exc:
        return _fail(args, type(exc).__name__, _located(_one_line(exc), args), exc.exit_status)
    except ValueError as exc:
        if not _digits_exceeded(exc):
            return _internal(args, exc)
        return _too_many_digits(args)
    except RecursionError:
        return _fail(args, "InputError", "input too deeply nested", 2)
    except Terminated:
        return _fail(args, "Terminated", "terminated (SIGTERM)", TERMINATED)
    except KeyboardInterrupt:
        return _fail(args, "KeyboardInterrupt", "interrupted", INTERRUPTED)
    except MemoryError:  # an estimate let through work that did not fit: input, not a bug
        return _fail(args, "MemoryError", "out of memory; lower the input's size or the caps of symkf.budget", 2)
    except Exception as exc:  # a bug, not bad input: one line and a status of its own
        return _internal(args, exc)
    try:
        if args.json:
            doc = {"schema_version": SCHEMA_VERSION, **{k: v for k, v in res.items() if not k.startswith("_")}}
            print(output.json_text(doc))
        else:
            if source is not None:
                print(source)
            (command.show or _print_plain)(res)
        sys.stdout.flush()
    except BrokenPipeError:  # e.g. `symkf demo | head`: the reader left; not an error of ours
        sys.stdout = open(os.devnull, "w")
    except ValueError as exc:
        if not _digits_exceeded(exc):
            return _internal(args, exc)
        return _too_many_digits(args)
    return res.get("_status", 0)


def _fail(args: argparse.Namespace, kind: str, message: str, status: int) -> int:
    """Report a failure in one line on stderr and, with ``--json``, as ``{"error": ...}`` on stdout."""
    print(f"symkf {args.command}: {message}", file=sys.stderr)
    if args.json:
        print(json.dumps(_error_document(kind, message, status), indent=2))
    return status


def _error_document(kind: str, message: str, status: int) -> dict[str, Any]:
    return {"schema_version": SCHEMA_VERSION, "error": {"type": kind, "message": message, "exit_status": status}}


@contextlib.contextmanager
def _interrupted_once(restore: bool) -> Iterator[None]:
    """The first SIGINT raises KeyboardInterrupt, the first SIGTERM :class:`Terminated`; any signal
    after it is ignored, so that the clean-up it starts (workers stopped, temporary files removed,
    the one-line message) runs to its end.  Afterwards the previous handlers are restored
    (``restore``), or both signals are ignored while the process ends; a signal ignored before
    stays ignored.  In the main thread only:
    a signal handler cannot be installed elsewhere."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    fired: list[int] = []

    def handler(signum: int, frame: Any) -> None:
        if fired:
            return
        fired.append(signum)
        raise Terminated() if signum == signal.SIGTERM else KeyboardInterrupt()

    # a signal ignored when the command started (a job started in the background with `&`) stays so
    previous = {s: signal.getsignal(s) for s in (signal.SIGINT, signal.SIGTERM)}
    previous = {s: h for s, h in previous.items() if h is not signal.SIG_IGN}
    for s in previous:
        signal.signal(s, handler)
    try:
        yield
    finally:
        for s, before in previous.items():
            signal.signal(s, (signal.SIG_DFL if before is None else before) if restore else signal.SIG_IGN)


@contextlib.contextmanager
def _quiet(quiet: bool) -> Iterator[None]:
    """``--quiet``: TQDM_DISABLE=1 for the command (and the worker processes it starts)."""
    previous = os.environ.get("TQDM_DISABLE")
    if quiet:
        os.environ["TQDM_DISABLE"] = "1"
    try:
        yield
    finally:
        if previous is None:
            os.environ.pop("TQDM_DISABLE", None)
        else:
            os.environ["TQDM_DISABLE"] = previous


def _internal(args: argparse.Namespace, exc: Exception) -> int:
    return _fail(args, "InternalError", f"internal error ({type(exc).__name__}: {_one_line(exc)}); "
                 "please report it", INTERNAL_ERROR)


def _one_line(exc: BaseException) -> str:
    text = _DIGIT_RUN.sub(lambda m: f"{m.group()[:6]}...({len(m.group())} digits)", " ".join(str(exc).split()))
    return text if len(text) <= 400 else text[:397] + "..."


#: a run of digits too long to show in a one-line message
_DIGIT_RUN = re.compile(r"\d{31,}")


#: the entries of errors about sweep arguments (symkf.run.sweep) named by their Python keywords,
#: and the options that gave them on the command line
_OPTION_ENTRIES = {"scheduler: ": "--scheduler: ", "jobs and scheduler: ": "--jobs and --scheduler: "}


def _located(message: str, args: argparse.Namespace) -> str:
    """``message`` prefixed by the command's input file when it does not name it already (an
    error found while computing, e.g. a theorem's assumption, after the file was read); an error
    about an output names its option and file instead, one about the Dask scheduler its option
    after the input file."""
    for keyword, option in _OPTION_ENTRIES.items():
        if message.startswith(keyword):
            message = option + message[len(keyword):]
    file = getattr(args, "file", None)
    if file is None or str(file) in message or message.startswith("--") and not message.startswith(
            tuple(_OPTION_ENTRIES.values())):
        return message
    return f"{file}: {message}"


def _too_many_digits(args: argparse.Namespace) -> int:
    message = (f"a number computed from the input has more than {sys.get_int_max_str_digits()} digits, the most "
               f"converted to text under {budget.OPTIONS['max_digits']} {budget.LIMITS.max_digits}")
    return _fail(args, "BudgetError", f"{_located(message, args)}; give smaller numbers or raise "
                 f"{budget.OPTIONS['max_digits']}", 2)


def _digits_exceeded(exc: ValueError) -> bool:
    """Whether ``exc`` is Python's refusal to convert an integer of too many digits to text."""
    return "integer string conversion" in str(exc)

check_public(globals())


if __name__ == "__main__":  # pragma: no cover
    raise SystemExit(main())
