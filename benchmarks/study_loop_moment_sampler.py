"""Study of a sampler for the closed loop's divergence: conditional moments with Doob-twisted losses.

Not used by symkf yet; measures what a replacement of the final-burst sampler of
:func:`symkf.numeric.closed_loop.loop_divergence` would decide, at the points of
``tests/control/test_control_verify.py`` and at UDP-like scalar noiseless points.

The loop (Schenato, Sinopoli, Franceschetti, Poolla, Sastry, "Foundations of control and
estimation over lossy networks", Proc. IEEE 95(1), 2007, Sections IV-V) is linear given the loss
sequence, with the filter's gains a function of the observations' losses (TCP-like: the Kalman
gain of ``P_{k|k-1}``; UDP-like: ``P`` takes ``E[u u' | losses]`` in place of ``u u'``, the same gain
as the simulated estimator when the measurements are noiseless).  So ``Sigma_k = E[z_k z_k' |
losses]``, ``z = (x_k, x^_{k|k-1})``, follows ``Sigma' = M_o Sigma M_o' + N_o`` for each step's
outcome ``o = (gamma_k, Gamma_k)`` and ``E[x_K' W x_K | losses]`` is computed, not sampled
(Rao-Blackwellisation: the noises leave the estimator's variance).  Only the losses are drawn,
from a path-level mixture (balance heuristic, exact likelihood ratios ``p / sum_c a_c q_c``: each
component's path probability is known for every path since ``Sigma_k`` is a function of the
losses):

0. the losses' own law (1/10, defensive);
1. the controls twisted by ``<H_{k+1}, E[x_{k+1} x_{k+1}' | o]>``, ``H_k = T*^(K-k) W`` the backward
   value of the control MJLS ``T*(H) = sum_a p(a) (A - B a L)' H (A - B a L)``, observations from
   their law: for TCP-like loops the Doob transform of ``x^``'s second moment (exact: the controls'
   losses do not touch the filter), so ``w v`` is nearly constant on the paths it draws;
2. every outcome twisted by ``<H_{k+1}, Sigma'_o> + c_{k+1}``, the backward value (with its noise
   term ``c``) of the loop's linear model with the steady gain of the filter that receives
   everything: exact for the UDP-like scalar noiseless loop (gain ``1 / c`` whenever received);
3. the observations twisted by the next ``tr P`` (greedy), controls from their law.

Measured on 2026-12-06 (horizons 30, 60, 90; verdicts by
:func:`symkf.numeric.montecarlo._divergence_verdict`, tolerance 0.01, confidence 0.999):

* UDP-like scalar noiseless (a = 2, 6/5; gamma = 9/10, 19/20; nu = nu_udp(gamma) +- 1/25),
  2000 paths: relative standard errors 2-3 %, every verdict right at seed 0 (6.7 CPU-s for the
  eight points); over the 20 seeds 0, 3, .., 57 (``--udp --seed S``): 160 of 160 verdicts right,
  none undecided, about 7 CPU-s per seed.  The bounded points' largest ``growth_high`` was 1.0068
  (a = 6/5) against 1 + tolerance = 1.01, the unbounded points' least margin lower end 1.029:
  the bounded side's margin is thin, a longer horizon is wanted there.
* TCP-like, the points of ``tests/control/test_control_verify.py`` (4000 paths, seed 0, R of the
  twist's model as given): scalar plants 6 of 6 right (rel. stderr 1-3 %); 2R(pi/2) 3 of 3
  (both sides; the old sampler left all three undecided); the Jordan block below nu_c = 65/81
  "unstable" with margin 1.108 in [1.079, 1.121] (exact second moments: 1.107), above it
  undecided (rel. stderr up to 0.3); two modes, one input: both unbounded points right, the
  bounded one undecided (rel. stderr 0.12-0.23 whatever the mixture: the heavy tail of the
  observations' losses, (1 - gamma) alpha^4 = 4.5 > 1, is carried by paths of the defensive
  component that no twisted component proposes); two modes, B invertible: the solve of the gains
  fails (a covariance leaves float64 under the twisted bursts).  No wrong verdict was seen.
  What is missing is a twist of the observations that values the covariance a reception moves
  into ``x^`` (the filter's tail), then the calibration over 20 seeds and the integration into
  :func:`~symkf.numeric.closed_loop.loop_divergence`.

    nice -n 10 python benchmarks/study_loop_moment_sampler.py [--tcp] [--udp] [--paths 4000] [--horizon 90]
"""

