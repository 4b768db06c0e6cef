/* SPDX-License-Identifier: LGPL-2.1-or-later */
/* test_medial_surface.c - the 3-D medial surface through the public API (issue 9;
 * docs/design/medial.md section 7, "Analytic solids"; "design N" below is that file): the
 * cuboid, the cube, the square prism, the L-bracket and the 48-gon disc, whose sheets,
 * seams and junctions are derived by hand; bit-identical results for any thread count and
 * triangle order; bad input refused with *out untouched.  Elements are matched by geometry
 * (their planes and lines), never by id. */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "mfg_test.h"
#include "mfgeom.h"
#include "medial_solids.h"

/* ---- access helpers ------------------------------------------------------------------------ */

static int64_t face_with(const mfg_medial *m, double nx, double ny, double nz, double d)
{
    for (int64_t f = 0; f < m->nfaces; f++) {
        const double *p = m->face_planes + 4 * f;
        if (fabs(p[0] - nx) < 1e-12 && fabs(p[1] - ny) < 1e-12 && fabs(p[2] - nz) < 1e-12 &&
            fabs(p[3] - d) < 1e-9)
            return f;
    }
    return -1;
}

static int64_t edge_on_line_z(const mfg_medial *m, double x, double y)
{
    for (int64_t i = 0; i < m->nedges; i++) {
        const double *A = m->edge_segments + 6 * i;
        if (A[0] == x && A[1] == y && A[3] == x && A[4] == y)
            return m->nfaces + i;
    }
    return -1;
}

static int cmp64(const void *a, const void *b)
{
    int64_t x = *(const int64_t *)a, y = *(const int64_t *)b;
    return (x > y) - (x < y);
}

static int set_eq(const int64_t *got, int64_t ng, int64_t *want, int64_t nw)
{
    qsort(want, (size_t)nw, sizeof *want, cmp64);
    return ng == nw && !memcmp(got, want, (size_t)nw * sizeof *want);
}

static double dist3(const double *a, const double *b)
{
    return sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) +
                (a[2] - b[2]) * (a[2] - b[2]));
}

/* The junction at p (within tol), or -1. */
static int64_t junction_at(const mfg_medial *m, const double *p, double tol)
{
    for (int64_t j = 0; j < m->njunctions; j++)
        if (dist3(m->junction_points + 3 * j, p) <= tol)
            return j;
    return -1;
}

static int junction_is(const mfg_medial *m, int64_t j, int64_t *want, int64_t n)
{
    int64_t o = m->junction_element_offsets[j];
    return set_eq(m->junction_elements + o, m->junction_element_offsets[j + 1] - o, want, n);
}

/* The sheet of pair {a, b} (the first), or -1; and the area of sheet s. */
static int64_t sheet_of(const mfg_medial *m, int64_t a, int64_t b)
{
    int64_t lo = a < b ? a : b, hi = a < b ? b : a;
    for (int64_t s = 0; s < m->nsheets; s++)
        if (m->sheet_elements[2 * s] == lo && m->sheet_elements[2 * s + 1] == hi)
            return s;
    return -1;
}

static double sheet_area(const mfg_medial *m, int64_t s)
{
    const double *V = m->sheet_vertices + 3 * m->sheet_vertex_offsets[s];
    double A = 0;
    for (int64_t t = m->sheet_triangle_offsets[s]; t < m->sheet_triangle_offsets[s + 1]; t++) {
        const int64_t *tv = m->sheet_triangles + 3 * t;
        const double *p = V + 3 * tv[0], *q = V + 3 * tv[1], *r = V + 3 * tv[2];
        double u[3] = {q[0] - p[0], q[1] - p[1], q[2] - p[2]};
        double v[3] = {r[0] - p[0], r[1] - p[1], r[2] - p[2]};
        double c[3] = {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]};
        A += 0.5 * sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]);
    }
    return A;
}

static double total_area(const mfg_medial *m)
{
    double A = 0;
    for (int64_t s = 0; s < m->nsheets; s++)
        A += sheet_area(m, s);
    return A;
}

/* The seam with exactly this element set (the first), or -1. */
static int64_t seam_with(const mfg_medial *m, int64_t *want, int64_t n)
{
    qsort(want, (size_t)n, sizeof *want, cmp64);
    for (int64_t c = 0; c < m->nseams; c++) {
        int64_t o = m->seam_element_offsets[c];
        if (m->seam_element_offsets[c + 1] - o == n && !memcmp(m->seam_elements + o, want, (size_t)n * 8))
            return c;
    }
    return -1;
}

static int64_t seams_with(const mfg_medial *m, int64_t *want, int64_t n)
{
    qsort(want, (size_t)n, sizeof *want, cmp64);
    int64_t k = 0;
    for (int64_t c = 0; c < m->nseams; c++) {
        int64_t o = m->seam_element_offsets[c];
        k += m->seam_element_offsets[c + 1] - o == n && !memcmp(m->seam_elements + o, want, (size_t)n * 8);
    }
    return k;
}

static double diag_of(const tmesh *t)
{
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (int64_t i = 0; i < t->nv; i++)
        for (int k = 0; k < 3; k++) {
            lo[k] = fmin(lo[k], t->xyz[3 * i + k]);
            hi[k] = fmax(hi[k], t->xyz[3 * i + k]);
        }
    return dist3(lo, hi);
}

