"""Scene advisor: which colloid model reaches a target accuracy cheapest
(issue 14; doc/choosing-a-model.md).

::

    import marble.advisor as adv
    rec = adv.recommend("D", accuracy=0.05, R=2.0)    # prints and returns a Recommendation
    rec.model, rec.integrator, rec.dt, rec.L, rec.run_time, rec.cpu_s
    adv.estimate_cost("srd", R=2.0, L=12.0, T=50.0)   # CPU-s of a 50-time-unit run here
    adv.check_scene(system, "D")                       # features the observable does not need

The numbers come from ``bench/three_solvents.py`` (package data
``marble/data/three_solvents.json``): for each model (``marble``: marble
colloid in the marble paper's DPD solvent; ``srd``: stochastic-boundary
colloid in SRD; ``core``: core-modified DPD colloid in Groot-Warren water)
the measured systematic error of D(inf) against Stokes-Einstein, the
variance of the estimate times the run length (error ~ 1/sqrt(T)) and the
CPU-seconds per unit simulated time, measured at R = 2, L = 10 (and the CPU
cost at R = 3, L = 15). Costs are rescaled to this machine by a probe run
(:func:`probe_speed`: 8 x 300 steps of a plain DPD fluid, the fastest), to other boxes
by the particle count and the time step. Other radii than the measured ones
are extrapolated with the drag error law sigma_v^2 T = 2 D(L) (marked
``extrapolated`` in the result).
"""
import json
import math
import os
import time

import numpy as np

from .system import System

_DATA = os.path.join(os.path.dirname(__file__), "data", "three_solvents.json")
#: Observables the advisor knows.
OBSERVABLES = ("D", "D_rot", "viscosity")
_MODELS = ("marble", "srd", "core")
_DENSITY = {"marble": 3.0, "srd": 5.0, "core": 3.0}
_V_DRAG = 0.12
_speed_cache = {}
KT = 1.0

SETTINGS = {
    "marble": dict(integrator="shardlow", dt=0.04, rho=3.0, gamma_dpd=5.0, gamma_marble=5.0),
    "srd": dict(integrator="vv (SRD streaming)", dt=0.025, tau=0.1, angle=90.0, density=5.0),
    "core": dict(integrator="vv", dt=0.0049, rho=3.0, a_ss=25.0, gamma_dpd=4.5),
}
BOUNDARY = {"marble": "stick", "srd": "stick", "core": "slip"}
ROTATES = {"marble": True, "srd": True, "core": False}


def marble_dt(R):
    """Shardlow step of the marble scene: 0.04 (the bench's) up to R = 2; 0.06 for
    larger colloids, with marble_substeps(R) = 3 RESPA substeps for the marble's
    WCA wall. At R = 3 (L = 12, drag at v = 0.12, skin 0.4) plain Shardlow at
    dt = 0.04 sent a bead through the wall fast enough to move 0.40-0.50 in one
    step in 3 of 3 runs within 190-440 time units (the integrator's check stops
    the run) and dt = 0.03 was the largest safe plain step; with the wall
    integrated at h = dt/3 = 0.02, dt = 0.06 ran 3 of 3 runs of 1000 time units
    with the same D (doc/speed-accuracy.md, "RESPA substeps for the marble's
    wall"); R = 2 at 0.04 ran 3 of 3 runs of 1500."""
    return 0.04 if _pos("R", R) <= 2.0 else 0.06


def marble_substeps(R):
    """RESPA substeps of the marble scene's Shardlow step marble_dt(R)
    (integrator.set_shardlow(substeps=...)): 1 up to R = 2, 3 above."""
    return 1 if _pos("R", R) <= 2.0 else 3


def core_dt(R):
    """VV step of the core-modified colloid: the colloid-solvent hat's
    stiffness F_cs / r'_c (1190 at R = 2, 5600 at R = 3) limits it to about
    0.17 / sqrt(stiffness) (doc/suspensions.md)."""
    from . import suspensions as sus
    k = sus.colloid_solvent_repulsion(R, 25.0) / sus.surface_cutoff(R)
    return float(min(0.01, round(0.17 / math.sqrt(k), 4)))


