/*
 * tests/unit/anim: rigid animation in the SDK (lightgraph/scene.h, ABI 3.1): lg_scene_pose,
 * lg_scene_pose_lights, lg_scene_pose_cameras. One command per meson test; every expected
 * value is computed by hand in the comments, not by the code under test:
 *
 *   interp     translation keys at t = 0 and 1 s: STEP holds key 0 until t = 1; LINEAR at
 *              0.25 s is a quarter of the way; CUBICSPLINE (glTF 2.0 Appendix C) with keys
 *              0 -> 1 over 2 s, out-tangent 1 and in-tangent 0, is 0.75 at t = 1 s; before
 *              the first key and after the last the end keys hold (no looping)
 *   slerp      rotation from identity to 90 degrees about z: 45 degrees at half time (x
 *              maps to (cos 45, sin 45, 0)), also with the second key given as -q (the
 *              shorter arc); a cubic-spline rotation is renormalised
 *   hierarchy  a moving root (translation keyed (0,0,0) -> (10,0,0), rest rotation 90
 *              degrees about z) carries its child (rest translation (1,0,0), scale
 *              (2,1,1)): at 0.5 s the child's origin is at (5, 1, 0); its normal matrix is
 *              the inverse transpose (lg_m4_normal_matrix) of its model matrix; an instance
 *              on a node without a moving ancestor keeps its matrices exactly
 *   carried    a light and a camera on the moving root: their positions, the light's
 *              direction and the camera's target and up follow the node; a light on a
 *              static node does not move
 *   bad        a NaN or infinite time is refused (LG_ERR_INVALID); a scene without an
 *              animation is copied unchanged at any time
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "common/check.h"
#include "lightgraph/scene.h"
#include "lightgraph/vecmath.h"

#define NEAR(a, b, tol) (fabs((double)(a) - (double)(b)) <= (tol))

static const float IDENT[16] = { 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1 };

/* A scene of `ni` instances of mesh 0 on the nodes `inode`, animated by `a`. */
typedef struct fixture {
    lg_scene s;
    lg_instance inst[4];
    lg_mesh mesh;
    lg_scene_animation a;
} fixture;

static void fixture_init(fixture *f, uint32_t ni, const uint32_t *inode, const lg_anim_node *nodes,
                         uint32_t nn, const lg_anim_channel *ch, uint32_t nc)
{
    memset(f, 0, sizeof *f);
    for (uint32_t i = 0; i < ni; i++) {
        memcpy(f->inst[i].model, IDENT, sizeof IDENT);
        f->inst[i].normal_matrix[0] = f->inst[i].normal_matrix[4] = f->inst[i].normal_matrix[8] = 1;
    }
    f->s.struct_size = sizeof f->s;
    f->s.meshes = &f->mesh;
    f->s.n_meshes = 1;
    f->s.instances = f->inst;
    f->s.n_instances = ni;
    f->a.nodes = nodes;
    f->a.n_nodes = nn;
    f->a.channels = ch;
    f->a.n_channels = nc;
    f->a.instance_node = inode;
    f->s.animation = &f->a;
}

static lg_anim_node node(int32_t parent, float tx, float ty, float tz, uint32_t animated)
{
    lg_anim_node n;
    memset(&n, 0, sizeof n);
    n.parent = parent;
    n.translation[0] = tx, n.translation[1] = ty, n.translation[2] = tz;
    n.rotation[3] = 1;
    n.scale[0] = n.scale[1] = n.scale[2] = 1;
    n.animated = animated;
    return n;
}

/* The translation of instance 0 at time t. */
static void pos_at(const lg_scene *s, double t, float out[3])
{
    lg_instance in[4];
    CHECK(lg_scene_pose(NULL, s, t, in) == 0);
    memcpy(out, in[0].model + 12, 3 * sizeof(float));
}

