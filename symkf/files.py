"""System files (TOML) as described in the docs' formats page; errors name the file and the key.

A system file holds ``[system]`` (``A``, optional ``Q``, ``P0``, ``name``), a list
``[[sensors]]`` (``C``, optional ``R``, ``name``) and an optional ``[loss]`` table whose
``kind`` selects the loss model; :data:`KEYS` lists the keys each table may hold.
Numbers are integers, decimals (TOML ``0.1`` is exactly 1/10: the file's text is read, never
a binary float) or strings read by :func:`symkf.exact.numbers.parse_exact` ("5/4",
"sqrt(3)/2"); symbols are refused (a file gives numbers).  ``rationalize = true`` is accepted
for older files and changes nothing.  A file larger than ``symkf.budget`` ``max_file_size``
(1 MiB, option ``--max-file-size``) is refused before it is parsed.

* ``kind = "iid"``: ``loss = [...]``, one loss probability per sensor (:class:`~symkf.losses.IID`);
* ``kind = "gilbert-elliott"``: ``fail = [...]``, ``recover = [...]``
  (:class:`~symkf.losses.GilbertElliott`);
* ``kind = "markov"``: a joint chain of order ``order`` (default 1) on the receival vectors
  (:class:`~symkf.losses.MarkovLoss`).  ``states`` lists every 0/1 vector of length ``d``
  once (1 = received); ``P[a][b]`` is the probability that the next vector is ``states[b]``
  after the history ``a``, the histories being the ``order``-tuples of ``states`` (oldest
  first) in the order of ``itertools.product(states, repeat=order)``; optional
  ``initial[a]`` is the law of the first history (default: the stationary law).
* ``kind = "network"``: a sensor tree over a fading network state (Quevedo et al.,
  :class:`~symkf.network.NetworkLoss`).  ``parents[m-1] = Par(S_m)`` (0 = gateway; sensor
  ``m`` of ``[[sensors]]`` is node ``S_m``, a relay is a sensor with ``C = 0``);
  ``phi[m-1][j-1] = phi_{m|j}``, the success probability of link ``E_m`` in network state
  ``j``; the network state is Markov (Assumption 1), ``P[i-1][j-1] = p_ij``, or
  semi-Markov (Assumption 3): the embedded chain ``q`` and ``holding[i-1]``, the law
  ``psi_i`` of the holding time, as a list ``[psi_i(1), psi_i(2), ...]`` or a table
  ``{ delta = psi_i(delta) }``; optional ``initial`` is the law of ``Xi(0)`` (default:
  stationary).  Messages about these keys count sensors and states from 1, as the paper.

A fusion file (arXiv:2012.04896) has ``[fusion]`` and ``[[sensors]]`` instead of ``[system]``
and is read by :func:`load_fusion`: ``arrival = [...]`` (packet arrival rates
``lambda_i``), and either ``A``, ``Q`` (discrete time, :meth:`FusionModel.discrete
<symkf.fusion.FusionModel.discrete>`) or ``Ac``, ``Bc``, ``noise_variance``, ``Ts`` (a
zero-order hold, :meth:`FusionModel.zoh <symkf.fusion.FusionModel.zoh>`).
"""

from __future__ import annotations

import itertools
import re
import stat
import tomllib
from decimal import Decimal
from pathlib import Path
from typing import TYPE_CHECKING, Any, Callable

from . import budget, output
from .errors import FileFormatError, SymkfError
from .exact.numbers import to_exact
from .losses import IID, GilbertElliott, LossModel, MarkovLoss
from .model import Sensor, System

if TYPE_CHECKING:
    from .fusion import FusionModel


def _get(table: dict, key: str, where: str, required: bool = True) -> Any:
    if key not in table:
        if required:
            raise FileFormatError(f"{where}: missing key '{key}'")
        return None
    return table[key]


