"""Weak-scaling estimate of the domain decomposition to 64-1024 ranks, from
the halo volume and the message counts measured on 1-4 ranks of this machine
(doc/parallel.md, section "Weak scaling: an estimate").

Run:  build/pymarble bench/mpi_weak_model.py [--quick] [--out DIR]

1. Measure. `mpiexec -n P` (P = 1, 2, 3, 4; oversubscribed: nothing here is
   timed) runs the marble paper's solvent (rho = 3, a = 0, gamma = 5, r_c = 1,
   skin 0.4) and records on every rank: its particles, its ghosts, and its MPI
   traffic over the timed steps (`_core.comm_stats()`: collective calls,
   neighbour exchanges, blocks and bytes sent to other ranks).
2. Check the geometry. The ghost count of every rank is compared with half
   of the shell volume rho [(lx + 2r)(ly + 2r)(lz + 2r) - lx ly lz]
   (r = r_c + skin): the half shell, for other ranks' particles and the
   rank's own periodic images alike - the model used below must reproduce
   the measured ghosts.
3. Measure the compute rate R1 (particle-steps per CPU-second, one rank,
   L = 20, median of rounds).
4. Extrapolate. Per step a rank spends
     t = n/R1 (1 + kappa g/n)                               compute + ghost work
       + c_a2a T_a2a(P) + c_red 2 alpha log2 P              collectives
       + (c_a2a m_a2a + c_nb m + c_var m_var) alpha + B g / beta   point-to-point data
   with n particles and g remote ghosts per rank, c_a2a all-rank alltoallv
   exchanges, c_nb fixed-size neighbour exchanges (ghost updates, force
   returns), c_var variable-size neighbour exchanges (migration and ghost
   set-up at a rebuild, 2 per rebuild) and c_red reductions per step and B
   bytes per remote ghost and step (all measured in 1.), m neighbour
   messages per fixed-size exchange (26 for a full shell, 13 for the half
   shell), m_var = 26 (a variable-size exchange sends one message, maybe
   empty, to each of the 26 neighbours), m_a2a = m (the non-empty blocks of
   an alltoallv). An alltoallv first exchanges its counts with
   MPI_Alltoall: T_a2a = alpha (P - 1) (linear/pairwise, Open MPI's choice
   for mid-size groups) or alpha log2 P (Bruck), both shown.
   kappa (ghost work per ghost, relative to a particle) is fitted to the
   2-rank strong-scaling efficiencies measured with the full shell (0.83 at
   L = 20, 0.86 at L = 40; doc/benchmarks.md).
   Network: alpha = 2 us, beta = 0.5 GB/s per rank (a 200 Gb/s link shared
   by 64 ranks of a node) and 5 GB/s (one rank per link): stated assumptions,
   not measurements. Three schemes are tabulated: the current one
   (half shell; everything point to point with the neighbour ranks, the
   rebuild's migration and ghost set-up included; its counts measured
   here), the previous one (half shell, but an all-rank alltoallv for the
   migration and the ghost set-up at every rebuild: counts measured on
   2026-12-01 with commit 82a6a25, kept in HALF_SHELL_A2A_PER_STEP) and the
   one before (full shell, an alltoallv with its all-rank count exchange
   for every ghost update and force return: counts measured on 2026-11-30
   with commit 65688bb, kept in FULL_SHELL_PER_STEP).
Writes bench/results/mpi_weak_model.json and a table on stdout.
"""
import argparse
import json
import math
import os
import shutil
import statistics
import subprocess
import sys
import tempfile
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
RHO, RCUT, SKIN = 3.0, 1.0, 0.4


def make_fluid(L, seed=7):
    import marble
    rng = np.random.default_rng(seed)
    n = int(round(RHO * L**3))
    s = marble.System(box_l=[L, L, L])
    s.time_step = 0.01
    s.cell_system.skin = SKIN
    s.part.add(pos=rng.random((n, 3)) * L, v=rng.normal(size=(n, 3)))
    s.thermostat.set_dpd(kT=1.0, seed=seed)
    s.non_bonded_inter[0, 0].dpd.set_params(weight_function=1, gamma=5.0, k=1.0, r_cut=RCUT)
    return s


