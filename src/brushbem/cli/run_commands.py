"""``brushbem run``, ``init`` and ``validate``: one pull-off from a configuration file."""

from __future__ import annotations

import contextlib
import numbers
from pathlib import Path
from typing import TYPE_CHECKING, Any

import click

if TYPE_CHECKING:  # the command line imports what a command needs when it runs (`brushbem --help` stays light)
    pass

# The figure files of a run, named by a light module (no numerics).
from brushbem.runs.pulloff import FIGURE_FILES

from brushbem.cli.common import (
    EXIT_INTERRUPTED,
    EXIT_INVALID_CONFIG,
    EXIT_NOT_CONVERGED,
    EXIT_WRITE_FAILED,
    RESULT_FILES,
    Console,
    Table,
    _load_or_exit,
    _number,
    _os_error,
    _OutFolder,
    _prepare_out,
    _Stop,
    signal_name,
)


def _summary_table(summary: dict[str, Any], units: Any = None, method: str | None = None) -> Table:
    """The headline numbers of a run with their units (``units``: `brushbem.results.units.Units`), theory ratios
    included, then what a designer reports (``design``) and the resolution's error estimate (``method``: the
    load path's, ``protocol.method``)."""
    from brushbem.results.units import Units

    units = units if units is not None else Units()

    def value(number: Any, dimension: str) -> str:
        # With [units], the SI prefix that reads (4 digits); without, the number as it is (6 digits).
        if units.dimensionless or not isinstance(number, numbers.Real) or isinstance(number, bool):
            return _number(number)
        return units.readable(float(number), dimension)

    table = Table(title="pull-off summary" + ("" if units.dimensionless else " (SI prefixes)"), show_header=False)
    table.add_column("quantity")
    table.add_column("value", justify="right")
    rows = [
        ("adhesive force", "adhesive_force", "force"),
        ("pull-off displacement", "pull_off_displacement", "length"),
        ("work of separation", "work_of_separation", "energy"),
    ]
    for label, key, dimension in rows:
        table.add_row(label, value(summary.get(key, "—"), dimension))
    design = summary.get("design") or {}
    if design.get("adhesion_strength") is not None:
        table.add_row("adhesion strength F_A / A0", value(design["adhesion_strength"], "stress"))
        table.add_row("apparent area A0", value(design["apparent_area"], "length^2"))
    if design.get("adhesive_force_per_pillar") is not None:
        table.add_row(f"F_A per pillar (N_p = {design['pillars']})", value(design["adhesive_force_per_pillar"], "force"))
    spring = design.get("spring")
    if spring:
        table.add_row(f"spring k ({spring['from'].split(':')[0]})", value(spring["stiffness"], "force / length"))
        if spring.get("buckling_force") is not None:
            table.add_row("Euler buckling force P_cr", value(spring["buckling_force"], "force"))
    resolution = summary.get("resolution")
    if resolution:
        low, high = resolution["force_error_range"]
        spread = "" if low == high else f" ({100 * low:+.2g} to {100 * high:+.2g})"
        table.add_row(f"elements per {resolution['length']}", _number(resolution["elements"]))
        table.add_row("F_A discretisation error (est.)", f"{100 * resolution['force_error_estimate']:+.2g} %{spread}")
    normalized = summary.get("normalized")
    if normalized:
        # A brush: the thesis's dimensionless numbers say more than the scales.
        labels = (
            ("F_A / F_K compact punch (eq. 4.11)", "force_by_compact_punch"),
            ("F_A / F_c rigid brush (eq. 5.3)", "force_by_rigid_brush"),
            ("F_A / N F_K ideal sharing (eq. 7.4)", "force_by_ideal_sharing"),
            ("d_A / d_c (eq. 4.12)", "displacement_by_rigid_brush"),
            ("k~ = k / (E* L)", "stiffness_ratio"),
            ("filling factor (rasterised)", "filling_factor"),
            ("pillars attached at F_A", "attached_pillars_at_pull_off"),
        )
        for label, key in labels:
            if normalized.get(key) is not None:
                table.add_row(label, _number(normalized[key]))
        table.add_row("phi^-1/4 (rigid limit, eq. 4.9)", _number((summary.get("theory") or {}).get(
            "rigid_brush_enhancement", "—")))
    else:
        for key, entry in (summary.get("theory") or {}).items():
            # Only scalar ratios and values belong in a one-screen table.
            if isinstance(entry, (numbers.Real, str)):
                table.add_row(f"theory: {key}", _number(entry))
    refinement = summary.get("refinement")
    if refinement:
        for label, key, dimension in (("F_A extrapolated", "adhesive_force", "force"),
                                      ("work extrapolated", "work_of_separation", "energy")):
            entry = refinement[key]
            tips = refinement.get("tip_elements_per_radius")
            levels = (f"tips at {', '.join(f'{q:.3g}' for q in tips)} elements per radius" if tips else
                      f"N = {', '.join(map(str, refinement['elements']))}")
            table.add_row(f"{label} ({levels})",
                          f"{value(entry['extrapolated'], dimension)} ± {value(entry['error_estimate'], dimension)}"
                          if entry.get("error_estimate") is not None else
                          f"{value(entry['extrapolated'], dimension)}, no error bound (two grids: --refine 3 bounds it)")
    table.add_row("converged", _number(summary.get("converged", "—")))
    if method == "pillars":
        # The pillar model solves the pillar-level system (directly, or by its own CG on a lattice's FFT that
        # the element CG's count does not hold): a 0 here would read as "no work".
        table.add_row("CG iterations per solve", "— (pillar model: not counted)")
    else:
        table.add_row("CG iterations per solve", _number(summary.get("mean_cg_iterations_per_solve", "—")))
    table.add_row("time (s)", _number(summary.get("wall_time_s", "—")))
    return table


