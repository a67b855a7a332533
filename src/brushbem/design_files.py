"""The files of a design (`write_design`) and its figure (`design_figure`, with the thesis's S_c fitted).

The design itself is `brushbem.design`.
"""

from __future__ import annotations

import numpy as np

from brushbem.physics import theory
from brushbem.protocol import ContactProblem
from brushbem.design import Design
from brushbem.physics.scales import normalized_stiffness

__all__ = ["DESIGN_FILE_NAMES", "DesignWriteError", "design_figure", "thesis_profile_fit", "write_design"]


#: The least coefficient of determination at which the design figure draws the thesis's S_c shape fitted to
#: the designed offsets (ours, the thesis states none): below it the shape does not describe the design, and
#: the figure says so instead of drawing a curve that misses the points.
FIT_MIN_R2 = 0.5


def thesis_profile_fit(problem: ContactProblem, offsets: np.ndarray) -> tuple[np.ndarray, float, float]:
    """The thesis's concave shape S_c (eq. 7.2-7.3) at the pillars, fitted to ``offsets`` by least squares.

    The fit is a S_c + b (an amplitude and a constant level, both by least squares).  Returns (the fitted
    offsets, the amplification h~ = a of the fit, with the default reference stress p_c = F_K / (pi r^2),
    and the fit's coefficient of determination R^2, 1 for a perfect fit, <= 0 for none).
    """
    info = problem.indenter.description
    centres = np.asarray(info.centres)
    radial = np.hypot(centres[:, 0], centres[:, 1])
    outer = float(radial.max()) if radial.max() > 0 else float(info.pillar_radius)
    stress = float(theory.concave_reference_stress(info.pillar_radius, contact_modulus=problem.contact_modulus,
                                                   work_of_adhesion=problem.work_of_adhesion))
    shape = np.asarray(theory.concave_offsets(radial, outer, 1.0, stress, contact_modulus=problem.contact_modulus))
    offsets = np.asarray(offsets, float)
    centred_shape, centred = shape - shape.mean(), offsets - offsets.mean()
    scale = float(centred_shape @ centred / (centred_shape @ centred_shape)) if np.any(centred_shape) else 0.0
    fitted = offsets.mean() + scale * centred_shape
    total = float(centred @ centred)
    r2 = 1.0 - float((offsets - fitted) @ (offsets - fitted)) / total if total > 0 else 0.0
    return fitted, scale, r2


def design_figure(problem: ContactProblem, result: Design, axes=None):
    """The designed profile against the distance from the centre, beside the thesis's S_c shape (a Figure).

    ``axes``: a pair of matplotlib axes to draw on (the profile, the
    verification history); their figure is returned.  By default a new
    Figure (no pyplot).  Offsets are drawn over |d_c| (eq. 4.12), stiffnesses
    as k~ = k / (E* L), forces over N F_K (eq. 7.4): every axis normalised.
    """
    from matplotlib.ticker import MaxNLocator

    from brushbem.figures import figstyle

    info = problem.indenter.description
    centres = np.asarray(info.centres)
    radial = np.hypot(centres[:, 0], centres[:, 1])
    outer = float(radial.max()) or 1.0
    with figstyle.style():
        if axes is None:
            fig = figstyle.new_figure(7.2, 3.4)
            left, right = fig.subplots(1, 2)
        else:
            left, right = axes
            fig = left.figure
        d_c = abs(result.rigid_brush_displacement)
        if result.target == "lengths":
            fitted, amplification, r2 = thesis_profile_fit(problem, result.values)
            order = np.argsort(radial)
            left.plot(radial / outer, result.values / d_c, "o", label=r"designed offsets $g_n$")
            if r2 >= FIT_MIN_R2 and amplification > 0:
                left.plot(radial[order] / outer, fitted[order] / d_c, "-",
                          label=rf"thesis $S_\mathrm{{c}}$ (eq. 7.2), fitted $\tilde h$ = {amplification:.3g}, "
                                rf"$R^2$ = {r2:.2f}")
            else:  # a curve that misses the points would read as a fit
                left.plot([], [], " ", label=rf"thesis $S_\mathrm{{c}}$ (eq. 7.2) does not fit ($R^2$ = {r2:.2f}): "
                                            "not drawn")
            left.set(ylabel=r"offset $g/|d_\mathrm{c}|$")
        else:
            side = float(getattr(problem.indenter.description, "region_size", problem.grid.size))  # L of eq. 4.13
            left.plot(radial / outer, normalized_stiffness(result.values, problem.contact_modulus, side), "o",
                      label=r"designed stiffness $k_n$")
            left.set(ylabel=r"pillar stiffness $\tilde k_n = k_n/(E^* L)$")
        left.set(xlabel=r"distance from the centre $\rho/\rho_\mathrm{max}$",
                 title=rf"design ({result.target}): $\tilde F$ = {result.verified_force_ratio:.4f}")
        left.legend()
        right.plot(range(1, len(result.history) + 1), result.history, "o-", label="verified")
        right.axhline(result.predicted_force_ratio, ls="--", color=figstyle.COLOURS[1], lw=0.8,
                      label=f"predicted (every edge critical at once): {result.predicted_force_ratio:.4f}")
        if result.bound_force_ratio is not None:
            right.axhline(result.bound_force_ratio, ls="-.", color=figstyle.COLOURS[2], lw=0.8,
                          label=f"bound in full contact (any design): {result.bound_force_ratio:.4f}")
        right.axhline(1.0, ls=":", color="0.5", lw=0.8,
                      label=r"$\tilde F$ = 1: isolated Kendall pillars (eq. 7.4)")
        right.set(xlabel="verification pull-off", ylabel=r"$\tilde F = F_\mathrm{A}/(N_\mathrm{p} F_\mathrm{K})$",
                  title="verified by the ordinary pull-off")
        right.xaxis.set_major_locator(MaxNLocator(integer=True, min_n_ticks=1))  # pull-offs are counted
        right.set_xlim(0.5, max(len(result.history), 1) + 0.5)
        right.legend()
    return fig


