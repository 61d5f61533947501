/*
 * The medium's shadow on surfaces (lightgraph issue 25; plugins/phong/README.md, "Shadows
 * of the medium"): phong multiplies each light by the transmittance T = e^(-sigma_t tau)
 * towards it through the medium's density field. Through the host, on GL: the plane of
 * testphongscene (y = 0, facing +Y) seen straight down, ka = 0, kd = 1, Od = 1, ambient 0,
 * one light and a `medium` node with a field; each image is divided by the same graph's
 * image with medium_shadows = false, which leaves T per pixel and channel, and that T is
 * compared with the exact one at the world point under the pixel's centre, computed here
 * in double from the medium's numbers. `test_phong_medium CASE`:
 *
 *   uniform   a box of fog (field = uniform, box_min, box_max) above the plane: T =
 *             e^(-sigma_t chord), the chord of the segment towards the light through the
 *             box (closed form), for a directional, a point (in range) and a spot light;
 *             points outside the box's shadow (the segment misses the box) equal the image
 *             without the medium bit for bit; every shading mode runs the shadow (points
 *             well inside and well outside it)
 *   height    height fog in a box whose floor is the plane (the plane's points lie on the
 *             box's face): tau = e^(-a (y0 - b)) (e^(-a Ly s0) - e^(-a Ly s1)) / (a Ly)
 *             (closed form), a point light and a spot light inside the box, a directional
 *             light
 *   fbm       fBm noise in a box above the plane: tau marched here in double (1000
 *             midpoint steps of lg_medium_field_at); the error shrinks as
 *             medium_shadow_res grows (16, 32, 64)
 *   grazing   a directional light 1.7 degrees above the horizon through a box standing on
 *             the plane: chords of metres, finite, within the same bound
 *   gating    the image without a medium, with a homogeneous medium (field = none), with a
 *             field and medium_shadows = false, and with a field of zero density (fBm whose
 *             offset exceeds its largest sum): all four the same bits
 *
 * The error's bounds are the measured errors with a margin (README.md gives the numbers):
 * the optical-depth volume is trilinear between its nodes, exact for a linear tau and off
 * by a fraction of a cell's change where tau bends (a chord's end moving from one face of
 * the box to another, the noise's detail finer than a cell).
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "lightgraph/medium.h"
#include "lightgraph/test.h"
#include "lightgraph/vecmath.h"

#ifndef PH_TEST_PLUGIN_DIR
#define PH_TEST_PLUGIN_DIR ""
#endif

#define W 48
#define H 48

static const char *const MODES[5] = { "flat", "gouraud", "phong", "mixed", "phong_half" };

/* The camera: straight down from 3 m at the origin, 60 degrees; image right is +X, image up
 * is -Z. */
static void ground_point(uint32_t x, uint32_t y, double p[3])
{
    const double half = 3.0 * tan(30.0 * LG_PI / 180.0);
    p[0] = ((x + 0.5) / (W / 2.0) - 1.0) * half;
    p[1] = 0.0;
    p[2] = ((y + 0.5) / (H / 2.0) - 1.0) * half;
}

typedef struct mlight {
    const char *what;   /* for messages */
    const char *params; /* the light node's */
    int local;          /* 0 directional (dir), 1 point or spot (pos) */
    double dir[3];      /* the direction the light travels */
    double pos[3];
} mlight;

typedef struct mfield {
    const char *params; /* the medium node's */
    double sigma_t[3];  /* density x (scattering + absorption) */
    double lo[3], hi[3];
    lg_medium medium; /* the same field, for the march */
    lg_density_field field;
} mfield;

/* Renders one graph with n phong nodes on the same lit scene, the k-th with parameters
 * phong[k] and written to out<k>.exr, read into imgs[k] (one host run: the tests stay fast). */
