/* SPDX-License-Identifier: LGPL-2.1-or-later */
/* test_medial_simplify.c - medial sheets made coarse within the tolerance
 * (medial/simplify.c, md_sheet_simplify) on the sheets of the octree's leaves
 * (md_octree_build, md_bvh, md_sheets_extract): the cuboid's mid-plane, the L-bracket's
 * mid-planes and parabolic cylinder, the 48-gon disc.  References: the input sheet (its
 * area, boundary and vertices), the analytic bisectors, and an exact count of the
 * output's edges (manifold, one orientation). */
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

/* A prism: the simple polygon P (n corners, counter-clockwise) extruded over z in [0, H];
 * caps triangulated by the given triangles T (nT of them, corner indices). */
static void prism(tmesh *m, const double (*P)[2], int n, double H, const int (*T)[3], int nT)
{
    memset(m, 0, sizeof *m);
    int64_t b[128], t[128];
    for (int i = 0; i < n; i++) {
        b[i] = ms_vtx(m, P[i][0], P[i][1], 0);
        t[i] = ms_vtx(m, P[i][0], P[i][1], H);
    }
    for (int i = 0; i < nT; i++) {
        ms_tri(m, t[T[i][0]], t[T[i][1]], t[T[i][2]]);
        ms_tri(m, b[T[i][0]], b[T[i][2]], b[T[i][1]]);
    }
    for (int i = 0; i < n; i++) {
        int j = (i + 1) % n;
        ms_tri(m, b[i], b[j], t[j]);
        ms_tri(m, b[i], t[j], t[i]);
    }
}

static void convex_prism(tmesh *m, const double (*P)[2], int n, double H)
{
    int T[128][3];
    for (int i = 1; i + 1 < n; i++) {
        T[i - 1][0] = 0;
        T[i - 1][1] = i;
        T[i - 1][2] = i + 1;
    }
    prism(m, P, n, H, (const int(*)[3])T, n - 2);
}

/* The edge element running from a to b (this direction only), or -1. */
static int64_t edge_from_to(const md_elements *el, const double *a, const double *b)
{
    for (int64_t i = 0; i < el->nedges; i++) {
        const double *s = el->edge_seg + 6 * i;
        if (!memcmp(s, a, 3 * sizeof *a) && !memcmp(s + 3, b, 3 * sizeof *b))
            return el->nfaces + i;
    }
    return -1;
}

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

/* ---- a sheet: one pair's triangles of the soup, vertices compacted ---------------------- */

typedef struct sheet {
    int64_t a, b, nv, nt;
    double *xyz, *radius;
    int64_t *tris;
    int64_t *label; /* seam labels (md_soup_seam_labels) */
} sheet;

static sheet sheet_of(const md_soup *s, int64_t a, int64_t b)
{
    sheet S;
    memset(&S, 0, sizeof S);
    S.a = a < b ? a : b;
    S.b = a < b ? b : a;
    int64_t *map = malloc((size_t)(s->nverts + 1) * sizeof *map);
    for (int64_t v = 0; v < s->nverts; v++)
        map[v] = -1;
    S.tris = malloc((size_t)(3 * s->ntris + 1) * sizeof *S.tris);
    for (int64_t t = 0; t < s->ntris; t++)
        if (s->tri_pair[2 * t] == S.a && s->tri_pair[2 * t + 1] == S.b) {
            for (int c = 0; c < 3; c++)
                map[s->tris[3 * t + c]] = 0;
            S.nt++;
        }
    for (int64_t v = 0; v < s->nverts; v++)
        if (map[v] >= 0)
            map[v] = S.nv++;
    S.xyz = malloc((size_t)(3 * S.nv + 1) * sizeof *S.xyz);
    S.radius = malloc((size_t)(S.nv + 1) * sizeof *S.radius);
    S.label = malloc((size_t)(S.nv + 1) * sizeof *S.label);
    int64_t *lab = malloc((size_t)(s->nverts + 1) * sizeof *lab);
    md_soup_seam_labels(s, lab);
    for (int64_t v = 0; v < s->nverts; v++)
        if (map[v] >= 0) {
            memcpy(S.xyz + 3 * map[v], s->xyz + 3 * v, 3 * sizeof *S.xyz);
            S.radius[map[v]] = s->radius[v];
            S.label[map[v]] = lab[v];
        }
    free(lab);
    int64_t k = 0;
    for (int64_t t = 0; t < s->ntris; t++)
        if (s->tri_pair[2 * t] == S.a && s->tri_pair[2 * t + 1] == S.b) {
            for (int c = 0; c < 3; c++)
                S.tris[3 * k + c] = map[s->tris[3 * t + c]];
            k++;
        }
    free(map);
    return S;
}

