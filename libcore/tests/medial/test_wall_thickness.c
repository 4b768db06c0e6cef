/* SPDX-License-Identifier: LGPL-2.1-or-later */
/* test_wall_thickness.c - mfg_wall_thickness / mfg_medial_thickness (issue 21, section 4)
 * against analytic wall thicknesses: a plate (every boundary point its thickness, convex
 * edges included), a T-section (the flange and the web, the thick spot under the web:
 * the ball through the two reflex edges, 2 r = 12.5), a wedge (a wall tapering to a
 * sharp edge: 2 s tan(alpha / 2) at distance s from the edge, full medial surface only),
 * invariance under a rigid motion, and hostile arguments, cancel and outputs left
 * untouched on failure. */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "medial_solids.h"
#include "mfg_test.h"
#include "mfgeom.h"

static int near(double a, double b, double tol)
{
    return fabs(a - b) <= tol;
}

/* Plate 100 x 60 x 4: every point of its boundary -- faces, convex edges, corners --
 * is 4 thick (the balls at convex corners are left out by the wall angle). */
static void test_plate(void)
{
    tmesh m;
    ms_box(&m, 100, 60, 4);
    double pts[3 * 9] = {50, 30, 0,  50, 30, 4,  1, 1, 4,   0, 30, 2,  100, 0, 0,
                         100, 60, 4, 99.9, 0.1, 2,  3, 60, 1,  50, 0, 4};
    double th[9], gaps[9], cen[27];
    double tol = 0.005 * sqrt(100 * 100 + 60 * 60 + 16);
    for (int full = 0; full < 2; full++) {
        CHECK_EQ_INT(mfg_wall_thickness(m.xyz, m.nv, m.tri, m.nt, tol, full ? MFG_MEDIAL_FULL : 0,
                                        0, pts, 9, MFG_WALL_ANGLE, th, cen, gaps, NULL),
                     MFG_OK);
        for (int i = 0; i < 9; i++) {
            CHECK(near(th[i], 4.0, 1e-9));
            CHECK(near(cen[3 * i + 2], 2.0, 1e-9)); /* every ball is centred mid-plate */
        }
        CHECK(gaps[0] < 1e-9 && gaps[1] < 1e-9); /* face middles: touched */
        CHECK(gaps[2] > 0.5);                    /* near a convex corner: the nearest */
    }
}

/* T-section (medial_solids.h): flange [0,60] x [0,10], web [25,35] x [10,50], z in
 * [0,40].  Flange and web are 10 thick; under the web the largest ball touches the
 * flange's underside and both reflex edges: (30, r) with 25 + (10 - r)^2 = r^2, r = 6.25;
 * a reflex edge takes the smallest ball touching it (r = 5, the flange's). */
static void test_tsection(void)
{
    tmesh m;
    ms_tsection(&m);
    const double pts[] = {30, 0, 20,  5, 0, 20,  5, 10, 20,  25, 30, 20,  35, 30, 20,
                          25, 10, 20,  30, 50, 20,  55, 5, 40};
    const double want[] = {12.5, 10, 10, 10, 10, 10, 10, 10};
    const int n = 8;
    double th[8], gaps[8];
    double tol = 0.005 * sqrt(60 * 60 + 50 * 50 + 40 * 40);
    CHECK_EQ_INT(mfg_wall_thickness(m.xyz, m.nv, m.tri, m.nt, tol, 0, 0, pts, n, MFG_WALL_ANGLE,
                                    th, NULL, gaps, NULL),
                 MFG_OK);
    for (int i = 0; i < n; i++) {
        CHECK(near(th[i], want[i], 2 * tol));
        if (!near(th[i], want[i], 2 * tol))
            fprintf(stderr, "  T-section point %d: %.9g, want %.9g\n", i, th[i], want[i]);
    }
    CHECK(gaps[0] < 1e-9); /* under the web: the junction ball touches it */

    /* The same through a medial result (mfg_medial_thickness), and moved and turned:
     * the values do not change (the balls move with the part). */
    mfg_medial *med = NULL;
    CHECK_EQ_INT(mfg_medial_surface(m.xyz, m.nv, m.tri, m.nt, tol, 0, 0, &med), MFG_OK);
    double th2[8];
    CHECK_EQ_INT(mfg_medial_thickness(med, pts, n, MFG_WALL_ANGLE, th2, NULL, NULL), MFG_OK);
    for (int i = 0; i < n; i++)
        CHECK(near(th2[i], th[i], 1e-12 * 60));
    mfg_medial_free(med);

    double c = cos(0.7), s = sin(0.7), moved[8 * 3];
    tmesh r = m;
    for (int64_t v = 0; v < r.nv; v++) {
        double *p = r.xyz + 3 * v, x = p[0], y = p[1];
        p[0] = c * x - s * y + 1234.5;
        p[1] = s * x + c * y - 77.25;
        p[2] += 0.125;
    }
    for (int i = 0; i < n; i++) {
        const double *p = pts + 3 * i;
        moved[3 * i] = c * p[0] - s * p[1] + 1234.5;
        moved[3 * i + 1] = s * p[0] + c * p[1] - 77.25;
        moved[3 * i + 2] = p[2] + 0.125;
    }
    double th3[8];
    CHECK_EQ_INT(mfg_wall_thickness(r.xyz, r.nv, r.tri, r.nt, tol, 0, 0, moved, n,
                                    MFG_WALL_ANGLE, th3, NULL, NULL, NULL),
                 MFG_OK);
    for (int i = 0; i < n; i++)
        CHECK(near(th3[i], want[i], 2 * tol));
}

