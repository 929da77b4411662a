"""Diagnosis of the phi = 0.3 excess of stick suspensions in uniform shear
(doc/suspensions.md, section 7j; issue 13).

Runs samples/lees_edwards_suspension.py's scene and measurement unchanged
(``scene()``, ``measure()``: stick colloids, ``solvent_count="bulk"``, no
lubrication, no colloid DPD, velocity Verlet at dt = 0.005, the settings of
section 7h's ``--no-lubrication --no-colloid-dpd`` rows) at other shear rates
and box sizes (optionally with the squeeze lubrication on below a short core gap,
``--lubrication-h-cut``), and optionally splits the shear stress by type pair:

    build/pymarble bench/suspension_shear_diagnosis.py run --phi 0.3 --rate 0.025 \
        --time 2000 --seed 11 [--box 8 8 8] [--split] [--lubrication-h-cut 0.13] --json FILE
    build/pymarble bench/suspension_shear_diagnosis.py table FILES [--eta0 0.3290 0.0030]
    build/pymarble bench/suspension_shear_diagnosis.py split FILES   # the split per scene
    build/pymarble bench/suspension_shear_diagnosis.py check-split

``--split`` records, at every stress sample, the xy stress of the
solvent-solvent pairs, of the colloid-solvent pairs (conservative repulsion,
DPD and stick friction: the colloids' stresslet, sum over pairs of
(r_c - r_b) F_cb) and of the colloid-colloid contact, by evaluating
``pressure_tensor()`` with the colloid-solvent (and then also the
colloid-colloid) kernels deactivated and restoring them at once. The
pressure tensor is a function of the state only, but changing a kernel's
parameters makes the next ``run()`` recompute the forces: that step's DPD and
friction noise is drawn anew (and its friction taken with the current
velocities), once per sample (every 10 steps). The trajectory is then the same
in distribution, not bit for bit (``check-split``: the parts add up to the total
to round-off; the positions differ by ~2e-4 one step after a toggle, ~5e-6 at
kT = 0; the measured kT is unchanged). The kinetic part is split into colloids and
solvent. Each part is reported as a viscosity, -<P_xy>/rate, with blocking
errors; in a continuum the solvent's part over the whole box is exactly eta_0
(the volume integral of a rigid particle's strain rate vanishes) and the
colloids' part is n S_xy / rate, Einstein's 2.5 phi eta_0 for dilute spheres.
"""
import argparse
import json
import math
import os
import sys
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "samples"))
sys.path.insert(0, HERE)

import marble  # noqa: E402
from marble.viscosity import block_average  # noqa: E402
from lees_edwards_suspension import scene, measure  # noqa: E402

COLLOID, SOLVENT = 1, 0  # setup_suspension's default types (checked at run time)
KINDS_CS = ("hat", "dpd", "surface_friction")
KINDS_CC = ("contact", "lubrication", "dpd", "morse")


def _sym_xy(t):
    t = np.asarray(t)
    return 0.5 * (t[0, 1] + t[1, 0])


