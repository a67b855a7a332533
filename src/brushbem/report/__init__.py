"""Reports, above the sweeps, the studies and the thesis comparison they read.

Modules
    `sweeps`
        A sweep's or a study's figures and its HTML report (`write_report`).
    `html`
        The HTML pieces of that report.
    `run`
        The HTML report of one run folder (``brushbem report RUN_DIR``).
"""