# --------------------------------------------------------------------------
# Scenes
# --------------------------------------------------------------------------
class Scene:
    """The measured scenes (bench/three_solvents.py, doc/choosing-a-model.md): a colloid of radius R in a cubic box L of one of the three solvents.
    Attributes: system, colloid, model, R, L, dt, n_solvent, solvent_mass."""

    def _keep(self, s, col, n_solvent):
        """Keep the system, the colloid and the solvent's size."""
        self.system, self.colloid = s, col
        self.n_solvent = int(n_solvent)
        self.solvent_mass = float(n_solvent)

    def _zero_momentum_and_keep(self, s, col):
        """Give the solvent the opposite of the colloid's momentum (total zero)
        and keep the system, the colloid and the solvent's size."""
        sol = s.part.select(type=0)
        p = col.mass * np.asarray(col.v) + np.sum(sol.v, axis=0)
        sol.v = np.asarray(sol.v) - p / len(sol)
        self._keep(s, col, len(sol))

    def __init__(self, model, R, L, seed, boundary="stick", warmup=5.0, gamma=None):
        """``boundary``: "stick" or "slip" (the model's two surfaces, BOUNDARY);
        for the marble also "partial": the tunable-slip coupling with surface
        friction ``gamma`` (e.g. from marble.slip.gamma_for_slip_length)."""
        if boundary not in ("stick", "slip", "partial"):
            raise ValueError(f"parameter 'boundary' must be 'stick', 'slip' or 'partial', "
                             f"got {boundary!r}")
        if boundary == "partial" and (model != "marble" or gamma is None):
            raise ValueError("parameter 'boundary': 'partial' needs model='marble' and a "
                             "surface friction 'gamma' > 0")
        self.model, self.R, self.L, self.boundary = model, float(R), float(L), boundary
        self.gamma = None if gamma is None else _pos("gamma", gamma)
        getattr(self, "_make_" + model)(seed)
        self.system.integrator.run(int(round(warmup / self.dt)))

    # (a) marble colloid, paper DPD solvent (colloid_runs.marble_box), Shardlow
    def _make_marble(self, seed):
        from .colloid_runs import marble_box
        st = SETTINGS["marble"]
        self.dt = marble_dt(self.R)
        # stick: tunable slip at gamma = 5; slip: central forces only; partial: tunable slip at gamma
        coupling = "dpd" if self.boundary == "slip" else "tunable_slip"
        gamma = self.gamma if self.boundary == "partial" else st["gamma_marble"]
        s, col, sol = marble_box(self.L, self.R, gamma, seed, rho=st["rho"],
                                 gamma_dpd=st["gamma_dpd"], kT=KT, dt=self.dt, coupling=coupling,
                                 skin=0.5)
        s.integrator.set_shardlow(substeps=marble_substeps(self.R))
        self._keep(s, col, len(sol))

    # (b) SRD solvent, stochastic (stick) or specular (slip) colloid
    def _make_srd(self, seed):
        from . import srd
        st = SETTINGS["srd"]
        L, R = self.L, self.R
        s = System(box_l=[L] * 3, time_step=st["dt"])
        self.dt = st["dt"]
        s.cell_system.skin = 0.5
        s.srd = srd.SRDFluid(types=[0], tau=st["tau"], angle=st["angle"], kT=KT, seed=seed,
                             thermostat="mbs")
        srd.add_fluid(s, density=st["density"], type=0, kT=KT, seed=seed + 1)
        rule = "stochastic" if self.boundary == "stick" else "slip"
        col = srd.add_colloid(s, pos=[L / 2] * 3, radius=R, type=1, rule=rule,
                              density=st["density"])
        self.system, self.colloid = s, col
        self.n_solvent = s.srd.n
        self.solvent_mass = float(s.srd.n)

    # (c) core-modified DPD colloid in Groot-Warren water
    def _make_core(self, seed):
        from . import suspensions as sus
        st = SETTINGS["core"]
        L, R = self.L, self.R
        s = System(box_l=[L] * 3)
        self.dt = s.time_step = core_dt(R)
        s.cell_system.skin = 0.4
        info = sus.setup_suspension(s, phi=1e-9, radius=R, density=st["rho"], kT=KT,
                                    gamma=st["gamma_dpd"], eta=None, seed=seed,
                                    lubrication=False, positions=[[L / 2] * 3])
        col = s.part.by_id(int(info["colloid_ids"][0]))
        # one colloid: its colloid-colloid kernels (contact, DPD with offset 2R)
        # never act, but their range 2R + r_c would set the cell grid of every
        # particle (7.6x the cost at R = 2; check_scene warns about it)
        s.non_bonded_inter[1, 1].contact.deactivate()
        s.non_bonded_inter[1, 1].dpd.deactivate()
        self._zero_momentum_and_keep(s, col)

    @property
    def n_particles(self):
        return self.n_solvent + 1

    def run(self, steps):
        """integrator.run(steps); returns its process CPU time."""
        c = time.process_time()
        self.system.integrator.run(int(steps))
        return time.process_time() - c

    def fluid_com_velocity(self):
        if self.model == "srd":
            return np.asarray(self.system.srd.v).mean(axis=0)
        return np.asarray(self.system.part.select(type=0).v).mean(axis=0)

    def set_drag(self, F):
        """Force F (x) on the colloid, -F/N on the solvent (net force zero)."""
        self.colloid.ext_force = [F, 0.0, 0.0]
        if self.model == "srd":
            self.system.srd.acceleration = [-F / self.n_solvent, 0.0, 0.0]
        else:
            self.system.part.select(type=0).ext_force = [-F / self.n_solvent, 0.0, 0.0]

    def drag_series(self, F, T, t_eq=20.0, sample=0.2):
        """Drag run: force F on the colloid (set_drag), ``t_eq`` time units to the
        steady state, then ``T`` more sampling the colloid's velocity relative to
        the fluid along x every ``sample``. Returns (v_rel array, CPU-s of the
        production run, CPU-s of the steady-state part)."""
        self.set_drag(F)
        cpu_eq = self.run(int(round(t_eq / self.dt)))
        every = max(1, int(round(sample / self.dt)))
        n = int(round(T / (every * self.dt)))
        v = np.empty(n)
        cpu = 0.0
        for i in range(n):
            cpu += self.run(every)
            v[i] = float(self.colloid.v[0]) - self.fluid_com_velocity()[0]
        return v, cpu, cpu_eq

    @property
    def frame_factor(self):
        M = float(self.colloid.mass)
        return (self.solvent_mass / (M + self.solvent_mass)) ** 2




