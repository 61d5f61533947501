/* Plugin discovery, scanning (in a child process) and loading. See exec.h. */
#include "exec/exec.h"

#include <dirent.h>
#include <dlfcn.h>
#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <link.h>
#include <poll.h>
#include <math.h>
#include <signal.h>
#include <stdlib.h>
#include <string.h>
#include <sys/prctl.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include "lightgraph/file.h"
#include "exec/names.h"

/* ---- descriptor validation ------------------------------------------------------------------- */

static bool valid_ident(const char *s)
{
    if (!s || !((*s >= 'a' && *s <= 'z') || *s == '_'))
        return false;
    for (; *s; s++)
        if (!((*s >= 'a' && *s <= 'z') || (*s >= '0' && *s <= '9') || *s == '_'))
            return false;
    return true;
}

static bool str_ok(const char *s, size_t max)
{
    return s && strnlen(s, max + 1) <= max;
}

/* Whether an enum parameter has a value at index i (its list is NULL-terminated). */
static bool enum_has(const lg_param_desc *p, int32_t i)
{
    for (int32_t k = 0; k <= i; k++)
        if (!p->enum_values[k])
            return false;
    return true;
}

#define FAIL(...)                                                                                  \
    do {                                                                                           \
        snprintf(err, errlen, __VA_ARGS__);                                                        \
        return -1;                                                                                 \
    } while (0)

static int validate_param(const lg_node_type *t, const lg_param_desc *p, char *err, size_t errlen)
{
    if (!valid_ident(p->key))
        FAIL("node type '%s': a parameter has an invalid key", t->name);
    if (p->type < LG_PARAM_BOOL || p->type > LG_PARAM_PATH_LIST)
        FAIL("node type '%s', parameter '%s': unknown type %d", t->name, p->key, (int)p->type);
    if (p->min > p->max)
        FAIL("node type '%s', parameter '%s': min %g > max %g", t->name, p->key, p->min, p->max);
    if (p->type == LG_PARAM_PATH_LIST && ((p->def.s && p->def.s[0]) || p->def.e != 0))
        FAIL("node type '%s', parameter '%s': a path list's default is the empty list", t->name,
             p->key);
    /* an output file is written only where the graph names one: a default would write it
     * on every render without anyone asking */
    if (p->role == LG_ROLE_OUTPUT_FILE && (p->type != LG_PARAM_PATH || (p->def.s && p->def.s[0])))
        FAIL("node type '%s', parameter '%s': an output file (LG_ROLE_OUTPUT_FILE) is a PATH "
             "parameter whose default is \"\"",
             t->name, p->key);
    bool ranged = p->min < p->max;
    switch (p->type) {
    case LG_PARAM_INT:
        if (ranged && ((double)p->def.i < p->min || (double)p->def.i > p->max))
            FAIL("node type '%s', parameter '%s': default %lld outside [%g, %g]", t->name, p->key,
                 (long long)p->def.i, p->min, p->max);
        break;
    case LG_PARAM_FLOAT:
        if (ranged && (p->def.f < p->min || p->def.f > p->max))
            FAIL("node type '%s', parameter '%s': default %g outside [%g, %g]", t->name, p->key,
                 p->def.f, p->min, p->max);
        break;
    case LG_PARAM_ENUM: {
        if (!p->enum_values || !p->enum_values[0])
            FAIL("node type '%s', parameter '%s': an enum without values", t->name, p->key);
        int n = 0;
        while (p->enum_values[n] && n < 256)
            n++;
        if (p->def.s) {
            bool found = false;
            for (int i = 0; i < n; i++)
                found |= strcmp(p->enum_values[i], p->def.s) == 0;
            if (!found)
                FAIL("node type '%s', parameter '%s': default '%s' is not one of its values",
                     t->name, p->key, p->def.s);
        } else if (p->def.e < 0 || p->def.e >= n) {
            FAIL("node type '%s', parameter '%s': default index %d out of range", t->name, p->key,
                 (int)p->def.e);
        }
        break;
    }
    case LG_PARAM_COLOR: {
        /* keywords (ABI 2.3): def.e names the default keyword, or -1 for the colour def.v */
        if (!p->enum_values)
            break;
        int n = 0;
        while (p->enum_values[n] && n < 256)
            n++;
        if (n == 0 || p->enum_values[n])
            FAIL("node type '%s', parameter '%s': a colour's keyword list is empty or longer "
                 "than 256",
                 t->name, p->key);
        for (int i = 0; i < n; i++)
            if (!valid_ident(p->enum_values[i]))
                FAIL("node type '%s', parameter '%s': keyword %d is not a bare word "
                     "[a-z_][a-z0-9_]*",
                     t->name, p->key, i);
        if (p->def.e < -1 || p->def.e >= n)
            FAIL("node type '%s', parameter '%s': default keyword index %d out of range (-1 "
                 "for the colour .def.v, 0 .. %d for a keyword)",
                 t->name, p->key, (int)p->def.e, n - 1);
        for (int i = 0; p->def.e == -1 && ranged && i < 3; i++)
            if (!(p->def.v[i] >= p->min && p->def.v[i] <= p->max))
                FAIL("node type '%s', parameter '%s': default colour component %d = %g outside "
                     "[%g, %g]",
                     t->name, p->key, i, p->def.v[i], p->min, p->max);
        break;
    }
    default: break;
    }
    return 0;
}

/* live: a plugin's own descriptor, whose callbacks are checked too; otherwise a decoded
 * scan result (no callbacks), whose enum defaults must also name their index. */
