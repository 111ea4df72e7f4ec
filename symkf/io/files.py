"""System files (TOML) as described in the docs' formats page; errors name the file and the key.

A system file holds ``[system]`` (``A``, optional ``Q``, ``P0``, ``name``), a list
``[[sensors]]`` (``C``, optional ``R``, ``name``) and an optional ``[loss]`` table whose
``kind`` selects the loss model; :data:`KEYS` lists the keys each table may hold (a ``[loss]``
table, those of its kind's model).  The plant of LQG control over lossy networks (Schenato,
Sinopoli, Franceschetti, Poolla, Sastry, "Foundations of control and estimation over lossy
networks", 2007, Section II) adds a list ``[[actuators]]`` (``B``, optional ``U``, ``name``), the
state weight ``W`` in ``[system]`` and an optional ``[actuator_loss]`` table, of the same kinds as
``[loss]`` with one channel per actuator (:func:`load_loop`).
Numbers are integers, decimals (TOML ``0.1`` is exactly 1/10: the file's text is read, never
a binary float) or strings read by :func:`symkf.exact.numbers.parse_exact` ("5/4",
"sqrt(3)/2"); symbols are refused (a file gives numbers).  ``rationalize = true`` is accepted
for older files and changes nothing.  A file larger than ``symkf.budget`` ``max_file_size``
(1 MiB, option ``--max-file-size``) is refused before it is parsed.

* ``kind = "iid"``: ``loss = [...]``, one loss probability per sensor (:class:`~symkf.model.iid.IID`);
* ``kind = "gilbert-elliott"``: ``fail = [...]``, ``recover = [...]``, optional
  ``initial_received = [...]`` (default: stationary; :class:`~symkf.model.gilbert_elliott.GilbertElliott`);
* ``kind = "markov"``: a joint chain of order ``order`` (default 1) on the receival vectors
  (:class:`~symkf.model.markov.MarkovLoss`).  ``states`` lists the 0/1 vectors of length ``d`` the
  chain lives on, each once (1 = received; all ``2^d`` of them, or those that can occur); ``P[a][b]`` is the probability that the next vector is ``states[b]``
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

import stat
import tomllib
from decimal import Decimal
from pathlib import Path
from typing import TYPE_CHECKING, Any

from ..arguments import check_public
from .. import budget, output
from ..errors import FileFormatError, SymkfError
from ..model.codec import built, check_keys, entry, exact_values, read_loss, within
from ..model.loss import LossModel
from ..model.system import Actuator, Sensor, System

if TYPE_CHECKING:
    from ..fusion import FusionModel


#: the keys each table may hold, by table ("" is the top level); any other key is refused (a
#: misspelt optional key would otherwise be silently replaced by its default). A ``[loss]``
#: table holds the keys of its kind's model (:func:`symkf.model.codec.loss_kinds`).
KEYS = {"": {"system", "sensors", "actuators", "loss", "actuator_loss", "rationalize", "design"},
        "[system]": {"A", "Q", "P0", "W", "name"},
        "[design]": {"query", "costs", "weights", "critical_rate", "recovery_rate", "margin"},
        "sensors": {"name", "C", "R"}, "actuators": {"name", "B", "U"},
        "fusion file": {"fusion", "sensors", "rationalize"},
        "[fusion]": {"arrival", "A", "Q", "Ac", "Bc", "noise_variance", "Ts"}}


def _name(value: Any, where: str) -> str | None:
    if value is not None and (not isinstance(value, str) or not value.strip()):
        raise FileFormatError(f"{where}: key 'name' must be a non-empty string, got {value!r}")
    return value


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
        return tomllib.loads(raw.decode("utf-8-sig"), parse_float=Decimal)   # a byte-order mark is not TOML
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


def load_loop(path: str | Path) -> tuple[System, LossModel | None, LossModel | None]:
    """Read a system file with its control loop: the system (its actuators included), the loss
    model of its sensors' channels (``[loss]``) and that of its actuators' channels
    (``[actuator_loss]``, one channel per actuator: Schenato et al., 2007, Section II), each None
    when absent."""
    return parse_loop(read_toml(path), str(path))


def _rationalize(data: dict, source: str) -> bool:
    rationalize = data.get("rationalize", False)
    if not isinstance(rationalize, bool):
        raise FileFormatError(f"{source}: key 'rationalize' must be true or false")
    return rationalize


#: a list of channels: its class and the keys of its matrix and weight
_CHANNELS = {"sensors": (Sensor, "C", "R"), "actuators": (Actuator, "B", "U")}


def _channels(data: dict, source: str, rationalize: bool, key: str = "sensors") -> list[Any]:
    """The sensors (``[[sensors]]``, at least one) or actuators (``[[actuators]]``, optional)."""
    kind, matrix, weight = _CHANNELS[key]
    listed = entry(data, key, source, required=kind is Sensor)
    if listed is None:
        return []
    if not isinstance(listed, list) or kind is Sensor and not listed:
        raise FileFormatError(f"{source}: [[{key}]] must list " + (
            "at least one sensor" if kind is Sensor else "tables, one per actuator"))
    # counted before a channel's matrices are read (40,000 small sensors in a 1 MB file took 12 s)
    within("max_sensors", len(listed), f"{source}: [[{key}]]", f"the number of {key}")
    out = []
    for i, c in enumerate(listed):
        where = f"{source}: {key}[{i}]"
        if not isinstance(c, dict):
            raise FileFormatError(f"{where} must be a table")
        check_keys(c, KEYS[key], where)
        M, name = entry(c, matrix, where), _name(c.get("name"), where)
        out.append(built(lambda: kind(M, c.get(weight), name=name, rationalize=rationalize), f"{key}[{i}]"))
    return out


def parse(data: dict, source: str) -> tuple[System, LossModel | None]:
    """The system and loss model of already-read TOML ``data``; errors are prefixed by ``source``
    (a file name, or a file and a family grid point).  The system's default name is the last
    path component of ``source``."""
    system, loss, _ = parse_loop(data, source)
    return system, loss


def parse_loop(data: dict, source: str) -> tuple[System, LossModel | None, LossModel | None]:
    """The system, the loss model of its sensors and that of its actuators of already-read TOML
    ``data`` (:func:`load_loop`); errors are prefixed by ``source`` as :func:`parse`'s."""
    if "fusion" in data:
        raise FileFormatError(f"{source}: key 'fusion': a fusion file (arXiv:2012.04896) has no [system]; "
                              "read it with symkf.io.files.load_fusion")
    if "family" in data or "grid" in data:
        raise FileFormatError(f"{source}: a family file ([family], [grid]), not a system file: `symkf table` and "
                              "`symkf verify` read it (from Python: symkf.load_family)")
    check_keys(data, KEYS[""], f"{source}")
    rationalize = _rationalize(data, source)
    return built(lambda: _system_and_loss(data, source, rationalize), source)


