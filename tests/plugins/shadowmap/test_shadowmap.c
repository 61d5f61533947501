/*
 * The shadowmap node through the host: `test_shadowmap CASE`. Scenes come from the test
 * plugin `shadowprobe` (this folder): `test_shadow_scene` is a floor quad (y = 0, facing
 * +Y, 8 x 8 unless a case says otherwise) and a unit box floating at (0, 1.5, 0); lights
 * come from the scene_tools `light` node; `test_shadow_probe` evaluates Shadow_L(p) on the
 * CPU from the node's payload and atlas (eq. 4 with the bias rules of
 * plugins/shadowmap/README.md), per light per point, into probe.exr (layout in
 * shadowprobe.c). Expected values come from geometry: a point is shadowed by light L when
 * the ray from it towards the light (-direction) hits the box.
 *
 *   basic      one light straight down: floor points under the box 0, beside it 1, the
 *              box's top 1, a point in the air under the box 0, above it 1, with and
 *              without normals; payload fields (one light, resolution, atlas size, depth-
 *              only atlas, default bias, texel size and depth range of the fit); the fit
 *              turns a light's view to the smallest box: a floor seen at azimuth 45 gets
 *              the texel it gets at azimuth 0
 *   cull       the stored depth under the box is the box's bottom (cull = front), its top
 *              (back, none, or a double-sided box with front); a mirroring instance culls
 *              like a plain one; the floor (facing the light) is absent with front and
 *              present with back or when double-sided
 *   lights2, lights8, lights32
 *              N lights at different azimuths and elevations: the tiles follow the grid
 *              (ceil(sqrt N) columns, row-major, top-left first) inside the atlas; every
 *              light's shadow lies where its own direction puts it: for a 7 x 7 grid of
 *              floor points and each light's shadow centre, Shadow_L matches the ray-box
 *              test for every light (points within 3 texels of a shadow's edge skipped)
 *   layout32   32 lights at the default resolution 1024 make a 6144 x 6144 atlas
 *              (--explain and the payload), and each light's shadow centre is dark
 *   bias       no acne: a floor drawn into the map (double-sided, or single-sided with
 *              cull = back) lit from 0, 30, 60, 75 and 85 degrees off vertical, at
 *              resolutions 256 and 1024: every floor point is lit with the default bias;
 *              with all three biases 0 the slanted lights do self-shadow it
 *   curved     the same on a convex body: centroids of a UV sphere's triangles (drawn
 *              double-sided, or single-sided with cull = back or front) with their
 *              interpolated normals, lit from 0, 45 and 70 degrees: none that faces a
 *              light (N.L > 0.2) is shadowed with the default bias; all biases 0 shadow
 *              many
 *   gating     without a light the node is gated and its plugin not loaded, and the probe
 *              gets NULL from lg_shadowmap_get; a point light before a directional one gets
 *              its cube first (six records, then the directional light's; before ABI 3.2
 *              it was skipped)
 *   frustum    fit = frustum with a camera looking down at the box on a 40 x 40 floor: a
 *              finer texel than fit = bounds, and the same shadows where the camera looks;
 *              a wider aspect gives a coarser map; a camera that sees none of the scene
 *              falls back to the bounds
 *   atlas      `output shadow.atlas "sm.exr"`: grey (r = g = b) depth in [0, 1], alpha 1,
 *              1 where nothing is drawn, the probe's stored depth at a point's texel; a
 *              box towards -Z under a light from straight above lands in the tile's top
 *              half (the tile is the light's view, upright, -Z up); a PNG is written too
 *   errors     an atlas past 2^28 texels, a light without a direction, a camera that does
 *              not exist (fit = frustum) and a resolution out of range stop the render
 *              with a message naming the cause
 *   spot       (ABI 3.2) a spot light's one perspective map: 625 floor points against the
 *              ray test toward its position (2 texels of margin), the shadow's edge within
 *              a texel of x = 1 (the box's top seen from the light)
 *   point      a point light's cube: a box 1 from the light along each face's axis in turn,
 *              600 points around the light against the segment test; the light inside the
 *              box shadows every point around; range 0 fits the far plane to the scene,
 *              range 1.5 to the range
 *   pcf        pcf_radius 0, 1, 2 through the SDK's lookup (the probe's sdk = true): the
 *              visibility across the box's edge is a monotone ramp of 2 r texels in steps
 *              of 1 / (2 r + 1)
 *
 * Every render also passes the host's GL state check (debug builds check after each node
 * that the bindings were restored; a violation fails the render).
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "lightgraph/vecmath.h"
#include "lightgraph/test.h"

#ifndef SM_PROBE_DIR
#define SM_PROBE_DIR ""
#endif

#define DEG (LG_PI / 180.0)
#define MAX_LIGHTS 40
#define MAX_POINTS 1200

/* every case needs GL and the probe plugin */
static void setup_case(lg_test *t)
{
    lg_test_require_backend(t, "gl");
    lg_test_use_plugins(t, SM_PROBE_DIR);
}

/* ---- a graph: the scene, its lights, the shadow map and the probe ---------------------------- */

typedef struct light_spec {
    bool point;
    lg_vec3 v; /* direction (travel) or position */
    /* since ABI 3.2: a spot light at v along `dir` (outer_deg > 0), and a range */
    lg_vec3 dir;
    float outer_deg, range;
} light_spec;

typedef struct setup {
    const char *scene;  /* test_shadow_scene parameters */
    const char *shadow; /* shadowmap parameters ("" for the defaults) */
    light_spec lights[MAX_LIGHTS];
    int n_lights;
    lg_vec3 pts[MAX_POINTS], nrm[MAX_POINTS]; /* normals: the floor's (0, 1, 0) unless set */
    int n_pts;
    bool normals;         /* pass the normals to the probe */
    bool no_shadow_input; /* leave the probe's `shadows` unconnected */
    bool sdk;             /* the probe tests every light with lg_shadowmap_visibility */
    const char *extra;    /* more graph lines (outputs) */
} setup;

static lg_vec3 dir_from(double off_vertical_deg, double azimuth_deg)
{
    double t = off_vertical_deg * DEG, a = azimuth_deg * DEG;
    return lg_v3((float)(sin(t) * sin(a)), (float)-cos(t), (float)(sin(t) * cos(a)));
}

static void add_light(setup *s, lg_vec3 d)
{
    s->lights[s->n_lights].point = false;
    s->lights[s->n_lights++].v = d;
}

static void add_point(setup *s, float x, float y, float z)
{
    s->nrm[s->n_pts] = lg_v3(0, 1, 0);
    s->pts[s->n_pts++] = lg_v3(x, y, z);
}

