"""Command line: ``brushbem run``, ``sweep``, ``validate``, ``study``, ``figure``, ``report``.

Each command is a thin shell over library functions: `brushbem.config` loads
and validates, `brushbem.runs.case.run_case` computes, `brushbem.io` and
`brushbem.figures.plot` write.  Exit status: 0 success, 2 invalid configuration
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

import click

from brushbem.cli.design_command import design
from brushbem.cli.run_commands import EXAMPLES, init, run, validate
from brushbem.cli.sweep_commands import figure, report, study, sweep
from brushbem.cli.thesis_commands import compare_thesis, export_tables, reproduce

__all__ = ["EXAMPLES", "main"]

@click.group()
@click.version_option(package_name="brushbem", prog_name="brushbem")
def main() -> None:
    """Adhesive pull-off of punches, spheres and brushes on an elastic half-space."""


for _command in (run, init, validate, design, sweep, study, figure, report, export_tables, reproduce, compare_thesis):
    main.add_command(_command)
