"""Reading result files back: a case folder (`read_case`), its stages (`stages`, `stage_field`) and its
`CaseResult` (`from_dataset`, `load_result`); `InconsistentCaseError` refuses a pair from different runs.
"""

from __future__ import annotations

import dataclasses
import json
from pathlib import Path
from typing import Any

import numpy as np
import xarray as xr

from brushbem.results import CaseResult, RunSummary

from brushbem.io.atomic import DATASET_FILE, SUMMARY_FILE
from brushbem.io.encoding import _attribute
from brushbem.results.plain import from_json_safe


class InconsistentCaseError(ValueError):
    """A case folder whose ``summary.json`` and ``result.nc`` are not one result."""


def read_case(out_dir: str | Path) -> xr.Dataset:
    """Read the ``result.nc`` of a case folder into memory.

    Parameters
    ----------
    out_dir : path
        A folder written by `write_case`.

    Returns
    -------
    xarray.Dataset
        Fully loaded; the file is closed on return.

    Raises
    ------
    InconsistentCaseError
        When ``summary.json`` is missing, unreadable, or from another run than
        ``result.nc`` (a run killed while writing its files).
    """
    out_dir = Path(out_dir)
    dataset = xr.load_dataset(out_dir / DATASET_FILE, engine="h5netcdf")
    run_id = dataset.attrs.get("run_id")
    if run_id is not None:
        try:
            summary = json.loads((out_dir / SUMMARY_FILE).read_text(encoding="utf-8"))
        except (OSError, ValueError) as exc:
            raise InconsistentCaseError(
                f"{out_dir}: {SUMMARY_FILE} is missing or unreadable beside {DATASET_FILE} "
                f"(a run stopped while writing?): {exc}") from None
        if not isinstance(summary, dict) or summary.get("run_id") != run_id:
            raise InconsistentCaseError(
                f"{out_dir}: {SUMMARY_FILE} and {DATASET_FILE} come from different runs (a run stopped "
                "between writing them); rerun the case")
    return dataset


def stages(dataset: xr.Dataset) -> list[str]:
    """The snapshot stages a ``result.nc`` holds, in its order (either layout of `stage_field`)."""
    if "stage" in dataset.coords:
        return [str(name) for name in dataset["stage"].to_numpy()]
    return [str(name)[len("pressure_"):] for name in dataset.data_vars if str(name).startswith("pressure_")]


def stage_field(dataset: xr.Dataset, name: str, stage: str) -> xr.DataArray | None:
    """The snapshot ``name`` (``"pressure"``, ``"contact"`` or ``"pillar_force"``) at ``stage``, or None.

    Reads both layouts of ``result.nc``: one variable along ``stage``
    (``pressure(stage, y, x)``, with the moment in the coordinates
    ``stage_displacement`` and ``stage_force``), and one variable per stage
    in files written before it (``pressure_<stage>``, the moment in its
    attributes).  The field returned carries the moment as the attributes
    ``displacement`` and ``force`` either way.
    """
    if "stage" in dataset.coords:
        if name not in dataset.data_vars or stage not in stages(dataset):
            return None
        field = dataset[name].sel(stage=stage)
        moment = {"displacement": float(field["stage_displacement"]), "force": float(field["stage_force"])}
        field = field.drop_vars([coord for coord in ("stage", "stage_displacement", "stage_force")
                                 if coord in field.coords])
        return field.assign_attrs(moment)
    legacy = f"{name}_{stage}"
    return dataset[legacy] if legacy in dataset.data_vars else None


def from_dataset(dataset: xr.Dataset) -> CaseResult:
    """The `CaseResult` of a ``result.nc`` (`to_dataset`'s layout), for figures and analysis.

    The curve, the snapshots (pressure, contact and per-pillar forces with
    their moment), the per-pillar arrays, the summary and the provenance
    attributes are read back; nothing is recomputed.
    """
    from brushbem.results import Curve, Snapshot

    def column(name: str, dtype: Any, default: Any = 0) -> np.ndarray:
        if name in dataset:
            return np.asarray(dataset[name].to_numpy(), dtype=dtype)
        return np.full(dataset.sizes.get("step", 0), default, dtype=dtype)

    curve = Curve(
        displacement=column("displacement", float), force=column("force", float),
        contact_area=column("contact_area", float), cg_iterations=column("cg_iterations", np.int64),
        converged=column("converged", bool, True), loading=column("loading", bool, False),
        attached_pillars=column("attached_pillars", np.int64),
    )
    snapshots = []
    for stage in stages(dataset):
        pressure = stage_field(dataset, "pressure", stage)
        if pressure is None or not {"displacement", "force"} <= set(pressure.attrs):
            continue  # a stage without its pressure field (a file cut short or edited): no snapshot
        contact = stage_field(dataset, "contact", stage)
        pillar_force = stage_field(dataset, "pillar_force", stage)
        forces = None if pillar_force is None else np.asarray(pillar_force.to_numpy(), dtype=float)
        snapshots.append(Snapshot(
            name=stage, displacement=float(pressure.attrs["displacement"]), force=float(pressure.attrs["force"]),
            pressure=np.asarray(pressure.to_numpy(), dtype=float),
            contact=(np.asarray(contact.to_numpy(), dtype=bool) if contact is not None
                     else np.zeros(pressure.shape, dtype=bool)),
            pillar_force=None if forces is None or np.all(np.isnan(forces)) else forces,
        ))
    pillars = {str(name)[len("pillar_"):]: dataset[name].to_numpy() for name in dataset.data_vars
               if str(name).startswith("pillar_") and not str(name).startswith("pillar_force")}
    x = dataset["x"].to_numpy() if "x" in dataset.coords else np.array([])
    attributes = {str(key): _attribute(value) for key, value in dataset.attrs.items()}
    summary = attributes.pop("summary", {})
    return CaseResult(
        curve=curve, snapshots=tuple(snapshots), summary=summary_from_mapping(summary),
        attributes=attributes, element_size=float(x[1] - x[0]) if x.size > 1 else 1.0, pillars=pillars,
    )


def summary_from_mapping(mapping: Any) -> RunSummary | dict[str, Any]:
    """The typed `RunSummary` of a decoded ``summary.json`` or ``summary`` attribute, nested records rebuilt.

    A mapping without ``adhesive_force`` (no run's summary: an empty attribute) stays a plain dict.

    Raises
    ------
    ValueError
        A run's summary of another layout (a key that is no field, a field missing), named.
    """
    if not isinstance(mapping, dict):
        return {}
    mapping = from_json_safe(mapping)
    if "adhesive_force" not in mapping:
        return mapping
    return RunSummary.from_mapping(mapping)


def load_result(path: str | Path) -> CaseResult:
    """The `CaseResult` of a case folder (``brushbem run --out``) or of one ``.nc`` file (a sweep's case).

    From a case folder the summary is ``summary.json``'s, with its ``run_id`` and ``provenance``; from
    one ``.nc`` file its ``summary`` attribute's.
    """
    path = Path(path)
    if path.is_dir():
        result = from_dataset(read_case(path))
        try:
            saved = json.loads((path / SUMMARY_FILE).read_text(encoding="utf-8"))
        except (OSError, ValueError):  # no summary.json beside a result.nc of no run_id: the dataset's summary
            return result
        return dataclasses.replace(result, summary=summary_from_mapping(saved))
    if path.is_file():
        return from_dataset(xr.load_dataset(path, engine="h5netcdf"))
    raise FileNotFoundError(f"{path}: no such case folder or result file")
