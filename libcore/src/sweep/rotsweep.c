/* SPDX-License-Identifier: LGPL-2.1-or-later */
/* rotsweep.c - the rotational swept volume of a closed polyhedron (seed 003, Baek & Shin).
 *
 * The paper's characterisation, made into a construction that cannot leave a crack:
 *
 *  - Directed circles.  Every point x lies on a circle about the axis, named by its
 *    meridian coordinates (r, z) (distance from the axis, height along it).  On that
 *    circle the solid O is a union of arcs [entry, exit]; because all points of the
 *    circle turn together, SV meets the circle in the union of the arcs
 *    [entry at t = 0, exit at t = theta] (the directed-circle rule).  circle_arcs()
 *    computes this exactly for one circle: the plane z = const cuts every triangle in a
 *    segment; the circle meets the segments at the roots of quadratics; a depth count
 *    along the circle gives O's arcs; extending each by theta and merging gives SV's.
 *    Each SV arc starts on a front face at t = 0 and ends on a back face turned by theta.
 *
 *  - The meridian decomposition.  The half-plane of (r, z) (the paper's H_ref, onto which
 *    RotProj projects the faces) is cut into cells by a quadtree.  A cell is accepted when
 *    the arc structure is the same all over it: which triangle starts and which ends every
 *    SV arc.  It changes only across the images of the mesh edges and of the silhouette
 *    lines inside faces (curves), at images of vertices, and where a front face at t = 0
 *    meets a back face at t = theta (the paper's case 1.3: the image of the 3-D segment
 *    B n R(theta) A, kept as a gap-closing curve).  A cell crossed by one curve is
 *    split along the chord between the curve's two crossings with the cell's sides; a
 *    cell holding one vertex image and only the curves that end there is split into a
 *    star round it (also round the junction of gap-closing curves; round an image on the
 *    axis, which lies on the side r = 0 of its cell, a half star); a cell crossed by
 *    several curves that do not cross in it is cut along all their chords.  Other cells
 *    are refined, down to a size below the tolerance; a cell
 *    still mixed there is cut into a fan round its centre and each piece takes the
 *    structure at its own centroid (the only approximation of the arrangement, within
 *    the smallest cell size).
 *
 *  - Lifting.  Every polygon of the decomposition carries its arc structure.  Over it, the
 *    start of an arc is a piece of one front triangle (the circle through each polygon
 *    corner meets the triangle's plane at one of two known roots), the end a piece of a
 *    back triangle turned by theta: flat polygons in the input's planes, exact up to
 *    rounding.  Corners on a curve use the curve's own 3-D point, so the pieces on both
 *    sides of an edge share their vertices.
 *
 *  - Walls.  Along every edge of the decomposition the arcs on its two sides are compared;
 *    where exactly one side covers an angle, the swept surface of revolution (plane,
 *    cone, cylinder or hyperboloid piece: the paper's silhouette faces, and the annular
 *    faces of faces perpendicular to the axis) closes the gap.  Walls are cut into strips
 *    at every angle where lines of the two sides cross, and tessellated on each circle at
 *    the angles of a per-radius grid (chord sag below half the tolerance) plus every arc
 *    end that any strip uses there, so neighbouring strips share their vertices.
 *
 * The result is the boundary of a union of "angular prisms" over the polygons: closed by
 * construction, each piece oriented by the side it bounds.
 */
#include <float.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "common/hashmap.h"
#include "mesh/mesh.h"
#include "common/mfg_internal.h"
#include "common/vec3.h"
#include "mesh/planar_merge.h"



/* ----------------------------------------------------------------------------------- */
/* Small containers                                                                     */
/* ----------------------------------------------------------------------------------- */

typedef struct sw_ctx sw_ctx;

static int64_t dbits(double x)
{
    int64_t b;
    if (x == 0)
        x = 0; /* -0 and +0 are one key */
    memcpy(&b, &x, sizeof b);
    return b;
}

/* Angle in [0, 2 pi). */
static double wrap_angle(double a)
{
    a = fmod(a, MFG_TWO_PI);
    if (a < 0)
        a += MFG_TWO_PI;
    if (a >= MFG_TWO_PI)
        a = 0;
    return a;
}

/* Signed difference a - b brought into (-pi, pi]. */
static double angle_diff(double a, double b)
{
    double d = fmod(a - b, MFG_TWO_PI);
    if (d > MFG_PI)
        d -= MFG_TWO_PI;
    else if (d <= -MFG_PI)
        d += MFG_TWO_PI;
    return d;
}

/* ----------------------------------------------------------------------------------- */
/* The solid in the axis frame                                                          */
/* ----------------------------------------------------------------------------------- */

typedef struct sw_tri {
    int64_t v[3];
    double n[3];       /* outward normal (not unit) */
    double d;          /* plane: n . x = d */
    double phi0;       /* direction of the horizontal part of n: the roots of a circle
                          with the plane lie at phi0 +- delta */
    double zmin, zmax, rmin, rmax;
    int vertical_ok;   /* the horizontal part of n is not zero: a circle can cross it */
} sw_tri;

/* A curve of the meridian decomposition: the image of a mesh edge or of a silhouette
 * segment inside a face, both straight 3-D segments p0 -> p0 + dir. */
typedef struct sw_curve {
    double p0[3], dir[3];
    double qa, qb, qc;  /* r^2(u) = qa u^2 + qb u + qc */
    double zmin, zmax, rmin, rmax;
    int64_t tri[2];     /* triangles it bounds (tri[1] = -1 for a silhouette segment) */
    int64_t vtx[2];     /* mesh vertices at u = 0, 1 (-1 where not a vertex) */
    int64_t gexit;      /* a gap-closing curve (on the entry triangle tri[0]): the exit
                           triangle whose turn by theta meets it there, else -1 */
} sw_curve;

/* One end of an SV arc on a circle: a triangle and which of the circle's two roots with
 * its plane (sigma = +-1), the angle found at the sample (exit: before the turn). */
typedef struct sw_end {
    int64_t tri;
    int sigma;
    double phi;
} sw_end;

typedef struct sw_arc {
    sw_end start, end;
} sw_arc;

/* The SV arcs of a circle: full, or n arcs (stored in the context's arc pool). */
typedef struct sw_struct {
    int full;
    int64_t n, first;
    int64_t xfirst, xn;    /* the triangles the circle crosses (in c->xpool): a full
                              circle's structure does not name them */
} sw_struct;

#define SW_MAXCURVES 8
typedef struct sw_vtx2 {   /* a vertex of the meridian decomposition */
    double r, z;
    int64_t curve;         /* the curve it lies on (-1: none) */
    double u;              /* its parameter there */
    int64_t mvtx;          /* a mesh vertex whose image it is (-1: none) */
    int ncurves;           /* every curve through it (curves with one image merge here) */
    int64_t curves[SW_MAXCURVES];
    double us[SW_MAXCURVES];
} sw_vtx2;

typedef struct sw_poly {   /* a polygon of the decomposition */
    int64_t first, n;      /* its vertex ids in poly_verts, counter-clockwise in (r, z) */
    sw_struct st;
} sw_poly;

typedef struct sw_leaf {
    int64_t ix, iz;        /* lower-left corner, in finest units */
    int level;             /* size = 2^(lmax - level) finest units */
    int kind;              /* LEAF_* */
    int64_t cfirst, cn;    /* its curves in leaf_curves */
    int64_t split_curve;   /* LEAF_SPLIT: the curve along which it is cut */
    int nchords;           /* LEAF_CHORDS: its distinct chords */
    double cr, cz;         /* LEAF_STAR / LEAF_FAN: the centre */
    int64_t cvtx;          /* LEAF_STAR: a mesh vertex imaged at the centre */
    int empty;             /* no arc anywhere and no triangle near: no polygon */
} sw_leaf;

enum { LEAF_CLEAN = 0, LEAF_SPLIT = 1, LEAF_STAR = 2, LEAF_FAN = 3, LEAF_REFINE = 4,
       LEAF_CHORDS = 5 /* cut along several chords that do not cross in it */ };

struct sw_ctx {
    mfg_status st;
    mfg_prog *prog;        /* progress of the call (mfg_progress) */
    /* input in the axis frame */
    int64_t nv, nt;
    double *lx;            /* 3 * nv local coordinates */
    double *vr;            /* r of each vertex */
    sw_tri *tris;
    int64_t *tcurves;      /* 4 per triangle: its 3 edge curves and its silhouette (-1) */
    int64_t *gstart;       /* per triangle (nt + 1): its gap-closing curves in gcurves */
    int64_t *gcurves;
    int64_t *cstamp;       /* per curve, and per triangle (vstamp): dedup stamps */
    int64_t *vstamp;
    int64_t *hstamp;       /* per triangle: the stamp of the cell in which it is hidden */
    double theta;
    int full_turn;
    double tol, hmin;
    double quantum;        /* output weld distance */
    double ext;            /* the part's extent in the axis frame */
    int bounding_only;     /* cells look at the curves of bounding triangles only */
    int64_t coarse_blocks; /* blocks in cells above the finest size (a cut that failed) */
    hmap refine;           /* (level, ix, iz) of such cells: refined when the tree is
                              built again (analyse_cell) */
    int64_t leaf_cap;      /* a placement stops past this many leaves (0: no cap) ... */
    int capped;            /* ... and says so here */
    double origin[3], frame[3][3]; /* rows: e1, e2, axis */
    /* curves */
    sw_curve *curves;
    int64_t ncurves, capcurves;
    /* bins of triangles over (r, z) */
    int64_t nbr, nbz;
    double br0, bz0, bdr, bdz;
    int64_t *bin_start, *bin_items;
    /* per-call scratch */
    int64_t *stamp;
    int64_t stampv;
    int64_t *cand;
    int64_t ncand, capcand;
    /* circle scratch */
    double *xphi;
    int64_t *xtri;
    int *xentry;
    int64_t nx, capx;
    /* triangles crossed by sampled circles */
    int64_t *xpool;
    int64_t nxpool, capxpool;
    /* arc pool */
    sw_arc *arcs;
    int64_t narcs, caparcs;
    /* quadtree */
    int lmax;
    double h;              /* finest cell size */
    double r0, z0;         /* grid origin */
    int64_t nroot_r, nroot_z;
    sw_leaf *leaves;
    int64_t nleaves, capleaves;
    int64_t *leaf_curves;
    int64_t nleaf_curves, capleaf_curves;
    hmap corners;          /* leaf corners (ix, iz) */
    hmap leafmap;          /* (level, ix, iz) -> leaf */
    /* decomposition */
    sw_vtx2 *v2;
    int64_t nv2, capv2;
    hmap v2map;
    int64_t *poly_verts;
    int64_t npv, cappv;
    sw_poly *polys;
    int64_t npolys, cappolys;
    /* output */
    double *ox;            /* 3 * nout */
    int64_t nout, capout;
    hmap outmap;           /* exact coordinates -> vertex */
    int64_t *otri;
    int64_t notri, capotri;
    int64_t *oring;        /* per triangle: its edge along a circle (walls), else -1 -1 */
    int64_t caporing;
    double *odir;          /* per triangle: the wall's direction off that circle */
    int64_t capodir;
    int64_t *oface;        /* per triangle: a face piece's plane (2 tri + exit), else -1 */
    int64_t capoface;
};

static int ctx_nomem(sw_ctx *c)
{
    if (c->st == MFG_OK)
        c->st = mfg_fail(MFG_ERR_NOMEM, "rotational sweep: out of memory");
    return 0;
}

/* Progress: one work unit (done of total) of the current stage; 0 (with c->st set to
 * MFG_ERR_CANCELLED) when the callback asked to stop. */
static int sw_poll(sw_ctx *c, double done, double total)
{
    if (mfg_prog_poll(c->prog, done, total))
        return 1;
    if (c->st == MFG_OK)
        c->st = mfg_prog_fail(c->prog);
    return 0;
}

static int sw_stage(sw_ctx *c, const char *stage, double lo, double hi, int64_t every)
{
    if (mfg_prog_stage(c->prog, stage, lo, hi, every))
        return 1;
    if (c->st == MFG_OK)
        c->st = mfg_prog_fail(c->prog);
    return 0;
}

/* A report inside a stage at its fraction q (0 .. 1), between steps that are not split
 * further. */
static int sw_report(sw_ctx *c, double q)
{
    if (mfg_prog_report(c->prog, q, 1.0))
        return 1;
    if (c->st == MFG_OK)
        c->st = mfg_prog_fail(c->prog);
    return 0;
}

/* Work units between progress reports: a quadtree cell analysed (~5-50 us), a leaf cut
 * into polygons (~2-20 us), a polygon's walls built (~2-20 us). */
#define SWEEP_EVERY_CELLS 512
#define SWEEP_EVERY_LEAVES 2048
#define SWEEP_EVERY_POLYS 2048

static double v_r(double x, double y)
{
    return sqrt(x * x + y * y);
}

/* ----------------------------------------------------------------------------------- */
/* Setup: frame, triangles, curves, bins                                                */
/* ----------------------------------------------------------------------------------- */

static void make_frame(sw_ctx *c, const double *p, const double *a)
{
    double len = sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
    double w[3] = {a[0] / len, a[1] / len, a[2] / len};
    double helper[3] = {1, 0, 0};
    if (fabs(w[0]) >= 0.9)
        helper[0] = 0, helper[1] = 1;
    /* e1 = w x helper, e2 = w x e1: (e1, e2, w) right-handed, angles grow about w */
    double e1[3] = {w[1] * helper[2] - w[2] * helper[1], w[2] * helper[0] - w[0] * helper[2],
                    w[0] * helper[1] - w[1] * helper[0]};
    double l1 = sqrt(e1[0] * e1[0] + e1[1] * e1[1] + e1[2] * e1[2]);
    for (int k = 0; k < 3; k++)
        e1[k] /= l1;
    double e2[3] = {w[1] * e1[2] - w[2] * e1[1], w[2] * e1[0] - w[0] * e1[2],
                    w[0] * e1[1] - w[1] * e1[0]};
    for (int k = 0; k < 3; k++) {
        c->origin[k] = p[k];
        c->frame[0][k] = e1[k];
        c->frame[1][k] = e2[k];
        c->frame[2][k] = w[k];
    }
}

/* Minimum distance from the axis (the local z axis) over a triangle. */
static double tri_rmin(const double *a, const double *b, const double *cc)
{
    /* Projected to the xy plane: 0 when the projection covers the origin, else the
     * distance to the nearest projected side. */
    const double *p[3] = {a, b, cc};
    double s[3];
    for (int i = 0; i < 3; i++) {
        const double *u = p[i], *v = p[(i + 1) % 3];
        s[i] = u[0] * v[1] - u[1] * v[0];
    }
    if ((s[0] >= 0 && s[1] >= 0 && s[2] >= 0) || (s[0] <= 0 && s[1] <= 0 && s[2] <= 0)) {
        double area = (b[0] - a[0]) * (cc[1] - a[1]) - (b[1] - a[1]) * (cc[0] - a[0]);
        if (area != 0)
            return 0;
    }
    double best = INFINITY;
    for (int i = 0; i < 3; i++) {
        const double *u = p[i], *v = p[(i + 1) % 3];
        double dx = v[0] - u[0], dy = v[1] - u[1];
        double l2 = dx * dx + dy * dy;
        double t = l2 > 0 ? -(u[0] * dx + u[1] * dy) / l2 : 0;
        if (t < 0)
            t = 0;
        if (t > 1)
            t = 1;
        double d = v_r(u[0] + t * dx, u[1] + t * dy);
        if (d < best)
            best = d;
    }
    return best;
}

static void curve_bounds(sw_curve *cv)
{
    const double *p = cv->p0, *d = cv->dir;
    cv->qa = d[0] * d[0] + d[1] * d[1];
    cv->qb = 2 * (p[0] * d[0] + p[1] * d[1]);
    cv->qc = p[0] * p[0] + p[1] * p[1];
    double z1 = p[2] + d[2];
    cv->zmin = fmin(p[2], z1);
    cv->zmax = fmax(p[2], z1);
    double r0 = sqrt(cv->qc), r1 = v_r(p[0] + d[0], p[1] + d[1]);
    cv->rmax = fmax(r0, r1);
    double rmin = fmin(r0, r1);
    if (cv->qa > 0) {
        double t = -cv->qb / (2 * cv->qa);
        if (t > 0 && t < 1)
            rmin = fmin(rmin, v_r(p[0] + t * d[0], p[1] + t * d[1]));
    }
    cv->rmin = rmin;
}

static int add_curve(sw_ctx *c, const double *a, const double *b, int64_t t0, int64_t t1,
                     int64_t va, int64_t vb)
{
    if (!mfg_grow((void **)&c->curves, &c->capcurves, c->ncurves + 1, sizeof *c->curves))
        return ctx_nomem(c);
    sw_curve *cv = &c->curves[c->ncurves++];
    for (int k = 0; k < 3; k++) {
        cv->p0[k] = a[k];
        cv->dir[k] = b[k] - a[k];
    }
    cv->tri[0] = t0;
    cv->tri[1] = t1;
    cv->vtx[0] = va;
    cv->vtx[1] = vb;
    cv->gexit = -1;
    curve_bounds(cv);
    return 1;
}

/* The point of edge (i, j) at height z, computed from the smaller index so that both
 * triangles of the edge get the same doubles. */
static void edge_at_z(const sw_ctx *c, int64_t i, int64_t j, double z, double out[3])
{
    if (j < i) {
        int64_t t = i;
        i = j;
        j = t;
    }
    const double *a = c->lx + 3 * i, *b = c->lx + 3 * j;
    double w = (z - a[2]) / (b[2] - a[2]);
    for (int k = 0; k < 2; k++)
        out[k] = a[k] + w * (b[k] - a[k]);
    out[2] = z;
}

/* 2^-40 of the part's size in the axis frame (its largest radius or its height): the
 * order of the frame transform's own rounding, below which the input conditioning below
 * moves vertices. */
static double frame_rounding(const sw_ctx *c)
{
    double zlo = INFINITY, zhi = -INFINITY, rhi = 0;
    for (int64_t i = 0; i < c->nv; i++) {
        zlo = fmin(zlo, c->lx[3 * i + 2]);
        zhi = fmax(zhi, c->lx[3 * i + 2]);
        rhi = fmax(rhi, c->vr[i]);
    }
    return ldexp(fmax(rhi, zhi - zlo), -40);
}

/* Faces perpendicular to the axis made exactly so.  A CAD part's flat face at z = 10 comes
 * out of tessellation and of the axis frame with heights a few ulps apart
 * (10.000000000000004 beside 10 on the bench arm); such a face then has edge images that
 * are not quite horizontal, no image of its own, and cells straddling its plane that no
 * curve explains: they were refined to the finest size and fanned, and the fans broke
 * the result's manifoldness.  Vertices joined by triangles whose heights agree to 2^-40
 * of the part's size get the height of the smallest vertex index of their group, when
 * the whole group agrees that well: a move of the order of the frame's own rounding. */
static int flatten_axial_faces(sw_ctx *c, const int64_t *tris)
{
    double eps = frame_rounding(c);
    int64_t *parent = malloc((size_t)(c->nv + 1) * sizeof *parent);
    double *lo = malloc((size_t)(2 * c->nv + 1) * sizeof *lo);
    if (!parent || !lo) {
        free(parent);
        free(lo);
        return ctx_nomem(c);
    }
    for (int64_t i = 0; i < c->nv; i++)
        parent[i] = i;
    for (int64_t t = 0; t < c->nt; t++) {
        const int64_t *v = tris + 3 * t;
        double z0 = c->lx[3 * v[0] + 2], z1 = c->lx[3 * v[1] + 2], z2 = c->lx[3 * v[2] + 2];
        if (fmax(z0, fmax(z1, z2)) - fmin(z0, fmin(z1, z2)) > eps)
            continue;
        for (int k = 1; k < 3; k++) /* the smallest index is the root: the group's height */
            mfg_uf_union(parent, v[0], v[k]);
    }
    double *hi = lo + c->nv;
    for (int64_t i = 0; i < c->nv; i++)
        lo[i] = INFINITY, hi[i] = -INFINITY;
    for (int64_t i = 0; i < c->nv; i++) {
        int64_t r = mfg_uf_find(parent, i);
        lo[r] = fmin(lo[r], c->lx[3 * i + 2]);
        hi[r] = fmax(hi[r], c->lx[3 * i + 2]);
    }
    for (int64_t i = 0; i < c->nv; i++) {
        int64_t r = mfg_uf_find(parent, i);
        if (r != i && hi[r] - lo[r] <= eps)
            c->lx[3 * i + 2] = c->lx[3 * r + 2];
    }
    free(parent);
    free(lo);
    return 1;
}

/* Vertices on the axis, as the frame computes them: at r of the order of its rounding
 * (1e-16 for a part moved off the world axes), not 0.  Their images then lie a hair
 * inside the first column of cells instead of on its side r = 0, and the curves from them
 * cross that column's sides within rounding of its corners, where the polygons' loops
 * drop such crossings (a cell cut along them found no ends to cut at and became one
 * coarse block: a box about an edge, moved, covered a whole turn near the axis, wrong by
 * the membership oracle).  Within 2^-40 of the part's size of the axis, a vertex is put
 * on it: a move of the order of the frame's own rounding. */
static void axis_vertices(sw_ctx *c)
{
    double eps = frame_rounding(c);
    for (int64_t i = 0; i < c->nv; i++)
        if (c->vr[i] <= eps) {
            c->lx[3 * i] = c->lx[3 * i + 1] = 0;
            c->vr[i] = 0;
        }
}

static int setup(sw_ctx *c, const double *xyz, const int64_t *tris, const int64_t *nb)
{
    c->lx = malloc((size_t)(3 * c->nv + 1) * sizeof *c->lx);
    c->vr = malloc((size_t)(c->nv + 1) * sizeof *c->vr);
    c->tris = malloc((size_t)(c->nt + 1) * sizeof *c->tris);
    if (!c->lx || !c->vr || !c->tris)
        return ctx_nomem(c);
    for (int64_t i = 0; i < c->nv; i++) {
        double d[3] = {xyz[3 * i] - c->origin[0], xyz[3 * i + 1] - c->origin[1],
                       xyz[3 * i + 2] - c->origin[2]};
        for (int k = 0; k < 3; k++)
            c->lx[3 * i + k] = c->frame[k][0] * d[0] + c->frame[k][1] * d[1] +
                               c->frame[k][2] * d[2];
        c->vr[i] = v_r(c->lx[3 * i], c->lx[3 * i + 1]);
    }
    axis_vertices(c);
    if (!flatten_axial_faces(c, tris))
        return 0;
    for (int64_t t = 0; t < c->nt; t++) {
        sw_tri *T = &c->tris[t];
        const double *p[3];
        for (int k = 0; k < 3; k++) {
            T->v[k] = tris[3 * t + k];
            p[k] = c->lx + 3 * T->v[k];
        }
        double e1[3], e2[3];
        for (int k = 0; k < 3; k++) {
            e1[k] = p[1][k] - p[0][k];
            e2[k] = p[2][k] - p[0][k];
        }
        T->n[0] = e1[1] * e2[2] - e1[2] * e2[1];
        T->n[1] = e1[2] * e2[0] - e1[0] * e2[2];
        T->n[2] = e1[0] * e2[1] - e1[1] * e2[0];
        T->d = (T->n[0] * (p[0][0] + p[1][0] + p[2][0]) + T->n[1] * (p[0][1] + p[1][1] + p[2][1]) +
                T->n[2] * (p[0][2] + p[1][2] + p[2][2])) / 3;
        double hn = v_r(T->n[0], T->n[1]);
        double nn = sqrt(hn * hn + T->n[2] * T->n[2]);
        T->vertical_ok = hn > 1e-14 * nn;
        T->phi0 = atan2(T->n[1], T->n[0]);
        T->zmin = fmin(p[0][2], fmin(p[1][2], p[2][2]));
        T->zmax = fmax(p[0][2], fmax(p[1][2], p[2][2]));
        T->rmax = fmax(c->vr[T->v[0]], fmax(c->vr[T->v[1]], c->vr[T->v[2]]));
        T->rmin = tri_rmin(p[0], p[1], p[2]);
    }
    c->tcurves = malloc((size_t)(4 * c->nt + 1) * sizeof *c->tcurves);
    c->vstamp = calloc((size_t)(c->nt + 1), sizeof *c->vstamp);
    c->hstamp = calloc((size_t)(c->nt + 1), sizeof *c->hstamp);
    if (!c->tcurves || !c->vstamp || !c->hstamp)
        return ctx_nomem(c);
    for (int64_t i = 0; i < 4 * c->nt; i++)
        c->tcurves[i] = -1;
    /* curves: every edge once (from the triangle with the smaller index) ... */
    for (int64_t t = 0; t < c->nt; t++)
        for (int k = 0; k < 3; k++) {
            int64_t o = nb[3 * t + k];
            if (o < t)
                continue;
            int64_t a = c->tris[t].v[k], b = c->tris[t].v[(k + 1) % 3];
            if (!add_curve(c, c->lx + 3 * a, c->lx + 3 * b, t, o, a, b))
                return 0;
            c->tcurves[4 * t + k] = c->ncurves - 1;
            for (int q = 0; q < 3; q++)
                if (tris[3 * o + q] == b && tris[3 * o + (q + 1) % 3] == a) {
                    c->tcurves[4 * o + q] = c->ncurves - 1;
                    break;
                }
        }
    /* ... and the silhouette segment inside each face: where the face's plane is tangent
     * to the circles, the line of the face in the meridian plane through phi0. */
    for (int64_t t = 0; t < c->nt; t++) {
        sw_tri *T = &c->tris[t];
        if (!T->vertical_ok)
            continue;
        double m[2] = {T->n[1], -T->n[0]}; /* n x axis */
        double s[3];
        for (int k = 0; k < 3; k++)
            s[k] = m[0] * c->lx[3 * T->v[k]] + m[1] * c->lx[3 * T->v[k] + 1];
        double pts[2][3];
        int np = 0;
        for (int k = 0; k < 3 && np < 2; k++) {
            double sa = s[k], sb = s[(k + 1) % 3];
            if ((sa < 0 && sb > 0) || (sa > 0 && sb < 0)) {
                const double *a = c->lx + 3 * T->v[k], *b = c->lx + 3 * T->v[(k + 1) % 3];
                double w = sa / (sa - sb);
                for (int q = 0; q < 3; q++)
                    pts[np][q] = a[q] + w * (b[q] - a[q]);
                np++;
            }
        }
        if (np == 1) { /* through a vertex */
            for (int k = 0; k < 3; k++)
                if (s[k] == 0) {
                    memcpy(pts[1], c->lx + 3 * T->v[k], sizeof pts[1]);
                    np = 2;
                    break;
                }
        }
        if (np == 2) {
            if (!add_curve(c, pts[0], pts[1], t, -1, -1, -1))
                return 0;
            c->tcurves[4 * t + 3] = c->ncurves - 1;
        }
    }
    /* ... and the image of each face perpendicular to the axis: the segment z = const
     * from its nearest to its farthest radius.  Circles just below such a face meet the
     * solid and circles just above do not (or the reverse) all along it, also where no
     * edge is imaged (a top face the axis passes through): without this curve the cells
     * straddling the plane saw no curve and were refined to the finest size and fanned
     * (591 fans along each of the 9-face arm's two faces).  It runs radially out to the
     * farthest vertex, which it names, so that cell stars see it end at that image.
     * Horizontal curves are never used to lift points (lift), only to cut cells. */
    for (int64_t t = 0; t < c->nt; t++) {
        sw_tri *T = &c->tris[t];
        if (T->vertical_ok || T->zmin != T->zmax || !(T->rmax > T->rmin))
            continue;
        int64_t far = T->v[0];
        for (int k = 1; k < 3; k++)
            if (c->vr[T->v[k]] > c->vr[far])
                far = T->v[k];
        const double *b = c->lx + 3 * far;
        double w = T->rmin / c->vr[far];
        double a[3] = {w * b[0], w * b[1], b[2]};
        /* when the nearest point is a vertex (a corner nearest the axis), the curve
         * starts at that vertex's image too, and names it: a star there sees every
         * curve end at the image (its computed start differs from it by rounding) */
        int64_t near = -1;
        for (int k = 0; k < 3; k++)
            if (c->vr[T->v[k]] == T->rmin && T->v[k] != far)
                near = T->v[k];
        if (!add_curve(c, a, b, t, -1, near, far))
            return 0;
        c->tcurves[4 * t + 3] = c->ncurves - 1;
    }
    c->cstamp = calloc((size_t)(c->ncurves + 1), sizeof *c->cstamp);
    if (!c->cstamp)
        return ctx_nomem(c);
    return 1;
}

