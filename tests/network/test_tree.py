"""Sensor-network trees rooted at the gateway (symkf.network.tree; Quevedo, Ahlén, Johansson,
Sec. II): paths and edges of Example 1, theta as the product of the link outcomes over a path, bad
trees refused."""

from __future__ import annotations

import itertools

import pytest

from symkf.errors import InputError
from symkf.network import SensorTree


def test_tree_paths_example1():
    # Fig. 2 / Example 1: Par(S4) = Par(S5) = S2, Node(Path(S7)) = {S7, S3, S1, S0}
    tree = SensorTree([0, 0, 1, 2, 2, 3, 3, 2])
    assert tree.parent(4) == tree.parent(5) == 2
    assert tree.path(7) == (7, 3, 1, 0)
    assert tree.edges(7) == (7, 3, 1)
    assert tree.children(3) == (6, 7)


def test_theta_is_product_over_path():
    tree = SensorTree({1: 0, 2: 1, 3: 2})
    for g in itertools.product((0, 1), repeat=3):
        assert tree.theta(g) == (g[0], g[0] * g[1], g[0] * g[1] * g[2])


@pytest.mark.parametrize("parents", [[1, 2, 1], [0, 5], [0, 2], [], [0, "1"]])
def test_bad_trees_are_refused(parents):
    with pytest.raises(InputError):
        SensorTree(parents)
