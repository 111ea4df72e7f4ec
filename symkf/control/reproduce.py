"""``symkf reproduce`` entries for Schenato, Sinopoli, Franceschetti, Poolla and Sastry, "Foundations of
control and estimation over lossy networks", Proc. IEEE 95(1), 2007.

The paper's full text could not be read (``proofs/control_schenato_sources.py`` records the search):
what was read is its abstract, the abstract of the conference version "Optimal control with
unreliable communication: the TCP case" (Sinopoli et al., ACC 2005), the information sets and cost
of "LQG control with missing observation and control packets" (IFAC 2005, eqs. (3)-(4), the model
symkf uses), and the paper's TCP-like theorem as J. P. Hespanha and A. R. Mesquita restate it in the Encyclopedia of Systems and Control
("Networked control systems: estimation and control over lossy networks", Theorems 1-3).  So no
numerical example or figure of the paper is compared.  :func:`reproduce_schenato_claims` checks
what those texts state; the other entries recompute the results symkf implements on plants given
here: the TCP-like region as the product of the two thresholds, the closed forms of the control
threshold, the UDP-like region of a scalar plant with noiseless measurements, the figure of both
regions, and the closed loop simulated on both sides of every threshold
(:func:`symkf.control.verify.verify_loop`).
"""

from __future__ import annotations

import os
from typing import Any

import sympy as sp

from .. import output
from ..arguments import check_public, count
from ..engine.stability import critical_loss_rate, stability
from ..exact.linalg import field_of, positive_definite
from ..exact.spectral import spectral_radius
from ..model.iid import IID
from ..model.system import Actuator, Sensor, System
from ..reproduction import discrepancy, reproduction
from .loop import tcp_region
from .threshold import ControlThreshold, critical_arrival_rate, lyapunov_certificate
from .udp import udp_region, udp_threshold
from .verify import verify_loop

SOURCE = ("Schenato, Sinopoli, Franceschetti, Poolla, Sastry, Foundations of control and estimation over "
          "lossy networks, Proc. IEEE 95(1), 2007, Sections IV-V")
#: the texts :func:`reproduce_schenato_claims` checks (the paper's own text could not be read)
CLAIMS_SOURCE = ("Schenato et al., Proc. IEEE 95(1), 2007, abstract; Sinopoli et al., Optimal control with "
                 "unreliable communication: the TCP case, ACC 2005, abstract; Hespanha and Mesquita, Networked "
                 "control systems: estimation and control over lossy networks, Encyclopedia of Systems and "
                 "Control, Theorems 1-3 (Theorem 2 restates Schenato et al.)")
#: what the paper holds that no entry compares, because its text was not available
NOT_COMPARED = ("the paper's numerical examples, figures (the regions over (gamma, nu), the costs) and printed "
                "values: its full text could not be read (proofs/control_schenato_sources.py)")

R = sp.Rational


def scalar_plant() -> System:
    """``x+ = 2 x + nu_k u + w``, ``y = gamma_k x + v``: ``gamma_c = nu_c = 3/4``."""
    return System(A=[[2]], sensors=[Sensor(C=[[1]], name="y")], actuators=[Actuator(B=[[1]], name="u")],
                  name="scalar a = 2")


def _simulated(system: System, points: list[tuple[Any, Any]], protocol: str, paths: int | None, horizon: int | None,
               noiseless: bool = False) -> list[dict[str, Any]]:
    out = []
    for g, v in points:
        r = verify_loop(system, g, v, protocol=protocol, noiseless=noiseless, paths=paths, horizon=horizon)
        out.append({"gamma": str(r.gamma), "nu": str(r.nu), "theory": r.theory, "simulation": r.simulated_verdict,
                    "rate": r.simulated_rate, "outcome": r.outcome})
    return out


