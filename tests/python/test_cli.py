# SPDX-License-Identifier: LGPL-2.1-or-later
"""Tests of the mfgeom command-line tool (mfgeom.cli and the tools/mfgeom launcher), run as subprocesses and compared with the Python binding."""

import json
import os
import subprocess

import numpy as np
import pytest

from mfgeom import core

_HERE = os.path.dirname(os.path.abspath(__file__))
_REPO = os.path.dirname(os.path.dirname(_HERE))
PYTHON = "/usr/bin/python3"
LAUNCHER = os.path.join(_REPO, "tools", "mfgeom")


def _env():
    env = dict(os.environ)
    env["PYTHONPATH"] = os.path.join(_REPO, "workbench")
    # the library the binding under test loaded (absolute: the children may run elsewhere)
    env["MFGEOM_LIBRARY"] = os.path.abspath(core.library_path)
    return env


def run(args, stdin=None, launcher=False):
    """Runs the CLI; returns (exit code, parsed stdout or None, parsed stderr or None)."""
    cmd = [LAUNCHER] if launcher else [PYTHON, "-m", "mfgeom.cli"]
    proc = subprocess.run(cmd + list(args), input=stdin, capture_output=True, text=True,
                          env=_env(), timeout=120, cwd=_REPO)
    out = json.loads(proc.stdout) if proc.stdout.strip() else None
    err = json.loads(proc.stderr) if proc.stderr.strip() else None
    return proc.returncode, out, err


def ok(args, doc=None, launcher=False):
    rc, out, err = run(args, None if doc is None else json.dumps(doc), launcher)
    assert rc == 0 and err is None, f"exit {rc}, stderr {err}"
    return out


def failed(args, stdin=None):
    rc, out, err = run(args, stdin)
    assert rc == 2 and out is None
    assert isinstance(err, dict) and set(err) == {"error"} and err["error"]
    return err["error"]


POCKET = [[0, 0, 1.0], [0.999, 0, 0.05], [-0.999, 0, 0.05], [0, 0.999, 0.05],
          [0, -0.999, 0.05]]


# --------------------------------------------------------------------------- #
# visibility-map                                                              #
# --------------------------------------------------------------------------- #

def test_visibility_map_from_stdin_matches_binding():
    out = ok(["visibility-map"], {"normals": POCKET})
    vm = core.visibility_map(POCKET)
    assert out["kind"] == vm.kind == "polygon" and out["closed"] is False
    assert np.array_equal(np.array(out["vertices"]), vm.vertices)   # exact round trip


def test_visibility_map_bare_list_file_and_options(tmp_path):
    path = tmp_path / "normals.json"
    path.write_text(json.dumps(POCKET))
    out = ok(["visibility-map", str(path), "--draft-angle", "0.02"])
    vm = core.visibility_map(POCKET, draft_angle=0.02)
    assert np.array_equal(np.array(out["vertices"]), vm.vertices)
    assert ok(["visibility-map", str(path), "--negative"])["kind"] == "polygon"
    neg = ok(["visibility-map"], {"normals": POCKET, "negative": True, "draft_angle": 0.0})
    assert np.array_equal(np.array(neg["vertices"]),
                          core.visibility_map(POCKET, negative=True).vertices)
    assert ok(["visibility-map", "-"], POCKET)["kind"] == "polygon"


def test_visibility_map_degenerate_kinds():
    out = ok(["visibility-map"], [[0, 0, 1.0], [0, 0, -1.0]])
    assert out["kind"] == "edge" and out["closed"] is True and len(out["vertices"]) == 3
    out = ok(["visibility-map"], [[1, 0, 0], [-1, 0, 0], [0, 1, 0], [0, -1, 0], [0, 0, 1]])
    assert out["kind"] == "point" and out["vertices"] == [[0.0, 0.0, 1.0]]
    out = ok(["visibility-map"], [[1, 1, 1], [1, -1, -1], [-1, 1, -1], [-1, -1, 1]])
    assert out == {"kind": "null", "vertices": [], "closed": False}


