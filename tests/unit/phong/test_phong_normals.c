/*
 * Vertex normals of plugins/phong/phong_model.h: seed 1 eq. 1-13 (lg_vertex_normals_eq13),
 * its false smoothing (fig. 1.27) reproduced on a mesh built for it, and the remedy, the crease split
 * (lg_vertex_normals_crease). C only: no device needed.
 *
 *   test_phong_normals eq13              known normals on a cube and a fan
 *   test_phong_normals eq13_degenerate   degenerate, zero-area, sliver, non-finite,
 *                                        cancelling and out-of-range triangles
 *   test_phong_normals false_smoothing   fig. 1.27 with numbers, and its remedy
 *   test_phong_normals crease            the crease split: cube, angles 0 and pi, a
 *                                        high-valence apex, bad input
 */
#include <float.h>
#include <inttypes.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "common/check.h"
#include "lightgraph/vecmath.h"
#include "phong_model.h"

static double len3(const float *v)
{
    return sqrt((double)v[0] * v[0] + (double)v[1] * v[1] + (double)v[2] * v[2]);
}

/* angle between two vectors, degrees */
static double angle_deg(const float *a, const float *b)
{
    double c = ((double)a[0] * b[0] + (double)a[1] * b[1] + (double)a[2] * b[2]) /
               (len3(a) * len3(b));
    return acos(fmax(-1.0, fmin(1.0, c))) * 180 / LG_PI;
}

static void expect_n(const float *got, double x, double y, double z, const char *what, uint32_t v)
{
    CHECKF(fabs(got[0] - x) < 1e-6 && fabs(got[1] - y) < 1e-6 && fabs(got[2] - z) < 1e-6,
           "%s vertex %" PRIu32 ": (%.9g %.9g %.9g), documented (%.9g %.9g %.9g)", what, v, got[0],
           got[1], got[2], x, y, z);
}

static void check_all_unit(const float *n, uint32_t nv, const char *what)
{
    for (uint32_t v = 0; v < nv; v++) {
        const float *p = n + 3 * (size_t)v;
        CHECKF(isfinite(p[0]) && isfinite(p[1]) && isfinite(p[2]) && fabs(len3(p) - 1) < 1e-6,
               "%s vertex %" PRIu32 ": (%g %g %g) is not a unit vector", what, v, p[0], p[1], p[2]);
    }
}

/* ---- meshes ---------------------------------------------------------------------------------- */

static const float cube_pos[8 * 3] = {
    -1, -1, -1, 1, -1, -1, 1, 1, -1, -1, 1, -1, -1, -1, 1, 1, -1, 1, 1, 1, 1, -1, 1, 1,
};
static const uint32_t cube_idx[36] = {
    0, 2, 1, 0, 3, 2, /* -z */ 4, 5, 6, 4, 6, 7, /* +z */ 0, 1, 5, 0, 5, 4, /* -y */
    3, 6, 2, 3, 7, 6, /* +y */ 0, 4, 7, 0, 7, 3, /* -x */ 1, 2, 6, 1, 6, 5, /* +x */
};

/* ---- eq. 1-13 -------------------------------------------------------------------------------- */

