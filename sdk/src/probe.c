/* lightgraph/probe.h: the probe conventions' solid angles, rotation and lookups on the
 * CPU. The direction <-> texel maps are inline in the header; shaders/common/probe.glsl
 * and shaders/common/probe.cl are their twins (tests/unit/probe holds them together). */
#include "lightgraph/probe.h"

#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* ---- rotation -------------------------------------------------------------------------------- */

/* sin and cos of an angle in degrees, exact at multiples of 90 (so that 90, 180 and the
 * 360 that reduces to 0 give exact matrices). */
static void sincos_deg(float deg, double *s, double *c)
{
    double a = isfinite(deg) ? fmod((double)deg, 360.0) : 0.0;
    if (a < 0)
        a += 360.0;
    if (a == 0 || a == 90 || a == 180 || a == 270) {
        int q = (int)(a / 90);
        static const double S[4] = { 0, 1, 0, -1 }, C[4] = { 1, 0, -1, 0 };
        *s = S[q];
        *c = C[q];
        return;
    }
    double r = a * (LG_PI / 180.0);
    *s = sin(r);
    *c = cos(r);
}

static void mul3(double out[9], const double a[9], const double b[9])
{
    double t[9];
    for (int c = 0; c < 3; c++)
        for (int r = 0; r < 3; r++)
            t[c * 3 + r] = a[0 * 3 + r] * b[c * 3 + 0] + a[1 * 3 + r] * b[c * 3 + 1] +
                           a[2 * 3 + r] * b[c * 3 + 2];
    memcpy(out, t, sizeof t);
}

void lg_probe_rotation_from_euler(float yaw_deg, float pitch_deg, float roll_deg, float rotation[9])
{
    double sy, cy, sp, cp, sr, cr;
    sincos_deg(yaw_deg, &sy, &cy);
    sincos_deg(pitch_deg, &sp, &cp);
    sincos_deg(roll_deg, &sr, &cr);
    /* column-major: element (row r, column c) at [c * 3 + r] */
    const double ry[9] = { cy, 0, -sy, 0, 1, 0, sy, 0, cy };
    const double rx[9] = { 1, 0, 0, 0, cp, sp, 0, -sp, cp };
    const double rz[9] = { cr, sr, 0, -sr, cr, 0, 0, 0, 1 };
    double m[9];
    mul3(m, ry, rx);
    mul3(m, m, rz);
    for (int k = 0; k < 9; k++)
        rotation[k] = (float)m[k] + 0.0f; /* no -0 */
}

/* ---- solid angles ---------------------------------------------------------------------------- */

/* Cube: the solid angle of [0, x] x [0, y] on the plane at distance 1, signed. */
static double cube_area(double x, double y)
{
    return atan2(x * y, sqrt(x * x + y * y + 1.0));
}

/* Angular map: (1 - cos(pi r)) / r^2 = 2 (sin(pi r / 2) / r)^2, bounded at r = 0. */
static double angular_h(double r2)
{
    double r = sqrt(r2);
    double q;
    if (r < 1e-5) {
        double t = 0.5 * LG_PI * r;
        q = 0.5 * LG_PI * (1.0 - t * t / 6.0);
    } else {
        q = sin(0.5 * LG_PI * r) / r;
    }
    return 2.0 * q * q;
}

/* 8-point Gauss-Legendre on [-1, 1]. */
static const double GL_X[4] = { 0.1834346424956498, 0.5255324099163290, 0.7966664774136267,
                                0.9602898564975363 };
static const double GL_W[4] = { 0.3626837833783620, 0.3137066458778873, 0.2223810344533745,
                                0.1012285362903763 };

/* The line integral of (1 - cos(pi min(r, 1))) dphi along the segment p0 -> p1 of the
 * angular map's plane (a right, b up). Along a line p(t) = p0 + t d, dphi =
 * (p0 x d) / |p|^2 dt, so the integrand is (p0 x d) H(r) / r^2 dt: bounded everywhere,
 * zero on a line through the origin. Outside the disc H = 2 and the integral is 2 dphi
 * exactly; inside it is smooth and Gauss-Legendre on pieces of length <= 1/8 is exact to
 * double rounding. */
