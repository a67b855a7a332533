"""The coupled operator A = K + sum_l (h^2 / k_l) P_l^T P_l on a window of the grid.

For an element i in the contact set S belonging to pillar n (DESIGN.md sec. 2)

    (K p)_i + sum_l (h^2 / k_l) * sum_{j in S, c_l(j) = c_l(i)} p_j = d - height_i,

the first term the half-space deflection, the second the deflection of the
springs of every level above the element (thesis eq. 3.11, 6.12, 6.17).  A is
symmetric positive definite on S.  The spring sums are computed either by
segment sums over the element-to-cluster incidence (``coupling="segments"``,
exact for any layout, O(n)) or, as in the thesis, by the convolution with the
discriminant matrix Pi_l folded into the kernel spectrum
(``coupling="discriminant"``, eq. 3.13-3.17 and 6.14-6.18), which is exact
only while every Pi_l covers a whole cluster and no part of another one; the
constructor checks that condition and refuses layouts that violate it.

The pieces compose: `ContactOperator` on a window is the half-space
(`brushbem.physics.halfspace.HalfSpace`, K on any block) plus the pillar springs of
every level on that window (`brushbem.physics.springs.PillarSprings`); `MaskedOperator`
restricts their sum to a contact set on the window's arrays, `ContactSystem` on
the |S| values of S (the springs by `PillarSprings.on_set`).  The last two are
the `brushbem.numerics.solver.cg.SetOperator`s that the conjugate gradient takes;
The operator computes and remembers nothing beyond its own spectra: what the
solves reuse (the pillar-block preconditioner's `PillarCache`, the last set
solver, the kept solution's deflection, the block operators) is the caller's
`brushbem.numerics.solver.cache.SolverCache`, passed in.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy import ndimage

from brushbem import backend
from brushbem.numerics.periods import halfspace_on_support
from brushbem.physics.halfspace import HalfSpace
from brushbem.physics.springs import PillarSprings
from brushbem.physics.structure import Indenter

__all__ = ["SINGLE_ERROR", "ContactOperator", "ContactSystem", "MaskedOperator", "Window", "discriminant_half_width",
           "fast_size"]


@dataclass(frozen=True)
class Window:
    """A rectangular block of the grid: rows [r0, r1) and columns [c0, c1)."""

    r0: int
    r1: int
    c0: int
    c1: int

    @classmethod
    def full(cls, n: int) -> Window:
        return cls(0, n, 0, n)

    @property
    def slices(self) -> tuple[slice, slice]:
        return (slice(self.r0, self.r1), slice(self.c0, self.c1))

    @property
    def shape(self) -> tuple[int, int]:
        return (self.r1 - self.r0, self.c1 - self.c0)

    @property
    def slices_local(self) -> tuple[slice, slice]:
        """The whole window, as slices of an array of the window's shape."""
        return (slice(0, self.r1 - self.r0), slice(0, self.c1 - self.c0))

    def contains(self, mask: np.ndarray) -> bool:
        """Whether every True element of the full-grid ``mask`` lies inside the window."""
        inside = np.zeros(mask.shape, dtype=bool)
        inside[self.slices] = True
        return not np.any(mask & ~inside)


#: Most loaded elements for which ``element_deflection`` sums kernels instead of
#: transforming (one kernel pass costs ~1/30 of an FFT pair on a 100 x 100 window).
FEW_ELEMENTS = 16


def fast_size(size: int) -> int:
    """Smallest m >= size whose padded transform length 2m has only factors 2, 3 and 5.

    2m is 5-smooth exactly when m is, so this is `backend.smooth_length`.
    """
    return backend.smooth_length(size)


def _support(xp, values) -> tuple[int, int, int, int] | None:
    """Bounding box (r0, r1, c0, c1) of the non-zero entries of a 2-D array (None: all zero)."""
    return backend.bounding_box(xp, values != 0)


