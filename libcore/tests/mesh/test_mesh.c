/* SPDX-License-Identifier: LGPL-2.1-or-later */
/* test_mesh.c - the closed-solid check and the soup weld (mesh.c) on meshes whose counts,
 * volume and area are known by construction or analytically. */
#define _POSIX_C_SOURCE 200809L /* clock_gettime */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "mesh/mesh.h"
#include "mfg_test.h"
#include "mfgeom.h"

/* A growable indexed mesh. */
typedef struct tmesh {
    double *xyz;
    int64_t *tri;
    int64_t nv, nt, capv, capt;
} tmesh;

static int64_t add_vertex(tmesh *m, double x, double y, double z)
{
    if (m->nv == m->capv) {
        m->capv = m->capv ? 2 * m->capv : 64;
        m->xyz = realloc(m->xyz, (size_t)m->capv * 3 * sizeof *m->xyz);
    }
    m->xyz[3 * m->nv] = x;
    m->xyz[3 * m->nv + 1] = y;
    m->xyz[3 * m->nv + 2] = z;
    return m->nv++;
}

static void add_tri(tmesh *m, int64_t a, int64_t b, int64_t c)
{
    if (m->nt == m->capt) {
        m->capt = m->capt ? 2 * m->capt : 64;
        m->tri = realloc(m->tri, (size_t)m->capt * 3 * sizeof *m->tri);
    }
    m->tri[3 * m->nt] = a;
    m->tri[3 * m->nt + 1] = b;
    m->tri[3 * m->nt + 2] = c;
    m->nt++;
}

static void tmesh_free(tmesh *m)
{
    free(m->xyz);
    free(m->tri);
    memset(m, 0, sizeof *m);
}

/* Box [x0,x1] x [y0,y1] x [z0,z1] with its own 8 vertices (index x + 2y + 4z), 12
 * triangles counter-clockwise seen from outside. */
static void add_box(tmesh *m, double x0, double y0, double z0, double x1, double y1, double z1)
{
    int64_t v = m->nv;
    for (int k = 0; k < 8; k++)
        add_vertex(m, k & 1 ? x1 : x0, k & 2 ? y1 : y0, k & 4 ? z1 : z0);
    static const int f[12][3] = {{0, 2, 3}, {0, 3, 1}, {4, 5, 7}, {4, 7, 6},
                                 {0, 1, 5}, {0, 5, 4}, {2, 6, 7}, {2, 7, 3},
                                 {0, 4, 6}, {0, 6, 2}, {1, 3, 7}, {1, 7, 5}};
    for (int t = 0; t < 12; t++)
        add_tri(m, v + f[t][0], v + f[t][1], v + f[t][2]);
}

/* The mesh as a soup (9 doubles per triangle), then welded back: shares the vertices of
 * boxes that touch. */
static tmesh welded(const tmesh *m)
{
    double *soup = malloc((size_t)(9 * m->nt + 1) * sizeof *soup);
    for (int64_t i = 0; i < 3 * m->nt; i++)
        memcpy(soup + 3 * i, m->xyz + 3 * m->tri[i], 3 * sizeof *soup);
    mfg_mesh *w = NULL;
    tmesh out = {0};
    CHECK_EQ_INT(mfg_mesh_weld(soup, m->nt, &w), MFG_OK);
    if (w) {
        for (int64_t k = 0; k < w->nvertices; k++)
            add_vertex(&out, w->vertices[3 * k], w->vertices[3 * k + 1], w->vertices[3 * k + 2]);
        for (int64_t t = 0; t < w->ntriangles; t++)
            add_tri(&out, w->triangles[3 * t], w->triangles[3 * t + 1], w->triangles[3 * t + 2]);
    }
    mfg_mesh_free(w);
    free(soup);
    return out;
}

static mfg_mesh_report check(const tmesh *m)
{
    mfg_mesh_report r;
    memset(&r, 0xab, sizeof r);
    CHECK_EQ_INT(mfg_mesh_check(m->xyz, m->nv, m->tri, m->nt, &r), MFG_OK);
    return r;
}

/* mfg_mesh_check_closed fails with status st and a detail containing `text`, leaving the
 * report untouched. */
static void expect_refused(const tmesh *m, mfg_status st, const char *text)
{
    mfg_mesh_report r, before;
    memset(&r, 0x5a, sizeof r);
    before = r;
    mfg_status got = mfg_mesh_check_closed(m->xyz, m->nv, m->tri, m->nt, &r);
    CHECK_EQ_INT(got, st);
    CHECK(strstr(mfg_last_error(), text) != NULL);
    if (!strstr(mfg_last_error(), text))
        fprintf(stderr, "  detail was: \"%s\", expected \"%s\"\n", mfg_last_error(), text);
    CHECK(memcmp(&r, &before, sizeof r) == 0);
    int64_t *nb = (int64_t *)&r; /* must stay untouched as well */
    CHECK_EQ_INT(mfg_mesh_require_closed(m->xyz, m->nv, m->tri, m->nt, NULL, &nb), st);
    CHECK(nb == (int64_t *)&r);
}

