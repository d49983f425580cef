/* The pure G2 QIC solve of one piece, compiled (issue 9).

   Plain C99, no Python C-API: loaded with ctypes by stimuli/curves/qic_kernel.py, which
   documents the calls (named apart: an extension module would shadow the Python module).
   It does what the numpy reference does (stimuli/curves/qic.py _solve_piece, stimuli/curves/qic_newton.py solve_nodes,
   stimuli/curves/euler.py segment_state and add_derivatives) step for step:
   chords and their circle-tangent end angles, the small-angle start, damped
   Newton on the node angles with A eliminated and the (cyclic) tridiagonal
   system solved by LAPACK's dgtsv algorithm (Sherman-Morrison for the corners),
   and the segments in pixels. The generalised Fresnel integrals are in
   clothoid_moments.c. */

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "qic_api.h"

#define PI 3.14159265358979323846

/* attneave_moments (clothoid_moments.c, declared in qic_api.h):
   X[k] + i Y[k] = I_k(a, b) exp(ic), k < nk (1 or 3) */

/* wrap to (-pi, pi], as euler.wrap_angle: pi - mod(pi - a, 2 pi) with a floored mod */
static double wrap(double a)
{
    const double tp = 2.0 * PI;
    double m = fmod(PI - a, tp);
    if (m < 0.0) m += tp;
    return PI - m;
}

/* euler.guess_A: Bertolazzi & Frego's polynomial refinement of 3 (phi0 + phi1) */
static double guess_A(double p0, double p1)
{
    static const double CF[6] = {2.989696028701907, 0.716228953608281, -0.458969738821509,
                                 -0.502821153340377, 0.261062141752652, -0.045854475238709};
    double X = p0 / PI, Y = p1 / PI, xy = X * Y, X2 = X * X, Y2 = Y * Y;
    return (p0 + p1) * (CF[0] + xy * (CF[1] + xy * CF[2]) + (CF[3] + xy * CF[4]) * (X2 + Y2)
                        + CF[5] * (X2 * X2 + Y2 * Y2));
}

/* LAPACK dgtsv (reference algorithm, partial pivoting) for one or two right-hand sides
   b0, b1 (b1 may be NULL); dl (n - 1), d (n), du (n - 1) are overwritten. 0 or the LAPACK info. */
static long gtsv(long n, double *dl, double *d, double *du, double *b0, double *b1)
{
    for (long i = 0; i < n - 1; i++) {
        if (fabs(d[i]) >= fabs(dl[i])) {
            if (d[i] == 0.0) return i + 1;
            double f = dl[i] / d[i];
            d[i + 1] -= f * du[i];
            b0[i + 1] -= f * b0[i];
            if (b1) b1[i + 1] -= f * b1[i];
            if (i < n - 2) dl[i] = 0.0;
        } else {
            double f = d[i] / dl[i], tmp;
            d[i] = dl[i];
            tmp = d[i + 1];
            d[i + 1] = du[i] - f * tmp;
            if (i < n - 2) {
                dl[i] = du[i + 1];
                du[i + 1] = -f * dl[i];
            }
            du[i] = tmp;
            tmp = b0[i];
            b0[i] = b0[i + 1];
            b0[i + 1] = tmp - f * b0[i + 1];
            if (b1) {
                tmp = b1[i];
                b1[i] = b1[i + 1];
                b1[i + 1] = tmp - f * b1[i + 1];
            }
        }
    }
    if (d[n - 1] == 0.0) return n;
    for (int c = 0; c < 2; c++) {
        double *b = c ? b1 : b0;
        if (!b) break;
        b[n - 1] /= d[n - 1];
        if (n > 1) b[n - 2] = (b[n - 2] - du[n - 2] * b[n - 1]) / d[n - 2];
        for (long i = n - 3; i >= 0; i--) b[i] = (b[i] - du[i] * b[i + 1] - dl[i] * b[i + 2]) / d[i];
    }
    return 0;
}

/* qic_newton.solve_tridiagonal: x (in rhs) of the (cyclic) system sub[i] x[i-1] + diag[i] x[i] +
   sup[i] x[i+1] = rhs[i]; sub, diag, sup are overwritten, z is scratch (n). 0, or -1 if singular. */
