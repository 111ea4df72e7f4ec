"""Theory against simulation for the closed loop: the exact verdict beside a Monte Carlo divergence test.

:func:`verify_loop` decides at arrival rates ``(gamma, nu)`` (every sensor at ``gamma``, every
actuator at ``nu``) whether the LQG cost is bounded, exactly (TCP-like: :func:`symkf.control.loop.lqg_stable`;
UDP-like, scalar plant with noiseless measurements: :func:`symkf.control.udp.udp_threshold`), and,
independently, whether ``E[x_k' W x_k]`` of the simulated loop grows
(:func:`symkf.numeric.closed_loop.loop_divergence`: three runs of the loop's conditional second
moments given losses drawn from a mixture of twisted laws, exact likelihood ratios and the
margin's Fieller interval, the same discipline as :func:`symkf.verify`; "stable" from the growth
alone needs an effective sample size of 100; where a burst spreads a covariance beyond float64
the horizon is cut to two thirds, down to 30 steps).  Where the sampler does not see a loop's
growth the outcome is "undecided", never "consistent": on ten plants of the tests, both sides of
both thresholds (``tests/control/test_control_verify.py``, seed 0, 4000 paths, horizon 90), 38 of
40 points decide, none contradicts; over 9 seeds (``benchmarks/calibrate_loop_verify.py``) 170 of
180 loop points decide and 72 of 72 UDP-like scalar noiseless points, none contradicts.  The outcome:

* ``"consistent"``: the simulation decides the theory's verdict;
* ``"contradiction"``: it decides the other one (a bug in the theory or the simulation);
* ``"undecided"``: the theory or the simulation does not decide, with the reason.

Where only the estimator diverges (TCP-like, the control side stabilizable) the loop's divergence
is the filter's, by separation, and its witness is the filter's own simulation
(:func:`symkf.numeric.verify.verify`, whose sampler targets the decisive loss pattern of the
estimator's theorem).  The simulated loop runs a linear controller ``u = -L x_hat``: where the theory says bounded, the
optimal gain at ``(gamma, nu)`` (TCP: the control MARE's; UDP: the coupled equations' of
Schenato et al. 2007, Section V); where it says unbounded, the best gain the theory knows (the
control threshold's certificate gain, or the optimal gain where only the estimator fails), so
divergence is seen for a gain that works just above the threshold.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
import sympy as sp

from ..arguments import check_public
from ..errors import InputError, NumericalBreakdownError, SymkfError
from ..exact.numbers import to_rational
from ..model.iid import IID
from ..model.system import System
from ..numeric.closed_loop import HORIZON, PATHS, control_riccati, loop_divergence, loop_plant, plant_of
from ..numeric.verify import verify as filter_verify
from ..output import JsonDocument
from .loop import lqg_stable
from .threshold import critical_arrival_rate
from .udp import udp_threshold

OUTCOMES = ("consistent", "contradiction", "undecided")


@dataclass(frozen=True, repr=False)
class LoopVerification(JsonDocument):
    """The exact verdict (``theory``: True bounded, False unbounded, None undecided, with
    ``theory_reason``) beside the simulation's (``simulation``), the ``outcome`` and its ``reason``."""

    protocol: str
    gamma: sp.Rational
    nu: sp.Rational
    theory: bool | None
    theory_reason: str
    simulation: Any    # LoopDivergence, or the filter's Verification where only the estimator diverges
    outcome: str
    reason: str

    @property
    def simulated_verdict(self) -> str | None:
        """The simulation's word: "stable", "unstable", "undecided" (None when it broke down)."""
        return self._simulated("verdict")

    @property
    def simulated_rate(self) -> float | None:
        """The simulated growth factor per step (margin), None when not resolved."""
        return self._simulated("rate")

    def _simulated(self, key: str) -> Any:
        # the loop's LoopDivergence holds its answer as attributes, the filter's Verification in a dict
        if self.simulation is None:
            return None
        if hasattr(self.simulation, "result"):
            return getattr(self.simulation, key)
        return self.simulation.simulation.get(key)

    def to_dict(self) -> dict[str, Any]:
        return {"protocol": self.protocol, "gamma": str(self.gamma), "nu": str(self.nu), "theory": self.theory,
                "theory_reason": self.theory_reason,
                "simulation": None if self.simulation is None else self.simulation.to_dict(),
                "outcome": self.outcome, "reason": self.reason}

    def __str__(self) -> str:
        word = {True: "bounded", False: "unbounded", None: "undecided"}[self.theory]
        return (f"{self.protocol.upper()}-like loop at gamma = {self.gamma}, nu = {self.nu}: theory {word}; "
                f"{self.outcome} ({self.reason})")

    __repr__ = __str__


