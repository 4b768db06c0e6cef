/* SPDX-License-Identifier: LGPL-2.1-or-later */
/* test_sweep_battery.c - the random battery of mfg_rotational_sweep (issue 20): a few
 * hundred seeded inputs (boxes, prisms, L-brackets, frames, tori, octahedra and sheared
 * boxes, tessellated real parts; random placements, axes, angles and tolerances), each
 * result checked for the contract - not refused, closed, no self-intersection, no
 * zero-area triangle, at least the input's volume, conservative, tight - and for order,
 * rigid-motion and scale invariance; one line per failing input, a summary, exit 1 when
 * any input is refused or fails.
 *
 *   test_sweep_battery [selftest]
 *   MFG_BATTERY_COUNT=n      inputs (default BATTERY_DEFAULT_COUNT; the families in turn)
 *   MFG_BATTERY_SEED=s       the run's seed (default BATTERY_DEFAULT_SEED)
 *   MFG_BATTERY_ONLY=family  only that family's inputs of the run (the same seeds)
 *   MFG_BATTERY_INPUT=family:seed  just that input (as printed on a failing line)
 *   MFG_BATTERY_DUMP=dir     write each failing input as dir/<family>_<seed>.off + .txt
 *   MFG_BATTERY_TIMEOUT=s    cancel a sweep after s seconds (a failure "timeout")
 *   MFG_BATTERY_VERBOSE=1    one line per input with its sizes and times
 *   MFG_BATTERY_VARIANTS=0   no invariance variants (half the inputs get one)
 *
 * The checks (eps: the rounding allowance, BT_EPS_REL = 1e-9 of the part's size about the
 * axis; the sample counts and query budgets are battery.h's BT_*):
 *   refused       status not MFG_OK (timeout: cancelled through the progress callback)
 *   closed        mfg_mesh_check_closed accepts the result
 *   selfint       no two triangles meet but at their common edge or vertex (exact)
 *   zeroarea      no triangle of zero area (exact)
 *   volume        the result's volume at least the input's (to 1e-9 relative)
 *   conservative  points of the input surface (corners, side and face points) turned
 *                 over [0, angle]: each arc is cut where it crosses the result's surface
 *                 and each piece classified (exact point-in-solid); no point outside by
 *                 more than eps.  Pieces along the surface get a branch and bound on the
 *                 r dt bound down to arcs of tol/16; arcs whose budget ran out first are
 *                 counted ("coarse"), not failed
 *   tight         result vertices and face points: none certified farther than tol + eps
 *                 from SV (dist(p, SV) = min over t of dist(R(-t) p, O), which changes by
 *                 at most r dt); points neither found within nor certified beyond are
 *                 "undecided": counted, not failed
 *   order         renumbered vertices, reordered and restarted triangles: identical arrays
 *   rigid         the problem moved: volumes within tol x area (+1e-9 relative: both
 *                 lie between vol(SV) and vol(SV) + tol area), and each result within
 *                 tol + 2 eps of the other (moved)
 *   scale2        scaled by 2^k: the result scaled by 2^k bit for bit
 *   scale10       scaled by 10^k (|k| <= 9): volume / 10^3k as for rigid, every check
 */
#define _POSIX_C_SOURCE 200809L /* clock_gettime */
#include <math.h>
#include <signal.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "battery.h"
#include "sweep_checks.h"

#define BATTERY_DEFAULT_COUNT 308 /* 44 per family */
#define BATTERY_DEFAULT_SEED 0x5EED2020ULL
#define BATTERY_DEFAULT_TIMEOUT 60.0 /* seconds: the new engine's inputs take ~0.1 s */

/* volumes of the same problem moved or scaled by 10^k agree to this (the brief's ~1e-9) */
#define VOLUME_REL 1e-9
/* the result's volume may fall below the input's by this much (rounding of the sums) */
#define VOLUME_FLOOR_REL 1e-9
/* results with more triangles skip the self-intersection check, which counts as failed
 * (unverified): it takes a minute on 500 000 long thin triangles of the first design, and
 * a battery input's result should have tens of thousands (issue 20: at most 3x a lower
 * bound of the input's faces plus silhouette surfaces at the tolerance's angular step) */
