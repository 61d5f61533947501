/*
 * The volumetric_polygonal node through the host (GL: a missing device fails), on scenes
 * built in memory by the test plugin testphongscene (tests/plugins/phong) and derived with
 * scene_tools' light and medium nodes. Every expected value is computed here from the scene's
 * numbers with lightgraph/medium.h, and every view ray from the camera's own definition
 * (look_at, vertical field of view, image row 0 at the top: vol_common.h), not from the
 * node. `test_polygonal CASE`:
 *
 *   closed_form   a plane (no other occluder), one light from above, from behind the camera
 *                 or from in front of it, the camera inside the lit volume, and one with the
 *                 camera outside the shadow map's frustum (the box beyond the tile is lit,
 *                 as vol_shadow_cpu has it): inscatter = L_c sigma_s p d seg(sigma_t d)
 *                 (lg_medium_inscatter) at every pixel, d = min(plane distance, z_limit /
 *                 cos) computed here; out = base e^(-sigma_t d) + inscatter
 *   balance       the generated meshes read back (mesh_file, a PLY) and intersected with
 *                 random rays here: #back - #front crossings is 1 from points in the lit fog
 *                 (the eye among them) and 0 from points in a shadow, on every ray
 *   shaft         a quad above the plane casts a shaft: against a ray-marched oracle with
 *                 exact visibility (the quad and the plane as occluders), relative RMSE below
 *                 4 % (8 % at resolution 32), and the in-scatter through the shaft drops as
 *                 the oracle's does; the fp32 accumulation against the same signed sum in
 *                 double on the mesh read back (the cancellation of the +-F terms)
 *   inside_shadow the camera under the quad, inside the shadow shaft, looking out (rays
 *                 start outside the lit volume; near-plane clipping of the shaft's walls)
 *   outside       the shaft seen from outside through a `camera` node whose near plane lies
 *                 beyond the shaft's near wall: the fog before znear counts (the oracle)
 *   outside_box   the examples' bunny box, the camera outside it (behind, beside its own
 *                 shadow; in front of the opening, the sun behind the camera), against
 *                 volumetric_reference: relative RMSE of inscatter below 2e-3
 *   lights32      32 lights of known directions and colours on the plane: the sum of the 32
 *                 closed forms; the node's profile memory grows by exactly one vertex buffer
 *                 per light (1, 2, 4, 8 lights, --profile-json)
 *   gating        fog density 0: the node is gated (its plugin not loaded), out = base
 *   mesh_file     the PLY goes through the host's outputs (LG_ROLE_OUTPUT_FILE): a FIFO, or
 *                 a link to one, is refused before anything runs and left as it was; a
 *                 failure later in the render (a node after vol that fails) and a gated
 *                 node leave no mesh and no temporary; success writes it
 *   errors        no shadows input, resolution = 1, z_limit before the near plane, a base
 *                 without depth, 33 lights: exit status != 0 and a message naming the node
 *                 and the value
 *   counters      the node's `volume pass:` line (-v; GL query objects around its draws)
 *                 against the mesh read back (mesh_file): the triangles drawn and generated
 *                 are the PLY's, and the fragments are the crossings of every pixel centre's
 *                 ray with the mesh counted here (Moller-Trumbore in double), on the plane
 *                 (every ray leaves the lit volume: at least one fragment a pixel) and with
 *                 the quad's shaft (rays crossing its walls too), 1 and 2 lights
 *
 * Point and spot lights (issue 25), their perspective maps written by hand by the test
 * plugin testpolyshadow (this folder) or none (the shadowmap node, gated); every value
 * against lg_point_inscatter in C at the pixel's ray, at the node's 8 nodes (within 2e-3
 * per pixel; the RMSE against 64 nodes, the rule's own error, is printed):
 *   point_closed      an unshadowed point light: six empty cube faces (their shared walls
 *                     cancel), the floor in the maps, no map (one viewport triangle)
 *   spot_cone         a spot seen from outside its cone, with its map and without
 *   point_occluder    a point light over the quad: against a march with exact visibility
 *                     (relative RMSE 1.5e-3, and 10x below the shadow's own weight); the six
 *                     meshes read back: one more exit than entry from random points in the
 *                     lit fog, as many in the shadow
 *   point_inside_cone the camera inside a spot's cone (no entry term), at a point light and
 *                     at a spot light (the faces through the light edge-on: dropped)
 *   point_range       range 0 (infinite), 2.5 (cuts the glow), 0.02 (black), a spot's 2.8
 *   point_errors      dual-paraboloid, off-centre and one-record maps, point_nodes 9, a
 *                     heterogeneous medium (test_poly_field_scene): refused, naming the node
 *   point_reference   against volumetric_reference (subpixel = centre) on a point light
 *                     over the quad (1e-3); skipped while the reference refuses point lights
 */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <dirent.h>
#include <sys/stat.h>
#include <unistd.h>

#include "lightgraph/image.h"
#include "lightgraph/medium.h"
#include "lightgraph/test.h"
#include "lightgraph/vecmath.h"

#define W 64
#define H 48

typedef struct cam {
    double eye[3], target[3], up[3], fov_deg;
    double f[3], r[3], u[3];
    double znear; /* > 0: the near plane of a `camera` node (no surface before it in base) */
} cam;

static void v3_norm(double v[3])
{
    double l = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    for (int i = 0; i < 3; i++)
        v[i] /= l;
}
static void v3_cross(const double a[3], const double b[3], double o[3])
{
    o[0] = a[1] * b[2] - a[2] * b[1];
    o[1] = a[2] * b[0] - a[0] * b[2];
    o[2] = a[0] * b[1] - a[1] * b[0];
}
static double v3_dot(const double a[3], const double b[3])
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

static void cam_init(cam *c)
{
    for (int i = 0; i < 3; i++)
        c->f[i] = c->target[i] - c->eye[i];
    v3_norm(c->f);
    v3_cross(c->f, c->up, c->r);
    v3_norm(c->r);
    v3_cross(c->r, c->f, c->u);
}

/* The unit ray through pixel (x, y) (row 0 at the top). */
static void cam_ray(const cam *c, double x, double y, double w[3])
{
    double t = tan(c->fov_deg * LG_PI / 360.0), a = (double)W / H;
    double nx = 2.0 * (x + 0.5) / W - 1.0, ny = 1.0 - 2.0 * (y + 0.5) / H;
    for (int i = 0; i < 3; i++)
        w[i] = c->f[i] + nx * t * a * c->r[i] + ny * t * c->u[i];
    v3_norm(w);
}

/* An axis-aligned square at height y0, half side h, centred on the Y axis. */
typedef struct quad {
    double y0, h;
} quad;

/* Distance along the ray to the square, or INFINITY. */
static double quad_hit(const quad *q, const double e[3], const double w[3])
{
    if (w[1] == 0.0)
        return INFINITY;
    double t = (q->y0 - e[1]) / w[1];
    if (!(t > 0.0))
        return INFINITY;
    double x = e[0] + t * w[0], z = e[2] + t * w[2];
    return fabs(x) <= q->h && fabs(z) <= q->h ? t : INFINITY;
}

typedef struct fog {
    double sigma_s[3], sigma_t[3], g, z_limit;
} fog;

typedef struct light {
    double dir[3]; /* unit: the direction the light travels */
    double l_c[3];
} light;

/* The fog's length along the pixel's ray: min(first hit of `quads`, z_limit / cos). A
 * surface before the camera's near plane is not in base (phong clips it): the ray goes on
 * to the next (it still casts its shadow). */
static double fog_length(const cam *c, const fog *m, const quad *quads, int nq, const double w[3])
{
    double cs = v3_dot(w, c->f), d = m->z_limit / cs;
    for (int k = 0; k < nq; k++) {
        double t = quad_hit(&quads[k], c->eye, w);
        if (t * cs >= c->znear)
            d = t < d ? t : d;
    }
    return d;
}

/* The in-scatter of an unshadowed segment [0, s] (lightgraph/medium.h), channel ch. */
static double closed(const fog *m, const light *l, const double w[3], int ch, double s)
{
    double mw[3] = { -l->dir[0], -l->dir[1], -l->dir[2] };
    double p = lg_hg_phase(m->g, v3_dot(w, mw));
    return lg_medium_inscatter(l->l_c[ch], m->sigma_s[ch], m->sigma_t[ch], p, s);
}

/* Oracle with exact visibility: [0, d] cut in `steps` pieces, each lit or not at its middle
 * (a point is shadowed when the ray from it towards the light hits a quad), each adding
 * the exact closed-form increment of its piece. */
static double marched(const fog *m, const light *l, const quad *quads, int nq, const double e[3],
                      const double w[3], int ch, double d, int steps)
{
    double sum = 0.0, back[3] = { -l->dir[0], -l->dir[1], -l->dir[2] };
    for (int i = 0; i < steps; i++) {
        double t0 = d * i / steps, t1 = d * (i + 1) / steps, tm = 0.5 * (t0 + t1), p[3];
        for (int k = 0; k < 3; k++)
            p[k] = e[k] + tm * w[k];
        bool lit = true;
        for (int q = 0; q < nq && lit; q++)
            lit = !isfinite(quad_hit(&quads[q], p, back));
        if (lit)
            sum += closed(m, l, w, ch, t1) - closed(m, l, w, ch, t0);
    }
    return sum;
}

/* ---- graphs ---------------------------------------------------------------------------------- */

