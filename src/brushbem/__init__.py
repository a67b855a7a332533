"""brushbem: adhesive contact of brush structures with an elastic half-space.

The boundary element method on a regular grid, with FFT-accelerated influence
coefficients, for pull-off simulations of punches, spheres and brushes of
pillars on springs.

Sign convention: the base displacement d is positive when the indenter presses
into the half-space; pressure and force are positive when compressive.

The package, from the floor to the applications (the order
``tests/test_architecture.py`` enforces):

- the floor: `brushbem.errors`, `brushbem.backend` (the array backend),
  `brushbem.settings` and `brushbem.results` (the typed records of a run);
- `brushbem.physics`: the half-space, the adhesion criterion, the pillars'
  connections (springs, laws, viscoelastic), the geometry
  (`physics.structure`) and the closed forms (`physics.theory`);
- `brushbem.config`: the schema of a run's TOML file, its rules, the memory rule;
- `brushbem.numerics`: the contact operator and the solvers;
- `brushbem.protocol`: the load path of a pull-off (fixed steps, events, the
  pillar-level model) and what it records;
- `brushbem.io` (the result files), `brushbem.figures`, `brushbem.runs`
  (assembly, running a case, its `PullOff`, refine) and `brushbem.design`;
- `brushbem.api` (`run`, `pull_off`, `load`) is the entry, re-exported here;
- the applications: `brushbem.sweep`, `brushbem.studies`,
  `brushbem.reproduction` (the thesis comparison), `brushbem.report` and
  `brushbem.cli`.
"""


def _version() -> str:
    """The installed distribution's version (importlib.metadata costs a tenth of a second: read on first use)."""
    from importlib.metadata import PackageNotFoundError, version

    try:
        return version("brushbem")
    except PackageNotFoundError:  # running from a source tree that is not installed
        return "0+unknown"

#: The public names and the module each lives in, imported on first use
#: (PEP 562): ``import brushbem`` stays light, and ``brushbem validate`` does
#: not load the numerics.
_PUBLIC = {
    "run": "api",
    "load": "api",
    "pull_off": "api",
    "PullOff": "runs.pulloff",
    "Grid": "physics.structure",
    "Level": "physics.structure",
    "Profile": "physics.structure",
    "Tip": "physics.structure",
    "Tilt": "physics.structure",
    "Grading": "physics.structure",
    "Viscoelastic": "physics.viscoelastic",
    "PiecewiseLinear": "physics.pillar_laws",
    "brush": "physics.structure",
    "flat_punch": "physics.structure",
    "sphere": "physics.structure",
    "height_map": "physics.structure",
    "ConfigError": "config",
    "RunConfig": "config",
    "load_config": "runs.assembly",
    "parse_config": "runs.assembly",
}

__all__ = [  # noqa: RUF022 - the version first, then the names of _PUBLIC
    "__version__", "ConfigError", "Grid", "Level", "Profile", "Tip", "Tilt", "Grading", "Viscoelastic",
    "PiecewiseLinear", "PullOff", "RunConfig", "brush", "flat_punch", "height_map", "load", "load_config", "parse_config",
    "pull_off", "run", "sphere",
]


def __getattr__(name: str):
    if name == "__version__":
        value = globals()["__version__"] = _version()
        return value
    module = _PUBLIC.get(name)
    if module is None:
        raise AttributeError(f"module 'brushbem' has no attribute {name!r}")
    from importlib import import_module

    value = getattr(import_module(f"{__name__}.{module}"), name)
    globals()[name] = value
    return value


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(_PUBLIC) | {"__version__"})