#define SELFINT_MAX_TRIANGLES 400000
/* each random choice of the checks has its own stream, the input's seed mixed with one of
 * these (a check's samples do not shift when another check draws more or fewer) */
enum { SALT_CONS = 0xC0, SALT_TIGHT = 0x71, SALT_VARIANT = 0xA11A, SALT_NEAR_A = 0x51, SALT_NEAR_B = 0x52,
       SALT_SCALED = 0x5CA1E };
/* powers of two and of ten for the scale variants */
#define SCALE2_MAX_EXP 40
#define SCALE10_MAX_EXP 9

/* ------------------------------------------------------------------------ */
/* What can fail                                                            */
/* ------------------------------------------------------------------------ */

enum {
    F_INPUT,   /* the battery's own input is not a valid solid (a bug here) */
    F_REFUSED, /* status not MFG_OK */
    F_TIMEOUT, /* cancelled after MFG_BATTERY_TIMEOUT */
    F_CLOSED,
    F_SELFINT,
    F_ZEROAREA,
    F_VOLUME,
    F_CONSERVATIVE,
    F_TIGHT,
    F_ORDER,
    F_RIGID,
    F_SCALE2,
    F_SCALE10,
    F_COUNT
};
static const char *const CHECK_NAME[F_COUNT] = {"input",  "refused", "timeout", "closed", "selfint",
                                                "zeroarea", "volume", "conservative", "tight", "order",
                                                "rigid", "scale2", "scale10"};

typedef struct verdict {
    unsigned fails; /* bit per check */
    char text[2048];
    long undecided;          /* tight: points neither within nor beyond */
    long arcs, coarse_arcs;  /* conservative: arcs, arcs checked at a coarser step */
    long points;             /* tight: points */
} verdict;

static void say(verdict *v, int check, const char *fmt, ...) __attribute__((format(printf, 3, 4)));

static void say(verdict *v, int check, const char *fmt, ...)
{
    v->fails |= 1u << check;
    size_t n = strlen(v->text);
    if (n + 4 >= sizeof v->text)
        return;
    if (n)
        n += (size_t)snprintf(v->text + n, sizeof v->text - n, "; ");
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(v->text + n, sizeof v->text - n, fmt, ap);
    va_end(ap);
}

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* ------------------------------------------------------------------------ */
/* Running the sweep                                                        */
/* ------------------------------------------------------------------------ */

static double timeout_s = BATTERY_DEFAULT_TIMEOUT;

static int past_deadline(void *user, double fraction, const char *stage)
{
    (void)fraction;
    (void)stage;
    return now() > *(const double *)user;
}

static mfg_status sweep(const bt_problem *p, mfg_mesh **out, mfg_sweep_stats *st, double *seconds)
{
    double t0 = now(), deadline = t0 + timeout_s;
    mfg_progress prog = {past_deadline, &deadline};
    *out = NULL;
    mfg_status s = mfg_rotational_sweep_p(p->in.xyz, p->in.nv, p->in.tri, p->in.nt, p->ap, p->ad, p->angle, p->tol,
                                          out, st, &prog);
    *seconds = now() - t0;
    return s;
}

static int refused(const bt_problem *p, mfg_status s, verdict *v, const char *label)
{
    if (s == MFG_OK)
        return 0;
    if (s == MFG_ERR_CANCELLED)
        say(v, F_TIMEOUT, "%stimeout: no result in %g s", label, timeout_s);
    else
        say(v, F_REFUSED, "%srefused: %s: %s", label, mfg_status_str(s), mfg_last_error());
    (void)p;
    return 1;
}

static double volume_of(const double *xyz, int64_t nv, const int64_t *tri, int64_t nt)
{
    double vol, area, box[6];
    mesh_measure(xyz, nv, tri, nt, &vol, &area, box);
    return vol;
}

static double area_of(const mfg_mesh *m)
{
    double vol, area, box[6];
    mesh_measure(m->vertices, m->nvertices, m->triangles, m->ntriangles, &vol, &area, box);
    return area;
}

/* Whether a problem's input is a valid solid: closed and outward (the library's check),
 * no self-intersection, no zero-area triangle (exact). */
