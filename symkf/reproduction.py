"""The report every ``reproduce_*`` function returns (``symkf reproduce NAME --json``).

``checks`` maps each claim symkf verified to a bool; every one must be True (a False is a
failure of symkf or of the paper's claim as symkf reads it, and the run reports it).
``discrepancies`` lists where a value the paper prints differs from the one symkf computes,
with both values: a misprint or a refuted formula is recorded there, not as a failed check.
"""

from __future__ import annotations

from typing import Any, Iterable

from .arguments import check_public


def discrepancy(claim: str, printed: Any, computed: Any, note: str = "") -> dict[str, str]:
    """One printed value against the computed one (both as exact text where they are exact)."""
    out = {"claim": claim, "printed": str(printed), "computed": str(computed)}
    if note:
        out["note"] = note
    return out


def reproduction(example: str, source: str, results: dict[str, Any], checks: dict[str, Any],
                 discrepancies: Iterable[dict[str, str]] = ()) -> dict[str, Any]:
    """``{"example", "source", "results", "checks", "discrepancies"}``; the checks' values (sympy and
    numpy booleans too) become plain bools."""
    return {"example": example, "source": source, "results": results,
            "checks": {claim: bool(ok) for claim, ok in checks.items()}, "discrepancies": list(discrepancies)}

check_public(globals())
