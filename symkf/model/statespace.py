"""The bridge to python-control: the parts of a discrete-time ``StateSpace`` that make a
:class:`~symkf.model.system.System` (:meth:`~symkf.model.system.System.from_statespace`), and a
system as a ``StateSpace`` (the ``control`` extra: ``pip install 'symkf[control]'``).

A ``StateSpace`` ``x[k+1] = A x[k] + B u[k]``, ``y[k] = C x[k] + D u[k]`` carries no noise, so
``Q`` (process noise, entering as ``w`` in ``x[k+1] = A x[k] + w[k]``, Sui-You-Fu eq. 1) and the
sensors' ``R_i`` are given separately, as for ``control.dlqe(A, I, C, Q, R)``.  ``B`` and ``D``
do not affect the error covariance and are not kept.

python-control stores every matrix as float64, so the usual float rule applies: a float whose
binary value is the decimal it prints as (``2.0``, ``-1.5``, ``0.625``) is exact; any other
(``0.1``) is refused unless ``rationalize=True`` (its shortest decimal, ``0.1`` as 1/10) or
``rationalize="nearby"`` (a nearby exact constant such as ``sqrt(3)/2``), which say so in one
warning (:func:`symkf.exact.numbers.to_exact`).
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any, Iterable, Mapping, Sequence

import numpy as np
import sympy as sp

from ..arguments import check_public, float_array
from ..errors import InputError, ShapeError, require_extra
from ..exact.numbers import as_matrix

if TYPE_CHECKING:
    import control

__all__ = ["statespace_parts", "statespace_of", "float_matrix"]


def statespace_parts(sys: "control.StateSpace", sensors: Mapping[str, Iterable[int]] | Sequence[str] | None = None,
                     R: Mapping[str, Any] | None = None) -> tuple[list, dict[str, tuple[list, Any]]]:
    """``A`` and, per sensor name, its rows of ``C`` and its ``R`` (or None), read from a
    discrete-time python-control ``StateSpace``: what :meth:`symkf.model.system.System.from_statespace`
    builds its system from.

    ``sensors`` says how the rows of ``C`` split into sensors: a mapping from sensor name to its
    row indices (every row in exactly one sensor), a list of names (one row each), or None: one
    sensor per row, named by ``sys.output_labels``.
    """
    if getattr(sys, "dt", None) in (0, None) or not hasattr(sys, "C"):
        raise InputError(f"sys: expected a discrete-time control.StateSpace (dt != 0), got {sys!r:.80}; "
                         "discretize a continuous system first (control.c2d)")
    rows = np.asarray(sys.C)
    groups = _sensor_rows(sensors, list(sys.output_labels), rows.shape[0])
    R = dict(R or {})
    unknown = sorted(set(R) - set(groups))
    if unknown:
        raise InputError(f"R: no sensor named {unknown[0]!r}; sensors are {sorted(groups)}")
    return np.asarray(sys.A).tolist(), {s: (rows[idx].tolist(), R.get(s)) for s, idx in groups.items()}


def _sensor_rows(sensors: Mapping[str, Sequence[int]] | Sequence[str] | None, labels: list[str],
                 p: int) -> dict[str, list[int]]:
    """Sensor name -> row indices of ``C``, checked to split the ``p`` rows exactly."""
    if sensors is None:
        sensors = labels
    if not isinstance(sensors, Mapping):
        names = list(sensors)
        if len(names) != p:
            raise ShapeError(f"sensors: {len(names)} names for the {p} rows of C; give one name per row "
                             "or a mapping from name to row indices")
        sensors = {s: [i] for i, s in enumerate(names)}
    groups = {str(s): [int(i) for i in idx] for s, idx in sensors.items()}
    used = sorted(i for idx in groups.values() for i in idx)
    if used != list(range(p)):
        raise InputError(f"sensors: rows {used} of C assigned; every row 0..{p - 1} must belong to exactly "
                         "one sensor")
    return groups


def statespace_of(A: sp.MatrixBase, C: sp.MatrixBase, outputs: Sequence[str], name: str | None, B: Any = None,
                  D: Any = None, dt: float | bool = 1) -> "control.StateSpace":
    """A python-control ``StateSpace`` (float64) of the exact ``A`` and stacked ``C`` with the
    output labels ``outputs``: what :meth:`symkf.model.system.System.to_statespace` returns.

    ``B``, ``D``: input and feedthrough matrices.  The papers' systems have no input, so the
    default is one input that does not act, ``B = 0`` and ``D = 0``, labelled ``no_input``.
    ``dt``: sampling time, 1 for one step of ``x_{k+1} = A x_k + w_k`` (``True``: discrete,
    unspecified).  A complex system is refused (python-control has none).
    """
    ct = require_extra("control", "control", "to_statespace")
    A, C = float_matrix(A, "A"), float_matrix(C, "C")
    n, p = A.shape[0], C.shape[0]
    # python-control mishandles empty (p, 0) feedthroughs, so "no input" is one input that does not act
    inputs = ["no_input"] if B is None else None
    B = np.zeros((n, 1)) if B is None else float_array(B, "B")
    if B.ndim != 2 or B.shape[0] != n or B.shape[1] == 0 or not np.all(np.isfinite(B)):
        raise ShapeError(f"B: expected a finite {n} x m matrix with m >= 1 inputs, got shape {B.shape}")
    D = np.zeros((p, B.shape[1])) if D is None else float_array(D, "D")
    if D.shape != (p, B.shape[1]) or not np.all(np.isfinite(D)):
        raise ShapeError(f"D: expected a finite {p} x {B.shape[1]} matrix (outputs x inputs), got shape {D.shape}")
    if isinstance(dt, bool) and not dt or not isinstance(dt, bool) and not 0 < dt < math.inf:
        raise InputError(f"dt: expected a positive sampling time or True (discrete, unspecified), got {dt!r}")
    return ct.ss(A, B, C, D, dt, outputs=list(outputs), inputs=inputs, name=name)


def float_matrix(M: sp.MatrixBase, entry: str) -> np.ndarray:
    """The float64 array of a real exact matrix (correctly rounded entries)."""
    values = [[complex(sp.N(v, 20)) for v in row] for row in as_matrix(M, entry).tolist()]
    if any(v.imag for row in values for v in row):
        raise InputError(f"{entry}: complex entries; python-control needs a real system "
                         "(symkf.numeric.filters.real_form gives one with the same tr P_k)")
    return np.array([[v.real for v in row] for row in values])

check_public(globals())