/* Writes the graph to g.lgraph; returns its text (malloc'd). */
static char *graph_text(const setup *s)
{
    size_t cap = 256 * 1024;
    char *g = malloc(cap);
    size_t k = 0;
#define ADD(...) (k += (size_t)snprintf(g + k, cap - k, __VA_ARGS__))
    ADD("lightgraph 1\ns = test_shadow_scene { %s }\n", s->scene ? s->scene : "");
    const char *last = "s";
    char names[MAX_LIGHTS][16];
    for (int i = 0; i < s->n_lights; i++) {
        snprintf(names[i], sizeof names[i], "l%d", i);
        const light_spec *l = &s->lights[i];
        if (l->point && l->outer_deg > 0)
            ADD("%s = light { scene = %s, mode = %s, type = spot, position = [%.9g, %.9g, "
                "%.9g], direction = [%.9g, %.9g, %.9g], inner_cone_deg = %.9g, "
                "outer_cone_deg = %.9g, range = %.9g }\n",
                names[i], last, i == 0 ? "replace" : "add", (double)l->v.x, (double)l->v.y,
                (double)l->v.z, (double)l->dir.x, (double)l->dir.y, (double)l->dir.z,
                0.5 * l->outer_deg, (double)l->outer_deg, (double)l->range);
        else if (l->point)
            ADD("%s = light { scene = %s, mode = %s, type = point, position = [%.9g, %.9g, "
                "%.9g], range = %.9g }\n",
                names[i], last, i == 0 ? "replace" : "add", (double)l->v.x, (double)l->v.y,
                (double)l->v.z, (double)l->range);
        else
            ADD("%s = light { scene = %s, mode = %s, direction = [%.9g, %.9g, %.9g] }\n", names[i],
                last, i == 0 ? "replace" : "add", (double)l->v.x, (double)l->v.y, (double)l->v.z);
        last = names[i];
    }
    ADD("shadow = shadowmap { scene = %s%s%s }\n", last, s->shadow && *s->shadow ? ", " : "",
        s->shadow ? s->shadow : "");
    ADD("probe = test_shadow_probe { scene = %s%s, points = \"", last,
        s->no_shadow_input ? "" : ", shadows = shadow");
    for (int i = 0; i < s->n_pts; i++)
        ADD("%s%.9g,%.9g,%.9g", i ? ";" : "", (double)s->pts[i].x, (double)s->pts[i].y,
            (double)s->pts[i].z);
    ADD("\"");
    if (s->normals) {
        ADD(", normals = \"");
        for (int i = 0; i < s->n_pts; i++)
            ADD("%s%.9g,%.9g,%.9g", i ? ";" : "", (double)s->nrm[i].x, (double)s->nrm[i].y,
                (double)s->nrm[i].z);
        ADD("\"");
    }
    ADD("%s }\noutput probe \"probe.exr\"\n%s", s->sdk ? ", sdk = true" : "",
        s->extra ? s->extra : "");
#undef ADD
    return g;
}

/* Renders; reads probe.exr into *img. *out gets what the program printed (may be NULL). */
static bool run(lg_test *t, const setup *s, const char *const *args, lg_image *img, char **out)
{
    char *g = graph_text(s);
    lg_test_write_text(t, "g.lgraph", g);
    free(g);
    char *text = NULL;
    int rc = lg_test_render(t, "g.lgraph", args, &text);
    LG_TEST_CHECK(t, rc == 0, "render failed (exit %d)", rc);
    if (out)
        *out = text;
    else
        free(text);
    if (rc)
        return false;
    unsigned bits = 0;
    if (!lg_test_read(t, "probe.exr", img, &bits))
        return false;
    LG_TEST_CHECK(t, bits == 32, "probe.exr has %u bits per channel, want 32", bits);
    LG_TEST_CHECK(t, img->height == (uint32_t)s->n_lights + 1, "probe height %u, want %d",
                  img->height, s->n_lights + 1);
    return bits == 32 && img->height == (uint32_t)s->n_lights + 1;
}

static const float *px(const lg_image *img, uint32_t x, uint32_t y)
{
    static const float none[4] = { NAN, NAN, NAN, NAN };
    return x < img->width && y < img->height ? img->pixels + ((size_t)y * img->width + x) * 4
                                             : none;
}

/* Probe accessors: light l (scene index), point j. */
static float S(const lg_image *p, int l, int j)
{
    return px(p, (uint32_t)j, (uint32_t)l)[0];
}
static float Z(const lg_image *p, int l, int j)
{
    return px(p, (uint32_t)j, (uint32_t)l)[1];
}
static float D(const lg_image *p, int l, int j)
{
    return px(p, (uint32_t)j, (uint32_t)l)[2];
}
static float HAS(const lg_image *p, int l, int j)
{
    return px(p, (uint32_t)j, (uint32_t)l)[3];
}
static const float *TILE(const lg_image *p, const setup *s, int l)
{
    return px(p, (uint32_t)s->n_pts, (uint32_t)l);
}
static const float *INFO(const lg_image *p, const setup *s, int col)
{
    return px(p, (uint32_t)col, (uint32_t)s->n_lights);
}

/* ---- the geometric reference ----------------------------------------------------------------- */

/* Does the piece p + t d, 0 <= t <= tmax, of a line cross the axis-aligned box c +- h (h
 * grown by m, m may be < 0)? The slab test. */
static bool line_hits_box(lg_vec3 p, lg_vec3 dv, float tmax, lg_vec3 c, lg_vec3 h, float m)
{
    float o[3] = { p.x - c.x, p.y - c.y, p.z - c.z }, d[3] = { dv.x, dv.y, dv.z };
    float hh[3] = { h.x + m, h.y + m, h.z + m };
    float t0 = 0.0f, t1 = tmax;
    for (int k = 0; k < 3; k++) {
        if (fabsf(d[k]) < 1e-9f) {
            if (fabsf(o[k]) > hh[k])
                return false;
            continue;
        }
        float a = (-hh[k] - o[k]) / d[k], b = (hh[k] - o[k]) / d[k];
        if (a > b) {
            float x = a;
            a = b;
            b = x;
        }
        t0 = fmaxf(t0, a);
        t1 = fminf(t1, b);
        if (t0 > t1)
            return false;
    }
    return true;
}

/* Does the ray from p along u hit the box? */
static bool ray_hits_box(lg_vec3 p, lg_vec3 u, lg_vec3 c, lg_vec3 h, float m)
{
    return line_hits_box(p, u, INFINITY, c, h, m);
}

/* Expected Shadow_L(p) for the default box (centre (0, 1.5, 0), half-edge 0.5): 1, 0, or -1
 * when p is within `margin` of the shadow's edge. */
static int expected(lg_vec3 p, lg_vec3 dir, float margin)
{
    lg_vec3 c = lg_v3(0, 1.5f, 0), h = lg_v3(0.5f, 0.5f, 0.5f), u = lg_v3_scale(dir, -1.0f);
    bool in = ray_hits_box(p, u, c, h, margin), core = ray_hits_box(p, u, c, h, -margin);
    return core ? 0 : !in ? 1 : -1;
}

/* Does the segment from p to q cross the box? */
static bool seg_hits_box(lg_vec3 p, lg_vec3 q, lg_vec3 c, lg_vec3 h, float m)
{
    return line_hits_box(p, lg_v3(q.x - p.x, q.y - p.y, q.z - p.z), 1.0f, c, h, m);
}

/* Expected Shadow of a light at q for p and the box c +- h: 1, 0, or -1 within m of the
 * shadow's edge (m in world units at the box). */
static int expected_at(lg_vec3 p, lg_vec3 q, lg_vec3 c, lg_vec3 h, float m)
{
    bool in = seg_hits_box(p, q, c, h, m), core = seg_hits_box(p, q, c, h, -m);
    return core ? 0 : !in ? 1 : -1;
}

static bool contains_line(const char *text, const char *prefix, const char *word)
{
    for (const char *l = text; l && *l;) {
        const char *e = strchr(l, '\n');
        size_t len = e ? (size_t)(e - l) : strlen(l);
        if (len >= strlen(prefix) && strncmp(l, prefix, strlen(prefix)) == 0) {
            char buf[1024];
            snprintf(buf, sizeof buf, "%.*s ", (int)(len < 1000 ? len : 1000), l);
            char w[80];
            snprintf(w, sizeof w, " %s ", word);
            return strstr(buf, w) != NULL;
        }
        l = e ? e + 1 : NULL;
    }
    return false;
}

