"""Structure of a sheared suspension (doc/suspensions.md section 7e): the
colloids' concentration profile across the reverse-Poiseuille channel and
their pair distribution g(r) near contact, under flow and at rest.

Recording (no extra run: bench/suspension_stick_viscosity.py --structure
FILE.npz samples the colloid centres during its own viscosity measurement,
every --structure-every time units, without changing the trajectory; with
--rest it runs the same scene without the force, g = 0):

    build/pymarble bench/suspension_stick_viscosity.py --phi 0.2 --boundary stick \
        --solvent-count exact --seed 11 --structure run.npz --json out.jsonl

Analysis (this script; one or more .npz files of the same setting pooled):

    build/pymarble bench/suspension_structure.py run1.npz run2.npz [--skip 50] [--json out.jsonl]

- Concentration profile: the number density of colloid centres against the
  distance u = |(z mod L/2) - L/4| from the nearest channel centre (the plane of
  zero shear between two force planes; the flow is symmetric about it), in bins
  of 0.25, relative to uniform, errors from 10 blocks in time (pooled over the
  files), and the fraction of centres within the fitted region of the viscosity
  fit (bins farther than the margin 1.5 from the force planes) against its
  uniform value.
- g(r) of the colloid centres (minimum image, the whole box), bins of 0.02 from
  the core contact 2a, normalised by the ideal-gas pair count N(N-1)/2 x shell/V;
  the contact value (mean over the core gaps 0.02-0.10, just outside the soft contact
  force's range Delta = 0.02) against Carnahan-Starling
  g(2R+) = (1 - phi/2)/(1 - phi)^3 at the core and the hydrodynamic phi.
"""
import argparse
import json
import math

import numpy as np


class StructureSampler:
    """Wraps a marble.System for reverse_poiseuille: its integrator.run calls the
    real one and records the colloid centres every ``every`` steps (reading
    positions does not change the trajectory)."""

    class _Integrator:
        def __init__(self, outer):
            self._outer = outer

        def run(self, steps):
            o = self._outer
            o._system.integrator.run(steps)
            o.steps += steps
            if o.steps >= o.next_sample:
                o.frames.append(np.mod(np.asarray(o._colloids.pos, float), o.box))
                o.times.append(o.steps * o._system.time_step)
                while o.next_sample <= o.steps:
                    o.next_sample += o.every

        def __getattr__(self, name):
            return getattr(self._outer._system.integrator, name)

    def __init__(self, system, colloid_ids, every):
        self._system = system
        self._colloids = system.part.by_ids(list(map(int, colloid_ids)))
        self.box = np.asarray(system.box_l, float)
        self.every = int(every)
        self.steps = 0
        self.next_sample = self.every
        self.frames, self.times = [], []
        self.integrator = StructureSampler._Integrator(self)

    def __getattr__(self, name):
        return getattr(self._system, name)

    def run_rest(self, steps):
        """Integrate ``steps`` without any force (g = 0), sampling as under flow."""
        chunk = self.every
        done = 0
        while done < steps:
            n = min(chunk, steps - done)
            self.integrator.run(n)
            done += n

    def save(self, path, **meta):
        np.savez_compressed(path, pos=np.array(self.frames), t=np.array(self.times), box=self.box,
                            meta=json.dumps(meta))


def carnahan_starling_contact(phi):
    """Carnahan-Starling hard-sphere contact value g(2R+) = (1 - phi/2)/(1 - phi)^3."""
    return (1.0 - 0.5 * phi) / (1.0 - phi) ** 3


def _slab_volume(zc, lo, hi, R):
    """Volume of the spheres of radius R centred at heights zc inside the slab lo <= z < hi."""
    a = np.clip(lo - zc, -R, R)
    b = np.clip(hi - zc, -R, R)
    F = lambda s: R * R * s - s ** 3 / 3.0  # noqa: E731
    return math.pi * (F(b) - F(a))


