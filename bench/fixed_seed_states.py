"""Fixed-seed end states of the scenes the pair loop serves, for bit-for-bit checks of speed work.

    build/pymarble bench/fixed_seed_states.py OUT.npz            # dump the end states of this build
    build/pymarble bench/fixed_seed_states.py OUT.npz --compare REF.npz
    build/pymarble bench/fixed_seed_states.py OUT.npz --compare REF.npz --steps 0 --tol 1e-14

Runs each scene for a few dozen steps from fixed seeds and saves positions, velocities, forces
(and, for LJ, energy and pressure) by particle id. With --compare it prints max |difference| per
array against REF.npz (made by another build, e.g. the commit before a change that must keep
trajectories) and exits 1 unless every difference is exactly 0. For changes at round-off level
(doc/benchmarks.md, session 9), --steps 0 saves the first force pass of every scene and --tol
bounds each array's max |difference| relative to its max |value| instead. Scenes: DPD a = 0 and a = 25 (the
SIMD loop), TRANS_DPD, two types with different cutoffs (the generic loop), dt = 0.04, a box smaller
than the interaction range, Shardlow, DPD-VV, fixed coordinates + external force + mass, an LJ fluid,
a marble colloid. A scene whose features are not compiled in is skipped (and said so).
"""
import argparse
import sys

import numpy as np

import marble


STEPS = None  # --steps: every scene runs this many steps instead of its own


def run(s, steps):
    """s.integrator.run(steps), or run(STEPS) where --steps is given (0: the first force pass)."""
    s.integrator.run(steps if STEPS is None else STEPS)


def dpd_box(L, n, seed, dt=0.01, skin=0.4):
    rng = np.random.default_rng(seed)
    s = marble.System(box_l=[L] * 3)
    s.time_step = dt
    s.cell_system.skin = skin
    # the half-skin rule: builds since session 29 (VV) and 30 (Shardlow, RESPA,
    # colloids) keep lists longer by default (cell_system.list_check), which
    # changes last bits; older builds have no such setting and ignore it
    s.cell_system.list_check = "half_skin"
    s.part.add(pos=rng.random((n, 3)) * L, v=rng.normal(size=(n, 3)))
    s.thermostat.set_dpd(kT=1.0, seed=seed)
    return s


def state(s, out, name, extra=()):
    p = s.part.all()
    o = np.argsort(np.asarray(p.id))
    out[name + "_pos"] = np.asarray(p.pos)[o]
    out[name + "_v"] = np.asarray(p.v)[o]
    out[name + "_f"] = np.asarray(p.f)[o]
    for k, v in extra:
        out[name + "_" + k] = np.atleast_1d(np.asarray(v, dtype=float))


