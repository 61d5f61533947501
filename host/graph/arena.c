/*
 * host/graph/arena.c: the arena a graph's strings and arrays live in, and a string -> index
 * map (node names, a node's keys). Generic; parse_priv.h says how to use them.
 */
#include "graph/parse_priv.h"

#include <stdlib.h>
#include <string.h>

#include "base/util.h"

/* ---- arena ----------------------------------------------------------------------------------- */

void *lg_arena_alloc(arena *a, size_t n)
{
    const size_t align = _Alignof(max_align_t);
    n = (n + align - 1) & ~(align - 1);
    if (!a->head || a->head->cap - a->head->used < n) {
        size_t cap = n > 32768 ? n : 32768;
        ablock *b = lg_xmalloc(sizeof *b + cap);
        b->used = 0;
        b->cap = cap;
        b->next = a->head;
        a->head = b;
    }
    void *p = (char *)a->head->data + a->head->used;
    a->head->used += n;
    return p;
}

void *lg_arena_zalloc(arena *a, size_t n)
{
    void *p = lg_arena_alloc(a, n);
    memset(p, 0, n);
    return p;
}

char *lg_arena_strndup(arena *a, const char *s, size_t n)
{
    char *p = lg_arena_alloc(a, n + 1);
    memcpy(p, s, n);
    p[n] = 0;
    return p;
}

char *lg_arena_strdup(arena *a, const char *s)
{
    return lg_arena_strndup(a, s, strlen(s));
}

void *lg_arena_copy(arena *a, const void *p, size_t n)
{
    if (n == 0)
        return NULL;
    void *q = lg_arena_alloc(a, n);
    memcpy(q, p, n);
    return q;
}

void lg_arena_free(arena *a)
{
    for (ablock *b = a->head, *next; b; b = next) {
        next = b->next;
        free(b);
    }
    a->head = NULL;
}

/* ---- a string -> index map (open addressing) ------------------------------------------------- */

uint32_t lg_strmap_find(const strmap *m, const char *key)
{
    if (m->cap == 0)
        return STRMAP_NONE;
    uint32_t i = (uint32_t)lg_hash64(key, strlen(key), 0) & (m->cap - 1);
    while (m->keys[i]) {
        if (strcmp(m->keys[i], key) == 0)
            return m->vals[i];
        i = (i + 1) & (m->cap - 1);
    }
    return STRMAP_NONE;
}

void lg_strmap_put(strmap *m, const char *key, uint32_t val)
{
    if ((m->n + 1) * 2 > m->cap) {
        strmap old = *m;
        m->cap = old.cap ? old.cap * 2 : 16;
        m->keys = lg_xcalloc(m->cap, sizeof *m->keys);
        m->vals = lg_xcalloc(m->cap, sizeof *m->vals);
        m->n = 0;
        for (uint32_t i = 0; i < old.cap; i++)
            if (old.keys[i])
                lg_strmap_put(m, old.keys[i], old.vals[i]);
        free(old.keys);
        free(old.vals);
    }
    uint32_t i = (uint32_t)lg_hash64(key, strlen(key), 0) & (m->cap - 1);
    while (m->keys[i]) {
        if (strcmp(m->keys[i], key) == 0) {
            m->vals[i] = val;
            return;
        }
        i = (i + 1) & (m->cap - 1);
    }
    m->keys[i] = key;
    m->vals[i] = val;
    m->n++;
}

void lg_strmap_free(strmap *m)
{
    free(m->keys);
    free(m->vals);
    memset(m, 0, sizeof *m);
}
