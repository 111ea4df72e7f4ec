"""Quevedo et al.: Theorems 1-2 against the exact verdict, as a markdown table.

Usage: python examples/quevedo_compare.py [NAME ...]   (default: the whole family)
"""

import sys

from symkf.network.compare import FAMILY, compare, example, markdown_table


def main(names: list[str]) -> None:
    members = [example(n) for n in names] if names else list(FAMILY)
    print(markdown_table([compare(ex) for ex in members]))


if __name__ == "__main__":
    main(sys.argv[1:])