@pytest.mark.parametrize("doc,fragment", [
    ({"normals": [[0, 0, 1], [0, 0, 0]]}, "zero"),
    ({"normals": []}, ""),
    ({"normals": [[0, 0]]}, "normals[0]"),
    ({"normals": [[0, 0, "x"]]}, "number"),
    ({"normals": [[0, 0, 1]], "draft_angle": 2.0}, "draft"),
    ({"normals": [[0, 0, 1]], "negative": "yes"}, "negative"),
    ({"normal": [[0, 0, 1]]}, "normals"),
    ("just a string", ""),
])
def test_visibility_map_errors(doc, fragment):
    msg = failed(["visibility-map"], json.dumps(doc))
    assert fragment in msg


def test_nan_in_json_is_rejected():
    msg = failed(["visibility-map"], '{"normals": [[0, 0, NaN]]}')
    assert "NaN" in msg or "invalid" in msg


# --------------------------------------------------------------------------- #
# max-intersection, level-regions, min-intersection                           #
# --------------------------------------------------------------------------- #

def _maps():
    rng = np.random.default_rng(5)
    maps = []
    for _ in range(8):
        c = rng.normal(size=3) * 0.5 + [0, 0, 1.0]
        c /= np.linalg.norm(c)
        a = rng.normal(size=(6, 3)) * 0.4 + c
        maps.append(core.visibility_map(a))
    return [m for m in maps if m.kind == "polygon"]


def _as_json(maps, objects):
    if objects:
        return [{"kind": m.kind, "vertices": m.vertices.tolist(), "closed": m.closed}
                for m in maps]
    return [m.vertices.tolist() for m in maps]


def _same_result(out, res):
    assert out["count"] == res.count
    assert out["direction"] == [float(x) for x in res.direction]
    assert out["margin"] == float(res.margin)
    assert len(out["regions"]) == len(res.regions)
    for r, reg in enumerate(out["regions"]):
        assert reg["kind"] == res.kinds[r]
        assert reg["cover"] == [int(i) for i in res.covers[r]]
        assert reg["centre"] == [float(x) for x in res.centres[r]]
        assert reg["margin"] == float(res.margins[r])
        if "vertices" in reg:
            assert np.array_equal(np.array(reg["vertices"]).reshape(-1, 3), res.regions[r])


@pytest.mark.parametrize("objects", [False, True])
def test_max_intersection_matches_binding(objects):
    maps = _maps()
    out = ok(["max-intersection"], {"maps": _as_json(maps, objects)})
    _same_result(out, core.max_intersection(maps))
    assert out["count"] >= 1 and abs(np.linalg.norm(out["direction"]) - 1) < 1e-12


def test_max_intersection_weights_bare_list_and_file(tmp_path):
    maps = _maps()
    w = [float(i + 1) for i in range(len(maps))]
    out = ok(["max-intersection"], {"maps": _as_json(maps, False), "weights": w})
    _same_result(out, core.max_intersection(maps, weights=w))
    path = tmp_path / "maps.json"
    path.write_text(json.dumps(_as_json(maps, True)))
    _same_result(ok(["max-intersection", str(path)]), core.max_intersection(maps))


def test_max_intersection_mixed_kinds():
    doc = {"maps": [
        [[1.0, 0, 0.1], [0, 1.0, 0.1], [-1.0, -1.0, 0.1]],
        {"kind": "point", "vertices": [[0, 0, 1.0]]},
        {"kind": "null", "vertices": []},
    ]}
    out = ok(["max-intersection"], doc)
    assert out["count"] == 2 and out["regions"][0]["kind"] == "point"
    assert out["regions"][0]["cover"] == [0, 1]
    assert np.allclose(out["direction"], [0, 0, 1.0], atol=1e-9)


def test_level_and_min_intersection_match_binding():
    maps = _maps()
    top = core.max_intersection(maps).count
    level = max(1, top - 1)
    out = ok(["level-regions", "--level", str(level)], {"maps": _as_json(maps, True)})
    _same_result(out, core.level_regions(maps, level))
    assert all(sum(1 for _ in reg["cover"]) >= level for reg in out["regions"])
    out = ok(["min-intersection"], _as_json(maps, False))
    res = core.min_intersection(maps)
    _same_result(out, res)
    assert all("vertices" not in reg for reg in out["regions"])
    assert out["regions"] and all(reg["kind"] == "face" for reg in out["regions"])