/* The explain table's state column ("kept", "gated", "culled") of node `name`. */
static const char *state_of(const char *text, const char *name)
{
    static char state[16];
    state[0] = 0;
    for (const char *l = text; l && *l;) {
        const char *e = strchr(l, '\n');
        char node[64], type[64], st[16];
        if (sscanf(l, "%63s %63s %15s", node, type, st) == 3 && strcmp(node, name) == 0) {
            snprintf(state, sizeof state, "%s", st);
            break;
        }
        l = e ? e + 1 : NULL;
    }
    return state;
}

/* ---- cases ----------------------------------------------------------------------------------- */

static void fit_rotation(lg_test *t);

static void case_basic(lg_test *t)
{
    for (int with_normals = 0; with_normals < 2; with_normals++) {
        setup s = { .shadow = "resolution = 256", .normals = with_normals != 0 };
        add_light(&s, lg_v3(0, -1, 0));
        add_point(&s, 0, 0, 0);          /* 0: floor under the box */
        add_point(&s, 3, 0, 3);          /* 1: floor far from it */
        add_point(&s, 0.35f, 0, -0.35f); /* 2: floor under the box, near its edge */
        add_point(&s, 0.65f, 0, 0);      /* 3: floor just beside it */
        add_point(&s, 0, 2, 0);          /* 4: the box's top */
        add_point(&s, -0.3f, 2, 0.2f);   /* 5: the box's top */
        int n_surface = s.n_pts;
        if (!with_normals) {
            add_point(&s, 0, 3, 0);    /* 6: in the air above the box */
            add_point(&s, 0, 0.5f, 0); /* 7: in the air under the box */
        }
        static const float want[8] = { 0, 1, 0, 1, 1, 1, 1, 0 };
        lg_image p = { 0 };
        if (!run(t, &s, NULL, &p, NULL))
            return;
        for (int j = 0; j < s.n_pts; j++) {
            LG_TEST_CHECK(t, S(&p, 0, j) == want[j],
                          "%s normals: point %d (%g, %g, %g): Shadow %g, want %g (z %.7g, D %.7g)",
                          with_normals ? "with" : "without", j, (double)s.pts[j].x,
                          (double)s.pts[j].y, (double)s.pts[j].z, (double)S(&p, 0, j),
                          (double)want[j], (double)Z(&p, 0, j), (double)D(&p, 0, j));
            LG_TEST_CHECK(t,
                          HAS(&p, 0, j) == 1 && Z(&p, 0, j) >= 0 && Z(&p, 0, j) <= 1 &&
                              D(&p, 0, j) >= 0 && D(&p, 0, j) <= 1,
                          "point %d: has %g z %g D %g", j, (double)HAS(&p, 0, j),
                          (double)Z(&p, 0, j), (double)D(&p, 0, j));
        }
        (void)n_surface;
        /* light depth grows away from the light: the floor is deeper than the box's top */
        LG_TEST_CHECK(t, Z(&p, 0, 1) > Z(&p, 0, 4), "floor depth %g not beyond the top's %g",
                      (double)Z(&p, 0, 1), (double)Z(&p, 0, 4));
        const float *i0 = INFO(&p, &s, 0), *i1 = INFO(&p, &s, 1), *i2 = INFO(&p, &s, 2);
        LG_TEST_CHECK(t, i0[0] == 1 && i0[1] == 256 && i0[2] == 256 && i0[3] == 256,
                      "payload: %g lights, resolution %g, atlas %gx%g; want 1, 256, 256x256",
                      (double)i0[0], (double)i0[1], (double)i0[2], (double)i0[3]);
        LG_TEST_CHECK(t, i1[3] == 1, "the payload's atlas is not a depth-only image of its size");
        LG_TEST_CHECK(t, i2[0] == 0, "%g payload lights are not directional lights of the scene",
                      (double)i2[0]);
        LG_TEST_CHECK(t,
                      fabsf(i1[0] - 0.0002f) < 1e-9f && fabsf(i1[1] - 0.0005f) < 1e-9f &&
                          i1[2] == 1.0f,
                      "default bias %g %g %g, want 0.0002 0.0005 1", (double)i1[0], (double)i1[1],
                      (double)i1[2]);
        /* light from +Y: the tile covers the floor's 8 x 8 and a margin of normal_offset
         * + 1 = 2 texels each side; the depth range is the bounds' sphere, 0.1 % wider */
        const float *tl = TILE(&p, &s, 0);
        double texel = 8.0 / 252.0;
        LG_TEST_CHECK(t, tl[0] == 0 && tl[1] == 0, "tile at (%g, %g)", (double)tl[0],
                      (double)tl[1]);
        LG_TEST_CHECK(t, fabs(tl[2] - texel) < 1e-4 * texel, "texel_world %.7g, want %.7g",
                      (double)tl[2], texel);
        double r = 0.5 * sqrt(8.0 * 8.0 * 2 + 2.0 * 2.0), range = 2.002 * r;
        LG_TEST_CHECK(t, fabs(tl[3] - range) < 1e-5 * range, "depth_range %.7g, want %.7g",
                      (double)tl[3], range);
        lg_image_free(&p);
    }
    fit_rotation(t);
}

/* The fit turns each light's view about its axis to the smallest box around the receivers:
 * the floor seen from 30 degrees off vertical at azimuth 45 needs a texel within 10 % of
 * the one at azimuth 0 (where its image is an upright rectangle; 7 % measured); with the
 * view's up left at world +Y it would be sqrt(2) coarser. */
static void fit_rotation(lg_test *t)
{
    setup s = { .scene = "box = false", .shadow = "resolution = 256" };
    add_light(&s, dir_from(30, 0));
    add_light(&s, dir_from(30, 45));
    add_point(&s, 3.9f, 0, 3.9f);
    add_point(&s, -3.9f, 0, 3.9f);
    lg_image p = { 0 };
    if (!run(t, &s, NULL, &p, NULL))
        return;
    float t0 = TILE(&p, &s, 0)[2], t45 = TILE(&p, &s, 1)[2];
    LG_TEST_CHECK(t, t45 < 1.1f * t0, "texel at azimuth 45: %g, at 0: %g", (double)t45, (double)t0);
    for (int l = 0; l < 2; l++)
        for (int j = 0; j < 2; j++)
            LG_TEST_CHECK(t, D(&p, l, j) >= 0 && S(&p, l, j) == 1,
                          "light %d: floor corner %d outside "
                          "the map or shadowed",
                          l, j);
    lg_image_free(&p);
}

/* The stored depth under the box's centre and at a floor point, against the depths of the
 * box's bottom, its top and the floor, for one configuration. */
static void cull_one(lg_test *t, const char *scene, const char *shadow, int want_box, bool floor_in)
{
    setup s = { .scene = scene, .shadow = shadow };
    add_light(&s, lg_v3(0, -1, 0));
    add_point(&s, 0, 1, 0); /* 0: the box's bottom */
    add_point(&s, 0, 2, 0); /* 1: the box's top */
    add_point(&s, 3, 0, 3); /* 2: the floor */
    lg_image p = { 0 };
    if (!run(t, &s, NULL, &p, NULL))
        return;
    float d = D(&p, 0, 0), want = want_box == 0 ? Z(&p, 0, 0) : Z(&p, 0, 1);
    LG_TEST_CHECK(t, fabsf(d - want) < 1e-5f,
                  "{%s} {%s}: depth under the box %.7g, want the %s's "
                  "%.7g",
                  scene, shadow, (double)d, want_box == 0 ? "bottom" : "top", (double)want);
    float fd = D(&p, 0, 2);
    if (floor_in)
        LG_TEST_CHECK(t, fabsf(fd - Z(&p, 0, 2)) < 1e-5f, "{%s} {%s}: floor depth %.7g, want %.7g",
                      scene, shadow, (double)fd, (double)Z(&p, 0, 2));
    else
        LG_TEST_CHECK(t, fd == 1.0f, "{%s} {%s}: floor drawn (depth %.7g), want 1 (culled)", scene,
                      shadow, (double)fd);
    lg_image_free(&p);
}

