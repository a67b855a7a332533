"""``brushbem sweep``, ``study``, ``figure`` and ``report``: many cases, their tables and figures."""

from __future__ import annotations

import contextlib
from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

import click

if TYPE_CHECKING:  # the command line imports what a command needs when it runs (`brushbem --help` stays light)
    pass

from brushbem.cli.common import (
    EXIT_INVALID_CONFIG,
    EXIT_NOT_CONVERGED,
    EXIT_WRITE_FAILED,
    Console,
    Table,
    _check_executor_options,
    _executor,
    _executor_options,
    _load_sweep_or_exit,
    _make_out,
    _number,
    _OutFolder,
    _reading_results,
    _sweep_errors,
)


@click.command()
@click.argument("sweep_path", metavar="SWEEP", type=click.Path(path_type=Path, dir_okay=False))
@click.option(
    "--out", "out_dir", default=None, type=_OutFolder(),
    help="Folder for sweep.json, cases/ and summary.parquet (created if absent; "
    "cases already there are not recomputed).",
)
@click.option(
    "--workers", type=click.IntRange(min=1), default=None,
    help="Local worker processes, or the workers of --dask's cluster [default: number of cores].",
)
@click.option("--dask", "use_dask", is_flag=True, help="Run on a new dask.distributed LocalCluster.")
@click.option("--scheduler", metavar="ADDRESS", default=None,
              help="Run on the dask.distributed scheduler at ADDRESS (e.g. tcp://host:8786).")
@click.option("--scheduler-file", type=click.Path(path_type=Path, dir_okay=False), default=None,
              help="Run on the dask.distributed scheduler described by this file.")
@click.option("--retry-failed", is_flag=True,
              help="Recompute cases recorded as failed (by default a rerun keeps them).")
@click.option("--dry-run", is_flag=True, help="Validate and list the cases; compute nothing.")
@click.option("--estimate", is_flag=True,
              help="Run a few sampled cases and print the expected CPU time of the whole sweep and its "
              "wall time on --workers; write nothing (--out is not needed).")
@click.option("--samples", type=click.IntRange(min=1), default=3, show_default=True,
              help="Cases that --estimate runs, spread over the sweep.")
@click.option("--quiet", is_flag=True, help="No progress output.")
def sweep(
    sweep_path: Path,
    out_dir: Path | None,
    workers: int | None,
    use_dask: bool,
    scheduler: str | None,
    scheduler_file: Path | None,
    retry_failed: bool,
    dry_run: bool,
    estimate: bool,
    samples: int,
    quiet: bool,
) -> None:
    """Run every case of the sweep in SWEEP; resume what is missing in --out."""
    from brushbem import sweep as sweep_module

    _check_executor_options(workers, use_dask, scheduler, scheduler_file)
    if out_dir is None and not (estimate or dry_run):
        raise click.UsageError("give --out DIR (only --estimate and --dry-run run without it)")
    study = _load_sweep_or_exit(sweep_path, f"invalid sweep {sweep_path}:")
    for warning in study.warnings:
        click.echo(f"warning: {warning}", err=True)
    if dry_run:
        console = Console()
        rows = [(case.case_id, str(case.realization), f"{case.seed}{'' if case.seed_applied else '*'}",
                 *(_number(case.values[key]) for key in study.keys)) for case in study.cases]
        headers = ("case", "realization", "seed", *study.keys)
        widths = [max([len(h), *(len(str(r[i])) for r in rows)]) for i, h in enumerate(headers)]
        if sum(widths) + 3 * len(widths) + 1 > console.width:
            # Too narrow for a table that shows every name whole: one line per case, key = value.
            console.print(f"{len(study.cases)} cases", highlight=False)
            for row in rows:
                values = "  ".join(f"{key} = {value}" for key, value in zip(study.keys, row[3:]))
                console.print(f"{row[0]}  realization {row[1]}  seed {row[2]}  {values}", highlight=False,
                              soft_wrap=True)
            if not all(case.seed_applied for case in study.cases):
                click.echo("* recorded only: the indenter of this case takes no seed")
            return
        table = Table(title=f"{len(study.cases)} cases")
        for column in ("case", "realization", "seed", *study.keys):
            # Case ids and the swept keys are typed by users: folded, never cut with an ellipsis.
            table.add_column(column, no_wrap=column == "case", overflow="fold",
                             min_width=max((len(c.case_id) for c in study.cases), default=4) if column == "case"
                             else None)
        for case in study.cases:
            table.add_row(case.case_id, str(case.realization),
                          f"{case.seed}{'' if case.seed_applied else '*'}",
                          *(_number(case.values[key]) for key in study.keys))
        Console().print(table)
        if not all(case.seed_applied for case in study.cases):
            click.echo("* recorded only: the indenter of this case takes no seed")
        return
    if estimate:
        _print_estimates({sweep_path.name: _estimate(study, samples, quiet)}, workers)
        return

    with _sweep_errors(out_dir), contextlib.ExitStack() as stack:
        executor = _executor(stack, workers, use_dask, scheduler, scheduler_file)
        _make_out(out_dir)
        outcome = sweep_module.run_sweep(
            study, out_dir, executor, workers=workers, retry_failed=retry_failed,
            progress=not quiet,
        )

    counts = ", ".join(f"{n} {status}" for status, n in sorted(outcome.counts.items()))
    if not quiet:
        click.echo(
            f"{len(study.cases)} cases ({counts}); computed {len(outcome.computed)}, "
            f"kept {len(outcome.skipped)}; summary in {out_dir / sweep_module.SUMMARY_FILE}"
        )
    if not outcome.complete:
        click.echo(f"warning: not every case finished ({counts})", err=True)
        raise click.exceptions.Exit(EXIT_NOT_CONVERGED)