/* Bins of triangles over their (r, z) images. */
static int build_bins(sw_ctx *c, double rmax, double zmin, double zmax)
{
    int64_t g = (int64_t)ceil(sqrt((double)c->nt)) + 1;
    if (g > 2048)
        g = 2048;
    for (;;) {
        c->nbr = g;
        c->nbz = g;
        c->br0 = 0;
        c->bz0 = zmin;
        c->bdr = (rmax > 0 ? rmax : 1) / (double)g * (1 + 1e-9);
        c->bdz = (zmax > zmin ? zmax - zmin : 1) / (double)g * (1 + 1e-9);
        int64_t total = 0;
        for (int64_t t = 0; t < c->nt; t++) {
            const sw_tri *T = &c->tris[t];
            int64_t i0 = (int64_t)(T->rmin / c->bdr), i1 = (int64_t)(T->rmax / c->bdr);
            int64_t j0 = (int64_t)((T->zmin - zmin) / c->bdz), j1 = (int64_t)((T->zmax - zmin) / c->bdz);
            if (i1 >= g) i1 = g - 1;
            if (j1 >= g) j1 = g - 1;
            total += (i1 - i0 + 1) * (j1 - j0 + 1);
        }
        if (total > 24 * c->nt + 64 && g > 4) {
            g /= 2;
            continue;
        }
        c->bin_start = calloc((size_t)(g * g + 1), sizeof *c->bin_start);
        c->bin_items = malloc((size_t)(total + 1) * sizeof *c->bin_items);
        if (!c->bin_start || !c->bin_items)
            return ctx_nomem(c);
        for (int pass = 0; pass < 2; pass++) {
            for (int64_t t = 0; t < c->nt; t++) {
                const sw_tri *T = &c->tris[t];
                int64_t i0 = (int64_t)(T->rmin / c->bdr), i1 = (int64_t)(T->rmax / c->bdr);
                int64_t j0 = (int64_t)((T->zmin - zmin) / c->bdz), j1 = (int64_t)((T->zmax - zmin) / c->bdz);
                if (i1 >= g) i1 = g - 1;
                if (j1 >= g) j1 = g - 1;
                for (int64_t j = j0; j <= j1; j++)
                    for (int64_t i = i0; i <= i1; i++) {
                        int64_t b = j * g + i;
                        if (pass == 0)
                            c->bin_start[b + 1]++;
                        else
                            c->bin_items[c->bin_start[b]++] = t;
                    }
            }
            if (pass == 0) {
                for (int64_t b = 0; b < g * g; b++)
                    c->bin_start[b + 1] += c->bin_start[b];
            } else {
                for (int64_t b = g * g; b > 0; b--)
                    c->bin_start[b] = c->bin_start[b - 1];
                c->bin_start[0] = 0;
            }
        }
        c->stamp = calloc((size_t)(c->nt + 1), sizeof *c->stamp);
        if (!c->stamp)
            return ctx_nomem(c);
        return 1;
    }
}

static int64_t bin_r(const sw_ctx *c, double r)
{
    if (r < 0)
        return 0;
    double i = r / c->bdr;
    return i >= (double)(c->nbr - 1) ? c->nbr - 1 : (int64_t)i;
}

static int64_t bin_z(const sw_ctx *c, double z)
{
    double i = (z - c->bz0) / c->bdz;
    if (i < 0)
        return 0;
    return i >= (double)(c->nbz - 1) ? c->nbz - 1 : (int64_t)i;
}

/* Triangles whose image box meets [ra, rb] x [za, zb] into c->cand (deduplicated). */
static int gather(sw_ctx *c, double ra, double rb, double za, double zb)
{
    c->ncand = 0;
    c->stampv++;
    int64_t i0 = bin_r(c, ra), i1 = bin_r(c, rb), j0 = bin_z(c, za), j1 = bin_z(c, zb);
    for (int64_t j = j0; j <= j1; j++)
        for (int64_t i = i0; i <= i1; i++) {
            int64_t b = j * c->nbr + i;
            for (int64_t k = c->bin_start[b]; k < c->bin_start[b + 1]; k++) {
                int64_t t = c->bin_items[k];
                if (c->stamp[t] == c->stampv)
                    continue;
                c->stamp[t] = c->stampv;
                const sw_tri *T = &c->tris[t];
                if (T->rmax < ra || T->rmin > rb || T->zmax < za || T->zmin > zb)
                    continue;
                if (!mfg_grow((void **)&c->cand, &c->capcand, c->ncand + 1, sizeof *c->cand))
                    return ctx_nomem(c);
                c->cand[c->ncand++] = t;
            }
        }
    return 1;
}

/* ----------------------------------------------------------------------------------- */
/* Directed circles                                                                     */
/* ----------------------------------------------------------------------------------- */

/* Clips the line x(s) = p + s d, lying in the plane of the triangle (a, b, cc) with normal
 * n (counter-clockwise about n), to the triangle: the interval [*s0, *s1] shrinks. */
static void clip_to_triangle(const double *p, const double *d, const double *a, const double *b,
                             const double *cc, const double *n, double *s0, double *s1)
{
    const double *v[3] = {a, b, cc};
    for (int k = 0; k < 3 && *s0 <= *s1; k++) {
        const double *u = v[k], *w = v[(k + 1) % 3];
        double e[3] = {w[0] - u[0], w[1] - u[1], w[2] - u[2]};
        double q[3] = {p[0] - u[0], p[1] - u[1], p[2] - u[2]};
        /* f(s) = ((e x (p + s d - u)) . n) >= 0 inside */
        double f0 = (e[1] * q[2] - e[2] * q[1]) * n[0] + (e[2] * q[0] - e[0] * q[2]) * n[1] +
                    (e[0] * q[1] - e[1] * q[0]) * n[2];
        double f1 = (e[1] * d[2] - e[2] * d[1]) * n[0] + (e[2] * d[0] - e[0] * d[2]) * n[1] +
                    (e[0] * d[1] - e[1] * d[0]) * n[2];
        if (f1 == 0) {
            if (f0 < 0)
                *s1 = *s0 - 1;
        } else if (f1 > 0) {
            *s0 = fmax(*s0, -f0 / f1);
        } else {
            *s1 = fmin(*s1, -f0 / f1);
        }
    }
}

/* Clips the line x(s) = p + s d to where the circle direction (-y, x, 0) points out of
 * (sign > 0) or into (sign < 0) a plane of normal n: the interval [*s0, *s1] shrinks. */
static void clip_to_motion(const double *p, const double *d, const double *n, int sign,
                           double *s0, double *s1)
{
    double f0 = sign * (n[1] * p[0] - n[0] * p[1]), f1 = sign * (n[1] * d[0] - n[0] * d[1]);
    if (f1 == 0) {
        if (f0 < 0)
            *s1 = *s0 - 1;
    } else if (f1 > 0) {
        *s0 = fmax(*s0, -f0 / f1);
    } else {
        *s1 = fmin(*s1, -f0 / f1);
    }
}

/* Does segment x0 x1 lie (within eps) on the line of a side of triangle v? */
static int along_an_edge(const double *x0, const double *x1, const double *const *v, double eps)
{
    for (int k = 0; k < 3; k++) {
        const double *u = v[k], *w = v[(k + 1) % 3];
        double e[3] = {w[0] - u[0], w[1] - u[1], w[2] - u[2]};
        double le = sqrt(e[0] * e[0] + e[1] * e[1] + e[2] * e[2]);
        if (!(le > 0))
            continue;
        int on = 1;
        for (int j = 0; j < 2 && on; j++) {
            const double *x = j ? x1 : x0;
            double q[3] = {x[0] - u[0], x[1] - u[1], x[2] - u[2]};
            double cx = q[1] * e[2] - q[2] * e[1], cy = q[2] * e[0] - q[0] * e[2],
                   cz = q[0] * e[1] - q[1] * e[0];
            on = sqrt(cx * cx + cy * cy + cz * cz) <= eps * le;
        }
        if (on)
            return 1;
    }
    return 0;
}

/* Does the circle direction (counter-clockwise about the axis) point into (sign < 0) or
 * out of (sign > 0) triangle T's plane somewhere on it? */
static int faces_motion(const sw_ctx *c, const sw_tri *T, int sign)
{
    for (int k = 0; k < 3; k++) {
        const double *p = c->lx + 3 * T->v[k];
        double nt = -T->n[0] * p[1] + T->n[1] * p[0];
        if (sign * nt > 0)
            return 1;
    }
    return 0;
}

/*
 * Gap-closing curves (the paper's case 1.3).  Where an exit face A, turned by theta, meets
 * an entry face B, the gap between two arcs of a circle closes: the arc structure changes
 * along the image of the 3-D segment B n R(theta) A although no edge is imaged there.
 * Without that curve the decomposition refined down to blocks all along it.  Each segment
 * is kept as a curve of B (its own lifts land on it), found for the pairs of triangles
 * whose (r, z) boxes overlap (the image of R(theta) A is A's).
 */
static int build_gap_curves(sw_ctx *c)
{
    if (c->full_turn)
        return 1;
    c->gstart = calloc((size_t)(c->nt + 2), sizeof *c->gstart);
    if (!c->gstart)
        return ctx_nomem(c);
    int64_t *items = NULL, nitems = 0, capitems = 0;
    double ct = cos(c->theta), st = sin(c->theta);
    for (int64_t b = 0; b < c->nt; b++) {
        c->gstart[b] = nitems;
        const sw_tri *B = &c->tris[b];
        if (!B->vertical_ok || !faces_motion(c, B, -1))
            continue;
        if (!gather(c, B->rmin, B->rmax, B->zmin, B->zmax)) {
            free(items);
            return 0;
        }
        const double *pb[3] = {c->lx + 3 * B->v[0], c->lx + 3 * B->v[1], c->lx + 3 * B->v[2]};
        double nbn = sqrt(B->n[0] * B->n[0] + B->n[1] * B->n[1] + B->n[2] * B->n[2]);
        for (int64_t k = 0; k < c->ncand; k++) {
            int64_t a = c->cand[k];
            const sw_tri *A = &c->tris[a];
            if (!A->vertical_ok || !faces_motion(c, A, 1))
                continue;
            /* A turned by theta */
            double pa[3][3], na[3];
            for (int q = 0; q < 3; q++) {
                const double *x = c->lx + 3 * A->v[q];
                pa[q][0] = x[0] * ct - x[1] * st;
                pa[q][1] = x[0] * st + x[1] * ct;
                pa[q][2] = x[2];
            }
            na[0] = A->n[0] * ct - A->n[1] * st;
            na[1] = A->n[0] * st + A->n[1] * ct;
            na[2] = A->n[2];
            double d[3] = {B->n[1] * na[2] - B->n[2] * na[1], B->n[2] * na[0] - B->n[0] * na[2],
                           B->n[0] * na[1] - B->n[1] * na[0]};
            double dd = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
            double nan_ = sqrt(na[0] * na[0] + na[1] * na[1] + na[2] * na[2]);
            if (!(dd > 1e-16 * nbn * nbn * nan_ * nan_))
                continue; /* parallel planes: no crossing line */
            /* a point on both planes: p = (dB (na x d) + dA (d x nB)) / |d|^2 */
            double dA = A->d; /* turning keeps the plane's offset from the axis origin */
            double nxd[3] = {na[1] * d[2] - na[2] * d[1], na[2] * d[0] - na[0] * d[2], na[0] * d[1] - na[1] * d[0]};
            double dxn[3] = {d[1] * B->n[2] - d[2] * B->n[1], d[2] * B->n[0] - d[0] * B->n[2],
                             d[0] * B->n[1] - d[1] * B->n[0]};
            double p[3];
            for (int q = 0; q < 3; q++)
                p[q] = (B->d * nxd[q] + dA * dxn[q]) / dd;
            double s0 = -INFINITY, s1 = INFINITY;
            clip_to_triangle(p, d, pb[0], pb[1], pb[2], B->n, &s0, &s1);
            clip_to_triangle(p, d, pa[0], pa[1], pa[2], na, &s0, &s1);
            /* only where the circles enter B and leave A turned: elsewhere the two faces
             * do not bound one gap, and the arc structure does not change */
            clip_to_motion(p, d, B->n, -1, &s0, &s1);
            clip_to_motion(p, d, na, 1, &s0, &s1);
            if (!(s1 > s0) || !isfinite(s0) || !isfinite(s1))
                continue;
            double x0[3], x1[3], len = 0;
            for (int q = 0; q < 3; q++) {
                x0[q] = p[q] + s0 * d[q];
                x1[q] = p[q] + s1 * d[q];
                len += (x1[q] - x0[q]) * (x1[q] - x0[q]);
            }
            if (!(sqrt(len) > 1e-6 * c->tol))
                continue;
            /* A segment stopped by the axis (where the motion changes sign, e.g. a plane and
             * its half turn) ends on it: exactly, and at u = 0, so that its image has r = 0
             * there (r(u) from the quadratic loses half the digits near the axis). */
            double scale = 1e-9 * (B->rmax + fabs(B->zmin) + fabs(B->zmax));
            if (v_r(x1[0], x1[1]) <= scale) {
                double t[3];
                memcpy(t, x0, sizeof t);
                memcpy(x0, x1, sizeof t);
                memcpy(x1, t, sizeof t);
            }
            if (v_r(x0[0], x0[1]) <= scale)
                x0[0] = x0[1] = 0;
            /* On the axis (two planes through it), or along an edge of B or of A turned
             * (the gap closes just where a face ends): the image is the axis or that edge's,
             * whose curve already cuts the cell; a second curve on one image only made
             * coincident chords. */
            if (v_r(x1[0], x1[1]) <= scale || along_an_edge(x0, x1, pb, scale) ||
                along_an_edge(x0, x1, (const double *[3]){pa[0], pa[1], pa[2]}, scale))
                continue;
            if (!add_curve(c, x0, x1, b, -1, -1, -1) ||
                !mfg_grow((void **)&items, &capitems, nitems + 1, sizeof *items)) {
                free(items);
                return ctx_nomem(c);
            }
            c->curves[c->ncurves - 1].gexit = a;
            items[nitems++] = c->ncurves - 1;
        }
    }
    c->gstart[c->nt] = nitems;
    c->gcurves = items;
    free(c->cstamp);
    c->cstamp = calloc((size_t)(c->ncurves + 1), sizeof *c->cstamp);
    if (!c->cstamp)
        return ctx_nomem(c);
    return 1;
}

/* The slice of triangle t by the plane z: 0 when it has none (a vertex counts as above
 * when its height is >= z, the same rule for every triangle, so the slices of a closed
 * mesh form closed polygons). */
static int tri_slice(const sw_ctx *c, int64_t t, double z, double e[2][3])
{
    const sw_tri *T = &c->tris[t];
    int above[3], na = 0;
    for (int k = 0; k < 3; k++) {
        above[k] = c->lx[3 * T->v[k] + 2] >= z;
        na += above[k];
    }
    if (na == 0 || na == 3)
        return 0;
    int m = 0;
    for (int k = 0; k < 3; k++) {
        int k1 = (k + 1) % 3;
        if (above[k] != above[k1])
            edge_at_z(c, T->v[k], T->v[k1], z, e[m++]);
    }
    return 1;
}

static int sigma_of(const sw_tri *T, double phi)
{
    return angle_diff(phi, T->phi0) >= 0 ? 1 : -1;
}

static int push_cross(sw_ctx *c, double phi, int64_t t, int entry)
{
    if (!mfg_grow((void **)&c->xphi, &c->capx, c->nx + 1, sizeof *c->xphi))
        return ctx_nomem(c);
    int64_t cap = c->capx;
    /* xtri and xentry follow xphi's capacity */
    int64_t *nt = realloc(c->xtri, (size_t)cap * sizeof *nt);
    if (!nt)
        return ctx_nomem(c);
    c->xtri = nt;
    int *ne = realloc(c->xentry, (size_t)cap * sizeof *ne);
    if (!ne)
        return ctx_nomem(c);
    c->xentry = ne;
    c->xphi[c->nx] = phi;
    c->xtri[c->nx] = t;
    c->xentry[c->nx] = entry;
    c->nx++;
    return 1;
}

/* Is the point (side * r, 0, z) inside O?  Ray parity in the plane z along side * x,
 * half-open on y. */
static int circle_inside_side(sw_ctx *c, double r, double z, int side)
{
    if (!gather(c, r, INFINITY, z, z))
        return -1;
    int inside = 0;
    for (int64_t k = 0; k < c->ncand; k++) {
        double e[2][3];
        if (!tri_slice(c, c->cand[k], z, e))
            continue;
        int ya = e[0][1] >= 0, yb = e[1][1] >= 0;
        if (ya == yb)
            continue;
        double w = e[0][1] / (e[0][1] - e[1][1]);
        double x = e[0][0] + w * (e[1][0] - e[0][0]);
        if (side * x > r)
            inside ^= 1;
    }
    return inside;
}

static int circle_inside(sw_ctx *c, double r, double z)
{
    return circle_inside_side(c, r, z, 1);
}

/* Is the point at angle psi on the circle (r, z) inside O?  The same ray parity as
 * circle_inside_side, along the ray from the point away from the axis (the slices turned
 * by -psi, so that shared slice ends stay shared). */
static int point_inside(sw_ctx *c, double r, double z, double psi)
{
    if (!gather(c, r, INFINITY, z, z))
        return -1;
    double cp = cos(psi), sp = sin(psi);
    int inside = 0;
    for (int64_t k = 0; k < c->ncand; k++) {
        double e[2][3];
        if (!tri_slice(c, c->cand[k], z, e))
            continue;
        double x0 = e[0][0] * cp + e[0][1] * sp, y0 = -e[0][0] * sp + e[0][1] * cp;
        double x1 = e[1][0] * cp + e[1][1] * sp, y1 = -e[1][0] * sp + e[1][1] * cp;
        int ya = y0 >= 0, yb = y1 >= 0;
        if (ya == yb)
            continue;
        double w = y0 / (y0 - y1);
        if (x0 + w * (x1 - x0) > r)
            inside ^= 1;
    }
    return inside;
}

typedef struct xsort {
    double phi;
    int64_t tri;
    int entry;
} xsort;

static int cmp_x(const void *pa, const void *pb)
{
    const xsort *a = pa, *b = pb;
    if (a->phi != b->phi)
        return a->phi < b->phi ? -1 : 1;
    if (a->tri != b->tri)
        return a->tri < b->tri ? -1 : 1;
    return a->entry - b->entry;
}

static int push_arc(sw_ctx *c, const sw_arc *a)
{
    if (!mfg_grow((void **)&c->arcs, &c->caparcs, c->narcs + 1, sizeof *c->arcs))
        return ctx_nomem(c);
    c->arcs[c->narcs++] = *a;
    return 1;
}

/* The SV arcs on the circle (r, z), appended to the arc pool. */
static int circle_arcs_at(sw_ctx *c, double r, double z, sw_struct *out, int *inconsistent)
{
    *inconsistent = 0;
    out->full = 0;
    out->n = 0;
    out->first = c->narcs;
    out->xfirst = c->nxpool;
    out->xn = 0;
    if (r <= 0) {
        int in = circle_inside(c, 0, z);
        if (in < 0)
            return 0;
        out->full = in;
        return 1;
    }
    if (!gather(c, r, r, z, z))
        return 0;
    c->nx = 0;
    double r2 = r * r;
    for (int64_t k = 0; k < c->ncand; k++) {
        int64_t t = c->cand[k];
        const sw_tri *T = &c->tris[t];
        if (!T->vertical_ok)
            continue;
        double e[2][3];
        if (!tri_slice(c, t, z, e))
            continue;
        double ga = e[0][0] * e[0][0] + e[0][1] * e[0][1] - r2;
        double gb = e[1][0] * e[1][0] + e[1][1] * e[1][1] - r2;
        double dx = e[1][0] - e[0][0], dy = e[1][1] - e[0][1];
        double qa = dx * dx + dy * dy;
        if (qa == 0)
            continue;
        double qb = 2 * (e[0][0] * dx + e[0][1] * dy);
        double roots[2];
        int nr = 0;
        int ina = ga < 0, inb = gb < 0;
        double disc = qb * qb - 4 * qa * ga;
        if (disc < 0)
            disc = 0;
        double sq = sqrt(disc);
        if (ina != inb) {
            /* one root in [0, 1]: the one where g changes sign */
            double s1 = (-qb - sq) / (2 * qa), s2 = (-qb + sq) / (2 * qa);
            double s = ina ? s2 : s1; /* leaving the disc: larger root; entering: smaller */
            if (s < 0) s = 0;
            if (s > 1) s = 1;
            roots[nr++] = s;
        } else if (!ina) {
            double sm = -qb / (2 * qa);
            if (sm > 0 && sm < 1) {
                double mx = e[0][0] + sm * dx, my = e[0][1] + sm * dy;
                if (mx * mx + my * my - r2 < 0) {
                    double s1 = (-qb - sq) / (2 * qa), s2 = (-qb + sq) / (2 * qa);
                    roots[nr++] = s1 < 0 ? 0 : s1;
                    roots[nr++] = s2 > 1 ? 1 : s2;
                }
            }
        }
        for (int q = 0; q < nr; q++) {
            double x = e[0][0] + roots[q] * dx, y = e[0][1] + roots[q] * dy;
            double phi = wrap_angle(atan2(y, x));
            /* moving along +phi (direction (-y, x)) against the outward normal: entry */
            double dot = T->n[0] * (-y) + T->n[1] * x;
            int entry;
            if (nr == 2)
                entry = dot < 0 ? 1 : (dot > 0 ? 0 : (q == 0));
            else
                entry = dot < 0;
            if (!push_cross(c, phi, t, entry))
                return 0;
        }
    }
    out->xfirst = c->nxpool;
    out->xn = 0;
    if (!mfg_grow((void **)&c->xpool, &c->capxpool, c->nxpool + c->nx + 1, sizeof *c->xpool))
        return ctx_nomem(c);
    for (int64_t i = 0; i < c->nx; i++)
        c->xpool[c->nxpool++] = c->xtri[i];
    out->xn = c->nx;
    if (c->nx == 0) {
        /* no crossing: the whole circle is in or out; two opposite points must agree */
        int in = circle_inside(c, r, z);
        if (in < 0)
            return 0;
        int in2 = circle_inside_side(c, r, z, -1);
        if (in2 < 0)
            return 0;
        if (in != in2) {
            *inconsistent = 1;
            return 1;
        }
        out->full = in;
        return 1;
    }
    /* sort by angle; depth count (relative to its minimum) gives O's arcs */
    xsort *xs = malloc((size_t)c->nx * sizeof *xs);
    if (!xs)
        return ctx_nomem(c);
    for (int64_t i = 0; i < c->nx; i++) {
        xs[i].phi = c->xphi[i];
        xs[i].tri = c->xtri[i];
        xs[i].entry = c->xentry[i];
    }
    qsort(xs, (size_t)c->nx, sizeof *xs, cmp_x);
    int64_t n = c->nx;
    int64_t depth = 0, mind = 0, minpos = 0;
    for (int64_t i = 0; i < n; i++) {
        depth += xs[i].entry ? 1 : -1;
        if (depth < mind) {
            mind = depth;
            minpos = i + 1;
        }
    }
    if (depth != 0) {
        /* entries and exits do not pair up: the circle grazes a vertex or an edge within
         * rounding; the caller moves it slightly */
        free(xs);
        *inconsistent = 1;
        return 1;
    }
    /* Start right after the position of minimum depth: there depth (relative) is 0. */
    int64_t nO = 0;
    sw_arc *oarcs = malloc((size_t)(n / 2 + 2) * sizeof *oarcs);
    if (!oarcs) {
        free(xs);
        return ctx_nomem(c);
    }
    int64_t d = 0;
    sw_arc cur;
    memset(&cur, 0, sizeof cur);
    double base = 0;
    for (int64_t k = 0; k < n; k++) {
        int64_t i = (minpos + k) % n;
        double phi = xs[i].phi + ((minpos + k) >= n ? MFG_TWO_PI : 0);
        if (k == 0)
            base = phi;
        (void)base;
        const sw_tri *T = &c->tris[xs[i].tri];
        if (xs[i].entry) {
            if (d == 0) {
                cur.start.tri = xs[i].tri;
                cur.start.phi = phi;
                cur.start.sigma = sigma_of(T, xs[i].phi);
            }
            d++;
        } else {
            if (d > 0)
                d--;
            if (d == 0 && nO < n / 2 + 2) {
                cur.end.tri = xs[i].tri;
                cur.end.phi = phi;
                cur.end.sigma = sigma_of(T, xs[i].phi);
                oarcs[nO++] = cur;
            }
        }
    }
    free(xs);
    if (nO == 0) {
        free(oarcs);
        *inconsistent = 1;
        return 1;
    }
    if (c->full_turn) {
        free(oarcs);
        out->full = 1;
        return 1;
    }
    /* extend each arc's end by theta and merge (arcs are in increasing start order, all
     * starts within one turn of the first) */
    double th = c->theta;
    for (int64_t i = 0; i < nO; i++)
        if (oarcs[i].end.phi + th - oarcs[i].start.phi >= MFG_TWO_PI) {
            free(oarcs);
            out->full = 1;
            return 1;
        }
    /* find an arc not covered by its predecessor's extension */
    int64_t j0 = -1;
    for (int64_t i = 0; i < nO; i++) {
        int64_t p = (i + nO - 1) % nO;
        double pend = oarcs[p].end.phi + th - (i == 0 ? MFG_TWO_PI : 0);
        if (pend < oarcs[i].start.phi) {
            j0 = i;
            break;
        }
    }
    if (j0 < 0) {
        free(oarcs);
        out->full = 1;
        return 1;
    }
    sw_arc m = oarcs[j0];
    double mend = m.end.phi + th;
    for (int64_t k = 1; k <= nO; k++) {
        int64_t i = (j0 + k) % nO;
        double s = oarcs[i].start.phi + ((j0 + k) >= nO ? MFG_TWO_PI : 0);
        if (k < nO && s <= mend) {
            double e = oarcs[i].end.phi + ((j0 + k) >= nO ? MFG_TWO_PI : 0) + th;
            if (e > mend) {
                mend = e;
                m.end = oarcs[i].end;
                m.end.phi = e - th; /* unwrapped like the start: end - start is the length */
            }
            continue;
        }
        if (!push_arc(c, &m)) {
            free(oarcs);
            return 0;
        }
        out->n++;
        if (k < nO) {
            m = oarcs[i];
            m.start.phi = s;
            m.end.phi = s + (oarcs[i].end.phi - oarcs[i].start.phi);
            mend = m.end.phi + th;
        }
    }
    free(oarcs);
    return 1;
}

static int cmp_double_asc(const void *pa, const void *pb);

/* The SV arcs on the circle (r, z).  A circle through a vertex or along an edge within
 * rounding can count entries and exits that do not pair up; it is then moved by a few
 * units in the last place of the part's size (far below any tolerance) until they do.
 * A sample on the axis (r = 0: corners and loop vertices of the cells along it) is taken
 * as the limit r -> 0+, on a circle of radius axis_radius: the structure of the polygons
 * touching the axis, which is what the samples stand for.  At r = 0 itself the "circle"
 * is a point, full or empty by ray parity, where the axis lies in a face or along an edge
 * of the solid an arbitrary answer that never matched its neighbours' arcs: every cell
 * along such an axis was refined down to blocks (box about an edge: one column of blocks
 * along the edge, blocks beyond the caps). */
static double axis_radius(const sw_ctx *c)
{
    /* far below the finest cell (a curve passing between the axis and it at a corner's
     * height is a near-coincidence the grid placement avoids), far above the rounding
     * moves below */
    return fmin(0.25 * c->h, fmax(ldexp(c->h, -12), ldexp(c->ext, -26)));
}

static int circle_arcs(sw_ctx *c, double r, double z, sw_struct *out)
{
    static const double dr[4] = {0, 0x1p-34, -0x1p-29, 0x1p-24};
    static const double dz[4] = {0, 0x1p-35, 0x1p-30, -0x1p-25};
    if (r <= 0)
        r = axis_radius(c);
    for (int k = 0; k < 4; k++) {
        int64_t mark = c->narcs, xmark = c->nxpool;
        int bad = 0;
        double rk = r + dr[k] * c->ext, zk = z + dz[k] * c->ext;
        if (rk < 0)
            rk = 0;
        if (!circle_arcs_at(c, rk, zk, out, &bad))
            return 0;
        if (!bad)
            return 1;
        c->narcs = mark;
        c->nxpool = xmark;
    }
    /* still unpaired: one arc over every crossing seen (the complement of the widest gap
     * between them), extended by theta - local and conservative, where a full circle
     * would put a ring far outside SV */
    int64_t mark = c->narcs;
    int bad = 0;
    if (!circle_arcs_at(c, r, z, out, &bad))
        return 0;
    c->narcs = mark;
    out->full = 0;
    out->n = 0;
    out->first = c->narcs;
    if (c->nx == 0)
        return 1;
    double *ph = malloc((size_t)c->nx * sizeof *ph);
    if (!ph)
        return ctx_nomem(c);
    for (int64_t i = 0; i < c->nx; i++)
        ph[i] = c->xphi[i];
    qsort(ph, (size_t)c->nx, sizeof *ph, cmp_double_asc);
    int64_t gi = c->nx - 1;
    double gap = ph[0] + MFG_TWO_PI - ph[c->nx - 1];
    for (int64_t i = 0; i + 1 < c->nx; i++)
        if (ph[i + 1] - ph[i] > gap) {
            gap = ph[i + 1] - ph[i];
            gi = i;
        }
    double a0 = ph[(gi + 1) % c->nx], a1 = ph[gi];
    free(ph);
    double len = wrap_angle(a1 - a0);
    if (len + c->theta >= MFG_TWO_PI || c->full_turn) {
        out->full = 1;
        return 1;
    }
    sw_arc arc;
    memset(&arc, 0, sizeof arc);
    arc.start.tri = arc.end.tri = -1; /* meridian caps, like a block's */
    arc.start.phi = a0;
    arc.end.phi = a0 + len;
    if (!push_arc(c, &arc))
        return 0;
    out->n = 1;
    return 1;
}

