# SPDX-License-Identifier: LGPL-2.1-or-later
"""The progress sink of the GUI (see mfgeom.progress): a modal progress dialog with a
Cancel button (Esc cancels too), shown only when a job lasts longer than SHOW_AFTER, so
the short recomputes of everyday editing never flash a window.

The computation runs in FreeCAD's main thread (a recompute), so the dialog lives only
through the library's and the job's reports: each one (at most every UPDATE_EVERY
seconds) updates the bar and lets Qt handle the events that arrived meanwhile, the Cancel
click among them.  The dialog is window-modal on the main window: while a job runs the
user can cancel it, not edit the document under it."""

import time

from PySide import QtCore, QtGui

SHOW_AFTER = 0.5      # s: a job that ends sooner shows nothing
UPDATE_EVERY = 0.05   # s: at most 20 redraws a second (processEvents is not free)
STEPS = 1000          # resolution of the bar


def _main_window():
    try:
        import FreeCADGui
        return FreeCADGui.getMainWindow()
    except Exception:  # no FreeCAD GUI (a test of the dialog alone): a top-level dialog
        return None


class ProgressDialog:
    """``report(title, fraction, stage)`` → True once the user cancelled; ``close()``."""

    def __init__(self):
        self.started = time.monotonic()
        self.last_update = None
        self.dialog = None
        self.cancelled = False

    def _open(self, title):
        dialog = QtGui.QProgressDialog(title, "Cancel", 0, STEPS, _main_window())
        dialog.setObjectName("mfgeomProgress")
        dialog.setWindowTitle("Manufacturing Geometry")
        dialog.setWindowModality(QtCore.Qt.WindowModal)
        dialog.setMinimumDuration(0)
        dialog.setAutoClose(False)
        dialog.setAutoReset(False)
        dialog.canceled.connect(self._cancel)
        dialog.show()
        self.dialog = dialog

    def _cancel(self):
        self.cancelled = True

    def report(self, title, fraction, stage):
        now = time.monotonic()
        if self.last_update is not None and now - self.last_update < UPDATE_EVERY:
            return self.cancelled
        self.last_update = now
        if self.dialog is None:
            if now - self.started < SHOW_AFTER:
                return self.cancelled
            self._open(title)
        self.dialog.setLabelText(f"{title}\n{stage}")
        self.dialog.setValue(int(round(fraction * STEPS)))
        QtGui.QApplication.processEvents()
        if self.dialog.wasCanceled():
            self.cancelled = True
        return self.cancelled

    def close(self):
        if self.dialog is not None:
            self.dialog.close()
            self.dialog.deleteLater()
            self.dialog = None
