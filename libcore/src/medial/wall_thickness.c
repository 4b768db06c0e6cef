/* SPDX-License-Identifier: LGPL-2.1-or-later */
/* wall_thickness.c - local wall thickness from the medial surface (issue 21, section 4):
 * the diameter of the maximal inscribed ball that touches a boundary point.
 *
 * Every ball of the medial surface touches its elements at their foot points (the closest
 * points of the elements to its centre).  Mapping a sheet triangle's three balls to their
 * feet on one of its two elements gives a *foot triangle* on that element (a segment or a
 * point where the element is an edge or a vertex), over which the radius is interpolated
 * linearly -- exact on plane-plane sheets, where the radius is an affine function of the
 * foot; seams give foot segments and junctions foot points.  The union of the foot
 * primitives is the part of the boundary that maximal balls touch; a query point takes
 * the smallest radius among the primitives nearest to it.
 *
 * Which balls are a wall's: the object angle (Foskey, Lin and Manocha, "Efficient
 * computation of a simplified medial axis", 2003) -- the largest angle, seen from the
 * ball's centre, between two of the points it touches.  The two sides of a wall face each
 * other (180 degrees, 180 - alpha for a wedge of angle alpha); near a convex edge the
 * balls touch the two faces of the edge only (90 degrees at a right angle) and shrink to
 * nothing at the edge: those are corners, not walls, and a thickness of 0 along every
 * convex edge would hide the walls' true values.  Balls below the angle are left out; the
 * boundary they alone touch takes the nearest wall ball's value.
 *
 * The primitives live in a small AABB tree (median splits on the longest axis of the
 * centroids) queried twice per point: the nearest distance, then the smallest radius of
 * the primitives within a rounding allowance of it. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "medial/medial.h"
#include "common/mfg_internal.h"

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

/* Primitives per leaf of the foot tree. */
#define FOOT_LEAF 4
/* Traversal stack of the foot tree: median splits halve every range (depth <= 41). */
#define FOOT_STACK 128
/* Distances within this fraction of the feet's bounding-box diagonal count as equal:
 * rounding of the foot points (a point on the reflex edge touched by a fan of balls
 * through a sheet's shared corners), far below any medial tolerance (>= L / 2^20). */
#define FOOT_TIE_REL 1e-9
/* Points handled between two progress reports. */
#define POINTS_PER_REPORT 4096

/* One foot primitive: n = 3 a triangle, 2 a segment, 1 a point; per corner the foot, the
 * ball's radius and its centre. */
typedef struct foot {
    double p[3][3];
    double c[3][3];
    double r[3];
    int32_t n;
} foot;

typedef struct foot_node {
    double lo[3], hi[3];
    int64_t right; /* internal: right child (the left is the next node); leaf: first */
    int32_t count; /* leaf: primitives (1 .. FOOT_LEAF); internal: 0 */
} foot_node;

typedef struct foot_tree {
    foot *prim;
    int64_t nprim, cap;
    foot_node *node;
    int64_t nnodes;
    double *key; /* centroids, 3 per primitive, for the build */
    double tie;  /* absolute: FOOT_TIE_REL times the feet's diagonal */
} foot_tree;

/* ---- feet and object angles ---------------------------------------------------------- */

/* The foot of element e (closest point of e to x) into f. */
static void element_foot(const mfg_medial *m, int64_t e, const double x[3], double f[3])
{
    int32_t kind = m->element_kinds[e];
    if (kind == MFG_ELEM_FACE) {
        const double *pl = m->face_planes + 4 * e;
        double s = mfg_dot3(pl, x) - pl[3];
        for (int k = 0; k < 3; k++)
            f[k] = x[k] - s * pl[k];
    } else if (kind == MFG_ELEM_EDGE) {
        const double *seg = m->edge_segments + 6 * (e - m->nfaces);
        md_closest_on_seg(x, seg, seg + 3, f, NULL);
    } else {
        memcpy(f, m->vertex_points + 3 * (e - m->nfaces - m->nedges), 3 * sizeof *f);
    }
}

