/* Test plugin "testprobe": looks into a probe resource so that tests/plugins/probe can check
 * what the `probe` node published, through the SDK's own accessors (lg_probe_get,
 * lg_probe_lookup), as a consumer would.
 *
 *   probe_tap { probe, dirs, mode }  -> out
 *     mode = lookup: out has the size of `dirs`; pixel p is lg_probe_lookup(nearest) of the
 *                    world direction dirs[p].rgb (through the probe's rotation)
 *     mode = bilinear: the same, bilinear
 *     mode = raw:    level 0's texels, W x (H * faces) (a cube's faces one under the other)
 *     mode = info:   8 x 1: (sum of the solid_angle part in double, layout, width, height),
 *                    (info.scale, levels, faces, has solid angles), rotation[0..2],
 *                    rotation[3..5], rotation[6..8], (struct_size, filter, 0, 0), 0, 0
 *   test_needs_probe { scene } -> out: a 1x1 image of 1; needs LG_NEEDS_PROBE (gated: 0)
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "lightgraph/lightgraph.h"

static const char *const tap_modes[] = { "lookup", "bilinear", "raw", "info", NULL };
enum { TAP_LOOKUP, TAP_BILINEAR, TAP_RAW, TAP_INFO };

static int tap_prepare(lg_node *n)
{
    int mode = lg_param_enum(n, "mode");
    lg_resource_info pi;
    const lg_resource *pr = lg_input(n, 0);
    if (!pr || lg_describe(pr, &pi, n))
        return lg_error(n, "no probe");
    const lg_resource *rad = lg_part(n, pr, "radiance");
    lg_resource_info ri;
    if (!rad || lg_describe(rad, &ri, n))
        return lg_error(n, "no radiance part");
    lg_image_desc d = { .format = LG_FORMAT_RGBA32F };
    if (mode == TAP_LOOKUP || mode == TAP_BILINEAR) {
        lg_resource_info di;
        const lg_resource *dirs = lg_input(n, 1);
        if (!dirs || lg_describe(dirs, &di, n) || di.kind != LG_KIND_IMAGE)
            return lg_error(n, "mode lookup needs the `dirs` image");
        d.width = di.image.width;
        d.height = di.image.height;
    } else if (mode == TAP_RAW) {
        d.width = ri.image.width;
        d.height = ri.image.height * lg_image_faces(&ri.image);
    } else {
        d.width = 8;
        d.height = 1;
    }
    int rc = lg_declare_image(n, 0, &d);
    return rc ? rc : lg_set_device(n, LG_DEVICE_CPU);
}

static int tap_execute(lg_node *n, const lg_frame *frame)
{
    (void)frame;
    int mode = lg_param_enum(n, "mode");
    lg_probe pv;
    const lg_probe *p = lg_probe_get(n, lg_input(n, 0), &pv);
    if (!p)
        return lg_error(n, "lg_probe_get failed");
    lg_cpu_view rv, ov;
    int rc;
    if ((rc = lg_map_cpu(n, p->radiance, LG_READ, &rv)) ||
        (rc = lg_map_cpu(n, lg_output(n, 0), LG_WRITE, &ov)))
        return rc;
    const lg_image_desc *d = &p->radiance_desc;
    float *o = ov.pixels;
    if (mode == TAP_LOOKUP || mode == TAP_BILINEAR) {
        lg_resource_info di;
        lg_cpu_view dv;
        if ((rc = lg_describe(lg_input(n, 1), &di, n)) ||
            (rc = lg_map_cpu(n, lg_input(n, 1), LG_READ, &dv)))
            return rc;
        lg_probe_image img = lg_probe_image_at(p->info.layout, d, rv.pixels, 0, p->info.rotation);
        const float *dp = dv.pixels;
        size_t cnt = (size_t)di.image.width * di.image.height;
        for (size_t i = 0; i < cnt; i++)
            lg_probe_lookup(&img, lg_v3(dp[4 * i], dp[4 * i + 1], dp[4 * i + 2]),
                            mode == TAP_LOOKUP ? LG_PROBE_NEAREST : LG_PROBE_BILINEAR, o + 4 * i);
    } else if (mode == TAP_RAW) {
        memcpy(o, rv.pixels, (size_t)d->width * d->height * lg_image_faces(d) * 16);
    } else {
        memset(o, 0, 8 * 16);
        double sum = 0;
        if (p->solid_angle) {
            lg_cpu_view sv;
            if ((rc = lg_map_cpu(n, p->solid_angle, LG_READ, &sv)))
                return rc;
            const float *s = sv.pixels;
            size_t cnt = (size_t)d->width * d->height * lg_image_faces(d);
            for (size_t i = 0; i < cnt; i++)
                sum += s[i];
        }
        o[0] = (float)sum;
        o[1] = (float)p->info.layout;
        o[2] = (float)d->width;
        o[3] = (float)d->height;
        o[4] = p->info.scale;
        o[5] = (float)lg_image_levels(d);
        o[6] = (float)lg_image_faces(d);
        o[7] = p->solid_angle ? 1.0f : 0.0f;
        for (int k = 0; k < 9; k++)
            o[8 + 4 * (k / 3) + k % 3] = p->info.rotation[k];
        o[20] = (float)p->info.struct_size;
        o[21] = (float)p->info.filter;
    }
    return 0;
}

static int needs_prepare(lg_node *n)
{
    lg_image_desc d = { .width = 1, .height = 1, .format = LG_FORMAT_RGBA32F };
    int rc = lg_declare_image(n, 0, &d);
    return rc ? rc : lg_set_device(n, LG_DEVICE_CPU);
}

static int needs_execute(lg_node *n, const lg_frame *frame)
{
    (void)frame;
    lg_cpu_view v;
    int rc = lg_map_cpu(n, lg_output(n, 0), LG_WRITE, &v);
    if (rc)
        return rc;
    float *p = v.pixels;
    p[0] = p[1] = p[2] = p[3] = 1.0f;
    return 0;
}

static const lg_param_desc tap_params[] = {
    { .key = "mode", .type = LG_PARAM_ENUM, .enum_values = tap_modes, .doc = "what to show" },
};
static const lg_port_desc tap_in[] = {
    { .name = "probe", .kind = LG_KIND_PROBE },
    { .name = "dirs", .kind = LG_KIND_IMAGE, .optional = true, .doc = "rgb: world directions" },
};
static const lg_port_desc img_out[] = { { .name = "out", .kind = LG_KIND_IMAGE } };
static const lg_port_desc scene_in[] = { { .name = "scene", .kind = LG_KIND_SCENE } };

static const lg_node_type types[] = {
    {
        .struct_size = sizeof(lg_node_type),
        .name = "probe_tap",
        .doc = "looks into a probe (lookups, raw texels, info)",
        LG_PARAMS(tap_params),
        LG_INPUTS(tap_in),
        LG_OUTPUTS(img_out),
        .prepare = tap_prepare,
        .execute = tap_execute,
    },
    {
        .struct_size = sizeof(lg_node_type),
        .name = "test_needs_probe",
        .doc = "1 when kept; needs a probe in the scene",
        LG_INPUTS(scene_in),
        LG_OUTPUTS(img_out),
        .needs = LG_NEEDS_PROBE,
        .prepare = needs_prepare,
        .execute = needs_execute,
    },
};

LG_PLUGIN_DEFINE("testprobe", "1.0.0", "Looks into probe resources (tests)", types)
