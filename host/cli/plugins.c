/* lightgraph plugins [--json]: the plugins found, their node types, and the ones refused;
 * everything a user can write in a graph file, from the plugins' own declarations. */
#include "cli/commands.h"

int lg_cmd_plugins(int argc, char **argv)
{
    bool json = false;
    const char *name = NULL;
    if (lg_json_args(argc, argv, &json, &name, false))
        return 2;
    lg_registry reg = { 0 };
    lg_registry_scan(&reg);
    if (json) {
        lg_str o = { 0 };
        lg_str_addf(&o, "{\"abi\": {\"major\": %d, \"minor\": %d}, \"search_path\": [",
                    LG_ABI_MAJOR, LG_ABI_MINOR);
        for (uint32_t i = 0; i < reg.n_dirs; i++) {
            if (i)
                lg_str_add(&o, ", ");
            lg_str_add_json(&o, reg.dirs[i]);
        }
        lg_str_add(&o, "],\n \"plugins\": [");
        for (uint32_t i = 0; i < reg.n_plugins; i++) {
            lg_plugin *p = reg.plugins[i];
            lg_str_add(&o, i ? ",\n  {\"name\": " : "\n  {\"name\": ");
            lg_str_add_json(&o, p->name);
            lg_str_add(&o, ", \"version\": ");
            lg_str_add_json(&o, p->version);
            lg_str_addf(&o, ", \"abi\": {\"major\": %u, \"minor\": %u}, \"path\": ", p->abi_major,
                        p->abi_minor);
            lg_str_add_json(&o, p->path);
            lg_str_add(&o, ", \"doc\": ");
            lg_str_add_json(&o, p->doc);
            lg_str_add(&o, ", \"node_types\": [");
            for (uint32_t j = 0; j < p->n_types; j++) {
                lg_str_add(&o, j ? ",\n    " : "\n    ");
                lg_print_type_json(&o, &p->types[j], p);
            }
            lg_str_add(&o, "]}");
        }
        lg_str_add(&o, "],\n \"refused\": [");
        for (uint32_t i = 0; i < reg.n_refused; i++) {
            lg_str_add(&o, i ? ", {\"path\": " : "{\"path\": ");
            lg_str_add_json(&o, reg.refused[i].path);
            lg_str_add(&o, ", \"reason\": ");
            lg_str_add_json(&o, reg.refused[i].reason);
            lg_str_add(&o, "}");
        }
        lg_str_add(&o, "]}\n");
        fputs(o.s, stdout);
        lg_str_free(&o);
    } else {
        printf("plugin ABI %d.%d; search path:", LG_ABI_MAJOR, LG_ABI_MINOR);
        for (uint32_t i = 0; i < reg.n_dirs; i++)
            printf(" %s", reg.dirs[i]);
        printf("\n");
        for (uint32_t i = 0; i < reg.n_plugins; i++) {
            lg_plugin *p = reg.plugins[i];
            printf("\n%s %s (ABI %u.%u) %s\n  %s\n", p->name, p->version, p->abi_major,
                   p->abi_minor, p->path, p->doc ? p->doc : "");
            for (uint32_t j = 0; j < p->n_types; j++) {
                printf("\n");
                lg_print_type_text(stdout, &p->types[j], NULL);
            }
        }
        for (uint32_t i = 0; i < reg.n_refused; i++)
            printf("\nrefused: %s: %s\n", reg.refused[i].path, reg.refused[i].reason);
        if (!reg.n_plugins)
            printf("\nno plugins found\n");
    }
    lg_registry_free(&reg);
    return 0;
}
