"""Scene and state dump shared by test_checkpoint.py and the restart process
it starts (doc/io.md): DPD solvent (hat + DPD), one marble colloid (with
MARBLE), a multiple-tau correlator and a mean/variance calculator in
auto_update."""
import numpy as np

import marble
import marble.accumulators
import marble.observables

L = 6.0
N_SOLVENT = 500


def make_scene(integrator="vv", seed=5):
    rng = np.random.default_rng(seed)
    s = marble.System(box_l=[L, L, L])
    s.time_step = 0.01
    s.cell_system.skin = 0.3
    v = rng.normal(size=(N_SOLVENT, 3))
    s.part.add(pos=rng.uniform(0, L, size=(N_SOLVENT, 3)), v=v - v.mean(axis=0))
    if marble.has_features("HAT"):
        s.non_bonded_inter[0, 0].hat.set_params(F_max=25.0, cutoff=1.0)
    s.non_bonded_inter[0, 0].dpd.set_params(weight_function=1, gamma=4.5, k=1.0, r_cut=1.0)
    s.thermostat.set_dpd(kT=1.0, seed=seed)
    ids = []
    if marble.has_features("MARBLE"):
        from marble.colloids import add_marble
        col = add_marble(s, pos=[3.0, 3.0, 3.0], radius=1.5, gamma=5.0)
        ids.append(int(col.id))
    getattr(s.integrator, "set_" + integrator)()
    solvent = [int(i) for i in s.part.select(type=0).id]  # add_marble removed the overlaps
    ids += solvent[:3]
    vel = marble.observables.ParticleVelocities(ids=ids, system=s)
    corr = marble.accumulators.Correlator(obs1=vel, tau_lin=8, tau_max=0.4, delta_N=1,
                                          corr_operation="componentwise_product")
    com = marble.observables.ComVelocity(ids=solvent[:20], system=s)
    mv = marble.accumulators.MeanVarianceCalculator(obs=com, delta_N=2)
    s.auto_update_accumulators.add(corr)
    s.auto_update_accumulators.add(mv)
    s.integrator.run(0)
    return s, corr, mv


def dump(s, corr, mv):
    """Every quantity compared bit for bit."""
    p = s.part.all()
    out = dict(id=p.id, pos=p.pos, v=p.v, f=p.f, image=p.image_box,
               corr=corr.result(), corr_n=np.asarray(corr.sample_sizes()),
               mean=mv.mean(), var=mv.variance(),
               time=np.array([s.time]), step=np.array([s.step]),
               counter=np.array([s.thermostat.dpd.philox_counter]))
    if marble.has_features("ROTATION"):
        out.update(omega=p.omega_lab, torque=p.torque_lab)
    return out
