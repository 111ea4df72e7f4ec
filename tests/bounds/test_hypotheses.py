"""The hypotheses of the published results decided exactly (symkf.bounds.hypotheses): Mo and
Sinopoli's non-degeneracy by hand."""



import symkf as sk
from symkf.bounds import hypotheses as hyp


def system(A, *rows, single=True):
    """One sensor holding all ``rows`` (``single``) or one sensor per row."""
    sensors = [sk.Sensor(C=list(rows))] if single else [sk.Sensor(C=[r]) for r in rows]
    return sk.System(A=A, sensors=sensors)


ROT3 = [[0, -4], [1, -2]]          # eigenvalues 2 e^(+-2 pi i/3): g = 3


def test_non_degenerate_by_hand():
    # diag(2, -2): one equiblock of size 2; C = [1 1] has rank C T = 1 (degenerate), C = I rank 2
    assert not hyp.non_degenerate(system([[2, 0], [0, -2]], [1, 1])).holds
    assert hyp.non_degenerate(system([[2, 0], [0, -2]], [1, 0], [0, 1])).holds
    assert hyp.non_degenerate(system([[2, 0], [0, 3]], [1, 1])).holds
    # a complex pair (one equiblock) with a scalar measurement is always degenerate
    assert not hyp.non_degenerate(system(ROT3, [1, 0])).holds
