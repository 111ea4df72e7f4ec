"""Systems, sensors and actuators with exact data (Sui-You-Fu eqs. 1-3).

``x_{k+1} = A x_k + w_k``, ``y_k^i = C_i x_k + v_k^i`` with ``w ~ N(0, Q)``,
``v^i ~ N(0, R_i)`` and ``x_0 ~ N(xbar_0, P0)``.  A system with actuators is the plant
``x_{k+1} = A x_k + sum_i B_i u_k^i + w_k`` of LQG control over lossy networks, each actuator's
packet ``u^i`` sent over its own lossy channel, with the cost ``E sum_k (x_k' W x_k + u_k' U u_k)``
(Schenato, Sinopoli, Franceschetti, Poolla, Sastry, "Foundations of control and estimation over
lossy networks", 2007, Section II).  Every entry is exact (see
:mod:`symkf.exact.numbers`); covariances are checked Hermitian positive
definite exactly (Sylvester's criterion with certified signs); the process noise ``Q`` may be
singular (positive semidefinite, symmetric elimination with certified signs).
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any, Iterable, Mapping, Sequence

import flint
import sympy as sp

from ..arguments import check_public
from .. import budget
from ..errors import (InputError, NotPositiveDefiniteError, ShapeError, SingularSystemError, SymkfError,
                      UncontrollableError, UnobservableError)
from ..exact.algebraic import sign
from ..output import JsonDocument
from ..exact.numbers import as_matrix, decimal_matrix, rationalization, sympify, to_exact_matrix

if TYPE_CHECKING:
    from ..exact.spectral import Eigenvalue


def _compare_periods(A: sp.MatrixBase, decimal_A: Any, partial: sp.MatrixBase | None = None) -> str:
    """Whether reading the floats of A as nearby constants rather than as decimals changed its
    governing periods (they decide the critical values, Sui-You-Fu Theorem 7).  ``partial``: the
    reading with the constants recognised in part of a block, which was not taken (A is then read
    as decimals there); its periods are given beside the decimals'."""
    from ..exact.spectral import eigen_blocks

    def periods(M: Any) -> str:
        return str(tuple(b.governing_period for b in eigen_blocks(M)))
    decimal_M = decimal_A()
    try:
        exact, decimal = periods(A if partial is None else partial), periods(decimal_M)
    except SymkfError as exc:
        return f"governing periods not compared ({exc})"
    first = "the recognised constants" if partial is None else "the constants recognised in part (not taken)"
    verdict = "they DIFFER, so the critical values may too" if exact != decimal else "equal"
    taken = "" if partial is None and A != decimal_M else "; A is read with the plain decimals"
    return (f"governing periods of A: {exact} with {first}, {decimal} with the plain decimals ({verdict}; "
            f"None = aperiodic){taken}")


def _identity(n: int) -> sp.ImmutableMatrix:
    return sp.ImmutableMatrix(sp.eye(n))


def _hermitian(M: Any, entry: str) -> sp.MatrixBase:
    """``M`` as a square, Hermitian exact matrix (a covariance), or the entry that breaks it."""
    M = as_matrix(M, entry)
    if M.shape[0] != M.shape[1]:
        raise ShapeError(f"{entry}: covariance must be square, got {M.shape[0]}x{M.shape[1]}")
    for i in range(M.shape[0]):
        for j in range(i + 1, M.shape[0]):
            if sp.simplify(M[i, j] - sp.conjugate(M[j, i])) != 0:
                raise NotPositiveDefiniteError(
                    f"{entry}: not symmetric, entry [{i}][{j}] = {M[i, j]} but [{j}][{i}] = {M[j, i]}")
    return M


def check_positive_definite(M: sp.MatrixBase, entry: str) -> None:
    """Raise unless ``M`` is Hermitian positive definite (exact leading minors)."""
    M = _hermitian(M, entry)
    for k in range(1, M.shape[0] + 1):
        minor = sp.expand(M[:k, :k].det(method="berkowitz"))
        if sign(minor) <= 0:
            raise NotPositiveDefiniteError(
                f"{entry}: not positive definite, leading {k}x{k} minor is {sp.simplify(minor)}")