static int check_desc(const lg_plugin_desc *d, bool live, char *err, size_t errlen)
{
    if (!d)
        FAIL("lg_plugin_entry() returned NULL");
    if (d->struct_size < offsetof(lg_plugin_desc, reserved))
        FAIL("malformed descriptor: struct_size %zu is smaller than the minimum %zu",
             d->struct_size, offsetof(lg_plugin_desc, reserved));
    if (d->abi_major < LG_ABI_MAJOR)
        FAIL("built for plugin ABI %u.%u; this host has ABI %d.%d, which no longer loads ABI "
             "%u plugins: rebuild it against the lightgraph %d SDK (docs/sdk.md, \"Migrating "
             "from ABI %u\")",
             d->abi_major, d->abi_minor, LG_ABI_MAJOR, LG_ABI_MINOR, d->abi_major, LG_ABI_MAJOR,
             d->abi_major);
    if (d->abi_major != LG_ABI_MAJOR || d->abi_minor > LG_ABI_MINOR)
        FAIL("built for plugin ABI %u.%u, this host has ABI %d.%d (needs major %d, minor at "
             "most %d)",
             d->abi_major, d->abi_minor, LG_ABI_MAJOR, LG_ABI_MINOR, LG_ABI_MAJOR, LG_ABI_MINOR);
    if (!valid_ident(d->name))
        FAIL("malformed descriptor: plugin name missing or not [a-z_][a-z0-9_]*");
    if (!str_ok(d->version, 64))
        FAIL("malformed descriptor: plugin '%s' has no version", d->name);
    if (!d->types || d->n_types == 0 || d->n_types > 1024)
        FAIL("malformed descriptor: plugin '%s' declares %u node types", d->name, d->n_types);
    for (uint32_t i = 0; i < d->n_types; i++) {
        const lg_node_type *t = &d->types[i];
        if (t->struct_size < offsetof(lg_node_type, reserved))
            FAIL("malformed descriptor: node type %u of '%s': struct_size %zu too small", i,
                 d->name, t->struct_size);
        if (!valid_ident(t->name))
            FAIL("malformed descriptor: node type %u of '%s' has no valid name", i, d->name);
        if (live && !t->execute)
            FAIL("node type '%s' has no execute callback", t->name);
        if (t->n_params > 256 || (t->n_params && !t->params))
            FAIL("node type '%s': bad parameter table (%u entries)", t->name, t->n_params);
        if (t->n_inputs > 64 || (t->n_inputs && !t->inputs) || t->n_outputs > 64 ||
            (t->n_outputs && !t->outputs))
            FAIL("node type '%s': bad port tables", t->name);
        for (uint32_t k = 0; k < t->n_params; k++) {
            const lg_param_desc *p = &t->params[k];
            if (validate_param(t, p, err, errlen))
                return -1;
            /* the encoder (put_desc) writes an enum default's name and index, agreeing */
            if (!live && p->type == LG_PARAM_ENUM &&
                (!p->def.s || p->def.e < 0 || p->def.e >= 256 || !enum_has(p, p->def.e) ||
                 strcmp(p->enum_values[p->def.e], p->def.s) != 0))
                FAIL("node type '%s', parameter '%s': default name and index disagree", t->name,
                     p->key);
            for (uint32_t j = 0; j < k; j++)
                if (strcmp(t->params[j].key, t->params[k].key) == 0)
                    FAIL("node type '%s': parameter '%s' declared twice", t->name,
                         t->params[k].key);
        }
        for (uint32_t k = 0; k < t->n_inputs + t->n_outputs; k++) {
            const lg_port_desc *p = k < t->n_inputs ? &t->inputs[k] : &t->outputs[k - t->n_inputs];
            if (!valid_ident(p->name))
                FAIL("node type '%s': a port has an invalid name", t->name);
            if ((int)p->kind < 0 || p->kind >= LG_KIND_COUNT_)
                FAIL("node type '%s', port '%s': unknown resource kind", t->name, p->name);
        }
        if ((int)t->neutral < LG_NEUTRAL_ZERO || t->neutral > LG_NEUTRAL_PASSTHROUGH_FIRST)
            FAIL("node type '%s': unknown neutral result %d", t->name, (int)t->neutral);
        if ((t->neutral == LG_NEUTRAL_PASSTHROUGH || t->neutral == LG_NEUTRAL_PASSTHROUGH_FIRST) &&
            t->neutral_input >= t->n_inputs)
            FAIL("node type '%s': neutral_input %u is not an input", t->name, t->neutral_input);
        /* a graph names a type by its name alone: of two with one name, one could never
         * be reached (names.h) */
        for (uint32_t j = 0; j < i; j++)
            if (strcmp(d->types[j].name, t->name) == 0)
                FAIL("malformed descriptor: plugin '%s' declares node type '%s' twice (types "
                     "%u and %u); node type names are unique",
                     d->name, t->name, j, i);
    }
    return 0;
}

int lg_descriptor_validate(const lg_plugin_desc *d, const char *path, char *err, size_t errlen)
{
    (void)path;
    return check_desc(d, true, err, errlen);
}
#undef FAIL

/* ---- serialisation of a descriptor (child -> parent) ----------------------------------------- */

static void put_list(lg_str *b, const char *const *l)
{
    uint32_t n = 0;
    while (l && l[n] && n < 256)
        n++;
    lg_wire_put_u32(b, l ? n : UINT32_MAX);
    for (uint32_t i = 0; i < n; i++)
        lg_wire_put_text(b, l[i]);
}

static void put_desc(lg_str *b, const lg_plugin_desc *d)
{
    lg_wire_put_raw(b, "LGSCAN2", 8);
    lg_wire_put_u32(b, d->abi_major);
    lg_wire_put_u32(b, d->abi_minor);
    lg_wire_put_text(b, d->name);
    lg_wire_put_text(b, d->version);
    lg_wire_put_text(b, d->doc);
    lg_wire_put_u32(b, d->n_types);
    for (uint32_t i = 0; i < d->n_types; i++) {
        const lg_node_type *t = &d->types[i];
        lg_wire_put_text(b, t->name);
        lg_wire_put_text(b, t->doc);
        lg_wire_put_u32(b, t->needs);
        lg_wire_put_u32(b, t->flags);
        lg_wire_put_u32(b, (uint32_t)t->neutral);
        lg_wire_put_u32(b, t->neutral_input);
        lg_wire_put_u32(b, t->n_params);
        for (uint32_t k = 0; k < t->n_params; k++) {
            const lg_param_desc *p = &t->params[k];
            lg_wire_put_text(b, p->key);
            lg_wire_put_u32(b, (uint32_t)p->type);
            /* a normalised copy: no padding garbage, enum index and name both set */
            lg_value v;
            memset(&v, 0, sizeof v);
            v.type = p->type;
            const char *sv = NULL;
            switch (p->type) {
            case LG_PARAM_BOOL: v.b = p->def.b; break;
            case LG_PARAM_INT: v.i = p->def.i; break;
            case LG_PARAM_FLOAT: v.f = p->def.f; break;
            case LG_PARAM_VEC2:
            case LG_PARAM_VEC3:
            case LG_PARAM_COLOR:
                memcpy(v.v, p->def.v, sizeof v.v);
                if (p->type == LG_PARAM_COLOR && p->enum_values) /* keyword index or -1 */
                    v.e = p->def.e;
                break;
            case LG_PARAM_INT3: memcpy(v.i3, p->def.i3, sizeof v.i3); break;
            case LG_PARAM_STRING:
            case LG_PARAM_PATH: sv = p->def.s; break;
            case LG_PARAM_PATH_LIST: break; /* always empty (validate_param) */
            case LG_PARAM_ENUM:
                v.e = p->def.e;
                sv = p->def.s ? p->def.s : p->enum_values[p->def.e];
                for (int e = 0; p->enum_values[e]; e++)
                    if (strcmp(p->enum_values[e], sv) == 0)
                        v.e = e;
                break;
            }
            lg_wire_put_raw(b, &v, sizeof v);
            lg_wire_put_text(b, sv);
            lg_wire_put_raw(b, &p->min, sizeof p->min);
            lg_wire_put_raw(b, &p->max, sizeof p->max);
            put_list(b, p->enum_values);
            lg_wire_put_text(b, p->doc);
            put_list(b, p->renamed_from);
            lg_wire_put_u32(b, p->role);
        }
        for (int io = 0; io < 2; io++) {
            uint32_t n = io ? t->n_outputs : t->n_inputs;
            const lg_port_desc *ports = io ? t->outputs : t->inputs;
            lg_wire_put_u32(b, n);
            for (uint32_t k = 0; k < n; k++) {
                lg_wire_put_text(b, ports[k].name);
                lg_wire_put_u32(b, (uint32_t)ports[k].kind);
                lg_wire_put_u32(b, ports[k].optional);
                lg_wire_put_text(b, ports[k].doc);
            }
        }
    }
}

