"""From a configuration to results, files, figures and reports.

Modules
    `assembly`
        Builds the problem and the load path of a validated configuration;
        the one place that maps the numerics' parameter errors to
        configuration keys.
    `case`, `pulloff`
        One run of a case (`run_case`) and its typed result (`PullOff`),
        which `brushbem.run` returns.
    `results`, `records`
        The typed records of a run: curve, snapshots, summary, theory.
    `refine`, `estimate`, `resources`
        Richardson extrapolation over grids (``--refine``), the cost of a
        run before it runs (``--estimate``), memory.
    `design`
        Pillar lengths or stiffnesses for equal load sharing (``brushbem design``).
    `plot`, `figstyle`, `report`, `report_html`, `run_report`, `units`
        Figures in one journal style, the study and run reports, units of the inputs.
"""
