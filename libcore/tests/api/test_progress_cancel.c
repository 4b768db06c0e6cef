/* SPDX-License-Identifier: LGPL-2.1-or-later */
/* test_progress_cancel.c - the progress / cancel mechanism (mfg_progress) of every long
 * entry point: the reports (documented stages in order, fractions monotone in [0, 1], the
 * result equal to a run without progress), a cancel at every stage boundary and at evenly
 * spaced reports (MFG_ERR_CANCELLED, the output untouched, no report after the cancel,
 * mfg_last_error naming the stage; leaks are caught by the ASan build), and the interval
 * between reports (work units, and wall time outside the sanitizer build).
 * Usage: test_progress_cancel [rays|maxisect|axis|sweep|medial|interval] (none: all). */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "medial/medial_solids.h"
#include "mfg_test.h"
#include "mfgeom.h"

#if defined(__SANITIZE_ADDRESS__)
#define UNDER_SANITIZER 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define UNDER_SANITIZER 1
#endif
#endif
#ifndef UNDER_SANITIZER
#define UNDER_SANITIZER 0
#endif

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* ---- the recording callback ------------------------------------------------------------ */

#define MAXREC 200000
typedef struct recorder {
    int n;
    int cancel_at;    /* return nonzero at this call (0-based); -1: never */
    int after_cancel; /* calls made after the one that cancelled */
    double *f;
    const char **stage;
    double *t;        /* wall time of each call */
    const char *cancel_stage; /* when set: cancel at report cancel_nth of this stage */
    int cancel_nth, seen_nth;
} recorder;

static int record(void *user, double fraction, const char *stage)
{
    recorder *r = user;
    if (r->cancel_at >= 0 && r->n > r->cancel_at)
        r->after_cancel++;
    if (r->n < MAXREC) {
        r->f[r->n] = fraction;
        r->stage[r->n] = stage;
        r->t[r->n] = now();
    }
    if (r->cancel_stage && r->cancel_at < 0 && strcmp(stage, r->cancel_stage) == 0 &&
        r->seen_nth++ == r->cancel_nth)
        r->cancel_at = r->n;
    int stop = r->n == r->cancel_at;
    r->n++;
    return stop;
}

static void rec_init(recorder *r, int cancel_at)
{
    r->n = 0;
    r->cancel_at = cancel_at;
    r->after_cancel = 0;
    r->cancel_stage = NULL;
    r->cancel_nth = r->seen_nth = 0;
    if (!r->f) {
        r->f = malloc(MAXREC * sizeof *r->f);
        r->stage = malloc(MAXREC * sizeof *r->stage);
        r->t = malloc(MAXREC * sizeof *r->t);
    }
}

static void rec_free(recorder *r)
{
    free(r->f);
    free(r->stage);
    free(r->t);
}

/* ---- one entry point behind a common signature ----------------------------------------- */

/* Runs the entry point with progress (may be NULL); on MFG_OK *digest gets a hash of the
 * whole result and the result is freed; *untouched says whether the output pointer still
 * holds the sentinel (it must on failure). */
typedef mfg_status (*runner)(const mfg_progress *progress, uint64_t *digest, int *untouched);

static uint64_t fnv(uint64_t h, const void *p, size_t n)
{
    const unsigned char *b = p;
    for (size_t i = 0; i < n; i++) {
        h ^= b[i];
        h *= 1099511628211ULL;
    }
    return h;
}
#define FNV0 1469598103934665603ULL
#define SENTINEL ((void *)(uintptr_t)0x5a5a5a50)

/* Checks the reports of a complete run against the documented stage list (stages appear
 * in that order; with may_repeat a stage may come back after later ones, as the sweep's
 * placements do). */
