"""Code generation from Python: the header of `dmbd codegen` for a diagram and for a
transfer function; the generated loop compiled and run against dmbd's own step response
of the discretised transfer function."""
import os
import pathlib
import shutil
import subprocess
import tempfile
import unittest
import warnings

import numpy as np

import dmbd

EXAMPLES = pathlib.Path(__file__).resolve().parents[2] / "examples"
DATA = pathlib.Path(__file__).resolve().parent / "data"


class Diagram(unittest.TestCase):
    def test_header_of_an_example_diagram(self):
        header = dmbd.generate_code(EXAMPLES / "diagrams" / "dob_controller.yaml", rate_hz=2000)
        self.assertIn("namespace dob_controller {", header)
        self.assertIn("class Controller", header)
        self.assertIn("kSampleTime = 0.0005", header)

    def test_name_scalar_and_parameters(self):
        with self.assertWarnsRegex(UserWarning, "pi_1k: .*loop with direct feedthrough"):
            header = dmbd.generate_code(str(DATA / "pi_loop.yaml"), rate_hz=1000, name="pi_1k", scalar="float",
                                        params={"Kp": 1.5})
        self.assertIn("namespace pi_1k {", header)
        self.assertIn("float", header)
        self.assertIn("the diagram " + str(DATA / "pi_loop.yaml"), header)

    def test_fixed_point(self):
        header = dmbd.generate_code(EXAMPLES / "diagrams" / "dob_controller.yaml", rate_hz=2000, scalar="fixed",
                                    word_bits=16)
        self.assertIn("namespace dob_controller {", header)
        self.assertIn("int16_t", header)

    def test_mistakes(self):
        with self.assertRaisesRegex(dmbd.InputError, "expected a C\\+\\+ identifier"):
            dmbd.generate_code(DATA / "pi_loop.yaml", rate_hz=1000, name="pi-loop")
        with self.assertRaisesRegex(dmbd.InputError, "scalar 'half'"):
            dmbd.generate_code(DATA / "pi_loop.yaml", rate_hz=1000, scalar="half")
        with self.assertRaises(dmbd.InputError):
            dmbd.generate_code(DATA / "pi_loop.yaml", rate_hz=1000, method="forward")
        with self.assertRaises(dmbd.DiagramError):
            dmbd.generate_code(DATA / "bad_diagram.yaml", rate_hz=1000)


# The command line of the same build (build/apps/dmbd next to build/python/dmbd).
DMBD_CLI = pathlib.Path(dmbd.__file__).resolve().parents[2] / "apps" / "dmbd"


class COutput(unittest.TestCase):
    """generate_code(..., language="c") returns (and writes) the files of `dmbd codegen
    --language c`, byte for byte: the same diagram file given to both as the same text."""

    CASES = [  # (diagram, rate, extra generate_code keywords, the same as CLI options)
        ("dob_controller.yaml", 2000, {}, []),
        ("force_dob.yaml", 1000, {"scalar": "float", "name": "fdob"}, ["--scalar", "float", "--name", "fdob"]),
        ("dob_controller.yaml", 2000, {"scalar": "fixed", "word_bits": 16}, ["--scalar", "fixed", "--word", "16"]),
        ("joint_pd_torque.yaml", 5000, {"method": "zoh", "params": {"Kp": 300}},
         ["--method", "zoh", "--param", "Kp=300"]),
    ]

    def cli_files(self, diagram, rate, options, out):
        subprocess.run([str(DMBD_CLI), "codegen", diagram, "--rate", str(rate), "--language", "c", "--out", str(out),
                        *options], check=True, capture_output=True)
        return {p.name: p.read_bytes() for p in pathlib.Path(out).iterdir() if p.suffix in (".h", ".c")}

    def test_same_bytes_as_the_command_line(self):
        if not DMBD_CLI.exists():
            self.skipTest(f"no command line at {DMBD_CLI}")
        for diagram, rate, kw, options in self.CASES:
            path = str(EXAMPLES / "diagrams" / diagram)
            with self.subTest(diagram=diagram, options=options), tempfile.TemporaryDirectory() as cli_dir, \
                    tempfile.TemporaryDirectory() as py_dir:
                want = self.cli_files(path, rate, options, cli_dir)
                self.assertEqual(len(want), 2, want.keys())
                with warnings.catch_warnings():
                    warnings.simplefilter("ignore")
                    got = dmbd.generate_code(path, rate_hz=rate, language="c", out_dir=py_dir, **kw)
                self.assertEqual({k: v.encode() for k, v in got.items()}, want)
                written = {p.name: p.read_bytes() for p in pathlib.Path(py_dir).iterdir()}
                self.assertEqual(written, want)

    def test_c_mistakes(self):
        with self.assertRaisesRegex(dmbd.InputError, "language 'fortran': expected cpp or c"):
            dmbd.generate_code(DATA / "pi_loop.yaml", rate_hz=1000, language="fortran")
        with self.assertRaisesRegex(dmbd.InputError, "out_dir .*not a directory"), warnings.catch_warnings():
            warnings.simplefilter("ignore")  # pi_loop's algebraic-loop warning
            dmbd.generate_code(DATA / "pi_loop.yaml", rate_hz=1000, language="c", out_dir=DATA / "missing")


class TransferFunction(unittest.TestCase):
    G = "wc^2/(s^2 + sqrt(2)*wc*s + wc^2)"

    def test_warning_above_nyquist(self):
        g = dmbd.tf("1/(s/5000 + 1)")
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            header = dmbd.generate_code(g, rate_hz=1000, name="fast")
        self.assertIn("namespace fast {", header)
        self.assertTrue(any("Nyquist" in str(w.message) for w in caught), [str(w.message) for w in caught])

    def test_generated_loop_runs_the_discretised_transfer(self):
        compiler = os.environ.get("DMBD_CXX") or shutil.which("c++")
        if not compiler:
            self.skipTest("no C++ compiler")
        rate, n = 1000.0, 200
        g = dmbd.tf(self.G, params={"wc": 2 * np.pi * 60})
        header = dmbd.generate_code(g, rate_hz=rate, method="tustin", name="q_filter")
        with tempfile.TemporaryDirectory() as tmp:
            tmp = pathlib.Path(tmp)
            (tmp / "q_filter.hpp").write_text(header)
            (tmp / "main.cpp").write_text(
                '#include <cstdio>\n#include "q_filter.hpp"\n'
                "int main() { q_filter::Controller c; double u = 1.0, y = 0.0;\n"
                f"  for (int k = 0; k < {n}; ++k) {{ c.step_real(&u, &y); std::printf(\"%.17g\\n\", y); }} }}\n")
            subprocess.run([compiler, "-std=c++11", "-O1", "-o", str(tmp / "run"), str(tmp / "main.cpp")], check=True)
            y = np.array([float(v) for v in subprocess.run([str(tmp / "run")], check=True, capture_output=True,
                                                            text=True).stdout.split()])
        ref = dmbd.step(dmbd.c2d(g, 1 / rate, "tustin"), np.arange(n) / rate)
        self.assertLessEqual(np.max(np.abs(y - ref)) / np.max(np.abs(ref)), 1e-12)


if __name__ == "__main__":
    unittest.main()