static int valid_input(const bt_problem *p)
{
    mfg_mesh in = bt_as_mfg(&p->in);
    mfg_mesh_report rep;
    int64_t first;
    self_intersections_quiet = 1;
    return mfg_mesh_check_closed(p->in.xyz, p->in.nv, p->in.tri, p->in.nt, &rep) == MFG_OK &&
           self_intersections(&in, "input") == 0 && zero_area_triangles(&in, &first) == 0;
}

/* ------------------------------------------------------------------------ */
/* The checks of one result                                                 */
/* ------------------------------------------------------------------------ */

typedef struct timing {
    double sweep, checks;
} timing;

static void check_result(const bt_problem *p, const mfg_mesh *m, verdict *v, const char *label, uint64_t seed)
{
    mfg_mesh_report rep;
    int closed = mfg_mesh_check_closed(m->vertices, m->nvertices, m->triangles, m->ntriangles, &rep) == MFG_OK;
    if (!closed)
        say(v, F_CLOSED, "%snot closed: %s", label, mfg_last_error());
    double t_si = now();
    if (m->ntriangles <= SELFINT_MAX_TRIANGLES) {
        self_intersections_quiet = 1;
        long bad = self_intersections(m, "battery");
        if (bad)
            say(v, F_SELFINT, "%s%ld self-intersecting triangle pairs of %lld", label, bad, (long long)m->ntriangles);
    } else {
        say(v, F_SELFINT, "%sself-intersections not checked: %lld triangles (the battery checks up to %d)", label,
            (long long)m->ntriangles, SELFINT_MAX_TRIANGLES);
    }
    t_si = now() - t_si;
    int64_t first;
    long flat = zero_area_triangles(m, &first);
    if (flat)
        say(v, F_ZEROAREA, "%s%ld zero-area triangles (first: %lld)", label, flat, (long long)first);
    double vin = volume_of(p->in.xyz, p->in.nv, p->in.tri, p->in.nt),
           vout = volume_of(m->vertices, m->nvertices, m->triangles, m->ntriangles);
    if (!(vout >= vin * (1 - VOLUME_FLOOR_REL)))
        say(v, F_VOLUME, "%svolume %.9g below the input's %.9g", label, vout, vin);
    if (!closed)
        return; /* inside and outside mean nothing for an open surface */

    double eps = bt_allowance(p);
    bt_index res, in;
    bt_index_build(&res, m->vertices, m->triangles, m->ntriangles);
    bt_index_build(&in, p->in.xyz, p->in.tri, p->in.nt);
    double t_cons = now();
    bt_cons_report c;
    bt_check_conservative(p, &res, eps, BT_CONS_ARCS, BT_CONS_EVALS, BT_CONS_EVALS_PER_ARC, seed ^ SALT_CONS, &c);
    if (c.outside) /* the farthest point confirmed by brute force: winding number, distance */
        say(v, F_CONSERVATIVE,
            "%snot conservative: %ld of %ld turned input points outside, the farthest by %.3g tol at t = %.9g "
            "(%.9g, %.9g, %.9g; brute force: winding %.3f, distance %.3g tol)",
            label, c.outside, c.arcs, c.worst / p->tol, c.worst_t, c.worst_q[0], c.worst_q[1], c.worst_q[2],
            winding(m, c.worst_q), mesh_dist(m, c.worst_q) / p->tol);
    t_cons = now() - t_cons;
    double t_tight = now();
    bt_tight_report t;
    bt_check_tight(p, &in, m, eps, BT_TIGHT_VERTICES, BT_TIGHT_FACE_POINTS, BT_TIGHT_EVALS, BT_TIGHT_EVALS_PER_POINT, seed ^ SALT_TIGHT, &t);
    if (t.beyond)
        say(v, F_TIGHT, "%snot tight: %ld of %ld result points farther than tol from SV, one at least %.3g tol "
                        "(%.9g, %.9g, %.9g)",
            label, t.beyond, t.points, t.worst_lb / p->tol, t.worst_p[0], t.worst_p[1], t.worst_p[2]);
    t_tight = now() - t_tight;
    v->undecided += t.undecided;
    v->points += t.points;
    v->arcs += c.arcs;
    v->coarse_arcs += c.coarse;
    if (getenv("MFG_BATTERY_VERBOSE"))
        printf("    %schecks: self-intersections %.3f s; conservative %.3f s: %ld arcs (%ld queries, %ld coarse at "
               "<= %.2g tol, %ld sides undecided); tight %.3f s: %ld points (%ld within, %ld beyond, %ld undecided "
               "up to %.3g tol; %ld queries)\n",
               label, t_si, t_cons, c.arcs, c.evals, c.coarse, c.coarse_step, c.unsure_side, t_tight, t.points,
               t.within, t.beyond, t.undecided, t.undecided_lb / p->tol, t.evals);
    if (getenv("MFG_BATTERY_VERBOSE") && t.undecided)
        printf("    %sundecided: (%.17g, %.17g, %.17g) sampled down to %.6g tol\n", label, t.undecided_p[0],
               t.undecided_p[1], t.undecided_p[2], t.undecided_min / p->tol);
    bt_index_free(&res);
    bt_index_free(&in);
}

