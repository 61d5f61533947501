/* lg_gl_pass (lightgraph/gl_pass.h): a GL pass made once, begun and ended every frame. */
#include "lightgraph/gl_pass.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "lightgraph/plugin.h"

/* Bindings tracked so that end can unbind exactly what the pass bound. GL guarantees at
 * least 8 storage blocks, 36 uniform blocks, 16 texture units and 8 image units per stage;
 * the pass handles the first 32 of each (an index beyond is an error at look-up). */
#define LG_PASS_MAX_BIND 32u

/* Distinct sampler states a pass keeps objects for (ibl needs three). */
#define LG_PASS_MAX_SAMPLERS 8u

/* One GL sampler object per distinct lg_gl_sampler state (the reserved fields excluded). */
typedef struct pass_sampler {
    lg_gl_filter filter;
    lg_gl_wrap wrap;
    bool compare;
    GLuint name;
} pass_sampler;

/* The buffer behind a uniform block binding (lg_gl_pass_uniforms): `checked` is the size
 * that lg_gl_pass_check_block accepted, so that the layout is checked once. */
typedef struct pass_ubo {
    GLuint name;
    size_t size, checked;
} pass_ubo;

/* What decides whether the scene's draw data can be kept (gl_pass.h: "made again when the
 * scene's meshes or instances change"): copies of the mesh and instance records (counts,
 * array addresses, matrices) and the material count the checks used. Comparing records
 * rather than the scene's address also catches a new scene allocated where the old one was. */
typedef struct pass_scene_key {
    lg_mesh *meshes;
    uint32_t n_meshes;
    lg_instance *instances;
    uint32_t n_instances;
    uint32_t n_materials;
} pass_scene_key;

struct lg_gl_pass {
    lg_node *node;
    const lg_gl *gl;
    char *name;
    char *output;
    GLenum colors[LG_GL_PASS_MAX_COLORS];
    unsigned n_colors;
    bool depth, depth_test, depth_write, depth_clamp;
    GLenum depth_func;
    lg_gl_blend blend;
    lg_gl_cull cull;
    unsigned scene_attribs;

    GLuint program;
    bool compute;
    GLint local[3];
    lg_gl_uniform first; /* the batch's first record (scene passes) */
    int failed;          /* a look-up failed: begin refuses */

    GLuint fbo, empty_vao;
    lg_gl_target target; /* between begin and end */
    bool active;

    lg_scene_gl *sgl;
    /* rigid animation (ABI 3.1): the time lg_gl_pass_set_time gave, and the draw data and
     * time whose pose the instance buffer holds */
    double pose_time, posed_time;
    const lg_scene_gl *posed_sgl;
    pass_scene_key key;

    /* bound between begin and end: bit i = binding i */
    uint32_t bound_ssbo, bound_ubo, bound_tex, bound_img, bound_smp;
    bool wrote_images, seamless;
    int bind_failed; /* a binding reported an error between begin and end: end returns it */

    pass_sampler samplers[LG_PASS_MAX_SAMPLERS];
    unsigned n_samplers;
    pass_ubo ubos[LG_PASS_MAX_BIND];
};

static char *dup_str(const char *s)
{
    if (!s)
        return NULL;
    size_t n = strlen(s) + 1;
    char *d = malloc(n);
    if (d)
        memcpy(d, s, n);
    return d;
}

static void key_free(pass_scene_key *k)
{
    free(k->meshes);
    free(k->instances);
    memset(k, 0, sizeof *k);
}

/* ---- create / destroy ------------------------------------------------------------------------ */

int lg_gl_pass_create(lg_node *n, const lg_gl_pass_desc *d, lg_gl_pass **out)
{
    *out = NULL;
    if (!d || !d->name || !d->name[0])
        return lg_error(n, "lg_gl_pass_create: the descriptor has no name");
    if (d->struct_size && d->struct_size != sizeof *d)
        return lg_error(n, "gl pass '%s': descriptor struct_size %zu, this SDK has %zu", d->name,
                        d->struct_size, sizeof *d);
    if (!d->stages || d->n_stages == 0)
        return lg_error(n, "gl pass '%s': no shader stages", d->name);
    bool compute = false;
    for (unsigned i = 0; i < d->n_stages; i++)
        if (d->stages[i].stage == GL_COMPUTE_SHADER)
            compute = true;
    if (compute && d->n_stages != 1)
        return lg_error(n, "gl pass '%s': a compute stage must be the pass's only stage", d->name);
    unsigned n_colors = 0;
    while (n_colors < LG_GL_PASS_MAX_COLORS && d->colors[n_colors])
        n_colors++;
    for (unsigned i = n_colors; i < LG_GL_PASS_MAX_COLORS; i++)
        if (d->colors[i])
            return lg_error(n,
                            "gl pass '%s': colour format %u follows an empty one (colors[] "
                            "ends at the first 0)",
                            d->name, i);
    if (compute && (n_colors || d->depth || d->output || d->scene))
        return lg_error(n,
                        "gl pass '%s': a compute pass has no colour, depth, output or "
                        "scene",
                        d->name);
    if (!compute && n_colors == 0 && !d->depth)
        return lg_error(n, "gl pass '%s': a raster pass needs a colour or a depth attachment",
                        d->name);
    if (d->scene & ~(unsigned)(LG_GL_SCENE_POSITIONS | LG_GL_SCENE_NORMALS))
        return lg_error(n, "gl pass '%s': unknown scene attributes 0x%x", d->name, d->scene);
    if ((unsigned)d->blend > LG_GL_BLEND_ADD || (unsigned)d->cull > LG_GL_CULL_FRONT)
        return lg_error(n, "gl pass '%s': unknown blend %d or cull %d", d->name, (int)d->blend,
                        (int)d->cull);
    switch (d->depth_func) {
    case 0:
    case GL_LESS:
    case GL_ALWAYS:
    case GL_LEQUAL:
    case GL_EQUAL:
    case GL_GREATER:
    case GL_GEQUAL:
    case GL_NOTEQUAL:
    case GL_NEVER: break;
    default:
        return lg_error(n,
                        "gl pass '%s': depth_func 0x%04x is not a GL comparison (GL_LESS, "
                        "GL_ALWAYS, GL_LEQUAL, ...)",
                        d->name, (unsigned)d->depth_func);
    }
    if (compute && d->depth_func)
        return lg_error(n, "gl pass '%s': a compute pass has no depth test (depth_func 0x%04x)",
                        d->name, (unsigned)d->depth_func);
    const lg_gl *gl = lg_gl_get(n);
    if (!gl)
        return LG_ERR_DEVICE;

    lg_gl_pass *p = calloc(1, sizeof *p);
    if (!p)
        return lg_error_code(n, LG_ERR_NOMEM, "out of memory");
    p->node = n;
    p->gl = gl;
    p->name = dup_str(d->name);
    p->output = dup_str(d->output);
    if (!p->name || (d->output && !p->output)) {
        lg_gl_pass_destroy(&p);
        return lg_error_code(n, LG_ERR_NOMEM, "out of memory");
    }
    memcpy(p->colors, d->colors, sizeof p->colors);
    p->n_colors = n_colors;
    p->depth = d->depth;
    p->depth_test = d->depth_test;
    p->depth_write = d->depth_write;
    p->depth_clamp = d->depth_clamp;
    p->depth_func = d->depth_func ? d->depth_func : GL_LESS;
    p->blend = d->blend;
    p->cull = d->cull;
    p->scene_attribs = d->scene ? d->scene | LG_GL_SCENE_POSITIONS : 0;
    p->compute = compute;
    p->first.location = -1;

    p->program = lg_gl_program(n, gl, d->stages, d->n_stages, d->defines);
    if (!p->program) {
        lg_gl_pass_destroy(&p);
        return LG_ERR_DEVICE;
    }
    if (compute)
        gl->GetProgramiv(p->program, GL_COMPUTE_WORK_GROUP_SIZE, p->local);
    if (p->scene_attribs)
        p->first = lg_gl_pass_uniform(p, d->first_uniform ? d->first_uniform : "u_first");
    int rc = p->failed ? p->failed : lg_gl_check(n, p->name);
    if (rc) {
        lg_gl_pass_destroy(&p);
        return rc;
    }
    *out = p;
    return 0;
}

