"""The examples of Quevedo, Ahlén, Johansson, each as ``reproduce_<name>() -> dict``.

Every claim the paper makes about an example that symkf verifies is a key of ``checks``
(see :mod:`symkf.reproduction`).
"""

from __future__ import annotations

import itertools
import os
from fractions import Fraction
from typing import Any

import numpy as np
import sympy as sp

from ..arguments import check_public
from .. import output
from ..exact.linalg import rank
from ..model.system import Sensor, System
from ..reproduction import reproduction
from .conditions import full_rank_configurations, full_rank_probability, theorem1
from .dynamics import PeriodicDynamics, certified_less_than_one, spectral_norm_squared
from .loss import NetworkLoss, phi_symbol
from .semi_markov import rank_deficiency_probabilities, rank_deficiency_probability_by_enumeration, theorem2
from .state import MarkovNetworkState, SemiMarkovNetworkState
from .tree import SensorTree

PAPER = "Quevedo, Ahlén, Johansson, State estimation over sensor networks with correlated wireless fading channels"

#: Example 3 as printed: J and Pr{r = 1 | Xi = j} (phi_m stands for phi_{m|j}).
EXAMPLE3_J = ((0, 1, 0, 1, 1), (0, 1, 1, 1, 1), (1, 1, 0, 0, 1), (1, 1, 0, 1, 0), (1, 1, 0, 1, 1),
              (1, 1, 1, 0, 0), (1, 1, 1, 0, 1), (1, 1, 1, 1, 0), (1, 1, 1, 1, 1))


def example3_printed_polynomial(j: int = 1) -> sp.Expr:
    """The nine-term polynomial printed after J in Example 3."""
    p1, p2, p3, p4, p5 = (phi_symbol(m, j) for m in range(1, 6))
    return ((1 - p1) * p2 * (1 - p3) * p4 * p5 + (1 - p1) * p2 * p3 * p4 * p5
            + p1 * p2 * (1 - p3) * (1 - p4) * p5 + p1 * p2 * (1 - p3) * p4 * (1 - p5)
            + p1 * p2 * (1 - p3) * p4 * p5 + p1 * p2 * p3 * (1 - p4) * (1 - p5)
            + p1 * p2 * p3 * (1 - p4) * p5 + p1 * p2 * p3 * p4 * (1 - p5) + p1 * p2 * p3 * p4 * p5)


def _s(x: Any) -> str:
    return str(x)


def _interval(b: tuple[Fraction, Fraction]) -> list[str]:
    return [f"{float(b[0]):.12g}", f"{float(b[1]):.12g}"]


def _plot(outdir: str | None, name: str, draw) -> str | None:
    if outdir is None:
        return None
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(5, 4))
    draw(ax)
    fig.tight_layout()
    path = str(output.save_figure(fig, os.path.join(output.plan_directory(outdir, "outdir"), name), "outdir", dpi=120))
    plt.close(fig)
    return path


# -- Example 3 --------------------------------------------------------------------------

def example3_tree() -> SensorTree:
    """Fig. 4: S1, S2 -> S0; S3 -> S1; S4, S5 -> S2."""
    return SensorTree([0, 0, 1, 2, 2])


def example3_dynamics() -> PeriodicDynamics:
    """A stated plant for Example 3: n = 3, C_m = [1, m, m^2], so any three sensors give full rank."""
    return PeriodicDynamics(sp.diag(sp.Rational(11, 10), 1, sp.Rational(9, 10)),
                            [[[1, m, m * m]] for m in range(1, 6)])