/* The scene part: s (testphongscene), the lights chained to `ls`, `fog`, `shadow`, `lit`. */
static void graph(char *g, size_t cap, const char *layout, const cam *c, const light *lights,
                  int nl, const fog *m, double density, int sm_res, const char *vol_params,
                  bool shadows)
{
    int k = snprintf(g, cap,
                     "lightgraph 1\n"
                     "s = test_phong_scene { layout = %s, size = 10, double_sided = true, "
                     "ka = 0.1, "
                     "camera_position = [%.17g, %.17g, %.17g], camera_target = [%.17g, %.17g, "
                     "%.17g], camera_up = [%.17g, %.17g, %.17g], yfov_deg = %.17g }\n",
                     layout, c->eye[0], c->eye[1], c->eye[2], c->target[0], c->target[1],
                     c->target[2], c->up[0], c->up[1], c->up[2], c->fov_deg);
    for (int i = 0; i < nl; i++) {
        const light *l = &lights[i];
        double in = fmax(l->l_c[0], fmax(l->l_c[1], l->l_c[2]));
        char prev[16];
        snprintf(prev, sizeof prev, i ? "l%d" : "s", i - 1);
        k += snprintf(g + k, cap - (size_t)k,
                      "l%d = light { scene = %s, direction = [%.17g, %.17g, %.17g], color = "
                      "[%.17g, %.17g, %.17g], intensity = %.17g }\n",
                      i, prev, l->dir[0], l->dir[1], l->dir[2], l->l_c[0] / in, l->l_c[1] / in,
                      l->l_c[2] / in, in);
    }
    /* the scattering and absorption of density 1; the node gets density separately */
    k += snprintf(g + k, cap - (size_t)k,
                  "fog = medium { scene = l%d, density = %.17g, scattering = [%.17g, %.17g, "
                  "%.17g], absorption = [%.17g, %.17g, %.17g], g = %.17g }\n"
                  "shadow = shadowmap { scene = fog, resolution = %d }\n"
                  "lit = phong { scene = fog, shadows = shadow }\n"
                  "vol = volumetric_polygonal { scene = fog, base = lit%s, z_limit = %.17g%s%s }\n"
                  "output vol.inscatter \"ins.exr\"\n"
                  "output vol \"out.exr\"\n"
                  "output lit \"lit.exr\"\n",
                  nl - 1, density, m->sigma_s[0], m->sigma_s[1], m->sigma_s[2],
                  m->sigma_t[0] - m->sigma_s[0], m->sigma_t[1] - m->sigma_s[1],
                  m->sigma_t[2] - m->sigma_s[2], m->g, sm_res, shadows ? ", shadows = shadow" : "",
                  m->z_limit, vol_params[0] ? ", " : "", vol_params);
}

static int render(lg_test *t, const char *g, const char *const *extra, char **text)
{
    lg_test_write_text(t, "g.lgraph", g);
    const char *args[12] = { "--size", "64x48" };
    int na = 2;
    for (int i = 0; extra && extra[i] && na < 11; i++)
        args[na++] = extra[i];
    args[na] = NULL;
    return lg_test_render(t, "g.lgraph", args, text);
}

static const fog default_fog = {
    .sigma_s = { 0.1, 0.2, 0.3 }, .sigma_t = { 0.15, 0.25, 0.35 }, .g = 0.4, .z_limit = 8
};

/* Renders the plane with `lights` and checks inscatter against the sum of closed forms and
 * out against base e^(-sigma_t d) + inscatter. Returns the largest relative error. */
static double check_closed(lg_test *t, const char *what, const cam *c, const light *lights, int nl,
                           const char *vol_params, int sm_res)
{
    const fog *m = &default_fog;
    char g[16384];
    graph(g, sizeof g, "plane", c, lights, nl, m, 1.0, sm_res, vol_params, true);
    char *text = NULL;
    int rc = render(t, g, NULL, &text);
    free(text);
    LG_TEST_CHECK(t, rc == 0, "%s: render failed (%d)", what, rc);
    if (rc)
        return INFINITY;
    lg_image ins, out, lit;
    if (!lg_test_read(t, "ins.exr", &ins, NULL) || !lg_test_read(t, "out.exr", &out, NULL) ||
        !lg_test_read(t, "lit.exr", &lit, NULL))
        return INFINITY;
    quad plane = { 0.0, 5.0 };
    double worst = 0.0, worst_out = 0.0;
    uint64_t over = 0;
    int wx = 0, wy = 0;
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++) {
            double w[3];
            cam_ray(c, x, y, w);
            double d = fog_length(c, m, &plane, 1, w);
            for (int ch = 0; ch < 3; ch++) {
                double want = 0.0;
                for (int l = 0; l < nl; l++)
                    want += closed(m, &lights[l], w, ch, d);
                size_t i = ((size_t)y * W + x) * 4 + ch;
                double got = ins.pixels[i];
                double rel = fabs(got - want) / want;
                if (rel > worst) {
                    worst = rel;
                    wx = x, wy = y;
                }
                /* fp32: the shaders' F and the exp differ from the double closed form by
                 * a few ulp; d from the depth buffer by ~1e-5 relative */
                if (!(rel <= 1e-4))
                    over++;
                double T = exp(-m->sigma_t[ch] * d);
                double want_out = lit.pixels[i] * T + got;
                double e = fabs(out.pixels[i] - want_out) / (fabs(want_out) + 1e-6);
                worst_out = e > worst_out ? e : worst_out;
            }
        }
    fprintf(stderr, "%s: inscatter max relative error %.3g at (%d, %d); out %.3g\n", what, worst,
            wx, wy, worst_out);
    LG_TEST_CHECK(t, over == 0, "%s: %llu values beyond 1e-4 relative (worst %.3g at %d, %d)", what,
                  (unsigned long long)over, worst, wx, wy);
    LG_TEST_CHECK(t, worst_out < 1e-3, "%s: out differs from base T + inscatter by %.3g", what,
                  worst_out);
    lg_image_free(&ins);
    lg_image_free(&out);
    lg_image_free(&lit);
    return worst;
}

static light mk_light(double dx, double dy, double dz, double r, double g, double b)
{
    light l = { { dx, dy, dz }, { r, g, b } };
    v3_norm(l.dir);
    return l;
}

static void case_closed_form(lg_test *t)
{
    cam c = { .eye = { 0, 2, 6 }, .target = { 0, 0, 0 }, .up = { 0, 1, 0 }, .fov_deg = 40 };
    cam_init(&c);
    /* from above; from behind the camera (the camera looks along -Z, this light travels
     * along -Z too); from in front of it, low, towards the camera (g = 0.4 brightens) */
    light above = mk_light(0.3, -1, 0.2, 5, 5, 5);
    light behind = mk_light(0.2, -0.5, -1, 3, 4, 5);
    light front = mk_light(-0.1, -0.4, 1, 6, 5, 4);
    check_closed(t, "light above", &c, &above, 1, "", 64);
    check_closed(t, "light behind the camera", &c, &behind, 1, "", 64);
    check_closed(t, "light in front", &c, &front, 1, "resolution = 16", 64);
    check_closed(t, "one vertex per texel", &c, &front, 1, "resolution = 0", 128);
    /* the camera far outside the shadow map's frustum (the map fits the plane, 10 x 10):
     * the fog around it is lit all the same */
    cam far = { .eye = { 0, 3, 14 }, .target = { 0, 0, 4 }, .up = { 0, 1, 0 }, .fov_deg = 30 };
    cam_init(&far);
    check_closed(t, "camera outside the light's frustum", &far, &above, 1, "", 64);
}

/* ---- balance: the PLY read back -------------------------------------------------------------- */

typedef struct mesh {
    float *v;
    int32_t *tri;
    uint64_t nv, nt;
} mesh;

static bool read_ply(lg_test *t, const char *rel, mesh *m)
{
    memset(m, 0, sizeof *m);
    FILE *f = fopen(lg_test_path(t, rel), "rb");
    LG_TEST_CHECK(t, f != NULL, "cannot open %s", rel);
    if (!f)
        return false;
    char line[512];
    bool ok = fgets(line, sizeof line, f) && strcmp(line, "ply\n") == 0;
    while (ok && fgets(line, sizeof line, f)) {
        unsigned long long n;
        if (sscanf(line, "element vertex %llu", &n) == 1)
            m->nv = n;
        else if (sscanf(line, "element face %llu", &n) == 1)
            m->nt = n;
        else if (strcmp(line, "end_header\n") == 0)
            break;
    }
    ok = ok && m->nv && m->nt;
    if (ok) {
        m->v = malloc(m->nv * 12);
        m->tri = malloc(m->nt * 12);
        ok = m->v && m->tri && fread(m->v, 12, m->nv, f) == m->nv;
        for (uint64_t i = 0; ok && i < m->nt; i++) {
            unsigned char cnt;
            ok = fread(&cnt, 1, 1, f) == 1 && cnt == 3 && fread(m->tri + 3 * i, 4, 3, f) == 3;
            for (int k = 0; ok && k < 3; k++)
                ok = m->tri[3 * i + k] >= 0 && (uint64_t)m->tri[3 * i + k] < m->nv;
        }
    }
    fclose(f);
    LG_TEST_CHECK(t, ok, "%s is not the PLY the node documents", rel);
    return ok;
}

/* Triangle i against the ray (o, w) (Moller-Trumbore in double): 0 when it misses or is hit
 * at s <= 0; else the hit's distance *s and +1 if the ray leaves through it (back face, its
 * normal along w), -1 if it enters. */
static int hit(const mesh *m, uint64_t i, const double o[3], const double w[3], double *s)
{
    double a[3], b[3], c[3];
    for (int k = 0; k < 3; k++) {
        a[k] = m->v[3 * m->tri[3 * i] + k];
        b[k] = m->v[3 * m->tri[3 * i + 1] + k];
        c[k] = m->v[3 * m->tri[3 * i + 2] + k];
    }
    double e1[3], e2[3], sv[3], p[3], q[3], n[3];
    for (int k = 0; k < 3; k++) {
        e1[k] = b[k] - a[k];
        e2[k] = c[k] - a[k];
        sv[k] = o[k] - a[k];
    }
    v3_cross(w, e2, p);
    double det = v3_dot(e1, p);
    if (det == 0.0)
        return 0;
    double u = v3_dot(sv, p) / det;
    if (u < 0.0 || u > 1.0)
        return 0;
    v3_cross(sv, e1, q);
    double v = v3_dot(w, q) / det;
    if (v < 0.0 || u + v > 1.0)
        return 0;
    *s = v3_dot(e2, q) / det;
    if (*s <= 0.0)
        return 0;
    v3_cross(e1, e2, n);
    return v3_dot(n, w) > 0.0 ? 1 : -1;
}

/* #back - #front crossings of the ray (o, w) with the mesh. */
static int crossings(const mesh *m, const double o[3], const double w[3])
{
    int sum = 0;
    double s;
    for (uint64_t i = 0; i < m->nt; i++)
        sum += hit(m, i, o, w, &s);
    return sum;
}

/* The signed sum the node accumulates, in double: every crossing of the ray (o, w) with the
 * mesh at s > 0 adds +-F(min(s, d)) (+ leaving); *abs_sum gets the sum of |F|. */
