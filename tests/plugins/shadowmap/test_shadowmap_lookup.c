/*
 * The SDK's CPU shadow lookups (lightgraph/shadowmap.h, ABI 3.2: lg_shadowmap_find,
 * lg_shadowmap_record_at, lg_shadowmap_visibility) against brute force, without GL:
 * `test_shadowmap_lookup CASE`. Each case builds the records as plugins/shadowmap fits them
 * (a cube of six 90-degree perspective faces +x, -x, +y, -y, +z, -z, a spot's one
 * perspective map, an orthographic map) and fills the atlas by ray casting an analytic
 * scene through every texel's centre, so that a map's content is known exactly; the
 * expected visibility of a point is the segment test between it and the light.
 *
 *   faces     record_at: a point on each face's axis gets that face; on the seams (two or
 *             three equal largest components) the lower face; a point light's records
 *             need not start at 0 (a directional light before it); a one-record light and
 *             first < 0 or past the end
 *   cube      a point light with a square occluder on each face at distance 1: for 6 x 400
 *             points on a sphere of radius 2, visibility = the segment test, except within
 *             2 texels of an occluder's edge; every face holds shadowed and lit points
 *   near      a point nearer to the light than a face's near plane is lit; a point beyond
 *             the far plane is tested at the far plane
 *   inside    a point light inside a closed box (a sphere of radius 0.05 around it):
 *             every point outside is shadowed
 *   spot      a spot's one perspective map (cone 30 degrees): a disc occluder's shadow on
 *             points of a plane below, with the camera's view inside the cone irrelevant
 *             (the lookup depends on the map only); outside the map: lit
 *   bias      the bias of a perspective map is in world units: an occluder 0.5 m in front
 *             of a receiver near the far plane shadows it (a bias of 0.0002 in window depth
 *             would have been 1/5 of the range there and lit it), and a receiver on the
 *             stored surface is lit at every distance
 *   pcf       pcf_radius r = 0..3 on an orthographic map with a straight edge: the
 *             visibility steps by 1 / (2 r + 1) across (2 r + 1) texels, monotone, 0 and 1
 *             beyond; taps past the tile's side are clamped to it
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "lightgraph/shadowmap.h"
#include "lightgraph/test.h"
#include "lightgraph/vecmath.h"

#define RES 64

/* ---- the analytic scene ---------------------------------------------------------------------- */

/* An axis-aligned square: centre c, normal axis `axis`, half-side h. */
typedef struct quad {
    double c[3];
    int axis;
    double h;
} quad;

typedef struct scene {
    quad q[8];
    int nq;
    double sphere_c[3], sphere_r; /* r > 0: an occluding sphere */
} scene;

/* The nearest hit t > 1e-9 of o + t d with the scene, INFINITY without one. */
static double cast(const scene *s, const double o[3], const double d[3])
{
    double best = INFINITY;
    for (int i = 0; i < s->nq; i++) {
        const quad *q = &s->q[i];
        int a = q->axis;
        if (fabs(d[a]) < 1e-15)
            continue;
        double t = (q->c[a] - o[a]) / d[a];
        if (!(t > 1e-9 && t < best))
            continue;
        bool in = true;
        for (int k = 0; k < 3; k++)
            if (k != a && fabs(o[k] + t * d[k] - q->c[k]) > q->h)
                in = false;
        if (in)
            best = t;
    }
    if (s->sphere_r > 0.0) {
        double oc[3], b = 0, c = 0, dd = 0;
        for (int k = 0; k < 3; k++) {
            oc[k] = o[k] - s->sphere_c[k];
            b += oc[k] * d[k];
            c += oc[k] * oc[k];
            dd += d[k] * d[k];
        }
        c -= s->sphere_r * s->sphere_r;
        double disc = b * b - dd * c;
        if (disc >= 0.0) {
            double r = sqrt(disc);
            double t0 = (-b - r) / dd, t1 = (-b + r) / dd;
            double t = t0 > 1e-9 ? t0 : t1;
            if (t > 1e-9 && t < best)
                best = t;
        }
    }
    return best;
}