/* A list put_list wrote: NULL for none, else at most 256 strings, none of them NULL (a
 * NULL would end the list early and leave the rest unowned). */
static const char *const *get_list(lg_wire_reader *r)
{
    uint32_t n = lg_wire_get_u32(r);
    if (n == UINT32_MAX || r->bad)
        return NULL;
    if (n > 256) {
        r->bad = true;
        return NULL;
    }
    char **l = lg_xcalloc(n + 1, sizeof *l);
    for (uint32_t i = 0; i < n && !r->bad; i++)
        if (!(l[i] = lg_wire_get_text(r)))
            r->bad = true;
    return (const char *const *)l;
}

#define DFAIL(...)                                                                                 \
    do {                                                                                           \
        snprintf(err, errlen, __VA_ARGS__);                                                        \
        return -1;                                                                                 \
    } while (0)

/* Decodes what put_desc wrote into p. Each count is set together with its array, so that
 * lg_plugin_free_schema frees a half-decoded p. Returns 0 (r->bad may still be set), or -1
 * with the reason in err. */
static int get_desc(lg_wire_reader *r, lg_plugin *p, char *err, size_t errlen)
{
    char magic[8];
    lg_wire_get_raw(r, magic, 8);
    if (r->bad || memcmp(magic, "LGSCAN2", 8) != 0)
        DFAIL("it does not start with LGSCAN2");
    p->abi_major = (uint16_t)lg_wire_get_u32(r);
    p->abi_minor = (uint16_t)lg_wire_get_u32(r);
    p->name = lg_wire_get_text(r);
    p->version = lg_wire_get_text(r);
    p->doc = lg_wire_get_text(r);
    uint32_t n_types = lg_wire_get_u32(r);
    if (!r->bad && n_types > 1024)
        DFAIL("%u node types, over the limit of 1024", n_types);
    p->types = lg_xcalloc(n_types ? n_types : 1, sizeof *p->types);
    p->n_types = n_types;
    for (uint32_t i = 0; i < n_types && !r->bad; i++) {
        lg_node_type *t = &p->types[i];
        t->struct_size = sizeof *t;
        t->name = lg_wire_get_text(r);
        t->doc = lg_wire_get_text(r);
        t->needs = lg_wire_get_u32(r);
        t->flags = lg_wire_get_u32(r);
        t->neutral = (lg_neutral)lg_wire_get_u32(r);
        t->neutral_input = lg_wire_get_u32(r);
        uint32_t n_params = lg_wire_get_u32(r);
        if (!r->bad && n_params > 256)
            DFAIL("node type %u: %u parameters, over the limit of 256", i, n_params);
        lg_param_desc *params = lg_xcalloc(n_params ? n_params : 1, sizeof *params);
        t->params = params;
        t->n_params = n_params;
        for (uint32_t k = 0; k < n_params && !r->bad; k++) {
            lg_param_desc *q = &params[k];
            q->key = lg_wire_get_text(r);
            q->type = (lg_param_type)lg_wire_get_u32(r);
            /* put_desc wrote a normalised lg_value: take the member the type uses, as a
             * value of its type (a bool byte other than 0 or 1 is not a bool) */
            lg_value raw, def;
            lg_wire_get_raw(r, &raw, sizeof raw);
            memset(&def, 0, sizeof def);
            def.type = q->type;
            switch (q->type) {
            case LG_PARAM_BOOL: {
                unsigned char c;
                memcpy(&c, &raw.b, 1);
                def.b = c != 0;
                break;
            }
            case LG_PARAM_INT: def.i = raw.i; break;
            case LG_PARAM_FLOAT: def.f = raw.f; break;
            case LG_PARAM_VEC2:
            case LG_PARAM_VEC3:
            case LG_PARAM_COLOR:
                memcpy(def.v, raw.v, sizeof def.v);
                if (q->type == LG_PARAM_COLOR)
                    def.e = raw.e; /* the keyword index (validated with the list) */
                break;
            case LG_PARAM_INT3: memcpy(def.i3, raw.i3, sizeof def.i3); break;
            case LG_PARAM_ENUM: def.e = raw.e; break;
            default: break; /* strings: the name follows; unknown types are refused later */
            }
            char *s = lg_wire_get_text(r);
            if (q->type == LG_PARAM_STRING || q->type == LG_PARAM_PATH || q->type == LG_PARAM_ENUM)
                def.s = s;
            else
                free(s);
            q->def = def;
            lg_wire_get_raw(r, &q->min, sizeof q->min);
            lg_wire_get_raw(r, &q->max, sizeof q->max);
            q->enum_values = get_list(r);
            q->doc = lg_wire_get_text(r);
            q->renamed_from = get_list(r);
            q->role = lg_wire_get_u32(r);
        }
        for (int io = 0; io < 2 && !r->bad; io++) {
            uint32_t n = lg_wire_get_u32(r);
            if (!r->bad && n > 64)
                DFAIL("node type %u: %u %s, over the limit of 64", i, n, io ? "outputs" : "inputs");
            lg_port_desc *ports = lg_xcalloc(n ? n : 1, sizeof *ports);
            if (io) {
                t->outputs = ports;
                t->n_outputs = n;
            } else {
                t->inputs = ports;
                t->n_inputs = n;
            }
            for (uint32_t k = 0; k < n && !r->bad; k++) {
                ports[k].name = lg_wire_get_text(r);
                ports[k].kind = (lg_resource_kind)lg_wire_get_u32(r);
                ports[k].optional = lg_wire_get_u32(r) != 0;
                ports[k].doc = lg_wire_get_text(r);
            }
        }
    }
    return 0;
}
#undef DFAIL

lg_plugin_desc lg_plugin_scanned_desc(const lg_plugin *p)
{
    return (lg_plugin_desc){
        .struct_size = sizeof(lg_plugin_desc),
        .abi_major = p->abi_major,
        .abi_minor = p->abi_minor,
        .name = p->name,
        .version = p->version,
        .doc = p->doc,
        .types = p->types,
        .n_types = p->n_types,
    };
}

int lg_registry_decode(const char *buf, size_t n, lg_plugin *p, char *err, size_t errlen)
{
    memset(p, 0, sizeof *p);
    lg_wire_reader r = { buf, buf + n, false };
    char why[512];
    int rc = get_desc(&r, p, why, sizeof why);
    if (rc == 0 && r.bad) {
        snprintf(why, sizeof why, "truncated (%zu bytes)", n);
        rc = -1;
    }
    if (rc == 0 && r.p != r.end) {
        snprintf(why, sizeof why, "%zu bytes after the descriptor", (size_t)(r.end - r.p));
        rc = -1;
    }
    if (rc == 0) {
        /* what the child validated, checked again: the bytes came from a process that ran
         * the plugin's code, which could have written anything to the pipe */
        lg_plugin_desc d = lg_plugin_scanned_desc(p);
        rc = check_desc(&d, false, why, sizeof why);
    }
    if (rc != 0) {
        lg_plugin_free_schema(p);
        snprintf(err, errlen, "malformed scan result: %s", why);
        return -1;
    }
    return 0;
}

