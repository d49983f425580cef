/*
 * The exact area-coverage rasteriser's inner loops in plain C99 (issue 13).
 *
 * Loaded through ctypes by stimuli/render/kernel.py; the numpy functions of
 * stimuli/render/raster.py are the reference, and this file follows them:
 *
 * - coordinates are shifted by +0.5, so that pixel (r, c) is the square
 *   [c, c+1] x [r, r+1];
 * - every piece between grid lines adds dx * (1 - f) to its pixel and
 *   dx * f to the pixel below, f = its mean height in the pixel minus the
 *   pixel's row (the signed area between the piece and the pixel's bottom
 *   side, and the rest of its cover);
 * - pieces left or right of the image add nothing, pieces above it are
 *   flattened onto its top edge, pieces below it onto its bottom edge;
 * - a column prefix sum then gives the winding integral of every pixel.
 *
 * This file cuts segments into pieces and deposits them; attneave_deposit
 * fills a buffer over the shape's whole box (float, 16-bit and disc images
 * need the integral there). The 8-bit renderers of coverage_bands.c
 * (attneave_ring_u8, attneave_stream_u8) cut the same pieces band by band.
 *
 * No Python C-API: plain functions on pointers, so the file builds with any
 * C99 compiler and its loading cannot break the interpreter.
 */
#include "coverage_kernel.h"
#include "coverage_api.h"

/* One piece inside pixel (r, c) (`cells`: the buffer's row r): deposit
 * it. Cutting knows the pixel, and the area is added per segment (the
 * integral of (h - y) dx; see part_area). */
static inline void deposit(const struct grid *g, double *cells, double r, const double *a,
                           const double *b, long c)
{
    double dx = b[0] - a[0];
    if (dx == 0.0)
        return;
    double f = 0.5 * (a[1] + b[1]) - r;
    c -= g->c0;
    c = c < 0 ? 0 : (c >= g->stride ? g->stride - 1 : c); /* never outside the buffer */
    double *cell = cells + c;
    cell[0] += dx - dx * f;
    cell[g->stride] += dx * f;
}

/* Flag the blocks of columns c .. d (either order) of buffer row i and the
 * row below, which a row piece deposited into. */
static inline void flag(const struct grid *g, long i, long c, long d)
{
    long lo = (c < d ? c : d) - g->c0, hi = (c < d ? d : c) - g->c0;
    lo = lo < 0 ? 0 : lo;
    hi = hi >= g->stride ? g->stride - 1 : hi;
    unsigned char *m = g->dirty + i * g->blocks;
    for (long k = lo / BLOCK; k <= hi / BLOCK; k++)
        m[k] = m[k + g->blocks] = 1;
}

/* Cut a piece a -> b of row r where it crosses the column lines and
 * deposit the parts. Crossing points have integral x, y interpolated from
 * a. A vertical piece adds nothing. */
static void cut_columns(struct grid *g, const double *a, const double *b, long r)
{
    double a0 = a[0], a1 = b[0];
    if (a0 == a1)
        return;
    long i = r - g->r0;
    i = i < 0 ? 0 : (i >= g->bh ? g->bh - 1 : i); /* never outside the buffer */
    double *cells = g->acc + i * g->stride, fr = (double)r;
    long first, c;
    if (floor0(a0) == floor0(a1)) {
        first = c = (long)a0;
        deposit(g, cells, fr, a, b, c);
    } else {
        double slope = (b[1] - a[1]) / (a1 - a0);
        double p[2] = {a[0], a[1]}, q[2];
        if (a1 > a0) {
            first = c = (long)a0;
            for (double line = floor0(a0) + 1.0; line < a1; line += 1.0, c++) {
                q[0] = line;
                q[1] = a[1] + (line - a0) * slope;
                deposit(g, cells, fr, p, q, c);
                p[0] = q[0], p[1] = q[1];
            }
        } else {
            first = c = (long)ceil0(a0) - 1;
            for (double line = ceil0(a0) - 1.0; line > a1; line -= 1.0, c--) {
                q[0] = line;
                q[1] = a[1] + (line - a0) * slope;
                deposit(g, cells, fr, p, q, c);
                p[0] = q[0], p[1] = q[1];
            }
        }
        deposit(g, cells, fr, p, b, c);
    }
    if (g->dirty)
        flag(g, i, first, c);
}

