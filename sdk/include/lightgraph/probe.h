/*
 * lightgraph/probe.h: the light-probe resource (LG_KIND_PROBE), since ABI 2.0.
 *
 * An HDR environment (radiance arriving from every direction, linear, in the scene's
 * units) with its layout, a world rotation and an intensity scale. Its parts
 * (lightgraph/kinds.h):
 *
 *   radiance     image: 2D for LG_PROBE_LATLONG and LG_PROBE_ANGULAR, a cube
 *                (LG_IMAGE_CUBE, OpenGL's face order and orientation) for LG_PROBE_CUBE;
 *                level 0 is the environment, further levels (if any) a prefiltered chain
 *                whose meaning lg_probe_info.filter states
 *   solid_angle  optional buffer: float steradians per texel of level 0 (every face), in
 *                the radiance image's texel order; sums over the sphere to 4 pi
 *   info         meta: lg_probe_info
 *
 * Directions are world directions with +Y up. A texel's direction in the probe's own
 * frame, d_probe, maps to the world as d_world = rotation * d_probe (lg_probe_info.rotation;
 * lg_probe_rotation_from_euler makes one). The conventions below are the only ones in
 * lightgraph: the C functions of this header, shaders/common/probe.glsl and
 * shaders/common/probe.cl implement them, and docs/probes.md draws them.
 *
 * Texture coordinates. A direction lands on a face (0 for the 2D layouts; 0..5 for the
 * cube in the order +X, -X, +Y, -Y, +Z, -Z) at continuous coordinates (u, v) in [0, 1]:
 * u to the right, v down, texel (i, j) of a W x H image covering [i/W, (i+1)/W] x
 * [j/H, (j+1)/H] (row 0 at the top, the first row in memory); its centre is
 * ((i + 0.5)/W, (j + 0.5)/H).
 *
 *   lat-long: phi = 2 pi (u - 0.5), theta = pi v measured from +Y,
 *     d = (sin theta sin phi, cos theta, -sin theta cos phi): the centre looks along -Z,
 *     u = 0.75 along +X, u = 0.25 along -X, the left and right edges along +Z (the seam),
 *     the top row is +Y; seen from inside, the panorama is not mirrored. Inverse:
 *     phi = atan2(x, -z) (0 at the poles, where x = z = 0), theta = atan2(sqrt(x^2+z^2), y).
 *     Any W x H (not only 2:1).
 *   angular (Debevec): a = 2u - 1 (right), b = 1 - 2v (up), r = sqrt(a^2 + b^2);
 *     theta = pi r is the angle from -Z, and d = (a/r sin theta, b/r sin theta, -cos theta):
 *     the centre looks along -Z, right is +X, up is +Y, the rim (r = 1) is +Z. Inverse
 *     with theta = atan2(sqrt(x^2+y^2), -z); near the centre (sqrt(x^2+y^2) < 1e-4) the
 *     factor theta/sqrt(x^2+y^2) is its limit 1/(-z), so there is no division by a
 *     vanishing radius and no acos. +Z itself (the rim, every point of it) maps to the
 *     bottom of the rim, (u, v) = (0.5, 1). Coordinates outside the unit disc (r > 1,
 *     the image's corners) have the direction +Z: they are not part of the sphere, their
 *     solid angle is 0.
 *   cube: OpenGL's convention (the GL 4.5 specification, table 8.19): the major axis is
 *     the component of largest magnitude (ties: X before Y before Z), then
 *         face   major  sc   tc        face   major  sc   tc
 *         +X      x    -z   -y          -X     -x   +z   -y
 *         +Y      y    +x   +z          -Y     -y   +x   -z
 *         +Z      z    +x   -y          -Z     -z   -x   -y
 *     u = (sc/|ma| + 1)/2, v = (tc/|ma| + 1)/2; v grows with the row index, so that the
 *     faces uploaded row 0 first (glTexImage2D / glTextureSubImage3D) sample the same in
 *     a GL cube texture. Every face is square (W == H).
 *
 * Direction arguments need not be unit: every function that takes one normalises it
 * first (lg_probe_safe_dir). A zero vector, one whose components are all below 1e-30 in
 * magnitude (denormals: a GPU flushes them to zero, so every device treats them alike),
 * or one with a NaN or infinite component means LG_PROBE_FALLBACK_DIR, -Z (the lat-long
 * and angular centre): a defined texel, never a NaN.
 *
 * Solid angles are exact (computed in double, stored as float): their sum over a layout
 * is 4 pi within float rounding (tests/unit/probe measures 3e-8 relative or better), so a
 * sum of radiance times solid angle is an integral over the sphere:
 *   lat-long  every texel of row j: (2 pi / W) (cos theta_j - cos theta_j+1),
 *             theta_j = pi j / H;
 *   cube      texel [x0, x1] x [y0, y1] of a face in its plane at distance 1 (x, y in
 *             [-1, 1]): A(x0,y0) - A(x0,y1) - A(x1,y0) + A(x1,y1) with
 *             A(x, y) = atan2(x y, sqrt(x^2 + y^2 + 1)), the same for every face;
 *   angular   the integral over the part of the texel inside the unit disc of the map's
 *             Jacobian pi sin(pi r) / r (texels outside the disc: 0; texels on the rim:
 *             only their covered part), evaluated exactly as the line integral of
 *             (1 - cos(pi min(r, 1))) dphi around the texel (Green's theorem: a closed form
 *             where the edge lies outside the disc, Gauss-Legendre quadrature to double
 *             precision inside).
 *
 * Lookups (lg_probe_lookup; the GLSL and CL twins do the same):
 *   nearest   the texel containing (u, v) (clamped to the image; lat-long u wraps).
 *   bilinear  the four texels around (u, v), weights from the distance to their centres;
 *     lat-long: columns wrap (the seam at u = 0 / 1 is invisible); a row beyond the top
 *       (bottom) is the first (last) row continued across the pole, at phi + pi: the
 *       row above row 0 at u is row 0 at u + 0.5, interpolated there. Exactly at a pole
 *       the result is the mean of row 0 at u and at u + 0.5: continuous along every
 *       meridian, as a bilinear lat-long lookup can be;
 *     angular: GL's clamp-to-edge bilinear filter on the image;
 *     cube: GL's seamless cube filtering (GL_TEXTURE_CUBE_MAP_SEAMLESS): a texel of the
 *       2x2 footprint beyond a face edge is found by extending the face's plane: the
 *       direction of that texel's centre is looked up again, which lands in the edge
 *       texel of the neighbouring face; the corner texel beyond two edges (which no face
 *       holds) is the mean of the three others, the specification's recommended rule.
 *       The result is continuous across edges and corners; a samplerCube with seamless
 *       filtering on gives the same (tests/unit/probe).
 *   Interpolation is a + (b - a) f (a cube corner's mean a + (b - a) / 3 + (c - a) / 3):
 *   a constant probe reads back exactly its constant, and finite texels of one sign
 *   (FLT_MAX beside 0 included) never give a non-finite value.
 *   A 1 x 1 lat-long or angular image gives its one texel everywhere; a 1 x 1 cube its
 *   face's texel along the face's axis, blending into the neighbouring faces toward the
 *   edges (a corner: the mean of its three faces). Lookups do not apply
 *   lg_probe_info.scale (the texels already carry it).
 *
 * Cost (tests/unit/probe `probe_cost` prints them; docs/probes.md has the table): on one
 * thread of a loaded 2-core x86-64 VM, 40 ns per texel direction, 40 to 90 ns per
 * direction -> coordinates, 140 to 280 ns per lookup of a random direction into a
 * multi-megabyte image (cache misses included), 20 ns per texel for the lat-long and cube
 * solid-angle tables and 400 ns for the angular one (compute it once per probe).
 *
 * Thread safety: every function here is pure (no state); call it from any thread.
 */