/* Carrier distance of element e from the public tables: the face's plane, the edge's
 * line, the vertex. */
static double carrier_dist(const mfg_medial *m, int64_t e, const double *x)
{
    if (e < m->nfaces) {
        const double *p = m->face_planes + 4 * e;
        return p[3] - (p[0] * x[0] + p[1] * x[1] + p[2] * x[2]);
    }
    if (e < m->nfaces + m->nedges) {
        const double *A = m->edge_segments + 6 * (e - m->nfaces), *B = A + 3;
        double u[3] = {B[0] - A[0], B[1] - A[1], B[2] - A[2]}, d[3] = {x[0] - A[0], x[1] - A[1], x[2] - A[2]};
        double l = sqrt(u[0] * u[0] + u[1] * u[1] + u[2] * u[2]), t = (d[0] * u[0] + d[1] * u[1] + d[2] * u[2]) / l;
        double r[3] = {d[0] - t * u[0] / l, d[1] - t * u[1] / l, d[2] - t * u[2] / l};
        return sqrt(r[0] * r[0] + r[1] * r[1] + r[2] * r[2]);
    }
    return dist3(x, m->vertex_points + 3 * (e - m->nfaces - m->nedges));
}

/* Every sheet vertex is equidistant from the sheet's two elements at its radius, within
 * 1e-9 L (design 4.1): checked on every result of this file. */
static int sheet_vertices_off(const mfg_medial *m, double L)
{
    int bad = 0;
    for (int64_t s = 0; s < m->nsheets; s++)
        for (int64_t v = m->sheet_vertex_offsets[s]; v < m->sheet_vertex_offsets[s + 1]; v++) {
            const double *p = m->sheet_vertices + 3 * v;
            double r = m->sheet_radii[v];
            bad += fabs(carrier_dist(m, m->sheet_elements[2 * s], p) - r) > 1e-9 * L ||
                   fabs(carrier_dist(m, m->sheet_elements[2 * s + 1], p) - r) > 1e-9 * L;
        }
    return bad;
}

static mfg_medial *run(const tmesh *t, double tol, uint32_t flags, int threads)
{
    mfg_medial *m = NULL;
    mfg_status st = mfg_medial_surface(t->xyz, t->nv, t->tri, t->nt, tol, flags, threads, &m);
    CHECK_EQ_INT(st, MFG_OK);
    if (st != MFG_OK)
        fprintf(stderr, "  mfg_medial_surface: %s\n", mfg_last_error());
    if (m)
        CHECK_EQ_INT(sheet_vertices_off(m, diag_of(t)), 0);
    return st == MFG_OK ? m : NULL;
}

/* Every sheet vertex: its radius is the distance to the planes given (the nearest of them,
 * for the solids here whose medial points are nearest to faces), within 1e-9 L. */

/* ---- the solids ------------------------------------------------------------------------------ */

