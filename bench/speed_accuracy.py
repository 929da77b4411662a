"""Speed against accuracy for the marble paper's solvent and a no-slip marble
(issue 6, item 1; doc/speed-accuracy.md explains the results).

Solvent: rho = 3 (section 2 also 4 and 5), DPD gamma = 5, w = 1 - r
(weight_function=1, k=1), r_c = 1, no conservative force, kT = 1.
Marble: tunable-slip coupling, gamma = 5 (no slip), R = 2, neutrally buoyant.

Sections (--part, comma separated; default all):
  kT       kT(dt) and cost per tau for VV, Shardlow S1 and DPD-VV at
           dt in {0.0025, 0.005, 0.01, 0.02, 0.04, 0.06}, L = 8 (1536 beads);
           error bars from block averaging; also the solvent self-diffusion
           coefficient from the same runs (MSD slope between 10 and 30 tau);
           side check "kT_touch": kT when ext_force is re-assigned between
           run() calls (as reverse_poiseuille does), which makes the next
           step recompute the forces.
  density  rho in {3, 4, 5}: cost per tau per unit volume and kT at dt = 0.01
           (VV); solvent viscosity eta (reverse Poiseuille, 10 x 10 x 12) per
           rho, and at rho = 3 for the three integrators at dt = 0.01 / 0.04
           (force re-assigned every 0.05 tau, and every ~0.25 tau).
  colloid  colloid D: drag (L = 8, 10, 12, 16; dt variants and a larger
           force at L = 8 / 10), VACF (Green-Kubo) and MSD at L = 8; D(L) vs
           Hasimoto, the L -> infinity value with and without the Hasimoto
           correction, cost per unit statistical error.
  plot     the summary (analysis of whatever is in the JSON) and the PNGs.

Cost is process CPU time (one core; the machine may be shared, CPU time is
what a run costs), in CPU-seconds per tau, and "cost to 1 %" = CPU-seconds x
(relative error / 0.01)^2, the CPU time a run of the same kind needs for a
1 % statistical error.

Run:   build/pymarble bench/speed_accuracy.py [--quick] [--part kT,plot] [--out DIR]
Writes DIR/speed_accuracy.json (resumable: cases already there are skipped,
--redo reruns them) and DIR/speed_accuracy_{kT,D,density}.png. --quick runs a
~15 s smoke version into speed_accuracy_quick.json / *_quick_*.png.
"""
import argparse
import json
import os
import sys
import time

import numpy as np

import marble
from marble import diffusion as dif
from marble import observables as obs
from marble import theory as th
from marble.colloid_runs import analyse_equilibrium, equilibrium_run, jsonable, make_system

from bench_common import machine_info
from marble.viscosity import block_average, reverse_poiseuille

HERE = os.path.dirname(os.path.abspath(__file__))
KT, GAMMA = 1.0, 5.0
R_COLLOID = 2.0
# Reference viscosity of the solvent (rho = 3, dt = 0.01, VV): the engine's
# most precise value, test_dpd_viscosity_paper.py, 12 x 12 x 16, 2000 tau
# (doc/dpd.md). Section 2 re-measures it; the D analysis uses this one.
ETA_REF, ETA_REF_ERR = 1.273, 0.007
V_DRAG = 0.12  # target drift velocity of the drag runs (R v / nu ~ 0.6)

INTEGRATORS = ("vv", "shardlow", "dpd_vv")
DTS = (0.0025, 0.005, 0.01, 0.02, 0.04, 0.06)


def log(*a):
    print(*a, flush=True)


def skin_for(dt):
    return 0.4 if dt <= 0.02 else (0.5 if dt <= 0.04 else 0.6)


class Store:
    """The JSON file: one dict per section, one entry per case; rewritten
    (atomically) after every case so that an interrupted run loses nothing."""

    def __init__(self, path, redo=False):
        self.path, self.redo = path, redo
        self.data = {}
        if os.path.exists(path):
            with open(path) as f:
                self.data = json.load(f)
        self.data.setdefault("runs", [])

    def has(self, section, key):
        return not self.redo and key in self.data.get(section, {})

    def put(self, section, key, value):
        self.data.setdefault(section, {})[key] = jsonable(value)
        self.save()

    def save(self):
        tmp = self.path + ".tmp"
        with open(tmp, "w") as f:
            json.dump(jsonable(self.data), f, indent=1)
        os.replace(tmp, self.path)


class Clock:
    """CPU and wall time of a block; cpu_run counts integrator.run only."""

    def __init__(self):
        self.cpu0, self.wall0, self.cpu_run = time.process_time(), time.time(), 0.0

    def run(self, system, n):
        c = time.process_time()
        system.integrator.run(n)
        self.cpu_run += time.process_time() - c

    def done(self):
        return dict(cpu_s=time.process_time() - self.cpu0, wall_s=time.time() - self.wall0,
                    cpu_run_s=self.cpu_run, load_avg=os.getloadavg()[0])


