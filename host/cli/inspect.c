/* lightgraph inspect NODE_TYPE [--json]: one node type, as the plugin declares it. */
#include "cli/commands.h"

int lg_cmd_inspect(int argc, char **argv)
{
    bool json = false;
    const char *name = NULL;
    if (lg_json_args(argc, argv, &json, &name, true))
        return 2;
    lg_registry reg = { 0 };
    lg_registry_scan(&reg);
    lg_plugin *p = NULL;
    const lg_node_type *t = lg_registry_lookup(&reg, name, &p);
    int rc = 0;
    if (!t) {
        const char *s = lg_suggest(name, reg.names, reg.n_names);
        fprintf(stderr, "lightgraph inspect: unknown node type '%s'%s%s%s\n", name,
                s ? "; did you mean '" : "", s ? s : "", s ? "'?" : "");
        rc = 2;
    } else if (json) {
        lg_str o = { 0 };
        lg_print_type_json(&o, t, p);
        lg_str_add(&o, "\n");
        fputs(o.s, stdout);
        lg_str_free(&o);
    } else {
        lg_print_type_text(stdout, t, p);
    }
    lg_registry_free(&reg);
    return rc;
}