static int render(lg_test *t, const mfield *f, const mlight *l, const char *const *phong, int n,
                  lg_image *imgs)
{
    char g[8192];
    int len = snprintf(g, sizeof g,
                       "lightgraph 1\n"
                       "s = test_phong_scene { layout = plane, size = 4, segments = 16, ka = 0, "
                       "kd = 1, ks = 0, od = [1, 1, 1], camera_position = [0, 3, 0], "
                       "camera_target = [0, 0, 0], camera_up = [0, 0, -1], yfov_deg = 60 }\n"
                       "ls = light { scene = s, intensity = 2, %s }\n"
                       "%s\n",
                       l->params, f ? f->params : "");
    for (int k = 0; k < n && len > 0 && (size_t)len < sizeof g; k++)
        len += snprintf(g + len, sizeof g - (size_t)len,
                        "lit%d = phong { scene = %s, ambient = [0, 0, 0], %s }\n"
                        "output lit%d \"out%d.exr\"\n",
                        k, f ? "fog" : "ls", phong[k], k, k);
    if (len <= 0 || (size_t)len >= sizeof g) {
        LG_TEST_FAILF(t, "the graph does not fit %zu bytes", sizeof g);
        return -3;
    }
    lg_test_write_text(t, "g.lgraph", g);
    const char *args[] = { "--size", "48x48", NULL };
    char *text = NULL;
    int rc = lg_test_render(t, "g.lgraph", args, &text);
    LG_TEST_CHECK(t, rc == 0, "render failed (%d):\n%s\n%s", rc, g, text ? text : "");
    free(text);
    if (rc)
        return rc;
    for (int k = 0; k < n; k++) {
        char name[32];
        snprintf(name, sizeof name, "out%d.exr", k);
        if (!lg_test_read(t, name, &imgs[k], NULL)) {
            for (int j = 0; j < k; j++)
                lg_image_free(&imgs[j]);
            return -2;
        }
    }
    return 0;
}

static void free_images(lg_image *imgs, int n)
{
    for (int k = 0; k < n; k++)
        lg_image_free(&imgs[k]);
}

/* The segment from p along unit d over [0, dmax] clipped to the box: [*s0, *s1], false when
 * it misses. */
static bool clip_box(const double p[3], const double d[3], double dmax, const double lo[3],
                     const double hi[3], double *s0, double *s1)
{
    double a = 0.0, b = dmax;
    for (int c = 0; c < 3; c++) {
        if (d[c] == 0.0) {
            if (p[c] < lo[c] || p[c] > hi[c])
                return false;
            continue;
        }
        double t0 = (lo[c] - p[c]) / d[c], t1 = (hi[c] - p[c]) / d[c];
        a = fmax(a, fmin(t0, t1));
        b = fmin(b, fmax(t0, t1));
    }
    *s0 = a;
    *s1 = b;
    return a < b;
}

/* The unit direction from p towards the light and its distance. */
static void towards(const mlight *l, const double p[3], double d[3], double *dist)
{
    if (!l->local) {
        double n = sqrt(l->dir[0] * l->dir[0] + l->dir[1] * l->dir[1] + l->dir[2] * l->dir[2]);
        for (int c = 0; c < 3; c++)
            d[c] = -l->dir[c] / n;
        *dist = INFINITY;
        return;
    }
    double n = 0.0;
    for (int c = 0; c < 3; c++) {
        d[c] = l->pos[c] - p[c];
        n += d[c] * d[c];
    }
    n = sqrt(n);
    for (int c = 0; c < 3; c++)
        d[c] /= n;
    *dist = n;
}

enum { EXACT_CHORD, EXACT_HEIGHT, EXACT_MARCH };

/* The exact optical depth (density multiplier integrated) from p towards the light. */
static double exact_tau(const mfield *f, const mlight *l, const double p[3], int how, double a,
                        double b)
{
    double d[3], dist, s0, s1;
    towards(l, p, d, &dist);
    if (!clip_box(p, d, dist, f->lo, f->hi, &s0, &s1))
        return 0.0;
    if (how == EXACT_CHORD)
        return s1 - s0;
    if (how == EXACT_HEIGHT) {
        double h0 = exp(-a * (p[1] - b));
        if (fabs(d[1]) < 1e-12)
            return h0 * (s1 - s0);
        return h0 * (exp(-a * d[1] * s0) - exp(-a * d[1] * s1)) / (a * d[1]);
    }
    const int steps = 1000;
    double h = (s1 - s0) / steps, tau = 0.0;
    for (int i = 0; i < steps; i++) {
        double q[3];
        for (int c = 0; c < 3; c++)
            q[c] = p[c] + d[c] * (s0 + h * (i + 0.5));
        tau += lg_medium_field_at(&f->medium, q) * h;
    }
    return tau;
}

typedef struct cmp_result {
    double max_err, mean_err;  /* |T - T_exact| over the compared pixels and channels */
    int compared, shadowed;    /* pixels; of them with T_exact < 0.9 in some channel */
    int outside, outside_same; /* pixels whose segment misses the box; of them bit-equal */
    int nonfinite;
} cmp_result;

