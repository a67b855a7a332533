"""The pillar model (``method = "pillars"``) on large brushes: CPU time and peak memory against the pillar count.

The CPU time of the loading (the model's build included, to the preload) and
of the pull-off are reported apart.

The chapter-5 family of ``benchmarks/pillars.py`` (a square n x n lattice at
phi = 0.16, pillars of 3.6 elements' radius, N = 16 n; Gaussian lengths of
sigma~ d_c, k~ = 0.01 by default, pressed to F_c and pulled off to
separation), for every n of ``--sizes``.  Each run is a fresh process (its
peak resident memory is the child's ``ru_maxrss``) limited to
``--limit`` seconds; a run past the limit is reported as such with the
states it had reached.  Sizes up to ``--exact-max`` pillars per side run the
exact event path too, in the same way, and print the ratio of the CPU
times (the exact path over the model).  ``--kept-baseline`` runs the model a
second time with the kept inverse at every size (``settings.using(kept_pillars=None)``:
no CG on the lattice, `brushbem.pillars.cg`) and prints the ratio of
its CPU time to the default's and the relative differences of F_A and the
work.  ``--before REF`` runs the model a second time at every size on the
sources of the git revision REF (its ``src/`` and ``benchmarks/``, exported
to a temporary folder) and prints the ratio of that run's CPU times
(loading, pull-off, all) to this tree's, and the relative differences of F_A
and the work: before and after in one run.  ``--repeat R`` runs the model
(and the revision's) R times, alternating, and reports the median CPU times.
``--brush size`` takes the ``size`` study's brush instead (phi = 0.12, 3.1
elements' radius, sigma = sigma~ d_c, its sweep files' numbers with
``--seed 0``), ``--pillar-solve`` the load path's ``pillar_solve``, and
``--states K`` or ``--solves K`` stop every run after K states or K CG
solves (a partial run: its CPU time per CG solve and iterations per solve;
with ``--before`` their ratios).  Every run reports its CG solves and
iterations (and, where the revision counts them, its products and how many
took the far field in single precision).  ``--pull-off K`` loads once and
times the next K pull-off states (after the first) by every variant of
``--variants`` (a JSON list of `brushbem.settings.Switches` fields, each
with optional ``"env"`` variables, e.g. ``BRUSHBEM_FFT_WORKERS``), each in a
child forked at that state, ``--repeat`` rounds alternating: the median CPU
and wall seconds a state, and each variant's ratios to the first within a
round and the largest difference of a state's force from the first's, the
pull-off states at 10^5 pillars without a loading each (``--profile
FOLDER``: each child's cProfile statistics).

    nice python benchmarks/large_brush.py                       # 32, 64, 100
    nice python benchmarks/large_brush.py --sizes 32 64 100 316 --limit 3600
    nice python benchmarks/large_brush.py --sizes 64 100 --sigma 0 --exact-max 0 --kept-baseline
    nice python benchmarks/large_brush.py --sizes 32 100 316 --sigma 0.5 --limit 3600   # rough
    nice python benchmarks/large_brush.py --sizes 100 --sigma 0.5 --exact-max 0 --before main~3
    nice python benchmarks/large_brush.py --sizes 100 --brush size --sigma 0.1 --seed 0 --exact-max 0 \
        --pillar-solve cg --before main                  # the size study's sigma~ = 0.1 brush, CG throughout
    nice python benchmarks/large_brush.py --sizes 316 --brush size --sigma 0.1 --seed 0 --exact-max 0 \
        --solves 40 --before main                        # its first 40 CG solves at 10^5 pillars
    nice python benchmarks/large_brush.py --sizes 316 --brush size --sigma 0.1 --seed 0 --pull-off 200 \
        --variants '[{}, {"env": {"BRUSHBEM_FFT_WORKERS": "2"}}]' --repeat 2   # its pull-off, 1 or 2 threads

Measured (CPU seconds, medians): the chapter-5 brush (``--sizes 32 --sigma 1
--before c48c002 --repeat 3``, a machine loaded 5-6 on two cores) loading
0.84 s against 1.10 s before the loading's rounds were cut (local release,
replayed cycles), pull-off 1.93 s, the whole 2.78 s against the exact path's
42.1 s (1/15.2), F_A and the work the same to 2e-15; again with ``--repeat 5``
(load 3-4) loading 1.00 s against 1.20 s, the whole 3.17 s against 51.7 s
(1/16.3); with the far field's and the peels' fixed costs cut (``--before
fe2b011 --repeat 5``, load 2-4) 1.84 s against 1.93 s before and the exact
path's 50.3 s (1/27.4), F_A and the work the same to the last bit.  The
316 x 316 rough brush (sigma~ = 0.5) loads in 346-376 CPU s, peak 2.8-3.1
GiB; its pull-off keeps the inverse on its 4270 attached pillars (within
Switches.kept_partial_bytes) at about 0.15 s a state, 1.1 s by CG
(``--kept-partial 4096``); with the states held by element (`State.pressed`)
its whole pull-off ran (``--sizes 316 --sigma 0.5 --exact-max 0 --limit
3600``'s child, load 2-3): 15575 states, loading 345 and pull-off 1572 CPU s
(0.101 s a state), 1917 CPU s in all, peak 2.9 GB.  The 100 x 100 rough
brush (``--sizes 100 --sigma 0.5 --exact-max 0 --before c48c002 --repeat 2``,
load 4-7) 58.9 s, loading 12.5 s against 18.4 s, pull-off 46.3 s, F_A the
same to 1e-14.  The ``size`` study's sigma~ = 0.1 brush with the CG's
recycled Ritz vectors (``--sizes 316 --brush size --sigma 0.1 --seed 0
--exact-max 0 --states 200 --before 499ac23``, load 5-7): loading 510
against 558 CPU-s, the pull-off's first 195 states 118 against 162 (1.37x),
iterations a solve 13.4 against 19.8; at 100 (``--pillar-solve cg``, whole
run) 155 against 181 CPU-s (pull-off 1.22x), F_A and the work the same to
5e-12.  With the late iterations' far fields in single precision
(``--solves 40 --before 7791b03 --repeat 3``, load about 3): the first 40
CG solves at 316 x 316, the model's build included, 46.1 against 59.8
CPU-s (1.30x, medians).  With the far field by slabs of the spectrum and
the CG's vectors on the attached rows (``--states 205 --before 0ffb9c6``,
one core busy with another process): loading 282 against 332 CPU-s
(1.18x), the pull-off's first 200 states 68.5 against 91.1 (1.33x), the
same iterations; at 100 (``--pillar-solve cg``, whole run) 111 against 127
CPU-s, F_A and the work the same to 1.1e-13 and 3.6e-13.  Two threads for
the far field (``--pull-off 200 --variants '[{"env":
{"BRUSHBEM_FFT_WORKERS": "1"}}, {"env": {"BRUSHBEM_FFT_WORKERS": "2"}}]'
--repeat 2``, two cores shared with two or three other processes): 0.429
wall-s and 0.384 CPU-s a state against 0.364 and 0.353 on one (medians),
the same forces.  The 10^5 part projected to 3500-5500 CPU-s (1.0-1.5 h)
on one thread; run by the study (one worker, the other core busy) it took
3105 s of wall time, 2.46 GB resident (``docs/beyond/size``).  The numbers of every size are in the docstring of
`brushbem.pillars`.
"""