void lg_registry_encode(lg_str *b, const lg_plugin_desc *d)
{
    put_desc(b, d);
}

/* ---- scanning -------------------------------------------------------------------------------- */

static void refuse(lg_registry *r, const char *path, const char *reason)
{
    r->refused = lg_xrealloc(r->refused, (r->n_refused + 1) * sizeof *r->refused);
    r->refused[r->n_refused].path = lg_xstrdup(path);
    r->refused[r->n_refused].reason = lg_xstrdup(reason);
    r->n_refused++;
    lg_hlog(LG_HWARN, "refusing plugin %s: %s", path, reason);
}

static void write_all(int fd, const char *p, size_t n)
{
    while (n > 0) {
        ssize_t w = write(fd, p, n);
        if (w < 0 && errno == EINTR)
            continue;
        if (w <= 0)
            return;
        p += w;
        n -= (size_t)w;
    }
}

/* In the child: load, validate, serialise. Status byte 'O' + descriptor, or 'E' + reason. */
static void scan_child(const char *path, int fd)
{
    lg_str b = { 0 };
    char err[512];
    void *h = dlopen(path, RTLD_NOW | RTLD_LOCAL);
    if (!h) {
        const char *e = dlerror();
        lg_str_addf(&b, "Ecannot be loaded: %s", e ? e : "dlopen failed");
    } else {
        lg_plugin_entry_fn entry = (lg_plugin_entry_fn)(uintptr_t)dlsym(h, LG_PLUGIN_ENTRY_NAME);
        if (!entry) {
            lg_str_addf(&b, "Eno '%s' symbol: not a lightgraph plugin", LG_PLUGIN_ENTRY_NAME);
        } else {
            const lg_plugin_desc *d = entry();
            if (lg_descriptor_validate(d, path, err, sizeof err)) {
                lg_str_addf(&b, "E%s", err);
            } else {
                lg_str_addc(&b, 'O');
                put_desc(&b, d);
            }
        }
    }
    write_all(fd, b.s, b.len);
    lg_str_free(&b);
}

/* How long one plugin's scan may take (dlopen with its constructors, the entry point, the
 * validation) before the plugin is refused and its scanner killed: a constructor that blocks
 * must not hang even `lightgraph check`. Scanning one plugin of this repository (fork,
 * dlopen with the OpenCL and GL libraries, serialise) took 20 to 50 ms on a 2-core machine
 * shared by several builds (`lightgraph check GRAPH -v -v` logs each scan's time), so 5 s is
 * a hundred times any honest scan, and short enough that a user facing a blocked plugin
 * sees the refusal rather than a hang. */
#define LG_SCAN_TIMEOUT_DEFAULT 5.0
#define LG_SCAN_TIMEOUT_MAX 3600.0
/* The most a scan result (the serialised descriptor) may be: the largest plugin of this
 * repository (phong) serialises to 4.3 KiB, so 4 MiB leaves room for any real plugin while a
 * descriptor with megabytes of documentation, or a child writing without end, is refused
 * after a bounded read. */
#define LG_SCAN_MAX_BYTES (4u << 20)

/* The scan timeout in seconds: LIGHTGRAPH_SCAN_TIMEOUT if it is a number in
 * (0, LG_SCAN_TIMEOUT_MAX], else the default (a malformed value is reported once). */
static double scan_timeout(void)
{
    static bool warned;
    const char *env = getenv("LIGHTGRAPH_SCAN_TIMEOUT");
    if (!env || !*env)
        return LG_SCAN_TIMEOUT_DEFAULT;
    char *end;
    errno = 0;
    double t = strtod(env, &end);
    if (errno || end == env || *end || !isfinite(t) || !(t > 0) || t > LG_SCAN_TIMEOUT_MAX) {
        if (!warned)
            lg_hlog(LG_HWARN,
                    "LIGHTGRAPH_SCAN_TIMEOUT='%s' is not a number of seconds in (0, %g]; using "
                    "the default %g s",
                    env, LG_SCAN_TIMEOUT_MAX, LG_SCAN_TIMEOUT_DEFAULT);
        warned = true;
        return LG_SCAN_TIMEOUT_DEFAULT;
    }
    return t;
}

/* Waits for the scanner `pid` to end; its wait status. */
static int reap_scanner(pid_t pid)
{
    int status = 0;
    while (waitpid(pid, &status, 0) < 0 && errno == EINTR)
        ;
    return status;
}

/* Starts the scanning child on `path`, which writes its result into the pipe whose read
 * end is *rfd; *t0 is when (lg_mono_now). Returns its pid, or -1 with *why_out (malloc'd). */
static pid_t start_scanner(const char *path, int *rfd, double *t0, char **why_out)
{
    int fds[2];
    if (pipe2(fds, O_CLOEXEC) != 0) {
        *why_out = lg_xstrdup("cannot scan: pipe() failed");
        return -1;
    }
    fflush(NULL);
    *t0 = lg_mono_now();
    pid_t pid = fork();
    if (pid < 0) {
        close(fds[0]);
        close(fds[1]);
        *why_out = lg_xstrdup("cannot scan: fork() failed");
        return -1;
    }
    if (pid == 0) {
        /* a scanner left behind by a host that died (Ctrl-C while a constructor blocks)
         * dies with it */
        prctl(PR_SET_PDEATHSIG, SIGKILL);
        close(fds[0]);
        scan_child(path, fds[1]);
        close(fds[1]);
        _exit(0);
    }
    close(fds[1]);
    *rfd = fds[0];
    return pid;
}

/* Reads the scanner's result from fd into *b until it closes the pipe, `timeout` seconds
 * after t0 have passed, or the result outgrows LG_SCAN_MAX_BYTES. Returns NULL, or why the
 * scanner is to be killed: "time" or "size". */
static const char *read_scan_result(int fd, double t0, double timeout, lg_str *b)
{
    char buf[8192];
    for (;;) {
        double left = timeout - (lg_mono_now() - t0);
        if (left <= 0)
            return "time";
        struct pollfd pfd = { fd, POLLIN, 0 };
        int pr = poll(&pfd, 1, (int)ceil(left * 1e3));
        if (pr < 0 && errno == EINTR)
            continue;
        if (pr < 0)
            return NULL;
        if (pr == 0)
            continue; /* the deadline is checked at the top */
        ssize_t n = read(fd, buf, sizeof buf);
        if (n < 0 && errno == EINTR)
            continue;
        if (n <= 0)
            return NULL;
        if ((size_t)n > LG_SCAN_MAX_BYTES - b->len)
            return "size";
        lg_str_addn(b, buf, (size_t)n);
    }
}

/* What the scanner's wait status and result say: 0 with *out decoded, or -1 with *why_out
 * (malloc'd): it crashed, said nothing, or reported the plugin's refusal ('E' and the
 * reason) or a result that does not decode. */
