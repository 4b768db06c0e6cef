# SPDX-License-Identifier: LGPL-2.1-or-later
"""mfgeom.fileio (issue 22): every output file is written through a temporary file in
its folder renamed into place, so a failure -- while writing, at the rename, no folder --
leaves the previous file untouched and no temporary behind; Outputs removes what a failed
command wrote."""
import os

import pytest

from mfgeom import fileio


def test_writes_bytes_and_text(tmp_path):
    fileio.write_atomic(tmp_path / "a.bin", b"\x00\x01")
    fileio.write_atomic(tmp_path / "b.txt", "x\ny\n", newline="\n")
    assert (tmp_path / "a.bin").read_bytes() == b"\x00\x01"
    assert (tmp_path / "b.txt").read_text() == "x\ny\n"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["a.bin", "b.txt"]


def test_failure_while_writing_keeps_the_old_file(tmp_path):
    target = tmp_path / "out.ply"
    target.write_text("old")
    with pytest.raises(UnicodeEncodeError):       # fails half-way through the write
        fileio.write_atomic(target, "abc" * 1000 + "\u00e9", encoding="ascii")
    assert target.read_text() == "old"
    assert [p.name for p in tmp_path.iterdir()] == ["out.ply"]


def test_failure_at_the_rename_keeps_the_old_file(tmp_path, monkeypatch):
    target = tmp_path / "out.json"
    target.write_text("old")

    def refuse(src, dst):
        raise OSError(28, "No space left on device")
    monkeypatch.setattr(os, "replace", refuse)
    with pytest.raises(OSError, match="No space"):
        fileio.write_atomic(target, "{}\n")
    monkeypatch.undo()
    assert target.read_text() == "old"
    assert [p.name for p in tmp_path.iterdir()] == ["out.json"]


def test_no_folder(tmp_path):
    with pytest.raises(OSError):
        fileio.write_atomic(tmp_path / "missing" / "out.json", "{}")
    assert list(tmp_path.iterdir()) == []


def test_outputs_remove_what_was_written(tmp_path):
    out = fileio.Outputs()
    for name in ("a.stl", "b.json"):
        fileio.write_atomic(tmp_path / name, "x")
        out.add(tmp_path / name)
    (tmp_path / "b.json").unlink()                 # one already gone: skipped
    (tmp_path / "keep.txt").write_text("not ours")
    out.remove_all()
    assert [p.name for p in tmp_path.iterdir()] == ["keep.txt"]
