"""result.nc keeps the snapshots as one variable each along a ``stage`` dimension (``pressure(stage, y, x)``,
``contact(stage, y, x)``, ``pillar_force(stage, pillar)``), whose coordinate names the stages and carries each
moment; files of the older layout (one variable per stage) are still read."""

from __future__ import annotations

import h5py
import numpy as np
import pytest
import xarray as xr

from brushbem.runs.assembly import parse_config
from brushbem.runs.case import run_case
from brushbem.io import from_dataset, load_result, read_case, stage_field, stages, write_case


@pytest.fixture(scope="module")
def brush_run():
    """A 2 x 2 brush on springs at N = 32 (a few tenths of a second): every stage field, pillar forces."""
    config = parse_config({
        "halfspace": {"contact_modulus": 1.0, "work_of_adhesion": 1e-4}, "grid": {"size": 1.0, "elements": 32},
        "indenter": {"shape": "brush", "layout": "square", "region": "square", "pillars_per_side": 2,
                     "pillar_radius": 0.1, "stiffness_ratio": 0.455},
        "protocol": {"preload_displacement": 0.002},
    })
    return run_case(config).result, config


def test_snapshots_are_one_variable_along_stage(brush_run, tmp_path):
    result, config = brush_run
    write_case(result, tmp_path, config=config)
    data = read_case(tmp_path)
    names = [snapshot.name for snapshot in result.snapshots]
    assert list(data["stage"].values) == names
    assert data["pressure"].dims == ("stage", "y", "x")
    assert data["contact"].dims == ("stage", "y", "x") and data["contact"].dtype == np.int8
    assert data["pillar_force"].dims == ("stage", "pillar")
    # No variable per stage any more.
    per_stage = {f"{field}_{name}" for field in ("pressure", "contact", "pillar_force") for name in names}
    assert not per_stage & set(map(str, data.data_vars))
    for snapshot in result.snapshots:
        at = data.sel(stage=snapshot.name)
        np.testing.assert_array_equal(at["pressure"], snapshot.pressure)
        np.testing.assert_array_equal(at["contact"].values.astype(bool), snapshot.contact)
        np.testing.assert_array_equal(at["pillar_force"], snapshot.pillar_force)
        assert float(at["stage_displacement"]) == snapshot.displacement
        assert float(at["stage_force"]) == snapshot.force
    assert data["stage_displacement"].attrs["dimension"] == "length"
    assert data["stage_force"].attrs["dimension"] == "force"
    # One compressed chunk per stage: reading a stage reads only its field.
    with h5py.File(tmp_path / "result.nc") as handle:
        assert handle["pressure"].chunks == (1, 32, 32) and handle["pressure"].compression == "gzip"
    # Read back as the same snapshots.
    back = from_dataset(data)
    assert [s.name for s in back.snapshots] == names
    for mine, theirs in zip(result.snapshots, back.snapshots):
        np.testing.assert_array_equal(mine.pressure, theirs.pressure)
        np.testing.assert_array_equal(mine.pillar_force, theirs.pillar_force)
        assert (mine.displacement, mine.force) == (theirs.displacement, theirs.force)
    assert "force" not in back.pillars and set(back.pillars) >= {"x", "y", "max_tension"}


def _legacy(result) -> xr.Dataset:
    """A result.nc of the layout before the stage dimension: pressure_<stage>, contact_<stage>, pillar_force_<stage>."""
    n = result.snapshots[0].pressure.shape[0]
    variables = {"displacement": ("step", result.curve.displacement), "force": ("step", result.curve.force)}
    for snapshot in result.snapshots:
        moment = {"displacement": snapshot.displacement, "force": snapshot.force}
        variables[f"pressure_{snapshot.name}"] = xr.Variable(("y", "x"), snapshot.pressure, moment)
        variables[f"contact_{snapshot.name}"] = xr.Variable(("y", "x"), snapshot.contact.astype(np.int8), moment)
        variables[f"pillar_force_{snapshot.name}"] = xr.Variable("pillar", snapshot.pillar_force, moment)
    centres = (np.arange(n) + 0.5) / n - 0.5
    return xr.Dataset(variables, coords={"x": centres, "y": centres})


def test_files_of_the_older_layout_are_still_read(brush_run, tmp_path):
    result, _ = brush_run
    path = tmp_path / "old.nc"
    _legacy(result).to_netcdf(path, engine="h5netcdf")
    with xr.open_dataset(path, engine="h5netcdf") as old:
        assert stages(old) == [snapshot.name for snapshot in result.snapshots]
        field = stage_field(old, "pressure", "adhesive_force")
        snapshot = next(s for s in result.snapshots if s.name == "adhesive_force")
        np.testing.assert_array_equal(field, snapshot.pressure)
        assert field.attrs["displacement"] == snapshot.displacement
        assert stage_field(old, "pressure", "no_such_stage") is None
    back = load_result(path)
    assert [s.name for s in back.snapshots] == [s.name for s in result.snapshots]
    for mine, theirs in zip(result.snapshots, back.snapshots):
        np.testing.assert_array_equal(mine.contact, theirs.contact)
        np.testing.assert_array_equal(mine.pillar_force, theirs.pillar_force)
    # The same accessor on the new layout gives the same field and moment.
    new = tmp_path / "new"
    write_case(result, new)
    field = stage_field(read_case(new), "pressure", "adhesive_force")
    assert field.dims == ("y", "x") and field.attrs["force"] == snapshot.force
    np.testing.assert_array_equal(field, snapshot.pressure)