/* Does the segment from p to the light at q cross the scene? */
static bool blocked(const scene *s, const double p[3], const double q[3])
{
    double d[3] = { q[0] - p[0], q[1] - p[1], q[2] - p[2] };
    return cast(s, p, d) < 1.0 - 1e-9;
}

/* ---- records and their atlas ----------------------------------------------------------------- */

typedef struct map {
    lg_shadow_light rec[8];
    lg_shadowmap sm;
    float *atlas;
} map;

/* A perspective record as plugins/shadowmap fits one (without the texel margin). */
static void persp_record(lg_shadow_light *l, lg_vec3 q, lg_vec3 axis, lg_vec3 up, double half,
                         float znear, float zfar)
{
    memset(l, 0, sizeof *l);
    lg_m4_look_at(l->view, q, lg_v3_add(q, axis), up);
    lg_m4_perspective(l->proj, (float)(2.0 * half), 1.0f, znear, zfar);
    for (int col = 0; col < 4; col++)
        l->proj[col * 4 + 1] = -l->proj[col * 4 + 1];
    lg_m4_mul(l->view_proj, l->proj, l->view);
    l->projection = LG_SHADOW_PERSPECTIVE;
    l->texel_world = (float)(2.0 * tan(half) / RES);
    l->depth_range = zfar - znear;
    l->znear = znear;
}

static const float CUBE_AXIS[6][3] = { { 1, 0, 0 },  { -1, 0, 0 }, { 0, 1, 0 },
                                       { 0, -1, 0 }, { 0, 0, 1 },  { 0, 0, -1 } };
static const float CUBE_UP[6][3] = { { 0, -1, 0 }, { 0, -1, 0 }, { 0, 0, 1 },
                                     { 0, 0, -1 }, { 0, -1, 0 }, { 0, -1, 0 } };

/* Records `first` .. first + 5: light `light`'s cube at q. */
static void cube_records(map *m, int first, uint32_t light, lg_vec3 q, float zn, float zf)
{
    for (int f = 0; f < 6; f++) {
        lg_shadow_light *l = &m->rec[first + f];
        persp_record(l, q, lg_v3(CUBE_AXIS[f][0], CUBE_AXIS[f][1], CUBE_AXIS[f][2]),
                     lg_v3(CUBE_UP[f][0], CUBE_UP[f][1], CUBE_UP[f][2]), LG_PI / 4.0, zn, zf);
        l->light = light;
        l->face = (uint32_t)f;
    }
}

/* The map's atlas: n records in a row of tiles, each texel the window depth of the first
 * hit of the ray through its centre (1 where none). */
static void fill(map *m, int n, const scene *s)
{
    m->sm = (lg_shadowmap){ .resolution = RES,
                            .n_lights = (uint32_t)n,
                            .lights = m->rec,
                            .atlas_width = (uint32_t)(RES * n),
                            .atlas_height = RES,
                            .bias_constant = 0.0002f };
    free(m->atlas);
    m->atlas = malloc(sizeof(float) * RES * RES * (size_t)n);
    for (int k = 0; k < n; k++) {
        lg_shadow_light *l = &m->rec[k];
        l->tile_x = (uint32_t)(k * RES);
        l->tile_y = 0;
        float inv[16];
        lg_m4_invert(inv, l->view_proj);
        for (int y = 0; y < RES; y++)
            for (int x = 0; x < RES; x++) {
                /* p_tex = ndc * 0.5 + 0.5; texel row 0 is p_tex.y = 0 */
                float nx = (float)((x + 0.5) / RES * 2.0 - 1.0);
                float ny = (float)((y + 0.5) / RES * 2.0 - 1.0);
                lg_vec3 a = lg_m4_point(inv, lg_v3(nx, ny, -1.0f));
                lg_vec3 b = lg_m4_point(inv, lg_v3(nx, ny, 1.0f));
                double o[3] = { a.x, a.y, a.z }, d[3] = { b.x - a.x, b.y - a.y, b.z - a.z };
                double t = cast(s, o, d);
                float depth = 1.0f;
                if (t <= 1.0) {
                    double h[3] = { o[0] + t * d[0], o[1] + t * d[1], o[2] + t * d[2] };
                    const float *vp = l->view_proj;
                    double c[4];
                    for (int r = 0; r < 4; r++)
                        c[r] = vp[r] * h[0] + vp[4 + r] * h[1] + vp[8 + r] * h[2] + vp[12 + r];
                    depth = (float)(c[2] / c[3] * 0.5 + 0.5);
                }
                m->atlas[(size_t)y * m->sm.atlas_width + (size_t)(k * RES + x)] = depth;
            }
    }
}

