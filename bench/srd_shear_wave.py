"""SRD shear viscosity from the decay of a transverse momentum wave, with and
without the MBS cell thermostat (doc/srd.md, "The 90 deg excess"): a wave
v_x = A sin(k z), k = 2 pi/Lz, laid on an equilibrium fluid (box 8 x 8 x 32,
density 5, tau = dt = 0.1) decays as exp(-nu k^2 t); nu from the mean
amplitude of n independent runs (each run once without and once with the
thermostat, the same seeds), jackknife errors, compared with
nu_kin + nu_col (reference.md section 6).

    build/pymarble bench/srd_shear_wave.py 90 150     # angle, runs (~1 CPU-s per run)
"""
import sys, time
import numpy as np
import marble, marble.srd as srd
angle = float(sys.argv[1]); nrun = int(sys.argv[2])
Lx, Lz, tau, A = 8.0, 32.0, 0.1, 0.2
k = 2 * np.pi / Lz
nu_th = srd.nu_kin(5, angle, tau) + srd.nu_col(5, angle, tau)
T = 1.2 / (nu_th * k * k)
nsamp = 24
ts = np.linspace(0, T, nsamp + 1)
steps = np.round(ts / tau).astype(int)
amps = {t: np.zeros((nrun, nsamp + 1)) for t in ("none", "mbs")}
t0 = time.process_time()
for r in range(nrun):
    for thermo in ("none", "mbs"):
        s = marble.System(box_l=[Lx, Lx, Lz], time_step=tau)
        s.srd = srd.SRDFluid(types=[0], tau=tau, angle=angle, kT=1.0, seed=500 + r, thermostat=thermo)
        srd.add_fluid(s, density=5, type=0, kT=1.0, seed=5000 + r)
        v = s.srd.v; z = s.srd.pos[:, 2]
        v[:, 0] += A * np.sin(k * z)
        s.srd.v = v
        for j in range(nsamp + 1):
            if j:
                s.integrator.run(int(steps[j] - steps[j - 1]))
            amps[thermo][r, j] = 2 * np.mean(s.srd.v[:, 0] * np.sin(k * s.srd.pos[:, 2]))
use = (ts > 0.1 * T) & (amps["none"].mean(axis=0) > 0.25 * A)
def nu(a):
    return -np.polyfit(ts[use], np.log(a.mean(axis=0)[use]), 1)[0] / k ** 2
def jk(f):
    full = f(np.arange(nrun))
    rr = np.array([f(np.delete(np.arange(nrun), i)) for i in range(nrun)])
    return full, np.sqrt((nrun - 1) * np.var(rr))
n0 = jk(lambda idx: nu(amps["none"][idx]))
n1 = jk(lambda idx: nu(amps["mbs"][idx]))
d = jk(lambda idx: nu(amps["mbs"][idx]) / nu(amps["none"][idx]) - 1)
print(f"angle {angle} runs {nrun}: nu none {n0[0]:.4f} +/- {n0[1]:.4f} (ratio {n0[0]/nu_th:.4f}), mbs {n1[0]:.4f} +/- {n1[1]:.4f} "
      f"(ratio {n1[0]/nu_th:.4f}); mbs/none - 1 = {d[0]:+.4f} +/- {d[1]:.4f}; theory {nu_th:.4f} ({time.process_time()-t0:.0f} CPU-s)")