static int cmd_eq13(void)
{
    float n[8 * 3];
    CHECK(lg_vertex_normals_eq13(cube_pos, 8, cube_idx, 36, n) == LG_OK);
    /* Each cube corner touches 3 faces, with one or two triangles each: eq. 1-13 counts
     * facets, so the corner normal leans towards the face that has two triangles there. */
    for (uint32_t v = 0; v < 8; v++) {
        double s[3] = { 0, 0, 0 };
        for (uint32_t t = 0; t < 12; t++) {
            const uint32_t *tri = cube_idx + 3 * t;
            if (tri[0] != v && tri[1] != v && tri[2] != v)
                continue;
            const float *a = cube_pos + 3 * tri[0], *b = cube_pos + 3 * tri[1],
                        *c = cube_pos + 3 * tri[2];
            double e1[3] = { b[0] - a[0], b[1] - a[1], b[2] - a[2] },
                   e2[3] = { c[0] - a[0], c[1] - a[1], c[2] - a[2] };
            double cr[3] = { e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2],
                             e1[0] * e2[1] - e1[1] * e2[0] };
            double l = sqrt(cr[0] * cr[0] + cr[1] * cr[1] + cr[2] * cr[2]);
            for (int i = 0; i < 3; i++)
                s[i] += cr[i] / l;
        }
        double l = sqrt(s[0] * s[0] + s[1] * s[1] + s[2] * s[2]);
        expect_n(n + 3 * v, s[0] / l, s[1] / l, s[2] / l, "cube eq. 1-13", v);
        /* and it points out of the cube, into the corner's octant */
        for (int i = 0; i < 3; i++)
            CHECKF(n[3 * v + i] * cube_pos[3 * v + i] > 0.2,
                   "cube vertex %" PRIu32 " normal does not point outwards", v);
    }
    check_all_unit(n, 8, "cube");

    /* A fan of 4 facets around a centre vertex, as in eq. 1-13's figure: a square pyramid
     * seen from above; the centre's normal is +Z by symmetry, the rim's lean outwards. */
    const float pyr_pos[5 * 3] = { 0, 0, 0.5f, 1, 0, 0, 0, 1, 0, -1, 0, 0, 0, -1, 0 };
    const uint32_t pyr_idx[12] = { 0, 1, 2, 0, 2, 3, 0, 3, 4, 0, 4, 1 };
    float pn[5 * 3];
    CHECK(lg_vertex_normals_eq13(pyr_pos, 5, pyr_idx, 12, pn) == LG_OK);
    expect_n(pn, 0, 0, 1, "pyramid apex", 0);
    /* facet normals (+-0.5, +-0.5, 1) / sqrt(1.5); rim vertex 1 (+x) has facets 0
     * (0.5, 0.5, 1) and 3 (0.5, -0.5, 1): (1, 0, 2) / sqrt(5) */
    expect_n(pn + 3, 1 / sqrt(5.0), 0, 2 / sqrt(5.0), "pyramid rim", 1);
    expect_n(pn + 6, 0, 1 / sqrt(5.0), 2 / sqrt(5.0), "pyramid rim", 2);
    return check_report("phong_normals eq13");
}

