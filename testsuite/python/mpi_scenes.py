"""Scenes run by test_mpi.py under `mpiexec -n N` (every rank runs this
script; reads are collective, so every rank reads and rank 0 writes).

    mpiexec -n 2 build/pymarble testsuite/python/mpi_scenes.py SCENE OUT.npz
"""
import sys

import numpy as np

import marble


def fluid(L, seed=5, gamma=5.0, kT=1.0, dt=0.01):
    rng = np.random.default_rng(seed)
    s = marble.System(box_l=[L, L, L])
    s.time_step = dt
    s.cell_system.skin = 0.4
    n = int(3 * L**3)
    s.part.add(pos=rng.uniform(0, L, (n, 3)), v=rng.normal(size=(n, 3)))
    s.non_bonded_inter[0, 0].dpd.set_params(weight_function=1, gamma=gamma, k=1.0, r_cut=1.0)
    s.thermostat.set_dpd(kT=kT, seed=3)
    return s


def _run_error(s, steps):
    """Run @p steps; the RuntimeError's message, or "no error"."""
    try:
        s.integrator.run(steps)
    except RuntimeError as e:
        return str(e)
    return "no error"


def scene_marble(L=8.0, R=2.0, steps=100):
    """DPD solvent + one rotating marble (tunable slip), moving across domains."""
    s = fluid(L)
    col = marble.colloids.add_marble(s, pos=[L / 2 - 0.3, L / 2, L / 2], radius=R, gamma=5.0)
    col.v = [0.3, 0.1, 0.0]
    owned0 = set(s.cell_system.local_ids())
    s.integrator.run(steps)
    owned1 = set(s.cell_system.local_ids())
    parts = s.part.all()
    out = dict(ids=parts.id, pos=parts.pos, v=parts.v, f=parts.f,
               cpos=col.pos, cv=col.v, comega=col.omega_lab, ctorque=col.torque_lab,
               energy=s.analysis.energy()["total"], momentum=s.analysis.linear_momentum(),
               node_grid=np.array(s.cell_system.node_grid),
               # particles that changed rank during the run, summed over ranks
               migrated=np.array(len(owned0 ^ owned1)))
    return s, out


def scene_marble_big():
    """A marble wider than a rank's domain (diameter 6 > L/2 = 4)."""
    return scene_marble(L=8.0, R=3.0, steps=100)


def _suspension_box():
    """The suspension scenes' box (L = 9, dt 1e-3): one cell grid on one rank,
    the colloids' large-range grid on N."""
    s = marble.System(box_l=[9.0] * 3)
    s.time_step = 1e-3
    s.cell_system.skin = 0.4
    s.cell_system.large_range_types = None if marble.mpi_size() == 1 else "auto"
    return s


def scene_suspension():
    """Colloids whose pairs reach farther than the solvent's (a large-range
    cell grid of their own, cells/CellSystem.hpp): they come to the other
    ranks from all sides, the solvent in a half shell. 20 VV steps with DPD
    noise; on one rank without the split (one grid), on N with it."""
    s = _suspension_box()
    marble.suspensions.setup_suspension(s, phi=0.2, radius=1.0, kT=0.1, gamma=4.5, eta=0.3,
                                        seed=4, h_cut=1.0)
    s.integrator.set_vv()
    s.integrator.run(20)
    parts = s.part.all()
    return s, dict(ids=parts.id, pos=parts.pos, v=parts.v, f=parts.f,
                   types=np.array(s.cell_system.get_state()["large_range_types"]),
                   node_grid=np.array(s.cell_system.node_grid))


def _stick_suspension(**kw):
    """Stick colloids at phi = 0.25 (surface_friction with rotation,
    setup_suspension(boundary="stick")) in the suspension box: (system, info)."""
    s = _suspension_box()
    info = marble.suspensions.setup_suspension(s, phi=0.25, radius=1.0, kT=0.1, gamma=4.5, eta=0.3,
                                               seed=6, h_cut=1.0, boundary="stick", **kw)
    return s, info


def _suspension_stick(shared):
    """Stick colloids with the shared-shell treatment ``shared``: a bead inside
    the shells of colloids that live on different ranks must count all of them
    ("split": gamma/n). 30 VV steps with noise, the two-grid split on N ranks."""
    s, info = _stick_suspension(shared=shared)
    s.integrator.set_vv()
    s.integrator.run(30)
    parts = s.part.all()
    col = s.part.by_ids(info["colloid_ids"])
    return s, dict(ids=parts.id, pos=parts.pos, v=parts.v, f=parts.f, comega=col.omega_lab,
                   ctorque=col.torque_lab, node_grid=np.array(s.cell_system.node_grid))


def scene_suspension_stick_split():
    return _suspension_stick("split")


def scene_suspension_stick_full():
    return _suspension_stick("full")


def scene_lj():
    """A Lennard-Jones fluid (VV without thermostat): energy conservation across ranks."""
    rng = np.random.default_rng(2)
    L = 7.0
    s = marble.System(box_l=[L, L, L])
    s.time_step = 0.005
    s.cell_system.skin = 0.3
    g = np.arange(0, L, L / 6)
    pos = np.array(np.meshgrid(g, g, g)).reshape(3, -1).T + 0.05
    s.part.add(pos=pos, v=rng.normal(scale=0.8, size=pos.shape))
    s.non_bonded_inter[0, 0].lennard_jones.set_params(epsilon=1.0, sigma=1.0, cutoff=2.5, shift="auto")
    e0 = s.analysis.energy()["total"]
    s.integrator.run(400)
    parts = s.part.all()
    out = dict(ids=parts.id, pos=parts.pos, v=parts.v, f=parts.f, e0=e0,
               energy=s.analysis.energy()["total"],
               pressure=s.analysis.pressure()["total"])
    return s, out


def scene_channel():
    """Tunable-slip walls, non-periodic z, a body force: the channel of the
    slip samples (marble.slip.make_channel), split in z on 2 ranks."""
    from marble.slip import make_channel
    s = make_channel(marble, box_xy=4.0, height=8.0, gamma_L=1.0, body_force=0.05, wall_velocity=0.2)
    s.integrator.run(100)
    parts = s.part.all()
    return s, dict(ids=parts.id, pos=parts.pos, v=parts.v, f=parts.f,
                   node_grid=np.array(s.cell_system.node_grid))


def _ckpt_dir():
    import os
    return os.environ["MARBLE_CKPT_DIR"]


def scene_ckpt_reference():
    """Checkpoint after N steps, then N more (the reference). Scene of
    test_checkpoint.py (DPD + hat + marble + correlator + mean/variance)."""
    import os
    sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
    from checkpoint_scene import dump, make_scene
    import marble.checkpointing
    s, corr, mv = make_scene("vv")
    s.integrator.run(60)
    ns = dict(system=s, corr=corr, mv=mv)
    cp = marble.checkpointing.Checkpoint(checkpoint_id="mpi", checkpoint_path=_ckpt_dir(),
                                         namespace=ns)
    cp.register("system", "corr", "mv")
    cp.save()
    s.integrator.run(60)
    return s, dump(s, corr, mv)


def scene_ckpt_restart():
    """A new mpiexec: load the checkpoint and run the second N steps."""
    import os
    sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
    from checkpoint_scene import dump
    import marble.checkpointing
    ns = {}
    cp = marble.checkpointing.Checkpoint(checkpoint_id="mpi", checkpoint_path=_ckpt_dir(),
                                         namespace=ns)
    cp.load()
    s = ns["system"]
    s.integrator.run(60)
    return s, dump(s, ns["corr"], ns["mv"])


def scene_uncaught():
    """An exception on rank 1 only: marble's excepthook must MPI_Abort every rank."""
    s = fluid(4.0)
    if marble.mpi_rank() == 1:
        raise ValueError("raised on rank 1 only")
    s.integrator.run(1000)  # rank 0 would wait here forever without the abort
    return s, {}


def scene_blowup():
    """A step far too large: every rank must stop with the same RuntimeError (no hang)."""
    s = fluid(4.0)
    s.non_bonded_inter[0, 0].dpd.set_params(weight_function=1, gamma=5.0, k=1.0, r_cut=1.0)
    s.time_step = 0.01
    s.part.by_id(7).v = [1e6, 0, 0]
    msg = _run_error(s, 10)
    # the system stays usable: fix the particle and go on
    s.part.by_id(7).v = [0, 0, 0]
    s.integrator.run(10)
    return s, dict(msg=np.array(msg), step=np.array(s.step))