#ifndef LIGHTGRAPH_PROBE_H
#define LIGHTGRAPH_PROBE_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "lightgraph/config.h"
#include "lightgraph/host.h"
#include "lightgraph/image.h"
#include "lightgraph/vecmath.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef enum lg_probe_layout {
    LG_PROBE_LATLONG = 1,
    LG_PROBE_ANGULAR,
    LG_PROBE_CUBE,
} lg_probe_layout;

/* What the levels above 0 hold. */
typedef enum lg_probe_filter {
    LG_PROBE_FILTER_NONE = 0, /* a plain box-filtered mip chain (or no chain) */
    LG_PROBE_FILTER_GGX,      /* level l of L prefiltered for GGX (alpha = roughness^2)
                               * of perceptual roughness l / (L - 1): level 0 is the probe
                               * itself, the last level roughness 1 (the ibl plugin makes
                               * such chains: plugins/ibl/ggx_prefilter.h) */
} lg_probe_filter;

/* How a probe is laid out in an image file (lg_probe_info.file_layout; lg_probe_pack).
 * A cube is one layout in memory (LG_PROBE_CUBE) and several in files; the one a probe
 * was read from, or that probe_convert was asked for, is remembered so that an `output`
 * statement writes the probe back that way. For LG_PROBE_LATLONG and LG_PROBE_ANGULAR
 * the file is the image itself and this field is ignored. Cells of a cross, in face-size
 * units (x right, y down), with the face order +X, -X, +Y, -Y, +Z, -Z:
 *
 *   horizontal cross (4N x 3N)        vertical cross (3N x 4N)
 *         .  +Y  .   .                      .  +Y  .
 *        -X  +Z  +X  -Z                    -X  +Z  +X
 *         .  -Y  .   .                      .  -Y  .
 *                                           .  -Z  .     (-Z turned by 180 degrees)
 *
 * Every face is stored as OpenGL orients it (row 0 of the face at the top of its cell),
 * except the vertical cross's -Z, turned by 180 degrees as cmft and HDRShop store it so
 * that its edge meets -Y's. Strips hold the faces left to right (6N x N) or top to bottom
 * (N x 6N) in the face order. */