/* img / ref against the exact T over every pixel where ref is lit (> 1e-3). */
static cmp_result compare(const mfield *f, const mlight *l, const lg_image *img,
                          const lg_image *ref, int how, double a, double b)
{
    cmp_result r = { 0 };
    double sum = 0.0;
    for (uint32_t y = 0; y < H; y++)
        for (uint32_t x = 0; x < W; x++) {
            const float *g = img->pixels + ((size_t)y * W + x) * 4;
            const float *q = ref->pixels + ((size_t)y * W + x) * 4;
            if (!isfinite(g[0]) || !isfinite(g[1]) || !isfinite(g[2])) {
                r.nonfinite++;
                continue;
            }
            if (!(q[0] > 1e-3f && q[1] > 1e-3f && q[2] > 1e-3f))
                continue;
            double p[3], d[3], dist, s0, s1;
            ground_point(x, y, p);
            towards(l, p, d, &dist);
            if (!clip_box(p, d, dist, f->lo, f->hi, &s0, &s1)) {
                r.outside++;
                r.outside_same += memcmp(g, q, 3 * sizeof *g) == 0;
            }
            double tau = exact_tau(f, l, p, how, a, b);
            bool sh = false;
            for (int c = 0; c < 3; c++) {
                double want = exp(-f->sigma_t[c] * tau), got = (double)g[c] / (double)q[c];
                double e = fabs(got - want);
                r.max_err = fmax(r.max_err, e);
                sum += e;
                sh = sh || want < 0.9;
            }
            r.compared++;
            r.shadowed += sh;
        }
    r.mean_err = r.compared ? sum / (3.0 * r.compared) : 0.0;
    return r;
}

/* Prints and returns the comparison of img (medium_shadows on) with ref (off). */
static cmp_result report(lg_test *t, const mfield *f, const mlight *l, const lg_image *img,
                         const lg_image *ref, int how, double a, double b, const char *extra)
{
    cmp_result r = compare(f, l, img, ref, how, a, b);
    printf("%-28s %-24s T error: max %.5f mean %.6f over %d pixels (%d shadowed, %d outside "
           "the box's shadow, %d of them the same bits)\n",
           l->what, extra ? extra : "", r.max_err, r.mean_err, r.compared, r.shadowed, r.outside,
           r.outside_same);
    LG_TEST_CHECK(t, r.nonfinite == 0, "%s: %d pixels are not finite", l->what, r.nonfinite);
    return r;
}

/* Renders with and without the medium's shadow and compares. */
static cmp_result check_light(lg_test *t, const mfield *f, const mlight *l, int how, double a,
                              double b)
{
    cmp_result r = { .max_err = INFINITY, .mean_err = INFINITY };
    lg_image img[2] = { 0 };
    const char *ph[2] = { "shading = phong", "shading = phong, medium_shadows = false" };
    if (render(t, f, l, ph, 2, img))
        return r;
    r = report(t, f, l, &img[0], &img[1], how, a, b, NULL);
    free_images(img, 2);
    return r;
}

static void box_field(mfield *f, const double lo[3], const double hi[3])
{
    memset(&f->field, 0, sizeof f->field);
    f->field.kind = LG_FIELD_UNIFORM;
    for (int c = 0; c < 3; c++) {
        f->lo[c] = lo[c];
        f->hi[c] = hi[c];
        f->field.bounds_min[c] = (float)lo[c];
        f->field.bounds_max[c] = (float)hi[c];
    }
    memset(&f->medium, 0, sizeof f->medium);
    f->medium.present = true;
    f->medium.density = 1.0f;
    f->medium.field = &f->field;
}

/* scattering [0.8, 1.2, 1.6], absorption [0.2, 0.1, 0]: sigma_t [1, 1.3, 1.6] */
#define FOG_COEFFS "density = 1, scattering = [0.8, 1.2, 1.6], absorption = [0.2, 0.1, 0]"
static const double FOG_SIGMA_T[3] = { 1.0, 1.3, 1.6 };

/* ---- uniform --------------------------------------------------------------------------------- */

static const mlight UNIFORM_LIGHTS[3] = {
    { "directional", "direction = [0.35, -1, 0.2]", 0, { 0.35, -1, 0.2 }, { 0 } },
    { "point (range 10)",
      "type = point, position = [0.3, 2.5, -0.2], range = 10",
      1,
      { 0 },
      { 0.3, 2.5, -0.2 } },
    { "spot (40 / 55 degrees)",
      "type = spot, position = [-0.2, 2.4, 0.3], aim = target, target = [0.1, 0, 0], "
      "inner_cone_deg = 40, outer_cone_deg = 55",
      1,
      { 0 },
      { -0.2, 2.4, 0.3 } },
};