@pytest.mark.parametrize("args,doc,fragment", [
    (["max-intersection"], {"maps": "nope"}, "maps"),
    (["max-intersection"], {"maps": [[[0, 0, 1], [1, 0]]]}, "maps[0][1]"),
    (["max-intersection"], {"maps": [{"kind": "blob", "vertices": []}]}, "kind"),
    (["max-intersection"], {"maps": [[[1, 0, 0], [0, 1, 0], [0, 0, 1]]], "weights": [1, 2]},
     "weights"),
    (["max-intersection"], {"maps": [[[1, 0, 0], [0, 1, 0], [0, 0, 1]]], "weights": [-1]}, ""),
    (["max-intersection"], {"weights": [1]}, "maps"),
    (["level-regions"], {"maps": []}, "--level"),
])
def test_intersection_errors(args, doc, fragment):
    msg = failed(args, json.dumps(doc))
    assert fragment in msg


# --------------------------------------------------------------------------- #
# classify-points                                                             #
# --------------------------------------------------------------------------- #

def test_classify_points_matches_binding():
    square = [[0, 0], [2, 0], [2, 2], [0, 2]]
    hole = [[0.5, 0.5], [1.5, 0.5], [1.5, 1.5], [0.5, 1.5]]
    pts = [[0.25, 0.25], [1, 1], [3, 3], [2, 1], [0.5, 1.0], [1.5 + 1e-12, 1.0]]
    out = ok(["classify-points", "--names"], {"rings": [square, hole], "points": pts,
                                              "tol": 1e-9})
    codes = core.classify_points([np.array(square, float), np.array(hole, float)], pts, 1e-9)
    assert out["codes"] == codes.tolist() == [1, 0, 0, 2, 2, 2]
    assert out["names"] == ["IN", "OUT", "OUT", "ON", "ON", "ON"]
    out = ok(["classify-points"], {"rings": [square], "points": [[1, 1]]})
    assert out == {"codes": [1]}


@pytest.mark.parametrize("doc,fragment", [
    ({"rings": [[[0, 0], [1, 0], [1, 1]]], "points": [[0.5, 0.2]], "tol": -1}, ""),
    ({"rings": [[[0, 0], [1, 0, 3]]], "points": []}, "rings[0][1]"),
    ({"points": [[0, 0]]}, "rings"),
])
def test_classify_points_errors(doc, fragment):
    assert fragment in failed(["classify-points"], json.dumps(doc))


# --------------------------------------------------------------------------- #
# Usage errors, files, the launcher                                           #
# --------------------------------------------------------------------------- #

def test_usage_errors_are_json():
    assert "invalid choice" in failed(["frobnicate"], "")
    assert failed([], "")
    assert "invalid JSON" in failed(["visibility-map"], "{not json")
    assert "cannot read" in failed(["visibility-map", "/nonexistent/normals.json"], "")
    assert "--level" in failed(["level-regions"], "[]")


def test_help_and_version():
    proc = subprocess.run([PYTHON, "-m", "mfgeom.cli", "--help"], capture_output=True,
                          text=True, env=_env(), timeout=60)
    assert proc.returncode == 0 and "visibility-map" in proc.stdout
    out = ok(["version"])
    assert out["library"] == core.version()


def test_launcher_in_the_source_tree():
    assert os.access(LAUNCHER, os.X_OK)
    out = ok(["visibility-map"], {"normals": POCKET}, launcher=True)
    assert np.array_equal(np.array(out["vertices"]), core.visibility_map(POCKET).vertices)
    rc, out, err = run(["visibility-map"], "[[0, 0, 0]]", launcher=True)
    assert rc == 2 and "error" in err


def test_launcher_in_the_build_tree():
    """CMake copies the launcher next to the library it builds (<build>/mfgeom)."""
    built = os.path.join(os.path.dirname(os.path.realpath(core.library_path)), "mfgeom")
    if not os.path.exists(built):
        pytest.skip(f"no configured launcher next to {core.library_path}")
    env = _env()
    env.pop("MFGEOM_LIBRARY")            # it must find the library next to itself
    env.pop("PYTHONPATH")
    proc = subprocess.run([built, "version"], capture_output=True, text=True, env=env,
                          timeout=60, cwd="/")
    assert proc.returncode == 0, proc.stderr
    info = json.loads(proc.stdout)
    assert os.path.realpath(info["library_path"]) == os.path.realpath(core.library_path)
    assert info["library"] == core.version()


# --------------------------------------------------------------------------- #
# Broken standard streams: still {"error": ...} on stderr and exit code 2     #
# --------------------------------------------------------------------------- #