static int cmd_eq13_degenerate(void)
{
    const float nan = NAN;
    /* clang-format off */
    float pos[] = {
        0, 0, 0,   1, 0, 0,   0, 1, 0,               /* 0-2: a good triangle, +Z */
        2, 0, 0,                                     /* 3: only in a collinear triangle */
        5, 5, 5,   6, 6, 6,   7, 7, 7,               /* 4-6: a collinear triangle only */
        nan, 0, 0,                                   /* 7: a non-finite position */
        9, 9, 9,                                     /* 8: unreferenced */
        0, 5, 0,   1, 5, 0,   0.5f, 5, 1e-8f,        /* 9-11: a sliver (angles ~1e-8 rad), -Y */
        0, 0, 3,   1, 0, 3,   0, 1, 4,               /* 12-14: a sheet, both sides, (0 -1 1) */
        1e38f, 0, 0,   0, 1e38f, 0,   0, 0, 1e38f,   /* 15-17: huge, fine */
        0, 0, 0,   1e-40f, 0, 0,   0, 1e-40f, 0,     /* 18-20: denormal size, fine (double) */
    };
    uint32_t idx[] = {
        0, 1, 2,
        0, 1, 3,      /* collinear: zero area */
        1, 1, 2,      /* repeated vertex */
        4, 5, 6,      /* collinear */
        0, 2, 7,      /* NaN position */
        9, 10, 11,    /* sliver */
        12, 13, 14,   12, 14, 13,   /* cancel */
        15, 16, 17,
        18, 19, 20,
    };
    /* clang-format on */
    uint32_t nv = sizeof pos / sizeof pos[0] / 3, ni = sizeof idx / sizeof idx[0];
    float n[21 * 3];
    int rc = lg_vertex_normals_eq13(pos, nv, idx, ni, n);
    CHECKF(rc == LG_OK, "rc %d", rc);
    check_all_unit(n, nv, "degenerate mesh");
    const double fx = LG_PHONG_NORMAL_FALLBACK_X, fy = LG_PHONG_NORMAL_FALLBACK_Y,
                 fz = LG_PHONG_NORMAL_FALLBACK_Z;
    for (uint32_t v = 0; v <= 2; v++)
        expect_n(n + 3 * v, 0, 0, 1, "good triangle, degenerate neighbours ignored", v);
    expect_n(n + 9, fx, fy, fz, "only a zero-area triangle: fallback", 3);
    for (uint32_t v = 4; v <= 6; v++)
        expect_n(n + 3 * v, fx, fy, fz, "only a collinear triangle: fallback", v);
    expect_n(n + 21, fx, fy, fz, "non-finite position: fallback", 7);
    expect_n(n + 24, fx, fy, fz, "unreferenced: fallback", 8);
    for (uint32_t v = 9; v <= 11; v++)
        expect_n(n + 3 * v, fx, fy, fz, "only a sliver: fallback", v);
    for (uint32_t v = 12; v <= 14; v++)
        expect_n(n + 3 * v, 0, -1 / sqrt(2.0), 1 / sqrt(2.0),
                 "cancelling sheet: first usable facet", v);
    double s = 1 / sqrt(3.0);
    for (uint32_t v = 15; v <= 17; v++)
        expect_n(n + 3 * v, s, s, s, "huge triangle", v);
    for (uint32_t v = 18; v <= 20; v++)
        expect_n(n + 3 * v, 0, 0, 1, "denormal-size triangle", v);
    printf("eq. 1-13 on the degenerate mesh:\n");
    for (uint32_t v = 0; v < nv; v++)
        printf("  vertex %2" PRIu32 ": (% .6f % .6f % .6f)\n", v, n[3 * v], n[3 * v + 1],
               n[3 * v + 2]);

    /* an index out of range: reported, that triangle skipped, the rest computed */
    uint32_t bad[] = { 0, 1, 2, 0, 99, 2 };
    float m[3 * 3];
    CHECK(lg_vertex_normals_eq13(pos, 3, bad, 6, m) == LG_ERR_INVALID);
    for (uint32_t v = 0; v < 3; v++)
        expect_n(m + 3 * v, 0, 0, 1, "out-of-range neighbour skipped", v);
    /* ni not a multiple of 3: the trailing indices ignored and reported */
    CHECK(lg_vertex_normals_eq13(pos, 3, idx, 4, m) == LG_ERR_INVALID);
    expect_n(m, 0, 0, 1, "trailing index ignored", 0);
    /* NULL with a count: nothing written; empty input: fine */
    CHECK(lg_vertex_normals_eq13(NULL, 3, idx, 3, m) == LG_ERR_INVALID);
    CHECK(lg_vertex_normals_eq13(pos, 3, NULL, 3, m) == LG_ERR_INVALID);
    CHECK(lg_vertex_normals_eq13(NULL, 0, NULL, 0, NULL) == LG_OK);
    return check_report("phong_normals eq13_degenerate");
}

/* ---- fig. 1.27 ------------------------------------------------------------------------------- */

/* A corrugated strip: columns i = 0..C-1 at x = i, height z = H on odd columns and 0 on
 * even ones, two rows (y = 0, 1); vertex (i, j) is 2 i + j. The facets alternate between
 * rising and falling at 45 degrees. The quads' diagonals alternate too, so that every
 * interior vertex has as many triangles on its rising side as on its falling side: eq. 1-13
 * (which counts facets) then sums pairs of mirror-image normals and gets +Z exactly
 * there, for ridges and valleys alike: fig. 1.27's parallel vertex normals. */
enum { COLS = 7, QUADS = COLS - 1, SV = 2 * COLS, SI = 6 * QUADS };
static const float H = 1.0f;