static int solve_tridiagonal(long n, int cyclic, double *sub, double *diag, double *sup, double *rhs, double *z)
{
    if (!cyclic || n < 3) {
        if (n == 1) {
            rhs[0] /= diag[0];
            return 0;
        }
        return gtsv(n, sub + 1, diag, sup, rhs, NULL) ? -1 : 0;
    }
    double top = sub[0], bottom = sup[n - 1], d0 = diag[0];
    double gamma = d0 != 0.0 ? -d0 : 1.0;
    diag[0] = d0 - gamma;
    diag[n - 1] -= top * bottom / gamma;
    memset(z, 0, n * sizeof(double));
    z[0] = gamma;
    z[n - 1] = bottom;
    if (gtsv(n, sub + 1, diag, sup, rhs, z)) return -1;
    double f = top / gamma;
    double vy = rhs[0] + f * rhs[n - 1], vz = z[0] + f * z[n - 1];
    double s = vy / (1.0 + vz);
    for (long i = 0; i < n; i++) rhs[i] -= s * z[i];
    return 0;
}

/* one Newton state: everything about the segments at given node angles and A */
typedef struct {
    double *phi0, *delta, *X0, *G, *X1, *Y1, *X2, *Y2, *L, *k0, *k1, *F;
    double merit;
} state_t;

typedef struct {
    long m, n;      /* segments, nodes */
    int closed, free_start, free_end;
    const double *r, *p0i, *p1i;
    const unsigned char *hold; /* NULL or n flags */
} problem_t;

/* the end node of segment j */
static inline long next_node(const problem_t *pb, long j) { return j + 1 < pb->n ? j + 1 : 0; }

/* qic_newton.solve_nodes's state(): 0 where a segment degenerates (X0 <= 0, L infinite, NaN) */
static int compute_state(const problem_t *pb, const double *d, const double *A, state_t *s)
{
    long m = pb->m, n = pb->n;
    for (long j = 0; j < m; j++) {
        double phi0 = pb->p0i[j] + d[j], phi1 = pb->p1i[j] + d[next_node(pb, j)];
        double delta = phi1 - phi0, a = A[j];
        double X[3], Y[3];
        attneave_moments(2.0 * a, delta - a, phi0, 3, X, Y);
        double L = pb->r[j] / X[0];
        if (!(X[0] > 0.0) || !(L < INFINITY)) return 0;
        s->phi0[j] = phi0;
        s->delta[j] = delta;
        s->X0[j] = X[0];
        s->G[j] = Y[0];
        s->X1[j] = X[1];
        s->Y1[j] = Y[1];
        s->X2[j] = X[2];
        s->Y2[j] = Y[2];
        s->L[j] = L;
        s->k0[j] = (delta - a) / L;
        s->k1[j] = (delta + a) / L;
    }
    /* residuals: curvature jumps at the nodes (qic_newton._residual) */
    double *F = s->F;
    if (pb->closed) {
        for (long i = 0; i < n; i++) F[i] = s->k1[i ? i - 1 : n - 1] - s->k0[i];
    } else {
        for (long i = 1; i < n - 1; i++) F[i] = s->k1[i - 1] - s->k0[i];
        F[0] = pb->free_start ? s->k0[0] : 0.0;
        F[n - 1] = pb->free_end ? s->k1[m - 1] : 0.0;
    }
    if (pb->hold)
        for (long i = 0; i < n; i++)
            if (pb->hold[i]) F[i] = 0.0;
    double merit = 0.0;
    for (long i = 0; i < n; i++) merit += F[i] * F[i];
    for (long j = 0; j < m; j++) merit += s->G[j] * s->G[j];
    s->merit = merit;
    return 1;
}

/* euler.add_derivatives (full=False) and qic_newton._linear_system: the tridiagonal Newton system
   in the node-angle increments (sub, diag, sup, rhs) and dA (3 x m), the change of A along the
   closure constraint per unit of (theta0, theta1, G) */
