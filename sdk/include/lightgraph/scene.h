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
    /* Since ABI 3.1, in the place of two of four reserved pointers (an anonymous union, so
     * that the struct's size and layout stay those of 3.0; producers built against 3.0 leave
     * them NULL): */
    union {
        void *reserved[4];
        struct {
            /* 4 floats per vertex, or NULL: the tangent (xyz, unit, orthogonal to the
             * normal) and w = +1 or -1, the bitangent's sign: B = w (N x T) (glTF
             * TANGENT). The loader fills it for every mesh whose material has a normal
             * texture: the file's tangents, else MikkTSpace's (plugins/scene_gltf). */
            const float *tangents;
            const float *texcoords1; /* 2 floats per vertex (glTF TEXCOORD_1), or NULL */
            void *reserved_3_1[2];
        };
    };
} lg_mesh;

typedef struct lg_instance {
    uint32_t mesh;          /* index into lg_scene.meshes */
    float model[16];        /* object to world, column-major */
    float normal_matrix[9]; /* inverse transpose of model's 3x3, column-major */
    void *reserved[2];
} lg_instance;

struct lg_scene;

/* ---- Textures (since ABI 3.1) ---------------------------------------------------------------- */
/*
 * A scene's textures are glTF's three levels: images (decoded pixels), textures (an image
 * and how to sample it) and texture references in materials (a texture, a texture
 * coordinate set and KHR_texture_transform). Images are decoded by the scene node to RGBA8
 * as the file stores them: a colour texture (base colour, emissive) holds sRGB-encoded
 * values that the sampler decodes, a data texture (normal, occlusion, metallic-roughness)
 * linear values. glTF's texture coordinate (0, 0) is the image's top-left corner: row 0 of
 * `rgba8` is the image's top row and v grows downwards (the same as lightgraph's images).
 */
typedef struct lg_scene_image {
    const char *name; /* the image's uri or name, for messages */
    uint32_t width, height;
    const uint8_t *rgba8; /* width * height * 4 bytes, rows top to bottom */
    void *reserved[4];
} lg_scene_image;

/* A glTF sampler's values, as the GL enums glTF uses. 0 means "not given": magnification
 * and minification then default to linear and trilinear (linear-mipmap-linear), wrapping to
 * repeat. */
enum {
    LG_TEX_NEAREST = 9728,
    LG_TEX_LINEAR = 9729,
    LG_TEX_NEAREST_MIPMAP_NEAREST = 9984,
    LG_TEX_LINEAR_MIPMAP_NEAREST = 9985,
    LG_TEX_NEAREST_MIPMAP_LINEAR = 9986,
    LG_TEX_LINEAR_MIPMAP_LINEAR = 9987,
    LG_TEX_CLAMP_TO_EDGE = 33071,
    LG_TEX_MIRRORED_REPEAT = 33648,
    LG_TEX_REPEAT = 10497,
};

typedef struct lg_scene_texture {
    uint32_t image;                  /* index into lg_scene_textures.images */
    uint32_t mag_filter, min_filter; /* LG_TEX_* filter values, 0 = default */
    uint32_t wrap_s, wrap_t;         /* LG_TEX_* wrap values, 0 = repeat */
    uint32_t reserved_u32[3];
    void *reserved[2];
} lg_scene_texture;

/* A material's use of a texture. */
typedef struct lg_texture_ref {
    int32_t texture;   /* index into lg_scene_textures.textures; -1 = none */
    uint32_t texcoord; /* the texture coordinate set: 0 (TEXCOORD_0) or 1 (TEXCOORD_1) */
    /* normalTexture.scale (the X and Y of the tangent-space normal are multiplied by it),
     * occlusionTexture.strength (occlusion = 1 + strength (texel - 1)); 1 for the others */
    float scale;
    /* KHR_texture_transform as a 2x3 matrix, column-major: uv' = (t[0] u + t[2] v + t[4],
     * t[1] u + t[3] v + t[5]), i.e. T * R * S of the extension's offset, rotation and scale.
     * Identity {1, 0, 0, 1, 0, 0} when the reference has no transform. */
    float transform[6];
    uint32_t reserved[2];
} lg_texture_ref;

