"""Speed of this build against another git ref, interleaved on the same machine.

    build/pymarble bench/compare_builds.py --baseline REF [--rounds 7] [--steps 200]

Builds REF (default: HEAD~1) with the default features in a temporary
directory (a git worktree + its own build), then runs every case below in a
fresh process of each build in turn (A B A B ...), so load from other jobs
hits both alike. Each process sets up one case, relaxes it and times
integrator.run(steps); the figure is particle-steps per CPU-second of that
process (process CPU time: the one-core throughput even on a shared
machine). Reported: the median of the rounds per build and their ratio, and the
range and median of the per-round ratios (each round's two runs are back to
back) with a 68 % bootstrap interval of that median. With --side-by-side the
two builds' processes of a round run at the same time, each pinned to its own
core, the cores swapped every round: on a machine whose speed drifts (a
virtual machine's host) the per-round ratios scatter less (session 17: 0.95-1.13
against 0.84-1.23 in sequence); it also reports the geometric mean of each two
consecutive rounds' ratios (each build once on each core), which cancels a
speed difference between the two cores. Each core's speed is probed before and
after the rounds (bench_common.core_speeds); --pin CORE (or --pin fastest)
runs the interleaved rounds all on one core. Writes bench/results/compare_builds.json.

Cases: the marble paper's DPD solvent (rho = 3, a = 0, gamma = 5, dt = 0.01,
L = 20: 24 000 beads), Groot-Warren water (a = 25, gamma = 4.5), the LJ fluid of
LAMMPS's in.lj (32 000 atoms), and the same paper solvent with one R = 3 marble
colloid (bench/marble_overhead.py's scene: its cost relative to the bare
solvent is the marble overhead). Two more cases, not run unless named in
--cases: shardlow_a0_g5 and shardlow_marble, the paper solvent alone and with
the marble under the Shardlow integrator at dt = 0.04, and fig4: the scene
of the paper's Fig. 4 as samples/marble_diffusion_vs_gamma.py --paper runs it
(Shardlow at dt = 0.06 with 3 RESPA substeps, skin 0.6). For these the rate
is also printed as CPU-s per tau: N / (rate dt).

One more case measures whole runs rather than steps: fig4_run runs each build's
own samples/marble_diffusion_vs_gamma.py (found through the build's
CMakeCache.txt) at the --paper settings for one (gamma = 2, seed 1) run,
shortened to --sample-time tau of equilibrium run (default 2500, half the
paper's) and a fifth of that of drag: set-up, correlators and analysis
included. Its figure is runs per CPU-second (the sample's own cpu_s of the run);
the CPU-s per run are printed as well. Use it with --side-by-side (two runs at
once, one per core): one round takes ~10 minutes on the development machine.
"""
import argparse
import json
import os
import shutil
import statistics
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
CASES = ("dpd_a0_g5", "dpd_a25_g4.5", "lj", "marble")
# not in the default set: the Shardlow integrator at dt = 0.04 (doc/speed-accuracy.md's choice for
# the paper solvent) on the paper solvent alone and with the R = 3 marble (session 11)
SHARDLOW_CASES = ("shardlow_a0_g5", "shardlow_marble", "fig4")
# whole runs of the build's own Fig. 4 sample (session 18)
SAMPLE_CASES = ("fig4_run",)
# fig4: the scene of the paper's Fig. 4 as samples/marble_diffusion_vs_gamma.py --paper runs it
# (colloid_runs.make_system: R = 3 marble, L = 20, gamma = 1, Shardlow dt = 0.06, 3 RESPA substeps,
# skin 0.6; session 15)
N_PARTICLES = {}  # case -> particle count of its last worker
DT = {}  # case -> time step of its last worker


def sample_worker(case, sample, sample_time):
    """Run the build's own Fig. 4 sample (@p sample) in this process for one
    (gamma, seed) at the --paper settings, @p sample_time tau of equilibrium run;
    print its CPU time as JSON."""
    import runpy

    import marble
    out = tempfile.mkdtemp(prefix="marble-fig4-run-")
    try:
        sys.argv = [sample, "--paper", "--integrator", "shardlow", "--eta", "1.273", "--gammas", "2.0",
                    "--seeds", "1", "--time", str(sample_time), "--drag-time", str(sample_time / 5),
                    "--out", out]
        sys.path.insert(0, os.path.dirname(sample))
        runpy.run_path(sample, run_name="__main__")
        with open(os.path.join(out, "marble_diffusion_vs_gamma.json")) as f:
            run = json.load(f)["runs"][0]
    finally:
        shutil.rmtree(out, ignore_errors=True)
    print(json.dumps({"case": case, "rate": 1.0 / run["cpu_s"], "cpu_s": run["cpu_s"], "D_drag": run["D_drag"],
                      "module": os.path.realpath(marble.__file__)}))


