"""Documentation: the API reference covers the public API, the file-format page is complete and
its snippets load, the CLI and JSON pages match the program, every relative link resolves, the
site loads no asset from another host, and papers are cited by authors and title, never by
internal file names.

The site itself is built by ``.ci/run`` (``sphinx -W``: warnings are errors, the tutorial notebook
executed)."""

from __future__ import annotations

import inspect
import json
import re
import subprocess
import sys
import tomllib
from pathlib import Path
from types import SimpleNamespace
from urllib.parse import unquote

import pytest

import symkf
from symkf import cli, examples
from symkf.io import families, files
from symkf.model.codec import loss_kinds

from conftest import ROOT

DOCS = ROOT / "docs"
PAGES = [ROOT / "README.md", *sorted(DOCS.glob("*.md"))]


def test_api_reference_documents_every_public_name():
    api = (DOCS / "api.md").read_text(encoding="utf-8")
    documented = set(re.findall(r"^\.\. automodule:: ([\w.]+)$", api, re.M))
    for name in symkf.__all__:
        obj = getattr(symkf, name)
        assert inspect.getdoc(obj), f"symkf.{name} has no docstring"
        module = obj.__name__ if inspect.ismodule(obj) else obj.__module__
        assert module in documented or module.rsplit(".", 1)[0] in documented, f"{name}: {module} not in docs/api.md"
    assert {"symkf.io.examples", "symkf.model.statespace", "symkf.io.files", "symkf.errors", "symkf.model.codec"} <= documented


def _toml_snippets(page: str) -> list[str]:
    return re.findall(r"^```toml\n(.*?)^```", (DOCS / page).read_text(encoding="utf-8"), re.M | re.S)


def test_every_format_snippet_loads(tmp_path):
    snippets = _toml_snippets("formats.md")
    kinds = {tomllib.loads(s).get("loss", {}).get("kind") for s in snippets}
    assert {"iid", "gilbert-elliott", "markov", "network", "independent"} <= kinds
    for i, text in enumerate(snippets):
        path = tmp_path / f"snippet{i}.toml"
        path.write_text(text, encoding="utf-8")
        data = tomllib.loads(text)
        if "family" in data:
            assert families.load_family(path).members
        elif "fusion" in data:
            assert files.load_fusion(path) is not None
        else:
            system, loss = files.load(path)
            assert system.n == len(data["system"]["A"]) and (loss is None) == ("loss" not in data)


def test_format_page_names_every_key_and_loss_kind():
    page = (DOCS / "formats.md").read_text(encoding="utf-8")
    tables = {**files.KEYS, **{kind: model.keys for kind, model in loss_kinds().items()}}
    for table, keys in tables.items():
        for key in keys:
            assert f"`{key}`" in page, f"docs/formats.md does not document key {key!r} ({table or 'top level'})"
    for kind in ("iid", "gilbert-elliott", "markov", "network", "independent"):
        assert f'`kind = "{kind}"`' in page
    for key in families._FAMILY_KEYS:
        assert f"`{key}`" in page, key


def test_cli_page_names_every_command_and_option():
    page = (DOCS / "cli.md").read_text(encoding="utf-8")
    parser = cli._parser()
    subparsers = next(a for a in parser._actions if a.choices and isinstance(a.choices, dict))
    for name, sub in subparsers.choices.items():
        assert f"`symkf {name}" in page, name
        for action in sub._actions:
            for flag in action.option_strings:
                if flag.startswith("--") and flag != "--help":
                    assert flag in page, f"docs/cli.md: symkf {name} {flag} is not documented"
    for status in (0, 1, 2, 3, cli.INTERNAL_ERROR):
        assert f"| {status} |" in page


def _printed(capsys, example: str) -> dict[str, dict]:
    """The JSON documents of ``symkf analyze`` and ``symkf critical`` on a shipped example."""
    printed = {}
    for command in ("analyze", "critical"):
        assert cli.main([command, str(examples.system(example)), "--json"]) == 0
        printed[command] = json.loads(capsys.readouterr().out)
    return printed


