"""Schenato, Sinopoli, Franceschetti, Poolla, Sastry, "Foundations of control and estimation over lossy
networks", Proc. IEEE 95(1), 2007: what of the paper could be read, what those texts claim, and the
checks of every claim symkf can decide.

Texts of the paper and its conference versions that could be read (public copies):

* https://vdocuments.net/invited-paper-foundations-of-control-and-sastrypubspdfs-of-theory-which.html
  and https://sciencedocbox.com/Physics/76508494-Ieee-copyright-statement.html: the Proc. IEEE paper's
  title page and abstract (nothing past the keywords).
* https://fdocuments.net/document/ieee-copyright-statement-brunospublications-by-luca-schenatomember-ieee.html:
  the IEEE copyright notice only.  https://sciencedocbox.com/amp/111788540-Physics/Foundations-of-control-and-estimation-over-lossy-networks.html:
  a list of related titles only (among them the IFAC 2005 paper "LQG control with missing observation and
  control packets": its title is all that was found).
* https://study.space/p/Foundations_of_Control_and_Estimation_Over_Lossy_Networks: generated summaries,
  no statement precise enough to check; not used.
* https://paperzz.com/doc/7332773/optimal-control-with-unreliable-communication--the-tcp-case: the ACC
  2005 conference version (Sinopoli, Schenato, Franceschetti, Poolla, Sastry, "Optimal control with
  unreliable communication: the TCP case"): title, abstract, the first paragraph of Section I.
* https://de.scribd.com/document/101084238/10-1-1-216-8237: a stretch of the IFAC 2005 conference
  version ("LQG control with missing observation and control packets"), the end of Section 2 and the
  start of Section 3: the information sets (3), ``F_k = {y^k, gamma^k, nu^(k-1)}`` (TCP) and
  ``G_k = {y^k, gamma^k}`` (UDP), the cost (4), ``J_N = E[x_N' W_N x_N + sum_k (x_k' W_k x_k +
  nu_k u_k' U_k u_k) | I_N]`` ("we are weighting the input only if it is successfully received"), and
  Lemma 1 (``E[x'Sx | I] = x_hat' S x_hat + trace(S P)``).
* GitHub text: a markdown conversion of J. P. Hespanha and A. R. Mesquita, "Networked control systems:
  estimation and control over lossy networks", Encyclopedia of Systems and Control (Springer), the
  section "Two-link networks" (pages 863-868 of the converted book): Theorem 1 (Sinopoli et al. 2004),
  Theorem 2 ("Schenato et al. 2007": the TCP-like control threshold as an LMI and the optimal control),
  Theorem 3 and the paragraph on lost acknowledgements (citing the paper: a Gaussian-mixture posterior,
  no separation).
* Not found: the paper's body (its examples, figures, section numbers), the rest of the IFAC 2005 text,
  Imer, Yuksel and Basar (Automatica 2006), Elia (Systems & Control Letters 2005).

So no numerical example, figure or printed value of the paper is compared anywhere in symkf: the
entries ``schenato-scalar`` and ``schenato-closed-forms`` use plants of the project's own, and the
section numbers symkf cites (IV for TCP-like, V for UDP-like) and the closed forms for one input and
for invertible ``B`` come from the project's earlier reading, not from a text checked here.

Claims of the texts read, and how they are checked (``symkf reproduce schenato-claims``):

C1 (both abstracts) TCP-like: separation holds, the optimal LQG control is linear in the estimate, and
   there are critical arrival probabilities below which the optimal controller fails.  Checked:
   (a) below, symbolically for every scalar plant: the control MARE ``S = a^2 S + w - nu a^2 b^2 S^2/(b^2 S + u)``
   is ``b^2 (a^2 (1 - nu) - 1) S^2 + (u (a^2 - 1) + w b^2) S + w u = 0``, whose constant and linear
   coefficients are positive for ``|a| > 1``: a positive root exists iff ``nu > 1 - 1/a^2``;
   (b) the entry: on ``a = 2`` the exact root's gain ``-(B'SB + U)^-1 B'SA`` is certified mean-square
   stabilizing at ``nu = 751/1000, 4/5, 9/10`` (Lyapunov solve over ``Q(sqrt(...))``).
C2 (Hespanha-Mesquita, Theorem 2, restating the paper) ``v_c = min{v >= 0: Psi_v(Y, Z) > 0, 0 <= Y <= I}``
   with the printed 5x5 block ``Psi_v``.  Checked: (a) below, for every scalar plant, ``Psi_v`` as printed
   is congruent to a rational matrix whose Schur complement is ``y (1 - (1 - v) a^2)`` minus
   ``w y^2 + v u z^2 + v (a y + b z)^2 / y``: feasible iff ``(1 - v) a^2 < 1`` (``z = -a y/b`` and small
   ``y`` when it holds), i.e. the feasible rates are ``(1 - 1/a^2, 1]``; (b) the entry: feasible, exactly,
   at symkf's certified rate on four plants (scalar, one input, invertible ``B``, two inputs on three
   modes), the point built from the certificate.
C3 (Hespanha-Mesquita, citing the paper) for fully observed processes the estimator's two bounds
   coincide: ``theta_c = 1 - 1/rho(A)^2`` for ``C`` invertible.  Checked: the engine's exact value on
   diag(2, 3), diag(2, 3, 5), 2R(pi/3) and ``a = 2``.
C4 (Proc. IEEE abstract; Hespanha-Mesquita on lost acknowledgements) UDP-like: the posterior is a Gaussian
   mixture, separation fails, the optimal controller is nonlinear in general.  Checked, for one step with
   a noisy measurement: ``E[x | y] = k y + (1 - k) d w(y)`` with ``w`` logistic in ``y``, curvature
   ``r d^3 nu (1 - nu)(1 - 2 nu)/(p + r)^3`` at ``y = d/2`` (nonzero for ``r > 0``, ``nu`` not 1/2), and
   ``Var(x | y) = k r + (1 - k)^2 d^2 w (1 - w)`` depends on the command ``d = b u``; both vanish with
   ``r = 0``, the case where the paper's controller is linear.  Not checked: that the optimal command
   itself is nonlinear (no UDP-like dynamic programme is solved here).
C5 (ACC abstract) analytic upper and lower bounds on the cost: not stated in the text read; not checked.
C6 (IFAC 2005, eqs. (3)-(4), Lemma 1) the information sets and the cost that weighs a command only when
   it arrives: the model symkf uses (docs/control.md; ``proofs/control_udp_scalar.py`` minimises the
   expected cost ``w (x_hat^2 + P) + nu u U^2``, Lemma 1 (b) for ``x``, eq. (4)'s ``nu_k`` for the input).
   Read and compared by hand, not computed.

Discrepancies, all in the secondary source (none of the paper itself could be compared):
D1 Theorems 1 and 3 print ``E[P_k] <= M`` iff ``theta_bar >= theta_c``: at ``theta_c`` the covariance
   diverges (Sinopoli et al. 2004, Theorem 2); ``a = 2``, ``C = 1``: unstable at ``theta_c = 3/4``.
D2 Theorem 2 prints ``v_c = min{...}`` over a strict LMI: the minimum is not attained (C2 (a): the
   feasible set is open at ``v_c``); read "inf".
D3 "a critical value theta_c for the dropout rate theta_bar, above which the estimation error covariance
   becomes unbounded": ``theta_bar`` is the arrival probability, and the covariance is unbounded below.
D4 Remark 1, "the upper bound in (3) is tight in the sense that theta_c - theta_min": (3) is the lower
   bound; read "theta_c = theta_min" (C3 confirms it for ``C`` invertible).

Status: C1-C4 checked (C1 (a) and C2 (a) proved for every scalar plant), C6 consistent by reading; the
paper's examples and figures not available.
"""

