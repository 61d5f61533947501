// Evaluates shaders/common/medium.cl (prepended by test_medium_devices.c) on a table of
// inputs: the records of medium_eval.comp, the same ops.
kernel void medium_eval(global const float4 *args, global const float4 *maps,
                        global float *results, int n)
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
    else
        r = lg_depth_to_slice(slicing, m, lg_slice_to_depth(slicing, m, x));
    results[i] = r;
}
