"""Command line: ``brushbem run``, ``sweep``, ``validate``, ``study``, ``figure``, ``report``.

Each command is a thin shell over library functions: `brushbem.config` loads
and validates, `brushbem.case.run_case` computes, `brushbem.io` and
`brushbem.plot` write.  Exit status: 0 success, 2 invalid configuration
(or an --out that cannot be written, or is in use by another process),
3 the run finished but some solve did not converge (results still written),
4 the results could not be written (a full disk: nothing half-written is
left), or for ``run`` only its figure (the message says that the result
files were written); ``run`` interrupted by SIGINT / SIGTERM writes its
partial result, marked interrupted, and exits 130 / 143;
for ``sweep`` and ``study``, 2 also when --out holds a different sweep, 3
also when some case failed or is still missing, and SIGINT / SIGTERM keep
every finished case, end the local workers and exit 130 / 143 (a rerun
computes the missing cases); ``figure`` and ``report`` exit 2 for a folder
they cannot read.
"""

from __future__ import annotations

import contextlib
import math
import numbers
import signal
import threading
from pathlib import Path
from typing import TYPE_CHECKING, Any, Self

import click

if TYPE_CHECKING:  # the command line imports what a command needs when it runs (`brushbem --help` stays light)
    from brushbem import assembly
    from brushbem.config import RunConfig


def Console(*args: Any, **kwargs: Any):  # noqa: N802 - stands in for rich's class, imported on first use
    from rich.console import Console as RichConsole

    return RichConsole(*args, **kwargs)


def Table(*args: Any, **kwargs: Any):  # noqa: N802
    from rich.table import Table as RichTable

    return RichTable(*args, **kwargs)

__all__ = ["main"]

EXIT_INVALID_CONFIG = 2
EXIT_NOT_CONVERGED = 3
EXIT_INTERRUPTED = 130
EXIT_WRITE_FAILED = 4


def _load_or_exit(config_path: Path, build: bool = False) -> RunConfig | assembly.Assembly:
    """Load and check a configuration completely (`brushbem.assembly`); ``build``: its `Assembly`.

    On any problem print them all and exit with status 2.
    """
    from brushbem import assembly
    from brushbem.config import ConfigError

    try:
        return assembly.load(config_path) if build else assembly.load_config(config_path)
    except ConfigError as error:
        click.echo(f"invalid configuration {config_path}:", err=True)
        for problem in error.problems:
            click.echo(f"  {problem}", err=True)
        raise click.exceptions.Exit(EXIT_INVALID_CONFIG) from None


def _number(value: Any) -> str:
    if isinstance(value, bool):
        return "yes" if value else "no"
    if isinstance(value, numbers.Real):
        return f"{float(value):.6g}"
    return str(value)


def _summary_table(summary: dict[str, Any]) -> Table:
    """The headline numbers of a run, theory ratios included."""
    table = Table(title="pull-off summary", show_header=False)
    table.add_column("quantity")
    table.add_column("value", justify="right")
    rows = [
        ("adhesive force", "adhesive_force"),
        ("pull-off displacement", "pull_off_displacement"),
        ("work of separation", "work_of_separation"),
    ]
    for label, key in rows:
        table.add_row(label, _number(summary.get(key, "—")))
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
        for key, value in (summary.get("theory") or {}).items():
            # Only scalar ratios and values belong in a one-screen table.
            if isinstance(value, (numbers.Real, str)):
                table.add_row(f"theory: {key}", _number(value))
    refinement = summary.get("refinement")
    if refinement:
        for label, key in (("F_A extrapolated", "adhesive_force"), ("work extrapolated", "work_of_separation")):
            entry = refinement[key]
            table.add_row(f"{label} (N = {', '.join(map(str, refinement['elements']))})",
                          f"{_number(entry['extrapolated'])} ± {_number(entry['error_estimate'])}")
    table.add_row("converged", _number(summary.get("converged", "—")))
    table.add_row("CG iterations per solve", _number(summary.get("mean_cg_iterations_per_solve", "—")))
    table.add_row("time (s)", _number(summary.get("wall_time_s", "—")))
    return table