from __future__ import annotations

import argparse
import json
import os
import resource
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]

#: The switches entered for the rest of a child process, held: a `settings.using` block entered and dropped
#: is closed when it is collected, and its switches are reset at once.
_HELD: list = []


def _size_problem(per_side: int, ratio: float, sigma: float, seed: int):
    """The ``size`` study's brush (``docs/studies/make_size_sweeps.py``): phi = 0.12, 3.1 elements' radius,
    N = 16 n, sigma = sigma~ d_c, and its preload F_c."""
    import math

    from brushbem.physics.structure import Grid, brush
    from brushbem.protocol import ContactProblem
    from brushbem.runs.case import brush_scales

    grid = Grid(1.0, 16 * per_side)

    def build(roughness: float):
        indenter = brush(grid, layout="square", pillars_per_side=per_side,
                         pillar_radius=round(math.sqrt(0.12 / math.pi) / per_side, 9), contact_modulus=1.0,
                         work_of_adhesion=1e-4, stiffness=ratio, roughness=roughness, seed=seed)
        return ContactProblem(grid, indenter, contact_modulus=1.0, work_of_adhesion=1e-4)

    scales = brush_scales(build(0.0))
    # Rounded as the sweep files write them.
    return (build(round(sigma * abs(scales["rigid_brush_displacement"]), 10)),
            round(scales["rigid_brush_force"], 9))