@click.command()
@click.argument("config_path", metavar="CONFIG", type=click.Path(path_type=Path, dir_okay=False))
@click.option(
    "--out", "out_dir", default=None, type=_OutFolder(),
    help="Folder for summary.json, result.nc and pulloff.png (created if absent); required unless --estimate.",
)
@click.option("--quiet", is_flag=True, help="No progress bar and no summary table.")
@click.option("--refine", "grids", type=click.IntRange(2, 3), default=None,
              help="Also run on the coarser grids N/2 (and N/4) and report the Richardson-extrapolated F_A and "
                   "work with error estimates in summary.json (refinement).")
@click.option("--overwrite", is_flag=True, help="Replace the results of an earlier run in --out.")
@click.option("--estimate", is_flag=True,
              help="Print the expected wall time and peak memory of the run, and their basis, from its first "
                   "states (about two seconds); run no further and write nothing (--out is not needed).")
def run(config_path: Path, out_dir: Path | None, quiet: bool, grids: int | None, overwrite: bool,
        estimate: bool) -> None:
    """Run the pull-off in CONFIG; write the results into --out.

    Ctrl-C (or SIGTERM) stops after the current state and writes the partial
    result, marked ``interrupted`` and not converged (exit 130, or 143).
    With --estimate, only the expected cost is printed (exit 0).
    """
    if out_dir is None and not estimate:
        raise click.UsageError("Missing option '--out' (only --estimate runs without it).")
    if estimate:
        try:
            if _print_size_estimate(config_path, grids):
                return
        except KeyboardInterrupt:
            click.echo("\ninterrupted: no estimate", err=True)
            raise click.exceptions.Exit(EXIT_INTERRUPTED) from None
    built = _load_or_exit(config_path, build=True)
    config = built.config
    from brushbem.results.units import Units
    if not estimate:
        earlier = [name for name in RESULT_FILES if (out_dir / name).exists()]
        if earlier and not overwrite:
            click.echo(f"--out {out_dir} holds the results of an earlier run ({', '.join(earlier)}); --overwrite "
                       "replaces them, or choose another --out", err=True)
            raise click.exceptions.Exit(EXIT_INVALID_CONFIG)
    refined = None
    if grids is not None:
        from brushbem.config import ConfigError
        from brushbem.runs.refine import refined_configs

        try:
            refined = refined_configs(config, grids)
        except ConfigError as exc:
            click.echo(f"invalid refinement of {config_path}:", err=True)
            for line in exc.problems:
                click.echo(f"  {line}", err=True)
            raise click.exceptions.Exit(EXIT_INVALID_CONFIG) from None
    if estimate:
        try:
            _print_run_estimate(config_path, [built] if refined is None else refined)
        except KeyboardInterrupt:  # Ctrl-C: the status of an interrupted command, not click's 1
            click.echo("\ninterrupted: no estimate", err=True)
            raise click.exceptions.Exit(EXIT_INTERRUPTED) from None
        return
    assert out_dir is not None
    _prepare_out(out_dir)  # before the computation, so that a bad --out does not lose it

    # Imported here so that `validate` and `--help` stay fast and do not need
    # the numerics.
    from brushbem.api import run as run_pull_off
    from brushbem.io import (
        FolderBusyError,
        exclusive_folder,
        remove_stale_temporaries,
    )

    stderr = Console(stderr=True)
    with contextlib.ExitStack() as stack:
        try:
            stack.enter_context(exclusive_folder(out_dir))
        except FolderBusyError as exc:
            click.echo(f"--out {exc}; wait for it or choose another folder", err=True)
            raise click.exceptions.Exit(EXIT_INVALID_CONFIG) from None
        except OSError as exc:  # a lock file that is a link or not brushbem's (UnsafeLockError), unreadable
            detail = f"{exc.filename}: {exc.strerror}" if exc.filename and exc.strerror else str(exc)
            click.echo(f"--out {out_dir}: cannot take the folder's lock ({detail})", err=True)
            raise click.exceptions.Exit(EXIT_INVALID_CONFIG) from None
        # A killed run's leftovers, by the names of the temporaries of its own files: never a complete
        # file, nor anything else in the folder.
        remove_stale_temporaries(out_dir, tuple(dict.fromkeys((*RESULT_FILES, *FIGURE_FILES, "report.html"))))
        stop = stack.enter_context(_Stop())
        from rich.progress import (
            BarColumn,
            Progress,
            TextColumn,
            TimeElapsedColumn,
            TimeRemainingColumn,
        )

        with Progress(
            TextColumn("{task.description}"),
            BarColumn(),
            TextColumn("{task.percentage:>3.0f}%"),
            TimeElapsedColumn(),
            TextColumn("remaining"),
            TimeRemainingColumn(),
            console=stderr,
            transient=True,
            disable=quiet,
        ) as progress:
            task = progress.add_task("pull-off", total=1.0)

            def report(fraction: float, message: str) -> None:
                progress.update(task, completed=min(max(fraction, 0.0), 1.0), description=message)

            pulled = run_pull_off(built, progress=report, stop=stop, refine=grids)
        result = pulled.result
        stop.computed = True

        # From here a second Ctrl-C ends the process at once, removing what was being written (_Stop.writing).
        stack.enter_context(stop.writing(out_dir, tuple(dict.fromkeys((*RESULT_FILES, *FIGURE_FILES)))))
        try:
            pulled.save(out_dir, figure=False)
        except OSError as exc:
            if not quiet:
                Console().print(_summary_table(result.summary, Units.from_config(config), built.path.method))
            click.echo(f"--out {out_dir}: could not write the results ({_os_error(exc)}); no file there "
                       "was left half-written", err=True)
            raise click.exceptions.Exit(EXIT_WRITE_FAILED) from None
        _remove_earlier_report(out_dir)
        figure_error = _draw_run_figure(pulled, out_dir)

    if not quiet:
        Console().print(_summary_table(result.summary, Units.from_config(config), built.path.method))
        click.echo(f"results written to {out_dir}" if figure_error is None else
                   f"summary.json and result.nc written to {out_dir}")
    for warning in result.summary.get("warnings", []):
        click.echo(f"warning: {warning}", err=True)
    if figure_error is not None:
        click.echo(f"--out {out_dir}: could not write the figure pulloff.png ({figure_error}); the results "
                   "summary.json and result.nc were written (`brushbem report` draws the figure from them)",
                   err=True)
    if stop.signal is not None and result.summary.get("interrupted", False):
        click.echo(f"interrupted: the partial result in {out_dir} is marked interrupted and not converged",
                   err=True)
        raise click.exceptions.Exit(stop.exit_status)
    if stop.signal is not None:  # it came after the last state: nothing was cut short
        click.echo(f"{signal_name(stop.signal)} arrived after the pull-off was computed: the result in {out_dir} "
                   "is complete, and was written whole", err=True)
    if not result.summary.get("converged", False):
        click.echo(
            f"warning: the pull-off did not converge ({result.summary.get('reason', 'no reason given')}); "
            f"results written to {out_dir} but they are not trustworthy",
            err=True,
        )
    if figure_error is not None:
        raise click.exceptions.Exit(EXIT_WRITE_FAILED)
    if not result.summary.get("converged", False):
        raise click.exceptions.Exit(EXIT_NOT_CONVERGED)


