# SPDX-License-Identifier: LGPL-2.1-or-later
"""The ctypes twins of mfgeom.h's public structs have the C layout.

libcore/tests/api/abi_layout (built with the library, in the same build tree) prints
sizeof / alignof of every public struct and offsetof / sizeof of every field, as the C
compiler lays them out; this test compares each with ctypes.sizeof / alignment and the
Structure fields' offset / size of the binding's class.  The header itself is parsed for
its struct definitions and their fields, so a struct or field added to mfgeom.h without
a twin in the binding, or without a line in abi_layout.c, fails here."""

import ctypes
import os
import re
import subprocess

import pytest

from build_tree import build_dir
from mfgeom import core, paths

HEADER = os.path.join(paths.REPO_DIR, "libcore", "include", "mfgeom.h")

# struct tag in mfgeom.h -> its ctypes twin in mfgeom.core
TWINS = {
    "mfg_progress": core._Progress,
    "mfg_region_info": core._RegionInfo,
    "mfg_spoly": core._SPoly,
    "mfg_regions": core._Regions,
    "mfg_mesh_report": core._MeshReport,
    "mfg_mesh": core._Mesh,
    "mfg_sweep_stats": core._SweepStats,
    "mfg_medial_axis": core._MedialAxis,
    "mfg_medial": core._Medial,
}


def header_structs(text):
    """{tag: [field names in order]} of every struct *defined* (with a body) in the
    header text; opaque declarations (typedef struct mfg_region mfg_region) have none."""
    text = re.sub(r"/\*.*?\*/", " ", text, flags=re.S)
    text = re.sub(r"//[^\n]*", " ", text)
    structs = {}
    for match in re.finditer(r"\bstruct\s+(mfg_\w+)\s*\{([^}]*)\}", text):
        fields = []
        for decl in match.group(2).split(";"):
            decl = " ".join(decl.split())
            if not decl:
                continue
            for part in decl.split(","):
                name = re.search(r"(\w+)\s*(\[[^\]]*\])?\s*$", part)
                assert name, f"cannot parse {decl!r} in struct {match.group(1)}"
                fields.append(name.group(1))
        structs[match.group(1)] = fields
    return structs


def test_header_parser_reads_a_known_struct():
    text = open(HEADER).read()
    structs = header_structs(text)
    assert structs["mfg_mesh_report"][:3] == ["nvertices", "ntriangles", "boundary_edges"]
    assert structs["mfg_mesh_report"][-1] == "bbox"
    assert "mfg_region" not in structs            # opaque
    assert len(structs) == len(re.findall(r"\bstruct\s+mfg_\w+\s*\{", text))


def test_every_header_struct_has_a_ctypes_twin_with_its_fields():
    structs = header_structs(open(HEADER).read())
    assert sorted(structs) == sorted(TWINS), \
        "mfgeom.h's structs and the binding's twins differ (update TWINS and the binding)"
    for tag, fields in structs.items():
        assert [name for name, *_ in TWINS[tag]._fields_] == fields, tag


def test_every_ctypes_structure_of_the_binding_is_a_twin():
    from mfgeom.core import arrays, axis2d, loader, medial, mesh, pointclass, sphere
    from mfgeom.core import status, sweep
    found = {obj for module in (arrays, axis2d, loader, medial, mesh, pointclass, sphere,
                                status, sweep)
             for obj in vars(module).values()
             if isinstance(obj, type) and issubclass(obj, ctypes.Structure)}
    assert found == set(TWINS.values())


@pytest.fixture(scope="module")
def c_layout():
    build = build_dir()
    if build is None:
        pytest.skip(f"{core.library_path} is not in a CMake build tree: no abi_layout to run")
    program = os.path.join(build, "libcore", "tests", "api", "abi_layout")
    assert os.path.isfile(program), (
        f"{program} is missing, but the library {core.library_path} comes from the build "
        f"tree {build}: build it with  cmake --build {build} --target abi_layout")
    proc = subprocess.run([program], capture_output=True, text=True, timeout=60)
    assert proc.returncode == 0, proc.stderr
    structs, version = {}, None
    for line in proc.stdout.splitlines():
        words = line.split()
        if words[0] == "version":
            version = words[1]
        elif words[0] == "struct":
            structs[words[1]] = {"size": int(words[2]), "align": int(words[3]), "fields": []}
        elif words[0] == "field":
            structs[words[1]]["fields"].append((words[2], int(words[3]), int(words[4])))
        else:
            raise AssertionError(f"unexpected line {line!r}")
    return {"version": version, "structs": structs}


def test_the_program_is_from_the_loaded_build(c_layout):
    assert c_layout["version"] == core.version()


def test_the_program_prints_every_struct_and_field_of_the_header(c_layout):
    structs = header_structs(open(HEADER).read())
    assert sorted(c_layout["structs"]) == sorted(structs)
    for tag, fields in structs.items():
        assert [f[0] for f in c_layout["structs"][tag]["fields"]] == fields, tag


@pytest.mark.parametrize("tag", sorted(TWINS))
def test_ctypes_layout_matches_the_c_layout(c_layout, tag):
    twin = TWINS[tag]
    c = c_layout["structs"][tag]
    assert ctypes.sizeof(twin) == c["size"], f"sizeof(struct {tag})"
    assert ctypes.alignment(twin) == c["align"], f"alignof(struct {tag})"
    for name, offset, size in c["fields"]:
        field = getattr(twin, name)
        assert (field.offset, field.size) == (offset, size), f"struct {tag}.{name}"