class _Enough(Exception):
    """A partial run reached its CG solves (``LARGE_BRUSH_SOLVES``)."""


def _count_solves(counts: dict, most: int) -> None:
    """Count the pillar model's CG solves and iterations into ``counts`` (a revision without CG counts none);
    after ``most`` solves (0: no limit) stop the run (`_Enough`)."""
    try:
        from brushbem.pillars import cg
    except ImportError:
        return
    solve = cg.LatticeCG.solve

    def counted(self, *args, **kwargs):
        start, products, single = self.iterations, getattr(self, "products", 0), getattr(self, "single_products", 0)
        out = solve(self, *args, **kwargs)
        counts["cg_solves"] += 1
        counts["cg_iterations"] += self.iterations - start
        counts["cg_products"] = counts.get("cg_products", 0) + getattr(self, "products", 0) - products
        counts["cg_single_products"] = (counts.get("cg_single_products", 0) + getattr(self, "single_products", 0)
                                        - single)
        if most and counts["cg_solves"] >= most:
            raise _Enough
        return out

    cg.LatticeCG.solve = counted


def _child(per_side: int, method: str, ratio: float, sigma: float, seed: int) -> None:
    """One pull-off in this process: a JSON line every 500 states (its progress) and a last one with the results.

    ``LARGE_BRUSH_BRUSH = size``: the ``size`` study's brush (`_size_problem`); ``LARGE_BRUSH_SOLVE``: the load
    path's ``pillar_solve``; ``LARGE_BRUSH_STATES`` or ``LARGE_BRUSH_SOLVES``: stop after that many states or CG
    solves (a partial run: its CPU time per state and per CG solve)."""
    # The brush of `benchmarks/pillars.py` beside the sources run (``--before``: the revision's own).
    sys.path.insert(0, os.environ.get("LARGE_BRUSH_HELPERS", str(ROOT / "benchmarks")))
    from pillars import _problem

    from brushbem.pillars import solver as pillar_solver
    from brushbem.protocol import LoadPath
    from brushbem.protocol.paths import pull_off

    if os.environ.get("LARGE_BRUSH_BRUSH") == "size":
        _problem = _size_problem  # noqa: F811
    extra = {"pillar_solve": os.environ["LARGE_BRUSH_SOLVE"]} if os.environ.get("LARGE_BRUSH_SOLVE") else {}
    most_states = int(os.environ.get("LARGE_BRUSH_STATES") or 0)
    counts = {"cg_solves": 0, "cg_iterations": 0}
    _count_solves(counts, int(os.environ.get("LARGE_BRUSH_SOLVES") or 0))

    if method == "pillars-kept":
        method = "pillars"
        try:
            from brushbem import settings

            _HELD.append(settings.using(kept_pillars=None))  # for the rest of this child process
            _HELD[-1].__enter__()
        except (ImportError, AttributeError):  # a commit whose limit was a module attribute
            pillar_solver.KEPT_PILLARS = None
    if os.environ.get("LARGE_BRUSH_KEPT_PARTIAL"):  # --kept-partial: for the rest of this child process
        from brushbem import settings

        _HELD.append(settings.using(kept_partial=int(os.environ["LARGE_BRUSH_KEPT_PARTIAL"])))
        _HELD[-1].__enter__()
    start = time.process_time()
    problem, preload = _problem(per_side, ratio, sigma, seed)
    built = time.process_time() - start
    states, force, work, previous, attached, loaded = 0, 0.0, 0.0, None, 0, None
    wall = time.perf_counter()

    def partial(states: int, attached: int) -> None:
        total = time.process_time() - start
        print(json.dumps({"partial": True, "states": states, "cpu_seconds": round(total, 2),
                          "wall_seconds_child": round(time.perf_counter() - wall, 2), "attached": attached, **counts,
                          "cpu_seconds_per_cg_solve": round(total / max(counts["cg_solves"], 1), 3),
                          "cg_iterations_per_solve": round(counts["cg_iterations"] / max(counts["cg_solves"], 1),
                                                           2)}), flush=True)

    # The tips on their rasters: the model the exact path checks, which the recorded sizes ran.
    path = LoadPath(method=method, preload_force=preload, max_steps=10**8, pillar_tip_peel=False, **extra)
    fork = int(os.environ.get("LARGE_BRUSH_FORK") or 0)
    states_left = pull_off(problem, path)
    try:
        for state in states_left:
            states += 1
            if fork and not state.loading:  # the first pull-off state: its next ``fork`` by every variant
                print(json.dumps({"loading_cpu_seconds": round(time.process_time() - start, 2),
                                  "attached_at_preload": attached, "loading_states": states - 1, **counts}),
                      flush=True)
                _variants(states_left, state, fork, counts)
                return
            if most_states and states > most_states:
                partial(states - 1, state.attached_pillars)
                return
            if state.loading:
                attached = state.attached_pillars  # the last loading state's: at the preload
            else:
                if loaded is None:  # the loading's CPU time, the model's build included
                    loaded = time.process_time() - start
                    print(json.dumps({"loading_cpu_seconds": round(loaded, 2), "attached_at_preload": attached,
                                      "loading_states": states - 1, "loading_cg_solves": counts["cg_solves"],
                                      "loading_cg_iterations": counts["cg_iterations"]}), flush=True)
                force = max(force, -state.force)
                if previous is not None:  # the tensile force's integral over the pull (trapezoids)
                    work += 0.5 * (max(-state.force, 0.0) + max(-previous.force, 0.0)) * abs(
                        state.displacement - previous.displacement)
                previous = state
            if states % (20 if most_states else 500) == 0:
                print(json.dumps({"states": states, "cpu_seconds": round(time.process_time() - start, 2), **counts}),
                      flush=True)
    except _Enough:
        partial(states, attached)
        return
    total = time.process_time() - start
    print(json.dumps({"done": True, "states": states, "build_cpu_seconds": round(built, 2), **counts,
                      "cpu_seconds": round(total, 2), "loading_cpu_seconds": round(loaded or total, 2),
                      "pull_off_cpu_seconds": round(total - (loaded or total), 2), "attached_at_preload": attached,
                      "adhesive_force": force,
                      "work_of_separation": work}), flush=True)