static void uniform_field(mfield *f)
{
    static const double lo[3] = { -0.7, 0.4, -0.6 }, hi[3] = { 0.6, 1.3, 0.5 };
    box_field(f, lo, hi);
    f->params = "fog = medium { scene = ls, " FOG_COEFFS ", field = uniform, "
                "box_min = [-0.7, 0.4, -0.6], box_max = [0.6, 1.3, 0.5] }";
    memcpy(f->sigma_t, FOG_SIGMA_T, sizeof f->sigma_t);
}

static void case_uniform(lg_test *t)
{
    mfield f;
    uniform_field(&f);
    for (int i = 0; i < 3; i++) {
        cmp_result r = check_light(t, &f, &UNIFORM_LIGHTS[i], EXACT_CHORD, 0, 0);
        /* measured: max 0.026 (directional: one pixel where the chord's exit moves from the
         * box's top to its side inside a cell), 8e-5 (point, spot); mean 1e-5 */
        LG_TEST_CHECK(t, r.max_err < 0.04 && r.mean_err < 2e-4,
                      "%s: T against e^(-sigma_t chord): max %g, mean %g", UNIFORM_LIGHTS[i].what,
                      r.max_err, r.mean_err);
        LG_TEST_CHECK(t, r.shadowed > 150 && r.outside > 150,
                      "%s: the image should hold the box's shadow (%d pixels) and points "
                      "outside it (%d)",
                      UNIFORM_LIGHTS[i].what, r.shadowed, r.outside);
        LG_TEST_CHECK(t, r.outside_same == r.outside,
                      "%s: %d of %d points outside the box's shadow differ from the image "
                      "without the medium",
                      UNIFORM_LIGHTS[i].what, r.outside - r.outside_same, r.outside);
    }
    /* every shading mode, in one graph: the shadow's core and the lit ground beyond it (the
     * per-vertex modes evaluate T at the vertices, 0.25 m apart, so only far from the
     * shadow's edge) */
    const mlight *l = &UNIFORM_LIGHTS[0];
    char ph_text[10][96];
    const char *ph[10];
    for (int m = 0; m < 5; m++) {
        snprintf(ph_text[2 * m], sizeof ph_text[0], "shading = %s", MODES[m]);
        snprintf(ph_text[2 * m + 1], sizeof ph_text[0], "shading = %s, medium_shadows = false",
                 MODES[m]);
        ph[2 * m] = ph_text[2 * m];
        ph[2 * m + 1] = ph_text[2 * m + 1];
    }
    lg_image img[10] = { 0 };
    if (render(t, &f, l, ph, 10, img))
        return;
    /* the shadow's core: the box's centre carried along the light onto the plane */
    static const double core[3] = { -0.05 + 0.35 * 0.85, 0, -0.05 + 0.2 * 0.85 };
    static const double lit[3] = { 1.2, 0, 1.2 };
    const double *pts[2] = { core, lit };
    const double half = 3.0 * tan(30.0 * LG_PI / 180.0);
    for (int m = 0; m < 5; m++)
        for (int k = 0; k < 2; k++) {
            uint32_t x = (uint32_t)((pts[k][0] / half + 1.0) * (W / 2.0));
            uint32_t y = (uint32_t)((pts[k][2] / half + 1.0) * (H / 2.0));
            double p[3];
            ground_point(x, y, p);
            double tau = exact_tau(&f, l, p, EXACT_CHORD, 0, 0);
            const float *g = img[2 * m].pixels + ((size_t)y * W + x) * 4;
            const float *q = img[2 * m + 1].pixels + ((size_t)y * W + x) * 4;
            for (int c = 0; c < 3; c++) {
                double want = exp(-f.sigma_t[c] * tau), got = (double)g[c] / (double)q[c];
                LG_TEST_CHECK(t, fabs(got - want) < 0.03 && (k == 1 || want < 0.5),
                              "shading %s, %s point (%u, %u) channel %d: T %g, exact %g", MODES[m],
                              k ? "lit" : "shadowed", x, y, c, got, want);
            }
        }
    free_images(img, 10);
}

/* ---- height ---------------------------------------------------------------------------------- */