static double angular_edge(double x0, double y0, double x1, double y1)
{
    double dx = x1 - x0, dy = y1 - y0;
    double cr = x0 * dy - y0 * dx;
    if (cr == 0)
        return 0;
    /* |p0 + t d|^2 = 1 */
    double a = dx * dx + dy * dy, b = 2 * (x0 * dx + y0 * dy), c = x0 * x0 + y0 * y0 - 1;
    double ts[4] = { 0, 0, 0, 1 };
    int n = 1;
    double disc = b * b - 4 * a * c;
    if (disc > 0) {
        double sq = sqrt(disc);
        double q = -0.5 * (b + (b >= 0 ? sq : -sq));
        double t1 = q / a, t2 = q != 0 ? c / q : t1;
        if (t1 > t2) {
            double t = t1;
            t1 = t2;
            t2 = t;
        }
        if (t1 > 0 && t1 < 1)
            ts[n++] = t1;
        if (t2 > 0 && t2 < 1)
            ts[n++] = t2;
    }
    ts[n++] = 1;
    double len = sqrt(a), sum = 0;
    for (int k = 0; k + 1 < n; k++) {
        double ta = ts[k], tb = ts[k + 1];
        if (!(tb > ta))
            continue;
        double tm = 0.5 * (ta + tb);
        double mx = x0 + tm * dx, my = y0 + tm * dy;
        if (mx * mx + my * my >= 1) {
            double ax = x0 + ta * dx, ay = y0 + ta * dy, bx = x0 + tb * dx, by = y0 + tb * dy;
            sum += 2 * atan2(ax * by - ay * bx, ax * bx + ay * by);
            continue;
        }
        int pieces = (int)ceil((tb - ta) * len * 8.0);
        if (pieces < 1)
            pieces = 1;
        double h = (tb - ta) / pieces, acc = 0;
        for (int p = 0; p < pieces; p++) {
            double mid = ta + (p + 0.5) * h, half = 0.5 * h;
            for (int g = 0; g < 4; g++)
                for (int sgn = -1; sgn <= 1; sgn += 2) {
                    double t = mid + sgn * GL_X[g] * half;
                    double px = x0 + t * dx, py = y0 + t * dy;
                    acc += GL_W[g] * half * angular_h(px * px + py * py);
                }
        }
        sum += cr * acc;
    }
    return sum;
}

static bool angular_outside(double x0, double x1, double y0, double y1)
{
    /* nearest point of the texel to the centre: outside the disc, nothing */
    double nx = x0 > 0 ? x0 : x1 < 0 ? x1 : 0, ny = y0 > 0 ? y0 : y1 < 0 ? y1 : 0;
    return nx * nx + ny * ny >= 1;
}

static double angular_texel(uint32_t w, uint32_t h, uint32_t i, uint32_t j)
{
    double x0 = 2.0 * i / w - 1, x1 = 2.0 * (i + 1) / w - 1;
    double y1 = 1 - 2.0 * j / h, y0 = 1 - 2.0 * (j + 1) / h; /* y0 < y1 */
    if (angular_outside(x0, x1, y0, y1))
        return 0;
    double s = angular_edge(x0, y0, x1, y0) + angular_edge(x1, y0, x1, y1) +
               angular_edge(x1, y1, x0, y1) + angular_edge(x0, y1, x0, y0);
    return s > 0 ? s : 0;
}

/* The whole table: each edge integral once (a texel's bottom edge is the top edge of the
 * texel below it, with the opposite orientation), so half the work of texel by texel. */