typedef enum lg_alpha_mode {
    LG_ALPHA_OPAQUE = 0, /* alpha ignored */
    LG_ALPHA_MASK,       /* alpha >= alpha_cutoff: opaque, else no surface at all */
    LG_ALPHA_BLEND,      /* blended over what lies behind (see the node's README) */
} lg_alpha_mode;

/* A material's textures (glTF 2.0 core materials). The surface's alpha is
 * base_color[3] times the base colour texture's alpha. */
typedef struct lg_material_maps {
    lg_texture_ref base_color;         /* sRGB RGB times lg_material.base_color; alpha */
    lg_texture_ref metallic_roughness; /* linear: B metallic, G roughness (times the factors) */
    lg_texture_ref normal;             /* linear tangent-space normal, 2 x texel - 1 */
    lg_texture_ref occlusion;          /* linear R: ambient occlusion */
    lg_texture_ref emissive;           /* sRGB RGB times lg_material.emissive */
    lg_alpha_mode alpha_mode;
    float alpha_cutoff; /* LG_ALPHA_MASK: 0.5 unless the file says */
    uint32_t reserved_u32[2];
    void *reserved[4];
} lg_material_maps;

/* The defaults: no texture (every ref's texture -1, scale 1, identity transform), opaque,
 * cutoff 0.5. Static data. */
LG_API const lg_material_maps *lg_material_maps_default(void);

/* The texture coordinates a reference reads, with its transform applied: uv0 and uv1 are
 * the vertex's (or fragment's) TEXCOORD_0 and TEXCOORD_1 (uv1 may be NULL when the mesh has
 * none: then set 1 reads set 0). */
static inline void lg_texture_ref_uv(const lg_texture_ref *r, const float *uv0, const float *uv1,
                                     float out[2])
{
    const float *uv = (r->texcoord == 1 && uv1) ? uv1 : uv0;
    const float *t = r->transform;
    float u = uv[0], v = uv[1];
    out[0] = t[0] * u + t[2] * v + t[4];
    out[1] = t[1] * u + t[3] * v + t[5];
}

/* The scene's textures (lg_scene.textures). */
typedef struct lg_scene_textures {
    const lg_scene_image *images;
    uint32_t n_images;
    const lg_scene_texture *textures;
    uint32_t n_textures;
    uint64_t bytes; /* decoded image bytes (counted against the scene node in the profile) */
    void *reserved[4];
} lg_scene_textures;

/* Samples texture reference `r` of scene `s` on the CPU at texture coordinates `uv` (the
 * transformed coordinates of lg_texture_ref_uv): bilinear on level 0 with the texture's
 * wrap modes (nearest when its mag_filter is LG_TEX_NEAREST), colour textures (`srgb`)
 * decoded from sRGB to linear before filtering. out = RGBA in [0, 1]; (1, 1, 1, 1) when the
 * reference has no texture or its index is out of range. Pure function of its inputs
 * (Embree filter functions, cpu backends and tests use it). */
LG_API void lg_scene_texture_sample(const struct lg_scene *s, const lg_texture_ref *r,
                                    const float uv[2], bool srgb, float out[4]);

/* The surface's alpha on material `m` at vertex coordinates uv0 / uv1 (base_color[3] times
 * the base colour texture's alpha), and whether an LG_ALPHA_MASK material has a surface
 * there (alpha >= cutoff). Materials not MASK always have one. */
LG_API bool lg_material_covers(const struct lg_scene *s, uint32_t material, const float *uv0,
                               const float *uv1);

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
    /* Since ABI 3.1, in the place of the first reserved pointer: the material's textures
     * and alpha mode, or NULL (no texture, opaque: what a 3.0 producer gives). Read it
     * through lg_material_maps_of(), which returns the defaults for NULL. */
    union {
        void *reserved[2];
        struct {
            const struct lg_material_maps *maps;
            void *reserved_3_1;
        };
    };
} lg_material;

