// shaders/common/probe.glsl: the probe conventions of lightgraph/probe.h in GLSL 4.50
// (docs/probes.md). #include "probe.glsl" (tools/embed.py resolves it). The C functions of
// probe.h and shaders/common/probe.cl are its twins; tests/unit/probe holds the three
// together (tolerances in docs/probes.md).
//
// Coordinates are vec3(u, v, face): u right, v down in [0, 1], face 0 for the 2D layouts
// and 0..5 (+X, -X, +Y, -Y, +Z, -Z) for the cube. Layouts as lg_probe_layout.
//
// Lookups:
//   lg_probe_2d_nearest / lg_probe_2d_bilinear (sampler2D, layout, level, dir): lat-long
//     or angular texture, read with texelFetch (the filter state of the texture does not
//     matter): lat-long wraps in u and continues across the poles at phi + pi, angular
//     clamps to the edge; exactly the CPU's arithmetic.
//   lg_probe_cube(samplerCube, lod, dir): textureLod with the texture's own filter; for the
//     CPU's bilinear lookup the texture needs GL_LINEAR filtering and
//     glEnable(GL_TEXTURE_CUBE_MAP_SEAMLESS); for nearest, GL_NEAREST.
//   lg_probe_from_world(rotation, dir): world -> probe with lg_probe_info.rotation (a mat3
//     from its column-major floats, probe -> world).
#ifndef LG_PROBE_GLSL
#define LG_PROBE_GLSL

#define LG_PROBE_LATLONG 1
#define LG_PROBE_ANGULAR 2
#define LG_PROBE_CUBE 3

const float LG_PROBE_PI = 3.14159265358979323846;

// NaN and infinities by their bits: GLSL compilers may fold isnan(x) away.
bool lg_probe_nonfinite(float x)
{
    return (floatBitsToUint(x) & 0x7f800000u) == 0x7f800000u;
}

// Unit vector along d; zero, denormal-only (below 1e-30), NaN or infinite -> -Z.
vec3 lg_probe_safe_dir(vec3 d)
{
    if (lg_probe_nonfinite(d.x) || lg_probe_nonfinite(d.y) || lg_probe_nonfinite(d.z))
        return vec3(0.0, 0.0, -1.0);
    float m = max(abs(d.x), max(abs(d.y), abs(d.z)));
    if (!(m > 1e-30))
        return vec3(0.0, 0.0, -1.0);
    d *= 1.0 / m;
    return d * (1.0 / length(d));
}

vec3 lg_probe_from_world(mat3 rotation, vec3 d)
{
    return transpose(rotation) * d;
}

// Cube face and (u, v) of a non-zero direction (GL's table; ties: X, then Y, then Z).
vec3 lg_probe_cube_coord(vec3 d)
{
    vec3 a = abs(d);
    float sc, tc, ma, face;
    if (a.x >= a.y && a.x >= a.z) {
        face = d.x >= 0.0 ? 0.0 : 1.0;
        ma = a.x;
        sc = d.x >= 0.0 ? -d.z : d.z;
        tc = -d.y;
    } else if (a.y >= a.z) {
        face = d.y >= 0.0 ? 2.0 : 3.0;
        ma = a.y;
        sc = d.x;
        tc = d.y >= 0.0 ? d.z : -d.z;
    } else {
        face = d.z >= 0.0 ? 4.0 : 5.0;
        ma = a.z;
        sc = d.z >= 0.0 ? d.x : -d.x;
        tc = -d.y;
    }
    return vec3(0.5 * (sc / ma + 1.0), 0.5 * (tc / ma + 1.0), face);
}

vec3 lg_probe_cube_plane_dir(int face, float sc, float tc)
{
    switch (face) {
    case 0: return vec3(1.0, -tc, -sc);
    case 1: return vec3(-1.0, -tc, sc);
    case 2: return vec3(sc, 1.0, tc);
    case 3: return vec3(sc, -1.0, -tc);
    case 4: return vec3(sc, -tc, 1.0);
    default: return vec3(-sc, -tc, -1.0);
    }
}

// Face and (u, v) of a direction of any length.
vec3 lg_probe_dir_to_coord(int lay, vec3 d)
{
    d = lg_probe_safe_dir(d);
    if (lay == LG_PROBE_CUBE)
        return lg_probe_cube_coord(d);
    if (lay == LG_PROBE_ANGULAR) {
        float rho = sqrt(d.x * d.x + d.y * d.y);
        float k;
        if (rho >= 1e-4)
            k = atan(rho, -d.z) / (LG_PROBE_PI * rho);
        else if (d.z < 0.0)
            k = 1.0 / (LG_PROBE_PI * -d.z);
        else if (rho > 0.0)
            k = atan(rho, -d.z) / (LG_PROBE_PI * rho);
        else
            return vec3(0.5, 1.0, 0.0);
        return vec3(0.5 * (d.x * k + 1.0), 0.5 * (1.0 - d.y * k), 0.0);
    }
    float phi = (d.x == 0.0 && d.z == 0.0) ? 0.0 : atan(d.x, -d.z);
    float theta = atan(sqrt(d.x * d.x + d.z * d.z), d.y);
    return vec3(phi * (0.5 / LG_PROBE_PI) + 0.5, theta * (1.0 / LG_PROBE_PI), 0.0);
}

