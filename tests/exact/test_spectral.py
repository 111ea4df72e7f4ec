"""Eigen-blocks, periods and the modal form (symkf.exact.spectral), per diagonal block of A.

The periods tau (of lambda/|lambda|) and the governing period g (of A^g scalar on the block) by
hand for rotations, sign flips and real blocks; aperiodicity proofs; eigenvalues, PBH and the
moduli of eigenvalues in each diagonal block's own field (symkf.exact.blocks), without resultants
where they are known, and the input caps that follow the blocks' fields; eigenvalues without a
closed form kept as flint's roots and shown abbreviated."""

from __future__ import annotations

from math import gcd

import flint
import pytest
import sympy as sp

import symkf as sk
from symkf import budget, cli
from symkf.errors import BudgetError, UnobservableError
from symkf.exact.algebraic import identify, real_from_ball
from symkf.exact import algebraic, nfpoly, spectral
from symkf.exact.field import NumberField
from symkf.exact.spectral import _abs_poly, _cosine_order, _resultant_y, diagonal_blocks, eigen_blocks, eigenvalues

from conftest import library, limited, refused_at_once, rotation


def rotation_entries(alpha, angle):
    c, s = sp.cos(angle), sp.sin(angle)
    return [[alpha * c, -alpha * s], [alpha * s, alpha * c]]


@pytest.mark.parametrize("m,k", [(m, k) for m in range(1, 13) for k in range(m) if gcd(k, m) == 1])
def test_rotation_periods(m, k):
    # eigenvalues 2 exp(+-2 pi i k/m): tau = m, governing period = order of exp(4 pi i k/m)
    (block,) = eigen_blocks(rotation_entries(2, 2 * sp.pi * k / m)) if m > 2 else (None,)
    if m <= 2:  # R(0) = I, R(pi) = -I are 1x1-repeated: one block, scalar
        (block,) = eigen_blocks(rotation_entries(2, 2 * sp.pi * k / m))
        assert block.governing_period == 1 and block.period == m
        return
    assert block.modulus == 2
    assert block.period == m
    assert block.governing_period == m // gcd(m, 2)


def test_diagonal_sign_flip():
    for A in ([[1, 0], [0, -1]], [[2, 0], [0, -2]]):
        (b,) = eigen_blocks(A)
        assert (b.period, b.governing_period) == (2, 2)


def test_aperiodic_rotation_has_proof():
    (b,) = eigen_blocks([["3/5", "-4/5"], ["4/5", "3/5"]])
    assert b.period is None and b.governing_period is None
    assert "25x^2 + 14x + 25" in b.proof and "not cyclotomic" in b.proof


def test_lower_triangular_plant_has_two_real_blocks():
    # Quevedo et al.'s plant of Sec. VII-C
    blocks = eigen_blocks([["5/4", 0], [1, "11/10"]])
    assert [b.modulus for b in blocks] == [sp.Rational(5, 4), sp.Rational(11, 10)]
    assert all(b.period == 1 and b.governing_period == 1 for b in blocks)


def test_quarter_turn_periods():
    # 2R(pi/2): tau = 4 (lambda/|lambda| = i), governing period 2 (A^2 = -4 I)
    (b,) = eigen_blocks([[0, -2], [2, 0]])
    assert (b.period, b.governing_period) == (4, 2)
    assert set(b.eigenvalues) == {2 * sp.I, -2 * sp.I}


def test_golden_ratio_blocks_and_sign_period():
    hi, lo = eigen_blocks([[1, 1], [1, 0]])
    assert hi.modulus == (1 + sp.sqrt(5)) / 2 and lo.modulus == (sp.sqrt(5) - 1) / 2
    assert (lo.period, lo.governing_period) == (2, 1)  # negative real eigenvalue