/* Largest angle at x between the feet of two of the elements ids[0 .. n-1].  Feet within
 * eps of x give no direction: a ball of no size (a seam ending on the boundary, r = 0 up
 * to rounding) separates nothing -- its rounded directions once made every facet corner
 * of a tessellated ball a "wall" 0 thick. */
static double object_angle(const mfg_medial *m, const int64_t *ids, int64_t n, const double x[3],
                           double eps)
{
    double best = 0;
    for (int64_t a = 0; a < n; a++) {
        double fa[3], da[3];
        element_foot(m, ids[a], x, fa);
        mfg_sub3(fa, x, da);
        if (!(mfg_dot3(da, da) > eps * eps))
            continue;
        for (int64_t b = a + 1; b < n; b++) {
            double fb[3], db[3];
            element_foot(m, ids[b], x, fb);
            mfg_sub3(fb, x, db);
            if (!(mfg_dot3(db, db) > eps * eps))
                continue;
            double ang = mfg_angle3(da, db);
            if (ang > best)
                best = ang;
        }
    }
    return best;
}

static int push_foot(foot_tree *t, const foot *f)
{
    if (!mfg_grow((void **)&t->prim, &t->cap, t->nprim + 1, sizeof *t->prim))
        return 0;
    t->prim[t->nprim++] = *f;
    return 1;
}

/* The foot primitives of the balls centres[0 .. n-1] (n = 1, 2, 3 corners) on each of the
 * elements ids[0 .. nids-1]. */
static int push_feet(foot_tree *t, const mfg_medial *m, const int64_t *ids, int64_t nids,
                     const double *const *centres, const double *radii, int n)
{
    for (int64_t a = 0; a < nids; a++) {
        foot f;
        memset(&f, 0, sizeof f);
        f.n = n;
        for (int k = 0; k < n; k++) {
            element_foot(m, ids[a], centres[k], f.p[k]);
            memcpy(f.c[k], centres[k], sizeof f.c[k]);
            f.r[k] = radii[k];
        }
        if (!push_foot(t, &f))
            return 0;
    }
    return 1;
}

/* Collects the primitives of the wall balls of m.  Returns 0 on allocation failure or
 * cancel (*stopped set). */
