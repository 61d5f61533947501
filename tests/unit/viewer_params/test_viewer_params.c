/*
 * tests/unit/viewer_params/test_viewer_params.c: the viewer's live parameters
 * (host/viewer/params.c) against the real parser and checker: every assignment a step
 * produces is applied with lg_graph_set and checked with lg_graph_check, as `lightgraph
 * view` does, and the checked value is compared with the one expected.
 *
 * The node types are declared here as plugins declare them (no plugin is loaded):
 *
 *   src        { seed: int [0, 100] }                               -> out (image)
 *   scene      { }                                                  -> scene (scene)
 *   gbuf       { scene <- scene }                                   -> color, depth (image)
 *   lit        { ks_scale: int [1, 1000], ambient: vec3 [0, 1e6], shading: enum,
 *                shininess: float [1, 129], exposure: float, white: float [0, 1e6],
 *                enabled: bool, tint: color [0, 1], albedo: color|{material, vertex},
 *                label: string, file: path, grid: int3 [1, 512], offset: vec2 [-10, 10],
 *                image <- image, scene <- scene (optional), mask <- any (optional) }
 *                                                                   -> out (image)
 *   tone       { key: float [0.001, 100], image <- image }          -> out (image)
 *   vol_froxel { slices: int [8, 256], image <- image, scene <- scene } -> out, inscatter
 *   vol_screen { samples: int [1, 64], image <- image, scene <- scene } -> out, inscatter
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "common/check.h"
#include "graph/graph.h"
#include "base/util.h"
#include "viewer/params.h"

/* ---- the schema ------------------------------------------------------------------------------ */

static const lg_port_desc out_image[] = { { .name = "out", .kind = LG_KIND_IMAGE } };
static const lg_param_desc src_params[] = {
    { .key = "seed", .type = LG_PARAM_INT, .def.i = 0, .min = 0, .max = 100 },
};

static const lg_port_desc out_scene[] = { { .name = "scene", .kind = LG_KIND_SCENE } };
static const lg_port_desc in_scene[] = { { .name = "scene", .kind = LG_KIND_SCENE } };
static const lg_port_desc gbuf_outputs[] = {
    { .name = "color", .kind = LG_KIND_IMAGE },
    { .name = "depth", .kind = LG_KIND_IMAGE },
};

static const char *const shading_values[] = { "flat",  "gouraud",    "phong",
                                              "mixed", "phong_half", NULL };
static const char *const albedo_words[] = { "material", "vertex", NULL };
static const lg_param_desc lit_params[] = {
    { .key = "ks_scale", .type = LG_PARAM_INT, .def.i = 1, .min = 1, .max = 1000 },
    { .key = "ambient", .type = LG_PARAM_VEC3, .def.v = { 0.3, 0.3, 0.3 }, .min = 0, .max = 1e6 },
    { .key = "shading", .type = LG_PARAM_ENUM, .def.s = "phong", .enum_values = shading_values },
    { .key = "shininess", .type = LG_PARAM_FLOAT, .def.f = 32, .min = 1, .max = 129 },
    { .key = "exposure", .type = LG_PARAM_FLOAT, .def.f = 0 },
    { .key = "white", .type = LG_PARAM_FLOAT, .def.f = 1, .min = 0, .max = 1e6 },
    { .key = "enabled", .type = LG_PARAM_BOOL, .def.b = true },
    { .key = "tint", .type = LG_PARAM_COLOR, .def.v = { 1, 1, 1 }, .min = 0, .max = 1 },
    { .key = "albedo",
      .type = LG_PARAM_COLOR,
      .def.e = 0,
      .enum_values = albedo_words,
      .min = 0,
      .max = 1 },
    { .key = "label", .type = LG_PARAM_STRING, .def.s = "lit" },
    { .key = "file", .type = LG_PARAM_PATH, .def.s = "" },
    { .key = "grid", .type = LG_PARAM_INT3, .def.i3 = { 8, 8, 8 }, .min = 1, .max = 512 },
    { .key = "offset", .type = LG_PARAM_VEC2, .min = -10, .max = 10 },
};
static const lg_port_desc lit_inputs[] = {
    { .name = "image", .kind = LG_KIND_IMAGE },
    { .name = "scene", .kind = LG_KIND_SCENE, .optional = true },
    { .name = "mask", .kind = LG_KIND_ANY, .optional = true },
};

