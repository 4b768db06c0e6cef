/* SPDX-License-Identifier: LGPL-2.1-or-later */
/* test_medial_sheets.c - the sheets of the medial surface before assembly
 * (medial/sheets.c: marching tets on the analytic bisectors, trimming, boundary points,
 * seam segments) on solids whose medial sheets are known by hand: the cuboid's mid-plane,
 * the L-bracket's mid-plane and parabolic cylinder, the cube's 12 edge triangles.  The
 * leaves come from a brute-force builder here (a uniform lattice over the bounding box,
 * every element a candidate), independent of the octree.  "design N" cites
 * docs/design/medial.md section N (the sheets: section 4.1). */
#define _POSIX_C_SOURCE 200809L /* clock_gettime */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "medial/medial.h"
#include "medial_find.h"
#include "medial_solids.h"
#include "mfg_test.h"
#include "mfgeom.h"

/* The box [0,X] x [0,Y] x [0,Z], counter-clockwise seen from outside. */
static void box(tmesh *m, double X, double Y, double Z)
{
    memset(m, 0, sizeof *m);
    double s[3] = {X, Y, Z};
    for (int ax = 0; ax < 3; ax++)
        for (int side = 0; side < 2; side++) {
            int64_t q[4];
            int uv[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
            for (int c = 0; c < 4; c++) {
                double p[3];
                p[ax] = side * s[ax];
                p[(ax + 1) % 3] = uv[c][0] * s[(ax + 1) % 3];
                p[(ax + 2) % 3] = uv[c][1] * s[(ax + 2) % 3];
                q[c] = ms_vtx(m, p[0], p[1], p[2]);
            }
            if (!side) {
                int64_t t = q[1];
                q[1] = q[3];
                q[3] = t;
            }
            ms_tri(m, q[0], q[1], q[2]);
            ms_tri(m, q[0], q[2], q[3]);
        }
}

/* T-section: flange [0,60] x [50,60], web [25,35] x [0,50], extruded over z in [0, 40]. */
static void t_section(tmesh *m)
{
    memset(m, 0, sizeof *m);
    static const double P[8][2] = {{25, 0}, {35, 0}, {35, 50}, {60, 50},
                                   {60, 60}, {0, 60},  {0, 50},  {25, 50}};
    static const int T[6][3] = {{0, 1, 2}, {0, 2, 7}, {5, 6, 7}, {5, 7, 2}, {5, 2, 3}, {5, 3, 4}};
    int64_t b[8], t[8];
    for (int i = 0; i < 8; i++) {
        b[i] = ms_vtx(m, P[i][0], P[i][1], 0);
        t[i] = ms_vtx(m, P[i][0], P[i][1], 40);
    }
    for (int i = 0; i < 6; i++) {
        ms_tri(m, t[T[i][0]], t[T[i][1]], t[T[i][2]]);
        ms_tri(m, b[T[i][0]], b[T[i][2]], b[T[i][1]]);
    }
    for (int i = 0; i < 8; i++) {
        int j = (i + 1) % 8;
        ms_tri(m, b[i], b[j], t[j]);
        ms_tri(m, b[i], t[j], t[i]);
    }
}

/* ---- brute-force leaves ---------------------------------------------------------------- */

/* Elements that can be nearest inside the solid (design 3.3): not convex edges, not
 * vertices whose edges are all convex or whose region is empty. */
static int can_be_nearest(const md_elements *el, int64_t e)
{
    int k = md_kind(el, e);
    if (k == MD_EDGE)
        return !el->edge_convex[e - el->nfaces];
    if (k == MD_VERTEX) {
        int64_t j = e - el->nfaces - el->nedges;
        if (el->vert_region_empty[j])
            return 0;
        for (int64_t q = el->vert_edge_offsets[j]; q < el->vert_edge_offsets[j + 1]; q++)
            if (!el->edge_convex[el->vert_edges[q] - el->nfaces])
                return 1;
        return 0;
    }
    return 1;
}

/* A uniform lattice of side lat->h over the bounding box (origin as design 3, unless
 * lat->depth > 0: then lat's own origin), every leaf with
 * C = all elements and P = all non-incident pairs of elements that can be nearest (major:
 * disjoint closures); nT from md_nearest_set_brute at the centre. */
static void brute_leaves_on(const md_elements *el, const md_lattice *lat, int full, md_leaves *lv)
{
    memset(lv, 0, sizeof *lv);
    double h = lat->h;
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (int64_t i = 0; i < el->nv; i++)
        for (int d = 0; d < 3; d++) {
            lo[d] = fmin(lo[d], el->xyz[3 * i + d]);
            hi[d] = fmax(hi[d], el->xyz[3 * i + d]);
        }
    static const double off[3] = {0.0137, 0.0213, 0.0311};
    int n[3], nmax = 1;
    for (int d = 0; d < 3; d++) {
        lv->lat.origin[d] = lat->depth > 0 ? lat->origin[d] : lo[d] - off[d] * h;
        n[d] = (int)ceil((hi[d] - lv->lat.origin[d]) / h);
        if (n[d] > nmax)
            nmax = n[d];
    }
    lv->lat.h = h;
    while ((1 << lv->lat.depth) < nmax)
        lv->lat.depth++;
    int64_t ne = el->nelements, np = 0;
    lv->C = malloc((size_t)ne * sizeof *lv->C);
    lv->P = malloc((size_t)(ne * ne + 1) * sizeof *lv->P);
    for (int64_t e = 0; e < ne; e++)
        lv->C[e] = e;
    for (int64_t a = 0; a < ne; a++)
        for (int64_t b = a + 1; b < ne; b++)
            if (can_be_nearest(el, a) && can_be_nearest(el, b) && !md_incident(el, a, b) &&
                (full || !md_adjacent(el, a, b))) {
                lv->P[2 * np] = a;
                lv->P[2 * np + 1] = b;
                np++;
            }
    lv->nleaves = (int64_t)n[0] * n[1] * n[2];
    lv->leaf = calloc((size_t)lv->nleaves, sizeof *lv->leaf);
    int64_t *T = malloc((size_t)ne * sizeof *T), m = 0;
    for (int i = 0; i < n[0]; i++)
        for (int j = 0; j < n[1]; j++)
            for (int k = 0; k < n[2]; k++) {
                md_leaf *L = lv->leaf + m++;
                L->ijk[0] = i;
                L->ijk[1] = j;
                L->ijk[2] = k;
                L->nC = (int32_t)ne;
                L->nP = (int32_t)np;
                L->C_off = 0;
                L->P_off = 0;
                double c[3] = {lv->lat.origin[0] + h * (i + 0.5), lv->lat.origin[1] + h * (j + 0.5),
                               lv->lat.origin[2] + h * (k + 0.5)};
                L->nT = (int32_t)md_nearest_set_brute(el, c, sqrt(3.0) * h, T, NULL);
            }
    free(T);
    lv->cells_visited = lv->nleaves;
}

static void brute_leaves(const md_elements *el, double h, int full, md_leaves *lv)
{
    md_lattice lat;
    memset(&lat, 0, sizeof lat);
    lat.h = h;
    brute_leaves_on(el, &lat, full, lv);
}

static void brute_free(md_leaves *lv)
{
    free(lv->leaf);
    free(lv->C);
    free(lv->P);
    memset(lv, 0, sizeof *lv);
}

/* ---- checks on a soup ---------------------------------------------------------------- */

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

static double tri_area(const md_soup *s, int64_t t)
{
    const double *p = s->xyz + 3 * s->tris[3 * t], *q = s->xyz + 3 * s->tris[3 * t + 1],
                 *r = s->xyz + 3 * s->tris[3 * t + 2];
    double u[3] = {q[0] - p[0], q[1] - p[1], q[2] - p[2]}, v[3] = {r[0] - p[0], r[1] - p[1], r[2] - p[2]};
    double n[3] = {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]};
    return 0.5 * sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
}