static double crossing_sum(const mesh *m, const fog *f, const light *l, const double o[3],
                           const double w[3], int ch, double d, double *abs_sum)
{
    double sum = 0.0, sa = 0.0, s;
    for (uint64_t i = 0; i < m->nt; i++) {
        int sign = hit(m, i, o, w, &s);
        if (!sign)
            continue;
        double F = closed(f, l, w, ch, s < d ? s : d);
        sum += sign * F;
        sa += F;
    }
    *abs_sum = sa;
    return sum;
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

static uint64_t rng_state = 0x9e3779b97f4a7c15ull;
static double rnd(void)
{
    rng_state ^= rng_state << 13;
    rng_state ^= rng_state >> 7;
    rng_state ^= rng_state << 17;
    return (double)(rng_state >> 11) / 9007199254740992.0;
}

static void case_balance(lg_test *t)
{
    cam c = { .eye = { 2.5, 1.6, 3.5 }, .target = { 0, 0.5, 0 }, .up = { 0, 1, 0 }, .fov_deg = 50 };
    cam_init(&c);
    light l[2] = { mk_light(0.2, -1, 0.1, 5, 5, 5), mk_light(-0.5, -1, 0.3, 2, 2, 2) };
    fog m = default_fog;
    char g[16384];
    graph(g, sizeof g, "shadow", &c, l, 2, &m, 1.0, 64, "mesh_file = \"mesh.ply\"", true);
    int rc = render(t, g, NULL, NULL);
    LG_TEST_CHECK(t, rc == 0, "render failed (%d)", rc);
    if (rc)
        return;
    mesh all;
    if (!read_ply(t, "mesh.ply", &all))
        return;
    /* two lights: the first half of the vertices and triangles is light 0's */
    mesh one[2] = { { all.v, all.tri, all.nv / 2, all.nt / 2 },
                    { all.v, all.tri + 3 * (all.nt / 2), all.nv, all.nt / 2 } };
    LG_TEST_CHECK(t, all.nv % 2 == 0 && all.nt % 2 == 0, "odd counts %llu %llu",
                  (unsigned long long)all.nv, (unsigned long long)all.nt);
    /* start points: the eye and a point in open fog (lit: 1); under the quad, in its
     * shadow for both lights (0); under the plane, in its shadow (0) */
    struct {
        double p[3];
        int want[2];
        const char *what;
    } starts[] = {
        { { c.eye[0], c.eye[1], c.eye[2] }, { 1, 1 }, "the eye" },
        { { -3, 2.5, 1 }, { 1, 1 }, "open fog" },
        { { 0.05, 0.5, 0.0 }, { 0, 0 }, "under the quad" },
        { { 0.5, -0.7, 0.5 }, { 0, 0 }, "under the plane" },
    };
    int bad = 0, rays = 0;
    for (int li = 0; li < 2; li++)
        for (size_t s = 0; s < sizeof starts / sizeof starts[0]; s++)
            for (int r = 0; r < 300; r++) {
                double w[3], z = 2 * rnd() - 1, ph = 2 * LG_PI * rnd();
                double sr = sqrt(1 - z * z);
                w[0] = sr * cos(ph), w[1] = sr * sin(ph), w[2] = z;
                int got = crossings(&one[li], starts[s].p, w);
                rays++;
                if (got != starts[s].want[li]) {
                    if (bad++ < 5)
                        fprintf(stderr,
                                "light %d, from %s, ray (%g %g %g): #back - #front = %d, "
                                "want %d\n",
                                li, starts[s].what, w[0], w[1], w[2], got, starts[s].want[li]);
                }
            }
    /* random points in and around the fog: every ray from one point gives the same count,
     * 0 or 1 */
    int incons = 0, points = 0;
    for (int li = 0; li < 2; li++)
        for (int s = 0; s < 150; s++) {
            double p[3] = { 8 * rnd() - 4, 3.5 * rnd() - 1, 8 * rnd() - 4 };
            int first = -99;
            points++;
            for (int r = 0; r < 6; r++) {
                double w[3], z = 2 * rnd() - 1, ph = 2 * LG_PI * rnd();
                double sr = sqrt(1 - z * z);
                w[0] = sr * cos(ph), w[1] = sr * sin(ph), w[2] = z;
                int got = crossings(&one[li], p, w);
                rays++;
                if (first == -99)
                    first = got;
                if (got != first || (got != 0 && got != 1)) {
                    if (incons++ < 5)
                        fprintf(stderr, "light %d, from (%g %g %g): #back - #front = %d and %d\n",
                                li, p[0], p[1], p[2], first, got);
                    break;
                }
            }
        }
    LG_TEST_CHECK(t, incons == 0, "%d of %d random points see unbalanced crossings", incons,
                  points);
    fprintf(stderr, "balance: %d of %d rays wrong\n", bad + incons, rays);
    LG_TEST_CHECK(t, bad == 0, "%d of %d rays cross the mesh unbalanced", bad, rays);
    free(all.v);
    free(all.tri);
}

/* ---- the shaft ------------------------------------------------------------------------------- */

/* The graph of check_shaft with the camera made again by scene_tools' `camera` node
 * between the scene and its light, with explicit near and far planes (the same eye, target,
 * up and field of view as the scene's: cam_ray stays the camera's definition). */
static bool with_camera_node(char *g, size_t cap, const cam *c, double znear, double zfar)
{
    const char *at = strstr(g, "l0 = light { scene = s,");
    if (!at)
        return false;
    size_t head = (size_t)(at - g);
    char *rest = strdup(at + strlen("l0 = light { scene = s,"));
    if (!rest)
        return false;
    int len =
        snprintf(g + head, cap - head,
                 "oc = camera { scene = s, mode = look_at, position = [%.17g, %.17g, %.17g], "
                 "target = [%.17g, %.17g, %.17g], up = [%.17g, %.17g, %.17g], fov_deg = %.17g, "
                 "znear = %.17g, zfar = %.17g }\n"
                 "l0 = light { scene = oc,%s",
                 c->eye[0], c->eye[1], c->eye[2], c->target[0], c->target[1], c->target[2],
                 c->up[0], c->up[1], c->up[2], c->fov_deg, znear, zfar, rest);
    free(rest);
    return len > 0 && (size_t)len < cap - head;
}

/* c->znear > 0: the camera through a `camera` node with that near plane (zfar 50). */
static void check_shaft(lg_test *t, const char *what, const cam *c, const light *l,
                        const char *vol_params, const char *ply, double max_rel_rmse)
{
    fog m = default_fog;
    m.z_limit = 7;
    char g[16384];
    graph(g, sizeof g, "shadow", c, l, 1, &m, 1.0, 256, vol_params, true);
    if (c->znear > 0.0 && !with_camera_node(g, sizeof g, c, c->znear, 50.0)) {
        LG_TEST_CHECK(t, false,
                      "%s: the graph has no light line to put the camera node "
                      "before (or it outgrew its buffer)",
                      what);
        return;
    }
    int rc = render(t, g, NULL, NULL);
    LG_TEST_CHECK(t, rc == 0, "%s: render failed (%d)", what, rc);
    if (rc)
        return;
    lg_image ins;
    if (!lg_test_read(t, "ins.exr", &ins, NULL))
        return;
    /* testphongscene's shadow layout: the plane (edge 10 here) and the quad x, z in
     * [-0.5, 0.5] at y = 1 */
    quad quads[2] = { { 0.0, 5.0 }, { 1.0, 0.5 } };
    double se = 0.0, sw = 0.0, best_drop = 1.0, best_got = 0.0;
    int n = 0;
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++) {
            double w[3];
            cam_ray(c, x, y, w);
            double d = fog_length(c, &m, quads, 2, w);
            double want = marched(&m, l, quads, 2, c->eye, w, 1, d, 2000);
            double open = closed(&m, l, w, 1, d);
            double got = ins.pixels[((size_t)y * W + x) * 4 + 1];
            se += (got - want) * (got - want);
            sw += want;
            n++;
            if (want / open < best_drop) {
                best_drop = want / open;
                best_got = got / open;
            }
        }
    double rel_rmse = sqrt(se / n) / (sw / n);
    mesh msh;
    if (ply && read_ply(t, ply, &msh)) {
        /* fp32 against double on the same mesh: the node's accumulation (and its d from
         * the depth buffer) against the signed sum recomputed here, relative to F(d) */
        /* every 4th pixel each way: 130 k triangles per ray (the sanitizer build is slow) */
        double *err = malloc(sizeof(double) * W * H), worst_cancel = 0.0;
        int k = 0;
        for (int y = 1; y < H; y += 4)
            for (int x = 1; x < W; x += 4) {
                double w[3], sa;
                cam_ray(c, x, y, w);
                double d = fog_length(c, &m, quads, 2, w);
                double net = crossing_sum(&msh, &m, l, c->eye, w, 1, d, &sa);
                double open = closed(&m, l, w, 1, d);
                double got = ins.pixels[((size_t)y * W + x) * 4 + 1];
                err[k++] = fabs(got - net) / open;
                worst_cancel = fmax(worst_cancel, sa / fmax(net, 1e-3 * open));
            }
        qsort(err, (size_t)k, sizeof *err, cmp_double);
        double p99 = err[(size_t)(0.99 * (k - 1))], p50 = err[k / 2];
        fprintf(stderr,
                "%s: fp32 accumulation against double on the same mesh: median %.2g, "
                "99th percentile %.2g, max %.2g of F(d); sum of |terms| up to %.1f x "
                "the net\n",
                what, p50, p99, err[k - 1], worst_cancel);
        /* the largest errors sit where a ray grazes a mesh edge and the rasteriser and
         * the double test pick different triangles: the 99th percentile is the fp32 one */
        LG_TEST_CHECK(t, p99 < 1e-4,
                      "%s: fp32 accumulation differs from double by %.3g "
                      "of F(d) at the 99th percentile",
                      what, p99);
        free(err);
        free(msh.v);
        free(msh.tri);
    }
    fprintf(stderr,
            "%s: relative RMSE %.4f; deepest shaft: oracle %.3f of the unshadowed "
            "value, node %.3f\n",
            what, rel_rmse, best_drop, best_got);
    LG_TEST_CHECK(t, rel_rmse < max_rel_rmse, "%s: relative RMSE %.4f against the oracle", what,
                  rel_rmse);
    LG_TEST_CHECK(t, best_drop < 0.9, "%s: the view misses the shaft (oracle %.3f)", what,
                  best_drop);
    LG_TEST_CHECK(t, fabs(best_got - best_drop) < 0.05,
                  "%s: through the shaft the node keeps "
                  "%.3f of the unshadowed in-scatter, the oracle %.3f",
                  what, best_got, best_drop);
    lg_image_free(&ins);
}

static void case_shaft(lg_test *t)
{
    cam c = { .eye = { 2.5, 1.6, 3.5 }, .target = { 0, 0.5, 0 }, .up = { 0, 1, 0 }, .fov_deg = 50 };
    cam_init(&c);
    light l = mk_light(0.2, -1, 0.1, 5, 5, 5);
    check_shaft(t, "shaft", &c, &l, "mesh_file = \"shaft.ply\"", "shaft.ply", 0.04);
    check_shaft(t, "shaft, resolution 32", &c, &l, "resolution = 32", NULL, 0.08);
}

