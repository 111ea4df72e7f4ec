"""UDP-like LQG control (no acknowledgements): the paper's results with their hypotheses checked exactly.

Schenato, Sinopoli, Franceschetti, Poolla and Sastry, "Foundations of control and estimation over
lossy networks", Proc. IEEE 95(1), 2007, Section V: without acknowledgements the estimator does
not know whether a control packet arrived (``x_hat+ = A x_hat + nu_bar B u``), its error covariance
gains ``nu_bar (1 - nu_bar) B u u' B'``, the separation principle fails and the optimal controller
is nonlinear in general.  With noiseless full-state measurements (``C`` invertible, ``R = 0``) it is
linear, ``u = -L x_hat`` with ``L = (B'SB + U + (1 - gamma)(1 - nu) B'TB)^{-1} B'SA``, and the
cost-to-go ``x_hat'S x_hat + e'(S + T)e`` obeys the coupled equations::

    S = A'SA + W - nu A'SB M^{-1} B'SA,   T = (1 - gamma) A'TA + nu A'SB M^{-1} B'SA,
    M = B'SB + U + (1 - gamma)(1 - nu) B'TB

(re-derived in ``proofs/control_udp_scalar.py``).  For a scalar plant ``a`` (``|a| > 1``) they
have a solution iff ``gamma > 1 - 1/a^2`` and::

    nu > nu_udp(gamma) = gamma (a^2 - 1) / (a^2 - (1 - gamma)(2 a^2 - 1))

(the homogeneous fixed direction of the coupled equations; at ``gamma = 1`` it is TCP's
``1 - 1/a^2``).  Rows, in the style of the bounds atlas: exact where proved, an outer bound where
the region is only bounded, "does not apply" with the reason otherwise.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import sympy as sp

from ..arguments import check_public
from ..errors import InputError
from ..exact.linalg import rank
from ..exact.numbers import to_exact
from ..model.system import System
from ..output import JsonDocument

SOURCE = "Schenato, Sinopoli, Franceschetti, Poolla, Sastry 2007, Section V"


@dataclass(frozen=True)
class UdpRow(JsonDocument):
    """One result on the UDP-like region: ``status`` is ``"exact"``, ``"outer bound"`` or
    ``"does not apply"``; ``hypotheses`` the exact checks, ``statement`` what the result says of
    this system (or why it does not apply)."""

    result: str
    source: str
    status: str
    hypotheses: tuple[tuple[str, bool], ...]
    statement: str

    def to_dict(self) -> dict[str, Any]:
        return {"result": self.result, "source": self.source, "status": self.status,
                "hypotheses": [{"hypothesis": h, "holds": ok} for h, ok in self.hypotheses],
                "statement": self.statement}


def udp_threshold(a: Any, gamma: Any) -> sp.Expr:
    """``nu_udp(gamma) = gamma (a^2 - 1) / (a^2 - (1 - gamma)(2 a^2 - 1))``, exact: the least control
    arrival rate of a scalar plant ``a`` (``|a| > 1``) with noiseless measurements arriving at rate
    ``gamma > 1 - 1/a^2`` (module doc)."""
    a2 = to_exact(a, "a") ** 2
    g = to_exact(gamma, "gamma")
    if not (a2 > 1):
        raise InputError(f"a: the scalar plant must be unstable, |a| > 1, got a^2 = {a2}")
    if not (0 <= g <= 1):
        raise InputError(f"gamma: an arrival rate lies in [0, 1], got {g}")
    if not (g > 1 - 1 / a2):
        raise InputError(f"gamma: {g} <= 1 - 1/a^2 = {1 - 1 / a2}: the estimation error diverges at every nu "
                         f"(T = (1 - gamma) a^2 T + ... has no solution)")
    return _boundary(a2, g)


def _boundary(a2: sp.Expr, gamma: sp.Expr) -> sp.Expr:
    """``gamma (a^2 - 1) / (a^2 - (1 - gamma)(2 a^2 - 1))`` for ``a2 = a^2`` (a number or a symbol)."""
    return sp.simplify(gamma * (a2 - 1) / (a2 - (1 - gamma) * (2 * a2 - 1)))


@dataclass(frozen=True, repr=False)
class UdpRegion(JsonDocument):
    """The UDP-like results for one system (:func:`udp_region`)."""

    rows: tuple[UdpRow, ...]
    noiseless: bool

    def __str__(self) -> str:
        lines = [f"UDP-like LQG ({'measurements taken noiseless, R = 0' if self.noiseless else 'R as given'}):"]
        for r in self.rows:
            lines.append(f"  {r.result} [{r.status}]: {r.statement}")
        return "\n".join(lines)

    __repr__ = __str__

    def to_dict(self) -> dict[str, Any]:
        return {"protocol": "UDP-like", "noiseless": self.noiseless, "rows": [r.to_dict() for r in self.rows]}


def udp_region(system: System, noiseless: bool = False) -> UdpRegion:
    """The UDP-like results that apply to ``system`` (module doc).  ``noiseless=True`` takes the
    measurements as noiseless (``R = 0``, the paper's hypothesis, which a :class:`System`'s positive
    definite ``R`` cannot state); otherwise the noiseless results are outer bounds (measurement
    noise only shrinks the region: a controller seeing noiseless data can add the noise itself).

    >>> import symkf as sk
    >>> S = sk.System(A=[[2]], sensors=[sk.Sensor(C=[[1]])], actuators=[sk.Actuator(B=[[1]])])
    >>> print(sk.control.udp_region(S, noiseless=True).rows[1].statement)
    bounded iff gamma > 3/4 and nu > 3*gamma/(7*gamma - 3) (at gamma = 1: nu > 3/4)
    """
    if not isinstance(noiseless, bool):
        raise InputError(f"noiseless: expected True or False, got {type(noiseless).__name__}")
    if not system.actuators:
        raise InputError("system: has no actuators; give System(..., actuators=[Actuator(B=...)])")
    n = system.n
    C = system.C
    invertible = rank(C) == n
    rows = [UdpRow("UDP inside TCP", SOURCE, "outer bound", (("always", True),),
                   "bounded only where the TCP-like cost is (the TCP controller knows more): "
                   "gamma > gamma_c and nu > nu_c, symkf.control.tcp_region")]
    hyp_scalar = (("n = 1", n == 1), ("C invertible", invertible), ("R = 0 (noiseless)", noiseless))
    if n == 1 and invertible:
        a = system.A[0, 0]
        g = sp.Symbol("gamma")
        a2 = a ** 2
        if a2 > 1:
            bound = _boundary(a2, g)
            text = (f"bounded iff gamma > {1 - 1 / a2} and nu > {bound} (at gamma = 1: nu > {1 - 1 / a2})")
        else:
            text = "|a| <= 1: bounded at every rate with nu > 0 or |a| < 1"
        rows.append(UdpRow("scalar plant, noiseless measurements", SOURCE + " (coupled equations; boundary "
                           "derived in proofs/control_udp_scalar.py)", "exact" if noiseless else "outer bound",
                           hyp_scalar, text))
    else:
        rows.append(UdpRow("scalar plant, noiseless measurements", SOURCE, "does not apply", hyp_scalar,
                           "needs n = 1 and C invertible"))
    hyp_linear = (("C invertible", invertible), ("R = 0 (noiseless)", noiseless))
    rows.append(UdpRow("linear optimal controller (coupled Riccati equations)", SOURCE,
                       ("exact" if noiseless else "outer bound") if invertible else "does not apply", hyp_linear,
                       "u = -L x_hat with S, T of the module doc; bounded iff they have a solution"
                       if invertible else "the UDP-optimal controller is nonlinear in general: only the TCP outer "
                       "bound applies"))
    return UdpRegion(tuple(rows), noiseless)


check_public(globals())