static sheet sheet_copy(const sheet *S)
{
    sheet C = *S;
    C.xyz = malloc((size_t)(3 * S->nv + 1) * sizeof *C.xyz);
    C.radius = malloc((size_t)(S->nv + 1) * sizeof *C.radius);
    C.tris = malloc((size_t)(3 * S->nt + 1) * sizeof *C.tris);
    memcpy(C.xyz, S->xyz, (size_t)(3 * S->nv) * sizeof *C.xyz);
    memcpy(C.radius, S->radius, (size_t)S->nv * sizeof *C.radius);
    memcpy(C.tris, S->tris, (size_t)(3 * S->nt) * sizeof *C.tris);
    C.label = NULL; /* read from the input */
    return C;
}

static void sheet_free(sheet *S)
{
    free(S->xyz);
    free(S->radius);
    free(S->tris);
    free(S->label);
}

static void tri_normal(const sheet *S, int64_t t, double n[3])
{
    const double *p = S->xyz + 3 * S->tris[3 * t], *q = S->xyz + 3 * S->tris[3 * t + 1],
                 *r = S->xyz + 3 * S->tris[3 * t + 2];
    double u[3] = {q[0] - p[0], q[1] - p[1], q[2] - p[2]}, v[3] = {r[0] - p[0], r[1] - p[1], r[2] - p[2]};
    n[0] = u[1] * v[2] - u[2] * v[1];
    n[1] = u[2] * v[0] - u[0] * v[2];
    n[2] = u[0] * v[1] - u[1] * v[0];
}

static double sheet_area(const sheet *S)
{
    double A = 0, n[3];
    for (int64_t t = 0; t < S->nt; t++) {
        tri_normal(S, t, n);
        A += 0.5 * sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    }
    return A;
}

typedef struct dedge {
    int64_t lo, hi;
    int dir; /* +1 lo -> hi, -1 hi -> lo */
} dedge;

static int cmp_dedge(const void *pa, const void *pb)
{
    const dedge *a = pa, *b = pb;
    if (a->lo != b->lo)
        return a->lo < b->lo ? -1 : 1;
    if (a->hi != b->hi)
        return a->hi < b->hi ? -1 : 1;
    return a->dir - b->dir;
}

/* Edges of the sheet: *nb used once (boundary), *ni twice in opposite directions, *bad
 * otherwise (twice one way, or more than twice); boundary edges written to bnd (2 each,
 * from -> to along the triangles' orientation) when not NULL. */
static void edges_of(const sheet *S, int64_t *nb, int64_t *ni, int64_t *bad, int64_t *bnd)
{
    dedge *E = malloc((size_t)(3 * S->nt + 1) * sizeof *E);
    for (int64_t t = 0; t < S->nt; t++)
        for (int c = 0; c < 3; c++) {
            int64_t x = S->tris[3 * t + c], y = S->tris[3 * t + (c + 1) % 3];
            E[3 * t + c] = (dedge){x < y ? x : y, x < y ? y : x, x < y ? 1 : -1};
        }
    qsort(E, (size_t)(3 * S->nt), sizeof *E, cmp_dedge);
    *nb = *ni = *bad = 0;
    for (int64_t i = 0; i < 3 * S->nt;) {
        int64_t j = i;
        while (j < 3 * S->nt && E[j].lo == E[i].lo && E[j].hi == E[i].hi)
            j++;
        if (j - i == 1) {
            if (bnd) {
                bnd[2 * *nb] = E[i].dir > 0 ? E[i].lo : E[i].hi;
                bnd[2 * *nb + 1] = E[i].dir > 0 ? E[i].hi : E[i].lo;
            }
            (*nb)++;
        } else if (j - i == 2 && E[i].dir != E[i + 1].dir) {
            (*ni)++;
        } else {
            (*bad)++;
        }
        i = j;
    }
    free(E);
}

static double seg_dist(const double *x, const double *s, const double *e)
{
    double d[3] = {e[0] - s[0], e[1] - s[1], e[2] - s[2]}, w[3] = {x[0] - s[0], x[1] - s[1], x[2] - s[2]};
    double dd = d[0] * d[0] + d[1] * d[1] + d[2] * d[2], t = 0;
    if (dd > 0)
        t = fmin(1, fmax(0, (w[0] * d[0] + w[1] * d[1] + w[2] * d[2]) / dd));
    double r[3] = {w[0] - t * d[0], w[1] - t * d[1], w[2] - t * d[2]};
    return sqrt(r[0] * r[0] + r[1] * r[1] + r[2] * r[2]);
}