static int near(double a, double b, double tol) { return fabs(a - b) <= tol; }

static void test_cube(void)
{
    tmesh m = {0};
    add_box(&m, -1, 0, 2, 2, 5, 6); /* 3 x 5 x 4 */
    mfg_mesh_report r = check(&m);
    CHECK_EQ_INT(r.nvertices, 8);
    CHECK_EQ_INT(r.ntriangles, 12);
    CHECK_EQ_INT(r.boundary_edges, 0);
    CHECK_EQ_INT(r.nonmanifold_edges, 0);
    CHECK_EQ_INT(r.inconsistent_edges, 0);
    CHECK_EQ_INT(r.nonmanifold_vertices, 0);
    CHECK_EQ_INT(r.degenerate_triangles, 0);
    CHECK_EQ_INT(r.unused_vertices, 0);
    CHECK_EQ_INT(r.components, 1);
    CHECK(r.volume == 60.0);                   /* exact: small integers */
    CHECK(r.area == 2.0 * (15 + 12 + 20));
    double box[6] = {-1, 0, 2, 2, 5, 6};
    CHECK(memcmp(r.bbox, box, sizeof box) == 0);

    mfg_mesh_report c;
    CHECK_EQ_INT(mfg_mesh_check_closed(m.xyz, m.nv, m.tri, m.nt, &c), MFG_OK);
    CHECK(memcmp(&c, &r, sizeof r) == 0);
    CHECK(strcmp(mfg_last_error(), "") == 0);

    /* The neighbours: across each side, a triangle running along it the other way. */
    int64_t *nb = NULL;
    CHECK_EQ_INT(mfg_mesh_require_closed(m.xyz, m.nv, m.tri, m.nt, NULL, &nb), MFG_OK);
    for (int64_t t = 0; nb && t < m.nt; t++)
        for (int k = 0; k < 3; k++) {
            int64_t a = m.tri[3 * t + k], b = m.tri[3 * t + (k + 1) % 3], u = nb[3 * t + k];
            CHECK(u >= 0 && u < m.nt && u != t);
            int found = 0;
            for (int j = 0; u >= 0 && u < m.nt && j < 3; j++)
                found += m.tri[3 * u + j] == b && m.tri[3 * u + (j + 1) % 3] == a;
            CHECK_EQ_INT(found, 1);
        }
    free(nb);

    /* An unused vertex is harmless and counted. */
    add_vertex(&m, 100, 100, 100);
    r = check(&m);
    CHECK_EQ_INT(r.unused_vertices, 1);
    CHECK(r.bbox[3] == 2.0); /* the unused vertex is not in the box */
    CHECK_EQ_INT(mfg_mesh_check_closed(m.xyz, m.nv, m.tri, m.nt, &c), MFG_OK);
    tmesh_free(&m);
}

static void test_tetrahedron(void)
{
    tmesh m = {0};
    add_vertex(&m, 0, 0, 0);
    add_vertex(&m, 1, 0, 0);
    add_vertex(&m, 0, 1, 0);
    add_vertex(&m, 0, 0, 1);
    add_tri(&m, 0, 2, 1);
    add_tri(&m, 0, 1, 3);
    add_tri(&m, 0, 3, 2);
    add_tri(&m, 1, 2, 3);
    mfg_mesh_report r = check(&m);
    CHECK(near(r.volume, 1.0 / 6.0, 1e-15));
    CHECK(near(r.area, 1.5 + sqrt(3.0) / 2.0, 1e-15));
    CHECK_EQ_INT(r.components, 1);
    CHECK_EQ_INT(r.boundary_edges + r.nonmanifold_edges + r.inconsistent_edges +
                     r.nonmanifold_vertices + r.degenerate_triangles, 0);
    CHECK_EQ_INT(mfg_mesh_check_closed(m.xyz, m.nv, m.tri, m.nt, &r), MFG_OK);

    /* Triangle order and starting corner change nothing. */
    tmesh p = {0};
    for (int64_t k = 0; k < m.nv; k++)
        add_vertex(&p, m.xyz[3 * k], m.xyz[3 * k + 1], m.xyz[3 * k + 2]);
    for (int64_t t = m.nt - 1; t >= 0; t--)
        add_tri(&p, m.tri[3 * t + 1], m.tri[3 * t + 2], m.tri[3 * t]);
    mfg_mesh_report q = check(&p);
    CHECK(q.volume == r.volume || near(q.volume, r.volume, 1e-16));
    CHECK_EQ_INT(q.components, 1);
    tmesh_free(&p);

    /* Flipped: negative volume. */
    int64_t s = m.tri[0];
    for (int64_t t = 0; t < m.nt; t++) {
        s = m.tri[3 * t + 1];
        m.tri[3 * t + 1] = m.tri[3 * t + 2];
        m.tri[3 * t + 2] = s;
    }
    r = check(&m);
    CHECK(near(r.volume, -1.0 / 6.0, 1e-15));
    CHECK_EQ_INT(r.inconsistent_edges, 0);
    expect_refused(&m, MFG_ERR_INVALID, "negative volume");
    expect_refused(&m, MFG_ERR_INVALID, "face inward");
    tmesh_free(&m);
}

