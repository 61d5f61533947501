/*
 * The test oracle of the reinhard plugin: the equations of plugins/reinhard/reinhard_cpu.h
 * in plain double-precision C, one pixel at a time, with the same bad-pixel policy. Every
 * backend of the plugin (cpu, gl, cl) is compared with it; it is never compiled into the
 * plugin.
 */
#ifndef LG_REINHARD_ORACLE_H
#define LG_REINHARD_ORACLE_H

#include "reinhard_cpu.h"

/* Adds `n` rgba32f pixels to `st` (which the caller zeroes first): log(delta + L) summed
 * in double. */
void lg_rh_ref_reduce(const float *rgba, size_t n, const lg_rh_params *p, lg_rh_stats *st);

/* Maps `n` rgba32f pixels with scale s = a / Lavg (in may equal out); the curve in double. */
void lg_rh_ref_map(const float *in, float *out, size_t n, double scale, const lg_rh_params *p);

/* The tone curve on a scaled value x >= 0 (+Inf allowed): x/(1+x), or the white-point
 * variant clamped to 1. inv_white2 = 1/Lwhite^2, 0 when white is off. */
double lg_rh_ref_curve(double x, double inv_white2);

#endif