/* The general checks of a simplified sheet O against its input I: every kept vertex an
 * input vertex (same bits, same radius), a manifold with one orientation (every normal on
 * the side of the input's mean normal field: checked as the sign of the sum against each
 * output triangle's nearest input triangle would be costly, so against the bisector's
 * gradient, which the input's triangles follow), the boundary: every output boundary
 * vertex an input boundary vertex, every input boundary vertex within tol / 4 of the
 * output's boundary.  Returns the output's boundary edge count. */
static int64_t check_sheet(const md_elements *el, const sheet *I, const sheet *O, const int64_t *vmap,
                           double tol, const char *name)
{
    /* kept vertices: the input's, bit for bit, in order */
    int64_t kept = 0, bad_v = 0, prev = -1;
    for (int64_t v = 0; v < I->nv; v++) {
        if (vmap[v] < 0)
            continue;
        kept++;
        bad_v += vmap[v] <= prev || vmap[v] >= O->nv ||
                 memcmp(O->xyz + 3 * vmap[v], I->xyz + 3 * v, 3 * sizeof(double)) ||
                 O->radius[vmap[v]] != I->radius[v];
        prev = vmap[v];
    }
    CHECK_EQ_INT(kept, O->nv);
    CHECK_EQ_INT(bad_v, 0);
    /* manifold, every vertex used */
    int64_t nbI, niI, badI, nbO, niO, badO;
    int64_t *bI = malloc((size_t)(6 * I->nt + 2) * sizeof *bI), *bO = malloc((size_t)(6 * O->nt + 2) * sizeof *bO);
    edges_of(I, &nbI, &niI, &badI, bI);
    edges_of(O, &nbO, &niO, &badO, bO);
    CHECK_EQ_INT(badI, 0);
    CHECK_EQ_INT(badO, 0);
    char *used = calloc((size_t)(O->nv + 1), 1);
    for (int64_t i = 0; i < 3 * O->nt; i++)
        used[O->tris[i]] = 1;
    int64_t unused = 0;
    for (int64_t v = 0; v < O->nv; v++)
        unused += !used[v];
    CHECK_EQ_INT(unused, 0);
    free(used);
    /* one orientation: the output's triangles all face one way along grad f, the way most
     * of the input's do (the extraction leaves an odd fold: the L-bracket's full soup has
     * one in its (0, 3) and (1, 3) sheets, |n.g| = |g|, printed) */
    int64_t cnt[2][2] = {{0, 0}, {0, 0}}; /* [input/output][negative/positive] */
    for (int pass = 0; pass < 2; pass++) {
        const sheet *S = pass ? O : I;
        for (int64_t t = 0; t < S->nt; t++) {
            double n[3], c[3], ga[3], gb[3];
            tri_normal(S, t, n);
            for (int k = 0; k < 3; k++)
                c[k] = (S->xyz[3 * S->tris[3 * t] + k] + S->xyz[3 * S->tris[3 * t + 1] + k] +
                        S->xyz[3 * S->tris[3 * t + 2] + k]) / 3;
            md_dist_car(el, I->a, c, ga);
            md_dist_car(el, I->b, c, gb);
            double d = n[0] * (ga[0] - gb[0]) + n[1] * (ga[1] - gb[1]) + n[2] * (ga[2] - gb[2]);
            double nn = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
            if (fabs(d) < 1e-6 * nn)
                continue; /* a sliver: no say */
            cnt[pass][d > 0]++;
        }
    }
    int sI = cnt[0][1] >= cnt[0][0];
    if (cnt[0][!sI])
        printf("%s: %lld input triangles of %lld folded against the rest\n", name, (long long)cnt[0][!sI],
               (long long)I->nt);
    CHECK_EQ_INT(cnt[1][!sI], 0);
    CHECK(cnt[1][sI] > 0);
    /* the boundary: output boundary vertices are input boundary vertices; every input
     * boundary vertex within tol / 4 of the output's boundary */
    char *onb = calloc((size_t)(I->nv + 1), 1);
    for (int64_t i = 0; i < 2 * nbI; i++)
        onb[bI[i]] = 1;
    int64_t *inv = malloc((size_t)(O->nv + 1) * sizeof *inv);
    for (int64_t v = 0; v < I->nv; v++)
        if (vmap[v] >= 0)
            inv[vmap[v]] = v;
    int64_t not_input = 0;
    for (int64_t i = 0; i < 2 * nbO; i++)
        not_input += !onb[inv[bO[i]]];
    CHECK_EQ_INT(not_input, 0);
    double worst = 0;
    for (int64_t v = 0; v < I->nv; v++) {
        if (!onb[v])
            continue;
        double d = INFINITY;
        for (int64_t i = 0; i < nbO; i++)
            d = fmin(d, seg_dist(I->xyz + 3 * v, O->xyz + 3 * bO[2 * i], O->xyz + 3 * bO[2 * i + 1]));
        worst = fmax(worst, d);
    }
    printf("%s: boundary %lld -> %lld edges, input boundary vertices within %.3g of the output's "
           "(tol/4 = %.3g)\n", name, (long long)nbI, (long long)nbO, worst, tol / 4);
    CHECK(worst <= tol / 4 * (1 + 1e-12));
    free(onb);
    free(inv);
    free(bI);
    free(bO);
    return nbO;
}