static int cmd_interp(void)
{
    lg_anim_node nodes[1] = { node(-1, 0, 0, 0, 1) };
    uint32_t inode[1] = { 0 };
    static const float times[2] = { 0, 1 };
    static const float vals[6] = { 0, 0, 0, 2, 4, 6 };
    lg_anim_channel ch;
    memset(&ch, 0, sizeof ch);
    ch.node = 0, ch.path = LG_ANIM_TRANSLATION, ch.n_keys = 2, ch.times = times, ch.values = vals;
    fixture f;
    float p[3];

    ch.interpolation = LG_ANIM_STEP;
    fixture_init(&f, 1, inode, nodes, 1, &ch, 1);
    CHECK(lg_scene_is_animated(&f.s));
    pos_at(&f.s, 0.99, p);
    CHECKF(p[0] == 0 && p[1] == 0 && p[2] == 0, "step at 0.99 s: %g %g %g", p[0], p[1], p[2]);
    pos_at(&f.s, 1.0, p);
    CHECKF(p[0] == 2 && p[1] == 4 && p[2] == 6, "step at 1 s: %g %g %g", p[0], p[1], p[2]);

    ch.interpolation = LG_ANIM_LINEAR;
    pos_at(&f.s, 0.25, p);
    CHECKF(NEAR(p[0], 0.5, 1e-6) && NEAR(p[1], 1, 1e-6) && NEAR(p[2], 1.5, 1e-6),
           "linear at 0.25 s: %g %g %g", p[0], p[1], p[2]);
    pos_at(&f.s, -3, p);
    CHECKF(p[0] == 0 && p[1] == 0 && p[2] == 0, "before the first key: %g %g %g", p[0], p[1], p[2]);
    pos_at(&f.s, 7, p);
    CHECKF(p[0] == 2 && p[1] == 4 && p[2] == 6, "after the last key: %g %g %g", p[0], p[1], p[2]);

    /* cubic: triples (in-tangent, value, out-tangent) per key; x: 0 -> 1 over 2 s, b0 = 1,
     * a1 = 0: p(u = 0.5) = h00 0 + td h10 b0 + h01 1 + td h11 a1 = 2 (0.125) + 0.5 = 0.75;
     * y: values 0 -> 0 with b0 = 3, a1 = -3: 2 (0.125)(3) + 2 (-0.125)(-3) = 1.5 */
    static const float ctimes[2] = { 0, 2 };
    static const float cvals[18] = { 9, 9,  9, 0, 0, 0, 1, 3, 0, /* key 0: a, v, b */
                                     0, -3, 0, 1, 0, 0, 9, 9, 9 /* key 1: a, v, b */ };
    ch.interpolation = LG_ANIM_CUBICSPLINE;
    ch.times = ctimes, ch.values = cvals;
    pos_at(&f.s, 1.0, p);
    CHECKF(NEAR(p[0], 0.75, 1e-6) && NEAR(p[1], 1.5, 1e-6) && p[2] == 0,
           "cubic at 1 s: %g %g %g (want 0.75 1.5 0)", p[0], p[1], p[2]);
    pos_at(&f.s, 2.0, p);
    CHECKF(p[0] == 1 && p[1] == 0, "cubic at the last key: the value, not a tangent: %g %g", p[0],
           p[1]);
    pos_at(&f.s, 0.0, p);
    CHECKF(p[0] == 0 && p[1] == 0, "cubic at the first key: %g %g", p[0], p[1]);
    return check_report("anim interp");
}

static int cmd_slerp(void)
{
    lg_anim_node nodes[1] = { node(-1, 0, 0, 0, 1) };
    uint32_t inode[1] = { 0 };
    static const float times[2] = { 0, 1 };
    double h = sqrt(0.5);
    float vals[8] = { 0, 0, 0, 1, 0, 0, (float)h, (float)h };
    lg_anim_channel ch;
    memset(&ch, 0, sizeof ch);
    ch.node = 0, ch.path = LG_ANIM_ROTATION, ch.interpolation = LG_ANIM_LINEAR, ch.n_keys = 2;
    ch.times = times, ch.values = vals;
    fixture f;
    fixture_init(&f, 1, inode, nodes, 1, &ch, 1);
    for (int neg = 0; neg < 2; neg++) {
        if (neg)
            for (int k = 4; k < 8; k++)
                vals[k] = -vals[k];
        lg_instance in[1];
        CHECK(lg_scene_pose(NULL, &f.s, 0.5, in) == 0);
        /* column 0: the image of x */
        CHECKF(NEAR(in[0].model[0], h, 1e-6) && NEAR(in[0].model[1], h, 1e-6) &&
                   NEAR(in[0].model[2], 0, 1e-6),
               "slerp (%s) at 0.5 s maps x to %g %g %g, want %g %g 0", neg ? "-q1" : "q1",
               in[0].model[0], in[0].model[1], in[0].model[2], h, h);
        /* a quarter of the way: 22.5 degrees */
        CHECK(lg_scene_pose(NULL, &f.s, 0.25, in) == 0);
        double c = cos(LG_PI / 8), s = sin(LG_PI / 8);
        CHECKF(NEAR(in[0].model[0], c, 1e-6) && NEAR(in[0].model[1], s, 1e-6),
               "slerp at 0.25 s: %g %g, want %g %g", in[0].model[0], in[0].model[1], c, s);
    }
    /* cubic with zero tangents between identity and 90 degrees: at the middle the Hermite
     * blend is (q0 + q1) / 2, renormalised: 45 degrees again */
    float cv[24] = { 0 };
    cv[4 + 3] = 1;                                /* key 0 value: identity */
    cv[16 + 2] = (float)h, cv[16 + 3] = (float)h; /* key 1 value */
    ch.interpolation = LG_ANIM_CUBICSPLINE;
    ch.values = cv;
    lg_instance in[1];
    CHECK(lg_scene_pose(NULL, &f.s, 0.5, in) == 0);
    double len =
        sqrt((double)in[0].model[0] * in[0].model[0] + (double)in[0].model[1] * in[0].model[1]);
    CHECKF(NEAR(len, 1, 1e-6), "cubic rotation not renormalised: column 0 has length %g", len);
    CHECKF(NEAR(in[0].model[0], h, 1e-6) && NEAR(in[0].model[1], h, 1e-6),
           "cubic rotation at 0.5 s: %g %g", in[0].model[0], in[0].model[1]);
    return check_report("anim slerp");
}

