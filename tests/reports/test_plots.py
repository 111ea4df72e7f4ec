"""Figures of the ``plot`` extra (symkf.reports.plots): each is drawn with small parameters, its data
checked, its PNG written; inline in a Jupyter kernel, vector files by their suffix."""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np
import pytest
import sympy as sp

pytest.importorskip("matplotlib")

from symkf import examples
from symkf.io import files
from symkf.reports import plots  # noqa: E402
from symkf.errors import InputError  # noqa: E402
from symkf.model.system import Sensor, System  # noqa: E402
from symkf.numeric.montecarlo import mean_trace_curve, exact_mean_trace  # noqa: E402

SYSTEMS = examples.directory() / "systems"
PNG = b"\x89PNG\r\n\x1a\n"
#: simulation seed of the figures judged against theory; checked with SYMKF_TEST_SEED = 0..19
SEED = 20 * int(os.environ.get("SYMKF_TEST_SEED", "0"))


def written(path: Path) -> bool:
    return path.read_bytes()[:8] == PNG and path.stat().st_size > 20_000


def labels(fig) -> list[str]:
    return [t.get_text() for t in fig.axes[0].get_legend().get_texts()]


def test_region_two_diagonal_modes(tmp_path):
    # A = diag(3/2, 5/4), each sensor sees one mode: stable iff loss_1 < 4/9 and loss_2 < 16/25
    S = System(A=[["3/2", 0], [0, "5/4"]], sensors=[Sensor(C=[[1, 0]]), Sensor(C=[[0, 1]])])
    fig = plots.stability_region_figure(S, samples=5, mc_points=2, paths=2000, horizon=40, seed=SEED,
                                        path=tmp_path / "region.png")
    assert written(tmp_path / "region.png")
    boundary = fig.axes[0].lines[0]
    x, y = boundary.get_xdata(), boundary.get_ydata()
    assert np.allclose(y[x < 4 / 9 - 1e-9], 16 / 25) and np.allclose(y[x > 4 / 9 + 1e-9], 0)
    assert np.isclose(x.min(), 0) and np.isclose(x.max(), 1) and np.any(np.isclose(x, 4 / 9))
    names = labels(fig)
    assert "Monte Carlo: stable" in names and "Monte Carlo: unstable" in names
    assert "simulation contradicts theory" not in names


def test_region_boundary_against_critical_loss_rate():
    # the drawn curve f(loss_1) is the critical loss_2 with loss_1 fixed (two independent computations)
    from symkf.engine.stability import critical_loss_rate
    S, _ = files.load(SYSTEMS / "ge-two-sensors.toml")
    x, y = plots.region_boundary(S, samples=400)
    for eps1 in (sp.Rational(1, 5), sp.Rational(1, 2), sp.Rational(9, 10)):
        exact = float(critical_loss_rate(S, "s2", others=[eps1, 0]))
        assert np.isclose(np.interp(float(eps1), x, y), exact, rtol=1e-3)   # linear between samples
    # the kink where 16 eps1 eps2^2 = 16 eps1^2 eps2 meet: eps1 = eps2 = 16^(-1/3)
    assert np.isclose(np.interp(16 ** (-1 / 3), x, y), 16 ** (-1 / 3))


def test_region_needs_two_sensors():
    S, _ = files.load(SYSTEMS / "design-rotation.toml")
    with pytest.raises(InputError, match="2 sensors"):
        plots.stability_region_figure(S)


def test_critical_angle_matches_hand_formula(tmp_path):
    # A = 2 R(pi p/q), C = [1 0]: eps_c = 2^(-2q/(q-1)) (strategies.Rotation); aperiodic: 1/4
    fig = plots.critical_angle_figure(2, max_denominator=3, path=tmp_path / "angle.png")
    assert written(tmp_path / "angle.png")
    periodic, aperiodic = fig.axes[0].lines[0], fig.axes[0].lines[1]
    assert np.allclose(periodic.get_xdata(), [np.pi / 3, np.pi / 2, 2 * np.pi / 3])
    assert np.allclose(periodic.get_ydata(), [2 ** -3, 2 ** -4, 2 ** -3])
    assert np.allclose(aperiodic.get_ydata(), [1 / 4]) and np.isclose(aperiodic.get_xdata()[0], np.arccos(3 / 5))


def test_legends_and_titles_show_exact_numbers_as_mathematics(tmp_path):
    # 1/scale^2 = 1/4 for scale 2, as LaTeX; C = [1 0] as a matrix, not Python's [[1, 0]]
    fig = plots.critical_angle_figure(2, max_denominator=2, path=tmp_path / "angle.png")
    assert r"1/scale$^2$ = $\frac{1}{4} \approx 0.25$" in labels(fig)
    assert fig.axes[0].get_title() == r"$A = 2\,R(\theta)$, $C = [1\ 0]$: exact critical loss"
    # a long closed form (Yang et al. Example 1's growth): LaTeX that matplotlib's mathtext renders
    long = 243 * 167 ** sp.Rational(3, 4) * 2 ** sp.Rational(1, 4) / 12500
    label = plots._math_label(long)
    assert label == r"$\frac{243 \cdot 167^{\frac{3}{4}} \sqrt[4]{2}}{12500} \approx 1.074$"
    from matplotlib.mathtext import MathTextParser
    MathTextParser("agg").parse(label)            # raises ValueError on what mathtext cannot read