def test_eigen_block_tau_and_governing_period() -> None:
    # A = 2 R(pi/2): eigenvalues +-2i, lambda/|lambda| = i has order 4 (tau = 4); A^2 = -4 I (g = 2)
    [block] = eigen_blocks(sk.System([[0, -2], [2, 0]], [sk.Sensor([[1, 0]])]).A)
    assert (block.tau, block.period, block.governing_period) == (4, 4, 2)
    assert repr(block) == "EigenBlock(modulus 2; eigenvalues 2i, -2i; τ = 4, governing period 2)"


def test_eigen_block_repr_shows_radicals_and_multiplicities() -> None:
    # x^4 + 1296/625: the roots (6/5) e^(i pi (2k+1)/4) = (3 sqrt(2)/5)(+-1 +- i), modulus 6/5;
    # beside it eigenvalue 1 of algebraic multiplicity 2, shown once with (×2)
    c = sp.Rational(-1296, 625)
    A = sp.diag(sp.Matrix([[0, 0, 0, c], [1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0]]), sp.eye(2))
    rotations, ones = eigen_blocks(A)
    assert repr(rotations) == ("EigenBlock(modulus 6/5; eigenvalues -3√2/5 + 3√2/5 i, -3√2/5 - 3√2/5 i, "
                               "3√2/5 + 3√2/5 i, 3√2/5 - 3√2/5 i; τ = 8, governing period 4)")
    assert ones.eigenvalues == (1, 1)
    assert repr(ones) == "EigenBlock(modulus 1; eigenvalues 1 (×2); τ = 1, governing period 1)"
    # a Jordan block: multiplicity 2, one eigenvector
    assert "1 (×2, 1 eigenvector)" in repr(eigen_blocks([[1, 1], [0, 1]])[0])


def test_eigen_block_repr_names_a_root_without_short_radical_by_value_and_polynomial() -> None:
    # x^3 - x - 1 (the plastic number 1.3247...): Cardano's form is long, so value and polynomial
    real, pair = eigen_blocks([[0, 0, 1], [1, 0, 1], [0, 1, 0]])
    assert repr(real) == ("EigenBlock(modulus root ≈ 1.324717957 of x^3 - x - 1; eigenvalues root ≈ 1.325 of x^3 - x - 1; "
                          "τ = 1, governing period 1)")
    assert "root ≈ -0.6624+0.5623i of x^3 - x - 1" in repr(pair) and "aperiodic" in repr(pair)
    assert "**" not in repr(pair) and "[" not in repr(pair)


def test_tiny_entry_in_a_rotation_block():
    """A = [[e, -2], [2, e]], e = 10^-100 (333 bits, under the cap): eigenvalues e +- 2i, modulus
    sqrt(4 + e^2) (a binomial's root, on which sympy's perfect-power extraction raised ValueError);
    no period, so the critical loss rate is 1/|lambda|^2 = 1/(4 + 10^-200)."""
    e = sp.Rational(1, 10 ** 100)
    S = sk.System(A=[["1e-100", -2], [2, "1e-100"]], sensors=[sk.Sensor(C=[[1, 1]])])
    assert sp.simplify(sk.critical_loss_rate(S).exact - 1 / (4 + e ** 2)) == 0
    assert not sk.stability(S, sk.IID(["1/2"])).stable
    (block,) = sk.eigen_blocks(S.A)
    assert sp.simplify(block.modulus.exact ** 2 - (4 + e ** 2)) == 0


# -- per diagonal block ------------------------------------------------------------------------

def test_diagonal_blocks_are_the_components_of_the_pattern():
    # states 0, 2 coupled, 1 alone, 3 - 4 coupled one way only
    A = sp.Matrix([[1, 0, 2, 0, 0], [0, 3, 0, 0, 0], [4, 0, 5, 0, 0], [0, 0, 0, 6, 7], [0, 0, 0, 0, 8]])
    assert sorted(diagonal_blocks(A)) == [[0, 2], [1], [3, 4]]


