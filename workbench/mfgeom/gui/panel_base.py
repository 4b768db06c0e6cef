# SPDX-License-Identifier: LGPL-2.1-or-later
"""What every mfgeom task panel shares: the buttons (OK, Apply, Cancel), checking the
values before anything is touched, closing, showing an error in the panel and the Report
view, and running a change through the Python console inside one undo transaction that
is aborted on a failure, so the document stays as it was."""

import FreeCAD
import FreeCADGui
from PySide import QtCore, QtGui

from mfgeom.errors import InputError, MfgeomError

# What a change may fail with and the panel then shows (a bad input, a library error, a
# library that cannot be loaded, FreeCAD's own errors); anything else is a bug.
ERRORS = (MfgeomError, ValueError, TypeError, RuntimeError, ImportError)


def spin(name, low, high, decimals, suffix="", value=0.0, tip=""):
    """A QDoubleSpinBox named ``name`` (for the tests) showing ``value``."""
    box = QtGui.QDoubleSpinBox()
    box.setObjectName(name)
    box.setRange(low, high)
    box.setDecimals(decimals)
    if suffix:
        box.setSuffix(suffix)
    box.setValue(value)
    if tip:
        box.setToolTip(tip)
    return box


def combo(name, items, tip=""):
    """A QComboBox named ``name`` of ``items``, (text, data) pairs."""
    box = QtGui.QComboBox()
    box.setObjectName(name)
    for text, data in items:
        box.addItem(text, data)
    if tip:
        box.setToolTip(tip)
    return box


class TaskPanel:
    """Base of the task panels.  A subclass makes ``self.form`` (with ``_new_form``,
    ``_add_result`` and ``_add_message`` for the error line), keeps the edited object in
    ``self.obj`` (None while creating) and implements ``_create()`` and ``_edit()`` (True
    when done; False after showing why not); ``_check()`` and ``_refresh()`` are optional
    hooks."""

    APPLY = True         # an Apply button besides OK and Cancel
    WAIT_CURSOR = True   # the wait cursor while a change runs

    obj = None

    def _new_form(self, title):
        """Makes ``self.form``, titled ``title`` (or "Edit <label>" when editing
        ``self.obj``), with the "what" line on top; returns its layout."""
        self.form = QtGui.QWidget()
        self.form.setWindowTitle(title if self.obj is None else f"Edit {self.obj.Label}")
        layout = QtGui.QFormLayout(self.form)
        self.what = QtGui.QLabel()
        self.what.setObjectName("what")
        self.what.setWordWrap(True)
        layout.addRow(self.what)
        return layout

    def _add_result(self, layout):
        """The line where the result is shown (selectable, to copy it)."""
        self.result = QtGui.QLabel()
        self.result.setObjectName("result")
        self.result.setWordWrap(True)
        self.result.setTextInteractionFlags(QtCore.Qt.TextSelectableByMouse)
        layout.addRow(self.result)

    def _add_message(self, layout):
        """The red line where a failure is shown."""
        self.message = QtGui.QLabel("")
        self.message.setObjectName("message")
        self.message.setWordWrap(True)
        self.message.setStyleSheet("color: #b00000")
        layout.addRow(self.message)

    # ------------------------------------------------------------- hooks
    def _check(self):
        """Raise InputError for a bad value before anything is touched."""

    def _refresh(self):
        """Show the values and result after a successful Apply."""

    def _create(self):
        raise NotImplementedError

    def _edit(self):
        raise NotImplementedError

    # ------------------------------------------------------------- task dialog protocol
    def getStandardButtons(self):
        buttons = QtGui.QDialogButtonBox.Ok | QtGui.QDialogButtonBox.Cancel
        if self.APPLY:
            buttons |= QtGui.QDialogButtonBox.Apply
        return int(buttons)

    def clicked(self, button):
        if button == QtGui.QDialogButtonBox.Apply:
            self.apply()

    def apply(self):
        """Create or update the object; the panel then shows its result.  Values are
        checked first, so a bad one is shown without touching the document."""
        try:
            self._check()
        except InputError as exc:
            self._show_error(str(exc))
            return False
        ok = self._create() if self.obj is None else self._edit()
        if ok:
            self._refresh()
        return ok

    def accept(self):
        ok = self.apply()
        if ok:
            self._close()
        return ok

    def reject(self):
        self._close()
        return True

    def _close(self):
        FreeCADGui.Control.closeDialog()
        if FreeCADGui.ActiveDocument is not None and FreeCADGui.ActiveDocument.getInEdit():
            FreeCADGui.ActiveDocument.resetEdit()

    def _show_error(self, text):
        self.message.setText(text)
        FreeCAD.Console.PrintError(f"mfgeom: {text}\n")

    # ------------------------------------------------------------- changing the document
    def _run(self, doc, name, work, restore=False):
        """Runs ``work()`` in ``doc`` inside one undo transaction ``name``.  On one of
        ERRORS the transaction is aborted (with ``restore``, when an edit failed, the
        document is recomputed so the old values' results are back too), the error shown
        and False returned; else it is committed, the message cleared and True returned."""
        doc.openTransaction(name)
        if self.WAIT_CURSOR:
            QtGui.QApplication.setOverrideCursor(QtCore.Qt.WaitCursor)
        try:
            work()
        except ERRORS as exc:
            doc.abortTransaction()
            if restore:
                doc.recompute()  # the old values are back: so are their results
            self._show_error(str(exc))
            return False
        finally:
            if self.WAIT_CURSOR:
                QtGui.QApplication.restoreOverrideCursor()
        doc.commitTransaction()
        self.message.setText("")
        return True

    def _create_by_call(self, doc, name, call, type_name, what):
        """The make function's ``call`` (Python source) run through the console in one
        undo transaction ``name`` (see _run, macro.echo_make); on success ``self.obj`` is
        the new object and the selection is cleared.  True when done."""
        from mfgeom.gui import macro
        new = []
        if not self._run(doc, name,
                         lambda: new.append(macro.echo_make(doc, call, type_name, what))):
            return False
        self.obj = new[0]
        FreeCADGui.Selection.clearSelection()
        return True

    @staticmethod
    def _set_and_recompute(obj, lines):
        """Runs the property assignments ``lines`` through the console, then the
        recompute; InputError with FreeCAD's status when ``obj`` failed."""
        from mfgeom.gui import macro
        for line in lines:
            FreeCADGui.doCommand(line)
        macro.recompute(obj)
        if not obj.isValid():
            from mfgeom.app.feature_base import status_line
            raise InputError(status_line(obj))

    def _edit_lines(self, lines):
        """``lines`` (property assignments of ``self.obj``) and the recompute in one
        transaction "Edit <label>"; True when done or nothing to change."""
        obj = self.obj
        if not lines:
            return True
        return self._run(obj.Document, f"Edit {obj.Label}",
                         lambda: self._set_and_recompute(obj, lines), restore=True)