void lg_gl_pass_destroy(lg_gl_pass **pass)
{
    lg_gl_pass *p = pass ? *pass : NULL;
    if (!p)
        return;
    *pass = NULL;
    const lg_gl *gl = p->gl;
    if (gl) {
        if (p->program)
            gl->DeleteProgram(p->program);
        if (p->fbo)
            gl->DeleteFramebuffers(1, &p->fbo);
        if (p->empty_vao)
            gl->DeleteVertexArrays(1, &p->empty_vao);
        for (unsigned i = 0; i < p->n_samplers; i++)
            gl->DeleteSamplers(1, &p->samplers[i].name);
        for (unsigned i = 0; i < LG_PASS_MAX_BIND; i++)
            if (p->ubos[i].name) {
                gl->DeleteBuffers(1, &p->ubos[i].name);
                lg_account_free(p->node, p->ubos[i].size);
            }
    }
    lg_scene_gl_destroy(gl, p->sgl);
    key_free(&p->key);
    free(p->name);
    free(p->output);
    free(p);
}

GLuint lg_gl_pass_program(const lg_gl_pass *p)
{
    return p ? p->program : 0;
}

const char *lg_gl_pass_name(const lg_gl_pass *p)
{
    return p ? p->name : "";
}

/* ---- uniforms and bindings ------------------------------------------------------------------- */

static lg_gl_uniform find_uniform(lg_gl_pass *p, const char *name, bool required)
{
    lg_gl_uniform u = { -1 };
    if (!name) {
        lg_error(p->node, "gl pass '%s': a uniform look-up without a name", p->name);
        p->failed = LG_ERR_INVALID;
        return u;
    }
    u.location = p->gl->GetUniformLocation(p->program, name);
    if (u.location < 0 && required) {
        lg_error(p->node,
                 "gl pass '%s': the program has no uniform '%s' (misspelt, or not "
                 "used by the shaders, which then drop it)",
                 p->name, name);
        p->failed = LG_ERR_INVALID;
    }
    return u;
}

lg_gl_uniform lg_gl_pass_uniform(lg_gl_pass *p, const char *name)
{
    return find_uniform(p, name, true);
}

lg_gl_uniform lg_gl_pass_uniform_optional(lg_gl_pass *p, const char *name)
{
    return find_uniform(p, name, false);
}

void lg_gl_set_int(lg_gl_pass *p, lg_gl_uniform u, int32_t v)
{
    if (u.location >= 0)
        p->gl->ProgramUniform1i(p->program, u.location, v);
}

void lg_gl_set_uint(lg_gl_pass *p, lg_gl_uniform u, uint32_t v)
{
    if (u.location >= 0)
        p->gl->ProgramUniform1ui(p->program, u.location, v);
}

void lg_gl_set_float(lg_gl_pass *p, lg_gl_uniform u, float v)
{
    if (u.location >= 0)
        p->gl->ProgramUniform1f(p->program, u.location, v);
}

void lg_gl_set_ivec2(lg_gl_pass *p, lg_gl_uniform u, int32_t x, int32_t y)
{
    if (u.location >= 0)
        p->gl->ProgramUniform2i(p->program, u.location, x, y);
}

void lg_gl_set_ivec3(lg_gl_pass *p, lg_gl_uniform u, int32_t x, int32_t y, int32_t z)
{
    if (u.location >= 0)
        p->gl->ProgramUniform3i(p->program, u.location, x, y, z);
}

void lg_gl_set_vec2(lg_gl_pass *p, lg_gl_uniform u, float x, float y)
{
    if (u.location >= 0)
        p->gl->ProgramUniform2f(p->program, u.location, x, y);
}

void lg_gl_set_vec3(lg_gl_pass *p, lg_gl_uniform u, float x, float y, float z)
{
    if (u.location >= 0)
        p->gl->ProgramUniform3f(p->program, u.location, x, y, z);
}

void lg_gl_set_vec3v(lg_gl_pass *p, lg_gl_uniform u, const float v[3])
{
    if (u.location >= 0)
        p->gl->ProgramUniform3fv(p->program, u.location, 1, v);
}

void lg_gl_set_vec4v(lg_gl_pass *p, lg_gl_uniform u, const float v[4])
{
    if (u.location >= 0)
        p->gl->ProgramUniform4fv(p->program, u.location, 1, v);
}

void lg_gl_set_mat4(lg_gl_pass *p, lg_gl_uniform u, const float m[16])
{
    if (u.location >= 0)
        p->gl->ProgramUniformMatrix4fv(p->program, u.location, 1, GL_FALSE, m);
}

void lg_gl_set_mat3(lg_gl_pass *p, lg_gl_uniform u, const float m[9])
{
    if (u.location >= 0)
        p->gl->ProgramUniformMatrix3fv(p->program, u.location, 1, GL_FALSE, m);
}

void lg_gl_set_floatv(lg_gl_pass *p, lg_gl_uniform u, uint32_t count, const float *v)
{
    if (u.location >= 0 && count)
        p->gl->ProgramUniform1fv(p->program, u.location, (GLsizei)count, v);
}

void lg_gl_set_intv(lg_gl_pass *p, lg_gl_uniform u, uint32_t count, const int32_t *v)
{
    if (u.location >= 0 && count)
        p->gl->ProgramUniform1iv(p->program, u.location, (GLsizei)count, v);
}

void lg_gl_set_vec3_array(lg_gl_pass *p, lg_gl_uniform u, uint32_t count, const float *v)
{
    if (u.location >= 0 && count)
        p->gl->ProgramUniform3fv(p->program, u.location, (GLsizei)count, v);
}