static void case_inside_shadow(lg_test *t)
{
    /* under the quad (its shadow spans y < 1 around the axis for a light straight down),
     * looking sideways and up past its edge: rays start in the shadow and the shaft's
     * walls pass through the near plane */
    cam c = {
        .eye = { 0.1, 0.6, 0.05 }, .target = { 3, 1.3, -1 }, .up = { 0, 1, 0 }, .fov_deg = 70
    };
    cam_init(&c);
    light l = mk_light(0.05, -1, 0.02, 5, 5, 5);
    check_shaft(t, "camera inside the shadow", &c, &l, "", NULL, 0.04);
}

static void case_outside(lg_test *t)
{
    /* The shaft test's view from outside the shaft, with the camera's near plane (4.2)
     * beyond the shaft's near wall: the central rays enter the shadow about 3.9 from the
     * eye, before the near plane, and are in it there. The fog before the near plane is
     * lit up to that wall: a crossing closer than znear must count as much as any other.
     * (A `camera` node outside a scene's bounds puts its near plane at 0.99 x the nearest
     * corner's depth: from outside the bunny box, beyond the box's own shadow's walls.) */
    cam c = { .eye = { 2.5, 1.6, 3.5 },
              .target = { 0, 0.5, 0 },
              .up = { 0, 1, 0 },
              .fov_deg = 50,
              .znear = 4.2 };
    cam_init(&c);
    light l = mk_light(0.2, -1, 0.1, 5, 5, 5);
    check_shaft(t, "near plane beyond the shaft's wall", &c, &l, "", NULL, 0.04);
}

/* The bunny box of examples/volumetric_scene.lgraph (the sun, the fog and the 1024^2 shadow
 * map of the examples) seen by the scene's `cam` moved to `pos`, looking at `target`, with
 * the camera node's automatic planes: the node and volumetric_reference (exact visibility
 * by Embree rays, pixel centres as the node samples, 512 steps, 4 samples) on the same
 * base. Returns the relative RMSE of inscatter (green) against the reference. */
static double box_vs_reference(lg_test *t, const char *what, const char *pos, const char *target)
{
    char g[2048];
    snprintf(g, sizeof g,
             "lightgraph 1\n"
             "include \"%s/examples/volumetric_scene.lgraph\"\n"
             "vol = volumetric_polygonal { scene = fog, base = lit, shadows = shadow, "
             "z_limit = 8 }\n"
             "ref = volumetric_reference { scene = fog, base = lit, steps = 512, spp = 4, "
             "subpixel = centre, z_limit = 8 }\n"
             "output vol.inscatter \"ins.exr\"\n"
             "output ref.inscatter \"ref.exr\"\n",
             POLY_SOURCE_ROOT);
    char set_pos[128], set_target[128];
    snprintf(set_pos, sizeof set_pos, "cam.position=%s", pos);
    snprintf(set_target, sizeof set_target, "cam.target=%s", target);
    lg_test_write_text(t, "box.lgraph", g);
    const char *args[] = { "--size", "64x36", "--set", set_pos, "--set", set_target, NULL };
    int rc = lg_test_render(t, "box.lgraph", args, NULL);
    LG_TEST_CHECK(t, rc == 0, "%s: render failed (%d)", what, rc);
    lg_image ins, ref;
    if (rc || !lg_test_read(t, "ins.exr", &ins, NULL))
        return INFINITY;
    if (!lg_test_read(t, "ref.exr", &ref, NULL)) {
        lg_image_free(&ins);
        return INFINITY;
    }
    double se = 0.0, sr = 0.0, worst = 0.0;
    size_t n = (size_t)ref.width * ref.height;
    for (size_t i = 0; i < n; i++) {
        double got = ins.pixels[4 * i + 1], want = ref.pixels[4 * i + 1];
        se += (got - want) * (got - want);
        sr += want * want;
        if (want > 0.0)
            worst = fmax(worst, fabs(got - want) / want);
    }
    double rel = sqrt(se / sr);
    fprintf(stderr,
            "%s: inscatter against the reference: relative RMSE %.4f, worst pixel "
            "%.3f relative\n",
            what, rel, worst);
    lg_image_free(&ins);
    lg_image_free(&ref);
    return rel;
}

static void case_outside_box(lg_test *t)
{
    /* beside and behind the box, above the box's shadow, which passes between the eye
     * and the near plane (znear ~3.5, the nearest corner's depth): the rays that end on
     * the back wall are in the box's shadow at the near plane and lit before it */
    double side = box_vs_reference(t, "box from outside, behind", "[3.5,2.6,3.5]", "[0,0.9,0]");
    /* in front of the opening, the sun behind the camera, looking in: the dent's walls
     * almost edge-on (with the examples' 1024^2 map one of them covered a pixel with the
     * wrong sign before gl_FrontFacing; at 512^2 none does, so the map stays 1024^2) */
    double front = box_vs_reference(t, "box from outside, in front", "[0.2,1.2,-4.5]", "[0,0.9,0]");
    /* measured (64x36, llvmpipe): 2.0e-4 behind, 1.0e-4 in front, no pixel beyond 0.4 %
     * (the reference's 512 jittered visibility samples and the shadow map's texels); a
     * tenfold margin. Before the crossings closer than znear counted: 0.118 behind (the
     * rays to the back wall lose their lit interval); before the sign came from
     * gl_FrontFacing: 0.023 in front (one pixel of -F(d) for +F(d)) */
    LG_TEST_CHECK(t, side < 2e-3, "camera behind the box: relative RMSE %.4f", side);
    LG_TEST_CHECK(t, front < 2e-3, "camera in front of the box: relative RMSE %.4f", front);
}

/* ---- 32 lights, memory ----------------------------------------------------------------------- */

static light light_k(int k)
{
    double a = 2 * LG_PI * k / 32.0;
    return mk_light(0.6 * cos(a), -1, 0.6 * sin(a), 0.2 + 0.02 * k, 0.5, 0.8 - 0.01 * k);
}

/* bytes_allocated of node "vol" in a profile JSON file, or -1. */
static long long profile_bytes(lg_test *t, const char *rel)
{
    FILE *f = fopen(lg_test_path(t, rel), "rb");
    if (!f)
        return -1;
    static char buf[1 << 16];
    size_t n = fread(buf, 1, sizeof buf - 1, f);
    fclose(f);
    buf[n] = 0;
    const char *p = strstr(buf, "\"name\": \"vol\"");
    if (!p || !(p = strstr(p, "\"bytes_allocated\": ")))
        return -1;
    return atoll(p + strlen("\"bytes_allocated\": "));
}

static void case_lights32(lg_test *t)
{
    cam c = { .eye = { 0, 2, 6 }, .target = { 0, 0, 0 }, .up = { 0, 1, 0 }, .fov_deg = 40 };
    cam_init(&c);
    light l[32];
    for (int k = 0; k < 32; k++)
        l[k] = light_k(k);
    check_closed(t, "32 lights", &c, l, 32, "resolution = 16", 32);

    /* memory: per light one vertex buffer of (16^2 + 4 * 15 + 8) vec4 */
    long long b[4];
    const int counts[4] = { 1, 2, 4, 8 };
    for (int i = 0; i < 4; i++) {
        char g[16384];
        graph(g, sizeof g, "plane", &c, l, counts[i], &default_fog, 1.0, 32, "resolution = 16",
              true);
        const char *extra[] = { "--profile-json", "prof.json", NULL };
        int rc = render(t, g, extra, NULL);
        LG_TEST_CHECK(t, rc == 0, "%d lights: render failed", counts[i]);
        b[i] = profile_bytes(t, "prof.json");
        LG_TEST_CHECK(t, b[i] > 0, "%d lights: no bytes_allocated for vol", counts[i]);
    }
    const long long per_light = (16 * 16 + 4 * 15 + 8) * 16;
    fprintf(stderr, "bytes_allocated for 1, 2, 4, 8 lights: %lld %lld %lld %lld\n", b[0], b[1],
            b[2], b[3]);
    for (int i = 1; i < 4; i++)
        LG_TEST_CHECK(t, b[i] - b[0] == (counts[i] - 1) * per_light,
                      "%d lights: %lld bytes, want %lld + %d x %lld", counts[i], b[i], b[0],
                      counts[i] - 1, per_light);
}

/* ---- gating, errors -------------------------------------------------------------------------- */

static void case_gating(lg_test *t)
{
    cam c = { .eye = { 0, 2, 6 }, .target = { 0, 0, 0 }, .up = { 0, 1, 0 }, .fov_deg = 40 };
    cam_init(&c);
    light l = mk_light(0.3, -1, 0.2, 5, 5, 5);
    char g[16384];
    graph(g, sizeof g, "plane", &c, &l, 1, &default_fog, 0.0, 64, "", true);
    const char *extra[] = { "--explain", NULL };
    char *text = NULL;
    int rc = render(t, g, extra, &text);
    LG_TEST_CHECK(t, rc == 0, "render failed (%d)", rc);
    LG_TEST_CHECK(t, text && strstr(text, "gated"), "--explain does not say the node is gated:\n%s",
                  text ? text : "");
    free(text);
    if (rc)
        return;
    lg_image out, lit, ins;
    if (!lg_test_read(t, "out.exr", &out, NULL) || !lg_test_read(t, "lit.exr", &lit, NULL) ||
        !lg_test_read(t, "ins.exr", &ins, NULL))
        return;
    lg_test_tol tol = { .max_abs = 0 };
    lg_test_check_image(t, &out, &lit, 32, &tol, "gated out = base");
    double mx = 0;
    for (size_t i = 0; i < (size_t)W * H; i++)
        for (int ch = 0; ch < 3; ch++)
            mx = fmax(mx, fabs(ins.pixels[4 * i + ch]));
    LG_TEST_CHECK(t, mx == 0.0, "gated inscatter is not black (%g)", mx);
    lg_image_free(&out);
    lg_image_free(&lit);
    lg_image_free(&ins);
}

static void expect_error(lg_test *t, const char *what, const char *g, const char *needle)
{
    lg_test_write_text(t, "e.lgraph", g);
    const char *args[] = { "--size", "32x24", NULL };
    char *text = NULL;
    int rc = lg_test_render(t, "e.lgraph", args, &text);
    LG_TEST_CHECK(t, rc == 1 || rc == 2, "%s: exit status %d, want 1 or 2", what, rc);
    LG_TEST_CHECK(t, text && strstr(text, needle), "%s: the message lacks \"%s\":\n%s", what,
                  needle, text ? text : "");
    LG_TEST_CHECK(t, text && strstr(text, "vol"), "%s: the message does not name the node:\n%s",
                  what, text ? text : "");
    free(text);
}