/* The point of a -> b at row line y = v (x interpolated from a). */
static inline void at_row(const double *a, double slope, double v, double *q)
{
    q[0] = a[0] + (v - a[1]) * slope;
    q[1] = v;
}

/* Cut a segment a -> b (inside [0, w] x [0, h]) where it crosses the row
 * lines, and pass the pieces whose row lies in [lo, hi) to cut_columns.
 * Every crossing point is computed from a and the segment's slope whatever
 * the window, so a segment cut in bands gives the very pieces it gives
 * whole. */
void coverage_cut_rows(struct grid *g, const struct part *part, double lo, double hi)
{
    const double *a = part->a, *b = part->b;
    double a0 = a[1], a1 = b[1];
    if (a0 == a1 || floor0(a0) == floor0(a1)) {
        double row = floor0(0.5 * (a0 + a1));
        if (row >= lo && row < hi)
            cut_columns(g, a, b, (long)row);
        return;
    }
    double slope = part->slope;
    double p[2] = {a[0], a[1]}, q[2];
    if (a1 > a0) {
        /* rows floor(a0) .. ceil(a1) - 1; the piece of row r runs from
         * y = max(a0, r) to y = min(a1, r + 1) */
        double first = floor0(a0), last = ceil0(a1) - 1.0;
        double rs = first > lo ? first : lo, re = last < hi - 1.0 ? last : hi - 1.0;
        if (rs > re)
            return;
        if (rs > first)
            at_row(a, slope, rs, p);
        long r = (long)rs;
        for (double line = rs + 1.0; line <= re; line += 1.0, r++) {
            at_row(a, slope, line, q);
            cut_columns(g, p, q, r);
            p[0] = q[0], p[1] = q[1];
        }
        if (re < last)
            at_row(a, slope, re + 1.0, q);
        cut_columns(g, p, re < last ? q : b, r);
    } else {
        /* rows ceil(a0) - 1 down to floor(a1); the piece of row r runs
         * from y = min(a0, r + 1) to y = max(a1, r) */
        double first = ceil0(a0) - 1.0, last = floor0(a1);
        double rs = first < hi - 1.0 ? first : hi - 1.0, re = last > lo ? last : lo;
        if (rs < re)
            return;
        if (rs < first)
            at_row(a, slope, rs + 1.0, p);
        long r = (long)rs;
        for (double line = rs; line > re; line -= 1.0, r--) {
            at_row(a, slope, line, q);
            cut_columns(g, p, q, r);
            p[0] = q[0], p[1] = q[1];
        }
        if (re > last)
            at_row(a, slope, re, q);
        cut_columns(g, p, re > last ? q : b, r);
    }
}

/* The point of a segment where coordinate a (x or y) takes the value v. */
static inline double at(double a0, double b0, double a1, double b1, double v)
{
    return b0 + (v - a0) * ((b1 - b0) / (a1 - a0));
}

static inline double clamp(double v, double lo, double hi) { return v < lo ? lo : (v > hi ? hi : v); }

/* Clip the segment (x0, y0) -> (x1, y1) to the image: the part left or
 * right of it adds nothing and is dropped, the part above it is flattened
 * onto y = 0, the part below onto y = h (where it adds nothing and is
 * dropped). Writes up to three parts, in the order of the segment, and
 * returns their count. */
