"""Strong scaling of the domain decomposition: a rho = 3 DPD fluid (the
marble paper's solvent: a = 0, gamma = 5, r_c = 1, kT = 1, dt = 0.01) in
boxes L = 20 and 40 on 1 and 2 MPI ranks.

Run:  build/pymarble bench/mpi_scaling.py [--quick] [--ranks 1 2] [--sizes 40] [--name NAME] [--out DIR]
                                          [--bind-to none|core] [--integrator vv|shardlow|shardlow_marble]
                                          [--shear RATE] [--balance EVERY]

(--integrator shardlow: the same fluid under Shardlow at dt = 0.04, on several
ranks since session 21; shardlow_marble: with the paper's marble colloid (R = 2,
tunable slip, add_marble) at the box centre, on several ranks since session 22.
--shear RATE: Lees-Edwards shear along x across y at that rate (the fluid
only; several ranks since session 23: the node grid splits z alone).
--balance EVERY: every multi-rank launch is run twice, interleaved, plain and
with the automatic load balance by measured work every EVERY steps
(cell_system.set_load_balance(EVERY, by="time", damping=0.5, threshold=0.02),
after a settling run of 4 EVERY steps), reported as "N+balance" (session 27);
--balance-by particles or pairs: by particle counts, or by particles weighted
by 1 + their listed pairs, instead. --crowded: two thirds of
the particles start in the lowest third of the box along x (the split axis),
an inhomogeneous load.
--bind-to: mpiexec's process binding; default none. Session 21 alternated the
two on an idle 2-core machine: E 0.842 unbound, 0.844 bound, doc/parallel.md.)

Every launch (`mpiexec -n N`) builds the fluid, relaxes it and times
integrator.run() in several rounds; launches of the rank counts compared are
interleaved (1 2 1 2 ...) so that load from other processes hits them alike.
Reported per case: median particle-steps per wall-second, and the parallel
efficiency E = t_1 / (N t_N) of the medians. On a shared machine E is only
meaningful when N cores are free: the JSON records the load average before
and after, and (from /proc/stat) the share of the cores that other processes
used while the bench ran and the share the virtual machine's host stole; the
run counts as idle when the others used less than 5 %. Idle is not enough on a
virtual machine whose cores run at different speeds (session 27): each core's
speed is probed before and after the launches (bench_common.core_speeds) and
the summary line gives the largest spread. Two CPU-time
efficiencies are reported as well, which a busy machine disturbs much less
(every rank records its process CPU time and, from `_core.comm_stats()`, the
CPU time it spent inside MPI calls):
  E_cpu  = cpu_1 / sum_r cpu_r: all CPU time, the polling waits included
           (Open MPI polls, so a rank waiting for a descheduled partner
           burns CPU: a lower bound on a busy machine);
  E_work = cpu_1 / sum_r (cpu_r - cpu in MPI calls_r): the work alone (ghost
           updates, ghost pairs, the extra list work): what the scheme
           costs on top of the split work, an upper bound for an idle
           machine, where the waits are short but not zero.
The wall time in MPI calls is reported as the slower rank's share of the
round, and the spread between the ranks (most minus least, per round: the
time one rank waits for the other, an imbalance of work or of memory
speed between them); the JSON holds each rank's time by kind of call
(reductions, neighbour exchanges, alltoallv, other; doc/parallel.md).
Writes bench/results/mpi_scaling.json and .png.
"""
import argparse
import json
import os
import shutil
import statistics
import subprocess
import sys
import tempfile
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))


def time_step(integrator):
    """The bench's dt: Shardlow at 0.04, velocity Verlet at 0.01."""
    return 0.04 if integrator.startswith("shardlow") else 0.01