static void case_cull(lg_test *t)
{
    cull_one(t, "", "resolution = 128", 0, false);
    cull_one(t, "", "resolution = 128, cull = front", 0, false);
    cull_one(t, "box_mirror = true", "resolution = 128", 0, false);
    cull_one(t, "", "resolution = 128, cull = back", 1, true);
    cull_one(t, "box_mirror = true", "resolution = 128, cull = back", 1, true);
    cull_one(t, "", "resolution = 128, cull = none", 1, true);
    cull_one(t, "box_double_sided = true, floor_double_sided = true", "resolution = 128", 1, true);
}

/* N lights at different azimuths and elevations; see the header. */
static void lights_n(lg_test *t, int n, int res)
{
    setup s = { .normals = true };
    char shadow[64];
    snprintf(shadow, sizeof shadow, "resolution = %d", res);
    s.shadow = shadow;
    for (int i = 0; i < n; i++)
        add_light(&s, dir_from(i % 2 ? 30.0 : 42.0, 360.0 * i / n + 10.0));
    /* each light's shadow centre: the box's centre carried along the light to y = 0 */
    for (int i = 0; i < n; i++) {
        lg_vec3 d = s.lights[i].v;
        float k = 1.5f / -d.y;
        add_point(&s, d.x * k, 0, d.z * k);
    }
    for (int a = -3; a <= 3; a++)
        for (int b = -3; b <= 3; b++)
            add_point(&s, (float)a, 0, (float)b);
    lg_image p = { 0 };
    if (!run(t, &s, NULL, &p, NULL))
        return;

    int cols = 1;
    while (cols * cols < n)
        cols++;
    int rows = (n + cols - 1) / cols;
    const float *i0 = INFO(&p, &s, 0);
    LG_TEST_CHECK(t, i0[0] == n && i0[1] == res && i0[2] == cols * res && i0[3] == rows * res,
                  "payload: %g lights at %g, atlas %gx%g; want %d at %d, %dx%d", (double)i0[0],
                  (double)i0[1], (double)i0[2], (double)i0[3], n, res, cols * res, rows * res);
    LG_TEST_CHECK(t, INFO(&p, &s, 1)[3] == 1, "the atlas is not a depth-only image of its size");
    LG_TEST_CHECK(t, INFO(&p, &s, 2)[0] == 0,
                  "the lights list names lights that are not "
                  "directional");
    int checked = 0, shadowed = 0, bad = 0;
    for (int l = 0; l < n; l++) {
        const float *tl = TILE(&p, &s, l);
        LG_TEST_CHECK(t, tl[0] == (float)((l % cols) * res) && tl[1] == (float)((l / cols) * res),
                      "light %d: tile at (%g, %g), want (%d, %d)", l, (double)tl[0], (double)tl[1],
                      (l % cols) * res, (l / cols) * res);
        float margin = 3.0f * tl[2];
        for (int j = 0; j < s.n_pts; j++) {
            int e = expected(s.pts[j], s.lights[l].v, margin);
            if (j == l)
                LG_TEST_CHECK(t, e == 0, "light %d: its shadow centre is not in its shadow", l);
            if (e < 0)
                continue;
            checked++;
            shadowed += e == 0;
            if (S(&p, l, j) != (float)e) {
                if (bad++ < 10)
                    fprintf(stderr,
                            "light %d (%.3f %.3f %.3f), point %d (%g, %g, %g): Shadow "
                            "%g, want %d (z %.7g, D %.7g)\n",
                            l, (double)s.lights[l].v.x, (double)s.lights[l].v.y,
                            (double)s.lights[l].v.z, j, (double)s.pts[j].x, (double)s.pts[j].y,
                            (double)s.pts[j].z, (double)S(&p, l, j), e, (double)Z(&p, l, j),
                            (double)D(&p, l, j));
            }
        }
    }
    LG_TEST_CHECK(t, bad == 0, "%d of %d light-point pairs disagree with the ray-box test", bad,
                  checked);
    LG_TEST_CHECK(t, shadowed >= n && checked - shadowed >= n * 20,
                  "too few pairs tested: %d shadowed, %d lit", shadowed, checked - shadowed);
    lg_image_free(&p);
}

static void case_lights2(lg_test *t)
{
    lights_n(t, 2, 512);
}
static void case_lights8(lg_test *t)
{
    lights_n(t, 8, 512);
}
static void case_lights32(lg_test *t)
{
    lights_n(t, 32, 256);
}

static void case_layout32(lg_test *t)
{
    setup s = { .normals = true, .shadow = "" };
    for (int i = 0; i < 32; i++)
        add_light(&s, dir_from(35.0, 360.0 * i / 32));
    for (int i = 0; i < 32; i++) {
        lg_vec3 d = s.lights[i].v;
        float k = 1.5f / -d.y;
        add_point(&s, d.x * k, 0, d.z * k);
    }
    const char *args[] = { "--explain", NULL };
    char *out = NULL;
    lg_image p = { 0 };
    bool ok = run(t, &s, args, &p, &out);
    LG_TEST_CHECK(t, out && strstr(out, "atlas: image 6144x6144 depth32f"),
                  "--explain does not show a 6144x6144 depth atlas:\n%s", out ? out : "");
    free(out);
    if (!ok)
        return;
    const float *i0 = INFO(&p, &s, 0);
    LG_TEST_CHECK(t, i0[0] == 32 && i0[1] == 1024 && i0[2] == 6144 && i0[3] == 6144,
                  "payload: %g lights at %g, atlas %gx%g; want 32 at 1024, 6144x6144",
                  (double)i0[0], (double)i0[1], (double)i0[2], (double)i0[3]);
    for (int l = 0; l < 32; l++) {
        LG_TEST_CHECK(t, S(&p, l, l) == 0, "light %d: its shadow centre is lit", l);
        const float *tl = TILE(&p, &s, l);
        LG_TEST_CHECK(t, tl[0] == (float)((l % 6) * 1024) && tl[1] == (float)((l / 6) * 1024),
                      "light %d: tile at (%g, %g)", l, (double)tl[0], (double)tl[1]);
    }
    lg_image_free(&p);
}

/* Floor points of a 15 x 15 grid, lit by lights 0, 30, 60, 75, 85 degrees off vertical;
 * returns how many (light, point) pairs are self-shadowed, or -1 if the render failed. */
static int acne(lg_test *t, const char *scene, const char *shadow)
{
    setup s = { .scene = scene, .shadow = shadow, .normals = true };
    static const double angles[5] = { 0, 30, 60, 75, 85 };
    for (int i = 0; i < 5; i++)
        add_light(&s, dir_from(angles[i], 20.0 + 50.0 * i));
    for (int a = 0; a < 15; a++)
        for (int b = 0; b < 15; b++)
            add_point(&s, -3.5f + 0.5f * a + 0.013f * b, 0, -3.5f + 0.5f * b + 0.007f * a);
    lg_image p = { 0 };
    if (!run(t, &s, NULL, &p, NULL))
        return -1;
    int n = 0;
    for (int l = 0; l < 5; l++) {
        int nl = 0;
        for (int j = 0; j < s.n_pts; j++) {
            if (HAS(&p, l, j) != 1 || D(&p, l, j) < 0)
                LG_TEST_CHECK(t, false, "light %d point %d is outside the map (has %g, z %g, D %g)",
                              l, j, (double)HAS(&p, l, j), (double)Z(&p, l, j),
                              (double)D(&p, l, j));
            nl += S(&p, l, j) == 0;
        }
        if (nl && getenv("LG_TEST_VERBOSE"))
            fprintf(stderr, "{%s} {%s}: light %d (%g deg): %d of %d points self-shadowed\n", scene,
                    shadow, l, angles[l], nl, s.n_pts);
        n += nl;
    }
    lg_image_free(&p);
    return n;
}

