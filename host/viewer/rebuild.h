/*
 * host/viewer/rebuild.h: `ninja -C DIR` in the background (private), for `lightgraph view` in a
 * development build: a shader edited under shaders/ is re-embedded and the plugins that use
 * it relinked by the build tool while the viewer keeps drawing; the rebuilt .so files are
 * then seen by the plugin watch (watch.h) and reloaded.
 *
 * The build runs as a child process in its own process group (so that stopping it stops
 * the compilers it started too), stdin from /dev/null, stdout and stderr into one pipe that
 * lg_rebuild_poll drains into memory. Started with posix_spawn: safe in a process with
 * threads and a GL context. The caller must not ignore SIGCHLD (SIG_IGN makes the kernel
 * reap the child, and its status is lost) nor reap children with waitpid(-1, ...).
 *
 * Not thread-safe: one thread uses a lg_rebuild. Nothing blocks but lg_rebuild_free of a
 * build still running (at most about 2 s, see there).
 */
#ifndef LG_HOST_REBUILD_H
#define LG_HOST_REBUILD_H

#include <stddef.h>

typedef struct lg_rebuild lg_rebuild;

/* The most output kept: the last LG_REBUILD_LOG_MAX bytes (errors come last). */
#define LG_REBUILD_LOG_MAX 65536

/* Starts `ninja -C build_dir` (ninja found on PATH). The environment variable
 * LIGHTGRAPH_REBUILD, when set and not empty, replaces that whole command line: split on
 * spaces (no quoting), its first word found on PATH unless it holds a '/', run as is in the
 * current directory (build_dir is not added). Returns 0 and *out (free with
 * lg_rebuild_free), or -1 with err ("ninja not found on PATH", "cannot run /x/tool: No
 * such file or directory", ...). */
int lg_rebuild_start(lg_rebuild **out, const char *build_dir, char *err, size_t errlen);

/* Reads the output that is there and looks whether the build has ended; never blocks.
 * Returns 0 while it runs; 1 once it has ended (and on every later call), with *status its
 * exit status (128 + the signal's number when a signal killed it) and *log its output
 * (NUL-terminated, the last LG_REBUILD_LOG_MAX bytes; owned by r, valid until
 * lg_rebuild_free). status and log may be NULL. */
int lg_rebuild_poll(lg_rebuild *r, int *status, const char **log);

/* Stops the build if it still runs (SIGTERM to its process group, SIGKILL after 2 s if it
 * has not ended), reaps it (no zombie is left) and frees r. *r may be NULL; clears *r. */
void lg_rebuild_free(lg_rebuild **r);

/* The build directory when this program runs from a development build tree: LG_BUILD_ROOT
 * (the meson build root, compiled in) exists, holds build.ninja, and /proc/self/exe lies
 * inside it. An installed program gets NULL. The path is resolved (realpath), malloc'd;
 * the caller frees. */
char *lg_rebuild_dev_build_dir(void);
/* The source tree's shaders/ directory (LG_SOURCE_ROOT "/shaders", compiled in) when
 * lg_rebuild_dev_build_dir() is not NULL and that directory exists, else NULL. Resolved,
 * malloc'd; the caller frees. */
char *lg_rebuild_dev_shader_dir(void);

#endif