static int collect_feet(foot_tree *t, const mfg_medial *m, double min_angle, mfg_prog *prog,
                        int *stopped)
{
    int64_t units = m->nsheets + m->nseams + 1;
    /* eps: rounding of the medial computations (MD_ROUND_REL of the polyhedron's size) */
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (int64_t v = 0; v < m->nvertices; v++)
        for (int k = 0; k < 3; k++) {
            lo[k] = fmin(lo[k], m->vertex_points[3 * v + k]);
            hi[k] = fmax(hi[k], m->vertex_points[3 * v + k]);
        }
    double span[3];
    mfg_sub3(hi, lo, span);
    double eps = m->nvertices ? MD_ROUND_REL * mfg_norm3(span) : 0;
    for (int64_t s = 0; s < m->nsheets; s++) {
        if (!mfg_prog_poll(prog, (double)s, (double)units)) {
            *stopped = 1;
            return 0;
        }
        const int64_t *ids = m->sheet_elements + 2 * s;
        const double *v = m->sheet_vertices + 3 * m->sheet_vertex_offsets[s];
        const double *r = m->sheet_radii + m->sheet_vertex_offsets[s];
        for (int64_t i = m->sheet_triangle_offsets[s]; i < m->sheet_triangle_offsets[s + 1]; i++) {
            const int64_t *tri = m->sheet_triangles + 3 * i;
            const double *cs[3] = {v + 3 * tri[0], v + 3 * tri[1], v + 3 * tri[2]};
            double rs[3] = {r[tri[0]], r[tri[1]], r[tri[2]]}, mid[3];
            for (int k = 0; k < 3; k++)
                mid[k] = (cs[0][k] + cs[1][k] + cs[2][k]) / 3;
            if (object_angle(m, ids, 2, mid, eps) < min_angle)
                continue;
            if (!push_feet(t, m, ids, 2, cs, rs, 3))
                return 0;
        }
    }
    for (int64_t c = 0; c < m->nseams; c++) {
        if (!mfg_prog_poll(prog, (double)(m->nsheets + c), (double)units)) {
            *stopped = 1;
            return 0;
        }
        const int64_t *ids = m->seam_elements + m->seam_element_offsets[c];
        int64_t nids = m->seam_element_offsets[c + 1] - m->seam_element_offsets[c];
        int64_t p0 = m->seam_point_offsets[c], p1 = m->seam_point_offsets[c + 1];
        for (int64_t i = p0; i < p1; i++) {
            /* Each point, then each segment to the next point. */
            const double *cs[2] = {m->seam_points + 3 * i, m->seam_points + 3 * (i + 1)};
            double rs[2] = {m->seam_radii[i], i + 1 < p1 ? m->seam_radii[i + 1] : 0};
            if (object_angle(m, ids, nids, cs[0], eps) >= min_angle &&
                !push_feet(t, m, ids, nids, cs, rs, 1))
                return 0;
            if (i + 1 < p1) {
                double mid[3];
                for (int k = 0; k < 3; k++)
                    mid[k] = (cs[0][k] + cs[1][k]) / 2;
                if (object_angle(m, ids, nids, mid, eps) >= min_angle &&
                    !push_feet(t, m, ids, nids, cs, rs, 2))
                    return 0;
            }
        }
    }
    for (int64_t j = 0; j < m->njunctions; j++) {
        const int64_t *ids = m->junction_elements + m->junction_element_offsets[j];
        int64_t nids = m->junction_element_offsets[j + 1] - m->junction_element_offsets[j];
        const double *cs[1] = {m->junction_points + 3 * j};
        if (object_angle(m, ids, nids, cs[0], eps) >= min_angle &&
            !push_feet(t, m, ids, nids, cs, m->junction_radii + j, 1))
            return 0;
    }
    return 1;
}

/* ---- the foot tree ------------------------------------------------------------------- */

static void prim_box(const foot *f, double lo[3], double hi[3])
{
    for (int k = 0; k < 3; k++) {
        lo[k] = hi[k] = f->p[0][k];
        for (int i = 1; i < f->n; i++) {
            lo[k] = fmin(lo[k], f->p[i][k]);
            hi[k] = fmax(hi[k], f->p[i][k]);
        }
    }
}

static void swap_prim(foot_tree *t, int64_t i, int64_t j)
{
    foot f = t->prim[i];
    t->prim[i] = t->prim[j];
    t->prim[j] = f;
    for (int k = 0; k < 3; k++) {
        double x = t->key[3 * i + k];
        t->key[3 * i + k] = t->key[3 * j + k];
        t->key[3 * j + k] = x;
    }
}

/* Partitions [b, e) so that position mid holds its order statistic along axis and the
 * smaller keys lie before it (Hoare's selection, middle pivot: deterministic). */
static void select_mid(foot_tree *t, int64_t b, int64_t e, int64_t mid, int axis)
{
    int64_t lo = b, hi = e - 1;
    while (lo < hi) {
        double pivot = t->key[3 * ((lo + hi) / 2) + axis];
        int64_t i = lo, j = hi;
        while (i <= j) {
            while (t->key[3 * i + axis] < pivot)
                i++;
            while (t->key[3 * j + axis] > pivot)
                j--;
            if (i <= j) {
                swap_prim(t, i, j);
                i++;
                j--;
            }
        }
        if (mid <= j)
            hi = j;
        else if (mid >= i)
            lo = i;
        else
            break;
    }
}

