"""The Python sessions of docs/python.md and README.md (their ```python blocks), run as
doctests from the source folder (their paths are relative to it), and the package's
docstring: what they show is what the module prints."""
import doctest
import os
import pathlib
import re
import unittest

ROOT = pathlib.Path(__file__).resolve().parents[2]


class Sessions(unittest.TestCase):
    def run_sessions(self, name):
        text = (ROOT / name).read_text()
        blocks = re.findall(r"^```python\n(.*?)^```$", text, flags=re.M | re.S)
        self.assertTrue(blocks, f"{name}: no Python session found")
        runner = doctest.DocTestRunner(optionflags=doctest.NORMALIZE_WHITESPACE)
        cwd = os.getcwd()
        os.chdir(ROOT)
        try:
            for k, block in enumerate(blocks):
                test = doctest.DocTestParser().get_doctest(block, {}, f"{name} session {k + 1}", name, 0)
                runner.run(test)
        finally:
            os.chdir(cwd)
        result = runner.summarize(verbose=False)
        self.assertGreater(result.attempted, 5, f"{name}: too few examples")
        self.assertEqual(result.failed, 0, f"{name}: {result.failed} of {result.attempted} examples differ")

    def test_python_md(self):
        self.run_sessions("docs/python.md")

    def test_readme(self):
        self.run_sessions("README.md")

    def test_package_docstring(self):
        import dmbd
        result = doctest.testmod(dmbd)
        self.assertGreater(result.attempted, 0)
        self.assertEqual(result.failed, 0)


if __name__ == "__main__":
    unittest.main()
