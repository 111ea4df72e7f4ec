"""Figures (the optional ``plot`` extra): exact boundaries with simulation overlaid.

* :func:`stability_region_figure`: the region of mean-square stability of two
  sensors in the ``(loss_1, loss_2)`` plane under i.i.d. losses, its boundary
  the exact piecewise curve of :func:`symkf.engine.region.stability_region`
  (Sui-You-Fu Theorems 4/7, eq. 36), Monte Carlo verdicts overlaid;
* :func:`mean_trace_figure`: ``E[tr P_k]`` against ``k`` (Monte Carlo with its
  confidence band), the exact growth rate, and Yang et al.'s lower bound
  ``G_k`` (Proposition 1, eq. 13) and upper bound ``V_k`` (Theorem 3, eq. 18);
* :func:`critical_angle_figure`: the critical loss rate of ``A = r R(theta)``
  against the rotation angle ``theta``.

Each returns a :class:`matplotlib.figure.Figure` (no pyplot state, no backend
change) and writes a PNG when ``path`` is given.  matplotlib is imported
lazily; without it :class:`PlotExtraError` (exit status 2 on the command line).
"""

from __future__ import annotations

import os
import sys
from fractions import Fraction
from math import gcd
from typing import Any, Sequence

import numpy as np
import sympy as sp

from .. import budget, output
from ..arguments import check_public, count
from ..exact.algebraic import sign
from ..errors import ExtraNotInstalledError, InputError, SymkfError
from ..exact.numbers import to_exact
from ..model.iid import IID
from ..model.loss import LossModel
from ..model.system import Sensor, System
from ..numeric.montecarlo import MeanTraceCurve
from ..numeric.simulation import Simulation
from ..run.progress import progress

VERDICT_STYLE = {"stable": ("o", "tab:green"), "unstable": ("x", "tab:red"), "undecided": ("s", "tab:gray")}


class PlotExtraError(ExtraNotInstalledError):
    """matplotlib (the ``plot`` extra) is not installed."""


def require_matplotlib() -> None:
    """Raise :class:`PlotExtraError` unless matplotlib can be imported."""
    try:
        import matplotlib  # noqa: F401
    except ImportError:
        raise PlotExtraError("plotting needs matplotlib: pip install 'symkf[plot]'") from None


def new_figure(width: float = 6.4, height: float = 4.8) -> Any:
    """A matplotlib figure of ``width`` x ``height`` inches (each in (0, 200]), without pyplot."""
    sizes = []
    for name, size in (("width", width), ("height", height)):
        inches = float(size)
        if not 0 < inches <= 200:
            raise InputError(f"{name}: expected a figure size in inches in (0, 200], got {size!r}")
        sizes.append(inches)
    require_matplotlib()
    from matplotlib.figure import Figure
    _inline_in_jupyter(Figure)
    return Figure(figsize=tuple(sizes), layout="constrained")


def _inline_in_jupyter(figure_type: type) -> None:
    """Figures display as images in a Jupyter kernel: IPython registers its figure formatter only
    once pyplot is imported, and these figures are made without pyplot."""
    ipython = sys.modules.get("IPython")
    shell = ipython.get_ipython() if ipython is not None else None
    if shell is not None:
        from IPython.core.pylabtools import print_figure
        shell.display_formatter.formatters["image/png"].for_type(figure_type, lambda fig: print_figure(fig, "png"))


def _math_label(exact: sp.Expr, limit: int = 60) -> str:
    """An exact number for a legend or title: matplotlib math (``$\\frac{\\sqrt{6}}{2} \\approx
    1.2247$``) when its LaTeX is at most ``limit`` characters, else the decimal alone; never
    SymPy's ``243*167**(3/4)``."""
    decimal = f"{float(exact):.5g}"
    latex = sp.latex(exact)
    if exact.is_Integer:
        return latex
    return rf"${latex} \approx {decimal}$" if len(latex) <= limit and not exact.has(sp.CRootOf) else f"≈ {decimal}"


def figure_target(path: Any) -> Any:
    """The output of a figure function, checked before its work (:func:`symkf.output.plan`): None
    when no ``path`` is given."""
    return None if path is None else output.plan(path, "path")


