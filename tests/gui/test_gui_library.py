# SPDX-License-Identifier: LGPL-2.1-or-later
"""FreeCAD GUI test of the workbench without its C library, as after an Addon Manager
install: run as a macro from a copy of the repository that has no build/ and no
MFGEOM_LIBRARY (tests/gui/run_gui_tests.sh sets that up).

Activating the workbench offers to build the library (the question box is answered
Cancel, then Build, by a timer); the document stays as it was while the library is missing;
the build runs in its dialog and the library is then loaded without restarting FreeCAD.
Prints ``freecad-gui-library: N passed, M failed`` and leaves with os._exit(rc).
"""

import os
import sys

import FreeCAD as App
import FreeCADGui as Gui

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from gui_harness import check, finish, pump  # noqa: E402

WORKBENCH = "MfgeomWorkbench"
COMMAND = "Mfgeom_ClassifyPoints"

asked = []     # the texts of the build offers
warned = []    # the texts of the warning boxes
answer = {"build": False}


def snapshot(doc):
    """What must not change while the library is missing."""
    return ([(o.Name, o.isValid(), "Touched" in o.State) for o in doc.Objects],
            doc.UndoCount)


class Answerer:
    """Answers the real Build / Cancel question box when it opens (pressing the button
    answer["build"] names) and keeps its text; other dialogs are left alone."""

    def __init__(self):
        from PySide import QtCore
        self.timer = QtCore.QTimer()
        self.timer.timeout.connect(self._tick)
        self.timer.start(100)

    def _tick(self):
        from PySide import QtGui
        box = QtGui.QApplication.activeModalWidget()
        if not isinstance(box, QtGui.QMessageBox):
            return
        asked.append(box.text())
        wanted = "Build" if answer["build"] else "Cancel"
        for button in box.buttons():
            if button.text().replace("&", "") == wanted:
                button.click()
                return
        box.done(0)


from mfgeom import building, core, paths        # noqa: E402  (after the FreeCAD imports)
from mfgeom.errors import LibraryError          # noqa: E402
from mfgeom.gui import library                  # noqa: E402

answerer = Answerer()
library.show_message = lambda title, text: warned.append(text)   # warnings: just recorded
library.AUTO_CLOSE = True          # the build dialog closes itself when the build ends

state = {}


@check("starts without a library (a copy without build/, no MFGEOM_LIBRARY)")
def _():
    assert "MFGEOM_LIBRARY" not in os.environ
    assert not os.path.exists(os.path.join(paths.REPO_DIR, "build")), paths.REPO_DIR
    assert core._loaded is None
    assert not building.missing_tools(), building.missing_tools()
    import Part  # noqa: F401
    import Points
    doc = App.newDocument("NoLibrary")
    box = doc.addObject("Part::Box", "Box")
    cloud = doc.addObject("Points::Feature", "Cloud")
    cloud.Points = Points.Points([App.Vector(x, y, 10.0) for x in (-1.0, 2.0, 5.0, 12.0)
                                  for y in (2.0, 5.0, 11.0)])
    doc.recompute()
    state.update(doc=doc, box=box, cloud=cloud, before=snapshot(doc))


@check("a make function raises LibraryError (an ImportError) and leaves the document")
def _():
    import mfgeom
    doc = state["doc"]
    try:
        mfgeom.make_point_classification(doc, (state["box"], "Face6"), state["cloud"], 0.1)
    except LibraryError as exc:
        assert isinstance(exc, ImportError)
        assert building.build_command_text() in str(exc), str(exc)
    else:
        raise AssertionError("no LibraryError")
    assert snapshot(doc) == state["before"], snapshot(doc)


@check("activating the workbench offers to build the library (Cancel)")
def _():
    Gui.activateWorkbench(WORKBENCH)
    assert Gui.activeWorkbench().name() == WORKBENCH
    assert pump(lambda: asked, 10), "no offer to build"
    assert len(asked) == 1, asked
    assert "Build it now?" in asked[0] and building.build_command_text() in asked[0], asked[0]
    assert core._loaded is None and not warned, warned
    assert snapshot(state["doc"]) == state["before"], snapshot(state["doc"])


@check("the offer comes once per session on activation")
def _():
    Gui.activateWorkbench("PartWorkbench")
    Gui.activateWorkbench(WORKBENCH)
    pump(lambda: len(asked) > 1, 2)
    assert len(asked) == 1, asked


@check("the command offers again (Cancel) and leaves the document")
def _():
    Gui.Selection.clearSelection()
    Gui.Selection.addSelection(state["box"], "Face6")
    Gui.Selection.addSelection(state["cloud"])
    Gui.runCommand(COMMAND)
    pump(lambda: len(asked) > 1, 5)
    assert len(asked) == 2, asked
    Gui.updateGui()
    assert Gui.Control.activeDialog() is False or not Gui.Control.activeDialog()
    assert snapshot(state["doc"]) == state["before"], snapshot(state["doc"])
    assert core._loaded is None
    Gui.Selection.clearSelection()


@check("without cmake or a C compiler it says what to install instead of offering")
def _():
    real = building.missing_tools
    building.missing_tools = lambda: ["cmake", "a C compiler"]
    try:
        assert library.ensure_library() is False
    finally:
        building.missing_tools = real
    assert len(asked) == 2 and len(warned) == 1, (asked, warned)
    assert building.install_command() in warned[0], warned[0]
    assert building.build_command_text() in warned[0], warned[0]
    warned.clear()
    assert snapshot(state["doc"]) == state["before"], snapshot(state["doc"])


@check("Build: the build runs, its output is shown, and the library is loaded")
def _():
    answer["build"] = True
    library._state["offered"] = False            # a new session, as far as the offer knows
    Gui.activateWorkbench("PartWorkbench")
    Gui.activateWorkbench(WORKBENCH)
    assert pump(lambda: core._loaded is not None or warned, 600), "the build did not finish"
    assert not warned, warned
    assert len(asked) == 3, asked
    link = os.path.join(paths.PACKAGE_DIR, "libmfgeom.so")
    assert core.library_path == link, core.library_path
    assert os.path.realpath(link) == os.path.realpath(
        os.path.join(paths.REPO_DIR, "build", "libmfgeom.so"))
    assert core.sanitizers(link) == [] and core.version()
    from PySide import QtGui

    def report():
        views = [w for w in Gui.getMainWindow().findChildren(QtGui.QTextEdit)
                 if w.objectName() == "Report view"]
        return views[0].toPlainText() if views else ""
    # the build's output reaches the Report view (which shows messages on its own events)
    assert pump(lambda: "built and loaded" in report(), 10), report()[-2000:]
    assert "build: compiling libmfgeom.so" in report() and "build: built" in report()
    assert snapshot(state["doc"]) == state["before"], snapshot(state["doc"])


@check("with the library loaded, the make function works in the same session")
def _():
    import mfgeom
    doc = state["doc"]
    obj = mfgeom.make_point_classification(doc, (state["box"], "Face6"), state["cloud"], 0.1)
    assert obj.isValid(), obj.getStatusString()
    assert obj.CountIn + obj.CountOn + obj.CountOut == 12
    # the top face of the 10 mm box: x, y in (2, 5) are IN, 12 and -1 OUT
    assert obj.CountIn == 4 and obj.CountOut == 8, (obj.CountIn, obj.CountOn, obj.CountOut)


finish("freecad-gui-library")