typedef enum lg_probe_file_layout {
    LG_PROBE_FILE_DEFAULT = 0, /* lat-long and angular: the image; a cube: LG_PROBE_FILE_CROSS */
    LG_PROBE_FILE_CROSS,       /* horizontal cross, 4N x 3N */
    LG_PROBE_FILE_VCROSS,      /* vertical cross, 3N x 4N */
    LG_PROBE_FILE_STRIP,       /* 6x1 strip, 6N x N */
    LG_PROBE_FILE_VSTRIP,      /* 1x6 strip, N x 6N */
} lg_probe_file_layout;

/* The `info` part. */
typedef struct lg_probe_info {
    uint32_t struct_size; /* sizeof(lg_probe_info) */
    lg_probe_layout layout;
    float rotation[9]; /* probe -> world, column-major 3x3, orthonormal */
    float scale;       /* radiance multiplier already applied to the texels: 1 */
    lg_probe_filter filter;
    uint32_t filter_samples; /* LG_PROBE_FILTER_GGX: samples per texel it used */
    uint32_t filter_reserved;
    uint32_t file_layout; /* since ABI 2.2 (was reserved, so 0 = DEFAULT from older
                           * producers): an lg_probe_file_layout, how a cube is
                           * written to a file (lg_probe_pack) */
    uint32_t reserved[7];
} lg_probe_info;

/* What a consumer sees (lg_probe_get). */
typedef struct lg_probe {
    lg_probe_info info;
    const lg_resource *radiance;    /* map it on the device of choice */
    const lg_resource *solid_angle; /* NULL when the producer made none */
    lg_image_desc radiance_desc;    /* its size, format, levels, cube flag */
    void *reserved[4];
} lg_probe;

/* Producer, prepare(): declares output `port` with a radiance image of description
 * `radiance` (a cube, LG_IMAGE_CUBE, for LG_PROBE_CUBE; 2D otherwise) and, if
 * with_solid_angle, the solid-angle table of its level 0. */
LG_API int lg_probe_declare(lg_node *node, uint32_t port, lg_probe_layout layout,
                            const lg_image_desc *radiance, bool with_solid_angle);
/* Producer, execute(): writes the info part. The radiance (and solid angles) are the
 * caller's to write through lg_part(). */