static int scan_verdict(int status, const lg_str *b, lg_plugin *out, char **why_out)
{
    if (WIFSIGNALED(status)) {
        *why_out = lg_xasprintf("crashed while being scanned (signal %d, %s)", WTERMSIG(status),
                                strsignal(WTERMSIG(status)));
        return -1;
    }
    if (b->len == 0 && WIFEXITED(status) && WEXITSTATUS(status) != 0) {
        /* a sanitizer's handler turns a crash into an exit status */
        *why_out = lg_xasprintf("crashed while being scanned (the scanner exited with "
                                "status %d)",
                                WEXITSTATUS(status));
        return -1;
    }
    if (b->len == 0) {
        *why_out = lg_xstrdup("the scanner produced nothing (the plugin exited while loading?)");
        return -1;
    }
    if (b->s[0] == 'E') {
        *why_out = lg_xstrdup(b->s + 1);
        return -1;
    }
    char bad[600];
    if (lg_registry_decode(b->s + 1, b->len - 1, out, bad, sizeof bad) != 0) {
        *why_out = lg_xstrdup(bad);
        return -1;
    }
    return 0;
}

/* Scans the shared object at `path` in a child process. Returns 0 with *out filled
 * (host-owned schema; path, handle and live zero), or -1 with *why (malloc'd). */
static int scan_file(const char *path, lg_plugin *out, char **why_out)
{
    memset(out, 0, sizeof *out);
    *why_out = NULL;
    /* only a regular file is given to dlopen (a FIFO would block the scanner until its
     * timeout); lightgraph/file.h's check, which opens without blocking */
    char why[256];
    int ffd = lg_file_open(path, UINT64_MAX, NULL, why, sizeof why);
    if (ffd < 0) {
        *why_out = lg_xasprintf("cannot be read: %s", why);
        return -1;
    }
    close(ffd);
    double timeout = scan_timeout();
    double t0;
    int rfd;
    pid_t pid = start_scanner(path, &rfd, &t0, why_out);
    if (pid < 0)
        return -1;
    lg_str b = { 0 };
    const char *killed = read_scan_result(rfd, t0, timeout, &b);
    close(rfd);
    if (killed) {
        kill(pid, SIGKILL);
        reap_scanner(pid);
        *why_out = strcmp(killed, "time") == 0
                       ? lg_xasprintf("its scan did not finish within %g s (a constructor or "
                                      "lg_plugin_entry() that blocks?); the scanner was killed "
                                      "(LIGHTGRAPH_SCAN_TIMEOUT sets the limit, in seconds)",
                                      timeout)
                       : lg_xasprintf("its scan result is larger than the %u MiB limit; the "
                                      "scanner was killed",
                                      LG_SCAN_MAX_BYTES >> 20);
        lg_str_free(&b);
        return -1;
    }
    lg_hlog(LG_HDEBUG, "scanned %s in %.1f ms (%zu bytes of descriptor)", path,
            (lg_mono_now() - t0) * 1e3, b.len);
    int rc = scan_verdict(reap_scanner(pid), &b, out, why_out);
    lg_str_free(&b);
    return rc;
}

/* ---- names: every plugin and node type name once (names.h) ----------------------------------- */

/* A plugin scanned but not yet in the registry. */
typedef struct candidate {
    lg_plugin *p;  /* heap entry, path set */
    bool first;    /* a shipped plugin (names.h) in the program's own plugin directory:
                    * admitted before any other */
    bool admitted; /* first: no other first one took its names (pass 1) */
} candidate;

typedef struct scan_list {
    candidate *c;
    uint32_t n;
} scan_list;

/* Whether a and b may not both be loaded: the same plugin name, or a node type name both
 * declare. Writes why b is refused (a was there first) into why. */
static bool names_clash(const lg_plugin *a, const lg_plugin *b, bool a_first, char *why, size_t n)
{
    const char *first = a_first ? ", one of lightgraph's own plugins, which are taken before "
                                  "any other"
                                : "";
    if (strcmp(a->name, b->name) == 0) {
        snprintf(why, n,
                 "its name '%s' is also the name of the plugin at %s%s; plugin names are "
                 "unique: keep one of the two on the search path (docs/sdk.md \"Names\")",
                 b->name, a->path, first);
        return true;
    }
    for (uint32_t i = 0; i < b->n_types; i++)
        for (uint32_t j = 0; j < a->n_types; j++)
            if (strcmp(a->types[j].name, b->types[i].name) == 0) {
                snprintf(why, n,
                         "its node type '%s' is also declared by the plugin '%s' at %s%s; node "
                         "type names are unique across plugins (a third-party plugin starts "
                         "its types with its vendor prefix, docs/sdk.md \"Names\")",
                         b->types[i].name, a->name, a->path, first);
                return true;
            }
    return false;
}

static void plugin_entry_free(lg_plugin *p);

static void append(lg_registry *r, lg_plugin *p)
{
    r->plugins = lg_xrealloc(r->plugins, (r->n_plugins + 1) * sizeof *r->plugins);
    r->plugins[r->n_plugins++] = p;
}

/* Puts the candidates into the registry, in the order they were found, refusing each whose
 * names another took before it: the shipped plugins of the program's own directory first
 * (pass 1), then everything in search order. A refusal names both files. */
static void admit(lg_registry *r, scan_list *l)
{
    char why[PATH_MAX * 2 + 512];
    for (uint32_t i = 0; i < l->n; i++) {
        candidate *c = &l->c[i];
        if (!c->first)
            continue;
        c->admitted = true;
        for (uint32_t k = 0; k < i && c->admitted; k++)
            if (l->c[k].admitted && names_clash(l->c[k].p, c->p, true, why, sizeof why))
                c->admitted = false;
        if (!c->admitted) {
            refuse(r, c->p->path, why);
            plugin_entry_free(c->p);
            c->p = NULL;
        }
    }
    for (uint32_t i = 0; i < l->n; i++) {
        candidate *c = &l->c[i];
        if (!c->p)
            continue;
        if (c->admitted) {
            append(r, c->p);
            continue;
        }
        bool clash = false;
        for (uint32_t k = 0; k < r->n_plugins && !clash; k++)
            clash = names_clash(r->plugins[k], c->p, false, why, sizeof why);
        for (uint32_t k = i + 1; k < l->n && !clash; k++)
            clash = l->c[k].admitted && names_clash(l->c[k].p, c->p, true, why, sizeof why);
        if (clash) {
            refuse(r, c->p->path, why);
            plugin_entry_free(c->p);
        } else {
            append(r, c->p);
        }
        c->p = NULL;
    }
    free(l->c);
    memset(l, 0, sizeof *l);
}

/* Scans one file into the list. A file already there (the same device and inode, reached
 * through two folders of the path or a link) is scanned once. */
