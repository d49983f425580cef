/* Generalised Fresnel integrals and clothoid points, compiled (issue 9; part of the QIC
   kernel, with qic_solve.c, loaded by stimuli/curves/qic_kernel.py).

   I_k(a, b) exp(ic) = int_0^1 t^k exp(i (a t^2/2 + b t + c)) dt, k < 3, are Gauss-Legendre
   sums: numpy's own rules (stimuli/curves/euler.py) where the phase's range p = |a|/2 + |b|
   is at most 4 (where the numpy path sums too), and composite 12-node sums over pieces on
   which the phase moves by at most 2 beyond (where the numpy path uses the Fresnel closed
   form or a series in a); both reach the rounding floor. */

#include <math.h>
#include <stdint.h>

#include "qic_api.h"

/* Gauss-Legendre rules on [0, 1] with 6, 7, 8, 9, 10, 12 and 14 nodes, bit for bit as
   stimuli/curves/euler.py builds them from numpy's leggauss: nodes t, t^2 / 2, weights w / 2. */
static const int GL_Q[7] = {6, 7, 8, 9, 10, 12, 14};
static const int GL_OFF[7] = {0, 6, 13, 21, 30, 40, 52};
static const double GL_T[66] = {
    0.03376524289842403, 0.16939530676686776, 0.38069040695840156,
    0.6193095930415985, 0.8306046932331322, 0.9662347571015759,
    0.0254460438286207, 0.12923440720030277, 0.2970774243113014,
    0.5, 0.7029225756886985, 0.8707655927996972,
    0.9745539561713793, 0.019855071751231912, 0.10166676129318664,
    0.2372337950418355, 0.4082826787521751, 0.5917173212478248,
    0.7627662049581645, 0.8983332387068134, 0.9801449282487681,
    0.015919880246186957, 0.08198444633668212, 0.19331428364970482,
    0.33787328829809554, 0.5, 0.6621267117019045,
    0.8066857163502952, 0.9180155536633179, 0.984080119753813,
    0.013046735741414128, 0.06746831665550773, 0.16029521585048778,
    0.2833023029353764, 0.4255628305091844, 0.5744371694908156,
    0.7166976970646236, 0.8397047841495122, 0.9325316833444923,
    0.9869532642585859, 0.009219682876640378, 0.0479413718147626,
    0.11504866290284765, 0.20634102285669126, 0.31608425050090994,
    0.43738329574426554, 0.5626167042557344, 0.6839157494990901,
    0.7936589771433087, 0.8849513370971523, 0.9520586281852375,
    0.9907803171233596, 0.006858095651593787, 0.03578255816821324,
    0.08639934246511749, 0.15635354759415726, 0.24237568182092295,
    0.3404438155360551, 0.44597252564632817, 0.5540274743536718,
    0.6595561844639448, 0.757624318179077, 0.8436464524058427,
    0.9136006575348825, 0.9642174418317868, 0.9931419043484062,
};
static const double GL_H[66] = {
    0.0005700458139947872, 0.014347384977320616, 0.07246259297507669,
    0.19177218601667517, 0.3449520782104529, 0.4668048029155707,
    0.0003237505732640428, 0.008350766002206834, 0.04412749801771851,
    0.125, 0.24705007370641707, 0.3791163588019041,
    0.47487770674464336, 0.00019711193712328373, 0.005168065175922896,
    0.02813993675497581, 0.08334737288452591, 0.17506469413235076,
    0.2909061417131403, 0.40350130388273625, 0.4803420401858914,
    0.00012672129352646685, 0.0033607247205661548, 0.018685206131499266,
    0.05707917947268399, 0.125, 0.2192058911745885,
    0.32537092248179444, 0.42137627838388403, 0.4842068410473395,
    8.510865675314643e-05, 0.002275986876163931, 0.012847278112277235,
    0.04013009742424389, 0.09055186135549441, 0.16498903084631,
    0.2568277944888675, 0.3525520622617895, 0.43480767022065625,
    0.487038372915339, 4.25012761729079e-05, 0.0011491875657406569,
    0.006618097417866537, 0.021288308856772794, 0.04995462670736099,
    0.09565207369805782, 0.15826877795379227, 0.23387037620645107,
    0.3149472860000815, 0.3915694345150189, 0.4532078157509781,
    0.49082281839953246, 2.351673798320481e-05, 0.0006401957345307821,
    0.0037324231892023273, 0.0122232159226392, 0.02937298556907864,
    0.057950995768373766, 0.09944574681568241, 0.15347322116935425,
    0.2175071802323186, 0.2869973037481557, 0.3558696683284819,
    0.4173330807240848, 0.4648576375663176, 0.49316542108638944,
};
static const double GL_W[66] = {
    0.08566224618958514, 0.18038078652406936, 0.23395696728634552,
    0.23395696728634552, 0.18038078652406936, 0.08566224618958514,
    0.06474248308443487, 0.13985269574463843, 0.19091502525255935,
    0.20897959183673465, 0.19091502525255935, 0.13985269574463843,
    0.06474248308443487, 0.05061426814518853, 0.11119051722668721,
    0.15685332293894344, 0.18134189168918083, 0.18134189168918083,
    0.15685332293894344, 0.11119051722668721, 0.05061426814518853,
    0.04063719418078708, 0.09032408034742868, 0.1303053482014678,
    0.15617353852000146, 0.16511967750062992, 0.15617353852000146,
    0.1303053482014678, 0.09032408034742868, 0.04063719418078708,
    0.03333567215434407, 0.0747256745752902, 0.109543181257991,
    0.13463335965499826, 0.1477621123573764, 0.1477621123573764,
    0.13463335965499826, 0.109543181257991, 0.0747256745752902,
    0.03333567215434407, 0.023587668193255706, 0.05346966299765953,
    0.08003916427167321, 0.10158371336153287, 0.1167462682691773,
    0.12457352290670134, 0.12457352290670134, 0.1167462682691773,
    0.10158371336153287, 0.08003916427167321, 0.05346966299765953,
    0.023587668193255706, 0.017559730165875875, 0.04007904357987999,
    0.060759285343951655, 0.07860158357909681, 0.09276919873896894,
    0.10259923186064786, 0.10763192673157897, 0.10763192673157897,
    0.10259923186064786, 0.09276919873896894, 0.07860158357909681,
    0.060759285343951655, 0.04007904357987999, 0.017559730165875875,
};