void lg_gl_set_vec4_array(lg_gl_pass *p, lg_gl_uniform u, uint32_t count, const float *v)
{
    if (u.location >= 0 && count)
        p->gl->ProgramUniform4fv(p->program, u.location, (GLsizei)count, v);
}

static const char *kind_name(GLenum kind)
{
    switch (kind) {
    case GL_SHADER_STORAGE_BLOCK: return "storage block";
    case GL_UNIFORM_BLOCK: return "uniform block";
    case GL_SAMPLER: return "sampler";
    default: return "image";
    }
}

static lg_gl_binding find_binding(lg_gl_pass *p, const char *name, GLenum kind, bool required)
{
    lg_gl_binding b = { -1, kind };
    const lg_gl *gl = p->gl;
    GLint index = -1;
    if (name && (kind == GL_SHADER_STORAGE_BLOCK || kind == GL_UNIFORM_BLOCK)) {
        GLuint res = gl->GetProgramResourceIndex(p->program, kind, name);
        if (res != GL_INVALID_INDEX) {
            const GLenum prop = GL_BUFFER_BINDING;
            gl->GetProgramResourceiv(p->program, kind, res, 1, &prop, 1, NULL, &index);
        }
    } else if (name) {
        GLint loc = gl->GetUniformLocation(p->program, name);
        if (loc >= 0)
            gl->GetUniformiv(p->program, loc, &index);
    }
    if (index < 0 && !required)
        return b;
    if (index < 0) {
        lg_error(p->node,
                 "gl pass '%s': the program has no %s '%s' (misspelt, or not used by "
                 "the shaders, which then drop it)",
                 p->name, kind_name(kind), name ? name : "(null)");
        p->failed = LG_ERR_INVALID;
        return b;
    }
    if ((GLuint)index >= LG_PASS_MAX_BIND) {
        lg_error(p->node, "gl pass '%s': %s '%s' is at binding %d; passes bind 0..%u", p->name,
                 kind_name(kind), name, index, LG_PASS_MAX_BIND - 1);
        p->failed = LG_ERR_UNSUPPORTED;
        return b;
    }
    b.index = index;
    return b;
}

lg_gl_binding lg_gl_pass_storage(lg_gl_pass *p, const char *block)
{
    return find_binding(p, block, GL_SHADER_STORAGE_BLOCK, true);
}

lg_gl_binding lg_gl_pass_uniform_block(lg_gl_pass *p, const char *block)
{
    return find_binding(p, block, GL_UNIFORM_BLOCK, true);
}

lg_gl_binding lg_gl_pass_texture(lg_gl_pass *p, const char *sampler)
{
    return find_binding(p, sampler, GL_SAMPLER, true);
}

lg_gl_binding lg_gl_pass_image(lg_gl_pass *p, const char *image)
{
    return find_binding(p, image, GL_IMAGE_2D, true);
}

lg_gl_binding lg_gl_pass_binding_optional(lg_gl_pass *p, GLenum kind, const char *name)
{
    if (kind != GL_SHADER_STORAGE_BLOCK && kind != GL_UNIFORM_BLOCK && kind != GL_SAMPLER &&
        kind != GL_IMAGE_2D) {
        lg_error(p->node, "gl pass '%s': binding '%s' of unknown kind 0x%x", p->name,
                 name ? name : "(null)", (unsigned)kind);
        p->failed = LG_ERR_INVALID;
        lg_gl_binding b = { -1, kind };
        return b;
    }
    return find_binding(p, name, kind, false);
}

/* Bytes of one value of a buffer variable's type (matrices: columns x matrix stride, as laid
 * out column-major); 0 for a type this table does not know. */
static GLint type_bytes(GLenum type, GLint matrix_stride)
{
    switch (type) {
    case GL_FLOAT:
    case GL_INT:
    case GL_UNSIGNED_INT:
    case GL_BOOL: return 4;
    case GL_FLOAT_VEC2:
    case GL_INT_VEC2:
    case GL_UNSIGNED_INT_VEC2:
    case GL_BOOL_VEC2:
    case GL_DOUBLE: return 8;
    case GL_FLOAT_VEC3:
    case GL_INT_VEC3:
    case GL_UNSIGNED_INT_VEC3:
    case GL_BOOL_VEC3: return 12;
    case GL_FLOAT_VEC4:
    case GL_INT_VEC4:
    case GL_UNSIGNED_INT_VEC4:
    case GL_BOOL_VEC4:
    case GL_DOUBLE_VEC2: return 16;
    case GL_DOUBLE_VEC3: return 24;
    case GL_DOUBLE_VEC4: return 32;
    case GL_FLOAT_MAT2:
    case GL_FLOAT_MAT2x3:
    case GL_FLOAT_MAT2x4: return 2 * matrix_stride;
    case GL_FLOAT_MAT3:
    case GL_FLOAT_MAT3x2:
    case GL_FLOAT_MAT3x4: return 3 * matrix_stride;
    case GL_FLOAT_MAT4:
    case GL_FLOAT_MAT4x2:
    case GL_FLOAT_MAT4x3: return 4 * matrix_stride;
    default: return 0;
    }
}

/* lg_gl_pass_check_block for the program's block resource `res` (named `block`). */
static int check_block_res(lg_gl_pass *p, GLenum kind, GLuint res, const char *block, size_t size)
{
    const lg_gl *gl = p->gl;
    const GLenum props[2] = { GL_BUFFER_DATA_SIZE, GL_NUM_ACTIVE_VARIABLES };
    GLint vals[2] = { 0, 0 };
    gl->GetProgramResourceiv(p->program, kind, res, 2, props, 2, NULL, vals);
    GLint data_size = vals[0], n_vars = vals[1];
    /* The block's extent: the end of its last member. GL_BUFFER_DATA_SIZE may be padded
     * (Mesa rounds it up to 16), so a C struct may match either. An unsized array at the
     * end: its stride is what one C element must match. */
    GLint stride = -1, extent = 0;
    GLenum var_kind = kind == GL_SHADER_STORAGE_BLOCK ? GL_BUFFER_VARIABLE : GL_UNIFORM;
    GLint *vars = calloc(n_vars > 0 ? (size_t)n_vars : 1, sizeof *vars);
    if (!vars) {
        lg_error_code(p->node, LG_ERR_NOMEM, "out of memory");
        return p->failed = LG_ERR_NOMEM;
    }
    const GLenum av = GL_ACTIVE_VARIABLES;
    if (n_vars > 0)
        gl->GetProgramResourceiv(p->program, kind, res, 1, &av, n_vars, NULL, vars);
    for (GLint i = 0; i < n_vars && extent >= 0; i++) {
        GLenum q[6] = { GL_OFFSET,       GL_TYPE,          GL_ARRAY_SIZE,
                        GL_ARRAY_STRIDE, GL_MATRIX_STRIDE, GL_TOP_LEVEL_ARRAY_SIZE };
        GLint r[6] = { 0, 0, 1, 0, 0, 1 };
        gl->GetProgramResourceiv(p->program, var_kind, (GLuint)vars[i],
                                 kind == GL_SHADER_STORAGE_BLOCK ? 6 : 5, q, 6, NULL, r);
        if (kind == GL_SHADER_STORAGE_BLOCK && r[5] == 0) {
            const GLenum ts = GL_TOP_LEVEL_ARRAY_STRIDE;
            gl->GetProgramResourceiv(p->program, var_kind, (GLuint)vars[i], 1, &ts, 1, NULL,
                                     &stride);
            break;
        }
        GLint bytes = type_bytes((GLenum)r[1], r[4]);
        if (bytes == 0) {
            extent = -1; /* a type the table does not know: the block size decides */
            break;
        }
        GLint end = r[0] + (r[2] > 1 ? (r[2] - 1) * r[3] : 0) + bytes;
        if (end > extent)
            extent = end;
    }
    free(vars);
    if (stride >= 0 ? (size_t)stride == size
                    : (size == (size_t)data_size || (extent > 0 && size == (size_t)extent)))
        return 0;
    if (stride >= 0)
        lg_error(p->node,
                 "gl pass '%s': %s '%s' ends in an array of stride %d bytes, the C "
                 "struct that mirrors one element has %zu",
                 p->name, kind_name(kind), block, stride, size);
    else
        lg_error(p->node,
                 "gl pass '%s': %s '%s' takes %d bytes (%d with GL's padding), the C "
                 "struct that mirrors it %zu",
                 p->name, kind_name(kind), block, extent, data_size, size);
    return p->failed = LG_ERR_INVALID;
}

