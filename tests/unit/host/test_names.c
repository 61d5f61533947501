/* host/exec/names.h and the registry's unique names, in process:
 *
 *   test_names rule                     lg_name_rule_ok, case by case (what conform calls)
 *   test_names shipped_list SRC BUILD   lg_shipped_plugins is exactly the folders of
 *                                       SRC (plugins/) with an LG_PLUGIN_DEFINE, in order,
 *                                       and each built BUILD/NAME/lg_NAME.so declares NAME
 *   test_names rescan A B               the viewer's reload (lg_registry_rescan) refuses a
 *                                       file B that declares a type of the plugin A, naming
 *                                       both files; A reloaded over itself is accepted
 */
#include <dirent.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "common/check.h"
#include "exec/exec.h"
#include "exec/names.h"

/* ---- rule ------------------------------------------------------------------------------------ */

static void expect_rule(const char *plugin, const char *type, bool ok, const char *words)
{
    char why[512];
    memset(why, 'x', sizeof why);
    bool got = lg_name_rule_ok(plugin, type, why, sizeof why);
    CHECKF(got == ok, "lg_name_rule_ok('%s', '%s') = %d, expected %d (%s)", plugin,
           type ? type : "(null)", got, ok, why);
    CHECKF(memchr(why, 0, sizeof why) != NULL, "why is not terminated");
    if (ok)
        CHECKF(why[0] == 0, "accepted with a reason: %s", why);
    else
        CHECKF(why[0] && strstr(why, words), "the reason '%s' does not say '%s'", why, words);
}

static void test_rule(void)
{
    /* what the rule accepts: VENDOR_NAME, types VENDOR_..., vendors of 2 and 16 */
    expect_rule("acme_blur", NULL, true, "");
    expect_rule("acme_blur", "acme_blur", true, "");
    expect_rule("acme_blur", "acme_sharpen_h", true, "");
    expect_rule("x264_enc", "x264_enc_frame", true, "");
    expect_rule("ab_c", "ab_c", true, "");
    expect_rule("abcdefghijklmnop_x", "abcdefghijklmnop_y", true, "");
    expect_rule("acme_fast_blur", "acme_x", true, "");
    /* the shipped plugins are exempt, with any of their types */
    expect_rule("core", "scale", true, "");
    expect_rule("volumetric_froxel", "volumetric_froxel", true, "");
    expect_rule("ibl", "reflect", true, "");
    /* plugin names */
    expect_rule("acme", NULL, false, "not VENDOR_NAME");
    expect_rule("acme_", NULL, false, "not VENDOR_NAME");
    expect_rule("a_blur", NULL, false, "has 1 characters, not 2 to 16");
    expect_rule("abcdefghijklmnopq_x", NULL, false, "has 17 characters, not 2 to 16");
    expect_rule("_blur", NULL, false, "has 0 characters");
    expect_rule("Acme_blur", NULL, false, "[a-z0-9] only");
    expect_rule("acme_Blur", NULL, false, "[a-z0-9_] only");
    expect_rule("lg_blur", "lg_blur", false, "'lg' is lightgraph's own");
    expect_rule("", NULL, false, "no name");
    expect_rule(NULL, NULL, false, "no name");
    /* a name like a shipped one is not shipped */
    expect_rule("core2", "scale", false, "not VENDOR_NAME");
    /* types */
    expect_rule("acme_blur", "blur", false, "does not start with its vendor prefix 'acme_'");
    expect_rule("acme_blur", "acmeblur", false, "vendor prefix 'acme_'");
    expect_rule("acme_blur", "acme_", false, "vendor prefix 'acme_'");
    expect_rule("acme_blur", "acm_blur", false, "vendor prefix 'acme_'");
    expect_rule("acme_blur", "scale", false, "node type 'scale' of plugin 'acme_blur'");
    /* no room for the reason: still an answer, nothing written */
    CHECK(!lg_name_rule_ok("acme", NULL, NULL, 0));
    char one[1] = { 'x' };
    CHECK(!lg_name_rule_ok("acme", NULL, one, sizeof one) && one[0] == 0);
}

/* ---- shipped_list ---------------------------------------------------------------------------- */

static int cmp_str(const void *a, const void *b)
{
    return strcmp(*(const char *const *)a, *(const char *const *)b);
}

/* Whether a .c file of folder `dir` declares the plugin `name` (LG_PLUGIN_DEFINE("name"). */
static bool folder_defines(const char *dir, const char *name)
{
    DIR *d = opendir(dir);
    if (!d)
        return false;
    char *want = lg_xasprintf("LG_PLUGIN_DEFINE(\"%s\"", name);
    bool found = false;
    struct dirent *e;
    while (!found && (e = readdir(d))) {
        size_t len = strlen(e->d_name);
        if (len < 3 || strcmp(e->d_name + len - 2, ".c") != 0)
            continue;
        char *path = lg_path_join(dir, e->d_name);
        size_t n = 0;
        char *text = lg_read_file(path, &n);
        found = text && strstr(text, want);
        free(text);
        free(path);
    }
    closedir(d);
    free(want);
    return found;
}

