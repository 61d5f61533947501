#version 450 core
// The viewer's image pass (host/viewer_display.c): the fitted rectangle of the window
// shows the image, multiplied by the exposure and encoded for display exactly as the PNG
// writer encodes (sdk/src/png.c: lg_srgb_encode of the value clamped to [0,1], NaN and
// -Inf 0, +Inf 1). Texel row 0 of the image is the top row of the picture, and GL's window
// y grows upwards: the texture's t runs from the rectangle's top edge down.

layout(location = 0) uniform vec4 u_rect;   // x0, y0, x1, y1 of the image in pixels
layout(location = 2) uniform float u_exposure;
// Taps per axis over the pixel's footprint: 1 at scales >= 1; ceil(1 / scale) (at most 8)
// when the image is shrunk, so that each pixel is the mean of the texels it covers (a box
// filter) rather than the two or four next to its centre.
layout(location = 3) uniform int u_taps;
layout(binding = 0) uniform sampler2D u_image;

layout(location = 0) out vec4 o_color;

// lg_srgb_encode (sdk/src/rgbe.c) with png.c's clamping. The NaN test comes first and is
// explicit: a comparison with NaN must not be left to the compiler's reordering.
float display_encode(float v)
{
    if (isnan(v) || !(v > 0.0))
        return 0.0;
    if (v >= 1.0)
        return 1.0;
    if (v <= 0.0031308)
        return 12.92 * v;
    return 1.055 * pow(v, 1.0 / 2.4) - 0.055;
}

void main()
{
    vec2 size = vec2(u_rect.z - u_rect.x, u_rect.w - u_rect.y);
    vec3 sum = vec3(0.0);
    for (int j = 0; j < u_taps; j++) {
        for (int i = 0; i < u_taps; i++) {
            vec2 p = gl_FragCoord.xy + (vec2(i, j) + 0.5) / float(u_taps) - 0.5;
            vec2 uv = vec2((p.x - u_rect.x) / size.x, (u_rect.w - p.y) / size.y);
            sum += texture(u_image, uv).rgb;
        }
    }
    vec3 v = sum / float(u_taps * u_taps) * u_exposure;
    o_color = vec4(display_encode(v.r), display_encode(v.g), display_encode(v.b), 1.0);
}