def load_table(path=None):
    """The measured table (dict) of bench/three_solvents.py."""
    with open(path or _DATA) as f:
        return json.load(f)


def probe_speed(steps=300, repeats=8):
    """This machine's speed in particle-steps per CPU-second (time.process_time):
    ``steps`` velocity-Verlet steps of a DPD fluid (rho = 3, L = 8, gamma = 5,
    no conservative force, dt = 0.01) after 100 steps of warm-up, the fastest
    of ``repeats`` (the least disturbed by other jobs and by the first
    allocations); cached per ``steps`` within the process."""
    if isinstance(steps, bool) or int(steps) != steps or steps < 10:
        raise ValueError(f"parameter 'steps' must be an integer >= 10, got {steps!r}")
    if steps in _speed_cache:
        return _speed_cache[steps]
    from .system import System
    L = 8.0
    s = System(box_l=[L] * 3)
    s.time_step = 0.01
    s.cell_system.skin = 0.4
    rng = np.random.default_rng(7)
    n = int(round(3.0 * L ** 3))
    s.part.add(pos=rng.random((n, 3)) * L, v=rng.normal(size=(n, 3)), type=0)
    s.thermostat.set_dpd(kT=1.0, seed=7)
    s.non_bonded_inter[0, 0].dpd.set_params(weight_function=1, gamma=5.0, k=1, r_cut=1.0)
    s.integrator.run(100)
    rates = []
    for _ in range(int(repeats)):
        c = time.process_time()
        s.integrator.run(int(steps))
        rates.append(n * steps / max(time.process_time() - c, 1e-9))
    _speed_cache[steps] = float(np.max(rates))
    return _speed_cache[steps]


