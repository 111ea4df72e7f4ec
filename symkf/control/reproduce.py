"""``symkf reproduce`` entries for Schenato, Sinopoli, Franceschetti, Poolla and Sastry, "Foundations of
control and estimation over lossy networks", Proc. IEEE 95(1), 2007, Sections IV and V.

The paper's text is not among the sources this project ships, so the entries recompute the
results it states on plants given here (docs/control.md says what differs): the TCP-like region
as the product of the two thresholds, the closed forms of the control threshold, the UDP-like
region of a scalar plant with noiseless measurements, the figure of both regions, and the closed
loop simulated on both sides of every threshold (:func:`symkf.control.verify.verify_loop`).
"""

from __future__ import annotations

import os
from typing import Any

import sympy as sp

from .. import output
from ..arguments import check_public, count
from ..model.system import Actuator, Sensor, System
from ..reproduction import reproduction
from .loop import tcp_region
from .threshold import critical_arrival_rate
from .udp import udp_region, udp_threshold
from .verify import verify_loop

SOURCE = ("Schenato, Sinopoli, Franceschetti, Poolla, Sastry, Foundations of control and estimation over "
          "lossy networks, Proc. IEEE 95(1), 2007, Sections IV-V")

R = sp.Rational


def scalar_plant() -> System:
    """``x+ = 2 x + nu_k u + w``, ``y = gamma_k x + v``: ``gamma_c = nu_c = 3/4``."""
    return System(A=[[2]], sensors=[Sensor(C=[[1]], name="y")], actuators=[Actuator(B=[[1]], name="u")],
                  name="scalar a = 2")


def _simulated(system: System, points: list[tuple[Any, Any]], protocol: str, paths: int, horizon: int,
               noiseless: bool = False) -> list[dict[str, Any]]:
    out = []
    for g, v in points:
        r = verify_loop(system, g, v, protocol=protocol, noiseless=noiseless, paths=paths, horizon=horizon)
        out.append({"gamma": str(r.gamma), "nu": str(r.nu), "theory": r.theory, "simulation": r.simulated_verdict,
                    "rate": r.simulated_rate, "outcome": r.outcome})
    return out


def reproduce_schenato_scalar(outdir: str | None = None, simulate: bool = True, paths: int = 20_000,
                              horizon: int = 120) -> dict:
    """The scalar plant ``a = 2``: TCP-like ``gamma_c = nu_c = 3/4`` exactly, the UDP-like boundary
    ``nu_udp(gamma) = 3 gamma/(7 gamma - 3)``, the figure of both regions (``outdir``), and the loop
    simulated on both sides of each TCP threshold (``simulate``)."""
    if outdir is not None:   # refused before the work, not after it
        output.plan_directory(outdir, "outdir")
    paths, horizon = count(paths, "paths", 2), count(horizon, "horizon", 8)
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


def reproduce_schenato_closed_forms(outdir: str | None = None, simulate: bool = True, paths: int = 20_000,
                                    horizon: int = 120) -> dict:
    """The control threshold's closed forms (one input, invertible ``B``) and a certified bracket where
    none applies, each simulated at ``nu_c -+ 1/50`` with every observation arriving (the results say
    which points the simulation decided; a check fails only on a contradiction)."""
    if outdir is not None:
        output.plan_directory(outdir, "outdir")
    paths, horizon = count(paths, "paths", 2), count(horizon, "horizon", 8)
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


check_public(globals())