static const lg_param_desc tone_params[] = {
    { .key = "key", .type = LG_PARAM_FLOAT, .def.f = 0.18, .min = 0.001, .max = 100 },
};
static const lg_port_desc in_image[] = { { .name = "image", .kind = LG_KIND_IMAGE } };

static const lg_param_desc froxel_params[] = {
    { .key = "slices", .type = LG_PARAM_INT, .def.i = 64, .min = 8, .max = 256 },
};
static const lg_param_desc screen_params[] = {
    { .key = "samples", .type = LG_PARAM_INT, .def.i = 8, .min = 1, .max = 64 },
};
static const lg_port_desc vol_inputs[] = {
    { .name = "image", .kind = LG_KIND_IMAGE },
    { .name = "scene", .kind = LG_KIND_SCENE },
};
static const lg_port_desc vol_outputs[] = {
    { .name = "out", .kind = LG_KIND_IMAGE },
    { .name = "inscatter", .kind = LG_KIND_IMAGE },
};

#define TYPE(n) .struct_size = sizeof(lg_node_type), .name = (n)
static const lg_node_type types[] = {
    { TYPE("src"), LG_PARAMS(src_params), LG_OUTPUTS(out_image) },
    { TYPE("scene"), LG_OUTPUTS(out_scene) },
    { TYPE("gbuf"), LG_INPUTS(in_scene), LG_OUTPUTS(gbuf_outputs) },
    { TYPE("lit"), LG_PARAMS(lit_params), LG_INPUTS(lit_inputs), LG_OUTPUTS(out_image) },
    { TYPE("tone"), LG_PARAMS(tone_params), LG_INPUTS(in_image), LG_OUTPUTS(out_image) },
    { TYPE("vol_froxel"), LG_PARAMS(froxel_params), LG_INPUTS(vol_inputs),
      LG_OUTPUTS(vol_outputs) },
    { TYPE("vol_screen"), LG_PARAMS(screen_params), LG_INPUTS(vol_inputs),
      LG_OUTPUTS(vol_outputs) },
};
#define N_TYPES (sizeof types / sizeof types[0])
static const char *const type_names[N_TYPES] = { "src",  "scene",      "gbuf",      "lit",
                                                 "tone", "vol_froxel", "vol_screen" };

static const lg_node_type *lookup(void *ctx, const char *name)
{
    (void)ctx;
    for (size_t i = 0; i < N_TYPES; i++)
        if (strcmp(types[i].name, name) == 0)
            return &types[i];
    return NULL;
}

static const lg_schema schema = { .lookup = lookup, .n_names = N_TYPES, .names = type_names };

/* ---- a viewer session without a window ------------------------------------------------------- */

/* The graph text, the overrides made so far, and the graph as the viewer has it now. */
typedef struct world {
    const char *text;
    lg_overrides ov;
    lg_graph *g;
    lg_checked *c;
    lg_vparams *vp;
} world;

static void drop(world *w)
{
    lg_checked_free(w->c); /* before the graph it points into */
    lg_graph_free(w->g);
    w->c = NULL;
    w->g = NULL;
}

/* Parses w->text, applies every override with lg_graph_set, checks and syncs the
 * selection, as the viewer does after each change. False (diagnostics on stderr) when
 * the graph does not check. */
static bool rebuild(world *w)
{
    drop(w);
    lg_diags d = { 0 };
    w->g = lg_graph_parse_string("test.lgraph", w->text, strlen(w->text), NULL, &d);
    for (uint32_t i = 0; w->g && i < w->ov.n; i++)
        lg_graph_set(w->g, w->ov.items[i], &d);
    if (w->g && d.errors == 0)
        w->c = lg_graph_check(w->g, &schema, &d);
    bool ok = w->c && d.errors == 0;
    if (!ok)
        lg_diags_print(&d, stderr);
    lg_diags_free(&d);
    if (ok)
        lg_vparams_sync(w->vp, w->g, w->c, NULL);
    return ok;
}

static bool open_world(world *w, const char *text)
{
    memset(w, 0, sizeof *w);
    w->text = text;
    w->vp = lg_vparams_new();
    return rebuild(w);
}

static void close_world(world *w)
{
    drop(w);
    lg_vparams_free(w->vp);
    lg_overrides_free(&w->ov);
}

static const lg_cnode *node(const world *w, const char *name)
{
    int32_t i = lg_graph_find_node(w->g, name);
    return i >= 0 ? &w->c->nodes[i] : NULL;
}