static void test_cuboid(void)
{
    tmesh t;
    ms_box(&t, 100, 60, 20);
    double L = diag_of(&t), tol = 0.005 * L, eps = 1e-9 * L;
    mfg_medial *m = run(&t, tol, 0, 0);
    if (!m)
        return;
    int64_t z0 = face_with(m, 0, 0, -1, 0), z1 = face_with(m, 0, 0, 1, 20);
    int64_t x0 = face_with(m, -1, 0, 0, 0), x1 = face_with(m, 1, 0, 0, 100);
    int64_t y0 = face_with(m, 0, -1, 0, 0), y1 = face_with(m, 0, 1, 0, 60);
    CHECK_EQ_INT(m->nelements, 26);
    /* One sheet {z0, z1}: z = 10 over [10, 90] x [10, 50], r = 10. */
    CHECK_EQ_INT(m->nsheets, 1);
    int64_t s = sheet_of(m, z0, z1);
    CHECK(s >= 0);
    if (s >= 0) {
        CHECK_EQ_INT(m->sheet_forms[s], 1);
        double A = sheet_area(m, s);
        CHECK(fabs(A - 3200) <= 0.01 * 3200);
        int bad = 0;
        for (int64_t v = m->sheet_vertex_offsets[s]; v < m->sheet_vertex_offsets[s + 1]; v++) {
            const double *p = m->sheet_vertices + 3 * v;
            bad += fabs(p[2] - 10) > eps || fabs(m->sheet_radii[v] - 10) > eps || p[0] < 10 - eps ||
                   p[0] > 90 + eps || p[1] < 10 - eps || p[1] > 50 + eps;
        }
        CHECK_EQ_INT(bad, 0);
    }
    /* 4 junctions (10|90, 10|50, 10) touching z0, z1 and the two sides, r = 10, BRANCH. */
    CHECK_EQ_INT(m->njunctions, 4);
    for (int c = 0; c < 4; c++) {
        double p[3] = {c & 1 ? 90 : 10, c & 2 ? 50 : 10, 10};
        int64_t j = junction_at(m, p, 1e-9 * L);
        CHECK(j >= 0);
        if (j < 0)
            continue;
        int64_t want[4] = {z0, z1, c & 1 ? x1 : x0, c & 2 ? y1 : y0};
        CHECK(junction_is(m, j, want, 4));
        CHECK(fabs(m->junction_radii[j] - 10) <= eps);
        CHECK_EQ_INT(m->junction_kinds[j], MFG_MEDIAL_BRANCH);
    }
    /* 4 BRANCH seams {z0, z1, side}, r = 10, on the sheet's edges, junction to junction. */
    CHECK_EQ_INT(m->nseams, 4);
    int64_t sides[4] = {x0, x1, y0, y1};
    for (int k = 0; k < 4; k++) {
        int64_t want[3] = {z0, z1, sides[k]};
        int64_t c = seam_with(m, want, 3);
        CHECK(c >= 0);
        if (c < 0)
            continue;
        CHECK_EQ_INT(m->seam_kinds[c], MFG_MEDIAL_BRANCH);
        CHECK(m->seam_ends[2 * c] >= 0 && m->seam_ends[2 * c + 1] >= 0 &&
              m->seam_ends[2 * c] != m->seam_ends[2 * c + 1]);
        int bad = 0;
        for (int64_t p = m->seam_point_offsets[c]; p < m->seam_point_offsets[c + 1]; p++) {
            const double *q = m->seam_points + 3 * p;
            double off = k == 0 ? fabs(q[0] - 10) : k == 1 ? fabs(q[0] - 90) : k == 2 ? fabs(q[1] - 10) : fabs(q[1] - 50);
            bad += fabs(q[2] - 10) > eps || off > eps || fabs(m->seam_radii[p] - 10) > eps;
        }
        CHECK_EQ_INT(bad, 0);
    }
    CHECK(m->leaves > 0 && m->cells_visited >= m->leaves && m->leaf_size > 0 && m->leaf_size <= tol);
    mfg_medial_free(m);

    /* Full: 13 sheets (the mid-plane, 8 trapezoids, 4 triangles), total area 11 685. */
    m = run(&t, tol, MFG_MEDIAL_FULL, 0);
    if (!m)
        return;
    CHECK_EQ_INT(m->nsheets, 13);
    double A = total_area(m), Aw = 3200 + 4 * 1272.79 + 4 * 707.107 + 4 * 141.421;
    CHECK(fabs(A - Aw) <= 0.01 * Aw);
    for (int c = 0; c < 4; c++) {
        double p[3] = {c & 1 ? 90 : 10, c & 2 ? 50 : 10, 10};
        CHECK(junction_at(m, p, 1e-9 * L) >= 0);
    }
    mfg_medial_free(m);
}

static void test_cube(void)
{
    tmesh t;
    ms_box(&t, 40, 40, 40);
    double L = diag_of(&t), tol = 0.005 * L;
    mfg_medial *m = run(&t, tol, 0, 0);
    if (!m)
        return;
    CHECK_EQ_INT(m->nsheets, 0);
    CHECK_EQ_INT(m->nseams, 0);
    CHECK_EQ_INT(m->njunctions, 1);
    if (m->njunctions == 1) {
        CHECK(dist3(m->junction_points, (double[3]){20, 20, 20}) <= 1e-9 * L);
        CHECK(fabs(m->junction_radii[0] - 20) <= 1e-9 * L);
        int64_t want[6] = {0, 1, 2, 3, 4, 5};
        CHECK(junction_is(m, 0, want, 6));
        CHECK_EQ_INT(m->junction_kinds[0], MFG_MEDIAL_BRANCH);
    }
    mfg_medial_free(m);
    /* Full: 12 triangles of 565.7 (the edges' bisector planes, out to the corners). */
    m = run(&t, tol, MFG_MEDIAL_FULL, 0);
    if (!m)
        return;
    CHECK_EQ_INT(m->nsheets, 12);
    CHECK(fabs(total_area(m) - 12 * 565.685) <= 0.01 * 12 * 565.685);
    /* 8 seams from the centre towards the corners */
    CHECK_EQ_INT(m->nseams, 8);
    CHECK_EQ_INT(m->njunctions, 1);
    mfg_medial_free(m);
}