def reproduce_quevedo_example3(outdir: str | None = None) -> dict:
    """Example 3 (Sec. V): J for "at least three measurements reach the gateway" and Pr{r = 1 | Xi}."""
    if outdir is not None:   # refused before the work, not after it
        output.plan_directory(outdir, "outdir")
    tree = example3_tree()
    J_rule = full_rank_configurations(tree, rule=lambda theta: sum(theta) >= 3)
    dyn = example3_dynamics()
    J_rank = full_rank_configurations(tree, dyn)
    symbolic = NetworkLoss(tree, MarkovNetworkState([[1]]), "symbols")
    prob = full_rank_probability(J_rank, list(symbolic.phi.col(0)))
    printed = example3_printed_polynomial(1)
    # Remark 2: theta_1 and theta_3 share link E_1, so they are dependent given Xi.
    law = symbolic.link_law(1)
    th = {g: tree.theta(g) for g in law}
    p13 = sp.expand(sum(p for g, p in law.items() if th[g][0] and th[g][2]))
    p1 = sp.expand(sum(p for g, p in law.items() if th[g][0]))
    p3 = sp.expand(sum(p for g, p in law.items() if th[g][2]))
    # Example 2 / Theorem 1 on a stated two-state network: links E1, E2 obstructed in state 2.
    state = MarkovNetworkState([["9/10", "1/10"], ["3/10", "7/10"]])
    phi = [["19/20", "1/2"], ["19/20", "1/2"], ["19/20", "19/20"], ["19/20", "19/20"], ["19/20", "19/20"]]
    t1 = theorem1(NetworkLoss(tree, state, phi), dyn)
    common = sp.Symbol("phi", positive=True)
    curve = sp.expand(prob.subs({phi_symbol(m, 1): common for m in range(1, 6)}))

    def draw(ax):
        xs = np.linspace(0, 1, 201)
        f = sp.lambdify(common, curve, "numpy")
        ax.plot(xs, f(xs))
        ax.set_xlabel(r"common link success probability $\phi$")
        ax.set_ylabel(r"Pr{r(k)=1 | $\Xi$}")
        ax.set_title("Example 3 (Fig. 4 tree)")

    png = _plot(outdir, "quevedo_example3.png", draw)
    return reproduction(
        "quevedo-example3", f"{PAPER}, Sec. V, Example 3 and Fig. 4",
        {
            "tree_parents": list(tree.parents),
            "configurations": [list(g) for g in J_rank],
            "rank_plant": {"A": _s(dyn.A[0].tolist()), "C": [_s(c.tolist()) for c in dyn.C]},
            "probability_full_rank": _s(prob),
            "probability_full_rank_expanded": _s(sp.expand(prob)),
            "probability_common_phi": _s(sp.factor(curve)),
            "theorem1_instance": {"P": _s(state.P.tolist()), "phi": phi, "nu": [_s(v) for v in t1.nu],
                                  "norm_A_squared": _s(t1.norms[0].exact),
                                  "rho": _s(t1.rho.exact), "rho_decimal": _s(t1.rho.evalf(12)),
                                  "holds": t1.holds},
            "figure": png,
        },
        {
            "J has nine vectors": len(J_rank) == 9,
            "J (exact rank of C(k)) equals the printed J": J_rank == EXAMPLE3_J,
            "J (rule: at least three measurements) equals the printed J": J_rule == EXAMPLE3_J,
            "printed Pr{r=1|Xi=j} equals the sum over J": sp.expand(prob - printed) == 0,
            "Remark 2: theta_1, theta_3 dependent given Xi": sp.expand(p13 - p1 * p3) != 0,
            "Remark 2: Pr{theta_m=1|Xi=j} = product of phi over Edge(Path(S_m))":
                p3 == sp.expand(phi_symbol(1, 1) * phi_symbol(3, 1)),
        })


# -- Example 4: the robot ---------------------------------------------------------------

ROBOT_Q = [["4/5", "1/10", 0, "1/10"], ["1/2", "3/10", "1/10", "1/10"],
           [0, "1/5", "1/2", "3/10"], ["3/5", "1/5", "1/10", "1/10"]]
ROBOT_HOLDING = [{30: 1}, {d: sp.Rational(1, 8) for d in range(1, 9)},
                 {d: sp.Rational(1, 8) for d in range(1, 9)}, {d: sp.Rational(1, 6) for d in range(5, 11)}]