static const lg_value *param(const world *w, const char *nname, const char *key)
{
    const lg_cnode *cn = node(w, nname);
    for (uint32_t j = 0; cn && j < cn->type->n_params; j++)
        if (strcmp(cn->type->params[j].key, key) == 0)
            return &cn->params[j];
    return NULL;
}

static const lg_edge *input(const world *w, const char *nname, const char *port)
{
    const lg_cnode *cn = node(w, nname);
    for (uint32_t j = 0; cn && j < cn->type->n_inputs; j++)
        if (strcmp(cn->type->inputs[j].name, port) == 0)
            return &cn->inputs[j];
    return NULL;
}

/* The name of the selected entry: "lit.ambient[1]", "lit.image". */
static void selected_name(const world *w, char *out, size_t n)
{
    int32_t ni;
    lg_vp_entry e;
    if (!lg_vparams_selected(w->vp, &ni, &e)) {
        snprintf(out, n, "(none)");
        return;
    }
    const lg_cnode *cn = &w->c->nodes[ni];
    const char *key = e.kind == LG_VP_PARAM ? cn->type->params[e.index].key
                                            : cn->type->inputs[e.index].name;
    if (e.component >= 0)
        snprintf(out, n, "%s.%s[%d]", cn->g->name, key, e.component);
    else
        snprintf(out, n, "%s.%s", cn->g->name, key);
}

/* Selects "node.key" or "node.key[i]" with the viewer's own moves (next node, next entry);
 * false when no sequence of moves reaches it. */
static bool select_entry(world *w, const char *want)
{
    char got[256];
    for (int i = 0; i < 64; i++) {
        const char *nn = lg_vparams_node(w->vp);
        size_t l = nn ? strlen(nn) : 0;
        if (nn && strncmp(want, nn, l) == 0 && want[l] == '.')
            break;
        lg_vparams_next_node(w->vp, +1);
    }
    for (int i = 0; i < 64; i++) {
        selected_name(w, got, sizeof got);
        if (strcmp(got, want) == 0)
            return true;
        lg_vparams_next_entry(w->vp, +1);
    }
    fprintf(stderr, "cannot select %s\n", want);
    return false;
}

/* Steps the selection, expects exactly `want` ("node.key=value", or NULL for a refusal
 * whose reason holds `why`), and applies it as the viewer does: overrides, lg_graph_set,
 * check, sync. The selection must survive the rebuild. */
static void step_expect(const char *file, int line, world *w, int dir, double scale,
                        const char *want, const char *why)
{
    char err[512] = "";
    char before[256], after[256];
    selected_name(w, before, sizeof before);
    char *a = lg_vparams_step(w->vp, w->g, w->c, dir, scale, err, sizeof err);
    if (!want) {
        if (a || !strstr(err, why)) {
            fprintf(stderr, "%s:%d: step %s: got '%s' (reason '%s'), want a refusal with '%s'\n",
                    file, line, before, a ? a : "(null)", err, why);
            check_failures++;
        }
        free(a);
        return;
    }
    if (!a || strcmp(a, want) != 0) {
        fprintf(stderr, "%s:%d: step %s: got '%s' (%s), want '%s'\n", file, line, before,
                a ? a : "(null)", err, want);
        check_failures++;
        free(a);
        return;
    }
    lg_overrides_set(&w->ov, a);
    free(a);
    if (!rebuild(w)) {
        fprintf(stderr, "%s:%d: '%s' does not check\n", file, line, want);
        check_failures++;
        lg_overrides_remove_last(&w->ov);
        CHECK(rebuild(w));
        return;
    }
    selected_name(w, after, sizeof after);
    CHECKF(strcmp(before, after) == 0, "%s:%d: selection %s became %s", file, line, before, after);
}
#define STEP(w, dir, scale, want) step_expect(__FILE__, __LINE__, w, dir, scale, want, NULL)
#define REFUSE(w, dir, scale, why) step_expect(__FILE__, __LINE__, w, dir, scale, NULL, why)

static bool near(double a, double b)
{
    return fabs(a - b) <= 1e-9 * (1 + fabs(b));
}

/* ---- stepping -------------------------------------------------------------------------------- */

static const char *const lit_graph =
    "lightgraph 1\n"
    "a = src {}\n"
    "l = lit { image = a, ks_scale = 998, shininess = 126, exposure = 2, white = 0 }\n";

