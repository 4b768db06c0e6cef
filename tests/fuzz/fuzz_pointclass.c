/* SPDX-License-Identifier: LGPL-2.1-or-later */
/* fuzz_pointclass.c - libFuzzer target checking mfg_classify_points and the prepared region for crashes, consistency, invariance and (for dyadic-lattice inputs) exact answers. */

/*
 * Build (see run_fuzz.sh):
 *   clang -g -O1 -ffp-contract=off -fsanitize=fuzzer,address,undefined \
 *         -fno-sanitize-recover=all -Ilibcore/include -Ilibcore/src \
 *         $(find libcore/src -name '*.c') tests/fuzz/fuzz_pointclass.c -lm -o build-fuzz/fuzz_pointclass
 *
 * Input layout (every read past the end yields zero bytes):
 *   byte 0   : bits 0-1 number of rings - 1 (1..4); bits 2-3 coordinate mode;
 *              bits 4-6 tolerance mode; bit 7 add derived points (vertices, midpoints, ...)
 *   byte 1-2 : binary exponent for the scaled modes
 *   per ring : 1 byte vertex count (0..40), then the coordinates
 *   tolerance: per tolerance mode
 *   1 byte   : number of explicit points (0..63), then their coordinates
 *   1 byte   : rotation seed for the invariance check
 *   1 byte   : aim flags (snap vertices onto grid reference points, aimed queries)
 * Coordinate modes: 0 small integers / 4; 1 raw doubles; 2 small integers * 2^e
 * (e from bytes 1-2, tiny to huge); 3 per value: raw double or small integer.
 *
 * Checked (failure -> __builtin_trap):
 *  (a) status is MFG_OK or an error code with a non-empty mfg_last_error(), and the
 *      output array is untouched on failure;
 *  (b) the prepared region gives the same status and identical answers;
 *  (c) answers do not change when every ring is reversed and rotated and the ring
 *      order is reversed;
 *  (d) when every value is an integer multiple of a common power of two with small
 *      multiplier, the answers equal an exact integer (__int128) reference.
 * A failed check prints the decoded case (rings, tol, offending point); FUZZ_DUMP=1 in
 * the environment prints every case (useful for sanitizer reports inside the library).
 */

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "mfgeom.h"

#define MAX_RINGS 4
#define MAX_VERTS 40
#define MAX_EXPLICIT_POINTS 63
#define SENTINEL 0xA5

#include "fuzz_reader.h"

/* The decoded case, printed when a check fails. */
static struct {
    const double *xy;
    const int64_t *off;
    int nrings;
    double tol;
    const double *pts;
    int64_t np;
    int64_t bad_point; /* index of the offending point or -1 */
} g_case;

static void dump_case(void)
{
    if (!g_case.xy)
        return;
    fprintf(stderr, "case: nrings=%d tol=%.17g (%a)\n", g_case.nrings, g_case.tol, g_case.tol);
    for (int r = 0; r < g_case.nrings; r++) {
        fprintf(stderr, "  ring %d:", r);
        for (int64_t k = g_case.off[r]; k < g_case.off[r + 1]; k++)
            fprintf(stderr, " (%.17g, %.17g)", g_case.xy[2 * k], g_case.xy[2 * k + 1]);
        fprintf(stderr, "\n");
    }
    if (g_case.bad_point >= 0) {
        const double *p = g_case.pts + 2 * g_case.bad_point;
        fprintf(stderr, "  offending point %lld: (%.17g, %.17g) = (%a, %a)\n",
                (long long)g_case.bad_point, p[0], p[1], p[0], p[1]);
    } else {
        fprintf(stderr, "  %lld points\n", (long long)g_case.np);
    }
}

static void fail(const char *what)
{
    fprintf(stderr, "fuzz_pointclass: check failed: %s\n", what);
    dump_case();
    __builtin_trap();
}

#define CHECK(cond, what)  \
    do {                   \
        if (!(cond))       \
            fail(what);    \
    } while (0)