static void strip(float *pos, uint32_t *idx)
{
    for (uint32_t i = 0; i < COLS; i++)
        for (uint32_t j = 0; j < 2; j++) {
            float *p = pos + 3 * (2 * i + j);
            p[0] = (float)i;
            p[1] = (float)j;
            p[2] = (i % 2) ? H : 0.0f;
        }
    for (uint32_t q = 0; q < QUADS; q++) {
        uint32_t a = 2 * q, b = 2 * (q + 1), c = 2 * (q + 1) + 1, d = 2 * q + 1; /* ccw from +Z */
        uint32_t *t = idx + 6 * q;
        if (q % 2 == 0) { /* diagonal a-c */
            uint32_t tt[6] = { a, b, c, a, c, d };
            memcpy(t, tt, sizeof tt);
        } else { /* diagonal b-d */
            uint32_t tt[6] = { a, b, d, b, c, d };
            memcpy(t, tt, sizeof tt);
        }
    }
}

static void facet_n(const float *pos, const uint32_t *tri, float out[3])
{
    const float *a = pos + 3 * tri[0], *b = pos + 3 * tri[1], *c = pos + 3 * tri[2];
    lg_vec3 n = lg_v3_cross(lg_v3(b[0] - a[0], b[1] - a[1], b[2] - a[2]),
                            lg_v3(c[0] - a[0], c[1] - a[1], c[2] - a[2]));
    n = lg_safe_normalize(n, lg_v3(0, 0, 0));
    out[0] = n.x;
    out[1] = n.y;
    out[2] = n.z;
}

/* lg_phong_direct's red channel at normal n, the light from +x at 45 degrees, viewer +Z */
static float shade(const float *n)
{
    static const lg_phong_material m = { 0.0f, 0.8f, 0.3f, 20.0f, { 1, 1, 1 }, { 1, 1, 1 } };
    lg_vec3 L = lg_safe_normalize(lg_v3(1, 0, 1), lg_v3(0, 0, 1));
    return lg_phong_direct(lg_v3(n[0], n[1], n[2]), lg_v3(0, 0, 1), L, lg_v3(1, 1, 1), &m,
                           LG_SPEC_PHONG, m.n)
        .x;
}

