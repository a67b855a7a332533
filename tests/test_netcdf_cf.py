"""result.nc follows CF-1.10 where a checker looks (cfchecks needs the UDUNITS-2 C library; this is its subset).

* global ``Conventions = "CF-1.10"``, ``title``, ``source``, ``references``
  (the thesis and papers brushbem implements);
* every dimension has a coordinate variable (``step``, ``x``, ``y``,
  ``pillar``);
* every numeric variable has a ``units`` that UDUNITS parses: brushbem's
  quantities are in the units of the configuration's inputs, written as the
  dimensionless ``"1"`` with the physical ``dimension`` beside it; or it is
  a flag variable with ``flag_values`` and as many ``flag_meanings``.
"""

from __future__ import annotations

import h5py
import numpy as np
import pytest

from brushbem.assembly import load_config
from brushbem.case import run_case
from brushbem.io import write_case

#: Unit strings UDUNITS-2 accepts that brushbem may write.
PARSEABLE_UNITS = {"1"}


@pytest.fixture(scope="module")
def result_file(tmp_path_factory):
    config = load_config("examples/default.toml")
    config = config.model_copy(update={"grid": config.grid.model_copy(update={"elements": 64}),
                                       "indenter": config.indenter.model_copy(update={"pillars_per_side": 4,
                                                                                      "pillar_radius": 0.0489})})
    result, _ = run_case(config)
    out = tmp_path_factory.mktemp("cf")
    write_case(result, out, config=config)
    return out / "result.nc"


def _text(value) -> str:
    return value.decode() if isinstance(value, bytes) else str(value)


def test_global_attributes(result_file):
    with h5py.File(result_file, "r") as f:
        attrs = {k: _text(v) for k, v in f.attrs.items() if k in ("Conventions", "title", "source", "references")}
    assert attrs["Conventions"] == "CF-1.10"
    assert attrs["title"] and attrs["source"].startswith("brushbem")
    assert "Brush-Structures" in attrs["references"] and "10.3390/lubricants8100094" in attrs["references"]


def test_every_dimension_has_a_coordinate_and_every_variable_parseable_units(result_file):
    import xarray as xr

    with xr.open_dataset(result_file, decode_cf=False) as ds:
        for dim in ds.dims:
            assert dim in ds.variables, f"dimension {dim} has no coordinate variable"
        for name, variable in ds.variables.items():
            attrs = variable.attrs
            if "flag_values" in attrs:
                values = np.atleast_1d(attrs["flag_values"])
                meanings = _text(attrs["flag_meanings"]).split()
                assert len(values) == len(meanings), name
                continue
            if np.issubdtype(variable.dtype, np.number):
                assert _text(attrs.get("units")) in PARSEABLE_UNITS, (name, attrs.get("units"))
        # The physical dimension is kept for readers (e.g. plotting labels).
        assert ds["displacement"].attrs["dimension"] == "length"
        assert ds["force"].attrs["dimension"] == "force"
