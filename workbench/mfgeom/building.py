# SPDX-License-Identifier: LGPL-2.1-or-later
"""Building libmfgeom.so where mfgeom is installed (e.g. an Addon Manager clone, which has
no library): the tools it needs, the command, what to install when they are missing.
FreeCAD-free: used by the binding's "not found" message and by the workbench's offer to
build."""

import os
import shlex
import shutil
import subprocess

from mfgeom import paths

BUILD_SCRIPT = os.path.join(paths.REPO_DIR, "scripts", "build.sh")

# The package that provides cmake and a C compiler, per distribution family (os-release ID
# or ID_LIKE); the command is shown to the user, never run by mfgeom.
_INSTALL = {
    "debian": "sudo apt-get install cmake gcc",
    "ubuntu": "sudo apt-get install cmake gcc",
    "fedora": "sudo dnf install cmake gcc",
    "rhel": "sudo dnf install cmake gcc",
    "suse": "sudo zypper install cmake gcc",
    "arch": "sudo pacman -S cmake gcc",
    "alpine": "sudo apk add cmake gcc musl-dev make",
}
_INSTALL_OTHERS = ("Debian/Ubuntu: sudo apt-get install cmake gcc; Fedora: sudo dnf install "
                   "cmake gcc; openSUSE: sudo zypper install cmake gcc; Arch: sudo pacman -S "
                   "cmake gcc; macOS: xcode-select --install and brew install cmake")


def c_compiler():
    """The C compiler cmake would pick ($CC, else cc, gcc or clang on PATH), or None."""
    env = os.environ.get("CC")
    if env:
        return shutil.which(shlex.split(env)[0]) if env.strip() else None
    for name in ("cc", "gcc", "clang"):
        found = shutil.which(name)
        if found:
            return found
    return None


def missing_tools():
    """The build tools that are not on PATH: a subset of ["cmake", "a C compiler"]."""
    missing = []
    if shutil.which("cmake") is None:
        missing.append("cmake")
    if c_compiler() is None:
        missing.append("a C compiler")
    return missing


def _os_release(path="/etc/os-release"):
    ids = []
    try:
        with open(path, encoding="utf-8") as f:
            for line in f:
                key, _, value = line.strip().partition("=")
                if key in ("ID", "ID_LIKE"):
                    ids += value.strip('"').split()
    except OSError:
        pass
    return ids


def install_command(os_release="/etc/os-release"):
    """The command that installs cmake and a C compiler on this system (a hint for the
    user, covering the common distributions when this one is not recognised)."""
    for ident in _os_release(os_release):
        for family, command in _INSTALL.items():
            if ident == family or ident.startswith(family):
                return command
    return _INSTALL_OTHERS


def build_argv():
    """(folder, argv) of the command that builds the library here."""
    if os.path.isfile(BUILD_SCRIPT):
        return paths.REPO_DIR, ["bash", os.path.join("scripts", "build.sh")]
    return paths.REPO_DIR, ["sh", "-c", "cmake -S . -B build -DCMAKE_BUILD_TYPE=Release "
                                        "-DMFG_SANITIZE=OFF && cmake --build build "
                                        "--target mfgeom"]


def build_command_text():
    """The build command as the user would type it, with the folder to run it in."""
    folder, argv = build_argv()
    command = argv[2] if argv[:2] == ["sh", "-c"] else " ".join(map(shlex.quote, argv))
    return f"cd {shlex.quote(folder)} && {command}"


def instructions():
    """How to build the library: the command, and what to install first if the tools
    are missing."""
    text = (f"Build it (needs cmake and a C compiler, no root) with:\n"
            f"  {build_command_text()}")
    missing = missing_tools()
    if missing:
        text += (f"\n{' and '.join(missing)} not found on PATH: install them first "
                 f"({install_command()}).")
    return text


def run(on_output=None):
    """Runs the build, passing each output line to ``on_output``; returns the exit code.
    Blocking: the GUI runs the same command through a QProcess instead."""
    folder, argv = build_argv()
    proc = subprocess.Popen(argv, cwd=folder, stdout=subprocess.PIPE,
                            stderr=subprocess.STDOUT, text=True, errors="replace")
    for line in proc.stdout:
        if on_output is not None:
            on_output(line)
    return proc.wait()
