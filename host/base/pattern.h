/*
 * host/base/pattern.h: frame patterns in output file names (private to the host).
 *
 * An output whose file name holds one printf-style integer conversion, %d or %0Nd (N a
 * width of 1 to 9 digits), is written once per frame of `render --frames N`: frame k's
 * file is the name with the conversion replaced by k ("frames/f_%04d.exr" -> "frames/
 * f_0007.exr"). "%%" stands for a literal '%' in a name that holds a pattern. A name
 * without any '%' is an ordinary output (written once, with the last frame). Anything
 * else with a '%' (%s, %x, %n, a width without the 0, two conversions, a lone '%') is
 * refused by the graph's check, with the character's position.
 */
#ifndef LG_HOST_PATTERN_H
#define LG_HOST_PATTERN_H

#include <stddef.h>
#include <stdint.h>

/* 1: `path` holds one frame conversion; 0: it has no '%' at all; -1: it is malformed:
 * *pos is the 0-based index of the offending '%' and `why` (may be NULL) says what is
 * wrong ("'%s' is not a frame number: use %d or %0Nd"). */
int lg_frame_pattern_scan(const char *path, size_t *pos, char *why, size_t why_len);

/* The file name of frame `frame` for a `path` that lg_frame_pattern_scan gave 1 (malloc'd,
 * owned by the caller); a copy of `path` for any other. */
char *lg_frame_pattern_name(const char *path, uint32_t frame);

#endif