static void test_int(void)
{
    world w;
    CHECK(open_world(&w, lit_graph));
    CHECK(select_entry(&w, "l.ks_scale"));
    STEP(&w, +1, 1, "l.ks_scale=999");
    CHECK(param(&w, "l", "ks_scale")->i == 999);
    STEP(&w, +1, 10, "l.ks_scale=1000"); /* coarse, clamped to the maximum */
    CHECK(param(&w, "l", "ks_scale")->i == 1000);
    REFUSE(&w, +1, 1, "l.ks_scale is at its maximum 1000");
    STEP(&w, -1, 10, "l.ks_scale=990");
    STEP(&w, -1, 0.1, "l.ks_scale=989"); /* fine is still a whole step */
    CHECK(param(&w, "l", "ks_scale")->i == 989);
    for (int i = 0; i < 10; i++)
        lg_overrides_remove_last(&w.ov);
    CHECK(w.ov.n == 0);
    w.text = "lightgraph 1\na = src {}\nl = lit { image = a, ks_scale = 3 }\n";
    CHECK(rebuild(&w));
    STEP(&w, -1, 10, "l.ks_scale=1");
    REFUSE(&w, -1, 1, "l.ks_scale is at its minimum 1");
    /* int3: one component stepped as an int, the whole vector written */
    CHECK(select_entry(&w, "l.grid[1]"));
    STEP(&w, +1, 1, "l.grid=[8, 9, 8]");
    CHECK(param(&w, "l", "grid")->i3[1] == 9 && param(&w, "l", "grid")->i3[0] == 8);
    close_world(&w);
}

static void test_float(void)
{
    world w;
    CHECK(open_world(&w, lit_graph));
    /* a range under 1e4 wide: (129 - 1) / 100 = 1.28 a step, clamped */
    CHECK(select_entry(&w, "l.shininess"));
    STEP(&w, +1, 1, "l.shininess=127.28");
    CHECK(near(param(&w, "l", "shininess")->f, 127.28));
    STEP(&w, +1, 1, "l.shininess=128.56");
    STEP(&w, +1, 1, "l.shininess=129");
    CHECK(param(&w, "l", "shininess")->f == 129);
    REFUSE(&w, +1, 1, "l.shininess is at its maximum 129");
    STEP(&w, -1, 0.1, "l.shininess=128.872");
    CHECK(near(param(&w, "l", "shininess")->f, 128.872));
    /* no range: 10% of the value, 0.1 at 0 */
    CHECK(select_entry(&w, "l.exposure"));
    STEP(&w, +1, 1, "l.exposure=2.2");
    CHECK(near(param(&w, "l", "exposure")->f, 2.2));
    STEP(&w, -1, 10, "l.exposure=0");
    CHECK(param(&w, "l", "exposure")->f == 0);
    STEP(&w, -1, 1, "l.exposure=-0.1");
    CHECK(near(param(&w, "l", "exposure")->f, -0.1));
    /* a range 1e4 wide or more counts as none for the step, but still bounds */
    CHECK(select_entry(&w, "l.white"));
    REFUSE(&w, -1, 1, "l.white is at its minimum 0");
    STEP(&w, +1, 1, "l.white=0.1");
    STEP(&w, +1, 1, "l.white=0.11");
    CHECK(near(param(&w, "l", "white")->f, 0.11));
    /* a bad scale is refused, not used */
    char err[256];
    CHECK(!lg_vparams_step(w.vp, w.g, w.c, +1, NAN, err, sizeof err));
    CHECK(strstr(err, "not a positive number"));
    close_world(&w);
}

static void test_enum_bool(void)
{
    world w;
    CHECK(open_world(&w, lit_graph));
    CHECK(select_entry(&w, "l.shading"));
    STEP(&w, +1, 1, "l.shading=mixed");
    STEP(&w, +1, 1, "l.shading=phong_half");
    STEP(&w, +1, 1, "l.shading=flat"); /* cyclic */
    CHECK(param(&w, "l", "shading")->e == 0);
    STEP(&w, -1, 1, "l.shading=phong_half");
    STEP(&w, -1, 10, "l.shading=mixed"); /* one value at a time whatever the scale */
    CHECK(param(&w, "l", "shading")->e == 3);
    CHECK(strcmp(param(&w, "l", "shading")->s, "mixed") == 0);
    lg_str s = { 0 };
    lg_vparams_describe(w.vp, w.c, &s);
    CHECKF(strcmp(s.s, "l (lit) 5/22  shading = mixed  {flat gouraud phong mixed phong_half}") == 0,
           "%s", s.s);
    lg_str_free(&s);

    CHECK(select_entry(&w, "l.enabled"));
    STEP(&w, +1, 1, "l.enabled=false");
    CHECK(!param(&w, "l", "enabled")->b);
    STEP(&w, -1, 1, "l.enabled=true");
    CHECK(param(&w, "l", "enabled")->b);
    close_world(&w);
}