def scenes():
    def a0(out):
        s = dpd_box(8.0, 1536, 1)
        s.non_bonded_inter[0, 0].dpd.set_params(weight_function=1, gamma=5.0, k=1.0, r_cut=1.0)
        run(s, 60)
        state(s, out, "a0")

    def a25(out):
        s = dpd_box(8.0, 1536, 2)
        s.non_bonded_inter[0, 0].dpd.set_params(weight_function=1, gamma=4.5, k=1.0, r_cut=1.0)
        s.non_bonded_inter[0, 0].hat.set_params(F_max=25.0, cutoff=1.0)
        p0 = s.part.by_id(0)
        p0.fix = [True, False, False]
        p0.ext_force = [1.0, 0.0, 0.0]
        s.part.by_id(1).mass = 3.0
        run(s, 60)
        state(s, out, "a25")

    def dt04(out):
        s = dpd_box(8.0, 1536, 3, dt=0.04, skin=0.5)
        s.non_bonded_inter[0, 0].dpd.set_params(weight_function=1, gamma=4.5, k=1.0, r_cut=1.0)
        s.non_bonded_inter[0, 0].hat.set_params(F_max=25.0, cutoff=1.0)
        run(s, 40)
        state(s, out, "dt04")

    def trans(out):
        s = dpd_box(8.0, 1536, 4)
        s.non_bonded_inter[0, 0].dpd.set_params(weight_function=1, gamma=4.5, k=1.0, r_cut=1.0,
                                                trans_weight_function=1, trans_gamma=3.0, trans_r_cut=1.0)
        run(s, 40)
        state(s, out, "trans")

    def two_types(out):
        s = dpd_box(8.0, 1536, 5)
        for pid in range(0, 1536, 3):
            s.part.by_id(pid).type = 1
        nb = s.non_bonded_inter
        nb[0, 0].dpd.set_params(weight_function=1, gamma=4.5, k=1.0, r_cut=1.0)
        nb[0, 1].dpd.set_params(weight_function=1, gamma=3.0, k=1.0, r_cut=1.2)
        nb[1, 1].dpd.set_params(weight_function=0, gamma=2.0, r_cut=0.9)
        nb[0, 0].hat.set_params(F_max=25.0, cutoff=1.0)
        nb[0, 1].hat.set_params(F_max=30.0, cutoff=1.2)
        run(s, 40)
        state(s, out, "two")

    def small_box(out):
        s = dpd_box(2.5, 47, 6)
        s.non_bonded_inter[0, 0].dpd.set_params(weight_function=1, gamma=4.5, k=1.0, r_cut=1.0)
        s.non_bonded_inter[0, 0].hat.set_params(F_max=25.0, cutoff=1.0)
        run(s, 40)
        state(s, out, "small")

    def dpd_integrator(seed, integrator, key):
        def scene(out):
            s = dpd_box(8.0, 1536, seed)
            s.non_bonded_inter[0, 0].dpd.set_params(weight_function=1, gamma=4.5, k=1.0, r_cut=1.0)
            s.non_bonded_inter[0, 0].hat.set_params(F_max=25.0, cutoff=1.0)
            getattr(s.integrator, integrator)()
            run(s, 30)
            state(s, out, key)
        return scene

    shardlow = dpd_integrator(7, "set_shardlow", "shardlow")
    dpd_vv = dpd_integrator(8, "set_dpd_vv", "dpdvv")

    def lj(out):
        rng = np.random.default_rng(9)
        from bench_common import lj_fcc_system
        s = lj_fcc_system(6, rng)
        s.cell_system.list_check = "half_skin"  # (as in dpd_box)
        run(s, 60)
        e = s.analysis.energy()
        pt = s.analysis.pressure_tensor()
        state(s, out, "lj", [("energy", e["total"]), ("pressure", pt["total"])])

    def marble_scene(out):
        from marble.colloids import add_marble
        s = dpd_box(10.0, 3000, 10)
        s.non_bonded_inter[0, 0].dpd.set_params(weight_function=1, gamma=5.0, k=1.0, r_cut=1.0)
        add_marble(s, pos=[5.0] * 3, radius=2.0, gamma=5.0)
        run(s, 30)
        state(s, out, "marble")

    return [("a0", a0), ("a25", a25), ("dt04", dt04), ("trans", trans), ("two_types", two_types),
            ("small_box", small_box), ("shardlow", shardlow), ("dpd_vv", dpd_vv), ("lj", lj),
            ("marble", marble_scene)]


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("out")
    ap.add_argument("--compare", help="reference .npz of another build")
    ap.add_argument("--steps", type=int, help="run every scene this many steps (0: the forces at the start, for "
                    "comparing builds that differ by round-off: their trajectories part after a few steps)")
    ap.add_argument("--tol", type=float, default=0.0,
                    help="pass if every array's max |difference| / max |value| is <= TOL (default 0: bit for bit)")
    args = ap.parse_args()
    global STEPS
    STEPS = args.steps
    return run_and_compare(scenes(), args.out, args.compare, args.tol)


def run_and_compare(scene_list, out_path, compare=None, tol=0.0):
    """Run the (name, fn) scenes (a scene whose features are missing is skipped
    and said so), save their arrays to @p out_path and, with @p compare (a
    reference .npz of another build), print max |difference| per array.
    Returns the exit code: 0 if every array agrees bit for bit, or with
    @p tol > 0 if every max |difference| / max |value| is <= tol; else 1."""
    out = {}
    for name, fn in scene_list:
        try:
            fn(out)
        except marble.FeaturesError as err:
            print(f"{name}: skipped ({err})")
    np.savez(out_path, **out)
    if not compare:
        return 0
    ref = np.load(compare)
    worst = worst_rel = 0.0
    for k in sorted(set(ref.files) | set(out)):
        if k not in ref.files or k not in out:
            print(f"{k}: only in one of the two")
            worst = worst_rel = np.inf
            continue
        d = float(np.max(np.abs(ref[k] - out[k]))) if ref[k].shape == out[k].shape else np.inf
        scale = float(np.max(np.abs(ref[k])))
        rel = d / scale if scale > 0 else d
        worst, worst_rel = max(worst, d), max(worst_rel, rel)
        print(f"{k}: max |difference| = {d:.3g} (relative to max |value|: {rel:.3g})")
    print(f"max |difference| over all = {worst:.3g}, relative {worst_rel:.3g}")
    if tol > 0:
        return 0 if worst_rel <= tol else 1
    return 0 if worst == 0.0 else 1

if __name__ == "__main__":
    sys.exit(main())
