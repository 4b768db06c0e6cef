/* SPDX-License-Identifier: LGPL-2.1-or-later */
/* bisector.c - points on the bisector of two boundary elements (issue 9; Lee & Lee, the
 * medial surface of a polyhedron; docs/design/medial.md section 4.0).  The paper's closed
 * forms of the 11 bisector surfaces ([LL95]) are not in the paper itself, so every sheet
 * vertex is found the same way: as the root of g(s) = d_a^car - d_b^car along a lattice
 * segment.  The linear forms (plane-plane, parallel lines, point-point) are solved by the
 * first secant step up to rounding. */
#include <math.h>

#include "medial/medial.h"
#include "common/predicates.h"

/* Unit roundoff of IEEE double (2^-53). */
#define U 1.1102230246251565e-16
#define MAX_STEPS 200

typedef struct probe {
    double s, g, da, db;
    double x[3];
} probe;

/* g at p + s (q - p); with grad_g (may be NULL) = (grad d_a - grad d_b) . (q - p). */
static void eval(const md_elements *el, int64_t a, int64_t b, const double *p, const double *pq,
                 double s, probe *r, double *dg)
{
    double ga[3], gb[3];
    r->s = s;
    for (int k = 0; k < 3; k++)
        r->x[k] = p[k] + s * pq[k];
    r->da = md_dist_car(el, a, r->x, dg ? ga : NULL);
    r->db = md_dist_car(el, b, r->x, dg ? gb : NULL);
    r->g = r->da - r->db;
    if (dg)
        *dg = (ga[0] - gb[0]) * pq[0] + (ga[1] - gb[1]) * pq[1] + (ga[2] - gb[2]) * pq[2];
}

/* Converged: |g| within 4u of the distances (design 4.0). */
static int small(const probe *r)
{
    return fabs(r->g) <= 4.0 * U * (fabs(r->da) + fabs(r->db));
}

static int sgn(double v)
{
    return (v > 0) - (v < 0);
}

int md_root_on_segment(const md_elements *el, int64_t a, int64_t b, const double p[3],
                       const double q[3], double out[3], double *s_out)
{
    double pq[3] = {q[0] - p[0], q[1] - p[1], q[2] - p[2]};
    probe lo, hi, m, best;
    eval(el, a, b, p, pq, 0.0, &lo, NULL);
    eval(el, a, b, p, pq, 1.0, &hi, NULL);
    if (sgn(lo.g) * sgn(hi.g) > 0)
        return 0;
    best = fabs(lo.g) <= fabs(hi.g) ? lo : hi;
    if (!small(&best) && lo.g != 0 && hi.g != 0) {
        /* The secant guess, then one Newton step from it with the exact gradients. */
        double s = lo.g / (lo.g - hi.g), dg;
        if (!(s > 0 && s < 1))
            s = 0.5;
        eval(el, a, b, p, pq, s, &m, &dg);
        for (int pass = 0; pass < 2; pass++) {
            if (fabs(m.g) < fabs(best.g))
                best = m;
            if (small(&m) || m.g == 0)
                break;
            if (sgn(m.g) == sgn(lo.g))
                lo = m;
            else
                hi = m;
            if (pass == 1)
                break;
            double sn = dg != 0 ? m.s - m.g / dg : -1.0;
            if (!(sn > lo.s && sn < hi.s))
                break;
            eval(el, a, b, p, pq, sn, &m, NULL);
        }
        /* Illinois regula falsi (an end kept twice has its weight halved), with a
         * bisection every fourth step as the safeguard. */
        double flo = lo.g, fhi = hi.g;
        int last = 0;
        for (int it = 0; it < MAX_STEPS && !small(&best) && best.g != 0; it++) {
            double big = fabs(lo.s) > fabs(hi.s) ? fabs(lo.s) : fabs(hi.s);
            double width = hi.s - lo.s;
            if (width <= 2.0 * (nextafter(big, INFINITY) - big))
                break; /* a 2-ulp bracket */
            double s = (lo.s * fhi - hi.s * flo) / (fhi - flo);
            if (!(s > lo.s && s < hi.s) || it % 4 == 3)
                s = lo.s + 0.5 * width;
            if (!(s > lo.s && s < hi.s))
                break;
            eval(el, a, b, p, pq, s, &m, NULL);
            if (fabs(m.g) < fabs(best.g))
                best = m;
            if (sgn(m.g) == sgn(lo.g)) {
                lo = m;
                flo = m.g;
                if (last < 0)
                    fhi *= 0.5;
                last = -1;
            } else {
                hi = m;
                fhi = m.g;
                if (last > 0)
                    flo *= 0.5;
                last = 1;
            }
        }
    }
    for (int k = 0; k < 3; k++)
        out[k] = best.x[k];
    if (s_out)
        *s_out = best.s;
    return 1;
}

int md_form(const md_elements *el, int64_t a, int64_t b)
{
    int ka = md_kind(el, a), kb = md_kind(el, b);
    if (ka < kb) { /* a: the higher kind (face, edge, vertex) */
        int64_t t = a;
        a = b;
        b = t;
        int k = ka;
        ka = kb;
        kb = k;
    }
    const double *na = ka == MD_FACE ? el->face_plane + 4 * a : NULL;
    const double *ua = ka == MD_EDGE ? el->edge_dir + 3 * (a - el->nfaces) : NULL;
    if (ka == MD_FACE) {
        if (kb == MD_FACE)
            return mfg_parallel3(na, el->face_plane + 4 * b) ? MD_FORM_PLANE_PLANE_PARALLEL
                                                             : MD_FORM_PLANE_PLANE;
        if (kb == MD_EDGE) {
            const double *ub = el->edge_dir + 3 * (b - el->nfaces);
            if (mfg_dot3_sign(na, ub) == 0)
                return MD_FORM_PLANE_LINE_PARALLEL;
            return mfg_parallel3(na, ub) ? MD_FORM_PLANE_LINE_PERPENDICULAR
                                         : MD_FORM_PLANE_LINE_OBLIQUE;
        }
        return MD_FORM_PLANE_POINT;
    }
    if (ka == MD_EDGE) {
        if (kb == MD_EDGE) {
            const double *ub = el->edge_dir + 3 * (b - el->nfaces);
            if (mfg_parallel3(ua, ub))
                return MD_FORM_LINE_LINE_PARALLEL;
            const double *A = el->edge_seg + 6 * (a - el->nfaces);
            const double *B = el->edge_seg + 6 * (b - el->nfaces);
            return mfg_orient3d(A, A + 3, B, B + 3) == 0 ? MD_FORM_LINE_LINE_CROSSING
                                                          : MD_FORM_LINE_LINE_SKEW;
        }
        return MD_FORM_LINE_POINT;
    }
    return MD_FORM_POINT_POINT;
}