def check_positive_semidefinite(M: sp.MatrixBase, entry: str) -> None:
    """Raise unless ``M`` is Hermitian positive semidefinite, exactly.

    Symmetric elimination with diagonal pivots: a negative pivot, or a zero pivot whose row is not
    zero, gives a principal minor ``det M[S]`` below zero (the pivots' product times the last
    pivot, or times ``-|e|^2``), which the message names with its rows."""
    M = _hermitian(M, entry)
    n = M.shape[0]
    rest, pivots = list(range(n)), []
    if all(sympify(v).is_Rational for v in M):   # flint's rationals: sympy's cost n^3 / 3 expansions (n = 64: seconds)
        S = [[flint.fmpq(int(v.p), int(v.q)) for v in row] for row in M.tolist()]
        product, expand, signum, conj = flint.fmpq(1), (lambda v: v), (lambda v: int(v > 0) - int(v < 0)), (lambda v: v)
    else:
        S, product, expand, signum, conj = M.tolist(), sp.Integer(1), sp.expand, sign, sp.conjugate

    def fail(rows: list[int], minor: Any) -> None:
        minor = sp.Rational(int(minor.p), int(minor.q)) if isinstance(minor, flint.fmpq) else sp.simplify(minor)
        raise NotPositiveDefiniteError(
            f"{entry}: not positive semidefinite, the principal minor on rows {sorted(rows)} is {minor} < 0")
    for i in range(n):   # the plainest witness first: a negative variance
        if signum(S[i][i]) < 0:
            fail([i], S[i][i])
    while rest:
        i = rest.pop(0)
        d = expand(S[i][i])
        s = signum(d)
        if s < 0:
            fail(pivots + [i], product * d)
        if s == 0:
            for j in rest:
                if signum(expand(S[i][j] * conj(S[i][j]))) != 0:
                    fail(pivots + [i, j], -product * S[i][j] * conj(S[i][j]))
            continue
        for j in rest:
            for k in rest:
                S[j][k] = expand(S[j][k] - S[j][i] * S[i][k] / d)
        pivots.append(i)
        product *= d


@dataclass(frozen=True)
class Sensor:
    """One sensor: ``y^i = C_i x + v^i`` with ``v^i ~ N(0, R_i)``; R defaults to I (Sui-You-Fu eq. 2).

    Parameters
    ----------
    C : matrix-like
        The ``m_i x n`` measurement matrix: nested lists of exact numbers (ints, Fractions,
        sympy numbers or strings such as ``"sqrt(3)/2"``).
    R : matrix-like, optional
        The ``m_i x m_i`` noise covariance, Hermitian positive definite; default the identity.
    name : str, optional
        The sensor's name in verdicts and errors; :class:`System` names an unnamed sensor
        ``s1``, ``s2``, ... by its position.
    rationalize : bool, default False
        Accept binary floats, read as the exact rationals they denote; otherwise a float is an
        error (exact stays exact).

    Raises
    ------
    InputError
        An entry is not an exact number (or a float without ``rationalize``).
    ShapeError
        ``R`` is not ``m_i x m_i``.
    NotPositiveDefiniteError
        ``R`` is not Hermitian positive definite (exact leading minors).

    Examples
    --------
    Two channels, ``R`` defaulting to the 2 x 2 identity:

    >>> import symkf as sk
    >>> s = sk.Sensor(C=[[1, 0], [0, 1]], name="gps")
    >>> s.m, s.R
    (2, Matrix([
    [1, 0],
    [0, 1]]))

    A noise variance must be positive:

    >>> sk.Sensor(C=[[1, 0]], R=[[-1]])
    Traceback (most recent call last):
    ...
    symkf.errors.NotPositiveDefiniteError: sensor R: not positive definite, leading 1x1 minor is -1
    """

    C: Any
    R: Any = None
    name: str | None = None
    rationalize: bool | str = False

    def __post_init__(self) -> None:
        _read_channel(self, "sensor", "C", "R", "row")

    @property
    def m(self) -> int:
        """Number of measurement channels m_i."""
        return self.C.shape[0]


def _read_channel(channel: Any, kind: str, matrix: str, weight: str, vector: str) -> None:
    """Read a channel's exact matrix and its Hermitian positive definite weight in place: a
    sensor's ``C`` (rows are its outputs) and ``R``, an actuator's ``B`` (columns are its inputs)
    and ``U``; the weight defaults to the identity of the channel's size."""
    label = f"{kind} {channel.name!r}" if channel.name else kind
    with rationalization(kind.capitalize()):
        M = to_exact_matrix(getattr(channel, matrix), f"{label} {matrix}", rationalize=channel.rationalize,
                            vector=vector)
        k = M.shape[0] if vector == "row" else M.shape[1]
        given = getattr(channel, weight)
        W = _identity(k) if given is None else to_exact_matrix(
            given, f"{label} {weight}", rationalize=channel.rationalize, shape=(k, k))
    object.__setattr__(channel, matrix, M)
    check_positive_definite(W, f"{label} {weight}")
    object.__setattr__(channel, weight, W)


