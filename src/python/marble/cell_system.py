"""Cell system: a regular cell grid with Verlet lists and a skin."""


class CellSystem:
    def __init__(self, system):
        self._system = system

    @property
    def skin(self):
        """Verlet-list skin (> 0, at most box_l/2). Lists are rebuilt when a
        particle has moved more than skin/2; a particle moving farther than the
        skin in one step stops the run (a blow-up)."""
        return self._system._core.skin

    @skin.setter
    def skin(self, value):
        self._system._core.skin = value

    def set_regular_decomposition(self, use_verlet_lists=True):
        """Marble always uses a regular cell grid with Verlet lists."""
        if not use_verlet_lists:
            raise ValueError("parameter 'use_verlet_lists' must be True (Marble always uses them)")

    @property
    def node_grid(self):
        """MPI ranks per axis (px, py, pz): the box is cut into px*py*pz equal
        domains, one per rank, chosen to minimise the domain surface (ties:
        x first). (1, 1, 1) without mpiexec. Read-only."""
        return tuple(int(n) for n in self._system._core.node_grid())

    def local_domain(self):
        """(lower corner, size) of this rank's domain (not collective)."""
        lo, size = self._system._core.local_domain()
        return lo, size

    def local_ids(self):
        """Ids of the particles this rank owns after the last rebuild (not collective)."""
        return list(self._system._core.local_ids())

    def get_state(self):
        core = self._system._core
        return {"type": "RegularDecomposition", "skin": core.skin,
                "n_cells": list(core.n_cells()), "max_cut": core.max_cut(),
                "verlet_rebuilds": core.n_rebuilds(), "node_grid": list(core.node_grid())}