def _check_executor_options(
    workers: int | None, use_dask: bool, scheduler: str | None, scheduler_file: Path | None,
) -> None:
    """Reject contradictory ``--workers/--dask/--scheduler/--scheduler-file`` (a usage error)."""
    if sum((use_dask, scheduler is not None, scheduler_file is not None)) > 1:
        raise click.UsageError("give at most one of --dask, --scheduler, --scheduler-file")
    if workers is not None and (scheduler is not None or scheduler_file is not None):
        raise click.UsageError("--workers sizes a local pool or --dask's cluster; "
                               "a running scheduler has its own workers")


def _executor(
    stack: contextlib.ExitStack,
    workers: int | None,
    use_dask: bool,
    scheduler: str | None,
    scheduler_file: Path | None,
) -> Any:
    """The dask client the options ask for (closed with ``stack``), or None for a local pool."""
    from brushbem import sweep as sweep_module

    if not (use_dask or scheduler is not None or scheduler_file is not None):
        return None
    try:
        return stack.enter_context(sweep_module.dask_client(
            address=scheduler, scheduler_file=scheduler_file, workers=workers,
        ))
    except ImportError as exc:
        raise click.ClickException(str(exc)) from None
    except (OSError, ValueError) as exc:  # no scheduler there, an unreadable scheduler file
        where = scheduler or scheduler_file or "a new LocalCluster"
        raise click.ClickException(f"cannot connect to the dask scheduler {where}: {exc}") from None


def _executor_options(function: Any) -> Any:
    """The ``--workers/--dask/--scheduler/--scheduler-file/--retry-failed`` options."""
    options = [
        click.option(
            "--workers", type=click.IntRange(min=1), default=None,
            help="Local worker processes, or the workers of --dask's cluster "
            "[default: number of cores].",
        ),
        click.option("--dask", "use_dask", is_flag=True,
                     help="Run on a new dask.distributed LocalCluster."),
        click.option("--scheduler", metavar="ADDRESS", default=None,
                     help="Run on the dask.distributed scheduler at ADDRESS (e.g. tcp://host:8786)."),
        click.option("--scheduler-file", type=click.Path(path_type=Path, dir_okay=False), default=None,
                     help="Run on the dask.distributed scheduler described by this file."),
        click.option("--retry-failed", is_flag=True,
                     help="Recompute cases recorded as failed (by default a rerun keeps them)."),
    ]
    for option in reversed(options):
        function = option(function)
    return function


@click.group()
@click.version_option(package_name="brushbem", prog_name="brushbem")
def main() -> None:
    """Adhesive pull-off of punches, spheres and brushes on an elastic half-space."""


class _Stop:
    """SIGINT and SIGTERM ask a run to stop after its current state (a second SIGINT aborts at once)."""

    def __init__(self) -> None:
        self.signal: int | None = None
        self._previous: dict[int, Any] = {}

    def __call__(self) -> bool:
        return self.signal is not None

    def _handle(self, number: int, frame: Any) -> None:
        if self.signal is not None and number == signal.SIGINT:
            raise KeyboardInterrupt
        self.signal = number
        click.echo(f"\n{signal.Signals(number).name}: stopping after the current state and keeping the "
                   "partial result (Ctrl-C again aborts without writing)", err=True)

    def __enter__(self) -> Self:
        if threading.current_thread() is threading.main_thread():
            for number in (signal.SIGINT, signal.SIGTERM):
                self._previous[number] = signal.signal(number, self._handle)
        return self

    def __exit__(self, *exc: object) -> None:
        for number, handler in self._previous.items():
            signal.signal(number, handler)

    @property
    def exit_status(self) -> int:
        """128 + the signal's number: 130 for SIGINT, 143 for SIGTERM."""
        return 128 + int(self.signal or signal.SIGINT)


#: The files of a design's output folder (`brushbem design` refuses to replace them without --overwrite).
DESIGN_FILES = ("design.npy", "design.csv", "design.json", "design.png", "design.pdf")

#: The files of a run's output folder (`brushbem run` refuses to replace them without --overwrite).
RESULT_FILES = ("summary.json", "result.nc", "pulloff.png", "pulloff.pdf")


class _OutFolder(click.Path):
    """An output folder; the empty path (which would write into the current folder) is refused."""

    def __init__(self) -> None:
        super().__init__(path_type=Path, file_okay=False)

    def convert(self, value: Any, param: click.Parameter | None, ctx: click.Context | None) -> Any:
        if isinstance(value, str) and not value.strip():
            self.fail(f"{value!r} is an empty path; give a folder (--out . for the current folder)", param, ctx)
        return super().convert(value, param, ctx)


