# SPDX-License-Identifier: LGPL-2.1-or-later
"""The workbench's side of progress and cancel (mfgeom.progress, issue 18): a job's sink
sees the library's stages through ``current()``, a sink that says stop cancels the
library call inside the job (core.Cancelled, which is an errors.Cancelled like the one
``step`` raises), nested jobs report to the outermost sink, the sink is closed whatever
happens, and outside a job nothing is reported and nothing cancels."""

import numpy as np
import pytest

from mfgeom import core, errors, progress
from test_progress import AXIS_STAGES


class Sink:
    def __init__(self, stop_at=None):
        self.reports, self.closed, self.stop_at = [], 0, stop_at

    def report(self, title, fraction, stage):
        self.reports.append((title, fraction, stage))
        return self.stop_at is not None and stage == self.stop_at

    def close(self):
        self.closed += 1


def _star(n=400):
    a = 2 * np.pi * np.arange(n) / n
    r = 10 + 3 * np.cos(7 * a)
    return [np.stack([r * np.cos(a), r * np.sin(a)], axis=1)]


def test_outside_a_job_nothing_reports():
    assert progress.current() is None
    progress.step(0.5, "anything")   # does nothing, raises nothing


def test_library_stages_reach_the_sink():
    sink = Sink()
    with progress.task("Axis", sink):
        axis = core.medial_axis(_star(), 0.01, progress=progress.current())
    plain = core.medial_axis(_star(), 0.01)
    assert repr(axis) == repr(plain)
    assert all(np.array_equal(a.points, b.points) for a, b in zip(axis.branches, plain.branches))
    stages = [s for _, _, s in sink.reports]
    assert [s for s in AXIS_STAGES if s in stages] == AXIS_STAGES, stages
    assert all(t == "Axis" for t, _, _ in sink.reports)
    fractions = [f for _, f, _ in sink.reports]
    assert fractions == sorted(fractions) and 0 <= fractions[0] and fractions[-1] <= 1
    assert sink.closed == 1


def test_sink_stop_cancels_the_library_call_and_closes():
    sink = Sink(stop_at="axis: branches")
    with pytest.raises(errors.Cancelled) as info:
        with progress.task("Axis", sink):
            core.medial_axis(_star(), 0.01, progress=progress.current())
    assert isinstance(info.value, core.Cancelled) and info.value.stage == "axis: branches"
    assert sink.closed == 1
    assert [s for _, _, s in sink.reports][-1] == "axis: branches"   # nothing after the stop


def test_step_raises_once_cancelled_and_nested_jobs_share_the_outer_sink():
    sink = Sink(stop_at="python loop")
    with pytest.raises(errors.Cancelled, match="python loop"):
        with progress.task("Outer", sink):
            with progress.task("Inner", Sink()) as inner:
                assert inner.title == "Outer"
                progress.step(0.1, "before")
                progress.step(0.2, "python loop")
    assert sink.closed == 1 and [s for _, _, s in sink.reports] == ["before", "python loop"]
    assert progress.current() is None   # the job is over


def test_no_sink_reports_nothing_but_runs():
    with progress.task("Quiet") as job:
        assert progress.current() is None
        progress.step(0.5, "x")
        assert not job.cancelled
