/* host/viewer/reload.c: hot reload. The watcher (watch.c) reports changed graph files
 * (the graph and its includes), plugin .so files in the plugin folders, and, in a
 * development build or with LIGHTGRAPH_SHADER_DIR, shader sources, which start a rebuild
 * (rebuild.c: `ninja` or LIGHTGRAPH_REBUILD) whose relinked plugins are then reloaded
 * together. Reloads are applied between frames, never while one is in flight, as changes
 * (load.c): a failure keeps the last good graph and puts the replaced plugins back.
 */
#include "viewer/state.h"

#include <stdlib.h>
#include <string.h>
#include <unistd.h>

void lg_viewer_start_watching(viewer *v)
{
    char err[1024];
    if (lg_watch_open(&v->watch, err, sizeof err)) {
        lg_hlog(LG_HWARN, "no hot reload: %s", err);
        return;
    }
    lg_viewer_watch_graph_files(v);
    static const char *const so[] = { ".so" };
    for (uint32_t i = 0; i < v->reg.n_dirs; i++)
        if (lg_watch_tree(v->watch, LG_WATCH_PLUGIN, v->reg.dirs[i], so, 1, false, err, sizeof err))
            lg_hlog(LG_HDEBUG, "not watching plugin directory %s: %s", v->reg.dirs[i], err);
    /* shaders: the development build's source tree, or LIGHTGRAPH_SHADER_DIR (an out-of-tree
     * plugin's shaders, rebuilt by LIGHTGRAPH_REBUILD) */
    v->dev_build = lg_rebuild_dev_build_dir();
    const char *env = getenv("LIGHTGRAPH_SHADER_DIR");
    if (env && *env)
        v->dev_shaders = lg_path_absolute(env);
    else
        v->dev_shaders = v->dev_build ? lg_rebuild_dev_shader_dir() : NULL;
    const char *cmd = getenv("LIGHTGRAPH_REBUILD");
    v->can_rebuild = v->dev_build || (cmd && *cmd);
    if (v->dev_shaders && v->can_rebuild) {
        static const char *const sh[] = { ".glsl", ".comp", ".vert", ".frag", ".geom", ".cl" };
        if (lg_watch_tree(v->watch, LG_WATCH_SHADER, v->dev_shaders, sh, 6, true, err, sizeof err))
            lg_hlog(LG_HWARN, "not watching the shaders: %s", err);
        else
            lg_hlog(LG_HINFO, "watching the shaders in %s (a change runs %s)", v->dev_shaders,
                    cmd && *cmd ? cmd : "ninja");
    }
}

static bool is_plugin_file(const char *path)
{
    const char *b = strrchr(path, '/');
    b = b ? b + 1 : path;
    size_t n = strlen(b);
    return strncmp(b, "lg_", 3) == 0 && n > 3 && strcmp(b + n - 3, ".so") == 0;
}

/* Reloads the changed plugins (all or none) and replans; a failure at any step puts
 * every replaced entry back. */
static void reload_plugins(viewer *v)
{
    uint32_t n = v->n_pending_plugins;
    char **paths = v->pending_plugins;
    v->pending_plugins = NULL;
    v->n_pending_plugins = 0;
    lg_plugin **fresh = lg_xcalloc(n + 1, sizeof *fresh), **old = lg_xcalloc(n + 1, sizeof *old);
    uint32_t done = 0;
    lg_str names = { 0 };
    char err[2048] = "";
    bool ok = true;
    for (uint32_t i = 0; i < n && ok; i++) {
        if (lg_registry_rescan(&v->reg, paths[i], &fresh[done], &old[done], err, sizeof err)) {
            ok = false;
            break;
        }
        lg_registry_replace(&v->reg, old[done], fresh[done]);
        lg_str_addf(&names, "%s%s", names.len ? ", " : "", fresh[done]->name);
        done++;
    }
    if (!ok) {
        lg_viewer_change_failed(v);
    } else {
        /* nodes of a reloaded plugin are made again with the parameters they had (the
         * graph's and the overrides); the others are adopted as they are */
        char *what = lg_xasprintf("plugin%s %s reloaded", done == 1 ? "" : "s",
                                  names.s ? names.s : "");
        ok = lg_viewer_attempt(v, what, false);
        free(what);
        if (!ok)
            snprintf(err, sizeof err, "%s", v->status ? v->status : "the reload failed");
    }
    if (!ok) {
        for (uint32_t i = done; i-- > 0;)
            lg_registry_replace(&v->reg, fresh[i], old[i]);
        lg_viewer_status(v, true, "plugin reload failed, rolled back to the previous version:\n%s",
                         err);
    }
    lg_str_free(&names);
    free(fresh);
    free(old);
    for (uint32_t i = 0; i < n; i++)
        free(paths[i]);
    free(paths);
}

