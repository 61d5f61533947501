// The template's formula, shared by its shaders through `#include "invert.glsl"`: the
// including shader's folder is searched first, then each -I folder given to embed.py.
// The C twin is the loop in template.c (backend = cpu); keep the two alike.
vec3 template_invert(vec3 c, float white)
{
    return max(vec3(0.0), vec3(white) - c);
}