static void test_square_prism(void)
{
    tmesh t;
    ms_box(&t, 20, 20, 100);
    double L = diag_of(&t), tol = 0.005 * L, eps = 1e-9 * L;
    mfg_medial *m = run(&t, tol, 0, 0);
    if (!m)
        return;
    int64_t sides[4] = {face_with(m, -1, 0, 0, 0), face_with(m, 1, 0, 0, 20),
                        face_with(m, 0, -1, 0, 0), face_with(m, 0, 1, 0, 20)};
    int64_t zf[2] = {face_with(m, 0, 0, -1, 0), face_with(m, 0, 0, 1, 100)};
    CHECK_EQ_INT(m->nsheets, 0);
    /* 2 junctions (10, 10, 10|90) with 5 faces, r = 10. */
    CHECK_EQ_INT(m->njunctions, 2);
    int64_t jend[2] = {-1, -1};
    for (int e = 0; e < 2; e++) {
        double p[3] = {10, 10, e ? 90 : 10};
        int64_t j = jend[e] = junction_at(m, p, eps);
        CHECK(j >= 0);
        if (j < 0)
            continue;
        int64_t want[5] = {sides[0], sides[1], sides[2], sides[3], zf[e]};
        CHECK(junction_is(m, j, want, 5));
        CHECK(fabs(m->junction_radii[j] - 10) <= eps);
    }
    /* 1 DEGENERATE seam along the axis with the 4 sides, r = 10, from end to end. */
    CHECK_EQ_INT(m->nseams, 1);
    int64_t want[4];
    memcpy(want, sides, sizeof want);
    int64_t c = seam_with(m, want, 4);
    CHECK(c >= 0);
    if (c >= 0) {
        CHECK_EQ_INT(m->seam_kinds[c], MFG_MEDIAL_DEGENERATE);
        int64_t p0 = m->seam_point_offsets[c], p1 = m->seam_point_offsets[c + 1] - 1;
        CHECK(dist3(m->seam_points + 3 * p0, (double[3]){10, 10, 10}) <= eps);
        CHECK(dist3(m->seam_points + 3 * p1, (double[3]){10, 10, 90}) <= eps);
        CHECK(m->seam_ends[2 * c] == jend[0] && m->seam_ends[2 * c + 1] == jend[1]);
        int bad = 0;
        for (int64_t p = p0; p <= p1; p++) {
            const double *q = m->seam_points + 3 * p;
            bad += fabs(q[0] - 10) > eps || fabs(q[1] - 10) > eps || fabs(m->seam_radii[p] - 10) > eps;
        }
        CHECK_EQ_INT(bad, 0);
    }
    mfg_medial_free(m);
    /* Full: 4 trapezoids and 8 end triangles; 8 seams from the junctions to the corners
     * and the axis once (the diagonal sheets' boundary segments on it name 3 sides). */
    m = run(&t, tol, MFG_MEDIAL_FULL, 0);
    if (!m)
        return;
    CHECK_EQ_INT(m->nsheets, 12);
    double Aw = 4 * 0.5 * (100 + 80) * 10 * sqrt(2.0) + 8 * 141.421;
    CHECK(fabs(total_area(m) - Aw) <= 0.01 * Aw);
    CHECK_EQ_INT(m->nseams, 9);
    CHECK_EQ_INT(m->njunctions, 2);
    memcpy(want, sides, sizeof want);
    CHECK_EQ_INT(seams_with(m, want, 4), 1);
    mfg_medial_free(m);
}

