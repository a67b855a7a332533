"""The pillar-level model of a brush of flat rigid tips: ``LoadPath.method = "pillars"``.

The element-level paths solve for the pressure on every element of every
tip.  A flat rigid tip in full contact carries a pressure that is almost
fixed by its own raster: the half-space inverse of a uniform displacement,
with small corrections where its neighbours' field is not uniform across it.
This model keeps a few numbers per pillar instead of every element.

Basis
    For every raster shape (the elements a tip holds), the full BEM on that
    tip alone gives the pressures phi_k = K_R^-1 P_k of the displacement
    polynomials P_k of the tip's coordinates: 1 (the uniform mode, whose
    amplitude is the tip's mean displacement), x and y (``modes="tilt"``),
    and x^2, x y, y^2 (``modes="quadratic"``, the default), made
    K-orthogonal to phi_0, so that only phi_0 carries a net force.  A tip's
    pressure is p = sum_k a_k phi_k.  Bases are cached by raster shape:
    pillars of a lattice share one; a random layout has a few shapes.

Coupling
    G_ij = Phi_i^T K_ij Phi_j, the Galerkin projection of the half-space
    between the modes of pillars i and j: exact (element-pair sums of the
    Love kernel over the two footprints, cached by the pair's shapes and
    offset) for centres closer than ``near`` (default 8 pillar radii), and by
    the multipole expansion of 1/r to second order in the modes' moments
    (the monopole F / (pi E* r) with its dipole and quadrupole corrections,
    and the element square's own second moment) beyond.  On a lattice
    (`brushbem.pillars.lattice`) the far sums are convolutions over
    the lattice, done by FFT, with every tip's moments taken about its
    lattice point; other layouts keep dense couplings.  Springs of every
    level (`brushbem.physics.structure.SpringLevel`, pillars' own and hierarchy
    clusters) enter the uniform mode as in the element operator: the
    Galerkin projection of A = K + sum_l (h^2 / k_l) P_l^T P_l.

Equilibrium
    On the attached set S the uniform amplitudes solve the pillar-level
    system (G00 + H)_SS a_0 = s_S (d - g_S) (s the force of phi_0, g the
    pillar's length offset): a dense SPD system of the attached pillars
    whose inverse is kept and updated by rank-one steps as pillars join,
    leave or change shape (checked by its residual, refactorised when it
    drifts); on a lattice with more than
    `brushbem.settings.Switches.kept_pillars` attached, by CG on the
    lattice's FFT product, preconditioned by a circulant on compact sets and
    by the near field's sparse factor on scattered ones
    (`brushbem.pillars.cg`), to a relative residual of 1e-11.  The
    higher modes follow locally from the field that the
    others' uniform modes cause across the tip (``coupling="local"``);
    ``coupling="full"`` solves all modes together (a dense factorisation per
    solve, small brushes).  Everything is affine in d on a fixed state, so,
    as on the element event path, the next event is found in closed form.

Loading of tips of unequal lengths (roughness, a length profile, a lengths file)
    The exact path presses such a brush as the non-adhesive contact problem
    at every d (`brushbem.protocol.contact_loading`): a tip that has just
    touched is in partial contact.  The model solves that problem at the
    pillar level (`brushbem.pillars.loading`): a tip holds the footprint slots where it
    meets the surface (the others' field across its footprint fitted by its
    polynomials from their projections on its modes, plus its own modes'
    exact displacement), an element in tension leaves, until neither
    happens; the preload force's displacement by Newton steps on the affine
    F(d) of a fixed set.  While pressing, the higher modes' near field is
    fed back (a fixed point): the edge of a partial contact depends on it
    (a concave 16 x 16 brush at k~ = 1e-2 without it: F_A +9.7 %).  A
    pillar that releases slots goes on releasing on its own in the same
    round, and a set already solved is replayed, not solved again (a cycle
    of edge slots runs to the flip limit without solves): the same contact
    in fewer rounds (`brushbem.pillars.loading`).

Detachment (Pohrt-Popov) and touch
    The criterion is the element grid's: an element of a tip detaches when
    its pressure, reconstructed from the basis, falls below -Sigma_c,
    Sigma_c = sqrt(E* dgamma / (0.473201 h)).  An element that reaches it
    leaves and the pillar peels on its own with the rest of the brush frozen,
    exactly as the element path's local cascade does (a raster of the
    remaining elements gets its own basis, the others' field across it is
    the fit above), until it is stable or gone; then the brush is solved
    again at the same d, and so on (the cascade).  A pillar that touches
    while pulled (a footprint slot meets the surface) enters with the slots
    that penetrate.

Accuracy against ``method = "events"`` (`docs/pillars/variants.md`, written
by ``docs/pillars/variants.py``, on ten 4 x 4 and 8 x 8 lattices, level and
rough, k~ from 10 to 1e-4): the uniform mode alone is +6.5 .. +22 % off on
F_A (the neighbours' field tilts and bends the pressure on every tip, a tip
on the brush's edge most, and the uniform mode misplaces the edge stress);
tilts with peeling tips -1.6 .. -0.2 %; the quadratic modes with peeling
(the default) -0.3 .. +0.4 % on F_A and -0.4 .. +0.2 % on the work, and
coupled in full -0.1 .. +0.1 %.  A tip peels (its corner elements leave
first): one that detaches whole at its first edge element comes off early.
At 2.3, 3.6 and 7.2 elements' radius the uniform and tilt models get worse
as the tip is resolved better, the quadratic model stays within 0.6 %.

The families of `docs/pillars/validation.md` (written by
``docs/pillars/validation.py``: flat, rough, random, hierarchical and
concave brushes of 64, 256 and 1024 pillars at k~ = 10, 1e-2 and 1e-5,
each against the exact path) hold every case within 1 % on F_A, 3 % on
the work and 2 % on the pillars attached at pull-off.

Cost: per event O(n^2) for the n attached pillars (the kept inverse), or
O(M log M) per CG iteration beyond ``Switches.kept_pillars`` on a lattice (7-9
iterations a solve), and O(M log M) for the M pillars of a lattice (the
FFT, and a bound at pillar level on how far each free tip is from the
surface, so that only the attached pillars and the free ones that may touch
are looked at slot by slot); O(M^2) off a lattice.  On a lattice the memory
is O(M) besides the kept inverse and G00, kept up to
`brushbem.pillars.basis.DENSE_PILLARS` pillars and filled entry by
entry as the solve reads it.  Measured on the chapter-5 family
(``benchmarks/large_brush.py``, CPU seconds of one core): 1024 pillars
3.2-3.5 s (the exact path 79-87 s, ``benchmarks/pillars.py``; measured again
with the tips' own bases, ``--sizes 32 --sigma 1 --repeat 3``: 5.5 s, median
of three, against the exact path's 54 s in the same run, 1/9.9; the states'
arrays written where the tips press and fewer fixed costs per event,
``--before e340948``: 2.88 s against the exact path's 42.7 s, 1/14.8, and
on a more loaded machine 3.77 s against 47.4 s, 1/12.6, where the revision
before took 5.43 s: the loading 1.43 s against the exact path's 4.36 s, the
pull-off 2.34 s against 43.1 s; the loading's rounds fewer, local release
and replayed cycles, ``--before c48c002``: loading 0.84 s against 1.10 s
before, the whole 2.78 s against the exact path's 42.1 s, 1/15.2, on a
machine loaded 5-6 on its two cores, the same F_A and work to 2e-15; on an
idle one the revision before took 2.41 s against 46.5 s, 1/19.3, its loading
0.95 s and pull-off 1.46 s; with the spent slots kept spent too,
``--repeat 5``, load 3-4: loading 1.00 s against 1.20 s, pull-off 2.18 s
against 1.96 s (the same solves and updates in both: the load's noise),
the whole 3.17 s against the exact path's 51.7 s, 1/16.3; with the far
field's and the peels' fixed costs cut, ``--before fe2b011 --repeat 5``,
load 2-4: 1.84 s, loading 0.55 s and pull-off 1.29 s, against 1.93 s
before and the exact path's 50.3 s, 1/27.4, the same F_A and work to the
last bit; on an idle machine 1.70 s against 39.5 s, 1/23.3), 4096 pillars
16 s, 10^4 pillars 45-51 s in 0.66 GB (806 pillars attached at the preload),
10^5 pillars (316 x 316, N = 5056) 35-39 min in 3.5 GB (2353 attached, 10523
states).  A level brush attaches every pillar (``--sigma 0 --kept-baseline``):
4096 pillars 12.6 s by CG against 39.4 s with the kept inverse, 10^4 pillars
42 s in at most 1 GB against 356 s in 4.1 GB (the same F_A to 5e-11 and work
to 4e-10).  A rough brush attaches a part (``--sizes 100 --sigma 0.5``): 10^4
pillars, k~ = 1e-2, pressed to F_c, loading 18.5 s (1424 pillars attached at
the preload, the kept inverse held on the partial set: `Switches.kept_partial_bytes`)
and pull-off 47 s (2959 states, 2108 solves) in 0.53 GB, against 21.5 s and
61 s for the same pull-off before the per-state costs fell (``--before``,
same run, the same F_A to 7e-15); by CG on the partial sets its loading had
not reached the preload in 600 s.  Measured again (``--sizes 100 --sigma 0.5
--exact-max 0 --before e340948 --repeat 2``, a loaded machine): 59.2 s
(64.4 and 54.0; loading 15.5 s, pull-off 43.7 s) against 72.6 s for the
revision before, in 0.53 GB, F_A and the work the same to the last digit.
With the loading's rounds cut (local release, replayed cycles, spent slots
kept spent near the last press's d; ``--before c48c002 --repeat 2``, load
4-7 on two cores): 58.9 s (59.9, 57.8; loading 12.5 s, pull-off 46.3 s)
against 63.8 s (loading 18.4 s), F_A the same to 1e-14, the work to 1e-15.
Where its time goes (py-spy, the whole run): the solves 54 % (the far
field's FFT over the whole lattice 23 %, about 5.4 ms a solve for its 24
transforms, and the kept inverse's product), the peels 14 %, the states
10 % (the N x N pressure and contact arrays every `State` carries, their pages
written afresh at every state; now held by element and built when read,
`State.pressed`: pull-off 29.4 s against 36.6 s, ``--before``), the rest the event search; the kept
inverse's updates (9 %) fall in the peels and the loading's rounds.  The
rough brush of 10^5 pillars (``--sizes 316 --sigma 0.5 --exact-max 0 --limit
2700``, N = 5056) did not finish in 45 min of wall time on a loaded machine
(16 CPU-min, 2.2 GB): its loading was in the preload search's sixth contact
problem (the force 0.2 % above F_c), 20 rounds into it at about 20 s a round.
Beyond `Switches.kept_partial` attached pillars the solves are CG on the
lattice, and the higher modes' near field fed back while pressing costs a CG
solve every round of `radiate`: 88 % of that loading's time (py-spy), each CG
product 24 FFTs of 640 x 640 (the products in the spectrum between them 24 %).
With the inverse kept on partial sets up to 16384 attached pillars
(``--kept-partial 16384``, `Switches.kept_partial`; the default stays 4096)
and the loading's rounds cut, the same loading took 179 CPU-s (load 3-4 on
two cores): ten presses, the preload search's seven reaching F_c at 4270
pillars attached, the fourth 93 s of it (9618 pillars joining at once, one
Schur complement of that size), peak memory 6.4 GB (the model 2.2 GB, the
rest that join's dense blocks: about five n^2 numbers at n = 10312); its
pull-off was not run.  Measured again with the switch held for the run
(the benchmark's ``--kept-partial`` had dropped its `settings.using` block,
fixed since; ``--kept-partial 16384``'s child, stopped at the preload): the
loading 133 CPU-s (4270 attached), peak resident 6.8 GB (6.5 GiB), within
``ulimit -v 8000000``.  With the default and the rounds cut it took the same
rounds (26 and 20 in the fourth and fifth presses) at 203 s and 185 s
against 93 s and 13 s kept, and was ten rounds into the sixth press at
655 CPU-s when stopped (15 min of wall time), in 2.2 GB.  With the near
field as CG's preconditioner on partial sets (`brushbem.pillars.cg`) the
default loads it: 359-376 CPU-s in two runs (load 4-5 on two cores), the
same ten presses to F_c at 4270 pillars attached, the fourth to sixth 88,
74-77 and 166 s, 159 CG solves of 13.8 iterations on average, peak 2.8 GB.
Its pull-off, stopped at 780 CPU-s: 300 states in 320 CPU-s (1.07 s a
state, a CG solve every second state at 13.3 iterations: the set stays
above ``kept_partial`` (then 4096), 4270 to 4223 attached, the force still compressive
at 0.81 F_c); at that rate a pull-off of tens of thousands of states (2959
at 10^4 pillars) takes hours, so it was not run to the end.  The kept
inverse's transients grow as n^2 (about 10.7 GB at 16384, beyond the 8 GB
this size is meant to run in), so on a partial set it is kept while their
estimate (`brushbem.config.resources.pillar_kept_bytes`: 9 n^2 numbers)
fits in `Switches.kept_partial_bytes` (2 GiB: 5461 pillars; a fixed count,
`Switches.kept_partial`, overrides it), and at run time in half of the
memory at hand, by CG beyond; the memory estimate counts it, and a run
beyond the memory at hand is refused naming the switches.  The brush's
4270 fit: its pull-off keeps the inverse, the first 300 states at 0.153
CPU-s a state against 1.06 by CG with ``kept_partial = 4096`` over the
first 100 in the same conditions (one thread, ``ulimit -v 8000000``, load
3-4; the force the same to 6e-11), loading 346-354 CPU-s in both, peak
3.1 GiB against 2.8 GiB.  With the states held by element (`State.pressed`:
their N x N arrays built only when read, two zeroed 5056 x 5056 arrays a
state before) its whole pull-off ran: 15575 states in all (3.6 a pillar attached at
the preload; 2.1 at 10^4 pillars, 1.4 at 1024: the pull-off's states grow
as n^1.3 from n = 32 to 100 pillars a side and n^1.4 from 100 to 316), loading 345
CPU-s, pull-off 1572 CPU-s (0.101 a state: the far field's FFT over the
640 x 640 padded lattice, about 0.1 s a call and 0.8 calls a state, is most
of it), 1917 CPU-s in all, peak resident 2.9 GB (2.74 GiB; one BLAS thread,
``ulimit -v 8000000``, nice 10 on a machine loaded 2-3; 39.6 min of wall
time), F_A 1.998e-6 and work 1.946e-9 (``benchmarks/large_brush.py --child
316 pillars 0.01 0.5 3``, the child of ``--sizes 316 --sigma 0.5
--exact-max 0``).  Before, the first 11500 states took about 1570 CPU-s
against 1235 here (0.135 against 0.107 a state, two runs of different
load).  The ``size`` study's sigma~ = 0.1 brush (phi = 0.12, k~ = 1e-2,
seed 0, pressed to F_c) attaches 4818 of 10^4 pillars and 18179 of 10^5
(18 %), beyond what the inverse is kept for at 10^5: its solves there are
CG on the lattice, each product a far field of 60-75 ms (24 transforms over
640 x 640).  Measured at 316 x 316 (``benchmarks/large_brush.py --sizes 316
--brush size --sigma 0.1 --seed 0 --exact-max 0 --states 110``, load 1-2):
loading 584 CPU-s (361 CG solves at 19.2 iterations), then the pull-off's
first 105 states in 91 CPU-s (0.87 a state: 0.50 solves a state at 22.3
iterations, 1.72 CPU-s a solve), peak 2.15 GB.  At 10^4 pillars by CG
throughout (``--sizes 100 ... --pillar-solve cg``) the pull-off's 1052
states took 0.064 CPU-s a state over its first 400, 0.143 on average (its
solves a state rise from 0.50 to about 1.25 as it detaches, at 19
iterations throughout); scaled so, the 10^5 pull-off's 4000-5500 states
(growing as n^1.2-1.4) would take 7600-10500 CPU-s, about 2.3-3.1
CPU-hours with the loading, so that part of the study stops at 10^4
pillars.  With the Ritz vectors kept from solve to solve (recycled
deflation, `brushbem.pillars.recycle`, 40 vectors; ``--before 499ac23``,
before and after in one run, machine loaded 5-7): at 316 x 316 the loading
took 510 CPU-s against 558 (13.2 iterations a solve against 19.2) and the
pull-off's first 195 states 118 CPU-s against 162 (1.37x; 13.9 iterations
a solve against 21.9), peak 2.23 GB; at 10^4 by CG throughout the whole
run took 155 CPU-s against 181 (pull-off 113 against 138, 1.22x; 14600
iterations against 25193), F_A and the work the same to 5e-12.  The
products fall with the iterations, but not the per-state costs besides
them (the kept vectors' products made afresh, the two-level steps); so the
10^5 part projects to 510 CPU-s of loading and 4000-5500 states at
1.9 / (1.22-1.37) CPU-s, 6100-9100 CPU-s in all (1.7-2.5 h).  With the
late iterations' far fields in single precision (`brushbem.pillars.cg`:
1.30x on the loading's first 40 solves at 316 x 316; at 10^4 by CG
throughout the pull-off 1.24x, the whole run 132 CPU-s against 165) it
projects to 390 CPU-s of loading and 1.07-1.26 CPU-s a state, 4700-7300
CPU-s (1.3-2.0 h): still beyond an hour.  With the far field by slabs of
the spectrum (`brushbem.pillars.lattice`: the transforms along y, the
spectral products and the transforms back 16 columns at a time, in the
cache; double-precision columns one at a time) and the CG's vectors on the
attached rows only (``--states 205 --before 0ffb9c6``, one of the two cores
busy with another process): loading 282 CPU-s against 332 (1.18x), the
pull-off's first 200 states 68.5 against 91.1 (1.33x), the same 6187
iterations and 7081 products (5050 single); at 10^4 by CG throughout the
whole run 111 against 127 CPU-s (pull-off 1.15x: below 512 x 512 points the
far field takes no slabs), F_A and the work the same to 1.1e-13 and
3.6e-13.  So the 10^5 part projects to 282 CPU-s of loading and 4000-5500
states at (1.07-1.26) / 1.33 = 0.80-0.95 CPU-s, 3500-5500 CPU-s (1.0-1.5
h) on one thread.  Run (``brushbem study size --parts rough_small
--skip-recorded docs/beyond --workers 1``, one worker, the machine's other
core busy throughout): 3105 s of wall time (52 min), 2.46 GB resident,
14630 states and 4209 solves, F_A / F_c = 0.461 (``docs/beyond/size``):
the states cost 0.2 s each on average, less than the first 200's (the
attached set shrinks as the brush peels).  A second core did not shorten it:
two threads for the far field (``BRUSHBEM_FFT_WORKERS = 2``,
`brushbem.pillars.lattice.far_workers`; 200 pull-off states from one
loaded state, ``--pull-off 200``, both cores shared with two or three
other processes) took 0.429 wall-s a state against 0.364 on one; on two
idle cores it was not measured.  At 10^4 pillars 96.7-97.9 % of all the
pillars share one set of moments along the pull-off (the full rasters; the
peeled ones make 183-281 other sets), so the far field of one kernel (a
transform each way) for them and a correction for the others might cut
the transforms up to sixfold; not tried.  Its
sets are scattered: every attached pillar's neighbours are
mostly off (`brushbem.pillars.cg.boundary_share` 0.93-1.0), where the near
field preconditions (12-25 iterations a solve at 10^4, 22 at 10^5) and the
circulant takes twice as many; a level brush's peel keeps compact sets, where
the circulant takes 5-6 and the near field 9-13, whatever their share of
the lattice (`brushbem.pillars.cg`).  By CG with the circulant a partial
set's solves took 21 iterations on average, 42 at most (64 x 64, sigma~ =
0.5, every solve by CG: loading 16.6 s), with the near field 10 and 18
(9.1 s).

Tip resolution
    By default a tip is held on the global grid's elements, so its
    resolution is the grid's (a lone flat tip's F_A is +2.7, +3.4, +2.1 and
    +1.0 % off at 4, 8, 16 and 32 elements per radius,
    ``data/resolution_error.csv``).  ``LoadPath.pillar_tip_resolution`` puts
    every tip on a finer raster of its own (`brushbem.pillars.tips`): the
    same brush on the grid N with tips f times finer is the model on the grid
    f N, while the global grid only places the pillars; a peeled raster of a
    footprint of 150 elements or more gets its modes through the footprint's
    kept inverse (`brushbem.pillars.modes`).  Against the exact path on the
    grid f N (``benchmarks/pillars.py --tips``: 8 x 8 brushes at phi = 0.16
    on N = 142, 4.0 elements per radius, pressed to F_c): tips at 16 elements
    per radius are -0.02 % (F_A) / +0.12 % (work) off on a rough brush
    (sigma~ = 1) at k~ = 10 in 4.7 CPU-s (the exact path on N = 568: 461 s),
    -0.39 % / -0.80 % on a level one in 12.7 s (113 s); at 8 elements per
    radius -0.35 .. +0.02 % (F_A) and -0.67 .. +0.19 % (work) at k~ = 10 and
    1e-5.  The grid's own tips there are +19 % (rough) and +2.2 % (level)
    from the exact path at 16 elements per radius: at the shipped 3-4
    elements per radius the tips decide the answer's error, and ``--refine``
    refines them alone (`brushbem.runs.refine`).  What fine tips cost
    (``benchmarks/pillars.py``: 1024 pillars at 16 elements per radius,
    about 9 times the grid's tips at 4): more steps of peeling (3339 states
    against 619) and a basis per peeled raster (half of the time), not
    the tips' bases or near-field blocks (computed once per shape and
    offset) nor the pillar-level system (the same M pillars and modes).
    The flat 8 x 8 brush at k~ = 10 (cProfile of ``benchmarks/pillars.py
    --tips 7.2 14.4 --tip-brush 8 --sigma 0 --stiffness-ratio 10
    --exact-elements 0``): 14, 12 and 30 states at 3.6, 7.2 and 14.4
    elements per radius in 0.2, 0.8 and 5.3 CPU-s; at 14.4 the peels are
    84 % of it, 156 of them in 3088 rounds (a tip's detachment front moves
    about an element a round) with 2875 new raster bases.  Those rounds are
    already taken at one d, without states or brush solves: once a flat
    tip's edge leaves, the rest follows at falling force (Kendall's
    instability), which the peel follows round by round because a tip that
    stops partly peeled decides F_A.  The states between them are events
    with a load increase (a finer raster's corner and edge elements leave
    in more, smaller stable steps), and F_A is the largest force over them:
    taking them together changes the answer.
    The validation families (``docs/pillars/tips.csv``, written by
    ``docs/pillars/tips.py``: flat, rough, random, hierarchical and concave
    8 x 8 brushes at k~ = 10, 1e-2 and 1e-5) with tips at 7.2 elements per
    radius on N = 128 are -0.57 .. +0.40 % (F_A) and -1.0 .. +1.2 % (work)
    from the exact path on N = 256, in 0.22 of its time; with tips at 14.4
    (N = 512; k~ = 10 and 1e-5, every family but the rough one at 1e-5)
    -0.46 .. +0.06 % and -0.66 .. +1.0 %, in 0.03 of its time, but for two
    outside the targets: the concave brush at k~ = 10, +2.3 % (F_A) and
    +1.7 % (work) (at 7.2 per radius +0.33 %), and the random one at 1e-5,
    -1.2 % (F_A).  The concave brush's F_A at k~ = 10 is the net of
    compressed corner pillars and pulled ones (``docs/pillars/pillar_forces.py
    concave 10 4``, 70 CPU-s): at the preload the model's pillar forces
    are the exact path's to 8.8e-7 (0.1 % of the largest); at pull-off the
    pillars' |F_i| sum to 4.3 F_A, and the model's differ by at most 2.3e-6
    each and by -2.7e-5 in sum: 0.53 % of sum |F_i|, 2.3 % of F_A (the
    pull-off displacement 0.5 % apart).  The random brush at 1e-5
    (``pillar_forces.py random 1e-5 4``, 12 CPU-min): on soft springs
    every pillar carries about F / 64 and F_A is the weakest pillar's; in
    the model one pillar comes off before the exact path's peak (d =
    -17.17, all 64 attached), and the other 63 peak at d = -17.23 with
    1.2 % less force: one tip's strength in its neighbours' field, with
    nothing to average it, is the brush's error.  Which modes of the
    neighbours' field that tip misses is not known.
    The grid's own tips (3.6 per radius, the
    default) are +0.0 .. +4.1 % (F_A) and up to +7.5 % (work) from the
    exact path on N = 256, +2.2 .. +19 % and +4.4 .. +22 % from the one on
    N = 512.  The exact path is not converged there either.  Where its F_A
    is in the asymptotic range over N = 128, 256 and 512
    (``docs/pillars/tips_extrapolated.csv``: flat and hierarchical at
    k~ = 10, observed order 0.98-1.02; flat, hierarchical, concave and
    random at 1e-5, 0.69-1.49), against its first-order extrapolation the
    default is +2.8 .. +7.8 % (the random brush the least), tips at 7.2 per
    radius +1.1 .. +4.2 % and at 14.4 -0.6 .. +2.2 % (the extrapolation's
    own error 0.05 .. 1.3 %); the
    rough, random and concave brushes at k~ = 10 are outside it (F_A not
    monotone, or its steps growing: -12 % from N = 256 to 512 on the rough
    one).
    A brush's F_A converges no faster than a lone punch's: a tip resolution
    within 1 % of the converged F_A is beyond 16 elements per radius,
    which cost 7.4 times the grid's tips at 10^4 pillars (before the
    peeled rasters' cheaper modes, 0.81 of the time at 1024 pillars);
    ``--refine`` extrapolates the tips instead.
    The pillar model with tips asked at 28.9 elements per radius
    (``benchmarks/pillars.py --tips 28.9 --tip-brush 8 --sigma 0
    --stiffness-ratio 10 --exact-elements 0``; 28.9 exceeds 8 x 3.611, so
    the tips ran at the factor 9, 32.5 per radius) puts the flat 8 x 8 brush
    at 0.0083952 (k~ = 10) and 0.0122299 (1e-5), 1.1 % and 0.4 % above the
    exact path's first-order extrapolation (0.0082899, 0.0120796).  What that
    gap means is settled in `docs/pillars/accuracy.md` ("The reference").

Against the limit (`docs/pillars/accuracy.md`: the reference, calibrated tips, criteria at coarse tips, a
small brush's correction, a periodic cell, the routes, and whether tips of 3-4 elements per radius can be shown
within 1 %)
    The reference is the flat brush's continuum problem (``docs/pillars/continuum.py``, rigid circular tips on
    springs, exact to 2e-9) with its tips' peel: a flat tip whose K varies along its edge peels stably before it
    runs away, in the continuum (``docs/pillars/front.py``: the first-order perturbation of its edge, 1.19 %
    beyond the first point at eps = 0.2, over 88 degrees of the edge, 0.044 a deep) as on the raster
    (``fine_tip.py``: the exact path of one tip to 160 elements per radius peels the same region, its gain
    2.0 % at 57.8 falling to 1.65 % at 160).  So the first point (the first tip at K_c; 0.0118133 at k~ = 1e-5, 0.0081111 at
    10) is not the limit, and the per-element criterion, which tends to it, is not the route.  With every
    tip's first-order peel the flat 8 x 8 brush holds 0.0120385 at k~ = 1e-5 (+1.9 %) and 0.0082839 at 10
    (+2.1 %) (``front_brush.csv``), the exact path's old first-order extrapolation within 0.34 % and 0.07 % of
    them; the edge tips' raster gains lie above the first-order ones at every resolution and fall with h (2.98 / 2.96 % on
    the middle of an edge at 57.8 / 80 elements per radius, ``fine_tip_brush.csv``), so their capacity at 80
    (0.0121588, the neighbours' deflection entering negated: `tilted.brush_fields`) bounds the brush above: at
    k~ = 1e-5 the limit is known to 1.0 % (``docs/pillars/limit.py``, middle 0.0120986).
    Tips of 3-4 elements per radius within 1 % of the limit are not shown (``limit.csv``): the default on the
    families' raster is +7.0 .. +8.1 % at k~ = 1e-5 and +7.8 % over the lower end at 10, plain tips averaged
    over placements of the lattice on their raster +3.7 % (3.6 per radius) .. +1.2 % (39.7) on the middle;
    8 of the 18 extrapolations of fine tips' placement means at k~ = 1e-5 land within 1 % of both ends
    (``limit.csv``), at hundreds to thousands of CPU-s on 8 x 8 pillars; the per-element criterion's mean at 3.6 per radius does too, on its
    way to the first point (-1.3 % below the lower end at 14.4).  With the tips on their rasters
    (``pillar_tip_peel = False``) a brush's F_A error in every run is the brush's own against the continuum limit
    (`brushbem.config.advice`, ``brush_resolution_error.csv``: +3.7 % at 3.6, +1.4 % at 28.9, +1.2 % at 39.7
    per radius).
    By default (``LoadPath.pillar_tip_peel`` unset, `peel`) every whole tip leaves at its continuum
    capacity, its K(theta) read off its modes: the flat 8 x 8 brush at 3.6 elements per radius -0.75 % at
    k~ = 10 and -0.71 % at 1e-5 of its limit (placements -0.75 .. +1.04 % at 10), the flat, hierarchical and
    concave families within 0.8 % of the exact path's extrapolation, the random one inside its own continuum
    interval (``docs/pillars/peel.csv``, ``front_random.csv``, ``front_random_tips.csv``), the rough one within
    0.3 % of its own tips at 28.9 per radius where F_A is not a small part of F_c and -3.9 .. -1.1 % where it
    is a tenth to a quarter (``docs/pillars/rough.csv``); a run reports that error.  The thesis's studies
    and the validation against the exact path on the same raster (``docs/pillars/validation.md``) name
    ``pillar_tip_peel = False``: the tips peel on their rasters, element by element, as the exact path's.

Where it does not apply it refuses, naming the key: tips that are not flat
(``brush(tip=...)``), a tilted base (``brush(tilt=...)``), viscoelastic
connections (``Indenter.viscoelastic``), nonlinear pillar laws
(``Indenter.pillar_law``), no adhesion (``work_of_adhesion = 0``), and
indenters that are not brushes.  Beyond a filling factor of 0.2 it warns
(`brushbem.pillars.domain`): measured against the exact path, its error
grows with phi (up to 1.3 % on F_A and 2.9 % on the work at 0.3, 4.4 % and
12 % at 0.6).

The package's modules:

* `path` - `pull_off`, the public path (``brushbem.protocol.pull_off`` with
  ``method = "pillars"`` calls it).
* `state` - `PillarState`, the state of one pull-off as a frozen value (the
  attached set, the rasters, the amplitudes, the loading's flags), its
  `RasterCache` (the model's raster arrays and the kept inverse, owned by the
  path), and the steps from state to state: the solves, the peeling and the
  cascades.
* `events` - the events, from the first touch to separation.
* `loading` - the loading of tips of unequal lengths (contact problems at
  pillar level).
* `basis` - `PillarModel`: the bases, couplings and springs.
* `modes` - `Basis`, `Bases`: the modes of one raster (a peeled raster of a
  large footprint through the footprint's kept inverse).
* `lattice` - the far field on a lattice by FFT.
* `tips` - the tips' raster: the global grid's footprints, or every tip on a
  finer raster of its own (``LoadPath.pillar_tip_resolution``).
* `peel` - a flat tip's peel in the continuum (the first-order edge model, its
  gain table) and K(theta) of a tip from its modes: whole tips leaving at their
  continuum capacity (``LoadPath.pillar_tip_peel``).
* `calibration` - a lone tip's pull-off on its raster, and the criterion
  calibrated to Kendall's force (``LoadPath.pillar_tip_calibration``).
* `solver` - the pillar-level solve (the kept inverse, the full coupling)
  and the higher modes' near field fed back (`radiate`).
* `cg` - the solve without a kept inverse (CG on the lattice's FFT).
* `recycle` - the Ritz vectors that CG keeps from solve to solve (its
  two-level preconditioner on scattered sets).
* `checks` - the refusals (`check_applicable`).
* `domain` - where it is accurate: the warning beyond `VALIDATED_FILLING`.

Imports run one way: tips, modes, lattice, peel < calibration < basis, recycle < cg < solver < state < loading <
events < path.
"""

from __future__ import annotations

from brushbem.pillars.basis import MODES, NEAR_RADII, Basis, PillarModel
from brushbem.pillars.checks import check_applicable
from brushbem.pillars.path import pull_off
from brushbem.pillars.state import PillarState, RasterCache

__all__ = ["MODES", "NEAR_RADII", "Basis", "PillarModel", "PillarState", "RasterCache", "check_applicable",
           "pull_off"]