int coverage_clip_segment(double x0, double y0, double x1, double y1, double W, double H,
                          struct part *out)
{
    if ((x0 <= 0.0 && x1 <= 0.0) || (x0 >= W && x1 >= W) || x0 == x1)
        return 0;
    double xa = x0, ya = y0, xb = x1, yb = y1;
    double lo = x0 < x1 ? 0.0 : W, hi = x0 < x1 ? W : 0.0;
    if ((x0 < x1 && x0 < 0.0) || (x0 > x1 && x0 > W))
        ya = at(x0, y0, x1, y1, lo), xa = lo;
    if ((x0 < x1 && x1 > W) || (x0 > x1 && x1 < 0.0))
        yb = at(x0, y0, x1, y1, hi), xb = hi;
    /* cut at y = 0 and y = h, in the order of the segment */
    double xs[4], ys[4];
    int k = 0;
    xs[k] = xa, ys[k++] = ya;
    if (ya != yb && (ya < 0.0 || ya > H || yb < 0.0 || yb > H)) {
        double cuts[2] = {0.0, H};
        if (yb < ya)
            cuts[0] = H, cuts[1] = 0.0;
        for (int i = 0; i < 2; i++) {
            double c = cuts[i];
            if ((ya < c && c < yb) || (yb < c && c < ya))
                xs[k] = at(ya, xa, yb, xb, c), ys[k++] = c;
        }
    }
    xs[k] = xb, ys[k++] = yb;
    int n = 0;
    for (int i = 0; i + 1 < k; i++) {
        struct part *p = out + n;
        p->a[0] = xs[i], p->a[1] = clamp(ys[i], 0.0, H);
        p->b[0] = xs[i + 1], p->b[1] = clamp(ys[i + 1], 0.0, H);
        double y0c = p->a[1], y1c = p->b[1];
        /* the rows of coverage_cut_rows() */
        if (y0c == y1c || floor0(y0c) == floor0(y1c))
            p->rlo = p->rhi = (long)floor0(0.5 * (y0c + y1c));
        else if (y1c > y0c)
            p->rlo = (long)floor0(y0c), p->rhi = (long)ceil0(y1c) - 1;
        else
            p->rlo = (long)floor0(y1c), p->rhi = (long)ceil0(y0c) - 1;
        if (p->rlo >= (long)H)
            continue; /* on the bottom edge: adds nothing */
        if (p->rhi >= (long)H)
            p->rhi = (long)H - 1;
        p->slope = y0c != y1c ? (p->b[0] - p->a[0]) / (y1c - y0c) : 0.0;
        n++;
    }
    return n;
}

/*
 * Deposit the pieces of a stream of n points (x, y: float64, shifted by
 * +0.5) into acc, the (bh + 1) x bw pixels from (r0, c0), which is zeroed
 * first. bridge (n - 1 flags, or NULL) marks the pieces joining two rings,
 * which add nothing. Returns the winding integral over the image,
 * sum(dx * (h - ym)) over the pieces.
 */
double attneave_deposit(const double *x, const double *y, long n,
                        const unsigned char *bridge, long h, long w,
                        long r0, long c0, long bh, long bw, double *acc)
{
    struct grid g = {acc, bw, r0, c0, h, bh, 0.0, NULL, 0};
    struct part parts[3];
    if (bh <= 0 || bw <= 0)
        return 0.0;
    memset(acc, 0, sizeof(double) * (size_t)(bh + 1) * (size_t)bw);
    for (long i = 0; i + 1 < n; i++) {
        if (bridge && bridge[i])
            continue;
        int k = coverage_clip_segment(x[i], y[i], x[i + 1], y[i + 1], (double)w, (double)h, parts);
        for (int j = 0; j < k; j++) {
            coverage_cut_rows(&g, parts + j, 0.0, (double)h);
            g.area += part_area(parts + j, (double)h);
        }
    }
    return g.area;
}

/* Column prefix sum of the rows x cols array acc, in place: the winding integral. */
PIXEL_LOOPS void attneave_integrate(double *acc, long rows, long cols)
{
    for (long i = 1; i < rows; i++) {
        double *row = acc + i * cols;
        const double *up = row - cols;
        for (long j = 0; j < cols; j++)
            row[j] += up[j];
    }
}

/*
 * 8-bit pixels from deposits (integrate = 1: the column prefix sum is taken
 * on the way, in run, cols doubles of scratch; acc is left as it is) or
 * from the winding integral (integrate = 0): with
 * level = rint(255 * min(|win|, 1)), img[i * row_step + j * pix_step] =
 * lut[level], or 255 - level when lut is NULL (black on white), over
 * rows x cols. levels is scratch space for one row of cols ints.
 */
PIXEL_LOOPS void attneave_paint_u8(const double *acc, long rows, long cols, int integrate,
                                   unsigned char *img, long row_step, long pix_step,
                                   const unsigned char *lut, int *levels, double *run)
{
    memset(run, 0, sizeof(double) * (size_t)cols);
    for (long i = 0; i < rows; i++) {
        row_levels((double *)acc + i * cols, cols, integrate, run, levels, 0);
        write_levels(levels, cols, img + i * row_step, pix_step, lut);
    }
}
