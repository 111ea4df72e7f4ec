"""The atlas against one parameter (symkf.bounds.figure): the exact critical rate and the bounds in
the legend."""

import time

import pytest

import symkf as sk


def test_figure_has_the_exact_rate_and_bounds():
    pytest.importorskip("matplotlib")
    from symkf.bounds.figure import atlas_figure, rotation_family
    fig = atlas_figure(rotation_family(2, 3), lmi_steps=1)
    labels = [t.get_text() for t in fig.axes[0].get_legend().get_texts()]
    assert any("exact" in t for t in labels) and any("Sinopoli" in t for t in labels)


def test_a_bad_figure_path_is_refused_before_the_atlas_is_computed(tmp_path):
    pytest.importorskip("matplotlib")
    from symkf.bounds.figure import atlas_figure
    start = time.process_time()
    with pytest.raises(sk.SymkfError, match="does not exist"):
        atlas_figure(path=tmp_path / "missing" / "atlas.png")     # refused after 4 s of work before
    assert time.process_time() - start < 1