def _fast_block(lo: int, hi: int, limit: int) -> tuple[int, int]:
    """[lo', hi') within [0, limit) that holds [lo, hi) and has a fast size (or is all of [0, limit))."""
    size = fast_size(hi - lo)
    if size >= limit:
        return 0, limit
    hi = min(lo + size, limit)
    return hi - size, hi


def discriminant_half_width(labels: np.ndarray) -> int:
    """Half-width w (in elements) of the square discriminant matrix for ``labels``.

    The box of side 2w + 1 centred on any element of a cluster must cover the
    whole cluster (w >= D - 1, D the largest cluster extent in elements) and no
    element of another cluster (thesis eq. 3.14-3.15).  Returns the smallest
    valid w, or raises ValueError saying which condition fails.
    """
    present = labels >= 0
    if not present.any():
        return 0
    objects = ndimage.find_objects(np.where(present, labels + 1, 0))
    extent = max(max(s[0].stop - s[0].start, s[1].stop - s[1].start) for s in objects if s is not None)
    width = extent - 1
    size = 2 * width + 1
    # Largest and smallest label within the box around every element: a box
    # that reaches another cluster sees two different labels.
    # The sentinel must survive ndimage's float64 arithmetic: one past the largest label.
    big = int(labels.max()) + 1
    highest = ndimage.maximum_filter(np.where(present, labels, -1), size=size, mode="constant", cval=-1)
    lowest = ndimage.minimum_filter(np.where(present, labels, big), size=size, mode="constant", cval=big)
    clash = present & ((highest != labels) | (lowest != labels))
    if clash.any():
        raise ValueError(
            "the discriminant matrix cannot be used for this layout: a box of half-width "
            f"w = {width} elements (needed to cover the largest cluster, {extent} elements wide) "
            "reaches another cluster (thesis eq. 3.14-3.15: Pi must be larger than every footprint "
            "and smaller than every gap); use coupling = \"segments\""
        )
    return width


