"""The verdict on each thesis number: reproduced, reproduced with a stated choice, contradicted, open, or used to identify.

The rule, which no declaration bends:

* A value is *reproduced* when ours is within `REPRODUCED_WITHIN` of the
  thesis's value, or when our standard error is precise (at most
  `PRECISE_WITHIN` of our value) and the gap is within `STANDARD_ERRORS` of
  them.  A gap within the standard errors of an imprecise estimate is *open*
  ("imprecise"): its seeds neither meet nor refute the thesis's value.
* A qualitative claim (a trend the text asserts, ``claim`` ``">"`` or ``"<"``
  against a threshold, and a thesis 0: "vanishes", "tends to zero", read as
  ``|ours| < VANISHES_BELOW``) is judged both ways alike: reproduced when ours
  lies on the asserted side by more than `STANDARD_ERRORS` standard errors,
  contradicted when it lies on the other side by as much, open in between.  A
  declaration does not change a qualitative verdict.  A difference within its
  standard errors of the threshold is *open* whichever side its sign is on;
  and one within the resolution the row states (``tie``: the model's own
  error on the compared numbers, measured and named in the row) is *open*
  ("a tie") however small its standard error: the seeds can make a tie
  precise, never decided; beyond it, the row is decided only where its
  distance from the threshold exceeds the resolution and two standard errors
  together.
* A row that meets the rule and is declared *reproduced with a stated choice*
  keeps that verdict: its number rests on a parameter the thesis leaves open,
  fixed once by its chapter's identification and named in the row.
* A row that fails the rule takes the verdict the study declares for it
  (`ThesisNumber.verdict`, with the evidence that supports it) where that is
  *contradicted* or *open*; it is *open* where the study declares nothing or
  declares *reproduced with a stated choice* (the choice does not meet the
  rule).  *Reproduced* cannot be declared: a declaration never turns a failing
  row into a reproduced one, with or without a choice.
* A row that a chapter's one identification uses (*used to identify*) keeps
  that verdict whatever its numbers: it decided a parameter, so it cannot also
  test it.
* A qualitative row whose evidence does not test its claim (``untested``: the
  tables hold a number the claim does not decide, e.g. how many pillars are
  attached at the pull-off for a claim about the order they leave in) is
  *open* ("the evidence does not test the claim") whatever its number.
* A comparative row (``claim``) of a chapter with a stated resolution
  (`RESOLUTIONS`: the chapter's measured model or grid error on the compared
  numbers, with its source) takes it as its ``tie``; where the chapter also
  states a mesh error of its ratios (``mesh``), a row decided beyond the tie and
  two standard errors by less than that mesh error is *open* ("cleared by less
  than the mesh error").
* A row computed from other rows' values (``inputs``, `derived`) inherits
  their held-out status: computed from a row *used to identify*, it is *used to
  identify* too (its value is not independent of the identification); computed
  from a row that the tied candidates opened, it cannot be *reproduced*.
* A held-out row of a chapter whose identification has tied candidates (the
  rule's tie-break, not its score, chose among them) is judged at each tied
  candidate where that candidate's value exists (`held_out`): it is
  *reproduced* or *reproduced with a stated choice* only if its verdict is the
  same at every one of them; otherwise it is *open* ("the identification's
  tied candidates disagree", with the values).  Where no tied candidate's
  value exists, the row says "checked at the identified candidate only".
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Mapping
from dataclasses import dataclass

__all__ = [
    "CHAPTERS",
    "CHECKED_AT_IDENTIFIED",
    "COMPUTED_FROM_IDENTIFYING",
    "CONTRADICTED",
    "DECLARABLE",
    "OPEN",
    "PRECISE_WITHIN",
    "REPRODUCED",
    "REPRODUCED_WITHIN",
    "RESOLUTIONS",
    "STANDARD_ERRORS",
    "STATED_CHOICE",
    "TIED_DISAGREE",
    "UNTESTED",
    "USED_TO_IDENTIFY",
    "VANISHES_BELOW",
    "VERDICTS",
    "Judgement",
    "Resolution",
    "count_by_chapter",
    "derived",
    "held_out",
    "judge",
    "judgement",
]

REPRODUCED = "reproduced"
STATED_CHOICE = "reproduced with a stated choice"
CONTRADICTED = "contradicted"
OPEN = "open"
USED_TO_IDENTIFY = "used to identify"
#: Every verdict, in the order of the count table.
VERDICTS = (REPRODUCED, STATED_CHOICE, CONTRADICTED, OPEN, USED_TO_IDENTIFY)
#: The verdicts a study may declare for a number (never *reproduced*: the rule alone gives that).
DECLARABLE = (STATED_CHOICE, CONTRADICTED, OPEN, USED_TO_IDENTIFY)
#: Relative distance within which a number is reproduced (the tolerance the comparison has always used).
REPRODUCED_WITHIN = 0.05
#: A number within this many standard errors of the thesis's value is reproduced, if its error is precise.
STANDARD_ERRORS = 2.0
#: A standard error counts (for the standard-error path) only up to this fraction of our value: a larger
#: one reproduces any nearby thesis number, and rewards running fewer seeds.
PRECISE_WITHIN = 0.05
#: A thesis 0 ("vanishes", "tends to zero") is the qualitative claim |ours| < this (every such number is
#: a force normalised by the rigid brush's or the equal-sharing force: 5 % of it).
VANISHES_BELOW = 0.05

#: The thesis chapter of each study.
CHAPTERS = {
    "punch_spring": 2, "sphere_spring": 2, "nested_vs_convolution": 3, "flat_brush": 4,
    "rough_brush": 5, "hierarchy": 6, "concave": 7,
}


@dataclass(frozen=True)
class Resolution:
    """A chapter's stated resolution of its comparative rows: the relative error of the compared numbers that
    its model or grid carries (measured; ``source`` says where), and a mesh error of its ratios (``mesh``, 0:
    none stated) that a decided row must clear too."""

    relative: float
    source: str
    mesh: float = 0.0
    mesh_source: str = ""

    def tie(self, threshold: float = 1.0) -> float:
        """The tie of a row judged against ``threshold`` (a ratio against 1: ``relative`` itself)."""
        return self.relative * (abs(threshold) if threshold else 1.0)

    @property
    def stated(self) -> str:
        """The resolution and its sources, as a row's evidence names them."""
        mesh = (f"; decided only where it also clears the mesh error {100 * self.mesh:.1f} %: {self.mesh_source}"
                if self.mesh else "")
        return f"a ratio within {100 * self.relative:.1f} % of 1 is a tie: {self.source}{mesh}"


