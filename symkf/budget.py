"""Resource budgets: caps checked before heavy work, refused early with a clear message.

Each cap bounds an *estimate* made before any expensive computation starts (the algebraic
degree of a parsed number, the size of a matrix, the states of a lifted Markov chain, the
memory of a Monte Carlo run, ...); ``max_work`` bounds the estimated CPU time of a heavy step,
priced by :func:`price` from its units of work at their measured costs (:data:`COSTS`), so that
a step estimated under it runs whatever the size of its input.  A refusal is a :class:`~symkf.errors.BudgetError` that
names the entry, the estimate, the cap, and how to raise it: the keyword of
:func:`limits` in Python, the option in :data:`OPTIONS` on the command line.

>>> from symkf import budget
>>> with budget.limits(max_degree=128):   # doctest: +SKIP
...     sk.System(A, sensors)

Limits are process-wide; :func:`symkf.run.sweep.sweep` hands the caller's caps to its worker processes.
"""

from __future__ import annotations

import contextlib
import dataclasses
import math
import numbers
import sys
import time
from dataclasses import dataclass
from typing import Callable, Iterator

from .arguments import check_public
from .errors import BudgetError, InputError


@dataclass
class Limits:
    """The caps (defaults in brackets are chosen so that every example of the papers passes; the
    costs they were sized on: docs/caps.md)."""

    #: algebraic degree over Q of a field with radicals, bounded by the product of the degrees of
    #: its radicals and trigonometric constants, times the size of the diagonal block of A whose
    #: eigenvalues it holds: such fields are built generically (sympy's minimal_polynomial,
    #: Trager's norm), whose cost explodes with the degree
    max_degree: int = 64
    #: a quarter of the degree of the cyclotomic field Q(zeta_m) holding the trigonometric constants
    #: and I of a number or matrix without radicals (its real subfield for real entries), times the
    #: size of the diagonal block: presented by zeta_m or 2 cos(2 pi/m), its arithmetic is cheap and
    #: its roots come from Euler's formula (2R(2 pi/1601), degree 3200: 2.1 CPU-s, 104 MB, passes;
    #: 2R(2 pi/2053), degree 4104, is refused);
    #: also phi(g) for an eigen-block over several diagonal blocks, g its class period (its field
    #: holds Q(zeta_g): four rotations 2R(2 pi/q), q = 5, 7, 9, 11, give phi(3465) = 1440; decided
    #: part by part first, symkf.engine.cylinders), and the degree of the field of all entries of the LMI
    #: of the bounds atlas, where its certificates are checked
    max_cyclotomic_degree: int = 1024
    #: bit size of the polynomial of the modulus of a complex eigenvalue of degree d, whose
    #: construction and factorisation are the cost: (d(d - 1) + 1) (d - 1) sum_i log2(1 + abs(c lambda_i))
    #: for the products of pairs of conjugates (symkf.exact.spectral._pair_modulus_poly; a dense 64 x 64
    #: integer A has 5.6e7 bits and passes, a 16 x 16 A over Q(sqrt 2) 2.7e7), else (2D + 1) D b, D = d(d+1)/2, for the power sums of
    #: all products (symkf.exact.spectral._abs_poly) of a b-bit minimal polynomial
    max_modulus_bits: int = 2 ** 26
    #: nesting depth of radicals (sqrt(2 + sqrt(3)) has depth 2)
    max_nesting: int = 4
    #: denominator q of an angle p*pi/q inside cos, sin, tan or exp (degree grows like q; the
    #: cyclotomic cap bounds the field, this one a single constant: 2R(2 pi/1601) passes both)
    max_angle_denominator: int = 4096
    #: modulus of an integer exponent (x**e) and decimal digits of any number
    max_exponent: int = 10_000
    max_digits: int = 1000
    #: characters of the text of one number
    max_number_length: int = 1000
    #: bit size (height) of an exact number, estimated before it is evaluated: the larger of a
    #: rational's numerator and denominator bits; for an algebraic number a bound on its
    #: absolute logarithmic (Weil) height in bits, the size that the engine's polynomial arithmetic
    #: and root isolation pay for, steeply beyond a thousand bits (a rotation block with an entry
    #: 10^-230 has 764 bits)
    max_bits: int = 768
    #: bits of precision of one certified ball (flint's ``acb``/``arb``), asked directly (``ball``,
    #: ``root_ball``, ``theta_ball``) or through a width, a number of digits or a power: flint
    #: allocates for it and aborts the process when it cannot (2^40 bits hang, sys.maxsize crashes),
    #: so it is checked before flint is asked; the engine's own refinements stay far below it
    max_precision: int = 2 ** 20
    #: rows or columns of a matrix (state dimension n, measurement channels; the exact engine's
    #: work on a dense system grows steeply with n, and is priced by max_modulus_bits: a dense
    #: 64 x 64 integer A with 3 sensors takes about a minute)
    max_dimension: int = 64
    #: sensors d of a system or loss model: a memory bound on what is read and held before any
    #: work is priced (a sensor and its rows, a loss per sensor: kilobytes each, so 2^14 of them
    #: take tens of MB); the work that grows with d is priced by ``max_work`` (independent sensors
    #: are decided per sensor, never through the joint 2^d-state chain, whose states
    #: ``max_markov_states`` bounds)
    max_sensors: int = 2 ** 14
    #: states of a joint (lifted) Markov loss chain: its S^2 exact entries are read and built, and its
    #: stationary law solved (S^3), whatever the query; 256 states (four correlated sensor pairs):
    #: about 3 CPU-s in all, 512: 26
    max_markov_states: int = 256
    #: estimated CPU milliseconds of one heavy step (60 000: a minute), priced before it starts by
    #: :func:`price` from its
    #: units of work and their costs (:data:`COSTS`, measured on the machine of docs/caps.md; a
    #: step estimated under it runs whatever the size of its input): the hyperplane screen
    #: (symkf.engine.hyperplane_screen: the points each stage classifies, and point-line
    #: incidences, about ``C(C, n - 2)`` per stage for ``C`` classes in an n-dim block, with a
    #: window of ``W`` classes ``C(W, n - 3) C + 10^4 C(W, n - 4)``), the two screens of a Markov loss's
    #: search together, the search through flats (symkf.engine.flat_screen), closing the sets a
    #: screen keeps (``kept sets x points``), and the hyperplanes a decay rate lists when no screen
    #: applies (``C(V, n - 1)`` for V distinct generators in K^n, or fewer through the flats of
    #: elements of several generators: BlockRows.listing_estimate; times the degree of K; their
    #: memory meets ``max_memory``), a margin polynomial built for each listed hyperplane, the LMIs of
    #: Theorem 4 (symkf.capacity.convergence.price_lmi; the bounds atlas's bisection at once), and the
    #: control threshold's quotient bound and continuation (symkf.control.threshold), the design
    #: queries upgrades, allocate_recovery and pareto_front, and symkf.fusion's local filters and expected covariance.  A 4-dim block of period 24 with 1024 sensors: 2.5e7 points and 2.4e8
    #: incidences, 31.5 CPU-s estimated, 13.5 measured; on Gilbert-Elliott channels its two screens,
    #: 63, refused at once; eight 2R(pi/97) blocks, one 16-dim eigen-block, with 64 sensors: about
    #: 10^42 incidences
    max_work: int = 60_000
    #: receival sequences ``2^(d (horizon - 1))`` that the exact mean trace enumerates
    #: (symkf.numeric.montecarlo.exact_mean_covariances and exact_mean_trace; estimate_mean_trace simulates),
    #: and ``2^(d N)`` that the brute-force symkf.engine.rates.probability_rank_deficient enumerates
    max_patterns: int = 2 ** 20
    #: (sensor, span) states of the probability that the received rows have full column rank
    #: (symkf.network.full_rank_probability_of, Quevedo et al.'s Pr{r = 1}), each one visited, bounded
    #: before it starts by sum_{k < n} C(M + 1, k + 1) for M sensors in dimension n (reached by rows
    #: in general position; 24 scalar sensors of a 6-state system have 245,505)
    max_span_states: int = 1_000_000
    #: hyperplanes of the exact verdict's limiting block that a Monte Carlo plan
    #: (symkf.numeric.montecarlo.verdict_plan) lists to find the bursts whose rate ties with the decisive
    #: one; above it the plan keeps the decisive pattern and its shifts only (no refusal)
    max_tie_search: int = 512
    #: rows of all sensors up to which Theorem 5's common threshold (symkf.capacity.compare) is
    #: maximised over every row order (r! Wonham decompositions: 6 rows, 720); above it the given
    #: order only (no refusal)
    max_order_rows: int = 6
    #: degree of an eigenvalue ratio's polynomial (the product of the two eigenvalues' degrees)
    #: up to which an aperiodicity proof prints the ratio's minimal polynomial, a resultant of that
    #: degree (1024 for the degree-32 eigenvalues of a dense 16 x 16 system: a costly resultant); above it,
    #: when the certified argument already proves it, the proof is printed from the argument
    max_proof_resultant_degree: int = 64
    #: size ``n d`` of the rational matrix whose characteristic polynomial is the norm of an
    #: n x n chain block's with entries in a number field of degree d (the exact Perron root,
    #: symkf.exact.perron_field): its cost grows like (n d)^4
    max_norm_dimension: int = 256
    #: degree C(m, k) of the polynomial of a product of k of the m conjugate roots of an
    #: eigenvalue's minimal polynomial (the Mahler measure of a dense A: its eigenvalues outside
    #: the unit circle): generically that product's own degree, whose roots' isolation is the cost
    #: (dense random integer A: 12 x 12 with k = 6 gives 924, 14 x 14 with k = 7 gives 3432)
    max_compound_degree: int = 1024
    #: states of the lifted chain of a network loss read from a file, bounded before it is built by
    #: (network states, or the sum over states of the longest holding time) times 2^M link outcomes
    max_network_chain: int = 4096
    #: items of one list or tuple argument of a call from outside symkf that holds sympy numbers,
    #: or rows and columns of such a matrix: each is priced at the boundary
    #: (symkf.arguments.PRICERS) at a cost per item, so a longer one is refused before the first
    #: is priced (the longest lists symkf reads, a network state's rows under max_network_chain, fit)
    max_priced_items: int = 4096
    #: members of a family file
    max_members: int = 2000
    #: bytes of the arrays one Monte Carlo run allocates at its peak, as estimated by
    #: symkf.numeric.montecarlo.memory_estimate (traces, receptions, kernel lanes, likelihood ratios,
    #: per-step records; within 1.5x of peak RSS: tests/numeric/test_memory_estimate.py)
    max_memory: int = 2 * 1024 ** 3
    #: bytes of an input file
    max_file_size: int = 1024 ** 2
    #: seconds a Dask scheduler may take to answer, and to have a worker (symkf.run.scheduler)
    scheduler_timeout: int = 20