from __future__ import annotations

import argparse
import itertools
import pathlib
import sys
import time

import numpy as np
import sympy as sp

ROOT = pathlib.Path(__file__).resolve().parents[1]
sys.path[:0] = [str(ROOT), str(ROOT / "tests"), str(ROOT / "tests" / "control")]

import symkf as sk  # noqa: E402
from symkf.control.loop import lqg_stable  # noqa: E402
from symkf.control.threshold import critical_arrival_rate  # noqa: E402
from symkf.control.udp import udp_threshold  # noqa: E402
from symkf.control.verify import _udp_theory  # noqa: E402
from symkf.model.iid import IID  # noqa: E402
from symkf.numeric.closed_loop import control_riccati, loop_plant, plant_of  # noqa: E402
from symkf.numeric.montecarlo import _divergence_verdict, _weighted_log_mean, rate_horizons  # noqa: E402

MIX = (0.1, 0.3, 0.3, 0.3)


def patterns(rates):
    """All reception patterns of independent channels (1 received) and their probabilities."""
    pats = np.array(list(itertools.product((1, 0), repeat=len(rates))), float)
    return pats, np.prod(np.where(pats == 1, rates, 1 - rates), axis=1)


def steady(plant):
    """``P_{k|k-1}`` of the filter receiving everything, iterated from ``P0``."""
    A, C, Q, R = plant.A, plant.C, plant.Q, plant.R
    P = plant.P0.copy()
    for _ in range(2000):
        CP = C @ P
        nxt = A @ (P - CP.T @ np.linalg.solve(CP @ C.T + R, CP)) @ A.T + Q
        nxt = (nxt + nxt.T) / 2
        if np.allclose(nxt, P, rtol=1e-12, atol=1e-14) or np.abs(nxt).max() > 1e12:
            break
        P = nxt
    return P


def maps(plant, L, protocol, g, a, lam, P):
    """Per outcome (and path): ``M`` with ``z' = M z + D K v + w``, ``D K``, ``J`` (``x^_{k|k} = J z + K v``), ``K``."""
    A, B, C, R = plant.A, plant.B, plant.C, plant.R
    n, p = plant.n, C.shape[0]
    CP = (C @ P)[..., None, :, :]
    S = (CP @ C.T + R) * (g[:, :, None] * g[:, None, :]) + np.eye(p) * (1 - g)[:, :, None]
    K = np.swapaxes(np.linalg.solve(S, CP * g[:, :, None]), -1, -2)
    KC = K @ C
    J = np.concatenate([KC, np.eye(n) - KC], axis=-1)
    BGL = B @ (a[:, :, None] * L)
    BEL = BGL if protocol == "tcp" else np.broadcast_to(B @ (lam[:, None] * L), BGL.shape)
    D = np.concatenate([-BGL, A - BEL], axis=-2)
    M = D @ J
    M[..., :n, :n] += A
    return M, D @ K, J, K


