"""Running a study into a folder, and redrawing its figures from what is stored.

Layout of ``run_study(name, DIR)``::

    DIR/study.json            study name, quick flag, parts, brushbem version
    DIR/<part>/               one sweep per part (`brushbem.sweep.run_sweep`)
    DIR/figures/*.png         drawn by the study's ``draw``

Running again computes only the cases still missing (the sweeps resume), then
redraws.  A folder holds one study: running another study (or the quick
sweeps into a folder of the full ones, or the reverse) into it is refused.
`draw_study` redraws from the stored results without computing.
"""

from __future__ import annotations

import dataclasses
import json
from collections.abc import Collection, Mapping
from concurrent.futures import Executor
from pathlib import Path
from typing import TYPE_CHECKING, Any

from brushbem import __version__

if TYPE_CHECKING:
    import pandas as pd

    from brushbem.studies.base import Study
    from brushbem.sweep import SweepRun

__all__ = [
    "FIGURES_DIR",
    "STUDY_FILE",
    "StudyError",
    "StudyRun",
    "draw_study",
    "load_results",
    "run_study",
]

#: The record of a study run, in its output folder.
STUDY_FILE = "study.json"
#: Where figures are drawn, inside a study's (or a sweep's) output folder.
FIGURES_DIR = "figures"


class StudyError(LookupError):
    """An unknown study, or a folder that holds no study run."""


@dataclasses.dataclass(frozen=True)
class StudyRun:
    """What one call of `run_study` did.

    Attributes
    ----------
    study : str
    out_dir : Path
    parts : dict
        Part name -> the `brushbem.sweep.SweepRun` of its sweep.
    figures : list of Path
        The figures drawn.
    draw_error : str
        Empty, or the exception that stopped the drawing (the results stay).
    """

    study: str
    out_dir: Path
    parts: dict[str, SweepRun]
    figures: list[Path]
    draw_error: str = ""

    @property
    def complete(self) -> bool:
        """Every case of every part finished (converged) and the figures were drawn."""
        return all(run.complete for run in self.parts.values()) and not self.draw_error


def _write_json(path: Path, value: Any) -> None:
    from brushbem.io import atomic_path

    with atomic_path(path) as temporary:
        temporary.write_text(json.dumps(value, indent=1) + "\n", encoding="utf-8")


def read_study_record(out_dir: str | Path) -> dict[str, Any]:
    """The ``study.json`` of a study run folder.

    Raises
    ------
    StudyError
        If the folder holds no ``study.json``, or one that cannot be read.
    """
    path = Path(out_dir) / STUDY_FILE
    if not path.is_file():
        raise StudyError(f"{out_dir} holds no {STUDY_FILE}: not a study run folder")
    try:
        record = json.loads(path.read_text(encoding="utf-8"))
    except (OSError, UnicodeDecodeError, ValueError) as exc:
        raise StudyError(f"{path} cannot be read as a study record ({type(exc).__name__}: {exc})") from None
    if not (isinstance(record, dict) and isinstance(record.get("study"), str)):
        raise StudyError(f"{path} is not a study record (no study name)")
    return record


def load_results(out_dir: str | Path, parts: tuple[str, ...] | None = None) -> dict[str, pd.DataFrame]:
    """Part name -> summary DataFrame of a study run folder, for the study's ``draw``.

    Each summary gets a ``case_file`` column (the path of the case's NetCDF
    file, for curves and snapshots; it may not exist for a missing case).  A
    part never started is an empty DataFrame with that column and ``status``.
    """
    import pandas as pd

    from brushbem.sweep import CASES_DIR, SWEEP_FILE, load_summary

    out_dir = Path(out_dir)
    if parts is None:
        parts = tuple(read_study_record(out_dir)["parts"])
    results: dict[str, pd.DataFrame] = {}
    for part in parts:
        folder = out_dir / part
        if not (folder / SWEEP_FILE).is_file():
            results[part] = pd.DataFrame(columns=["case_id", "status", "case_file"])
            continue
        frame = load_summary(folder)
        frame["case_file"] = [str(folder / CASES_DIR / f"{case_id}.nc") for case_id in frame["case_id"]]
        results[part] = frame
    return results


def draw_study(study: Study, out_dir: str | Path) -> list[Path]:
    """Redraw the figures of ``study`` from the results stored in ``out_dir`` (nothing is computed).

    Returns
    -------
    list of Path
        The figures written, in ``out_dir/figures/``.
    """
    out_dir = Path(out_dir)
    record = read_study_record(out_dir)
    results = load_results(out_dir, tuple(record.get("parts", study.parts)))
    figures_dir = out_dir / FIGURES_DIR
    figures_dir.mkdir(parents=True, exist_ok=True)
    return [Path(path) for path in (study.draw(results, figures_dir) or [])]