static int cmd_hierarchy(void)
{
    lg_anim_node nodes[3] = { node(-1, 0, 0, 0, 1), node(0, 1, 0, 0, 1), node(-1, 3, 0, 0, 0) };
    double h = sqrt(0.5);
    nodes[0].rotation[2] = (float)h, nodes[0].rotation[3] = (float)h; /* 90 degrees about z */
    nodes[1].scale[0] = 2;
    uint32_t inode[2] = { 1, 2 };
    static const float times[2] = { 0, 1 };
    static const float vals[6] = { 0, 0, 0, 10, 0, 0 };
    lg_anim_channel ch;
    memset(&ch, 0, sizeof ch);
    ch.node = 0, ch.path = LG_ANIM_TRANSLATION, ch.interpolation = LG_ANIM_LINEAR, ch.n_keys = 2;
    ch.times = times, ch.values = vals;
    fixture f;
    fixture_init(&f, 2, inode, nodes, 3, &ch, 1);
    f.inst[1].model[12] = 3; /* its rest pose, as the loader would have placed it */
    lg_instance in[2];
    CHECK(lg_scene_pose(NULL, &f.s, 0.5, in) == 0);
    CHECKF(NEAR(in[0].model[12], 5, 1e-5) && NEAR(in[0].model[13], 1, 1e-5) &&
               NEAR(in[0].model[14], 0, 1e-5),
           "child at 0.5 s: %g %g %g, want 5 1 0", in[0].model[12], in[0].model[13],
           in[0].model[14]);
    /* the child's x axis: scaled 2, turned 90 degrees: (0, 2, 0) */
    CHECKF(NEAR(in[0].model[0], 0, 1e-6) && NEAR(in[0].model[1], 2, 1e-6),
           "child's x axis %g %g, want 0 2", in[0].model[0], in[0].model[1]);
    float nm[9];
    CHECK(lg_m4_normal_matrix(nm, in[0].model) == 0);
    for (int k = 0; k < 9; k++)
        CHECKF(NEAR(nm[k], in[0].normal_matrix[k], 1e-6), "normal matrix [%d]: %g, want %g", k,
               in[0].normal_matrix[k], nm[k]);
    CHECK(memcmp(&in[1], &f.inst[1], sizeof in[1]) == 0);
    CHECK(in[0].mesh == f.inst[0].mesh);
    return check_report("anim hierarchy");
}

