/* SPDX-License-Identifier: LGPL-2.1-or-later */
/* alloc_fail.c - allocation-failure injection over every entry point: for N = 1, 2, 3, ...
 * the N-th allocation of the call fails, until a call completes without a failure.  Each
 * time: MFG_ERR_NOMEM with a detail and the output untouched (or success with the same
 * result as without failures), nothing leaked, no crash. */
#define _GNU_SOURCE /* fork, mmap, strsignal */
#include <math.h>
#include <signal.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>
#include <sys/wait.h>
#include <unistd.h>

#include "alloc_shim.h"
#include "mfgeom.h"

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

/* More allocations than any case below makes: a call still failing after this many is a
 * loop that retries forever. */
#define MAX_ATTEMPTS 200000

/* ------------------------------------------------------------------------ */
/* Inputs (built once, before any window opens)                             */
/* ------------------------------------------------------------------------ */

static unsigned long long rng_state = 0x9E3779B97F4A7C15ULL;
static double uniform(double lo, double hi)
{
    rng_state ^= rng_state << 13;
    rng_state ^= rng_state >> 7;
    rng_state ^= rng_state << 17;
    return lo + (hi - lo) * ((double)(rng_state >> 11) * 0x1p-53);
}

/* Planar: a 96-vertex star with a square hole, and points around and on it. */
enum { STAR = 96, NPTS = 400 };
static double ring_xy[2 * (STAR + 4)];
static int64_t ring_off[3];
static double pts[2 * NPTS];
static mfg_region *prepared; /* for the region_classify and region_stats cases */

static void make_planar(void)
{
    for (int i = 0; i < STAR; i++) {
        double a = 2 * M_PI * i / STAR, r = i % 2 ? 10.0 : 4.0 + uniform(0, 1);
        ring_xy[2 * i] = r * cos(a);
        ring_xy[2 * i + 1] = r * sin(a);
    }
    const double hole[8] = {-1, -1, -1, 1, 1, 1, 1, -1};
    memcpy(ring_xy + 2 * STAR, hole, sizeof hole);
    ring_off[0] = 0;
    ring_off[1] = STAR;
    ring_off[2] = STAR + 4;
    for (int i = 0; i < NPTS; i++) {
        pts[2 * i] = uniform(-11, 11);
        pts[2 * i + 1] = uniform(-11, 11);
    }
    pts[0] = ring_xy[0]; /* a vertex: ON */
    pts[1] = ring_xy[1];
}

/* Spherical: random normals in a cap, normals on one great circle, and maps to
 * intersect: small-circle polygons around nearby centres (they overlap in many ways, so
 * the search subdivides cells and builds several regions), an arc and a point. */
enum { NNORM = 300, NCIRC = 64, NCONE = 200, NPOLY = 40, PV = 7 };
static double normals[3 * NNORM], circle_normals[3 * NCIRC], cone_normals[3 * NCONE];
static double sv[3 * (NPOLY * PV + 3 + 1)];
static int64_t soff[NPOLY + 3];
static int32_t skinds[NPOLY + 2];
static double sweights[NPOLY + 2];

static void unit(double *v)
{
    double n = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    v[0] /= n;
    v[1] /= n;
    v[2] /= n;
}

