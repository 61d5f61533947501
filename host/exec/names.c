/* The names of plugins and node types. See names.h. */
#include "exec/names.h"

#include <stdarg.h>
#include <stdio.h>
#include <string.h>

/* One line per folder of plugins/ that builds a plugin (plugins/meson.build); the folders
 * that build only a library (embree_common, volumetric_common) are not plugins. Keep it in
 * alphabetical order: tests/unit/host/test_names.c compares it with the folders and with
 * the name each built lg_NAME.so declares. */
const char *const lg_shipped_plugins[] = {
    "core",
    "ibl",
    "phong",
    "preview",
    "probe",
    "prt",
    "prt_bake",
    "reinhard",
    "scene_gltf",
    "scene_tools",
    "sh_project",
    "shadow_reference",
    "shadowmap",
    "volumetric_froxel",
    "volumetric_polygonal",
    "volumetric_reference",
    "volumetric_screen",
    NULL,
};

bool lg_shipped_plugin(const char *plugin_name)
{
    for (size_t i = 0; plugin_name && lg_shipped_plugins[i]; i++)
        if (strcmp(lg_shipped_plugins[i], plugin_name) == 0)
            return true;
    return false;
}

#define LG_VENDOR_MIN 2
#define LG_VENDOR_MAX 16

static bool lower_or_digit(char c)
{
    return (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9');
}

/* Writes the reason into why (when there is room) and returns false. */
__attribute__((format(printf, 3, 4))) static bool refuse(char *why, size_t n, const char *fmt, ...)
{
    if (why && n) {
        va_list ap;
        va_start(ap, fmt);
        vsnprintf(why, n, fmt, ap);
        va_end(ap);
    }
    return false;
}

bool lg_name_rule_ok(const char *plugin_name, const char *type_name, char *why, size_t n)
{
    if (why && n)
        why[0] = 0;
    if (!plugin_name || !plugin_name[0])
        return refuse(why, n, "the plugin has no name");
    if (lg_shipped_plugin(plugin_name))
        return true;
    /* VENDOR is everything before the first '_' */
    const char *us = strchr(plugin_name, '_');
    size_t vlen = us ? (size_t)(us - plugin_name) : strlen(plugin_name);
    if (!us || !us[1])
        return refuse(why, n,
                      "plugin name '%s' is not VENDOR_NAME (a vendor prefix of 2 to 16 of "
                      "[a-z0-9], '_', then the plugin's own name, e.g. 'acme_blur')",
                      plugin_name);
    if (vlen < LG_VENDOR_MIN || vlen > LG_VENDOR_MAX)
        return refuse(why, n,
                      "plugin name '%s': its vendor prefix '%.*s' has %zu characters, not 2 "
                      "to 16",
                      plugin_name, (int)(vlen > 64 ? 64 : vlen), plugin_name, vlen);
    for (size_t i = 0; i < vlen; i++)
        if (!lower_or_digit(plugin_name[i]))
            return refuse(why, n,
                          "plugin name '%s': its vendor prefix '%.*s' is not made of [a-z0-9] "
                          "only",
                          plugin_name, (int)vlen, plugin_name);
    for (const char *c = us + 1; *c; c++)
        if (!lower_or_digit(*c) && *c != '_')
            return refuse(why, n, "plugin name '%s' is not made of [a-z0-9_] only", plugin_name);
    if (vlen == 2 && strncmp(plugin_name, "lg", 2) == 0)
        return refuse(why, n,
                      "plugin name '%s': the vendor prefix 'lg' is lightgraph's own; choose "
                      "your own (2 to 16 of [a-z0-9])",
                      plugin_name);
    if (!type_name)
        return true;
    if (strncmp(type_name, plugin_name, vlen + 1) != 0 || !type_name[vlen + 1])
        return refuse(why, n,
                      "node type '%s' of plugin '%s' does not start with its vendor prefix "
                      "'%.*s' followed by a name (e.g. '%.*sblur')",
                      type_name, plugin_name, (int)vlen + 1, plugin_name, (int)vlen + 1,
                      plugin_name);
    return true;
}
