# labels: python
"""The mass option of samples/lees_edwards_suspension.py (doc/suspensions.md 7l):
``scene(..., mass_scale=M)`` multiplies every mass and rotational inertia by M
and keeps kT; the dissipative forces do not depend on the mass (no DPD_MASS_*
in the default build); the solvent's kinetic stress grows with M; Re and Pe."""
import math
import os
import sys

import numpy as np
import pytest

import marble
import marble.lees_edwards as le

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "..", "samples"))
import lees_edwards_suspension as les  # noqa: E402

pytestmark = pytest.mark.skipif(
    not marble.has_features("MASS", "ROTATION", "DPD", "HAT", "CONTACT", "LUBRICATION"),
    reason="needs MASS, ROTATION, DPD, HAT, CONTACT, LUBRICATION")


def _stick(mass_scale, **kw):
    return les.scene(0.3, [6.0, 6.0, 6.0], 0.0025, seed=5, boundary="stick", shardlow=False, equil=0.0,
                     mass_scale=mass_scale, **kw)


def test_masses_inertia_velocities():
    """M = 0.25 against M = 1 (same seed): the same positions; every mass and
    the colloids' inertia x M, velocities and spins / sqrt(M) (so kT is kept),
    zero total momentum (the momentum fix of 7k with unequal masses)."""
    s1, i1 = _stick(1.0)
    p1 = s1.part.all()
    col1 = np.asarray(p1.type) == 1
    m1, x1, v1 = np.asarray(p1.mass, float), np.asarray(p1.pos), np.asarray(p1.v)
    I1, w1 = np.asarray(p1.rinertia, float)[col1], np.asarray(p1.omega_lab)[col1]
    del s1, p1
    M = 0.25
    s, info = _stick(M)
    p = s.part.all()
    col = np.asarray(p.type) == 1
    assert col.sum() == i1["n_colloids"] > 10 and np.array_equal(col, col1)
    m = np.asarray(p.mass, float)
    np.testing.assert_array_equal(np.asarray(p.pos), x1)
    np.testing.assert_allclose(m, M * m1, rtol=1e-15)
    assert np.all(m[~col] == M) and np.all(m1[~col] == 1.0)
    assert np.allclose(m[col], M * i1["colloid_mass"]) and info["colloid_mass"] == pytest.approx(M * i1["colloid_mass"])
    np.testing.assert_allclose(np.asarray(p.rinertia, float)[col], M * I1, rtol=1e-15)
    assert info["rinertia"] == pytest.approx(M * i1["rinertia"]) and info["mass_scale"] == M
    v = np.asarray(p.v)
    np.testing.assert_allclose(v, v1 / math.sqrt(M), rtol=0, atol=1e-12)
    np.testing.assert_allclose(np.asarray(p.omega_lab)[col], w1 / math.sqrt(M), rtol=0, atol=1e-12)
    # kinetic energy unchanged, total momentum zero (relative to the momentum's natural size)
    assert (m * (v ** 2).sum(axis=1)).sum() == pytest.approx((m1 * (v1 ** 2).sum(axis=1)).sum(), rel=1e-12)
    P, scale = (m[:, None] * v).sum(axis=0), np.abs(m[:, None] * v).sum()
    assert np.all(np.abs(P) < 1e-14 * scale), P
    # the stability check accepts VV at dt = 0.0025 with the 4x friction rates, and momentum stays zero
    s.integrator.run(40)
    v = np.asarray(p.v)
    assert np.all(np.isfinite(v)) and np.all(np.abs((m[:, None] * v).sum(axis=0)) < 1e-12 * scale)


def test_default_is_unchanged():
    """mass_scale=1 (and leaving it out) gives the same trajectory bit for bit."""
    out = []
    for kw in ({}, {"mass_scale": 1.0}, {"mass_scale": 1}):
        s, info = les.scene(0.3, [6.0, 6.0, 6.0], 0.0025, seed=5, boundary="stick", shardlow=False, equil=0.0, **kw)
        s.integrator.run(20)
        out.append(np.asarray(s.part.all().pos).copy())
        assert info["mass_scale"] == 1.0
        del s
    assert np.array_equal(out[0], out[1]) and np.array_equal(out[0], out[2])