static void case_height(lg_test *t)
{
    mfield f;
    static const double lo[3] = { -1.8, 0.0, -1.8 }, hi[3] = { 1.8, 1.6, 1.8 };
    box_field(&f, lo, hi);
    f.field.height_falloff = 1.2f;
    f.field.height_base = 0.0f;
    f.params = "fog = medium { scene = ls, " FOG_COEFFS ", field = uniform, height_falloff = 1.2, "
               "height_base = 0, box_min = [-1.8, 0, -1.8], box_max = [1.8, 1.6, 1.8] }";
    memcpy(f.sigma_t, FOG_SIGMA_T, sizeof f.sigma_t);
    static const mlight lights[3] = {
        { "directional", "direction = [-0.5, -1, 0.3]", 0, { -0.5, -1, 0.3 }, { 0 } },
        { "point inside the box",
          "type = point, position = [0.2, 0.9, -0.1]",
          1,
          { 0 },
          { 0.2, 0.9, -0.1 } },
        { "spot inside the box",
          "type = spot, position = [-0.3, 1.2, 0.2], aim = target, target = [0.2, 0, -0.1], "
          "inner_cone_deg = 45, outer_cone_deg = 60",
          1,
          { 0 },
          { -0.3, 1.2, 0.2 } },
    };
    for (int i = 0; i < 3; i++) {
        cmp_result r = check_light(t, &f, &lights[i], EXACT_HEIGHT, 1.2, 0.0);
        /* measured: max 0.023, mean 2.3e-4 (directional: the chord's exit moving from the
         * top to a side inside a cell), max 3e-4, mean 6e-5 (the lights inside the box) */
        LG_TEST_CHECK(t, r.max_err < 0.035 && r.mean_err < 4e-4,
                      "%s: T against the closed form of the height fog: max %g, mean %g",
                      lights[i].what, r.max_err, r.mean_err);
        LG_TEST_CHECK(t, r.shadowed > 300, "%s: only %d pixels are attenuated", lights[i].what,
                      r.shadowed);
    }
}

/* ---- fbm ------------------------------------------------------------------------------------- */

static void case_fbm(lg_test *t)
{
    mfield f;
    static const double lo[3] = { -1.0, 0.2, -1.0 }, hi[3] = { 1.0, 1.2, 1.0 };
    box_field(&f, lo, hi);
    f.field.kind = LG_FIELD_FBM;
    f.field.fbm = (lg_density_fbm){ .octaves = 4,
                                    .seed = 3,
                                    .frequency = 1.5f,
                                    .lacunarity = 2.0f,
                                    .gain = 0.5f,
                                    .offset = 0.05f,
                                    .scale = 3.0f };
    f.params = "fog = medium { scene = ls, " FOG_COEFFS ", field = fbm, octaves = 4, seed = 3, "
               "frequency = 1.5, lacunarity = 2, gain = 0.5, offset = 0.05, scale = 3, "
               "box_min = [-1, 0.2, -1], box_max = [1, 1.2, 1] }";
    memcpy(f.sigma_t, FOG_SIGMA_T, sizeof f.sigma_t);
    static const mlight lights[2] = {
        { "directional", "direction = [0.3, -1, -0.25]", 0, { 0.3, -1, -0.25 }, { 0 } },
        { "spot (50 / 70 degrees)",
          "type = spot, position = [0.1, 2.8, 0.2], aim = target, target = [0, 0, 0], "
          "inner_cone_deg = 50, outer_cone_deg = 70",
          1,
          { 0 },
          { 0.1, 2.8, 0.2 } },
    };
    /* measured at medium_shadow_res 64: max 0.032, mean 0.0014 (directional), max 0.031,
     * mean 0.0018 (spot): the noise's finest octave (12 / m) is finer than a cell (3 cm) */
    cmp_result r = check_light(t, &f, &lights[1], EXACT_MARCH, 0, 0);
    LG_TEST_CHECK(t, r.max_err < 0.05 && r.mean_err < 0.003,
                  "%s: T against a double march of the fBm: max %g, mean %g", lights[1].what,
                  r.max_err, r.mean_err);
    LG_TEST_CHECK(t, r.shadowed > 300, "%s: only %d pixels are attenuated", lights[1].what,
                  r.shadowed);
    /* the directional light at three resolutions in one graph: the resolution is the knob,
     * the error falls as it grows (measured means 0.0145, 0.0047, 0.0014) */
    double mean[3];
    const char *ph[4] = { "medium_shadow_res = 16", "medium_shadow_res = 32",
                          "medium_shadow_res = 64", "medium_shadows = false" };
    lg_image img[4] = { 0 };
    if (render(t, &f, &lights[0], ph, 4, img))
        return;
    for (int k = 0; k < 3; k++) {
        r = report(t, &f, &lights[0], &img[k], &img[3], EXACT_MARCH, 0, 0, ph[k]);
        mean[k] = r.mean_err;
    }
    free_images(img, 4);
    LG_TEST_CHECK(t, r.max_err < 0.05 && r.mean_err < 0.003,
                  "%s at 64: T against a double march of the fBm: max %g, mean %g", lights[0].what,
                  r.max_err, r.mean_err);
    LG_TEST_CHECK(t, r.shadowed > 300, "%s: only %d pixels are attenuated", lights[0].what,
                  r.shadowed);
    LG_TEST_CHECK(t, mean[0] > 1.5 * mean[1] && mean[1] > 1.5 * mean[2],
                  "the error should fall with medium_shadow_res: %g (16), %g (32), %g (64)",
                  mean[0], mean[1], mean[2]);
}