def _variants(states_left, first, most: int, counts: dict) -> None:
    """``--pull-off``: the next ``most`` pull-off states after ``first``, once per variant and repeat, each in a
    child forked here (the same loaded model for all); a JSON line per child.

    ``LARGE_BRUSH_VARIANTS``: a JSON list of variants, each a dict of `brushbem.settings.Switches` fields and
    optionally ``"env"`` (environment variables set in the child, e.g. ``BRUSHBEM_FFT_WORKERS``);
    ``LARGE_BRUSH_REPEAT``: the rounds (alternating the variants); ``LARGE_BRUSH_PROFILE``: a folder where each
    child writes its cProfile statistics."""
    variants = json.loads(os.environ.get("LARGE_BRUSH_VARIANTS") or "[{}]")
    profile = os.environ.get("LARGE_BRUSH_PROFILE")
    for rep in range(int(os.environ.get("LARGE_BRUSH_REPEAT") or 1)):
        for number, variant in enumerate(variants):
            pid = os.fork()
            if pid:
                os.waitpid(pid, 0)
                continue
            try:
                variant = dict(variant)
                os.environ.update(variant.pop("env", {}))
                from brushbem import settings

                _HELD.append(settings.using(**variant))
                _HELD[-1].__enter__()
                profiler = None
                if profile:
                    import cProfile

                    profiler = cProfile.Profile()
                    profiler.enable()
                solves, iterations = counts["cg_solves"], counts["cg_iterations"]
                products, single = counts.get("cg_products", 0), counts.get("cg_single_products", 0)
                cpu, wall = time.process_time(), time.perf_counter()
                forces, previous, work = [], first, 0.0
                for state in states_left:
                    forces.append(state.force)
                    work += 0.5 * (max(-state.force, 0.0) + max(-previous.force, 0.0)) * abs(
                        state.displacement - previous.displacement)
                    previous = state
                    if len(forces) >= most:
                        break
                cpu, wall = time.process_time() - cpu, time.perf_counter() - wall
                if profiler is not None:
                    profiler.disable()
                    profiler.dump_stats(os.path.join(profile, f"variant{number}_round{rep}.prof"))
                print(json.dumps({"variant": number, "round": rep, "states": len(forces), "cpu_seconds": cpu,
                                  "wall_seconds": wall, "cg_solves": counts["cg_solves"] - solves,
                                  "cg_iterations": counts["cg_iterations"] - iterations,
                                  "cg_products": counts.get("cg_products", 0) - products,
                                  "cg_single_products": counts.get("cg_single_products", 0) - single,
                                  "adhesive_force": max(0.0, -first.force, *(-f for f in forces)),
                                  "work_of_separation": work, "forces": forces}), flush=True)
            finally:
                sys.stdout.flush()
                os._exit(0)