/* Torus (genus 1): n x k grid of quads on ((R + r cos v) cos u, (R + r cos v) sin u,
 * r sin v); (du, dv) is outward. */
static void test_torus(void)
{
    const int n = 64, k = 32;
    const double R = 3, rr = 1;
    tmesh m = {0};
    for (int i = 0; i < n; i++)
        for (int j = 0; j < k; j++) {
            double u = 2 * M_PI * i / n, v = 2 * M_PI * j / k;
            add_vertex(&m, (R + rr * cos(v)) * cos(u), (R + rr * cos(v)) * sin(u), rr * sin(v));
        }
    for (int i = 0; i < n; i++)
        for (int j = 0; j < k; j++) {
            int64_t a = i * k + j, b = ((i + 1) % n) * k + j, c = ((i + 1) % n) * k + (j + 1) % k,
                    d = i * k + (j + 1) % k;
            add_tri(&m, a, b, c);
            add_tri(&m, a, c, d);
        }
    mfg_mesh_report r = check(&m);
    CHECK_EQ_INT(r.components, 1);
    CHECK_EQ_INT(r.boundary_edges + r.nonmanifold_edges + r.inconsistent_edges +
                     r.nonmanifold_vertices + r.degenerate_triangles, 0);
    /* Inscribed polyhedron: a little below 2 pi^2 R r^2 (the chord error of the 64- and
     * 32-gons is 1 - cos(pi/32) ~ 0.5% of the section). */
    double exact = 2 * M_PI * M_PI * R * rr * rr;
    CHECK(r.volume < exact && r.volume > 0.98 * exact);
    CHECK(r.area < 4 * M_PI * M_PI * R * rr && r.area > 0.98 * 4 * M_PI * M_PI * R * rr);
    CHECK_EQ_INT(mfg_mesh_check_closed(m.xyz, m.nv, m.tri, m.nt, &r), MFG_OK);
    tmesh_free(&m);
}

static void test_two_cubes(void)
{
    tmesh m = {0};
    add_box(&m, 0, 0, 0, 1, 1, 1);
    add_box(&m, 5, 0, 0, 7, 1, 1);
    mfg_mesh_report r = check(&m);
    CHECK_EQ_INT(r.components, 2);
    CHECK(r.volume == 3.0);
    CHECK_EQ_INT(mfg_mesh_check_closed(m.xyz, m.nv, m.tri, m.nt, &r), MFG_OK);

    /* A cavity: the inner box turned inward; the total volume is positive. */
    tmesh h = {0};
    add_box(&h, 0, 0, 0, 4, 4, 4);
    add_box(&h, 1, 1, 1, 2, 2, 2);
    for (int64_t t = 12; t < 24; t++) {
        int64_t s = h.tri[3 * t + 1];
        h.tri[3 * t + 1] = h.tri[3 * t + 2];
        h.tri[3 * t + 2] = s;
    }
    r = check(&h);
    CHECK(r.volume == 63.0);
    CHECK_EQ_INT(r.components, 2);
    CHECK_EQ_INT(mfg_mesh_check_closed(h.xyz, h.nv, h.tri, h.nt, &r), MFG_OK);
    tmesh_free(&h);
    tmesh_free(&m);
}

static void test_open_and_flipped(void)
{
    tmesh m = {0};
    add_box(&m, 0, 0, 0, 1, 1, 1);
    m.nt--; /* remove the last triangle (1, 7, 5) */
    mfg_mesh_report r = check(&m);
    CHECK_EQ_INT(r.boundary_edges, 3);
    CHECK_EQ_INT(r.inconsistent_edges, 0);
    CHECK_EQ_INT(r.nonmanifold_vertices, 0); /* fans may be open at the hole */
    CHECK_EQ_INT(r.components, 1);
    /* First boundary edge in (smaller, larger) order: 1-5 of the sides 1-7, 7-5, 5-1. */
    expect_refused(&m, MFG_ERR_INVALID, "mesh is not closed: 3 boundary edges (first: vertices 1-5)");
    m.nt++;

    /* One triangle flipped: its 3 edges are used twice the same way. */
    int64_t s = m.tri[3 * 4 + 1];
    m.tri[3 * 4 + 1] = m.tri[3 * 4 + 2];
    m.tri[3 * 4 + 2] = s;
    r = check(&m);
    CHECK_EQ_INT(r.inconsistent_edges, 3);
    CHECK_EQ_INT(r.boundary_edges, 0);
    CHECK_EQ_INT(r.nonmanifold_vertices, 0);
    expect_refused(&m, MFG_ERR_INVALID, "inconsistent orientation across 3 edges");
    m.tri[3 * 4 + 2] = m.tri[3 * 4 + 1];
    m.tri[3 * 4 + 1] = s;

    /* Every triangle flipped: consistent, but inward. */
    for (int64_t t = 0; t < m.nt; t++) {
        s = m.tri[3 * t];
        m.tri[3 * t] = m.tri[3 * t + 1];
        m.tri[3 * t + 1] = s;
    }
    r = check(&m);
    CHECK(r.volume == -1.0);
    CHECK_EQ_INT(r.inconsistent_edges, 0);
    expect_refused(&m, MFG_ERR_INVALID, "negative volume -1: the triangles face inward");
    tmesh_free(&m);
}

