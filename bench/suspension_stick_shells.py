"""Who carries the stick friction's shear stress in a sheared stick suspension
(doc/suspensions.md section 7c, "Shared shells"): the scene of
samples/suspension_viscosity.py with boundary="stick", the mass-proportional
reverse Poiseuille force (g = 0.02, flow x, gradient z), and every 0.1 time
units the colloid-bead surface_friction pairs recomputed in numpy (friction
part, shared="full" as set), grouped by the number of colloid shells holding
the bead (1, 2, 3+). For each group: the friction virial -sum (z_c - z_b) F_x
/ V signed by the sign of the reverse Poiseuille shear stress at the colloid,
against the total mean |sigma_xz| = n g L/8; blocking errors.

    ./pymarble bench/suspension_stick_shells.py --phi 0.2 --time 1500
"""
import argparse
import json
import os
import sys

import numpy as np

import marble.suspensions as sus
from marble.viscosity import block_average

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "samples"))
import suspension_viscosity as sample  # noqa: E402

parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
parser.add_argument("--phi", type=float, default=0.2)
parser.add_argument("--time", type=float, default=1500.0, help="sampled time")
parser.add_argument("--flow", type=float, default=120.0, help="time with the force on before sampling")
parser.add_argument("--g", type=float, default=0.02)
parser.add_argument("--seed", type=int, default=11)
parser.add_argument("--seed004-kernels", action="store_true",
                    help="the settings of section 7c (seed 004's colloid DPD, plain lubrication to h_cut = 1, Poisson solvent count) instead of setup_suspension's stick defaults (section 7i)")
parser.add_argument("--json", help="append the result (a JSON line) to this file")
args = parser.parse_args()

box = np.array([7.0, 7.0, 10.0])
V, L, DT = float(np.prod(box)), box[2], 0.01
old = dict(colloid_dpd=True, lubrication_form="plain", h_cut=1.0, solvent_count="poisson")
s, info = sample.scene(args.phi, box, seed=args.seed, boundary="stick", **(old if args.seed004_kernels else {}))
rp = info["stick_shell"]
gam = info["trans_gamma"]
R = info["radius"]
P = s.part.all()
mass = np.asarray(P.mass)
n = len(P) / V
typ = np.asarray(P.type)
ci, bi = np.where(typ == 1)[0], np.where(typ == 0)[0]


def force():
    z = np.mod(P.pos[:, 2], L)
    acc = np.where(z < L / 2, args.g, -args.g) / mass.mean()
    acc -= np.sum(mass * acc) / mass.sum()
    f = np.zeros((len(P), 3))
    f[:, 0] = mass * acc
    P.ext_force = f


def run(t):
    for _ in range(max(1, int(round(t / (5 * DT))))):
        force()
        s.integrator.run(5)


run(args.flow)
series = {1: [], 2: [], 3: []}
counts = []
for _ in range(int(round(args.time / 0.1))):
    run(0.1)
    pos, v, om = np.asarray(P.pos), np.asarray(P.v), np.asarray(P.omega_lab)
    d = pos[ci][:, None, :] - pos[bi][None, :, :]
    d -= box * np.round(d / box)
    r = np.linalg.norm(d, axis=2)
    h = r - R
    inshell = h < rp
    nb = inshell.sum(axis=0)
    I, J = np.nonzero(inshell)
    dd, rr = d[I, J], r[I, J]
    e = dd / rr[:, None]
    w = 1 - np.maximum(h[I, J], 0) / rp
    u = v[ci][I] - v[bi][J] - np.cross(om[ci][I], dd)
    f = -gam * (w * w)[:, None] * u
    f -= np.sum(f * e, axis=1)[:, None] * e
    zc = np.mod(pos[ci][I, 2], L)
    sign = np.sign(np.where(zc < L / 2, -(zc - L / 4), zc - 3 * L / 4))
    st = -dd[:, 2] * f[:, 0] * sign / V
    k = np.minimum(nb[J], 3)
    for c in (1, 2, 3):
        series[c].append((st[k == c].sum(), np.count_nonzero(k == c)))
    counts.append(np.bincount(np.minimum(nb, 3), minlength=4))
ref = n * args.g * L / 8
out = dict(part="shells", phi=info["phi"], seed=args.seed, time=args.time, g=args.g, ref_stress=ref,
           beads_by_shells=np.mean(counts, axis=0).tolist())
for c, a in series.items():
    a = np.array(a, dtype=float)
    m, e = block_average(a[:, 0])
    out[f"shells_{c}"] = dict(share=m / ref, share_err=e / ref, pairs=a[:, 1].mean())
print(json.dumps(out))
if args.json:
    with open(args.json, "a") as fh:
        fh.write(json.dumps(out) + "\n")