static void make_spherical(void)
{
    for (int i = 0; i < NNORM; i++) {
        normals[3 * i] = uniform(-0.6, 0.6);
        normals[3 * i + 1] = uniform(-0.6, 0.6);
        normals[3 * i + 2] = 1.0;
    }
    for (int i = 0; i < NCIRC; i++) { /* on the circle z = 0, within a half circle */
        double a = M_PI * 0.9 * i / (NCIRC - 1);
        circle_normals[3 * i] = cos(a);
        circle_normals[3 * i + 1] = sin(a);
        circle_normals[3 * i + 2] = 0.0;
    }
    for (int i = 0; i < NCONE; i++) { /* a tessellated cone: every normal a hull vertex */
        double a = 2 * M_PI * i / NCONE;
        cone_normals[3 * i] = 0.6 * cos(a);
        cone_normals[3 * i + 1] = 0.6 * sin(a);
        cone_normals[3 * i + 2] = 0.8;
    }
    int64_t k = 0;
    for (int p = 0; p < NPOLY; p++) {
        double c[3] = {uniform(-0.5, 0.5), uniform(-0.5, 0.5), 1.0};
        unit(c);
        double e1[3] = {c[2], 0, -c[0]}; /* orthogonal to c (c[1] aside: c[2] > 0) */
        double d = e1[0] * c[0] + e1[2] * c[2];
        for (int i = 0; i < 3; i++)
            e1[i] -= d * c[i];
        unit(e1);
        double e2[3] = {c[1] * e1[2] - c[2] * e1[1], c[2] * e1[0] - c[0] * e1[2],
                        c[0] * e1[1] - c[1] * e1[0]}; /* e1 x e2 = c: increasing angle is CCW */
        double rho = uniform(0.3, 0.6), a0 = uniform(0, 2 * M_PI);
        soff[p] = k;
        for (int i = 0; i < PV; i++, k++) {
            double a = a0 + 2 * M_PI * (i + uniform(0.1, 0.9)) / PV;
            for (int j = 0; j < 3; j++)
                sv[3 * k + j] = cos(rho) * c[j] + sin(rho) * (cos(a) * e1[j] + sin(a) * e2[j]);
        }
        skinds[p] = MFG_VM_POLYGON;
        sweights[p] = 1.0 + (p % 3);
    }
    /* an arc through the cluster and a point in it */
    const double arc[9] = {-0.3, 0.05, 1, 0, 0.05, 1, 0.3, 0.05, 1};
    soff[NPOLY] = k;
    for (int i = 0; i < 3; i++, k++) {
        memcpy(sv + 3 * k, arc + 3 * i, 3 * sizeof(double));
        unit(sv + 3 * k);
    }
    skinds[NPOLY] = MFG_VM_EDGE;
    sweights[NPOLY] = 2.5;
    soff[NPOLY + 1] = k;
    sv[3 * k] = 0.02;
    sv[3 * k + 1] = -0.01;
    sv[3 * k + 2] = 1.0;
    unit(sv + 3 * k);
    k++;
    skinds[NPOLY + 1] = MFG_VM_POINT;
    sweights[NPOLY + 1] = 1.5;
    soff[NPOLY + 2] = k;
}

/* Rotational sweep: a 2 x 1 x 1 box turned about an edge by 90 deg, and about a skew axis
 * through it by a full turn, at the coarsest tolerance (1: the fewest allocations, as each
 * failing N reruns the whole call; still ~10^4 and ~1.4 10^3 allocations). */
static const double box_xyz[24] = {0, 0, 0, 2, 0, 0, 0, 1, 0, 2, 1, 0, 0, 0, 1, 2, 0, 1, 0, 1, 1, 2, 1, 1};
static const int64_t box_tri[36] = {0, 2, 3, 0, 3, 1, 4, 5, 7, 4, 7, 6, 0, 1, 5, 0, 5, 4,
                                    2, 6, 7, 2, 7, 3, 0, 4, 6, 0, 6, 2, 1, 3, 7, 1, 7, 5};

/* ------------------------------------------------------------------------ */
/* Cases: how to call, compare and release each entry point's output        */
/* ------------------------------------------------------------------------ */

/* The output slot of one call: a library object or a buffer of answers. */
typedef union slot {
    void *ptr;
    uint8_t classes[NPTS];
    int64_t stats[4];
    struct {
        void *ptr; /* the mesh: the same place as ptr above */
        mfg_sweep_stats stats;
    } sweep;
} slot;

static void *const SENTINEL_PTR = (void *)&rng_state;
#define SENTINEL_BYTE 0xA5

typedef struct acase {
    const char *name;
    int kind; /* which output: see below */
    mfg_status (*call)(slot *out);
} acase;

enum { OUT_CLASSES, OUT_STATS, OUT_REGION, OUT_SPOLY, OUT_REGIONS, OUT_SWEEP };