def _u_slabs(u1, u2, L):
    """The z slabs (periodic images included) whose distance u from the nearest channel
    centre (L/4 or 3L/4) lies in [u1, u2)."""
    out = []
    for c in (0.25 * L, 0.75 * L):
        out += [(c + u1, c + u2), (c - u2, c - u1)]
    return out


def _volume_in(z, slabs, R, L):
    return sum(_slab_volume(z + k * L, lo, hi, R) for lo, hi in slabs for k in (-1, 0, 1))


def _min_image(d, L):
    return d - L * np.round(d / L)


def analyse(files, skip=50.0, n_blocks=10, dr=0.02, r_max=4.0, contact=(0.02, 0.10), margin=1.5,
            grad_dir=2):
    """Pool the .npz files (same setting); returns a dict of the profile, g(r) and contact values."""
    prof_blocks, g_blocks, fit_frac_blocks, phi_fit_blocks, phi_prof_blocks = [], [], [], [], []
    phi_fine_blocks = []
    metas = []
    for path in files:
        d = np.load(path)
        meta = json.loads(str(d["meta"]))
        metas.append(meta)
        pos, t, box = d["pos"], d["t"], d["box"]
        pos = pos[t >= skip]
        n_f, n_c, _ = pos.shape
        L = box[grad_dir]
        V = float(np.prod(box))
        a = meta["core_radius"]
        # concentration profile, folded: u = distance from the nearest channel centre
        u_edges = np.arange(0.0, L / 4 + 1e-9, 0.25)
        z = pos[:, :, grad_dir]
        u = np.abs(np.mod(z, L / 2) - L / 4)
        # volume-fraction profile (spheres of the hydrodynamic radius R = phi's radius)
        Rh = (meta["phi"] * V / (n_c * 4.0 / 3.0 * math.pi)) ** (1.0 / 3.0)
        A = V / L
        fit_slabs = _u_slabs(0.0, L / 4 - margin, L)
        u_slabs = [_u_slabs(u_edges[i], u_edges[i + 1], L) for i in range(len(u_edges) - 1)]
        uf_edges = np.linspace(0.0, L / 4, 51)
        uf_slabs = [_u_slabs(uf_edges[i], uf_edges[i + 1], L) for i in range(len(uf_edges) - 1)]
        # g(r)
        # in the core gap h = r - 2a (files with different cores pool by gap)
        h_edges = np.arange(0.0, r_max - 2.0 + 1e-9, dr)
        r_edges = 2 * a + h_edges
        iu = np.triu_indices(n_c, 1)
        shell = 4.0 / 3.0 * math.pi * (r_edges[1:] ** 3 - r_edges[:-1] ** 3)
        ideal = 0.5 * n_c * (n_c - 1) * shell / V
        for blk in np.array_split(np.arange(n_f), n_blocks):
            h, _ = np.histogram(u[blk].ravel(), bins=u_edges)
            prof_blocks.append(h / (len(blk) * n_c) / (np.diff(u_edges) / (L / 4)))
            fit_frac_blocks.append(np.mean(u[blk] <= L / 4 - margin))
            zb = z[blk].ravel()
            phi_fit_blocks.append(np.sum(_volume_in(zb, fit_slabs, Rh, L)) / len(blk)
                                  / (A * 4 * (L / 4 - margin)))
            phi_fine_blocks.append([np.sum(_volume_in(zb, sl, Rh, L)) / len(blk) / (A * 4 * (sl[0][1] - sl[0][0]))
                                    for sl in uf_slabs])
            phi_prof_blocks.append([np.sum(_volume_in(zb, sl, Rh, L)) / len(blk) / (A * 4 * (sl[0][1] - sl[0][0]))
                                    for sl in u_slabs])
            cnt = np.zeros(len(r_edges) - 1)
            for f in blk:
                dd = _min_image(pos[f][:, None, :] - pos[f][None, :, :], box)
                r = np.linalg.norm(dd, axis=2)[iu]
                cnt += np.histogram(r, bins=r_edges)[0]
            g_blocks.append(cnt / len(blk) / ideal)
    P = np.array(prof_blocks)
    G = np.array(g_blocks)
    nb = len(P)
    m0 = metas[0]
    a = m0["core_radius"]
    phi_h, phi_c = m0["phi"], m0["phi_core"]
    h_c = 0.5 * (h_edges[1:] + h_edges[:-1])
    r_c = 2 * a + h_c  # of the first file
    k_contact = (h_c > contact[0]) & (h_c < contact[1])
    g_cont = G[:, k_contact].mean(axis=1)
    prof = P.mean(axis=0)
    prof_err = P.std(axis=0, ddof=1) / math.sqrt(nb)
    chi2 = float(np.sum(((prof - 1.0) / np.maximum(prof_err, 1e-12)) ** 2))
    fit_frac = np.array(fit_frac_blocks)
    out = dict(files=list(map(str, files)), n_blocks=nb, L=float(L), margin=margin, skip=skip, core_radius=a, phi=phi_h, phi_core=phi_c,
               u_edges=u_edges.tolist(), profile=prof.tolist(), profile_err=prof_err.tolist(),
               profile_chi2=chi2, profile_dof=len(prof),
               fit_fraction=float(fit_frac.mean()), fit_fraction_err=float(fit_frac.std(ddof=1) / math.sqrt(nb)),
               fit_fraction_uniform=float((L / 4 - margin) / (L / 4)),
               phi_fit=float(np.mean(phi_fit_blocks)), phi_fit_err=float(np.std(phi_fit_blocks, ddof=1) / math.sqrt(nb)),
               phi_profile=np.mean(phi_prof_blocks, axis=0).tolist(),
               phi_profile_err=(np.std(phi_prof_blocks, axis=0, ddof=1) / math.sqrt(nb)).tolist(),
               fit_fraction_blocks=fit_frac.tolist(),
               u_fine_edges=uf_edges.tolist(), phi_fine=np.mean(phi_fine_blocks, axis=0).tolist(),
               h=h_c.tolist(), r=r_c.tolist(), g=G.mean(axis=0).tolist(), g_err=(G.std(axis=0, ddof=1) / math.sqrt(nb)).tolist(),
               g_contact=float(g_cont.mean()), g_contact_err=float(g_cont.std(ddof=1) / math.sqrt(nb)),
               contact=list(contact), g_max=float(G.mean(axis=0).max()),
               g_max_gap=float(h_c[int(np.argmax(G.mean(axis=0)))]),
               cs_contact_core=carnahan_starling_contact(phi_c), cs_contact_hydro=carnahan_starling_contact(phi_h),
               settings=[{k: m.get(k) for k in ("seed", "colloid_dpd", "rest", "g")} for m in metas])
    return out