int lg_gl_pass_check_block(lg_gl_pass *p, GLenum kind, const char *block, size_t size)
{
    if (kind != GL_SHADER_STORAGE_BLOCK && kind != GL_UNIFORM_BLOCK) {
        lg_error(p->node,
                 "gl pass '%s': lg_gl_pass_check_block of '%s': kind 0x%x is not a "
                 "block",
                 p->name, block ? block : "(null)", (unsigned)kind);
        return p->failed = LG_ERR_INVALID;
    }
    GLuint res = block ? p->gl->GetProgramResourceIndex(p->program, kind, block) : GL_INVALID_INDEX;
    if (res == GL_INVALID_INDEX) {
        lg_error(p->node, "gl pass '%s': the program has no %s '%s'", p->name, kind_name(kind),
                 block ? block : "(null)");
        return p->failed = LG_ERR_INVALID;
    }
    return check_block_res(p, kind, res, block, size);
}

/* The uniform block at binding `index`: its resource index and name (for messages), found
 * by walking the program's blocks (a binding carries only its index). */
static GLuint block_at_binding(lg_gl_pass *p, GLint index, char *name, size_t len)
{
    const lg_gl *gl = p->gl;
    GLint n_blocks = 0;
    gl->GetProgramInterfaceiv(p->program, GL_UNIFORM_BLOCK, GL_ACTIVE_RESOURCES, &n_blocks);
    for (GLint i = 0; i < n_blocks; i++) {
        const GLenum prop = GL_BUFFER_BINDING;
        GLint binding = -1;
        gl->GetProgramResourceiv(p->program, GL_UNIFORM_BLOCK, (GLuint)i, 1, &prop, 1, NULL,
                                 &binding);
        if (binding == index) {
            gl->GetProgramResourceName(p->program, GL_UNIFORM_BLOCK, (GLuint)i, (GLsizei)len, NULL,
                                       name);
            return (GLuint)i;
        }
    }
    snprintf(name, len, "(binding %d)", index);
    return GL_INVALID_INDEX;
}

int lg_gl_pass_uniforms(lg_gl_pass *p, lg_gl_binding b, const void *data, size_t size)
{
    if (b.index < 0)
        return 0;
    if (b.kind != GL_UNIFORM_BLOCK || (GLuint)b.index >= LG_PASS_MAX_BIND)
        return lg_error(p->node,
                        "gl pass '%s': lg_gl_pass_uniforms on a %s at binding %d (it "
                        "takes a uniform block: lg_gl_pass_uniform_block)",
                        p->name, kind_name(b.kind), b.index);
    if (!p->active)
        return lg_error(p->node, "gl pass '%s': lg_gl_pass_uniforms outside begin/end", p->name);
    if (!data || size == 0)
        return lg_error(p->node, "gl pass '%s': lg_gl_pass_uniforms at binding %d with %s", p->name,
                        b.index, data ? "0 bytes" : "no data");
    const lg_gl *gl = p->gl;
    pass_ubo *u = &p->ubos[b.index];
    if (u->checked != size) {
        /* the layout is checked once per size: a struct that mirrors the block has one */
        char name[128];
        GLuint res = block_at_binding(p, b.index, name, sizeof name);
        if (res == GL_INVALID_INDEX) {
            lg_error(p->node, "gl pass '%s': the program has no uniform block at binding %d",
                     p->name, b.index);
            return p->failed = LG_ERR_INVALID;
        }
        int rc = check_block_res(p, GL_UNIFORM_BLOCK, res, name, size);
        if (rc)
            return rc;
        u->checked = size;
    }
    if (u->name && u->size < size) {
        gl->DeleteBuffers(1, &u->name);
        lg_account_free(p->node, u->size);
        u->name = 0;
        u->size = 0;
    }
    if (!u->name) {
        /* immutable storage, updated in place: a few hundred bytes per pass */
        gl->CreateBuffers(1, &u->name);
        gl->NamedBufferStorage(u->name, (GLsizeiptr)size, data, GL_DYNAMIC_STORAGE_BIT);
        u->size = size;
        lg_account_alloc(p->node, size);
    } else {
        gl->NamedBufferSubData(u->name, 0, (GLsizeiptr)size, data);
    }
    gl->BindBufferBase(GL_UNIFORM_BUFFER, (GLuint)b.index, u->name);
    p->bound_ubo |= 1u << b.index;
    char what[160];
    snprintf(what, sizeof what, "gl pass '%s': uploading uniform block binding %d (%zu bytes)",
             p->name, b.index, size);
    return lg_gl_check(p->node, what);
}

void lg_gl_pass_bind_buffer(lg_gl_pass *p, lg_gl_binding b, GLuint buffer)
{
    if (b.index < 0)
        return;
    if (b.kind == GL_SHADER_STORAGE_BLOCK) {
        p->gl->BindBufferBase(GL_SHADER_STORAGE_BUFFER, (GLuint)b.index, buffer);
        p->bound_ssbo |= 1u << b.index;
    } else if (b.kind == GL_UNIFORM_BLOCK) {
        p->gl->BindBufferBase(GL_UNIFORM_BUFFER, (GLuint)b.index, buffer);
        p->bound_ubo |= 1u << b.index;
    } else {
        lg_error(p->node, "gl pass '%s': lg_gl_pass_bind_buffer on a %s", p->name,
                 kind_name(b.kind));
    }
}

