"""Wall time per step of the paper's marble scene (marble.colloid_runs.make_system: L, R = 3,
gamma = 5) under velocity Verlet with RESPA substeps n, on the ranks of mpiexec (issue 15;
doc/speed-accuracy.md, "Several MPI ranks"). One JSON line from rank 0:

    for n in 1 3; do for r in 1 2; do
      mpiexec -n $r build/pymarble bench/respa_mpi_timing.py --dt 0.02 --substeps $n --steps 300 --L 20
    done; done >> respa_mpi.jsonl

Against another git ref, interleaved on the same machine (run it on an otherwise idle machine:
the wall time is what is compared):

    build/pymarble bench/respa_mpi_timing.py --baseline REF [--baseline-build DIR] [--rounds 12]

builds REF (as bench/compare_builds.py does: a git worktree and its own build in a temporary
directory; --baseline-build takes an existing build instead) and runs, in every round, the same
8 launches with each build in turn: substeps 1 and 3 (--substeps-list), on 1 and 2 ranks
(--ranks-list). This script drives both builds (each launch imports the build's own marble).
Prints, per substep count and rank count, the median ms per step of each build and the median
of the per-round ratios baseline / current (> 1: the current build is faster) with a 68 %
bootstrap interval, and each build's 2-rank efficiency (t_1 / (2 t_2), medians). Every launch's
line goes to bench/results/respa_mpi_timing_baseline.jsonl (--out-name), prefixed with "build"
and "round"; the summary to the same name with .json.
"""
import argparse
import json
import os
import shutil
import statistics
import subprocess
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)


def measure(a):
    import marble
    from marble.colloid_runs import make_system
    s, _, _ = make_system(a.L, 3.0, 5.0, a.seed, integrator="vv", dt=a.dt, substeps=a.substeps, warmup=1.0)
    s.integrator.run(20)
    t0, c0 = time.perf_counter(), time.process_time()
    s.integrator.run(a.steps)
    wall, cpu = time.perf_counter() - t0, time.process_time() - c0
    if marble.mpi_rank() == 0:
        print(json.dumps(dict(L=a.L, dt=a.dt, substeps=a.substeps, steps=a.steps, ranks=marble.mpi_size(),
                              wall_s=wall, cpu_s_rank0=cpu, ms_per_step=1e3 * wall / a.steps,
                              module=os.path.realpath(marble.__file__))), flush=True)


def launch(launcher, ranks, substeps, a):
    """One mpiexec launch of this script's measurement with the build of @p launcher."""
    env = {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}
    env.update(OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1",
               OMPI_MCA_rmaps_base_oversubscribe="1")
    mpiexec = shutil.which("mpiexec")
    if mpiexec is None:
        raise SystemExit("--baseline needs mpiexec on the PATH")
    cmd = [mpiexec, "-n", str(ranks), launcher, os.path.abspath(__file__), "--dt", str(a.dt),
           "--substeps", str(substeps), "--steps", str(a.steps), "--L", str(a.L), "--seed", str(a.seed)]
    p = subprocess.run(cmd, env=env, capture_output=True, text=True)
    if p.returncode != 0:
        raise RuntimeError(f"{' '.join(cmd)} failed (exit {p.returncode}):\n{p.stderr[-2000:]}")
    res = json.loads(p.stdout.strip().splitlines()[-1])
    build = os.path.realpath(os.path.dirname(launcher))
    if not res["module"].startswith(build + os.sep):
        raise RuntimeError(f"{launcher} imported marble from {res['module']}, not from its own build {build}")
    return res


