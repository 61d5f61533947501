/* What the plugins declare, printed (commands.h): a node type as text or JSON, a parameter
 * value as written in a graph file, and the `[--json] [NAME]` command line that `plugins`
 * and `inspect` share. */
#include "cli/commands.h"

#include "lightgraph/kinds.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static const char *type_names[] = { "?",     "bool",   "int",  "float", "vec2", "vec3",
                                    "color", "string", "path", "enum",  "int3", "path_list" };

static const char *part_type_name(lg_part_type t)
{
    return t == LG_PART_IMAGE    ? "image"
           : t == LG_PART_VOLUME ? "volume"
           : t == LG_PART_BUFFER ? "buffer"
                                 : "meta";
}

static const char *ptype_name(lg_param_type t)
{
    return (unsigned)t <= LG_PARAM_PATH_LIST ? type_names[t] : "?";
}

static void num(lg_str *o, double v, bool json)
{
    if (!isfinite(v)) {
        lg_str_add(o, json ? "null" : (v > 0 ? "inf" : v < 0 ? "-inf" : "nan"));
        return;
    }
    char buf[64];
    for (int prec = 1; prec <= 17; prec++) {
        snprintf(buf, sizeof buf, "%.*g", prec, v);
        if (strtod(buf, NULL) == v)
            break;
    }
    /* keep a float recognisable as one */
    if (!strpbrk(buf, ".eEn"))
        strcat(buf, ".0");
    lg_str_add(o, buf);
}

static void value(lg_str *o, const lg_value *v, lg_param_type t, bool json)
{
    switch (t) {
    case LG_PARAM_BOOL: lg_str_add(o, v->b ? "true" : "false"); break;
    case LG_PARAM_INT: lg_str_addf(o, "%lld", (long long)v->i); break;
    case LG_PARAM_FLOAT: num(o, v->f, json); break;
    case LG_PARAM_VEC2:
    case LG_PARAM_VEC3:
    case LG_PARAM_COLOR: {
        int n = t == LG_PARAM_VEC2 ? 2 : 3;
        lg_str_add(o, "[");
        for (int i = 0; i < n; i++) {
            if (i)
                lg_str_add(o, ", ");
            num(o, v->v[i], json);
        }
        lg_str_add(o, "]");
        break;
    }
    case LG_PARAM_INT3:
        lg_str_addf(o, "[%lld, %lld, %lld]", (long long)v->i3[0], (long long)v->i3[1],
                    (long long)v->i3[2]);
        break;
    case LG_PARAM_STRING:
    case LG_PARAM_PATH:
    case LG_PARAM_ENUM: lg_str_add_json(o, v->s ? v->s : ""); break;
    case LG_PARAM_PATH_LIST: {
        lg_str_add(o, "[");
        const char *s = v->s;
        for (int32_t i = 0; s && i < v->e; i++, s += strlen(s) + 1) {
            if (i)
                lg_str_add(o, ", ");
            lg_str_add_json(o, s);
        }
        lg_str_add(o, "]");
        break;
    }
    }
}

/* A parameter's default as written in a graph file (or as JSON): a colour that also takes
 * keywords (ABI 2.3) may default to a keyword, def.e >= 0, printed as its word. */
static void default_value(lg_str *o, const lg_param_desc *q, bool json)
{
    if (q->type == LG_PARAM_COLOR && q->enum_values && q->def.e >= 0) {
        if (json)
            lg_str_add_json(o, q->enum_values[q->def.e]);
        else
            lg_str_add(o, q->enum_values[q->def.e]);
        return;
    }
    value(o, &q->def, q->type, json);
}

void lg_print_value(lg_str *out, const lg_value *v, lg_param_type type)
{
    value(out, v, type, false);
}

static const char *need_names[] = { "geometry", "light", "directional_light", "point_light",
                                    "medium",   "probe", "specular_material", "reflective_material",
                                    "textures" };