def test_an_eigenvalue_of_two_blocks_is_tested_jointly():
    """diag(R, R), R = 2R(pi/3): each eigenvalue is in both blocks (multiplicity 2).  The sensor
    [1, 0, 1, 0] sees each block's eigenvectors, but not v = (u, -u) for an eigenvector u of R:
    C v = u_1 - u_1 = 0, so (A, C) is not detectable (|lambda| = 2).  Two sensors [1, 0, 0, 0] and
    [0, 0, 1, 0] see every eigenvector (u_1 != 0 for both eigenvectors of a rotation)."""
    R = rotation(sp.pi / 3, 2)
    A = sp.diag(R, R)
    assert sorted(e.multiplicity for e in eigenvalues(A)) == [2, 2]
    with pytest.raises(UnobservableError, match="not seen by any sensor"):
        sk.System(A=A, sensors=[sk.Sensor(C=[[1, 0, 1, 0]])])
    S = sk.System(A=A, sensors=[sk.Sensor(C=[[1, 0, 0, 0]]), sk.Sensor(C=[[0, 0, 1, 0]])])
    assert S.observable


@pytest.mark.parametrize("A, modulus", [
    ([[-3]], 3),                                  # real: |lambda| = -lambda
    ([["cos(pi/7)"]], sp.cos(sp.pi / 7)),         # real, degree 3
    ([[1, -1], [1, 1]], sp.sqrt(2)),             # 1 +- i: lambda conj(lambda) = 2
    ([[1, -2], [1, 1]], sp.sqrt(3)),             # 1 +- i sqrt 2: 3
    ([[0, 0, 2], [1, 0, 0], [0, 1, 0]], sp.cbrt(2)),  # x^3 - 2: |lambda|^2 = 2^(2/3) irrational: resultant
])
def test_moduli_agree_with_the_resultant(A, modulus):
    """Each eigenvalue's modulus (fast path or not) is the root of the resultant Res_y(f(y),
    y^d f(z^2/y)) that the ball |lambda| picks, as of the power-sum polynomial spectral._abs_poly,
    and equals the value derived by hand."""
    for ev in eigenvalues(A):
        f = tuple(int(c) for c in ev.minpoly.coeffs())
        d = len(f) - 1
        resultant = _resultant_y(f, {(d - k, 2 * k): c for k, c in enumerate(f) if c})
        ball = lambda prec: flint.acb(abs(ev.ball(prec)))  # noqa: E731
        poly, idx = identify(resultant, ball, "modulus")
        assert identify(_abs_poly(f), ball, "modulus") == (poly, idx)
        assert ev.modulus == real_from_ball(poly, idx)
        if abs(complex(ev.ball(64).mid())) > 1e-9 and abs(abs(complex(ev.ball(64).mid())) - float(modulus)) < 1e-9:
            assert ev.modulus == modulus


def test_rotation_by_2pi_97_has_modulus_2():
    (block,) = eigen_blocks(rotation(2 * sp.pi / 97, 2))
    assert block.modulus == 2 and block.period == 97


def test_cosine_order():
    """2 cos(2 pi/7) has minimal polynomial x^3 + x^2 - 2x - 1, so cos(2 pi/7) has 8x^3 + 4x^2 - 4x - 1
    (m = 7); the roots +-sqrt 2 of x^2 - 2 exceed 1, no cosines; 2x^2 - 1 has the roots
    +-cos(pi/4) = cos(2 pi k/8), k = 1, 3 (m = 8)."""
    assert _cosine_order(flint.fmpz_poly([-1, -4, 4, 8])) == 7
    assert _cosine_order(flint.fmpz_poly([-2, 0, 1])) == 0
    assert _cosine_order(flint.fmpz_poly([-1, 0, 2])) == 8