LG_API int lg_probe_publish(lg_node *node, uint32_t port, const lg_probe_info *info);
/* Consumer: fills *out and returns it; NULL without an error for NULL or neutral, NULL
 * after lg_error for another kind or inconsistent parts. */
LG_API const lg_probe *lg_probe_get(lg_node *node, const lg_resource *res, lg_probe *out);

/* ---- conventions as code --------------------------------------------------------------------- */

/* Where a direction lands: face (0 for 2D layouts, 0..5 = +X, -X, +Y, -Y, +Z, -Z for the
 * cube) and continuous coordinates in [0, 1] (u right, v down), as described above. */
typedef struct lg_probe_coord {
    uint32_t face;
    float u, v;
} lg_probe_coord;

/* What a direction-less vector means (see above): -Z. */
#define LG_PROBE_FALLBACK_DIR lg_v3(0.0f, 0.0f, -1.0f)

/* Pi as a float: LG_PIF (lightgraph/vecmath.h) under the name the probe functions use. */
#define LG_PROBE_PI_F LG_PIF

/* Unit vector along d; zero, denormal-only, NaN or infinite input gives -Z. */
static inline lg_vec3 lg_probe_safe_dir(lg_vec3 d)
{
    return lg_v3_normalize_or(d, LG_PROBE_FALLBACK_DIR);
}

/* Cube: face and (u, v) of a direction (any length but not zero: callers go through
 * lg_probe_safe_dir first). */
static inline lg_probe_coord lg_probe_cube_coord(lg_vec3 d)
{
    float ax = fabsf(d.x), ay = fabsf(d.y), az = fabsf(d.z);
    float sc, tc, ma;
    uint32_t face;
    if (ax >= ay && ax >= az) {
        face = d.x >= 0 ? 0u : 1u;
        ma = ax;
        sc = d.x >= 0 ? -d.z : d.z;
        tc = -d.y;
    } else if (ay >= az) {
        face = d.y >= 0 ? 2u : 3u;
        ma = ay;
        sc = d.x;
        tc = d.y >= 0 ? d.z : -d.z;
    } else {
        face = d.z >= 0 ? 4u : 5u;
        ma = az;
        sc = d.z >= 0 ? d.x : -d.x;
        tc = -d.y;
    }
    lg_probe_coord c;
    c.face = face;
    c.u = 0.5f * (sc / ma + 1.0f);
    c.v = 0.5f * (tc / ma + 1.0f);
    return c;
}

/* Cube: the (not normalised) direction of face coordinates (sc, tc) in [-1, 1] (or
 * beyond, on the face's plane extended). */
static inline lg_vec3 lg_probe_cube_plane_dir(uint32_t face, float sc, float tc)
{
    switch (face) {
    case 0: return lg_v3(1.0f, -tc, -sc);
    case 1: return lg_v3(-1.0f, -tc, sc);
    case 2: return lg_v3(sc, 1.0f, tc);
    case 3: return lg_v3(sc, -1.0f, -tc);
    case 4: return lg_v3(sc, -tc, 1.0f);
    default: return lg_v3(-sc, -tc, -1.0f);
    }
}

/* Face and (u, v) of a direction of any length (lg_probe_safe_dir is applied). */
static inline lg_probe_coord lg_probe_dir_to_coord(lg_probe_layout layout, lg_vec3 d)
{
    d = lg_probe_safe_dir(d);
    lg_probe_coord c;
    c.face = 0;
    if (layout == LG_PROBE_CUBE)
        return lg_probe_cube_coord(d);
    if (layout == LG_PROBE_ANGULAR) {
        float rho = sqrtf(d.x * d.x + d.y * d.y);
        float k; /* r / rho = theta / (pi rho) */
        if (rho >= 1e-4f)
            k = atan2f(rho, -d.z) / (LG_PROBE_PI_F * rho);
        else if (d.z < 0)
            k = 1.0f / (LG_PROBE_PI_F * -d.z); /* atan(t)/t = 1 - t^2/3 + ..., t < 1e-4 */
        else if (rho > 0)
            k = atan2f(rho, -d.z) / (LG_PROBE_PI_F * rho);
        else {
            c.u = 0.5f; /* +Z: the bottom of the rim */
            c.v = 1.0f;
            return c;
        }
        c.u = 0.5f * (d.x * k + 1.0f);
        c.v = 0.5f * (1.0f - d.y * k);
        return c;
    }
    /* lat-long */
    float phi = (d.x == 0.0f && d.z == 0.0f) ? 0.0f : atan2f(d.x, -d.z);
    float theta = atan2f(sqrtf(d.x * d.x + d.z * d.z), d.y);
    c.u = phi * (0.5f / LG_PROBE_PI_F) + 0.5f;
    c.v = theta * (1.0f / LG_PROBE_PI_F);
    return c;
}

