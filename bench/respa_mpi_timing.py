"""Wall time per step of the paper's marble scene (marble.colloid_runs.make_system: L, R = 3,
gamma = 5) under velocity Verlet with RESPA substeps n, on the ranks of mpiexec (issue 15;
doc/speed-accuracy.md, "Several MPI ranks"). One JSON line from rank 0:

    for n in 1 3; do for r in 1 2; do
      mpiexec -n $r build/pymarble bench/respa_mpi_timing.py --dt 0.02 --substeps $n --steps 300 --L 20
    done; done >> respa_mpi.jsonl

Run it on an otherwise idle machine (stop other jobs): the wall time is what is compared.
Two builds side by side (bench/results/respa_mpi_timing_s20.jsonl: OLD a build of the
previous commit in a temporary directory; each line prefixed with "build" and "round"):

    for round in $(seq 17); do for b in OLD build; do for n in 1 3; do for r in 1 2; do
      mpiexec -n $r $b/pymarble bench/respa_mpi_timing.py --substeps $n --steps 600
    done; done; done; done
"""
import argparse
import json
import time

import marble
from marble.colloid_runs import make_system


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--dt", type=float, default=0.02)
    ap.add_argument("--substeps", type=int, default=3)
    ap.add_argument("--steps", type=int, default=300)
    ap.add_argument("--L", type=float, default=20.0)
    ap.add_argument("--seed", type=int, default=1)
    a = ap.parse_args()
    s, _, _ = make_system(a.L, 3.0, 5.0, a.seed, integrator="vv", dt=a.dt, substeps=a.substeps, warmup=1.0)
    s.integrator.run(20)
    t0, c0 = time.perf_counter(), time.process_time()
    s.integrator.run(a.steps)
    wall, cpu = time.perf_counter() - t0, time.process_time() - c0
    if marble.mpi_rank() == 0:
        print(json.dumps(dict(L=a.L, dt=a.dt, substeps=a.substeps, steps=a.steps, ranks=marble.mpi_size(),
                              wall_s=wall, cpu_s_rank0=cpu, ms_per_step=1e3 * wall / a.steps)), flush=True)


if __name__ == "__main__":
    main()
