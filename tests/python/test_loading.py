# SPDX-License-Identifier: LGPL-2.1-or-later
"""Tests of how mfgeom.core finds and loads libmfgeom.so: lazily, once, never a sanitizer
build unless named by MFGEOM_LIBRARY, and with one clear message (places searched, the
build command) when it is missing.  Each case runs in a fresh interpreter on a copy of
the package, because loading is once per process."""

import json
import os
import shutil
import subprocess
import textwrap

import pytest

from mfgeom import building, core

_HERE = os.path.dirname(os.path.abspath(__file__))
_REPO = os.path.dirname(os.path.dirname(_HERE))
PYTHON = "/usr/bin/python3"


def release_library():
    """The normal build the test session uses (tests run with MFGEOM_LIBRARY set)."""
    return os.path.realpath(core.library_path)


def make_copy(tmp_path, library_at=None, library=None):
    """A copy of the repository's Python package and build script, without any library
    (like an Addon Manager clone); ``library`` is copied to ``library_at`` (relative)."""
    root = tmp_path / "addon"
    shutil.copytree(os.path.join(_REPO, "workbench"), root / "workbench",
                    ignore=shutil.ignore_patterns("*.so", "__pycache__"))
    (root / "scripts").mkdir()
    shutil.copy(os.path.join(_REPO, "scripts", "build.sh"), root / "scripts" / "build.sh")
    if library_at:
        (root / library_at).parent.mkdir(parents=True, exist_ok=True)
        shutil.copy(library, root / library_at)
    return root


def run_python(code, root=None, env_extra=None, unset=("MFGEOM_LIBRARY",)):
    """Runs ``code`` in a fresh interpreter with the package of ``root`` (default: this
    repository); returns the CompletedProcess.  The code prints JSON on its last line."""
    env = {k: v for k, v in os.environ.items() if k not in unset and k != "LD_LIBRARY_PATH"}
    env["PYTHONPATH"] = os.path.join(str(root or _REPO), "workbench")
    env.update(env_extra or {})
    return subprocess.run([PYTHON, "-c", textwrap.dedent(code)], capture_output=True,
                          text=True, env=env, timeout=120, cwd="/")


def result(proc):
    assert proc.returncode == 0, f"exit {proc.returncode}\n{proc.stdout}\n{proc.stderr}"
    return json.loads(proc.stdout.strip().splitlines()[-1])


LOAD_AND_REPORT = """
    import json
    from mfgeom import core, errors
    try:
        lib = core.load()
        out = {"loaded": core.library_path, "version": core.version()}
    except errors.LibraryError as exc:
        out = {"error": str(exc), "import_error": isinstance(exc, ImportError),
               "mfgeom_error": isinstance(exc, errors.MfgeomError)}
    print(json.dumps(out))
"""


def asan_stand_in(tmp_path, compiler):
    """A tiny shared library built with ASan+UBSan the way MFG_SANITIZE=ON builds, named
    libmfgeom.so: loading it into a process whose first library is not the ASan runtime
    kills the process, which is exactly what the loader must avoid."""
    cc = shutil.which(compiler)
    if cc is None:
        pytest.skip(f"{compiler} not installed")
    src = tmp_path / "stand_in.c"
    src.write_text("int mfg_stand_in(const int *p) { return p[1]; }\n")
    out = tmp_path / compiler / "libmfgeom.so"
    out.parent.mkdir()
    proc = subprocess.run([cc, "-shared", "-fPIC", "-fsanitize=address,undefined", "-o",
                           str(out), str(src)], capture_output=True, text=True)
    if proc.returncode != 0:
        pytest.skip(f"{compiler} cannot build a sanitizer library: {proc.stderr[-300:]}")
    return str(out)


# --------------------------------------------------------------------------- #
# Lazy, once, thread-safe                                                     #
# --------------------------------------------------------------------------- #

def test_import_needs_no_library():
    out = result(run_python("""
        import json, os
        from mfgeom import core
        maps = open("/proc/self/maps").read()
        print(json.dumps({"loaded": core._loaded is not None,
                          "mapped": "libmfgeom" in maps}))
    """, env_extra={"MFGEOM_LIBRARY": "/nonexistent/libmfgeom.so"}, unset=()))
    assert out == {"loaded": False, "mapped": False}


def test_first_call_loads_and_library_path_works():
    lib = release_library()
    out = result(run_python("""
        import json
        from mfgeom import core
        before = core._loaded is None
        codes = core.classify_points([[[0, 0], [1, 0], [1, 1], [0, 1]]], [[0.5, 0.5]], 0.0)
        print(json.dumps({"before": before, "codes": codes.tolist(),
                          "path": core.library_path, "same": core.load() is core.load()}))
    """, env_extra={"MFGEOM_LIBRARY": lib}, unset=()))
    assert out == {"before": True, "codes": [1], "path": lib, "same": True}