def reproduce_schenato_scalar(outdir: str | None = None, simulate: bool = True, paths: int | None = None,
                              horizon: int | None = None) -> dict:
    """The scalar plant ``a = 2``: TCP-like ``gamma_c = nu_c = 3/4`` exactly, the UDP-like boundary
    ``nu_udp(gamma) = 3 gamma/(7 gamma - 3)``, the figure of both regions (``outdir``), and the loop
    simulated on both sides of each TCP threshold (``simulate``)."""
    if outdir is not None:   # refused before the work, not after it
        output.plan_directory(outdir, "outdir")
    paths = None if paths is None else count(paths, "paths", 2)   # None: the witnesses' own defaults
    horizon = None if horizon is None else count(horizon, "horizon", 8)
    S = scalar_plant()
    region = tcp_region(S)
    rows = udp_region(S, noiseless=True).rows
    grid = [R(k, 20) for k in range(16, 21)]
    boundary = {str(g): str(udp_threshold(2, g)) for g in grid}
    results: dict[str, Any] = {"gamma_c": str(region.gamma_c.exact), "nu_c": str(region.control.lower.exact),
                               "nu_c_certificate_rate": str(region.control.upper),
                               "udp_boundary": boundary, "udp_rows": [r.to_dict() for r in rows]}
    checks = {
        "TCP: gamma_c = 1 - 1/a^2 = 3/4 (the engine's exact critical value)": region.gamma_c == R(3, 4),
        "TCP: nu_c = 1 - 1/a^2 = 3/4 (one input), certificate verified": region.control.exact == R(3, 4)
        and region.control.check(),
        "UDP: nu_udp(1) = nu_c (perfect observations: no mismatch)": udp_threshold(2, 1) == R(3, 4),
        "UDP inside TCP: nu_udp(gamma) >= nu_c on the grid gamma = 4/5..1": all(udp_threshold(2, g) >= R(3, 4)
                                                                              for g in grid),
    }
    if simulate:
        tcp = _simulated(S, [("19/20", "17/20"), ("19/20", "13/20"), ("17/20", "19/20"), ("13/20", "19/20")],
                         "tcp", paths, horizon)
        results["tcp_simulation"] = tcp
        checks["TCP: the simulated loop agrees on both sides of gamma_c and nu_c"] = \
            all(p["outcome"] == "consistent" for p in tcp)
    if outdir is not None:
        from .figure import region_figure
        fig = region_figure(S, noiseless=True, title="Scalar plant a = 2: TCP-like and UDP-like regions")
        path = os.path.join(output.plan_directory(outdir, "outdir"), "schenato_scalar_regions.png")
        results["figure"] = str(output.save_figure(fig, path, "outdir", dpi=120))
        import matplotlib.pyplot as plt
        plt.close(fig)
    return reproduction("schenato-scalar", SOURCE, results, checks)


def closed_form_plants() -> dict[str, System]:
    """One input (``1 - 1/(2 * 3)^2 = 35/36``), invertible ``B`` (``1 - 1/3^2 = 8/9``) and two inputs on
    three modes (no closed form: the bracket at the quotient bound ``29/30``)."""
    eye2, eye3 = [[1, 0], [0, 1]], [[1, 0, 0], [0, 1, 0], [0, 0, 1]]
    return {
        "one input": System(A=[[2, 1], [0, 3]], sensors=[Sensor(C=eye2)], actuators=[Actuator(B=[[0], [1]])],
                            name="one input"),
        "B invertible": System(A=[[2, 1], [0, 3]], sensors=[Sensor(C=eye2)], actuators=[Actuator(B=eye2)],
                               name="B invertible"),
        "two inputs, three modes": System(A=[[2, 0, 0], [0, 3, 0], [0, 0, 5]], sensors=[Sensor(C=eye3)],
                                          actuators=[Actuator(B=[[1, 0], [0, 1], [1, 1]])],
                                          name="two inputs, three modes"),
    }