static void case_errors(lg_test *t)
{
    cam c = { .eye = { 0, 2, 6 }, .target = { 0, 0, 0 }, .up = { 0, 1, 0 }, .fov_deg = 40 };
    cam_init(&c);
    light l = mk_light(0.3, -1, 0.2, 5, 5, 5);
    char g[16384];
    graph(g, sizeof g, "plane", &c, &l, 1, &default_fog, 1.0, 64, "", false);
    expect_error(t, "no shadows", g, "shadows");
    graph(g, sizeof g, "plane", &c, &l, 1, &default_fog, 1.0, 64, "resolution = 1", true);
    expect_error(t, "resolution 1", g, "resolution");
    fog near = default_fog;
    near.z_limit = 0.05; /* the camera's znear is 0.1 */
    graph(g, sizeof g, "plane", &c, &l, 1, &near, 1.0, 64, "", true);
    expect_error(t, "z_limit before znear", g, "z_limit 0.05");
    graph(g, sizeof g, "plane", &c, &l, 1, &default_fog, 1.0, 64, "resolution = -3", true);
    expect_error(t, "negative resolution", g, "resolution");

    /* a base without depth: an image read from a file */
    lg_image img;
    lg_image_alloc(&img, 32, 24);
    lg_test_write_exr(t, "flat.exr", &img);
    lg_image_free(&img);
    graph(g, sizeof g, "plane", &c, &l, 1, &default_fog, 1.0, 64, "", true);
    char *at = strstr(g, "base = lit");
    char g2[16500];
    snprintf(g2, sizeof g2, "%.*sbase = flat%s", (int)(at - g), g, at + strlen("base = lit"));
    at = strstr(g2, "vol = ");
    char g3[16600];
    snprintf(g3, sizeof g3, "%.*sflat = image { file = \"flat.exr\" }\n%s", (int)(at - g2), g2, at);
    expect_error(t, "base without depth", g3, "no depth plane");

    /* 33 directional lights */
    light many[33];
    for (int k = 0; k < 33; k++)
        many[k] = light_k(k % 32);
    graph(g, sizeof g, "plane", &c, many, 33, &default_fog, 1.0, 16, "", true);
    expect_error(t, "33 lights", g, "more than 32");
}

/* ---- mesh_file through the host's outputs ---------------------------------------------------- */

/* Files in the test's folder that are temporaries: the host's (".m.lgtmp-PID-XXXXXX.ply", the
 * image writer's "..NAME.XXXXXX") or the plugin's own of old ("m.ply.tmp-XXXXXX"). */
static int temporaries(lg_test *t, char *names, size_t cap)
{
    DIR *d = opendir(lg_test_dir(t));
    int n = 0;
    names[0] = 0;
    struct dirent *e;
    while (d && (e = readdir(d))) {
        if (strcmp(e->d_name, ".") == 0 || strcmp(e->d_name, "..") == 0)
            continue;
        if (e->d_name[0] == '.' || strstr(e->d_name, ".tmp")) {
            size_t k = strlen(names);
            snprintf(names + k, cap - k, " %s", e->d_name);
            n++;
        }
    }
    if (d)
        closedir(d);
    return n;
}

static bool exists(lg_test *t, const char *rel)
{
    struct stat st;
    return lstat(lg_test_path(t, rel), &st) == 0;
}

static void case_mesh_file(lg_test *t)
{
    cam c = { .eye = { 0, 2, 6 }, .target = { 0, 0, 0 }, .up = { 0, 1, 0 }, .fov_deg = 40 };
    cam_init(&c);
    light l = mk_light(0.3, -1, 0.2, 5, 5, 5);
    char g[16384], names[4096];
    char *text = NULL;
    struct stat st;

    /* a FIFO, then a link to it: refused before anything runs (no image written), the FIFO
     * still a FIFO */
    const char *fifo = lg_test_path(t, "fifo.ply");
    LG_TEST_CHECK(t, mkfifo(fifo, 0600) == 0, "mkfifo %s", fifo);
    LG_TEST_CHECK(t, symlink("fifo.ply", lg_test_path(t, "link.ply")) == 0, "symlink");
    const char *dests[] = { "fifo.ply", "link.ply" };
    for (int k = 0; k < 2; k++) {
        char p[64];
        snprintf(p, sizeof p, "mesh_file = \"%s\"", dests[k]);
        graph(g, sizeof g, "plane", &c, &l, 1, &default_fog, 1.0, 64, p, true);
        int rc = render(t, g, NULL, &text);
        LG_TEST_CHECK(t, rc == 1, "%s: exit status %d, want 1", dests[k], rc);
        LG_TEST_CHECK(t,
                      text && strstr(text, "node 'vol', parameter mesh_file") &&
                          strstr(text, "it is a FIFO") && strstr(text, "nothing was run"),
                      "%s: the message lacks the node, the parameter and why:\n%s", dests[k],
                      text ? text : "");
        free(text);
        text = NULL;
        LG_TEST_CHECK(t, lstat(fifo, &st) == 0 && S_ISFIFO(st.st_mode), "the FIFO was replaced");
        LG_TEST_CHECK(t, !exists(t, "out.exr") && !exists(t, "lit.exr"), "%s: an image was written",
                      dests[k]);
        LG_TEST_CHECK(t, temporaries(t, names, sizeof names) == 0, "%s: temporaries left:%s",
                      dests[k], names);
    }

    /* the node writes its mesh, then a node after it fails: no mesh, no temporary */
    graph(g, sizeof g, "plane", &c, &l, 1, &default_fog, 1.0, 64, "mesh_file = \"m.ply\"", true);
    size_t k = strlen(g);
    snprintf(g + k, sizeof g - k,
             "late = test_file_writer { image = vol, fail = true }\n"
             "output late \"late.exr\"\n");
    int rc = render(t, g, NULL, &text);
    if (text && lg_test_output_says_no_device(text))
        LG_TEST_FAILF(t, "no GL device:\n%s", text);
    LG_TEST_CHECK(t, rc == 1 && text && strstr(text, "failing as asked"),
                  "the late failure: exit status %d:\n%s", rc, text ? text : "");
    free(text);
    text = NULL;
    LG_TEST_CHECK(t, !exists(t, "m.ply"), "a failed render left m.ply");
    LG_TEST_CHECK(t, temporaries(t, names, sizeof names) == 0, "temporaries left:%s", names);

    /* gated (density 0): the node never runs, no mesh file is made */
    graph(g, sizeof g, "plane", &c, &l, 1, &default_fog, 0.0, 64, "mesh_file = \"m.ply\"", true);
    rc = render(t, g, NULL, NULL);
    LG_TEST_CHECK(t, rc == 0, "gated render: exit status %d", rc);
    LG_TEST_CHECK(t, !exists(t, "m.ply"), "a gated node made m.ply");
    LG_TEST_CHECK(t, temporaries(t, names, sizeof names) == 0, "temporaries left:%s", names);

    /* success: the PLY is written with the images */
    graph(g, sizeof g, "plane", &c, &l, 1, &default_fog, 1.0, 64, "mesh_file = \"m.ply\"", true);
    rc = render(t, g, NULL, NULL);
    LG_TEST_CHECK(t, rc == 0, "render: exit status %d", rc);
    FILE *f = fopen(lg_test_path(t, "m.ply"), "rb");
    char head[32] = "";
    if (f) {
        size_t got = fread(head, 1, sizeof head - 1, f);
        head[got] = 0;
        fclose(f);
    }
    LG_TEST_CHECK(t, strncmp(head, "ply\nformat binary_little_endian", 31) == 0,
                  "m.ply is not a binary PLY: \"%s\"", head);
    LG_TEST_CHECK(t, exists(t, "out.exr"), "out.exr not written");
    LG_TEST_CHECK(t, temporaries(t, names, sizeof names) == 0, "temporaries left:%s", names);
}

/* ---- counters: fragments and triangles of the volume pass ------------------------------------ */

/* The numbers of the node's line "volume pass: L light(s), T triangles drawn, P primitives
 * generated, F fragments, X per pixel (WxH)"; false when the output has none. */
static bool read_counters(const char *text, unsigned *lights, unsigned long long *drawn,
                          unsigned long long *prims, unsigned long long *frags, double *per_pixel,
                          unsigned *w, unsigned *h)
{
    const char *at = text ? strstr(text, "volume pass: ") : NULL;
    if (!at)
        return false;
    char unit[16];
    return sscanf(at,
                  "volume pass: %u %15s %llu triangles drawn, %llu primitives generated, %llu "
                  "fragments, %lf per pixel (%ux%u)",
                  lights, unit, drawn, prims, frags, per_pixel, w, h) == 8;
}

static void check_counters(lg_test *t, const char *what, const char *layout, const cam *c,
                           const light *l, int nl)
{
    char g[16384];
    graph(g, sizeof g, layout, c, l, nl, &default_fog, 1.0, 64, "mesh_file = \"mesh.ply\"", true);
    char *text = NULL;
    const char *v[] = { "-v", NULL };
    int rc = render(t, g, v, &text);
    LG_TEST_CHECK(t, rc == 0, "%s: render failed (%d):\n%s", what, rc, text ? text : "");
    unsigned lights = 0, w = 0, h = 0;
    unsigned long long drawn = 0, prims = 0, frags = 0;
    double per_pixel = -1;
    bool said = read_counters(text, &lights, &drawn, &prims, &frags, &per_pixel, &w, &h);
    LG_TEST_CHECK(t, said, "%s: no readable 'volume pass:' line in:\n%s", what, text ? text : "");
    /* directional lights alone: the program without point and spot lights' code (what ran
     * before issue 25, at its cost: docs/volumetric.md) */
    LG_TEST_CHECK(t, text && strstr(text, "volume program: directional lights only"),
                  "%s: the directional program did not run:\n%s", what, text ? text : "");
    free(text);
    mesh all;
    if (rc || !said || !read_ply(t, "mesh.ply", &all))
        return;
    /* every pixel centre's ray from the eye, against every triangle of every light's mesh:
     * the pass has no depth test and no culling, so each crossing in front of the near
     * plane (1e-6 z_limit from the eye) is one fragment */
    unsigned long long want = 0, min_px = ~0ull;
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++) {
            double wd[3], s;
            cam_ray(c, x, y, wd);
            unsigned long long px = 0;
            for (uint64_t i = 0; i < all.nt; i++)
                px += hit(&all, i, c->eye, wd, &s) != 0 && s * v3_dot(wd, c->f) > 1e-5;
            want += px;
            min_px = px < min_px ? px : min_px;
        }
    fprintf(stderr,
            "%s: %u light(s), %llu triangles (PLY %llu), %llu primitives, %llu fragments "
            "(%.4f per pixel); crossings counted here %llu, at least %llu a pixel\n",
            what, lights, drawn, (unsigned long long)all.nt, prims, frags, per_pixel, want, min_px);
    LG_TEST_CHECK(t, lights == (unsigned)nl && w == W && h == H, "%s: %u lights at %ux%u", what,
                  lights, w, h);
    LG_TEST_CHECK(t, drawn == all.nt && prims == all.nt,
                  "%s: %llu triangles drawn and %llu generated, the meshes have %llu", what, drawn,
                  prims, (unsigned long long)all.nt);
    LG_TEST_CHECK(t, fabs(per_pixel - (double)frags / (W * H)) < 1e-4,
                  "%s: %.6f per pixel is not %llu / %d", what, per_pixel, frags, W * H);
    LG_TEST_CHECK(t, min_px >= (unsigned long long)nl,
                  "%s: a pixel's ray leaves the lit volumes %llu times, fewer than %d", what,
                  min_px, nl);
    /* a ray through a shared edge or vertex is one fragment to the rasteriser (its tie
     * rules) and 0 or 2 crossings to the double-precision test here: a handful of pixels
     * in 3072 at most (0.02 % of the fragments, and never below 4) */
    double slack = fmax(4.0, 2e-4 * (double)want);
    LG_TEST_CHECK(t, fabs((double)frags - (double)want) <= slack,
                  "%s: %llu fragments, the rays cross the meshes %llu times", what, frags, want);
    free(all.v);
    free(all.tri);
}

