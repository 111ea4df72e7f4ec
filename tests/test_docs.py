"""Documentation: docs/api.md is current and complete, and every relative link in the docs resolves."""

from __future__ import annotations

import difflib
import importlib.util
import inspect
import re
from pathlib import Path
from urllib.parse import unquote

import pytest

import symkf

ROOT = Path(__file__).resolve().parent.parent
PAGES = [ROOT / "README.md", *sorted((ROOT / "docs").glob("*.md"))]


@pytest.fixture(scope="module")
def gen_api():
    spec = importlib.util.spec_from_file_location("gen_api", ROOT / "docs" / "gen_api.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


@pytest.fixture(scope="module")
def generated(gen_api, tmp_path_factory):
    out = tmp_path_factory.mktemp("api") / "api.md"
    assert gen_api.main([str(out)]) == 0
    return out.read_text(encoding="utf-8")


def test_committed_api_reference_is_current(generated):
    committed = (ROOT / "docs" / "api.md").read_text(encoding="utf-8")
    if committed != generated:
        diff = "\n".join(list(difflib.unified_diff(committed.splitlines(), generated.splitlines(),
                                                   "docs/api.md (committed)", "generated", lineterm=""))[:40])
        pytest.fail(f"docs/api.md is out of date: run `python docs/gen_api.py` and commit it\n{diff}")


def test_every_public_name_is_listed_with_a_docstring(gen_api, generated):
    for name in symkf.__all__:
        obj = getattr(symkf, name)
        assert inspect.getdoc(obj), f"symkf.{name} has no docstring"
        assert re.search(rf"^\| \[`{name}`\]\(#[\w-]+\) \| \w+ \| (?!\*\(no docstring)", generated, re.M), name
    for m in gen_api.MODULES:
        assert f"## `symkf.{m}`" in generated, m
    for name in symkf.capacity.__all__ + symkf.fusion.__all__ + symkf.network.__all__:
        assert f"### `{name}" in generated, name
    missing = [line for line in generated.splitlines() if gen_api.MISSING in line]
    assert not missing, "public names without a docstring (add one, then run docs/gen_api.py):\n" + "\n".join(missing)


def test_signatures_and_summaries_render_as_written(gen_api):
    # forward references unquoted, self / cls dropped, class signatures without "-> None"
    from symkf.tables import Cell
    assert gen_api.signature(symkf.System).endswith("name: str | None = None)")
    members = {name: gen_api._member_line(name, attr, kind) for name, attr, kind in gen_api._members(Cell)}
    assert members["text"] == "- `.text(text: str) -> Cell` (classmethod): A cell of literal text (escaped for LaTeX)."
    members = {name: gen_api._member_line(name, attr, kind) for name, attr, kind in gen_api._members(symkf.System)}
    assert members["sensor_index"].startswith("- `.sensor_index(name: str) -> int`: ")
    assert members["n"] == "- `.n` (property): State dimension `n`."

    def documented():
        """Calls :func:`~symkf.stability.stability` on ``S``
        and more.

        Not this paragraph."""

    class Bare:
        pass

    class Child(symkf.SymkfError):
        pass
    assert gen_api.summary(documented) == "Calls `symkf.stability.stability` on `S` and more."
    assert gen_api.summary(Bare) == gen_api.MISSING == gen_api.summary(Child)   # no docstring of its own


def _without_code(text: str) -> str:
    """Markdown without fenced code blocks and inline code (links there are not links)."""
    return re.sub(r"`[^`\n]*`", "", re.sub(r"^```.*?^```", "", text, flags=re.M | re.S))


def _links(text: str) -> list[str]:
    body = _without_code(text)
    return re.findall(r"\]\(([^)\s]+)(?:\s+\"[^\"]*\")?\)", body) + re.findall(r"^\[[^\]]+\]:\s*(\S+)", body, re.M)


def _anchors(text: str) -> set[str]:
    """Explicit ``id="..."`` anchors and GitHub's heading slugs."""
    ids = set(re.findall(r'id="([^"]+)"', text))
    for heading in re.findall(r"^#+\s+(.*?)\s*$", _without_code_fences(text), re.M):
        ids.add(re.sub(r"[^\w\- ]", "", heading.lower()).replace(" ", "-"))
    return ids


def _without_code_fences(text: str) -> str:
    return re.sub(r"^```.*?^```", "", text, flags=re.M | re.S)


def _broken(page: Path) -> list[str]:
    """The relative links of ``page`` whose file (or anchor, in a Markdown file) does not exist."""
    broken = []
    for link in _links(page.read_text(encoding="utf-8")):
        if re.match(r"^[a-z][a-z0-9+.-]*:", link, re.I):   # http:, https:, mailto:
            continue
        target, _, fragment = unquote(link).partition("#")
        path = (page.parent / target).resolve() if target else page
        if not path.exists():
            broken.append(f"{link} (no such file)")
        elif fragment and path.suffix == ".md" and fragment not in _anchors(path.read_text(encoding="utf-8")):
            broken.append(f"{link} (no anchor #{fragment} in {path.name})")
    return broken


@pytest.mark.parametrize("page", PAGES, ids=lambda p: p.name)
def test_relative_links_resolve(page):
    assert not _broken(page), f"{page.relative_to(ROOT)}: broken links: {_broken(page)}"


def test_link_checker_sees_broken_links(tmp_path):
    page = tmp_path / "page.md"
    page.write_text("# Top `part`\n[ok](page.md#top-part) [gone](nope.md) ![img](fig.png) `[code](x.md)`\n"
                    "[bad anchor](#nowhere) [ok too](#top-part)\n```\n[fenced](y.md)\n```\n"
                    "[ref]: missing/ref.md\n[web](https://example.org/x.md)\n")
    assert _broken(page) == ["nope.md (no such file)", "fig.png (no such file)",
                             "#nowhere (no anchor #nowhere in page.md)", "missing/ref.md (no such file)"]