# --------------------------------------------------------------------------
# Section 1 (and 2): kT(dt), cost per tau, solvent self-diffusion
# --------------------------------------------------------------------------
def make_solvent(L, rho, integ, dt, seed, box=None):
    box = [L] * 3 if box is None else list(box)
    rng = np.random.default_rng(seed)
    n = int(round(rho * np.prod(box)))
    s = marble.System(box_l=box)
    s.time_step = dt
    s.cell_system.skin = skin_for(dt)
    v = rng.normal(size=(n, 3)) * np.sqrt(KT)
    v -= v.mean(axis=0)
    s.part.add(pos=rng.random((n, 3)) * np.asarray(box), v=v)
    s.non_bonded_inter[0, 0].dpd.set_params(weight_function=1, gamma=GAMMA, k=1.0, r_cut=1.0)
    s.thermostat.set_dpd(kT=KT, seed=seed)
    getattr(s.integrator, "set_" + integ)()
    return s, n


def solvent_msd_D(P, dt_s, t1, t2, n_blocks=8):
    """Self-diffusion from unfolded positions P (n_samples, N, 3) sampled every
    dt_s: D = [MSD(t2) - MSD(t1)] / (6 (t2 - t1)), MSD averaged over particles
    and over origins. The error is the spread of the same estimate over
    n_blocks consecutive blocks of origins (each block's displacements may
    reach into the next block)."""
    m1, m2 = int(round(t1 / dt_s)), int(round(t2 / dt_s))
    n_orig = P.shape[0] - m2
    if n_orig < n_blocks:
        return np.nan, np.nan
    def est(orig):
        d2 = np.mean(np.sum((P[orig + m2] - P[orig]) ** 2, axis=-1))
        d1 = np.mean(np.sum((P[orig + m1] - P[orig]) ** 2, axis=-1))
        return (d2 - d1) / (6.0 * (m2 - m1) * dt_s)
    allo = np.arange(n_orig)
    D = est(allo)
    blocks = [est(b) for b in np.array_split(allo, n_blocks)]
    return float(D), float(np.std(blocks, ddof=1) / np.sqrt(n_blocks))


def kT_run(integ, dt, L, T, rho=3.0, seed=1, t_eq=5.0, msd=True, touch_every=0):
    """touch_every > 0: re-assign ext_force = 0 to every particle every that
    many steps (what reverse_poiseuille does with its body force), which makes
    the next run() recompute the forces (at the full-step velocities)."""
    s, n = make_solvent(L, rho, integ, dt, seed)
    s.integrator.run(int(round(t_eq / dt)))
    every = max(1, int(round(0.1 / dt)))
    if touch_every:
        every = touch_every
        zeros = np.zeros((n, 3))
        msd = False
    pos_every = max(1, int(round(0.5 / (every * dt))))  # in kT samples
    posobs = obs.ParticlePositions(ids=list(range(n)), system=s) if msd else None
    n_samp = int(round(T / (every * dt)))
    kts, P = [], []
    clk = Clock()
    for i in range(n_samp):
        if touch_every:
            s.part.all().ext_force = zeros
        clk.run(s, every)
        kts.append(2.0 * s.analysis.energy()["kinetic"] / (3.0 * n - 3.0))
        if msd and i % pos_every == 0:
            P.append(np.array(posobs.calculate()))
    t = clk.done()
    kT, kT_err = block_average(kts)
    T_done = n_samp * every * dt
    out = dict(integrator=integ, dt=dt, L=L, rho=rho, N=n, T=T_done, seed=seed, kT=kT,
               touch_every=touch_every,
               kT_err=kT_err, steps=n_samp * every, **t)
    out["cpu_per_tau"] = t["cpu_run_s"] / T_done
    out["cpu_per_tau_per_1000p"] = out["cpu_per_tau"] / n * 1000.0
    out["cpu_per_tau_per_volume"] = out["cpu_per_tau"] / L ** 3
    out["particle_steps_per_cpu_s"] = n * out["steps"] / t["cpu_run_s"]
    if msd and len(P) > 10:
        P = np.asarray(P)
        dt_s = pos_every * every * dt
        t2 = min(30.0, 0.3 * T_done)
        D, D_err = solvent_msd_D(P, dt_s, t1=t2 / 3.0, t2=t2)
        out.update(Ds=D, Ds_err=D_err, Ds_window=[t2 / 3.0, t2])
    return out