def worker(L, steps, rounds, out, integrator="vv", shear=0.0, balance=0, balance_by="time", crowded=False):
    import marble
    rng = np.random.default_rng(7)
    n = int(round(3.0 * L**3))
    s = marble.System(box_l=[L, L, L])
    s.time_step = time_step(integrator)
    s.cell_system.skin = 0.4
    pos = rng.random((n, 3)) * L
    if crowded:  # two thirds of the particles in the lowest third along x (the split axis)
        pos[: 2 * n // 3, 0] /= 3.0
    s.part.add(pos=pos, v=rng.normal(size=(n, 3)))
    s.thermostat.set_dpd(kT=1.0, seed=7)
    s.non_bonded_inter[0, 0].dpd.set_params(weight_function=1, gamma=5.0, k=1.0, r_cut=1.0)
    if integrator == "shardlow_marble":
        # the paper's marble (R = 2, tunable slip, WCA wall) at the centre: on
        # the face between the two ranks' domains, so both hold coupling pairs
        from marble.colloids import add_marble
        add_marble(s, pos=[L / 2] * 3, radius=2.0, gamma=5.0)
        n = len(s.part.all().id)
    if integrator.startswith("shardlow"):
        s.integrator.set_shardlow()
    if shear > 0.0:
        import marble.lees_edwards as le
        s.lees_edwards.set_boundary_conditions(shear_direction="x", shear_plane_normal="y",
                                               protocol=le.LinearShear(shear_velocity=shear * L))
    s.integrator.run(30)
    if balance > 0:
        # the automatic balance by measured work (doc/parallel.md "Load balance"):
        # every `balance` steps, half way to the computed planes; a settling run first
        s.cell_system.set_load_balance(balance, by=balance_by, damping=0.5, threshold=0.02)
        s.integrator.run(4 * balance)
    core = s._core
    wall, cpu, comm_cpu, comm_wall, comm_kinds = [], [], [], [], []
    for _ in range(rounds):
        s.analysis.energy()  # a collective call: the ranks start together
        core.reset_comm_stats()
        t0, c0 = time.perf_counter(), time.process_time()
        s.integrator.run(steps)
        s.analysis.energy()
        wall.append(time.perf_counter() - t0)
        cpu.append(time.process_time() - c0)
        st = dict(core.comm_stats())
        comm_cpu.append(st.get("cpu_seconds", 0.0))
        comm_wall.append(st.get("wall_seconds", 0.0))
        # where the wall time in MPI calls went: the reductions' votes or the exchanges
        comm_kinds.append({k: st.get("wall_" + k, 0.0) for k in ("allreduce", "alltoallv", "neighbor", "other")})
    # every rank writes its own record (no collective read needed)
    with open(f"{out}.{marble.mpi_rank()}", "w") as f:
        json.dump(dict(n=n, steps=steps, wall=wall, cpu=cpu, comm_cpu=comm_cpu, comm_wall=comm_wall,
                       comm_kinds=comm_kinds, n_local=len(s.cell_system.local_ids()),
                       domain_cuts=[list(c) for c in s.cell_system.domain_cuts],
                       n_balances=s.cell_system.get_load_balance()["n_balances"],
                       ranks=marble.mpi_size(), node_grid=list(s.cell_system.node_grid)), f)


def cpu_counters():
    """Machine-wide busy and stolen CPU seconds (/proc/stat; None elsewhere), this
    process's CPU seconds with its waited-for children (the mpiexec launches and
    their ranks), and the wall clock."""
    import resource
    own = sum(getattr(resource.getrusage(w), f) for w in (resource.RUSAGE_SELF, resource.RUSAGE_CHILDREN)
              for f in ("ru_utime", "ru_stime"))
    busy = steal = None
    try:
        with open("/proc/stat") as f:
            v = [int(x) for x in f.readline().split()[1:]]
        tick = os.sysconf("SC_CLK_TCK")
        # user nice system idle iowait irq softirq steal ...
        busy = (v[0] + v[1] + v[2] + v[5] + v[6]) / tick
        steal = (v[7] if len(v) > 7 else 0) / tick
    except (OSError, ValueError, IndexError):
        pass
    return dict(busy=busy, steal=steal, own=own, wall=time.time())


def others_share(c0, c1):
    """The CPU time of other processes between two cpu_counters() readings, and
    the time the host stole, as fractions of all cores' wall time (None: no /proc/stat)."""
    if c0["busy"] is None or c1["busy"] is None:
        return None, None
    cap = (c1["wall"] - c0["wall"]) * os.cpu_count()
    others = max(0.0, (c1["busy"] - c0["busy"]) - (c1["own"] - c0["own"]))
    return others / cap, (c1["steal"] - c0["steal"]) / cap


def launch(ranks, L, steps, rounds, bind="none", integrator="vv", shear=0.0, balance=0, balance_by="time",
           crowded=False):
    with tempfile.TemporaryDirectory() as d:
        out = os.path.join(d, "r.json")
        env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1",
                   OMPI_MCA_rmaps_base_oversubscribe="1")
        cmd = [shutil.which("mpiexec"), "-n", str(ranks), "--bind-to", bind, sys.executable,
               os.path.abspath(__file__), "--worker", str(L), str(steps), str(rounds), out,
               "--integrator", integrator, "--shear", str(shear), "--balance", str(balance),
               "--balance-by", balance_by] + (["--crowded"] if crowded else [])
        subprocess.run(cmd, env=env, check=True)
        recs = []
        for r in range(ranks):
            with open(f"{out}.{r}") as f:
                recs.append(json.load(f))
        res = dict(recs[0])
        # per round: CPU seconds summed over the ranks, without the time inside MPI calls
        res["cpu_sum"] = [sum(x["cpu"][k] for x in recs) for k in range(len(res["wall"]))]
        res["work_sum"] = [sum(x["cpu"][k] - x["comm_cpu"][k] for x in recs)
                           for k in range(len(res["wall"]))]
        res["comm_wall_max"] = [max(x["comm_wall"][k] for x in recs) for k in range(len(res["wall"]))]
        # the spread of the ranks' wall time in MPI calls: the time the faster rank
        # waits for the slower one (an imbalance of work or of speed between them)
        res["comm_wall_min"] = [min(x["comm_wall"][k] for x in recs) for k in range(len(res["wall"]))]
        res["comm_kinds_per_rank"] = [x["comm_kinds"] for x in recs]
        res["n_local_per_rank"] = [x["n_local"] for x in recs]
        return res


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--quick", action="store_true", help="L = 10 and 20 only, short rounds")
    p.add_argument("--ranks", type=int, nargs="+", default=[1, 2])
    p.add_argument("--launches", type=int, default=3, help="launches per rank count")
    p.add_argument("--sizes", type=float, nargs="+", help="run only these box sizes (of 20 40; quick: 10 20)")
    p.add_argument("--integrator", default="vv", choices=["vv", "shardlow", "shardlow_marble"],
                   help="velocity Verlet at dt = 0.01 (default), Shardlow at dt = 0.04, or Shardlow with "
                        "the paper's marble (R = 2) at the box centre")
    p.add_argument("--shear", type=float, default=0.0,
                   help="Lees-Edwards shear rate along x across y (default 0: none)")
    p.add_argument("--bind-to", default="none", choices=["none", "core"],
                   help="mpiexec's process binding (default none)")
    p.add_argument("--name", help="output file name (default mpi_scaling or mpi_scaling_quick)")
    p.add_argument("--out", default=os.path.join(HERE, "results"))
    p.add_argument("--balance", type=int, default=0, metavar="EVERY",
                   help="also run every multi-rank launch with the automatic load balance by time every "
                        "EVERY steps (cell_system.set_load_balance), interleaved with the plain launch; "
                        "reports its efficiency as 'N+balance' (default 0: not run)")
    p.add_argument("--balance-by", default="time", choices=["time", "particles", "pairs"],
                   help="what --balance measures (default time)")
    p.add_argument("--crowded", action="store_true",
                   help="start with two thirds of the particles in the lowest third of the box along x "
                        "(an inhomogeneous load; the fluid spreads slowly: a = 0)")
    p.add_argument("--worker", nargs=4, help=argparse.SUPPRESS)
    a = p.parse_args()
    if a.worker:
        worker(float(a.worker[0]), int(a.worker[1]), int(a.worker[2]), a.worker[3], a.integrator, a.shear,
               a.balance, a.balance_by, a.crowded)
        return
    cases = {10.0: 200, 20.0: 40} if a.quick else {20.0: 300, 40.0: 40}
    if a.sizes:
        cases = {L: s for L, s in cases.items() if L in a.sizes}
    rounds = 2 if a.quick else 3
    from bench_common import machine_info, probe_cores
    machine = machine_info()
    machine["core_speed"] = probe_cores("before")
    machine["load_avg_before"] = machine.pop("load_avg")
    counters0 = cpu_counters()
    res = dict(machine=machine,
               fluid=dict(rho=3.0, a=0.0, gamma=5.0, r_cut=1.0, kT=1.0,
                          dt=time_step(a.integrator), skin=0.4),
               launches=a.launches, rounds_per_launch=rounds, bind_to=a.bind_to, integrator=a.integrator, shear=a.shear,
               balance=a.balance, balance_by=a.balance_by, crowded=a.crowded, cases={})
    # the launches compared: (label, ranks, balance every); with --balance
    # each multi-rank launch is also run with the automatic load balance
    variants = [(str(n), n, 0) for n in a.ranks]
    if a.balance > 0:
        variants += [(f"{n}+balance", n, a.balance) for n in a.ranks if n > 1]
    n_of = {v: n for v, n, _ in variants}
    base_v = variants[0][0]
    for L, steps in cases.items():
        samples = {v: [] for v, _, _ in variants}
        cpu_rate = {v: [] for v, _, _ in variants}   # particle-steps per CPU-second (all ranks)
        work_rate = {v: [] for v, _, _ in variants}  # the same without the CPU time in MPI calls
        comm_share = {v: [] for v, _, _ in variants}  # wall time in MPI calls / round wall time
        wait_spread = {v: [] for v, _, _ in variants}  # (most - least of the ranks' MPI wall time) / round wall time
        kinds = {v: [] for v, _, _ in variants}  # per launch: each rank's MPI wall time by kind, per round
        for k in range(a.launches):
            for n, nr, bal in variants:
                r = launch(nr, L, steps, rounds, a.bind_to, a.integrator, a.shear, bal, a.balance_by, a.crowded)
                samples[n] += [r["n"] * r["steps"] / t for t in r["wall"]]
                cpu_rate[n] += [r["n"] * r["steps"] / t for t in r["cpu_sum"]]
                work_rate[n] += [r["n"] * r["steps"] / t for t in r["work_sum"]]
                comm_share[n] += [c / w for c, w in zip(r["comm_wall_max"], r["wall"])]
                wait_spread[n] += [(c - m) / w for c, m, w in zip(r["comm_wall_max"], r["comm_wall_min"], r["wall"])]
                kinds[n].append(r["comm_kinds_per_rank"])
                per_rank = f"{r['n_local_per_rank']} particles per rank, " if bal else ""
                print(f"L={L:g} ranks={n} launch {k}: {per_rank}"
                      f"{statistics.median(samples[n][-rounds:]):.3e} particle-steps/s", flush=True)
        case = dict(L=L, n=int(round(3 * L**3)), steps_per_round=steps)
        base = statistics.median(samples[base_v])
        b0 = samples[base_v]
        for n, nr, _ in variants:
            med = statistics.median(samples[n])
            # spread: the efficiency of each interleaved launch pair (medians of its rounds)
            per_launch = [statistics.median(samples[n][k * rounds:(k + 1) * rounds])
                          / statistics.median(b0[k * rounds:(k + 1) * rounds]) / (nr / n_of[base_v])
                          for k in range(a.launches)]
            c0 = statistics.median(cpu_rate[base_v])
            w0 = statistics.median(work_rate[base_v])
            cpu_per_launch = [statistics.median(cpu_rate[n][k * rounds:(k + 1) * rounds])
                              / statistics.median(cpu_rate[base_v][k * rounds:(k + 1) * rounds])
                              for k in range(a.launches)]
            work_per_launch = [statistics.median(work_rate[n][k * rounds:(k + 1) * rounds])
                               / statistics.median(work_rate[base_v][k * rounds:(k + 1) * rounds])
                               for k in range(a.launches)]
            case[f"ranks{n}"] = dict(median_wall=med, samples_wall=samples[n],
                                     speedup=med / base, efficiency=med / base / (nr / n_of[base_v]),
                                     efficiency_per_launch=per_launch,
                                     samples_cpu_rate=cpu_rate[n], samples_work_rate=work_rate[n],
                                     efficiency_cpu=statistics.median(cpu_rate[n]) / c0,
                                     efficiency_cpu_per_launch=cpu_per_launch,
                                     efficiency_work=statistics.median(work_rate[n]) / w0,
                                     efficiency_work_per_launch=work_per_launch,
                                     comm_wall_share=statistics.median(comm_share[n]),
                                     comm_wall_share_range=[min(comm_share[n]), max(comm_share[n])],
                                     comm_wait_spread=statistics.median(wait_spread[n]),
                                     comm_wait_spread_range=[min(wait_spread[n]), max(wait_spread[n])],
                                     comm_kinds_per_launch=kinds[n])
        res["cases"][f"L{L:g}"] = case
    res["machine"]["load_avg_after"] = os.getloadavg()
    res["machine"]["core_speed_after"] = probe_cores("after")
    # the cores' speeds, before and after: a rank on a slower core makes its
    # partner wait, which no load or steal figure shows (session 27)
    spreads = [c["spread"] for c in (res["machine"]["core_speed"], res["machine"]["core_speed_after"])
               if c is not None]
    others, stolen = others_share(counters0, cpu_counters())
    # the idle test: what other processes used while the bench ran (the load
    # average lags by a minute and counts the bench's own ranks)
    res["machine"]["others_cpu_share"] = others
    res["machine"]["stolen_cpu_share"] = stolen
    os.makedirs(a.out, exist_ok=True)
    name = a.name or ("mpi_scaling_quick" if a.quick else "mpi_scaling")
    with open(os.path.join(a.out, name + ".json"), "w") as f:
        json.dump(res, f, indent=1)
    for key, c in res["cases"].items():
        print(key, " ".join(f"{n} ranks: {c[f'ranks{n}']['median_wall']:.3e}/s "
                            f"(E = {c[f'ranks{n}']['efficiency']:.2f})" for n, _, _ in variants))
    # the one-line summary (issue 15's goal: E >= 0.92 at L = 40 on 2 ranks, idle machine)
    # busy or not: judged from the load before the bench only (the 1-minute
    # load average after it includes the bench's own ranks, up to max(ranks)
    # of them, so an idle run would read as busy); the after value is printed
    # with the bench's ranks subtracted, for information
    la = res["machine"]["load_avg_before"][0], res["machine"]["load_avg_after"][0]
    la_after_others = max(0.0, la[1] - max(a.ranks))
    if others is None:  # no /proc/stat: the load average before the bench decides
        busy, how = la[0] > 0.5, ""
    else:
        busy = others > 0.05
        how = (f"; other processes used {100 * others:.1f} % of the cores during the bench, the host "
               f"stole {100 * stolen:.1f} %")
    summary = []
    for key, c in res["cases"].items():
        for n, _, _ in variants[1:]:
            e = c[f"ranks{n}"]
            summary.append(f"{key} {n} ranks E = {e['efficiency']:.3f} "
                           f"(per launch {min(e['efficiency_per_launch']):.3f}-"
                           f"{max(e['efficiency_per_launch']):.3f}), E_cpu = {e['efficiency_cpu']:.3f} "
                           f"({min(e['efficiency_cpu_per_launch']):.3f}-"
                           f"{max(e['efficiency_cpu_per_launch']):.3f}), E_work = "
                           f"{e['efficiency_work']:.3f} ({min(e['efficiency_work_per_launch']):.3f}-"
                           f"{max(e['efficiency_work_per_launch']):.3f}), time in MPI calls "
                           f"{e['comm_wall_share']:.2f} of the wall time (the ranks differ by "
                           f"{e['comm_wait_spread']:.2f}: one waits for the other)")
    print("EFFICIENCY: " + "; ".join(summary) +
          f"; load average {la[0]:.1f} before, {la[1]:.1f} after ({la_after_others:.1f} without the "
          f"bench's {max(a.ranks)} ranks) on {os.cpu_count()} cores" + how
          + (f"; the cores' speeds differed by up to {100 * max(spreads):.1f} %" if spreads else "")
          + (" (machine busy: not an idle measurement)" if busy else ""))
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        fig, ax = plt.subplots(1, 2, figsize=(9, 3.6))
        keys = list(res["cases"])
        x = np.arange(len(keys))
        w = 0.8 / len(a.ranks)
        for i, n in enumerate(a.ranks):
            ax[0].bar(x + i * w, [res["cases"][k][f"ranks{n}"]["median_wall"] for k in keys], w,
                      label=f"{n} rank(s)")
            ax[1].bar(x + i * w, [res["cases"][k][f"ranks{n}"]["efficiency"] for k in keys], w)
        for axi, lab in zip(ax, ("particle-steps per wall-second", "parallel efficiency")):
            axi.set_xticks(x + w * (len(a.ranks) - 1) / 2, [f"L = {k[1:]}" for k in keys])
            axi.set_ylabel(lab)
        ax[1].axhline(1.0, color="k", lw=0.8)
        ax[0].legend()
        fig.suptitle("rho = 3 DPD fluid, strong scaling (Marble, MPI)")
        fig.tight_layout()
        fig.savefig(os.path.join(a.out, name + ".png"), dpi=110)
    except ImportError:
        pass


if __name__ == "__main__":
    main()
