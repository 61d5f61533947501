/*
 * Dual-paraboloid shadow records are refused by every consumer (since ABI 3.3:
 * lg_shadowmap_get refuses them, so each consumer does through it): a point light's two
 * paraboloid records written by tests/plugins/volumetric_polygonal's test producer
 * (test_poly_shadow, defect = paraboloid) given to phong, to volumetric_froxel on cpu and on
 * gl, and to the shadow-map tests' probe (a third-party consumer): each render exits 1 with
 * the reason, naming the consumer, and writes no file. (volumetric_polygonal's own refusal
 * is `volumetric_polygonal point_errors`.)
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "lightgraph/test.h"

static void setup_case(lg_test *t)
{
    lg_test_require_backend(t, "gl");
    lg_test_use_plugins(t, SR_PROBE_DIR ":" SR_POLY_DIR);
}

#define HEAD                                                                                       \
    "lightgraph 1\n"                                                                               \
    "s = test_shadow_scene { }\n"                                                                  \
    "lamp = light { scene = s, type = point, position = [0, 3, 0], intensity = 5 }\n"              \
    "fog = medium { scene = lamp, density = 1 }\n"                                                 \
    "sh = test_poly_shadow { scene = fog, defect = paraboloid }\n"

static void refused(lg_test *t, const char *consumer, const char *node_line, const char *node)
{
    char g[2048], *msg = NULL;
    snprintf(g, sizeof g, HEAD "%s\noutput %s \"o.exr\" float\n", node_line, node);
    remove(lg_test_path(t, "o.exr"));
    lg_test_write_text(t, "g.lgraph", g);
    static const char *const args[] = { "--size", "32x24", NULL };
    int rc = lg_test_render(t, "g.lgraph", args, &msg);
    char named[64];
    snprintf(named, sizeof named, "'%s'", node);
    LG_TEST_CHECK(t, rc == 1, "%s: status %d, want 1", consumer, rc);
    LG_TEST_CHECK(t, msg && strstr(msg, "dual-paraboloid") && strstr(msg, named),
                  "%s: the message does not name the node and the paraboloid: %s", consumer,
                  msg ? msg : "");
    FILE *f = fopen(lg_test_path(t, "o.exr"), "rb");
    LG_TEST_CHECK(t, f == NULL, "%s: o.exr written despite the refusal", consumer);
    if (f)
        fclose(f);
    free(msg);
}

static void case_refused(lg_test *t)
{
    refused(t, "phong", "lit = phong { scene = fog, shadows = sh }", "lit");
    refused(t, "froxel cpu",
            "lit = phong { scene = fog }\n"
            "vol = volumetric_froxel { scene = fog, base = lit, shadows = sh, backend = cpu }",
            "vol");
    refused(t, "froxel gl",
            "lit = phong { scene = fog }\n"
            "vol = volumetric_froxel { scene = fog, base = lit, shadows = sh, backend = gl }",
            "vol");
    refused(t, "the probe", "probe = test_shadow_probe { scene = fog, shadows = sh }", "probe");
    /* the control: the same producer's cube (defect = none) is read */
    char g[2048];
    snprintf(g, sizeof g,
             "lightgraph 1\n"
             "s = test_shadow_scene { }\n"
             "lamp = light { scene = s, type = point, position = [0, 3, 0], intensity = 5 }\n"
             "sh = test_poly_shadow { scene = lamp }\n"
             "lit = phong { scene = lamp, shadows = sh }\n"
             "output lit \"o.exr\" float\n");
    lg_test_write_text(t, "g.lgraph", g);
    static const char *const args[] = { "--size", "32x24", NULL };
    int rc = lg_test_render(t, "g.lgraph", args, NULL);
    LG_TEST_CHECK(t, rc == 0, "the cube: status %d", rc);
}

int main(int argc, char **argv)
{
    static const lg_test_case cases[] = { { "refused", case_refused } };
    lg_test_main_opts o = { .setup = setup_case };
    return lg_test_main(argc, argv, cases, sizeof cases / sizeof cases[0], &o);
}
