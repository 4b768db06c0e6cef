/* SPDX-License-Identifier: LGPL-2.1-or-later */
/* sweep/setup.c - Setup: the solid in the axis frame: the frame, the triangles, the curves
 * of the meridian decomposition (edge and silhouette images) and the (r, z) bins of
 * triangles.  Overview and file map: sweep/sweep.h. */
#include "sweep/sweep.h"

void sw_make_frame(sw_ctx *c, const double *p, const double *a)
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

int sw_add_curve(sw_ctx *c, const double *a, const double *b, int64_t t0, int64_t t1,
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
void sw_edge_at_z(const sw_ctx *c, int64_t i, int64_t j, double z, double out[3])
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

int sw_setup(sw_ctx *c, const double *xyz, const int64_t *tris, const int64_t *nb)
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
        T->vertical_ok = hn > SW_EPS_HORIZ * nn;
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
            if (!sw_add_curve(c, c->lx + 3 * a, c->lx + 3 * b, t, o, a, b))
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
            if (!sw_add_curve(c, pts[0], pts[1], t, -1, -1, -1))
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
        if (!sw_add_curve(c, a, b, t, -1, near, far))
            return 0;
        c->tcurves[4 * t + 3] = c->ncurves - 1;
    }
    c->cstamp = calloc((size_t)(c->ncurves + 1), sizeof *c->cstamp);
    if (!c->cstamp)
        return ctx_nomem(c);
    return 1;
}

/* The bins [i0, i1] x [j0, j1] of a g x g grid over which triangle T's (r, z) box lies. */
static void tri_bins(const sw_ctx *c, const sw_tri *T, double zmin, int64_t g, int64_t *i0,
                     int64_t *i1, int64_t *j0, int64_t *j1)
{
    *i0 = (int64_t)(T->rmin / c->bdr), *i1 = (int64_t)(T->rmax / c->bdr);
    *j0 = (int64_t)((T->zmin - zmin) / c->bdz), *j1 = (int64_t)((T->zmax - zmin) / c->bdz);
    if (*i1 >= g) *i1 = g - 1;
    if (*j1 >= g) *j1 = g - 1;
}

/* Bins of triangles over their (r, z) images. */
int sw_build_bins(sw_ctx *c, double rmax, double zmin, double zmax)
{
    int64_t g = (int64_t)ceil(sqrt((double)c->nt)) + 1;
    if (g > 2048)
        g = 2048;
    for (;;) {
        c->nbr = g;
        c->nbz = g;
        c->br0 = 0;
        c->bz0 = zmin;
        c->bdr = (rmax > 0 ? rmax : 1) / (double)g * (1 + SW_EPS_REL);
        c->bdz = (zmax > zmin ? zmax - zmin : 1) / (double)g * (1 + SW_EPS_REL);
        int64_t total = 0;
        for (int64_t t = 0; t < c->nt; t++) {
            int64_t i0, i1, j0, j1;
            tri_bins(c, &c->tris[t], zmin, g, &i0, &i1, &j0, &j1);
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
                int64_t i0, i1, j0, j1;
                tri_bins(c, &c->tris[t], zmin, g, &i0, &i1, &j0, &j1);
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
int sw_gather(sw_ctx *c, double ra, double rb, double za, double zb)
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
