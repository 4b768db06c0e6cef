# SPDX-License-Identifier: LGPL-2.1-or-later
"""scripts/build.sh as an Addon Manager user runs it: in a fresh copy of the repository
without any library, as a normal (non-root) user, with only cmake and a C compiler (no
C++ compiler); the binding then finds the library it built.  And a clear message when
the tools are missing."""

import json
import os
import pathlib
import shutil
import subprocess
import tempfile

import pytest

_HERE = os.path.dirname(os.path.abspath(__file__))
_REPO = os.path.dirname(os.path.dirname(_HERE))
PYTHON = "/usr/bin/python3"


def fresh_copy(dest):
    """The working tree's tracked and new files (what a clone of it would hold, with the
    uncommitted changes under test), without build outputs."""
    files = subprocess.run(["git", "ls-files", "-z", "--cached", "--others",
                            "--exclude-standard"], cwd=_REPO, capture_output=True,
                           check=True).stdout.decode().split("\0")
    for rel in filter(None, files):
        src = os.path.join(_REPO, rel)
        if not os.path.lexists(src):          # deleted in the working tree
            continue
        os.makedirs(os.path.join(dest, os.path.dirname(rel)), exist_ok=True)
        shutil.copy2(src, os.path.join(dest, rel), follow_symlinks=False)
    return dest


def as_normal_user(cmd, home):
    """``cmd`` run as user nobody when we are root (the script must not need root)."""
    if os.geteuid() != 0:
        return cmd
    setpriv = shutil.which("setpriv")
    if setpriv is None:
        pytest.skip("running as root and setpriv is missing")
    return [setpriv, "--reuid=nobody", "--regid=nogroup", "--clear-groups"] + cmd


@pytest.fixture
def open_tmp():
    """A temporary directory other users can reach (pytest's tmp_path is private to
    root when the tests run as root)."""
    path = tempfile.mkdtemp(prefix="mfgeom-build-test-")
    os.chmod(path, 0o755)
    yield pathlib.Path(path)
    shutil.rmtree(path, ignore_errors=True)


@pytest.mark.skipif(shutil.which("cmake") is None, reason="cmake not installed")
def test_build_script_in_a_fresh_copy_as_a_normal_user(open_tmp):
    tmp_path = open_tmp
    root = fresh_copy(str(tmp_path / "addon"))
    home = tmp_path / "home"
    home.mkdir()
    assert not os.path.lexists(os.path.join(root, "build"))
    assert not os.path.lexists(os.path.join(root, "workbench", "mfgeom", "libmfgeom.so"))
    if os.geteuid() == 0:
        subprocess.run(["chown", "-R", "nobody:nogroup", str(tmp_path)], check=True)
        os.chmod(tmp_path, 0o755)
    env = {"PATH": "/usr/bin:/bin", "HOME": str(home), "LANG": "C.UTF-8",
           # no C++ compiler may be needed: make any use of one fail
           "CXX": "/nonexistent/c++"}
    proc = subprocess.run(as_normal_user(["bash", "scripts/build.sh"], str(home)),
                          cwd=root, env=env, capture_output=True, text=True, timeout=900)
    assert proc.returncode == 0, proc.stdout[-2000:] + proc.stderr[-2000:]
    link = os.path.join(root, "workbench", "mfgeom", "libmfgeom.so")
    assert os.path.islink(link) and os.readlink(link) == "../../build/libmfgeom.so"
    assert f"build: built {root}/build/libmfgeom.so" in proc.stdout
    # the copy's binding loads what was built, with no MFGEOM_LIBRARY
    code = ("import json; from mfgeom import core; "
            "print(json.dumps([core.library_path, core.version(), core.sanitizers("
            "core.library_path), core.classify_points([[[0, 0], [1, 0], [0, 1]]], "
            "[[0.2, 0.2], [1, 1]], 0.0).tolist()]))")
    env = {"PATH": "/usr/bin:/bin", "HOME": str(home),
           "PYTHONPATH": os.path.join(root, "workbench")}
    out = subprocess.run(as_normal_user([PYTHON, "-c", code], str(home)), cwd="/", env=env,
                         capture_output=True, text=True, timeout=120)
    assert out.returncode == 0, out.stderr
    path, version, sanitizers, codes = json.loads(out.stdout)
    assert path == link and version and sanitizers == [] and codes == [1, 0]


def test_build_script_says_what_to_install(tmp_path):
    """Without cmake and a C compiler: exit 1, what is missing and how to install it."""
    root = tmp_path / "addon"
    (root / "scripts").mkdir(parents=True)
    shutil.copy(os.path.join(_REPO, "scripts", "build.sh"), root / "scripts")
    bin_dir = tmp_path / "bin"                 # the basic tools the script uses, no more
    bin_dir.mkdir()
    for tool in ("dirname", "uname", "sed"):
        os.symlink(shutil.which(tool), bin_dir / tool)
    os_release = "/etc/os-release"
    proc = subprocess.run([shutil.which("bash"), "scripts/build.sh"], cwd=root,
                          env={"PATH": str(bin_dir)}, capture_output=True, text=True,
                          timeout=60)
    assert proc.returncode == 1 and proc.stdout == ""
    assert "build: missing cmake and a C compiler" in proc.stderr
    if os.path.exists(os_release) and "debian" in open(os_release).read():
        assert "sudo apt-get install cmake gcc" in proc.stderr
    assert not (root / "build").exists()
