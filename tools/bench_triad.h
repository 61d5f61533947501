/*
 * tools/bench_triad.h: the STREAM triad that the roofline benchmarks (bench_roofline.c,
 * bench_prt_roofline.c) measure a kernel against, in the same run.
 *
 * a[i] = b[i] + s c[i] over three arrays of doubles of `mib` MiB each (far beyond any
 * last-level cache at the default 256), first touched and then run by the host's pool, so
 * that the threads and their memory placement are the kernels'. One warm-up, then `repeat`
 * timed runs; the best one counts, as STREAM reports: *ms_best and *gbs = 24 bytes per
 * element / time (STREAM's convention: no write-allocate traffic).
 *
 * Returns 0, or 1 after printing why on stderr (`prog` names the tool).
 */
#ifndef LG_TOOLS_BENCH_TRIAD_H
#define LG_TOOLS_BENCH_TRIAD_H

#include <stddef.h>

#include "base/pool.h"

int lg_bench_triad(lg_pool *pool, size_t mib, int repeat, const char *prog, double *gbs,
                   double *ms_best);

#endif
