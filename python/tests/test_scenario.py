"""Scenarios from Python: a shipped scenario run for a short time, its logs as NumPy
arrays of the right length, its metrics as a dict; a mistake in a scenario file raises
InputError at its file:line:column."""
import pathlib
import re
import tempfile
import unittest

import numpy as np

import dmbd

EXAMPLES = pathlib.Path(__file__).resolve().parents[2] / "examples"
DATA = pathlib.Path(__file__).resolve().parent / "data"


class PositionControllers(unittest.TestCase):
    DURATION = 1.0  # s (the scenario's 7.5 s cut short): the 0.3 rad step at 0.5 s and its rise; logged at 1 kHz

    @classmethod
    def setUpClass(cls):
        cls.out = tempfile.TemporaryDirectory()
        cls.result = dmbd.run_scenario(EXAMPLES / "scenarios" / "position_controllers.yaml", duration_s=cls.DURATION,
                                    out_dir=cls.out.name)

    @classmethod
    def tearDownClass(cls):
        cls.out.cleanup()

    def test_variants(self):
        self.assertEqual(self.result.name, "position_controllers")
        self.assertEqual(self.result.variants, ["encoder", "potentiometer", "encoder_force"])

    def test_logs_are_arrays_of_the_run_length(self):
        for variant in self.result.variants:
            with self.subTest(variant):
                log = self.result.log(variant)
                t = log["t"]
                self.assertIsInstance(t, np.ndarray)
                self.assertEqual(len(t), round(self.DURATION * 1000) + 1)
                self.assertAlmostEqual(t[0], 0.0)
                self.assertAlmostEqual(t[-1], self.DURATION, places=9)
                self.assertTrue(np.all(np.diff(t) > 0))
                for name, values in log.items():
                    self.assertEqual(values.shape, t.shape, name)
                q = log["l_knee.q"]
                self.assertTrue(np.all(np.isfinite(q)))
                # The knee starts bent at 1 rad (robot.initial); the reference steps to
                # 1.3 rad at 0.5 s, and every controller has followed it by 1 s.
                self.assertAlmostEqual(q[0], 1.0, places=3)
                np.testing.assert_allclose(log["q_total"][[0, 499, 501, -1]], [1.0, 1.0, 1.3, 1.3])
                self.assertLess(abs(q[-1] - 1.3), 0.02)
                self.assertEqual(self.result.units(variant)["t"], "s")
                self.assertEqual(self.result.units(variant)["l_knee.q"], "rad")

    def test_metrics_are_a_dict(self):
        m = self.result.metrics
        self.assertIsInstance(m, dict)
        for variant in self.result.variants:
            figures = m["controllers"][variant]
            self.assertGreater(figures["rise_time_s"], 0.0)
            self.assertLess(figures["rise_time_s"], 0.5)
            # The sinusoid window (3.5 s to 7.5 s) was not reached: NaN, and a warning.
            self.assertTrue(np.isnan(figures["rms_error_rad"]))
            self.assertEqual(m["runs"][variant]["duration_s"], self.DURATION)
        self.assertTrue(any("ends at 1 s" in w for w in self.result.warnings), self.result.warnings)
        self.assertEqual(len(self.result.runs), 3)
        self.assertEqual([r["name"] for r in self.result.runs], self.result.variants)
        self.assertTrue(all(r["wall_s"] > 0 for r in self.result.runs))

    def test_run_directory(self):
        self.assertEqual(self.result.out_dir, self.out.name)
        self.assertIn("log.csv", self.result.files)
        self.assertIn("metrics.json", self.result.files)
        self.assertTrue((pathlib.Path(self.out.name) / "metrics.json").is_file())

    def test_variant_must_be_named(self):
        with self.assertRaisesRegex(KeyError, "encoder, potentiometer, encoder_force"):
            self.result.log()
        with self.assertRaisesRegex(KeyError, "no variant 'fast'"):
            self.result.log("fast")


class Mistakes(unittest.TestCase):
    def test_scenario_error_carries_file_line_column(self):
        path = str(DATA / "bad_scenario.yaml")
        with self.assertRaises(dmbd.InputError) as cm:
            dmbd.run_scenario(path)
        self.assertRegex(str(cm.exception), re.escape(path) + r":4:\d+: .*duration_s")

    def test_duration_must_be_positive(self):
        with self.assertRaisesRegex(dmbd.InputError, "duration_s"):
            dmbd.run_scenario(EXAMPLES / "scenarios" / "position_controllers.yaml", duration_s=-1.0)


if __name__ == "__main__":
    unittest.main()