static double pair_area(const md_soup *s, int64_t a, int64_t b)
{
    double A = 0;
    for (int64_t t = 0; t < s->ntris; t++)
        if (s->tri_pair[2 * t] == a && s->tri_pair[2 * t + 1] == b)
            A += tri_area(s, t);
    return A;
}

/* Every sheet vertex equidistant to its pair (carrier distances), its radius that
 * distance, and every seam point equidistant to its 3 elements; returns the worst
 * deviations in *dv, *dr, *ds. */
static void equidistance(const md_elements *el, const md_soup *s, double *dv, double *dr, double *ds)
{
    *dv = *dr = *ds = 0;
    for (int64_t t = 0; t < s->ntris; t++)
        for (int k = 0; k < 3; k++) {
            const double *x = s->xyz + 3 * s->tris[3 * t + k];
            double da = md_dist_car(el, s->tri_pair[2 * t], x, NULL);
            double db = md_dist_car(el, s->tri_pair[2 * t + 1], x, NULL);
            *dv = fmax(*dv, fabs(da - db));
            *dr = fmax(*dr, fabs(s->radius[s->tris[3 * t + k]] - da));
        }
    for (int64_t g = 0; g < s->nsegs; g++)
        for (int k = 0; k < 2; k++) {
            const double *x = s->xyz + 3 * s->seg_verts[2 * g + k];
            double d0 = md_dist_car(el, s->seg_elems[3 * g], x, NULL);
            for (int i = 1; i < 3; i++)
                *ds = fmax(*ds, fabs(md_dist_car(el, s->seg_elems[3 * g + i], x, NULL) - d0));
        }
}

typedef struct edge_rec {
    int64_t u, v;
    int src; /* 0 triangle side, 1 seam segment */
    int fwd; /* a triangle side: 1 when the triangle runs from u to v */
} edge_rec;

static int cmp_edge(const void *pa, const void *pb)
{
    const edge_rec *x = pa, *y = pb;
    if (x->u != y->u)
        return x->u < y->u ? -1 : 1;
    if (x->v != y->v)
        return x->v < y->v ? -1 : 1;
    return x->src - y->src;
}

/* The welded mesh of pair (a, b): counts of edges in 1, 2 and more triangles, and of the
 * edges in one triangle that are not seam segments (*open) and seam segments of the pair
 * that are not triangle edges (*lost), counting only edges longer than minlen (the
 * triangles under 1e-6 h^2 that the extraction drops leave tiny gaps).  Also checks that
 * the two triangles at an edge run along it in opposite directions (one orientation over
 * the sheet). */
static void manifold(const md_soup *s, int64_t a, int64_t b, double minlen, int64_t *n1, int64_t *n2,
                     int64_t *nmore, int64_t *open, int64_t *lost)
{
    edge_rec *E = malloc((size_t)(3 * s->ntris + s->nsegs + 1) * sizeof *E);
    int64_t n = 0;
    for (int64_t t = 0; t < s->ntris; t++) {
        if (s->tri_pair[2 * t] != a || s->tri_pair[2 * t + 1] != b)
            continue;
        for (int k = 0; k < 3; k++) {
            int64_t u = s->tris[3 * t + k], v = s->tris[3 * t + (k + 1) % 3];
            E[n].u = u < v ? u : v;
            E[n].v = u < v ? v : u;
            E[n].src = 0;
            E[n].fwd = u < v;
            n++;
        }
    }
    for (int64_t g = 0; g < s->nsegs; g++) {
        const int64_t *e3 = s->seg_elems + 3 * g;
        int has_a = e3[0] == a || e3[1] == a || e3[2] == a, has_b = e3[0] == b || e3[1] == b || e3[2] == b;
        CHECK(has_a || s->seg_pair[2 * g] != a || s->seg_pair[2 * g + 1] != b);
        CHECK(has_b || s->seg_pair[2 * g] != a || s->seg_pair[2 * g + 1] != b);
        if (s->seg_pair[2 * g] != a || s->seg_pair[2 * g + 1] != b)
            continue;
        int64_t u = s->seg_verts[2 * g], v = s->seg_verts[2 * g + 1];
        E[n].u = u < v ? u : v;
        E[n].v = u < v ? v : u;
        E[n].src = 1;
        E[n].fwd = 0;
        n++;
    }
    qsort(E, (size_t)n, sizeof *E, cmp_edge);
    *n1 = *n2 = *nmore = *open = *lost = 0;
    for (int64_t i = 0; i < n;) {
        int64_t j = i, nt = 0, ns = 0, nf = 0;
        while (j < n && E[j].u == E[i].u && E[j].v == E[i].v) {
            nt += E[j].src == 0;
            ns += E[j].src == 1;
            nf += E[j].src == 0 && E[j].fwd;
            j++;
        }
        if (nt == 2)
            CHECK_EQ_INT(nf, 1);
        if (nt == 1)
            (*n1)++;
        else if (nt == 2)
            (*n2)++;
        else if (nt > 2)
            (*nmore)++;
        const double *p = s->xyz + 3 * E[i].u, *q = s->xyz + 3 * E[i].v;
        int longer = hypot(hypot(p[0] - q[0], p[1] - q[1]), p[2] - q[2]) > minlen;
        if (nt == 1 && ns == 0 && longer)
            (*open)++;
        if (ns > 0 && nt == 0 && longer)
            (*lost)++;
        i = j;
    }
    free(E);
}

static int same_soup(const md_soup *x, const md_soup *y)
{
    return x->nverts == y->nverts && x->ntris == y->ntris && x->nsegs == y->nsegs &&
           !memcmp(x->xyz, y->xyz, 3 * (size_t)x->nverts * sizeof(double)) &&
           !memcmp(x->radius, y->radius, (size_t)x->nverts * sizeof(double)) &&
           !memcmp(x->tris, y->tris, 3 * (size_t)x->ntris * sizeof(int64_t)) &&
           !memcmp(x->tri_pair, y->tri_pair, 2 * (size_t)x->ntris * sizeof(int64_t)) &&
           !memcmp(x->seg_verts, y->seg_verts, 2 * (size_t)x->nsegs * sizeof(int64_t)) &&
           !memcmp(x->seg_elems, y->seg_elems, 3 * (size_t)x->nsegs * sizeof(int64_t)) &&
           !memcmp(x->seg_kind, y->seg_kind, (size_t)x->nsegs * sizeof(int32_t)) &&
           !memcmp(x->seg_pair, y->seg_pair, 2 * (size_t)x->nsegs * sizeof(int64_t));
}

