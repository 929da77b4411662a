"""Fixed-seed end states of Shardlow scenes, for bit-for-bit checks of work on the pair sweep.

    build/pymarble bench/shardlow_states.py OUT.npz                    # dump this build's end states
    build/pymarble bench/shardlow_states.py OUT.npz --compare REF.npz  # and compare with another build's

The companion of bench/fixed_seed_states.py (whose one Shardlow scene is Groot-Warren water) for the
paths of integrators/shardlow.cpp's sweep (session 11, issue 15): the marble paper's solvent (a = 0,
gamma = 5) at dt = 0.04, the same with an R = 2 marble, transverse DPD with two types, different cutoffs
and unequal masses (the division path), colloids with surface friction, lubrication and contact forces
and Lees-Edwards shear (the sweep's other updates), a box smaller than twice the range (ghost images
of one particle), and the Fig. 4 step with RESPA substeps (with and without a colloid list that goes
stale between substeps). Saves positions, velocities (and spins where they rotate) by particle id after a few
dozen steps. With --compare, prints max |difference| per array and exits 1 unless all are exactly 0.
A scene whose features are not compiled in is skipped (and said so).
"""
import argparse
import sys

import numpy as np

import marble
from fixed_seed_states import run_and_compare  # bench/ is the script's directory


def box(L, n, seed, dt=0.04, skin=0.4, mass=None):
    rng = np.random.default_rng(seed)
    s = marble.System(box_l=[L] * 3)
    s.time_step = dt
    s.cell_system.skin = skin
    # the half-skin rule: builds since session 29 (VV) and 30 (Shardlow, RESPA,
    # colloids) keep lists longer by default (cell_system.list_check), which
    # changes last bits; older builds have no such setting and ignore it
    s.cell_system.list_check = "half_skin"
    kw = {} if mass is None else {"mass": mass(rng, n)}
    s.part.add(pos=rng.random((n, 3)) * L, v=rng.normal(size=(n, 3)), **kw)
    s.thermostat.set_dpd(kT=1.0, seed=seed)
    return s


def state(s, out, name):
    p = s.part.all()
    o = np.argsort(np.asarray(p.id))
    out[name + "_pos"] = np.asarray(p.pos)[o]
    out[name + "_v"] = np.asarray(p.v)[o]
    if hasattr(p, "omega_lab"):
        try:
            out[name + "_omega"] = np.asarray(p.omega_lab)[o]
        except marble.FeaturesError:
            pass


