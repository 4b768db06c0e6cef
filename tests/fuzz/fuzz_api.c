/* SPDX-License-Identifier: LGPL-2.1-or-later */
/* fuzz_api.c - libFuzzer target for the raw C API: counts, offsets, kinds, closed flags,
 * weights, coordinates and NULL pointers decoded from the input and passed to every
 * entry point, which must answer consistently and never crash or hit undefined behaviour. */

/*
 * Build (see run_fuzz.sh): like fuzz_pointclass.c, with tests/fuzz/fuzz_api.c.
 *
 * The arrays handed to the library are always as long as the counts they are passed
 * with claim, except for counts and offsets that no caller can own memory for (negative,
 * or 2^59 and more): those the library must reject before reading through them.  So
 * every sanitizer report is the library's fault.
 *
 * Input: four sections read one after the other (every read past the end gives zero
 * bytes): planar rings + points, normals, spherical sets, a rotational sweep.  Each
 * section starts with a flags byte; counts and offsets use rd_count / rd_offsets below.
 *
 * Checked (failure -> __builtin_trap):
 *  - every status is MFG_OK or an error with a non-empty mfg_last_error(); never
 *    MFG_ERR_INTERNAL; outputs untouched on failure;
 *  - point classification and visibility maps: MFG_OK exactly when the input is valid
 *    by the header's rules (the harness decides validity independently);
 *  - spherical sets: an input that breaks a structural rule (count, offsets, NULL,
 *    kind, non-finite value, negative weight or level) is refused, never with NOMEM;
 *  - results are well formed (classes, region stats, kinds and vertex counts, unit
 *    vectors, offsets, cover indices, margins) and free cleanly; a prepared region
 *    answers like the one-shot call; every vertex of a visibility map sees every normal
 *    (d . p >= sin(draft) up to rounding); a maximum's weight is its cover's weight;
 *  - rotational sweep (tiny meshes, coarse tolerances): see fuzz_sweep.
 */

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "mfgeom.h"

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

#define SENTINEL 0xA5
#define IMPOSSIBLE ((int64_t)1 << 59) /* counts from here on cannot be backed by memory */

#include "fuzz_reader.h"

static const char *g_where = "";

static void fail(const char *what)
{
    fprintf(stderr, "fuzz_api: check failed in %s: %s (last error: \"%s\")\n", g_where, what,
            mfg_last_error());
    __builtin_trap();
}

#define CHECK(cond, what)  \
    do {                   \
        if (!(cond))       \
            fail(what);    \
    } while (0)

/* Hostile values for counts and offsets: negative, or beyond any array. */
static const int64_t HOSTILE[] = {-1, -2, -3, INT64_MIN, INT64_MIN + 1, INT64_MIN + 2,
                                  -((int64_t)1 << 40), INT64_MAX, INT64_MAX - 1, (int64_t)1 << 62,
                                  ((int64_t)1 << 61) + 3, ((int64_t)1 << 60) + 4, IMPOSSIBLE};
#define NHOSTILE (int)(sizeof HOSTILE / sizeof HOSTILE[0])

static int hostile_value(int64_t v) { return v < 0 || v >= IMPOSSIBLE; }

/* A count: mostly 0..max, sometimes hostile (then *hostile is set). */
static int64_t rd_count(reader *r, int64_t max, int *hostile)
{
    uint8_t b = rd_u8(r);
    if (b >= 0xF0) {
        *hostile = 1;
        if (b == 0xFF) { /* any 64-bit value, folded into the hostile range */
            int64_t v = (int64_t)rd_u64(r);
            return hostile_value(v) ? v : v | INT64_MIN;
        }
        return HOSTILE[(b - 0xF0) % NHOSTILE];
    }
    return b % (max + 1);
}

/*
 * n + 1 offsets for n items of up to per_item elements each, within cap elements.
 * Natural ones (0, then cumulative sizes), then optionally a few corrupted: a hostile
 * value, a step back, a first offset other than 0.  *hostile is set when a value the
 * library must refuse before reading the arrays appears; *broken when the sequence is
 * not 0, non-decreasing (a valid but short item is for the caller to judge).
 */
static void rd_offsets(reader *r, int64_t n, int64_t per_item, int64_t cap, int64_t *off,
                       int *hostile, int *broken)
{
    off[0] = 0;
    for (int64_t i = 0; i < n; i++) {
        int64_t sz = rd_u8(r) % (per_item + 1);
        off[i + 1] = off[i] + sz <= cap ? off[i] + sz : cap;
    }
    uint8_t ncorrupt = rd_u8(r);
    ncorrupt = ncorrupt >= 0xC0 ? 1 + (ncorrupt & 1) : 0;
    for (int c = 0; c < ncorrupt; c++) {
        uint8_t w = rd_u8(r), how = rd_u8(r);
        int64_t i = w % (n + 1);
        if (how < 0x80) {
            off[i] = HOSTILE[how % NHOSTILE];
        } else if (how < 0xC0) {
            /* step back (wrapping: off[i - 1] may already be a hostile INT64_MIN) / not 0 */
            off[i] = i > 0 ? (int64_t)((uint64_t)off[i - 1] - 1 - (how & 3)) : 1 + (how & 3);
        } else {
            off[i] = (how & 0x3F) % (cap + 1); /* some small value */
        }
    }
    for (int64_t i = 0; i <= n; i++)
        if (hostile_value(off[i]))
            *hostile = 1;
    if (off[0] != 0)
        *broken = 1;
    for (int64_t i = 0; i < n; i++)
        if (off[i + 1] < off[i])
            *broken = 1;
}

/* Coordinates: small values, raw doubles, or the edges of the accepted range. */
static double rd_coord(reader *r, int mode)
{
    static const double special[] = {0.0, -0.0, NAN, INFINITY, -INFINITY, 1e-300, -1e300,
                                     MFG_MIN_COORD, MFG_MAX_COORD, MFG_MIN_COORD * 0.5,
                                     MFG_MAX_COORD * 2, 4.9406564584124654e-324, 1.0, -1.0};
    switch (mode & 3) {
    case 0:
        return (double)(int8_t)rd_u8(r) * 0.25;
    case 1:
        return rd_f64(r);
    case 2: {
        uint8_t b = rd_u8(r);
        if (b >= 0xF0)
            return special[(b - 0xF0) % (sizeof special / sizeof special[0])];
        return (double)(int8_t)b * 0.125;
    }
    default:
        return ldexp((double)(int8_t)rd_u8(r), (int)(rd_u8(r) % 64) - 32);
    }
}