static double rd_coord(reader *r, int mode, int exp2)
{
    switch (mode) {
    case 0:
        return (double)(int8_t)rd_u8(r) * 0.25;
    case 1:
        return rd_f64(r);
    case 2:
        return ldexp((double)(int8_t)rd_u8(r), exp2);
    default: {
        uint8_t sel = rd_u8(r);
        if (sel & 0x80)
            return rd_f64(r);
        return (double)(int8_t)rd_u8(r) * 0.5;
    }
    }
}

static double rd_tol(reader *r, int mode, int exp2)
{
    switch (mode) {
    case 0:
        return 0.0;
    case 1:
        return (double)rd_u8(r) * 0.125;
    case 2:
        return rd_f64(r); /* anything, including negative / NaN / Inf */
    case 3:
        return ldexp((double)rd_u8(r), exp2);
    case 4:
        return ldexp((double)rd_u8(r), -60);
    case 5:
        return 0.25;
    case 6:
        return fabs(rd_f64(r));
    default:
        return (double)rd_u8(r) * 0.25 + 0.25;
    }
}

/* ------------------------------------------------------------------------ */
/* Aiming at the prepared grid: the grid geometry and reference-point       */
/* fractions of pointclass_grid.c, used only to place vertices and queries  */
/* exactly on cell reference points and borders (if the implementation      */
/* changes they are ordinary points and every check stays valid).           */
/* ------------------------------------------------------------------------ */

static const double ref_fx[8] = {0.5, 0.3819660112501051, 0.6180339887498949, 0.2360679774997897,
                                 0.7639320225002103, 0.1458980337503155, 0.8541019662496845,
                                 0.4142135623730950};
static const double ref_fy[8] = {0.5, 0.6180339887498949, 0.3819660112501051, 0.8541019662496845,
                                 0.1458980337503155, 0.7639320225002103, 0.2360679774997897,
                                 0.2679491924311227};

typedef struct grid_geo {
    double gx0, gy0, cw, ch;
    int64_t nx, ny;
    double minx, maxx, miny, maxy;
} grid_geo;

/* 1 when the region builds and its grid geometry could be reproduced. */
static int grid_geometry(const double *xy, const int64_t *off, int nrings, double tol,
                         grid_geo *g)
{
    mfg_region *region = NULL;
    if (mfg_region_new(xy, off, nrings, tol, &region) != MFG_OK)
        return 0;
    int64_t st[4];
    int ok = mfg_region_stats(region, st) == MFG_OK;
    mfg_region_free(region);
    if (!ok || st[0] < 1 || st[1] < 1 || off[nrings] < 1)
        return 0;
    g->nx = st[0];
    g->ny = st[1];
    g->minx = g->maxx = xy[0];
    g->miny = g->maxy = xy[1];
    for (int64_t k = 1; k < off[nrings]; k++) {
        g->minx = fmin(g->minx, xy[2 * k]);
        g->maxx = fmax(g->maxx, xy[2 * k]);
        g->miny = fmin(g->miny, xy[2 * k + 1]);
        g->maxy = fmax(g->maxy, xy[2 * k + 1]);
    }
    double x0 = g->minx - tol, x1 = g->maxx + tol, y0 = g->miny - tol, y1 = g->maxy + tol;
    double w = x1 - x0, h = y1 - y0;
    double margin = 128.0 * 0x1p-53 * (fabs(x0) + fabs(x1) + fabs(y0) + fabs(y1) + w + h);
    margin = fmax(margin, 0x1p-1000);
    g->gx0 = x0 - 2.0 * margin;
    g->gy0 = y0 - 2.0 * margin;
    g->cw = (w + 4.0 * margin) / (double)g->nx;
    g->ch = (h + 4.0 * margin) / (double)g->ny;
    return isfinite(g->cw) && isfinite(g->ch) && g->cw > 0 && g->ch > 0;
}

static void ref_point(const grid_geo *g, int64_t i, int64_t j, unsigned k, double *x, double *y)
{
    *x = g->gx0 + ((double)i + ref_fx[k & 7]) * g->cw;
    *y = g->gy0 + ((double)j + ref_fy[k & 7]) * g->ch;
}