def worker(L, steps, out):
    """One launch: per-rank particles, ghosts and traffic over @p steps steps."""
    import marble
    s = make_fluid(L)
    s.integrator.run(20)
    core = s._core
    rebuilds0 = core.n_rebuilds()
    core.reset_comm_stats()
    s.integrator.run(steps)
    stats = dict(core.comm_stats())
    lo, size = s.cell_system.local_domain()
    rec = dict(rank=marble.mpi_rank(), n_local=len(s.cell_system.local_ids()), n_ghosts=core.n_ghosts(),
               domain=[float(x) for x in size], stats=stats, rebuilds=core.n_rebuilds() - rebuilds0,
               steps=steps, node_grid=list(s.cell_system.node_grid))
    with open(f"{out}.{marble.mpi_rank()}", "w") as f:
        json.dump(rec, f)


def launch(ranks, L, steps):
    with tempfile.TemporaryDirectory() as d:
        out = os.path.join(d, "r")
        env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1",
                   OMPI_MCA_rmaps_base_oversubscribe="1")
        cmd = [shutil.which("mpiexec"), "-n", str(ranks), "--bind-to", "none", sys.executable,
               os.path.abspath(__file__), "--worker", str(L), str(steps), out]
        subprocess.run(cmd, env=env, check=True, stdout=subprocess.DEVNULL)
        recs = []
        for r in range(ranks):
            with open(f"{out}.{r}") as f:
                recs.append(json.load(f))
        return recs


def shell_volume(dom, r):
    """Volume within r of a box of sides dom, outside it (the full ghost shell)."""
    return float(np.prod(np.asarray(dom) + 2 * r) - np.prod(dom))


def ghost_volumes(dom, grid, r):
    """(remote, own) ghost-shell volumes of a domain of sides @p dom in node grid @p grid:
    own = the part displaced only along axes the grid does not split (periodic
    images of the rank's own particles, made with positive shifts only, so half
    of it becomes ghosts); remote = the rest (other ranks' particles)."""
    split = [g > 1 for g in grid]
    inner = np.prod([l for l, sp in zip(dom, split) if sp]) if any(split) else 1.0
    un = [l for l, sp in zip(dom, split) if not sp]
    own = inner * (np.prod(np.asarray(un) + 2 * r) - np.prod(un)) if un else 0.0
    return shell_volume(dom, r) - own, float(own)


