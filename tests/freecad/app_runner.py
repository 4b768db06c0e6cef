# SPDX-License-Identifier: LGPL-2.1-or-later
"""The runner of the freecadcmd test files: freecadcmd runs a file with exec(), so it is
not in sys.modules and unittest cannot find its tests by module; they are collected from
the file's globals, and the summary line "LABEL: N passed, M failed" that
tests/run_freecad_tests.sh reads is printed at the end."""

import sys
import unittest


def run_tests(namespace, label):
    """Runs every unittest.TestCase class in ``namespace`` (a file's globals()); returns
    the exit code: 0 when tests ran and none failed."""
    loader = unittest.defaultTestLoader
    suite = unittest.TestSuite(
        loader.loadTestsFromTestCase(cls) for cls in list(namespace.values())
        if isinstance(cls, type) and issubclass(cls, unittest.TestCase))
    result = unittest.TextTestRunner(stream=sys.stdout, verbosity=2).run(suite)
    failed = len(result.failures) + len(result.errors)
    passed = result.testsRun - failed - len(result.skipped)
    sys.stdout.write(f"{label}: {passed} passed, {failed} failed\n")
    sys.stdout.flush()
    return 0 if failed == 0 and result.testsRun > 0 else 1
