/* lg_gl_material_*, lg_gl_pass_bind_material (lightgraph/gl_pass.h, ABI 3.1): a scene
 * material's block and textures for shaders/common/material.glsl. */
#include <string.h>

#include "gl_pass_priv.h"
#include "lightgraph/gl_pass.h"
#include "lightgraph/plugin.h"

/* The five maps in the block's order (material.glsl's lg_mat_uv indices). */
static const lg_texture_ref *map_ref(const lg_material_maps *mp, int k)
{
    const lg_texture_ref *refs[5] = { &mp->base_color, &mp->metallic_roughness, &mp->normal,
                                      &mp->occlusion, &mp->emissive };
    return refs[k];
}

static bool has_texture(const lg_scene *s, const lg_texture_ref *r)
{
    const lg_scene_textures *t = s->textures;
    return t && r->texture >= 0 && (uint32_t)r->texture < t->n_textures &&
           t->textures[r->texture].image < t->n_images;
}

bool lg_gl_material_make(const lg_scene *s, uint32_t material, lg_gl_material *out)
{
    memset(out, 0, sizeof *out);
    for (int k = 0; k < 4; k++)
        out->base_color[k] = 1.0f;
    out->normal_scale = out->occlusion_strength = 1.0f;
    for (int k = 0; k < 5; k++)
        out->transform[2 * k][0] = out->transform[2 * k][3] = 1.0f;
    if (!s || material >= s->n_materials)
        return false;
    const lg_material *m = &s->materials[material];
    const lg_material_maps *mp = lg_material_maps_of(m);
    memcpy(out->base_color, m->base_color, sizeof out->base_color);
    memcpy(out->emissive, m->emissive, sizeof out->emissive);
    out->metallic = m->metallic;
    out->roughness = m->roughness;
    out->normal_scale = mp->normal.scale;
    out->occlusion_strength = mp->occlusion.scale;
    out->alpha_mode = (int32_t)mp->alpha_mode;
    /* BLEND is drawn as a mask at one half by the raster nodes (order-independent) */
    out->alpha_cutoff = mp->alpha_mode == LG_ALPHA_MASK    ? mp->alpha_cutoff
                        : mp->alpha_mode == LG_ALPHA_BLEND ? 0.5f
                                                           : 0.0f;
    out->double_sided = m->double_sided;
    for (int k = 0; k < 5; k++) {
        const lg_texture_ref *r = map_ref(mp, k);
        int32_t has = has_texture(s, r);
        if (k < 4)
            out->has[k] = has;
        else
            out->has_emissive = has;
        memcpy(out->transform[2 * k], r->transform, 4 * sizeof(float));
        out->transform[2 * k + 1][0] = r->transform[4];
        out->transform[2 * k + 1][1] = r->transform[5];
        out->transform[2 * k + 1][2] = r->texcoord == 1 ? 1.0f : 0.0f;
    }
    return true;
}

void lg_gl_pass_material_binds(lg_gl_pass *pass, lg_gl_material_binds *out)
{
    static const char *const names[5] = { "lg_mat_base_tex", "lg_mat_mr_tex", "lg_mat_normal_tex",
                                          "lg_mat_occlusion_tex", "lg_mat_emissive_tex" };
    memset(out, 0, sizeof *out);
    out->block = lg_gl_pass_binding_optional(pass, GL_UNIFORM_BLOCK, "LgMaterial");
    for (int k = 0; k < 5; k++)
        out->maps[k] = lg_gl_pass_binding_optional(pass, GL_SAMPLER, names[k]);
}

int lg_gl_pass_bind_material(lg_gl_pass *pass, const lg_gl_material_binds *b,
                             const lg_resource *scene, uint32_t material,
                             const lg_gl_material_opts *opts)
{
    const lg_scene_gl *sgl = lg_gl_pass_scene(pass);
    const lg_scene *s = sgl && sgl->res == scene ? sgl->scene : NULL;
    /* the pass's node reports; the scene comes from the pass's draw data when it is this
     * resource's, else from the resource */
    lg_node *n = lg_gl_pass_node_(pass);
    if (!s && !(s = lg_scene_get(n, scene)))
        return LG_ERR_INVALID;
    lg_gl_material u;
    if (!lg_gl_material_make(s, material, &u))
        return lg_error(n, "gl pass '%s': material %u does not exist (the scene has %u)",
                        lg_gl_pass_name(pass), material, s->n_materials);
    int rc = lg_gl_pass_uniforms(pass, b->block, &u, sizeof u);
    if (rc)
        return rc;
    lg_gl_material_opts o = { .filter = LG_GL_MATERIAL_FILTER_FILE, .max_anisotropy = 16.0f };
    if (opts)
        o = *opts;
    const lg_material_maps *mp = lg_material_maps_of(&s->materials[material]);
    for (int k = 0; k < 5; k++) {
        const lg_texture_ref *r = map_ref(mp, k);
        if (b->maps[k].index < 0 || !has_texture(s, r))
            continue;
        bool srgb = k == 0 || k == 4;
        GLuint tex = 0;
        if ((rc = lg_scene_texture_gl(n, scene, r->texture, srgb, &tex)))
            return rc;
        lg_gl_sampler smp = lg_gl_sampler_scene(s, r->texture, o.max_anisotropy);
        switch (o.filter) {
        case LG_GL_MATERIAL_FILTER_FILE: break;
        case LG_GL_MATERIAL_FILTER_NEAREST:
            smp.min_filter = smp.mag_filter = GL_NEAREST;
            smp.max_anisotropy = 0.0f;
            break;
        case LG_GL_MATERIAL_FILTER_BILINEAR:
            smp.min_filter = smp.mag_filter = GL_LINEAR;
            smp.max_anisotropy = 0.0f;
            break;
        case LG_GL_MATERIAL_FILTER_TRILINEAR:
            smp.min_filter = GL_LINEAR_MIPMAP_LINEAR;
            smp.mag_filter = GL_LINEAR;
            smp.max_anisotropy = o.max_anisotropy > 1.0f ? o.max_anisotropy : 0.0f;
            break;
        default:
            return lg_error(n, "gl pass '%s': unknown material filter %d", lg_gl_pass_name(pass),
                            (int)o.filter);
        }
        lg_gl_pass_bind_texture_sampled(pass, b->maps[k], tex, &smp);
    }
    return 0;
}