def _system_and_loss(data: dict, source: str, rationalize: bool
                     ) -> tuple[System, LossModel | None, LossModel | None]:
    sysdata = entry(data, "system", source)
    if not isinstance(sysdata, dict):
        raise FileFormatError(f"{source}: [system] must be a table")
    check_keys(sysdata, KEYS["[system]"], f"{source}: [system]")
    sensors = _channels(data, source, rationalize)
    actuators = _channels(data, source, rationalize, "actuators")
    system = System(A=entry(sysdata, "A", f"{source}: [system]"), sensors=sensors, Q=sysdata.get("Q"),
                    P0=sysdata.get("P0"), rationalize=rationalize,
                    name=_name(sysdata.get("name"), f"{source}: [system]") or Path(source).stem,
                    actuators=actuators, W=sysdata.get("W"))
    return (system, _loss(data, "loss", source, system.d, rationalize),
            _loss(data, "actuator_loss", source, len(system.actuators), rationalize))


def _loss(data: dict, key: str, source: str, d: int, rationalize: bool) -> LossModel | None:
    """The loss model of the table ``key``: ``loss`` (one channel per sensor) or ``actuator_loss``
    (one per actuator)."""
    table = data.get(key)
    if table is None:
        return None
    if not isinstance(table, dict):
        raise FileFormatError(f"{source}: [{key}] must be a table")
    channels = "sensor" if key == "loss" else "actuator"
    if d == 0:
        raise FileFormatError(f"{source}: [{key}] gives the losses of the {channels}s' channels, and the file "
                              f"has no [[{channels}s]]")
    return read_loss(table, f"{source}: [{key}]", d, rationalize, label=f"[{key}]", channels=channels)


#: the queries of a ``[design]`` table (:mod:`symkf.design`)
DESIGN_QUERIES = ("select", "pareto", "allocate", "upgrades", "active")


