"""The layout of ``result.nc``: a `CaseResult` as an `xarray.Dataset` (`to_dataset`).

The curve along ``step``, the snapshots along ``stage``, the per-pillar
arrays along ``pillar``, CF-1.10 attributes and the provenance; and the
compression of the fields on the grid (`_field_compression`).
"""

from __future__ import annotations

from typing import Any

import numpy as np
import xarray as xr

from brushbem import __version__
from brushbem.config import RunConfig, config_to_dict
from brushbem.results import CaseResult
from brushbem.results.units import DIMENSIONS, Units

from brushbem.io.encoding import netcdf_attributes

_PILLAR_ATTRS: dict[str, dict[str, str]] = {
    "x": {"long_name": "pillar centre x", "units": "length"},
    "y": {"long_name": "pillar centre y", "units": "length"},
    "offset": {"long_name": "pillar length offset g (0: longest pillar)", "units": "length"},
    "elements": {"long_name": "elements in the rasterised pillar footprint"},
    "stiffness": {"long_name": "stiffness of the pillar's own spring (level 1)", "units": "force / length"},
    "separation_displacement": {"long_name": "last base displacement with contact on the pull-off "
                                             "(nan: never in contact)", "units": "length"},
    "max_tension": {"long_name": "largest tensile force carried on the pull-off (>= 0)", "units": "force"},
    "max_tension_displacement": {"long_name": "base displacement at the pillar's largest tension (nan: never in "
                                             "tension)", "units": "length"},
}


#: What brushbem's equations and figures refer to (the NetCDF ``references`` attribute).
REFERENCES = (
    "X. He, The Boundary Element Method Simulation of Adhesion of Brush-Structures (doctoral thesis; brushbem's "
    "eq., Fig. and sec. numbers refer to it); X. He, Q. Li, V. L. Popov, Lubricants 8 (2020) 94, "
    "doi:10.3390/lubricants8100094; X. He, Q. Li, V. L. Popov, The Journal of Adhesion (2021), "
    "doi:10.1080/00218464.2021.1939017; R. Pohrt, V. L. Popov, Facta Universitatis, Series: Mechanical "
    "Engineering (2015) (the detachment criterion)"
)

def _units_of(result: CaseResult, config: RunConfig | None) -> Units:
    """The configuration's ``[units]`` (`brushbem.results.units`): from ``config``, else from the provenance."""
    return Units.from_config(config) if config is not None else Units.of_record(result.attributes)


def _cf_variables(variables: dict[str, xr.Variable], coords: dict[str, xr.Variable], units: Units) -> None:
    """CF-1.10 attributes: parseable units, flags for masks and booleans.

    The quantities are in the units of the configuration's inputs (E* sets the
    stress, grid.size the length): with ``[units]`` their UDUNITS names, without
    it CF's dimensionless ``"1"``; the physical dimension is always kept in the
    attribute ``dimension``.
    """
    for variable in (*variables.values(), *coords.values()):
        attrs = variable.attrs
        unit = attrs.get("units")
        if unit in DIMENSIONS:
            attrs["dimension"] = unit
            attrs["units"] = units.of(unit)
        elif variable.dtype == np.int8 and "contact" in attrs.get("long_name", ""):
            attrs["flag_values"] = np.array([0, 1], dtype=np.int8)
            attrs["flag_meanings"] = "not_in_contact in_contact"
        elif variable.dtype == bool:  # stored as int8 0 / 1 (xarray's encoding of booleans)
            attrs["flag_values"] = np.array([0, 1], dtype=np.int8)
            attrs["flag_meanings"] = "false true"
        elif unit is None and np.issubdtype(variable.dtype, np.number):
            attrs["units"] = "1"


def _stage_variables(result: CaseResult, h: float, n_pillars: int, variables: dict[str, xr.Variable],
                     coords: dict[str, xr.Variable]) -> None:
    """The snapshots along dimension ``stage``: ``pressure``, ``contact`` (and ``pillar_force``), one variable each.

    The ``stage`` coordinate holds the stage names (in the order recorded), and
    ``stage_displacement`` and ``stage_force`` the moment of each along it.
    """
    snapshots = result.snapshots
    coords["stage"] = xr.Variable("stage", np.array([snapshot.name for snapshot in snapshots], dtype=object),
                                  {"long_name": "snapshot stage of the pull-off (thesis Fig. 4-3)"})
    coords["stage_displacement"] = xr.Variable(
        "stage", np.array([float(snapshot.displacement) for snapshot in snapshots]),
        {"long_name": "base displacement d at the stage (presses > 0)", "units": "length"})
    coords["stage_force"] = xr.Variable(
        "stage", np.array([float(snapshot.force) for snapshot in snapshots]),
        {"long_name": "normal force F at the stage (compressive > 0)", "units": "force"})
    variables["pressure"] = xr.Variable(
        ("stage", "y", "x"), np.stack([np.asarray(snapshot.pressure, dtype=float) for snapshot in snapshots]),
        {"long_name": "pressure at the stage (compressive > 0)", "units": "stress"})
    variables["contact"] = xr.Variable(
        ("stage", "y", "x"), np.stack([np.asarray(snapshot.contact, dtype=np.int8) for snapshot in snapshots]),
        {"long_name": "contact set at the stage (1 = in contact)"})
    if n_pillars and any(snapshot.pillar_force is not None for snapshot in snapshots):
        forces = np.full((len(snapshots), n_pillars), np.nan)
        for k, snapshot in enumerate(snapshots):
            if snapshot.pillar_force is not None:
                forces[k] = np.asarray(snapshot.pillar_force, dtype=float)
        variables["pillar_force"] = xr.Variable(
            ("stage", "pillar"), forces,
            {"long_name": "force on every pillar at the stage (compressive > 0; nan: not recorded)",
             "units": "force"})
    pattern = next((snapshot for snapshot in snapshots if snapshot.name == "adhesive_force"), None)
    if pattern is not None:
        # The stress cross-section through the centre at the critical
        # moment (thesis Fig. 7-4): the row of elements just above y = 0.
        row = pattern.pressure.shape[0] // 2
        variables["cross_section_adhesive_force"] = xr.Variable(
            "x", np.asarray(pattern.pressure[row], dtype=float),
            {"long_name": "pressure along the row through the centre at the adhesive-force moment "
                          "(compressive > 0)", "units": "stress",
             "y": float((row + 0.5) * h - pattern.pressure.shape[0] * h / 2),
             "displacement": float(pattern.displacement), "force": float(pattern.force)},
        )