static int angular_table(uint32_t w, uint32_t h, float *out)
{
    /* row edges: at y = b_j (j = 0..h), from x_i to x_i+1, rightwards;
     * column edges: at x = a_i (i = 0..w), from b_j+1 up to b_j */
    double *eh = malloc(sizeof(double) * ((size_t)(h + 1) * w + (size_t)(w + 1) * h));
    if (!eh)
        return LG_ERR_NOMEM;
    double *ev = eh + (size_t)(h + 1) * w;
    for (uint32_t j = 0; j <= h; j++) {
        double y = 1 - 2.0 * j / h;
        for (uint32_t i = 0; i < w; i++)
            eh[(size_t)j * w + i] = angular_edge(2.0 * i / w - 1, y, 2.0 * (i + 1) / w - 1, y);
    }
    for (uint32_t i = 0; i <= w; i++) {
        double x = 2.0 * i / w - 1;
        for (uint32_t j = 0; j < h; j++)
            ev[(size_t)i * h + j] = angular_edge(x, 1 - 2.0 * (j + 1) / h, x, 1 - 2.0 * j / h);
    }
    for (uint32_t j = 0; j < h; j++)
        for (uint32_t i = 0; i < w; i++) {
            double x0 = 2.0 * i / w - 1, x1 = 2.0 * (i + 1) / w - 1;
            double y1 = 1 - 2.0 * j / h, y0 = 1 - 2.0 * (j + 1) / h;
            double s = 0;
            if (!angular_outside(x0, x1, y0, y1))
                /* counterclockwise: bottom (row j+1) rightwards, right edge up, top (row
                 * j) leftwards, left edge down */
                s = eh[(size_t)(j + 1) * w + i] + ev[(size_t)(i + 1) * h + j] -
                    eh[(size_t)j * w + i] - ev[(size_t)i * h + j];
            out[(size_t)j * w + i] = (float)(s > 0 ? s : 0);
        }
    free(eh);
    return 0;
}

static bool valid_size(lg_probe_layout layout, uint32_t w, uint32_t h)
{
    if (w == 0 || h == 0)
        return false;
    if (layout == LG_PROBE_CUBE)
        return w == h;
    return layout == LG_PROBE_LATLONG || layout == LG_PROBE_ANGULAR;
}

static double latlong_row(uint32_t w, uint32_t h, uint32_t j)
{
    /* cos a - cos b = 2 sin((a + b)/2) sin((b - a)/2): no cancellation near the poles */
    return 2 * LG_PI / w * 2 * sin(LG_PI * (j + 0.5) / h) * sin(0.5 * LG_PI / h);
}

static double cube_texel(uint32_t n, uint32_t i, uint32_t j)
{
    double x0 = 2.0 * i / n - 1, x1 = 2.0 * (i + 1) / n - 1;
    double y0 = 2.0 * j / n - 1, y1 = 2.0 * (j + 1) / n - 1;
    return fabs(cube_area(x0, y0) - cube_area(x0, y1) - cube_area(x1, y0) + cube_area(x1, y1));
}

double lg_probe_texel_solid_angle(lg_probe_layout layout, uint32_t width, uint32_t height,
                                  uint32_t face, uint32_t i, uint32_t j)
{
    if (!valid_size(layout, width, height) || i >= width || j >= height ||
        face >= (layout == LG_PROBE_CUBE ? 6u : 1u))
        return 0;
    switch (layout) {
    case LG_PROBE_LATLONG: return latlong_row(width, height, j);
    case LG_PROBE_CUBE: return cube_texel(width, i, j);
    default: return angular_texel(width, height, i, j);
    }
}

int lg_probe_solid_angles(lg_probe_layout layout, uint32_t width, uint32_t height, float *out)
{
    if (!valid_size(layout, width, height) || !out)
        return LG_ERR_INVALID;
    size_t wh = (size_t)width * height;
    switch (layout) {
    case LG_PROBE_LATLONG:
        for (uint32_t j = 0; j < height; j++) {
            float s = (float)latlong_row(width, height, j);
            for (uint32_t i = 0; i < width; i++)
                out[(size_t)j * width + i] = s;
        }
        break;
    case LG_PROBE_CUBE:
        /* every face alike, and each face symmetric in both axes */
        for (uint32_t j = 0; j < height; j++)
            for (uint32_t i = 0; i < width; i++) {
                uint32_t ii = i < width - 1 - i ? i : width - 1 - i;
                uint32_t jj = j < height - 1 - j ? j : height - 1 - j;
                out[(size_t)j * width + i] = (ii != i || jj != j) /* mirror done */
                                                 ? out[(size_t)jj * width + ii]
                                                 : (float)cube_texel(width, i, j);
            }
        for (int f = 1; f < 6; f++)
            memcpy(out + f * wh, out, wh * sizeof *out);
        break;
    default: return angular_table(width, height, out);
    }
    return 0;
}