/* Wedge: the triangle (0,0), (100,0), (100,10) extruded over z in [0, 40]; the slanted
 * and the bottom face meet at the sharp edge x = 0 at alpha = atan(0.1).  A point on the
 * bottom face at distance s from the edge is touched by the circle tangent to both
 * faces there: 2 r = 2 s tan(alpha / 2) -- with the full medial surface (the two faces
 * share the edge, so the major part has no sheet between them). */
static void test_wedge(void)
{
    tmesh m;
    const double P[3][2] = {{0, 0}, {100, 0}, {100, 10}};
    ms_prism(&m, P, 3, 40);
    double alpha = atan(0.1), tol = 0.005 * sqrt(100 * 100 + 100 + 1600);
    const double s[] = {5, 20, 40, 60};
    double pts[12], th[4], gaps[4];
    for (int i = 0; i < 4; i++) {
        pts[3 * i] = s[i];
        pts[3 * i + 1] = 0;
        pts[3 * i + 2] = 20;
    }
    CHECK_EQ_INT(mfg_wall_thickness(m.xyz, m.nv, m.tri, m.nt, tol, MFG_MEDIAL_FULL, 0, pts, 4,
                                    MFG_WALL_ANGLE, th, NULL, gaps, NULL),
                 MFG_OK);
    for (int i = 0; i < 4; i++) {
        double want = 2 * s[i] * tan(alpha / 2);
        CHECK(near(th[i], want, 2 * tol));
        CHECK(gaps[i] < 1e-9);
    }
    /* The major part has no ball that spans the wedge: refused with a reason. */
    CHECK_EQ_INT(mfg_wall_thickness(m.xyz, m.nv, m.tri, m.nt, tol, 0, 0, pts, 4, MFG_WALL_ANGLE,
                                    th, NULL, NULL, NULL),
                 MFG_ERR_DEGENERATE);
    CHECK(strstr(mfg_last_error(), "mfg_wall_thickness") != NULL);
}

static int cancel_at_thickness(void *user, double fraction, const char *stage)
{
    (void)fraction;
    int *calls = user;
    ++*calls;
    return strncmp(stage, "thickness:", 10) == 0;
}

static int cancel_at_once(void *user, double fraction, const char *stage)
{
    (void)fraction;
    (void)stage;
    (void)user;
    return 1;
}

