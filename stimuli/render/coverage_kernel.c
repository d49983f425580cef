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
 * Two ways through: attneave_deposit fills a buffer over the shape's whole
 * box (float, 16-bit and disc images need the integral there); the 8-bit
 * renderers (attneave_ring_u8, attneave_stream_u8) walk the image in bands
 * of rows, depositing one band into a buffer that stays in the L1/L2 cache,
 * summing and painting it, so that the working set is tens of kilobytes
 * instead of the megabyte of a whole box (which evicted the PNG encoder's
 * tables from the cache and ran cold itself).
 *
 * No Python C-API: plain functions on pointers, so the file builds with any
 * C99 compiler and its loading cannot break the interpreter.
 */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

/* floor and ceil of x >= 0 (every coordinate once clipped to the image):
 * libm's calls are not inlined on baseline x86-64, and this loop is hot. */
static inline double floor0(double x) { return (double)(long)x; }
static inline double ceil0(double x)
{
    double t = (double)(long)x;
    return t < x ? t + 1.0 : t;
}

/* Round 0 <= x < 2^51 half to even (the default rounding mode), as
 * OpenCV's saturate_cast does: adding and removing 2^52 leaves no bits
 * below the unit. Unlike nearbyint it is inlined (build without -ffast-math). */
static inline double round_even(double x)
{
    const double big = 4503599627370496.0; /* 2^52 */
    return (x + big) - big;
}

/* The per-pixel loops also get an AVX2 clone, chosen at load time on CPUs
 * that have it (GCC on x86-64 Linux; about 1.7x faster there); elsewhere
 * the baseline build alone. */
#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__) && defined(__linux__)
#define PIXEL_LOOPS __attribute__((target_clones("avx2", "default")))
#else
#define PIXEL_LOOPS
#endif

/* The box of pixels being deposited into, and the area so far. */
struct grid {
    double *acc;            /* (bh + 1) x stride deposits from pixel (r0, c0) */
    long stride, r0, c0, h; /* h: the image's height */
    long bh;                /* rows of the box */
    double area;            /* the winding integral over the image so far */
    unsigned char *dirty;   /* NULL, or per row of acc `blocks` flags: 1
                             * where BLOCK columns were deposited into */
    long blocks;            /* a multiple of 8, read 8 flags at a time */
};