def test_concurrent_first_calls_load_once():
    lib = release_library()
    out = result(run_python("""
        import json, threading, time
        from mfgeom import core
        calls = []
        real = core._find_and_open
        def slow_find():
            calls.append(1)
            time.sleep(0.2)        # widen the window in which other threads arrive
            return real()
        core._find_and_open = slow_find
        barrier = threading.Barrier(8)
        got = []
        def worker():
            barrier.wait()
            got.append((id(core.load()), core.version()))
        threads = [threading.Thread(target=worker) for _ in range(8)]
        for t in threads: t.start()
        for t in threads: t.join()
        print(json.dumps({"calls": len(calls), "distinct": len(set(got)), "n": len(got)}))
    """, env_extra={"MFGEOM_LIBRARY": lib}, unset=()))
    assert out == {"calls": 1, "distinct": 1, "n": 8}


# --------------------------------------------------------------------------- #
# Missing library: one message with the places and the command                #
# --------------------------------------------------------------------------- #

def test_missing_library_lists_places_and_build_command(tmp_path):
    root = make_copy(tmp_path)
    out = result(run_python(LOAD_AND_REPORT, root))
    assert out["import_error"] and out["mfgeom_error"]
    msg = out["error"]
    pkg = root / "workbench" / "mfgeom" / "libmfgeom.so"
    assert f"{pkg}: no such file" in msg
    assert f"{root / 'build' / 'libmfgeom.so'}: no such file" in msg
    assert "/usr/local/lib/libmfgeom.so: no such file" in msg
    assert f"cd {root} && bash scripts/build.sh" in msg
    assert "MFGEOM_LIBRARY" in msg


def test_make_function_raises_library_error_before_touching_anything(tmp_path):
    """mfgeom.make_point_classification checks the library first: a LibraryError, and
    the document (a stand-in that records calls) is never used."""
    root = make_copy(tmp_path)
    out = result(run_python("""
        import json
        import mfgeom
        from mfgeom import errors
        class Doc:
            used = []
            def __getattr__(self, name):
                Doc.used.append(name)
                raise AssertionError(name)
        try:
            mfgeom.make_point_classification(Doc(), (None, "Face1"), None, 0.1)
            out = {"raised": None}
        except errors.LibraryError as exc:
            out = {"raised": type(exc).__name__, "import_error": isinstance(exc, ImportError)}
        out["used"] = Doc.used
        print(json.dumps(out))
    """, root))
    assert out == {"raised": "LibraryError", "import_error": True, "used": []}


def test_every_make_function_raises_library_error_before_touching_anything(tmp_path):
    """Every public mfgeom.make_* is @needs_library (the package's promise): without the
    library each raises LibraryError, and neither the document nor the source is used."""
    root = make_copy(tmp_path)
    out = result(run_python("""
        import json
        import mfgeom
        from mfgeom import errors
        class Doc:
            used = []
            def __getattr__(self, name):
                Doc.used.append(name)
                raise AssertionError(name)
        raised = {}
        for name in sorted(n for n in dir(mfgeom) if n.startswith("make_")):
            try:
                getattr(mfgeom, name)(Doc(), Doc())
                raised[name] = None
            except errors.LibraryError:
                raised[name] = "LibraryError"
            except BaseException as exc:
                raised[name] = type(exc).__name__
        print(json.dumps({"raised": raised, "used": Doc.used}))
    """, root))
    assert "make_parting_analysis" in out["raised"] and len(out["raised"]) >= 6, out
    assert set(out["raised"].values()) == {"LibraryError"}, out
    assert out["used"] == []


def test_explicit_missing_file_is_library_error(tmp_path):
    root = make_copy(tmp_path, "workbench/mfgeom/libmfgeom.so", release_library())
    missing = str(tmp_path / "nowhere" / "libmfgeom.so")
    out = result(run_python(LOAD_AND_REPORT, root, {"MFGEOM_LIBRARY": missing}))
    # no silent fallback to the library that is there
    assert "error" in out and out["import_error"]
    assert f"MFGEOM_LIBRARY={missing}" in out["error"]
    assert f"{missing}: no such file" in out["error"]


def test_failed_load_is_retried_after_the_build(tmp_path):
    root = make_copy(tmp_path)
    target = root / "workbench" / "mfgeom" / "libmfgeom.so"
    out = result(run_python(f"""
        import json, shutil
        from mfgeom import core, errors
        try:
            core.load()
            first = "loaded"
        except errors.LibraryError:
            first = "error"
        shutil.copy({release_library()!r}, {str(target)!r})   # "the build"
        core.load()
        print(json.dumps({{"first": first, "then": core.library_path,
                           "version": core.version()}}))
    """, root))
    assert out["first"] == "error" and out["then"] == str(target) and out["version"]


# --------------------------------------------------------------------------- #
# Sanitizer builds                                                            #
# --------------------------------------------------------------------------- #