def finish_figure(fig: Any, target: output.Planned | None) -> Any:
    """Write ``fig`` to ``target`` (:func:`figure_target`), atomically; returns the figure."""
    if not hasattr(fig, "savefig"):
        raise InputError(f"fig: expected a matplotlib figure, got {type(fig).__name__}")
    if target is not None:
        target.put_figure(fig, dpi=110)
    return fig


def _grid(count: int, entry: str) -> list[Fraction]:
    if not isinstance(count, int) or count < 2:
        raise InputError(f"{entry}: expected an integer >= 2, got {count!r}")
    return [Fraction(i, count + 1) for i in range(1, count + 1)]


def region_boundary(system: System, samples: int = 60) -> tuple[np.ndarray, np.ndarray]:
    """Points ``(eps_1, f(eps_1))`` of the exact critical curve of two sensors, for drawing.

    The pieces of :meth:`symkf.engine.region.StabilityRegion.boundary` (exact laws
    between exact breakpoints) are each sampled at ``samples`` points
    including both ends, so jumps between pieces appear as vertical edges.
    """
    from ..engine.region import stability_region

    if system.d != 2:
        raise InputError(f"system: the region figure needs exactly 2 sensors, the system has {system.d}")
    if not isinstance(samples, int) or samples < 2:
        raise InputError(f"samples: expected an integer >= 2, got {samples!r}")
    region = stability_region(system)
    e1 = region.symbols[0]
    xs, ys = [], []
    for piece in region.boundary():
        x = np.linspace(float(piece.lo), float(piece.hi), samples)
        f = sp.lambdify(e1, piece.expr, "numpy")
        xs.append(x)
        ys.append(np.broadcast_to(np.asarray(f(x), dtype=float), x.shape))
    return np.concatenate(xs), np.minimum(np.concatenate(ys), 1.0)


def stability_region_figure(system: System, *, samples: int = 60, mc_points: int = 4,
                            paths: int = 20_000, horizon: int = 120, seed: int = 0, path: Any = None) -> Any:
    """The stable set ``{(loss_1, loss_2)}`` of a two-sensor system under i.i.d. losses.

    Boundary: the exact critical curve ``loss_2 = f(loss_1)`` (stable iff
    ``loss_2 < f(loss_1)``; :func:`region_boundary`).  Overlay: on an
    ``mc_points`` x ``mc_points`` grid, the verdict of
    :func:`symkf.numeric.verify.simulated_verdict` (final-burst importance sampling steered
    by the exact decisive pattern) with ``paths``, ``horizon``, ``seed``, judged
    against the exact verdict by :func:`symkf.numeric.verify.judge`; contradictions are circled.
    """
    target = figure_target(path)   # checked before the work
    from ..engine.stability import stability
    from ..numeric.verify import judge, simulated_verdict

    x, y = region_boundary(system, samples)
    mc = _grid(mc_points, "mc_points")
    verdicts = []
    with progress(len(mc) ** 2, "region") as bar:
        for l1 in mc:
            for l2 in mc:
                loss = IID([sp.Rational(l1), sp.Rational(l2)])
                v = stability(system, loss)
                sim = simulated_verdict(system, loss, v, seed=seed, paths=paths, horizon=horizon)
                verdicts.append((float(l1), float(l2), sim["verdict"], judge(v, sim)["outcome"]))
                bar.update()
    fig = new_figure()
    ax = fig.add_subplot()
    ax.fill_between(x, 0, y, color="tab:green", alpha=0.15, label="stable (exact)")
    ax.plot(x, y, "-", color="tab:green", lw=1.5, label="exact critical curve")
    for kind, (marker, color) in VERDICT_STYLE.items():
        pts = [(a, b) for a, b, s, _ in verdicts if s == kind]
        if pts:
            ax.scatter(*zip(*pts), marker=marker, color=color, s=50, label=f"Monte Carlo: {kind}")
    wrong = [(a, b) for a, b, _, outcome in verdicts if outcome == "contradiction"]
    if wrong:
        ax.scatter(*zip(*wrong), marker="o", facecolors="none", edgecolors="black", s=160,
                   label="simulation contradicts theory")
    names = system.sensor_names
    ax.set(xlim=(0, 1), ylim=(0, 1.02), xlabel=f"loss probability of {names[0]}",
           ylabel=f"loss probability of {names[1]}",
           title=f"Where the filter is mean-square stable: exact region and simulation\n"
                 f"({paths} paths per run, horizon {horizon}, seed {seed})")
    ax.legend(loc="upper right", fontsize="small")
    return finish_figure(fig, target)


