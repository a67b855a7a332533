"""One run of a case: from a validated configuration to its typed result.

Modules
    `assembly`
        Builds the problem and the load path of a validated configuration;
        the one place that maps the numerics' parameter errors to
        configuration keys.
    `case`, `pulloff`
        One run of a case (`run_case`) and its typed result (`PullOff`),
        which `brushbem.run` returns.
    `refine`
        Richardson extrapolation over grids (``--refine``).

The records a run produces live in `brushbem.results` (below the load path
and the files), its figures in `brushbem.figures`, the memory rule with the
configuration (`brushbem.config.resources`); the cost of a run before it runs
is `brushbem.sweep.estimate`, the design of pillar lengths `brushbem.design`,
the reports `brushbem.report`.
"""