static mfg_status call_classify(slot *o)
{
    return mfg_classify_points(ring_xy, ring_off, 2, pts, NPTS, 0.05, o->classes);
}
static mfg_status call_region_new(slot *o)
{
    return mfg_region_new(ring_xy, ring_off, 2, 0.05, (mfg_region **)&o->ptr);
}
static mfg_status call_region_classify(slot *o)
{
    return mfg_region_classify(prepared, pts, NPTS, o->classes);
}
static mfg_status call_region_stats(slot *o) { return mfg_region_stats(prepared, o->stats); }
static mfg_status call_vm(slot *o) { return mfg_visibility_map(normals, NNORM, 0.0, (mfg_spoly **)&o->ptr); }
static mfg_status call_vm_draft(slot *o)
{
    return mfg_visibility_map(normals, NNORM, 0.2, (mfg_spoly **)&o->ptr);
}
static mfg_status call_vm_circle(slot *o)
{
    return mfg_visibility_map(circle_normals, NCIRC, 0.0, (mfg_spoly **)&o->ptr);
}
static mfg_status call_vm_cone(slot *o)
{
    return mfg_visibility_map(cone_normals, NCONE, 0.0, (mfg_spoly **)&o->ptr);
}
static mfg_status call_vm_cone_draft(slot *o)
{
    return mfg_visibility_map(cone_normals, NCONE, 0.1, (mfg_spoly **)&o->ptr);
}
static mfg_status call_max(slot *o)
{
    return mfg_max_intersection(sv, soff, skinds, NULL, NPOLY + 2, sweights, (mfg_regions **)&o->ptr);
}
static mfg_status call_level(slot *o)
{
    return mfg_level_regions(sv, soff, skinds, NULL, NPOLY + 2, sweights, 6.0, (mfg_regions **)&o->ptr);
}
static mfg_status call_min(slot *o)
{
    return mfg_min_intersection(sv, soff, skinds, NULL, NPOLY + 2, sweights, (mfg_regions **)&o->ptr);
}

static mfg_status call_sweep_edge(slot *o)
{
    static const double ap[3] = {0, 0, 0}, ad[3] = {0, 0, 1};
    return mfg_rotational_sweep(box_xyz, 8, box_tri, 12, ap, ad, M_PI / 2, 1.0, (mfg_mesh **)&o->sweep.ptr,
                                &o->sweep.stats);
}
static mfg_status call_sweep_skew(slot *o)
{
    static const double ap[3] = {1, 0.5, 0.5}, ad[3] = {0.3, -0.2, 1};
    return mfg_rotational_sweep(box_xyz, 8, box_tri, 12, ap, ad, 2 * M_PI, 1.0, (mfg_mesh **)&o->sweep.ptr,
                                &o->sweep.stats);
}

static const acase CASES[] = {
    {"mfg_classify_points", OUT_CLASSES, call_classify},
    {"mfg_region_new", OUT_REGION, call_region_new},
    {"mfg_region_classify (prepared region)", OUT_CLASSES, call_region_classify},
    {"mfg_region_stats (prepared region)", OUT_STATS, call_region_stats},
    {"mfg_visibility_map (cap normals)", OUT_SPOLY, call_vm},
    {"mfg_visibility_map (draft 0.2)", OUT_SPOLY, call_vm_draft},
    {"mfg_visibility_map (normals on a circle)", OUT_SPOLY, call_vm_circle},
    {"mfg_visibility_map (tessellated cone)", OUT_SPOLY, call_vm_cone},
    {"mfg_visibility_map (cone, draft 0.1)", OUT_SPOLY, call_vm_cone_draft},
    {"mfg_max_intersection", OUT_REGIONS, call_max},
    {"mfg_level_regions", OUT_REGIONS, call_level},
    {"mfg_min_intersection", OUT_REGIONS, call_min},
    {"mfg_rotational_sweep (box about an edge)", OUT_SWEEP, call_sweep_edge},
    {"mfg_rotational_sweep (skew axis, full turn)", OUT_SWEEP, call_sweep_skew},
};
#define NCASES (sizeof CASES / sizeof CASES[0])

static void reset(const acase *c, slot *o)
{
    if (c->kind == OUT_CLASSES || c->kind == OUT_STATS) {
        memset(o, SENTINEL_BYTE, sizeof *o);
    } else if (c->kind == OUT_SWEEP) {
        memset(&o->sweep.stats, SENTINEL_BYTE, sizeof o->sweep.stats);
        o->sweep.ptr = SENTINEL_PTR;
    } else {
        o->ptr = SENTINEL_PTR;
    }
}