def _remove_earlier_report(out_dir: Path) -> None:
    """Remove the ``report.html`` of an earlier run in ``out_dir`` (it describes results just replaced).

    Only a report that `brushbem.report.run` wrote (its generator mark) is
    removed; any other file of that name is left as it is.
    """
    from brushbem.report.run import REPORT_FILE, is_run_report

    report = out_dir / REPORT_FILE
    if report.is_file() and not report.is_symlink() and is_run_report(report):
        with contextlib.suppress(OSError):
            report.unlink()


def _draw_run_figure(pulled: Any, out_dir: Path) -> str | None:
    """Draw the run's figure into ``out_dir`` (`brushbem.PullOff.save_figure`); on failure, why.

    The results are written before: a figure that cannot be drawn or written
    loses nothing, and the message says so.  On failure no figure file is
    left, one of an earlier run (``--overwrite``) included, so that it is
    never taken for this run's.
    """
    try:
        pulled.save_figure(out_dir)
    except Exception as exc:  # noqa: BLE001 - any failure of the figure: the results are safe, say what failed
        return _os_error(exc) if isinstance(exc, OSError) else f"{type(exc).__name__}: {exc}"
    return None


def _duration(seconds: float) -> str:
    """A wall time in the unit that reads best (s, min, h, days, years)."""
    for unit, size in (("years", 365.25 * 86400), ("days", 86400), ("h", 3600), ("min", 60)):
        if seconds >= 2 * size:
            return f"{seconds / size:.3g} {unit}"
    return f"{seconds:.2g} s" if seconds < 10 else f"{seconds:.0f} s"


