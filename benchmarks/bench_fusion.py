"""Time the optimal fusion weights: Theorem 2's closed form against the SDP (Problem 2) and Problem 3.

N = 10 sensors, n = 4, Sigma singular as in eq. (20) (random orthonormal
observable bases of dimension 1..3 plus one full sensor).  Prints medians over
repeated runs in the same process and the SDP / closed-form ratio.  The
closed form's target is <= 50 ms.
"""

import statistics
import time

import numpy as np

from symkf.fusion import optimal_weights


def instance(seed: int, n: int = 4, N: int = 10):
    rng = np.random.default_rng(seed)
    Vs = [np.eye(n)] + [np.linalg.qr(rng.standard_normal((n, k)))[0] for k in rng.integers(1, n, N - 1)]
    L = rng.standard_normal((sum(V.shape[1] for V in Vs),) * 2)
    blocks = np.zeros((n * N, L.shape[0]))
    c = 0
    for i, V in enumerate(Vs):
        blocks[i * n:(i + 1) * n, c:c + V.shape[1]] = V
        c += V.shape[1]
    return blocks @ L @ L.T @ blocks.T, np.vstack([V @ V.T for V in Vs])


def median_ms(method: str, cases, repeats: int) -> float:
    times = []
    for Sigma, Vo in cases:
        for _ in range(repeats):
            t = time.perf_counter()
            optimal_weights(Sigma, Vo, method)
            times.append(1e3 * (time.perf_counter() - t))
    return statistics.median(times)


def main() -> None:
    cases = [instance(s) for s in range(5)]
    optimal_weights(*cases[0], "sdp")                      # import cvxpy outside the timing
    closed = median_ms("closed-form", cases, 20)
    kkt = median_ms("problem3", cases, 20)
    sdp = median_ms("sdp", cases, 2)
    print(f"N = 10, n = 4, Sigma 40 x 40 (rank < 40), 5 instances")
    print(f"closed form (Theorem 2): median {closed:8.2f} ms   (target <= 50 ms: {'met' if closed <= 50 else 'MISSED'})")
    print(f"Problem 3 (KKT system):  median {kkt:8.2f} ms   ratio to closed form {kkt / closed:6.2f}")
    print(f"SDP (Problem 2, Clarabel): median {sdp:8.2f} ms ratio to closed form {sdp / closed:6.1f}")


if __name__ == "__main__":
    main()