def apparent_viscosity(u_edges, eta_r_of_u, L=10.0, margin=1.5, bin_width=0.5):
    """The viscosity the reverse-Poiseuille fit (marble.viscosity: bins of ``bin_width``,
    bins closer than ``margin`` to the force planes left out, one parabola per half)
    reports for a local viscosity eta_r(u) (u the distance from the channel centre, bins
    ``u_edges``), with the stress growing linearly from the centre: v'(u) = -u / eta(u)
    (force density 1). A uniform eta_r gives eta_r exactly."""
    u_edges = np.asarray(u_edges, float)
    du = np.diff(u_edges)
    uc = 0.5 * (u_edges[1:] + u_edges[:-1])
    dv = -uc / np.asarray(eta_r_of_u, float) * du
    v_edges = np.concatenate([[0.0], np.cumsum(dv)])
    v_c = 0.5 * (v_edges[1:] + v_edges[:-1])  # bin-centre values (trapezoid)
    n_fit = int(round((L / 4 - margin) / bin_width))
    vb, u2 = [], []
    for k in range(n_fit):
        m = (uc >= k * bin_width) & (uc < (k + 1) * bin_width)
        vb.append(np.sum(v_c[m] * du[m]) / np.sum(du[m]))
        u2.append(np.sum(uc[m] ** 2 * du[m]) / np.sum(du[m]))
    c = np.polyfit(u2, vb, 1)[0]  # v = a + c u^2 over the fitted bins
    return -1.0 / (2.0 * c)