def run_study(
    study: Study,
    out_dir: str | Path,
    quick: bool = False,
    executor: Executor | Any | None = None,
    *,
    workers: int | None = None,
    retry_failed: bool = False,
    progress: bool = False,
    draw: bool = True,
    files: Mapping[str, str | Path] | None = None,
    recorded: Mapping[str, Collection[str]] | None = None,
) -> StudyRun:
    """Run every part of a study into ``out_dir`` (resuming what is there), then draw it.

    Parameters
    ----------
    study : Study
        The study (`brushbem.studies.get_study` finds one by name).
    out_dir : path
        Created if absent; part ``p`` runs into ``out_dir/p``.
    quick : bool
        Run the coarse ``.quick.toml`` sweep files (minutes instead of hours).
    executor, workers, retry_failed, progress
        As for `brushbem.sweep.run_sweep`.
    files : mapping, optional
        Part -> sweep file; by default the shipped files
        (`brushbem.studies.base.sweep_file`) of every part.  Only these parts
        run; the parts an earlier run recorded in ``out_dir`` stay recorded.
    recorded : mapping, optional
        Part -> the case hashes finished in the tables of an earlier run
        (`brushbem.reproduction.recorded_cases`): not computed again
        (`brushbem.sweep.run_sweep`).
    draw : bool
        Draw the figures afterwards (from whatever finished).  An exception of
        the study's ``draw`` is recorded in `StudyRun.draw_error`, not raised:
        the computed results are never lost to a plotting bug.

    Raises
    ------
    StudyError
        Unknown study, a sweep file of a part is missing, or ``out_dir``
        holds another study (or the same one with the other ``quick``).
    brushbem.sweep.SweepError
        A part's sweep file is invalid.
    brushbem.sweep.SweepFolderError
        A part's folder holds a different sweep.
    """
    import sys
    import traceback

    from brushbem.studies.base import sweep_file
    from brushbem.sweep import run_sweep

    out_dir = Path(out_dir)
    if files is None:
        files = {part: sweep_file(study.name, part, quick) for part in study.parts}
    absent = [str(path) for path in files.values() if not Path(path).is_file()]
    if absent:
        raise StudyError(f"study {study.name!r}: missing sweep file(s): {', '.join(absent)}")
    out_dir.mkdir(parents=True, exist_ok=True)
    previous = None
    if (out_dir / STUDY_FILE).exists():
        try:
            previous = read_study_record(out_dir)
        except StudyError:
            previous = None  # unreadable: each part's sweep.json still guards its folder
        if previous is not None and (previous["study"], bool(previous.get("quick"))) != (study.name, bool(quick)):
            raise StudyError(
                f"{out_dir} holds study {previous['study']!r} (quick: {bool(previous.get('quick'))}), "
                f"not {study.name!r} (quick: {bool(quick)}): run it into a new --out folder")
    for stale in out_dir.glob(f".{STUDY_FILE}.*.tmp"):  # of a driver killed while writing
        stale.unlink(missing_ok=True)
    # A run of some parts keeps the parts an earlier run recorded (and their sweep files).
    run_before = dict(previous.get("sweep_files", {})) if previous is not None else {}
    sweep_files = {**{part: str(path) for part, path in run_before.items() if part in study.parts},
                   **{part: str(path) for part, path in files.items()}}
    _write_json(out_dir / STUDY_FILE, {
        "study": study.name,
        "title": study.title,
        "figures": list(study.figures),
        "quick": bool(quick),
        "parts": [part for part in study.parts if part in sweep_files],
        "sweep_files": {part: sweep_files[part] for part in study.parts if part in sweep_files},
        "brushbem_version": __version__,
    })
    runs: dict[str, SweepRun] = {}
    for number, (part, path) in enumerate(files.items(), start=1):
        if progress:
            # Which part runs: the sweep's own progress below it counts that part's cases.
            print(f"study {study.name}: part {number} of {len(files)}, {part!r} ({Path(path).name})",
                  file=sys.stderr, flush=True)
        runs[part] = run_sweep(path, out_dir / part, executor, workers=workers,
                               retry_failed=retry_failed, progress=progress,
                               recorded=(recorded or {}).get(part, ()))
    figures: list[Path] = []
    draw_error = ""
    if draw:
        try:
            figures = draw_study(study, out_dir)
        except Exception as exc:  # noqa: BLE001 - reported, not raised
            draw_error = f"{type(exc).__name__}: {exc}\n{traceback.format_exc()}"
    return StudyRun(study=study.name, out_dir=out_dir, parts=runs, figures=figures, draw_error=draw_error)