/* Extracts with 1 and 3 threads, checks that both are identical, returns the first. */
static md_soup extract(const md_elements *el, const md_bvh *bvh, const md_leaves *lv, double tol,
                       const char *name)
{
    md_soup s1, s3;
    double t0 = now();
    CHECK_EQ_INT(md_sheets_extract(el, bvh, lv, tol, 1, &s1), MFG_OK);
    double t1 = now();
    CHECK_EQ_INT(md_sheets_extract(el, bvh, lv, tol, 3, &s3), MFG_OK);
    double t2 = now();
    CHECK(same_soup(&s1, &s3));
    printf("%s: %lld leaves, %lld verts, %lld tris, %lld segs; %.3f s (1 thread), %.3f s (3)\n",
           name, (long long)lv->nleaves, (long long)s1.nverts, (long long)s1.ntris,
           (long long)s1.nsegs, t1 - t0, t2 - t1);
    md_soup_free(&s3);
    return s1;
}

/* ---- the cuboid 100 x 60 x 20: one major sheet z = 10 ---------------------------------- */

static void test_cuboid(double h)
{
    tmesh m;
    box(&m, 100, 60, 20);
    md_elements el;
    CHECK_EQ_INT(md_elements_build(m.xyz, m.nv, m.tri, m.nt, h, &el), MFG_OK);
    md_leaves lv;
    brute_leaves(&el, h, 0, &lv);
    md_soup s = extract(&el, NULL, &lv, h, "cuboid"); /* convex: no inside test needed */
    int64_t z0 = face_with(&el, 0, 0, -1, 0), z1 = face_with(&el, 0, 0, 1, 20);
    int64_t x0 = face_with(&el, -1, 0, 0, 0), x1 = face_with(&el, 1, 0, 0, 100);
    int64_t y0 = face_with(&el, 0, -1, 0, 0), y1 = face_with(&el, 0, 1, 0, 60);
    int64_t a = z0 < z1 ? z0 : z1, b = z0 < z1 ? z1 : z0;
    CHECK(s.ntris > 100);
    int other = 0;
    for (int64_t t = 0; t < s.ntris; t++)
        other += s.tri_pair[2 * t] != a || s.tri_pair[2 * t + 1] != b;
    CHECK_EQ_INT(other, 0);
    double A = pair_area(&s, a, b);
    printf("cuboid h=%g: area %.9f (3200), error %.3g = %.3g h^2\n", h, A, A - 3200,
           (A - 3200) / (h * h));
    /* The boundary points are exact: only the 4 corners, cut by a chord inside one leaf
     * each (the junctions come at assembly), may lose area, under h^2 each. */
    CHECK(A <= 3200 + 1e-9 && A >= 3200 - 4 * h * h);
    double bad_z = 0, bad_r = 0, out = 0;
    for (int64_t v = 0; v < s.nverts; v++) {
        const double *x = s.xyz + 3 * v;
        bad_z = fmax(bad_z, fabs(x[2] - 10));
        bad_r = fmax(bad_r, fabs(s.radius[v] - 10));
        out = fmax(out, fmax(fmax(10 - x[0], x[0] - 90), fmax(10 - x[1], x[1] - 50)));
    }
    CHECK(bad_z <= 1e-12);
    CHECK(bad_r <= 1e-9);
    CHECK(out <= 1e-9);
    double dv, dr, ds;
    equidistance(&el, &s, &dv, &dr, &ds);
    CHECK(dv <= 1e-9 * el.diag);
    CHECK(dr <= 1e-9 * el.diag);
    CHECK(ds <= 1e-9 * el.diag);
    /* Seams: BRANCH {z0, z1, side}, their points on the side's offset line (analytic). */
    int bad_seam = 0, per_side[4] = {0, 0, 0, 0};
    const int64_t side[4] = {x0, x1, y0, y1};
    for (int64_t g = 0; g < s.nsegs; g++) {
        const int64_t *e3 = s.seg_elems + 3 * g;
        int which = -1;
        for (int k = 0; k < 4; k++)
            for (int i = 0; i < 3; i++)
                if (e3[i] == side[k])
                    which = k;
        int ok = s.seg_kind[g] == MFG_MEDIAL_BRANCH && which >= 0 &&
                 (e3[0] == a || e3[1] == a) && (e3[1] == b || e3[2] == b);
        if (ok) {
            per_side[which]++;
            for (int k = 0; k < 2; k++) {
                const double *x = s.xyz + 3 * s.seg_verts[2 * g + k];
                double want = which == 0 ? 10 : which == 1 ? 90 : which == 2 ? 10 : 50;
                double got = which < 2 ? x[0] : x[1];
                ok = ok && fabs(got - want) <= 1e-9 && fabs(x[2] - 10) <= 1e-12;
            }
        }
        bad_seam += !ok;
    }
    CHECK_EQ_INT(bad_seam, 0);
    for (int k = 0; k < 4; k++)
        CHECK(per_side[k] * h >= (k < 2 ? 40 : 80) - 2 * h); /* each side's seam is covered */
    int64_t n1, n2, nmore, open, lost;
    manifold(&s, a, b, 0.01 * h, &n1, &n2, &nmore, &open, &lost);
    printf("cuboid mesh: %lld boundary edges, %lld interior, %lld over-used, %lld open, %lld lost\n",
           (long long)n1, (long long)n2, (long long)nmore, (long long)open, (long long)lost);
    CHECK_EQ_INT(nmore, 0);
    CHECK_EQ_INT(open, 0); /* every boundary edge of the sheet is a seam segment */
    CHECK_EQ_INT(lost, 0);
    CHECK(n2 > n1);
    md_soup_free(&s);
    brute_free(&lv);
    md_elements_free(&el);
}

/* ---- the L-bracket: the plane x = 5 and the parabolic cylinder of (Fo, E) ----------- */