def source_dir(launcher):
    """The source tree of the build of @p launcher (its CMakeCache.txt)."""
    cache = os.path.join(os.path.dirname(launcher), "CMakeCache.txt")
    try:
        with open(cache) as f:
            for line in f:
                if line.startswith("CMAKE_HOME_DIRECTORY:"):
                    return line.split("=", 1)[1].strip()
    except OSError:
        pass
    raise SystemExit(f"fig4_run runs the build's own sample: no source directory in {cache}")


def worker(case, steps):
    """Set up @p case with the marble of this process, time it, print JSON."""
    import time

    import numpy as np

    import marble
    rng = np.random.default_rng(7)
    if case == "lj":
        from bench_common import lj_fcc_system
        s = lj_fcc_system(20, rng)
        s.integrator.run(20)
    elif case == "fig4":
        from marble.colloid_runs import make_system
        s, _, _ = make_system(20.0, 3.0, 1.0, 7, integrator="shardlow", warmup=3.0)
    else:
        L = 20.0
        n = int(3 * L ** 3)
        s = marble.System(box_l=[L] * 3)
        shardlow = case.startswith("shardlow_")
        s.time_step = 0.04 if shardlow else 0.01
        s.cell_system.skin = 0.6
        s.part.add(pos=rng.random((n, 3)) * L, v=rng.normal(size=(n, 3)))
        s.thermostat.set_dpd(kT=1.0, seed=7)
        gamma = 4.5 if case == "dpd_a25_g4.5" else 5.0
        s.non_bonded_inter[0, 0].dpd.set_params(weight_function=1, gamma=gamma, k=1.0, r_cut=1.0)
        if case == "dpd_a25_g4.5":
            s.non_bonded_inter[0, 0].hat.set_params(F_max=25.0, cutoff=1.0)
        if shardlow:
            s.integrator.set_shardlow()
        if case in ("marble", "shardlow_marble"):
            from marble.colloids import add_marble
            add_marble(s, pos=[L / 2] * 3, radius=3.0, gamma=5.0)
        s.integrator.run(60)
        s.cell_system.skin = 0.4
        s.integrator.run(20)
    n = len(s.part)
    c0 = time.process_time()
    s.integrator.run(steps)
    print(json.dumps({"case": case, "rate": n * steps / (time.process_time() - c0), "n": n,
                      "dt": s.time_step, "module": os.path.realpath(marble.__file__)}))


def build_ref(ref, where):
    """Worktree of @p ref at @p where/src, built in @p where/build; returns its launcher."""
    src, bld = os.path.join(where, "src"), os.path.join(where, "build")
    subprocess.run(["git", "-C", ROOT, "worktree", "add", "--detach", src, ref], check=True,
                   capture_output=True)
    subprocess.run(["cmake", "-S", src, "-B", bld, "-DCMAKE_BUILD_TYPE=Release",
                    f"-DPython3_EXECUTABLE={sys.executable}",
                    f"-DMARBLE_MYCONFIG={os.path.join(src, 'maintainer/configs/default.hpp')}"],
                   check=True, capture_output=True)
    subprocess.run(["make", "-C", bld, f"-j{os.cpu_count()}"], check=True, capture_output=True)
    return os.path.join(bld, "pymarble")


def current_and_baseline(baseline, baseline_build):
    """(launcher of this process's build, launcher of the baseline, temporary
    directory or None): the baseline is @p baseline_build if given, else the git
    ref @p baseline built in a new temporary directory (remove it with
    remove_ref)."""
    import marble
    current = os.path.normpath(os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(marble.__file__))),
                                            os.pardir, os.pardir, "pymarble"))
    if baseline_build:
        return current, os.path.join(baseline_build, "pymarble"), None
    tmp = tempfile.mkdtemp(prefix="marble-baseline-")
    print(f"building {baseline} in {tmp} ...", flush=True)
    return current, build_ref(baseline, tmp), tmp


def remove_ref(tmp):
    """Remove the worktree and build of current_and_baseline's temporary directory."""
    if tmp:
        subprocess.run(["git", "-C", ROOT, "worktree", "remove", "--force", os.path.join(tmp, "src")],
                       capture_output=True)
        shutil.rmtree(tmp, ignore_errors=True)


