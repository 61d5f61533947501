// Evaluates shaders/common/rgbe.cl (prepended by test_rgbe_devices.c): per input, the
// encoded bytes, the decode of the given bytes and lg_half_range of the input.
kernel void rgbe_eval(global const float4 *inputs, global const uchar4 *bytes_in,
                      global uchar4 *encoded, global float4 *decoded,
                      global float4 *half_range, int n)
{
    int i = get_global_id(0);
    if (i >= n)
        return;
    encoded[i] = lg_rgbe_encode(inputs[i].xyz);
    // .w: lg_half_range_count of the input
    decoded[i] = (float4)(lg_rgbe_decode(bytes_in[i]), (float)lg_half_range_count(inputs[i]));
    half_range[i] = lg_half_range(inputs[i]);
}