def reproduce_schenato_closed_forms(outdir: str | None = None, simulate: bool = True, paths: int | None = None,
                                    horizon: int | None = None) -> dict:
    """The control threshold's closed forms (one input, invertible ``B``) and a certified bracket where
    none applies, each simulated at ``nu_c -+ 1/50`` with every observation arriving (the results say
    which points the simulation decided; a check fails only on a contradiction)."""
    if outdir is not None:
        output.plan_directory(outdir, "outdir")
    paths = None if paths is None else count(paths, "paths", 2)   # None: the witnesses' own defaults
    horizon = None if horizon is None else count(horizon, "horizon", 8)
    expected = {"one input": R(35, 36), "B invertible": R(8, 9), "two inputs, three modes": R(29, 30)}
    results: dict[str, Any] = {}
    checks: dict[str, bool] = {}
    for name, S in closed_form_plants().items():
        t = critical_arrival_rate(S)
        results[name] = t.to_dict()
        checks[f"{name}: nu_c's lower end is {expected[name]} and the bracket reaches 1e-12"] = \
            t.lower == expected[name] and t.reached and t.check()
        if simulate:
            nu = expected[name]
            low, high = nu - R(1, 50), min(R(1), nu + R(1, 50))
            sim = _simulated(S, [(1, low), (1, high)], "tcp", paths, horizon)
            results[name]["simulation"] = sim
            checks[f"{name}: the simulated loop never contradicts the threshold at nu_c -+ 1/50"] = \
                all(p["outcome"] != "contradiction" for p in sim)
    checks["one input: a closed form applies"] = critical_arrival_rate(closed_form_plants()["one input"]).exact is not None
    return reproduction("schenato-closed-forms", SOURCE, results, checks)


def _positive_definite(M: sp.MatrixBase) -> bool:
    """Exact, over the number field of ``M``'s entries."""
    field = field_of(M)
    return positive_definite(field, field.matrix(M))


def _mare_root(nu: sp.Rational) -> sp.Expr | None:
    """The positive fixed point of the scalar control MARE ``S = 4 S + 1 - 4 nu S^2/(S + 1)`` (``a = 2``,
    ``b = W = U = 1``): the positive root of ``(3 - 4 nu) S^2 + 4 S + 1``, None when there is none (for
    ``nu <= 3/4`` every coefficient is nonnegative)."""
    S = sp.Symbol("S", positive=True)
    roots = sp.solve((3 - 4 * nu) * S ** 2 + 4 * S + 1, S)
    return roots[0] if roots else None


def _lmi_point(system: System, t: ControlThreshold) -> dict[str, Any]:
    """Hespanha and Mesquita's Theorem 2 (restating Schenato et al.): ``Psi_nu(Y, Z) > 0`` and
    ``0 <= Y <= I`` at ``nu = t.upper``, decided exactly at a point built from symkf's certificate.

    ``S0 - T(S0) = I`` (``T`` the loop's second-moment map with the certified gain ``K``) gives, for
    ``S = c S0`` with ``c = 1 + tr(W + nu K'UK)``, ``S - T(S) = c I > W + nu K'UK``; take ``Y = S^-1``,
    ``Z = Y K'``.  The printed ``Psi_nu``, with entries ``sqrt(nu)``, ``sqrt(1 - nu)`` and ``U^(1/2)``, is
    congruent (scale its last three block rows and columns by ``U^(-1/2)/sqrt(nu)``, ``1/sqrt(nu)`` and
    ``1/sqrt(1 - nu)``) to the rational matrix::

        [[Y, Y, Z, YA' + ZB', YA'], [Y, W^-1, 0, 0, 0], [Z', 0, U^-1/nu, 0, 0],
         [AY + BZ', 0, 0, Y/nu, 0], [AY, 0, 0, 0, Y/(1 - nu)]]

    whose definiteness is decided exactly; ``Y < I`` is ``c S0 - I > 0``."""
    A, B = sp.Matrix(t.A), sp.Matrix(t.B)
    W, U = sp.Matrix(system.W), sp.Matrix(system.U)
    nu, K = sp.Rational(t.upper.numerator, t.upper.denominator), sp.Matrix(t.gain)
    n, m = B.shape
    c = 1 + (W + nu * K.T * U * K).trace()
    S = c * sp.Matrix(t.certificate)
    Y = S.inv()
    Z = Y * K.T
    O = sp.zeros
    psi = sp.BlockMatrix([[Y, Y, Z, Y * A.T + Z * B.T, Y * A.T],
                          [Y, W.inv(), O(n, m), O(n, n), O(n, n)],
                          [Z.T, O(m, n), U.inv() / nu, O(m, n), O(m, n)],
                          [A * Y + B * Z.T, O(n, n), O(n, m), Y / nu, O(n, n)],
                          [A * Y, O(n, n), O(n, m), O(n, n), Y / (1 - nu)]]).as_explicit()
    return {"nu": str(nu), "psi_positive_definite": _positive_definite(psi),
            "Y_below_I": _positive_definite(S - sp.eye(n))}