/* md_sheet_simplify on T (a copy of S, whose labels it uses), in place. */
static mfg_status sheet_simplify(const md_elements *el, const sheet *S, double tol, sheet *T,
                                 int64_t *vmap)
{
    md_sheet_mesh m = {T->nv, T->xyz, T->radius, T->nt, T->tris};
    mfg_status st = md_sheet_simplify(el, T->a, T->b, tol, S->label, &m, vmap);
    T->nv = m.nverts;
    T->nt = m.ntris;
    return st;
}

/* Simplifies a copy of S; *out gets the result, vmap (room for S->nv) the vertex map. */
static void simplify(const md_elements *el, const sheet *S, double tol, sheet *out, int64_t *vmap,
                     const char *name)
{
    *out = sheet_copy(S);
    double t0 = now();
    CHECK_EQ_INT(sheet_simplify(el, S, tol, out, vmap),
                 MFG_OK);
    double t1 = now();
    printf("%s (form %d): %lld -> %lld triangles, %lld -> %lld vertices, %.3f s\n", name,
           md_form(el, S->a, S->b), (long long)S->nt, (long long)out->nt, (long long)S->nv,
           (long long)out->nv, t1 - t0);
    /* again on the result's input: the same bits (no dependence on anything else) */
    sheet again = sheet_copy(S);
    CHECK_EQ_INT(sheet_simplify(el, S, tol, &again, NULL),
                 MFG_OK);
    CHECK(again.nv == out->nv && again.nt == out->nt &&
          !memcmp(again.tris, out->tris, (size_t)(3 * out->nt) * sizeof *out->tris));
    sheet_free(&again);
}

typedef struct pipeline {
    md_elements el;
    md_bvh *bvh;
    md_leaves lv;
    md_soup s;
} pipeline;

static void pipeline_run_full(pipeline *P, const tmesh *m, double tol, int full, const char *name)
{
    CHECK_EQ_INT(md_elements_build(m->xyz, m->nv, m->tri, m->nt, tol, &P->el), MFG_OK);
    CHECK_EQ_INT(md_bvh_build(&P->el, &P->bvh), MFG_OK);
    CHECK_EQ_INT(md_octree_build(&P->el, P->bvh, tol, full, 2, &P->lv), MFG_OK);
    CHECK_EQ_INT(md_sheets_extract(&P->el, P->bvh, &P->lv, tol, 2, &P->s), MFG_OK);
    printf("%s: tol %g, h %g, soup %lld triangles\n", name, tol, P->lv.lat.h, (long long)P->s.ntris);
}

static void pipeline_run(pipeline *P, const tmesh *m, double tol, const char *name)
{
    pipeline_run_full(P, m, tol, 0, name);
}

static void pipeline_free(pipeline *P)
{
    md_soup_free(&P->s);
    md_leaves_free(&P->lv);
    md_bvh_free(P->bvh);
    md_elements_free(&P->el);
}

/* ---- the cuboid: the mid-plane z = 10 over [10, 90] x [10, 50] ---------------------------- */

static void test_cuboid(double tol)
{
    static const double R[4][2] = {{0, 0}, {100, 0}, {100, 60}, {0, 60}};
    tmesh m;
    convex_prism(&m, R, 4, 20);
    pipeline P;
    pipeline_run(&P, &m, tol, "cuboid");
    int64_t z0 = face_with(&P.el, 0, 0, -1, 0), z1 = face_with(&P.el, 0, 0, 1, 20);
    sheet S = sheet_of(&P.s, z0, z1), O;
    CHECK(S.nt > 100);
    double A0 = sheet_area(&S);
    int64_t *vmap = malloc((size_t)(S.nv + 1) * sizeof *vmap);
    simplify(&P.el, &S, tol, &O, vmap, "cuboid mid-sheet");
    double A = sheet_area(&O);
    printf("cuboid: area %.12f -> %.12f (3200)\n", A0, A);
    CHECK(fabs(A - A0) <= 1e-9 * A0);
    CHECK(fabs(A - 3200) <= 1e-9 * 3200);
    CHECK(O.nt >= 2 && O.nt <= 10);
    int64_t bad = 0;
    for (int64_t v = 0; v < O.nv; v++)
        bad += fabs(O.xyz[3 * v + 2] - 10) > 1e-12 || fabs(O.radius[v] - 10) > 1e-9;
    CHECK_EQ_INT(bad, 0);
    check_sheet(&P.el, &S, &O, vmap, tol, "cuboid mid-sheet");
    free(vmap);
    sheet_free(&O);
    sheet_free(&S);
    pipeline_free(&P);
}