#: The stated resolution of each chapter's comparative rows (one home: the rows take ``tie`` and ``mesh`` from
#: here).  Chapters 2 and 3 compare closed forms and methods, not brushes: none.
RESOLUTIONS = {
    4: Resolution(0.031, "chapter 4's grid error, the stiff F~_A at k~ = 10 with each regular lattice refined to "
                         "twice its elements a radius: -1.5 % (8 x 8, N = 256 to 512), -2.1 % (16 x 16, 512 to 1024), "
                         "-3.1 % (48 x 48, 512 to 1024; notes, chapter 4, `benchmarks/brush.py --elements 1024`), the "
                         "largest taken"),
    6: Resolution(0.015, "the pillar-level model against the exact path on the same brushes (N = 1024, seed 803261128; "
                         "set mesh of fig63_* against clustered_*) is -0.76 %, -1.47 %, -0.05 % for one, two, three "
                         "levels, +1.44 % on three over two",
                  0.014, "from 4.5 to 9 elements a radius (seed 803261128, set mesh and fig63_tips) one level's "
                         "plateau moves -2.5 %, two and three levels' -3.8 %: three over one by -1.4 %"),
    7: Resolution(0.039, "chapter 7's grid error on its identified 24 x 24: the stiff maximum (k~ = 10, phi = 0.06) "
                         "on N = 464, 488, 536, 560 against N = 512 is +3.9, +2.8, +0.7, +2.1 % "
                         "(probe_concave_count.csv), the largest taken (16 x 16, N = 320 against 512, every point: "
                         "ratios of forces up to 3.3 %)"),
}


@dataclass(frozen=True)
class Judgement:
    """A verdict and, where the rule and not the study decided it, why (else "")."""

    verdict: str
    reason: str = ""
    qualitative: bool = False