static void test_l_bracket(double h)
{
    tmesh m;
    ms_l_bracket(&m);
    md_elements el;
    CHECK_EQ_INT(md_elements_build(m.xyz, m.nv, m.tri, m.nt, h, &el), MFG_OK);
    md_leaves lv;
    brute_leaves(&el, h, 0, &lv);
    md_bvh *bvh = NULL;
    CHECK_EQ_INT(md_bvh_build(&el, &bvh), MFG_OK);
    md_soup s = extract(&el, bvh, &lv, h, "L-bracket");
    int64_t Fo = face_with(&el, -1, 0, 0, 0), Fi = face_with(&el, 1, 0, 0, 10);
    int64_t Go = face_with(&el, 0, -1, 0, 0), Gi = face_with(&el, 0, 1, 0, 10);
    double e0[3] = {10, 10, 0}, e1[3] = {10, 10, 40};
    int64_t E = edge_with(&el, e0, e1);
    CHECK(Fo >= 0 && Fi >= 0 && Go >= 0 && Gi >= 0 && E >= 0);
    CHECK(Fo < E && Fi < E && Go < E);
    double rho = (2 - sqrt(2.0)) * 10;
    /* The (Fo, Fi) sheet: x = 5 over y in [10, 45], z in [5, 35], r = 5. */
    double A = pair_area(&s, Fo < Fi ? Fo : Fi, Fo < Fi ? Fi : Fo);
    double Ag = pair_area(&s, Go < Gi ? Go : Gi, Go < Gi ? Gi : Go);
    printf("L-bracket h=%g: (Fo,Fi) area %.6f, (Go,Gi) area %.6f (1050)\n", h, A, Ag);
    CHECK(A <= 1050 + 1e-9 && A >= 1050 - 4 * h * h);
    CHECK(Ag <= 1050 + 1e-9 && Ag >= 1050 - 4 * h * h);
    double bad_plane = 0, bad_par = 0, y_lo = INFINITY, y_hi = -INFINITY, A_par = 0;
    for (int64_t t = 0; t < s.ntris; t++) {
        int64_t a = s.tri_pair[2 * t], b = s.tri_pair[2 * t + 1];
        for (int k = 0; k < 3; k++) {
            const double *x = s.xyz + 3 * s.tris[3 * t + k];
            if (a == (Fo < Fi ? Fo : Fi) && b == (Fo < Fi ? Fi : Fo))
                bad_plane = fmax(bad_plane, fmax(fabs(x[0] - 5), fabs(s.radius[s.tris[3 * t + k]] - 5)));
            if (a == Fo && b == E) {
                bad_par = fmax(bad_par, fabs(x[0] - (100 + (x[1] - 10) * (x[1] - 10)) / 20));
                bad_par = fmax(bad_par, fabs(s.radius[s.tris[3 * t + k]] - x[0]));
                y_lo = fmin(y_lo, x[1]);
                y_hi = fmax(y_hi, x[1]);
            }
        }
        if (a == Fo && b == E)
            A_par += tri_area(&s, t);
    }
    printf("L-bracket: (Fo,E) y in [%.12f, %.12f] (rho* %.12f, 10), area %.4f\n", y_lo, y_hi, rho,
           A_par);
    CHECK(bad_plane <= 1e-9);
    CHECK(bad_par <= 1e-9);
    CHECK(y_lo >= rho - 1e-9 && y_lo <= rho + 1e-9 && y_hi <= 10 + 1e-9 && y_hi >= 10 - 1e-9);
    /* Its area: the integral of the z extent 40 - 2x (z in [x, 40 - x]) along the
     * parabola from y = rho* to 10 (midpoint rule).  Flat triangles inscribed in the
     * curved sheet, and the 4 corners, may lose a little. */
    double A_ref = 0;
    for (int i = 0; i < 100000; i++) {
        double ya = rho + (10 - rho) * i / 1e5, yb = rho + (10 - rho) * (i + 1) / 1e5;
        double xa = (100 + (ya - 10) * (ya - 10)) / 20, xb = (100 + (yb - 10) * (yb - 10)) / 20;
        A_ref += (40 - (xa + xb)) * hypot(xb - xa, yb - ya);
    }
    printf("L-bracket: (Fo,E) reference area %.4f\n", A_ref);
    CHECK(A_par <= A_ref + 1e-6 && A_par >= A_ref - 0.01 * A_ref);
    double dv, dr, ds;
    equidistance(&el, &s, &dv, &dr, &ds);
    printf("L-bracket: worst |da-db| %.3g, |r-da| %.3g, seam spread %.3g\n", dv, dr, ds);
    CHECK(dv <= 1e-9 * el.diag);
    CHECK(dr <= 1e-9 * el.diag);
    CHECK(ds <= 1e-9 * el.diag);
    /* Seams: SMOOTH {Fo, Fi, E} on y = 10; BRANCH {Fo, Go, E} on x = y = rho*. */
    int smooth = 0, branch = 0, bad = 0;
    for (int64_t g = 0; g < s.nsegs; g++) {
        const int64_t *e3 = s.seg_elems + 3 * g;
        const double *p = s.xyz + 3 * s.seg_verts[2 * g], *q = s.xyz + 3 * s.seg_verts[2 * g + 1];
        int64_t lo = Fo < Fi ? Fo : Fi, hi = Fo < Fi ? Fi : Fo;
        if (e3[0] == lo && e3[1] == hi && e3[2] == E) {
            smooth++;
            bad += s.seg_kind[g] != MFG_MEDIAL_SMOOTH || fabs(p[1] - 10) > 1e-9 || fabs(q[1] - 10) > 1e-9;
        }
        lo = Fo < Go ? Fo : Go;
        hi = Fo < Go ? Go : Fo;
        if (e3[0] == lo && e3[1] == hi && e3[2] == E) {
            branch++;
            bad += s.seg_kind[g] != MFG_MEDIAL_BRANCH || fabs(p[0] - rho) > 1e-9 ||
                   fabs(p[1] - rho) > 1e-9 || fabs(q[0] - rho) > 1e-9 || fabs(q[1] - rho) > 1e-9;
        }
    }
    printf("L-bracket: %d SMOOTH (Fo,Fi,E) segments, %d BRANCH (Fo,Go,E)\n", smooth, branch);
    CHECK(smooth * h >= 30 - 2 * h);
    CHECK(branch * h >= 40 - 2 * rho - 2 * h);
    CHECK_EQ_INT(bad, 0);
    /* Every sheet vertex is medial: the brute-force D equals its radius, and at least 2
     * elements touch its ball. */
    int64_t *T = malloc((size_t)el.nelements * sizeof *T);
    int notmedial = 0;
    for (int64_t v = 0; v < s.nverts; v++) {
        double D;
        int64_t n = md_nearest_set_brute(&el, s.xyz + 3 * v, 1e-9 * el.diag, T, &D);
        notmedial += n < 2 || fabs(D - s.radius[v]) > 1e-9 * el.diag;
    }
    free(T);
    CHECK_EQ_INT(notmedial, 0);
    int64_t n1, n2, nmore, open, lost;
    manifold(&s, Fo < Fi ? Fo : Fi, Fo < Fi ? Fi : Fo, 0.01 * h, &n1, &n2, &nmore, &open, &lost);
    printf("L-bracket (Fo,Fi) mesh: %lld boundary, %lld interior, %lld over-used, %lld open, %lld lost\n",
           (long long)n1, (long long)n2, (long long)nmore, (long long)open, (long long)lost);
    CHECK_EQ_INT(nmore, 0);
    CHECK_EQ_INT(open, 0);
    CHECK_EQ_INT(lost, 0);
    manifold(&s, Fo, E, 0.01 * h, &n1, &n2, &nmore, &open, &lost);
    printf("L-bracket (Fo,E) mesh: %lld boundary, %lld interior, %lld over-used, %lld open, %lld lost\n",
           (long long)n1, (long long)n2, (long long)nmore, (long long)open, (long long)lost);
    CHECK_EQ_INT(nmore, 0);
    md_soup_free(&s);
    brute_free(&lv);
    md_bvh_free(bvh);
    md_elements_free(&el);
}

/* ---- the cube of side 40, full mode: 12 triangles from the edges to the centre -------- */

