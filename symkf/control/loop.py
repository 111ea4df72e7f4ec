"""The closed LQG loop over two lossy networks, TCP-like: the estimator's and the controller's thresholds.

Schenato, Sinopoli, Franceschetti, Poolla and Sastry, "Foundations of control and estimation over
lossy networks", Proc. IEEE 95(1), 2007, Section IV: with acknowledged control packets the
separation principle holds, the optimal controller is ``u = -L x_hat`` and the infinite-horizon
cost is bounded iff the Kalman filter with intermittent observations has bounded expected error
covariance and the control MARE has a fixed point.  The paper brackets the estimation side with
Sinopoli et al.'s bounds; here it is symkf's exact verdict (:func:`symkf.engine.stability.stability`,
every loss model the engine decides) and, for a common i.i.d. rate of all sensors, the exact
critical value ``gamma_c = 1 - eps_c`` (:func:`symkf.engine.stability.critical_loss_rate`).  The
control side is :func:`symkf.control.threshold.critical_arrival_rate` for one channel carrying
every input, and, for independent per-actuator channels, the multi-channel MARE's linear matrix
inequality decided with exact certificates: the control MARE with per-actuator arrivals is Yang
et al.'s multi-sensor MARE (eq. 18) of the dual system ``(A', B_i', U_i)``
(:func:`symkf.capacity.convergence.mare_stabilizable`).
"""

from __future__ import annotations

from dataclasses import dataclass
from fractions import Fraction
from typing import Any

import sympy as sp

from ..arguments import check_public
from ..capacity.convergence import mare_stabilizable
from ..engine.stability import Verdict, critical_loss_rate, stability
from ..errors import AssumptionError, InputError
from ..exact.algebraic import AlgebraicNumber
from ..exact.numbers import to_rational
from ..exact.text import algebraic_text
from ..model.iid import IID
from ..model.loss import LossModel
from ..model.system import Sensor, System
from ..output import JsonDocument
from .markov import _gilbert_elliott_stabilizable
from .threshold import ControlThreshold, _quotient_rank, _quotients, critical_arrival_rate, exact_plant


@dataclass(frozen=True, repr=False)
class TcpRegion(JsonDocument):
    """The region ``gamma > gamma_c``, ``nu > nu_c`` of (observation, control) arrival rates where the
    TCP-like LQG cost is bounded, every sensor at the common rate ``gamma`` and one control channel
    at rate ``nu`` (Schenato et al. 2007, Section IV)."""

    gamma_c: AlgebraicNumber
    control: ControlThreshold

    @property
    def nu_c(self) -> ControlThreshold:
        return self.control

    def contains(self, gamma: Any, nu: Any) -> bool | None:
        """Whether the cost is bounded at ``(gamma, nu)``, exactly; None when ``nu`` lies inside the
        control threshold's certified bracket (not decided)."""
        g = to_rational(gamma, "gamma")
        if not 0 <= g <= 1:
            raise InputError(f"gamma: an arrival rate lies in [0, 1], got {g}")
        control = self.control.decides(nu)
        return False if not self.gamma_c < g else control

    def __str__(self) -> str:
        return (f"TCP-like LQG bounded iff gamma > gamma_c = {algebraic_text(self.gamma_c)} (observations, every "
                f"sensor at rate gamma) and nu > nu_c, {self.control}")

    __repr__ = __str__

    def to_dict(self) -> dict[str, Any]:
        return {"protocol": "TCP-like", "gamma_c": self.gamma_c.to_dict(), "nu_c": self.control.to_dict()}

    def _repr_latex_(self) -> str:
        return rf"$\gamma > \gamma_c = {sp.latex(self.gamma_c.exact)},\quad$ " + self.control._repr_latex_()


def tcp_region(system: System, tolerance: Any = "1e-12") -> TcpRegion:
    """The TCP-like stability region over (observation, control) arrival rates (module doc): the
    exact ``gamma_c = 1 - eps_c`` of the sensors at a common i.i.d. rate and ``nu_c`` of one control
    channel (:func:`~symkf.control.threshold.critical_arrival_rate`, with ``tolerance``).

    >>> import symkf as sk
    >>> S = sk.System(A=[[2]], sensors=[sk.Sensor(C=[[1]])], actuators=[sk.Actuator(B=[[1]])])
    >>> r = sk.control.tcp_region(S)
    >>> r.gamma_c.exact, r.nu_c.exact.exact, r.contains("4/5", "4/5"), r.contains("4/5", "7/10")
    (3/4, 3/4, True, False)
    """
    control = critical_arrival_rate(system, tolerance)
    return TcpRegion(1 - critical_loss_rate(system), control)


@dataclass(frozen=True, repr=False)
class LoopVerdict(JsonDocument):
    """Whether the TCP-like LQG cost stays bounded under the given sensor and actuator losses: the
    estimator's exact verdict and the controller's, each with its reason."""

    estimation: Verdict
    control: bool | None
    control_reason: str

    @property
    def stable(self) -> bool | None:
        """Both sides stable (separation, Schenato et al. 2007, Section IV); None when the control side
        is undecided."""
        if not self.estimation.stable or self.control is False:
            return False
        return self.control

    def __bool__(self) -> bool:
        return bool(self.stable)

    def __str__(self) -> str:
        word = {True: "bounded", False: "unbounded", None: "undecided"}[self.stable]
        est = "stable" if self.estimation.stable else "unstable"
        ctl = {True: "stabilizable", False: "not stabilizable", None: "undecided"}[self.control]
        return f"TCP-like LQG cost {word}: estimator {est} ({self.estimation.theorem}); control {ctl} ({self.control_reason})"

    __repr__ = __str__

    def to_dict(self) -> dict[str, Any]:
        return {"protocol": "TCP-like", "stable": self.stable, "estimation": self.estimation.to_dict(),
                "control": self.control, "control_reason": self.control_reason}


