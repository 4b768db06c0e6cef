# SPDX-License-Identifier: LGPL-2.1-or-later
"""The workbench without its C library (an Addon Manager install is a git clone without
libmfgeom.so): offers to build it when cmake and a C compiler are there, shows the build's
output and loads the result without restarting FreeCAD; otherwise says what to install.

:func:`ensure_library` is called when the workbench is activated (once per session) and
by every command before it needs the library.  The dialogs are module functions
(:func:`ask_build`, :func:`show_message`, :func:`run_build`) so tests can answer them."""

import FreeCAD
import FreeCADGui

from mfgeom import building, core
from mfgeom.errors import LibraryError
from mfgeom.gui import messages

TITLE = "Manufacturing Geometry"
AUTO_CLOSE = False                 # tests: close the build dialog as soon as the build ends
_state = {"offered": False}        # offer once per session on activation; commands ask again


def _qt():
    from PySide import QtCore, QtGui
    return QtCore, QtGui


def show_message(title, text):
    """A warning box (and the same text in the Report view): :func:`messages.warn`, under
    a name of its own here so that tests can answer this module's dialogs."""
    messages.warn(title, text)


def ask_build(text):
    """Build / Cancel; True to build."""
    _QtCore, QtGui = _qt()
    box = QtGui.QMessageBox(QtGui.QMessageBox.Question, TITLE, text,
                            QtGui.QMessageBox.NoButton, FreeCADGui.getMainWindow())
    build = box.addButton("Build", QtGui.QMessageBox.AcceptRole)
    box.addButton(QtGui.QMessageBox.Cancel)
    box.setDefaultButton(build)
    box.exec_()
    return box.clickedButton() is build


class BuildDialog:
    """Runs the build (a QProcess, so FreeCAD stays responsive) and shows its output,
    also copied to the Report view.  ``exit_code`` is None until it has finished."""

    def __init__(self, close_when_done=False):
        QtCore, QtGui = _qt()
        self.close_when_done = close_when_done
        self.exit_code = None
        self.dialog = QtGui.QDialog(FreeCADGui.getMainWindow())
        self.dialog.setWindowTitle(f"{TITLE}: building the library")
        self.dialog.resize(720, 420)
        layout = QtGui.QVBoxLayout(self.dialog)
        self.status = QtGui.QLabel(f"Running: {building.build_command_text()}")
        self.status.setWordWrap(True)
        self.output = QtGui.QPlainTextEdit()
        self.output.setReadOnly(True)
        self.buttons = QtGui.QDialogButtonBox(QtGui.QDialogButtonBox.Close)
        self.buttons.rejected.connect(self._close)
        for widget in (self.status, self.output, self.buttons):
            layout.addWidget(widget)
        folder, argv = building.build_argv()
        self.process = QtCore.QProcess(self.dialog)
        self.process.setWorkingDirectory(folder)
        self.process.setProcessChannelMode(QtCore.QProcess.MergedChannels)
        self.process.readyReadStandardOutput.connect(self._read)
        self.process.finished.connect(self._finished)
        self.process.errorOccurred.connect(self._error)
        self.process.start(argv[0], argv[1:])

    def _append(self, text):
        self.output.appendPlainText(text.rstrip("\n"))
        FreeCAD.Console.PrintMessage(text if text.endswith("\n") else text + "\n")

    def _read(self):
        self._append(bytes(self.process.readAllStandardOutput()).decode("utf-8", "replace"))

    def _finished(self, code, _status=None):
        self._read()
        self.exit_code = int(code)
        self.status.setText("Built: the library is loaded." if code == 0 else
                            f"The build failed (exit code {code}): see the output above.")
        if self.close_when_done:
            self.dialog.accept()

    def _error(self, error):
        QtCore, _QtGui = _qt()
        if error == QtCore.QProcess.FailedToStart:
            self._append(f"could not start {building.build_command_text()}")
            self._finished(-1)

    def _close(self):
        QtCore, _QtGui = _qt()
        if self.process.state() != QtCore.QProcess.NotRunning:
            self.process.kill()                      # closing the dialog cancels the build
            self.process.waitForFinished(5000)
        self.dialog.reject()

    def exec_(self):
        if self.exit_code is None or not self.close_when_done:
            self.dialog.exec_()
        return self.exit_code if self.exit_code is not None else -1


def run_build(close_when_done=False):
    """Runs the build in a dialog that shows its output; returns its exit code."""
    FreeCAD.Console.PrintMessage(f"mfgeom: building the library: "
                                 f"{building.build_command_text()}\n")
    return BuildDialog(close_when_done).exec_()


def ensure_library(title=TITLE):
    """True if libmfgeom is loaded, after building it if the user agrees.  Otherwise the
    user has been told why and what to do, and False is returned: nothing else happens
    (no document is touched)."""
    try:
        core.load()
        return True
    except LibraryError as exc:
        FreeCAD.Console.PrintLog(f"mfgeom: {exc}\n")
    missing = building.missing_tools()
    if missing:
        show_message(title, (
            "The mfgeom C library is not built yet, and building it needs "
            f"{' and '.join(missing)}, not found on PATH.\n\n"
            f"Install them:\n  {building.install_command()}\n"
            "then use the workbench again (it offers to build the library), or build it "
            f"yourself:\n  {building.build_command_text()}"))
        return False
    if not ask_build(
            "The mfgeom C library (libmfgeom.so) is not built yet: an Addon Manager "
            "install does not include it.\n\nBuild it now? This runs, as your user:\n"
            f"  {building.build_command_text()}\n(about a minute; cmake and a C "
            "compiler are installed)."):
        FreeCAD.Console.PrintWarning(
            f"mfgeom: the library is not built; build it with: "
            f"{building.build_command_text()}\n")
        return False
    code = run_build(close_when_done=AUTO_CLOSE)
    if code != 0:
        show_message(title, f"Building the library failed (exit code {code}); its output "
                            "is in the Report view.\nThe command was:\n  "
                            f"{building.build_command_text()}")
        return False
    try:
        core.load()
    except LibraryError as exc:
        show_message(title, f"The library was built but cannot be loaded:\n{exc}")
        return False
    FreeCAD.Console.PrintMessage(f"mfgeom: built and loaded {core.library_path}\n")
    return True


def offer_on_activation():
    """Called when the workbench is activated: the first time in a session without the
    library, offer to build it (after the workbench switch has finished)."""
    if _state["offered"] or core._loaded is not None:
        return
    _state["offered"] = True
    QtCore, _QtGui = _qt()
    QtCore.QTimer.singleShot(0, ensure_library)