static void scan_one(lg_registry *r, scan_list *l, const char *path, bool own_dir)
{
    struct stat st;
    memset(&st, 0, sizeof st);
    if (stat(path, &st) == 0) {
        for (uint32_t i = 0; i < l->n; i++)
            if (l->c[i].p->dev == (uint64_t)st.st_dev && l->c[i].p->ino == (uint64_t)st.st_ino) {
                lg_hlog(LG_HDEBUG, "%s is %s, scanned once", path, l->c[i].p->path);
                /* a shipped plugin's file reached first through LIGHTGRAPH_PLUGIN_PATH is
                 * still the program's own */
                if (own_dir && lg_shipped_plugin(l->c[i].p->name))
                    l->c[i].first = true;
                return;
            }
        for (uint32_t i = 0; i < r->n_plugins; i++)
            if (r->plugins[i]->dev == (uint64_t)st.st_dev &&
                r->plugins[i]->ino == (uint64_t)st.st_ino)
                return;
    }
    lg_plugin p;
    char *why = NULL;
    if (scan_file(path, &p, &why) != 0) {
        refuse(r, path, why);
        free(why);
        return;
    }
    p.path = lg_xstrdup(path);
    p.dev = (uint64_t)st.st_dev;
    p.ino = (uint64_t)st.st_ino;
    l->c = lg_xrealloc(l->c, (l->n + 1) * sizeof *l->c);
    l->c[l->n].p = lg_xmalloc(sizeof p);
    *l->c[l->n].p = p;
    l->c[l->n].first = own_dir && lg_shipped_plugin(p.name);
    l->c[l->n].admitted = false;
    l->n++;
}

static int cmp_str(const void *a, const void *b)
{
    return strcmp(*(const char *const *)a, *(const char *const *)b);
}

/* The lg_*.so files of `dir` and of its immediate subdirectories (depth 0 -> 1, no deeper),
 * in name order, hidden entries skipped, links followed. */
static void scan_dir(lg_registry *r, scan_list *l, const char *dir, int depth, bool own_dir)
{
    DIR *d = opendir(dir);
    if (!d)
        return;
    char **names = NULL;
    size_t n = 0;
    struct dirent *e;
    while ((e = readdir(d))) {
        if (e->d_name[0] == '.')
            continue;
        names = lg_xrealloc(names, (n + 1) * sizeof *names);
        names[n++] = lg_xstrdup(e->d_name);
    }
    closedir(d);
    if (n > 1) /* qsort(NULL, 0, ...) is undefined (UBSan stops on an empty folder) */
        qsort(names, n, sizeof *names, cmp_str);
    for (size_t i = 0; i < n; i++) {
        char *full = lg_path_join(dir, names[i]);
        struct stat st;
        if (stat(full, &st) == 0) {
            size_t len = strlen(names[i]);
            if (S_ISDIR(st.st_mode) && depth == 0)
                scan_dir(r, l, full, 1, own_dir);
            else if (S_ISREG(st.st_mode) && strncmp(names[i], "lg_", 3) == 0 && len > 3 &&
                     strcmp(names[i] + len - 3, ".so") == 0)
                scan_one(r, l, full, own_dir);
        }
        free(full);
        free(names[i]);
    }
    free(names);
}

static void add_dir(lg_registry *r, const char *dir)
{
    char *abs = lg_path_absolute(dir);
    for (uint32_t i = 0; i < r->n_dirs; i++)
        if (strcmp(r->dirs[i], abs) == 0) {
            free(abs);
            return;
        }
    r->dirs = lg_xrealloc(r->dirs, (r->n_dirs + 1) * sizeof *r->dirs);
    r->dirs[r->n_dirs++] = abs;
}

/* True when this program is the one in the build tree. */
static bool running_from_build_tree(void)
{
    char exe[PATH_MAX], root[PATH_MAX];
    ssize_t n = readlink("/proc/self/exe", exe, sizeof exe - 1);
    if (n <= 0)
        return false;
    exe[n] = 0;
    char *dir = lg_path_dirname(exe);
    bool same = false;
    if (realpath(LG_BUILD_ROOT, root)) {
        char rd[PATH_MAX];
        same = realpath(dir, rd) && strcmp(rd, root) == 0;
        /* tests and tools built in the tree run from its subdirectories */
        if (!same && realpath(dir, rd)) {
            size_t rl = strlen(root);
            same = strncmp(rd, root, rl) == 0 && rd[rl] == '/';
        }
    }
    free(dir);
    return same;
}

/* The installed plugins (absolute, malloc'd): <the program's folder>/LG_PLUGIN_DIR_FROM_BIN
 * when that folder exists, so that a prefix installed with --destdir or moved finds its own
 * plugins and not another installation's; else the prefix's folder compiled in (a prefix
 * that is not relocatable: LG_PLUGIN_DIR_FROM_BIN is ""). */
static char *installed_plugin_dir(void)
{
    char exe[PATH_MAX];
    ssize_t n = *LG_PLUGIN_DIR_FROM_BIN ? readlink("/proc/self/exe", exe, sizeof exe - 1) : -1;
    if (n > 0) {
        exe[n] = 0;
        char *dir = lg_path_dirname(exe);
        size_t len = strlen(dir) + sizeof LG_PLUGIN_DIR_FROM_BIN + 1;
        char *plugins = lg_xmalloc(len);
        snprintf(plugins, len, "%s/%s", dir, LG_PLUGIN_DIR_FROM_BIN);
        free(dir);
        struct stat st;
        if (stat(plugins, &st) == 0 && S_ISDIR(st.st_mode)) {
            char *abs = lg_path_absolute(plugins);
            free(plugins);
            return abs;
        }
        free(plugins);
    }
    return lg_path_absolute(LG_INSTALL_PLUGIN_DIR);
}

static void finish_names(lg_registry *r)
{
    free(r->names);
    r->n_names = 0;
    for (uint32_t i = 0; i < r->n_plugins; i++)
        r->n_names += r->plugins[i]->n_types;
    r->names = lg_xcalloc(r->n_names ? r->n_names : 1, sizeof *r->names);
    uint32_t k = 0;
    for (uint32_t i = 0; i < r->n_plugins; i++)
        for (uint32_t j = 0; j < r->plugins[i]->n_types; j++)
            r->names[k++] = r->plugins[i]->types[j].name;
}

int lg_registry_scan(lg_registry *r)
{
    const char *env = getenv("LIGHTGRAPH_PLUGIN_PATH");
    if (env && *env) {
        char *copy = lg_xstrdup(env);
        for (char *save = NULL, *tok = strtok_r(copy, ":", &save); tok;
             tok = strtok_r(NULL, ":", &save))
            if (*tok)
                add_dir(r, tok);
        free(copy);
    }
    /* The program's own plugins: the build tree's when it runs from there, else the
     * installed ones, found from the program's own file. A program of the build tree does
     * not look at an installed lightgraph's plugins: they may be of another version, and
     * each would clash with its twin here. */
    char *own = running_from_build_tree() ? lg_path_absolute(LG_BUILD_PLUGIN_DIR)
                                          : installed_plugin_dir();
    add_dir(r, own);
    scan_list l = { 0 };
    for (uint32_t i = 0; i < r->n_dirs; i++)
        scan_dir(r, &l, r->dirs[i], 0, strcmp(r->dirs[i], own) == 0);
    free(own);
    admit(r, &l);
    finish_names(r);
    return 0;
}

int lg_registry_scan_files(lg_registry *r, char **paths, uint32_t n)
{
    scan_list l = { 0 };
    for (uint32_t i = 0; i < n; i++) {
        char *abs = lg_path_absolute(paths[i]);
        scan_one(r, &l, abs, false);
        free(abs);
    }
    admit(r, &l);
    finish_names(r);
    return 0;
}

