#!/usr/bin/env python3
"""volumetric_lights_table.py: each volumetric method against volumetric_reference per light
type (directional, point, spot) in the fogged bunny box: the relative RMSE of the
in-scattering over the image and the node's time from --profile, as a markdown table
(docs/volumetric.md, "Every light in every medium"). Needs a build in build/.

usage: tools/volumetric_lights_table.py [WxH]   (default 192x108; a few minutes)"""
import math
import os
import subprocess
import sys
import tempfile
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), 'accuracy'))
import exr  # noqa: E402
ROOT=os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
LIGHTS={
 'directional':'L = light { scene = cam, mode = replace, direction = [0.4, -0.25, 1], intensity = 10 }',
 'point':'L = light { scene = cam, mode = replace, type = point, position = [0.3, 1.4, -0.2], intensity = 3 }',
 'spot':'L = light { scene = cam, mode = replace, type = spot, position = [-0.7, 1.9, 0.4], aim = target, target = [0.1, 0.3, -0.1], inner_cone_deg = 15, outer_cone_deg = 25, intensity = 30 }',
}
METHODS={
 'screen gl':'volumetric_screen { scene = fog, base = lit, samples = 64, z_limit = 8 }',
 'polygonal gl':'volumetric_polygonal { scene = fog, base = lit, shadows = shadow, z_limit = 8 }',
 'froxel gl z_near 0.2':'volumetric_froxel { scene = fog, base = lit, shadows = shadow, z_limit = 8, z_near = 0.2, backend = gl }',
 'froxel gl exponential':'volumetric_froxel { scene = fog, base = lit, shadows = shadow, z_limit = 8, slicing = exponential, backend = gl }',
 'froxel cl exponential':'volumetric_froxel { scene = fog, base = lit, shadows = shadow, z_limit = 8, slicing = exponential, backend = cl }',
 'froxel cpu exponential':'volumetric_froxel { scene = fog, base = lit, shadows = shadow, z_limit = 8, slicing = exponential, backend = cpu }',
}
REF='volumetric_reference { scene = fog, base = lit, z_limit = 8, steps = 256, spp = 16, subpixel = centre }'
SIZE=sys.argv[1] if len(sys.argv)>1 else '192x108'
TMP=tempfile.mkdtemp(prefix='lg_lights_')
def graph(light, vol, out):
    return f'''lightgraph 1
scene = gltf {{ file = "{ROOT}/assets/meshes/bunny_cornell_box.glb" }}
cam = camera {{ scene = scene, mode = look_at, position = [0.7, 0.6, 0.9], target = [-0.5, 0.7, -1.5], fov_deg = 70 }}
{LIGHTS[light]}
fog = medium {{ scene = L, density = 3, scattering = [0.1, 0.1, 0.1], absorption = [0, 0, 0], g = 0.4 }}
shadow = shadowmap {{ scene = fog, resolution = 1024 }}
lit = phong {{ scene = fog, shadows = shadow, ambient = [0.05, 0.05, 0.05], background = [0.6, 0.7, 0.9] }}
vol = {vol}
output vol.inscatter "{out}"
'''
def run(light, name, vol):
    out=f'{TMP}/{light}_{name.replace(" ","_")}.exr'
    g=f'{TMP}/g_{light}_{name.replace(" ","_")}.lgraph'
    open(g,'w').write(graph(light, vol, out))
    p=subprocess.run([ROOT+'/build/lightgraph','render',g,'--size',SIZE,'--profile'],capture_output=True,text=True)
    if p.returncode: return None, None, (p.stderr.strip().splitlines() or ['?'])[-1]
    ms=None
    for line in (p.stdout+p.stderr).splitlines():
        f=line.split()
        if len(f)>4 and f[0]=='vol': ms=float(f[4])
    return out, ms, None
rows=[]
for light in LIGHTS:
    ref, rms, err = run(light, 'reference', REF)
    if not ref: print(light, 'reference failed', err); continue
    _,_,R=exr.read_exr(ref)
    den=sum(R[c][i]**2 for c in 'RGB' for i in range(len(R['G'])))
    rows.append((light,'reference cpu',0.0,rms))
    for name,vol in METHODS.items():
        o, ms, err = run(light, name, vol)
        if not o: rows.append((light,name,None,err)); continue
        _,_,M=exr.read_exr(o)
        se=sum((M[c][i]-R[c][i])**2 for c in 'RGB' for i in range(len(R['G'])))
        rows.append((light,name,math.sqrt(se/den),ms))
print('| light | method | relative RMSE vs reference | node ms |')
print('|---|---|---|---|')
for r in rows:
    if r[2] is None: print(f'| {r[0]} | {r[1]} | failed: {r[3]} | |')
    else: print(f'| {r[0]} | {r[1]} | {r[2]:.3g} | {r[3]:.0f} |')