static void test_l_bracket(void)
{
    tmesh t;
    ms_l_bracket(&t);
    double L = diag_of(&t), tol = 0.005 * L, eps = 1e-9 * L, rs = (2 - sqrt(2.0)) * 10;
    mfg_medial *m = run(&t, tol, 0, 0);
    if (!m)
        return;
    CHECK_EQ_INT(m->nfaces, 8);
    CHECK_EQ_INT(m->nedges, 18);
    CHECK_EQ_INT(m->nvertices, 12);
    int64_t Fo = face_with(m, -1, 0, 0, 0), Fi = face_with(m, 1, 0, 0, 10);
    int64_t Go = face_with(m, 0, -1, 0, 0), Gi = face_with(m, 0, 1, 0, 10);
    int64_t z0 = face_with(m, 0, 0, -1, 0), z1 = face_with(m, 0, 0, 1, 40);
    int64_t Ft = face_with(m, 0, 1, 0, 50), Gt = face_with(m, 1, 0, 0, 50);
    int64_t E = edge_on_line_z(m, 10, 10);
    CHECK(Fo >= 0 && Fi >= 0 && Go >= 0 && Gi >= 0 && z0 >= 0 && z1 >= 0 && Ft >= 0 && Gt >= 0 && E >= 0);
    CHECK_EQ_INT(m->element_convex[E], 0);
    /* 10 junctions. */
    CHECK_EQ_INT(m->njunctions, 10);
    for (int top = 0; top < 2; top++) {
        double z = top ? 40 - rs : rs, zz = top ? 35 : 5;
        int64_t zf = top ? z1 : z0;
        /* (rho*, rho*, rho*) {Fo, Go, E, z}: BRANCH */
        int64_t j = junction_at(m, (double[3]){rs, rs, z}, eps);
        CHECK(j >= 0);
        if (j >= 0) {
            int64_t want[4] = {Fo, Go, E, zf};
            CHECK(junction_is(m, j, want, 4));
            CHECK(fabs(m->junction_radii[j] - rs) <= eps);
            CHECK_EQ_INT(m->junction_kinds[j], MFG_MEDIAL_BRANCH);
        }
        /* (5, 10, 5) {Fo, Fi, E, z} and its mirror: SMOOTH */
        for (int mir = 0; mir < 2; mir++) {
            double p[3] = {mir ? 10 : 5, mir ? 5 : 10, zz};
            j = junction_at(m, p, eps);
            CHECK(j >= 0);
            if (j < 0)
                continue;
            int64_t want[4] = {mir ? Go : Fo, mir ? Gi : Fi, E, zf};
            CHECK(junction_is(m, j, want, 4));
            CHECK(fabs(m->junction_radii[j] - 5) <= eps);
            CHECK_EQ_INT(m->junction_kinds[j], MFG_MEDIAL_SMOOTH);
            /* the arm end (5, 45, 5) {Fo, Fi, top, z}: BRANCH */
            double q[3] = {mir ? 45 : 5, mir ? 5 : 45, zz};
            j = junction_at(m, q, eps);
            CHECK(j >= 0);
            if (j < 0)
                continue;
            int64_t want2[4] = {mir ? Go : Fo, mir ? Gi : Fi, mir ? Gt : Ft, zf};
            CHECK(junction_is(m, j, want2, 4));
            CHECK_EQ_INT(m->junction_kinds[j], MFG_MEDIAL_BRANCH);
        }
    }
    /* Sheets {Fo, Fi} (x = 5, y in [10, 45], z in [5, 35]: area 1050) and {Fo, E}, and
     * their mirror images. */
    int64_t s = sheet_of(m, Fo, Fi);
    CHECK(s >= 0);
    if (s >= 0)
        CHECK(fabs(sheet_area(m, s) - 1050) <= 0.01 * 1050);
    s = sheet_of(m, Go, Gi);
    CHECK(s >= 0);
    if (s >= 0)
        CHECK(fabs(sheet_area(m, s) - 1050) <= 0.01 * 1050);
    s = sheet_of(m, Fo, E);
    CHECK(s >= 0);
    if (s >= 0) { /* x = (100 + (y - 10)^2) / 20 = r */
        int bad = 0;
        for (int64_t v = m->sheet_vertex_offsets[s]; v < m->sheet_vertex_offsets[s + 1]; v++) {
            const double *p = m->sheet_vertices + 3 * v;
            double x = (100 + (p[1] - 10) * (p[1] - 10)) / 20;
            bad += fabs(p[0] - x) > 1e-9 * L || fabs(m->sheet_radii[v] - x) > eps ||
                   p[1] < rs - eps || p[1] > 10 + eps;
        }
        CHECK_EQ_INT(bad, 0);
    }
    CHECK(sheet_of(m, Go, E) >= 0);
    /* The BRANCH seam {Fo, Go, E} from (rho*, rho*, rho*) to (rho*, rho*, 40 - rho*). */
    int64_t want[3] = {Fo, Go, E};
    int64_t c = seam_with(m, want, 3);
    CHECK(c >= 0);
    if (c >= 0) {
        CHECK_EQ_INT(m->seam_kinds[c], MFG_MEDIAL_BRANCH);
        int64_t p0 = m->seam_point_offsets[c], p1 = m->seam_point_offsets[c + 1] - 1;
        CHECK(dist3(m->seam_points + 3 * p0, (double[3]){rs, rs, rs}) <= eps);
        CHECK(dist3(m->seam_points + 3 * p1, (double[3]){rs, rs, 40 - rs}) <= eps);
    }
    /* The SMOOTH seam {Fo, Fi, E} at y = 10. */
    int64_t want2[3] = {Fo, Fi, E};
    c = seam_with(m, want2, 3);
    CHECK(c >= 0);
    if (c >= 0)
        CHECK_EQ_INT(m->seam_kinds[c], MFG_MEDIAL_SMOOTH);
    CHECK_EQ_INT(m->nseams, 13);
    mfg_medial_free(m);
    /* Full: the smooth seam {z0, Fi, E} from (5, 10, 5) down to the corner (10, 10, 0) is
     * one polyline (the sheet's trimmed boundary breaks between leaves there). */
    m = run(&t, tol, MFG_MEDIAL_FULL, 0);
    if (!m)
        return;
    CHECK_EQ_INT(m->njunctions, 10);
    int64_t want3[3] = {z0, Fi, E};
    CHECK_EQ_INT(seams_with(m, want3, 3), 1);
    /* (run() checks every sheet vertex on its bisector: at 1 % L the extraction gives one
     * vertex of {z1, E} 0.41 off it by the corner (10, 10, 40), dropped by the assembly.) */
    mfg_medial *m1 = run(&t, 0.01 * L, MFG_MEDIAL_FULL, 0);
    mfg_medial_free(m1);
    c = seam_with(m, want3, 3);
    if (c >= 0) {
        int64_t p0 = m->seam_point_offsets[c], p1 = m->seam_point_offsets[c + 1] - 1;
        CHECK(dist3(m->seam_points + 3 * p0, (double[3]){5, 10, 5}) <= eps);
        CHECK(dist3(m->seam_points + 3 * p1, (double[3]){10, 10, 0}) <= tol);
        CHECK_EQ_INT(m->seam_kinds[c], MFG_MEDIAL_SMOOTH);
    }
    mfg_medial_free(m);
}

/* T-section (design 7): the web's mid-sheet {x = 25, x = 35} passes at y = 10 into the
 * sheet of the two reflex edges E_L = (25, 10, z), E_R = (35, 10, z) (x = 30), which meets
 * the flange's mid-sheets {y0, E_L}, {y0, E_R} in a BRANCH seam {y0, E_L, E_R} at
 * y = 6.25 (|(30, y) - (25, 10)| = y), r = 6.25. */