def _prepare_out(out_dir: Path) -> None:
    """Create ``out_dir`` and check that it takes files, before anything is computed; else exit 2."""
    from brushbem.io import check_writable

    try:
        out_dir.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        click.echo(f"--out {out_dir}: cannot create the output folder ({exc.strerror or exc})", err=True)
        raise click.exceptions.Exit(EXIT_INVALID_CONFIG) from None
    try:
        check_writable(out_dir)
    except OSError as exc:
        click.echo(f"--out {out_dir}: cannot write into the output folder ({exc.strerror or exc})", err=True)
        raise click.exceptions.Exit(EXIT_INVALID_CONFIG) from None


@main.command()
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
    built = _load_or_exit(config_path, build=True)
    config = built.config
    if not estimate:
        earlier = [name for name in RESULT_FILES if (out_dir / name).exists()]
        if earlier and not overwrite:
            click.echo(f"--out {out_dir} holds the results of an earlier run ({', '.join(earlier)}); --overwrite "
                       "replaces them, or choose another --out", err=True)
            raise click.exceptions.Exit(EXIT_INVALID_CONFIG)
    refined = None
    if grids is not None:
        from brushbem.config import ConfigError
        from brushbem.refine import refined_configs

        try:
            refined = refined_configs(config, grids)
        except ConfigError as exc:
            click.echo(f"invalid refinement of {config_path}:", err=True)
            for line in exc.problems:
                click.echo(f"  {line}", err=True)
            raise click.exceptions.Exit(EXIT_INVALID_CONFIG) from None
    if estimate:
        _print_run_estimate(config_path, [built] if refined is None else refined)
        return
    assert out_dir is not None
    _prepare_out(out_dir)  # before the computation, so that a bad --out does not lose it

    # Imported here so that `validate` and `--help` stay fast and do not need
    # the numerics.
    from brushbem import case as case_module
    from brushbem.io import (
        FolderBusyError,
        exclusive_folder,
        remove_stale_temporaries,
        write_case,
    )
    from brushbem.plot import plot_pull_off

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
        from rich.progress import BarColumn, Progress, TextColumn, TimeElapsedColumn, TimeRemainingColumn

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

            if grids is None:
                result, reference = case_module.run_case(built, progress=report, stop=stop)
            else:
                from brushbem.refine import refined_run

                result, reference = refined_run(
                    config, grids, progress=report,
                    run=lambda cfg, progress: case_module.run_case(cfg, progress=progress, stop=stop))

        try:
            write_case(result, out_dir, config=config)
        except OSError as exc:
            if not quiet:
                Console().print(_summary_table(result.summary))
            click.echo(f"--out {out_dir}: could not write the results ({_os_error(exc)}); no file there "
                       "was left half-written", err=True)
            raise click.exceptions.Exit(EXIT_WRITE_FAILED) from None
        _remove_earlier_report(out_dir)
        figure_error = _draw_run_figure(plot_pull_off, result, reference, out_dir)

    if not quiet:
        Console().print(_summary_table(result.summary))
        click.echo(f"results written to {out_dir}" if figure_error is None else
                   f"summary.json and result.nc written to {out_dir}")
    for warning in result.summary.get("warnings", []):
        click.echo(f"warning: {warning}", err=True)
    if figure_error is not None:
        click.echo(f"--out {out_dir}: could not write the figure pulloff.png ({figure_error}); the results "
                   "summary.json and result.nc were written (`brushbem report` draws the figure from them)",
                   err=True)
    if stop.signal is not None:
        click.echo(f"interrupted: the partial result in {out_dir} is marked interrupted and not converged",
                   err=True)
        raise click.exceptions.Exit(stop.exit_status)
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


#: The figure files of a run (`brushbem.plot.plot_pull_off` writes the PNG and a PDF beside it).
FIGURE_FILES = ("pulloff.png", "pulloff.pdf")


def _os_error(exc: OSError) -> str:
    """An ``OSError`` for a message: the file's name and the system's reason."""
    reason = exc.strerror or str(exc)
    return f"{Path(exc.filename).name}: {reason}" if exc.filename else reason