def _udp_gain(A: np.ndarray, B: np.ndarray, W: np.ndarray, U: np.ndarray, gamma: float, nu: float
              ) -> np.ndarray | None:
    """The optimal UDP-like gain of the coupled equations (module :mod:`.udp`) by iteration, or None
    when they diverge."""
    S, T = W.copy(), np.zeros_like(W)
    for _ in range(20000):
        M = B.T @ S @ B + U + (1 - gamma) * (1 - nu) * B.T @ T @ B
        G = np.linalg.solve(M, B.T @ S @ A)
        R = A.T @ S @ B @ G
        S_new, T_new = A.T @ S @ A + W - nu * R, (1 - gamma) * A.T @ T @ A + nu * R
        if not np.all(np.isfinite(S_new)) or np.abs(S_new).max() > 1e12 or np.abs(T_new).max() > 1e12:
            return None
        if np.allclose(S_new, S, rtol=1e-13, atol=1e-13) and np.allclose(T_new, T, rtol=1e-13, atol=1e-13):
            return G
        S, T = S_new, T_new
    return G


def verify_loop(system: System, gamma: Any, nu: Any, *, protocol: str = "tcp", noiseless: bool = False,
                seed: int = 0, paths: int | None = None, horizon: int | None = None) -> LoopVerification:
    """The exact verdict of the loop at ``(gamma, nu)`` against its simulation (module doc).

    ``paths`` and ``horizon`` default to each witness's own: the loop sampler's 4000 paths of 90
    steps (``closed_loop.PATHS``, ``HORIZON``, where it was calibrated), the filter's
    (:func:`symkf.numeric.verify.verify`) where only the estimator diverges.

    ``protocol="udp"`` is decided exactly for a scalar plant with noiseless measurements only
    (``noiseless=True``; simulated with ``R = 10^-12``); otherwise the theory is undecided there.
    """
    if protocol not in ("tcp", "udp"):
        raise InputError(f"protocol: 'tcp' or 'udp', got {protocol!r}")
    if not isinstance(noiseless, bool):
        raise InputError(f"noiseless: expected True or False, got {type(noiseless).__name__}")
    g, v = to_rational(gamma, "gamma"), to_rational(nu, "nu")
    for value, entry in ((g, "gamma"), (v, "nu")):
        if not 0 < value <= 1:
            raise InputError(f"{entry}: an arrival rate in (0, 1], got {value}")
    plant = plant_of(system)
    if protocol == "tcp":
        verdict = lqg_stable(system, IID(loss=[1 - g] * system.d), IID(loss=[1 - v] * len(system.actuators)))
        theory, theory_reason = verdict.stable, str(verdict)
        if verdict.control and not verdict.estimation.stable:
            # separation: only the filter diverges; its witness is the filter's own simulation, whose
            # sampler targets the decisive loss pattern (symkf.verify)
            try:
                sim = filter_verify(system, IID(loss=[1 - g] * system.d), seed=seed,
                                    **{k: v for k, v in (("paths", paths), ("horizon", horizon)) if v is not None})
            except SymkfError as exc:   # e.g. a margin priced above a cap at this rate
                return LoopVerification(protocol, g, v, theory, theory_reason, None, "undecided",
                                        f"the filter's simulation was refused: {exc}")
            said = {"stable": True, "unstable": False}.get(sim.simulation["verdict"])
            return _judged(protocol, g, v, theory, theory_reason, sim, said, sim.simulation["verdict"])
        if verdict.control:
            gain = control_riccati(plant.A, plant.B, plant.W, plant.U, float(v))[1]
        else:
            gain = -np.array(critical_arrival_rate(system).gain.tolist(), dtype=float)
    else:
        theory, theory_reason, gain = _udp_theory(system, g, v, noiseless, plant)
        if noiseless:
            plant = loop_plant(plant.A, plant.B, plant.C, plant.Q, 1e-12 * np.eye(plant.C.shape[0]), plant.W,
                               plant.U, plant.P0)
    # a long horizon's bursts may spread the covariances beyond float64: then the horizon is cut
    # to two thirds, down to 30 steps, before the point is left undecided
    paths, horizon = PATHS if paths is None else paths, HORIZON if horizon is None else horizon
    while True:
        try:
            sim = loop_divergence(plant, float(g), float(v), protocol=protocol, gain=gain, horizon=horizon,
                                  paths=paths, seed=seed)
            break
        except NumericalBreakdownError as exc:
            if horizon * 2 // 3 < 30:
                return LoopVerification(protocol, g, v, theory, theory_reason, None, "undecided",
                                        f"the simulation broke down: {exc}")
            horizon = horizon * 2 // 3
    return _judged(protocol, g, v, theory, theory_reason, sim, {"stable": True, "unstable": False}.get(sim.verdict),
                   sim.verdict)