#: the keys each table may hold, by table ("" is the top level) and by loss ``kind``; any
#: other key is refused (a misspelt optional key would otherwise be silently replaced by
#: its default)
KEYS = {"": {"system", "sensors", "loss", "rationalize"}, "[system]": {"A", "Q", "P0", "name"},
        "sensors": {"name", "C", "R"}, "iid": {"kind", "loss"}, "gilbert-elliott": {"kind", "fail", "recover"},
        "markov": {"kind", "order", "states", "P", "initial"},
        "network": {"kind", "parents", "phi", "P", "q", "holding", "initial"},
        "fusion file": {"fusion", "sensors", "rationalize"},
        "[fusion]": {"arrival", "A", "Q", "Ac", "Bc", "noise_variance", "Ts"}}

#: the largest lifted chain of a network loss a file may ask for: (network states, or the
#: sum over states of the longest holding time) times 2^M link outcomes
MAX_NETWORK_CHAIN = 4096


def _check_keys(table: dict, allowed: set[str], where: str) -> None:
    unknown = sorted(set(table) - allowed)
    if unknown:
        raise FileFormatError(f"{where}: unknown key '{unknown[0]}' (allowed: {', '.join(sorted(allowed))})")


def _name(value: Any, where: str) -> str | None:
    if value is not None and (not isinstance(value, str) or not value.strip()):
        raise FileFormatError(f"{where}: key 'name' must be a non-empty string, got {value!r}")
    return value


def _exact(value: Any, entry: str, rationalize: bool, start: int = 0) -> Any:
    """``value`` with every number of its nested lists exact; ``entry`` (file, table and key)
    names it in errors and notes, list positions counted from ``start``.  Floats need
    ``rationalize``; symbols are refused."""
    if isinstance(value, list):
        return [_exact(v, f"{entry}[{i}]", rationalize, start) for i, v in enumerate(value, start=start)]
    try:
        return to_exact(value, entry, rationalize=rationalize)
    except SymkfError as exc:
        raise FileFormatError(str(exc)) from None


def read_toml(path: str | Path) -> dict:
    """The TOML document at ``path``, decimals as :class:`~decimal.Decimal` (exact); at most
    ``max_file_size`` bytes are read (a huge file is refused, not exhausted) from a regular file
    (a FIFO, directory or device such as ``/dev/zero`` is refused without waiting on it)."""
    path = Path(path)
    output.note_input(path)
    cap = budget.LIMITS.max_file_size
    try:
        # refused before it is opened unless it is a regular file (opening a FIFO with no writer
        # waits forever): a directory, FIFO, socket or device is not a system file
        mode = path.stat().st_mode
        if not stat.S_ISREG(mode):
            kind = "a directory" if stat.S_ISDIR(mode) else "a FIFO" if stat.S_ISFIFO(mode) else \
                "a device" if stat.S_ISCHR(mode) or stat.S_ISBLK(mode) else "a special file"
            raise FileFormatError(f"{path}: is {kind}, not a TOML file")
        with path.open("rb") as f:
            raw = f.read(cap + 1)
        budget.check("max_file_size", len(raw), str(path), "the size in bytes (at least)")
        return tomllib.loads(raw.decode("utf-8"), parse_float=Decimal)
    except FileNotFoundError:
        raise FileFormatError(f"{path}: no such file") from None
    except (tomllib.TOMLDecodeError, UnicodeDecodeError) as exc:
        raise FileFormatError(f"{path}: not valid TOML ({exc})") from None
    except ValueError as exc:  # e.g. an integer beyond Python's digit limit for str -> int
        if isinstance(exc, SymkfError):
            raise
        raise FileFormatError(f"{path}: not a usable TOML file ({exc})") from None
    except OSError as exc:
        raise FileFormatError(f"{path}: cannot read ({exc.strerror or type(exc).__name__})") from None


def load(path: str | Path) -> tuple[System, LossModel | None]:
    """Read a system file; returns the system and its loss model (None when absent)."""
    return parse(read_toml(path), str(path))