def _lmi_scalar_schur(nu: sp.Expr) -> sp.Expr:
    """``a = 2``, ``b = W = U = 1``: the Schur complement of the congruent ``Psi_nu`` (:func:`_lmi_point`)
    on its last four blocks, plus the three terms that are nonnegative for ``y > 0``: it is
    ``y (1 - (1 - nu) a^2)``, so at ``(1 - nu) a^2 >= 1`` no ``y > 0`` and ``z`` make ``Psi_nu > 0``."""
    y, z = sp.Symbol("y", positive=True), sp.Symbol("z", real=True)
    a = 2
    row = sp.Matrix([[y, z, a * y + z, a * y]])
    D = sp.diag(1, 1 / nu, y / nu, y / (1 - nu))
    schur = y - (row * D.inv() * row.T)[0, 0]
    return sp.simplify(schur + y ** 2 + nu * z ** 2 + nu * (a * y + z) ** 2 / y)


def _udp_mixture() -> dict[str, sp.Expr]:
    """One UDP-like step with a noisy measurement.  Shifted by the estimate, the state is ``N(d, p)`` if
    the unacknowledged command arrived (``d = b u``, probability ``nu``) and ``N(0, p)`` if not; ``y = x + v``
    with ``v ~ N(0, r)``, ``s = p + r``, ``k = p/s``.  The posterior is the mixture with weight ``w(y)`` on the
    first component.  Returned, each zero when the identity holds: ``w' - (d/s) w (1 - w)``, ``E[x | y]``
    minus ``k y + (1 - k) d w`` and ``Var(x | y)`` minus ``k r + (1 - k)^2 d^2 w (1 - w)`` (``w`` a free
    weight), and ``d^2 E[x | y]/dy^2`` at ``y = d/2`` minus ``r d^3 nu (1 - nu)(1 - 2 nu)/s^3``; and that
    curvature itself at ``nu = 9/10``, ``d = p = r = 1`` and at ``r = 0``."""
    y, d = sp.symbols("y d", real=True)
    p, r, nu = sp.symbols("p r nu", positive=True)
    s, k = p + r, p / (p + r)
    g1, g0 = nu * sp.exp(-(y - d) ** 2 / (2 * s)), (1 - nu) * sp.exp(-y ** 2 / (2 * s))
    w = g1 / (g1 + g0)
    ww = sp.Symbol("w")
    m1, m0, v = d + k * (y - d), k * y, p * r / s
    mean = ww * m1 + (1 - ww) * m0
    second = ww * (v + m1 ** 2) + (1 - ww) * (v + m0 ** 2)
    curvature = sp.simplify(sp.diff(k * y + (1 - k) * d * w, y, 2).subs(y, d / 2))
    return {"dw": sp.simplify(sp.diff(w, y) - d / s * w * (1 - w)),
            "mean": sp.simplify(mean - (k * y + (1 - k) * d * ww)),
            "variance": sp.simplify(second - mean ** 2 - (k * r + (1 - k) ** 2 * d ** 2 * ww * (1 - ww))),
            "curvature": sp.factor(curvature),
            "curvature_formula": sp.simplify(curvature - r * d ** 3 * nu * (1 - nu) * (1 - 2 * nu) / s ** 3),
            "curvature_9/10": curvature.subs({nu: sp.Rational(9, 10), d: 1, p: 1, r: 1}),
            "curvature_noiseless": sp.simplify(curvature.subs(r, 0))}


def _fully_observed() -> dict[str, System]:
    return {"diag(2, 3)": System(A=[[2, 0], [0, 3]], sensors=[Sensor(C=[[1, 0], [0, 1]])]),
            "diag(2, 3, 5)": System(A=[[2, 0, 0], [0, 3, 0], [0, 0, 5]],
                                    sensors=[Sensor(C=[[1, 0, 0], [0, 1, 0], [0, 0, 1]])]),
            "2R(pi/3)": System(A=[[1, "-sqrt(3)"], ["sqrt(3)", 1]], sensors=[Sensor(C=[[1, 0], [0, 1]])]),
            "a = 2": System(A=[[2]], sensors=[Sensor(C=[[1]])])}