@pytest.mark.parametrize("m", [5, 7, 9, 13, 24, 97])
def test_cosine_order_of_cos_2pi_over_m_from_closed_form_roots_and_from_phi_m(m, monkeypatch):
    """The minimal polynomial of cos(2 pi/m) (2^d psi_m(2x), psi_m that of 2 cos(2 pi/m)) has order
    m, read off its closed-form roots and, without them, from x^d g(x + 1/x) = Phi_m."""
    psi = flint.fmpz_poly.cos_minpoly(m)
    f = flint.fmpz_poly([int(c) * 2 ** k for k, c in enumerate(psi.coeffs())])
    assert _cosine_order(f) == m
    monkeypatch.setattr(spectral, "_known_roots", lambda coeffs: None)
    assert _cosine_order(f) == m


@pytest.mark.parametrize("m", [5, 7, 13])
def test_rotation_eigenvalues_from_roots_of_unity_match_the_norm(m, monkeypatch):
    """The eigenvalues 2 exp(+-2 pi i/m) of 2R(2 pi/m) over its entries' field, identified by
    powers of x modulo the factor, are those identified among the roots of Trager's norm."""
    A = sp.ImmutableMatrix(rotation(2 * sp.pi / m, 2))
    K = NumberField([sp.cos(2 * sp.pi / m), sp.sin(2 * sp.pi / m)])
    fast = spectral._factor_charpoly(A, K)
    monkeypatch.setattr(nfpoly, "unit_root_minpoly", lambda K, h: None)
    slow = spectral._factor_charpoly(A, K)
    assert fast == slow
    assert [[(tuple(f.coeffs()), i) for f, i in roots] for _, _, roots in fast] == \
        [[(tuple(f.coeffs()), i) for f, i in roots] for _, _, roots in slow]


def test_field_of_a_matrix_is_budgeted_per_diagonal_block():
    """Six distinct square roots on a diagonal: six 1x1 blocks, each decided in its own field of
    degree 2, so the system is accepted; its critical loss rate is 1/13 (one sensor sees every
    mode; the largest |lambda|^2 = 13 decides: 13 * loss < 1).  Coupled by a superdiagonal of
    ones the six form one triangular block, whose eigenvalues are still its diagonal entries: the
    entries' field of degree 2^6 = 64 is the cap, and the value is the same.  Closed into a cycle
    (a one in the corner) the block is not triangular: the entries' field 64 times size 6 is 384 > 64.
    A rotation by pi/7 (cos and sin in Q(zeta_28), phi(28) = 12) is a rotation block of cyclotomic
    degree 12."""
    primes = (2, 3, 5, 7, 11, 13)
    for coupling in (0, 1):
        S = sk.System([[f"sqrt({p})" if i == j else coupling * int(j == i + 1) for j in range(6)]
                       for i, p in enumerate(primes)], [sk.Sensor([[1] * 6])])
        assert sk.critical_loss_rate(S).exact == sp.Rational(1, 13)
    with pytest.raises(BudgetError, match=r"diagonal block rows 1-6 .* is 384, above the cap 64.*--max-degree"):
        sk.System([[f"sqrt({p})" if i == j else int(j == (i + 1) % 6) for j in range(6)] for i, p in enumerate(primes)],
                  [sk.Sensor([[1] * 6])])
    S = sk.System([["2*cos(pi/7)", "-2*sin(pi/7)"], ["2*sin(pi/7)", "2*cos(pi/7)"]], [sk.Sensor([[1, 0]])])
    assert S.n == 2