static int coord_ok(double v)
{
    double a = fabs(v);
    return v == 0.0 || (a >= MFG_MIN_COORD && a <= MFG_MAX_COORD);
}

static int untouched(const uint8_t *out, int64_t n)
{
    for (int64_t i = 0; i < n; i++)
        if (out[i] != SENTINEL)
            return 0;
    return 1;
}

/* Any status: known, never internal, a detail on failure. */
static void check_status(mfg_status st)
{
    CHECK(st >= MFG_OK && st <= MFG_ERR_INTERNAL, "unknown status");
    CHECK(st != MFG_ERR_INTERNAL, "MFG_ERR_INTERNAL (broken invariant)");
    if (st != MFG_OK)
        CHECK(mfg_last_error()[0] != '\0', "failure without a detail");
}

/* ------------------------------------------------------------------------ */
/* Point classification                                                     */
/* ------------------------------------------------------------------------ */

#define PC_RINGS 6
#define PC_VERTS 24
#define PC_CAP (PC_RINGS * PC_VERTS)
#define PC_POINTS 32

static void fuzz_pointclass(reader *r)
{
    g_where = "point classification";
    uint8_t flags = rd_u8(r);
    int cmode = flags & 3, hostile = 0, broken = 0;
    int64_t nrings = rd_count(r, PC_RINGS, &hostile);
    static int64_t off[PC_RINGS + 1];
    int64_t noff = nrings >= 0 && nrings <= PC_RINGS ? nrings : 1; /* array as long as claimed */
    rd_offsets(r, noff, PC_VERTS, PC_CAP, off, &hostile, &broken);
    static double xy[2 * PC_CAP];
    for (int64_t k = 0; k < 2 * PC_CAP; k++)
        xy[k] = k < 4 * PC_VERTS ? rd_coord(r, cmode) : (double)(k % 7); /* the rest: cheap */
    double tol = (flags & 4) ? rd_coord(r, 1) : (double)rd_u8(r) * 0.0625;
    int hostile_np = 0;
    int64_t np = rd_count(r, PC_POINTS, &hostile_np);
    static double pts[2 * PC_POINTS];
    for (int64_t k = 0; k < 2 * PC_POINTS; k++)
        pts[k] = k < 2 * (np >= 0 && np <= PC_POINTS ? np : 0) ? rd_coord(r, cmode) : 0.0;
    uint8_t nulls = (flags & 0x80) ? rd_u8(r) : 0;
    const double *xyp = (nulls & 1) ? NULL : xy, *ptsp = (nulls & 4) ? NULL : pts;
    const int64_t *offp = (nulls & 2) ? NULL : off;
    static uint8_t out1[PC_POINTS], out2[PC_POINTS];
    uint8_t *outp = (nulls & 8) ? NULL : out1;

    /* Valid by the header's rules (checked here independently of the library). */
    int valid = !hostile && !broken && nrings >= 1 && offp && xyp;
    for (int64_t i = 0; valid && i < nrings; i++)
        valid = off[i + 1] - off[i] >= 3;
    for (int64_t k = 0; valid && k < 2 * off[nrings]; k++)
        valid = coord_ok(xy[k]);
    valid = valid && tol >= 0 && coord_ok(tol);
    int points_valid = !hostile_np && (np == 0 || (ptsp && outp));
    for (int64_t k = 0; points_valid && k < 2 * np; k++)
        points_valid = coord_ok(pts[k]);

    memset(out1, SENTINEL, sizeof out1);
    mfg_status st = mfg_classify_points(xyp, offp, nrings, ptsp, np, tol, outp);
    check_status(st);
    CHECK((st == MFG_OK) == (valid && points_valid), "mfg_classify_points: status disagrees with the input's validity");
    if (hostile || hostile_np)
        CHECK(st != MFG_ERR_NOMEM, "an impossible count reported as out of memory");
    if (st != MFG_OK)
        CHECK(untouched(out1, PC_POINTS), "mfg_classify_points wrote its output on failure");
    else
        for (int64_t i = 0; i < np; i++)
            CHECK(out1[i] <= MFG_ON, "class not OUT/IN/ON");

    /* The 2-D medial axis of the same rings (flags bit 6; issue 22), at a tolerance of at
     * least 1/64 of the rings' extent (cost bounded): structurally invalid input refused,
     * never MFG_ERR_INTERNAL, nothing written on failure, the result's samples finite with
     * radii >= 0 and branch offsets ascending. */
    if (flags & 0x40) {
        g_where = "mfg_medial_axis";
        double ext = 0, atol = tol;
        for (int64_t k = 0; valid && k < 2 * off[nrings]; k++)
            ext = fmax(ext, fabs(xy[k]));
        if (valid && atol > 0)
            atol = fmax(atol, ext / 64);
        struct mfg_medial_axis *asent = (struct mfg_medial_axis *)(uintptr_t)&asent, *ax = asent;
        st = mfg_medial_axis(xyp, offp, nrings, atol, (nulls & 16) ? NULL : &ax);
        check_status(st);
        if (!valid || !(atol > 0) || (nulls & 16))
            CHECK(st != MFG_OK, "mfg_medial_axis accepted invalid input");
        if (hostile)
            CHECK(st != MFG_ERR_NOMEM, "an impossible count reported as out of memory");
        if (st != MFG_OK) {
            CHECK(ax == asent, "mfg_medial_axis wrote its output on failure");
        } else {
            CHECK(ax != NULL && ax != asent, "no medial axis returned");
            for (int64_t b = 0; b < ax->nbranches; b++)
                CHECK(ax->branch_offsets[b] <= ax->branch_offsets[b + 1], "branch offsets decrease");
            for (int64_t i = 0; i < ax->npoints; i++)
                CHECK(isfinite(ax->points[2 * i]) && isfinite(ax->points[2 * i + 1]) && ax->radii[i] >= 0,
                      "a medial axis sample is not finite or has a negative radius");
            mfg_medial_axis_free(ax);
        }
    }

    mfg_region *sentinel = (mfg_region *)(uintptr_t)&sentinel, *region = sentinel;
    g_where = "mfg_region_new";
    st = mfg_region_new(xyp, offp, nrings, tol, (nulls & 16) ? NULL : &region);
    check_status(st);
    CHECK((st == MFG_OK) == (valid && !(nulls & 16)), "mfg_region_new: status disagrees with the input's validity");
    if (st != MFG_OK) {
        CHECK(region == sentinel, "mfg_region_new wrote out_region on failure");
        return;
    }
    CHECK(region != NULL && region != sentinel, "no region returned");
    g_where = "mfg_region_classify";
    memset(out2, SENTINEL, sizeof out2);
    st = mfg_region_classify((nulls & 32) ? NULL : region, ptsp, np, outp ? out2 : NULL);
    check_status(st);
    CHECK((st == MFG_OK) == (points_valid && !(nulls & 32)), "mfg_region_classify: status disagrees with validity");
    if (st == MFG_OK && valid && points_valid)
        CHECK(memcmp(out1, out2, (size_t)np) == 0, "prepared answers differ from one-shot answers");
    if (st != MFG_OK)
        CHECK(untouched(out2, PC_POINTS), "mfg_region_classify wrote its output on failure");
    int64_t stats[4] = {-7, -7, -7, -7};
    st = mfg_region_stats(region, (nulls & 64) ? NULL : stats);
    check_status(st);
    if (st == MFG_OK)
        CHECK(stats[0] >= 1 && stats[1] >= 1 && stats[2] >= 0 && stats[2] <= stats[0] * stats[1] && stats[3] >= 0,
              "bad region stats");
    else
        CHECK(stats[0] == -7 && stats[3] == -7, "mfg_region_stats wrote its output on failure");
    mfg_region_free(region);
}