static int cmp_double_asc(const void *pa, const void *pb)
{
    double a = *(const double *)pa, b = *(const double *)pb;
    return (a > b) - (a < b);
}

/* Same structure: same full flag and the same (triangle, root) at both ends of every arc,
 * compared as sets (the arcs of one circle are distinct, their order cyclic). */
static int same_struct(const sw_ctx *c, const sw_struct *a, const sw_struct *b)
{
    if (a->full != b->full || a->n != b->n)
        return 0;
    for (int64_t i = 0; i < a->n; i++) {
        const sw_arc *x = &c->arcs[a->first + i];
        int found = 0;
        for (int64_t j = 0; j < b->n && !found; j++) {
            const sw_arc *y = &c->arcs[b->first + j];
            found = x->start.tri == y->start.tri && x->start.sigma == y->start.sigma &&
                    x->end.tri == y->end.tri && x->end.sigma == y->end.sigma;
        }
        if (!found)
            return 0;
    }
    return 1;
}

/* ----------------------------------------------------------------------------------- */
/* The meridian decomposition                                                           */
/* ----------------------------------------------------------------------------------- */

static double grid_r(const sw_ctx *c, int64_t i)
{
    return c->r0 + (double)i * c->h;
}

static double grid_z(const sw_ctx *c, int64_t i)
{
    return c->z0 + (double)i * c->h;
}

/* A crossing of a curve with a side of a cell: its position along the side's line, the
 * curve parameter and which root. */
typedef struct sw_cross {
    double pos, u;
    int64_t curve;
} sw_cross;

/* The real roots of a x^2 + b x + c = 0 in ascending order, in the stable form (no
 * cancellation between -b and the square root); a negative discriminant counts as zero
 * (a double root) when clamp is set - a tangency lost to rounding - else gives none. */
static int solve_quadratic(double a, double b, double c, int clamp, double roots[2])
{
    if (a == 0) {
        if (b == 0)
            return 0;
        roots[0] = -c / b;
        return 1;
    }
    double disc = b * b - 4 * a * c;
    if (disc < 0) {
        if (!clamp)
            return 0;
        disc = 0;
    }
    double sq = sqrt(disc), q = -0.5 * (b + (b >= 0 ? sq : -sq));
    double r1 = q / a, r2 = q != 0 ? c / q : r1;
    if (r1 > r2) {
        double t = r1;
        r1 = r2;
        r2 = t;
    }
    roots[0] = r1;
    if (r2 == r1)
        return 1;
    roots[1] = r2;
    return 2;
}

/* Crossings of curve cv with the open segment of the line r = val (vertical_side) or
 * z = val between lo and hi.  Up to 2. */
static int curve_side(const sw_curve *cv, int rside, double val, double lo, double hi,
                      double pos[2], double us[2])
{
    int n = 0;
    if (!rside) {
        if (cv->dir[2] == 0)
            return 0; /* horizontal: lies in its own plane z = const, never crosses one */
        double u = (val - cv->p0[2]) / cv->dir[2];
        if (!(u >= 0 && u <= 1))
            return 0;
        double r2 = cv->qa * u * u + cv->qb * u + cv->qc;
        double r = sqrt(r2 > 0 ? r2 : 0);
        if (r > lo && r < hi) {
            pos[n] = r;
            us[n++] = u;
        }
        return n;
    }
    /* qa u^2 + qb u + qc - val^2 = 0 */
    double roots[2];
    int nr = solve_quadratic(cv->qa, cv->qb, cv->qc - val * val, 0, roots);
    for (int k = 0; k < nr; k++) {
        double u = roots[k];
        if (!(u >= 0 && u <= 1))
            continue;
        double z = cv->p0[2] + u * cv->dir[2];
        if (z > lo && z < hi) {
            pos[n] = z;
            us[n++] = u;
        }
    }
    return n;
}

/* The 4 sides of cell (ix, iz, size s) in counter-clockwise order: side k runs from
 * corner k to corner k+1; corners (ix, iz), (ix+s, iz), (ix+s, iz+s), (ix, iz+s). */
static void side_geom(const sw_ctx *c, int64_t ix, int64_t iz, int64_t s, int k, int *rside,
                      double *val, double *lo, double *hi)
{
    double ra = grid_r(c, ix), rb = grid_r(c, ix + s), za = grid_z(c, iz), zb = grid_z(c, iz + s);
    switch (k) {
    case 0: *rside = 0; *val = za; *lo = ra; *hi = rb; break;
    case 1: *rside = 1; *val = rb; *lo = za; *hi = zb; break;
    case 2: *rside = 0; *val = zb; *lo = ra; *hi = rb; break;
    default: *rside = 1; *val = ra; *lo = za; *hi = zb; break;
    }
}

typedef struct sw_cellinfo {
    int kind;              /* 0 clean, 1 split, 2 star, 3 refine / fallback */
    int64_t split_curve;
    int64_t nvimg;         /* distinct vertex images in the closed cell */
    double vimg[2];        /* one of them */
    int64_t vimg_vtx;
    int vimg_inside;       /* strictly inside */
} sw_cellinfo;

/* Sample (cached at grid corners). */
static int corner_sample(sw_ctx *c, hmap *cache, int64_t ix, int64_t iz, sw_struct **pool,
                         int64_t *npool, int64_t *cappool, int64_t *out)
{
    hkey k = mkkey(ix, iz, 0, 0);
    int64_t v = hmap_get(cache, &k);
    if (v >= 0) {
        *out = v;
        return 1;
    }
    sw_struct s;
    if (!circle_arcs(c, grid_r(c, ix), grid_z(c, iz), &s))
        return 0;
    if (!mfg_grow((void **)pool, cappool, *npool + 1, sizeof **pool))
        return ctx_nomem(c);
    (*pool)[*npool] = s;
    if (!hmap_put(cache, &k, *npool))
        return ctx_nomem(c);
    *out = (*npool)++;
    return 1;
}


/* Sag of curve cv between parameters ua and ub from its chord, in the (r, z) plane. */
static double curve_sag(const sw_curve *cv, double ua, double ub)
{
    double ra = sqrt(fmax(0, cv->qa * ua * ua + cv->qb * ua + cv->qc));
    double rb = sqrt(fmax(0, cv->qa * ub * ub + cv->qb * ub + cv->qc));
    double za = cv->p0[2] + ua * cv->dir[2], zb = cv->p0[2] + ub * cv->dir[2];
    double dr = rb - ra, dz = zb - za, len = sqrt(dr * dr + dz * dz);
    double worst = 0;
    for (int k = 1; k < 8; k++) {
        double u = ua + (ub - ua) * k / 8.0;
        double r = sqrt(fmax(0, cv->qa * u * u + cv->qb * u + cv->qc));
        double z = cv->p0[2] + u * cv->dir[2];
        double d = len > 0 ? fabs((r - ra) * dz - (z - za) * dr) / len : sqrt((r - ra) * (r - ra) + (z - za) * (z - za));
        if (d > worst)
            worst = d;
    }
    return worst;
}

/* Do the two crossings pts and q of chords with a cell's sides coincide (in either order)? */
static int same_pair(double pts[][2], double q[2][2], double eps)
{
    return (fabs(pts[0][0] - q[0][0]) <= eps && fabs(pts[0][1] - q[0][1]) <= eps &&
            fabs(pts[1][0] - q[1][0]) <= eps && fabs(pts[1][1] - q[1][1]) <= eps) ||
           (fabs(pts[0][0] - q[1][0]) <= eps && fabs(pts[0][1] - q[1][1]) <= eps &&
            fabs(pts[1][0] - q[0][0]) <= eps && fabs(pts[1][1] - q[0][1]) <= eps);
}

static double curve_r(const sw_curve *cv, double u)
{
    return sqrt(fmax(0, cv->qa * u * u + cv->qb * u + cv->qc));
}

/* The parameter in [lo, hi] (widened by rounding) at which curve cv has radius r, or NAN. */
static double curve_u_at_r(const sw_curve *cv, double r, double lo, double hi)
{
    double roots[2], best = NAN, slack = 1e-9;
    int nr = solve_quadratic(cv->qa, cv->qb, cv->qc - r * r, 1, roots);
    for (int k = 0; k < nr; k++)
        if (roots[k] >= lo - slack && roots[k] <= hi + slack)
            best = roots[k];
    return best;
}

/*
 * Where two chords cross inside a cell (two edge images, not at a vertex image), the
 * cell is cut into the four wedges round their crossing, like a star round a vertex image,
 * instead of being refined down to blocks at every crossing (the output grew with the
 * number of crossings times the depth of the tree).  Accepted when the two curves meet
 * once strictly inside the cell, each half of each curve stays within tol/4 of its chord
 * from the crossing, and the corners in the same wedge agree.  The crossing is computed
 * on the curves themselves, so that the lifts there land on both edges.
 */
static int crossing_cell(sw_ctx *c, sw_leaf *L, const sw_struct *const *all, double ra,
                         double rb, double za, double zb, const double *ua, int64_t cb,
                         const double *ub)
{
    const sw_curve *A = &c->curves[L->split_curve], *B = &c->curves[cb];
    double alo = fmin(ua[0], ua[1]), ahi = fmax(ua[0], ua[1]);
    double blo = fmin(ub[0], ub[1]), bhi = fmax(ub[0], ub[1]);
    if (A->dir[2] == 0 && B->dir[2] == 0)
        return 0;
    if (A->dir[2] == 0) {
        const sw_curve *t = A;
        A = B;
        B = t;
        double t0 = alo, t1 = ahi;
        alo = blo;
        ahi = bhi;
        blo = t0;
        bhi = t1;
    }
    /* A is not horizontal: z = A.p0z + u A.dz, u in [alo, ahi] */
    double u = NAN, v = NAN;
    if (B->dir[2] == 0) {
        double z = B->p0[2];
        u = (z - A->p0[2]) / A->dir[2];
        if (!(u > alo && u < ahi))
            return 0;
        v = curve_u_at_r(B, curve_r(A, u), blo, bhi);
    } else {
        /* r_A(z)^2 = r_B(z)^2, with u = (z - a0) / ad, v = (z - b0) / bd: a quadratic in z */
        double a0 = A->p0[2], ad = A->dir[2], b0 = B->p0[2], bd = B->dir[2];
        double ka = A->qa / (ad * ad), kb = B->qa / (bd * bd);
        double qa = ka - kb;
        double qb = A->qb / ad - 2 * ka * a0 - (B->qb / bd - 2 * kb * b0);
        double qc = ka * a0 * a0 - A->qb * a0 / ad + A->qc - (kb * b0 * b0 - B->qb * b0 / bd + B->qc);
        double zs[2];
        int nz = solve_quadratic(qa, qb, qc, 0, zs);
        int found = 0;
        for (int k = 0; k < nz; k++) {
            double uu = (zs[k] - a0) / ad, vv = (zs[k] - b0) / bd;
            if (uu > alo && uu < ahi && vv > blo && vv < bhi) {
                found++;
                u = uu;
                v = vv;
            }
        }
        if (found != 1)
            return 0;
    }
    if (!(v > blo && v < bhi) || !(u > alo && u < ahi))
        return 0;
    double cr = curve_r(A, u), cz = A->p0[2] + u * A->dir[2];
    /* not within rounding of a side: a crossing on the axis (a plane and its half turn
     * meet there) computed at r = 1e-9 left a ring of that radius open */
    double eps = 1e-9 * (rb + fabs(zb)) + 1e-6 * c->tol;
    if (!(cr - ra > eps && rb - cr > eps && cz - za > eps && zb - cz > eps))
        return 0;
    double lim = 0.25 * c->tol;
    if (curve_sag(A, alo, u) > lim || curve_sag(A, u, ahi) > lim || curve_sag(B, blo, v) > lim ||
        curve_sag(B, v, bhi) > lim)
        return 0;
    /* corners in one wedge (same side of both chords) agree */
    double pa[2][2], pb[2][2];
    for (int e = 0; e < 2; e++) {
        double ue = e ? ahi : alo, ve = e ? bhi : blo;
        pa[e][0] = curve_r(A, ue);
        pa[e][1] = A->p0[2] + ue * A->dir[2];
        pb[e][0] = curve_r(B, ve);
        pb[e][1] = B->p0[2] + ve * B->dir[2];
    }
    double crs[4][2] = {{ra, za}, {rb, za}, {rb, zb}, {ra, zb}};
    int side[4][2];
    for (int k = 0; k < 4; k++) {
        double oa = (pa[1][0] - pa[0][0]) * (crs[k][1] - pa[0][1]) - (pa[1][1] - pa[0][1]) * (crs[k][0] - pa[0][0]);
        double ob = (pb[1][0] - pb[0][0]) * (crs[k][1] - pb[0][1]) - (pb[1][1] - pb[0][1]) * (crs[k][0] - pb[0][0]);
        if (oa == 0 || ob == 0)
            return 0;
        side[k][0] = oa > 0;
        side[k][1] = ob > 0;
    }
    for (int k = 0; k < 4; k++)
        for (int j = k + 1; j < 4; j++)
            if (side[k][0] == side[j][0] && side[k][1] == side[j][1] &&
                !same_struct(c, all[k], all[j]))
                return 0;
    L->kind = LEAF_STAR;
    L->cr = cr;
    L->cz = cz;
    L->cvtx = -1;
    return 1;
}

/* A curve through a cell and its crossings with the cell's sides. */
#define SW_MAXJUNCTION 16
typedef struct sw_jcurve {
    int64_t curve;
    int ncr;
    double pts[8][2];
} sw_jcurve;

/* The point of curve cv at (r, z) within eps, or NAN: its parameter there. */
static double curve_u_at(const sw_curve *cv, double r, double z, double eps)
{
    double u;
    if (cv->dir[2] != 0) {
        u = (z - cv->p0[2]) / cv->dir[2];
    } else {
        if (fabs(cv->p0[2] - z) > eps)
            return NAN;
        u = curve_u_at_r(cv, r, 0, 1);
    }
    if (!(u >= -1e-9 && u <= 1 + 1e-9) || fabs(curve_r(cv, u) - r) > eps)
        return NAN;
    return u;
}

/*
 * Where gap-closing curves meet (the exit or entry face changes across an edge, or the
 * gap stops at a silhouette), the arc structure changes round a point that is not the
 * image of a mesh vertex: the end of a gap-closing curve on another curve.  The cell is
 * cut into a star round it, as round a vertex image, when every curve through the cell
 * ends there or passes through it, each piece from the junction to a side stays within
 * tol/4 of its chord, and the corners and the centre in one wedge agree.
 */
static int junction_cell(sw_ctx *c, sw_leaf *L, const sw_struct *const *all, double ra,
                         double rb, double za, double zb, const sw_jcurve *jc, int njc)
{
    double eps = 1e-9 * (rb + fabs(zb)) + 1e-6 * c->tol;
    double J[2] = {NAN, NAN};
    /* the junction: an end of a gap-closing curve strictly inside the cell */
    for (int i = 0; i < njc && !(J[0] == J[0]); i++) {
        const sw_curve *cv = &c->curves[jc[i].curve];
        if (cv->gexit < 0)
            continue;
        for (int e = 0; e < 2; e++) {
            double r = curve_r(cv, e), z = cv->p0[2] + e * cv->dir[2];
            if (r > ra && r < rb && z > za && z < zb) {
                J[0] = r;
                J[1] = z;
                break;
            }
        }
    }
    /* ... or an end of a silhouette or of a face's image that is no vertex's image: where
     * the image of an edge folds back at its point nearest the axis (a horizontal edge
     * of a part about a parallel axis: the silhouette of the side face through it ends
     * there, and the image of the cap starts there) */
    for (int i = 0; i < njc && !(J[0] == J[0]); i++) {
        const sw_curve *cv = &c->curves[jc[i].curve];
        if (cv->tri[1] >= 0 || cv->gexit >= 0)
            continue;
        for (int e = 0; e < 2; e++) {
            double r = curve_r(cv, e), z = cv->p0[2] + e * cv->dir[2];
            if (cv->vtx[e] < 0 && r > ra && r < rb && z > za && z < zb) {
                J[0] = r;
                J[1] = z;
                break;
            }
        }
    }
    if (!(J[0] == J[0]))
        return 0;
    if (!(J[0] - ra > eps && rb - J[0] > eps && J[1] - za > eps && zb - J[1] > eps))
        return 0;
    double ang[2 * SW_MAXJUNCTION];
    int nray = 0;
    for (int i = 0; i < njc; i++) {
        const sw_curve *cv = &c->curves[jc[i].curve];
        double u = curve_u_at(cv, J[0], J[1], eps);
        if (!(u == u))
            return 0;
        int at_end = u <= 1e-9 || u >= 1 - 1e-9;
        /* ends at J: one crossing; passes through J: two; a horizontal curve at J's
         * height lies on the line through it, folded or not: one or two */
        int along = cv->dir[2] == 0 && fabs(cv->p0[2] - J[1]) <= eps;
        if (along ? jc[i].ncr < 1 : jc[i].ncr != (at_end ? 1 : 2))
            return 0;
        for (int k = 0; k < jc[i].ncr; k++) {
            double pr = jc[i].pts[k][0], pz = jc[i].pts[k][1];
            double uk = curve_u_at(cv, pr, pz, eps);
            if (!(uk == uk) || curve_sag(cv, fmin(u, uk), fmax(u, uk)) > 0.25 * c->tol)
                return 0;
            ang[nray++] = atan2(pz - J[1], pr - J[0]);
        }
    }
    if (nray < 2)
        return 0;
    qsort(ang, (size_t)nray, sizeof *ang, cmp_double_asc);
    /* the wedge of each sample: the number of rays below its direction */
    double crs[5][2] = {{ra, za}, {rb, za}, {rb, zb}, {ra, zb}, {0.5 * (ra + rb), 0.5 * (za + zb)}};
    int wedge[5];
    for (int k = 0; k < 5; k++) {
        double dr = crs[k][0] - J[0], dz = crs[k][1] - J[1];
        if (fabs(dr) <= eps && fabs(dz) <= eps) {
            wedge[k] = -1;
            continue;
        }
        double a = atan2(dz, dr);
        int w = 0;
        for (int q = 0; q < nray; q++) {
            if (a == ang[q])
                return 0;
            w += ang[q] < a;
        }
        wedge[k] = w % nray;
    }
    for (int k = 0; k < 5; k++)
        for (int j = k + 1; j < 5; j++)
            if (wedge[k] >= 0 && wedge[k] == wedge[j] && !same_struct(c, all[k], all[j]))
                return 0;
    L->kind = LEAF_STAR;
    L->cr = J[0];
    L->cz = J[1];
    L->cvtx = -1;
    return 1;
}

/*
 * Several curves cross the cell, each from side to side, without crossing one another in
 * it: two curves diverging from a junction or a vertex image just outside, a gap-closing
 * curve beside the edge it ends on.  The cell is cut along all their chords (instead of
 * being refined down to blocks all along the narrow angle between them) when each curve
 * stays within tol/4 of its chord, no two chords meet, and the samples with the same
 * sides of every chord agree.  Coincident chords (one image) count once.
 */
static int chords_cell(sw_ctx *c, sw_leaf *L, const sw_struct *const *all, double ra,
                       double rb, double za, double zb, const sw_jcurve *jc, int njc,
                       double peps)
{
    double ch[SW_MAXJUNCTION][2][2];
    int nch = 0;
    for (int i = 0; i < njc; i++) {
        if (jc[i].ncr != 2)
            return 0;
        double q[2][2];
        memcpy(q, jc[i].pts, sizeof q);
        int dup = 0;
        for (int j = 0; j < nch && !dup; j++)
            dup = same_pair(ch[j], q, peps);
        if (dup)
            continue;
        const sw_curve *cv = &c->curves[jc[i].curve];
        double eps = 1e-9 * (rb + fabs(zb)) + 1e-6 * c->tol;
        double u0 = curve_u_at(cv, q[0][0], q[0][1], eps), u1 = curve_u_at(cv, q[1][0], q[1][1], eps);
        if (!(u0 == u0) || !(u1 == u1) || curve_sag(cv, fmin(u0, u1), fmax(u0, u1)) > 0.25 * c->tol)
            return 0;
        memcpy(ch[nch], q, sizeof q);
        nch++;
    }
    if (nch < 2)
        return 0;
    /* chords of a convex cell with ends on its sides cross iff the ends of one lie on both
     * sides of the other; ends in common are refused too */
    for (int i = 0; i < nch; i++)
        for (int j = 0; j < nch; j++) {
            if (i == j)
                continue;
            double o[2];
            for (int e = 0; e < 2; e++)
                o[e] = (ch[i][1][0] - ch[i][0][0]) * (ch[j][e][1] - ch[i][0][1]) -
                       (ch[i][1][1] - ch[i][0][1]) * (ch[j][e][0] - ch[i][0][0]);
            if (o[0] == 0 || o[1] == 0 || (o[0] > 0) != (o[1] > 0))
                return 0;
            for (int e = 0; e < 2; e++)
                for (int f = 0; f < 2; f++)
                    if (fabs(ch[i][e][0] - ch[j][f][0]) <= peps && fabs(ch[i][e][1] - ch[j][f][1]) <= peps)
                        return 0;
        }
    double crs[5][2] = {{ra, za}, {rb, za}, {rb, zb}, {ra, zb}, {0.5 * (ra + rb), 0.5 * (za + zb)}};
    unsigned sig[5];
    for (int k = 0; k < 5; k++) {
        sig[k] = 0;
        for (int i = 0; i < nch; i++) {
            double o = (ch[i][1][0] - ch[i][0][0]) * (crs[k][1] - ch[i][0][1]) -
                       (ch[i][1][1] - ch[i][0][1]) * (crs[k][0] - ch[i][0][0]);
            if (o == 0)
                return 0;
            sig[k] |= (unsigned)(o > 0) << i;
        }
    }
    for (int k = 0; k < 5; k++)
        for (int j = k + 1; j < 5; j++)
            if (sig[k] == sig[j] && !same_struct(c, all[k], all[j]))
                return 0;
    L->kind = LEAF_CHORDS;
    L->nchords = nch;
    return 1;
}

typedef struct sw_iv {
    double a, b; /* unwrapped: a in [0, 2 pi), b > a */
} sw_iv;

static int cmp_iv(const void *pa, const void *pb)
{
    const sw_iv *x = pa, *y = pb;
    return (x->a > y->a) - (x->a < y->a);
}

/*
 * Hidden triangles.  Every triangle near a cell used to cut it with its curves, also where
 * it is crossed strictly inside an SV arc on every circle of the cell: on a tessellated
 * torus swept by a half or a full turn the images of all its edges crossed one another.
 * A cell now ignores the triangles it can show to be hidden, by this argument.  (At 90 deg
 * the bench torus has almost nothing hidden: 660 of 702 crossings of 233 random circles
 * start or end an SV arc.)
 *
 * Let Phi_t be an interval of angles holding every point of triangle t whose (r, z) lies in
 * the cell (tri_cell_angles: t clipped to the slab and the annulus of the cell, with a
 * margin).  The union of the Phi_t of all triangles near the cell is a set of closed
 * angular blocks; between them lie gaps.  The part of the cell's solid of revolution over a
 * gap meets no triangle and is connected, so it lies wholly inside O or wholly outside it,
 * on every circle of the cell alike: one ray test tells which.  SV on a circle is the set
 * of angles phi with [phi - theta, phi] meeting O, and O is the inside gaps plus its parts
 * in the blocks, so on every circle of the cell
 *     SV = C u  U_blocks B  cov(O n B),   C = U_inside gaps (a, b)  (a, b + theta),
 * with cov(O n B) inside [B.lo, B.hi + theta] whatever the triangles of B do.  A block
 * whose [B.lo, B.hi + theta] lies in one (open) component of C is hidden: what happens in
 * it (arcs born at silhouettes, crossings passing edges) changes no point of SV, and no
 * end of an SV arc lies in C.  So SV, its arcs and the triangles that start and end them
 * are functions of the crossings in the other blocks alone, whose triangles all keep their
 * curves: the structure changes only where one of their crossings changes triangle or root
 * (their edges and silhouettes), is born or dies (silhouettes, vertex images), or meets
 * the turned end of another (a gap-closing curve between two triangles of visible blocks;
 * a crossing meeting C's bounds meets the first crossing of the block there, the same
 * kind of event, or lies in C on both sides when that block is hidden).  Two triangles
 * sharing an edge have overlapping Phi, so a crossing never passes from a visible block
 * into a hidden one.  Hidden blocks are decided per cell, for every circle of the cell,
 * not from the samples alone: the argument holds when the samples differ too.  A full turn
 * with one inside gap hides everything (C is the whole circle).
 *
 * A block is the unit, not a triangle: a triangle whose crossings all lie in C, so that it
 * never starts or ends an arc, can still change SV - an arc of O born at its silhouette
 * covers [phi, phi + theta], which can reach past C and swallow the end of another arc
 * (the bench torus has such notches: they are kept).  A triangle of a hidden
 * block loses its edges, silhouette and gap-closing curves in the cell, and its vertices
 * are no vertex images there (the neighbours of the visible ones keep their common edges).
 */

/* Angles at which circles of the cell [ra, rb] x [za, zb] can meet triangle t: 0 when no
 * point of t lies over the cell, 1 with the closed interval [*lo, *hi] (lo in [0, 2 pi),
 * hi - lo < pi), 2 when t comes near the axis (no bound). */
static int tri_cell_angles(const sw_ctx *c, int64_t t, double ra, double rb, double za,
                           double zb, double *lo, double *hi)
{
    const sw_tri *T = &c->tris[t];
    double m = 1e-9 * c->ext; /* the cell widened by far more than rounding */
    ra = fmax(0, ra - m);
    rb += m;
    za -= m;
    zb += m;
    if (T->rmax < ra || T->rmin > rb || T->zmax < za || T->zmin > zb)
        return 0;
    /* t clipped to the slab za <= z <= zb: a convex polygon of up to 5 corners */
    double P[8][3], Q[8][3];
    int n = 3;
    for (int k = 0; k < 3; k++)
        memcpy(P[k], c->lx + 3 * T->v[k], sizeof P[k]);
    for (int sd = 0; sd < 2 && n > 0; sd++) {
        int nq = 0;
        for (int i = 0; i < n; i++) {
            const double *a = P[i], *b = P[(i + 1) % n];
            double fa = sd ? zb - a[2] : a[2] - za, fb = sd ? zb - b[2] : b[2] - za;
            if (fa >= 0)
                memcpy(Q[nq++], a, sizeof Q[0]);
            if ((fa < 0 && fb > 0) || (fa > 0 && fb < 0)) {
                double w = fa / (fa - fb);
                for (int q = 0; q < 3; q++)
                    Q[nq][q] = a[q] + w * (b[q] - a[q]);
                nq++;
            }
        }
        n = nq;
        memcpy(P, Q, (size_t)n * sizeof P[0]);
    }
    if (n == 0)
        return 0;
    /* its shadow on the plane z = 0: no bound when it covers the axis or comes within
     * 1e-7 of the part's size of it (angles lose their digits there) */
    double dist = INFINITY;
    int pos = 0, neg = 0;
    for (int i = 0; i < n; i++) {
        const double *u = P[i], *v = P[(i + 1) % n];
        double cr = u[0] * v[1] - u[1] * v[0];
        pos |= cr > 0;
        neg |= cr < 0;
        double dx = v[0] - u[0], dy = v[1] - u[1], l2 = dx * dx + dy * dy;
        double s = l2 > 0 ? fmin(1, fmax(0, -(u[0] * dx + u[1] * dy) / l2)) : 0;
        dist = fmin(dist, v_r(u[0] + s * dx, u[1] + s * dy));
    }
    if ((pos && !neg) || (neg && !pos) || !(dist > 1e-7 * c->ext))
        return 2;
    /* a convex set away from the axis spans less than half a turn: its angles over the
     * annulus are those of its corners in the annulus and of its sides' crossings with the
     * annulus' two circles */
    int any = 0;
    double a0 = 0, dlo = 0, dhi = 0;
    for (int i = 0; i < n; i++) {
        const double *u = P[i], *v = P[(i + 1) % n];
        double pts[5][2];
        int np = 0;
        double ru = v_r(u[0], u[1]);
        if (ru >= ra && ru <= rb) {
            pts[np][0] = u[0];
            pts[np++][1] = u[1];
        }
        double dx = v[0] - u[0], dy = v[1] - u[1];
        double qa = dx * dx + dy * dy, qb = 2 * (u[0] * dx + u[1] * dy);
        for (int e = 0; e < 2 && qa > 0; e++) {
            double R = e ? rb : ra, roots[2];
            if (R <= 0)
                continue;
            int nr = solve_quadratic(qa, qb, u[0] * u[0] + u[1] * u[1] - R * R, 0, roots);
            for (int k = 0; k < nr; k++)
                if (roots[k] >= 0 && roots[k] <= 1) {
                    pts[np][0] = u[0] + roots[k] * dx;
                    pts[np++][1] = u[1] + roots[k] * dy;
                }
        }
        for (int k = 0; k < np; k++) {
            double ang = atan2(pts[k][1], pts[k][0]);
            if (!any) {
                a0 = ang;
                any = 1;
                continue;
            }
            double d = angle_diff(ang, a0);
            dlo = fmin(dlo, d);
            dhi = fmax(dhi, d);
        }
    }
    if (!any)
        return 0;
    double marg = 1e-9 + 1e-13 * c->ext / dist;
    *lo = wrap_angle(a0 + dlo - marg);
    *hi = *lo + (dhi - dlo) + 2 * marg;
    return 1;
}