#: the command-line option that raises each cap
OPTIONS = {f.name: "--" + f.name.replace("_", "-") for f in dataclasses.fields(Limits)}

#: the limits in force
LIMITS = Limits()

#: CPU seconds per unit of each kind of work that :func:`price` prices against ``max_work``,
#: measured on the machine of docs/caps.md (shared, 2 cores with AVX-512; fitted within 3x on the
#: rows of ``benchmarks/bench_markov_search.py``: many sensors, and the listed general-position block)
COSTS = {
    #: a point reduced mod the stage's point and classified (a sort of packed keys) at one stage of
    #: the hyperplane screen
    "screen point": 0.5e-6,
    #: a point-line incidence tested by the hyperplane screen (a vectorised pass counts as
    #: ``hyperplane_screen.PASS`` of them)
    "incidence": 0.08e-6,
    #: a hyperplane listed (its generators' set built and counted, ``BlockRows.inside``), per degree
    #: of the block's field: 1.2 million over a field of degree 8 took 12 CPU-s, 597 000 over one of
    #: degree 120 51 CPU-s
    "hyperplane degree": 1e-6,
    #: the same through the flats of elements of several generators (multi-row sensors), each
    #: hyperplane found by exact echelon forms over the field: 18 240 over a field of degree 8 took
    #: 1.4 CPU-s, 1 970 640 over one of degree 4 (a 6-dim block) 52 CPU-s
    "flat hyperplane degree": 8e-6,
    #: a hyperplane's margin built in flint as a polynomial in the recovery rate (the critical
    #: recovery rate's list, symkf.engine.recovery.listed_margins), per hyperplane of the listing's
    #: estimate: 11 to 26 µs on the rows of benchmarks/bench_margin_cost.py (4- and 6-dim blocks,
    #: fields of degree 4 to 48; C(36, 5) = 376 992 of the 6-dim block (3/2) diag(R(pi/2), R(pi/3),
    #: R(2 pi/3)) with three Gilbert-Elliott sensors, 6.9 CPU-s)
    "margin": 20e-6,
    #: the same margin built in sympy as a polynomial in the loss model's parameters (the symbolic
    #: stable set, symkf.engine.region.ge_margins): 132, 214 and 267 µs on the same rows' period 35
    #: with two and three sensors and period 24 with four
    "symbolic margin": 200e-6,
    #: a point tested against a set kept by a screen, to close it mod p (the kept sets of a low
    #: floor: each is closed over every point, then confirmed exactly)
    "kept point": 0.5e-6,
    #: a unit C(D, k)^1.5 of a product of k of the D conjugate eigenvalues in the control quotient
    #: bound (symkf.control.threshold.quotient_bound: summed over its quotients)
    "quotient degree": 40e-6,
    #: an entry of A per quotient of that bound (its cofactor h(A) and the rank of h(A) B)
    "quotient entry": 47e-6,
    #: a unit of an exact certificate's solve in the control threshold (symkf.control.threshold:
    #: (n^2 deg K)^2 n^2 per solve of the n^2 unknowns of S - T(S) = I)
    "stein entry": 0.6e-8,
    #: a unit (n^2)^3 of a policy evaluation of that continuation (a solve in 256-bit balls)
    "policy entry": 2e-8,
    #: a critical i.i.d. loss rate of a design query (symkf.design.upgrades: along a ray) per
    #: square of the number of sensors d (its heaviest-hyperplane search grows about so)
    "ray query": 0.5e-3,
    #: a critical recovery rate of one sensor's channel (symkf.design.allocate_recovery), apart from
    #: its sensors
    "recovery query": 0.04,
    #: the same per square of the number of sensors d (its screens grow about so)
    "recovery pair": 0.75e-3,
    #: a point of symkf.design.pareto_front (a covering search and a critical rate; d points priced)
    "front point": 0.25,
    #: the same, per square of the number of sensors d
    "front pair": 1.7e-3,
    #: a local filter of the fusion set-up (symkf.fusion.local_filters: a Riccati equation per sensor)
    "local filter": 1e-3,
    #: a unit M^3 of a dense float solve of size M (the joint Stein equation of symkf.fusion.local_filters)
    "float cube": 5e-9,
    #: a Stein equation of a pair of sensors solved by symkf.fusion.expected_remote_covariance, apart
    #: from its size
    "fusion pair": 70e-6,
    #: a unit (n_i n_j)^3 of such an equation, a dense solve of n_i n_j unknowns
    "stein float": 6e-11,
    #: a unit M^3 of the fusion weights of an M x M Sigma by Theorem 2's closed form or Problem 3's
    #: linear system (symkf.fusion.optimal_weights: an eigenvalue check, SVDs and a pseudo-inverse)
    "weights cube": 8e-10,
    #: a unit M^4 of the same weights by Problem 2's SDP (an interior-point solve with an M x M
    #: matrix variable)
    "weights sdp entry": 4e-7,
    #: a block P^(ij) of the joint covariance of symkf.fusion.simulate_fusion's holding times, built
    #: the first time (matrix powers and sums of the block's pair of sensors)
    "fusion block": 300e-6,
    #: an LMI of Theorem 4 (Yang et al.) set up, solved and checked, apart from its size
    #: (symkf.capacity.convergence.price_lmi; small ones take this)
    "lmi": 0.03,
    #: an entry of a basis matrix of that LMI written in SymPy
    #: (symkf.capacity.convergence.price_lmi: the bounds atlas's LMI row bisects on it)
    "lmi basis entry": 15e-6,
    #: a unit ``N^2 V`` of that LMI's SDP, its size ``N`` and coordinates ``V``
    "lmi sdp entry": 0.05e-6,
}