#: The files `write_design` writes.
DESIGN_FILE_NAMES = ("design.npy", "design.csv", "design.json", "design.png", "design.pdf")


class DesignWriteError(OSError):
    """A design file could not be written; the files of the design written before it were removed.

    ``filename`` is the file that failed; ``removed`` the files of this design that were removed again.
    """

    def __init__(self, errno: int | None, strerror: str, filename, removed: list):
        super().__init__(errno, strerror, str(filename))
        self.removed = removed


def write_design(problem: ContactProblem, result: Design, out_dir, config_path: str | None = None) -> list:
    """``design.npy`` (the values), ``design.csv`` (per pillar), ``design.json`` (scalars), ``design.png``; atomic.

    Every file is written to a temporary and renamed over its name.  When one fails (a full disk, a quota),
    the files of this design already written are removed again, so a folder never holds a design whose
    files disagree, and `DesignWriteError` names the file that failed.
    """
    import csv
    import io as _io
    import json
    from pathlib import Path

    from brushbem.figures import figstyle
    from brushbem.io import atomic_path

    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    info = problem.indenter.description
    centres = np.asarray(info.centres)
    written: list = []
    current = out / "design.npy"
    try:
        with atomic_path(current) as temporary, open(temporary, "wb") as stream:
            np.save(stream, result.values)
        written.append(current)
        buffer = _io.StringIO()
        writer = csv.writer(buffer)
        name = "offset" if result.target == "lengths" else "stiffness"
        writer.writerow(["pillar", "y", "x", "r", name, "detachment_displacement"])
        for n, ((y, x), value, d) in enumerate(zip(centres, result.values, result.detachment, strict=True)):
            writer.writerow([n, repr(float(y)), repr(float(x)), repr(float(np.hypot(y, x))), repr(float(value)),
                             repr(float(d))])
        current = out / "design.csv"
        with atomic_path(current) as temporary:
            Path(temporary).write_text(buffer.getvalue())
        written.append(current)
        scalars = {**result.scalars(), "config": config_path}
        if result.target == "lengths":
            _, scalars["thesis_profile_amplification"], scalars["thesis_profile_r2"] = thesis_profile_fit(
                problem, result.values)
        current = out / "design.json"
        with atomic_path(current) as temporary:
            Path(temporary).write_text(json.dumps(scalars, indent=2) + "\n")
        written.append(current)
        current = out / "design.png"
        figure = design_figure(problem, result)
        written.append(figstyle.save(figure, current))  # and design.pdf
        written.append(current.with_suffix(".pdf"))
    except OSError as exc:
        failed = current
        if getattr(exc, "filename", None):
            name = Path(exc.filename).name
            if name.startswith(".") and name.endswith(".tmp"):  # atomic_path's temporary: .NAME.RANDOM.tmp
                name = name[1:-4].rsplit(".", 1)[0]
            if name in DESIGN_FILE_NAMES:
                failed = out / name
        removed = []
        for path in dict.fromkeys((*written, out / "design.png")):
            if path != failed and path.exists():
                path.unlink()
                removed.append(path)
        raise DesignWriteError(exc.errno, exc.strerror or str(exc), failed, removed) from exc
    return written
