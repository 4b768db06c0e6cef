# SPDX-License-Identifier: LGPL-2.1-or-later
"""The FreeCAD suites' runner (tests/freecad/fc_testsupport.py) on dummy unittest suites,
without FreeCAD: a suite fails when a test fails, when no test ran and when every test
was skipped; skips are listed with their reasons; the summary line is the one
tests/run_freecad_tests.sh and tests/gui/run_gui_tests.sh read."""

import io
import os
import re
import sys
import unittest

sys.path.insert(0, os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))),
                                "freecad"))
import fc_testsupport  # noqa: E402

# the shell scripts' test of a clean run
CLEAN = re.compile(r"^dummy: [0-9]+ passed, 0 failed$", re.M)


def run(*cases):
    """(exit code, output) of run_suite on the TestCase classes ``cases``."""
    out = io.StringIO()
    suite = unittest.TestSuite(unittest.defaultTestLoader.loadTestsFromTestCase(c)
                               for c in cases)
    return fc_testsupport.run_suite(suite, "dummy", out=out), out.getvalue()


class Passing(unittest.TestCase):
    __test__ = False   # a dummy for the runner, not a test of pytest's

    def test_one(self):
        self.assertEqual(1 + 1, 2)

    def test_two(self):
        pass


class Skipping(unittest.TestCase):
    __test__ = False   # a dummy for the runner, not a test of pytest's

    def test_skipped(self):
        self.skipTest("no such module here")

    @unittest.skip("decorated away")
    def test_decorated(self):
        raise AssertionError("must not run")


class Failing(unittest.TestCase):
    __test__ = False   # a dummy for the runner, not a test of pytest's

    def test_fails(self):
        self.assertEqual(1, 2)

    def test_errors(self):
        raise RuntimeError("boom")


class SubTests(unittest.TestCase):
    __test__ = False   # a dummy for the runner, not a test of pytest's

    def test_parts(self):
        for i in range(3):
            with self.subTest(i=i):
                self.assertNotEqual(i, 1)


def test_all_passing_suite_passes():
    rc, out = run(Passing)
    assert rc == 0
    assert CLEAN.search(out) and "dummy: 2 passed, 0 failed" in out
    assert "SKIP" not in out


def test_all_skipped_suite_fails_and_lists_reasons():
    rc, out = run(Skipping)
    assert rc == 1
    assert not CLEAN.search(out), out
    assert "dummy: 0 passed, 1 failed" in out
    assert "FAIL: every test of dummy was skipped (2)" in out
    assert re.search(r"^SKIP: .*test_skipped: no such module here$", out, re.M), out
    assert re.search(r"^SKIP: .*test_decorated: decorated away$", out, re.M), out
    assert "dummy: 2 skipped" in out


def test_empty_suite_fails():
    rc, out = run()
    assert rc == 1
    assert not CLEAN.search(out)
    assert "FAIL: no test of dummy ran" in out


def test_some_skipped_still_passes_and_lists_them():
    rc, out = run(Passing, Skipping)
    assert rc == 0
    assert "dummy: 2 passed, 0 failed" in out
    assert "dummy: 2 skipped" in out
    assert out.count("SKIP: ") == 2


def test_failures_and_errors_count():
    rc, out = run(Passing, Failing)
    assert rc == 1
    assert "dummy: 2 passed, 2 failed" in out


def test_failed_subtests_count_once():
    rc, out = run(Passing, SubTests)
    assert rc == 1
    assert "dummy: 2 passed, 1 failed" in out


def test_summarize_counts_an_empty_gui_run_as_failed():
    """The GUI harness (tests/gui/gui_harness.py) reports through summarize."""
    out = io.StringIO()
    assert fc_testsupport.summarize("gui", 0, 0, [("a check", "no display")], out) == 1
    assert "gui: 0 passed, 1 failed" in out.getvalue()
    out = io.StringIO()
    assert fc_testsupport.summarize("gui", 3, 0, [], out) == 0
    assert out.getvalue() == "gui: 3 passed, 0 failed\n"


def test_collect_takes_the_files_own_classes_only():
    """run_file collects a freecadcmd file's globals(): its own TestCase classes, not the
    imported base class (whose tests would run twice) nor excluded ones."""
    namespace = {"__name__": __name__, "Passing": Passing, "Skipping": Skipping,
                 "DocumentTestCase": fc_testsupport.DocumentTestCase,
                 "unittest": unittest}
    suite = fc_testsupport.collect(namespace, exclude=(Skipping,))
    assert suite.countTestCases() == 2