/* Merges the intervals iv[0 .. n-1] (a in [0, 2 pi)) on the circle into out: returns how
 * many disjoint ones are left (starting from one that no other reaches; their a and b
 * unwrapped from there), or -1 when they cover the whole circle.  Closed intervals that
 * touch merge; open ones do not. */
static int64_t merge_on_circle(sw_iv *iv, int64_t n, int open, sw_iv *out)
{
    if (n == 0)
        return 0;
    for (int64_t i = 0; i < n; i++)
        if (iv[i].b - iv[i].a >= MFG_TWO_PI)
            return -1;
    qsort(iv, (size_t)n, sizeof *iv, cmp_iv);
    double best = -INFINITY;
    for (int64_t i = 0; i < n; i++)
        best = fmax(best, iv[i].b - MFG_TWO_PI);
    int64_t j0 = -1;
    for (int64_t i = 0; i < n; i++) {
        if (open ? iv[i].a >= best : iv[i].a > best) {
            j0 = i;
            break;
        }
        best = fmax(best, iv[i].b);
    }
    if (j0 < 0)
        return -1;
    int64_t m = 0;
    double ca = iv[j0].a, cb = iv[j0].b;
    for (int64_t k = 1; k <= n; k++) {
        int64_t i = (j0 + k) % n;
        double w = (j0 + k) >= n ? MFG_TWO_PI : 0, a = iv[i].a + w, b = iv[i].b + w;
        if (k < n && (open ? a < cb : a <= cb)) {
            cb = fmax(cb, b);
            continue;
        }
        out[m].a = ca;
        out[m].b = cb;
        m++;
        ca = a;
        cb = b;
    }
    return m;
}

/* The component of the merged intervals iv[0 .. n-1] holding the closed interval [x, y]
 * (x in [0, 2 pi), y >= x), open at both ends (strictly inside) or closed, or -1. */
static int64_t circle_component(const sw_iv *iv, int64_t n, double x, double y, int open)
{
    for (int64_t i = 0; i < n; i++) {
        double xs = iv[i].a + fmod(x - iv[i].a + 2 * MFG_TWO_PI, MFG_TWO_PI);
        double ys = xs + (y - x);
        if (open ? (xs > iv[i].a && ys < iv[i].b) : (xs >= iv[i].a && ys <= iv[i].b))
            return i;
    }
    return -1;
}

/* Marks (c->hstamp[t] = vs) the triangles of the candidate list c->cand that are hidden in
 * the cell [ra, rb] x [za, zb] (see above); centre is SV at the cell's centre, a shortcut for
 * the gaps outside O.  c->cand is left as it was. */
static int mark_hidden(sw_ctx *c, const sw_struct *centre, double ra, double rb, double za,
                       double zb, int64_t vs)
{
    int64_t n = c->ncand;
    if (n == 0)
        return 1;
    int64_t *cand = malloc((size_t)n * sizeof *cand);
    sw_iv *phi = malloc((size_t)n * sizeof *phi), *blk = malloc((size_t)n * sizeof *blk);
    sw_iv *cv = malloc((size_t)(n + 1) * sizeof *cv), *cm = malloc((size_t)(n + 1) * sizeof *cm);
    signed char *kind = malloc((size_t)n);
    int ok = 1;
    if (!cand || !phi || !blk || !cv || !cm || !kind) {
        ok = ctx_nomem(c);
        goto done;
    }
    memcpy(cand, c->cand, (size_t)n * sizeof *cand);
    int64_t nphi = 0;
    for (int64_t k = 0; k < n; k++) {
        phi[k].a = phi[k].b = 0;
        kind[k] = (signed char)tri_cell_angles(c, cand[k], ra, rb, za, zb, &phi[k].a, &phi[k].b);
        if (kind[k] == 2)
            goto done; /* no gap: nothing is hidden */
        if (kind[k] == 1) {
            /* widened by 5e-10 for the blocks: gaps narrower than 1e-9 close, and each
             * Phi_t lies well inside its own block, in no other */
            double w = wrap_angle(phi[k].a - 5e-10);
            cv[nphi].a = w;
            cv[nphi++].b = w + (phi[k].b - phi[k].a) + 1e-9;
        }
    }
    int64_t nb = merge_on_circle(cv, nphi, 0, blk);
    if (nb < 0)
        goto done;
    /* C from the gaps inside O */
    int64_t nc = 0;
    int cfull = 0;
    double rc = 0.5 * (ra + rb), zc = 0.5 * (za + zb);
    /* the centre sample may have been moved (circle_arcs) by up to 2^-24 of the part */
    int shortcut = !centre->full && 0.5 * (rb - ra) > 0x1p-22 * c->ext;
    for (int64_t a = 0; a < centre->n; a++)
        if (c->arcs[centre->first + a].start.tri < 0)
            shortcut = 0; /* a conservative arc, not SV's */
    for (int64_t i = 0; i < nb && !cfull; i++) {
        double ga = blk[i].b, gb = i + 1 < nb ? blk[i + 1].a : blk[0].a + MFG_TWO_PI;
        if (!(gb > ga))
            continue;
        double psi = wrap_angle(0.5 * (ga + gb));
        if (shortcut) {
            /* O lies in SV: an angle SV misses at the centre is outside O */
            int in_sv = 0;
            for (int64_t a = 0; a < centre->n && !in_sv; a++) {
                const sw_arc *arc = &c->arcs[centre->first + a];
                double s0 = arc->start.phi, len = arc->end.phi + c->theta - s0;
                in_sv = fmod(psi - s0 + 2 * MFG_TWO_PI, MFG_TWO_PI) <= len;
            }
            if (!in_sv)
                continue;
        }
        int in = point_inside(c, rc, zc, psi);
        if (in < 0) {
            ok = 0;
            goto done;
        }
        if (!in)
            continue;
        if (gb + c->theta - ga >= MFG_TWO_PI || c->full_turn) {
            cfull = 1;
            break;
        }
        cv[nc].a = wrap_angle(ga);
        cv[nc].b = cv[nc].a + (gb + c->theta - ga);
        nc++;
    }
    int64_t ncm = 0;
    if (!cfull) {
        ncm = merge_on_circle(cv, nc, 1, cm);
        cfull = ncm < 0;
    }
    if (!cfull && ncm == 0)
        goto done;
    /* the hidden blocks, then their triangles */
    for (int64_t i = 0; i < nb; i++) {
        double x = wrap_angle(blk[i].a), len = blk[i].b - blk[i].a + c->theta;
        blk[i].a = x;
        blk[i].b = cfull || circle_component(cm, ncm, x, x + len, 1) >= 0 ? x + (len - c->theta) : -1;
    }
    for (int64_t k = 0; k < n; k++) {
        int64_t t = cand[k];
        if (kind[k] == 0) {
            c->hstamp[t] = vs; /* nothing of it over the cell */
            continue;
        }
        for (int64_t i = 0; i < nb && kind[k] == 1; i++)
            if (blk[i].b >= 0 && circle_component(blk + i, 1, phi[k].a, phi[k].b, 0) == 0) {
                c->hstamp[t] = vs;
                break;
            }
    }
done:
    if (cand) {
        memcpy(c->cand, cand, (size_t)n * sizeof *cand);
        c->ncand = n;
    }
    free(cand);
    free(phi);
    free(blk);
    free(cv);
    free(cm);
    free(kind);
    return ok;
}

typedef struct sw_samples {
    hmap cache;            /* (ix, iz) -> index in pool */
    sw_struct *pool;
    int64_t n, cap;
} sw_samples;

/* Decides what to do with cell (ix, iz, level); fills the leaf fields and appends the
 * curves that pass through the cell to leaf_curves. */
static int analyse_cell(sw_ctx *c, sw_samples *sp, sw_leaf *L)
{
    if (L->level < c->lmax && c->refine.keys) {
        /* a cell whose cut failed when the polygons were built last time */
        hkey rk = mkkey(L->level, L->ix, L->iz, 0);
        if (hmap_get(&c->refine, &rk) >= 0) {
            L->cfirst = c->nleaf_curves;
            L->cn = 0;
            L->split_curve = -1;
            L->cvtx = -1;
            L->empty = 0;
            L->kind = LEAF_REFINE;
            return 1;
        }
    }
    int64_t s = (int64_t)1 << (c->lmax - L->level);
    double ra = grid_r(c, L->ix), rb = grid_r(c, L->ix + s);
    double za = grid_z(c, L->iz), zb = grid_z(c, L->iz + s);
    int64_t ci[4];
    int64_t cx[4] = {L->ix, L->ix + s, L->ix + s, L->ix}, cz[4] = {L->iz, L->iz, L->iz + s, L->iz + s};
    for (int k = 0; k < 4; k++)
        if (!corner_sample(c, &sp->cache, cx[k], cz[k], &sp->pool, &sp->n, &sp->cap, &ci[k]))
            return 0;
    sw_struct centre;
    if (!circle_arcs(c, 0.5 * (ra + rb), 0.5 * (za + zb), &centre))
        return 0;
    L->cfirst = c->nleaf_curves;
    L->cn = 0;
    L->split_curve = -1;
    L->cvtx = -1;
    L->empty = 0;
    /* the triangles that bound SV at the samples */
    c->stampv++;
    int64_t vs = c->stampv;
    const sw_struct *all[5] = {&sp->pool[ci[0]], &sp->pool[ci[1]], &sp->pool[ci[2]],
                               &sp->pool[ci[3]], &centre};
    int any_arc = 0;
    for (int k = 0; k < 5; k++) {
        if (all[k]->full || all[k]->n)
            any_arc = 1;

        for (int64_t a = 0; a < all[k]->n; a++) {
            const sw_arc *arc = &c->arcs[all[k]->first + a];
            c->vstamp[arc->start.tri] = vs;
            c->vstamp[arc->end.tri] = vs;
        }
    }
    if (!gather(c, ra, rb, za, zb))
        return 0;
    /* the triangles hidden in the cell (the bounding ones never are) */
    if (!c->bounding_only && !mark_hidden(c, &centre, ra, rb, za, zb, vs))
        return 0;
    /* vertex images in the closed cell */
    int64_t nimg = 0;
    double img[2] = {0, 0};
    int64_t imgv = -1;
    int img_inside = 0;
    for (int64_t k = 0; k < c->ncand; k++) {
        const sw_tri *T = &c->tris[c->cand[k]];
        if (c->hstamp[c->cand[k]] == vs)
            continue;
        for (int q = 0; q < 3; q++) {
            int64_t v = T->v[q];
            double r = c->vr[v], z = c->lx[3 * v + 2];
            if (r < ra || r > rb || z < za || z > zb)
                continue;
            if (nimg == 0) {
                img[0] = r;
                img[1] = z;
                imgv = v;
                img_inside = r > ra && r < rb && z > za && z < zb;
                nimg = 1;
            } else if (nimg == 1 && (r != img[0] || z != img[1])) {
                nimg = 2;
            }
        }
    }
    if (c->ncand == 0 && !any_arc) {
        L->empty = 1;
        L->kind = LEAF_CLEAN;
        return 1;
    }
    /* curves of the bounding triangles through the cell */
    int64_t npass = 0, ncross_split = 0, all_from_img = 1, one_cross_each = 1;
    int star_sag_ok = 1;
    /* a vertex image on the axis lies on the cell's side r = 0, never strictly inside:
     * a half star round it (below) when every curve is a spoke from it */
    int img_on_axis = nimg == 1 && img[0] == 0 && ra == 0 && img[1] > za && img[1] < zb;
    /* ... and, with no vertex image, round the point where curves touch the axis (an
     * edge or a face diagonal crossing it): their images fold there */
    int axis_touch = nimg == 0 && ra == 0;
    double touch_z = NAN;
    int all_spokes = 1;
    double aeps = 1e-9 * (rb + fabs(zb)) + 1e-6 * c->tol;
    double split_u[2] = {0, 0}, split_p[2][2] = {{0, 0}, {0, 0}};
    int64_t second_curve = -1, ncross_second = 0;
    double second_u[2] = {0, 0}, second_p[2][2] = {{0, 0}, {0, 0}};
    double peps = 1e-9 * (rb - ra) + 1e-12 * (fabs(rb) + fabs(zb));
    /* the curves through the cell with their side crossings, for a junction of
     * gap-closing curves or several chords (below) */
    sw_jcurve jc[SW_MAXJUNCTION];
    int njc = 0, jn_ok = 1;
    for (int64_t k = 0; k < c->ncand; k++) {
        int64_t t = c->cand[k];
        /* Every triangle near the cell counts, not only those bounding SV at the
         * samples: a face can enter the cell between samples (the inner wall of a
         * ring-shaped sweep entered a large cell whose five samples all missed it).
         * Only the triangles shown hidden on every circle of the cell are left out
         * (mark_hidden).
         * The last two placements fall back to the bounding triangles only, which
         * closes surfaces the full rule leaves open at vertices on the axis (a cube
         * spun about its diagonal), at the price of that blind spot. */
        if ((c->bounding_only && c->vstamp[t] != vs) || c->hstamp[t] == vs)
            continue;
        int64_t nq = 4 + (c->gstart ? c->gstart[t + 1] - c->gstart[t] : 0);
        for (int64_t q = 0; q < nq; q++) {
            int64_t ic = q < 4 ? c->tcurves[4 * t + q] : c->gcurves[c->gstart[t] + q - 4];
            if (ic < 0 || c->cstamp[ic] == vs)
                continue;
            c->cstamp[ic] = vs;
            const sw_curve *cv = &c->curves[ic];
            if (cv->gexit >= 0 && c->hstamp[cv->gexit] == vs)
                continue; /* the exit turned onto this triangle is hidden */
            if (cv->rmax < ra || cv->rmin > rb || cv->zmax < za || cv->zmin > zb)
                continue;
            int ncr = 0, nd = 0;
            double us[8], pts[8][2];
            for (int sd = 0; sd < 4; sd++) {
                int rside;
                double val, lo, hi, pos[2], uu[2];
                side_geom(c, L->ix, L->iz, s, sd, &rside, &val, &lo, &hi);
                int m = curve_side(cv, rside, val, lo, hi, pos, uu);
                for (int j = 0; j < m && ncr < 8; j++) {
                    double pr = rside ? val : pos[j], pz = rside ? pos[j] : val;
                    int dup = 0;
                    for (int q2 = 0; q2 < nd; q2++)
                        dup |= fabs(pts[q2][0] - pr) <= peps && fabs(pts[q2][1] - pz) <= peps;
                    if (!dup) {
                        pts[nd][0] = pr;
                        pts[nd][1] = pz;
                        us[nd++] = uu[j];
                    }
                    ncr++;
                }
            }
            ncr = nd; /* a curve folded on its image (a horizontal edge) meets a side
                         twice at one point */
            int end_in = 0;
            for (int e = 0; e < 2; e++) {
                double u = (double)e;
                double r = sqrt(fmax(0, cv->qa * u * u + cv->qb * u + cv->qc));
                double z = cv->p0[2] + u * cv->dir[2];
                if (r > ra && r < rb && z > za && z < zb)
                    end_in = 1;
            }
            /* a horizontal curve inside the open cell has no crossing with a z side but
             * may cross neither r side either when it ends inside: end_in covers it */
            if (ncr == 0 && !end_in)
                continue;
            if (!mfg_grow((void **)&c->leaf_curves, &c->capleaf_curves, c->nleaf_curves + 1,
                      sizeof *c->leaf_curves))
                return ctx_nomem(c);
            c->leaf_curves[c->nleaf_curves++] = ic;
            L->cn++;
            /* curves with one image (the edges of a face perpendicular to the axis, a
             * silhouette along an edge) cut the cell along one chord: one group */
            int same_chord = npass > 0 && ncross_split == 2 && !end_in && ncr == 2 &&
                             ((fabs(pts[0][0] - split_p[0][0]) <= peps && fabs(pts[0][1] - split_p[0][1]) <= peps &&
                               fabs(pts[1][0] - split_p[1][0]) <= peps && fabs(pts[1][1] - split_p[1][1]) <= peps) ||
                              (fabs(pts[0][0] - split_p[1][0]) <= peps && fabs(pts[0][1] - split_p[1][1]) <= peps &&
                               fabs(pts[1][0] - split_p[0][0]) <= peps && fabs(pts[1][1] - split_p[0][1]) <= peps));
            /* a second chord (for a crossing of two chords, below), with its own group
             * of coincident curves */
            int same_second = !same_chord && npass == 2 && ncross_second == 2 && !end_in &&
                              ncr == 2 && same_pair(pts, second_p, peps);
            if (!same_chord && !same_second)
                npass++;
            if (npass == 2 && !same_chord && !same_second) {
                second_curve = ic;
                ncross_second = end_in ? -1 : ncr;
                if (ncr == 2) {
                    second_u[0] = us[0];
                    second_u[1] = us[1];
                    memcpy(second_p, pts, sizeof second_p);
                }
            }
            if (npass == 1 && !same_chord) {
                L->split_curve = ic;
                ncross_split = end_in ? -1 : ncr;
                if (ncr == 2) {
                    split_u[0] = us[0];
                    split_u[1] = us[1];
                    memcpy(split_p, pts, sizeof split_p);
                }
            }
            /* star: the curve must end at the vertex image and leave the cell once */
            int from_img = 0;
            for (int e = 0; e < 2; e++) {
                double u = (double)e;
                double r = sqrt(fmax(0, cv->qa * u * u + cv->qb * u + cv->qc));
                double z = cv->p0[2] + u * cv->dir[2];
                /* an end at a mesh vertex: the vertex's own image (r(1) from the
                 * quadratic differs from it by rounding, and the star was refused) */
                if (cv->vtx[e] >= 0) {
                    r = c->vr[cv->vtx[e]];
                    z = c->lx[3 * cv->vtx[e] + 2];
                }
                if (nimg == 1 && r == img[0] && z == img[1]) {
                    from_img = 1;
                    /* the spoke is the chord from the image to the crossing: within
                     * tol/4 of the curve, as a split's chord (an edge whose image leaves
                     * the image of its end nearest the axis tangentially bends away from
                     * its chord by more than the tolerance over a coarse cell: the
                     * result missed SV there by 3 tol, box about a face diagonal) */
                    if (ncr == 1 && curve_sag(cv, fmin(u, us[0]), fmax(u, us[0])) > 0.25 * c->tol)
                        star_sag_ok = 0;
                }
            }
            /* a horizontal curve at the image's height passing through it (an edge or
             * the image of a face perpendicular to the axis, running through the image
             * of a vertex of that face: the 9-face arm's top corners) is two spokes of
             * the star, one to each r side: its image is exactly the line z = const */
            int through_img = nimg == 1 && cv->dir[2] == 0 && cv->p0[2] == img[1];
            /* ... also when it ends at the image or folds back over it (a diagonal of a
             * face perpendicular to the axis, whose image runs in to its nearest point
             * and back out to the vertex): every point of it in the cell is on that
             * line, so every crossing is a spoke, if no end other than the image lies
             * inside the cell */
            for (int e = 0; e < 2 && through_img; e++) {
                double r = cv->vtx[e] >= 0 ? c->vr[cv->vtx[e]] : curve_r(cv, (double)e);
                if (r > ra && r < rb && !(cv->vtx[e] >= 0 ? r == img[0] : fabs(r - img[0]) <= aeps))
                    through_img = 0;
            }
            if (!from_img && !through_img)
                all_from_img = 0;
            if (ncr != 1 && !through_img)
                one_cross_each = 0;
            if (img_on_axis) {
                /* a spoke of the half star: from the image (or, a horizontal curve
                 * folded on itself, through it) out of the cell once; its crossing
                 * with the axis side, if any is found, is the image itself.  The image
                 * of a segment from a point of the axis is straight ((r, z) linear in
                 * the parameter), so the spoke is exactly its chord. */
                int nat = 0, nother = 0;
                for (int j = 0; j < ncr; j++) {
                    if (pts[j][0] == ra && fabs(pts[j][1] - img[1]) <= aeps)
                        nat++;
                    else
                        nother++;
                }
                /* through the image: a crossing of the axis side there (a gap-closing
                 * curve's computed end, a horizontal curve folded on itself) */
                if (end_in || nother != 1 || nat > 1 || !(from_img || nat == 1))
                    all_spokes = 0;
            }
            if (axis_touch) {
                /* through the touching point, its one crossing with the axis side: each
                 * half of the curve a spoke from it (straight, as above), out of the cell
                 * once */
                int nat = 0, nother = 0;
                for (int j = 0; j < ncr; j++) {
                    if (pts[j][0] != ra) {
                        nother++;
                        continue;
                    }
                    if (!(touch_z == touch_z))
                        touch_z = pts[j][1];
                    if (fabs(pts[j][1] - touch_z) <= aeps)
                        nat++;
                    else
                        all_spokes = 0;
                }
                if (end_in || nat != 1 || nother < 1 || nother > 2)
                    all_spokes = 0;
            }
            if (njc < SW_MAXJUNCTION && ncr <= 2) {
                jc[njc].curve = ic;
                jc[njc].ncr = ncr;
                memcpy(jc[njc].pts, pts, sizeof jc[njc].pts);
                njc++;
            } else {
                jn_ok = 0;
            }
        }
    }
    int same5 = same_struct(c, all[0], all[1]) && same_struct(c, all[0], all[2]) &&
                same_struct(c, all[0], all[3]) && same_struct(c, all[0], all[4]);
    if (npass == 0 && nimg == 0 && same5) {
        L->kind = LEAF_CLEAN;
        return 1;
    }
    if (npass == 1 && nimg == 0 && ncross_split == 2) {
        const sw_curve *cv = &c->curves[L->split_curve];
        if (curve_sag(cv, split_u[0], split_u[1]) <= 0.25 * c->tol) {
            /* corners on each side of the chord must agree, and the centre with its side */
            double p[2][2];
            for (int e = 0; e < 2; e++) {
                double u = split_u[e];
                p[e][0] = sqrt(fmax(0, cv->qa * u * u + cv->qb * u + cv->qc));
                p[e][1] = cv->p0[2] + u * cv->dir[2];
            }
            double crs[5][2] = {{ra, za}, {rb, za}, {rb, zb}, {ra, zb},
                                {0.5 * (ra + rb), 0.5 * (za + zb)}};
            int side_of[5];
            for (int k = 0; k < 5; k++) {
                double o = (p[1][0] - p[0][0]) * (crs[k][1] - p[0][1]) -
                           (p[1][1] - p[0][1]) * (crs[k][0] - p[0][0]);
                side_of[k] = o > 0 ? 1 : (o < 0 ? -1 : 0);
            }
            int ok = 1;
            for (int k = 0; k < 5 && ok; k++)
                for (int j = k + 1; j < 5 && ok; j++)
                    if (side_of[k] == 0 || side_of[j] == 0 ||
                        (side_of[k] == side_of[j] && !same_struct(c, all[k], all[j])))
                        ok = 0;
            if (ok) {
                L->kind = LEAF_SPLIT;
                return 1;
            }
        }
    }
    if (nimg == 1 && img_inside && npass >= 1 && all_from_img && one_cross_each && star_sag_ok) {
        L->kind = LEAF_STAR;
        L->cr = img[0];
        L->cz = img[1];
        L->cvtx = imgv;
        return 1;
    }
    if ((img_on_axis || (axis_touch && touch_z == touch_z)) && npass >= 1 && all_spokes) {
        /* the half star: built round the image on the axis side (build_polygons) */
        L->kind = LEAF_STAR;
        L->cr = 0;
        L->cz = img_on_axis ? img[1] : touch_z;
        L->cvtx = img_on_axis ? imgv : -1;
        return 1;
    }
    if (npass == 2 && nimg == 0 && ncross_split == 2 && ncross_second == 2 &&
        crossing_cell(c, L, all, ra, rb, za, zb, split_u, second_curve, second_u))
        return 1;
    if (nimg == 0 && jn_ok && njc >= 2 && junction_cell(c, L, all, ra, rb, za, zb, jc, njc))
        return 1;
    if (nimg == 0 && jn_ok && njc >= 2 && chords_cell(c, L, all, ra, rb, za, zb, jc, njc, peps))
        return 1;
    if (L->level < c->lmax) {
        L->kind = LEAF_REFINE;
        c->nleaf_curves = L->cfirst; /* the children find their own */
        L->cn = 0;
        return 1;
    }
    L->kind = LEAF_FAN;
    if (nimg == 1 && img_inside) {
        L->cr = img[0];
        L->cz = img[1];
        L->cvtx = imgv;
    } else {
        L->cr = 0.5 * (ra + rb);
        L->cz = 0.5 * (za + zb);
    }
    return 1;
}

static int build_quadtree(sw_ctx *c)
{
    sw_samples sp;
    memset(&sp, 0, sizeof sp);
    if (!hmap_init(&sp.cache, 1024) || !hmap_init(&c->corners, 1024) ||
        !hmap_init(&c->leafmap, 1024)) {
        hmap_free(&sp.cache);
        return ctx_nomem(c);
    }
    int ok = 1;
    sw_leaf *stack = NULL;
    int64_t nstack = 0, capstack = 0;
    int64_t root = (int64_t)1 << c->lmax;
    for (int64_t j = c->nroot_z - 1; j >= 0 && ok; j--)
        for (int64_t i = c->nroot_r - 1; i >= 0; i--) {
            if (!mfg_grow((void **)&stack, &capstack, nstack + 1, sizeof *stack)) {
                ok = ctx_nomem(c);
                break;
            }
            memset(&stack[nstack], 0, sizeof *stack);
            stack[nstack].ix = i * root;
            stack[nstack].iz = j * root;
            stack[nstack].level = 0;
            nstack++;
        }
    while (ok && nstack > 0) {
        if (c->leaf_cap > 0 && c->nleaves > c->leaf_cap) {
            c->capped = 1;
            break;
        }
        if (!sw_poll(c, (double)c->nleaves, (double)(c->nleaves + 4 * nstack))) {
            ok = 0;
            break;
        }
        sw_leaf L = stack[--nstack];
        /* arcs of the centre sample are scratch: keep the pool from growing without end */
        int64_t mark = c->narcs;
        if (!analyse_cell(c, &sp, &L)) {
            ok = 0;
            break;
        }
        (void)mark;
        if (L.kind == LEAF_REFINE) {
            int64_t h2 = (int64_t)1 << (c->lmax - L.level - 1);
            if (!mfg_grow((void **)&stack, &capstack, nstack + 4, sizeof *stack)) {
                ok = ctx_nomem(c);
                break;
            }
            for (int q = 3; q >= 0; q--) {
                sw_leaf ch;
                memset(&ch, 0, sizeof ch);
                ch.ix = L.ix + (q & 1) * h2;
                ch.iz = L.iz + (q >> 1) * h2;
                ch.level = L.level + 1;
                stack[nstack++] = ch;
            }
            continue;
        }
        if (!mfg_grow((void **)&c->leaves, &c->capleaves, c->nleaves + 1, sizeof *c->leaves)) {
            ok = ctx_nomem(c);
            break;
        }
        c->leaves[c->nleaves] = L;
        int64_t s = (int64_t)1 << (c->lmax - L.level);
        hkey lk = mkkey(L.level, L.ix, L.iz, 0);
        if (!hmap_put(&c->leafmap, &lk, c->nleaves)) {
            ok = ctx_nomem(c);
            break;
        }
        int64_t cxs[4] = {L.ix, L.ix + s, L.ix + s, L.ix}, czs[4] = {L.iz, L.iz, L.iz + s, L.iz + s};
        for (int k = 0; k < 4 && ok; k++) {
            hkey ck = mkkey(cxs[k], czs[k], 0, 0);
            if (!hmap_put(&c->corners, &ck, 1))
                ok = ctx_nomem(c);
        }
        c->nleaves++;
    }
    free(stack);
    hmap_free(&sp.cache);
    free(sp.pool);
    return ok;
}