/* The unit direction at face coordinates c (any values: lat-long is periodic, angular
 * outside the disc gives +Z, the cube's plane is extended). */
static inline lg_vec3 lg_probe_coord_to_dir(lg_probe_layout layout, lg_probe_coord c)
{
    if (layout == LG_PROBE_CUBE)
        return lg_probe_safe_dir(
            lg_probe_cube_plane_dir(c.face, 2.0f * c.u - 1.0f, 2.0f * c.v - 1.0f));
    if (layout == LG_PROBE_ANGULAR) {
        float a = 2.0f * c.u - 1.0f, b = 1.0f - 2.0f * c.v;
        float r = sqrtf(a * a + b * b);
        if (!(r < 1.0f))
            return lg_v3(0.0f, 0.0f, 1.0f);
        float t = LG_PROBE_PI_F * r;
        /* sin(pi r) / r, its series near the centre */
        float s = r < 1e-4f ? LG_PROBE_PI_F * (1.0f - t * t * (1.0f / 6.0f)) : sinf(t) / r;
        return lg_v3(a * s, b * s, -cosf(t));
    }
    float phi = 2.0f * LG_PROBE_PI_F * (c.u - 0.5f), theta = LG_PROBE_PI_F * c.v;
    float st = sinf(theta);
    return lg_v3(st * sinf(phi), cosf(theta), -st * cosf(phi));
}

/* The direction of the centre of texel (i, j) of face `face` of a W x H level. */
static inline lg_vec3 lg_probe_texel_dir(lg_probe_layout layout, uint32_t width, uint32_t height,
                                         uint32_t face, uint32_t i, uint32_t j)
{
    lg_probe_coord c;
    c.face = face;
    c.u = ((float)i + 0.5f) / (float)width;
    c.v = ((float)j + 0.5f) / (float)height;
    return lg_probe_coord_to_dir(layout, c);
}

/* Probe <-> world with a rotation (probe -> world, column-major 3x3 as
 * lg_probe_info.rotation; NULL is the identity). */
static inline lg_vec3 lg_probe_to_world(const float *rotation, lg_vec3 d)
{
    if (!rotation)
        return d;
    const float *m = rotation;
    return lg_v3(m[0] * d.x + m[3] * d.y + m[6] * d.z, m[1] * d.x + m[4] * d.y + m[7] * d.z,
                 m[2] * d.x + m[5] * d.y + m[8] * d.z);
}
static inline lg_vec3 lg_probe_from_world(const float *rotation, lg_vec3 d)
{
    if (!rotation)
        return d;
    const float *m = rotation;
    return lg_v3(m[0] * d.x + m[1] * d.y + m[2] * d.z, m[3] * d.x + m[4] * d.y + m[5] * d.z,
                 m[6] * d.x + m[7] * d.y + m[8] * d.z);
}

/* The probe -> world rotation for yaw, pitch and roll in degrees:
 * R = Ry(yaw) Rx(pitch) Rz(roll), each a right-handed rotation about the world axis
 * (counterclockwise seen from the axis' positive end): roll first, about +Z (positive
 * roll turns the probe's up, +Y, toward -X), then pitch about +X (positive pitch raises
 * the probe's centre, -Z, toward +Y), then yaw about +Y (positive yaw turns the centre
 * toward -X, to the left seen from above). Angles are reduced modulo 360 first and
 * multiples of 90 degrees are exact, so 360 is the identity bit for bit. Non-finite
 * angles count as 0. Writes 9 floats, column-major (lg_probe_info.rotation). */
