"""Generate docs/api.md, the API reference, from the package's docstrings.

    python docs/gen_api.py [OUT.md]        (default: docs/api.md next to this script)

For ``symkf`` itself (``symkf.__all__``) and each public module it lists the public
functions and classes (a package's ``__all__``, else the names a module defines
without a leading underscore) with their signature and the first paragraph of their
docstring; classes also list their public methods and properties.  Pure stdlib
(:mod:`inspect`).  ``tests/test_docs.py`` checks that the committed file is current.
"""

from __future__ import annotations

import dataclasses
import importlib
import inspect
import re
import sys
from pathlib import Path
from types import ModuleType
from typing import Any

ROOT = Path(__file__).resolve().parent.parent
if str(ROOT) not in sys.path:
    sys.path.insert(0, str(ROOT))

#: the public modules, in reading order (model and losses first, the engine, simulation, tooling, papers)
MODULES = ("model", "losses", "spectral", "observability", "decay", "stability", "region", "second_order",
           "montecarlo", "filtering", "verify", "sweep", "progress", "families", "tables", "plots", "strategies",
           "files", "budget", "output", "errors", "capacity", "fusion", "network", "exact.numbers",
           "exact.algebraic")
MISSING = "*(no docstring)*"

HEADER = """# symkf API reference

Generated from the docstrings by `python docs/gen_api.py`; do not edit by hand
(`tests/test_docs.py` fails when this file is out of date).  Each entry gives the
signature and the first paragraph of the docstring; `help(symkf.NAME)` shows the rest.
Numbers are exact (sympy) unless a docstring says otherwise; the [README](../README.md)
has a tour of the main entry points.
"""


class _Annotation(str):
    """An annotation kept as source text (``from __future__ import annotations``), shown unquoted."""

    def __repr__(self) -> str:
        return str(self)


def signature(obj: Any, *, method: bool = False) -> str:
    """``obj``'s call signature as written in its source (without ``self`` when ``method``), or ``""``."""
    try:
        sig = inspect.signature(obj)
    except (TypeError, ValueError):
        return ""

    def plain(a: Any) -> Any:  # forward references ("Cell") unquoted too
        return _Annotation(re.sub(r"'([A-Za-z_][\w.]*)'", r"\1", a)) if isinstance(a, str) else a
    params = list(sig.parameters.values())[1 if method else 0:]
    sig = sig.replace(parameters=[p.replace(annotation=plain(p.annotation)) for p in params],
                      return_annotation=inspect.Signature.empty if inspect.isclass(obj)
                      else plain(sig.return_annotation))
    return re.sub(r" at 0x[0-9a-f]+", "", str(sig))  # object reprs in defaults: no addresses


def summary(obj: Any) -> str:
    """First paragraph of ``obj``'s own docstring in Markdown (RST roles and literals simplified)."""
    doc = obj.__doc__ if isinstance(obj, property) else inspect.getdoc(obj)
    if isinstance(obj, type) and (doc == inspect.getdoc(obj.__mro__[1])
                                  or (dataclasses.is_dataclass(obj) and doc.startswith(obj.__name__ + "("))):
        doc = None  # inherited from a base class, or the field list dataclasses writes
    if not doc or not doc.strip():
        return MISSING
    first = inspect.cleandoc(doc).split("\n\n")[0]
    first = re.sub(r":[a-z]+:`~?([^`]+)`", r"`\1`", first)   # :func:`~symkf.x.y` -> `symkf.x.y`
    first = first.replace("``", "`")
    return " ".join(first.split())


def public_names(module: ModuleType) -> list[str]:
    """A package's ``__all__``, else the functions and classes ``module`` defines, in source order."""
    if hasattr(module, "__all__"):
        return list(module.__all__)
    own = [(name, obj) for name, obj in vars(module).items()
           if not name.startswith("_") and (inspect.isfunction(obj) or inspect.isclass(obj))
           and obj.__module__ == module.__name__]
    return [name for name, obj in sorted(own, key=lambda item: _line(item[1]))]


