#version 450 core
// The assembly pass of the phong node's phong_half mode (plugins/phong; seed 1, 1.3.6, the
// second optimisation: the lighting equation on every other pixel, the rest interpolated),
// drawn over the whole output (phong_fullscreen.vert): a fragment pass, because llvmpipe
// runs it several times faster than the same work as a compute dispatch.
//
// The raster passes left: the surface id (the instance, from 1; 0 = background) and the
// depth of every pixel at full size, and per-pixel Phong for the pixels with x + y even, in
// two quarter-size images: u_even holds (2i, 2j), u_odd holds (2i + 1, 2j + 1). Here every
// covered pixel with x + y even takes its evaluated value; every other covered pixel (its
// four edge neighbours are all evaluated ones) takes the mean of those neighbours that show
// the same surface: the same id at a linear depth within u_depth_tol (relative) of its own.
// Without such a neighbour it takes the evaluated neighbour nearest in depth, and with no
// covered neighbour at all the background.

layout(binding = 0) uniform sampler2D u_depth; // full-size GL window depth (texelFetch)
layout(binding = 1) uniform sampler2D u_even;  // pixels (2i, 2j)
layout(binding = 2) uniform sampler2D u_odd;   // pixels (2i + 1, 2j + 1)
layout(binding = 3) uniform usampler2D u_id;   // full-size surface ids

uniform ivec2 u_size;
uniform vec2 u_near_far;   // the camera's znear, zfar
uniform float u_depth_tol; // relative linear-depth difference that still counts as one surface
uniform vec3 u_background;

layout(location = 0) out vec4 o_color;

float linear_depth(ivec2 p)
{
    float d = texelFetch(u_depth, p, 0).r;
    float n = u_near_far.x, f = u_near_far.y;
    return n * f / (f - d * (f - n));
}

// The evaluated colour of pixel p (x + y even).
vec3 evaluated(ivec2 p)
{
    return (p.y & 1) == 0 ? texelFetch(u_even, p >> 1, 0).rgb : texelFetch(u_odd, p >> 1, 0).rgb;
}

void main()
{
    ivec2 p = ivec2(gl_FragCoord.xy);
    uint id = texelFetch(u_id, p, 0).r;
    vec3 c = u_background;
    if (id != 0u && ((p.x + p.y) & 1) == 0) {
        c = evaluated(p);
    } else if (id != 0u) {
        float z = linear_depth(p);
        const ivec2 nb[4] = ivec2[4](ivec2(-1, 0), ivec2(1, 0), ivec2(0, -1), ivec2(0, 1));
        vec3 sum = vec3(0.0);
        float best = 1e30;
        int n = 0;
        for (int i = 0; i < 4; i++) {
            ivec2 q = p + nb[i];
            if (q.x < 0 || q.y < 0 || q.x >= u_size.x || q.y >= u_size.y)
                continue;
            uint qid = texelFetch(u_id, q, 0).r;
            if (qid == 0u)
                continue;
            float dz = abs(linear_depth(q) - z);
            vec3 e = evaluated(q);
            if (qid == id && dz <= u_depth_tol * z) {
                sum += e;
                n++;
            }
            if (dz < best) {
                best = dz;
                c = e;
            }
        }
        if (n > 0)
            c = sum / float(n);
    }
    o_color = vec4(c, 1.0);
}
