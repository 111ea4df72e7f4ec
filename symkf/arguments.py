"""Arguments checked against their annotations, before the body runs.

A public function given an argument of the wrong kind (a string for a ``System``, a dict for a
polynomial, an object for an ``int``) would fail somewhere inside with an AttributeError or a
TypeError that names neither the argument nor what was expected.  :func:`check_public` wraps
every public function and method of a module so that such an argument is refused at once with
an :class:`~symkf.errors.InputError` naming the function, the parameter and the expected kind.

What an annotation asks (resolved lazily, on the first call, so forward references work):

* a class: an instance of it (a symkf class: of its symkf root class, so that the function names
  the assumption a sibling fails, e.g. an i.i.d. theorem given a Gilbert-Elliott model; any
  sympy matrix for a sympy matrix class; ``float`` and mpmath's ``mpf`` take any real number, a path
  takes ``str`` or ``os.PathLike``);
* ``X | None``, unions, ``Literal[...]`` (one of the values), ``Callable``;
* ``Sequence[X]``/``list[X]``/``tuple[X, ...]`` (a list or tuple), ``set[X]``/``frozenset[X]``,
  ``Iterable[X]``/``Collection[X]`` (any iterable but a string), each with its elements checked
  when it is a list, tuple or set; ``tuple[A, B]`` element by element; ``Mapping``/``dict`` (keys and values);
* ``Any``, type variables and anything unresolvable: not checked.

A parameter left at its default is not checked, and neither is a call from symkf itself: the
checks guard the boundary, where outside data comes in, and cost nothing inside the engine.

The boundary is also where a loss model meets its system: an argument sized by its sibling (a
common loss rate, ``IID("1/10")``, has ``d = None`` and ``with_sensors(d)``) takes the number of
sensors of the one system among the arguments (the object with ``sensor_names``), as NumPy
broadcasts a scalar; :func:`symkf.model.loss.checked` does the same inside.
"""

from __future__ import annotations

import cmath
import collections.abc as abc
import functools
import inspect
import numbers
import os
import reprlib
import sys
import types
import typing
from typing import Any, Callable

import numpy as np

from .errors import ArgumentError, InputError, SymkfError

_ABSENT = object()


