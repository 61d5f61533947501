/*
 * host/viewer/params.h: live parameters, overrides and method switching for `lightgraph
 * view` (private to the host; issue 12 item 3).
 *
 * Nothing here changes a graph. Every edit is produced as an assignment "NODE.KEY=VALUE"
 * in the form --set takes; the viewer applies it with lg_graph_set() and checks it with
 * lg_graph_check() exactly as the command line's --set, so a rejected value is reported by
 * the checker with its usual message. This module only decides which value comes next.
 *
 * A viewer session goes:
 *
 *     lg_vparams *vp = lg_vparams_new();
 *     lg_overrides ov = {0};
 *     lg_vparams_sync(vp, g, c, kept);            after every (re)check
 *     lg_vparams_next_node(vp, +1);               keys
 *     char *a = lg_vparams_step(vp, g, c, +1, 1.0, err, sizeof err);
 *     if (a) { lg_overrides_set(&ov, a); ...re-parse, apply every ov.items with
 *              lg_graph_set, check; if that fails: lg_overrides_remove_last(&ov)... }
 *     char *args = lg_overrides_args(&ov);        print
 *     lg_overrides_free(&ov); lg_vparams_free(vp);
 *
 * Values are printed so that the checker reads them back as the same value: floats with
 * %.9g (or %.17g when the shorter text would fall outside the parameter's range), vectors
 * as "[x, y, z]", enum values and keywords as their bare names, references as NODE (a node
 * with one output) or NODE.PORT.
 *
 * Not thread-safe; the viewer calls everything from its main thread.
 */
#ifndef LG_HOST_VIEWER_PARAMS_H
#define LG_HOST_VIEWER_PARAMS_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "graph/graph.h"
#include "base/util.h"

/* ---- the selection --------------------------------------------------------------------------- */

/* One editable entry of a node: a parameter, one component of a vec2/vec3/color/int3
 * parameter, or an input port (its value is a reference NODE[.PORT] to a compatible
 * source). A colour that also takes keywords (lg_param_desc.enum_values on an
 * LG_PARAM_COLOR) has one more entry, component -1, listed before its components: it
 * cycles through the keywords and a colour. */
typedef enum lg_vp_kind { LG_VP_PARAM, LG_VP_INPUT } lg_vp_kind;
typedef struct lg_vp_entry {
    lg_vp_kind kind;
    uint32_t index; /* parameter or input index in the node type */
    int component;  /* -1, or 0..2 for a vector component */
} lg_vp_entry;

/* The selectable nodes and entries with the current selection. Owns copies of the names
 * it keeps, so that it outlives the graph it was synced with. */
typedef struct lg_vparams lg_vparams;

lg_vparams *lg_vparams_new(void);    /* never NULL */
void lg_vparams_free(lg_vparams *p); /* NULL ok */

/* Rebuilds the selectable list from a checked graph `c` of `g`: the nodes with `offer[i]`
 * true (offer has c->n_nodes items; the viewer passes the nodes the plan kept; NULL: all
 * nodes), in file order, each with its entries: every parameter but strings, paths and
 * path lists, vectors and colours split into components; then the inputs that are
 * connected. A node without any entry is not listed.
 *
 * The selection stays on the node of the same name and on its entry of the same kind, key
 * and component when they still exist; else on the entry with the same key, else the
 * entry at the same position (or the last); a node that is gone gives way to the listed
 * node nearest to where it was in the file. The first sync selects the first entry of the
 * first node. */
void lg_vparams_sync(lg_vparams *p, const lg_graph *g, const lg_checked *c, const bool *offer);

/* Moves the selection to the next (dir +1) or previous (-1) node, cyclic; the entry goes
 * to the one with the same key in the new node when there is one, else the first. */
void lg_vparams_next_node(lg_vparams *p, int dir);
/* Moves to the next or previous entry within the selected node, cyclic. */
void lg_vparams_next_entry(lg_vparams *p, int dir);
/* Selects the node's first entry (its first parameter). */
void lg_vparams_first_entry(lg_vparams *p);

/* The selected node's name (owned by p, valid until the next sync or free), or NULL when
 * nothing is selected. */
const char *lg_vparams_node(const lg_vparams *p);
/* The selected node's index in the graph last synced and its selected entry; false when
 * nothing is selected. */
bool lg_vparams_selected(const lg_vparams *p, int32_t *node, lg_vp_entry *entry);

/* The assignment that steps the selected entry by one step in `dir` (+1/-1) at `scale`
 * (1 normal, 10 coarse, 0.1 fine), as a malloc'd "node.key=value" (the caller frees it);
 * NULL with the reason in err when it cannot move: at the end of the range ("lit.ks_scale
 * is at its maximum 1000"), nothing selected, no other compatible source, a keyword colour
 * whose component is asked for, or `c` not the graph last synced. `g` and `c` must be the
 * graph and check last given to lg_vparams_sync.
 *
 *  - int (and an int3 component): +-1 x scale (at least 1), clamped to [min, max];
 *  - float (and a vec2/vec3/color component): (max - min)/100 when both bounds are finite
 *    and the range is under 1e4 wide, else 10% of |value| (0.1 at 0), times scale, clamped
 *    to the range (min == max: no range);
 *  - enum: the next/previous value, cyclic;
 *  - a keyword colour's own entry (component -1): the next/previous of its keywords and,
 *    after the last keyword, a colour (the default colour when the default is one, else
 *    the middle of the range, else white), cyclic;
 *  - bool: toggles (dir does not matter);
 *  - vector component: that component stepped, the whole vector printed;
 *  - input: the next/previous (node, output port) in file order, cyclic, whose kind the
 *    input takes (LG_KIND_ANY on either side matches any), leaving out the node itself
 *    and every node downstream of it (a cycle); never a part reference (NODE.PART).
 */
