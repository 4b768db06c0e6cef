/* SPDX-License-Identifier: LGPL-2.1-or-later */
/* mesh.c - closed triangle meshes: the check that a mesh bounds a solid (closed,
 * consistently oriented, 2-manifold, positive volume), shared by the rotational sweep and
 * the medial surface, and the weld of a triangle soup (STL) into an indexed mesh. */
#include <stdlib.h>
#include <string.h>

#include "mesh/mesh.h"
#include "common/mfg_internal.h"
#include "common/predicates.h"

/*
 * Edges are found by sorting, not hashing: every triangle side is filed under its smaller
 * vertex index (a counting sort over the vertices, O(n)), and each vertex's short list is
 * sorted by the larger index (O(d log d) for a vertex of degree d).  Equal pairs are then
 * adjacent, and the groups come out in (smaller, larger) order, so "the first" problem
 * reported does not depend on the order of the triangles.
 * Fans round a vertex are counted with a union-find over the triangle corners: the two
 * corners at an end of an edge used by exactly two sides are joined; the sets left at a
 * vertex are its fans.  The components are a union-find over the triangles.
 */

/* Volume sign bound, in units of 6 * volume: 2^-47 (64 units of rounding) times the sum
 * of the determinants' absolute products (their permanents).  Each determinant of the
 * translated corners is within 7u of its permanent (u = 2^-53; Shewchuk's bound for a
 * 3x3 determinant of differences) and the compensated sum adds 2u of the total, so the
 * margin is ample; rounding cannot turn a volume beyond it to the other sign. */
#define VOLUME_BOUND 0x1p-47

typedef struct side_ref {
    int64_t hi;   /* the larger vertex index of the side */
    int64_t side; /* 3t + k: triangle t, from corner k to corner (k+1) % 3 */
} side_ref;

/* What the analysis found, beyond the public report: the first of each problem, for the
 * messages of mfg_mesh_require_closed. */
typedef struct mesh_findings {
    mfg_mesh_report rep;
    int64_t repeated, first_repeated;          /* triangles with a repeated index */
    int64_t boundary_a, boundary_b;            /* first boundary edge */
    int64_t nonmanifold_a, nonmanifold_b, nonmanifold_uses;
    int64_t inconsistent_a, inconsistent_b, inconsistent_t1, inconsistent_t2;
    int64_t nm_vertex, nm_vertex_fans;
    double volume6, volume6_bound;             /* 6 * volume and its rounding bound */
} mesh_findings;

static int cmp_side(const void *pa, const void *pb)
{
    const side_ref *a = pa, *b = pb;
    if (a->hi != b->hi)
        return a->hi < b->hi ? -1 : 1;
    return (a->side > b->side) - (a->side < b->side);
}

static int repeats_index(const int64_t *t)
{
    return t[0] == t[1] || t[1] == t[2] || t[2] == t[0];
}

/* Zero area, exactly: the cross product (b - a) x (c - a) vanishes iff its three
 * components do, and each is the orientation of the triangle projected on a coordinate
 * plane, decided exactly. */
static int zero_area(const double *a, const double *b, const double *c)
{
    return mfg_orient2d(a[0], a[1], b[0], b[1], c[0], c[1]) == 0 &&
           mfg_orient2d(a[1], a[2], b[1], b[2], c[1], c[2]) == 0 &&
           mfg_orient2d(a[2], a[0], b[2], b[0], c[2], c[0]) == 0;
}

int mfg_triangle_zero_area(const double *a, const double *b, const double *c)
{
    return zero_area(a, b, c);
}

/* The corner of side `side`'s triangle at vertex v (an end of that side). */
static int64_t corner_at(const int64_t *tris, int64_t side, int64_t v)
{
    int64_t t = side / 3, k = side % 3;
    return tris[side] == v ? side : 3 * t + (k + 1) % 3;
}