def _print_available_memory() -> None:
    from brushbem.config.resources import available_memory, format_bytes

    try:
        limit, source = available_memory()
    except ValueError:
        limit, source = None, "unknown"
    if limit is not None:
        click.echo(f"  available memory {format_bytes(limit)} ({source})")


def _print_size_estimate(config_path: Path, grids: int | None) -> bool:
    """``run --estimate`` of a run too large to sample in seconds: its size and memory from the keys alone.

    True when printed (the configuration's sections are validated, but its brush is not rasterised and no
    state is computed); False when the run is small enough for `_print_run_estimate`.
    """
    from brushbem.config import ConfigError
    from brushbem.config.loading import load_config
    from brushbem.sweep.estimate import configured_pillars, too_large_to_sample
    from brushbem.config.resources import format_bytes, memory_estimate, result_size_estimate

    try:
        config = load_config(config_path)  # the sections and their rules, without rasterising
    except ConfigError:
        return False  # the full load says what is wrong
    why = too_large_to_sample(config)
    if why is None:
        return False
    click.echo(f"estimate for {config_path} (nothing written, nothing computed: {why}, so even building the "
               "brush would take long; the rasterised checks of `brushbem validate` are not run either):")
    click.echo(f"  N = {config.grid.elements} ({config.grid.elements ** 2:,} elements), "
               f"{configured_pillars(config):,} pillars, method \"{config.protocol.method}\"" +
               (f", on {grids} grids (the finest shown)" if grids else ""))
    click.echo("    wall time    not estimated: a state of this size must be computed to measure its cost "
               "(time a smaller grid or fewer pillars with --estimate, or run a few minutes and read the "
               "progress)")
    click.echo(f"    peak memory  {format_bytes(memory_estimate(config))} "
               f"(brushbem.config.resources.memory_estimate); result.nc at most "
               f"{format_bytes(result_size_estimate(config))}")
    _print_available_memory()
    return True


def _print_run_estimate(config_path: Path, configs: list[Any]) -> None:
    """``run --estimate``: the expected cost of the run (of every grid of --refine), with its basis; no file."""
    from brushbem.sweep.estimate import estimate_run
    from brushbem.config.resources import format_bytes

    estimates = [estimate_run(config) for config in configs]
    total = sum(estimate.seconds for estimate in estimates)
    grids = f" on {len(estimates)} grids" if len(estimates) > 1 else ""
    click.echo(f"estimate for {config_path}{grids} (nothing written; the path's first states computed to "
               "measure the cost of a state):")
    for estimate in estimates:
        click.echo(f"  N = {estimate.elements}, method \"{estimate.method}\":")
        if estimate.complete:
            click.echo(f"    wall time    {_duration(estimate.seconds)} (measured: the sample ran the whole path, "
                       f"{estimate.states} states)")
        elif estimate.loading_seconds is not None:
            click.echo(f"    wall time    {estimate.kind} {_duration(estimate.seconds)} = the loading as measured "
                       f"({estimate.loading_seconds:.3g} s, set-up included) + the unloading's states at "
                       f"{estimate.seconds_per_state:.3g} s each (their sampled mean); {estimate.states:,} states")
        else:
            click.echo(f"    wall time    {estimate.kind} {_duration(estimate.seconds)} = {estimate.states:,} states x "
                       f"{estimate.seconds_per_state:.3g} s (mean of the {estimate.sampled_states - 1} sampled "
                       f"states after the first) + {estimate.setup_seconds:.2g} s (set-up and first state)")
            for line in estimate.basis:
                click.echo(f"    basis        {line}")
        click.echo(f"    peak memory  {format_bytes(estimate.memory_bytes)} (brushbem.config.resources.memory_estimate); "
                   f"result.nc at most {format_bytes(estimate.result_bytes)}")
        if estimate.stops:
            click.echo(f"    note         {estimate.stops}")
    if len(estimates) > 1:
        kinds = {estimate.kind for estimate in estimates if estimate.kind != "measured"}
        click.echo(f"  total wall time {kinds.pop() if len(kinds) == 1 else 'about'} {_duration(total)}")
    _print_available_memory()
    click.echo("  (the computation only: writing the files and the figure takes a few seconds more)")


