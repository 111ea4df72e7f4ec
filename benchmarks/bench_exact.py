"""Speed of the exact core: ranks over Q(zeta_24) and eigen-blocks of a 6x6 rational A.

1. Exact rank of the 96 x 4 matrix of rows c_i D^k (k = 0..23, four sensors), D the
   modal form diag(z, z^-1, z^5, z^-5) of the rotation pair R(pi/12), R(5 pi/12),
   z = exp(i pi/12), entries in Q(zeta_24) (degree 8).  Two cases: full rank (elimination
   stops after four pivots) and rank 3 (every c_i has last coordinate 0: every row is
   reduced).  Baseline: sympy's DomainMatrix rank over the same field
   (QQ<zeta_24>) on the already converted matrix, run in this process (converting the
   sympy entries into that domain takes sympy about 20 s; symkf converts in ~2 ms).
2. eigen_blocks of a random 6x6 rational A (eigenvalues, moduli, both periods, the
   diagonalizability proof).

Prints medians over repeats and the ratios.
"""

import random
import statistics
import time

import sympy as sp
from sympy.polys.matrices import DomainMatrix

from symkf.exact.field import NumberField
from symkf.exact.linalg import rank_rows
from symkf.exact.spectral import eigen_blocks
from timing import median_time

Z = sp.exp(sp.I * sp.pi / 12)


def modal_rows(last_zero: bool, seed: int = 1) -> sp.Matrix:
    rnd = random.Random(seed)
    diag = [Z, Z ** -1, Z ** 5, Z ** -5]
    rows = []
    for _ in range(4):
        c = [sp.Rational(rnd.randint(-9, 9), rnd.randint(1, 9)) or sp.Integer(1) for _ in range(4)]
        if last_zero:
            c[3] = sp.Integer(0)
        rows += [[c[j] * sp.expand_complex(diag[j] ** k) for j in range(4)] for k in range(24)]
    return sp.Matrix(rows)


def main() -> None:
    K = NumberField([sp.expand_complex(Z)])
    for label, last_zero, expected in (("full rank", False, 4), ("rank 3", True, 3)):
        M = modal_rows(last_zero)
        rows = K.matrix(M)
        assert rank_rows(K, rows, 4) == expected
        ours = median_time(lambda: rank_rows(K, rows, 4), 21)
        dom = sp.QQ.algebraic_field(sp.expand_complex(Z))
        dm = DomainMatrix.from_Matrix(M).convert_to(dom)
        assert dm.rank() == expected
        base = median_time(lambda: dm.rank(), 5)
        print(f"rank of 96x4 over Q(zeta24), {label}: symkf {ours * 1e3:.2f} ms, "
              f"sympy DomainMatrix {base * 1e3:.1f} ms, ratio {base / ours:.2f}x (target <= 10 ms)")

    rnd = random.Random(6)
    mats = [sp.Matrix(6, 6, lambda i, j: sp.Rational(rnd.randint(-9, 9), rnd.randint(1, 5))) for _ in range(7)]
    times = []
    for A in mats:
        t = time.perf_counter()
        eigen_blocks(A)
        times.append(time.perf_counter() - t)
    t6 = statistics.median(times)
    base = median_time(lambda: mats[0].eigenvals(), 1)
    print(f"eigen_blocks of a random 6x6 rational A: median {t6 * 1e3:.0f} ms over {len(mats)} matrices "
          f"(target <= 100 ms); sympy eigenvals of one of them {base * 1e3:.0f} ms, ratio {base / t6:.1f}x")


if __name__ == "__main__":
    main()