/* ---- cases ----------------------------------------------------------------------------------- */

static void case_faces(lg_test *t)
{
    map m = { 0 };
    /* record 0: a directional light 0 (orthographic, one record); 1..6: point light 1 */
    m.rec[0].light = 0;
    lg_vec3 q = lg_v3(1, 2, 3);
    cube_records(&m, 1, 1, q, 0.01f, 10.0f);
    scene empty = { 0 };
    fill(&m, 7, &empty);
    LG_TEST_CHECK(t,
                  lg_shadowmap_find(&m.sm, 0) == 0 && lg_shadowmap_find(&m.sm, 1) == 1 &&
                      lg_shadowmap_find(&m.sm, 2) == -1 && lg_shadowmap_find(NULL, 0) == -1,
                  "find: %d %d %d", lg_shadowmap_find(&m.sm, 0), lg_shadowmap_find(&m.sm, 1),
                  lg_shadowmap_find(&m.sm, 2));
    for (int f = 0; f < 6; f++) {
        double p[3] = { q.x + 1.5 * CUBE_AXIS[f][0] + 0.3, q.y + 1.5 * CUBE_AXIS[f][1] - 0.2,
                        q.z + 1.5 * CUBE_AXIS[f][2] + 0.1 };
        int32_t r = lg_shadowmap_record_at(&m.sm, 1, p);
        LG_TEST_CHECK(t, r == 1 + f, "face %d: record_at = %d, want %d", f, r, 1 + f);
    }
    /* seams: ties go to the lower face (x before y before z, + before -) */
    struct {
        double d[3];
        int face;
    } seams[] = {
        { { 1, 1, 0.2 }, 0 }, { { -1, 1, 0.2 }, 1 }, { { 0.1, -1, 1 }, 3 }, { { 0.1, 1, -1 }, 2 },
        { { 1, 1, 1 }, 0 },   { { -1, -1, -1 }, 1 }, { { 0, 0, -1 }, 5 },   { { 0, 0, 0 }, 0 },
    };
    for (size_t i = 0; i < sizeof seams / sizeof seams[0]; i++) {
        double p[3] = { q.x + seams[i].d[0], q.y + seams[i].d[1], q.z + seams[i].d[2] };
        int32_t r = lg_shadowmap_record_at(&m.sm, 1, p);
        LG_TEST_CHECK(t, r == 1 + seams[i].face, "seam (%g, %g, %g): record_at = %d, want %d",
                      seams[i].d[0], seams[i].d[1], seams[i].d[2], r, 1 + seams[i].face);
    }
    double p[3] = { 5, 5, 5 };
    LG_TEST_CHECK(t, lg_shadowmap_record_at(&m.sm, 0, p) == 0, "a one-record light");
    LG_TEST_CHECK(t, lg_shadowmap_record_at(&m.sm, -1, p) == -1, "first = -1");
    LG_TEST_CHECK(t, lg_shadowmap_record_at(&m.sm, 7, p) == -1, "first past the end");
    LG_TEST_CHECK(t, lg_shadowmap_visibility(&m.sm, m.atlas, 5, p, 0.0) == 1.0f,
                  "a light without a record is lit");
    free(m.atlas);
}

/* A point on the sphere of radius rad around q, index i of n (a Fibonacci spiral). */
static void sphere_point(lg_vec3 q, double rad, int i, int n, double p[3])
{
    double z = 1.0 - (2.0 * i + 1.0) / n, r = sqrt(1.0 - z * z);
    double a = i * LG_PI * (3.0 - sqrt(5.0));
    p[0] = q.x + rad * r * cos(a);
    p[1] = q.y + rad * z;
    p[2] = q.z + rad * r * sin(a);
}