def kd_apparent(res, phi_m=0.63):
    """Krieger-Dougherty applied to the measured local volume fraction phi(u), passed
    through the fit: the eta_r the measurement would report for a KD suspension with
    this concentration profile."""
    from marble import theory
    return apparent_viscosity(res["u_fine_edges"], theory.krieger_dougherty_viscosity(np.asarray(res["phi_fine"])),
                              L=res["L"], margin=res["margin"])


def report(res):
    print(f"{len(res['files'])} file(s), {res['n_blocks']} blocks; phi = {res['phi']:.4f} (cores {res['phi_core']:.4f}, "
          f"core radius {res['core_radius']:.4f})")
    print(" u (from channel centre)  n(u)/uniform      phi(u)")
    e = res["u_edges"]
    for i, (p, pe) in enumerate(zip(res["profile"], res["profile_err"])):
        print(f"  {e[i]:.2f}-{e[i + 1]:.2f}            {p:.3f} +/- {pe:.3f}   "
              f"{res['phi_profile'][i]:.4f} +/- {res['phi_profile_err'][i]:.4f}")
    print(f" chi^2 against uniform: {res['profile_chi2']:.1f} for {res['profile_dof']} bins")
    print(f" fraction of centres in the fitted region: {res['fit_fraction']:.4f} +/- {res['fit_fraction_err']:.4f}"
          f" (uniform {res['fit_fraction_uniform']:.4f})")
    print(f" volume fraction in the fitted region: {res['phi_fit']:.4f} +/- {res['phi_fit_err']:.4f} (phi {res['phi']:.4f})")
    from marble import theory
    print(f" Krieger-Dougherty at phi {theory.krieger_dougherty_viscosity(res['phi']):.3f}, at the fitted region's phi "
          f"{theory.krieger_dougherty_viscosity(res['phi_fit']):.3f}, applied locally to phi(u) and fitted "
          f"{kd_apparent(res):.3f}; Batchelor at phi {theory.batchelor_viscosity(res['phi']):.3f}, at the fitted "
          f"region's phi {theory.batchelor_viscosity(res['phi_fit']):.3f}")
    fb = res["fit_fraction_blocks"]
    print(" fraction in the fitted region by block: " + " ".join(f"{x:.3f}" for x in fb))
    print(" core gap h  r (first file)  g")
    for h, r, g, ge in list(zip(res["h"], res["r"], res["g"], res["g_err"]))[:25]:
        print(f"  {h:.3f}   {r:.3f}   {g:.3f} +/- {ge:.3f}")
    print(f" g at contact (core gaps {res['contact'][0]}-{res['contact'][1]}, outside the contact force): {res['g_contact']:.3f} +/- {res['g_contact_err']:.3f};"
          f" Carnahan-Starling at phi_core {res['cs_contact_core']:.3f}, at phi {res['cs_contact_hydro']:.3f}; "
          f"largest g {res['g_max']:.3f} at core gap {res['g_max_gap']:.2f}")


def weighted_mean(x, e):
    """Weighted mean of x with errors e; the error scaled by sqrt(chi^2/dof) when that
    exceeds 1 (the scatter between scenes is larger than their blocking errors).
    Returns (mean, error, chi2, dof)."""
    x, e = np.asarray(x, float), np.asarray(e, float)
    w = 1.0 / e ** 2
    m = float(np.sum(w * x) / np.sum(w))
    err = float(1.0 / math.sqrt(np.sum(w)))
    dof = len(x) - 1
    chi2 = float(np.sum(((x - m) / e) ** 2))
    if dof > 0 and chi2 > dof:
        err *= math.sqrt(chi2 / dof)
    return m, err, chi2, dof


