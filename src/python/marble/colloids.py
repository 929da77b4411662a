"""Helpers to set up marble colloids (Zhou & Schmid) in a DPD solvent.

    from marble.colloids import add_marble
    col = add_marble(system, pos=system.box_l / 2, radius=3.0, gamma=5.0)
"""
import numpy as np

from .code_features import assert_features

WCA_CUTOFF = 2.0 ** (1.0 / 6.0)


def neutrally_buoyant_mass(radius, solvent_density, solvent_mass=1.0):
    """M = rho m (4/3) pi R^3 (reference.md section 3)."""
    return solvent_density * solvent_mass * 4.0 / 3.0 * np.pi * radius ** 3


def add_marble(system, pos, radius=3.0, gamma=5.0, colloid_type=1, solvent_types=(0,),
               coupling="tunable_slip", r_cut=1.0, weight_function=1, k=1.0, mass=None,
               rinertia=None, v=(0.0, 0.0, 0.0), remove_overlap=True, excluded_volume=True,
               lj_epsilon=1.0, lj_sigma=1.0, lj_cutoff=WCA_CUTOFF, lj_offset=None):
    """Add one marble colloid and couple it to the solvent.

    - mass: default neutrally buoyant, M = rho_solvent m (4/3) pi R^3, with the
      solvent's number density and mean mass measured before insertion.
    - rinertia: default (2/5) M R^2 (solid sphere); rotation is switched on.
    - excluded volume: LJ with offset R - sigma and a WCA cutoff (reference.md
      section 3), so solvent beads stay at r >~ R; set excluded_volume=False
      to manage it yourself, or pass lj_* to override.
    - remove_overlap: delete solvent beads closer than R - sigma + lj_cutoff to the centre
      (inside the repulsive range), so the first step does not blow up.
    - the marble coupling non_bonded_inter[colloid_type, s].marble for every s in solvent_types.

    Returns the colloid's ParticleHandle.
    """
    assert_features("MARBLE")
    pos = np.asarray(pos, dtype=float)
    if pos.shape != (3,) or not np.all(np.isfinite(pos)):
        raise ValueError("parameter 'pos' must be a finite 3-vector")
    if not (np.isfinite(radius) and radius > 0):
        raise ValueError(f"parameter 'radius' must be > 0, got {radius}")
    solvent_types = [int(t) for t in np.atleast_1d(solvent_types)]
    if int(colloid_type) in solvent_types:
        raise ValueError("parameter 'colloid_type' must differ from the solvent types")
    parts = system.part.all()
    solvent = [pid for pid, t in zip(parts.id, parts.type) if t in solvent_types] \
        if len(parts) else []
    rho_before = len(solvent) / np.prod(system.box_l)
    offset = radius - lj_sigma if lj_offset is None else lj_offset
    if offset < 0:
        raise ValueError(f"LJ offset R - sigma = {offset} < 0: use radius > lj_sigma or set lj_offset")
    if remove_overlap and solvent:
        sl = system.part.by_ids(solvent)
        d = sl.pos_folded - pos
        L = system.box_l
        d -= L * np.round(d / L)
        r = np.linalg.norm(d, axis=1)
        inside = np.asarray(solvent)[r < offset + lj_cutoff]
        if len(inside):
            system.part.by_ids(inside).remove()
            solvent = sorted(set(solvent) - set(int(i) for i in inside))
    if mass is None:
        if not solvent:
            raise ValueError("no solvent particles to derive a neutrally buoyant mass from: "
                             "add the solvent first or pass mass=")
        rho = rho_before
        m_s = float(np.mean(system.part.by_ids(solvent).mass))
        mass = neutrally_buoyant_mass(radius, rho, m_s)
    if rinertia is None:
        rinertia = 0.4 * mass * radius ** 2
    colloid = system.part.add(pos=pos, v=v, type=colloid_type, mass=mass, rinertia=rinertia,
                              rotation=True)
    for s in solvent_types:
        if excluded_volume:
            system.non_bonded_inter[colloid_type, s].lennard_jones.set_params(
                epsilon=lj_epsilon, sigma=lj_sigma, cutoff=lj_cutoff, shift="auto", offset=offset)
        system.non_bonded_inter[colloid_type, s].marble.set_params(
            radius=radius, gamma=gamma, r_cut=r_cut, weight_function=weight_function, k=k,
            coupling=coupling)
    return colloid