def _line(obj: Any) -> int:
    try:
        return inspect.getsourcelines(obj)[1]
    except (OSError, TypeError):
        return 0


def _kind(obj: Any) -> str:
    if inspect.ismodule(obj):
        return "module"
    if inspect.isclass(obj):
        return "exception" if issubclass(obj, BaseException) else "class"
    return "function" if callable(obj) else "data"


def _members(cls: type) -> list[tuple[str, Any, str]]:
    """Public methods and properties ``cls`` defines itself (not inherited), in source order:
    ``(name, object, kind)`` with kind ``"method"``, ``"classmethod"``, ``"staticmethod"`` or ``"property"``."""
    out = []
    for name, attr in vars(cls).items():
        if name.startswith("_"):
            continue
        if isinstance(attr, (staticmethod, classmethod)):
            out.append((name, attr.__func__, type(attr).__name__))
        elif inspect.isfunction(attr):
            out.append((name, attr, "method"))
        elif isinstance(attr, property):
            out.append((name, attr, "property"))
    return sorted(out, key=lambda item: _line(item[1].fget if isinstance(item[1], property) else item[1]))


def _member_line(name: str, attr: Any, kind: str) -> str:
    if kind == "property":
        return f"- `.{name}` (property): {summary(attr)}"
    sig = signature(attr, method=kind != "staticmethod")
    return f"- `.{name}{sig}`{'' if kind == 'method' else f' ({kind})'}: {summary(attr)}"


def anchor(qualified: str) -> str:
    return qualified.replace(".", "-")


def entry(module: str, name: str, obj: Any) -> list[str]:
    """Markdown for one public name of ``module``."""
    qualified = f"{module}.{name}"
    lines = [f'<a id="{anchor(qualified)}"></a>', "", f"### `{name}{signature(obj)}`", "",
             f"*{_kind(obj)}*" + (f", defined in `{obj.__module__}`"
                                  if getattr(obj, "__module__", module) != module and not inspect.ismodule(obj)
                                  else "") + f". {summary(obj)}", ""]
    members = _members(obj) if inspect.isclass(obj) and not issubclass(obj, BaseException) else []
    lines += [_member_line(*m) for m in members] + ([""] if members else [])
    return lines


def render() -> str:
    """The whole of docs/api.md."""
    import symkf
    out = [HEADER, "## Contents", "", "- [`symkf` (top level)](#symkf)"]
    out += [f"- [`symkf.{m}`](#{anchor('symkf.' + m)}-module)" for m in MODULES]
    out += ["", '<a id="symkf"></a>', "", "## `symkf`", "", summary(symkf), "",
            "| name | kind | summary |", "|---|---|---|"]
    for name in symkf.__all__:
        obj = getattr(symkf, name)
        home = obj.__name__ if inspect.ismodule(obj) else f"{obj.__module__}.{name}"
        target = f"#{anchor(home)}-module" if inspect.ismodule(obj) else f"#{anchor(home)}"
        out.append(f"| [`{name}`]({target}) | {_kind(obj)} | {summary(obj).replace('|', '&#124;')} |")
    out.append("")
    for m in MODULES:
        module = importlib.import_module(f"symkf.{m}")
        out += [f'<a id="{anchor(module.__name__)}-module"></a>', "", f"## `{module.__name__}`", "",
                summary(module), ""]
        for name in public_names(module):
            out += entry(module.__name__, name, getattr(module, name))
    return "\n".join(out).rstrip() + "\n"


def main(argv: list[str] | None = None) -> int:
    argv = sys.argv[1:] if argv is None else argv
    out = Path(argv[0]) if argv else Path(__file__).resolve().parent / "api.md"
    out.write_text(render(), encoding="utf-8")
    print(f"wrote {out}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