def _rationalize(data: dict, source: str) -> bool:
    rationalize = data.get("rationalize", False)
    if not isinstance(rationalize, bool):
        raise FileFormatError(f"{source}: key 'rationalize' must be true or false")
    return rationalize


def _sensors(data: dict, source: str, rationalize: bool) -> list[Sensor]:
    sensors_data = _get(data, "sensors", source)
    if not isinstance(sensors_data, list) or not sensors_data:
        raise FileFormatError(f"{source}: [[sensors]] must list at least one sensor")
    sensors = []
    for i, s in enumerate(sensors_data):
        where = f"{source}: sensors[{i}]"
        if not isinstance(s, dict):
            raise FileFormatError(f"{where} must be a table")
        _check_keys(s, KEYS["sensors"], where)
        C, name = _get(s, "C", where), _name(s.get("name"), where)
        sensors.append(_built(lambda: Sensor(C=C, R=s.get("R"), name=name, rationalize=rationalize),
                              f"sensors[{i}]"))
    return sensors


def parse(data: dict, source: str) -> tuple[System, LossModel | None]:
    """The system and loss model of already-read TOML ``data``; errors are prefixed by ``source``
    (a file name, or a file and a family grid point).  The system's default name is the last
    path component of ``source``."""
    if "fusion" in data:
        raise FileFormatError(f"{source}: key 'fusion': a fusion file (arXiv:2012.04896) has no [system]; "
                              "read it with symkf.files.load_fusion")
    _check_keys(data, KEYS[""], f"{source}")
    rationalize = _rationalize(data, source)
    return _built(lambda: _system_and_loss(data, source, rationalize), source)


def _system_and_loss(data: dict, source: str, rationalize: bool) -> tuple[System, LossModel | None]:
    sysdata = _get(data, "system", source)
    if not isinstance(sysdata, dict):
        raise FileFormatError(f"{source}: [system] must be a table")
    _check_keys(sysdata, KEYS["[system]"], f"{source}: [system]")
    sensors = _sensors(data, source, rationalize)
    system = System(A=_get(sysdata, "A", f"{source}: [system]"), sensors=sensors, Q=sysdata.get("Q"),
                    P0=sysdata.get("P0"), rationalize=rationalize,
                    name=_name(sysdata.get("name"), f"{source}: [system]") or Path(source).stem)
    return system, _loss(data.get("loss"), source, system, rationalize)


def _located(exc: SymkfError, where: str) -> SymkfError:
    """``exc`` with its message prefixed by ``where`` (the file, or the table inside it)."""
    exc.args = (f"{where}: {exc.args[0] if exc.args else exc}",)
    return exc


def _loss(table: Any, source: str, system: System, rationalize: bool) -> LossModel | None:
    if table is None:
        return None
    if not isinstance(table, dict):
        raise FileFormatError(f"{source}: [loss] must be a table")
    where = f"{source}: [loss]"
    kind = table.get("kind", "iid")
    if not isinstance(kind, str) or kind not in LOSS_KINDS:
        raise FileFormatError(f"{where} kind {kind!r} is not one of {', '.join(map(repr, LOSS_KINDS))}")
    _check_keys(table, KEYS[kind], where)
    model = _built(lambda: LOSS_KINDS[kind](table, where, system, rationalize), "[loss]")
    if model.d != system.d:
        raise FileFormatError(f"{where} gives {model.d} value(s) for {system.d} sensor(s)")
    return model


def _built(build: Callable[[], Any], where: str) -> Any:
    """``build()``, its errors (other than a :class:`FileFormatError`, which names the file
    already) prefixed by ``where``: the file, or a table or key inside it."""
    try:
        return build()
    except FileFormatError:
        raise
    except SymkfError as exc:
        raise _located(exc, where) from None


def _iid(table: dict, where: str, system: System, rationalize: bool) -> IID:
    return IID(_exact(_get(table, "loss", where), f"{where} loss", rationalize))