static void check_reports(const char *name, const recorder *r, const char *const *stages,
                          int nstages, int may_repeat)
{
    CHECK(r->n >= nstages);
    int n = r->n < MAXREC ? r->n : MAXREC;
    double last = 0;
    int pos = 0;
    for (int i = 0; i < n; i++) {
        CHECK(r->f[i] >= 0 && r->f[i] <= 1);
        CHECK(r->f[i] >= last);
        last = r->f[i];
        int k = -1;
        for (int s = 0; s < nstages; s++)
            if (strcmp(r->stage[i], stages[s]) == 0)
                k = s;
        if (k < 0) {
            fprintf(stderr, "%s: undocumented stage \"%s\"\n", name, r->stage[i]);
            CHECK(k >= 0);
            continue;
        }
        if (!may_repeat)
            CHECK(k >= pos);
        pos = k;
    }
    CHECK(strcmp(r->stage[0], stages[0]) == 0);
    CHECK(strcmp(r->stage[n - 1], stages[nstages - 1]) == 0);
    CHECK(r->f[n - 1] == 1.0);
    /* every documented stage is reported */
    for (int s = 0; s < nstages; s++) {
        int seen = 0;
        for (int i = 0; i < n && !seen; i++)
            seen = strcmp(r->stage[i], stages[s]) == 0;
        if (!seen)
            fprintf(stderr, "%s: stage \"%s\" never reported\n", name, stages[s]);
        CHECK(seen);
    }
}

/* The whole protocol for one entry point; returns the number of reports of a full run. */
static int check_entry(const char *name, runner run, const char *const *stages, int nstages,
                       int may_repeat, int samples)
{
    uint64_t d0 = 0, d1 = 0;
    int untouched = 0;
    CHECK_EQ_INT(run(NULL, &d0, &untouched), MFG_OK);
    /* a progress without a callback changes nothing */
    mfg_progress none = {NULL, NULL};
    uint64_t dn = 0;
    CHECK_EQ_INT(run(&none, &dn, &untouched), MFG_OK);
    CHECK(dn == d0);

    recorder full = {0};
    rec_init(&full, -1);
    mfg_progress pg = {record, &full};
    CHECK_EQ_INT(run(&pg, &d1, &untouched), MFG_OK);
    CHECK(d1 == d0);
    check_reports(name, &full, stages, nstages, may_repeat);
    int n = full.n < MAXREC ? full.n : MAXREC;

    /* cancel points: both sides of every stage change, and `samples` evenly spaced */
    char *want = calloc((size_t)n, 1);
    for (int i = 0; i < n; i++)
        if (i == 0 || i == n - 1 || strcmp(full.stage[i], full.stage[i - 1]) != 0 ||
            (i + 1 < n && strcmp(full.stage[i], full.stage[i + 1]) != 0))
            want[i] = 1;
    for (int s = 0; s < samples && n > 1; s++)
        want[(int)((long long)s * (n - 1) / (samples > 1 ? samples - 1 : 1))] = 1;
    int ncancel = 0;
    recorder rc = {0};
    for (int k = 0; k < n; k++) {
        if (!want[k])
            continue;
        ncancel++;
        rec_init(&rc, k);
        mfg_progress pc = {record, &rc};
        uint64_t dc = 0;
        untouched = 0;
        mfg_status st = run(&pc, &dc, &untouched);
        if (st != MFG_ERR_CANCELLED)
            fprintf(stderr, "%s: cancel at report %d of %d (%s): status %d (%s)\n", name, k, n,
                    full.stage[k], (int)st, mfg_last_error());
        CHECK_EQ_INT(st, MFG_ERR_CANCELLED);
        CHECK(untouched);
        CHECK_EQ_INT(rc.n, k + 1);
        CHECK_EQ_INT(rc.after_cancel, 0);
        char expect[256];
        snprintf(expect, sizeof expect, "cancelled in stage \"%s\"", rc.stage[k]);
        CHECK(strstr(mfg_last_error(), expect) != NULL);
        CHECK(strstr(mfg_last_error(), name) != NULL);
        /* the same run without cancel stays deterministic: the cancelled call saw the
         * same reports up to k */
        CHECK(strcmp(rc.stage[k], full.stage[k]) == 0);
        CHECK(rc.f[k] == full.f[k]);
    }
    CHECK(strcmp(mfg_status_str(MFG_ERR_CANCELLED), "cancelled") == 0);
    printf("%s: %d reports, %d cancel points checked\n", name, n, ncancel);
    free(want);
    rec_free(&rc);
    rec_free(&full);
    return n;
}

