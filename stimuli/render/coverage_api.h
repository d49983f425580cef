/*
 * The interface of the rasteriser's compiled kernel: every function that
 * Python calls (through ctypes, in kernel.py). Both C files include this
 * header, so the compiler checks each definition against its prototype, and
 * tests/test_kernel_interface.py checks every prototype against the ctypes
 * declarations in kernel.py (SIGNATURES): a changed signature on either side
 * fails the build or the test instead of corrupting memory.
 */
#ifndef ATTNEAVE_COVERAGE_API_H
#define ATTNEAVE_COVERAGE_API_H

double attneave_deposit(const double *x, const double *y, long n, const unsigned char *bridge, long h, long w,
                        long r0, long c0, long bh, long bw, double *acc);
void attneave_integrate(double *acc, long rows, long cols);
void attneave_paint_u8(const double *acc, long rows, long cols, int integrate, unsigned char *img, long row_step,
                       long pix_step, const unsigned char *lut, int *levels, double *run);
double attneave_ring_u8(const double *pts, long n, int oriented, unsigned char *img, long h, long w, long row_step,
                        long pix_step, long channels, const unsigned char *luts);
double attneave_stream_u8(const double *x, const double *y, long n, const unsigned char *bridge, unsigned char *img,
                          long h, long w, long row_step, long pix_step, long channels, const unsigned char *luts);

#endif