def eta_table(files, eta0=0.3290, eta0_err=0.0030):
    """The drag-calibrated stick scenes (box 7 x 7 x 10, shared "full", trans_gamma 45, exact
    or Poisson count as recorded) of the JSON-lines files, grouped by phi and colloid DPD:
    eta_r means (error: weighted, scaled by sqrt(chi^2/dof) when > 1, plus eta_0's) and
    the paired differences (same phi and seed) with minus without colloid DPD."""
    rows = []
    for path in files:
        for line in open(path):
            d = json.loads(line)
            if d.get("boundary") != "stick" or d.get("shared") != "full" or d.get("trans_gamma") != 45.0:
                continue
            # the drag calibration: "stick", or its earlier value 1.02 given as a number
            # ("rotation" and "stresslet" build other cores)
            if d.get("radius_calibration") in (None, "none", "rotation", "stresslet") or d.get("rest"):
                continue
            if list(d.get("box", [7.0, 7.0, 10.0])) != [7.0, 7.0, 10.0] or not d.get("lubrication", True):
                continue
            if d.get("extra_solvent", 0.0) != 0.0 or d.get("g") != 0.02 or d.get("part"):
                continue
            rows.append(d)
    from marble import theory
    out = {}
    for phi_nom in sorted({d["phi_nominal"] for d in rows}):
        sel = {dpd: {d["seed"]: d for d in rows if d["phi_nominal"] == phi_nom and d["colloid_dpd"] == dpd}
               for dpd in (True, False)}
        phi = next(d["phi"] for d in rows if d["phi_nominal"] == phi_nom)
        kd, bat = theory.krieger_dougherty_viscosity(phi), theory.batchelor_viscosity(phi)
        res = dict(phi=phi, batchelor=bat, krieger_dougherty=kd)
        for dpd, runs in sel.items():
            if not runs:
                continue
            seeds = sorted(runs)
            m, e, chi2, dof = weighted_mean([runs[k]["eta"] for k in seeds], [runs[k]["eta_err"] for k in seeds])
            er = m / eta0
            er_err = er * math.hypot(e / m, eta0_err / eta0)
            res["dpd" if dpd else "nodpd"] = dict(
                seeds=seeds, eta=[runs[k]["eta"] for k in seeds], eta_err=[runs[k]["eta_err"] for k in seeds],
                eta_mean=m, eta_mean_err=e, chi2=chi2, dof=dof, eta_r=er, eta_r_err=er_err,
                vs_kd=er / kd - 1, vs_kd_err=er_err / kd, vs_batchelor=er / bat - 1, vs_batchelor_err=er_err / bat)
        common = sorted(set(sel[True]) & set(sel[False]))
        if common:
            dx = [sel[True][k]["eta"] - sel[False][k]["eta"] for k in common]
            de = [math.hypot(sel[True][k]["eta_err"], sel[False][k]["eta_err"]) for k in common]
            m, e, chi2, dof = weighted_mean(dx, de)
            res["paired"] = dict(seeds=common, d_eta=dx, d_eta_err=de, d_eta_r=m / eta0, d_eta_r_err=e / eta0,
                                 chi2=chi2, dof=dof)
        out[phi_nom] = res
    return out