/* ----------------------------------------------------------------------------------- */
/* Polygons of the decomposition                                                        */
/* ----------------------------------------------------------------------------------- */

static int64_t add_v2(sw_ctx *c, const hkey *k, double r, double z, int64_t curve, double u,
                      int64_t mvtx)
{
    int64_t id = hmap_get(&c->v2map, k);
    if (id >= 0)
        return id;
    if (!mfg_grow((void **)&c->v2, &c->capv2, c->nv2 + 1, sizeof *c->v2))
        return ctx_nomem(c) - 1;
    sw_vtx2 *w = &c->v2[c->nv2];
    w->r = r;
    w->z = z;
    w->curve = curve;
    w->u = u;
    w->mvtx = mvtx;
    w->ncurves = 0;
    if (curve >= 0) {
        w->curves[0] = curve;
        w->us[0] = u;
        w->ncurves = 1;
    }
    if (!hmap_put(&c->v2map, k, c->nv2))
        return ctx_nomem(c) - 1;
    return c->nv2++;
}

static int64_t corner_v2(sw_ctx *c, int64_t ix, int64_t iz)
{
    hkey k = mkkey(0, ix, iz, 0);
    return add_v2(c, &k, grid_r(c, ix), grid_z(c, iz), -1, 0, -1);
}

static const sw_leaf *leaf_at(const sw_ctx *c, int64_t x2, int64_t z2)
{
    if (x2 < 0 || z2 < 0)
        return NULL;
    for (int lv = c->lmax; lv >= 0; lv--) {
        int64_t S = (int64_t)1 << (c->lmax - lv);
        hkey k = mkkey(lv, (x2 / (2 * S)) * S, (z2 / (2 * S)) * S, 0);
        int64_t id = hmap_get(&c->leafmap, &k);
        if (id >= 0)
            return &c->leaves[id];
    }
    return NULL;
}

typedef struct sw_ipt {
    double key; /* position along the traversal direction */
    double pos, u;
    int64_t curve;
} sw_ipt;

static int cmp_ipt(const void *pa, const void *pb)
{
    const sw_ipt *a = pa, *b = pb;
    if (a->key != b->key)
        return (a->key > b->key) - (a->key < b->key);
    return (a->curve > b->curve) - (a->curve < b->curve);
}

/* Appends to *loop the vertices of the sub-side from integer point (ax, az) to (bx, bz)
 * (axis-parallel, excluding the end): the start, then the crossings of the curves of
 * this leaf and of the leaf across. */
static int sub_side(sw_ctx *c, const sw_leaf *L, int64_t ax, int64_t az, int64_t bx, int64_t bz,
                    int64_t **loop, int64_t *nloop, int64_t *caploop)
{
    int64_t a = corner_v2(c, ax, az);
    if (a < 0)
        return 0;
    if (!mfg_grow((void **)loop, caploop, *nloop + 1, sizeof **loop))
        return ctx_nomem(c);
    (*loop)[(*nloop)++] = a;
    int64_t first_x = *nloop;
    int rside = ax == bx;
    double val = rside ? grid_r(c, ax) : grid_z(c, az);
    double pa = rside ? grid_z(c, az) : grid_r(c, ax), pb = rside ? grid_z(c, bz) : grid_r(c, bx);
    double lo = fmin(pa, pb), hi = fmax(pa, pb);
    int dirn = pb > pa ? 1 : -1;
    /* the leaf across: the point just outside the middle of the sub-side */
    int64_t mx2 = ax + bx, mz2 = az + bz;
    int64_t s = (int64_t)1 << (c->lmax - L->level);
    if (rside)
        mx2 += ax == L->ix ? -1 : 1;
    else
        mz2 += az == L->iz ? -1 : 1;
    (void)s;
    const sw_leaf *N = leaf_at(c, mx2, mz2);
    sw_ipt pts[64];
    int np = 0;
    const sw_leaf *both[2] = {L, N};
    for (int w = 0; w < 2; w++) {
        if (!both[w])
            continue;
        for (int64_t k = 0; k < both[w]->cn; k++) {
            int64_t ic = c->leaf_curves[both[w]->cfirst + k];
            int dup = 0;
            for (int q = 0; q < np; q++)
                dup |= pts[q].curve == ic;
            if (dup)
                continue;
            double pos[2], us[2];
            int m = curve_side(&c->curves[ic], rside, val, lo, hi, pos, us);
            for (int q = 0; q < m && np < 64; q++) {
                pts[np].pos = pos[q];
                pts[np].key = pos[q];
                pts[np].u = us[q];
                pts[np].curve = ic;
                np++;
            }
        }
    }
    /* Crossings within eps of one another are one vertex, made from the lowest of them:
     * sorted upwards whichever way this leaf runs along the side, so that the leaf across
     * (running the other way) makes the same vertex - a silhouette ending on an edge just
     * beside the side gave two vertices a rounding apart, one per leaf, and a crack. */
    qsort(pts, (size_t)np, sizeof *pts, cmp_ipt);
    /* the same merge distance as analyse_cell's chord test */
    double eps = 1e-9 * (hi - lo) + 1e-12 * (fabs(hi) + fabs(lo) + fabs(val));
    double last = dirn > 0 ? lo : -hi;
    (void)last;
    double prev = -INFINITY;
    int64_t prev_id = -1;
    for (int q = 0; q < np; q++) {
        if (fabs(pts[q].pos - pa) <= eps || fabs(pts[q].pos - pb) <= eps)
            continue;
        if (pts[q].key - prev <= eps) {
            /* another curve through the same point: the vertex keeps it for lifting */
            sw_vtx2 *w = &c->v2[prev_id];
            int known = 0;
            for (int j = 0; j < w->ncurves; j++)
                known |= w->curves[j] == pts[q].curve;
            if (!known && w->ncurves < SW_MAXCURVES) {
                w->curves[w->ncurves] = pts[q].curve;
                w->us[w->ncurves++] = pts[q].u;
            }
            continue;
        }
        prev = pts[q].key;
        const sw_curve *cv = &c->curves[pts[q].curve];
        int64_t mv = pts[q].u == 0 ? cv->vtx[0] : (pts[q].u == 1 ? cv->vtx[1] : -1);
        hkey k = mkkey(1 + rside, rside ? ax : az, dbits(pts[q].pos), 0);
        int64_t id = add_v2(c, &k, rside ? val : pts[q].pos, rside ? pts[q].pos : val,
                            pts[q].curve, pts[q].u, mv);
        if (id < 0)
            return 0;
        prev_id = id;
        if (!mfg_grow((void **)loop, caploop, *nloop + 1, sizeof **loop))
            return ctx_nomem(c);
        (*loop)[(*nloop)++] = id;
    }
    if (dirn < 0) /* back into this leaf's direction */
        for (int64_t i = first_x, j = *nloop - 1; i < j; i++, j--) {
            int64_t t = (*loop)[i];
            (*loop)[i] = (*loop)[j];
            (*loop)[j] = t;
        }
    return 1;
}

/* The side from (ax, az) to (bx, bz), cut at the corners of finer leaves across it. */
static int side_loop(sw_ctx *c, const sw_leaf *L, int64_t ax, int64_t az, int64_t bx, int64_t bz,
                     int64_t **loop, int64_t *nloop, int64_t *caploop)
{
    int64_t len = llabs(bx - ax) + llabs(bz - az);
    if (len >= 2) {
        int64_t mx = (ax + bx) / 2, mz = (az + bz) / 2;
        hkey k = mkkey(mx, mz, 0, 0);
        if (hmap_get(&c->corners, &k) >= 0)
            return side_loop(c, L, ax, az, mx, mz, loop, nloop, caploop) &&
                   side_loop(c, L, mx, mz, bx, bz, loop, nloop, caploop);
    }
    return sub_side(c, L, ax, az, bx, bz, loop, nloop, caploop);
}

/* Keeps polygon vs[0 .. n-1] with its arc structure (an empty one is dropped: nothing
 * covers it, and its edges bound nothing). */
static int store_poly(sw_ctx *c, const int64_t *vs, int64_t n, const sw_struct *st)
{
    if (!st->full && st->n == 0)
        return 1;
    if (!mfg_grow((void **)&c->polys, &c->cappolys, c->npolys + 1, sizeof *c->polys) ||
        !mfg_grow((void **)&c->poly_verts, &c->cappv, c->npv + n, sizeof *c->poly_verts))
        return ctx_nomem(c);
    sw_poly *P = &c->polys[c->npolys++];
    P->first = c->npv;
    P->n = n;
    P->st = *st;
    memcpy(c->poly_verts + c->npv, vs, (size_t)n * sizeof *vs);
    c->npv += n;
    return 1;
}

static int add_poly(sw_ctx *c, const int64_t *vs, int64_t n)
{
    if (n < 3)
        return 1;
    double r = 0, z = 0;
    for (int64_t i = 0; i < n; i++) {
        r += c->v2[vs[i]].r;
        z += c->v2[vs[i]].z;
    }
    r /= (double)n;
    z /= (double)n;
    sw_struct st;
    if (!circle_arcs(c, r, z, &st))
        return 0;
    return store_poly(c, vs, n, &st);
}

/*
 * A cell still mixed at the finest size (several curves, vertex images, case-1.3 curves
 * crossing): a block.  Over the whole cell SV is taken as the union of its arcs at the
 * cell's corners, side points, centre and a 4 x 4 grid, each end moved out by the angle
 * the cell's size spans at its smallest radius (the cell is below a quarter of the
 * tolerance, so the block lies within it).  Its caps are flat pieces of meridian
 * half-planes; the walls to its neighbours come out of the common comparison.
 */
static int add_block(sw_ctx *c, const sw_leaf *L, const int64_t *loop, int64_t nloop)
{
    if (L->level < c->lmax) {
        hkey rk = mkkey(L->level, L->ix, L->iz, 0);
        if (!hmap_put(&c->refine, &rk, 1))
            return ctx_nomem(c);
        c->coarse_blocks++;
    }
    int64_t s = (int64_t)1 << (c->lmax - L->level);
    double ra = grid_r(c, L->ix), rb = grid_r(c, L->ix + s);
    double za = grid_z(c, L->iz), zb = grid_z(c, L->iz + s);
    int64_t ns = nloop + 16;
    sw_iv *iv = NULL;
    int64_t niv = 0, capiv = 0;
    int full = 0, ok = 1;
    for (int64_t k = 0; k < ns && ok && !full; k++) {
        double r, z;
        if (k < nloop) {
            /* points on curves are where circles graze edges: the grid inside and the
             * corners sample the block */
            if (c->v2[loop[k]].ncurves > 0)
                continue;
            r = c->v2[loop[k]].r;
            z = c->v2[loop[k]].z;
        } else {
            int64_t q = k - nloop;
            r = ra + (rb - ra) * (0.125 + 0.25 * (double)(q % 4));
            z = za + (zb - za) * (0.125 + 0.25 * (double)(q / 4));
        }
        int64_t mark = c->narcs;
        sw_struct st;
        if (!circle_arcs(c, r, z, &st)) {
            ok = 0;
            break;
        }
        if (st.full)
            full = 1;
        for (int64_t a = 0; a < st.n && ok; a++) {
            const sw_arc *arc = &c->arcs[st.first + a];
            if (!mfg_grow((void **)&iv, &capiv, niv + 1, sizeof *iv)) {
                ok = ctx_nomem(c);
                break;
            }
            double a0 = wrap_angle(arc->start.phi);
            iv[niv].a = a0;
            iv[niv].b = a0 + (arc->end.phi + c->theta - arc->start.phi);
            niv++;
        }
        c->narcs = mark; /* the samples' arcs are not kept */
    }
    if (!ok) {
        free(iv);
        return 0;
    }
    double rmin = fmax(ra, c->h);
    double margin = fmin(MFG_PI, 2 * (rb - ra) / rmin);
    sw_struct bst;
    bst.full = full;
    bst.n = 0;
    bst.first = c->narcs;
    if (!full && niv > 0) {
        for (int64_t i = 0; i < niv; i++) {
            iv[i].a -= margin;
            iv[i].b += margin;
            if (iv[i].b - iv[i].a >= MFG_TWO_PI)
                full = 1;
            double w = wrap_angle(iv[i].a);
            iv[i].b += w - iv[i].a;
            iv[i].a = w;
        }
        qsort(iv, (size_t)niv, sizeof *iv, cmp_iv);
        /* merge on the circle: find an interval not reached by any earlier one (with the
         * wrap of the last ones), start there */
        double reach = -INFINITY;
        for (int64_t i = 0; i < niv; i++)
            reach = fmax(reach, iv[i].b - MFG_TWO_PI);
        int64_t j0 = -1;
        double best = reach;
        for (int64_t i = 0; i < niv && !full; i++) {
            if (iv[i].a > best) {
                j0 = i;
                break;
            }
            best = fmax(best, iv[i].b);
        }
        if (j0 < 0)
            full = 1;
        bst.full = full;
        if (!full) {
            double ca = iv[j0].a, cb = iv[j0].b;
            for (int64_t k = 1; k <= niv && ok; k++) {
                int64_t i = (j0 + k) % niv;
                double a = iv[i].a + ((j0 + k) >= niv ? MFG_TWO_PI : 0);
                double b = iv[i].b + ((j0 + k) >= niv ? MFG_TWO_PI : 0);
                if (k < niv && a <= cb) {
                    cb = fmax(cb, b);
                    continue;
                }
                sw_arc arc;
                memset(&arc, 0, sizeof arc);
                arc.start.tri = arc.end.tri = -1;
                arc.start.phi = ca;
                arc.end.phi = cb - c->theta;
                ok = push_arc(c, &arc);
                bst.n++;
                ca = a;
                cb = b;
            }
        }
    }
    free(iv);
    if (!ok)
        return 0;
    return store_poly(c, loop, nloop, &bst);
}

/* The curves of leaf L through its centre (a crossing of chords), with their parameters
 * there, kept on the centre's 2-D vertex: its lifts onto the triangles of those edges
 * land on the edges, so that the pieces meeting there share the vertex. */
static void centre_curves(const sw_ctx *c, const sw_leaf *L, sw_vtx2 *w)
{
    double eps = 1e-9 * (w->r + fabs(w->z)) + 1e-6 * c->tol;
    for (int64_t k = 0; k < L->cn && w->ncurves < SW_MAXCURVES; k++) {
        int64_t ic = c->leaf_curves[L->cfirst + k];
        const sw_curve *cv = &c->curves[ic];
        double u;
        if (cv->dir[2] != 0) {
            u = (w->z - cv->p0[2]) / cv->dir[2];
        } else {
            if (fabs(cv->p0[2] - w->z) > eps)
                continue;
            u = curve_u_at_r(cv, w->r, 0, 1);
        }
        /* an end of a gap-closing curve at a junction: u = 0 or 1 up to rounding */
        if (u < 0 && u >= -1e-9)
            u = 0;
        if (u > 1 && u <= 1 + 1e-9)
            u = 1;
        if (!(u >= 0 && u <= 1) || fabs(curve_r(cv, u) - w->r) > eps)
            continue;
        int known = 0;
        for (int j = 0; j < w->ncurves; j++)
            known |= w->curves[j] == ic;
        if (!known) {
            w->curves[w->ncurves] = ic;
            w->us[w->ncurves++] = u;
        }
    }
}

static int on_curve(const sw_vtx2 *w, int64_t ic)
{
    for (int j = 0; j < w->ncurves; j++)
        if (w->curves[j] == ic)
            return 1;
    return 0;
}

/* Cuts the boundary loop of a LEAF_CHORDS cell along each of its curves' chords and adds
 * the pieces; 0 on error, -1 when a chord's two ends are not found in one piece (then the
 * caller makes the cell a block). */
static int cut_chords(sw_ctx *c, const sw_leaf *L, const int64_t *loop, int64_t nloop)
{
    int64_t cap = 3 * (nloop + 2 * SW_MAXJUNCTION) + 8;
    int64_t *buf = malloc((size_t)cap * sizeof *buf);
    int64_t first[SW_MAXJUNCTION + 2], len[SW_MAXJUNCTION + 2];
    if (!buf)
        return ctx_nomem(c);
    memcpy(buf, loop, (size_t)nloop * sizeof *buf);
    int np = 1, res = 1;
    int64_t used = nloop;
    first[0] = 0;
    len[0] = nloop;
    for (int64_t k = 0; k < L->cn && res == 1; k++) {
        int64_t ic = c->leaf_curves[L->cfirst + k];
        int done = 0, seen = 0;
        for (int p = 0; p < np && !done; p++) {
            int64_t at[2], m = 0, n = len[p];
            const int64_t *v = buf + first[p];
            for (int64_t i = 0; i < n; i++)
                if (on_curve(&c->v2[v[i]], ic)) {
                    if (m < 2)
                        at[m] = i;
                    m++;
                }
            seen += (int)m;
            if (m != 2)
                continue;
            if (at[1] == at[0] + 1 || (at[0] == 0 && at[1] == n - 1)) {
                done = 1; /* a coincident chord, already cut */
                continue;
            }
            if (np >= SW_MAXJUNCTION + 2 || used + n + 2 > cap)
                break;
            /* the piece from at[0] to at[1], and the rest from at[1] round to at[0] */
            int64_t f2 = used, n1 = at[1] - at[0] + 1, n2 = n - n1 + 2;
            for (int64_t i = 0; i < n2; i++)
                buf[f2 + i] = v[(at[1] + i) % n];
            int64_t *w = buf + first[p];
            memmove(w, w + at[0], (size_t)n1 * sizeof *w);
            len[p] = n1;
            first[np] = f2;
            len[np] = n2;
            np++;
            used += n2;
            done = 1;
        }
        /* a curve named at fewer than two vertices: one of several with one chord,
         * whose vertices keep SW_MAXCURVES of them (the count below checks the cut) */
        if (!done && seen >= 2)
            res = -1;
    }
    if (np != L->nchords + 1)
        res = -1;
    for (int p = 0; p < np && res == 1; p++)
        res = add_poly(c, buf + first[p], len[p]);
    free(buf);
    return res;
}

/*
 * The half star round a vertex image on the axis (analyse_cell): the image lies on the
 * cell's side r = 0, where the loop already has a vertex if a curve's crossing with that
 * side was found there (within rounding).  That vertex becomes the centre (one 2-D vertex
 * at the image, at the image's exact coordinates); the other vertices of the side
 * strictly between its corners are crossings at the image too (analyse_cell allows no
 * other) and are dropped.  Then one triangle from the centre to every loop edge that
 * does not touch it, each with the structure at its own centroid.  No cell lies across
 * the side r = 0, so its vertices belong to this cell alone.
 */
static int half_star(sw_ctx *c, const sw_leaf *L, const int64_t *loop, int64_t nloop)
{
    int64_t s = (int64_t)1 << (c->lmax - L->level);
    double za = grid_z(c, L->iz), zb = grid_z(c, L->iz + s);
    int64_t *w = malloc((size_t)(nloop + 1) * sizeof *w);
    if (!w)
        return ctx_nomem(c);
    int64_t n = 0, centre = -1, at = -1;
    for (int64_t i = 0; i < nloop; i++) {
        const sw_vtx2 *v = &c->v2[loop[i]];
        if (v->r == 0 && v->z > za && v->z < zb) {
            if (centre < 0)
                centre = loop[i];
            continue;
        }
        w[n++] = loop[i];
        if (v->r == 0 && v->z == zb)
            at = n; /* the side r = 0 runs down from here */
    }
    if (centre < 0) {
        hkey k = mkkey(3, dbits(0), dbits(L->cz), 0);
        centre = add_v2(c, &k, 0, L->cz, -1, 0, L->cvtx);
        if (centre < 0) {
            free(w);
            return 0;
        }
    }
    if (at < 0) { /* no corner (0, zb): cannot happen; a block is always safe */
        free(w);
        return add_block(c, L, loop, nloop);
    }
    sw_vtx2 *cv = &c->v2[centre];
    cv->z = L->cz;
    cv->mvtx = L->cvtx;
    memmove(w + at + 1, w + at, (size_t)(n - at) * sizeof *w);
    w[at] = centre;
    n++;
    int ok = 1;
    for (int64_t i = 0; i < n && ok; i++) {
        int64_t a = w[i], b = w[(i + 1) % n];
        if (a == centre || b == centre)
            continue;
        int64_t tri[3] = {centre, a, b};
        ok = add_poly(c, tri, 3);
    }
    free(w);
    return ok;
}

static int build_polygons(sw_ctx *c)
{
    if (!hmap_init(&c->v2map, 4 * c->nleaves + 64))
        return ctx_nomem(c);
    int64_t *loop = NULL, nloop = 0, caploop = 0;
    int ok = 1;
    for (int64_t li = 0; li < c->nleaves && ok; li++) {
        if (!sw_poll(c, (double)li, (double)c->nleaves)) {
            ok = 0;
            break;
        }
        const sw_leaf *L = &c->leaves[li];
        if (L->empty)
            continue;
        int64_t s = (int64_t)1 << (c->lmax - L->level);
        int64_t cx[5] = {L->ix, L->ix + s, L->ix + s, L->ix, L->ix};
        int64_t cz[5] = {L->iz, L->iz, L->iz + s, L->iz + s, L->iz};
        nloop = 0;
        for (int k = 0; k < 4 && ok; k++)
            ok = side_loop(c, L, cx[k], cz[k], cx[k + 1], cz[k + 1], &loop, &nloop, &caploop);
        if (!ok)
            break;
        int kind = L->kind;
        if (kind == LEAF_SPLIT) {
            int64_t at[2], m = 0;
            for (int64_t i = 0; i < nloop && m <= 2; i++) {
                const sw_vtx2 *w = &c->v2[loop[i]];
                int on = 0;
                for (int j = 0; j < w->ncurves; j++)
                    on |= w->curves[j] == L->split_curve;
                if (on) {
                    if (m < 2)
                        at[m] = i;
                    m++;
                }
            }
            if (m != 2) {
                kind = LEAF_FAN;
            } else {
                int64_t *tmp = malloc((size_t)(nloop + 2) * sizeof *tmp);
                if (!tmp) {
                    ok = ctx_nomem(c);
                    break;
                }
                int64_t n1 = 0;
                for (int64_t i = at[0]; i <= at[1]; i++)
                    tmp[n1++] = loop[i];
                ok = add_poly(c, tmp, n1);
                int64_t n2 = 0;
                for (int64_t i = at[1]; i != at[0]; i = (i + 1) % nloop)
                    tmp[n2++] = loop[i];
                tmp[n2++] = loop[at[0]];
                if (ok)
                    ok = add_poly(c, tmp, n2);
                free(tmp);
                continue;
            }
        }
        if (kind == LEAF_CHORDS) {
            int r = cut_chords(c, L, loop, nloop);
            if (r == 0) {
                ok = 0;
                break;
            }
            if (r == 1)
                continue;
            kind = LEAF_FAN; /* nothing was added: the pieces are added after the cuts */
        }
        if (kind == LEAF_CLEAN) {
            ok = add_poly(c, loop, nloop);
            continue;
        }
        if (kind == LEAF_FAN) {
            ok = add_block(c, L, loop, nloop);
            continue;
        }
        if (kind == LEAF_STAR && L->cr == 0) {
            ok = half_star(c, L, loop, nloop);
            continue;
        }
        /* star round the vertex image */
        hkey k = mkkey(3, dbits(L->cr), dbits(L->cz), 0);
        int64_t cv = add_v2(c, &k, L->cr, L->cz, -1, 0, kind == LEAF_STAR || L->cvtx >= 0 ? L->cvtx : -1);
        if (cv < 0) {
            ok = 0;
            break;
        }
        if (L->cvtx < 0)
            centre_curves(c, L, &c->v2[cv]);
        for (int64_t i = 0; i < nloop && ok; i++) {
            int64_t tri[3] = {cv, loop[i], loop[(i + 1) % nloop]};
            ok = add_poly(c, tri, 3);
        }
    }
    free(loop);
    return ok;
}

/* ----------------------------------------------------------------------------------- */
/* Output vertices, lifts                                                               */
/* ----------------------------------------------------------------------------------- */

typedef struct sw_out {
    double *phi;           /* angle of each output vertex */
    int64_t capphi;
    hmap lifts;            /* (v2, tri, sigma, exit) -> vertex */
} sw_out;

/* The output vertex at local point p (merged with any vertex of the same doubles). */
static int64_t out_vertex(sw_ctx *c, sw_out *o, const double p[3], double phi)
{
    /* Points closer than the weld quantum (2^-40 of the part's size) are one vertex:
     * lifts of one corner onto the planes of two triangles of one face, or onto a face
     * and its neighbour at their common edge, agree only up to rounding. */
    int64_t q[3];
    double pz[3];
    /* a coordinate below the library's range (2^-200, mfg_coord_ok: a turn by a tiny
     * angle) is 0, far below the weld quantum */
    for (int i = 0; i < 3; i++)
        pz[i] = fabs(p[i]) < 0x1p-200 ? 0 : p[i];
    p = pz;
    for (int i = 0; i < 3; i++)
        q[i] = (int64_t)floor(p[i] / c->quantum + 0.5);
    hkey k = mkkey(q[0], q[1], q[2], 0);
    int64_t id = hmap_get(&c->outmap, &k);
    if (id >= 0)
        return id;
    /* a point just across a cell boundary of the quantisation */
    for (int dx = -1; dx <= 1; dx++)
        for (int dy = -1; dy <= 1; dy++)
            for (int dz = -1; dz <= 1; dz++) {
                if (!dx && !dy && !dz)
                    continue;
                hkey kn = mkkey(q[0] + dx, q[1] + dy, q[2] + dz, 0);
                int64_t j = hmap_get(&c->outmap, &kn);
                if (j >= 0) {
                    const double *r = c->ox + 3 * j;
                    if (fabs(r[0] - p[0]) <= c->quantum && fabs(r[1] - p[1]) <= c->quantum &&
                        fabs(r[2] - p[2]) <= c->quantum)
                        return j;
                }
            }
    if (!mfg_grow((void **)&c->ox, &c->capout, c->nout + 1, 3 * sizeof *c->ox) ||
        !mfg_grow((void **)&o->phi, &o->capphi, c->nout + 1, sizeof *o->phi))
        return ctx_nomem(c) - 1;
    memcpy(c->ox + 3 * c->nout, p, 3 * sizeof *p);
    o->phi[c->nout] = phi;
    if (!hmap_put(&c->outmap, &k, c->nout))
        return ctx_nomem(c) - 1;
    return c->nout++;
}

static int64_t ring_vertex(sw_ctx *c, sw_out *o, const sw_vtx2 *w, double phi)
{
    double p[3] = {w->r * cos(phi), w->r * sin(phi), w->z};
    if (w->r == 0)
        p[0] = p[1] = 0;
    return out_vertex(c, o, p, wrap_angle(phi));
}

/* The point over 2-D vertex w on the plane of triangle t at root sigma; turned by theta
 * for the end of an arc. */