def _fluid_with_list_check(check):
    """A DPD fluid (L = 8, VV) whose lists outlive the half-skin mark under
    cell_system.list_check = "pairs": the hot particles of every rank are
    compared with each rank's warm ones, one vote per check."""
    s = fluid(8.0, seed=6)
    s.cell_system.list_check = check
    r0 = s.cell_system.get_state()["verlet_rebuilds"]
    s.integrator.run(150)
    st = s.cell_system.get_state()
    parts = s.part.all()
    return s, dict(ids=parts.id, pos=parts.pos, v=parts.v, f=parts.f,
                   rebuilds=np.array(st["verlet_rebuilds"] - r0),
                   pair_test=np.array(st["pair_test_applies"]))


def scene_fluid_pairs():
    return _fluid_with_list_check("pairs")


def scene_fluid_half_skin():
    return _fluid_with_list_check("half_skin")


def _water(shardlow, check="pairs", L=9.0):
    """Groot-Warren water (hat a = 25; under Shardlow with DPD gamma = 4.5 at
    dt = 0.04, skin 0.3, where the half-skin rule rebuilds at almost every
    step; else NVE at dt = 0.01, skin 0.4), after 20 steps."""
    rng = np.random.default_rng(12)
    s = marble.System(box_l=[L, L, L])
    s.time_step = 0.04 if shardlow else 0.01
    s.cell_system.skin = 0.3 if shardlow else 0.4
    s.cell_system.list_check = check
    n = int(3 * L**3)
    s.part.add(pos=rng.uniform(0, L, (n, 3)), v=rng.normal(size=(n, 3)))
    s.non_bonded_inter[0, 0].hat.set_params(F_max=25.0, cutoff=1.0)
    if shardlow:
        s.non_bonded_inter[0, 0].dpd.set_params(weight_function=1, gamma=4.5, k=1.0, r_cut=1.0)
        s.thermostat.set_dpd(kT=1.0, seed=7)
        s.integrator.set_shardlow()
    s.integrator.run(20)
    return s


def _by_id(parts, key):
    return np.array(getattr(parts, key))[np.argsort(parts.id)]


def _shardlow_water_with_list_check(check, steps=30):
    """_water under Shardlow: positions and forces (the hat's only: the DPD
    pairs act in the sweep) after each of @p steps single steps, and the
    total momentum."""
    s = _water(True, check)
    L = s.box_l[0]
    p0 = np.array(s.part.all().v).sum(axis=0)
    r0 = s.cell_system.get_state()["verlet_rebuilds"]
    pos, f = [], []
    for _ in range(steps):
        s.integrator.run(1)
        parts = s.part.all()
        pos.append(_by_id(parts, "pos")), f.append(_by_id(parts, "f"))
    st = s.cell_system.get_state()
    return s, dict(L=np.array(L), pos=np.array(pos), f=np.array(f), p0=p0,
                   p1=np.array(s.part.all().v).sum(axis=0),
                   rebuilds=np.array(st["verlet_rebuilds"] - r0),
                   pair_test=np.array(st["pair_test_applies"]))


def _pairs_closing_across_faces(shardlow):
    """_water brought to rest, with three pairs flying at each other across the
    planes x = 3, 4.5 and 0 (the domain faces of 2 and 3 ranks, and the
    periodic face): each particle moves 0.6 skins in the step, so each pair is
    in range after it without having been in the list, and nothing else moves
    half a skin. Returns the positions and forces after the step and the
    rebuilds it made (1: the pair test found a missing pair)."""
    s = _water(shardlow)
    L, skin = s.box_l[0], s.cell_system.skin
    if shardlow:
        s.thermostat.set_dpd(kT=0.0, seed=7)
    parts = s.part.all()
    parts.v = np.zeros((len(parts), 3))
    gap, speed = 1.0 + 1.15 * skin, 0.6 * skin / s.time_step
    for k, (plane, y) in enumerate(((3.0, 1.5), (4.5, 4.5), (0.0, 7.5))):
        a, b = s.part.by_id(2 * k), s.part.by_id(2 * k + 1)
        a.pos, a.v = [(plane - gap / 2) % L, y, y], [speed, 0.0, 0.0]
        b.pos, b.v = [plane + gap / 2, y, y], [-speed, 0.0, 0.0]
    s.cell_system.skin = skin  # a list built at these positions
    s.integrator.run(0)
    r0 = s.cell_system.get_state()["verlet_rebuilds"]
    s.integrator.run(1)
    parts = s.part.all()
    return s, dict(L=np.array(L), pos=_by_id(parts, "pos"), f=_by_id(parts, "f"),
                   rebuilds=np.array(s.cell_system.get_state()["verlet_rebuilds"] - r0))


def scene_pairs_closing_vv():
    return _pairs_closing_across_faces(False)


def scene_pairs_closing_shardlow():
    return _pairs_closing_across_faces(True)


def scene_shardlow_pairs():
    return _shardlow_water_with_list_check("pairs")


def scene_shardlow_half_skin():
    return _shardlow_water_with_list_check("half_skin")


def scene_dpd_vv():
    """DPD-VV (the friction pass needs the ghosts' velocity change and sends
    the ghosts' friction back), with a marble."""
    s = fluid(8.0, seed=4)
    col = marble.colloids.add_marble(s, pos=[3.7, 4.0, 4.0], radius=2.0, gamma=5.0)
    col.v = [0.2, 0.0, 0.1]
    s.integrator.set_dpd_vv()
    s.integrator.run(100)
    parts = s.part.all()
    return s, dict(ids=parts.id, pos=parts.pos, v=parts.v, f=parts.f, cpos=col.pos,
                   comega=col.omega_lab)


def scene_shardlow_narrow(substeps=1):
    """Shardlow on ranks whose domains (2 wide) are narrower than twice the
    pair range (1.4): refused before any step; one rank runs. @p substeps > 1:
    through RESPA's run (with a marble colloid, whose substeps then act)."""
    s = fluid(4.0)
    if substeps > 1:
        marble.colloids.add_marble(s, pos=[2.0, 2.0, 2.0], radius=1.0, gamma=5.0, excluded_volume=False)
    s.integrator.set_shardlow(substeps=substeps)
    return s, dict(msg=np.array(_run_error(s, 1)), step=np.array(s.step))


def scene_shardlow_narrow_respa():
    return scene_shardlow_narrow(substeps=2)


def shardlow_dimers(L=12.0, spacing=3.0, seed=8):
    """Isolated pairs (dimers 0.6 long, centres 3 apart, x = 3 i + 0.05): every
    particle has one partner, so the Shardlow sweep's order does not matter
    and every decomposition gives the same trajectory. Several of them straddle
    the domain faces of 2 and 3 ranks (x = 0, 4, 6, 8)."""
    rng = np.random.default_rng(seed)
    s = marble.System(box_l=[L, L, L])
    s.time_step = 0.04
    s.cell_system.skin = 0.4
    g = np.arange(0.0, L - 1e-9, spacing)
    centres = np.array([[x + 0.05, y + 0.05, z + 0.05] for x in g for y in g for z in g])
    u = rng.normal(size=(len(centres), 3))
    u /= np.linalg.norm(u, axis=1)[:, None]
    pos = np.concatenate([centres + 0.3 * u, centres - 0.3 * u]) % L
    s.part.add(pos=pos, v=0.3 * rng.normal(size=pos.shape))
    s.non_bonded_inter[0, 0].dpd.set_params(weight_function=1, gamma=5.0, k=1.0, r_cut=1.0)
    s.thermostat.set_dpd(kT=1.0, seed=4)
    s.integrator.set_shardlow()
    return s, pos