class SplitRecorder:
    """Wraps ``system.analysis.pressure_tensor`` so that every call made by
    ``measure()`` also records the type-pair split of the xy stress."""

    def __init__(self, s, colloid_type, solvent_type):
        self.s = s
        self.orig = s.analysis.pressure_tensor
        ia = s.non_bonded_inter
        self.cs = [(getattr(ia[colloid_type, solvent_type], k), getattr(ia[colloid_type, solvent_type], k).get_params())
                   for k in KINDS_CS]
        self.cs = [(h, p) for h, p in self.cs if p]
        self.cc = [(getattr(ia[colloid_type, colloid_type], k), getattr(ia[colloid_type, colloid_type], k).get_params())
                   for k in KINDS_CC]
        self.cc = [(h, p) for h, p in self.cc if p]
        parts = s.part.all()
        ids = np.asarray(parts.id)[np.asarray(parts.type) == colloid_type]
        self.col = s.part.by_ids(ids) if len(ids) else None
        self.m_col = np.asarray(self.col.mass, dtype=float) if len(ids) else np.zeros(0)
        self.V = float(np.prod(np.asarray(s.box_l, dtype=float)))
        self.rows = []

    def __call__(self):
        full = self.orig()
        tot = _sym_xy(full["total"] + full["dpd"])
        for h, _ in self.cs:
            h.deactivate()
        try:
            no_cs = self.orig()
            for h, _ in self.cc:
                h.deactivate()
            try:
                ss = self.orig()
            finally:
                for h, p in self.cc:
                    h.set_params(**p)
        finally:
            for h, p in self.cs:
                h.set_params(**p)
        kin_c = 0.0
        if len(self.m_col):
            v = np.asarray(self.col.v)  # the frame of the folded position, as the pressure tensor's
            kin_c = float((self.m_col * v[:, 0] * v[:, 1]).sum() / self.V)
        kin = _sym_xy(full["kinetic"])
        pair = lambda p: _sym_xy(p["non_bonded"] + p["dpd"])  # noqa: E731
        self.rows.append(dict(total=tot, kinetic_colloid=kin_c, kinetic_solvent=kin - kin_c,
                              pair_ss=pair(ss), pair_cc=pair(no_cs) - pair(ss),
                              pair_cs=pair(full) - pair(no_cs)))
        return full

    def result(self, rate):
        out = {}
        for k in self.rows[0]:
            m, e = block_average([r[k] for r in self.rows], min_blocks=8)
            out[k] = (-m / rate, e / rate)
        return out


def run(args):
    t0, w0 = time.process_time(), time.time()
    stick = args.phi > 0
    lub = args.lubrication_h_cut is not None
    s, info = scene(args.phi, args.box, args.dt, seed=args.seed, boundary="stick", shardlow=False,
                    solvent_count="bulk", lubrication=lub, colloid_dpd=False,
                    h_cut=args.lubrication_h_cut if lub else 1.0, lubrication_form=args.lubrication_form)
    rec = None
    if args.split:
        types = set(np.asarray(s.part.all().type).tolist())
        if types != ({COLLOID, SOLVENT} if stick else {SOLVENT}):
            raise ValueError(f"expected particle types {{0, 1}} (solvent 0), got {sorted(types)}")
        rec = SplitRecorder(s, COLLOID, SOLVENT)
        s.analysis.pressure_tensor = rec
    eta, err, slope, slope_err, kt = measure(s, args.rate, args.time)
    row = dict(phi=info.get("phi", 0.0), phi_nominal=args.phi, boundary="stick" if stick else "solvent",
               n_colloids=info.get("n_colloids", 0), box=list(args.box), rate=args.rate, time=args.time,
               dt=args.dt, integrator="vv", seed=args.seed, eta=eta, eta_err=err,
               solvent_count="bulk" if stick else "exact", lubrication=lub if stick else None,
               colloid_dpd=False if stick else None,
               h_cut=(args.lubrication_h_cut if lub else 1.0) if stick else None,
               lubrication_form=args.lubrication_form if (stick and lub) else None,
               n_solvent=len(info["solvent_ids"]) if stick else int(round(3.0 * np.prod(args.box))),
               cpu_s=time.process_time() - t0, wall_s=time.time() - w0, slope=slope, slope_err=slope_err, kT=kt)
    if rec is not None:
        row["split"] = rec.result(args.rate)
    print(json.dumps(row))
    if args.json:
        with open(args.json, "a") as f:
            f.write(json.dumps(row) + "\n")
    return row


