"""Chapter 5's claims in words (L885-887, L905, L913, L931, L933, L958, L964): one row each.

Each row is judged by the rule (`brushbem.studies.verdicts`) from the committed tables at chapter 5's
one identification (16 x 16 pillars, c read at F~_P = 0.1).  A claim that no committed table at that
identification decides is a row whose value is not computable, *open*, saying which table is missing.
`rough_brush` passes its readers in (`claims`), so that this module imports no study.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping

import numpy as np
import pandas as pd

from brushbem.studies._ch5_7 import (
    FA,
    FP,
    K,
    PRELOAD,
    SATURATED,
    SIG,
    SIGMA,
    adhesion_coefficients,
    finished,
    fit_eq58,
    has,
)
from brushbem.studies._common import safe
from brushbem.studies.base import ThesisNumber
from brushbem.studies.verdicts import OPEN, VANISHES_BELOW

Reader = Callable[[Mapping[str, pd.DataFrame]], float]

#: The part that samples F~_A over the preload at chapter 5's identification (16 x 16 pillars).
PRELOAD_PART = "preload16"
#: The share of F~_A's rise over the sampled preloads that comes in their last doubling (F~_P = 10 to 20)
#: under this fraction reads as "increases ... and ultimately reaches a plateau" (ours: the thesis states
#: no threshold).
PLATEAU_RISE_SHARE = 0.1
#: The plateau begins where the mean F~_A first reaches this fraction of its largest (ours, as `SATURATED`
#: of the reading of c: the thesis states no criterion).
PLATEAU_SHARE = SATURATED


def _curves(results: Mapping[str, pd.DataFrame], k: float) -> dict[float, pd.DataFrame]:
    """sigma~ -> (F~_P, mean F~_A) by preload at k~ in part `PRELOAD_PART`, the curves whose largest mean
    F~_A reaches `VANISHES_BELOW` (a vanishing curve has neither a linear region nor a plateau to read)."""
    frame = finished(results, PRELOAD_PART)
    if not has(frame, FA, FP, SIG, K, SIGMA, PRELOAD):
        return {}
    frame = frame[np.isclose(frame[K], k, rtol=1e-6)]
    means = frame.groupby([SIGMA, PRELOAD]).agg(fp=(FP, "mean"), fa=(FA, "mean"), sig=(SIG, "mean")).reset_index()
    curves = {}
    for _, curve in means.groupby(SIGMA):
        curve = curve.sort_values("fp")
        if len(curve) >= 4 and curve["fa"].max() >= VANISHES_BELOW:
            curves[round(float(curve["sig"].mean()), 2)] = curve
    return curves


@safe
def _last_rise_share(results: Mapping[str, pd.DataFrame]) -> float:
    """At k~ = 10, the largest over sigma~ of the share of the mean F~_A's rise from the smallest to the
    largest preload that comes between the two largest (part preload16); infinite where F~_A does not rise."""
    shares = []
    for curve in _curves(results, 10.0).values():
        fa = curve["fa"].to_numpy()
        rise = fa[-1] - fa[0]
        shares.append((fa[-1] - fa[-2]) / rise if rise > 0 else math.inf)
    return max(shares) if shares else math.nan


def _plateau_onset(curve: pd.DataFrame) -> float:
    """F~_P where the mean F~_A first reaches `PLATEAU_SHARE` of its largest, linear in log F~_P between
    the sampled preloads."""
    fp, fa = np.log(curve["fp"].to_numpy()), curve["fa"].to_numpy()
    level = PLATEAU_SHARE * fa.max()
    i = int(np.argmax(fa >= level))
    if i == 0:
        return float(math.exp(fp[0]))
    return float(math.exp(fp[i - 1] + (level - fa[i - 1]) / (fa[i] - fa[i - 1]) * (fp[i] - fp[i - 1])))


@safe
def _onset_soft_over_stiff(results: Mapping[str, pd.DataFrame]) -> float:
    """The plateau's onset at k~ = 0.001 over k~ = 10, the largest over the sigma~ where both adhere."""
    soft, stiff = _curves(results, 0.001), _curves(results, 10.0)
    ratios = [_plateau_onset(soft[s]) / _plateau_onset(stiff[s]) for s in soft if s in stiff]
    return max(ratios) if ratios else math.nan


def _coefficients(results: Mapping[str, pd.DataFrame]) -> pd.DataFrame:
    return adhesion_coefficients(finished(results, "table1"), [K, SIGMA])


def _roughness_drop(k: float) -> Reader:
    """c at the roughest sigma~ of Table 1 over c at the smoothest, at k~ (part table1)."""
    def compute(results) -> float:
        coeff = _coefficients(results)
        column = coeff[np.isclose(coeff[K], k, rtol=1e-6)].sort_values("sigma")
        return float(column["c"].iloc[-1] / column["c"].iloc[0]) if len(column) else math.nan
    return compute


def _fit_over_computed(k: float) -> Reader:
    """eq. 5.8 as `rough_brush.table_1` fits it over c, the fitted c over the computed, the farthest from 1."""
    def compute(results) -> float:
        coeff = _coefficients(results)
        column = coeff[np.isclose(coeff[K], k, rtol=1e-6) & (coeff["c"] > 0)]
        if len(column) < 2:
            return math.nan
        alpha, beta = fit_eq58(column["sigma"].to_numpy(), column["c"].to_numpy())
        ratio = (alpha / column["sigma"] - beta).to_numpy() / column["c"].to_numpy()
        return float(ratio[int(np.argmax(np.abs(ratio - 1)))])
    return compute