void lg_gl_pass_bind_texture(lg_gl_pass *p, lg_gl_binding b, GLuint tex)
{
    lg_gl_pass_bind_texture_sampled(p, b, tex, NULL);
}

/* The pass's sampler object for state `s`, made at its first use; 0 after an error. */
static GLuint sampler_for(lg_gl_pass *p, const lg_gl_sampler *s)
{
    for (unsigned i = 0; i < p->n_samplers; i++) {
        const pass_sampler *k = &p->samplers[i];
        if (k->filter == s->filter && k->wrap == s->wrap && k->compare == s->compare_less_equal)
            return k->name;
    }
    static const GLint wraps[] = { GL_CLAMP_TO_EDGE, GL_REPEAT, GL_MIRRORED_REPEAT,
                                   GL_CLAMP_TO_BORDER };
    if ((unsigned)s->filter > LG_GL_FILTER_LINEAR_MIPMAP ||
        (unsigned)s->wrap > LG_GL_WRAP_BORDER_ZERO) {
        p->bind_failed = lg_error(p->node,
                                  "gl pass '%s': sampler with unknown filter %d or "
                                  "wrap %d",
                                  p->name, (int)s->filter, (int)s->wrap);
        return 0;
    }
    if (p->n_samplers == LG_PASS_MAX_SAMPLERS) {
        p->bind_failed = lg_error_code(p->node, LG_ERR_UNSUPPORTED,
                                       "gl pass '%s': more than %u distinct sampler states",
                                       p->name, LG_PASS_MAX_SAMPLERS);
        return 0;
    }
    const lg_gl *gl = p->gl;
    GLuint name = 0;
    gl->CreateSamplers(1, &name);
    GLint mag = s->filter == LG_GL_FILTER_NEAREST ? GL_NEAREST : GL_LINEAR;
    GLint min = s->filter == LG_GL_FILTER_LINEAR_MIPMAP ? GL_LINEAR_MIPMAP_LINEAR : mag;
    gl->SamplerParameteri(name, GL_TEXTURE_MIN_FILTER, min);
    gl->SamplerParameteri(name, GL_TEXTURE_MAG_FILTER, mag);
    gl->SamplerParameteri(name, GL_TEXTURE_WRAP_S, wraps[s->wrap]);
    gl->SamplerParameteri(name, GL_TEXTURE_WRAP_T, wraps[s->wrap]);
    gl->SamplerParameteri(name, GL_TEXTURE_WRAP_R, wraps[s->wrap]);
    const float border[4] = { 0.0f, 0.0f, 0.0f, 0.0f };
    gl->SamplerParameterfv(name, GL_TEXTURE_BORDER_COLOR, border);
    if (s->compare_less_equal) {
        gl->SamplerParameteri(name, GL_TEXTURE_COMPARE_MODE, GL_COMPARE_REF_TO_TEXTURE);
        gl->SamplerParameteri(name, GL_TEXTURE_COMPARE_FUNC, GL_LEQUAL);
    }
    p->samplers[p->n_samplers++] = (pass_sampler){
        .filter = s->filter, .wrap = s->wrap, .compare = s->compare_less_equal, .name = name
    };
    return name;
}

void lg_gl_pass_bind_texture_sampled(lg_gl_pass *p, lg_gl_binding b, GLuint tex,
                                     const lg_gl_sampler *s)
{
    if (b.index < 0)
        return;
    const lg_gl *gl = p->gl;
    GLuint unit = (GLuint)b.index, smp = 0;
    if (s && !(smp = sampler_for(p, s)))
        return;
    gl->BindTextureUnit(unit, tex);
    p->bound_tex |= 1u << unit;
    /* a sampler this pass put on the unit earlier would override the texture's own state */
    if (smp || (p->bound_smp & (1u << unit))) {
        gl->BindSampler(unit, smp);
        if (smp)
            p->bound_smp |= 1u << unit;
        else
            p->bound_smp &= ~(1u << unit);
    }
    if (s && s->seamless_cube && !p->seamless) {
        gl->Enable(GL_TEXTURE_CUBE_MAP_SEAMLESS);
        p->seamless = true;
    }
}

void lg_gl_pass_bind_image_level(lg_gl_pass *p, lg_gl_binding b, GLuint tex, GLint level,
                                 GLint layer, GLenum access, GLenum format)
{
    if (b.index < 0)
        return;
    bool all = layer == LG_GL_ALL_LAYERS;
    p->gl->BindImageTexture((GLuint)b.index, tex, level, all ? GL_TRUE : GL_FALSE, all ? 0 : layer,
                            access, format);
    p->bound_img |= 1u << b.index;
    if (access != GL_READ_ONLY)
        p->wrote_images = true;
}

void lg_gl_pass_bind_image(lg_gl_pass *p, lg_gl_binding b, GLuint tex, GLenum access, GLenum format)
{
    lg_gl_pass_bind_image_level(p, b, tex, 0, 0, access, format);
}

/* ---- targets --------------------------------------------------------------------------------- */

static int port_index(lg_node *n, const char *port, unsigned *out)
{
    const lg_node_type *t = n->type;
    for (uint32_t i = 0; t && i < t->n_outputs; i++)
        if (t->outputs[i].name && strcmp(t->outputs[i].name, port) == 0) {
            *out = i;
            return 0;
        }
    return lg_error(n, "the node has no output port '%s'", port);
}

int lg_gl_target_output(lg_node *n, const char *port, lg_gl_target *t)
{
    memset(t, 0, sizeof *t);
    unsigned i = 0;
    int rc = port_index(n, port, &i);
    if (rc)
        return rc;
    const lg_resource *r = lg_output(n, i);
    lg_resource_info info;
    if (!r || lg_describe(r, &info, n) != 0 || info.kind != LG_KIND_IMAGE)
        return lg_error(n, "output '%s' is not an image (declared in prepare?)", port);
    uint32_t color = 0, depth = 0;
    if ((rc = lg_map_gl(n, r, LG_WRITE, &color, &depth)))
        return rc;
    t->color[0] = color;
    t->depth = depth;
    t->width = info.image.width;
    t->height = info.image.height;
    return 0;
}

static const char *format_name(GLenum f)
{
    switch (f) {
    case GL_RGBA32F: return "GL_RGBA32F";
    case GL_RGBA16F: return "GL_RGBA16F";
    case GL_RGBA8: return "GL_RGBA8";
    case GL_R32UI: return "GL_R32UI";
    case GL_R32F: return "GL_R32F";
    case GL_DEPTH_COMPONENT32F: return "GL_DEPTH_COMPONENT32F";
    case GL_DEPTH_COMPONENT24: return "GL_DEPTH_COMPONENT24";
    default: return NULL;
    }
}