/* The maps of material `m`: m->maps, or the defaults when the producer gave none. */
static inline const lg_material_maps *lg_material_maps_of(const lg_material *m)
{
    return m->maps ? m->maps : lg_material_maps_default();
}

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

/* ---- Density fields (since ABI 3.2) ---------------------------------------------------------- */
/*
 * A heterogeneous medium scales its coefficients by a density multiplier m(p) >= 0 at world
 * point p (lightgraph/medium.h: lg_medium_field_at evaluates it, lg_medium_field_max bounds
 * it over a box):
 *
 *     sigma_s(p) = density m(p) scattering,   sigma_t(p) = density m(p) (scattering + absorption)
 *     m(p) = inside(p) f(p) h(p)
 *
 *   f(p)      the field's kind: 1 (uniform), a voxel grid read trilinearly, or fBm noise;
 *   h(p)      height fog, exp(-height_falloff (p.y - height_base)) (y up, as glTF), 1 for
 *             height_falloff = 0; above height_base it thins out, below it thickens;
 *   inside(p) 1 inside [bounds_min, bounds_max] (closed), 0 outside.
 *
 * A scene whose medium has no field (lg_medium.field NULL, every 3.0 and 3.1 producer) is
 * homogeneous: m = 1 everywhere, exactly as before.
 */
typedef enum lg_field_kind {
    LG_FIELD_UNIFORM = 0, /* f = 1 (height fog alone, or a box of fog) */
    LG_FIELD_GRID,        /* f = the grid, trilinear between voxel centres */
    LG_FIELD_FBM,         /* f = fBm of gradient noise (lg_fbm3) */
} lg_field_kind;

/* A dense voxel grid (an OpenVDB float grid made dense over its active bounding box). */
typedef struct lg_density_grid {
    uint32_t nx, ny, nz; /* voxels, each >= 1 */
    const float *values; /* nx ny nz values, x fastest: values[i + nx (j + ny k)]; finite, >= 0 */
    float max_value;     /* the largest value */
    /* world -> index space, column-major affine: voxel (i, j, k)'s centre is at index point
     * (i, j, k) (OpenVDB's convention). f(p) is the trilinear blend of the eight voxels
     * around index point q = world_to_index p, a voxel outside the grid counting 0 (the VDB
     * background), so f falls to 0 over the voxel beyond the outer centres: OpenVDB's
     * tools::BoxSampler with a background of 0. */
    double world_to_index[16];
    double index_to_world[16]; /* its inverse */
    const char *source;        /* "FILE:GRID", for messages */
    void *reserved[4];
} lg_density_grid;

/* fBm noise: f(p) = scale max(0, sum_{o < octaves} gain^o noise(frequency lacunarity^o p
 * + seed offset) - offset), noise = lg_noise3 (improved Perlin gradient noise, in about
 * [-1, 1]). lg_fbm3 evaluates the sum. */
typedef struct lg_density_fbm {
    uint32_t octaves; /* 1 .. 16 */
    uint32_t seed;    /* shifts the lattice: different clouds for different seeds */
    float frequency;  /* of the first octave, 1 / scene unit, > 0 */
    float lacunarity; /* frequency ratio between octaves, >= 1 (2 usual) */
    float gain;       /* amplitude ratio, (0, 1) (0.5 usual) */
    float offset;     /* subtracted from the sum: > 0 leaves holes (clouds) */
    float scale;      /* multiplies what is left, >= 0 */
    uint32_t reserved[5];
} lg_density_fbm;

typedef struct lg_density_field {
    lg_field_kind kind;
    const lg_density_grid *grid; /* LG_FIELD_GRID */
    lg_density_fbm fbm;          /* LG_FIELD_FBM */
    float height_falloff;        /* >= 0, 1 / scene unit; 0 = no height fog */
    float height_base;           /* world y where h = 1 */
    /* the box outside which m = 0 (a grid: the support of f, the world box of index box
     * [-1, n] (one voxel beyond the outer centres), possibly clipped by a box given to the
     * medium; uniform and fBm: a box given to the medium, or -/+FLT_MAX for everywhere) */
    float bounds_min[3], bounds_max[3];
    void *reserved[4];
} lg_density_field;