def described(value: Any) -> str:
    """``value`` for an error message: its type and a short repr (a hostile ``__repr__`` is never
    needed to build the message)."""
    try:
        shown = reprlib.repr(value)
    except Exception:  # noqa: BLE001 - any failure of the caller's __repr__ just hides the value
        shown = "..."
    return f"{type(value).__name__} {shown if isinstance(shown, str) else '...'}"


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
        return (lambda v: any(type(v) is type(a) and v == a for a in args)), "one of " + ", ".join(map(repr, args))
    if origin is not None:
        hint = origin
    if not isinstance(hint, type):
        return None
    if hint in (abc.Callable,):
        return callable, "a callable"
    if hint is tuple and args and args[-1] is not Ellipsis:  # tuple[A, B, C]: one element each
        parts = [_test(a) or (lambda v: True, "anything") for a in args]
        return (lambda v: isinstance(v, (list, tuple)) and len(v) == len(parts)
                and all(t(e) for (t, _), e in zip(parts, v))), f"a tuple ({', '.join(w for _, w in parts)})"
    if hint in (list, tuple, abc.Sequence, abc.MutableSequence, set, frozenset, abc.Set, abc.MutableSet,
                abc.Iterable, abc.Collection):
        # the elements of a list, tuple, set or dict (its keys) are checked; a generator is left to the function
        kind = ((list, tuple), "a list or tuple") if hint in (list, tuple, abc.Sequence, abc.MutableSequence) else \
            ((set, frozenset), "a set") if hint in (set, frozenset, abc.Set, abc.MutableSet) else (None, "an iterable")
        container = (lambda v: isinstance(v, kind[0])) if kind[0] else _iterable
        inner = _test(args[0]) if args and (len(args) == 1 or args[1] is Ellipsis) else None
        if inner is None:
            return container, kind[1]
        return (lambda v: container(v) and (not isinstance(v, (list, tuple, set, frozenset, dict, np.ndarray))
                                            or all(inner[0](e) for e in v))), f"{kind[1]} of {inner[1]}"
    if hint in (dict, abc.Mapping, abc.MutableMapping):
        # keys and values checked like a sequence's elements (a span's basis: int -> row of a field)
        parts = [_test(a) for a in args] if len(args) == 2 else [None, None]
        if parts == [None, None]:
            return (lambda v: isinstance(v, abc.Mapping)), "a mapping"
        (kt, kw), (vt, vw) = (p or ((lambda v: True), "anything") for p in parts)
        return (lambda v: isinstance(v, abc.Mapping) and all(kt(k) and vt(x) for k, x in v.items())), \
            f"a mapping of {kw} to {vw}"
    if hint is abc.Iterator:
        return _iterable, "an iterable"
    if hint is bool:
        return (lambda v: isinstance(v, bool) or type(v).__name__ == "bool_"), "a bool"
    # sympy's numbers count as numbers too, but an int is an integer (a count or an index: no
    # infinity), and no float or complex is nan (an infinite float is a bound some functions take)
    if hint is int:  # a bool is an int here: the function's own check names what it wants
        return (lambda v: isinstance(v, numbers.Integral) or getattr(v, "is_Integer", False) is True), "an int"
    if hint in (float, complex):
        return (lambda v: (isinstance(v, numbers.Real if hint is float else numbers.Complex) and not isinstance(v, bool)
                           or getattr(v, "is_Number", False) is True) and _number(v)), f"a {hint.__name__} (not nan)"
    if hint is str:
        return (lambda v: isinstance(v, str)), "a string"
    if issubclass(hint, os.PathLike):
        return (lambda v: isinstance(v, (str, os.PathLike))), "a path"
    module = hint.__module__.split(".")[0]
    if module == "sympy" and hasattr(hint, "is_Matrix") and issubclass(hint, _sympy_matrix()):
        return (lambda v: isinstance(v, _sympy_matrix())), "a sympy matrix"
    if hint is np.ndarray:  # of numbers: numpy's kernels do not take objects or text
        return (lambda v: isinstance(v, np.ndarray) and v.dtype.kind in "biufc"), "a numeric array"
    if module == "mpmath":
        return (lambda v: isinstance(v, (hint, numbers.Real)) and not isinstance(v, bool)), "a real number"
    if module == "symkf":  # a sibling of the same symkf root (e.g. any loss model) is the function's to refuse
        # the family's root, not a mixin every public result shares (output.JsonDocument)
        root = [c for c in hint.__mro__ if c.__module__.split(".")[0] == "symkf"
                and (c is hint or c.__module__ != "symkf.output")][-1]
        return (lambda v: isinstance(v, root)), f"a {root.__name__}"
    return (lambda v: isinstance(v, hint)), f"a {hint.__name__}"


def _number(value: Any) -> bool:
    """Not nan, nor sympy's complex infinity."""
    if getattr(value, "is_Number", False) is True:   # sympy: nan and zoo are Numbers
        return value.is_extended_real is True or value.is_finite is True
    try:
        return not cmath.isnan(complex(value))
    except (TypeError, ValueError, OverflowError):   # an int too large for a complex is a number
        return isinstance(value, numbers.Integral)


#: how deep an argument's lists, tuples and sets may nest: symkf reads matrices of rows (two levels)
#: and tables of them; far deeper input ends in a RecursionError inside a library (a mapping nested
#: deep is a file's table, which the codec reads without recursion and names)
MAX_NESTING = 32
_NESTED = (list, tuple, set, frozenset)


