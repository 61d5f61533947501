/*
 * lightgraph/gl_pass.h: one GL pass (raster or compute), made once and run every frame.
 * Optional, like lightgraph/gl.h, which it includes.
 *
 * A pass is made from a descriptor (zero means default) the first time a node executes, and
 * kept until the node is destroyed. It holds what does not change from frame to frame: the
 * program, the names of its uniforms and bindings, its framebuffer, and the scene's GL draw
 * data (vertex array and instance buffer, rebuilt only when the scene changes).
 *
 *     static const lg_gl_shader_src src[] = {
 *         { GL_VERTEX_SHADER, lg_src_my_vert_file, lg_src_my_vert },
 *         { GL_FRAGMENT_SHADER, lg_src_my_frag_file, lg_src_my_frag },
 *     };
 *     if (!st->pass) {                                  // in execute: GL is current
 *         lg_gl_pass_desc d = { .name = "my pass", .stages = src, .n_stages = 2,
 *                               .output = "out", .colors = { GL_RGBA32F }, .depth = true,
 *                               .depth_test = true, .depth_write = true,
 *                               .scene = LG_GL_SCENE_POSITIONS | LG_GL_SCENE_NORMALS };
 *         if ((rc = lg_gl_pass_create(n, &d, &st->pass))) return rc;
 *         st->u_view_proj = lg_gl_pass_uniform(st->pass, "u_view_proj");
 *     }
 *     if ((rc = lg_gl_pass_begin(st->pass, NULL))) return rc;  // maps "out", sets the state
 *     lg_gl_pass_clear_color(st->pass, 0, background);
 *     lg_gl_pass_clear_depth(st->pass, 1.0f);
 *     lg_gl_set_mat4(st->pass, st->u_view_proj, view.view_proj);
 *     rc = lg_gl_pass_draw_scene(st->pass, lg_input(n, 0), NULL);
 *     return lg_gl_pass_end(st->pass, rc);                // restores the state
 *
 *     lg_gl_pass_destroy(&st->pass);                     // in destroy
 *
 * Compute. A pass whose one stage is GL_COMPUTE_SHADER is a compute pass: begin makes its
 * program current, lg_gl_pass_dispatch runs it over a size (the group counts come from the
 * shader's local size), images and storage buffers are bound by their names in the shader.
 *
 * State. lg_gl_pass_begin sets all the state the pass relies on (below); lg_gl_pass_end
 * leaves GL as docs/devices.md ("The GL state contract") wants it after a node: framebuffer
 * 0 (draw and read), program 0, vertex array 0, buffer 0 on the generic GL_ARRAY_BUFFER,
 * GL_SHADER_STORAGE_BUFFER and GL_UNIFORM_BUFFER points, every indexed buffer binding
 * (lg_gl_pass_uniforms' blocks included), texture unit, sampler object and image unit the
 * pass bound unbound again, seamless cube maps off, active texture GL_TEXTURE0; and for a
 * raster pass the capabilities it changed at GL's defaults (depth test, depth clamp, blend,
 * cull face and scissor test disabled, depth mask true, glDepthFunc GL_LESS, glCullFace
 * GL_BACK, glFrontFace GL_CCW, blend GL_ONE, GL_ZERO, GL_FUNC_ADD). A node that runs only
 * passes therefore needs no unbinding code of its own, and needs no GL state call of its
 * own either: what a pass may change is in its descriptor (depth function, blending,
 * culling), its texture bindings (sampler state) and its uniforms (arrays, mat3, blocks).
 * Between begin and end the pass's program is current and its framebuffer bound.
 *
 * State set by begin, every pass: seamless cube maps off (a seamless binding turns them
 * on), the program. Raster passes also: the framebuffer with the target's textures
 * attached (made once, attached again at every begin, so that a texture the host re-made
 * is never missed), draw buffers = the colour attachments, viewport = the whole target,
 * scissor test off, colour mask all true, depth test (glDepthFunc = the descriptor's
 * depth_func, GL_LESS by default; glDepthRange 0..1) and depth mask as the descriptor
 * says, depth clamp, polygon offset off, rasterizer discard off, polygon mode fill,
 * blending, glCullFace (culling itself: see lg_gl_pass_draw_scene), glFrontFace GL_CCW.
 *
 * Errors. Every int function returns 0 or an LG_ERR_* after reporting on the node (the
 * message names the pass). lg_gl_pass_uniform and the binding look-ups report a name the
 * program does not have and leave the pass failed: its next begin returns LG_ERR_INVALID
 * without drawing, so that a node may look up all its names in a row and check once.
 *
 * Ownership. The pass owns its program, framebuffer, vertex arrays, instance buffer,
 * sampler objects and uniform-block buffers; lg_gl_pass_destroy deletes them and needs the node's GL context current (call it from
 * the node's destroy, or execute). Textures and buffers handed to the pass stay the
 * caller's (or the host's); the pass never deletes them. The descriptor and its strings
 * are copied: they need not outlive lg_gl_pass_create. One pass belongs to one node and one
 * thread.
 */
