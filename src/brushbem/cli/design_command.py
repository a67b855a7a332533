"""``brushbem design``: a brush designed for equal load sharing, with ``run``'s protections of --out."""

from __future__ import annotations

import contextlib
from pathlib import Path
from typing import TYPE_CHECKING

import click

if TYPE_CHECKING:  # the command line imports what a command needs when it runs (`brushbem --help` stays light)
    pass

from brushbem.cli.common import (
    EXIT_INVALID_CONFIG,
    EXIT_NOT_CONVERGED,
    EXIT_WRITE_FAILED,
    _load_or_exit,
    _OutFolder,
    _prepare_out,
    _Stop,
    signal_name,
)

#: The files of a design's output folder (`brushbem design` refuses to replace them without --overwrite).
DESIGN_FILES = ("design.npy", "design.csv", "design.json", "design.png", "design.pdf")


@click.command()
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
    from brushbem.design import DesignError, DesignInterrupted
    from brushbem.design_files import DesignWriteError, write_design
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
        stop.computed = True
        try:
            write_design(built.problem, result, out_dir, str(config_path))
        except DesignWriteError as exc:
            kept = "; the files of this design written before it were removed" if exc.removed else ""
            click.echo(f"--out {out_dir}: could not write {exc.filename} ({exc.strerror}){kept}: nothing of this "
                       "design is kept", err=True)
            raise click.exceptions.Exit(EXIT_WRITE_FAILED) from None
        except OSError as exc:
            click.echo(f"--out {out_dir}: could not write the design ({exc.strerror or exc}): nothing of it is "
                       "kept", err=True)
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
    if stop.signal is not None and result.interrupted:
        raise click.exceptions.Exit(stop.exit_status)
    if stop.signal is not None:  # after the design was complete: written whole, nothing cut short
        click.echo(f"{signal_name(stop.signal)} arrived after the design was complete: it was written whole",
                   err=True)
