#version 450 core
// The prt node's raster pass (plugins/prt): the interpolated per-vertex radiance; alpha 1
// where geometry covers the pixel (the clear leaves 0 elsewhere).

in vec3 v_radiance;
layout(location = 0) out vec4 o_color;

void main()
{
    o_color = vec4(v_radiance, 1.0);
}