/* Arguments as every entry point takes them: out may be checked by the caller. */
mfg_status mfg_mesh_validate(const double *xyz, int64_t nv, const int64_t *tris, int64_t nt)
{
    if (nv < 0 || nv > MFG_MAX_COUNT)
        return mfg_fail(MFG_ERR_INVALID, "nvertices must be between 0 and %lld (got %lld)",
                        (long long)MFG_MAX_COUNT, (long long)nv);
    if (nt < 0 || nt > MFG_MAX_COUNT)
        return mfg_fail(MFG_ERR_INVALID, "ntriangles must be between 0 and %lld (got %lld)",
                        (long long)MFG_MAX_COUNT, (long long)nt);
    if (nv > 0 && !xyz)
        return mfg_fail(MFG_ERR_NULL, "xyz (vertices) is NULL");
    if (nt > 0 && !tris)
        return mfg_fail(MFG_ERR_NULL, "triangles is NULL");
    for (int64_t i = 0; i < 3 * nv; i++)
        if (!mfg_coord_ok(xyz[i]))
            return mfg_fail(MFG_ERR_INVALID,
                            "vertex %lld has a NaN, infinite or out-of-range coordinate (%g; allowed: 0 or 2^-200 <= |x| <= 2^200)",
                            (long long)(i / 3), xyz[i]);
    for (int64_t i = 0; i < 3 * nt; i++)
        if (tris[i] < 0 || tris[i] >= nv)
            return mfg_fail(MFG_ERR_INVALID,
                            "triangle %lld uses vertex index %lld, outside 0 .. %lld",
                            (long long)(i / 3), (long long)tris[i], (long long)(nv - 1));
    return MFG_OK;
}

/* The whole analysis of a validated mesh.  neighbours (3 * nt, or NULL) receives the
 * triangle across each side used by exactly two sides running opposite ways (-1
 * elsewhere). */
