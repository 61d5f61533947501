/*
 * tests/common/testscene.h: the scene builder of the test plugins that make an lg_scene in
 * memory (testiblscene, testphongscene, testmeshscene, testprtscene, testprtinputs,
 * testcube, shadowprobe, testvolscene, testvsinputs), so that each describes its scene and
 * none repeats the bookkeeping: arrays, growth, out-of-memory paths, instance normal
 * matrices, bounds, features, the payload and its free function. Linked into those plugins
 * as a static library (lg_test_scene_dep, tests/common/meson.build).
 *
 * Use:
 *
 *     lg_ts_builder *b = lg_ts_begin("test_x_scene");      // NULL only if out of memory
 *     lg_material *m = lg_ts_material(b, "test");          // zeroed, fill what you need
 *     m->kd = 1.0f;
 *     lg_ts_mesh(b, "test mesh#0", 0);                     // mesh 0, material 0
 *     lg_ts_quad(b, NULL, lg_v3(1, 0, 0), lg_v3(0, 1, 0), NULL);
 *     lg_ts_instance(b, 0, NULL);                          // identity
 *     lg_ts_camera(b, "test", eye, target, up, yfov, 0.1f, 50.0f);
 *     return lg_ts_publish(n, 0, b);                       // consumes b
 *
 * Ownership. The builder owns everything it is given or makes; lg_ts_publish and
 * lg_ts_finish consume it (the scene they give back is the builder's own memory, freed by
 * lg_ts_free), lg_ts_abandon frees it unfinished. Strings (source, mesh, material, light
 * and camera names) are NOT copied: pass literals, or strings that outlive the scene.
 * A pointer the builder returns into its arrays (lg_ts_material, lg_ts_camera,
 * lg_ts_light, lg_ts_indices) stays valid until the next call that adds to the same array.
 *
 * Errors. An allocation that fails makes the builder sticky-failed: every later call does
 * nothing (returning 0 or a pointer to a scratch record), and lg_ts_publish reports
 * "out of memory" on the node. Calls are not validated against the scene's rules (an
 * index past a mesh's vertices, an instance of a mesh that does not exist, no camera, no
 * material): tests make such scenes on purpose.
 *
 * Order. Meshes, instances, materials, lights and cameras appear in the scene in the order
 * they were added; vertices and triangles in a mesh likewise. Arithmetic is spelled out for
 * every shape below, so that a test can compute the same floats.
 */
#ifndef LG_TEST_COMMON_TESTSCENE_H
#define LG_TEST_COMMON_TESTSCENE_H

#include <stdbool.h>
#include <stdint.h>

#include "lightgraph/lightgraph.h"
#include "lightgraph/scene.h"
#include "lightgraph/vecmath.h"

typedef struct lg_ts_builder lg_ts_builder;

/* A new, empty scene (no mesh, material, light or camera; camera index 0; no medium)
 * whose lg_scene.source is `source`. NULL when out of memory. */
lg_ts_builder *lg_ts_begin(const char *source);

/* ---- meshes ---------------------------------------------------------------------------------- */

/* Starts mesh number lg_scene.n_meshes (returned) drawn with material `material`; the
 * vertex and triangle calls below append to it until the next lg_ts_mesh. */
uint32_t lg_ts_mesh(lg_ts_builder *b, const char *name, uint32_t material);

/* Appends a vertex to the current mesh; returns its index in the mesh. */
uint32_t lg_ts_vertex(lg_ts_builder *b, lg_vec3 position, lg_vec3 normal);

/* The same with position and normal given in double precision, each component rounded to
 * float (the arithmetic of shapes computed in double). */
uint32_t lg_ts_vertex_d(lg_ts_builder *b, const double position[3], const double normal[3]);

/* Appends the triangle (i0, i1, i2) of the current mesh's vertex indices, as given. */
void lg_ts_triangle(lg_ts_builder *b, uint32_t i0, uint32_t i1, uint32_t i2);

/* The current mesh's index array (n_indices of them so far), to spoil on purpose. */
uint32_t *lg_ts_indices(lg_ts_builder *b);

/* The triangles of a grid of cols x rows cells over the last (cols + 1) (rows + 1)
 * vertices added, row-major (vertex (i, j) at first + j (cols + 1) + i): cell (i, j) with
 * a = its vertex (i, j) and W = cols + 1 gives (a, a+1, a+W+1) and (a, a+W+1, a+W), or with
 * `flip` the other winding, (a, a+W+1, a+1) and (a, a+W, a+W+1). */
void lg_ts_grid_triangles(lg_ts_builder *b, uint32_t cols, uint32_t rows, bool flip);

/* A quad of 4 vertices and 2 triangles in the current mesh: vertex k at
 * centre + (su_k u + sv_k v) with (su, sv) = (-1, -1), (1, -1), (1, 1), (-1, 1), triangles
 * (0, 1, 2) and (0, 2, 3): its front (counter-clockwise) side faces u x v. `centre` NULL:
 * the position is su_k u + sv_k v with nothing added (a zero centre would turn -0 into +0).
 * `normal` NULL: every vertex's normal is lg_v3_normalize_or(u x v, +Z). */
void lg_ts_quad(lg_ts_builder *b, const lg_vec3 *centre, lg_vec3 u, lg_vec3 v,
                const lg_vec3 *normal);