int lg_registry_add_builtin(lg_registry *r, const lg_plugin_desc *d, const char *path, char *err,
                            size_t errlen)
{
    if (lg_descriptor_validate(d, path, err, errlen))
        return -1;
    /* unique names, as for any plugin: a scanned plugin that declares one of these types
     * keeps it, and the program's plugin is refused */
    for (uint32_t i = 0; i < d->n_types; i++) {
        lg_plugin *other = NULL;
        if (lg_registry_lookup(r, d->types[i].name, &other)) {
            snprintf(err, errlen, "node type '%s' of %s is declared by plugin '%s' (%s) too",
                     d->types[i].name, path, other->name, other->path);
            return -1;
        }
    }
    /* the same host-owned schema copy a scan makes, so that everything downstream (the
     * checker, the planner, lg_registry_load's comparison) treats it as any plugin */
    lg_str b = { 0 };
    put_desc(&b, d);
    lg_plugin p;
    int rc = lg_registry_decode(b.s, b.len, &p, err, errlen);
    lg_str_free(&b);
    if (rc)
        return -1;
    p.path = lg_xstrdup(path);
    p.handle = (void *)d;
    p.live = d;
    p.builtin = true;
    r->plugins = lg_xrealloc(r->plugins, (r->n_plugins + 1) * sizeof *r->plugins);
    r->plugins[r->n_plugins] = lg_xmalloc(sizeof p);
    *r->plugins[r->n_plugins++] = p;
    finish_names(r);
    return 0;
}

const lg_node_type *lg_registry_lookup(const lg_registry *r, const char *type, lg_plugin **plugin)
{
    for (uint32_t i = 0; i < r->n_plugins; i++)
        for (uint32_t j = 0; j < r->plugins[i]->n_types; j++)
            if (strcmp(r->plugins[i]->types[j].name, type) == 0) {
                if (plugin)
                    *plugin = r->plugins[i];
                return &r->plugins[i]->types[j];
            }
    return NULL;
}

static const lg_node_type *schema_lookup(void *ctx, const char *name)
{
    return lg_registry_lookup(ctx, name, NULL);
}

void lg_registry_schema(const lg_registry *r, lg_schema *out)
{
    out->ctx = (void *)r;
    out->lookup = schema_lookup;
    out->n_names = r->n_names;
    out->names = r->names;
    out->max_pixels = 0; /* the caller sets the pixel limit in force (lg_image_max_pixels) */
}

static int reload_dir(lg_registry *r, char *err, size_t errlen);
static int copy_file(const char *src, const char *dst, char *err, size_t errlen);
static char *private_copy_path(lg_registry *r, const char *path);

int lg_registry_load(lg_registry *r, lg_plugin *p, char *err, size_t errlen)
{
    if (p->handle)
        return 0;
    if (r->private_copies && !p->load_path) {
        if (reload_dir(r, err, errlen))
            return -1;
        char *copy = private_copy_path(r, p->path);
        if (copy_file(p->path, copy, err, errlen)) {
            free(copy);
            return -1;
        }
        p->load_path = copy;
    }
    void *h = dlopen(p->load_path ? p->load_path : p->path, RTLD_NOW | RTLD_LOCAL);
    if (!h) {
        const char *e = dlerror();
        snprintf(err, errlen, "plugin %s: cannot be loaded: %s", p->path, e ? e : "?");
        return -1;
    }
    lg_plugin_entry_fn entry = (lg_plugin_entry_fn)(uintptr_t)dlsym(h, LG_PLUGIN_ENTRY_NAME);
    const lg_plugin_desc *d = entry ? entry() : NULL;
    char why[512];
    if (!entry || lg_descriptor_validate(d, p->path, why, sizeof why)) {
        snprintf(err, errlen, "plugin %s: %s", p->path, entry ? why : "no entry symbol");
        dlclose(h);
        return -1;
    }
    /* The file may have been rebuilt since the scan: the schema the graph was checked
     * against must be the one that runs. */
    lg_str a = { 0 }, b = { 0 };
    put_desc(&a, d);
    bool same = strcmp(d->name, p->name) == 0 && d->n_types == p->n_types;
    if (same) {
        lg_plugin_desc shadow = *d;
        shadow.types = p->types;
        shadow.name = p->name;
        shadow.version = p->version;
        shadow.doc = p->doc;
        shadow.abi_major = p->abi_major;
        shadow.abi_minor = p->abi_minor;
        put_desc(&b, &shadow);
        same = a.len == b.len && memcmp(a.s, b.s, a.len) == 0;
    }
    lg_str_free(&a);
    lg_str_free(&b);
    if (!same) {
        snprintf(err, errlen, "plugin %s changed between scanning and loading; run again", p->path);
        dlclose(h);
        return -1;
    }
    p->handle = h;
    p->live = d;
    lg_hlog(LG_HDEBUG, "loaded plugin %s (%s)", p->name, p->path);
    return 0;
}

const lg_node_type *lg_plugin_live_type(const lg_plugin *p, const char *type)
{
    if (!p->live)
        return NULL;
    for (uint32_t i = 0; i < p->live->n_types; i++)
        if (strcmp(p->live->types[i].name, type) == 0)
            return &p->live->types[i];
    return NULL;
}

typedef struct loaded_ctx {
    const lg_registry *r;
    lg_str *out;
} loaded_ctx;

static int phdr_cb(struct dl_phdr_info *info, size_t size, void *data)
{
    (void)size;
    loaded_ctx *c = data;
    if (!info->dlpi_name || !info->dlpi_name[0])
        return 0;
    for (uint32_t i = 0; i < c->r->n_plugins; i++) {
        char a[PATH_MAX], b[PATH_MAX];
        if (realpath(info->dlpi_name, a) && realpath(c->r->plugins[i]->path, b) &&
            strcmp(a, b) == 0)
            lg_str_addf(c->out, "%s%s", c->out->len ? " " : "", c->r->plugins[i]->name);
    }
    return 0;
}

char *lg_registry_loaded_list(const lg_registry *r)
{
    lg_str out = { 0 };
    loaded_ctx c = { r, &out };
    dl_iterate_phdr(phdr_cb, &c);
    return lg_str_take(&out);
}

static void free_list(const char *const *l)
{
    if (!l)
        return;
    for (int i = 0; l[i]; i++)
        free((char *)l[i]);
    free((void *)l);
}

void lg_plugin_free_schema(lg_plugin *p)
{
    for (uint32_t j = 0; j < p->n_types; j++) {
        lg_node_type *t = &p->types[j];
        for (uint32_t k = 0; k < t->n_params; k++) {
            lg_param_desc *q = (lg_param_desc *)&t->params[k];
            free((char *)q->key);
            free((char *)q->doc);
            if (q->type == LG_PARAM_STRING || q->type == LG_PARAM_PATH || q->type == LG_PARAM_ENUM)
                free((char *)q->def.s);
            free_list(q->enum_values);
            free_list(q->renamed_from);
        }
        free((void *)t->params);
        for (uint32_t k = 0; k < t->n_inputs; k++) {
            free((char *)t->inputs[k].name);
            free((char *)t->inputs[k].doc);
        }
        for (uint32_t k = 0; k < t->n_outputs; k++) {
            free((char *)t->outputs[k].name);
            free((char *)t->outputs[k].doc);
        }
        free((void *)t->inputs);
        free((void *)t->outputs);
        free((char *)t->name);
        free((char *)t->doc);
    }
    free(p->types);
    free(p->name);
    free(p->version);
    free(p->doc);
    p->types = NULL;
    p->n_types = 0;
    p->name = p->version = p->doc = NULL;
}