void lg_print_type_json(lg_str *o, const lg_node_type *t, const lg_plugin *p)
{
    lg_str_add(o, "{\"name\": ");
    lg_str_add_json(o, t->name);
    lg_str_add(o, ", \"doc\": ");
    lg_str_add_json(o, t->doc);
    if (p) {
        lg_str_add(o, ", \"plugin\": ");
        lg_str_add_json(o, p->name);
    }
    for (int io = 0; io < 2; io++) {
        const lg_port_desc *ports = io ? t->outputs : t->inputs;
        uint32_t n = io ? t->n_outputs : t->n_inputs;
        lg_str_addf(o, ", \"%s\": [", io ? "outputs" : "inputs");
        for (uint32_t i = 0; i < n; i++) {
            lg_str_add(o, i ? ", {\"name\": " : "{\"name\": ");
            lg_str_add_json(o, ports[i].name);
            lg_str_addf(o, ", \"kind\": \"%s\"", lg_kind_name(ports[i].kind));
            const lg_kind_desc *kd = lg_kind_describe(ports[i].kind);
            if (kd && kd->n_parts) {
                lg_str_add(o, ", \"parts\": [");
                for (uint32_t j = 0; j < kd->n_parts; j++)
                    lg_str_addf(o, "%s{\"name\": \"%s\", \"type\": \"%s\", \"optional\": %s}",
                                j ? ", " : "", kd->parts[j].name, part_type_name(kd->parts[j].type),
                                kd->parts[j].optional ? "true" : "false");
                lg_str_add(o, "]");
            }
            if (!io)
                lg_str_addf(o, ", \"optional\": %s", ports[i].optional ? "true" : "false");
            lg_str_add(o, ", \"doc\": ");
            lg_str_add_json(o, ports[i].doc);
            lg_str_add(o, "}");
        }
        lg_str_add(o, "]");
    }
    lg_str_add(o, ", \"parameters\": [");
    for (uint32_t i = 0; i < t->n_params; i++) {
        const lg_param_desc *q = &t->params[i];
        lg_str_add(o, i ? ", {\"key\": " : "{\"key\": ");
        lg_str_add_json(o, q->key);
        lg_str_addf(o, ", \"type\": \"%s\", \"default\": ", ptype_name(q->type));
        default_value(o, q, true);
        if (q->min < q->max) {
            lg_str_add(o, ", \"min\": ");
            num(o, q->min, true);
            lg_str_add(o, ", \"max\": ");
            num(o, q->max, true);
        }
        if (q->enum_values) {
            lg_str_add(o, ", \"values\": [");
            for (int e = 0; q->enum_values[e]; e++) {
                if (e)
                    lg_str_add(o, ", ");
                lg_str_add_json(o, q->enum_values[e]);
            }
            lg_str_add(o, "]");
        }
        if (q->renamed_from && q->renamed_from[0]) {
            lg_str_add(o, ", \"renamed_from\": [");
            for (int e = 0; q->renamed_from[e]; e++) {
                if (e)
                    lg_str_add(o, ", ");
                lg_str_add_json(o, q->renamed_from[e]);
            }
            lg_str_add(o, "]");
        }
        lg_str_add(o, ", \"doc\": ");
        lg_str_add_json(o, q->doc);
        lg_str_add(o, "}");
    }
    lg_str_add(o, "], \"needs\": [");
    bool first = true;
    for (int b = 0; b < (int)(sizeof need_names / sizeof *need_names); b++)
        if (t->needs & (1u << b)) {
            lg_str_addf(o, "%s\"%s\"", first ? "" : ", ", need_names[b]);
            first = false;
        }
    lg_str_addf(o, "], \"side_effect\": %s, \"per_frame\": %s, \"neutral\": ",
                (t->flags & LG_NODE_SIDE_EFFECT) ? "true" : "false",
                (t->flags & LG_NODE_PER_FRAME) ? "true" : "false");
    if ((t->neutral == LG_NEUTRAL_PASSTHROUGH || t->neutral == LG_NEUTRAL_PASSTHROUGH_FIRST) &&
        t->neutral_input < t->n_inputs) {
        lg_str_add(o, t->neutral == LG_NEUTRAL_PASSTHROUGH ? "{\"passthrough\": "
                                                           : "{\"passthrough_first\": ");
        lg_str_add_json(o, t->inputs[t->neutral_input].name);
        lg_str_add(o, "}");
    } else {
        lg_str_add(o, "\"zero\"");
    }
    lg_str_add(o, "}");
}