LG_API void lg_probe_rotation_from_euler(float yaw_deg, float pitch_deg, float roll_deg,
                                         float rotation[9]);

/* The solid angle (steradians) of texel (i, j) of face `face` of a W x H level 0 (for the
 * cube, W == H is the face size), computed in double as described above. 0 for a texel
 * outside the image or an invalid layout or size. */
LG_API double lg_probe_texel_solid_angle(lg_probe_layout layout, uint32_t width, uint32_t height,
                                         uint32_t face, uint32_t i, uint32_t j);

/* Fills `out` with the solid angle of every texel of a W x H level 0 in the radiance
 * image's texel order (face, then row 0 first, then column): W * H floats for the 2D
 * layouts, 6 * W * W for the cube (the `solid_angle` part). Returns 0, or LG_ERR_INVALID
 * for an unknown layout, a zero size or a cube with W != H. `out` is the caller's. */
LG_API int lg_probe_solid_angles(lg_probe_layout layout, uint32_t width, uint32_t height,
                                 float *out);

/* A level of a probe on the CPU, for lookups. The struct need only live for the call. */
typedef struct lg_probe_image {
    lg_probe_layout layout;
    uint32_t width, height; /* the level's size; a cube's face size (width == height) */
    const float *rgba;      /* RGBA float texels, W*H (2D) or 6*W*H (cube: faces in
                             * order, each row 0 first), e.g. lg_image_offset() into a
                             * mapped radiance image */
    const float *rotation;  /* probe -> world (lg_probe_info.rotation), NULL = identity */
    uint32_t reserved[4];
} lg_probe_image;

/* The lg_probe_image of `level` of a radiance image mapped on the CPU (`rgba`: the start
 * of its colour data, every level packed as lg_image_offset says); `rotation` as in
 * lg_probe_image. A level past the last gives an empty image (lookups read 0). */
static inline lg_probe_image lg_probe_image_at(lg_probe_layout layout, const lg_image_desc *desc,
                                               const float *rgba, uint32_t level,
                                               const float *rotation)
{
    lg_probe_image img;
    memset(&img, 0, sizeof img);
    img.layout = layout;
    img.rotation = rotation;
    if (!desc || !rgba || level >= lg_image_levels(desc))
        return img;
    img.width = lg_image_level_width(desc, level);
    img.height = lg_image_level_height(desc, level);
    img.rgba = rgba + 4 * lg_image_offset(desc, level, 0);
    return img;
}

typedef enum lg_probe_sampling {
    LG_PROBE_NEAREST = 0,
    LG_PROBE_BILINEAR,
} lg_probe_sampling;

/* The radiance seen along world direction `dir` (any length; see lg_probe_safe_dir),
 * nearest or bilinear as described above. Writes RGBA to out. An image with a zero
 * size or no texels gives 0. */
LG_API void lg_probe_lookup(const lg_probe_image *img, lg_vec3 dir, lg_probe_sampling sampling,
                            float out[4]);

/* ---- probes as image files ------------------------------------------------------------------- */

/* Where face `face` (0..5, the GL order) of a cube sits in a file of layout `file` (a
 * cube layout; DEFAULT is the horizontal cross): its cell (*cx, *cy) in face-size units
 * and whether it is turned by 180 degrees there (*turn), as drawn above. Returns false
 * for a face or layout outside the enums. The `probe` node reads with this table and
 * lg_probe_pack writes with it, so the two are inverses. */
LG_API bool lg_probe_file_cell(lg_probe_file_layout file, uint32_t face, uint32_t *cx, uint32_t *cy,
                               bool *turn);