def _too_deep(value: Any) -> bool:
    """Whether ``value`` nests lists, tuples or sets more than :data:`MAX_NESTING` deep (iterative:
    the test itself must not recurse; each container is looked at once)."""
    stack, seen = ([(value, 0)] if isinstance(value, _NESTED) else []), set()
    while stack:
        item, depth = stack.pop()
        if id(item) in seen:
            continue
        if depth >= MAX_NESTING:
            return True
        seen.add(id(item))
        stack.extend((child, depth + 1) for child in item if isinstance(child, _NESTED))
    return False


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
    names = {**_symkf_classes(), **vars(sys.modules[fn.__module__])}  # the module's own names first
    out = []
    for position, (name, p) in enumerate(signature.parameters.items()):
        if p.annotation is p.empty or p.kind in (p.VAR_POSITIONAL, p.VAR_KEYWORD):
            continue
        try:
            probe = type("Probe", (), {"__annotations__": {name: p.annotation}, "__module__": fn.__module__})
            hint = typing.get_type_hints(probe, localns=names)[name]
        except Exception:  # noqa: BLE001 - an annotation we cannot resolve asks nothing checkable
            continue
        test = _test(hint)
        if test is not None:
            out.append((position if p.kind != p.KEYWORD_ONLY else -1, name, *test,
                        _ABSENT if p.default is p.empty else p.default))
    return out


def _symkf_classes() -> dict[str, type]:
    """The public classes of the symkf modules imported so far, by name: annotations that name a
    class imported only for type checking resolve through them."""
    out: dict[str, type] = {}
    # dict.copy, not list(d.items()): building a tuple per item may start the garbage collector,
    # whose finalizers can import (and so grow sys.modules) in the middle of the iteration
    for name, module in sys.modules.copy().items():
        if name.startswith("symkf.") and module is not None:
            # a copy taken at once: a module another thread is importing still gains names
            out.update({k: v for k, v in vars(module).copy().items()
                        if isinstance(v, type) and not k.startswith("_") and v.__module__.startswith("symkf.")})
    return out


def float_array(value: Any, entry: str) -> np.ndarray:
    """``value`` as a float64 array, or an :class:`InputError` naming ``entry`` (numpy's
    ``asarray`` raises ValueError or TypeError for text, objects and ragged rows, RecursionError for
    rows nested past Python's limit)."""
    if not isinstance(entry, str):
        raise InputError(f"float_array: entry must be a string naming the argument, got {described(entry)}")
    try:
        return np.asarray(value, dtype=float)
    except (TypeError, ValueError, OverflowError, RecursionError):
        raise InputError(f"{entry}: expected real numbers (an array or rows), got {described(value)}") from None


def index(value: Any, size: int, entry: str, first: int = 0) -> int:
    """``value`` as one of ``size`` positions numbered from ``first`` (a sensor, a state numbered
    from 1 as in a paper, a block), or an :class:`InputError` naming ``entry`` and the range
    (Python's negative positions are not taken: a position from outside names one thing)."""
    if not isinstance(entry, str) or any(isinstance(v, bool) or not isinstance(v, int) for v in (size, first)):
        raise InputError(f"index: expected int size and first and a str entry, got {described(size)}, "
                         f"{described(first)}, {described(entry)}")
    if isinstance(value, bool) or not isinstance(value, numbers.Integral) or not first <= value < first + size:
        raise InputError(f"{entry}: expected a position {first}..{first + size - 1}, got {described(value)}")
    return int(value)


def count(value: Any, entry: str, least: int = 0) -> int:
    """``value`` as an integer count at least ``least`` (a horizon, a holding time), or an
    :class:`InputError` naming ``entry``."""
    if not isinstance(entry, str) or isinstance(least, bool) or not isinstance(least, int):
        raise InputError(f"count: expected an int least and a str entry, got {described(least)}, {described(entry)}")
    if isinstance(value, bool) or not isinstance(value, numbers.Integral) or value < least:
        raise InputError(f"{entry}: expected an integer >= {least}, got {described(value)}")
    return int(value)


def _shown(signature: inspect.Signature) -> str:
    """``signature`` as written in the source, without its annotations (what a caller passes)."""
    return str(signature.replace(parameters=[p.replace(annotation=p.empty) for p in signature.parameters.values()],
                                 return_annotation=signature.empty))