/* ------------------------------------------------------------------------ */
/* Invariance variants                                                      */
/* ------------------------------------------------------------------------ */

static int same_arrays(const mfg_mesh *a, const mfg_mesh *b)
{
    return a->nvertices == b->nvertices && a->ntriangles == b->ntriangles &&
           !memcmp(a->vertices, b->vertices, (size_t)a->nvertices * 3 * sizeof(double)) &&
           !memcmp(a->triangles, b->triangles, (size_t)a->ntriangles * 3 * sizeof(int64_t));
}

/* a copy of p's problem with the vertices renumbered, the triangles reordered and each
 * started at another corner */
static void permuted(const bt_problem *p, bt_rng *r, bt_problem *q)
{
    *q = *p;
    q->in = bt_mesh_copy(&p->in);
    int64_t nv = p->in.nv, nt = p->in.nt;
    int64_t *perm = malloc((size_t)nv * sizeof *perm), *order = malloc((size_t)nt * sizeof *order);
    for (int64_t i = 0; i < nv; i++)
        perm[i] = i;
    for (int64_t i = nv - 1; i > 0; i--) {
        int64_t j = bt_int(r, 0, i), x = perm[i];
        perm[i] = perm[j];
        perm[j] = x;
    }
    for (int64_t i = 0; i < nt; i++)
        order[i] = i;
    for (int64_t i = nt - 1; i > 0; i--) {
        int64_t j = bt_int(r, 0, i), x = order[i];
        order[i] = order[j];
        order[j] = x;
    }
    for (int64_t i = 0; i < nv; i++)
        memcpy(q->in.xyz + 3 * perm[i], p->in.xyz + 3 * i, 3 * sizeof(double));
    for (int64_t t = 0; t < nt; t++) {
        const int64_t *src = p->in.tri + 3 * order[t];
        int k = (int)bt_int(r, 0, 2);
        for (int j = 0; j < 3; j++)
            q->in.tri[3 * t + j] = perm[src[(j + k) % 3]];
    }
    free(perm);
    free(order);
}

static void apply_rigid(const double R[9], const double T[3], const double *x, double *y, int with_shift)
{
    for (int c = 0; c < 3; c++)
        y[c] = R[3 * c] * x[0] + R[3 * c + 1] * x[1] + R[3 * c + 2] * x[2] + (with_shift ? T[c] : 0);
}

static void random_rigid(bt_rng *r, double size, double R[9], double T[3])
{
    bt_random_rotation(r, R);
    for (int c = 0; c < 3; c++)
        T[c] = bt_unif(r, -2, 2) * size;
}

enum { V_ORDER, V_RIGID, V_SCALE2, V_SCALE10, V_NONE };
static const char *const VARIANT_NAME[] = {"order", "rigid", "scale2", "scale10", "none"};

/* Which variant an input gets: from its seed, so MFG_BATTERY_INPUT reproduces it; half
 * of the inputs get none (the battery's time). */
static int variant_of(uint64_t seed)
{
    const char *e = getenv("MFG_BATTERY_VARIANTS");
    if (e && *e == '0')
        return V_NONE;
    int k = (int)((seed >> 59) & 7);
    return k < 4 ? k : V_NONE;
}

