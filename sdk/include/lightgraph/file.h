/*
 * lightgraph/file.h: reading files by the rules every loader follows.
 *
 * A loader (the graph parser, the image codecs, glTF and its buffers, cache entries, probes,
 * SH coefficient files, bake caches) reads its input through these functions, so that every
 * input of lightgraph obeys the same three rules:
 *
 *   1. Regular files only. A FIFO, a character or block device (/dev/zero), a directory or a
 *      socket is refused at once with a message naming what it is ("it is a FIFO, not a
 *      regular file"). The open never blocks: it uses O_NONBLOCK, and blocking I/O is
 *      restored only once the file is known to be regular.
 *   2. Bounded. The size is checked against the caller's limit before a byte is read or
 *      allocated, and no more than the size found is ever read: a file that grows while it
 *      is read is refused ("it grew while being read").
 *   3. Confined, where the caller names a folder. A referenced path (a glTF buffer, a glTF
 *      image) is resolved with every symbolic link followed and refused when the file it
 *      names lies outside that folder, in the message the path as written and where it
 *      leads. The check is made on the file actually opened (its /proc/self/fd link), so a
 *      link swapped between check and open cannot escape.
 *
 * Errors: each function writes the reason, without the path, into err (e.g. "it is 1.2 GiB,
 * over the 16 MiB limit"), sets errno (EISDIR, EINVAL for other non-regular files, EFBIG for
 * sizes, EACCES for confinement, or the system's own) and returns -1 or NULL. Callers prefix
 * the path: "cannot read 'scene.lgraph': it is a FIFO, not a regular file".
 *
 * Thread-safety: all functions are reentrant.
 */
#ifndef LIGHTGRAPH_FILE_H
#define LIGHTGRAPH_FILE_H

#include <stddef.h>
#include <stdint.h>

#include "lightgraph/config.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Opens path for reading when it is a regular file of at most limit bytes. Returns a
 * blocking, close-on-exec descriptor (the caller closes it) and stores the size in *size
 * (may be NULL), or returns -1 with the reason in err. */
LG_API int lg_file_open(const char *path, uint64_t limit, uint64_t *size, char *err, size_t errlen);

/* As lg_file_open, and the file must lie inside the folder root once every symbolic link is
 * resolved (root itself may be a link). A relative path is taken relative to root. */
LG_API int lg_file_open_within(const char *root, const char *path, uint64_t limit, uint64_t *size,
                               char *err, size_t errlen);

/* Reads a whole file of at most limit bytes. Returns a malloc'd buffer with a NUL byte after
 * the content (the caller frees it), its length in *len (may be NULL); NULL with the reason
 * in err. */
LG_API void *lg_file_read(const char *path, uint64_t limit, size_t *len, char *err, size_t errlen);

/* lg_file_read confined to root, as lg_file_open_within. */
LG_API void *lg_file_read_within(const char *root, const char *path, uint64_t limit, size_t *len,
                                 char *err, size_t errlen);

/* Reads exactly size bytes (the size lg_file_open found) from fd, refusing a file that grew
 * or failed; the buffer as lg_file_read's. Does not close fd. */
LG_API void *lg_file_read_fd(int fd, uint64_t size, size_t *len, char *err, size_t errlen);

/* Whether path, resolved with every link followed, names an existing file or folder inside
 * root. Returns 0, or -1 with the reason in err ("'../x' leads to '/etc/x', outside
 * '/models/box'"). For paths that a third-party library opens itself; prefer
 * lg_file_open_within, which checks the file it opens. */
LG_API int lg_path_within(const char *root, const char *path, char *err, size_t errlen);

#ifdef __cplusplus
}
#endif

#endif