/* ------------------------------------------------------------------------ */
/* Visibility maps                                                          */
/* ------------------------------------------------------------------------ */

#define VM_NORMALS 48

/* p / |p| computed without overflow or underflow (components are in range). */
static void unit_of(const double *p, double *u)
{
    double s = fmax(fabs(p[0]), fmax(fabs(p[1]), fabs(p[2])));
    double a = p[0] / s, b = p[1] / s, c = p[2] / s, n = sqrt(a * a + b * b + c * c);
    u[0] = a / n;
    u[1] = b / n;
    u[2] = c / n;
}

static int is_unit(const double *v)
{
    if (!isfinite(v[0]) || !isfinite(v[1]) || !isfinite(v[2]))
        return 0;
    return fabs(v[0] * v[0] + v[1] * v[1] + v[2] * v[2] - 1.0) < 1e-9;
}

static void fuzz_visibility(reader *r)
{
    g_where = "mfg_visibility_map";
    uint8_t flags = rd_u8(r);
    int hostile = 0;
    int64_t m = rd_count(r, VM_NORMALS, &hostile);
    static double nrm[3 * VM_NORMALS];
    /* with a hostile m every slot holds a valid normal: reading past the array must not
     * stop early at a bad value */
    int64_t mm = m >= 0 && m <= VM_NORMALS ? m : VM_NORMALS;
    int around = flags & 8; /* normals around a random axis: maps of every kind */
    double axis[3] = {rd_coord(r, 0), rd_coord(r, 0), 1.0 + rd_coord(r, 0)};
    for (int64_t k = 0; k < 3 * mm; k++)
        nrm[k] = around ? axis[k % 3] + (double)(int8_t)rd_u8(r) * (1.0 / 64) : rd_coord(r, flags & 3);
    if (flags & 16) /* some normals exactly on one great circle */
        for (int64_t i = 0; i < mm; i += 2)
            nrm[3 * i + 2] = 0.0;
    double draft = (flags & 4) ? rd_coord(r, 1) : (double)(rd_u8(r) % 16) * 0.1;
    uint8_t nulls = (flags & 0x80) ? rd_u8(r) : 0;

    int valid = !hostile && m >= 1 && !(nulls & 1) && !(nulls & 2) && draft >= 0 && draft < M_PI / 2;
    for (int64_t i = 0; valid && i < m; i++) {
        const double *p = nrm + 3 * i;
        valid = coord_ok(p[0]) && coord_ok(p[1]) && coord_ok(p[2]) && (p[0] != 0 || p[1] != 0 || p[2] != 0);
    }
    /* pi/2 rounds below the true pi/2: the library and the harness compare with the same
     * double, so they agree */
    mfg_spoly *sentinel = (mfg_spoly *)(uintptr_t)&sentinel, *map = sentinel;
    mfg_status st = mfg_visibility_map((nulls & 1) ? NULL : nrm, m, draft, (nulls & 2) ? NULL : &map);
    check_status(st);
    CHECK((st == MFG_OK) == valid, "status disagrees with the input's validity");
    if (hostile)
        CHECK(st != MFG_ERR_NOMEM, "an impossible count reported as out of memory");
    if (st != MFG_OK) {
        CHECK(map == sentinel, "out_map written on failure");
        return;
    }
    CHECK(map != NULL && map != sentinel, "no map returned");
    int64_t n = map->nvertices;
    switch (map->kind) {
    case MFG_VM_NULL: CHECK(n == 0, "NULL map with vertices"); break;
    case MFG_VM_POINT: CHECK(n == 1 || n == 2, "POINT map without 1 or 2 vertices"); break;
    case MFG_VM_EDGE: CHECK(n >= 3, "EDGE map with fewer than 3 vertices"); break;
    case MFG_VM_POLYGON: CHECK(n >= 3, "POLYGON map with fewer than 3 vertices"); break;
    default: fail("unknown map kind");
    }
    CHECK(map->closed == 0 || (map->closed == 1 && map->kind == MFG_VM_EDGE), "closed flag on a non-EDGE map");
    CHECK(n == 0 || map->vertices != NULL, "vertices missing");
    double s = draft > 0 ? sin(draft) : 0.0;
    for (int64_t k = 0; k < n; k++) {
        const double *d = map->vertices + 3 * k;
        CHECK(is_unit(d), "map vertex not a unit vector");
        for (int64_t i = 0; i < m; i++) {
            double u[3];
            unit_of(nrm + 3 * i, u);
            /* a vertex of the map sees every normal (within rounding and the drafted
             * polygon's documented 1e-4 rad slack is only on the inside) */
            CHECK(d[0] * u[0] + d[1] * u[1] + d[2] * u[2] >= s - 1e-9, "map vertex outside a normal's hemisphere");
        }
    }
    mfg_spoly_free(map);
}

/* ------------------------------------------------------------------------ */
/* Maximum / level / minimum intersection                                   */
/* ------------------------------------------------------------------------ */

#define SP_SETS 8
#define SP_VERTS 10
#define SP_CAP (SP_SETS * SP_VERTS)

/* Appends a convex spherical polygon (vertices on a small circle at increasing angles,
 * counter-clockwise from outside), an arc or a point of the given size. */