/* ---- inputs ---------------------------------------------------------------------------- */

static tmesh cup; /* examples/parts/cup.py, 32 segments */

static uint64_t mesh_digest(const mfg_mesh *m)
{
    uint64_t h = fnv(FNV0, m->vertices, (size_t)(3 * m->nvertices) * sizeof(double));
    return fnv(h, m->triangles, (size_t)(3 * m->ntriangles) * sizeof(int64_t));
}

/* rays: the cup against points on a grid through it, along z */
#define RAY_N 120000
static double *ray_pts;

static mfg_status run_rays(const mfg_progress *pg, uint64_t *digest, int *untouched)
{
    static uint8_t out[RAY_N];
    memset(out, 0xee, sizeof out);
    const double d[3] = {0.1, 0.2, 1.0};
    mfg_status st = mfg_ray_blocked_p(cup.xyz, cup.nv, cup.tri, cup.nt, ray_pts, NULL, RAY_N,
                                      d, out, pg);
    int same = 1;
    for (int i = 0; i < RAY_N; i++)
        same &= out[i] == 0xee;
    *untouched = same;
    if (st == MFG_OK)
        *digest = fnv(FNV0, out, sizeof out);
    return st;
}

/* maxisect: visibility maps of random clusters of normals */
#define MI_SETS 60
static double mi_level;
static double *mi_v;
static int64_t mi_off[MI_SETS + 1];
static int32_t mi_kind[MI_SETS];
static int32_t mi_closed[MI_SETS];

static void make_maps(void)
{
    mi_v = malloc(3 * 64 * MI_SETS * sizeof *mi_v);
    mi_off[0] = 0;
    for (int s = 0; s < MI_SETS; s++) {
        double c[3] = {rng_uniform(-1, 1), rng_uniform(-1, 1), rng_uniform(-1, 1)};
        double n[3 * 6];
        for (int k = 0; k < 6; k++)
            for (int i = 0; i < 3; i++)
                n[3 * k + i] = c[i] + rng_uniform(-0.8, 0.8);
        mfg_spoly *vm = NULL;
        if (mfg_visibility_map(n, 6, 0.0, &vm) != MFG_OK || vm->nvertices > 64) {
            mfg_spoly_free(vm);
            s--;
            continue;
        }
        memcpy(mi_v + 3 * mi_off[s], vm->vertices, (size_t)(3 * vm->nvertices) * sizeof(double));
        mi_off[s + 1] = mi_off[s] + vm->nvertices;
        mi_kind[s] = vm->kind;
        mi_closed[s] = vm->closed;
        mfg_spoly_free(vm);
    }
    /* the level: three below the maximum (the runner-up local maxima too: a longer search) */
    mfg_regions *r = NULL;
    if (mfg_max_intersection(mi_v, mi_off, mi_kind, mi_closed, MI_SETS, NULL, &r) == MFG_OK) {
        mi_level = r->weight - 3;
        mfg_regions_free(r);
    }
}

static uint64_t regions_digest(const mfg_regions *r)
{
    int64_t nr = r->nregions;
    uint64_t h = fnv(FNV0, &r->weight, sizeof r->weight);
    h = fnv(h, &nr, sizeof nr);
    h = fnv(h, r->kinds, (size_t)nr * sizeof(int32_t));
    h = fnv(h, r->vertex_offsets, (size_t)(nr + 1) * sizeof(int64_t));
    h = fnv(h, r->vertices, (size_t)(3 * r->vertex_offsets[nr]) * sizeof(double));
    h = fnv(h, r->cover_offsets, (size_t)(nr + 1) * sizeof(int64_t));
    h = fnv(h, r->cover, (size_t)r->cover_offsets[nr] * sizeof(int64_t));
    h = fnv(h, r->centres, (size_t)(3 * nr) * sizeof(double));
    return fnv(h, r->margins, (size_t)nr * sizeof(double));
}

