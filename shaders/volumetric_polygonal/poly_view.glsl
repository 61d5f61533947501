// volumetric_polygonal: the camera and the medium as the volume pass (steps 2) and the
// composite (step 3) read them, one std140 block uploaded in one call from the C struct
// that mirrors it (poly_gpu_view in plugins/volumetric_polygonal/polygonal.c, 208 bytes).
// No instance name: the members read as plain uniforms.
layout(std140, binding = 0) uniform PolyView {
    mat4 u_view_proj;      // the camera's, far plane at infinity, near plane at the eye
    mat4 u_inv_view_proj;  // the camera's (the finite one phong drew base with)
    vec3 u_eye;
    float u_z_limit;
    vec3 u_forward;
    float u_g;
    vec3 u_sigma_s;
    vec3 u_sigma_t;
    vec2 u_size;
};