static void make_set(reader *r, int kind, int64_t nv, double *v)
{
    double lon = rd_u8(r) * (2 * M_PI / 256), lat = ((double)rd_u8(r) - 128) * (M_PI / 256);
    double c[3] = {cos(lat) * cos(lon), cos(lat) * sin(lon), sin(lat)};
    double e1[3] = {-sin(lon), cos(lon), 0}, e2[3] = {c[1] * e1[2] - c[2] * e1[1], c[2] * e1[0] - c[0] * e1[2],
                                                      c[0] * e1[1] - c[1] * e1[0]};
    double rho = 0.05 + rd_u8(r) * (1.4 / 256), a = rd_u8(r) * (2 * M_PI / 256);
    for (int64_t k = 0; k < nv; k++) {
        double dx, dy, rr = rho;
        if (kind == MFG_VM_POLYGON) {
            a += (2 * M_PI / (double)nv) * (0.2 + 0.6 * rd_u8(r) / 255.0);
            dx = cos(a);
            dy = sin(a);
        } else if (kind == MFG_VM_EDGE) { /* along the great circle through c in direction e1 */
            rr = (k - 0.5 * (double)(nv - 1)) * rho;
            dx = 1;
            dy = 0;
        } else {
            rr = 0;
            dx = dy = 0;
        }
        for (int i = 0; i < 3; i++)
            v[3 * k + i] = cos(rr) * c[i] + sin(rr) * (dx * e1[i] + dy * e2[i]);
        if (kind == MFG_VM_POINT && k == 1) /* the antipode */
            for (int i = 0; i < 3; i++)
                v[3 * k + i] = -v[i];
    }
}

static void check_regions(const mfg_regions *res, int mode, int64_t npolys, const int32_t *kinds,
                          const double *weights, double level)
{
    if (mode == 1)
        CHECK(res->weight == level, "level regions: weight is not the level asked for");
    else
        CHECK(isfinite(res->weight) && res->weight >= 0, "weight not finite and >= 0");
    CHECK(res->nregions >= 0 && res->nregions <= 100000, "bad region count");
    int64_t n = res->nregions;
    if (mode != 1)
        CHECK(n >= 1, "no region for the maximum / minimum");
    CHECK(res->vertex_offsets[0] == 0 && res->cover_offsets[0] == 0, "offsets not from 0");
    double total = 0;
    for (int64_t i = 0; i < npolys; i++)
        total += kinds[i] == MFG_VM_NULL ? 0.0 : weights ? weights[i] : 1.0;
    for (int64_t g = 0; g < n; g++) {
        int64_t v0 = res->vertex_offsets[g], v1 = res->vertex_offsets[g + 1];
        int64_t c0 = res->cover_offsets[g], c1 = res->cover_offsets[g + 1];
        CHECK(v1 >= v0 && c1 >= c0, "offsets decrease");
        int k = res->kinds[g];
        if (mode == 2)
            CHECK(k == MFG_VM_FACE && v1 == v0, "a minimum's region is not a FACE without vertices");
        else
            CHECK(k == MFG_VM_POINT || k == MFG_VM_EDGE || k == MFG_VM_POLYGON, "bad region kind");
        CHECK(res->closed[g] == 0 || (res->closed[g] == 1 && k == MFG_VM_EDGE), "closed flag on a non-EDGE region");
        if (mode != 2) {
            CHECK(k != MFG_VM_POINT || v1 - v0 == 1 || v1 - v0 == 2, "POINT region without 1 or 2 vertices");
            CHECK(k == MFG_VM_POINT || v1 - v0 >= 2, "EDGE/POLYGON region with too few vertices");
        }
        for (int64_t j = v0; j < v1; j++)
            CHECK(is_unit(res->vertices + 3 * j), "region vertex not a unit vector");
        CHECK(is_unit(res->centres + 3 * g), "centre not a unit vector");
        CHECK(isfinite(res->margins[g]) && res->margins[g] >= 0 && res->margins[g] <= M_PI, "bad margin");
        double w = 0;
        for (int64_t j = c0; j < c1; j++) {
            int64_t s = res->cover[j];
            CHECK(s >= 0 && s < npolys, "cover index out of range");
            CHECK(j == c0 || res->cover[j - 1] < s, "cover indices not increasing");
            if (s >= 0 && s < npolys)
                w += weights ? weights[s] : 1.0;
        }
        double eps = 1e-9 * fmax(total, 1.0);
        if (mode == 0 || mode == 2)
            CHECK(fabs(w - res->weight) <= eps, "region cover weight differs from the reported weight");
        else
            CHECK(w >= level - eps, "level region below the level");
    }
}

