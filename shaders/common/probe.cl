// shaders/common/probe.cl: the probe conventions of lightgraph/probe.h in OpenCL C 1.2
// (docs/probes.md). The C functions of probe.h and shaders/common/probe.glsl are its
// twins; tests/unit/probe holds the three together.
//
// Embedded byte for byte (tools/embed.py: lg_src_probe_cl); a kernel that uses it is
// built from this text followed by its own, joined by lg_cl_source_join
// (lightgraph/cl.h): OpenCL has no #include of embedded text.
//
// Images are buffers of float4 laid out as the CPU copy of a radiance image
// (lg_image_offset): W*H texels for the 2D layouts, 6 faces of W*W for the cube (+X, -X,
// +Y, -Y, +Z, -Z), each face row 0 first. Coordinates are float3(u, v, face).
//
//   float4 lg_probe_lookup(global const float4 *rgba, int layout, int w, int h,
//                          float3 dir, int bilinear)
//     the lookup of lg_probe_lookup (nearest or bilinear), dir in the probe's frame
//     (lg_probe_from_world(c0, c1, c2, dir) first for a world direction, with the
//     columns of lg_probe_info.rotation).
#ifndef LG_PROBE_CL
#define LG_PROBE_CL

#define LG_PROBE_LATLONG 1
#define LG_PROBE_ANGULAR 2
#define LG_PROBE_CUBE 3

#define LG_PROBE_PI 3.14159265358979323846f

inline int lg_probe_nonfinite(float x)
{
    return (as_uint(x) & 0x7f800000u) == 0x7f800000u;
}

// Unit vector along d; zero, denormal-only (below 1e-30), NaN or infinite -> -Z.
inline float3 lg_probe_safe_dir(float3 d)
{
    if (lg_probe_nonfinite(d.x) || lg_probe_nonfinite(d.y) || lg_probe_nonfinite(d.z))
        return (float3)(0.0f, 0.0f, -1.0f);
    float m = fmax(fabs(d.x), fmax(fabs(d.y), fabs(d.z)));
    if (!(m > 1e-30f))
        return (float3)(0.0f, 0.0f, -1.0f);
    d *= 1.0f / m;
    return d * (1.0f / sqrt(d.x * d.x + d.y * d.y + d.z * d.z));
}

// world -> probe: c0, c1, c2 are the columns of lg_probe_info.rotation (probe -> world,
// column-major 3x3: c0 = (m[0], m[1], m[2]), ...); the result is its transpose times d
inline float3 lg_probe_from_world(float3 c0, float3 c1, float3 c2, float3 d)
{
    return (float3)(dot(c0, d), dot(c1, d), dot(c2, d));
}

inline float3 lg_probe_cube_coord(float3 d)
{
    float ax = fabs(d.x), ay = fabs(d.y), az = fabs(d.z);
    float sc, tc, ma, face;
    if (ax >= ay && ax >= az) {
        face = d.x >= 0.0f ? 0.0f : 1.0f;
        ma = ax;
        sc = d.x >= 0.0f ? -d.z : d.z;
        tc = -d.y;
    } else if (ay >= az) {
        face = d.y >= 0.0f ? 2.0f : 3.0f;
        ma = ay;
        sc = d.x;
        tc = d.y >= 0.0f ? d.z : -d.z;
    } else {
        face = d.z >= 0.0f ? 4.0f : 5.0f;
        ma = az;
        sc = d.z >= 0.0f ? d.x : -d.x;
        tc = -d.y;
    }
    return (float3)(0.5f * (sc / ma + 1.0f), 0.5f * (tc / ma + 1.0f), face);
}

inline float3 lg_probe_cube_plane_dir(int face, float sc, float tc)
{
    switch (face) {
    case 0: return (float3)(1.0f, -tc, -sc);
    case 1: return (float3)(-1.0f, -tc, sc);
    case 2: return (float3)(sc, 1.0f, tc);
    case 3: return (float3)(sc, -1.0f, -tc);
    case 4: return (float3)(sc, -tc, 1.0f);
    default: return (float3)(-sc, -tc, -1.0f);
    }
}

inline float3 lg_probe_dir_to_coord(int layout, float3 d)
{
    d = lg_probe_safe_dir(d);
    if (layout == LG_PROBE_CUBE)
        return lg_probe_cube_coord(d);
    if (layout == LG_PROBE_ANGULAR) {
        float rho = sqrt(d.x * d.x + d.y * d.y);
        float k;
        if (rho >= 1e-4f)
            k = atan2(rho, -d.z) / (LG_PROBE_PI * rho);
        else if (d.z < 0.0f)
            k = 1.0f / (LG_PROBE_PI * -d.z);
        else if (rho > 0.0f)
            k = atan2(rho, -d.z) / (LG_PROBE_PI * rho);
        else
            return (float3)(0.5f, 1.0f, 0.0f);
        return (float3)(0.5f * (d.x * k + 1.0f), 0.5f * (1.0f - d.y * k), 0.0f);
    }
    float phi = (d.x == 0.0f && d.z == 0.0f) ? 0.0f : atan2(d.x, -d.z);
    float theta = atan2(sqrt(d.x * d.x + d.z * d.z), d.y);
    return (float3)(phi * (0.5f / LG_PROBE_PI) + 0.5f, theta * (1.0f / LG_PROBE_PI), 0.0f);
}

