/*
 * The volumetric_polygonal plugin: in-scattering through polygonal light volumes (seed 2,
 * 3.2.2, eq. 9; Billeter et al. 2010, Hoobler 2016; TECHNIQUES.md §6) on GL.
 *
 * Per directional light (1..32), with its record in the shadow map:
 *   1. poly_mesh.comp turns the light's shadow-map tile into a closed mesh bounding the lit
 *      volume: a box around the camera's fog in the light's NDC, less the shadowed dent
 *      under the tile's depths (a Ws x Hs grid at the stored depths, walls down to the
 *      box's far side, a frame there; the vertex order is the shader's comment; the
 *      triangles, fixed for a grid size, come from poly_indices below and are shared by
 *      all lights);
 *   2. poly_volume.vert/.frag rasterise it from the camera into `inscatter` with additive
 *      blending and no depth test: each crossing at distance s adds sign F(min(s, d)),
 *      + where the ray leaves the volume, - where it enters (the triangle's winding in the
 *      window, gl_FrontFacing, with the light's handedness u_flip),
 *      F(s) = L_c sigma_s p (1 - e^(-sigma_t s)) / sigma_t.
 * Then poly_composite.frag writes out = base e^(-sigma_t d) + inscatter.
 *
 * Point and spot lights (since issue 25) take the same two steps with one mesh per record
 * of their shadow map (lightgraph/shadowmap.h 3.2: a spot's one perspective map, a point
 * light's six cube faces): the map's depth surface unprojected through its perspective
 * view_proj, the frustum's sides converging at the light's position, its far side beyond
 * the fog (poly_persp). Each crossing then adds sign L_c sigma_s A(0, min(s, d)), A the
 * airlight integral from the eye (lg_point_inscatter with `point_nodes` nodes), so the
 * signed sum is the integral over the lit intervals as before. The six faces of a cube
 * share their side walls (coincident triangles of opposite orientation): a ray crossing
 * from one face's frustum into the next leaves one and enters the other at the same s,
 * and the two terms cancel. A point or spot light without a map (the shadow map lacks it,
 * or the shadowmap node was gated) is unshadowed: one triangle over the viewport adds
 * A(0, d) at every pixel. With the eye at a point or spot light (within LG_LIGHT_EPSILON)
 * the faces through the light are edge-on from it and the volume pass drops them
 * (poly_volume.frag, radial_face). A dual-paraboloid map is refused (its depth surface is not a
 * perspective unprojection), and so is a heterogeneous medium (vol_setup_make without
 * VOL_ACCEPT_FIELD: the closed forms need a homogeneous one).
 *
 * Geometry conventions (view rays, d, z_limit) are plugins/volumetric_common/vol_common.h's.
 * For step 2 the camera's far plane is moved to infinity and its near plane to
 * POLY_NEAR_REL z_limit from the eye, so that no crossing between the eye and the fog's end
 * is clipped away (README "Near plane": the camera's own znear dropped the crossings before
 * it, and a ray in a shadow at znear lost its whole lit interval before it).
 *
 * Memory per mesh (a directional or spot light has one, a point light six): one vertex
 * buffer of (Ws Hs + 2 (Ws - 1) + 2 (Hs - 1) + 8) vec4; once for all meshes the index buffer (3 uint32 per triangle). Both are lg_gl_buffers, kept
 * between frames (remade when the grid grows or a light is added; the indices uploaded
 * again when the grid changes) and counted by the SDK, release included; the mesh itself
 * is generated again on every execute.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "lightgraph/gl_pass.h"
#include "lightgraph/lightgraph.h"
#include "lightgraph/medium.h"
#include "lightgraph/scene.h"
#include "lightgraph/shadowmap.h"

#include "vol_common.h"

#include "poly_composite.frag.h"
#include "poly_fullscreen.vert.h"
#include "poly_mesh.comp.h"
#include "poly_volume.frag.h"
#include "poly_volume.vert.h"

/* The near plane of the volume pass, relative to z_limit (see poly_execute, step 2). */
#define POLY_NEAR_REL 1e-6f
/* Meshes: one per directional or spot light, six per point light. */
#define POLY_MAX_MESHES (6 * VOL_MAX_LIGHTS)
/* poly_mesh.comp's u_far for a perspective map: any value above the capped grid's NDC 1 */
#define POLY_PERSP_FAR 2.0f

typedef struct poly_state {
    int64_t resolution; /* 0: one vertex per texel */
    float z_limit;
    bool per_frame;
    const char *mesh_file; /* debug: the meshes as PLY ("" none) */
    int32_t point_nodes;   /* Gauss-Legendre nodes of the point/spot airlight integral */
    uint32_t width, height;

    lg_gl_pass *mesh, *vol, *comp;
    bool vol_local; /* vol was compiled with POLY_LOCAL (point and spot lights) */
    lg_gl_uniform m_inv_light, m_tile, m_res, m_grid, m_bias, m_near, m_far, m_outer;
    lg_gl_uniform m_persp, m_light, m_far_scale;
    lg_gl_binding m_atlas, m_verts;
    lg_gl_uniform v_flip, v_lc, v_dir;
    lg_gl_uniform v_type, v_pos, v_range, v_cone, v_nodes, v_full, v_apex_eye, v_grid;
    lg_gl_binding v_view;
    lg_gl_binding v_verts, v_idx, v_depth;
    lg_gl_binding c_view;
    lg_gl_binding c_base, c_depth, c_ins;

    lg_gl_buffer vbuf[POLY_MAX_MESHES], ibuf;
    uint32_t ibuf_grid[2]; /* the grid whose indices ibuf holds */
    uint64_t n_indices;
    bool reported_nonfinite; /* base's NaN/Inf pixels said (lg_check_input_finite) */
    /* GL_SAMPLES_PASSED and GL_PRIMITIVES_GENERATED around the volume pass's draws: the
     * fragments the light volumes cost (their overdraw) and the triangles they send, said
     * in the node's log line (poly_report) */
    GLuint queries[2];
} poly_state;

/* ---- the mesh's topology --------------------------------------------------------------------- */

/* Vertex and triangle counts of a Ws x Hs grid's closed mesh. */
static uint64_t poly_vertices(uint32_t ws, uint32_t hs)
{
    return (uint64_t)ws * hs + 2u * (ws - 1) + 2u * (hs - 1) + 8;
}
static uint64_t poly_triangles(uint32_t ws, uint32_t hs)
{
    uint64_t ring = 2u * (uint64_t)(ws - 1) + 2u * (hs - 1);
    return 2u * (uint64_t)(ws - 1) * (hs - 1) + 3u * ring + 14;
}

/* Grid vertex of border (ring) index q, as ring_cell() in poly_mesh.comp. */
static uint32_t poly_ring_cell(uint32_t ws, uint32_t hs, uint32_t q)
{
    uint32_t W = ws - 1, H = hs - 1, i, j;
    if (q < W)
        i = q, j = 0;
    else if (q < W + H)
        i = W, j = q - W;
    else if (q < 2 * W + H)
        i = W - (q - W - H), j = H;
    else
        i = 0, j = H - (q - 2 * W - H);
    return j * ws + i;
}

