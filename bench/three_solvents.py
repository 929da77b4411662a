"""One colloid, three solvents (issue 14; doc/choosing-a-model.md explains the results).

The same colloid (radius R in solvent units, kT = 1, L/R = 5; at R = 2 also
L/R = 8, where D(inf) after Hasimoto's correction must come out the same) in
  marble  the marble colloid in the marble paper's DPD solvent (seed 000):
          rho = 3, DPD gamma = 5, no conservative force, tunable-slip coupling
          gamma = 5 (stick; coupling "dpd" = central forces only: slip;
          case R2_L10_b1: the tunable-slip gamma that the shipped calibration
          marble.slip.gamma_for_slip_length(1.0, surface="marble") gives for
          slip length b = 1, compared with Basset's partial-slip drag),
          Shardlow at dt = 0.04 (doc/speed-accuracy.md);
  srd     the SRD solvent with a stochastic-boundary stick colloid (seed 003):
          density 5, tau = 0.1, alpha = 90 deg, MBS thermostat, dt = 0.025,
          neutrally buoyant colloid (rule "slip": specular, perfect slip);
  core    a core-modified DPD colloid (seed 004) in Groot-Warren water:
          rho = 3, a_ss = 25 kT, gamma = 4.5, colloid-solvent hat and DPD on the
          gap with the equal-volume cutoff and the mean-field F_max
          (marble.suspensions.setup_suspension, one colloid), velocity Verlet
          at dt = 0.005 (R = 2; the shell stiffness sets it). Only central
          forces act on the colloid: it has no rotation and its surface is a
          slip surface -- it is compared with the slip value kT/(4 pi eta R).

For each model: the solvent's own viscosity (reverse Poiseuille,
marble.viscosity / marble.srd, combined with the engine's earlier
measurement by a weighted mean), D(L) by drag (constant force, mean relative
velocity) and by Green-Kubo (VACF integral over independent chunks, frame
factor (Ms/(M+Ms))^2 as in marble.colloid_runs), D(inf) with Hasimoto's
correction, its error against Stokes-Einstein (stick or slip) = the model's
systematic error; the rotational D by Green-Kubo where the colloid rotates;
CPU-seconds (time.process_time of integrator.run) per unit simulated time
and the CPU time to 1 % and 5 % statistical error in D(inf):
T_eps = T (sigma_D / (eps D(inf)))^2 (error ~ 1/sqrt(T)).

Sections (--part, comma separated; default all): eta, drag, gk, paper, probe, plot.
`--part retime` (alone) re-times the advisor's package table with the current code
(retime_package: after a change of the engine's speed).
"paper" measures only the CPU cost per unit time at R = 3, L = 15 (short runs);
the statistical errors there are extrapolated (doc/choosing-a-model.md says which).

Run:   build/pymarble bench/three_solvents.py [--model marble,srd,core] [--part ...]
                                              [--case R2_L16,R2_L10_b1] [--no-package]
Writes bench/results/three_solvents_<model>.json (resumable: cases already
there are skipped, --redo reruns them), and with --part plot the merged
bench/results/three_solvents.json, doc/figures/three_solvents.png and the
advisor's package data src/python/marble/data/three_solvents.json.
--quick: a ~1 min smoke version into three_solvents_quick_<model>.json.
"""
import argparse
import json
import math
import os
import sys
import time

import numpy as np

import marble
from marble import accumulators as acc
from marble import diffusion as dif
from marble import observables as obs
from marble import theory as th
from marble.colloid_runs import jsonable
from marble.viscosity import block_average

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
KT = 1.0
V_DRAG = 0.12          # target drift velocity of the drag runs
MODELS = ("marble", "srd", "core")

# Engine's earlier viscosity measurements of the same solvents (same tools):
# marble paper solvent: doc/dpd.md (12 x 12 x 16, 2000 tau, VV dt = 0.01);
# SRD gamma = 5, 90 deg, tau = 0.1: doc/srd.md (Poiseuille, T = 3000);
# Groot-Warren water (a = 25, gamma = 4.5): doc/dpd.md (300 tau).
ETA_PRIOR = {"marble": (1.273, 0.007), "srd": (2.603, 0.035), "core": (0.851, 0.017)}

from marble.advisor import BOUNDARY, ROTATES, SETTINGS, Scene  # noqa: E402


def log(*a):
    print(*a, flush=True)


def eta_of(model, data):
    """The viscosity used for the analysis: weighted mean of this bench's
    measurement and the engine's earlier one (ETA_PRIOR)."""
    vals = [ETA_PRIOR[model]]
    m = data.get("eta", {}).get("eta")
    if m and m.get("eta_err"):
        vals.append((m["eta"], m["eta_err"]))
    w = np.array([1.0 / e ** 2 for _, e in vals])
    x = np.array([v for v, _ in vals])
    return float(np.sum(w * x) / np.sum(w)), float(1.0 / math.sqrt(np.sum(w)))


def D_guess(model, R, L, eta, boundary, b=None):
    if boundary == "partial":
        return th.diffusion_coefficient(eta, R, L, b, KT)
    b = 0.0 if boundary == "stick" else np.inf
    D = th.diffusion_coefficient(eta, R, L, b, KT)
    if model == "srd":
        import marble.srd as srd
        M = SETTINGS["srd"]["density"] * 4.0 / 3.0 * math.pi * R ** 3
        rule = "stochastic" if boundary == "stick" else "slip"
        D += KT / (M * srd.kinetic_friction(R, M, SETTINGS["srd"]["density"], rule)[0])
    return D