def shardlow_clusters(L=12.0):
    """Small clusters of three particles a1 - p - a2 (two pairs sharing p, a1
    and a2 out of range of each other) placed across the domain faces of 2, 3
    and 4 ranks: chains across the faces x = 4, 6, 8 (their two pairs on
    different ranks), and one across the periodic face x = 0 whose a1 and a2
    see p through two periodic images along z (an axis these node grids do not
    split). Returns (positions, velocities, external forces), clusters in
    rows of three: a1, p, a2."""
    pos, vel = [], []
    rng = np.random.default_rng(21)
    for f, y in ((4.0, 3.0), (6.0, 6.5), (8.0, 9.5)):
        pos += [[f - 0.6, y, 6.0], [f + 0.1, y + 0.05, 6.0], [f + 0.8, y, 6.1]]
    pos += [[L - 0.25, 6.0, 0.75], [0.2, 6.0, 0.2], [L - 0.25, 6.0, L - 0.35]]
    vel = rng.normal(size=(len(pos), 3))
    force = 0.5 * rng.normal(size=(len(pos), 3))
    return np.array(pos), vel, force


def scene_shardlow_clusters():
    """One Shardlow step (kT = 0, a = 0, an external force on every particle,
    so the half kick before the sweep changes the velocities) of
    shardlow_clusters(): the test compares each cluster with the two
    sequential orders of its pairs, computed in numpy."""
    L = 12.0
    pos, vel, force = shardlow_clusters(L)
    s = marble.System(box_l=[L, L, L])
    s.time_step = 0.05
    s.cell_system.skin = 0.4
    s.part.add(pos=pos, v=vel, ext_force=force)
    s.non_bonded_inter[0, 0].dpd.set_params(weight_function=1, gamma=40.0, k=1.0, r_cut=1.0)
    s.thermostat.set_dpd(kT=0.0, seed=3)
    s.integrator.set_shardlow()
    s.integrator.run(1)
    parts = s.part.all()
    return s, dict(ids=parts.id, pos=parts.pos, v=parts.v, pos0=pos, v0=vel, force=force, L=np.array(L),
                   dt=np.array(0.05), gamma=np.array(40.0), node_grid=np.array(s.cell_system.node_grid))


#: the narrow-domain chains (shardlow_chains, test_mpi.py): domains 2.4
#: wide along x (skin 0.1: twice the pair range 1.1 fits, three times not)
CHAIN = dict(slab=2.4, Lyz=4.0, skin=0.1, dt=0.05, gamma=200.0)


def shardlow_chains(ranks):
    """Chains k - i - j - m of three pairs across the domain of rank 1 (x in
    [2.4, 4.8)) on a node grid ranks x 1 x 1: k in the domain below, i 0.75
    inside the lower face, j 0.85 inside the upper face, m in the domain
    above (on 2 ranks, across the periodic face). i lies at the lower face
    and j at the upper face of the same domain, so the pair (i, j) touches
    both faces (the sweep's colour rounds after the face rounds,
    integrators/shardlow.cpp); (k, i) and (j, m) cross the faces. A second
    chain runs the other way. Returns (positions, velocities, external
    forces, box), chains in rows of four: k, i, j, m."""
    p = CHAIN
    lo, hi = p["slab"], 2 * p["slab"]
    L = [ranks * p["slab"], p["Lyz"], p["Lyz"]]
    xs = [lo - 0.05, lo + 0.75, hi - 0.85, hi + 0.05]
    pos = [[x % L[0], 1.0, 1.0] for x in xs] + [[x % L[0], 3.0, 3.0] for x in xs[::-1]]
    rng = np.random.default_rng(5)
    vel = 0.3 * rng.normal(size=(len(pos), 3))
    force = 0.5 * rng.normal(size=(len(pos), 3))
    return np.array(pos), vel, force, np.array(L)


def _shardlow_chains(wide):
    """One Shardlow step of shardlow_chains() (kT = 0, a = 0, external forces):
    the test compares each chain with the six sequential orders of its pairs.
    @p wide: the particles' type a large-range type (cells/CellSystem.hpp:
    a full shell of ghosts, so a domain's locals go to the ranks on both
    sides; with the half shell of small types and the grid split along x they
    go to one side only, and no pair touches both faces)."""
    p = CHAIN
    pos, vel, force, L = shardlow_chains(marble.mpi_size())
    s = marble.System(box_l=list(L))
    s.time_step = p["dt"]
    s.cell_system.skin = p["skin"]
    if wide:  # (a small type for the solvent grid, without particles)
        s.non_bonded_inter[1, 1].dpd.set_params(weight_function=1, gamma=1.0, k=1.0, r_cut=0.5)
        s.cell_system.large_range_types = [0]
    s.part.add(pos=pos, v=vel, ext_force=force)
    s.non_bonded_inter[0, 0].dpd.set_params(weight_function=1, gamma=p["gamma"], k=1.0, r_cut=1.0)
    s.thermostat.set_dpd(kT=0.0, seed=3)
    s.integrator.set_shardlow()
    s.integrator.run(1)
    parts = s.part.all()
    return s, dict(ids=parts.id, pos=parts.pos, v=parts.v, pos0=pos, v0=vel, force=force, L=L,
                   node_grid=np.array(s.cell_system.node_grid),
                   types=np.array(s.cell_system.get_state()["large_range_types"]))


def scene_shardlow_chains():
    return _shardlow_chains(wide=False)


def scene_shardlow_chains_wide():
    return _shardlow_chains(wide=True)


