# SPDX-License-Identifier: LGPL-2.1-or-later
"""The corpus of real parts the project did not make (issue 17, item 6): the list of
parts with their origin and licence, and a loader giving each part's solids.

Every part comes from a package installed on the development machine (Debian 12):
FreeCAD's own data (``freecad-common``: its IDF library of electronic packages, its
Path tool-bit shapes and test documents) and Open CASCADE's sample data
(``occt-misc``).  STEP files are stored gzipped as shipped; BREP files gzipped after
``Shape.cleaned()`` (the stored triangulation removed, the geometry unchanged);
FreeCAD documents as shipped (they are zip files already).

    /usr/bin/python3 tests/corpus/corpus.py --list        # the parts, faces, solids
    /usr/bin/python3 tests/corpus/corpus.py --licenses    # rewrites LICENSES.md
    /usr/bin/python3 tests/corpus/corpus.py --copy        # re-creates the files from the
                                                          # installed packages

Loading (:func:`load`) goes through the workbench's own reader,
:func:`mfgeom.app.parting_batch.load_sources`: every solid of a STEP/BREP file, and
for a FreeCAD document every solid of its result objects, in global coordinates.
"""

import gzip
import json
import os
import resource
import select
import shutil
import signal
import sys
import tempfile
import time
from dataclasses import dataclass

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(os.path.dirname(HERE))
if os.path.join(REPO, "workbench") not in sys.path:
    sys.path.append(os.path.join(REPO, "workbench"))

FREECAD_PKG = ("FreeCAD 0.20.2 (Debian package freecad-common 0.20.2+dfsg1-4+deb12u1; "
               "upstream github.com/FreeCAD/FreeCAD tag 0.20.2)")
OCCT_PKG = ("Open CASCADE Technology 7.6.3 (Debian package occt-misc 7.6.3+dfsg1-7; "
            "upstream git.dev.opencascade.org occt.git tag V7_6_3)")
LGPL2 = "LGPL-2.0-or-later (FreeCAD, Debian copyright 'Files: *')"
OCCT_LIC = "LGPL-2.1-only with the Open CASCADE exception (Debian copyright of occt-misc)"
FC_IDF = ("Milos Koutny and FreeCAD contributors (IDF library of FreeCAD's Idf "
          "module; STEP written by the Open CASCADE STEP processor)")
FC_PATH = "FreeCAD contributors (Path workbench)"
FC_DOC_NOTE = ("the document's own License property says 'All rights reserved' "
               "(FreeCAD's default at save time); it is shipped in FreeCAD's source and "
               "package under the licence above")


@dataclass(frozen=True)
class Part:
    """One corpus file: ``file`` (in tests/corpus), ``source`` (the installed file it
    was made from), ``upstream`` (its path in the upstream repository), ``origin``,
    ``author``, ``licence``, ``what`` (a description), ``expect_solids`` (0: a file
    with no solid, which the loader must refuse) and ``tags`` (what it tests)."""
    file: str
    source: str
    upstream: str
    origin: str
    author: str
    licence: str
    what: str
    expect_solids: int
    tags: tuple = ()
    note: str = ""


def _idf(name, what, solids, tags=()):
    return Part(f"{name}.stp.gz", f"/usr/share/freecad/Mod/Idf/Idflibs/{name}.stp",
                f"src/Mod/Idf/Idflibs/{name}.stp", FREECAD_PKG, FC_IDF, LGPL2, what,
                solids, tags)


def _occ(name, what, solids, tags=(), sub="occ", ext="brep"):
    out = f"{name}.{ext}.gz"
    return Part(out, f"/usr/share/opencascade/data/{sub}/{name}.{ext}",
                f"data/{sub}/{name}.{ext}", OCCT_PKG, "Open CASCADE SAS", OCCT_LIC, what,
                solids, tags)


def _fc(path, upstream, what, solids, tags=(), licence=LGPL2, note=FC_DOC_NOTE):
    return Part(os.path.basename(path), path, upstream, FREECAD_PKG, FC_PATH, licence,
                what, solids, tags, note)