def _check_model(model):
    if model not in _MODELS:
        raise ValueError(f"parameter 'model' must be one of {_MODELS}, got {model!r}")


def _pos(name, x):
    try:
        x = float(x)
    except (TypeError, ValueError):
        raise ValueError(f"parameter '{name}' must be a number > 0, got {x!r}") from None
    if not math.isfinite(x) or x <= 0:
        raise ValueError(f"parameter '{name}' must be a finite number > 0, got {x}")
    return x


def model_dt(model, R, table=None):
    """The time step of ``model`` at radius R (the core-modified colloid's
    VV step shrinks with the stiffness of its thin colloid-solvent shell; the
    marble's Shardlow step is 0.06 with 3 RESPA substeps above R = 2, marble_dt)."""
    _check_model(model)
    if model == "core":
        return core_dt(R)
    return marble_dt(R) if model == "marble" else float(SETTINGS[model]["dt"])


def n_particles(model, R, L):
    """Particles of a scene: solvent at the model's density outside the colloid (SRD
    particles and DPD beads alike) plus the colloid; the marble's surface is a
    single particle, its interior holds no solvent either."""
    _check_model(model)
    return int(round(_DENSITY[model] * (L ** 3 - 4.0 / 3.0 * math.pi * R ** 3))) + 1


def cpu_per_time(model, R, L, speed=None, table=None):
    """Estimated CPU-seconds per unit simulated time of a ``model`` scene (colloid
    radius R, cubic box L) on this machine: the measured cost per particle-step
    (at R = 2 and R = 3), interpolated linearly in R (constant outside),
    times this scene's particles and steps per unit time, times (measuring
    machine's probe speed / this machine's). The core colloid's range no
    longer sets the solvent's cell grid (the second grid for colloids), so
    its cost per particle-step, like the others', depends on R only weakly."""
    _check_model(model)
    R, L = _pos("R", R), _pos("L", L)
    t = table or load_table()
    m = t["models"][model]
    pts = sorted((c["R"], c["cpu_per_tau"] * c["dt"] / c["N"]) for c in
                 (m[k] for k in ("drag", "paper") if k in m))
    x = [r for r, _ in pts]
    y = [c for _, c in pts]
    if len(pts) == 1 or abs(x[-1] - x[0]) < 1e-12:
        per_particle_step = y[0]
    else:                   # linear in R between the measured radii, constant outside
        per_particle_step = float(np.interp(R, x, y))
    dt = model_dt(model, R, t)
    cost = per_particle_step * n_particles(model, R, L) / dt
    if speed is None:
        speed = probe_speed()
    return cost * t["probe_particle_steps_per_cpu_s"] / speed


def estimate_cost(model, R, L, T, speed=None, table=None):
    """Estimated CPU-seconds (time.process_time) of ``integrator.run`` over ``T``
    time units of a ``model`` scene with one colloid of radius R in a box L."""
    return cpu_per_time(model, R, L, speed, table) * _pos("T", T)


def _var_T(model, observable, R, L, t, key="drag"):
    """(relative error)^2 x run length of the observable's best method, and
    whether it was extrapolated from the measured R, L."""
    from . import theory as th
    m = t["models"][model]
    if observable == "viscosity":
        e = m.get("eta_run")
        if not e:
            return None, None
        return (e["eta_err"] / e["eta"]) ** 2 * e["T"], False
    if observable == "D_rot":
        g = m.get("gk")
        if not g or "var_T_rot" not in g:
            return None, None
        return g["var_T_rot"], not (abs(g["R"] - R) < 1e-9 and abs(g["L"] - L) < 1e-9)
    d = m[key]
    if abs(d["R"] - R) < 1e-9 and abs(d["L"] - L) < 1e-9:
        return d["var_T"], False
    # drag floor law at the same velocity, scaled by the measured/law ratio
    eta = m["eta"][0]
    b = 0.0 if (m["boundary"] == "stick" and key == "drag") or key == "drag_stick" else np.inf

    def law(R_, L_):
        D_inf = th.diffusion_coefficient(eta, R_, np.inf, b) * (1 + d["sys"])
        D_L = D_inf - (th.diffusion_coefficient(eta, R_, np.inf, b)
                       - th.diffusion_coefficient(eta, R_, L_, b))
        return 2.0 / (_V_DRAG ** 2 * D_inf ** 2) * D_L
    return d["var_T"] * law(R, L) / law(d["R"], d["L"]), True