static void case_bias(lg_test *t)
{
    static const char *const configs[][2] = {
        { "box = false, floor_double_sided = true", "resolution = 256" },
        { "box = false, floor_double_sided = true", "resolution = 1024" },
        { "box = false", "resolution = 1024, cull = back" },
        { "box = false, floor_double_sided = true", "resolution = 16" },
    };
    for (size_t i = 0; i < sizeof configs / sizeof configs[0]; i++) {
        int n = acne(t, configs[i][0], configs[i][1]);
        LG_TEST_CHECK(t, n == 0, "{%s} {%s}: %d floor points self-shadowed with the default bias",
                      configs[i][0], configs[i][1], n);
    }
    /* without any bias the slanted lights shadow the floor they light */
    int n = acne(t, "box = false, floor_double_sided = true",
                 "resolution = 256, bias_constant = 0, bias_slope = 0, normal_offset = 0");
    LG_TEST_CHECK(t, n > 100,
                  "without bias only %d floor points are self-shadowed; the test "
                  "cannot see acne",
                  n);
}

/* Points on a UV sphere of radius 1 at (0, 1.5, 0) (shadowprobe.c, ss_sphere, 12 rings):
 * the centroids of its triangles, with the interpolated normal there. Lit from three
 * directions; a convex body shadows none of its own points that face a light, so every
 * centroid whose normal and facet both face light L (N.L > 0.2) must be lit. Returns how
 * many such (light, point) pairs are shadowed, or -1. */
static int sphere_acne(lg_test *t, const char *scene, const char *shadow)
{
    setup *s = calloc(1, sizeof *s);
    char sc[256];
    snprintf(sc, sizeof sc, "shape = sphere, box_size = [2, 2, 2], sphere_rings = 12%s%s",
             *scene ? ", " : "", scene);
    s->scene = sc;
    s->shadow = shadow;
    s->normals = true;
    static const double angles[3] = { 0, 45, 70 };
    for (int i = 0; i < 3; i++)
        add_light(s, dir_from(angles[i], 30.0 + 100.0 * i));
    const int R = 12, SG = 24;
    lg_vec3 v[13 * 25];
    for (int r = 0; r <= R; r++)
        for (int k = 0; k <= SG; k++) {
            double th = LG_PI * r / R, az = 2 * LG_PI * k / SG;
            v[r * (SG + 1) + k] = lg_v3((float)(sin(th) * cos(az)), (float)cos(th),
                                        (float)(sin(th) * sin(az)));
        }
    lg_vec3 facet[MAX_POINTS];
    for (int r = 0; r < R; r++)
        for (int k = 0; k < SG; k++) {
            int a = r * (SG + 1) + k, b = a + SG + 1;
            int tri[2][3] = { { a, b, b + 1 }, { a, b + 1, a + 1 } };
            for (int i = 0; i < 2; i++) {
                lg_vec3 p0 = v[tri[i][0]], p1 = v[tri[i][1]], p2 = v[tri[i][2]];
                lg_vec3 c = lg_v3_scale(lg_v3_add(p0, lg_v3_add(p1, p2)), 1.0f / 3.0f);
                lg_vec3 fn = lg_v3_cross(lg_v3_sub(p1, p0), lg_v3_sub(p2, p0));
                if (lg_v3_length(fn) < 1e-6f)
                    continue; /* a degenerate triangle at a pole */
                if (lg_v3_dot(fn, c) < 0)
                    fn = lg_v3_scale(fn, -1.0f);
                facet[s->n_pts] = lg_v3_normalize_or(fn, c);
                /* the vertices' normals are their positions: the centroid's interpolated
                 * normal is the centroid's direction */
                s->nrm[s->n_pts] = lg_v3_normalize_or(c, lg_v3(0, 1, 0));
                s->pts[s->n_pts++] = lg_v3(c.x, c.y + 1.5f, c.z);
            }
        }
    lg_image p = { 0 };
    int bad = -1;
    if (run(t, s, NULL, &p, NULL)) {
        bad = 0;
        int tested = 0;
        for (int l = 0; l < 3; l++) {
            lg_vec3 to_light = lg_v3_scale(s->lights[l].v, -1.0f);
            int nl = 0;
            for (int j = 0; j < s->n_pts; j++) {
                if (lg_v3_dot(s->nrm[j], to_light) <= 0.2f || lg_v3_dot(facet[j], to_light) <= 0.0f)
                    continue;
                tested++;
                nl += S(&p, l, j) == 0;
            }
            if (nl && getenv("LG_TEST_VERBOSE"))
                fprintf(stderr, "{%s} {%s}: light %d (%g deg): %d points self-shadowed\n", sc,
                        shadow, l, angles[l], nl);
            bad += nl;
        }
        LG_TEST_CHECK(t, tested > 500, "only %d sphere points face a light", tested);
        lg_image_free(&p);
    }
    free(s);
    return bad;
}

static void case_curved(lg_test *t)
{
    static const char *const configs[][2] = {
        { "box_double_sided = true", "resolution = 256" },
        { "box_double_sided = true", "resolution = 1024" },
        { "", "resolution = 1024, cull = back" },
        { "", "resolution = 1024" },
    };
    for (size_t i = 0; i < sizeof configs / sizeof configs[0]; i++) {
        int n = sphere_acne(t, configs[i][0], configs[i][1]);
        LG_TEST_CHECK(t, n == 0,
                      "{%s} {%s}: %d sphere points facing a light are self-shadowed "
                      "with the default bias",
                      configs[i][0], configs[i][1], n);
    }
    int n = sphere_acne(t, "box_double_sided = true",
                        "resolution = 1024, bias_constant = 0, bias_slope = 0, normal_offset = 0");
    LG_TEST_CHECK(t, n > 50,
                  "without bias only %d sphere points are self-shadowed; the test "
                  "cannot see acne",
                  n);
}