static void test_cube_full(double h)
{
    tmesh m;
    box(&m, 40, 40, 40);
    md_elements el;
    CHECK_EQ_INT(md_elements_build(m.xyz, m.nv, m.tri, m.nt, h, &el), MFG_OK);
    md_leaves lv;
    brute_leaves(&el, h, 1, &lv);
    md_bvh *bvh = NULL;
    CHECK_EQ_INT(md_bvh_build(&el, &bvh), MFG_OK);
    md_soup s = extract(&el, bvh, &lv, h, "cube (full)");
    double want = 40 * 20 * sqrt(2.0) / 2, total = 0, worst = 0;
    int sheets = 0;
    for (int64_t a = 0; a < el.nfaces; a++)
        for (int64_t b = a + 1; b < el.nfaces; b++) {
            double A = pair_area(&s, a, b);
            int adjacent = md_adjacent(&el, a, b);
            total += A;
            if (!adjacent) {
                CHECK(A <= 1e-9);
                continue;
            }
            sheets++;
            worst = fmax(worst, fabs(A - want));
            CHECK(A <= want + 1e-9 && A >= want - 2 * h * h);
            int64_t n1, n2, nmore, open, lost;
            manifold(&s, a, b, 0.01 * h, &n1, &n2, &nmore, &open, &lost);
            CHECK_EQ_INT(nmore, 0);
            CHECK_EQ_INT(lost, 0);
        }
    printf("cube h=%g: %d sheets of %.4f, worst error %.4g, total %.4f (%.4f)\n", h, sheets, want,
           worst, total, 12 * want);
    CHECK_EQ_INT(sheets, 12);
    double other = 0;
    for (int64_t t = 0; t < s.ntris; t++)
        if (s.tri_pair[2 * t + 1] >= el.nfaces)
            other += tri_area(&s, t);
    CHECK(other <= 1e-9);
    double dv, dr, ds;
    equidistance(&el, &s, &dv, &dr, &ds);
    CHECK(dv <= 1e-9 * el.diag);
    CHECK(dr <= 1e-9 * el.diag);
    CHECK(ds <= 1e-9 * el.diag);
    md_soup_free(&s);
    brute_free(&lv);
    md_bvh_free(bvh);
    md_elements_free(&el);
}

/* The full L-bracket at tolerance 1 % L on the octree: every vertex of every triangle lies
 * on its pair's bisector, at its radius, within 1e-9 L, and every seam point is equidistant
 * to its 3 elements.  A boundary point whose tet face the bisector leaves through B-C (the
 * cone {z1, E} by the convex corner (10, 10, 40), sharp at r ~ 0.006) once fell back on
 * the chord between the face's two vertices: 0.41 off the cone, and the assembly dropped
 * its triangles, a notch about one leaf wide. */
static void test_l_bracket_full_on_bisector(void)
{
    tmesh m;
    ms_l_bracket(&m);
    double tol = 0.01 * sqrt(50 * 50 + 50 * 50 + 40 * 40);
    md_elements el;
    CHECK_EQ_INT(md_elements_build(m.xyz, m.nv, m.tri, m.nt, tol, &el), MFG_OK);
    md_bvh *bvh = NULL;
    CHECK_EQ_INT(md_bvh_build(&el, &bvh), MFG_OK);
    md_leaves lv;
    CHECK_EQ_INT(md_octree_build(&el, bvh, tol, 1, 2, &lv), MFG_OK);
    md_soup s = extract(&el, bvh, &lv, tol, "L-bracket full 1 % L/octree");
    double dv, dr, ds;
    equidistance(&el, &s, &dv, &dr, &ds);
    printf("L-bracket full 1 %% L: worst |d_a - d_b| %.3g, |r - d_a| %.3g, seam %.3g (L = %.4f)\n",
           dv, dr, ds, el.diag);
    CHECK(dv <= 1e-9 * el.diag);
    CHECK(dr <= 1e-9 * el.diag);
    CHECK(ds <= 1e-9 * el.diag);
    md_soup_free(&s);
    md_leaves_free(&lv);
    md_bvh_free(bvh);
    md_elements_free(&el);
}

/* ---- coarse plane leaves (design 3.4, medial/sheet_coarse.c) ------------------------------ */

/* A sheet edge as the coordinates of its ends (smaller first) and its pair. */
typedef struct xedge {
    int64_t a, b;
    double p[3], q[3];
} xedge;

static int cmp_xedge(const void *pa, const void *pb)
{
    const xedge *x = pa, *y = pb;
    if (x->a != y->a)
        return x->a < y->a ? -1 : 1;
    if (x->b != y->b)
        return x->b < y->b ? -1 : 1;
    int c = memcmp(x->p, y->p, sizeof x->p);
    return c ? c : memcmp(x->q, y->q, sizeof x->q);
}

static void put_xedge(xedge *e, int64_t a, int64_t b, const double *p, const double *q)
{
    int swap = memcmp(p, q, 3 * sizeof *p) > 0; /* any fixed order of the bits will do */
    e->a = a;
    e->b = b;
    memcpy(e->p, swap ? q : p, sizeof e->p);
    memcpy(e->q, swap ? p : q, sizeof e->q);
}

/* The edges of the soup's triangles that lie in exactly one triangle of their pair (the
 * sheets' boundaries, by coordinates), sorted; their count. */
static int64_t open_edges(const md_soup *s, xedge **out)
{
    xedge *E = malloc((size_t)(3 * s->ntris + 1) * sizeof *E);
    for (int64_t t = 0; t < s->ntris; t++)
        for (int k = 0; k < 3; k++)
            put_xedge(E + 3 * t + k, s->tri_pair[2 * t], s->tri_pair[2 * t + 1],
                      s->xyz + 3 * s->tris[3 * t + k], s->xyz + 3 * s->tris[3 * t + (k + 1) % 3]);
    qsort(E, (size_t)(3 * s->ntris), sizeof *E, cmp_xedge);
    int64_t n = 0;
    for (int64_t i = 0; i < 3 * s->ntris;) {
        int64_t j = i;
        while (j < 3 * s->ntris && !cmp_xedge(E + j, E + i))
            j++;
        if (j - i == 1)
            E[n++] = E[i];
        i = j;
    }
    *out = E;
    return n;
}

/* The seam segments by coordinates (with their pair), sorted. */
static int64_t seam_edges(const md_soup *s, xedge **out)
{
    xedge *E = malloc((size_t)(s->nsegs + 1) * sizeof *E);
    for (int64_t g = 0; g < s->nsegs; g++)
        put_xedge(E + g, s->seg_pair[2 * g], s->seg_pair[2 * g + 1],
                  s->xyz + 3 * s->seg_verts[2 * g], s->xyz + 3 * s->seg_verts[2 * g + 1]);
    qsort(E, (size_t)s->nsegs, sizeof *E, cmp_xedge);
    *out = E;
    return s->nsegs;
}