class Recommendation:
    """What :func:`recommend` returns: ``model``, ``observable``, ``accuracy``,
    ``method``, ``integrator``, ``dt``, ``R``, ``L``, ``n_particles``,
    ``run_time`` (simulated time units of production), ``cpu_s`` (estimated CPU
    seconds on this machine), ``systematic`` (the model's measured systematic
    error, relative), ``extrapolated`` (bool), ``alternatives`` (the other
    models' rows, cheapest first) and ``notes``."""

    def __init__(self, **kw):
        self.__dict__.update(kw)

    def as_dict(self):
        """The recommendation as a plain dict."""
        return dict(self.__dict__)

    def __str__(self):
        s = (f"{self.observable} to {100 * self.accuracy:.3g} %: use '{self.model}' "
             f"({self.method}), {self.integrator} dt = {self.dt:g}, box L = {self.L:g} "
             f"(R = {self.R:g}, {self.n_particles} particles), run {self.run_time:.4g} time units "
             f"~ {self.cpu_s:.3g} CPU-s here; systematic error {100 * self.systematic:+.1f} %"
             + (" (extrapolated)" if self.extrapolated else ""))
        for a in self.alternatives:
            s += (f"\n   {a['model']:7s} {a['cpu_s']:10.3g} CPU-s, systematic "
                  f"{100 * a['systematic']:+.1f} %" + ("" if a["eligible"] else
                                                       "  (systematic error above the target)"))
        for n in self.notes:
            s += "\n   note: " + n
        return s

    __repr__ = __str__