def yang_bounds(system: System, loss: LossModel, horizon: int) -> tuple[np.ndarray, np.ndarray]:
    """``tr G_{k+1}`` and ``tr V_{k+1}``, k = 0..horizon-1: bounds of ``E[tr P_{k|k-1}]`` (Yang et al.).

    Yang et al. index the first prediction ``P_1^-``, which is ``P_{0|-1} = P0`` here.
    """
    from ..capacity import MARE, lower_bound_sequence
    G = lower_bound_sequence(system, loss, horizon)
    V = MARE(system, loss).sequence(horizon)
    return np.array([np.trace(g) for g in G]), np.array([np.trace(v) for v in V])


def simulation_figure(sim: Simulation, *, path: Any = None) -> Any:
    """The ``symkf simulate --plot`` figure of a :class:`~symkf.numeric.simulation.Simulation` run
    with ``curve=True``: :func:`mean_trace_figure` of its system, loss model and curve."""
    if sim.curve is None:
        raise InputError("curve: this simulation has no importance-sampled curve; pass curve=True to simulate")
    return mean_trace_figure(sim.system, sim.loss, sim.curve, path=path)


def mean_trace_figure(system: System, loss: LossModel, curve: MeanTraceCurve, *, path: Any = None) -> Any:
    """``log10 E[tr P_{k|k-1}]`` against ``k``: estimate with its band, the exact growth rate as a
    slope through the estimate, and (i.i.d. losses) Yang's bounds ``tr G_k`` and ``tr V_k``.

    The estimate is :func:`symkf.numeric.montecarlo.mean_trace_curve` (final-burst importance
    sampling, log-scale filter), so the curve shows the growth the theory predicts instead of
    the typical path.  The exact line has slope ``log10 r`` (``r = max alpha_i^2 rho_i`` when
    unstable, 1 when stable) and passes through the mean of ``log E_k - k log r`` over the
    second half of the steps.  Parts whose theory does not apply are left out and the
    reason is put in the title.
    """
    target = figure_target(path)   # checked before the work
    from ..engine.stability import stability
    from ..numeric.montecarlo import exact_growth_rate

    fig = new_figure()
    ax = fig.add_subplot()
    k = curve.ks
    ln10 = np.log(10)
    low, high = curve.band()
    ax.plot(k, curve.log_mean / ln10, "o-", color="tab:blue", ms=3,
            label=f"simulation ({curve.paths} paths per point, seed {curve.seed})")
    ax.fill_between(k, low / ln10, high / ln10, color="tab:blue", alpha=0.25,
                    label=f"{100 * curve.confidence:g}% interval")
    notes = []
    try:
        v = stability(system, loss)
        r = exact_growth_rate(v)
        half = k >= k[-1] / 2
        slope = np.log(float(r))
        anchor = float(np.mean(curve.log_mean[half] - k[half] * slope))
        ax.plot(k, (anchor + k * slope) / ln10, "--", color="black",
                label=f"exact growth rate {_math_label(r.exact)} per step ({'stable' if v.stable else 'not stable'})")
    except SymkfError as exc:
        notes.append(f"no exact rate: {exc}".splitlines()[0][:70])
    if curve.float_cap is not None:
        notes.append(f"stops at k = {int(k[-1])} of {curve.requested}: float64 limit (montecarlo.float_horizon)")
    if loss.bernoulli is not None:  # Yang's bounds are stated for i.i.d. losses only: otherwise not drawn
        try:
            G, V = yang_bounds(system, loss, int(k[-1]) + 1)
            with np.errstate(divide="ignore", invalid="ignore"):
                ax.plot(k, np.log10(G[k]), ":", color="tab:purple", label="Yang lower bound tr $G_k$")
                ax.plot(k, np.log10(V[k]), "-.", color="tab:orange", label="Yang upper bound tr $V_k$")
        except SymkfError as exc:
            notes.append(f"no Yang bounds: {exc}".splitlines()[0][:70])
    name = system.name or "the system"
    ax.set(xlabel="step k", ylabel=r"$\log_{10}$ E[tr $P_{k|k-1}$]",
           title="\n".join(["Growth of the expected error covariance:", f"{name} under {loss.words()}",
                             "importance sampling of final loss bursts" if "burst" in curve.sampling
                             else "plain Monte Carlo"] + notes))
    ax.title.set_fontsize("small")
    ax.legend(fontsize="small")
    return finish_figure(fig, target)