static int check_format(lg_gl_pass *p, GLuint tex, GLenum want, const char *what, unsigned i)
{
    GLint got = 0;
    p->gl->GetTextureLevelParameteriv(tex, 0, GL_TEXTURE_INTERNAL_FORMAT, &got);
    if ((GLenum)got == want)
        return 0;
    const char *g = format_name((GLenum)got), *w = format_name(want);
    char gb[16], wb[16];
    snprintf(gb, sizeof gb, "0x%04x", (unsigned)got);
    snprintf(wb, sizeof wb, "0x%04x", (unsigned)want);
    return lg_error_code(p->node, LG_ERR_DEVICE,
                         "gl pass '%s': %s %u (texture %u) is %s, the pass writes %s", p->name,
                         what, i, tex, g ? g : gb, w ? w : wb);
}

/* Attaches the target to the pass's framebuffer (made once) and checks it. */
static int attach(lg_gl_pass *p, const lg_gl_target *t)
{
    const lg_gl *gl = p->gl;
    if (t->width == 0 || t->height == 0)
        return lg_error(p->node, "gl pass '%s': the target is %ux%u", p->name, t->width, t->height);
    for (unsigned i = 0; i < LG_GL_PASS_MAX_COLORS; i++) {
        if (i < p->n_colors && !t->color[i])
            return lg_error_code(p->node, LG_ERR_DEVICE,
                                 "gl pass '%s': the target has no texture for colour %u", p->name,
                                 i);
        if (i >= p->n_colors && t->color[i])
            return lg_error(p->node,
                            "gl pass '%s': the target has a texture for colour %u, "
                            "the pass has %u colour attachment%s",
                            p->name, i, p->n_colors, p->n_colors == 1 ? "" : "s");
    }
    if (p->depth && !t->depth)
        return lg_error_code(p->node, LG_ERR_DEVICE,
                             "gl pass '%s': the target has no depth texture (an image "
                             "declared without LG_IMAGE_DEPTH?)",
                             p->name);
    int rc;
    for (unsigned i = 0; i < p->n_colors; i++)
        if ((rc = check_format(p, t->color[i], p->colors[i], "colour", i)))
            return rc;
    if (!p->fbo)
        gl->CreateFramebuffers(1, &p->fbo);
    GLenum bufs[LG_GL_PASS_MAX_COLORS];
    for (unsigned i = 0; i < LG_GL_PASS_MAX_COLORS; i++) {
        /* attached every time: a texture name the host deleted and made again is another
         * object, which a kept attachment would miss */
        gl->NamedFramebufferTexture(p->fbo, GL_COLOR_ATTACHMENT0 + i,
                                    i < p->n_colors ? t->color[i] : 0, 0);
        bufs[i] = GL_COLOR_ATTACHMENT0 + i;
    }
    gl->NamedFramebufferTexture(p->fbo, GL_DEPTH_ATTACHMENT, p->depth ? t->depth : 0, 0);
    if (p->n_colors) {
        gl->NamedFramebufferDrawBuffers(p->fbo, (GLsizei)p->n_colors, bufs);
        gl->NamedFramebufferReadBuffer(p->fbo, GL_COLOR_ATTACHMENT0);
    } else {
        gl->NamedFramebufferDrawBuffer(p->fbo, GL_NONE);
        gl->NamedFramebufferReadBuffer(p->fbo, GL_NONE);
    }
    GLenum status = gl->CheckNamedFramebufferStatus(p->fbo, GL_FRAMEBUFFER);
    if (status != GL_FRAMEBUFFER_COMPLETE)
        return lg_error_code(p->node, LG_ERR_DEVICE,
                             "gl pass '%s': the framebuffer (%u colour attachment%s%s, %ux%u) is "
                             "incomplete: status 0x%04x",
                             p->name, p->n_colors, p->n_colors == 1 ? "" : "s",
                             p->depth ? " and depth" : "", t->width, t->height, (unsigned)status);
    return 0;
}

/* ---- begin ----------------------------------------------------------------------------------- */