def report_eta(tab):
    for phi_nom, r in tab.items():
        print(f"phi = {r['phi']:.4f}: Batchelor {r['batchelor']:.3f}, Krieger-Dougherty {r['krieger_dougherty']:.3f}")
        for key in ("dpd", "nodpd"):
            if key in r:
                x = r[key]
                sc = ", ".join(f"{a:.4f}({round(b * 1e4):d}) ({k})" for a, b, k in zip(x["eta"], x["eta_err"], x["seeds"]))
                print(f"  {key:6s}: {sc}")
                print(f"          eta = {x['eta_mean']:.4f} +/- {x['eta_mean_err']:.4f} (chi^2 {x['chi2']:.1f}/{x['dof']}),"
                      f" eta_r = {x['eta_r']:.3f} +/- {x['eta_r_err']:.3f};"
                      f" vs KD {100 * x['vs_kd']:+.1f} +/- {100 * x['vs_kd_err']:.1f} %,"
                      f" vs Batchelor {100 * x['vs_batchelor']:+.1f} +/- {100 * x['vs_batchelor_err']:.1f} %")
        if "paired" in r:
            p = r["paired"]
            print(f"  paired (DPD - no DPD), seeds {p['seeds']}: d eta_r = {p['d_eta_r']:.3f} +/- {p['d_eta_r_err']:.3f}"
                  f" (chi^2 {p['chi2']:.1f}/{p['dof']}); per seed "
                  + ", ".join(f"{a / 0.329:.3f}" for a in p["d_eta"]))


def solvent_profile(phi, seed=11, box=(7.0, 7.0, 10.0), frames=100, every=1.0, single=False, far=1.0, dr=0.05,
                    extra=0.0, solvent_count="exact"):
    """The solvent around the colloids at rest: the bead density against the distance
    r - a from the nearest colloid centre (a the core radius; shell volumes by Monte
    Carlo), the density beyond ``far`` from every core surface ("bulk") and the excess
    number of beads per colloid within ``far`` of a surface relative to that bulk.
    ``single``: the single stick colloid of the drag calibration (phi = 0.05, cube
    L = 4.376, one colloid at the centre, doc/suspensions.md 7c/7d) instead of the
    viscosity scene (samples/suspension_viscosity.py, calibrated stick colloids,
    exact solvent count). ``extra``: beads per colloid added after the setup as
    bench/suspension_stick_viscosity.py --extra-solvent does (then 20 time units at
    rest). ``solvent_count``: setup_suspension's ("exact", or "bulk": the exact
    count plus the adsorbed beads). Returns a dict."""
    import os
    import sys
    import marble
    import marble.suspensions as sus
    sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "samples"))
    import suspension_viscosity as sample
    if single:
        L = (4.0 * math.pi / (3.0 * 0.05)) ** (1.0 / 3.0)
        box = np.array([L] * 3)
        s = marble.System(box_l=box)
        s.time_step = 0.01
        s.cell_system.skin = 0.4
        info = sus.setup_suspension(s, phi=0.05, radius=1.0, kT=0.1, gamma=4.5, eta=0.3, seed=seed,
                                    positions=[[L / 2] * 3], boundary="stick", solvent_count=solvent_count)
        s.integrator.set_shardlow()
        s.integrator.run(2000)
    else:
        box = np.asarray(box, float)
        s, info = sample.scene(phi, box, seed=seed, equil=20.0, boundary="stick",
                              solvent_count=solvent_count)
    a = info["core_radius"]
    added = sample.add_extra_solvent(s, info, box, extra, seed)  # as --extra-solvent
    if added is not None:
        info = dict(info, solvent_ids=np.concatenate([info["solvent_ids"], np.asarray(added.id)]))
        s.integrator.run(2000)
    r = sus.solvent_structure(s, info, frames=frames, every=every, far=far, dr=dr, seed=1)
    return dict(phi=info["phi"], core_radius=a, n_colloids=r["n_colloids"], n_solvent=r["n_solvent"],
                nominal_density=r["nominal_density"], bulk_density=r["bulk_density"],
                bulk_density_err=r["bulk_density_err"], far=far, excess_per_colloid=r["excess_per_colloid"],
                h=r["h"], density=r["density"],
                single=single, seed=seed, frames=frames, extra=extra, solvent_count=solvent_count)


def kd_inverse(eta_r, phi_m=0.63):
    """The volume fraction at which Krieger-Dougherty (1 - phi/phi_m)^(-2.5 phi_m) = eta_r."""
    return phi_m * (1.0 - eta_r ** (-1.0 / (2.5 * phi_m)))