void lg_print_type_text(FILE *f, const lg_node_type *t, const lg_plugin *p)
{
    fprintf(f, "%s: %s\n", t->name, t->doc ? t->doc : "");
    if (p)
        fprintf(f, "  plugin %s %s (%s)\n", p->name, p->version, p->path);
    for (int io = 0; io < 2; io++) {
        const lg_port_desc *ports = io ? t->outputs : t->inputs;
        uint32_t n = io ? t->n_outputs : t->n_inputs;
        fprintf(f, "  %s:%s\n", io ? "outputs" : "inputs", n ? "" : " (none)");
        for (uint32_t i = 0; i < n; i++) {
            fprintf(f, "    %-12s %-10s %-9s %s\n", ports[i].name, lg_kind_name(ports[i].kind),
                    io                  ? ""
                    : ports[i].optional ? "optional"
                                        : "required",
                    ports[i].doc ? ports[i].doc : "");
            const lg_kind_desc *kd = lg_kind_describe(ports[i].kind);
            for (uint32_t j = 0; kd && j < kd->n_parts; j++)
                fprintf(f, "      .%-10s %-10s %-9s %s\n", kd->parts[j].name,
                        part_type_name(kd->parts[j].type), kd->parts[j].optional ? "optional" : "",
                        kd->parts[j].doc);
        }
    }
    fprintf(f, "  parameters:%s\n", t->n_params ? "" : " (none)");
    for (uint32_t i = 0; i < t->n_params; i++) {
        const lg_param_desc *q = &t->params[i];
        lg_str d = { 0 }, r = { 0 };
        default_value(&d, q, false);
        if (q->type == LG_PARAM_COLOR && q->enum_values) {
            /* a colour or a keyword (ABI 2.3): "[0, 1] or {material}" */
            if (q->min < q->max) {
                lg_str_add(&r, "[");
                num(&r, q->min, false);
                lg_str_add(&r, ", ");
                num(&r, q->max, false);
                lg_str_add(&r, "] or ");
            } else {
                lg_str_add(&r, "colour or ");
            }
            lg_str_add(&r, "{");
            for (int e = 0; q->enum_values[e]; e++)
                lg_str_addf(&r, "%s%s", e ? ", " : "", q->enum_values[e]);
            lg_str_add(&r, "}");
        } else if (q->min < q->max && (q->type == LG_PARAM_INT || q->type == LG_PARAM_INT3)) {
            lg_str_addf(&r, "[%.0f, %.0f]", q->min, q->max);
        } else if (q->min < q->max) {
            lg_str_add(&r, "[");
            num(&r, q->min, false);
            lg_str_add(&r, ", ");
            num(&r, q->max, false);
            lg_str_add(&r, "]");
        } else if (q->enum_values) {
            lg_str_add(&r, "{");
            for (int e = 0; q->enum_values[e]; e++)
                lg_str_addf(&r, "%s%s", e ? ", " : "", q->enum_values[e]);
            lg_str_add(&r, "}");
        }
        fprintf(f, "    %-14s %-6s = %-12s %-20s %s\n", q->key, ptype_name(q->type), d.s,
                r.s ? r.s : "", q->doc ? q->doc : "");
        if (q->renamed_from && q->renamed_from[0]) {
            fprintf(f, "    %-14s (formerly:", "");
            for (int e = 0; q->renamed_from[e]; e++)
                fprintf(f, " %s", q->renamed_from[e]);
            fprintf(f, ")\n");
        }
        lg_str_free(&d);
        lg_str_free(&r);
    }
    if (t->needs) {
        fprintf(f, "  needs from the scene:");
        for (int b = 0; b < (int)(sizeof need_names / sizeof *need_names); b++)
            if (t->needs & (1u << b))
                fprintf(f, " %s", need_names[b]);
        fprintf(f, " (otherwise gated: %s)\n",
                t->neutral == LG_NEUTRAL_PASSTHROUGH ? "passes its input through"
                : t->neutral == LG_NEUTRAL_PASSTHROUGH_FIRST
                    ? "its first output passes its input through, the others are black / empty"
                    : "yields black / empty");
    }
}

int lg_json_args(int argc, char **argv, bool *json, const char **name, bool want_name)
{
    for (int i = 1; i < argc; i++) {
        if (strcmp(argv[i], "--json") == 0)
            *json = true;
        else if (want_name && !*name && argv[i][0] != '-')
            *name = argv[i];
        else {
            fprintf(stderr, "lightgraph %s: unexpected argument '%s'\n", argv[0], argv[i]);
            return -1;
        }
    }
    if (want_name && !*name) {
        fprintf(stderr, "usage: lightgraph inspect NODE_TYPE [--json]\n");
        return -1;
    }
    return 0;
}