# --------------------------------------------------------------------------
# Measurements
# --------------------------------------------------------------------------
def eta_case(model, T, seed=21):
    """Reverse Poiseuille viscosity of the pure solvent."""
    c0 = time.process_time()
    if model == "srd":
        import marble.srd as srd
        st = SETTINGS["srd"]
        s = marble.System(box_l=[8.0, 8.0, 16.0], time_step=st["tau"])
        s.srd = srd.SRDFluid(types=[0], tau=st["tau"], angle=st["angle"], kT=KT, seed=seed,
                             thermostat="mbs")
        srd.add_fluid(s, density=st["density"], type=0, kT=KT, seed=seed + 1)
        r = srd.reverse_poiseuille(s, g=0.02, time=T, n_blocks=16, sample_every=5)
        box = [8, 8, 16]
    else:
        from marble.viscosity import reverse_poiseuille
        st = SETTINGS[model]
        box = [10.0, 10.0, 12.0]
        s = marble.System(box_l=box)
        s.time_step = st["dt"] if model == "marble" else 0.005
        s.cell_system.skin = 0.4
        rng = np.random.default_rng(seed)
        n = int(round(3.0 * np.prod(box)))
        s.part.add(pos=rng.random((n, 3)) * np.asarray(box), v=rng.normal(size=(n, 3)), type=0)
        s.thermostat.set_dpd(kT=KT, seed=seed)
        if model == "marble":
            s.non_bonded_inter[0, 0].dpd.set_params(weight_function=1, gamma=5.0, k=1, r_cut=1.0)
            s.integrator.set_shardlow()
            g = 0.06
        else:
            s.non_bonded_inter[0, 0].hat.set_params(F_max=25.0, cutoff=1.0)
            s.non_bonded_inter[0, 0].dpd.set_params(weight_function=1, gamma=4.5, r_cut=1.0)
            g = 0.045
        s.integrator.run(int(round(5.0 / s.time_step)))
        r = reverse_poiseuille(s, g=g, time=T, n_blocks=16)
    return dict(eta=r.eta, eta_err=r.eta_err, T=T, box=box, cpu_s=time.process_time() - c0,
                eta_prior=ETA_PRIOR[model][0], eta_prior_err=ETA_PRIOR[model][1])


def drag_case(model, R, L, T, eta, boundary="stick", seed=41, t_eq=20.0, b=None):
    """Drag method: D(L) = kT <v_rel> / F, error the larger of the blocking
    error and the floor sqrt(2 D / T) (marble.colloid_runs.drag_run).
    boundary="partial" (marble only): the tunable-slip marble at the surface
    friction that the shipped calibration curve gives for slip length ``b``
    (marble.slip.gamma_for_slip_length(b, surface="marble")); the curve's b
    and its error at that gamma are stored with the run."""
    extra = {}
    gamma = None
    if boundary == "partial":
        from marble import slip
        gamma, gamma_err = slip.gamma_for_slip_length(b, surface="marble", radius=R)
        b_curve, b_curve_err = slip.slip_length_for_gamma(gamma, "marble")
        cond = slip.load_curve("marble")["conditions"]
        extra = dict(b_target=b, gamma=gamma, gamma_err=gamma_err, b=b_curve,
                     b_err_curve=b_curve_err,
                     curve_integrator=f"{cond['integrator']} dt = {cond['dt']}")
        log(f"      calibrated marble: b = {b} -> gamma = {gamma:.4f} +/- {gamma_err:.4f} "
            f"(curve: b = {b_curve:.4f} +/- {b_curve_err:.4f})")
    sc = Scene(model, R, L, seed, boundary, gamma=gamma)
    F = V_DRAG / D_guess(model, R, L, eta, boundary, b)
    vrel, cpu_run, cpu = sc.drag_series(F, T, t_eq)
    v, v_err_blk = block_average(vrel, min_blocks=16)
    D = KT * v / F
    v_floor = math.sqrt(2.0 * max(D, 0.0) / T)
    v_err = max(v_err_blk, v_floor)
    return dict(method="drag", model=model, boundary=boundary, R=R, L=L, T=T, t_eq=t_eq, F=F,
                dt=sc.dt, N=sc.n_particles, v=v, v_err=v_err, v_err_blocking=v_err_blk,
                D=D, D_err=KT * v_err / F, D_err_blocking=KT * v_err_blk / F, seed=seed,
                cpu_run_s=cpu_run, cpu_eq_s=cpu, cpu_per_tau=cpu_run / T,
                load_avg=os.getloadavg()[0], **extra)