/* The image file of level 0 of a probe: lat-long and angular images as they are, a cube
 * assembled into info->file_layout (a cross's unused cells are black with alpha 0, which
 * marks them as no part of the sphere; the faces keep their alpha, 1 from the probe
 * node). `rgba`: level 0's texels as lg_probe_image holds them (width x height, a cube's
 * six faces one after the other), `width` and `height` level 0's size (a cube's face
 * size). The probe's scale is already in its texels; a rotation other than the identity
 * cannot be held by a file: that is LG_ERR_INVALID with the reason in err (probe_convert
 * bakes a rotation in). On success *out is the caller's (lg_image_free); reading it back
 * with the probe node (layout = auto) gives the same texels. Returns 0, LG_ERR_INVALID or
 * LG_ERR_NOMEM, with a message in err (errlen bytes) on failure. */
LG_API int lg_probe_pack(const lg_probe_info *info, uint32_t width, uint32_t height,
                         const float *rgba, lg_image *out, char *err, size_t errlen);

/* ---- resampling between layouts -------------------------------------------------------------- */

/* How lg_probe_resample reads the source. Zeroed (or a NULL pointer) means the defaults. */
typedef struct lg_probe_resample_opts {
    lg_probe_sampling sampling; /* LG_PROBE_NEAREST (default): the source is piecewise
                                 * constant on its texels, each destination texel gets the
                                 * area-weighted box mean of the source texels it covers:
                                 * the integral-preserving choice, measured below.
                                 * LG_PROBE_BILINEAR: the mean of the bilinear
                                 * reconstruction (smoother when upsampling; its integral
                                 * differs from the texel sum at second order) */
    uint32_t oversample;        /* sub-rectangles per source texel extent: 0 = 2 */
    uint32_t max_subdiv;        /* cap on the subdivision per axis: 0 = 64 (at most 1024) */
    uint32_t no_balance;        /* nonzero: skip the balancing (measurements only) */
    uint32_t reserved[3];
} lg_probe_resample_opts;

/* What a resampling measured (LG_PROBE_NEAREST; zero with bilinear). */
typedef struct lg_probe_resample_stats {
    uint64_t samples;       /* sub-rectangles read */
    uint64_t entries;       /* (destination, source) texel pairs that overlap */
    uint64_t unread;        /* source texels of nonzero solid angle no sub-rectangle
                             * read (their energy is lost): 0 unless max_subdiv caps */
    uint32_t max_subdiv;    /* the largest subdivision per axis used */
    uint32_t iterations;    /* balancing rounds run */
    double raw_area_error;  /* before balancing: sum over source texels of |solid angle
                             * received - exact solid angle|, over 4 pi */
    double raw_total_error; /* before balancing: the relative error of this image's
                             * integral (largest of R, G, B) that the received solid
                             * angles imply */
    double area_error;      /* the same two after balancing: the error of the result */
    double total_error;
    double reserved[4];
} lg_probe_resample_stats;

