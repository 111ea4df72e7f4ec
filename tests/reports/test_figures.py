"""Figures for notebooks and papers: inline in a Jupyter kernel, vector files by their suffix."""

from __future__ import annotations

import pytest

pytest.importorskip("matplotlib")
from symkf.reports import plots  # noqa: E402


@pytest.fixture(scope="module")
def figure():
    return plots.critical_angle_figure(2, max_denominator=3)


@pytest.mark.parametrize("suffix, magic", [(".svg", b"<svg"), (".pdf", b"%PDF"), (".png", b"\x89PNG")])
def test_file_format_follows_the_suffix(figure, tmp_path, suffix, magic):
    path = tmp_path / f"fig{suffix}"
    plots.finish_figure(figure, path)
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
