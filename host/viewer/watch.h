/*
 * host/watch.h: files watched for changes through inotify (private), for `lightgraph view`'s
 * hot reload. Linux only.
 *
 * A watcher holds registrations, each under a caller's tag: exact files (lg_watch_files)
 * and directory trees filtered by file-name suffix (lg_watch_tree). Files are watched
 * through their directories, never their inodes, so that every way of changing a file is
 * seen: written in place, saved by an editor as a temporary renamed over it, deleted and
 * created again, created after the watch started, its permissions changed. A directory that
 * disappears (and with it its watch) is tried again at most every 0.25 s of the `now` given
 * to lg_watch_poll; when it is back, its registered files are reported as changed.
 *
 * Debouncing. Events are stamped with the `now` of the lg_watch_poll call that reads them,
 * and a path is reported once no event has touched it for `quiet_s` seconds: an editor
 * writes in steps, a linker writes a .so over a while, ninja touches many files, and none of
 * that should trigger a reload of a half-written file. Each changed path is reported once
 * per quiet period. A file being written continuously is not reported until it stops.
 * A file still open for writing (its last events were its creation as a regular file or a
 * write, and no close has come yet: a linker pausing between bursts) waits for its close,
 * or for 10 quiet periods without an event (a writer that never closes, a hard link).
 *
 * Tags are bit flags (LG_WATCH_*, or the caller's own powers of two): a path registered
 * under several tags (a file both listed and inside a watched tree) is reported once, with
 * `tag` the bitwise OR of the tags it is registered with.
 *
 * Limits (Linux): each watched directory costs one inotify watch, counted against
 * /proc/sys/fs/inotify/max_user_watches (per user, shared with every other program; an
 * error from lg_watch_files/lg_watch_tree says when it is reached), and events wait in a
 * queue of /proc/sys/fs/inotify/max_queued_events. When that queue overflows (a huge build
 * writing in a watched tree while nobody polls), events are lost: lg_watch_poll then
 * rescans the trees and reports every registered file as changed, which is never wrong,
 * only more work.
 *
 * Not thread-safe: one thread uses a watcher (the viewer's event loop). Nothing blocks.
 */
#ifndef LG_HOST_WATCH_H
#define LG_HOST_WATCH_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

typedef struct lg_watch lg_watch;

/* The viewer's tags: the graph file and the files it includes, the shader sources, the
 * plugin shared objects. */
enum { LG_WATCH_GRAPH = 1, LG_WATCH_SHADER = 2, LG_WATCH_PLUGIN = 4 };

/* One changed file, as lg_watch_poll reports it. */
typedef struct lg_watch_change {
    int tag;    /* the tag the file was registered with (OR of them, see above) */
    char *path; /* absolute and normalised (lg_path_absolute: no symlink resolved) as
                 * registered, or directory + "/" + name for a file found in a tree */
} lg_watch_change;

/* Makes a watcher (inotify_init1 with IN_NONBLOCK | IN_CLOEXEC). Returns 0 and *out (free
 * with lg_watch_close), or -1 with err (the per-user instance limit,
 * /proc/sys/fs/inotify/max_user_instances, is named when it is the cause). */
int lg_watch_open(lg_watch **out, char *err, size_t errlen);
/* Closes the watcher and frees everything; *w may be NULL. Clears *w. */
void lg_watch_close(lg_watch **w);

/* Watches exactly the `n` files `paths` (relative ones against the current directory)
 * under `tag`, replacing the files registered with that tag before (n == 0 drops them
 * all). The files need not exist; their directories must: a directory that does not exist
 * (or is not a directory) is an error naming it, and then the previous registration of the
 * tag stays in force. Files are watched through their directories for IN_CLOSE_WRITE,
 * IN_MODIFY, IN_MOVED_TO, IN_MOVED_FROM, IN_CREATE, IN_DELETE and IN_ATTRIB. The path
 * strings need only live until the call returns. Returns 0, or -1 with err. */
int lg_watch_files(lg_watch *w, int tag, const char *const *paths, uint32_t n, char *err,
                   size_t errlen);

/* Watches every file under the directory `dir`, recursively (subdirectories made later
 * included: their files are reported as changed when they appear), whose name ends with
 * one of the `n_suffixes` strings `suffixes` (".glsl", ".so"; case-sensitive; n_suffixes 0:
 * any name), under `tag`. With `replace`, the trees registered with `tag` before are
 * dropped first; without, this one is added to them. `dir` must exist and be a directory,
 * else an error names it and nothing changes. Symbolic links to directories inside the
 * tree are not followed. Returns 0, or -1 with err. */
int lg_watch_tree(lg_watch *w, int tag, const char *dir, const char *const *suffixes,
                  uint32_t n_suffixes, bool replace, char *err, size_t errlen);

/* Reads the pending events (never blocks) and reports the registered files that changed
 * and have had no event for `quiet_s` seconds of `now` (monotonic seconds, lg_mono_now(); tests
 * may pass any increasing clock). Returns the count and *out, an array sorted by path
 * without duplicates (free with lg_watch_changes_free), or 0 and *out NULL when there is
 * nothing, or -1 with err when reading the inotify descriptor fails (a queue overflow is not
 * an error: see above). */
int lg_watch_poll(lg_watch *w, double now, double quiet_s, lg_watch_change **out, char *err,
                  size_t errlen);
/* Frees what lg_watch_poll returned; c may be NULL. */
void lg_watch_changes_free(lg_watch_change *c, int n);

/* The inotify descriptor, readable when events wait: for the caller's poll()/select(), or
 * glfwWaitEventsTimeout's caller to decide how long to sleep. Reading it is
 * lg_watch_poll's job. */
int lg_watch_fd(const lg_watch *w);

#endif