def test_yang_bounds_bracket_the_exact_mean():
    # Proposition 1 and Theorem 3 (Yang et al.): tr G_{k+1} <= E[tr P_{k|k-1}] <= tr V_{k+1}
    S, loss = files.load(SYSTEMS / "design-rotation.toml")
    G, V = plots.yang_bounds(S, loss, 8)
    exact = exact_mean_trace(S, loss, 8)
    assert np.all(G <= exact + 1e-9) and np.all(exact <= V + 1e-9)
    assert G[0] == 0 and np.isclose(V[0], 2)                       # G_1 = 0, V_1 = P0 = I


def test_mean_trace_figure(tmp_path):
    S, loss = files.load(SYSTEMS / "design-rotation.toml")
    curve = mean_trace_curve(S, loss, 20, 500, seed=0, points=5)
    fig = plots.mean_trace_figure(S, loss, curve, path=tmp_path / "trace.png")
    assert written(tmp_path / "trace.png")
    names = labels(fig)
    assert "exact growth rate 1 per step (stable)" in names
    assert {"Yang lower bound tr $G_k$", "Yang upper bound tr $V_k$"} <= set(names)
    assert "i.i.d. losses" in fig.axes[0].get_title() and "IID(" not in fig.axes[0].get_title()


def test_mean_trace_figure_markov_shows_the_exact_growth(tmp_path):
    # Gilbert-Elliott (fail 1/4, recover 1/2): not stable, E[tr P_k] grows like (sqrt(6)/2)^k.
    # The simulated curve must show that slope (plain Monte Carlo drew a flat curve here)
    S, loss = files.load(SYSTEMS / "ge-two-sensors.toml")
    curve = mean_trace_curve(S, loss, 40, 2000, seed=SEED, points=5)   # float_horizon: 40 steps
    fig = plots.mean_trace_figure(S, loss, curve)
    assert "Yang" not in fig.axes[0].get_title() and not any("Yang" in name for name in labels(fig))
    assert r"exact growth rate $\frac{\sqrt{6}}{2} \approx 1.2247$ per step (not stable)" in labels(fig)
    # the plotted points at k = 20, 30, 40 (independent runs) give the margin by the difference
    # ratio, whose widened 99 % interval must contain sqrt(6)/2 (the former check, a least-squares
    # slope within 2 % of ln(sqrt(6)/2), measured the finite-horizon rate: 3.4 % off at seed 20)
    from symkf.numeric.montecarlo import LogMeanEstimate, margin_interval, polynomial_allowance
    assert list(curve.ks[2:]) == [20, 30, 40]
    runs = [LogMeanEstimate(float(m), float(r), 0.0, 2000, int(k), None, "")
            for m, r, k in zip(curve.log_mean[2:], curve.rel_stderr[2:], curve.ks[2:])]
    rate, low, high = margin_interval(runs, 0.99)
    delta = np.exp(polynomial_allowance((20, 30, 40)))
    assert low / delta <= np.sqrt(6) / 2 <= high and abs(rate / (np.sqrt(6) / 2) - 1) < 0.03


# -- figures for notebooks and papers: inline in a Jupyter kernel, vector files by their suffix --

@pytest.fixture(scope="module")
def figure():
    return plots.critical_angle_figure(2, max_denominator=3)


@pytest.mark.parametrize("suffix, magic", [(".svg", b"<svg"), (".pdf", b"%PDF"), (".png", b"\x89PNG")])
def test_file_format_follows_the_suffix(figure, tmp_path, suffix, magic):
    path = tmp_path / f"fig{suffix}"
    plots.finish_figure(figure, plots.figure_target(path))
    assert magic in path.read_bytes()[:400]


def test_figures_render_as_png_in_an_ipython_kernel(figure):
    shell_module = pytest.importorskip("IPython.core.interactiveshell")
    shell = shell_module.InteractiveShell.instance()
    try:
        assert "image/png" not in shell.display_formatter.format(figure)[0]   # pyplot never imported
        plots.critical_angle_figure(2, max_denominator=2)                      # registers the formatter
        data, _ = shell.display_formatter.format(figure)
        assert data["image/png"][:4] == b"\x89PNG"
    finally:
        shell_module.InteractiveShell.clear_instance()


def test_titles_say_the_loss_model_in_words():
    import symkf as sk
    from symkf.numeric.montecarlo import mean_trace_curve
    S = sk.System(A=[[0, -2], [2, 0]], sensors=[sk.Sensor(C=[[1, 0]], name="s1")], name="rotation")
    for loss, words in ((sk.IID(["1/20"]), "rotation under i.i.d. losses 1/20"),
                        (sk.GilbertElliott(["1/4"], ["1/2"]), "Gilbert-Elliott channels, fail 1/4, recover 1/2")):
        title = plots.mean_trace_figure(S, loss, mean_trace_curve(S, loss, 10, 50, seed=0)).axes[0].get_title()
        assert words in title and "IID(" not in title and "GilbertElliott(" not in title