@dataclass(frozen=True)
class Actuator:
    """One actuator: the columns ``B_i`` of the input matrix that its control packet ``u^i``
    drives, with the weight ``U_i`` of ``u^i`` in the LQG cost; U defaults to I.

    The plant is ``x_{k+1} = A x_k + sum_i nu_k^i B_i u_k^i + w_k`` where ``nu_k^i`` is 1 when
    actuator ``i``'s packet arrives and 0 when it is lost, and the cost is
    ``E sum_k (x_k' W x_k + nu_k u_k' U u_k)`` (Schenato, Sinopoli, Franceschetti, Poolla,
    Sastry, "Foundations of control and estimation over lossy networks", 2007, Section II: the
    plant and the LQG cost functional, here with one lossy channel per actuator).

    Parameters
    ----------
    B : matrix-like
        The ``n x m_i`` input matrix of this actuator (``m_i >= 1`` columns), exact entries as
        for :class:`Sensor`; a flat list is one column.
    U : matrix-like, optional
        The ``m_i x m_i`` input weight of the LQG cost, Hermitian positive definite; default the
        identity.
    name : str, optional
        The actuator's name; :class:`System` names an unnamed actuator ``a1``, ``a2``, ... by
        its position.
    rationalize : bool, default False
        Accept binary floats, read as the exact rationals they denote.

    Raises
    ------
    InputError
        An entry is not an exact number (or a float without ``rationalize``).
    ShapeError
        ``U`` is not ``m_i x m_i``.
    NotPositiveDefiniteError
        ``U`` is not Hermitian positive definite (exact leading minors).

    Examples
    --------
    >>> import symkf as sk
    >>> a = sk.Actuator(B=[[0], [1]], name="thrust")
    >>> a.m, a.U
    (1, Matrix([[1]]))
    >>> sk.Actuator(B=[[0], [1]], U=[[0]])
    Traceback (most recent call last):
    ...
    symkf.errors.NotPositiveDefiniteError: actuator U: not positive definite, leading 1x1 minor is 0
    """

    B: Any
    U: Any = None
    name: str | None = None
    rationalize: bool | str = False

    def __post_init__(self) -> None:
        _read_channel(self, "actuator", "B", "U", "column")

    @property
    def m(self) -> int:
        """Number of inputs m_i (columns of B_i)."""
        return self.B.shape[1]