def _shell(script, stdin=None):
    """Runs ``script`` in bash with $CLI set to the CLI command; returns the process."""
    env = _env()
    env["CLI"] = f"{PYTHON} -m mfgeom.cli"
    return subprocess.run(["bash", "-c", script], input=stdin, capture_output=True,
                          text=True, env=env, timeout=120, cwd=_REPO)


def _only_json_error(stderr, fragment):
    assert "Traceback" not in stderr, stderr
    err = json.loads(stderr)
    assert set(err) == {"error"} and fragment in err["error"], err
    return err["error"]


def test_stdout_closed():
    proc = _shell('$CLI visibility-map >&-', json.dumps(POCKET))
    assert proc.returncode == 2
    _only_json_error(proc.stderr, "stdout is closed")


def test_stdout_full():
    proc = _shell('$CLI visibility-map >/dev/full', json.dumps(POCKET))
    assert proc.returncode == 2
    _only_json_error(proc.stderr, "No space left on device")
    proc = _shell('$CLI --help >/dev/full')
    assert proc.returncode == 2
    _only_json_error(proc.stderr, "No space left on device")


def test_stdout_reader_gone():
    """`mfgeom ... | head -c1` on a result larger than the pipe buffer: the reader is
    gone before the write ends (EPIPE).  The reader reads one byte and leaves (GNU head
    9.1 here drains its input, so it would not break the pipe)."""
    doc = {"rings": [[[0, 0], [1, 0], [1, 1]]], "points": [[0.5, 0.25]] * 200000, "tol": 0}
    proc = _shell(f'$CLI classify-points --names | {PYTHON} -c "import os; os.read(0, 1)"; '
                  'echo "exit ${PIPESTATUS[0]}" >&2', json.dumps(doc))
    err, status = proc.stderr.rstrip("\n").rsplit("\n", 1)
    assert status == "exit 2", proc.stderr
    _only_json_error(err, "Broken pipe")


def test_stdout_pipe_closed_before_start():
    read_end, write_end = os.pipe()
    os.close(read_end)
    try:
        proc = subprocess.run([PYTHON, "-m", "mfgeom.cli", "visibility-map"],
                              input=json.dumps(POCKET).encode(), stdout=write_end,
                              stderr=subprocess.PIPE, env=_env(), timeout=120)
    finally:
        os.close(write_end)
    assert proc.returncode == 2
    _only_json_error(proc.stderr.decode(), "Broken pipe")


def test_stdin_closed():
    proc = _shell('$CLI visibility-map <&-')
    assert proc.returncode == 2
    _only_json_error(proc.stderr, "stdin")
    # a FILE argument needs no stdin
    proc = _shell('$CLI version <&-')
    assert proc.returncode == 0 and json.loads(proc.stdout)["library"] == core.version()


def test_every_stream_closed_still_exits_2():
    proc = _shell('$CLI visibility-map <&- >&- 2>&-; echo "exit $?"')
    assert proc.stdout.strip() == "exit 2" and proc.stderr == ""


def test_large_result_through_a_slow_pipe_is_complete():
    """A result far larger than the pipe buffer, read slowly, arrives whole."""
    doc = {"rings": [[[0, 0], [1, 0], [1, 1]]], "points": [[0.5, 0.25]] * 200000, "tol": 0}
    proc = _shell(f'$CLI classify-points | {PYTHON} -c "import sys, time; time.sleep(0.5); '
                  f'sys.stdout.write(sys.stdin.read())"', json.dumps(doc))
    assert proc.returncode == 0 and proc.stderr == ""
    assert json.loads(proc.stdout)["codes"] == [1] * 200000


def test_missing_library_is_a_json_error(tmp_path):
    env = _env()
    env["MFGEOM_LIBRARY"] = str(tmp_path / "libmfgeom.so")
    proc = subprocess.run([PYTHON, "-m", "mfgeom.cli", "visibility-map"],
                          input=json.dumps(POCKET), capture_output=True, text=True, env=env,
                          timeout=120)
    assert proc.returncode == 2 and proc.stdout == ""
    msg = _only_json_error(proc.stderr, "cannot be used")
    assert f"{tmp_path / 'libmfgeom.so'}: no such file" in msg and "scripts/build.sh" in msg
