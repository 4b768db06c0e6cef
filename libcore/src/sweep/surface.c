/* SPDX-License-Identifier: LGPL-2.1-or-later */
/* sweep/surface.c - From the chain to the result: the boundary of {w >= 1} by the exact
 * arrangement (arrange/), its points rounded once, and the pieces of each plane merged
 * and triangulated again on their outlines (mesh/planar_merge.c).
 *
 * A plane's pieces: the arrangement's faces of one cluster lie in one plane exactly; the
 * pieces of one planar face of the input (F at t = 0, or B turned by theta) lie in one
 * plane up to the rounding of their cut points, and so do clusters that share a member
 * with such a face: all of them form one group (union-find over the input's planar
 * groups and the clusters). */
#include <stdio.h>
#include <string.h>
#ifdef ARR_DEBUG
#include <time.h>
#endif

#include "sweep/envelope.h"
#include "mesh/mesh.h"
#include "mesh/mesh_repair.h"
#include "mesh/planar_merge.h"

/* Points of the chain closer than this are welded before the arrangement: turns of
 * different vertices onto one position (a part symmetric about the axis, whose strips
 * coincide when the steps line up) come out of the rounding a few ulps apart, and as
 * separate points they would make the arrangement cut nearly coincident sheets into
 * slivers; welded, the sheets are one plane's (a cluster) and add up exactly. */
#define SW_SOUP_WELD 0x1p-36

/* How often the boundary is arranged again after its points were rounded: rounding the
 * arrangement's implicit points can make faces that met only along an edge cross by an
 * ulp, fold a sliver over or leave a triangle without area.  Arranged again, the rounded
 * surface's crossings become points of their own and its boundary of {w >= 1} is taken
 * once more (a triangle without area drops out).  Each pass rounds fewer, smaller
 * features; a surface whose arrangement makes no point and drops no face has no crossing
 * and no zero-area triangle: it is the result.  No weld and no needle removal here: they
 * move points by more than the rounding and undo what the exact pass decided. */
#define SW_ROUND_PASSES 10 /* 6 until the growing weld below made the late passes converge */
/* Rounded points closer than this are welded between passes (unit scale: 2^-40 of the
 * part, far below the smallest tolerance, 2^-24; the chain stays closed, mesh_repair.h). */
#define SW_ROUND_WELD 0x1p-40
/* From the third pass on, the weld grows by 2^SW_WELD_STEP_LOG2 per pass up to
 * SW_ROUND_WELD_MAX: crossings that the rounding makes again and again are features a
 * few grid cells across (a star prism: three points 3e-11 apart on one line, the triangles
 * round them crossing every time, a pass giving the same surface back); welded, they are
 * gone (the passes at 2^-40 gave the same surface back up to the tenth).  2^-30 of the
 * unit box, reached at the sixth pass, moves a point by at most 1/64 of the smallest
 * tolerance (2^-24); most sweeps are clean after one or two passes and never weld more
 * than 2^-40. */
#define SW_WELD_STEP_LOG2 3
#define SW_ROUND_WELD_MAX 0x1p-30
/* A pass after the first may make at most nv / SW_PASS_POINTS_DIV + 1024 points of its
 * own (nv: its input's): the last crossings of the rounding make a handful. */
#define SW_PASS_POINTS_DIV 2

/* One arrangement of the closed chain (x0, nv0; tri0, nt0; grp0: per triangle a planar
 * group below G or -1; NULL: none), its boundary's points rounded to the grid and each
 * plane's pieces merged.  *clean = 1 when the arrangement made no point of its own: its
 * faces then lie on the chain's own points, nothing was rounded, and they are the exact
 * boundary (free of crossings, no zero-area face): *out holds them as they are, unmerged
 * (merging would move nothing but could fold a piece again).  MFG_OK with the new
 * surface in *out. */