static int cmd_false_smoothing(void)
{
    float pos[SV * 3], n[SV * 3];
    uint32_t idx[SI];
    strip(pos, idx);
    CHECK(lg_vertex_normals_eq13(pos, SV, idx, SI, n) == LG_OK);

    printf("Fig. 1.27 on a corrugated strip of %d facets (columns x = 0..%d, z = 0, %g, 0, ...):\n",
           QUADS, COLS - 1, (double)H);
    printf("  facet normals (the surface is not flat):\n");
    float fn[QUADS][3];
    for (uint32_t q = 0; q < QUADS; q++) {
        facet_n(pos, idx + 6 * q, fn[q]);
        printf("    facet %" PRIu32 ": (% .6f % .6f % .6f)  flat shading %.6f\n", q, fn[q][0],
               fn[q][1], fn[q][2], (double)shade(fn[q]));
    }
    for (uint32_t q = 0; q + 1 < QUADS; q++)
        CHECKF(fabs(angle_deg(fn[q], fn[q + 1]) - 90) < 1e-4,
               "facets %" PRIu32 " and %" PRIu32 " meet at %.6f degrees", q, q + 1,
               angle_deg(fn[q], fn[q + 1]));

    /* eq. 1-13: every interior vertex normal is +Z */
    printf("  eq. 1-13 vertex normals (row y = 0):\n");
    double worst = 0;
    for (uint32_t i = 0; i < COLS; i++) {
        const float *v = n + 3 * (2 * i);
        printf("    column %" PRIu32 ": (% .6f % .6f % .6f)\n", i, v[0], v[1], v[2]);
    }
    for (uint32_t i = 1; i + 1 < COLS; i++)
        for (uint32_t j = 0; j < 2; j++) {
            const float up[3] = { 0, 0, 1 };
            double a = angle_deg(n + 3 * (2 * i + j), up);
            worst = fmax(worst, a);
        }
    printf("  largest angle between an interior eq. 1-13 normal and +Z: %.3g degrees\n", worst);
    CHECKF(worst < 1e-4, "interior eq. 1-13 normals are not parallel: %.6g degrees", worst);

    /* Gouraud: colours at the vertices of the interior facets (1 .. QUADS-2) are all equal,
     * so those facets are drawn in one flat colour; Phong shading interpolates the same
     * parallel normals and draws the same. The true facets alternate between N.L = 0 and 1. */
    float g_min = INFINITY, g_max = -INFINITY;
    for (uint32_t i = 1; i + 1 < COLS; i++)
        for (uint32_t j = 0; j < 2; j++) {
            float c = shade(n + 3 * (2 * i + j));
            g_min = fminf(g_min, c);
            g_max = fmaxf(g_max, c);
        }
    float f_min = INFINITY, f_max = -INFINITY;
    for (uint32_t q = 1; q + 1 < QUADS; q++) {
        f_min = fminf(f_min, shade(fn[q]));
        f_max = fmaxf(f_max, shade(fn[q]));
    }
    printf("  interior facets: Gouraud/Phong with eq. 1-13 normals span [%.6f, %.6f] (flat look); "
           "true facet shading spans [%.6f, %.6f]\n",
           (double)g_min, (double)g_max, (double)f_min, (double)f_max);
    CHECKF(g_max - g_min < 1e-6f, "eq. 1-13 shading varies over the interior: %g",
           (double)(g_max - g_min));
    CHECKF(f_max - f_min > 0.5f, "the facets themselves should differ a lot: %g",
           (double)(f_max - f_min));

    /* The remedy: split normals at creases sharper than 60 degrees (the facets meet at 90). */
    uint32_t out_idx[SI], out_src[SI], out_nv = 0;
    float out_n[SI * 3];
    int rc = lg_vertex_normals_crease(pos, SV, idx, SI, 60.0f * (float)LG_PI / 180.0f, out_idx,
                                      out_src, out_n, &out_nv);
    CHECKF(rc == LG_OK, "rc %d", rc);
    /* columns 0 and COLS-1 keep one vertex each per row; interior ones split in two */
    CHECKF(out_nv == 2 * 2 + 2 * 2 * (COLS - 2), "%" PRIu32 " output vertices", out_nv);
    double worst_corner = 0;
    for (uint32_t q = 0; q < QUADS; q++)
        for (uint32_t k = 0; k < 6; k++) {
            uint32_t o = out_idx[6 * q + k];
            CHECKF(out_src[o] == idx[6 * q + k],
                   "output vertex %" PRIu32 " copies %" PRIu32 ", corner uses %" PRIu32, o,
                   out_src[o], idx[6 * q + k]);
            worst_corner = fmax(worst_corner, angle_deg(out_n + 3 * o, fn[q]));
            CHECKF(fabsf(shade(out_n + 3 * o) - shade(fn[q])) < 1e-5f,
                   "facet %" PRIu32 " corner shades %g, facet %g", q, (double)shade(out_n + 3 * o),
                   (double)shade(fn[q]));
        }
    printf("  crease split at 60 degrees: %" PRIu32
           " vertices (from %d); every corner's normal within %.3g degrees of "
           "its facet's: the shading alternates again as the facets do\n",
           out_nv, SV, worst_corner);
    CHECKF(worst_corner < 1e-4, "corner normals off their facets by %.6g degrees", worst_corner);
    /* distinct normals at a ridge vertex: its two copies differ by the facets' 90 degrees */
    uint32_t ridge = 2 * 1, copies[4], nc = 0;
    for (uint32_t o = 0; o < out_nv && nc < 4; o++)
        if (out_src[o] == ridge)
            copies[nc++] = o;
    CHECKF(nc == 2, "ridge vertex split into %" PRIu32 " copies", nc);
    if (nc == 2) {
        double a = angle_deg(out_n + 3 * copies[0], out_n + 3 * copies[1]);
        printf(
            "  ridge vertex (column 1): normals (% .6f % .6f % .6f) and (% .6f % .6f % .6f), %.3f degrees apart\n",
            out_n[3 * copies[0]], out_n[3 * copies[0] + 1], out_n[3 * copies[0] + 2],
            out_n[3 * copies[1]], out_n[3 * copies[1] + 1], out_n[3 * copies[1] + 2], a);
        CHECKF(fabs(a - 90) < 1e-4, "ridge copies %.6f degrees apart", a);
    }

    /* A crease angle above the facets' 90 degrees does not split: false smoothing again. */
    rc = lg_vertex_normals_crease(pos, SV, idx, SI, 100.0f * (float)LG_PI / 180.0f, out_idx,
                                  out_src, out_n, &out_nv);
    CHECK(rc == LG_OK);
    CHECKF(out_nv == SV, "crease 100 degrees: %" PRIu32 " vertices, expected %d (no split)", out_nv,
           SV);
    printf("  crease split at 100 degrees: %" PRIu32
           " vertices (no split: the crease angle must be below the "
           "angle between the facets)\n",
           out_nv);
    return check_report("phong_normals false_smoothing");
}