def check_split(args):
    """The parts add up to the total, and what the toggles change: the
    positions one step after one toggle, with and without noise."""
    s, _ = scene(0.3, [6.0, 6.0, 6.0], 0.005, seed=3, boundary="stick", shardlow=False,
                 solvent_count="bulk", lubrication=False, colloid_dpd=False, equil=0.5)
    rec = SplitRecorder(s, COLLOID, SOLVENT)
    s.analysis.pressure_tensor = rec
    measure(s, 0.05, 1.0, equil=0.5)
    r = rec.rows[-1]
    parts = r["kinetic_colloid"] + r["kinetic_solvent"] + r["pair_ss"] + r["pair_cc"] + r["pair_cs"]
    print(f"sum of the parts {parts:.12g}, total {r['total']:.12g}")
    del s, rec
    for kT in (0.1, 0.0):
        ends = []
        for toggle in (False, True):
            s, _ = scene(0.3, [6.0, 6.0, 6.0], 0.005, seed=3, boundary="stick", shardlow=False,
                         solvent_count="bulk", lubrication=False, colloid_dpd=False, equil=0.5)
            s.thermostat.set_dpd(kT=kT, seed=3)
            s.integrator.run(10)
            if toggle:
                h = s.non_bonded_inter[COLLOID, SOLVENT].hat
                p = h.get_params()
                h.deactivate()
                h.set_params(**p)
            s.integrator.run(1)
            ends.append(np.asarray(s.part.all().pos).copy())
            del s
        print(f"kT = {kT}: max |position difference| one step after a toggle: "
              f"{float(np.max(np.abs(ends[0] - ends[1]))):.3g}")


def weighted(x, e):
    x, e = np.asarray(x, float), np.asarray(e, float)
    w = 1.0 / e ** 2
    m = float((w * x).sum() / w.sum())
    err = float(1.0 / math.sqrt(w.sum()))
    chi2 = float((w * (x - m) ** 2).sum())
    if len(x) > 1 and chi2 > len(x) - 1:
        err *= math.sqrt(chi2 / (len(x) - 1))
    return m, err, chi2


def kd(phi, phi_m=0.63):
    return (1 - phi / phi_m) ** (-2.5 * phi_m)


def table(files, eta0=0.3290, eta0_err=0.0030):
    """eta_r grouped by (phi, rate, box) over seeds: weighted mean, error scaled
    by sqrt(chi^2/dof) when larger than 1, eta_0's error added; against
    Krieger-Dougherty (phi_m = 0.63) or Batchelor (phi < 0.15)."""
    rows = [json.loads(line) for f in files for line in open(f) if line.strip()]
    groups = {}
    for r in rows:
        if r.get("phi_nominal", 0) != 0 and (r.get("solvent_count") != "bulk" or r.get("colloid_dpd", True) is True or
                                            (r.get("lubrication", True) and r.get("h_cut", 1.0) == 1.0)):
            continue  # only the scenes without the double-counted kernels (or with a short-range lubrication)
        lub = r.get("h_cut") if r.get("lubrication") else None
        key = (r["phi_nominal"], r["rate"], tuple(r["box"]), lub)
        groups.setdefault(key, []).append(r)
    out = []
    for (pn, rate, box, lub), sel in sorted(groups.items(), key=lambda kv: (kv[0][:3], kv[0][3] or 0)):
        phi = sel[0]["phi"]
        m, err, chi2 = weighted([r["eta"] for r in sel], [r["eta_err"] for r in sel])
        d = dict(phi=phi, rate=rate, box=box, lubrication_h_cut=lub, seeds=[r["seed"] for r in sel], eta=m, eta_err=err, chi2=chi2,
                 per_seed=[(r["eta"] / eta0, r["eta_err"] / eta0, r["seed"]) for r in sel],
                 cpu_s=[round(r.get("cpu_s", 0)) for r in sel])
        if "split" in sel[0]:
            d["split"] = {k: weighted([r["split"][k][0] for r in sel if "split" in r],
                                      [r["split"][k][1] for r in sel if "split" in r])[:2]
                          for k in sel[0]["split"] if sel[0]["split"][k][1] > 0}
        if pn > 0:
            er = m / eta0
            d["eta_r"], d["eta_r_err"] = er, er * math.hypot(err / m, eta0_err / eta0)
            th = 1 + 2.5 * phi + 6.2 * phi ** 2 if phi < 0.15 else kd(phi)
            d["theory"], d["deviation"], d["deviation_err"] = th, er / th - 1, d["eta_r_err"] / th
        out.append(d)
    return out


