"""Cell system: a regular cell grid with Verlet lists and a skin."""
import numbers

#: Verlet skin the lists use when a script sets ``skin = 0`` (Marble's default).
ZERO_SKIN_EFFECTIVE = 0.4


class CellSystem:
    """``system.cell_system``: the Verlet skin and the domain decomposition."""

    def __init__(self, system):
        self._system = system

    @property
    def skin(self):
        """Verlet-list skin in [0, box_l/2]. Lists are rebuilt when a particle
        has moved more than skin/2 (and, by default, a pair may be missing:
        ``list_check``); a particle moving farther than the skin in
        one step stops the run (a blow-up).

        ``skin = 0`` (accepted for ESPResSo scripts) reads back 0 but the lists
        then use a skin of min(0.4, box_l/2) internally: the forces are the same
        for every skin (a pair enters the list before it is within the cutoff),
        and Marble's blow-up check needs a distance a particle may move per step
        (doc/porting-from-espresso.md)."""
        if self._system.__dict__.get("_skin_zero", False):
            return 0.0
        return self._system._core.skin

    @skin.setter
    def skin(self, value):
        core = self._system._core
        if isinstance(value, numbers.Real) and not isinstance(value, bool) and value == 0:
            core.skin = min(ZERO_SKIN_EFFECTIVE, 0.5 * float(min(core.box_l)))
            self._system.__dict__["_skin_zero"] = True
            return
        core.skin = value  # validated in C++: (0, box_l/2]
        self._system.__dict__["_skin_zero"] = False

    @property
    def effective_skin(self):
        """The skin the Verlet lists use (differs from ``skin`` only after ``skin = 0``)."""
        return self._system._core.skin

    def tune_skin(self, min_skin, max_skin, tol, int_steps, adjust_max_skin=False):
        """Choose the Verlet skin that makes ``int_steps`` steps cheapest and
        set it; returns the skin (ESPResSo's ``cell_system.tune_skin``).

        A larger skin means fewer list rebuilds but more listed pairs to test
        every step (doc/benchmarks.md, "Verlet build and integrator passes").
        The search is a golden-section search on [min_skin, max_skin] down to
        an interval of ``tol``; each trial runs ``int_steps`` steps on a
        *copy* of the system (pickled: the whole state) and times them in
        process CPU time, so this system's state (positions, velocities, step
        counter, thermostat counters) is unchanged: only the skin is set. A
        trial skin at which a step moves a particle farther than the skin (a
        refused step) counts as infinitely slow. The choice depends on the
        machine's load; the physics does not depend on the skin (the pair
        sums only change at round-off through the list order).

        Parameters: ``min_skin`` > 0, ``max_skin`` > ``min_skin`` (at most
        half the smallest box length; with ``adjust_max_skin=True`` a larger
        value is lowered to that limit), ``tol`` > 0, ``int_steps`` >= 1.
        Runs on one MPI rank only (raises ``RuntimeError`` under mpiexec)."""
        import math
        import pickle
        import time

        from . import _marble
        core = self._system._core

        def real(name, x):
            if isinstance(x, bool) or not isinstance(x, numbers.Real) or not math.isfinite(x):
                raise ValueError(f"parameter '{name}' must be a finite number, got {x!r}")
            return float(x)

        min_skin, max_skin, tol = real("min_skin", min_skin), real("max_skin", max_skin), real("tol", tol)
        half_box = 0.5 * float(min(core.box_l))
        if adjust_max_skin:
            max_skin = min(max_skin, half_box)
        if not min_skin > 0:
            raise ValueError(f"parameter 'min_skin' must be > 0, got {min_skin}")
        if not min_skin < max_skin <= half_box:
            raise ValueError(f"parameter 'max_skin' must be in ({min_skin}, {half_box}] (min_skin, "
                             f"half the smallest box length), got {max_skin}")
        if not tol > 0:
            raise ValueError(f"parameter 'tol' must be > 0, got {tol}")
        if isinstance(int_steps, bool) or not isinstance(int_steps, numbers.Integral) or int_steps < 1:
            raise ValueError(f"parameter 'int_steps' must be an integer >= 1, got {int_steps!r}")
        if _marble.mpi_size() > 1:
            raise RuntimeError("cell_system.tune_skin runs on one MPI rank only: tune the skin "
                               "without mpiexec and set cell_system.skin in the MPI run")
        blob = pickle.dumps(self._system)

        def cost(skin):
            trial = pickle.loads(blob)
            trial.cell_system.skin = skin
            try:
                trial.integrator.run(0)  # the list build at this skin, outside the timing
                c0 = time.process_time()
                trial.integrator.run(int(int_steps))
                return time.process_time() - c0
            except RuntimeError:  # a step moved a particle farther than the skin
                return math.inf

        g = (math.sqrt(5.0) - 1.0) / 2.0
        a, b = min_skin, max_skin
        c, d = b - g * (b - a), a + g * (b - a)
        fc, fd = cost(c), cost(d)
        while b - a > tol:
            if fc <= fd:
                b, d, fd = d, c, fc
                c = b - g * (b - a)
                fc = cost(c)
            else:
                a, c, fc = c, d, fd
                d = a + g * (b - a)
                fd = cost(d)
        best = c if fc <= fd else d
        self.skin = best
        return best

    _LIST_CHECKS = ("pairs", "half_skin")

    @property
    def list_check(self):
        """When the Verlet lists are rebuilt: ``"pairs"`` (the default) or
        ``"half_skin"``.

        ``"half_skin"`` rebuilds as soon as some particle has moved more than
        half the skin since the last build (ESPResSo's and LAMMPS's rule).
        ``"pairs"`` then first checks whether a pair can be missing from the
        list. Such a pair moved apart by more than the skin, so only particles
        that moved more than half the skin need comparing with those that
        moved more than ``skin - d_max``. The lists live ~1.25x longer, and the
        test is cheaper than the rebuilds it saves (3.5-5 % on a DPD fluid;
        doc/benchmarks.md, "The Verlet list's life"). Where that test does
        not apply, ``"pairs"`` acts as ``"half_skin"``:

        - other integrators than velocity Verlet, DPD-VV and Shardlow (RESPA
          substeps included);
        - Lees-Edwards boundaries, an SRD solvent, large-range types
          (``large_range_types``);
        - a periodic box shorter than 3 pair ranges (cutoff + skin).

        With colloids (marble, stick) the colloid pair list, built with the
        Verlet list, is kept only while no bead and colloid can have come
        closer by a skin (the largest displacement plus the largest colloid
        displacement below the skin). Both give the same forces; only the
        list order, and so the trajectories' last bits (Shardlow: its sweep
        order), differ. Saved in checkpoints."""
        return self._LIST_CHECKS[self._system._core.list_check]

    @list_check.setter
    def list_check(self, value):
        if not isinstance(value, str) or value not in self._LIST_CHECKS:
            raise ValueError(f"parameter 'list_check' must be one of {list(self._LIST_CHECKS)}, got {value!r}")
        self._system._core.list_check = self._LIST_CHECKS.index(value)

    def set_regular_decomposition(self, use_verlet_lists=True):
        """Accepted for ESPResSo scripts: Marble always uses a regular cell grid
        with Verlet lists. ``use_verlet_lists=False`` is accepted too; the forces
        are the same with or without lists (only the speed differs)."""
        if not isinstance(use_verlet_lists, (bool, int)):
            raise ValueError("parameter 'use_verlet_lists' must be a bool")

    def set_n_square(self, use_verlet_lists=True):
        """Accepted for ESPResSo scripts: Marble keeps its regular cell grid,
        which finds the same pairs as ESPResSo's N-square cell system."""
        self.set_regular_decomposition(use_verlet_lists)

    @property
    def node_grid(self):
        """MPI ranks per axis (px, py, pz): the box is cut into px*py*pz
        domains, one per rank (equal unless :attr:`domain_cuts` moved them), chosen to minimise the domain surface (ties:
        x first); with Lees-Edwards boundaries only the vorticity axis is
        split, e.g. (1, 1, P) for shear along x across y. (1, 1, 1) without
        mpiexec. Read-only."""
        return tuple(int(n) for n in self._system._core.node_grid())

    def local_domain(self):
        """(lower corner, size) of this rank's domain (not collective)."""
        lo, size = self._system._core.local_domain()
        return lo, size

    @property
    def domain_cuts(self):
        """The domains' boundaries along each axis: a tuple of three arrays,
        ``node_grid[d] + 1`` increasing positions from 0 to ``box_l[d]`` (the
        domain at node coordinate c along axis d is [cuts[c], cuts[c + 1])).
        By default the box is split into equal parts. Set it to move the
        boundaries by hand (a list of three entries, each ``None`` for the
        equal split or the positions as above), or ``None`` for the equal
        split along every axis; :meth:`balance` and
        :meth:`set_load_balance` move them from the measured work. Setting
        it is collective (every rank the same values); the particles move to
        their new ranks at the next force computation. Without mpiexec the
        single domain is the box. Part of the core's checkpoint (doc/io.md;
        doc/parallel.md, "Load balance")."""
        import numpy as np
        return tuple(np.asarray(c, dtype=float) for c in self._system._core.domain_cuts())

    @domain_cuts.setter
    def domain_cuts(self, value):
        import numpy as np
        core = self._system._core
        grid = core.node_grid()
        box_l = [float(x) for x in core.box_l]
        if value is None:
            core.set_domain_cuts([[], [], []])
            return
        if isinstance(value, (str, bytes)) or not hasattr(value, "__len__") or len(value) != 3:
            raise ValueError(f"parameter 'domain_cuts' must be None or a list of three entries (one per axis, "
                             f"each None or node_grid[d] + 1 positions from 0 to box_l[d]), got {value!r}")
        cuts = []
        for d, c in enumerate(value):
            if c is None:
                cuts.append([])
                continue
            try:
                a = np.asarray(c, dtype=float).ravel()
            except (TypeError, ValueError):
                raise ValueError(f"parameter 'domain_cuts[{d}]' must be None or a list of numbers, "
                                 f"got {c!r}") from None
            L, p = box_l[d], int(grid[d])
            tol = 1e-12 * L
            if a.size != p + 1:
                raise ValueError(f"parameter 'domain_cuts[{d}]' must have node_grid[{d}] + 1 = {p + 1} "
                                 f"positions (node grid {tuple(grid)}), got {a.size}")
            if not np.all(np.isfinite(a)) or abs(a[0]) > tol or abs(a[-1] - L) > tol:
                raise ValueError(f"parameter 'domain_cuts[{d}]' must run from 0 to box_l[{d}] = {L}, "
                                 f"got {a.tolist()}")
            if p > 1 and not np.all(np.diff(a) > 0):
                raise ValueError(f"parameter 'domain_cuts[{d}]' must be strictly increasing (every domain "
                                 f"wider than 0), got {a.tolist()}")
            a[0], a[-1] = 0.0, L
            cuts.append(a.tolist() if p > 1 else [])
        core.set_domain_cuts(cuts)

    _BALANCE_BY = {"particles": 0, "time": 1, "pairs": 2}

    def _balance_args(self, by, damping, threshold):
        if not isinstance(by, str) or by not in self._BALANCE_BY:
            raise ValueError(f"parameter 'by' must be 'time', 'particles' or 'pairs', got {by!r}")
        for name, x, lo, hi, lo_open in (("damping", damping, 0.0, 1.0, True),
                                         ("threshold", threshold, 0.0, float("inf"), False)):
            if isinstance(x, bool) or not isinstance(x, numbers.Real) or not (
                    (x > lo if lo_open else x >= lo) and x <= hi):
                rng = f"({lo}, {hi}]" if lo_open else f"[{lo}, inf)"
                raise ValueError(f"parameter '{name}' must be a number in {rng}, got {x!r}")
        return self._BALANCE_BY[by], float(damping), float(threshold)

    def balance(self, by="time", damping=1.0, threshold=0.05):
        """Move the domain boundaries once so that every slab of ranks along a
        split axis gets a share of the particles proportional to its speed
        (as LAMMPS's ``balance`` command with ``shift``):

        - ``by="time"``: a slab's speed is its particles per second of its
          ranks' own work (wall time less the time inside MPI calls, where a
          rank waits for the others) since the last balance, the last
          :meth:`set_load_balance` or the system's creation: a rank on a
          slower core or with costlier particles gets fewer. The boundaries
          then depend on the machine's timing, so the last bits of a
          trajectory are not reproducible from run to run; the physics is
          the same on any decomposition (doc/parallel.md).
        - ``by="particles"``: equal particle counts (deterministic).
        - ``by="pairs"``: equal counts of particles weighted by 1 + their
          pairs in the Verlet list (LAMMPS's ``weight neigh``): a denser
          region gets fewer particles (deterministic).

        ``damping`` in (0, 1]: the fraction of the way to the computed
        boundaries; ``threshold`` >= 0: nothing moves unless the largest
        rank's cost exceeds the mean by more than this fraction. Domains stay
        at least one pair range (cutoff + skin; twice that under Shardlow)
        wide. Collective. Returns a dict: ``imbalance`` (largest rank cost /
        mean, before), ``moved`` and the ``domain_cuts`` after."""
        b, damping, threshold = self._balance_args(by, damping, threshold)
        imbalance, moved = self._system._core.balance_domains(b, damping, threshold)
        return {"imbalance": float(imbalance), "moved": bool(moved), "domain_cuts": self.domain_cuts}

    def set_load_balance(self, every, by="time", damping=0.5, threshold=0.05):
        """Balance automatically during ``integrator.run()``: :meth:`balance`
        with these parameters after every ``every``-th step (as LAMMPS's
        ``fix balance``) of velocity Verlet, DPD-VV or Shardlow (RESPA
        substeps included; not during steepest descent or Brownian
        dynamics); ``every=0`` turns it off. Collective. Part of the
        checkpoint (with the number of balances so far), so a continued run
        balances at the same steps as the uninterrupted one."""
        if isinstance(every, bool) or not isinstance(every, numbers.Integral) or every < 0:
            raise ValueError(f"parameter 'every' must be an integer >= 0 (0: off), got {every!r}")
        b, damping, threshold = self._balance_args(by, damping, threshold)
        self._system._core.set_balance(int(every), b, damping, threshold)

    def get_load_balance(self):
        """The automatic balance's parameters and the number of balances that
        moved the boundaries so far (a dict)."""
        every, by, damping, threshold = self._system._core.balance_settings()
        by_name = {v: k for k, v in self._BALANCE_BY.items()}[by]
        return {"every": every, "by": by_name, "damping": damping, "threshold": threshold,
                "n_balances": self._system._core.n_balances()}

    def local_ids(self):
        """Ids of the particles this rank owns after the last rebuild (not collective)."""
        return list(self._system._core.local_ids())

    @property
    def large_range_types(self):
        """Which particle types get the coarse second cell grid
        (doc/architecture.md, "Two cell grids"): ``"auto"`` (default: types
        whose own pairs reach more than twice the shortest pair range, e.g. the
        colloids of a suspension, when they are at most a quarter of the
        particles), ``None`` (one grid for all types, as before), or a list of
        types. The pairs and forces are the same in every mode; only the cost
        differs. The choice made at the last list rebuild (e.g. after
        ``integrator.run(0)``) is in :meth:`get_state`: ``large_range_types``
        and the pair ranges (cutoff + skin) ``pair_range_small`` (solvent
        grid), ``pair_range_large`` and ``pair_range_large_small``. The
        setting is part of the core's checkpoint (doc/io.md)."""
        core = self._system._core
        mode = core.large_range_mode()
        if mode < 0:
            return "auto"
        if mode == 0:
            return None
        return list(core.large_range_types_requested())

    @large_range_types.setter
    def large_range_types(self, value):
        core = self._system._core
        if isinstance(value, str):
            if value != "auto":
                raise ValueError(f"parameter 'large_range_types' must be 'auto', None or a list "
                                 f"of types, got {value!r}")
            core.set_large_range_mode(-1, [])
        elif value is None:
            core.set_large_range_mode(0, [])
        else:
            try:
                types = [int(t) for t in value]
            except (TypeError, ValueError):
                raise ValueError(f"parameter 'large_range_types' must be 'auto', None or a list "
                                 f"of types, got {value!r}") from None
            if any(isinstance(t, bool) or int(t) != t for t in value):
                raise ValueError(f"parameter 'large_range_types' must hold integer types, got {value!r}")
            core.set_large_range_mode(1, types)

    def get_state(self):
        """Cell-system parameters and counters (a dict)."""
        core = self._system._core
        return {"type": "RegularDecomposition", "skin": self.skin, "effective_skin": core.skin,
                "n_cells": list(core.n_cells()), "max_cut": core.max_cut(),
                "verlet_rebuilds": core.n_rebuilds(), "list_check": self.list_check,
                "pair_test_applies": bool(core.pair_test_applies()), "node_grid": list(core.node_grid()),
                "domain_cuts": [list(c) for c in core.domain_cuts()],
                **self._large_range_state()}

    def _large_range_state(self):
        types, r_small, r_ll, r_ls = self._system._core.large_range_state()
        return {"large_range_types": list(types), "pair_range_small": r_small,
                "pair_range_large": r_ll, "pair_range_large_small": r_ls}