/* ---- grazing --------------------------------------------------------------------------------- */

static void case_grazing(lg_test *t)
{
    mfield f;
    static const double lo[3] = { -0.5, 0.0, -0.5 }, hi[3] = { 0.5, 0.5, 0.5 };
    box_field(&f, lo, hi);
    f.params = "fog = medium { scene = ls, " FOG_COEFFS ", field = uniform, "
               "box_min = [-0.5, 0, -0.5], box_max = [0.5, 0.5, 0.5] }";
    memcpy(f.sigma_t, FOG_SIGMA_T, sizeof f.sigma_t);
    /* 1.7 degrees above the horizon, travelling towards -x: the box's shadow runs from its
     * foot out of the image towards -x */
    static const mlight l = {
        "directional, 1.7 degrees", "direction = [-1, -0.03, 0.2]", 0, { -1, -0.03, 0.2 }, { 0 }
    };
    cmp_result r = check_light(t, &f, &l, EXACT_CHORD, 0, 0);
    /* measured: max 0.0068, mean 9e-6 */
    LG_TEST_CHECK(t, r.max_err < 0.015 && r.mean_err < 1e-4,
                  "grazing: T against e^(-sigma_t chord): max %g, mean %g", r.max_err, r.mean_err);
    LG_TEST_CHECK(t, r.shadowed > 200 && r.outside_same == r.outside,
                  "grazing: %d shadowed pixels; %d of %d outside differ", r.shadowed,
                  r.outside - r.outside_same, r.outside);
}

/* ---- gating ---------------------------------------------------------------------------------- */

static void case_gating(lg_test *t)
{
    const mlight *l = &UNIFORM_LIGHTS[2];
    mfield homog = { .params = "fog = medium { scene = ls, " FOG_COEFFS " }" };
    mfield field;
    uniform_field(&field);
    mfield zero = { .params = "fog = medium { scene = ls, " FOG_COEFFS ", field = fbm, "
                              "offset = 8, box_min = [-1, 0, -1], box_max = [1, 1, 1] }" };
    /* the four in one graph would share one medium node: four graphs */
    lg_image none = { 0 }, img = { 0 };
    const char *plain = "shading = phong";
    if (render(t, NULL, l, &plain, 1, &none))
        return;
    struct {
        const mfield *f;
        const char *phong, *what;
    } runs[3] = {
        { &homog, "shading = phong", "a homogeneous medium" },
        { &field, "shading = phong, medium_shadows = false", "a field, medium_shadows = false" },
        { &zero, "shading = phong", "a field of zero density" },
    };
    for (int k = 0; k < 3; k++) {
        if (render(t, runs[k].f, l, &runs[k].phong, 1, &img))
            break;
        size_t diff = 0;
        for (size_t i = 0; i < (size_t)W * H * 4; i++)
            diff += memcmp(&img.pixels[i], &none.pixels[i], sizeof(float)) != 0;
        LG_TEST_CHECK(t, diff == 0, "%s: %zu channels differ from the image without a medium",
                      runs[k].what, diff);
        lg_image_free(&img);
    }
    lg_image_free(&none);
}

static void setup(lg_test *t)
{
    lg_test_use_plugins(t, PH_TEST_PLUGIN_DIR);
    lg_test_require_backend(t, "gl");
}

int main(int argc, char **argv)
{
    static const lg_test_case cases[] = {
        { "uniform", case_uniform }, { "height", case_height }, { "fbm", case_fbm },
        { "grazing", case_grazing }, { "gating", case_gating },
    };
    lg_test_main_opts o = { .setup = setup };
    return lg_test_main(argc, argv, cases, sizeof cases / sizeof cases[0], &o);
}
