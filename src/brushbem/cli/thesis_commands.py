"""``brushbem export-tables``, ``reproduce`` and ``compare-thesis``: the thesis comparison."""

from __future__ import annotations

import math
from pathlib import Path
from typing import TYPE_CHECKING

import click

if TYPE_CHECKING:  # the command line imports what a command needs when it runs (`brushbem --help` stays light)
    pass

from brushbem.cli.common import (
    EXIT_INVALID_CONFIG,
    EXIT_NOT_CONVERGED,
    _OutFolder,
    _sweep_errors,
)


@click.command("export-tables")
@click.argument("study_dirs", metavar="DIR...", nargs=-1, required=True,
                type=click.Path(path_type=Path, file_okay=False, exists=True))
@click.option("--to", "tables_root", required=True, type=click.Path(path_type=Path, file_okay=False),
              help="Folder of the comparison tables (e.g. docs/reproduction); DIR's study goes to a subfolder.")
@click.option("--update", is_flag=True,
              help="Merge DIR into the study's tables already under --to instead of replacing them: the cases "
                   "they record stay (their run folder need not be here), DIR adds what it finished.")
def export_tables(study_dirs: tuple[Path, ...], tables_root: Path, update: bool) -> None:
    """Write the compact tables (CSV per part, provenance.json) of the study run folder DIR.

    Several folders of one study (its sampled run and a `--sampled-set` run)
    merge into one table per part; with --update, into the tables recorded
    under --to (a run of an earlier session or another machine).
    """
    from brushbem import studies
    from brushbem.reproduction import export_tables as export

    try:
        folder = export(list(study_dirs), tables_root, update=update)
    except studies.StudyError as error:
        click.echo(str(error), err=True)
        raise click.exceptions.Exit(EXIT_INVALID_CONFIG) from None
    click.echo(str(folder))


@click.command()
@click.argument("study_name", metavar="STUDY")
@click.argument("quantity")
@click.option("--out", "out_dir", type=_OutFolder(), default=None,
              help="Folder for the row's cases, one sweep folder per part (resumed if there).")
@click.option("--tables", "tables_root", type=click.Path(path_type=Path, file_okay=False),
              default=Path("docs/reproduction"), show_default=True,
              help="The committed tables the row comes from.")
@click.option("--realizations", type=click.IntRange(min=1), default=None,
              help="Run only the first R seeds and check the number they give (default: every seed the tables "
              "have finished).")
@click.option("--dry-run", is_flag=True, help="Print the cases the row reads and their recorded time; run nothing.")
@click.option("--rivals", type=click.IntRange(min=0), default=2, show_default=True,
              help="Also run this many runners-up: points the number would read if their results changed by "
              "up to 2 % (for a maximum, the next-largest).")
