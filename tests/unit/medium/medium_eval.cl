// Evaluates shaders/common/medium.cl (prepended by test_medium_devices.c) on a table of
// inputs: the records of medium_eval.comp, the same ops.
kernel void medium_eval(global const float4 *args, global const float4 *maps,
                        global float *results, int n, global const float4 *ext)
{
    int i = get_global_id(0);
    if (i >= n)
        return;
    int op = (int)args[i].x, slicing = (int)args[i].y;
    float x = args[i].z;
    float4 m = maps[i];
    float r;
    if (op == 0)
        r = lg_hg_phase(m.x, x);
    else if (op == 1)
        r = lg_medium_segment(x);
    else if (op == 2)
        r = lg_slice_to_depth(slicing, m, x);
    else if (op == 3)
        r = lg_depth_to_slice(slicing, m, x);
    else if (op == 4)
        r = lg_depth_to_slice(slicing, m, lg_slice_to_depth(slicing, m, x));
    else if (op == 5)
        r = lg_light_window(x, m.x);
    else if (op == 6)
        r = lg_spot_cone(x, m.x, m.y);
    else if (op == 7) {
        float4 e0 = ext[4 * i], e1 = ext[4 * i + 1], e2 = ext[4 * i + 2];
        float3 tl;
        float d;
        r = lg_local_falloff(e0.xyz, e0.w, e1.w != 0.0f, e1.xyz, m.xy, e2.xyz, &tl, &d);
    } else {
        float4 e0 = ext[4 * i], e1 = ext[4 * i + 1], e2 = ext[4 * i + 2], e3 = ext[4 * i + 3];
        r = lg_point_inscatter(e0.xyz, e1.xyz, e0.w, e1.w, e2.xyz, e2.w, e3.w != 0.0f, e3.xyz,
                               m.xy, m.z, m.w, (int)x);
    }
    results[i] = r;
}
