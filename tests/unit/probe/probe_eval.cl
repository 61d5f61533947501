// Evaluates shaders/common/probe.cl (prepended to this file by test_probe_devices.c) on an
// array of directions: per direction, the lookup and the coordinates.
kernel void probe_eval(global const float4 *rgba, int layout, int w, int h, int bilinear,
                       global const float4 *dirs, global float4 *results, int n, float4 c0,
                       float4 c1, float4 c2)
{
    int i = get_global_id(0);
    if (i >= n)
        return;
    // world -> probe with the rotation's columns
    float3 d = lg_probe_from_world(c0.xyz, c1.xyz, c2.xyz, dirs[i].xyz);
    results[2 * i] = lg_probe_lookup(rgba, layout, w, h, d, bilinear);
    results[2 * i + 1] = (float4)(lg_probe_dir_to_coord(layout, d), 0.0f);
}
