/* The viewer's camera controller (viewer_camera.h): orbit, pan, zoom and fly on a look-at
 * camera, and the camera as a graph node's text. */
#include "viewer/camera.h"

#include <math.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "lightgraph/vecmath.h"

/* The math is done in double: a camera turned a thousand times must not drift off its
 * distance or lose the orthogonality of its frame, and float only holds the result. */
typedef struct dv3 {
    double x, y, z;
} dv3;

/* How close pitch may come to the poles: 0.5 degrees. */
static const double kPitchLimit = LG_HALF_PI - 0.5 * LG_PI / 180.0;

static dv3 d3(double x, double y, double z)
{
    dv3 r = { x, y, z };
    return r;
}
static dv3 d3f(const float v[3])
{
    return d3(v[0], v[1], v[2]);
}
static void d3store(float out[3], dv3 v)
{
    out[0] = (float)v.x;
    out[1] = (float)v.y;
    out[2] = (float)v.z;
}
static dv3 add(dv3 a, dv3 b)
{
    return d3(a.x + b.x, a.y + b.y, a.z + b.z);
}
static dv3 sub(dv3 a, dv3 b)
{
    return d3(a.x - b.x, a.y - b.y, a.z - b.z);
}
static dv3 mul(dv3 a, double s)
{
    return d3(a.x * s, a.y * s, a.z * s);
}
static double dot(dv3 a, dv3 b)
{
    return a.x * b.x + a.y * b.y + a.z * b.z;
}
static dv3 cross(dv3 a, dv3 b)
{
    return d3(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x);
}
static double len(dv3 a)
{
    return sqrt(dot(a, a));
}
static bool finite3f(const float v[3])
{
    return isfinite(v[0]) && isfinite(v[1]) && isfinite(v[2]);
}

/* A unit vector perpendicular to the unit vector f, as near to `want` as can be: want made
 * perpendicular, or the world up, or -Z when want is (nearly) parallel to f. */
static dv3 perpendicular_up(dv3 f, dv3 want)
{
    const dv3 tries[3] = { want, d3(0, 1, 0), d3(0, 0, -1) };
    for (int i = 0; i < 3; i++) {
        dv3 u = sub(tries[i], mul(f, dot(tries[i], f)));
        double l = len(u), lw = len(tries[i]);
        if (isfinite(l) && lw > 0.0 && l > 1e-4 * lw)
            return mul(u, 1.0 / l);
    }
    return d3(1, 0, 0); /* f is not finite; the caller's check rejects the result */
}

/* What every function leaves behind: finite values, position != target as floats, a unit
 * up perpendicular to the view direction, a field of view a camera can have. */
static bool vcam_valid(const lg_vcam *v)
{
    if (!finite3f(v->position) || !finite3f(v->target) || !finite3f(v->up) || !isfinite(v->yfov) ||
        !isfinite(v->znear) || !isfinite(v->zfar) || !isfinite(v->aspect) || !isfinite(v->scale) ||
        !(v->scale > 0.0f))
        return false;
    if (v->position[0] == v->target[0] && v->position[1] == v->target[1] &&
        v->position[2] == v->target[2])
        return false;
    dv3 f = sub(d3f(v->target), d3f(v->position));
    f = mul(f, 1.0 / len(f));
    dv3 u = d3f(v->up);
    return fabs(len(u) - 1.0) < 1e-3 && fabs(dot(u, f)) < 1e-3;
}

/* The view direction (unit), the distance from position to target. */
static dv3 forward(const lg_vcam *v, double *dist)
{
    dv3 f = sub(d3f(v->target), d3f(v->position));
    double l = len(f);
    if (dist)
        *dist = l;
    return mul(f, 1.0 / l);
}

/* Yaw (about +Y, from +Z towards +X) and pitch (above the horizontal) of the unit vector
 * dir. At a pole the yaw is undefined; it is taken from the camera's up, which there lies
 * in the horizontal plane and points where dir would lean towards (away from dir's
 * vertical side). */
static void angles_of(dv3 dir, dv3 up, double *yaw, double *pitch)
{
    double h = sqrt(dir.x * dir.x + dir.z * dir.z);
    *pitch = atan2(dir.y, h);
    if (h > 1e-9) {
        *yaw = atan2(dir.x, dir.z);
    } else {
        double s = dir.y > 0.0 ? -1.0 : 1.0;
        *yaw = atan2(s * up.x, s * up.z);
    }
}

static dv3 from_angles(double yaw, double pitch)
{
    return d3(cos(pitch) * sin(yaw), sin(pitch), cos(pitch) * cos(yaw));
}

