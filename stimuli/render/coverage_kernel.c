/*
 * The exact area-coverage rasteriser's inner loops in plain C99 (issue 13).
 *
 * Loaded through ctypes by stimuli/render/kernel.py; the numpy functions of
 * stimuli/render/raster.py are the reference, and this file follows them:
 *
 * - the stream is the one of raster._stream: x and y rows already shifted
 *   by +0.5, so that pixel (r, c) is the square [c, c+1] x [r, r+1];
 * - every piece between grid lines adds dx * (1 - f) to its pixel and
 *   dx * f to the pixel below, f = its mean height in the pixel minus the
 *   pixel's row (the signed area between the piece and the pixel's bottom
 *   side, and the rest of its cover);
 * - pieces left or right of the image add nothing, pieces above it are
 *   flattened onto its top edge, pieces below it onto its bottom edge;
 * - a column prefix sum then gives the winding integral of every pixel.
 *
 * No Python C-API: plain functions on pointers, so the file builds with any
 * C99 compiler and its loading cannot break the interpreter.
 */
#include <math.h>
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
};

/* One piece inside one pixel: deposit it and add its share of the area. */
static inline void deposit(struct grid *g, const double *a, const double *b)
{
    double dx = b[0] - a[0];
    if (dx == 0.0)
        return;
    double ym = 0.5 * (a[1] + b[1]);
    double row = floor0(ym);
    if (row >= (double)g->h)
        return; /* on the bottom edge: outside the image */
    long r = (long)row - g->r0, c = (long)floor0(0.5 * (a[0] + b[0])) - g->c0;
    double f = ym - row;
    /* round-off can put a midpoint a hair outside the box: never write
     * outside the buffer */
    r = r < 0 ? 0 : (r >= g->bh ? g->bh - 1 : r);
    c = c < 0 ? 0 : (c >= g->stride ? g->stride - 1 : c);
    double *cell = g->acc + r * g->stride + c;
    cell[0] += dx - dx * f;
    cell[g->stride] += dx * f;
    g->area += dx * ((double)g->h - ym);
}

static void cut_columns(struct grid *g, const double *a, const double *b);

/* A piece between two grid lines of `axis`: cut it at the columns next
 * (after the rows), or deposit it (after the columns). */
static inline void piece(struct grid *g, int axis, const double *a, const double *b)
{
    if (axis == 1)
        cut_columns(g, a, b);
    else
        deposit(g, a, b);
}

/* Cut the segment a -> b ((x, y) inside [0, w] x [0, h]) where it crosses
 * the grid lines of `axis` (1: rows, then columns; 0: columns). Crossing
 * points are integral on `axis`, the other coordinate interpolated from a. */
static inline void cut(struct grid *g, int axis, const double *a, const double *b)
{
    double a0 = a[axis], a1 = b[axis];
    if (a0 == a1 || floor0(a0) == floor0(a1)) {
        piece(g, axis, a, b);
        return;
    }
    int other = 1 - axis;
    double slope = (b[other] - a[other]) / (a1 - a0);
    double p[2] = {a[0], a[1]}, q[2];
    double step = a1 > a0 ? 1.0 : -1.0;
    double line = a1 > a0 ? floor0(a0) + 1.0 : ceil0(a0) - 1.0;
    for (; step > 0.0 ? line < a1 : line > a1; line += step) {
        q[axis] = line;
        q[other] = a[other] + (line - a0) * slope;
        piece(g, axis, p, q);
        p[0] = q[0], p[1] = q[1];
    }
    piece(g, axis, p, b);
}

/* cut() for each axis, so that the compiler specialises it for both */
static void cut_columns(struct grid *g, const double *a, const double *b) { cut(g, 0, a, b); }
static void cut_rows(struct grid *g, const double *a, const double *b) { cut(g, 1, a, b); }

/* The point of a segment where coordinate a (x or y) takes the value v. */
static inline double at(double a0, double b0, double a1, double b1, double v)
{
    return b0 + (v - a0) * ((b1 - b0) / (a1 - a0));
}