def _remove_earlier_report(out_dir: Path) -> None:
    """Remove the ``report.html`` of an earlier run in ``out_dir`` (it describes results just replaced).

    Only a report that `brushbem.run_report` wrote (its generator mark) is
    removed; any other file of that name is left as it is.
    """
    from brushbem.run_report import REPORT_FILE, is_run_report

    report = out_dir / REPORT_FILE
    if report.is_file() and not report.is_symlink() and is_run_report(report):
        with contextlib.suppress(OSError):
            report.unlink()


def _draw_run_figure(plot: Any, result: Any, reference: Any, out_dir: Path) -> str | None:
    """Draw the run's figure into ``out_dir``; on failure, why (and no figure of an earlier run is left).

    The results are written before: a figure that cannot be drawn or written
    loses nothing, and the message says so.  A figure file of an earlier run
    (``--overwrite``) is removed, so that it is never taken for this run's.
    """
    try:
        plot(result, out_dir / "pulloff.png", reference)
    except Exception as exc:  # noqa: BLE001 - any failure of the figure: the results are safe, say what failed
        for name in FIGURE_FILES:
            with contextlib.suppress(OSError):
                (out_dir / name).unlink(missing_ok=True)
        return _os_error(exc) if isinstance(exc, OSError) else f"{type(exc).__name__}: {exc}"
    return None


def _duration(seconds: float) -> str:
    """A wall time in the unit that reads best (s, min, h, days, years)."""
    for unit, size in (("years", 365.25 * 86400), ("days", 86400), ("h", 3600), ("min", 60)):
        if seconds >= 2 * size:
            return f"{seconds / size:.3g} {unit}"
    return f"{seconds:.2g} s" if seconds < 10 else f"{seconds:.0f} s"


def _print_run_estimate(config_path: Path, configs: list[Any]) -> None:
    """``run --estimate``: the expected cost of the run (of every grid of --refine), with its basis; no file."""
    from brushbem.estimate import estimate_run
    from brushbem.resources import available_memory, format_bytes

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
        else:
            click.echo(f"    wall time    {estimate.kind} {_duration(estimate.seconds)} = {estimate.states:,} states x "
                       f"{estimate.seconds_per_state:.3g} s (mean of the {estimate.sampled_states - 1} sampled "
                       f"states after the first) + {estimate.setup_seconds:.2g} s (set-up and first state)")
            for line in estimate.basis:
                click.echo(f"    basis        {line}")
        click.echo(f"    peak memory  {format_bytes(estimate.memory_bytes)} (brushbem.resources.memory_estimate); "
                   f"result.nc at most {format_bytes(estimate.result_bytes)}")
        if estimate.stops:
            click.echo(f"    note         {estimate.stops}")
    if len(estimates) > 1:
        kinds = {estimate.kind for estimate in estimates if estimate.kind != "measured"}
        click.echo(f"  total wall time {kinds.pop() if len(kinds) == 1 else 'about'} {_duration(total)}")
    try:
        limit, source = available_memory()
    except ValueError:
        limit, source = None, "unknown"
    if limit is not None:
        click.echo(f"  available memory {format_bytes(limit)} ({source})")
    click.echo("  (the computation only: writing the files and the figure takes a few seconds more)")


#: The examples `brushbem init` writes (shipped in brushbem/examples/), and what each is.
EXAMPLES = {
    "default": ("default.toml", "a 16 x 16 brush of flat pillars on springs (thesis Fig. 4-3 a)"),
    "punch": ("punch.toml", "Kendall's flat punch, rigid"),
    "punch_spring": ("punch_spring.toml", "a flat punch on a spring (thesis sec. 2.3)"),
    "sphere_spring": ("sphere_spring.toml", "a JKR sphere on a spring"),
    "sweep": ("sweep.toml", "a parameter sweep over the punch's spring stiffness (with punch_spring.toml)"),
}


