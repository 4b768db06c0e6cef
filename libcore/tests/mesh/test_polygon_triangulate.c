/* SPDX-License-Identifier: LGPL-2.1-or-later */
/* test_polygon_triangulate.c - the private polygon-with-holes triangulation against
 * references it does not compute itself: analytic areas, the triangle count of a
 * triangulation on the polygon's own vertices (n - 2 + 2h), and brute-force checks of the
 * result (every triangle counter-clockwise, no triangle holding another vertex, the loop
 * edges each used once and every other edge twice in opposite directions). */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "mfg_test.h"
#include "mesh/polygon_triangulate.h"

#define MAXP 4096

typedef struct poly {
    double xy[2 * MAXP];
    int64_t start[64];
    int64_t nloops, n;
} poly;

static void begin_loop(poly *p)
{
    if (p->nloops == 0)
        p->start[0] = 0;
    p->nloops++;
    p->start[p->nloops] = p->n;
}

static void add_pt(poly *p, double x, double y)
{
    p->xy[2 * p->n] = x;
    p->xy[2 * p->n + 1] = y;
    p->n++;
    p->start[p->nloops] = p->n;
}

/* straight edge from (x0, y0) to (x1, y1) with k points (the start included, the end not) */
static void add_run(poly *p, double x0, double y0, double x1, double y1, int k)
{
    for (int i = 0; i < k; i++)
        add_pt(p, x0 + (x1 - x0) * i / k, y0 + (y1 - y0) * i / k);
}