/* Area-weighted resampling of a probe level into another layout and size (or the same):
 * every destination texel receives the solid-angle-weighted mean of the source radiance
 * over the texel's footprint on the sphere, so that the integral of radiance (sum of
 * radiance x lg_probe_solid_angles) over the sphere, and over any region made of whole
 * destination texels, is the source's as far as the destination resolution allows.
 *
 * Method (docs/probes.md "Resampling"): each destination texel is split into kx x ky
 * sub-rectangles of its (u, v), kx and ky chosen per texel so that a sub-rectangle spans
 * at most 1/oversample of the source texel's local extent (in radians, where it lands on
 * the sphere: lat-long texels narrow toward the poles, cube texels toward the corners,
 * angular texels tangentially toward the rim), up to max_subdiv. Each sub-rectangle has
 * its own solid angle (lat-long: rows in closed form; cube: the corners' closed form; the
 * angular map: its Jacobian at the sub-rectangle's centre times its area, rescaled so
 * that a texel's weights sum to the texel's exact solid angle), which goes to the source
 * texels under the bounding box of its corners' images in proportion to their overlap.
 * The overlaps form a sparse matrix whose row sums are the destination texels' exact
 * solid angles; its columns (what each source texel hands out) are then balanced to the
 * source texels' exact solid angles by alternate column and row scaling (Sinkhorn, up to
 * 100 rounds): each source texel's energy is kept, each destination texel still averages
 * with weights summing to its own solid angle. A texel's value is the weighted mean of
 * its row: a constant probe stays exactly constant. The balancing's column step is
 * over-relaxed (factor^1.8), in double, to 1e-9 of 4 pi or 300 rounds, stopping early when
 * the residual has not fallen by 10% in 100 rounds. Angular destination texels outside
 * the disc are 0; a rim texel averages over its covered part only. Every channel (alpha
 * too) is resampled alike. LG_PROBE_BILINEAR skips the matrix (no balancing).
 *
 * Accuracy (measured; tests/unit/probe/test_probe_resample.c): the real probe
 * assets/probes/forest_1024x512.hdr through cube 256 and back keeps its total and each
 * octant's integral within 5e-6 relative; white noise over 4 decades (the adversarial
 * case) within 1.8e-5 through a cube (the 1e-4 oracle) and 2.8e-3 through the
 * angular map, whose rim texels the balancing cannot converge on (no matrix of that
 * sparsity meets both marginals there); one texel's energy within 1.6e-4.
 *
 * Cost: forest 1024x512 -> cube 256 about 7 s of CPU time on a loaded 2-core VM (the
 * overlap matrix about half, the balancing's up to 300 rounds the rest), divided among
 * the pool's threads by lg_probe_resample_pool; memory about 12 bytes per overlapping
 * texel pair (2 million here) plus 8 per texel of each side. For converters, not per
 * frame.
 *
 * src: the source level (its rotation, probe -> world, applies); layout, width, height:
 * the destination (cube: width == height, the face size); rotation: the destination's
 * probe -> world rotation (NULL = identity): texel direction d reads the source along
 * R_src^T R_dst d, so resampling with rotation NULL bakes the source's rotation in.
 * out: 4 floats per destination texel in the radiance image's order (faces, rows from
 * row 0, columns), the caller's. opts and stats may be NULL.
 * Returns 0, LG_ERR_INVALID (unknown layout, zero size, a side above 65536 or a cube that
 * is not square, on either side; no pixels) or LG_ERR_NOMEM. Pure and re-entrant; runs on
 * the calling thread (lg_probe_resample_pool with NULL). */
LG_API int lg_probe_resample(const lg_probe_image *src, lg_probe_layout layout, uint32_t width,
                             uint32_t height, const float *rotation,
                             const lg_probe_resample_opts *opts, float *out,
                             lg_probe_resample_stats *stats);

/* lg_probe_resample on the host's thread pool (lightgraph/host.h, lg_parallel_for) of node
 * `pool`, from its execute() or prepare(); NULL runs on the calling thread. The work is
 * cut into chunks that depend on the sizes only (destination rows for the overlap matrix,
 * entries and texels for the balancing), each chunk writes only what it owns, and the
 * sums across chunks are made in one fixed order: the result is bit for bit the same on
 * any number of threads (tests/plugins/probe `convert_threads`). Besides LG_ERR_INVALID
 * and LG_ERR_NOMEM it returns LG_ERR_INVALID when the pool refuses the work (it has then
 * reported why through the node). */
LG_API int lg_probe_resample_pool(lg_node *pool, const lg_probe_image *src, lg_probe_layout layout,
                                  uint32_t width, uint32_t height, const float *rotation,
                                  const lg_probe_resample_opts *opts, float *out,
                                  lg_probe_resample_stats *stats);

/* Since ABI 2.7. The working memory, in bytes, that lg_probe_resample (LG_PROBE_NEAREST)
 * needs to resample `src_texels` texels (every face of a cube counted) into `dst_texels`:
 * 20 bytes per source texel (its solid angle, received area and balancing factor), 16 per
 * destination texel (row sums and starts) and 24 per overlapping texel pair (the chunks'
 * matrices and the merged one, 12 bytes each), with at least max(src, dst) pairs, since
 * every texel of either side overlaps one of the other. A lower bound, within about 2x of
 * what a resampling of very different sizes takes; the caller's `out` is not included. For
 * checking in prepare() against lg_memory_available (lightgraph/image.h) before a
 * resampling of a large probe runs. */
LG_API uint64_t lg_probe_resample_bytes(uint64_t src_texels, uint64_t dst_texels);

#ifdef __cplusplus
}
#endif
#endif
