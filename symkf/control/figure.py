"""The stability region of the LQG loop over (observation, control) arrival rates, as a figure.

Schenato, Sinopoli, Franceschetti, Poolla and Sastry, "Foundations of control and estimation over
lossy networks", Proc. IEEE 95(1), 2007, Sections IV-V draw the regions where the TCP-like and the
UDP-like costs stay bounded: TCP's is the rectangle ``gamma > gamma_c``, ``nu > nu_c``
(:func:`symkf.control.loop.tcp_region`, exact or a certified bracket), UDP's lies inside it and,
for a scalar plant with noiseless measurements, is bounded by ``nu_udp(gamma)``
(:func:`symkf.control.udp.udp_threshold`).  The curve is drawn from exact values at rational
``gamma``; floats only place the pixels.
"""

from __future__ import annotations

from typing import Any

import sympy as sp

from ..arguments import check_public, count
from ..errors import InputError, require_extra
from ..model.system import System
from .loop import tcp_region
from .udp import udp_threshold


def region_figure(system: System, noiseless: bool = True, points: int = 200, title: str | None = None) -> Any:
    """A matplotlib figure of the TCP-like region and, for a scalar plant, the UDP-like boundary
    (``noiseless``: the measurements taken noiseless, the paper's hypothesis for UDP; otherwise the
    curve is an outer bound and labelled so).  ``points`` rational ``gamma`` place the curve."""
    require_extra("matplotlib", "plot", "region_figure")
    points = count(points, "points", 2)
    if not isinstance(noiseless, bool):
        raise InputError(f"noiseless: expected True or False, got {type(noiseless).__name__}")
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    region = tcp_region(system)
    gc, nc = float(region.gamma_c), float(region.control.lower)
    fig, ax = plt.subplots(figsize=(5, 5))
    ax.fill([gc, 1, 1, gc], [nc, nc, 1, 1], alpha=0.25, label=f"TCP-like: γ > {gc:.4g}, ν > {nc:.4g}")
    if system.n == 1 and any(c != 0 for c in system.C) and abs(system.A[0, 0]) > 1:
        a = system.A[0, 0]
        low = 1 - 1 / a ** 2
        gammas = [sp.Rational(k, points) for k in range(1, points + 1) if sp.Rational(k, points) > low]
        kept = [(float(g), float(v)) for g in gammas if (v := udp_threshold(a, g)) <= 1]
        label = "UDP-like boundary ν_udp(γ)" + ("" if noiseless else " (outer bound: R > 0)")
        ax.plot([g for g, _ in kept], [v for _, v in kept], color="C3", label=label)
    ax.set_xlim(0, 1)
    ax.set_ylim(0, 1)
    ax.set_xlabel("observation arrival rate γ")
    ax.set_ylabel("control arrival rate ν")
    ax.set_title(title or f"LQG over lossy networks: {system.name or 'the plant'}")
    ax.legend(loc="lower left")
    fig.tight_layout()
    return fig


check_public(globals())
