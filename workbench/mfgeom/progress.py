# SPDX-License-Identifier: LGPL-2.1-or-later
"""Progress and cancel of the workbench's long computations (FreeCAD-free).

A long job (a feature's recompute) runs inside ``task(title, sink)``.  The library calls
of the job pass ``progress=current()`` to the binding, whose long functions report to it
from C (fraction and stage name, see ``mfg_progress`` in mfgeom.h) and stop when it says
so; the job's own Python loops call ``step(fraction, stage)``.  With no task running
``current()`` is None and ``step`` does nothing, so scripts and tests are unaffected.

The sink is what shows the progress: ``sink.report(title, fraction, stage)`` returns True
when the user asked to stop, ``sink.close()`` ends it.  The workbench's sink is a
progress dialog with a Cancel button (mfgeom.gui.progress_dialog); a task started inside
another one reports to the outer task's sink, so a recompute of several features shows
one dialog at a time and one Cancel stops them all.

Why a context variable and not an argument: the computations are reached through
FreeCAD's recompute (``execute(obj)``), whose signature we do not choose; the variable
lives in the job's own context, so two documents recomputed in two threads do not share
it.  A cancelled library call raises ``Cancelled``; so does ``step``, and the job then
ends as every failed recompute does (nothing written, the feature marked in error)."""

import contextlib
import contextvars

from mfgeom.errors import Cancelled

_active = contextvars.ContextVar("mfgeom_progress_task", default=None)


class _Task:
    """One running job: its title and sink, and whether it was cancelled."""

    def __init__(self, title, sink):
        self.title = title
        self.sink = sink
        self.cancelled = False
        self.stage = ""

    def report(self, fraction, stage):
        """The callable the binding calls: True asks the library to stop."""
        self.stage = stage
        if not self.cancelled and self.sink is not None:
            fraction = min(1.0, max(0.0, float(fraction)))
            self.cancelled = bool(self.sink.report(self.title, fraction, stage))
        return self.cancelled


@contextlib.contextmanager
def task(title, sink=None):
    """Runs the body as the job ``title`` reporting to ``sink`` (None: nothing shown,
    nothing cancels).  Inside another task the outer one goes on reporting; the sink of
    the outermost task is closed when it ends, whatever happened."""
    outer = _active.get()
    if outer is not None:
        yield outer
        return
    job = _Task(title, sink)
    token = _active.set(job)
    try:
        yield job
    finally:
        _active.reset(token)
        if sink is not None:
            sink.close()


def current():
    """The progress callable for the binding's ``progress=`` argument: None outside a
    task (the library then reports nothing)."""
    job = _active.get()
    return None if job is None or job.sink is None else job.report


def step(fraction, stage):
    """Reports the job's own (Python) work; raises Cancelled when the user asked to stop.
    Outside a task it does nothing."""
    job = _active.get()
    if job is not None and job.report(fraction, stage):
        raise Cancelled(f"cancelled ({stage})")