/* phase-range bounds of the rules, as _GAUSS_BOUNDS in euler.py (bisect_left) */
static const double GL_BOUND[6] = {0.05, 0.1, 0.25, 0.5, 1.0, 2.0};
/* beyond this phase range the sum would need more than 2 * MAX_PIECES pieces: the segment turns
   by thousands of radians, never a solution; its moments are NaN (a rejected Newton trial) */
#define SINGLE_MAX 4.0
/* up to this phase range, Taylor polynomials of cos and sin instead of libm per node */
#define SERIES_MAX 0.5
/* (-1)^m / (2m)! and (-1)^m / (2m + 1)!, m = 1 .. 7 */
static const double COS_T[7] = {-1.0 / 2, 1.0 / 24, -1.0 / 720, 1.0 / 40320, -1.0 / 3628800,
                                1.0 / 479001600, -1.0 / 87178291200.0};
static const double SIN_T[7] = {-1.0 / 6, 1.0 / 120, -1.0 / 5040, 1.0 / 362880, -1.0 / 39916800,
                                1.0 / 6227020800.0, -1.0 / 1307674368000.0};
#define MAX_PIECES 4096

/* adds the node (weight w at t, w cos, w sin of the phase) to the sums S of X0, Y0, X1, Y1, X2, Y2 */
static inline void add_node(double *S, int nk, double t, double wc, double ws)
{
    S[0] += wc;
    S[1] += ws;
    if (nk > 1) {
        S[2] += t * wc;
        S[3] += t * ws;
        S[4] += t * t * wc;
        S[5] += t * t * ws;
    }
}