class ContactOperator:
    """A restricted to a window: ``apply(p, mask) = mask * (K p + springs(p))``.

    Parameters
    ----------
    halfspace : HalfSpace
        The half-space operator of the whole grid.
    indenter : Indenter
        The rasterised indenter (pillars, springs).
    window : Window
        The block of the grid the operator acts on.  Pressure outside the
        window is zero.
    coupling : {"segments", "discriminant"}
        How the spring sums are computed (module docstring).
    """

    def __init__(
        self,
        halfspace: HalfSpace,
        indenter: Indenter,
        window: Window,
        coupling: str = "segments",
        _widths: tuple | None = None,
    ):
        if coupling not in ("segments", "discriminant"):
            raise ValueError(f"coupling = {coupling!r} must be 'segments' or 'discriminant'")
        self.halfspace = halfspace
        self.indenter = indenter
        self.window = window
        self.coupling = coupling
        xp = halfspace.xp
        self.xp = xp
        #: The springs of every elastic level on this window.
        self.springs = PillarSprings(indenter, halfspace.element_size, window.slices, xp)
        if _widths is None:
            # Per elastic level: the discriminant half-width (shared with the sub-operators).
            _widths = tuple(
                discriminant_half_width(indenter.element_clusters(lv.level)) if coupling == "discriminant" else None
                for lv in self.springs.levels
            )
        self._widths = _widths
        rows, cols = window.shape
        spectrum = None
        if coupling == "discriminant":
            for lv in self.springs.levels:
                if not lv.level.uniform:
                    raise ValueError(
                        "coupling = 'discriminant' needs one stiffness per spring level (its spectrum carries "
                        "one compliance); a graded or per-pillar stiffness needs coupling = 'segments'"
                    )
            for lv, width in zip(self.springs.levels, _widths):
                if spectrum is None:
                    spectrum = xp.asarray(halfspace.spectrum(rows, cols), copy=True)
                spectrum = spectrum + float(lv.compliance[0]) * self._box_spectrum(rows, cols, width)
        #: The half-space and the springs in one spectrum (discriminant coupling), else None.
        self.spectrum = spectrum
        #: Pillar index of every window element (-1 outside the footprints).
        self.pillar_labels = indenter.pillar[window.slices]

    def for_window(self, window: Window) -> ContactOperator:
        """The same operator on another window (the springs' labels and widths are shared)."""
        return ContactOperator(self.halfspace, self.indenter, window, self.coupling, _widths=self._widths)

    def block_window(self, mask) -> Window | None:
        """The smallest FFT-friendly block of the window that holds ``mask`` (None: the window itself).

        A_S x for x supported on S only needs the deflection on S, so the
        padded convolution can run on a block around S instead of the whole
        window: with the block side b, the FFTs are 2b long instead of 2m.
        The working window carries a margin around the contact (for the
        attachment predictions and the outside-penetration bound), so the
        block is typically 20-50 % smaller in area; the result is the same
        (the kernel is translation invariant and the springs only couple
        elements of S).  The operator on the block is ``for_window`` of it; the
        solves keep it in their `brushbem.numerics.solver.cache.SolverCache`.

        Parameters
        ----------
        mask : ndarray of bool, the window's shape
            The set the solve works on (not empty).
        """
        box = backend.bounding_box(self.xp, mask)
        if box is None:
            return None
        w_rows, w_cols = self.window.shape
        r0, r1 = _fast_block(box[0], box[1], w_rows)
        c0, c1 = _fast_block(box[2], box[3], w_cols)
        if (r1 - r0, c1 - c0) == (w_rows, w_cols):
            return None
        return Window(self.window.r0 + r0, self.window.r0 + r1, self.window.c0 + c0, self.window.c0 + c1)

    def _box_spectrum(self, rows: int, cols: int, width: int):
        """Spectrum of the padded discriminant matrix (ones for |offset| <= width)."""
        xp = self.xp
        padded = np.zeros((2 * rows, 2 * cols))
        wr = min(width, rows - 1)
        wc = min(width, cols - 1)
        row_idx = np.r_[0 : wr + 1, 2 * rows - wr : 2 * rows]
        col_idx = np.r_[0 : wc + 1, 2 * cols - wc : 2 * cols]
        padded[np.ix_(row_idx, col_idx)] = 1.0
        return xp.real(backend.rfft2(xp, xp.asarray(padded), (2 * rows, 2 * cols)))

    def system(self, mask) -> ContactSystem:
        """A_S on the elements of ``mask`` (the window's shape), as a `ContactSystem`."""
        return ContactSystem(self, mask)

    @property
    def has_springs(self) -> bool:
        return bool(self.springs)

    @property
    def spring_levels(self) -> list[tuple[np.ndarray, np.ndarray]]:
        """``(h^2 / k_c of every cluster, cluster of every pillar)`` of every elastic level, bottom-up."""
        return [(lv.compliance, lv.level.cluster) for lv in self.springs.levels]

    def halfspace_deflection(self, pressure):
        """K p on the window, in units of length."""
        return self.halfspace.apply(pressure)

    def cluster_forces(self, pressure):
        """Force carried by every cluster of every elastic level: list of arrays h^2 sum p."""
        return self.springs.cluster_forces(pressure)

    def spring_deflection(self, pressure):
        """Total spring deflection above every element of the window (`PillarSprings.apply`)."""
        return self.springs.apply(pressure)

    def tip_deflection(self, pressure):
        """K p plus the spring deflection (segment sums) on the window, unmasked.

        The deflection that the penetration d - height - u is measured with
        (``deflection`` folds the springs into the spectrum for the
        discriminant coupling; on the footprint the two agree to round-off).
        Always transformed: a deflection a solve already knows is its
        caller's (`brushbem.numerics.solver.cache.SolverCache`).
        """
        deflection = halfspace_on_support(self.halfspace, pressure, _support(self.xp, pressure))
        if self.springs:
            deflection = deflection + self.springs.apply(pressure)
        return deflection

    def element_deflection(self, values, mask):
        """``tip_deflection(values * mask)`` for a pressure on a few elements.

        Up to ``FEW_ELEMENTS`` loaded elements, the deflection is the sum of
        their shifted kernels (``HalfSpace.mirrored_kernel``), a few array
        passes instead of an FFT pair; otherwise it is transformed.  Used to
        keep a known deflection in step when a few elements leave the contact
        (their pressure is dropped).
        """
        xp = self.xp
        loaded = mask & (values != 0)
        rows_at, cols_at = (np.asarray(backend.to_numpy(i)) for i in xp.nonzero(loaded))
        if rows_at.size > FEW_ELEMENTS:
            return self.tip_deflection(xp.where(loaded, values, 0.0))
        rows, cols = self.window.shape
        deflection = xp.zeros((rows, cols), dtype=xp.float64)
        if rows_at.size == 0:
            return deflection
        table = self.halfspace.mirrored_kernel(rows, cols)
        weights = np.asarray(backend.to_numpy(values[loaded]))
        for r, c, w in zip(rows_at.tolist(), cols_at.tolist(), weights.tolist()):
            deflection += w * table[rows - 1 - r : 2 * rows - 1 - r, cols - 1 - c : 2 * cols - 1 - c]
        if self.springs:
            deflection = deflection + self.springs.apply(xp.where(loaded, values, 0.0))
        return deflection

    def deflection(self, pressure):
        """(K + springs) p on the window, unmasked."""
        if self.spectrum is not None:
            return self.halfspace.apply(pressure, spectrum=self.spectrum)
        result = self.halfspace.apply(pressure)
        if self.springs:
            result = result + self.springs.apply(pressure)
        return result

    def apply(self, pressure, mask):
        """A_S p: the deflection of the contact elements, zero elsewhere.

        ``mask`` is the set S as bool, or as its 0/1 float copy (cheaper to
        multiply by, for the solvers that apply A_S many times).
        """
        xp = self.xp
        if mask.dtype == xp.bool:
            mask = xp.astype(mask, xp.float64)  # the array API has no bool * float
        return self.deflection(pressure) * mask