def robot_network() -> tuple[SensorTree, PeriodicDynamics, list[list[str]]]:
    """The stated network for Example 4 (the paper gives none).

    S1 (C = [1 0]) and the relay S2 (C = 0) talk to the gateway; S3 (C = [0 1])
    and S4 (C = [1 1]) reach it through S2.  A = [[21/20, 1/10], [0, 1]].
    Robot positions: 1 home (all links 9/10), 2 shadows E1 (1/10),
    3 shadows the relay link E2 (1/10), 4 all links 7/10.
    """
    tree = SensorTree([0, 0, 2, 2])
    dyn = PeriodicDynamics([["21/20", "1/10"], [0, 1]], [[[1, 0]], [[0, 0]], [[0, 1]], [[1, 1]]])
    phi = [["9/10", "1/10", "9/10", "7/10"], ["9/10", "9/10", "1/10", "7/10"],
           ["9/10", "9/10", "9/10", "7/10"], ["9/10", "9/10", "9/10", "7/10"]]
    return tree, dyn, phi


def reproduce_quevedo_robot(outdir: str | None = None) -> dict:
    """Example 4 (Sec. VII-A): the four-state semi-Markov robot model and Theorem 2's left-hand side."""
    if outdir is not None:   # refused before the work, not after it
        output.plan_directory(outdir, "outdir")
    tree, dyn, phi = robot_network()
    state = SemiMarkovNetworkState(ROBOT_Q, ROBOT_HOLDING)
    loss = NetworkLoss(tree, state, phi)
    t2 = theorem2(loss, dyn)
    markov = NetworkLoss(tree, MarkovNetworkState(ROBOT_Q), phi)
    t1 = theorem1(markov, dyn)
    t2m = theorem2(NetworkLoss(tree, markov.state.as_semi_markov(), phi), dyn)
    reduces = all(sp.simplify(t2m.lhs[(i, 0)] - t1.lhs[(i, 0)]) == 0 for i in range(1, 5))
    reduces_paper = all(sp.simplify(t2m.lhs_paper[(i, 0)] - t1.lhs[(i, 0)]) == 0 for i in range(1, 5))
    from ..engine.stability import stability
    exact = stability(System(dyn.A[0], [Sensor(c) for c in dyn.C]), loss)  # symkf's extension, docs/quevedo.md
    worst = max(t2.bounds, key=lambda k: t2.bounds[k][1])
    worst_paper = max(t2.bounds_paper, key=lambda k: t2.bounds_paper[k][1])

    def draw(ax):
        for j in range(1, 5):
            ax.semilogy(range(1, 31), [max(float(v), 1e-300) for v in t2.pi[(j, 0)]], label=f"Xi = {j}")
        ax.set_xlabel(r"holding time $\delta$")
        ax.set_ylabel(r"Pr{O not full rank | $\Xi$ = j, $\Delta$ = $\delta$}")
        ax.legend()
        ax.set_title("Example 4 robot network")

    png = _plot(outdir, "quevedo_robot.png", draw)
    return reproduction(
        "quevedo-robot", f"{PAPER}, Sec. VII-A, Example 4 and Fig. 1 (sensor network stated by symkf)",
        {
            "q": ROBOT_Q,
            "holding": {str(i + 1): {str(d): _s(p) for d, p in h.items()} for i, h in enumerate(state.holding)},
            "sigma": state.sigma,
            "network": {"parents": list(tree.parents), "A": _s(dyn.A[0].tolist()),
                        "C": [_s(c.tolist()) for c in dyn.C], "phi[m][j]": phi},
            "lifted_chain_states": len(loss.chain.states),
            "theorem2_lhs_corrected": {str(i): _interval(t2.bounds[(i, 0)]) for i in range(1, 5)},
            "theorem2_lhs_as_printed": {str(i): _interval(t2.bounds_paper[(i, 0)]) for i in range(1, 5)},
            "worst_previous_state": worst[0], "worst_previous_state_as_printed": worst_paper[0],
            "holds_corrected": t2.holds, "holds_as_printed": t2.holds_paper,
            "pi_j(sigma)": {str(j): f"{float(t2.pi[(j, 0)][-1]):.6g}" for j in range(1, 5)},
            "exact_verdict": {"stable": exact.stable,
                              "margins": [_interval(m.refine(sp.Rational(1, 10 ** 12)).interval) for m in exact.margins],
                              "margin_minpoly_degrees": [m.minpoly.degree() for m in exact.margins]},
            "figure": png,
        },
        {
            "lifted chain (Xi, holding counter, theta) is stochastic":
                all(sp.simplify(x - 1) == 0 for x in loss.chain.P * sp.ImmutableMatrix.ones(len(loss.chain.states), 1)),
            "sigma = 30 (psi_1 is a point mass at 30)": state.sigma == 30,
            "Sec. VII-B: with q = p and psi(1) = 1, (32) reduces to (22)": reduces and reduces_paper,
            "the exact verdict (irreducible lifted chain, 560 states) agrees: stable": exact.stable,
        })