static void case_counters(lg_test *t)
{
    cam c = { .eye = { 2.5, 1.6, 3.5 }, .target = { 0, 0.5, 0 }, .up = { 0, 1, 0 }, .fov_deg = 50 };
    cam_init(&c);
    light l[2] = { mk_light(0.2, -1, 0.1, 5, 5, 5), mk_light(-0.5, -1, 0.3, 2, 2, 2) };
    check_counters(t, "plane", "plane", &c, l, 1);
    check_counters(t, "shaft", "shadow", &c, l, 1);
    check_counters(t, "shaft, two lights", "shadow", &c, l, 2);
}

/* ---- point and spot lights (issue 25) -------------------------------------------------------- */

typedef struct plight {
    bool spot;
    double pos[3], dir[3]; /* dir: a spot's axis (the direction its light travels), unit */
    double l_c[3];
    double range, inner_deg, outer_deg;
} plight;

/* The graph of one point or spot light `pl` over testphongscene's `layout`: its shadow map
 * from `shadows` ("hand" testpolyshadow with `sm_params`, "node" the shadowmap node, which
 * makes none for these lights and is gated, "none" no input) into volumetric_polygonal. */
static void pgraph(char *g, size_t cap, const char *layout, const cam *c, const plight *pl,
                   const fog *m, const char *shadows, const char *sm_params, const char *vol_params)
{
    double in = fmax(pl->l_c[0], fmax(pl->l_c[1], pl->l_c[2]));
    int k = snprintf(g, cap,
                     "lightgraph 1\n"
                     "s = test_phong_scene { layout = %s, size = 10, double_sided = true, "
                     "ka = 0.1, camera_position = [%.17g, %.17g, %.17g], camera_target = "
                     "[%.17g, %.17g, %.17g], camera_up = [%.17g, %.17g, %.17g], yfov_deg = "
                     "%.17g }\n"
                     "l0 = light { scene = s, type = %s, position = [%.17g, %.17g, %.17g], "
                     "direction = [%.17g, %.17g, %.17g], inner_cone_deg = %.17g, "
                     "outer_cone_deg = %.17g, range = %.17g, color = [%.17g, %.17g, %.17g], "
                     "intensity = %.17g }\n"
                     "fog = medium { scene = l0, density = 1, scattering = [%.17g, %.17g, "
                     "%.17g], absorption = [%.17g, %.17g, %.17g], g = %.17g }\n"
                     "lit = phong { scene = fog }\n",
                     layout, c->eye[0], c->eye[1], c->eye[2], c->target[0], c->target[1],
                     c->target[2], c->up[0], c->up[1], c->up[2], c->fov_deg,
                     pl->spot ? "spot" : "point", pl->pos[0], pl->pos[1], pl->pos[2], pl->dir[0],
                     pl->dir[1], pl->dir[2], pl->inner_deg, pl->outer_deg, pl->range,
                     pl->l_c[0] / in, pl->l_c[1] / in, pl->l_c[2] / in, in, m->sigma_s[0],
                     m->sigma_s[1], m->sigma_s[2], m->sigma_t[0] - m->sigma_s[0],
                     m->sigma_t[1] - m->sigma_s[1], m->sigma_t[2] - m->sigma_s[2], m->g);
    if (strcmp(shadows, "hand") == 0)
        k += snprintf(g + k, cap - (size_t)k, "shadow = test_poly_shadow { scene = fog%s%s }\n",
                      sm_params[0] ? ", " : "", sm_params);
    else if (strcmp(shadows, "node") == 0)
        k += snprintf(g + k, cap - (size_t)k, "shadow = shadowmap { scene = fog }\n");
    snprintf(g + k, cap - (size_t)k,
             "vol = volumetric_polygonal { scene = fog, base = lit%s, z_limit = %.17g%s%s }\n"
             "output vol.inscatter \"ins.exr\"\n"
             "output vol \"out.exr\"\n"
             "output lit \"lit.exr\"\n",
             strcmp(shadows, "none") ? ", shadows = shadow" : "", m->z_limit,
             vol_params[0] ? ", " : "", vol_params);
}

/* The Gauss-Legendre nodes of the expectation: the node's default point_nodes, so that the
 * comparison is of the node's geometry and signed sum with the same integral in C; the
 * rule's own error (against 64 nodes) is printed as RMSE64 and bounded where said
 * (medium_lights tests the rule against the integral's definition). */
static int air_nodes = 8;

/* A(0, t) of light pl along (e, w), channel ch, per unit L_c sigma_s (lg_point_inscatter
 * in C, air_nodes nodes). */
static double airlight(const plight *pl, const fog *m, const double e[3], const double w[3], int ch,
                       double t)
{
    double spot[5] = { pl->dir[0], pl->dir[1], pl->dir[2], cos(pl->inner_deg * LG_PI / 180.0),
                       cos(pl->outer_deg * LG_PI / 180.0) };
    return lg_point_inscatter(e, w, 0.0, t, pl->pos, pl->range, pl->spot ? spot : NULL, m->g,
                              m->sigma_t[ch], air_nodes);
}

/* Is the segment p -> q blocked by the `quads` (open segment)? */
static bool blocked(const quad *quads, int nq, const double p[3], const double q[3])
{
    double d[3] = { q[0] - p[0], q[1] - p[1], q[2] - p[2] };
    for (int k = 0; k < nq; k++) {
        double t = quad_hit(&quads[k], p, d);
        if (t < 1.0 - 1e-9)
            return true;
    }
    return false;
}

/* Renders graph g and compares inscatter with the per-pixel expectation: the closed form
 * A(0, d) unshadowed (nq = 0 occluders), else the march over [0, d] in `steps` pieces, each
 * lit or not at its middle (blocked towards the light by `occ`), adding A(0, t1) - A(0, t0).
 * The fog's length d is along the plane (and the occluders, which base shows too).
 * dark_below: the maps hold the floor's plane beyond the scene's plane (testpolyshadow
 * floor_half 1000), so no light reaches y < 0: a ray past the plane's edge is lit up to
 * y = 0 only (exactly, in the closed form). Returns
 * the relative RMSE (over the channels, against the expectation's RMS) and the largest
 * relative error (each value against max(its expectation, 1e-3 x the largest)) in *worst;
 * *unshadowed_rmse gets the RMSE of the unshadowed closed form against the expectation. */
/* The last check_point's relative RMSE against the 64-node integral (unshadowed cases). */
static double last_rmse64;

static double check_point(lg_test *t, const char *what, const char *g, const cam *c,
                          const plight *pl, const fog *m, bool dark_below, const quad *occ, int nq,
                          int steps, double *worst, double *unshadowed_rmse)
{
    char *text = NULL;
    int rc = render(t, g, NULL, &text);
    LG_TEST_CHECK(t, rc == 0, "%s: render failed (%d):\n%s", what, rc, text ? text : "");
    free(text);
    *worst = INFINITY;
    if (rc)
        return INFINITY;
    lg_image ins;
    if (!lg_test_read(t, "ins.exr", &ins, NULL))
        return INFINITY;
    quad surf[3] = { { 0.0, 5.0 } };
    int ns = 1;
    for (int k = 0; k < nq; k++)
        surf[ns++] = occ[k];
    double *want = malloc(sizeof(double) * W * H * 3), *free_ = malloc(sizeof(double) * W * H * 3);
    double *conv = malloc(sizeof(double) * W * H * 3);
    double peak = 0.0;
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++) {
            double w[3];
            cam_ray(c, x, y, w);
            double d = fog_length(c, m, surf, ns, w);
            for (int ch = 0; ch < 3; ch++) {
                double k = pl->l_c[ch] * m->sigma_s[ch];
                double dl = d;
                if (dark_below && w[1] < 0.0)
                    dl = fmin(d, c->eye[1] / -w[1]);
                double a_full = airlight(pl, m, c->eye, w, ch, dl), a = a_full;
                air_nodes = 64;
                conv[((size_t)y * W + x) * 3 + ch] = k * airlight(pl, m, c->eye, w, ch, dl);
                air_nodes = 8;
                if (nq) {
                    a = 0.0;
                    double prev = 0.0;
                    for (int i = 0; i < steps; i++) {
                        double t0 = dl * i / steps, t1 = dl * (i + 1) / steps;
                        double tm = 0.5 * (t0 + t1);
                        double next = airlight(pl, m, c->eye, w, ch, t1), p[3];
                        for (int j = 0; j < 3; j++)
                            p[j] = c->eye[j] + tm * w[j];
                        if (!blocked(occ, nq, p, pl->pos))
                            a += next - prev;
                        prev = next;
                    }
                }
                size_t i = ((size_t)y * W + x) * 3 + ch;
                want[i] = k * a;
                free_[i] = k * a_full;
                peak = fmax(peak, want[i]);
            }
        }
    double se = 0.0, ss = 0.0, su = 0.0, mx = 0.0, wgot = 0.0, wwant = 0.0, sc = 0.0;
    int wx = 0, wy = 0;
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++)
            for (int ch = 0; ch < 3; ch++) {
                size_t i = ((size_t)y * W + x) * 3 + ch;
                double got = ins.pixels[((size_t)y * W + x) * 4 + ch];
                LG_TEST_CHECK(t, isfinite(got), "%s: pixel (%d, %d) is not finite", what, x, y);
                se += (got - want[i]) * (got - want[i]);
                sc += (got - conv[i]) * (got - conv[i]);
                su += (free_[i] - want[i]) * (free_[i] - want[i]);
                ss += want[i] * want[i];
                /* relative, floored at 1e-3 of the peak (and at 1e-6: an image that should
                 * be black is held to it) */
                double rel = fabs(got - want[i]) / fmax(fmax(want[i], 1e-3 * peak), 1e-6);
                if (rel > mx) {
                    mx = rel;
                    wx = x, wy = y;
                    wgot = got, wwant = want[i];
                }
            }
    double rmse = sqrt(se / ss);
    last_rmse64 = nq ? NAN : sqrt(sc / ss);
    *worst = mx;
    if (unshadowed_rmse)
        *unshadowed_rmse = sqrt(su / ss);
    fprintf(stderr,
            "%s: relative RMSE %.3g, max relative error %.3g at (%d, %d) (%.6g, want %.6g), "
            "peak %.4g; RMSE64 %.3g\n",
            what, rmse, mx, wx, wy, wgot, wwant, peak, last_rmse64);
    free(want);
    free(free_);
    free(conv);
    lg_image_free(&ins);
    return rmse;
}