static double clamp_pitch(double p)
{
    return p > kPitchLimit ? kPitchLimit : p < -kPitchLimit ? -kPitchLimit : p;
}

/* ---- init / out ------------------------------------------------------------------------------ */

void lg_vcam_init(lg_vcam *v, const lg_camera *c, const float bmin[3], const float bmax[3])
{
    memset(v, 0, sizeof *v);
    v->mode = LG_VCAM_ORBIT;

    dv3 centre = d3(0, 0, 0);
    double scale = 0.0;
    if (bmin && bmax && finite3f(bmin) && finite3f(bmax) && bmin[0] <= bmax[0] &&
        bmin[1] <= bmax[1] && bmin[2] <= bmax[2]) {
        centre = mul(add(d3f(bmin), d3f(bmax)), 0.5);
        scale = 0.5 * len(sub(d3f(bmax), d3f(bmin)));
    }
    if (!(scale > 0.0) || !isfinite(scale) || scale > 1e30)
        scale = 1.0;
    v->scale = (float)scale;

    bool usable = c && finite3f(c->position) && finite3f(c->target) && finite3f(c->up) &&
                  isfinite(c->yfov) && c->yfov > 0.0f && c->yfov < 3.1f &&
                  !(c->position[0] == c->target[0] && c->position[1] == c->target[1] &&
                    c->position[2] == c->target[2]);
    if (usable) {
        memcpy(v->position, c->position, sizeof v->position);
        memcpy(v->target, c->target, sizeof v->target);
        v->yfov = c->yfov;
        dv3 f = forward(v, NULL);
        d3store(v->up, perpendicular_up(f, d3f(c->up)));
        /* the depth range and aspect when they make sense, else 0 ("from the bounds", "from
         * the image") */
        if (isfinite(c->znear) && isfinite(c->zfar) && c->znear >= 0.0f && c->zfar >= 0.0f &&
            (c->zfar == 0.0f || c->zfar > c->znear)) {
            v->znear = c->znear;
            v->zfar = c->zfar;
        }
        if (isfinite(c->aspect) && c->aspect > 0.0f)
            v->aspect = c->aspect;
    } else {
        /* as scene_tools' camera in orbit mode with its defaults: azimuth 0, elevation 20
         * degrees, the bounding sphere fitting the vertical field of view */
        v->yfov = (float)(45.0 * LG_PI / 180.0);
        double dist = scale / sin(0.5 * v->yfov);
        double el = 20.0 * LG_PI / 180.0;
        d3store(v->target, centre);
        d3store(v->position, add(centre, mul(from_angles(0.0, el), dist)));
        dv3 f = forward(v, NULL);
        d3store(v->up, perpendicular_up(f, d3(0, 1, 0)));
    }
}

void lg_vcam_to_camera(const lg_vcam *v, lg_camera *out)
{
    memset(out, 0, sizeof *out); /* name NULL, reserved zero */
    memcpy(out->position, v->position, sizeof out->position);
    memcpy(out->target, v->target, sizeof out->target);
    memcpy(out->up, v->up, sizeof out->up);
    out->yfov = v->yfov;
    out->znear = v->znear;
    out->zfar = v->zfar;
    out->aspect = v->aspect;
}

/* ---- input ----------------------------------------------------------------------------------- */

/* Each input function works on a copy's worth of state and keeps the old camera when the
 * result would not be valid (a float overflow, a target that rounds onto the eye). */
static void commit_or_revert(lg_vcam *v, const lg_vcam *old)
{
    if (!vcam_valid(v))
        *v = *old;
}

/* pi per view height: the angle of a drag of (dx, dy) pixels, or false for input that
 * cannot be a drag. */
static bool drag_angles(double dx, double dy, int h, double *ax, double *ay)
{
    if (h <= 0 || !isfinite(dx) || !isfinite(dy))
        return false;
    *ax = LG_PI * dx / (double)h;
    *ay = LG_PI * dy / (double)h;
    /* a drag of millions of view heights is as good as its remainder: keep the angles in a
     * range where sin/cos stay exact */
    *ax = fmod(*ax, 2.0 * LG_PI);
    return isfinite(*ay);
}

void lg_vcam_orbit(lg_vcam *v, double dx, double dy, int h)
{
    double ax, ay;
    if (!drag_angles(dx, dy, h, &ax, &ay))
        return;
    lg_vcam old = *v;
    double dist;
    dv3 f = forward(v, &dist);
    dv3 offset_dir = mul(f, -1.0); /* from the target to the eye */
    double yaw, pitch;
    angles_of(offset_dir, d3f(v->up), &yaw, &pitch);
    yaw -= ax;
    pitch = clamp_pitch(pitch + ay);
    dv3 o = from_angles(yaw, pitch);
    d3store(v->position, add(d3f(v->target), mul(o, dist)));
    d3store(v->up, perpendicular_up(mul(o, -1.0), d3(0, 1, 0)));
    commit_or_revert(v, &old);
}