@dataclass(frozen=True)
class System(JsonDocument):
    """A linear system observed by ``d`` sensors over lossy channels.

    ``Q`` and ``P0`` default to the identity.  ``(A, C)`` with ``C`` the stack
    of all ``C_i`` must be detectable: every eigenvalue with ``|lambda| >= 1``
    seen by some sensor (PBH test); the error names an unseen one.  The papers
    assume observability; modes with ``|lambda| < 1`` never decide stability
    (:meth:`System.set_aside`).

    Parameters
    ----------
    A : matrix-like
        The ``n x n`` state matrix (Sui-You-Fu eq. 1), exact entries as for :class:`Sensor`.
    sensors : sequence of Sensor
        The ``d >= 1`` sensors, with distinct names (unnamed ones become ``s1``, ``s2``, ...).
    Q : matrix-like, optional
        Process-noise covariance, Hermitian positive semidefinite; default the identity.  A
        singular ``Q`` (a tracker's ``q G G'``) leaves the verdicts those of ``Q > 0`` when ``P0 > 0``
        (:meth:`System.undriven`); the one exception is refused by :func:`symkf.stability`.
    P0 : matrix-like, optional
        Covariance of ``x_0``, Hermitian positive definite; default the identity.
    rationalize : bool, default False
        Accept binary floats in ``A``, ``Q``, ``P0`` and ``W`` as the rationals they denote.
    name : str, optional
        A name for reports and tables.
    actuators : sequence of Actuator, keyword only
        The actuators of the LQG plant ``x_{k+1} = A x_k + B u_k + w_k`` with ``B = [B_1, ...,
        B_c]`` (Schenato et al., 2007, Section II), each on its own lossy channel; names
        distinct from each other and from the sensors' (unnamed ones become ``a1``, ``a2``, ...).
        Default none: an estimation-only system.
    W : matrix-like, keyword only, optional
        State weight of the LQG cost ``E sum_k (x_k' W x_k + u_k' U u_k)``, Hermitian positive
        semidefinite; default the identity.

    Raises
    ------
    InputError
        No sensor, a non-:class:`Sensor` or non-:class:`Actuator` entry, repeated names (an
        actuator's included), or an inexact entry.
    ShapeError
        ``A`` is not square, or a ``C_i``, ``B_i``, ``Q``, ``P0`` or ``W`` does not fit ``n``.
    NotPositiveDefiniteError
        ``Q`` or ``W`` is not Hermitian positive semidefinite or ``P0`` not positive definite.
    UnobservableError
        ``(A, C)`` is not detectable; the message names the unseen eigenvalue.

    Examples
    --------
    ``A = 2R(pi/2)`` (rotation by a quarter turn, scaled by 2) watched by two scalar sensors;
    the stacked ``C`` (eq. 3) is their rows in order:

    >>> import symkf as sk
    >>> S = sk.System(A=[[0, -2], [2, 0]], sensors=[sk.Sensor(C=[[1, 0]], name="s1"),
    ...                                             sk.Sensor(C=[[1, 1]], name="s2")])
    >>> S.n, S.d, S.sensor_names, S.observable
    (2, 2, ('s1', 's2'), True)
    >>> S.C
    Matrix([
    [1, 0],
    [1, 1]])

    ``diag(2, 3)`` seen only through its first coordinate: the eigenvalue 3 (``|3| >= 1``) has
    the eigenvector ``e_2`` in the kernel of ``C`` (PBH), so no Kalman filter can track it:

    >>> sk.System(A=[[2, 0], [0, 3]], sensors=[sk.Sensor(C=[[1, 0]])])  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    symkf.errors.UnobservableError: detectability of (A, C) fails: the eigenvalue 3 of A ...
    """

    A: Any
    sensors: Sequence[Sensor]
    Q: Any = None
    P0: Any = None
    rationalize: bool | str = False
    name: str | None = None
    actuators: Sequence[Actuator] = field(default=(), kw_only=True)
    W: Any = field(default=None, kw_only=True)
    _cache: dict = field(default_factory=dict, init=False, repr=False, compare=False, hash=False)

    def __getstate__(self) -> dict:
        # the cache is derived data (rebuilt on demand): pickles, e.g. to sweep workers, stay small
        return {**self.__dict__, "_cache": {}}

    def __post_init__(self) -> None:
        with rationalization("System") as record:
            self._read(record)
        self.check_detectable()

    @classmethod
    def _unchecked(cls, A: Any, sensors: Sequence[Sensor]) -> "System":
        """A system the engine derives from a checked one (a direct summand of its ``A``, a lifted
        orbit: :mod:`symkf.engine.cylinders`), read as any other but not required to be detectable: a
        mode that these sensors do not see is seen elsewhere in the system it came from."""
        out = object.__new__(cls)
        given = {"A": A, "sensors": sensors}
        for f in dataclasses.fields(cls):   # the others at their defaults
            object.__setattr__(out, f.name, given[f.name] if f.name in given else
                               f.default_factory() if f.default is dataclasses.MISSING else f.default)
        with rationalization("System") as record:
            out._read(record)
        return out

    def _read(self, record: Any) -> None:
        raw = self.A
        A = to_exact_matrix(raw, "A", rationalize=self.rationalize)
        if self.rationalize == "nearby" and any(e == "A" or e.startswith("A[") for e, *_ in record.changes):
            record.notes.append(_compare_periods(A, lambda: decimal_matrix(raw, "A"), record.partial.get("A")))
        if A.shape[0] != A.shape[1]:
            raise ShapeError(f"A: must be square, got {A.shape[0]}x{A.shape[1]}")
        n = A.shape[0]
        object.__setattr__(self, "A", A)
        if isinstance(self.sensors, Sequence) and not self.sensors:
            raise InputError("sensors: at least one sensor is needed")
        self._channels("sensors", Sensor, n)
        self._channels("actuators", Actuator, n, taken=self.sensor_names)
        for key, check in (("Q", check_positive_semidefinite), ("P0", check_positive_definite),
                           ("W", check_positive_semidefinite)):
            value = getattr(self, key)
            M = _identity(n) if value is None else to_exact_matrix(
                value, key, rationalize=self.rationalize, shape=(n, n))
            check(M, key)
            object.__setattr__(self, key, M)

    def _channels(self, key: str, kind: type, n: int, taken: Sequence[str] = ()) -> None:
        """Check and name the sensors (``key = "sensors"``, the rows of ``C``) or the actuators
        (``"actuators"``, the columns of ``B``) in place: each of ``kind``, fitting ``n``, counted
        against ``max_sensors`` before any is looked at, unnamed ones named by position (``s1``,
        ``a1``, ...), names distinct and none of them in ``taken``."""
        value = getattr(self, key)
        items = list(value) if isinstance(value, Sequence) else [value]
        budget.check("max_sensors", len(items), key, f"the number of {key}")
        matrix, axis = ("C", 1) if kind is Sensor else ("B", 0)
        names = []
        for i, c in enumerate(items):
            if not isinstance(c, kind):
                raise InputError(f"{key}[{i}]: expected a symkf.{kind.__name__}, got {type(c).__name__}")
            M = getattr(c, matrix)
            if M.shape[axis] != n:
                raise ShapeError(f"{key}[{i}].{matrix}{f' ({c.name!r})' if c.name else ''}: has {M.shape[axis]} "
                                 f"{('rows', 'columns')[axis]}, A is {n}x{n}")
            names.append(c.name or f"{key[0]}{i + 1}")
        if len(set(names)) != len(names):
            raise InputError(f"{key}: names must be distinct, got {names}")
        clash = [name for name in names if name in taken]
        if clash:
            raise InputError(f"{key}: the name {clash[0]!r} is also a sensor's; a system's sensors and actuators "
                             "share one namespace (files and commands name either by it), so rename one")
        object.__setattr__(self, key, tuple(c if c.name else dataclasses.replace(c, name=names[i])
                                            for i, c in enumerate(items)))

    @property
    def n(self) -> int:
        """State dimension ``n``."""
        return self.A.shape[0]

    @property
    def d(self) -> int:
        """Number of sensors ``d``."""
        return len(self.sensors)

    @property
    def C(self) -> sp.ImmutableMatrix:
        """The stacked ``C = col{C_1, ..., C_d}`` (eq. 3; cached: built once from the rows, as
        stacking d matrices pairwise costs time quadratic in d)."""
        cached = self._cache.get("C")
        if cached is None:
            rows = [list(s.C.row(i)) for s in self.sensors for i in range(s.C.rows)]
            cached = self._cache["C"] = sp.ImmutableMatrix(len(rows), self.n, [v for r in rows for v in r])
        return cached

    @property
    def R(self) -> sp.ImmutableMatrix:
        """Block-diagonal ``R = diag(R_1, ..., R_d)`` of the sensors' noise covariances (eq. 3)."""
        return sp.ImmutableMatrix(sp.diag(*[s.R for s in self.sensors]))

    @property
    def sensor_names(self) -> tuple[str, ...]:
        """The sensors' names, in order."""
        return tuple(s.name for s in self.sensors)

    @property
    def B(self) -> sp.ImmutableMatrix:
        """The input matrix ``B = [B_1, ..., B_c]`` of the actuators side by side (Schenato et al.,
        2007, Section II); ``n x 0`` when the system has no actuator."""
        return sp.ImmutableMatrix(sp.Matrix.hstack(sp.zeros(self.n, 0), *[a.B for a in self.actuators]))

    @property
    def U(self) -> sp.ImmutableMatrix:
        """Block-diagonal ``U = diag(U_1, ..., U_c)``, the input weight of the LQG cost; ``0 x 0``
        without actuators."""
        return sp.ImmutableMatrix(sp.diag(*[a.U for a in self.actuators]))

    @property
    def inputs(self) -> int:
        """Number of inputs: the columns of ``B`` (``len(system.actuators)`` counts the channels)."""
        return sum(a.m for a in self.actuators)

    @property
    def actuator_names(self) -> tuple[str, ...]:
        """The actuators' names, in order."""
        return tuple(a.name for a in self.actuators)

    def _pbh(self, key: str, A: sp.MatrixBase, C: sp.MatrixBase) -> frozenset:
        """The eigenvalue keys that :func:`symkf.exact.spectral.unseen` finds for ``(A, C)``, cached under ``key``."""
        cached = self._cache.get(key)
        if cached is None:
            from ..exact.spectral import unseen
            cached = self._cache[key] = unseen(A, C)
        return cached

    def unseen(self, lam: "Eigenvalue") -> bool:
        """PBH test: whether the eigenvalue ``lam`` (a :class:`~symkf.exact.spectral.Eigenvalue` of A)
        has an eigenvector in the kernel of every C_i (:func:`symkf.exact.spectral.unseen`, cached)."""
        return lam.key in self._pbh("unseen", self.A, self.C)

    def unreached(self, lam: "Eigenvalue") -> bool:
        """PBH test, the control dual of :meth:`unseen`: whether no actuator reaches the eigenvalue
        ``lam`` of A, i.e. ``rank [A - lam I, B] < n``: a left eigenvector ``w' A = lam w'`` with
        ``w' B = 0``, an eigenvector of ``A'`` in the kernel of ``B'`` (cached)."""
        return lam.key in self._pbh("unreached", self.A.T, self.B.T)

    @property
    def noise_definite(self) -> bool:
        """Whether ``Q > 0`` (cached): of full rank, ``Q`` being checked positive semidefinite."""
        cached = self._cache.get("noise_definite")
        if cached is None:
            from ..exact.linalg import rank
            cached = self._cache["noise_definite"] = rank(sp.Matrix(self.Q)) == self.n
        return cached

    def undriven(self) -> tuple["Eigenvalue", ...]:
        """The eigenvalues of ``A`` that the process noise does not drive (cached): PBH on
        ``(A, Q^(1/2))``, a left eigenvector ``w' A = lambda w'`` with ``Q w = 0`` (``range Q^(1/2) =
        range Q``); none when ``Q > 0``.

        With ``P0 > 0`` an undriven mode changes no verdict off the unit circle (the argument and
        its exact checks: ``proofs/sui_singular_process_noise.py``).  ``E[P_k]`` is monotone in
        ``Q``, so a stable verdict for ``Q + I`` holds for ``Q``; and the lower bound ``P_N >= p I``
        that the necessity half of Sui-You-Fu Theorems 4 and 7 takes from ``Q > 0`` holds for
        ``Q = 0`` on the modes with ``|lambda| > 1``: there ``A^(-1)`` is stable, so the information
        ``P_N^(-1)`` gathered from ``x_0`` and every measurement is bounded.  On the unit circle an
        undriven mode's error need not grow: :func:`symkf.stability` refuses a verdict that such a
        mode decides."""
        cached = self._cache.get("undriven")
        if cached is None:
            from ..exact.spectral import unseen
            keys = frozenset() if self.noise_definite else unseen(self.A.T, self.Q)
            cached = self._cache["undriven"] = tuple(
                lam for block in self.eigen_blocks() for lam in block.members if lam.key in keys)
        return cached

    def _full_rank(self, key: str, A: sp.MatrixBase, C: sp.MatrixBase, missed: Any) -> bool:
        """Whether ``(A, C)`` is observable (cached under ``key``): the exact rank of
        ``col{C, CA, ..., CA^(n-1)}`` over Q, else no eigenvalue ``missed`` (Hautus), decided per
        diagonal block of A in its own field.  ``(A', B')`` gives controllability."""
        cached = self._cache.get(key)
        if cached is None:
            if all(sympify(v).is_Rational for M in (A, C) for v in M):
                from ..exact.linalg import krylov_rank
                cached = C.rows > 0 and krylov_rank(A, C) == self.n
            else:
                cached = not any(missed(e) for b in self.eigen_blocks() for e in b.members)
            self._cache[key] = cached
        return cached

    @property
    def observable(self) -> bool:
        """Whether ``(A, C)`` is observable (cached): the exact rank of the observability matrix
        over Q, else no eigenvalue unseen (Hautus), decided per diagonal block of A in its own field."""
        return self._full_rank("observable", self.A, self.C, self.unseen)

    @property
    def controllable(self) -> bool:
        """Whether ``(A, B)`` is controllable (cached), as :attr:`observable` decides ``(A', B')``;
        False without actuators (for ``n >= 1``)."""
        return self._full_rank("controllable", self.A.T, self.B.T, self.unreached)

    @property
    def stabilizable(self) -> bool:
        """Whether ``(A, B)`` is stabilizable (cached): ``rank [A - lambda I, B] = n`` for every
        eigenvalue with ``|lambda| >= 1`` (PBH), the assumption under which the LQG controller of
        Schenato et al. (2007, Section II) exists without losses.  True when every mode is stable,
        even without actuators."""
        cached = self._cache.get("stabilizable")
        if cached is None:
            cached = self._cache["stabilizable"] = self._unreached_unstable() is None
        return cached

    def _unreached_unstable(self) -> tuple[Any, "Eigenvalue"] | None:
        """The first (block, eigenvalue) with ``|lambda| >= 1`` that no actuator reaches, or None."""
        if self.controllable:
            return None
        return next(((block, lam) for block in self.eigen_blocks() if not block.is_stable
                     for lam in block.members if self.unreached(lam)), None)

    def check_stabilizable(self) -> None:
        """Raise :class:`~symkf.errors.UncontrollableError` naming an eigenvalue with
        ``|lambda| >= 1`` that no actuator reaches (PBH: ``rank [A - lambda I, B] < n``).

        Stabilizability of ``(A, B)`` is what LQG control needs (Schenato et al., 2007, Section
        II); a mode with ``|lambda| < 1`` that no actuator reaches decays by itself.  Not checked
        at construction: an estimation-only system has no actuator.

        >>> import symkf as sk
        >>> S = sk.System(A=[[2, 0], [0, "1/2"]], sensors=[sk.Sensor(C=[[1, 1]])],
        ...               actuators=[sk.Actuator(B=[[0], [1]], name="u")])
        >>> S.stabilizable
        False
        >>> S.check_stabilizable()  # doctest: +ELLIPSIS
        Traceback (most recent call last):
        ...
        symkf.errors.UncontrollableError: (A, B) stabilizable: ... the eigenvalue 2 of A ...
        """
        if self.stabilizable:
            return
        block, lam = self._unreached_unstable()
        raise UncontrollableError(
            f"the eigenvalue {lam.expr} of A (|lambda| = {block.modulus} >= 1) is not reached by any actuator"
            + ("" if self.actuators else " (the system has none)") + ", so (A, B) is not stabilizable",
            assumption="(A, B) stabilizable: PBH rank [A - lambda I, B] = n for |lambda| >= 1",
            applies_instead=f"add an actuator acting on the mode of {lam.expr} (a column of B not orthogonal to "
                            "its left eigenvector), or estimation alone (symkf.stability), which needs no actuator")

    def check_detectable(self) -> None:
        """Raise :class:`UnobservableError` naming an eigenvalue with ``|lambda| >= 1`` that no sensor sees.

        Detectability (PBH on ``|lambda| >= 1`` only) is what a Kalman filter needs: an unseen
        mode with ``|lambda| < 1`` decays by itself and is set aside (:meth:`set_aside`)."""
        if self.observable:
            return
        for block in self.eigen_blocks():
            for lam in block.members:
                if not block.is_stable and self.unseen(lam):
                    unit = block.modulus == 1 and lam.key in {e.key for e in self.undriven()}
                    raise UnobservableError(
                        f"the eigenvalue {lam.expr} of A (|lambda| = {block.modulus} >= 1) is not seen by any "
                        "sensor (PBH rank test), so (A, C) is not detectable" + (
                            "; it is not driven by Q either, so its error need not grow, which the theory "
                            "(Sui-You-Fu, Q > 0) does not decide" if unit else ""),
                        assumption="detectability of (A, C)",
                        applies_instead="a sensor set whose stacked C sees every mode with |lambda| >= 1" + (
                            ", or a model without this undriven mode, or with process noise on it" if unit else ""))

    def eigen_blocks(self) -> tuple[Any, ...]:
        """:func:`symkf.exact.spectral.eigen_blocks` of ``A`` (cached)."""
        cached = self._cache.get("eigen_blocks")
        if cached is None:
            from ..exact.spectral import eigen_blocks
            cached = self._cache["eigen_blocks"] = eigen_blocks(self.A)
        return cached

    def set_aside(self) -> tuple[tuple[Any, str], ...]:
        """The eigen-blocks of modulus < 1 left out of the verdict, each with the reason (cached).

        A block with ``alpha_i < 1`` has margin ``alpha_i^2 rho_i <= alpha_i^2 < 1`` and never
        decides stability.  symkf keeps such a block in the verdict when the papers' analysis
        applies to it (diagonalizable, nonzero, every mode seen) and sets it aside otherwise:
        zero eigenvalues, stable Jordan chains, stable modes no sensor sees."""
        cached = self._cache.get("set_aside")
        if cached is None:
            out = []
            for block in self.eigen_blocks():
                if not block.is_stable:
                    continue
                names = ", ".join(e.label for e in block.members)
                if block.modulus == 0:
                    out.append((block, "eigenvalue 0: its modes vanish after finitely many steps"))
                elif block.defective:
                    out.append((block, f"eigenvalue(s) {names} with Jordan chains and |lambda| = "
                                       f"{block.modulus} < 1: they decay without measurements"))
                elif any(self.unseen(e) for e in block.members):
                    out.append((block, f"eigenvalue(s) {names} with |lambda| = {block.modulus} < 1, not all "
                                       "seen by the sensors: detectability suffices"))
            cached = self._cache["set_aside"] = tuple(out)
        return cached

    def require_invertible_A(self) -> None:
        """Lemma 2 (Sui-You-Fu) needs A invertible."""
        if self.A.det() == 0:
            raise SingularSystemError("A is singular (det A = 0)",
                                      assumption="Lemma 2 (Sui-You-Fu): A invertible")

    def __repr__(self) -> str:
        """Short: the size, the sensors, the actuators if any, and A (the matrices in full: ``.A``,
        ``.C``, ``.B``, ``.Q``, ``.P0``)."""
        def rows(M: Any) -> str:
            return "[" + ", ".join("[" + ", ".join(map(str, M.row(i))) + "]" for i in range(M.rows)) + "]"

        def listed(channels: Sequence[Any], matrix: str, what: str) -> str:
            shown = ", ".join(f"{c.name} " + (rows(getattr(c, matrix)) if self.n <= 4 else
                                              "<{}x{}>".format(*getattr(c, matrix).shape)) for c in channels[:8])
            return f"{what}: {shown}" + (f", ... ({len(channels)} {what})" if len(channels) > 8 else "")
        A = rows(self.A) if self.n <= 4 else f"<{self.n}x{self.n}>"
        name = f"{self.name!r}, " if self.name else ""
        acting = f", {listed(self.actuators, 'B', 'actuators')}" if self.actuators else ""
        return f"System({name}n={self.n}, A={A}, {listed(self.sensors, 'C', 'sensors')}{acting})"

    def to_dict(self) -> dict[str, Any]:
        """The system file's tables (``[system]`` with the name when there is one, ``[[sensors]]``,
        and ``[[actuators]]`` with ``W`` in ``[system]`` when the system has actuators or a ``W``
        other than I: docs/formats.md), entries as exact strings that the file reader takes back."""
        def rows(M: Any) -> list[list[str]]:
            return [[str(v) for v in M.row(i)] for i in range(M.rows)]
        named: dict[str, Any] = {"name": self.name} if self.name else {}
        control = bool(self.actuators) or self.W != _identity(self.n)
        weighted: dict[str, Any] = {"W": rows(self.W)} if control else {}
        acting = {"actuators": [{"name": a.name, "B": rows(a.B), "U": rows(a.U)} for a in self.actuators]} \
            if self.actuators else {}
        return {"system": {"A": rows(self.A), "Q": rows(self.Q), "P0": rows(self.P0), **weighted, **named},
                "sensors": [{"name": s.name, "C": rows(s.C), "R": rows(s.R)} for s in self.sensors], **acting}

    def _repr_latex_(self) -> str:
        """``A``, the stacked ``C`` (Sui-You-Fu eq. 3) and, with actuators, ``B`` (Schenato et al.,
        2007, Section II) for a notebook."""
        names = ", ".join(self.sensor_names)
        acting = rf" + {sp.latex(self.B)}\, u_k" if self.actuators else ""
        actuators = f"; actuators {', '.join(self.actuator_names)}" if self.actuators else ""
        return (rf"$x_{{k+1}} = {sp.latex(self.A)}\, x_k{acting} + w_k,\quad y_k = {sp.latex(self.C)}\, x_k + v_k"
                rf"\quad(\text{{sensors {names}{actuators}}})$")

    def sensor_index(self, name: str) -> int:
        """Position of the sensor called ``name``; :class:`~symkf.errors.InputError` listing the names if none."""
        return _position(self.sensor_names, name, "sensor")

    def actuator_index(self, name: str) -> int:
        """Position of the actuator called ``name``; :class:`~symkf.errors.InputError` listing the names if none."""
        return _position(self.actuator_names, name, "actuator")

    @classmethod
    def from_statespace(cls, sys: Any, sensors: Mapping[str, Iterable[int]] | Sequence[str] | None = None,
                        actuators: Mapping[str, Iterable[int]] | Sequence[str] | None = None, *, Q: Any = None,
                        R: Mapping[str, Any] | None = None, P0: Any = None, W: Any = None,
                        U: Mapping[str, Any] | None = None, rationalize: bool | str = False,
                        name: str | None = None) -> System:
        """The system ``(A, C)``, with its actuators ``B``, of a discrete-time python-control
        ``StateSpace`` (``D`` is not used; python-control carries no noise and no cost, so ``Q``,
        ``P0``, ``W``, the sensors' ``R`` and the actuators' ``U``, mappings from name to matrix,
        are given here and default to identities).

        ``sensors`` splits the rows of ``C``: a mapping from sensor name to row indices, a list
        of names (one row each), or None (one sensor per row, named by ``sys.output_labels``);
        ``actuators`` splits the columns of ``B`` likewise (None: one actuator per input, named
        by ``sys.input_labels``; none when ``B`` is zero, as the ``no_input`` of
        :meth:`to_statespace` without actuators); see
        :func:`symkf.model.statespace.statespace_parts`. python-control stores float64, so
        entries that are not exact in binary need ``rationalize`` (True: the shortest decimal;
        ``"nearby"``: a nearby exact constant).

        >>> import control as ct
        >>> plant = ct.ss([[0, -2], [2, 0]], [[0], [1]], [[1, 0], [1, 1]], 0, dt=1, inputs=["u"])
        >>> S = System.from_statespace(plant, {"s1": [0], "s2": [1]}, rationalize=True)
        >>> S.sensor_names, S.actuator_names, S.A.tolist(), S.B.tolist()
        (('s1', 's2'), ('u',), [[0, -2], [2, 0]], [[0], [1]])
        """
        from .statespace import statespace_parts
        A, parts, inputs = statespace_parts(sys, sensors, R, actuators, U)
        return cls(A=A, Q=Q, P0=P0, W=W, rationalize=rationalize, name=name or sys.name,
                   sensors=[Sensor(C=C, R=Rs, name=s, rationalize=rationalize) for s, (C, Rs) in parts.items()],
                   actuators=[Actuator(B=B, U=Ua, name=a, rationalize=rationalize) for a, (B, Ua) in inputs.items()])

    def to_statespace(self, B: Any = None, D: Any = None, dt: float | bool = 1) -> Any:
        """This system as a python-control ``StateSpace`` (float64, the ``control`` extra): ``A``,
        the stacked ``C`` and the actuators' ``B``; the rows of sensor ``s`` with ``m`` rows
        labelled ``s`` (``m = 1``) or ``s[0]``, ..., ``s[m-1]``, the inputs of each actuator
        likewise.  A ``B`` given here replaces the actuators' (inputs labelled by python-control);
        ``B``, ``D`` and ``dt`` as :func:`symkf.model.statespace.statespace_of` (default without
        actuators: one input that does not act, ``dt = 1``: one step of ``x_{k+1} = A x_k + w_k``).
        ``Q`` and ``R`` for ``control.dlqe`` are :func:`~symkf.model.statespace.float_matrix` of
        ``Q`` and ``R``.

        >>> S = System(A=[[0, -2], [2, 0]], sensors=[Sensor(C=[[1, 0]], name="s1")])
        >>> G = S.to_statespace()
        >>> G.output_labels, G.input_labels, G.dt
        (['s1'], ['no_input'], 1)
        >>> S = System(A=S.A, sensors=S.sensors, actuators=[Actuator(B=[[0], [1]], name="u")])
        >>> S.to_statespace().input_labels
        ['u']
        """
        from .statespace import float_matrix, statespace_of
        inputs = None
        if B is None and self.actuators:
            B, inputs = float_matrix(self.B, "B"), _labels(self.actuators)
        return statespace_of(self.A, self.C, _labels(self.sensors), self.name, B, D, dt, inputs=inputs)


def _labels(channels: Sequence[Any]) -> list[str]:
    """One label per output of the sensors (or input of the actuators): ``s`` for a single one,
    ``s[0]``, ..., ``s[m-1]`` for ``m`` of them."""
    return [c.name if c.m == 1 else f"{c.name}[{j}]" for c in channels for j in range(c.m)]


def _position(names: tuple[str, ...], name: str, kind: str) -> int:
    try:
        return names.index(name)
    except ValueError:
        raise InputError(f"no {kind} named {name!r}; {kind}s are {list(names)}") from None


check_public(globals())
