"""The flat brushes' F_A in the continuum limit (h -> 0), by a spectral solution of the rigid tips on springs.

The exact event path converges slowly in the element size h (order 0.7-1,
with the staircase of the rasterised circles on top), so its extrapolation
from N = 128, 256 and 512 (``tips_extrapolated.csv``) is only as good as its
observed order: 1.3 % at k~ = 1e-5.  This script computes the limit the
exact path converges to directly, with no grid.

The problem (the families' flat brush, `validation.problem`): n x n rigid
flat circular tips of radius a on a square lattice of pitch
a sqrt(pi / phi), each on a linear spring k (k = k~ E* L), bonded to an
elastic half-space (surface deflection (1 / (pi E*)) int p / |x - x'| dA').
Each tip's pressure is expanded in the disk's spectral basis

    p_mn(r, theta) = (r / a)^m P_n^(m, -1/2)(1 - 2 r^2 / a^2) {cos, sin}(m theta) / sqrt(1 - r^2 / a^2),

(m + 2 n <= ``degree``), on which the half-space's own-disk operator is
diagonal: the deflection on the disk is pi a l_mn / (pi E*) times the same
polynomial, l_mn = Gamma(n + 1/2) Gamma(n + m + 1/2) / (n! (n + m)!) (at
m = n = 0 Kendall's flat punch, at m = 1, n = 0 the tilted one; checked by
direct quadrature in ``tests/test_pillar_continuum.py``).  The neighbours'
deflection on a tip is smooth and is projected onto the same basis
(Galerkin, Gauss-Legendre in s = sqrt(1 - r^2 / a^2) and the trapezoidal
rule in theta; ``nodes`` x ``angles`` points a disk).  The stress intensity
along a tip's edge is K(theta) = sqrt(pi a) sum_b c_b p_b(a, theta)
sqrt(1 - r^2 / a^2).

Detachment (the limit of the Pohrt-Popov criterion, as the lone tip's F_K
is the limit of its raster's pull-off, `brushbem.pillars.calibration`): a
tip comes off whole when the largest K on its edge reaches
K_c = sqrt(2 E* dgamma).  Ours (the thesis states none): once a flat tip's
edge starts to peel its contact shrinks, which raises its mean stress
intensity at the same load or the same displacement (Kendall's
instability), so no partly peeled tip is held.  The brush is pulled by its
base displacement d; between detachments every force is linear in d, so
the path is a sequence of events, and F_A is the largest total force at an
event (before its drop).

Measured (``continuum_reference.csv``; every value changes by less than
2e-9 from degree 12 to 16 and from 12 x 48 to 16 x 64 points; 76 CPU-s in
all): the 4 x 4 brush 0.0089535 (k~ = 1e-5) and 0.0076990 (10); the 8 x 8
brush 0.0118133 (1e-5, the middle of an edge first, 0.7771 n^2 F_K) and
0.0081111 (10, at the fifth event: the four corners first, 60 tips
attached at F_A, as in the exact path).

The exact path lies above it at every resolution (``continuum_exact.csv``,
``--exact``, 179 CPU-s): the 8 x 8 brush +10.0 / +6.6 / +4.4 % at 3.6 /
7.2 / 14.4 elements per radius (k~ = 1e-5) and +10.4 / +6.3 / +4.2 %
(10); its first-order extrapolation (``tips_extrapolated.csv``) +2.25 %
and +2.20 %; the 4 x 4 brush at 28.9 per radius +3.1 % and +3.5 %.  Its
first detachment of an element is no limit either (at 28.9 per radius
1.4 % below the first point here, its F_A then 4.6-5.0 % above that
detachment).  So the first point is a lower bound of the brush's limit, not
the limit: a flat tip whose K varies along its edge peels stably where K
peaks before the peel runs away.  How much that adds is measured on one tip
at a time in its continuum field by ``tilted.py``, which gives the limit.
`Brush` also takes tips at any centres (the random family's brush,
``front.py --random``).

Rows go to ``continuum.csv`` as each completes (atomically; a rerun skips
the rows already there): per brush, k~ and resolution (``degree``,
``nodes``, ``angles``) F_A, the tips attached at F_A, F_A / (n^2 F_K) and
the CPU time.  ``continuum_reference.csv`` (written at the end of every run
and by ``--reference``) holds per brush and k~ the value at the finest
resolution and its error: the sum of the changes from the next coarser
degree and from the coarser quadrature.  ``--exact`` runs the exact path's
rows (``continuum_exact.csv``: its F_A and the force at its first
detachment of an element, on the families' raster N = 16 n times 1, 2, 4
and, for 4 x 4, 8).

    nice python docs/pillars/continuum.py               # every row, resuming
    nice python docs/pillars/continuum.py --exact       # the exact path's rows, resuming
    python docs/pillars/continuum.py --reference        # only rewrite continuum_reference.csv
"""