char *lg_vparams_step(const lg_vparams *p, const lg_graph *g, const lg_checked *c, int dir,
                      double scale, char *err, size_t errlen);

/* One line for the overlay, appended to `out`:
 *     "lit (phong) 3/9  shading = phong  {flat gouraud phong mixed phong_half}"
 *     "lit (phong) 5/9  ambient[1] = 0.3 of [0.3, 0.3, 0.3]  [0, 1e+06]"
 *     "lit (phong) 9/9  image <- src  (image)"
 * the node, its type, the entry's position in the node, the value ("(default)" when the
 * graph does not set it) and the choices or the range. `c` is the check last synced;
 * "nothing to edit" when nothing is selected. */
void lg_vparams_describe(const lg_vparams *p, const lg_checked *c, lg_str *out);

/* ---- method switching ------------------------------------------------------------------------ */

/* Method switching (issue 12 item 3, the volumetric thesis's menu). Two nodes are
 * alternatives when they differ in node type or in a parameter value, have output ports
 * with the same names and kinds, and read the same sources (the same set of connected
 * input edges: node, port, part). Walking upstream from node `shown` (breadth first,
 * `shown` itself first, inputs in their order), the first node X with at least one
 * alternative is switched: every input of every node that reads X.port is rewired to the
 * next (dir +1) or previous (-1) alternative Y.port, in file order, cyclic among X and its
 * alternatives.
 *
 * Returns 1 when it switched: *assignments is a malloc'd array of *n malloc'd
 * "consumer.input=Y.port" strings (free each and the array; *n may be 0 when X is `shown`
 * and nothing else reads it), *switched_from is X and *switched_to Y (node indices), and
 * *new_shown is Y when X is `shown` (the viewer then shows Y.port instead), else -1.
 * Returns 0 with the reason in err ("no node upstream of 'tone' has an alternative: ...")
 * and *assignments NULL, *n 0 when nothing can switch. */
int lg_vparams_switch_method(const lg_graph *g, const lg_checked *c, int32_t shown, int dir,
                             char ***assignments, uint32_t *n, int32_t *switched_from,
                             int32_t *switched_to, int32_t *new_shown, char *err, size_t errlen);

/* Method "off" (issue 24; the thesis's menu has it): the image without a method, the
 * method's own input passed through. Node x's stand-in for its output `port` is the first
 * connected input of x whose source output has that output's kind (the volumetric methods'
 * `base`, the lit image they draw over), read as a whole (not a part). Returns 1 with the
 * source in *src, else 0 (x has no such input: its method cannot be switched off). */
int lg_vparams_passthrough(const lg_checked *c, int32_t x, uint32_t port, lg_edge *src);
/* The reference "NODE" or "NODE.PORT" (a part: "NODE.PART") that names edge e in a --set,
 * malloc'd; NULL when a part has no name of its own on its node. */
char *lg_vparams_edge_ref(const lg_checked *c, lg_edge e);
/* Among x and its alternatives, in file order: the first (dir >= 0) or the last (dir < 0).
 * M after "off" switches that one on. x itself when it has none. */
int32_t lg_vparams_alternative_end(const lg_checked *c, int32_t x, int dir);

/* ---- overrides ------------------------------------------------------------------------------- */

/* The overrides made so far, in the order first set: setting NODE.KEY again replaces it
 * in place. Zero-initialise (`lg_overrides o = {0};`); items are owned by the struct. The
 * fields after `n` are private: they remember what each set replaced, so that
 * lg_overrides_remove_last can undo the last LG_OVERRIDES_UNDO sets, newest first. */
#define LG_OVERRIDES_UNDO 256
typedef struct lg_overrides {
    char **items; /* "node.key=value", as given to lg_overrides_set */
    uint32_t n;
    uint32_t cap;
    struct lg_override_undo *undo; /* private */
    uint32_t n_undo, cap_undo;
} lg_overrides;

/* Adds a copy of `assignment` ("node.key=value"; the key is the text before the first
 * '=', spaces around it ignored), or replaces the item with the same key in place. */
void lg_overrides_set(lg_overrides *o, const char *assignment);
/* Undoes the last lg_overrides_set not yet undone (a rejected change): the item it added
 * is removed, or the value it replaced is back. Nothing to undo: does nothing. */
void lg_overrides_remove_last(lg_overrides *o);
/* "--set lit.shading=flat --set 'sun.direction=[0.4, -0.25, 1]'": each item shell-quoted
 * (in single quotes) when it holds anything but letters, digits and _ . , = / : + @ % -;
 * "" when there is none. Malloc'd, never NULL. */
char *lg_overrides_args(const lg_overrides *o);
void lg_overrides_free(lg_overrides *o); /* frees everything and zeroes *o */

#endif