static void fuzz_sphere(reader *r)
{
    uint8_t flags = rd_u8(r);
    int hostile = 0, broken = 0, structural = 0;
    int64_t npolys = rd_count(r, SP_SETS, &hostile);
    int64_t nn = npolys >= 0 && npolys <= SP_SETS ? npolys : 1;
    static int64_t off[SP_SETS + 1];
    static int32_t kinds[SP_SETS], closed[SP_SETS];
    static double v[3 * SP_CAP], weights[SP_SETS];
    memset(kinds, 0, sizeof kinds);
    memset(closed, 0, sizeof closed);
    for (int64_t i = 0; i < SP_SETS; i++)
        weights[i] = 1.0;
    int generated = !(flags & 1);
    if (generated) { /* well-formed sets of random kinds and sizes */
        off[0] = 0;
        for (int64_t i = 0; i < nn; i++) {
            uint8_t b = rd_u8(r);
            int kind = b & 3;
            int64_t nv = kind == MFG_VM_POLYGON ? 3 + (b >> 2) % (SP_VERTS - 2)
                         : kind == MFG_VM_EDGE  ? 2 + (b >> 2) % 4
                         : kind == MFG_VM_POINT ? 1 + ((b >> 2) & 1)
                                                : 0;
            kinds[i] = kind;
            make_set(r, kind, nv, v + 3 * off[i]);
            off[i + 1] = off[i] + nv;
        }
        if (rd_u8(r) >= 0xE0) { /* one corrupted offset */
            uint8_t w = rd_u8(r), how = rd_u8(r);
            int64_t i = w % (nn + 1);
            off[i] = how < 0x80 ? HOSTILE[how % NHOSTILE] : (i > 0 ? off[i - 1] - 1 : 1);
            hostile |= hostile_value(off[i]);
            broken = 1;
        }
    } else { /* raw offsets, kinds and vertices */
        rd_offsets(r, nn, SP_VERTS, SP_CAP, off, &hostile, &broken);
        for (int64_t i = 0; i < nn; i++)
            kinds[i] = rd_u8(r) % 4;
        for (int64_t k = 0; k < 3 * SP_CAP; k++)
            v[k] = k < 3 * 2 * SP_VERTS ? rd_coord(r, flags >> 1) : 1.0 / (double)(k + 1);
    }
    if (flags & 8) { /* hostile kinds */
        uint8_t w = rd_u8(r);
        static const int32_t bad[] = {-1, 4, 5, INT32_MIN, INT32_MAX};
        kinds[w % SP_SETS] = bad[(w >> 3) % 5];
        structural |= w % SP_SETS < nn;
    }
    if (flags & 16) /* closed flags, including nonsense values */
        for (int64_t i = 0; i < nn; i++)
            closed[i] = (int32_t)(int8_t)rd_u8(r) % 3;
    int use_weights = flags & 32;
    if (use_weights)
        for (int64_t i = 0; i < nn; i++) {
            uint8_t b = rd_u8(r);
            weights[i] = b >= 0xF8 ? (double[]){NAN, INFINITY, -1.0, -0.0, 0.0, 1e-300, 1e200, -INFINITY}[b - 0xF8]
                                   : (double)(b % 16) * 0.5;
            structural |= !(weights[i] >= 0) || isinf(weights[i]);
        }
    double level = rd_u8(r) >= 0xF0 ? rd_f64(r) : (double)(rd_u8(r) % 12) * 0.5;
    uint8_t nulls = (flags & 0x80) ? rd_u8(r) : 0;
    const double *vp = (nulls & 1) ? NULL : v;
    const int64_t *offp = (nulls & 2) ? NULL : off;
    const int32_t *kp = (nulls & 4) ? NULL : kinds;
    const int32_t *cp = (flags & 16) && !(nulls & 8) ? closed : NULL;
    const double *wp = use_weights ? weights : NULL;

    structural |= hostile || broken || npolys < 1 || !offp || !kp;
    /* vertices are read only when the offsets are sound */
    if (!hostile && !broken && npolys >= 1) {
        if (off[npolys] > 0 && !vp)
            structural = 1;
        for (int64_t k = 0; vp && k < 3 * off[npolys]; k++)
            structural |= !coord_ok(v[k]);
    }
    static const char *const names[3] = {"mfg_max_intersection", "mfg_level_regions", "mfg_min_intersection"};
    int first = (nulls >> 4) % 3, count = (flags & 64) ? 3 : 1;
    for (int t = 0; t < count; t++) {
        int mode = (first + t) % 3;
        g_where = names[mode];
        mfg_regions *sentinel = (mfg_regions *)(uintptr_t)&sentinel, *res = sentinel;
        mfg_regions **outp = (nulls & 64) ? NULL : &res;
        mfg_status st = mode == 0   ? mfg_max_intersection(vp, offp, kp, cp, npolys, wp, outp)
                        : mode == 1 ? mfg_level_regions(vp, offp, kp, cp, npolys, wp, level, outp)
                                    : mfg_min_intersection(vp, offp, kp, cp, npolys, wp, outp);
        check_status(st);
        int refused = structural || !outp || (mode == 1 && !(level > -1e300 && level < 1e300));
        if (refused)
            CHECK(st != MFG_OK, "a structurally invalid input was accepted");
        if (hostile)
            CHECK(st != MFG_ERR_NOMEM, "an impossible count or offset reported as out of memory");
        if (st != MFG_OK) {
            CHECK(res == sentinel, "out written on failure");
            continue;
        }
        CHECK(res != NULL && res != sentinel, "no result returned");
        check_regions(res, mode, npolys, kinds, wp, level);
        mfg_regions_free(res);
    }
}

/* ------------------------------------------------------------------------ */
/* Rotational sweep                                                         */
/* ------------------------------------------------------------------------ */

#define SW_VERTS 12
#define SW_TRIS 24

/* Box corners k = (x: bit 0, y: bit 1, z: bit 2); 12 triangles, outward. */
static const int64_t SW_BOX[36] = {0, 2, 3, 0, 3, 1, 4, 5, 7, 4, 7, 6, 0, 1, 5, 0, 5, 4,
                                   2, 6, 7, 2, 7, 3, 0, 4, 6, 0, 6, 2, 1, 3, 7, 1, 7, 5};
/* Octahedron: vertices +x, -x, +y, -y, +z, -z; 8 triangles, outward. */
static const int64_t SW_OCTA[24] = {0, 2, 4, 2, 1, 4, 1, 3, 4, 3, 0, 4, 2, 0, 5, 1, 2, 5, 3, 1, 5, 0, 3, 5};

static double small_coord(reader *r) { return (double)(int8_t)rd_u8(r) * (1.0 / 32); }

/* The small mesh of the sweep and medial sections (described above fuzz_sweep), by the
 * section's flags byte: *hostile for counts no caller can back, *structural for anything
 * the entry points must refuse before looking at the geometry. */
typedef struct small_mesh {
    uint8_t flags; /* the section's flags byte (read first) */
    double xyz[3 * SW_VERTS];
    int64_t tri[3 * SW_TRIS];
    int64_t nv, nt;
    int hostile, structural;
} small_mesh;