def run(plant, L, protocol, rs, ra, K, m, rng):
    """``log E[x_K' W x_K | losses]`` and ``log dP/dQ`` per path (one channel per side)."""
    A, B, C, Q, R, W = plant.A, plant.B, plant.C, plant.Q, plant.R, plant.W
    n, ix_s, ix_a = plant.n, np.zeros(C.shape[0], int), np.zeros(B.shape[1], int)
    gG, pg = patterns(rs)
    aA, pa = patterns(ra)
    nG, nA = len(pg), len(pa)
    p = np.outer(pg, pa).ravel()
    g, a = np.repeat(gG, nA, axis=0)[:, ix_s], np.tile(aA, (nG, 1))[:, ix_a]
    lam = ra[ix_a]
    Qz, Wz = np.zeros((2 * n, 2 * n)), np.zeros((2 * n, 2 * n))
    Qz[:n, :n], Wz[:n, :n] = Q, W
    Ms, Ns, _, _ = maps(plant, L, protocol, g, a, lam, steady(plant))
    H, c, Hc = [None] * (K + 1), np.zeros(K + 1), [None] * (K + 1)
    H[K], Hc[K] = Wz / np.trace(Wz), W / np.trace(W)
    Fa = A - B @ (aA[:, ix_a][:, :, None] * L)
    for k in range(K - 1, -1, -1):
        nxt = np.einsum("o,oji,jk,okl->il", p, Ms, H[k + 1], Ms)
        cn = c[k + 1] + np.einsum("ij,ij", H[k + 1], Qz) + np.einsum("o,oij,jk,olk,il", p, Ns, R, Ns, H[k + 1])
        s = np.trace(nxt) + 1e-300
        H[k], c[k] = nxt / s, cn / s
        nc = np.einsum("a,aji,jk,akl->il", pa, Fa, Hc[k + 1], Fa)
        Hc[k] = nc / (np.trace(nc) + 1e-300)
    Sig = np.zeros((m, 2 * n, 2 * n))
    Sig[:, :n, :n] = plant.P0
    P = np.broadcast_to(plant.P0, (m, n, n)).copy()
    logp, logq = np.zeros(m), np.zeros((3, m))
    comp = np.searchsorted(np.cumsum(MIX), rng.random(m), side="right")
    rows, I = np.arange(m), np.eye(n)
    V = np.where(ix_a[:, None] == ix_a[None, :], (lam * (1 - lam))[:, None], 0.0)
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        for k in range(K):
            M, Nv, J, Kt = maps(plant, L, protocol, g, a, lam, P)
            Sn = M @ Sig[:, None] @ np.swapaxes(M, -1, -2) + Nv @ R @ np.swapaxes(Nv, -1, -2) + Qz
            Sn = (Sn + np.swapaxes(Sn, -1, -2)) / 2
            h1 = np.clip(np.einsum("poij,ij->po", Sn[:, :, :n, :n], Hc[k + 1]), 1e-300, None).reshape(m, nG, nA)
            q1 = pa * h1
            q1 = (pg[:, None] * q1 / q1.sum(axis=2, keepdims=True)).reshape(m, -1)
            q2 = p * np.clip(np.einsum("poij,ij->po", Sn, H[k + 1]) + c[k + 1], 1e-300, None)
            q2 = q2 / q2.sum(axis=1, keepdims=True)
            t = pg * np.clip(np.trace(P, axis1=1, axis2=2)[:, None]
                             - np.einsum("pgij,pij->pg", maps(plant, L, protocol, gG[:, ix_s], aA[:1].repeat(nG, 0)[:, ix_a],
                                                             lam, P)[3] @ C, P), 1e-300, None)
            q3 = ((t / t.sum(axis=1, keepdims=True))[:, :, None] * pa).reshape(m, -1)
            q = np.select([comp[:, None] == 0, comp[:, None] == 1, comp[:, None] == 2], [p[None], q1, q2], q3)
            o = (np.cumsum(q, axis=1)[:, :-1] <= rng.random(m)[:, None]).sum(axis=1)
            logp += np.log(p[o])
            logq += np.log(np.stack([q1[rows, o], q2[rows, o], q3[rows, o]]))
            if protocol == "udp":
                Jo, Ko = J[rows, o], Kt[rows, o]
                Euu = L @ (Jo @ Sig @ np.swapaxes(Jo, -1, -2) + Ko @ R @ np.swapaxes(Ko, -1, -2)) @ L.T
            Sig = Sn[rows, o]
            KC, Ko = (Kt @ C)[rows, o], Kt[rows, o]
            P = A @ ((I - KC) @ P @ np.swapaxes(I - KC, -1, -2) + Ko @ R @ np.swapaxes(Ko, -1, -2)) @ A.T + Q
            if protocol == "udp":
                P = P + B @ (V * Euu) @ B.T
            P = (P + np.swapaxes(P, -1, -2)) / 2
            if not (np.all(np.isfinite(P)) and np.all(np.isfinite(Sig))):
                raise FloatingPointError(f"left float64 at step {k}")
        mix = np.log(np.array(MIX))[:, None]
        logw = logp - np.logaddexp.reduce(np.vstack([mix[0] + logp, mix[1:] + logq]), axis=0)
        return np.log(np.einsum("pij,ij->p", Sig[:, :n, :n], W)), logw