_TOOLS = "/usr/share/freecad/Mod/Path/Tools/Shape"
PARTS = (
    # --- moulded and machined parts with B-spline faces, fillets, spheres, tori
    _occ("bottle", "the OCCT tutorial bottle: filleted body, threaded neck", 1,
         ("fillets", "bspline", "torus")),
    _occ("Pump_TopCover", "pump top cover (a moulded cap: sphere dome, B-spline faces)",
         1, ("housing", "bspline", "sphere")),
    _occ("Pump_Nut", "pump nut (cones, tori)", 1, ("cone",)),
    _occ("Bottom", "pump housing, bottom half (323 faces, 120 B-spline)", 1,
         ("housing", "bspline", "large")),
    _occ("CrankArm", "crank arm, two solids (B-spline blends)", 2,
         ("bspline", "multi-solid")),
    _occ("Ball", "ball joint, two solids (sphere, B-spline faces)", 2,
         ("bspline", "sphere", "multi-solid")),
    _occ("Motor-c", "motor assembly, 17 solids", 17, ("assembly", "multi-solid")),
    _occ("Axis_of_bearing", "bearing axis assembly, 18 solids (balls: sphere poles)", 18,
         ("assembly", "multi-solid", "sphere")),
    _occ("MODERN_Sink_1", "kitchen sink, 3 solids (tori, B-spline)", 3,
         ("multi-solid", "torus")),
    _occ("MODERN_Exhaust_1", "cooker hood, 3 solids", 3, ("multi-solid", "bspline")),
    _occ("MODERN_Chair_1", "chair, 4 solids (sphere feet)", 4, ("multi-solid", "sphere")),
    _occ("mal_vis", "screw of the 'mal' set (torus)", 1, ("torus",)),
    _occ("screw", "screw (cones, tori)", 1, ("cone",), sub="step", ext="step"),
    _occ("shell1", "an open shell of 99 B-spline faces (no solid)", 0,
         ("open-shell", "bspline")),
    # --- FreeCAD's IDF library: moulded electronic packages (plastic bodies, leads)
    _idf("0603_SMD", "0603 SMD chip (39 B-spline faces, sphere corners)", 1,
         ("bspline", "sphere")),
    _idf("CAP_50SGV_8_10", "electrolytic capacitor (can, torus, B-spline)", 1,
         ("bspline", "torus")),
    _idf("RLF_7030", "SMD inductor (25 B-spline faces)", 1, ("bspline",)),
    _idf("RLF_12545", "SMD inductor, 3 solids (B-spline)", 3,
         ("bspline", "multi-solid")),
    _idf("I22_2_5_16withEPL22_6_16", "ferrite core with its clip: 2 solids", 2,
         ("assembly", "multi-solid", "clip")),
    _idf("SOT404", "SOT404 package: 4 solids and a free shell", 4, ("multi-solid",)),
    _idf("MSOP_10", "MSOP-10 moulded package (157 faces)", 1, ("housing",)),
    _idf("SOT_96", "SO-8 (SOT96) package, spherical ejector marks", 1,
         ("housing", "sphere")),
    _idf("SOT428_DPAK", "DPAK moulded package", 1, ("housing",)),
    _idf("TCMT1107_4", "TCMT turning insert (machined)", 1, ()),
    _idf("TSM_103_01_L_DV_A", "3-pin header with a moulded body (434 faces, cones)", 1,
         ("large", "cone")),
    _idf("SOD_323", "SOD-323 package as 75 free B-spline faces (no solid)", 0,
         ("open-shell", "bspline")),
    # --- FreeCAD Path tool bits and test documents (.FCStd)
    _fc(f"{_TOOLS}/ballend.fcstd", "src/Mod/Path/Tools/Shape/ballend.fcstd",
        "ball-end mill body (sphere pole on the axis)", 1, ("sphere", "pole")),
    _fc(f"{_TOOLS}/v-bit.fcstd", "src/Mod/Path/Tools/Shape/v-bit.fcstd",
        "V-bit (cone apex)", 1, ("cone", "apex")),
    _fc(f"{_TOOLS}/drill.fcstd", "src/Mod/Path/Tools/Shape/drill.fcstd",
        "drill (cone apex)", 1, ("cone", "apex")),
    _fc(f"{_TOOLS}/bullnose.fcstd", "src/Mod/Path/Tools/Shape/bullnose.fcstd",
        "bull-nose mill (torus)", 1, ("torus",)),
    _fc("/usr/share/freecad/Mod/Path/PathTests/boxtest.fcstd",
        "src/Mod/Path/PathTests/boxtest.fcstd",
        "Path test document: 8 result objects (boxes with holes, cones)", 8,
        ("multi-solid", "cone")),
    _fc("/usr/share/freecad/Mod/Path/PathTests/Drilling_1.FCStd",
        "src/Mod/Path/PathTests/Drilling_1.FCStd",
        "Path drilling test part (holes, extrusion faces)", 1, ("holes",),
        licence=LGPL2 + "; the document itself says CC-BY-4.0", note=""),
)


