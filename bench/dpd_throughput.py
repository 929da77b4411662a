"""Throughput of a rho = 3, r_c = 1 DPD fluid, and of a Lennard-Jones fluid
against LAMMPS on the same machine (one core).

Run:  build/pymarble bench/dpd_throughput.py [--quick] [--no-lammps] [--lj-only] [--out DIR]
      build/pymarble bench/dpd_throughput.py --baseline [REF] [--baseline-build DIR] [--rounds N] [--side-by-side | --pin CORE|fastest]

With --baseline the bench instead builds the git ref REF (default: BASELINE_REF,
the last commit before the speed work of issue E) in a temporary directory and
runs it interleaved with this build on the paper's solvent (rho = 3, a = 0,
gamma = 5, dt = 0.01, N = 24 000) and Groot-Warren water (a = 25, gamma = 4.5),
one fresh process per round and build (bench/compare_builds.py does the work);
it prints the CPU-time medians, their ratio, and the issue's goal (>= 2.5x).
Writes bench/results/dpd_throughput_baseline.json.

The LJ fluid is LAMMPS' bench/in.lj (N = 32 000), run by Debian's `lmp` with
`pair_style lj/cut` and, where the OPT package is in, `lj/cut/opt`, in the same
interleaved rounds as Marble (which uses its best skin of 0.3-0.5; LAMMPS keeps
in.lj's neighbor 0.3 bin, every 20 check no); the goals are the issue's
(>= 2x lj/cut, >= 1.3x lj/cut/opt per CPU-second).

Writes bench/results/dpd_throughput.json and .png. Every figure is a median of
>= 3 timed rounds; rounds of the codes compared are interleaved (A B A B ...)
so that load from other processes hits them alike. Throughput is
particle-steps per second of integrator.run() (LAMMPS: its 'Loop time'),
reported per CPU-second (process CPU time; LAMMPS: Loop time x '% CPU use')
and per wall-second: on a machine shared with other jobs the CPU-time figure
is the single-core throughput, on an idle one the two agree.
"""
import argparse
import json
import os
import re
import shutil
import statistics
import subprocess
import sys
import tempfile
import time

import numpy as np

import marble

from bench_common import machine_info, probe_cores

HERE = os.path.dirname(os.path.abspath(__file__))

# The two DPD fluids (reference.md section 1): Groot-Warren water and the
# marble paper's pure-DPD solvent. Both use the standard weight w = 1 - r/r_c.
DPD_CASES = {
    "a25_g4.5": dict(a=25.0, gamma=4.5),
    "a0_g5": dict(a=0.0, gamma=5.0),
}
LAMMPS_DPD_PUBLISHED = 1.0e6  # LAMMPS bench/ DPD figure, atom-steps/s per core


def log(*a):
    print(*a, flush=True)


# --------------------------------------------------------------------------
# Marble set-ups
# --------------------------------------------------------------------------
def make_dpd(L, a, gamma, dt, skin, seed=7):
    rng = np.random.default_rng(seed)
    n = int(round(3.0 * L**3))
    s = marble.System(box_l=[L, L, L])
    s.time_step = 0.01
    s.cell_system.skin = 0.6
    s.part.add(pos=rng.random((n, 3)) * L, v=rng.normal(size=(n, 3)))
    s.thermostat.set_dpd(kT=1.0, seed=seed)
    s.non_bonded_inter[0, 0].dpd.set_params(weight_function=1, gamma=gamma, k=1.0, r_cut=1.0)
    if a > 0:
        s.non_bonded_inter[0, 0].hat.set_params(F_max=a, cutoff=1.0)
    s.integrator.run(60)  # relax the random start at a safe dt and skin
    s.time_step = dt
    s.cell_system.skin = skin
    s.integrator.run(20)
    return s


def fcc_positions(ncell, rho):
    a = (4.0 / rho) ** (1.0 / 3.0)
    basis = np.array([[0, 0, 0], [0.5, 0.5, 0], [0.5, 0, 0.5], [0, 0.5, 0.5]])
    g = np.arange(ncell)
    cells = np.array(np.meshgrid(g, g, g, indexing="ij")).reshape(3, -1).T
    pos = (cells[:, None, :] + basis[None, :, :]).reshape(-1, 3) * a
    return pos, ncell * a