def section_kT(store, quick):
    L = 5.0 if quick else 8.0
    dts = (0.01, 0.04) if quick else DTS
    order = sorted(dts, reverse=True)  # the large dt first: they matter most
    for dt in order:
        for integ in INTEGRATORS:
            key = f"{integ}_dt{dt}"
            if store.has("kT", key):
                continue
            T = 30.0 if quick else (400.0 if dt >= 0.01 else 200.0)
            log(f"[kT] {key}: L = {L}, T = {T} tau ...")
            r = kT_run(integ, dt, L, T, seed=11)
            log(f"      kT = {r['kT']:.4f} +/- {r['kT_err']:.4f}, D_s = {r.get('Ds', np.nan):.4f}"
                f" +/- {r.get('Ds_err', np.nan):.4f}, {r['cpu_per_tau_per_1000p']:.4f} CPU-s"
                f" per tau per 1000 beads, {r['cpu_s']:.1f} CPU-s")
            store.put("kT", key, r)
    # side check: re-assigning ext_force between run() calls (as reverse_poiseuille
    # does) changes what VV / DPD-VV do on the following step
    for integ, dt, touch in (("vv", 0.04, 1), ("vv", 0.04, 6), ("vv", 0.01, 5),
                             ("dpd_vv", 0.04, 1), ("shardlow", 0.04, 1)):
        if quick and dt != 0.04:
            continue
        key = f"{integ}_dt{dt}_touch{touch}"
        if store.has("kT_touch", key):
            continue
        T = 30.0 if quick else 200.0
        log(f"[kT_touch] {key}: ext_force re-assigned every {touch} steps, T = {T} tau ...")
        r = kT_run(integ, dt, L, T, seed=12, touch_every=touch)
        log(f"      kT = {r['kT']:.4f} +/- {r['kT_err']:.4f}")
        store.put("kT_touch", key, r)


# --------------------------------------------------------------------------
# Section 2: density, viscosity
# --------------------------------------------------------------------------
def eta_run(rho, integ, dt, T, box, seed=21, upd_tau=0.05):
    s, n = make_solvent(None, rho, integ, dt, seed, box=box)
    s.integrator.run(int(round(5.0 / dt)))
    g = 0.06 * 3.0 / rho  # n g fixed: the same force density as doc/dpd.md's g = 0.06 at rho = 3
    clk = Clock()
    # Every re-assignment of ext_force marks the forces invalid, and the next
    # run() recomputes them at the full-step velocities (with the last step's
    # noise): with VV / DPD-VV that changes the integrator on those steps
    # (VV at dt = 0.04 re-assigned every step: kT 1.001 instead of 1.037).
    # Shardlow is unaffected (its DPD is not in the forces).
    upd = max(1, int(round(upd_tau / dt)))
    smp = max(upd, int(round(0.1 / dt)))
    res = reverse_poiseuille(s, g=g, time=T, update_every=upd, sample_every=smp,
                             progress=lambda f: log(f"      {100 * f:.0f} %"))
    t = clk.done()
    V = float(np.prod(box))
    out = dict(rho=rho, integrator=integ, dt=dt, box=list(box), N=n, T=res.time, g=g,
               update_every=upd, update_every_tau=upd * dt,
               eta=res.eta, eta_err=res.eta_err, kT_flow=res.kT, v_max=res.v_max, **t)
    out["cpu_per_tau_per_volume"] = t["cpu_s"] / res.time / V
    out["cost_1pct"] = t["cpu_s"] * (res.eta_err / res.eta / 0.01) ** 2
    return out


def section_density(store, quick):
    rhos = (3.0,) if quick else (3.0, 4.0, 5.0)
    L = 5.0 if quick else 8.0
    for rho in rhos:
        key = f"rho{rho:g}"
        if store.has("density", key):
            continue
        T = 10.0 if quick else 200.0
        log(f"[density] {key}: kT run, VV, dt = 0.01, L = {L}, T = {T} ...")
        r = kT_run("vv", 0.01, L, T, rho=rho, seed=31)
        log(f"      kT = {r['kT']:.4f} +/- {r['kT_err']:.4f}, D_s = {r.get('Ds', np.nan):.4f},"
            f" {r['cpu_per_tau_per_volume']:.5f} CPU-s per tau per unit volume")
        store.put("density", key, r)
    box = (6.0, 6.0, 8.0) if quick else (10.0, 10.0, 12.0)
    cases = [(rho, "vv", 0.01, 0.05) for rho in rhos]
    if not quick:
        cases += [(3.0, "shardlow", 0.01, 0.05), (3.0, "vv", 0.04, 0.05),
                  (3.0, "shardlow", 0.04, 0.05), (3.0, "dpd_vv", 0.04, 0.05),
                  # the force re-assigned every ~0.25 tau: 1 step in 25 (dt 0.01) or
                  # 6 (dt 0.04) sees the recomputed forces (see eta_run)
                  (3.0, "vv", 0.01, 0.25), (3.0, "vv", 0.04, 0.24), (3.0, "dpd_vv", 0.04, 0.24)]
    for rho, integ, dt, upd_tau in cases:
        key = f"rho{rho:g}_{integ}_dt{dt}" + ("" if upd_tau == 0.05 else f"_upd{upd_tau:g}")
        if store.has("eta", key):
            continue
        T = 40.0 if quick else (600.0 if (rho, integ, dt) == (3.0, "vv", 0.01)
                                     else (400.0 if dt == 0.01 else 500.0))
        log(f"[eta] {key}: box {box}, T = {T} tau ...")
        r = eta_run(rho, integ, dt, T, box, upd_tau=upd_tau)
        log(f"      eta = {r['eta']:.4f} +/- {r['eta_err']:.4f} (kT in the flow {r['kT_flow']:.4f},"
            f" v_max {r['v_max']:.2f}), {r['cpu_s']:.1f} CPU-s, cost to 1 %: {r['cost_1pct']:.0f} CPU-s")
        store.put("eta", key, r)