@main.command()
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
    names = [EXAMPLES[name][0]] + (["punch_spring.toml"] if name == "sweep" else [])
    targets = [out_dir / file for file in names]
    existing = [str(t) for t in targets if t.exists()]
    if existing and not force:
        click.echo(f"{', '.join(existing)} exists; --force replaces it, or choose another --out", err=True)
        raise click.exceptions.Exit(EXIT_INVALID_CONFIG)
    out_dir.mkdir(parents=True, exist_ok=True)
    for file, target in zip(names, targets):
        target.write_text(files("brushbem.examples").joinpath(file).read_text(encoding="utf-8"), encoding="utf-8")
        click.echo(f"wrote {target}")
    first = targets[0]
    check = f"brushbem sweep {first} --dry-run" if name == "sweep" else f"brushbem validate {first}"
    command = "sweep" if name == "sweep" else "run"
    click.echo(f"next: {check} && brushbem {command} {first} --out out/{first.stem}")


@main.command()
@click.argument("config_path", metavar="CONFIG", type=click.Path(path_type=Path, dir_okay=False))
@click.option("--out", "out_dir", required=True, type=_OutFolder(),
              help="Folder for design.npy, design.csv, design.json and design.png.")
@click.option("--target", type=click.Choice(["lengths", "stiffness"]), default="lengths", show_default=True,
              help="Design the pillars' length offsets, or their stiffnesses.")
@click.option("--iterations", type=click.IntRange(0, 50), default=2, show_default=True,
              help="Corrective pull-offs after the direct solve.")
@click.option("--bound", is_flag=True,
              help="Also compute the most any length or stiffness design in full contact can reach (a linear "
                   "programme over the pillar forces; one solve per pillar).")
@click.option("--quiet", is_flag=True, help="No progress output.")
@click.option("--overwrite", is_flag=True, help="Replace the design files of an earlier design in --out.")
def design(config_path: Path, out_dir: Path, target: str, iterations: int, bound: bool, quiet: bool,
           overwrite: bool) -> None:
    """Design CONFIG's brush for equal load sharing (lengths or stiffnesses), verified by pull-offs.

    Every pillar is brought to the criterion at the same moment by a direct
    solve for prescribed pillar forces; the ordinary pull-off of the designed
    brush then verifies F~ = F_A / (N F_K) (brushbem.design).  --out is
    checked and locked before anything is computed; Ctrl-C (or SIGTERM) stops
    after the current verification and writes the best design verified so far
    (exit 130, or 143).
    """
    built = _load_or_exit(config_path, build=True)
    earlier = [name for name in DESIGN_FILES if (out_dir / name).exists()]
    if earlier and not overwrite:
        click.echo(f"--out {out_dir} holds an earlier design ({', '.join(earlier)}); --overwrite replaces it, "
                   "or choose another --out", err=True)
        raise click.exceptions.Exit(EXIT_INVALID_CONFIG)
    _prepare_out(out_dir)
    from brushbem.design import DesignError, DesignInterrupted, write_design
    from brushbem.design import design as run_design
    from brushbem.io import FolderBusyError, exclusive_folder, remove_stale_temporaries

    with contextlib.ExitStack() as stack:
        try:
            stack.enter_context(exclusive_folder(out_dir))
        except FolderBusyError as exc:
            click.echo(f"--out {exc}; wait for it or choose another folder", err=True)
            raise click.exceptions.Exit(EXIT_INVALID_CONFIG) from None
        except OSError as exc:  # a lock file that is a link or not brushbem's, unreadable
            detail = f"{exc.filename}: {exc.strerror}" if exc.filename and exc.strerror else str(exc)
            click.echo(f"--out {out_dir}: cannot take the folder's lock ({detail})", err=True)
            raise click.exceptions.Exit(EXIT_INVALID_CONFIG) from None
        remove_stale_temporaries(out_dir, DESIGN_FILES)
        stop = stack.enter_context(_Stop())
        try:
            result = run_design(built.problem, built.path, target=target, iterations=iterations, bound=bound,
                                progress=None if quiet else lambda f, m: click.echo(m, err=True), stop=stop)
        except DesignError as exc:
            click.echo(f"cannot design {config_path}: {exc}", err=True)
            raise click.exceptions.Exit(EXIT_INVALID_CONFIG) from None
        except DesignInterrupted as exc:
            click.echo(f"design of {config_path} {exc}", err=True)
            raise click.exceptions.Exit(stop.exit_status) from None
        try:
            write_design(built.problem, result, out_dir, str(config_path))
        except OSError as exc:
            click.echo(f"--out {out_dir}: could not write the design ({exc.strerror or exc})", err=True)
            raise click.exceptions.Exit(EXIT_WRITE_FAILED) from None
    for warning in result.warnings:
        click.echo(f"warning: {warning}", err=True)
    if not quiet:
        click.echo(f"the brush as given: F~ = {result.start_force_ratio:.4f}")
        click.echo(f"predicted F~ = {result.predicted_force_ratio:.4f} (every pillar's edge critical at once), "
                   f"verified F~ = {result.verified_force_ratio:.4f} after {result.iterations} corrective pull-offs; "
                   f"detachment spread {result.spread:.3g} |d_c|; written to {out_dir}")
        if result.bound_force_ratio is not None:
            click.echo(f"no design exceeds F~ = {result.bound_force_ratio:.4f} while every pillar is in full "
                       "contact (the load-sharing bound; partial detachments, which the verification includes, "
                       "may add to it in dense arrays)")
    if not result.converged:
        click.echo("warning: a verification pull-off did not converge", err=True)
        raise click.exceptions.Exit(EXIT_NOT_CONVERGED)
    if stop.signal is not None:
        raise click.exceptions.Exit(stop.exit_status)