static mfg_status analyse(const double *xyz, int64_t nv, const int64_t *tris, int64_t nt,
                          mesh_findings *f, int64_t *neighbours)
{
    memset(f, 0, sizeof *f);
    f->first_repeated = f->boundary_a = f->nonmanifold_a = f->inconsistent_a = -1;
    f->nm_vertex = -1;
    mfg_mesh_report *r = &f->rep;
    r->nvertices = nv;
    r->ntriangles = nt;

    /* Sizes: nt, nv <= 2^40, so 3 * nt * 16 bytes and (nv + 1) * 8 bytes cannot wrap. */
    int64_t *offsets = calloc((size_t)nv + 1, sizeof *offsets);
    side_ref *sides = malloc((size_t)(3 * nt + 1) * sizeof *sides);
    int64_t *corner_parent = malloc((size_t)(3 * nt + 1) * sizeof *corner_parent);
    int64_t *tri_parent = malloc((size_t)(nt + 1) * sizeof *tri_parent);
    unsigned char *used = calloc((size_t)nv + 1, 1);
    if (!offsets || !sides || !corner_parent || !tri_parent || !used) {
        free(offsets);
        free(sides);
        free(corner_parent);
        free(tri_parent);
        free(used);
        return mfg_fail(MFG_ERR_NOMEM, "out of memory checking a mesh of %lld triangles",
                        (long long)nt);
    }

    /* Pass 1: used vertices, bounding box, repeated indices, zero areas. */
    double lo[3] = {0, 0, 0}, hi[3] = {0, 0, 0};
    int have_box = 0;
    for (int64_t t = 0; t < nt; t++) {
        const int64_t *tv = tris + 3 * t;
        for (int k = 0; k < 3; k++) {
            const double *p = xyz + 3 * tv[k];
            used[tv[k]] = 1;
            for (int c = 0; c < 3; c++) {
                if (!have_box || p[c] < lo[c])
                    lo[c] = p[c];
                if (!have_box || p[c] > hi[c])
                    hi[c] = p[c];
            }
            have_box = 1;
        }
        if (repeats_index(tv)) {
            if (f->repeated++ == 0)
                f->first_repeated = t;
            r->degenerate_triangles++;
        } else if (zero_area(xyz + 3 * tv[0], xyz + 3 * tv[1], xyz + 3 * tv[2])) {
            r->degenerate_triangles++;
        }
    }
    for (int64_t v = 0; v < nv; v++)
        r->unused_vertices += !used[v];
    for (int c = 0; c < 3; c++) {
        r->bbox[c] = lo[c];
        r->bbox[3 + c] = hi[c];
    }

    /* Pass 2: volume and area.  The apex of the tetrahedra is the box centre, which keeps
     * the products small (the sum is the same for any apex when the mesh is closed). */
    double o[3];
    for (int c = 0; c < 3; c++)
        o[c] = lo[c] * 0.5 + hi[c] * 0.5;
    double sum = 0.0, comp = 0.0, perm = 0.0, area2 = 0.0;
    for (int64_t t = 0; t < nt; t++) {
        const int64_t *tv = tris + 3 * t;
        if (repeats_index(tv))
            continue;
        const double *pa = xyz + 3 * tv[0], *pb = xyz + 3 * tv[1], *pc = xyz + 3 * tv[2];
        double a[3], b[3], c[3];
        for (int i = 0; i < 3; i++) {
            a[i] = pa[i] - o[i];
            b[i] = pb[i] - o[i];
            c[i] = pc[i] - o[i];
        }
        double det = a[0] * (b[1] * c[2] - b[2] * c[1]) + a[1] * (b[2] * c[0] - b[0] * c[2]) +
                     a[2] * (b[0] * c[1] - b[1] * c[0]);
        perm += fabs(a[0]) * (fabs(b[1] * c[2]) + fabs(b[2] * c[1])) +
                fabs(a[1]) * (fabs(b[2] * c[0]) + fabs(b[0] * c[2])) +
                fabs(a[2]) * (fabs(b[0] * c[1]) + fabs(b[1] * c[0]));
        /* Neumaier's compensated sum: a closed mesh's terms cancel heavily. */
        double s = sum + det;
        comp += fabs(sum) >= fabs(det) ? (sum - s) + det : (det - s) + sum;
        sum = s;
        double u[3] = {pb[0] - pa[0], pb[1] - pa[1], pb[2] - pa[2]};
        double w[3] = {pc[0] - pa[0], pc[1] - pa[1], pc[2] - pa[2]};
        double n0 = u[1] * w[2] - u[2] * w[1], n1 = u[2] * w[0] - u[0] * w[2],
               n2 = u[0] * w[1] - u[1] * w[0];
        area2 += sqrt(n0 * n0 + n1 * n1 + n2 * n2);
    }
    f->volume6 = sum + comp;
    f->volume6_bound = VOLUME_BOUND * perm;
    r->volume = f->volume6 / 6.0;
    r->area = area2 * 0.5;

    /* Pass 3: file every side under its smaller vertex (counting sort), then sort each
     * vertex's list by the larger vertex. */
    for (int64_t t = 0; t < nt; t++) {
        const int64_t *tv = tris + 3 * t;
        if (repeats_index(tv))
            continue;
        for (int k = 0; k < 3; k++) {
            int64_t a = tv[k], b = tv[(k + 1) % 3];
            offsets[(a < b ? a : b) + 1]++;
        }
    }
    for (int64_t v = 0; v < nv; v++)
        offsets[v + 1] += offsets[v];
    for (int64_t t = 0; t < nt; t++) {
        const int64_t *tv = tris + 3 * t;
        tri_parent[t] = t;
        for (int k = 0; k < 3; k++)
            corner_parent[3 * t + k] = 3 * t + k;
        if (repeats_index(tv))
            continue;
        for (int k = 0; k < 3; k++) {
            int64_t a = tv[k], b = tv[(k + 1) % 3];
            int64_t l = a < b ? a : b;
            /* offsets[l] walks from the start of l's list to its end (restored below). */
            side_ref *s = &sides[offsets[l]++];
            s->hi = a < b ? b : a;
            s->side = 3 * t + k;
        }
    }
    for (int64_t v = nv; v > 0; v--) /* offsets[v] now ends v's list: shift back */
        offsets[v] = offsets[v - 1];
    offsets[0] = 0;
    if (neighbours)
        for (int64_t i = 0; i < 3 * nt; i++)
            neighbours[i] = -1;

    /* Pass 4: classify the edges, group by group. */
    for (int64_t l = 0; l < nv; l++) {
        side_ref *list = sides + offsets[l];
        int64_t len = offsets[l + 1] - offsets[l];
        if (len > 1)
            qsort(list, (size_t)len, sizeof *list, cmp_side);
        for (int64_t i = 0; i < len;) {
            int64_t j = i + 1;
            while (j < len && list[j].hi == list[i].hi)
                j++;
            int64_t uses = j - i, h = list[i].hi;
            int64_t s1 = list[i].side, s2 = uses > 1 ? list[i + 1].side : -1;
            if (uses == 1) {
                if (r->boundary_edges++ == 0) {
                    f->boundary_a = l;
                    f->boundary_b = h;
                }
            } else if (uses == 2) {
                /* Opposite ways iff exactly one of the two sides starts at l. */
                int same_way = (tris[s1] == l) == (tris[s2] == l);
                if (same_way) {
                    if (r->inconsistent_edges++ == 0) {
                        f->inconsistent_a = tris[s1];
                        f->inconsistent_b = tris[s1] == l ? h : l;
                        f->inconsistent_t1 = s1 / 3;
                        f->inconsistent_t2 = s2 / 3;
                    }
                } else if (neighbours) {
                    neighbours[s1] = s2 / 3;
                    neighbours[s2] = s1 / 3;
                }
                mfg_uf_union(corner_parent, corner_at(tris, s1, l), corner_at(tris, s2, l));
                mfg_uf_union(corner_parent, corner_at(tris, s1, h), corner_at(tris, s2, h));
            } else if (r->nonmanifold_edges++ == 0) {
                f->nonmanifold_a = l;
                f->nonmanifold_b = h;
                f->nonmanifold_uses = uses;
            }
            for (int64_t k = i + 1; k < j; k++)
                mfg_uf_union(tri_parent, list[i].side / 3, list[k].side / 3);
            i = j;
        }
    }

    /* Pass 5: fans per vertex (offsets is reused as the count), components. */
    memset(offsets, 0, ((size_t)nv + 1) * sizeof *offsets);
    for (int64_t t = 0; t < nt; t++) {
        if (repeats_index(tris + 3 * t))
            continue;
        r->components += mfg_uf_find(tri_parent, t) == t;
        for (int k = 0; k < 3; k++)
            if (mfg_uf_find(corner_parent, 3 * t + k) == 3 * t + k)
                offsets[tris[3 * t + k]]++;
    }
    for (int64_t v = 0; v < nv; v++)
        if (offsets[v] > 1 && r->nonmanifold_vertices++ == 0) {
            f->nm_vertex = v;
            f->nm_vertex_fans = offsets[v];
        }

    free(offsets);
    free(sides);
    free(corner_parent);
    free(tri_parent);
    free(used);
    return MFG_OK;
}

