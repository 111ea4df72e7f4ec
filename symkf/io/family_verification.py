"""Theory against simulation over a parameter family: :func:`symkf.numeric.verify.verify` on
every member of a family (a TOML family file with a ``[loss]`` template, see
:mod:`symkf.io.families`) with :func:`symkf.run.sweep.sweep`, serially, on local processes or on
a Dask cluster.

Member ``i`` is simulated with the seeds ``seed + 3i`` .. ``seed + 3i + 2``, fixed by its place
in the family, so the reports are identical however the sweep runs.  A member whose
assumptions fail or whose simulation breaks down gets its own row with the reason; the run
continues.
"""

from __future__ import annotations

import functools
import html
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Iterator, Sequence

from ..output import JsonDocument
from ..arguments import check_public
from ..errors import AssumptionError, FileFormatError, InputError, NumericalBreakdownError, SymkfError
from ..numeric.verify import BREAKDOWN, INAPPLICABLE, OUTCOMES, Verification, approximately, interval_text, verify
from ..run.sweep import sweep
from .families import Family, Member, load_family
from .files import read_toml


def is_family_file(path: str | Path) -> bool:
    """Whether ``path`` is a TOML file with a ``[family]`` table (else it is read as a system file)."""
    try:
        return isinstance(read_toml(path).get("family"), dict)
    except SymkfError:
        return False  # the system-file reader reports the problem


@dataclass(frozen=True)
class MemberVerification(JsonDocument):
    """One member of a verified family: its ``label``, ``index``, grid ``point`` (name, exact
    value) pairs, ``seed``, ``outcome`` and ``reason``; ``verification`` is None when the
    member is inapplicable or its simulation broke down."""

    label: str
    index: int
    point: tuple[tuple[str, Any], ...]
    seed: int
    outcome: str
    reason: str
    verification: Verification | None = None

    def to_dict(self) -> dict[str, Any]:
        head = {"member": self.label, "index": self.index, "point": {k: str(v) for k, v in self.point},
                "seed": self.seed}
        if self.verification is None:
            return {**head, "outcome": self.outcome, "reason": self.reason}
        return {**head, **self.verification.to_dict()}


@dataclass(frozen=True, repr=False)
class FamilyVerification(Sequence[MemberVerification], JsonDocument):
    """:func:`verify` over a family (:func:`verify_family`): a sequence of
    :class:`MemberVerification` in the family's order.  ``str()`` is the ``symkf verify`` table,
    ``to_dict()`` the family's name and its members' ``--json`` documents."""

    name: str
    members: tuple[MemberVerification, ...]

    def __getitem__(self, i):  # type: ignore[override]
        return self.members[i]

    def __len__(self) -> int:
        return len(self.members)

    def __iter__(self) -> Iterator[MemberVerification]:
        return iter(self.members)

    def counts(self) -> dict[str, int]:
        """How many members have each outcome."""
        return {o: sum(m.outcome == o for m in self.members) for o in (*OUTCOMES, INAPPLICABLE, BREAKDOWN)}

    def to_dict(self) -> dict[str, Any]:
        return {"family": self.name, "members": [m.to_dict() for m in self.members]}

    def __str__(self) -> str:
        return family_summary(self.to_dict()["members"])

    def __repr__(self) -> str:
        counts = ", ".join(f"{n} {o}" for o, n in self.counts().items() if n)
        return f"<FamilyVerification {self.name}: {len(self)} members, {counts}>"

    def _repr_html_(self) -> str:
        return f"<pre>{html.escape(str(self))}</pre>"


def verify_member(task: tuple[int, Member, int], **kw: Any) -> MemberVerification:
    """:func:`verify` on member ``(index, member, seed)`` of a family (runs on sweep workers).

    A member whose theorem assumptions fail gets outcome ``"inapplicable"``, one whose
    simulation breaks down numerically ``"breakdown"``, each with the reason naming the
    member, so one such member does not stop a campaign.
    """
    index, member, seed = task
    head = (member.label, index, tuple(member.point), seed)
    system, loss = member.system()
    try:
        result = verify(system, loss, seed=seed, **kw)
    except AssumptionError as exc:
        return MemberVerification(*head, INAPPLICABLE, str(exc))
    except NumericalBreakdownError as exc:
        return MemberVerification(*head, BREAKDOWN, f"member {member.label}: {exc}")
    return MemberVerification(*head, result.outcome, result.reason, result)


def verify_family(path: str | Path | Family, jobs: int = 1, scheduler: Any = None, *, seed: int = 0,
                  progress: bool | None = None, **kw: Any) -> FamilyVerification:
    """:func:`verify` on every member of the family file ``path``, in the family's order.

    The family needs a ``[loss]`` template.  Member ``i`` uses ``seed + 3i`` (its three
    simulation runs take ``seed + 3i`` .. ``seed + 3i + 2``, so no two runs share a random
    stream), which makes the reports identical for ``jobs=1``, ``jobs=N`` and a Dask
    ``scheduler`` (see :func:`symkf.run.sweep.sweep`).  ``kw`` goes to :func:`verify`
    (``paths``, ``horizon``, ``tolerance``, ``confidence``).  Each member is a
    :class:`MemberVerification`: label, index, grid point, seed and :func:`verify`'s result; a
    member whose assumptions fail has ``outcome = "inapplicable"`` and its ``reason``.
    """
    family = path if isinstance(path, Family) else load_family(path)
    if not family.members[0].has_loss:
        raise FileFormatError(f"{family.path}: [loss]: verify needs a loss model; give the family a [loss] "
                              "template, e.g. kind = \"iid\", loss = [\"eps\"] with eps in [grid]")
    tasks = [(i, m, seed + 3 * i) for i, m in enumerate(family.members)]
    return FamilyVerification(family.name, tuple(sweep(functools.partial(verify_member, **kw), tasks, jobs=jobs,
                                                       scheduler=scheduler, progress=progress,
                                                       desc=f"verify {family.name}", label=_member_label)))


def _member_label(task: tuple[int, Member, int]) -> str:
    return f"member {task[1].label}"


def family_summary(reports: list[dict[str, Any]]) -> str:
    """One line per member (theory, simulation, outcome) and a count of the outcomes."""
    if not reports:
        raise InputError("reports: a family verification has at least one member's report")
    width = max(len(r["member"]) for r in reports)
    lines = []
    for r in reports:
        if r["outcome"] in (INAPPLICABLE, BREAKDOWN):
            lines.append(f"{r['member']:<{width}}  {r['outcome'].upper()}: {' '.join(r['reason'].split())}")
            continue
        t, s = r["theory"], r["simulation"]
        lines.append(f"{r['member']:<{width}}  theory {'stable' if t['stable'] else 'NOT stable':<10} "
                     f"growth {approximately(t['growth_rate']['exact'], t['growth_rate']['decimal'])}; "
                     f"simulation {s['verdict']:<9} margin {interval_text(s, short=True)}, "
                     f"seeds {', '.join(map(str, s['seeds']))}; {r['outcome'].upper()}")
    counts = [f"{sum(r['outcome'] == o for r in reports)} {o}" for o in (*OUTCOMES, INAPPLICABLE, BREAKDOWN)]
    lines.append(f"{len(reports)} members: " + ", ".join(counts))
    return "\n".join(lines)


check_public(globals())