#: the largest ``max_digits``: :func:`limits` lets Python convert integers of twice that many
#: digits to text, and Python's limit is a C int
MAX_DIGITS_CAP = (2 ** 31 - 1) // 2


@contextlib.contextmanager
def limits(**caps: int) -> Iterator[Limits]:
    """Raise (or lower) caps inside a ``with`` block, e.g. ``limits(max_degree=128)``; Python's
    limit on int <-> str conversion follows ``max_digits``."""
    unknown = sorted(map(str, set(caps) - set(OPTIONS)))
    if unknown:
        raise InputError(f"unknown cap(s) {unknown}; caps are {sorted(OPTIONS)}")
    for name, value in caps.items():
        if isinstance(value, bool) or not isinstance(value, int) or value < 1:
            raise InputError(f"{name}: expected a positive integer, got {type(value).__name__}")
    if caps.get("max_digits", 1) > MAX_DIGITS_CAP:
        raise InputError(f"max_digits: {caps['max_digits']} is above {MAX_DIGITS_CAP}, the most digits "
                         "Python converts between integers and text")
    saved, digits = dataclasses.asdict(LIMITS), sys.get_int_max_str_digits()
    for name, value in caps.items():
        setattr(LIMITS, name, value)
    sys.set_int_max_str_digits(max(digits, 2 * LIMITS.max_digits))
    try:
        yield LIMITS
    finally:
        for name, value in saved.items():
            setattr(LIMITS, name, value)
        sys.set_int_max_str_digits(digits)