# -- Section VII-C ----------------------------------------------------------------------

VIIC_A = [["5/4", 0], [1, "11/10"]]
VIIC_C1 = [[1, 1]]
VIIC_HOLDING = [{d: sp.Rational(1, 5) for d in range(1, 6)}, {d: sp.Rational(1, 7) for d in range(1, 8)}]


def viic_printed_condition(i: int, q: sp.MatrixBase, norms: list[sp.Expr], mu: list[sp.Expr]) -> sp.Expr:
    """The displayed left-hand side after (34) (``norms[d-1] = ||A^d||^2``, ``mu[d-1] = mu_i(d)``)."""
    qi1, qi2 = q[i - 1, 0], q[i - 1, 1]
    return ((qi1 / 5 + qi2 / 7) * (norms[0] + sum(norms[d - 1] * mu[d - 1] for d in range(2, 6)))
            + qi2 / 7 * sum(norms[d - 1] * mu[d - 1] for d in range(6, 8)))


def _viic_lhs_numeric(norms: list[float]):
    """Fast float versions of (32) as printed and as corrected for Sec. VII-C (plots only)."""
    def pi(f, d):
        return 1.0 if d == 1 else (1 - f) ** d + d * (1 - f) ** (d - 1) * f

    def lhs(f1, f2, q, corrected):
        best = 0.0
        for i in range(2):
            s = 0.0
            for d in range(1, 8):
                psi = (0.2 if d <= 5 else 0.0, 1 / 7)
                pis = (pi(f1, d), pi(f2, d))
                if corrected:
                    s += sum(q[i][j] * psi[j] * pis[j] for j in range(2)) * norms[d - 1]
                else:
                    s += (sum(q[i][j] * pis[j] for j in range(2))
                          * sum(q[i][j] * psi[j] for j in range(2)) * norms[d - 1])
            best = max(best, s)
        return best
    return lhs