/* The triangles (3 indices each) in the vertex order of poly_mesh.comp, each turning
 * counter-clockwise about the lit volume's outward normal in light NDC (x, y across the
 * tile, z away from the light): the grid +z; the dent's walls towards the tile's centre;
 * the frame around the tile on the far side +z; the box's walls away from it; its cap on
 * the light's side -z. Every edge is shared by exactly two triangles (watertight).
 * `out` holds 3 poly_triangles(ws, hs) entries. */
static void poly_indices(uint32_t ws, uint32_t hs, uint32_t *out)
{
    size_t k = 0;
    for (uint32_t j = 0; j + 1 < hs; j++)
        for (uint32_t i = 0; i + 1 < ws; i++) {
            uint32_t a = j * ws + i, b = a + 1, c = a + ws + 1, d = a + ws;
            out[k++] = a, out[k++] = b, out[k++] = c;
            out[k++] = a, out[k++] = c, out[k++] = d;
        }
    uint32_t W = ws - 1, H = hs - 1;
    uint32_t ring = 2 * W + 2 * H, far = ws * hs, fc = far + ring, nc = fc + 4;
    /* where each side of the tile starts on the ring: bottom, right, top, left */
    const uint32_t side_start[5] = { 0, W, W + H, 2 * W + H, ring };
    for (uint32_t side = 0; side < 4; side++) {
        for (uint32_t r = side_start[side]; r < side_start[side + 1]; r++) {
            uint32_t r1 = (r + 1) % ring;
            uint32_t g0 = poly_ring_cell(ws, hs, r), g1 = poly_ring_cell(ws, hs, r1);
            uint32_t f0 = far + r, f1 = far + r1;
            /* the dent's wall under the border edge g0 -> g1 (normal towards the centre) */
            out[k++] = f0, out[k++] = f1, out[k++] = g1;
            out[k++] = f0, out[k++] = g1, out[k++] = g0;
            /* the far frame: a fan from the side's starting outer corner */
            out[k++] = fc + side, out[k++] = f1, out[k++] = f0;
        }
        /* the rest of the frame's trapezoid, to the side's ending corners */
        uint32_t c0 = fc + side, c1 = fc + (side + 1) % 4;
        out[k++] = c0, out[k++] = c1, out[k++] = far + side_start[side + 1] % ring;
        /* the box's wall on this side (normal outwards) */
        uint32_t n0 = nc + side, n1 = nc + (side + 1) % 4;
        out[k++] = c0, out[k++] = n1, out[k++] = c1;
        out[k++] = c0, out[k++] = n0, out[k++] = n1;
    }
    /* the cap on the light's side */
    out[k++] = nc + 0, out[k++] = nc + 2, out[k++] = nc + 1;
    out[k++] = nc + 0, out[k++] = nc + 3, out[k++] = nc + 2;
}

/* ---- create / prepare ------------------------------------------------------------------------ */

static int poly_create(lg_node *n)
{
    poly_state *st = lg_create_state(n, sizeof *st);
    if (!st)
        return LG_ERR_NOMEM;
    st->resolution = lg_param_int(n, "resolution");
    double z = lg_param_float(n, "z_limit");
    st->per_frame = lg_param_bool(n, "per_frame");
    st->mesh_file = lg_param_string(n, "mesh_file");
    st->point_nodes = (int32_t)lg_param_int(n, "point_nodes");
    if (st->resolution == 1)
        return lg_error(n, "resolution = 1: the mesh needs at least 2 x 2 vertices; give 0 "
                           "(one per shadow-map texel) or 2 .. 16384");
    if (!isfinite(z) || z < 0.0)
        return lg_error(n, "z_limit = %g: give a view depth > 0, or 0 for the camera's zfar", z);
    st->z_limit = (float)z;
    return 0;
}

static int poly_prepare(lg_node *n)
{
    poly_state *st = n->user;
    int rc = vol_declare_outputs(n, &st->width, &st->height);
    if (rc)
        return rc;
    lg_resource_info info;
    const lg_resource *sh = lg_input(n, VOL_IN_SHADOWS);
    lg_assert_input(n, VOL_IN_SHADOWS); /* required here, unlike in froxel */
    if (lg_describe(sh, &info, n) != 0 || info.kind != LG_KIND_SHADOWMAP)
        return lg_error(n, "input 'shadows' is not a shadow map");
    if (st->per_frame)
        lg_set_per_frame(n, true);
    return lg_set_device(n, LG_DEVICE_GL);
}

/* ---- the passes ------------------------------------------------------------------------------ */

/* The block PolyView (std140, shaders/volumetric_polygonal/poly_view.glsl) that the volume
 * pass and the composite read, uploaded with one lg_gl_pass_uniforms in each. */
typedef struct poly_gpu_view {
    float view_proj[16];
    float inv_view_proj[16];
    float eye[3];
    float z_limit;
    float forward[3];
    float g;
    float sigma_s[3];
    float pad0_;
    float sigma_t[3];
    float pad1_;
    float size[2];
    float pad2_[2];
} poly_gpu_view;

LG_GL_BLOCK_SIZE(poly_gpu_view, 208);
LG_GL_BLOCK_OFFSET(poly_gpu_view, inv_view_proj, 64);
LG_GL_BLOCK_OFFSET(poly_gpu_view, z_limit, 140);
LG_GL_BLOCK_OFFSET(poly_gpu_view, g, 156);
LG_GL_BLOCK_OFFSET(poly_gpu_view, sigma_t, 176);
LG_GL_BLOCK_OFFSET(poly_gpu_view, size, 192);

/* local: the frame has a point or spot light. The volume pass is compiled with
 * POLY_LOCAL only then: a scene of directional lights runs the shaders it ran before point
 * and spot lights existed (their code, even behind a uniform branch, cost llvmpipe 15-20 %
 * a fragment: docs/volumetric.md, "The cost of a directional scene"). */
