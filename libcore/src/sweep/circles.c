/* SPDX-License-Identifier: LGPL-2.1-or-later */
/* sweep/circles.c - Directed circles: the SV arcs of one circle about the axis (the
 * directed-circle rule).  Overview and file map: sweep/sweep.h. */
#include "sweep/sweep.h"

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
            sw_edge_at_z(c, T->v[k], T->v[k1], z, e[m++]);
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
    if (!sw_gather(c, r, INFINITY, z, z))
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
int sw_point_inside(sw_ctx *c, double r, double z, double psi)
{
    if (!sw_gather(c, r, INFINITY, z, z))
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

int sw_push_arc(sw_ctx *c, const sw_arc *a)
{
    if (!mfg_grow((void **)&c->arcs, &c->caparcs, c->narcs + 1, sizeof *c->arcs))
        return ctx_nomem(c);
    c->arcs[c->narcs++] = *a;
    return 1;
}

/* The crossings of the circle (r, z) with the slices of the gathered triangles, pushed
 * with push_cross (angle, triangle, entry or exit). */
static int slice_crossings(sw_ctx *c, double r, double z)
{
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
    return 1;
}

/* O's arcs on the circle from its crossings in c->xphi / xtri / xentry: sorted by angle, a
 * depth count relative to its minimum.  1 with *oarcs_out (malloc'd, *nO_out arcs), or 1
 * with *oarcs_out untouched and *inconsistent = 1 when entries and exits do not pair up or
 * no arc closes; 0 when memory runs out. */
static int solid_arcs(sw_ctx *c, sw_arc **oarcs_out, int64_t *nO_out, int *inconsistent)
{
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
    *oarcs_out = oarcs;
    *nO_out = nO;
    return 1;
}

/* SV's arcs from O's (the directed-circle rule): each end extended by theta and the
 * overlapping arcs merged, pushed to the arc pool (out->n of them), or out->full.  Frees
 * oarcs. */
static int swept_arcs(sw_ctx *c, sw_arc *oarcs, int64_t nO, sw_struct *out)
{
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
        if (!sw_push_arc(c, &m)) {
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
    if (!sw_gather(c, r, r, z, z))
        return 0;
    if (!slice_crossings(c, r, z))
        return 0;
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
    sw_arc *oarcs = NULL;
    int64_t nO = 0;
    if (!solid_arcs(c, &oarcs, &nO, inconsistent))
        return 0;
    if (!oarcs)
        return 1; /* *inconsistent: the caller moves the circle */
    return swept_arcs(c, oarcs, nO, out);
}

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

int sw_circle_arcs(sw_ctx *c, double r, double z, sw_struct *out)
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
    qsort(ph, (size_t)c->nx, sizeof *ph, sw_cmp_double_asc);
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
    if (!sw_push_arc(c, &arc))
        return 0;
    out->n = 1;
    return 1;
}

int sw_cmp_double_asc(const void *pa, const void *pb)
{
    double a = *(const double *)pa, b = *(const double *)pb;
    return (a > b) - (a < b);
}

/* Same structure: same full flag and the same (triangle, root) at both ends of every arc,
 * compared as sets (the arcs of one circle are distinct, their order cyclic). */
int sw_same_struct(const sw_ctx *c, const sw_struct *a, const sw_struct *b)
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
