/*
 * host/exec/outputs.h: all-or-nothing output files (private to the host).
 *
 * Every command that writes files (render and its --profile-json, sweep, diff --heatmap, and
 * the files nodes write: parameters marked LG_ROLE_OUTPUT_FILE) goes through one set of
 * outputs, in three steps:
 *
 *   1. Before any work, lg_outputs_add() names each destination. It is checked (the directory
 *      exists and is a directory, the destination is not a directory, a FIFO or a device, an image
 *      has a known extension) and a temporary file is created beside it, in the same directory:
 *      ".NAME.lgtmp-PID-XXXXXX.EXT". Creating it proves the directory is writable, the final rename
 *      stays inside one file system (so it is atomic), and the kept extension selects the
 *      image format when an image is written to the temporary.
 *   2. The work writes each output into its temporary (lg_outputs_temp, or the write helpers
 *      below, which hold SIGINT/SIGTERM/SIGHUP while they write).
 *   3. Only when everything succeeded, lg_outputs_commit() renames every temporary into
 *      place. A rename that fails part way puts back what the earlier renames replaced (the
 *      previous files are kept as hard links until the end), so either every destination
 *      holds its new file or every destination is as it was.
 *
 * lg_outputs_free() of a set that was not committed removes its temporaries: a failure leaves
 * no new file and every previous file untouched. While a set holds temporaries, SIGINT,
 * SIGTERM and SIGHUP remove them before the process dies of the signal.
 *
 * Missing directories are refused, never created: the message names the directory.
 *
 * Stale temporaries. A process killed outright (SIGKILL, a crash outside a plugin callback:
 * a plugin's crash in render or sweep removes them, lg_temp_remove_all) leaves its
 * temporaries.
 * Adding a destination removes those of earlier processes beside it whose PID (in the name)
 * is no running process; a live process's are kept (a directory can be shared by
 * concurrent renders); only names of exactly that pattern are touched.
 *
 * Not thread-safe (the host writes its outputs from the main thread).
 */
#ifndef LG_HOST_OUTPUTS_H
#define LG_HOST_OUTPUTS_H

#include <stdbool.h>
#include <stddef.h>

#include "lightgraph/image.h"

typedef struct lg_outputs lg_outputs;

typedef enum lg_output_kind {
    LG_OUTPUT_IMAGE, /* .png, .exr, .hdr or .pic */
    LG_OUTPUT_FILE,  /* any other file (CSV, JSON, a gnuplot script) */
} lg_output_kind;

/* A new, empty set (free with lg_outputs_free). */
lg_outputs *lg_outputs_new(void);
/* A set whose files another process writes: an MPI rank other than 0 (docs/distributed.md:
 * rank 0 alone writes). Paths are recorded and nothing else: not checked (the folder may
 * exist on rank 0's machine only), no temporary (lg_outputs_temp gives "", which is not a
 * file to read back), writes succeed without writing, the commit succeeds. */
lg_outputs *lg_outputs_new_elsewhere(void);

/* Checks `path` as a destination and reserves its temporary. Adding a path already in the set
 * returns 0 and keeps the one temporary (a sweep writes a run's image once per repeat).
 * Returns 0, or -1 with the reason in err ("cannot write 'out/a.png': the directory 'out' does
 * not exist (lightgraph does not create directories)"). */
int lg_outputs_add(lg_outputs *o, const char *path, lg_output_kind kind, char *err, size_t errlen);

/* A file a node writes (a parameter marked LG_ROLE_OUTPUT_FILE), checked and reserved like
 * an LG_OUTPUT_FILE. `owner` says whose it is ("node 'vol' (mesh_file)"; copied): a
 * destination that another owner, or the run's own outputs, already holds is refused
 * (adding it again under the same owner returns 0, as lg_outputs_add does). It is written
 * with lg_outputs_write_data; one that was never written when the set is committed (the
 * node was gated or failed to run) is dropped: no file is made and the previous one stays. */
int lg_outputs_add_owned(lg_outputs *o, const char *path, const char *owner, char *err,
                         size_t errlen);
/* The checks of lg_outputs_add without the temporary: for a caller with many outputs that
 * checks every destination before any work and adds each one (which makes its temporary)
 * only when the work that writes it starts (sweep: one run's image and heat map at a
 * time, not 20,000 empty files up front). The directory's writability is proven only by
 * a temporary made there. Returns 0, or -1 with the reason in err, as lg_outputs_add. */
int lg_outputs_check(const char *path, lg_output_kind kind, char *err, size_t errlen);

/* The temporary file that stands for `path` until the commit, or NULL when `path` was not
 * added. Owned by the set. */
const char *lg_outputs_temp(const lg_outputs *o, const char *path);

/* Writes an image or bytes into the temporary of an added `path`, with the signals held.
 * Return 0, or -1 with the reason in err. */
int lg_outputs_write_image(lg_outputs *o, const char *path, const lg_image *img,
                           const lg_image_write_opts *wo, char *err, size_t errlen);
int lg_outputs_write_data(lg_outputs *o, const char *path, const void *data, size_t n, char *err,
                          size_t errlen);

/* Takes `path` out of the set and removes its temporary (an optional output that could not
 * be made, such as a plot without gnuplot). */
void lg_outputs_drop(lg_outputs *o, const char *path);

/* Renames every temporary into place, all or nothing (see above). Returns 0, or -1 with the
 * reason in err, every destination then as it was before. A signal that arrived while the
 * outputs were written is honoured here, before any rename: nothing is committed. */
int lg_outputs_commit(lg_outputs *o, char *err, size_t errlen);

/* Removes the temporaries of an uncommitted set, then frees it; NULL is fine; *o is
 * cleared. */
void lg_outputs_free(lg_outputs **o);

/* Other temporaries the signal handler removes (the cache's entries being written):
 * lg_temp_track before the file is created, lg_temp_untrack once it is renamed or removed.
 * `tmp` stays the caller's and must stay valid until untracked. */
void lg_temp_track(char *tmp);
void lg_temp_untrack(const char *tmp);

/* Removes every temporary the handlers know (the outputs' and the cache's), for a handler
 * that then ends the process (a plugin's crash: exec.c, LG_GUARD_EXIT). Async-signal-safe
 * (unlink only); a no-op in a forked child. */
void lg_temp_remove_all(void);

/* Whether no process has `pid` (kill(pid, 0) fails with ESRCH): the temporaries it named
 * after itself are stale. False for this process and for a live process of another user. */
bool lg_temp_owner_dead(long pid);

/* (outputs.c) A --size the user gave, against the pixel limit (--max-pixels,
 * LIGHTGRAPH_MAX_PIXELS): true, after a message naming `cmd`, the size, its pixels and the
 * limit, when W x H is over it (bad usage: exit 2). The default size is not checked here: a
 * node that makes an image of it is, when it declares that image. */
bool lg_size_over_limit(const char *cmd, uint32_t w, uint32_t h);

#endif
