"""SRD throughput: particle-collision-steps per CPU-second of a pure SRD fluid
(density 5, a0 = 1, tau = dt = 0.1, alpha = 90 deg, grid shift on, kT = 1, no
thermostat), Marble side by side with LAMMPS `fix srd` (Debian package
`lammps`, installed with apt-get if `lmp` is missing), interleaved rounds,
medians; plus the cost of one stick colloid (a = 2) per MD step in Marble
(the extra time of a run with --colloids of them, default 8, per colloid).
Writes bench/results/srd_throughput.json (doc/srd.md quotes it).
With --baseline DIR (a directory holding another build's `marble` package,
e.g. a copy of an older build's build/src/python) the same pure-fluid run of
that build is timed in each round too (its own process), for the gain of this
build measured in the same conditions (median of the per-round ratios).
With --ranks 1 2 it measures instead the wall-clock rate of the same fluid on
1 and 2 MPI ranks (each run its own `mpiexec -n R`, interleaved rounds,
medians; speed-up = median of the per-round ratios) and the CPU time per
particle-collision-step summed over the ranks, in all and outside MPI calls
(MPI polls while it waits, so on a busy machine the total grows with the
load, the part outside MPI much less), written to
bench/results/srd_throughput_ranks.json.

    build/pymarble bench/srd_throughput.py [--sizes 40000 320000] [--rounds 3]
    build/pymarble bench/srd_throughput.py --ranks 1 2 --sizes 320000 --rounds 5
    build/pymarble bench/srd_throughput.py --sizes 320000 --rounds 7 --baseline /tmp/prev/python
    build/pymarble bench/srd_throughput.py --colloid-cost --sizes 40000 --rounds 7 --baseline /tmp/prev/python
"""
import argparse
import json
import os
import re
import shutil
import subprocess
import sys
import tempfile
import time

import numpy as np

import marble
import marble.srd as srd
from bench_common import HERE, machine_info

p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
p.add_argument("--sizes", type=float, nargs="+", default=[4e4, 3.2e5])
p.add_argument("--rounds", type=int, default=3)
p.add_argument("--work", type=float, default=1.5e7, help="particle-steps per timed run")
p.add_argument("--no-lammps", action="store_true")
p.add_argument("--colloids", type=int, default=8,
               help="stick colloids (a = 2) of the colloid run; the cost of one is the extra time / this")
p.add_argument("--ranks", type=int, nargs="+", default=None,
               help="wall-clock scaling over these MPI rank counts instead of the LAMMPS comparison")
p.add_argument("--baseline", default=None,
               help="directory with another build's marble package: timed in every round as well")
p.add_argument("--worker", nargs=2, type=float, default=None, help=argparse.SUPPRESS)
p.add_argument("--cpu-worker", nargs="+", type=float, default=None, help=argparse.SUPPRESS)
p.add_argument("--colloid-cost", action="store_true",
               help="only the cost of one colloid per MD step: a run with --colloids of them and a pure run, "
                    "each its own process, for this build and (with --baseline) the other, interleaved rounds; "
                    "writes bench/results/srd_colloid_cost.json")
args = p.parse_args()