def compare(a):
    from compare_builds import current_and_baseline, median_interval, remove_ref
    current, base, tmp = current_and_baseline(a.baseline, a.baseline_build)
    builds = (("baseline", base), ("current", current))
    configs = [(n, r) for n in a.substeps_list for r in a.ranks_list]
    t = {w: {c: [] for c in configs} for w, _ in builds}
    os.makedirs(a.out, exist_ok=True)
    lines = os.path.join(a.out, a.out_name + ".jsonl")
    try:
        with open(lines, "w") as log:
            for k in range(a.rounds):
                for who, launcher in builds:
                    for n, r in configs:
                        res = launch(launcher, r, n, a)
                        t[who][(n, r)].append(res["ms_per_step"])
                        log.write(json.dumps(dict(build=who, round=k, **res)) + "\n")
                        log.flush()
                print(f"round {k + 1}/{a.rounds}: " + ", ".join(
                    f"n={n} r={r} {t['baseline'][(n, r)][-1]:.1f}/{t['current'][(n, r)][-1]:.1f} ms"
                    for n, r in configs), flush=True)
    finally:
        remove_ref(tmp)
    out = dict(baseline=a.baseline, rounds=a.rounds, L=a.L, dt=a.dt, steps=a.steps, configs={})
    print(f"\nms per step, median of {a.rounds} interleaved rounds; ratio = baseline / current "
          "(per round, median and 68 % bootstrap interval)")
    print(f"{'substeps':>8s} {'ranks':>5s} {'baseline':>9s} {'current':>9s}  ratio")
    for n, r in configs:
        mb, mc = statistics.median(t["baseline"][(n, r)]), statistics.median(t["current"][(n, r)])
        rr = [b / c for b, c in zip(t["baseline"][(n, r)], t["current"][(n, r)])]
        lo, hi = median_interval(rr)
        out["configs"][f"substeps{n}_ranks{r}"] = dict(baseline=mb, current=mc, samples=
                                                       {w: t[w][(n, r)] for w, _ in builds},
                                                       round_ratios=rr, ratio=statistics.median(rr),
                                                       ratio_interval=[lo, hi])
        print(f"{n:8d} {r:5d} {mb:9.2f} {mc:9.2f}  {statistics.median(rr):.3f} ({lo:.3f}-{hi:.3f}), "
              f"rounds {min(rr):.3f}-{max(rr):.3f}")
    if 1 in a.ranks_list:
        for n in a.substeps_list:
            for r in a.ranks_list:
                if r == 1:
                    continue
                eff = {w: statistics.median(t[w][(n, 1)]) / (r * statistics.median(t[w][(n, r)]))
                       for w, _ in builds}
                out["configs"][f"substeps{n}_ranks{r}"]["efficiency"] = eff
                print(f"substeps {n}: {r}-rank efficiency {eff['baseline']:.2f} (baseline) -> "
                      f"{eff['current']:.2f} (current)")
    with open(os.path.join(a.out, a.out_name + ".json"), "w") as f:
        json.dump(out, f, indent=1)
    return out


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--dt", type=float, default=0.02)
    ap.add_argument("--substeps", type=int, default=3)
    ap.add_argument("--steps", type=int, default=300)
    ap.add_argument("--L", type=float, default=20.0)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--baseline", help="git ref to compare with, interleaved (see above)")
    ap.add_argument("--baseline-build", help="an existing build dir of the baseline (skips building it)")
    ap.add_argument("--rounds", type=int, default=12, help="rounds of the --baseline comparison")
    ap.add_argument("--substeps-list", type=int, nargs="+", default=[1, 3])
    ap.add_argument("--ranks-list", type=int, nargs="+", default=[1, 2])
    ap.add_argument("--out", default=os.path.join(HERE, "results"))
    ap.add_argument("--out-name", default="respa_mpi_timing_baseline")
    a = ap.parse_args(argv)
    for name in ("dt", "L"):
        if not getattr(a, name) > 0:
            raise SystemExit(f"--{name} must be > 0, got {getattr(a, name)}")
    for name in ("steps", "rounds"):
        if getattr(a, name) < 1:
            raise SystemExit(f"--{name} must be >= 1, got {getattr(a, name)}")
    if a.baseline or a.baseline_build:
        a.baseline = a.baseline or "(given build)"
        return compare(a)
    return measure(a)


if __name__ == "__main__":
    main()