static void test_vectors(void)
{
    world w;
    CHECK(open_world(&w, lit_graph));
    CHECK(select_entry(&w, "l.ambient[1]"));
    lg_str s = { 0 };
    lg_vparams_describe(w.vp, w.c, &s);
    CHECKF(strcmp(s.s, "l (lit) 3/22  ambient[1] = 0.3 of [0.3, 0.3, 0.3] (default)  "
                       "[0, 1e6]") == 0,
           "%s", s.s);
    lg_str_free(&s);
    STEP(&w, +1, 1, "l.ambient=[0.3, 0.33, 0.3]");
    const lg_value *v = param(&w, "l", "ambient");
    CHECK(near(v->v[0], 0.3) && near(v->v[1], 0.33) && near(v->v[2], 0.3));
    CHECK(select_entry(&w, "l.offset[0]"));
    STEP(&w, +1, 1, "l.offset=[0.2, 0]");
    CHECK(near(param(&w, "l", "offset")->v[0], 0.2));

    /* a colour component; a colour range [0, 1]: 0.01 a step */
    CHECK(select_entry(&w, "l.tint[2]"));
    REFUSE(&w, +1, 1, "l.tint[2] is at its maximum 1");
    STEP(&w, -1, 1, "l.tint=[1, 1, 0.99]");
    CHECK(near(param(&w, "l", "tint")->v[2], 0.99));
    STEP(&w, -1, 10, "l.tint=[1, 1, 0.89]");
    CHECK(near(param(&w, "l", "tint")->v[2], 0.89));

    /* a colour with keywords: its own entry cycles the keywords and a colour */
    CHECK(select_entry(&w, "l.albedo[0]"));
    REFUSE(&w, +1, 1, "is the keyword 'material', not a colour");
    CHECK(select_entry(&w, "l.albedo"));
    STEP(&w, +1, 1, "l.albedo=vertex");
    CHECK(param(&w, "l", "albedo")->e == 1);
    STEP(&w, +1, 1, "l.albedo=[0.5, 0.5, 0.5]");
    CHECK(param(&w, "l", "albedo")->e == -1 && near(param(&w, "l", "albedo")->v[1], 0.5));
    CHECK(select_entry(&w, "l.albedo[0]"));
    STEP(&w, +1, 1, "l.albedo=[0.51, 0.5, 0.5]");
    CHECK(near(param(&w, "l", "albedo")->v[0], 0.51));
    CHECK(select_entry(&w, "l.albedo"));
    STEP(&w, +1, 1, "l.albedo=material");
    CHECK(param(&w, "l", "albedo")->e == 0);
    STEP(&w, -1, 1, "l.albedo=[0.5, 0.5, 0.5]");
    close_world(&w);
}

/* ---- inputs ---------------------------------------------------------------------------------- */