/* ---- lookups --------------------------------------------------------------------------------- */

static inline const float *texel(const lg_probe_image *img, uint32_t face, uint32_t i, uint32_t j)
{
    return img->rgba + 4 * (((size_t)face * img->height + j) * img->width + i);
}

/* a + (b - a) f: exactly a where a == b, so that a constant probe reads back exactly its
 * constant (the GLSL and CL twins interpolate the same way) */
static inline void lerp4(float *o, const float *a, const float *b, float f)
{
    for (int k = 0; k < 4; k++)
        o[k] = a[k] + (b[k] - a[k]) * f;
}

/* The 2x2 footprint t[0..3] = (i0, j0), (i0+1, j0), (i0, j0+1), (i0+1, j0+1). */
static inline void bilerp4(float *o, const float *const t[4], float fx, float fy)
{
    float r0[4], r1[4];
    lerp4(r0, t[0], t[1], fx);
    lerp4(r1, t[2], t[3], fx);
    lerp4(o, r0, r1, fy);
}

static inline uint32_t clampi(int64_t i, uint32_t n)
{
    return i < 0 ? 0u : i >= (int64_t)n ? n - 1 : (uint32_t)i;
}

static inline uint32_t wrapi(int64_t i, uint32_t n)
{
    int64_t m = i % (int64_t)n;
    return (uint32_t)(m < 0 ? m + n : m);
}

/* One lat-long row (already inside [0, H)) at column coordinate x (texel centres at
 * integers), linear in x with wrap. */
static inline void latlong_row_lerp(const lg_probe_image *img, uint32_t j, float x, float *o)
{
    float fl = floorf(x);
    float fx = x - fl;
    int64_t i0 = (int64_t)fl;
    lerp4(o, texel(img, 0, wrapi(i0, img->width), j), texel(img, 0, wrapi(i0 + 1, img->width), j),
          fx);
}

static void latlong_bilinear(const lg_probe_image *img, lg_probe_coord c, float *o)
{
    uint32_t W = img->width, H = img->height;
    float x = c.u * (float)W - 0.5f, y = c.v * (float)H - 0.5f;
    float fy0 = floorf(y);
    float fy = y - fy0;
    int64_t j0 = (int64_t)fy0;
    float rows[2][4];
    for (int k = 0; k < 2; k++) {
        int64_t j = j0 + k;
        float xx = x;
        /* beyond a pole: the same ring of texels, half a turn away */
        if (j < 0) {
            j = -1 - j;
            xx = x + 0.5f * (float)W;
        } else if (j >= (int64_t)H) {
            j = 2 * (int64_t)H - 1 - j;
            xx = x + 0.5f * (float)W;
        }
        latlong_row_lerp(img, clampi(j, H), xx, rows[k]);
    }
    lerp4(o, rows[0], rows[1], fy);
}

static void angular_bilinear(const lg_probe_image *img, lg_probe_coord c, float *o)
{
    float x = c.u * (float)img->width - 0.5f, y = c.v * (float)img->height - 0.5f;
    float flx = floorf(x), fly = floorf(y);
    float fx = x - flx, fy = y - fly;
    int64_t i0 = (int64_t)flx, j0 = (int64_t)fly;
    const float *t[4];
    for (int k = 0; k < 4; k++)
        t[k] = texel(img, 0, clampi(i0 + (k & 1), img->width), clampi(j0 + (k >> 1), img->height));
    bilerp4(o, t, fx, fy);
}

/* A texel of the 2x2 footprint beyond the edge of `face`: the direction of its centre on
 * the face's plane extended, looked up again, lands in the neighbouring face's edge
 * texel (the extended centre is less than half a texel from that texel's centre). */