/* Takes the watcher's changes: a graph file marks the graph pending, a plugin file joins
 * the pending plugins (once). Returns whether a shader changed. */
static bool collect_changes(viewer *v)
{
    lg_watch_change *ch = NULL;
    char err[1024];
    int n = lg_watch_poll(v->watch, lg_mono_now(), 0.15, &ch, err, sizeof err);
    if (n < 0) {
        lg_hlog(LG_HWARN, "watching files: %s", err);
        n = 0;
    }
    bool shaders = false;
    for (int i = 0; i < n; i++) {
        if (ch[i].tag == LG_WATCH_GRAPH) {
            v->pending_graph = true;
        } else if (ch[i].tag == LG_WATCH_SHADER) {
            shaders = true;
        } else if (ch[i].tag == LG_WATCH_PLUGIN && is_plugin_file(ch[i].path) &&
                   access(ch[i].path, R_OK) == 0) {
            bool dup = false;
            for (uint32_t k = 0; k < v->n_pending_plugins; k++)
                dup |= strcmp(v->pending_plugins[k], ch[i].path) == 0;
            if (!dup) {
                v->pending_plugins = lg_xrealloc(v->pending_plugins,
                                                 (v->n_pending_plugins + 1) * sizeof(char *));
                v->pending_plugins[v->n_pending_plugins++] = lg_xstrdup(ch[i].path);
            }
        }
    }
    lg_watch_changes_free(ch, n);
    return shaders;
}

/* Shaders changed: a rebuild starts, or runs again once the running one ends. */
static void start_rebuild(viewer *v)
{
    char err[1024];
    if (v->rebuild) {
        v->rebuild_again = true;
    } else if (lg_rebuild_start(&v->rebuild, v->dev_build, err, sizeof err)) {
        lg_viewer_status(v, true, "shaders changed, but the rebuild cannot start: %s", err);
    } else {
        lg_viewer_status(v, false, "shaders changed: rebuilding (%s)",
                         getenv("LIGHTGRAPH_REBUILD") ? getenv("LIGHTGRAPH_REBUILD") : "ninja");
    }
}

/* Follows the running rebuild. Returns true while one runs (the reloads wait for it): a
 * failed one is a failed change, and one asked for again starts now. */
static bool rebuild_running(viewer *v)
{
    int status = 0;
    const char *log = NULL;
    int r = lg_rebuild_poll(v->rebuild, &status, &log);
    if (r == 0)
        return true; /* plugins relinked by the build are reloaded together once it ends */
    if (r < 0) {
        lg_viewer_refuse(v, "the rebuild's process could not be followed; the plugins are "
                            "as they were");
    } else if (status != 0) {
        lg_viewer_change_failed(v);
        size_t len = log ? strlen(log) : 0;
        const char *tail = len > 2000 ? log + len - 2000 : log ? log : "";
        lg_viewer_status(v, true,
                         "the rebuild failed (status %d); the plugins are as they "
                         "were:\n%s",
                         status, tail);
    }
    lg_rebuild_free(&v->rebuild);
    if (v->rebuild_again) {
        v->rebuild_again = false;
        char err[1024];
        if (lg_rebuild_start(&v->rebuild, v->dev_build, err, sizeof err) == 0)
            return true;
    }
    /* the relinked .so files settle a moment after the build: the next polls
     * collect them */
    return false;
}

void lg_viewer_poll_reloads(viewer *v)
{
    if (!v->watch)
        return;
    if (collect_changes(v) && v->can_rebuild)
        start_rebuild(v);
    if (v->rebuild && rebuild_running(v))
        return;
    if (v->n_pending_plugins)
        reload_plugins(v);
    else if (v->pending_graph) {
        v->pending_graph = false;
        lg_viewer_attempt(v, "graph reloaded", false);
    }
}
