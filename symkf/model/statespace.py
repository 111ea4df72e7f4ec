"""The bridge to python-control: the parts of a discrete-time ``StateSpace`` that make a
:class:`~symkf.model.system.System` (:meth:`~symkf.model.system.System.from_statespace`), and a
system as a ``StateSpace`` (the ``control`` extra: ``pip install 'symkf[control]'``).

A ``StateSpace`` ``x[k+1] = A x[k] + B u[k]``, ``y[k] = C x[k] + D u[k]`` carries no noise, so
``Q`` (process noise, entering as ``w`` in ``x[k+1] = A x[k] + w[k]``, Sui-You-Fu eq. 1) and the
sensors' ``R_i`` are given separately, as for ``control.dlqe(A, I, C, Q, R)``.  The columns of
``B`` are the actuators' inputs of the LQG plant ``x[k+1] = A x[k] + B u[k] + w[k]`` (Schenato,
Sinopoli, Franceschetti, Poolla, Sastry, "Foundations of control and estimation over lossy
networks", 2007, Section II), their cost weights ``U_i`` given separately too; an all-zero ``B``
(the ``no_input`` of a system without actuators) gives none.  ``D`` is not kept.

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


#: a split of ``C``'s rows into sensors or ``B``'s columns into actuators: name -> indices, names
#: (one index each) or None (one each, named by the StateSpace's labels)
Split = Mapping[str, Iterable[int]] | Sequence[str] | None


def statespace_parts(sys: "control.StateSpace", sensors: Split = None, R: Mapping[str, Any] | None = None,
                     actuators: Split = None, U: Mapping[str, Any] | None = None
                     ) -> tuple[list, dict[str, tuple[list, Any]], dict[str, tuple[list, Any]]]:
    """``A``; per sensor name, its rows of ``C`` and its ``R`` (or None); per actuator name, its
    columns of ``B`` and its ``U`` (or None), read from a discrete-time python-control
    ``StateSpace``: what :meth:`symkf.model.system.System.from_statespace` builds its system from.

    ``sensors`` says how the rows of ``C`` split into sensors: a mapping from sensor name to its
    row indices (every row in exactly one sensor), a list of names (one row each), or None: one
    sensor per row, named by ``sys.output_labels``.  ``actuators`` splits the columns of ``B``
    likewise (None: one actuator per input, named by ``sys.input_labels``, and none at all when
    ``B`` is zero).
    """
    if getattr(sys, "dt", None) in (0, None) or not all(hasattr(sys, key) for key in ("A", "B", "C")):
        raise InputError(f"sys: expected a discrete-time control.StateSpace (dt != 0), got {sys!r:.80}; "
                         "discretize a continuous system first (control.c2d)")
    rows, columns = np.asarray(sys.C), np.asarray(sys.B).T
    measured = _parts(rows, _split(sensors, list(sys.output_labels), rows.shape[0], "sensors", "row", "C"),
                      R, "R", "sensor")
    acting = actuators is not None or columns.any()
    groups = _split(actuators, list(sys.input_labels), columns.shape[0], "actuators", "column", "B") if acting else {}
    driven = _parts(columns, groups, U, "U", "actuator")
    return (np.asarray(sys.A).tolist(), {s: (C.tolist(), R_s) for s, (C, R_s) in measured.items()},
            {a: (Bt.T.tolist(), U_a) for a, (Bt, U_a) in driven.items()})


def _parts(vectors: np.ndarray, groups: dict[str, list[int]], weights: Mapping[str, Any] | None, key: str,
           kind: str) -> dict[str, tuple[np.ndarray, Any]]:
    """Per name, its rows of ``vectors`` (``C``, or ``B'``) and its weight from ``weights`` (or None)."""
    weights = dict(weights or {})
    unknown = sorted(set(weights) - set(groups))
    if unknown:
        raise InputError(f"{key}: no {kind} named {unknown[0]!r}; {kind}s are {sorted(groups)}")
    return {name: (vectors[idx], weights.get(name)) for name, idx in groups.items()}


def _split(given: Split, labels: list[str], count: int, key: str, unit: str, matrix: str) -> dict[str, list[int]]:
    """Name -> indices of the ``count`` rows of ``C`` (``key = "sensors"``) or columns of ``B``
    (``"actuators"``), checked to split them exactly."""
    if given is None:
        given = labels
    if not isinstance(given, Mapping):
        names = list(given)
        if len(names) != count:
            raise ShapeError(f"{key}: {len(names)} names for the {count} {unit}s of {matrix}; give one name per "
                             f"{unit} or a mapping from name to {unit} indices")
        given = {s: [i] for i, s in enumerate(names)}
    groups = {str(s): [int(i) for i in idx] for s, idx in given.items()}
    used = sorted(i for idx in groups.values() for i in idx)
    if used != list(range(count)):
        raise InputError(f"{key}: {unit}s {used} of {matrix} assigned; every {unit} 0..{count - 1} must belong to "
                         f"exactly one {key[:-1]}")
    return groups


def statespace_of(A: sp.MatrixBase, C: sp.MatrixBase, outputs: Sequence[str], name: str | None, B: Any = None,
                  D: Any = None, dt: float | bool = 1, inputs: Sequence[str] | None = None) -> "control.StateSpace":
    """A python-control ``StateSpace`` (float64) of the exact ``A`` and stacked ``C`` with the
    output labels ``outputs``: what :meth:`symkf.model.system.System.to_statespace` returns.

    ``B``, ``D``: input and feedthrough matrices, the inputs labelled ``inputs`` (default
    python-control's ``u[i]``).  A system without actuators has no input, so the default is one
    input that does not act, ``B = 0`` and ``D = 0``, labelled ``no_input``.
    ``dt``: sampling time, 1 for one step of ``x_{k+1} = A x_k + w_k`` (``True``: discrete,
    unspecified).  A complex system is refused (python-control has none).
    """
    ct = require_extra("control", "control", "to_statespace")
    A, C = float_matrix(A, "A"), float_matrix(C, "C")
    n, p = A.shape[0], C.shape[0]
    # python-control mishandles empty (p, 0) feedthroughs, so "no input" is one input that does not act
    inputs = ["no_input"] if B is None else inputs
    B = np.zeros((n, 1)) if B is None else float_array(B, "B")
    if B.ndim != 2 or B.shape[0] != n or B.shape[1] == 0 or not np.all(np.isfinite(B)):
        raise ShapeError(f"B: expected a finite {n} x m matrix with m >= 1 inputs, got shape {B.shape}")
    D = np.zeros((p, B.shape[1])) if D is None else float_array(D, "D")
    if D.shape != (p, B.shape[1]) or not np.all(np.isfinite(D)):
        raise ShapeError(f"D: expected a finite {p} x {B.shape[1]} matrix (outputs x inputs), got shape {D.shape}")
    if isinstance(dt, bool) and not dt or not isinstance(dt, bool) and not 0 < dt < math.inf:
        raise InputError(f"dt: expected a positive sampling time or True (discrete, unspecified), got {dt!r}")
    if inputs is not None and len(inputs) != B.shape[1]:
        raise ShapeError(f"inputs: {len(inputs)} labels for the {B.shape[1]} columns of B")
    return ct.ss(A, B, C, D, dt, outputs=list(outputs), inputs=None if inputs is None else list(inputs), name=name)


def float_matrix(M: sp.MatrixBase, entry: str) -> np.ndarray:
    """The float64 array of a real exact matrix (correctly rounded entries)."""
    values = [[complex(sp.N(v, 20)) for v in row] for row in as_matrix(M, entry).tolist()]
    if any(v.imag for row in values for v in row):
        raise InputError(f"{entry}: complex entries; python-control needs a real system "
                         "(symkf.numeric.filters.real_form gives one with the same tr P_k)")
    return np.array([[v.real for v in row] for row in values])

check_public(globals())