from __future__ import annotations

import argparse
import math
import sys
import time
from pathlib import Path

import numpy as np
import scipy.sparse.linalg
import scipy.special

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
from calibration import write as write_table  # noqa: E402
from reference import load  # noqa: E402

TABLE = HERE / "continuum.csv"
REFERENCE = HERE / "continuum_reference.csv"
EXACT = HERE / "continuum_exact.csv"
EXACT_FIELDS = ("pillars_per_side", "stiffness_ratio", "tip_factor", "tip_elements_per_radius",
                "first_detachment_force", "adhesive_force", "peel_gain", "attached_at_pull_off", "cpu_seconds")
#: (pillars per side, k~, tips' factor of the grid N = 16 n): the exact path's first detachment and F_A.
EXACT_CASES = tuple((n, k, f) for n, factors in ((4, (1, 2, 4, 8)), (8, (1, 2, 4))) for k in (1e-5, 10.0)
                    for f in factors)
FIELDS = ("pillars_per_side", "stiffness_ratio", "degree", "nodes", "angles", "adhesive_force",
          "attached_at_pull_off", "force_by_ideal_sharing", "events", "cpu_seconds")
REFERENCE_FIELDS = ("pillars_per_side", "stiffness_ratio", "degree", "nodes", "angles", "adhesive_force",
                    "error", "attached_at_pull_off", "force_by_ideal_sharing")
#: The families' flat brush (`validation.problem`): domain side L = 1, E* = 1, dgamma = 1e-4, phi = 0.16.
PHI, DGAMMA, MODULUS = 0.16, 1e-4, 1.0
#: (pillars per side, k~, degree, nodes, angles): the resolutions per case, coarse to fine; the last two
#: degrees at the finest quadrature and the finest degree at the coarser quadrature give the error.
RESOLUTIONS = ((8, 12, 48), (12, 12, 48), (16, 12, 48), (16, 16, 64))
CASES = tuple((n, k, *res) for n in (4, 8) for k in (1e-5, 10.0) for res in RESOLUTIONS)


