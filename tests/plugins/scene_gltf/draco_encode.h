/*
 * draco_encode.h: libdraco's encoder for the texture tests (draco_encode.cpp).
 */
#ifndef LG_TESTS_DRACO_ENCODE_H
#define LG_TESTS_DRACO_ENCODE_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/* Encodes n_faces triangles given per corner (3 x dim floats per face for each of pos 3,
 * nrm 3, uv0 2, uv1 2, tan 4) without quantisation. *out is malloc'd; ids receive the Draco
 * unique ids of POSITION, NORMAL, TEXCOORD_0, TEXCOORD_1, TANGENT. Returns 0 or -1. */
int gt_draco_encode(uint32_t n_faces, const float *pos, const float *nrm, const float *uv0,
                    const float *uv1, const float *tan, uint8_t **out, size_t *size, int ids[5]);

#ifdef __cplusplus
}
#endif
#endif
