"""How many pair slots a cluster-pair list would compute for the DPD bench fluid (geometry only).

    /usr/bin/python3 bench/cluster_pair_estimate.py [--L 20] [--seed 1]

Ideal-gas positions at rho = 3 in a periodic box of side L (the paper solvent of
bench/dpd_throughput.py has the same pair statistics within a few per cent), r_c = 1,
Verlet range r_list = r_c + skin. Prints, per particle:

1. GROMACS-style c x c clusters (nbnxm; Pall & Hess, Comput. Phys. Commun. 184, 2641
   (2013)): columns of side (c / rho)^(1/3) in x-y, sorted by z, cut into clusters of c;
   a cluster pair is listed where the bounding boxes are closer than r_list. Lane pairs =
   c^2 per cluster pair (half of it for a cluster with itself), against the pairs within
   r_list (what Marble's Verlet list holds) and within r_c (what the forces need).
2. Marble's half list regrouped by i-clusters of c consecutive rows (the particles sorted
   by cell of side >= r_list, as CellSystem does): entries = distinct partners j per
   cluster, lane slots = c x entries (what a 1 x c cluster select reads).

No timing: doc/benchmarks.md (session 10) has the measured select.
"""
import argparse

import numpy as np
from scipy.spatial import cKDTree


def nbnxm(x, L, rho, c, rlist):
    side = (c / rho) ** (1 / 3)
    nc = int(L // side)
    s = L / nc
    col = (x[:, 0] // s).astype(int) % nc * nc + (x[:, 1] // s).astype(int) % nc
    order = np.lexsort((x[:, 2], col))
    bounds = np.searchsorted(col[order], np.arange(nc * nc + 1))
    clusters = [order[bounds[q] + k:min(bounds[q] + k + c, bounds[q + 1])]
                for q in range(nc * nc) for k in range(0, bounds[q + 1] - bounds[q], c)]
    lo = np.array([x[m].min(0) for m in clusters])
    hi = np.array([x[m].max(0) for m in clusters])
    cen, half = (lo + hi) / 2, (hi - lo) / 2
    reach = rlist + 2 * np.linalg.norm(half, axis=1).max() * 1.01
    cand = cKDTree(cen, boxsize=L).query_pairs(reach, output_type="ndarray")
    d = np.abs(cen[cand[:, 0]] - cen[cand[:, 1]])
    d = np.minimum(d, L - d)
    gap = np.maximum(d - half[cand[:, 0]] - half[cand[:, 1]], 0.)
    n_cp = int(((gap ** 2).sum(1) < rlist ** 2).sum())
    return (n_cp * c * c + len(clusters) * c * c / 2) / len(x)


def row_clusters(x, L, rlist, cs):
    nc = int(L // rlist)
    cell = (x // (L / nc)).astype(int)
    order = np.argsort((cell[:, 0] * nc + cell[:, 1]) * nc + cell[:, 2], kind="stable")
    y = x[order]
    nb = cKDTree(y, boxsize=L).query_ball_point(y, rlist)
    rows = [[j for j in nb[i] if j > i] for i in range(len(y))]
    listed = sum(len(r) for r in rows)
    out = {}
    for c in cs:
        entries = sum(len(set().union(*rows[g:g + c])) for g in range(0, len(y), c))
        out[c] = (entries / len(y), c * entries / len(y))
    return listed / len(y), out


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--L", type=float, default=20.)
    ap.add_argument("--seed", type=int, default=1)
    args = ap.parse_args()
    rho, rc = 3., 1.
    x = np.random.default_rng(args.seed).random((int(rho * args.L ** 3), 3)) * args.L
    tree = cKDTree(x, boxsize=args.L)
    n_rc = len(tree.query_pairs(rc)) / len(x)
    print(f"N = {len(x)}, pairs within r_c per particle: {n_rc:.2f}")
    for rlist in (1.0, 1.2, 1.4):
        n_rl = len(tree.query_pairs(rlist)) / len(x)
        for c in (2, 4):
            lanes = nbnxm(x, args.L, rho, c, rlist)
            print(f"r_list {rlist}: {c}x{c} cluster pairs: {lanes:.1f} lane pairs per particle "
                  f"({lanes / n_rc:.1f}x the pairs within r_c; Verlet list {n_rl:.2f}, {n_rl / n_rc:.2f}x)")
    listed, rc_out = row_clusters(x, args.L, 1.4, (2, 4, 8))
    for c, (e, s) in rc_out.items():
        print(f"half list (r_list 1.4, {listed:.2f} pairs per particle) by i-clusters of {c} rows: "
              f"{e:.2f} entries, {s:.1f} lane slots per particle")


if __name__ == "__main__":
    main()
