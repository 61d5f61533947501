/*
 * host/conform.h: `lightgraph conform PLUGIN.so [--json]` (cmd_conform.c) and its
 * synthetic inputs (conform_sources.c). docs/conform.md says what is checked and how.
 */
#ifndef LG_HOST_CONFORM_H
#define LG_HOST_CONFORM_H

#include <stdbool.h>
#include <stddef.h>

#include "lightgraph/plugin.h"

/* The descriptor of the program's own plugin "conform" (conform_sources.c): one node type
 * per resource kind, making the synthetic inputs. Static data. */
const lg_plugin_desc *lg_conform_sources(void);
/* The conform_* node type that makes a resource of `kind` (LG_KIND_ANY: an image). */
const char *lg_conform_source_for(lg_resource_kind kind);

/* Starts the count of conform_image's `squeeze` again (each case of a child process). */
void lg_conform_squeeze_reset(void);

/* The values of the sources' enum parameters, in order (NULL-terminated). */
extern const char *const lg_conform_formats[];   /* rgba32f rgba16f rgba8 rgbe8 */
extern const char *const lg_conform_patterns[];  /* ramp nan inf negative huge */
extern const char *const lg_conform_scenes[];    /* full empty unlit */
enum { LG_CONFORM_RAMP = 0, LG_CONFORM_NAN, LG_CONFORM_INF, LG_CONFORM_NEGATIVE,
       LG_CONFORM_HUGE };
enum { LG_CONFORM_SCENE_FULL = 0, LG_CONFORM_SCENE_EMPTY, LG_CONFORM_SCENE_UNLIT };

/* The naming rule for third-party plugins (docs/plugin-guide.md, "Names"): the plugin is
 * VENDOR_NAME and each node type VENDOR_..., VENDOR 2 to 16 of [a-z0-9] and not "lg";
 * the plugins of this repository are exempt. `type` NULL checks the plugin's name alone.
 * False with the reason in why[n].
 * A local stand-in: branch `names` gives the same rule as lg_name_rule_ok (host/names.h),
 * with this very signature, and its lg_shipped_plugins list; once it is merged, the two
 * calls in cmd_conform.c call that and this function and in_tree_plugins go. */
bool lg_conform_name_rule_ok(const char *plugin, const char *type, char *why, size_t n);

#endif
