"""Regression matrices, rank deficiency, projection (Sui-You-Fu eqs. 14-17, Algorithm 1).

For an eigen-block ``i`` in modal coordinates (``A T_i = T_i D_i``, ``D_i``
diagonal over the number field K of the block), the rows of ``O_N^i`` are
``C_j T_i D_i^k`` for the received pairs (sensor ``j``, time ``k``).  With
``g`` the block's class period, ``D_i^g`` is scalar on each class of
eigenvalues whose ratios are roots of unity, so:

* periodic block (one class, ``g`` the governing period): the row at time
  ``k`` is parallel to the row at ``k mod g``; O_N^i is rank deficient iff the
  projected pattern (Algorithm 1 with period ``g``) is, for every N;
* otherwise the row of an *element* (sensor ``j``, phase ``r``) received
  infinitely often spans its class components ``E_{j,r}``; a uniform bound on
  the zeros of non-degenerate linear recurrences (Evertse-Schlickewei-Schmidt)
  makes the finitely many other receptions irrelevant to decay rates.

Either way an element is a list of generator vectors over K, and the maximal
rank-deficient patterns are the hyperplanes of the matroid of all generators.
"""

from __future__ import annotations

import itertools
import math
from dataclasses import dataclass, field
from functools import cached_property
from typing import Callable, ClassVar, Iterator, Sequence

import flint
import numpy as np  # vectorised hyperplane screen and counts (BlockRows.inside)
import sympy as sp

from .. import budget
from . import flat_screen, hyperplane_screen
from ..arguments import check_public
from ..errors import InputError
from ..exact.field import Elem, NumberField
from ..exact.linalg import field_of, normal_of, nullspace_rows, rank_rows
from ..exact.numbers import sympify
from ..model.system import System
from ..exact.spectral import EigenBlock, eigenvalue_key, factors_in, support


#: the share of ``budget.Limits.max_memory`` the hyperplane screens' kept sets may take: the
#: screen's own arrays and the caller's copies of the sets take as much again and more, and the
#: whole must stay within ``max_memory`` (docs/performance.md)
KEPT_SHARE = 4


@dataclass(frozen=True)
class Element:
    """Sensor ``sensor`` at phase ``phase`` (time k with k mod period = phase)."""

    sensor: int
    phase: int


#: coefficients (over Q) of the generators that :class:`PhaseGenerators` keeps of the elements asked
#: for last: the fibres of five cyclotomic fields ask for each of the 143 elements of a lifted pair
#: (over a field of degree 240) about 95 times; 2^18 coefficients took 24 MB there
RECENT = 1 << 18


