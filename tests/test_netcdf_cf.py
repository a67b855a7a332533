"""result.nc follows CF-1.10 where a checker looks (cfchecks needs the UDUNITS-2 C library; this is its subset).

* global ``Conventions = "CF-1.10"``, ``title``, ``source``, ``references``
  (the thesis and papers brushbem implements);
* every dimension has a coordinate variable (``step``, ``x``, ``y``,
  ``pillar``);
* every numeric variable has a ``units`` that UDUNITS parses: brushbem's
  quantities are in the units of the configuration's inputs, named by its
  ``[units]`` table (``"mm"``, ``"N"``) or, without it, the dimensionless
  ``"1"``, with the physical ``dimension`` beside it; or it is a flag
  variable with ``flag_values`` and as many ``flag_meanings``.
"""

from __future__ import annotations

import json
import re

import h5py
import numpy as np
import pytest

from brushbem.runs.assembly import load_config
from brushbem.runs.case import run_case
from brushbem.config.schema import UnitsConfig
from brushbem.io import write_case

#: A product of SI-prefixed UDUNITS-2 symbols with integer powers ("N mm-1", "MPa cm2", "um2"): the
#: subset of the UDUNITS-2 grammar brushbem writes, or the dimensionless "1".
_SYMBOL = re.compile(r"^(p|n|u|m|c|k|M|G)?(m|Pa|N|J)(-?[1-9])?$")


def parseable(unit: str) -> bool:
    return unit == "1" or all(_SYMBOL.match(token) for token in unit.split(" "))


@pytest.fixture(scope="module", params=[None, ("mm", "MPa"), ("um", "kPa")], ids=["dimensionless", "mm-MPa",
                                                                                 "um-kPa"])
def result_file(request, tmp_path_factory):
    config = load_config("examples/default.toml")
    update = {"grid": config.grid.model_copy(update={"elements": 64}),
              "indenter": config.indenter.model_copy(update={"pillars_per_side": 4, "pillar_radius": 0.0489})}
    if request.param is not None:
        update["units"] = UnitsConfig(length=request.param[0], stress=request.param[1])
    config = config.model_copy(update=update)
    result = run_case(config).result
    out = tmp_path_factory.mktemp("cf")
    write_case(result, out, config=config)
    return out / "result.nc"


def test_the_unit_grammar_check_refuses_what_udunits_refuses():
    assert parseable("N mm-1") and parseable("MPa cm2") and parseable("um2") and parseable("1")
    assert not parseable("length") and not parseable("force / length") and not parseable("N/mm")


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
                assert parseable(_text(attrs.get("units"))), (name, attrs.get("units"))
        # The physical dimension is kept for readers (e.g. plotting labels).
        assert ds["displacement"].attrs["dimension"] == "length"
        assert ds["force"].attrs["dimension"] == "force"


def test_declared_units_name_every_dimension(result_file, request):
    """[units] length = "mm", stress = "MPa": forces in N, stresses in MPa, lengths in mm (an MPa mm^2 is
    a newton); um and kPa: forces in nN (1e3 Pa x 1e-12 m^2); no [units]: all dimensionless."""
    import xarray as xr

    expected = {None: ("1", "1", "1"), ("mm", "MPa"): ("mm", "N", "MPa"), ("um", "kPa"): ("um", "nN", "kPa")}
    declared = request.node.callspec.params["result_file"]  # what the fixture configured, not what the file says
    with xr.open_dataset(result_file, decode_cf=False) as ds:
        units = tuple(ds[name].attrs["units"] for name in ("displacement", "force", "pressure"))
        recorded = json.loads(ds.attrs["config"]).get("units")
    assert units == expected[declared]
    assert recorded == (None if declared is None else {"length": declared[0], "stress": declared[1]})


def test_a_run_records_its_provenance(tmp_path):
    """summary.json says which version, commit, time, units and configuration gave its numbers; result.nc its
    creation date (ACDD date_created)."""
    import json

    import xarray as xr

    import brushbem

    out = tmp_path / "run"
    brushbem.run({"halfspace": {"contact_modulus": 1.0, "work_of_adhesion": 1e-4}, "grid": {"size": 1.0, "elements": 32},
                  "indenter": {"shape": "flat_punch", "radius": 0.2}, "protocol": {"preload_displacement": 1e-3},
                  "units": {"length": "mm", "stress": "MPa"}}).save(out)
    provenance = json.loads((out / "summary.json").read_text())["provenance"]
    assert provenance["brushbem_version"] and provenance["created"].endswith("+00:00") and "commit" in provenance
    assert provenance["units"]["force"] == "N" and provenance["config"]["grid"]["elements"] == 32
    with xr.open_dataset(out / "result.nc") as dataset:
        assert dataset.attrs["date_created"] == provenance["created"]