def lees_edwards_table(files, eta0=0.3290, eta0_err=0.0030, rate=0.05, phi_m=0.63):
    """eta_r of the uniform-shear scenes (samples/lees_edwards_suspension.py --json),
    grouped by (solvent count, kernels, the stick shells' ``shared`` mode, phi): the weighted mean over seeds (error scaled by
    sqrt(chi^2/dof) when chi^2 > dof, eta_0's error added), the theory (Batchelor
    at phi < 0.15, else Krieger-Dougherty), the effective radius R_eff / R =
    (phi_eff / phi)^(1/3) for which Krieger-Dougherty gives the measured eta_r, and
    the deviations from de Kruif et al.'s hard-sphere fits (1 - phi/phi_m)^-2 at low
    (phi_m = 0.63) and high shear (0.71) (marble.theory.quemada_viscosity)."""
    from marble.theory import quemada_viscosity
    rows = [json.loads(line) for f in files for line in open(f) if line.strip()]
    groups = {}
    for r in rows:
        if r.get("phi_nominal", 0) == 0 or r.get("rate") != rate:
            continue
        variant = r.get("solvent_count", "exact") + ("" if r.get("lubrication", True) else ", no lubrication") + \
            ("" if r.get("h_cut", 1.0) in (None, 1.0) else f", h_cut {r['h_cut']}") + \
            ("" if r.get("colloid_dpd", True) else ", no colloid DPD") + \
            ("" if r.get("shared", "full") == "full" else f", shared {r['shared']}")
        groups.setdefault((variant, r["phi_nominal"]), []).append(r)
    out = []
    for (count, pn), sel in sorted(groups.items()):
        phi = sel[0]["phi"]
        x = np.array([r["eta"] / eta0 for r in sel])
        e = np.array([r["eta_err"] / eta0 for r in sel])
        m, err, chi2, _ = weighted_mean(x, e)
        err = math.hypot(err, m * eta0_err / eta0)
        theory = 1 + 2.5 * phi + 6.2 * phi ** 2 if phi < 0.15 else (1 - phi / phi_m) ** (-2.5 * phi_m)
        pe = [kd_inverse(v, phi_m) for v in (m - err, m, m + err)]
        ratio = [(p / phi) ** (1.0 / 3.0) for p in pe]
        # de Kruif et al. (1985): the hard-sphere fits (1 - phi/phi_m)^-2 at low and at high shear
        q_low, q_high = quemada_viscosity(phi, 0.63), quemada_viscosity(phi, 0.71)
        out.append(dict(solvent_count=count, phi=phi, seeds=[r["seed"] for r in sel], eta_r=m, eta_r_err=err,
                        chi2=chi2, per_seed=list(zip(x.tolist(), e.tolist())), theory=theory,
                        deviation=m / theory - 1, deviation_err=err / theory,
                        hard_sphere_low_shear=q_low, deviation_low_shear=m / q_low - 1,
                        hard_sphere_high_shear=q_high, deviation_high_shear=m / q_high - 1, phi_eff=pe[1],
                        radius_ratio=ratio[1], radius_ratio_err=0.5 * (ratio[2] - ratio[0]),
                        cpu_s=[r.get("cpu_s") for r in sel]))
    return out