static void read_small_mesh_into(reader *r, uint8_t flags, double *xyz, int64_t *tri, int64_t *nvp,
                                 int64_t *ntp, int *hostilep, int *structuralp)
{
    int hostile = 0, structural = 0;
    memset(xyz, 0, 3 * SW_VERTS * sizeof *xyz);
    memset(tri, 0, 3 * SW_TRIS * sizeof *tri);
    int64_t nv, nt;
    int kind = flags & 7;
    if (kind < 5) { /* generated */
        if (kind <= 1) { /* a box; kind 1: corners moved */
            double lo[3], hi[3];
            for (int c = 0; c < 3; c++) {
                lo[c] = small_coord(r);
                hi[c] = lo[c] + (double)(rd_u8(r) % 64) * (1.0 / 32);
            }
            for (int k = 0; k < 8; k++)
                for (int c = 0; c < 3; c++)
                    xyz[3 * k + c] = ((k >> c) & 1 ? hi[c] : lo[c]) + (kind == 1 ? small_coord(r) / 8 : 0.0);
            memcpy(tri, SW_BOX, sizeof SW_BOX);
            nv = 8;
            nt = 12;
        } else if (kind == 2) { /* a tetrahedron, turned outward */
            for (int k = 0; k < 12; k++)
                xyz[k] = small_coord(r);
            double a[3], b[3], c[3];
            for (int i = 0; i < 3; i++) {
                a[i] = xyz[3 + i] - xyz[i];
                b[i] = xyz[6 + i] - xyz[i];
                c[i] = xyz[9 + i] - xyz[i];
            }
            double det = a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) +
                         a[2] * (b[0] * c[1] - b[1] * c[0]);
            static const int64_t T[12] = {0, 2, 1, 0, 1, 3, 1, 2, 3, 0, 3, 2};
            memcpy(tri, T, sizeof T);
            if (det < 0) /* small multiples of 1/32: det is exact, its sign true */
                for (int t = 0; t < 4; t++) {
                    int64_t x = tri[3 * t + 1];
                    tri[3 * t + 1] = tri[3 * t + 2];
                    tri[3 * t + 2] = x;
                }
            nv = 4;
            nt = 4;
        } else { /* an octahedron with its own radius per vertex (star-shaped) */
            double centre[3] = {small_coord(r), small_coord(r), small_coord(r)};
            for (int k = 0; k < 6; k++) {
                double rad = (double)(1 + rd_u8(r) % 64) * (1.0 / 32);
                for (int c = 0; c < 3; c++)
                    xyz[3 * k + c] = centre[c] + (c == k / 2 ? (k % 2 ? -rad : rad) : 0.0);
            }
            memcpy(tri, SW_OCTA, sizeof SW_OCTA);
            nv = 6;
            nt = 8;
        }
        uint8_t damage = rd_u8(r);
        if (damage >= 0xC0) {
            int64_t t = rd_u8(r) % nt;
            switch (damage & 3) {
            case 0: /* dropped: the last triangle takes its place */
                memcpy(tri + 3 * t, tri + 3 * (nt - 1), 3 * sizeof *tri);
                nt--;
                break;
            case 1: { /* flipped */
                int64_t x = tri[3 * t + 1];
                tri[3 * t + 1] = tri[3 * t + 2];
                tri[3 * t + 2] = x;
                break;
            }
            case 2: /* repeated */
                memcpy(tri + 3 * nt, tri + 3 * t, 3 * sizeof *tri);
                nt++;
                break;
            default: /* an index out of range */
                tri[3 * t + rd_u8(r) % 3] = (damage & 4) ? nv : -1;
                structural = 1;
            }
        }
    } else { /* raw: counts, coordinates and indices from the input */
        nv = rd_count(r, SW_VERTS, &hostile);
        nt = rd_count(r, SW_TRIS, &hostile);
        int64_t mv = nv >= 0 && nv <= SW_VERTS ? nv : SW_VERTS, mt = nt >= 0 && nt <= SW_TRIS ? nt : SW_TRIS;
        for (int64_t k = 0; k < 3 * mv; k++)
            xyz[k] = rd_coord(r, kind == 5 ? 0 : flags >> 6);
        for (int64_t k = 0; k < 3 * mt; k++) {
            uint8_t b = rd_u8(r);
            tri[k] = b >= 0xF8 ? (int64_t[]){-1, INT64_MIN, INT64_MAX, SW_VERTS, mv, mv + 1, -2, 1 << 20}[b - 0xF8]
                               : (int64_t)(b % (mv ? mv : 1));
        }
        structural |= hostile;
        if (!hostile) {
            for (int64_t k = 0; k < 3 * nv; k++)
                structural |= !coord_ok(xyz[k]);
            for (int64_t k = 0; k < 3 * nt; k++)
                structural |= tri[k] < 0 || tri[k] >= nv;
        }
    }

    *nvp = nv;
    *ntp = nt;
    *hostilep = hostile;
    *structuralp = structural;
}

/* The flags byte, then the mesh it describes. */
static void read_small_mesh(reader *r, small_mesh *m)
{
    m->flags = rd_u8(r);
    read_small_mesh_into(r, m->flags, m->xyz, m->tri, &m->nv, &m->nt, &m->hostile, &m->structural);
}

/*
 * A small mesh (at most 12 vertices, 24 triangles: the sweep of a tiny mesh at a coarse
 * tolerance takes milliseconds), an axis, an angle and a tolerance.  The mesh is either
 * generated (a box, a box with its corners moved, a tetrahedron, a star-shaped
 * octahedron: closed, or zero-volume when degenerate) and then maybe damaged (a triangle
 * dropped, flipped, repeated; an index out of range), or raw bytes.  The tolerance is
 * never below 1/8 of the input's extent about the axis point.
 * Checked: structurally invalid arguments are refused (never with NOMEM for impossible
 * counts); otherwise the sweep refuses exactly the meshes mfg_mesh_check_closed refuses,
 * with the same status; a result is a closed solid (mfg_mesh_check_closed accepts it)
 * whose stats are its own, whose volume is at least the input's and at most that of the
 * cylinder about the axis holding every turned input (widened by the tolerance).
 */