def divergence(plant, L, protocol, g, v, horizon, paths, seed):
    runs = []
    for j, k in enumerate(rate_horizons(horizon, 1)):
        lv, lw = run(plant, L, protocol, np.array([g]), np.array([v]), k, paths, np.random.default_rng(seed + j))
        runs.append(_weighted_log_mean(lv, lw, k, seed + j, "conditional moments, Doob-twisted losses"))
    return _divergence_verdict(runs, None, 0.01, 0.999, 1, paths, seed)


def line(name, g, v, bounded, r):
    rate = "-" if r.rate is None else f"{r.rate:.4f} [{r.rate_low:.4f}, {r.rate_high:.4f}]"
    ok = {"stable": bounded, "unstable": not bounded}.get(r.verdict)
    return (f"{name[:30]:30s} {str(g):9s} {str(v):9s} {'bounded' if bounded else 'unbounded':9s} {r.verdict:9s} "
            f"{'ok' if ok else 'WRONG' if ok is False else '?':5s} margin {rate}  growth {r.growth:.4f} "
            f"[{r.growth_low:.4f}, {r.growth_high:.4f}]  rel. stderr {[round(e.rel_stderr, 3) for e in r.estimates]}")


def tcp(args):
    from test_control_verify import PLANTS, _sides
    for S in PLANTS:
        plant = plant_of(S)
        for (g, v), bounded in _sides(S)[:3]:
            verdict = lqg_stable(S, IID(loss=[1 - g] * S.d), IID(loss=[1 - v] * len(S.actuators)))
            L = (control_riccati(plant.A, plant.B, plant.W, plant.U, float(v))[1] if verdict.control
                 else -np.array(critical_arrival_rate(S).gain.tolist(), dtype=float))
            try:
                print(line(S.name, g, v, bounded, divergence(plant, L, "tcp", float(g), float(v), args.horizon,
                                                             args.paths, args.seed)), flush=True)
            except (FloatingPointError, np.linalg.LinAlgError) as exc:
                print(f"{S.name[:30]:30s} {str(g):9s} {str(v):9s} broke down: {exc}", flush=True)


def udp(args):
    R = sp.Rational
    for a in (sp.Integer(2), R(6, 5)):
        S = sk.System(A=[[a]], sensors=[sk.Sensor(C=[[1]])], actuators=[sk.Actuator(B=[[1]])])
        for g in (R(9, 10), R(19, 20)):
            star = udp_threshold(a, g)
            for v in (min(R(1), star + R(1, 25)), star - R(1, 25)):
                v = R(int(v * 1000), 1000)
                plant = plant_of(S)
                theory, _, L = _udp_theory(S, g, v, True, plant)
                plant = loop_plant(plant.A, plant.B, plant.C, plant.Q, 1e-12 * np.eye(1), plant.W, plant.U, plant.P0)
                print(line(f"UDP a = {a}", g, v, theory, divergence(plant, L, "udp", float(g), float(v), args.horizon,
                                                                     args.paths, args.seed)), flush=True)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--tcp", action="store_true")
    ap.add_argument("--udp", action="store_true")
    ap.add_argument("--paths", type=int, default=4000)
    ap.add_argument("--horizon", type=int, default=90)
    ap.add_argument("--seed", type=int, default=0)
    args = ap.parse_args()
    t = time.process_time()
    if args.udp or not args.tcp:
        udp(args)
    if args.tcp or not args.udp:
        tcp(args)
    print(f"CPU {time.process_time() - t:.1f} s")


if __name__ == "__main__":
    main()
