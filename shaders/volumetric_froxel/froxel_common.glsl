// shaders/volumetric_froxel/froxel_common.glsl: what the three froxel compute passes share
// (plugins/volumetric_froxel/froxel.h is the spec; vol_common.h the view-ray rule). Functions
// only: each pass declares its own uniforms, so that none is dropped as unused.
#ifndef FX_COMMON_GLSL
#define FX_COMMON_GLSL

#include "medium.glsl"

// +Inf (GLSL has no literal for it): the distance to a sky pixel.
#define FX_INF uintBitsToFloat(0x7f800000u)

// The world point at NDC (ndc, z) of the camera whose inverse view-projection is inv_vp.
vec3 fx_unproject(mat4 inv_vp, vec2 ndc, float z)
{
    vec4 r = inv_vp * vec4(ndc, z, 1.0);
    return r.xyz / r.w;
}

// The unit view ray through NDC point ndc (vol_ray: unprojected at NDC z 0, from the eye),
// from vol_ray_matrix's ray_vp: the offset from the eye made in double on the host (not
// fx_unproject(...) - eye in float: NDC z 0 lies millimetres from the eye, and that
// difference cost the ray up to 8e-6 rad).
vec3 fx_ray(mat4 ray_vp, vec2 ndc)
{
    vec4 r = ray_vp * vec4(ndc, 0.0, 1.0);
    return normalize(r.xyz / r.w);
}

// The NDC of the centre of cell (or pixel) i of a row of n: 2 (i + 0.5) / n - 1.
vec2 fx_ndc(ivec2 i, ivec2 n)
{
    return 2.0 * (vec2(i) + 0.5) / vec2(n) - 1.0;
}

#endif