def _pull_off_variants(per_side: int, args) -> None:
    """``--pull-off K``: one loading, then K pull-off states by every variant in forked children (`_variants`):
    the median CPU and wall seconds a state, iterations a solve, each variant's ratios to the first (its CPU and
    wall over theirs) and the largest relative difference of a state's force from the first variant's."""
    command = [sys.executable, __file__, "--child", str(per_side), "pillars", str(args.stiffness_ratio),
               str(args.sigma), str(args.seed)]
    environment = dict(os.environ)
    environment["PYTHONPATH"] = os.pathsep.join([str(ROOT / "src"), environment.get("PYTHONPATH", "")])
    environment["LARGE_BRUSH_HELPERS"] = str(ROOT / "benchmarks")
    environment.update({"LARGE_BRUSH_BRUSH": args.brush, "LARGE_BRUSH_SOLVE": args.pillar_solve or "",
                        "LARGE_BRUSH_FORK": str(args.pull_off), "LARGE_BRUSH_VARIANTS": args.variants,
                        "LARGE_BRUSH_REPEAT": str(args.repeat), "LARGE_BRUSH_PROFILE": args.profile or ""})
    completed = subprocess.run(command, capture_output=True, text=True, env=environment)
    lines = [json.loads(line) for line in completed.stdout.splitlines() if line.startswith("{")]
    if completed.returncode != 0 or not lines:
        print(json.dumps({"failed": completed.stderr.strip().splitlines()[-3:]}), flush=True)
        return
    runs = [line for line in lines if "variant" in line]
    out = {"pillars": per_side**2, "pull_off_states": args.pull_off, "loading": lines[0], "variants": []}
    first = [run for run in runs if run["variant"] == 0]
    for number, variant in enumerate(json.loads(args.variants)):
        mine = [run for run in runs if run["variant"] == number]
        if not mine:
            continue
        entry = {"variant": variant, "rounds": len(mine),
                 "cpu_seconds_per_state": statistics.median(run["cpu_seconds"] / run["states"] for run in mine),
                 "wall_seconds_per_state": statistics.median(run["wall_seconds"] / run["states"] for run in mine),
                 "cg_iterations_per_solve": round(mine[0]["cg_iterations"] / max(mine[0]["cg_solves"], 1), 2),
                 "cg_solves_per_state": round(mine[0]["cg_solves"] / max(mine[0]["states"], 1), 2),
                 "cg_products": mine[0]["cg_products"], "cg_single_products": mine[0]["cg_single_products"],
                 "adhesive_force": mine[0]["adhesive_force"], "work_of_separation": mine[0]["work_of_separation"]}
        if number and first:
            # Ratios within a round (the same machine load on both), their median.
            pairs = [(a, b) for a in first for b in mine if a["round"] == b["round"]]
            entry["cpu_ratio_first_over_this"] = round(statistics.median(a["cpu_seconds"] / b["cpu_seconds"]
                                                                         for a, b in pairs), 3)
            entry["wall_ratio_first_over_this"] = round(statistics.median(a["wall_seconds"] / b["wall_seconds"]
                                                                          for a, b in pairs), 3)
            n = min(len(first[0]["forces"]), len(mine[0]["forces"]))
            scale = max(abs(f) for f in first[0]["forces"][:n]) or 1.0
            entry["force_max_rel_diff"] = max(abs(a - b) for a, b in zip(first[0]["forces"][:n],
                                                                         mine[0]["forces"][:n])) / scale
        out["variants"].append(entry)
    print(json.dumps(out), flush=True)