static void case_cube(lg_test *t)
{
    map m = { 0 };
    lg_vec3 q = lg_v3(0.5f, 1.0f, -0.25f);
    cube_records(&m, 0, 0, q, 0.02f, 6.0f);
    scene s = { 0 };
    for (int f = 0; f < 6; f++) {
        quad *o = &s.q[s.nq++];
        o->axis = f / 2;
        o->h = 0.35;
        o->c[0] = q.x + CUBE_AXIS[f][0], o->c[1] = q.y + CUBE_AXIS[f][1];
        o->c[2] = q.z + CUBE_AXIS[f][2];
        /* off the axis, so that each shadow has edges across the face */
        o->c[(o->axis + 1) % 3] += 0.2;
    }
    fill(&m, 6, &s);
    const double texel = 2.0 / RES; /* at unit distance, where the occluders are */
    const double qa[3] = { q.x, q.y, q.z };
    int tested = 0, shadowed[6] = { 0 }, lit[6] = { 0 }, wrong = 0;
    const int n = 2400;
    for (int i = 0; i < n; i++) {
        double p[3];
        sphere_point(q, 2.0, i, n, p);
        /* skip points whose segment passes within 2 texels of an occluder's edge */
        bool near_edge = false;
        for (int k = 0; k < s.nq && !near_edge; k++) {
            const quad *o = &s.q[k];
            int a = o->axis;
            double dq = o->c[a] - qa[a], dp = p[a] - qa[a];
            if (dp / dq <= 0.0 || fabs(dp) < fabs(dq))
                continue;
            double tt = dq / dp;
            for (int c = 0; c < 3; c++)
                if (c != a) {
                    double x = qa[c] + tt * (p[c] - qa[c]);
                    if (fabs(fabs(x - o->c[c]) - o->h) < 2.0 * texel)
                        near_edge = true;
                }
        }
        if (near_edge)
            continue;
        int want = blocked(&s, p, qa) ? 0 : 1;
        float got = lg_shadowmap_visibility(&m.sm, m.atlas, 0, p, 0.0);
        int face = lg_shadowmap_record_at(&m.sm, 0, p);
        tested++;
        if (got != (float)want) {
            if (wrong++ < 5)
                LG_TEST_FAILF(t, "point (%g, %g, %g) face %d: visibility %g, want %d", p[0], p[1],
                              p[2], face, (double)got, want);
        } else if (face >= 0) {
            (want ? lit : shadowed)[face]++;
        }
    }
    LG_TEST_CHECK(t, wrong == 0, "%d of %d points wrong", wrong, tested);
    for (int f = 0; f < 6; f++)
        LG_TEST_CHECK(t, shadowed[f] > 10 && lit[f] > 10, "face %d: %d shadowed, %d lit", f,
                      shadowed[f], lit[f]);
    printf("%d points tested (%d near an edge skipped)\n", tested, n - tested);
    free(m.atlas);
}

static void case_near(lg_test *t)
{
    map m = { 0 };
    lg_vec3 q = lg_v3(0, 0, 0);
    cube_records(&m, 0, 0, q, 0.5f, 4.0f);
    scene s = { .nq = 1, .q = { { .c = { 0, 0, 2 }, .axis = 2, .h = 1.0 } } };
    fill(&m, 6, &s);
    double behind_near[3] = { 0.05, 0.02, 0.3 }; /* view depth 0.3 < znear 0.5 */
    LG_TEST_CHECK(t, lg_shadowmap_visibility(&m.sm, m.atlas, 0, behind_near, 0.0) == 1.0f,
                  "a point nearer than the near plane is lit");
    double shadowed[3] = { 0.1, 0.1, 3.0 }, beyond[3] = { 0.2, 0.1, 9.0 };
    LG_TEST_CHECK(t, lg_shadowmap_visibility(&m.sm, m.atlas, 0, shadowed, 0.0) == 0.0f,
                  "a point behind the occluder is shadowed");
    LG_TEST_CHECK(t, lg_shadowmap_visibility(&m.sm, m.atlas, 0, beyond, 0.0) == 0.0f,
                  "a point past the far plane, behind the occluder, is tested at the far "
                  "plane: shadowed");
    double open[3] = { 0.1, 0.1, -9.0 };
    LG_TEST_CHECK(t, lg_shadowmap_visibility(&m.sm, m.atlas, 0, open, 0.0) == 1.0f,
                  "a point past the far plane where nothing was drawn is lit");
    free(m.atlas);
}

