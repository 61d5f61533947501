/*
 * Test plugin "testvsinputs": the inputs of the volumetric_screen tests
 * (test_volumetric_screen.c), made in memory so that every value is known.
 *
 *   test_vs_scene -> scene   no geometry; one camera at the origin looking down -Z (up +Y,
 *                            60 degrees vertical field of view, znear 0.1, zfar 20, aspect
 *                            from the image); a medium (density 1, `scattering`,
 *                            `absorption`, `g`); `lights` directional lights: light 0
 *                            travels along `direction`, light k > 0 along direction +
 *                            0.25 (cos 2.4k, sin 2.4k, 0) (normalised); colour of light k
 *                            (1, 1 - k/64, 1 - k/128), intensity `intensity`. only = k
 *                            keeps light k alone (-1: all). type = point or spot: light
 *                            k at `position` + 0.25 (cos 2.4k, sin 2.4k, 0) instead, with
 *                            `range`, a spot's axis `direction` (light k's, as above) and
 *                            cone angles `inner_cone`, `outer_cone` (degrees). field =
 *                            true: the medium gets a density field (height fog over the
 *                            whole space: heterogeneous).
 *   test_vs_base  -> image   rgba32f `color`, alpha 1, with a depth plane: `depth`
 *                            everywhere except the box [box_x0, box_x1) x [box_y0, box_y1)
 *                            (pixels) at `box_depth`; depth_plane = false: no depth plane.
 *                            nan_pixels = N: the first N pixels (row-major) get a NaN red;
 *                            inf_pixels = M: the next M get +Inf green and -Inf blue (two
 *                            channels, one pixel): N + M non-finite pixels in all.
 */
#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "lightgraph/lightgraph.h"
#include "lightgraph/scene.h"
#include "lightgraph/vecmath.h"

#include "common/testscene.h"

#define VS_TEST_MAX_LIGHTS 40

static int tv_scene_prepare(lg_node *n)
{
    int64_t count = lg_param_int(n, "lights"), only = lg_param_int(n, "only");
    if (only >= count)
        return lg_error(n, "only = %lld but there are %lld lights", (long long)only,
                        (long long)count);
    lg_ts_builder *b = lg_ts_begin("test_vs_scene");
    if (!b)
        return lg_error_code(n, LG_ERR_NOMEM, "out of memory");
    lg_ts_camera(b, "test", lg_v3(0, 0, 0), lg_v3(0, 0, -1), lg_v3(0, 1, 0),
                 (float)(60.0 * LG_PI / 180.0), 0.1f, 20.0f);
    const lg_value *dir = lg_param(n, "direction"), *pos = lg_param(n, "position");
    int type = lg_param_enum(n, "type");
    for (int64_t k = 0; k < count; k++) {
        if (only >= 0 && k != only)
            continue;
        double d[3] = { dir->v[0], dir->v[1], dir->v[2] };
        if (k > 0) {
            d[0] += 0.25 * cos(2.4 * (double)k);
            d[1] += 0.25 * sin(2.4 * (double)k);
        }
        double len = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
        float u[3];
        for (int i = 0; i < 3; i++)
            u[i] = len > 0 ? (float)(d[i] / len) : 0.0f;
        lg_light *l =
            lg_ts_dir_light(b, "test", lg_v3(u[0], u[1], u[2]),
                            lg_v3(1.0f, 1.0f - (float)k / 64.0f, 1.0f - (float)k / 128.0f),
                            (float)lg_param_float(n, "intensity"));
        if (type != 0) {
            l->type = type == 1 ? LG_LIGHT_POINT : LG_LIGHT_SPOT;
            double o[3] = { 0, 0, 0 };
            if (k > 0) {
                o[0] = 0.25 * cos(2.4 * (double)k);
                o[1] = 0.25 * sin(2.4 * (double)k);
            }
            for (int i = 0; i < 3; i++)
                l->position[i] = (float)(pos->v[i] + o[i]);
            l->range = (float)lg_param_float(n, "range");
            l->inner_cone = (float)(lg_param_float(n, "inner_cone") * LG_PI / 180.0);
            l->outer_cone = (float)(lg_param_float(n, "outer_cone") * LG_PI / 180.0);
        }
    }
    float sca = (float)lg_param_float(n, "scattering");
    float ab = (float)lg_param_float(n, "absorption");
    lg_ts_medium(b, 1.0f, lg_v3(sca, sca, sca), lg_v3(ab, ab, ab), (float)lg_param_float(n, "g"));
    if (!lg_param_bool(n, "field"))
        return lg_ts_publish(n, 0, b);
    /* height fog everywhere: the scene's medium made heterogeneous (the field is static,
     * it outlives every scene) */
    static const lg_density_field fog = {
        .kind = LG_FIELD_UNIFORM,
        .height_falloff = 0.5f,
        .bounds_min = { -FLT_MAX, -FLT_MAX, -FLT_MAX },
        .bounds_max = { FLT_MAX, FLT_MAX, FLT_MAX },
    };
    lg_scene *s = lg_ts_finish(b);
    if (!s)
        return lg_error_code(n, LG_ERR_NOMEM, "out of memory building the test scene");
    s->medium.field = &fog;
    lg_scene_compute_features(s);
    return lg_declare_payload(n, 0, LG_KIND_SCENE, &s->features, s, lg_ts_free);
}