class MaskedOperator:
    """A_S on a window's arrays: ``apply(p) = mask * (K p + springs(p))`` (a `brushbem.numerics.solver.cg.SetOperator`).

    Parameters
    ----------
    operator : ContactOperator
        The operator of the window.
    mask : ndarray of bool, the window's shape
        The set S.
    """

    def __init__(self, operator: ContactOperator, mask):
        self.operator = operator
        self.mask = mask
        self.xp = operator.xp
        #: S as 0/1 floats: a cheaper mask to multiply by.
        self.weights = operator.xp.astype(mask, operator.xp.float64)

    def apply(self, values):
        return self.operator.apply(values, self.weights)


#: Bound on the relative error of `ContactSystem.apply_block` with ``single`` against without (2-norms,
#: on S and on the whole window).  Measured: at most 2.8e-7 over the 1073 CG directions of a pull-off
#: of a 16 x 16 rough brush at N = 256, and 0.3-1.8e-7 for uniform, signed random and constant
#: pressures on every tip of 8 x 8 to 64 x 64 brushes at N = 128 to 1024 (the error grows like log N);
#: the bound leaves a factor 3.5 (`tests/test_single_products.py` checks it at N = 128).
SINGLE_ERROR = 1e-6


class ContactSystem:
    """A_S on a contact set S of a window, acting on vectors of the |S| values of S.

    The elements of S are numbered in row-major order of the window
    (``gather`` / ``scatter`` convert).  ``apply(v)`` = A_S v: the half-space
    deflection of the pressure v on S, evaluated on S, plus the spring sums.
    The convolution transforms along the rows only the rows that hold S
    (`backend.padded_convolution_rows`), and every other operation of a CG
    iteration touches |S| numbers instead of the window's: for a brush S is a
    tenth of the window or less.

    Parameters
    ----------
    operator : ContactOperator
        The operator of the window (usually the block around S, see
        ``ContactOperator.sub_operator``).
    mask : ndarray of bool, the window's shape
        The set S.
    """

    def __init__(self, operator: ContactOperator, mask):
        xp = operator.xp
        self.operator = operator
        self.xp = xp
        m = np.asarray(backend.to_numpy(mask), dtype=bool)
        self.shape = m.shape
        cols = m.shape[1]
        index = np.flatnonzero(m)
        self.size = int(index.size)
        self.element_rows, self.element_cols = np.divmod(index, cols)
        rows = np.flatnonzero(m.any(axis=1))
        compact = np.searchsorted(rows, self.element_rows) * cols + self.element_cols
        self._rows_np = rows
        self.index = xp.asarray(index)
        self._rows = xp.asarray(rows)
        self._compact = xp.asarray(compact)
        rows_w, cols_w = m.shape
        self._padded_shape = (2 * rows_w, 2 * cols_w)
        #: The spring sums on S in segment form, whatever the coupling (`spring_deflection`).
        self.springs = operator.springs.on_set(self.index)
        if operator.spectrum is not None:
            self._spectrum = operator.spectrum  # the springs are folded into it
            self._springs = None
        else:
            self._spectrum = operator.halfspace.spectrum(rows_w, cols_w)
            self._springs = self.springs
        self._spectrum_single = None
        #: Pillar of every element of S (-1 off the pillars).
        self.pillars = np.asarray(backend.to_numpy(operator.pillar_labels)).ravel()[index]
        #: Whether `apply_block` gives K v on the whole window (the springs are not in the spectrum).
        self.gives_block_deflection = operator.spectrum is None

    @property
    def mask(self):
        """Every entry of a vector on S is on S (the `brushbem.numerics.solver.cg.SetOperator` contract)."""
        return self.xp.ones(self.size, dtype=self.xp.bool)

    def gather(self, array):
        """The values of a window-shaped array on S."""
        return self.xp.reshape(array, (-1,))[self.index]

    def scatter(self, values):
        """The window-shaped array that is ``values`` on S and zero elsewhere."""
        xp = self.xp
        out = xp.zeros(self.shape[0] * self.shape[1], dtype=values.dtype)
        out[self.index] = values
        return xp.reshape(out, self.shape)

    def spring_deflection(self, values):
        """The springs' part of A_S v for v on S: the deflection of every level above each element."""
        return self.springs.apply(values)

    def apply(self, values):
        """A_S v for v on S (a vector of |S| values)."""
        return self._apply(values, False)[0]

    def apply_block(self, values, single: bool = False):
        """(A_S v on S, K v on the whole window) for v on S, when ``gives_block_deflection``.

        K v is the half-space's deflection alone (no springs), window-shaped;
        it costs the inverse transforms along the rows of the whole window
        instead of those of S only.  ``single``: the half-space's transforms
        in single precision (relative error at most ``SINGLE_ERROR``).
        """
        return self._apply(values, True, single)

    def _apply(self, values, whole: bool, single: bool = False):
        xp = self.xp
        spectrum = self._spectrum
        if single:
            if self._spectrum_single is None:
                self._spectrum_single = xp.astype(spectrum, xp.float32)
            spectrum = self._spectrum_single
        rows = xp.zeros(int(self._rows_np.size) * self.shape[1], dtype=xp.float32 if single else values.dtype)
        rows[self._compact] = values
        rows = xp.reshape(rows, (int(self._rows_np.size), self.shape[1]))
        deflection = backend.padded_convolution_rows(xp, rows, self._rows, spectrum, self._padded_shape,
                                                     out_rows=self.shape[0] if whole else None)
        if single:
            deflection = xp.astype(deflection, xp.float64)
        out = xp.reshape(deflection, (-1,))[self.index if whole else self._compact]
        if self._springs:
            out = self._springs.apply(values, out)
        return out, (deflection if whole else None)