/* A grid of s x s quads over centre +- u +- v in the current mesh, facing u x v: vertex
 * (i, j) (i, j = 0 .. s, row-major) at centre + (a u + c v) with a = 2 i / s - 1,
 * c = 2 j / s - 1 in float, normal lg_v3_normalize_or(u x v, +Z); the triangles of
 * lg_ts_grid_triangles(b, s, s, false). */
void lg_ts_grid(lg_ts_builder *b, lg_vec3 centre, lg_vec3 u, lg_vec3 v, uint32_t s);

/* A g x g grid spanned from a corner, computed in double: vertex (i, j) at
 * origin + (i / g) span_u + (j / g) span_v, every normal `normal`; the triangles of
 * lg_ts_grid_triangles(b, g, g, flip) (flip: counter-clockwise seen from the side
 * span_v x span_u points to, whatever `normal` says). */
void lg_ts_grid_span(lg_ts_builder *b, uint32_t g, const double origin[3], const double span_u[3],
                     const double span_v[3], const double normal[3], bool flip);

/* The unit cube (edge 1) at the origin, 24 vertices with face normals, 12 triangles
 * counter-clockwise seen from outside, faces in the order +X, -X, +Y, -Y, +Z, -Z: each
 * face an lg_ts_quad (grid_faces false) or a 1 x 1 lg_ts_grid (true: the vertex order of
 * the phong tests' cube). */
void lg_ts_unit_cube(lg_ts_builder *b, bool grid_faces);

/* A box of half extents `half` at the origin, 24 vertices with face normals, 12 triangles
 * counter-clockwise seen from outside; faces +X, -X, +Y, -Y, +Z, -Z, each with its axis a,
 * b = the next axis, c = the one after (a, b, c = x, y, z; y, z, x; z, x, y) and
 * s = +-1: vertex k at p[a] = s half[a], p[b] = s su_k half[b], p[c] = sv_k half[c]
 * ((su, sv) as in lg_ts_quad), triangles (0, 1, 2), (0, 2, 3). */
void lg_ts_box(lg_ts_builder *b, lg_vec3 half);

/* A UV sphere: cols x rows quads, (cols + 1) (rows + 1) vertices, vertex (i, j) (row j from
 * +Y, j = 0 .. rows; column i = 0 .. cols) with th = pi j / rows, ph = 2 pi i / cols in
 * double and n = (sin th cos ph, cos th, -sin th sin ph) rounded to float: normal n,
 * position centre + radius n (`centre` NULL: radius n, nothing added); quad (i, j) with
 * a = vertex (i, j), W = cols + 1 gives triangles (a, a+W, a+W+1) and (a, a+W+1, a+1),
 * counter-clockwise seen from outside. */
void lg_ts_uv_sphere(lg_ts_builder *b, const lg_vec3 *centre, float radius, uint32_t cols,
                     uint32_t rows);

/* ---- instances, materials, lights, cameras, medium ------------------------------------------- */

/* An instance of mesh `mesh` (not checked) with `model` (column-major; NULL: identity) and
 * its normal matrix (lg_m4_normal_matrix). Returns its index. */
uint32_t lg_ts_instance(lg_ts_builder *b, uint32_t mesh, const float model[16]);

/* A new material, zeroed but for its name, for the caller to fill. */
lg_material *lg_ts_material(lg_ts_builder *b, const char *name);

/* A new light, zeroed but for its name and type, for the caller to fill. */
lg_light *lg_ts_light(lg_ts_builder *b, const char *name, lg_light_type type);

/* A directional light travelling along `direction` (taken as given, not normalised). */
lg_light *lg_ts_dir_light(lg_ts_builder *b, const char *name, lg_vec3 direction, lg_vec3 color,
                          float intensity);

/* A camera at `position` looking at `target` (aspect 0: from the image); more fields can
 * be set through the pointer. */
lg_camera *lg_ts_camera(lg_ts_builder *b, const char *name, lg_vec3 position, lg_vec3 target,
                        lg_vec3 up, float yfov, float znear, float zfar);

/* The scene's medium (present = true). */
void lg_ts_medium(lg_ts_builder *b, float density, lg_vec3 scattering, lg_vec3 absorption, float g);

/* ---- the end --------------------------------------------------------------------------------- */

/* Finishes the scene: its arrays, every mesh's bounds and the world bounds
 * (lg_test_scene_bounds), its features (lg_scene_compute_features). Consumes `b`; returns
 * the scene, which the caller frees with lg_ts_free, or NULL if some allocation failed. */
lg_scene *lg_ts_finish(lg_ts_builder *b);

/* Frees a scene lg_ts_finish made (NULL: nothing); the free_fn of its payload. */
void lg_ts_free(void *scene);

/* Frees an unfinished builder (NULL: nothing). */
void lg_ts_abandon(lg_ts_builder *b);

/* lg_ts_finish, then declares the scene as node n's payload on output `port`
 * (LG_KIND_SCENE, freed by lg_ts_free when the host releases it). Consumes `b` (NULL is
 * taken as out of memory). Returns 0, LG_ERR_NOMEM after lg_error on n, or what
 * declare_payload returned. */
int lg_ts_publish(lg_node *n, uint32_t port, lg_ts_builder *b);

/* Sets each of meshes[0 .. s->n_meshes) bounds from its positions, then s's world bounds
 * from the eight corners of each instance's mesh bounds through the instance's model
 * matrix. `meshes` is s->meshes, writable. Instances of a mesh that does not exist are
 * passed over; with no instance the world bounds stay empty (+inf, -inf). */
void lg_test_scene_bounds(lg_scene *s, lg_mesh *meshes);

#endif