static void test_tsection(void)
{
    tmesh t;
    ms_tsection(&t);
    double L = diag_of(&t), tol = 0.005 * L, eps = 1e-9 * L;
    mfg_medial *m = run(&t, tol, 0, 0);
    if (!m)
        return;
    CHECK_EQ_INT(m->nfaces, 10);
    int64_t y0 = face_with(m, 0, -1, 0, 0), wl = face_with(m, -1, 0, 0, -25), wr = face_with(m, 1, 0, 0, 35);
    int64_t El = edge_on_line_z(m, 25, 10), Er = edge_on_line_z(m, 35, 10);
    CHECK(y0 >= 0 && wl >= 0 && wr >= 0 && El >= 0 && Er >= 0);
    int64_t want[3] = {y0, El, Er};
    int64_t c = seam_with(m, want, 3);
    CHECK(c >= 0);
    if (c >= 0) {
        CHECK_EQ_INT(m->seam_kinds[c], MFG_MEDIAL_BRANCH);
        int bad = 0;
        for (int64_t p = m->seam_point_offsets[c]; p < m->seam_point_offsets[c + 1]; p++) {
            const double *q = m->seam_points + 3 * p;
            bad += fabs(q[0] - 30) > eps || fabs(q[1] - 6.25) > eps || fabs(m->seam_radii[p] - 6.25) > eps;
        }
        CHECK_EQ_INT(bad, 0);
        int64_t p0 = m->seam_point_offsets[c], p1 = m->seam_point_offsets[c + 1] - 1;
        CHECK(dist3(m->seam_points + 3 * p0, (double[3]){30, 6.25, 6.25}) <= eps);
        CHECK(dist3(m->seam_points + 3 * p1, (double[3]){30, 6.25, 33.75}) <= eps);
    }
    /* Where the web's sheet passes into the edges' sheet all four stay equidistant: one
     * SMOOTH seam from (30, 10, 5) to (30, 10, 35). */
    int64_t want4[4] = {wl, wr, El, Er};
    CHECK_EQ_INT(seams_with(m, want4, 4), 1);
    c = seam_with(m, want4, 4);
    if (c >= 0) {
        CHECK_EQ_INT(m->seam_kinds[c], MFG_MEDIAL_SMOOTH);
        int64_t p0 = m->seam_point_offsets[c], p1 = m->seam_point_offsets[c + 1] - 1;
        CHECK(dist3(m->seam_points + 3 * p0, (double[3]){30, 10, 5}) <= eps);
        CHECK(dist3(m->seam_points + 3 * p1, (double[3]){30, 10, 35}) <= eps);
    }
    CHECK(sheet_of(m, wl, wr) >= 0 && sheet_of(m, El, Er) >= 0);
    CHECK_EQ_INT(m->nsheets, 6);
    CHECK_EQ_INT(m->njunctions, 14);
    CHECK_EQ_INT(m->nseams, 19);
    mfg_medial_free(m);
}

/* The inner corner of a tray: [0, 10]^3 without [3, 10]^3 (walls and floor 3).  At
 * (1.5, 3, 3), r = 1.5, the outer wall x = 0 faces the inner wall x = 3, its two reflex
 * edges and their reflex vertex (3, 3, 3): two contact clusters, yet an isolated point
 * where four smooth seams end (and likewise at (3, 1.5, 3), (3, 3, 1.5)). */
static void test_inner_corner(void)
{
    tmesh t;
    const double g[3] = {0, 3, 10};
    const int occ[2][2][2] = {{{1, 1}, {1, 1}}, {{1, 1}, {1, 0}}};
    ms_grid2(&t, g, g, g, occ);
    double L = diag_of(&t), tol = 0.01 * L, eps = 1e-9 * L;
    mfg_medial *m = run(&t, tol, 0, 0);
    if (!m)
        return;
    CHECK_EQ_INT(m->nfaces, 9);
    for (int ax = 0; ax < 3; ax++) {
        double p[3] = {3, 3, 3};
        p[ax] = 1.5;
        int64_t j = junction_at(m, p, eps);
        CHECK(j >= 0);
        if (j < 0)
            continue;
        CHECK(fabs(m->junction_radii[j] - 1.5) <= eps);
        CHECK_EQ_INT(m->junction_element_offsets[j + 1] - m->junction_element_offsets[j], 5);
        CHECK_EQ_INT(m->junction_kinds[j], MFG_MEDIAL_SMOOTH);
        /* the seams with the outer wall ending there end at this junction */
        int ends = 0;
        for (int64_t c = 0; c < m->nseams; c++)
            ends += (m->seam_ends[2 * c] == j) + (m->seam_ends[2 * c + 1] == j);
        CHECK(ends >= 4);
    }
    mfg_medial_free(m);
}

/* A tessellated curved part, 24 segments at 0.5 % of L: the facets' junctions that the
 * leaf search misses are recovered where the seams end (issue 9, left item 1; 18 seam
 * ends had no junction before).  Every seam end is a junction whose element set holds
 * the seam's, at the seam's end point; every junction is equidistant from its elements
 * (carrier distances from the public tables, within 1e-9 L). */