if __name__ == "__main__":
    import sys
    if len(sys.argv) > 1 and sys.argv[1] == "solvent":
        ap = argparse.ArgumentParser(description="solvent density around the colloids (at rest)")
        ap.add_argument("cmd")
        ap.add_argument("--phi", type=float, default=0.2)
        ap.add_argument("--seed", type=int, default=11)
        ap.add_argument("--single", action="store_true", help="the single colloid of the drag calibration")
        ap.add_argument("--frames", type=int, default=100)
        ap.add_argument("--extra", type=float, default=0.0, help="beads per colloid added (--extra-solvent)")
        ap.add_argument("--solvent-count", choices=["exact", "bulk"], default="exact")
        ap.add_argument("--json", help="append the result (a JSON line) to this file")
        a = ap.parse_args()
        r = solvent_profile(a.phi, seed=a.seed, frames=a.frames, single=a.single, extra=a.extra,
                            solvent_count=a.solvent_count)
        print(f"phi {r['phi']:.4f}, {r['n_colloids']} colloid(s), core {r['core_radius']:.4f}, {r['n_solvent']} beads "
              f"(density {r['nominal_density']:.3f} in the free volume); bulk (farther than {r['far']} from every "
              f"core surface) {r['bulk_density']:.4f} +/- {r['bulk_density_err']:.4f}; excess beads per colloid "
              f"within {r['far']}: {r['excess_per_colloid']:.2f}")
        for h, d in zip(r["h"], r["density"]):
            print(f"  r - a {h:+.3f}  n {d:.3f}")
        if a.json:
            with open(a.json, "a") as f:
                f.write(json.dumps(dict(r, part="solvent")) + "\n")
        sys.exit(0)
    if len(sys.argv) > 1 and sys.argv[1] == "lees-edwards":
        ap = argparse.ArgumentParser(description="eta_r table of the Lees-Edwards scenes, with the "
                                     "Krieger-Dougherty effective radius")
        ap.add_argument("cmd")
        ap.add_argument("files", nargs="+", help="JSON-lines files of samples/lees_edwards_suspension.py --json")
        ap.add_argument("--eta0", type=float, nargs=2, default=[0.3290, 0.0030])
        ap.add_argument("--rate", type=float, default=0.05, help="the shear rate of the rows to table")
        a = ap.parse_args()
        for r in lees_edwards_table(a.files, eta0=a.eta0[0], eta0_err=a.eta0[1], rate=a.rate):
            per = ", ".join(f"{v:.3f}({1000 * e:.0f}) ({sd})" for (v, e), sd in zip(r["per_seed"], r["seeds"]))
            print(f"{r['solvent_count']} phi {r['phi']:.4f}: {per}; eta_r = {r['eta_r']:.3f} +/- "
                  f"{r['eta_r_err']:.3f} (chi^2 {r['chi2']:.1f}/{len(r['seeds']) - 1}); theory {r['theory']:.3f}: "
                  f"{100 * r['deviation']:+.1f} +/- {100 * r['deviation_err']:.1f} %; KD phi_eff {r['phi_eff']:.4f}, "
                  f"R_eff/R = {r['radius_ratio']:.3f} +/- {r['radius_ratio_err']:.3f}; hard-sphere fits "
                  f"(de Kruif et al. 1985) low shear {r['hard_sphere_low_shear']:.3f}: "
                  f"{100 * r['deviation_low_shear']:+.1f} %, high shear {r['hard_sphere_high_shear']:.3f}: "
                  f"{100 * r['deviation_high_shear']:+.1f} %")
        sys.exit(0)
    if len(sys.argv) > 1 and sys.argv[1] == "eta":
        ap = argparse.ArgumentParser(description="eta_r table of the calibrated stick scenes")
        ap.add_argument("cmd")
        ap.add_argument("files", nargs="+", help="JSON-lines files of bench/suspension_stick_viscosity.py")
        a = ap.parse_args()
        report_eta(eta_table(a.files))
        sys.exit(0)
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("files", nargs="+", help=".npz files of bench/suspension_stick_viscosity.py --structure")
    ap.add_argument("--skip", type=float, default=50.0, help="time units at the start not used")
    ap.add_argument("--label", default="")
    ap.add_argument("--json", help="append the result (a JSON line) to this file")
    args = ap.parse_args()
    res = analyse(args.files, skip=args.skip)
    res["label"] = args.label
    res["kd_apparent"] = kd_apparent(res)
    report(res)
    if args.json:
        with open(args.json, "a") as f:
            f.write(json.dumps(res) + "\n")