static void run_variant(const bt_problem *p, const mfg_mesh *m, int variant, verdict *v, timing *tm,
                        const char *dump)
{
    bt_rng r = {p->seed ^ SALT_VARIANT};
    bt_problem q;
    char label[64];
    snprintf(label, sizeof label, "[%s] ", VARIANT_NAME[variant]);
    double vol = volume_of(m->vertices, m->nvertices, m->triangles, m->ntriangles), R[9], T[3], f = 1;
    int k = 0;
    if (variant == V_ORDER) {
        permuted(p, &r, &q);
    } else {
        q = *p;
        q.in = bt_mesh_copy(&p->in);
        if (variant == V_RIGID) {
            random_rigid(&r, p->size, R, T);
            for (int64_t i = 0; i < q.in.nv; i++)
                apply_rigid(R, T, p->in.xyz + 3 * i, q.in.xyz + 3 * i, 1);
            apply_rigid(R, T, p->ap, q.ap, 1);
            apply_rigid(R, T, p->ad, q.ad, 0);
        } else {
            if (variant == V_SCALE2) {
                do
                    k = (int)bt_int(&r, -SCALE2_MAX_EXP, SCALE2_MAX_EXP);
                while (!k);
                f = ldexp(1, k);
            } else {
                do
                    k = (int)bt_int(&r, -SCALE10_MAX_EXP / 3, SCALE10_MAX_EXP / 3) * 3;
                while (!k);
                f = pow(10, k);
            }
            for (int64_t i = 0; i < 3 * q.in.nv; i++)
                q.in.xyz[i] = p->in.xyz[i] * f;
            for (int c = 0; c < 3; c++)
                q.ap[c] = p->ap[c] * f;
            q.tol = p->tol * f;
            q.size = bt_diag(q.in.xyz, q.in.nv);
        }
    }
    if ((variant == V_RIGID || variant == V_SCALE10) && !valid_input(&q)) {
        /* rounding the moved or scaled coordinates broke the solid: not the sweep's fault */
        printf("  note %s 0x%016llx: the %s copy of the input is not a valid solid; variant skipped\n", p->family,
               (unsigned long long)p->seed, VARIANT_NAME[variant]);
        bt_problem_free(&q);
        return;
    }
    mfg_mesh *m2;
    mfg_sweep_stats st;
    double secs;
    mfg_status s = sweep(&q, &m2, &st, &secs);
    tm->sweep += secs;
    double t0 = now();
    unsigned before = v->fails;
    if (!refused(&q, s, v, label)) {
        double vol2 = volume_of(m2->vertices, m2->nvertices, m2->triangles, m2->ntriangles);
        /* Two results of one problem both hold SV and lie within tol of it, so their
         * volumes lie in [vol(SV), vol(SV) + tol area]: a moved or 10^k-scaled input (not
         * exactly the same numbers) may step differently and differ by that much. */
        double vol_slack = VOLUME_REL * vol + p->tol * area_of(m);
        if (variant == V_ORDER) {
            if (!same_arrays(m, m2))
                say(v, F_ORDER, "%sa renumbered, reordered input gave other arrays (%lld / %lld triangles, volume "
                                "%.17g / %.17g)",
                    label, (long long)m->ntriangles, (long long)m2->ntriangles, vol, vol2);
        } else if (variant == V_RIGID) {
            if (!(fabs(vol2 - vol) <= vol_slack))
                say(v, F_RIGID, "%svolume %.12g moved, %.12g in place (rel. %.2e)", label, vol2, vol,
                    (vol2 - vol) / vol);
            /* each result within tol of the other (both hold SV and lie within tol of it) */
            double *moved = malloc((size_t)m->nvertices * 3 * sizeof *moved);
            for (int64_t i = 0; i < m->nvertices; i++)
                apply_rigid(R, T, m->vertices + 3 * i, moved + 3 * i, 1);
            mfg_mesh gm = {m->nvertices, m->ntriangles, moved, m->triangles};
            bt_index ig, i2;
            bt_index_build(&ig, gm.vertices, gm.triangles, gm.ntriangles);
            bt_index_build(&i2, m2->vertices, m2->triangles, m2->ntriangles);
            double bound = p->tol + 2 * bt_allowance(&q), w1, w2;
            long b1 = bt_within_solid(m2, &ig, bound, BT_NEAR_POINTS, p->seed ^ SALT_NEAR_A, &w1);
            long b2 = bt_within_solid(&gm, &i2, bound, BT_NEAR_POINTS, p->seed ^ SALT_NEAR_B, &w2);
            if (b1 || b2)
                say(v, F_RIGID, "%sthe moved result and the result moved differ by more than tol: %ld + %ld of %d "
                                "points, up to %.3g tol",
                    label, b1, b2, 2 * BT_NEAR_POINTS, fmax(w1, w2) / p->tol);
            bt_index_free(&ig);
            bt_index_free(&i2);
            free(moved);
        } else if (variant == V_SCALE2) {
            int same = m->nvertices == m2->nvertices && m->ntriangles == m2->ntriangles &&
                       !memcmp(m->triangles, m2->triangles, (size_t)m->ntriangles * 3 * sizeof(int64_t));
            for (int64_t i = 0; same && i < 3 * m->nvertices; i++)
                same = m2->vertices[i] == ldexp(m->vertices[i], k);
            if (!same)
                say(v, F_SCALE2, "%sscaled by 2^%d: not the result scaled bit for bit (%lld / %lld triangles, "
                                 "volume / 8^k %.17g / %.17g)",
                    label, k, (long long)m->ntriangles, (long long)m2->ntriangles, vol, ldexp(vol2, -3 * k));
        } else {
            double back = vol2 / (f * f * f);
            if (!(fabs(back - vol) <= vol_slack))
                say(v, F_SCALE10, "%sscaled by 1e%d: volume / f^3 %.12g, unscaled %.12g (rel. %.2e)", label, k, back,
                    vol, (back - vol) / vol);
            check_result(&q, m2, v, label, p->seed ^ SALT_SCALED);
        }
        mfg_mesh_free(m2);
    }
    if (v->fails != before && dump) {
        char tag[96];
        snprintf(tag, sizeof tag, "%s_0x%016llx_%s", p->family, (unsigned long long)p->seed, VARIANT_NAME[variant]);
        bt_write_problem(dump, tag, &q);
    }
    bt_problem_free(&q);
    tm->checks += now() - t0;
}

