/*
 * The scene_gltf plugin: node `gltf`, a glTF 2.0 file (.gltf or .glb, Draco included) as
 * a scene resource (lightgraph/scene.h). The loading is gltf_load.c's; README.md
 * describes the node, the mappings and the limits.
 *
 * The file is read in prepare(), not execute(): the planner gates downstream nodes by the
 * scene's features, which must exist before those nodes are prepared. execute() has
 * nothing left to do.
 */
#include <inttypes.h>
#include <stdlib.h>

#include "gltf_load.h"
#include "lightgraph/lightgraph.h"

static const char *const normals_values[] = { "auto", "smooth", "flat", NULL };

static const lg_param_desc params[] = {
    { .key = "file",
      .type = LG_PARAM_PATH,
      .def.s = "",
      .doc = "the .gltf or .glb file (Draco-compressed meshes included)" },
    { .key = "scene",
      .type = LG_PARAM_INT,
      .def.i = -1,
      .min = -1,
      .max = 1e9,
      .doc = "the glTF scene to load; -1: the file's default, else scene 0, else every root node" },
    { .key = "camera",
      .type = LG_PARAM_INT,
      .def.i = -1,
      .min = -1,
      .max = 1e9,
      .doc = "the active camera: the file's cameras in node order, then the automatic one; "
             "-1: the first" },
    { .key = "normals",
      .type = LG_PARAM_ENUM,
      .def.e = 0,
      .enum_values = normals_values,
      .doc = "auto: the file's normals, else smooth; smooth: computed, split at crease_deg; "
             "flat: one per facet" },
    { .key = "crease_deg",
      .type = LG_PARAM_FLOAT,
      .def.f = 60,
      .min = 0,
      .max = 180,
      .doc = "smooth normals: facets meeting at more than this angle (degrees) keep a crease" },
    { .key = "animation",
      .type = LG_PARAM_INT,
      .def.i = 0,
      .min = -1,
      .max = 1e9,
      .doc = "the glTF animation played by --frames/--dt (lg_scene.animation): its index among "
             "the file's animations (0, the first, is ignored in a file without any); -1: none, "
             "the rest pose" },
};

static const lg_port_desc outputs[] = {
    { .name = "scene",
      .kind = LG_KIND_SCENE,
      .doc = "meshes, instances, materials, lights, cameras and medium of the file" },
};

static void free_scene(void *payload)
{
    lg_gltf_scene_free(payload);
}

static void log_warning(void *user, const char *message)
{
    lg_log(user, LG_LOG_WARN, "%s", message);
}

static int gltf_prepare(lg_node *n)
{
    const char *path = lg_param_string(n, "file");
    if (!path || !*path)
        return lg_error(n, "parameter 'file' is empty: name a .gltf or .glb file");
    lg_gltf_options opt = lg_gltf_default_options();
    opt.normals = (lg_gltf_normals)lg_param_enum(n, "normals");
    opt.crease_deg = lg_param_float(n, "crease_deg");
    opt.scene = lg_param_int(n, "scene");
    opt.camera = lg_param_int(n, "camera");
    opt.animation = lg_param_int(n, "animation");
    opt.warn = log_warning;
    opt.warn_user = n;

    double t0 = lg_now(n);
    lg_scene *scene = NULL;
    uint64_t hash = 0;
    char err[1024];
    int rc = lg_gltf_load(path, &opt, &scene, &hash, err, sizeof err);
    if (rc)
        return lg_error_code(n, rc, "%s", err);
    lg_log(n, LG_LOG_INFO,
           "file '%s': %u meshes, %u instances, %" PRIu64 " triangles, %u lights, %u cameras, "
           "loaded in %.1f ms",
           path, scene->n_meshes, scene->n_instances, scene->features.triangles, scene->n_lights,
           scene->n_cameras, (lg_now(n) - t0) * 1e3);

    /* the content (file and external buffers) is part of the result's identity */
    lg_add_content_key(n, &hash, sizeof hash);
    rc = lg_declare_payload(n, 0, LG_KIND_SCENE, &scene->features, scene, free_scene);
    if (rc)
        return rc; /* the host has freed the scene */
    return lg_set_device(n, LG_DEVICE_CPU);
}

static int gltf_execute(lg_node *n, const lg_frame *frame)
{
    (void)n;
    (void)frame;
    return 0;
}

static const lg_node_type types[] = { {
    .struct_size = sizeof(lg_node_type),
    .name = "gltf",
    .doc = "A glTF 2.0 scene (.gltf, .glb, Draco): meshes, instances, materials, lights, "
           "cameras, medium",
    LG_PARAMS(params),
    LG_OUTPUTS(outputs),
    .prepare = gltf_prepare,
    .execute = gltf_execute,
} };

LG_PLUGIN_DEFINE("scene_gltf", "1.0.0", "glTF 2.0 scenes (tinygltf, Draco)", types)
