/*
 * What the two files of the rasteriser's compiled kernel share
 * (coverage_kernel.c: cutting segments into pieces and depositing them;
 * coverage_bands.c: 8-bit images painted band by band). See
 * coverage_kernel.c for what is computed.
 */
#ifndef ATTNEAVE_COVERAGE_KERNEL_H
#define ATTNEAVE_COVERAGE_KERNEL_H

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

/* A segment clipped to the image: x in [0, w], y in [0, h], and the rows
 * its pieces fall in. */
struct part {
    double a[2], b[2];
    long rlo, rhi;
    double slope; /* dx / dy (0 if horizontal), once rather than per band */
};

/* A part's share of the winding integral over the image: the integral of
 * (h - y) dx along it, the sum of dx * (h - ym) over its pieces. */
static inline double part_area(const struct part *p, double H)
{
    return (p->b[0] - p->a[0]) * (H - 0.5 * (p->a[1] + p->b[1]));
}

/* Cut a part at the row lines and deposit the pieces whose row lies in
 * [lo, hi) (coverage_kernel.c). */
void coverage_cut_rows(struct grid *g, const struct part *part, double lo, double hi);

/* Clip a segment to the image: up to three parts, their count returned
 * (coverage_kernel.c). */
int coverage_clip_segment(double x0, double y0, double x1, double y1, double W, double H,
                          struct part *out);

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

#endif