def _gilbert_elliott(table: dict, where: str, system: System, rationalize: bool) -> GilbertElliott:
    fail, recover = (_exact(_get(table, key, where), f"{where} {key}", rationalize) for key in ("fail", "recover"))
    return GilbertElliott(fail, recover)


def _positive_int(value: Any, entry: str) -> int:
    if isinstance(value, bool) or not isinstance(value, int) or value < 1:
        raise FileFormatError(f"{entry} must be a positive integer, got {value!r}")
    return value


def _markov(table: dict, where: str, system: System, rationalize: bool) -> MarkovLoss:
    order = _positive_int(table.get("order", 1), f"{where} key 'order'")
    states = _get(table, "states", where)
    d = system.d
    if not isinstance(states, list) or any(
            not isinstance(v, list) or len(v) != d or any(type(g) is not int or g not in (0, 1) for g in v)
            for v in states):
        raise FileFormatError(f"{where} key 'states': expected a list of 0/1 receival vectors of length {d} "
                              "(one entry per sensor, 1 = received)")
    vectors = [tuple(v) for v in states]
    seen: set[tuple[int, ...]] = set()
    for v in vectors:
        if v in seen:
            raise FileFormatError(f"{where} key 'states': {list(v)} is listed twice")
        seen.add(v)
    if len(vectors) != 2 ** d:  # then a missing vector is among the first len(vectors) + 1
        missing = next(v for v in itertools.product((1, 0), repeat=d) if v not in seen)
        raise FileFormatError(f"{where} key 'states': {list(missing)} is missing; list each of the "
                              f"2^{d} vectors once")
    P = _exact(_get(table, "P", where), f"{where} P", rationalize)
    rows = len(P) if isinstance(P, list) else 0
    # len(vectors) >= 2 rows per step of order: an order above rows.bit_length() cannot fit
    if order > rows.bit_length() or rows != len(vectors) ** order or any(
            not isinstance(row, list) or len(row) != len(vectors) for row in P):
        raise FileFormatError(f"{where} key 'P': expected {len(vectors)}^{order} rows (one per history) of "
                              f"{len(vectors)} probabilities (one per next vector in 'states')")
    histories = list(itertools.product(vectors, repeat=order))
    initial = table.get("initial")
    if initial is not None:
        initial = _exact(initial, f"{where} initial", rationalize)
        if not isinstance(initial, list) or len(initial) != len(histories):
            raise FileFormatError(f"{where} key 'initial': expected {len(histories)} probabilities, one per "
                                  "history (the rows of 'P')")
        initial = dict(zip(histories, initial))
    model = _built(lambda: MarkovLoss({h: dict(zip(vectors, row)) for h, row in zip(histories, P)}, order,
                                      initial), "key 'P'")
    _built(lambda: model.chain, "key 'initial'")  # the initial law is checked when the chain is built
    return model


def _holding(value: Any, where: str, rationalize: bool) -> list[Any]:
    """Holding-time laws as lists ``[psi(1), ...]`` or tables ``{delta: psi(delta)}`` (TOML keys are text)."""
    if not isinstance(value, list):
        raise FileFormatError(f"{where} key 'holding': expected a list of holding-time laws, one per network state")
    laws = []
    for i, law in enumerate(value, start=1):
        if isinstance(law, dict):
            bad = [k for k in law if not re.fullmatch(r"[1-9][0-9]{0,5}", k)]
            if bad:
                raise FileFormatError(f"{where} key 'holding[{i}]': holding time {bad[0]!r} is not a positive "
                                      "integer below 10^6")
            law = {int(k): _exact(p, f"{where} holding[{i}][{k}]", rationalize) for k, p in law.items()}
        laws.append(_exact(law, f"{where} holding[{i}]", rationalize, start=1) if isinstance(law, list) else law)
    return laws