# --------------------------------------------------------------------------
# Section 3: colloid diffusion
# --------------------------------------------------------------------------
def colloid_system(L, integ, dt, seed):
    system, colloid, solvent = make_system(L, R_COLLOID, GAMMA, seed, warmup=0.0)
    system.time_step = dt
    system.cell_system.skin = skin_for(dt)
    getattr(system.integrator, "set_" + integ)()
    system.integrator.run(int(round(10.0 / dt)))
    return system, colloid


def drag_case(L, T, integ="vv", dt=0.01, v_target=V_DRAG, seed=41, t_eq=20.0):
    """The drag method (marble.diffusion.measure_drag) with the error of
    marble.colloid_runs.drag_run: the larger of the blocking error and the
    floor sqrt(2 D / T) / v (written here for any dt; drag_run assumes 0.01)."""
    clk = Clock()
    system, colloid = colloid_system(L, integ, dt, seed)
    D_guess = th.hasimoto_D(ETA_REF, R_COLLOID, L)
    F = v_target / D_guess
    delta_N = max(1, int(round(0.1 / dt)))
    c = time.process_time()
    res = dif.measure_drag(system, [colloid], force=[F, 0.0, 0.0], steps=int(round(T / dt)),
                           equilibration_steps=int(round(t_eq / dt)), delta_N=delta_N, kT=KT)
    clk.cpu_run += time.process_time() - c
    t = clk.done()
    v_floor = np.sqrt(2.0 * max(res.D, 0.0) / T)
    D_err = KT * max(res.v_err, v_floor) / F
    N = len(system.part.all())
    out = dict(method="drag", L=L, R=R_COLLOID, integrator=integ, dt=dt, T=T, t_eq=t_eq, F=F,
               N=N, v=res.v, D=res.D, D_err=D_err, D_err_blocking=res.D_err,
               blocking_converged=bool(res.blocking.converged), seed=seed, **t)
    out["cpu_per_tau"] = t["cpu_run_s"] / (T + t_eq + 10.0)
    return out


def equilibrium_case(L, t_chunk, n_chunks, seed=51):
    clk = Clock()
    system, colloid = colloid_system(L, "vv", 0.01, seed)
    def on_chunk(out, c):
        log(f"      chunk {c}/{n_chunks}")
    c = time.process_time()
    eq = equilibrium_run(system, colloid, t_chunk, n_chunks, vacf_tau_max=30.0,
                         msd_tau_max=50.0, on_chunk=on_chunk)
    clk.cpu_run += time.process_time() - c
    t = clk.done()
    gk, win_gk, msd, win_msd = analyse_equilibrium(eq, L, ETA_REF)
    return dict(L=L, R=R_COLLOID, T=t_chunk * n_chunks, t_chunk=t_chunk, n_chunks=n_chunks,
                N=len(system.part.all()), frame_factor=eq["frame_factor"], seed=seed,
                D_gk=gk.value, D_gk_err=gk.error, window_gk=list(win_gk),
                D_msd=msd.value, D_msd_err=msd.error, window_msd=list(win_msd), **t)