/* ------------------------------------------------------------------------ */
/* One input                                                                */
/* ------------------------------------------------------------------------ */

#define MAX_FAMILIES 16

typedef struct totals {
    long inputs, failing, refused, undecided, undecided_inputs, arcs, coarse_arcs, points;
    long wrong; /* inputs with a result that fails a check (not refused, not timed out) */
    long by_check[F_COUNT];
    /* per family (bt_families' order): inputs, failing, and failures by check */
    long fam_inputs[MAX_FAMILIES], fam_failing[MAX_FAMILIES], fam_check[MAX_FAMILIES][F_COUNT];
    double sweep_s, check_s;
    struct {
        double s;
        char what[96];
    } slowest[5];
} totals;

static void note_slow(totals *tot, double s, const bt_problem *p, int64_t ntri)
{
    int n = (int)(sizeof tot->slowest / sizeof tot->slowest[0]), at = n;
    while (at > 0 && tot->slowest[at - 1].s < s)
        at--;
    if (at == n)
        return;
    memmove(tot->slowest + at + 1, tot->slowest + at, (size_t)(n - 1 - at) * sizeof tot->slowest[0]);
    tot->slowest[at].s = s;
    snprintf(tot->slowest[at].what, sizeof tot->slowest[at].what, "%s:0x%016llx (%lld -> %lld triangles)", p->family,
             (unsigned long long)p->seed, (long long)p->in.nt, (long long)ntri);
}

/* The input being run, for the crash handler: a crash in the library or a check names
 * it (written with write(2): async-signal-safe). */
static char crash_note[160];

#if !defined(__SANITIZE_ADDRESS__) /* AddressSanitizer's own handler says more */
static void on_crash(int sig)
{
    ssize_t n = write(2, crash_note, strlen(crash_note));
    (void)n;
    signal(sig, SIG_DFL);
    raise(sig);
}
#endif

