"""The phong node's shading modes against per-pixel Phong: where the equation is evaluated
(flat, gouraud, phong, mixed, phong_half) x the mesh's tessellation, mixed's threshold, depth
cueing, and many lights (the old tools/phong_cost.py, folded in)."""
import math
import os
import subprocess
import sys

from accuracy.study import Study, StudyError

TITLE = "Local illumination: Phong shading modes"
ORDER = 10
INTRO = """\
The `phong` node (Phong's reflection model, seed 1) evaluates its equation once per facet
(`flat`), per vertex (`gouraud`), per pixel (`phong`), per pixel on highlight facets only
(`mixed`, threshold `mixed_threshold_deg`) or per pixel on half the pixels (`phong_half`);
[plugins/phong/README.md](../plugins/phong/README.md). **Reference:** per-pixel Phong
(`shading = phong`) on the most finely tessellated sphere (level 128, 65,024 triangles, where
the silhouette's facets are below a pixel) for the sphere sweep, and on the same mesh for the
bunny box, whose mesh is what it is: per-pixel shading evaluates the model exactly at every
pixel centre, so its only error against the model is the mesh's. Knobs swept: the shading
mode x the sphere's tessellation (UV sphere, 4 L (L - 1) triangles at level L); mixed's
threshold; depth cueing (eq. 1-12, `depth_cue = true`, `k` = 1) in every mode; 16
directional lights, where per-pixel lighting costs enough for the cheaper modes to pay.
Time: the `phong` node's per frame (`per_frame = true`, the mean of the frames after the
first, so its shader compilation is left out), llvmpipe. Metric: relative RMSE of the linear
radiance."""

MODES = ["flat", "gouraud", "phong", "mixed", "phong_half"]
LEVELS = [4, 8, 16, 32, 64]
QUICK_LEVELS = [4, 16]
REF_LEVEL, QUICK_REF_LEVEL = 128, 32

# a pronounced highlight (kd 0.7, Od (0.8, 0.3, 0.2), ks 1, Os 0.8, n 40), as phong_cost had,
# so that Gouraud's lost highlight and mixed's recovery show
SPHERE_MATERIAL = ('{"ka": 0.2, "kd": 0.7, "ks": 1, "od": [0.8, 0.3, 0.2], '
                   '"os": [0.8, 0.8, 0.8], "shininess": 40}')


def sphere(ctx, name, level, lights):
    glb = os.path.join(ctx.tmp, name + ".glb")
    cmd = [sys.executable, os.path.join(ctx.root, "tools/gen_scene.py"), "sphere", "--level",
           str(level), "--material-extras", SPHERE_MATERIAL] + lights + [
           "--camera-pos", "0,0.4,3.2", "--camera-target", "0,0,0", "--yfov", "45", "-q",
           "-o", glb]
    r = subprocess.run(cmd, capture_output=True, text=True)
    if r.returncode != 0:
        raise StudyError("gen_scene.py sphere --level %d failed:\n%s" % (level, r.stderr))
    return glb


def sphere_graph(ctx, name, glb):
    return ctx.write(name + ".lgraph",
                     'lightgraph 1\n'
                     'scene = gltf { file = "%s" }\n'
                     'lit = phong { scene = scene, ambient = [0.2, 0.2, 0.2], '
                     'background = [0, 0, 0], per_frame = true }\n'
                     'output lit "%s"\n' % (glb, os.path.join(ctx.tmp, name + ".exr")))


def bunny_graph(ctx, name):
    return ctx.write(name + ".lgraph",
                     'lightgraph 1\n'
                     'include "%s"\n'
                     'lit = phong { scene = bulb, shadows = shadow, ambient = [0.3, 0.3, 0.3], '
                     'ks_scale = 20, background = [0.02, 0.02, 0.03], per_frame = true }\n'
                     'output lit "%s"\n'
                     % (os.path.join(ctx.root, "examples/phong_scene.lgraph"),
                        os.path.join(ctx.tmp, name + ".exr")))


def studies(ctx):
    sun = ["--dir-light=-0.5,-0.6,-0.8,1.5"]
    levels = QUICK_LEVELS if ctx.quick else LEVELS
    ref_level = QUICK_REF_LEVEL if ctx.quick else REF_LEVEL
    files = [sphere(ctx, "sphere_%03d" % lv, lv, sun) for lv in levels]
    ref = sphere_graph(ctx, "sphere_ref", sphere(ctx, "sphere_ref", ref_level, sun))
    # the tessellation is the file the gltf node loads: one value per level, named by it
    tess = ("scene.file", files)
    lights16 = ["--dir-light=%.4f,-0.5,%.4f,0.2" % (0.6 * math.cos(0.39 * i),
                                                     0.6 * math.sin(0.39 * i) - 0.6)
                for i in range(16)]
    s16 = sphere_graph(ctx, "sphere16_16lights",
                       sphere(ctx, "sphere16_16lights", 16, lights16))
    bunny = bunny_graph(ctx, "bunny")
    common = dict(technique="phong", backend="gl", time_node="lit", size="320x180",
                  quick_size="64x36", frames=4, repeat=3, metric="rel_rmse")
    return [
        Study(id="phong_sphere", title="sphere, 1 light: shading mode x tessellation",
              graph=sphere_graph(ctx, "sphere", files[0]),
              vary=[("lit.shading", MODES), tess],
              quick_vary=[("lit.shading", ["gouraud", "phong"]), tess],
              reference=ref, ref_sets=["lit.shading=phong"],
              reference_label="per-pixel Phong on the level-%d sphere, %d triangles"
              % (ref_level, 4 * ref_level * (ref_level - 1)),
              value_labels={"scene.file": {f: "L%d (%d tris)" % (lv, 4 * lv * (lv - 1))
                                           for f, lv in zip(files, levels)}},
              **common),
        Study(id="phong_bunny", title="bunny box (5,009 triangles, a sun with shadows and a "
              "bulb): shading mode", graph=bunny, vary=[("lit.shading", MODES)],
              quick_vary=[("lit.shading", ["flat", "mixed"])],
              ref_sets=["lit.shading=phong"],
              reference_label="per-pixel Phong on the same mesh", **common),
        Study(id="phong_mixed", title="bunny box: mixed's highlight threshold",
              graph=bunny, sets=["lit.shading=mixed"],
              vary=[("lit.mixed_threshold_deg", ["5", "10", "20", "30", "45", "90"])],
              ref_sets=["lit.shading=phong"],
              reference_label="per-pixel Phong on the same mesh", **common),
        Study(id="phong_depth_cue", title="bunny box, depth cueing (k = 1): shading mode",
              graph=bunny, sets=["lit.depth_cue=true", "lit.k=1"],
              vary=[("lit.shading", MODES)], quick_vary=[("lit.shading", ["gouraud", "phong"])],
              ref_sets=["lit.shading=phong"],
              reference_label="per-pixel Phong with the same depth cueing", **common),
        Study(id="phong_16lights", title="level-16 sphere, 16 directional lights: shading mode",
              graph=s16, vary=[("lit.shading", MODES)],
              quick_vary=[("lit.shading", ["gouraud", "phong_half"])],
              ref_sets=["lit.shading=phong"],
              reference_label="per-pixel Phong on the same mesh", **common),
    ]
