#version 450
// shaders/volumetric_froxel/froxel_accum.comp: PLACEHOLDER (helper D writes the GL backend;
// the spec is plugins/volumetric_froxel/froxel.h).
layout(local_size_x = 1) in;
void main() {}