static void case_inside(lg_test *t)
{
    map m = { 0 };
    lg_vec3 q = lg_v3(1, 1, 1);
    cube_records(&m, 0, 0, q, 0.01f, 5.0f);
    scene s = { .sphere_c = { 1, 1, 1 }, .sphere_r = 0.05 };
    fill(&m, 6, &s);
    int lit = 0;
    for (int i = 0; i < 300; i++) {
        double p[3];
        sphere_point(q, 1.0 + 0.01 * i, i, 300, p);
        lit += lg_shadowmap_visibility(&m.sm, m.atlas, 0, p, 0.0) != 0.0f;
    }
    LG_TEST_CHECK(t, lit == 0, "a light inside geometry: %d of 300 points lit", lit);
    free(m.atlas);
}

static void case_spot(lg_test *t)
{
    map m = { 0 };
    lg_vec3 q = lg_v3(0, 3, 0);
    const double cone = 30.0 * LG_PI / 180.0;
    persp_record(&m.rec[0], q, lg_v3(0, -1, 0), lg_v3(0, 0, -1), cone, 0.1f, 4.0f);
    scene s = { .nq = 1, .q = { { .c = { 0.2, 2, 0 }, .axis = 1, .h = 0.3 } } };
    fill(&m, 1, &s);
    /* on the plane y = 0 the occluder's shadow is x in [-0.1, 0.5] * 3, z in [-0.3, 0.3] * 3 */
    double texel_floor = 2.0 * tan(cone) / RES * 3.0;
    int tested = 0, wrong = 0, dark = 0;
    for (int i = 0; i <= 60; i++)
        for (int j = 0; j <= 60; j++) {
            double p[3] = { -1.6 + 3.2 * i / 60.0, 0.0, -1.6 + 3.2 * j / 60.0 };
            double ex = fmin(fabs(p[0] + 0.3), fabs(p[0] - 1.5)), ez = fabs(fabs(p[2]) - 0.9);
            double mg = 2 * texel_floor; /* the corners too */
            bool inside_x = p[0] > -0.3 - mg && p[0] < 1.5 + mg, inside_z = fabs(p[2]) < 0.9 + mg;
            if ((ex < mg && inside_z) || (ez < mg && inside_x))
                continue;
            double qq[3] = { q.x, q.y, q.z };
            int want = blocked(&s, p, qq) ? 0 : 1;
            float got = lg_shadowmap_visibility(&m.sm, m.atlas, 0, p, 0.0);
            tested++;
            dark += want == 0;
            if (got != (float)want && wrong++ < 5)
                LG_TEST_FAILF(t, "(%g, 0, %g): visibility %g, want %d", p[0], p[2], (double)got,
                              want);
        }
    LG_TEST_CHECK(t, wrong == 0 && dark > 100, "%d of %d wrong, %d in the shadow", wrong, tested,
                  dark);
    double outside[3] = { 2.5, 0.0, 0.0 }; /* 40 degrees off the axis: outside the map */
    LG_TEST_CHECK(t, lg_shadowmap_visibility(&m.sm, m.atlas, 0, outside, 0.0) == 1.0f,
                  "outside the spot's map: lit");
    double behind[3] = { 0.0, 5.0, 0.0 }; /* w < 0 */
    LG_TEST_CHECK(t, lg_shadowmap_visibility(&m.sm, m.atlas, 0, behind, 0.0) == 1.0f,
                  "behind the spot: lit");
    free(m.atlas);
}

