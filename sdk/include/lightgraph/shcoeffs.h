/*
 * lightgraph/shcoeffs.h: the spherical-harmonic coefficient resource (LG_KIND_SH), since
 * ABI 2.0: lighting (a probe's radiance) projected to n bands, RGB.
 *
 * Parts (lightgraph/kinds.h):
 *
 *   coeffs  buffer: float[3][n^2], the R plane, then G, then B; within a plane,
 *           coefficient i = l (l + 1) + m for band l in [0, n) and m in [-l, l]
 *   info    meta: lg_sh_info
 *
 * Planes rather than interleaved RGB so that a dot product with a per-vertex transfer
 * vector (lightgraph/transfer.h, the same plane order) streams both contiguously on every
 * device. The basis (real SH, normalisation, sign convention) is the one lightgraph/sh.h
 * documents; the coefficients are integrals over the sphere in world directions.
 */
#ifndef LIGHTGRAPH_SHCOEFFS_H
#define LIGHTGRAPH_SHCOEFFS_H

#include <stdint.h>

#include "lightgraph/config.h"
#include "lightgraph/host.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Bands an SH resource may hold: 1 .. LG_SH_MAX_BANDS (n^2 coefficients). */
#define LG_SH_MAX_BANDS 64u

enum { LG_SH_WINDOWED = 1u << 0 }; /* lg_sh_info.flags: a ringing window was applied */

/* The `info` part. */
typedef struct lg_sh_info {
    uint32_t struct_size; /* sizeof(lg_sh_info) */
    uint32_t bands;       /* n */
    uint32_t flags;       /* LG_SH_* */
    uint32_t reserved[9];
} lg_sh_info;

typedef struct lg_sh {
    lg_sh_info info;
    uint32_t n_coeffs;         /* bands^2 */
    const lg_resource *coeffs; /* map it on the device of choice */
    void *reserved[4];
} lg_sh;

/* Producer, prepare(): declares output `port` with `bands` bands (1..LG_SH_MAX_BANDS). */
LG_API int lg_sh_declare(lg_node *node, uint32_t port, uint32_t bands);
/* Producer, execute(): writes the info part (info->bands must be the declared count). */
LG_API int lg_sh_publish(lg_node *node, uint32_t port, const lg_sh_info *info);
/* Consumer: fills *out and returns it; NULL without an error for NULL or neutral, NULL
 * after lg_error for another kind or inconsistent parts. */
LG_API const lg_sh *lg_sh_get(lg_node *node, const lg_resource *res, lg_sh *out);

#ifdef __cplusplus
}
#endif
#endif