@click.option("--workers", type=click.IntRange(min=1), default=None, help="Local worker processes.")
@click.option("--quiet", is_flag=True, help="No progress output.")
def reproduce(study_name: str, quantity: str, out_dir: Path | None, tables_root: Path, realizations: int | None,
              dry_run: bool, rivals: int, workers: int | None, quiet: bool) -> None:
    """Recompute one row of the thesis comparison: only the cases its number reads.

    QUANTITY is the row's quantity as printed (or a part of it that names one
    row).  The cases are the shipped sweep's (same configurations and seeds as
    the committed tables), with the runners-up that could change the number
    (so a maximum's position is checked against its neighbours, not only
    recomputed at itself).  The recomputed number must equal the committed
    one (exit status 1 if not); with --realizations R, the one the tables'
    first R seeds give (a check in minutes of a row that reads ten seeds).
    """
    from brushbem.reproduction import ReproduceError, plan_row, reproduce_row

    if out_dir is None and not dry_run:
        raise click.UsageError("give --out DIR (or --dry-run)")
    try:
        plan = plan_row(tables_root, study_name, quantity, realizations, rivals)
    except ReproduceError as error:
        click.echo(str(error), err=True)
        raise click.exceptions.Exit(EXIT_INVALID_CONFIG) from None
    click.echo(f"{plan.study}: {plan.quantity}")
    for part, points in plan.points.items():
        click.echo(f"  part {part} ({plan.sweep_files[part].name}): {len(points)} point(s)")
        for point in points:
            rival = " (runner-up: read if its results changed)" if point in plan.rivals.get(part, []) else ""
            click.echo("    " + ", ".join(f"{key} = {value}" for key, value in point.items()) + rival)
    click.echo(f"  {plan.cases} case(s), {plan.realizations} seed(s); recorded wall time {plan.recorded_seconds:.0f} s")
    if dry_run:
        return
    with _sweep_errors(out_dir):
        try:
            value = reproduce_row(plan, out_dir, workers=workers, progress=not quiet)
        except ReproduceError as error:
            click.echo(str(error), err=True)
            raise click.exceptions.Exit(EXIT_NOT_CONVERGED) from None
    seeds = "" if _same_number(plan.committed, plan.every_seed) else (
        f" (its first {plan.realizations} seed(s); all seeds: {plan.every_seed:.10g})")
    click.echo(f"committed {plan.committed:.10g}{seeds}, recomputed {value:.10g}")
    if not _same_number(value, plan.committed):
        click.echo("the recomputed number differs from the committed one", err=True)
        raise click.exceptions.Exit(1)


def _same_number(a: float, b: float) -> bool:
    """Equal to the digits a rerun of the same cases reproduces: the solves' tolerance, 1e-8.

    The solver is deterministic, but a change of its arithmetic that leaves the answer alone (a
    transform's period, a start vector) moves the iterates of a CG solve to 1e-8 and a number by up to
    a few 1e-9 (the punch's w~ at k~ = 0.3 moved by 2.7e-9 when the event path's transforms and start
    vectors changed).
    """
    return math.isclose(a, b, rel_tol=1e-8, abs_tol=1e-15)


@click.command("compare-thesis")
@click.argument("tables_root", metavar="TABLES", type=click.Path(path_type=Path, file_okay=False, exists=True))
@click.option("--out", "out_file", type=click.Path(path_type=Path, dir_okay=False), default=None,
              help="Write the document here (default: standard output).")
@click.option("--check", is_flag=True, help="Exit 1 if --out differs from what TABLES give (write nothing).")
@click.option("--figures", "figures_root", type=click.Path(path_type=Path, file_okay=False), default=None,
              help="Also draw the figures the tables determine into DIR/<study>/ and link them in the document "
              "(with --check: only link the figures already there).")
def compare_thesis(tables_root: Path, out_file: Path | None, check: bool, figures_root: Path | None) -> None:
    """The thesis's numbers beside ours, computed from the tables in TABLES (Markdown)."""
    import os

    from brushbem.io import atomic_path
    from brushbem.reproduction import comparison_document, draw_table_figures

    links: dict[str, list[str]] = {}
    if figures_root is not None:
        if check:
            drawn = {folder.name: sorted(folder.glob("*.png")) for folder in sorted(figures_root.glob("*"))
                     if folder.is_dir()}
        else:
            drawn = draw_table_figures(tables_root, figures_root)
        base = (out_file.parent if out_file is not None else Path.cwd()).resolve()
        links = {name: [Path(os.path.relpath(Path(p).resolve(), base)).as_posix() for p in sorted(paths)]
                 for name, paths in drawn.items()}
    document = comparison_document(tables_root, links)
    if check:
        if out_file is None:
            raise click.UsageError("--check needs --out FILE")
        current = out_file.read_text(encoding="utf-8") if out_file.is_file() else ""
        if current != document:
            click.echo(f"{out_file} is not what {tables_root} give: run brushbem compare-thesis "
                       f"{tables_root} --out {out_file}", err=True)
            raise click.exceptions.Exit(1)
        return
    if out_file is None:
        click.echo(document, nl=False)
        return
    with atomic_path(out_file) as temporary:
        Path(temporary).write_text(document, encoding="utf-8")
    click.echo(str(out_file))