def reproduce_quevedo_semi_markov(outdir: str | None = None, simulate: bool = True) -> dict:
    """Sec. VII-C: one sensor, two network states with uniform holding times on 1..5 and 1..7."""
    if outdir is not None:   # refused before the work, not after it
        output.plan_directory(outdir, "outdir")
    dyn = PeriodicDynamics(VIIC_A, [VIIC_C1])
    A, C1 = dyn.A[0], dyn.C[0]
    invertible = {r: (C1.col_join(C1 * A ** r)).det() != 0 for r in range(1, 7)}
    q = sp.Matrix(2, 2, sp.symbols("q11 q12 q21 q22", nonnegative=True))
    qs = [[q[0, 0], 1 - q[0, 0]], [q[1, 0], 1 - q[1, 0]]]
    sym = NetworkLoss(SensorTree([0]), SemiMarkovNetworkState([[sp.Rational(1, 2)] * 2] * 2, VIIC_HOLDING),
                      "symbols")
    f = [phi_symbol(1, 1), phi_symbol(1, 2)]
    pis = {j: rank_deficiency_probabilities(sym, dyn, j, 7) for j in (1, 2)}
    eq34 = all(sp.expand(pis[j][d - 1] - ((1 - f[j - 1]) ** d + d * (1 - f[j - 1]) ** (d - 1) * f[j - 1])) == 0
               for j in (1, 2) for d in range(2, 8)) and all(pis[j][0] == 1 for j in (1, 2))
    # "varrho = 0 iff at most one packet arrives": every gamma sequence, delta <= 7, exact ranks
    varrho_claim = all(
        (rank(sp.Matrix.vstack(*[g[t] * C1 * A ** t for t in range(d)])) < 2) == (sum(g) <= 1)
        for d in range(1, 8) for g in itertools.product((0, 1), repeat=d))
    enum_agrees = all(sp.expand(rank_deficiency_probability_by_enumeration(sym, dyn, 1, d) - pis[1][d - 1]) == 0
                      for d in range(1, 6))
    norms = [spectral_norm_squared(A ** d) for d in range(1, 8)]
    psi = [[sp.Rational(1, 5) if d <= 5 else 0 for d in range(1, 8)], [sp.Rational(1, 7)] * 7]
    coeff_printed, coeff_corrected, display_ok = {}, {}, True  # (32) = sum_d coeff[d] ||A^d||^2
    for i in (1, 2):
        qi = qs[i - 1]
        mu = [sp.expand(sum(qi[j] * pis[j + 1][d - 1] for j in range(2))) for d in range(1, 8)]
        coeff_printed[i] = [mu[d - 1] * sum(psi[j][d - 1] * qi[j] for j in range(2)) for d in range(1, 8)]
        coeff_corrected[i] = [sum(qi[j] * psi[j][d - 1] * pis[j + 1][d - 1] for j in range(2))
                              for d in range(1, 8)]
        display = viic_printed_condition(i, sp.Matrix(qs), [n.exact for n in norms], mu)
        eq32 = sum(c * n.exact for c, n in zip(coeff_printed[i], norms))
        display_ok &= sp.expand(eq32 - display) == 0
    # Stated instance: q_ij = 1/2, phi on the diagonal: the exact boundary of the region by bisection
    half = {q[0, 0]: sp.Rational(1, 2), q[1, 0]: sp.Rational(1, 2)}

    def holds(coeff, a, b):
        vals = {f[0]: a, f[1]: b, **half}
        return all(certified_less_than_one([sp.expand(c.subs(vals)) for c in coeff[i]], norms) for i in (1, 2))

    def boundary(coeff):
        lo, hi = sp.Rational(0), sp.Rational(1)  # fails at 0, holds at 1
        while hi - lo > sp.Rational(1, 2 ** 20):
            mid = (lo + hi) / 2
            lo, hi = (lo, mid) if holds(coeff, mid, mid) else (mid, hi)
        return lo, hi

    b_printed, b_corrected = boundary(coeff_printed), boundary(coeff_corrected)
    # a point where (32) as printed holds but the corrected condition fails
    witness = (sp.Rational(43, 50), sp.Rational(191, 200))
    w_printed, w_corrected = holds(coeff_printed, *witness), holds(coeff_corrected, *witness)
    fnum = _viic_lhs_numeric([float(n) for n in norms])
    grid = np.linspace(0.8, 1, 81)
    qf = [[0.5, 0.5], [0.5, 0.5]]
    region_p = np.array([[fnum(a, b, qf, False) < 1 for a in grid] for b in grid])
    region_c = np.array([[fnum(a, b, qf, True) < 1 for a in grid] for b in grid])

    def draw(ax):
        ax.contour(grid, grid, region_p.astype(float), levels=[0.5], colors="C0")
        ax.contour(grid, grid, region_c.astype(float), levels=[0.5], colors="C1", linestyles="--")
        ax.plot([], [], "C0", label="(32) as printed")
        ax.plot([], [], "C1--", label="(32) corrected")
        ax.plot(*[float(v) for v in witness], "kx")
        ax.set_xlabel(r"$\phi_{1|1}$")
        ax.set_ylabel(r"$\phi_{1|2}$")
        ax.set_title(r"Sec. VII-C, $q_{ij}=1/2$: condition holds above/right")
        ax.legend()

    png = _plot(outdir, "quevedo_semi_markov.png", draw)
    results = {
        "A": VIIC_A, "C1": VIIC_C1, "holding": "psi_1 uniform on 1..5, psi_2 uniform on 1..7",
        "invertible_C1_C1Ar": {str(r): v for r, v in invertible.items()},
        "pi_j(delta)": {str(j): [_s(sp.factor(p)) for p in pis[j]] for j in (1, 2)},
        "norm_A_delta_squared": [_s(n.exact) for n in norms],
        "theorem2_lhs_as_printed": {str(i): {"coefficient_of_norm_A^d_squared": [
            _s(sp.factor(c)) for c in coeff_printed[i]]} for i in (1, 2)},
        "theorem2_lhs_corrected": {str(i): {"coefficient_of_norm_A^d_squared": [
            _s(sp.factor(c)) for c in coeff_corrected[i]]} for i in (1, 2)},
        "diagonal_boundary_q_half": {"as_printed": [f"{float(b):.7f}" for b in b_printed],
                                     "corrected": [f"{float(b):.7f}" for b in b_corrected]},
        "witness_q_half": {"phi11": _s(witness[0]), "phi12": _s(witness[1]),
                           "holds_as_printed": w_printed, "holds_corrected": w_corrected},
        "region_fraction_on_[0.8,1]^2_q_half": {"as_printed": float(region_p.mean()),
                                                  "corrected": float(region_c.mean())},
        "figure": png,
    }
    checks = {
        "[C1; C1 A^r] invertible for r = 1..6": all(invertible.values()),
        "varrho = 0 iff sum of gamma <= 1 (every sequence, delta <= 7)": varrho_claim,
        "mu_i(k_l, 1) = 1": all(pis[j][0] == 1 for j in (1, 2)),
        "eq. (34): Pr{sum gamma <= 1} = (1-phi)^delta + delta (1-phi)^(delta-1) phi": eq34,
        "DP and enumeration agree on pi_j(delta)": enum_agrees,
        "displayed condition after (34) equals (32) as printed": display_ok,
    }
    if simulate:
        results["simulation"], checks["bounded E[tr P] where the corrected condition holds"] = viic_simulation(dyn)
    return reproduction("quevedo-semi-markov", f"{PAPER}, Sec. VII-C, eqs. (33)-(34), Fig. 6", results, checks)


