# labels: python
"""marble.viscosity.reverse_poiseuille(mass_proportional=True) (doc/suspensions.md,
"Viscosity of a suspension"): the body force on particle i is +-g m_i/<m>, i.e.
the same acceleration for every particle, as a pressure gradient gives neutrally
buoyant colloids; the net force is zero; with equal masses it is the old
per-particle force. The forces are read at each force update of a short run."""
import numpy as np
import pytest

import marble
from marble.viscosity import reverse_poiseuille

if not marble.has_features("DPD", "MASS", "EXTERNAL_FORCE"):
    pytest.skip("needs DPD, MASS, EXTERNAL_FORCE", allow_module_level=True)


def fluid(masses):
    rng = np.random.default_rng(3)
    L = 6.0
    s = marble.System(box_l=[L, L, L])
    s.time_step = 0.01
    n = len(masses)
    s.part.add(pos=rng.uniform(0, L, (n, 3)), mass=masses, v=rng.normal(size=(n, 3)) * 0.1)
    s.non_bonded_inter[0, 0].dpd.set_params(weight_function=1, gamma=4.5, r_cut=1.0)
    s.thermostat.set_dpd(kT=0.1, seed=2)
    return s


def captured_forces(s, **kw):
    """The ext_force of every force update during a short reverse_poiseuille run."""
    seen = []
    run = s.integrator.run
    parts = s.part.all()

    def spy(steps=1, **a):
        seen.append((np.asarray(parts.pos)[:, 2].copy(), np.asarray(parts.ext_force).copy()))
        return run(steps, **a)

    s.integrator.run = spy
    try:
        reverse_poiseuille(s, g=0.05, time=0.4, equilibration=0.0, n_blocks=2, update_every=5,
                           sample_every=10, n_bins=4, margin=0.0, **kw)
    finally:
        s.integrator.run = run
    assert np.all(np.asarray(parts.ext_force) == 0.0)  # restored
    return seen


def test_mass_proportional_force():
    rng = np.random.default_rng(5)
    masses = np.where(rng.random(400) < 0.2, 12.0, 1.0)
    s = fluid(masses)
    L = s.box_l[2]
    for z, f in captured_forces(s, mass_proportional=True):
        sg = np.where(np.mod(z, L) < 0.5 * L, 1.0, -1.0)
        a = sg * 0.05 / masses.mean()
        a -= np.sum(masses * a) / masses.sum()
        np.testing.assert_allclose(f[:, 0], masses * a, rtol=0, atol=1e-14)
        np.testing.assert_array_equal(f[:, 1:], 0.0)
        assert abs(f[:, 0].sum()) < 1e-12
        # the force density is n g as for the per-particle force (up to the zero-net-force shift)
        assert np.sum(np.abs(masses * sg * 0.05 / masses.mean())) == pytest.approx(0.05 * len(masses))


def test_equal_masses_same_as_per_particle():
    s1, s2 = fluid(np.ones(300)), fluid(np.ones(300))
    a = captured_forces(s1, mass_proportional=True)
    b = captured_forces(s2)
    assert len(a) == len(b)
    for (_, fa), (_, fb) in zip(a, b):
        np.testing.assert_allclose(fa, fb, rtol=0, atol=1e-15)
