/*
 * lightgraph/scene_gl.h: a scene rasterised on GL, the part every raster technique shares
 * (plugins preview, shadowmap and phong): the camera's view and projection, the instances
 * to draw and their matrices in a storage buffer, one vertex array, and the draw loop.
 *
 *     lg_scene_view v;
 *     if ((rc = lg_scene_view_make(n, s, camera, width, height, &v))) return rc;
 *     lg_scene_gl *sgl = NULL;
 *     if ((rc = lg_scene_gl_create(n, scene_res, LG_SCENE_GL_NORMALS, &sgl))) return rc;
 *     ...                                       // program, framebuffer, fixed state
 *     rc = lg_scene_gl_upload(n, gl, sgl);      // the storage buffer and the vertex array
 *     gl->UseProgram(prog);                     // plus the caller's uniforms
 *     lg_scene_gl_draw_desc d = { .program = prog, .first_location = U_FIRST,
 *                                 .cull_material = true };
 *     if (!rc) rc = lg_scene_gl_draw(n, gl, sgl, &d);
 *     if (!rc) rc = lg_gl_check(n, "my pass: drawing the scene");
 *     ...                                       // restore the GL state (below)
 *     lg_scene_gl_destroy(gl, sgl);
 *
 * Camera. lg_scene_view_make applies the rules of plugins/preview/README.md ("Camera"):
 * the output's aspect ratio; when the camera has its own aspect and the output is narrower,
 * the vertical field of view widens to keep the camera's horizontal one (at most 3.1 rad);
 * zfar 0 means "from the scene's bounds" (the farthest corner along the view axis, plus
 * 1 %; at least 2 znear; 100 when nothing lies in front); znear 0 means zfar * 1e-4. The
 * projection flips Y in clip space, because texel row 0 is the image's top row
 * (docs/sdk.md, "Row order"): counter-clockwise front faces become clockwise in the
 * window, which lg_scene_gl_draw accounts for.
 *
 * Instances. lg_scene_gl_create checks what the draw relies on (instance -> mesh in range;
 * per drawn mesh: positions and indices (and normals with LG_SCENE_GL_NORMALS), a whole
 * number of triangles one draw can take, every index in range, a material that exists;
 * finite model matrices) and sorts the instances by mesh, then handedness (a model matrix
 * with a negative determinant mirrors), then scene order. Meshes without triangles are
 * left out. It does not touch GL.
 *
 * Storage buffer. One record per drawn instance in the sorted order, std430:
 *     mat4 model;                 always
 *     mat4 normal;                with LG_SCENE_GL_NORMALS: the 3x3 normal matrix in the
 *                                 upper-left, column-major, [3][3] = 1, the rest 0
 * lg_scene_gl_draw binds a range of it at GL_SHADER_STORAGE_BUFFER binding 0 and sets the
 * program's int uniform `first_location` to the index, within that range, of the batch's
 * first instance: the vertex shader reads record (first + gl_InstanceID).
 *
 * Vertex array. Attribute 0 = positions (vec3, buffer binding 0); with LG_SCENE_GL_NORMALS,
 * attribute 1 = normals (vec3, buffer binding 1). The buffers are the scene's GPU copies
 * (lg_scene_mesh_gl), bound per mesh by the draw; the element buffer is the mesh's indices.
 *
 * Ownership. The lg_scene_gl owns its vertex array and storage buffer (made by
 * lg_scene_gl_upload, deleted by lg_scene_gl_destroy, which needs the GL context current,
 * i.e. call it from execute); the meshes' buffers belong to the host (scene.h).
 *
 * GL state. lg_scene_gl_draw sets only: the vertex array binding (its own), the vertex
 * array's buffers, the storage-buffer binding 0 (generic and indexed), GL_CULL_FACE
 * (enabled per mesh when desc->cull_material and the material is single-sided, else
 * disabled), glFrontFace (GL_CW, GL_CCW for mirrored instances) and the uniform
 * `first_location` of desc->program. Everything else (framebuffer, viewport, depth test,
 * glCullFace, program in use, the caller's uniforms) is the caller's to set before. Before
 * execute returns, the caller restores what docs/devices.md ("The GL state contract")
 * asks: at least glBindVertexArray(0), glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, 0)
 * and glBindBuffer(GL_SHADER_STORAGE_BUFFER, 0).
 *
 * Errors. Every function returns 0 or an LG_ERR_* after reporting on the node: the
 * message names the camera, mesh or instance and the value at fault.
 *
 * Compatibility. Like the other public structs, these end in reserved fields that must be
 * zero, so that a later minor version can add fields without breaking plugins built
 * against this one. lightgraph/gl_pass.h builds on these functions and keeps the draw data
 * across frames; prefer it for a new node.
 */
#ifndef LIGHTGRAPH_SCENE_GL_H
#define LIGHTGRAPH_SCENE_GL_H

#include <stdbool.h>
#include <stdint.h>

#include "lightgraph/gl.h"
#include "lightgraph/vecmath.h"
#include "lightgraph/scene.h"