def scenes():
    def paper_solvent(out, name, L, n, seed):
        """The marble paper's solvent (a = 0, gamma = 5) under Shardlow, 40 steps."""
        s = box(L, n, seed)
        s.non_bonded_inter[0, 0].dpd.set_params(weight_function=1, gamma=5.0, k=1.0, r_cut=1.0)
        s.integrator.set_shardlow()
        s.integrator.run(40)
        state(s, out, name)

    def paper(out):
        paper_solvent(out, "paper", 8.0, 1536, 21)

    def marble_scene(out):
        from marble.colloids import add_marble
        s = box(10.0, 3000, 22)
        s.non_bonded_inter[0, 0].dpd.set_params(weight_function=1, gamma=5.0, k=1.0, r_cut=1.0)
        add_marble(s, pos=[5.0] * 3, radius=2.0, gamma=5.0)
        s.integrator.set_shardlow()
        s.integrator.run(40)
        state(s, out, "marble")

    def trans_masses(out):
        s = box(8.0, 1536, 23, dt=0.02, mass=lambda rng, n: rng.choice([1.0, 2.5], size=n))
        for pid in range(0, 1536, 3):
            s.part.by_id(pid).type = 1
        nb = s.non_bonded_inter
        nb[0, 0].dpd.set_params(weight_function=1, gamma=4.5, k=1.0, r_cut=1.0,
                                trans_weight_function=1, trans_gamma=3.0, trans_r_cut=1.0)
        nb[0, 1].dpd.set_params(weight_function=1, gamma=3.0, k=2.0, r_cut=1.2,
                                trans_weight_function=0, trans_gamma=1.0, trans_r_cut=0.7)
        nb[1, 1].dpd.set_params(weight_function=0, gamma=0.0, r_cut=0.9,
                                trans_weight_function=1, trans_gamma=2.0, trans_r_cut=0.9)
        nb[0, 0].hat.set_params(F_max=25.0, cutoff=1.0)
        s.integrator.set_shardlow()
        s.integrator.run(30)
        state(s, out, "trans_masses")

    def small_box(out):
        paper_solvent(out, "small", 2.5, 47, 24)

    def colloids(out):
        """Surface friction (colloid-colloid pairs in the main list), lubrication and contact."""
        L = 12.0
        rng = np.random.default_rng(25)
        s = marble.System(box_l=[L] * 3)
        s.time_step = 0.005
        s.cell_system.list_check = "half_skin"  # (as in box)
        grid = np.stack(np.meshgrid(*[np.arange(3) * 4.0] * 3), -1).reshape(-1, 3)
        s.part.add(pos=grid + 0.2 * rng.random(grid.shape), v=rng.normal(size=grid.shape),
                   mass=rng.choice([1.0, 4.0], size=len(grid)), rotation=[[True] * 3] * len(grid),
                   rinertia=[[1.5] * 3] * len(grid))
        nb = s.non_bonded_inter
        nb[0, 0].lubrication.set_params(eta=0.5, a1=1.8, a2=1.8, h_cut=0.8, log_term="on")
        nb[0, 0].contact.set_params(f_contact=20.0, delta=0.05, offset=3.6)
        nb[0, 0].surface_friction.set_params(gamma=5.0, r_cut=1.0, a1=1.8, a2=1.8)
        nb[0, 0].dpd.set_params(weight_function=1, gamma=2.0, k=1.0, r_cut=4.5, offset=0.0)
        s.thermostat.set_dpd(kT=1.0, seed=25)
        s.integrator.set_shardlow()
        s.integrator.run(200)
        state(s, out, "colloids")

    def lees_edwards(out):
        import marble.lees_edwards as le
        s = box(6.0, 648, 26, dt=0.02)
        s.non_bonded_inter[0, 0].dpd.set_params(weight_function=1, gamma=5.0, k=1.0, r_cut=1.0)
        s.lees_edwards.set_boundary_conditions(
            shear_direction="x", shear_plane_normal="y",
            protocol=le.LinearShear(initial_pos_offset=0.3, shear_velocity=0.5, time_0=0.0))
        s.integrator.set_shardlow()
        s.integrator.run(40)
        state(s, out, "lees_edwards")

    def respa(out):
        """The Fig. 4 step (colloid_runs.make_system: Shardlow dt = 0.06, 3 RESPA substeps for the
        marble's wall, skin 0.6; L = 12, R = 3), 60 steps; then 40 steps with the colloid pushed
        at 8.5 every step, so that its pair list goes stale inside a step (a rebuild between
        substeps: session 15's sweeps of the particles outside the list take the other path)."""
        from marble.colloid_runs import make_system
        s, c, _ = make_system(12.0, 3.0, 1.0, 5, integrator="shardlow", warmup=0.0)
        s.integrator.run(60)
        state(s, out, "respa")
        n0 = s.cell_system.get_state()["verlet_rebuilds"]
        for _ in range(40):
            c.v = [8.5, 1.0, 0.0]
            s.integrator.run(1)
        n_mid = s.cell_system.get_state()["verlet_rebuilds"] - n0 - 40
        print(f"respa: at least {max(n_mid, 0)} rebuilds between substeps in 40 steps")
        state(s, out, "respa_stale")

    return [("paper", paper), ("marble", marble_scene), ("trans_masses", trans_masses),
            ("small_box", small_box), ("colloids", colloids), ("lees_edwards", lees_edwards),
            ("respa", respa)]


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("out")
    ap.add_argument("--compare", help="reference .npz of another build")
    args = ap.parse_args()
    return run_and_compare(scenes(), args.out, args.compare)

if __name__ == "__main__":
    sys.exit(main())