def recommend(observable="D", accuracy=0.05, R=2.0, boundary="stick", L_over_R=5.0,
              calibrated=False, speed=None, verbose=True, table=None):
    """Recommended model, integrator, dt, box and run length for ``observable``
    ("D", "D_rot" or "viscosity") to a relative ``accuracy``, with the estimated
    CPU cost on this machine.

    A model is eligible when its measured systematic error (D(inf) against
    Stokes-Einstein at the requested ``boundary``) is below ``accuracy``; the
    statistical error then gets the rest, sqrt(accuracy^2 - systematic^2).
    ``calibrated=True`` accepts a model whose surface has been calibrated (its
    measured hydrodynamic radius used in place of R): then only the uncertainty
    of that systematic error counts. The cheapest eligible model wins; when none
    is eligible the one with the smallest systematic error is returned with a note.
    """
    if observable not in OBSERVABLES:
        raise ValueError(f"parameter 'observable' must be one of {OBSERVABLES}, got {observable!r}")
    acc = _pos("accuracy", accuracy)
    if acc >= 1:
        raise ValueError(f"parameter 'accuracy' must be a relative error in (0, 1), got {accuracy}")
    R = _pos("R", R)
    if boundary not in ("stick", "slip"):
        raise ValueError(f"parameter 'boundary' must be 'stick' or 'slip', got {boundary!r}")
    t = table or load_table()
    if speed is None:
        speed = probe_speed()
    rows = []
    for model, m in t["models"].items():
        if observable != "viscosity" and m["boundary"] != boundary:
            key = "drag_" + boundary
            if key not in m:
                continue
        L = float(L_over_R * R) if model != "srd" else float(round(L_over_R * R))
        if model == "core":   # setup_suspension needs L > 2 (2R + r_c)
            L = max(L, float(math.floor(2 * (2 * R + 1.0)) + 1))
        dkey = "drag" if m["boundary"] == boundary else "drag_" + boundary
        vt, extrap = _var_T(model, observable, R, L, t, dkey)
        if vt is None:
            continue
        if observable == "viscosity":
            sysm, syse = 0.0, 0.0
            e = m["eta_run"]
            L = float(e["box"][0])
            cost_t = e["cpu_s"] / e["T"] * t["probe_particle_steps_per_cpu_s"] / speed
            n = int(round(_DENSITY[model] * np.prod(e["box"])))
            method, dt = "reverse Poiseuille", m["settings"]["dt"] if model != "srd" else 0.1
        else:
            src = m["drag"] if (observable == "D" and m["boundary"] == boundary) else \
                m.get("drag_" + boundary, m["drag"]) if observable == "D" else m["gk"]
            sysm = src["sys_rot"] if observable == "D_rot" else src["sys"]
            syse = src.get("sys_err", 0.0) if observable == "D" else \
                src["D_rot_err"] / src["D_rot"] * (1 + sysm)
            cost_t = cpu_per_time(model, R, L, speed, t)
            n = n_particles(model, R, L)
            method = "drag + Hasimoto" if observable == "D" else "Green-Kubo (angular VACF)"
            dt = model_dt(model, R, t)
        # a calibration (the measured hydrodynamic radius) holds at the measured R only
        calib = calibrated and not extrap
        budget_sys = syse if calib else abs(sysm)
        eligible = budget_sys < acc
        stat = math.sqrt(acc ** 2 - budget_sys ** 2) if eligible else acc
        T = vt / stat ** 2
        rows.append(dict(model=model, method=method, L=L, dt=dt, n_particles=n, run_time=T,
                         cpu_s=T * cost_t, cpu_per_time=cost_t, systematic=sysm,
                         systematic_err=syse, eligible=eligible, extrapolated=bool(extrap),
                         integrator=m["settings"]["integrator"]))
    if not rows:
        raise ValueError(f"no measured model offers {observable!r} with a {boundary} surface")
    ok = [r for r in rows if r["eligible"]]
    notes = []
    if ok:
        best = min(ok, key=lambda r: r["cpu_s"])
    else:
        best = min(rows, key=lambda r: abs(r["systematic"]))
        notes.append(f"no model's systematic error is below {100 * acc:.3g} %: "
                     f"'{best['model']}' has the smallest ({100 * best['systematic']:+.1f} %); "
                     "calibrate its hydrodynamic radius (calibrated=True) or accept it")
    alts = sorted([r for r in rows if r is not best], key=lambda r: r["cpu_s"])
    if calibrated and best["extrapolated"]:
        notes.append("calibrated=True applies at the measured radius only: the systematic "
                     "error at this R is the measured one, not recalibrated")
    if observable == "D":
        notes.append(f"D(L) in the box L = {best['L']:g} is corrected to D(inf) with Hasimoto's "
                     "formula at the solvent's measured viscosity (marble.theory.diffusion_coefficient)")
    rec = Recommendation(observable=observable, accuracy=acc, R=R, boundary=boundary,
                         extrapolated=best["extrapolated"], alternatives=alts, notes=notes,
                         **{k: best[k] for k in ("model", "method", "integrator", "dt", "L",
                                                 "n_particles", "run_time", "cpu_s",
                                                 "systematic")})
    if verbose:
        print(rec)
    return rec


# --- scene inspection -------------------------------------------------------

_CONSERVATIVE = ("hat", "lennard_jones", "morse")
_COLLOID_PAIR = ("contact", "lubrication", "dpd", "morse", "hat", "lennard_jones")


def _active(handle, kind):
    k = getattr(handle, kind, None)
    try:
        return k is not None and k.is_active()
    except Exception:  # noqa: BLE001 - kernel not compiled into this build
        return False


def _on_second_grid(system, ptype):
    """True if @p ptype is served by the coarse second cell grid (doc/architecture.md):
    listed in cell_system.large_range_types, or chosen there by "auto" at the
    last list rebuild."""
    mode = system.cell_system.large_range_types
    if mode is None:
        return False
    if mode != "auto":
        return ptype in mode
    return ptype in system.cell_system.get_state()["large_range_types"]