from __future__ import annotations

import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

import sympy as sp  # noqa: E402

from symkf.control.reproduce import reproduce_schenato_claims  # noqa: E402

a, b, w, u, nu = sp.symbols("a b w u nu", positive=True)
y = sp.Symbol("y", positive=True)
z = sp.Symbol("z", real=True)


def scalar_mare() -> bool:
    S = sp.Symbol("S", positive=True)
    mare = (a ** 2 * S + w - nu * a ** 2 * b ** 2 * S ** 2 / (b ** 2 * S + u) - S) * (b ** 2 * S + u)
    quadratic = b ** 2 * (a ** 2 * (1 - nu) - 1) * S ** 2 + (u * (a ** 2 - 1) + w * b ** 2) * S + w * u
    ok = sp.cancel(mare - quadratic) == 0
    print(f"{'ok ' if ok else 'BAD'} scalar control MARE = b^2 (a^2 (1 - nu) - 1) S^2 + (u (a^2 - 1) + w b^2) S + w u")
    return ok


def scalar_lmi() -> bool:
    sq, sq1 = sp.sqrt(nu), sp.sqrt(1 - nu)
    printed = sp.Matrix([[y, y, sq * z * sp.sqrt(u), sq * (y * a + z * b), sq1 * y * a],
                         [y, 1 / w, 0, 0, 0],
                         [sq * sp.sqrt(u) * z, 0, 1, 0, 0],
                         [sq * (a * y + b * z), 0, 0, y, 0],
                         [sq1 * a * y, 0, 0, 0, y]])
    rational = sp.Matrix([[y, y, z, a * y + b * z, a * y],
                          [y, 1 / w, 0, 0, 0],
                          [z, 0, 1 / (nu * u), 0, 0],
                          [a * y + b * z, 0, 0, y / nu, 0],
                          [a * y, 0, 0, 0, y / (1 - nu)]])
    D = sp.diag(1, 1, sq * sp.sqrt(u), sq, sq1)
    congruent = sp.simplify(D * rational * D - printed) == sp.zeros(5, 5)
    row = rational[0, 1:]
    schur = rational[0, 0] - (row * rational[1:, 1:].inv() * row.T)[0, 0]
    identity = sp.simplify(schur + w * y ** 2 + nu * u * z ** 2 + nu * (a * y + b * z) ** 2 / y
                           - y * (1 - (1 - nu) * a ** 2)) == 0
    # where (1 - nu) a^2 < 1: z = -a y / b and y small make the Schur complement positive
    at = schur.subs(z, -a * y / b)
    witness = sp.simplify(at - y * (1 - (1 - nu) * a ** 2 - w * y - nu * u * a ** 2 * y / b ** 2)) == 0
    ok = congruent and identity and witness
    print(f"{'ok ' if ok else 'BAD'} Psi_nu as printed is congruent to a rational matrix with Schur complement "
          f"y (1 - (1 - nu) a^2) - w y^2 - nu u z^2 - nu (a y + b z)^2/y: feasible iff nu > 1 - 1/a^2")
    return ok


def entry() -> bool:
    rep = reproduce_schenato_claims()
    ok = all(rep["checks"].values()) and len(rep["checks"]) == 8 and len(rep["discrepancies"]) == 4
    for claim, holds in rep["checks"].items():
        print(f"{'ok ' if holds else 'BAD'} {claim}")
    for d in rep["discrepancies"]:
        print(f"    discrepancy: {d['claim']}: printed {d['printed']}; computed {d['computed']}")
    return ok


def main() -> bool:
    ok = all([scalar_mare(), scalar_lmi(), entry()])
    print("PASS" if ok else "FAIL")
    return ok


if __name__ == "__main__":
    sys.exit(0 if main() else 1)