static int tv_nothing(lg_node *n, const lg_frame *frame)
{
    (void)n;
    (void)frame;
    return 0;
}

static int tv_base_prepare(lg_node *n)
{
    lg_image_desc d = { .format = LG_FORMAT_RGBA32F };
    lg_output_size(n, "width", "height", &d.width, &d.height);
    if (lg_param_bool(n, "depth_plane"))
        d.flags = LG_IMAGE_DEPTH;
    int rc = lg_declare_image(n, 0, &d);
    return rc ? rc : lg_set_device(n, LG_DEVICE_CPU);
}

static int tv_base_execute(lg_node *n, const lg_frame *frame)
{
    (void)frame;
    lg_resource_info info;
    int rc = lg_describe(lg_output(n, 0), &info, n);
    lg_cpu_view v;
    if (rc || (rc = lg_map_cpu(n, lg_output(n, 0), LG_WRITE, &v)))
        return rc;
    const lg_value *col = lg_param(n, "color");
    float depth = (float)lg_param_float(n, "depth"), box = (float)lg_param_float(n, "box_depth");
    int64_t x0 = lg_param_int(n, "box_x0"), x1 = lg_param_int(n, "box_x1");
    int64_t y0 = lg_param_int(n, "box_y0"), y1 = lg_param_int(n, "box_y1");
    int64_t n_nan = lg_param_int(n, "nan_pixels"), n_inf = lg_param_int(n, "inf_pixels");
    float *px = v.pixels;
    for (uint32_t y = 0; y < info.image.height; y++)
        for (uint32_t x = 0; x < info.image.width; x++) {
            size_t i = (size_t)y * info.image.width + x;
            for (int c = 0; c < 3; c++)
                px[4 * i + c] = (float)col->v[c];
            px[4 * i + 3] = 1.0f;
            if ((int64_t)i < n_nan)
                px[4 * i] = NAN;
            else if ((int64_t)i < n_nan + n_inf)
                px[4 * i + 1] = INFINITY, px[4 * i + 2] = -INFINITY;
            if (v.depth)
                v.depth[i] = x >= x0 && x < x1 && y >= y0 && y < y1 ? box : depth;
        }
    return 0;
}

static const char *const tv_light_types[] = { "directional", "point", "spot", NULL };

