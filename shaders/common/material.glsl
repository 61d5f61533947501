// shaders/common/material.glsl: a glTF material's textures and alpha mode, the GLSL twin of
// lightgraph/gl_pass.h's lg_gl_material (ABI 3.1). One source for every node that shades a
// surface (preview, phong, shadowmap, ibl, prt): the block, the texture units and the
// functions below. The C side fills the block and binds the textures with
// lg_gl_pass_bind_material; a map without a texture reads its factor alone.
//
// Bindings (a node may #define them before the #include when its own use these):
//   LG_MATERIAL_BINDING  the uniform block's binding (default 6)
//   LG_MATERIAL_UNIT     the first of five texture units: base colour, metallic-roughness,
//                        normal, occlusion, emissive (default 8: units 8..12)
// Texture coordinates follow glTF: (0, 0) is the image's top-left corner, which is texel
// row 0 and t = 0 of the GL texture, so (u, v) are used as (s, t) as they are.
// A shader that reads only some maps leaves the others' samplers unused (GL drops them;
// the C side binds only those the program has).

#ifndef LG_MATERIAL_BINDING
#define LG_MATERIAL_BINDING 6
#endif
#ifndef LG_MATERIAL_UNIT
#define LG_MATERIAL_UNIT 8
#endif

// std140, 240 bytes (LG_GL_BLOCK_SIZE(lg_gl_material, 240) in gl_pass.h)
layout(std140, binding = LG_MATERIAL_BINDING) uniform LgMaterial {
    vec4 base_color; // baseColorFactor: linear RGB, alpha
    vec4 emissive;   // rgb: emissiveFactor; w: the alpha cutoff (MASK: the file's; BLEND: 0.5)
    vec4 pbr;        // x metallic, y roughness factors; z normal scale, w occlusion strength
    ivec4 has;       // 1 where the material has a texture: base colour, metallic-roughness,
                     // normal, occlusion
    ivec4 mode;      // x: emissive texture; y: alpha mode (0 opaque, 1 mask, 2 blend);
                     // z: double-sided; w: 0
    vec4 xf[10];     // per map (same order, emissive last): KHR_texture_transform t[0..3],
                     // then (t[4], t[5], texcoord set, 0)
} lg_mat;

layout(binding = LG_MATERIAL_UNIT + 0) uniform sampler2D lg_mat_base_tex;     // GL_SRGB8_ALPHA8
layout(binding = LG_MATERIAL_UNIT + 1) uniform sampler2D lg_mat_mr_tex;       // GL_RGBA8
layout(binding = LG_MATERIAL_UNIT + 2) uniform sampler2D lg_mat_normal_tex;   // GL_RGBA8
layout(binding = LG_MATERIAL_UNIT + 3) uniform sampler2D lg_mat_occlusion_tex; // GL_RGBA8
layout(binding = LG_MATERIAL_UNIT + 4) uniform sampler2D lg_mat_emissive_tex; // GL_SRGB8_ALPHA8

// The coordinates map `m` (0 base colour .. 4 emissive) reads: its set, transformed.
vec2 lg_mat_uv(int m, vec2 uv0, vec2 uv1)
{
    vec4 a = lg_mat.xf[2 * m], b = lg_mat.xf[2 * m + 1];
    vec2 uv = b.z > 0.5 ? uv1 : uv0;
    return vec2(a.x * uv.x + a.z * uv.y + b.x, a.y * uv.x + a.w * uv.y + b.y);
}

// Base colour, linear RGBA: the factor times the texture (sRGB decoded by the sampler).
vec4 lg_mat_base_color(vec2 uv0, vec2 uv1)
{
    vec4 c = lg_mat.base_color;
    if (lg_mat.has.x != 0)
        c *= texture(lg_mat_base_tex, lg_mat_uv(0, uv0, uv1));
    return c;
}

// True where the surface is absent: alpha below the cutoff of a MASK material, and of a
// BLEND one, which the raster nodes draw as a mask at 0.5 (order-independent; README).
bool lg_mat_cut(float alpha)
{
    return lg_mat.mode.y != 0 && alpha < lg_mat.emissive.w;
}

// (metallic, roughness): the factors times the texture's B and G.
vec2 lg_mat_metallic_roughness(vec2 uv0, vec2 uv1)
{
    vec2 mr = lg_mat.pbr.xy;
    if (lg_mat.has.y != 0)
        mr *= texture(lg_mat_mr_tex, lg_mat_uv(1, uv0, uv1)).bg;
    return mr;
}

// Ambient occlusion: 1 + strength (R - 1); 1 without a texture.
float lg_mat_occlusion(vec2 uv0, vec2 uv1)
{
    if (lg_mat.has.w == 0)
        return 1.0;
    float o = texture(lg_mat_occlusion_tex, lg_mat_uv(3, uv0, uv1)).r;
    return 1.0 + lg_mat.pbr.w * (o - 1.0);
}

// Emitted radiance, linear RGB: the factor times the texture.
vec3 lg_mat_emissive(vec2 uv0, vec2 uv1)
{
    vec3 e = lg_mat.emissive.rgb;
    if (lg_mat.mode.x != 0)
        e *= texture(lg_mat_emissive_tex, lg_mat_uv(4, uv0, uv1)).rgb;
    return e;
}

// The tangent in world space from the object's (a vertex stage's helper): xyz through the
// model matrix, w (the bitangent's sign) flipped by a mirroring one, as the winding is.
vec4 lg_mat_world_tangent(mat4 model, vec4 t)
{
    mat3 m = mat3(model);
    return vec4(m * t.xyz, determinant(m) < 0.0 ? -t.w : t.w);
}

// The shading normal, unit, world space: `n` the interpolated normal, `t` the interpolated
// world tangent (w its sign), `front` gl_FrontFacing. A double-sided material's back face
// turns the whole frame round (N, T and B), as glTF asks. With a normal texture:
// N' = normalize(T x + B y + N z) of the texel's 2 texel - 1 with x and y times the scale,
// T made orthogonal to N (Gram-Schmidt), B = w (N x T); a tangent parallel to N (none in
// the mesh: the constant (1, 0, 0, 1) on a surface facing X) gives N.
vec3 lg_mat_normal(vec3 n, vec4 t, vec2 uv0, vec2 uv1, bool front)
{
    float l = length(n);
    vec3 N = l > 0.0 ? n / l : vec3(0.0, 0.0, 1.0);
    float side = (lg_mat.mode.z != 0 && !front) ? -1.0 : 1.0;
    if (lg_mat.has.z == 0)
        return side * N;
    vec3 T = t.xyz - N * dot(N, t.xyz);
    float lt = length(T);
    if (!(lt > 1e-6))
        return side * N;
    T /= lt;
    vec3 B = (t.w < 0.0 ? -1.0 : 1.0) * cross(N, T);
    vec3 tn = texture(lg_mat_normal_tex, lg_mat_uv(2, uv0, uv1)).xyz * 2.0 - 1.0;
    tn.xy *= lg_mat.pbr.z;
    vec3 r = side * (T * tn.x + B * tn.y + N * tn.z);
    float lr = length(r);
    return lr > 0.0 ? r / lr : side * N;
}
