/*
 * lightgraph/scene.h: the scene resource (LG_KIND_SCENE), what every technique renders and
 * what the planner reads to decide which effects a scene calls for.
 *
 * A scene is immutable CPU data made by a scene node (the `gltf` node of plugin scene_gltf,
 * or a node deriving one scene from another: camera, lights, medium) and published with
 *
 *     lg_declare_payload(n, port, LG_KIND_SCENE, &scene->features, scene, free_fn);
 *
 * The producing plugin owns the lg_scene and everything it points to, and frees it in
 * free_fn when the host releases the resource. Consumers read it with lg_scene_get() and
 * never modify it.
 *
 * GPU copies. A consumer that needs a mesh's vertex and index arrays in GL or CL asks with
 * lg_scene_mesh_gl() / lg_scene_mesh_cl(): the host uploads each array once per scene (not
 * per consumer), owns the GPU buffers, frees them with the scene, and counts the bytes
 * against the node that asked first. Derived scenes share their source's geometry and its
 * GPU copies (lg_scene.geometry).
 *
 * Geometry. Meshes are indexed triangle lists in object space. Instances place a mesh in
 * the world with a 4x4 matrix: several instances of one mesh share its arrays (the
 * scene's triangle count counts every instance; its memory counts each mesh once).
 * Every mesh has normals: the loader computes them when the file has none.
 *
 * Conventions: right-handed, Y-up world (glTF), metres as the file says, column-major
 * matrices (lightgraph/vecmath.h), linear RGB colours, angles in radians.
 */
#ifndef LIGHTGRAPH_SCENE_H
#define LIGHTGRAPH_SCENE_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "lightgraph/config.h"
#include "lightgraph/host.h"
#include "lightgraph/types.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct lg_mesh {
    const char *name; /* glTF "mesh name#primitive index", for messages */
    uint32_t n_vertices;
    uint32_t n_indices;                 /* 3 per triangle */
    const float *positions;             /* 3 floats per vertex */
    const float *normals;               /* 3 floats per vertex, unit length */
    const float *texcoords;             /* 2 floats per vertex, or NULL */
    const uint32_t *indices;            /* triangle list, every index < n_vertices */
    uint32_t material;                  /* index into lg_scene.materials */
    float bounds_min[3], bounds_max[3]; /* object space */
    void *reserved[4];
} lg_mesh;

typedef struct lg_instance {
    uint32_t mesh;          /* index into lg_scene.meshes */
    float model[16];        /* object to world, column-major */
    float normal_matrix[9]; /* inverse transpose of model's 3x3, column-major */
    void *reserved[2];
} lg_instance;

/* The Phong parameters of TECHNIQUES.md §1 (seed 1 eq. 1-4, 1-8):
 *   I = Ia ka Od + Ii [kd Od (N.L) + ks Os (R.V)^n]
 * mapped from glTF PBR by the loader (plugins/scene_gltf/README.md says how), and
 * overridden by the material's `extras` where it names them. */
typedef struct lg_material {
    const char *name;
    float ka, kd, ks;          /* ambient, diffuse, specular coefficients */
    float shininess;           /* n, >= 0 */
    float od[3];               /* object (diffuse) colour */
    float os[3];               /* specular colour */
    float base_color[4];       /* glTF baseColorFactor (linear RGBA) */
    float metallic, roughness; /* glTF metallicRoughness factors */
    float emissive[3];
    bool double_sided;
    /* Since ABI 2.2 (in the place of two of four reserved pointers): how much of the
     * environment the surface mirrors, per channel, at normal incidence (the F0 that
     * image-based lighting uses; Fresnel-Schlick raises it toward 1 at grazing angles).
     * From glTF: metals (metallic > 0) mix(F0 dielectric, baseColor, metallic) weighted
     * so that metallic 0 without KHR_materials_specular gives 0; a dielectric with
     * KHR_materials_specular its specular F0; `extras.reflectivity` (a number or
     * [r, g, b]) overrides. 0 means the material reflects nothing (plugins/scene_gltf/
     * README.md, "Materials"). roughness above is glTF's perceptual roughness. */
    float reflectivity[3];
    uint32_t reserved_u32;
    void *reserved[2];
} lg_material;

