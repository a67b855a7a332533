"""What the commands share: exit statuses, loading a configuration or a sweep, the --out folder, stopping on a signal, executor options."""

from __future__ import annotations

import contextlib
import numbers
import signal
import threading
from pathlib import Path
from typing import TYPE_CHECKING, Any, Self

import click

if TYPE_CHECKING:  # the command line imports what a command needs when it runs (`brushbem --help` stays light)
    from brushbem.runs import assembly
    from brushbem.config import RunConfig

def Console(*args: Any, **kwargs: Any):  # noqa: N802 - stands in for rich's class, imported on first use
    from rich.console import Console as RichConsole

    return RichConsole(*args, **kwargs)


def Table(*args: Any, **kwargs: Any):  # noqa: N802
    from rich.table import Table as RichTable

    return RichTable(*args, **kwargs)

EXIT_INVALID_CONFIG = 2
EXIT_NOT_CONVERGED = 3
EXIT_INTERRUPTED = 130
EXIT_WRITE_FAILED = 4


def _load_or_exit(config_path: Path, build: bool = False) -> RunConfig | assembly.Assembly:
    """Load and check a configuration completely (`brushbem.runs.assembly`); ``build``: its `Assembly`.

    On any problem print them all and exit with status 2.
    """
    from brushbem.runs import assembly
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


def signal_name(number: int) -> str:
    """SIGINT, SIGTERM: the name of a signal's number."""
    return signal.Signals(number).name


class _Stop:
    """SIGINT and SIGTERM ask a run to stop after its current state (a second SIGINT aborts at once).

    While the results are written (`writing`), a second SIGINT does not raise `KeyboardInterrupt` into the
    writer: landing inside a library that holds a non-reentrant lock (xarray's, HDF5's) it left the process
    hung on that lock, holding the folder's lock, its temporary behind.  It removes the temporaries of the
    files being written and ends the process at once (`os._exit`, status 130; the kernel releases the
    folder's lock): the files already in place stay as they were, ``summary.json`` (written last) is the
    earlier run's or absent.
    """

    def __init__(self) -> None:
        self.signal: int | None = None
        #: Set once the computation has ended (the result is being written): a signal then cuts nothing short.
        self.computed = False
        self._previous: dict[int, Any] = {}
        self._writing: tuple[Path, tuple[str, ...]] | None = None

    def __call__(self) -> bool:
        return self.signal is not None

    @contextlib.contextmanager
    def writing(self, folder: Path, names: tuple[str, ...]) -> Any:
        """Within this block a second SIGINT removes the temporaries of ``names`` in ``folder`` and exits 130."""
        self._writing = (Path(folder), tuple(names))
        try:
            yield
        finally:
            self._writing = None

    def _abort_writing(self) -> None:
        import os

        from brushbem.io import remove_stale_temporaries

        folder, names = self._writing  # type: ignore[misc]
        with contextlib.suppress(OSError):
            remove_stale_temporaries(folder, names)
        with contextlib.suppress(Exception):
            click.echo(f"\nSIGINT again: aborted while writing into {folder}; the files being written were not "
                       "replaced (their temporaries removed)", err=True)
        os._exit(128 + int(signal.SIGINT))

    def _handle(self, number: int, frame: Any) -> None:
        if self.signal is not None and number == signal.SIGINT:
            if self._writing is not None:
                self._abort_writing()
            raise KeyboardInterrupt
        self.signal = number
        if self.computed:
            click.echo(f"\n{signal.Signals(number).name}: the computation is complete; its result is being "
                       "written whole (Ctrl-C again aborts without writing)", err=True)
            return
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

#: The files of a run's output folder (`brushbem run` refuses to replace them without --overwrite).
RESULT_FILES = ("summary.json", "result.nc", "curve.csv", "pulloff.png", "pulloff.pdf")


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


def _os_error(exc: OSError) -> str:
    """An ``OSError`` for a message: the file's name and the system's reason."""
    reason = exc.strerror or str(exc)
    return f"{Path(exc.filename).name}: {reason}" if exc.filename else reason


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
