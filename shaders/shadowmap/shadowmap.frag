#version 450 core
// The shadow map's fragment stage (plugins/shadowmap): nothing to shade. The pass writes
// only depth (the framebuffer has no colour attachment); GL writes the window depth of
// the rasterised fragment, unbiased (no polygon offset, no gl_FragDepth).

void main()
{
}