static int mi_mode;
static mfg_status run_maxisect(const mfg_progress *pg, uint64_t *digest, int *untouched)
{
    mfg_regions *r = SENTINEL;
    mfg_status st;
    if (mi_mode == 0)
        st = mfg_max_intersection_p(mi_v, mi_off, mi_kind, mi_closed, MI_SETS, NULL, &r, pg);
    else if (mi_mode == 1)
        st = mfg_level_regions_p(mi_v, mi_off, mi_kind, mi_closed, MI_SETS, NULL, mi_level, &r, pg);
    else
        st = mfg_min_intersection_p(mi_v, mi_off, mi_kind, mi_closed, MI_SETS, NULL, &r, pg);
    *untouched = r == SENTINEL;
    if (st == MFG_OK) {
        *digest = regions_digest(r);
        mfg_regions_free(r);
    }
    return st;
}

/* axis: a star with many spikes and a hole */
#define AX_N 1200
static double ax_xy[2 * (AX_N + 4)];
static int64_t ax_off[3];

static void make_star(void)
{
    for (int i = 0; i < AX_N; i++) {
        double a = 2 * M_PI * i / AX_N, r = i % 2 ? 100 : 90 + 3 * sin(7 * a);
        ax_xy[2 * i] = r * cos(a);
        ax_xy[2 * i + 1] = r * sin(a);
    }
    const double hole[4][2] = {{-10, -10}, {-10, 10}, {10, 10}, {10, -10}};
    for (int k = 0; k < 4; k++) {
        ax_xy[2 * (AX_N + k)] = hole[k][0];
        ax_xy[2 * (AX_N + k) + 1] = hole[k][1];
    }
    ax_off[0] = 0;
    ax_off[1] = AX_N;
    ax_off[2] = AX_N + 4;
}

static mfg_status run_axis(const mfg_progress *pg, uint64_t *digest, int *untouched)
{
    struct mfg_medial_axis *a = SENTINEL;
    mfg_status st = mfg_medial_axis_p(ax_xy, ax_off, 2, 1e-2, &a, pg);
    *untouched = a == SENTINEL;
    if (st == MFG_OK) {
        uint64_t h = fnv(FNV0, a->branch_offsets, (size_t)(a->nbranches + 1) * sizeof(int64_t));
        h = fnv(h, a->points, (size_t)(2 * a->npoints) * sizeof(double));
        h = fnv(h, a->radii, (size_t)a->npoints * sizeof(double));
        h = fnv(h, a->junction_points, (size_t)(2 * a->njunctions) * sizeof(double));
        *digest = fnv(h, a->junction_elements,
                      (size_t)a->junction_offsets[a->njunctions] * sizeof(int64_t));
        mfg_medial_axis_free(a);
    }
    return st;
}

/* sweep: the cup about an axis beside it, by 1.5 rad */
static mfg_status run_sweep(const mfg_progress *pg, uint64_t *digest, int *untouched)
{
    const double ap[3] = {30, 5, 0}, ad[3] = {0.2, 0.1, 1};
    mfg_mesh *m = SENTINEL;
    mfg_sweep_stats S, S0;
    memset(&S, 0x7b, sizeof S);
    S0 = S;
    mfg_status st = mfg_rotational_sweep_p(cup.xyz, cup.nv, cup.tri, cup.nt, ap, ad, 1.5, 0.1,
                                           &m, &S, pg);
    *untouched = m == SENTINEL && memcmp(&S, &S0, sizeof S) == 0;
    if (st == MFG_OK) {
        *digest = fnv(mesh_digest(m), &S, sizeof S);
        mfg_mesh_free(m);
    }
    return st;
}

/* medial: the L-bracket, full medial surface */
static tmesh bracket;
static int md_threads = 1;
static double MD_TOL = 1.0;
static mfg_status run_medial(const mfg_progress *pg, uint64_t *digest, int *untouched)
{
    mfg_medial *m = SENTINEL;
    mfg_status st = mfg_medial_surface_p(bracket.xyz, bracket.nv, bracket.tri, bracket.nt, MD_TOL,
                                         MFG_MEDIAL_FULL, md_threads, &m, pg);
    *untouched = m == SENTINEL;
    if (st == MFG_OK) {
        uint64_t h = fnv(FNV0, m->sheet_vertex_offsets, (size_t)(m->nsheets + 1) * sizeof(int64_t));
        h = fnv(h, m->sheet_vertices, (size_t)(3 * m->sheet_vertex_offsets[m->nsheets]) * sizeof(double));
        h = fnv(h, m->sheet_triangles,
                (size_t)(3 * m->sheet_triangle_offsets[m->nsheets]) * sizeof(int64_t));
        h = fnv(h, m->seam_point_offsets, (size_t)(m->nseams + 1) * sizeof(int64_t));
        h = fnv(h, m->seam_points, (size_t)(3 * m->seam_point_offsets[m->nseams]) * sizeof(double));
        *digest = fnv(h, m->junction_points, (size_t)(3 * m->njunctions) * sizeof(double));
        mfg_medial_free(m);
    }
    return st;
}