static int64_t cell_of(double v, double v0, double c, int64_t n)
{
    double f = floor((v - v0) / c);
    if (!(f >= 0))
        return 0;
    if (f >= (double)(n - 1))
        return n - 1;
    return (int64_t)f;
}

static double into_range(double v)
{
    if (v != 0 && fabs(v) < MFG_MIN_COORD)
        return copysign(MFG_MIN_COORD, v);
    return v;
}

/* ------------------------------------------------------------------------ */
/* Exact reference on a common dyadic lattice: every value v == k * 2^unit.  */
/* ------------------------------------------------------------------------ */

typedef __int128 i128;

/* k with v == k * 2^unit and |k| <= 2^24, else 0 with *ok cleared. */
static int64_t lattice_int(double v, int unit, int *ok)
{
    if (!isfinite(v)) {
        *ok = 0;
        return 0;
    }
    double k = ldexp(v, -unit);
    if (!(fabs(k) <= 16777216.0) || k != floor(k)) {
        *ok = 0;
        return 0;
    }
    return (int64_t)k;
}

static uint8_t ref_classify(const int64_t *ix, const int64_t *iy, const int64_t *off,
                            int64_t nrings, int64_t tx, int64_t ty, int64_t itol)
{
    i128 tol2 = (i128)itol * itol;
    int crossings = 0;
    for (int64_t r = 0; r < nrings; r++) {
        int64_t first = off[r], n = off[r + 1] - off[r];
        for (int64_t i = 0; i < n; i++) {
            int64_t ax = ix[first + i], ay = iy[first + i];
            int64_t bx = ix[first + (i + 1) % n], by = iy[first + (i + 1) % n];
            i128 dx = bx - ax, dy = by - ay, wx = tx - ax, wy = ty - ay;
            i128 len2 = dx * dx + dy * dy, u = wx * dx + wy * dy;
            int on;
            if (u <= 0) {
                on = wx * wx + wy * wy <= tol2;
            } else if (u >= len2) {
                i128 ex = tx - bx, ey = ty - by;
                on = ex * ex + ey * ey <= tol2;
            } else {
                i128 c = wx * dy - wy * dx; /* |c| < 2^52: c*c < 2^104, tol2*len2 < 2^104 */
                on = c * c <= tol2 * len2;
            }
            if (on)
                return MFG_ON;
            if ((ay > ty) != (by > ty)) {
                i128 num = (i128)(ax - tx) * (by - ay) + (i128)(ty - ay) * (bx - ax);
                if (num != 0 && ((num > 0) == (by - ay > 0)))
                    crossings++;
            }
        }
    }
    return (crossings & 1) ? MFG_IN : MFG_OUT;
}

/* ------------------------------------------------------------------------ */

static int status_ok_or_reported(mfg_status st, const uint8_t *out, int64_t n)
{
    if (st == MFG_OK)
        return 1;
    CHECK(st >= MFG_ERR_NULL && st <= MFG_ERR_INTERNAL, "unknown status code");
    const char *msg = mfg_last_error();
    if (st == MFG_ERR_INTERNAL)
        fprintf(stderr, "mfg_last_error: %s\n", msg ? msg : "(null)");
    CHECK(st != MFG_ERR_INTERNAL, "MFG_ERR_INTERNAL (broken invariant)");
    CHECK(msg != NULL && msg[0] != '\0', "error without mfg_last_error() detail");
    CHECK(mfg_status_str(st) != NULL, "mfg_status_str returned NULL");
    for (int64_t i = 0; i < n; i++)
        CHECK(out[i] == SENTINEL, "output written on failure");
    return 0;
}

