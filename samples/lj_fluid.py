"""Lennard-Jones liquid: the LAMMPS ``bench/in.lj`` set-up, scaled down.

An fcc lattice at number density rho = 0.8442 (LJ units, eps = sigma = m = 1)
melts from initial velocities at T = 1.44; LJ cutoff 2.5 sigma with the energy
shifted to zero there, time step 0.005, Verlet skin 0.3. LAMMPS runs 32000
atoms for 100 steps; the default here is 4000 atoms (10^3 fcc cells) for 2000
steps, which takes a few seconds. The script prints temperature, energies and
pressure every few hundred steps and the speed in particle-steps per second.

Checks at step 0 (a perfect lattice, so the numbers do not depend on the box
size): the potential energy against a direct lattice sum done here in numpy,
and the pressure against the step-0 line of the LAMMPS benchmark log
(Press = -5.0197073; the cutoff shift does not change forces, so it applies).

    build/pymarble samples/lj_fluid.py [--cells 10] [--steps 2000]

With MARBLE_SAMPLE_TEST=1 (the ctest run) it uses 500 atoms and 200 steps.
"""
import argparse
import os
import time

import numpy as np

import marble

short = os.environ.get("MARBLE_SAMPLE_TEST") == "1"
parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
parser.add_argument("--cells", type=int, default=5 if short else 10,
                    help="fcc unit cells per box edge (4 atoms each)")
parser.add_argument("--steps", type=int, default=200 if short else 2000)
parser.add_argument("--every", type=int, default=100 if short else 250,
                    help="print every this many steps")
args = parser.parse_args()

marble.assert_features("LENNARD_JONES")

RHO, T0, DT, SKIN = 0.8442, 1.44, 0.005, 0.3
EPS, SIG, RCUT = 1.0, 1.0, 2.5

# fcc lattice: 4 atoms per cubic cell of edge a, rho = 4 / a^3.
a = (4.0 / RHO) ** (1.0 / 3.0)
n = args.cells
basis = np.array([[0, 0, 0], [0.5, 0.5, 0], [0.5, 0, 0.5], [0, 0.5, 0.5]])
cells = np.stack(np.meshgrid(np.arange(n), np.arange(n), np.arange(n), indexing="ij"),
                 axis=-1).reshape(-1, 3)
pos = ((cells[:, None, :] + basis[None, :, :]) * a).reshape(-1, 3)
N = len(pos)
L = n * a

# Gaussian velocities (fixed seed), zero total momentum, scaled to T0 exactly
# (T = sum m v^2 / (3 N), as system.analysis.kinetic_temperature()).
rng = np.random.default_rng(87287)
vel = rng.normal(size=(N, 3))
vel -= vel.mean(axis=0)
vel *= np.sqrt(3 * N * T0 / np.sum(vel**2))

system = marble.System(box_l=[L, L, L])
system.time_step = DT
system.cell_system.skin = SKIN
system.part.add(pos=pos, v=vel)
system.non_bonded_inter[0, 0].lennard_jones.set_params(
    epsilon=EPS, sigma=SIG, cutoff=RCUT, shift="auto")
shift = system.non_bonded_inter[0, 0].lennard_jones.get_params()["shift"]

print(f"LJ fluid: N = {N}, box {L:.4f}^3, rho = {N / L**3:.4f}, T0 = {T0}, "
      f"dt = {DT}, r_cut = {RCUT}, skin = {SKIN}, {args.steps} steps")
print(f"features: {' '.join(marble.features())}")


def lattice_energy_per_atom(shift):
    """LJ energy per atom of the perfect fcc lattice, summed directly."""
    m = int(np.ceil(RCUT / a)) + 1
    r = np.arange(-m, m + 1)
    c = np.stack(np.meshgrid(r, r, r, indexing="ij"), axis=-1).reshape(-1, 3)
    sites = ((c[:, None, :] + basis[None, :, :]) * a).reshape(-1, 3)
    d = np.linalg.norm(sites, axis=1)
    d = d[(d > 0) & (d < RCUT)]
    return 0.5 * np.sum(4 * EPS * ((SIG / d) ** 12 - (SIG / d) ** 6 + shift))


def report(step, elapsed):
    e = system.analysis.energy()
    p = system.analysis.pressure()
    T = system.analysis.kinetic_temperature()
    rate = f"{step * N / elapsed:12.4g}" if elapsed > 0 else f"{'-':>12}"
    print(f"{step:6d} {T:9.5f} {e['non_bonded'] / N:11.6f} {e['total'] / N:11.6f} "
          f"{p['total']:11.6f} {rate}")
    return e, p


system.integrator.run(0)  # forces of the initial configuration
print(f"{'step':>6} {'T':>9} {'E_pair/N':>11} {'E_tot/N':>11} {'P':>11} {'part-steps/s':>12}")
e0, p0 = report(0, 0.0)

# Step-0 checks. LAMMPS (bench/in.lj, 32000 atoms) prints at step 0
# E_pair = -6.7733681 (unshifted LJ) and Press = -5.0197073; its kinetic
# pressure counts 3N-3 degrees of freedom, 1.2e-5 relative below ours.
e_direct = lattice_energy_per_atom(shift)
print(f"step 0: E_pair/N = {e0['non_bonded'] / N:.7f}, direct lattice sum {e_direct:.7f}; "
      f"unshifted lattice sum {lattice_energy_per_atom(0.0):.7f} (LAMMPS: -6.7733681)")
p_lammps_dof = p0["total"] - RHO * T0 / 32000
print(f"step 0: P = {p0['total']:.7f}, with LAMMPS's 3N-3 kinetic term for N = 32000: "
      f"{p_lammps_dof:.7f} (LAMMPS: -5.0197073)")
assert abs(e0["non_bonded"] / N - e_direct) < 1e-8, "lattice energy mismatch"

elapsed = 0.0
done = 0
while done < args.steps:
    k = min(args.every, args.steps - done)
    t = time.perf_counter()
    system.integrator.run(k)
    elapsed += time.perf_counter() - t
    done += k
    e, p = report(done, elapsed)

drift = (e["total"] - e0["total"]) / N
print(f"energy drift per atom over {done} steps: {drift:+.2e} (E_tot/N at step 0: "
      f"{e0['total'] / N:.6f})")
print(f"Verlet list rebuilds: {system.cell_system.get_state()['verlet_rebuilds']}")
print(f"speed: {done * N / elapsed:.4g} particle-steps/s ({elapsed:.2f} s in integrator.run)")
assert np.isfinite(e["total"]), "non-finite energy"
assert abs(drift) < 0.01, "total energy not conserved"