def gk_case(model, R, L, t_chunk, n_chunks, eta, seed=51, boundary="stick"):
    """Equilibrium runs: VACF and rotational VACF (multiple-tau correlators)
    of n_chunks independent chunks; Green-Kubo D(L) of the colloid-solvent
    relative coordinate (divided by the frame factor) and D_rot."""
    sc = Scene(model, R, L, seed, boundary, warmup=10.0 if model != "core" else 5.0)
    s, col = sc.system, sc.colloid
    rho_m = 5.0 if model == "srd" else 3.0
    tau_box = L ** 2 / (4 * math.pi ** 2 * eta / rho_m)
    # plateau window (3, 6) tau_box (marble.colloid_runs.gk_window); the core
    # colloid's slow box modes (nu = 0.28) would need 70-tau chunks: (1, 2) there
    win = (1.0 * tau_box, 2.0 * tau_box) if model == "core" else (3.0 * tau_box, 6.0 * tau_box)
    win_r = (1.0 * tau_box, 2.0 * tau_box)
    dN = max(1, int(round(0.05 / sc.dt)))
    vel = obs.ParticleVelocities(ids=[col.id], system=s)
    omg = obs.ParticleAngularVelocities(ids=[col.id], system=s) if ROTATES[model] else None
    V, W = [], []
    steps = int(round(t_chunk / sc.dt))
    cpu = 0.0
    for c in range(n_chunks):
        cv = acc.Correlator(obs1=vel, tau_lin=16, tau_max=win[1] * 1.1, delta_N=dN,
                            corr_operation="scalar_product", compress1="linear")
        s.auto_update_accumulators.add(cv)
        if omg is not None:
            cw = acc.Correlator(obs1=omg, tau_lin=16, tau_max=win[1] * 1.1, delta_N=dN,
                                corr_operation="scalar_product", compress1="linear")
            s.auto_update_accumulators.add(cw)
        cpu += sc.run(steps)
        s.auto_update_accumulators.clear()
        t = cv.lag_times()
        V.append(cv.result()[:, 0])
        if omg is not None:
            tw = cw.lag_times()
            W.append(cw.result()[:, 0])
        log(f"      chunk {c + 1}/{n_chunks}, {cpu:.0f} CPU-s")
    ff = sc.frame_factor
    gk = dif.green_kubo(t, np.array(V) / ff, window=win)
    out = dict(method="gk", model=model, boundary=boundary, R=R, L=L, T=t_chunk * n_chunks,
               t_chunk=t_chunk, n_chunks=n_chunks, dt=sc.dt, N=sc.n_particles, frame_factor=ff,
               window=list(win), D=gk.value, D_err=gk.error, cpu_run_s=cpu,
               cpu_per_tau=cpu / (t_chunk * n_chunks), seed=seed, load_avg=os.getloadavg()[0],
               t_vacf=t, vacf=np.mean(V, axis=0))
    if W:
        gr = dif.green_kubo(tw, np.array(W), window=win_r)
        out.update(D_rot=gr.value, D_rot_err=gr.error, window_rot=list(win_r),
                   rvacf=np.mean(W, axis=0))
    return out


def cost_case(model, R, L, T, seed=61):
    """CPU-seconds per unit time of the scene (no measurement): the paper-size probe."""
    sc = Scene(model, R, L, seed, warmup=min(1.0, T))
    cpu = sc.run(int(round(T / sc.dt)))
    return dict(model=model, R=R, L=L, T=T, dt=sc.dt, N=sc.n_particles, cpu_run_s=cpu,
                cpu_per_tau=cpu / T, load_avg=os.getloadavg()[0])


# --------------------------------------------------------------------------
# Store, plan
# --------------------------------------------------------------------------
class Store:
    """JSON file, rewritten atomically after every case (resumable)."""

    def __init__(self, path, redo=False):
        self.path, self.redo, self.data = path, redo, {}
        if os.path.exists(path):
            with open(path) as f:
                self.data = json.load(f)

    def has(self, section, key):
        return not self.redo and key in self.data.get(section, {})

    def put(self, section, key, value):
        self.data.setdefault(section, {})[key] = jsonable(value)
        tmp = self.path + ".tmp"
        with open(tmp, "w") as f:
            json.dump(jsonable(self.data), f, indent=1)
        os.replace(tmp, self.path)


def plan(model, quick):
    """Cases per section at reduced size (R = 2, L = 10; core: 11) and the
    paper-size cost probe (R = 3, L = 15). The stored core-modified runs
    still had the colloid-colloid kernels (70x the marble's cost per unit
    time, now 11x: advisor.Scene removes them), so its runs are short."""
    f = 0.03 if quick else 1.0
    T_drag = {"marble": 2000.0, "srd": 4000.0, "core": 60.0}[model] * f
    chunk = {"marble": 150.0, "srd": 200.0, "core": 25.0}[model]
    n_ch = {"marble": 16, "srd": 20, "core": 2}[model]
    if quick:
        chunk, n_ch = (40.0, 2) if model != "core" else (10.0, 2)
    # setup_suspension needs L > 2 (2R + r_c) = 10 at R = 2: the core colloid gets L = 11
    L = 11.0 if model == "core" else 10.0
    p = {"eta": [("eta", dict(T={"marble": 400.0, "srd": 2000.0, "core": 100.0}[model] * f))],
         "drag": [("R2_L10", dict(R=2.0, L=L, T=T_drag, boundary=BOUNDARY[model],
                                  t_eq=20.0 if model != "core" else 10.0))],
         "gk": [("R2_L10", dict(R=2.0, L=L, t_chunk=chunk, n_chunks=n_ch))],
         "paper": [("R3_L15", dict(R=3.0, L=15.0, T=(0.2 if quick else
                                                     (1.0 if model == "core" else 10.0))))]}
    # slip where the model has both (marble: central "dpd" coupling; SRD: specular)
    if model in ("marble", "srd"):
        p["drag"].append(("R2_L10_slip", dict(R=2.0, L=10.0, T=T_drag / 2, boundary="slip")))
    # the calibrated tunable-slip marble (marble.slip, b = 1 for R = 2): Basset's drag
    if model == "marble":
        p["drag"].append(("R2_L10_b1", dict(R=2.0, L=10.0, T=1500.0 * f, boundary="partial",
                                            b=1.0)))
    # L/R = 8 (R = 2, L = 16): D(inf) after Hasimoto's correction must not depend on L
    p["drag"].append(("R2_L16", dict(R=2.0, L=16.0,
                                     T={"marble": 1000.0, "srd": 3000.0, "core": 100.0}[model] * f,
                                     boundary=BOUNDARY[model],
                                     t_eq=20.0 if model != "core" else 10.0)))
    if model == "marble":   # a second seed: the first came out 2 sigma low
        p["drag"].append(("R2_L16_s2", dict(R=2.0, L=16.0, T=1000.0 * f, boundary="stick",
                                            seed=43)))
    # paper size (R = 3, L = 15): the systematic error measured by drag (the core
    # colloid costs ~35x the marble per unit time there: a shorter run)
    p["drag"].append(("R3_L15", dict(R=3.0, L=15.0,
                                     T={"marble": 800.0, "srd": 3000.0, "core": 100.0}[model] * f,
                                     boundary=BOUNDARY[model], t_eq=20.0 if model != "core" else 10.0)))
    return p