def start_case(launcher, case, steps, cpu=None, sample_time=2500.0):
    """A fresh process of @p launcher (a build's pymarble) running @p case,
    pinned to core @p cpu if given (fig4_run: the build's own sample for
    @p sample_time tau).

    The child gets no inherited PYTHONPATH (pymarble appends it to its own, so
    a build without its Python package would silently import this process's
    marble), and the module it imported must lie in the launcher's build."""
    env = {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}
    pin = None if cpu is None else (lambda: os.sched_setaffinity(0, {cpu}))
    extra = []
    if case in SAMPLE_CASES:
        extra = ["--sample", os.path.join(source_dir(launcher), "samples", "marble_diffusion_vs_gamma.py"),
                 "--sample-time", str(sample_time)]
    return subprocess.Popen([launcher, os.path.abspath(__file__), "--worker", case, "--steps", str(steps)] + extra,
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=env,
                            preexec_fn=pin)


def run_case(launcher, case, steps, proc):
    """Rate of @p case from its process @p proc of @p launcher (start_case)."""
    p = proc
    stdout, stderr = p.communicate()
    if p.returncode != 0:
        raise RuntimeError(f"{launcher} failed on case {case} (exit {p.returncode}):\n{stderr[-2000:]}")
    res = json.loads(stdout.strip().splitlines()[-1])
    build = os.path.realpath(os.path.dirname(launcher))
    if not res["module"].startswith(build + os.sep):
        raise RuntimeError(f"{launcher} imported marble from {res['module']}, not from its own build {build}: "
                           "is its Python package built (make marble_python)?")
    N_PARTICLES[case] = res.get("n")
    DT[case] = res.get("dt")
    return res["rate"]