def test_cyclotomic_rotations_pass_the_default_caps():
    """Rotation blocks of trigonometric constants stay in Q(zeta_m) (m = 4q): 2R(2 pi/97) has
    cyclotomic degree phi(388) = 192 <= 1024 and is decided, to the value the engine gave before the
    cost model with --max-degree raised (2^(192/193)/4), as is 2R(2 pi/401) (phi(1604) = 800,
    2^(800/801)/4) and 2R(2 pi/521) (phi(2084) = 1040, 2^(1040/1041)/4): a rotation's field is
    priced at a quarter of its degree, so 2R(2 pi/2053) (phi(8212) = 4104) is refused.  A 1x1 cos(pi/97)
    is its own eigenvalue (real, modulus cos(pi/97) < 1: stable for every loss rate).  The same
    constants off the rotation pattern give eigenvalues of degree up to 2 * 192 in a generic
    extension: refused under max_degree, at once."""
    rot = lambda t: [[f"2*cos({t})", f"-2*sin({t})"], [f"2*sin({t})", f"2*cos({t})"]]  # noqa: E731
    S = sk.System(rot("2*pi/97"), [sk.Sensor([[1, 0]]), sk.Sensor([[0, 1]])])
    assert sk.critical_loss_rate(S).exact == 2 ** sp.Rational(192, 193) / 4
    S = sk.System(rot("2*pi/401"), [sk.Sensor([[1, 0]]), sk.Sensor([[0, 1]])])
    assert sk.critical_loss_rate(S).exact == 2 ** sp.Rational(800, 801) / 4
    S = sk.System(rot("2*pi/521"), [sk.Sensor([[1, 0]]), sk.Sensor([[0, 1]])])
    assert sk.critical_loss_rate(S).exact == 2 ** sp.Rational(1040, 1041) / 4
    with pytest.raises(BudgetError, match="4104 .* is 1026, above the cap 1024.*--max-cyclotomic-degree"):
        sk.System(rot("2*pi/2053"), [sk.Sensor([[1, 0]])])
    assert sk.critical_loss_rate(sk.System([["cos(pi/97)"]], [sk.Sensor([[1]])])).exact == 1
    with pytest.raises(BudgetError, match="is 384, above the cap 64.*--max-degree"):
        sk.System([["cos(2*pi/97)", 1], [1, "sin(2*pi/97)"]], [sk.Sensor([[1, 0]])])
    # +-i cos(pi/97): a complex eigenvalue of degree 96 whose squared modulus cos(pi/97)^2 is
    # irrational, so |lambda| needs a resultant of degree 2 * 96^2: generic, refused
    with pytest.raises(BudgetError, match="is 384, above the cap 64.*--max-degree"):
        sk.System([[0, "-cos(pi/97)"], ["cos(pi/97)", 0]], [sk.Sensor([[1, 0]])])


def _sqrt2_matrix() -> list[list[str]]:
    import random
    rng = random.Random(0)
    return [[rng.choice(["sqrt(2)", "-sqrt(2)", "1", "1/2", "0"]) for _ in range(16)] for _ in range(16)]


def test_modulus_polynomial_is_sized_before_it_is_built():
    """The polynomial of |lambda| of a 16x16 A with entries in {+-sqrt 2, 1, 1/2, 0} (d = 32: the
    products of pairs of its conjugate eigenvalues) is sized once d and the eigenvalues' sizes are
    known: under a cap below its size refused at once, naming the cap."""
    with budget.limits(max_modulus_bits=2 ** 24):
        code, err = limited(library, lambda: sk.System(A=_sqrt2_matrix(), sensors=[sk.Sensor(C=[[1] * 16])]))
        assert code == 2, err
        with pytest.raises(BudgetError, match=r"pairs of conjugate eigenvalues of degree d = 32 is \d+.*--max-modulus-bits"):
            sk.System(A=_sqrt2_matrix(), sensors=[sk.Sensor(C=[[1] * 16])])


# -- eigenvalues without a closed form ------------------------------------------------------------

def _companion(a: list[int]) -> sp.Matrix:
    """The companion matrix of the monic ``x^n + a[n-1] x^(n-1) + ... + a[0]``."""
    n = len(a)
    return sp.Matrix(n, n, lambda i, j: (1 if i == j + 1 else 0) + (-a[i] if j == n - 1 else 0))


