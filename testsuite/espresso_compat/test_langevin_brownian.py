"""The Langevin thermostat and Brownian dynamics called as ESPResSo 4.2 test
scripts call them: set_langevin / set_brownian, per-particle gamma
(THERMOSTAT_PER_PARTICLE), rotation, set_brownian_dynamics, the friction-only
limits (kT = 0) against the analytic solutions, turn_off and the refused
integrator/thermostat combinations."""
import unittest as ut

import numpy as np
import unittest_decorators as utx

import espressomd


def scheme_rtol(rate, dt, t):
    """Relative deviation of velocity Verlet with friction on the half-step
    velocity from exp(-rate t): (1 - a)^k vs exp(-a k), a = rate dt, k = t / dt,
    ~ k a^2 / 2; twice that as the tolerance."""
    return rate**2 * dt * t + 1e-6


class LangevinBrownian(ut.TestCase):

    system = espressomd.System(box_l=3 * [10.0])
    system.time_step = 0.01
    system.cell_system.skin = 0.4

    def tearDown(self):
        self.system.part.clear()
        self.system.thermostat.turn_off()
        self.system.integrator.set_vv()
        self.system.time = 0.0

    def test_00_seed_required(self):
        with self.assertRaises(ValueError):
            espressomd.System(box_l=3 * [5.0]).thermostat.set_langevin(kT=1.0, gamma=1.0)
        with self.assertRaises(ValueError):
            espressomd.System(box_l=3 * [5.0]).thermostat.set_brownian(kT=1.0, gamma=1.0)

    def test_01_langevin_friction_trans(self):
        system = self.system
        gamma = 2.0
        system.thermostat.set_langevin(kT=0.0, gamma=gamma, seed=41)
        v0 = np.array([5.0, 5.0, 5.0])
        p = system.part.add(pos=[0, 0, 0], v=v0)
        system.time = 0.0
        for _ in range(40):
            system.integrator.run(5)
            t = system.time
            np.testing.assert_allclose(p.v, v0 * np.exp(-gamma * t),
                                       rtol=scheme_rtol(gamma, system.time_step, t))
        state = system.thermostat.get_state()
        self.assertEqual(state[0]["type"], "LANGEVIN")
        self.assertEqual(state[0]["seed"], 41)

    @utx.skipIfMissingFeatures(["THERMOSTAT_PER_PARTICLE", "MASS"])
    def test_02_per_particle_gamma_and_mass(self):
        system = self.system
        system.thermostat.set_langevin(kT=0.0, gamma=2.0, seed=41)
        v0 = np.array([1.0, -2.0, 3.0])
        p_glob = system.part.add(pos=[0, 0, 0], v=v0, mass=2.0)
        p_own = system.part.add(pos=[5, 5, 5], v=v0, gamma=0.5)
        self.assertEqual(p_own.gamma, 0.5)
        system.time = 0.0
        system.integrator.run(100)
        t = system.time
        dt = system.time_step
        np.testing.assert_allclose(p_glob.v, v0 * np.exp(-2.0 / 2.0 * t), rtol=scheme_rtol(1.0, dt, t))
        np.testing.assert_allclose(p_own.v, v0 * np.exp(-0.5 * t), rtol=scheme_rtol(0.5, dt, t))

    @utx.skipIfMissingFeatures("ROTATION")
    def test_03_langevin_friction_rot(self):
        system = self.system
        system.thermostat.set_langevin(kT=0.0, gamma=1.0, gamma_rotation=3.0, seed=41)
        o0 = np.array([2.0, 1.0, -1.0])
        p = system.part.add(pos=[0, 0, 0], rotation=[True, True, True], omega_body=o0,
                            rinertia=[2.0, 2.0, 2.0])
        system.time = 0.0
        system.integrator.run(100)
        t = system.time
        np.testing.assert_allclose(p.omega_body, o0 * np.exp(-3.0 / 2.0 * t),
                                   rtol=scheme_rtol(1.5, system.time_step, t))

    @utx.skipIfMissingFeatures("EXTERNAL_FORCES")
    def test_04_brownian_friction_trans(self):
        system = self.system
        system.integrator.set_brownian_dynamics()
        system.thermostat.set_brownian(kT=0.0, gamma=4.0, seed=42)
        f = np.array([1.0, -2.0, 0.5])
        p = system.part.add(pos=[1, 1, 1], ext_force=f)
        x0 = np.copy(p.pos)
        system.time = 0.0
        system.integrator.run(50)
        np.testing.assert_allclose(p.v, f / 4.0, atol=1e-12)
        np.testing.assert_allclose(p.pos - x0, f / 4.0 * system.time, atol=1e-10)

    def test_05_bd_requires_bd_thermostat(self):
        system = self.system
        system.part.add(pos=[1, 1, 1])
        system.integrator.set_brownian_dynamics()
        with self.assertRaises(RuntimeError):
            system.integrator.run(1)
        system.thermostat.set_langevin(kT=1.0, gamma=1.0, seed=1)
        with self.assertRaises(RuntimeError):
            system.integrator.run(1)
        system.thermostat.turn_off()
        system.thermostat.set_brownian(kT=1.0, gamma=1.0, seed=1)
        system.integrator.run(1)
        system.integrator.set_vv()
        with self.assertRaises(RuntimeError):
            system.integrator.run(1)

    def test_06_brownian_diffusion(self):
        system = self.system
        system.cell_system.skin = 1.0
        n = 500
        rng = np.random.default_rng(4)
        parts = system.part.add(pos=rng.uniform(0, 10, (n, 3)))
        system.integrator.set_brownian_dynamics()
        system.thermostat.set_brownian(kT=1.0, gamma=2.0, seed=42)
        x0 = np.copy(parts.pos)
        system.integrator.run(200)
        msd = np.sum((parts.pos - x0) ** 2, axis=1)
        # 6 D t with D = kT / gamma; the MSD of one particle has relative std sqrt(2/3)
        self.assertAlmostEqual(msd.mean() / (6 * 0.5 * 200 * 0.01), 1.0,
                               delta=4 * np.sqrt(2 / 3 / n))
        system.cell_system.skin = 0.4


if __name__ == "__main__":
    ut.main()
