"""Feature queries and module names as an ESPResSo 4.2 script uses them."""
import importlib
import unittest as ut

import espressomd
import espressomd.accumulators
import espressomd.code_info
import espressomd.galilei
import espressomd.observables
import marble


class CodeFeatures(ut.TestCase):

    def test_modules_import(self):
        for name in ("interactions", "observables", "accumulators", "galilei", "checkpointing",
                     "io", "code_features", "code_info", "shapes", "constraints", "integrate", "thermostat",
                     "analysis", "cell_system", "particle_data", "system"):
            mod = importlib.import_module("espressomd." + name)
            self.assertIs(getattr(espressomd, name, mod), mod)
        self.assertIs(espressomd.observables.ParticlePositions,
                      marble.observables.ParticlePositions)
        self.assertIs(espressomd.accumulators.Correlator, marble.accumulators.Correlator)
        self.assertIs(espressomd.galilei.GalileiTransform, marble.galilei.GalileiTransform)
        self.assertIs(espressomd.System, marble.System)
        self.assertIs(espressomd.FeaturesError, marble.FeaturesError)
        from espressomd.checkpointing import Checkpoint
        self.assertIs(Checkpoint, marble.checkpointing.Checkpoint)

    def test_h5md_writer_path(self):
        from espressomd.io.writer import h5md
        self.assertIs(h5md.H5md, marble.io.H5md)
        if not marble.io.have_hdf5():
            return
        import os
        import tempfile
        system = espressomd.System(box_l=[3.0, 3.0, 3.0])
        system.part.add(pos=[[0.5, 0.5, 0.5], [1.5, 1.0, 1.0]])
        with tempfile.TemporaryDirectory() as tmp:
            path = os.path.join(tmp, "traj.h5")
            h5 = h5md.H5md(file_path=path, system=system)
            h5.write()
            h5.write()
            self.assertEqual(h5.n_frames, 2)
            h5.close()
            self.assertGreater(os.path.getsize(path), 0)

    def test_espresso_names(self):
        compiled = marble.features()
        self.assertEqual(espressomd.has_features("EXTERNAL_FORCES"), "EXTERNAL_FORCE" in compiled)
        if "EXTERNAL_FORCE" in compiled:
            self.assertIn("EXTERNAL_FORCES", espressomd.features())
            self.assertNotIn("EXTERNAL_FORCE", espressomd.features())
        for name in ("LENNARD_JONES", "DPD", "ROTATION", "MASS"):
            self.assertEqual(espressomd.has_features(name), name in compiled, name)
            self.assertEqual(espressomd.code_features.has_features(name), name in compiled)
        self.assertTrue(espressomd.has_features(espressomd.features()))
        self.assertEqual(espressomd.code_info.features(), espressomd.features())
        self.assertEqual(espressomd.missing_features(espressomd.features()), [])
        self.assertEqual(set(espressomd.features()) <= set(espressomd.all_features()), True)

    def test_unknown_names_are_missing(self):
        for name in ("ELECTROSTATICS", "VIRTUAL_SITES_RELATIVE", "LB_WALBERLA", "WCA"):
            self.assertFalse(espressomd.has_features(name))
            self.assertFalse(espressomd.has_features(["DPD", name]))
            self.assertFalse(marble.has_features(name))
            self.assertEqual(espressomd.missing_features("DPD", name)[-1], name)
            self.assertEqual(espressomd.missing_features([name]), [name])
            with self.assertRaisesRegex(espressomd.FeaturesError, name):
                espressomd.assert_features(name)
        self.assertTrue(espressomd.has_features())

    def test_non_string_is_an_error(self):
        for bad in (1, None, 2.5):
            with self.assertRaisesRegex(ValueError, "feature names must be strings"):
                espressomd.has_features(bad)
            with self.assertRaisesRegex(ValueError, "feature names must be strings"):
                espressomd.missing_features(["DPD", bad])


if __name__ == "__main__":
    ut.main()