static int poly_passes(lg_node *n, poly_state *st, bool local)
{
    int rc;
    if (st->vol && st->vol_local != local)
        lg_gl_pass_destroy(&st->vol);
    if (!st->mesh) {
        static const lg_gl_shader_src src[] = {
            { GL_COMPUTE_SHADER, lg_src_poly_mesh_comp_file, lg_src_poly_mesh_comp },
        };
        lg_gl_pass_desc d = { .name = "volumetric_polygonal mesh", .stages = src, .n_stages = 1 };
        if ((rc = lg_gl_pass_create(n, &d, &st->mesh)))
            return rc;
        lg_gl_pass *p = st->mesh;
        st->m_inv_light = lg_gl_pass_uniform(p, "u_inv_light");
        st->m_tile = lg_gl_pass_uniform(p, "u_tile");
        st->m_res = lg_gl_pass_uniform(p, "u_res");
        st->m_grid = lg_gl_pass_uniform(p, "u_grid");
        st->m_bias = lg_gl_pass_uniform(p, "u_bias");
        st->m_near = lg_gl_pass_uniform(p, "u_near");
        st->m_far = lg_gl_pass_uniform(p, "u_far");
        st->m_outer = lg_gl_pass_uniform(p, "u_outer");
        st->m_persp = lg_gl_pass_uniform(p, "u_persp");
        st->m_light = lg_gl_pass_uniform(p, "u_light");
        st->m_far_scale = lg_gl_pass_uniform(p, "u_far_scale");
        st->m_atlas = lg_gl_pass_texture(p, "u_atlas");
        st->m_verts = lg_gl_pass_storage(p, "Vertices");
    }
    if (!st->vol) {
        static const lg_gl_shader_src src[] = {
            { GL_VERTEX_SHADER, lg_src_poly_volume_vert_file, lg_src_poly_volume_vert },
            { GL_FRAGMENT_SHADER, lg_src_poly_volume_frag_file, lg_src_poly_volume_frag },
        };
        /* every fragment counts: no depth test, no culling, additive blending */
        lg_gl_pass_desc d = { .name = "volumetric_polygonal volume",
                              .stages = src,
                              .n_stages = 2,
                              .defines = local ? "#define POLY_LOCAL 1\n" : NULL,
                              .output = "inscatter",
                              .colors = { GL_RGBA32F },
                              .blend = LG_GL_BLEND_ADD };
        if ((rc = lg_gl_pass_create(n, &d, &st->vol)))
            return rc;
        st->vol_local = local;
        /* which program a frame runs, said when it is compiled (tests read it) */
        lg_log(n, LG_LOG_INFO, "volume program: %s",
               local ? "point and spot lights (compiled with POLY_LOCAL)"
                     : "directional lights only (compiled without POLY_LOCAL)");
        lg_gl_pass *p = st->vol;
        st->v_view = lg_gl_pass_uniform_block(p, "PolyView");
        st->v_flip = lg_gl_pass_uniform(p, "u_flip");
        st->v_lc = lg_gl_pass_uniform(p, "u_l_c");
        st->v_dir = lg_gl_pass_uniform(p, "u_dir");
        if (local) { /* the directional program has none of these */
            st->v_type = lg_gl_pass_uniform(p, "u_type");
            st->v_pos = lg_gl_pass_uniform(p, "u_pos");
            st->v_range = lg_gl_pass_uniform(p, "u_range");
            st->v_cone = lg_gl_pass_uniform(p, "u_cone");
            st->v_nodes = lg_gl_pass_uniform(p, "u_nodes");
            st->v_full = lg_gl_pass_uniform(p, "u_full");
            st->v_apex_eye = lg_gl_pass_uniform(p, "u_apex_eye");
            st->v_grid = lg_gl_pass_uniform(p, "u_grid");
        }
        st->v_verts = lg_gl_pass_storage(p, "Vertices");
        st->v_idx = lg_gl_pass_storage(p, "Indices");
        st->v_depth = lg_gl_pass_texture(p, "u_base_depth");
    }
    if (!st->comp) {
        static const lg_gl_shader_src src[] = {
            { GL_VERTEX_SHADER, lg_src_poly_fullscreen_vert_file, lg_src_poly_fullscreen_vert },
            { GL_FRAGMENT_SHADER, lg_src_poly_composite_frag_file, lg_src_poly_composite_frag },
        };
        /* every pixel is written, its depth base's: no test against the cleared plane */
        lg_gl_pass_desc d = { .name = "volumetric_polygonal composite",
                              .stages = src,
                              .n_stages = 2,
                              .output = "out",
                              .colors = { GL_RGBA32F },
                              .depth = true,
                              .depth_test = true,
                              .depth_write = true,
                              .depth_func = GL_ALWAYS };
        if ((rc = lg_gl_pass_create(n, &d, &st->comp)))
            return rc;
        lg_gl_pass *p = st->comp;
        st->c_view = lg_gl_pass_uniform_block(p, "PolyView");
        st->c_base = lg_gl_pass_texture(p, "u_base");
        st->c_depth = lg_gl_pass_texture(p, "u_base_depth");
        st->c_ins = lg_gl_pass_texture(p, "u_inscatter");
    }
    return 0;
}

/* ---- geometry helpers ------------------------------------------------------------------------ */

static void poly_mat_mul(float out[16], const float a[16], const float b[16])
{
    for (int c = 0; c < 4; c++)
        for (int r = 0; r < 4; r++) {
            double s = 0.0;
            for (int k = 0; k < 4; k++)
                s += (double)a[k * 4 + r] * b[c * 4 + k];
            out[c * 4 + r] = (float)s;
        }
}

/* Inverse of an affine (orthographic) 4x4 in double, column-major; its 3x3 determinant in
 * *det. Returns -1 when singular or when the bottom row is not (0 0 0 1). */
static int poly_inv_affine(const float m[16], float out[16], double *det)
{
    if (m[3] != 0.0f || m[7] != 0.0f || m[11] != 0.0f || m[15] != 1.0f)
        return -1;
    double a[3][3], inv[3][3];
    for (int r = 0; r < 3; r++)
        for (int c = 0; c < 3; c++)
            a[r][c] = m[c * 4 + r];
    double d = a[0][0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1]) -
               a[0][1] * (a[1][0] * a[2][2] - a[1][2] * a[2][0]) +
               a[0][2] * (a[1][0] * a[2][1] - a[1][1] * a[2][0]);
    if (!(fabs(d) > 0.0) || !isfinite(d))
        return -1;
    for (int r = 0; r < 3; r++)
        for (int c = 0; c < 3; c++) {
            int r1 = (c + 1) % 3, r2 = (c + 2) % 3, c1 = (r + 1) % 3, c2 = (r + 2) % 3;
            inv[r][c] = (a[r1][c1] * a[r2][c2] - a[r1][c2] * a[r2][c1]) / d;
        }
    memset(out, 0, 16 * sizeof(float));
    for (int r = 0; r < 3; r++) {
        double t = 0.0;
        for (int c = 0; c < 3; c++) {
            out[c * 4 + r] = (float)inv[r][c];
            t -= inv[r][c] * m[12 + c];
        }
        out[12 + r] = (float)t;
    }
    out[15] = 1.0f;
    *det = d;
    return 0;
}

/* The box in light NDC that holds the camera's fog (its eye, its near-plane corners and the
 * corners of the plane at view depth z_limit; the fog is their convex hull and the map is
 * affine) and the light's tile [-1, 1]^2 x [-1, 1], with a margin so that no crossing sits
 * on its faces: lo/hi = x, y, z. */
static void poly_fog_points(const vol_setup *v, double pts[9][3])
{
    memcpy(pts[0], v->eye, sizeof pts[0]);
    for (int k = 0; k < 4; k++) {
        double x = (k & 1) ? v->width : 0.0, y = (k & 2) ? v->height : 0.0, w[3];
        vol_ray(v, x, y, w);
        double c = w[0] * v->forward[0] + w[1] * v->forward[1] + w[2] * v->forward[2];
        double tn = v->view.znear / c, tf = v->z_limit / c;
        for (int i = 0; i < 3; i++) {
            pts[1 + k][i] = v->eye[i] + w[i] * tn;
            pts[5 + k][i] = v->eye[i] + w[i] * tf;
        }
    }
}