static void linear_system(const problem_t *pb, const state_t *s, const double *A, double *dA,
                          double *dK, double *sub, double *diag, double *sup, double *rhs)
{
    long m = pb->m, n = pb->n;
    /* dK: 6 rows of m, (k0, k1) by (theta0, theta1, r) */
    for (long j = 0; j < m; j++) {
        double X0 = s->X0[j], Y0 = s->G[j], X1 = s->X1[j], Y1 = s->Y1[j], X2 = s->X2[j], Y2 = s->Y2[j];
        double r = pb->r[j], a = A[j];
        double g = -1.0 / (X2 - X1);
        double dA0 = (X0 - X1) * g, dA1 = X1 * g, dA2 = Y0 * g;
        dA[j] = dA0;
        dA[m + j] = dA1;
        dA[2 * m + j] = dA2;
        double y12 = Y1 - Y2;
        double dX0 = y12 * dA0 + (Y1 - Y0), dX1 = y12 * dA1 - Y1, dX2 = y12 * dA2;
        double n0 = (s->delta[j] - a) / r, n1 = (s->delta[j] + a) / r, xr = X0 / r;
        dK[j] = n0 * dX0 + (-1.0 - dA0) * xr;
        dK[m + j] = n0 * dX1 + (1.0 - dA1) * xr;
        dK[2 * m + j] = n0 * dX2 + (0.0 - dA2) * xr;
        dK[3 * m + j] = n1 * dX0 + (-1.0 + dA0) * xr;
        dK[4 * m + j] = n1 * dX1 + (1.0 + dA1) * xr;
        dK[5 * m + j] = n1 * dX2 + (0.0 + dA2) * xr;
    }
    const double *k0t0 = dK, *k0t1 = dK + m, *k0r = dK + 2 * m;
    const double *k1t0 = dK + 3 * m, *k1t1 = dK + 4 * m, *k1r = dK + 5 * m;
    const double *F = s->F;
    if (pb->closed) {
        for (long i = 0; i < n; i++) {
            long p = i ? i - 1 : n - 1;
            sub[i] = k1t0[p];
            diag[i] = k1t1[p] - k0t0[i];
            sup[i] = -k0t1[i];
            rhs[i] = (k0r[i] - F[i]) - k1r[p];
        }
    } else {
        for (long i = 0; i < n; i++) {
            sub[i] = 0.0;
            diag[i] = 1.0;
            sup[i] = 0.0;
            rhs[i] = 0.0;
        }
        for (long i = 1; i < n - 1; i++) {
            sub[i] = k1t0[i - 1];
            diag[i] = k1t1[i - 1] - k0t0[i];
            sup[i] = -k0t1[i];
            rhs[i] = -((F[i] + k1r[i - 1]) - k0r[i]);
        }
        if (pb->free_start) {
            diag[0] = k0t0[0];
            sup[0] = k0t1[0];
            rhs[0] = -(F[0] + k0r[0]);
        }
        if (pb->free_end) {
            sub[n - 1] = k1t0[m - 1];
            diag[n - 1] = k1t1[m - 1];
            rhs[n - 1] = -(F[n - 1] + k1r[m - 1]);
        }
    }
    if (pb->hold)
        for (long i = 0; i < n; i++)
            if (pb->hold[i]) {
                sub[i] = 0.0;
                diag[i] = 1.0;
                sup[i] = 0.0;
                rhs[i] = 0.0;
            }
}

/* qic_newton.small_angle_start: node-angle increments of the small-angle G2 spline, in d;
   -1 if the system is singular */