static void test_inputs(void)
{
    world w;
    CHECK(open_world(&w, "lightgraph 1\n"
                         "a = src {}\n"
                         "sc = scene {}\n"
                         "g = gbuf { scene = sc }\n"
                         "l = lit { image = a, scene = sc, mask = a }\n"
                         "t = tone { image = l }\n"
                         "u = tone { image = t }\n"
                         "b = src {}\n"));
    /* image: a, g.color, g.depth, b; never sc (a scene), l itself, t and u (they read
     * l: a cycle) */
    CHECK(select_entry(&w, "l.image"));
    STEP(&w, +1, 1, "l.image=g.color");
    const lg_edge *e = input(&w, "l", "image");
    CHECK(e->node == lg_graph_find_node(w.g, "g") && e->port == 0);
    STEP(&w, +1, 1, "l.image=g.depth");
    CHECK(input(&w, "l", "image")->port == 1);
    STEP(&w, +1, 1, "l.image=b");
    CHECK(input(&w, "l", "image")->node == lg_graph_find_node(w.g, "b"));
    STEP(&w, +1, 1, "l.image=a"); /* past u, t, l: back to the first */
    STEP(&w, -1, 1, "l.image=b");
    /* mask takes any kind: the scene too, but still nothing downstream */
    CHECK(select_entry(&w, "l.mask"));
    STEP(&w, +1, 1, "l.mask=sc");
    CHECK(input(&w, "l", "mask")->node == lg_graph_find_node(w.g, "sc"));
    STEP(&w, +1, 1, "l.mask=g.color");
    STEP(&w, -1, 1, "l.mask=sc");
    STEP(&w, -1, 1, "l.mask=a");
    STEP(&w, -1, 1, "l.mask=b");
    /* the scene input: sc is the only scene */
    CHECK(select_entry(&w, "l.scene"));
    REFUSE(&w, +1, 1, "l.scene has no other source");
    /* u reads t which reads l: for t.image everything but t and u */
    CHECK(select_entry(&w, "t.image"));
    STEP(&w, -1, 1, "t.image=g.depth");
    lg_str s = { 0 };
    lg_vparams_describe(w.vp, w.c, &s);
    CHECKF(strcmp(s.s, "t (tone) 2/2  image <- g.depth  (image)") == 0, "%s", s.s);
    lg_str_free(&s);
    close_world(&w);
}

/* ---- method switching ------------------------------------------------------------------------ */

static const char *const methods_graph =
    "lightgraph 1\n"
    "sc = scene {}\n"
    "a = src {}\n"
    "lit = lit { image = a, scene = sc }\n"
    "vol_froxel = vol_froxel { image = lit, scene = sc }\n"
    "vol_screen = vol_screen { image = lit, scene = sc }\n"
    "vol_fine = vol_froxel { image = lit, scene = sc, slices = 128 }\n"
    "vol_other = vol_screen { image = a, scene = sc }\n" /* other sources */
    "tone = tone { image = vol_froxel }\n"
    "bloom = tone { image = vol_froxel.inscatter }\n";

static int32_t switch_apply(world *w, const char *shown, int dir, const char *want0,
                            const char *want1)
{
    char **as = NULL;
    uint32_t n = 0;
    int32_t from, to, new_shown;
    char err[512] = "";
    int32_t si = lg_graph_find_node(w->g, shown);
    int r = lg_vparams_switch_method(w->g, w->c, si, dir, &as, &n, &from, &to, &new_shown, err,
                                     sizeof err);
    CHECKF(r == 1, "%s", err);
    if (r != 1)
        return -2;
    CHECKF(n == 2 && strcmp(as[0], want0) == 0 && strcmp(as[1], want1) == 0, "got %u: %s, %s", n,
           n > 0 ? as[0] : "", n > 1 ? as[1] : "");
    CHECK(new_shown == -1);
    for (uint32_t i = 0; i < n; i++) {
        lg_overrides_set(&w->ov, as[i]);
        free(as[i]);
    }
    free(as);
    CHECK(rebuild(w));
    CHECK(input(w, "tone", "image")->node == to && input(w, "bloom", "image")->node == to);
    CHECK(input(w, "bloom", "image")->port == 1 && input(w, "tone", "image")->port == 0);
    return from;
}

