"""Arguments checked against their annotations, before the body runs.

A public function given an argument of the wrong kind (a string for a ``System``, a dict for a
polynomial, an object for an ``int``) would fail somewhere inside with an AttributeError or a
TypeError that names neither the argument nor what was expected.  :func:`check_public` wraps
every public function and method of a module so that such an argument is refused at once with
an :class:`~symkf.errors.InputError` naming the function, the parameter and the expected kind.

What an annotation asks (resolved lazily, on the first call, so forward references work):

* a class: an instance of it (a symkf class: of its symkf root class, so that the function names
  the assumption a sibling fails, e.g. an i.i.d. theorem given a Gilbert-Elliott model;
  ``float`` takes any real number, a path
  takes ``str`` or ``os.PathLike``, a sympy expression also takes a number or a string, which the
  function reads through :mod:`symkf.exact.numbers`; a matrix also takes rows);
* ``X | None``, unions, ``Literal[...]`` (one of the values), ``Callable``;
* ``Sequence``/``list``/``tuple`` (a list or tuple), ``Mapping``/``dict``, ``set``/``frozenset``,
  ``Iterable``/``Collection`` (any iterable but a string): the container, not its elements,
  which the function validates with its own entry names;
* ``Any``, type variables and anything unresolvable: not checked.

A parameter left at its default is not checked.
"""

from __future__ import annotations

import collections.abc as abc
import functools
import inspect
import numbers
import os
import reprlib
import types
import typing
from decimal import Decimal
from fractions import Fraction
from typing import Any, Callable

from .errors import InputError

_ABSENT = object()


def described(value: Any) -> str:
    """``value`` for an error message: its type and a short repr (a hostile ``__repr__`` is never
    needed to build the message)."""
    try:
        shown = reprlib.repr(value)
    except Exception:  # noqa: BLE001 - any failure of the caller's __repr__ just hides the value
        shown = "..."
    return f"{type(value).__name__} {shown if isinstance(shown, str) else '...'}"


def _number_like(value: Any) -> bool:
    return isinstance(value, (numbers.Number, Fraction, Decimal, str)) and not isinstance(value, bool) \
        or hasattr(type(value), "_sympy_")


def _test(hint: Any) -> tuple[Callable[[Any], bool], str] | None:
    """(predicate, words) for an annotation, or None when it asks nothing checkable."""
    origin, args = typing.get_origin(hint), typing.get_args(hint)
    if hint is Any or isinstance(hint, typing.TypeVar) or hint is None:
        return None
    if origin in (typing.Union, types.UnionType):
        tests = [_test(a) for a in args if a is not type(None)]
        if any(t is None for t in tests):
            return None
        none = type(None) in args
        return (lambda v: (none and v is None) or any(t(v) for t, _ in tests),
                " or ".join([w for _, w in tests] + ["None"] * none))
    if origin is typing.Literal:
        return (lambda v: any(v == a and type(v) is type(a) for a in args)), "one of " + ", ".join(map(repr, args))
    if origin is not None:
        hint = origin
    if not isinstance(hint, type):
        return None
    if hint in (abc.Callable,):
        return callable, "a callable"
    if hint in (list, tuple, abc.Sequence, abc.MutableSequence):
        return (lambda v: isinstance(v, (list, tuple))), "a list or tuple"
    if hint in (dict, abc.Mapping, abc.MutableMapping):
        return (lambda v: isinstance(v, abc.Mapping)), "a mapping"
    if hint in (set, frozenset, abc.Set, abc.MutableSet):
        return (lambda v: isinstance(v, (set, frozenset))), "a set"
    if hint in (abc.Iterable, abc.Collection, abc.Iterator):
        return _iterable, "an iterable"
    if hint is bool:
        return (lambda v: isinstance(v, bool) or type(v).__name__ == "bool_"), "a bool"
    # sympy's numbers (an Integer, oo from an estimate) count as numbers too
    if hint is int:  # a bool is an int here: the function's own check names what it wants
        return (lambda v: isinstance(v, numbers.Integral) or getattr(v, "is_Number", False) is True), "an int"
    if hint in (float, complex):
        return (lambda v: isinstance(v, numbers.Real if hint is float else numbers.Complex)
                and not isinstance(v, bool) or getattr(v, "is_Number", False) is True), f"a {hint.__name__}"
    if hint is str:
        return (lambda v: isinstance(v, str)), "a string"
    if issubclass(hint, os.PathLike):
        return (lambda v: isinstance(v, (str, os.PathLike))), "a path"
    module = hint.__module__.split(".")[0]
    if module == "sympy" and hasattr(hint, "is_Matrix") and issubclass(hint, _sympy_matrix()):
        return (lambda v: isinstance(v, (hint, list, tuple)) or type(v).__name__ == "ndarray"), \
            f"a {hint.__name__} or a list of rows"
    if module == "sympy":
        return (lambda v: isinstance(v, hint) or _number_like(v)), f"a {hint.__name__} or an exact number"
    if module == "numpy" and hint.__name__ == "ndarray":
        return (lambda v: isinstance(v, (hint, list, tuple))), "an array or a list"
    if module == "symkf":  # a sibling of the same symkf root (e.g. any loss model) is the function's to refuse
        root = [c for c in hint.__mro__ if c.__module__.split(".")[0] == "symkf"][-1]
        return (lambda v: isinstance(v, root)), f"a {root.__name__}"
    return (lambda v: isinstance(v, hint)), f"a {hint.__name__}"


