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

    def get_state(self):
        core = self._system._core
        return {"type": "RegularDecomposition", "skin": core.skin,
                "n_cells": list(core.n_cells()), "max_cut": core.max_cut(),
                "verlet_rebuilds": core.n_rebuilds()}