static mfg_status round_pass(sw_env *e, const double *x0, int64_t nv0, const int64_t *tri0,
                             int64_t nt0, const int64_t *grp0, int64_t G, int64_t max_points,
                             double weld, mfg_rmesh *out, int *clean)
{
    const arr_stages stages = {{"sweep: intersections", "sweep: faces", "sweep: boundary"},
                               {0.3, 0.55, 0.8, 0.9},
                               max_points};
    arr_table T;
    arr_face *F = NULL;
    int64_t nf = 0, *tcl = NULL, ncl = 0;
    mfg_status st = arr_union_boundary(x0, nv0, tri0, nt0, e->prog, &stages, &T, &F, &nf,
                                       &tcl, &ncl);
    if (st != MFG_OK)
        return st;
    int64_t *uf = malloc((size_t)(G + ncl + 1) * sizeof *uf);
    int64_t *map = malloc((size_t)(T.npts + 1) * sizeof *map);
    double *x = malloc((size_t)(3 * 3 * nf + 3) * sizeof *x);
    int64_t *tri = malloc((size_t)(3 * nf + 3) * sizeof *tri);
    int64_t *grp = malloc((size_t)(nf + 1) * sizeof *grp);
    st = uf && map && x && tri && grp ? MFG_OK : MFG_ERR_NOMEM;
    if (st == MFG_OK) {
        for (int64_t i = 0; i < G + ncl; i++)
            uf[i] = i;
        for (int64_t t = 0; t < nt0; t++)
            if (grp0 && grp0[t] >= 0 && tcl[t] >= 0)
                mfg_uf_union(uf, grp0[t], G + tcl[t]);
        for (int64_t i = 0; i < T.npts; i++)
            map[i] = -1;
        int64_t nv = 0;
        *clean = 1;
        arr_points P = arr_view(&T);
        for (int64_t f = 0; f < nf; f++) {
            for (int k = 0; k < 3; k++) {
                int64_t p = F[f].v[k];
                if (p >= nv0) {
#ifdef ARR_DEBUG
                    if (*clean || getenv("MFG_SWEEP_NEWPTS")) {
                        double q[3];
                        arr_coords(&P, p, q);
                        fprintf(stderr, "  new point %lld (face %lld of cluster %lld): %.17g %.17g %.17g\n",
                                (long long)p, (long long)f, (long long)F[f].cluster, q[0], q[1], q[2]);
                    }
#endif
                    *clean = 0;
                }
                if (map[p] < 0) {
                    map[p] = nv;
                    arr_coords(&P, p, x + 3 * nv);
                    for (int j = 0; j < 3; j++) /* the next pass's input is on the grid */
                        x[3 * nv + j] = sw_snap(x[3 * nv + j]);
                    nv++;
                }
                tri[3 * f + k] = map[p];
            }
            grp[f] = mfg_uf_find(uf, G + F[f].cluster);
        }
        int64_t ntri = nf;
#ifdef ARR_DEBUG
        if (getenv("MFG_SWEEP_CHECK_RAW")) {
            mfg_mesh_report rep0;
            mfg_status c0 = mfg_mesh_check_closed(x, nv, tri, nf, &rep0);
            fprintf(stderr, "  arrangement's boundary, rounded: %lld faces, %s\n", (long long)nf,
                    c0 == MFG_OK ? "closed" : mfg_last_error());
        }
#endif
        int merge = !*clean;
#ifdef ARR_DEBUG
        if (getenv("MFG_SWEEP_NOMERGE"))
            merge = 0;
#endif
        if (merge && !mfg_merge_planar_groups(x, nv, tri, &ntri, grp, NULL))
            st = MFG_ERR_NOMEM;
        mfg_rmesh rm = {x, nv, 3 * nf + 1, tri, ntri, nf + 1, NULL};
        /* points the rounding brought within SW_ROUND_WELD of each other are one, needles
         * thinner than it go (mesh_repair.h): the next pass would otherwise cut the folds
         * between them finer and finer (measured: a box about its long diagonal went from
         * 10^3 to 10^4 triangles in three passes) */
        if (st == MFG_OK && !*clean && !mfg_mesh_repair(&rm, weld))
            st = MFG_ERR_NOMEM;
        x = rm.x;
        tri = rm.t;
        if (st == MFG_OK) {
            *out = rm;
            x = NULL;
            tri = NULL;
        }
    }
    if (st == MFG_ERR_NOMEM)
        st = mfg_fail(MFG_ERR_NOMEM, "rotational sweep: out of memory");
    free(uf);
    free(map);
    free(x);
    free(tri);
    free(grp);
    free(F);
    free(tcl);
    arr_table_free(&T);
    return st;
}

/* Points from the axis frame to the caller's axes at unit scale, scaled by a power of
 * two to |x| < 1 and snapped to the grid: the passes after the turn decide crossings on
 * the very numbers the caller gets (times 2^out_exp, exact), so turning the result back
 * cannot make faces cross by an ulp after the last check.  The first nexact points are
 * the input's: they are taken from the caller's own coordinates (e->cx), not turned
 * there and back. */