/* Hostile arguments: every error leaves the outputs untouched and says why. */
static void test_errors(void)
{
    tmesh m;
    ms_box(&m, 10, 6, 2);
    double pts[6] = {5, 3, 0, 5, 3, 2}, th[2] = {-7, -7}, cen[6], gaps[2];
    const double tol = 0.05;
#define UNTOUCHED() CHECK(th[0] == -7 && th[1] == -7)
    CHECK_EQ_INT(mfg_wall_thickness(m.xyz, m.nv, m.tri, m.nt, tol, 0, 0, NULL, 2, MFG_WALL_ANGLE,
                                    th, NULL, NULL, NULL),
                 MFG_ERR_NULL);
    CHECK_EQ_INT(mfg_wall_thickness(m.xyz, m.nv, m.tri, m.nt, tol, 0, 0, pts, 2, MFG_WALL_ANGLE,
                                    NULL, NULL, NULL, NULL),
                 MFG_ERR_NULL);
    CHECK_EQ_INT(mfg_wall_thickness(m.xyz, m.nv, m.tri, m.nt, tol, 0, 0, pts, -1, MFG_WALL_ANGLE,
                                    th, NULL, NULL, NULL),
                 MFG_ERR_INVALID);
    CHECK_EQ_INT(mfg_wall_thickness(m.xyz, m.nv, m.tri, m.nt, tol, 0, 0, pts, INT64_MAX,
                                    MFG_WALL_ANGLE, th, NULL, NULL, NULL),
                 MFG_ERR_INVALID);
    const double bad_angles[] = {0, -1, 3.5, NAN, INFINITY};
    for (int i = 0; i < 5; i++)
        CHECK_EQ_INT(mfg_wall_thickness(m.xyz, m.nv, m.tri, m.nt, tol, 0, 0, pts, 2, bad_angles[i],
                                        th, NULL, NULL, NULL),
                     MFG_ERR_INVALID);
    pts[4] = NAN;
    CHECK_EQ_INT(mfg_wall_thickness(m.xyz, m.nv, m.tri, m.nt, tol, 0, 0, pts, 2, MFG_WALL_ANGLE,
                                    th, NULL, NULL, NULL),
                 MFG_ERR_INVALID);
    CHECK(strstr(mfg_last_error(), "point 1") != NULL);
    pts[4] = 3;
    /* the mesh's own errors (open mesh: one triangle dropped), named for this call */
    CHECK_EQ_INT(mfg_wall_thickness(m.xyz, m.nv, m.tri, m.nt - 1, tol, 0, 0, pts, 2,
                                    MFG_WALL_ANGLE, th, NULL, NULL, NULL),
                 MFG_ERR_INVALID);
    CHECK(strncmp(mfg_last_error(), "mfg_wall_thickness: ", 20) == 0);
    CHECK_EQ_INT(mfg_wall_thickness(m.xyz, m.nv, m.tri, m.nt, -1, 0, 0, pts, 2, MFG_WALL_ANGLE, th,
                                    NULL, NULL, NULL),
                 MFG_ERR_INVALID);
    CHECK_EQ_INT(mfg_medial_thickness(NULL, pts, 2, MFG_WALL_ANGLE, th, NULL, NULL), MFG_ERR_NULL);
    UNTOUCHED();
    /* An empty medial result: no wall ball. */
    mfg_medial empty;
    memset(&empty, 0, sizeof empty);
    CHECK_EQ_INT(mfg_medial_thickness(&empty, pts, 2, MFG_WALL_ANGLE, th, cen, gaps),
                 MFG_ERR_DEGENERATE);
    UNTOUCHED();
    /* Cancel in the medial stages and in the thickness stages. */
    int calls = 0;
    mfg_progress stop_now = {cancel_at_once, &calls};
    CHECK_EQ_INT(mfg_wall_thickness(m.xyz, m.nv, m.tri, m.nt, tol, 0, 0, pts, 2, MFG_WALL_ANGLE,
                                    th, NULL, NULL, &stop_now),
                 MFG_ERR_CANCELLED);
    CHECK(strstr(mfg_last_error(), "mfg_wall_thickness: cancelled in stage \"medial:") != NULL);
    mfg_progress stop_late = {cancel_at_thickness, &calls};
    CHECK_EQ_INT(mfg_wall_thickness(m.xyz, m.nv, m.tri, m.nt, tol, 0, 0, pts, 2, MFG_WALL_ANGLE,
                                    th, NULL, NULL, &stop_late),
                 MFG_ERR_CANCELLED);
    CHECK(strstr(mfg_last_error(), "cancelled in stage \"thickness:") != NULL);
    UNTOUCHED();
    /* No points: nothing to do, OK. */
    CHECK_EQ_INT(mfg_wall_thickness(m.xyz, m.nv, m.tri, m.nt, tol, 0, 0, NULL, 0, MFG_WALL_ANGLE,
                                    th, NULL, NULL, NULL),
                 MFG_OK);
    UNTOUCHED();
#undef UNTOUCHED
}

/* Fractions of a successful call never decrease, end at 1 with "thickness: done". */
typedef struct prog_log {
    double last;
    int monotone, calls;
    const char *stage;
} prog_log;

static int log_progress(void *user, double fraction, const char *stage)
{
    prog_log *l = user;
    if (fraction < l->last)
        l->monotone = 0;
    l->last = fraction;
    l->stage = stage;
    l->calls++;
    return 0;
}

static void test_progress(void)
{
    tmesh m;
    ms_l_bracket(&m);
    double pts[3] = {30, 0, 20}, th;
    prog_log l = {0, 1, 0, ""};
    mfg_progress p = {log_progress, &l};
    CHECK_EQ_INT(mfg_wall_thickness(m.xyz, m.nv, m.tri, m.nt, 0.5, 0, 0, pts, 1, MFG_WALL_ANGLE,
                                    &th, NULL, NULL, &p),
                 MFG_OK);
    CHECK(l.monotone && l.calls > 3 && l.last == 1.0 && strcmp(l.stage, "thickness: done") == 0);
    CHECK(near(th, 10, 1.0));
}

int main(int argc, char **argv)
{
    const char *which = argc > 1 ? argv[1] : "all";
    if (!strcmp(which, "plate") || !strcmp(which, "all"))
        test_plate();
    if (!strcmp(which, "tsection") || !strcmp(which, "all"))
        test_tsection();
    if (!strcmp(which, "wedge") || !strcmp(which, "all"))
        test_wedge();
    if (!strcmp(which, "errors") || !strcmp(which, "all")) {
        test_errors();
        test_progress();
    }
    return mfg_test_report("test_wall_thickness");
}