@main.command()
@click.argument("config_path", metavar="CONFIG", type=click.Path(path_type=Path, dir_okay=False))
def validate(config_path: Path) -> None:
    """Check CONFIG: print "ok", or every problem (exit status 2)."""
    _load_or_exit(config_path)
    click.echo("ok")


@main.command()
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


#: Exit status of a sweep or study stopped by SIGTERM (after the same clean-up as Ctrl-C).
EXIT_TERMINATED = 143


class _Terminated(KeyboardInterrupt):
    """SIGTERM during a sweep or study: it stops the way Ctrl-C does."""


def _make_out(out_dir: Path) -> None:
    """Create a sweep's or study's ``out_dir`` before anything runs; exit 2 naming it if that fails."""
    try:
        out_dir.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        click.echo(f"--out {out_dir}: cannot create the output folder ({exc.strerror or exc})", err=True)
        raise click.exceptions.Exit(EXIT_INVALID_CONFIG) from None


@contextlib.contextmanager
def _sweep_errors(out_dir: Path) -> Any:
    """Run a sweep or study: SIGTERM handled like Ctrl-C, every outcome a message and an exit status.

    Interrupted: 130 (SIGINT) or 143 (SIGTERM), every finished case kept;
    a folder holding another sweep: 2; another driver in the folder: 1; a
    file that cannot be written (a full disk): 4, the cases written kept.
    """
    from brushbem import sweep as sweep_module

    def terminate(number: int, frame: Any) -> None:
        raise _Terminated

    previous = None
    if threading.current_thread() is threading.main_thread():
        previous = signal.signal(signal.SIGTERM, terminate)
    try:
        yield
    except KeyboardInterrupt as interruption:
        name = "terminated (SIGTERM)" if isinstance(interruption, _Terminated) else "interrupted"
        click.echo(f"{name}; the finished cases are kept, rerun to compute the missing ones in {out_dir}",
                   err=True)
        status = EXIT_TERMINATED if isinstance(interruption, _Terminated) else EXIT_INTERRUPTED
        raise click.exceptions.Exit(status) from None
    except sweep_module.SweepFolderError as error:
        click.echo(f"cannot run into {out_dir}:", err=True)
        for problem in error.problems:
            click.echo(f"  {problem}", err=True)
        raise click.exceptions.Exit(EXIT_INVALID_CONFIG) from None
    except OSError as exc:
        where = exc.filename or out_dir
        click.echo(f"cannot write {where} ({exc.strerror or exc}); the cases written so far are kept, "
                   "a rerun computes the rest", err=True)
        raise click.exceptions.Exit(EXIT_WRITE_FAILED) from None
    except (click.exceptions.Exit, click.exceptions.Abort):  # RuntimeErrors too, but already said
        raise
    except RuntimeError as exc:  # another sweep runs in the same folder: a busy --out, as for `run` (exit 2)
        click.echo(f"--out {exc}; wait for it or choose another folder", err=True)
        raise click.exceptions.Exit(EXIT_INVALID_CONFIG) from None
    finally:
        if previous is not None:
            signal.signal(signal.SIGTERM, previous)