def shardlow_stick_clusters(L=12.0):
    """Clusters b1 - C - b2 of a rotating colloid C (radius 1) and two point
    beads inside its stick-friction shell (surface_friction, gap < 0.5) on
    opposite sides, the beads out of each other's reach: across the domain
    faces x = 4, 6, 8 (the colloid and one bead on one side), and one across
    the periodic face x = 0 whose beads see C through two periodic images
    along z, and one at the corner x = y = 6 whose beads lie on two ranks
    that do not own C (4 ranks). Returns (positions, velocities, external forces, colloid spins,
    external torques), clusters in rows of three: b1, C, b2."""
    rng = np.random.default_rng(23)
    pos = []
    for f, y in ((4.0, 3.0), (6.0, 6.5), (8.0, 9.5)):
        c = np.array([f + 0.1, y, 6.0])
        pos += [c + [-1.2, 0.3, 0.1], c, c + [1.15, -0.2, 0.3]]
    pos += [[L - 1.0, 6.0, L - 0.5], [0.1, 6.0, 0.1], [L - 1.0, 6.3, 0.8]]
    # (4 ranks, node grid 2 x 2 x 1: the beads on two ranks, neither the colloid's)
    pos += [[4.9, 6.35, 10.1], [6.1, 6.1, 10.0], [6.3, 4.9, 9.85]]
    n = len(pos)
    vel = rng.normal(size=(n, 3))
    force = 0.5 * rng.normal(size=(n, 3))
    omega = rng.normal(size=(n // 3, 3))
    torque = rng.normal(size=(n // 3, 3))
    return np.array(pos), vel, force, omega, torque


#: the stick clusters' parameters (shardlow_stick_clusters, test_mpi.py)
STICK_CLUSTER = dict(L=12.0, dt=0.05, gamma=40.0, r_cut=0.5, radius=1.0, mass=5.0, rinertia=2.0)


def _shardlow_colloid_clusters(kind, substeps=1, fixed=False):
    """One Shardlow step (kT = 0, external forces and torques, so the half
    kick before the sweep changes velocities and spins) of
    shardlow_stick_clusters(), their colloids (STICK_CLUSTER's radius, mass,
    inertia, gamma, r_cut) coupled to the beads by the stick friction
    (@p kind "stick": surface_friction) or the marble coupling ("marble":
    tunable slip; the beads at gaps 0.2-0.34 from the surface): the test
    compares each cluster with the two sequential orders of its pair updates,
    computed in numpy. @p substeps > 1: the step through RESPA's path (no
    conservative colloid force here, so its substeps drift the positions as
    one step does, to round-off). @p fixed: every colloid fixed (infinitely
    heavy: the pair updates no longer depend on their order, so every
    decomposition must give one rank's result)."""
    p = STICK_CLUSTER
    pos, vel, force, omega, torque = shardlow_stick_clusters(p["L"])
    s = marble.System(box_l=[p["L"]] * 3)
    s.time_step = p["dt"]
    s.cell_system.skin = 0.4
    types = np.tile([0, 1, 0], len(pos) // 3)
    s.part.add(pos=pos, v=vel, ext_force=force, type=types)
    col = s.part.select(type=1)
    col.mass = np.full(len(col.id), p["mass"])
    col.rotation = np.ones((len(col.id), 3), bool)
    col.rinertia = np.full((len(col.id), 3), p["rinertia"])
    col.omega_lab = omega
    col.ext_torque = torque
    if fixed:
        col.fix = np.ones((len(col.id), 3), bool)
    if kind == "marble":
        s.non_bonded_inter[1, 0].marble.set_params(radius=p["radius"], gamma=p["gamma"], r_cut=p["r_cut"],
                                                   weight_function=1, k=1.0, coupling="tunable_slip")
    else:
        s.non_bonded_inter[1, 0].surface_friction.set_params(gamma=p["gamma"], r_cut=p["r_cut"],
                                                             a1=p["radius"], a2=0.0)
    s.thermostat.set_dpd(kT=0.0, seed=3)
    s.integrator.set_shardlow(substeps=substeps)
    s.integrator.run(1)
    parts = s.part.all()
    return s, dict(ids=parts.id, pos=parts.pos, v=parts.v, omega=parts.omega_lab, pos0=pos, v0=vel,
                   force=force, omega0=omega, torque=torque, node_grid=np.array(s.cell_system.node_grid))


def scene_shardlow_stick_clusters():
    return _shardlow_colloid_clusters("stick")


def scene_shardlow_marble_clusters():
    return _shardlow_colloid_clusters("marble")


def scene_shardlow_marble_clusters_respa():
    return _shardlow_colloid_clusters("marble", substeps=3)


def scene_shardlow_marble_clusters_fixed():
    return _shardlow_colloid_clusters("marble", fixed=True)


def scene_shardlow_stick_shared():
    """Two groups A - b - B: a bead b in the stick-friction shells of two
    colloids A, B (radius 1, r_cut 0.5) with shared="split" (gamma/2 for each
    of b's pairs, the shell count taken over the ranks): across the face
    x = 6 (A and B on two ranks of a 2 x 1 x 1 grid) and across the periodic
    face x = 0. One Shardlow step at kT = 0 with external forces and torques;
    the test compares with the two sequential orders at gamma/2 (numpy).
    (Scene from session 22's review.)"""
    p = STICK_CLUSTER
    L = p["L"]
    rng = np.random.default_rng(5)
    pos = np.array([[4.95, 3.0, 6.0], [6.2, 3.1, 6.1], [7.45, 3.0, 6.2],
                    [0.55, 8.0, 6.0], [L - 0.7, 8.1, 6.0], [L - 1.95, 8.0, 5.9]])
    n = len(pos)
    types = np.array([1, 0, 1, 1, 0, 1])
    vel, force = rng.normal(size=(n, 3)), 0.5 * rng.normal(size=(n, 3))
    omega, torque = rng.normal(size=(n, 3)), rng.normal(size=(n, 3))
    s = marble.System(box_l=[L] * 3)
    s.time_step = p["dt"]
    s.cell_system.skin = 0.4
    s.part.add(pos=pos, v=vel, ext_force=force, type=types)
    col = s.part.select(type=1)
    k = np.array(col.id)
    col.mass = np.full(len(k), p["mass"])
    col.rotation = np.ones((len(k), 3), bool)
    col.rinertia = np.full((len(k), 3), p["rinertia"])
    col.omega_lab = omega[k]
    col.ext_torque = torque[k]
    s.non_bonded_inter[1, 0].surface_friction.set_params(gamma=p["gamma"], r_cut=p["r_cut"], a1=p["radius"],
                                                         a2=0.0, shared="split")
    s.thermostat.set_dpd(kT=0.0, seed=3)
    s.integrator.set_shardlow()
    s.integrator.run(1)
    parts = s.part.all()
    return s, dict(ids=parts.id, pos=parts.pos, v=parts.v, omega=parts.omega_lab, pos0=pos, v0=vel,
                   force=force, omega0=omega, torque=torque, types=types,
                   node_grid=np.array(s.cell_system.node_grid))


def _momentum(s):
    """The total momentum sum m v (all ranks' particles)."""
    parts = s.part.all()
    return (np.asarray(parts.mass).reshape(-1, 1) * parts.v).sum(axis=0)


def _colloid_kT_run(s, ids, M, I):
    """100 steps, then 600 samples 10 steps apart of the beads' kT and the
    colloids' (@p ids, mass @p M, inertia @p I) translational and rotational
    kT; the total momentum before and after."""
    p0 = _momentum(s)
    s.integrator.run(100)
    kT_b, kT_t, kT_r = [], [], []
    for _ in range(600):
        s.integrator.run(10)
        parts = s.part.all()
        col = np.isin(parts.id, ids)
        kT_b.append(np.mean(parts.v[~col] ** 2))
        kT_t.append(M * np.mean(parts.v[col] ** 2))
        kT_r.append(I * np.mean(parts.omega_lab[col] ** 2))
    return dict(kT_beads=np.array(kT_b), kT_trans=np.array(kT_t), kT_rot=np.array(kT_r), p0=p0,
                p1=_momentum(s), node_grid=np.array(s.cell_system.node_grid))


def scene_shardlow_marble_temperature():
    """The ideal DPD fluid (a = 0, L = 10) with 12 marble colloids (radius 1,
    tunable slip, add_marble without excluded volume: no conservative force
    anywhere) under Shardlow at dt = 0.02: every update is exact or free
    flight, so the beads' kT and the colloids' translational and rotational
    kT are 1; the total momentum m v stays what it was."""
    from marble.colloids import add_marble
    s = fluid(10.0, seed=14, dt=0.02)
    rng = np.random.default_rng(15)
    # (one mass for all: the neutrally buoyant default would follow the solvent each removal left)
    cols = [add_marble(s, pos=rng.uniform(0, 10.0, 3), radius=1.0, gamma=5.0, excluded_volume=False, mass=12.0)
            for _ in range(12)]
    s.integrator.set_shardlow()
    return s, _colloid_kT_run(s, np.array([c.id for c in cols]), 12.0, cols[0].rinertia[0])


def scene_shardlow_stick_temperature():
    """The ideal DPD fluid (a = 0, L = 9) with 40 rotating colloids (radius 1,
    mass 10, I = 4, no colloid-colloid forces) coupled to it by the stick
    friction only, under Shardlow at dt = 0.02: the sweep is exact, so the
    beads' kT and the colloids' translational and rotational kT are 1; the
    total momentum m v stays what it was."""
    s = fluid(9.0, seed=12, dt=0.02)
    rng = np.random.default_rng(13)
    n_col = 40
    cols = s.part.add(pos=rng.uniform(0, 9.0, (n_col, 3)), v=rng.normal(scale=0.3, size=(n_col, 3)),
                      type=[1] * n_col, mass=[10.0] * n_col, rotation=np.ones((n_col, 3), bool),
                      rinertia=np.full((n_col, 3), 4.0), omega_lab=rng.normal(scale=0.5, size=(n_col, 3)))
    s.non_bonded_inter[1, 0].surface_friction.set_params(gamma=20.0, r_cut=0.5, a1=1.0, a2=0.0)
    s.integrator.set_shardlow()
    return s, _colloid_kT_run(s, np.array(cols.id), 10.0, 4.0)


def scene_shardlow_dimers():
    s, pos0 = shardlow_dimers()
    s.integrator.run(15)
    parts = s.part.all()
    return s, dict(ids=parts.id, pos=parts.pos, v=parts.v, f=parts.f, pos0=pos0)


def scene_shardlow_suspension():
    """Colloids (R = 1, phi = 0.2, large-range grid on N ranks) with squeeze
    lubrication in a DPD solvent under Shardlow (dt = 1e-3): the colloid
    pairs come to the other ranks from all sides, and their lubrication is in
    the sweep. L = 14: domains 7 wide on 2 ranks, at least twice the colloid
    pairs' range (2 R + h_cut + skin = 3.4). The total momentum must stay."""
    s = marble.System(box_l=[14.0] * 3)
    s.time_step = 1e-3
    s.cell_system.skin = 0.4
    info = marble.suspensions.setup_suspension(s, phi=0.2, radius=1.0, kT=0.1, gamma=4.5, eta=0.3,
                                               seed=4, h_cut=1.0)
    s.integrator.set_shardlow()
    p0 = _momentum(s)
    s.integrator.run(30)
    return s, dict(p0=p0, p1=_momentum(s), n=np.array(len(s.part.all().id)),
                   n_colloids=np.array(info["n_colloids"]),
                   types=np.array(s.cell_system.get_state()["large_range_types"]),
                   node_grid=np.array(s.cell_system.node_grid))


def scene_shardlow_temperature():
    """The ideal DPD fluid (a = 0) under Shardlow at dt = 0.04: kT = 1 for any
    dt (the sweep is exact, the drift is free flight); the total momentum
    stays what it was."""
    s = fluid(9.0, seed=9, dt=0.04)
    s.integrator.set_shardlow()
    p0 = s.part.all().v.sum(axis=0)
    kT = _kT_series(s, 100, 60, 10)
    return s, dict(kT=kT, p0=p0, p1=s.part.all().v.sum(axis=0))


def _sheared(s, direction="x", normal="y", velocity=2.0, offset=1.3):
    """Lees-Edwards linear shear on @p s: only the third (vorticity) axis is
    split on several ranks."""
    import marble.lees_edwards as le
    s.lees_edwards.set_boundary_conditions(
        shear_direction=direction, shear_plane_normal=normal,
        protocol=le.LinearShear(initial_pos_offset=offset, shear_velocity=velocity))
    return s


def _le_state(s):
    parts = s.part.all()
    return dict(ids=parts.id, pos=parts.pos, v=parts.v, f=parts.f,
                pressure=np.array(s.analysis.pressure_tensor()["total"]),
                energy=np.array(s.analysis.energy()["total"]),
                offset=np.array(s.lees_edwards.pos_offset),
                node_grid=np.array(s.cell_system.node_grid))


def scene_lees_edwards(direction="x", normal="y"):
    """The DPD fluid under Lees-Edwards shear (velocity Verlet, noise): 150
    steps in which the offset moves by 3 (rebuilds by the offset's drift),
    particles cross the shear plane and the rank faces."""
    s = _sheared(fluid(8.0, seed=12), direction, normal)
    if marble.has_features("TRANS_DPD"):  # (the transverse friction sees the jump too)
        s.non_bonded_inter[0, 0].dpd.set_params(weight_function=1, gamma=5.0, k=1.0, r_cut=1.0,
                                                trans_weight_function=1, trans_gamma=2.0, trans_r_cut=1.0)
    s.integrator.run(150)
    return s, _le_state(s)


def scene_lees_edwards_zx():
    """The same with shear along z, normal x (the grid splits y)."""
    return scene_lees_edwards("z", "x")


def scene_lees_edwards_switch():
    """Lees-Edwards switched on after 20 steps and off again 40 steps later:
    on N ranks the node grid changes both times (N x 1 x 1 -> 1 x 1 x N -> back),
    and the next list build sends the particles to their new ranks."""
    s = fluid(8.0, seed=13)
    s.integrator.run(20)
    grids = [s.cell_system.node_grid]
    _sheared(s, velocity=1.5, offset=0.7)
    s.integrator.run(40)
    grids.append(s.cell_system.node_grid)
    s.lees_edwards.set_boundary_conditions(protocol=None)
    s.integrator.run(20)
    grids.append(s.cell_system.node_grid)
    parts = s.part.all()
    return s, dict(ids=parts.id, pos=parts.pos, v=parts.v, f=parts.f, grids=np.array(grids))


def scene_lees_edwards_stick():
    """Stick colloids (large-range grid: a full shell of colloid ghosts, the
    solvent's half shell; setup_suspension's shared="off", so a bead in the
    shells of colloids on other ranks must see them all) under Lees-Edwards
    shear, 30 VV steps with noise."""
    s, info = _stick_suspension()
    _sheared(s, velocity=0.5, offset=2.2)
    s.integrator.set_vv()
    s.integrator.run(30)
    col = s.part.by_ids(info["colloid_ids"])
    return s, dict(_le_state(s), comega=col.omega_lab, ctorque=col.torque_lab)


def scene_lees_edwards_shardlow_pairs():
    """Four isolated pairs straddling the shear plane (kT = 0, DPD friction
    only, Shardlow): one across the periodic face of the split axis, the others
    across the faces of 2 or 3 ranks or inside one domain, so a pair's partner
    is an own image or another rank's particle. Each pair's update is the
    exact one of its relative velocity across the plane, whatever the order:
    every rank count gives the same velocities to round-off."""
    s = marble.System(box_l=[6.0, 6.0, 9.0])
    s.time_step = 0.01
    s.cell_system.skin = 0.4
    for x, z in ((1.0, 3.0), (4.0, 4.5), (1.0, 6.0), (4.0, 0.0)):
        s.part.add(pos=[[x, 5.8, (z - 0.05) % 9.0], [x - 0.1, 0.1, z + 0.05]], v=[[0.0, 0.0, 0.0]] * 2)
    s.non_bonded_inter[0, 0].dpd.set_params(weight_function=1, gamma=4.5, k=1.0, r_cut=1.0)
    s.thermostat.set_dpd(kT=0.0, seed=1)
    s.integrator.set_shardlow()
    _sheared(s, velocity=0.7, offset=0.25)
    s.integrator.run(5)
    parts = s.part.all()
    return s, dict(ids=parts.id, pos=parts.pos, v=parts.v, node_grid=np.array(s.cell_system.node_grid))


def scene_lees_edwards_shardlow():
    """The ideal DPD fluid sheared under Shardlow at dt = 0.04 (the sweep adds
    the shear velocity jump to pairs across the plane, also when the partner is
    another rank's particle): the kinetic temperature of the velocities
    relative to the mean flow of their slab along the normal, and the shear
    stress, every 10 steps."""
    L, V = 9.0, 1.0
    s = _sheared(fluid(L, seed=9, dt=0.04), velocity=V)
    s.integrator.set_shardlow()
    s.integrator.run(300)
    kT, sxy = [], []
    for _ in range(100):
        s.integrator.run(10)
        p = s.part.all()
        y, v = np.asarray(p.pos_folded)[:, 1], np.asarray(p.v)
        slab = np.minimum((y / L * 9).astype(int), 8)
        mean = np.array([v[slab == k].mean(axis=0) for k in range(9)])
        kT.append(np.mean((v - mean[slab]) ** 2))
        sxy.append(s.analysis.pressure_tensor()["total"][0][1])
    return s, dict(kT=np.array(kT), sxy=np.array(sxy), node_grid=np.array(s.cell_system.node_grid))


def scene_respa():
    """RESPA substeps (integrator.set_vv(substeps=3)) with a fast rotating marble
    crossing the domains: between substeps the ghosts get the new positions and
    the fast forces on ghosts go back to their owners; the colloid list goes
    stale inside steps too (mid-step rebuilds, with migration on N ranks)."""
    s = fluid(8.0, seed=7)
    col = marble.colloids.add_marble(s, pos=[3.7, 4.0, 4.0], radius=2.0, gamma=5.0)
    col.v = [6.0, 1.0, 0.0]
    s.integrator.set_vv(substeps=3)
    owned0 = set(s.cell_system.local_ids())
    s.integrator.run(60)
    owned1 = set(s.cell_system.local_ids())
    parts = s.part.all()
    return s, dict(ids=parts.id, pos=parts.pos, v=parts.v, f=parts.f, cpos=col.pos,
                   cv=col.v, comega=col.omega_lab,
                   rebuilds=np.array(s.cell_system.get_state()["verlet_rebuilds"]),
                   migrated=np.array(len(owned0 ^ owned1)))


def scene_respa_shardlow():
    """The respa scene under Shardlow (set_shardlow(substeps=3)): the marble
    coupling in the sweep, rank by rank on N ranks, after the substeps, the
    mid-step rebuilds and migration. The total momentum m v must stay."""
    s = fluid(8.0, seed=7)
    col = marble.colloids.add_marble(s, pos=[3.7, 4.0, 4.0], radius=2.0, gamma=5.0)
    col.v = [6.0, 1.0, 0.0]
    s.integrator.set_shardlow(substeps=3)
    p0 = _momentum(s)
    owned0 = set(s.cell_system.local_ids())
    s.integrator.run(60)
    owned1 = set(s.cell_system.local_ids())
    return s, dict(p0=p0, p1=_momentum(s), cpos=col.pos, node_grid=np.array(s.cell_system.node_grid),
                   rebuilds=np.array(s.cell_system.get_state()["verlet_rebuilds"]),
                   migrated=np.array(len(owned0 ^ owned1)))


def scene_respa_plain():
    """RESPA substeps with no colloid and no pair interaction (no cell range, so no
    ghosts; the substeps' exchange of colloid copies has nothing to send), with
    particles crossing the domains."""
    rng = np.random.default_rng(9)
    s = marble.System(box_l=[6.0, 6.0, 6.0])
    s.time_step = 0.02
    s.part.add(pos=rng.uniform(0, 6, (300, 3)), v=3.0 * rng.normal(size=(300, 3)))
    s.integrator.set_vv(substeps=3)
    owned0 = set(s.cell_system.local_ids())
    s.integrator.run(40)
    owned1 = set(s.cell_system.local_ids())
    parts = s.part.all()
    return s, dict(ids=parts.id, pos=parts.pos, v=parts.v, f=parts.f, migrated=np.array(len(owned0 ^ owned1)))


def scene_respa_blowup():
    """A particle far too fast under RESPA (substeps = 3, a marble present):
    every rank stops in the first substep with the same RuntimeError (no hang),
    and the system goes on after new velocities."""
    s = fluid(8.0, seed=7)
    marble.colloids.add_marble(s, pos=[3.7, 4.0, 4.0], radius=2.0, gamma=5.0)
    s.integrator.set_vv(substeps=3)
    s.integrator.run(2)
    s.part.by_id(7).v = [1e6, 0, 0]
    msg = _run_error(s, 10)
    # a refused RESPA step keeps what was done before the refusal (the outer
    # half kick, which gave the fast particle's neighbours its DPD friction):
    # new velocities for all, and the run goes on
    parts = s.part.all()
    parts.v = np.random.default_rng(8).normal(size=(len(parts), 3))
    s.integrator.run(10)
    return s, dict(msg=np.array(msg), step=np.array(s.step))


def _narrow(box, r_cut, steps=30, seed=3):
    """A DPD fluid (rho = 3) in a small box with a long cutoff: on several
    ranks the domains are thinner than the interaction range (cutoff + skin
    0.4), so a rank's ghosts come from several domains and periodic images."""
    rng = np.random.default_rng(seed)
    box = np.array(box, dtype=float)
    s = marble.System(box_l=list(box))
    s.time_step = 0.005
    s.cell_system.skin = 0.4
    n = int(3 * np.prod(box))
    s.part.add(pos=rng.random((n, 3)) * box, v=rng.normal(size=(n, 3)))
    s.non_bonded_inter[0, 0].dpd.set_params(weight_function=1, gamma=5.0, k=1.0, r_cut=r_cut)
    s.thermostat.set_dpd(kT=1.0, seed=3)
    s.integrator.run(steps)
    parts = s.part.all()
    return s, dict(ids=parts.id, pos=parts.pos, v=parts.v, f=parts.f,
                   node_grid=np.array(s.cell_system.node_grid))


def scene_narrow():
    """6 x 6 x 4, r_cut 2.3 (range 2.7): on 3 ranks the domains are 2 wide,
    thinner than the cutoff itself."""
    return _narrow([6.0, 6.0, 4.0], 2.3)


def scene_thin():
    """6 x 6 x 4, r_cut 1.8: on 3 ranks the domains (2) are wider than the
    cutoff but thinner than cutoff + skin (2.2)."""
    return _narrow([6.0, 6.0, 4.0], 1.8)


def scene_images():
    """9 x 2 x 2, r_cut 2.3: the box is thinner than the range along y and z
    (two periodic images on each side), and on 3 ranks the domains are 3 wide."""
    return _narrow([9.0, 2.0, 2.0], 2.3)


def scene_teleport():
    """A long box (24 x 4 x 4, on 6 ranks a 6 x 1 x 1 grid: rank 0's neighbours
    are ranks 1 and 5 only). Mid-run the script moves particles across the box,
    to ranks that are not neighbours of their owner: the next rebuild must
    notice it and migrate through the all-rank exchange (counted)."""
    rng = np.random.default_rng(8)
    box = np.array([24.0, 4.0, 4.0])
    s = marble.System(box_l=list(box))
    s.time_step = 0.01
    s.cell_system.skin = 0.4
    n = int(3 * np.prod(box))
    s.part.add(pos=rng.random((n, 3)) * box, v=rng.normal(size=(n, 3)))
    s.non_bonded_inter[0, 0].dpd.set_params(weight_function=1, gamma=5.0, k=1.0, r_cut=1.0)
    s.thermostat.set_dpd(kT=1.0, seed=3)
    s.integrator.run(20)
    core = s._core
    core.reset_comm_stats()
    s.integrator.run(20)
    a2a_run = dict(core.comm_stats())["alltoallv"]
    for pid, x in ((3, 13.3), (40, 2.2), (77, 21.0)):
        p = s.part.by_id(pid)
        p.pos = [x, p.pos[1], p.pos[2]]
    core.reset_comm_stats()
    s.integrator.run(20)
    a2a_teleport = dict(core.comm_stats())["alltoallv"]
    parts = s.part.all()
    return s, dict(ids=parts.id, pos=parts.pos, v=parts.v, f=parts.f,
                   node_grid=np.array(s.cell_system.node_grid),
                   a2a_run=np.array(a2a_run), a2a_teleport=np.array(a2a_teleport))


def scene_rank0_read():
    """The SPMD mistake of doc/parallel.md: a particle read inside
    `if marble.mpi_rank() == 0:` (rank 0 waits for the other ranks in the
    gather, which have left the script): the exit handshake must report it
    and stop every rank (MARBLE_MPI_EXIT_TIMEOUT) instead of hanging."""
    s, _ = _narrow([4.0, 4.0, 4.0], 1.0, steps=2)
    if marble.mpi_rank() == 0:
        return s, dict(pos=s.part.all().pos)
    return s, {}


def _kT_series(s, warmup, samples, every):
    """The kinetic temperature every @p every steps, @p samples times, after @p warmup steps."""
    s.integrator.run(warmup)
    kT = []
    for _ in range(samples):
        s.integrator.run(every)
        kT.append(2.0 / 3.0 * s.analysis.energy()["kinetic"] / len(s.part.all()))
    return np.array(kT)


def scene_temperature():
    """Longer run: observables agree statistically across rank counts."""
    s = fluid(6.0, seed=9)
    return s, dict(kT=_kT_series(s, 200, 60, 20))


def _wca_gas(L=7.0, seed=6):
    """A dilute WCA gas crossing the domain boundaries (implicit solvent)."""
    rng = np.random.default_rng(seed)
    s = marble.System(box_l=[L, L, L])
    s.time_step = 0.005
    s.cell_system.skin = 0.4
    g = np.arange(0, L, L / 5)
    pos = np.array(np.meshgrid(g, g, g)).reshape(3, -1).T + 0.1
    n = len(pos)
    extra = {}
    if marble.has_features("ROTATION"):
        extra["rotation"] = np.arange(n) % 2 == 0
    s.part.add(pos=pos, v=rng.normal(size=(n, 3)), **extra)
    s.non_bonded_inter[0, 0].lennard_jones.set_params(epsilon=1.0, sigma=1.0, cutoff=2**(1 / 6),
                                                      shift="auto")
    return s


def _thermostat_state(s):
    """What the Langevin and Brownian scenes compare: ids, positions,
    velocities, forces (and angular velocities with ROTATION)."""
    parts = s.part.all()
    out = dict(ids=parts.id, pos=parts.pos, v=parts.v, f=parts.f)
    if marble.has_features("ROTATION"):
        out["omega"] = parts.omega_lab
    return out


def scene_langevin():
    """Langevin (per-particle gamma on a subset, rotation) + DPD: 1 vs 2 ranks."""
    s = _wca_gas()
    parts = s.part.all()
    parts.gamma = np.where(np.arange(len(parts)) % 3 == 0, 2.5, -1.0)
    s.thermostat.set_langevin(kT=1.3, gamma=0.7, gamma_rotation=0.9, seed=17)
    if marble.has_features("DPD"):
        s.non_bonded_inter[0, 0].dpd.set_params(weight_function=1, gamma=1.0, k=1.0, r_cut=1.2)
        s.thermostat.set_dpd(kT=1.3, seed=3)
    s.integrator.run(150)
    return s, _thermostat_state(s)


def scene_brownian():
    """Brownian dynamics of the WCA gas: 1 vs 2 ranks."""
    s = _wca_gas(seed=7)
    s.time_step = 0.001
    s.integrator.set_brownian_dynamics()
    s.thermostat.set_brownian(kT=1.0, gamma=2.0, seed=23)
    s.integrator.run(150)
    return s, _thermostat_state(s)


def _srd_state(s, col=None):
    """SRD particles sorted by id (+ the colloid): the state compared across rank counts."""
    ids = np.asarray(s.srd.ids)
    order = np.argsort(ids)
    out = dict(ids=ids[order], pos=s.srd.pos[order], v=s.srd.v[order],
               n_collisions=np.array(s.srd.n_collisions),
               to_colloids=np.asarray(s.srd.momentum_to_colloids()),
               to_walls=np.asarray(s.srd.momentum_to_walls()))
    if col is not None:
        out.update(cpos=np.asarray(col.pos), cv=np.asarray(col.v), comega=np.asarray(col.omega_lab))
    return out


def _srd_box(L=8.0, dt=0.05, seed=11, **kw):
    import marble.srd as srd
    s = marble.System(box_l=[L] * 3, time_step=dt)
    s.cell_system.skin = 0.4
    s.srd = srd.SRDFluid(types=[0], tau=0.1, kT=1.0, seed=seed, **kw)
    srd.add_fluid(s, density=5, type=0, kT=1.0, seed=seed + 1)
    return s


def scene_srd_colloid(collisions=200, rule="srd", **kw):
    """SRD fluid (random grid shift) + a stochastic stick colloid moving
    across the domains: 200 collisions, 1 vs 2 (3) ranks."""
    import marble.srd as srd
    L = 8.0
    s = _srd_box(L, rule=rule, **kw)
    col = srd.add_colloid(s, pos=[L / 2 - 0.3, L / 2, L / 2], radius=1.5, mass=60.0, type=1,
                          rule="stochastic", v=(0.3, 0.2, 0.1))
    col.omega_lab = [0.0, 0.0, 0.2]
    col.ext_force = [6.0, 0.0, 0.0]  # drifts ~1.3 along x: crosses the domain face x = 4
    s.integrator.run(2 * collisions)  # tau = 2 time steps
    return s, _srd_state(s, col)


def scene_srd_at():
    """The same with the angular-momentum conserving Andersen rule (AT+a), 25
    collisions: its 3x3 solve in cells of few particles amplifies round-off
    (differences of 1e-15 grow to ~1e-11 in 40 collisions, to O(1) by 200),
    so only a short run can agree to 1e-9 (doc/srd.md)."""
    return scene_srd_colloid(collisions=25, rule="at", conserve_angular=True, angle=0.0)


def scene_srd_thermo():
    """Rule srd (130 deg) with the cell thermostat."""
    return scene_srd_colloid(angle=130.0, thermostat="mbs")


def scene_srd_fluid(collisions=100):
    """Pure SRD fluid (no colloid: the streaming step lists the particles that
    leave the rank's domain for the next migration) in a 12 x 8 x 8 box
    drifting at (0.9, -0.5, 0.3), so many particles change rank; tau = 2
    time steps."""
    import marble.srd as srd
    s = marble.System(box_l=[12.0, 8.0, 8.0], time_step=0.05)
    s.cell_system.skin = 0.4
    s.srd = srd.SRDFluid(types=[0], tau=0.1, kT=1.0, seed=31, angle=130.0)
    srd.add_fluid(s, density=5, type=0, kT=1.0, seed=32)
    s.srd.v = s.srd.v + np.array([0.9, -0.5, 0.3])
    s.integrator.run(2 * collisions)
    out = _srd_state(s)
    out["node_grid"] = np.array(s.cell_system.node_grid)
    return s, out


def scene_srd_balance():
    """scene_srd_fluid's box, crowded: 2/3 of the SRD particles in the lowest
    third along x; balance(by="particles") counts the SRD particles (there
    are no MD particles); then 40 collisions."""
    import marble.srd as srd
    s = marble.System(box_l=[12.0, 8.0, 8.0], time_step=0.05)
    s.cell_system.skin = 0.4
    s.srd = srd.SRDFluid(types=[0], tau=0.1, kT=1.0, seed=31, angle=130.0)
    srd.add_fluid(s, density=5, type=0, kT=1.0, seed=32)
    pos, ids = np.array(s.srd.pos), np.asarray(s.srd.ids)  # (in rank order: crowd by id)
    pos[ids < 2 * len(ids) // 3, 0] /= 3.0
    s.srd.pos = pos
    s.integrator.run(2)  # (the SRD particles move to their ranks)
    res = s.cell_system.balance(by="particles")
    s.integrator.run(78)
    out = _srd_state(s)
    out.update(imbalance=np.array(res["imbalance"]), moved=np.array(res["moved"]),
               domain_cuts_x=np.asarray(s.cell_system.domain_cuts[0]))
    return s, out


def scene_srd_walls(collisions=100):
    """SRD channel: stochastic walls at z = 1.25 and 7 (inside the box) moving at
    +-0.2 (Couette), split in z on 2 ranks."""
    import marble.srd as srd
    L = 8.0
    s = marble.System(box_l=[4.0, 4.0, L], time_step=0.05)
    s.cell_system.skin = 0.4
    s.srd = srd.SRDFluid(types=[0], tau=0.1, kT=1.0, seed=21, angle=130.0, wall_axis=2,
                         wall_rule="stochastic", wall_velocity_lo=[-0.2, 0, 0],
                         wall_velocity_hi=[0.2, 0, 0], wall_positions=(1.25, 7.0))
    srd.add_fluid(s, density=5, type=0, kT=1.0, seed=22)
    s.integrator.run(2 * collisions)
    out = _srd_state(s)
    out["node_grid"] = np.array(s.cell_system.node_grid)
    return s, out


def scene_srd_walls_colloid(collisions=100):
    """A stochastic stick colloid (pair coupling) 0.7 from the lower of two
    stochastic walls (z = 0, 8; split in z on 2 ranks), driven along x: the
    wall bounces of the colloid's candidates are events of its sequence."""
    import marble.srd as srd
    L = 8.0
    s = _srd_box(L, angle=130.0, wall_axis=2, wall_rule="stochastic", wall_velocity_hi=[0.2, 0, 0])
    col = srd.add_colloid(s, pos=[L / 2 - 0.3, L / 2, 2.2], radius=1.5, mass=30.0, type=1,
                          rule="stochastic", v=(0.3, 0.2, 0.0))
    col.ext_force = [6.0, 0.0, 0.0]
    s.integrator.run(2 * collisions)
    return s, _srd_state(s, col)


def _save_system(s, checkpoint_id):
    """Checkpoint @p s alone (as "system") under MARBLE_CKPT_DIR."""
    import marble.checkpointing
    cp = marble.checkpointing.Checkpoint(checkpoint_id=checkpoint_id, checkpoint_path=_ckpt_dir(),
                                         namespace=dict(system=s))
    cp.register("system")
    cp.save()


def _load_system(checkpoint_id):
    """The System of _save_system's last checkpoint."""
    import marble.checkpointing
    ns = {}
    marble.checkpointing.Checkpoint(checkpoint_id=checkpoint_id, checkpoint_path=_ckpt_dir(), namespace=ns).load()
    return ns["system"]


def scene_srd_ckpt_reference():
    """SRD + colloid: checkpoint after 60 collisions, then 60 more."""
    s, _ = scene_srd_colloid(collisions=60)
    _save_system(s, "srd")
    s.integrator.run(120)
    return s, _srd_state(s)


def scene_srd_ckpt_restart():
    """A new mpiexec (any rank count): load the SRD checkpoint, run 60 collisions."""
    s = _load_system("srd")
    s.integrator.run(120)
    return s, _srd_state(s)


def scene_srd_h5md():
    """SRD + colloid written to H5MD on N ranks (file in MARBLE_CKPT_DIR):
    the /particles/srd rows are the SRD particles by id."""
    import os
    import marble.io
    s, _ = scene_srd_colloid(collisions=10)
    h5 = marble.io.H5md(file_path=os.path.join(_ckpt_dir(), "srd.h5"), system=s)
    h5.write()
    s.integrator.run(4)
    h5.write()
    h5.close()
    return s, _srd_state(s)


# --- domain cuts and load balance (test_mpi_balance.py) ---------------------

def _uneven_cuts(grid, box_l):
    """Fixed uneven domain cuts along every split axis: plane j of p at
    (j / p)^1.4 of the box (narrowest domain first); None along an axis not split."""
    return [None if p == 1 else [float(box_l[d]) * (j / p) ** 1.4 for j in range(p + 1)]
            for d, p in enumerate(grid)]


def _rank_state(s):
    """This rank's locals and its domain, and every particle's position
    (a collective read: the same on every rank)."""
    parts = s.part.all()
    ids = np.array(s.cell_system.local_ids(), dtype=int)
    lo, size = s.cell_system.local_domain()
    cuts = s.cell_system.domain_cuts
    return dict(local_ids=ids, all_ids=parts.id, all_pos=parts.pos, dom_lo=np.asarray(lo), dom_size=np.asarray(size),
                grid=np.array(s.cell_system.node_grid), cuts_x=cuts[0], cuts_y=cuts[1], cuts_z=cuts[2])


def _traj(s):
    parts = s.part.all()
    return dict(ids=parts.id, pos=parts.pos, v=parts.v, f=parts.f)


def scene_cuts_marble():
    """scene_marble's fluid and marble on uneven domains set by hand."""
    s = fluid(8.0)
    s.cell_system.domain_cuts = _uneven_cuts(s.cell_system.node_grid, s.box_l)
    col = marble.colloids.add_marble(s, pos=[8 / 2 - 0.3, 4.0, 4.0], radius=2.0, gamma=5.0)
    col.v = [0.3, 0.1, 0.0]
    s.integrator.run(0)
    at_start = _rank_state(s)
    s.integrator.run(100)
    out = _traj(s)
    out.update(cpos=col.pos, comega=col.omega_lab, energy=s.analysis.energy()["total"])
    out["rank_state"] = at_start
    return s, out


def _crowded_fluid(L=8.0, seed=6):
    """A DPD fluid with two thirds of its particles in the lowest third along x."""
    rng = np.random.default_rng(seed)
    s = marble.System(box_l=[L, L, L])
    s.time_step = 0.01
    s.cell_system.skin = 0.4
    n = int(3 * L**3)
    pos = rng.uniform(0, L, (n, 3))
    pos[: 2 * n // 3, 0] *= 1 / 3
    s.part.add(pos=pos, v=rng.normal(size=(n, 3)))
    s.non_bonded_inter[0, 0].dpd.set_params(weight_function=1, gamma=5.0, k=1.0, r_cut=1.0)
    s.thermostat.set_dpd(kT=1.0, seed=3)
    return s


def scene_balance_particles(by="particles"):
    """balance(by=@p by) of a crowded fluid, then 50 steps."""
    s = _crowded_fluid()
    s.integrator.run(0)
    before = len(s.cell_system.local_ids())
    res = s.cell_system.balance(by=by)
    s.integrator.run(0)
    state = _rank_state(s)
    state["n_before"] = np.array(before)
    s.integrator.run(50)
    out = _traj(s)
    out.update(imbalance=np.array(res["imbalance"]), moved=np.array(res["moved"]), rank_state=state)
    return s, out


def scene_balance_pairs():
    return scene_balance_particles(by="pairs")


def scene_balance_auto(shardlow=False):
    """The crowded fluid with the automatic balance by time every 10 steps
    (threshold 0: every balance moves the planes); velocity Verlet, or
    Shardlow (whose sweep order, and so its trajectory, depends on the
    decomposition: its momentum and the domains' width are checked)."""
    s = _crowded_fluid(seed=7)
    if shardlow:
        s.time_step = 0.04
        s.integrator.set_shardlow()
    s.cell_system.set_load_balance(10, by="time", damping=0.5, threshold=0.0)
    p0 = s.analysis.linear_momentum()
    s.integrator.run(60)
    s.integrator.run(0)
    out = _traj(s)
    out.update(n_balances=np.array(s.cell_system.get_load_balance()["n_balances"]), rank_state=_rank_state(s),
               dp=np.asarray(s.analysis.linear_momentum()) - np.asarray(p0))
    return s, out


def scene_balance_auto_shardlow():
    return scene_balance_auto(shardlow=True)


def _balance_ckpt_out(s):
    s.integrator.run(0)
    out = _traj(s)
    lb = s.cell_system.get_load_balance()
    out.update(n_balances=np.array(lb["n_balances"]), every=np.array(lb["every"]), by=np.array(lb["by"]))
    return out


def scene_balance_ckpt_reference():
    """The crowded fluid balanced automatically by pairs every 10 steps
    (deterministic): checkpoint after 35 steps, then 35 more (the reference;
    balances at steps 10-70)."""
    s = _crowded_fluid(seed=8)
    s.cell_system.set_load_balance(10, by="pairs", damping=0.5, threshold=0.0)
    s.integrator.run(35)
    _save_system(s, "balance")
    s.integrator.run(35)
    return s, _balance_ckpt_out(s)


def scene_balance_ckpt_restart():
    """A new mpiexec that sets no balance: load the checkpoint, run 35 steps."""
    s = _load_system("balance")
    s.integrator.run(35)
    return s, _balance_ckpt_out(s)


def scene_cuts_bad():
    """Bad cuts on N >= 2 ranks: each a ValueError, nothing changed; then
    Shardlow refused on a domain narrower than twice the pair range."""
    s = fluid(8.0)
    L, p = 8.0, s.cell_system.node_grid[0]
    good = [L * j / p for j in range(p + 1)]
    msgs = []
    for bad in ([list(np.linspace(0, L, p + 2)), None, None],  # one position too many
                [[0.0] * p + [L], None, None],  # an empty domain
                [[0.5] + good[1:], None, None],  # not from 0
                [good[:-1] + [L + 1], None, None],  # not to box_l
                [good, None],  # two entries
                "x"):
        try:
            s.cell_system.domain_cuts = bad
            msgs.append("no error")
        except ValueError as e:
            msgs.append(str(e))
    unchanged = np.array([np.asarray(c) for c in s.cell_system.domain_cuts][0])
    s.cell_system.domain_cuts = [[0.0, 2.0] + [2.0 + (L - 2.0) * j / (p - 1) for j in range(1, p)], None, None]
    s.integrator.set_shardlow()
    msgs.append(_run_error(s, 1))
    return s, dict(msgs=np.array(msgs), unchanged=unchanged)


def _with_uneven_cuts():
    """Make every integrator.run() of this process use _uneven_cuts' planes
    (set again where the node grid changed, e.g. when Lees-Edwards turned on):
    the scenes run as "cuts_of_SCENE" on uneven domains."""
    import marble.integrate
    run = marble.integrate.Integrator.run

    def run_on_uneven_domains(self, *args, **kwargs):
        core = self._core
        want = _uneven_cuts(core.node_grid(), core.box_l)
        if [list(c) for c in core.domain_cuts()] != [c or [0.0, float(L)] for c, L in zip(want, core.box_l)]:
            core.set_domain_cuts([c or [] for c in want])
        return run(self, *args, **kwargs)

    marble.integrate.Integrator.run = run_on_uneven_domains


if __name__ == "__main__":
    name, path = sys.argv[1], sys.argv[2]
    if name.startswith("cuts_of_"):
        name = name[len("cuts_of_"):]
        _with_uneven_cuts()
    system, data = globals()["scene_" + name]()
    for axis, cuts in zip("xyz", system.cell_system.domain_cuts):
        data["domain_cuts_" + axis] = cuts
    data["ranks"] = np.array(marble.mpi_size())
    rank_state = data.pop("rank_state", None)
    if rank_state is not None:  # every rank's own state, in a file of its own
        np.savez(f"{path}.rank{marble.mpi_rank()}.npz", **rank_state)
    if marble.mpi_rank() == 0:
        np.savez(path, **data)