static void fuzz_sweep(reader *r)
{
    g_where = "mfg_rotational_sweep";
    static small_mesh m; /* static, as the buffers were */
    read_small_mesh(r, &m);

    double ap[3], ad[3];
    uint8_t axis_mode = rd_u8(r);
    for (int c = 0; c < 3; c++) {
        ap[c] = axis_mode & 1 ? rd_coord(r, 2) : small_coord(r);
        ad[c] = axis_mode & 2 ? rd_coord(r, 2) : small_coord(r);
    }
    if (axis_mode & 4) { /* an axis through a vertex or along an edge */
        int64_t a = m.tri[0] >= 0 && m.tri[0] < SW_VERTS ? m.tri[0] : 0, b = m.tri[1] >= 0 && m.tri[1] < SW_VERTS ? m.tri[1] : 0;
        for (int c = 0; c < 3; c++) {
            ap[c] = m.xyz[3 * a + c];
            if (axis_mode & 8)
                ad[c] = m.xyz[3 * b + c] - m.xyz[3 * a + c];
        }
    }
    for (int c = 0; c < 3; c++)
        m.structural |= !coord_ok(ap[c]) || !coord_ok(ad[c]);
    m.structural |= ad[0] == 0 && ad[1] == 0 && ad[2] == 0;
    uint8_t ab = rd_u8(r);
    static const double ANGLES[] = {0.0, -0.0, -1.0, NAN, INFINITY, 2 * M_PI, 2 * M_PI + 0.5e-12,
                                    2 * M_PI + 2e-12, 2 * M_PI - 0.5e-12, 1e-300, 1e-9, M_PI};
    double angle = ab >= 0xF0 ? ANGLES[(ab - 0xF0) % (sizeof ANGLES / sizeof ANGLES[0])]
                              : (double)(ab + 1) * (2 * M_PI / 0xF0);
    m.structural |= !(angle > 0) || !(angle <= 2 * M_PI + 1e-12);
    uint8_t tb = rd_u8(r);
    static const double BAD_TOLS[] = {0.0, -0.0, -1.0, NAN, INFINITY, 1e-300, 1e300, -INFINITY};
    double tol = tb >= 0xF8 ? BAD_TOLS[tb - 0xF8] : 0.0;
    m.structural |= tb >= 0xF8;
    if (tb < 0xF8 && !m.structural) {
        /* a coarse tolerance: 1/8 .. 1 of the input's extent about the axis point (and
         * never tiny against the coordinates), so no input runs long (a sweep at 1/64 took
         * seconds in this build) */
        double ext = 0;
        for (int64_t k = 0; k < m.nv; k++)
            for (int c = 0; c < 3; c++)
                ext = fmax(ext, fabs(m.xyz[3 * k + c] - ap[c]));
        tol = fmax(ext, 1e-3) * (double)(4 + tb % 29) * (1.0 / 32);
        m.structural |= !coord_ok(tol);
    } else if (tb < 0xF8) {
        tol = 0.1;
    }
    uint8_t nulls = (m.flags & 8) ? rd_u8(r) : 0;
    const double *xyzp = (nulls & 1) ? NULL : m.xyz, *app = (nulls & 4) ? NULL : ap, *adp = (nulls & 8) ? NULL : ad;
    const int64_t *trip = (nulls & 2) ? NULL : m.tri;
    m.structural |= (nulls & 1 && m.nv > 0) || (nulls & 2 && m.nt > 0) || (nulls & 4) || (nulls & 8) || (nulls & 16);

    /* what the mesh check says of the mesh (when the arguments are otherwise sound) */
    mfg_status closed = MFG_ERR_INVALID;
    mfg_mesh_report in_rep;
    memset(&in_rep, 0, sizeof in_rep);
    if (!m.structural)
        closed = mfg_mesh_check_closed(xyzp, m.nv, trip, m.nt, &in_rep);

    if (getenv("FUZZ_DUMP") && !m.structural) { /* the input, to reproduce it outside */
        fprintf(stderr, "sweep input: %lld %lld\n", (long long)m.nv, (long long)m.nt);
        for (int64_t k = 0; k < m.nv; k++)
            fprintf(stderr, "%.17g %.17g %.17g\n", m.xyz[3 * k], m.xyz[3 * k + 1], m.xyz[3 * k + 2]);
        for (int64_t k = 0; k < m.nt; k++)
            fprintf(stderr, "%lld %lld %lld\n", (long long)m.tri[3 * k], (long long)m.tri[3 * k + 1],
                    (long long)m.tri[3 * k + 2]);
        fprintf(stderr, "axis %.17g %.17g %.17g  %.17g %.17g %.17g angle %.17g tol %.17g\n", ap[0], ap[1],
                ap[2], ad[0], ad[1], ad[2], angle, tol);
    }
    mfg_mesh *sentinel = (mfg_mesh *)(uintptr_t)&sentinel, *res = sentinel;
    mfg_sweep_stats stats;
    memset(&stats, SENTINEL, sizeof stats);
    mfg_sweep_stats *statsp = (nulls & 32) ? NULL : &stats;
    mfg_status st = mfg_rotational_sweep(xyzp, m.nv, trip, m.nt, app, adp, angle, tol, (nulls & 16) ? NULL : &res, statsp);
    check_status(st);
    /* the documented refusals of a part the grids cannot resolve (rotsweep.c: too small
     * against its distance from the axis point, or for its coordinates) */
    int too_small = st == MFG_ERR_INVALID && (strstr(mfg_last_error(), "too small against") != NULL ||
                                              strstr(mfg_last_error(), "too small for its coordinates") != NULL);
    if (m.structural)
        CHECK(st != MFG_OK, "a structurally invalid input was accepted");
    if (m.hostile)
        CHECK(st != MFG_ERR_NOMEM, "an impossible count reported as out of memory");
    /* A valid solid may only be refused as too small for the grids (above); an accepted
     * invalid mesh or a returned invalid surface (checked below) must never happen. */
    if (!m.structural)
        CHECK(st == closed || st == MFG_ERR_NOMEM || (closed == MFG_OK && too_small),
              "the sweep and mfg_mesh_check_closed disagree on the mesh");
    if (st != MFG_OK) {
        CHECK(res == sentinel, "out_mesh written on failure");
        CHECK(untouched((const uint8_t *)&stats, sizeof stats), "out_stats written on failure");
        return;
    }
    CHECK(res != NULL && res != sentinel, "no mesh returned");
    mfg_mesh_report rep;
    mfg_status rst = mfg_mesh_check_closed(res->vertices, res->nvertices, res->triangles, res->ntriangles, &rep);
    CHECK(rst == MFG_OK, "the result is not a closed, outward oriented solid");
    if (statsp) {
        CHECK(fabs(stats.volume - rep.volume) <= 1e-9 * fabs(rep.volume), "stats volume is not the mesh's");
        CHECK(fabs(stats.area - rep.area) <= 1e-9 * rep.area, "stats area is not the mesh's");
        CHECK(memcmp(stats.bbox, rep.bbox, sizeof stats.bbox) == 0, "stats bbox is not the mesh's");
    }
    /* R(0) O lies in SV; SV lies in the cylinder about the axis through the farthest
     * vertex, between the input's extreme heights */
    CHECK(rep.volume >= in_rep.volume * (1 - 1e-9), "the result holds less volume than the input");
    double u[3];
    unit_of(ad, u);
    double rmax = 0, hmin = INFINITY, hmax = -INFINITY;
    for (int64_t k = 0; k < m.nv; k++) {
        double v[3] = {m.xyz[3 * k] - ap[0], m.xyz[3 * k + 1] - ap[1], m.xyz[3 * k + 2] - ap[2]};
        double h = v[0] * u[0] + v[1] * u[1] + v[2] * u[2];
        double r2 = v[0] * v[0] + v[1] * v[1] + v[2] * v[2] - h * h;
        rmax = fmax(rmax, sqrt(fmax(r2, 0)));
        hmin = fmin(hmin, h);
        hmax = fmax(hmax, h);
    }
    double cyl = M_PI * (rmax + 2 * tol) * (rmax + 2 * tol) * (hmax - hmin + 4 * tol);
    CHECK(rep.volume <= cyl * (1 + 1e-9), "the result is larger than the cylinder holding every turned input");
    mfg_mesh_free(res);
}

