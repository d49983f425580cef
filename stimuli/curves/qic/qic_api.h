/*
 * The interface of the QIC spline's compiled kernel: every function that
 * Python calls (through ctypes, in kernel.py), and attneave_moments, which
 * qic_solve.c takes from clothoid_moments.c. Both C files include this
 * header, so the compiler checks each definition against its prototype, and
 * tests/test_kernel_interface.py checks every prototype called from Python
 * against the ctypes declarations in kernel.py (SIGNATURES).
 */
#ifndef ATTNEAVE_QIC_API_H
#define ATTNEAVE_QIC_API_H

#include <stdint.h>

void attneave_moments(double a, double b, double c, int nk, double *X, double *Y);
void attneave_clothoid_points(long n, const double *x0, const double *y0, const double *theta0, const double *k,
                              const double *dk, const double *s, double *x, double *y);
long attneave_sample_segments(long m, int64_t *counts, double max_step, long max_samples, const double *x0,
                              const double *y0, const double *theta0, const double *k0, const double *dk,
                              const double *L, const double *xe, const double *ye, double sign, long cap,
                              double *out);
long attneave_turn_samples(long m, double max_step, long max_samples, long cap, const double *P, long n,
                           const int64_t *start, const double *seg, double *out);
long attneave_qic_piece(const double *xy, long npts, long closed, double t_start, double t_end,
                        const double *theta_hold, double tol, long max_iter, long max_halvings, double *out);

#endif