#: The reason of a qualitative row whose evidence does not test its claim.
UNTESTED = "the evidence does not test the claim"


def judgement(thesis: float, ours: float, standard_error: float, declared: str | None,
              claim: str | None = None, realizations: int = 0, tie: float = 0.0, mesh: float = 0.0,
              untested: str = "") -> Judgement:
    """The verdict of one row, with the rule's reason (module docstring).

    ``declared`` is the study's verdict (one of `DECLARABLE`), or None.
    ``claim`` ``">"`` or ``"<"`` makes the row a trend the text asserts (ours above or below
    ``thesis``); a ``thesis`` of 0 is the claim ``|ours| < VANISHES_BELOW``.  ``realizations``:
    the seeds behind the standard error (named in the reason of an imprecise row).  ``tie``: for a
    qualitative row, the distance from the threshold within which ours cannot tell the two sides
    apart (the model's error on the compared numbers); 0: none stated.  ``mesh``: a further error of
    the compared numbers (`Resolution.mesh`) a decided row must clear too.  ``untested``: non-empty, why
    the row's evidence does not test its qualitative claim (the row is then *open*).

    Raises
    ------
    ValueError
        ``declared`` not one of `DECLARABLE` (*reproduced* included), ``claim`` not ``">"``/``"<"``,
        or ``tie`` or ``mesh`` negative or not finite.
    """
    if declared is not None and declared not in DECLARABLE:
        raise ValueError(f"declared verdict must be one of {DECLARABLE} (a declaration never makes a row "
                         f"{REPRODUCED!r}: the rule alone does); got {declared!r}")
    if claim is not None and claim not in (">", "<"):
        raise ValueError(f"claim must be '>' or '<'; got {claim!r}")
    for name, v in (("tie", tie), ("mesh", mesh)):
        if not (math.isfinite(v) and v >= 0):
            raise ValueError(f"{name} must be finite and >= 0 (a distance from the threshold); got {v!r}")
    if declared == USED_TO_IDENTIFY:
        return Judgement(USED_TO_IDENTIFY)
    qualitative = claim is not None or thesis == 0
    if qualitative:
        if untested:
            return Judgement(OPEN, f"{UNTESTED}: {untested}", True)
        if not math.isfinite(ours):
            return Judgement(OPEN, "not computable", True)
        margin = STANDARD_ERRORS * standard_error if math.isfinite(standard_error) else 0.0
        if claim is None:  # a thesis 0: |ours| below the threshold
            above = VANISHES_BELOW - abs(ours)
        else:
            above = ours - thesis if claim == ">" else thesis - ours
        if abs(above) <= tie:
            return Judgement(OPEN, f"a tie: within {tie:g} of the threshold, the resolution the row states", True)
        margin += tie  # decided only beyond the stated resolution and the standard errors together
        if abs(above) > margin + mesh:
            return Judgement(REPRODUCED if above > 0 else CONTRADICTED, "", True)
        if abs(above) > margin:
            return Judgement(OPEN, f"cleared by {abs(above) - margin:.2g}, less than the mesh error {mesh:g} "
                                   "the row states", True)
        within = f"{STANDARD_ERRORS:g} standard errors" + (f" and the resolution {tie:g}" if tie else "")
        return Judgement(OPEN, f"undecided: within {within} of the threshold", True)
    if math.isfinite(ours):
        gap = abs(ours - thesis)
        met = REPRODUCED if declared != STATED_CHOICE else STATED_CHOICE
        if gap <= REPRODUCED_WITHIN * abs(thesis):
            return Judgement(met)
        if math.isfinite(standard_error) and standard_error > 0 and gap <= STANDARD_ERRORS * standard_error:
            if standard_error <= PRECISE_WITHIN * abs(ours):
                return Judgement(met)
            seeds = f", {realizations} seeds" if realizations else ""
            return Judgement(OPEN, f"imprecise{seeds}: the standard error is {100 * standard_error / abs(ours):.0f} % "
                                   f"of the value (the rule counts it up to {100 * PRECISE_WITHIN:.0f} %)")
    if declared == STATED_CHOICE:
        return Judgement(OPEN, "the stated choice does not meet the rule")
    return Judgement(declared if declared is not None else OPEN)