static int small_angle_start(const problem_t *pb, double *d, double *sub, double *diag, double *sup, double *z)
{
    long m = pb->m, n = pb->n;
    const double *r = pb->r, *p0 = pb->p0i, *p1 = pb->p1i;
    if (pb->closed) {
        for (long i = 0; i < n; i++) {
            long p = i ? i - 1 : n - 1;
            double w = 2.0 / r[i], wp = 2.0 / r[p];
            double c0 = (p0[i] + p1[i] + p0[i]) * w, c1p = (p0[p] + p1[p] + p1[p]) * wp;
            sub[i] = wp;
            sup[i] = w;
            diag[i] = (wp + w) * 2.0;
            d[i] = -(c1p + c0);
        }
    } else {
        for (long i = 0; i < n; i++) sub[i] = diag[i] = sup[i] = d[i] = 0.0;
        for (long j = 0; j < m; j++) {
            double w = 2.0 / r[j], s = p0[j] + p1[j];
            sub[j + 1] = w;
            sup[j] = w;
            diag[j] += 2.0 * w;
            diag[j + 1] += 2.0 * w;
            d[j] -= (s + p0[j]) * w;
            d[j + 1] -= (s + p1[j]) * w;
        }
        if (!pb->free_start) sup[0] = 0.0, diag[0] = 1.0, d[0] = 0.0;
        if (!pb->free_end) sub[n - 1] = 0.0, diag[n - 1] = 1.0, d[n - 1] = 0.0;
    }
    if (pb->hold)
        for (long i = 0; i < n; i++)
            if (pb->hold[i]) sub[i] = 0.0, diag[i] = 1.0, sup[i] = 0.0, d[i] = 0.0;
    return solve_tridiagonal(n, pb->closed, sub, diag, sup, d, z);
}

/* status codes, as qic_kernel.py reads them */
#define QIC_OK 0
#define QIC_NO_START 1   /* the initial guess gives a degenerate segment */
#define QIC_NO_CONVERGENCE 2
#define QIC_DEGENERATE 3 /* converged towards a segment far longer than its chord */
#define QIC_NO_MEMORY 4

#define MIN_X0 1e-6      /* qic._MIN_X0 */

static void end_angles(problem_t *pb, const double *phi, double t_start, double t_end, double *p0, double *p1)
{
    long m = pb->m;
    const double *r = pb->r;
    if (pb->closed) {
        double beta_first = 0.0;
        for (long j = 0; j < m; j++) {
            long p = j ? j - 1 : m - 1;
            double t = wrap(phi[j] - phi[p]);
            /* inscribed angle: between 0 and the turn t */
            double beta = atan2(r[p] * sin(t), r[j] + r[p] * cos(t));
            p0[j] = beta - t;
            if (j) p1[p] = beta;
            else beta_first = beta;
        }
        p1[m - 1] = beta_first;
        return;
    }
    for (long j = 0; j < m; j++) p0[j] = p1[j] = 0.0;
    for (long j = 0; j + 1 < m; j++) {
        double t = wrap(phi[j + 1] - phi[j]);
        double beta = atan2(r[j] * sin(t), r[j + 1] + r[j] * cos(t));
        p1[j] = beta;
        p0[j + 1] = beta - t;
    }
    int has_s = !isnan(t_start), has_e = !isnan(t_end);
    if (has_s) p0[0] = wrap(t_start - phi[0]);
    if (has_e) p1[m - 1] = wrap(t_end - phi[m - 1]);
    if (!has_s) p0[0] = (m > 1 || has_e) ? -0.5 * p1[0] : 0.0;
    if (!has_e) p1[m - 1] = (m > 1 || has_s) ? -0.5 * p0[m - 1] : 0.0;
}

/* The pure G2 QIC spline through the npts points xy (x0, y0, x1, y1, ...) of one piece: closed,
   or open with tangent angles t_start / t_end (NaN: a natural end). theta_hold: NULL, or per node
   the tangent angle at which a G1 node is held (NaN: free; ignored at an open piece's ends).
   out (7 m + 8 doubles) receives theta0, k0, dk, L, turn, chord_dev, X0 (rows of m), then
   iterations, status, g2, closure, miss. Returns the status. */