def make_lj(ncell, seed=87287, skin=0.3):
    """LAMMPS bench/in.lj: fcc rho* = 0.8442, T* = 1.44, r_c = 2.5, NVE (LAMMPS:
    skin 0.3 rebuilt every 20 steps; Marble: its own skin, rebuilt when a
    particle has moved half of it)."""
    pos, L = fcc_positions(ncell, 0.8442)
    rng = np.random.default_rng(seed)
    v = rng.normal(size=pos.shape)
    v -= v.mean(axis=0)
    v *= np.sqrt(1.44 * 3 * (len(v) - 1) / len(v) / np.sum(v * v) * len(v))
    s = marble.System(box_l=[L, L, L])
    s.time_step = 0.005
    s.cell_system.skin = skin
    s.part.add(pos=pos, v=v)
    s.non_bonded_inter[0, 0].lennard_jones.set_params(epsilon=1.0, sigma=1.0, cutoff=2.5, shift=0.0)
    s.integrator.run(20)
    return s


def time_marble(s, steps):
    """(wall, cpu) particle-steps/s of integrator.run(steps). The CPU-time
    figure counts only the time this process ran: on a shared, loaded machine
    it is the one-core throughput; on an idle machine both agree."""
    n = len(s.part)
    t0, c0 = time.perf_counter(), time.process_time()
    s.integrator.run(steps)
    t, c = time.perf_counter() - t0, time.process_time() - c0
    return n * steps / t, n * steps / c


# --------------------------------------------------------------------------
# LAMMPS peer
# --------------------------------------------------------------------------
def lammps_exe():
    return shutil.which("lmp") or shutil.which("lmp_serial") or shutil.which("lmp_mpi")


def lammps_styles(exe):
    try:
        out = subprocess.run([exe, "-h"], capture_output=True, text=True, timeout=60).stdout
    except (OSError, subprocess.TimeoutExpired):
        return set()
    m = re.search(r"\* Pair styles:(.*?)\n\* ", out, re.S)
    return set(m.group(1).split()) if m else set()


LJ_IN = """units lj
atom_style atomic
lattice fcc 0.8442
region box block 0 {n} 0 {n} 0 {n}
create_box 1 box
create_atoms 1 box
mass 1 1.0
velocity all create 1.44 87287 loop geom
pair_style {style} 2.5
pair_coeff 1 1 1.0 1.0 2.5
neighbor 0.3 bin
neigh_modify delay 0 every 20 check no
fix 1 all nve
thermo 1000
run {warm}
run {steps}
"""

DPD_IN = """units lj
atom_style atomic
comm_modify vel yes
region box block 0 {L} 0 {L} 0 {L}
create_box 1 box
create_atoms 1 random {n} 4711 box
mass 1 1.0
velocity all create 1.0 8821 loop geom
pair_style dpd 1.0 1.0 34387
pair_coeff 1 1 {a} {gamma} 1.0
neighbor {skin} bin
neigh_modify delay 0 every 1 check yes
timestep {dt}
fix 1 all nve
thermo 1000
run {warm}
run {steps}
"""


def run_lammps(exe, text):
    """(wall, cpu) particle-steps/s of the last 'run' of an input, from its
    'Loop time' line and the '% CPU use' that follows it."""
    with tempfile.TemporaryDirectory() as d:
        path = os.path.join(d, "in.bench")
        with open(path, "w") as f:
            f.write(text)
        env = dict(os.environ, OMP_NUM_THREADS="1")
        screen = os.path.join(d, "screen.txt")
        p = subprocess.run([exe, "-in", path, "-log", "none", "-screen", screen, "-nocite"],
                           capture_output=True, text=True, cwd=d, env=env, timeout=1800)
        text_out = open(screen).read() if os.path.exists(screen) else p.stdout
    loops = re.findall(r"Loop time of ([0-9.eE+-]+) on (\d+) procs for (\d+) steps with (\d+) atoms"
                       r"(?:.*?\n([0-9.]+)% CPU use)?", text_out, re.S)
    if p.returncode != 0 or not loops:
        raise RuntimeError(f"lmp failed (rc {p.returncode}): {text_out[-500:]} {p.stderr[-500:]}")
    t, procs, steps, atoms, cpu_pct = loops[-1]
    rate = int(atoms) * int(steps) / float(t)
    return rate, (rate * 100.0 / float(cpu_pct) if cpu_pct and float(cpu_pct) > 0 else rate)