/* Coarse plane leaves against the uniform lattice on the same solid: the octree with
 * coarse leaves keeps fewer leaves, and its soup has, bit for bit, the same seam segments
 * as the soup of the leaves of side h alone, and no open edge (an edge in one triangle of
 * its pair) that is not a seam segment or open there too: each coarse leaf's fan meets its
 * neighbours along the same fine roots (no crack; no overlap: an edge in three triangles
 * would show), and nothing is trimmed inside it.  Every pair's area agrees to rounding, every vertex lies
 * on its pair's bisector at its radius, the welded sheets are manifold with one
 * orientation (manifold()). */
static void test_coarse_vs_uniform(const tmesh *m, double tol, int full, const char *name)
{
    md_elements el;
    CHECK_EQ_INT(md_elements_build(m->xyz, m->nv, m->tri, m->nt, tol, &el), MFG_OK);
    md_bvh *bvh = NULL;
    CHECK_EQ_INT(md_bvh_build(&el, &bvh), MFG_OK);
    md_leaves lu, lc;
    CHECK_EQ_INT(md_octree_build(&el, bvh, tol, full, 2, &lu), MFG_OK);
    CHECK_EQ_INT(md_octree_build_p(&el, bvh, tol, full, 1, 2, &lc, NULL), MFG_OK);
    int64_t ncoarse = 0, covered = 0;
    for (int64_t i = 0; i < lc.nleaves; i++)
        if (lc.leaf[i].level > 0) {
            ncoarse++;
            covered += (int64_t)1 << (3 * lc.leaf[i].level);
            CHECK(lc.leaf[i].nC == 2 && lc.leaf[i].nP == 1 && lc.leaf[i].nT == 2);
            CHECK(lc.P[lc.leaf[i].P_off] < el.nfaces && lc.P[lc.leaf[i].P_off + 1] < el.nfaces);
        }
    md_soup su = extract(&el, bvh, &lu, tol, name);
    md_soup sc = extract(&el, bvh, &lc, tol, name);
    xedge *ou, *oc, *gu, *gc;
    int64_t nou = open_edges(&su, &ou), noc = open_edges(&sc, &oc);
    int64_t ngu = seam_edges(&su, &gu), ngc = seam_edges(&sc, &gc);
    int same_seams = ngu == ngc && !memcmp(gu, gc, (size_t)ngu * sizeof *gu);
    /* The coarse soup's open edges: each a seam segment or open in the uniform soup too
     * (whose triangles below 1e-6 h^2 may leave pinholes where a coarse fan has none). */
    int64_t new_open = 0;
    for (int64_t i = 0; i < noc; i++)
        new_open += !bsearch(oc + i, ou, (size_t)nou, sizeof *ou, cmp_xedge) &&
                    !bsearch(oc + i, gc, (size_t)ngc, sizeof *gc, cmp_xedge);
    int same_open = nou == noc && !memcmp(ou, oc, (size_t)nou * sizeof *ou);
    printf("%s: %lld leaves of side h -> %lld leaves (%lld coarse, standing for %lld of side h); "
           "%lld -> %lld triangles; open edges %lld / %lld (%s, %lld new), seam segments %lld / "
           "%lld (%s)\n",
           name, (long long)lu.nleaves, (long long)lc.nleaves, (long long)ncoarse,
           (long long)covered, (long long)su.ntris, (long long)sc.ntris, (long long)nou,
           (long long)noc, same_open ? "same" : "differ", (long long)new_open, (long long)ngu,
           (long long)ngc,
           same_seams ? "same" : "DIFFER");
    CHECK(ncoarse > 0);
    CHECK(lc.nleaves < lu.nleaves);
    CHECK_EQ_INT(new_open, 0);
    CHECK(same_seams);
    double dv, dr, ds;
    equidistance(&el, &sc, &dv, &dr, &ds);
    CHECK(dv <= 1e-9 * el.diag);
    CHECK(dr <= 1e-9 * el.diag);
    CHECK(ds <= 1e-9 * el.diag);
    /* per pair of a coarse leaf: the area and the manifold counts */
    for (int64_t i = 0; i < lc.nleaves; i++) {
        if (lc.leaf[i].level == 0)
            continue;
        int64_t a = lc.P[lc.leaf[i].P_off], b = lc.P[lc.leaf[i].P_off + 1], seen = 0;
        for (int64_t j = 0; j < i && !seen; j++)
            seen = lc.leaf[j].level > 0 && lc.P[lc.leaf[j].P_off] == a &&
                   lc.P[lc.leaf[j].P_off + 1] == b;
        if (seen)
            continue;
        double au = pair_area(&su, a, b), ac = pair_area(&sc, a, b);
        CHECK(fabs(au - ac) <= 1e-6 * au); /* the uniform soup's pinholes: ~1e-6 h^2 each */
        int64_t n1, n2, nmore, open, lost;
        manifold(&sc, a, b, 1e-6 * lc.lat.h, &n1, &n2, &nmore, &open, &lost);
        CHECK_EQ_INT(nmore, 0);
    }
    free(ou);
    free(oc);
    free(gu);
    free(gc);
    md_soup_free(&su);
    md_soup_free(&sc);
    md_leaves_free(&lu);
    md_leaves_free(&lc);
    md_bvh_free(bvh);
    md_elements_free(&el);
}

/* The solid turned about an oblique axis and moved: bisector planes off the lattice. */
static void turned(tmesh *m)
{
    double ax[3] = {0.36, -0.48, 0.8}, c = cos(0.7), s = sin(0.7);
    for (int64_t i = 0; i < m->nv; i++) {
        double *p = m->xyz + 3 * i, q[3];
        double d = ax[0] * p[0] + ax[1] * p[1] + ax[2] * p[2];
        double x[3] = {ax[1] * p[2] - ax[2] * p[1], ax[2] * p[0] - ax[0] * p[2],
                       ax[0] * p[1] - ax[1] * p[0]};
        for (int k = 0; k < 3; k++)
            q[k] = p[k] * c + x[k] * s + ax[k] * d * (1 - c);
        p[0] = q[0] + 3.25;
        p[1] = q[1] - 17.5;
        p[2] = q[2] + 0.125;
    }
}

/* ---- on the octree's leaves (medial/octree.c) -------------------------------------------- */

/* The soup from the octree's leaves (with the BVH) equals, bit for bit, the soup from
 * brute-force leaves on the same lattice (every element a candidate, every pair in every
 * leaf): the octree drops no leaf or pair that holds a kept triangle, its candidate sets
 * decide every trim the same way, and the radii (min over C) come out the same. */
/* Inside the L-bracket (closed, to 1e-9): the notch x, y > 10 is outside. */
static int in_l_bracket(const double *x)
{
    double e = 1e-9;
    return x[0] >= -e && x[1] >= -e && x[2] >= -e && x[0] <= 50 + e && x[1] <= 50 + e &&
           x[2] <= 40 + e && (x[0] <= 10 + e || x[1] <= 10 + e);
}