def ensure_lammps():
    if shutil.which("lmp"):
        return True
    try:
        subprocess.run(["apt-get", "install", "-y", "lammps"], check=True,
                       env=dict(os.environ, DEBIAN_FRONTEND="noninteractive"),
                       stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    except (OSError, subprocess.CalledProcessError):
        try:
            subprocess.run(["apt-get", "update"], check=True, stdout=subprocess.DEVNULL)
            subprocess.run(["apt-get", "install", "-y", "lammps"], check=True,
                           env=dict(os.environ, DEBIAN_FRONTEND="noninteractive"),
                           stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        except (OSError, subprocess.CalledProcessError):
            return False
    return shutil.which("lmp") is not None


def marble_rate(N, steps, colloids=0):
    L = round((N / 5) ** (1 / 3))
    s = marble.System(box_l=[L] * 3, time_step=0.1)
    s.cell_system.skin = 0.5
    s.srd = srd.SRDFluid(types=[0], tau=0.1, angle=90, kT=1.0, seed=1)
    srd.add_fluid(s, density=5, type=0, kT=1.0, seed=2)
    if colloids:
        # on a simple cubic lattice (spacing >= 2a + 2 needs L >= 6 k for k^3 colloids)
        k = int(np.ceil(colloids ** (1 / 3) - 1e-9))
        sites = [(i, j, m) for i in range(k) for j in range(k) for m in range(k)][:colloids]
        for site in sites:
            srd.add_colloid(s, pos=[(x + 0.5) * L / k for x in site], radius=2.0, mass=125.0, type=1)
    s.integrator.run(5)
    t0 = time.process_time()
    s.integrator.run(steps)
    cpu = time.process_time() - t0
    return s.srd.n * steps / cpu, cpu / steps


LMP_IN = """units lj
atom_style atomic
atom_modify first empty
region box block 0 {L} 0 {L} 0 {L}
create_box 2 box
create_atoms 1 random {N} 4711 NULL
group empty type 2
mass * 1.0
velocity all create 1.0 593849 loop geom
neighbor 0.3 bin
neigh_modify delay 1 every 1 check no
comm_modify group empty
timestep 0.1
fix 1 all srd 1 NULL 1.0 1.0 49894 shift yes 54979 rescale no
run 5
run {steps}
"""


def lammps_rate(N, steps):
    L = round((N / 5) ** (1 / 3))
    n = int(5 * L ** 3)
    with tempfile.TemporaryDirectory() as d:
        inp = os.path.join(d, "in.srd")
        with open(inp, "w") as f:
            f.write(LMP_IN.format(L=L, N=n, steps=steps))
        out = subprocess.run(["lmp", "-in", inp, "-log", "none"],
                             capture_output=True, text=True, cwd=d,
                             env=dict(os.environ, OMP_NUM_THREADS="1"))
    loops = re.findall(r"Loop time of ([0-9.eE+-]+) on (\d+) procs for (\d+) steps", out.stdout)
    cpu_util = re.findall(r"([0-9.]+)% CPU use", out.stdout)
    if not loops:
        raise RuntimeError("LAMMPS failed:\n" + out.stdout[-2000:] + out.stderr[-2000:])
    t = float(loops[-1][0]) * (float(cpu_util[-1]) / 100 if cpu_util else 1.0)
    return n * steps / t, t / steps


def worker(N, steps):
    """One timed run in this (MPI) process group; rank 0 prints the wall time."""
    L = round((N / 5) ** (1 / 3))
    s = marble.System(box_l=[L] * 3, time_step=0.1)
    s.cell_system.skin = 0.5
    s.srd = srd.SRDFluid(types=[0], tau=0.1, angle=90, kT=1.0, seed=1)
    srd.add_fluid(s, density=5, type=0, kT=1.0, seed=2)
    s.integrator.run(5)
    s._core.reset_comm_stats()
    t0, c0 = time.perf_counter(), time.process_time()
    s.integrator.run(steps)
    wall, cpu = time.perf_counter() - t0, time.process_time() - c0
    mpi_cpu = dict(s._core.comm_stats())["cpu_seconds"]
    n = s.srd.n
    # every rank: its CPU time, and the part inside MPI calls (waits poll: CPU)
    print(f"CPU {marble.mpi_rank()} {cpu!r} {mpi_cpu!r}", flush=True)
    if marble.mpi_rank() == 0:
        print(f"WALL {wall!r} N {n}", flush=True)


def ranks_rate(N, steps, ranks):
    env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1",
               OMPI_MCA_rmaps_base_oversubscribe="1", OMPI_MCA_mpi_yield_when_idle="1",
               OMP_NUM_THREADS="1")
    cmd = ["mpiexec", "-n", str(ranks), sys.executable, os.path.abspath(__file__),
           "--worker", str(N), str(steps)]
    out = subprocess.run(cmd, capture_output=True, text=True, env=env)
    m = re.search(r"WALL ([0-9.eE+-]+) N (\d+)", out.stdout)
    cpus = re.findall(r"CPU (\d+) ([0-9.eE+-]+) ([0-9.eE+-]+)", out.stdout)
    if not m or len(cpus) != ranks:
        raise RuntimeError(" ".join(cmd) + " failed:\n" + out.stdout[-2000:] + out.stderr[-2000:])
    n_ps = int(m.group(2)) * steps
    # wall-clock rate; CPU per particle-step summed over the ranks, and that part outside MPI calls
    cpu = sum(float(c[1]) for c in cpus)
    work = sum(float(c[1]) - float(c[2]) for c in cpus)
    return n_ps / float(m.group(1)), cpu / n_ps, work / n_ps


def baseline_rate(N, steps):
    """The pure-fluid rate of the build in args.baseline (its own process)."""
    env = dict(os.environ, PYTHONPATH=os.path.abspath(args.baseline), OMP_NUM_THREADS="1")
    cmd = [sys.executable, os.path.abspath(__file__), "--cpu-worker", str(N), str(steps)]
    out = subprocess.run(cmd, capture_output=True, text=True, env=env,
                         cwd=os.path.dirname(os.path.abspath(__file__)))
    m = re.search(r"RATE ([0-9.eE+-]+)", out.stdout)
    if not m:
        raise RuntimeError("baseline run failed:\n" + out.stdout[-2000:] + out.stderr[-2000:])
    return float(m.group(1))


if args.cpu_worker:
    ncol = int(args.cpu_worker[2]) if len(args.cpu_worker) > 2 else 0
    rate, per_step = marble_rate(int(args.cpu_worker[0]), int(args.cpu_worker[1]), colloids=ncol)
    print(f"RATE {rate!r} STEP {per_step!r} MODULE {marble.__file__}", flush=True)
    sys.exit(0)


def step_cpu(package, N, steps, colloids):
    """CPU seconds per MD step of the fluid with `colloids` colloids, in its own
    process, with the marble package in `package` (None: this build)."""
    env = dict(os.environ, OMP_NUM_THREADS="1")
    if package:
        env["PYTHONPATH"] = os.path.abspath(package)
    cmd = [sys.executable, os.path.abspath(__file__), "--cpu-worker", str(N), str(steps), str(colloids)]
    out = subprocess.run(cmd, capture_output=True, text=True, env=env,
                         cwd=os.path.dirname(os.path.abspath(__file__)))
    m = re.search(r"STEP ([0-9.eE+-]+) MODULE (\S+)", out.stdout)
    if not m:
        raise RuntimeError("worker run failed:\n" + out.stdout[-2000:] + out.stderr[-2000:])
    if package and not os.path.abspath(m.group(2)).startswith(os.path.abspath(package)):
        raise RuntimeError(f"the worker imported {m.group(2)}, not the package in {package}")
    return float(m.group(1))


if args.colloid_cost:
    builds = [("this", None)] + ([("baseline", args.baseline)] if args.baseline else [])
    res = dict(machine=machine_info(), setup=f"SRD fluid as below, {args.colloids} stick colloids "
               "(a = 2, M = 125, stochastic, pair coupling) on a cubic lattice against none, tau = dt = 0.1; "
               "extra CPU per MD step / number of colloids, each run its own process, interleaved rounds",
               baseline=args.baseline, sizes=[])
    for N in args.sizes:
        N = int(N)
        steps = max(5, int(args.work / N))
        per = {name: [] for name, _ in builds}
        for r in range(args.rounds):
            for name, pkg in builds:
                t_pure = step_cpu(pkg, N, steps, 0)
                t_col = step_cpu(pkg, N, steps, args.colloids)
                per[name].append((t_col - t_pure) / args.colloids)
            print(f"N = {N} round {r}: " + ", ".join(f"{name} {1e3 * per[name][-1]:.4f}" for name in per)
                  + " ms per colloid and step", flush=True)
        row = dict(N=N, steps=steps, n_colloids=args.colloids,
                   **{f"{name}_ms": 1e3 * float(np.median(v)) for name, v in per.items()},
                   **{f"{name}_all_ms": [1e3 * x for x in v] for name, v in per.items()})
        if args.baseline:
            row["ratio_median_of_rounds"] = float(np.median(np.array(per["this"]) / np.array(per["baseline"])))
        res["sizes"].append(row)
        print(f"N = {N}: " + ", ".join(f"{name} {row[name + '_ms']:.4f} ms" for name in per)
              + (f", this/baseline x{row['ratio_median_of_rounds']:.2f} (median of rounds)" if args.baseline else ""),
              flush=True)
    os.makedirs(os.path.join(HERE, "results"), exist_ok=True)
    with open(os.path.join(HERE, "results", "srd_colloid_cost.json"), "w") as f:
        json.dump(res, f, indent=1)
    sys.exit(0)

if args.worker:
    worker(int(args.worker[0]), int(args.worker[1]))
    sys.exit(0)

if args.ranks:
    res = dict(machine=machine_info(), setup="pure SRD fluid as below, wall-clock particle-collision-steps "
               "per second on R MPI ranks (mpiexec), interleaved rounds", sizes=[])
    for N in args.sizes:
        N = int(N)
        steps = max(5, int(2 * args.work / N))
        rates = {r: [] for r in args.ranks}
        cpus = {r: [] for r in args.ranks}
        works = {r: [] for r in args.ranks}
        loads = []
        for _ in range(args.rounds):
            loads.append(os.getloadavg()[0])
            for r in args.ranks:
                rate, cpu, work = ranks_rate(N, steps, r)
                rates[r].append(rate), cpus[r].append(cpu), works[r].append(work)
        r0 = args.ranks[0]
        med = lambda d: {str(r): float(np.median(v)) for r, v in d.items()}
        row = dict(N=int(5 * round((N / 5) ** (1 / 3)) ** 3), steps=steps,
                   rate=med(rates), rate_all={str(r): v for r, v in rates.items()},
                   speedup={str(r): float(np.median(np.array(v) / np.array(rates[r0])))
                            for r, v in rates.items()},
                   cpu_ns_per_particle_step=med({r: 1e9 * np.array(v) for r, v in cpus.items()}),
                   work_ns_per_particle_step=med({r: 1e9 * np.array(v) for r, v in works.items()}),
                   cpu_all={str(r): v for r, v in cpus.items()}, work_all={str(r): v for r, v in works.items()},
                   load_average=loads)
        res["sizes"].append(row)
        print(f"N = {row['N']} (load average {min(loads):.1f}-{max(loads):.1f}): " + ", ".join(
            f"{r} ranks {row['rate'][str(r)]:.3g}/s (x{row['speedup'][str(r)]:.2f}), CPU "
            f"{row['cpu_ns_per_particle_step'][str(r)]:.1f} ns per particle-step summed over ranks "
            f"(outside MPI {row['work_ns_per_particle_step'][str(r)]:.1f})" for r in args.ranks), flush=True)
    os.makedirs(os.path.join(HERE, "results"), exist_ok=True)
    with open(os.path.join(HERE, "results", "srd_throughput_ranks.json"), "w") as f:
        json.dump(res, f, indent=1)
    sys.exit(0)

res = dict(machine=machine_info(), setup="pure SRD fluid, density 5, a0 = 1, tau = dt = 0.1, "
           "alpha = 90 deg (LAMMPS default rotation), grid shift on, no thermostat, 1 core",
           sizes=[], marble=[], lammps=[], colloid=[])
have_lmp = not args.no_lammps and ensure_lammps()
for N in args.sizes:
    N = int(N)
    steps = max(5, int(args.work / N))
    m, lm, mc, bl = [], [], [], []
    for r in range(args.rounds):
        if args.baseline:
            bl.append(baseline_rate(N, steps))
        rate, t_pure = marble_rate(N, steps)
        m.append(rate)
        if have_lmp:
            lm.append(lammps_rate(N, steps)[0])
        # one colloid: extra cost per MD step of args.colloids of them / their number
        # (pure run of this round as reference)
        mc.append((marble_rate(N, steps, colloids=args.colloids)[1] - t_pure) / args.colloids)
    row = dict(N=int(5 * round((N / 5) ** (1 / 3)) ** 3), steps=steps, marble=float(np.median(m)), marble_all=m,
               lammps=float(np.median(lm)) if lm else None, lammps_all=lm,
               colloid_extra_s_per_step=float(np.median(mc)), colloid_extra_all=mc,
               n_colloids=args.colloids)
    if lm:
        row["ratio_per_round"] = [a / b for a, b in zip(m, lm)]
        row["ratio_median_of_rounds"] = float(np.median(row["ratio_per_round"]))
    if bl:
        row["baseline"] = float(np.median(bl))
        row["baseline_all"] = bl
        row["gain_median_of_rounds"] = float(np.median(np.array(m) / np.array(bl)))
    res["sizes"].append(row)
    print(f"N = {N}: Marble {row['marble']:.3g} / CPU-s"
          + (f", LAMMPS {row['lammps']:.3g} / CPU-s (rounds {min(lm):.3g}-{max(lm):.3g}), ratio "
             f"{row['marble'] / row['lammps']:.2f} (median of per-round ratios {row['ratio_median_of_rounds']:.2f}, "
             f"{min(row['ratio_per_round']):.2f}-{max(row['ratio_per_round']):.2f})" if lm else "")
          + (f", baseline {row['baseline']:.3g}, gain x{row['gain_median_of_rounds']:.2f}" if bl else "")
          + f"; one a = 2 colloid: +{1e3 * row['colloid_extra_s_per_step']:.3f} ms/step", flush=True)
os.makedirs(os.path.join(HERE, "results"), exist_ok=True)
with open(os.path.join(HERE, "results", "srd_throughput.json"), "w") as f:
    json.dump(res, f, indent=1)