static void build_node(foot_tree *t, int64_t b, int64_t e)
{
    int64_t me = t->nnodes++;
    foot_node *n = &t->node[me];
    prim_box(&t->prim[b], n->lo, n->hi);
    double clo[3], chi[3];
    for (int k = 0; k < 3; k++)
        clo[k] = chi[k] = t->key[3 * b + k];
    for (int64_t i = b + 1; i < e; i++) {
        double lo[3], hi[3];
        prim_box(&t->prim[i], lo, hi);
        for (int k = 0; k < 3; k++) {
            n->lo[k] = fmin(n->lo[k], lo[k]);
            n->hi[k] = fmax(n->hi[k], hi[k]);
            clo[k] = fmin(clo[k], t->key[3 * i + k]);
            chi[k] = fmax(chi[k], t->key[3 * i + k]);
        }
    }
    if (e - b <= FOOT_LEAF) {
        n->right = b;
        n->count = (int32_t)(e - b);
        return;
    }
    int axis = 0;
    for (int k = 1; k < 3; k++)
        if (chi[k] - clo[k] > chi[axis] - clo[axis])
            axis = k;
    int64_t mid = b + (e - b) / 2;
    select_mid(t, b, e, mid, axis);
    n->count = 0;
    build_node(t, b, mid);
    t->node[me].right = t->nnodes; /* the node array is allocated whole: n stays valid */
    build_node(t, mid, e);
}

static int build_tree(foot_tree *t)
{
    t->key = malloc((size_t)(3 * t->nprim) * sizeof *t->key);
    t->node = malloc((size_t)(2 * t->nprim) * sizeof *t->node);
    if (!t->key || !t->node)
        return 0;
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (int64_t i = 0; i < t->nprim; i++) {
        const foot *f = &t->prim[i];
        for (int k = 0; k < 3; k++) {
            double s = 0;
            for (int j = 0; j < f->n; j++)
                s += f->p[j][k];
            t->key[3 * i + k] = s / f->n;
            for (int j = 0; j < f->n; j++) {
                lo[k] = fmin(lo[k], f->p[j][k]);
                hi[k] = fmax(hi[k], f->p[j][k]);
            }
        }
    }
    double d[3];
    mfg_sub3(hi, lo, d);
    t->tie = FOOT_TIE_REL * mfg_norm3(d);
    t->nnodes = 0;
    build_node(t, 0, t->nprim);
    return 1;
}

static double box_dist2(const foot_node *n, const double *p)
{
    return mfg_box_dist2(n->lo, n->hi, p);
}

/* Closest point of primitive f to x: its distance, the interpolated radius and centre. */
static double prim_closest(const foot *f, const double x[3], double *r, double c[3])
{
    double q[3], w[3] = {1, 0, 0};
    if (f->n == 3) {
        md_closest_on_tri(x, f->p[0], f->p[1], f->p[2], q, w);
    } else if (f->n == 2) {
        double t;
        md_closest_on_seg(x, f->p[0], f->p[1], q, &t);
        w[0] = 1 - t;
        w[1] = t;
    } else {
        memcpy(q, f->p[0], sizeof q);
    }
    *r = 0;
    for (int k = 0; k < 3; k++)
        c[k] = 0;
    for (int i = 0; i < f->n; i++) {
        *r += w[i] * f->r[i];
        for (int k = 0; k < 3; k++)
            c[k] += w[i] * f->c[i][k];
    }
    return mfg_dist3(x, q);
}

/* The thickness query of one point: pass 1 the nearest distance, pass 2 the smallest
 * radius within the tie allowance of it. */