mfg_status mfg_mesh_check(const double *xyz, int64_t nvertices, const int64_t *triangles,
                          int64_t ntriangles, mfg_mesh_report *out)
{
    if (!out)
        return mfg_fail(MFG_ERR_NULL, "out (the report) is NULL");
    mfg_status st = mfg_mesh_validate(xyz, nvertices, triangles, ntriangles);
    if (st != MFG_OK)
        return st;
    mesh_findings f;
    st = analyse(xyz, nvertices, triangles, ntriangles, &f, NULL);
    if (st != MFG_OK)
        return st;
    *out = f.rep;
    mfg_clear_error();
    return MFG_OK;
}

/* The first problem that keeps the analysed mesh from bounding a solid, as a status and
 * detail; MFG_OK when there is none. */
static mfg_status first_problem(const mesh_findings *f)
{
    const mfg_mesh_report *r = &f->rep;
    if (r->ntriangles == 0)
        return mfg_fail(MFG_ERR_DEGENERATE, "mesh has no triangles");
    if (f->repeated)
        return mfg_fail(MFG_ERR_INVALID,
                        "triangle %lld repeats a vertex index (%lld triangles with a repeated vertex index)",
                        (long long)f->first_repeated, (long long)f->repeated);
    if (r->degenerate_triangles == r->ntriangles)
        return mfg_fail(MFG_ERR_DEGENERATE, "all %lld triangles have zero area",
                        (long long)r->ntriangles);
    if (r->boundary_edges)
        return mfg_fail(MFG_ERR_INVALID,
                        "mesh is not closed: %lld boundary edges (first: vertices %lld-%lld)",
                        (long long)r->boundary_edges, (long long)f->boundary_a,
                        (long long)f->boundary_b);
    if (r->nonmanifold_edges)
        return mfg_fail(MFG_ERR_INVALID,
                        "non-manifold edge %lld-%lld shared by %lld triangles (%lld non-manifold edges)",
                        (long long)f->nonmanifold_a, (long long)f->nonmanifold_b,
                        (long long)f->nonmanifold_uses, (long long)r->nonmanifold_edges);
    if (r->inconsistent_edges)
        return mfg_fail(MFG_ERR_INVALID,
                        "inconsistent orientation across %lld edges (first: triangles %lld and %lld both run from vertex %lld to %lld)",
                        (long long)r->inconsistent_edges, (long long)f->inconsistent_t1,
                        (long long)f->inconsistent_t2, (long long)f->inconsistent_a,
                        (long long)f->inconsistent_b);
    if (r->nonmanifold_vertices)
        return mfg_fail(MFG_ERR_INVALID,
                        "non-manifold vertex %lld: its triangles form %lld separate fans (%lld non-manifold vertices)",
                        (long long)f->nm_vertex, (long long)f->nm_vertex_fans,
                        (long long)r->nonmanifold_vertices);
    if (f->volume6 < -f->volume6_bound)
        return mfg_fail(MFG_ERR_INVALID,
                        "negative volume %g: the triangles face inward (reverse their vertex order)",
                        r->volume);
    if (!(f->volume6 > f->volume6_bound))
        return mfg_fail(MFG_ERR_DEGENERATE,
                        "zero volume (%g, within rounding of 0): the mesh encloses no solid",
                        r->volume);
    return MFG_OK;
}