static void case_bias(lg_test *t)
{
    map m = { 0 };
    lg_vec3 q = lg_v3(0, 0, 0);
    /* near / far = 1 / 1000, as the node fits a light inside the scene */
    persp_record(&m.rec[0], q, lg_v3(0, 0, -1), lg_v3(0, 1, 0), LG_PI / 8.0, 0.01f, 10.0f);
    scene s = { .nq = 1, .q = { { .c = { 0, 0, -9.0 }, .axis = 2, .h = 2.0 } } };
    fill(&m, 1, &s);
    double behind[3] = { 0.1, 0.05, -9.5 };
    float v = lg_shadowmap_visibility(&m.sm, m.atlas, 0, behind, 0.0);
    LG_TEST_CHECK(t, v == 0.0f,
                  "a receiver 0.5 m behind an occluder at 9 m (far 10 m) is lit (%g): the bias "
                  "is not in world units",
                  (double)v);
    /* receivers on the stored surface itself, at several distances: lit (no acne) */
    int acne = 0;
    for (int i = 0; i < 40; i++) {
        double z = -(0.05 + 9.5 * i / 39.0);
        scene w = { .nq = 1, .q = { { .c = { 0, 0, z }, .axis = 2, .h = 20.0 } } };
        fill(&m, 1, &w);
        for (int k = 0; k < 5; k++) {
            double p[3] = { 0.3 * k * -z / 4.0, -0.1 * k * -z / 4.0, z };
            acne += lg_shadowmap_visibility(&m.sm, m.atlas, 0, p, 0.0) != 1.0f;
        }
    }
    LG_TEST_CHECK(t, acne == 0, "%d of 200 receivers on the stored surface are shadowed", acne);
    free(m.atlas);
}

static void case_pcf(lg_test *t)
{
    /* an orthographic map straight down over x, z in [-1, 1], depth [0, 4] from y = 2: the
     * half x < 0.0 covered at y = 1 */
    map m = { 0 };
    lg_shadow_light *l = &m.rec[0];
    lg_m4_look_at(l->view, lg_v3(0, 2, 0), lg_v3(0, 1, 0), lg_v3(0, 0, -1));
    lg_m4_ortho(l->proj, -1, 1, -1, 1, 0, 4);
    for (int col = 0; col < 4; col++)
        l->proj[col * 4 + 1] = -l->proj[col * 4 + 1];
    lg_m4_mul(l->view_proj, l->proj, l->view);
    l->texel_world = 2.0f / RES;
    l->depth_range = 4.0f;
    scene s = { .nq = 1, .q = { { .c = { -1.0, 1.0, 0 }, .axis = 1, .h = 1.0 } } };
    fill(&m, 1, &s);
    const double texel = 2.0 / RES;
    for (uint32_t r = 0; r <= 3; r++) {
        m.sm.pcf_radius = r;
        /* sample at texel centres across the edge (x = 0 is a texel boundary) */
        int first_lit = 999, last_dark = -999;
        float prev = -1.0f;
        bool monotone = true, steps = true;
        for (int c = -8; c < 8; c++) {
            double p[3] = { (c + 0.5) * texel, 0.0, 0.1 };
            float v = lg_shadowmap_visibility(&m.sm, m.atlas, 0, p, 0.0);
            monotone = monotone && v >= prev;
            prev = v;
            float k = v * (float)(2 * r + 1);
            steps = steps && fabsf(k - roundf(k)) < 1e-5f;
            if (v == 0.0f)
                last_dark = c;
            if (v == 1.0f && first_lit == 999)
                first_lit = c;
        }
        LG_TEST_CHECK(t, monotone && steps, "pcf %u: not a monotone ramp of steps 1/%u", r,
                      2 * r + 1);
        LG_TEST_CHECK(t, first_lit - last_dark == (int)(2 * r + 1),
                      "pcf %u: the ramp is %d texels wide (last dark %d, first lit %d), want %u", r,
                      first_lit - last_dark, last_dark, first_lit, 2 * r + 1);
        /* the tile's side: a point in the first column reads the clamped taps */
        double side[3] = { -1.0 + 0.5 * texel, 0.0, 0.0 };
        LG_TEST_CHECK(t, lg_shadowmap_visibility(&m.sm, m.atlas, 0, side, 0.0) == 0.0f,
                      "pcf %u: a point at the tile's side under the occluder", r);
    }
    free(m.atlas);
}

int main(int argc, char **argv)
{
    static const lg_test_case cases[] = {
        { "faces", case_faces },   { "cube", case_cube }, { "near", case_near },
        { "inside", case_inside }, { "spot", case_spot }, { "bias", case_bias },
        { "pcf", case_pcf },
    };
    return lg_test_main(argc, argv, cases, sizeof cases / sizeof cases[0], NULL);
}