@pytest.fixture
def no_sympy_complex_isolation(monkeypatch):
    """Fail on sympy's isolation of complex roots (what a ``CRootOf`` of a non-real root needs: for
    the degree-32 eigenvalues of the 16 x 16 system below it took over 130 of ``analyze``'s CPU-s)."""
    from sympy.polys.rootoftools import ComplexRootOf

    def refuse(*args, **kwargs):
        raise AssertionError("sympy isolated complex roots")
    monkeypatch.setattr(ComplexRootOf, "_get_complexes", classmethod(refuse))


def test_generic_eigenvalues_are_flint_roots(no_sympy_complex_isolation):
    """x^3 - x - 1 (the plastic number rho ~ 1.3247 and two complex roots of product 1/rho and sum
    -rho, by Vieta): the real root keeps its ``CRootOf``, the complex pair, with no closed form, is
    ``FlintRoot`` 1 and 2 (flint's ordering: positive imaginary part first), never isolated by sympy."""
    blocks = cli._blocks_json(_companion([-1, -1, 0]))
    assert [b["eigenvalues"] for b in blocks] == [["CRootOf(x**3 - x - 1, 0)"],
                                                  ["FlintRoot(x**3 - x - 1, 1)", "FlintRoot(x**3 - x - 1, 2)"]]
    assert blocks[1]["eigenvalues_decimal"] == ["-0.6623589786 + 0.5622795121*I", "-0.6623589786 - 0.5622795121*I"]
    rho = sp.CRootOf(sp.Symbol("x") ** 3 - sp.Symbol("x") - 1, 0)
    z1, z2 = (e.expr for e in sk.eigen_blocks(_companion([-1, -1, 0]))[1].members)
    assert abs(sp.N(z1 * z2 - 1 / rho, 50)) < 1e-45 and abs(sp.N(z1 + z2 + rho, 50)) < 1e-45


def test_long_eigenvalues_abbreviated_in_text(tmp_path, capsys, no_sympy_complex_isolation):
    """x^5 + x^4 - (5 10^60 + 3) x^3 + (3 10^60 + 1) x^2 - (10^60 + 7) x + 5 (irreducible: three
    real roots, about -+sqrt(5) 10^30 and 10^-60, and a complex pair near 0.3 +- 0.33 i): the exact
    forms run past 200 characters, so the block line shows each as its decimal and degree, the way
    it shows a long modulus; the JSON keeps the exact ``FlintRoot``."""
    big = 10 ** 60
    a = [5, -(big + 7), 3 * big + 1, -(5 * big + 3), 1]
    rows = ", ".join("[" + ", ".join(f'"{v}"' for v in row) + "]" for row in _companion(a).tolist())
    path = tmp_path / "long.toml"
    path.write_text(f'[system]\nA = [{rows}]\n[[sensors]]\nC = [["0", "0", "0", "0", "1"]]\n')
    assert cli.main(["analyze", str(path)]) == 0
    text = capsys.readouterr().out
    words = " ".join(text.split())   # the block line is wrapped at 100 characters
    assert "root ≈ 0.3+0.3317i of a degree-5 polynomial, root ≈ 0.3-0.3317i of a degree-5 polynomial" in words
    assert "FlintRoot" not in text and "CRootOf" not in text and max(map(len, text.splitlines())) <= 100
    pair = [e for b in cli._blocks_json(_companion(a)) for e in b["eigenvalues"] if e.startswith("FlintRoot")]
    assert len(pair) == 2 and all(e.endswith(f"{k})") and f"- {5 * big + 3}*x**3" in e for e, k in zip(pair, (3, 4)))