static int cmd_carried(void)
{
    lg_anim_node nodes[2] = { node(-1, 0, 0, 0, 1), node(-1, 0, 5, 0, 0) };
    double h = sqrt(0.5);
    uint32_t inode[1] = { 0 };
    static const float times[2] = { 0, 1 };
    /* the root turns from identity to 90 degrees about z */
    float vals[8] = { 0, 0, 0, 1, 0, 0, (float)h, (float)h };
    lg_anim_channel ch;
    memset(&ch, 0, sizeof ch);
    ch.node = 0, ch.path = LG_ANIM_ROTATION, ch.interpolation = LG_ANIM_LINEAR, ch.n_keys = 2;
    ch.times = times, ch.values = vals;
    fixture f;
    fixture_init(&f, 1, inode, nodes, 2, &ch, 1);
    lg_light lights[2];
    memset(lights, 0, sizeof lights);
    lights[0].position[0] = 1, lights[0].direction[0] = 1; /* on the root (rest: identity) */
    lights[1].position[1] = 5, lights[1].direction[2] = -1;
    lg_camera cams[1];
    memset(cams, 0, sizeof cams);
    cams[0].position[0] = 2, cams[0].target[0] = 3, cams[0].up[2] = 1;
    int32_t lnode[2] = { 0, -1 }, cnode[1] = { 0 };
    f.a.light_node = lnode, f.a.camera_node = cnode;
    f.s.lights = lights, f.s.n_lights = 2, f.s.cameras = cams, f.s.n_cameras = 1;
    lg_light lo[2];
    lg_camera co[1];
    CHECK(lg_scene_pose_lights(NULL, &f.s, 1.0, lo) == 0);
    CHECK(lg_scene_pose_cameras(NULL, &f.s, 1.0, co) == 0);
    /* 90 degrees about z: x -> y */
    CHECKF(NEAR(lo[0].position[0], 0, 1e-6) && NEAR(lo[0].position[1], 1, 1e-6),
           "light position %g %g, want 0 1", lo[0].position[0], lo[0].position[1]);
    CHECKF(NEAR(lo[0].direction[0], 0, 1e-6) && NEAR(lo[0].direction[1], 1, 1e-6),
           "light direction %g %g, want 0 1", lo[0].direction[0], lo[0].direction[1]);
    CHECK(memcmp(&lo[1], &lights[1], sizeof lo[1]) == 0);
    CHECKF(NEAR(co[0].position[1], 2, 1e-6) && NEAR(co[0].target[1], 3, 1e-6) &&
               NEAR(co[0].up[2], 1, 1e-6),
           "camera %g %g %g", co[0].position[1], co[0].target[1], co[0].up[2]);
    CHECK(lg_scene_pose_lights(NULL, &f.s, 0.0, lo) == 0);
    CHECK(NEAR(lo[0].position[0], 1, 1e-6) && NEAR(lo[0].position[1], 0, 1e-6));
    return check_report("anim carried");
}

static int cmd_bad(void)
{
    lg_anim_node nodes[1] = { node(-1, 0, 0, 0, 1) };
    uint32_t inode[1] = { 0 };
    static const float times[1] = { 0 };
    static const float vals[3] = { 1, 2, 3 };
    lg_anim_channel ch;
    memset(&ch, 0, sizeof ch);
    ch.node = 0, ch.path = LG_ANIM_TRANSLATION, ch.n_keys = 1, ch.times = times, ch.values = vals;
    fixture f;
    fixture_init(&f, 1, inode, nodes, 1, &ch, 1);
    lg_instance in[1];
    lg_light lo[1];
    CHECK(lg_scene_pose(NULL, &f.s, NAN, in) == LG_ERR_INVALID);
    CHECK(lg_scene_pose(NULL, &f.s, INFINITY, in) == LG_ERR_INVALID);
    CHECK(lg_scene_pose_lights(NULL, &f.s, NAN, lo) == LG_ERR_INVALID);
    /* a single key poses the scene at every time */
    float p[3];
    pos_at(&f.s, 100, p);
    CHECK(p[0] == 1 && p[1] == 2 && p[2] == 3);
    /* without an animation: the instances as they are */
    f.s.animation = NULL;
    f.inst[0].model[12] = 7;
    CHECK(!lg_scene_is_animated(&f.s));
    CHECK(lg_scene_pose(NULL, &f.s, 3.0, in) == 0);
    CHECK(memcmp(in, f.inst, sizeof in[0]) == 0);
    return check_report("anim bad");
}

int main(int argc, char **argv)
{
    const char *c = argc > 1 ? argv[1] : "";
    if (!strcmp(c, "interp"))
        return cmd_interp();
    if (!strcmp(c, "slerp"))
        return cmd_slerp();
    if (!strcmp(c, "hierarchy"))
        return cmd_hierarchy();
    if (!strcmp(c, "carried"))
        return cmd_carried();
    if (!strcmp(c, "bad"))
        return cmd_bad();
    fprintf(stderr, "usage: test_anim interp|slerp|hierarchy|carried|bad\n");
    return 2;
}