def run_model(model, parts, quick, redo, out_dir, cases=None):
    suffix = "_quick" if quick else ""
    store = Store(os.path.join(out_dir, f"three_solvents{suffix}_{model}.json"), redo)
    store.data.setdefault("machine", {"python": sys.version.split()[0]})
    p = plan(model, quick)
    for section in ("eta", "drag", "gk", "paper"):
        if section not in parts:
            continue
        for key, kw in p[section]:
            if store.has(section, key) or (cases and key not in cases):
                continue
            eta = eta_of(model, store.data)[0]
            log(f"[{model}] {section} {key} {kw} ...")
            t0 = time.time()
            if section == "eta":
                r = eta_case(model, **kw)
                log(f"      eta = {r['eta']:.4f} +/- {r['eta_err']:.4f}")
            elif section == "drag":
                r = drag_case(model, eta=eta, **kw)
                log(f"      D(L) = {r['D']:.5f} +/- {r['D_err']:.5f}, v = {r['v']:.3f}, "
                    f"{r['cpu_per_tau']:.4f} CPU-s/tau")
            elif section == "gk":
                r = gk_case(model, eta=eta, **kw)
                log(f"      D_GK(L) = {r['D']:.5f} +/- {r['D_err']:.5f}"
                    + (f", D_rot = {r['D_rot']:.5f} +/- {r['D_rot_err']:.5f}" if "D_rot" in r else ""))
            else:
                r = cost_case(model, **kw)
                log(f"      {r['cpu_per_tau']:.4f} CPU-s/tau at N = {r['N']}")
            r["wall_s"] = time.time() - t0
            store.put(section, key, r)


# --------------------------------------------------------------------------
# Analysis
# --------------------------------------------------------------------------
def probe_speed(steps=300):
    """This machine's speed: particle-steps per CPU-second of a plain DPD fluid
    (rho = 3, L = 8, VV, dt = 0.01, gamma = 5, no conservative force). The
    advisor (marble.advisor.probe_speed) runs the same probe to rescale costs."""
    import marble.advisor as adv
    # the fastest of three probes (each the fastest of 8 x 300 steps), a few
    # seconds apart: the probe is disturbed by other jobs on a shared machine
    best = 0.0
    for _ in range(3):
        adv._speed_cache.clear()
        best = max(best, adv.probe_speed(steps))
        time.sleep(2.0)
    return best


def analyse(datas):
    """Per model and case: D(inf), systematic error, cost to 1 % and 5 %."""
    rows = []
    for model, d in datas.items():
        eta, eta_err = eta_of(model, d)
        for section in ("drag", "gk"):
            for key, r in d.get(section, {}).items():
                # the core colloid has only one surface (slip), whatever the run was labelled
                R, L = r["R"], r["L"]
                bc = BOUNDARY["core"] if model == "core" else r.get("boundary", "stick")
                b = {"stick": 0.0, "slip": np.inf}.get(bc, r.get("b"))
                shift = th.diffusion_coefficient(eta, R, np.inf, b) - th.diffusion_coefficient(eta, R, L, b)
                D_inf = r["D"] + shift
                ref = th.diffusion_coefficient(eta, R, np.inf, b)
                # d(D_inf/ref)/d eta: D_inf has shift ~ 1/eta, ref ~ 1/eta
                rel_stat = r["D_err"] / D_inf
                sys_err = D_inf / ref - 1.0
                sys_eta = (r["D"] / ref) * (eta_err / eta)   # (D_inf/ref) changes by D(L)/ref x deta/eta
                sys_cal = 0.0
                if bc == "partial":
                    # the calibration curve's error of b at the run's gamma, carried through
                    # Basset + Hasimoto: (D(L) + shift(b)) / D_Basset(b) at b +/- sigma_b
                    sb = r["b_err_curve"]

                    def ratio(bb):
                        return (r["D"] + th.diffusion_coefficient(eta, R, np.inf, bb)
                                - th.diffusion_coefficient(eta, R, L, bb)) / \
                            th.diffusion_coefficient(eta, R, np.inf, bb)
                    sys_cal = 0.5 * abs(ratio(b + sb) - ratio(max(b - sb, 0.0)))
                cpu_tau, N = r["cpu_per_tau"], r["N"]
                c = d.get("cost", {}).get(f"R{R:g}_L{L:g}")
                if c:   # the same scene re-timed without unused kernels (cost_note in the JSON)
                    cpu_tau, N = c["cpu_per_tau"], c["N"]
                row = dict(model=model, method=section, case=key, boundary=bc, R=R, L=L, T=r["T"],
                           eta=eta, eta_err=eta_err, D_L=r["D"], D_L_err=r["D_err"], D_inf=D_inf,
                           D_inf_err=r["D_err"], D_stokes=ref, sys=sys_err, shift=shift,
                           sys_err=math.sqrt((rel_stat * (1 + sys_err)) ** 2 + sys_eta ** 2
                                             + sys_cal ** 2),
                           sys_err_stat=rel_stat * (1 + sys_err), sys_err_eta=sys_eta,
                           sys_err_calibration=sys_cal,
                           cpu_per_tau=cpu_tau, cpu_per_tau_run=r["cpu_per_tau"], N=N, dt=r["dt"],
                           rel_err=rel_stat, var_T=rel_stat ** 2 * r["T"])
                for eps in (0.01, 0.05):
                    row[f"T_{int(eps * 100)}"] = r["T"] * (rel_stat / eps) ** 2
                    row[f"cpu_{int(eps * 100)}"] = row[f"T_{int(eps * 100)}"] * cpu_tau
                if bc == "partial":
                    row.update(b=b, b_err_curve=r["b_err_curve"], gamma=r["gamma"],
                               gamma_err=r["gamma_err"], b_target=r["b_target"],
                               curve_integrator=r["curve_integrator"])
                    # the slip length this run measures (Basset + Hasimoto), for the record
                    try:
                        bm, bme = th.slip_length_from_D(r["D"], eta, R, L, r["D_err"], KT)
                        row.update(b_measured=bm, b_measured_err=bme)
                    except ValueError:
                        pass
                if "D_rot" in r:
                    Dr_th = th.rotational_diffusion_coefficient(eta, R, L, b if bc == "stick" else 0.0)
                    Dr_inf_th = th.rotational_diffusion_coefficient(eta, R, np.inf, 0.0)
                    # the L^-3 rotlet correction, kT/(6 eta L^3)
                    Dr_inf = r["D_rot"] + KT / (6 * eta * L ** 3)
                    row.update(D_rot=r["D_rot"], D_rot_err=r["D_rot_err"], D_rot_inf=Dr_inf,
                               D_rot_stokes=Dr_inf_th, sys_rot=Dr_inf / Dr_inf_th - 1.0,
                               D_rot_L_theory=Dr_th)
                    rr = r["D_rot_err"] / Dr_inf
                    row["cpu_rot_5"] = r["T"] * (rr / 0.05) ** 2 * cpu_tau
                    row["cpu_rot_1"] = r["T"] * (rr / 0.01) ** 2 * cpu_tau
                rows.append(row)
    return rows


