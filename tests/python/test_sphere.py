# SPDX-License-Identifier: LGPL-2.1-or-later
"""Tests of visibility maps and the maximum / level / minimum intersection of spherical convex polygons (seed 000) against their definitions, by dense sampling of the sphere."""

import math

import numpy as np
import pytest

from mfgeom import core

# --------------------------------------------------------------------------- #
# Helpers: sampling, random normals, our own containment tests                #
# --------------------------------------------------------------------------- #

def fibonacci_sphere(n):
    """n nearly uniform unit directions (Fibonacci lattice)."""
    i = np.arange(n, dtype=np.float64) + 0.5
    z = 1.0 - 2.0 * i / n
    r = np.sqrt(np.maximum(0.0, 1.0 - z * z))
    phi = i * (math.pi * (3.0 - math.sqrt(5.0)))
    return np.column_stack((r * np.cos(phi), r * np.sin(phi), z))


FIB_200K = fibonacci_sphere(200_000)
FIB_100K = fibonacci_sphere(100_000)


def unit(v):
    v = np.asarray(v, dtype=np.float64)
    return v / np.linalg.norm(v, axis=-1, keepdims=True)


def frame(c):
    """Two unit vectors completing unit c to a right-handed orthonormal frame."""
    c = unit(c)
    a = np.array([1.0, 0, 0]) if abs(c[0]) < 0.9 else np.array([0, 1.0, 0])
    e1 = unit(np.cross(c, a))
    return e1, np.cross(c, e1)


def cap_samples(rng, centre, radius, n):
    """n uniform random directions in the cap of angular radius ``radius`` about centre."""
    e1, e2 = frame(centre)
    c = unit(centre)
    z = rng.uniform(math.cos(radius), 1.0, n)
    r = np.sqrt(np.maximum(0.0, 1.0 - z * z))
    phi = rng.uniform(0, 2 * math.pi, n)
    return (z[:, None] * c + (r * np.cos(phi))[:, None] * e1 + (r * np.sin(phi))[:, None] * e2)


def circle_points(centre, radius, angles):
    e1, e2 = frame(centre)
    c = unit(centre)
    a = np.asarray(angles, dtype=np.float64)
    return (math.cos(radius) * c + math.sin(radius) * (np.cos(a)[:, None] * e1
                                                       + np.sin(a)[:, None] * e2))


def random_direction(rng):
    return unit(rng.normal(size=3))