static void set_raster_state(lg_gl_pass *p)
{
    const lg_gl *gl = p->gl;
    gl->BindFramebuffer(GL_FRAMEBUFFER, p->fbo);
    gl->Viewport(0, 0, (GLsizei)p->target.width, (GLsizei)p->target.height);
    gl->Disable(GL_SCISSOR_TEST);
    for (unsigned i = 0; i < p->n_colors; i++)
        gl->ColorMaski(i, GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    if (p->depth_test)
        gl->Enable(GL_DEPTH_TEST);
    else
        gl->Disable(GL_DEPTH_TEST);
    gl->DepthFunc(p->depth_func);
    gl->DepthRangef(0.0f, 1.0f);
    gl->DepthMask(p->depth_write ? GL_TRUE : GL_FALSE);
    if (p->depth_clamp)
        gl->Enable(GL_DEPTH_CLAMP);
    else
        gl->Disable(GL_DEPTH_CLAMP);
    gl->Disable(GL_POLYGON_OFFSET_FILL);
    gl->Disable(GL_RASTERIZER_DISCARD);
    gl->PolygonMode(GL_FRONT_AND_BACK, GL_FILL);
    switch (p->blend) {
    case LG_GL_BLEND_NONE: gl->Disable(GL_BLEND); break;
    case LG_GL_BLEND_ALPHA:
        gl->Enable(GL_BLEND);
        gl->BlendEquation(GL_FUNC_ADD);
        gl->BlendFuncSeparate(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA, GL_ONE, GL_ONE_MINUS_SRC_ALPHA);
        break;
    case LG_GL_BLEND_PREMULTIPLIED:
        gl->Enable(GL_BLEND);
        gl->BlendEquation(GL_FUNC_ADD);
        gl->BlendFunc(GL_ONE, GL_ONE_MINUS_SRC_ALPHA);
        break;
    case LG_GL_BLEND_ADD:
        gl->Enable(GL_BLEND);
        gl->BlendEquation(GL_FUNC_ADD);
        gl->BlendFunc(GL_ONE, GL_ONE);
        break;
    }
    /* culling: the scene draw enables it per material; other draws cull when asked */
    gl->CullFace(p->cull == LG_GL_CULL_FRONT ? GL_FRONT : GL_BACK);
    if (p->cull != LG_GL_CULL_NONE && !p->scene_attribs)
        gl->Enable(GL_CULL_FACE);
    else
        gl->Disable(GL_CULL_FACE);
    gl->FrontFace(GL_CCW);
}

int lg_gl_pass_begin(lg_gl_pass *p, const lg_gl_target *target)
{
    if (p->failed)
        return lg_error_code(p->node, p->failed,
                             "gl pass '%s' is not usable: a name look-up failed (above)", p->name);
    if (p->active)
        return lg_error(p->node, "gl pass '%s': begin called twice without end", p->name);
    int rc;
    if (p->compute) {
        if (target)
            return lg_error(p->node, "gl pass '%s' is a compute pass: it has no target", p->name);
    } else {
        lg_gl_target t;
        if (!target) {
            if (!p->output)
                return lg_error(p->node,
                                "gl pass '%s' has no output port: give begin a "
                                "target",
                                p->name);
            if ((rc = lg_gl_target_output(p->node, p->output, &t)))
                return rc;
            target = &t;
        }
        if ((rc = attach(p, target)))
            return rc;
        p->target = *target;
    }
    p->active = true;
    p->bound_ssbo = p->bound_ubo = p->bound_tex = p->bound_img = p->bound_smp = 0;
    p->wrote_images = false;
    p->bind_failed = 0;
    p->gl->Disable(GL_TEXTURE_CUBE_MAP_SEAMLESS);
    p->seamless = false;
    if (!p->compute)
        set_raster_state(p);
    p->gl->UseProgram(p->program);
    return 0;
}

const lg_gl_target *lg_gl_pass_current_target(const lg_gl_pass *p)
{
    return p->active && !p->compute ? &p->target : NULL;
}

void lg_gl_pass_viewport(lg_gl_pass *p, int32_t x, int32_t y, uint32_t w, uint32_t h)
{
    p->gl->Viewport(x, y, (GLsizei)w, (GLsizei)h);
}

static bool integer_format(GLenum f)
{
    switch (f) {
    case GL_R8UI:
    case GL_R16UI:
    case GL_R32UI:
    case GL_RG8UI:
    case GL_RG16UI:
    case GL_RG32UI:
    case GL_RGBA8UI:
    case GL_RGBA16UI:
    case GL_RGBA32UI: return true;
    default: return false;
    }
}

static bool signed_format(GLenum f)
{
    switch (f) {
    case GL_R8I:
    case GL_R16I:
    case GL_R32I:
    case GL_RG8I:
    case GL_RG16I:
    case GL_RG32I:
    case GL_RGBA8I:
    case GL_RGBA16I:
    case GL_RGBA32I: return true;
    default: return false;
    }
}

void lg_gl_pass_clear_color(lg_gl_pass *p, unsigned i, const float rgba[4])
{
    if (!p->active || p->compute || i >= p->n_colors) {
        lg_error(p->node,
                 "gl pass '%s': clearing colour %u, which it does not have (or "
                 "outside begin/end)",
                 p->name, i);
        return;
    }
    if (integer_format(p->colors[i])) {
        GLuint v[4];
        for (int k = 0; k < 4; k++)
            v[k] = rgba[k] > 0.0f ? (GLuint)rgba[k] : 0u;
        p->gl->ClearNamedFramebufferuiv(p->fbo, GL_COLOR, (GLint)i, v);
    } else if (signed_format(p->colors[i])) {
        GLint v[4];
        for (int k = 0; k < 4; k++)
            v[k] = (GLint)rgba[k];
        p->gl->ClearNamedFramebufferiv(p->fbo, GL_COLOR, (GLint)i, v);
    } else {
        p->gl->ClearNamedFramebufferfv(p->fbo, GL_COLOR, (GLint)i, rgba);
    }
}

void lg_gl_pass_clear_depth(lg_gl_pass *p, float depth)
{
    if (!p->active || !p->depth) {
        lg_error(p->node,
                 "gl pass '%s': clearing a depth attachment it does not have (or "
                 "outside begin/end)",
                 p->name);
        return;
    }
    /* glClear honours the depth mask */
    p->gl->DepthMask(GL_TRUE);
    p->gl->ClearNamedFramebufferfv(p->fbo, GL_DEPTH, 0, &depth);
    p->gl->DepthMask(p->depth_write ? GL_TRUE : GL_FALSE);
}

/* ---- drawing --------------------------------------------------------------------------------- */

static bool key_matches(const pass_scene_key *k, const lg_scene *s)
{
    return k->n_meshes == s->n_meshes && k->n_instances == s->n_instances &&
           k->n_materials == s->n_materials &&
           (!s->n_meshes || memcmp(k->meshes, s->meshes, s->n_meshes * sizeof *s->meshes) == 0) &&
           (!s->n_instances ||
            memcmp(k->instances, s->instances, s->n_instances * sizeof *s->instances) == 0);
}

static int key_make(lg_node *n, pass_scene_key *k, const lg_scene *s)
{
    key_free(k);
    k->meshes = malloc((s->n_meshes ? s->n_meshes : 1) * sizeof *s->meshes);
    k->instances = malloc((s->n_instances ? s->n_instances : 1) * sizeof *s->instances);
    if (!k->meshes || !k->instances) {
        key_free(k);
        return lg_error_code(n, LG_ERR_NOMEM, "out of memory");
    }
    if (s->n_meshes)
        memcpy(k->meshes, s->meshes, s->n_meshes * sizeof *s->meshes);
    if (s->n_instances)
        memcpy(k->instances, s->instances, s->n_instances * sizeof *s->instances);
    k->n_meshes = s->n_meshes;
    k->n_instances = s->n_instances;
    k->n_materials = s->n_materials;
    return 0;
}

/* The scene's draw data: kept when the scene's geometry and instances are the same. */
static int scene_data(lg_gl_pass *p, const lg_resource *res)
{
    lg_node *n = p->node;
    const lg_scene *s = lg_scene_get(n, res);
    if (!s)
        return LG_ERR_INVALID;
    if (p->sgl && key_matches(&p->key, s)) {
        /* the same geometry, maybe on another (derived) scene: materials and the GPU
         * copies are read from the current one */
        p->sgl->scene = s;
        p->sgl->res = res;
        return 0;
    }
    lg_scene_gl_destroy(p->gl, p->sgl);
    p->sgl = NULL;
    p->posed_sgl = NULL; /* the new draw data holds the rest pose */
    key_free(&p->key);
    unsigned flags = p->scene_attribs & LG_GL_SCENE_NORMALS ? LG_SCENE_GL_NORMALS : 0;
    int rc = lg_scene_gl_create(n, res, flags, &p->sgl);
    if (!rc)
        rc = lg_scene_gl_upload(n, p->gl, p->sgl);
    if (!rc)
        rc = key_make(n, &p->key, s);
    if (rc) {
        lg_scene_gl_destroy(p->gl, p->sgl);
        p->sgl = NULL;
    }
    return rc;
}

int lg_gl_pass_draw_scene(lg_gl_pass *p, const lg_resource *scene, const lg_gl_scene_draw *d)
{
    if (!p->active || p->compute || !p->scene_attribs)
        return lg_error(p->node,
                        "gl pass '%s': lg_gl_pass_draw_scene needs a begun raster "
                        "pass whose descriptor names the scene's attributes",
                        p->name);
    int rc = scene_data(p, scene);
    if (rc)
        return rc;
    /* an animated scene: the matrices at the pass's time, filled again when it changed
     * (or the draw data was made again) */
    if (lg_scene_is_animated(p->sgl->scene) &&
        (p->sgl != p->posed_sgl || p->posed_time != p->pose_time)) {
        if ((rc = lg_scene_gl_pose(p->node, p->gl, p->sgl, p->pose_time)))
            return rc;
        p->posed_sgl = p->sgl;
        p->posed_time = p->pose_time;
    }
    lg_scene_gl_draw_desc sd = { .program = p->program,
                                 .first_location = p->first.location,
                                 .cull_material = p->cull != LG_GL_CULL_NONE };
    if (d) {
        sd.on_mesh = d->on_mesh;
        sd.on_batch = d->on_batch;
        sd.user = d->user;
    }
    p->bound_ssbo |= 1u; /* the instance records */
    if ((rc = lg_scene_gl_draw(p->node, p->gl, p->sgl, &sd)))
        return rc;
    char what[160];
    snprintf(what, sizeof what, "gl pass '%s': drawing the scene", p->name);
    return lg_gl_check(p->node, what);
}

void lg_gl_pass_set_time(lg_gl_pass *p, double time)
{
    if (p)
        p->pose_time = time;
}

const lg_scene_gl *lg_gl_pass_scene(const lg_gl_pass *p)
{
    return p ? p->sgl : NULL;
}

int lg_gl_pass_draw(lg_gl_pass *p, GLenum mode, uint32_t vertices)
{
    if (!p->active || p->compute)
        return lg_error(p->node, "gl pass '%s': lg_gl_pass_draw needs a begun raster pass",
                        p->name);
    const lg_gl *gl = p->gl;
    /* the core profile draws nothing without a vertex array, even one with no attributes */
    if (!p->empty_vao)
        gl->CreateVertexArrays(1, &p->empty_vao);
    gl->BindVertexArray(p->empty_vao);
    gl->DrawArrays(mode, 0, (GLsizei)vertices);
    char what[160];
    snprintf(what, sizeof what, "gl pass '%s': drawing %u vertices", p->name, vertices);
    return lg_gl_check(p->node, what);
}

/* ---- compute --------------------------------------------------------------------------------- */

void lg_gl_pass_local_size(const lg_gl_pass *p, uint32_t size[3])
{
    for (int i = 0; i < 3; i++)
        size[i] = p->compute && p->local[i] > 0 ? (uint32_t)p->local[i] : 1;
}

int lg_gl_pass_dispatch_groups(lg_gl_pass *p, uint32_t gx, uint32_t gy, uint32_t gz)
{
    if (!p->active || !p->compute)
        return lg_error(p->node, "gl pass '%s': dispatch needs a begun compute pass", p->name);
    const lg_gl *gl = p->gl;
    uint32_t g[3] = { gx, gy, gz };
    for (GLuint i = 0; i < 3; i++) {
        GLint max = 0;
        gl->GetIntegeri_v(GL_MAX_COMPUTE_WORK_GROUP_COUNT, i, &max);
        if (g[i] == 0 || (max > 0 && g[i] > (uint32_t)max))
            return lg_error_code(p->node, LG_ERR_UNSUPPORTED,
                                 "gl pass '%s': %u work groups along axis %u (this GL device "
                                 "takes 1..%d)",
                                 p->name, g[i], i, max);
    }
    gl->DispatchCompute(gx, gy, gz);
    char what[160];
    snprintf(what, sizeof what, "gl pass '%s': dispatching %ux%ux%u groups", p->name, gx, gy, gz);
    return lg_gl_check(p->node, what);
}

int lg_gl_pass_dispatch(lg_gl_pass *p, uint32_t w, uint32_t h, uint32_t d)
{
    uint32_t l[3], s[3] = { w ? w : 1, h ? h : 1, d ? d : 1 }, g[3];
    lg_gl_pass_local_size(p, l);
    for (int i = 0; i < 3; i++)
        g[i] = (uint32_t)(((uint64_t)s[i] + l[i] - 1) / l[i]);
    return lg_gl_pass_dispatch_groups(p, g[0], g[1], g[2]);
}

void lg_gl_pass_barrier(lg_gl_pass *p, GLbitfield bits)
{
    p->gl->MemoryBarrier(bits);
}

/* ---- end ------------------------------------------------------------------------------------- */

static void unbind_mask(const lg_gl *gl, GLenum target, uint32_t mask)
{
    for (GLuint i = 0; mask; i++, mask >>= 1)
        if (mask & 1u)
            gl->BindBufferBase(target, i, 0);
}

int lg_gl_pass_end(lg_gl_pass *p, int rc)
{
    if (!p->active) {
        int e = lg_error(p->node, "gl pass '%s': end without begin", p->name);
        return rc ? rc : e;
    }
    const lg_gl *gl = p->gl;
    if (p->compute && (p->wrote_images || p->bound_ssbo))
        /* whoever reads the results next: a texture fetch, an image load, a storage or
         * uniform read, a read-back or a copy */
        gl->MemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT |
                          GL_TEXTURE_UPDATE_BARRIER_BIT | GL_PIXEL_BUFFER_BARRIER_BIT |
                          GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT |
                          GL_UNIFORM_BARRIER_BIT);
    gl->UseProgram(0);
    unbind_mask(gl, GL_SHADER_STORAGE_BUFFER, p->bound_ssbo);
    unbind_mask(gl, GL_UNIFORM_BUFFER, p->bound_ubo);
    gl->BindBuffer(GL_SHADER_STORAGE_BUFFER, 0);
    gl->BindBuffer(GL_UNIFORM_BUFFER, 0);
    gl->BindBuffer(GL_ARRAY_BUFFER, 0);
    for (GLuint i = 0, m = p->bound_tex; m; i++, m >>= 1)
        if (m & 1u)
            gl->BindTextureUnit(i, 0);
    for (GLuint i = 0, m = p->bound_smp; m; i++, m >>= 1)
        if (m & 1u)
            gl->BindSampler(i, 0);
    if (p->seamless)
        gl->Disable(GL_TEXTURE_CUBE_MAP_SEAMLESS);
    for (GLuint i = 0, m = p->bound_img; m; i++, m >>= 1)
        if (m & 1u)
            gl->BindImageTexture(i, 0, 0, GL_FALSE, 0, GL_READ_ONLY, GL_R8);
    gl->ActiveTexture(GL_TEXTURE0);
    if (!p->compute) {
        gl->BindFramebuffer(GL_FRAMEBUFFER, 0);
        gl->BindVertexArray(0);
        gl->Disable(GL_DEPTH_TEST);
        gl->Disable(GL_DEPTH_CLAMP);
        gl->Disable(GL_BLEND);
        gl->Disable(GL_CULL_FACE);
        gl->Disable(GL_SCISSOR_TEST);
        gl->DepthMask(GL_TRUE);
        gl->DepthFunc(GL_LESS);
        gl->CullFace(GL_BACK);
        gl->FrontFace(GL_CCW);
        gl->BlendEquation(GL_FUNC_ADD);
        gl->BlendFunc(GL_ONE, GL_ZERO);
    }
    p->active = false;
    p->seamless = false;
    p->bound_ssbo = p->bound_ubo = p->bound_tex = p->bound_img = p->bound_smp = 0;
    memset(&p->target, 0, sizeof p->target);
    char what[160];
    snprintf(what, sizeof what, "gl pass '%s'", p->name);
    int e = lg_gl_check(p->node, what);
    if (!e)
        e = p->bind_failed;
    p->bind_failed = 0;
    return rc ? rc : e;
}