static void test_cup(void)
{
    static tmesh t;
    memset(&t, 0, sizeof t);
    ms_cup(&t, 24);
    double L = diag_of(&t), tol = 0.005 * L, eps = 1e-9 * L;
    mfg_medial *m = run(&t, tol, 0, 0);
    if (!m)
        return;
    CHECK(m->njunctions >= 200);
    int64_t free_ends = 0, bad_set = 0, bad_point = 0, bad_radius = 0;
    for (int64_t c = 0; c < m->nseams; c++) {
        const int64_t *se = m->seam_elements + m->seam_element_offsets[c];
        int64_t ns = m->seam_element_offsets[c + 1] - m->seam_element_offsets[c];
        int64_t p0 = m->seam_point_offsets[c], p1 = m->seam_point_offsets[c + 1] - 1;
        for (int e = 0; e < 2; e++) {
            int64_t j = m->seam_ends[2 * c + e];
            if (j < 0) {
                free_ends += m->seam_radii[e ? p1 : p0] > tol;
                continue;
            }
            const int64_t *je = m->junction_elements + m->junction_element_offsets[j];
            int64_t nj = m->junction_element_offsets[j + 1] - m->junction_element_offsets[j];
            for (int64_t a = 0, b = 0; a < ns; a++) {
                while (b < nj && je[b] < se[a])
                    b++;
                bad_set += b == nj || je[b] != se[a];
            }
            bad_point += dist3(m->seam_points + 3 * (e ? p1 : p0), m->junction_points + 3 * j) > eps;
        }
    }
    for (int64_t j = 0; j < m->njunctions; j++)
        for (int64_t k = m->junction_element_offsets[j]; k < m->junction_element_offsets[j + 1]; k++)
            bad_radius += fabs(carrier_dist(m, m->junction_elements[k], m->junction_points + 3 * j) -
                               m->junction_radii[j]) > eps;
    CHECK_EQ_INT(free_ends, 0);
    CHECK_EQ_INT(bad_set, 0);
    CHECK_EQ_INT(bad_point, 0);
    CHECK_EQ_INT(bad_radius, 0);
    mfg_medial_free(m);
}

/* At 1 % of L the leaves near the rim hold the convex edges and vertices as well (11
 * elements within D + 2 rho): the junction search must still find all 48. */
static void test_disc_at(double frac)
{
    tmesh t;
    ms_disc(&t, 48, 50, 4);
    double L = diag_of(&t), tol = frac * L, eps = 1e-9 * L;
    mfg_medial *m = run(&t, tol, 0, 0);
    if (!m)
        return;
    CHECK_EQ_INT(m->nfaces, 50);
    int64_t bot = face_with(m, 0, 0, -1, 0), top = face_with(m, 0, 0, 1, 4);
    CHECK_EQ_INT(m->nsheets, 1);
    int64_t s = sheet_of(m, bot, top);
    CHECK(s >= 0);
    double apothem = 50 * cos(M_PI / 48), inner = apothem - 2;
    double Aw = 48 * inner * inner * tan(M_PI / 48);
    if (s >= 0)
        CHECK(fabs(sheet_area(m, s) - Aw) <= 0.01 * Aw);
    CHECK_EQ_INT(m->nseams, 48);
    CHECK_EQ_INT(m->njunctions, 48);
    int bad = 0;
    double rj = inner / cos(M_PI / 48);
    for (int64_t j = 0; j < m->njunctions; j++) {
        const double *p = m->junction_points + 3 * j;
        bad += fabs(hypot(p[0], p[1]) - rj) > 1e-9 * L || fabs(p[2] - 2) > eps ||
               fabs(m->junction_radii[j] - 2) > eps ||
               m->junction_element_offsets[j + 1] - m->junction_element_offsets[j] != 4;
    }
    CHECK_EQ_INT(bad, 0);
    for (int64_t c = 0; c < m->nseams; c++)
        bad += m->seam_kinds[c] != MFG_MEDIAL_BRANCH ||
               m->seam_element_offsets[c + 1] - m->seam_element_offsets[c] != 3;
    CHECK_EQ_INT(bad, 0);
    mfg_medial_free(m);
}

/* ---- invariance and errors ------------------------------------------------------------------- */

#define SAME(field, count) \
    ((count) == 0 || !memcmp(a->field, b->field, (size_t)(count) * sizeof *a->field))

static int same_result(const mfg_medial *a, const mfg_medial *b)
{
    if (a->nelements != b->nelements || a->nsheets != b->nsheets || a->nseams != b->nseams ||
        a->njunctions != b->njunctions)
        return 0;
    int64_t nsv = a->sheet_vertex_offsets[a->nsheets], nst = a->sheet_triangle_offsets[a->nsheets];
    int64_t ncp = a->seam_point_offsets[a->nseams], nce = a->seam_element_offsets[a->nseams];
    int64_t nje = a->junction_element_offsets[a->njunctions];
    if (nsv != b->sheet_vertex_offsets[b->nsheets] || nst != b->sheet_triangle_offsets[b->nsheets] ||
        ncp != b->seam_point_offsets[b->nseams] || nce != b->seam_element_offsets[b->nseams] ||
        nje != b->junction_element_offsets[b->njunctions])
        return 0;
    return SAME(element_kinds, a->nelements) && SAME(face_planes, 4 * a->nfaces) &&
           SAME(sheet_elements, 2 * a->nsheets) && SAME(sheet_forms, a->nsheets) &&
           SAME(sheet_vertex_offsets, a->nsheets + 1) && SAME(sheet_triangle_offsets, a->nsheets + 1) &&
           SAME(sheet_vertices, 3 * nsv) && SAME(sheet_radii, nsv) && SAME(sheet_triangles, 3 * nst) &&
           SAME(seam_kinds, a->nseams) && SAME(seam_point_offsets, a->nseams + 1) &&
           SAME(seam_points, 3 * ncp) && SAME(seam_radii, ncp) &&
           SAME(seam_element_offsets, a->nseams + 1) && SAME(seam_elements, nce) &&
           SAME(seam_ends, 2 * a->nseams) && SAME(junction_kinds, a->njunctions) &&
           SAME(junction_points, 3 * a->njunctions) && SAME(junction_radii, a->njunctions) &&
           SAME(junction_element_offsets, a->njunctions + 1) && SAME(junction_elements, nje);
}

