/*
 * lightgraph/lightgraph.h: the whole plugin SDK but for the optional device headers.
 *
 *   lightgraph/config.h   ABI version, export macros (generated)
 *   lightgraph/types.h    error codes, resource kinds, formats, devices, scene features
 *   lightgraph/plugin.h   the plugin descriptor: node types, parameters, ports, callbacks
 *   lightgraph/host.h     the host's services: parameters, resources, devices, cache, log
 *   lightgraph/image.h    images in memory and in files (EXR, HDR, PNG), metrics
 *   lightgraph/file.h     bounded, confined reads of regular files (every loader's rules)
 *   lightgraph/color.h    luminance and colour helpers
 *   lightgraph/vecmath.h  vectors and 4x4 matrices (column-major)
 *   lightgraph/scene.h    the scene resource: meshes, instances, materials, lights, cameras
 *   lightgraph/kinds.h    resource kinds and their parts (composite resources)
 *   lightgraph/shadowmap.h  shadow maps: a depth atlas and each light's matrices
 *   lightgraph/probe.h    light probes: radiance with its layout, solid angles
 *   lightgraph/shcoeffs.h SH coefficients (n bands x RGB)
 *   lightgraph/transfer.h per-vertex PRT transfer vectors
 *   lightgraph/froxel.h   froxel volumes with their slice map
 *   lightgraph/gl.h       OpenGL 4.5 through the SDK's loader (optional)
 *   lightgraph/cl.h       OpenCL (optional)
 *   lightgraph/scene_gl.h a scene rasterised on GL: camera matrices, instances, draw loop
 *                         (optional, includes gl.h)
 *   lightgraph/gl_pass.h  a GL raster or compute pass made once and run every frame:
 *                         program, uniforms by name, framebuffer, scene draw data, state
 *                         set and restored (optional, includes gl.h and scene_gl.h)
 *
 * docs/sdk.md is the plugin author's guide.
 */
#ifndef LIGHTGRAPH_LIGHTGRAPH_H
#define LIGHTGRAPH_LIGHTGRAPH_H

#include "lightgraph/config.h"
#include "lightgraph/types.h"
#include "lightgraph/plugin.h"
#include "lightgraph/host.h"
#include "lightgraph/image.h"
#include "lightgraph/file.h"
#include "lightgraph/color.h"
#include "lightgraph/vecmath.h"
#include "lightgraph/scene.h"
#include "lightgraph/kinds.h"
#include "lightgraph/shadowmap.h"
#include "lightgraph/probe.h"
#include "lightgraph/shcoeffs.h"
#include "lightgraph/transfer.h"
#include "lightgraph/froxel.h"

#endif