#ifdef __cplusplus
extern "C" {
#endif

/* A camera's matrices for an output of a given size (column-major, OpenGL clip space with
 * Y flipped). */
typedef struct lg_scene_view {
    float view[16], proj[16], view_proj[16];
    float znear, zfar;    /* the depth range used, after the zfar 0 / znear 0 rules */
    float yfov;           /* the vertical field of view used, radians */
    uint32_t camera;      /* index of the camera in the scene */
    lg_vec3 eye;          /* the camera's position */
    lg_vec3 forward;      /* unit vector from the position to the target */
    uint32_t reserved[8]; /* zero (lg_scene_view_make clears them) */
} lg_scene_view;

/* The view of camera `camera` of `s` (-1: the scene's active camera) for a width x height
 * output (both > 0). Errors: no camera, an index out of range, a value not finite, a field
 * of view outside (0, 3.1), znear/zfar not a range, position = target. */
LG_API int lg_scene_view_make(lg_node *node, const lg_scene *s, int64_t camera, uint32_t width,
                              uint32_t height, lg_scene_view *out);

/* Flags of lg_scene_gl_create. */
enum {
    /* meshes must have normals; records carry the normal matrix; vertex attribute 1 */
    LG_SCENE_GL_NORMALS = 1u << 0,
};

/* One drawn instance. */
typedef struct lg_scene_gl_item {
    uint32_t mesh;
    uint32_t mirrored; /* 1 when the model matrix has a negative determinant */
    uint32_t instance; /* index in lg_scene.instances */
    uint32_t reserved; /* zero */
} lg_scene_gl_item;

typedef struct lg_scene_gl {
    const lg_scene *scene;
    const lg_resource *res;  /* the scene resource (for lg_scene_mesh_gl) */
    unsigned flags;          /* LG_SCENE_GL_* */
    lg_scene_gl_item *items; /* count items, sorted (see above) */
    uint32_t count;
    uint64_t triangles;    /* triangles of one draw of every item */
    size_t record_size;    /* bytes of one storage-buffer record: 64, or 128 with normals */
    GLuint vao, instances; /* 0 until lg_scene_gl_upload; instances stays 0 if count = 0 */
    void *reserved[4];     /* zero */
} lg_scene_gl;

/* Checks and sorts the instances of the scene resource `scene_res` (see "Instances"). On
 * success *out is a new lg_scene_gl, to be freed with lg_scene_gl_destroy. */
LG_API int lg_scene_gl_create(lg_node *node, const lg_resource *scene_res, unsigned flags,
                              lg_scene_gl **out);

/* Makes the storage buffer (when there are instances) and the vertex array. Once. */
LG_API int lg_scene_gl_upload(lg_node *node, const lg_gl *gl, lg_scene_gl *sgl);

/* Since ABI 3.1: refills the storage buffer with the instances' matrices at `time` seconds
 * (lg_scene_pose) when the scene is animated; does nothing for a static one. The sorting
 * (mesh, handedness) stays that of the rest pose: an animation that mirrors an instance
 * (a negative scale key) draws it with the rest pose's winding. Returns 0 or an LG_ERR_*
 * (a non-finite time or a posed matrix that is not finite). */
LG_API int lg_scene_gl_pose(lg_node *node, const lg_gl *gl, lg_scene_gl *sgl, double time);

/* How to draw. Only program and first_location are required. */
typedef struct lg_scene_gl_draw_desc {
    GLuint program;       /* the program in use: receives first_location */
    GLint first_location; /* its int uniform: first record of the batch, within the range */
    /* cull the back faces of single-sided materials (GL_CULL_FACE per mesh; glCullFace is
     * the caller's). Batches then also split by handedness, so that each has one winding. */
    bool cull_material;
    /* Optional: called when the draw moves to another mesh, before its first batch; may set
     * uniforms (the material's) and replace *normals, the normal buffer to bind (with
     * LG_SCENE_GL_NORMALS). A non-zero return stops the draw and is returned. */
    int (*on_mesh)(lg_node *node, void *user, uint32_t mesh, GLuint *normals);
    /* Optional: called before each instanced draw; `first` = index in sgl->items of the
     * batch's first instance. */
    void (*on_batch)(void *user, uint32_t first);
    void *user;
    void *reserved[4]; /* zero (designated initialisers leave them so) */
} lg_scene_gl_draw_desc;

/* Draws every item: one instanced draw per mesh (per mesh and handedness when culling),
 * split where a batch would exceed GL_MAX_SHADER_STORAGE_BLOCK_SIZE. The caller has bound
 * the framebuffer and the program and set the state, and checks glGetError after
 * (lg_gl_check, with its own description of the pass). */
LG_API int lg_scene_gl_draw(lg_node *node, const lg_gl *gl, const lg_scene_gl *sgl,
                            const lg_scene_gl_draw_desc *desc);

/* Frees the items and deletes the GL objects (gl may be NULL when upload was never
 * called). NULL sgl is allowed. */
LG_API void lg_scene_gl_destroy(const lg_gl *gl, lg_scene_gl *sgl);

#ifdef __cplusplus
}
#endif
#endif