def philox_cost():
    """ns per pair of the DPD pair noise (bench/philox_cost.cpp): the block
    draw the pair loop uses now (Philox4x32-10 in SIMD lanes) and, for
    comparison, the old Philox4x64-10 draw; None if no C++ compiler is found."""
    cxx = shutil.which("c++") or shutil.which("g++") or shutil.which("clang++")
    if cxx is None:
        return None
    src = os.path.join(HERE, "philox_cost.cpp")
    root = os.path.join(HERE, os.pardir, "src")
    with tempfile.TemporaryDirectory() as d:
        exe = os.path.join(d, "philox_cost")
        p = subprocess.run([cxx, "-O3", "-std=c++20", "-I" + os.path.join(root, "utils", "include"),
                            "-I" + os.path.join(root, "core"), src,
                            os.path.join(root, "core", "forces", "pair_noise.cpp"), "-o", exe],
                           capture_output=True, text=True)
        if p.returncode != 0:
            return None
        out = subprocess.run([exe], capture_output=True, text=True).stdout
    path = re.search(r"pair_loop_path (\w+)", out)
    now = re.search(rf"philox4x32_10_block_{path.group(1)}_ns_per_pair ([0-9.]+)", out) if path else None
    old = re.search(r"philox4x64_10_ns_per_pair ([0-9.]+)", out)
    if not now:
        return None
    return {"ns_per_pair": float(now.group(1)), "path": path.group(1),
            "philox4x64_ns_per_pair": float(old.group(1)) if old else None}


# --------------------------------------------------------------------------
def median_rounds(fns, rounds):
    """Interleave the callables (A B A B ...), each returning (wall, cpu)
    rates; medians and all samples per key."""
    samples = {k: [] for k in fns}
    for _ in range(rounds):
        for k, fn in fns.items():
            samples[k].append(fn())
    return {k: dict(median=statistics.median(c for _, c in v),
                    median_wall=statistics.median(w for w, _ in v),
                    samples_cpu=[c for _, c in v], samples_wall=[w for w, _ in v])
            for k, v in samples.items()}


def tune_skin(case, dt, skins, L, rounds, steps):
    """Median throughput per skin at box L; returns (best skin, table)."""
    systems = {sk: make_dpd(L, case["a"], case["gamma"], dt, sk) for sk in skins}
    res = median_rounds({sk: (lambda s=s: time_marble(s, steps)) for sk, s in systems.items()}, rounds)
    best = max(res, key=lambda sk: res[sk]["median"])
    return best, {str(sk): r["median"] for sk, r in res.items()}


# The last commit of main before the speed work (issue E): --baseline's default.
BASELINE_REF = "6171f5e"
BASELINE_GOAL = 2.5
# Marble's LJ skin in --quick mode (the full run scans 0.3-0.5), and the
# issue's goals per CPU-second against the LAMMPS pair styles
LJ_SKIN = 0.4
LJ_GOALS = {"lj/cut": 2.0, "lj/cut/opt": 1.3}