def paper_rows(datas, rows):
    """R = 3, L = 15: measured CPU-s per tau; the drag error extrapolated from
    R = 2 with the floor law sigma_v^2 T = 2 D(L) (the relative error of D(inf)
    is sqrt(2 D(L)/T)/v x D(L)/D(inf)) at the same v, with D(L) and D(inf)
    from Hasimoto and the model's systematic error measured at R = 2."""
    out = []
    for model, d in datas.items():
        pr = d.get("cost", {}).get("R3_L15") or d.get("paper", {}).get("R3_L15")
        r2 = [r for r in rows if r["model"] == model and r["method"] == "drag" and r["R"] == 2.0
              and r["boundary"] == BOUNDARY[model]]
        if not pr or not r2:
            continue
        r2 = r2[0]
        eta = r2["eta"]
        b = 0.0 if BOUNDARY[model] == "stick" else np.inf
        R, L = pr["R"], pr["L"]
        shift = th.diffusion_coefficient(eta, R, np.inf, b) - th.diffusion_coefficient(eta, R, L, b)
        # the R = 2 excess over Stokes (kinetic friction, surface) scaled as D ~ 1/R
        D_inf = th.diffusion_coefficient(eta, R, np.inf, b) * (1 + r2["sys"])
        D_L = D_inf - shift
        var_T = 2 * D_L / V_DRAG ** 2 * (D_L / D_inf) ** 2 / D_L ** 2
        # compare the R = 2 measured var_T with the same law, apply the measured ratio
        law2 = 2 * r2["D_L"] / V_DRAG ** 2 * (r2["D_L"] / r2["D_inf"]) ** 2 / r2["D_L"] ** 2
        var_T *= r2["var_T"] / law2
        row = dict(model=model, R=R, L=L, N=pr["N"], dt=pr["dt"], cpu_per_tau=pr["cpu_per_tau"],
                   cpu_per_tau_measured=True, D_inf_est=D_inf, var_T=var_T,
                   T_1=var_T / 0.01 ** 2, T_5=var_T / 0.05 ** 2, extrapolated="error, D")
        row["cpu_1"] = row["T_1"] * pr["cpu_per_tau"]
        row["cpu_5"] = row["T_5"] * pr["cpu_per_tau"]
        out.append(row)
    return out


def hasimoto_rows(rows):
    """L/R = 5 against L/R = 8 at R = 2 (drag, the model's own surface): D(inf)
    after Hasimoto's correction should not depend on L. The difference
    D(inf; L/R = 8) - D(inf; L/R = 5) with its error (both runs' statistics;
    the viscosity's error moves the two shifts together: d/d eta of the
    difference is -(shift_5 - shift_8)/eta), and, for contrast, the
    difference of the uncorrected D(L) and the shift Hasimoto predicts."""
    out = []
    for model in MODELS:
        rs = [r for r in rows if r["model"] == model and r["method"] == "drag" and r["R"] == 2.0
              and r["boundary"] == BOUNDARY[model]]
        small = [r for r in rs if r["case"] == "R2_L10"]
        big = [r for r in rs if r["case"].startswith("R2_L16")]
        if not small or not big:
            continue
        a, c = small[0], dict(big[0])
        if len(big) > 1:   # several seeds at L/R = 8: their weighted mean (same eta, same shift)
            w = np.array([1.0 / r["D_inf_err"] ** 2 for r in big])
            for key in ("D_L", "D_inf"):
                c[key] = float(np.sum(w * [r[key] for r in big]) / np.sum(w))
            c["D_L_err"] = c["D_inf_err"] = float(1.0 / np.sqrt(np.sum(w)))
            c["T"] = float(sum(r["T"] for r in big))
            c["sys"] = c["D_inf"] / c["D_stokes"] - 1.0
            c["sys_err"] = math.hypot(c["D_inf_err"] / c["D_stokes"], c["sys_err_eta"])
            c["cpu_per_tau"] = float(sum(r["cpu_per_tau"] * r["T"] for r in big) / c["T"])
            var_T = (c["D_inf_err"] / c["D_inf"]) ** 2 * c["T"]
            c["cpu_5"] = var_T / 0.05 ** 2 * c["cpu_per_tau"]
            c["cpu_1"] = var_T / 0.01 ** 2 * c["cpu_per_tau"]
        diff = c["D_inf"] - a["D_inf"]
        err_eta = abs(a["shift"] - c["shift"]) * a["eta_err"] / a["eta"]
        err = math.sqrt(a["D_inf_err"] ** 2 + c["D_inf_err"] ** 2 + err_eta ** 2)
        out.append(dict(model=model, boundary=a["boundary"], L_small=a["L"], L_big=c["L"],
                        D_L_small=a["D_L"], D_L_small_err=a["D_L_err"], D_L_big=c["D_L"],
                        D_L_big_err=c["D_L_err"], shift_small=a["shift"], shift_big=c["shift"],
                        D_inf_small=a["D_inf"], D_inf_big=c["D_inf"], diff=diff, diff_err=err,
                        diff_rel=diff / a["D_inf"], diff_rel_err=err / a["D_inf"],
                        diff_uncorrected=c["D_L"] - a["D_L"],
                        diff_predicted=a["shift"] - c["shift"],
                        n_runs_big=len(big), cases_big=[r["case"] for r in big],
                        sys_small=a["sys"], sys_small_err=a["sys_err"], sys_big=c["sys"],
                        sys_big_err=c["sys_err"], T_big=c["T"], cpu_per_tau_big=c["cpu_per_tau"],
                        cpu_run_big=c["cpu_per_tau"] * c["T"], N_big=c["N"],
                        cpu_5_big=c["cpu_5"], cpu_1_big=c["cpu_1"]))
    return out


