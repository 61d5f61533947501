// shaders/common/medium.glsl: lightgraph/medium.h in GLSL 4.50. #include "medium.glsl".
// The C functions (sdk/src/medium.c, float versions) and shaders/common/medium.cl are its
// twins; tests/unit/medium holds them together. Conventions and units in medium.h:
// cos theta = dot(view ray direction, direction towards the light); slice maps z in
// [0, depth] <-> view depth t.
#ifndef LG_MEDIUM_GLSL
#define LG_MEDIUM_GLSL

const float LG_MEDIUM_PI = 3.14159265358979323846;
const float LG_HG_G_MAX = 0.999999;
#define LG_SLICING_UNIFORM_CLIP 1
#define LG_SLICING_EXPONENTIAL 2

// Henyey-Greenstein, 1/sr, the stable form (lightgraph/medium.h).
float lg_hg_phase(float g, float c)
{
    g = clamp(g, -LG_HG_G_MAX, LG_HG_G_MAX);
    c = clamp(c, -1.0, 1.0);
    float den = g >= 0.0 ? (1.0 - g) * (1.0 - g) + 2.0 * g * (1.0 - c)
                         : (1.0 + g) * (1.0 + g) - 2.0 * g * (1.0 + c);
    return (1.0 - g) * (1.0 + g) / (4.0 * LG_MEDIUM_PI * den * sqrt(den));
}

// (1 - e^-tau) / tau, 1 at tau <= 0; a series below 1/4 (no expm1 in GLSL).
float lg_medium_segment(float tau)
{
    if (!(tau > 0.0))
        return 1.0;
    if (tau < 0.25)
        return 1.0 - tau * (0.5 - tau * (1.0 / 6.0 - tau * (
               1.0 / 24.0 - tau * (1.0 / 120.0 - tau * (1.0 / 720.0)))));
    return (1.0 - exp(-tau)) / tau;
}
vec3 lg_medium_segment3(vec3 tau)
{
    return vec3(lg_medium_segment(tau.x), lg_medium_segment(tau.y), lg_medium_segment(tau.z));
}

// Slice maps: map = (near, far, near_offset, depth), slicing = LG_SLICING_*.
float lg_slice_to_depth(int slicing, vec4 map, float z)
{
    float near = map.x, far = map.y, off = map.z, D = map.w;
    if (slicing == LG_SLICING_EXPONENTIAL) {
        if (D <= 1.0)
            return near + z * (far - near);
        if (z <= 1.0)
            return near + z * (off - near);
        return off * pow(far / off, (z - 1.0) / (D - 1.0));
    }
    return 1.0 / (1.0 / near + (z / D) * (1.0 / far - 1.0 / near));
}

float lg_depth_to_slice(int slicing, vec4 map, float t)
{
    float near = map.x, far = map.y, off = map.z, D = map.w;
    if (slicing == LG_SLICING_EXPONENTIAL) {
        if (D <= 1.0)
            return (t - near) / (far - near);
        if (t <= off)
            return (t - near) / (off - near);
        return 1.0 + (D - 1.0) * log(t / off) / log(far / off);
    }
    if (!(t > 0.0))
        return 0.0;
    return D * (1.0 / t - 1.0 / near) / (1.0 / far - 1.0 / near);
}

// ---- Point and spot lights (since ABI 3.2; lightgraph/medium.h) -----------------------------
const float LG_LIGHT_EPSILON = 1e-3;

// KHR_lights_punctual's range window; 1 for range <= 0 (infinite).
float lg_light_window(float d, float range)
{
    if (!(range > 0.0))
        return 1.0;
    float r = d / range;
    float r2 = r * r;
    return clamp(1.0 - r2 * r2, 0.0, 1.0);
}

// The spot's smooth cone falloff t^2.
float lg_spot_cone(float cos_angle, float cos_inner, float cos_outer)
{
    float t = clamp((cos_angle - cos_outer) / max(cos_inner - cos_outer, 1e-4), 0.0, 1.0);
    return t * t;
}