static void test_switch(void)
{
    world w;
    CHECK(open_world(&w, methods_graph));
    int32_t froxel = lg_graph_find_node(w.g, "vol_froxel");
    /* three alternatives (two types, one type with other parameters): round and back */
    CHECK(switch_apply(&w, "tone", +1, "tone.image=vol_screen.out",
                       "bloom.image=vol_screen.inscatter") == froxel);
    switch_apply(&w, "tone", +1, "tone.image=vol_fine.out", "bloom.image=vol_fine.inscatter");
    switch_apply(&w, "tone", +1, "tone.image=vol_froxel.out", "bloom.image=vol_froxel.inscatter");
    switch_apply(&w, "tone", -1, "tone.image=vol_fine.out", "bloom.image=vol_fine.inscatter");
    switch_apply(&w, "tone", -1, "tone.image=vol_screen.out", "bloom.image=vol_screen.inscatter");
    CHECK(w.ov.n == 2); /* replaced in place */

    /* the shown node itself switching: no consumer, the viewer shows the other */
    char **as;
    uint32_t n;
    int32_t from, to, new_shown;
    char err[512];
    int32_t vs = lg_graph_find_node(w.g, "vol_screen");
    CHECK(lg_vparams_switch_method(w.g, w.c, vs, +1, &as, &n, &from, &to, &new_shown, err,
                                   sizeof err) == 1);
    CHECK(from == vs && to == lg_graph_find_node(w.g, "vol_fine") && new_shown == to);
    CHECK(n == 2); /* tone and bloom read it */
    for (uint32_t i = 0; i < n; i++)
        free(as[i]);
    free(as);
    close_world(&w);

    /* no alternative anywhere upstream */
    CHECK(open_world(&w, "lightgraph 1\na = src {}\nl = lit { image = a }\n"
                         "t = tone { image = l }\nk = tone { image = l }\n"));
    int32_t t = lg_graph_find_node(w.g, "t");
    as = (char **)&w; /* must come back NULL */
    CHECK(lg_vparams_switch_method(w.g, w.c, t, +1, &as, &n, &from, &to, &new_shown, err,
                                   sizeof err) == 0);
    CHECK(as == NULL && n == 0);
    CHECKF(strstr(err, "no node upstream of 't' has an alternative: ") == err, "%s", err);
    close_world(&w);

    /* the shown node switching with nothing reading it */
    CHECK(open_world(&w, "lightgraph 1\na = src {}\nt = tone { image = a }\n"
                         "k = tone { image = a, key = 1 }\n"));
    t = lg_graph_find_node(w.g, "t");
    CHECK(lg_vparams_switch_method(w.g, w.c, t, -1, &as, &n, &from, &to, &new_shown, err,
                                   sizeof err) == 1);
    CHECK(n == 0 && from == t && to == lg_graph_find_node(w.g, "k") && new_shown == to);
    free(as);
    close_world(&w);
}

/* ---- overrides ------------------------------------------------------------------------------- */

static char *shell_echo(const char *args)
{
    char *cmd = lg_xasprintf("printf '%%s\\n' %s", args);
    /* sh -c CMD: the shell parses the arguments exactly as a user's would */
    char *full = NULL;
    lg_str q = { 0 };
    lg_str_add(&q, "sh -c '");
    for (const char *p = cmd; *p; p++) {
        if (*p == '\'')
            lg_str_add(&q, "'\\''");
        else
            lg_str_addc(&q, *p);
    }
    lg_str_add(&q, "'");
    full = lg_str_take(&q);
    free(cmd);
    FILE *f = popen(full, "r");
    free(full);
    lg_str out = { 0 };
    char buf[256];
    size_t k;
    while (f && (k = fread(buf, 1, sizeof buf, f)) > 0)
        lg_str_addn(&out, buf, k);
    CHECK(f && pclose(f) == 0);
    return lg_str_take(&out);
}

static void test_overrides(void)
{
    lg_overrides o = { 0 };
    char *s = lg_overrides_args(&o);
    CHECK(strcmp(s, "") == 0);
    free(s);
    lg_overrides_set(&o, "lit.shading=flat");
    lg_overrides_set(&o, "sun.direction=[0.4, -0.25, 1]");
    lg_overrides_set(&o, "lit.label=it's");
    lg_overrides_set(&o, " lit.shading = phong"); /* the same key: in place */
    CHECK(o.n == 3);
    CHECK(strcmp(o.items[0], " lit.shading = phong") == 0);
    s = lg_overrides_args(&o);
    CHECKF(strcmp(s, "--set ' lit.shading = phong' --set 'sun.direction=[0.4, -0.25, 1]' "
                     "--set 'lit.label=it'\\''s'") == 0,
           "%s", s);
    char *echo = shell_echo(s);
    CHECKF(strcmp(echo, "--set\n lit.shading = phong\n--set\nsun.direction=[0.4, -0.25, 1]\n"
                        "--set\nlit.label=it's\n") == 0,
           "%s", echo);
    free(echo);
    free(s);

    lg_overrides_remove_last(&o); /* the replaced value comes back */
    CHECK(o.n == 3 && strcmp(o.items[0], "lit.shading=flat") == 0);
    lg_overrides_remove_last(&o); /* the added one goes */
    CHECK(o.n == 2 && strcmp(o.items[1], "sun.direction=[0.4, -0.25, 1]") == 0);
    lg_overrides_set(&o, "a.b=1");
    lg_overrides_set(&o, "lit.shading=mixed");
    s = lg_overrides_args(&o);
    CHECKF(strcmp(s, "--set lit.shading=mixed --set 'sun.direction=[0.4, -0.25, 1]' "
                     "--set a.b=1") == 0,
           "%s", s);
    free(s);
    for (int i = 0; i < 10; i++)
        lg_overrides_remove_last(&o); /* more than there is: stops at none */
    CHECK(o.n == 0);

    /* the history is bounded; the newest sets still undo */
    for (int i = 0; i < LG_OVERRIDES_UNDO + 10; i++) {
        char a[64];
        snprintf(a, sizeof a, "n.k=%d", i);
        lg_overrides_set(&o, a);
    }
    lg_overrides_remove_last(&o);
    CHECK(o.n == 1 && strcmp(o.items[0], "n.k=264") == 0);
    lg_overrides_free(&o);
    CHECK(o.n == 0 && o.items == NULL);
}