/* The box of the points above in the light's NDC (orthographic), with the tile, widened. */
static void poly_fog_box(const vol_setup *v, const float light_vp[16], float lo_out[3],
                         float hi_out[3])
{
    double pts[9][3];
    poly_fog_points(v, pts);
    for (int c = 0; c < 3; c++) {
        double lo = -1.0, hi = 1.0;
        for (int k = 0; k < 9; k++) {
            double z = light_vp[c] * pts[k][0] + light_vp[4 + c] * pts[k][1] +
                       light_vp[8 + c] * pts[k][2] + light_vp[12 + c];
            lo = z < lo ? z : lo;
            hi = z > hi ? z : hi;
        }
        /* a margin of 1 % of the range and at least 0.01 */
        double m = 0.01 * (hi - lo) + 0.01;
        lo_out[c] = (float)(lo - m);
        hi_out[c] = (float)(hi + m);
    }
}

/* ---- perspective maps (point and spot lights) ------------------------------------------------ */

/* The determinant of a column-major 4x4, in double (Laplace along the 2x2 minors). */
static double poly_det4(const float f[16])
{
    double m[16];
    for (int i = 0; i < 16; i++)
        m[i] = f[i];
#define M(r, c) m[(c)*4 + (r)]
    double s0 = M(0, 0) * M(1, 1) - M(1, 0) * M(0, 1), s1 = M(0, 0) * M(1, 2) - M(1, 0) * M(0, 2);
    double s2 = M(0, 0) * M(1, 3) - M(1, 0) * M(0, 3), s3 = M(0, 1) * M(1, 2) - M(1, 1) * M(0, 2);
    double s4 = M(0, 1) * M(1, 3) - M(1, 1) * M(0, 3), s5 = M(0, 2) * M(1, 3) - M(1, 2) * M(0, 3);
    double c5 = M(2, 2) * M(3, 3) - M(3, 2) * M(2, 3), c4 = M(2, 1) * M(3, 3) - M(3, 1) * M(2, 3);
    double c3 = M(2, 1) * M(3, 2) - M(3, 1) * M(2, 2), c2 = M(2, 0) * M(3, 3) - M(3, 0) * M(2, 3);
    double c1 = M(2, 0) * M(3, 2) - M(3, 0) * M(2, 2), c0 = M(2, 0) * M(3, 1) - M(3, 0) * M(2, 1);
#undef M
    return s0 * c5 - s1 * c4 + s2 * c3 + s3 * c2 - s4 * c1 + s5 * c0;
}

/* Light NDC (x, y, z) -> world through the inverse view_proj `inv`; false when the point is
 * at or behind the projection's centre (w <= 0) or not finite. */
static bool poly_unproject(const float inv[16], double x, double y, double z, double out[3])
{
    double h[4];
    for (int r = 0; r < 4; r++)
        h[r] = inv[r] * x + inv[4 + r] * y + inv[8 + r] * z + inv[12 + r];
    if (!(h[3] > 0.0) && !(h[3] < 0.0))
        return false;
    for (int r = 0; r < 3; r++)
        out[r] = h[r] / h[3];
    return isfinite(out[0]) && isfinite(out[1]) && isfinite(out[2]);
}

/* The distance from q to the plane through the first three of four points. */
static double poly_plane_distance(const double q[3], const double c[4][3])
{
    double a[3], b[3], nrm[3];
    for (int i = 0; i < 3; i++) {
        a[i] = c[1][i] - c[0][i];
        b[i] = c[2][i] - c[0][i];
    }
    nrm[0] = a[1] * b[2] - a[2] * b[1];
    nrm[1] = a[2] * b[0] - a[0] * b[2];
    nrm[2] = a[0] * b[1] - a[1] * b[0];
    double nl = sqrt(nrm[0] * nrm[0] + nrm[1] * nrm[1] + nrm[2] * nrm[2]);
    if (!(nl > 0.0))
        return NAN;
    return fabs(nrm[0] * (c[0][0] - q[0]) + nrm[1] * (c[0][1] - q[1]) + nrm[2] * (c[0][2] - q[2])) /
           nl;
}

/* A perspective record's mesh parameters (poly_mesh.comp): the inverse of its view_proj,
 * the orientation of NDC -> world (the sign of the 4x4 determinant: the Jacobian of a
 * projective map is det / w^4, of one sign in front of the light) and the far side's
 * distance from the light over the near plane's, so that the far side lies beyond both
 * the map's far plane and every point of the camera's fog (the hull of poly_fog_points:
 * its farthest point from the light is one of its corners). The map must be centred on
 * the light: its near and far corners on common rays from the light's position. */
static int poly_persp(lg_node *n, const vol_setup *v, const vol_light *vl, int32_t rec,
                      const lg_shadow_light *L, float inv[16], double *flip, float *far_scale)
{
    uint32_t li = vl->scene_index;
    double det = poly_det4(L->view_proj);
    if (!(fabs(det) > 0.0) || !isfinite(det) || lg_m4_invert(inv, L->view_proj) != 0)
        return lg_error(n, "light %u: its shadow map record %d's view_proj is singular", li, rec);
    const double q[3] = { vl->pos[0], vl->pos[1], vl->pos[2] };
    double nc[4][3], fc[4][3];
    bool ok = true;
    double worst = 0.0;
    for (int k = 0; k < 4 && ok; k++) {
        double x = (k & 1) ? 1.0 : -1.0, y = (k & 2) ? 1.0 : -1.0;
        ok = poly_unproject(inv, x, y, -1.0, nc[k]) && poly_unproject(inv, x, y, 1.0, fc[k]);
        /* the angle between q -> near corner and q -> far corner */
        double a[3], b[3], cr[3];
        for (int i = 0; ok && i < 3; i++) {
            a[i] = nc[k][i] - q[i];
            b[i] = fc[k][i] - q[i];
        }
        cr[0] = a[1] * b[2] - a[2] * b[1];
        cr[1] = a[2] * b[0] - a[0] * b[2];
        cr[2] = a[0] * b[1] - a[1] * b[0];
        double la = sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
        double lb = sqrt(b[0] * b[0] + b[1] * b[1] + b[2] * b[2]);
        double sn = sqrt(cr[0] * cr[0] + cr[1] * cr[1] + cr[2] * cr[2]) / (la * lb);
        double dt = a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
        if (!(dt > 0.0))
            sn = INFINITY;
        worst = fmax(worst, isfinite(sn) ? sn : INFINITY);
    }
    double zn = ok ? poly_plane_distance(q, nc) : NAN, zf = ok ? poly_plane_distance(q, fc) : NAN;
    if (!ok || !(zn > 0.0) || !(zf > zn) || !isfinite(zf))
        return lg_error(n,
                        "light %u: its shadow map record %d is not a perspective frustum "
                        "in front of the light (near plane at %g, far plane at %g)",
                        li, rec, zn, zf);
    if (!(worst < 1e-3))
        return lg_error(n,
                        "light %u: its shadow map record %d is not centred on the light at "
                        "[%g, %g, %g] (its frustum's edges miss it by %.3g rad)",
                        li, rec, q[0], q[1], q[2], worst);
    double pts[9][3], far = zf;
    poly_fog_points(v, pts);
    for (int k = 0; k < 9; k++) {
        double d2 = 0.0;
        for (int i = 0; i < 3; i++)
            d2 += (pts[k][i] - q[i]) * (pts[k][i] - q[i]);
        far = fmax(far, sqrt(d2));
    }
    *far_scale = (float)(1.01 * far / zn);
    *flip = det > 0.0 ? 1.0 : -1.0;
    return 0;
}