static void plugin_entry_free(lg_plugin *p)
{
    lg_plugin_free_schema(p);
    /* Plugins stay loaded until every object they made is gone; by the time the
     * registry is freed the executor has destroyed them all. LIGHTGRAPH_NO_DLCLOSE keeps
     * them mapped, so that a leak checker can still name their functions. A plugin that
     * crashed may have left anything behind: it stays mapped. */
    if (p->handle && !p->builtin && p->live_refs == 0 && !p->poisoned &&
        !getenv("LIGHTGRAPH_NO_DLCLOSE"))
        dlclose(p->handle);
    if (p->load_path)
        unlink(p->load_path);
    free(p->load_path);
    free(p->path);
    free(p);
}

void lg_registry_free(lg_registry *r)
{
    for (uint32_t i = 0; i < r->n_plugins; i++)
        plugin_entry_free(r->plugins[i]);
    free(r->plugins);
    for (uint32_t i = 0; i < r->n_retired; i++)
        plugin_entry_free(r->retired[i]);
    free(r->retired);
    if (r->reload_dir)
        rmdir(r->reload_dir);
    free(r->reload_dir);
    for (uint32_t i = 0; i < r->n_refused; i++) {
        free(r->refused[i].path);
        free(r->refused[i].reason);
    }
    free(r->refused);
    free(r->names);
    for (uint32_t i = 0; i < r->n_dirs; i++)
        free(r->dirs[i]);
    free(r->dirs);
    memset(r, 0, sizeof *r);
}

/* ---- the viewer's reloads -------------------------------------------------------------------- */

lg_plugin *lg_registry_find_path(const lg_registry *r, const char *path)
{
    for (uint32_t i = 0; i < r->n_plugins; i++)
        if (strcmp(r->plugins[i]->path, path) == 0)
            return r->plugins[i];
    return NULL;
}

/* Copies `src` to `dst` (a new file). Returns 0 or -1 with err. */
static int copy_file(const char *src, const char *dst, char *err, size_t errlen)
{
    char why[256];
    int in = lg_file_open(src, UINT64_MAX, NULL, why, sizeof why);
    if (in < 0) {
        snprintf(err, errlen, "%s cannot be read: %s", src, why);
        return -1;
    }
    int out = open(dst, O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0700);
    if (out < 0) {
        snprintf(err, errlen, "cannot create %s: %s", dst, strerror(errno));
        close(in);
        return -1;
    }
    char buf[65536];
    int rc = 0;
    for (;;) {
        ssize_t n = read(in, buf, sizeof buf);
        if (n < 0 && errno == EINTR)
            continue;
        if (n < 0) {
            snprintf(err, errlen, "reading %s: %s", src, strerror(errno));
            rc = -1;
            break;
        }
        if (n == 0)
            break;
        for (ssize_t off = 0; off < n;) {
            ssize_t w = write(out, buf + off, (size_t)(n - off));
            if (w < 0 && errno == EINTR)
                continue;
            if (w < 0) {
                snprintf(err, errlen, "writing %s: %s", dst, strerror(errno));
                rc = -1;
                break;
            }
            off += w;
        }
        if (rc)
            break;
    }
    if (close(out) != 0 && rc == 0) {
        snprintf(err, errlen, "writing %s: %s", dst, strerror(errno));
        rc = -1;
    }
    close(in);
    if (rc)
        unlink(dst);
    return rc;
}

/* The registry's private directory for plugin copies, made on first use. */
static int reload_dir(lg_registry *r, char *err, size_t errlen)
{
    if (r->reload_dir)
        return 0;
    const char *tmp = getenv("TMPDIR");
    char *tmpl = lg_xasprintf("%s/lightgraph-reload-XXXXXX", tmp && *tmp ? tmp : "/tmp");
    if (!mkdtemp(tmpl)) {
        snprintf(err, errlen, "cannot make a directory for plugin copies (%s): %s", tmpl,
                 strerror(errno));
        free(tmpl);
        return -1;
    }
    r->reload_dir = tmpl;
    return 0;
}

/* DIR/lg_name.N.so, a new name for every copy. */
static char *private_copy_path(lg_registry *r, const char *path)
{
    const char *base = strrchr(path, '/');
    base = base ? base + 1 : path;
    size_t blen = strlen(base);
    if (blen > 3 && strcmp(base + blen - 3, ".so") == 0)
        blen -= 3;
    return lg_xasprintf("%s/%.*s.%u.so", r->reload_dir, (int)blen, base, ++r->reloads);
}

int lg_registry_rescan(lg_registry *r, const char *path, lg_plugin **fresh, lg_plugin **old,
                       char *err, size_t errlen)
{
    *fresh = NULL;
    *old = lg_registry_find_path(r, path);
    if (reload_dir(r, err, errlen))
        return -1;
    char *copy = private_copy_path(r, path);
    if (copy_file(path, copy, err, errlen) != 0) {
        free(copy);
        return -1;
    }
    lg_plugin p;
    char *why = NULL;
    if (scan_file(copy, &p, &why) != 0) {
        snprintf(err, errlen, "plugin %s is refused: %s", path, why);
        free(why);
        unlink(copy);
        free(copy);
        return -1;
    }
    p.path = lg_xstrdup(path);
    for (uint32_t i = 0; i < r->n_plugins; i++) {
        char reason[PATH_MAX * 2 + 512];
        if (r->plugins[i] != *old && names_clash(r->plugins[i], &p, false, reason, sizeof reason)) {
            snprintf(err, errlen, "plugin %s is refused: %s", path, reason);
            lg_plugin_free_schema(&p);
            free(p.path);
            unlink(copy);
            free(copy);
            return -1;
        }
    }
    p.load_path = copy;
    *fresh = lg_xmalloc(sizeof p);
    **fresh = p;
    return 0;
}

void lg_registry_replace(lg_registry *r, lg_plugin *from, lg_plugin *to)
{
    /* `to` may come back from the retired entries (a rollback) */
    for (uint32_t i = 0; to && i < r->n_retired; i++)
        if (r->retired[i] == to) {
            r->retired[i] = r->retired[--r->n_retired];
            break;
        }
    uint32_t at = r->n_plugins;
    for (uint32_t i = 0; from && i < r->n_plugins; i++)
        if (r->plugins[i] == from)
            at = i;
    if (at == r->n_plugins) {
        if (to) {
            r->plugins = lg_xrealloc(r->plugins, (r->n_plugins + 1) * sizeof *r->plugins);
            r->plugins[r->n_plugins++] = to;
        }
    } else if (to) {
        r->plugins[at] = to;
    } else {
        memmove(&r->plugins[at], &r->plugins[at + 1], (r->n_plugins - at - 1) * sizeof *r->plugins);
        r->n_plugins--;
    }
    if (from) {
        r->retired = lg_xrealloc(r->retired, (r->n_retired + 1) * sizeof *r->retired);
        r->retired[r->n_retired++] = from;
    }
    finish_names(r);
}