static void query(const foot_tree *t, const double x[3], double *radius, double centre[3],
                  double *gap)
{
    int64_t stack[FOOT_STACK];
    int sp = 0;
    double best = INFINITY, r, c[3];
    stack[sp++] = 0;
    while (sp) {
        const foot_node *n = &t->node[stack[--sp]];
        if (box_dist2(n, x) > best * best)
            continue;
        if (n->count) {
            for (int64_t i = n->right; i < n->right + n->count; i++) {
                double d = prim_closest(&t->prim[i], x, &r, c);
                if (d < best)
                    best = d;
            }
        } else {
            int64_t l = (n - t->node) + 1, rgt = n->right;
            double dl = box_dist2(&t->node[l], x), dr = box_dist2(&t->node[rgt], x);
            /* the nearer child on top of the stack */
            if (dl < dr) {
                stack[sp++] = rgt;
                stack[sp++] = l;
            } else {
                stack[sp++] = l;
                stack[sp++] = rgt;
            }
        }
    }
    double limit = best + t->tie, rmin = INFINITY;
    sp = 0;
    stack[sp++] = 0;
    while (sp) {
        const foot_node *n = &t->node[stack[--sp]];
        if (box_dist2(n, x) > limit * limit)
            continue;
        if (n->count) {
            for (int64_t i = n->right; i < n->right + n->count; i++) {
                double d = prim_closest(&t->prim[i], x, &r, c);
                if (d <= limit && r < rmin) {
                    rmin = r;
                    memcpy(centre, c, 3 * sizeof *centre);
                }
            }
        } else {
            stack[sp++] = n->right;
            stack[sp++] = (n - t->node) + 1;
        }
    }
    *radius = rmin;
    *gap = best;
}

static void tree_free(foot_tree *t)
{
    free(t->prim);
    free(t->node);
    free(t->key);
}

/* ---- entry points -------------------------------------------------------------------- */

static mfg_status thickness_run(const char *call, const mfg_medial *m, const double *points,
                                int64_t npoints, double min_angle, double *thickness,
                                double *centres, double *gaps, mfg_prog *prog)
{
    if (!m || (!points && npoints > 0) || !thickness)
        return mfg_fail(MFG_ERR_NULL, "%s: %s is NULL", call,
                        !m ? "medial" : !thickness ? "thickness" : "points");
    if (npoints < 0 || npoints > MFG_MAX_COUNT)
        return mfg_fail(MFG_ERR_INVALID, "%s: npoints %lld out of range", call,
                        (long long)npoints);
    if (!(min_angle > 0 && min_angle <= M_PI))
        return mfg_fail(MFG_ERR_INVALID, "%s: min_angle %g is not in (0, pi]", call, min_angle);
    for (int64_t i = 0; i < 3 * npoints; i++)
        if (!mfg_coord_ok(points[i]))
            return mfg_fail(MFG_ERR_INVALID, "%s: point %lld is not finite or out of range",
                            call, (long long)(i / 3));

    foot_tree t;
    memset(&t, 0, sizeof t);
    int stopped = 0;
    if (!mfg_prog_stage(prog, "thickness: balls", prog->last, 0.93, 64))
        return mfg_prog_fail(prog);
    if (!collect_feet(&t, m, min_angle, prog, &stopped)) {
        tree_free(&t);
        return stopped ? mfg_prog_fail(prog) : mfg_fail(MFG_ERR_NOMEM, "%s: out of memory", call);
    }
    if (t.nprim == 0) {
        tree_free(&t);
        return mfg_fail(MFG_ERR_DEGENERATE,
                        "%s: no ball of the medial surface touches two points %.1f degrees "
                        "apart (no wall: an empty medial surface or a too large min_angle)",
                        call, min_angle * 180 / M_PI);
    }
    if (!build_tree(&t)) {
        tree_free(&t);
        return mfg_fail(MFG_ERR_NOMEM, "%s: out of memory", call);
    }
    if (!mfg_prog_stage(prog, "thickness: points", 0.93, 1.0, POINTS_PER_REPORT)) {
        tree_free(&t);
        return mfg_prog_fail(prog);
    }
    /* Results go to scratch first: outputs stay untouched on cancel. */
    double *out = malloc((size_t)(npoints ? 5 * npoints : 1) * sizeof *out);
    if (!out) {
        tree_free(&t);
        return mfg_fail(MFG_ERR_NOMEM, "%s: out of memory", call);
    }
    for (int64_t i = 0; i < npoints; i++) {
        if (!mfg_prog_poll(prog, (double)i, (double)npoints)) {
            free(out);
            tree_free(&t);
            return mfg_prog_fail(prog);
        }
        double r;
        query(&t, points + 3 * i, &r, out + 5 * i + 1, out + 5 * i + 4);
        out[5 * i] = 2 * r;
    }
    for (int64_t i = 0; i < npoints; i++) {
        thickness[i] = out[5 * i];
        if (centres)
            memcpy(centres + 3 * i, out + 5 * i + 1, 3 * sizeof *centres);
        if (gaps)
            gaps[i] = out[5 * i + 4];
    }
    free(out);
    tree_free(&t);
    mfg_prog_stage(prog, "thickness: done", 1, 1, 1);
    return MFG_OK;
}