static int64_t lift(sw_ctx *c, sw_out *o, int64_t iw, const sw_end *en, int isexit)
{
    int64_t t = en->tri;
    int sigma = en->sigma;
    const sw_vtx2 *w = &c->v2[iw];
    if (t < 0) {
        /* a block's cap: the meridian half-plane at a fixed angle (the end's angle is
         * stored before the turn, like an exit's) */
        double ang = en->phi + (isexit ? c->theta : 0);
        return ring_vertex(c, o, w, ang);
    }
    hkey k = mkkey(iw, t, sigma + 1, isexit);
    int64_t id = hmap_get(&o->lifts, &k);
    if (id >= 0)
        return id;
    const sw_tri *T = &c->tris[t];
    double p[3];
    int done = 0;
    if (w->r == 0) {
        p[0] = p[1] = 0;
        p[2] = w->z;
        done = 1;
    }
    double phi_root = 0;
    {
        double A = T->n[0] * w->r, B = T->n[1] * w->r, C = T->d - T->n[2] * w->z;
        double R = sqrt(A * A + B * B);
        double cv = R > 0 ? C / R : 1;
        if (cv > 1)
            cv = 1;
        if (cv < -1)
            cv = -1;
        phi_root = T->phi0 + sigma * acos(cv);
    }
    /* a vertex of the triangle imaged here, at this root: the vertex itself (a triangle
     * may hold two vertices with one image, mirror images across its meridian) */
    for (int q = 0; q < 3 && !done; q++) {
        int64_t v = T->v[q];
        if (c->vr[v] == w->r && c->lx[3 * v + 2] == w->z) {
            double dphi = fabs(angle_diff(atan2(c->lx[3 * v + 1], c->lx[3 * v]), phi_root));
            if (dphi * w->r <= 1e-6 * (w->r + c->tol) + 0.01 * c->tol) {
                memcpy(p, c->lx + 3 * v, sizeof p);
                done = 1;
            }
        }
    }
    /* on a curve (an edge or silhouette): the curve's own point when this root lands on
     * it, so that every piece meeting there shares the vertex; curves of the triangle
     * first */
    if (!done && w->ncurves > 0) {
        double snap = 1e-9 * (w->r + fabs(w->z)) + 1e-6 * c->tol;
        double pr[3] = {w->r * cos(phi_root), w->r * sin(phi_root), w->z};
        for (int pass = 0; pass < 2 && !done; pass++)
            for (int j = 0; j < w->ncurves && !done; j++) {
                const sw_curve *cv = &c->curves[w->curves[j]];
                /* a gap-closing curve lies on its entry triangle and, turned back by
                 * theta, on its exit triangle: the end there lifts to the same point */
                int back = isexit && cv->gexit == t;
                int own = cv->tri[0] == t || cv->tri[1] == t || back;
                if ((pass == 0) != own || cv->dir[2] == 0)
                    continue;
                double q[3];
                for (int i = 0; i < 3; i++)
                    q[i] = cv->p0[i] + w->us[j] * cv->dir[i];
                if (back) {
                    double dx0 = q[0] - pr[0], dy0 = q[1] - pr[1];
                    double ct = cos(c->theta), st = sin(c->theta);
                    double qb[3] = {q[0] * ct + q[1] * st, -q[0] * st + q[1] * ct, q[2]};
                    double dxb = qb[0] - pr[0], dyb = qb[1] - pr[1];
                    /* the exit triangle may be the entry one: the nearer of the two */
                    if (cv->tri[0] != t || dxb * dxb + dyb * dyb < dx0 * dx0 + dy0 * dy0)
                        memcpy(q, qb, sizeof q);
                }
                double dx = q[0] - pr[0], dy = q[1] - pr[1];
                double lim = own ? 1e-6 * (w->r + c->tol) + 0.01 * c->tol : snap;
                if (sqrt(dx * dx + dy * dy) <= lim) {
                    memcpy(p, q, sizeof p);
                    done = 1;
                }
            }
    }
    if (!done) {
        p[0] = w->r * cos(phi_root);
        p[1] = w->r * sin(phi_root);
        p[2] = w->z;
    }
    if (isexit && w->r != 0) {
        double ct = cos(c->theta), st = sin(c->theta);
        double x = p[0] * ct - p[1] * st, y = p[0] * st + p[1] * ct;
        p[0] = x;
        p[1] = y;
    }
    id = out_vertex(c, o, p, wrap_angle(atan2(p[1], p[0])));
    if (id < 0)
        return -1;
    if (!hmap_put(&o->lifts, &k, id))
        return ctx_nomem(c) - 1;
    return id;
}

/* Appends triangle (a, b, d).  A wall triangle names its edge along a circle (ring_a,
 * ring_b) and the direction (angle in the meridian plane) in which the wall leaves that
 * circle: what resolve_pinches orders pieces by, where coordinates would mislead (a chord's
 * sag, circumscribed vertices). */
static int emit_tri_ring(sw_ctx *c, int64_t a, int64_t b, int64_t d, int64_t ring_a, int64_t ring_b,
                         double dir)
{
    if (a == b || b == d || d == a)
        return 1;
    if (!mfg_grow((void **)&c->otri, &c->capotri, c->notri + 1, 3 * sizeof *c->otri) ||
        !mfg_grow((void **)&c->oring, &c->caporing, c->notri + 1, 2 * sizeof *c->oring) ||
        !mfg_grow((void **)&c->odir, &c->capodir, c->notri + 1, sizeof *c->odir) ||
        !mfg_grow((void **)&c->oface, &c->capoface, c->notri + 1, sizeof *c->oface))
        return ctx_nomem(c);
    c->otri[3 * c->notri] = a;
    c->otri[3 * c->notri + 1] = b;
    c->otri[3 * c->notri + 2] = d;
    c->oring[2 * c->notri] = ring_a;
    c->oring[2 * c->notri + 1] = ring_b;
    c->odir[c->notri] = dir;
    c->oface[c->notri] = -1;
    c->notri++;
    return 1;
}

/* A face triangle: a piece of input triangle tri's plane (turned by theta for an exit),
 * which merge_faces joins with the other pieces of that plane; tri < 0 for none. */
static int emit_tri(sw_ctx *c, int64_t a, int64_t b, int64_t d, int64_t tri, int isexit)
{
    int64_t n = c->notri;
    if (!emit_tri_ring(c, a, b, d, -1, -1, 0))
        return 0;
    if (c->notri > n && tri >= 0)
        c->oface[n] = 2 * tri + isexit;
    return 1;
}

/* Number of grid steps on a circle of radius r: chord sag r (1 - cos(pi / N)) below half
 * the tolerance. */
static int64_t ring_steps(const sw_ctx *c, double r)
{
    double sag = 0.5 * c->tol;
    if (r <= sag)
        return 8;
    double step = 2 * acos(1 - sag / r);
    double n = ceil(MFG_TWO_PI / step);
    if (n < 8)
        n = 8;
    if (n > 1 << 20)
        n = 1 << 20;
    return (int64_t)n;
}

/* ----------------------------------------------------------------------------------- */
/* Walls                                                                                */
/* ----------------------------------------------------------------------------------- */

typedef struct wline {
    int side;              /* 0: the polygon on the left of u -> v, 1: on the right */
    int isend;
    int64_t arc;
    int64_t va, vb;        /* output vertices over u and over v */
    double pa, pb;         /* their angles, pb unwrapped to within pi of pa */
    int cancelled;         /* the same line on both sides: no wall along it */
} wline;

typedef struct wend {
    int64_t v2;            /* 2-D vertex, or -1: an event point (ring = evring) */
    int64_t ring_first, ring_n;
    double r, z;
    int64_t lo, hi;        /* vertices bounding the strip on this circle */
} wend;

typedef struct wstrip {
    wend e[2];
    int full;              /* a whole turn (no lines) */
    int left_covers;       /* the polygon on the left covers the strip */
    double span_mid;       /* its angular width half-way: the ends' widths are taken
                              within pi of it (a width of -1e-17 is 0, not 2 pi) */
} wstrip;

typedef struct sw_walls {
    wstrip *strips;
    int64_t nstrips, capstrips;
    /* ring entries at 2-D vertices: (v2, vertex) */
    int64_t *rv2, *rvid;
    int64_t nring, capring, capring2;
    int64_t *ring_start;   /* per v2, after sorting: entries [ring_start[v], ring_start[v+1]) */
    int64_t *evring;       /* vertices of event circles */
    int64_t nevring, capevring;
    char *push;            /* per 2-D vertex: its circle carries an outer wall, whose
                              grid vertices go out to circumscribe the circle */
    int64_t cappush;
    hmap evlists;          /* (poly, edge, line, 0) -> index in evl */
    int64_t *evl;
    int64_t nevl, capevl;
} sw_walls;

static double line_at(const wline *l, double s)
{
    return l->pa + s * (l->pb - l->pa);
}

/* Does a side cover angle phi at s?  Arc a runs from its start line over a length that
 * varies linearly from lenu[a] (over u) to lenv[a] (over v): lengths are unwrapped from
 * the polygon's own sample, so an arc that closes to a full turn along the edge (its end
 * passing its start) covers everything instead of a sliver. */
static int covered(const wline *lines, const int64_t *starts, const double *lenu,
                   const double *lenv, int64_t narc, int full, double s, double phi)
{
    if (full)
        return 1;
    for (int64_t a = 0; a < narc; a++) {
        double len = lenu[a] + s * (lenv[a] - lenu[a]);
        if (len >= MFG_TWO_PI)
            return 1;
        if (len <= 0)
            continue;
        double st = line_at(&lines[starts[a]], s);
        if (wrap_angle(phi - st) <= len)
            return 1;
    }
    return 0;
}

static int ring_add(sw_ctx *c, sw_walls *W, int64_t v2, int64_t vid)
{
    if (!mfg_grow((void **)&W->rv2, &W->capring, W->nring + 1, sizeof *W->rv2) ||
        !mfg_grow((void **)&W->rvid, &W->capring2, W->nring + 1, sizeof *W->rvid))
        return ctx_nomem(c);
    W->rv2[W->nring] = v2;
    W->rvid[W->nring] = vid;
    W->nring++;
    return 1;
}

typedef struct sw_bd {
    double phi;
    int64_t line;
} sw_bd;

static int cmp_bd(const void *pa, const void *pb)
{
    const sw_bd *a = pa, *b = pb;
    return (a->phi > b->phi) - (a->phi < b->phi);
}

static int cmp_double(const void *pa, const void *pb)
{
    double a = *(const double *)pa, b = *(const double *)pb;
    return (a > b) - (a < b);
}

/* The walls along the edge u -> v: P is the polygon on its left (edge index ip), Q the one
 * on its right (edge index iq of v -> u) or -1. */
static int edge_walls(sw_ctx *c, sw_out *o, sw_walls *W, int64_t u, int64_t v, int64_t P,
                      int64_t ip, int64_t Q, int64_t iq)
{
    const sw_poly *polys[2] = {&c->polys[P], Q >= 0 ? &c->polys[Q] : NULL};
    int64_t nl = 0;
    for (int sd = 0; sd < 2; sd++)
        if (polys[sd])
            nl += 2 * polys[sd]->st.n;
    wline *lines = malloc((size_t)(nl + 1) * sizeof *lines);
    int64_t *starts = malloc((size_t)(nl + 1) * sizeof *starts);
    int64_t *ends = malloc((size_t)(nl + 1) * sizeof *ends);
    double *lenu = malloc((size_t)(nl + 1) * sizeof *lenu);
    double *lenv = malloc((size_t)(nl + 1) * sizeof *lenv);
    double *ev = malloc((size_t)(nl * nl + 2) * sizeof *ev);
    sw_bd *bd = malloc((size_t)(nl + 1) * sizeof *bd);
    if (!lines || !starts || !ends || !ev || !bd || !lenu || !lenv) {
        free(lenu);
        free(lenv);
        free(lines);
        free(starts);
        free(ends);
        free(ev);
        free(bd);
        return ctx_nomem(c);
    }
    int ok = 1;
    int64_t k = 0, narc[2] = {0, 0}, first_arc[2] = {0, 0};
    for (int sd = 0; sd < 2 && ok; sd++) {
        first_arc[sd] = k / 2;
        if (!polys[sd])
            continue;
        for (int64_t a = 0; a < polys[sd]->st.n && ok; a++) {
            const sw_arc *arc = &c->arcs[polys[sd]->st.first + a];
            for (int e = 0; e < 2; e++) {
                const sw_end *en = e ? &arc->end : &arc->start;
                wline *l = &lines[k];
                l->side = sd;
                l->isend = e;
                l->arc = a;
                l->cancelled = 0;
                l->va = lift(c, o, u, en, e);
                l->vb = lift(c, o, v, en, e);
                if (l->va < 0 || l->vb < 0) {
                    ok = 0;
                    break;
                }
                /* on the axis every angle is the same point: take the other end's */
                double fa = o->phi[l->va], fb = o->phi[l->vb];
                if (c->v2[u].r == 0)
                    fa = fb;
                if (c->v2[v].r == 0)
                    fb = fa;
                l->pa = fa;
                l->pb = l->pa + angle_diff(fb, l->pa);
                if (e)
                    ends[k / 2] = k;
                else
                    starts[k / 2] = k;
                ok = ok && ring_add(c, W, u, l->va) && ring_add(c, W, v, l->vb);
                k++;
            }
            if (ok) {
                /* the arc's length over u and v, unwrapped from its length at the sample */
                double L0 = arc->end.phi + c->theta - arc->start.phi;
                const wline *ls = &lines[k - 2], *le = &lines[k - 1];
                int64_t ai = k / 2 - 1;
                lenu[ai] = L0 + angle_diff(le->pa - ls->pa, L0);
                lenv[ai] = L0 + angle_diff(le->pb - ls->pb, L0);
            }
            narc[sd]++;
        }
    }
    /* the same line on both sides bounds nothing */
    for (int64_t i = 0; i < nl && ok; i++)
        for (int64_t j = 0; j < nl; j++)
            if (lines[i].side == 0 && lines[j].side == 1 && !lines[i].cancelled &&
                !lines[j].cancelled && lines[i].va == lines[j].va && lines[i].vb == lines[j].vb &&
                lines[i].isend == lines[j].isend) {
                lines[i].cancelled = lines[j].cancelled = 1;
                break;
            }
    /* events: where two lines cross */
    int64_t nev = 0;
    ev[nev++] = 0;
    for (int64_t i = 0; i < nl && ok; i++)
        for (int64_t j = 0; j < nl; j++) {
            /* any two lines: a polygon's own start and end lines cross where its arc
             * closes to a full turn (a fan piece astride a case-1.3 curve) */
            if (j <= i)
                continue; /* cancelled lines too: their arcs' closing still cuts faces */
            double f0 = lines[i].pa - lines[j].pa, f1 = lines[i].pb - lines[j].pb;
            double lo = fmin(f0, f1), hi = fmax(f0, f1);
            for (double m = ceil(lo / MFG_TWO_PI); m * MFG_TWO_PI <= hi; m += 1) {
                if (f1 == f0)
                    break;
                double s = (m * MFG_TWO_PI - f0) / (f1 - f0);
                if (s > 1e-9 && s < 1 - 1e-9)
                    ev[nev++] = s;
            }
        }
    ev[nev++] = 1;
    qsort(ev, (size_t)nev, sizeof *ev, cmp_double);
    int64_t m = 0;
    for (int64_t i = 0; i < nev; i++)
        if (m == 0 || ev[i] - ev[m - 1] > 1e-9)
            ev[m++] = ev[i];
    if (ev[m - 1] != 1)
        ev[m - 1] = 1;
    nev = m;
    /* event vertices: on every line's chord at every inner event (lines that meet there
     * share one) */
    int64_t ninner = nev - 2;
    int64_t *evv = malloc((size_t)(nl * (ninner > 0 ? ninner : 1) + 1) * sizeof *evv);
    int64_t *evr_first = malloc((size_t)(nev + 1) * sizeof *evr_first);
    if (!evv || !evr_first) {
        free(evv);
        free(evr_first);
        evv = NULL; /* freed again at the end */
        evr_first = NULL;
        ok = ctx_nomem(c);
    }
    const sw_vtx2 *wu = &c->v2[u], *wv = &c->v2[v];
    for (int64_t e = 1; e + 1 < nev && ok; e++) {
        double s = ev[e];
        evr_first[e] = W->nevring;
        for (int64_t i = 0; i < nl && ok; i++) {
            int64_t id = -1;
            double val = line_at(&lines[i], s);
            for (int64_t j = 0; j < i; j++)
                if (fabs(angle_diff(line_at(&lines[j], s), val)) < 1e-12) {
                    id = evv[j * ninner + e - 1];
                    break;
                }
            if (id < 0) {
                const double *a = c->ox + 3 * lines[i].va, *b = c->ox + 3 * lines[i].vb;
                double p[3] = {a[0] + s * (b[0] - a[0]), a[1] + s * (b[1] - a[1]),
                               a[2] + s * (b[2] - a[2])};
                id = out_vertex(c, o, p, wrap_angle(atan2(p[1], p[0])));
                if (id < 0) {
                    ok = 0;
                    break;
                }
            }
            evv[i * ninner + e - 1] = id;
            if (!mfg_grow((void **)&W->evring, &W->capevring, W->nevring + 1, sizeof *W->evring)) {
                ok = ctx_nomem(c);
                break;
            }
            W->evring[W->nevring++] = id;
        }
    }
    if (ok)
        evr_first[nev - 1] = W->nevring;
    /* per polygon edge and line, the event vertices in the polygon's direction */
    for (int64_t i = 0; i < nl && ok && ninner > 0; i++) {
        int sd = lines[i].side;
        int64_t pid = sd ? Q : P, eid = sd ? iq : ip;
        hkey key = mkkey(pid, eid, 2 * lines[i].arc + lines[i].isend, 0);
        if (!mfg_grow((void **)&W->evl, &W->capevl, W->nevl + 2 * ninner + 1, sizeof *W->evl)) {
            ok = ctx_nomem(c);
            break;
        }
        if (!hmap_put(&W->evlists, &key, W->nevl)) {
            ok = ctx_nomem(c);
            break;
        }
        /* count, then (vertex, position along the polygon's edge as double bits) */
        W->evl[W->nevl++] = ninner;
        for (int64_t e = 0; e < ninner; e++) {
            int64_t ei = sd ? ninner - 1 - e : e;
            double sp = sd ? 1 - ev[ei + 1] : ev[ei + 1];
            W->evl[W->nevl++] = evv[i * ninner + ei];
            memcpy(&W->evl[W->nevl++], &sp, sizeof sp);
        }
    }
    /* strips between consecutive events */
    for (int64_t e = 0; e + 1 < nev && ok; e++) {
        double s0 = ev[e], s1 = ev[e + 1], sm = 0.5 * (s0 + s1);
        int64_t nb = 0;
        for (int64_t i = 0; i < nl; i++)
            if (!lines[i].cancelled) {
                bd[nb].phi = wrap_angle(line_at(&lines[i], sm));
                bd[nb].line = i;
                nb++;
            }
        qsort(bd, (size_t)nb, sizeof *bd, cmp_bd);
        int fullL = polys[0]->st.full, fullR = polys[1] ? polys[1]->st.full : 0;
        int64_t nseg = nb > 0 ? nb : 1;
        for (int64_t q = 0; q < nseg && ok; q++) {
            double a0, a1;
            if (nb > 0) {
                a0 = bd[q].phi;
                a1 = q + 1 < nb ? bd[q + 1].phi : bd[0].phi + MFG_TWO_PI;
                if (a1 - a0 <= 0)
                    continue;
            } else {
                a0 = 0;
                a1 = MFG_TWO_PI;
            }
            double ph = 0.5 * (a0 + a1);
            int cl = covered(lines, starts + first_arc[0], lenu + first_arc[0], lenv + first_arc[0],
                             narc[0], fullL, sm, ph);
            int cr = polys[1] ? covered(lines, starts + first_arc[1], lenu + first_arc[1],
                                        lenv + first_arc[1], narc[1], fullR, sm, ph)
                              : 0;
            if (cl == cr)
                continue;
            if (!mfg_grow((void **)&W->strips, &W->capstrips, W->nstrips + 1, sizeof *W->strips)) {
                ok = ctx_nomem(c);
                break;
            }
            wstrip *S = &W->strips[W->nstrips++];
            S->full = nb == 0;
            S->left_covers = cl;
            {
                /* an outer wall (its outward normal points away from the axis): the
                 * chords of its circles would cut into SV; mark them to circumscribe */
                double dz = wv->z - wu->z;
                double nr = cl ? dz : -dz;
                if (nr > 0) {
                    if (!mfg_grow((void **)&W->push, &W->cappush, c->nv2, sizeof *W->push)) {
                        ok = ctx_nomem(c);
                        break;
                    }
                    W->push[u] = W->push[v] = 1;
                }
            }
            S->span_mid = a1 - a0;
            for (int end = 0; end < 2; end++) {
                double s = end ? s1 : s0;
                int64_t ei = end ? e + 1 : e;
                wend *we = &S->e[end];
                if (ei == 0 || ei == nev - 1) {
                    const sw_vtx2 *w = ei == 0 ? wu : wv;
                    we->v2 = ei == 0 ? u : v;
                    we->r = w->r;
                    we->z = w->z;
                    we->ring_first = we->ring_n = 0;
                    if (!S->full) {
                        const wline *llo = &lines[bd[q].line], *lhi = &lines[bd[(q + 1) % nb].line];
                        we->lo = ei == 0 ? llo->va : llo->vb;
                        we->hi = ei == 0 ? lhi->va : lhi->vb;
                    }
                } else {
                    we->v2 = -1;
                    we->r = wu->r + s * (wv->r - wu->r);
                    we->z = wu->z + s * (wv->z - wu->z);
                    we->ring_first = evr_first[ei];
                    we->ring_n = evr_first[ei + 1] - evr_first[ei];
                    if (!S->full) {
                        we->lo = evv[bd[q].line * ninner + ei - 1];
                        we->hi = evv[bd[(q + 1) % nb].line * ninner + ei - 1];
                    }
                }
            }
        }
    }
    free(evv);
    free(evr_first);
    free(lenu);
    free(lenv);
    free(lines);
    free(starts);
    free(ends);
    free(ev);
    free(bd);
    return ok;
}

typedef struct sw_pl {
    int64_t vid;
    double off;
    int grid;              /* a grid vertex of an outer wall's circumscribed polygon */
} sw_pl;

static int cmp_pl(const void *pa, const void *pb)
{
    const sw_pl *a = pa, *b = pb;
    if (a->off != b->off)
        return (a->off > b->off) - (a->off < b->off);
    return (a->vid > b->vid) - (a->vid < b->vid);
}

/* The vertices of one end of a strip, in increasing angle from lo to hi (a full turn for
 * full strips, closed by repeating the first), with offsets normalised to [0, 1]. */
static int end_polyline(sw_ctx *c, sw_out *o, const sw_walls *W, const wend *we, int full,
                        double span_mid, sw_pl **out, int64_t *nout, int64_t *capout)
{
    *nout = 0;
    sw_vtx2 w;
    memset(&w, 0, sizeof w);
    w.r = we->r;
    w.z = we->z;
    if (we->r == 0) {
        int64_t id = ring_vertex(c, o, &w, 0);
        if (id < 0)
            return 0;
        if (!mfg_grow((void **)out, capout, 2, sizeof **out))
            return ctx_nomem(c);
        (*out)[0].vid = id;
        (*out)[0].off = 0;
        *nout = 1;
        return 1;
    }
    double plo, span;
    int64_t lo, hi;
    int lo_grid = 0; /* a full ring starting at the grid vertex at angle 0 */
    if (full) {
        sw_vtx2 w0 = w;
        if (we->v2 >= 0 && W->push[we->v2])
            w0.r = w.r / cos(MFG_PI / (double)ring_steps(c, we->r));
        /* the ring starts at angle 0, or at the vertex already there: the other strips
         * on this circle drop the grid vertex at an angle where a line ends (below), and
         * on an outer wall's circle the two are not one point (a 4-edge hole next to the
         * apex of the tetrahedron about its edge) */
        lo = -1;
        int64_t nr = we->v2 >= 0 ? W->ring_start[we->v2 + 1] - W->ring_start[we->v2] : we->ring_n;
        for (int64_t i = 0; i < nr && lo < 0; i++) {
            int64_t vid = we->v2 >= 0 ? W->rvid[W->ring_start[we->v2] + i] : W->evring[we->ring_first + i];
            if (fabs(angle_diff(o->phi[vid], 0)) <= 1e-9)
                lo = vid;
        }
        if (lo < 0) {
            lo = ring_vertex(c, o, &w0, 0);
            lo_grid = 1;
        }
        hi = lo;
        if (lo < 0)
            return 0;
        plo = 0;
        span = MFG_TWO_PI;
    } else {
        lo = we->lo;
        hi = we->hi;
        plo = o->phi[lo];
        span = span_mid + angle_diff(o->phi[hi] - plo, span_mid);
        if (span < 0 || lo == hi)
            span = 0;
        /* one arc whose gap closes at this end (the paper's case 1.3 on a gap-closing
         * curve): its two lines share the vertex, and the arc is the whole circle */
        if (lo == hi && span_mid > MFG_PI)
            span = MFG_TWO_PI;
        if (span > MFG_TWO_PI)
            span = MFG_TWO_PI;
    }
    int64_t nsteps = ring_steps(c, we->r);
    int64_t cand_n = we->v2 >= 0 ? W->ring_start[we->v2 + 1] - W->ring_start[we->v2] : we->ring_n;
    int64_t cap_need = cand_n + nsteps + 4;
    if (!mfg_grow((void **)out, capout, cap_need, sizeof **out))
        return ctx_nomem(c);
    sw_pl *pl = *out;
    int64_t n = 0;
    int pushed = we->v2 >= 0 && W->push[we->v2];
    memset(pl, 0, (size_t)cap_need * sizeof *pl);
    lo_grid = lo_grid && pushed;
    pl[n].vid = lo;
    pl[n].grid = lo_grid;
    pl[n++].off = 0;
    const double dtiny = 1e-9;
    if (span > 0) {
        for (int64_t i = 0; i < cand_n; i++) {
            int64_t vid = we->v2 >= 0 ? W->rvid[W->ring_start[we->v2] + i] : W->evring[we->ring_first + i];
            if (vid == lo || vid == hi)
                continue;
            double off = wrap_angle(o->phi[vid] - plo);
            if (off > 0 && off < span && off < MFG_TWO_PI - 1e-12)
                pl[n].vid = vid, pl[n++].off = off;
        }
        /* grid vertices of an outer wall's circle lie on the circumscribed polygon */
        sw_vtx2 wg = w;
        if (we->v2 >= 0 && W->push[we->v2])
            wg.r = w.r / cos(MFG_PI / (double)nsteps);
        for (int64_t j = 0; j < nsteps; j++) {
            double ang = MFG_TWO_PI * (double)j / (double)nsteps;
            double off = wrap_angle(ang - plo);
            if (off > dtiny && off < span - dtiny) {
                /* a grid angle at an arc end on this circle is that end's vertex (which
                 * every strip here uses): no second vertex at one angle */
                int clash = 0;
                for (int64_t i = 0; i < cand_n && !clash; i++) {
                    int64_t vid = we->v2 >= 0 ? W->rvid[W->ring_start[we->v2] + i]
                                              : W->evring[we->ring_first + i];
                    clash = fabs(angle_diff(o->phi[vid], ang)) <= dtiny;
                }
                if (clash)
                    continue;
                int64_t id = ring_vertex(c, o, &wg, ang);
                if (id < 0)
                    return 0;
                pl[n].vid = id;
                pl[n].grid = pushed;
                pl[n++].off = off;
            }
        }
        pl[n].vid = hi;
        pl[n].grid = lo_grid; /* a full ring ends where it starts */
        pl[n++].off = span;
    } else if (hi != lo) {
        /* two lines meeting (within rounding) at this end: a strip end of no width still
         * has both vertices, which the faces along the lines use */
        pl[n].vid = hi;
        pl[n++].off = 1;
        span = 1;
    }
    qsort(pl, (size_t)n, sizeof *pl, cmp_pl);
    /* drop repeats, normalise */
    int64_t m = 0;
    for (int64_t i = 0; i < n; i++)
        if (m == 0 || pl[i].vid != pl[m - 1].vid)
            pl[m++] = pl[i];
    if (pushed && span > 0 && m > 1) {
        /* An outer wall's circle between two vertices that are not both grid vertices
         * of the circumscribed polygon: an arc end lies on the circle itself, so the
         * chord to its neighbour cuts into SV (an arc shorter than one grid step had
         * only its chord: the box about an edge turned by 1 deg held less than SV).
         * The point where the tangents there meet (at an arc end: the circle's tangent;
         * at a grid vertex: the polygon's side, tangent half a step away) goes in
         * between.  It depends only on the two vertices, which every strip using this
         * stretch of the circle has consecutive, so they all get it. */
        if (!mfg_grow((void **)out, capout, 2 * m + 2, sizeof **out))
            return ctx_nomem(c);
        pl = *out;
        int64_t mm = m;
        double half = MFG_PI / (double)nsteps;
        sw_pl *ins = malloc((size_t)(mm + 1) * sizeof *ins);
        if (!ins)
            return ctx_nomem(c);
        int64_t nins = 0;
        for (int64_t i = 0; i + 1 < mm; i++) {
            if (pl[i].grid && pl[i + 1].grid)
                continue;
            double t0 = pl[i].off + (pl[i].grid ? half : 0);
            double t1 = pl[i + 1].off - (pl[i + 1].grid ? half : 0);
            if (!(t1 - t0 > dtiny))
                continue;
            sw_vtx2 wx = w;
            wx.r = w.r / cos(0.5 * (t1 - t0));
            int64_t id = ring_vertex(c, o, &wx, plo + 0.5 * (t0 + t1));
            if (id < 0) {
                free(ins);
                return 0;
            }
            ins[nins].vid = id;
            ins[nins].off = 0.5 * (t0 + t1);
            ins[nins++].grid = 0;
        }
        for (int64_t i = 0; i < nins; i++)
            pl[m++] = ins[i];
        free(ins);
        qsort(pl, (size_t)m, sizeof *pl, cmp_pl);
        /* a point welded to a neighbour (a circle of a radius near the weld quantum) */
        int64_t m2 = 0;
        for (int64_t i = 0; i < m; i++)
            if (m2 == 0 || pl[i].vid != pl[m2 - 1].vid)
                pl[m2++] = pl[i];
        m = m2;
    }
    for (int64_t i = 0; i < m; i++)
        pl[i].off = span > 0 ? pl[i].off / span : 0;
    if (m > 1)
        pl[m - 1].off = 1;
    *nout = m;
    return 1;
}

static int cmp_ring(const void *pa, const void *pb)
{
    const int64_t *a = pa, *b = pb;
    if (a[0] != b[0])
        return (a[0] > b[0]) - (a[0] < b[0]);
    return (a[1] > b[1]) - (a[1] < b[1]);
}