static const lg_param_desc tv_scene_params[] = {
    { .key = "lights",
      .type = LG_PARAM_INT,
      .def.i = 1,
      .min = 0,
      .max = VS_TEST_MAX_LIGHTS,
      .doc = "lights" },
    { .key = "only",
      .type = LG_PARAM_INT,
      .def.i = -1,
      .min = -1,
      .max = VS_TEST_MAX_LIGHTS - 1,
      .doc = "keep light k alone; -1 all" },
    { .key = "direction",
      .type = LG_PARAM_VEC3,
      .def.v = { 0, 0, 1 },
      .min = -1e3,
      .max = 1e3,
      .doc = "the direction light 0 travels" },
    { .key = "type",
      .type = LG_PARAM_ENUM,
      .def.e = 0,
      .enum_values = tv_light_types,
      .doc = "every light's type" },
    { .key = "position",
      .type = LG_PARAM_VEC3,
      .def.v = { 0, 0, -5 },
      .min = -1e3,
      .max = 1e3,
      .doc = "point, spot: light 0's position" },
    { .key = "range",
      .type = LG_PARAM_FLOAT,
      .def.f = 0,
      .min = 0,
      .max = 1e6,
      .doc = "point, spot: the range (0 infinite)" },
    { .key = "inner_cone",
      .type = LG_PARAM_FLOAT,
      .def.f = 10,
      .min = 0,
      .max = 90,
      .doc = "spot: degrees" },
    { .key = "outer_cone",
      .type = LG_PARAM_FLOAT,
      .def.f = 20,
      .min = 0,
      .max = 90,
      .doc = "spot: degrees" },
    { .key = "field",
      .type = LG_PARAM_BOOL,
      .def.b = false,
      .doc = "a heterogeneous medium (height fog)" },
    { .key = "intensity",
      .type = LG_PARAM_FLOAT,
      .def.f = 10,
      .min = 0,
      .max = 1e6,
      .doc = "every light's intensity" },
    { .key = "scattering",
      .type = LG_PARAM_FLOAT,
      .def.f = 0.1,
      .min = 0,
      .max = 1e3,
      .doc = "sigma_s, 1 / scene unit" },
    { .key = "absorption",
      .type = LG_PARAM_FLOAT,
      .def.f = 0,
      .min = 0,
      .max = 1e3,
      .doc = "sigma_a, 1 / scene unit" },
    { .key = "g",
      .type = LG_PARAM_FLOAT,
      .def.f = 0.4,
      .min = -1,
      .max = 1,
      .doc = "Henyey-Greenstein anisotropy" },
};
static const lg_param_desc tv_base_params[] = {
    { .key = "width",
      .type = LG_PARAM_INT,
      .def.i = 0,
      .min = 0,
      .max = 16384,
      .doc = "pixels; 0 = the render width",
      .role = LG_ROLE_IMAGE_WIDTH },
    { .key = "height",
      .type = LG_PARAM_INT,
      .def.i = 0,
      .min = 0,
      .max = 16384,
      .doc = "pixels; 0 = the render height",
      .role = LG_ROLE_IMAGE_HEIGHT },
    { .key = "color",
      .type = LG_PARAM_COLOR,
      .def.v = { 0.2, 0.3, 0.4 },
      .min = 0,
      .max = 1e6,
      .doc = "every pixel's colour" },
    { .key = "depth",
      .type = LG_PARAM_FLOAT,
      .def.f = 1,
      .min = 0,
      .max = 1,
      .doc = "window depth outside the box (1 = sky)" },
    { .key = "box_depth",
      .type = LG_PARAM_FLOAT,
      .def.f = 0.5,
      .min = 0,
      .max = 1,
      .doc = "window depth inside the box" },
    { .key = "box_x0", .type = LG_PARAM_INT, .def.i = 0, .min = 0, .max = 16384, .doc = "" },
    { .key = "box_y0", .type = LG_PARAM_INT, .def.i = 0, .min = 0, .max = 16384, .doc = "" },
    { .key = "box_x1", .type = LG_PARAM_INT, .def.i = 0, .min = 0, .max = 16384, .doc = "" },
    { .key = "box_y1", .type = LG_PARAM_INT, .def.i = 0, .min = 0, .max = 16384, .doc = "" },
    { .key = "depth_plane",
      .type = LG_PARAM_BOOL,
      .def.b = true,
      .doc = "false: an image without a depth plane" },
    { .key = "nan_pixels",
      .type = LG_PARAM_INT,
      .def.i = 0,
      .min = 0,
      .max = 1 << 28,
      .doc = "the first N pixels get a NaN red" },
    { .key = "inf_pixels",
      .type = LG_PARAM_INT,
      .def.i = 0,
      .min = 0,
      .max = 1 << 28,
      .doc = "the next M pixels get +Inf green and -Inf blue" },
};
static const lg_port_desc tv_scene_out[] = { { .name = "scene", .kind = LG_KIND_SCENE } };
static const lg_port_desc tv_image_out[] = { { .name = "out", .kind = LG_KIND_IMAGE } };

static const lg_node_type tv_types[] = {
    { .struct_size = sizeof(lg_node_type),
      .name = "test_vs_scene",
      .doc = "a camera, lights and a medium (test)",
      LG_PARAMS(tv_scene_params),
      LG_OUTPUTS(tv_scene_out),
      .prepare = tv_scene_prepare,
      .execute = tv_nothing },
    { .struct_size = sizeof(lg_node_type),
      .name = "test_vs_base",
      .doc = "a lit image with a depth plane of known values (test)",
      LG_PARAMS(tv_base_params),
      LG_OUTPUTS(tv_image_out),
      .prepare = tv_base_prepare,
      .execute = tv_base_execute },
};

LG_PLUGIN_DEFINE("testvsinputs", "1.0.0", "inputs of the volumetric_screen tests", tv_types)