@pytest.mark.parametrize("compiler", ["gcc", "clang"])
def test_sanitizer_build_is_detected(tmp_path, compiler):
    asan = asan_stand_in(tmp_path, compiler)
    assert "AddressSanitizer" in core.sanitizers(asan)
    assert core.sanitizers(release_library()) == []


@pytest.mark.parametrize("compiler", ["gcc", "clang"])
def test_sanitizer_build_is_skipped_unless_named(tmp_path, compiler):
    """The issue's case: the usual place holds an ASan build (build-asan copied or
    configured into build/).  Before, the process died; now it is skipped, with the
    reason in the message, and the next place is used."""
    asan = asan_stand_in(tmp_path, compiler)
    root = make_copy(tmp_path, "build/libmfgeom.so", asan)
    out = result(run_python(LOAD_AND_REPORT, root))
    assert "error" in out, out
    skipped = f"{root / 'build' / 'libmfgeom.so'}: skipped: built with AddressSanitizer"
    assert skipped in out["error"], out["error"]
    # the sanitizer build first in the order (beside the binding), a normal one in build/:
    # the first is skipped, the second loaded
    shutil.copy(asan, root / "workbench" / "mfgeom" / "libmfgeom.so")
    shutil.copy(release_library(), root / "build" / "libmfgeom.so")
    out = result(run_python(LOAD_AND_REPORT, root))
    assert out.get("loaded") == str(root / "build" / "libmfgeom.so"), out


def test_build_asan_is_not_a_fallback(tmp_path):
    """The issue's repro: build/ empty, build-asan/ present.  The old loader tried
    build-asan/ and the process died ("ASan runtime does not come first")."""
    asan = asan_stand_in(tmp_path, "gcc")
    root = make_copy(tmp_path, "build-asan/libmfgeom.so", asan)
    (root / "build").mkdir()
    out = result(run_python(LOAD_AND_REPORT, root))
    assert "error" in out and "build-asan" not in out["error"], out


@pytest.mark.parametrize("compiler", ["gcc", "clang"])
def test_named_sanitizer_build_without_its_runtime_is_an_error_not_a_crash(tmp_path,
                                                                             compiler):
    asan = asan_stand_in(tmp_path, compiler)
    out = result(run_python(LOAD_AND_REPORT, None, {"MFGEOM_LIBRARY": asan}))
    assert "error" in out and "is built with AddressSanitizer" in out["error"]
    assert "LD_PRELOAD" in out["error"]


def test_named_sanitizer_build_loads_under_its_runtime(tmp_path):
    asan = asan_stand_in(tmp_path, "gcc")
    runtime = subprocess.run(["gcc", "-print-file-name=libasan.so"], capture_output=True,
                             text=True).stdout.strip()
    if not os.path.isabs(runtime):
        pytest.skip("gcc has no libasan.so")
    proc = run_python("""
        import json
        from mfgeom import core
        core.load()
        print(json.dumps({"loaded": core.library_path}))
    """, None, {"MFGEOM_LIBRARY": asan, "LD_PRELOAD": runtime,
                "ASAN_OPTIONS": "detect_leaks=0"})
    assert result(proc) == {"loaded": asan}


def test_elf_reader_on_non_elf_files(tmp_path):
    junk = tmp_path / "libmfgeom.so"
    junk.write_bytes(b"\x7fELF\x02\x01" + b"\xff" * 20)     # truncated header
    assert core.sanitizers(str(junk)) == []
    junk.write_text("not a library")
    assert core.sanitizers(str(junk)) == []


# --------------------------------------------------------------------------- #
# What to install                                                             #
# --------------------------------------------------------------------------- #

@pytest.mark.parametrize("release,expected", [
    ('ID=debian\nVERSION_ID="12"\n', "sudo apt-get install cmake gcc"),
    ('ID=linuxmint\nID_LIKE="ubuntu debian"\n', "sudo apt-get install cmake gcc"),
    ('ID="fedora"\n', "sudo dnf install cmake gcc"),
    ('ID="opensuse-tumbleweed"\nID_LIKE="opensuse suse"\n', "sudo zypper install cmake gcc"),
    ("ID=arch\n", "sudo pacman -S cmake gcc"),
])
def test_install_command_per_distribution(tmp_path, release, expected):
    path = tmp_path / "os-release"
    path.write_text(release)
    assert building.install_command(str(path)) == expected


def test_install_command_unknown_system_lists_the_common_ones(tmp_path):
    text = building.install_command(str(tmp_path / "missing"))
    assert "sudo apt-get install cmake gcc" in text and "dnf" in text and "brew" in text


def test_instructions_name_missing_tools(monkeypatch):
    monkeypatch.setenv("PATH", "/nonexistent")
    monkeypatch.delenv("CC", raising=False)
    assert building.missing_tools() == ["cmake", "a C compiler"]
    text = building.instructions()
    assert "cmake and a C compiler not found" in text and "install them first" in text