def load_all(out_dir, quick):
    suffix = "_quick" if quick else ""
    datas = {}
    for m in MODELS:
        p = os.path.join(out_dir, f"three_solvents{suffix}_{m}.json")
        if os.path.exists(p):
            with open(p) as f:
                datas[m] = json.load(f)
    return datas


def summary_and_plot(out_dir, quick, package=True):
    datas = load_all(out_dir, quick)
    rows = analyse(datas)
    prow = paper_rows(datas, rows)
    speed = probe_speed()
    summary = dict(rows=rows, paper=prow, hasimoto=hasimoto_rows(rows),
                   probe_particle_steps_per_cpu_s=speed,
                   settings=SETTINGS, boundary=BOUNDARY, eta_prior=ETA_PRIOR,
                   eta={m: eta_of(m, d) for m, d in datas.items()},
                   eta_bench={m: d.get("eta", {}).get("eta") for m, d in datas.items()})
    suffix = "_quick" if quick else ""
    with open(os.path.join(out_dir, f"three_solvents{suffix}.json"), "w") as f:
        json.dump(jsonable(summary), f, indent=1)
    log(f"\n{'model':7s} {'meth':4s} {'case':12s} {'eta':>7s} {'D(L)':>9s} {'D(inf)':>9s} "
        f"{'Stokes':>8s} {'sys':>12s} {'CPU/tau':>8s} {'CPU 1%':>9s} {'CPU 5%':>8s}")
    for r in rows:
        log(f"{r['model']:7s} {r['method']:4s} {r['case']:12s} {r['eta']:7.3f} "
            f"{r['D_L']:.5f}({r['D_L_err'] * 1e5:3.0f}) {r['D_inf']:9.5f} {r['D_stokes']:8.5f} "
            f"{100 * r['sys']:+6.1f}+/-{100 * r['sys_err']:4.1f}% {r['cpu_per_tau']:8.4f} "
            f"{r['cpu_1']:9.0f} {r['cpu_5']:8.1f}"
            + (f"  D_rot {r['D_rot']:.5f}({r['D_rot_err'] * 1e5:.0f}) vs {r['D_rot_stokes']:.5f}"
               if "D_rot" in r else ""))
    for r in prow:
        log(f"paper {r['model']:7s} R=3 L=15 N={r['N']} {r['cpu_per_tau']:.4f} CPU-s/tau, "
            f"CPU to 1 % {r['cpu_1']:.0f}, 5 % {r['cpu_5']:.1f} (error extrapolated)")
    print_markdown(summary)
    if not quick and package:
        write_package_data(summary)
    plot(rows, prow, datas, os.path.join(ROOT, "doc", "figures", f"three_solvents{suffix}.png"))


def _pm(x, e, nd=5):
    return f"{x:.{nd}f}({int(round(e * 10 ** nd))})" if e is not None and np.isfinite(e) else f"{x:.{nd}f}"