static void check_answers(const uint8_t *out, int64_t n)
{
    for (int64_t i = 0; i < n; i++)
        CHECK(out[i] == MFG_OUT || out[i] == MFG_IN || out[i] == MFG_ON, "answer not OUT/IN/ON");
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    reader rd = {data, size};
    uint8_t h0 = rd_u8(&rd);
    int nrings = 1 + (h0 & 3);
    int cmode = (h0 >> 2) & 3;
    int tmode = (h0 >> 4) & 7;
    int derived = (h0 >> 7) & 1;
    unsigned e16 = (unsigned)rd_u8(&rd) | ((unsigned)rd_u8(&rd) << 8);
    /* 2^-215 .. 2^195: int8 * 2^e reaches just beyond both ends of the accepted range
     * [MFG_MIN_COORD, MFG_MAX_COORD] = [2^-200, 2^200], so both sides of it are tested. */
    int exp2 = -215 + (int)(e16 % 411u);

    double xy[2 * MAX_RINGS * MAX_VERTS];
    int64_t off[MAX_RINGS + 1];
    off[0] = 0;
    int64_t nv = 0;
    for (int r = 0; r < nrings; r++) {
        int n = rd_u8(&rd) % (MAX_VERTS + 1);
        for (int i = 0; i < n; i++) {
            xy[2 * nv] = rd_coord(&rd, cmode, exp2);
            xy[2 * nv + 1] = rd_coord(&rd, cmode, exp2);
            nv++;
        }
        off[r + 1] = nv;
    }
    double tol = rd_tol(&rd, tmode, exp2);

    /* Points: explicit ones, then (optionally) derived ones near the boundary. */
    enum { MAXPTS = MAX_EXPLICIT_POINTS + 12 * MAX_RINGS * MAX_VERTS + 12 * MAX_RINGS * MAX_VERTS + 1 };
    static double pts[2 * MAXPTS];
    int64_t max_aim_points = 0; /* room reserved below for aimed queries */
    int64_t np = 0;
    int nexp = rd_u8(&rd) % (MAX_EXPLICIT_POINTS + 1);
    for (int i = 0; i < nexp; i++) {
        pts[2 * np] = rd_coord(&rd, cmode, exp2);
        pts[2 * np + 1] = rd_coord(&rd, cmode, exp2);
        np++;
    }
    uint8_t rot_seed = rd_u8(&rd);
    /* Aim byte: bit 0 snaps vertices (those not on the bounding box) onto reference
     * points of their grid cells, bits 1-3 pick the reference point, bit 4 adds queries
     * at reference points and cell corners around every vertex. */
    uint8_t aim = rd_u8(&rd);
    grid_geo geo;
    int have_geo = (aim & 0x11) && isfinite(tol) && tol >= 0 &&
                   grid_geometry(xy, off, nrings, tol, &geo);
    if (have_geo && (aim & 1)) {
        for (int64_t k = 0; k < nv; k++) {
            double x = xy[2 * k], y = xy[2 * k + 1];
            if (x == geo.minx || x == geo.maxx || y == geo.miny || y == geo.maxy)
                continue; /* keep the bounding box, hence the grid */
            double rx, ry;
            unsigned which = ((aim >> 1) + (unsigned)k) & 7;
            ref_point(&geo, cell_of(x, geo.gx0, geo.cw, geo.nx), cell_of(y, geo.gy0, geo.ch, geo.ny),
                      which, &rx, &ry);
            if (rx > geo.minx && rx < geo.maxx && ry > geo.miny && ry < geo.maxy) {
                xy[2 * k] = rx;
                xy[2 * k + 1] = ry;
            }
        }
    }
    if (derived && isfinite(tol)) {
        for (int r = 0; r < nrings; r++) {
            int64_t first = off[r], n = off[r + 1] - off[r];
            for (int64_t i = 0; i < n; i++) {
                double ax = xy[2 * (first + i)], ay = xy[2 * (first + i) + 1];
                double bx = xy[2 * (first + (i + 1) % n)], by = xy[2 * (first + (i + 1) % n) + 1];
                double cand[12][2] = {
                    {ax, ay},
                    {0.5 * ax + 0.5 * bx, 0.5 * ay + 0.5 * by},
                    {ax + tol, ay},
                    {ax - tol, ay},
                    {ax, ay + tol},
                    {ax, ay - tol},
                    {ax + 0.75 * tol, ay + 0.75 * tol},   /* in the tol-box, outside the disc */
                    {ax - 0.75 * tol, ay - 0.75 * tol},
                    {ax + 0.6 * tol, ay - 0.8 * tol},     /* about on the disc boundary */
                    {nextafter(ax, INFINITY), ay},
                    {bx, ay},                              /* shares y with a vertex */
                    {0.25 * ax + 0.75 * bx, 0.25 * ay + 0.75 * by},
                };
                for (int k = 0; k < 12; k++) {
                    /* keep derived points in range: a non-zero |v| < 2^-200 (e.g. the
                     * neighbour of 0) would only make the whole call invalid */
                    pts[2 * np] = into_range(cand[k][0]);
                    pts[2 * np + 1] = into_range(cand[k][1]);
                    np++;
                }
            }
        }
    }

    g_case.xy = xy;
    g_case.off = off;
    g_case.nrings = nrings;
    g_case.tol = tol;
    g_case.pts = pts;
    g_case.np = np;
    g_case.bad_point = -1;
    /* FUZZ_DUMP=1 prints every decoded case (to see the input of a sanitizer report). */
    static int dump = -1;
    if (dump < 0)
        dump = getenv("FUZZ_DUMP") != NULL;
    if (dump) {
        dump_case();
        for (int64_t i = 0; i < np; i++)
            fprintf(stderr, "  point %lld: (%.17g, %.17g)\n", (long long)i, pts[2 * i], pts[2 * i + 1]);
    }

    if (have_geo && (aim & 0x10)) {
        /* the snapped rings may have a different grid: recompute it */
        grid_geo g2;
        if (grid_geometry(xy, off, nrings, tol, &g2)) {
            for (int64_t k = 0; k < nv && max_aim_points + 12 <= 12 * MAX_RINGS * MAX_VERTS; k++) {
                int64_t i = cell_of(xy[2 * k], g2.gx0, g2.cw, g2.nx);
                int64_t j = cell_of(xy[2 * k + 1], g2.gy0, g2.ch, g2.ny);
                for (unsigned r = 0; r < 8; r++) {
                    ref_point(&g2, i, j, r, &pts[2 * np], &pts[2 * np + 1]);
                    np++;
                }
                double cx = g2.gx0 + (double)i * g2.cw, cy = g2.gy0 + (double)j * g2.ch;
                double corners[4][2] = {{cx, cy}, {cx, xy[2 * k + 1]}, {xy[2 * k], cy},
                                        {g2.gx0 + (double)(i + 1) * g2.cw, cy}};
                for (int c = 0; c < 4; c++) {
                    pts[2 * np] = into_range(corners[c][0]);
                    pts[2 * np + 1] = into_range(corners[c][1]);
                    np++;
                }
                max_aim_points += 12;
            }
        }
    }

    static uint8_t out1[MAXPTS], out2[MAXPTS], out3[MAXPTS];
    memset(out1, SENTINEL, sizeof out1);
    memset(out2, SENTINEL, sizeof out2);
    memset(out3, SENTINEL, sizeof out3);

    /* (a) one-shot */
    mfg_status st1 = mfg_classify_points(xy, off, nrings, pts, np, tol, out1);
    int ok1 = status_ok_or_reported(st1, out1, np);
    if (ok1)
        check_answers(out1, np);

    /* (b) prepared */
    mfg_region *region = (mfg_region *)(uintptr_t)0x1; /* must stay untouched on failure */
    mfg_status st2 = mfg_region_new(xy, off, nrings, tol, &region);
    if (st2 == MFG_OK) {
        CHECK(region != NULL && region != (mfg_region *)(uintptr_t)0x1, "no region returned");
        int64_t stats[4] = {-1, -1, -1, -1};
        CHECK(mfg_region_stats(region, stats) == MFG_OK, "mfg_region_stats failed");
        CHECK(stats[0] >= 1 && stats[1] >= 1 && stats[2] >= 0 && stats[3] >= 0, "bad stats");
        CHECK(stats[2] <= stats[0] * stats[1], "more boundary cells than cells");
        mfg_status st3 = mfg_region_classify(region, pts, np, out2);
        int ok3 = status_ok_or_reported(st3, out2, np);
        CHECK(ok3 == ok1, "prepared classify status differs from one-shot");
        if (ok1) {
            for (int64_t i = 0; i < np; i++) {
                g_case.bad_point = i;
                if (out1[i] != out2[i])
                    fprintf(stderr, "one-shot %d, prepared %d\n", out1[i], out2[i]);
                CHECK(out1[i] == out2[i], "prepared answer != one-shot answer");
            }
            g_case.bad_point = -1;
            /* a second query on the same region must give the same answers */
            memset(out3, SENTINEL, (size_t)np);
            CHECK(mfg_region_classify(region, pts, np, out3) == MFG_OK, "repeat classify failed");
            CHECK(memcmp(out2, out3, (size_t)np) == 0, "prepared region not deterministic");
        }
        mfg_region_free(region);
    } else {
        status_ok_or_reported(st2, out2, 0);
        CHECK(region == (mfg_region *)(uintptr_t)0x1, "region pointer written on failure");
        CHECK(!ok1, "mfg_region_new failed where mfg_classify_points succeeded");
    }

    /* (c) invariance: reverse every ring, rotate its start vertex, reverse ring order */
    double xy2[2 * MAX_RINGS * MAX_VERTS];
    int64_t off2[MAX_RINGS + 1];
    off2[0] = 0;
    int64_t k2 = 0;
    for (int r = nrings - 1; r >= 0; r--) {
        int64_t first = off[r], n = off[r + 1] - off[r];
        int64_t rot = n ? (rot_seed + 7 * r) % n : 0;
        for (int64_t i = 0; i < n; i++) {
            int64_t src = first + ((rot - i) % n + n) % n; /* reversed, starting at rot */
            xy2[2 * k2] = xy[2 * src];
            xy2[2 * k2 + 1] = xy[2 * src + 1];
            k2++;
        }
        off2[nrings - r] = k2;
    }
    memset(out3, SENTINEL, sizeof out3);
    mfg_status st4 = mfg_classify_points(xy2, off2, nrings, pts, np, tol, out3);
    int ok4 = status_ok_or_reported(st4, out3, np);
    CHECK(ok4 == ok1, "status changed under ring reversal/rotation/reordering");
    if (ok1) {
        for (int64_t i = 0; i < np; i++) {
            g_case.bad_point = i;
            if (out1[i] != out3[i])
                fprintf(stderr, "original %d, reversed/rotated %d\n", out1[i], out3[i]);
            CHECK(out1[i] == out3[i], "answer changed under ring reversal/rotation/reordering");
        }
        g_case.bad_point = -1;
    }

    /* (d) exact reference on a common dyadic lattice */
    if (ok1) {
        int unit = -250;
        double absmax = 0.0;
        for (int64_t i = 0; i < 2 * nv; i++)
            absmax = fmax(absmax, fabs(xy[i]));
        absmax = fmax(absmax, tol);
        if (absmax > 0) {
            int e;
            frexp(absmax, &e);
            unit = e - 24; /* lattice unit 2^unit: |k| <= 2^24 for every vertex and tol */
        }
        int lat = 1;
        static int64_t ix[MAX_RINGS * MAX_VERTS], iy[MAX_RINGS * MAX_VERTS];
        for (int64_t i = 0; i < nv && lat; i++) {
            ix[i] = lattice_int(xy[2 * i], unit, &lat);
            iy[i] = lattice_int(xy[2 * i + 1], unit, &lat);
        }
        int64_t itol = lattice_int(tol, unit, &lat);
        if (lat) {
            for (int64_t i = 0; i < np; i++) {
                int pl = 1;
                int64_t tx = lattice_int(pts[2 * i], unit, &pl);
                int64_t ty = lattice_int(pts[2 * i + 1], unit, &pl);
                if (!pl)
                    continue;
                uint8_t want = ref_classify(ix, iy, off, nrings, tx, ty, itol);
                if (want != out1[i]) {
                    g_case.bad_point = i;
                    fprintf(stderr, "reference %d, library %d (0 OUT, 1 IN, 2 ON)\n", want, out1[i]);
                    fail("library answer differs from the exact reference");
                }
            }
        }
    }
    return 0;
}