static int untouched(const acase *c, const slot *o)
{
    if (c->kind == OUT_CLASSES || c->kind == OUT_STATS) {
        const uint8_t *b = (const uint8_t *)o;
        for (size_t i = 0; i < sizeof *o; i++)
            if (b[i] != SENTINEL_BYTE)
                return 0;
        return 1;
    }
    if (c->kind == OUT_SWEEP) {
        const uint8_t *b = (const uint8_t *)&o->sweep.stats;
        for (size_t i = 0; i < sizeof o->sweep.stats; i++)
            if (b[i] != SENTINEL_BYTE)
                return 0;
    }
    return o->ptr == SENTINEL_PTR;
}

static int same_regions(const mfg_regions *a, const mfg_regions *b)
{
    if (a->weight != b->weight || a->nregions != b->nregions)
        return 0;
    int64_t n = a->nregions;
    if (memcmp(a->kinds, b->kinds, (size_t)n * sizeof(int32_t)) ||
        memcmp(a->closed, b->closed, (size_t)n * sizeof(int32_t)) ||
        memcmp(a->vertex_offsets, b->vertex_offsets, (size_t)(n + 1) * sizeof(int64_t)) ||
        memcmp(a->cover_offsets, b->cover_offsets, (size_t)(n + 1) * sizeof(int64_t)) ||
        memcmp(a->centres, b->centres, (size_t)n * 3 * sizeof(double)) ||
        memcmp(a->margins, b->margins, (size_t)n * sizeof(double)))
        return 0;
    return !memcmp(a->vertices, b->vertices, (size_t)a->vertex_offsets[n] * 3 * sizeof(double)) &&
           !memcmp(a->cover, b->cover, (size_t)a->cover_offsets[n] * sizeof(int64_t));
}

/* Same answers as the reference; a region is compared by what it answers. */
static int same(const acase *c, const slot *got, const slot *ref)
{
    switch (c->kind) {
    case OUT_CLASSES: return !memcmp(got->classes, ref->classes, sizeof got->classes);
    case OUT_STATS: return !memcmp(got->stats, ref->stats, sizeof got->stats);
    case OUT_REGION: {
        uint8_t a[NPTS], b[NPTS];
        int64_t sa[4], sb[4];
        return mfg_region_classify(got->ptr, pts, NPTS, a) == MFG_OK &&
               mfg_region_classify(ref->ptr, pts, NPTS, b) == MFG_OK && !memcmp(a, b, sizeof a) &&
               mfg_region_stats(got->ptr, sa) == MFG_OK && mfg_region_stats(ref->ptr, sb) == MFG_OK &&
               !memcmp(sa, sb, sizeof sa);
    }
    case OUT_SPOLY: {
        const mfg_spoly *a = got->ptr, *b = ref->ptr;
        return a->kind == b->kind && a->closed == b->closed && a->nvertices == b->nvertices &&
               !memcmp(a->vertices, b->vertices, (size_t)a->nvertices * 3 * sizeof(double));
    }
    case OUT_SWEEP: {
        const mfg_mesh *a = got->sweep.ptr, *b = ref->sweep.ptr;
        return a->nvertices == b->nvertices && a->ntriangles == b->ntriangles &&
               !memcmp(a->vertices, b->vertices, (size_t)a->nvertices * 3 * sizeof(double)) &&
               !memcmp(a->triangles, b->triangles, (size_t)a->ntriangles * 3 * sizeof(int64_t)) &&
               !memcmp(&got->sweep.stats, &ref->sweep.stats, sizeof got->sweep.stats);
    }
    default: return same_regions(got->ptr, ref->ptr);
    }
}

static void release(const acase *c, slot *o)
{
    if (c->kind == OUT_REGION)
        mfg_region_free(o->ptr);
    else if (c->kind == OUT_SPOLY)
        mfg_spoly_free(o->ptr);
    else if (c->kind == OUT_REGIONS)
        mfg_regions_free(o->ptr);
    else if (c->kind == OUT_SWEEP)
        mfg_mesh_free(o->sweep.ptr);
}

/* ------------------------------------------------------------------------ */

/* Where a crashing child was (shared with the parent). */
static volatile long *progress;