static void test_octree_vs_brute(const tmesh *m, double tol, int full, const char *name,
                                 int (*inside)(const double *))
{
    md_elements el;
    CHECK_EQ_INT(md_elements_build(m->xyz, m->nv, m->tri, m->nt, tol, &el), MFG_OK);
    md_bvh *bvh = NULL;
    CHECK_EQ_INT(md_bvh_build(&el, &bvh), MFG_OK);
    md_leaves lv, bl;
    double t0 = now();
    CHECK_EQ_INT(md_octree_build(&el, bvh, tol, full, 2, &lv), MFG_OK);
    printf("%s: octree %.3f s, %lld leaves, h = %g\n", name, now() - t0, (long long)lv.nleaves,
           lv.lat.h);
    md_soup so = extract(&el, bvh, &lv, tol, name);
    brute_leaves_on(&el, &lv.lat, full, &bl);
    md_soup sb;
    CHECK_EQ_INT(md_sheets_extract(&el, bvh, &bl, tol, 2, &sb), MFG_OK);
    int same = same_soup(&so, &sb);
    printf("%s: octree soup %s the brute-force soup (%lld / %lld triangles)\n", name,
           same ? "equals" : "DIFFERS FROM", (long long)so.ntris, (long long)sb.ntris);
    CHECK(same);
    /* Nothing outside the solid, even from brute-force leaves that reach into a notch. */
    int outside = 0;
    for (int64_t v = 0; inside && v < so.nverts; v++)
        outside += !inside(so.xyz + 3 * v);
    for (int64_t v = 0; inside && v < sb.nverts; v++)
        outside += !inside(sb.xyz + 3 * v);
    CHECK_EQ_INT(outside, 0);
    md_soup_free(&so);
    md_soup_free(&sb);
    brute_free(&bl);
    md_leaves_free(&lv);
    md_bvh_free(bvh);
    md_elements_free(&el);
}

/* The 48-gon disc (circumradius 50, thickness 4) on the octree: its one major sheet
 * {top, bottom} is the 48-gon z = 2 of apothem 50 cos(pi/48) - 2, area 7216.3. */
static void test_disc(double tol)
{
    double P[48][2];
    for (int i = 0; i < 48; i++) {
        P[i][0] = 50 * cos(2 * M_PI * i / 48);
        P[i][1] = 50 * sin(2 * M_PI * i / 48);
    }
    tmesh m;
    ms_prism(&m, (const double(*)[2])P, 48, 4);
    md_elements el;
    CHECK_EQ_INT(md_elements_build(m.xyz, m.nv, m.tri, m.nt, tol, &el), MFG_OK);
    md_bvh *bvh = NULL;
    CHECK_EQ_INT(md_bvh_build(&el, &bvh), MFG_OK);
    md_leaves lv;
    double t0 = now();
    CHECK_EQ_INT(md_octree_build(&el, bvh, tol, 0, 2, &lv), MFG_OK);
    printf("disc48: octree %.3f s, %lld leaves, h = %g\n", now() - t0, (long long)lv.nleaves, lv.lat.h);
    md_soup s = extract(&el, bvh, &lv, tol, "disc48");
    int64_t top = face_with(&el, 0, 0, 1, 4), bot = face_with(&el, 0, 0, -1, 0);
    int64_t a = top < bot ? top : bot, b = top < bot ? bot : top;
    double ap = 50 * cos(M_PI / 48) - 2, want = 48 * ap * ap * tan(M_PI / 48);
    double A = pair_area(&s, a, b), other = 0, bad = 0;
    for (int64_t t = 0; t < s.ntris; t++)
        if (s.tri_pair[2 * t] != a || s.tri_pair[2 * t + 1] != b)
            other += tri_area(&s, t);
    for (int64_t v = 0; v < s.nverts; v++)
        bad = fmax(bad, fmax(fabs(s.xyz[3 * v + 2] - 2), fabs(s.radius[v] - 2)));
    printf("disc48: sheet area %.6f (%.6f), other pairs %.3g, worst |z-2|,|r-2| %.3g\n", A, want,
           other, bad);
    CHECK(fabs(A - want) <= 1e-6 * want);
    CHECK(other <= 1e-9);
    CHECK(bad <= 1e-9);
    int64_t n1, n2, nmore, open, lost;
    manifold(&s, a, b, 0.01 * lv.lat.h, &n1, &n2, &nmore, &open, &lost);
    CHECK_EQ_INT(nmore, 0);
    CHECK_EQ_INT(open, 0);
    CHECK_EQ_INT(lost, 0);
    double dv, dr, ds;
    equidistance(&el, &s, &dv, &dr, &ds);
    CHECK(dv <= 1e-9 * el.diag && dr <= 1e-9 * el.diag && ds <= 1e-9 * el.diag);
    md_soup_free(&s);
    md_leaves_free(&lv);
    md_bvh_free(bvh);
    md_elements_free(&el);
}

/* The full T-section at tol 1 % of L (N6's oracle setting) on the octree: every side of
 * the soup's triangles that lies in one triangle only, away from the solid's boundary
 * (radius > tol), is a seam segment, at any length.  Its sheet {z1, E} (E the reflex edge
 * (35, 50, z)) passes within rounding of the lattice point (33.94, 54.018, 35.8445): the
 * roots crowd there and the triangles under 1e-6 h^2 that were dropped left a pinhole of
 * sides ~ 0.001 (6 open sides). */
static void test_t_section_closed(void)
{
    tmesh m;
    t_section(&m);
    double tol = 0.01 * sqrt(60 * 60 + 60 * 60 + 40 * 40);
    md_elements el;
    CHECK_EQ_INT(md_elements_build(m.xyz, m.nv, m.tri, m.nt, tol, &el), MFG_OK);
    md_bvh *bvh = NULL;
    CHECK_EQ_INT(md_bvh_build(&el, &bvh), MFG_OK);
    md_leaves lv;
    CHECK_EQ_INT(md_octree_build(&el, bvh, tol, 1, 2, &lv), MFG_OK);
    md_soup s = extract(&el, bvh, &lv, tol, "T-section full/octree");
    edge_rec *E = malloc((size_t)(3 * s.ntris + s.nsegs + 1) * sizeof *E);
    int64_t n = 0, open = 0, inner = 0;
    for (int64_t t = 0; t < s.ntris; t++)
        for (int k = 0; k < 3; k++) {
            int64_t u = s.tris[3 * t + k], v = s.tris[3 * t + (k + 1) % 3];
            E[n].u = u < v ? u : v;
            E[n].v = u < v ? v : u;
            E[n].src = 0;
            E[n].fwd = 0;
            n++;
        }
    for (int64_t g = 0; g < s.nsegs; g++) {
        int64_t u = s.seg_verts[2 * g], v = s.seg_verts[2 * g + 1];
        E[n].u = u < v ? u : v;
        E[n].v = u < v ? v : u;
        E[n].src = 1;
        E[n].fwd = 0;
        n++;
    }
    qsort(E, (size_t)n, sizeof *E, cmp_edge);
    for (int64_t i = 0; i < n;) {
        int64_t j = i, nt = 0, ns = 0;
        for (; j < n && E[j].u == E[i].u && E[j].v == E[i].v; j++) {
            nt += E[j].src == 0;
            ns += E[j].src == 1;
        }
        if (nt == 1 && fmax(s.radius[E[i].u], s.radius[E[i].v]) > tol) {
            inner++;
            if (ns == 0) {
                const double *p = s.xyz + 3 * E[i].u;
                if (!open)
                    printf("T-section: open side off every seam at (%.4f %.4f %.4f)\n", p[0], p[1], p[2]);
                open++;
            }
        }
        i = j;
    }
    printf("T-section full: %lld inner open sides, %lld of them not seam segments\n",
           (long long)inner, (long long)open);
    CHECK(inner > 0); /* the seams bound the sheets */
    CHECK_EQ_INT(open, 0);
    free(E);
    md_soup_free(&s);
    md_leaves_free(&lv);
    md_bvh_free(bvh);
    md_elements_free(&el);
}