def section_colloid(store, quick):
    if quick:
        cases = [("drag_L8", dict(L=8.0, T=150.0, t_eq=5.0))]
        eq_cases = [("eq_L8", dict(L=8.0, t_chunk=40.0, n_chunks=3))]
    else:
        cases = [
            ("drag_L8", dict(L=8.0, T=3000.0)),
            ("drag_L10", dict(L=10.0, T=3000.0)),
            ("drag_L12", dict(L=12.0, T=2000.0)),
            ("drag_L16", dict(L=16.0, T=1000.0)),
            ("drag_L10_v0.24", dict(L=10.0, T=1500.0, v_target=0.24)),
            ("drag_L8_shardlow_dt0.04", dict(L=8.0, T=1500.0, integ="shardlow", dt=0.04)),
            ("drag_L8_vv_dt0.04", dict(L=8.0, T=1500.0, integ="vv", dt=0.04)),
            ("drag_L8_shardlow_dt0.02", dict(L=8.0, T=1500.0, integ="shardlow", dt=0.02)),
        ]
        eq_cases = [("eq_L8", dict(L=8.0, t_chunk=100.0, n_chunks=30))]
    # the equilibrium run first after the main drag series: all methods at L = 8 early
    order = cases[:2] + eq_cases + cases[2:]
    for key, kw in order:
        if store.has("colloid", key):
            continue
        if key.startswith("eq"):
            log(f"[colloid] {key}: VACF + MSD, {kw} ...")
            r = equilibrium_case(**kw)
            log(f"      D_GK = {r['D_gk']:.5f} +/- {r['D_gk_err']:.5f}, D_MSD = {r['D_msd']:.5f}"
                f" +/- {r['D_msd_err']:.5f}, {r['cpu_s']:.0f} CPU-s")
        else:
            log(f"[colloid] {key}: drag, {kw} ...")
            r = drag_case(**kw)
            log(f"      D = {r['D']:.5f} +/- {r['D_err']:.5f} (v = {r['v']:.3f}; Hasimoto "
                f"{th.hasimoto_D(ETA_REF, R_COLLOID, r['L']):.5f}), {r['cpu_s']:.0f} CPU-s")
        store.put("colloid", key, r)


# --------------------------------------------------------------------------
# Analysis and plots
# --------------------------------------------------------------------------
def hasimoto_shift(L, eta=ETA_REF, R=R_COLLOID):
    """D(inf) - D(L) for a stick sphere: kT/(6 pi eta) [2.837297/L - (4 pi/3) R^2/L^3]."""
    return th.hasimoto_D(eta, R) - th.hasimoto_D(eta, R, L)


def crossing_dt(dts, dev, err, level):
    """Largest dt of the sweep below which |kT - 1| stays under level (linear
    interpolation of |dev| between neighbouring dt)."""
    dts, dev = np.asarray(dts), np.abs(np.asarray(dev))
    ok = dev < level
    if not ok[0]:
        return None
    for i in range(1, len(dts)):
        if not ok[i]:
            return float(dts[i - 1] + (level - dev[i - 1]) * (dts[i] - dts[i - 1]) /
                         (dev[i] - dev[i - 1]))
    return float(dts[-1])