/* X[k] + i Y[k] = I_k(a, b) exp(ic), k < nk (1 or 3) */
void attneave_moments(double a, double b, double c, int nk, double *X, double *Y)
{
    double p = 0.5 * fabs(a) + fabs(b);
    double S[6] = {0, 0, 0, 0, 0, 0};
    if (p <= SINGLE_MAX) {
        int r = 0;
        while (r < 6 && p > GL_BOUND[r]) r++;
        const double *t = GL_T + GL_OFF[r], *h = GL_H + GL_OFF[r], *w = GL_W + GL_OFF[r];
        int q = GL_Q[r];
        if (p <= SERIES_MAX) {
            /* sum exp(i psi), psi = a t^2/2 + b t, by its Taylor polynomials (|psi| <= 1/2: the
               first omitted terms are below 1e-18) and turn the sums by exp(ic) once: one sincos
               per segment instead of one per node */
            for (int j = 0; j < q; j++) {
                double psi = h[j] * a + t[j] * b, z = psi * psi;
                double cp = 1.0 + z * (COS_T[0] + z * (COS_T[1] + z * (COS_T[2] + z * (COS_T[3]
                            + z * (COS_T[4] + z * (COS_T[5] + z * COS_T[6]))))));
                double sp = psi * (1.0 + z * (SIN_T[0] + z * (SIN_T[1] + z * (SIN_T[2] + z * (SIN_T[3]
                            + z * (SIN_T[4] + z * (SIN_T[5] + z * SIN_T[6])))))));
                add_node(S, nk, t[j], w[j] * cp, w[j] * sp);
            }
            double cc = cos(c), sc = sin(c);
            for (int k = 0; k < 6; k += 2) {
                double u = S[k];
                S[k] = cc * u - sc * S[k + 1];
                S[k + 1] = sc * u + cc * S[k + 1];
            }
        } else {
            for (int j = 0; j < q; j++) {
                double th = h[j] * a + t[j] * b + c;
                add_node(S, nk, t[j], w[j] * cos(th), w[j] * sin(th));
            }
        }
    } else {
        /* on a piece of width 1/m the phase moves by at most (|a| + |b|) / m <= 2 */
        double pieces = ceil(0.5 * (fabs(a) + fabs(b)));
        if (!(pieces <= MAX_PIECES)) { /* also NaN */
            for (int k = 0; k < nk; k++) X[k] = Y[k] = NAN;
            return;
        }
        long m = (long)pieces;
        double hw = 1.0 / (double)m;
        const double *t = GL_T + GL_OFF[5], *w = GL_W + GL_OFF[5];
        for (long i = 0; i < m; i++) {
            for (int j = 0; j < 12; j++) {
                double tt = i * hw + hw * t[j];
                double th = (0.5 * a * tt + b) * tt + c, ww = hw * w[j];
                add_node(S, nk, tt, ww * cos(th), ww * sin(th));
            }
        }
    }
    for (int k = 0; k < nk; k++) {
        X[k] = S[2 * k];
        Y[k] = S[2 * k + 1];
    }
}

/* Points of clothoids (euler.clothoid_points): x + i y = x0 + i y0 + s exp(i theta0) I_0(dk s^2, k s)
   for n samples, every argument an array of n. */
void attneave_clothoid_points(long n, const double *x0, const double *y0, const double *theta0,
                              const double *k, const double *dk, const double *s, double *x, double *y)
{
    for (long i = 0; i < n; i++) {
        double X, Y, si = s[i];
        attneave_moments(dk[i] * si * si, k[i] * si, theta0[i], 1, &X, &Y);
        x[i] = x0[i] + X * si;
        y[i] = y0[i] + Y * si;
    }
}

/* The number of samples sample_by_turn gives a segment: as few as keep the tangent's change between
   neighbours at most max_step (curvature is linear on a segment: |k| at an end bounds it), at least
   3 and at most max(max_samples, 3). */
static long turn_count(double k0, double dk, double L, double max_step, long max_samples)
{
    long hi = max_samples > 3 ? max_samples : 3;
    double kmax = fmax(fabs(k0), fabs(k0 + dk * L));
    long c = (long)ceil(fmin(L * kmax / max_step, (double)max_samples)) + 1;
    return c < 3 ? 3 : (c > hi ? hi : c);
}

/* c points of one segment, equally spaced in arc length, to x[q * stride], y[q * stride]; the last
   one put on (xe, ye) exactly. Each sample from the one before: the integral over the step turns by
   about the tangent's change between samples, a cheap sum, where from the segment's start it would
   turn by up to the whole segment's (an error of ~1e-16 of the step per step). The first sample is
   the start (a step of length 0 adds +0.0) and the last is put on (xe, ye): neither needs the
   integral, which on smooth curves (3 samples a segment) saves two of its three evaluations. */