def to_dataset(result: CaseResult, config: RunConfig | None = None) -> xr.Dataset:
    """The ``result.nc`` content of one run as an in-memory `xarray.Dataset`.

    Variables along ``step`` (the curve), ``x``/``y`` (the snapshots' pressure
    and contact) and ``pillar`` (per-pillar arrays), the summary and the
    provenance as attributes; ``config`` (the resolved configuration) is
    recorded when given.
    """
    return _dataset(result, config)


def _dataset(result: CaseResult, config: RunConfig | None) -> xr.Dataset:
    curve = result.curve
    h = float(result.element_size)
    variables: dict[str, xr.Variable] = {
        "displacement": xr.Variable(
            "step", np.asarray(curve.displacement, dtype=float),
            {"long_name": "base displacement d (presses > 0)", "units": "length"},
        ),
        "force": xr.Variable(
            "step", np.asarray(curve.force, dtype=float),
            {"long_name": "normal force F (compressive > 0)", "units": "force"},
        ),
        "contact_area": xr.Variable(
            "step", np.asarray(curve.contact_area, dtype=float),
            {"long_name": "contact area h^2 x elements in contact", "units": "length^2"},
        ),
        "cg_iterations": xr.Variable(
            "step", np.asarray(curve.cg_iterations, dtype=np.int64),
            {"long_name": "conjugate-gradient iterations spent on this row"},
        ),
        "converged": xr.Variable(
            "step", np.asarray(curve.converged, dtype=bool),
            {"long_name": "every solve behind this row converged"},
        ),
        "loading": xr.Variable(
            "step", np.asarray(curve.loading, dtype=bool),
            {"long_name": "row belongs to the loading branch (False: unloading)"},
        ),
        "attached_pillars": xr.Variable(
            "step", np.asarray(curve.attached_pillars, dtype=np.int64),
            {"long_name": "pillars with at least one element in contact"},
        ),
    }
    coords: dict[str, xr.Variable] = {}
    if result.snapshots:
        n = result.snapshots[0].pressure.shape[0]
        length = n * h
        centres = (np.arange(n) + 0.5) * h - length / 2
        coords = {
            "x": xr.Variable("x", centres, {"long_name": "element centre x", "units": "length"}),
            "y": xr.Variable("y", centres, {"long_name": "element centre y", "units": "length"}),
        }
    n_pillars = 0
    for snapshot in result.snapshots:
        if snapshot.pillar_force is not None:
            n_pillars = len(snapshot.pillar_force)
    for name, values in result.pillars.items():
        n_pillars = len(values)
    if n_pillars:
        coords["pillar"] = xr.Variable("pillar", np.arange(n_pillars), {"long_name": "pillar index"})
        for name, values in result.pillars.items():
            variables[f"pillar_{name}"] = xr.Variable("pillar", np.asarray(values), _PILLAR_ATTRS.get(name, {}))
    if result.snapshots:
        _stage_variables(result, h, n_pillars, variables, coords)
    coords["step"] = xr.Variable("step", np.arange(len(curve.displacement), dtype=np.int64),
                                 {"long_name": "index of the recorded state along the load path", "units": "1"})
    _cf_variables(variables, coords, _units_of(result, config))
    attributes: dict[str, Any] = {
        "Conventions": "CF-1.10",
        "title": "brushbem pull-off: force-displacement curve, contact snapshots and per-pillar results",
        "source": f"brushbem {__version__}",
        "references": REFERENCES,
        "brushbem_version": __version__,
        # JSON null: not recorded by the caller (not "no seeds" or "no config").
        "config": "null",
        "seeds": "null",
        "backend": "unknown",
        "summary": result.summary,
    }
    attributes.update(result.attributes)
    if config is not None:
        attributes["config"] = config_to_dict(config)
    return xr.Dataset(variables, coords=coords, attrs=netcdf_attributes(attributes))


def _field_compression(dataset: Any) -> dict[str, dict[str, Any]]:
    """Lossless gzip (with byte shuffling) for the fields on the grid (``y``, ``x``) of a result: the
    pressure and contact snapshots are mostly zeros outside the pillars, so a brush's file shrinks many
    times; one chunk per stage, so that reading one stage reads only its field.  Curves and per-pillar
    arrays stay uncompressed (small, and read whole)."""
    encoding = {}
    for name, variable in dataset.data_vars.items():
        if "x" in variable.dims and "y" in variable.dims and variable.ndim >= 2:
            chunks = tuple(1 if dim == "stage" else int(size) for dim, size in zip(variable.dims, variable.shape))
            encoding[str(name)] = {"zlib": True, "complevel": 4, "shuffle": True, "chunksizes": chunks}
    return encoding