def analyse(data):
    S = {}
    kt = data.get("kT", {})
    if kt:
        per = {}
        for integ in INTEGRATORS:
            rows = sorted((r for r in kt.values() if r["integrator"] == integ), key=lambda r: r["dt"])
            if not rows:
                continue
            dts = [r["dt"] for r in rows]
            dev = [r["kT"] - 1.0 for r in rows]
            err = [r["kT_err"] for r in rows]
            cost = [r["cpu_per_tau_per_1000p"] for r in rows]
            e = dict(dt=dts, dev=dev, err=err, cost=cost)
            for lev in (0.01, 0.005, 0.02):
                d = crossing_dt(dts, dev, err, lev)
                e[f"dt_for_{lev}"] = d
                if d is not None:
                    e[f"cost_at_{lev}"] = float(np.exp(np.interp(np.log(d), np.log(dts),
                                                                 np.log(cost))))
            per[integ] = e
        S["kT"] = per
        # Pareto front on the 2-sigma upper bound of |kT - 1| (at small dt the
        # deviation is below the statistical error; its bare value is noise)
        pts = [(r["cpu_per_tau_per_1000p"], abs(r["kT"] - 1.0) + 2 * r["kT_err"], k)
               for k, r in kt.items()]
        front, best = [], np.inf
        for c, a, k in sorted(pts):
            if a < best:
                front.append(k)
                best = a
        S["kT_pareto_front"] = front
        # solvent self-diffusion relative to the smallest-dt VV value
        ref = [r for r in kt.values() if r["integrator"] == "vv" and r.get("Ds")]
        if ref:
            r0 = min(ref, key=lambda r: r["dt"])
            S["Ds_reference"] = dict(key=f"vv_dt{r0['dt']}", Ds=r0["Ds"], Ds_err=r0["Ds_err"])
    eta = data.get("eta", {})
    if eta:
        S["eta"] = {k: dict(eta=r["eta"], eta_err=r["eta_err"], dev_vs_ref=r["eta"] / ETA_REF - 1.0,
                            cost_1pct=r["cost_1pct"]) for k, r in eta.items()}
    col = data.get("colloid", {})
    if col:
        D = {}
        for k, r in col.items():
            L = r["L"]
            hz = th.hasimoto_D(ETA_REF, R_COLLOID, L)
            if r.get("method") == "drag":
                vals = [("drag", r["D"], r["D_err"])]
            else:
                vals = [("gk", r["D_gk"], r["D_gk_err"]), ("msd", r["D_msd"], r["D_msd_err"])]
            for m, d, de in vals:
                shift = hasimoto_shift(L)
                # error of the corrected value: statistics + eta's uncertainty in the shift
                shift_err = shift * ETA_REF_ERR / ETA_REF
                dinf = d + shift
                D[k if m == "drag" else f"{k}_{m}"] = dict(
                    L=L, method=m, D=d, D_err=de, hasimoto=hz, ratio=d / hz, ratio_err=de / hz,
                    rel_err=de / d, cpu_s=r["cpu_s"], cost_1pct=r["cpu_s"] * (de / d / 0.01) ** 2,
                    D_inf_corrected=dinf, D_inf_corrected_err=float(np.hypot(de, shift_err)),
                    cost_1pct_Dinf=r["cpu_s"] * (de / dinf / 0.01) ** 2,
                    integrator=r.get("integrator", "vv"), dt=r.get("dt", 0.01), v=r.get("v"))
        S["D"] = D
        main = [v for k, v in D.items() if v["method"] == "drag" and v["integrator"] == "vv"
                and v["dt"] == 0.01 and (v["v"] or 0) < 0.18]
        if main:
            x = np.array([v["D_inf_corrected"] for v in main])
            w = 1.0 / np.array([v["D_err"] for v in main]) ** 2
            m = float(np.sum(w * x) / np.sum(w))
            m_err_stat = float(1.0 / np.sqrt(np.sum(w)))
            # eta's error moves every corrected point together
            sh = np.array([hasimoto_shift(v["L"]) for v in main])
            m_err_eta = float(np.sum(w * sh) / np.sum(w) * ETA_REF_ERR / ETA_REF)
            chi2 = float(np.sum(w * (x - m) ** 2))
            conv = dict(D_inf=m, D_inf_err_stat=m_err_stat, D_inf_err_eta=m_err_eta,
                        D_inf_err=float(np.hypot(m_err_stat, m_err_eta)), chi2=chi2,
                        ndof=len(main) - 1, from_=[f"L={v['L']:g}" for v in main],
                        stokes_stick=th.hasimoto_D(ETA_REF, R_COLLOID),
                        R_h=float(KT / (6 * np.pi * ETA_REF * m)))
            Ls = np.array([v["L"] for v in main])
            if len(main) >= 3:
                # free extrapolation: D(L) - B/L^3 = D_inf - A/L, A fitted (no eta needed for D_inf)
                y = np.array([v["D"] for v in main]) - \
                    KT / (6 * np.pi * ETA_REF) * (4 * np.pi / 3) * R_COLLOID ** 2 / Ls ** 3
                A = np.stack([np.ones_like(Ls), -1.0 / Ls], axis=1)
                W = np.sqrt(w)[:, None]
                coef, *_ = np.linalg.lstsq(A * W, y * W[:, 0], rcond=None)
                cov = np.linalg.inv((A * W).T @ (A * W))
                conv["free_fit"] = dict(D_inf=float(coef[0]), D_inf_err=float(np.sqrt(cov[0, 0])),
                                        A=float(coef[1]), A_err=float(np.sqrt(cov[1, 1])),
                                        A_hasimoto=th.HASIMOTO_XI * KT / (6 * np.pi * ETA_REF),
                                        eta_from_A=float(th.HASIMOTO_XI * KT / (6 * np.pi * coef[1])))
            big = max(main, key=lambda v: v["L"])
            conv["largest_L"] = dict(L=big["L"], D=big["D"], D_err=big["D_err"],
                                     uncorrected_error=big["D"] / m - 1.0)
            S["D_converged"] = conv
            for v in D.values():
                v["uncorrected_error"] = v["D"] / m - 1.0
                v["corrected_error"] = v["D_inf_corrected"] / m - 1.0
    return S