def _estimate(study: Any, samples: int, quiet: bool) -> Any:
    from brushbem.sweep.estimate import estimate_sweep

    def report(message: str) -> None:
        if not quiet:
            click.echo(message, err=True)

    return estimate_sweep(study, samples=samples, progress=report)


def _print_estimates(estimates: dict[str, Any], workers: int | None) -> None:
    """One row per sweep (and a total): cases, sampled seconds, CPU hours, wall hours on the workers."""
    from brushbem.sweep import default_workers

    workers = workers or default_workers()
    table = Table(title=f"expected cost (wall time on {workers} workers)")
    for column in ("sweep", "cases", "sampled s (each)", "CPU h", "wall h"):
        table.add_column(column)
    total_cpu = total_error2 = total_wall = 0.0
    unknown = False
    for name, estimate in estimates.items():
        seconds = ", ".join(f"{t:.1f}" for t in estimate.seconds)
        failed = [s for s in estimate.statuses if s != "finished"]
        note = f" ({len(failed)} not finished)" if failed else ""
        error = estimate.cpu_hours_error
        spread = (f" ± {error:.2g}" if error is not None
                  else " (one sample: no spread, the error is not known; --samples 3 measures it)")
        table.add_row(name, str(estimate.cases), seconds + note, f"{estimate.cpu_hours:.3g}{spread}",
                      f"{estimate.wall_hours(workers):.3g}")
        total_cpu += estimate.cpu_hours
        unknown = unknown or error is None
        total_error2 += (error or 0.0) ** 2
        total_wall += estimate.wall_hours(workers)
    if len(estimates) > 1:
        total_spread = " (error not known: a sweep with one sample)" if unknown else f" ± {total_error2**0.5:.2g}"
        table.add_row("total", str(sum(e.cases for e in estimates.values())), "",
                      f"{total_cpu:.3g}{total_spread}", f"{total_wall:.3g}")
    Console().print(table)


#: What each study costs at its full grids, in CPU hours on one core: measured on the runs whose tables are
#: committed (`docs/reproduction/*/provenance.json`, `docs/beyond/*/provenance.json`, summed over the parts'
#: wall times on one of 2 shared cores), or "~" estimated by `brushbem study NAME --estimate` where only a
#: sampled subset was run (docs/site/studies.md, "What a full study costs").  A study not named here has not
#: been timed: its row says to estimate it.
STUDY_COSTS = {
    "punch_spring": "0.02 h",
    "sphere_spring": "0.28 h",
    "flat_brush": "4.2 h",
    "concave": "1.2 h",
    "rough_brush": "~790 h",
    "hierarchy": "~150 h a part",
    "size": "4.1 h",
    "robustness": "0.45 h",
}
_LIST_WIDTH = 80


def _figure_span(figures: Sequence[str]) -> str:
    """The thesis figures of a study in a few characters: "7-3 to 7-7", "5-2 to 5-7, Table 1", "3-5"."""
    import re

    numbered = [f for f in figures if re.fullmatch(r"\d+-\d+", f)]
    others = [f for f in figures if f not in numbered]
    span = (f"{numbered[0]} to {numbered[-1]}" if len(numbered) > 2 else ", ".join(numbered))
    return ", ".join(part for part in (span, *others) if part) or "—"


