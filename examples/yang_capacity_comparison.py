"""Capacity conditions of Yang et al. against exact critical loss rates (docs/capacity.md table).

Uses the exact engine ``symkf.stability`` for eps* and the verdicts;
``symkf.capacity.compare`` for the capacity thresholds.
Usage: python examples/yang_capacity_comparison.py
"""


import sympy as sp

from symkf import IID, Sensor, System
from symkf.capacity import comparison_table, critical_loss_comparison, verdict_comparison
from symkf.engine.stability import critical_loss_rate, stability

R = sp.Rational
SYSTEMS = [
    System(A=[[0, -2], [2, 0]], sensors=[Sensor(C=[[1, 0]])], name="rotation, C=[1 0]"),
    System(A=[[R(5, 4), 0], [1, R(11, 10)]], sensors=[Sensor(C=[[1, 1]])], name="lower-triangular, C=[1 1]"),
    System(A=[[2, 1], [0, 3]], sensors=[Sensor(C=[[1, 0], [0, 1]])], name="C = I"),
    System(A=[[2]], sensors=[Sensor(C=[[1]]), Sensor(C=[[1]])], name="a = 2, two sensors"),
    System(A=[[2, 0], [0, 3]], sensors=[Sensor(C=[[1, 0]]), Sensor(C=[[0, 1]])], name="diag(2,3), one mode each"),
    System(A=[[2, 0], [0, 3]], sensors=[Sensor(C=[[1, 0]]), Sensor(C=[[1, 1]])], name="diag(2,3), C2 sees both"),
    System(A=[[2, 0, 0], [0, R(3, 2), 0], [0, 0, R(-5, 4)]],
           sensors=[Sensor(C=[[1, 1, 1]]), Sensor(C=[[0, 1, 0]]), Sensor(C=[[0, 0, 1]])], name="diag(2,3/2,-5/4), N=3"),
]
UNEQUAL = [(SYSTEMS[4], ["1/5", "1/10"]), (SYSTEMS[4], ["1/10", "1/5"]), (SYSTEMS[5], ["1/2", "1/20"]),
           (SYSTEMS[3], ["1/10", "9/10"]), (SYSTEMS[3], ["3/5", "3/5"])]

if __name__ == "__main__":
    print(comparison_table([critical_loss_comparison(S, critical_loss_rate(S)) for S in SYSTEMS]))
    print()
    print("| system | loss | exact stable | C > ln rho | C > h(A) | Theorem 5 per sensor |")
    print("|---|---|---|---|---|---|")
    for S, loss in UNEQUAL:
        v = verdict_comparison(S, IID(loss), stability(S, IID(loss)).stable)
        assert v["consistent"], v
        print(f"| {S.name} | {', '.join(loss)} | {v['exact_stable']} | {v['C_gt_ln_rho']} | "
              f"{v['C_gt_entropy']} | {v['theorem5_per_sensor']} |")