def _dual(system: System) -> System:
    """``(A', B_i', U_i)``: the system whose multi-sensor MARE is this plant's control MARE with one
    channel per actuator (transposition maps ``A'SA - A'SB (...)^{-1} B'SA`` to ``A X A' - ...``)."""
    return System(A=system.A.T, sensors=[Sensor(C=a.B.T, R=a.U, name=a.name) for a in system.actuators])


def control_stabilizable(system: System, actuator_loss: LossModel) -> tuple[bool | None, str]:
    """Whether the control MARE has a fixed point under the actuators' losses, with the reason: one
    actuator (one channel): against :func:`~symkf.control.threshold.critical_arrival_rate`;
    independent i.i.d. channels per actuator: the multi-channel MARE's LMI with exact certificates
    (None near its boundary); one Gilbert-Elliott channel for every input: :mod:`.markov` (exact where
    a certificate decides, else None).  Other loss processes are refused with the reason."""
    fail, recover = actuator_loss.channel_fail, actuator_loss.channel_recover
    if actuator_loss.bernoulli is None and fail is not None and recover is not None and len(system.actuators) == 1 \
            and len(fail) == 1:
        A, B = exact_plant(system)
        return _gilbert_elliott_stabilizable(sp.Matrix(A), sp.Matrix(B), sp.Matrix(system.W), sp.Matrix(system.U),
                                             fail[0], recover[0])
    losses = actuator_loss.require_bernoulli(
        "i.i.d. control-packet losses, or one Gilbert-Elliott channel for every input (Schenato et al. 2007, "
        "Section IV)",
        "per-actuator Markov channels make the control recursion a Markov jump linear system with one mode per "
        "joint channel state, not decided here")
    if len(losses) != len(system.actuators):
        raise InputError(f"actuator_loss: {len(losses)} channels for {len(system.actuators)} actuators")
    if len(losses) == 1:
        nu = 1 - sp.Rational(losses[0])
        threshold = critical_arrival_rate(system)
        decided = threshold.decides(nu)
        where = {False: "<= nu_c", True: "> nu_c", None: "inside the certified bracket"}[decided]
        return decided, f"nu = {nu} {where}, {threshold}"
    system.check_stabilizable()
    obstruction = _quotient_obstruction(system, [1 - sp.Rational(e) for e in losses])
    if obstruction:
        return False, obstruction
    verdict = mare_stabilizable(_dual(system), IID(loss=list(losses)))
    return verdict.holds, f"multi-channel MARE LMI (Yang et al., Theorem 4 on the dual system): {verdict.certificate}"


def _quotient_obstruction(system: System, arrivals: list[sp.Expr]) -> str | None:
    """A quotient (module :mod:`.threshold`) that no arrival rates this low can stabilize, in words,
    or None.  Per quotient ``Q`` and the set ``J`` of actuators reaching it: one actuator alone is
    one channel, so its rate must exceed the quotient bound ``1 - |det A_Q|^(-2/r)``; several must
    pass ``prod_{j in J} (1 - nu_j) rho(A_Q)^2 < 1`` (the second-moment map of the quotient
    dominates its all-lost term).  Unknown reach (an irrational quotient) counts as reaching:
    more actuators only weaken both conditions."""
    A = sp.Matrix(system.A)
    for members, det2, H in _quotients(A):
        dim = sum(e.multiplicity for e in members)
        ranks = [_quotient_rank(H, a.B, dim)[0] for a in system.actuators]
        reach = [j for j, r in enumerate(ranks) if r > 0]
        eigen = ", ".join(e.label for e in members)
        if len(reach) == 1:
            j = reach[0]
            bound = AlgebraicNumber.from_expr(1 - 1 / sp.root(det2.exact, ranks[j]))
            if not bound < arrivals[j]:
                return (f"the quotient on {{{eigen}}} is reached by {system.actuators[j].name} alone, whose "
                        f"arrival rate {arrivals[j]} <= 1 - |det A_Q|^(-2/{ranks[j]}) = {algebraic_text(bound)}")
        elif reach:
            rho2 = max(e.modulus for e in members) ** 2
            lost = sp.Mul(*[1 - arrivals[j] for j in reach])
            if not rho2 * lost < 1:
                names = ", ".join(system.actuators[j].name for j in reach)
                return (f"the quotient on {{{eigen}}} is reached by {names} only, all lost together with "
                        f"probability {lost}, and {lost} rho(A_Q)^2 = {algebraic_text(rho2 * lost)} >= 1")
    return None


def lqg_stable(system: System, sensor_loss: LossModel, actuator_loss: LossModel) -> LoopVerdict:
    """Whether the TCP-like LQG cost is bounded: the estimator's verdict under ``sensor_loss`` (any
    loss model :func:`symkf.stability` decides) and the control side under ``actuator_loss``
    (:func:`control_stabilizable`); bounded iff both (separation, Schenato et al. 2007, Section IV)."""
    if not isinstance(actuator_loss, LossModel):
        raise InputError(f"actuator_loss: expected a loss model, got {type(actuator_loss).__name__}")
    estimation = stability(system, sensor_loss)
    control, reason = control_stabilizable(system, actuator_loss)
    return LoopVerdict(estimation, control, reason)


check_public(globals())