static void to_caller_axes(sw_env *e, double *x, int64_t nv, int64_t nexact)
{
    double big = 0;
    for (int64_t i = 0; i < nv; i++) { /* turned in place, then scaled once the extent is known */
        double *q = x + 3 * i, w[3];
        for (int k = 0; k < 3; k++)
            w[k] = i < nexact ? e->cx[3 * i + k]
                              : q[0] * e->frame[0][k] + q[1] * e->frame[1][k] +
                                    q[2] * e->frame[2][k] + e->origin[k];
        for (int k = 0; k < 3; k++) {
            q[k] = w[k];
            big = fmax(big, fabs(w[k]));
        }
    }
    int ex = 0;
    if (big > 0)
        (void)frexp(big, &ex); /* big < 2^ex */
    e->out_exp = ex; /* |x| < 1, as the unit scale (cdt.c's enclosing triangle) */
    for (int64_t i = 0; i < 3 * nv; i++)
        x[i] = sw_snap(ldexp(x[i], -e->out_exp));
}

#ifdef ARR_DEBUG
/* Writes the mesh to a file: "nv nt", the points, the triangles. */
static void debug_dump_path(const char *path, const double *x, int64_t nv, const int64_t *t, int64_t nt)
{
    FILE *fp = fopen(path, "w");
    if (!fp)
        return;
    fprintf(fp, "%lld %lld\n", (long long)nv, (long long)nt);
    for (int64_t i = 0; i < nv; i++)
        fprintf(fp, "%.17g %.17g %.17g\n", x[3 * i], x[3 * i + 1], x[3 * i + 2]);
    for (int64_t i = 0; i < nt; i++)
        fprintf(fp, "%lld %lld %lld\n", (long long)t[3 * i], (long long)t[3 * i + 1], (long long)t[3 * i + 2]);
    fclose(fp);
}

/* The mesh to the file the environment variable names, if it does (MFG_SWEEP_DUMP: the
 * soup; MFG_SWEEP_DUMP1: the first pass's surface in the caller's axes, before the second
 * pass; with MFG_SWEEP_DUMP_KEEP an existing file, the first build's, is kept). */
static void debug_dump(const char *var, const double *x, int64_t nv, const int64_t *t, int64_t nt)
{
    const char *path = getenv(var);
    FILE *fp = path && getenv("MFG_SWEEP_DUMP_KEEP") ? fopen(path, "r") : NULL;
    if (fp) {
        fclose(fp);
        return;
    }
    if (path)
        debug_dump_path(path, x, nv, t, nt);
}
#endif

static void rmesh_free(mfg_rmesh *m)
{
    free(m->x);
    free(m->t);
    free(m->g);
    memset(m, 0, sizeof *m);
}