static const fog point_fog = {
    .sigma_s = { 0.1, 0.2, 0.3 }, .sigma_t = { 0.15, 0.25, 0.35 }, .g = 0.4, .z_limit = 12
};

/* Unshadowed in the closed form, within fp32 and 8 Gauss-Legendre nodes against 64 */
#define POINT_CLOSED_TOL 2e-3

static void case_point_closed(lg_test *t)
{
    cam c = { .eye = { 0, 2, 6 }, .target = { 0, 0.5, 0 }, .up = { 0, 1, 0 }, .fov_deg = 50 };
    cam_init(&c);
    plight pl = { .pos = { 0.4, 1.5, -0.3 }, .l_c = { 8, 6, 5 } };
    char g[8192];
    double worst;
    /* six empty cube faces: their walls cancel, every ray is lit */
    pgraph(g, sizeof g, "plane", &c, &pl, &point_fog, "hand", "occluders = none", "");
    check_point(t, "point light, six empty faces", g, &c, &pl, &point_fog, false, NULL, 0, 0,
                &worst, NULL);
    LG_TEST_CHECK(t, worst < POINT_CLOSED_TOL, "six empty faces: %.3g beyond %.3g", worst,
                  POINT_CLOSED_TOL);
    /* the floor in the maps: the dent at the plane's depth (the fog ends there anyway) */
    pgraph(g, sizeof g, "plane", &c, &pl, &point_fog, "hand",
           "occluders = floor, floor_half = 1000", "");
    check_point(t, "point light, the floor in its maps", g, &c, &pl, &point_fog, true, NULL, 0, 0,
                &worst, NULL);
    LG_TEST_CHECK(t, worst < POINT_CLOSED_TOL, "floor in the maps: %.3g beyond %.3g", worst,
                  POINT_CLOSED_TOL);
    /* the shadowmap node's own cube (since issue 25 it maps point lights, so the "no map"
     * case this test had, a gated shadow map, no longer exists): the floor's dent from
     * 1024^2 faces instead of exact hand-made ones. Measured: relative RMSE 4.4e-3, the
     * worst pixel 0.09 relative at a value 2 % of the peak (a ray grazing the floor, where
     * a texel decides); bounded by RMSE, the map's discretisation */
    pgraph(g, sizeof g, "plane", &c, &pl, &point_fog, "node", "", "");
    double rmse = check_point(t, "point light, the shadowmap node's cube", g, &c, &pl, &point_fog,
                              true, NULL, 0, 0, &worst, NULL);
    LG_TEST_CHECK(t, rmse < 0.01, "the node's cube: relative RMSE %.3g beyond 0.01", rmse);
}

/* A point light compiles the volume program with POLY_LOCAL (the directional program is
 * checked by `counters`): which program runs is the frame's lights' choice. */
static void case_programs(lg_test *t)
{
    cam c = { .eye = { 0, 2, 6 }, .target = { 0, 0.5, 0 }, .up = { 0, 1, 0 }, .fov_deg = 50 };
    cam_init(&c);
    plight pl = { .pos = { 0.4, 1.5, -0.3 }, .l_c = { 8, 6, 5 } };
    char g[8192];
    pgraph(g, sizeof g, "plane", &c, &pl, &point_fog, "hand", "occluders = none", "");
    char *text = NULL;
    const char *v[] = { "-v", NULL };
    int rc = render(t, g, v, &text);
    LG_TEST_CHECK(t, rc == 0, "point light: render failed (%d):\n%s", rc, text ? text : "");
    LG_TEST_CHECK(t, text && strstr(text, "volume program: point and spot lights"),
                  "point light: the program with point and spot lights did not run:\n%s",
                  text ? text : "");
    LG_TEST_CHECK(t, !text || !strstr(text, "volume program: directional lights only"),
                  "point light: the directional program ran too:\n%s", text ? text : "");
    free(text);
}

static void case_spot_cone(lg_test *t)
{
    cam c = { .eye = { 3, 2.5, 5 }, .target = { 0, 0.8, 0 }, .up = { 0, 1, 0 }, .fov_deg = 50 };
    cam_init(&c);
    plight pl = { .spot = true,
                  .pos = { -0.5, 3, 0.2 },
                  .dir = { 0.3, -1, -0.1 },
                  .l_c = { 20, 20, 16 },
                  .inner_deg = 15,
                  .outer_deg = 30 };
    v3_norm(pl.dir);
    char g[8192];
    double worst;
    pgraph(g, sizeof g, "plane", &c, &pl, &point_fog, "hand",
           "occluders = floor, floor_half = 1000", "");
    check_point(t, "spot light, its cone", g, &c, &pl, &point_fog, true, NULL, 0, 0, &worst, NULL);
    LG_TEST_CHECK(t, worst < POINT_CLOSED_TOL, "spot cone: %.3g beyond %.3g", worst,
                  POINT_CLOSED_TOL);
    pgraph(g, sizeof g, "plane", &c, &pl, &point_fog, "node", "", "point_nodes = 8");
    check_point(t, "spot light, no map", g, &c, &pl, &point_fog, false, NULL, 0, 0, &worst, NULL);
    LG_TEST_CHECK(t, worst < POINT_CLOSED_TOL, "spot, no map: %.3g beyond %.3g", worst,
                  POINT_CLOSED_TOL);
}

static void case_point_occluder(lg_test *t)
{
    cam c = { .eye = { 2.5, 1.6, 3.5 }, .target = { 0, 0.5, 0 }, .up = { 0, 1, 0 }, .fov_deg = 50 };
    cam_init(&c);
    /* off the quad's centre, so that a map read upside down or mirrored misplaces the shaft */
    plight pl = { .pos = { 0.3, 2.2, -0.2 }, .l_c = { 6, 6, 6 } };
    quad occ = { 1.0, 0.5 };
    char g[8192];
    double worst, unsh;
    pgraph(g, sizeof g, "shadow", &c, &pl, &point_fog, "hand",
           "occluders = shadow, floor_half = 1000, resolution = 128", "mesh_file = \"point.ply\"");
    double rmse = check_point(t, "point light above the quad", g, &c, &pl, &point_fog, false, &occ,
                              1, 200, &worst, &unsh);
    fprintf(stderr, "  (the unshadowed closed form's RMSE against the oracle: %.3g)\n", unsh);
    /* measured 2.7e-4 (the map's 128 texels a face at the shadow's edges); the quad's
     * shadow is 8e-3 of the image's RMSE (unsh): both bounds catch a map read mirrored */
    LG_TEST_CHECK(t, rmse < 1.5e-3, "point light above the quad: relative RMSE %.3g", rmse);
    LG_TEST_CHECK(t, unsh > 10 * rmse,
                  "the quad's shadow hardly matters (unshadowed %.3g, node %.3g): no test", unsh,
                  rmse);
    /* the six faces' meshes read back: from points in the lit fog every ray leaves the
     * volumes once more than it enters them, from points in the shadow as often */
    mesh ms;
    if (!read_ply(t, "point.ply", &ms))
        return;
    uint64_t rng = 12345;
    int bad = 0, tried = 0, lit_n = 0, dark_n = 0;
    for (int k = 0; k < 200; k++) {
        double p[3], w[3];
        for (int j = 0; j < 3; j++) {
            rng = rng * 6364136223846793005ull + 1442695040888963407ull;
            double u = (double)(rng >> 11) / 9007199254740992.0;
            p[j] = j == 1 ? 0.05 + 2.0 * u : -1.5 + 3.0 * u;
            rng = rng * 6364136223846793005ull + 1442695040888963407ull;
            w[j] = (double)(rng >> 11) / 9007199254740992.0 - 0.5;
        }
        v3_norm(w);
        bool lit = !blocked(&occ, 1, p, pl.pos);
        /* skip points within a map texel of the shadow's boundary */
        double dq[3] = { pl.pos[0] - p[0], pl.pos[1] - p[1], pl.pos[2] - p[2] };
        double tq = (1.0 - p[1]) / dq[1];
        if (tq > 0 && tq < 1) {
            double x = p[0] + tq * dq[0], z = p[2] + tq * dq[2];
            if (fabs(fabs(x) - 0.5) < 0.03 || fabs(fabs(z) - 0.5) < 0.03)
                continue;
        }
        tried++;
        lit_n += lit;
        dark_n += !lit;
        int cr = crossings(&ms, p, w);
        if (cr != (lit ? 1 : 0))
            bad++;
    }
    LG_TEST_CHECK(t, bad == 0 && lit_n > 20 && dark_n > 5,
                  "six faces' meshes: %d of %d points with the wrong crossing balance (%d lit, "
                  "%d in the shadow)",
                  bad, tried, lit_n, dark_n);
    free(ms.v);
    free(ms.tri);
}