static void case_gating(lg_test *t)
{
    const char *args[] = { "--explain", NULL };
    /* no light at all (a point light alone has its cube since ABI 3.2: case 'point') */
    for (int k = 0; k < 1; k++) {
        setup s = { 0 };
        add_point(&s, 0, 0, 0);
        add_point(&s, 3, 0, 3);
        char *out = NULL;
        lg_image p = { 0 };
        bool ok = run(t, &s, args, &p, &out);
        const char *o = out ? out : "";
        LG_TEST_CHECK(t, contains_line(o, "plugins not loaded:", "shadowmap"),
                      "%s: shadowmap is not among the plugins not loaded:\n%s",
                      k ? "point light" : "no light", o);
        LG_TEST_CHECK(t, !contains_line(o, "plugins loaded:", "shadowmap"),
                      "%s: shadowmap was loaded:\n%s", k ? "point light" : "no light", o);
        LG_TEST_CHECK(t, strcmp(state_of(o, "shadow"), "gated") == 0,
                      "the node is not shown gated:\n%s", o);
        free(out);
        if (!ok)
            continue;
        LG_TEST_CHECK(t, INFO(&p, &s, 0)[0] == -1, "the probe got shadow maps from a gated node");
        for (int l = 0; l < s.n_lights; l++)
            for (int j = 0; j < s.n_pts; j++)
                LG_TEST_CHECK(t, S(&p, l, j) == 1 && HAS(&p, l, j) == 0,
                              "light %d point %d: Shadow %g has %g without shadow maps", l, j,
                              (double)S(&p, l, j), (double)HAS(&p, l, j));
        lg_image_free(&p);
    }

    /* a point light, then a directional light: the point light's cube (six tiles), then
     * one tile for scene light 1 (before ABI 3.2 the point light was skipped) */
    setup s = { .shadow = "resolution = 256" };
    s.lights[0].point = true;
    s.lights[0].v = lg_v3(0, 3, 0);
    s.n_lights = 1;
    add_light(&s, lg_v3(0, -1, 0));
    add_point(&s, 0, 0, 0);
    add_point(&s, 3, 0, 3);
    char *out = NULL;
    lg_image p = { 0 };
    bool ok = run(t, &s, args, &p, &out);
    LG_TEST_CHECK(t, contains_line(out ? out : "", "plugins loaded:", "shadowmap"),
                  "shadowmap not loaded with a directional light:\n%s", out ? out : "");
    free(out);
    if (ok) {
        LG_TEST_CHECK(t, INFO(&p, &s, 0)[0] == 7, "payload has %g maps, want 7",
                      (double)INFO(&p, &s, 0)[0]);
        LG_TEST_CHECK(t,
                      INFO(&p, &s, 2)[0] == 0 && INFO(&p, &s, 2)[1] == 6 && INFO(&p, &s, 2)[2] == 6,
                      "the lights list: %g mismatched, %g perspective, %g of point lights; want "
                      "0, 6, 6",
                      (double)INFO(&p, &s, 2)[0], (double)INFO(&p, &s, 2)[1],
                      (double)INFO(&p, &s, 2)[2]);
        LG_TEST_CHECK(t, HAS(&p, 0, 0) == 1 && S(&p, 0, 0) == 0 && S(&p, 0, 1) == 1,
                      "the point light (scene light 0) over the box: has %g, Shadow %g %g; want "
                      "1, 0 1",
                      (double)HAS(&p, 0, 0), (double)S(&p, 0, 0), (double)S(&p, 0, 1));
        LG_TEST_CHECK(t, HAS(&p, 1, 0) == 1 && S(&p, 1, 0) == 0 && S(&p, 1, 1) == 1,
                      "scene light 1: has %g, Shadow %g %g; want 1, 0 1", (double)HAS(&p, 1, 0),
                      (double)S(&p, 1, 0), (double)S(&p, 1, 1));
        lg_image_free(&p);
    }

    /* an unconnected shadows input: NULL as well */
    setup u = { .no_shadow_input = true };
    add_light(&u, lg_v3(0, -1, 0));
    add_point(&u, 0, 0, 0);
    if (run(t, &u, NULL, &p, NULL)) {
        LG_TEST_CHECK(t, INFO(&p, &u, 0)[0] == -1 && S(&p, 0, 0) == 1,
                      "an unconnected input gave shadow maps");
        lg_image_free(&p);
    }
}

static void case_frustum(lg_test *t)
{
    /* a 40 x 40 floor; the camera looks down at the box from (0, 6, 2) */
    const char *scene = "floor_size = 40, camera_position = [0, 6, 2], camera_target = [0, 0, 0], "
                        "yfov = 40";
    lg_vec3 dir = lg_v3_normalize_or(lg_v3(0.3f, -1, 0.2f), lg_v3(0, -1, 0));
    float texel[2] = { 0, 0 };
    for (int fit = 0; fit < 2; fit++) {
        setup s = { .scene = scene,
                    .normals = true,
                    .shadow = fit ? "resolution = 512, fit = frustum" : "resolution = 512" };
        add_light(&s, dir);
        for (int a = -4; a <= 4; a++)
            for (int b = -4; b <= 4; b++)
                add_point(&s, 0.25f * (float)a, 0, 0.25f * (float)b);
        add_point(&s, 15, 0, -15); /* far outside the camera's view */
        lg_image p = { 0 };
        if (!run(t, &s, (const char *const[]){ "--size", "64x64", NULL }, &p, NULL))
            return;
        texel[fit] = TILE(&p, &s, 0)[2];
        int bad = 0, checked = 0;
        for (int j = 0; j < s.n_pts - 1; j++) {
            int e = expected(s.pts[j], dir, 3.0f * texel[fit]);
            LG_TEST_CHECK(t, D(&p, 0, j) >= 0, "fit %d: point %d (%g, 0, %g) outside the map", fit,
                          j, (double)s.pts[j].x, (double)s.pts[j].z);
            if (e < 0)
                continue;
            checked++;
            if (S(&p, 0, j) != (float)e && bad++ < 5)
                fprintf(stderr, "fit %d: point %d (%g, 0, %g): Shadow %g, want %d\n", fit, j,
                        (double)s.pts[j].x, (double)s.pts[j].z, (double)S(&p, 0, j), e);
        }
        LG_TEST_CHECK(t, bad == 0 && checked > 25, "fit %d: %d of %d points disagree", fit, bad,
                      checked);
        lg_image_free(&p);
    }
    /* the camera sees about 4.4 m of floor; the bounds are 40 m wide */
    LG_TEST_CHECK(t, texel[1] < texel[0] / 4,
                  "fit = frustum texel %g is not much finer than the "
                  "bounds' %g",
                  (double)texel[1], (double)texel[0]);

    /* a wider image sees more of the floor: a coarser map */
    setup w = { .scene = scene, .shadow = "resolution = 512, fit = frustum, aspect = 4" };
    add_light(&w, dir);
    add_point(&w, 0, 0, 0);
    lg_image pw = { 0 };
    if (run(t, &w, (const char *const[]){ "--size", "64x64", NULL }, &pw, NULL)) {
        float tw = TILE(&pw, &w, 0)[2];
        LG_TEST_CHECK(t, tw > 1.5f * texel[1] && tw < texel[0],
                      "aspect 4: texel %g, aspect 1: %g, "
                      "bounds: %g",
                      (double)tw, (double)texel[1], (double)texel[0]);
        LG_TEST_CHECK(t, S(&pw, 0, 0) == 0, "aspect 4: the box's shadow is gone");
        lg_image_free(&pw);
    }

    /* a camera looking up at nothing: the bounds' fit */
    setup s = { .scene = "floor_size = 40, camera_position = [0, 6, 2], camera_target = [0, 20, "
                         "2.5], yfov = 40",
                .shadow = "resolution = 512, fit = frustum" };
    add_light(&s, dir);
    add_point(&s, 0, 0, 0);
    lg_image p = { 0 };
    if (run(t, &s, NULL, &p, NULL)) {
        LG_TEST_CHECK(t, fabsf(TILE(&p, &s, 0)[2] - texel[0]) < 1e-6f * texel[0],
                      "camera seeing nothing: texel %g, want the bounds' %g",
                      (double)TILE(&p, &s, 0)[2], (double)texel[0]);
        LG_TEST_CHECK(t, S(&p, 0, 0) == 0, "camera seeing nothing: the box's shadow is gone");
        lg_image_free(&p);
    }
}

