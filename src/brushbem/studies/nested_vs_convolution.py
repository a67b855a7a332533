"""Nested loop against the convolution method (thesis sec. 3.3, Figure 3-5).

The deformed surface of the half-space, cross-section through the centre, for
three elastically embedded indenters pressed without adhesion: (a) a flat
punch, (b) a sphere, (c) a 5 x 5 array of flat pillars.  Each is computed
three ways: rigid (no spring), the coupled operator A = K + (h^2/k) P^T P
("convolution", `brushbem.numerics.solver.equilibrium`) and the nested loop that
corrects the pillar positions until the spring and contact forces balance
(`brushbem.numerics.nested`, per pillar for the array).  The thesis's numbers: k = 50
N/mm, E = 100 MPa, domain 1 mm x 1 mm; taken here as E* = 100 (the thesis does
not give nu) in N and mm.  The geometry and depth are not stated; we use a
punch of radius 0.2, a sphere of radius 1, pillars of radius 0.05 at pitch
0.2, all pressed to d = 0.01.

This study has no sweep: the three equilibria take seconds.  The first draw
computes them and stores the cross-sections in ``DIR/nested_vs_convolution.npz``;
later draws (``brushbem figure``) read that file.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from brushbem.figures.figstyle import styled
from brushbem.physics.halfspace import HalfSpace
from brushbem.numerics.nested import nested_loop_brush_equilibrium, nested_loop_equilibrium
from brushbem.numerics.operator import ContactOperator, Window
from brushbem.numerics.solver import Settings, Start, equilibrium
from brushbem.physics.structure import Grid, Indenter, brush, flat_punch, sphere
from brushbem.studies._common import new_figure, save
from brushbem.studies.base import Study

MODULUS = 100.0      # E*, N/mm^2
STIFFNESS = 50.0     # k, N/mm
DEPTH = 0.01         # d, mm
ELEMENTS = 128
DATA_FILE = "nested_vs_convolution.npz"


def _indenters(grid: Grid) -> dict[str, Indenter]:
    return {
        "punch": flat_punch(grid, 0.2, STIFFNESS),
        "sphere": sphere(grid, 1.0, STIFFNESS),
        "pillars": brush(grid, layout="square", pillars_per_side=5, spacing=0.2, pillar_radius=0.05,
                         contact_modulus=MODULUS, work_of_adhesion=0.0, stiffness=STIFFNESS),
    }


def compute(elements: int = ELEMENTS, tolerance: float = 1e-10) -> dict[str, np.ndarray]:
    """Centre-row surface deflection u(x) of the three indenters, three ways each."""
    grid = Grid(1.0, elements)
    halfspace = HalfSpace(elements, grid.element_size, MODULUS)
    window = Window.full(elements)
    row = elements // 2
    out: dict[str, np.ndarray] = {"x": grid.centres()}
    for name, indenter in _indenters(grid).items():
        rigid_body = Indenter(indenter.height, indenter.pillar)
        rigid = ContactOperator(halfspace, rigid_body, window)
        coupled = ContactOperator(halfspace, indenter, window)
        start = indenter.footprint & (indenter.height <= DEPTH)
        zeros = np.zeros(indenter.height.shape)
        results = {
            "rigid": equilibrium(rigid, indenter.height, DEPTH, Start(contact=start, pressure=zeros),
                                 critical=0.0, settings=Settings(tolerance=tolerance)),
            "convolution": equilibrium(coupled, indenter.height, DEPTH, Start(contact=start, pressure=zeros),
                                       critical=0.0, settings=Settings(tolerance=tolerance)),
        }
        if indenter.n_pillars == 1:
            nested = nested_loop_equilibrium(rigid, indenter.height, DEPTH, STIFFNESS, start, zeros, 0.0, tolerance)
        else:
            nested = nested_loop_brush_equilibrium(rigid, indenter.pillar, indenter.height, DEPTH, STIFFNESS,
                                                   start, zeros, 0.0, tolerance)
        for method, state in (*results.items(), ("nested", nested)):
            if not state.converged:
                raise RuntimeError(f"{name}, {method}: {state.reason}")
            out[f"{name}_{method}"] = np.asarray(halfspace.apply(state.pressure))[row]
    return out


@styled
def draw(results, figures_dir: Path) -> list[Path]:
    figures_dir = Path(figures_dir)
    store = figures_dir.parent / DATA_FILE
    if store.exists():
        with np.load(store) as data:
            curves = dict(data)
    else:
        curves = compute()
        store.parent.mkdir(parents=True, exist_ok=True)
        np.savez(store, **curves)
    fig, axes = new_figure(ncols=3, width=3.4, height=3.2)
    x = curves["x"]
    titles = {"punch": "(a) flat punch", "sphere": "(b) sphere", "pillars": "(c) 5 × 5 pillars"}
    for ax, name in zip(axes[0], ("punch", "sphere", "pillars")):
        ax.plot(x, -curves[f"{name}_rigid"], color="tab:red", label="rigid")
        ax.plot(x, -curves[f"{name}_convolution"], color="tab:blue", label="convolution (coupled operator)")
        ax.plot(x, -curves[f"{name}_nested"], color="tab:green", linestyle="--", label="nested loop")
        difference = np.max(np.abs(curves[f"{name}_nested"] - curves[f"{name}_convolution"]))
        scale = np.max(np.abs(curves[f"{name}_convolution"]))
        ax.set_title(f"{titles[name]}\n" + r"$\max|u_\mathrm{nested} - u_\mathrm{conv}|/\max|u|$"
                     + f" = {difference / scale:.1e}")
        ax.set_xlabel("$x$ (mm)")
    axes[0, 0].set_ylabel("surface position $-u$ (mm)")
    axes[0, 0].legend(fontsize="small", loc="lower left")
    return [save(fig, figures_dir / "fig3-5_nested_vs_convolution.png")]


STUDY = Study(
    name="nested_vs_convolution",
    title="Nested loop vs convolution: deformed surface under a punch, a sphere and 5 x 5 pillars (Fig. 3-5)",
    figures=("3-5",),
    parts=(),
    draw=draw,
    notes="No sweep: three direct equilibria, cached in DIR/nested_vs_convolution.npz.",
)
