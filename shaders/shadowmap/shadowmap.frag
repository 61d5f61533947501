#version 450 core
// The shadow map's fragment stage (plugins/shadowmap): nothing to shade. The pass writes
// only depth (the framebuffer has no colour attachment); GL writes the window depth of
// the rasterised fragment, unbiased (no polygon offset, no gl_FragDepth). Alpha-masked
// materials (MASK, and BLEND as a mask at 0.5: shaders/common/material.glsl) cast no
// shadow where their alpha is below the cutoff: the fragment is discarded, so light passes
// through the gaps of foliage cards and blinds. Opaque materials read no texture.

#include "material.glsl"

in vec2 v_uv0, v_uv1;

void main()
{
    if (lg_mat.mode.y != 0 && lg_mat_cut(lg_mat_base_color(v_uv0, v_uv1).a))
        discard;
}