static void case_atlas(lg_test *t)
{
    /* light from straight above; the box towards the back (-Z) */
    setup s = { .scene = "box_center = [0, 1.5, -2]",
                .shadow = "resolution = 128",
                .extra = "output shadow.atlas \"sm.exr\"\noutput shadow.atlas \"sm.png\"\n" };
    add_light(&s, lg_v3(0, -1, 0));
    add_point(&s, 0.1f, 1, -2.1f); /* the box's bottom: what front-face culling stores */
    lg_image p = { 0 }, a = { 0 };
    if (!run(t, &s, NULL, &p, NULL))
        return;
    unsigned bits = 0;
    if (!lg_test_read(t, "sm.exr", &a, &bits)) {
        lg_image_free(&p);
        return;
    }
    LG_TEST_CHECK(t, a.width == 128 && a.height == 128, "atlas file %ux%u", a.width, a.height);
    uint32_t grey = 0, range = 0, drawn = 0, top = 0;
    for (uint32_t y = 0; y < a.height; y++)
        for (uint32_t x = 0; x < a.width; x++) {
            const float *q = px(&a, x, y);
            grey += q[0] == q[1] && q[1] == q[2] && q[3] == 1.0f;
            range += q[0] >= 0.0f && q[0] <= 1.0f;
            if (q[0] < 1.0f) {
                drawn++;
                top += y < a.height / 2;
            }
        }
    size_t np = (size_t)a.width * a.height;
    LG_TEST_CHECK(t, grey == np, "%zu of %zu atlas pixels are not grey with alpha 1", np - grey,
                  np);
    LG_TEST_CHECK(t, range == np, "%zu atlas values outside [0, 1]", np - range);
    /* the box covers 1 x 1 of the 8 x 8 floor: 1/64 of the tile, minus the margin */
    double want = np / 64.0 * (124.0 / 128.0) * (124.0 / 128.0);
    LG_TEST_CHECK(t, fabs(drawn - want) < 0.15 * want, "%u texels drawn, want about %.0f", drawn,
                  want);
    LG_TEST_CHECK(t, drawn > 0 && top == drawn,
                  "%u of %u drawn texels in the top half: the tile "
                  "is not upright (-Z up under a light from above)",
                  top, drawn);
    /* the probe's texel of the box's bottom point has the file's value */
    const float *tl = TILE(&p, &s, 0);
    double tw = tl[2];
    /* light view: x = world x, y = world -z; the tile's centre is the bounds' (0, 0) */
    uint32_t cx = (uint32_t)floor(64 + 0.1 / tw), cy = (uint32_t)floor(64 - 2.1 / tw);
    LG_TEST_CHECK(t, fabsf(px(&a, cx, cy)[0] - D(&p, 0, 0)) < 1e-6f,
                  "file depth %.7g at (%u, %u), the probe read %.7g", (double)px(&a, cx, cy)[0], cx,
                  cy, (double)D(&p, 0, 0));
    LG_TEST_CHECK(t, fabsf(D(&p, 0, 0) - Z(&p, 0, 0)) < 1e-5f,
                  "stored %.7g, the bottom's depth %.7g", (double)D(&p, 0, 0), (double)Z(&p, 0, 0));
    FILE *f = fopen(lg_test_path(t, "sm.png"), "rb");
    LG_TEST_CHECK(t, f != NULL, "sm.png was not written");
    if (f)
        fclose(f);
    lg_image_free(&a);
    lg_image_free(&p);
}

static void expect_error(lg_test *t, const setup *s, int code, const char *msg)
{
    char *g = graph_text(s);
    lg_test_write_text(t, "g.lgraph", g);
    free(g);
    char *out = NULL;
    int rc = lg_test_render(t, "g.lgraph", NULL, &out);
    LG_TEST_CHECK(t, rc == code, "exit %d, want %d (%s)", rc, code, msg);
    LG_TEST_CHECK(t, out && strstr(out, msg), "the message lacks '%s':\n%s", msg, out ? out : "");
    free(out);
}

static void case_errors(lg_test *t)
{
    setup s = { .shadow = "resolution = 8192" };
    for (int i = 0; i < 32; i++)
        add_light(&s, dir_from(35.0, 360.0 * i / 32));
    add_point(&s, 0, 0, 0);
    expect_error(t, &s, 1,
                 "32 maps (32 directional, 0 spot, 0 cubes of 6) at resolution 8192 need an "
                 "atlas of 49152x49152 texels");

    setup b = { .scene = "bad_light = true" };
    add_point(&b, 0, 0, 0);
    expect_error(t, &b, 1, "light 0 'bad': direction [0, 0, 0] is not a direction");

    setup c = { .shadow = "fit = frustum, camera = 3" };
    add_light(&c, lg_v3(0, -1, 0));
    add_point(&c, 0, 0, 0);
    expect_error(t, &c, 1, "fit = frustum: camera 3 does not exist: the scene has 1 camera");

    setup r = { .shadow = "resolution = 8" };
    add_light(&r, lg_v3(0, -1, 0));
    add_point(&r, 0, 0, 0);
    expect_error(t, &r, 2, "resolution");
}

/* ---- spot and point lights (ABI 3.2) --------------------------------------------------------- */

static void add_local(setup *s, lg_vec3 pos, lg_vec3 dir, float outer_deg, float range)
{
    light_spec *l = &s->lights[s->n_lights++];
    l->point = true;
    l->v = pos;
    l->dir = dir;
    l->outer_deg = outer_deg;
    l->range = range;
}

static void case_spot(lg_test *t)
{
    /* a spot 4 above the floor, straight down, cone 40 degrees: the unit box (top at y = 2)
     * casts a square shadow of half-side 0.5 * 4 / 2 = 1 (its top's edges) */
    const lg_vec3 q = lg_v3(0, 4, 0), c = lg_v3(0, 1.5f, 0), h = lg_v3(0.5f, 0.5f, 0.5f);
    setup s = { .shadow = "resolution = 256" };
    add_local(&s, q, lg_v3(0, -1, 0), 40.0f, 0.0f);
    for (int i = 0; i <= 24; i++)
        for (int j = 0; j <= 24; j++)
            add_point(&s, -2.4f + 0.2f * (float)i, 0, -2.4f + 0.2f * (float)j);
    int n_grid = s.n_pts;
    /* across the shadow's edge at x = 1 (z = 0.1): 1 mm steps */
    for (int i = 0; i <= 200; i++)
        add_point(&s, 0.9f + 0.001f * (float)i, 0, 0.1f);
    lg_image p = { 0 };
    if (!run(t, &s, NULL, &p, NULL))
        return;
    const float *info2 = INFO(&p, &s, 2);
    LG_TEST_CHECK(t, INFO(&p, &s, 0)[0] == 1 && info2[0] == 0 && info2[1] == 1,
                  "a spot light: %g maps, %g mismatched, %g perspective; want 1, 0, 1",
                  (double)INFO(&p, &s, 0)[0], (double)info2[0], (double)info2[1]);
    float texel = TILE(&p, &s, 0)[2] * 4.0f; /* at the floor, 4 from the light */
    LG_TEST_CHECK(t, texel > 0 && texel < 0.05f, "texel at the floor %g", (double)texel);
    int wrong = 0, dark = 0, tested = 0;
    for (int j = 0; j < n_grid; j++) {
        /* the margin at the box's top, 2 from the light: half the floor's texel */
        int want = expected_at(s.pts[j], q, c, h, 2.0f * 0.5f * texel);
        float outside = tanf(40.0f * (float)DEG) * 4.0f;
        if (want < 0 || fabsf(s.pts[j].x) > outside || fabsf(s.pts[j].z) > outside)
            continue;
        tested++;
        dark += want == 0;
        if (S(&p, 0, j) != (float)want && wrong++ < 5)
            LG_TEST_FAILF(t, "floor (%g, %g): Shadow %g, want %d", (double)s.pts[j].x,
                          (double)s.pts[j].z, (double)S(&p, 0, j), want);
    }
    LG_TEST_CHECK(t, wrong == 0 && dark >= 60 && tested > 300,
                  "%d of %d floor points wrong (%d in the shadow)", wrong, tested, dark);
    /* the edge: the last shadowed point within a texel of x = 1 */
    float edge = NAN;
    for (int j = n_grid; j < s.n_pts; j++)
        if (S(&p, 0, j) == 0)
            edge = s.pts[j].x;
    LG_TEST_CHECK(t, fabsf(edge - 1.0f) <= texel,
                  "the shadow's edge at x = %g, want 1 within a texel (%g)", (double)edge,
                  (double)texel);
    printf("spot: edge at x = %.4f (geometry: 1), texel %.4f at the floor\n", (double)edge,
           (double)texel);
    lg_image_free(&p);
}

