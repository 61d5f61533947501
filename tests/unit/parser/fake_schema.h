/*
 * tests/unit/parser/fake_schema.h: a few node types declared as plugins declare them, for
 * the parser tests and the graph fuzzer (no plugin is loaded).
 *
 *   image    { file: path }                                     -> out (image)
 *   reinhard { key: float [0.001, 100], white: float [0, 1e6],
 *              mode: enum {rgb, luminance}, backend: enum {cpu, gl, cl},
 *              exposure: float (renamed from 'gain'), image <- image } -> out (image)
 *   add      { a <- image, b <- image }                         -> out (image)
 *   scene    { file: path }                                     -> scene (scene)
 *   gbuffer  { scene <- scene }                                 -> color, depth (image)
 *   blur     { radius: int [0, 64], offset: vec2 [-10, 10], tint: color [0, 1],
 *              grid: int3 [1, 512], enabled: bool, label: string, image <- image,
 *              mask <- any (optional) }                          -> out (image)
 *   sink     { image <- image (optional) }                       (no outputs)
 */
#ifndef LG_TEST_FAKE_SCHEMA_H
#define LG_TEST_FAKE_SCHEMA_H

#include "graph/graph.h"

/* A schema over the types above; lookup is a linear search by name. */
const lg_schema *lg_fake_schema(void);

#endif