static void run_input(const char *family, uint64_t seed, totals *tot)
{
    snprintf(crash_note, sizeof crash_note, "\nbattery: crashed in MFG_BATTERY_INPUT=%s:0x%016llx\n", family,
             (unsigned long long)seed);
    bt_problem p;
    verdict v;
    memset(&v, 0, sizeof v);
    timing tm = {0, 0};
    const char *dump = getenv("MFG_BATTERY_DUMP");
    if (dump && !*dump)
        dump = NULL;
    tot->inputs++;
    if (!bt_make(family, seed, &p)) {
        say(&v, F_INPUT, "cannot make the input");
        p.what[0] = 0;
    } else {
        if (!valid_input(&p)) /* the battery's own bug */
            say(&v, F_INPUT, "the generated input is not a valid solid: %s", mfg_last_error());
    }
    if (!v.fails) {
        mfg_mesh *m;
        mfg_sweep_stats st;
        mfg_status s = sweep(&p, &m, &st, &tm.sweep);
        double t0 = now();
        if (!refused(&p, s, &v, "")) {
            check_result(&p, m, &v, "", seed);
            tm.checks += now() - t0;
            note_slow(tot, tm.sweep, &p, m->ntriangles);
            int var = variant_of(seed);
            if (getenv("MFG_BATTERY_VERBOSE"))
                printf("  %s 0x%016llx: %lld -> %lld triangles, sweep %.3f s, checks %.3f s%s%s\n", family,
                       (unsigned long long)seed, (long long)p.in.nt, (long long)m->ntriangles, tm.sweep, tm.checks,
                       var != V_NONE ? ", variant " : "", var != V_NONE ? VARIANT_NAME[var] : "");
            if (var != V_NONE)
                run_variant(&p, m, var, &v, &tm, dump);
            mfg_mesh_free(m);
        } else {
            note_slow(tot, tm.sweep, &p, 0);
            tm.checks += now() - t0;
        }
    }
    tot->sweep_s += tm.sweep;
    tot->check_s += tm.checks;
    tot->arcs += v.arcs;
    tot->coarse_arcs += v.coarse_arcs;
    tot->points += v.points;
    if (v.undecided) {
        tot->undecided += v.undecided;
        tot->undecided_inputs++;
    }
    int fam = 0;
    while (fam < bt_nfamilies && strcmp(bt_families[fam], family))
        fam++;
    fam = fam < MAX_FAMILIES ? fam : MAX_FAMILIES - 1;
    tot->fam_inputs[fam]++;
    if (v.fails) {
        if (v.fails & (1u << F_REFUSED))
            tot->refused++;
        if (v.fails & ~(1u << F_REFUSED))
            tot->failing++;
        if (v.fails & ~((1u << F_REFUSED) | (1u << F_TIMEOUT)))
            tot->wrong++;
        tot->fam_failing[fam]++;
        for (int c = 0; c < F_COUNT; c++) {
            tot->by_check[c] += (v.fails >> c) & 1;
            tot->fam_check[fam][c] += (v.fails >> c) & 1;
        }
        printf("FAIL %s 0x%016llx (%s; sweep %.2f s): %s  [MFG_BATTERY_INPUT=%s:0x%016llx]\n", family,
               (unsigned long long)seed, p.what, tm.sweep, v.text, family, (unsigned long long)seed);
        if (dump && p.in.nv) {
            char tag[96];
            snprintf(tag, sizeof tag, "%s_0x%016llx", family, (unsigned long long)seed);
            if (!bt_write_problem(dump, tag, &p))
                fprintf(stderr, "battery: cannot write %s/%s.off\n", dump, tag);
        }
    }
    bt_problem_free(&p);
}

/* ------------------------------------------------------------------------ */
/* The run                                                                  */
/* ------------------------------------------------------------------------ */

/* the seed of the run's i-th input */
static uint64_t input_seed(uint64_t run_seed, long i)
{
    bt_rng r = {run_seed ^ ((uint64_t)i * 0xD1B54A32D192ED03ULL)};
    return bt_next(&r);
}