def path_of(part):
    return os.path.join(HERE, part.file)


def parts(tag=None):
    """The corpus parts (with ``tag``: those carrying it)."""
    return [p for p in PARTS if tag is None or tag in p.tags]


def _inner_name(part):
    return part.file[:-3] if part.file.endswith(".gz") else part.file


def load(part):
    """(name, [Part solids in global coordinates], closer) of one corpus part; raises
    :class:`mfgeom.app.parting_batch.PartError` for a file with no solid.  The solids
    are copies: they stay valid after closer() (which closes an opened document)."""
    from mfgeom.app import gauss_map, parting_batch
    tmp = None
    path = path_of(part)
    if part.file.endswith(".gz"):
        tmp = tempfile.mkdtemp(prefix="mfgeom-corpus-")
        path = os.path.join(tmp, _inner_name(part))
        with gzip.open(path_of(part), "rb") as src, open(path, "wb") as dst:
            shutil.copyfileobj(src, dst)
    try:
        sources, close = parting_batch.load_sources(path)
        try:
            solids = []
            for _label, source, names in sources:
                shape = gauss_map.shape_of(source)
                if names is None:
                    solids += shape.Solids
                else:
                    chosen = [shape.Faces[int(n[4:]) - 1] for n in names]
                    solids.append(next(s for s in shape.Solids
                                       if all(any(f.isSame(g) for g in s.Faces)
                                              for f in chosen)))
        finally:
            close()
        return os.path.splitext(_inner_name(part))[0], solids
    finally:
        if tmp:
            shutil.rmtree(tmp, ignore_errors=True)


def load_sources(part):
    """:func:`mfgeom.app.parting_batch.load_sources` on the part's (un-gzipped) file:
    (sources, closer), the way the CLI batch and the tests read it."""
    from mfgeom.app import parting_batch
    path = path_of(part)
    if part.file.endswith(".gz"):
        tmp = tempfile.mkdtemp(prefix="mfgeom-corpus-")
        inner = os.path.join(tmp, _inner_name(part))
        with gzip.open(path, "rb") as src, open(inner, "wb") as dst:
            shutil.copyfileobj(src, dst)
        try:
            sources, close = parting_batch.load_sources(inner)
        except Exception:
            shutil.rmtree(tmp, ignore_errors=True)
            raise

        def closer():
            close()
            shutil.rmtree(tmp, ignore_errors=True)
        return sources, closer
    return parting_batch.load_sources(path)


def face_kinds(shapes):
    """{surface type name: count} over the faces of ``shapes``."""
    out = {}
    for s in shapes:
        for f in s.Faces:
            name = type(f.Surface).__name__
            out[name] = out.get(name, 0) + 1
    return out


def _vm_limit(memory_gb):
    """Address-space limit for a child: the current size plus ``memory_gb``."""
    with open("/proc/self/status") as f:
        size_kb = next(int(line.split()[1]) for line in f if line.startswith("VmSize:"))
    return size_kb * 1024 + int(memory_gb * 2**30)


def run_isolated(work, timeout, memory_gb=3.0):
    """Runs ``work(emit)`` in a forked child with an address-space limit (its size +
    ``memory_gb``), killed after ``timeout`` s: one part that hangs or exhausts memory
    does not take the others with it (as the CLI batch runs one worker per part).
    ``emit(dict)`` sends a JSON-able message to the parent at once (so the last one
    tells where a killed child was).  Returns (messages, wall seconds, status: "ok",
    "timeout" or "died: signal N / exit N")."""
    rfd, wfd = os.pipe()
    limit = _vm_limit(memory_gb)
    t0 = time.perf_counter()
    pid = os.fork()
    if pid == 0:   # child: never returns
        os.close(rfd)
        rc = 0
        try:
            resource.setrlimit(resource.RLIMIT_AS, (limit, limit))
            out = os.fdopen(wfd, "w")

            def emit(msg):
                out.write(json.dumps(msg) + "\n")
                out.flush()
            work(emit)
            out.close()
        except BaseException:  # noqa: BLE001 - reported as the exit status
            rc = 3
        os._exit(rc)
    os.close(wfd)
    messages, buf, status = [], b"", "ok"
    deadline = t0 + timeout
    while True:
        left = deadline - time.perf_counter()
        if left <= 0:
            os.kill(pid, signal.SIGKILL)
            status = "timeout"
            break
        ready, _, _ = select.select([rfd], [], [], left)
        if not ready:
            continue
        chunk = os.read(rfd, 65536)
        if not chunk:
            break
        buf += chunk
        *lines, buf = buf.split(b"\n")
        messages += [json.loads(x) for x in lines if x]
    os.close(rfd)
    _, code = os.waitpid(pid, 0)
    if status == "ok" and code != 0:
        status = (f"died: signal {os.WTERMSIG(code)}" if os.WIFSIGNALED(code)
                  else f"died: exit {os.WEXITSTATUS(code)}")
    return messages, time.perf_counter() - t0, status