def min_dot(dirs, normals):
    """min over the normals p of d . p^ for every direction d (the definition of VM)."""
    pn = unit(np.asarray(normals, dtype=np.float64)).T.copy()
    chunk = max(1, 4_000_000 // pn.shape[1])   # at most 32 MB of products at a time
    out = np.empty(len(dirs))
    for s in range(0, len(dirs), chunk):
        out[s:s + chunk] = (dirs[s:s + chunk] @ pn).min(axis=1)
    return out


def edge_normals(verts, unit_len=True):
    v = np.asarray(verts)
    n = np.cross(v, np.roll(v, -1, axis=0))
    return unit(n) if unit_len else n


def inside_polygon(dirs, verts, tol=1e-12):
    """Our own containment test: d . (v_i x v_i+1) >= -tol for every edge."""
    n = edge_normals(verts, unit_len=False)
    return np.all(dirs @ n.T >= -tol, axis=1)


def slerp_points(a, b, k):
    """k points strictly inside the minor arc a -> b."""
    t = (np.arange(k) + 1.0) / (k + 1.0)
    ang = math.acos(max(-1.0, min(1.0, float(a @ b))))
    if ang < 1e-15:
        return np.repeat(a[None], k, axis=0)
    return unit((np.sin((1 - t) * ang)[:, None] * a + np.sin(t * ang)[:, None] * b)
                / math.sin(ang))


def assert_valid_vm(normals, vm, samples=None, rng=None):
    """Checks a visibility map against VM(P) = {d : d.p >= 0}: structure of the
    polygon and dense sampling of the definition.  Returns the number of samples
    found strictly inside."""
    P = np.asarray(normals, dtype=np.float64)
    Pn = unit(P)
    V = vm.vertices
    assert np.all(np.isfinite(V))
    if len(V):
        assert np.allclose(np.linalg.norm(V, axis=1), 1.0, atol=1e-14), "vertices not unit"
        # every returned direction is in VM(P)
        mv = min_dot(V, P)
        assert mv.min() >= -1e-12, f"a vertex is outside VM: min d.p = {mv.min()!r}"
    # directions strictly in VM(P), globally and near the map
    dirs = FIB_200K if samples is None else samples
    if samples is None and rng is not None and len(V):
        c = unit(V.sum(axis=0)) if np.linalg.norm(V.sum(axis=0)) > 1e-6 else V[0]
        rad = min(math.pi, max(float(np.arccos(np.clip(V @ c, -1, 1)).max()) * 1.5, 1e-3))
        dirs = np.vstack((dirs, cap_samples(rng, c, rad, 50_000)))
    md = min_dot(dirs, P)
    strict_in = md > 1e-9
    strict_out = md < -1e-9
    if vm.kind != "polygon":
        assert not strict_in.any(), (
            f"kind {vm.kind} but {strict_in.sum()} directions are strictly inside VM")
        return 0
    assert len(V) >= 3
    inside = inside_polygon(dirs, V)
    bad_in = strict_in & ~inside
    bad_out = strict_out & inside
    assert not bad_in.any(), (
        f"{bad_in.sum()} directions in VM (min d.p up to {md[bad_in].max():.3g}) are outside "
        f"the polygon, e.g. {dirs[bad_in][0].tolist()}")
    assert not bad_out.any(), (
        f"{bad_out.sum()} directions outside VM (min d.p down to {md[bad_out].min():.3g}) are "
        f"inside the polygon, e.g. {dirs[bad_out][0].tolist()}")
    # edges: minor arcs, each on a great circle GC(p) of one normal p
    k = len(V)
    cr = np.linalg.norm(np.cross(V, np.roll(V, -1, axis=0)), axis=1)
    dots = np.einsum("ij,ij->i", V, np.roll(V, -1, axis=0))
    assert np.all((cr > 1e-14) & ((dots > 0) | (cr > 1e-9))), "an edge is not a minor arc"
    on = np.abs(V @ Pn.T) < 1e-12
    for i in range(k):
        assert np.any(on[i] & on[(i + 1) % k]), (
            f"edge {i} ({V[i].tolist()} -> {V[(i + 1) % k].tolist()}) lies on no great "
            f"circle GC(p): min |v.p| = {np.abs(V[i] @ Pn.T).min():.3g}, "
            f"{np.abs(V[(i + 1) % k] @ Pn.T).min():.3g}")
    # convex and counter-clockwise: every vertex left of (or on) every edge, and the
    # deepest interior sample strictly left of all of them
    n = edge_normals(V)
    assert (V @ n.T).min() >= -1e-12, "polygon is not convex / not counter-clockwise"
    if strict_in.any():
        best = dirs[np.argmax(md)]
        assert np.all(best @ n.T > 0), "interior is not on the left of the edges (not CCW)"
    return int(strict_in.sum())


def random_cap_normals(rng, m, radius=None, centre=None):
    if radius is None:
        radius = rng.uniform(0.05, math.radians(89.0))
    if centre is None:
        centre = random_direction(rng)
    return cap_samples(rng, centre, radius, m)


def vm_same_set(a, b, tol=1e-12):
    """Two vertex lists describe the same set of directions (unique polygon vertices)."""
    if len(a) != len(b):
        return False
    d = np.linalg.norm(a[:, None, :] - b[None, :, :], axis=2)
    return bool(np.all(d.min(axis=1) <= tol) and np.all(d.min(axis=0) <= tol))


def polygons_close(a, b, tol):
    """Two convex polygons are the same set up to ``tol`` radians: no vertex of either
    lies farther than tol outside the other."""
    def outside(p, v):
        return -np.arcsin(np.clip(p @ edge_normals(v).T, -1, 1)).min(axis=1)
    return bool(outside(a, b).max() <= tol and outside(b, a).max() <= tol)


# --------------------------------------------------------------------------- #
# Visibility maps: constructed kinds                                          #
# --------------------------------------------------------------------------- #

def test_one_normal_is_a_hemisphere():
    p = np.array([[0.3, -0.4, 0.8]])
    vm = core.visibility_map(p)
    assert vm.kind == "polygon" and len(vm.vertices) == 3
    assert np.all(np.abs(vm.vertices @ unit(p[0])) < 1e-15)
    assert_valid_vm(p, vm)


def test_two_normals_give_a_lune():
    p = np.array([[0, 0, 1.0], [1.0, 0.2, 0.1]])
    vm = core.visibility_map(p)
    assert vm.kind == "polygon" and len(vm.vertices) == 4
    assert_valid_vm(p, vm)
    # its two corners are the poles of the plane of the normals
    pole = unit(np.cross(p[0], p[1]))
    assert min(np.linalg.norm(vm.vertices - pole, axis=1)) < 1e-14
    assert min(np.linalg.norm(vm.vertices + pole, axis=1)) < 1e-14


def test_parallel_normals_give_a_hemisphere():
    p = np.array([[1.0, 2.0, 3.0], [2.0, 4.0, 6.0], [1e-3, 2e-3, 3e-3]])
    vm = core.visibility_map(p)
    assert vm.kind == "polygon" and len(vm.vertices) == 3
    assert_valid_vm(p, vm)


def test_antipodal_pair_is_a_whole_great_circle():
    p = np.array([[0.0, 0.6, 0.8], [0.0, -0.6, -0.8]])
    vm = core.visibility_map(p)
    assert vm.kind == "edge" and vm.closed and len(vm.vertices) == 3
    assert np.all(np.abs(vm.vertices @ p[0]) < 1e-15)
    # three points 120 degrees apart
    g = vm.vertices @ vm.vertices.T
    assert np.allclose(g[np.triu_indices(3, 1)], -0.5, atol=1e-14)
    assert_valid_vm(p, vm)


def test_antipodal_pair_and_a_third_is_a_half_circle():
    p = np.array([[0, 0, 1.0], [0, 0, -1.0], [1.0, 1.0, 0.5]])
    vm = core.visibility_map(p)
    assert vm.kind == "edge" and not vm.closed and len(vm.vertices) == 3
    v = vm.vertices
    assert np.all(np.abs(v[:, 2]) < 1e-15)
    assert np.allclose(v[0], -v[-1], atol=1e-14), "ends of a half circle are antipodal"
    assert np.allclose(v[1], unit([1.0, 1.0, 0.0]), atol=1e-14), "midpoint: projection of p3"
    assert min_dot(v, p).min() >= -1e-15
    assert_valid_vm(p, vm)


def test_antipodal_pair_and_two_more_is_a_shorter_arc():
    p = np.array([[0, 0, 1.0], [0, 0, -1.0], [1.0, 0, 0.3], [0, 1.0, -0.2]])
    vm = core.visibility_map(p)
    assert vm.kind == "edge" and not vm.closed
    v = vm.vertices
    assert np.all(np.abs(v[:, 2]) < 1e-15)
    ends = {tuple(np.round(v[0], 12)), tuple(np.round(v[-1], 12))}
    assert ends == {(1.0, 0.0, 0.0), (0.0, 1.0, 0.0)}
    assert np.all(np.einsum("ij,ij->i", v[:-1], v[1:]) > -1 + 1e-9)
    # the whole arc is visible, and nothing beyond its ends
    arc = np.vstack([slerp_points(v[i], v[i + 1], 50) for i in range(len(v) - 1)])
    assert min_dot(arc, p).min() >= -1e-15
    t = 1e-6
    beyond = np.array([[math.cos(-t), math.sin(-t), 0], [math.sin(-t), math.cos(-t), 0]])
    assert min_dot(beyond, p).max() < 0
    assert_valid_vm(p, vm)


def test_three_normals_on_a_great_circle_in_no_half_are_two_points():
    a = np.array([0.0, 1.1, 2.3, 4.0])
    p = np.column_stack((np.cos(a), np.sin(a), np.zeros(4)))[[0, 2, 3]]  # spans > pi
    vm = core.visibility_map(p)
    assert vm.kind == "point" and len(vm.vertices) == 2
    v = vm.vertices
    assert np.allclose(np.abs(v[:, 2]), 1.0, atol=1e-15) and v[0][2] == -v[1][2]
    assert_valid_vm(p, vm)


def test_same_plus_one_off_the_circle_is_one_point():
    a = np.array([0.0, 2.3, 4.0])
    p = np.column_stack((np.cos(a), np.sin(a), np.zeros(3)))
    p = np.vstack((p, [[0.2, 0.3, -0.5]]))
    vm = core.visibility_map(p)
    assert vm.kind == "point" and len(vm.vertices) == 1
    assert np.allclose(vm.vertices[0], [0, 0, -1.0], atol=1e-15)
    assert_valid_vm(p, vm)


def test_normals_beyond_a_hemisphere_are_null():
    p = np.array([[1, 1, 1.0], [1, -1, -1.0], [-1, 1, -1.0], [-1, -1, 1.0]])  # tetrahedron
    vm = core.visibility_map(p)
    assert vm.kind == "null" and len(vm.vertices) == 0
    assert_valid_vm(p, vm)


def test_box_is_null_and_pocket_is_its_floor_direction():
    box = np.array([[1, 0, 0], [-1, 0, 0], [0, 1, 0], [0, -1, 0], [0, 0, 1], [0, 0, -1.0]])
    assert core.visibility_map(box).kind == "null"
    pocket = np.array([[0, 0, 1.0], [1, 0, 0], [-1, 0, 0], [0, 1, 0], [0, -1, 0]])
    vm = core.visibility_map(pocket)
    assert vm.kind == "point" and len(vm.vertices) == 1
    assert np.allclose(vm.vertices[0], [0, 0, 1], atol=1e-15)
    # drafted walls (3 degrees): the map opens to a polygon around +z
    t = math.radians(3)
    drafted = np.array([[0, 0, 1.0], [math.cos(t), 0, math.sin(t)],
                        [-math.cos(t), 0, math.sin(t)], [0, math.cos(t), math.sin(t)],
                        [0, -math.cos(t), math.sin(t)]])
    vm = core.visibility_map(drafted)
    assert vm.kind == "polygon" and len(vm.vertices) == 4
    assert inside_polygon(np.array([[0, 0, 1.0]]), vm.vertices)[0]
    assert assert_valid_vm(drafted, vm, rng=np.random.default_rng(1)) > 0
    # the negative map is the mirror image, about -z
    neg = core.visibility_map(drafted, negative=True)
    assert neg.kind == "polygon" and inside_polygon(np.array([[0, 0, -1.0]]), neg.vertices)[0]
    assert vm_same_set(-neg.vertices, vm.vertices)
    # a pocket with an undercut wall (tilted 3 degrees the other way) and its floor
    # cannot be seen from one side: the floor normal z and the wall normal (1, 0, -s)
    # with its opposite wall make VM a point or empty; with two undercut walls, empty
    under = drafted.copy()
    under[1:, 2] *= -1
    assert core.visibility_map(under).kind == "null"


# --------------------------------------------------------------------------- #
# Visibility maps: duplicates, random caps, large inputs                      #
# --------------------------------------------------------------------------- #

def test_duplicated_normals():
    rng = np.random.default_rng(7)
    p = random_cap_normals(rng, 12, radius=0.8, centre=[0.1, 0.2, 1.0])
    # exact duplicates and power-of-two multiples are the same directions: same map
    pd = np.vstack((p, p, 4.0 * p[:5], 0.125 * p[3:]))
    vm1, vm2 = core.visibility_map(p), core.visibility_map(pd)
    assert vm1.kind == vm2.kind == "polygon"
    assert vm_same_set(vm1.vertices, vm2.vertices)
    assert_valid_vm(pd, vm2, rng=rng)
    # 3p is rounded: a direction ~1e-17 away, which may add a vertex to the exact map
    p3 = np.vstack((p, 3.0 * p))
    vm3 = core.visibility_map(p3)
    assert vm3.kind == "polygon"
    assert_valid_vm(p3, vm3, rng=rng)
    assert polygons_close(vm3.vertices, vm1.vertices, 1e-12)


@pytest.mark.parametrize("seed", range(6))
def test_near_duplicate_normals(seed):
    """Normals perturbed by ~1e-15: the exact hull may keep both copies; the map must
    still match the definition and its edges lie on the normals' great circles."""
    rng = np.random.default_rng(100 + seed)
    p = random_cap_normals(rng, 8, radius=rng.uniform(0.2, 1.3))
    ulp = np.spacing(np.abs(p)).max(axis=1)
    copies = [p]
    for _ in range(3):
        copies.append(p + rng.integers(-4, 5, size=p.shape) * ulp[:, None])
    pd = np.vstack(copies)
    vm = core.visibility_map(pd)
    assert vm.kind == "polygon"
    assert_valid_vm(pd, vm, rng=rng)


def test_near_duplicate_minimal_case():
    """The smallest near-duplicate case: two normals 1 ulp apart plus three others."""
    p = np.array([[0.3, 0.2, 1.0], [0.3, 0.2, 1.0 + 2.220446049250313e-16],
                  [0.30000000000000004, 0.2, 1.0], [-0.3, 0.1, 1.0], [0.0, -0.4, 1.0]])
    vm = core.visibility_map(p)
    assert vm.kind == "polygon"
    assert_valid_vm(p, vm, rng=np.random.default_rng(5))


@pytest.mark.parametrize("seed", range(12))
def test_random_caps_against_definition(seed):
    rng = np.random.default_rng(seed)
    m = int(rng.choice([3, 5, 10, 40, 200]))
    p = random_cap_normals(rng, m)
    p *= rng.uniform(0.1, 10.0, size=(m, 1))  # lengths do not matter
    vm = core.visibility_map(p)
    assert vm.kind == "polygon", "normals in an open cap < 90 degrees: VM has interior"
    assert assert_valid_vm(p, vm, rng=rng) > 0


def test_random_normals_over_the_sphere_are_null():
    rng = np.random.default_rng(3)
    p = rng.normal(size=(50, 3))
    assert core.visibility_map(p).kind == "null"


def test_permutation_invariance():
    rng = np.random.default_rng(11)
    for _ in range(5):
        p = random_cap_normals(rng, 60)
        vm = core.visibility_map(p)
        for _ in range(3):
            vmp = core.visibility_map(p[rng.permutation(len(p))])
            assert vmp.kind == vm.kind
            assert vm_same_set(vm.vertices, vmp.vertices)


def _survives_in_a_subprocess(normals, tmp_path):
    """Computes VM(normals) in a child interpreter first, so that a crash is reported as
    a failure instead of taking the whole test run down.  Returns (exit code, stderr)."""
    import os
    import subprocess
    import sys
    path = os.path.join(str(tmp_path), "normals.npy")
    np.save(path, np.asarray(normals, dtype=np.float64))
    env = dict(os.environ)
    env["PYTHONPATH"] = os.pathsep.join(p for p in sys.path if p)
    code = ("import sys, numpy as np\nfrom mfgeom import core\n"
            "core.visibility_map(np.load(sys.argv[1]))\n")
    proc = subprocess.run([sys.executable, "-c", code, path], env=env, capture_output=True,
                          text=True, timeout=120)
    return proc.returncode, proc.stderr[-2000:]


@pytest.mark.parametrize("k", [64, 65, 100, 1000])
def test_many_hull_vertices(k, tmp_path):
    """k normals on one circle: all are hull vertices, so VM has exactly k vertices."""
    t = 2 * np.pi * np.arange(k) / k
    p = np.column_stack((0.5 * np.cos(t), 0.5 * np.sin(t), np.full(k, 0.75 ** 0.5)))
    rc, err = _survives_in_a_subprocess(p, tmp_path)
    assert rc == 0, f"visibility_map of {k} normals on a circle crashed (rc {rc}): {err}"
    vm = core.visibility_map(p)
    assert vm.kind == "polygon" and len(vm.vertices) == k
    # VM of k normals at 30 degrees from +z: a regular k-gon about the 60-degree cap,
    # with vertices at z = c / sqrt(c^2 + 3), c = cos(pi / k)
    c = math.cos(math.pi / k)
    assert np.allclose(vm.vertices[:, 2], c / math.sqrt(c * c + 3), atol=1e-12)
    rng = np.random.default_rng(k)
    samples = np.vstack((FIB_100K, cap_samples(rng, [0, 0, 1.0], 1.1, 20_000)))
    assert assert_valid_vm(p, vm, samples=samples) > 0


def test_hundred_thousand_normals(tmp_path):
    rng = np.random.default_rng(12)
    p = random_cap_normals(rng, 100_000, radius=1.2, centre=[0.3, -0.2, 1.0])
    rc, err = _survives_in_a_subprocess(p, tmp_path)
    assert rc == 0, f"visibility_map of 1e5 normals crashed (rc {rc}): {err}"
    vm = core.visibility_map(p)
    assert vm.kind == "polygon"
    samples = np.vstack((fibonacci_sphere(4_000),
                         cap_samples(rng, [0.3, -0.2, 1.0], math.pi / 2 - 1.1, 4_000)))
    assert assert_valid_vm(p, vm, samples=samples) > 0
    # every vertex against all 1e5 constraints, and the polygon is tight: each edge's
    # great circle is a constraint (checked above), each vertex on two of them
    on = np.abs(vm.vertices @ unit(p).T) < 1e-12
    assert np.all(on.sum(axis=1) >= 2)


def test_negative_map_is_minus_vm():
    rng = np.random.default_rng(13)
    for _ in range(4):
        p = random_cap_normals(rng, 30, radius=rng.uniform(0.3, 1.4))
        neg = core.visibility_map(p, negative=True)
        direct = core.visibility_map(-p)
        assert neg.kind == direct.kind == "polygon"
        assert np.array_equal(neg.vertices, direct.vertices)
        pos = core.visibility_map(p)
        assert vm_same_set(-neg.vertices, pos.vertices)
        assert_valid_vm(-p, neg, rng=rng)


@pytest.mark.parametrize("seed", range(4))
def test_draft_angle(seed):
    rng = np.random.default_rng(200 + seed)
    m = int(rng.choice([1, 2, 6, 30]))
    p = random_cap_normals(rng, m, radius=rng.uniform(0.05, 0.9))
    alpha = float(rng.uniform(0.01, 0.4))
    vm = core.visibility_map(p, draft_angle=alpha)
    assert vm.kind == "polygon"
    sa = math.sin(alpha)
    assert min_dot(vm.vertices, p).min() >= sa - 1e-12
    # the polygon is inside the drafted set (convex: vertices suffice) and no point of
    # that set deeper than 2e-4 is missed
    c = unit(unit(p).sum(axis=0))
    dirs = np.vstack((FIB_200K, cap_samples(rng, c, math.pi / 2, 100_000)))
    md = min_dot(dirs, p)
    inside = inside_polygon(dirs, vm.vertices)
    assert not np.any(inside & (md < sa - 1e-9)), "polygon leaves the drafted set"
    deep = md >= sa + 2e-4
    assert deep.any()
    assert np.all(inside[deep]), f"{np.sum(deep & ~inside)} deep directions missed"


def test_draft_on_degenerate_maps_is_null():
    assert core.visibility_map([[0, 0, 1.0], [0, 0, -1.0]], draft_angle=0.1).kind == "null"
    box = [[1, 0, 0], [-1, 0, 0], [0, 1, 0], [0, -1, 0], [0, 0, 1], [0, 0, -1.0]]
    assert core.visibility_map(box, draft_angle=0.1).kind == "null"


@pytest.mark.parametrize("normals,draft,exc", [
    ([[0, 0, float("nan")]], 0.0, core.MfgError),
    ([[0, 0, float("inf")]], 0.0, core.MfgError),
    ([[0, 0, 1.0], [0, 0, 0]], 0.0, core.MfgError),
    (np.zeros((0, 3)), 0.0, core.MfgError),
    ([[0, 0, 1.0, 2.0]], 0.0, ValueError),
    ([0, 0, 1.0], 0.0, ValueError),
    ([[0, 0, 1.0]], math.pi / 2, core.MfgError),
    ([[0, 0, 1.0]], 2.0, core.MfgError),
    ([[0, 0, 1.0]], -0.1, core.MfgError),
    ([[0, 0, 1.0]], float("nan"), core.MfgError),
])
def test_bad_input(normals, draft, exc):
    with pytest.raises(exc) as info:
        core.visibility_map(normals, draft_angle=draft)
    if exc is core.MfgError:
        assert info.value.detail, "the error carries a detail message"


# --------------------------------------------------------------------------- #
# Maximum intersection: helpers                                               #
# --------------------------------------------------------------------------- #

class Cover:
    """Our own closed-set membership for maps (VisibilityMap or vertex arrays), with a
    bounding-cap early-out."""

    def __init__(self, m):
        if isinstance(m, core.VisibilityMap):
            self.kind, self.v, self.closed = m.kind, m.vertices, m.closed
        else:
            self.kind, self.v, self.closed = "polygon", unit(np.asarray(m, float)), False
        self.cos_r = -2.0
        self.zlo, self.zhi = -2.0, 2.0   # z range of the polygon (bounding cap)
        self.c = np.array([0, 0, 1.0])
        if self.kind == "polygon":
            self.n = edge_normals(self.v)
            s = self.v.sum(axis=0)
            if np.linalg.norm(s) > 1e-9:
                self.c = unit(s)
                rad = math.acos(float(np.clip(self.v @ self.c, -1, 1).min()))
                if rad < math.pi / 2 - 1e-6:
                    self.cos_r = math.cos(rad + 1e-6)
                    polar = math.acos(max(-1.0, min(1.0, self.c[2])))
                    self.zhi = math.cos(max(0.0, polar - rad - 1e-6)) + 1e-12
                    self.zlo = math.cos(min(math.pi, polar + rad + 1e-6)) - 1e-12
        elif self.kind == "edge":
            self.g = unit(np.cross(self.v[0], self.v[1]))

    def contains(self, d, tol):
        d = np.atleast_2d(d)
        out = np.zeros(len(d), dtype=bool)
        if self.kind == "null":
            return out
        if self.kind == "point":
            return np.any(np.linalg.norm(d[:, None] - self.v[None], axis=2) <= tol, axis=1)
        if self.kind == "edge":
            on = np.abs(d @ self.g) <= tol
            pieces = len(self.v) if self.closed else len(self.v) - 1
            within = np.zeros(len(d), dtype=bool)
            for i in range(pieces):
                a, b = self.v[i], self.v[(i + 1) % len(self.v)]
                within |= (np.cross(a, d) @ self.g >= -tol) & (np.cross(d, b) @ self.g >= -tol)
            return on & within
        out[self.inside_indices(d, tol)] = True
        return out

    def inside_indices(self, d, tol):
        """Indices of the directions inside this polygon: the bounding cap first, then
        the edges one by one on the survivors."""
        if self.cos_r > -1:
            idx = np.nonzero(d @ self.c >= self.cos_r)[0]
        else:
            idx = np.nonzero(d @ self.n[0] >= -tol)[0]
        for e in self.n:
            if not len(idx):
                break
            idx = idx[d[idx] @ e >= -tol]
        return idx


def coverage(covers, weights, dirs, tol):
    """Covered weight of every direction, map by map; the directions are sorted by z so
    that a polygon only looks at the z band of its bounding cap."""
    w = np.ones(len(covers)) if weights is None else np.asarray(weights, float)
    order = np.argsort(-dirs[:, 2], kind="stable")
    ds = dirs[order]
    negz = -ds[:, 2]
    total = np.zeros(len(dirs))
    for i, c in enumerate(covers):
        if c.kind == "polygon":
            lo = np.searchsorted(negz, -c.zhi, side="left")
            hi = np.searchsorted(negz, -c.zlo, side="right")
            total[lo + c.inside_indices(ds[lo:hi], tol)] += w[i]
        else:
            total += w[i] * c.contains(ds, tol)
    out = np.empty_like(total)
    out[order] = total
    return out


def cover_set(covers, d, tol):
    return frozenset(i for i, c in enumerate(covers) if c.contains(d, tol)[0])


def random_vm(rng, centre=None, radius=None, m=None):
    """A random polygonal visibility map: VM of normals in a random cap < 90 degrees."""
    m = int(rng.integers(3, 30)) if m is None else m
    while True:
        vm = core.visibility_map(random_cap_normals(rng, m, radius=radius, centre=centre))
        if vm.kind == "polygon":
            return vm


def paper_scale_maps(rng, n=29, target_vertices=272):
    """n maps with ~target_vertices vertices in total, over a common hemisphere of
    directions (as the maps of a part's faces would be)."""
    maps, total = [], 0
    for i in range(n):
        k = int(round((target_vertices - total) / (n - i))) + int(rng.integers(-1, 2))
        k = max(3, k)
        centre = unit(np.array([0, 0, 1.0]) + 0.6 * rng.normal(size=3))
        rad = rng.uniform(math.radians(25), math.radians(70))
        ang = np.sort(rng.uniform(0, 2 * math.pi, k))
        normals = circle_points(centre, rad, ang)  # all extreme: k hull vertices
        normals = np.vstack((normals, cap_samples(rng, centre, rad * 0.9, 5)))
        vm = core.visibility_map(normals)
        assert vm.kind == "polygon"
        maps.append(vm)
        total += len(vm.vertices)
    return maps, total


def check_max_result(maps, res, weights=None, samples=FIB_100K):
    covers = [Cover(m) for m in maps]
    w = np.ones(len(maps)) if weights is None else np.asarray(weights, float)
    assert res.count >= 0
    assert len(res.regions) == len(res.kinds) == len(res.covers) == len(res.margins)
    assert len(res.centres) == len(res.regions) >= 1
    d = np.asarray(res.direction, float)
    assert abs(np.linalg.norm(d) - 1) < 1e-12
    assert np.allclose(d, res.centres[0], atol=1e-15)
    margins = np.asarray(res.margins)
    assert np.all(np.diff(margins) <= 1e-15), "regions sorted by decreasing margin"
    assert margins[0] == margins.max() and res.margin == margins[0]
    for r in range(len(res.regions)):
        cov = frozenset(int(i) for i in res.covers[r])
        assert abs(w[list(cov)].sum() - res.count) <= 1e-9 * max(1.0, abs(res.count))
        c = np.asarray(res.centres[r])
        if res.kinds[r] == "polygon" and res.margins[r] > 1e-9:
            # deep inside: exactly the cover set holds it, with a tight tolerance
            assert cover_set(covers, c, 1e-12) == cov, f"region {r}: centre's cover set"
            # the inscribed circle lies in the region
            V = np.asarray(res.regions[r])
            assert len(V) >= 3 and inside_polygon(c[None], V)[0]
            dist = np.arcsin(np.clip(c @ edge_normals(V).T, -1, 1)).min()
            assert dist >= res.margins[r] - 1e-9, "inscribed circle leaves the region"
            for i in cov:
                assert covers[i].contains(V, 1e-9).all(), "region vertex outside its cover"
        else:
            # degenerate region: its point lies in every map of its cover set
            for i in cov:
                assert covers[i].contains(c, 1e-9)[0]
    # no sampled direction (nor any centre) is covered by more weight
    probe = np.vstack((samples, np.asarray(res.centres)))
    best = coverage(covers, w, probe, 1e-12).max()
    assert best <= res.count + 1e-9, f"a direction is covered by {best} > {res.count}"
    return covers


def result_signature(res, mapping=None):
    sets = set()
    for cov in res.covers:
        s = frozenset(int(i) for i in cov)
        if mapping is not None:
            s = frozenset(int(mapping[i]) for i in s)
        sets.add(s)
    return sets


# --------------------------------------------------------------------------- #
# Maximum intersection                                                        #
# --------------------------------------------------------------------------- #

def test_max_intersection_small_by_hand():
    a = core.visibility_map([[0, 0, 1.0], [0.3, 0, 1.0], [0, 0.3, 1.0]])
    b = core.visibility_map([[1.0, 0, 1.0]])
    c = core.visibility_map([[-1.0, 0, 0.2]])
    res = core.max_intersection([a, b, c])
    # all three hold +z; c (x <= 0.2 z) and b (x >= -z) leave a wedge about +z
    assert res.count == 3
    assert set(int(i) for i in res.covers[0]) == {0, 1, 2}
    check_max_result([a, b, c], res)


def test_max_intersection_paper_scale():
    rng = np.random.default_rng(29)
    maps, total = paper_scale_maps(rng)
    assert 250 <= total <= 295
    res = core.max_intersection(maps)
    check_max_result(maps, res)
    # the best sampled direction should reach the maximum here (regions are wide)
    covers = [Cover(m) for m in maps]
    assert coverage(covers, None, FIB_100K, 1e-12).max() >= res.count - 1


@pytest.mark.parametrize("n,seed", [(5, 1), (20, 2), (100, 3), (300, 4), (1000, 5)])
def test_max_intersection_random(n, seed):
    rng = np.random.default_rng(1000 + seed)
    maps = [random_vm(rng, m=int(rng.integers(3, 12))) for _ in range(n)]
    res = core.max_intersection(maps)
    check_max_result(maps, res)


def test_max_intersection_vertex_arrays_and_vm_objects_agree():
    rng = np.random.default_rng(21)
    maps = [random_vm(rng, centre=[0, 0, 1.0], radius=rng.uniform(0.3, 1.2)) for _ in range(15)]
    r1 = core.max_intersection(maps)
    r2 = core.max_intersection([m.vertices for m in maps])
    assert r1.count == r2.count
    assert result_signature(r1) == result_signature(r2)
    assert np.allclose(r1.direction, r2.direction, atol=1e-12)


@pytest.mark.parametrize("seed", range(3))
def test_max_intersection_permutation_invariance(seed):
    rng = np.random.default_rng(300 + seed)
    maps = [random_vm(rng, centre=unit([0, 0, 1.0] + 0.5 * rng.normal(size=3)))
            for _ in range(40)]
    res = core.max_intersection(maps)
    for _ in range(3):
        perm = rng.permutation(len(maps))
        resp = core.max_intersection([maps[i] for i in perm])
        assert resp.count == res.count
        assert result_signature(resp, mapping=perm) == result_signature(res)
        assert np.allclose(resp.direction, res.direction, atol=1e-9)
        assert abs(resp.margin - res.margin) < 1e-9


def test_max_intersection_weights():
    rng = np.random.default_rng(41)
    maps = [random_vm(rng, centre=unit([0, 0, 1.0] + 0.7 * rng.normal(size=3)))
            for _ in range(30)]
    w = rng.uniform(0.1, 5.0, size=len(maps))
    res = core.max_intersection(maps, weights=w)
    check_max_result(maps, res, weights=w)
    # unit weights give the plain count
    r1 = core.max_intersection(maps, weights=np.ones(len(maps)))
    r0 = core.max_intersection(maps)
    assert r1.count == r0.count and result_signature(r1) == result_signature(r0)
    # a dominant weight forces its map into every maximum region
    w2 = np.ones(len(maps))
    w2[7] = 1000.0
    r2 = core.max_intersection(maps, weights=w2)
    assert all(7 in set(int(i) for i in cov) for cov in r2.covers)
    check_max_result(maps, r2, weights=w2)


def test_max_intersection_bad_weights():
    rng = np.random.default_rng(42)
    maps = [random_vm(rng) for _ in range(3)]
    for bad in ([1.0, -1.0, 1.0], [1.0, float("nan"), 1.0], [1.0, 1.0]):
        with pytest.raises((core.MfgError, ValueError)):
            core.max_intersection(maps, weights=bad)


def test_max_intersection_identical_maps():
    vm = core.visibility_map([[0, 0, 1.0], [0.4, 0.1, 1.0], [-0.2, 0.3, 1.0], [0, -0.5, 1.0]])
    maps = [vm] * 6
    res = core.max_intersection(maps)
    assert res.count == 6 and len(res.regions) == 1 and res.kinds[0] == "polygon"
    assert set(int(i) for i in res.covers[0]) == set(range(6))
    assert vm_same_set(np.asarray(res.regions[0]), vm.vertices, tol=1e-9)
    check_max_result(maps, res)


def test_max_intersection_maps_touching_along_a_circle():
    up = core.visibility_map([[0, 0, 1.0], [1.0, 0.2, 1.0], [-0.3, 1.0, 1.0]])
    down = core.visibility_map([[0, 0, -1.0], [1.0, 0.2, -1.0], [-0.3, 1.0, -1.0]])
    # both have an edge on the equator GC(z), mirror images of each other
    # a third map away from both (around -x-y, where neither is)
    other = random_vm(np.random.default_rng(8), centre=[-1.0, -1.0, 0], radius=1.4)
    maps = [up, down, other]
    res = core.max_intersection(maps)
    assert res.count == 2
    assert res.kinds[0] == "edge", f"touching maps meet in an edge, got {res.kinds}"
    assert set(int(i) for i in res.covers[0]) == {0, 1}
    V = np.asarray(res.regions[0])
    assert np.all(np.abs(V[:, 2]) < 1e-9), "the edge lies on the shared circle"
    assert abs(res.direction[2]) < 1e-9 and res.margin == 0
    # the common arc: directions of the equator in both maps
    t = np.linspace(0, 2 * math.pi, 3601)
    eq = np.column_stack((np.cos(t), np.sin(t), np.zeros_like(t)))
    cu, cd = Cover(up), Cover(down)
    common = eq[cu.contains(eq, 1e-12) & cd.contains(eq, 1e-12)]
    assert len(common) > 10
    assert Cover(core.VisibilityMap("edge", V)).contains(common, 1e-9).all()


def test_max_intersection_maps_touching_at_a_point():
    a = core.visibility_map([[1.0, 0, 0], [0, 1.0, 0], [1.0, 1.0, 1.0]])
    b = core.visibility_map([[-1.0, 0, 0], [0, -1.0, 0], [-1.0, -1.0, 1.0]])
    res = core.max_intersection([a, b])
    assert res.count == 2
    assert res.kinds[0] == "point"
    assert np.allclose(res.direction, [0, 0, 1.0], atol=1e-9)
    assert set(int(i) for i in res.covers[0]) == {0, 1}


def test_max_intersection_disjoint_and_degenerate_inputs():
    ring = circle_points([0, 0, 1.0], 0.5, np.linspace(0, 2 * math.pi, 7)[:-1])
    a = core.visibility_map(ring)                  # a cap about +z, radius ~ 1.07
    b = core.visibility_map(ring, negative=True)   # its mirror about -z: disjoint
    empty = core.visibility_map([[1, 1, 1.0], [1, -1, -1.0], [-1, 1, -1.0], [-1, -1, 1.0]])
    assert empty.kind == "null"
    res = core.max_intersection([a, b, empty])
    assert res.count == 1
    covs = result_signature(res)
    assert covs == {frozenset({0}), frozenset({1})}
    # a POINT map inside a polygon map: both cover it
    res = core.max_intersection([a, core.visibility_map([[0, 0, 1.0], [1.0, 0, 0], [-1.0, 0, 0],
                                                         [0, 1.0, 0], [0, -1.0, 0]])])
    assert res.count == 2 and res.kinds[0] == "point"
    assert np.allclose(res.direction, [0, 0, 1.0], atol=1e-9)


def test_max_intersection_maps_sharing_normals():
    """Maps built from subsets of one pool of normals: many boundaries lie on the same
    great circles and many vertices coincide exactly."""
    rng = np.random.default_rng(61)
    pool = random_cap_normals(rng, 14, radius=math.radians(75), centre=[0.2, -0.1, 1.0])
    maps = []
    for _ in range(40):
        sub = pool[rng.choice(len(pool), size=int(rng.integers(1, 6)), replace=False)]
        maps.append(core.visibility_map(sub))
    assert all(m.kind == "polygon" for m in maps)
    res = core.max_intersection(maps)
    check_max_result(maps, res)
    # every map contains VM(pool), which has interior: all 40 maps overlap
    assert core.visibility_map(pool).kind == "polygon"
    assert res.count == 40
    # the region is VM(pool) as a set (its vertex list may hold extra points on the edges,
    # where other maps' collinear edges end)
    assert polygons_close(np.asarray(res.regions[0]), core.visibility_map(pool).vertices, 1e-9)


def test_max_intersection_hemispheres_and_lunes():
    rng = np.random.default_rng(62)
    maps = [core.visibility_map(random_cap_normals(rng, int(rng.integers(1, 3)),
                                                   radius=math.radians(60),
                                                   centre=[0, 0, 1.0]))
            for _ in range(30)]
    maps += [core.visibility_map(random_cap_normals(rng, 1, radius=1.0, centre=[1.0, 0, 0]))
             for _ in range(10)]
    res = core.max_intersection(maps)
    check_max_result(maps, res)


def test_max_intersection_lune_and_two_hemispheres():
    """Smallest failing case found by shrinking a random instance: a lune and two
    hemispheres whose triple overlap is a thin sliver (about 0.004 rad wide)."""
    A = [[0.8162086830222494, 0.1827130934047817, 0.5481052009035684],
         [-0.5042742110762157, 0.6882984988538673, 0.5214908403020834],
         [-0.8162086830222494, -0.1827130934047817, -0.5481052009035684],
         [-0.2088789055840977, -0.7911878208588164, 0.5747968640543083]]
    B = [[0.4423040635139557, -0.0, 0.896865160098798],
         [-0.43877577391203365, -0.8313370532946871, -0.34110778948479364],
         [-0.0035282896019221965, 0.8313370532946868, -0.5557573706140045]]
    C = [[0.0, -0.2954890334521524, -0.955346131571962],
         [-0.6862540715705638, 0.6524126997736189, 0.32157894587009406],
         [0.6862540715705635, -0.3569236663214662, 0.6337671857018681]]
    maps = [np.array(A), np.array(B), np.array(C)]
    witness = unit([0.4302042109267622, -0.05856319664159273, 0.90083])
    covers = [Cover(m) for m in maps]
    assert all(np.arcsin(c.n @ witness).min() > 4e-3 for c in covers)
    for order in ([0, 1, 2], [1, 2, 0], [2, 0, 1]):
        res = core.max_intersection([maps[i] for i in order])
        assert res.count == 3, f"order {order}: count {res.count}, covers {res.covers}"
        check_max_result([maps[i] for i in order], res)


def test_max_intersection_opposite_hemispheres_meet_in_a_circle():
    """HS(p) and HS(-p) share only the great circle GC(p): an EDGE, never a polygon."""
    for p in ([0, 0, 1.0], [0.3, 0.2, 0.9], [1.0, 2.0, 3.0]):
        a, b = core.visibility_map([p]), core.visibility_map([p], negative=True)
        for maps in ([a, b], [a.vertices, b.vertices], [b, a, a]):
            res = core.max_intersection(maps)
            assert res.count == len(maps)
            assert res.kinds == ["edge"], f"p = {p}: kinds {res.kinds}, margin {res.margin}"
            assert res.margin == 0
            assert abs(res.direction @ unit(p)) < 1e-10, "the direction lies on GC(p)"
            V = np.asarray(res.regions[0])
            assert np.all(np.abs(V @ unit(p)) < 1e-10)


def test_max_intersection_lune_and_its_antipode_meet_in_two_points():
    """L = {d.x >= 0, d.y >= 0} and -L share only their corners +-z."""
    for P in ([[1.0, 0, 0], [0, 1.0, 0]], [[1.0, 0, 0.2], [0.3, 1.0, -0.4]]):
        a, b = core.visibility_map(P), core.visibility_map(P, negative=True)
        res = core.max_intersection([a, b])
        corner = unit(np.cross(P[0], P[1]))
        assert res.count == 2
        assert all(k == "point" for k in res.kinds), f"kinds {res.kinds}"
        pts = np.vstack(res.regions)
        assert np.all(np.minimum(np.linalg.norm(pts - corner, axis=1),
                                 np.linalg.norm(pts + corner, axis=1)) < 1e-10)
        for c in res.centres:
            assert Cover(a).contains(c, 1e-10)[0] and Cover(b).contains(c, 1e-10)[0]


@pytest.mark.parametrize("P,Q,midpoint", [
    ([[0, 0, 1.0]], [[0, 0, -1.0], [1.0, 0, 0]], [1.0, 0, 0]),               # HS & lune
    ([[0, 0, 1.0], [1.0, 0, 0]], [[0, 0, -1.0], [1.0, 0, 0]], [1.0, 0, 0]),  # lune & lune
    ([[0, 0, 1.0], [1.0, 0, 0]], [[0, 0, -1.0]], [1.0, 0, 0]),               # lune & HS
    ([[0.2, 0.3, 0.9]], [[-0.2, -0.3, -0.9], [0.5, -0.7, 0.1]], None),       # tilted
])
def test_max_intersection_hemispheres_and_lunes_touching_along_a_half_circle(P, Q, midpoint):
    """Maps with opposite boundary circles (a planar face's map and the negative map of a
    face with the opposite normal, as in the mould application) meet in a half circle."""
    a, b = core.visibility_map(P), core.visibility_map(Q)
    res = core.max_intersection([a, b])
    assert res.count == 2 and res.kinds == ["edge"] and res.margin == 0
    g = unit(P[0])
    V = np.asarray(res.regions[0])
    assert np.all(np.abs(V @ g) < 1e-10), "the edge lies on the shared circle"
    for m in (a, b):
        assert Cover(m).contains(res.direction, 1e-10)[0], (
            f"direction {res.direction} is not in both maps")
        assert Cover(m).contains(V, 1e-10).all()
    if midpoint is not None:
        assert np.allclose(res.direction, midpoint, atol=1e-9)


def test_max_intersection_long_touching_arc_is_on_the_shared_circle():
    """Two lunes touching along a 174-degree arc of a shared great circle: the EDGE
    region's direction must stay within the sphere tolerance (1e-10) of both."""
    a = np.array([[0.6546561132536016, 0.19037296120781572, -0.7315623753451614],
                  [0.7418134506202125, 0.024343213464062628, 0.670164317490253],
                  [-0.6546561132536016, -0.19037296120781572, 0.7315623753451614],
                  [-0.5196420159184001, -0.5895136749125072, -0.6184220261143777]])
    b = np.array([[0.7307563490321276, 0.19188749119773674, -0.6551139970043945],
                  [0.19756818286221775, 0.8591572681012902, 0.47203347528459155],
                  [-0.7307563490321276, -0.19188749119773674, 0.6551139970043945],
                  [0.6669759969373819, 0.0036942012164895145, 0.7450700452888692]])
    res = core.max_intersection([a, b])
    assert res.count == 2 and res.kinds == ["edge"]
    for m in (a, b):
        dist = np.arcsin(np.clip(Cover(m).n @ res.direction, -1, 1)).min()
        assert dist >= -2e-10, f"direction {dist:.3g} rad outside a map of its cover"


def test_max_intersection_with_edge_and_point_maps():
    cap = core.visibility_map(circle_points([0, 0, 1.0], 0.6, np.linspace(0, 6, 5)))
    arc = core.visibility_map([[0, 1.0, 0], [0, -1.0, 0], [0.1, 0, 1.0]])  # half circle
    assert arc.kind == "edge"
    pt = core.visibility_map([[0, 0, 1.0], [1.0, 0, 0], [-1.0, 0, 0], [0, 1.0, 0],
                              [0, -1.0, 0]])
    assert pt.kind == "point"
    res = core.max_intersection([cap, arc, pt])
    assert res.count == 3 and res.kinds[0] == "point"
    assert np.allclose(res.direction, [0, 0, 1.0], atol=1e-9)
    res = core.max_intersection([cap, arc])
    assert res.count == 2 and res.kinds[0] == "edge"
    V = np.asarray(res.regions[0])
    assert np.all(np.abs(V[:, 1]) < 1e-9) and Cover(cap).contains(V, 1e-9).all()
    assert Cover(arc).contains(V, 1e-9).all()


def test_max_intersection_zero_weights():
    rng = np.random.default_rng(63)
    maps = [random_vm(rng, centre=[0, 0, 1.0], radius=1.0) for _ in range(6)]
    w = np.array([1.0, 0.0, 2.0, 0.0, 1.0, 3.0])
    res = core.max_intersection(maps, weights=w)
    covers = [Cover(m) for m in maps]
    best = coverage(covers, w, np.vstack((FIB_100K, res.centres)), 1e-12).max()
    assert best <= res.count + 1e-9
    assert abs(res.count - 7.0) < 1e-12   # all the weighted maps contain +z's neighbourhood


def test_level_regions_and_min_intersection_against_sampling():
    rng = np.random.default_rng(51)
    maps = [random_vm(rng, centre=unit([0, 0, 1.0] + 0.8 * rng.normal(size=3)))
            for _ in range(25)]
    covers = [Cover(m) for m in maps]
    res = core.max_intersection(maps)
    top = res.count
    # level = max is the maximum intersection
    lev = core.level_regions(maps, top)
    assert lev.count == top
    assert result_signature(lev) == result_signature(res)
    # a lower level: every region is a local maximum of weight >= level, and every
    # sampled cover set of weight >= level is inside one of them
    level = max(1, top - 2)
    lev = core.level_regions(maps, level)
    regions = result_signature(lev)
    assert all(len(s) >= level for s in regions)
    assert regions >= result_signature(res)
    for r, cov in enumerate(lev.covers):
        if lev.kinds[r] == "polygon" and lev.margins[r] > 1e-9:
            assert cover_set(covers, np.asarray(lev.centres[r]), 1e-12) == frozenset(
                int(i) for i in cov)
    dirs = FIB_100K[::4]
    member = np.column_stack([c.contains(dirs, 1e-12) for c in covers])
    counts = member.sum(axis=1)
    for row in member[counts >= level]:
        s = frozenset(np.nonzero(row)[0].tolist())
        assert any(s <= t for t in regions), f"sampled cover set {sorted(s)} not in a region"
    # minimum intersection: nothing sampled is covered less; its points have that weight
    mn = core.min_intersection(maps)
    assert mn.count <= counts.min()
    # its regions are faces of the arrangement: their own kind, no vertices (issue 6)
    assert mn.kinds and all(k == "face" for k in mn.kinds)
    assert all(len(v) == 0 for v in mn.regions) and all(m == 0 for m in mn.margins)
    for r, cov in enumerate(mn.covers):
        c = np.asarray(mn.centres[r])
        assert len(cov) == mn.count
        loose = coverage(covers, None, c[None], 1e-9)[0]
        strict = coverage(covers, None, c[None], -1e-9)[0]
        assert strict <= mn.count <= loose
    # maps clustered about +z leave the far side uncovered
    assert mn.count == 0 and counts.min() == 0


# --------------------------------------------------------------------------- #
# Issue 6: malformed maps, unit vertices, weight scale (binding level)          #
# --------------------------------------------------------------------------- #

OCTANT = np.eye(3)


@pytest.mark.parametrize("bad, what", [
    (core.VisibilityMap("point", np.array([[1.0, 0, 0], [0, 1.0, 0]])), "antipodal"),
    (core.VisibilityMap("edge", np.array([[1.0, 0, 0], [-1.0, 0, 0]])), "antipodal"),
    (core.VisibilityMap("edge", np.array([[1.0, 0, 0], [0.6, 0.8, 0], [0, 0.6, 0.8]])),
     "off the great circle"),
    (core.VisibilityMap("polygon", np.array([[1.0, 0, 0], [0, 0, 1.0], [0, 1.0, 0]])),
     "counter-clockwise"),
    (core.VisibilityMap("polygon", 2 * np.eye(3)), "not a unit vector"),
])
def test_malformed_maps_are_refused_by_name(bad, what):
    with pytest.raises(core.MfgError) as err:
        core.max_intersection([OCTANT, bad])
    assert "map 1" in str(err.value) and what in str(err.value)


def test_bare_vertex_arrays_may_have_any_length():
    ref = core.max_intersection([OCTANT, OCTANT @ np.diag([1.0, 1.0, -1.0])[[1, 0, 2]]])
    scaled = core.max_intersection([3 * OCTANT, 0.5 * OCTANT @ np.diag([1.0, 1.0, -1.0])[[1, 0, 2]]])
    assert ref.count == scaled.count == 2 and ref.kinds == scaled.kinds == ["edge"]
    assert np.allclose(ref.regions[0], scaled.regions[0], atol=1e-15)


@pytest.mark.parametrize("scale", [1e-300, 1e-12, 1e-9, 1.0, 1e12, 1e200])
def test_results_do_not_depend_on_the_weight_scale(scale):
    rng = np.random.default_rng(7)
    maps = [random_vm(rng, centre=unit([0, 0, 1.0] + 0.8 * rng.normal(size=3)))
            for _ in range(15)]
    w = rng.uniform(0.5, 2.0, size=len(maps))
    ref = core.max_intersection(maps, weights=w)
    res = core.max_intersection(maps, weights=w * scale)
    assert math.isclose(res.count, ref.count * scale, rel_tol=1e-12)
    assert [sorted(c) for c in res.covers] == [sorted(c) for c in ref.covers]
    lev = core.level_regions(maps, 0.8 * ref.count * scale, weights=w * scale)
    assert all(w[list(c)].sum() * scale >= 0.8 * ref.count * scale * (1 - 1e-12) for c in lev.covers)


def _mixed_maps(rng):
    """Polygons (some of 40..200 vertices, so the library's fans are used), one- and
    two-direction POINT maps and EDGE arcs, about +z."""
    maps = []
    for _ in range(rng.integers(5, 25)):
        r = rng.random()
        if r < 0.55:
            maps.append(random_vm(rng, centre=unit([0, 0, 1.0] + 0.9 * rng.normal(size=3))))
        elif r < 0.65:
            c = unit([0, 0, 1.0] + 0.9 * rng.normal(size=3))
            e1, e2 = frame(c)
            k, rho = int(rng.integers(40, 200)), rng.uniform(0.3, 1.2)
            ang = np.sort(rng.uniform(0, 2 * np.pi, k))
            maps.append(core.visibility_map(np.cos(rho) * c + np.sin(rho) * (
                np.cos(ang)[:, None] * e1 + np.sin(ang)[:, None] * e2)))
        elif r < 0.8:
            p = unit(rng.normal(size=3))
            maps.append(core.VisibilityMap("point", np.array([p, -p]) if rng.random() < 0.5 else p[None]))
        else:
            a = unit(rng.normal(size=3))
            g = unit(np.cross(a, rng.normal(size=3)))
            L = rng.uniform(0.2, 2.5)
            t = np.cross(g, a)
            maps.append(core.VisibilityMap("edge", np.array(
                [a, math.cos(L / 2) * a + math.sin(L / 2) * t, math.cos(L) * a + math.sin(L) * t])))
    return [m for m in maps if m.kind != "null"]


@pytest.mark.parametrize("seed", range(60))
def test_max_intersection_mixed_kinds_any_weight_scale_against_sampling(seed):
    """No sampled direction is covered by more than the answer; every region's centre is
    covered by the answer's weight, which is its cover set's (issue 6: fans, POINT pairs,
    weights from 1e-12 to 1e12)."""
    rng = np.random.default_rng(1000 + seed)
    maps = _mixed_maps(rng)
    w = rng.uniform(0.2, 3.0, size=len(maps)) * 10.0 ** rng.integers(-12, 12)
    res = core.max_intersection(maps, weights=w)
    covers = [Cover(m) for m in maps]
    assert res.count >= coverage(covers, w, fibonacci_sphere(60000), -1e-9).max() * (1 - 1e-12)
    for r, cov in enumerate(res.covers):
        assert coverage(covers, w, np.asarray(res.centres[r])[None], 1e-8)[0] >= res.count * (1 - 1e-12)
        assert abs(w[list(cov)].sum() - res.count) <= 1e-12 * res.count