/* ---- the L-bracket: the planes x = 5, y = 5 and the parabolic cylinder of (Fo, E) -------- */

/* Distance from x to the parabolic cylinder 20 X = 100 + (Y - 10)^2 (any z): the closest
 * point by a scan in Y and golden-section refinement (the squared distance is unimodal near
 * its minimum at this curvature). */
static double parabola_dist(const double *x)
{
    double best = INFINITY, by = 0;
    for (double y = x[1] - 30; y <= x[1] + 30; y += 1e-3) {
        double X = (100 + (y - 10) * (y - 10)) / 20, d = (x[0] - X) * (x[0] - X) + (x[1] - y) * (x[1] - y);
        if (d < best) {
            best = d;
            by = y;
        }
    }
    double lo = by - 2e-3, hi = by + 2e-3, g = (sqrt(5.0) - 1) / 2;
    for (int it = 0; it < 100; it++) {
        double y1 = hi - g * (hi - lo), y2 = lo + g * (hi - lo);
        double X1 = (100 + (y1 - 10) * (y1 - 10)) / 20, X2 = (100 + (y2 - 10) * (y2 - 10)) / 20;
        double d1 = (x[0] - X1) * (x[0] - X1) + (x[1] - y1) * (x[1] - y1);
        double d2 = (x[0] - X2) * (x[0] - X2) + (x[1] - y2) * (x[1] - y2);
        if (d1 < d2)
            hi = y2;
        else
            lo = y1;
    }
    double y = 0.5 * (lo + hi), X = (100 + (y - 10) * (y - 10)) / 20;
    return sqrt((x[0] - X) * (x[0] - X) + (x[1] - y) * (x[1] - y));
}

static void test_l_bracket(double tol)
{
    static const double Pl[6][2] = {{0, 0}, {50, 0}, {50, 10}, {10, 10}, {10, 50}, {0, 50}};
    static const int T[4][3] = {{0, 1, 2}, {0, 2, 3}, {0, 3, 4}, {0, 4, 5}};
    tmesh m;
    prism(&m, Pl, 6, 40, T, 4);
    pipeline P;
    pipeline_run(&P, &m, tol, "L-bracket");
    const md_elements *el = &P.el;
    int64_t Fo = face_with(el, -1, 0, 0, 0), Fi = face_with(el, 1, 0, 0, 10);
    int64_t Go = face_with(el, 0, -1, 0, 0), Gi = face_with(el, 0, 1, 0, 10);
    double e0[3] = {10, 10, 0}, e1[3] = {10, 10, 40};
    int64_t E = edge_from_to(el, e0, e1);
    CHECK(Fo >= 0 && Fi >= 0 && Go >= 0 && Gi >= 0 && E >= 0);
    /* the flat sheets: x = 5 over y in [10, 45], z in [5, 35] (and y = 5 likewise) */
    for (int k = 0; k < 2; k++) {
        sheet S = sheet_of(&P.s, k ? Go : Fo, k ? Gi : Fi), O;
        double A0 = sheet_area(&S);
        int64_t *vmap = malloc((size_t)(S.nv + 1) * sizeof *vmap);
        simplify(el, &S, tol, &O, vmap, k ? "L-bracket (Go,Gi)" : "L-bracket (Fo,Fi)");
        double A = sheet_area(&O);
        printf("L-bracket flat: area %.9f -> %.9f (1050)\n", A0, A);
        CHECK(fabs(A - A0) <= 1e-9 * A0);
        CHECK(O.nt >= 2 && O.nt <= 10);
        check_sheet(el, &S, &O, vmap, tol, "L-bracket flat");
        free(vmap);
        sheet_free(&O);
        sheet_free(&S);
    }
    /* the parabolic cylinder 20 x = 100 + (y - 10)^2, z in [x, 40 - x], y in [rho*, 10] */
    sheet S = sheet_of(&P.s, Fo, E), O;
    int64_t *vmap = malloc((size_t)(S.nv + 1) * sizeof *vmap);
    simplify(el, &S, tol, &O, vmap, "L-bracket (Fo,E)");
    double bad_par = 0, dev = 0;
    for (int64_t v = 0; v < O.nv; v++) {
        const double *x = O.xyz + 3 * v;
        bad_par = fmax(bad_par, fabs(x[0] - (100 + (x[1] - 10) * (x[1] - 10)) / 20));
        bad_par = fmax(bad_par, fabs(O.radius[v] - x[0]));
    }
    for (int64_t t = 0; t < O.nt; t++) {
        double c[3];
        for (int k = 0; k < 3; k++)
            c[k] = (O.xyz[3 * O.tris[3 * t] + k] + O.xyz[3 * O.tris[3 * t + 1] + k] +
                    O.xyz[3 * O.tris[3 * t + 2] + k]) / 3;
        dev = fmax(dev, parabola_dist(c));
    }
    double rho = (2 - sqrt(2.0)) * 10, A_ref = 0;
    for (int i = 0; i < 100000; i++) {
        double ya = rho + (10 - rho) * i / 1e5, yb = rho + (10 - rho) * (i + 1) / 1e5;
        double xa = (100 + (ya - 10) * (ya - 10)) / 20, xb = (100 + (yb - 10) * (yb - 10)) / 20;
        A_ref += (40 - (xa + xb)) * hypot(xb - xa, yb - ya);
    }
    double A0 = sheet_area(&S), A = sheet_area(&O);
    printf("L-bracket (Fo,E): area %.4f -> %.4f (integral %.4f), worst vertex off the parabola %.3g, "
           "worst centroid %.3g (tol/2 = %.3g)\n", A0, A, A_ref, bad_par, dev, tol / 2);
    CHECK(bad_par <= 1e-9);
    CHECK(fabs(A - A_ref) <= 0.01 * A_ref);
    CHECK(O.nt * 10 <= S.nt);
    CHECK(dev <= tol / 2);
    check_sheet(el, &S, &O, vmap, tol, "L-bracket (Fo,E)");
    free(vmap);
    sheet_free(&O);
    sheet_free(&S);
    pipeline_free(&P);
}