typedef enum lg_light_type {
    LG_LIGHT_DIRECTIONAL = 0,
    LG_LIGHT_POINT,
    LG_LIGHT_SPOT,
} lg_light_type;

typedef struct lg_light {
    const char *name;
    lg_light_type type;
    float color[3];               /* linear RGB */
    float intensity;              /* glTF units: lux (directional), candela (point, spot) */
    float direction[3];           /* world, unit: the direction the light travels */
    float position[3];            /* world (point, spot) */
    float range;                  /* 0 = infinite */
    float inner_cone, outer_cone; /* spot, radians */
    void *reserved[4];
} lg_light;

typedef struct lg_camera {
    const char *name;
    float position[3], target[3], up[3]; /* world */
    float yfov;                          /* vertical field of view, radians */
    float znear, zfar;                   /* zfar 0 = infinite (consumers pick from the bounds) */
    float aspect;                        /* 0 = from the output image */
    void *reserved[4];
} lg_camera;

/* A homogeneous participating medium (TECHNIQUES.md §6). density scales the coefficients:
 * sigma_s = density * scattering, sigma_a = density * absorption, sigma_t = sigma_s +
 * sigma_a. present is true when the scene declares one (density may still be 0). */
typedef struct lg_medium {
    bool present;
    float density;
    float scattering[3]; /* per unit density, 1/m */
    float absorption[3]; /* per unit density, 1/m */
    float g;             /* Henyey-Greenstein anisotropy, (-1, 1) */
    void *reserved[4];
} lg_medium;

typedef struct lg_scene {
    size_t struct_size; /* sizeof(lg_scene) */
    const char *source; /* the file it came from, or a description */
    const lg_mesh *meshes;
    uint32_t n_meshes;
    const lg_instance *instances;
    uint32_t n_instances;
    const lg_material *materials; /* at least one (a default) */
    uint32_t n_materials;
    const lg_light *lights;
    uint32_t n_lights;
    const lg_camera *cameras; /* at least one (the loader makes one from the bounds) */
    uint32_t n_cameras;
    uint32_t camera; /* the active camera */
    lg_medium medium;
    float bounds_min[3], bounds_max[3]; /* world, all instances */
    lg_scene_features features;
    /* The resource whose GPU copies hold this scene's geometry: the scene's own resource
     * (NULL) or, for a derived scene, its source's. */
    const lg_resource *geometry;
    void *reserved[8];
} lg_scene;

/* The scene on a resource, or NULL (after lg_error) if the resource is not a scene. */
LG_API const lg_scene *lg_scene_get(lg_node *node, const lg_resource *res);

/* Fills scene->features from its contents (triangles and vertices over instances, light
 * counts by type, medium with density > 0, any material with ks > 0, the materials with
 * a non-zero reflectivity that some instance draws). */
LG_API void lg_scene_compute_features(lg_scene *scene);

/* GPU copies of a mesh's arrays. Names are 0 (or NULL) for arrays the mesh lacks. */
typedef struct lg_mesh_gl {
    uint32_t positions, normals, texcoords; /* GL buffer objects, tightly packed floats */
    uint32_t indices;                       /* GL buffer of uint32 */
    uint32_t reserved[4];
} lg_mesh_gl;

typedef struct lg_mesh_cl {
    void *positions, *normals, *texcoords, *indices; /* cl_mem */
    void *reserved[4];
} lg_mesh_cl;

/* `res` is the scene resource the node received (lg_input). Returns 0 or an LG_ERR_*. */
LG_API int lg_scene_mesh_gl(lg_node *node, const lg_resource *res, uint32_t mesh, lg_mesh_gl *out);
LG_API int lg_scene_mesh_cl(lg_node *node, const lg_resource *res, uint32_t mesh, lg_mesh_cl *out);

#ifdef __cplusplus
}
#endif
#endif
