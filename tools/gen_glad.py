#!/usr/bin/env python3
"""Generate the SDK's GL 4.5 core loader with glad 2 (Debian's python3-glad).

usage: gen_glad.py GLAD_EXECUTABLE OUT_GL_H OUT_KHR_H OUT_GL_C

glad writes include/glad/gl.h, include/KHR/khrplatform.h and src/gl.c; we move them under
lightgraph/glad/ so the installed SDK does not collide with another glad or with the
system's KHR headers. --reproducible keeps glad offline (it uses its bundled gl.xml).
"""
import os
import shutil
import subprocess
import sys
import tempfile

glad, out_h, out_khr, out_c = sys.argv[1:5]
with tempfile.TemporaryDirectory() as tmp:
    subprocess.run([glad, "--quiet", "--reproducible", "--api", "gl:core=4.5",
                    "--extensions", "", "--out-path", tmp, "c", "--mx"], check=True)
    with open(os.path.join(tmp, "include/glad/gl.h")) as f:
        h = f.read().replace("#include <KHR/khrplatform.h>",
                             '#include "lightgraph/glad/khrplatform.h"')
    with open(os.path.join(tmp, "src/gl.c")) as f:
        c = f.read().replace("#include <glad/gl.h>", '#include "lightgraph/glad/gl.h"')
    with open(out_h, "w") as f:
        f.write(h)
    with open(out_c, "w") as f:
        f.write(c)
    shutil.copyfile(os.path.join(tmp, "include/KHR/khrplatform.h"), out_khr)
