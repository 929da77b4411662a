"""Diagnosis of the phi = 0.3 excess of stick suspensions in uniform shear
(doc/suspensions.md, section 7j; issue 13).

Runs samples/lees_edwards_suspension.py's scene and measurement unchanged
(``scene()``, ``measure()``: stick colloids, ``solvent_count="bulk"``, no
lubrication, no colloid DPD, velocity Verlet at dt = 0.005, the settings of
section 7h's ``--no-lubrication --no-colloid-dpd`` rows) at other shear rates
and box sizes (optionally with the squeeze lubrication on below a short core gap,
``--lubrication-h-cut``), and optionally splits the shear stress by type pair:

    build/pymarble bench/suspension_shear_diagnosis.py run --phi 0.3 --rate 0.025 \
        --time 2000 --seed 11 [--box 8 8 8] [--split] [--lubrication-h-cut 0.13] [--shared off] --json FILE
    build/pymarble bench/suspension_shear_diagnosis.py table FILES [--eta0 0.3290 0.0030]
    build/pymarble bench/suspension_shear_diagnosis.py split FILES   # the split per scene
    build/pymarble bench/suspension_shear_diagnosis.py check-split
    build/pymarble bench/suspension_shear_diagnosis.py run ... --mass-scale M   # section 7l
    build/pymarble bench/suspension_shear_diagnosis.py mass FILES --eta0-files FILES

``--mass-scale M`` multiplies every particle's mass and rotational inertia
(samples/lees_edwards_suspension.py's ``scale_masses``): the particle Reynolds
number changes at fixed radius, kT and friction; ``mass`` tabulates eta_r at
phi = 0.3 per M, each relative to eta_0 measured at that M, with Re and Pe, and
fits Lin, Peery & Schowalter's inertial law through Krieger-Dougherty
(doc/suspensions.md 7l).

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
import marble.suspensions as sus  # noqa: E402
from marble.theory import krieger_dougherty_viscosity as kd  # noqa: E402
from marble.viscosity import block_average  # noqa: E402
from lees_edwards_suspension import scene, measure, dimensionless  # noqa: E402

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
                    h_cut=args.lubrication_h_cut if lub else 1.0, lubrication_form=args.lubrication_form,
                    mass_scale=args.mass_scale, shared=args.shared)
    rec = None
    if args.split:
        types = set(np.asarray(s.part.all().type).tolist())
        if types != ({COLLOID, SOLVENT} if stick else {SOLVENT}):
            raise ValueError(f"expected particle types {{0, 1}} (solvent 0), got {sorted(types)}")
        rec = SplitRecorder(s, COLLOID, SOLVENT)
        s.analysis.pressure_tensor = rec
    eta, err, slope, slope_err, kt = measure(s, args.rate, args.time)
    row = {} if args.mass_scale == 1.0 else dict(mass_scale=args.mass_scale)
    row.update(phi=info.get("phi", 0.0), phi_nominal=args.phi, boundary="stick" if stick else "solvent",
               n_colloids=info.get("n_colloids", 0), box=list(args.box), rate=args.rate, time=args.time,
               dt=args.dt, integrator="vv", seed=args.seed, eta=eta, eta_err=err,
               solvent_count="bulk" if stick else "exact", lubrication=lub if stick else None,
               colloid_dpd=False if stick else None,
               h_cut=(args.lubrication_h_cut if lub else 1.0) if stick else None,
               lubrication_form=args.lubrication_form if (stick and lub) else None,
               shared=info["shared"] if stick else None,
               n_solvent=len(info["solvent_ids"]) if stick else int(round(3.0 * np.prod(args.box))),
               cpu_s=time.process_time() - t0, wall_s=time.time() - w0, slope=slope, slope_err=slope_err, kT=kt)
    if args.eta0 is not None:  # the solvent's viscosity at this mass: Re and Pe of the scene
        row["eta0"] = list(args.eta0)
        row["Re"], row["Pe"] = dimensionless(args.rate, args.eta0[0], args.mass_scale)
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
        key = (r["phi_nominal"], r["rate"], tuple(r["box"]), lub, r.get("mass_scale", 1.0))
        groups.setdefault(key, []).append(r)
    out = []
    for (pn, rate, box, lub, mscale), sel in sorted(groups.items(),
                                                    key=lambda kv: (kv[0][4], kv[0][:3], kv[0][3] or 0)):
        phi = sel[0]["phi"]
        m, err, chi2 = weighted([r["eta"] for r in sel], [r["eta_err"] for r in sel])
        d = dict(phi=phi, rate=rate, box=box, lubrication_h_cut=lub, mass_scale=mscale, seeds=[r["seed"] for r in sel], eta=m, eta_err=err, chi2=chi2,
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


def mass_table(files, eta0_files, eta0_ref=(0.3290, 0.0030), phi_nominal=0.3):
    """Section 7l: eta_r at phi_nominal for each particle mass scale M, each
    relative to the solvent's eta_0 measured at the same M (the phi = 0 rows of
    ``eta0_files``, weighted over seeds; M = 1 takes ``eta0_ref``, section 7f's
    0.3290(30)), with Re = 3 M rate R^2/eta_0(M) and Pe = 6 pi eta_0 R^3 rate/kT.
    eta_r's error: seeds (weighted, scaled by sqrt(chi^2/dof) where > 1) and
    eta_0's added in quadrature. Then the inertial law of Lin, Peery &
    Schowalter (J. Fluid Mech. 44, 1 (1970)), [eta] = 2.5 + c Re^(3/2), carried
    through Krieger-Dougherty's exponent: ln eta_r = A + k c Re^(3/2) with
    k = -phi_m ln(1 - phi/phi_m); c fitted (weighted least squares) and compared
    with Lin's 1.34."""
    rows = [json.loads(line) for f in files for line in open(f) if line.strip()]
    e0rows = [json.loads(line) for f in eta0_files for line in open(f) if line.strip()]
    eta0 = {1.0: (eta0_ref[0], eta0_ref[1], [], None)}
    by_m = {}
    for r in e0rows:
        if r.get("phi_nominal", 0) == 0:
            by_m.setdefault(r.get("mass_scale", 1.0), []).append(r)
    for M, sel in by_m.items():
        m, e, chi2 = weighted([r["eta"] for r in sel], [r["eta_err"] for r in sel])
        split = None
        if all("split" in r for r in sel):
            split = {k: weighted([r["split"][k][0] for r in sel], [r["split"][k][1] for r in sel])[:2]
                     for k in ("kinetic_solvent", "pair_ss")}
        eta0[M] = (m, e, [(r["seed"], r["eta"], r["eta_err"], r["kT"], r["rate"], r["time"], r["dt"],
                           round(r.get("cpu_s", 0))) for r in sel], split)
    groups = {}
    for r in rows:
        if r.get("phi_nominal") != phi_nominal or r.get("solvent_count") != "bulk" or r.get("colloid_dpd"):
            continue
        if not (r.get("lubrication") and r.get("h_cut") == 0.15 and r.get("lubrication_form") == "shifted"):
            continue  # the stick defaults of 7i/7k only
        groups.setdefault((r.get("mass_scale", 1.0), r["rate"], tuple(r["box"])), []).append(r)
    out = []
    for (M, rate, box), sel in sorted(groups.items()):
        if M not in eta0:
            continue
        e0, e0_err = eta0[M][:2]
        er = [r["eta"] / e0 for r in sel]
        ee = [r["eta_err"] / e0 for r in sel]
        m, err, chi2 = weighted(er, ee)
        tot = math.hypot(err, m * e0_err / e0)
        phi = sel[0]["phi"]
        Re, Pe = dimensionless(rate, e0, M)
        k = math.log(kd(phi)) / 2.5  # d ln eta_r / d [eta] in KD: -phi_m ln(1 - phi/phi_m)
        d = dict(mass_scale=M, rate=rate, box=box, phi=phi, eta0=(e0, e0_err), eta0_seeds=eta0[M][2],
                 eta0_split=eta0[M][3], Re=Re, Pe=Pe, k=k,
                 per_seed=[(r["seed"], x, e, r["kT"], round(r.get("cpu_s", 0))) for r, x, e in zip(sel, er, ee)],
                 eta_r=m, eta_r_err_seeds=err, eta_r_err=tot, chi2=chi2, n=len(sel),
                 theory=kd(phi), deviation=m / kd(phi) - 1, deviation_err=tot / kd(phi),
                 kT=(min(r["kT"] for r in sel), max(r["kT"] for r in sel)))
        if all("split" in r for r in sel):
            d["split"] = {kk: weighted([r["split"][kk][0] / e0 for r in sel], [r["split"][kk][1] / e0 for r in sel])[:2]
                          for kk in sel[0]["split"] if kk != "total"}
        out.append(d)
    fit = None
    if len(out) >= 2:
        x = np.array([d["Re"] ** 1.5 * d["k"] for d in out])
        y = np.array([math.log(d["eta_r"]) for d in out])
        w = np.array([(d["eta_r"] / d["eta_r_err"]) ** 2 for d in out])
        X = np.vstack([np.ones_like(x), x]).T
        cov = np.linalg.inv(X.T @ (w[:, None] * X))
        A, c = cov @ (X.T @ (w * y))
        chi2 = float((w * (y - A - c * x) ** 2).sum())
        fit = dict(c=float(c), c_err=float(math.sqrt(cov[1, 1])), A=float(A), eta_r_stokes=math.exp(A),
                   eta_r_stokes_err=math.exp(A) * math.sqrt(cov[0, 0]), chi2=chi2, dof=len(out) - 2)
    return out, fit


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
    r.add_argument("--mass-scale", type=float, default=1.0,
                   help="every particle's mass and rotational inertia x this (section 7l; default 1: unchanged)")
    r.add_argument("--eta0", type=float, nargs=2, metavar=("ETA0", "ERR"), default=None,
                   help="the solvent viscosity at this mass: only recorded, with Re and Pe, in the JSON row")
    r.add_argument("--shared", choices=sus.STICK_SHARED_MODES, default="full",
                   help="the stick shells' treatment of a bead in several colloids' shells (default full, "
                        "as in sections 7j-7l; setup_suspension's default is off since session 36, 7u)")
    r.add_argument("--json")
    sub.add_parser("check-split")
    t = sub.add_parser("table")
    t.add_argument("files", nargs="+")
    t.add_argument("--eta0", type=float, nargs=2, default=[0.3290, 0.0030])
    ms = sub.add_parser("mass", help="section 7l: eta_r at phi 0.3 against the particle mass (Re at fixed Pe)")
    ms.add_argument("files", nargs="+", help="phi = 0.3 rows (stick defaults), any mass")
    ms.add_argument("--eta0-files", nargs="+", required=True, help="phi = 0 rows at the masses != 1")
    ms.add_argument("--eta0", type=float, nargs=2, default=[0.3290, 0.0030], help="eta_0 at mass 1")
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
    if a.cmd == "mass":
        out, fit = mass_table(a.files, a.eta0_files, tuple(a.eta0))
        for d in out:
            if d["eta0_seeds"]:
                print(f"M = {d['mass_scale']:g}: eta_0 per seed " + ", ".join(
                    f"{e:.4f}({1e4 * ee:.0f}) (seed {sd}, kT {kt:.4f}, rate {rt}, {t:g} tu, dt {dt}, {c} CPU-s)"
                    for sd, e, ee, kt, rt, t, dt, c in d["eta0_seeds"]))
                if d["eta0_split"]:
                    print("    eta_0 split: " + ", ".join(f"{k} {m:.4f}({1e4 * e:.0f})" for k, (m, e) in d["eta0_split"].items()))
            print(f"M = {d['mass_scale']:g}, rate {d['rate']}, phi {d['phi']:.4f}: eta_0 = {d['eta0'][0]:.4f} +/- {d['eta0'][1]:.4f}, "
                  f"Re = {d['Re']:.3f}, Pe = {d['Pe']:.2f}; eta_r per seed "
                  + ", ".join(f"{x:.3f}({1000 * e:.0f}) ({sd}, kT {kt:.4f}, {c} CPU-s)" for sd, x, e, kt, c in d["per_seed"])
                  + f"; eta_r = {d['eta_r']:.3f} +/- {d['eta_r_err']:.3f} (seeds {d['eta_r_err_seeds']:.3f}, chi^2 "
                  f"{d['chi2']:.1f}/{d['n'] - 1}); KD {d['theory']:.3f}: {100 * d['deviation']:+.1f} +/- "
                  f"{100 * d['deviation_err']:.1f} %")
            if "split" in d:
                print("    split (eta_0(M) units): " + ", ".join(f"{k} {m:.3f}({1000 * e:.0f})" for k, (m, e) in d["split"].items()))
        if fit:
            print(f"fit ln eta_r = A + k c Re^1.5 (k = {out[0]['k']:.4f}): c = {fit['c']:.2f} +/- {fit['c_err']:.2f} "
                  f"(Lin et al.: 1.34), eta_r(Re -> 0) = {fit['eta_r_stokes']:.3f} +/- {fit['eta_r_stokes_err']:.3f}, "
                  f"chi^2 {fit['chi2']:.2f}/{fit['dof']}")
        return
    if a.cmd == "run":
        run(a)
    elif a.cmd == "check-split":
        check_split(a)
    else:
        for d in table(a.files, a.eta0[0], a.eta0[1]):
            per = ", ".join(f"{x:.3f}({1000 * e:.0f}) ({sd})" for x, e, sd in d["per_seed"])
            lubs = f" lubrication h_cut {d['lubrication_h_cut']}" if d["lubrication_h_cut"] else ""
            if d["mass_scale"] != 1.0:
                lubs += f" mass x {d['mass_scale']:g}"
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