// The unit direction at coordinates c.
vec3 lg_probe_coord_to_dir(int lay, vec3 c)
{
    if (lay == LG_PROBE_CUBE)
        return lg_probe_safe_dir(lg_probe_cube_plane_dir(int(c.z), 2.0 * c.x - 1.0,
                                                         2.0 * c.y - 1.0));
    if (lay == LG_PROBE_ANGULAR) {
        float a = 2.0 * c.x - 1.0, b = 1.0 - 2.0 * c.y;
        float r = sqrt(a * a + b * b);
        if (!(r < 1.0))
            return vec3(0.0, 0.0, 1.0);
        float t = LG_PROBE_PI * r;
        float s = r < 1e-4 ? LG_PROBE_PI * (1.0 - t * t * (1.0 / 6.0)) : sin(t) / r;
        return vec3(a * s, b * s, -cos(t));
    }
    float phi = 2.0 * LG_PROBE_PI * (c.x - 0.5), theta = LG_PROBE_PI * c.y;
    float st = sin(theta);
    return vec3(st * sin(phi), cos(theta), -st * cos(phi));
}

// i mod n for i >= -n (GLSL leaves % of a negative operand undefined: llvmpipe computes
// it unsigned, right only for powers of two)
int lg_probe_wrap(int i, int n)
{
    return int(uint(i + n) % uint(n));
}

vec4 lg_probe_2d_nearest(sampler2D tex, int lay, int level, vec3 dir)
{
    ivec2 size = textureSize(tex, level);
    vec3 c = lg_probe_dir_to_coord(lay, dir);
    int i = int(floor(c.x * float(size.x)));
    int j = clamp(int(floor(c.y * float(size.y))), 0, size.y - 1);
    i = lay == LG_PROBE_LATLONG ? lg_probe_wrap(i, size.x) : clamp(i, 0, size.x - 1);
    return texelFetch(tex, ivec2(i, j), level);
}

// a + (b - a) f: exactly a where a == b (a constant probe reads back its constant), as
// on the CPU
vec4 lg_probe_lerp(vec4 a, vec4 b, float f)
{
    return a + (b - a) * f;
}

// One lat-long row at column coordinate x (texel centres at integers), wrapping.
vec4 lg_probe_latlong_row(sampler2D tex, int level, int W, int j, float x)
{
    float fl = floor(x);
    float fx = x - fl;
    int i0 = int(fl);
    return lg_probe_lerp(texelFetch(tex, ivec2(lg_probe_wrap(i0, W), j), level),
                         texelFetch(tex, ivec2(lg_probe_wrap(i0 + 1, W), j), level), fx);
}

vec4 lg_probe_2d_bilinear(sampler2D tex, int lay, int level, vec3 dir)
{
    ivec2 size = textureSize(tex, level);
    vec3 c = lg_probe_dir_to_coord(lay, dir);
    float x = c.x * float(size.x) - 0.5, y = c.y * float(size.y) - 0.5;
    float fly = floor(y);
    float fy = y - fly;
    int j0 = int(fly);
    if (lay == LG_PROBE_LATLONG) {
        vec4 rows[2];
        for (int k = 0; k < 2; k++) {
            int j = j0 + k;
            float xx = x;
            // beyond a pole: the same ring, half a turn away
            if (j < 0) {
                j = -1 - j;
                xx = x + 0.5 * float(size.x);
            } else if (j >= size.y) {
                j = 2 * size.y - 1 - j;
                xx = x + 0.5 * float(size.x);
            }
            rows[k] = lg_probe_latlong_row(tex, level, size.x, clamp(j, 0, size.y - 1), xx);
        }
        return lg_probe_lerp(rows[0], rows[1], fy);
    }
    float flx = floor(x);
    float fx = x - flx;
    int i0 = int(flx);
    ivec2 hi = size - 1;
    vec4 t00 = texelFetch(tex, clamp(ivec2(i0, j0), ivec2(0), hi), level);
    vec4 t10 = texelFetch(tex, clamp(ivec2(i0 + 1, j0), ivec2(0), hi), level);
    vec4 t01 = texelFetch(tex, clamp(ivec2(i0, j0 + 1), ivec2(0), hi), level);
    vec4 t11 = texelFetch(tex, clamp(ivec2(i0 + 1, j0 + 1), ivec2(0), hi), level);
    return lg_probe_lerp(lg_probe_lerp(t00, t10, fx), lg_probe_lerp(t01, t11, fx), fy);
}

vec4 lg_probe_cube(samplerCube tex, float lod, vec3 dir)
{
    return textureLod(tex, lg_probe_safe_dir(dir), lod);
}

#endif