/* ---- sync across edits ----------------------------------------------------------------------- */

static void test_sync(void)
{
    world w;
    CHECK(open_world(&w, "lightgraph 1\n"
                         "a = src {}\n"
                         "l = lit { image = a }\n"
                         "t = tone { image = l }\n"));
    CHECK(select_entry(&w, "l.ambient[2]"));
    /* a node added before it and a parameter given: the same node and entry */
    w.text = "lightgraph 1\n"
             "a = src {}\n"
             "b = src { seed = 4 }\n"
             "l = lit { image = b, ambient = [1, 2, 3] }\n"
             "t = tone { image = l }\n";
    CHECK(rebuild(&w));
    char name[256];
    selected_name(&w, name, sizeof name);
    CHECKF(strcmp(name, "l.ambient[2]") == 0, "%s", name);
    STEP(&w, +1, 1, "l.ambient=[1, 2, 3.3]");

    /* the node gone: the nearest in the file */
    w.text = "lightgraph 1\n"
             "a = src {}\n"
             "b = src { seed = 4 }\n"
             "t = tone { image = b }\n";
    lg_overrides_free(&w.ov);
    CHECK(rebuild(&w));
    CHECKF(lg_vparams_node(w.vp) && strcmp(lg_vparams_node(w.vp), "t") == 0, "%s",
           lg_vparams_node(w.vp));
    /* only offered nodes are listed; the node moves keep the entry's key */
    bool offer[3] = { true, false, true };
    lg_vparams_sync(w.vp, w.g, w.c, offer);
    CHECK(strcmp(lg_vparams_node(w.vp), "t") == 0);
    lg_vparams_next_node(w.vp, +1);
    CHECK(strcmp(lg_vparams_node(w.vp), "a") == 0);
    lg_vparams_next_node(w.vp, -1);
    lg_vparams_next_node(w.vp, -1);
    CHECK(strcmp(lg_vparams_node(w.vp), "a") == 0);
    lg_vparams_next_entry(w.vp, -1);
    selected_name(&w, name, sizeof name);
    CHECKF(strcmp(name, "a.seed") == 0, "%s", name);

    /* a stale check is refused, not read */
    char err[256];
    lg_checked *old = w.c;
    w.c = NULL;
    w.text = "lightgraph 1\nz = tone { image = y }\ny = src {}\n";
    lg_diags d = { 0 };
    lg_graph *g2 = lg_graph_parse_string("x.lgraph", w.text, strlen(w.text), NULL, &d);
    lg_checked *c2 = lg_graph_check(g2, &schema, &d);
    CHECK(c2 && d.errors == 0);
    CHECK(!lg_vparams_step(w.vp, g2, c2, +1, 1, err, sizeof err));
    CHECKF(strstr(err, "the graph changed"), "%s", err);
    lg_checked_free(c2);
    lg_graph_free(g2);
    lg_diags_free(&d);
    w.c = old;

    /* nothing to select */
    lg_vparams *empty = lg_vparams_new();
    CHECK(lg_vparams_node(empty) == NULL);
    CHECK(!lg_vparams_step(empty, w.g, w.c, +1, 1, err, sizeof err));
    CHECK(strstr(err, "nothing selected"));
    lg_str s = { 0 };
    lg_vparams_describe(empty, w.c, &s);
    CHECK(strcmp(s.s, "nothing to edit") == 0);
    lg_str_free(&s);
    lg_vparams_free(empty);
    lg_vparams_free(NULL);
    close_world(&w);
}

int main(void)
{
    test_int();
    test_float();
    test_enum_bool();
    test_vectors();
    test_inputs();
    test_switch();
    test_overrides();
    test_sync();
    return check_report("viewer_params");
}