static const float *cube_beyond(const lg_probe_image *img, uint32_t face, int64_t i, int64_t j)
{
    uint32_t n = img->width;
    float sc = 2.0f * ((float)i + 0.5f) / (float)n - 1.0f;
    float tc = 2.0f * ((float)j + 0.5f) / (float)n - 1.0f;
    lg_probe_coord c = lg_probe_cube_coord(lg_probe_cube_plane_dir(face, sc, tc));
    return texel(img, c.face, clampi((int64_t)floorf(c.u * (float)n), n),
                 clampi((int64_t)floorf(c.v * (float)n), n));
}

static void cube_bilinear(const lg_probe_image *img, lg_probe_coord c, float *o)
{
    uint32_t n = img->width;
    float x = c.u * (float)n - 0.5f, y = c.v * (float)n - 0.5f;
    float flx = floorf(x), fly = floorf(y);
    float fx = x - flx, fy = y - fly;
    int64_t i0 = (int64_t)flx, j0 = (int64_t)fly;
    const float *t[4];
    int corner = -1;
    for (int k = 0; k < 4; k++) {
        int64_t i = i0 + (k & 1), j = j0 + (k >> 1);
        bool in_i = i >= 0 && i < (int64_t)n, in_j = j >= 0 && j < (int64_t)n;
        if (in_i && in_j)
            t[k] = texel(img, c.face, (uint32_t)i, (uint32_t)j);
        else if (in_i || in_j)
            t[k] = cube_beyond(img, c.face, i, j);
        else {
            t[k] = NULL;
            corner = k;
        }
    }
    float cornerv[4];
    if (corner >= 0) {
        /* the mean of the three others, as a + (b - a) / 3 + (c - a) / 3: exactly a when
         * all three are equal, and each third at most a third of the float range, so a
         * texel at FLT_MAX beside a 0 gives a finite mean ((b - a) + (c - a) would
         * overflow to Inf there: reflect's non-finite pixels under a clamped probe) */
        const float *a = t[corner ^ 1], *b = t[corner ^ 2], *d = t[corner ^ 3];
        for (int k = 0; k < 4; k++)
            cornerv[k] = a[k] + (b[k] - a[k]) * (1.0f / 3.0f) + (d[k] - a[k]) * (1.0f / 3.0f);
        t[corner] = cornerv;
    }
    bilerp4(o, t, fx, fy);
}

void lg_probe_lookup(const lg_probe_image *img, lg_vec3 dir, lg_probe_sampling sampling,
                     float out[4])
{
    out[0] = out[1] = out[2] = out[3] = 0;
    if (!img || !img->rgba || img->width == 0 || img->height == 0)
        return;
    if (img->layout == LG_PROBE_CUBE && img->width != img->height)
        return;
    lg_vec3 d = lg_probe_from_world(img->rotation, dir);
    lg_probe_coord c = lg_probe_dir_to_coord(img->layout, d);
    if (sampling == LG_PROBE_NEAREST) {
        int64_t i = (int64_t)floorf(c.u * (float)img->width);
        int64_t j = (int64_t)floorf(c.v * (float)img->height);
        uint32_t ii = img->layout == LG_PROBE_LATLONG ? wrapi(i, img->width)
                                                      : clampi(i, img->width);
        const float *t = texel(img, c.face, ii, clampi(j, img->height));
        memcpy(out, t, 4 * sizeof *out);
        return;
    }
    switch (img->layout) {
    case LG_PROBE_LATLONG: latlong_bilinear(img, c, out); break;
    case LG_PROBE_CUBE: cube_bilinear(img, c, out); break;
    default: angular_bilinear(img, c, out); break;
    }
}

/* ---- probes as image files ------------------------------------------------------------------- */