#: The examples `brushbem init` writes (shipped in brushbem/examples/), and what each is.
EXAMPLES = {
    "default": ("default.toml", "a 16 x 16 brush of flat pillars on springs (thesis Fig. 4-3 a)"),
    "punch": ("punch.toml", "Kendall's flat punch, rigid"),
    "punch_spring": ("punch_spring.toml", "a flat punch on a spring (thesis sec. 2.3)"),
    "sphere_spring": ("sphere_spring.toml", "a JKR sphere on a spring"),
    "pdms_fibrils": ("pdms_fibrils.toml", "6 x 6 PDMS fibrils in um and MPa: k from the fibril, nu = 0.5, F_A / A0"),
    "sweep": ("sweep.toml", "a parameter sweep over the punch's spring stiffness (with punch_spring.toml)"),
}


@click.command()
@click.argument("name", required=False, default="default", type=click.Choice(list(EXAMPLES)))
@click.option("--out", "out_dir", type=_OutFolder(), default=Path("."),
              show_default=True, help="Folder to write the example into.")
@click.option("--force", is_flag=True, help="Replace files of the same name.")
@click.option("--list", "list_only", is_flag=True, help="List the examples and exit.")
def init(name: str, out_dir: Path, force: bool, list_only: bool) -> None:
    """Write a commented example configuration NAME (default: the default brush) to start from."""
    from importlib.resources import files

    if list_only:
        for key, (file, text) in EXAMPLES.items():
            click.echo(f"{key:14s} {file:20s} {text}")
        return
    from brushbem.io import atomic_path

    names = [EXAMPLES[name][0]] + (["punch_spring.toml"] if name == "sweep" else [])
    targets = [out_dir / file for file in names]
    folders = [str(t) for t in targets if t.is_dir() and not t.is_symlink()]
    if folders:
        click.echo(f"{', '.join(folders)} is a folder, not an example file; choose another --out", err=True)
        raise click.exceptions.Exit(EXIT_INVALID_CONFIG)
    existing = [str(t) for t in targets if t.exists() or t.is_symlink()]
    if existing and not force:
        click.echo(f"{', '.join(existing)} exists; --force replaces it, or choose another --out", err=True)
        raise click.exceptions.Exit(EXIT_INVALID_CONFIG)
    _prepare_out(out_dir)  # a folder that cannot be created or written: exit 2 before any file
    written = []
    try:
        for file, target in zip(names, targets):
            # A temporary renamed over the name: a link of that name is replaced, never written through.
            with atomic_path(target) as temporary:
                temporary.write_text(files("brushbem.examples").joinpath(file).read_text(encoding="utf-8"),
                                     encoding="utf-8")
            written.append(target)
    except OSError as exc:
        click.echo(f"--out {out_dir}: could not write the example ({_os_error(exc)})"
                   + (f"; written before: {', '.join(map(str, written))}" if written else "; nothing written"),
                   err=True)
        raise click.exceptions.Exit(EXIT_WRITE_FAILED) from None
    for target in written:
        click.echo(f"wrote {target}")
    first = targets[0]
    check = f"brushbem sweep {first} --dry-run" if name == "sweep" else f"brushbem validate {first}"
    command = "sweep" if name == "sweep" else "run"
    # The results beside the example, as the tutorial and the README run it (`--out DIR/out`).
    click.echo(f"next: {check} && brushbem {command} {first} --out {out_dir / 'out'}")


@click.command()
@click.argument("config_path", metavar="CONFIG", type=click.Path(path_type=Path, dir_okay=False))
def validate(config_path: Path) -> None:
    """Check CONFIG: print "ok", or every problem (exit status 2).

    A valid configuration's warnings (inputs far outside the physical range in its ``[units]``, a
    deciding radius under 8 elements with the error it carries: `brushbem.config.advice`) follow the
    "ok" on the standard error, one a line; they do not change the exit status.
    """
    from brushbem.config import advice

    config = _load_or_exit(config_path)
    warnings = advice.advice(config)
    click.echo("ok" if not warnings else f"ok, with {len(warnings)} warning{'s' if len(warnings) > 1 else ''}")
    for warning in warnings:
        click.echo(f"warning: {warning}", err=True)