def modes(degree: int) -> list[tuple[int, int, int]]:
    """(m, n, sine) of the basis, m + 2 n <= ``degree``; the first is the uniform mode (0, 0, 0)."""
    return [(m, n, s) for m in range(degree + 1) for n in range((degree - m) // 2 + 1)
            for s in ((0,) if m == 0 else (0, 1))]


def eigenvalue(m: int, n: int) -> float:
    """l_mn: the own-disk operator int p / |x - x'| dA' on the unit disk is pi l_mn on p_mn."""
    g = scipy.special.gammaln
    return math.exp(g(n + 0.5) + g(n + m + 0.5) - g(n + 1) - g(n + m + 1))


def polynomial(basis, r, theta) -> np.ndarray:
    """p_mn sqrt(1 - r^2) on the unit disk at (r, theta): shape (len(r), len(basis))."""
    r, theta = np.asarray(r, float), np.asarray(theta, float)
    out = np.empty((r.size, len(basis)))
    for b, (m, n, s) in enumerate(basis):
        angular = np.sin(m * theta) if s else np.cos(m * theta)
        out[:, b] = r**m * scipy.special.eval_jacobi(n, m, -0.5, 1 - 2 * r**2) * angular
    return out


def quadrature(nodes: int, angles: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Points (x, y) of the unit disk and weights w with sum w f = int f / sqrt(1 - r^2) dA (exact for
    polynomials of degree < 2 ``nodes`` in s and trigonometric ones below ``angles`` in theta)."""
    s, ws = np.polynomial.legendre.leggauss(nodes)
    s, ws = (s + 1) / 2, ws / 2
    theta = 2 * np.pi * np.arange(angles) / angles
    r = np.sqrt(1 - s**2)
    rr, tt = np.meshgrid(r, theta, indexing="ij")
    weights = np.repeat(ws, angles) * (2 * np.pi / angles)
    return rr.ravel(), tt.ravel(), weights


class Brush:
    """The Galerkin operator of n x n unit disks at ``pitch`` (in radii) and its solutions; or, with ``centres``
    (shape (tips, 2), in radii; ``per_side`` and ``pitch`` then unused), of unit disks at any centres that keep
    them apart: one block per ordered pair of tips (i, j), those of pairs closer than ``near[0]`` (centres'
    distance in radii) on the finer quadrature of ``near[1]`` x ``near[2]`` points a disk, the basis' norms exact.
    The lattice's blocks are keyed by the pair's offset (target - source) and computed once per offset."""

    def __init__(self, per_side: int, pitch: float, degree: int, nodes: int, angles: int,
                 centres: np.ndarray | None = None, near: tuple[float, int, int] | None = None) -> None:
        self.basis = modes(degree)
        r, theta, weights = quadrature(nodes, angles)
        phi = polynomial(self.basis, r, theta)
        self.own = np.array([math.pi * eigenvalue(m, n) for m, n, _ in self.basis])
        self.norm = np.einsum("q,qb,qb->b", weights, phi, phi)
        self.edge_angles = 2 * np.pi * np.arange(4096) / 4096
        self.edge = polynomial(self.basis, np.ones(4096), self.edge_angles)
        self.blocks: dict[tuple[int, int], np.ndarray] = {}
        if centres is not None:
            self._pairs(np.asarray(centres, float), (r, theta, weights, phi), near)
            return
        grid = np.array([(i, j) for i in range(per_side) for j in range(per_side)])
        self.centres = pitch * grid.astype(float)
        x, y = r * np.cos(theta), r * np.sin(theta)
        weighted = phi * weights[:, None]
        for dx in range(-(per_side - 1), per_side):
            for dy in range(-(per_side - 1), per_side):
                if (dx, dy) == (0, 0) or (dx, dy) in self.blocks:
                    continue
                kernel = 1 / np.hypot(pitch * dx + x[:, None] - x[None, :], pitch * dy + y[:, None] - y[None, :])
                block = weighted.T @ kernel @ weighted
                self.blocks[(dx, dy)] = block
                self.blocks[(-dx, -dy)] = block.T
        self.grid = grid

    def _pairs(self, centres: np.ndarray, points: tuple, near: tuple[float, int, int] | None) -> None:
        """The blocks of tips at arbitrary ``centres`` (radii), keyed (target, source); ``self.grid`` is None."""
        if centres.ndim != 2 or centres.shape[1] != 2:
            raise ValueError(f"centres: shape {centres.shape}, must be (tips, 2)")
        distance = np.hypot(*(centres[:, None, :] - centres[None, :, :]).transpose(2, 0, 1))
        np.fill_diagonal(distance, np.inf)
        if distance.min() <= 2:
            raise ValueError(f"centres: two tips {distance.min():g} radii apart, must be more than 2 (no overlap)")
        rules = [points]
        if near is not None:
            r, theta, weights = quadrature(near[1], near[2])
            rules.append((r, theta, weights, polynomial(self.basis, r, theta)))
        quadratures = [(r * np.cos(theta), r * np.sin(theta), phi * weights[:, None])
                       for r, theta, weights, phi in rules]
        self.centres, self.grid = centres, None
        # The basis' norms exactly (p_b^2 is a polynomial of degree 2 ``degree`` in s and below 2 ``degree`` + 1
        # in theta), whatever the blocks' quadrature: the own-disk part is then the exact Galerkin operator.
        degree = max(m + 2 * n for m, n, _ in self.basis)
        r, theta, weights = quadrature(degree + 1, 2 * degree + 2)
        phi = polynomial(self.basis, r, theta)
        self.norm = np.einsum("q,qb,qb->b", weights, phi, phi)
        for i in range(len(centres)):
            for j in range(i + 1, len(centres)):
                x, y, weighted = quadratures[int(near is not None and distance[i, j] < near[0])]
                dx, dy = centres[i] - centres[j]
                kernel = 1 / np.hypot(dx + x[:, None] - x[None, :], dy + y[:, None] - y[None, :])
                block = weighted.T @ kernel @ weighted
                self.blocks[(i, j)] = block
                self.blocks[(j, i)] = block.T

    def solve(self, attached: np.ndarray, spring: float) -> np.ndarray:
        """Coefficients c (attached tips x basis) at d = 1 on the unit disks: (1 / pi) [own c_i + sum_j B_ij c_j]
        + 2 pi spring c_i00 e_00 = 2 pi e_00 (``spring`` = 2 pi E* a / k, everything in E* = 1, a = 1)."""
        index = np.flatnonzero(attached)
        nb = len(self.basis)
        if self.grid is None:
            return self._solve_dense(index, spring)
        pairs: dict[tuple[int, int], tuple[list[int], list[int]]] = {}
        for p, i in enumerate(index):
            for q, j in enumerate(index):
                if p != q:
                    key = tuple(self.grid[i] - self.grid[j])
                    pairs.setdefault(key, ([], []))[0].append(p)
                    pairs[key][1].append(q)
        pairs_arrays = {key: (np.array(a), np.array(b)) for key, (a, b) in pairs.items()}
        diagonal = np.tile(self.own * self.norm / math.pi, (len(index), 1))
        diagonal[:, 0] += spring * self.norm[0]

        def apply(flat: np.ndarray) -> np.ndarray:
            c = flat.reshape(len(index), nb)
            out = diagonal * c
            for key, (rows, cols) in pairs_arrays.items():
                out[rows] += c[cols] @ self.blocks[key].T / math.pi  # one source per row at an offset
            return out.ravel()

        size = diagonal.size
        return self._gmres(scipy.sparse.linalg.LinearOperator((size, size), matvec=apply), diagonal, index,
                           len(self.grid))

    def _solve_dense(self, index: np.ndarray, spring: float) -> np.ndarray:
        """`solve` for tips at arbitrary centres: the same system, assembled for the attached tips ``index``."""
        nb = len(self.basis)
        diagonal = np.tile(self.own * self.norm / math.pi, (len(index), 1))
        diagonal[:, 0] += spring * self.norm[0]
        matrix = np.zeros((len(index) * nb, len(index) * nb))
        for p, i in enumerate(index):
            for q, j in enumerate(index):
                if p != q:
                    matrix[p * nb:(p + 1) * nb, q * nb:(q + 1) * nb] = self.blocks[(int(i), int(j))] / math.pi
        matrix[np.diag_indices_from(matrix)] += diagonal.ravel()
        return self._gmres(scipy.sparse.linalg.aslinearoperator(matrix), diagonal, index, len(self.centres))

    def _gmres(self, operator, diagonal: np.ndarray, index: np.ndarray, tips: int) -> np.ndarray:
        """The coefficients (``tips`` x basis, 0 off ``index``) of the system ``operator`` at d = 1: its right-hand
        side 2 pi d projected on the uniform mode, GMRES preconditioned by its ``diagonal``."""
        nb = len(self.basis)
        rhs = np.zeros((len(index), nb))
        rhs[:, 0] = self.norm[0]  # 2 pi d projected on the uniform mode, d = 1
        size = rhs.size
        preconditioner = scipy.sparse.linalg.LinearOperator((size, size), matvec=lambda v: v / diagonal.ravel())
        solution, info = scipy.sparse.linalg.gmres(operator, rhs.ravel(), M=preconditioner, rtol=1e-13,
                                                   atol=0.0, restart=200, maxiter=2000)
        if info != 0:
            raise RuntimeError(f"gmres did not converge (info {info})")
        out = np.zeros((tips, nb))
        out[index] = solution.reshape(len(index), nb)
        return out

    def external(self, c: np.ndarray, tip: int, points: np.ndarray, nodes: int = 16, angles: int = 64) -> np.ndarray:
        """The other tips' deflection at ``points`` (unit-disk coordinates of ``tip``, shape (q, 2)) per unit load on
        ``tip``, E* = 1, a = 1, from the coefficients ``c`` of `solve` (all tips' loads in proportion)."""
        r, theta, weights = quadrature(nodes, angles)
        density = weights[:, None] * polynomial(self.basis, r, theta)  # (nodes, basis)
        x, y = r * np.cos(theta), r * np.sin(theta)
        out = np.zeros(len(points))
        for j in range(len(self.centres)):
            if j == tip or not c[j].any():
                continue
            dx, dy = self.centres[j] - self.centres[tip]
            distance = np.hypot(dx + x[None, :] - points[:, :1], dy + y[None, :] - points[:, 1:])
            out += (1 / distance) @ (density @ c[j])
        # (1 / pi) int p / |x - x'| dA' on unit disks, per unit load P = 2 pi c_00 (E* = 1, a = 1, d = 1).
        return out / math.pi / (2 * math.pi * c[tip, 0])

    def pull_off(self, spring: float, last: int = 0) -> list[tuple[float, int, int]]:
        """The events (total force at the event on unit disks, E* = 1, K_c = 1; tips attached before it; the tip
        that comes off), in order, until ``last`` tips are left."""
        attached = np.ones(len(self.centres), bool)
        events = []
        while attached.sum() > last:
            c = self.solve(attached, spring)
            intensity = math.sqrt(math.pi) * (c @ self.edge.T)  # (tips, angles) at d = 1
            peak = np.where(attached, intensity.max(axis=1), -np.inf)
            first = int(np.argmax(peak))
            if peak[first] <= 0:
                break
            scale = 1 / peak[first]  # d at which the first tip reaches K_c = 1
            force = 2 * math.pi * c[:, 0].sum() * scale
            events.append((force, int(attached.sum()), first))
            attached[first] = False
        return events


def run_case(per_side: int, stiffness: float, degree: int, nodes: int, angles: int) -> dict:
    """One row: the flat n x n brush of the families at k~ ``stiffness``."""
    start = time.process_time()
    a = math.sqrt(PHI / math.pi) / per_side
    pitch = 1 / per_side / a
    brush = Brush(per_side, pitch, degree, nodes, angles)
    k = stiffness * MODULUS * 1.0  # k = k~ E* L, L = 1
    # F_A comes at the first event on soft springs and at the fifth (the corners gone) at k~ = 10: the first
    # twelve events hold it.
    events = brush.pull_off(2 * math.pi * MODULUS * a / k, last=max(0, per_side**2 - 12))
    # Unit disks, E* = 1, K_c = 1 -> force scale E* a^2 ... : F = F_unit * K_c a^(3/2) (F_K = 2 sqrt(pi) K_c a^1.5).
    k_c = math.sqrt(2 * MODULUS * DGAMMA)
    forces = [force * k_c * a**1.5 for force, _, _ in events]
    best = int(np.argmax(forces))
    kendall = math.sqrt(8 * math.pi * MODULUS * DGAMMA * a**3)
    return {"pillars_per_side": per_side, "stiffness_ratio": stiffness, "degree": degree, "nodes": nodes,
            "angles": angles, "adhesive_force": forces[best], "attached_at_pull_off": events[best][1],
            "force_by_ideal_sharing": forces[best] / (per_side**2 * kendall), "events": len(events),
            "cpu_seconds": round(time.process_time() - start, 2)}


def run_exact(per_side: int, stiffness: float, factor: int) -> dict:
    """The exact path on the families' flat brush at ``factor`` times the grid N = 16 n: the total force at its
    first detachment of an element (the last unloading state before the contact area first falls) and F_A."""
    from brushbem.protocol import LoadPath, record_pull_off
    from validation import problem

    coarse, preload = problem("flat", per_side, stiffness)
    case, _ = problem("flat", per_side, stiffness, factor=factor)
    start = time.process_time()
    record = record_pull_off(case, LoadPath(method="events", preload_force=preload, max_steps=10**7))
    seconds = time.process_time() - start
    if not record.summary["converged"]:
        raise RuntimeError(f"events: {record.summary['reason']}")
    curve = record.curve
    unloading = np.flatnonzero(~np.asarray(curve.loading))
    area = np.asarray(curve.contact_area)
    first = next(i for i in unloading[:-1] if area[i + 1] < area[i])
    force, adhesive = -float(curve.force[first]), float(record.summary["adhesive_force"])
    per_radius = factor * float(coarse.indenter.description.pillar_radius) / coarse.grid.element_size
    return {"pillars_per_side": per_side, "stiffness_ratio": stiffness, "tip_factor": factor,
            "tip_elements_per_radius": round(per_radius, 3), "first_detachment_force": force,
            "adhesive_force": adhesive, "peel_gain": adhesive / force - 1,
            "attached_at_pull_off": int(record.summary["attached_pillars_at_pull_off"]),
            "cpu_seconds": round(seconds, 2)}


def _key(row: dict) -> tuple:
    return (int(row["pillars_per_side"]), float(row["stiffness_ratio"]), int(row["degree"]), int(row["nodes"]),
            int(row["angles"]))


def reference(rows: list[dict]) -> list[dict]:
    """Per (n, k~): the finest row, its error the change from the next coarser degree plus that from the coarser
    quadrature (``RESOLUTIONS``' last three)."""
    table = {_key(row): row for row in rows}
    out = []
    for n in sorted({int(row["pillars_per_side"]) for row in rows}):
        for k in sorted({float(row["stiffness_ratio"]) for row in rows}):
            found = [table.get((n, k, *res)) for res in RESOLUTIONS[-3:]]
            if any(row is None for row in found):
                continue
            coarser, same_nodes, finest = (float(row["adhesive_force"]) for row in found)
            error = abs(same_nodes / coarser - 1) + abs(finest / same_nodes - 1)
            best = found[-1]
            out.append({"pillars_per_side": n, "stiffness_ratio": k, "degree": int(best["degree"]),
                        "nodes": int(best["nodes"]), "angles": int(best["angles"]), "adhesive_force": finest,
                        "error": error, "attached_at_pull_off": int(best["attached_at_pull_off"]),
                        "force_by_ideal_sharing": float(best["force_by_ideal_sharing"])})
    return out


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--reference", action="store_true", help="only rewrite continuum_reference.csv")
    parser.add_argument("--exact", action="store_true", help="the exact path's rows (continuum_exact.csv)")
    args = parser.parse_args()
    if args.exact:
        rows = load(EXACT)
        done = {(int(r["pillars_per_side"]), float(r["stiffness_ratio"]), int(r["tip_factor"])) for r in rows}
        for case in EXACT_CASES:
            if case not in done:
                row = run_exact(*case)
                rows.append(row)
                order = {c: i for i, c in enumerate(EXACT_CASES)}
                rows.sort(key=lambda r: order[(int(r["pillars_per_side"]), float(r["stiffness_ratio"]),
                                                int(r["tip_factor"]))])
                write_table(rows, EXACT, EXACT_FIELDS, digits=8)
                print(", ".join(f"{name}={row[name]}" for name in EXACT_FIELDS), flush=True)
        return
    rows = load(TABLE)
    if not args.reference:
        done = {_key(row) for row in rows}
        for case in CASES:
            if case in done:
                continue
            row = run_case(*case)
            rows.append(row)
            order = {c: i for i, c in enumerate(CASES)}
            rows.sort(key=lambda line: order.get(_key(line), len(order)))
            write_table(rows, TABLE, FIELDS, digits=8)
            print(", ".join(f"{name}={row[name]}" for name in FIELDS), flush=True)
    write_table(reference(rows), REFERENCE, REFERENCE_FIELDS, digits=8)


if __name__ == "__main__":
    main()