/* Timings at the design's bench tolerance (0.5 % of L), octree + extraction: printed only. */
static void time_l_bracket(double tol, int threads)
{
    tmesh m;
    ms_l_bracket(&m);
    md_elements el;
    CHECK_EQ_INT(md_elements_build(m.xyz, m.nv, m.tri, m.nt, tol, &el), MFG_OK);
    md_bvh *bvh = NULL;
    CHECK_EQ_INT(md_bvh_build(&el, &bvh), MFG_OK);
    md_leaves lv;
    double t0 = now();
    CHECK_EQ_INT(md_octree_build(&el, bvh, tol, 0, threads, &lv), MFG_OK);
    double t1 = now();
    md_soup s;
    CHECK_EQ_INT(md_sheets_extract(&el, bvh, &lv, tol, threads, &s), MFG_OK);
    double t2 = now();
    int64_t np = 0;
    for (int64_t i = 0; i < lv.nleaves; i++)
        np += lv.leaf[i].nP;
    printf("L-bracket tol %g, %d threads: %lld leaves (%lld leaf pairs), octree %.3f s, sheets %.3f s: "
           "%lld verts, %lld tris, %lld segs\n", tol, threads, (long long)lv.nleaves, (long long)np,
           t1 - t0, t2 - t1, (long long)s.nverts, (long long)s.ntris, (long long)s.nsegs);
    md_soup_free(&s);
    md_leaves_free(&lv);
    md_bvh_free(bvh);
    md_elements_free(&el);
}

#ifdef MFG_SHEETS_ALLOC_FAIL
#include "alloc_shim.h"

/* md_sheets_extract with each allocation failing in turn (one thread: the failing
 * allocator is single-threaded): MFG_ERR_NOMEM, the output zeroed, no block leaked; or,
 * when libc absorbs the failure (qsort), the same soup. */
static void test_alloc_fail(void)
{
    tmesh m;
    box(&m, 100, 60, 20);
    md_elements el;
    CHECK_EQ_INT(md_elements_build(m.xyz, m.nv, m.tri, m.nt, 8, &el), MFG_OK);
    md_leaves lv;
    brute_leaves(&el, 8, 1, &lv);
    md_soup ref;
    CHECK_EQ_INT(md_sheets_extract(&el, NULL, &lv, 8, 1, &ref), MFG_OK);
    CHECK(ref.ntris > 0 && ref.nsegs > 0);
    int done = 0;
    long n, absorbed = 0;
    for (n = 1; n < 100000 && !done; n++) {
        md_soup s;
        memset(&s, 0x5a, sizeof s);
        alloc_shim_arm(n);
        mfg_status st = md_sheets_extract(&el, NULL, &lv, 8, 1, &s);
        int same = st == MFG_OK && same_soup(&s, &ref);
        if (st == MFG_OK)
            md_soup_free(&s);
        alloc_shim_stats a = alloc_shim_disarm();
        CHECK_EQ_INT(a.net, 0);
        if (a.failed == 0) {
            done = 1;
            CHECK_EQ_INT(st, MFG_OK);
            continue;
        }
        if (st == MFG_OK) {
            absorbed++;
            CHECK(same);
            continue;
        }
        CHECK_EQ_INT(st, MFG_ERR_NOMEM);
        CHECK(s.nverts == 0 && s.ntris == 0 && s.nsegs == 0 && s.xyz == NULL && s.tris == NULL &&
              s.seg_pair == NULL);
    }
    CHECK(done);
    printf("allocations failed in turn: %ld (%ld absorbed by libc)\n", n - 2, absorbed);
    md_soup_free(&ref);
    brute_free(&lv);
    md_elements_free(&el);
}

#endif

/* "alloc" (the allocation-failure build only): md_sheets_extract under failing allocations;
 * otherwise the analytic solids. */
int main(int argc, char **argv)
{
#ifdef MFG_SHEETS_ALLOC_FAIL
    if (argc > 1 && !strcmp(argv[1], "alloc")) {
        test_alloc_fail();
        return mfg_test_report("medial_sheets_alloc");
    }
#endif
    if (argc > 1 && !strcmp(argv[1], "time")) { /* not a ctest test: timings only */
        time_l_bracket(0.4, 1);
        time_l_bracket(0.4, 2);
        return mfg_test_report("medial_sheets_time");
    }
    int all = argc < 2, brute = all || !strcmp(argv[1], "brute");
    int octree = all || !strcmp(argv[1], "octree");
    if (brute) {
        test_cuboid(2.5);
        test_cuboid(3.7);
        test_l_bracket(2.0);
        test_cube_full(4.0);
    }
    if (octree) {
        tmesh m;
        box(&m, 100, 60, 20);
        test_octree_vs_brute(&m, 2.5, 0, "cuboid/octree", NULL);
        ms_l_bracket(&m);
        test_octree_vs_brute(&m, 2.0, 0, "L-bracket/octree", in_l_bracket);
        test_octree_vs_brute(&m, 4.0, 1, "L-bracket full/octree", in_l_bracket);
        box(&m, 40, 40, 40);
        test_octree_vs_brute(&m, 4.0, 1, "cube full/octree", NULL);
        test_disc(1.0);
        test_t_section_closed();
        test_l_bracket_full_on_bisector();
    }
    if (all || !strcmp(argv[1], "coarse")) {
        tmesh m;
        box(&m, 100, 60, 20);
        test_coarse_vs_uniform(&m, 2.5, 0, "cuboid coarse/uniform");
        test_coarse_vs_uniform(&m, 1.0, 1, "cuboid full coarse/uniform");
        /* turned: bisector planes off the lattice, passing near lattice points (a coarse
         * leaf's corner cut off within rounding: the fan collapses as a root triangle) */
        for (int r = 0; r < 4; r++) {
            turned(&m);
            test_coarse_vs_uniform(&m, 1.5 - 0.25 * r, 0, "turned cuboid coarse/uniform");
        }
        box(&m, 2, 1, 0.5);
        test_coarse_vs_uniform(&m, 2.29e-3 * 2.5, 0, "box 2 x 1 x 0.5 at L/400 coarse/uniform");
        ms_l_bracket(&m);
        turned(&m);
        test_coarse_vs_uniform(&m, 1.2, 0, "turned L-bracket coarse/uniform");
        ms_l_bracket(&m);
        test_coarse_vs_uniform(&m, 1.0, 0, "L-bracket coarse/uniform");
        test_coarse_vs_uniform(&m, 2.0, 1, "L-bracket full coarse/uniform");
    }
    return mfg_test_report("medial_sheets");
}
