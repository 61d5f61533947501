// Evaluates shaders/common/probe.cl (prepended to this file by test_probe_devices.c) on an
// array of directions: per direction, the lookup and the coordinates.
kernel void probe_eval(global const float4 *rgba, int layout, int w, int h, int bilinear,
                       global const float4 *dirs, global float4 *results, int n)
{
    int i = get_global_id(0);
    if (i >= n)
        return;
    float3 d = dirs[i].xyz;
    results[2 * i] = lg_probe_lookup(rgba, layout, w, h, d, bilinear);
    results[2 * i + 1] = (float4)(lg_probe_dir_to_coord(layout, d), 0.0f);
}