def check(cap: str, estimate: int, entry: str, what: str | Callable[[], str]) -> None:
    """Refuse when ``estimate`` of ``what`` for ``entry`` exceeds the cap named ``cap``
    (``what`` may be a function giving the words, called only when refusing: writing a large
    expression out costs more than checking it)."""
    bound = getattr(LIMITS, cap)
    if estimate > bound:
        what = what if isinstance(what, str) else what()
        raise BudgetError(f"{entry}: {what} is {_shown(estimate)}, above the cap {bound}; {_raise_it(cap)}")

def seconds(**units: float) -> float:
    """The estimated CPU seconds of ``units`` of work: per kind of :data:`COSTS` (spaces written
    as underscores, ``seconds(screen_point=P, incidence=I)``) its amount times its cost."""
    return sum(_cost(kind) * float(min(_amount(kind, amount), 1e300)) for kind, amount in units.items())


def affordable(kind: str, **beside: float) -> float:
    """The most units of the kind ``kind`` of :data:`COSTS` that ``max_work`` allows beside the
    work ``beside`` (units as in :func:`seconds`; none: alone), at least 0."""
    return max(0.0, LIMITS.max_work / 1000 - seconds(**beside)) / _cost(kind)


def _cost(kind: str) -> float:
    """The cost of a unit of ``kind`` (spaces written as underscores), or an InputError naming the kinds."""
    cost = COSTS.get(str(kind).replace("_", " "))
    if cost is None:
        raise InputError(f"{kind}: not a kind of work; the kinds are {sorted(COSTS)}")
    return cost


