#version 450
// volumetric_polygonal, step 1: the lit-volume mesh of one light from its shadow map
// (seed 2, 3.2.2; Billeter et al. 2010). One invocation per vertex; the topology (which
// vertices make each triangle) is fixed for a grid size and built once on the CPU
// (plugins/volumetric_polygonal/polygonal.c, poly_indices). In the light's NDC (x, y
// across the tile, z away from the light) the lit volume is a box [X0, X1] x [Y0, Y1] x
// [u_near, u_far] that holds the camera's fog, less the shadowed dent under the tile's
// depths (as vol_shadow_cpu: outside the tile and before the light's near plane is lit).
// Vertices, in this order:
//
//   [0, G = Ws Hs)        the grid: vertex (i, j) at the centre of texel
//                         round(i (res - 1) / (Ws - 1)), round(j (res - 1) / (Hs - 1)) of
//                         the light's tile, at the depth stored there (plus the map's
//                         constant bias). A texel where nothing was drawn (depth 1) is put
//                         at u_far: unshadowed. (The outer half texel of the tile is thus
//                         outside the grid: lit, as the box around it.)
//   [G, G + P)            the grid's P = 2 (Ws - 1) + 2 (Hs - 1) border vertices,
//                         counter-clockwise, at u_far: the dent's walls join them to the grid
//   G + P + s, s < 4      the box's corners at u_far (s = 0 (X0, Y0), 1 (X1, Y0), 2 (X1, Y1),
//                         3 (X0, Y1))
//   G + P + 4 + s         the same at u_near
//
// Positions are light NDC unprojected by the light's inverse view_proj (orthographic: w =
// 1), written as world-space vec4 (w = 1).
//
// A perspective map (a spot light's, or one face of a point light's cube; u_persp = 1) is
// the same mesh with the box replaced by the map's frustum: u_outer is the tile's own edge
// [-1, 1]^2 (beyond it a spot's cone is dark and a cube's neighbouring face takes over),
// the cap on the light's side shrinks to the light's position u_light (the four side walls
// converge there: everything between the light and the map's near plane is lit, as the
// lookup has it), and every vertex at the far side lies on the plane u_far_scale times the
// near plane's distance from the light, along its ray from the light (unprojecting an NDC
// z close to the projection's asymptote would lose the precision). A stored depth is
// capped at the map's far plane (NDC 1), so the dent never passes the far side.
layout(local_size_x = 64) in;

layout(binding = 0) uniform sampler2D u_atlas;   // the shadow map atlas (depth)
layout(std430, binding = 0) writeonly buffer Vertices { vec4 verts[]; };

uniform mat4 u_inv_light;   // inverse of the light's view_proj
uniform ivec2 u_tile;       // the tile's top-left texel in the atlas
uniform int u_res;          // the tile's side, texels
uniform ivec2 u_grid;       // Ws, Hs (>= 2)
uniform float u_bias;       // the map's constant bias, window depth units
uniform float u_near;       // NDC z of the box's cap on the light's side (< -1)
uniform float u_far;        // NDC z of the box's far side (> 1)
uniform vec4 u_outer;       // X0, Y0, X1, Y1 (X0 < -1, Y0 < -1, X1 > 1, Y1 > 1)
uniform int u_persp;        // 1: a perspective map (then u_outer = -1, -1, 1, 1)
uniform vec3 u_light;       // perspective: the light's position, world
uniform float u_far_scale;  // perspective: the far side's distance over the near plane's

// The border loop: ring index k -> grid (i, j), counter-clockwise in (u, v).
ivec2 ring_cell(int k)
{
    int W = u_grid.x - 1, H = u_grid.y - 1;
    if (k < W)
        return ivec2(k, 0);
    k -= W;
    if (k < H)
        return ivec2(W, k);
    k -= H;
    if (k < W)
        return ivec2(W - k, H);
    k -= W;
    return ivec2(0, H - k);
}

// Grid vertex c sits at the centre of texel t = round(c (res - 1) / (grid - 1)), where the
// map's depth is exact (the rasteriser sampled it there): vertices 0 and grid - 1 on the
// tile's first and last texels, every texel one vertex when grid = res.
vec3 grid_ndc(ivec2 c)
{
    ivec2 t = (c * (u_res - 1) + (u_grid - 1) / 2) / (u_grid - 1);
    vec2 uv = (vec2(t) + 0.5) / float(u_res);
    float d = texelFetch(u_atlas, u_tile + t, 0).r;
    float z = d >= 1.0 ? u_far : 2.0 * (d + u_bias) - 1.0;
    if (u_persp != 0 && d < 1.0)
        z = min(z, 1.0);
    return vec3(2.0 * uv - 1.0, z);
}

// Light NDC -> world. A perspective map's far side (z = u_far) is placed along the ray from
// the light through the near plane's point of the same x, y.
vec3 to_world(vec3 ndc)
{
    if (u_persp != 0 && ndc.z == u_far) {
        vec4 n = u_inv_light * vec4(ndc.xy, -1.0, 1.0);
        return u_light + (n.xyz / n.w - u_light) * u_far_scale;
    }
    vec4 w = u_inv_light * vec4(ndc, 1.0);
    return w.xyz / w.w;
}

void main()
{
    // rows of gl_NumWorkGroups.x * 64 vertices: a 2048^2 mesh needs more than the 65535
    // groups one axis may have
    int id = int(gl_GlobalInvocationID.y * gl_NumWorkGroups.x * gl_WorkGroupSize.x +
                 gl_GlobalInvocationID.x);
    int n_grid = u_grid.x * u_grid.y;
    int P = 2 * (u_grid.x - 1) + 2 * (u_grid.y - 1);
    if (id >= n_grid + P + 8)
        return;
    vec3 ndc;
    if (id < n_grid) {
        ndc = grid_ndc(ivec2(id % u_grid.x, id / u_grid.x));
    } else if (id < n_grid + P) {
        ndc = vec3(grid_ndc(ring_cell(id - n_grid)).xy, u_far);
    } else {
        int s = (id - n_grid - P) & 3;
        float x = (s == 1 || s == 2) ? u_outer.z : u_outer.x;
        float y = s >= 2 ? u_outer.w : u_outer.y;
        ndc = vec3(x, y, id - n_grid - P < 4 ? u_far : u_near);
        if (u_persp != 0 && id - n_grid - P >= 4) {
            verts[id] = vec4(u_light, 1.0); // the cap on the light's side: its apex
            return;
        }
    }
    verts[id] = vec4(to_world(ndc), 1.0);
}
