# labels: python long
"""The solvent count at fixed bulk density (setup_suspension(solvent_count="bulk"),
doc/suspensions.md sections 6 and 7e).

The calibrated stick colloids of the viscosity scenes (phi = 0.2, R = 1, box
7 x 7 x 10, 23 colloids, seed 004's solvent, the soft contact of
samples/suspension_viscosity.py, Shardlow dt = 0.01, 20 time units at rest)
adsorb about 4 solvent beads each in their shells, so the exact count
(density 3 in the free volume) leaves the solvent between them depleted
(2.78 measured). With "bulk" setup_suspension adds the adsorbed beads
(ADSORBED_PER_AREA x 4 pi a^2 per colloid) and the bulk is at density 3.

Measured by marble.suspensions.solvent_structure (the bulk: farther than 1 from
every core surface; 60 frames 1 time unit apart; error from 10 blocks):
- "bulk": the bulk density within 3 sigma + 0.02 of 3 (0.02: the +/- 0.3 beads
  per colloid of the adsorbed calibration at 23 colloids in ~400 free volume);
- "exact": the bulk below 3 by more than 3 sigma + 0.05 (the depletion the
  "bulk" count removes; the test fails if the count adds nothing);
- the adsorbed excess per colloid measured in both scenes within 25 % of the
  default ADSORBED_PER_AREA x 4 pi a^2 (4.00).
And bad input: "bulk" without ``adsorbed`` for another solvent, ``adsorbed`` with
another count, a negative ``adsorbed``: ValueError, nothing changed.
"""
import math

import numpy as np
import pytest

import marble

if not marble.has_features("DPD", "TRANS_DPD", "ROTATION", "HAT", "CONTACT", "LUBRICATION", "MASS"):
    pytest.skip("needs DPD, TRANS_DPD, ROTATION, HAT, CONTACT, LUBRICATION, MASS", allow_module_level=True)

import marble.suspensions as sus

BOX = np.array([7.0, 7.0, 10.0])


def scene(count, seed=12):
    s = marble.System(box_l=BOX)
    s.time_step = 0.01
    s.cell_system.skin = 0.4
    info = sus.setup_suspension(s, phi=0.2, radius=1.0, kT=0.1, gamma=4.5, eta=0.3, seed=seed, h_cut=1.0,
                                f_contact=50.0, delta=0.02, boundary="stick", solvent_count=count,
                                lubrication_form="plain", colloid_dpd=True)  # the kernels as measured (7e)
    s.integrator.set_shardlow()
    p = s.part.all()
    v = np.asarray(p.v)
    m = np.asarray(p.mass)
    p.v = v - np.sum(m[:, None] * v, axis=0) / np.sum(m)
    s.integrator.run(2000)
    return s, info


def test_bulk_count_restores_the_bulk_density():
    res = {}
    for count in ("exact", "bulk"):
        s, info = scene(count)
        r = sus.solvent_structure(s, info, frames=60, every=1.0)
        res[count] = (info, r)
        print(f"{count}: {info['n_solvent']} beads ({info['n_colloids']} colloids, adsorbed "
              f"{info['adsorbed']}), bulk density {r['bulk_density']:.4f} +/- {r['bulk_density_err']:.4f}, "
              f"excess per colloid {r['excess_per_colloid']:.2f}")
    a = res["bulk"][0]["core_radius"]
    default = sus.ADSORBED_PER_AREA * 4.0 * math.pi * a * a
    assert res["bulk"][0]["adsorbed"] == pytest.approx(default, rel=1e-14)
    assert res["exact"][0]["adsorbed"] is None
    n_col = res["bulk"][0]["n_colloids"]
    assert res["bulk"][0]["n_solvent"] - res["exact"][0]["n_solvent"] == int(round(default * n_col))
    rb, re = res["bulk"][1], res["exact"][1]
    assert abs(rb["bulk_density"] - 3.0) < 3 * rb["bulk_density_err"] + 0.02
    assert re["bulk_density"] < 3.0 - 3 * re["bulk_density_err"] - 0.05
    for _, r in res.values():
        assert r["excess_per_colloid"] == pytest.approx(default, rel=0.25)


def test_bulk_count_bad_input():
    s = marble.System(box_l=BOX)
    s.time_step = 0.01
    kw = dict(phi=0.2, radius=1.0, kT=0.1, gamma=4.5, eta=0.3, seed=1, boundary="stick")
    with pytest.raises(ValueError, match="adsorbed"):
        sus.setup_suspension(s, density=4.0, solvent_count="bulk", **kw)
    with pytest.raises(ValueError, match="adsorbed"):
        sus.setup_suspension(s, a_cs=10.0, solvent_count="bulk", **kw)
    with pytest.raises(ValueError, match="adsorbed"):
        sus.setup_suspension(s, solvent_count="exact", adsorbed=4.0, **kw)
    with pytest.raises(ValueError, match="adsorbed"):
        sus.setup_suspension(s, solvent_count="bulk", adsorbed=-1.0, **kw)
    with pytest.raises(ValueError, match="solvent_count"):
        sus.setup_suspension(s, solvent_count="dense", **kw)
    assert len(s.part.all()) == 0
    # another solvent with its own measured adsorption is accepted
    info = sus.setup_suspension(s, density=4.0, solvent_count="bulk", adsorbed=5.0, **kw)
    assert info["adsorbed"] == 5.0
    with pytest.raises(ValueError, match="frames"):
        sus.solvent_structure(s, info, frames=5)