#: ``(type, pricer)``: an argument of a call from outside symkf that is an instance of ``type``, or a
#: list, tuple or matrix holding one, is priced by ``pricer(value, entry)`` before the function
#: runs.  The exact layer registers sympy expressions, priced like the text of the safe parser
#: (degree, height, angles, nesting), so that an object costs what the same number as a string does.
PRICERS: list[tuple[type, Callable[[Any, str], None]]] = []


#: ``check(length, entry)``: refuses a list, tuple or matrix (its larger side) holding items that
#: :data:`PRICERS` price, when it is longer than any symkf reads, before its first item is priced (pricing is per
#: item: a million sympy numbers take minutes).  The exact layer registers the budget's cap.
LENGTHS: list[Callable[[int, str], None]] = []

#: lists up to this long are priced item by item without first looking at their items' types
_SHORT = 64


def _price(value: Any, entry: str, depth: int = 0) -> None:
    """Apply :data:`PRICERS` to ``value`` and, two levels deep, the items of its lists, tuples and
    matrices (``entry`` names it in errors); a long one is measured by :data:`LENGTHS` first, and
    walked only when it holds priced items or containers."""
    for kind, pricer in PRICERS:
        if isinstance(value, kind):
            pricer(value, entry)
            return
    matrix = type(value).__module__.startswith("sympy.matrices")
    if depth >= 2 or not isinstance(value, (list, tuple)) and not matrix:
        return
    if matrix and hasattr(value, "values"):
        # a sympy matrix's distinct nonzero entries, read from its internal representation: a
        # 560 x 560 transfer of a few distinct numbers is priced in milliseconds, not entry by entry
        # through sympy's indexing (its entries are all sympy numbers: measured by its larger side)
        distinct = set(value.values())
        if len(value) > _SHORT:   # by its larger side, and by its distinct numbers that cost more than a rational's bits
            for check in LENGTHS:
                check(max(value.shape), entry)
                check(sum(not getattr(item, "is_Rational", False) for item in distinct), entry)
        refused = set()
        for item in distinct:
            try:
                _price(item, entry, depth + 1)
            except SymkfError:
                refused.add(item)
        if refused:   # the first refused place in row-major order is priced again under its name, and raises
            i, j = min(key for key, v in value.todok().items() if v in refused)
            _price(value[i, j], f"{entry}[{i * value.shape[1] + j}]", depth + 1)
        return
    if len(value) > _SHORT:
        kinds = set(map(type, value))   # at C speed: a list of floats or strings is left at once
        if any(issubclass(k, kind) for k in kinds for kind, _ in PRICERS):
            for check in LENGTHS:   # a matrix by its larger side, as a list of rows by each level's length
                check(max(value.shape) if matrix else len(value), entry)
        elif not any(issubclass(k, (list, tuple)) or k.__module__.startswith("sympy.matrices") for k in kinds):
            return
    for i, item in enumerate(value):
        _price(item, f"{entry}[{i}]", depth + 1)


def unpriced(fn: Callable) -> Callable:
    """Mark ``fn`` as a measure of its arguments (a height, a field's degree): its arguments are
    checked against its annotations but not priced by :data:`PRICERS`, whose work it is."""
    if not callable(fn):
        raise InputError(f"unpriced: expected a function, got {described(fn)}")
    fn.__symkf_unpriced__ = True
    return fn


def outside(module: str) -> bool:
    """Whether the first caller outside the module ``module`` is outside symkf (a user's call, to
    be priced): for operators, which :func:`check_public` does not wrap."""
    if not isinstance(module, str):
        raise InputError(f"module: expected a module name, got {described(module)}")
    frame = sys._getframe(1)
    while frame is not None and frame.f_globals.get("__name__") == module:
        frame = frame.f_back
    return frame is None or not frame.f_globals.get("__name__", "").startswith("symkf.")