def _amount(kind: str, amount: object) -> numbers.Real:
    """``amount`` checked as a count of units: a real number >= 0 (not NaN)."""
    if isinstance(amount, bool) or not isinstance(amount, numbers.Real) or not amount >= 0:
        raise InputError(f"{kind}: expected a number of units >= 0, got {amount!r}"[:200])
    return amount


def price(entry: str | Callable[[], str], what: str | Callable[[], str], **units: float) -> float:
    """:func:`seconds` of ``units``, refused above ``max_work`` before the step they measure starts
    (a :class:`~symkf.errors.BudgetError` naming the estimate, its units, the cap and how to raise
    it); ``entry`` and ``what`` name the step (or are functions giving the words, called only when
    refusing: writing a large expression out costs more than pricing it)."""
    estimate = seconds(**units)
    bound = LIMITS.max_work
    if 1000 * estimate > bound:
        entry, what = (v if isinstance(v, str) else v() for v in (entry, what))
        parts = ", ".join(f"{_shown(amount)} {kind.replace('_', ' ')}s at {_seconds(_cost(kind))}"
                          for kind, amount in units.items() if amount)
        raise BudgetError(f"{entry}: the estimated work of {what} is {_seconds(estimate)}, above the cap max_work = "
                          f"{bound} CPU-ms; {_raise_it('max_work')} (the estimate: {parts})")
    return estimate


