"""Cost of a seed-004 suspension step (doc/suspensions.md): CPU time per step of
marble.suspensions.setup_suspension scenes (R = 1, rho = 3, kT = 0.1, gamma = 4.5,
eta0 = 0.3, Shardlow, dt = 1e-3) at several volume fractions and lubrication
cutoffs, against the pure solvent of the same box. Colloid-colloid pairs go
through the main Verlet list (no second cell grid yet), so h_cut enlarges the
solvent's cells: the table shows that cost.

Reference point (reference.md section 7, not comparable one to one): LAMMPS
pair lubricate + pair brownian (implicit solvent) took 1.4 ms CPU per step for
1331 spheres at phi ~ 0.2 on this kind of machine; here the solvent is explicit.

    build/pymarble bench/suspension_cost.py [--box 12] [--steps 200]

Writes bench/results/suspension_cost.json.
"""
import argparse
import json
import os
import time

import marble
import marble.suspensions as sus
from bench_common import HERE, machine_info

parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
parser.add_argument("--box", type=float, default=12.0)
parser.add_argument("--steps", type=int, default=200)
parser.add_argument("--out", default=os.path.join(HERE, "results", "suspension_cost.json"))
args = parser.parse_args()


def timed(phi, h_cut, colloid_dpd=True):
    s = marble.System(box_l=[args.box] * 3)
    s.time_step = 1e-3
    if phi > 0:
        info = sus.setup_suspension(s, phi=phi, radius=1.0, kT=0.1, gamma=4.5, eta=0.3, seed=1,
                                    h_cut=h_cut, colloid_dpd=colloid_dpd)
    else:  # the same solvent without colloids
        info = sus.setup_suspension(s, phi=1e-9, radius=1.0, kT=0.1, gamma=4.5, eta=0.3, seed=1,
                                    positions=[[0.5 * args.box] * 3], h_cut=h_cut)
        s.part.by_ids(info["colloid_ids"]).remove()
        info["n_colloids"] = 0
        s.non_bonded_inter.reset()
        s.non_bonded_inter[0, 0].hat.set_params(F_max=2.5, cutoff=1.0)
        s.non_bonded_inter[0, 0].dpd.set_params(weight_function=1, gamma=4.5, r_cut=1.0)
    s.integrator.set_shardlow()
    s.integrator.run(20)
    t0 = time.process_time()
    s.integrator.run(args.steps)
    dt = (time.process_time() - t0) / args.steps
    row = dict(phi=phi, h_cut=h_cut, colloid_dpd=colloid_dpd, n_colloids=info["n_colloids"],
               n_particles=len(s.part.all()), cpu_ms_per_step=1e3 * dt,
               max_cut=s.cell_system.get_state()["max_cut"])
    print(row)
    return row


rows = [timed(0.0, 0.3)]
for phi in (0.1, 0.2):
    for h_cut, cdpd in ((0.3, False), (1.0, True)):
        rows.append(timed(phi, h_cut, cdpd))
os.makedirs(os.path.dirname(args.out), exist_ok=True)
with open(args.out, "w") as f:
    json.dump(dict(machine=machine_info(), box=args.box, steps=args.steps, rows=rows), f, indent=1)
print("wrote", args.out)