def viic_simulation(dyn: PeriodicDynamics) -> tuple[dict, bool]:
    """Monte Carlo over the lifted chain (q_ij = 1/2): phi = 19/20 (condition holds) and 3/10 (fails)."""
    from ..numeric.montecarlo import simulate_traces

    system = System(dyn.A[0], [Sensor(dyn.C[0])])
    horizon, paths, seed = 400, 4000, 2
    out, verdicts = {}, {}
    for phi in ("19/20", "3/10"):
        state = SemiMarkovNetworkState([["1/2", "1/2"], ["1/2", "1/2"]], VIIC_HOLDING)
        loss = NetworkLoss(SensorTree([0]), state, [[phi, phi]])
        t2 = theorem2(loss, dyn)
        mean = simulate_traces(system, loss, horizon=horizon, paths=paths, seed=seed).mean(axis=0)
        early, late = float(mean[100:200].mean()), float(mean[300:400].mean())
        verdicts[phi] = (t2.holds, late < 2 * early)
        out[f"phi = {phi} (both states)"] = {
            "corrected_condition_holds": t2.holds, "as_printed_holds": t2.holds_paper,
            "lhs_interval": {str(k[0]): _interval(b) for k, b in t2.bounds.items()},
            "mean_trace_k100_200": early, "mean_trace_k300_400": late}
    out.update({"q": "1/2", "horizon": horizon, "paths": paths, "seed": seed})
    return out, verdicts["19/20"] == (True, True)

check_public(globals())