static void test_shipped_list(const char *src, const char *build)
{
    size_t n_list = 0;
    while (lg_shipped_plugins[n_list])
        n_list++;
    CHECKF(n_list >= 16, "only %zu shipped plugins listed", n_list);
    for (size_t i = 1; i < n_list; i++)
        CHECKF(strcmp(lg_shipped_plugins[i - 1], lg_shipped_plugins[i]) < 0,
               "the list is not in alphabetical order, or has '%s' twice", lg_shipped_plugins[i]);
    /* the folders of plugins/ that define their plugin, sorted */
    DIR *d = opendir(src);
    CHECKF(d != NULL, "cannot open %s", src);
    if (!d)
        return;
    char **folders = NULL;
    size_t n_folders = 0, n_all = 0;
    struct dirent *e;
    while ((e = readdir(d))) {
        if (e->d_name[0] == '.')
            continue;
        char *dir = lg_path_join(src, e->d_name);
        struct stat st;
        if (stat(dir, &st) == 0 && S_ISDIR(st.st_mode)) {
            n_all++;
            if (folder_defines(dir, e->d_name)) {
                folders = lg_xrealloc(folders, (n_folders + 1) * sizeof *folders);
                folders[n_folders++] = lg_xstrdup(e->d_name);
            }
        }
        free(dir);
    }
    closedir(d);
    if (n_folders > 1)
        qsort(folders, n_folders, sizeof *folders, cmp_str);
    CHECKF(n_all > n_folders,
           "every folder of %s defines a plugin: the libraries "
           "(embree_common, volumetric_common) were expected not to",
           src);
    for (size_t i = 0; i < n_folders || i < n_list; i++) {
        const char *f = i < n_folders ? folders[i] : "(none)";
        const char *l = i < n_list ? lg_shipped_plugins[i] : "(none)";
        CHECKF(strcmp(f, l) == 0,
               "entry %zu: plugins/%s defines a plugin, lg_shipped_plugins has '%s' "
               "(host/exec/names.c: one line per folder of plugins/ that builds a plugin)",
               i, f, l);
    }
    /* each built plugin declares its folder's name */
    char **paths = lg_xcalloc(n_list + 1, sizeof *paths);
    for (size_t i = 0; i < n_list; i++) {
        char *dir = lg_path_join(build, lg_shipped_plugins[i]);
        char *file = lg_xasprintf("lg_%s.so", lg_shipped_plugins[i]);
        paths[i] = lg_path_join(dir, file);
        free(dir);
        free(file);
    }
    lg_registry r = { 0 };
    lg_registry_scan_files(&r, paths, (uint32_t)n_list);
    CHECKF(r.n_refused == 0, "%u of the built plugins refused (first: %s: %s)", r.n_refused,
           r.n_refused ? r.refused[0].path : "", r.n_refused ? r.refused[0].reason : "");
    CHECKF(r.n_plugins == n_list, "%u of %zu built plugins scanned", r.n_plugins, n_list);
    for (uint32_t i = 0; i < r.n_plugins; i++) {
        const char *base = strrchr(r.plugins[i]->path, '/');
        char *want = lg_xasprintf("/lg_%s.so", r.plugins[i]->name);
        CHECKF(base && strcmp(base, want) == 0 && lg_shipped_plugin(r.plugins[i]->name),
               "%s declares the plugin '%s'", r.plugins[i]->path, r.plugins[i]->name);
        free(want);
    }
    lg_registry_free(&r);
    for (size_t i = 0; i < n_list; i++)
        free(paths[i]);
    free(paths);
    for (size_t i = 0; i < n_folders; i++)
        free(folders[i]);
    free(folders);
}

/* ---- rescan ---------------------------------------------------------------------------------- */

static void test_rescan(const char *a, const char *b)
{
    char *files[] = { (char *)a };
    lg_registry r = { 0 };
    lg_registry_scan_files(&r, files, 1);
    CHECKF(r.n_plugins == 1, "%s did not scan", a);
    if (r.n_plugins != 1) {
        lg_registry_free(&r);
        return;
    }
    char *pa = lg_xstrdup(r.plugins[0]->path);
    char *pb = lg_path_absolute(b);
    lg_plugin *fresh = NULL, *old = NULL;
    char err[4096] = "";
    int rc = lg_registry_rescan(&r, pb, &fresh, &old, err, sizeof err);
    CHECKF(rc == -1 && !fresh, "a plugin whose type is taken was reloaded: %d", rc);
    CHECKF(strstr(err, pa) && strstr(err, pb) && strstr(err, "'names_dup_a'"),
           "the refusal does not name both files and the type: %s", err);
    /* the plugin reloaded over itself takes nothing from anyone */
    err[0] = 0;
    rc = lg_registry_rescan(&r, pa, &fresh, &old, err, sizeof err);
    CHECKF(rc == 0 && fresh && old == r.plugins[0], "reloading %s over itself: %s", pa, err);
    if (rc == 0)
        lg_registry_replace(&r, old, fresh);
    lg_registry_free(&r);
    free(pa);
    free(pb);
}

int main(int argc, char **argv)
{
    const char *t = argc > 1 ? argv[1] : "";
    if (strcmp(t, "rule") == 0)
        test_rule();
    else if (strcmp(t, "shipped_list") == 0 && argc == 4)
        test_shipped_list(argv[2], argv[3]);
    else if (strcmp(t, "rescan") == 0 && argc == 4)
        test_rescan(argv[2], argv[3]);
    else {
        fprintf(stderr, "usage: test_names rule | shipped_list SRC BUILD | rescan A B\n");
        return 2;
    }
    return check_report(t);
}