class Meter:
    """The work of a loop whose rounds' cost is not known before it runs (row generation, cutting
    planes, a simulation whose cache of solves fills as it goes), held to ``max_work`` as it goes:
    each round's start calls :meth:`round`, which refuses when the CPU time spent so far and one
    more round as dear as the dearest yet would pass the cap, or, when the loop has a known number
    of ``rounds`` and a tenth of the cap is spent, when the rounds left at the mean cost of the
    rounds in the latter half (at least) of the time spent would (the first rounds of a loop whose
    cache fills cost more than the later ones; a burst of dear rounds is averaged out). The first
    round is not refused here (its own steps are priced); a loop that would run for hours is
    stopped within a tenth of the cap, with what it spent, the rounds it made and how to raise
    the cap."""

    def __init__(self, entry: str, what: str, rounds: int | None = None) -> None:
        if not (isinstance(entry, str) and isinstance(what, str)):
            raise InputError(f"Meter: entry and what must be strings, got {type(entry).__name__}, {type(what).__name__}")
        if rounds is not None and (isinstance(rounds, bool) or not isinstance(rounds, int) or rounds < 0):
            raise InputError(f"Meter: rounds must be an int >= 0 or None, got {rounds!r}"[:200])
        self.entry, self.what, self.total = entry, what, rounds
        self.rounds, self.dearest = 0, 0.0
        self._start = self._last = time.process_time()
        self._marks = [(0.0, 0)]   # (time spent, rounds made) each time the time spent doubled

    def round(self) -> None:
        """Start a round: refused when the time spent and one more of the dearest round, or (with a
        known number of rounds) the rounds left at the recent cost, pass ``max_work``."""
        now = time.process_time()
        if self.rounds:
            self.dearest = max(self.dearest, now - self._last)
            spent = now - self._start
            if 1000 * (spent + self.dearest) > LIMITS.max_work:
                raise BudgetError(
                    f"{self.entry}: {self.what} spent {_seconds(spent)} in {self.rounds} rounds, and one more (up to "
                    f"{_seconds(self.dearest)}) would pass the cap max_work = {LIMITS.max_work} CPU-ms; "
                    f"{_raise_it('max_work')}")
            if self.total is not None:
                self._project(spent)
        self.rounds += 1
        self._last = now

    def _project(self, spent: float) -> None:
        """The refusal of :meth:`round` by the rounds left at the recent cost (a known number of rounds)."""
        if spent >= 2 * self._marks[-1][0]:
            self._marks.append((spent, self.rounds))
        if 10_000 * spent < LIMITS.max_work:
            return
        since, made = self._marks[-2]   # at most half the time spent: the window holds the latter half
        recent = (spent - since) / max(self.rounds - made, 1)
        left = max(self.total - self.rounds, 0)
        if 1000 * (spent + left * recent) > LIMITS.max_work:
            raise BudgetError(
                f"{self.entry}: {self.what} spent {_seconds(spent)} in {self.rounds} of {self.total} rounds; the {left} "
                f"left at {_seconds(recent)} each (the mean of the last {self.rounds - made}) would take "
                f"{_seconds(spent + left * recent)} in all, above the cap max_work = {LIMITS.max_work} CPU-ms; "
                f"{_raise_it('max_work')}")


def _raise_it(cap: str) -> str:
    """How a refusal by ``cap`` is lifted, in the words every refusal ends with."""
    return f"raise it with symkf.budget.limits({cap}=...) or the command-line option {OPTIONS[cap]}"


def _shown(amount: float) -> str:
    """A count as written in a refusal: exact up to 10^15, else its power of ten."""
    return f"{int(amount)}" if amount < 10 ** 15 else f"about 10^{math.floor(math.log10(min(amount, 1e300)))}"


def _seconds(seconds: float) -> str:
    """CPU seconds as written in a refusal (µs for a unit cost, powers of ten when astronomical)."""
    if seconds < 1e-3:
        return f"{seconds * 1e6:g} µs"
    return f"{seconds:.3g} CPU-s" if seconds < 1e15 else f"about 10^{math.floor(math.log10(seconds))} CPU-s"


def check_power(cap: str, base: int, exponent: int, entry: str, what: str) -> None:
    """:func:`check` of ``base ** exponent`` without computing it when it is far above the cap
    (the power of a huge exponent is itself the work the cap guards): compared in logarithms."""
    bound = getattr(LIMITS, cap)
    if base > 1 and exponent * math.log2(base) > math.log2(max(bound, 1)) + 64:   # far above: never built
        raise BudgetError(f"{entry}: {what} is {base}^{exponent}, above the cap {bound}; {_raise_it(cap)}")
    check(cap, base ** exponent, entry, what)


check_public(globals())