def check_scene(system, observable="D", verbose=False):
    """Warnings (list of dicts with 'code', 'message') for features of the scene in
    ``system`` that ``observable`` does not need and that only cost time:

    - ``unneeded_rotation``: colloids with rotation when only "D" or "viscosity" is
      asked for (a single sphere's translational mobility does not couple to its
      rotation; the marble's tunable-slip coupling keeps its stick surface with
      rotation frozen, too);
    - ``unneeded_conservative``: a conservative pair force (hat, Lennard-Jones,
      Morse) between solvent particles: D, D_rot and the viscosity need only
      the solvent's viscosity, and a fluid without it (the marble paper's) is
      cheaper per step;
    - ``unneeded_colloid_pairs``: contact/lubrication kernels with a single
      colloid whose type is not on the second cell grid (with
      ``cell_system.large_range_types = "auto"`` it is, after the first list
      build, and the kernels cost nothing).
    """
    if observable not in OBSERVABLES:
        raise ValueError(f"parameter 'observable' must be one of {OBSERVABLES}, got {observable!r}")
    out = []
    parts = system.part.all()
    types = sorted(set(int(x) for x in np.atleast_1d(parts.type))) if len(parts) else []
    inter = system.non_bonded_inter
    colloid_types = set()
    for i in types:
        for j in types:
            h = inter[i, j]
            if _active(h, "marble") or _active(h, "srd_boundary"):
                colloid_types.add(i)
    srd = getattr(system, "_srd", None)
    if srd is not None:
        for i in types:
            for s in srd.get_params().get("types", []):
                if _active(inter[i, s], "srd_boundary"):
                    colloid_types.add(i)
    for i in types:
        for j in types:
            if _active(inter[i, j], "contact") or _active(inter[i, j], "lubrication"):
                colloid_types.update({i, j})
    solvent_types = [t for t in types if t not in colloid_types]
    if observable in ("D", "viscosity") and len(parts):
        rot = np.asarray(parts.rotation) if hasattr(parts, "rotation") else None
        if rot is not None and rot.size and np.any(rot):
            n = int(np.sum(np.any(np.atleast_2d(rot), axis=1)))
            out.append(dict(code="unneeded_rotation", value=n,
                            message=f"{n} particle(s) rotate, but '{observable}' needs only "
                                    "translation: in the Stokes limit a single sphere's "
                                    "translational mobility does not couple to its rotation; "
                                    "rotation=[False]*3 saves the rotational integration (a "
                                    "small cost). Not measured here: a frozen surface changes "
                                    "the short-time (kinetic) friction, check D once"))
    for i in solvent_types:
        for j in solvent_types:
            if j < i:
                continue
            kinds = [k for k in _CONSERVATIVE if _active(inter[i, j], k)]
            if kinds:
                out.append(dict(code="unneeded_conservative", value=kinds, types=(i, j),
                                message=f"solvent pair ({i}, {j}) has a conservative force "
                                        f"({', '.join(kinds)}): '{observable}' needs only the "
                                        "solvent's viscosity; without it (the marble paper's "
                                        "solvent) a step is cheaper. Keep it if the fluid's "
                                        "compressibility or structure matters (e.g. the "
                                        "core-modified colloid's solvent)"))
    for c in sorted(colloid_types):
        n_c = len(system.part.select(type=c))
        kinds = [k for k in _COLLOID_PAIR if _active(inter[c, c], k)]
        if n_c <= 1 and kinds and not _on_second_grid(system, c):
            out.append(dict(code="unneeded_colloid_pairs", value=kinds, types=(c, c),
                            message=f"colloid type {c} has {n_c} particle: its {', '.join(kinds)} "
                                    "kernel(s) never act, but with one cell grid "
                                    "(cell_system.large_range_types) their range sets the cell "
                                    "grid of every particle (measured: 7.6x the CPU per step of a "
                                    "core-modified colloid at R = 2, L = 11 with contact and DPD on "
                                    "the colloid pair; 14.9x in bench/suspension_cost.py)"))
    if verbose:
        for w in out:
            print("warning:", w["message"])
    return out