def median_interval(x, n_boot=2000, seed=1):
    """The 16th and 84th percentiles of the bootstrap distribution of median(@p x)."""
    import random
    rng = random.Random(seed)
    meds = sorted(statistics.median(rng.choices(x, k=len(x))) for _ in range(n_boot))
    return meds[int(0.16 * n_boot)], meds[int(0.84 * n_boot)]


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--baseline", default="HEAD~1", help="git ref to compare with (default HEAD~1)")
    ap.add_argument("--baseline-build", help="an existing build dir of the baseline (skips building)")
    ap.add_argument("--rounds", type=int, default=7)
    ap.add_argument("--steps", type=int, default=200)
    ap.add_argument("--cases", default=",".join(CASES),
                    help="comma-separated, from " + ", ".join(CASES + SHARDLOW_CASES))
    ap.add_argument("--pin", default=None, metavar="CORE",
                    help="interleaved rounds (not --side-by-side): run every process pinned to this core, or "
                         "'fastest' for the core the speed probe found fastest (a machine whose cores differ "
                         "then compares both builds on one core)")
    ap.add_argument("--side-by-side", action="store_true",
                    help="run the two builds' processes at the same time, each pinned to its own core "
                         "(the cores swapped every round): drifts of the machine's speed hit both alike")
    ap.add_argument("--out", default=os.path.join(HERE, "results"))
    ap.add_argument("--out-name", default="compare_builds.json", help=argparse.SUPPRESS)
    ap.add_argument("--sample-time", type=float, default=2500.0,
                    help="fig4_run: tau of equilibrium run per run (drag: a fifth of it; default 2500)")
    ap.add_argument("--worker", help=argparse.SUPPRESS)
    ap.add_argument("--sample", help=argparse.SUPPRESS)
    args = ap.parse_args(argv)
    if args.worker:
        if args.worker in SAMPLE_CASES:
            return sample_worker(args.worker, args.sample, args.sample_time)
        return worker(args.worker, args.steps)
    if not args.sample_time > 0:
        raise SystemExit(f"--sample-time must be > 0 tau, got {args.sample_time}")
    if args.pin is not None:  # (checked before the baseline is built)
        if args.side_by_side:
            raise SystemExit("--pin and --side-by-side exclude each other (side by side pins each build itself)")
        allowed = sorted(os.sched_getaffinity(0))
        if args.pin != "fastest" and not (args.pin.isdigit() and int(args.pin) in allowed):
            raise SystemExit(f"--pin must be 'fastest' or one of the cores {allowed}, got {args.pin!r}")
    current, base, tmp = current_and_baseline(args.baseline, args.baseline_build)
    from bench_common import probe_cores
    speeds_before = probe_cores("before")  # with this build: the probe measures the cores, not the builds
    cases = args.cases.split(",")
    pin = None
    if args.pin == "fastest":
        if speeds_before is None:
            raise SystemExit("--pin fastest: the core speeds could not be probed")
        pin = int(max(speeds_before["rates"], key=speeds_before["rates"].get))
    elif args.pin is not None:
        pin = int(args.pin)
    if pin is not None:
        print(f"every process pinned to core {pin}", flush=True)
    samples = {c: {"current": [], "baseline": []} for c in cases}
    try:
        for r in range(args.rounds):
            for c in cases:
                if args.side_by_side:
                    cores = sorted(os.sched_getaffinity(0))
                    if len(cores) < 2:
                        raise SystemExit("--side-by-side needs two cores")
                    pair = (cores[r % 2], cores[(r + 1) % 2])
                    procs = {who: start_case(launcher, c, args.steps, cpu, args.sample_time)
                             for (who, launcher), cpu in zip((("current", current), ("baseline", base)), pair)}
                    for who, launcher in (("current", current), ("baseline", base)):
                        samples[c][who].append(run_case(launcher, c, args.steps, procs[who]))
                    continue
                for who, launcher in (("current", current), ("baseline", base)):
                    samples[c][who].append(run_case(launcher, c, args.steps,
                                                    start_case(launcher, c, args.steps, pin, args.sample_time)))
            print(f"round {r + 1}/{args.rounds}: " + ", ".join(
                f"{c} {samples[c]['current'][-1]:.3g}/{samples[c]['baseline'][-1]:.3g}" for c in cases),
                flush=True)
    finally:
        remove_ref(tmp)
    speeds_after = probe_cores("after")
    out = {"baseline": args.baseline, "rounds": args.rounds, "steps": args.steps,
           "side_by_side": bool(args.side_by_side), "pinned_core": pin, "core_speed_before": speeds_before,
           "core_speed_after": speeds_after, "cases": {}}
    how = "side-by-side" if args.side_by_side else ("interleaved" if pin is None else f"interleaved, core {pin}")
    print(f"\nparticle-steps per CPU-second (fig4_run: runs per CPU-second), median of {args.rounds} {how} rounds")
    print(f"{'case':14s} {'current':>10s} {'baseline':>10s} {'ratio':>7s}  per-round ratios: "
          "min-max, median (68 % bootstrap interval)")
    for c in cases:
        mc, mb = (statistics.median(samples[c][w]) for w in ("current", "baseline"))
        # each round's current/baseline pair ran back to back: its ratio sees the same load
        rr = [a / b for a, b in zip(samples[c]["current"], samples[c]["baseline"])]
        lo, hi = median_interval(rr)
        out["cases"][c] = dict(current=mc, baseline=mb, ratio=mc / mb, samples=samples[c],
                               round_ratios=rr, round_ratio_median=statistics.median(rr),
                               round_ratio_interval=[lo, hi])
        print(f"{c:14s} {mc:10.4g} {mb:10.4g} {mc / mb:7.3f}  {min(rr):.3f}-{max(rr):.3f}, "
              f"{statistics.median(rr):.3f} ({lo:.3f}-{hi:.3f})")
        if args.side_by_side and len(rr) >= 2:
            # rounds 2k and 2k + 1 ran each build once on each core: the
            # geometric mean of their two ratios cancels a speed difference
            # between the cores (which the per-round ratios carry in full)
            sw = [(rr[2 * k] * rr[2 * k + 1]) ** 0.5 for k in range(len(rr) // 2)]
            slo, shi = median_interval(sw)
            out["cases"][c].update(swapped_pair_ratios=sw, swapped_pair_ratio_median=statistics.median(sw),
                                   swapped_pair_ratio_interval=[slo, shi])
            print(f"{'':14s} swapped-core pairs (geometric mean of the two rounds, each build once on each "
                  f"core): {min(sw):.3f}-{max(sw):.3f}, median {statistics.median(sw):.3f} ({slo:.3f}-{shi:.3f})")
        if c in SHARDLOW_CASES:  # N / (rate dt): CPU-seconds per unit of time tau
            tau = {w: N_PARTICLES[c] / (out["cases"][c][w] * DT[c]) for w in ("current", "baseline")}
            out["cases"][c]["cpu_s_per_tau"] = tau
            print(f"{'':14s} CPU-s per tau: {tau['current']:.4f} (current), {tau['baseline']:.4f} (baseline)")
        if c in SAMPLE_CASES:  # the rate is runs per CPU-second: its inverse, CPU-s per run
            per_run = {w: [1.0 / x for x in samples[c][w]] for w in ("current", "baseline")}
            out["cases"][c]["cpu_s_per_run"] = per_run
            out["sample_time"] = args.sample_time
            print(f"{'':14s} CPU-s per run: {statistics.median(per_run['current']):.0f} (current), "
                  f"{statistics.median(per_run['baseline']):.0f} (baseline)")
    if "marble" in cases and "dpd_a0_g5" in cases:
        for w in ("current", "baseline"):
            ov = out["cases"]["dpd_a0_g5"][w] / out["cases"]["marble"][w]
            out[f"marble_overhead_{w}"] = ov
            print(f"marble overhead ({w}): x{ov:.3f} time per particle-step of the bare solvent")
    os.makedirs(args.out, exist_ok=True)
    with open(os.path.join(args.out, args.out_name), "w") as f:
        json.dump(out, f, indent=1)
    return out


if __name__ == "__main__":
    main()