def print_markdown(summary):
    """The tables of doc/choosing-a-model.md."""
    log("\n| model | method | surface | L | eta | D(L) | D(inf) | Stokes | systematic error | "
        "CPU-s per tau | CPU-s to 5 % | CPU-s to 1 % |")
    log("|---|---|---|---|---|---|---|---|---|---|---|---|")
    for r in summary["rows"]:
        log(f"| {r['model']} | {r['method']} | {r['boundary']} | {r['L']:g} | "
            f"{_pm(r['eta'], r['eta_err'], 3)} | {_pm(r['D_L'], r['D_L_err'])} | {r['D_inf']:.5f} | "
            f"{r['D_stokes']:.5f} | {100 * r['sys']:+.1f} +/- {100 * r['sys_err']:.1f} % | "
            f"{r['cpu_per_tau']:.4f} | {r['cpu_5']:.3g} | {r['cpu_1']:.3g} |")
    log("\n| model | method | D_rot(L) | D_rot(inf) | Stokes 1/(8 pi eta R^3) | systematic error | "
        "CPU-s to 5 % |")
    log("|---|---|---|---|---|---|---|")
    for r in summary["rows"]:
        if "D_rot" in r:
            log(f"| {r['model']} | Green-Kubo | {_pm(r['D_rot'], r['D_rot_err'], 6)} | "
                f"{r['D_rot_inf']:.6f} | {r['D_rot_stokes']:.6f} | {100 * r['sys_rot']:+.0f} +/- "
                f"{100 * r['D_rot_err'] / r['D_rot_stokes']:.0f} % | {r['cpu_rot_5']:.3g} |")
    log("\n| model | surface | L/R = 5: D(L) | shift | D(inf) | L/R = 8: D(L) | shift | D(inf) | "
        "D(inf) difference | D(L) difference | Hasimoto's |")
    log("|---|---|---|---|---|---|---|---|---|---|---|")
    for h in summary["hasimoto"]:
        log(f"| {h['model']} | {h['boundary']} | {_pm(h['D_L_small'], h['D_L_small_err'])} | "
            f"{h['shift_small']:.5f} | {h['D_inf_small']:.5f} | {_pm(h['D_L_big'], h['D_L_big_err'])} | "
            f"{h['shift_big']:.5f} | {h['D_inf_big']:.5f} | {_pm(h['diff'], h['diff_err'])} "
            f"({100 * h['diff_rel']:+.1f} +/- {100 * h['diff_rel_err']:.1f} %) | "
            f"{h['diff_uncorrected']:+.5f} | {h['diff_predicted']:+.5f} |")
    for r in summary["rows"]:
        if r["boundary"] == "partial":
            log(f"\npartial slip: b = {r['b']:.3f} +/- {r['b_err_curve']:.3f} (curve) -> gamma = "
                f"{r['gamma']:.4f} +/- {r['gamma_err']:.4f}; D(L) = {_pm(r['D_L'], r['D_L_err'])}, "
                f"D(inf) = {r['D_inf']:.5f}, Basset {r['D_stokes']:.5f}: {100 * r['sys']:+.1f} +/- "
                f"{100 * r['sys_err']:.1f} % (stat {100 * r['sys_err_stat']:.1f}, eta "
                f"{100 * r['sys_err_eta']:.1f}, calibration {100 * r['sys_err_calibration']:.1f}); "
                f"b from this drag {r.get('b_measured', float('nan')):.3f} +/- "
                f"{r.get('b_measured_err', float('nan')):.3f}")
    log("\n| model | N | dt | CPU-s per tau (measured) | CPU-s to 5 % (extrapolated) | "
        "CPU-s to 1 % (extrapolated) |")
    log("|---|---|---|---|---|---|")
    for r in summary["paper"]:
        log(f"| {r['model']} | {r['N']} | {r['dt']:g} | {r['cpu_per_tau']:.4f} | {r['cpu_5']:.3g} | "
            f"{r['cpu_1']:.3g} |")


def write_package_data(summary):
    """The advisor's table: per model the best D method at R = 2 (drag) and
    GK/rotation, with the probe speed of the machine that measured it."""
    models = {}
    for r in summary["rows"]:
        # the advisor's table is the R = 2, L/R = 5 set of the models' own surfaces;
        # R = 3, L/R = 8 and the calibrated partial-slip marble are in the doc
        if r["R"] != 2.0 or not r["case"].startswith("R2_L10") or r["boundary"] == "partial":
            continue
        m = models.setdefault(r["model"], {"settings": SETTINGS[r["model"]],
                                           "boundary": BOUNDARY[r["model"]],
                                           "eta": summary["eta"][r["model"]]})
        key = r["method"] if r["boundary"] == BOUNDARY[r["model"]] or r["model"] == "core" \
            else r["method"] + "_" + r["boundary"]
        m[key] = {k: r[k] for k in ("R", "L", "T", "N", "dt", "cpu_per_tau", "var_T", "sys",
                                    "sys_err", "D_inf", "D_stokes", "cpu_1", "cpu_5")}
        if "D_rot" in r:
            m[key].update(D_rot=r["D_rot"], D_rot_err=r["D_rot_err"], sys_rot=r["sys_rot"],
                          var_T_rot=(r["D_rot_err"] / r["D_rot_inf"]) ** 2 * r["T"])
    for p in summary["paper"]:
        models[p["model"]]["paper"] = {k: p[k] for k in ("R", "L", "N", "dt", "cpu_per_tau",
                                                         "var_T", "cpu_1", "cpu_5")}
    for m, d in load_all(os.path.join(HERE, "results"), False).items():
        if "eta" in d and m in models:
            e = d["eta"]["eta"]
            models[m]["eta_run"] = {"cpu_s": e["cpu_s"], "T": e["T"], "box": e["box"],
                                    "eta": e["eta"], "eta_err": e["eta_err"]}
    rank = sorted(models, key=lambda m: models[m]["drag"]["cpu_per_tau"])
    pkg = dict(source="bench/three_solvents.py (doc/choosing-a-model.md)",
               ranking_cpu_per_time=rank,
               probe_particle_steps_per_cpu_s=summary["probe_particle_steps_per_cpu_s"],
               kT=KT, models=models)
    path = os.path.join(ROOT, "src", "python", "marble", "data", "three_solvents.json")
    with open(path, "w") as f:
        json.dump(jsonable(pkg), f, indent=1)
    log(f"wrote {path}")


RETIME_T = {"marble": 60.0, "srd": 180.0, "core": 3.0}  # ~1 min in all; 3x shorter runs scattered by ~20 %