/* Runs one case for N = 1, 2, ... in this process; returns the number of failed checks. */
static int run_case(const acase *c)
{
    slot ref, got;
    reset(c, &ref);
    mfg_status st = c->call(&ref);
    if (st != MFG_OK) {
        fprintf(stderr, "%s: reference call failed: %s (%s)\n", c->name, mfg_status_str(st), mfg_last_error());
        return 1;
    }
    int bad = 0;
    long nomem = 0, ok_despite = 0, n;
    for (n = 1; n <= MAX_ATTEMPTS && bad < 10; n++) {
        *progress = n;
        reset(c, &got);
        alloc_shim_arm(n);
        st = c->call(&got);
        int ok = st == MFG_OK;
        /* compared and released inside the window: a result's blocks must all come back */
        int equal = ok ? same(c, &got, &ref) : 0;
        if (ok)
            release(c, &got);
        alloc_shim_stats s = alloc_shim_disarm();
        const char *msg = mfg_last_error();
        if (ok && !equal) {
            fprintf(stderr, "%s, allocation %ld failed: success, but a different result\n", c->name, n);
            bad++;
        }
        if (!ok && st != MFG_ERR_NOMEM) {
            fprintf(stderr, "%s, allocation %ld failed: status %s (%s), expected out of memory\n", c->name, n,
                    mfg_status_str(st), msg);
            bad++;
        }
        if (!ok && s.failed == 0) {
            fprintf(stderr, "%s: failure without a failed allocation (N = %ld)\n", c->name, n);
            bad++;
        }
        if (!ok && !msg[0]) {
            fprintf(stderr, "%s, allocation %ld failed: no mfg_last_error() detail\n", c->name, n);
            bad++;
        }
        if (!ok && !untouched(c, &got)) {
            fprintf(stderr, "%s, allocation %ld failed: output written\n", c->name, n);
            bad++;
        }
        if (s.net != 0) {
            fprintf(stderr, "%s, allocation %ld failed (status %s): %ld block(s) %s\n", c->name, n,
                    mfg_status_str(st), labs(s.net), s.net > 0 ? "leaked" : "freed too many");
            bad++;
        }
        nomem += st == MFG_ERR_NOMEM;
        ok_despite += ok && s.failed;
        if (s.failed == 0)
            break; /* fewer than n allocations: the call ran to its end */
    }
    if (n > MAX_ATTEMPTS) {
        fprintf(stderr, "%s: still failing after %d allocations\n", c->name, MAX_ATTEMPTS);
        bad++;
    }
    printf("%-42s %5ld allocation(s): %5ld x out of memory, %4ld x success despite a failure%s\n", c->name,
           n - 1, nomem, ok_despite, bad ? "  FAILED" : "");
    release(c, &ref);
    return bad;
}

int main(int argc, char **argv)
{
    /* sanity: the shim is in place (a build that bypassed it would test nothing) */
    alloc_shim_arm(1);
    void *p = malloc(16);
    alloc_shim_stats s = alloc_shim_disarm();
    if (p || s.failed != 1) {
        fprintf(stderr, "the failing allocator is not interposed\n");
        return 1;
    }
    make_planar();
    make_spherical();
    if (mfg_region_new(ring_xy, ring_off, 2, 0.05, &prepared) != MFG_OK) {
        fprintf(stderr, "cannot prepare the region: %s\n", mfg_last_error());
        return 1;
    }
    progress = mmap(NULL, sizeof *progress, PROT_READ | PROT_WRITE, MAP_SHARED | MAP_ANONYMOUS, -1, 0);
    if (progress == MAP_FAILED)
        return 1;
    const char *only = argc > 1 ? argv[1] : NULL;
    int failed = 0;
    fflush(stdout);
    for (size_t i = 0; i < NCASES; i++) {
        if (only && !strstr(CASES[i].name, only))
            continue;
        /* each case in a child: a crash is reported with the allocation that caused it,
         * and the other cases still run */
        *progress = 0;
        pid_t pid = fork();
        if (pid < 0)
            return 1;
        if (pid == 0) {
            int bad = run_case(&CASES[i]);
            fflush(stdout);
            _exit(bad ? 1 : 0);
        }
        int status;
        waitpid(pid, &status, 0);
        if (WIFSIGNALED(status)) {
            printf("%-42s CRASHED (signal %d, %s) when allocation %ld failed\n", CASES[i].name, WTERMSIG(status),
                   strsignal(WTERMSIG(status)), *progress);
            failed++;
        } else if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) {
            failed++;
        }
        fflush(stdout);
    }
    mfg_region_free(prepared);
    printf("alloc_fail: %d case(s) failed\n", failed);
    return failed ? 1 : 0;
}