def identifying_row(k: float, sigma: float) -> str:
    """The quantity of the chapter-5 row used to identify at (k~, sigma~): a row computed from it names it
    (`ThesisNumber.inputs`)."""
    return f"plateau F~_A, k~ = {k:g}, sigma~ = {sigma:g}, 16 x 16 pillars"


def _divided(first: Reader, second: Reader) -> Reader:
    @safe
    def compute(results) -> float:
        return first(results) / second(results)
    return compute


def claims(plateau: Callable[[float, float, str], Reader], table_value: Callable[[str, float, str], Reader],
           held_out: Callable[[str], str]) -> list[ThesisNumber]:
    """The rows, with `rough_brush`'s readers: ``plateau(k, sigma, part)``, ``table_value(column, k, part)``
    and ``held_out(text)`` (the identification's text, which every counted row names)."""
    return [
        ThesisNumber("F~_A against F~_P at k~ = 10: 'increases with the preload ... and ultimately reaches a "
                     "plateau ... for all cases of different roughnesses': the share of F~_A's rise from F~_P = 0.1 "
                     "to 20 that comes between 10 and 20, the largest over sigma~ = 0.07, 0.5 and 2.1, 16 x 16 "
                     "pillars", "Fig. 5-3, text (L885-887, L964)", PLATEAU_RISE_SHARE, _last_rise_share, claim="<",
                     evidence=held_out(f"part {PRELOAD_PART} (F~_P = 0.1 to 20, two realisations); the threshold "
                                       f"{PLATEAU_RISE_SHARE:g} is ours (the thesis states none); a curve whose "
                                       "largest F~_A stays under 0.05 (k~ = 10, sigma~ = 2.1: 0.017) has neither "
                                       "region and is left out; 'almost linearly firstly' is not resolved: the "
                                       "preloads are a factor 3 apart and at F~_P = 0.1 the smooth brush already "
                                       "has half its plateau")),
        ThesisNumber("preload where the plateau begins (F~_A at 90 % of its largest), k~ = 0.001 over k~ = 10, the "
                     "largest over the sigma~ where both adhere: 'softer structure reaches the plateau region "
                     "earlier', 16 x 16 pillars", "Fig. 5-4, text (L905)", 1.0, _onset_soft_over_stiff, claim="<",
                     evidence=held_out(f"part {PRELOAD_PART} (F~_P = 0.1 to 20, two realisations; the onset linear "
                                       "in log F~_P between the sampled preloads, the 90 % share ours: the thesis "
                                       "states no criterion)")),
        ThesisNumber("c at the roughest over the smoothest sigma~ of Table 1 (2.9 over 0.01), k~ = 10 over k~ = 0.001, "
                     "16 x 16 pillars ('c decreases rapidly with roughness, especially for cases of large stiffness', "
                     "L913)", "Fig. 5-5, text (L913)", 1.0, _divided(_roughness_drop(10.0), _roughness_drop(0.001)),
                     claim="<", evidence=held_out("c at F~_P = 0.1 (part table1)")),
        ThesisNumber("eq. 5.8 fitted to c at k~ = 10: the fitted c over the computed, the farthest from 1 over the 13 "
                     "roughnesses, 16 x 16 pillars ('the function Eq. (5.8) describes the relation well', L931)",
                     "Fig. 5-5, text (L931)", 1.0, _fit_over_computed(10.0), OPEN,
                     held_out("'well' states no tolerance, and the reading of c decides it: at F~_P = 0.1 the fit "
                              "(least relative residuals, as Table 1's) is off by 40-60 % r.m.s. in every column, "
                              "with beta < 0; the thesis does not say where it reads c (L907-911)")),
        ThesisNumber("sigma~_c at k~ = 0.001 over k~ = 10, 16 x 16 pillars ('the transition from adhering to "
                     "non-adhering surfaces is rather sharp ... this value strongly depends on the pillar stiffness', "
                     "L933; 'this value became larger for cases of smaller stiffness', L964)",
                     "Table 1, text (L933, L964)", 1.0,
                     _divided(table_value("critical_roughness", 0.001, "table1"),
                              table_value("critical_roughness", 10.0, "table1")), OPEN,
                     held_out("at F~_P = 0.1 beta < 0 in every column: c stays above zero up to sigma~ = 3 (a few "
                              "pillars still touch), the fit of eq. 5.8 crosses no zero and no sigma~_c exists to "
                              "compare (the sigma~_c rows are n/a)")),
        ThesisNumber("plateau F~_A of the soft smooth brush (k~ = 0.001, sigma~ = 0.01) over the stiff rough one "
                     "(k~ = 1, sigma~ = 2.1), 16 x 16 pillars ('the large adhesive force exists in a very narrow "
                     "region, and it drops quickly to zero [as] roughness or stiffness becomes large', L958)",
                     "Fig. 5-7, text (L958)", 1.0, _divided(plateau(0.001, 0.01, "count"), plateau(1.0, 2.1, "count_rough")),
                     claim=">", evidence=held_out("the map's two corners the committed 16 x 16 tables hold"),
                     inputs=(identifying_row(0.001, 0.01),)),
        ThesisNumber("plateau F~_A, k~ = 0.001 over k~ = 10 at the smallest roughnesses (sigma~ = 0.01 and 0.07), "
                     "16 x 16 pillars ('the maximum adhesive force in the plateau region increased with decreasing "
                     "stiffness', L964)", "Fig. 5-6, text (L964)", 1.0,
                     _divided(plateau(0.001, 0.01, "count"), plateau(10.0, 0.07, "count")), claim=">",
                     evidence=held_out("part count holds the soft brush at sigma~ = 0.01 and the stiff at 0.07"),
                     inputs=(identifying_row(0.001, 0.01), identifying_row(10.0, 0.07))),
    ]