/* ---- the debug dump -------------------------------------------------------------------------- */

/* Writes every light's mesh (read back from GL) as one binary little-endian PLY: vertex
 * positions (float x y z, world) and triangles (uchar count, int indices) turning
 * counter-clockwise about the outward normal in world space. Made in memory, then handed to
 * the host (lg_output_file_write), which checked the destination before the render and
 * renames it into place with the render's other outputs, or not at all. */
static int poly_write_ply(lg_node *n, poly_state *st, const lg_gl *gl, uint32_t n_lights,
                          const uint32_t grid[][2], const double flip[])
{
    uint64_t nv = 0, nt = 0;
    for (uint32_t l = 0; l < n_lights; l++) {
        nv += poly_vertices(grid[l][0], grid[l][1]);
        nt += poly_triangles(grid[l][0], grid[l][1]);
    }
    char header[512];
    int hl = snprintf(header, sizeof header,
                      "ply\nformat binary_little_endian 1.0\ncomment lightgraph "
                      "volumetric_polygonal: the lit volume of %u mesh(es), outward "
                      "counter-clockwise\nelement vertex %llu\nproperty float x\nproperty "
                      "float y\nproperty float z\nelement face %llu\nproperty list uchar int "
                      "vertex_indices\nend_header\n",
                      n_lights, (unsigned long long)nv, (unsigned long long)nt);
    /* 12 bytes a vertex, 13 a face; at most 32 lights of 16384^2 vertices, which a 64-bit
     * size_t holds (the allocation fails first) */
    size_t size = (size_t)hl + (size_t)nv * 12 + (size_t)nt * 13;
    unsigned char *out = malloc(size);
    if (!out)
        return lg_error_code(n, LG_ERR_NOMEM, "mesh_file: out of memory for %zu bytes", size);
    unsigned char *w = out;
    memcpy(w, header, (size_t)hl);
    w += hl;
    int rc = 0;
    for (uint32_t l = 0; l < n_lights && !rc; l++) {
        uint64_t v = poly_vertices(grid[l][0], grid[l][1]);
        float *buf = malloc((size_t)v * 16);
        if (!buf) {
            rc = lg_error_code(n, LG_ERR_NOMEM, "out of memory");
            break;
        }
        gl->GetNamedBufferSubData(st->vbuf[l].name, 0, (GLsizeiptr)(v * 16), buf);
        for (uint64_t i = 0; i < v; i++, w += 12)
            memcpy(w, buf + 4 * i, 12);
        free(buf);
    }
    uint64_t offset = 0;
    for (uint32_t l = 0; l < n_lights && !rc; l++) {
        uint64_t t = poly_triangles(grid[l][0], grid[l][1]);
        uint32_t *idx = malloc((size_t)t * 12);
        if (!idx) {
            rc = lg_error_code(n, LG_ERR_NOMEM, "out of memory");
            break;
        }
        poly_indices(grid[l][0], grid[l][1], idx);
        for (uint64_t i = 0; i < t; i++, w += 13) {
            int32_t tri[3] = { (int32_t)(idx[3 * i] + offset), (int32_t)(idx[3 * i + 1] + offset),
                               (int32_t)(idx[3 * i + 2] + offset) };
            if (flip[l] < 0) {
                int32_t s = tri[1];
                tri[1] = tri[2];
                tri[2] = s;
            }
            w[0] = 3;
            memcpy(w + 1, tri, 12);
        }
        free(idx);
        offset += poly_vertices(grid[l][0], grid[l][1]);
    }
    if (!rc)
        rc = lg_output_file_write(n, "mesh_file", out, size);
    free(out);
    return rc;
}

/* ---- the volume pass's counters -------------------------------------------------------------- */

/* The volume pass rasterises every crossing of every pixel's ray with every light's mesh
 * (no depth test, no culling), so its fragment count is the method's real per-pixel work:
 * fragments / pixels is the mean number of volume faces a view ray crosses, whatever the
 * scene's triangle count. Said on the first frame at info level (`-v`), later frames at
 * debug level (an animated scene's counts change), as one line a script can read:
 *   "volume pass: L lights, T triangles drawn, P primitives generated, F fragments,
 *    X per pixel (WxH)". */
static void poly_report(lg_node *n, const lg_gl *gl, const poly_state *st, const lg_frame *frame,
                        uint32_t n_lights, uint64_t tris_drawn)
{
    GLuint64 fragments = 0, primitives = 0;
    gl->GetQueryObjectui64v(st->queries[0], GL_QUERY_RESULT, &fragments);
    gl->GetQueryObjectui64v(st->queries[1], GL_QUERY_RESULT, &primitives);
    double pixels = (double)st->width * st->height;
    lg_log(n, frame && frame->index > 0 ? LG_LOG_DEBUG : LG_LOG_INFO,
           "volume pass: %u light%s, %llu triangles drawn, %llu primitives generated, %llu "
           "fragments, %.4f per pixel (%ux%u)",
           n_lights, n_lights == 1 ? "" : "s", (unsigned long long)tris_drawn,
           (unsigned long long)primitives, (unsigned long long)fragments,
           pixels > 0 ? (double)fragments / pixels : 0.0, st->width, st->height);
}

/* ---- execute --------------------------------------------------------------------------------- */