def test_dissipative_forces_do_not_depend_on_mass():
    """Two beads approaching at kT = 0 inside the DPD range, one of them with a
    colloid's surface friction: the pair forces at M = 1 and M = 0.25 are the
    same (friction = gamma w(r)^2 (v_ij . e) e, no mass factor)."""
    forces = []
    for M in (1.0, 0.25):
        s = marble.System(box_l=[6.0, 6.0, 6.0])
        s.time_step = 0.001
        s.cell_system.skin = 0.3
        s.part.add(pos=[[2.0, 3.0, 3.0], [2.6, 3.1, 3.0]], v=[[0.3, 0.1, 0.0], [-0.2, 0.0, 0.05]])
        s.non_bonded_inter[0, 0].dpd.set_params(weight_function=1, gamma=4.5, r_cut=1.0)
        s.thermostat.set_dpd(kT=0.0, seed=1)
        les.scale_masses(s, M)
        s.part.all().v = [[0.3, 0.1, 0.0], [-0.2, 0.0, 0.05]]  # the same velocities at both masses
        assert np.all(np.asarray(s.part.all().mass, float) == M)
        s.integrator.run(0)
        forces.append(np.asarray(s.part.all().f).copy())
        del s
    assert np.abs(forces[0]).max() > 0.1
    np.testing.assert_allclose(forces[1], forces[0], rtol=1e-13, atol=1e-15)


def _kinetic_viscosity(M, rate=0.2, time=80.0, seed=3):
    s, _ = les.scene(0.0, [5.0, 5.0, 5.0], 0.0025 if M < 1 else 0.005, seed=seed, shardlow=False, equil=2.0,
                     mass_scale=M)
    L = np.asarray(s.box_l, float)
    s.lees_edwards.set_boundary_conditions(shear_direction="x", shear_plane_normal="y",
                                           protocol=le.LinearShear(shear_velocity=rate * L[1], time_0=s.time))
    p = s.part.all()
    v = np.asarray(p.v)
    v[:, 0] += rate * (np.asarray(p.pos_folded)[:, 1] - 0.5 * L[1])
    p.v = v
    s.integrator.run(int(round(4.0 / s.time_step)))
    kin, n_step = [], max(1, int(round(0.1 / s.time_step)))
    for _ in range(int(time / 0.1)):
        s.integrator.run(n_step)
        k = s.analysis.pressure_tensor()["kinetic"]
        kin.append(-0.5 * (k[0, 1] + k[1, 0]) / rate)
    from marble.viscosity import block_average
    return block_average(kin, min_blocks=8)


def test_kinetic_viscosity_grows_with_mass():
    """The solvent's kinetic (momentum-transport) part of eta in shear: for DPD
    it is ~ n kT tau_v with the velocity relaxation time tau_v ~ M/gamma, so it
    grows with the mass (measured at M = 1: 0.1145(45) of eta_0 = 0.329,
    doc/suspensions.md 7j). M = 4 against M = 0.25: at least 4 times larger and
    separated by 5 combined errors; also not a huge factor (< 30: the linear
    law gives 16)."""
    lo, lo_err = _kinetic_viscosity(0.25)
    hi, hi_err = _kinetic_viscosity(4.0)
    assert lo_err < 0.3 * abs(lo) + 0.01 and hi_err < 0.15 * hi, (lo, lo_err, hi, hi_err)
    assert lo > 0
    assert hi - lo > 5 * math.hypot(lo_err, hi_err), (lo, lo_err, hi, hi_err)
    assert 4 < hi / lo < 30, (lo, hi)


def test_dimensionless_numbers():
    """Re = 3 M rate R^2/eta_0, Pe = 6 pi eta_0 R^3 rate/kT (R = 1, kT = 0.1)."""
    Re, Pe = les.dimensionless(0.05, 0.329)
    assert Re == pytest.approx(0.15 / 0.329, rel=1e-14) and Re == pytest.approx(0.4559, abs=1e-4)
    assert Pe == pytest.approx(6 * math.pi * 0.329 * 0.05 / 0.1, rel=1e-14) and Pe == pytest.approx(3.101, abs=1e-3)
    Re4, Pe4 = les.dimensionless(0.05, 0.329, mass_scale=4.0)
    assert Re4 == pytest.approx(4 * Re) and Pe4 == Pe


@pytest.mark.parametrize("bad", [0.0, -1.0, float("nan"), float("inf"), "heavy", None])
def test_bad_mass_scale(bad):
    with pytest.raises(ValueError, match="mass_scale"):
        les.scene(0.0, [4.0, 4.0, 4.0], 0.005, seed=1, shardlow=False, equil=0.0, mass_scale=bad)
    s = marble.System(box_l=[4.0, 4.0, 4.0])
    s.part.add(pos=[[1.0, 1.0, 1.0]])
    with pytest.raises(ValueError, match="mass_scale"):
        les.scale_masses(s, bad)
    assert float(np.asarray(s.part.all().mass, float)[0]) == 1.0