def plot_all(data, S, prefix):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    colors = dict(vv="C0", shardlow="C1", dpd_vv="C2")
    names = dict(vv="VV", shardlow="Shardlow S1", dpd_vv="DPD-VV")
    files = []
    if "kT" in S:
        fig, ax = plt.subplots(1, 2, figsize=(12, 4.8))
        kt = data["kT"]
        for integ, e in S["kT"].items():
            c = np.array(e["cost"])
            a = np.abs(e["dev"])
            err = np.array(e["err"])
            ub = a + 2 * err
            sig = a > 2 * err
            ax[0].plot(c, ub, "-", color=colors[integ], lw=1)
            ax[0].plot(c[sig], ub[sig], "o", color=colors[integ], label=names[integ])
            ax[0].plot(c[~sig], ub[~sig], "o", mfc="none", color=colors[integ])
            for ci, ai, d in zip(c, ub, e["dt"]):
                ax[0].annotate(f"{d:g}", (ci, ai), fontsize=7, textcoords="offset points",
                               xytext=(3, 3))
            ax[1].errorbar(e["dt"], np.array(e["dev"]) + 1.0, yerr=e["err"], fmt="o-",
                           color=colors[integ], label=names[integ], capsize=2)
        fr = S["kT_pareto_front"]
        ax[0].plot([kt[k]["cpu_per_tau_per_1000p"] for k in fr],
                   [abs(kt[k]["kT"] - 1) + 2 * kt[k]["kT_err"] for k in fr], "k--", lw=1,
                   label="Pareto front")
        ax[0].plot([], [], "o", mfc="none", color="grey", label="|kT - 1| < 2 sigma (bound only)")
        ax[0].axhline(0.01, color="grey", ls=":", lw=1)
        ax[0].axhline(0.005, color="grey", ls=":", lw=1)
        ax[0].set_xscale("log")
        ax[0].set_yscale("log")
        ax[0].set_ylim(1e-3, 0.1)
        ax[0].set_xlabel("CPU-s per tau per 1000 beads (one core)")
        ax[0].set_ylabel("|kT - 1| + 2 sigma (labels: dt)")
        ax[0].set_title("paper solvent (a=0, gamma=5, rho=3): accuracy vs cost")
        ax[0].legend(fontsize=8)
        ax[1].axhline(1.0, color="k", lw=0.8)
        ax[1].set_xlabel("dt")
        ax[1].set_ylabel("kinetic temperature")
        ax[1].set_title("kT(dt), L = 8, block-averaged error bars")
        ax[1].legend(fontsize=8)
        fig.tight_layout()
        f = prefix + "_kT.png"
        fig.savefig(f, dpi=110)
        plt.close(fig)
        files.append(f)
    if "D" in S:
        D = S["D"]
        fig, ax = plt.subplots(1, 2, figsize=(12, 4.8))
        Lg = np.linspace(7.0, 60.0, 200)
        ax[0].plot(1 / Lg, [th.hasimoto_D(ETA_REF, R_COLLOID, L) for L in Lg], "k-", lw=1,
                   label=f"Hasimoto stick, eta = {ETA_REF}")
        mk = dict(drag="o", gk="s", msd="^")
        for k, v in D.items():
            lab = f"{v['method']} {v['integrator']} dt={v['dt']:g}" + \
                (f" v={v['v']:.2f}" if v["method"] == "drag" else "")
            main = v["method"] == "drag" and v["integrator"] == "vv" and v["dt"] == 0.01 \
                and (v["v"] or 0) < 0.18
            col = "C0" if main else ("C3" if v["method"] != "drag" else "C2")
            x = 1 / v["L"] + (0.0 if main else 0.002 * (hash(k) % 5 - 2))
            ax[0].errorbar(x, v["D"], yerr=v["D_err"], fmt=mk[v["method"]], color=col, capsize=2,
                           label=lab if not main else None, ms=5)
            if main:
                ax[0].errorbar(x, v["D_inf_corrected"], yerr=v["D_inf_corrected_err"], fmt="D",
                               mfc="none", color="C1", capsize=2, ms=5)
        ax[0].plot([], [], "o", color="C0", label="drag VV dt=0.01 v=0.12: D(L)")
        ax[0].plot([], [], "D", mfc="none", color="C1", label="same, Hasimoto-corrected to L=inf")
        if "D_converged" in S:
            cv = S["D_converged"]
            ax[0].axhspan(cv["D_inf"] - cv["D_inf_err"], cv["D_inf"] + cv["D_inf_err"],
                          color="C1", alpha=0.2)
            ax[0].plot(1 / Lg, [th.hasimoto_D(ETA_REF, cv["R_h"], L) for L in Lg], "k:", lw=1,
                       label=f"Hasimoto stick, R_h = {cv['R_h']:.2f} (from D_inf)")
            if "free_fit" in cv:
                ff = cv["free_fit"]
                ax[0].plot(1 / Lg, ff["D_inf"] - ff["A"] / Lg + KT / (6 * np.pi * ETA_REF)
                           * (4 * np.pi / 3) * R_COLLOID ** 2 / Lg ** 3, "C1--", lw=1,
                           label="free fit D_inf - A/L")
        ax[0].set_xlim(0, 0.14)
        ax[0].set_xlabel("1/L")
        ax[0].set_ylabel("D (colloid-solvent relative coordinate)")
        ax[0].set_title(f"no-slip marble R = {R_COLLOID:g}: D(L)")
        ax[0].legend(fontsize=7)
        keys = [k for k in D]
        labels = [f"{D[k]['method']} L={D[k]['L']:g}\n{D[k]['integrator']} {D[k]['dt']:g}"
                  + (f" v{D[k]['v']:.2f}" if D[k]['method'] == 'drag' else "") for k in keys]
        y = np.arange(len(keys))
        ax[1].barh(y - 0.2, [D[k]["cost_1pct"] for k in keys], 0.4, label="D(L) to 1 %")
        ax[1].barh(y + 0.2, [D[k]["cost_1pct_Dinf"] for k in keys], 0.4,
                   label="D(inf) via Hasimoto to 1 % (stat. only)")
        ax[1].set_yticks(y)
        ax[1].set_yticklabels(labels, fontsize=7)
        ax[1].set_xscale("log")
        ax[1].set_xlabel("CPU-s for a 1 % statistical error (CPU-s x (rel. err / 1 %)^2)")
        ax[1].set_title("cost per unit statistical error")
        ax[1].legend(fontsize=8)
        fig.tight_layout()
        f = prefix + "_D.png"
        fig.savefig(f, dpi=110)
        plt.close(fig)
        files.append(f)
    if data.get("density") or data.get("eta"):
        fig, ax = plt.subplots(1, 2, figsize=(11, 4.3))
        dn = data.get("density", {})
        if dn:
            rows = sorted(dn.values(), key=lambda r: r["rho"])
            ax[0].plot([r["rho"] for r in rows], [r["cpu_per_tau_per_volume"] * 1e3 for r in rows],
                       "o-")
            ax[0].set_xlabel("rho")
            ax[0].set_ylabel("CPU-ms per tau per unit volume (VV, dt = 0.01)")
            ax[0].set_title("cost vs solvent density")
        et = data.get("eta", {})
        if et:
            rows = [r for r in et.values() if r["integrator"] == "vv" and r["dt"] == 0.01]
            rows.sort(key=lambda r: r["rho"])
            ax[1].errorbar([r["rho"] for r in rows], [r["eta"] for r in rows],
                           yerr=[r["eta_err"] for r in rows], fmt="o-", capsize=2, label="VV dt 0.01")
            others = [r for r in et.values() if not (r["integrator"] == "vv" and r["dt"] == 0.01)]
            for i, r in enumerate(others):
                ax[1].errorbar(r["rho"] + 0.06 * (i + 1), r["eta"], yerr=r["eta_err"], fmt="s",
                               capsize=2, label=f"{r['integrator']} dt {r['dt']:g}")
            ax[1].set_xlabel("rho")
            ax[1].set_ylabel("eta (reverse Poiseuille)")
            ax[1].legend(fontsize=7)
            ax[1].set_title("solvent viscosity")
        fig.tight_layout()
        f = prefix + "_density.png"
        fig.savefig(f, dpi=110)
        plt.close(fig)
        files.append(f)
    return files