static int poly_execute(lg_node *n, const lg_frame *frame)
{
    poly_state *st = n->user;
    /* base passes into `out`: its NaN and Inf are said once, as `image` says a file's */
    int rc0 = lg_check_input_finite(n, frame, VOL_IN_BASE, "base", NULL, &st->reported_nonfinite);
    if (rc0)
        return rc0;
    const lg_scene *s = lg_scene_get(n, lg_input(n, VOL_IN_SCENE));
    if (!s)
        return LG_ERR_INVALID;
    lg_shadowmap smv;
    const lg_shadowmap *sm = lg_shadowmap_get(n, lg_input(n, VOL_IN_SHADOWS), &smv);
    vol_setup v;
    int rc = vol_setup_make(n, s, st->width, st->height, st->z_limit, sm, VOL_ACCEPT_LIGHTS, &v);
    if (rc)
        return rc;
    bool any_dir = false;
    for (uint32_t l = 0; l < v.n_lights; l++)
        any_dir = any_dir || v.lights[l].type == LG_LIGHT_DIRECTIONAL;
    if (!sm && any_dir)
        return lg_error(n, "input 'shadows' holds no shadow map (its node was gated: the "
                           "scene has no light it makes maps of)");
    if (!sm)
        lg_log(n, LG_LOG_WARN,
               "input 'shadows' holds no shadow map (its node was gated): the scene's %u point "
               "and spot light(s) are unshadowed",
               v.n_lights);
    if (sm && (!sm->atlas || sm->resolution < 2 || (!sm->lights && sm->n_lights)))
        return lg_error(n, "input 'shadows': the shadow maps have no atlas, a resolution "
                           "below 2 or no light list");

    /* the meshes: one per directional or spot light's record, six per point light's cube;
     * a point or spot light without a record gets none (unshadowed, drawn over the whole
     * view) */
    typedef struct poly_mesh {
        uint32_t light; /* in v.lights */
        int32_t rec;    /* in sm->lights */
        bool persp;
        double flip;
        float far_scale;
        float inv[16];
    } poly_mesh;
    poly_mesh meshes[POLY_MAX_MESHES];
    uint32_t n_meshes = 0, n_full = 0;
    for (uint32_t l = 0; l < v.n_lights; l++) {
        const vol_light *vl = &v.lights[l];
        if (vl->shadow < 0) {
            if (vl->type == LG_LIGHT_DIRECTIONAL)
                return lg_error(n,
                                "light %u (scene light %u) has no shadow map in input "
                                "'shadows': connect a shadowmap node of this scene",
                                l, vl->scene_index);
            n_full++;
            continue;
        }
        uint32_t faces = vl->type == LG_LIGHT_POINT ? 6 : 1;
        for (uint32_t f = 0; f < faces; f++) {
            int32_t r = vl->shadow + (int32_t)f;
            const lg_shadow_light *L = (uint32_t)r < sm->n_lights ? &sm->lights[r] : NULL;
            bool persp = vl->type != LG_LIGHT_DIRECTIONAL;
            if (L && (L->face == LG_SHADOW_FACE_PARABOLOID_FRONT ||
                      L->face == LG_SHADOW_FACE_PARABOLOID_BACK))
                return lg_error(n,
                                "light %u: its shadow map is dual-paraboloid; "
                                "volumetric_polygonal builds its volumes from perspective "
                                "maps only (a paraboloid's depth surface is not a "
                                "perspective unprojection): make cube maps (point_mode)",
                                vl->scene_index);
            if (!L || L->light != vl->scene_index || L->face != f ||
                L->projection != (persp ? LG_SHADOW_PERSPECTIVE : LG_SHADOW_ORTHOGRAPHIC))
                return lg_error(n,
                                "light %u (%s): input 'shadows' has no %s record for its map "
                                "%u (record %d): a %s light needs %u consecutive record(s), "
                                "faces 0 .. %u",
                                vl->scene_index,
                                vl->type == LG_LIGHT_POINT  ? "point"
                                : vl->type == LG_LIGHT_SPOT ? "spot"
                                                            : "directional",
                                persp ? "perspective" : "orthographic", f, r,
                                vl->type == LG_LIGHT_POINT ? "point" : "directional or spot", faces,
                                faces - 1);
            poly_mesh *m = &meshes[n_meshes++];
            m->light = l;
            m->rec = r;
            m->persp = persp;
            m->far_scale = 0.0f;
        }
    }
    uint32_t R = sm ? sm->resolution : 2;
    uint32_t ws = st->resolution == 0 ? R : (uint32_t)st->resolution;
    if (ws > R) {
        lg_log(n, LG_LOG_INFO, "resolution %u is above the shadow maps' %u: capped", ws, R);
        ws = R;
    }
    uint32_t hs = ws;
    uint64_t nverts = poly_vertices(ws, hs), ntris = poly_triangles(ws, hs);

    const lg_gl *gl = lg_gl_get(n);
    if (!gl)
        return LG_ERR_DEVICE;
    GLint max_block = 0;
    gl->GetIntegerv(GL_MAX_SHADER_STORAGE_BLOCK_SIZE, &max_block);
    uint64_t max_bytes = (uint64_t)(GLuint)max_block;
    if (ntris * 12 > max_bytes || nverts * 16 > max_bytes || ntris * 3 > 0x7fffffffu)
        return lg_error(n,
                        "resolution %u: the mesh (%llu vertices, %llu triangles) exceeds "
                        "the GL device's largest storage buffer (%d bytes); lower "
                        "`resolution`",
                        ws, (unsigned long long)nverts, (unsigned long long)ntris, max_block);
    bool local = false;
    for (uint32_t l = 0; l < v.n_lights; l++)
        local = local || v.lights[l].type != LG_LIGHT_DIRECTIONAL;
    if ((rc = poly_passes(n, st, local)))
        return rc;

    /* the buffers: indices for this grid, a vertex buffer per mesh */
    bool regrid = st->ibuf_grid[0] != ws || st->ibuf_grid[1] != hs;
    if (regrid || !st->ibuf.name) {
        uint32_t *idx = malloc((size_t)ntris * 12);
        if (!idx)
            return lg_error_code(n, LG_ERR_NOMEM, "out of memory (%llu triangles)",
                                 (unsigned long long)ntris);
        poly_indices(ws, hs, idx);
        rc = lg_gl_buffer_recreate(n, &st->ibuf, (size_t)ntris * 12, 0, idx);
        free(idx);
        if (rc)
            return rc;
        st->ibuf_grid[0] = ws;
        st->ibuf_grid[1] = hs;
    }
    for (uint32_t k = 0; k < n_meshes; k++)
        if ((rc = lg_gl_buffer_recreate(n, &st->vbuf[k], (size_t)nverts * 16, 0, NULL)))
            return rc;

    uint32_t atlas_color = 0, atlas = 0, base_tex = 0, base_depth = 0;
    if (n_meshes) {
        if ((rc = lg_map_gl(n, sm->atlas, LG_READ, &atlas_color, &atlas)))
            return rc;
        if (!atlas)
            return lg_error_code(n, LG_ERR_DEVICE,
                                 "input 'shadows': the atlas has no GL depth "
                                 "texture");
    }
    if ((rc = lg_map_gl(n, lg_input(n, VOL_IN_BASE), LG_READ, &base_tex, &base_depth)))
        return rc;
    if (!base_depth)
        return lg_error(n, "input 'base' has no depth plane on GL");

    /* step 1: the meshes */
    double flip[POLY_MAX_MESHES];
    uint32_t grid[POLY_MAX_MESHES][2];
    if (n_meshes && (rc = lg_gl_pass_begin(st->mesh, NULL)))
        return rc;
    if (n_meshes)
        lg_gl_pass_bind_texture(st->mesh, st->m_atlas, atlas);
    for (uint32_t k = 0; k < n_meshes && !rc; k++) {
        poly_mesh *m = &meshes[k];
        const vol_light *vl = &v.lights[m->light];
        const lg_shadow_light *L = &sm->lights[m->rec];
        if ((uint64_t)L->tile_x + R > sm->atlas_width ||
            (uint64_t)L->tile_y + R > sm->atlas_height) {
            rc = lg_error(n,
                          "input 'shadows': light %u's tile at (%u, %u) of side %u lies "
                          "outside the %ux%u atlas",
                          vl->scene_index, L->tile_x, L->tile_y, R, sm->atlas_width,
                          sm->atlas_height);
            break;
        }
        float lo[3], hi[3];
        if (m->persp) {
            if ((rc = poly_persp(n, &v, vl, m->rec, L, m->inv, &m->flip, &m->far_scale)))
                break;
            lo[0] = lo[1] = -1.0f;
            hi[0] = hi[1] = 1.0f;
            lo[2] = -1.0f;
            hi[2] = POLY_PERSP_FAR;
        } else {
            double det;
            if (poly_inv_affine(L->view_proj, m->inv, &det) != 0) {
                rc = lg_error(n,
                              "light %u: its shadow map's view_proj is singular or not "
                              "orthographic",
                              vl->scene_index);
                break;
            }
            /* NDC -> world turns orientation when the inverse's determinant (of det's
             * sign) is negative: the shaders' cross products then point inwards */
            m->flip = det > 0 ? 1.0 : -1.0;
            poly_fog_box(&v, L->view_proj, lo, hi);
        }
        flip[k] = m->flip;
        grid[k][0] = ws;
        grid[k][1] = hs;
        lg_gl_set_mat4(st->mesh, st->m_inv_light, m->inv);
        lg_gl_set_ivec2(st->mesh, st->m_tile, (int32_t)L->tile_x, (int32_t)L->tile_y);
        lg_gl_set_int(st->mesh, st->m_res, (int32_t)R);
        lg_gl_set_ivec2(st->mesh, st->m_grid, (int32_t)ws, (int32_t)hs);
        lg_gl_set_float(st->mesh, st->m_bias, sm->bias_constant);
        lg_gl_set_float(st->mesh, st->m_near, lo[2]);
        lg_gl_set_float(st->mesh, st->m_far, hi[2]);
        const float outer[4] = { lo[0], lo[1], hi[0], hi[1] };
        lg_gl_set_vec4v(st->mesh, st->m_outer, outer);
        lg_gl_set_int(st->mesh, st->m_persp, m->persp ? 1 : 0);
        lg_gl_set_vec3v(st->mesh, st->m_light, vl->pos);
        lg_gl_set_float(st->mesh, st->m_far_scale, m->far_scale);
        lg_gl_pass_bind_buffer(st->mesh, st->m_verts, st->vbuf[k].name);
        /* rows of 65536 invocations (1024 groups of 64; the shader rebuilds the index), so
         * that no axis exceeds GL's 65535 groups however large the mesh */
        uint32_t row = 65536u, rows = (uint32_t)((nverts + row - 1) / row);
        rc = lg_gl_pass_dispatch(st->mesh, nverts < row ? (uint32_t)nverts : row, rows, 1);
    }
    if (n_meshes && (rc = lg_gl_pass_end(st->mesh, rc)))
        return rc;
    if (rc)
        return rc;

    /* step 2: the volumes from the camera, the far plane at infinity and the near plane
     * brought up to the eye. The fog starts at the eye, not at the camera's near plane: a
     * boundary crossed between the two must still add its term, or a ray that enters a
     * shadow before znear and is in it there loses its whole lit interval [0, s] (a camera
     * outside the scene's bounds has znear = 0.99 x the nearest corner's depth, often
     * most of the fog's length). No depth test or write here, so the near plane only
     * clips: at POLY_NEAR_REL x z_limit, a crossing it still drops costs its pixel at
     * most F(1e-6 z_limit / cos), 1e-6 of an unshadowed ray's in-scatter to z_limit
     * (README "Near plane"). */
    float proj[16], vp_inf[16], inv_vp[16];
    memcpy(proj, v.view.proj, sizeof proj);
    if (proj[11] != -1.0f || proj[15] != 0.0f || proj[3] != 0.0f || proj[7] != 0.0f)
        return lg_error(n, "the camera's projection is not a perspective one");
    float near = fminf(v.view.znear, POLY_NEAR_REL * v.z_limit);
    proj[10] = -1.0f;
    proj[14] = -2.0f * near;
    poly_mat_mul(vp_inf, proj, v.view.view);
    for (int i = 0; i < 16; i++)
        inv_vp[i] = (float)v.inv_view_proj[i];
    /* what the volume pass and the composite read: the block PolyView */
    poly_gpu_view view = {
        .eye = { (float)v.eye[0], (float)v.eye[1], (float)v.eye[2] },
        .z_limit = v.z_limit,
        .forward = { (float)v.forward[0], (float)v.forward[1], (float)v.forward[2] },
        .g = v.g,
        .size = { (float)v.width, (float)v.height },
    };
    memcpy(view.view_proj, vp_inf, sizeof view.view_proj);
    memcpy(view.inv_view_proj, inv_vp, sizeof view.inv_view_proj);
    memcpy(view.sigma_s, v.sigma_s, sizeof view.sigma_s);
    memcpy(view.sigma_t, v.sigma_t, sizeof view.sigma_t);
    lg_gl_pass *p = st->vol;
    if ((rc = lg_gl_pass_begin(p, NULL)))
        return rc;
    const float clear[4] = { 0, 0, 0, 1 };
    lg_gl_pass_clear_color(p, 0, clear);
    if ((rc = lg_gl_pass_uniforms(p, st->v_view, &view, sizeof view)))
        return lg_gl_pass_end(p, rc);
    lg_gl_pass_bind_texture(p, st->v_depth, base_depth);
    lg_gl_pass_bind_buffer(p, st->v_idx, st->ibuf.name);
    /* the counters span exactly the draws, and end before the pass restores the state */
    if (!st->queries[0])
        gl->GenQueries(2, st->queries);
    gl->BeginQuery(GL_SAMPLES_PASSED, st->queries[0]);
    gl->BeginQuery(GL_PRIMITIVES_GENERATED, st->queries[1]);
    /* the meshes in order, then the unshadowed point and spot lights' viewport triangles */
    if (st->vol_local) {
        lg_gl_set_int(p, st->v_nodes, st->point_nodes);
        lg_gl_set_ivec2(p, st->v_grid, (int32_t)ws, (int32_t)hs);
    }
    for (uint32_t k = 0; k < n_meshes + v.n_lights && !rc; k++) {
        bool full = k >= n_meshes;
        uint32_t l = full ? k - n_meshes : meshes[k].light;
        const vol_light *vl = &v.lights[l];
        if (full && vl->shadow >= 0)
            continue;
        lg_gl_set_float(p, st->v_flip, full ? 1.0f : (float)flip[k]);
        lg_gl_set_vec3v(p, st->v_lc, vl->l_c);
        lg_gl_set_vec3v(p, st->v_dir, vl->dir);
        if (st->vol_local) {
            lg_gl_set_int(p, st->v_type, (int32_t)vl->type);
            lg_gl_set_vec3v(p, st->v_pos, vl->pos);
            lg_gl_set_float(p, st->v_range, vl->range);
            const float cone[2] = { vl->cos_inner, vl->cos_outer };
            lg_gl_set_vec2(p, st->v_cone, cone[0], cone[1]);
            lg_gl_set_int(p, st->v_full, full ? 1 : 0);
            /* the eye at a point or spot light (within its bulb, LG_LIGHT_EPSILON): the
             * faces through the light are edge-on from the eye; the shader drops them */
            double de = 0.0;
            for (int c = 0; c < 3; c++)
                de += (v.eye[c] - vl->pos[c]) * (v.eye[c] - vl->pos[c]);
            bool apex = !full && vl->type != LG_LIGHT_DIRECTIONAL &&
                        de < LG_LIGHT_EPSILON * LG_LIGHT_EPSILON;
            lg_gl_set_int(p, st->v_apex_eye, apex ? 1 : 0);
        }
        /* the viewport triangle reads no vertex: any buffer keeps the binding valid */
        lg_gl_pass_bind_buffer(p, st->v_verts, full ? st->ibuf.name : st->vbuf[k].name);
        rc = lg_gl_pass_draw(p, GL_TRIANGLES, full ? 3u : (uint32_t)(ntris * 3));
    }
    gl->EndQuery(GL_PRIMITIVES_GENERATED);
    gl->EndQuery(GL_SAMPLES_PASSED);
    if ((rc = lg_gl_pass_end(p, rc)))
        return rc;
    poly_report(n, gl, st, frame, v.n_lights, ntris * n_meshes + n_full);

    /* step 3: the composite */
    lg_gl_target ins;
    if ((rc = lg_gl_target_output(n, "inscatter", &ins)))
        return rc;
    p = st->comp;
    if ((rc = lg_gl_pass_begin(p, NULL)))
        return rc;
    if ((rc = lg_gl_pass_uniforms(p, st->c_view, &view, sizeof view)))
        return lg_gl_pass_end(p, rc);
    lg_gl_pass_bind_texture(p, st->c_base, base_tex);
    lg_gl_pass_bind_texture(p, st->c_depth, base_depth);
    lg_gl_pass_bind_texture(p, st->c_ins, ins.color[0]);
    rc = lg_gl_pass_draw(p, GL_TRIANGLES, 3);
    if ((rc = lg_gl_pass_end(p, rc)))
        return rc;

    if (st->mesh_file && st->mesh_file[0])
        rc = poly_write_ply(n, st, gl, n_meshes, (const uint32_t(*)[2])grid, flip);
    return rc;
}