long attneave_qic_piece(const double *xy, long npts, long closed, double t_start, double t_end,
                        const double *theta_hold, double tol, long max_iter, long max_halvings,
                        double *out)
{
    problem_t pb;
    long m = closed ? npts : npts - 1, n = npts;
    pb.m = m;
    pb.n = n;
    pb.closed = (int)closed;
    pb.free_start = closed || isnan(t_start);
    pb.free_end = closed || isnan(t_end);
    double *info = out + 7 * m;
    for (int i = 0; i < 8; i++) info[i] = 0.0;
    /* one block: 5 m (r, rn, phi, p0i, p1i) + 4 n (d, dd, d trial, z) + 2 m (A, A trial)
       + 3 m (dA) + 6 m (dK) + 4 n (system) + 2 states (11 m + n) + n flags */
    size_t nd = (size_t)(5 * m + 4 * n + 2 * m + 3 * m + 6 * m + 4 * n + 2 * (11 * m + n));
    double *w = malloc(nd * sizeof(double) + (size_t)n);
    if (!w) {
        info[1] = QIC_NO_MEMORY;
        return QIC_NO_MEMORY;
    }
    double *r = w, *rn = r + m, *phi = rn + m, *p0i = phi + m, *p1i = p0i + m;
    double *d = p1i + m, *dd = d + n, *dt = dd + n, *z = dt + n;
    double *A = z + n, *At = A + m, *dA = At + m, *dK = dA + 3 * m;
    double *sub = dK + 6 * m, *diag = sub + n, *sup = diag + n, *rhs = sup + n;
    state_t S[2];
    double *q = rhs + n;
    for (int k = 0; k < 2; k++) {
        double **f[] = {&S[k].phi0, &S[k].delta, &S[k].X0, &S[k].G, &S[k].X1, &S[k].Y1, &S[k].X2,
                        &S[k].Y2, &S[k].L, &S[k].k0, &S[k].k1};
        for (int i = 0; i < 11; i++, q += m) *f[i] = q;
        S[k].F = q;
        q += n;
    }
    unsigned char *hold = (unsigned char *)q;

    /* chords, scaled by their mean (the piece's scale) */
    double h = 0.0;
    for (long j = 0; j < m; j++) {
        long e = j + 1 < npts ? j + 1 : 0;
        double dx = xy[2 * e] - xy[2 * j], dy = xy[2 * e + 1] - xy[2 * j + 1];
        r[j] = hypot(dx, dy);
        phi[j] = atan2(dy, dx);
        h += r[j];
    }
    h /= (double)m;
    for (long j = 0; j < m; j++) rn[j] = r[j] / h;
    pb.r = rn;
    end_angles(&pb, phi, t_start, t_end, p0i, p1i);
    pb.hold = NULL;
    if (theta_hold) {
        for (long k = 0; k < n; k++) {
            hold[k] = !isnan(theta_hold[k]) && (closed || (k > 0 && k < n - 1));
            if (!hold[k]) continue;
            pb.hold = hold;
            if (k < m) p0i[k] = wrap(theta_hold[k] - phi[k]);
            long km = k > 0 ? k - 1 : (closed ? m - 1 : -1);
            if (km >= 0) p1i[km] = wrap(theta_hold[k] - phi[km]);
        }
    }
    pb.p0i = p0i;
    pb.p1i = p1i;

    /* the small-angle start (beyond a radian: the circle tangents and guess_A) */
    state_t *s = &S[0], *st = &S[1];
    int have = 0, started = small_angle_start(&pb, d, sub, diag, sup, z) == 0;
    double big = 0.0;
    for (long i = 0; started && i < n; i++) big = fmax(big, fabs(d[i]));
    if (started && big <= 1.0) { /* NaN fails */
        for (long j = 0; j < m; j++) A[j] = 3.0 * (((p0i[j] + d[j]) + p1i[j]) + d[next_node(&pb, j)]);
        have = compute_state(&pb, d, A, s);
    }
    if (!have) {
        int moved = 0;
        for (long i = 0; i < n; i++) moved |= started && big <= 1.0 && d[i] != 0.0;
        if (!(started && big <= 1.0) || moved) {
            for (long i = 0; i < n; i++) d[i] = 0.0;
            for (long j = 0; j < m; j++) A[j] = guess_A(p0i[j], p1i[j]);
            have = compute_state(&pb, d, A, s);
        }
    }
    if (!have) {
        free(w);
        info[1] = QIC_NO_START;
        return QIC_NO_START;
    }

    long it = 0;
    double kmax, fres, gres;
    for (;;) {
        kmax = fres = gres = 0.0;
        for (long j = 0; j < m; j++) {
            kmax = fmax(kmax, fmax(fabs(s->k0[j]), fabs(s->k1[j])));
            gres = fmax(gres, fabs(s->G[j]));
        }
        for (long i = 0; i < n; i++) fres = fmax(fres, fabs(s->F[i]));
        if ((fres <= tol * kmax && gres <= 1e-14) || it >= max_iter) break;
        linear_system(&pb, s, A, dA, dK, sub, diag, sup, rhs);
        if (solve_tridiagonal(n, pb.closed, sub, diag, sup, rhs, z)) break;
        big = 0.0;
        for (long i = 0; i < n; i++) {
            dd[i] = rhs[i];
            big = isnan(dd[i]) ? NAN : fmax(big, fabs(dd[i]));
        }
        if (!(big < INFINITY)) break;
        double *dAs = dK; /* dK is no longer needed: the change of A along the closure */
        for (long j = 0; j < m; j++) dAs[j] = dA[j] * dd[j] + dA[2 * m + j] + dA[m + j] * dd[next_node(&pb, j)];
        /* a step of more than one radian in any angle leaves the linearisation's region */
        double step = fmin(1.0, 1.0 / fmax(big, 1e-300));
        int accepted = 0;
        for (long hv = 0; hv < max_halvings; hv++) {
            for (long i = 0; i < n; i++) dt[i] = d[i] + step * dd[i];
            for (long j = 0; j < m; j++) At[j] = A[j] + step * dAs[j];
            if (compute_state(&pb, dt, At, st) && st->merit <= (1.0 - 1e-4 * step) * s->merit) {
                accepted = 1;
                break;
            }
            step *= 0.5;
        }
        it++;
        if (!accepted) break;
        double *tmp = d;
        d = dt;
        dt = tmp;
        tmp = A;
        A = At;
        At = tmp;
        state_t *ts = s;
        s = st;
        st = ts;
    }
    /* the rounding floor can stop the last halving short of tol: accept what is still far inside
       the documented guarantee */
    int ok = (fres <= fmax(tol, 1e-11) * kmax || fres <= 1e-14) && gres <= 1e-13;
    double minx = INFINITY, miss = 0.0;
    for (long j = 0; j < m; j++) {
        minx = fmin(minx, s->X0[j]);
        miss = fmax(miss, fabs(r[j] * s->G[j] / s->X0[j]));
    }
    long status = !ok ? QIC_NO_CONVERGENCE : (minx < MIN_X0 ? QIC_DEGENERATE : QIC_OK);
    info[0] = (double)it;
    info[1] = (double)status;
    info[2] = kmax > 0.0 ? fres / kmax : 0.0;
    info[3] = gres;
    info[4] = miss;
    /* the segments in pixels, and each one's tangent range (qic_newton.tangent_range) */
    double *theta0 = out, *k0 = out + m, *dk = out + 2 * m, *L = out + 3 * m;
    double *turn = out + 4 * m, *chord_dev = out + 5 * m, *X0 = out + 6 * m;
    for (long j = 0; j < m; j++) {
        double p0 = s->phi0[j], delta = s->delta[j], a = A[j];
        theta0[j] = phi[j] + p0;
        k0[j] = s->k0[j] / h;
        dk[j] = (s->k1[j] - s->k0[j]) / s->L[j] / (h * h);
        L[j] = s->L[j] * h;
        X0[j] = s->X0[j];
        double tv = a != 0.0 ? (a - delta) / (2.0 * a) : 0.0;
        tv = tv < 0.0 ? 0.0 : (tv > 1.0 ? 1.0 : tv);
        double thv = (delta - a) * tv + a * tv * tv;
        double hi = fmax(fmax(0.0, delta), thv), lo = fmin(fmin(0.0, delta), thv);
        turn[j] = hi - lo;
        chord_dev[j] = fmax(fabs(p0 + hi), fabs(p0 + lo));
    }
    free(w);
    return status;
}
