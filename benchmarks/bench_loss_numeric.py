"""Monte Carlo fixed cost (the exact-engine part): float (P, initial, emit) of i.i.d. and
Gilbert-Elliott losses for d sensors by ``LossModel.numeric()`` (Kronecker products of the sensors'
2x2 chains in float64).  Baseline, measured in the same process on a fresh model: ``loss.chain.numeric()``
(the 2^d x 2^d exact sympy chain, then floats), run only for d <= BASELINE_MAX (its exact entries
grow like 4^d).  CPU seconds (time.process_time), medians.  Usage: python bench_loss_numeric.py [REPEATS] [BASELINE_MAX]"""

import statistics
import sys
import time

import numpy as np

import symkf as sk
from symkf import budget


def cpu(fn, repeats):
    times, out = [], None
    for _ in range(repeats):
        start = time.process_time()
        out = fn()
        times.append(time.process_time() - start)
    return statistics.median(times), out


def main(repeats: int, baseline_max: int) -> None:
    print("float loss chains: LossModel.numeric() vs loss.chain.numeric(); CPU seconds, medians")
    for name, make in (("IID", lambda d: sk.IID(["1/10"] * d)),
                       ("GilbertElliott", lambda d: sk.GilbertElliott(["1/10"] * d, ["1/2"] * d))):
        for d in (4, 6, 8, 10, 11):
            new, fast = cpu(lambda: make(d).numeric(), repeats)
            line = f"  {name:15s} d = {d:2d}: new {new:8.4f}"
            if d <= baseline_max:
                with budget.limits(max_markov_states=2 ** d):   # the joint chain is refused by default
                    old, ref = cpu(lambda: make(d).chain.numeric(), 1)
                agree = all(np.allclose(a, b, rtol=1e-15 * d, atol=0) for a, b in zip(fast, ref))
                line += f"   chain {old:8.3f}   ratio {old / new:8.0f}x   same floats (rtol {d}e-15): {agree}"
            print(line)


if __name__ == "__main__":
    main(int(sys.argv[1]) if len(sys.argv) > 1 else 3, int(sys.argv[2]) if len(sys.argv) > 2 else 8)