def _load_sweep_or_exit(path: Path, heading: str) -> Any:
    """The validated sweep of ``path``; on problems print ``heading`` and them, and exit 2."""
    from brushbem import sweep as sweep_module

    try:
        return sweep_module.load_sweep(path)
    except sweep_module.SweepError as error:
        click.echo(heading, err=True)
        for problem in error.problems:
            click.echo(f"  {problem}", err=True)
        raise click.exceptions.Exit(EXIT_INVALID_CONFIG) from None


def _estimate(study: Any, samples: int, quiet: bool) -> Any:
    from brushbem.estimate import estimate_sweep

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
    for name, estimate in estimates.items():
        seconds = ", ".join(f"{t:.1f}" for t in estimate.seconds)
        failed = [s for s in estimate.statuses if s != "finished"]
        note = f" ({len(failed)} not finished)" if failed else ""
        table.add_row(name, str(estimate.cases), seconds + note,
                      f"{estimate.cpu_hours:.3g} ± {estimate.cpu_hours_error:.2g}",
                      f"{estimate.wall_hours(workers):.3g}")
        total_cpu += estimate.cpu_hours
        total_error2 += estimate.cpu_hours_error**2
        total_wall += estimate.wall_hours(workers)
    if len(estimates) > 1:
        table.add_row("total", str(sum(e.cases for e in estimates.values())), "",
                      f"{total_cpu:.3g} ± {total_error2**0.5:.2g}", f"{total_wall:.3g}")
    Console().print(table)


def _list_studies() -> None:
    from brushbem import studies

    table = Table(title=f"{len(studies.STUDIES)} studies")
    # The names a user types are never cut: the study column is as wide as the longest name, the rest folds.
    table.add_column("study", no_wrap=True, min_width=max(len(name) for name in studies.STUDIES))
    for column in ("title", "thesis figures", "parts"):
        table.add_column(column, overflow="fold")
    for study in studies.STUDIES.values():
        table.add_row(study.name, study.title, ", ".join(study.figures), ", ".join(study.parts))
    Console().print(table)


@main.command()
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


@contextlib.contextmanager
def _reading_results() -> Any:
    """Draw or report from a results folder: repairs as warnings, a folder it cannot read exits 2.

    A summary rebuilt on reading is a ``warning:`` line; a folder that is no
    study or sweep folder, or whose record cannot be read, exits 2 naming
    it; a file that cannot be written exits 4.
    """
    import warnings

    from brushbem import studies
    from brushbem import sweep as sweep_module

    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", sweep_module.SweepWarning)
        try:
            yield
        except (FileNotFoundError, studies.StudyError) as error:
            click.echo(str(error), err=True)
            raise click.exceptions.Exit(EXIT_INVALID_CONFIG) from None
        except sweep_module.SweepFolderError as error:
            for problem in error.problems:
                click.echo(problem, err=True)
            raise click.exceptions.Exit(EXIT_INVALID_CONFIG) from None
        except OSError as exc:
            click.echo(f"cannot write {exc.filename or 'the output'} ({exc.strerror or exc})", err=True)
            raise click.exceptions.Exit(EXIT_WRITE_FAILED) from None
        finally:
            for notice in dict.fromkeys(str(w.message) for w in caught
                                        if issubclass(w.category, sweep_module.SweepWarning)):
                click.echo(f"warning: {notice}", err=True)


@main.command()
@click.argument("out_dir", metavar="DIR", type=click.Path(path_type=Path, file_okay=False, exists=True))
def figure(out_dir: Path) -> None:
    """Redraw the figures of the study or sweep in DIR from its stored results (no computing)."""
    from brushbem.report import draw_figures

    with _reading_results():
        paths = draw_figures(out_dir)
    for path in paths:
        click.echo(str(path))


@main.command()
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
    from brushbem.run_report import RunReportError, is_run_folder, write_run_report

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
    from brushbem.report import write_report

    with _reading_results():
        path = write_report(out_dir, redraw=redraw)
    click.echo(str(path))


@main.command("export-tables")
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


@main.command()
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
    """Equal to the digits a rerun of the same cases reproduces (the solver is deterministic)."""
    return math.isclose(a, b, rel_tol=1e-9, abs_tol=1e-15)


@main.command("compare-thesis")
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