/* ---- the 48-gon disc: its sheet z = 2, the 48-gon of apothem 50 cos(pi/48) - 2 ----------- */

static void test_disc(double tol)
{
    double Pd[48][2];
    for (int i = 0; i < 48; i++) {
        Pd[i][0] = 50 * cos(2 * M_PI * i / 48);
        Pd[i][1] = 50 * sin(2 * M_PI * i / 48);
    }
    tmesh m;
    convex_prism(&m, (const double(*)[2])Pd, 48, 4);
    pipeline P;
    pipeline_run(&P, &m, tol, "disc48");
    int64_t top = face_with(&P.el, 0, 0, 1, 4), bot = face_with(&P.el, 0, 0, -1, 0);
    sheet S = sheet_of(&P.s, top, bot), O;
    int64_t *vmap = malloc((size_t)(S.nv + 1) * sizeof *vmap);
    simplify(&P.el, &S, tol, &O, vmap, "disc48 sheet");
    double ap = 50 * cos(M_PI / 48) - 2, want = 48 * ap * ap * tan(M_PI / 48);
    double A0 = sheet_area(&S), A = sheet_area(&O);
    printf("disc48: area %.9f -> %.9f (%.9f)\n", A0, A, want);
    CHECK(fabs(A - want) <= 1e-6 * want);
    int64_t nb = check_sheet(&P.el, &S, &O, vmap, tol, "disc48 sheet");
    /* one planar polygon: the 48-gon's corners only (every kept vertex on its circumcircle),
     * fanned into 46 triangles */
    CHECK_EQ_INT(nb, 48);
    CHECK_EQ_INT(O.nt, 46);
    int64_t bad = 0;
    for (int64_t v = 0; v < O.nv; v++) {
        double r = hypot(O.xyz[3 * v], O.xyz[3 * v + 1]);
        bad += fabs(O.xyz[3 * v + 2] - 2) > 1e-9 || fabs(r - ap / cos(M_PI / 48)) > 1e-6;
    }
    CHECK_EQ_INT(bad, 0);
    free(vmap);
    sheet_free(&O);
    sheet_free(&S);
    pipeline_free(&P);
}

/* ---- every sheet of a solid, every bisector form ------------------------------------------ */

/* Distance from x to the bisector of (a, b) along its normal line: the root of
 * d_a^car - d_b^car on the segment x -+ R grad / |grad| (md_root_on_segment, independent of
 * the first-order estimate the simplification uses); +INFINITY when there is none. */
static double normal_dist(const md_elements *el, int64_t a, int64_t b, const double *x, double R)
{
    double ga[3], gb[3], g[3];
    md_dist_car(el, a, x, ga);
    md_dist_car(el, b, x, gb);
    for (int k = 0; k < 3; k++)
        g[k] = ga[k] - gb[k];
    double gn = sqrt(g[0] * g[0] + g[1] * g[1] + g[2] * g[2]);
    if (!(gn > 0))
        return INFINITY;
    double best = INFINITY;
    for (int side = -1; side <= 1; side += 2) {
        double q[3], r[3];
        for (int k = 0; k < 3; k++)
            q[k] = x[k] + side * R * g[k] / gn;
        if (md_root_on_segment(el, a, b, x, q, r, NULL))
            best = fmin(best, sqrt((r[0] - x[0]) * (r[0] - x[0]) + (r[1] - x[1]) * (r[1] - x[1]) +
                                   (r[2] - x[2]) * (r[2] - x[2])));
    }
    return best;
}