bool lg_probe_file_cell(lg_probe_file_layout file, uint32_t face, uint32_t *cx, uint32_t *cy,
                        bool *turn)
{
    /* (cx, cy, turn) per face, GL order; docs/probes.md draws them */
    static const uint8_t cells[5][6][3] = {
        { { 2, 1, 0 },
          { 0, 1, 0 },
          { 1, 0, 0 },
          { 1, 2, 0 },
          { 1, 1, 0 },
          { 3, 1, 0 } }, /* DEFAULT */
        { { 2, 1, 0 },
          { 0, 1, 0 },
          { 1, 0, 0 },
          { 1, 2, 0 },
          { 1, 1, 0 },
          { 3, 1, 0 } }, /* CROSS */
        { { 2, 1, 0 },
          { 0, 1, 0 },
          { 1, 0, 0 },
          { 1, 2, 0 },
          { 1, 1, 0 },
          { 1, 3, 1 } }, /* VCROSS */
        { { 0, 0, 0 },
          { 1, 0, 0 },
          { 2, 0, 0 },
          { 3, 0, 0 },
          { 4, 0, 0 },
          { 5, 0, 0 } }, /* STRIP */
        { { 0, 0, 0 },
          { 0, 1, 0 },
          { 0, 2, 0 },
          { 0, 3, 0 },
          { 0, 4, 0 },
          { 0, 5, 0 } }, /* VSTRIP */
    };
    if ((unsigned)file > LG_PROBE_FILE_VSTRIP || face > 5)
        return false;
    *cx = cells[file][face][0];
    *cy = cells[file][face][1];
    *turn = cells[file][face][2] != 0;
    return true;
}

static bool is_identity(const float r[9])
{
    for (int k = 0; k < 9; k++)
        if (r[k] != (k % 4 == 0 ? 1.0f : 0.0f))
            return false;
    return true;
}

int lg_probe_pack(const lg_probe_info *info, uint32_t width, uint32_t height, const float *rgba,
                  lg_image *out, char *err, size_t errlen)
{
    memset(out, 0, sizeof *out);
    if (!info || !rgba || !valid_size(info->layout, width, height)) {
        snprintf(err, errlen, "not a probe level 0 of a known layout and size (%ux%u)", width,
                 height);
        return LG_ERR_INVALID;
    }
    if (!is_identity(info->rotation)) {
        snprintf(err, errlen,
                 "the probe has a rotation (rotate_deg) that an image file cannot "
                 "hold: write it through probe_convert, which bakes the rotation into the "
                 "texels");
        return LG_ERR_INVALID;
    }
    if (info->layout != LG_PROBE_CUBE) {
        if (lg_image_alloc(out, width, height)) {
            snprintf(err, errlen, "out of memory (a %ux%u image)", width, height);
            return LG_ERR_NOMEM;
        }
        memcpy(out->pixels, rgba, (size_t)width * height * 16);
        return 0;
    }
    lg_probe_file_layout file = (lg_probe_file_layout)info->file_layout;
    if ((unsigned)file > LG_PROBE_FILE_VSTRIP) {
        snprintf(err, errlen, "unknown file layout %u in the probe's info", info->file_layout);
        return LG_ERR_INVALID;
    }
    uint32_t n = width;
    uint32_t cw = file == LG_PROBE_FILE_VCROSS   ? 3
                  : file == LG_PROBE_FILE_STRIP  ? 6
                  : file == LG_PROBE_FILE_VSTRIP ? 1
                                                 : 4;
    uint32_t ch = file == LG_PROBE_FILE_VCROSS   ? 4
                  : file == LG_PROBE_FILE_STRIP  ? 1
                  : file == LG_PROBE_FILE_VSTRIP ? 6
                                                 : 3;
    if ((uint64_t)n * cw > 65536 || (uint64_t)n * ch > 65536 ||
        lg_image_alloc(out, n * cw, n * ch)) {
        snprintf(err, errlen, "cannot make a %ux%u image for a cube of face %u", n * cw, n * ch, n);
        return LG_ERR_NOMEM;
    }
    /* lg_image_alloc zeroes: unused cells are black, alpha 0 */
    for (uint32_t f = 0; f < 6; f++) {
        uint32_t cx, cy;
        bool turn;
        lg_probe_file_cell(file, f, &cx, &cy, &turn);
        const float *face = rgba + (size_t)4 * f * n * n;
        for (uint32_t y = 0; y < n; y++)
            for (uint32_t x = 0; x < n; x++) {
                uint32_t sx = turn ? n - 1 - x : x, sy = turn ? n - 1 - y : y;
                float *d = out->pixels + 4 * ((size_t)(cy * n + y) * out->width + cx * n + x);
                memcpy(d, face + 4 * ((size_t)sy * n + sx), 16);
            }
    }
    return 0;
}