void lg_vcam_look(lg_vcam *v, double dx, double dy, int h)
{
    double ax, ay;
    if (!drag_angles(dx, dy, h, &ax, &ay))
        return;
    lg_vcam old = *v;
    double dist;
    dv3 f = forward(v, &dist);
    double yaw, pitch;
    angles_of(f, d3f(v->up), &yaw, &pitch);
    yaw -= ax;
    pitch = clamp_pitch(pitch - ay);
    dv3 nf = from_angles(yaw, pitch);
    d3store(v->target, add(d3f(v->position), mul(nf, dist)));
    d3store(v->up, perpendicular_up(nf, d3(0, 1, 0)));
    commit_or_revert(v, &old);
}

void lg_vcam_pan(lg_vcam *v, double dx, double dy, int h)
{
    if (h <= 0 || !isfinite(dx) || !isfinite(dy))
        return;
    lg_vcam old = *v;
    double dist;
    dv3 f = forward(v, &dist);
    dv3 up = perpendicular_up(f, d3f(v->up));
    dv3 right = cross(f, up);
    /* world units per pixel at the target's depth: the view spans 2 d tan(yfov / 2) */
    double k = 2.0 * dist * tan(0.5 * (double)v->yfov) / (double)h;
    /* a point that stays put moves on screen against the camera: to make it follow the
     * pointer right (and down: y grows downwards) the camera goes left (and up) */
    dv3 delta = add(mul(right, -dx * k), mul(up, dy * k));
    d3store(v->position, add(d3f(v->position), delta));
    d3store(v->target, add(d3f(v->target), delta));
    commit_or_revert(v, &old);
}

void lg_vcam_zoom(lg_vcam *v, double d)
{
    if (!isfinite(d))
        return;
    lg_vcam old = *v;
    double dist;
    dv3 f = forward(v, &dist);
    double nd = dist * pow(0.85, d);
    double lo = 1e-4 * (double)v->scale, hi = 1e9 * (double)v->scale;
    if (!(nd >= lo)) /* also NaN from an underflow to 0 * inf */
        nd = lo;
    if (nd > hi)
        nd = dist > hi ? dist : hi; /* beyond the ceiling already: no farther */
    d3store(v->position, sub(d3f(v->target), mul(f, nd)));
    commit_or_revert(v, &old);
}

void lg_vcam_move(lg_vcam *v, const float rul[3], double dt, double speed)
{
    if (!rul || !finite3f(rul) || !isfinite(dt) || !isfinite(speed) || dt <= 0.0 || speed <= 0.0)
        return;
    lg_vcam old = *v;
    dv3 m = d3f(rul);
    m.x = fmax(-1.0, fmin(1.0, m.x));
    m.y = fmax(-1.0, fmin(1.0, m.y));
    m.z = fmax(-1.0, fmin(1.0, m.z));
    double l = len(m);
    if (l > 1.0)
        m = mul(m, 1.0 / l);
    dv3 f = forward(v, NULL);
    dv3 up = perpendicular_up(f, d3f(v->up));
    dv3 right = cross(f, up);
    dv3 delta = mul(add(add(mul(right, m.x), mul(up, m.y)), mul(f, m.z)),
                    speed * dt * (double)v->scale);
    d3store(v->position, add(d3f(v->position), delta));
    d3store(v->target, add(d3f(v->target), delta));
    commit_or_revert(v, &old);
}

/* ---- node text ------------------------------------------------------------------------------- */

static bool is_graph_name(const char *s)
{
    if (!s || !((*s >= 'A' && *s <= 'Z') || (*s >= 'a' && *s <= 'z') || *s == '_'))
        return false;
    for (; *s; s++)
        if (!((*s >= 'A' && *s <= 'Z') || (*s >= 'a' && *s <= 'z') || (*s >= '0' && *s <= '9') ||
              *s == '_'))
            return false;
    return true;
}

/* "[x, y, z]" with `digits` significant digits; -0 is printed as 0. */
static void print_vec(char *buf, size_t size, const float p[3], int digits)
{
    snprintf(buf, size, "[%.*g, %.*g, %.*g]", digits, (double)p[0] + 0.0, digits,
             (double)p[1] + 0.0, digits, (double)p[2] + 0.0);
}