def rotation_system(scale: Any, angle: Any, C: Sequence[Sequence[Any]] = ((1, 0),)) -> System:
    """``A = scale [[cos t, -sin t], [sin t, cos t]]`` with ``t = angle`` (exact), sensor ``C``."""
    r, t = to_exact(scale, "scale"), to_exact(angle, "angle", algebraic=False)
    return System(A=[[r * sp.cos(t), -r * sp.sin(t)], [r * sp.sin(t), r * sp.cos(t)]],
                  sensors=[Sensor(C=[list(row) for row in C])])


def rational_angles(max_denominator: int) -> list[Fraction]:
    """Fractions ``p/q`` in (0, 1) in lowest terms with ``q <= max_denominator``, increasing."""
    max_denominator = count(max_denominator, "max_denominator")
    budget.check("max_members", max_denominator * (max_denominator - 1) // 2, "max_denominator",
                 f"the number of fractions p/q with q <= {max_denominator} (before lowest terms)")
    return sorted(Fraction(p, q) for q in range(2, max_denominator + 1) for p in range(1, q) if gcd(p, q) == 1)


def critical_angle_figure(scale: Any = 2, *, max_denominator: int = 6, C: Sequence[Sequence[Any]] = ((1, 0),),
                          path: str | os.PathLike | None = None) -> Any:
    """The exact critical common loss rate of ``A = scale R(pi p/q)`` against the angle ``pi p/q``.

    At a rational angle the block is periodic and rows ``C A^k`` repeat
    direction with the governing period; an aperiodic rotation (``cos t =
    3/5``, proved aperiodic) is shown for comparison: its critical rate is
    ``1/scale^2``.
    """
    target = figure_target(path)   # checked before the work
    from ..engine.stability import critical_loss_rate

    scale = to_exact(scale, "scale")
    if sign(scale) <= 0:
        raise InputError(f"scale: expected the rotation's modulus, a positive number, got {scale}")
    angles = rational_angles(max_denominator)
    if not angles:
        raise InputError(f"max_denominator: expected an integer >= 2, got {max_denominator!r}")
    with progress(len(angles) + 1, "angles") as bar:
        values = []
        for f in angles:
            values.append(float(critical_loss_rate(rotation_system(scale, sp.pi * sp.Rational(f.numerator,
                                                                                             f.denominator), C))))
            bar.update()
        aperiodic = sp.acos(sp.Rational(3, 5))
        generic = float(critical_loss_rate(rotation_system(scale, aperiodic, C)))
        bar.update()
    fig = new_figure()
    ax = fig.add_subplot()
    x = [float(f) * np.pi for f in angles]
    ax.vlines(x, 0, values, color="tab:blue", lw=0.8)
    ax.plot(x, values, "o", color="tab:blue", label=r"$\theta = \pi p/q$ (periodic)")
    for xi, f, yv in zip(x, angles, values):
        ax.annotate(f"{f.numerator}/{f.denominator}", (xi, yv), textcoords="offset points", xytext=(0, 5),
                    ha="center", fontsize="x-small")
    ax.plot([float(aperiodic)], [generic], "D", color="tab:red", label=r"$\cos\theta = 3/5$ (aperiodic)")
    ax.axhline(1 / float(scale) ** 2, color="tab:red", ls=":", lw=1,
               label=f"1/scale$^2$ = {_math_label(1 / scale ** 2)}")
    rows = "; ".join(r"\ ".join(sp.latex(to_exact(v, "C")) for v in row) for row in C)
    ax.set(xlim=(0, np.pi), ylim=(0, 1.1 * max(values + [generic])), xlabel=r"rotation angle $\theta$",
           ylabel="critical common i.i.d. loss rate",
           title=rf"$A = {sp.latex(scale)}\,R(\theta)$, $C = [{rows}]$: exact critical loss")
    ax.legend(fontsize="small", loc="lower right")
    return finish_figure(fig, target)

check_public(globals())
