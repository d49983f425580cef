/*
 * 8-bit images from the compiled kernel, painted band by band (issue 13):
 * see coverage_kernel.c for the pieces and their deposits.
 *
 * The image is walked in bands of rows: the segments are bucketed by the
 * first band they reach, and each band deposits the pieces of the segments
 * active in it into a buffer of BAND_BYTES that stays in the L2 cache,
 * then sums and paints its rows, so that the working set is tens of
 * kilobytes instead of the megabyte of the shape's whole box (which evicted
 * the PNG encoder's tables from the cache and then ran cold itself). A
 * column's running sum changes only where something was deposited, so each
 * row starts as a copy of the row above and only its flagged blocks of
 * BLOCK columns are recomputed (every column where most blocks are).
 */
#include "coverage_kernel.h"
#include "coverage_api.h"

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

/* Bytes of deposits per band: small enough to stay in the L2 cache while
 * it is filled, summed and painted, large enough that the segments active
 * in a band are not re-entered too often (each band cuts every active
 * segment anew: with 32 KB, 8 rows of a 512-pixel box, the long edges of
 * a spiky star made that a fifth of its time). */
#ifndef BAND_BYTES
#define BAND_BYTES 131072
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
            coverage_cut_rows(&g, p, (double)r, (double)(r + rows));
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
        np += coverage_clip_segment(x0, y0, b[0] + 0.5, b[1] + 0.5, W, H, parts + np);
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
            np += coverage_clip_segment(x[i], y[i], x[i + 1], y[i + 1], (double)w, (double)h, parts + np);
    }
    if (ylo >= (double)h || yhi <= 0.0 || xhi <= 0.0 || xlo >= (double)w)
        np = 0;
    double area = render_parts(parts, np, yhi, &im);
    free(parts);
    return area;
}