/* A participating medium (TECHNIQUES.md §6). density scales the coefficients: sigma_s =
 * density * scattering, sigma_a = density * absorption, sigma_t = sigma_s + sigma_a, times
 * the field's multiplier where there is a field (above). present is true when the scene
 * declares one (density may still be 0). */
typedef struct lg_medium {
    bool present;
    float density;
    float scattering[3]; /* per unit density, 1/m */
    float absorption[3]; /* per unit density, 1/m */
    float g;             /* Henyey-Greenstein anisotropy, (-1, 1) */
    /* Since ABI 3.2, in the place of the first reserved pointer: the density field, NULL
     * for a homogeneous medium. Owned by the scene's producer (lives as long as the
     * scene). */
    union {
        void *reserved[4];
        struct {
            const lg_density_field *field;
            void *reserved_3_2[3];
        };
    };
} lg_medium;

/* ---- Rigid animation (since ABI 3.1) --------------------------------------------------------- */
/*
 * glTF node animations: channels that key a node's translation, rotation or scale. The
 * scene keeps the node tree so that a pose can be evaluated at any time; lg_scene_pose
 * turns it into instance matrices. lg_scene.instances holds the rest pose (the nodes'
 * own TRS), so a consumer that ignores animation draws the rest pose, as before.
 */
typedef enum lg_anim_path {
    LG_ANIM_TRANSLATION = 0, /* 3 floats per key */
    LG_ANIM_ROTATION,        /* 4 floats per key, a unit quaternion x, y, z, w */
    LG_ANIM_SCALE,           /* 3 floats per key */
} lg_anim_path;

typedef enum lg_anim_interp {
    LG_ANIM_LINEAR = 0, /* rotation: spherical linear (slerp, shortest path) */
    LG_ANIM_STEP,
    LG_ANIM_CUBICSPLINE, /* Hermite with the file's tangents (glTF 2.0 Appendix C) */
} lg_anim_interp;

typedef struct lg_anim_channel {
    uint32_t node; /* index into lg_scene_animation.nodes */
    lg_anim_path path;
    lg_anim_interp interpolation;
    uint32_t n_keys;    /* at least 1 */
    const float *times; /* n_keys seconds, strictly increasing, finite, >= 0 */
    /* n_keys values of the path's size; CUBICSPLINE: n_keys triples (in-tangent, value,
     * out-tangent), as glTF stores them */
    const float *values;
    void *reserved[2];
} lg_anim_channel;

typedef struct lg_anim_node {
    int32_t parent;       /* index into lg_scene_animation.nodes, -1 for a root */
    float translation[3]; /* the rest pose's TRS (a node given by a matrix has it */
    float rotation[4];    /* decomposed; glTF forbids animating such a node) */
    float scale[3];
    uint32_t animated; /* 1 when a channel targets this node or one of its ancestors */
    void *reserved[2];
} lg_anim_node;

typedef struct lg_scene_animation {
    const char *name; /* the glTF animation played, for messages */
    double duration;  /* the largest key time of its channels, seconds */
    const lg_anim_node *nodes;
    uint32_t n_nodes;
    const lg_anim_channel *channels;
    uint32_t n_channels;
    /* per instance (lg_scene.n_instances): the node whose world matrix places it */
    const uint32_t *instance_node;
    /* per light and per camera: the node that carries it, or -1 (not animated) */
    const int32_t *light_node, *camera_node;
    void *reserved[4];
} lg_scene_animation;

/* The scene's instances at `time` seconds: out[i] (n_instances of them) is instance i
 * with its model and normal matrices at that time. Times beyond the animation's duration
 * hold its last pose, times before 0 its first (no looping: the graph's frame time is the
 * animation's). A scene without animation gives its instances as they are. Returns 0, or
 * LG_ERR_INVALID (reported on `node`, which may be NULL) for a non-finite time. */
LG_API int lg_scene_pose(lg_node *node, const struct lg_scene *s, double time, lg_instance *out);