// F(p) of a local light at q: W C / (d^2 + eps^2); spot = (axis, unused), cone = (cos_inner,
// cos_outer); is_spot false: a point light. to_light: unit p -> q (the axis reversed at q).
float lg_local_falloff(vec3 q, float range, bool is_spot, vec3 axis, vec2 cone, vec3 p,
                       out vec3 to_light, out float dist)
{
    vec3 v = q - p;
    float d2 = dot(v, v);
    dist = sqrt(d2);
    to_light = dist > 0.0 ? v / dist : -axis;
    float f = lg_light_window(dist, range) / (d2 + LG_LIGHT_EPSILON * LG_LIGHT_EPSILON);
    if (is_spot)
        f *= lg_spot_cone(dot(-to_light, axis), cone.x, cone.y);
    return f;
}

// The airlight integral of lg_point_inscatter (per unit L_c and sigma_s), one Gauss-Legendre
// panel of n = 1 .. 8 nodes in xi. The same nodes as the C function's single panel.
const float LG_GL8_X[20] = float[20](
    0.0,
    0.5773502691896257645,
    0.0, 0.7745966692414833770,
    0.3399810435848562648, 0.8611363115940525752,
    0.0, 0.5384693101056830910, 0.9061798459386639928,
    0.2386191860831969086, 0.6612093864662645137, 0.9324695142031520279,
    0.0, 0.4058451513773971669, 0.7415311855993944399, 0.9491079123427585245,
    0.1834346424956498049, 0.5255324099163289858, 0.7966664774136267396, 0.9602898564975362317);
const float LG_GL8_W[20] = float[20](
    2.0,
    1.0,
    0.8888888888888888889, 0.5555555555555555556,
    0.6521451548625461427, 0.3478548451374538574,
    0.5688888888888888889, 0.4786286704993664680, 0.2369268850561890875,
    0.4679139345726910473, 0.3607615730481386076, 0.1713244923791703450,
    0.4179591836734693878, 0.3818300505051189449, 0.2797053914892766679, 0.1294849661688696933,
    0.3626837833783619830, 0.3137066458778872873, 0.2223810344533744706, 0.1012285362903762592);
const int LG_GL8_OFF[8] = int[8](0, 1, 2, 4, 6, 9, 12, 16);

// lg_light_clip's test of the piece [p0, p1]: inside the cone at its middle widens [lo, hi].
void lg_clip_piece(vec3 y0, vec3 w, vec3 axis, float cos_outer, float p0, float p1, inout float lo,
                   inout float hi)
{
    vec3 y = y0 + (0.5 * (p0 + p1)) * w;
    if (dot(y, axis) >= cos_outer * length(y)) {
        lo = min(lo, p0);
        hi = max(hi, p1);
    }
}