# ------------------------------------------------------------------ maintenance
def _copy():
    """Re-creates the corpus files from the installed packages."""
    import FreeCAD  # noqa: F401  (Part needs FreeCAD imported first)
    import Part as OcctPart
    for p in PARTS:
        dst = path_of(p)
        if p.file.endswith(".brep.gz"):
            shape = OcctPart.read(p.source).cleaned()
            with tempfile.TemporaryDirectory() as tmp:
                brep = os.path.join(tmp, "x.brep")
                shape.exportBrep(brep)
                with open(brep, "rb") as f:
                    data = f.read()
            with gzip.GzipFile(dst, "wb", compresslevel=9, mtime=0) as g:
                g.write(data)
        elif p.file.endswith(".gz"):
            with open(p.source, "rb") as f:
                data = f.read()
            with gzip.GzipFile(dst, "wb", compresslevel=9, mtime=0) as g:
                g.write(data)
        else:
            shutil.copyfile(p.source, dst)
        print(f"{p.file}: {os.path.getsize(dst)} bytes")


def _stats(p):
    try:
        _name, solids = load(p)
    except Exception as exc:
        return None, str(exc)
    return solids, ""


def _licences():
    lines = ["<!-- SPDX-License-Identifier: LGPL-2.1-or-later -->",
             "# Corpus of real parts: origin and licence of each file", "",
             "Written by `/usr/bin/python3 tests/corpus/corpus.py --licenses` from the table "
             "in `corpus.py`. None of these parts was made by the mfgeom project; each file "
             "keeps the licence of the project it comes from. STEP files are stored gzipped "
             "as shipped; BREP files gzipped after `Shape.cleaned()` (the stored "
             "triangulation removed, geometry unchanged); `.fcstd` files as shipped.", "",
             "Full licence texts: LGPL-2.0/2.1 `/usr/share/common-licenses/LGPL-2` and "
             "`LGPL-2.1` on Debian; the Open CASCADE exception: "
             "`/usr/share/doc/occt-misc/copyright` (and OCCT_LGPL_EXCEPTION.txt upstream).",
             ""]
    for p in PARTS:
        solids, err = _stats(p)
        if solids is None:
            shape_note = f"no solid: the loader says \"{err}\""
        else:
            k = face_kinds(solids)
            shape_note = (f"{sum(k.values())} faces in {len(solids)} solid(s), "
                          f"{k.get('BSplineSurface', 0)} B-spline; "
                          + ", ".join(f"{n} {c}" for n, c in sorted(k.items())))
        lines += [f"## {p.file}", "",
                  f"- what: {p.what} ({shape_note})",
                  f"- origin: {p.origin}; installed file `{p.source}`; upstream path "
                  f"`{p.upstream}`",
                  f"- author: {p.author}",
                  f"- licence: {p.licence}"]
        if p.note:
            lines.append(f"- note: {p.note}")
        lines.append("")
    with open(os.path.join(HERE, "LICENSES.md"), "w") as f:
        f.write("\n".join(lines))


def _list():
    for p in PARTS:
        solids, err = _stats(p)
        if solids is None:
            print(f"{p.file:36s} no solid ({err})")
            continue
        k = face_kinds(solids)
        print(f"{p.file:36s} {sum(k.values()):5d} faces {k.get('BSplineSurface', 0):4d} "
              f"B-spline {len(solids):3d} solids  {os.path.getsize(path_of(p)):8d} bytes")


if __name__ == "__main__":
    sys.path.insert(0, os.path.join(REPO, "workbench"))
    from mfgeom import paths  # noqa: E402
    paths.add_freecad_to_path()  # FreeCAD's lib and Mod/Part
    import FreeCAD  # noqa: F401,E402
    arg = sys.argv[1] if len(sys.argv) > 1 else "--list"
    {"--copy": _copy, "--licenses": _licences, "--list": _list}[arg]()