static void test_invariance(void)
{
    tmesh t;
    ms_l_bracket(&t);
    double tol = 0.005 * diag_of(&t);
    for (int full = 0; full < 2; full++) {
        mfg_medial *ref = run(&t, tol, full ? MFG_MEDIAL_FULL : 0, 1);
        if (!ref)
            return;
        int threads[3] = {2, 7, 0};
        for (int i = 0; i < 3; i++) {
            mfg_medial *m = run(&t, tol, full ? MFG_MEDIAL_FULL : 0, threads[i]);
            CHECK(m && same_result(ref, m));
            mfg_medial_free(m);
        }
        tmesh u = t;
        ms_shuffle(&u, 12345);
        mfg_medial *m = run(&u, tol, full ? MFG_MEDIAL_FULL : 0, 2);
        CHECK(m && same_result(ref, m));
        mfg_medial_free(m);
        mfg_medial_free(ref);
    }
}

static void test_errors(void)
{
    tmesh t;
    ms_box(&t, 10, 10, 10);
    mfg_medial *sentinel = (mfg_medial *)&t, *out = sentinel;
    CHECK_EQ_INT(mfg_medial_surface(t.xyz, t.nv, t.tri, t.nt, 0.1, 0, 1, NULL), MFG_ERR_NULL);
    CHECK_EQ_INT(mfg_medial_surface(t.xyz, t.nv, t.tri, t.nt, 0.0, 0, 1, &out), MFG_ERR_INVALID);
    CHECK_EQ_INT(mfg_medial_surface(t.xyz, t.nv, t.tri, t.nt, -1.0, 0, 1, &out), MFG_ERR_INVALID);
    CHECK_EQ_INT(mfg_medial_surface(t.xyz, t.nv, t.tri, t.nt, NAN, 0, 1, &out), MFG_ERR_INVALID);
    CHECK_EQ_INT(mfg_medial_surface(t.xyz, t.nv, t.tri, t.nt, 100.0, 0, 1, &out), MFG_ERR_INVALID);
    CHECK_EQ_INT(mfg_medial_surface(t.xyz, t.nv, t.tri, t.nt, 0.1, 4u, 1, &out), MFG_ERR_INVALID);
    CHECK_EQ_INT(mfg_medial_surface(t.xyz, t.nv, t.tri, t.nt, 0.1, 0, -1, &out), MFG_ERR_INVALID);
    /* open (one triangle missing), flipped (one triangle reversed), NaN */
    CHECK_EQ_INT(mfg_medial_surface(t.xyz, t.nv, t.tri, t.nt - 1, 0.1, 0, 1, &out), MFG_ERR_INVALID);
    tmesh u = t;
    int64_t a = u.tri[0];
    u.tri[0] = u.tri[1];
    u.tri[1] = a;
    CHECK_EQ_INT(mfg_medial_surface(u.xyz, u.nv, u.tri, u.nt, 0.1, 0, 1, &out), MFG_ERR_INVALID);
    u = t;
    u.xyz[4] = NAN;
    CHECK_EQ_INT(mfg_medial_surface(u.xyz, u.nv, u.tri, u.nt, 0.1, 0, 1, &out), MFG_ERR_INVALID);
    CHECK(out == sentinel);
    CHECK(strlen(mfg_last_error()) > 0);
    mfg_medial_free(NULL);
}

int main(int argc, char **argv)
{
    const char *only = argc > 1 ? argv[1] : NULL;
    if (!only || !strcmp(only, "cuboid"))
        test_cuboid();
    if (!only || !strcmp(only, "cube"))
        test_cube();
    if (!only || !strcmp(only, "prism"))
        test_square_prism();
    if (!only || !strcmp(only, "lbracket"))
        test_l_bracket();
    if (!only || !strcmp(only, "disc")) {
        test_disc_at(0.005);
        test_disc_at(0.01);
    }
    if (!only || !strcmp(only, "tsection"))
        test_tsection();
    if (!only || !strcmp(only, "corner"))
        test_inner_corner();
    if (!only || !strcmp(only, "cup"))
        test_cup();
    if (!only || !strcmp(only, "invariance"))
        test_invariance();
    if (!only || !strcmp(only, "errors"))
        test_errors();
    return mfg_test_report("test_medial_surface");
}