/* ---- crease split ---------------------------------------------------------------------------- */

static int cmd_crease(void)
{
    uint32_t oi[36], os[36], onv;
    float on[36 * 3], eq[8 * 3];
    /* 30 degrees: a cube's faces (90 degrees apart) keep their own normals: 24 vertices */
    CHECK(lg_vertex_normals_crease(cube_pos, 8, cube_idx, 36, 30.0f * (float)LG_PI / 180.0f, oi, os,
                                   on, &onv) == LG_OK);
    CHECKF(onv == 24, "cube, 30 degrees: %" PRIu32 " vertices", onv);
    check_all_unit(on, onv, "cube, 30 degrees");
    for (uint32_t t = 0; t < 12; t++) {
        float fn[3];
        const float *a = cube_pos + 3 * cube_idx[3 * t], *b = cube_pos + 3 * cube_idx[3 * t + 1],
                    *c = cube_pos + 3 * cube_idx[3 * t + 2];
        lg_vec3 x = lg_v3_cross(lg_v3(b[0] - a[0], b[1] - a[1], b[2] - a[2]),
                                lg_v3(c[0] - a[0], c[1] - a[1], c[2] - a[2]));
        x = lg_safe_normalize(x, lg_v3(0, 0, 0));
        fn[0] = x.x;
        fn[1] = x.y;
        fn[2] = x.z;
        for (int k = 0; k < 3; k++) {
            uint32_t o = oi[3 * t + k];
            CHECKF(o < onv && os[o] == cube_idx[3 * t + k], "triangle %" PRIu32 " corner %d", t, k);
            expect_n(on + 3 * o, fn[0], fn[1], fn[2], "cube, 30 degrees: the face normal", o);
        }
    }
    /* crease 0 (and NaN): flat; coplanar triangles of a face still share vertices */
    CHECK(lg_vertex_normals_crease(cube_pos, 8, cube_idx, 36, 0.0f, oi, os, on, &onv) == LG_OK);
    CHECKF(onv == 24, "cube, 0 degrees: %" PRIu32 " vertices", onv);
    CHECK(lg_vertex_normals_crease(cube_pos, 8, cube_idx, 36, NAN, oi, os, on, &onv) == LG_OK);
    CHECKF(onv == 24, "cube, NaN degrees: %" PRIu32 " vertices", onv);
    /* pi: eq. 1-13, no split */
    CHECK(lg_vertex_normals_eq13(cube_pos, 8, cube_idx, 36, eq) == LG_OK);
    CHECK(lg_vertex_normals_crease(cube_pos, 8, cube_idx, 36, (float)LG_PI, oi, os, on, &onv) ==
          LG_OK);
    CHECKF(onv == 8, "cube, 180 degrees: %" PRIu32 " vertices", onv);
    for (uint32_t o = 0; o < onv; o++)
        expect_n(on + 3 * o, eq[3 * os[o]], eq[3 * os[o] + 1], eq[3 * os[o] + 2],
                 "cube, 180 degrees = eq. 1-13", o);

    /* a cone whose apex has 200 facets (the grouped path above 128): the apex splits into
     * groups, every corner normal within 31 degrees of its facet at crease 30 */
    enum { SIDES = 200 };
    float cpos[(SIDES + 1) * 3];
    uint32_t cidx[SIDES * 3], coi[SIDES * 3], cos_[SIDES * 3], cnv;
    float con[SIDES * 3 * 3];
    cpos[0] = cpos[1] = 0;
    cpos[2] = 1;
    for (uint32_t s = 0; s < SIDES; s++) {
        double a = 2 * LG_PI * s / SIDES;
        cpos[3 * (s + 1)] = (float)cos(a);
        cpos[3 * (s + 1) + 1] = (float)sin(a);
        cpos[3 * (s + 1) + 2] = 0;
        cidx[3 * s] = 0;
        cidx[3 * s + 1] = s + 1;
        cidx[3 * s + 2] = (s + 1) % SIDES + 1;
    }
    CHECK(lg_vertex_normals_crease(cpos, SIDES + 1, cidx, SIDES * 3, 30.0f * (float)LG_PI / 180.0f,
                                   coi, cos_, con, &cnv) == LG_OK);
    check_all_unit(con, cnv, "cone");
    uint32_t apex_copies = 0;
    double worst = 0;
    for (uint32_t o = 0; o < cnv; o++)
        apex_copies += cos_[o] == 0;
    for (uint32_t t = 0; t < SIDES; t++) {
        float fn[3];
        facet_n(cpos, cidx + 3 * t, fn);
        worst = fmax(worst, angle_deg(con + 3 * coi[3 * t], fn));
    }
    printf("cone apex with %d facets, crease 30 degrees: %" PRIu32
           " apex copies, corners within %.2f degrees of their "
           "facets\n",
           SIDES, apex_copies, worst);
    CHECKF(apex_copies >= 2 && apex_copies <= 64, "%" PRIu32 " apex copies", apex_copies);
    CHECKF(worst < 31, "apex corner %.3f degrees off its facet", worst);
    /* rim vertices (valence 2, pairwise): two adjacent facets 1.8 degrees apart: no split */
    CHECKF(cnv == SIDES + apex_copies, "%" PRIu32 " vertices: the rim should not split", cnv);

    /* bad input */
    uint32_t bad[3] = { 0, 1, 8 };
    onv = 7;
    CHECK(lg_vertex_normals_crease(cube_pos, 8, bad, 3, 1.0f, oi, os, on, &onv) == LG_ERR_INVALID);
    CHECK(onv == 0);
    CHECK(lg_vertex_normals_crease(cube_pos, 8, cube_idx, 35, 1.0f, oi, os, on, &onv) ==
          LG_ERR_INVALID);
    CHECK(lg_vertex_normals_crease(cube_pos, 8, cube_idx, 36, 1.0f, NULL, os, on, &onv) ==
          LG_ERR_INVALID);
    CHECK(lg_vertex_normals_crease(cube_pos, 8, cube_idx, 36, 1.0f, oi, os, on, NULL) ==
          LG_ERR_INVALID);
    CHECK(lg_vertex_normals_crease(cube_pos, 8, NULL, 0, 1.0f, NULL, NULL, NULL, &onv) == LG_OK &&
          onv == 0);
    /* a degenerate triangle's corners take their vertex's eq. 1-13 normal */
    const uint32_t with_degenerate[9] = { 0, 1, 2, 0, 2, 2, 4, 5, 6 };
    CHECK(lg_vertex_normals_crease(cube_pos, 8, with_degenerate, 9, 0.5f, oi, os, on, &onv) ==
          LG_OK);
    check_all_unit(on, onv, "with a degenerate triangle");
    return check_report("phong_normals crease");
}

int main(int argc, char **argv)
{
    const char *cmd = argc > 1 ? argv[1] : "";
    if (strcmp(cmd, "eq13") == 0)
        return cmd_eq13();
    if (strcmp(cmd, "eq13_degenerate") == 0)
        return cmd_eq13_degenerate();
    if (strcmp(cmd, "false_smoothing") == 0)
        return cmd_false_smoothing();
    if (strcmp(cmd, "crease") == 0)
        return cmd_crease();
    fprintf(
        stderr,
        "test_phong_normals: unknown command '%s' (eq13, eq13_degenerate, false_smoothing, crease)\n",
        cmd);
    return 2;
}
