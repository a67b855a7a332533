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

from brushbem.studies._ch5_7 import K, SIGMA, adhesion_coefficients, finished, fit_eq58
from brushbem.studies._common import safe
from brushbem.studies.base import ThesisNumber
from brushbem.studies.verdicts import OPEN

Reader = Callable[[Mapping[str, pd.DataFrame]], float]

#: Why a claim on F~_A against the preload has no counted value: the identified 16 x 16 brush is
#: committed at one preload per point.
NO_PRELOAD_SWEEP = ("no committed table at chapter 5's identification (16 x 16 pillars) samples F~_A over the "
                    "preload: table1 holds F~_P = 0.1 and count the plateau preload; the preload sweep of Fig. 5-3 "
                    "and 5-4 is committed at 32 x 32 only (part preload, outside the counts)")


def _not_in_the_tables(results: Mapping[str, pd.DataFrame]) -> float:
    return math.nan


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
        ThesisNumber("F~_A against F~_P: 'increases with the preload almost linearly firstly, and ultimately reaches "
                     "a plateau ... for all cases of different roughnesses', 16 x 16 pillars", "Fig. 5-3, text "
                     "(L885-887, L964)", 1.0, _not_in_the_tables, OPEN, held_out(NO_PRELOAD_SWEEP)),
        ThesisNumber("preload where the plateau begins, softer over stiffer: 'softer structure reaches the plateau "
                     "region earlier', 16 x 16 pillars", "Fig. 5-4, text (L905)", 1.0, _not_in_the_tables, OPEN,
                     held_out(NO_PRELOAD_SWEEP)),
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
                     claim=">", evidence=held_out("the map's two corners the committed 16 x 16 tables hold")),
        ThesisNumber("plateau F~_A, k~ = 0.001 over k~ = 10 at the smallest roughnesses (sigma~ = 0.01 and 0.07), "
                     "16 x 16 pillars ('the maximum adhesive force in the plateau region increased with decreasing "
                     "stiffness', L964)", "Fig. 5-6, text (L964)", 1.0,
                     _divided(plateau(0.001, 0.01, "count"), plateau(10.0, 0.07, "count")), claim=">",
                     evidence=held_out("part count holds the soft brush at sigma~ = 0.01 and the stiff at 0.07")),
    ]