def _list_studies() -> None:
    """One line a study (name, thesis figures, parts, cost), its title and parts wrapped beneath: 80 columns."""
    import textwrap

    from brushbem import studies

    width = max(len(name) for name in studies.STUDIES) + 2
    lines = [f"{len(studies.STUDIES)} studies. cost: CPU hours at the full grids on one core, measured",
             "(~: estimated); `brushbem study NAME --estimate` prices any; --quick: minutes.", "",
             f"{'study':<{width}}{'thesis figures':<22}{'parts':>5}  cost"]
    for study in studies.STUDIES.values():
        cost = STUDY_COSTS.get(study.name, "--estimate" if study.parts else "no sweep")
        lines.append(f"{study.name:<{width}}{_figure_span(study.figures):<22}{len(study.parts):>5}  {cost}")
        text = study.title.rstrip(".") + (f". Parts: {', '.join(study.parts)}." if study.parts else ".")
        lines += textwrap.wrap(text, width=_LIST_WIDTH, initial_indent="    ", subsequent_indent="    ",
                               break_on_hyphens=False)
    for line in lines:
        click.echo(line)


@click.command()
@click.argument("name", required=False)
@click.option(
    "--out", "out_dir", type=_OutFolder(), default=None,
    help="Folder for study.json, one sweep folder per part and figures/ (created if absent; "
    "cases already there are not recomputed).",
)
@click.option("--quick", is_flag=True, help="Run the coarse sweep files (a quick check, not the full grids).")
@click.option("--sampled", is_flag=True,
              help="Run, for the parts that ship one, the sampled subset of the full sweep (the parameter "
                   "points that carry the thesis's stated numbers, at its grid).")
@click.option("--sampled-set", "sampled_set", default=None, metavar="SET",
              help="Run the named sampled set (`<study>.<part>.<SET>.sampled.toml`) of the parts that ship it, "
                   "into its own --out; `brushbem export-tables` merges it with the study's other folders.")
@click.option("--parts", "part_names", default=None, metavar="P1,P2,...",
              help="Run only these parts of the study (comma-separated; `--list` names them); the parts "
                   "already run in --out are kept.")
@click.option("--skip-recorded", "recorded_root", default=None, metavar="TABLES",
              type=click.Path(path_type=Path, file_okay=False, exists=True),
              help="Leave out the cases finished in the study's tables under TABLES (e.g. docs/reproduction: "
                   "a run of an earlier session or machine); `brushbem export-tables --update` merges the rest in.")
@click.option("--list", "list_studies", is_flag=True, help="List the studies and exit.")
@click.option("--estimate", is_flag=True,
              help="Run a few sampled cases of every part and print the expected CPU time of the study "
              "and its wall time on --workers; write nothing (--out is not needed).")
@click.option("--samples", type=click.IntRange(min=1), default=3, show_default=True,
              help="Cases that --estimate runs per part, spread over it.")