int sw_surface(sw_env *e, double **ox, int64_t *nox, int64_t **ot, int64_t *not_)
{
    /* the fallback builds (rotsweep.c) arrange the soup in the caller's axes from the
     * first pass: the input's points exact, the soup's own rounded once, and no turn of
     * the arranged surface (whose grazing sheets an ulp of the turn can make cross: a torus
     * turned 0.02 rad about its own axis had 0 crossings before the turn and 178 after) */
    if (e->caller_first)
        to_caller_axes(e, e->x, e->nv, e->nin);
    mfg_rmesh soup = {e->x, e->nv, e->capv, e->st, e->nst, e->capst, e->sgroup};
    if (!mfg_chain_weld(&soup, SW_SOUP_WELD)) {
        e->st_code = mfg_fail(MFG_ERR_NOMEM, "rotational sweep: out of memory");
        return 0;
    }
    e->nst = soup.nt;
#ifdef ARR_DEBUG
    debug_dump("MFG_SWEEP_DUMP", e->x, e->nv, e->st, e->nst);
#endif
    /* the first pass arranges the soup; later ones the previous pass's rounded surface,
     * whose pieces of one plane are merged only where they are still exactly one plane
     * (a cluster of that pass) */
    mfg_rmesh cur = {0}, next = {0};
    int clean = 0;
    mfg_status st = round_pass(e, e->x, e->nv, e->st, e->nst, e->sgroup, e->ngroups, 0,
                               SW_ROUND_WELD, &cur, &clean);
    if (st == MFG_OK && !e->caller_first)
        to_caller_axes(e, cur.x, cur.nv, 0);
#ifdef ARR_DEBUG
    if (st == MFG_OK)
        debug_dump("MFG_SWEEP_DUMP1", cur.x, cur.nv, cur.t, cur.nt);
#endif
    for (int pass = 1; st == MFG_OK; pass++) {
        /* a pass whose arrangement makes many points is a cascade (see below) found
         * before it ends: a star prism's second pass went on for minutes to 230 172
         * triangles from 28 962 */
        double weld = ldexp(SW_ROUND_WELD, SW_WELD_STEP_LOG2 * (pass > 2 ? pass - 2 : 0));
        st = round_pass(e, cur.x, cur.nv, cur.t, cur.nt, NULL, 0,
                        cur.nv + cur.nv / SW_PASS_POINTS_DIV + 1024, fmin(weld, SW_ROUND_WELD_MAX),
                        &next, &clean);
        if (st == MFG_ERR_INTERNAL && strstr(mfg_last_error(), "the caller's bound")) {
            char why[256];
            snprintf(why, sizeof why, "%s", mfg_last_error());
            st = mfg_fail(MFG_ERR_INTERNAL, "rotational sweep: the rounded boundary's "
                          "crossings multiply (pass %d: %s); please report this input",
                          pass + 1, why);
        }
#ifdef ARR_DEBUG
        fprintf(stderr, "round pass %d (%.2f s of CPU): %lld -> %lld triangles, clean %d\n", pass, (double)clock() / CLOCKS_PER_SEC,
                (long long)cur.nt, (long long)next.nt, clean);
#endif
        if (st != MFG_OK)
            break;
#ifdef ARR_DEBUG
        if (getenv("MFG_SWEEP_DUMPP")) { /* every pass: PREFIX.build.pass */
            char path[512];
            snprintf(path, sizeof path, "%s.%d.%d", getenv("MFG_SWEEP_DUMPP"),
                     e->attempt + 10 * e->caller_first, pass);
            debug_dump_path(path, next.x, next.nv, next.t, next.nt);
        }
#endif
        if (clean) { /* next: the exact boundary on cur's points, the result */
            rmesh_free(&cur);
            cur = next;
            break;
        }
        int growing = next.nt > cur.nt + cur.nt / 4 + 64;
        rmesh_free(&cur);
        cur = next;
        memset(&next, 0, sizeof next);
        /* a pass that cuts the surface finer by a quarter is a cascade of folds, not the
         * last few crossings of the rounding: another build of the soup is faster (a
         * 14-vertex part went to 362 186 triangles in the passes without this) */
        if (growing) {
            st = mfg_fail(MFG_ERR_INTERNAL, "rotational sweep: the rounded boundary's "
                          "crossings multiply (pass %d); please report this input", pass + 1);
            break;
        }
        if (pass + 1 >= SW_ROUND_PASSES) {
            st = mfg_fail(MFG_ERR_INTERNAL, "rotational sweep: the rounded boundary still "
                          "crosses itself after %d passes; please report this input", pass + 1);
            break;
        }
    }
    /* where the solid touches itself (along an edge, at a point) its sheets are told apart */
    if (st == MFG_OK && !mfg_mesh_separate_sheets(&cur))
        st = mfg_fail(MFG_ERR_NOMEM, "rotational sweep: out of memory");
    /* and flat shells (debris of the rounding where a full turn's sheets touch) dropped */
    if (st == MFG_OK && !mfg_mesh_drop_flat_shells(&cur))
        st = mfg_fail(MFG_ERR_NOMEM, "rotational sweep: out of memory");
    if (st == MFG_OK) {
        mfg_mesh_report rep;
        st = mfg_mesh_check_closed(cur.x, cur.nv, cur.t, cur.nt, &rep);
        if (st != MFG_OK && st != MFG_ERR_NOMEM) {
            char why[256];
            snprintf(why, sizeof why, "%s", mfg_last_error());
            st = mfg_fail(MFG_ERR_INTERNAL, "rotational sweep: the boundary is not a closed "
                          "2-manifold (%s); please report this input", why);
        }
    }
    if (st == MFG_OK) {
        *ox = cur.x;
        *nox = cur.nv;
        *ot = cur.t;
        *not_ = cur.nt;
        free(cur.g);
        return 1;
    }
    rmesh_free(&cur);
    e->st_code = st;
    return 0;
}
