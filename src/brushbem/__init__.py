"""brushbem: adhesive contact of brush structures with an elastic half-space.

The boundary element method on a regular grid, with FFT-accelerated influence
coefficients, for pull-off simulations of punches, spheres and brushes of
pillars on springs.

Sign convention: the base displacement d is positive when the indenter presses
into the half-space; pressure and force are positive when compressive.
"""

from importlib.metadata import PackageNotFoundError, version

try:
    __version__ = version("brushbem")
except PackageNotFoundError:  # running from a source tree that is not installed
    __version__ = "0+unknown"

__all__ = ["__version__"]