static void case_point_inside_cone(lg_test *t)
{
    /* the camera inside the spot's cone (18 degrees off its axis of 30), looking across it:
     * every ray starts inside the light volume (no entry crossing: A(0, 0) = 0) */
    cam c = {
        .eye = { 0.3, 1.5, 0.4 }, .target = { 2, 0.2, -1 }, .up = { 0, 1, 0 }, .fov_deg = 60
    };
    cam_init(&c);
    plight sp = { .spot = true,
                  .pos = { 0, 3, 0 },
                  .dir = { 0, -1, 0 },
                  .l_c = { 10, 10, 10 },
                  .inner_deg = 20,
                  .outer_deg = 30 };
    char g[8192];
    double worst;
    pgraph(g, sizeof g, "plane", &c, &sp, &point_fog, "hand",
           "occluders = floor, floor_half = 1000", "");
    check_point(t, "camera inside the spot's cone", g, &c, &sp, &point_fog, true, NULL, 0, 0,
                &worst, NULL);
    LG_TEST_CHECK(t, worst < POINT_CLOSED_TOL, "inside the cone: %.3g beyond %.3g", worst,
                  POINT_CLOSED_TOL);
    /* the camera at the point light itself: the six frusta's apex at the eye (their walls
     * edge-on), A's largest values (H = LG_LIGHT_EPSILON on the rays through the light) */
    cam at = {
        .eye = { 0.2, 1.2, 0.1 }, .target = { 1, 0.3, -2 }, .up = { 0, 1, 0 }, .fov_deg = 60
    };
    cam_init(&at);
    plight pl = { .pos = { 0.2, 1.2, 0.1 }, .l_c = { 2, 2, 2 } };
    pgraph(g, sizeof g, "plane", &at, &pl, &point_fog, "hand",
           "occluders = floor, floor_half = 1000", "");
    check_point(t, "camera at the point light", g, &at, &pl, &point_fog, true, NULL, 0, 0, &worst,
                NULL);
    /* the six frusta's faces through the light are edge-on from the eye: dropped (a wall's
     * sliver gave one pixel on its line 19 % before) */
    LG_TEST_CHECK(t, worst < POINT_CLOSED_TOL, "camera at the light: %.3g beyond %.3g", worst,
                  POINT_CLOSED_TOL);
    /* the camera at a spot light, looking along (and beside) its cone */
    cam as = {
        .eye = { 0.1, 2.5, -0.2 }, .target = { 0.9, 0, -0.6 }, .up = { 0, 1, 0 }, .fov_deg = 70
    };
    cam_init(&as);
    plight sa = { .spot = true,
                  .pos = { 0.1, 2.5, -0.2 },
                  .dir = { 0.2, -1, 0 },
                  .l_c = { 10, 10, 10 },
                  .inner_deg = 10,
                  .outer_deg = 25 };
    v3_norm(sa.dir);
    pgraph(g, sizeof g, "plane", &as, &sa, &point_fog, "hand",
           "occluders = floor, floor_half = 1000", "");
    check_point(t, "camera at the spot light", g, &as, &sa, &point_fog, true, NULL, 0, 0, &worst,
                NULL);
    LG_TEST_CHECK(t, worst < POINT_CLOSED_TOL, "camera at the spot: %.3g beyond %.3g", worst,
                  POINT_CLOSED_TOL);
}

static void case_point_range(lg_test *t)
{
    cam c = { .eye = { 0, 2, 6 }, .target = { 0, 0.5, 0 }, .up = { 0, 1, 0 }, .fov_deg = 50 };
    cam_init(&c);
    char g[8192];
    double worst;
    /* range 0 is infinite (glTF); range 2.5 cuts the glow off inside the view; a range far
     * below the map's planes (0.02) leaves almost nothing */
    const double ranges[] = { 0.0, 2.5, 0.02 };
    for (int k = 0; k < 3; k++) {
        plight pl = { .pos = { 0.4, 1.5, -0.3 }, .l_c = { 8, 6, 5 }, .range = ranges[k] };
        char what[64];
        snprintf(what, sizeof what, "point light, range %g", ranges[k]);
        pgraph(g, sizeof g, "plane", &c, &pl, &point_fog, "hand",
               "occluders = floor, floor_half = 1000", "");
        check_point(t, what, g, &c, &pl, &point_fog, true, NULL, 0, 0, &worst, NULL);
        LG_TEST_CHECK(t, worst < POINT_CLOSED_TOL, "%s: %.3g beyond %.3g", what, worst,
                      POINT_CLOSED_TOL);
    }
    plight sp = { .spot = true,
                  .pos = { -0.5, 3, 0.2 },
                  .dir = { 0, -1, 0 },
                  .l_c = { 20, 20, 16 },
                  .inner_deg = 10,
                  .outer_deg = 35,
                  .range = 2.8 };
    pgraph(g, sizeof g, "plane", &c, &sp, &point_fog, "hand",
           "occluders = floor, floor_half = 1000", "");
    check_point(t, "spot light, range 2.8", g, &c, &sp, &point_fog, true, NULL, 0, 0, &worst, NULL);
    LG_TEST_CHECK(t, worst < POINT_CLOSED_TOL, "spot, range 2.8: %.3g beyond %.3g", worst,
                  POINT_CLOSED_TOL);
}

static void case_point_errors(lg_test *t)
{
    cam c = { .eye = { 0, 2, 6 }, .target = { 0, 0.5, 0 }, .up = { 0, 1, 0 }, .fov_deg = 50 };
    cam_init(&c);
    plight pl = { .pos = { 0.4, 1.5, -0.3 }, .l_c = { 8, 6, 5 } };
    char g[8192];
    pgraph(g, sizeof g, "plane", &c, &pl, &point_fog, "hand", "defect = paraboloid", "");
    expect_error(t, "dual-paraboloid maps", g, "dual-paraboloid");
    pgraph(g, sizeof g, "plane", &c, &pl, &point_fog, "hand", "defect = offcentre", "");
    expect_error(t, "maps beside the light", g, "not centred on the light");
    pgraph(g, sizeof g, "plane", &c, &pl, &point_fog, "hand", "defect = short", "");
    expect_error(t, "one record for a point light", g, "6 consecutive record");
    pgraph(g, sizeof g, "plane", &c, &pl, &point_fog, "hand", "", "point_nodes = 9");
    expect_error(t, "point_nodes 9", g, "point_nodes");
    /* a heterogeneous medium: refused, by vol_common (no VOL_ACCEPT_FIELD) */
    snprintf(g, sizeof g,
             "lightgraph 1\n"
             "s = test_poly_field_scene { }\n"
             "lit = phong { scene = s }\n"
             "shadow = test_poly_shadow { scene = s }\n"
             "vol = volumetric_polygonal { scene = s, base = lit, shadows = shadow }\n"
             "output vol \"out.exr\"\n");
    expect_error(t, "heterogeneous medium", g, "density field");
}

/* Agreement with volumetric_reference on a point light above the quad (Embree visibility
 * there, the hand-made maps here). The reference gains point lights in parallel (issue 25):
 * until then it refuses them and this case is skipped. The reference's rays go through
 * the pixel centres (subpixel = centre), as this node's do: its default jittered rays
 * average the pixel's footprint, and the glow's peak pixel (36, 2), whose centre ray passes
 * h = 0.03 from the light, is near-singular there (footprint mean 3.75 in red, centre
 * 3.23; jittered spp 4 gave 5.07, 2.68, 5.09 with seeds 0, 1, 2): relative RMSE 0.10 to
 * 0.27 from that one pixel (94 % of the squared error). */
static void case_point_reference(lg_test *t)
{
    cam c = { .eye = { 2.5, 1.6, 3.5 }, .target = { 0, 0.5, 0 }, .up = { 0, 1, 0 }, .fov_deg = 50 };
    cam_init(&c);
    plight pl = { .pos = { 0.3, 2.2, -0.2 }, .l_c = { 6, 6, 6 } };
    char g[8192];
    pgraph(g, sizeof g, "shadow", &c, &pl, &point_fog, "hand",
           "occluders = shadow, floor_half = 1000, resolution = 128", "");
    size_t len = strlen(g);
    snprintf(g + len, sizeof g - len,
             "ref = volumetric_reference { scene = fog, base = lit, steps = 512, spp = 4, "
             "subpixel = centre, z_limit = %.17g }\n"
             "output ref.inscatter \"ref.exr\"\n",
             point_fog.z_limit);
    char *text = NULL;
    int rc = render(t, g, NULL, &text);
    bool refused = rc != 0 && text && strstr(text, "ref") &&
                   (strstr(text, "light") || strstr(text, "gated"));
    if (rc != 0 && !refused)
        LG_TEST_CHECK(t, false, "render failed (%d):\n%s", rc, text ? text : "");
    free(text);
    if (refused)
        lg_test_skip(t, "volumetric_reference refuses point lights (before issue 25's merge)");
    if (rc)
        return;
    lg_image ins, ref;
    if (!lg_test_read(t, "ins.exr", &ins, NULL) || !lg_test_read(t, "ref.exr", &ref, NULL))
        return;
    double se = 0.0, ss = 0.0;
    for (size_t i = 0; i < (size_t)W * H; i++)
        for (int ch = 0; ch < 3; ch++) {
            double a = ins.pixels[4 * i + ch], b = ref.pixels[4 * i + ch];
            se += (a - b) * (a - b);
            ss += b * b;
        }
    if (ss == 0.0)
        lg_test_skip(t, "volumetric_reference leaves point lights out (black inscatter)");
    double rmse = sqrt(se / ss);
    fprintf(stderr, "point light against volumetric_reference: relative RMSE %.3g\n", rmse);
    /* measured 4.8e-4 .. 5.4e-4 (seeds 0 .. 4), 5.1e-4 against the reference at 4096 steps
     * and 16 rays: this node's own error (point_occluder's map, 2.7e-4 against exact
     * visibility, and the 8-node rule's, RMSE64 4e-4 unshadowed; the peak pixel (36, 2) is
     * 59 % of it, 6.5e-4 off there). The reference's noise at 512 steps and 4 rays is
     * 5e-5 .. 7e-5 against 4096 x 16. 1e-3 keeps twice the margin and still catches the
     * quad's shadow left out (8e-3 of the image, point_occluder) */
    LG_TEST_CHECK(t, rmse < 1e-3, "relative RMSE %.3g against volumetric_reference", rmse);
    lg_image_free(&ins);
    lg_image_free(&ref);
}

static void setup(lg_test *t)
{
    lg_test_use_plugins(t, POLY_TEST_PLUGIN_DIR);
}

int main(int argc, char **argv)
{
    static const lg_test_case cases[] = {
        { "closed_form", case_closed_form },
        { "balance", case_balance },
        { "shaft", case_shaft },
        { "inside_shadow", case_inside_shadow },
        { "outside", case_outside },
        { "outside_box", case_outside_box },
        { "lights32", case_lights32 },
        { "gating", case_gating },
        { "errors", case_errors },
        { "mesh_file", case_mesh_file },
        { "counters", case_counters },
        { "point_closed", case_point_closed },
        { "programs", case_programs },
        { "spot_cone", case_spot_cone },
        { "point_occluder", case_point_occluder },
        { "point_inside_cone", case_point_inside_cone },
        { "point_range", case_point_range },
        { "point_errors", case_point_errors },
        { "point_reference", case_point_reference },
    };
    lg_test_main_opts o = { .prefix = NULL, .setup = setup };
    return lg_test_main(argc, argv, cases, sizeof cases / sizeof cases[0], &o);
}