def _measure(per_side: int, method: str, args, sources: Path | None = None) -> dict:
    """Run one pull-off in a child process under the time limit: its last report and peak memory.

    ``sources``: a folder holding the package's ``src/`` to run (``--before``); by default this tree's, whatever
    an installed copy of the package would give."""
    command = [sys.executable, __file__, "--child", str(per_side), method, str(args.stiffness_ratio),
               str(args.sigma), str(args.seed)]
    environment = dict(os.environ)
    environment["PYTHONPATH"] = os.pathsep.join([str((sources or ROOT) / "src"), environment.get("PYTHONPATH", "")])
    environment["LARGE_BRUSH_HELPERS"] = str((sources or ROOT) / "benchmarks")
    if args.kept_partial is not None:
        environment["LARGE_BRUSH_KEPT_PARTIAL"] = str(args.kept_partial)
    environment["LARGE_BRUSH_BRUSH"] = args.brush
    environment["LARGE_BRUSH_SOLVE"] = args.pillar_solve or ""
    environment["LARGE_BRUSH_STATES"] = str(args.states or "")
    environment["LARGE_BRUSH_SOLVES"] = str(args.solves or "")
    before = resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss
    start = time.perf_counter()
    try:
        completed = subprocess.run(command, capture_output=True, text=True, timeout=args.limit, env=environment)
        output, timed_out = completed.stdout, False
        if completed.returncode != 0:
            return {"failed": completed.stderr.strip().splitlines()[-1:]}
    except subprocess.TimeoutExpired as expired:
        output = expired.stdout.decode() if isinstance(expired.stdout, bytes) else (expired.stdout or "")
        timed_out = True
    lines = [json.loads(line) for line in output.splitlines() if line.startswith("{")]
    last = {}
    for line in lines:  # the loading's report stays with a run stopped in its pull-off
        last.update(line)
    peak = resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss
    result = dict(last)
    result["wall_seconds"] = round(time.perf_counter() - start, 1)
    # ru_maxrss is the largest child so far (KiB on Linux): a new maximum is this child's.
    result["peak_memory_gb"] = round(peak / 2**20, 2) if peak > before else f"<= {before / 2**20:.2f}"
    if timed_out:
        result["timed_out_after_seconds"] = args.limit
    return result


def _against(model: dict, reference: dict, ratio_key: str, prefix: str) -> dict:
    """The reference's CPU time over the model's and the model's relative differences of F_A and the work."""
    if "done" not in model or "done" not in reference:
        return {}
    return {ratio_key: round(reference["cpu_seconds"] / model["cpu_seconds"], 2),
            f"{prefix}adhesive_force_rel_diff": model["adhesive_force"] / reference["adhesive_force"] - 1,
            f"{prefix}work_rel_diff": model["work_of_separation"] / reference["work_of_separation"] - 1}


def _median(runs: list[dict]) -> dict:
    """The first run's report with the median of every CPU time over ``runs`` (and each run's total)."""
    done = [run for run in runs if "done" in run or "partial" in run]
    if len(done) < len(runs) or len(runs) == 1:
        return runs[0] if len(runs) == 1 or not done else {**runs[0], "runs_done": len(done)}
    out = dict(done[0])
    for key in ("cpu_seconds", "loading_cpu_seconds", "pull_off_cpu_seconds", "build_cpu_seconds",
                "cpu_seconds_per_cg_solve", "wall_seconds"):
        if all(key in run for run in done):
            out[key] = statistics.median(run[key] for run in done)
    out["peak_memory_gb"] = max((run["peak_memory_gb"] for run in done if isinstance(run["peak_memory_gb"], float)),
                                default=done[0]["peak_memory_gb"])
    out["cpu_seconds_runs"] = [run["cpu_seconds"] for run in done]
    return out


def _export(revision: str, folder: Path) -> Path:
    """The ``src/`` and ``benchmarks/`` of git ``revision`` of this repository, exported into ``folder``."""
    archive = subprocess.run(["git", "-C", str(ROOT), "archive", revision, "src", "benchmarks"], capture_output=True,
                             check=True)
    subprocess.run(["tar", "-x", "-C", str(folder)], input=archive.stdout, check=True)
    return folder


def _before_after(now: dict, before: dict) -> dict:
    """The CPU times of ``before`` over ``now`` (loading, pull-off, all) and now's differences of F_A and work."""
    if "partial" in now and "partial" in before:  # the same states on both
        return {"cpu_ratio_before_over_now": round(before["cpu_seconds"] / now["cpu_seconds"], 3),
                "cpu_per_cg_solve_ratio_before_over_now": round(before["cpu_seconds_per_cg_solve"]
                                                                / now["cpu_seconds_per_cg_solve"], 3),
                "wall_ratio_before_over_now": round(before["wall_seconds"] / now["wall_seconds"], 3)}
    if "done" not in now or "done" not in before:
        return {}
    ratios = {f"cpu_ratio_before_over_now_{key}": round(before[f"{key}cpu_seconds"] / now[f"{key}cpu_seconds"], 3)
              for key in ("loading_", "pull_off_", "") if now[f"{key}cpu_seconds"] > 0}
    return {**ratios, "before_adhesive_force_rel_diff": now["adhesive_force"] / before["adhesive_force"] - 1,
            "before_work_rel_diff": now["work_of_separation"] / before["work_of_separation"] - 1}


