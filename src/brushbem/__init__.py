"""brushbem: adhesive contact of brush structures with an elastic half-space.

The boundary element method on a regular grid, with FFT-accelerated influence
coefficients, for pull-off simulations of punches, spheres and brushes of
pillars on springs.

Sign convention: the base displacement d is positive when the indenter presses
into the half-space; pressure and force are positive when compressive.
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
    "pull_off": "api",
    "PullOff": "pulloff",
    "Grid": "structure",
    "Level": "structure",
    "Profile": "structure",
    "Tip": "structure",
    "Tilt": "structure",
    "Grading": "structure",
    "Viscoelastic": "viscoelastic",
    "PiecewiseLinear": "pillar_laws",
    "brush": "structure",
    "flat_punch": "structure",
    "sphere": "structure",
    "height_map": "structure",
    "ConfigError": "config",
    "RunConfig": "config",
    "load_config": "assembly",
    "parse_config": "assembly",
}

__all__ = [  # noqa: RUF022 - the version first, then the names of _PUBLIC
    "__version__", "ConfigError", "Grid", "Level", "Profile", "Tip", "Tilt", "Grading", "Viscoelastic",
    "PiecewiseLinear", "PullOff", "RunConfig", "brush", "flat_punch", "height_map", "load_config", "parse_config",
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