static void case_point(lg_test *t)
{
    static const float axes[6][3] = { { 1, 0, 0 },  { -1, 0, 0 }, { 0, 1, 0 },
                                      { 0, -1, 0 }, { 0, 0, 1 },  { 0, 0, -1 } };
    const lg_vec3 q = lg_v3(0, 3, 0), h = lg_v3(0.3f, 0.3f, 0.3f);
    for (int f = 0; f < 6; f++) {
        /* an occluder 1 from the light along each face's axis, off the axis by 0.15 */
        lg_vec3 c = lg_v3(q.x + axes[f][0] + (f / 2 == 0 ? 0 : 0.15f),
                          q.y + axes[f][1] + (f / 2 == 1 ? 0 : 0.15f), q.z + axes[f][2]);
        char scene[256];
        snprintf(scene, sizeof scene, "box_center = [%g, %g, %g], box_size = [0.6, 0.6, 0.6]",
                 (double)c.x, (double)c.y, (double)c.z);
        setup s = { .scene = scene, .shadow = "resolution = 256" };
        add_local(&s, q, lg_v3(0, 0, 0), 0.0f, 0.0f);
        const int n = 600;
        for (int i = 0; i < n; i++) {
            double z = 1.0 - (2.0 * i + 1.0) / n, r = sqrt(1.0 - z * z);
            double a = i * LG_PI * (3.0 - sqrt(5.0));
            add_point(&s, (float)(q.x + 2.2 * r * cos(a)), (float)(q.y + 2.2 * z),
                      (float)(q.z + 2.2 * r * sin(a)));
        }
        lg_image p = { 0 };
        if (!run(t, &s, NULL, &p, NULL))
            return;
        LG_TEST_CHECK(t, INFO(&p, &s, 0)[0] == 6 && INFO(&p, &s, 2)[0] == 0,
                      "face %d: %g maps (want 6), %g mismatched", f, (double)INFO(&p, &s, 0)[0],
                      (double)INFO(&p, &s, 2)[0]);
        /* the margin: 2 texels at the box's farthest corner from the light */
        float m = 2.0f * TILE(&p, &s, 0)[2] * 1.6f;
        int wrong = 0, dark = 0;
        for (int j = 0; j < s.n_pts; j++) {
            int want = expected_at(s.pts[j], q, c, h, m);
            if (want < 0)
                continue;
            dark += want == 0;
            if (S(&p, 0, j) != (float)want && wrong++ < 5)
                LG_TEST_FAILF(t, "face %d: (%g, %g, %g): Shadow %g, want %d", f, (double)s.pts[j].x,
                              (double)s.pts[j].y, (double)s.pts[j].z, (double)S(&p, 0, j), want);
        }
        LG_TEST_CHECK(t, wrong == 0 && dark >= 10, "face %d: %d wrong, %d in the shadow", f, wrong,
                      dark);
        lg_image_free(&p);
    }

    /* the light inside the box: every point around is in its shadow; range 0 = infinite
     * fits the far plane to the scene, a range of 1.5 to the range */
    for (int k = 0; k < 2; k++) {
        setup s = { .shadow = "resolution = 128" };
        add_local(&s, lg_v3(0, 1.5f, 0), lg_v3(0, 0, 0), 0.0f, k ? 1.5f : 0.0f);
        for (int i = 0; i < 40; i++)
            add_point(&s, 1.2f * cosf((float)i), 1.5f + 0.9f * sinf(0.7f * (float)i),
                      1.2f * sinf((float)i));
        lg_image p = { 0 };
        if (!run(t, &s, NULL, &p, NULL))
            return;
        int lit = 0;
        for (int j = 0; j < s.n_pts; j++)
            lit += S(&p, 0, j) != 0;
        LG_TEST_CHECK(t, lit == 0, "range %g: a light inside the box: %d of %d points lit",
                      k ? 1.5 : 0.0, lit, s.n_pts);
        float far = TILE(&p, &s, 0)[3];
        /* the floor's corner (4, 0, 4) is sqrt(32 + 2.25) = 5.85 from the light */
        LG_TEST_CHECK(t, k ? far > 1.4f && far < 1.6f : far > 5.8f && far < 6.0f,
                      "range %g: depth range %g", k ? 1.5 : 0.0, (double)far);
        lg_image_free(&p);
    }
}

static void case_pcf(lg_test *t)
{
    /* straight down: the box's shadow edge at x = 0.5; PCF over (2 r + 1)^2 texels makes it a
     * ramp from 0 to 1 over 2 r texels, in steps of 1 / (2 r + 1) */
    for (int r = 0; r <= 2; r++) {
        char sh[128];
        snprintf(sh, sizeof sh, "resolution = 256, pcf_radius = %d", r);
        setup s = { .shadow = sh, .scene = "box_size = [1, 1, 0.6]" };
        add_light(&s, lg_v3(0, -1, 0));
        for (int i = 0; i <= 300; i++)
            add_point(&s, 0.2f + 0.002f * (float)i, 0, 0.05f);
        s.sdk = true; /* the SDK's lookup, with the map's PCF, for the directional light */
        lg_image p = { 0 };
        if (!run(t, &s, NULL, &p, NULL))
            return;
        LG_TEST_CHECK(t, INFO(&p, &s, 2)[3] == (float)r, "payload pcf_radius %g, want %d",
                      (double)INFO(&p, &s, 2)[3], r);
        float texel = TILE(&p, &s, 0)[2];
        float last_dark = NAN, first_lit = NAN, prev = -1;
        bool monotone = true, steps = true;
        for (int j = 0; j < s.n_pts; j++) {
            float v = S(&p, 0, j), k = v * (float)(2 * r + 1);
            monotone = monotone && v >= prev;
            steps = steps && fabsf(k - roundf(k)) < 1e-4f;
            prev = v;
            if (v == 0)
                last_dark = s.pts[j].x;
            if (v == 1 && isnan(first_lit))
                first_lit = s.pts[j].x;
        }
        float width = (first_lit - last_dark) / texel;
        LG_TEST_CHECK(t, monotone && steps, "pcf %d: not a monotone ramp in steps of 1/%d", r,
                      2 * r + 1);
        /* the kernel is 2 r + 1 texels wide: the visibility leaves 0 where its last tap
         * crosses the edge and reaches 1 where its first does, 2 r texels on (the points
         * are 1/16 texel apart) */
        LG_TEST_CHECK(t, fabsf(width - (float)(2 * r)) <= 0.25f,
                      "pcf %d: the ramp is %g texels wide, want %d", r, (double)width, 2 * r);
        printf("pcf %d: ramp %.2f texels (x %.4f .. %.4f, texel %.4f)\n", r, (double)width,
               (double)last_dark, (double)first_lit, (double)texel);
        lg_image_free(&p);
    }
}

int main(int argc, char **argv)
{
    static const lg_test_case cases[] = {
        { "basic", case_basic },     { "cull", case_cull },         { "lights2", case_lights2 },
        { "lights8", case_lights8 }, { "lights32", case_lights32 }, { "layout32", case_layout32 },
        { "bias", case_bias },       { "curved", case_curved },     { "gating", case_gating },
        { "frustum", case_frustum }, { "atlas", case_atlas },       { "errors", case_errors },
        { "spot", case_spot },       { "point", case_point },       { "pcf", case_pcf },
    };
    lg_test_main_opts o = { .setup = setup_case };
    return lg_test_main(argc, argv, cases, sizeof cases / sizeof cases[0], &o);
}