@pytest.mark.full
def test_sqrt2_matrix_analyze_shows_eigenvalues_without_crootof(tmp_path, capsys, no_sympy_complex_isolation):
    """The 16 x 16 A with entries in {+-sqrt 2, 1, 1/2, 0} (eigenvalues of degree 32, no closed
    form), one sensor: ``analyze`` ran 181 CPU-s, printing the blocks: sympy isolated the 32
    ``CRootOf`` candidates of each eigenvalue (24 s) and degree-1024 resultants were built only to
    print aperiodicity proofs; now the eigenvalues are ``FlintRoot`` s, the block lines abbreviate
    them, the proofs state the certified argument, and the command takes 52 CPU-s, same verdict."""
    rows = ", ".join("[" + ", ".join(f'"{v}"' for v in row) + "]" for row in _sqrt2_matrix())
    path = tmp_path / "sqrt2.toml"
    path.write_text(f'[system]\nA = [{rows}]\n[[sensors]]\nC = [[{", ".join(["1"] * 16)}]]\n'
                    '[loss]\nkind = "iid"\nloss = ["1/2"]\n')
    assert cli.main(["analyze", "--json", str(path)]) in (0, 1)
    doc = __import__("json").loads(capsys.readouterr().out)
    shown = [e for b in doc["blocks"] for e in b["eigenvalues"]]
    assert len(shown) == 16 and sum(e.startswith("FlintRoot") for e in shown) >= 2
    assert sum(sum(b["eigenvalue_degrees"]) for b in doc["blocks"]) >= 16


def test_aperiodicity_proof_printed_without_the_ratio_polynomial(monkeypatch):
    """(3 + 4i)/(3 - 4i) = (-7 + 24 i)/25 is not a root of unity (not an algebraic integer); the
    proof is decided from the certified arg / (2 pi) ~ 0.2952 (no fraction of denominator <= 32
    there) and printed the same way, without the ratio's resultant (for the 16 x 16 system above,
    a degree-1024 resultant that took most of what remained of ``analyze``'s time)."""
    from symkf.exact import spectral

    def refuse(*args):
        raise AssertionError("ratio polynomial built")
    monkeypatch.setattr(spectral, "_ratio_poly", refuse)
    with budget.limits(max_proof_resultant_degree=2):  # below it (4) the proof prints the minimal polynomial
        (block,) = sk.eigen_blocks([["3/5", "-4/5"], ["4/5", "3/5"]])
        proof = block.proof
    assert block.tau is None and "has arg/(2 pi) in [0.2951672353" in proof
    assert "denominator <= 2 d^2 = 32" in proof and "not a root of unity (aperiodic)" in proof


def test_a_block_in_a_notebook_shows_its_modulus_eigenvalues_and_period():
    unit, = [b for b in eigen_blocks(sp.Matrix([[1, 1, 0], [0, 1, 0], [0, 0, 2]])) if b.modulus == 1]
    assert unit._repr_latex_() == r"$|\lambda| = 1:\quad \lambda \in \{1\ (\times 2)\},\quad g = 1$"
    plastic = eigen_blocks(sp.Matrix([[0, 0, 1], [1, 0, 1], [0, 1, 0]]))   # x^3 - x - 1: no short form
    assert plastic[0]._repr_latex_().startswith(r"$|\lambda| \approx 1.324717957:") and "aperiodic" in plastic[1]._repr_latex_()


# -- moduli from the products of pairs of eigenvalues -------------------------------------------

DENSE_6 = [[2, -1, 3, 0, 1, -2], [1, 0, -3, 2, 2, 1], [-2, 3, 1, 1, 0, -1],
           [0, 2, -1, -3, 1, 3], [3, 1, 0, 2, -2, 1], [-1, -3, 2, 1, 3, 0]]