def main():
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--quick", action="store_true", help="~15 s smoke run (own output files)")
    ap.add_argument("--out", default=os.path.join(HERE, "results"))
    ap.add_argument("--part", default="kT,density,colloid,plot",
                    help="comma-separated sections: kT, density, colloid, plot")
    ap.add_argument("--redo", action="store_true", help="rerun cases already in the JSON")
    args = ap.parse_args()
    parts = [p.strip() for p in args.part.split(",") if p.strip()]
    bad = set(parts) - {"kT", "density", "colloid", "plot"}
    if bad:
        ap.error(f"unknown --part {sorted(bad)}")
    os.makedirs(args.out, exist_ok=True)
    name = "speed_accuracy_quick" if args.quick else "speed_accuracy"
    store = Store(os.path.join(args.out, name + ".json"), redo=args.redo)
    store.data.setdefault("config", dict(
        solvent=dict(rho=3.0, gamma=GAMMA, weight_function=1, k=1.0, r_cut=1.0, a=0.0, kT=KT),
        marble=dict(R=R_COLLOID, coupling="tunable_slip", gamma=GAMMA, mass="neutrally buoyant"),
        eta_ref=ETA_REF, eta_ref_err=ETA_REF_ERR, v_drag=V_DRAG, quick=args.quick,
        cost="process CPU time of one core; cost_1pct = cpu_s * (rel_err / 0.01)^2"))
    t0c, t0w = time.process_time(), time.time()
    info = machine_info()
    info["parts"] = parts
    store.data["runs"].append(info)
    store.save()
    if "kT" in parts:
        section_kT(store, args.quick)
    if "density" in parts:
        section_density(store, args.quick)
    if "colloid" in parts:
        section_colloid(store, args.quick)
    info.update(cpu_s=time.process_time() - t0c, wall_s=time.time() - t0w,
                load_avg_end=list(os.getloadavg()))
    store.data["summary"] = analyse(store.data)
    store.save()
    if "plot" in parts:
        files = plot_all(store.data, store.data["summary"], os.path.join(args.out, name))
        log("wrote", ", ".join(files))
    log(f"wrote {store.path}; this invocation: {info['cpu_s']:.0f} CPU-s, {info['wall_s']:.0f} s wall")
    return 0


if __name__ == "__main__":
    sys.exit(main())