static void test_nonmanifold(void)
{
    /* Two cubes sharing the edge x = y = 1, 0 <= z <= 1 (both cut their faces along it). */
    tmesh s = {0};
    add_box(&s, 0, 0, 0, 1, 1, 1);
    add_box(&s, 1, 1, 0, 2, 2, 1);
    tmesh m = welded(&s);
    CHECK_EQ_INT(m.nv, 14);
    mfg_mesh_report r = check(&m);
    CHECK_EQ_INT(r.nonmanifold_edges, 1);
    CHECK_EQ_INT(r.boundary_edges, 0);
    CHECK_EQ_INT(r.inconsistent_edges, 0);
    CHECK_EQ_INT(r.nonmanifold_vertices, 2); /* the edge's ends: two fans each */
    CHECK_EQ_INT(r.components, 1);
    CHECK(r.volume == 2.0);
    /* Welded numbering (first appearance: box corners 0 2 3 1 4 5 7 6 become 0..7): the
     * edge (1,1,0)-(1,1,1), box corners 3-7, is 2-6. */
    expect_refused(&m, MFG_ERR_INVALID, "non-manifold edge 2-6 shared by 4 triangles (1 non-manifold edges)");
    tmesh_free(&m);
    tmesh_free(&s);

    /* Two cubes touching at the corner (1, 1, 1): a vertex with two fans. */
    add_box(&s, 0, 0, 0, 1, 1, 1);
    add_box(&s, 1, 1, 1, 2, 2, 2);
    m = welded(&s);
    CHECK_EQ_INT(m.nv, 15);
    r = check(&m);
    CHECK_EQ_INT(r.nonmanifold_edges, 0);
    CHECK_EQ_INT(r.boundary_edges, 0);
    CHECK_EQ_INT(r.nonmanifold_vertices, 1);
    CHECK_EQ_INT(r.components, 2);
    expect_refused(&m, MFG_ERR_INVALID, "non-manifold vertex 6: its triangles form 2 separate fans");
    tmesh_free(&m);
    tmesh_free(&s);

    /* An edge used by three triangles (a fin on a closed tetrahedron). */
    add_vertex(&m, 0, 0, 0);
    add_vertex(&m, 1, 0, 0);
    add_vertex(&m, 0, 1, 0);
    add_vertex(&m, 0, 0, 1);
    add_vertex(&m, 1, 1, 1);
    add_tri(&m, 0, 2, 1);
    add_tri(&m, 0, 1, 3);
    add_tri(&m, 0, 3, 2);
    add_tri(&m, 1, 2, 3);
    add_tri(&m, 1, 2, 4);
    r = check(&m);
    CHECK_EQ_INT(r.nonmanifold_edges, 1);
    CHECK_EQ_INT(r.boundary_edges, 2);
    expect_refused(&m, MFG_ERR_INVALID, "mesh is not closed: 2 boundary edges");
    tmesh_free(&m);
}