static double cross(const double *a, const double *b, const double *c)
{
    return (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
}

/* Triangulates p and checks the result; expect_ntri < 0: expects a refusal (0). */
static void check_poly(const char *name, const poly *p, int64_t expect_ntri, double expect_area)
{
    int64_t cap = p->n + 2 * p->nloops;
    int64_t *tri = malloc((size_t)(3 * cap) * sizeof *tri);
    int64_t nt = -1;
    int rc = mfg_polygon_triangulate(p->xy, p->start, p->nloops, tri, &nt);
    if (expect_ntri < 0) {
        CHECK_EQ_INT(rc, 0);
        if (rc != 0)
            fprintf(stderr, "  %s: expected a refusal\n", name);
        free(tri);
        return;
    }
    CHECK_EQ_INT(rc, 1);
    CHECK_EQ_INT(nt, expect_ntri);
    if (rc != 1 || nt != expect_ntri) {
        fprintf(stderr, "  %s: rc %d, %lld triangles, expected %lld\n", name, rc, (long long)nt,
                (long long)expect_ntri);
        free(tri);
        return;
    }
    double area = 0;
    int bad_ccw = 0, bad_inside = 0, bad_edges = 0;
    char *used = calloc((size_t)p->n, 1);
    for (int64_t t = 0; t < nt; t++) {
        const double *a = p->xy + 2 * tri[3 * t], *b = p->xy + 2 * tri[3 * t + 1], *c = p->xy + 2 * tri[3 * t + 2];
        double cr = cross(a, b, c);
        area += 0.5 * cr;
        if (!(cr > 0))
            bad_ccw++;
        for (int k = 0; k < 3; k++)
            used[tri[3 * t + k]] = 1;
        for (int64_t i = 0; i < p->n; i++) {
            const double *q = p->xy + 2 * i;
            if ((q[0] == a[0] && q[1] == a[1]) || (q[0] == b[0] && q[1] == b[1]) || (q[0] == c[0] && q[1] == c[1]))
                continue;
            if (cross(a, b, q) >= 0 && cross(b, c, q) >= 0 && cross(c, a, q) >= 0)
                bad_inside++;
        }
    }
    /* edges: by point position (a point occurring twice is one vertex of the region) */
    for (int64_t t = 0; t < nt; t++)
        for (int k = 0; k < 3; k++) {
            const double *u = p->xy + 2 * tri[3 * t + k], *v = p->xy + 2 * tri[3 * t + (k + 1) % 3];
            int same = 0, rev = 0, loop = 0;
            for (int64_t s = 0; s < nt; s++)
                for (int j = 0; j < 3; j++) {
                    const double *x = p->xy + 2 * tri[3 * s + j], *y = p->xy + 2 * tri[3 * s + (j + 1) % 3];
                    if (x[0] == u[0] && x[1] == u[1] && y[0] == v[0] && y[1] == v[1])
                        same++;
                    if (x[0] == v[0] && x[1] == v[1] && y[0] == u[0] && y[1] == u[1])
                        rev++;
                }
            for (int64_t l = 0; l < p->nloops; l++)
                for (int64_t i = p->start[l]; i < p->start[l + 1]; i++) {
                    int64_t j = i + 1 < p->start[l + 1] ? i + 1 : p->start[l];
                    const double *x = p->xy + 2 * i, *y = p->xy + 2 * j;
                    if (x[0] == u[0] && x[1] == u[1] && y[0] == v[0] && y[1] == v[1])
                        loop++;
                }
            if (same != 1 || (loop ? rev != 0 : rev != 1) || loop > 1)
                bad_edges++;
        }
    int64_t unused = 0;
    for (int64_t i = 0; i < p->n; i++)
        unused += !used[i];
    CHECK(fabs(area - expect_area) <= 1e-9 * fabs(expect_area));
    CHECK_EQ_INT(bad_ccw, 0);
    CHECK_EQ_INT(bad_inside, 0);
    CHECK_EQ_INT(bad_edges, 0);
    CHECK_EQ_INT(unused, 0);
    if (fabs(area - expect_area) > 1e-9 * fabs(expect_area) || bad_ccw || bad_inside || bad_edges || unused)
        fprintf(stderr, "  %s: area %.17g (expected %.17g), %d cw, %d holding a vertex, %d bad edges, %lld unused\n",
                name, area, expect_area, bad_ccw, bad_inside, bad_edges, (long long)unused);
    free(used);
    free(tri);
}

static void test_squares(void)
{
    poly *p = calloc(1, sizeof *p);
    begin_loop(p);
    add_run(p, 0, 0, 1, 0, 1);
    add_run(p, 1, 0, 1, 1, 1);
    add_run(p, 1, 1, 0, 1, 1);
    add_run(p, 0, 1, 0, 0, 1);
    check_poly("unit square", p, 2, 1.0);
    /* collinear runs: 10 points on every side */
    memset(p, 0, sizeof *p);
    begin_loop(p);
    add_run(p, 0, 0, 8, 0, 10);
    add_run(p, 8, 0, 8, 4, 10);
    add_run(p, 8, 4, 0, 4, 10);
    add_run(p, 0, 4, 0, 0, 10);
    check_poly("rectangle, collinear runs", p, 38, 32.0);
    /* the same rectangle with one and with three holes (clockwise), listed before the
     * outer loop, holes with collinear runs too */
    for (int nh = 1; nh <= 3; nh++) {
        memset(p, 0, sizeof *p);
        double harea = 0;
        for (int h = 0; h < nh; h++) {
            double x0 = 1 + 2.5 * h, y0 = 1 + 0.5 * h;
            begin_loop(p);
            add_run(p, x0, y0, x0, y0 + 1.5, 3);
            add_run(p, x0, y0 + 1.5, x0 + 1, y0 + 1.5, 2);
            add_run(p, x0 + 1, y0 + 1.5, x0 + 1, y0, 3);
            add_run(p, x0 + 1, y0, x0, y0, 4);
            harea += 1.5;
        }
        begin_loop(p);
        add_run(p, 0, 0, 8, 0, 10);
        add_run(p, 8, 0, 8, 4, 10);
        add_run(p, 8, 4, 0, 4, 10);
        add_run(p, 0, 4, 0, 0, 10);
        char name[64];
        snprintf(name, sizeof name, "rectangle with %d holes", nh);
        check_poly(name, p, p->n - 2 + 2 * nh, 32.0 - harea);
    }
    free(p);
}

/* A comb: base [0, 2k - 1] x [0, 1], k teeth [2i, 2i + 1] x [1, 1 + len] (collinear
 * corners along the base's top between the teeth). */
static void test_combs(void)
{
    poly *p = calloc(1, sizeof *p);
    for (int k = 1; k <= 40; k += 3) {
        double len = 0.5 + (k % 7);
        memset(p, 0, sizeof *p);
        begin_loop(p);
        add_pt(p, 0, 0);
        add_pt(p, 2 * k - 1, 0);
        for (int i = k - 1; i >= 0; i--) {
            add_pt(p, 2 * i + 1, 1);
            add_pt(p, 2 * i + 1, 1 + len);
            add_pt(p, 2 * i, 1 + len);
            add_pt(p, 2 * i, 1);
        }
        /* the last point (0, 1) is on the left side: collinear with (0, 0) and ... */
        char name[64];
        snprintf(name, sizeof name, "comb of %d teeth", k);
        check_poly(name, p, p->n - 2, (2 * k - 1) * 1.0 + k * len);
        /* a comb-shaped hole in a box round it */
        poly *q = calloc(1, sizeof *q);
        begin_loop(q);
        add_pt(q, -1, -1);
        add_pt(q, 2 * k, -1);
        add_pt(q, 2 * k, 2 + len);
        add_pt(q, -1, 2 + len);
        begin_loop(q);
        for (int64_t i = p->n - 1; i >= 0; i--)
            add_pt(q, p->xy[2 * i], p->xy[2 * i + 1]);
        snprintf(name, sizeof name, "box round a comb hole of %d teeth", k);
        check_poly(name, q, q->n, (2 * k + 1) * (3 + len) - ((2 * k - 1) * 1.0 + k * len));
        free(q);
    }
    free(p);
}

/* Random star-shaped polygons about the origin, alone and as holes of a box; the
 * reference area is the sum of the triangles round the centre. */
static void test_stars(void)
{
    poly *p = calloc(1, sizeof *p);
    double ang[600];
    for (int trial = 0; trial < 60; trial++) {
        int n = (int)rng_int(3, trial < 40 ? 60 : 500);
        for (int i = 0; i < n; i++)
            ang[i] = rng_uniform(0, 2 * M_PI);
        /* sorted, and at least a little apart */
        for (int i = 1; i < n; i++)
            for (int j = i; j > 0 && ang[j] < ang[j - 1]; j--) {
                double t = ang[j];
                ang[j] = ang[j - 1];
                ang[j - 1] = t;
            }
        int m = 0;
        for (int i = 0; i < n; i++)
            if (m == 0 || ang[i] - ang[m - 1] > 1e-3)
                ang[m++] = ang[i];
        n = m;
        if (n < 3 || ang[n - 1] - ang[0] < M_PI + 0.1)
            continue;
        int ok = 1;
        for (int i = 0; i < n; i++)
            if (ang[(i + 1) % n] - ang[i] + (i == n - 1 ? 2 * M_PI : 0) >= M_PI - 1e-3)
                ok = 0; /* the origin must be strictly inside */
        if (!ok)
            continue;
        memset(p, 0, sizeof *p);
        begin_loop(p);
        double area = 0;
        for (int i = 0; i < n; i++) {
            double r = rng_uniform(0.2, 1);
            add_pt(p, r * cos(ang[i]), r * sin(ang[i]));
        }
        for (int i = 0; i < n; i++) {
            const double o[2] = {0, 0};
            area += 0.5 * cross(o, p->xy + 2 * i, p->xy + 2 * ((i + 1) % n));
        }
        char name[64];
        snprintf(name, sizeof name, "star %d (%d corners)", trial, n);
        check_poly(name, p, n - 2, area);
        /* as a hole of a square round it, listed first */
        poly *q = calloc(1, sizeof *q);
        begin_loop(q);
        for (int i = n - 1; i >= 0; i--)
            add_pt(q, p->xy[2 * i], p->xy[2 * i + 1]);
        begin_loop(q);
        add_run(q, -1.5, -1.5, 1.5, -1.5, 3);
        add_run(q, 1.5, -1.5, 1.5, 1.5, 3);
        add_run(q, 1.5, 1.5, -1.5, 1.5, 3);
        add_run(q, -1.5, 1.5, -1.5, -1.5, 3);
        snprintf(name, sizeof name, "square round star hole %d", trial);
        check_poly(name, q, q->n, 9.0 - area);
        free(q);
    }
    free(p);
}

/* A grid of square holes, some with collinear runs, in a box: every bridge has to find
 * its way between the other holes. */
static void test_hole_grid(void)
{
    poly *p = calloc(1, sizeof *p);
    for (int g = 1; g <= 6; g++) {
        memset(p, 0, sizeof *p);
        begin_loop(p);
        add_run(p, 0, 0, 3 * g + 1, 0, 2 * g);
        add_run(p, 3 * g + 1, 0, 3 * g + 1, 3 * g + 1, 1);
        add_run(p, 3 * g + 1, 3 * g + 1, 0, 3 * g + 1, 1);
        add_run(p, 0, 3 * g + 1, 0, 0, g);
        double holes = 0;
        for (int i = 0; i < g; i++)
            for (int j = 0; j < g; j++) {
                double x0 = 1 + 3 * i, y0 = 1 + 3 * j;
                int k = 1 + (i + j) % 3;
                begin_loop(p);
                add_run(p, x0, y0, x0, y0 + 2, k);
                add_run(p, x0, y0 + 2, x0 + 2, y0 + 2, 1);
                add_run(p, x0 + 2, y0 + 2, x0 + 2, y0, k);
                add_run(p, x0 + 2, y0, x0, y0, 1);
                holes += 4;
            }
        char name[64];
        snprintf(name, sizeof name, "%d x %d holes", g, g);
        check_poly(name, p, p->n - 2 + 2 * g * g, (3.0 * g + 1) * (3.0 * g + 1) - holes);
    }
    free(p);
}

static void test_touching(void)
{
    poly *p = calloc(1, sizeof *p);
    /* a diamond hole touching the outer loop at (2, 0), as a loop of its own */
    begin_loop(p);
    add_pt(p, 2, 0);
    add_pt(p, 1, 1);
    add_pt(p, 2, 2);
    add_pt(p, 3, 1);
    begin_loop(p);
    add_pt(p, 0, 0);
    add_pt(p, 2, 0);
    add_pt(p, 4, 0);
    add_pt(p, 4, 4);
    add_pt(p, 0, 4);
    check_poly("hole touching the outer loop", p, 7, 14.0);
    /* the same region as one loop through (2, 0) twice */
    memset(p, 0, sizeof *p);
    begin_loop(p);
    add_pt(p, 0, 0);
    add_pt(p, 2, 0);
    add_pt(p, 1, 1);
    add_pt(p, 2, 2);
    add_pt(p, 3, 1);
    add_pt(p, 2, 0);
    add_pt(p, 4, 0);
    add_pt(p, 4, 4);
    add_pt(p, 0, 4);
    check_poly("loop touching itself round a hole", p, 7, 14.0);
    /* two holes touching each other at a point, and an L-shaped outer loop touching
     * itself round a slot */
    memset(p, 0, sizeof *p);
    begin_loop(p);
    add_pt(p, 1, 1);
    add_pt(p, 1, 2);
    add_pt(p, 2, 2);
    add_pt(p, 2, 1);
    begin_loop(p);
    add_pt(p, 2, 2);
    add_pt(p, 2, 3);
    add_pt(p, 3, 3);
    add_pt(p, 3, 2);
    begin_loop(p);
    add_run(p, 0, 0, 4, 0, 4);
    add_run(p, 4, 0, 4, 4, 4);
    add_run(p, 4, 4, 0, 4, 4);
    add_run(p, 0, 4, 0, 0, 4);
    check_poly("two holes touching at a point", p, p->n - 2 + 2, 14.0);
    /* a loop touching itself so that the region falls apart there (two lobes): refused */
    memset(p, 0, sizeof *p);
    begin_loop(p);
    add_pt(p, 0, 0);
    add_pt(p, 1, 0);
    add_pt(p, 1, 1);
    add_pt(p, 0, 0);
    add_pt(p, -1, 0);
    add_pt(p, -1, -1);
    check_poly("two lobes touching at a point", p, -1, 0);
    /* a self-crossing loop (an uneven bow tie): refused */
    memset(p, 0, sizeof *p);
    begin_loop(p);
    add_pt(p, 0, 0);
    add_pt(p, 3, 3);
    add_pt(p, 3, 0);
    add_pt(p, 0, 1);
    check_poly("self-crossing loop", p, -1, 0);
    /* two outer loops, a hole outside the outer loop, a degenerate loop: refused */
    memset(p, 0, sizeof *p);
    begin_loop(p);
    add_pt(p, 0, 0);
    add_pt(p, 1, 0);
    add_pt(p, 1, 1);
    begin_loop(p);
    add_pt(p, 2, 0);
    add_pt(p, 3, 0);
    add_pt(p, 3, 1);
    check_poly("two outer loops", p, -1, 0);
    memset(p, 0, sizeof *p);
    begin_loop(p);
    add_pt(p, 0, 0);
    add_pt(p, 1, 0);
    add_pt(p, 2, 0);
    check_poly("collinear loop", p, -1, 0);
    memset(p, 0, sizeof *p);
    begin_loop(p);
    add_pt(p, 0, 0);
    add_pt(p, 4, 0);
    add_pt(p, 4, 4);
    add_pt(p, 0, 4);
    begin_loop(p);
    add_pt(p, 5, 1);
    add_pt(p, 5, 2);
    add_pt(p, 6, 2);
    add_pt(p, 6, 1);
    check_poly("hole outside the outer loop", p, -1, 0);
    free(p);
}

int main(void)
{
    test_squares();
    test_combs();
    test_stars();
    test_hole_grid();
    test_touching();
    return mfg_test_report("test_polygon_triangulate");
}
