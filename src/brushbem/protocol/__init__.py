"""Load paths as generators: press, then pull off until complete separation.

``pull_off(problem, path)`` yields one ``State`` per recorded equilibrium::

    for state in pull_off(problem, path):
        print(state.displacement, state.force)

Three methods:

* ``"fixed"`` - displacement steps, the thesis's method (L648; its step is
  ours: the thesis states none): press to the preload (by
  displacement, or by force with a final secant refinement), then retract by
  ``step`` until the contact set is empty.  Each step is an equilibrium with
  the detachment/attachment loop, warm-started from the previous one.  The
  first solve of a step is on the previous contact set, so the first
  element to reach the criterion inside the step, and the force there, are
  located exactly (a state of kind "event"), and the work of separation
  takes the cascade there (`recording._fixed_unloading_path`).  A brush
  whose tips are not level is pressed as contact problems, as by
  ``"events"``.
* ``"events"`` - exact event-driven path.  A brush of two or more pillars
  whose tips are not all level (rough, concave, length offsets) is pressed
  as non-adhesive contact problems (`contact_loading._contact_loading`:
  the same branch, checked on its samples, in a few constrained CG solves
  instead of one global solve per element that joins); single bodies, level brushes (one
  loading event) and the unloading of every structure go event by event.
* ``"element_events"`` - the event-driven path with every element event on
  the loading branch too: the reference that ``"events"`` is tested against.
* ``"pillars"`` - the pillar-level model of a brush of flat tips, level or
  of unequal lengths (the package `brushbem.pillars`): a few numbers per
  pillar instead of every element, events exact in the reduced model,
  checked against ``"events"``; any other indenter is refused
  (`brushbem.pillars.check_applicable`).

The event-driven path: for a fixed contact set S the solution is affine in
d, p(d) = p(d0) + (d - d0) a with a = A_S^-1 1, and the penetration outside
S is affine too; the path jumps to the displacement at which the next
element reaches the critical stress or touches, records that state (an
equilibrium on the threshold), lets the element leave or join and follows
the cascade at the same d.  There is no step-size error: the force
  extremum is found exactly up to the solver tolerance.  Elements whose event
  displacements lie within ``LoadPath.event_window`` x h of each other are
  treated together (`brushbem.protocol.problem.event_tie`).

Both work on a window of the grid that holds the contact set with a margin
(the half-space convolution is translation invariant).  After every
equilibrium a bound proves that nothing outside the window penetrates; when it
cannot, the window is rebuilt around the contact and, if the bound still fails,
the penetration is checked on the whole grid and the window enlarged to take in
what touches (`window.WorkingWindow`).  The CG solves run on the block of
the window around the contact set (``SolverCache.sub_operator``).  The event path also keeps the
deflections of the pressure and of A_S^-1 1 on the window in step (both are
affine between events), so that an event transforms only the new A_S^-1 1.

The package's modules:

* `problem` - what is asked: `ContactProblem`, `LoadPath`, `State`.
* `paths` - the drivers `pull_off` and `indent`: the fixed-step path (with
  the force search of its loading) and the event-driven path.
* `events` - the events inside a fixed step and the event path's step.
* `contact_loading` - a brush's loading branch as contact problems.
* `path_states` - the `State` records the paths make of the path's state
  (its total force, contact area and attached pillars).
* `values` - `PathState`, the path's state as one frozen value, and `Known`.
* `steps` - the steps that take the path's state and give the next
  (`solve_from`, `step_from`, ...) and `PathContext`, what they share besides
  (the problem's constants, the product ledgers); `unit_response` - the
  event path's unit response as such steps; the state carries
* `window` - `WorkingWindow`, the working window as a value: its operator,
  the tip heights and the checks that nothing outside the window touches, and
* `connections` - `ConnectionState`, the viscoelastic history and the
  nonlinear pillar law's pieces and breaks (the springs and tip offsets
  they give the solves).
* `recording` - `record_pull_off`: curve, snapshots, summary.
"""

from __future__ import annotations

from brushbem.protocol.paths import LOADING_SAMPLES, indent, pull_off
from brushbem.protocol.problem import ContactProblem, LoadPath, NotConvergedError, State
from brushbem.protocol.recording import PullOffRecord, record_pull_off, work_of_separation
from brushbem.protocol.steps import PathContext

__all__ = [
    "LOADING_SAMPLES",
    "ContactProblem",
    "LoadPath",
    "NotConvergedError",
    "PullOffRecord",
    "State",
    "PathContext",
    "indent",
    "pull_off",
    "record_pull_off",
    "work_of_separation",
]