/* Every pair's sheet of the soup simplified: the general checks, every vertex still on its
 * bisector (|d_a - d_b| as the soup had it), the triangles' centroids and edge midpoints
 * within tolerance / 2 of the bisector along its normal (to 2 % for the curvature the
 * first-order test does not see), and the count per form. */
static void test_all_sheets(const tmesh *m, double tol, int full, const char *name)
{
    pipeline P;
    pipeline_run_full(&P, m, tol, full, name);
    const md_soup *s = &P.s;
    int64_t *pairs = malloc((size_t)(2 * s->ntris + 2) * sizeof *pairs), np = 0;
    for (int64_t t = 0; t < s->ntris; t++) {
        int64_t a = s->tri_pair[2 * t], b = s->tri_pair[2 * t + 1], seen = 0;
        for (int64_t i = 0; i < np && !seen; i++)
            seen = pairs[2 * i] == a && pairs[2 * i + 1] == b;
        if (!seen) {
            pairs[2 * np] = a;
            pairs[2 * np + 1] = b;
            np++;
        }
    }
    int64_t before[12] = {0}, after[12] = {0};
    double worst = 0, worst_v = 0, worst_in = 0;
    for (int64_t i = 0; i < np; i++) {
        sheet S = sheet_of(s, pairs[2 * i], pairs[2 * i + 1]), O;
        int64_t *vmap = malloc((size_t)(S.nv + 1) * sizeof *vmap);
        O = sheet_copy(&S);
        CHECK_EQ_INT(sheet_simplify(&P.el, &S, tol, &O, vmap),
                     MFG_OK);
        int form = md_form(&P.el, S.a, S.b);
        before[form] += S.nt;
        after[form] += O.nt;
        CHECK(O.nt <= S.nt && O.nt > 0);
        char what[96];
        snprintf(what, sizeof what, "%s (%lld,%lld) form %d", name, (long long)S.a, (long long)S.b, form);
        check_sheet(&P.el, &S, &O, vmap, tol, what);
        for (int64_t v = 0; v < O.nv; v++) {
            const double *x = O.xyz + 3 * v;
            worst_v = fmax(worst_v, fabs(md_dist_car(&P.el, S.a, x, NULL) - md_dist_car(&P.el, S.b, x, NULL)));
        }
        for (int64_t v = 0; v < S.nv; v++) {
            const double *x = S.xyz + 3 * v;
            worst_in = fmax(worst_in, fabs(md_dist_car(&P.el, S.a, x, NULL) - md_dist_car(&P.el, S.b, x, NULL)));
        }
        for (int64_t t = 0; t < O.nt; t++) {
            const double *p[3];
            for (int c = 0; c < 3; c++)
                p[c] = O.xyz + 3 * O.tris[3 * t + c];
            static const double W[4][3] = {{1.0 / 3, 1.0 / 3, 1.0 / 3}, {0.5, 0.5, 0}, {0, 0.5, 0.5}, {0.5, 0, 0.5}};
            for (int w = 0; w < 4; w++) {
                double x[3];
                for (int k = 0; k < 3; k++)
                    x[k] = W[w][0] * p[0][k] + W[w][1] * p[1][k] + W[w][2] * p[2][k];
                worst = fmax(worst, normal_dist(&P.el, S.a, S.b, x, tol));
            }
        }
        free(vmap);
        sheet_free(&O);
        sheet_free(&S);
    }
    for (int f = 1; f <= 11; f++)
        if (before[f])
            printf("%s: form %d: %lld -> %lld triangles\n", name, f, (long long)before[f], (long long)after[f]);
    printf("%s: %lld sheets; worst vertex |da - db| %.3g (input %.3g), worst sample off the bisector %.4g "
           "(tol/2 = %.4g)\n", name, (long long)np, worst_v, worst_in, worst, tol / 2);
    /* Kept vertices are input vertices (check_sheet: bit for bit): none further off than the
     * input's.  (The L-bracket's full soup has one boundary point 0.41 off: the (top, E) sheet
     * at (10, 9.994, 39.58), radius 0.006, where the corner (10, 10, 40) pinches it; an
     * extraction matter, medial/sheets.c.) */
    CHECK(worst_v <= fmax(worst_in, 1e-9 * P.el.diag));
    CHECK(worst <= 0.51 * tol);
    free(pairs);
    pipeline_free(&P);
}