@pytest.mark.parametrize("A", [
    DENSE_6,                                      # dense integer: complex pairs beside real eigenvalues
    _companion([-7, 3, 0, -2, 1]),             # x^5 + x^4 - 2x^3 + 3x - 7: real roots of both signs
    _companion([3, 0, 1, 0]),                  # x^4 + x^2 + 3: lambda, -lambda and conjugates, one modulus
    _companion([5, 0, 0, 1, 0, 0]),            # x^6 + x^3 + 5: lambda, omega lambda, omega^2 lambda (rotations)
])
def test_moduli_from_pair_products_agree_with_the_isolated_resultant(A):
    """The modulus named from the products lambda_i lambda_j (spectral._pair_modulus_poly) is the
    root that the old path (every root of the power-sum polynomial isolated) names: the same
    minimal polynomial and flint index; conjugates and rotated eigenvalues (lambda, -lambda,
    omega lambda) get one equal modulus, and a block holds exactly the eigenvalues of equal
    |lambda| (decided on balls)."""
    evs = eigenvalues(A)
    for ev in evs:
        if ev.is_real:
            continue
        f = tuple(int(c) for c in ev.minpoly.coeffs())
        ball = lambda prec, ev=ev: flint.acb(abs(ev.ball(prec)))  # noqa: E731
        assert (ev.modulus._poly, ev.modulus._index) == identify(_abs_poly(f), ball, "modulus")
    for block in eigen_blocks(A):
        members = {e.key for e in block.members}
        for ev in evs:
            size = abs(complex(ev.ball(128).mid()))
            assert (ev.key in members) == (abs(size - float(block.modulus)) < 1e-12)


def test_dense_moduli_are_named_without_isolating_the_pair_polynomial(monkeypatch):
    """For a dense 6 x 6 integer A (degree-6 characteristic polynomial, squarefree pair products)
    the moduli come from the roots of f alone: no polynomial of degree above 6 has its roots
    isolated, where the old path isolated the 30 roots of x^2-polynomial of the products."""
    isolated = []
    real = algebraic._complex_roots

    def spy(coeffs, prec):
        isolated.append(len(coeffs) - 1)
        return real(coeffs, prec)
    monkeypatch.setattr(algebraic, "_complex_roots", spy)
    monkeypatch.setattr(spectral, "_complex_roots", spy)
    A = [[v + 1 if i == j else v for j, v in enumerate(row)] for i, row in enumerate(DENSE_6)]
    moduli = [ev.modulus for ev in eigenvalues(A) if not ev.is_real]
    assert moduli and max(isolated) <= 6
    f = tuple(int(c) for c in eigenvalues(A)[0].minpoly.coeffs())
    assert spectral._pair_modulus_poly(f).degree() == 30
    for m, ev in zip(moduli, [ev for ev in eigenvalues(A) if not ev.is_real]):
        assert abs(float(m) - abs(complex(ev.ball(128).mid()))) < 1e-12


def test_products_that_coincide_fall_back_to_isolation():
    """x^4 + x^2 + 3 has roots lambda, -lambda and conjugates: lambda (-conj lambda) = -(lambda
    conj lambda) twice, so the pair polynomial is not squarefree and realness cannot be read off
    the pairs: the old path names the modulus 3^(1/4) (|lambda|^4 = |lambda^2|^2 = 3)."""
    assert spectral._pair_modulus_poly((3, 0, 1, 0, 1)) is None
    (block,) = eigen_blocks(_companion([3, 0, 1, 0]))
    assert block.modulus == sp.root(3, 4) and len(block.members) == 4


def test_pair_polynomial_of_a_dense_64_by_64_matrix_is_priced_before_it_is_built():
    """The pair polynomial of a dense 64 x 64 integer A (entries -3..3, seed 0) has about 5.6e7 bits
    by its estimate, under the default max_modulus_bits: below that cap the moduli are refused from
    the roots of the characteristic polynomial alone, within seconds, naming the cap."""
    import numpy as np
    A = [[int(v) for v in row] for row in np.random.default_rng(0).integers(-3, 4, (64, 64))]
    with budget.limits(max_modulus_bits=5 * 10 ** 7):
        code, err = limited(refused_at_once, lambda: eigen_blocks(A), "max_modulus_bits", 20.0)
    assert code == 0, err