/* ---- the families ---------------------------------------------------------------------- */

static void test_rays(void)
{
    static const char *const st[] = {"rays: index", "rays: queries", "rays: done"};
    int n = check_entry("mfg_ray_blocked", run_rays, st, 3, 0, 12);
    CHECK(n >= 10); /* 120000 points, a report every 8192 */
}

static void test_maxisect(void)
{
    static const char *const st[] = {"maxisect: sets", "maxisect: search", "maxisect: regions",
                                     "maxisect: done"};
    static const char *const names[] = {"mfg_max_intersection", "mfg_level_regions",
                                        "mfg_min_intersection"};
    for (mi_mode = 0; mi_mode < 3; mi_mode++) {
        int n = check_entry(names[mi_mode], run_maxisect, st, 4, 0, 12);
        CHECK(n >= 4);
    }
}

static void test_axis(void)
{
    static const char *const st[] = {"axis: setup", "axis: branches", "axis: output",
                                     "axis: done"};
    int n = check_entry("mfg_medial_axis", run_axis, st, 4, 0, 12);
    CHECK(n >= 8);
}

static void test_sweep(void)
{
    static const char *const st[] = {"sweep: setup",         "sweep: contour",
                                     "sweep: strips",        "sweep: intersections",
                                     "sweep: faces",         "sweep: boundary",
                                     "sweep: output",        "sweep: done"};
    int n = check_entry("mfg_rotational_sweep", run_sweep, st, 8, 1, 6);
    CHECK(n >= 10);
}

static void test_medial(void)
{
    static const char *const st[] = {"medial: elements", "medial: octree", "medial: sheets",
                                     "medial: junctions", "medial: assembly", "medial: done"};
    md_threads = 1; /* one thread: the reports are the same run after run */
    int n = check_entry("mfg_medial_surface", run_medial, st, 6, 0, 6);
    CHECK(n >= 10);
    /* with worker threads: the result is the same, a cancel in each parallel stage stops
     * them all and frees everything */
    md_threads = 3;
    uint64_t d1 = 0, d3 = 0;
    int untouched = 0;
    md_threads = 1;
    CHECK_EQ_INT(run_medial(NULL, &d1, &untouched), MFG_OK);
    md_threads = 3;
    recorder r = {0};
    rec_init(&r, -1);
    mfg_progress pg = {record, &r};
    CHECK_EQ_INT(run_medial(&pg, &d3, &untouched), MFG_OK);
    CHECK(d3 == d1);
    check_reports("mfg_medial_surface (3 threads)", &r, st, 6, 0);
    static const char *const par[] = {"medial: octree", "medial: sheets", "medial: junctions"};
    for (int s = 0; s < 3; s++) {
        int first = -1, count = 0;
        for (int i = 0; i < r.n; i++)
            if (strcmp(r.stage[i], par[s]) == 0) {
                if (first < 0)
                    first = i;
                count++;
            }
        CHECK(first >= 0);
        /* at the stage's start (always reported), and at its second report, which the
         * caller's thread makes only if it took enough units itself: then cancelled, else
         * the call completes */
        for (int nth = 0; nth < 2 && nth < count; nth++) {
            recorder rc = {0};
            rec_init(&rc, -1);
            rc.cancel_stage = par[s];
            rc.cancel_nth = nth;
            mfg_progress pc = {record, &rc};
            uint64_t dc = 0;
            untouched = 0;
            mfg_status st = run_medial(&pc, &dc, &untouched);
            if (nth == 0 || rc.cancel_at >= 0) {
                CHECK_EQ_INT(st, MFG_ERR_CANCELLED);
                CHECK(untouched);
                CHECK_EQ_INT(rc.after_cancel, 0);
                char expect[128];
                snprintf(expect, sizeof expect, "cancelled in stage \"%s\"", par[s]);
                CHECK(strstr(mfg_last_error(), expect) != NULL);
            } else {
                CHECK_EQ_INT(st, MFG_OK);
                CHECK(dc == d1);
            }
            rec_free(&rc);
        }
    }
    rec_free(&r);
    md_threads = 1;
}

