/* Test plugin "testscene": a scene description whose features are its parameters, so the
 * planner's gating can be tested before real scenes exist (and independently of them). */
#include <stdlib.h>
#include <string.h>

#include "lightgraph/lightgraph.h"

static const lg_param_desc scene_params[] = {
    { .key = "triangles",
      .type = LG_PARAM_INT,
      .def.i = 12,
      .min = 0,
      .max = 1e12,
      .doc = "triangle count the scene claims" },
    { .key = "dir_lights",
      .type = LG_PARAM_INT,
      .def.i = 1,
      .min = 0,
      .max = 1024,
      .doc = "directional lights" },
    { .key = "point_lights",
      .type = LG_PARAM_INT,
      .def.i = 0,
      .min = 0,
      .max = 1024,
      .doc = "point lights" },
    { .key = "medium_density",
      .type = LG_PARAM_FLOAT,
      .def.f = 0,
      .min = 0,
      .max = 1e6,
      .doc = "participating medium density (0: no medium)" },
    { .key = "probe", .type = LG_PARAM_BOOL, .def.b = false, .doc = "a light probe is present" },
    { .key = "specular",
      .type = LG_PARAM_BOOL,
      .def.b = false,
      .doc = "a material has a specular term" },
};
static const lg_port_desc scene_out[] = {
    { .name = "scene", .kind = LG_KIND_SCENE, .doc = "the described scene" }
};

static int scene_prepare(lg_node *n)
{
    lg_scene_features f;
    memset(&f, 0, sizeof f);
    f.triangles = (uint64_t)lg_param_int(n, "triangles");
    f.vertices = f.triangles * 3;
    f.dir_lights = (uint32_t)lg_param_int(n, "dir_lights");
    f.point_lights = (uint32_t)lg_param_int(n, "point_lights");
    f.medium_density = (float)lg_param_float(n, "medium_density");
    f.medium = f.medium_density > 0;
    f.probe = lg_param_bool(n, "probe");
    f.specular = lg_param_bool(n, "specular");
    return lg_declare_payload(n, 0, LG_KIND_SCENE, &f, NULL, NULL);
}

static int scene_execute(lg_node *n, const lg_frame *frame)
{
    (void)n;
    (void)frame;
    return 0;
}

static const lg_node_type types[] = { {
    .struct_size = sizeof(lg_node_type),
    .name = "test_scene",
    .doc = "A scene description for tests: its features are its parameters",
    LG_PARAMS(scene_params),
    LG_OUTPUTS(scene_out),
    .prepare = scene_prepare,
    .execute = scene_execute,
} };

LG_PLUGIN_DEFINE("testscene", "1.0.0", "Scene descriptions for planner tests", types)
