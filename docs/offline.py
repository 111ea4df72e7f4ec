"""Sphinx extension: the built site works without a network.

MathJax is served from the site itself (the ``sphinx-mathjax-offline`` package copies
MathJax 3 into ``_static/mathjax``), and when the HTML build finishes every page is checked:
a ``<script src>``, a stylesheet ``<link href>`` or an ``<img src>`` on another host fails the
build, naming the page and the address.  ``external_assets(directory)`` is the check itself
(tests/test_docs.py runs it on built and on hand-made pages).
"""

from __future__ import annotations

from html.parser import HTMLParser
from pathlib import Path
from urllib.parse import urlsplit


class _Assets(HTMLParser):
    """The addresses of the scripts, stylesheets and images a page loads."""

    def __init__(self) -> None:
        super().__init__()
        self.found: list[str] = []

    def handle_starttag(self, tag: str, attrs: list[tuple[str, str | None]]) -> None:
        a = dict(attrs)
        if tag == "script" and a.get("src"):
            self.found.append(a["src"])
        elif tag == "link" and "stylesheet" in (a.get("rel") or "").split() and a.get("href"):
            self.found.append(a["href"])
        elif tag == "img" and a.get("src"):
            self.found.append(a["src"])


def external_assets(directory: str | Path) -> list[str]:
    """``"page: address"`` for every asset a built page loads from another host."""
    out = []
    root = Path(directory)
    for page in sorted(root.rglob("*.html")):
        parser = _Assets()
        parser.feed(page.read_text(encoding="utf-8", errors="replace"))
        out += [f"{page.relative_to(root)}: {src}" for src in parser.found
                if urlsplit(src).scheme not in ("", "file") or src.startswith("//")]
    return out


def _check(app, exc) -> None:
    if exc is None and app.builder.format == "html":
        bad = external_assets(app.outdir)
        if bad:
            raise RuntimeError("pages load assets from another host (the docs must work offline): "
                               + "; ".join(bad[:10]))


def setup(app):
    app.setup_extension("sphinx-mathjax-offline")
    app.connect("build-finished", _check, priority=900)   # after the MathJax files are copied
    return {"parallel_read_safe": True}