def main() -> None:
    if len(sys.argv) > 1 and sys.argv[1] == "--child":
        per_side, method, ratio, sigma, seed = sys.argv[2:7]
        _child(int(per_side), method, float(ratio), float(sigma), int(seed))
        return
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", type=int, nargs="*", default=[32, 64, 100], help="pillars per side")
    parser.add_argument("--exact-max", type=int, default=32, help="largest size that runs the exact path too")
    parser.add_argument("--stiffness-ratio", type=float, default=0.01)
    parser.add_argument("--sigma", type=float, default=1.0, help="sigma~ = sigma / d_c")
    parser.add_argument("--seed", type=int, default=3)
    parser.add_argument("--limit", type=float, default=600.0, help="seconds per run")
    parser.add_argument("--kept-baseline", action="store_true",
                        help="also run the model with the kept inverse at every size (no CG on the lattice)")
    parser.add_argument("--before", metavar="REF", help="also run the model on the sources of git revision REF")
    parser.add_argument("--kept-partial", type=int, default=None,
                        help="Switches.kept_partial of the model's runs (the kept inverse on a partial set up to this "
                             "many attached pillars, in place of the memory budget Switches.kept_partial_bytes)")
    parser.add_argument("--repeat", type=int, default=1,
                        help="runs of the model (and of --before's) per size; their median CPU times")
    parser.add_argument("--brush", choices=("chapter5", "size"), default="chapter5",
                        help="the brush: benchmarks/pillars.py's chapter-5 family (phi = 0.16) or the size study's "
                             "(phi = 0.12, seed 0 with --seed 0)")
    parser.add_argument("--pillar-solve", choices=("auto", "kept", "cg"), default=None,
                        help="LoadPath.pillar_solve of the model's runs")
    parser.add_argument("--states", type=int, default=None,
                        help="stop every run after this many states (a partial run: CPU per state and per CG solve)")
    parser.add_argument("--solves", type=int, default=None,
                        help="stop every run after this many CG solves of the pillar model (a partial run)")
    parser.add_argument("--pull-off", type=int, default=None, metavar="K",
                        help="load once, then time the next K pull-off states by every --variants in forked "
                             "children (the same loaded state for all)")
    parser.add_argument("--variants", default="[{}]",
                        help="with --pull-off: a JSON list of variants, each a dict of Switches fields and "
                             "optionally \"env\" (environment variables)")
    parser.add_argument("--profile", metavar="FOLDER", default=None,
                        help="with --pull-off: write each child's cProfile statistics to FOLDER")
    args = parser.parse_args()
    if args.pull_off:
        for per_side in args.sizes:
            _pull_off_variants(per_side, args)
        return
    with tempfile.TemporaryDirectory(prefix="large_brush_before_") as folder:
        sources = _export(args.before, Path(folder)) if args.before else None
        for per_side in args.sizes:
            _size(per_side, args, sources)


def _size(per_side: int, args, sources: Path | None) -> None:
    """The line of one size: the model, and beside it what the options ask for."""
    now, before = [], []
    for _ in range(args.repeat):  # alternating, so that a change of the machine's load falls on both
        now.append(_measure(per_side, "pillars", args))
        if sources is not None:
            before.append(_measure(per_side, "pillars", args, sources))
    line = {"pillars": per_side**2, "pillars_per_side": per_side, "elements": 16 * per_side,
            "pillars_method": _median(now)}
    if sources is not None:
        line["before"] = _median(before)
        line.update(_before_after(line["pillars_method"], line["before"]))
    if args.kept_baseline:
        line["kept_inverse"] = _measure(per_side, "pillars-kept", args)
        line.update(_against(line["pillars_method"], line["kept_inverse"], "cpu_ratio_kept_over_default",
                             "kept_"))
    if per_side <= args.exact_max:
        line["events_method"] = _measure(per_side, "events", args)
        line.update(_against(line["pillars_method"], line["events_method"], "cpu_ratio_events_over_pillars",
                             ""))
    print(json.dumps(line), flush=True)


if __name__ == "__main__":
    main()
