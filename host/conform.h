/*
 * host/conform.h: `lightgraph conform PLUGIN.so [--json]` (cmd_conform.c) and its
 * synthetic inputs (conform_sources.c). docs/conform.md says what is checked and how.
 */
#ifndef LG_HOST_CONFORM_H
#define LG_HOST_CONFORM_H

#include <stdbool.h>
#include <stddef.h>

#include "lightgraph/plugin.h"

/* lightgraph conform PLUGIN.so [--json] [-v] [--quick]; argv[0] is "conform". Returns the
 * exit status: 0 every contract holds, 1 one is broken (the report names the node, the
 * check and the values), 2 bad usage (no such file). */
int lg_cmd_conform(int argc, char **argv);

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
 * (A local stand-in with the signature branch `names` gives lg_name_rule_ok; replace the
 * call once that branch is merged.) */
bool lg_conform_name_rule_ok(const char *plugin, const char *type, char *why, size_t n);

#endif