int main(int argc, char **argv)
{
    const char *e;
    int only_selftest = argc > 1 && !strcmp(argv[1], "selftest");
    /* lines as they come (a crash or a timeout of ctest keeps what was found), and the
     * input named on a crash */
    setvbuf(stdout, NULL, _IOLBF, 0);
#if !defined(__SANITIZE_ADDRESS__)
    static const int fatal[] = {SIGSEGV, SIGBUS, SIGFPE, SIGILL, SIGABRT};
    for (size_t k = 0; k < sizeof fatal / sizeof fatal[0]; k++)
        signal(fatal[k], on_crash);
#endif
    double t_start = now();
    int self = bt_selftest(getenv("MFG_BATTERY_VERBOSE") != NULL);
    printf("battery: self-test of the checks: %d failures (%.2f s)\n", self, now() - t_start);
    if (self || only_selftest)
        return self ? 1 : 0;

    long count = BATTERY_DEFAULT_COUNT;
    uint64_t run_seed = BATTERY_DEFAULT_SEED;
    if ((e = getenv("MFG_BATTERY_COUNT")) && *e)
        count = strtol(e, NULL, 0);
    if ((e = getenv("MFG_BATTERY_SEED")) && *e)
        run_seed = strtoull(e, NULL, 0);
    if ((e = getenv("MFG_BATTERY_TIMEOUT")) && *e)
        timeout_s = strtod(e, NULL);
    const char *only = getenv("MFG_BATTERY_ONLY");
    int only_f = -1;
    if (only && *only) {
        for (int f = 0; f < bt_nfamilies; f++)
            if (!strcmp(only, bt_families[f]))
                only_f = f;
        if (only_f < 0) {
            fprintf(stderr, "battery: unknown family %s\n", only);
            return 2;
        }
    }
    totals tot;
    memset(&tot, 0, sizeof tot);
    if ((e = getenv("MFG_BATTERY_INPUT")) && *e) {
        char fam[32];
        const char *colon = strchr(e, ':');
        if (!colon || colon - e >= (long)sizeof fam) {
            fprintf(stderr, "battery: MFG_BATTERY_INPUT=family:seed\n");
            return 2;
        }
        memcpy(fam, e, (size_t)(colon - e));
        fam[colon - e] = 0;
        run_input(fam, strtoull(colon + 1, NULL, 0), &tot);
    } else {
        /* input i of the run belongs to family i mod F; ONLY keeps that family's inputs
         * of the same run, so their seeds are the ones a full run prints */
        for (long j = 0; j < count; j++) {
            long i = only_f < 0 ? j : only_f + j * bt_nfamilies;
            run_input(bt_families[i % bt_nfamilies], input_seed(run_seed, i), &tot);
        }
    }
    for (int f = 0; f < bt_nfamilies && f < MAX_FAMILIES; f++) {
        if (!tot.fam_inputs[f])
            continue;
        printf("battery: %-9s %3ld inputs, %3ld failing or refused:", bt_families[f], tot.fam_inputs[f],
               tot.fam_failing[f]);
        for (int c = 0; c < F_COUNT; c++)
            if (tot.fam_check[f][c])
                printf(" %s %ld", CHECK_NAME[c], tot.fam_check[f][c]);
        printf("\n");
    }
    printf("battery: %ld inputs, %ld refused, %ld failing (", tot.inputs, tot.refused, tot.failing);
    int any = 0;
    for (int c = 0; c < F_COUNT; c++)
        if (c != F_REFUSED && tot.by_check[c]) {
            printf("%s%s %ld", any ? ", " : "", CHECK_NAME[c], tot.by_check[c]);
            any = 1;
        }
    printf("%s), %ld undecided (tight points, in %ld inputs)\n", any ? "" : "none", tot.undecided,
           tot.undecided_inputs);
    printf("battery: checked %ld turned arcs of input points (%ld at a step coarser than tol/%g: budget) and %ld "
           "result points\n", tot.arcs, tot.coarse_arcs, 1 / BT_FINE_ARC_TOLS, tot.points);
    printf("battery: time %.1f s (processor %.1f s): sweeps %.1f s, checks %.1f s; slowest sweeps:", now() - t_start,
           (double)clock() / CLOCKS_PER_SEC, tot.sweep_s, tot.check_s);
    for (int k = 0; k < 5 && tot.slowest[k].s > 0; k++)
        printf(" %.2f s %s%s", tot.slowest[k].s, tot.slowest[k].what, k < 4 ? "," : "");
    printf("\n");
    /* every refusal, timeout and failed check fails the run (issue 20: 0 refused, 0
     * failing; the known-gap ratchets are gone since 2026-12-06) */
    return tot.wrong || tot.refused || tot.by_check[F_TIMEOUT] ? 1 : 0;
}
