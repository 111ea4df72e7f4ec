"""The atlas against one parameter (symkf.bounds.figure): the exact critical rate and the bounds in
the legend."""


import pytest


def test_figure_has_the_exact_rate_and_bounds():
    pytest.importorskip("matplotlib")
    from symkf.bounds.figure import atlas_figure, rotation_family
    fig = atlas_figure(rotation_family(2, 3), lmi_steps=1)
    labels = [t.get_text() for t in fig.axes[0].get_legend().get_texts()]
    assert any("exact" in t for t in labels) and any("Sinopoli" in t for t in labels)