static void test_degenerate(void)
{
    /* A tetrahedron whose edge 0-1 is split at its midpoint m = 4 on one side, closed by
     * the zero-area triangle (1, m, 0): closed, consistent, one degenerate triangle. */
    tmesh m = {0};
    add_vertex(&m, 0, 0, 0);
    add_vertex(&m, 1, 0, 0);
    add_vertex(&m, 0, 1, 0);
    add_vertex(&m, 0, 0, 1);
    add_vertex(&m, 0.5, 0, 0);
    add_tri(&m, 0, 2, 1);
    add_tri(&m, 0, 4, 3);
    add_tri(&m, 4, 1, 3);
    add_tri(&m, 0, 3, 2);
    add_tri(&m, 1, 2, 3);
    add_tri(&m, 1, 4, 0);
    mfg_mesh_report r = check(&m);
    CHECK_EQ_INT(r.degenerate_triangles, 1);
    CHECK_EQ_INT(r.boundary_edges + r.nonmanifold_edges + r.inconsistent_edges +
                     r.nonmanifold_vertices, 0);
    CHECK(near(r.volume, 1.0 / 6.0, 1e-15));
    CHECK_EQ_INT(mfg_mesh_check_closed(m.xyz, m.nv, m.tri, m.nt, &r), MFG_OK);

    /* Collinear but not exactly (a rounding-size kink): not degenerate. */
    m.xyz[3 * 4 + 1] = 0x1p-60;
    r = check(&m);
    CHECK_EQ_INT(r.degenerate_triangles, 0);
    tmesh_free(&m);

    /* Zero-area triangles only: a closed, consistent "mesh" of two collinear triangles. */
    add_vertex(&m, 0, 0, 0);
    add_vertex(&m, 1, 1, 1);
    add_vertex(&m, 3, 3, 3);
    add_tri(&m, 0, 1, 2);
    add_tri(&m, 0, 2, 1);
    r = check(&m);
    CHECK_EQ_INT(r.degenerate_triangles, 2);
    CHECK_EQ_INT(r.boundary_edges, 0);
    CHECK(r.area == 0.0);
    expect_refused(&m, MFG_ERR_DEGENERATE, "all 2 triangles have zero area");

    /* A doubly covered triangle: closed and consistent, but no volume. */
    m.xyz[3 * 2] = 7;
    r = check(&m);
    CHECK_EQ_INT(r.degenerate_triangles, 0);
    CHECK(r.volume == 0.0);
    expect_refused(&m, MFG_ERR_DEGENERATE, "zero volume");
    tmesh_free(&m);

    /* A very thin but real solid far from the origin: the volume bound scales with the
     * solid's own products (apex at the box centre), so the volume still counts. */
    add_vertex(&m, 1000, 1000, 0);
    add_vertex(&m, 1001, 1000, 0);
    add_vertex(&m, 1000, 1001, 0);
    add_vertex(&m, 1000, 1000, 0x1p-70);
    add_tri(&m, 0, 2, 1);
    add_tri(&m, 0, 1, 3);
    add_tri(&m, 0, 3, 2);
    add_tri(&m, 1, 2, 3);
    CHECK_EQ_INT(mfg_mesh_check_closed(m.xyz, m.nv, m.tri, m.nt, &r), MFG_OK);
    CHECK(near(r.volume, 0x1p-70 / 6, 1e-15 * 0x1p-70));
    tmesh_free(&m);

    /* A repeated index: degenerate, no sides; refused by name. */
    add_box(&m, 0, 0, 0, 1, 1, 1);
    add_tri(&m, 3, 3, 5);
    r = check(&m);
    CHECK_EQ_INT(r.degenerate_triangles, 1);
    CHECK_EQ_INT(r.boundary_edges, 0);
    CHECK_EQ_INT(r.components, 1);
    CHECK(r.volume == 1.0);
    expect_refused(&m, MFG_ERR_INVALID, "triangle 12 repeats a vertex index");
    tmesh_free(&m);

    /* No triangles. */
    add_vertex(&m, 0, 0, 0);
    r = check(&m);
    CHECK_EQ_INT(r.ntriangles, 0);
    CHECK_EQ_INT(r.unused_vertices, 1);
    CHECK_EQ_INT(r.components, 0);
    CHECK(r.volume == 0.0 && r.bbox[0] == 0.0 && r.bbox[5] == 0.0);
    expect_refused(&m, MFG_ERR_DEGENERATE, "no triangles");
    tmesh_free(&m);
}