inline float3 lg_probe_coord_to_dir(int layout, float3 c)
{
    if (layout == LG_PROBE_CUBE)
        return lg_probe_safe_dir(lg_probe_cube_plane_dir((int)c.z, 2.0f * c.x - 1.0f,
                                                         2.0f * c.y - 1.0f));
    if (layout == LG_PROBE_ANGULAR) {
        float a = 2.0f * c.x - 1.0f, b = 1.0f - 2.0f * c.y;
        float r = sqrt(a * a + b * b);
        if (!(r < 1.0f))
            return (float3)(0.0f, 0.0f, 1.0f);
        float t = LG_PROBE_PI * r;
        float s = r < 1e-4f ? LG_PROBE_PI * (1.0f - t * t * (1.0f / 6.0f)) : sin(t) / r;
        return (float3)(a * s, b * s, -cos(t));
    }
    float phi = 2.0f * LG_PROBE_PI * (c.x - 0.5f), theta = LG_PROBE_PI * c.y;
    float st = sin(theta);
    return (float3)(st * sin(phi), cos(theta), -st * cos(phi));
}

inline int lg_probe_wrap(int i, int n)
{
    int m = i % n;
    return m < 0 ? m + n : m;
}

inline float4 lg_probe_texel(global const float4 *rgba, int w, int h, int face, int i, int j)
{
    return rgba[((size_t)face * h + j) * w + i];
}

// a + (b - a) f: exactly a where a == b (a constant probe reads back its constant), as on
// the CPU
inline float4 lg_probe_lerp(float4 a, float4 b, float f)
{
    return a + (b - a) * f;
}

inline float4 lg_probe_latlong_row(global const float4 *rgba, int w, int j, float x)
{
    float fl = floor(x);
    float fx = x - fl;
    int i0 = (int)fl;
    return lg_probe_lerp(rgba[(size_t)j * w + lg_probe_wrap(i0, w)],
                         rgba[(size_t)j * w + lg_probe_wrap(i0 + 1, w)], fx);
}

// A cube texel beyond the edge of `face`: its centre on the face's plane extended, looked
// up again (the neighbour's edge texel).
inline float4 lg_probe_cube_beyond(global const float4 *rgba, int n, int face, int i, int j)
{
    float sc = 2.0f * ((float)i + 0.5f) / (float)n - 1.0f;
    float tc = 2.0f * ((float)j + 0.5f) / (float)n - 1.0f;
    float3 c = lg_probe_cube_coord(lg_probe_cube_plane_dir(face, sc, tc));
    return lg_probe_texel(rgba, n, n, (int)c.z, clamp((int)floor(c.x * (float)n), 0, n - 1),
                          clamp((int)floor(c.y * (float)n), 0, n - 1));
}

inline float4 lg_probe_lookup(global const float4 *rgba, int layout, int w, int h, float3 dir,
                              int bilinear)
{
    float3 c = lg_probe_dir_to_coord(layout, dir);
    int face = (int)c.z;
    if (!bilinear) {
        int i = (int)floor(c.x * (float)w);
        int j = clamp((int)floor(c.y * (float)h), 0, h - 1);
        i = layout == LG_PROBE_LATLONG ? lg_probe_wrap(i, w) : clamp(i, 0, w - 1);
        return lg_probe_texel(rgba, w, h, face, i, j);
    }
    float x = c.x * (float)w - 0.5f, y = c.y * (float)h - 0.5f;
    float fly = floor(y);
    float fy = y - fly;
    int j0 = (int)fly;
    if (layout == LG_PROBE_LATLONG) {
        float4 rows[2];
        for (int k = 0; k < 2; k++) {
            int j = j0 + k;
            float xx = x;
            // beyond a pole: the same ring, half a turn away
            if (j < 0) {
                j = -1 - j;
                xx = x + 0.5f * (float)w;
            } else if (j >= h) {
                j = 2 * h - 1 - j;
                xx = x + 0.5f * (float)w;
            }
            rows[k] = lg_probe_latlong_row(rgba, w, clamp(j, 0, h - 1), xx);
        }
        return lg_probe_lerp(rows[0], rows[1], fy);
    }
    float flx = floor(x);
    float fx = x - flx;
    int i0 = (int)flx;
    float4 t[4];
    if (layout == LG_PROBE_ANGULAR) {
        for (int k = 0; k < 4; k++)
            t[k] = lg_probe_texel(rgba, w, h, 0, clamp(i0 + (k & 1), 0, w - 1),
                                  clamp(j0 + (k >> 1), 0, h - 1));
    } else {
        int corner = -1;
        for (int k = 0; k < 4; k++) {
            int i = i0 + (k & 1), j = j0 + (k >> 1);
            int in_i = i >= 0 && i < w, in_j = j >= 0 && j < w;
            if (in_i && in_j)
                t[k] = lg_probe_texel(rgba, w, w, face, i, j);
            else if (in_i || in_j)
                t[k] = lg_probe_cube_beyond(rgba, w, face, i, j);
            else {
                t[k] = (float4)(0.0f);
                corner = k;
            }
        }
        // the corner beyond two edges: the mean of the three others, as
        // a + (b - a) / 3 + (c - a) / 3 (exactly a when all are equal; no sum of two
        // differences, which overflows beside a texel at FLT_MAX), as on the CPU
        if (corner >= 0) {
            float4 a = t[corner ^ 1];
            t[corner] = a + (t[corner ^ 2] - a) * (1.0f / 3.0f) + (t[corner ^ 3] - a) * (1.0f / 3.0f);
        }
    }
    return lg_probe_lerp(lg_probe_lerp(t[0], t[1], fx), lg_probe_lerp(t[2], t[3], fx), fy);
}

#endif