def _network(table: dict, where: str, system: System, rationalize: bool):
    from .network import MarkovNetworkState, NetworkLoss, SemiMarkovNetworkState, SensorTree
    parents = _get(table, "parents", where)
    if not isinstance(parents, list):
        raise FileFormatError(f"{where} key 'parents': expected a list, parents[m-1] = Par(S_m) (0 = gateway)")
    tree = SensorTree(parents)
    if tree.M != system.d:
        raise FileFormatError(f"{where} key 'parents': the tree has {tree.M} sensor node(s), the system has "
                              f"{system.d} sensor(s); sensor m of [[sensors]] is node S_m")
    markov, semi = "P" in table, "q" in table or "holding" in table
    if markov == semi:
        raise FileFormatError(f"{where}: give 'P' (Markov network state, Assumption 1) or 'q' and 'holding' "
                              "(semi-Markov, Assumption 3), not " + ("both" if markov else "neither"))
    initial = table.get("initial")
    initial = None if initial is None else _exact(initial, f"{where} initial", rationalize, start=1)
    if markov:
        state = MarkovNetworkState(_exact(table["P"], f"{where} P", rationalize, start=1), initial)
        hidden = state.B
    else:
        q = _exact(_get(table, "q", where), f"{where} q", rationalize, start=1)
        holding = _holding(_get(table, "holding", where), where, rationalize)
        state = SemiMarkovNetworkState(q, holding, initial)
        hidden = sum(max(h) for h in state.holding)
    if hidden * 2 ** tree.M > MAX_NETWORK_CHAIN:
        raise FileFormatError(f"{where} key '{'P' if markov else 'holding'}': the lifted chain would have up to "
                              f"{hidden} x 2^{tree.M} states; files are limited to {MAX_NETWORK_CHAIN}")
    phi = _exact(_get(table, "phi", where), f"{where} phi", rationalize, start=1)
    return NetworkLoss(tree, state, phi)


#: ``[loss] kind`` -> reader(table, where, system, rationalize)
LOSS_KINDS: dict[str, Callable[[dict, str, System, bool], LossModel]] = {
    "iid": _iid, "gilbert-elliott": _gilbert_elliott, "markov": _markov, "network": _network}


def load_fusion(path: str | Path) -> "FusionModel":
    """Read a fusion file (arXiv:2012.04896): ``[fusion]`` and ``[[sensors]]``, see the module docstring."""
    return parse_fusion(read_toml(path), str(path))


def parse_fusion(data: dict, source: str) -> "FusionModel":
    """The :class:`~symkf.fusion.FusionModel` of already-read TOML ``data``; errors are prefixed by ``source``."""
    if "system" in data:
        raise FileFormatError(f"{source}: key 'system': a system file, not a fusion file; read it with "
                              "symkf.files.load")
    _check_keys(data, KEYS["fusion file"], source)
    rationalize = _rationalize(data, source)
    return _built(lambda: _fusion(data, source, rationalize), source)


def _fusion(data: dict, source: str, rationalize: bool) -> "FusionModel":
    from .fusion import FusionModel
    table = _get(data, "fusion", source)
    where = f"{source}: [fusion]"
    if not isinstance(table, dict):
        raise FileFormatError(f"{where} must be a table")
    _check_keys(table, KEYS["[fusion]"], where)
    sensors = _sensors(data, source, rationalize)
    if "Ac" in table:
        keys, build = ("Ac", "Bc", "noise_variance", "Ts"), FusionModel.zoh
    else:
        keys, build = ("A", "Q"), FusionModel.discrete
    extra = sorted(KEYS["[fusion]"] - {"arrival"} - set(keys) & set(table))
    if extra:
        raise FileFormatError(f"{where}: key '{extra[0]}' does not belong with {', '.join(keys)} "
                              "(give A, Q for discrete time or Ac, Bc, noise_variance, Ts for a zero-order hold)")
    values = [_exact(_get(table, key, where), f"{where} {key}", rationalize) for key in keys + ("arrival",)]
    return _built(lambda: build(*values[:-1], sensors, values[-1]), "[fusion]")