static void poly_destroy(lg_node *n)
{
    poly_state *st = n->user;
    if (!st)
        return;
    for (int k = 0; k < POLY_MAX_MESHES; k++)
        lg_gl_buffer_destroy(n, &st->vbuf[k]);
    lg_gl_buffer_destroy(n, &st->ibuf);
    if (st->queries[0]) {
        const lg_gl *gl = lg_gl_get(n);
        if (gl)
            gl->DeleteQueries(2, st->queries);
    }
    lg_gl_pass_destroy(&st->mesh);
    lg_gl_pass_destroy(&st->vol);
    lg_gl_pass_destroy(&st->comp);
    free(st);
    n->user = NULL;
}

/* ---- the descriptor -------------------------------------------------------------------------- */

static const lg_param_desc poly_params[] = {
    { .key = "resolution",
      .type = LG_PARAM_INT,
      .def.i = 0,
      .min = 0,
      .max = 16384,
      .doc = "vertices per side of each light's mesh (Ws = Hs); 0 = one per shadow-map texel "
             "(the thesis); capped at the shadow maps' resolution" },
    { .key = "z_limit",
      .type = LG_PARAM_FLOAT,
      .def.f = 0,
      .min = 0,
      .max = 1e30,
      .doc = "view depth where the fog ends, scene units; 0 = the camera's zfar" },
    { .key = "point_nodes",
      .type = LG_PARAM_INT,
      .def.i = 8,
      .min = 1,
      .max = 8,
      .doc = "point and spot lights: Gauss-Legendre nodes of the airlight integral A(0, s) "
             "each volume crossing evaluates (lg_point_inscatter; exact at any count for "
             "g = 0, no extinction and no range; README \"Point and spot lights\")" },
    { .key = "per_frame",
      .type = LG_PARAM_BOOL,
      .def.b = false,
      .doc = "render again on every frame (--frames), for timing; the result is the same" },
    { .key = "mesh_file",
      .type = LG_PARAM_PATH,
      .def.s = "",
      .role = LG_ROLE_OUTPUT_FILE,
      .doc = "debug: write every light's generated mesh (read back from GL) to this binary "
             "PLY file, triangles counter-clockwise about the outward normal; \"\" = none" },
};
static const lg_port_desc poly_inputs[] = {
    { .name = "scene",
      .kind = LG_KIND_SCENE,
      .doc = "the scene: its directional, point and spot lights (1..32), its homogeneous "
             "medium, its active camera" },
    { .name = "base",
      .kind = LG_KIND_IMAGE,
      .doc = "the lit image with its depth (phong's out), of the output's size" },
    { .name = "shadows",
      .kind = LG_KIND_SHADOWMAP,
      .doc = "shadow maps of the same scene's lights: one volume per map record (a "
             "point light's six cube faces each); a point or spot light without one is "
             "unshadowed" },
};
static const lg_port_desc poly_outputs[] = {
    { .name = "out",
      .kind = LG_KIND_IMAGE,
      .doc = "rgba32f + depth: base e^(-sigma_t d) + inscatter; depth = base's" },
    { .name = "inscatter",
      .kind = LG_KIND_IMAGE,
      .doc = "rgba32f: the in-scattered radiance L_v alone (lightgraph/medium.h units), "
             "alpha 1" },
};

static const lg_node_type poly_types[] = {
    {
        .struct_size = sizeof(lg_node_type),
        .name = "volumetric_polygonal",
        .doc = "Light shafts through polygonal light volumes built from the shadow maps "
               "(seed 2, 3.2.2, eq. 9), signed additive accumulation on GL",
        LG_PARAMS(poly_params),
        LG_INPUTS(poly_inputs),
        LG_OUTPUTS(poly_outputs),
        .needs = LG_NEEDS_MEDIUM | LG_NEEDS_LIGHT,
        .neutral = LG_NEUTRAL_PASSTHROUGH_FIRST,
        .neutral_input = VOL_IN_BASE,
        .create = poly_create,
        .prepare = poly_prepare,
        .execute = poly_execute,
        .destroy = poly_destroy,
    },
};

LG_PLUGIN_DEFINE("volumetric_polygonal", "1.0.0",
                 "In-scattering through polygonal light volumes (Billeter 2010, Hoobler "
                 "2016): a mesh per shadow map (directional, spot, a point light's six "
                 "faces), rasterised with signed additive blending",
                 poly_types)