mfg_status mfg_medial_thickness(const mfg_medial *medial, const double *points, int64_t npoints,
                                double min_angle, double *thickness, double *centres,
                                double *gaps)
{
    mfg_prog prog;
    mfg_prog_init(&prog, NULL, "mfg_medial_thickness");
    return thickness_run("mfg_medial_thickness", medial, points, npoints, min_angle, thickness,
                         centres, gaps, &prog);
}

/* The medial stages' reports, mapped to [0, 0.9] of the whole call; "medial: done" is
 * held back (the call goes on). */
typedef struct medial_relay {
    const mfg_progress *outer;
    const char *stage; /* the last stage relayed, for the cancel detail */
} medial_relay;

static int relay_progress(void *user, double fraction, const char *stage)
{
    medial_relay *r = user;
    if (strcmp(stage, "medial: done") == 0)
        return 0;
    r->stage = stage;
    return r->outer->callback(r->outer->user, 0.9 * fraction, stage);
}

mfg_status mfg_wall_thickness(const double *xyz, int64_t nvertices, const int64_t *triangles,
                              int64_t ntriangles, double tolerance, uint32_t flags,
                              int32_t nthreads, const double *points, int64_t npoints,
                              double min_angle, double *thickness, double *centres,
                              double *gaps, const mfg_progress *progress)
{
    static const char call[] = "mfg_wall_thickness";
    if ((!points && npoints > 0) || !thickness)
        return mfg_fail(MFG_ERR_NULL, "%s: %s is NULL", call, !thickness ? "thickness" : "points");
    if (npoints < 0 || npoints > MFG_MAX_COUNT)
        return mfg_fail(MFG_ERR_INVALID, "%s: npoints %lld out of range", call,
                        (long long)npoints);
    if (!(min_angle > 0 && min_angle <= M_PI))
        return mfg_fail(MFG_ERR_INVALID, "%s: min_angle %g is not in (0, pi]", call, min_angle);
    int relayed = progress && progress->callback;
    medial_relay relay = {progress, "medial: elements"};
    mfg_progress inner = {relay_progress, &relay};
    mfg_medial *m = NULL;
    mfg_status st = mfg_medial_surface_p(xyz, nvertices, triangles, ntriangles, tolerance, flags,
                                         nthreads, &m, relayed ? &inner : NULL);
    if (st == MFG_ERR_CANCELLED)
        return mfg_fail(st, "%s: cancelled in stage \"%s\"", call, relay.stage);
    if (st != MFG_OK) {
        /* The detail names this call, not the one it made. */
        static const char inner_call[] = "mfg_medial_surface: ";
        char detail[512];
        const char *e = mfg_last_error();
        if (strncmp(e, inner_call, sizeof inner_call - 1) == 0)
            e += sizeof inner_call - 1;
        snprintf(detail, sizeof detail, "%s", e);
        return mfg_fail(st, "%s: %s", call, detail);
    }
    mfg_prog prog;
    mfg_prog_init(&prog, progress, call);
    prog.last = relayed ? 0.9 : 0;
    st = thickness_run(call, m, points, npoints, min_angle, thickness, centres, gaps, &prog);
    mfg_medial_free(m);
    return st;
}
