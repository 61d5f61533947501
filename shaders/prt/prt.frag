#version 450 core
// The prt node's raster pass (plugins/prt): the interpolated per-vertex radiance times the
// material's base colour texture at the pixel (sRGB decoded by the sampler; its transform
// and texture coordinate set: shaders/common/material.glsl); alpha 1 where geometry covers
// the pixel (the clear leaves 0 elsewhere). The transfer holds the base colour factor
// already (prt_bake bakes a textured material for its factor), so the factor is not applied
// again: without a texture the radiance is written as it is. An alpha mask (and BLEND,
// drawn as a mask at 0.5 as the other raster nodes do) discards: nothing is drawn there.
#include "material.glsl"

in vec3 v_radiance;
in vec2 v_uv0, v_uv1;
layout(location = 0) out vec4 o_color;

void main()
{
    vec4 t = vec4(1.0);
    if (lg_mat.has.x != 0)
        t = texture(lg_mat_base_tex, lg_mat_uv(0, v_uv0, v_uv1));
    if (lg_mat_cut(lg_mat.base_color.a * t.a))
        discard;
    o_color = vec4(v_radiance * t.rgb, 1.0);
}