def _iterable(value: Any) -> bool:
    if isinstance(value, (str, bytes)):
        return False
    try:
        iter(value)
    except TypeError:
        return False
    return True


def _sympy_matrix() -> type:
    import sympy
    return sympy.MatrixBase


def _tests(fn: Callable) -> list[tuple[int, str, Callable[[Any], bool], str, Any]]:
    """(position, name, predicate, words, default) per checked parameter of ``fn``."""
    signature = inspect.signature(fn)
    out = []
    for position, (name, p) in enumerate(signature.parameters.items()):
        if p.annotation is p.empty or p.kind in (p.VAR_POSITIONAL, p.VAR_KEYWORD):
            continue
        try:
            probe = type("Probe", (), {"__annotations__": {name: p.annotation}, "__module__": fn.__module__})
            hint = typing.get_type_hints(probe)[name]
        except Exception:  # noqa: BLE001 - an annotation we cannot resolve asks nothing checkable
            continue
        test = _test(hint)
        if test is not None:
            out.append((position if p.kind != p.KEYWORD_ONLY else -1, name, *test,
                        _ABSENT if p.default is p.empty else p.default))
    return out


def checked(fn: Callable) -> Callable:
    """``fn`` with its annotated arguments checked first (module docstring)."""
    tests: list | None = None

    @functools.wraps(fn)
    def call(*args, **kwargs):
        nonlocal tests
        if tests is None:
            tests = _tests(fn)
        for position, name, test, words, default in tests:
            value = args[position] if 0 <= position < len(args) else kwargs.get(name, _ABSENT)
            if value is _ABSENT or value is default:
                continue
            if not test(value):
                raise InputError(f"{fn.__qualname__}: argument {name!r} must be {words}, got {described(value)}")
        return fn(*args, **kwargs)

    call.__symkf_checked__ = True
    return call


def check_public(namespace: dict) -> None:
    """Wrap every public function and public method defined in the module whose globals are
    ``namespace`` with :func:`checked`."""
    module = namespace["__name__"]
    for name, obj in list(namespace.items()):
        if name.startswith("_") or getattr(obj, "__module__", None) != module:
            continue
        if inspect.isfunction(obj) and not getattr(obj, "__symkf_checked__", False):
            namespace[name] = checked(obj)
        elif isinstance(obj, type):
            for attr, member in list(vars(obj).items()):
                if attr.startswith("_"):
                    continue
                if inspect.isfunction(member):
                    setattr(obj, attr, checked(member))
                elif isinstance(member, (classmethod, staticmethod)) and inspect.isfunction(member.__func__):
                    setattr(obj, attr, type(member)(checked(member.__func__)))
