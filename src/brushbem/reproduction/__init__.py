"""The thesis's numbers beside ours, from committed tables.

A study run folder (``brushbem study NAME --out DIR``) holds NetCDF case files
and parquet summaries: too large to commit, and tied to one machine.
`export_tables` writes what the comparison needs as compact text instead:

    TABLES/<study>/<part>.csv        one row per case: swept values, seed,
                                     status, the summary numbers (full precision)
    TABLES/<study>/provenance.json   brushbem version, commit, quick or full,
                                     per part: sweep file, cases, seeds, grid,
                                     wall time

`compare` computes every `brushbem.studies.ThesisNumber` of every study found
there from those tables alone, with the standard error over realisations
where a part has several, and `render` writes the comparison as Markdown
(``docs/thesis-comparison.md``), followed by the hand-written notes of
``TABLES/notes.md``.  The document is a function of the tables: the same
tables give the same bytes, which a test checks for the committed ones.

    brushbem export-tables DIR --to docs/reproduction
    brushbem compare-thesis docs/reproduction --out docs/thesis-comparison.md [--check]

The package's modules:

- `tables`: exporting, loading and the recorded cases of the compact tables;
- `comparison`: the numbers from the tables, with standard errors over realisations (`compare`);
- `document`: the comparison document, the notes that explain deviations, deviations;
- `figures`: the full-grid (not quick) studies' figures drawn from the tables;
- `rows`: planning and recomputing one row (`plan_row`, `reproduce_row`, rivals).
"""

from __future__ import annotations

from brushbem.reproduction.comparison import (
    ComparisonRow,
    compare,
)
from brushbem.reproduction.comparison import _compute as _compute
from brushbem.reproduction.comparison import _counted_realizations as _counted_realizations
from brushbem.reproduction.comparison import _of_realizations as _of_realizations
from brushbem.reproduction.comparison import _plain as _plain
from brushbem.reproduction.comparison import _Points as _Points
from brushbem.reproduction.comparison import _points as _points
from brushbem.reproduction.comparison import _realizations as _realizations
from brushbem.reproduction.comparison import _same as _same
from brushbem.reproduction.comparison import _standard_error as _standard_error
from brushbem.reproduction.comparison import _swept_keys as _swept_keys
from brushbem.reproduction.document import (
    EXPLAIN_ABOVE,
    THESIS_GRIDS,
    comparison_document,
    deviation_of,
    explaining_sections,
    identifications,
    note_anchor,
    notes_sections,
    render,
)
from brushbem.reproduction.figures import draw_table_figures
from brushbem.reproduction.rows import (
    RIVAL_STEPS,
    RIVALS,
    ReproduceError,
    RowPlan,
    plan_row,
    reproduce_row,
)
from brushbem.reproduction.rows import _file_with as _file_with
from brushbem.reproduction.rows import _find_number as _find_number
from brushbem.reproduction.rows import _rivals as _rivals
from brushbem.reproduction.tables import (
    NOTES_FILE,
    PROVENANCE_FILE,
    case_hash,
    export_tables,
    load_tables,
    recorded_cases,
)

__all__ = [
    "EXPLAIN_ABOVE",
    "NOTES_FILE",
    "PROVENANCE_FILE",
    "RIVALS",
    "RIVAL_STEPS",
    "THESIS_GRIDS",
    "ComparisonRow",
    "ReproduceError",
    "RowPlan",
    "case_hash",
    "compare",
    "comparison_document",
    "deviation_of",
    "draw_table_figures",
    "explaining_sections",
    "identifications",
    "export_tables",
    "load_tables",
    "note_anchor",
    "notes_sections",
    "plan_row",
    "recorded_cases",
    "render",
    "reproduce_row",
]