/* Clip a segment to 0 <= y <= h: the part above is flattened onto y = 0,
 * the part below onto y = h (which adds nothing); walk the pieces. */
static void clip_rows(struct grid *g, double x0, double y0, double x1, double y1)
{
    double H = (double)g->h;
    double ya = y0 < 0.0 ? 0.0 : (y0 > H ? H : y0);
    double yb = y1 < 0.0 ? 0.0 : (y1 > H ? H : y1);
    if (ya == y0 && yb == y1) {
        double a[2] = {x0, y0}, b[2] = {x1, y1};
        cut_rows(g, a, b);
        return;
    }
    /* up to three parts, in the order of the segment: cut at y = 0 and y = h */
    double xs[4], ys[4];
    int k = 0;
    xs[k] = x0, ys[k++] = y0;
    if (y1 != y0) {
        double cuts[2] = {0.0, H};
        if (y1 < y0)
            cuts[0] = H, cuts[1] = 0.0;
        for (int i = 0; i < 2; i++) {
            double g = cuts[i];
            if ((y0 < g && g < y1) || (y1 < g && g < y0))
                xs[k] = at(y0, x0, y1, x1, g), ys[k++] = g;
        }
    }
    xs[k] = x1, ys[k++] = y1;
    for (int i = 0; i + 1 < k; i++) {
        double a = ys[i] < 0.0 ? 0.0 : (ys[i] > H ? H : ys[i]);
        double b = ys[i + 1] < 0.0 ? 0.0 : (ys[i + 1] > H ? H : ys[i + 1]);
        double p[2] = {xs[i], a}, q[2] = {xs[i + 1], b};
        cut_rows(g, p, q);
    }
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
    double W = (double)w;
    struct grid g = {acc, bw, r0, c0, h, bh, 0.0};
    if (bh <= 0 || bw <= 0)
        return 0.0;
    memset(acc, 0, sizeof(double) * (size_t)(bh + 1) * (size_t)bw);
    for (long i = 0; i + 1 < n; i++) {
        if (bridge && bridge[i])
            continue;
        double x0 = x[i], y0 = y[i], x1 = x[i + 1], y1 = y[i + 1];
        /* the part left or right of the image adds nothing: keep 0 <= x <= w */
        if ((x0 <= 0.0 && x1 <= 0.0) || (x0 >= W && x1 >= W) || x0 == x1)
            continue;
        double xa = x0, ya = y0, xb = x1, yb = y1;
        double lo = x0 < x1 ? 0.0 : W, hi = x0 < x1 ? W : 0.0;
        if ((x0 < x1 && x0 < 0.0) || (x0 > x1 && x0 > W))
            ya = at(x0, y0, x1, y1, lo), xa = lo;
        if ((x0 < x1 && x1 > W) || (x0 > x1 && x1 < 0.0))
            yb = at(x0, y0, x1, y1, hi), xb = hi;
        clip_rows(&g, xa, ya, xb, yb);
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
 * level = rint(255 * min(|win|, 1)) (half to even, as OpenCV's
 * convertScaleAbs rounds), img[i * row_step + j * pix_step] = lut[level],
 * or 255 - level when lut is NULL (black on white), over rows x cols.
 * levels is scratch space for one row of cols ints.
 */
PIXEL_LOOPS void attneave_paint_u8(const double *acc, long rows, long cols, int integrate,
                       unsigned char *img, long row_step, long pix_step,
                       const unsigned char *lut, int *levels, double *run)
{
    memset(run, 0, sizeof(double) * (size_t)cols);
    for (long i = 0; i < rows; i++) {
        const double *row = acc + i * cols;
        unsigned char *out = img + i * row_step;
        /* simple loops, which the compiler vectorises (-fno-trapping-math) */
        if (integrate) {
            for (long j = 0; j < cols; j++) {
                double s = run[j] + row[j];
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
}