mfg_status mfg_mesh_require_closed(const double *xyz, int64_t nvertices,
                                   const int64_t *triangles, int64_t ntriangles,
                                   mfg_mesh_report *report, int64_t **out_neighbours)
{
    mfg_status st = mfg_mesh_validate(xyz, nvertices, triangles, ntriangles);
    if (st != MFG_OK)
        return st;
    int64_t *nb = NULL;
    if (out_neighbours) {
        nb = malloc((size_t)(3 * ntriangles + 1) * sizeof *nb);
        if (!nb)
            return mfg_fail(MFG_ERR_NOMEM, "out of memory for the neighbours of %lld triangles",
                            (long long)ntriangles);
    }
    mesh_findings f;
    st = analyse(xyz, nvertices, triangles, ntriangles, &f, nb);
    if (st == MFG_OK)
        st = first_problem(&f);
    if (st == MFG_OK)
        st = mfg_mesh_shells_problem(xyz, nvertices, triangles, ntriangles);
    if (st != MFG_OK) {
        free(nb);
        return st;
    }
    if (report)
        *report = f.rep;
    if (out_neighbours)
        *out_neighbours = nb;
    mfg_clear_error();
    return MFG_OK;
}

mfg_status mfg_mesh_check_closed(const double *xyz, int64_t nvertices,
                                 const int64_t *triangles, int64_t ntriangles,
                                 mfg_mesh_report *out)
{
    if (!out)
        return mfg_fail(MFG_ERR_NULL, "out (the report) is NULL");
    return mfg_mesh_require_closed(xyz, nvertices, triangles, ntriangles, out, NULL);
}

/* ---- Welding a triangle soup ---------------------------------------------------------- */

typedef struct soup_corner {
    double x, y, z; /* -0 made +0, so that equal doubles compare equal bit for bit */
    int64_t index;  /* corner index in the soup: 3t + k */
} soup_corner;

