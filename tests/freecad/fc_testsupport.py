# SPDX-License-Identifier: LGPL-2.1-or-later
"""What the FreeCAD test files share (tests/freecad/test_*_app.py under freecadcmd,
tests/gui/test_gui*.py through tests/gui/gui_harness.py): the document test base class,
the runner and the summary line "LABEL: N passed, M failed" that
tests/run_freecad_tests.sh and tests/gui/run_gui_tests.sh read.

A suite fails when a test fails, when no test ran, or when every test was skipped: a
skip is for an environmental reason only (no FreeCAD module, no metadata reader) and a
suite that checked nothing must not look green.  Every skip is listed with its reason
("SKIP: <test>: <reason>").

Plain Python 3.8+ and the standard library only: importable without FreeCAD (FreeCAD is
imported by DocumentTestCase.setUp), so tests/python/test_fc_testsupport.py checks the
runner itself with pytest.

freecadcmd runs a test file with exec(), so the file is not in sys.modules and unittest
cannot find its tests by module: run_file collects the TestCase classes from the file's
globals().  Each file ends in ``sys.exit(run_file(globals(), "LABEL"))``.
"""

import sys
import unittest


class DocumentTestCase(unittest.TestCase):
    """A test with its own FreeCAD document ``self.doc``, closed after the test.
    ``DOC_NAME`` names it (default: mfgeom_<test method>)."""

    DOC_NAME = None

    def setUp(self):
        import FreeCAD as App
        self.doc = App.newDocument(self.DOC_NAME or f"mfgeom_{self.id().split('.')[-1]}")

    def tearDown(self):
        import FreeCAD as App
        if self.doc.Name in App.listDocuments():
            App.closeDocument(self.doc.Name)


def summarize(label, passed, failed, skipped, out=None):
    """Prints the skips (``skipped``: (name, reason) pairs) and the summary line
    ``<label>: N passed, M failed``; returns the exit code.  An empty run (nothing passed,
    nothing failed: no test, or every test skipped) is counted as one failure with a
    ``FAIL:`` line saying so, so the summary line cannot read "0 failed"."""
    out = out or sys.stdout
    for name, reason in skipped:
        out.write(f"SKIP: {name}: {reason}\n")
    if passed == 0 and failed == 0:
        why = (f"every test of {label} was skipped ({len(skipped)})" if skipped
               else f"no test of {label} ran")
        out.write(f"FAIL: {why}\n")
        failed = 1
    if skipped:
        out.write(f"{label}: {len(skipped)} skipped\n")
    out.write(f"{label}: {passed} passed, {failed} failed\n")
    out.flush()
    return 0 if failed == 0 else 1


def collect(namespace, exclude=()):
    """The unittest suite of every TestCase class in ``namespace`` (a file's globals())
    defined there (not the imported base classes), except those in ``exclude``."""
    loader = unittest.defaultTestLoader
    name = namespace.get("__name__")
    classes = [cls for cls in list(namespace.values())
               if isinstance(cls, type) and issubclass(cls, unittest.TestCase)
               and cls not in exclude and cls.__module__ == name]
    return unittest.TestSuite(loader.loadTestsFromTestCase(cls) for cls in classes)


def run_suite(suite, label, before_summary=None, out=None):
    """Runs ``suite`` (verbose, to ``out``), calls ``before_summary(result)`` (a file's
    extra report lines), prints the skips and the summary; returns the exit code: 0 when
    at least one test passed and none failed.  A test with failed subtests counts once."""
    out = out or sys.stdout
    result = unittest.TextTestRunner(stream=out, verbosity=2).run(suite)
    if before_summary is not None:
        before_summary(result)
    failed_ids = {getattr(t, "test_case", t).id() for t, _ in result.failures + result.errors}
    failed_ids |= {t.id() for t in getattr(result, "unexpectedSuccesses", [])}
    skipped = [(t.id(), reason) for t, reason in result.skipped]
    # a skipped subtest is listed, but its test still ran
    skipped_ids = {t.id() for t, _ in result.skipped if not hasattr(t, "test_case")}
    passed = result.testsRun - len(failed_ids) - len(skipped_ids - failed_ids)
    return summarize(label, passed, len(failed_ids), skipped, out)


def run_file(namespace, label, exclude=(), before_summary=None):
    """The end of a freecadcmd test file: ``sys.exit(run_file(globals(), LABEL))``."""
    return run_suite(collect(namespace, exclude), label, before_summary)