def reproduce_schenato_claims(outdir: str | None = None) -> dict:
    """What the texts read of Schenato et al. state (module doc), checked exactly:

    * the abstracts (TCP-like): the optimal control is linear in the estimate and a critical arrival
      probability exists below which it fails: on ``a = 2`` the control MARE's positive root exists iff
      ``nu > 3/4``, and its gain ``-(B'SB + U)^-1 B'SA`` is certified mean-square stabilizing at
      ``nu = 751/1000, 4/5, 9/10`` over ``Q(sqrt(...))``;
    * Hespanha and Mesquita's Theorem 2: the LMI ``Psi_nu(Y, Z) > 0, 0 <= Y <= I`` as printed is feasible at
      symkf's certified rate on four plants (:func:`_lmi_point`) and infeasible at ``nu_c`` (scalar);
    * their statement, citing Schenato et al., that the estimator's bounds coincide for fully observed
      plants: ``theta_c = 1 - 1/rho(A)^2`` against the engine's exact value on four plants;
    * the abstracts (UDP-like): with a noisy measurement the posterior is a Gaussian mixture whose mean is
      nonlinear in ``y`` (``d^2 E[x | y]/dy^2 != 0``) and whose variance depends on the command
      (:func:`_udp_mixture`); with ``R = 0`` (``k = 1``) both nonlinear terms vanish.

    ``discrepancies`` lists the secondary source's misstatements, each against an exact computation;
    nothing printed in the paper itself could be compared (``results["not_compared"]``).  ``outdir`` is
    accepted for the command line and unused (no figure)."""
    if outdir is not None:
        output.plan_directory(outdir, "outdir")
    results: dict[str, Any] = {"not_compared": NOT_COMPARED}
    checks: dict[str, bool] = {}

    no_root = all(_mare_root(nu) is None for nu in (R(0), R(1, 2), R(3, 4)))
    gains: dict[str, Any] = {}
    for nu in (R(751, 1000), R(4, 5), R(9, 10)):
        s = _mare_root(nu)
        fixed = sp.simplify(4 * s + 1 - 4 * nu * s ** 2 / (s + 1) - s) == 0
        K = sp.radsimp(-2 * s / (s + 1))
        gains[str(nu)] = {"S": str(s), "gain": str(K), "fixed_point": fixed,
                          "certified": lyapunov_certificate([[2]], [[1]], [[K]], nu) is not None}
    results["tcp_scalar_mare"] = {"equation": "(3 - 4 nu) S^2 + 4 S + 1 = 0 (a = 2, b = W = U = 1)", "nu_c": "3/4",
                                  "optimal_gains": gains}
    checks["abstracts, TCP-like: a critical arrival probability exists; a = 2: no positive MARE root at "
           "nu = 0, 1/2, 3/4"] = no_root
    checks["abstracts, TCP-like: the optimal control -(B'SB + U)^-1 B'SA x_hat is linear and, from the exact MARE "
           "root, certified mean-square stabilizing at nu = 751/1000, 4/5, 9/10"] = \
        all(g["fixed_point"] and g["certified"] for g in gains.values())

    plants = {"scalar a = 2": scalar_plant(), **closed_form_plants()}
    lmi = {name: _lmi_point(S, critical_arrival_rate(S)) for name, S in plants.items()}
    results["theorem2_lmi"] = lmi
    checks["Hespanha-Mesquita Thm 2 (Schenato et al.): Psi_nu(Y, Z) > 0 and 0 <= Y <= I, as printed, hold at the "
           "certified rate nu_c + 5e-13 on four plants (exact)"] = \
        all(v["psi_positive_definite"] and v["Y_below_I"] for v in lmi.values())
    at_nu_c = _lmi_scalar_schur(R(3, 4))
    results["theorem2_lmi_at_nu_c"] = {"plant": "a = 2", "nu": "3/4", "schur_plus_nonnegative_terms": str(at_nu_c)}
    checks["Hespanha-Mesquita Thm 2: the LMI is infeasible at nu <= nu_c (a = 2: the Schur complement is "
           "y (1 - (1 - nu) a^2) minus nonnegative terms, 0 at nu = 3/4)"] = at_nu_c == 0

    observed = {}
    for name, S in _fully_observed().items():
        rho = spectral_radius(S.A)
        eps = critical_loss_rate(S).exact
        observed[name] = {"theta_c": str(1 - eps), "1 - 1/rho^2": str(sp.simplify(1 - 1 / rho ** 2)),
                          "equal": sp.simplify(eps - 1 / rho ** 2) == 0}
    results["fully_observed_theta_c"] = observed
    checks["Hespanha-Mesquita, citing Schenato et al.: C invertible gives theta_c = theta_min = 1 - 1/rho(A)^2 "
           "(the engine's exact value, four plants)"] = all(v["equal"] for v in observed.values())

    mix = _udp_mixture()
    results["udp_mixture"] = {"d^2 E[x|y]/dy^2 at y = d/2": str(mix["curvature"]),
                              "at nu = 9/10, d = p = r = 1": str(mix["curvature_9/10"]),
                              "Var(x|y)": "k r + (1 - k)^2 d^2 w (1 - w), k = p/(p + r)"}
    checks["Proc. IEEE abstract, UDP-like: the posterior is a Gaussian mixture; E[x|y] = k y + (1 - k) d w(y) and "
           "Var(x|y) = k r + (1 - k)^2 d^2 w(1 - w) (symbolic identities)"] = \
        mix["dw"] == 0 and mix["mean"] == 0 and mix["variance"] == 0
    checks["Proc. IEEE abstract, UDP-like: with r > 0 the estimate is nonlinear in y (d^2 E[x|y]/dy^2 = "
           "r d^3 nu (1 - nu)(1 - 2 nu)/(p + r)^3 at y = d/2, nonzero at nu = 9/10) and its variance depends on the "
           "command; with r = 0 both vanish"] = \
        mix["curvature_formula"] == 0 and mix["curvature_9/10"] != 0 and mix["curvature_noiseless"] == 0

    scalar = _fully_observed()["a = 2"]
    verdict = {str(g): stability(scalar, IID(loss=[str(1 - g)])).stable for g in (R(1, 2), R(3, 4), R(9, 10))}
    results["scalar_estimator_verdicts"] = {"a = 2, C = 1, theta_bar": verdict}
    lmi_scalar = lmi["scalar a = 2"]
    discrepancies = [
        discrepancy("Hespanha-Mesquita Thm 1 and Thm 3: E[P_k] <= M for all k iff theta_bar >= theta_c",
                    "bounded at theta_bar = theta_c",
                    f"unbounded at theta_bar = theta_c: a = 2, C = 1 has theta_c = 3/4 and the engine's verdict "
                    f"there is stable = {verdict['3/4']} (margin (1 - theta_bar) a^2 = 1)",
                    "Sinopoli et al. 2004, Theorem 2: E[P_t] diverges for lambda <= lambda_c; read '>'"),
        discrepancy("Hespanha-Mesquita Thm 2: v_c = min{v >= 0 : Psi_v(Y, Z) > 0, 0 <= Y <= I}",
                    "a minimum (attained)",
                    f"an infimum, not attained: a = 2 is infeasible at v_c = 3/4 and feasible at "
                    f"{lmi_scalar['nu']}",
                    "the strict LMI's feasible rates are the open interval (v_c, 1]"),
        discrepancy("Hespanha-Mesquita, before Thm 1: 'a critical value theta_c for the dropout rate theta_bar, "
                    "above which the estimation error covariance becomes unbounded'",
                    "unbounded above theta_c",
                    f"unbounded below: theta_bar = Pr{{theta_k = 1}} is the arrival rate; a = 2, C = 1: stable = "
                    f"{verdict['1/2']} at 1/2, {verdict['9/10']} at 9/10"),
        discrepancy("Hespanha-Mesquita Remark 1: 'the upper bound in (3) is tight in the sense that "
                    "theta_c - theta_min'",
                    "the upper bound in (3)",
                    "(3) is the lower bound theta_min; tight means theta_c = theta_min, which the engine confirms "
                    "for C invertible on four plants"),
    ]
    checks["Sinopoli et al. 2004 (the estimator of Thm 1): a = 2, C = 1 is unstable at theta_bar = 1/2 and at "
           "theta_c = 3/4, stable at 9/10 (exact verdicts)"] = verdict == {"1/2": False, "3/4": False, "9/10": True}
    return reproduction("schenato-claims", CLAIMS_SOURCE, results, checks, discrepancies)


check_public(globals())
