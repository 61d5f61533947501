/*
 * host/exec/names.h: the names of plugins and node types (docs/sdk.md "Names").
 *
 * Two rules, enforced in two places:
 *
 *   - Unique names, by every scan (registry.c): two plugins with the same name, or two node
 *     types with the same name (in two plugins, or twice in one), are never both loaded; the
 *     one found later is refused with both paths in the message. A plugin shipped with
 *     lightgraph (lg_shipped_plugin) found in the program's own plugin directory is taken
 *     before any other, so a third-party plugin can never displace one of them.
 *   - The naming rule for third-party plugins, by `lightgraph conform` only (a plugin that
 *     breaks it still loads): its name is VENDOR_NAME and every node type it declares starts
 *     with VENDOR_, where VENDOR is 2 to 16 of [a-z0-9] and not "lg". The plugins shipped in
 *     this repository keep their short names (core, phong, ...): they are exempt, and their
 *     names are the list below, which tests/unit/host (host_names_shipped_list) holds equal
 *     to the plugins plugins/ builds.
 */
#ifndef LG_HOST_NAMES_H
#define LG_HOST_NAMES_H

#include <stdbool.h>
#include <stddef.h>

/* The plugins built from plugins/NAME/ (each lg_NAME.so declares the plugin NAME), in
 * alphabetical order, NULL-terminated. */
extern const char *const lg_shipped_plugins[];

/* Whether `plugin_name` is one of lg_shipped_plugins. */
bool lg_shipped_plugin(const char *plugin_name);

/* The naming rule for a third-party plugin, for `lightgraph conform`. `type_name` is one
 * node type the plugin declares, or NULL to check the plugin's name alone. A shipped plugin
 * (lg_shipped_plugin) passes with any of its types. Returns true when the names follow the
 * rule; else false with why (n bytes, always NUL-terminated when n > 0) saying which name
 * breaks which part of it, e.g. "node type 'blur' of plugin 'acme_blur' does not start with
 * its vendor prefix 'acme_'". `why` may be NULL when n is 0. */
bool lg_name_rule_ok(const char *plugin_name, const char *type_name, char *why, size_t n);

#endif
