"""Number fields Q(theta) (symkf.exact.field, embedding, nfpoly): exact conversions and factorisations.

Round trips are checked independently of symkf: trigonometric values are rewritten as
powers of z = exp(i pi / N) and reduced modulo the cyclotomic polynomial (exact), radicals
through sympy's minimal polynomial of the difference; the field degree is the degree of
sympy's minimal polynomial of theta; small fields are compared with sympy's algebraic_field."""

from math import gcd

import flint
import pytest
import sympy as sp
from hypothesis import given, settings
from hypothesis import strategies as st

from symkf.errors import InputError
from symkf.exact import nfpoly
from symkf.exact.embedding import integral_scale
from symkf.exact.field import NumberField

x, z = sp.symbols("x z")


def vanishes_cyclotomic(expr: sp.Expr, N: int) -> bool:
    """Exactly whether ``expr`` (trig / exp of multiples of pi/N) is zero: a polynomial in
    z = exp(i pi/N) reduced modulo the 2N-th cyclotomic polynomial."""
    e = sp.expand(expr.rewrite(sp.exp))

    def power(t):
        k = t.args[0] / (sp.I * sp.pi) * N
        assert k.is_Integer, t
        return z ** int(k)
    e = e.replace(lambda t: isinstance(t, sp.exp), power)
    if N % 2 == 0:  # i = z^(N/2) (sine rewrites carry a bare I)
        e = sp.expand(e.subs(sp.I, z ** (N // 2)))
    num = sp.numer(sp.together(e))
    return sp.rem(sp.Poly(num, z), sp.Poly(sp.cyclotomic_poly(2 * N, z), z)).is_zero


ANGLES = [(p, q) for q in range(1, 13) for p in range(1, 2 * q) if gcd(p, q) == 1 and q > 2]


@pytest.mark.parametrize("p,q", ANGLES)
def test_trig_round_trip(p, q):
    c, s = sp.cos(sp.pi * p / q), sp.sin(sp.pi * p / q)
    K = NumberField([c, s])
    N = 4 * q  # theta may be 2 cos(2 pi/m) with m = lcm(4, 2q): exp(i pi/(4q)) covers every such m
    for a in (c, s, c * s + 3, c ** 2 + s ** 2):
        assert vanishes_cyclotomic(K.to_sympy(K.convert(a)) - a, N)
    assert K.convert(c ** 2 + s ** 2) == flint.fmpq_poly([1])


def test_modal_field_of_rotation():
    # Q(cos 3pi/11, sin 3pi/11) = Q(zeta_44)^+ has degree 10; adjoining exp(3 i pi / 11) doubles it
    t = 3 * sp.pi / 11
    r = sp.Rational(3, 2)
    c, s = sp.cos(t), sp.sin(t)
    assert NumberField([r * c, -r * s, r * s]).degree == 10
    lam, mu = r * sp.exp(sp.I * t), r * sp.exp(-sp.I * t)
    K = NumberField([r * c, -r * s, r * s, lam, mu])
    assert K.degree == 20
    # identities that hold only if every representation denotes the intended conjugate
    L, M, C, S, i = (K.convert(v) for v in (lam, mu, c, s, sp.I))
    assert K.mul(i, i) == K.convert(-1)
    R = K.convert(r)
    assert L == K.mul(R, C + K.mul(i, S)) and M == K.mul(R, C - K.mul(i, S))
    assert K.mul(L, M) == K.convert(r ** 2)
    ratio = K.mul(L, K.inv(M))  # exp(6 i pi / 11), of order 11
    assert K.pow(ratio, 11) == K.convert(1) and ratio != K.convert(1)


@pytest.mark.parametrize("gens,degree", [
    ([sp.sqrt(2), sp.sqrt(3)], 4),
    ([sp.sqrt(2), -sp.sqrt(2), 2 * sp.sqrt(2) + 1], 2),
    ([sp.cbrt(2), sp.I * sp.sqrt(3)], 6),
    ([sp.cos(sp.pi / 12), sp.sin(sp.pi / 12)], 4),
    ([sp.sqrt(2) + sp.sqrt(3), sp.sqrt(6)], 4),
])
def test_primitive_element_degree(gens, degree):
    K = NumberField(gens)
    assert K.degree == degree
    # theta's minimal polynomial by sympy is the modulus
    assert sp.Poly(sp.minimal_polynomial(K.theta, x), x).monic().as_expr() == \
        sum(sp.Rational(int(c.p), int(c.q)) * x ** i for i, c in enumerate(K.modulus.coeffs()))
    for g in gens:
        assert sp.minimal_polynomial(K.to_sympy(K.convert(g)) - g, x) == x


def test_radical_round_trips():
    K = NumberField([sp.cbrt(2), sp.I * sp.sqrt(3)])
    w = (-1 + sp.I * sp.sqrt(3)) / 2  # a cube root of unity: w cbrt(2) is another root of x^3 - 2
    for a in (w * sp.cbrt(2), sp.cbrt(4) / 3 + w, 1 / (1 + sp.cbrt(2))):
        assert sp.minimal_polynomial(K.to_sympy(K.convert(a)) - a, x) == x


@pytest.mark.parametrize("gens,a", [
    ([sp.sqrt(2)], sp.sqrt(3)),
    ([sp.cos(2 * sp.pi / 7)], sp.sin(2 * sp.pi / 7)),
    ([sp.cos(3 * sp.pi / 11), sp.sin(3 * sp.pi / 11)], sp.I),
    ([sp.sqrt(2)], sp.pi),
    ([], sp.sqrt(2)),
])
def test_non_members_refused(gens, a):
    with pytest.raises(InputError, match="not in the number field"):
        NumberField(gens).convert(a)


def test_rational_field_accepts_disguised_rationals():
    assert NumberField([]).convert(sp.sqrt(8) / sp.sqrt(2)) == flint.fmpq_poly([2])
    assert NumberField([sp.sqrt(2)]).convert(sp.cos(sp.pi / 3)) == flint.fmpq_poly([1]) / 2


def test_integral_scale():
    # 2 x^2 - 3: sqrt(3/2) needs c = 2 (2 sqrt(3/2) = sqrt 6); 8 x^3 + 1: 2 * (-1/2) = -1
    assert integral_scale(flint.fmpz_poly([-3, 0, 2])) == (2, flint.fmpz_poly([-6, 0, 1]))
    assert integral_scale(flint.fmpz_poly([1, 0, 0, 8])) == (2, flint.fmpz_poly([1, 0, 0, 1]))
    # 4 x^2 - 2 (sqrt(2)/2 ... primitive form 2 x^2 - 1): c = 2, (2 b)^2 = 2
    assert integral_scale(flint.fmpz_poly([-1, 0, 2])) == (2, flint.fmpz_poly([-2, 0, 1]))


def _poly(K, coeffs):
    return [K.convert(c) for c in coeffs]


def _expr(K, f):
    return sp.expand(sum(K.to_sympy(c) * x ** i for i, c in enumerate(f)))


def test_trager_factorisations():
    K = NumberField([sp.sqrt(2)])
    fs = nfpoly.factor(K, _poly(K, [4, 0, -4, 0, 1]))  # (x^2 - 2)^2
    assert sorted((str(_expr(K, h)), e) for h, e in fs) == [("x + sqrt(2)", 2), ("x - sqrt(2)", 2)]
    Ki = NumberField([sp.I])
    fs = nfpoly.factor(Ki, _poly(Ki, [1, 0, 0, 0, 1]))  # x^4 + 1 = (x^2 - i)(x^2 + i)
    assert sorted(str(_expr(Ki, h)) for h, _ in fs) == sorted(["x**2 - I", "x**2 + I"])
    K8 = NumberField([sp.exp(sp.I * sp.pi / 4)])
    fs = nfpoly.factor(K8, _poly(K8, [1, 0, 0, 0, 1]))
    assert [len(h) - 1 for h, _ in fs] == [1, 1, 1, 1]
    assert nfpoly.factor(K, _poly(K, [-3, 0, 1])) == [(_poly(K, [-3, 0, 1]), 1)]  # irreducible over Q(sqrt 2)


def test_charpoly_and_norm():
    K = NumberField([sp.sqrt(2), sp.sqrt(3)])
    M = sp.Matrix([[sp.sqrt(2), 1, 0], [sp.sqrt(3), 2, sp.sqrt(6)], [1, 0, -sp.sqrt(2)]])
    chi = nfpoly.charpoly(K, K.matrix(M))
    assert sp.expand(_expr(K, chi) - M.charpoly(x).as_expr()) == 0
    # N(x - sqrt 2) over Q(sqrt 2, sqrt 3) = (x^2 - 2)^2
    assert nfpoly.norm(K, _poly(K, [-sp.sqrt(2), 1])) == flint.fmpq_poly([4, 0, -4, 0, 1])


SQRTS = [2, 3, 5, 6, 7]


@settings(max_examples=25, deadline=None)
@given(st.lists(st.sampled_from(SQRTS), min_size=1, max_size=2, unique=True),
       st.lists(st.integers(-4, 4), min_size=3, max_size=3))
def test_against_sympy_algebraic_field(radicands, c):
    gens = [sp.sqrt(n) for n in radicands]
    a = c[0] + c[1] * gens[0] + c[2] * gens[-1] * gens[0]
    K = NumberField(gens)
    Ks = sp.QQ.algebraic_field(*gens)
    assert K.degree == Ks.mod.degree()
    ours, theirs = K.to_sympy(K.convert(a)), Ks.to_sympy(Ks.from_sympy(a))
    assert sp.minimal_polynomial(ours - theirs, x) == x


@pytest.mark.parametrize("g", [sp.pi, sp.Symbol("a"), sp.exp(1)])
def test_non_algebraic_generators_refused(g):
    with pytest.raises(InputError, match="cannot build the number field"):
        NumberField([sp.sqrt(2), g])


def test_radicals_of_cyclotomic_fields_join_the_cyclotomic_presentation():
    """sympy writes cos(2 pi/5) = (sqrt 5 - 1)/4 and sin(2 pi/5) = sqrt(sqrt 5/8 + 5/8): by hand
    sqrt 5 = 1 + 4 cos(2 pi/5) = 1 + 2 t (t = 2 cos(2 pi/5), the real subfield of Q(zeta_5)) and
    sin(2 pi/5) = cos(2 pi/20) = u/2 (u = 2 cos(2 pi/20)).  With the rotations by 2 pi/7, 2 pi/9
    and the eigenvalue exp(2 pi i/5) the field is Q(zeta_1260) (degree phi(1260) = 288), presented
    by its cyclotomic polynomial, not by a generic primitive element (minutes, before, to decide
    that sqrt 5 lies in it); sqrt 7 (in Q(zeta_28)^+ of degree 6) and cbrt 2 (not abelian) are not
    recognised."""
    from symkf.exact.field import _cyclotomic_radicals
    c5, s5 = sp.cos(2 * sp.pi / 5), sp.sin(2 * sp.pi / 5)
    assert not c5.has(sp.cos) and not s5.has(sp.sin)  # sympy's radicals
    found = _cyclotomic_radicals([c5, s5, sp.sqrt(7), sp.cbrt(2)])
    assert found.keys() == {sp.sqrt(5), s5}
    assert found[sp.sqrt(5)][:2] == (5, True) and found[sp.sqrt(5)][2] == flint.fmpq_poly([1, 2])
    assert found[s5][:2] == (20, True) and found[s5][2] == flint.fmpq_poly([0, flint.fmpq(1, 2)])
    gens = [c5, s5, sp.cos(2 * sp.pi / 7), sp.sin(2 * sp.pi / 7), sp.cos(2 * sp.pi / 9), sp.sin(2 * sp.pi / 9),
            sp.exp(2 * sp.pi * sp.I / 5)]
    K = NumberField(gens)
    assert K.degree == 288 and K.modulus == flint.fmpq_poly(flint.fmpz_poly.cyclotomic(1260))
    C, S, E = (K.convert(v) for v in (c5, s5, sp.exp(2 * sp.pi * sp.I / 5)))
    assert K.mul(C, C) + K.mul(S, S) == K.convert(1)
    assert K.mul(K.convert(sp.sqrt(5)), K.convert(sp.sqrt(5))) == K.convert(5)
    assert 2 * C == E + K.inv(E)  # 2 cos(2 pi/5) = zeta_5 + zeta_5^-1: the intended conjugate
    for g in gens[2:]:  # the trigonometric atoms, by Euler's formula independently of symkf
        assert vanishes_cyclotomic(K.to_sympy(K.convert(g)) - g, 630)


def _rotation_field(m, scale=2):
    c, s = sp.cos(2 * sp.pi / m), sp.sin(2 * sp.pi / m)
    K = NumberField([c, s])
    return K, nfpoly.charpoly(K, K.matrix(scale * sp.Matrix([[c, -s], [s, c]])))


@pytest.mark.parametrize("m", [5, 7, 13])
def test_quadratic_with_negative_discriminant_is_factored_as_trager_factors_it(m, monkeypatch):
    """x^2 - 4 cos(2 pi/m) x + 4 over Q(cos, sin) has discriminant -16 sin^2(2 pi/m) < 0 at the real
    embedding: irreducible without the norm, and Trager's algorithm agrees."""
    K, chi = _rotation_field(m)
    fast = nfpoly.factor(K, chi)
    monkeypatch.setattr(nfpoly, "_negative_at_real_embedding", lambda K, a: False)
    assert fast == nfpoly.factor(K, chi) == [(nfpoly.monic(K, chi), 1)]


def test_quadratic_with_positive_discriminant_goes_to_trager():
    """x^2 - 2 over Q(sqrt 2) splits (discriminant 8 > 0: no shortcut); x^2 + 1 over Q(i) too
    (theta = i is not real)."""
    K = NumberField([sp.sqrt(2)])
    assert not nfpoly._negative_at_real_embedding(K, _poly(K, [8])[0])
    assert len(nfpoly.factor(K, _poly(K, [-2, 0, 1]))) == 2
    Ki = NumberField([sp.I])
    assert not nfpoly._negative_at_real_embedding(Ki, _poly(Ki, [-4])[0])
    assert len(nfpoly.factor(Ki, _poly(Ki, [1, 0, 1]))) == 2


@pytest.mark.parametrize("m, scale", [(5, 2), (7, 2), (13, 2), (7, sp.Rational(3, 2)), (9, 1)])
def test_unit_root_minpoly_is_the_factor_of_the_norm(m, scale):
    """The roots scale * exp(+-2 pi i/m) of a rotation's characteristic polynomial: their minimal
    polynomial c^d Phi_m(x/c) (primitive) is the factor of Trager's norm that they are roots of."""
    K, chi = _rotation_field(m, scale)
    ((h, _),) = nfpoly.factor(K, chi)
    g = nfpoly.unit_root_minpoly(K, h)
    expected = sp.Poly(scale ** sp.totient(m) * sp.cyclotomic_poly(m, x / scale), x).clear_denoms()[1].primitive()[1]
    assert [int(c) for c in reversed(g.coeffs())] == expected.all_coeffs()
    norm_factors = [f.numer() // f.numer().content() for f, _ in nfpoly.norm(K, h).factor()[1]]
    assert g in norm_factors or -g in norm_factors


def test_unit_root_minpoly_refuses_other_roots():
    """1 + 2 exp(+-2 pi i/7) (|.| irrational) and 2 sqrt 2 exp(+-2 pi i/7) (c^2 = 8, c irrational):
    no scaled root of unity by a rational c."""
    c, s = sp.cos(2 * sp.pi / 7), sp.sin(2 * sp.pi / 7)
    K = NumberField([c, s, sp.sqrt(2)])
    for M in (sp.eye(2) + 2 * sp.Matrix([[c, -s], [s, c]]), 2 * sp.sqrt(2) * sp.Matrix([[c, -s], [s, c]])):
        ((h, _),) = nfpoly.factor(K, nfpoly.charpoly(K, K.matrix(M)))
        assert nfpoly.unit_root_minpoly(K, h) is None


def test_lucas_ladder_is_the_chebyshev_recurrence():
    """V_k(theta) = 2 cos(2 pi k/60) at theta = 2 cos(2 pi/60), from the ladder, equals the
    three-term recurrence V_(k+1) = theta V_k - V_(k-1) reduced modulo theta's minimal polynomial."""
    from symkf.exact.field import _lucas
    mod, t = flint.fmpq_poly(flint.fmpz_poly.cos_minpoly(60)), flint.fmpq_poly([0, 1])
    V = [flint.fmpq_poly([2]), t]
    for _ in range(40):
        V.append((t * V[-1] - V[-2]) % mod)
    assert all(_lucas(k, t, mod) == V[k] % mod for k in range(42))


def test_roots_of_unity_of_the_cyclotomic_presentation_are_exponents_of_theta():
    """Q(zeta_9, cos(2 pi/7), sin(2 pi/7)) is Q(zeta_252) (degree phi(252) = 72, theta = zeta_252):
    exp(2 pi i/9) = theta^28, -1 = theta^126, exp(2 pi i/9) exp(2 pi i/7)^3 = theta^(28 + 108),
    -exp(2 pi i/9) = theta^154; 1/2, cos(2 pi/7) and 2 exp(2 pi i/9) are no roots of unity.  The
    product by theta^k takes k of any sign, modulo 252.  A field presented by a generic primitive
    element, or by 2 cos(2 pi/7) (real), has no root order."""
    z9, c7, s7 = sp.exp(2 * sp.pi * sp.I / 9), sp.cos(2 * sp.pi / 7), sp.sin(2 * sp.pi / 7)
    K = NumberField([z9, c7, s7])
    assert (K.degree, K.root_order) == (72, 252)
    z7 = K.convert(c7 + sp.I * s7)
    cases = [(K.convert(z9), 28), (flint.fmpq_poly([-1]), 126), (K.mul(K.convert(z9), K.pow(z7, 3)), 136),
             (flint.fmpq_poly([1]), 0), (K.convert(-z9), 154)]
    assert [K.root_exponent(a) for a, _ in cases] == [k for _, k in cases]
    assert [K.root_exponent(K.convert(a)) for a in (sp.Rational(1, 2), c7, 2 * z9)] == [None] * 3
    a = K.convert(1 + 3 * z9)
    assert K.times_root_power(a, -28) == K.mul(a, K.inv(K.convert(z9)))
    assert K.times_root_power(a, 300) == K.mul(a, K.pow(flint.fmpq_poly([0, 1]), 48))
    for L in (NumberField([sp.sqrt(2)]), NumberField([c7])):
        assert L.root_order == 0 and L.root_exponent(flint.fmpq_poly([-1])) is None
        with pytest.raises(InputError, match="no root of unity"):
            L.times_root_power(flint.fmpq_poly([1]), 1)