/*
 * The medial surface (issue 22) of the sweep section's small meshes, at a coarse
 * tolerance (1/16 .. 1/2 of the bounding-box diagonal: milliseconds), major or full,
 * one or two threads.  Checked: structurally invalid arguments and unknown flags are
 * refused; a mesh mfg_mesh_check_closed refuses is refused; nothing is written on
 * failure; never MFG_ERR_INTERNAL (check_status); a result's counts and offsets are
 * consistent, every radius finite and >= 0, every sheet triangle's indices in range.
 */
static void fuzz_medial(reader *r)
{
    g_where = "mfg_medial_surface";
    static small_mesh m; /* static, as the buffers were */
    read_small_mesh(r, &m);
    uint8_t tb = rd_u8(r), mode = rd_u8(r);
    double tol = 0.1;
    if (!m.structural && m.nv > 0) {
        double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
        for (int64_t k = 0; k < m.nv; k++)
            for (int c = 0; c < 3; c++) {
                lo[c] = fmin(lo[c], m.xyz[3 * k + c]);
                hi[c] = fmax(hi[c], m.xyz[3 * k + c]);
            }
        double diag = sqrt((hi[0] - lo[0]) * (hi[0] - lo[0]) + (hi[1] - lo[1]) * (hi[1] - lo[1]) +
                           (hi[2] - lo[2]) * (hi[2] - lo[2]));
        tol = diag * (double)(4 + tb % 28) * (1.0 / 64);
    }
    static const double BAD_TOLS[] = {0.0, -1.0, NAN, INFINITY};
    if (tb >= 0xFC) {
        tol = BAD_TOLS[tb - 0xFC];
        m.structural = 1;
    }
    if (!(tol > 0) || !isfinite(tol))
        m.structural = 1;
    uint32_t mflags = (mode & 1) ? MFG_MEDIAL_FULL : 0;
    if ((mode & 0xF0) == 0xF0) {
        mflags |= 1u << 7; /* an unknown flag */
        m.structural = 1;
    }
    int32_t threads = 1 + ((mode >> 1) & 1);
    uint8_t nulls = (m.flags & 8) ? rd_u8(r) : 0;
    const double *xyzp = (nulls & 1) ? NULL : m.xyz;
    const int64_t *trip = (nulls & 2) ? NULL : m.tri;
    m.structural |= (nulls & 1 && m.nv > 0) || (nulls & 2 && m.nt > 0) || (nulls & 4);
    mfg_status closed = MFG_ERR_INVALID;
    mfg_mesh_report rep;
    if (!m.structural)
        closed = mfg_mesh_check_closed(xyzp, m.nv, trip, m.nt, &rep);

    if (getenv("FUZZ_DUMP") && !m.structural) { /* the input, to reproduce it outside */
        fprintf(stderr, "medial input: %lld %lld tol %.17g m.flags %u\n", (long long)m.nv, (long long)m.nt, tol, mflags);
        for (int64_t k = 0; k < m.nv; k++)
            fprintf(stderr, "%.17g %.17g %.17g\n", m.xyz[3 * k], m.xyz[3 * k + 1], m.xyz[3 * k + 2]);
        for (int64_t k = 0; k < m.nt; k++)
            fprintf(stderr, "%lld %lld %lld\n", (long long)m.tri[3 * k], (long long)m.tri[3 * k + 1],
                    (long long)m.tri[3 * k + 2]);
    }
    mfg_medial *sentinel = (mfg_medial *)(uintptr_t)&sentinel, *res = sentinel;
    mfg_status st = mfg_medial_surface(xyzp, m.nv, trip, m.nt, tol, mflags, threads,
                                       (nulls & 4) ? NULL : &res);
    check_status(st);
    if (m.structural)
        CHECK(st != MFG_OK, "a structurally invalid input was accepted");
    if (m.hostile)
        CHECK(st != MFG_ERR_NOMEM, "an impossible count reported as out of memory");
    if (!m.structural && closed != MFG_OK)
        CHECK(st != MFG_OK, "a mesh mfg_mesh_check_closed refuses was accepted");
    if (st != MFG_OK) {
        CHECK(res == sentinel, "out written on failure");
        return;
    }
    CHECK(res != NULL && res != sentinel, "no medial surface returned");
    CHECK(res->nsheets >= 0 && res->nseams >= 0 && res->njunctions >= 0, "negative counts");
    for (int64_t s = 0; s < res->nsheets; s++) {
        int64_t v0 = res->sheet_vertex_offsets[s], v1 = res->sheet_vertex_offsets[s + 1];
        int64_t t0 = res->sheet_triangle_offsets[s], t1 = res->sheet_triangle_offsets[s + 1];
        CHECK(v0 <= v1 && t0 <= t1, "sheet offsets decrease");
        for (int64_t v = v0; v < v1; v++)
            CHECK(isfinite(res->sheet_radii[v]) && res->sheet_radii[v] >= 0, "a sheet radius is not finite and >= 0");
        for (int64_t k = 3 * t0; k < 3 * t1; k++)
            CHECK(res->sheet_triangles[k] >= 0 && res->sheet_triangles[k] < v1 - v0,
                  "a sheet triangle's index is out of its sheet");
    }
    for (int64_t j = 0; j < res->njunctions; j++)
        CHECK(isfinite(res->junction_radii[j]) && res->junction_radii[j] >= 0, "a junction radius is not finite and >= 0");
    mfg_medial_free(res);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    reader rd = {data, size};
    uint8_t which = rd_u8(&rd);
    /* each section can be skipped, so the fuzzer can spend its input on one of them */
    if (!(which & 1))
        fuzz_pointclass(&rd);
    if (!(which & 2))
        fuzz_visibility(&rd);
    if (!(which & 4))
        fuzz_sphere(&rd);
    /* the sweep section runs only when asked (bit 8): older seeds keep their meaning */
    if (which & 8)
        fuzz_sweep(&rd);
    /* the medial surface (bit 16), likewise */
    if (which & 16)
        fuzz_medial(&rd);
    return 0;
}