static int cmp_corner(const void *pa, const void *pb)
{
    const soup_corner *a = pa, *b = pb;
    if (a->x != b->x)
        return a->x < b->x ? -1 : 1;
    if (a->y != b->y)
        return a->y < b->y ? -1 : 1;
    if (a->z != b->z)
        return a->z < b->z ? -1 : 1;
    return (a->index > b->index) - (a->index < b->index);
}

mfg_status mfg_mesh_weld(const double *xyz_soup, int64_t ntriangles, mfg_mesh **out_mesh)
{
    if (!out_mesh)
        return mfg_fail(MFG_ERR_NULL, "out_mesh is NULL");
    if (ntriangles < 0 || ntriangles > MFG_MAX_COUNT)
        return mfg_fail(MFG_ERR_INVALID, "ntriangles must be between 0 and %lld (got %lld)",
                        (long long)MFG_MAX_COUNT, (long long)ntriangles);
    if (ntriangles > 0 && !xyz_soup)
        return mfg_fail(MFG_ERR_NULL, "xyz_soup is NULL");
    int64_t n = 3 * ntriangles;
    for (int64_t i = 0; i < 3 * n; i++)
        if (!mfg_coord_ok(xyz_soup[i]))
            return mfg_fail(MFG_ERR_INVALID,
                            "triangle %lld has a NaN, infinite or out-of-range coordinate (%g; allowed: 0 or 2^-200 <= |x| <= 2^200)",
                            (long long)(i / 9), xyz_soup[i]);

    soup_corner *corners = malloc((size_t)(n + 1) * sizeof *corners);
    int64_t *rep = malloc((size_t)(n + 1) * sizeof *rep);
    mfg_mesh *mesh = malloc(sizeof *mesh);
    int64_t *tris = malloc((size_t)(n + 1) * sizeof *tris);
    double *verts = NULL;
    if (!corners || !rep || !mesh || !tris)
        goto nomem;
    for (int64_t i = 0; i < n; i++) {
        const double *p = xyz_soup + 3 * i;
        corners[i].x = p[0] + 0.0; /* -0 + 0 = +0 in round-to-nearest */
        corners[i].y = p[1] + 0.0;
        corners[i].z = p[2] + 0.0;
        corners[i].index = i;
    }
    qsort(corners, (size_t)n, sizeof *corners, cmp_corner);
    /* rep[i]: the first corner with i's coordinates (groups are sorted by index). */
    for (int64_t i = 0; i < n;) {
        int64_t j = i + 1;
        while (j < n && corners[j].x == corners[i].x && corners[j].y == corners[i].y &&
               corners[j].z == corners[i].z)
            j++;
        for (int64_t k = i; k < j; k++)
            rep[corners[k].index] = corners[i].index;
        i = j;
    }
    free(corners);
    corners = NULL;
    /* Vertices numbered by first appearance; tris[] first holds each first corner's new
     * number, then every corner takes its first corner's. */
    int64_t nv = 0;
    for (int64_t i = 0; i < n; i++)
        if (rep[i] == i)
            tris[i] = nv++;
    verts = malloc((size_t)(3 * nv + 1) * sizeof *verts);
    if (!verts)
        goto nomem;
    for (int64_t i = 0; i < n; i++)
        if (rep[i] == i)
            memcpy(verts + 3 * tris[i], xyz_soup + 3 * i, 3 * sizeof *verts);
        else
            tris[i] = tris[rep[i]]; /* rep[i] < i: already numbered */
    free(rep);
    mesh->nvertices = nv;
    mesh->ntriangles = ntriangles;
    mesh->vertices = verts;
    mesh->triangles = tris;
    *out_mesh = mesh;
    mfg_clear_error();
    return MFG_OK;

nomem:
    free(corners);
    free(rep);
    free(mesh);
    free(tris);
    free(verts);
    return mfg_fail(MFG_ERR_NOMEM, "out of memory welding %lld triangles", (long long)ntriangles);
}

void mfg_mesh_free(mfg_mesh *mesh)
{
    if (!mesh)
        return;
    free(mesh->vertices);
    free(mesh->triangles);
    free(mesh);
}