def judge(thesis: float, ours: float, standard_error: float, declared: str | None,
          claim: str | None = None, realizations: int = 0, tie: float = 0.0, mesh: float = 0.0,
          untested: str = "") -> str:
    """The verdict of one row (`judgement`'s, without its reason)."""
    return judgement(thesis, ours, standard_error, declared, claim, realizations, tie, mesh, untested).verdict


#: The reasons `held_out` gives.
TIED_DISAGREE = "the identification's tied candidates disagree"
CHECKED_AT_IDENTIFIED = "checked at the identified candidate only"


def held_out(judged: Judgement, thesis: float, ours: float, tied: Mapping[str, float], declared: str | None,
             claim: str | None = None, tie: float = 0.0, identified: str = "the identified candidate",
             mesh: float = 0.0) -> Judgement:
    """``judged`` (the row's `judgement` at the identified candidate, value ``ours``) checked at the
    identification's other tied candidates (module docstring).

    ``tied``: tied candidate -> the row's value there (NaN: not computed there); each is one
    deterministic layout, judged without a standard error, with the row's ``declared``, ``claim``
    and ``tie``.  A *reproduced* (with or without a stated choice) row whose verdict differs at a
    tied candidate becomes *open*; every other verdict stands.  The reason names every tied value
    (or says none was computed).
    """
    computed = {name: float(v) for name, v in tied.items() if math.isfinite(v)}
    missing = [name for name, v in tied.items() if not math.isfinite(v)]
    if not tied:
        return judged
    at = {name: judgement(thesis, v, math.nan, declared, claim, tie=tie, mesh=mesh).verdict
          for name, v in computed.items()}
    shown = "; ".join(f"{v:.4g} at {name} ({at[name]})" for name, v in computed.items())
    unchecked = (f"not computed at {', '.join(missing)}" if computed else CHECKED_AT_IDENTIFIED) if missing else ""
    decided = judged.verdict in (REPRODUCED, STATED_CHOICE)
    if decided and any(v != judged.verdict for v in at.values()):
        reason = f"{TIED_DISAGREE} ({ours:.4g} at {identified}; {shown})"
        return Judgement(OPEN, "; ".join(p for p in (reason, unchecked) if p), judged.qualitative)
    beside = (f"the same at the tied {shown}" if decided else f"at the tied {shown}") if computed else ""
    return Judgement(judged.verdict, "; ".join(p for p in (judged.reason, beside, unchecked) if p), judged.qualitative)


#: The reason of a row computed from a row used to identify.
COMPUTED_FROM_IDENTIFYING = "computed from a row used to identify"


def derived(judged: Judgement, inputs: Mapping[str, Judgement]) -> Judgement:
    """``judged`` (a row computed from other rows' values) with its inputs' held-out status (module docstring).

    ``inputs``: each input row's quantity -> its judgement.  An input *used to identify* makes the row *used to
    identify* (naming the inputs); an input that the identification's tied candidates opened (`held_out`) makes a
    *reproduced* row (with or without a stated choice) *open*; otherwise ``judged`` stands.
    """
    identifying = [q for q, j in inputs.items() if j.verdict == USED_TO_IDENTIFY]
    if identifying:
        return Judgement(USED_TO_IDENTIFY, f"{COMPUTED_FROM_IDENTIFYING} ({'; '.join(identifying)})", judged.qualitative)
    opened = [q for q, j in inputs.items() if TIED_DISAGREE in j.reason]
    if opened and judged.verdict in (REPRODUCED, STATED_CHOICE):
        return Judgement(OPEN, f"an input row is open because {TIED_DISAGREE} ({'; '.join(opened)})",
                         judged.qualitative)
    return judged


def count_by_chapter(rows: Iterable[tuple[str, str]]) -> dict[int, dict[str, int]]:
    """Chapter -> verdict -> rows, from (study, verdict) pairs (studies outside `CHAPTERS` under 0)."""
    counts: dict[int, dict[str, int]] = {}
    for study, verdict in rows:
        chapter = counts.setdefault(CHAPTERS.get(study, 0), dict.fromkeys(VERDICTS, 0))
        chapter[verdict] += 1
    return dict(sorted(counts.items()))
