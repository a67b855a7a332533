"""The full-grid (not quick) studies' figures, drawn from the committed tables."""

from __future__ import annotations

from pathlib import Path

from brushbem.reproduction.tables import PROVENANCE_FILE, load_tables

__all__ = ["draw_table_figures"]


def draw_table_figures(tables_root: str | Path, figures_root: str | Path) -> dict[str, list[Path]]:
    """Draw, for every full-grid (not quick) study in ``tables_root`` with ``draw_tables``, its figures from the tables.

    The figures go to ``figures_root/<study>/``; they carry the thesis's
    axes, normalisations and closed-form lines, and are drawn from the
    same tables as the comparison rows.

    Returns
    -------
    dict
        Study name -> the figures written.
    """
    from brushbem.studies import STUDIES

    drawn: dict[str, list[Path]] = {}
    for folder in sorted(Path(tables_root).iterdir()):
        study = STUDIES.get(folder.name)
        if study is None or study.draw_tables is None or not (folder / PROVENANCE_FILE).is_file():
            continue
        provenance, tables = load_tables(folder)
        if provenance.get("quick"):
            continue  # quick grids test the machinery: no figure beside the thesis's
        drawn[study.name] = study.draw_tables(tables, Path(figures_root) / study.name)
    return drawn