/* The interval between reports on mid-size inputs: the largest gap in wall time (outside
 * the sanitizer build, which is ~10x slower) and the number of reports. */
static double max_gap(const recorder *r, double t0, double t1, const char **after,
                      const char **before)
{
    double g = r->n > 0 ? r->t[0] - t0 : t1 - t0;
    *after = "(start)";
    *before = r->n > 0 ? r->stage[0] : "(end)";
    int n = r->n < MAXREC ? r->n : MAXREC;
    for (int i = 1; i < n; i++)
        if (r->t[i] - r->t[i - 1] > g) {
            g = r->t[i] - r->t[i - 1];
            *after = r->stage[i - 1];
            *before = r->stage[i];
            if (getenv("MFG_GAP_DEBUG"))
                fprintf(stderr, "gap %.1f ms between fractions %.4f and %.4f\n",
                        1e3 * g, r->f[i - 1], r->f[i]);
        }
    if (n > 0 && t1 - r->t[n - 1] > g) {
        g = t1 - r->t[n - 1];
        *after = r->stage[n - 1];
        *before = "(end)";
    }
    return g;
}

static void test_interval(void)
{
    recorder r = {0};
    struct {
        const char *name;
        runner run;
    } e[] = {{"mfg_ray_blocked", run_rays},  {"mfg_max_intersection", run_maxisect},
             {"mfg_medial_axis", run_axis}, {"mfg_rotational_sweep", run_sweep},
             {"mfg_medial_surface", run_medial}};
    mi_mode = 0;
    md_threads = 2;
    for (int i = 0; i < 5; i++) {
        rec_init(&r, -1);
        mfg_progress pg = {record, &r};
        uint64_t d = 0;
        int untouched = 0;
        double t0 = now();
        CHECK_EQ_INT(e[i].run(&pg, &d, &untouched), MFG_OK);
        const char *after, *before;
        double t1 = now(), g = max_gap(&r, t0, t1, &after, &before);
        printf("interval: %-22s %6.1f ms total, %5d reports, largest gap %6.2f ms (%s -> %s)\n",
               e[i].name, 1e3 * (t1 - t0), r.n, 1e3 * g, after, before);
        /* 2 cores shared by several jobs: generous, yet far below "frozen" */
        if (!UNDER_SANITIZER)
            CHECK(g < 0.25);
    }
    md_threads = 1;
    rec_free(&r);
}

int main(int argc, char **argv)
{
    const char *only = argc > 1 ? argv[1] : NULL;
    ms_cup(&cup, 32);
    memset(&bracket, 0, sizeof bracket);
    ms_l_bracket(&bracket);
    ray_pts = malloc(3 * RAY_N * sizeof *ray_pts);
    for (int i = 0; i < RAY_N; i++) {
        ray_pts[3 * i] = rng_uniform(-22, 22);
        ray_pts[3 * i + 1] = rng_uniform(-22, 22);
        ray_pts[3 * i + 2] = rng_uniform(-2, 32);
    }
    make_maps();
    make_star();
    if (!only || !strcmp(only, "rays"))
        test_rays();
    if (!only || !strcmp(only, "maxisect"))
        test_maxisect();
    if (!only || !strcmp(only, "axis"))
        test_axis();
    if (!only || !strcmp(only, "sweep"))
        test_sweep();
    if (!only || !strcmp(only, "medial"))
        test_medial();
    if (!only || !strcmp(only, "interval"))
        test_interval();
    free(ray_pts);
    free(mi_v);
    return mfg_test_report("progress_cancel");
}
