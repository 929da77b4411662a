"""The scene of the kernel-registry regression test (test_registry_regression.py):
DPD solvent with a soft repulsion, a rotating marble colloid with its LJ excluded
volume, a second bead type with LJ, and two tunable-slip walls (WCA + friction)
in a box non-periodic in z. Every kernel family of the pair loop, the colloid
pair list and the walls acts, with the DPD thermostat on.

    build/pymarble testsuite/python/registry_scene.py OUT.npz   # write a reference
"""
import sys

import numpy as np

import marble
from marble.colloids import add_marble
from marble.shapes import Wall

FEATURES = ["DPD", "HAT", "LENNARD_JONES", "MARBLE", "TUNABLE_SLIP"]
INTEGRATORS = ("vv", "shardlow", "dpd_vv")
N_STEPS = 500


def make_scene(integrator):
    L = (8.0, 8.0, 9.0)
    s = marble.System(box_l=list(L))
    s.periodicity = [True, True, False]
    s.time_step = 0.01
    s.cell_system.skin = 0.4
    # the reference's rebuild schedule: the half-skin rule (the pair test of
    # cell_system.list_check = "pairs", the default since session 29 and with
    # marble colloids since session 30, keeps lists longer: the same forces in
    # another list order, so other last bits; this scene checks the arithmetic)
    s.cell_system.list_check = "half_skin"
    rng = np.random.default_rng(2026)
    n = int(3 * L[0] * L[1] * (L[2] - 2.0))
    pos = rng.random((n, 3)) * [L[0], L[1], L[2] - 2.0] + [0.0, 0.0, 1.0]
    types = np.where(rng.random(n) < 0.1, 2, 0)
    s.part.add(pos=pos, v=rng.normal(size=(n, 3)), type=types)
    s.thermostat.set_dpd(kT=1.0, seed=11)
    nb = s.non_bonded_inter
    nb[0, 0].dpd.set_params(weight_function=1, gamma=4.5, k=1, r_cut=1.0)
    nb[0, 0].hat.set_params(F_max=10.0, cutoff=1.0)
    nb[0, 2].dpd.set_params(weight_function=1, gamma=4.5, k=1, r_cut=1.0)
    nb[0, 2].lennard_jones.set_params(epsilon=0.5, sigma=0.8, cutoff=0.8 * 2 ** (1 / 6), shift="auto")
    nb[2, 2].dpd.set_params(weight_function=0, gamma=2.0, r_cut=1.0)
    nb[2, 2].lennard_jones.set_params(epsilon=0.5, sigma=0.8, cutoff=1.2, shift=0.1, offset=0.05)
    add_marble(s, pos=[4.0, 4.0, 4.5], radius=1.5, gamma=5.0, colloid_type=1, solvent_types=(0, 2))
    for wall_type, normal, dist in ((3, [0, 0, 1], 0.0), (3, [0, 0, -1], -L[2])):
        s.constraints.add(shape=Wall(normal=normal, dist=dist), particle_type=wall_type)
    for t in (0, 2):
        nb[3, t].lennard_jones.set_params(epsilon=1.0, sigma=1.0, cutoff=2 ** (1 / 6), shift="auto")
        nb[3, t].tunable_slip.set_params(gamma=1.0, r_cut=1.0, offset=0.5)
    s.integrator.set_steepest_descent(f_max=20.0, gamma=0.01, max_displacement=0.05)
    s.integrator.run(300)
    getattr(s.integrator, {"vv": "set_vv", "shardlow": "set_shardlow", "dpd_vv": "set_dpd_vv"}[integrator])()
    return s


def trajectory_end(integrator, n_steps=N_STEPS):
    s = make_scene(integrator)
    s.integrator.run(n_steps)
    p = s.part.all()
    order = np.argsort(p.id)
    e = s.analysis.energy()
    st = s.analysis.dpd_stress_split()
    return {"pos": p.pos[order], "v": p.v[order], "omega": p.omega_lab[order],
            "f": p.f[order], "energy": np.array([e["total"], e["non_bonded"]]),
            "pressure": s.analysis.pressure_tensor()["total"],
            "dpd_stress": np.array([st["friction"], st["noise"]])}


if __name__ == "__main__":
    out = {}
    for name in INTEGRATORS:
        for k, v in trajectory_end(name).items():
            out[f"{name}_{k}"] = v
    np.savez_compressed(sys.argv[1], **out)
    print("wrote", sys.argv[1], {k: v.shape for k, v in out.items()})