#ifndef LIGHTGRAPH_GL_PASS_H
#define LIGHTGRAPH_GL_PASS_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "lightgraph/gl.h"
#include "lightgraph/scene_gl.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Compile-time checks for a C struct that mirrors a std430 (or std140) block or struct:
 * its size and the byte offset of each member as the GLSL layout rules place them. Put
 * them next to the struct:
 *
 *     typedef struct my_light { float pos[4]; float color[3]; int32_t shadow; } my_light;
 *     LG_GL_BLOCK_SIZE(my_light, 32);          // struct LgLight { vec4 pos; vec3 color;
 *     LG_GL_BLOCK_OFFSET(my_light, shadow, 28); //                 int shadow; }
 *
 * The layout rules themselves are GLSL's (std430: a vec3 is aligned like a vec4 and a
 * scalar may follow it in its fourth slot; an array element or a struct is aligned to its
 * largest member; std140 also rounds arrays and structs up to 16 bytes). */
#ifdef __cplusplus
#define LG_GL_STATIC_ASSERT_ static_assert
#else
#define LG_GL_STATIC_ASSERT_ _Static_assert
#endif
#define LG_GL_BLOCK_SIZE(type, bytes)                                                              \
    LG_GL_STATIC_ASSERT_(sizeof(type) == (bytes),                                                  \
                         #type " does not have the size of its GLSL block (" #bytes " bytes)")
#define LG_GL_BLOCK_OFFSET(type, member, bytes)                                                    \
    LG_GL_STATIC_ASSERT_(offsetof(type, member) == (bytes),                                        \
                         #type "." #member " is not at its GLSL offset (" #bytes ")")

/* Colour attachments a raster pass may have. */
#define LG_GL_PASS_MAX_COLORS 4

typedef enum lg_gl_blend {
    LG_GL_BLEND_NONE = 0,      /* the fragment replaces the pixel */
    LG_GL_BLEND_ALPHA,         /* src * a + dst * (1 - a) */
    LG_GL_BLEND_PREMULTIPLIED, /* src + dst * (1 - a) */
    LG_GL_BLEND_ADD,           /* src + dst (accumulation) */
} lg_gl_blend;

typedef enum lg_gl_cull {
    LG_GL_CULL_NONE = 0, /* both sides are drawn */
    LG_GL_CULL_BACK,     /* back faces are culled */
    LG_GL_CULL_FRONT,    /* front faces are culled (shadow maps, against acne) */
} lg_gl_cull;

/* The scene's vertex attributes a pass reads (lg_gl_pass_desc.scene): attribute 0 =
 * positions (vec3) and, with normals, attribute 1 = normals (vec3); the instance records
 * are those of lightgraph/scene_gl.h ("Storage buffer"). */
enum {
    LG_GL_SCENE_POSITIONS = 1u << 0,
    LG_GL_SCENE_NORMALS = 1u << 1,
};

typedef struct lg_gl_pass_desc {
    size_t struct_size; /* 0 or sizeof(lg_gl_pass_desc) */
    const char *name;   /* for messages, e.g. "phong" (required) */

    /* The program: a vertex and a fragment stage (and an optional geometry or tessellation
     * stage), or one compute stage. `defines` as lg_gl_program has it (may be NULL). */
    const lg_gl_shader_src *stages;
    unsigned n_stages;
    const char *defines;

    /* Raster passes: where they draw. `output` names the node's output port (an image) that
     * lg_gl_pass_begin(pass, NULL) maps for writing: its colour texture becomes colour
     * attachment 0 and, with `depth`, its depth plane the depth attachment. NULL: the caller
     * gives a target to every begin. colors[i] is the GL internal format of attachment i
     * (GL_RGBA32F, GL_R32UI, ...), 0 after the last; begin checks each texture against it.
     * No colour and `depth`: a depth-only pass. */
    const char *output;
    GLenum colors[LG_GL_PASS_MAX_COLORS];
    bool depth;

    /* Raster state (zero: off). */
    bool depth_test;  /* against the depth attachment, with depth_func (GL_LESS) */
    bool depth_write; /* else glDepthMask(GL_FALSE) */
    bool depth_clamp; /* GL_DEPTH_CLAMP: nothing is clipped by the near and far planes */
    lg_gl_blend blend;
    lg_gl_cull cull;

    /* The scene's vertex attributes read by lg_gl_pass_draw_scene (LG_GL_SCENE_*); 0: the
     * pass does not draw a scene. `first_uniform` names the vertex stage's int uniform that
     * receives the index of a batch's first record (NULL: "u_first"). */
    unsigned scene;
    const char *first_uniform;

    /* Since ABI 3.0: the depth test's comparison (glDepthFunc), set at begin and restored
     * to GL_LESS at end. 0 = GL_LESS; GL_ALWAYS (a full-screen pass that writes every
     * pixel's depth whatever the cleared plane holds), GL_LEQUAL, GL_EQUAL, GL_GREATER,
     * GL_GEQUAL, GL_NOTEQUAL, GL_NEVER. Only meaningful with depth_test. */
    GLenum depth_func;

    void *reserved[4];
} lg_gl_pass_desc;

typedef struct lg_gl_pass lg_gl_pass;

/* Compiles and links the program (lg_gl_program, so messages name the files) and makes the
 * pass. Needs the node's GL context: call it from execute. On success *out is the pass. */
LG_API int lg_gl_pass_create(lg_node *node, const lg_gl_pass_desc *desc, lg_gl_pass **out);

/* Deletes the pass's GL objects, frees it and sets *pass to NULL. NULL and a NULL *pass are
 * allowed. */
LG_API void lg_gl_pass_destroy(lg_gl_pass **pass);

/* The program's name (for GL calls the pass does not wrap) and the pass's name. */
LG_API GLuint lg_gl_pass_program(const lg_gl_pass *pass);
LG_API const char *lg_gl_pass_name(const lg_gl_pass *pass);

/* ---- uniforms and bindings, resolved by name once -------------------------------------------- */

/* A uniform of the pass's program. location -1: absent (setters then do nothing). */
typedef struct lg_gl_uniform {
    GLint location;
} lg_gl_uniform;

/* The uniform `name` (an array element as "u_x[2]"). A name the program lacks (misspelt,
 * or unused by the shaders, which then drop it) is an error naming the pass, the uniform
 * and the program's files, and fails the pass (see "Errors"). */
LG_API lg_gl_uniform lg_gl_pass_uniform(lg_gl_pass *pass, const char *name);

/* The same, for a uniform that some variants of the program do not use (for example one
 * removed by a #define): absent is no error. */
LG_API lg_gl_uniform lg_gl_pass_uniform_optional(lg_gl_pass *pass, const char *name);

/* Typed setters (glProgramUniform*: the program need not be current). */
LG_API void lg_gl_set_int(lg_gl_pass *pass, lg_gl_uniform u, int32_t v);
LG_API void lg_gl_set_uint(lg_gl_pass *pass, lg_gl_uniform u, uint32_t v);
LG_API void lg_gl_set_float(lg_gl_pass *pass, lg_gl_uniform u, float v);
LG_API void lg_gl_set_ivec2(lg_gl_pass *pass, lg_gl_uniform u, int32_t x, int32_t y);
LG_API void lg_gl_set_ivec3(lg_gl_pass *pass, lg_gl_uniform u, int32_t x, int32_t y,
                            int32_t z); /* since ABI 2.6 */
LG_API void lg_gl_set_vec2(lg_gl_pass *pass, lg_gl_uniform u, float x, float y);
LG_API void lg_gl_set_vec3(lg_gl_pass *pass, lg_gl_uniform u, float x, float y, float z);
LG_API void lg_gl_set_vec3v(lg_gl_pass *pass, lg_gl_uniform u, const float v[3]);
LG_API void lg_gl_set_vec4v(lg_gl_pass *pass, lg_gl_uniform u, const float v[4]);
LG_API void lg_gl_set_mat4(lg_gl_pass *pass, lg_gl_uniform u, const float m[16]); /* column-major */

/* Since ABI 3.0: a mat3 (9 floats, column-major, as lightgraph/probe.h's rotation), and
 * arrays: `count` elements from element 0 of the array uniform `u` (look it up as "u_x" or
 * "u_x[0]"); v holds count floats, ints, vec3s (3 * count floats, packed) or vec4s
 * (4 * count floats). A count beyond the array's length is GL's error, reported at end. */
LG_API void lg_gl_set_mat3(lg_gl_pass *pass, lg_gl_uniform u, const float m[9]);
LG_API void lg_gl_set_floatv(lg_gl_pass *pass, lg_gl_uniform u, uint32_t count, const float *v);
LG_API void lg_gl_set_intv(lg_gl_pass *pass, lg_gl_uniform u, uint32_t count, const int32_t *v);
LG_API void lg_gl_set_vec3_array(lg_gl_pass *pass, lg_gl_uniform u, uint32_t count, const float *v);
LG_API void lg_gl_set_vec4_array(lg_gl_pass *pass, lg_gl_uniform u, uint32_t count, const float *v);

/* A binding point of the program, by the name of what the shader binds there:
 *   lg_gl_pass_storage        a shader storage block ("LgLights", the block's name)
 *   lg_gl_pass_uniform_block  a uniform block
 *   lg_gl_pass_texture        a sampler uniform ("u_atlas"): its texture unit
 *   lg_gl_pass_image          an image uniform ("u_in"): its image unit
 * The binding index is the one the shader declares (layout(binding = N)). A name the
 * program lacks is an error as for lg_gl_pass_uniform. */
typedef struct lg_gl_binding {
    GLint index; /* -1: absent */
    GLenum kind; /* GL_SHADER_STORAGE_BLOCK, GL_UNIFORM_BLOCK, GL_SAMPLER or GL_IMAGE_2D */
} lg_gl_binding;

LG_API lg_gl_binding lg_gl_pass_storage(lg_gl_pass *pass, const char *block);
LG_API lg_gl_binding lg_gl_pass_uniform_block(lg_gl_pass *pass, const char *block);
LG_API lg_gl_binding lg_gl_pass_texture(lg_gl_pass *pass, const char *sampler);
LG_API lg_gl_binding lg_gl_pass_image(lg_gl_pass *pass, const char *image);

/* Any of the four by `kind` (GL_SHADER_STORAGE_BLOCK, GL_UNIFORM_BLOCK, GL_SAMPLER,
 * GL_IMAGE_2D), for a binding that some variants of the program do not use: absent gives
 * index -1 (binding it then does nothing) and no error. */
LG_API lg_gl_binding lg_gl_pass_binding_optional(lg_gl_pass *pass, GLenum kind, const char *name);

/* The run-time half of LG_GL_BLOCK_SIZE: checks that the program's storage or uniform block
 * `block` has the layout a C struct of `size` bytes mirrors. For a block that ends in an
 * unsized array of structs (`LgLight lg_lights[];`) `size` is one element's and is compared
 * with the array's stride; otherwise with the block's size. A mismatch (or an absent block)
 * is an error naming the pass, the block and both sizes, and fails the pass. Returns 0 or
 * LG_ERR_INVALID. */
LG_API int lg_gl_pass_check_block(lg_gl_pass *pass, GLenum kind, const char *block, size_t size);

/* Since ABI 3.0: a whole uniform block from one C struct that mirrors it (sokol's
 * sg_apply_uniforms), in place of a setter call per uniform:
 *
 *     typedef struct my_params {            // layout(std140, binding = 1) uniform MyParams {
 *         float view_proj[16];              //     mat4 view_proj;
 *         float light_dir[3];               //     vec3 light_dir;
 *         float exposure;                   //     float exposure;
 *     } my_params;                          // };
 *     LG_GL_BLOCK_SIZE(my_params, 80);
 *     LG_GL_BLOCK_OFFSET(my_params, exposure, 76);
 *
 *     st->b_params = lg_gl_pass_uniform_block(st->pass, "MyParams");   // once
 *     ...
 *     my_params u = { .exposure = 2.0f, ... };                          // between begin and end
 *     if ((rc = lg_gl_pass_uniforms(st->pass, st->b_params, &u, sizeof u)))
 *         return lg_gl_pass_end(st->pass, rc);
 *
 * The pass owns one buffer per block binding (made at the first call, counted in the
 * node's profile with lg_account_alloc, deleted by lg_gl_pass_destroy). The first call for
 * a binding, and any call with another `size`, checks `size` against the block as
 * lg_gl_pass_check_block does (std140's rounding included: mirror a float array as
 * vec4-strided); a mismatch is an error naming the pass, the block and both sizes, and
 * fails the pass. Then `data` is uploaded and the buffer bound to the block's binding
 * until end. Calling it again before another draw replaces the values (GL keeps what an
 * earlier draw of the same pass read). An absent optional binding (index -1) does nothing
 * and returns 0. Returns 0, LG_ERR_INVALID (outside begin/end, not a uniform block, size
 * mismatch) or LG_ERR_DEVICE. */
LG_API int lg_gl_pass_uniforms(lg_gl_pass *pass, lg_gl_binding block, const void *data,
                               size_t size);

/* Binds, between begin and end (end unbinds): the whole of `buffer` to a storage or
 * uniform block; texture `tex` to a sampler's unit; level 0 of `tex` to an image unit with
 * `access` (GL_READ_ONLY, GL_WRITE_ONLY, GL_READ_WRITE) and `format` (GL_RGBA32F...). */
LG_API void lg_gl_pass_bind_buffer(lg_gl_pass *pass, lg_gl_binding b, GLuint buffer);
LG_API void lg_gl_pass_bind_texture(lg_gl_pass *pass, lg_gl_binding b, GLuint tex);
LG_API void lg_gl_pass_bind_image(lg_gl_pass *pass, lg_gl_binding b, GLuint tex, GLenum access,
                                  GLenum format);

/* Since ABI 2.6: lg_gl_pass_bind_image for any image of `tex`: mip `level`, and either one
 * `layer` (a layer of a 3D, array or cube-map texture, seen by the shader as a 2D image) or,
 * with layer = LG_GL_ALL_LAYERS, every layer at once (a 3D volume as an image3D, a cube
 * map as an imageCube). lg_gl_pass_bind_image(p, b, t, a, f) is
 * lg_gl_pass_bind_image_level(p, b, t, 0, 0, a, f): level 0, layer 0 (the whole of a 2D
 * texture). A level or layer outside the texture is GL's error, reported at end. */
#define LG_GL_ALL_LAYERS (-1)
LG_API void lg_gl_pass_bind_image_level(lg_gl_pass *pass, lg_gl_binding b, GLuint tex, GLint level,
                                        GLint layer, GLenum access, GLenum format);

/* Since ABI 3.0: how a texture binding samples (zero = bilinear, clamped to the edge, not
 * seamless, no comparison). */
typedef enum lg_gl_filter {
    LG_GL_FILTER_LINEAR = 0,    /* bilinear, level 0's neighbours (GL_LINEAR both ways) */
    LG_GL_FILTER_NEAREST,       /* the nearest texel (GL_NEAREST both ways) */
    LG_GL_FILTER_LINEAR_MIPMAP, /* trilinear: GL_LINEAR_MIPMAP_LINEAR, magnified GL_LINEAR */
} lg_gl_filter;

typedef enum lg_gl_wrap {
    LG_GL_WRAP_CLAMP = 0,   /* GL_CLAMP_TO_EDGE */
    LG_GL_WRAP_REPEAT,      /* GL_REPEAT */
    LG_GL_WRAP_MIRROR,      /* GL_MIRRORED_REPEAT */
    LG_GL_WRAP_BORDER_ZERO, /* GL_CLAMP_TO_BORDER with a border of (0, 0, 0, 0) */
} lg_gl_wrap;

typedef struct lg_gl_sampler {
    lg_gl_filter filter;
    lg_gl_wrap wrap;         /* all axes (S, T, R) */
    bool seamless_cube;      /* cube-map fetches filter across faces (see below) */
    bool compare_less_equal; /* depth comparison for a sampler2DShadow: GL_LEQUAL */
    uint32_t reserved[4];
} lg_gl_sampler;

/* Binds `tex` to the unit of sampler `b` with the sampler state `s` (NULL: the texture's
 * own parameters, as lg_gl_pass_bind_texture), between begin and end. The pass owns the
 * GL sampler objects: one per distinct state, made at its first use and deleted by
 * lg_gl_pass_destroy; end unbinds them from their units. seamless_cube sets
 * GL_TEXTURE_CUBE_MAP_SEAMLESS, which GL 4.5 core has as one switch for the whole context:
 * from this bind to end every cube-map fetch of the pass is seamless (begin turns it off,
 * end turns it off again). An unknown filter or wrap is an error reported on the node and
 * the binding is left unmade. */
LG_API void lg_gl_pass_bind_texture_sampled(lg_gl_pass *pass, lg_gl_binding b, GLuint tex,
                                            const lg_gl_sampler *s);

/* ---- a raster pass --------------------------------------------------------------------------- */

/* What a raster pass draws into: textures (color[i] for attachment i, depth for the depth
 * attachment; 0 where the descriptor has none) of width x height texels. */
typedef struct lg_gl_target {
    GLuint color[LG_GL_PASS_MAX_COLORS];
    GLuint depth;
    uint32_t width, height;
    uint32_t reserved[4];
} lg_gl_target;

/* Maps the node's output port `port` (by name) for writing and fills *t: color[0] = its
 * texture, depth = its depth plane (0 when it has none), its size. */
LG_API int lg_gl_target_output(lg_node *node, const char *port, lg_gl_target *t);

/* Starts the pass: for a raster pass binds the framebuffer with `target` (NULL: the
 * descriptor's output, mapped with lg_gl_target_output) and sets the state (see "State");
 * for a compute pass (target NULL) makes the program current. Returns LG_ERR_INVALID
 * without touching GL when a name look-up failed. After a failed begin, do not call end. */
LG_API int lg_gl_pass_begin(lg_gl_pass *pass, const lg_gl_target *target);

/* The target of the current raster pass (valid between begin and end). */
LG_API const lg_gl_target *lg_gl_pass_current_target(const lg_gl_pass *pass);

/* Draws into a part of the target (shadow-map tiles); begin sets the whole target. */
LG_API void lg_gl_pass_viewport(lg_gl_pass *pass, int32_t x, int32_t y, uint32_t width,
                                uint32_t height);

/* Clears colour attachment `i` to rgba (an integer format gets the values converted), or
 * the depth attachment to `depth`. */
LG_API void lg_gl_pass_clear_color(lg_gl_pass *pass, unsigned i, const float rgba[4]);
LG_API void lg_gl_pass_clear_depth(lg_gl_pass *pass, float depth);

/* How lg_gl_pass_draw_scene draws (all optional; NULL = none of them). The callbacks are
 * lightgraph/scene_gl.h's: on_mesh before a mesh's first batch (material uniforms, a
 * replacement normal buffer), on_batch before each instanced draw. */
typedef struct lg_gl_scene_draw {
    int (*on_mesh)(lg_node *node, void *user, uint32_t mesh, GLuint *normals);
    void (*on_batch)(void *user, uint32_t first);
    void *user;
    void *reserved[4];
} lg_gl_scene_draw;

/* Draws every instance of the scene resource `scene` (lightgraph/scene_gl.h: sorted by mesh
 * and handedness, one instanced draw per batch, the records at storage binding 0). The
 * draw data is made on the first call and kept; it is made again when a field of a mesh or
 * instance record changes (counts, array addresses, matrices) or the number of materials
 * does: a scene payload is immutable, so equal records mean equal geometry. Culling: with cull BACK or
 * FRONT, the faces of single-sided materials are culled and double-sided materials are
 * drawn from both sides (glTF's doubleSided); the window winding accounts for the
 * projection's flipped Y and for mirrored instances. Checks glGetError after. */
LG_API int lg_gl_pass_draw_scene(lg_gl_pass *pass, const lg_resource *scene,
                                 const lg_gl_scene_draw *draw);

/* Since ABI 3.1: the time (seconds, lg_frame.time) at which lg_gl_pass_draw_scene poses an
 * animated scene's instances (lg_scene_pose; 0 until set). A node that draws a scene calls
 * it in execute with frame->time; a static scene ignores it. */
LG_API void lg_gl_pass_set_time(lg_gl_pass *pass, double time);

/* The draw data of the last lg_gl_pass_draw_scene (its instance count and triangles, for
 * logs), or NULL before the first. Owned by the pass. */
LG_API const lg_scene_gl *lg_gl_pass_scene(const lg_gl_pass *pass);

/* Draws `vertices` vertices with no attributes (a full-screen triangle made from
 * gl_VertexID: mode GL_TRIANGLES, 3), through a vertex array the pass owns. */
LG_API int lg_gl_pass_draw(lg_gl_pass *pass, GLenum mode, uint32_t vertices);

/* ---- a compute pass -------------------------------------------------------------------------- */

/* Runs the program over width x height x depth invocations: ceil(size / local size) groups
 * per axis (0 counts as 1). Checks the counts against GL_MAX_COMPUTE_WORK_GROUP_COUNT. */
LG_API int lg_gl_pass_dispatch(lg_gl_pass *pass, uint32_t width, uint32_t height, uint32_t depth);

/* Runs gx x gy x gz work groups. */
LG_API int lg_gl_pass_dispatch_groups(lg_gl_pass *pass, uint32_t gx, uint32_t gy, uint32_t gz);

/* The program's local size (layout(local_size_x = ...)). */
LG_API void lg_gl_pass_local_size(const lg_gl_pass *pass, uint32_t size[3]);

/* glMemoryBarrier(bits): between dispatches that read what an earlier one wrote. end adds
 * the barrier that makes images and buffers written by a compute pass visible to whoever
 * reads them next (texture fetches, image loads, buffer reads, read-backs). */
LG_API void lg_gl_pass_barrier(lg_gl_pass *pass, GLbitfield bits);

/* ---- the end --------------------------------------------------------------------------------- */

/* Ends the pass and restores the state (see "State"); then reports a pending GL error
 * naming the pass. Returns `rc` when it is non-zero (the first error wins), else 0 or
 * LG_ERR_DEVICE: `return lg_gl_pass_end(pass, rc);` ends an execute. */
LG_API int lg_gl_pass_end(lg_gl_pass *pass, int rc);

#ifdef __cplusplus
}
#endif
#endif
