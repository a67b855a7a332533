"""Result files of one case: ``summary.json`` and ``result.nc``.

``summary.json``
    The `CaseResult.summary` mapping, indented JSON.  JSON has no infinity or
    NaN; such values are written as the strings ``"inf"``, ``"-inf"``,
    ``"nan"`` (never ``null``, which would read as "missing").

``result.nc`` (NetCDF-4 through h5netcdf)
    The load path along dimension ``step`` (``displacement``, ``force``,
    ``contact_area``, ``cg_iterations``, ``converged``, ``loading``,
    ``attached_pillars``) and the snapshots along dimension ``stage``, whose
    coordinate holds the stage names (``max_preload``, ``zero_force``,
    ``adhesive_force``, ``half_detached``, ``before_separation``: those the
    path passed through), with the base displacement and the force of each
    moment as the coordinates ``stage_displacement`` and ``stage_force``:
    ``pressure`` (float) and ``contact`` (int8, 1 = in contact) on dimensions
    ``(stage, y, x)``, and ``pillar_force`` on ``(stage, pillar)``;
    coordinates ``x``, ``y`` are element centres in units of length, centred
    on the domain: x_i = (i + 1/2) h - L/2.  Per pillar (dimension
    ``pillar``): ``pillar_x``, ``pillar_y``, ``pillar_offset``,
    ``pillar_elements``, ``pillar_stiffness`` (pillars on springs),
    ``pillar_separation_displacement``, ``pillar_max_tension``,
    ``pillar_max_tension_displacement``; ``cross_section_adhesive_force`` is
    the pressure along the element row through the centre at the
    adhesive-force moment (thesis Fig. 7-4).  Global attributes record
    provenance: ``brushbem_version``, ``config`` (the resolved configuration
    as JSON), ``seeds``, ``backend``, ``summary`` (JSON), and every entry of
    `CaseResult.attributes`.  Files written before the ``stage`` dimension
    (one variable per stage, ``pressure_<name>``) are read as well
    (`stage_field`, `from_dataset`).

Every file is written to a temporary file in the output folder and moved into
place with `os.replace`, so a reader never sees a half-written file.  The two
files form one result: both carry the same ``run_id``; ``result.nc`` is moved
into place first and ``summary.json`` last, so that a run killed between the
two leaves a pair whose ids differ, which `read_case` refuses
(`InconsistentCaseError`) instead of pairing an old dataset with a new
summary.  A NetCDF file is rendered in memory and written by Python (up to
`IN_MEMORY_LIMIT` bytes); a larger one, after a free-space check, is streamed
by HDF5 through a Python file object that never passes a failed write on to
HDF5 (`_GuardedFile`).  Either way a full disk or a quota is an ``OSError``
with its errno, never a crash inside the HDF5 library.

Sign convention: d > 0 presses into the half-space; pressure and force are
positive when compressive.

The package's modules: `brushbem.io.atomic` (file names, atomic writes,
temporaries, folder locks, free space), `brushbem.io.encoding` (JSON and
NetCDF attribute values), `brushbem.io.dataset` (the layout of
``result.nc``), `brushbem.io.writing` (`write_dataset`, `write_case`, the
streamed writing) and `brushbem.io.reading` (`read_case`, `from_dataset`,
`load_result`).  Every name is re-exported here; a test that patches a
module global (``IN_MEMORY_LIMIT``, ``_check_free_space``, ``open``) patches
`brushbem.io.writing`, where it is read.
"""

from __future__ import annotations

from brushbem.io.atomic import (
    CURVE_FILE,
    DATASET_FILE,
    SUMMARY_FILE,
    FolderBusyError,
    UnsafeLockError,
    atomic_path,
    check_writable,
    exclusive_folder,
    remove_stale_temporaries,
    temporary_of,
)
from brushbem.io.atomic import _check_free_space as _check_free_space  # patch it in `brushbem.io.writing`
from brushbem.io.dataset import REFERENCES, to_dataset
from brushbem.io.encoding import netcdf_attributes
from brushbem.results.plain import from_json_safe
from brushbem.io.reading import (
    InconsistentCaseError,
    from_dataset,
    load_result,
    read_case,
    stage_field,
    stages,
    summary_from_mapping,
)
from brushbem.io.writing import IN_MEMORY_LIMIT, source_commit, write_case, write_curve, write_dataset

__all__ = [
    "CURVE_FILE",
    "DATASET_FILE",
    "IN_MEMORY_LIMIT",
    "REFERENCES",
    "SUMMARY_FILE",
    "FolderBusyError",
    "InconsistentCaseError",
    "UnsafeLockError",
    "atomic_path",
    "check_writable",
    "exclusive_folder",
    "from_dataset",
    "from_json_safe",
    "load_result",
    "netcdf_attributes",
    "read_case",
    "remove_stale_temporaries",
    "source_commit",
    "stage_field",
    "stages",
    "summary_from_mapping",
    "temporary_of",
    "to_dataset",
    "write_case",
    "write_curve",
    "write_dataset",
]