static int emit_strips(sw_ctx *c, sw_out *o, sw_walls *W)
{
    /* ring entries sorted by 2-D vertex, without repeats */
    int64_t n = W->nring;
    int64_t *pairs = malloc((size_t)(2 * n + 2) * sizeof *pairs);
    W->ring_start = calloc((size_t)(c->nv2 + 2), sizeof *W->ring_start);
    if (!pairs || !W->ring_start) {
        free(pairs);
        return ctx_nomem(c);
    }
    for (int64_t i = 0; i < n; i++) {
        pairs[2 * i] = W->rv2[i];
        pairs[2 * i + 1] = W->rvid[i];
    }
    qsort(pairs, (size_t)n, 2 * sizeof *pairs, cmp_ring);
    int64_t m = 0;
    for (int64_t i = 0; i < n; i++)
        if (m == 0 || pairs[2 * i] != W->rv2[m - 1] || pairs[2 * i + 1] != W->rvid[m - 1]) {
            W->rv2[m] = pairs[2 * i];
            W->rvid[m] = pairs[2 * i + 1];
            m++;
        }
    free(pairs);
    W->nring = m;
    for (int64_t i = 0; i < m; i++)
        W->ring_start[W->rv2[i] + 1]++;
    for (int64_t v = 0; v < c->nv2; v++)
        W->ring_start[v + 1] += W->ring_start[v];
    sw_pl *A = NULL, *B = NULL;
    int64_t na = 0, nb = 0, capa = 0, capb = 0;
    int ok = 1;
    for (int64_t si = 0; si < W->nstrips && ok; si++) {
        const wstrip *S = &W->strips[si];
        ok = end_polyline(c, o, W, &S->e[0], S->full, S->span_mid, &A, &na, &capa) &&
             end_polyline(c, o, W, &S->e[1], S->full, S->span_mid, &B, &nb, &capb);
        if (!ok)
            break;
        if (S->full) {
            /* close the rings: the first vertex again at offset 1 */
            if (na > 1) {
                if (!mfg_grow((void **)&A, &capa, na + 1, sizeof *A)) { ok = ctx_nomem(c); break; }
                A[na] = A[0];
                A[na++].off = 1;
            }
            if (nb > 1) {
                if (!mfg_grow((void **)&B, &capb, nb + 1, sizeof *B)) { ok = ctx_nomem(c); break; }
                B[nb] = B[0];
                B[nb++].off = 1;
            }
        }
        int64_t i = 0, j = 0;
        while (ok && (i + 1 < na || j + 1 < nb)) {
            int adv_a;
            if (i + 1 >= na)
                adv_a = 0;
            else if (j + 1 >= nb)
                adv_a = 1;
            else if (A[i + 1].off != B[j + 1].off)
                adv_a = A[i + 1].off < B[j + 1].off;
            else {
                /* both ends step at one angle: the quad's diagonal through its smallest
                 * vertex, whichever end is A, so that a copy of this strip with the
                 * opposite orientation (a wall met by its own copy) gets the same two
                 * triangles and cancel_twins removes the pair */
                int64_t mn = A[i].vid;
                if (A[i + 1].vid < mn)
                    mn = A[i + 1].vid;
                if (B[j].vid < mn)
                    mn = B[j].vid;
                if (B[j + 1].vid < mn)
                    mn = B[j + 1].vid;
                adv_a = mn == A[i + 1].vid || mn == B[j].vid;
            }
            int64_t t0 = A[i].vid, t1 = B[j].vid, t2 = adv_a ? A[i + 1].vid : B[j + 1].vid;
            /* the circle edge of this triangle and the wall's direction off it */
            int64_t ra = adv_a ? A[i].vid : B[j].vid, rb = t2;
            double dir = adv_a ? atan2(S->e[1].z - S->e[0].z, S->e[1].r - S->e[0].r)
                               : atan2(S->e[0].z - S->e[1].z, S->e[0].r - S->e[1].r);
            /* (A_i, B_j, next) has its normal to the left of u -> v: outward when the right
             * side covers the strip */
            if (S->left_covers)
                ok = emit_tri_ring(c, t0, t2, t1, ra, rb, dir);
            else
                ok = emit_tri_ring(c, t0, t1, t2, ra, rb, dir);
            if (adv_a)
                i++;
            else
                j++;
        }
    }
    free(A);
    free(B);
    return ok;
}

/* The start (entry at t = 0) and end (exit turned by theta) faces over every polygon. */
#define SW_MAXARCS_FACE 64

static int emit_faces(sw_ctx *c, sw_out *o, sw_walls *W)
{
    int64_t *loop = NULL, nloop = 0, caploop = 0;
    int64_t *face = NULL, capface = 0;
    int ok = 1;
    for (int64_t pi = 0; pi < c->npolys && ok; pi++) {
        const sw_poly *P = &c->polys[pi];
        /* The boundary of the polygon with its event points: at each point the start and
         * end vertex of every arc.  A face stops where the gap before it closes (the end
         * of the previous arc turned by theta reaches this arc's start; for a single arc,
         * its own end): the two lines share a vertex there, and the start face and the end
         * face meet in the crease of the paper's case 1.3. */
        int64_t na = P->st.n;
        if (na == 0)
            continue;
        int64_t w = 2 * na;
        nloop = 0;
        for (int64_t i = 0; i < P->n && ok; i++) {
            int64_t w0 = c->poly_verts[P->first + i];
            int64_t ne = -1;
            int64_t at[2 * SW_MAXARCS_FACE];
            if (na > SW_MAXARCS_FACE) {
                ok = 0;
                c->st = mfg_fail(MFG_ERR_INTERNAL, "rotational sweep: more than %d arcs on one circle",
                                 SW_MAXARCS_FACE);
                break;
            }
            for (int64_t l = 0; l < w; l++) {
                hkey key = mkkey(pi, i, l, 0);
                at[l] = hmap_get(&W->evlists, &key);
                int64_t cnt = at[l] >= 0 ? W->evl[at[l]] : 0;
                if (ne < 0 || cnt < ne)
                    ne = cnt;
            }
            if (!mfg_grow((void **)&loop, &caploop, w * (nloop + ne + 1), sizeof *loop)) {
                ok = ctx_nomem(c);
                break;
            }
            for (int64_t l = 0; l < w && ok; l++) {
                const sw_arc *arc = &c->arcs[P->st.first + l / 2];
                const sw_end *en = (l & 1) ? &arc->end : &arc->start;
                int64_t id = lift(c, o, w0, en, (int)(l & 1));
                if (id < 0)
                    ok = 0;
                loop[w * nloop + l] = id;
            }
            nloop++;
            for (int64_t q = 0; q < ne && ok; q++) {
                for (int64_t l = 0; l < w; l++)
                    loop[w * nloop + l] = W->evl[at[l] + 1 + 2 * q];
                nloop++;
            }
        }
        if (!ok)
            break;
        for (int64_t a = 0; a < na && ok; a++) {
            const sw_arc *arc = &c->arcs[P->st.first + a];
            const sw_arc *prev = &c->arcs[P->st.first + (a + na - 1) % na];
            const sw_arc *next = &c->arcs[P->st.first + (a + 1) % na];
            int64_t ap = (a + na - 1) % na, an = (a + 1) % na;
            /* gaps at the sample: before this arc, and after it */
            double g_before = wrap_angle(arc->start.phi - (prev->end.phi + c->theta));
            double g_after = wrap_angle(next->start.phi - (arc->end.phi + c->theta));
            if (na == 1) {
                g_before = g_after = MFG_TWO_PI - (arc->end.phi + c->theta - arc->start.phi);
            }
            for (int e = 0; e < 2 && ok; e++) {
                int64_t m = 0;
                if (!mfg_grow((void **)&face, &capface, nloop + 1, sizeof *face)) {
                    ok = ctx_nomem(c);
                    break;
                }
                for (int64_t i = 0; i < nloop; i++) {
                    const int64_t *L = loop + w * i;
                    int64_t mine = L[2 * a + e];
                    /* the other line of the gap next to this face */
                    int64_t other = e == 0 ? L[2 * ap + 1] : L[2 * an];
                    double g0 = e == 0 ? g_before : g_after;
                    double raw = e == 0 ? o->phi[mine] - o->phi[other] : o->phi[other] - o->phi[mine];
                    double gap = g0 + angle_diff(raw, g0);
                    if (!(gap > 0 || mine == other))
                        continue;
                    if (m == 0 || face[m - 1] != mine)
                        face[m++] = mine;
                }
                while (m > 1 && face[m - 1] == face[0])
                    m--;
                int64_t ft = e == 0 ? arc->start.tri : arc->end.tri;
                for (int64_t i = 1; i + 1 < m && ok; i++) {
                    if (e == 0)
                        ok = emit_tri(c, face[0], face[i], face[i + 1], ft, e);
                    else
                        ok = emit_tri(c, face[0], face[i + 1], face[i], ft, e);
                }
            }
        }
    }
    free(face);
    free(loop);
    return ok;
}

/* ----------------------------------------------------------------------------------- */
/* Pinches                                                                              */
/* ----------------------------------------------------------------------------------- */

typedef struct sw_he {
    int64_t lo, hi; /* undirected edge */
    int64_t tri;    /* triangle using it */
    int dir;        /* +1: lo -> hi in the triangle, -1: hi -> lo */
    double ang;     /* angle of the triangle's third corner round the edge */
} sw_he;

static int cmp_he(const void *pa, const void *pb)
{
    const sw_he *a = pa, *b = pb;
    if (a->lo != b->lo)
        return (a->lo > b->lo) - (a->lo < b->lo);
    if (a->hi != b->hi)
        return (a->hi > b->hi) - (a->hi < b->hi);
    return (a->ang > b->ang) - (a->ang < b->ang);
}

/* Joins the corners at the edge's two ends of triangles h and g (paired across it). */
static void join_across(const sw_ctx *c, const sw_he *h, const sw_he *g, int64_t *parent)
{
    int64_t t1 = h->tri / 3, t2 = g->tri / 3;
    for (int k = 0; k < 3; k++)
        for (int m = 0; m < 3; m++) {
            int64_t v1 = c->otri[3 * t1 + k], v2 = c->otri[3 * t2 + m];
            if (v1 == v2 && (v1 == h->lo || v1 == h->hi))
                mfg_uf_union(parent, 3 * t1 + k, 3 * t2 + m);
        }
}

/* Do the n triangles round an edge (sorted by angle) alternate in direction? */
static int alternates(const sw_he *e, int64_t n)
{
    if (n % 2)
        return 0;
    for (int64_t q = 0; q < n; q++)
        if (e[q].dir == e[(q + 1) % n].dir)
            return 0;
    return 1;
}

/* Where the directions round an edge do not alternate (rounding swapped two nearly
 * coincident pieces), the triangles are read in decreasing angle as a cyclic bracket
 * sequence (+1 opens, -1 closes) and each +1 is paired with its matching -1: every
 * triangle gets a partner, where pairing with the next one round would leave some
 * unpaired and the edge open once the vertices are split.  An edge with unequal counts
 * of the two directions is left as it is (the closedness check reports it). */
static int pair_round_edge(sw_ctx *c, const sw_he *e, int64_t n, int64_t *parent,
                           int64_t **stack, int64_t *capstack)
{
    int64_t sum = 0, low = 0, start = 0;
    for (int64_t k = 0; k < n; k++) {
        sum += e[n - 1 - k].dir;
        if (sum < low) {
            low = sum;
            start = k + 1;
        }
    }
    if (sum != 0)
        return 1;
    if (!mfg_grow((void **)stack, capstack, n, sizeof **stack))
        return ctx_nomem(c);
    int64_t depth = 0;
    for (int64_t k = 0; k < n; k++) {
        int64_t idx = n - 1 - (start + k) % n;
        if (e[idx].dir == 1)
            (*stack)[depth++] = idx;
        else if (depth > 0)
            join_across(c, &e[(*stack)[--depth]], &e[idx], parent);
    }
    return 1;
}

/*
 * The boundary of a union of prisms may touch itself: where two covered regions meet
 * across a corner of the decomposition, four pieces share an arc (a pinch), and a vertex
 * may join two separate fans.  Each such edge is resolved by pairing its triangles round
 * it (each with the next one of the opposite direction), and each vertex gets one copy per
 * fan of triangles joined through paired edges: the surface stays closed and becomes a
 * 2-manifold that touches itself there, as the true boundary does.
 */
static int resolve_pinches(sw_ctx *c, sw_out *o)
{
    int64_t nt = c->notri, ne = 3 * nt;
    sw_he *he = malloc((size_t)(ne + 1) * sizeof *he);
    int64_t *parent = malloc((size_t)(ne + 1) * sizeof *parent);
    if (!he || !parent) {
        free(he);
        free(parent);
        return ctx_nomem(c);
    }
    for (int64_t t = 0; t < nt; t++)
        for (int k = 0; k < 3; k++) {
            int64_t a = c->otri[3 * t + k], b = c->otri[3 * t + (k + 1) % 3];
            int64_t d = c->otri[3 * t + (k + 2) % 3];
            sw_he *h = &he[3 * t + k];
            h->lo = a < b ? a : b;
            h->hi = a < b ? b : a;
            h->tri = 3 * t + k;
            h->dir = a < b ? 1 : -1;
            /* angle of corner d round the axis lo -> hi */
            const double *P = c->ox + 3 * h->lo, *Q = c->ox + 3 * h->hi, *D = c->ox + 3 * d;
            double ax[3] = {Q[0] - P[0], Q[1] - P[1], Q[2] - P[2]};
            double w[3] = {D[0] - P[0], D[1] - P[1], D[2] - P[2]};
            double l2 = ax[0] * ax[0] + ax[1] * ax[1] + ax[2] * ax[2];
            double pr = l2 > 0 ? (w[0] * ax[0] + w[1] * ax[1] + w[2] * ax[2]) / l2 : 0;
            double u[3] = {w[0] - pr * ax[0], w[1] - pr * ax[1], w[2] - pr * ax[2]};
            /* a fixed frame perpendicular to the edge */
            double ref[3] = {1, 0, 0};
            if (fabs(ax[0]) > fabs(ax[1]) && fabs(ax[0]) > fabs(ax[2]))
                ref[0] = 0, ref[1] = 1;
            double e1[3] = {ax[1] * ref[2] - ax[2] * ref[1], ax[2] * ref[0] - ax[0] * ref[2],
                            ax[0] * ref[1] - ax[1] * ref[0]};
            double e2[3] = {ax[1] * e1[2] - ax[2] * e1[1], ax[2] * e1[0] - ax[0] * e1[2],
                            ax[0] * e1[1] - ax[1] * e1[0]};
            h->ang = atan2(u[0] * e2[0] + u[1] * e2[1] + u[2] * e2[2],
                           u[0] * e1[0] + u[1] * e1[1] + u[2] * e1[2]);
            /* an edge along a circle (a chord between two ring vertices): the pieces leave
             * it in the directions of their 2-D edges, which the circle's own sag would
             * hide; measure the third corner's direction in the meridian plane */
            double rp = v_r(P[0], P[1]), rq = v_r(Q[0], Q[1]);
            int64_t r0 = c->oring[2 * t], r1 = c->oring[2 * t + 1];
            if ((r0 == a && r1 == b) || (r0 == b && r1 == a)) {
                double dr = cos(c->odir[t]), dz = sin(c->odir[t]);
                (void)rp;
                (void)rq;
                double turn = angle_diff(atan2(Q[1], Q[0]), atan2(P[1], P[0]));
                h->ang = turn > 0 ? atan2(dr, dz) : atan2(dz, dr);
            }
        }
    for (int64_t i = 0; i < ne; i++)
        parent[i] = i;
    if (!sw_report(c, 0.84)) {
        free(he);
        free(parent);
        return 0;
    }
    qsort(he, (size_t)ne, sizeof *he, cmp_he);
    if (!sw_report(c, 0.88)) {
        free(he);
        free(parent);
        return 0;
    }
    int64_t *stack = NULL, capstack = 0;
    /* corners: 3t + k is the corner at otri[3t + k] */
    for (int64_t i = 0; i < ne;) {
        int64_t j = i;
        while (j < ne && he[j].lo == he[i].lo && he[j].hi == he[i].hi)
            j++;
        int64_t n = j - i;
        /* pair each triangle with the next one round the edge of the other direction
         * (going round in decreasing angle): where the directions alternate, each pair
         * bounds a consistently oriented wedge */
        if (n >= 2 && alternates(he + i, n)) {
            for (int64_t q = 0; q < n; q++)
                if (he[i + q].dir == 1)
                    join_across(c, &he[i + q], &he[i + (q + n - 1) % n], parent);
        } else if (n >= 2 && !pair_round_edge(c, he + i, n, parent, &stack, &capstack)) {
            free(he);
            free(parent);
            free(stack);
            return 0;
        }
        i = j;
    }
    if (!sw_report(c, 0.92)) {
        free(he);
        free(parent);
        free(stack);
        return 0;
    }
    /* one vertex per class of corners */
    hmap seen;
    if (!hmap_init(&seen, ne + 16)) {
        free(he);
        free(parent);
        return ctx_nomem(c);
    }
    int ok = 1;
    for (int64_t cr = 0; cr < ne && ok; cr++) {
        if ((cr & 63) == 0 && !sw_poll(c, 0.92 * ne + 0.08 * cr, ne)) {
            ok = 0;
            break;
        }
        int64_t root = mfg_uf_find(parent, cr);
        int64_t v = c->otri[cr];
        hkey k = mkkey(root, 0, 0, 0);
        int64_t nv = hmap_get(&seen, &k);
        if (nv < 0) {
            /* the first class of a vertex keeps it; later ones get a copy */
            hkey kv = mkkey(-1 - v, 0, 0, 0);
            if (hmap_get(&seen, &kv) < 0) {
                nv = v;
                ok = hmap_put(&seen, &kv, 1);
            } else {
                if (!mfg_grow((void **)&c->ox, &c->capout, c->nout + 1, 3 * sizeof *c->ox) ||
                    !mfg_grow((void **)&o->phi, &o->capphi, c->nout + 1, sizeof *o->phi)) {
                    ok = ctx_nomem(c);
                    break;
                }
                memcpy(c->ox + 3 * c->nout, c->ox + 3 * v, 3 * sizeof *c->ox);
                o->phi[c->nout] = o->phi[v];
                nv = c->nout++;
            }
            ok = ok && hmap_put(&seen, &k, nv);
        }
        c->otri[cr] = nv;
    }
    if (!ok)
        ctx_nomem(c); /* keeps a cancel's status: ctx_nomem sets only an empty one */
    hmap_free(&seen);
    free(he);
    free(parent);
    free(stack);
    return ok;
}

/* Six times the signed volume of the tetrahedron (origin, a, b, d): a triangle's share of
 * the volume its closed surface encloses (divergence theorem about the origin). */
static double tet_volume6(const double *a, const double *b, const double *d)
{
    return a[0] * (b[1] * d[2] - b[2] * d[1]) - a[1] * (b[0] * d[2] - b[2] * d[0]) +
           a[2] * (b[0] * d[1] - b[1] * d[0]);
}

/* The volume enclosed by triangles tris (n of them) over the points xyz (about the
 * origin; local coordinates keep the numbers small). */
static double mesh_volume(const double *xyz, const int64_t *tris, int64_t n)
{
    double vol = 0;
    for (int64_t t = 0; t < n; t++)
        vol += tet_volume6(xyz + 3 * tris[3 * t], xyz + 3 * tris[3 * t + 1], xyz + 3 * tris[3 * t + 2]);
    return vol / 6;
}

/* Parity of the ray from p along dir through the triangles of component comp (tcomp per
 * triangle): 1 inside, 0 outside, -1 when the ray grazes an edge or vertex (undecided). */