static void test_hostile(void)
{
    tmesh m = {0};
    add_box(&m, 0, 0, 0, 1, 1, 1);
    mfg_mesh_report r, before;
    memset(&r, 0x77, sizeof r);
    before = r;
    const int64_t counts[] = {-1, INT64_MIN, INT64_MAX, ((int64_t)1 << 40) + 1};
    for (int i = 0; i < 4; i++) {
        CHECK_EQ_INT(mfg_mesh_check(m.xyz, counts[i], m.tri, m.nt, &r), MFG_ERR_INVALID);
        CHECK(strstr(mfg_last_error(), "nvertices") != NULL);
        CHECK_EQ_INT(mfg_mesh_check(m.xyz, m.nv, m.tri, counts[i], &r), MFG_ERR_INVALID);
        CHECK(strstr(mfg_last_error(), "ntriangles") != NULL);
        CHECK_EQ_INT(mfg_mesh_check_closed(m.xyz, m.nv, m.tri, counts[i], &r), MFG_ERR_INVALID);
        mfg_mesh *w = (mfg_mesh *)&r;
        CHECK_EQ_INT(mfg_mesh_weld(m.xyz, counts[i], &w), MFG_ERR_INVALID);
        CHECK(w == (mfg_mesh *)&r);
    }
    /* Fewer vertices than the triangles use. */
    CHECK_EQ_INT(mfg_mesh_check(m.xyz, 7, m.tri, m.nt, &r), MFG_ERR_INVALID);
    CHECK(strstr(mfg_last_error(), "vertex index 7, outside 0 .. 6") != NULL);
    const int64_t bad[] = {-1, 8, INT64_MAX, INT64_MIN};
    for (int i = 0; i < 4; i++) {
        int64_t keep = m.tri[3 * 5 + 2];
        m.tri[3 * 5 + 2] = bad[i];
        CHECK_EQ_INT(mfg_mesh_check(m.xyz, m.nv, m.tri, m.nt, &r), MFG_ERR_INVALID);
        CHECK(strstr(mfg_last_error(), "triangle 5 uses vertex index") != NULL);
        CHECK_EQ_INT(mfg_mesh_check_closed(m.xyz, m.nv, m.tri, m.nt, &r), MFG_ERR_INVALID);
        m.tri[3 * 5 + 2] = keep;
    }
    const double coords[] = {NAN, INFINITY, -INFINITY, 1e300, 1e-300};
    for (int i = 0; i < 5; i++) {
        double keep = m.xyz[3 * 6 + 1];
        m.xyz[3 * 6 + 1] = coords[i];
        CHECK_EQ_INT(mfg_mesh_check(m.xyz, m.nv, m.tri, m.nt, &r), MFG_ERR_INVALID);
        CHECK(strstr(mfg_last_error(), "vertex 6 has a NaN") != NULL);
        CHECK_EQ_INT(mfg_mesh_check_closed(m.xyz, m.nv, m.tri, m.nt, &r), MFG_ERR_INVALID);
        m.xyz[3 * 6 + 1] = keep;
        double soup[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
        soup[4] = coords[i];
        mfg_mesh *w = NULL;
        CHECK_EQ_INT(mfg_mesh_weld(soup, 1, &w), MFG_ERR_INVALID);
        CHECK(w == NULL);
    }
    CHECK(memcmp(&r, &before, sizeof r) == 0);
    CHECK_EQ_INT(mfg_mesh_check(NULL, m.nv, m.tri, m.nt, &r), MFG_ERR_NULL);
    CHECK_EQ_INT(mfg_mesh_check(m.xyz, m.nv, NULL, m.nt, &r), MFG_ERR_NULL);
    CHECK_EQ_INT(mfg_mesh_check(m.xyz, m.nv, m.tri, m.nt, NULL), MFG_ERR_NULL);
    CHECK_EQ_INT(mfg_mesh_check_closed(m.xyz, m.nv, m.tri, m.nt, NULL), MFG_ERR_NULL);
    CHECK_EQ_INT(mfg_mesh_weld(NULL, 1, (mfg_mesh **)&r), MFG_ERR_NULL);
    CHECK_EQ_INT(mfg_mesh_weld(m.xyz, 1, NULL), MFG_ERR_NULL);
    CHECK(memcmp(&r, &before, sizeof r) == 0);
    /* Empty is valid with NULL arrays. */
    CHECK_EQ_INT(mfg_mesh_check(NULL, 0, NULL, 0, &r), MFG_OK);
    CHECK_EQ_INT(r.components, 0);
    mfg_mesh *w = NULL;
    CHECK_EQ_INT(mfg_mesh_weld(NULL, 0, &w), MFG_OK);
    CHECK(w && w->nvertices == 0 && w->ntriangles == 0);
    mfg_mesh_free(w);
    mfg_mesh_free(NULL);
    tmesh_free(&m);
}

static void test_weld(void)
{
    tmesh m = {0};
    add_box(&m, 0, 0, 0, 1, 1, 1);
    /* Renumber the box so its vertices appear in triangle order: then welding its soup
     * must give back exactly this mesh. */
    int64_t map[8], next = 0;
    for (int i = 0; i < 8; i++)
        map[i] = -1;
    for (int64_t i = 0; i < 3 * m.nt; i++)
        if (map[m.tri[i]] < 0)
            map[m.tri[i]] = next++;
    tmesh ref = {0};
    for (int k = 0; k < 8; k++)
        add_vertex(&ref, 0, 0, 0);
    for (int k = 0; k < 8; k++)
        memcpy(ref.xyz + 3 * map[k], m.xyz + 3 * k, 3 * sizeof(double));
    for (int64_t t = 0; t < m.nt; t++)
        add_tri(&ref, map[m.tri[3 * t]], map[m.tri[3 * t + 1]], map[m.tri[3 * t + 2]]);
    tmesh w = welded(&m);
    CHECK_EQ_INT(w.nv, 8);
    CHECK_EQ_INT(w.nt, 12);
    CHECK(w.nv == 8 && memcmp(w.xyz, ref.xyz, 24 * sizeof(double)) == 0);
    CHECK(w.nt == 12 && memcmp(w.tri, ref.tri, 36 * sizeof(int64_t)) == 0);
    tmesh_free(&w);
    tmesh_free(&ref);
    tmesh_free(&m);

    /* -0 and +0 are one vertex; values one ulp apart are not; the first appearance's
     * doubles are kept. */
    double soup[18] = {-0.0, 0, 0, 1, 0, 0, 0, 1, 0,
                       0.0, -0.0, 0, 0, 1, 0, nextafter(1.0, 2.0), 0, 0};
    mfg_mesh *r = NULL;
    CHECK_EQ_INT(mfg_mesh_weld(soup, 2, &r), MFG_OK);
    CHECK_EQ_INT(r->nvertices, 4);
    const int64_t tris[6] = {0, 1, 2, 0, 2, 3};
    CHECK(memcmp(r->triangles, tris, sizeof tris) == 0);
    CHECK(signbit(r->vertices[0]) && r->vertices[9] == nextafter(1.0, 2.0));
    mfg_mesh_free(r);

    /* Coincident corners give a repeated index, kept for the check to count. */
    double flat[9] = {1, 2, 3, 1, 2, 3, 4, 5, 6};
    CHECK_EQ_INT(mfg_mesh_weld(flat, 1, &r), MFG_OK);
    CHECK_EQ_INT(r->nvertices, 2);
    CHECK(r->triangles[0] == 0 && r->triangles[1] == 0 && r->triangles[2] == 1);
    mfg_mesh_report rep;
    CHECK_EQ_INT(mfg_mesh_check(r->vertices, r->nvertices, r->triangles, r->ntriangles, &rep),
                 MFG_OK);
    CHECK_EQ_INT(rep.degenerate_triangles, 1);
    mfg_mesh_free(r);
}

/* A UV sphere: poles plus (rings) x (segments) vertices, 2 * segments * (rings - 1)
 * triangles; (theta, phi) order is outward. */
static void make_sphere(tmesh *m, int rings, int segments)
{
    int64_t north = add_vertex(m, 0, 0, 1);
    for (int i = 1; i <= rings; i++)
        for (int j = 0; j < segments; j++) {
            double th = M_PI * i / (rings + 1), ph = 2 * M_PI * j / segments;
            add_vertex(m, sin(th) * cos(ph), sin(th) * sin(ph), cos(th));
        }
    int64_t south = add_vertex(m, 0, 0, -1);
#define RING(i, j) (1 + (int64_t)((i) - 1) * segments + ((j) % segments))
    for (int j = 0; j < segments; j++) {
        add_tri(m, north, RING(1, j), RING(1, j + 1));
        for (int i = 1; i < rings; i++) {
            add_tri(m, RING(i, j), RING(i + 1, j), RING(i + 1, j + 1));
            add_tri(m, RING(i, j), RING(i + 1, j + 1), RING(i, j + 1));
        }
        add_tri(m, RING(rings, j), south, RING(rings, j + 1));
    }
#undef RING
}

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

static void test_big_sphere(void)
{
    tmesh m = {0};
    make_sphere(&m, 500, 1000); /* 1,000,000 triangles */
    CHECK_EQ_INT(m.nt, 1000000);
    double t0 = now();
    mfg_mesh_report r;
    int64_t *nb = NULL;
    CHECK_EQ_INT(mfg_mesh_require_closed(m.xyz, m.nv, m.tri, m.nt, &r, &nb), MFG_OK);
    double t1 = now();
    free(nb);
    printf("closed check of a %lld-triangle sphere: %.3f s\n", (long long)m.nt, t1 - t0);
    CHECK(near(r.volume, 4 * M_PI / 3, 1e-4) && r.volume < 4 * M_PI / 3);
    printf("volume %.9f (4 pi/3 = %.9f), area %.9f (4 pi = %.9f)\n", r.volume, 4 * M_PI / 3,
           r.area, 4 * M_PI);
    CHECK(near(r.area, 4 * M_PI, 2e-4) && r.area < 4 * M_PI);
    CHECK_EQ_INT(r.components, 1);
    /* Through a soup and back: the weld numbers the vertices in another order, so the
     * reports are compared, not the arrays. */
    double *soup = malloc((size_t)m.nt * 9 * sizeof *soup);
    for (int64_t i = 0; i < 3 * m.nt; i++)
        memcpy(soup + 3 * i, m.xyz + 3 * m.tri[i], 3 * sizeof *soup);
    t0 = now();
    mfg_mesh *w = NULL;
    CHECK_EQ_INT(mfg_mesh_weld(soup, m.nt, &w), MFG_OK);
    t1 = now();
    printf("weld of the same sphere's soup: %.3f s\n", t1 - t0);
    CHECK(w && w->nvertices == m.nv);
    mfg_mesh_report q;
    if (w) {
        CHECK_EQ_INT(mfg_mesh_check_closed(w->vertices, w->nvertices, w->triangles,
                                           w->ntriangles, &q), MFG_OK);
        CHECK(near(q.volume, r.volume, 1e-12));
    }
    mfg_mesh_free(w);
    free(soup);
    tmesh_free(&m);
}

/* Issue 22: shells that cross or nest wrongly pass every edge test but bound no solid. */
static void flip_from(tmesh *m, int64_t t0)
{
    for (int64_t t = t0; t < m->nt; t++) {
        int64_t x = m->tri[3 * t + 1];
        m->tri[3 * t + 1] = m->tri[3 * t + 2];
        m->tri[3 * t + 2] = x;
    }
}

static void test_crossing_and_nested_shells(void)
{
    /* Two overlapping boxes (volume 4 against a union of 3.75): axis-aligned, their top
     * and bottom faces coplanar (the coplanar overlap test), and moved off the planes
     * (edges piercing faces). */
    tmesh a = {0};
    add_box(&a, 0, 0, 0, 2, 1, 1);
    add_box(&a, 1.5, 0.5, 0, 3.5, 1.5, 1);
    CHECK(check(&a).volume == 4.0);
    expect_refused(&a, MFG_ERR_INVALID, "shells cross: triangles");
    tmesh b = {0};
    add_box(&b, 0, 0, 0, 2, 1, 1);
    add_box(&b, 1.5, 0.25, 0.25, 3.5, 1.25, 1.25);
    expect_refused(&b, MFG_ERR_INVALID, "shells cross: triangles");
    /* Two boxes glued face to face as separate shells: the shared face twice. */
    tmesh g = {0};
    add_box(&g, 0, 0, 0, 1, 1, 1);
    add_box(&g, 1, 0, 0, 2, 1, 1);
    expect_refused(&g, MFG_ERR_INVALID, "shells cross");
    /* A box inside a box, both facing out; the same turned into a cavity is fine, and so
     * is an island inside the cavity; one turned inside-out alone is not. */
    tmesh n = {0};
    add_box(&n, 0, 0, 0, 4, 4, 4);
    add_box(&n, 1, 1, 1, 2, 2, 2);
    expect_refused(&n, MFG_ERR_INVALID, "nested shells: the shell of triangle 12 (facing out)");
    tmesh c = {0};
    add_box(&c, 0, 0, 0, 6, 6, 6);
    add_box(&c, 1, 1, 1, 5, 5, 5);
    flip_from(&c, 12);
    add_box(&c, 2, 2, 2, 3, 3, 3);
    mfg_mesh_report r;
    CHECK_EQ_INT(mfg_mesh_check_closed(c.xyz, c.nv, c.tri, c.nt, &r), MFG_OK);
    CHECK(r.volume == 216.0 - 64.0 + 1.0);
    tmesh o = {0};
    add_box(&o, 0, 0, 0, 4, 4, 4);
    add_box(&o, 10, 0, 0, 11, 1, 1);
    flip_from(&o, 12);
    expect_refused(&o, MFG_ERR_INVALID, "outside every solid shell");
    /* Shells touching at a vertex only (strict tests): not a crossing. */
    tmesh v = {0};
    add_box(&v, 0, 0, 0, 1, 1, 1);
    add_box(&v, 1, 1, 1, 2, 2, 2);
    CHECK_EQ_INT(mfg_mesh_check_closed(v.xyz, v.nv, v.tri, v.nt, &r), MFG_OK);
    /* A box and, beside it, a tetrahedron folded flat (four coplanar corners: closed and
     * 2-manifold, volume 0, its faces overlapping but sharing vertices): a flat shell. */
    tmesh f = {0};
    add_box(&f, 0, 0, 0, 1, 1, 1);
    int64_t f0 = add_vertex(&f, 3, 0, 0), f1 = add_vertex(&f, 4, 0, 0), f2 = add_vertex(&f, 3, 1, 0);
    int64_t f3 = add_vertex(&f, 3.25, 0.25, 0);
    add_tri(&f, f0, f1, f2);
    add_tri(&f, f0, f3, f1);
    add_tri(&f, f1, f3, f2);
    add_tri(&f, f2, f3, f0);
    CHECK(check(&f).volume == 1.0);
    expect_refused(&f, MFG_ERR_INVALID, "flat shell: the shell of triangle 12 (4 triangles)");
    /* A cavity (an octahedron) touching its box at one corner on the box's bottom face,
     * that corner listed first: a vertex there has no winding number (it lies on the other
     * shell), the centroid of a triangle has - accepted, volume 64 - 4/3. */
    tmesh t = {0};
    add_box(&t, 0, 0, 0, 4, 4, 4);
    int64_t o0 = add_vertex(&t, 2, 2, 0), o1 = add_vertex(&t, 2, 2, 2), o2 = add_vertex(&t, 1, 2, 1);
    int64_t o3 = add_vertex(&t, 3, 2, 1), o4 = add_vertex(&t, 2, 1, 1), o5 = add_vertex(&t, 2, 3, 1);
    /* facing in: each face's corners clockwise seen from outside the octahedron */
    const int64_t eq[4] = {o2, o4, o3, o5};
    for (int k = 0; k < 4; k++) {
        add_tri(&t, o0, eq[k], eq[(k + 1) % 4]);
        add_tri(&t, o1, eq[(k + 1) % 4], eq[k]);
    }
    mfg_status ts = mfg_mesh_check_closed(t.xyz, t.nv, t.tri, t.nt, &r);
    CHECK_EQ_INT(ts, MFG_OK);
    if (ts != MFG_OK)
        fprintf(stderr, "  touching cavity: %s\n", mfg_last_error());
    CHECK(fabs(r.volume - (64.0 - 4.0 / 3.0)) < 1e-12);
    tmesh *all[] = {&a, &b, &g, &n, &c, &o, &v, &f, &t};
    for (size_t i = 0; i < sizeof all / sizeof *all; i++)
        tmesh_free(all[i]);
}

int main(void)
{
    test_cube();
    test_tetrahedron();
    test_torus();
    test_two_cubes();
    test_crossing_and_nested_shells();
    test_open_and_flipped();
    test_nonmanifold();
    test_degenerate();
    test_hostile();
    test_weld();
    test_big_sphere();
    return mfg_test_report("mesh");
}