/* The scene's lights (n_lights of them into out) and cameras (n_cameras) at `time`, as
 * lg_scene_pose gives its instances: one carried by an animated node (light_node,
 * camera_node >= 0) moves with it, by D = world(time) * world(rest)^-1 of that node
 * (positions and a camera's target as points, directions and up as unit vectors); the
 * others are copied as they are. Returns 0, or LG_ERR_INVALID (reported on `node`, which
 * may be NULL) for a non-finite time, LG_ERR_NOMEM. Since ABI 3.1. */
LG_API int lg_scene_pose_lights(lg_node *node, const struct lg_scene *s, double time,
                                lg_light *out);
LG_API int lg_scene_pose_cameras(lg_node *node, const struct lg_scene *s, double time,
                                 lg_camera *out);

/* The scene as a node that reads lights and cameras sees it at `time`: *out is a shallow
 * copy of *s whose lights and cameras are posed (lg_scene_pose_lights, _cameras) into arrays
 * made here when the animation moves one of them; every other pointer is s's (instances
 * stay the rest pose: lg_scene_pose, lg_gl_pass_set_time). Free with lg_scene_at_free(s,
 * out), which frees only what this call made. Returns 0 or an LG_ERR_* (reported). */
LG_API int lg_scene_at(lg_node *node, const struct lg_scene *s, double time, struct lg_scene *out);
LG_API void lg_scene_at_free(const struct lg_scene *s, struct lg_scene *out);

/* True when the scene has an animation whose channels move something (duration may be 0:
 * a single key still poses the scene). */
LG_API bool lg_scene_is_animated(const struct lg_scene *s);

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
    /* Since ABI 3.1, in the place of two of eight reserved pointers (NULL from a 3.0
     * producer, and for a scene without textures or animation): */
    union {
        void *reserved[8];
        struct {
            const lg_scene_textures *textures;
            const lg_scene_animation *animation;
            void *reserved_3_1[6];
        };
    };
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
    /* Since ABI 3.1, in the place of two reserved words (anonymous union, same layout):
     * lg_mesh.tangents (4 floats a vertex) and lg_mesh.texcoords1 (2), 0 when the mesh
     * has none. lg_scene_mesh_gl uploads them with the other arrays (the CL copies do not
     * have them). */
    union {
        uint32_t reserved[4];
        struct {
            uint32_t tangents, texcoords1;
            uint32_t reserved_3_1[2];
        };
    };
} lg_mesh_gl;

typedef struct lg_mesh_cl {
    void *positions, *normals, *texcoords, *indices; /* cl_mem */
    void *reserved[4];
} lg_mesh_cl;

/* `res` is the scene resource the node received (lg_input). Returns 0 or an LG_ERR_*. */
LG_API int lg_scene_mesh_gl(lg_node *node, const lg_resource *res, uint32_t mesh, lg_mesh_gl *out);
LG_API int lg_scene_mesh_cl(lg_node *node, const lg_resource *res, uint32_t mesh, lg_mesh_cl *out);

/* Since ABI 3.1: the GL texture of scene texture `texture` (an index into
 * lg_scene.textures->textures) of the scene resource `res`: its image uploaded once per
 * scene by the host (like the meshes' arrays; a derived scene shares its source's copy),
 * owned by the host and freed with the scene, its bytes (every mip level) counted against
 * the node that asked first. `srgb` true: internal format GL_SRGB8_ALPHA8, for colour
 * textures (base colour, emissive: the sampler decodes sRGB to linear before filtering);
 * false: GL_RGBA8, for data (normal, occlusion, metallic-roughness). An image used both
 * ways gets one texture of each. The full mip chain is made by glGenerateTextureMipmap
 * (the driver's filter: a 2x2 box on Mesa, in linear space for sRGB). Sample it with the
 * texture's glTF sampler: lg_gl_sampler_scene (lightgraph/gl_pass.h). Errors: no textures,
 * an index out of range, an image without pixels, a size the device does not take. */
LG_API int lg_scene_texture_gl(lg_node *node, const lg_resource *res, int32_t texture, bool srgb,
                               uint32_t *out);

#ifdef __cplusplus
}
#endif
#endif