/* Columns per dirty flag: 8 doubles, one cache line, two AVX2 vectors. */
#define BLOCK 8

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
static void cut_rows(struct grid *g, const double *a, const double *b, double lo, double hi)
{
    double a0 = a[1], a1 = b[1];
    if (a0 == a1 || floor0(a0) == floor0(a1)) {
        double row = floor0(0.5 * (a0 + a1));
        if (row >= lo && row < hi)
            cut_columns(g, a, b, (long)row);
        return;
    }
    double slope = (b[0] - a[0]) / (a1 - a0);
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

/* A segment clipped to the image: x in [0, w], y in [0, h], and the rows
 * its pieces fall in. */
struct part {
    double a[2], b[2];
    long rlo, rhi;
};

/* A part's share of the winding integral over the image: the integral of
 * (h - y) dx along it, the sum of dx * (h - ym) over its pieces. */
static inline double part_area(const struct part *p, double H)
{
    return (p->b[0] - p->a[0]) * (H - 0.5 * (p->a[1] + p->b[1]));
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
static int clip_segment(double x0, double y0, double x1, double y1, double W, double H,
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
        /* the rows of cut_rows() */
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
        int k = clip_segment(x[i], y[i], x[i + 1], y[i + 1], (double)w, (double)h, parts);
        for (int j = 0; j < k; j++) {
            cut_rows(&g, parts[j].a, parts[j].b, 0.0, (double)h);
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

/* The 8-bit levels rint(255 * min(|win|, 1)) of one row (half to even, as
 * OpenCV's convertScaleAbs rounds), win = run += row if integrate, else
 * row. Simple loops, which the compiler vectorises (-fno-trapping-math). */
static inline __attribute__((always_inline)) void
row_levels(double *row, long cols, int integrate, double *run, int *levels, int zero)
{
    if (integrate) {
        for (long j = 0; j < cols; j++) {
            double s = run[j] + row[j];
            if (zero) /* leave the deposits zero for the next band */
                row[j] = 0.0;
            run[j] = s;
            double v = fabs(s);
            v = v < 1.0 ? v : 1.0;
            levels[j] = (int)round_even(255.0 * v);
        }
    } else {
        for (long j = 0; j < cols; j++) {
            double v = fabs(row[j]);
            v = v < 1.0 ? v : 1.0;
            levels[j] = (int)round_even(255.0 * v);
        }
    }
}

/* out[j * pix_step] = lut[levels[j]], or 255 - levels[j] (black on white)
 * when lut is NULL. */
static inline __attribute__((always_inline)) void
write_levels(const int *levels, long cols, unsigned char *out, long pix_step,
             const unsigned char *lut)
{
    if (lut == NULL && pix_step == 1)
        for (long j = 0; j < cols; j++)
            out[j] = (unsigned char)(255 - levels[j]);
    else if (lut == NULL)
        for (long j = 0; j < cols; j++)
            out[j * pix_step] = (unsigned char)(255 - levels[j]);
    else
        for (long j = 0; j < cols; j++)
            out[j * pix_step] = lut[levels[j]];
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

/* An 8-bit image's layout and colours: channels interleaved (pix_step
 * bytes apart), luts channels x 256 levels, or NULL for grey black on white. */
struct image {
    unsigned char *img;
    long h, w, row_step, pix_step, channels;
    const unsigned char *luts;
};

/* Ground (level 0) in columns [c0, c1) of rows [r0, r1). */
static void fill_ground(const struct image *im, long r0, long r1, long c0, long c1)
{
    if (c1 <= c0)
        return;
    for (long i = r0; i < r1; i++) {
        unsigned char *out = im->img + i * im->row_step + c0 * im->pix_step;
        if (im->luts == NULL && im->pix_step == 1) {
            memset(out, 255, (size_t)(c1 - c0));
            continue;
        }
        for (long ch = 0; ch < im->channels; ch++) {
            unsigned char v = im->luts ? im->luts[256 * ch] : 255;
            for (long j = 0; j < c1 - c0; j++)
                out[j * im->pix_step + ch] = v;
        }
    }
}

/* One channel's byte of a level: lut[level], or 255 - level. */
static inline unsigned char colour(const struct image *im, long ch, int level)
{
    return im->luts ? im->luts[256 * ch + level] : (unsigned char)(255 - level);
}

/* Columns [col, col + n) of one row: run += deposits (which are zeroed for
 * the next band), then the pixels. */
static inline __attribute__((always_inline)) void
paint_block(const struct image *im, double *cells, double *run, long n, unsigned char *out)
{
    int levels[BLOCK];
    for (long j = 0; j < n; j++) {
        double s = run[j] + cells[j];
        cells[j] = 0.0;
        run[j] = s;
        double v = fabs(s);
        v = v < 1.0 ? v : 1.0;
        levels[j] = (int)round_even(255.0 * v);
    }
    for (long j = 0; j < n; j++)
        for (long ch = 0; ch < im->channels; ch++)
            out[j * im->pix_step + ch] = colour(im, ch, levels[j]);
}

/*
 * Sum and paint rows [r, r + rows) from the band's deposits, columns c0 ..
 * c0 + bw - 1. A column's running sum changes only where something was
 * deposited, so each row starts as a copy of the row above (or as ground,
 * in the shape's first row) and only its dirty blocks are recomputed, or
 * the whole row where most blocks are dirty. Deposits are left zero.
 */
/* The next flagged block from `k` of a row's n flags, or n; flags read
 * are cleared. */
static inline long next_block(unsigned char *m, long k, long n)
{
    for (k &= ~7L; k < n; k += 8) {
        uint64_t word;
        memcpy(&word, m + k, 8);
        if (word) {
            long j = k + __builtin_ctzll(word) / 8;
            m[j] = 0;
            return j;
        }
    }
    return n;
}

PIXEL_LOOPS static void paint_band(const struct image *im, double *buf, unsigned char *dirty,
                                   long blocks, long r, long rows, long first, long c0, long bw,
                                   double *run, int *levels)
{
    long bytes = im->w * im->pix_step, nblocks = (bw + BLOCK - 1) / BLOCK;
    for (long i = 0; i < rows; i++) {
        unsigned char *row = im->img + (r + i) * im->row_step, *out = row + c0 * im->pix_step;
        double *cells = buf + i * bw;
        unsigned char *m = dirty + i * blocks;
        if (r + i == first)
            fill_ground(im, r + i, r + i + 1, 0, im->w);
        else
            memcpy(row, row - im->row_step, (size_t)bytes);
        long count = 0;
        for (long k = 0; k < blocks; k += 8) {
            uint64_t word;
            memcpy(&word, m + k, 8);
            count += __builtin_popcountll(word);
        }
        if (4 * count > nblocks) {
            row_levels(cells, bw, 1, run, levels, 1);
            for (long ch = 0; ch < im->channels; ch++)
                write_levels(levels, bw, out + ch, im->pix_step, im->luts ? im->luts + 256 * ch : NULL);
            memset(m, 0, (size_t)blocks);
            continue;
        }
        for (long k = next_block(m, 0, blocks); k < blocks; k = next_block(m, k, blocks)) {
            long col = k * BLOCK;
            if (col + BLOCK <= bw) /* a constant trip count, vectorised */
                paint_block(im, cells + col, run + col, BLOCK, out + col * im->pix_step);
            else
                paint_block(im, cells + col, run + col, bw - col, out + col * im->pix_step);
        }
    }
}

/* Bytes of deposits per band: small enough to stay in the L1/L2 cache
 * while it is filled, summed and painted. */
#ifndef BAND_BYTES
#define BAND_BYTES 32768
#endif

/*
 * Render the clipped segments `parts` into the 8-bit image in bands of rows
 * (see the top of the file), down to the row of the shape's lowest point,
 * yhi (the cover of pieces above reaches the rows below them). The parts
 * are bucketed by their first band; each band walks the parts active in
 * it, whose pieces in other rows wait for their own band. Returns the
 * winding integral over the image, or NAN if memory ran out.
 */
static double render_parts(const struct part *parts, long np, double yhi, const struct image *im)
{
    if (np == 0) {
        fill_ground(im, 0, im->h, 0, im->w);
        return 0.0;
    }
    long rlo = parts[0].rlo, rhi = parts[0].rhi;
    double xmin = parts[0].a[0], xmax = xmin, area = 0.0;
    for (long i = 0; i < np; i++) {
        const struct part *p = parts + i;
        area += part_area(p, (double)im->h);
        rlo = p->rlo < rlo ? p->rlo : rlo;
        rhi = p->rhi > rhi ? p->rhi : rhi;
        double u = p->a[0] < p->b[0] ? p->a[0] : p->b[0], v = p->a[0] < p->b[0] ? p->b[0] : p->a[0];
        xmin = u < xmin ? u : xmin;
        xmax = v > xmax ? v : xmax;
    }
    long last = yhi < (double)im->h ? (long)yhi : im->h - 1;
    rhi = last > rhi ? last : rhi;
    long c0 = (long)xmin, c1 = (long)xmax;
    c1 = c1 < im->w - 1 ? c1 : im->w - 1;
    long bw = c1 - c0 + 1, blocks = (bw + 8 * BLOCK - 1) / (8 * BLOCK) * 8;
    long band = BAND_BYTES / (8 * bw);
    band = band < 4 ? 4 : band;
    long nbands = (rhi - rlo) / band + 1;
    size_t zeroed = sizeof(double) * (size_t)((band + 2) * bw) + (size_t)((band + 1) * blocks);
    double *buf = malloc(zeroed + sizeof(long) * (size_t)(2 * np + nbands + 1) + sizeof(int) * (size_t)bw);
    if (buf == NULL)
        return NAN;
    double *run = buf + (band + 1) * bw;
    unsigned char *dirty = (unsigned char *)(run + bw); /* (band + 1) * blocks, a multiple of 8 */
    long *order = (long *)(dirty + (band + 1) * blocks), *active = order + np, *ends = active + np;
    int *levels = (int *)(ends + nbands + 1);
    memset(buf, 0, zeroed);
    /* counting sort by first band: band b's parts end at ends[b] */
    memset(ends, 0, sizeof(long) * (size_t)(nbands + 1));
    for (long i = 0; i < np; i++)
        ends[(parts[i].rlo - rlo) / band + 1]++;
    for (long b = 1; b <= nbands; b++)
        ends[b] += ends[b - 1];
    for (long i = 0; i < np; i++)
        order[ends[(parts[i].rlo - rlo) / band]++] = i;
    struct grid g = {buf, bw, rlo, c0, im->h, band, 0.0, dirty, blocks};
    long nact = 0, next = 0;
    fill_ground(im, 0, rlo, 0, im->w);
    for (long b = 0; b < nbands; b++) {
        long r = rlo + b * band, rows = rhi + 1 - r < band ? rhi + 1 - r : band;
        while (next < ends[b])
            active[nact++] = order[next++];
        g.r0 = r, g.bh = rows;
        for (long k = 0; k < nact;) {
            const struct part *p = parts + active[k];
            cut_rows(&g, p->a, p->b, (double)r, (double)(r + rows));
            if (p->rhi < r + rows)
                active[k] = active[--nact]; /* done */
            else
                k++;
        }
        paint_band(im, buf, dirty, blocks, r, rows, rlo, c0, bw, run, levels);
        /* the cover deposited below the band's last row starts the next
         * band: move its flagged blocks to the first row */
        double *over = buf + rows * bw;
        unsigned char *m = dirty + rows * blocks;
        for (long k = next_block(m, 0, blocks); k < blocks; k = next_block(m, k, blocks)) {
            long col = k * BLOCK, n = col + BLOCK <= bw ? BLOCK : bw - col;
            memcpy(buf + col, over + col, sizeof(double) * (size_t)n);
            memset(over + col, 0, sizeof(double) * (size_t)n);
            dirty[k] = 1;
        }
    }
    fill_ground(im, rhi + 1, im->h, 0, im->w);
    free(buf);
    return area;
}

/* The rest of both 8-bit entries' arguments. */
#define IMAGE_ARGS unsigned char *img, long h, long w, long row_step, long pix_step, \
                   long channels, const unsigned char *luts

/* Whether the ring of n points is one render_silhouette takes as it is: n
 * finite points, the first not repeated at the end, at least 3 distinct
 * (else the caller takes its validating path, stimuli.render.rings). */
static int plain_ring(const double *pts, long n)
{
    if (n < 3 || (pts[0] == pts[2 * n - 2] && pts[1] == pts[2 * n - 1]))
        return 0;
    for (long i = 0; i < 2 * n; i++)
        if (!isfinite(pts[i]))
            return 0;
    long k = 1;
    while (k < n && pts[2 * k] == pts[0] && pts[2 * k + 1] == pts[1])
        k++;
    for (long j = k + 1; j < n; j++) {
        const double *q = pts + 2 * j;
        if ((q[0] != pts[0] || q[1] != pts[1]) && (q[0] != pts[2 * k] || q[1] != pts[2 * k + 1]))
            return 1;
    }
    return 0;
}

/*
 * One closed ring of n points (x, y interleaved, float64, not shifted, the
 * first point not repeated) as an 8-bit image: img (h x w, channels
 * interleaved, rows row_step and pixels pix_step bytes apart) gets
 * luts[256 * ch + level] in channel ch, or 255 - level when luts is NULL.
 * Returns the winding integral over the image (with `oriented`, that of the
 * ring turned to a positive shoelace sum, as raster.ring_area gives), or
 * NAN if the ring is not plain (see plain_ring) or memory ran out.
 */
double attneave_ring_u8(const double *pts, long n, int oriented, IMAGE_ARGS)
{
    struct image im = {img, h, w, row_step, pix_step, channels, luts};
    double W = (double)w, H = (double)h;
    if (!plain_ring(pts, n))
        return NAN;
    struct part *parts = malloc(sizeof(struct part) * (size_t)(3 * n));
    if (parts == NULL)
        return NAN;
    long np = 0;
    double twice = 0.0; /* twice the shoelace sum */
    double xlo = pts[0] + 0.5, xhi = xlo, ylo = pts[1] + 0.5, yhi = ylo;
    for (long i = 0; i < n; i++) {
        const double *a = pts + 2 * i, *b = pts + (i + 1 < n ? 2 * (i + 1) : 0);
        double x0 = a[0] + 0.5, y0 = a[1] + 0.5;
        twice += a[0] * b[1] - b[0] * a[1];
        xlo = x0 < xlo ? x0 : xlo, xhi = x0 > xhi ? x0 : xhi;
        ylo = y0 < ylo ? y0 : ylo, yhi = y0 > yhi ? y0 : yhi;
        np += clip_segment(x0, y0, b[0] + 0.5, b[1] + 0.5, W, H, parts + np);
    }
    /* wholly outside (above: flattened onto the top edge, where the pieces
     * of every column cancel): nothing, exactly */
    if (ylo >= H || yhi <= 0.0 || xhi <= 0.0 || xlo >= W)
        np = 0;
    double area = render_parts(parts, np, yhi, &im);
    free(parts);
    if (oriented && np) {
        int clipped = xlo < 0.0 || xhi >= W || ylo < 0.0 || yhi > H;
        area = !clipped ? fabs(area) : (twice >= 0.0 ? area : -area);
    }
    return area;
}

/*
 * A stream of n points (x, y: float64, shifted by +0.5; see
 * attneave_deposit) as an 8-bit image (see attneave_ring_u8). Returns the
 * winding integral over the image, or NAN if memory ran out.
 */
double attneave_stream_u8(const double *x, const double *y, long n, const unsigned char *bridge,
                          IMAGE_ARGS)
{
    struct image im = {img, h, w, row_step, pix_step, channels, luts};
    struct part *parts = malloc(sizeof(struct part) * (size_t)(3 * (n > 1 ? n - 1 : 1)));
    if (parts == NULL)
        return NAN;
    long np = 0;
    double xlo = x[0], xhi = x[0], ylo = y[0], yhi = y[0];
    for (long i = 0; i < n; i++) {
        xlo = x[i] < xlo ? x[i] : xlo, xhi = x[i] > xhi ? x[i] : xhi;
        ylo = y[i] < ylo ? y[i] : ylo, yhi = y[i] > yhi ? y[i] : yhi;
        if (i + 1 < n && !(bridge && bridge[i]))
            np += clip_segment(x[i], y[i], x[i + 1], y[i + 1], (double)w, (double)h, parts + np);
    }
    if (ylo >= (double)h || yhi <= 0.0 || xhi <= 0.0 || xlo >= (double)w)
        np = 0;
    double area = render_parts(parts, np, yhi, &im);
    free(parts);
    return area;
}
