/*
 * host/cli/conform.h: `lightgraph conform PLUGIN.so [--json]` (conform.c) and its
 * synthetic inputs (conform_sources.c). docs/conform.md says what is checked and how.
 */
#ifndef LG_HOST_CONFORM_H
#define LG_HOST_CONFORM_H

#include "lightgraph/plugin.h"

/* The descriptor of the program's own plugin "conform" (conform_sources.c): one node type
 * per resource kind, making the synthetic inputs. Static data. */
const lg_plugin_desc *lg_conform_sources(void);
/* The conform_* node type that makes a resource of `kind` (LG_KIND_ANY: an image). */
const char *lg_conform_source_for(lg_resource_kind kind);

/* Starts the count of conform_image's `squeeze` again (each case of a child process). */
void lg_conform_squeeze_reset(void);

/* The values of the sources' enum parameters, in order (NULL-terminated). */
extern const char *const lg_conform_formats[];  /* rgba32f rgba16f rgba8 rgbe8 */
extern const char *const lg_conform_patterns[]; /* ramp nan inf negative huge */
extern const char *const lg_conform_scenes[];   /* full empty unlit */
enum { LG_CONFORM_RAMP = 0, LG_CONFORM_NAN, LG_CONFORM_INF, LG_CONFORM_NEGATIVE, LG_CONFORM_HUGE };
enum { LG_CONFORM_SCENE_FULL = 0, LG_CONFORM_SCENE_EMPTY, LG_CONFORM_SCENE_UNLIT };

#endif