// The part [a, b] of the segment where the light reaches (sdk/src/medium.c's light_clip,
// line by line): within range of the light, inside a spot's outer cone (cos_outer >= 0:
// convex, one interval), worked in s = t - tc from the ray's closest point y0 (relative to
// the light, |y0|^2 = h2). False when nothing is left.
bool lg_light_clip(vec3 y0, vec3 w, float tc, float h2, float range, bool is_spot, vec3 axis,
                   float cos_outer, inout float a, inout float b)
{
    float sa = a - tc, sb = b - tc;
    if (range > 0.0) {
        float r2 = range * range - h2;
        if (!(r2 > 0.0))
            return false;
        float r = sqrt(r2);
        sa = max(sa, -r);
        sb = min(sb, r);
    }
    if (is_spot && cos_outer >= 0.0 && sb > sa) {
        float co2 = cos_outer * cos_outer;
        float ya = dot(y0, axis), wa = dot(w, axis);
        float A = wa * wa - co2, B = 2.0 * ya * wa, C = ya * ya - co2 * h2;
        // breakpoints: the ends, the roots, s = 0, sorted by a fixed network (medium.c)
        float b1 = 0.0 > sa && 0.0 < sb ? 0.0 : sb, b2 = sb, b3 = sb;
        float disc = max(B * B - 4.0 * A * C, 0.0);
        if (A != 0.0) {
            float qq = -0.5 * (B + (B >= 0.0 ? sqrt(disc) : -sqrt(disc)));
            float r0 = qq / A, r1 = qq != 0.0 ? C / qq : r0;
            b2 = r0 > sa && r0 < sb ? r0 : sb;
            b3 = r1 > sa && r1 < sb ? r1 : sb;
        } else if (B != 0.0) {
            float r = -C / B;
            b2 = r > sa && r < sb ? r : sb;
        }
        float tmp;
        if (b2 < b1) {
            tmp = b1;
            b1 = b2;
            b2 = tmp;
        }
        if (b3 < b2) {
            tmp = b2;
            b2 = b3;
            b3 = tmp;
        }
        if (b2 < b1) {
            tmp = b1;
            b1 = b2;
            b2 = tmp;
        }
        float lo = 3.0e38, hi = -3.0e38;
        lg_clip_piece(y0, w, axis, cos_outer, sa, b1, lo, hi);
        lg_clip_piece(y0, w, axis, cos_outer, b1, b2, lo, hi);
        lg_clip_piece(y0, w, axis, cos_outer, b2, b3, lo, hi);
        lg_clip_piece(y0, w, axis, cos_outer, b3, sb, lo, hi);
        sa = lo;
        sb = hi;
    }
    a = tc + sa;
    b = tc + sb;
    return sb > sa;
}

float lg_point_inscatter(vec3 o, vec3 w, float t0, float t1, vec3 q, float range, bool is_spot,
                         vec3 axis, vec2 cone, float g, float sigma_t, int n)
{
    if (!(t1 > t0))
        return 0.0;
    n = clamp(n, 1, 8);
    vec3 qo = q - o;
    float tc = dot(qo, w);
    // h from the perpendicular offset, not |qo|^2 - tc^2 (cancels near the light; medium.c)
    vec3 perp = qo - tc * w;
    float h2 = dot(perp, perp);
    float H = sqrt(h2 + LG_LIGHT_EPSILON * LG_LIGHT_EPSILON);
    // the nodes go where the light reaches; the extinction still counts from t0
    float ta = t0, tb = t1;
    if (!lg_light_clip(-perp, w, tc, h2, range, is_spot, axis, cone.y, ta, tb))
        return 0.0;
    float xi0 = atan((ta - tc) / H), xi1 = atan((tb - tc) / H);
    float half_w = 0.5 * (xi1 - xi0), mid = 0.5 * (xi1 + xi0);
    int half_n = n / 2, off = LG_GL8_OFF[n - 1];
    float sum = 0.0;
    for (int i = 0; i < n; i++) {
        int k;
        float x;
        if ((n & 1) == 1) {
            k = abs(i - half_n);
            x = i < half_n ? -LG_GL8_X[off + k] : LG_GL8_X[off + k];
        } else {
            k = i < half_n ? half_n - 1 - i : i - half_n;
            x = i < half_n ? -LG_GL8_X[off + k] : LG_GL8_X[off + k];
        }
        float xi = mid + half_w * x;
        float sx = H * tan(xi), t = tc + sx;
        vec3 l = perp - sx * w;
        float d = length(l);
        float cw = d > 0.0 ? dot(l, w) / d : 0.0;
        float f = lg_hg_phase(g, cw) * lg_light_window(d, range);
        if (is_spot)
            f *= lg_spot_cone(d > 0.0 ? -dot(l, axis) / d : 1.0, cone.x, cone.y);
        if (sigma_t > 0.0)
            f *= exp(-sigma_t * ((t - t0) + d));
        sum += half_w * LG_GL8_W[off + k] * f;
    }
    return sum / H;
}

#endif