/* v as read back from %.6g text. */
static dv3 printed6(const float v[3])
{
    double r[3];
    for (int i = 0; i < 3; i++) {
        char s[64];
        snprintf(s, sizeof s, "%.6g", (double)v[i]);
        r[i] = (double)strtof(s, NULL);
    }
    return d3(r[0], r[1], r[2]);
}

/* Whether six digits keep the view: the eye-to-target vector read back from the text within
 * 1e-5 (relative length and radians) of the camera's. Six digits round each coordinate by
 * up to 5e-7 of its size, which an eye close to a far-off target (near the zoom floor, or
 * far from the origin) turns into a visible error, or even into target = position. */
static bool six_digits_enough(const lg_vcam *v)
{
    dv3 want = sub(d3f(v->target), d3f(v->position));
    dv3 got = sub(printed6(v->target), printed6(v->position));
    double lw = len(want), lg = len(got);
    if (!(lg > 0.0))
        return false;
    double cosang = dot(want, got) / (lw * lg);
    return fabs(lg - lw) <= 1e-5 * lw && cosang >= 1.0 - 0.5e-10; /* 1 - cos(1e-5) */
}

char *lg_vcam_node_text(const lg_vcam *v, const char *name, const char *scene_ref)
{
    if (!is_graph_name(name) || !is_graph_name(scene_ref))
        return NULL;
    int digits = six_digits_enough(v) ? 6 : 9;
    char pos[128], tgt[128], up[128], extra[192] = "";
    print_vec(pos, sizeof pos, v->position, digits);
    print_vec(tgt, sizeof tgt, v->target, digits);
    print_vec(up, sizeof up, v->up, 6);
    size_t e = 0;
    if (v->znear != 0.0f)
        e += (size_t)snprintf(extra + e, sizeof extra - e, "    znear = %.6g\n", (double)v->znear);
    if (v->zfar != 0.0f)
        e += (size_t)snprintf(extra + e, sizeof extra - e, "    zfar = %.6g\n", (double)v->zfar);
    if (v->aspect != 0.0f)
        snprintf(extra + e, sizeof extra - e, "    aspect = %.6g\n", (double)v->aspect);
    const char *fmt = "%s = camera {\n"
                      "    scene = %s\n"
                      "    mode = look_at\n"
                      "    position = %s\n"
                      "    target = %s\n"
                      "    up = %s\n"
                      "    fov_deg = %.6g\n"
                      "%s"
                      "}\n";
    double fov_deg = (double)v->yfov * 180.0 / LG_PI;
    int n = snprintf(NULL, 0, fmt, name, scene_ref, pos, tgt, up, fov_deg, extra);
    if (n < 0)
        return NULL;
    char *text = malloc((size_t)n + 1);
    if (text)
        snprintf(text, (size_t)n + 1, fmt, name, scene_ref, pos, tgt, up, fov_deg, extra);
    return text;
}

void lg_vcam_fit_clip(lg_vcam *v, const float bmin[3], const float bmax[3])
{
    dv3 eye = d3f(v->position), t = d3f(v->target);
    double dist = len(sub(t, eye));
    if (!(dist > 0) || !isfinite(dist))
        return;
    dv3 f = mul(sub(t, eye), 1.0 / dist);
    bool have = bmin && bmax && finite3f(bmin) && finite3f(bmax) && bmin[0] <= bmax[0] &&
                bmin[1] <= bmax[1] && bmin[2] <= bmax[2];
    double near, far;
    if (!have) {
        near = dist / 100.0;
        far = dist * 100.0;
    } else {
        double dmin = INFINITY, dmax = -INFINITY;
        for (int k = 0; k < 8; k++) {
            dv3 c = d3(k & 1 ? bmax[0] : bmin[0], k & 2 ? bmax[1] : bmin[1],
                       k & 4 ? bmax[2] : bmin[2]);
            double d = dot(sub(c, eye), f);
            dmin = d < dmin ? d : dmin;
            dmax = d > dmax ? d : dmax;
        }
        far = dmax * 1.01;
        if (!(far > 0)) { /* the scene behind the camera: any far plane past it */
            dv3 centre = mul(add(d3f(bmin), d3f(bmax)), 0.5);
            far = len(sub(centre, eye)) + 0.5 * len(sub(d3f(bmax), d3f(bmin)));
        }
        if (!(far > 0))
            far = 1.0;
        near = dmin * 0.99;
        if (!(near > far * 1e-3)) /* inside the bounds: keep depth precision usable */
            near = far * 1e-3;
    }
    if (isfinite(near) && isfinite(far) && near > 0 && far > near) {
        v->znear = (float)near;
        v->zfar = (float)far;
    }
}