#ifdef MFG_SIMPLIFY_ALLOC_FAIL
#include "alloc_shim.h"

/* md_sheet_simplify with each allocation failing in turn: MFG_ERR_NOMEM with the arrays
 * untouched and no block leaked, or (libc absorbing the failure: qsort) the same result. */
static void alloc_fail_on(const md_elements *el, const sheet *S, double tol, const char *name)
{
    sheet ref = sheet_copy(S);
    CHECK_EQ_INT(sheet_simplify(el, S, tol, &ref, NULL),
                 MFG_OK);
    CHECK(ref.nt < S->nt);
    int done = 0;
    long n, absorbed = 0, bad = 0;
    for (n = 1; n < 100000 && !done; n++) {
        sheet C = sheet_copy(S);
        alloc_shim_arm(n);
        mfg_status st = sheet_simplify(el, S, tol, &C, NULL);
        alloc_shim_stats a = alloc_shim_disarm();
        CHECK_EQ_INT(a.net, 0);
        if (a.failed == 0) {
            done = 1;
            CHECK_EQ_INT(st, MFG_OK);
        } else if (st == MFG_OK) {
            absorbed++;
            bad += C.nt != ref.nt || C.nv != ref.nv ||
                   memcmp(C.tris, ref.tris, (size_t)(3 * ref.nt) * sizeof *C.tris) != 0;
        } else {
            CHECK_EQ_INT(st, MFG_ERR_NOMEM);
            bad += C.nt != S->nt || C.nv != S->nv ||
                   memcmp(C.tris, S->tris, (size_t)(3 * S->nt) * sizeof *C.tris) != 0 ||
                   memcmp(C.xyz, S->xyz, (size_t)(3 * S->nv) * sizeof *C.xyz) != 0;
        }
        sheet_free(&C);
    }
    CHECK(done);
    CHECK_EQ_INT(bad, 0);
    printf("%s: allocations failed in turn: %ld (%ld absorbed by libc)\n", name, n - 2, absorbed);
    sheet_free(&ref);
}

static void test_alloc_fail(void)
{
    static const double R[4][2] = {{0, 0}, {100, 0}, {100, 60}, {0, 60}};
    tmesh m;
    convex_prism(&m, R, 4, 20);
    pipeline P;
    pipeline_run(&P, &m, 8, "cuboid");
    sheet S = sheet_of(&P.s, face_with(&P.el, 0, 0, -1, 0), face_with(&P.el, 0, 0, 1, 20));
    alloc_fail_on(&P.el, &S, 8, "cuboid mid-sheet");
    sheet_free(&S);
    pipeline_free(&P);
    static const double Pl[6][2] = {{0, 0}, {50, 0}, {50, 10}, {10, 10}, {10, 50}, {0, 50}};
    static const int T[4][3] = {{0, 1, 2}, {0, 2, 3}, {0, 3, 4}, {0, 4, 5}};
    prism(&m, Pl, 6, 40, T, 4);
    pipeline_run(&P, &m, 2, "L-bracket");
    double e0[3] = {10, 10, 0}, e1[3] = {10, 10, 40};
    S = sheet_of(&P.s, face_with(&P.el, -1, 0, 0, 0), edge_from_to(&P.el, e0, e1));
    alloc_fail_on(&P.el, &S, 2, "L-bracket (Fo,E)");
    sheet_free(&S);
    pipeline_free(&P);
}
#endif

/* "alloc" (the allocation-failure build only): md_sheet_simplify under failing
 * allocations; otherwise the analytic solids. */
int main(int argc, char **argv)
{
#ifdef MFG_SIMPLIFY_ALLOC_FAIL
    if (argc > 1 && !strcmp(argv[1], "alloc")) {
        test_alloc_fail();
        return mfg_test_report("medial_simplify_alloc");
    }
#endif
    (void)argc;
    (void)argv;
    test_cuboid(2.5);
    test_cuboid(0.7);
    test_l_bracket(1.0);
    test_l_bracket(0.3);
    test_disc(1.0);
    {
        static const double Pl[6][2] = {{0, 0}, {50, 0}, {50, 10}, {10, 10}, {10, 50}, {0, 50}};
        static const int T[4][3] = {{0, 1, 2}, {0, 2, 3}, {0, 3, 4}, {0, 4, 5}};
        static const double C[4][2] = {{0, 0}, {40, 0}, {40, 40}, {0, 40}};
        tmesh m;
        prism(&m, Pl, 6, 40, T, 4);
        test_all_sheets(&m, 1.0, 1, "L-bracket full");
        convex_prism(&m, C, 4, 40);
        test_all_sheets(&m, 2.0, 1, "cube full");
    }
    return mfg_test_report("medial_simplify");
}