@_executor_options
@click.option("--quiet", is_flag=True, help="No progress output.")
def study(
    name: str | None,
    out_dir: Path | None,
    quick: bool,
    sampled: bool,
    sampled_set: str | None,
    part_names: str | None,
    recorded_root: Path | None,
    list_studies: bool,
    estimate: bool,
    samples: int,
    workers: int | None,
    use_dask: bool,
    scheduler: str | None,
    scheduler_file: Path | None,
    retry_failed: bool,
    quiet: bool,
) -> None:
    """Run the thesis study NAME into --out and draw its figures (``--list``: the studies)."""
    from brushbem import studies
    from brushbem import sweep as sweep_module
    from brushbem.reproduction import recorded_cases

    if list_studies:
        _list_studies()
        return
    if name is None or (out_dir is None and not estimate):
        raise click.UsageError("give a study NAME and --out DIR (or --list, or --estimate)")
    try:
        found = studies.get_study(name)
    except studies.StudyError as error:
        click.echo(str(error), err=True)
        raise click.exceptions.Exit(EXIT_INVALID_CONFIG) from None
    parts = found.parts
    if part_names is not None:
        parts = tuple(part.strip() for part in part_names.split(",") if part.strip())
        unknown = [part for part in parts if part not in found.parts]
        if unknown or not parts:
            click.echo(f"--parts: study {name} has no part(s) {', '.join(unknown) or '(none given)'}; "
                       f"its parts: {', '.join(found.parts)}", err=True)
            raise click.exceptions.Exit(EXIT_INVALID_CONFIG)
    if sampled_set is not None:
        if quick:
            raise click.UsageError("--sampled-set is a subset of the full grid; it does not go with --quick")
        sets = studies.sampled_sets(name)
        if sampled_set not in sets or any(part not in sets[sampled_set] for part in (
                parts if part_names is not None else ())):
            shipped = "; ".join(f"{s}: parts {', '.join(p)}" for s, p in sets.items()) or "none"
            click.echo(f"--sampled-set: study {name} ships no set {sampled_set!r} for "
                       f"{'these parts' if sampled_set in sets else 'any part'}; its sets: {shipped}", err=True)
            raise click.exceptions.Exit(EXIT_INVALID_CONFIG)
        if part_names is None:
            parts = sets[sampled_set]
    if estimate:
        estimates = {}
        for part in [part for part in found.parts if part in parts]:
            path = studies.sweep_file(name, part, quick, sampled, sampled_set)
            loaded = _load_sweep_or_exit(path, f"invalid sweep file {path.name}:")
            estimates[part] = _estimate(loaded, samples, quiet)
        _print_estimates(estimates, workers)
        return
    _check_executor_options(workers, use_dask, scheduler, scheduler_file)

    with _sweep_errors(out_dir), contextlib.ExitStack() as stack:
        executor = _executor(stack, workers, use_dask, scheduler, scheduler_file)
        _make_out(out_dir)
        try:
            outcome = studies.run_study(
                name, out_dir, quick=quick, executor=executor, workers=workers, sampled=sampled,
                parts=None if part_names is None else parts, sampled_set=sampled_set,
                retry_failed=retry_failed, progress=not quiet,
                recorded=None if recorded_root is None else recorded_cases(recorded_root, name),
            )
        except sweep_module.SweepFolderError:
            raise
        except sweep_module.SweepError as error:
            click.echo(f"invalid sweep file of study {name}:", err=True)
            for problem in error.problems:
                click.echo(f"  {problem}", err=True)
            raise click.exceptions.Exit(EXIT_INVALID_CONFIG) from None
        except studies.StudyError as error:
            click.echo(str(error), err=True)
            raise click.exceptions.Exit(EXIT_INVALID_CONFIG) from None

    incomplete = []
    for part, run_ in outcome.parts.items():
        counts = ", ".join(f"{n} {status}" for status, n in sorted(run_.counts.items()))
        if not quiet:
            click.echo(f"{part}: {counts}; computed {len(run_.computed)}, kept {len(run_.skipped)}")
        if not run_.complete:
            incomplete.append(f"{part} ({counts})")
    if outcome.draw_error:
        # The first line: the exception (its traceback is in StudyRun.draw_error for the API).
        click.echo(f"warning: drawing the figures failed: {outcome.draw_error.splitlines()[0]}", err=True)
    elif not quiet:
        click.echo(f"{len(outcome.figures)} figures in {out_dir / 'figures'}")
    if incomplete:
        click.echo(f"warning: not every case finished: {'; '.join(incomplete)}", err=True)
    if incomplete or outcome.draw_error:
        raise click.exceptions.Exit(EXIT_NOT_CONVERGED)


@click.command()
@click.argument("out_dir", metavar="DIR", type=click.Path(path_type=Path, file_okay=False, exists=True))
def figure(out_dir: Path) -> None:
    """Redraw the figures of the study or sweep in DIR from its stored results (no computing)."""
    from brushbem.report.sweeps import draw_figures

    with _reading_results():
        paths = draw_figures(out_dir)
    for path in paths:
        click.echo(str(path))


@click.command()
@click.argument("out_dir", metavar="DIR", type=click.Path(path_type=Path, file_okay=False, exists=True))
@click.option("--redraw", is_flag=True,
              help="Redraw the figures even if DIR/figures has some (a run folder: the curve from result.nc).")
def report(out_dir: Path, redraw: bool) -> None:
    """Write DIR/report.html: figures, summary table, thesis numbers, provenance (one file).

    DIR is a study or sweep folder, or one run's folder (`brushbem run --out
    DIR`): then the report shows its pull-off curve, the snapshots, the
    summary with units, the comparison with the closed forms and the
    provenance.
    """
    from brushbem.report.run import RunReportError, is_run_folder, not_a_results_folder, write_run_report

    if not is_run_folder(out_dir) and not (out_dir / "study.json").is_file() and not (out_dir / "sweep.json").is_file():
        click.echo(not_a_results_folder(out_dir), err=True)
        raise click.exceptions.Exit(EXIT_INVALID_CONFIG)
    if is_run_folder(out_dir):
        try:
            path = write_run_report(out_dir, redraw=redraw)
        except RunReportError as error:
            click.echo(str(error), err=True)
            raise click.exceptions.Exit(EXIT_INVALID_CONFIG) from None
        except OSError as exc:
            click.echo(f"cannot write {exc.filename or out_dir / 'report.html'} ({exc.strerror or exc})", err=True)
            raise click.exceptions.Exit(EXIT_WRITE_FAILED) from None
        click.echo(str(path))
        return
    from brushbem.report.sweeps import write_report

    with _reading_results():
        path = write_report(out_dir, redraw=redraw)
    click.echo(str(path))