static void segment_points(double x0, double y0, double theta0, double k0, double dk, double L,
                           double xe, double ye, long c, double *x, double *y, long stride)
{
    double px = 0.0, py = 0.0, ps = 0.0; /* from the start: rounding at the segment's scale */
    x[0] = x0 + px;
    y[0] = y0 + py;
    for (long q = 1; q < c - 1; q++) {
        double u = (double)q / (double)(c - 1), sl = L * u, X, Y, d = sl - ps;
        double tprev = theta0 + k0 * ps + 0.5 * dk * ps * ps;
        attneave_moments(dk * d * d, (k0 + dk * ps) * d, tprev, 1, &X, &Y);
        px += X * d;
        py += Y * d;
        ps = sl;
        x[q * stride] = x0 + px;
        y[q * stride] = y0 + py;
    }
    x[(c - 1) * stride] = xe;
    y[(c - 1) * stride] = ye;
}

/* The samples of QICSpline.sample and sample_by_turn: counts[j] (>= 2) points on segment j
   (x0, y0, theta0, k0, dk, L) equally spaced in arc
   length, the last one on the next point, exactly. With max_step > 0 the counts are chosen here
   (turn_count) and written to counts. Rows of out (5 x cap, cap >= the total): s from the first
   point, x, y, tangent angle and sign * curvature. Returns the total. */
long attneave_sample_segments(long m, int64_t *counts, double max_step, long max_samples,
                              const double *x0, const double *y0, const double *theta0,
                              const double *k0, const double *dk, const double *L,
                              const double *xe, const double *ye, double sign, long cap, double *out)
{
    double *s = out, *x = out + cap, *y = out + 2 * cap, *th = out + 3 * cap, *kk = out + 4 * cap;
    double offset = 0.0;
    long i = 0;
    for (long j = 0; j < m; j++) {
        if (max_step > 0.0)
            counts[j] = turn_count(k0[j], dk[j], L[j], max_step, max_samples);
        long c = (long)counts[j];
        segment_points(x0[j], y0[j], theta0[j], k0[j], dk[j], L[j], xe[j], ye[j], c, x + i, y + i, 1);
        for (long q = 0; q < c; q++, i++) {
            double sl = L[j] * ((double)q / (double)(c - 1));
            s[i] = offset + sl;
            th[i] = theta0[j] + k0[j] * sl + 0.5 * dk[j] * sl * sl;
            kk[i] = sign * (k0[j] + dk[j] * sl);
        }
        offset += L[j];
    }
    return i;
}

/* The robust rule's checks on the samples of attneave_sample_segments with max_step > 0 (the same
   points), without the rows it does not need. Segment j runs from point start[j] of the n points P
   (x, y interleaved) to the next (cyclic); seg holds 4 rows of m: theta0, k0, dk, L. Written to out:
   x, y interleaved (2 x cap doubles, cap >= the total; the layout GEOS takes), then per segment the
   largest distance of its samples from the line through its chord (m doubles; the bulge before
   division by the mean chord), computed as segment_bulge in qic_rule.py does, operation for
   operation. Returns the total. */
long attneave_turn_samples(long m, double max_step, long max_samples, long cap, const double *P, long n,
                           const int64_t *start, const double *seg, double *out)
{
    const double *theta0 = seg, *k0 = seg + m, *dk = seg + 2 * m, *L = seg + 3 * m;
    double *dist = out + 2 * cap;
    long i = 0;
    for (long j = 0; j < m; j++) {
        long a = (long)start[j], b = (a + 1) % n;
        double x0 = P[2 * a], y0 = P[2 * a + 1], xe = P[2 * b], ye = P[2 * b + 1];
        long c = turn_count(k0[j], dk[j], L[j], max_step, max_samples);
        double *x = out + 2 * i, *y = x + 1;
        segment_points(x0, y0, theta0[j], k0[j], dk[j], L[j], xe, ye, c, x, y, 2);
        double dx = xe - x0, dy = ye - y0, r = hypot(dx, dy), ux = dx / r, uy = dy / r;
        double big = 0.0;
        for (long q = 0; q < c; q++) {
            double cr = fabs((x[2 * q] - x0) * uy - (y[2 * q] - y0) * ux);
            if (cr > big || cr != cr)
                big = cr;
        }
        dist[j] = big;
        i += c;
    }
    return i;
}