def test_json_page_documents_every_printed_key(capsys):
    page = (DOCS / "json.md").read_text(encoding="utf-8")
    printed = _printed(capsys, "ge-two-sensors")
    verdict = printed["analyze"]["verdict"]
    nested = [*verdict, *verdict["margins"][0], *printed["analyze"]["blocks"][0], *verdict["certificate"][0]]
    # the control side of a file with actuators
    lqg = _printed(capsys, "lqg-two-modes")
    control, region = lqg["analyze"]["control"], lqg["critical"]["control"]
    nested += [*control, *control["critical_arrival_rate"], *control["loop"], *control["udp"],
               *control["udp"]["rows"][0], *control["udp"]["rows"][0]["hypotheses"][0], *region, *region["nu_c"]]
    for key in [*printed["analyze"], *printed["critical"], "control", *nested]:
        assert f"`{key}`" in page, f"docs/json.md does not document {key!r}"
    assert {"critical_loss_rate", "varied", "theorem"} <= set(printed["critical"])


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


def test_architecture_page_names_every_module():
    import pkgutil

    import symkf.exact
    page = (DOCS / "architecture.md").read_text(encoding="utf-8")
    modules = [m.name for m in pkgutil.iter_modules(symkf.__path__) if m.name != "__main__"]
    assert [m for m in modules if f"symkf.{m}" not in page] == []
    exact = [m.name for m in pkgutil.iter_modules(symkf.exact.__path__)]
    assert [m for m in exact if f"`{m}`" not in page and f"symkf.exact.{m}" not in page] == []
    assert "architecture" in (DOCS / "index.md").read_text(encoding="utf-8")


@pytest.mark.full
def test_docs_build_offline_with_math(tmp_path):
    # the site's MathJax is its own: no page loads a script or style from another host
    # (docs/offline.py fails the build otherwise), and the tutorial's math is MathJax's to render
    for module in ("sphinx", "myst_nb", "sphinx-mathjax-offline"):
        pytest.importorskip(module)
    out = tmp_path / "html"
    run = subprocess.run([sys.executable, "-m", "sphinx", "-W", "--keep-going", "-q", "-b", "html", DOCS, out],
                         capture_output=True, text=True)
    assert run.returncode == 0, run.stderr[-3000:]
    sys.path.insert(0, str(DOCS))
    try:
        from offline import external_assets
    finally:
        sys.path.remove(str(DOCS))
    assert external_assets(out) == []
    tutorial = (out / "tutorial.html").read_text(encoding="utf-8")
    assert 'src="_static/mathjax/tex-chtml.js"' in tutorial and (out / "_static/mathjax/tex-chtml.js").is_file()
    assert tutorial.count("math notranslate nohighlight") >= 4   # the LaTeX results, for MathJax
    assert "IProgress" not in tutorial and "TQDM_DISABLE" not in tutorial


def test_offline_check_finds_assets_from_other_hosts(tmp_path):
    sys.path.insert(0, str(ROOT / "docs"))
    try:
        from offline import _check, external_assets
    finally:
        sys.path.remove(str(ROOT / "docs"))
    (tmp_path / "a.html").write_text('<script src="_static/mathjax/tex-chtml.js"></script>'
                                     '<link rel="stylesheet" href="_static/x.css"><a href="https://x.org">x</a>')
    assert external_assets(tmp_path) == []
    (tmp_path / "b.html").write_text('<script defer src="https://cdn.jsdelivr.net/npm/mathjax@3/es5/tex.js">'
                                     '</script><link rel="stylesheet" href="//fonts.example/f.css">')
    assert external_assets(tmp_path) == ["b.html: https://cdn.jsdelivr.net/npm/mathjax@3/es5/tex.js",
                                         "b.html: //fonts.example/f.css"]
    app = SimpleNamespace(builder=SimpleNamespace(format="html"), outdir=str(tmp_path))
    with pytest.raises(RuntimeError, match="b.html: https://cdn.jsdelivr.net"):   # the build fails
        _check(app, None)


def test_no_internal_words_reach_users():
    # papers are cited by authors and title; the file names of the papers and of the project's
    # internal notes never reach users
    internal = re.compile(r"[Ss]eed 00\d|seeds/|DESIGN\.md|DESIGN example|DESIGN rotation")
    files = [p for p in [*(ROOT / "symkf").rglob("*"), *(ROOT / "docs").glob("*.md"), *(ROOT / "examples").glob("*"),
                         *(ROOT / "proofs").glob("*"), ROOT / "README.md"]
             if p.is_file() and p.suffix in (".py", ".md", ".toml")]
    found = [f"{p.relative_to(ROOT)}:{i}" for p in files
             for i, line in enumerate(p.read_text(encoding="utf-8").splitlines(), 1) if internal.search(line)]
    assert found == []


def test_readme_snippets_print_what_they_show():
    import doctest
    result = doctest.testfile(str(ROOT / "README.md"), module_relative=False, optionflags=doctest.ELLIPSIS)
    assert result.attempted >= 5 and result.failed == 0