def run_baseline(args):
    """Interleaved current-vs-REF comparison of the two DPD fluids."""
    import compare_builds
    argv = ["--baseline", args.baseline, "--cases", "dpd_a0_g5,dpd_a25_g4.5",
            "--rounds", str(args.rounds), "--steps", str(args.steps), "--out", args.out,
            "--out-name", "dpd_throughput_baseline.json"]
    if args.baseline_build:
        argv += ["--baseline-build", args.baseline_build]
    if args.side_by_side:
        argv += ["--side-by-side"]
    if args.pin is not None:
        argv += ["--pin", args.pin]
    out = compare_builds.main(argv)
    for c, r in out["cases"].items():
        # side by side: the swapped-core pairs' median (the medians of the
        # rounds mix the two cores' speeds)
        met = r.get("swapped_pair_ratio_median", r["ratio"]) >= BASELINE_GOAL

        sw = (f"; swapped-core pairs x{r['swapped_pair_ratio_median']:.2f}"
              if "swapped_pair_ratio_median" in r else "")
        log(f"{c}: x{r['ratio']:.2f} against {args.baseline} per CPU-second{sw} "
            f"(goal >= {BASELINE_GOAL}: {'met' if met else 'not met'})")
    return 0


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--quick", action="store_true", help="short run: L=20 only, fixed skin, 3 rounds")
    ap.add_argument("--no-lammps", action="store_true", help="do not run LAMMPS")
    ap.add_argument("--lj-only", action="store_true", help="only the LJ fluid against LAMMPS (no DPD part)")
    ap.add_argument("--out", default=os.path.join(HERE, "results"))
    ap.add_argument("--baseline", nargs="?", const=BASELINE_REF, default=None,
                    help=f"compare with a build of this git ref instead (default {BASELINE_REF})")
    ap.add_argument("--baseline-build", help="an existing build dir of the baseline (skips building it)")
    ap.add_argument("--rounds", type=int, default=7, help="rounds of the --baseline comparison")
    ap.add_argument("--steps", type=int, default=200, help="steps per round of the --baseline comparison")
    ap.add_argument("--side-by-side", action="store_true",
                    help="--baseline: each round runs the two builds at the same time, each pinned to its own "
                         "core, the cores swapped every round (compare_builds.py --side-by-side): for a machine "
                         "whose cores differ in speed (the core-speed probe says so)")
    ap.add_argument("--pin", default=None, metavar="CORE",
                    help="--baseline: run every round on this core, or 'fastest' (the core the speed probe "
                         "found fastest): both builds on one core, one at a time")
    args = ap.parse_args()
    if args.baseline is not None:
        return run_baseline(args)
    quick = args.quick
    rounds = 3 if quick else 5
    os.makedirs(args.out, exist_ok=True)
    out = dict(machine=machine_info(), quick=quick, rounds=rounds, dpd={}, skin_scan={}, lj={},
               lammps={})
    log(f"machine: {out['machine']['cpu']}, {out['machine']['cores']} cores, "
        f"load {out['machine']['load_avg'][0]:.2f}")
    out["machine"]["core_speed"] = probe_cores()

    # ---- LAMMPS availability --------------------------------------------
    exe = None if args.no_lammps else lammps_exe()
    dpd_peer = lj_peer = lj_opt_peer = False
    if args.no_lammps:
        log("LAMMPS: skipped (--no-lammps)")
    elif exe is None:
        log("LAMMPS: skipped: no 'lmp' on PATH (Debian: apt-get install -y lammps)")
    else:
        styles = lammps_styles(exe)
        lj_peer = "lj/cut" in styles
        lj_opt_peer = "lj/cut/opt" in styles
        dpd_peer = "dpd" in styles
        out["lammps"] = dict(exe=exe, has_dpd=dpd_peer, has_lj_cut=lj_peer, has_lj_cut_opt=lj_opt_peer)
        if lj_peer and not lj_opt_peer:
            log(f"LAMMPS LJ: no 'pair_style lj/cut/opt' in {exe} (OPT package): lj/cut only")
        if not dpd_peer:
            log(f"LAMMPS DPD: skipped: no DPD-capable lmp on PATH ({exe} has no 'pair_style dpd'; "
                "build LAMMPS with the DPD-BASIC package to compare)")
        if not lj_peer:
            log(f"LAMMPS LJ: skipped: {exe} has no 'pair_style lj/cut'")

    # ---- DPD: skin scan ---------------------------------------------------
    dts = [0.01, 0.04]
    boxes = [] if args.lj_only else [20.0] if quick else [20.0, 40.0]
    skins = {0.01: 0.4, 0.04: 0.5}  # used in --quick mode (the scan's usual winners)
    if not quick and boxes:
        scan = {0.01: [0.2, 0.3, 0.4, 0.5, 0.6], 0.04: [0.3, 0.4, 0.5, 0.6, 0.8]}
        for dt in dts:
            best, table = tune_skin(DPD_CASES["a0_g5"], dt, scan[dt], 20.0, 3, int(40 / dt / 10))
            skins[dt] = best
            out["skin_scan"][str(dt)] = table
            log(f"skin scan (a0_g5, L=20, dt={dt}): " +
                ", ".join(f"{k}: {v:.3g}" for k, v in table.items()) + f" -> skin {best}")

    # ---- DPD throughput ----------------------------------------------------
    for L in boxes:
        n = int(round(3 * L**3))
        steps = {dt: max(10, int(round((1.5e6 if quick else 3e6) / n))) for dt in dts}
        fns, meta = {}, {}
        for name, case in DPD_CASES.items():
            for dt in dts:
                key = f"{name}_dt{dt}_L{int(L)}"
                s = make_dpd(L, case["a"], case["gamma"], dt, skins[dt])
                fns[key] = (lambda s=s, st=steps[dt]: time_marble(s, st))
                meta[key] = dict(case=name, a=case["a"], gamma=case["gamma"], dt=dt, L=L, n=n,
                                 skin=skins[dt], steps_per_round=steps[dt], system=s,
                                 rebuilds0=s.cell_system.get_state()["verlet_rebuilds"])
                if dpd_peer:
                    txt = DPD_IN.format(L=L, n=n, a=case["a"], gamma=case["gamma"], skin=skins[dt],
                                        dt=dt, warm=50, steps=steps[dt])
                    fns["lammps_" + key] = (lambda t=txt: run_lammps(exe, t))
        res = median_rounds(fns, rounds)
        for key, m in meta.items():
            sysm = m.pop("system")
            m["steps_per_rebuild"] = rounds * m["steps_per_round"] / max(
                1, sysm.cell_system.get_state()["verlet_rebuilds"] - m.pop("rebuilds0"))
            m.update(marble=res[key])
            if "lammps_" + key in res:
                m["lammps"] = res["lammps_" + key]
                m["ratio_marble_over_lammps"] = res[key]["median"] / res["lammps_" + key]["median"]
            out["dpd"][key] = m
            extra = (f"  LAMMPS {m['lammps']['median']:.3e}  ratio {m['ratio_marble_over_lammps']:.2f}"
                     if "lammps" in m else "")
            log(f"DPD {key:22s} N={n:6d} skin={m['skin']}: {res[key]['median']:.3e} particle-steps/CPU-s "
                f"(wall {res[key]['median_wall']:.3e}) "
                f"({res[key]['median'] / LAMMPS_DPD_PUBLISHED:.2f}x LAMMPS published 1e6), "
                f"{m['steps_per_rebuild']:.1f} steps/rebuild{extra}")

    # ---- LJ vs LAMMPS ------------------------------------------------------
    ncell = 14 if quick else 20  # 4 ncell^3 atoms: 10976 / 32000
    lj_steps = 50 if quick else 100
    lj_skin = LJ_SKIN
    if not quick:  # Marble's best skin for this fluid (LAMMPS keeps in.lj's 0.3)
        systems = {sk: make_lj(ncell, skin=sk) for sk in (0.3, 0.4, 0.5)}
        res = median_rounds({sk: (lambda s=s: time_marble(s, lj_steps // 2)) for sk, s in systems.items()}, 3)
        lj_skin = max(res, key=lambda sk: res[sk]["median"])
        out["lj_skin_scan"] = {str(sk): r["median"] for sk, r in res.items()}
        log("LJ skin scan: " + ", ".join(f"{k}: {v:.3g}" for k, v in out["lj_skin_scan"].items()) +
            f" -> skin {lj_skin}")
        del systems
    s = make_lj(ncell, skin=lj_skin)
    fns = {"marble": lambda: time_marble(s, lj_steps)}
    peers = {}
    if lj_peer:
        peers["lammps"] = "lj/cut"
    if lj_opt_peer:
        peers["lammps_opt"] = "lj/cut/opt"
    for key, style in peers.items():
        txt = LJ_IN.format(n=ncell, warm=20, steps=lj_steps, style=style)
        fns[key] = (lambda t=txt: run_lammps(exe, t))
    res = median_rounds(fns, rounds)
    out["lj"] = dict(n=len(s.part), steps_per_round=lj_steps, rho=0.8442, T=1.44, r_cut=2.5, skin=lj_skin,
                     lammps_skin=0.3, dt=0.005, **{k: v for k, v in res.items()})
    line = (f"LJ N={len(s.part)} skin {lj_skin}: Marble {res['marble']['median']:.3e} particle-steps/CPU-s "
            f"(wall {res['marble']['median_wall']:.3e}, rounds {min(res['marble']['samples_cpu']):.3e}-"
            f"{max(res['marble']['samples_cpu']):.3e})")
    for key, style in peers.items():
        goal = LJ_GOALS[style]
        ratios = [a / b for a, b in zip(res["marble"]["samples_cpu"], res[key]["samples_cpu"])]
        ratio = res["marble"]["median"] / res[key]["median"]
        out["lj"]["ratio_marble_over_" + key] = ratio
        out["lj"]["ratio_marble_over_" + key + "_wall"] = res["marble"]["median_wall"] / res[key]["median_wall"]
        out["lj"]["ratio_marble_over_" + key + "_rounds"] = [min(ratios), max(ratios)]
        line += (f"\n  LAMMPS {style} {res[key]['median']:.3e} (wall {res[key]['median_wall']:.3e}): "
                 f"Marble/LAMMPS x{ratio:.2f} per CPU-s (per round {min(ratios):.2f}-{max(ratios):.2f}; "
                 f"wall x{out['lj']['ratio_marble_over_' + key + '_wall']:.2f}); goal >= {goal}: "
                 f"{'met' if ratio >= goal else 'not met'}")
    log(line)

    # ---- what limits it: the noise ------------------------------------------
    cost = philox_cost()
    if cost is not None:
        ns = cost["ns_per_pair"]
        pairs = 3.0 * 4.0 / 3.0 * np.pi / 2.0  # pairs within r_c per particle at rho = 3
        ref = out["dpd"].get("a0_g5_dt0.01_L20", {}).get("marble", {}).get("median")
        share = ns * 1e-9 * pairs * ref if ref else None
        out["philox"] = dict(cost, pairs_per_particle=pairs, **{"share_of_step_a0_g5_dt0.01_L20": share})
        log(f"pair noise (Philox4x32-10 block, {cost['path']}): {ns:.2f} ns per pair "
            f"(old Philox4x64-10: {cost['philox4x64_ns_per_pair']:.2f}), {pairs:.2f} pairs per particle"
            + (f" -> {100 * share:.0f} % of the a0_g5 dt=0.01 step" if share else ""))

    jpath = os.path.join(args.out, "dpd_throughput.json")
    with open(jpath, "w") as f:
        json.dump(out, f, indent=1)
    log(f"wrote {jpath}")
    plot(out, os.path.join(args.out, "dpd_throughput.png"))


def plot(out, path):
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        log("matplotlib missing: no PNG (apt-get install -y python3-matplotlib)")
        return
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(12, 4.5), gridspec_kw=dict(width_ratios=[3, 1]))
    keys = list(out["dpd"])
    x = np.arange(len(keys))
    ax1.bar(x, [out["dpd"][k]["marble"]["median"] for k in keys], color="C0", label="Marble")
    lam = [out["dpd"][k].get("lammps", {}).get("median", 0.0) for k in keys]
    if any(lam):
        ax1.bar(x + 0.4, lam, width=0.4, color="C1", label="LAMMPS (this machine)")
    ax1.axhline(LAMMPS_DPD_PUBLISHED, color="C1", ls="--", label="LAMMPS published DPD (1e6)")
    ax1.axhline(3 * LAMMPS_DPD_PUBLISHED, color="k", ls=":", label="goal 3e6")
    ax1.set_xticks(x, [k.replace("_", "\n", 1) for k in keys], fontsize=7)
    ax1.set_ylabel("particle-steps per CPU-second (one core)")
    ax1.set_title("DPD fluid, rho = 3, r_c = 1, w = 1 - r")
    ax1.legend(fontsize=8)
    lj = out["lj"]
    peers = [(k, lbl) for k, lbl in (("lammps", "LAMMPS\nlj/cut"), ("lammps_opt", "LAMMPS\nlj/cut/opt")) if k in lj]
    names = ["Marble"] + [lbl for _, lbl in peers]
    vals = [lj["marble"]["median"]] + [lj[k]["median"] for k, _ in peers]
    ax2.bar(names, vals, color=["C0", "C1", "C2"][: len(vals)])
    ax2.set_title(f"LJ fluid, N = {lj['n']}")
    ax2.set_ylabel("particle-steps per CPU-second")
    fig.suptitle(f"{out['machine']['cpu']} — medians of {out['rounds']} interleaved rounds", fontsize=9)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    log(f"wrote {path}")


if __name__ == "__main__":
    sys.exit(main())