def guarded(fn: Callable, types: bool = True) -> Callable:
    """``fn`` with its arguments bound to its signature (an :class:`ArgumentError` otherwise) and,
    with ``types``, its annotated arguments checked first (module docstring)."""
    tests: list | None = None
    signature: inspect.Signature | None = None

    @functools.wraps(fn)
    def call(*args, **kwargs):
        nonlocal tests, signature
        if sys._getframe(1).f_globals.get("__name__", "").startswith("symkf."):
            return fn(*args, **kwargs)  # symkf's own calls pass what it built: the checks guard the boundary
        if tests is None:
            signature = inspect.signature(getattr(fn, "py_func", fn))
            tests = _tests(getattr(fn, "py_func", fn)) if types else []   # a numba kernel: its py_func's annotations
        try:
            bound = signature.bind(*args, **kwargs)
        except TypeError as e:   # Python's message ("missing a required argument: 'loss'") and the signature
            raise ArgumentError(f"{fn.__qualname__}{_shown(signature)}: {e}") from None
        for name, value in bound.arguments.items():
            if _too_deep(value):
                raise InputError(f"{fn.__qualname__}: argument {name!r} nests lists more than {MAX_NESTING} deep")
        for position, name, test, words, default in tests:
            value = args[position] if 0 <= position < len(args) else kwargs.get(name, _ABSENT)
            if value is _ABSENT or value is default:
                continue
            if not test(value):
                raise InputError(f"{fn.__qualname__}: argument {name!r} must be {words}, got {described(value)}")
        if PRICERS and not getattr(fn, "__symkf_unpriced__", False):
            for name, value in bound.arguments.items():
                _price(value, name)
        if _sized_by_sibling(bound):
            return fn(*bound.args, **bound.kwargs)
        return fn(*args, **kwargs)

    call.__symkf_checked__ = True
    for attr in ("cache_clear", "cache_info"):  # an lru_cache stays clearable
        if hasattr(fn, attr):
            setattr(call, attr, getattr(fn, attr))
    return call


def _sized_by_sibling(bound: inspect.BoundArguments) -> bool:
    """Give each argument without a size (``d is None``, a common loss rate) the number of sensors
    of the one system among the arguments; whether one was given."""
    # looked up statically: an argument's own attribute hooks never run here (nor a half-built self's)
    static = inspect.getattr_static
    args = {k: v for k, v in bound.arguments.items() if k not in ("self", "cls")}
    sizes = {v.d for v in args.values() if isinstance(static(v, "sensor_names", None), property)}
    unsized = [k for k, v in args.items() if static(v, "d", 0) is None and static(v, "with_sensors", None) is not None]
    if len(sizes) != 1 or not unsized:
        return False
    (d,) = sizes
    for name in unsized:
        bound.arguments[name] = bound.arguments[name].with_sensors(d)
    return True


def check_public(namespace: dict) -> None:
    """Wrap every public function and public method defined in the module whose globals are
    ``namespace`` with :func:`checked`."""
    if not isinstance(namespace, dict) or not isinstance(namespace.get("__name__"), str):
        raise InputError(f"namespace: expected a module's globals(), got {described(namespace)}")
    module = namespace["__name__"]
    for name, obj in list(namespace.items()):
        if name.startswith("_") or getattr(obj, "__module__", None) != module:
            continue
        # plain functions, and the ones behind functools.lru_cache or a numba kernel
        if (inspect.isfunction(obj) or callable(obj) and (hasattr(obj, "__wrapped__") or hasattr(obj, "py_func"))) \
                and not isinstance(obj, type) and not getattr(obj, "__symkf_checked__", False):
            namespace[name] = guarded(obj)
        elif isinstance(obj, type):
            for attr, member in list(vars(obj).items()):
                # a hand-written __init__ is checked; a dataclass's generated one (code from
                # "<string>") only stores the fields, which __post_init__ checks: its call is bound
                if attr.startswith("_") and not (attr == "__init__" and inspect.isfunction(member)):
                    continue
                if inspect.isfunction(member):
                    setattr(obj, attr, guarded(member, types=member.__code__.co_filename != "<string>"))
                elif isinstance(member, (classmethod, staticmethod)) and inspect.isfunction(member.__func__):
                    setattr(obj, attr, type(member)(guarded(member.__func__)))