def _judged(protocol: str, g: sp.Rational, v: sp.Rational, theory: bool | None, theory_reason: str, sim: Any,
            said: bool | None, word: str) -> LoopVerification:
    if theory is None or said is None:
        outcome = "undecided"
        reason = ("the theory does not decide this point" if theory is None else
                  f"the simulation does not decide ({word})")
    elif said == theory:
        outcome, reason = "consistent", "the simulation decides the theory's verdict"
    else:
        outcome, reason = "contradiction", f"the theory says {'bounded' if theory else 'unbounded'}, the simulation {word}"
    return LoopVerification(protocol, g, v, theory, theory_reason, sim, outcome, reason)


def _udp_theory(system: System, g: sp.Rational, v: sp.Rational, noiseless: bool, plant
                ) -> tuple[bool | None, str, np.ndarray]:
    """The UDP-like verdict of a scalar plant with noiseless measurements, and the gain to simulate."""
    if not (noiseless and system.n == 1 and any(c != 0 for c in system.C)):
        raise InputError("protocol 'udp': the exact verdict needs a scalar plant, C != 0 and noiseless=True "
                         "(Schenato et al. 2007, Section V; symkf.control.udp_region says what else applies)")
    a = system.A[0, 0]
    if not a ** 2 > 1:
        return True, "|a| <= 1", np.zeros((plant.B.shape[1], 1))
    low = 1 - 1 / a ** 2
    if not g > low:
        theory, reason = False, f"gamma <= 1 - 1/a^2 = {low}"
    else:
        star = udp_threshold(a, g)
        theory, reason = bool(v > star), f"nu_udp(gamma) = {star}"
    # where unbounded, the gain optimal just inside the region (at this gamma when it can be)
    g2 = g if g > low else (1 + low) / 2
    v2 = v if theory else min(sp.Integer(1), udp_threshold(a, g2) + sp.Rational(1, 50))
    gain = _udp_gain(plant.A, plant.B, plant.W, plant.U, float(g2), float(v2))
    if gain is None:
        raise NumericalBreakdownError(f"the UDP coupled equations did not converge at gamma = {g2}, nu = {v2}")
    return theory, reason, gain


check_public(globals())