class PhaseGenerators(Sequence):
    """The generators of the elements ``(j, r)`` (index ``j g + r``) of a block without Jordan
    chains, each computed when asked: those of ``(j, 0)`` (``base[j]``, the independent class parts
    of ``C_j T``) times ``(D / lambda_1)^r`` coordinatewise (``step``; None for a unit step).  An
    invertible diagonal map keeps which vectors are independent, so these are the generators of
    ``(j, r)`` that :func:`direct_rows` would choose at each phase.  Stored, they took memory
    ``g d [K:Q]``, growing as ``m^2`` for the rotation ``2 R(2 pi/m)`` (g = m, [K:Q] = 2(m - 1)):
    about 120 MB at m = 1601.  A step that is a power ``theta^k`` of K's root of unity (the
    cyclotomic presentation: :meth:`~symkf.exact.field.NumberField.root_exponent`) is kept as its
    exponent: ``a s^r`` is then ``a theta^(k r)``, a shift and one reduction, where ``s^r`` cost
    ``log r`` products (the exact rows of five cyclotomic fields spent most of their time there).
    The generators of the elements asked for last are kept, up to :data:`RECENT` coefficients."""

    def __init__(self, K: NumberField, base: tuple[tuple[tuple[Elem, ...], ...], ...],
                 step: tuple[Elem | None, ...], g: int):
        self.K, self.base, self.step, self.g = K, base, step, g
        self.counts = tuple(len(gs) for gs in base for _ in range(g))
        self.exponents = tuple(None if s is None else K.root_exponent(s) for s in step)
        self._recent: dict[int, tuple[tuple[Elem, ...], ...]] = {}
        self._room = max(16, RECENT // max(1, len(step) * K.degree * max((len(gs) for gs in base), default=1)))

    def __len__(self) -> int:
        return len(self.counts)

    def __getitem__(self, e):
        e = range(len(self))[e]
        found = self._recent.get(e)
        if found is None:
            found = self._recent[e] = self._phase(*divmod(e, self.g))
            if len(self._recent) > self._room:   # the earliest asked goes
                del self._recent[next(iter(self._recent))]
        return found

    def _phase(self, j: int, r: int) -> tuple[tuple[Elem, ...], ...]:
        """The generators of element ``(j, r)``."""
        if not r:
            return self.base[j]
        K = self.K
        powers = [None if s is None or k is not None else K.pow(s, r) for s, k in zip(self.step, self.exponents)]
        return tuple(tuple(a if (s is None and k is None) or a.is_zero() else
                           K.times_root_power(a, k * r) if k is not None else K.mul(a, s)
                           for a, s, k in zip(v, powers, self.exponents)) for v in self.base[j])

    def __iter__(self) -> Iterator[tuple[tuple[Elem, ...], ...]]:
        for gs in self.base:   # one product per phase and coordinate, as direct_rows built them
            for r in range(self.g):
                yield gs
                gs = tuple(self._scaled(v, self.step) for v in gs)

    def _scaled(self, v: tuple[Elem, ...], factors: Sequence[Elem | None]) -> tuple[Elem, ...]:
        return tuple(a if s is None or a.is_zero() else self.K.mul(a, s) for a, s in zip(v, factors))

    def points(self, elements: Sequence[int], tail: Sequence[Sequence[Elem]] = ()) -> "PhasePoints":
        """The generators of ``elements`` in order, then the vectors ``tail``, computed when asked."""
        return PhasePoints(self, [(int(e), i) for e in elements for i in range(self.counts[e])], list(tail))


class PhasePoints(Sequence):
    """A list of vectors: generators ``(element, index)`` of :class:`PhaseGenerators`, then plain
    vectors ``tail``.  :func:`_reduction` maps them mod p from the base generators and the step
    (``phi(v s^r) = phi(v) phi(s)^r``: phi is a ring map) without computing them over K."""

    def __init__(self, generators: PhaseGenerators, owner: list[tuple[int, int]], tail: list):
        self.generators, self.owner, self.tail = generators, owner, tail

    def __len__(self) -> int:
        return len(self.owner) + len(self.tail)

    def __getitem__(self, k):
        k = range(len(self))[k]
        if k >= len(self.owner):
            return self.tail[k - len(self.owner)]
        e, i = self.owner[k]
        return self.generators[e][i]

    def entries(self) -> list[Elem]:
        """Elements of K whose denominators (and the modulus's) any prime p must avoid for every
        vector to lie in ``Z_(p)[theta]``: the base generators', the steps', the tail's."""
        G = self.generators
        return [a for gs in G.base for v in gs for a in v] + [s for s in G.step if s is not None] + \
            [a for v in self.tail for a in v]

    def images(self, phi, p: int) -> list[list[int]]:
        """The vectors mapped by the ring map ``phi`` into ``F_p``."""
        G = self.generators
        out = np.zeros((len(self.owner), len(G.step)), dtype=np.int64)
        if self.owner:
            base = [[[phi(a) for a in v] for v in gs] for gs in G.base]
            e, i = np.array(self.owner, dtype=np.int64).T
            j, r = np.divmod(e, G.g)
            powers = np.ones((len(G.step), G.g), dtype=np.int64)   # phi(s_k)^r mod p, r < g
            for k, s in enumerate(G.step):
                x = 1 if s is None else phi(s)
                for q in range(1, G.g):
                    powers[k, q] = powers[k, q - 1] * x % p
            B = np.array([base[a][b] for a, b in zip(j.tolist(), i.tolist())], dtype=np.int64)
            out = B * powers[:, r].T % p   # residues below 2^30: a product fits in int64
        return out.tolist() + [[phi(a) for a in v] for v in self.tail]


@dataclass(frozen=True, eq=False)
class BlockRows:
    """Rows of the regression matrix restricted to one eigen-block, per element."""

    block: EigenBlock
    K: NumberField
    class_period: int  # the block's class period (EigenBlock.class_period): the elements' phases
    elements: tuple[Element, ...]
    generators: Sequence[tuple[tuple[Elem, ...], ...]]  # per element (PhaseGenerators: computed when asked)
    size: int
    T: list = field(repr=False)      # modal eigenvector columns (n x n_i over K; see modal_form's conjugate_pair)
    diag: list = field(repr=False)   # the block's eigenvalues in K, repeated by multiplicity
    phase_shift: bool = False        # generators are the class parts of C_j T D^phase (not Jordan chains)

    #: the rows of sub-systems whose lifted hyperplanes are this block's that miss a part of it
    #: (:class:`symkf.engine.cylinders.SplitRows`); none here: these rows hold all their hyperplanes
    cylinders: ClassVar[tuple] = ()

    @cached_property
    def counts(self) -> tuple[int, ...]:
        """The number of generators of each element (without computing them)."""
        if isinstance(self.generators, PhaseGenerators):
            return self.generators.counts
        return tuple(len(gs) for gs in self.generators)

    def _points(self, elements: Sequence[int], tail: Sequence[Sequence[Elem]] = ()) -> Sequence[tuple[Elem, ...]]:
        """The generators of ``elements`` in order, then the vectors ``tail`` (computed when asked
        from :class:`PhaseGenerators`)."""
        if isinstance(self.generators, PhaseGenerators):
            return self.generators.points(elements, tail)
        return [g for e in elements for g in self.generators[e]] + list(tail)

    @cached_property
    def hyperplanes(self) -> tuple[frozenset[int], ...]:
        """Maximal sets of elements whose generators lie in a common hyperplane (indices)."""
        return tuple(_set(row) for row in self.inside)

    @cached_property
    def inside(self) -> np.ndarray:
        """Boolean matrix: ``inside[h, e]`` iff element ``e`` lies in hyperplane ``h`` (the order of
        :attr:`hyperplanes`, sorted by their sorted index lists).  Counting is vectorised: an
        element is inside a generator hyperplane ``S`` iff all its generators are in ``S``."""
        n, E = self.size, len(self.generators)
        if n == 1:
            return np.array([[not c for c in self.counts]], dtype=bool)
        vectors, bases = self._bases
        member = np.zeros((E, len(vectors)), dtype=np.float32)  # small counts: exact, and BLAS
        for e, b in enumerate(bases):
            member[e, list(b)] = 1
        found = _generator_hyperplanes(self.K, vectors, n, _element_flats(bases, len(vectors), n))
        S = np.zeros((len(found), len(vectors)), dtype=np.float32)
        S[np.repeat(np.arange(len(found)), [len(hs) for hs in found]),
          np.fromiter(itertools.chain.from_iterable(found), dtype=np.int64)] = 1
        inside = S @ member.T == member.sum(axis=1)
        # an element set spans its hyperplane when its generators are all of S (S holds n - 1
        # independent vectors); then it is maximal and no other hyperplane has the same set
        spanning = ((inside.astype(np.float32) @ member > 0) == S.astype(bool)).all(axis=1)
        sets = inside[spanning]
        partial = np.unique(inside[~spanning], axis=0)
        if len(partial):  # kept unless strictly inside another set
            every = np.concatenate([sets, partial])
            sizes = every.sum(axis=1)
            keep = [not (every[:, r].all(axis=1) & (sizes > r.sum())).any() for r in partial]
            sets = np.concatenate([sets, partial[keep]])
        return sets[_lex_order(sets)]

    @cached_property
    def _bases(self) -> tuple[list[tuple[Elem, ...]], list[tuple[int, ...]]]:
        """The distinct generators and, per element, the indices of its own (independent) ones."""
        vectors: list[tuple[Elem, ...]] = []
        index: dict[str, int] = {}
        bases = []
        for gs in self.generators:   # one pass: PhaseGenerators computes them as it goes
            own = []
            for g in gs:
                k = _key(g)
                if k not in index:
                    index[k] = len(vectors)
                    vectors.append(g)
                own.append(index[k])
            bases.append(tuple(own))
        return vectors, bases

    @cached_property
    def through_element_flats(self) -> bool:
        """Whether :attr:`inside` lists through the flats of the elements' generators
        (:func:`_element_flats`: elements of several generators), where each hyperplane costs
        exact echelon forms over K, rather than through every ``n - 1`` generators."""
        vectors, bases = self._bases
        return _element_flats(bases, len(vectors), self.size) is not None

    def listing_estimate(self) -> tuple[int, str]:
        """An upper bound on the number of generator hyperplanes :attr:`inside` builds (each a row
        of its matrices, :meth:`listing_bytes`; the element sets it lists are fewer), and its
        formula: ``C(V, n - 1)`` for V distinct generators, or, when :func:`_element_flats`
        applies, ``sum_e C(V - s_e, n - 1 - s_e)`` over the elements held by some hyperplane, with
        ``s_e = min(r_e, n - 2)`` for ``r_e`` independent generators.

        Why it bounds them.  Through the flats of an element ``e`` with ``r_e <= n - 2`` the listing
        finds the hyperplanes ``H`` holding its span ``P_e``; a basis of ``H`` extends ``b_e`` by
        ``n - 1 - r_e`` generators outside ``P_e``, which holds ``r_e`` of the ``V`` (``b_e``), so
        there are at most ``C(V - r_e, n - 1 - r_e)`` of them.  With ``r_e = n - 1`` the listing
        visits the flat ``Z`` of ``b_e``'s first ``n - 2`` and every hyperplane through it, each
        ``Z`` and one generator outside it: at most ``V - (n - 2)``.  Every row is one of these."""
        vectors, bases = self._bases
        V, n = len(vectors), self.size
        if _element_flats(bases, V, n) is None:
            return math.comb(V, n - 1), f"C({V}, {n - 1}) for {V} generators in dimension {n}"
        live = [min(len(b), n - 2) for b in bases if 0 < len(b) < n]
        return (sum(math.comb(V - s, n - 1 - s) for s in live),
                f"the sum of C({V} - s, {n - 1} - s) over {len(live)} elements of s = min(r, {n - 2}) of r generators, "
                f"in dimension {n}")

    def listing_bytes(self, hyperplanes: int) -> int:
        """Bytes that :attr:`inside` holds at its peak for ``hyperplanes`` hyperplanes: per
        hyperplane a float32 row over the ``V`` distinct generators, its boolean and float32 rows
        over the ``E`` elements, and its generators' index tuple (about 128 bytes)."""
        return hyperplanes * (4 * len(self._bases[0]) + 5 * len(self.elements) + 128)

    def heaviest(self, weights: Sequence[float], floor: float | None = None, strict: bool = False,
                 screens: int = 1, needed: Callable[[frozenset[int]], bool] | None = None
                 ) -> list[frozenset[int]] | None:
        """The hyperplanes (element sets, as in :attr:`hyperplanes`) whose weight ``sum_{e in H}
        weights[e]`` may be maximal, without enumerating every hyperplane; None when the fast
        path does not apply (then enumerate).

        Weights are floats >= 0 (``-log loss``) used only to screen; every set whose screened
        weight is within ``1e-9 (1 + total weight)`` of the screened maximum is confirmed exactly
        (rank ``n - 1`` over K) and returned, and the caller decides among them exactly (float
        sums of at most E correctly rounded terms err by far less than the tolerance).  With
        ``floor``, every set whose screened weight is at least ``min(floor, maximum)`` (less the
        tolerance) is returned: all hyperplanes that an additive upper bound cannot rule out; with
        ``strict`` too, only those at least ``floor`` (none when every hyperplane is lighter).

        The screen (:mod:`symkf.engine.hyperplane_screen`) works mod p, stage by stage: each orbit of
        elements under the phase shift ``(j, r) -> (j, r + 1 mod g)`` (a symmetry of the hyperplanes
        when the generator of ``(j, r + 1)`` is that of ``(j, r)`` times ``D_i``, by construction in
        :func:`_block_rows`; else every element is its own orbit) contributes the hyperplanes through its first
        element ``a`` that hold no element of an earlier orbit; every hyperplane is a shift of one
        of those.  Within a stage, a hyperplane ``H`` is visited at the flat ``Z_p`` spanned mod p
        by ``a`` and its first ``n - 3`` classes independent mod ``a`` (independent over K, as
        independent mod p), with the line of the later classes of ``H``: every later element of
        ``H`` lies in ``Z_p`` or, by Cramer with an (n - 1)-minor nonzero mod p, on that one line,
        so the screened set (``Z_p`` alone when no later class is left) contains ``H``, and weights
        are >= 0.  Each kept set is closed mod p (every element on the mod-p span of its normal)
        and confirmed exactly (rank ``n - 1`` over K): the closure is then an exact hyperplane, no
        lighter than the set, so the screened maximum is the exact one and every exact maximiser
        is among the closures' shifts.  A kept set of rank below ``n - 1`` over K (a flat that a
        low ``floor`` lets through) holds no hyperplane and is dropped.  A failed confirmation (a merge mod p that is not exact, or
        a representative vanishing mod p) repeats the screen with the next prime, then returns
        None.  Applies when the generators span K^n mod p.  With the phase shift (and weights it preserves), the
        cosets of shifts seed a lower bound of the heaviest weight, and every orbit becomes a stage
        whose greedy bases come from a window of positions after its first element, when that is
        the cheaper plan (:func:`symkf.engine.hyperplane_screen._windowed`: the pigeonhole argument that
        no hyperplane at the bound is missed).  The screen's work (:func:`symkf.engine.hyperplane_screen.work`,
        about ``C(C, n - 2)`` incidences per stage, and the points each stage classifies) is priced
        before it starts and refused (:class:`~symkf.errors.BudgetError`) above ``budget.Limits.max_work``.

        ``needed``: a test of element sets that is false only on a set of which the caller needs no
        subset, nor of any of its phase shifts (a rate's upper bound, monotone in the set and kept by
        the shift, below the least rate the caller wants: :func:`symkf.engine.search._reaching`).  A
        closure it rejects is neither confirmed exactly nor returned: every exact hyperplane the
        closure stands for lies inside it (above).  The confirmations of closures the caller never
        reads were most of the time of a Gilbert-Elliott verdict (docs/performance.md).  The search
        through flats (elements of several generators) does not test its sets.

        ``screens``: the screens of this block the caller's query runs, this one and others
        priced alike (the points they classify are the same; their windows at a lower floor are
        no shorter), so that a query beyond ``max_work`` is refused before the first of them.

        An element with several generators (a sensor of several rows, a Jordan chain's
        ``w_(c, s)``) lies in ``H`` iff all of them do: then :meth:`_through_flats`.

        Without ``floor`` the answer is kept per direction of ``weights`` (each over the largest, as
        floats): weights in proportion have the same maximisers, and the sets kept hold them all
        (a common loss rate's critical value and a verdict at equal rates screen once, not twice).
        """
        weights = self.screen_weights(weights)
        top = max(weights, default=0.0)
        if floor is not None or needed is not None or not top > 0:
            return self._heaviest(weights, floor, strict, screens, needed)
        direction = tuple(float(w) / top for w in weights)
        if direction not in self._maxima:
            self._maxima[direction] = self._heaviest(weights, None, screens=screens)
        found = self._maxima[direction]
        return None if found is None else list(found)

    @cached_property
    def _maxima(self) -> dict[tuple[float, ...], list[frozenset[int]] | None]:
        """:meth:`heaviest` without a floor, per direction of the weights."""
        return {}

    def _heaviest(self, weights: Sequence[float], floor: float | None, strict: bool = False, screens: int = 1,
                  needed: Callable[[frozenset[int]], bool] | None = None) -> list[frozenset[int]] | None:
        """:meth:`heaviest`, screened."""
        n = self.size
        if n < 2:
            return None
        live = [e for e, c in enumerate(self.counts) if 0 < c < n]
        if not live:   # every hyperplane holds the same elements, those without generators
            return [self._always] if not strict or float(np.asarray(weights)[list(self._always)].sum()) >= floor else []
        if self.several_generators:
            return self._through_flats(weights, floor, strict, screens)
        owner = np.array(live, dtype=np.int64)  # point -> element
        vectors = self._points(live)   # one generator each
        w = np.asarray(weights, dtype=float)
        shift = self._shift(owner)
        moved = np.arange(len(self.generators))  # the shift on elements (those without points stay)
        if shift is not None:
            moved[owner] = owner[shift]
        wanted = None if needed is None else lambda c: needed(frozenset(owner[c].tolist()) | self._always)
        closures = self._screened(vectors, w[owner], shift, 1e-9 * (1 + w.sum()), floor, f"{len(live)} elements", strict,
                                  screens, wanted)
        if closures is None:
            return None
        out = set()
        for c in closures:
            members = owner[c]
            for _ in range(self.class_period if shift is not None else 1):
                out.add(frozenset(members.tolist()) | self._always)
                members = moved[members]
        return list(out)

    @cached_property
    def _always(self) -> frozenset[int]:
        """The elements without generators: in every hyperplane."""
        return frozenset(e for e, c in enumerate(self.counts) if not c)

    def _through_flats(self, weights: Sequence[float], floor: float | None, strict: bool = False, screens: int = 1
                       ) -> list[frozenset[int]] | None:
        """:meth:`heaviest` for elements of several generators, by :mod:`symkf.engine.flat_screen`: the
        hyperplanes through the first flat element they hold (one stage per orbit under the phase
        shift, when that is a symmetry of the weights), and those holding none through the points of
        the elements of rank one.  Each kept set is closed mod p (every element inside the span of
        its generators), its shifts added, sets strictly inside another dropped, and what remains
        confirmed exactly: its generators have the same rank over K as mod p (at least as large
        over K; equal, the span over K reduces to the span mod p, so exactly the same elements lie
        in it, and it is deficient).  A maximal set over K lies in a hyperplane mod p that the
        search visits with its full weight, so no kept set strictly inside it survives.  A failed
        confirmation (a merge mod p) repeats the search with the next prime, then returns None."""
        n, E = self.size, len(self.generators)
        live = np.array([e for e, c in enumerate(self.counts) if 0 < c < n], dtype=np.int64)
        owner = np.array([e for e in live for _ in range(self.counts[e])], dtype=np.int64)
        vectors = self._points(live.tolist())
        w = np.asarray(weights, dtype=float)
        tol = 1e-9 * (1 + w.sum())
        moved = np.arange(E)
        shift = self._shift(owner)
        if shift is not None:
            moved[owner] = owner[shift]
            if not np.array_equal(w[moved], w):
                shift, moved = None, np.arange(E)
        orbit = np.arange(E)   # per element the least element of its orbit
        for e in live.tolist():
            f = int(moved[e])
            while f != e:
                orbit[e] = min(orbit[e], f)
                f = int(moved[f])
        always = sorted(self._always)
        base_weight = float(w[always].sum())
        p = 1 << 27
        for _ in range(3):
            p, images = _reduction(self.K, vectors, p)
            X = np.array(images, dtype=np.int64)
            rank = {e: flint.nmod_mat(X[owner == e].tolist(), p).rank() for e in live.tolist()}
            flats = [e for e in live.tolist() if rank[e] >= 2]
            points = [e for e in live.tolist() if rank[e] == 1]
            stages = [e for e in flats if orbit[e] == e]
            classes = len(np.unique(hyperplane_screen._labels(X[np.isin(owner, points)], p)[1], axis=0))
            work = flat_screen.work(n, list(rank.values()), len(stages), len(live)) + \
                hyperplane_screen._stage_work(classes, n + 1)
            budget.price(lambda: f"eigen-block of modulus {self.block.modulus}",
                         lambda: f"the hyperplane search through the flats of {len(flats)} elements of several "
                                 f"generators and {len(points)} of one, in dimension {n} ({len(stages)} stages"
                                 + (f", {screens} such searches)" if screens > 1 else ")"),
                         incidence=screens * work)
            config = flat_screen.Configuration(X, owner, live, w)
            screen = hyperplane_screen.Screen(tol, floor, budget.LIMITS.max_memory // KEPT_SHARE, strict)
            for a in stages:   # a hyperplane through a's flat and no flat element of an earlier orbit
                keep = np.array([e for e in live.tolist() if e != a and not (e in rank and rank[e] >= 2
                                 and orbit[e] < orbit[a])], dtype=np.int64)
                try:
                    flat_screen.stage(config.select(keep), X[owner == a], a, p, screen, always, base_weight)
                except hyperplane_screen.Crowded as crowded:
                    budget.check("max_memory", crowded.bytes, f"eigen-block of modulus {self.block.modulus}",
                                 f"the bytes (estimate) of the element sets kept by the search through the flats "
                                 f"({crowded}, {hyperplane_screen.MEMBER_BYTES} bytes per point)")
            flat_screen.points_only(config.select(np.array(points, dtype=np.int64)), p, screen, always, base_weight)
            budget.price(lambda: f"eigen-block of modulus {self.block.modulus}",
                         lambda: f"closing the {len(screen.kept)} element sets kept by the search through the flats",
                         kept_point=len(screen.kept) * len(owner))
            sets = self._closed(X, owner, p, screen.kept, moved)
            if sets is not None:
                return sets
        return None

    def _closed(self, X: np.ndarray, owner: np.ndarray, p: int, kept, moved: np.ndarray) -> list[frozenset[int]] | None:
        """The kept element sets of :meth:`_through_flats` closed mod p, shifted, maximal and confirmed
        exactly; None when a confirmation fails."""
        n = self.size
        vectors = self._points(sorted(set(owner.tolist())))
        closures: dict[frozenset[int], tuple[np.ndarray, int]] = {}
        for S in kept:
            rows = np.flatnonzero(np.isin(owner, list(S)))
            N = flat_screen.normals(X[rows], p)
            on = ~(X @ N % p).any(axis=1)
            off = np.unique(owner[~on])
            members = frozenset(np.setdiff1d(owner, off).tolist()) | self._always
            closures.setdefault(members, (np.flatnonzero(on), n - N.shape[1]))
        out: dict[frozenset[int], frozenset[int]] = {}   # each shift of a closure -> the closure confirmed
        for members in closures:
            shifted = members
            for _ in range(self.class_period):
                out.setdefault(shifted, members)
                shifted = frozenset(moved[list(shifted)].tolist())
        maximal = _maximal(list(out))
        for members in {out[S] for S in maximal}:
            on, rank = closures[members]
            if rank == n - 1:
                if not self._exact(X, p, on, vectors):
                    return None
            elif rank_rows(self.K, _distinct([vectors[i] for i in on]), n) != rank:
                return None
        return maximal

    def generic_weight(self, weights: Sequence[float]) -> float:
        """The weight of a hyperplane through ``n - 1`` elements of one generator in general position
        (the ``n - 1`` largest weights): a ``floor`` at or below it lets :meth:`heaviest` keep every
        such hyperplane, ``C(E, n - 1)`` of them (with elements of several generators the search
        goes through their flats, and every hyperplane it keeps holds its elements' full weight)."""
        return float(sum(sorted(w for w, c in zip(weights, self.counts) if c == 1)[-(self.size - 1):]))

    @cached_property
    def several_generators(self) -> bool:
        """Whether some element that a hyperplane may hold has several generators (:meth:`heaviest`
        then searches through the flats of such elements)."""
        return any(1 < c < self.size for c in self.counts)

    def _screened(self, vectors: list, weights: np.ndarray, shift: np.ndarray | None, tol: float,
                  floor: float | None, points: str, strict: bool = False, screens: int = 1,
                  needed: Callable[[np.ndarray], bool] | None = None) -> list[np.ndarray] | None:
        """The exact closures (point indices) of the sets :mod:`symkf.engine.hyperplane_screen` keeps for
        the points ``vectors`` with ``weights`` (see :meth:`heaviest`; ``points`` names them in a
        refusal; ``screens`` and ``needed``, a test of closures, as in :meth:`heaviest`), or None."""
        n = self.size
        orbits = _orbits(len(vectors), shift)
        cycles = _cycles(len(vectors), shift) if shift is not None and np.array_equal(weights[shift], weights) \
            else None
        powers = _powers(shift, self.class_period)
        entry = lambda: f"eigen-block of modulus {self.block.modulus}"   # noqa: E731

        def screen_of(detail: str) -> str:
            return f"the hyperplane screen ({points} in dimension {n}, {detail}" + \
                (f"; {screens} such screens)" if screens > 1 else ")")
        p = 1 << 27
        for _ in range(3):
            p, images = _reduction(self.K, vectors, p)
            if flint.nmod_mat(images, p).rank() < n:
                return None
            X = np.array(images, dtype=np.int64)
            skip = self._parallel_orbits(X, p, orbits, vectors)
            screen = hyperplane_screen.Screen(tol, floor, budget.LIMITS.max_memory // KEPT_SHARE, strict)
            try:   # Crowded: more sets than fit, and the caller lists, refused by its own estimate
                if cycles is not None:
                    # the floor reads every point per flat of the cycles: refused first when even the
                    # cheaper plan's points pass the cap
                    budget.price(entry, lambda: screen_of(f"{len(cycles)} cycles; its points alone, whichever plan"),
                                 screen_point=screens * hyperplane_screen.least_visits(orbits, skip, cycles))
                    hyperplane_screen.lower_bound(X, weights, p, cycles, screen)
                plan = hyperplane_screen.stages(X, weights, p, orbits, skip, screen.bar, cycles)
                # when the points alone pass the cap, the incidences (a class count per stage: seconds
                # at thousands of sensors) are not counted past the first stage
                visits = screens * sum(len(s.points) for s in plan)
                left = int(budget.affordable("incidence")) if budget.affordable("incidence", screen_point=visits) else 0
                budget.price(entry, lambda: screen_of(f"{len(orbits) - len(skip)} orbits, {len(plan)} stages"),
                             screen_point=visits, incidence=screens * hyperplane_screen.work(X, p, plan, left))
                if not hyperplane_screen.search(X, weights, p, plan, screen):
                    continue
            except hyperplane_screen.Crowded:
                return None
            if len(screen.kept) * len(X) > budget.affordable("kept point"):
                return None   # closing them costs more than listing is allowed: the caller lists, priced
            mod_p = {}  # many kept sets share a closure, or one up to the shift (the caller shifts)
            seen = set()  # a closure's key sorts all its shifts: once per closure, not per kept set
            for S in screen.kept:
                c = self._mod_p_closure(X, p, sorted(S), vectors)
                if c is None:
                    break
                if len(c) and c.tobytes() not in seen:
                    seen.add(c.tobytes())
                    mod_p.setdefault(_least_shift(c, powers), c)
            else:
                wanted = [c for c in mod_p.values() if needed is None or needed(c)]
                if all(self._exact(X, p, c, vectors) for c in wanted):
                    return wanted
        return None

    @cached_property
    def live(self) -> list[int]:
        """The elements with a generator (the others lie in every hyperplane)."""
        return [e for e, c in enumerate(self.counts) if c]

    def screen_weights(self, weights: Sequence[float]) -> list[float]:
        """``weights`` checked as one finite float ``>= 0`` per element (the screens' ``-log loss``)."""
        out = list(weights)
        if len(out) != len(self.elements) or not all(isinstance(w, (int, float)) and not isinstance(w, bool)
                                                     and 0 <= w < math.inf for w in out):
            raise InputError(f"weights: expected {len(self.elements)} finite floats >= 0, one per element")
        return [float(w) for w in out]

    def spanned(self, weights: Sequence[float], count: int = 9) -> list[frozenset[int]]:
        """The hyperplanes spanned by ``n - 1`` of the ``count`` heaviest generators (exact): a cheap
        guess of a heavy hyperplane (:meth:`on_hyperplanes`)."""
        weights = self.screen_weights(weights)
        n, K = self.size, self.K
        owner = [e for e, c in enumerate(self.counts) for _ in range(c)]
        points = self._points(range(len(self.counts)))
        # the distinct generators (point indices, in order of their first): grouped by their images
        # mod p and split exactly where several share one (keyed by their coefficients, they took
        # memory E [K:Q]: 2 R(2 pi/m) has E = 2m over a field of degree 2(m - 1))
        distinct: list[list[int]] = []
        by_image: dict[tuple[int, ...], list[list[int]]] = {}
        for i, image in enumerate(_reduction(K, points)[1] if owner else []):
            group = by_image.setdefault(tuple(image), [])
            for same in group:
                if points[same[0]] == points[i]:
                    same.append(i)
                    break
            else:
                group.append([i])
                distinct.append(group[-1])
        weight = [sum(weights[owner[i]] for i in same) for same in distinct]
        top = [points[distinct[c][0]] for c in sorted(range(len(distinct)), key=lambda c: -weight[c])[:count]]
        normals = []
        for rows in itertools.combinations(top, n - 1):
            normal = nullspace_rows(K, rows, n) if n > 1 else []
            if len(normal) == 1:   # rank n - 1
                normals.extend(normal)
        return self.on_hyperplanes(normals) if normals else []

    def on_hyperplanes(self, normals: Sequence[Sequence[Elem]]) -> list[frozenset[int]]:
        """Per normal vector ``v`` (in K^n), the elements all of whose generators ``g`` have ``g . v =
        0`` (an element without generators lies on every hyperplane).  Screened mod p, vectorised: a
        dot product that vanishes over K vanishes mod p, so only the generators vanishing mod p are
        confirmed exactly."""
        if any(len(v) != self.size for v in normals):
            raise InputError(f"normals: each a vector of length {self.size} (the block's dimension)")
        if not normals:
            return []
        owner = [e for e, c in enumerate(self.counts) for _ in range(c)]
        if not owner:
            return [frozenset(range(len(self.generators)))] * len(normals)
        flat = self._points(range(len(self.counts)), normals)
        p, images = _reduction(self.K, flat)
        G, N = np.array(images[:len(owner)], dtype=np.int64), np.array(images[len(owner):], dtype=np.int64)
        dots = np.zeros((len(owner), len(normals)), dtype=np.int64)
        for k in range(self.size):  # residues below 2^31: a product fits in int64 before reduction
            dots = (dots + G[:, k:k + 1] * N[None, :, k] % p) % p
        out = []
        for h, normal in enumerate(normals):
            off = {owner[i] for i in range(len(owner))
                   if dots[i, h] != 0 or not self.K.dot(flat[i], normal).is_zero()}
            out.append(frozenset(e for e in range(len(self.generators)) if e not in off))
        return out

    def _shift(self, owner: np.ndarray) -> np.ndarray | None:
        """The phase shift on the points (generators; ``owner[k]`` the element of point ``k``, an
        element's points consecutive): generator ``i`` of ``(j, r)`` goes to generator ``i`` of
        ``(j, r + 1 mod g)``, when the generators are the class parts of ``C_j T D^r``
        (:attr:`phase_shift`): those of ``(j, r + 1)`` are then those of ``(j, r)`` times ``D_i``
        (chosen alike: an invertible diagonal map keeps which are independent), parallel to them
        at ``r = g - 1`` (``D_i^g`` is scalar on each class), so shifts map hyperplanes to
        hyperplanes; else None."""
        if self.class_period < 2 or not self.phase_shift:
            return None
        at = {(e.sensor, e.phase): i for i, e in enumerate(self.elements)}
        first: dict[int, int] = {}
        for k, e in enumerate(owner.tolist()):
            first.setdefault(e, k)
        out = []
        for k, e in enumerate(owner.tolist()):
            element = self.elements[e]
            nxt = at[(element.sensor, (element.phase + 1) % self.class_period)]
            if nxt not in first or self.counts[nxt] != self.counts[e]:
                return None  # pragma: no cover - the counts agree by construction
            out.append(first[nxt] + k - first[e])
        return np.array(out, dtype=np.int64)

    def _parallel_orbits(self, X: np.ndarray, p: int, orbits: list[list[int]], vectors) -> set[int]:
        """Orbits whose first element is parallel over K to an element of an earlier orbit (every
        hyperplane through it holds that element: the stage finds nothing new)."""
        _, classes, _ = hyperplane_screen._classes(X, p)
        label = np.empty(len(X), dtype=np.int64)
        for c, members in enumerate(classes):
            label[members] = c
        stage = np.empty(len(X), dtype=np.int64)
        for o, orbit in enumerate(orbits):
            stage[orbit] = o
        out = set()
        for o, orbit in enumerate(orbits):
            a = orbit[0]
            earlier = [i for i in classes[label[a]] if stage[i] < o]
            if earlier and _parallel(self.K, vectors[a], vectors[earlier[0]]):
                out.add(o)
        return out

    def _mod_p_closure(self, X: np.ndarray, p: int, S: list[int], vectors) -> np.ndarray | None:
        """Every point on the mod-p hyperplane spanned by ``S``, if that set has rank ``n - 1`` mod p
        (:meth:`_exact` then decides whether it is the exact hyperplane through ``S``); no point
        when ``S`` has rank below ``n - 1`` over K (it holds no hyperplane: a flat a low floor
        kept); else None."""
        null, nullity = flint.nmod_mat(X[S].tolist(), p).nullspace()
        if nullity != 1:
            if nullity > 1 and rank_rows(self.K, _distinct([vectors[i] for i in S]), self.size) < self.size - 1:
                return np.zeros(0, dtype=np.int64)
            return None
        normal = np.array([int(null[i, 0]) for i in range(self.size)], dtype=np.int64)
        return np.flatnonzero(X @ normal % p == 0)

    def _exact(self, X: np.ndarray, p: int, members: np.ndarray, vectors) -> bool:
        """Whether the points ``members`` (a mod-p closure: rank ``n - 1`` mod p, so at least that
        over K) have rank ``n - 1`` over K (:func:`_hyperplane_normal`)."""
        return _hyperplane_normal(self.K, [vectors[i] for i in members], X[members], p, self.size) is not None

    def normal(self, S: frozenset[int]) -> list[Elem] | None:
        """A normal over K of the span of the generators of the elements ``S`` when that span is a
        hyperplane (rank ``n - 1``), else None: :func:`_hyperplane_normal` from ``n - 1`` of them
        independent mod p, by minors, without the inverses in K of an echelon form (each costs
        hundreds of products at high degree: the fibres of five cyclotomic fields took 1570 of
        them, most of the row's time); an echelon form only when they have lower rank mod p."""
        members = self._indices(S)
        vectors = [v for e in members for v in self.generators[e]]
        if not vectors:
            return None
        p, X = self._images_of(members)
        found = _hyperplane_normal(self.K, vectors, X, p, self.size)
        if found is None and flint.nmod_mat(X.tolist(), p).rank() < self.size - 1:
            basis = nullspace_rows(self.K, vectors, self.size)
            found = basis[0] if len(basis) == 1 else None
        return found

    def longest_run(self, sensor: int) -> int | None:
        """The most consecutive phases (cyclically) of ``sensor`` whose elements one hyperplane
        holds, ``n - 1``, when the generators of its elements at phases ``0 .. n - 1`` (one each)
        have rank ``n`` mod p (:func:`_reduction`; then over K too): those of any ``n`` consecutive
        phases are theirs times a power of the step ``D / lambda_1`` (:class:`PhaseGenerators`, an
        invertible diagonal map; ``(D / lambda_1)^g = I`` across the period's end), so they span
        K^n and no hyperplane holds them all.  None when that is not shown (the block's generators
        are not a phase shift's, or the sensor sees too little of it)."""
        if not isinstance(sensor, int) or isinstance(sensor, bool) or \
                not 0 <= sensor < 1 + max((e.sensor for e in self.elements), default=-1):
            raise InputError(f"sensor: a sensor index of this block's elements expected, got {str(sensor)[:80]}")
        n, g = self.size, self.class_period
        if not isinstance(self.generators, PhaseGenerators) or n > g:
            return None
        at = {(e.sensor, e.phase): i for i, e in enumerate(self.elements)}
        phases = [at.get((sensor, r)) for r in range(n)]
        if None in phases or any(self.counts[e] != 1 for e in phases):
            return None
        p, X = self._images_of(phases)
        return n - 1 if flint.nmod_mat(X.tolist(), p).rank() == n else None

    def state_normal_mod_p(self, S: frozenset[int]) -> tuple[int, np.ndarray] | None:
        """``(p, u)``: the image under a ring map ``Z_(p)[theta] -> F_p`` (:func:`_reduction`) of
        the normal of ``S``'s span in state coordinates (``T`` times it), when the generators of
        ``S`` have rank ``n - 1`` mod p; else None.  Then they have rank ``n - 1`` or ``n`` over K,
        and with rank ``n - 1`` the image of their exact normal (:meth:`normal`) is a multiple of
        the one mod p: a coordinate of ``u`` nonzero mod p is nonzero over K."""
        members = self._indices(S)
        if not any(self.generators[e] for e in members):
            return None
        p, X = self._images_of(members)
        null, nullity = flint.nmod_mat(X.tolist(), p).nullspace()
        if nullity != 1:
            return None
        N = np.array([int(null[i, 0]) for i in range(self.size)], dtype=np.int64)
        return p, self._images[3] @ N % p

    def _indices(self, S: frozenset[int]) -> list[int]:
        """The element indices ``S``, sorted; an :class:`~symkf.errors.InputError` naming them when
        one is not an element of this block."""
        members = sorted(int(e) for e in S)   # a bool is an int, never a numpy mask
        if any(not 0 <= e < len(self.elements) for e in members):
            raise InputError(f"S: element indices from 0 to {len(self.elements) - 1} expected (the block's "
                             f"elements), got {str(members)[:80]}")
        return members

    def _images_of(self, members: Sequence[int]) -> tuple[int, np.ndarray]:
        """The prime of :attr:`_images` and the images of the generators of ``members``, in order."""
        p, images, first, _ = self._images
        return p, images[np.concatenate([np.arange(first[e], first[e + 1]) for e in members])]

    @cached_property
    def _images(self) -> tuple[int, np.ndarray, np.ndarray, np.ndarray]:
        """A prime, the images mod p of every element's generators (:func:`_reduction`), element by
        element, where each element's rows start (with the end), and the image of ``T`` under the
        same map."""
        gens = [v for gs in self.generators for v in gs]
        p, images = _reduction(self.K, [*gens, *self.T])
        first = np.concatenate([[0], np.cumsum([len(gs) for gs in self.generators])])
        images = np.array(images, dtype=np.int64).reshape(-1, self.size)
        return p, images[:len(gens)], first, images[len(gens):]

    def deficient(self, pattern: frozenset[int]) -> bool:
        """Whether the elements in ``pattern`` leave O^i rank deficient."""
        rows = list(self._points(sorted(pattern)))
        return rank_rows(self.K, rows, self.size) < self.size


def _maximal(sets: list[frozenset[int]]) -> list[frozenset[int]]:
    """The sets not strictly inside another: each compared with the larger sets holding its rarest
    element (listed largest first, so the scan stops at the first set no larger)."""
    holding: dict[int, list[frozenset[int]]] = {}
    for T in sorted(sets, key=len, reverse=True):
        for e in T:
            holding.setdefault(e, []).append(T)

    def inside_another(S: frozenset[int]) -> bool:
        if not S:
            return any(sets)
        for T in min((holding[e] for e in S), key=len):
            if len(T) <= len(S):
                return False
            if S < T:
                return True
        return False
    return [S for S in sets if not inside_another(S)]


def _orbits(count: int, shift: np.ndarray | None) -> list[list[int]]:
    """The cycles of ``shift`` on ``range(count)`` (each element alone without it), each sorted,
    in the order of their least elements."""
    if shift is None:
        return [[i] for i in range(count)]
    return [sorted(cycle) for cycle in _cycles(count, shift)]


def _cycles(count: int, shift: np.ndarray) -> list[list[int]]:
    """The cycles of ``shift`` on ``range(count)``, each listed along it from its least element, in
    the order of those."""
    seen = np.zeros(count, dtype=bool)
    out = []
    for i in range(count):
        if not seen[i]:
            cycle, j = [], i
            while not seen[j]:
                seen[j] = True
                cycle.append(j)
                j = int(shift[j])
            out.append(cycle)
    return out


def _parallel(K: NumberField, u: Sequence[Elem], v: Sequence[Elem]) -> bool:
    """Whether the nonzero vectors ``u`` and ``v`` over K are parallel (all 2 x 2 minors vanish)."""
    k = next(i for i, a in enumerate(u) if not a.is_zero())
    return all(K.mul(a, v[k]) == K.mul(b, u[k]) for a, b in zip(u, v))


def _set(row: np.ndarray) -> frozenset[int]:
    return frozenset(np.flatnonzero(row).tolist())


def _as_rows(sets, elements: int) -> np.ndarray:
    """Element sets as boolean rows over ``elements`` columns (boolean rows pass through)."""
    if isinstance(sets, np.ndarray):
        return sets
    rows = np.zeros((len(sets), elements), dtype=bool)
    for h, H in enumerate(sets):
        rows[h, list(H)] = True
    return rows


def _lex_order(rows: np.ndarray) -> np.ndarray:
    """The permutation sorting boolean rows as their sorted lists of True indices are sorted."""
    r, c = np.nonzero(rows)
    counts = rows.sum(axis=1)
    padded = np.full((len(rows), int(counts.max(initial=0)) + 1), -1, dtype=np.int64)  # -1: the list ended
    padded[r, np.arange(len(r)) - np.repeat(np.cumsum(counts) - counts, counts)] = c
    return np.lexsort(padded.T[::-1])


def _key(v: Sequence[Elem]) -> str:
    return str([c.coeffs() for c in v])


def _distinct(vectors: Sequence[tuple[Elem, ...]]) -> list[tuple[Elem, ...]]:
    out, keys = [], set()
    for v in vectors:
        k = _key(v)
        if k not in keys:
            keys.add(k)
            out.append(v)
    return out


def _reduction(K: NumberField, vectors: Sequence[Sequence[Elem]], start: int = 1 << 27) \
        -> tuple[int, list[list[int]]]:
    """A prime ``p`` and the images of ``vectors`` under a ring map ``phi: Z_(p)[theta] -> F_p``.

    ``phi`` sends ``theta`` to a root of its minimal polynomial mod ``p``; ``p`` divides no
    denominator, so every linear relation over K maps to one over F_p."""
    p = start  # below 2^30: products of two residues, summed n times, stay in int64
    elements = vectors.entries() if isinstance(vectors, PhasePoints) else [a for v in vectors for a in v]
    denominators = int(np.lcm.reduce([int(a.denom()) for a in elements] + [int(K.modulus.denom())], dtype=object))
    m = _conductor(K.modulus)
    while True:
        p = int(sp.nextprime(p)) if not m else _next_prime_1_mod(p, m)
        if denominators % p == 0 or int(K.modulus.coeffs()[-1].p) % p == 0:
            continue
        f = flint.nmod_poly([int(c.p) * pow(int(c.q), -1, p) % p for c in K.modulus.coeffs()], p)
        r = _cyclotomic_root(f, p, m) if m else _some_root(f, p)
        if r is None:
            continue

        def phi(a: Elem) -> int:
            return int(flint.nmod_poly(a.numer(), p)(r)) * pow(int(a.denom()), -1, p) % p
        return p, vectors.images(phi, p) if isinstance(vectors, PhasePoints) else [[phi(a) for a in v] for v in vectors]


def _powers(shift: np.ndarray | None, g: int) -> tuple[np.ndarray, ...] | None:
    """The powers ``shift^k`` (k = 0..g-1) of the permutation ``shift`` (None without it) as its
    cycles: ``shift^k(i) = cycles[start_i + (pos_i + k) mod length_i]`` with the cycles listed end to
    end along the shift (int32), per point its cycle's ``start``, its ``pos`` in it, the cycle's
    ``length``, and ``g``.  The table of all powers took ``g`` rows of every point: 20 MB for the
    rotation ``2 R(2 pi/1601)``, growing as ``m^2``."""
    if shift is None:
        return None
    cycles = _cycles(len(shift), shift)
    lengths = np.array([len(c) for c in cycles], dtype=np.int64)
    order = np.concatenate(cycles).astype(np.int32)
    start, pos, length = (np.empty(len(shift), dtype=np.int64) for _ in range(3))
    start[order] = np.repeat(np.cumsum(lengths) - lengths, lengths)
    pos[order] = np.arange(len(order)) - start[order]
    length[order] = np.repeat(lengths, lengths)
    return order, start, pos, length, np.arange(g)[:, None]


def _least_shift(points: np.ndarray, powers: tuple[np.ndarray, ...] | None) -> bytes:
    """A key shared by the point sets that are shifts of one another (``powers``: :func:`_powers`;
    without them the points themselves): the least of the shifts' sorted index lists in
    lexicographic order, as bytes.  All shifts in one sort: a Markov screen keys many closures,
    each with all its shifts, and sorted one shift at a time they are millions of numpy calls on a
    few indices each, whose per-call cost would dominate (docs/performance.md)."""
    if powers is None:
        return points.tobytes()
    order, start, pos, length, k = powers
    orbit = np.sort(order[start[points] + (pos[points] + k) % length[points]], axis=1)
    return orbit[np.lexsort(orbit.T[::-1])[0]].tobytes()


def _independent_mod_p(rows: np.ndarray, p: int) -> list[int]:
    """The indices of the greedy basis of ``rows`` mod p (the pivot columns of the transpose's
    reduced echelon form)."""
    R, rank = flint.nmod_mat(rows.T.tolist(), p).rref()
    out, col = [], 0
    for r in range(rank):
        while int(R[r, col]) == 0:
            col += 1
        out.append(col)
    return out


def _hyperplane_normal(K: NumberField, vectors: Sequence[Sequence[Elem]], X: np.ndarray, p: int, n: int) \
        -> list[Elem] | None:
    """The exact normal (signed maximal minors, :func:`symkf.exact.linalg.normal_of`) of ``n - 1`` of
    ``vectors`` independent mod p (their images ``X``, independent over K as they are mod p), when
    it is orthogonal to every other one: then the vectors have rank ``n - 1`` over K.  None when
    they do not have rank ``n - 1`` mod p or some vector is off that normal (a dot product each,
    where an echelon form of all of them costs about n times more; one nonzero mod p is nonzero
    over K, and only those vanishing mod p are checked exactly)."""
    basis = _independent_mod_p(X, p)
    if len(basis) != n - 1:
        return None
    rest = np.delete(np.arange(len(vectors)), basis)
    null, _ = flint.nmod_mat(X[basis].tolist(), p).nullspace()
    if (X[rest] @ np.array([int(null[i, 0]) for i in range(n)], dtype=np.int64) % p).any():
        return None
    normal = normal_of(K, [vectors[i] for i in basis], n)
    return normal if all(K.dot(vectors[i], normal).is_zero() for i in rest) else None


def _some_root(f: flint.nmod_poly, p: int) -> int | None:
    x = flint.nmod_poly([0, 1], p)
    split = f.gcd(x.pow_mod(p, f) - x)  # the linear factors of f: finding them all costs far more
    return int(split.roots()[0][0]) if split.degree() >= 1 else None


def _conductor(modulus: Elem) -> int:
    """m when ``modulus`` is the cyclotomic ``Phi_m`` or the minimal polynomial of ``2 cos(2 pi/m)``
    (the presentations of :mod:`symkf.exact.field`), else 0: both split mod every prime
    ``p = 1 mod m``, where a root is a power ``a^((p - 1)/m)`` (no search over primes, whose
    density with a root is ``1/phi(m)``)."""
    if modulus.denom() != 1 or modulus.degree() < 2:
        return 0
    f = flint.fmpz_poly([int(c) for c in modulus.coeffs()])
    if m := int(f.is_cyclotomic()):
        return m
    d, t, x = f.degree(), flint.fmpz_poly([1, 0, 1]), flint.fmpz_poly([0, 1])  # x^d f(x + 1/x)
    h = sum((int(c) * t ** k * x ** (d - k) for k, c in enumerate(f.coeffs())), flint.fmpz_poly([]))
    return int(h.is_cyclotomic())


def _next_prime_1_mod(p: int, m: int) -> int:
    q = p + 1 + (-p) % m  # the next q = 1 mod m above p
    while not sp.isprime(q):
        q += m
    return q


def _cyclotomic_root(f: flint.nmod_poly, p: int, m: int) -> int | None:
    """A root of ``f`` (``Phi_m`` or the polynomial of ``2 cos(2 pi/m)`` mod ``p = 1 mod m``):
    ``zeta = a^((p - 1)/m)`` is a primitive m-th root of unity for some small ``a``."""
    for a in range(2, 200):
        z = pow(a, (p - 1) // m, p)
        for r in (z, (z + pow(z, -1, p)) % p):
            if int(f(r)) == 0:
                return r
    return None


def _element_flats(bases: Sequence[tuple[int, ...]], V: int, n: int) -> Iterator[tuple[int, ...]] | None:
    """Bases of the flats of rank ``n - 2`` through which :func:`_generator_hyperplanes` finds every
    hyperplane holding an element, when there are fewer of them than ``C(V, n - 2)``: each element's
    independent generators ``b_e`` (``r_e`` of them, ``0 < r_e < n``) with every ``n - 2 - r_e``
    further generators (the first ``n - 2`` of ``b_e`` when ``r_e = n - 1``); None otherwise.

    Why nothing is missed.  A set of elements maximal among those a hyperplane holds spans, with
    its generators, a flat ``W`` of rank at most ``n - 1``; generators span K^n, so ``W`` extends
    by generators to a hyperplane ``H``, which holds the set and, the set being maximal, no more.
    For ``e`` in the set, ``b_e`` extends by generators of ``H`` to a basis of a rank ``n - 2`` flat
    inside ``H``, which is listed here; ``H`` is one of the hyperplanes through it."""
    live = [b for b in bases if 0 < len(b) < n]
    if not live or sum(math.comb(V, max(0, n - 2 - len(b))) for b in live) >= math.comb(V, n - 2):
        return None

    def flats() -> Iterator[tuple[int, ...]]:
        for b in live:
            if len(b) == n - 1:
                yield b[:n - 2]
                continue
            for T in itertools.combinations([i for i in range(V) if i not in b], n - 2 - len(b)):
                yield (*b, *T)
    return flats()


def _generator_hyperplanes(K: NumberField, vectors: Sequence[Sequence[Elem]], n: int,
                           flats: Iterator[tuple[int, ...]] | None = None) -> list[frozenset[int]]:
    """Every hyperplane spanned by ``vectors`` (distinct, in K^n, n >= 2), as the set of vectors it holds;
    with ``flats``, every hyperplane through one of those flats (:func:`_element_flats`: the
    hyperplanes holding an element).

    The hyperplanes through a flat ``Z`` of rank ``n - 2`` partition the vectors outside ``Z``
    by their direction in the plane ``K^n / Z``: with ``N`` a basis of the normals of ``Z``,
    ``v`` lies on the line ``(v.N_2 : -v.N_1)``.  Each flat is visited once, from its
    lexicographically first basis ``c`` (the greedy basis; later bases lie in a known flat),
    and a hyperplane ``Z + G`` is kept there only when ``min G > max c``: its greedy basis then
    starts with ``c``, so every hyperplane is found exactly once.

    Screened mod p, decided exactly: ``n - 2`` (or ``n - 1``) vectors independent mod p are
    independent over K and the mod-p members of their span are a superset of the exact ones
    (Cramer's identity with a minor nonzero mod p maps to F_p).  So a set of exactly ``n - 1``
    vectors is exact, larger sets (``Z`` and kept ``Z + G``) are confirmed by an exact rank,
    and a flat where a confirmation fails, or whose basis is dependent mod p, is done exactly.
    """
    p, images = _reduction(K, vectors)
    W = np.array(images, dtype=np.int64)
    V = len(vectors)
    found: set[frozenset[int]] = set()
    exact: dict[frozenset[int], bool] = {}

    def flat(S: frozenset[int], rank: int) -> bool:  # S holds independent vectors of that rank
        if len(S) == rank:
            return True
        if S not in exact:
            exact[S] = rank_rows(K, [vectors[i] for i in S], n) == rank
        return exact[S]

    covered: set[tuple[int, ...]] = set()  # bases of visited flats are (n-2)-subsets of them
    every = flats is not None  # given flats: each visited in full (their greedy bases are elsewhere)
    combos = flats if every else itertools.combinations(range(V), n - 2)
    while chunk := list(itertools.islice(combos, 2048)):
        batch = [c for c in chunk if c not in covered]
        normals: list[np.ndarray | None] = []
        for c in batch:
            normals.append(_normals(images, c, p, n))
        good = [N for N in normals if N is not None]
        if good:  # B x V x 2 images of the vectors in the planes K^n / Z (entries < n p^2 < 2^63)
            XY = np.einsum("vn,bnk->bvk", W, np.stack(good)) % p
            lines = iter(_line_keys(XY[..., 0], XY[..., 1], p))
        for c, N in zip(batch, normals):
            if N is not None:
                key = next(lines)
                if c in covered:
                    continue
                out = _hyperplanes_through(c, key, p, n, flat, every)
            elif c in covered:
                continue
            elif rank_rows(K, [vectors[i] for i in c], n) == n - 2:
                out = None  # independent, but not mod p: decide exactly
            else:
                continue  # dependent: spans no flat of rank n - 2
            if out is None:
                out = _hyperplanes_through_exact(K, vectors, c, n)
            Z, hyperplanes = out
            found.update(hyperplanes)
            if len(Z) > n - 2 and not every:
                covered.update(itertools.combinations(sorted(Z), n - 2))
    return list(found)


def _normals(images: Sequence[Sequence[int]], c: tuple[int, ...], p: int, n: int) -> np.ndarray | None:
    """A basis (n x 2) of the mod-p normals of the vectors ``c`` (n - 2 of them), None if dependent mod p."""
    if not c:
        return np.eye(2, dtype=np.int64)
    null, nullity = flint.nmod_mat([images[i] for i in c], p).nullspace()
    if nullity != 2:
        return None
    return np.array([[int(null[i, k]) for k in range(2)] for i in range(n)], dtype=np.int64)


def _line_keys(x: np.ndarray, y: np.ndarray, p: int) -> np.ndarray:
    """The point ``(x : y)`` of the projective line over F_p as ``x / y`` in ``0..p-1``, ``p`` for
    ``y = 0``, and ``p + 1`` for ``x = y = 0`` (the vector lies in the flat)."""
    inv = hyperplane_screen.inverses(np.where(y != 0, y, 1), p)
    return np.where(y != 0, x * inv % p, np.where(x != 0, p, p + 1))


def _hyperplanes_through(c: tuple[int, ...], key: np.ndarray, p: int, n: int, flat, every: bool = False) \
        -> tuple[frozenset[int], list[frozenset[int]]] | None:
    """The flat ``Z`` spanned by ``c`` and the hyperplanes through it whose greedy basis starts
    with ``c`` (``every``: all of them), from the mod-p line of every vector; None when an exact
    confirmation fails."""
    Z = frozenset(np.flatnonzero(key == p + 1).tolist())
    if not flat(Z, n - 2):
        return None
    outside = np.flatnonzero(key != p + 1)
    last = c[-1] if c and not every else -1
    order = np.argsort(key[outside], kind="stable")  # lines, each with ascending members
    keys, members = key[outside][order], outside[order].tolist()
    bounds = [0, *(np.flatnonzero(keys[1:] != keys[:-1]) + 1).tolist(), len(members)]
    out = []
    for a, b in zip(bounds, bounds[1:]):
        if members[b - 1] < last:
            continue
        S = Z | frozenset(members[a:b])
        # kept sets are confirmed; so are straddling ones, which could hide a kept set (a false merge mod p)
        if not flat(S, n - 1):
            return None
        if members[a] > last:
            out.append(S)
    return Z, out


def _hyperplanes_through_exact(K: NumberField, vectors: Sequence[Sequence[Elem]], c: tuple[int, ...],
                               n: int) -> tuple[frozenset[int], list[frozenset[int]]]:
    """The flat spanned by the independent ``c`` and every hyperplane through it, exactly."""
    rows = [vectors[i] for i in c]
    Z = frozenset(i for i, v in enumerate(vectors) if rank_rows(K, rows + [v], n) == n - 2)
    out, done = [], set(Z)
    for i, v in enumerate(vectors):
        if i not in done:
            (normal,) = nullspace_rows(K, rows + [v], n)
            S = frozenset(j for j, u in enumerate(vectors) if K.dot(u, normal).is_zero())
            out.append(S)
            done |= S
    return Z, out


def modal_form(A: sp.MatrixBase, block: EigenBlock, extra: Sequence[sp.MatrixBase] = (),
               conjugate_pair: bool = False) -> tuple[NumberField, list[list[Elem]], list[Elem]]:
    """Exact modal form of one eigen-block: field K, eigenvector columns ``T_i`` (n x n_i), ``D_i``.

    K is the smallest field holding the entries of the diagonal blocks of ``A`` that hold the
    block's eigenvalues (:func:`symkf.exact.spectral.support`; all of ``A`` for Jordan chains), of
    ``extra`` matrices (the sensors' C) and the block's eigenvalues: the columns vanish outside
    those diagonal blocks.  For an eigenvalue
    with Jordan chains the columns span its generalized eigenspace
    ``ker (A - lambda I)^m`` (``D_i`` then holds only its diagonal).  With ``conjugate_pair``
    (see :func:`is_conjugate_pair`) the second eigenvalue ``conj(lambda)`` and its
    eigenvector are replaced by their complex conjugates ``lambda``, ``v``: K is then
    ``Q(lambda)`` (degree ``deg``) instead of ``Q(lambda, conj(lambda))`` (up to
    ``deg (deg - 1)``).  This is the modal form up to conjugating the second class, which
    preserves linear dependence within that class: right for the per-class generators,
    not for rows that mix the two classes.
    """
    members = block.members[:1] * 2 if conjugate_pair else block.members
    n = A.shape[0]
    # the eigenvectors live on the diagonal blocks of A holding the members (spectral.support); a
    # block with Jordan chains keeps all of A, which _jordan_block_rows multiplies by
    index = list(range(n)) if block.defective else support(A, block.members)
    if not block.defective and len({tuple(support(A, [e])) for e in members}) > 1:
        # the compositum holds Q(zeta_g) (the ratios of the eigenvalues of one class, g their
        # class period), so phi(g) bounds its degree from below: refused before any field arithmetic
        # of that degree (2R(2 pi/5) + 2R(2 pi/7) + 2R(2 pi/9) + 2R(2 pi/11): phi(3465) = 1440 and the
        # field Q(zeta_13860) of degree 2880)
        budget.check("max_cyclotomic_degree", int(sp.totient(block.class_period)),
                     f"eigen-block of modulus {block.modulus}",
                     f"the degree of the field of its eigenvectors, at least phi({block.class_period}) "
                     f"(it holds the ratios of the eigenvalues: roots of unity of order {block.class_period})")
        return _split_modal_form(A, members, extra, index)
    sub = A.extract(index, index)
    K = field_of(sub, *extra)
    # an eigenvalue with a linear factor over the entries' field is an element of it already
    inside = {eigenvalue_key(f, i): K.mul(-h[0], K.inv(h[1])) for h, _, roots in factors_in(sub, K) if len(h) == 2
              for f, i in roots}
    own = all(e.key in inside for e in members)
    if not own:
        K = NumberField([*K.generators, *(e.expr for e in members if not e.expr.is_Rational)])
    Ak = K.matrix(sub)
    m = len(index)
    cols: list[list[Elem]] = []
    diag: list[Elem] = []
    for ev in members:
        lam = inside[ev.key] if own else K.convert(ev.expr)
        shifted = [[(Ak[i][j] - lam) % K.modulus if i == j else Ak[i][j] for j in range(m)] for i in range(m)]
        if ev.defective:
            shifted = _matpow(K, shifted, ev.multiplicity)
        basis = _krylov_eigenvector(K, sub, lam) if ev.multiplicity == 1 else None
        basis = basis or nullspace_rows(K, shifted, m)
        if len(basis) != ev.multiplicity:
            raise AssertionError("generalized eigenspace dimension mismatch")  # pragma: no cover
        cols.extend(basis)
        diag.extend([lam] * ev.multiplicity)
    row_of = {i: r for r, i in enumerate(index)}
    zero = flint.fmpq_poly([])
    T = [[cols[c][row_of[i]] if i in row_of else zero for c in range(len(cols))] for i in range(n)]
    return K, T, diag


def _split_modal_form(A: sp.MatrixBase, members: Sequence, extra: Sequence[sp.MatrixBase], index: list[int]) \
        -> tuple[NumberField, list[list[Elem]], list[Elem]]:
    """:func:`modal_form` of a block whose eigenvalues live on different diagonal blocks of ``A``
    (rotations of one modulus from several cyclotomic fields): each eigenvector is found on the
    diagonal blocks holding its eigenvalue only (it vanishes elsewhere), without factoring the
    characteristic polynomial over the compositum of all entries (the costliest step otherwise)."""
    K = NumberField([*field_of(A.extract(index, index), *extra).generators,
                     *(e.expr for e in members if not e.expr.is_Rational)])
    n, zero = A.shape[0], flint.fmpq_poly([])
    cols: list[list[Elem]] = []
    diag: list[Elem] = []
    for ev in members:
        own = support(A, [ev])
        sub = A.extract(own, own)
        lam = K.convert(ev.expr)
        basis = _krylov_eigenvector(K, sub, lam) if ev.multiplicity == 1 else None
        if not basis:
            Ak = K.matrix(sub)
            shifted = [[(Ak[i][j] - lam) % K.modulus if i == j else Ak[i][j] for j in range(len(own))]
                       for i in range(len(own))]
            basis = (_plane_eigenvector(K, shifted) if len(own) == 2 and ev.multiplicity == 1 else None) or \
                nullspace_rows(K, shifted, len(own))
        if len(basis) != ev.multiplicity:
            raise AssertionError("eigenspace dimension mismatch")  # pragma: no cover
        row_of = {i: r for r, i in enumerate(own)}
        cols.extend([[v[row_of[i]] if i in row_of else zero for i in range(n)] for v in basis])
        diag.extend([lam] * ev.multiplicity)
    return K, [[col[i] for col in cols] for i in range(n)], diag


def _plane_eigenvector(K: NumberField, M: list[list[Elem]]) -> list[list[Elem]] | None:
    """``[v]`` with ``M v = 0``, ``v != 0``, for a singular 2 x 2 ``M = A - lam I`` over K of rank 1
    (a 2 x 2 diagonal block of ``A``, ``lam`` a simple eigenvalue): a nonzero row of the adjugate,
    ``(-q, p)`` or ``(s, -r)`` for rows ``(p, q)``, ``(r, s)``, checked exactly; None when ``M`` is
    zero.  Without the inverse in K of an echelon form's pivot (0.1 CPU-s at degree 1440: the modal
    forms of five cyclotomic fields' sub-systems took 96 of them)."""
    (p, q), (r, s) = M
    for v in ([-q, p], [s, -r]):
        if any(not a.is_zero() for a in v):
            if not all(K.dot(row, v).is_zero() for row in M):
                raise AssertionError("adjugate eigenvector check failed")  # pragma: no cover
            return [v]
    return None


def _krylov_eigenvector(K: NumberField, A: sp.MatrixBase, lam: Elem) -> list[list[Elem]] | None:
    """``[v]`` with ``A v = lam v``, ``v != 0``, for a rational ``A`` and a simple eigenvalue ``lam``
    in K, from the adjugate instead of an echelon form over K (whose coefficients swell with the
    size of ``A``): ``adj(lam I - A) = sum_j q_j(lam) A^j`` with
    ``q(x, y) = (chi(x) - chi(y)) / (x - y) = sum_j q_j(x) y^j``, of rank 1, so a nonzero column
    ``sum_j q_j(lam) A^j e_k`` spans the eigenspace (checked exactly); None when A is not rational."""
    if not all(v.is_Rational for v in A):
        return None
    n = A.shape[0]
    M = flint.fmpq_mat([[flint.fmpq(int(v.p), int(v.q)) for v in A.row(i)] for i in range(n)])
    chi = M.charpoly().coeffs()
    q = [flint.fmpq_poly([chi[n]])]  # q_(n-1) = chi_n; q_j = lam q_(j+1) + chi_(j+1)
    for j in range(n - 2, -1, -1):
        q.append(K.mul(lam, q[-1]) + chi[j + 1])
    q.reverse()
    for k in range(n):
        w = flint.fmpq_mat(n, 1, [1 if i == k else 0 for i in range(n)])
        v = [flint.fmpq_poly([]) for _ in range(n)]
        for j in range(n):
            for i in range(n):
                if w[i, 0] != 0:
                    v[i] += q[j] * w[i, 0]
            w = M * w
        if any(not a.is_zero() for a in v):
            for i in range(n):  # (A - lam I) v = 0 exactly
                if not (sum((v[j] * M[i, j] for j in range(n) if M[i, j] != 0), flint.fmpq_poly([]))
                        - K.mul(lam, v[i])) % K.modulus == 0:
                    raise AssertionError("adjugate eigenvector check failed")  # pragma: no cover
            return [v]
    return None


def _matmul(K: NumberField, X: Sequence[Sequence[Elem]], Y: Sequence[Sequence[Elem]]) -> list[list[Elem]]:
    return [K.vecmat(row, Y) for row in X]


def _matpow(K: NumberField, X: list[list[Elem]], k: int) -> list[list[Elem]]:
    out = X
    for _ in range(k - 1):
        out = _matmul(K, out, X)
    return out


def is_conjugate_pair(system: System, block: EigenBlock) -> bool:
    """Whether the block is ``{lambda, conj(lambda)}`` (simple) in two classes of a real system.

    For real ``A`` a block of two simple eigenvalues that are not in one class (their ratio is
    no root of unity; ``lambda, -lambda`` are) is a conjugate pair, and with real ``C`` the
    eigenvectors can be chosen conjugate, so the second class's generators are the conjugates
    of the first's (the generic case of a dense real matrix)."""
    return (len(block.members) == 2 and len(block.classes) == 2
            and all(e.multiplicity == 1 for e in block.members)
            and all(sympify(v).is_real for M in (system.A, *(s.C for s in system.sensors)) for v in M))


def direct_rows(system: System, block: EigenBlock) -> BlockRows:
    K, T, diag = modal_form(system.A, block, [s.C for s in system.sensors], is_conjugate_pair(system, block))
    if block.defective:
        return _jordan_rows(system, block, K, T, diag)
    g = block.class_period
    class_of = [ci for ci, members in enumerate(block.classes)
                for m in members for _ in range(block.members[m].multiplicity)]
    # rows C_j T D^phase scaled by lambda_1^-phase (parallel, so the same hyperplanes): the ratios
    # lambda_k / lambda_1 are roots of unity within a class, and the rows' coefficients stay small
    # (times 2^phase unscaled for modulus 2: 300-bit coefficients at phase 300)
    first = K.inv(diag[0])  # once: an inverse in a field of high degree is costly
    one = flint.fmpq_poly([1])
    # a unit step (lambda_1's own, a conjugate pair's second class: see modal_form) keeps the entry
    step = tuple(None if s == one else s for s in (K.mul(lam, first) for lam in diag))
    zero = flint.fmpq_poly([])
    base = []
    for sensor in system.sensors:
        CT = [K.vecmat(K.matrix(sensor.C)[r], T) for r in range(sensor.m)]
        gens = []
        for c in range(len(block.classes)):
            for row in CT:
                v = tuple(a if class_of[k] == c else zero for k, a in enumerate(row))
                if any(not a.is_zero() for a in v):
                    gens.append(v)
        base.append(tuple(_independent(K, gens, block.size)))
    elements = tuple(Element(j, phase) for j in range(len(system.sensors)) for phase in range(g))
    return BlockRows(block, K, g, elements, PhaseGenerators(K, tuple(base), step, g), block.size, T, diag,
                     phase_shift=True)


def _jordan_rows(system: System, block: EigenBlock, K: NumberField, T: list, diag: list) -> BlockRows:
    """Generators of a block with Jordan chains (symkf's extension, docs/sui.md).

    With ``g`` the class period, ``A^g`` acts on the generalized eigenspace of class ``c``
    (columns ``T_c``) as ``c_c (I + N'_c)``, ``N'_c`` nilpotent: ``A^g T_c = c_c T_c (I + N'_c)``.
    The row of sensor j at time ``r + g t`` is then ``sum_c c_c^t sum_s binom(t, s) w_(c, s)`` with
    ``w_(c, s) = C_j A^r B_c^s T_c`` and ``B_c = A^g / c_c - I`` (``T_c N'_c = B_c T_c``).  Received
    at ``n_i`` or more times ``t`` (binomials of degree < n_i are independent functions of t) its
    rows span every ``w_(c, s)``: these are the element's generators.  With no Jordan chain
    ``B_c T_c = 0`` and they are today's class projections ``C_j A^r T_c``."""
    g = block.class_period
    Ak = K.matrix(system.A)
    class_of = [ci for ci, members in enumerate(block.classes)
                for m in members for _ in range(block.members[m].multiplicity)]
    zero = flint.fmpq_poly([])
    Ag = _matpow(K, Ak, g) if g > 1 else Ak
    B = []
    for c in range(len(block.classes)):
        inv = K.inv(K.pow(diag[class_of.index(c)], g))
        B.append([[(K.mul(a, inv) - (1 if i == j else 0)) % K.modulus for j, a in enumerate(row)]
                  for i, row in enumerate(Ag)])
    elements, generators = [], []
    for j, sensor in enumerate(system.sensors):
        rows = K.matrix(sensor.C)  # C_j A^r, r = phase
        for phase in range(g):
            gens = []
            for c in range(len(block.classes)):
                ws = rows
                for _ in range(block.size):
                    for w in _matmul(K, ws, T):
                        v = tuple(a if class_of[k] == c else zero for k, a in enumerate(w))
                        if any(not a.is_zero() for a in v):
                            gens.append(v)
                    ws = _matmul(K, ws, B[c])
            elements.append(Element(j, phase))
            generators.append(tuple(_independent(K, gens, block.size)))
            rows = _matmul(K, rows, Ak)
    return BlockRows(block, K, g, tuple(elements), tuple(generators), block.size, T, diag)


def _independent(K: NumberField, vectors: list[tuple[Elem, ...]], n: int) -> list[tuple[Elem, ...]]:
    """A maximal independent subset (generators of the same span, fewer rank tests later)."""
    if len(vectors) == 1:  # nonzero
        return list(vectors)
    out: list[tuple[Elem, ...]] = []
    for v in vectors:
        if rank_rows(K, out + [v], n) > len(out):
            out.append(v)
    return out


def regression_matrix(system: System, pattern: Sequence[Sequence[int]]) -> sp.Matrix:
    """``O_N = S_N col{C, CA, ..., CA^{N-1}}`` (eq. 14) for receival vectors ``pattern[k]``."""
    rows = []
    Ak = sp.eye(system.n)
    for vec in pattern:
        for j, s in enumerate(system.sensors):
            rows.append((s.C * Ak) * (1 if vec[j] else 0))
        Ak = Ak * system.A
    return sp.Matrix.vstack(*rows)


def project(pattern: Sequence[Sequence[int]], period: int) -> frozenset[Element]:
    """Algorithm 1: the elements (sensor, k mod period) received at least once."""
    return frozenset(Element(j, k % period) for k, vec in enumerate(pattern) for j, g in enumerate(vec) if g)

check_public(globals())
