"""The thesis's studies (chapters 2-7), each reproducible by one command.

A study is a named set of *parts*; each part is an ordinary sweep file shipped
in ``brushbem/studies/sweeps/`` (``<study>.<part>.toml`` and its coarse twin
``<study>.<part>.quick.toml``) that users can copy and edit, run with
`brushbem.sweep.run_sweep` into ``DIR/<part>/``.  The study then draws its
figures from the stored results (``DIR/figures/*.png``), in the thesis's axes,
scales and normalisations, with its closed-form lines and the numbers the
thesis states marked.

Every thesis study module in this package defines ``STUDY = Study(...)``
(`brushbem.studies.base`); `brushbem.studies.beyond` defines the
studies beyond the thesis (tip shapes, grading, tilt, viscoelastic pillars,
the design's robustness), `brushbem.studies.size` the pillar count.
The registry `STUDIES` lists them explicitly, by name.

    brushbem study NAME --out DIR [--quick]
    brushbem figure DIR          # redraw from stored results
    brushbem report DIR          # one self-contained HTML file
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path
from typing import Any

from brushbem.studies import (
    _framework,
    beyond,
    concave,
    flat_brush,
    hierarchy,
    nested_vs_convolution,
    punch_spring,
    rough_brush,
    size,
    sphere_spring,
)
from brushbem.studies._framework import (
    STUDY_FILE,
    StudyError,
    StudyRun,
    load_results,
    read_study_record,
)
from brushbem.studies.base import (
    SWEEPS_DIR,
    Study,
    ThesisNumber,
    finished,
    sampled_sets,
    sweep_file,
)

__all__ = [
    "STUDIES",
    "STUDY_FILE",
    "SWEEPS_DIR",
    "Study",
    "StudyError",
    "StudyRun",
    "ThesisNumber",
    "draw_study",
    "finished",
    "get_study",
    "load_results",
    "run_study",
    "sampled_sets",
    "sweep_file",
]

#: The studies by name, registered here and nowhere else.
STUDIES: dict[str, Study] = {
    study.name: study
    for study in sorted(
        (
            punch_spring.STUDY,
            sphere_spring.STUDY,
            nested_vs_convolution.STUDY,
            flat_brush.STUDY,
            rough_brush.STUDY,
            hierarchy.STUDY,
            concave.STUDY,
            beyond.TIP_SHAPE,
            beyond.GRADING,
            beyond.TILT,
            beyond.VISCOELASTIC,
            beyond.ROBUSTNESS,
            size.SIZE,
        ),
        key=lambda study: study.name,
    )
}


def get_study(name: str) -> Study:
    """The registered study called ``name``.

    Raises
    ------
    StudyError
        If there is none; the message lists the known names.
    """
    try:
        return STUDIES[name]
    except KeyError:
        known = ", ".join(STUDIES) or "(none registered)"
        raise StudyError(f"unknown study {name!r}; known studies: {known}") from None


def run_study(name: str, out_dir: str | Path, quick: bool = False, executor: Any = None, *,
              sampled: bool = False, parts: Sequence[str] | None = None, sampled_set: str | None = None,
              **options: Any) -> StudyRun:
    """Run every part of the study ``name`` into ``out_dir`` (resuming), then draw it.

    ``sampled`` runs a part's ``.sampled.toml`` subset where one is shipped
    (`brushbem.studies.base.sweep_file`); ``sampled_set`` runs a named sampled
    set instead (`brushbem.studies.base.sampled_sets`), by default on every
    part that ships it, into its own folder (``brushbem.export_tables`` merges
    the folders of one study).  ``parts`` runs only those parts (in
    the study's order); the parts run before in ``out_dir`` are kept.  The
    other options are those of `brushbem.studies._framework.run_study`
    (``workers``, ``retry_failed``, ``progress``, ``draw``).

    Raises
    ------
    StudyError
        An unknown study, a part it does not have (the message lists its
        parts), or a sampled set it does not ship for a part asked for.
    """
    study = get_study(name)
    if sampled_set is not None:
        sets = sampled_sets(study.name)
        if sampled_set not in sets:
            raise StudyError(f"study {name!r} ships no sampled set {sampled_set!r}; its sets: "
                             + (", ".join(f"{s} (parts {', '.join(p)})" for s, p in sets.items()) or "(none)"))
        lacking = [part for part in parts or () if part not in sets[sampled_set]]
        if lacking:
            raise StudyError(f"study {name!r}: part(s) {', '.join(map(repr, lacking))} have no sampled set "
                             f"{sampled_set!r}; the parts that have it: {', '.join(sets[sampled_set])}")
        if quick:
            raise StudyError("a sampled set is of the full grid: it cannot be run --quick")
        parts = parts or sets[sampled_set]
    if parts is not None:
        unknown = [part for part in parts if part not in study.parts]
        if unknown or not parts:
            raise StudyError(f"study {name!r} has no part(s) {', '.join(map(repr, unknown)) or '(none given)'}; "
                             f"its parts: {', '.join(study.parts)}")
    chosen = [part for part in study.parts if parts is None or part in parts]
    files = {part: sweep_file(study.name, part, quick, sampled, sampled_set) for part in chosen}
    return _framework.run_study(study, out_dir, quick, executor, files=files, **options)


def draw_study(out_dir: str | Path) -> list[Path]:
    """Redraw the figures of the study run in ``out_dir`` from its stored results (nothing is computed)."""
    return _framework.draw_study(get_study(read_study_record(out_dir)["study"]), out_dir)