static int ray_parity(const sw_ctx *c, const int64_t *tcomp, int64_t comp, const double *p,
                      const double *dir)
{
    int inside = 0;
    for (int64_t t = 0; t < c->notri; t++) {
        if (tcomp[t] != comp)
            continue;
        const double *a = c->ox + 3 * c->otri[3 * t], *b = c->ox + 3 * c->otri[3 * t + 1],
                     *d = c->ox + 3 * c->otri[3 * t + 2];
        double e1[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
        double e2[3] = {d[0] - a[0], d[1] - a[1], d[2] - a[2]};
        double q[3] = {dir[1] * e2[2] - dir[2] * e2[1], dir[2] * e2[0] - dir[0] * e2[2],
                       dir[0] * e2[1] - dir[1] * e2[0]};
        double det = e1[0] * q[0] + e1[1] * q[1] + e1[2] * q[2];
        if (det == 0)
            continue;
        double w[3] = {p[0] - a[0], p[1] - a[1], p[2] - a[2]};
        double u = (w[0] * q[0] + w[1] * q[1] + w[2] * q[2]) / det;
        double rr[3] = {w[1] * e1[2] - w[2] * e1[1], w[2] * e1[0] - w[0] * e1[2], w[0] * e1[1] - w[1] * e1[0]};
        double v = (dir[0] * rr[0] + dir[1] * rr[1] + dir[2] * rr[2]) / det;
        double tt = (e2[0] * rr[0] + e2[1] * rr[1] + e2[2] * rr[2]) / det;
        const double g = 1e-9;
        if (u < -g || v < -g || u + v > 1 + g || tt < -g)
            continue;
        if (u < g || v < g || u + v > 1 - g || tt < g)
            return -1;
        inside ^= 1;
    }
    return inside;
}

/*
 * A shell of the result lying wholly inside another (two walls of a sliver left inside the
 * solid where pieces of the decomposition did not cancel) bounds nothing the union does
 * not already hold, but it is no part of the boundary: such shells are dropped.  A shell
 * is dropped only when every one of its sampled vertices is inside the other shell by two
 * rays that do not graze it.  A shell with some vertex inside another and some not
 * crosses it: *overlap is set, and the caller treats the result as it treats an open one.
 */
static int drop_nested_shells(sw_ctx *c, int *overlap)
{
    *overlap = 0;
    int64_t nt = c->notri, nv = c->nout;
    int64_t *parent = malloc((size_t)(nv + 1) * sizeof *parent);
    int64_t *tcomp = malloc((size_t)(nt + 1) * sizeof *tcomp);
    if (!parent || !tcomp) {
        free(parent);
        free(tcomp);
        return ctx_nomem(c);
    }
    for (int64_t i = 0; i < nv; i++)
        parent[i] = i;
    for (int64_t t = 0; t < nt; t++) {
        mfg_uf_union(parent, c->otri[3 * t], c->otri[3 * t + 1]);
        mfg_uf_union(parent, c->otri[3 * t], c->otri[3 * t + 2]);
    }
    /* components: roots, their volumes */
    int64_t ncomp = 0, *roots = NULL, capr = 0;
    double *vol = NULL, *box = NULL;
    int64_t capv = 0, capb = 0, *count = NULL, capn = 0;
    int ok = 1;
    for (int64_t t = 0; t < nt && ok; t++) {
        int64_t r = mfg_uf_find(parent, c->otri[3 * t]);
        int64_t k = 0;
        while (k < ncomp && roots[k] != r)
            k++;
        if (k == ncomp) {
            if (ncomp >= 64) { /* many shells: leave them (the search below is quadratic) */
                ncomp = 0;
                break;
            }
            if (!mfg_grow((void **)&roots, &capr, ncomp + 1, sizeof *roots) ||
                !mfg_grow((void **)&vol, &capv, ncomp + 1, sizeof *vol) ||
                !mfg_grow((void **)&count, &capn, ncomp + 1, sizeof *count) ||
                !mfg_grow((void **)&box, &capb, 6 * (ncomp + 1), sizeof *box)) {
                ok = ctx_nomem(c);
                break;
            }
            roots[ncomp] = r;
            vol[ncomp] = 0;
            count[ncomp] = 0;
            for (int e = 0; e < 3; e++) {
                box[6 * ncomp + e] = INFINITY;
                box[6 * ncomp + 3 + e] = -INFINITY;
            }
            ncomp++;
        }
        tcomp[t] = k;
        count[k]++;
        const double *a = c->ox + 3 * c->otri[3 * t], *b = c->ox + 3 * c->otri[3 * t + 1],
                     *d = c->ox + 3 * c->otri[3 * t + 2];
        vol[k] += tet_volume6(a, b, d);
        for (int q = 0; q < 3; q++)
            for (int e = 0; e < 3; e++) {
                double x = c->ox[3 * c->otri[3 * t + q] + e];
                box[6 * k + e] = fmin(box[6 * k + e], x);
                box[6 * k + 3 + e] = fmax(box[6 * k + 3 + e], x);
            }
    }
    char *drop = ok && ncomp > 1 ? calloc((size_t)ncomp, 1) : NULL;
    if (ok && ncomp > 1 && !drop)
        ok = ctx_nomem(c);
    static const double rays[2][3] = {{0.5377, 0.3141, 0.7826}, {-0.2718, 0.8660, -0.4192}};
    for (int64_t k = 0; ok && drop && k < ncomp; k++) {
        if (!(vol[k] > 0))
            continue;
        for (int64_t j = 0; j < ncomp && !drop[k]; j++) {
            if (j == k || drop[j] || !(vol[j] > vol[k]))
                continue;
            /* up to 16 vertices of shell k, spread over its triangles: all inside j? */
            int all_in = 1, tested = 0, some_in = 0;
            const double *bj = box + 6 * j;
            int64_t stride = count[k] / 16 + 1, seen = 0;
            for (int64_t t = 0; t < nt && all_in; t++) {
                if (tcomp[t] != k || seen++ % stride)
                    continue;
                const double *p = c->ox + 3 * c->otri[3 * t];
                if (ray_parity(c, tcomp, j, p, rays[0]) != 1 || ray_parity(c, tcomp, j, p, rays[1]) != 1)
                    all_in = 0;
                tested++;
            }
            if (all_in && tested > 0) {
                drop[k] = 1;
                continue;
            }
            /* else: does shell k reach into j?  Its vertices in j's box, up to 256 */
            int64_t nin = 0;
            for (int64_t t = 0; t < nt; t++) {
                if (tcomp[t] != k)
                    continue;
                const double *p = c->ox + 3 * c->otri[3 * t];
                nin += p[0] > bj[0] && p[1] > bj[1] && p[2] > bj[2] && p[0] < bj[3] &&
                       p[1] < bj[4] && p[2] < bj[5];
            }
            stride = nin / 256 + 1;
            seen = 0;
            for (int64_t t = 0; t < nt && !some_in; t++) {
                if (tcomp[t] != k)
                    continue;
                const double *p = c->ox + 3 * c->otri[3 * t];
                if (!(p[0] > bj[0] && p[1] > bj[1] && p[2] > bj[2] && p[0] < bj[3] &&
                      p[1] < bj[4] && p[2] < bj[5]) || seen++ % stride)
                    continue;
                some_in = ray_parity(c, tcomp, j, p, rays[0]) == 1 &&
                          ray_parity(c, tcomp, j, p, rays[1]) == 1;
            }
            if (some_in)
                *overlap = 1; /* two shells crossing: the union's boundary is neither */
        }
    }
    if (ok && drop) {
        int64_t m = 0;
        for (int64_t t = 0; t < nt; t++) {
            if (drop[tcomp[t]])
                continue;
            for (int q = 0; q < 3; q++)
                c->otri[3 * m + q] = c->otri[3 * t + q];
            c->oring[2 * m] = c->oring[2 * t];
            c->oring[2 * m + 1] = c->oring[2 * t + 1];
            c->odir[m] = c->odir[t];
            c->oface[m] = c->oface[t];
            m++;
        }
        c->notri = m;
    }
    free(drop);
    free(roots);
    free(vol);
    free(count);
    free(box);
    free(parent);
    free(tcomp);
    return ok;
}

/* Two copies of one triangle with opposite orientations (a strip of no width laid on a
 * face, a face met by its own copy) bound nothing: both go. */
/* Height of corner m over the line through p and q, and whether m projects strictly
 * between them. */
static double corner_height(const double *p, const double *q, const double *m, int *between)
{
    double d[3], e[3];
    for (int k = 0; k < 3; k++) {
        d[k] = q[k] - p[k];
        e[k] = m[k] - p[k];
    }
    double dd = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
    double de = d[0] * e[0] + d[1] * e[1] + d[2] * e[2];
    double x[3] = {d[1] * e[2] - d[2] * e[1], d[2] * e[0] - d[0] * e[2], d[0] * e[1] - d[1] * e[0]};
    *between = dd > 0 && de > 0 && de < dd;
    return dd > 0 ? sqrt((x[0] * x[0] + x[1] * x[1] + x[2] * x[2]) / dd) : INFINITY;
}

/* The height of triangle (a, b, d) over its longest side; *side (optional) gets that
 * side's index k (from corner k to k + 1), *between whether the opposite corner projects
 * strictly between its ends. */
static double tri_flatness(const double *a, const double *b, const double *d, int *side,
                           int *between)
{
    const double *v[3] = {a, b, d};
    double best = -1;
    int kl = 0;
    for (int k = 0; k < 3; k++) {
        const double *p = v[k], *q = v[(k + 1) % 3];
        double l = (q[0] - p[0]) * (q[0] - p[0]) + (q[1] - p[1]) * (q[1] - p[1]) +
                   (q[2] - p[2]) * (q[2] - p[2]);
        if (l > best)
            best = l, kl = k;
    }
    int btw;
    double h = corner_height(v[kl], v[(kl + 1) % 3], v[(kl + 2) % 3], &btw);
    if (side)
        *side = kl;
    if (between)
        *between = btw;
    return h;
}

/* Slivers flipped away.  Where a wall's strip or a face's fan has three corners on one
 * line (a ruling of a cylinder cut at a vertex of the neighbouring strip, a face's
 * collinear corners), the triangle has no area; OCCT's sewing and solid check (the
 * Solid representation) take its corners for a self-intersecting wire, and the bench
 * arm came out with 64 such triangles.  A triangle (p, q, m) whose corner m lies within
 * 2^-30 of the part's size of its longest side p q, between p and q, is replaced with
 * its neighbour (q, p, d) across that side by (q, m, d) and (m, p, d): the neighbour
 * split at m, the same surface up to that height.  Skipped when the edge m d exists
 * already (the mesh would stop being a 2-manifold) or a new triangle would be a sliver
 * too; the mesh stays closed and oriented either way. */
static int flip_out_slivers(sw_ctx *c)
{
    double eps = ldexp(c->ext, -30);
    hmap he;
    if (!hmap_init(&he, 3 * c->notri))
        return ctx_nomem(c);
    int ok = 1;
    /* directed edge (a, b) -> triangle + 1 (0: gone) */
    for (int64_t t = 0; t < c->notri && ok; t++)
        for (int k = 0; k < 3 && ok; k++) {
            hkey key = mkkey(c->otri[3 * t + k], c->otri[3 * t + (k + 1) % 3], 0, 0);
            ok = hmap_put(&he, &key, t + 1);
        }
    /* a run of collinear corners (a ruling cut at several vertices) is a chain of
     * slivers, each the neighbour of the next across its longest side: the outermost
     * flips first, the next one on the following pass */
    int64_t flipped = 1;
    for (int pass = 0; pass < 16 && flipped && ok; pass++) {
        flipped = 0;
        for (int64_t t = 0; t < c->notri && ok; t++) {
            int64_t *T = c->otri + 3 * t;
            /* the longest side p -> q, m opposite */
            int kl, between;
            double h = tri_flatness(c->ox + 3 * T[0], c->ox + 3 * T[1], c->ox + 3 * T[2], &kl,
                                    &between);
            if (!(h <= eps) || !between)
                continue;
            int64_t p = T[kl], q = T[(kl + 1) % 3], mm = T[(kl + 2) % 3];
            hkey kqp = mkkey(q, p, 0, 0);
            int64_t t2 = hmap_get(&he, &kqp) - 1;
            if (t2 < 0 || t2 == t)
                continue;
            int64_t *U = c->otri + 3 * t2;
            int64_t d = -1;
            for (int k = 0; k < 3; k++)
                if (U[k] != p && U[k] != q)
                    d = U[k];
            hkey kmd = mkkey(mm, d, 0, 0), kdm = mkkey(d, mm, 0, 0);
            if (d < 0 || d == mm || hmap_get(&he, &kmd) > 0 || hmap_get(&he, &kdm) > 0)
                continue;
            const double *X = c->ox;
            if (!(tri_flatness(X + 3 * q, X + 3 * mm, X + 3 * d, NULL, NULL) > eps) ||
                !(tri_flatness(X + 3 * mm, X + 3 * p, X + 3 * d, NULL, NULL) > eps))
                continue;
            T[0] = q, T[1] = mm, T[2] = d;
            U[0] = mm, U[1] = p, U[2] = d;
            hkey gone[2] = {mkkey(p, q, 0, 0), kqp};
            hkey toT[3] = {mkkey(q, mm, 0, 0), kmd, mkkey(d, q, 0, 0)};
            hkey toU[3] = {mkkey(mm, p, 0, 0), mkkey(p, d, 0, 0), kdm};
            for (int k = 0; k < 2 && ok; k++)
                ok = hmap_put(&he, &gone[k], 0);
            for (int k = 0; k < 3 && ok; k++)
                ok = hmap_put(&he, &toT[k], t + 1) && hmap_put(&he, &toU[k], t2 + 1);
            flipped++;
        }
    }
    hmap_free(&he);
    return ok ? 1 : ctx_nomem(c);
}

static int cancel_twins(sw_ctx *c)
{
    hmap m;
    if (!hmap_init(&m, c->notri + 16))
        return ctx_nomem(c);
    char *dead = calloc((size_t)(c->notri + 1), 1);
    if (!dead) {
        hmap_free(&m);
        return ctx_nomem(c);
    }
    int ok = 1;
    for (int64_t t = 0; t < c->notri && ok; t++) {
        int64_t *v = c->otri + 3 * t;
        /* rotate so the smallest index is first: (a, b, c) keeps its orientation */
        int r = v[0] < v[1] ? (v[0] < v[2] ? 0 : 2) : (v[1] < v[2] ? 1 : 2);
        int64_t a = v[r], b = v[(r + 1) % 3], d = v[(r + 2) % 3];
        hkey twin = mkkey(a, d, b, 0);
        int64_t o = hmap_get(&m, &twin);
        if (o >= 0 && o < c->notri && !dead[o]) {
            dead[o] = dead[t] = 1;
            hkey gone = twin;
            ok = hmap_put(&m, &gone, c->notri); /* past every triangle: the slot is used up */
            continue;
        }
        hkey mine = mkkey(a, b, d, 0);
        if (hmap_get(&m, &mine) < 0)
            ok = hmap_put(&m, &mine, t);
    }
    if (ok) {
        int64_t n = 0;
        for (int64_t t = 0; t < c->notri; t++)
            if (!dead[t]) {
                memmove(c->otri + 3 * n, c->otri + 3 * t, 3 * sizeof *c->otri);
                c->oring[2 * n] = c->oring[2 * t];
                c->oring[2 * n + 1] = c->oring[2 * t + 1];
                c->odir[n] = c->odir[t];
                c->oface[n] = c->oface[t];
                n++;
            }
        c->notri = n;
    } else {
        ctx_nomem(c);
    }
    free(dead);
    hmap_free(&m);
    return ok;
}

/* The face pieces of one input plane (an input face: edge-adjacent triangles in one plane,
 * at the start or turned by theta), and the walls in one plane z = const (the annuli
 * swept by faces perpendicular to the axis: every corner at that height), merged
 * back into one triangulated region each: the decomposition cuts every face into one
 * piece per cell, which only adds inner vertices (planar_merge.c).  Where the merged
 * surface would not pass the closed-manifold check, the pieces are kept.  oring, odir and
 * oface no longer describe the triangles after it. */
static int merge_faces(sw_ctx *c)
{
    int64_t *root = malloc((size_t)(c->nt + 1) * sizeof *root);
    int64_t *group = malloc((size_t)(c->notri + 1) * sizeof *group);
    int64_t *keep = malloc((size_t)(3 * c->notri + 1) * sizeof *keep);
    hmap zs;
    memset(&zs, 0, sizeof zs);
    if (!root || !group || !keep || !hmap_init(&zs, 64)) {
        free(root);
        free(group);
        free(keep);
        hmap_free(&zs);
        return ctx_nomem(c);
    }
    for (int64_t t = 0; t < c->nt; t++)
        root[t] = t;
    /* neighbours across an edge (a curve with two triangles) in one plane: the fourth
     * vertex on the first one's plane up to rounding, the normals the same way */
    for (int64_t i = 0; i < c->ncurves; i++) {
        const sw_curve *cv = &c->curves[i];
        if (cv->tri[1] < 0)
            continue;
        const sw_tri *A = &c->tris[cv->tri[0]], *B = &c->tris[cv->tri[1]];
        double na = sqrt(A->n[0] * A->n[0] + A->n[1] * A->n[1] + A->n[2] * A->n[2]);
        if (!(na > 0) || A->n[0] * B->n[0] + A->n[1] * B->n[1] + A->n[2] * B->n[2] <= 0)
            continue;
        int flat = 1;
        for (int k = 0; k < 3; k++) {
            const double *p = c->lx + 3 * B->v[k];
            if (fabs(A->n[0] * p[0] + A->n[1] * p[1] + A->n[2] * p[2] - A->d) > 1e-12 * c->ext * na)
                flat = 0;
        }
        if (!flat)
            continue;
        int64_t a = cv->tri[0], b = cv->tri[1];
        while (root[a] != a)
            a = root[a] = root[root[a]];
        while (root[b] != b)
            b = root[b] = root[root[b]];
        if (a != b)
            root[a < b ? b : a] = a < b ? a : b;
    }
    int ok = 1;
    for (int64_t t = 0; t < c->notri && ok; t++) {
        const int64_t *tv = c->otri + 3 * t;
        double z = c->ox[3 * tv[0] + 2];
        if (c->oface[t] < 0 && c->ox[3 * tv[1] + 2] == z && c->ox[3 * tv[2] + 2] == z) {
            hkey k = mkkey(dbits(z), 0, 0, 0);
            int64_t id = hmap_get(&zs, &k);
            if (id < 0) {
                id = 2 * c->nt + zs.n;
                ok = hmap_put(&zs, &k, id);
            }
            group[t] = id;
            continue;
        }
        int64_t f = c->oface[t];
        if (f < 0) {
            group[t] = -1;
            continue;
        }
        int64_t r = f / 2;
        while (root[r] != r)
            r = root[r];
        group[t] = 2 * r + (f & 1);
    }
    memcpy(keep, c->otri, (size_t)(3 * c->notri) * sizeof *keep);
    int64_t nkeep = c->notri;
    if (ok)
        ok = mfg_merge_planar_groups(c->ox, c->nout, c->otri, &c->notri, group, NULL);
    if (!ok) {
        ctx_nomem(c);
    } else if (c->notri != nkeep) {
        mfg_mesh_report rep;
        mfg_status cs = mfg_mesh_check_closed(c->ox, c->nout, c->otri, c->notri, &rep);
        if (cs == MFG_ERR_NOMEM)
            ok = ctx_nomem(c);
        if (cs != MFG_OK) {
            memcpy(c->otri, keep, (size_t)(3 * nkeep) * sizeof *keep);
            c->notri = nkeep;
        }
    }
    free(root);
    free(group);
    free(keep);
    hmap_free(&zs);
    return ok;
}

static int build_walls(sw_ctx *c, sw_out *o)
{
    sw_walls W;
    memset(&W, 0, sizeof W);
    hmap edges;
    if (!hmap_init(&W.evlists, 1024) || !hmap_init(&edges, c->npv + 64)) {
        hmap_free(&W.evlists);
        return ctx_nomem(c);
    }
    int ok = 1;
    W.push = calloc((size_t)(c->nv2 + 1), 1);
    W.cappush = c->nv2 + 1;
    if (!W.push)
        ok = ctx_nomem(c);
    for (int64_t pi = 0; pi < c->npolys && ok; pi++) {
        const sw_poly *P = &c->polys[pi];
        for (int64_t i = 0; i < P->n && ok; i++) {
            int64_t a = c->poly_verts[P->first + i], b = c->poly_verts[P->first + (i + 1) % P->n];
            hkey k = mkkey(a, b, 0, 0);
            if (!hmap_put(&edges, &k, pi * ((int64_t)1 << 24) + i))
                ok = ctx_nomem(c);
        }
    }
    for (int64_t pi = 0; pi < c->npolys && ok; pi++) {
        if (!sw_poll(c, (double)pi, (double)c->npolys)) {
            ok = 0;
            break;
        }
        const sw_poly *P = &c->polys[pi];
        for (int64_t i = 0; i < P->n && ok; i++) {
            int64_t a = c->poly_verts[P->first + i], b = c->poly_verts[P->first + (i + 1) % P->n];
            if (a == b)
                continue;
            hkey k = mkkey(b, a, 0, 0);
            int64_t tw = hmap_get(&edges, &k);
            int64_t Q = tw >= 0 ? tw / ((int64_t)1 << 24) : -1, iq = tw >= 0 ? tw % ((int64_t)1 << 24) : -1;
            if (Q >= 0 && Q < pi)
                continue; /* done from Q's side */
            ok = edge_walls(c, o, &W, a, b, pi, i, Q, iq);
        }
    }
    hmap_free(&edges);
    if (ok)
        ok = sw_report(c, 0.4) && emit_strips(c, o, &W) && sw_report(c, 0.55) &&
             emit_faces(c, o, &W);
    free(W.strips);
    free(W.rv2);
    free(W.rvid);
    free(W.ring_start);
    free(W.evring);
    free(W.evl);
    free(W.push);
    hmap_free(&W.evlists);
    return ok;
}

/* ----------------------------------------------------------------------------------- */
/* Entry point                                                                          */
/* ----------------------------------------------------------------------------------- */

/* Frees what one placement of the decomposition built (leaves, 2-D vertices, polygons,
 * output) and leaves those fields empty, for ctx_free and for a rebuild. */
static void free_decomposition(sw_ctx *c)
{
    free(c->leaves);
    free(c->leaf_curves);
    hmap_free(&c->corners);
    hmap_free(&c->leafmap);
    free(c->v2);
    hmap_free(&c->v2map);
    free(c->poly_verts);
    free(c->polys);
    free(c->ox);
    hmap_free(&c->outmap);
    free(c->otri);
    free(c->oring);
    free(c->odir);
    free(c->oface);
    c->leaves = NULL; c->nleaves = c->capleaves = 0;
    c->leaf_curves = NULL; c->nleaf_curves = c->capleaf_curves = 0;
    c->v2 = NULL; c->nv2 = c->capv2 = 0;
    c->poly_verts = NULL; c->npv = c->cappv = 0;
    c->polys = NULL; c->npolys = c->cappolys = 0;
    c->ox = NULL; c->nout = c->capout = 0;
    c->otri = NULL; c->notri = c->capotri = 0;
    c->oring = NULL;
    c->odir = NULL;
    c->oface = NULL;
    c->caporing = c->capodir = c->capoface = 0;
}

static void ctx_free(sw_ctx *c)
{
    hmap_free(&c->refine);
    free(c->lx);
    free(c->vr);
    free(c->tris);
    free(c->tcurves);
    free(c->gstart);
    free(c->gcurves);
    free(c->cstamp);
    free(c->vstamp);
    free(c->hstamp);
    free(c->curves);
    free(c->bin_start);
    free(c->bin_items);
    free(c->stamp);
    free(c->cand);
    free(c->xphi);
    free(c->xtri);
    free(c->xentry);
    free(c->arcs);
    free(c->xpool);
    free_decomposition(c);
}

/* Drops everything built by one placement of the decomposition (the solid, its curves
 * and bins stay). */
static void reset_attempt(sw_ctx *c, sw_out *o)
{
    free_decomposition(c);
    free(o->phi);
    hmap_free(&o->lifts);
    o->phi = NULL;
    o->capphi = 0;
    c->narcs = 0;
    c->nxpool = 0;
}

/* Arguments other than the mesh (which mfg_mesh_require_closed checks). */
static mfg_status check_sweep_args(const double *axis_point, const double *axis_dir,
                                   double angle, double tolerance, mfg_mesh **out_mesh)
{
    if (!axis_point || !axis_dir || !out_mesh)
        return mfg_fail(MFG_ERR_NULL, "rotational sweep: %s is NULL",
                        !axis_point ? "axis_point" : !axis_dir ? "axis_direction" : "out_mesh");
    for (int k = 0; k < 3; k++) {
        if (!mfg_coord_ok(axis_point[k]))
            return mfg_fail(MFG_ERR_INVALID, "rotational sweep: axis point coordinate %d is %g "
                            "(not finite or out of range)", k, axis_point[k]);
        if (!mfg_coord_ok(axis_dir[k]))
            return mfg_fail(MFG_ERR_INVALID, "rotational sweep: axis direction component %d is "
                            "%g (not finite or out of range)", k, axis_dir[k]);
    }
    if (axis_dir[0] == 0 && axis_dir[1] == 0 && axis_dir[2] == 0)
        return mfg_fail(MFG_ERR_INVALID, "rotational sweep: the axis direction is the zero vector");
    if (!(angle > 0) || !(angle <= MFG_TWO_PI + 1e-12))
        return mfg_fail(MFG_ERR_INVALID, "rotational sweep: angle %g rad is outside (0, 2*pi]",
                        angle);
    if (!(tolerance > 0) || !mfg_coord_ok(tolerance))
        return mfg_fail(MFG_ERR_INVALID, "rotational sweep: tolerance %g must be positive and "
                        "finite", tolerance);
    return MFG_OK;
}

mfg_status mfg_rotational_sweep(const double *xyz, int64_t nvertices, const int64_t *triangles,
                                int64_t ntriangles, const double axis_point[3],
                                const double axis_direction[3], double angle, double tolerance,
                                mfg_mesh **out_mesh, mfg_sweep_stats *out_stats)
{
    return mfg_rotational_sweep_p(xyz, nvertices, triangles, ntriangles, axis_point,
                                  axis_direction, angle, tolerance, out_mesh, out_stats, NULL);
}

mfg_status mfg_rotational_sweep_p(const double *xyz, int64_t nvertices,
                                  const int64_t *triangles, int64_t ntriangles,
                                  const double axis_point[3], const double axis_direction[3],
                                  double angle, double tolerance, mfg_mesh **out_mesh,
                                  mfg_sweep_stats *out_stats, const mfg_progress *progress)
{
    mfg_status st = check_sweep_args(axis_point, axis_direction, angle, tolerance, out_mesh);
    if (st != MFG_OK)
        return st;
    mfg_prog prog;
    mfg_prog_init(&prog, progress, "mfg_rotational_sweep");
    if (!mfg_prog_stage(&prog, "sweep: setup", 0, 0.05, 1))
        return mfg_prog_fail(&prog);
    int64_t *nb = NULL;
    st = mfg_mesh_require_closed(xyz, nvertices, triangles, ntriangles, NULL, &nb);
    if (st != MFG_OK)
        return st;
    sw_ctx c;
    memset(&c, 0, sizeof c);
    c.st = MFG_OK;
    c.prog = &prog;
    c.nv = nvertices;
    c.nt = ntriangles;
    c.full_turn = angle >= MFG_TWO_PI - 1e-12;
    c.theta = c.full_turn ? MFG_TWO_PI : angle;
    c.tol = tolerance;
    make_frame(&c, axis_point, axis_direction);
    sw_out o;
    memset(&o, 0, sizeof o);
    int ok = setup(&c, xyz, triangles, nb);
    free(nb);
    double rmax = 0, zmin = INFINITY, zmax = -INFINITY;
    if (ok) {
        for (int64_t i = 0; i < c.nv; i++) {
            rmax = fmax(rmax, c.vr[i]);
            zmin = fmin(zmin, c.lx[3 * i + 2]);
            zmax = fmax(zmax, c.lx[3 * i + 2]);
        }
        ok = build_bins(&c, rmax, zmin, zmax);
        if (ok)
            ok = build_gap_curves(&c);
    }
    /* The decomposition's grid is placed by odd factors, so that its lines rarely pass
     * through vertices or along edges of round-numbered parts.  When they do and the
     * result is not a closed 2-manifold (checked as the input is), the decomposition is
     * built again on a grid placed differently; after the last placement the call fails
     * with MFG_ERR_INTERNAL rather than return an open surface. */
    double in_volume = ok ? mesh_volume(c.lx, triangles, ntriangles) : 0;
    static const double grid_scale[4] = {1.0123456789, 1.0371093751, 0.9812988281, 1.0557861328};
    static const double grid_shift[4] = {0.0371, 0.0629, 0.0147, 0.0853};
    mfg_mesh_report rep;
    int attempt = 0, valid = 0;
    int64_t leaves0 = 0;
    char why[256] = "";
    for (attempt = 0; ok && attempt < 4 && !valid; attempt++) {
        if (attempt > 0)
            reset_attempt(&c, &o);
        double ext = fmax(rmax, zmax - zmin);
        c.ext = ext;
        c.quantum = ldexp(ext, -40);
        c.bounding_only = attempt >= 2;
        double S0 = 0.5 * ext * grid_scale[attempt];
        double hmin = 0.25 * tolerance;
        int lmax = 0;
        while (lmax < 40 && ldexp(S0, -lmax) > hmin)
            lmax++;
        c.lmax = lmax;
        c.h = ldexp(S0, -lmax);
        c.hmin = c.h;
        c.r0 = 0;
        c.z0 = zmin - grid_shift[attempt] * S0;
        c.nroot_r = (int64_t)floor(rmax / S0) + 1;
        c.nroot_z = (int64_t)floor((zmax - c.z0) / S0) + 1;
        /* A placement whose tree grows far past the first one's is given up at once: the
         * fallback placements on the 9-face arm grew to 1.4 M and 2.5 M triangles before
         * failing the check anyway (a refusal took 9 s and 1.5 GB). */
        c.capped = 0;
        c.leaf_cap = attempt > 0 ? 4 * leaves0 + 4096 : 0;
        ok = sw_stage(&c, "sweep: cells", 0.05, 0.35, SWEEP_EVERY_CELLS) && build_quadtree(&c);
        if (attempt == 0)
            leaves0 = c.nleaves;
        if (ok && c.capped) {
            size_t lw = strlen(why);
            snprintf(why + lw, sizeof why - lw, "%splacement %d given up past %lld cells",
                     lw ? "; " : "", attempt, (long long)c.leaf_cap);
            continue;
        }
        /* A cut that fails in build_polygons (a chord or star whose vertices do not come
         * out on the loop) leaves a block the size of its cell, beyond the tolerance where
         * the cell is coarse: the cube spun about its diagonal had vertices 1.03 tol
         * outside SV, from blocks a quarter of the part wide.  Such cells are refined when
         * the tree is built again, until no cut fails above the finest size; a placement
         * that still has such blocks after 8 rounds is given up (another placement, or a
         * refusal). */
        hmap_free(&c.refine);
        if (ok && !hmap_init(&c.refine, 64))
            ok = ctx_nomem(&c);
        int rounds = 0;
        for (;;) {
            c.coarse_blocks = 0;
            ok = ok && sw_stage(&c, "sweep: polygons", 0.35, 0.6, SWEEP_EVERY_LEAVES) &&
                 build_polygons(&c);
            if (!ok || !c.coarse_blocks || ++rounds > 8)
                break;
            reset_attempt(&c, &o);
            ok = sw_stage(&c, "sweep: cells", 0.05, 0.35, SWEEP_EVERY_CELLS) &&
                 build_quadtree(&c);
            if (ok && c.capped)
                break;
        }
        if (ok && c.capped) {
            size_t lw = strlen(why);
            snprintf(why + lw, sizeof why - lw, "%splacement %d given up past %lld cells",
                     lw ? "; " : "", attempt, (long long)c.leaf_cap);
            continue;
        }
        if (ok && c.coarse_blocks) {
            size_t lw = strlen(why);
            snprintf(why + lw, sizeof why - lw, "%splacement %d: %lld cuts failed in coarse cells",
                     lw ? "; " : "", attempt, (long long)c.coarse_blocks);
            continue;
        }
        if (ok)
            ok = hmap_init(&c.outmap, 1024) && hmap_init(&o.lifts, 1024) ? 1 : ctx_nomem(&c);
        /* the walls: one unit per polygon, then the strips and faces (build_walls), the
         * twins and the pinches, each reported when done */
        if (ok)
            ok = sw_stage(&c, "sweep: walls", 0.6, 0.85, SWEEP_EVERY_POLYS) &&
                 build_walls(&c, &o) && sw_report(&c, 0.7) && cancel_twins(&c) &&
                 sw_report(&c, 0.8) && resolve_pinches(&c, &o);
        ok = ok && sw_stage(&c, "sweep: check", 0.85, 0.95, 1);
        if (ok) {
            mfg_status cs = mfg_mesh_check_closed(c.ox, c.nout, c.otri, c.notri, &rep);
            if (cs == MFG_OK) {
                valid = 1;
                int overlap = 0;
                if (!drop_nested_shells(&c, &overlap)) {
                    ok = 0;
                    break;
                }
                if (overlap) {
                    /* treated like an open surface: another placement, or a refusal */
                    valid = 0;
                    snprintf(why, sizeof why, "two of its shells cross each other");
                } else if (!(mesh_volume(c.ox, c.otri, c.notri) >= in_volume * (1 - 1e-9))) {
                    /* SV holds O (t = 0): a closed surface holding less is wrong somewhere,
                     * like an open one (found by fuzz_api) */
                    valid = 0;
                    snprintf(why, sizeof why, "it holds less volume than the input");
                }
                /* the merge of planar pieces last, on the shells that are kept (it reads oface,
                 * which drop_nested_shells keeps aligned with the triangles) */
                if (valid)
                    ok = merge_faces(&c);
            } else {
                if (cs == MFG_ERR_NOMEM) {
                    ok = ctx_nomem(&c);
                    break;
                }
                snprintf(why, sizeof why, "%s", mfg_last_error());
            }
        }
    }
    if (ok && !valid) {
        ok = 0;
        c.st = mfg_fail(MFG_ERR_INTERNAL, "rotational sweep: the swept surface could not be made "
                        "a closed 2-manifold (%s) on 4 placements of the decomposition; please "
                        "report this input", why);
    }
    if (ok)
        ok = sw_stage(&c, "sweep: output", 0.95, 1.0, 1) && flip_out_slivers(&c);
    mfg_mesh *m = NULL;
    if (ok) {
        m = calloc(1, sizeof *m);
        if (m) {
            m->vertices = malloc((size_t)(3 * c.nout + 1) * sizeof *m->vertices);
            m->triangles = malloc((size_t)(3 * c.notri + 1) * sizeof *m->triangles);
        }
        if (!m || !m->vertices || !m->triangles) {
            if (m) {
                free(m->vertices);
                free(m->triangles);
                free(m);
            }
            m = NULL;
            ok = ctx_nomem(&c);
        }
    }
    if (ok) {
        /* only the vertices the triangles use (lifts and ring points left over by
         * cancelled twins are dropped), numbered in order of first use */
        int64_t *map = malloc((size_t)(c.nout + 1) * sizeof *map);
        if (!map) {
            free(m->vertices);
            free(m->triangles);
            free(m);
            m = NULL;
            ok = ctx_nomem(&c);
        } else {
            for (int64_t i = 0; i < c.nout; i++)
                map[i] = -1;
            int64_t nused = 0;
            for (int64_t i = 0; i < 3 * c.notri; i++) {
                int64_t w = c.otri[i];
                if (map[w] < 0) {
                    map[w] = nused;
                    const double *p = c.ox + 3 * w;
                    for (int k = 0; k < 3; k++) {
                        double x = c.origin[k] + p[0] * c.frame[0][k] + p[1] * c.frame[1][k] +
                                   p[2] * c.frame[2][k];
                        m->vertices[3 * nused + k] = fabs(x) < 0x1p-200 ? 0 : x;
                    }
                    nused++;
                }
                m->triangles[i] = map[w];
            }
            free(map);
            m->nvertices = nused;
            m->ntriangles = c.notri;
        }
    }
    if (ok && !sw_stage(&c, "sweep: done", 1.0, 1.0, 1)) {
        mfg_mesh_free(m);
        m = NULL;
        ok = 0;
    }
    if (ok) {
        if (out_stats) {
            mfg_sweep_stats S;
            memset(&S, 0, sizeof S);
            for (int k = 0; k < 3; k++) {
                S.bbox[k] = INFINITY;
                S.bbox[3 + k] = -INFINITY;
            }
            for (int64_t i = 0; i < m->nvertices; i++)
                for (int k = 0; k < 3; k++) {
                    S.bbox[k] = fmin(S.bbox[k], m->vertices[3 * i + k]);
                    S.bbox[3 + k] = fmax(S.bbox[3 + k], m->vertices[3 * i + k]);
                }
            double area = 0;
            for (int64_t t = 0; t < c.notri; t++) {
                const double *a = c.ox + 3 * c.otri[3 * t], *b = c.ox + 3 * c.otri[3 * t + 1],
                             *d = c.ox + 3 * c.otri[3 * t + 2];
                double e1[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
                double e2[3] = {d[0] - a[0], d[1] - a[1], d[2] - a[2]};
                double cx = e1[1] * e2[2] - e1[2] * e2[1], cy = e1[2] * e2[0] - e1[0] * e2[2],
                       cz = e1[0] * e2[1] - e1[1] * e2[0];
                area += 0.5 * sqrt(cx * cx + cy * cy + cz * cz);
            }
            S.volume = mesh_volume(c.ox, c.otri, c.notri); /* about the axis point */
            S.area = area;
            *out_stats = S;
        }
        *out_mesh = m;
    }
    st = ok ? MFG_OK : c.st;
    free(o.phi);
    hmap_free(&o.lifts);
    ctx_free(&c);
    if (st == MFG_OK)
        mfg_clear_error();
    return st;
}