def split_rows(files, eta0=0.3290):
    """Per scene: eta_r and the split's parts in units of eta_0 (value, error),
    with the solvent part (kinetic + ss; error not given: the parts are correlated)."""
    out = []
    for f in files:
        for line in open(f):
            if not line.strip():
                continue
            r = json.loads(line)
            sp = r.get("split")
            if not sp:
                continue
            d = dict(phi=r["phi"], rate=r["rate"], box=r["box"], seed=r["seed"],
                     eta_r=(r["eta"] / eta0, r["eta_err"] / eta0))
            for k, (m, e) in sp.items():
                if k != "total":
                    d[k] = (m / eta0, e / eta0)
            d["solvent_part"] = d["kinetic_solvent"][0] + d["pair_ss"][0]
            out.append(d)
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    sub = ap.add_subparsers(dest="cmd", required=True)
    r = sub.add_parser("run")
    r.add_argument("--phi", type=float, default=0.3)
    r.add_argument("--box", type=float, nargs=3, default=[8.0, 8.0, 8.0])
    r.add_argument("--rate", type=float, default=0.05)
    r.add_argument("--time", type=float, default=2000.0)
    r.add_argument("--dt", type=float, default=0.005)
    r.add_argument("--seed", type=int, default=11)
    r.add_argument("--split", action="store_true", help="record the type-pair split of the shear stress")
    r.add_argument("--lubrication-h-cut", type=float, default=None,
                   help="switch the squeeze lubrication on with this range on the core gap (section 7g: ~0.13); "
                        "default off")
    r.add_argument("--lubrication-form", choices=["plain", "shifted"], default="plain",
                   help="the kernel's form with --lubrication-h-cut (section 7j's check: plain; "
                        "setup_suspension's stick default since 7i: shifted)")
    r.add_argument("--json")
    sub.add_parser("check-split")
    t = sub.add_parser("table")
    t.add_argument("files", nargs="+")
    t.add_argument("--eta0", type=float, nargs=2, default=[0.3290, 0.0030])
    sp = sub.add_parser("split", help="the type-pair split per scene, in units of eta_0")
    sp.add_argument("files", nargs="+")
    sp.add_argument("--eta0", type=float, default=0.3290)
    a = ap.parse_args()
    if a.cmd == "split":
        keys = ("kinetic_solvent", "pair_ss", "kinetic_colloid", "pair_cc", "pair_cs")
        print("phi rate box seed | eta_r | " + " | ".join(keys) + " | solvent part")
        for d in split_rows(a.files, a.eta0):
            print(f"{d['phi']:.4f} {d['rate']} {d['box'][0]:g} {d['seed']} | {d['eta_r'][0]:.3f}({1000 * d['eta_r'][1]:.0f}) | "
                  + " | ".join(f"{d[k][0]:.3f}({1000 * d[k][1]:.0f})" if d[k][1] > 0 else "-" for k in keys)
                  + f" | {d['solvent_part']:.3f}")
        return
    if a.cmd == "run":
        run(a)
    elif a.cmd == "check-split":
        check_split(a)
    else:
        for d in table(a.files, a.eta0[0], a.eta0[1]):
            per = ", ".join(f"{x:.3f}({1000 * e:.0f}) ({sd})" for x, e, sd in d["per_seed"])
            lubs = f" lubrication h_cut {d['lubrication_h_cut']}" if d["lubrication_h_cut"] else ""
            line = (f"phi {d['phi']:.4f} rate {d['rate']} box {'x'.join(f'{b:g}' for b in d['box'])}{lubs}: "
                    f"eta {d['eta']:.4f} +/- {d['eta_err']:.4f} (chi^2 {d['chi2']:.1f}/{len(d['seeds']) - 1})")
            if "eta_r" in d:
                line += (f"; eta_r per seed {per}; eta_r = {d['eta_r']:.3f} +/- {d['eta_r_err']:.3f}; theory "
                         f"{d['theory']:.3f}: {100 * d['deviation']:+.1f} +/- {100 * d['deviation_err']:.1f} %")
            line += f"; CPU-s {d['cpu_s']}"
            print(line)
            if "split" in d:
                for k, (m, e) in d["split"].items():
                    print(f"    {k:16s} {m:+.4f} +/- {e:.4f}  ({m / a.eta0[0]:+.3f} eta_0)")


if __name__ == "__main__":
    main()