def load_design(path: str | Path) -> tuple[System, LossModel | None, dict[str, Any]]:
    """Read a system file with a ``[design]`` table: the system (its sensors are the candidates),
    the loss model and the query, checked: ``query`` (one of :data:`DESIGN_QUERIES`, default
    ``"select"``), ``costs`` / ``weights`` (a table from sensor names to exact non-negative
    numbers), ``critical_rate``, ``recovery_rate``, ``margin`` (exact numbers)."""
    data = read_toml(path)
    source = str(path)
    system, loss = parse(data, source)
    table = data.get("design")
    where = f"{source}: [design]"
    if not isinstance(table, dict):
        raise FileFormatError(f"{source}: key 'design' missing; symkf design needs a [design] table "
                              f"(query = one of {', '.join(map(repr, DESIGN_QUERIES))})")
    check_keys(table, KEYS["[design]"], where)
    query = table.get("query", "select")
    if query not in DESIGN_QUERIES:
        raise FileFormatError(f"{where} key 'query': {query!r} is not one of {', '.join(map(repr, DESIGN_QUERIES))}")
    out: dict[str, Any] = {"query": query}
    for key in ("costs", "weights"):
        if key in table:
            prices = table[key]
            if not isinstance(prices, dict):
                raise FileFormatError(f"{where} key '{key}': expected a table from sensor names to numbers")
            unknown = [k for k in prices if k not in system.sensor_names]
            if unknown:
                raise FileFormatError(f"{where} key '{key}': {unknown[0]!r} is not a sensor "
                                      f"({', '.join(system.sensor_names)})")
            names = list(prices)
            values = exact_values([prices[k] for k in names], f"{where} {key}", False)
            out[key] = dict(zip(names, values))
    for key in ("critical_rate", "recovery_rate", "margin"):
        if key in table:
            out[key] = exact_values(table[key], f"{where} {key}", False, caps=())
    return system, loss, out


#: the caps on the lengths of each fusion key's lists (:func:`symkf.model.codec.exact_values`)
_FUSION_SHAPES = {"A": ("max_dimension", "max_dimension"), "Q": ("max_dimension", "max_dimension"),
                  "Ac": ("max_dimension", "max_dimension"), "Bc": ("max_dimension", "max_dimension"),
                  "noise_variance": (), "Ts": (), "arrival": ("max_sensors",)}


def load_fusion(path: str | Path) -> "FusionModel":
    """Read a fusion file (arXiv:2012.04896): ``[fusion]`` and ``[[sensors]]``, see the module docstring."""
    return parse_fusion(read_toml(path), str(path))


def parse_fusion(data: dict, source: str) -> "FusionModel":
    """The :class:`~symkf.fusion.FusionModel` of already-read TOML ``data``; errors are prefixed by ``source``."""
    if "system" in data:
        raise FileFormatError(f"{source}: key 'system': a system file, not a fusion file; read it with "
                              "symkf.io.files.load")
    check_keys(data, KEYS["fusion file"], source)
    rationalize = _rationalize(data, source)
    return built(lambda: _fusion(data, source, rationalize), source)


def _fusion(data: dict, source: str, rationalize: bool) -> "FusionModel":
    from ..fusion import FusionModel
    table = entry(data, "fusion", source)
    where = f"{source}: [fusion]"
    if not isinstance(table, dict):
        raise FileFormatError(f"{where} must be a table")
    check_keys(table, KEYS["[fusion]"], where)
    sensors = _channels(data, source, rationalize)
    if "Ac" in table:
        keys, build = ("Ac", "Bc", "noise_variance", "Ts"), FusionModel.zoh
    else:
        keys, build = ("A", "Q"), FusionModel.discrete
    extra = sorted(KEYS["[fusion]"] - {"arrival"} - set(keys) & set(table))
    if extra:
        raise FileFormatError(f"{where}: key '{extra[0]}' does not belong with {', '.join(keys)} "
                              "(give A, Q for discrete time or Ac, Bc, noise_variance, Ts for a zero-order hold)")
    values = [exact_values(entry(table, key, where), f"{where} {key}", rationalize, caps=_FUSION_SHAPES[key])
              for key in keys + ("arrival",)]
    return built(lambda: build(*values[:-1], sensors, values[-1]), "[fusion]")

check_public(globals())