def retime_package():
    """Re-measure the CPU cost of the advisor's table with the current code.

    The table's accuracies (var_T, systematic errors) do not depend on the
    code's speed, its CPU costs do: after a change of the pair loop (issue 15's
    SIMD loop, x1.5 for the DPD solvent) or of the cell grid (the second grid
    for colloids, ~3x for the core colloid) the measured CPU per unit time and
    the probe speed stored with it go stale. Each (model, R, L) of the table
    is re-timed over RETIME_T time units (cost_case) next to a new probe; every
    CPU entry of that model at that (R, L) is scaled by new/old CPU per step
    (the entry keeps its own dt),
    the viscosity run's by the factor of the model's drag scene (the same
    solvent). Writes the package table in place, with the factors."""
    import subprocess
    path = os.path.join(ROOT, "src", "python", "marble", "data", "three_solvents.json")
    with open(path) as f:
        t = json.load(f)
    speed = probe_speed()
    old_speed = t["probe_particle_steps_per_cpu_s"]
    factors = {}
    for model, m in t["models"].items():
        for key, e in m.items():
            if not (isinstance(e, dict) and "cpu_per_tau" in e):
                continue
            rl = (e["R"], e["L"])
            if (model, rl) not in factors:
                c = cost_case(model, e["R"], e["L"], RETIME_T[model])
                # per step: the scene's step may have changed (advisor.marble_dt at R > 2)
                factors[(model, rl)] = (c["cpu_per_tau"] * c["dt"]) / (e["cpu_per_tau"] * e["dt"])
                log(f"retime {model} R = {e['R']:g} L = {e['L']:g}: {e['cpu_per_tau']:.4g} -> "
                    f"{c['cpu_per_tau']:.4g} CPU-s per unit time (probe {old_speed:.3g} -> "
                    f"{speed:.3g})")
            f_ = factors[(model, rl)]
            for k in ("cpu_per_tau", "cpu_1", "cpu_5"):
                if k in e:
                    e[k] *= f_
        drag = m.get("drag")
        if "eta_run" in m and drag:
            m["eta_run"]["cpu_s"] *= factors[(model, (drag["R"], drag["L"]))]
    try:
        rev = subprocess.run(["git", "-C", ROOT, "rev-parse", "--short", "HEAD"],
                             capture_output=True, text=True).stdout.strip()
    except OSError:
        rev = ""
    t["probe_particle_steps_per_cpu_s"] = speed
    t["retimed"] = dict(git=rev, date=time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime()),
                        old_probe=old_speed, probe=speed,
                        factors={f"{m} R={rl[0]:g} L={rl[1]:g}": v for (m, rl), v in factors.items()})
    t["ranking_cpu_per_time"] = sorted(t["models"], key=lambda k: t["models"][k]["drag"]["cpu_per_tau"])
    with open(path, "w") as f:
        json.dump(jsonable(t), f, indent=1)
    log(f"wrote {path}")


def plot(rows, prow, datas, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(1, 3, figsize=(15, 5.5))
    colors = {"marble": "C0", "srd": "C1", "core": "C2"}
    for i, r in enumerate(rows):
        mk = "o" if r["method"] == "drag" else "s"
        fill = colors[r["model"]] if r["boundary"] == "stick" else "none"
        ax[0].errorbar(i, 100 * r["sys"], yerr=100 * r["sys_err"], fmt=mk, color=colors[r["model"]],
                       mfc=fill)
        ax[1].semilogy(i, r["cpu_5"], mk, color=colors[r["model"]], mfc=fill)
        ax[1].semilogy(i, r["cpu_1"], mk, color=colors[r["model"]], mfc=fill, alpha=0.4)
    labels = [f"{r['model']} {r['method']} {r['boundary']} R={r['R']:g} L={r['L']:g}" for r in rows]
    for a in ax[:2]:
        a.set_xticks(range(len(rows)))
        a.set_xticklabels(labels, fontsize=7, rotation=90)
    ax[0].axhline(0, color="k", lw=0.5)
    ax[0].set_ylabel("D(inf) / Stokes - 1  [%]")
    ax[0].set_title("systematic error (Hasimoto-corrected)")
    ax[1].set_ylabel("CPU-s to 5 % (solid) and 1 % (faint)")
    ax[1].set_title("statistical cost of D(inf)")
    for m, d in datas.items():
        g = d.get("gk", {}).get("R2_L10")
        if g and g.get("vacf"):
            t = np.array([np.nan if x is None else x for x in g["t_vacf"]], float)
            C = np.array([np.nan if x is None else x for x in g["vacf"]], float) / 3
            ok = (t > 0) & np.isfinite(C)
            ax[2].loglog(t[ok], np.abs(C[ok]), color=colors[m], label=f"{m}: |C_V(t)|")
    ax[2].set_xlabel("t")
    ax[2].set_title("colloid VACF (R = 2, L = 10)")
    ax[2].legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    log(f"wrote {path}")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--model", default=",".join(MODELS))
    ap.add_argument("--part", default="eta,drag,gk,paper,plot")
    ap.add_argument("--quick", action="store_true")
    ap.add_argument("--redo", action="store_true")
    ap.add_argument("--case", default="", help="run only these case keys (comma separated), "
                    "e.g. R2_L16,R2_L10_b1")
    ap.add_argument("--no-package", action="store_true",
                    help="with --part plot: do not rewrite the advisor's package data")
    ap.add_argument("--out", default=os.path.join(HERE, "results"))
    a = ap.parse_args()
    parts = a.part.split(",")
    if parts == ["retime"]:
        retime_package()
        return
    for m in a.model.split(","):
        if m not in MODELS:
            raise ValueError(f"parameter '--model': {m!r} is not one of {MODELS}")
        run_model(m, parts, a.quick, a.redo, a.out, [c for c in a.case.split(",") if c])
    if "plot" in parts:
        summary_and_plot(a.out, a.quick, package=not a.no_package)


if __name__ == "__main__":
    main()
