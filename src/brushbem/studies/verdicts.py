"""The verdict on each thesis number: reproduced, reproduced with a stated choice, contradicted, or open.

A row is *reproduced* when ours is within `REPRODUCED_WITHIN` of the thesis's
value or within `STANDARD_ERRORS` standard errors of it (a thesis 0 is met
only within the standard errors: a trend the text asserts is judged against
the spread of the seeds, never against an absolute threshold).  Otherwise the
verdict is the one the study declares for the number (`ThesisNumber.verdict`,
with the evidence that supports it), and *open* where it declares none.  A
declared verdict never overrides the rule: a row that meets it is reproduced.
"""

from __future__ import annotations

import math
from collections.abc import Iterable

__all__ = [
    "CHAPTERS",
    "CONTRADICTED",
    "OPEN",
    "REPRODUCED",
    "REPRODUCED_WITHIN",
    "STANDARD_ERRORS",
    "STATED_CHOICE",
    "VERDICTS",
    "count_by_chapter",
    "judge",
]

REPRODUCED = "reproduced"
STATED_CHOICE = "reproduced with a stated choice"
CONTRADICTED = "contradicted"
OPEN = "open"
#: Every verdict, in the order of the count table.
VERDICTS = (REPRODUCED, STATED_CHOICE, CONTRADICTED, OPEN)
#: Relative distance within which a number is reproduced (the tolerance the comparison has always used).
REPRODUCED_WITHIN = 0.05
#: A number within this many standard errors of the thesis's value is reproduced.
STANDARD_ERRORS = 2.0

#: The thesis chapter of each study.
CHAPTERS = {
    "punch_spring": 2, "sphere_spring": 2, "nested_vs_convolution": 3, "flat_brush": 4,
    "rough_brush": 5, "hierarchy": 6, "concave": 7,
}


def judge(thesis: float, ours: float, standard_error: float, declared: str | None,
          claim: str | None = None) -> str:
    """The verdict of one row (module docstring); ``declared`` is the study's verdict, or None.

    ``claim`` ``">"`` or ``"<"`` makes the row a trend the text asserts (ours above or below
    ``thesis``): reproduced when ours lies on the asserted side by more than `STANDARD_ERRORS`
    standard errors (by any margin where there are none), contradicted when it lies on the other
    side by as much, and else the declared verdict.
    """
    if declared is not None and declared not in VERDICTS:
        raise ValueError(f"declared verdict must be one of {VERDICTS}; got {declared!r}")
    if claim is not None:
        if claim not in (">", "<"):
            raise ValueError(f"claim must be '>' or '<'; got {claim!r}")
        if math.isfinite(ours):
            margin = STANDARD_ERRORS * standard_error if math.isfinite(standard_error) else 0.0
            above = ours - thesis if claim == ">" else thesis - ours
            if above > margin:
                return REPRODUCED
            if -above > margin:
                return CONTRADICTED
        return declared if declared is not None else OPEN
    if math.isfinite(ours):
        gap = abs(ours - thesis)
        if thesis != 0 and gap <= REPRODUCED_WITHIN * abs(thesis):
            return REPRODUCED
        if math.isfinite(standard_error) and standard_error > 0 and gap <= STANDARD_ERRORS * standard_error:
            return REPRODUCED
    return declared if declared is not None else OPEN


def count_by_chapter(rows: Iterable[tuple[str, str]]) -> dict[int, dict[str, int]]:
    """Chapter -> verdict -> rows, from (study, verdict) pairs (studies outside `CHAPTERS` under 0)."""
    counts: dict[int, dict[str, int]] = {}
    for study, verdict in rows:
        chapter = counts.setdefault(CHAPTERS.get(study, 0), dict.fromkeys(VERDICTS, 0))
        chapter[verdict] += 1
    return dict(sorted(counts.items()))
