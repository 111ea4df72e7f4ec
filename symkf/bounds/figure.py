"""The atlas against one parameter: every applicable result and the exact critical rate.

:func:`atlas_figure` evaluates :func:`symkf.bounds.bounds` on each member of a one-parameter
family (default: ``A = 2 R(pi p/q)``, ``C = [1 0]`` over rational angles) and draws each
applicable row's threshold (an LMI's certified bracket as an error bar) beside the exact
``eps_c``.  matplotlib is the optional ``plot`` extra.
"""

from __future__ import annotations

from typing import Any, Sequence

import numpy as np
import sympy as sp

from ..arguments import check_public
from ..errors import InputError
from ..model.system import System
from ..reports.plots import figure_target, finish_figure, new_figure, rational_angles, rotation_system
from ..run.progress import progress
from .atlas import bounds
from .row import OTHER

#: marker per row key (rows not listed get the default cycle)
STYLE = {"sinopoli-lower": ("v", "tab:red"), "sinopoli-lmi": ("^", "tab:green"),
         "mo-sinopoli": ("s", "tab:purple"), "mo-sinopoli-degenerate": ("D", "tab:purple"),
         "you-fu-xie": ("x", "tab:orange"), "sui-theorem12": ("+", "tab:brown"),
         "yang-theorem2": ("1", "tab:pink"), "yang-theorem5": ("2", "tab:olive"), "quevedo-theorem1": ("3", "tab:cyan")}


def rotation_family(scale: Any = 2, max_denominator: int = 6) -> list[tuple[float, System]]:
    """``(theta, System)`` for ``A = scale R(theta)``, ``C = [1 0]``, ``theta = pi p/q``, ``q <= max_denominator``."""
    out = []
    for f in rational_angles(max_denominator):
        theta = sp.pi * sp.Rational(f.numerator, f.denominator)
        out.append((float(theta), rotation_system(scale, theta)))
    return out


def atlas_figure(family: Sequence[tuple[float, System]] | None = None, *, parameter: str = r"rotation angle $\theta$",
                 title: str = r"$A = 2R(\theta)$, $C = [1\ 0]$: published results and the exact $\varepsilon_c$",
                 lmi_steps: int = 5, path: Any = None) -> Any:
    """Each applicable row's threshold and the exact critical loss against the family's parameter."""
    target = figure_target(path)   # checked before the work
    family = rotation_family() if family is None else list(family)
    if not family or not all(isinstance(m, (tuple, list)) and len(m) == 2 and isinstance(m[1], System) for m in family):
        raise InputError("family: expected a non-empty list of (parameter value, System) pairs")
    points: dict[str, list] = {}
    labels: dict[str, str] = {}
    exact = []
    with progress(len(family), "systems") as bar:
        for x, system in family:
            atlas = bounds(system, lmi_steps=lmi_steps)
            exact.append((x, float(atlas.quantity.critical)))
            for r in atlas.rows:
                if not r.applies or r.claim == OTHER:
                    continue
                labels[r.key] = r.result
                if r.bracket is not None:
                    lo, hi = (float(v) for v in r.bracket)
                    points.setdefault(r.key, []).append((x, (lo + hi) / 2, (hi - lo) / 2))
                elif r.value is not None and r.stable is not None and len(r.stable) <= 1:
                    points.setdefault(r.key, []).append((x, min(float(r.value), 1.0), 0.0))
            bar.update()
    fig = new_figure(7.2, 5.6)
    ax = fig.add_subplot()
    xs, ys = zip(*exact)
    ax.plot(xs, ys, "o", ms=9, mfc="none", color="black", label="exact $\\varepsilon_c$ (symkf)")
    for key, pts in points.items():
        marker, color = STYLE.get(key, ("o", None))
        x, y, err = (np.array(v) for v in zip(*pts))
        if err.any():
            ax.errorbar(x, y, yerr=err, fmt=marker, color=color, capsize=2, label=labels[key] + " (certified)")
        else:
            ax.plot(x, y, marker, color=color, label=labels[key])
    ax.set(xlabel=parameter, ylabel="critical common i.i.d. loss probability", title=title, ylim=(0, None))
    ax.legend(fontsize="x-small", loc="upper center", bbox_to_anchor=(0.5, -0.13), ncol=3)
    return finish_figure(fig, target)


check_public(globals())