def node_grid(P):
    """Marble's factorisation: the node grid of smallest domain surface (ties: split x first)."""
    best = None
    for px in range(1, P + 1):
        if P % px:
            continue
        for py in range(1, P // px + 1):
            if (P // px) % py:
                continue
            pz = P // px // py
            surf = 1 / px * 1 / py + 1 / py * 1 / pz + 1 / px * 1 / pz
            key = (round(surf, 12), -px, -py)
            if best is None or key < best[0]:
                best = (key, (px, py, pz))
    return best[1]


def compute_rate(L, steps, rounds):
    """Particle-steps per CPU-second on one rank (median of rounds)."""
    s = make_fluid(L)
    s.integrator.run(30)
    rates = []
    for _ in range(rounds):
        c0 = time.process_time()
        s.integrator.run(steps)
        rates.append(len(s.part.all().id) * steps / (time.process_time() - c0))
    return statistics.median(rates), rates


# per step and rank with the previous scheme (full shell, every ghost exchange an
# alltoallv), measured by this script on 4 ranks on 2026-11-30 (commit 65688bb)
FULL_SHELL_PER_STEP = dict(alltoallv=2.2, neighbor=0.0, allreduce=3.09, bytes_per_ghost=125.8)
# per step and rank with the half shell but the rebuild's migration and ghost
# set-up as all-rank alltoallv: measured by this script on 4 ranks on
# 2026-12-01 (commit 82a6a25)
HALF_SHELL_A2A_PER_STEP = dict(alltoallv=0.44, neighbor=1.78, neighbor_var=0.0, allreduce=2.31,
                               bytes_per_ghost=125.0)


def model(P, n_per_rank, R1, kappa, per_step, alpha, beta, half_shell=False, bruck=False):
    """Seconds per step of one rank and the weak-scaling efficiency (see the module doc)."""
    l = (n_per_rank / RHO) ** (1 / 3)
    r = RCUT + SKIN
    g_full = RHO * shell_volume([l] * 3, r)
    g1 = g_full / 2  # one rank: half shell of own images
    t1 = n_per_rank / R1 * (1 + kappa * g1 / n_per_rank)
    if P == 1:
        return t1, 1.0, dict(compute=t1, collectives=0.0, data=0.0)
    g = g_full / 2 if half_shell else g_full
    comp = n_per_rank / R1 * (1 + kappa * g / n_per_rank)
    logp = math.log2(P)
    t_a2a = alpha * (logp if bruck else (P - 1))
    coll = per_step["alltoallv"] * t_a2a + per_step["allreduce"] * 2 * alpha * logp
    msgs = 13 if half_shell else 26
    var = per_step.get("neighbor_var", 0.0)  # variable-size: one message to each of 26
    fixed = per_step.get("neighbor", 0.0) - var
    data = ((per_step["alltoallv"] + fixed) * msgs * alpha + var * 26 * alpha
            + per_step["bytes_per_ghost"] * g / beta)
    t = comp + coll + data
    return t, t1 / t, dict(compute=comp, collectives=coll, data=data)


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--quick", action="store_true", help="smaller box, fewer steps (seconds)")
    p.add_argument("--out", default=os.path.join(HERE, "results"))
    p.add_argument("--worker", nargs=3, help=argparse.SUPPRESS)
    a = p.parse_args()
    if a.worker:
        worker(float(a.worker[0]), int(a.worker[1]), a.worker[2])
        return
    import marble
    if shutil.which("mpiexec") is None or "MPI" not in marble.build_options():
        sys.exit("needs mpiexec and an MPI build")
    L, steps = (10.0, 20) if a.quick else (16.0, 100)
    r = RCUT + SKIN
    measured, checks = {}, []
    for P in (1, 2, 3, 4):
        recs = launch(P, L, steps)
        g_remote = g_total = 0.0
        for rec in recs:
            remote, own = ghost_volumes(rec["domain"], rec["node_grid"], r)
            pred = RHO * (remote + own) / 2  # half shell: half of each part
            checks.append(dict(P=P, rank=rec["rank"], ghosts=rec["n_ghosts"], predicted=pred,
                               ratio=rec["n_ghosts"] / pred))
            g_total += rec["n_ghosts"]
            g_remote += RHO * remote / 2 / P
        st = [rec["stats"] for rec in recs]
        nst = steps
        per = dict(alltoallv=statistics.mean(x["alltoallv"] for x in st) / nst,
                   neighbor=statistics.mean(x.get("neighbor", 0) for x in st) / nst,
                   allreduce=statistics.mean(x["allreduce"] for x in st) / nst,
                   other=statistics.mean(x["other"] for x in st) / nst,
                   messages=statistics.mean(x["messages"] for x in st) / nst,
                   bytes=statistics.mean(x["bytes"] for x in st) / nst,
                   rebuilds=recs[0]["rebuilds"] / nst)
        # the variable-size neighbour exchanges: migration and ghost set-up at each
        # rebuild when they do not go through the all-rank alltoallv
        per["neighbor_var"] = 2 * per["rebuilds"] if P > 1 and per["alltoallv"] == 0 else 0.0
        if P > 1:  # bytes per step per remote ghost (other ranks' particles; model count)
            per["bytes_per_ghost"] = per["bytes"] / g_remote
        measured[P] = dict(node_grid=recs[0]["node_grid"], per_step=per, ghosts_mean=g_total / P,
                           n_local_mean=statistics.mean(x["n_local"] for x in recs))
        print(f"P={P} grid={recs[0]['node_grid']}: ghosts/rank {g_total / P:.0f}, per step: "
              + ", ".join(f"{k} {v:.3g}" for k, v in per.items()), flush=True)
    worst = max(abs(c["ratio"] - 1) for c in checks)
    print(f"ghost count vs shell model: worst |measured/predicted - 1| = {worst:.3f}")
    # per-step traffic of the steady state (largest P measured)
    per_step = measured[4]["per_step"]
    R1, rates = compute_rate(10.0 if a.quick else 20.0, 20 if a.quick else 100, 3)
    print(f"compute rate R1 = {R1:.3e} particle-steps per CPU-second (one rank)")
    # kappa from the measured 2-rank strong-scaling efficiencies (doc/benchmarks.md):
    # E = (1 + kappa g1/N) / (1 + kappa g2/(N/2)) with g1 half-shell on 1 rank, g2 full shell
    kappas = []
    for Lb, E in ((20.0, 0.83), (40.0, 0.86)):
        N = RHO * Lb**3
        x1 = RHO * shell_volume([Lb] * 3, r) / 2 / N
        x2 = RHO * shell_volume([Lb / 2, Lb, Lb], r) / (N / 2)
        kappas.append((1 - E) / (E * x2 - x1))
    kappa = statistics.mean(kappas)
    print(f"kappa (ghost work per ghost) = {kappa:.2f} from E(2 ranks) at L = 20, 40 ({kappas})")
    table = []
    for n_per in (24000, 3000):
        for beta in (0.5e9, 5e9):
            for P in (8, 64, 128, 256, 512, 1024):
                row = dict(n_per_rank=n_per, beta=beta, P=P, grid=node_grid(P))
                for name, per, kw in (("full_linear", FULL_SHELL_PER_STEP, {}),
                                      ("full_bruck", FULL_SHELL_PER_STEP, dict(bruck=True)),
                                      ("half_a2a_linear", HALF_SHELL_A2A_PER_STEP, dict(half_shell=True)),
                                      ("half_a2a_bruck", HALF_SHELL_A2A_PER_STEP,
                                       dict(bruck=True, half_shell=True)),
                                      ("neighbour", per_step, dict(half_shell=True))):
                    t, E, parts = model(P, n_per, R1, kappa, per, 2e-6, beta, **kw)
                    row[name] = dict(t_step=t, E=E, **parts)
                table.append(row)
    print("\nweak-scaling efficiency E(P) = t(1)/t(P) (alpha = 2 us)")
    print(f"{'n/rank':>7} {'beta GB/s':>9} {'P':>5}  full shell: linear a2a | Bruck"
          f" | half shell + a2a at rebuilds: linear | Bruck | now: neighbours only")
    for row in table:
        print(f"{row['n_per_rank']:>7} {row['beta'] / 1e9:>9.1f} {row['P']:>5}  "
              f"{row['full_linear']['E']:>22.2f} | {row['full_bruck']['E']:>5.2f} | "
              f"{row['half_a2a_linear']['E']:>36.2f} | {row['half_a2a_bruck']['E']:>5.2f} | "
              f"{row['neighbour']['E']:>20.2f}")
    from bench_common import machine_info
    res = dict(machine=machine_info(), L_measured=L, steps=steps, skin=SKIN, r_cut=RCUT,
               measured={str(k): v for k, v in measured.items()}, ghost_checks=checks,
               ghost_model_worst_rel_error=worst, R1=R1, R1_rounds=rates, kappa=kappa,
               kappa_fits=kappas, alpha=2e-6, full_shell_per_step=FULL_SHELL_PER_STEP,
               half_shell_a2a_per_step=HALF_SHELL_A2A_PER_STEP, table=table)
    os.makedirs(a.out, exist_ok=True)
    name = "mpi_weak_model_quick" if a.quick else "mpi_weak_model"
    with open(os.path.join(a.out, name + ".json"), "w") as f:
        json.dump(res, f, indent=1)


if __name__ == "__main__":
    main()
