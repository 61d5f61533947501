#!/usr/bin/env python3
"""lightgraph view under Xvfb, driven by --script (issue 12, item 7; docs/viewer.md).

Each test starts its own X server (Xvfb -displayfd: the server picks a free display and
says which, so parallel tests never race for one), runs the viewer with a script, and checks
what it wrote and said:

  no_display     without DISPLAY: one line that says so, exit 1
  bad_script     a script with an unknown event: FILE:LINE and exit 2, no window needed
  screenshot_fail  a screenshot_window (and a screenshot) that cannot be written fails the
                 script: SCRIPT:LINE and the reason, exit 1, the script goes on (it used to
                 print the error and exit 0)
  headless       the window's frame of examples/phong.lgraph matches `render` of the same
                 graph: the linear EXR screenshot within float noise, the PNG screenshot
                 exactly, and the window's own pixels (overlay hidden) within 1 code value
  keys           Tab/Down select lit.shading, Right cycles it through every mode (each a
                 different picture, the overlay's change printed), a rejected --set value
                 keeps the last good frame and says why, O prints the overrides
  edit           an edit of the graph file is picked up (the picture changes, the
                 unchanged nodes are adopted, not made again); a broken edit keeps the last
                 good frame and reports file:line; fixing it recovers
  shader         a shader edit runs the build: a failed build is shown and changes nothing,
                 a build that relinks a plugin gets it reloaded
  plugin         a rebuilt plugin is reloaded (the picture shows the new build) with the
                 parameter it had; a build that crashes in create() and one built for ABI 1
                 are rolled back to the working one, the error shown
  camera         a drag changes the picture, R restores the graph's camera exactly, C prints
                 a camera node that renders the dragged view headless (with shadow maps
                 fitted to the camera's frustum, which follow the viewer's camera)
  view_independent  a camera move runs the shadow maps again only when they are fitted to
                 the camera's frustum; phong on every move
  method         M switches between alternative nodes feeding the shown image, and back
  methods_example  examples/volumetric_methods.lgraph: M cycles the three volumetric methods
                 (different inputs and outputs, still alternatives) and "off", plugins
                 loaded only when switched to; the camera moves the froxel view
  method_off     "off" in the method cycle shows the methods' input (the lit image), as
                 render with the tone mapper reading it; M again switches the first on
  play           play, pause, time T, `.` and `,` drive lg_frame.time (test_clock); a
                 negative or huge time is clamped; static nodes upstream run once
  anim           an animated glTF through preview: `time T` shows render's pose at T;
                 paused, preview does not run again; playing, it runs every frame
  resize         a scripted window resize re-renders at the new size, equal to render at
                 that size; a 0x0 (minimised) framebuffer renders nothing, no crash

usage: test_viewer.py TEST_NAME
"""
import os
import shutil
import signal
import stat
import subprocess
import sys
import tempfile
import time

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "host"))
import exr_read  # noqa: E402

EXE = os.environ["LG_EXE"]
SRC = os.environ["LG_SOURCE_ROOT"]
TMP = tempfile.mkdtemp(prefix="lg-viewer-")
W, H = 160, 90
SIZE = ["--size", "%dx%d" % (W, H)]


class Fail(Exception):
    pass


def check(cond, msg):
    if not cond:
        raise Fail(msg)


# ---- X server -------------------------------------------------------------------------

class Xvfb:
    def __init__(self):
        exe = shutil.which("Xvfb")
        if not exe:
            print("SKIP: Xvfb is not installed (Debian package xvfb; `sh tools/deps.sh` "
                  "installs it): the viewer's tests need an X server")
            sys.exit(77)
        r, w = os.pipe()
        self.p = subprocess.Popen([exe, "-displayfd", str(w), "-screen", "0", "1024x768x24",
                                   "-nolisten", "tcp", "-noreset"],
                                  pass_fds=(w,), stdout=subprocess.DEVNULL,
                                  stderr=subprocess.DEVNULL)
        os.close(w)
        data = b""
        deadline = time.time() + 30
        while not data.endswith(b"\n") and time.time() < deadline:
            chunk = os.read(r, 64)
            if not chunk:
                break
            data += chunk
        os.close(r)
        check(data.strip().isdigit(), "Xvfb did not start (said %r)" % data)
        self.display = ":" + data.strip().decode()

    def close(self):
        self.p.send_signal(signal.SIGTERM)
        try:
            self.p.wait(10)
        except subprocess.TimeoutExpired:
            self.p.kill()
            self.p.wait()


XV = None


def env_with_display(extra=None):
    e = dict(os.environ)
    e["DISPLAY"] = XV.display
    if extra:
        e.update(extra)
    return e


def view(graph, script, args=(), env=None, timeout=600, expect=0):
    """Runs the viewer with `script` (a list of lines) written next to the graph."""
    path = os.path.join(TMP, "script-%d.txt" % int(time.time() * 1e6))
    with open(path, "w") as f:
        f.write("\n".join(script) + "\n")
    cmd = [EXE, "view", graph, "--script", path] + SIZE + list(args)
    p = subprocess.run(cmd, env=env if env is not None else env_with_display(),
                       capture_output=True, text=True, timeout=timeout)
    out = p.stdout + p.stderr
    if expect is not None and p.returncode != expect:
        raise Fail("%s exited %d, expected %d:\n%s" % (" ".join(cmd), p.returncode, expect,
                                                        out[-6000:]))
    return p.returncode, p.stdout, p.stderr


def render(graph, out, args=()):
    cmd = [EXE, "render", graph, "-o", out] + SIZE + list(args)
    p = subprocess.run(cmd, capture_output=True, text=True, timeout=600)
    check(p.returncode == 0, "%s failed:\n%s" % (" ".join(cmd), p.stderr[-4000:]))


# ---- images ---------------------------------------------------------------------------

def exr_rows(path):
    """Rows of (r, g, b, a), top row first."""
    return exr_read.read_exr(path)


def max_exr_diff(a, b):
    ra, rb = exr_rows(a), exr_rows(b)
    check(len(ra) == len(rb) and len(ra[0]) == len(rb[0]),
          "%s and %s differ in size" % (a, b))
    return max(abs(x - y) for p, q in zip(ra, rb) for u, v in zip(p, q)
               for x, y in zip(u[:3], v[:3]))


def diff(a, b, args=()):
    """lightgraph diff A B --json: the metrics."""
    import json
    p = subprocess.run([EXE, "diff", a, b, "--json"] + list(args), capture_output=True,
                       text=True, timeout=120)
    check(p.returncode in (0, 1), "diff %s %s failed: %s" % (a, b, p.stderr))
    return json.loads(p.stdout)


def mean_exr(path):
    rows = exr_rows(path)
    n = len(rows) * len(rows[0])
    return sum(p[0] + p[1] + p[2] for r in rows for p in r) / (3 * n)


def max_png_diff(a, b):
    """The largest difference of two PNG files, linear, as `lightgraph diff` reads them."""
    return diff(a, b)["max_abs"]


# ---- graphs ---------------------------------------------------------------------------

def phong_graph(name="g.lgraph", key=0.12, extra=""):
    """A graph like examples/phong.lgraph that includes the example's scene by absolute
    path, in TMP (edits go there, never into the source tree)."""
    path = os.path.join(TMP, name)
    with open(path, "w") as f:
        f.write("""lightgraph 1
include "%s"

lit = phong {
    scene = bulb
    shadows = shadow
    shading = phong
    specular = phong
    ambient = [0.3, 0.3, 0.3]
    ks_scale = 20
    background = [0.02, 0.02, 0.03]
}

tone = reinhard { image = lit, key = %g }
%s
output tone "out.png"
""" % (os.path.join(SRC, "examples", "phong_scene.lgraph"), key, extra))
    return path


# ---- tests ----------------------------------------------------------------------------

def t_no_display():
    e = dict(os.environ)
    e.pop("DISPLAY", None)
    e.pop("WAYLAND_DISPLAY", None)
    p = subprocess.run([EXE, "view", os.path.join(SRC, "examples", "phong.lgraph")], env=e,
                       capture_output=True, text=True, timeout=60)
    check(p.returncode == 1, "exit %d without a display:\n%s" % (p.returncode, p.stderr))
    lines = [l for l in p.stderr.splitlines() if l.strip()]
    check(len(lines) == 1 and "no display" in lines[0],
          "expected one line saying 'no display', got:\n%s" % p.stderr)


def t_bad_script():
    g = phong_graph()
    path = os.path.join(TMP, "bad.txt")
    with open(path, "w") as f:
        f.write("wait_frames 2\n# fine so far\nfrobnicate 3\n")
    p = subprocess.run([EXE, "view", g, "--script", path], env=env_with_display(),
                       capture_output=True, text=True, timeout=60)
    check(p.returncode == 2, "exit %d for a bad script:\n%s" % (p.returncode, p.stderr))
    check("%s:3:" % path in p.stderr, "the error does not name bad.txt:3:\n%s" % p.stderr)


def t_headless():
    g = phong_graph()
    render(g, os.path.join(TMP, "h.exr"))
    render(g, os.path.join(TMP, "h.png"))
    black = os.path.join(TMP, "black.lgraph")
    with open(black, "w") as f:
        f.write('lightgraph 1\nk = constant { color = [0, 0, 0] }\noutput k "black.png"\n')
    render(black, os.path.join(TMP, "black.png"))
    view(g, ["wait_frames 3", "screenshot v.exr", "screenshot v.png", "key H", "wait_frames 2",
             "screenshot_window w.png", "key F12", "quit"])
    rows = exr_rows(os.path.join(TMP, "v.exr"))
    check(len(rows) == H and len(rows[0]) == W, "the screenshot is not %dx%d" % (W, H))
    worst = max_exr_diff(os.path.join(TMP, "h.exr"), os.path.join(TMP, "v.exr"))
    check(worst < 1e-3, "the viewer's EXR differs from render's by %g" % worst)
    # PNG: one code value is at most 0.0094 in linear terms (the sRGB curve's steepest, at 1)
    d = max_png_diff(os.path.join(TMP, "h.png"), os.path.join(TMP, "v.png"))
    check(d <= 0.0095, "the viewer's PNG differs from render's by %g (linear)" % d)
    # the window at the render's size shows the picture 1:1 (overlay hidden with H)
    d = max_png_diff(os.path.join(TMP, "h.png"), os.path.join(TMP, "w.png"))
    check(d <= 0.019, "the window's pixels differ from render's PNG by %g (linear)" % d)
    shots = sorted(f for f in os.listdir(TMP) if f.startswith("g-") and f[-4:] in (".png", ".exr"))
    check(len(shots) == 2 and shots[0].endswith(".exr") and shots[1].endswith(".png"),
          "F12 did not write a PNG and an EXR next to the graph: %s" % shots)
    check(max_exr_diff(os.path.join(TMP, shots[0]), os.path.join(TMP, "h.exr")) < 1e-3,
          "F12's EXR is not the shown image")
    check(diff(os.path.join(TMP, "w.png"), os.path.join(TMP, "black.png"))["mean_abs"] > 0.02,
          "the window is (nearly) black")


def t_node_file():
    """The viewer writes no file a node would write (LG_ROLE_OUTPUT_FILE): the parameter
    reads "" there, one warning says so, and the destination (a FIFO here) is not touched."""
    plugins = os.environ["LG_TEST_PLUGINS"] + ":" + os.path.join(os.environ["LG_BUILD_ROOT"],
                                                                 "plugins")
    g = os.path.join(TMP, "file.lgraph")
    with open(g, "w") as f:
        f.write('lightgraph 1\nc = constant { color = [0.5, 1, 2] }\n'
                'w = test_file_writer { image = c, file = "dump.txt" }\noutput w "w.exr"\n')
    fifo = os.path.join(TMP, "dump.txt")
    os.mkfifo(fifo)
    _, out, err = view(g, ["wait_frames 3", "quit"],
                       env=env_with_display({"LIGHTGRAPH_PLUGIN_PATH": plugins}), timeout=120)
    check("file '%s' is not written: the viewer writes no files" % fifo in err, err[-3000:])
    check(err.count("is not written") == 1, "said more than once:\n" + err[-3000:])
    check(stat.S_ISFIFO(os.lstat(fifo).st_mode), "the FIFO was replaced")
    left = [n for n in os.listdir(TMP) if n.startswith(".")]
    check(left == [], "temporaries left: %s" % left)


def t_screenshot_fail():
    g = os.path.join(TMP, "flat.lgraph")
    with open(g, "w") as f:
        f.write('lightgraph 1\nk = constant { color = [0.2, 0.4, 0.6] }\noutput k "flat.png"\n')
    os.mkdir(os.path.join(TMP, "taken.png"))
    missing = os.path.join(TMP, "no", "such", "w.png")
    for event in ("screenshot_window", "screenshot"):
        for bad, why in ((os.path.join(TMP, "taken.png"), "it is a directory"),
                         (missing, "does not exist")):
            ok = os.path.join(TMP, "after.png")
            if os.path.exists(ok):
                os.remove(ok)
            rc, out, err = view(g, ["wait_frames 2", "%s %s" % (event, bad), "wait_frames 1",
                                    "screenshot_window after.png", "quit"], expect=1)
            check(":2: %s %s: " % (event, bad) in err and why in err,
                  "%s into %s: the failure does not say where and why:\n%s" % (event, bad, err))
            check(os.path.exists(ok), "the script stopped at the failed %s" % event)
    # and written, exit 0
    view(g, ["wait_frames 2", "screenshot_window w.png", "quit"], expect=0)
    check(open(os.path.join(TMP, "w.png"), "rb").read(4) == b"\x89PNG", "w.png written")


def selections(stdout):
    return [l for l in stdout.splitlines() if l.startswith("lightgraph view: select: ")]


def t_keys():
    g = phong_graph()
    # the nodes offered are the kept ones in file order (scene, sun, bulb, shadow from the
    # included file, then lit, tone): lit is four Tabs from the first; Home selects its
    # first entry, shading
    modes = ["mixed", "phong_half", "flat", "gouraud", "phong"]
    script = ["wait_frames 2", "screenshot k0.exr"] + ["key TAB"] * 4 + ["key HOME"]
    for i, m in enumerate(modes):
        script += ["key RIGHT", "expect_ok", "wait_frames 1", "screenshot k%d.exr" % (i + 1)]
    script += ["set lit.shading=bogus", "expect_error bogus", "screenshot kbad.exr",
               "set tone.key=-1", "expect_error", "key O", "quit"]
    rc, out, err = view(g, script)
    sel = selections(out)
    check(sel and "lit" in sel[-1] and "shading" in sel[-1],
          "four Tabs did not select lit.shading: %s" % (sel[-1:] or out[-2000:]))
    for m in modes:
        check("lit.shading=%s" % m in out, "no change to %s reported:\n%s" % (m, out[-3000:]))
    k = [os.path.join(TMP, "k%d.exr" % i) for i in range(6)]
    for i in range(1, 5):
        for j in range(i):
            check(max_exr_diff(k[i], k[j]) > 1e-3, "shading %s and %s look the same" %
                  (modes[i - 1], modes[j - 1] if j else "phong (start)"))
    check(max_exr_diff(k[5], k[0]) < 1e-6, "back to phong is not the first picture")
    check(max_exr_diff(os.path.join(TMP, "kbad.exr"), k[5]) == 0,
          "a rejected value changed the picture")
    check("--set lit.shading=phong" in out, "O did not print the overrides:\n%s" % out[-2000:])


def t_edit():
    g = phong_graph(key=0.12)
    script = ["wait_frames 2", "screenshot e0.exr",
              "shell sed -i 's/key = 0.12/key = 0.5/' g.lgraph",
              "wait_reload 120", "expect_ok", "wait_frames 1", "screenshot e1.exr",
              "shell printf 'broken = {\\n' >> g.lgraph",
              "wait_reload 120", "expect_error g.lgraph", "wait_frames 1", "screenshot e2.exr",
              "shell sed -i '$d' g.lgraph",
              "wait_reload 120", "expect_ok", "wait_frames 1", "screenshot e3.exr", "quit"]
    rc, out, err = view(g, script, args=["-v", "-v"])
    e = [os.path.join(TMP, "e%d.exr" % i) for i in range(4)]
    check(mean_exr(e[1]) > 1.5 * mean_exr(e[0]),
          "key 0.12 -> 0.5 did not brighten the picture: %g -> %g" % (mean_exr(e[0]),
                                                                   mean_exr(e[1])))
    check(max_exr_diff(e[2], e[1]) == 0, "the broken edit changed the picture")
    check(max_exr_diff(e[3], e[1]) == 0, "the fixed graph does not show the same picture")
    for node in ("scene", "shadow", "lit"):
        check("node '%s' kept from the previous plan" % node in err,
              "'%s' was made again although only tone's key changed:\n%s" % (node,
                                                                             err[-3000:]))
    check("g.lgraph:" in out + err, "the broken edit's error does not name the file")


RELOADABLE = os.environ.get("LG_RELOADABLE_DIRS", "")


def reloadable(variant):
    dirs = dict(kv.split("=", 1) for kv in RELOADABLE.split(":") if kv)
    return os.path.join(dirs[variant], "lg_reloadable.so")


def t_plugin():
    plug = os.path.join(TMP, "plug")
    os.makedirs(plug)
    shutil.copy(reloadable("v1"), os.path.join(plug, "lg_reloadable.so"))
    g = os.path.join(TMP, "r.lgraph")
    with open(g, "w") as f:
        f.write('lightgraph 1\nc = reloadable { gain = 1.5 }\noutput c "out.exr"\n')

    def swap(variant):
        return ("shell cp '%s' plug/.next && mv plug/.next plug/lg_reloadable.so"
                % reloadable(variant))
    script = ["wait_frames 2", "screenshot p1.exr", "set c.gain=1.8", "expect_ok",
              swap("v2"), "wait_reload 120", "expect_ok", "wait_frames 1", "screenshot p2.exr",
              swap("crash"), "wait_reload 120", "expect_error crashed", "wait_frames 1",
              "screenshot p3.exr",
              swap("abi1"), "wait_reload 120", "expect_error ABI", "wait_frames 1",
              "screenshot p4.exr",
              swap("v2"), "wait_reload 120", "expect_ok", "set c.gain=1", "expect_ok",
              "screenshot p5.exr", "quit"]
    rc, out, err = view(g, script, env=env_with_display({"LIGHTGRAPH_PLUGIN_PATH": plug}))
    px = {i: exr_rows(os.path.join(TMP, "p%d.exr" % i))[3][5] for i in range(1, 6)}
    check(abs(px[1][0] - 0.75) < 1e-6 and px[1][1] == 0, "build 1 shows %s" % (px[1],))
    check(abs(px[2][1] - 0.9) < 1e-6 and px[2][0] == 0,
          "the rebuilt plugin is not shown with gain 1.8: %s" % (px[2],))
    check(px[3] == px[2] and px[4] == px[2],
          "a broken build changed the picture: %s, %s" % (px[3], px[4]))
    check(abs(px[5][1] - 0.5) < 1e-6, "after the rollbacks the plugin does not work: %s" %
          (px[5],))
    check("rolled back" in out + err, "no rollback reported:\n%s" % (out + err)[-3000:])


def t_shader():
    """A shader edit runs the build (LIGHTGRAPH_REBUILD stands for `ninja -C build`, and
    LIGHTGRAPH_SHADER_DIR for the source tree's shaders/): a failing build shows its error
    and changes nothing; a build that relinks the plugin gets it reloaded."""
    plug = os.path.join(TMP, "plug")
    shaders = os.path.join(TMP, "shaders")
    os.makedirs(plug)
    os.makedirs(shaders)
    shutil.copy(reloadable("v1"), os.path.join(plug, "lg_reloadable.so"))
    with open(os.path.join(shaders, "fill.frag"), "w") as f:
        f.write("// version 1\n")
    build = os.path.join(TMP, "build.sh")
    with open(build, "w") as f:
        f.write("""#!/bin/sh
if grep -q broken '%s'; then echo "fill.frag:2: error: 'broken' : syntax error" >&2; exit 1; fi
cp '%s' '%s/.next' && mv '%s/.next' '%s/lg_reloadable.so'
""" % (os.path.join(shaders, "fill.frag"), reloadable("v2"), plug, plug, plug))
    g = os.path.join(TMP, "r.lgraph")
    with open(g, "w") as f:
        f.write('lightgraph 1\nc = reloadable { gain = 1.5 }\noutput c "out.exr"\n')
    script = ["wait_frames 2", "screenshot s1.exr",
              "shell echo broken >> shaders/fill.frag", "wait_reload 120",
              "expect_error syntax error", "wait_frames 1", "screenshot s2.exr",
              "shell echo '// version 2' > shaders/fill.frag", "wait_reload 120", "expect_ok",
              "wait_frames 1", "screenshot s3.exr", "quit"]
    rc, out, err = view(g, script, env=env_with_display({
        "LIGHTGRAPH_PLUGIN_PATH": plug, "LIGHTGRAPH_SHADER_DIR": shaders,
        "LIGHTGRAPH_REBUILD": "sh " + build}))
    px = {i: exr_rows(os.path.join(TMP, "s%d.exr" % i))[3][5] for i in range(1, 4)}
    check(abs(px[1][0] - 0.75) < 1e-6, "build 1 shows %s" % (px[1],))
    check(px[2] == px[1], "a failed rebuild changed the picture: %s" % (px[2],))
    check(abs(px[3][1] - 0.75) < 1e-6 and px[3][0] == 0,
          "the rebuilt plugin is not shown: %s" % (px[3],))
    check("rebuild failed" in out + err, "the failed build was not reported")


def t_camera():
    g = phong_graph()
    script = ["wait_frames 2", "screenshot c0.exr", "drag 40 10", "wait_frames 2",
              "screenshot c1.exr", "key C", "key R", "wait_frames 2", "screenshot c2.exr",
              "scroll 2", "wait_frames 1", "screenshot c3.exr", "key F", "hold W 5",
              "wait_frames 1", "screenshot c4.exr", "quit"]
    # the shadow maps fitted to the camera's frustum follow the viewer's camera
    frustum = ["--set", "shadow.fit=frustum"]
    rc, out, err = view(g, script, args=frustum)
    c = [os.path.join(TMP, "c%d.exr" % i) for i in range(5)]
    check(max_exr_diff(c[1], c[0]) > 1e-2, "the drag did not move the camera")
    check(max_exr_diff(c[2], c[0]) < 1e-6, "R did not restore the graph's camera")
    check(max_exr_diff(c[3], c[0]) > 1e-2, "the wheel did not zoom")
    check(max_exr_diff(c[4], c[3]) > 1e-2, "flying forward did not move the camera")
    start = out.find("cam = camera {")
    check(start >= 0, "C printed no camera node:\n%s" % out[-2000:])
    node = out[start:out.index("}", start) + 1]
    g2 = os.path.join(TMP, "cam.lgraph")
    with open(g, "r") as f:
        text = f.read()
    text = text.replace("scene = bulb", "scene = cam")
    text = text.replace("\ntone = ", node + "\n\ntone = ")
    with open(g2, "w") as f:
        f.write(text.replace('"out.png"', '"cam.exr"'))
    render(g2, os.path.join(TMP, "cam.exr"), frustum)
    d = max_exr_diff(os.path.join(TMP, "cam.exr"), c[1])
    check(d < 0.05, "the printed camera node does not render the dragged view (max %g)" % d)


def t_view_independent():
    """A camera move runs again what depends on the camera and nothing else: with
    `fit = bounds` the shadow maps (LG_NODE_VIEW_INDEPENDENT) render once while phong renders
    on every move; with `fit = frustum` the instance declares itself view dependent
    (lg_set_view_independent) and the maps render again after the move."""
    g = phong_graph()
    script = ["wait_frames 2", "drag 30 0", "wait_frames 2", "scroll 1", "wait_frames 2",
              "quit"]
    counts = {}
    for fit in ("bounds", "frustum"):
        rc, out, err = view(g, script, args=["-v", "--set", "shadow.fit=" + fit])
        counts[fit] = (err.count("node 'shadow' (shadowmap): 1 directional light"),
                       err.count("node 'lit' (phong): "))
    check(counts["bounds"][0] == 1, "fit = bounds: the shadow maps rendered %d times, not once"
          % counts["bounds"][0])
    check(counts["bounds"][1] >= 3, "phong did not render again after the moves (%d runs)"
          % counts["bounds"][1])
    check(counts["frustum"][0] >= 3, "fit = frustum: the shadow maps did not follow the "
          "camera (%d renders)" % counts["frustum"][0])


def t_method():
    g = os.path.join(TMP, "m.lgraph")
    with open(g, "w") as f:
        f.write("""lightgraph 1
include "%s"
lit_a = phong { scene = bulb, shadows = shadow, shading = flat, ks_scale = 20 }
lit_b = phong { scene = bulb, shadows = shadow, shading = phong, ks_scale = 20,
                background = [0.3, 0.1, 0.1] }
tone = reinhard { image = lit_a, key = 0.12 }
output tone "out.png"
""" % os.path.join(SRC, "examples", "phong_scene.lgraph"))
    script = ["wait_frames 2", "screenshot m0.exr", "key M", "expect_ok", "wait_frames 1",
              "screenshot m1.exr", "key M", "expect_ok", "wait_frames 1", "screenshot m2.exr",
              "key O", "quit"]
    rc, out, err = view(g, script)
    m = [os.path.join(TMP, "m%d.exr" % i) for i in range(3)]
    check(max_exr_diff(m[1], m[0]) > 1e-2, "M did not switch the method")
    check(max_exr_diff(m[2], m[0]) < 1e-6, "M twice did not come back")
    check("lit_a -> lit_b" in out and "lit_b -> lit_a" in out,
          "the switches were not reported:\n%s" % out[-2000:])


def t_methods_example():
    """examples/volumetric_methods.lgraph: M cycles froxel -> screen -> polygonal -> froxel
    (file order); the screen-space method reads no shadow maps and froxel has an extra
    output, and both are still alternatives; `lit`, which they are made from, is not. A
    method not shown is culled and its plugin not loaded until it is switched to. The camera
    moves with froxel's temporal reprojection on."""
    g = os.path.join(SRC, "examples", "volumetric_methods.lgraph")
    shots = []
    script = ["wait_frames 2", "screenshot x0.exr", "shell echo SWITCHING >&2"]
    for i in range(1, 5):
        script += ["key M", "expect_ok", "wait_frames 1", "screenshot x%d.exr" % i]
    script += ["drag 8 0", "wait_frames 3", "screenshot x5.exr", "quit"]
    fast = ["--set", "vol_froxel.width=48", "--set", "vol_froxel.height=27",
            "--set", "vol_froxel.depth=32", "--set", "vol_froxel.temporal=true",
            "--set", "shadow.resolution=256", "--size", "96x54", "-v", "-v"]
    rc, out, err = view(g, script, args=fast)
    # since issue 24 the cycle passes "off" (the lit image) after the last method
    # (froxel is the last in file order: off comes first)
    order = ["vol_froxel -> off", "off -> vol_screen", "vol_screen -> vol_polygonal",
             "vol_polygonal -> vol_froxel"]
    for o in order:
        check(("method: %s" % o) in out, "no switch %s:\n%s" % (o, out[-3000:]))
    x = [os.path.join(TMP, "x%d.exr" % i) for i in range(6)]
    for i in (1, 2, 3):
        check(max_exr_diff(x[i], x[0]) > 1e-3, "method %d looks like froxel" % i)
    check(max_exr_diff(x[2], x[3]) > 1e-3, "screen and polygonal look the same")
    check(max_exr_diff(x[5], x[4]) > 1e-3, "the drag did not move the froxel view")
    # the marker goes to the viewer's stderr (the script's shell inherits it), in order
    mark = err.find("SWITCHING")
    check(mark > 0, "the marker is missing from stderr")
    for p in ("volumetric_screen", "volumetric_polygonal"):
        at = err.find("loaded plugin %s " % p)
        check(at > mark, "%s was loaded %s it was switched to" %
              (p, "never when" if at < 0 else "before"))
    check(0 <= err.find("loaded plugin volumetric_froxel ") < mark,
          "volumetric_froxel was not loaded for the first frame")


def t_method_off():
    """M past the last method shows the image without one: "off" passes the methods' `base`
    (the lit image) through, as the thesis's menu has it; M again switches the first method
    on, shift+M from it goes to "off" too. The off picture equals `render` with the tone
    mapper reading `lit` directly."""
    g = os.path.join(SRC, "examples", "volumetric_methods.lgraph")
    fast = ["--set", "vol_froxel.width=48", "--set", "vol_froxel.height=27",
            "--set", "vol_froxel.depth=32", "--set", "shadow.resolution=256"]
    # file order: screen, polygonal, froxel (shown first), then off
    script = ["wait_frames 2", "screenshot o0.exr", "key M", "expect_ok", "key O",
              "wait_frames 1", "screenshot o1.exr", "key M", "expect_ok", "wait_frames 1",
              "screenshot o2.exr", "key shift+M", "expect_ok", "wait_frames 1",
              "screenshot o3.exr", "key shift+M", "expect_ok", "wait_frames 1",
              "screenshot o4.exr", "quit"]
    rc, out, err = view(g, script, args=fast)
    for o in ("vol_froxel -> off (lit passed through)", "off -> vol_screen",
              "vol_screen -> off", "off -> vol_froxel"):
        check(("method: %s" % o) in out, "no switch %s:\n%s" % (o, out[-3000:]))
    check("--set tone.image=lit" in out, "O does not print the off switch:\n%s" % out[-2000:])
    render(g, os.path.join(TMP, "off.exr"), fast + ["--set", "tone.image=lit"])
    o = [os.path.join(TMP, "o%d.exr" % i) for i in range(5)]
    off = os.path.join(TMP, "off.exr")
    check(max_exr_diff(o[1], off) < 1e-3, "off does not show the lit image (max %g)"
          % max_exr_diff(o[1], off))
    check(max_exr_diff(o[3], off) < 1e-3, "shift+M from the first method is not off")
    check(max_exr_diff(o[0], off) > 1e-2, "the froxel method looks like off")
    check(max_exr_diff(o[2], off) > 1e-2, "the screen-space method looks like off")
    check(max_exr_diff(o[4], o[0]) < 1e-3, "shift+M after off is not the froxel method again")


def clock_graph():
    """phong_graph with test_clock (tests/plugins/testnodes/testclock.c) after `lit`: the
    shown image is lit + (time, frame index, 0) per pixel; scene, shadows and lit stay
    static."""
    return phong_graph("clock.lgraph", extra="clk = test_clock { image = lit }")


def red_offsets(a, b):
    """min and max over the pixels of red(a) - red(b)."""
    ra, rb = exr_rows(a), exr_rows(b)
    d = [p[0] - q[0] for r, t in zip(ra, rb) for p, q in zip(r, t)]
    return min(d), max(d)


def t_play():
    """play, pause and time drive lg_frame.time (docs/viewer.md "Animation"): a paused
    clock shows one time, a scrub shows the time asked for (a negative one clamped to 0, a
    huge one to 10^6 s), play advances by --dt a frame, `.` steps one frame and pauses; the
    static nodes upstream (scene, shadow maps, phong) run once through all of it."""
    g = clock_graph()
    plugins = os.environ["LG_TEST_PLUGINS"] + ":" + os.path.join(os.environ["LG_BUILD_ROOT"],
                                                                 "plugins")
    script = ["wait_frames 2", "pause", "time -5", "wait_frames 1", "screenshot t0.exr",
              "time 1.25", "wait_frames 1", "screenshot t1.exr", "wait_frames 3",
              "screenshot t2.exr", "play", "wait_frames 4", "pause", "wait_frames 1",
              "screenshot t3.exr", "time 2", "key PERIOD", "wait_frames 2", "screenshot t4.exr",
              "key shift+COMMA", "wait_frames 1", "screenshot t5.exr",
              "time 1e300", "wait_frames 1", "screenshot t6.exr", "quit"]
    rc, out, err = view(g, script, args=["--show", "clk", "--dt", "0.25", "-v"],
                        env=env_with_display({"LIGHTGRAPH_PLUGIN_PATH": plugins}))
    t = [os.path.join(TMP, "t%d.exr" % i) for i in range(7)]

    def offset(i, want, tol=1e-4):
        lo, hi = red_offsets(t[i], t[0])
        check(abs(lo - want) <= tol and abs(hi - want) <= tol,
              "t%d: red - red(time 0) is %g .. %g, expected %g" % (i, lo, hi, want))
        return lo

    offset(1, 1.25)
    offset(2, 1.25)  # paused: the same time three frames later
    lo, _ = red_offsets(t[3], t[0])
    steps = (lo - 1.25) / 0.25
    check(steps >= 3 and abs(steps - round(steps)) < 1e-3,
          "playing did not advance by --dt a frame: %g s after 1.25" % lo)
    offset(3, lo)
    offset(4, 2.25)  # `.`: one frame of 0.25 s, paused
    offset(5, 0.0)   # shift+,: ten frames back from 2.25, clamped at 0
    offset(6, 1e6, tol=0.2)
    check("clamped to [0, 1e+06]" in out, "the clamp was not reported:\n" + out[-2000:])
    runs = err.count("node 'lit' (phong): ")
    check(runs == 1, "phong (static, upstream of the clock) ran %d times, not once" % runs)
    runs = err.count("node 'shadow' (shadowmap): 1 directional light")
    check(runs == 1, "the shadow maps (static) rendered %d times, not once" % runs)


def t_anim():
    """An animated glTF (a cube keyed from x = -1 at 0 s to x = +1 at 1 s, tools/gen_scene.py)
    through preview, which the planner runs per frame: the viewer's `time T` shows the pose
    `render --frames N --dt 0.25` draws at that time; paused, the pose holds and preview does
    not run again (the nodes per frame only for the animation wait for the time to move);
    playing, it runs every frame."""
    glb = os.path.join(TMP, "moving.glb")
    p = subprocess.run([sys.executable, os.path.join(SRC, "tools", "gen_scene.py"), "cube",
                        "--anim-translation", "0:-1,0,0;1:1,0,0", "-q", "-o", glb],
                       capture_output=True, text=True, timeout=60)
    check(p.returncode == 0, "gen_scene.py failed: " + p.stderr)
    g = os.path.join(TMP, "anim.lgraph")
    with open(g, "w") as f:
        f.write('lightgraph 1\nscene = gltf { file = "%s" }\nv = preview { scene = scene }\n'
                'output v "anim.exr"\n' % glb)
    script = ["wait_frames 2", "pause", "time 0.25", "wait_frames 1", "screenshot a1.exr",
              "shell echo PAUSED >&2", "wait_frames 5", "shell echo MOVED >&2",
              "screenshot a2.exr", "time 0.75", "wait_frames 1", "screenshot a3.exr",
              "shell echo PLAYING >&2", "play", "wait_frames 4", "shell echo END >&2", "quit"]
    rc, out, err = view(g, script, args=["--dt", "0.25", "-v"])
    for frames, name in ((2, "r1.exr"), (4, "r3.exr")):
        render(g, os.path.join(TMP, name), ["--frames", str(frames), "--dt", "0.25"])
    a = [os.path.join(TMP, "a%d.exr" % i) for i in (1, 2, 3)]
    d = max_exr_diff(a[0], os.path.join(TMP, "r1.exr"))
    check(d < 1e-3, "time 0.25 differs from render's frame at 0.25 s by %g" % d)
    d = max_exr_diff(a[2], os.path.join(TMP, "r3.exr"))
    check(d < 1e-3, "time 0.75 differs from render's frame at 0.75 s by %g" % d)
    check(max_exr_diff(a[1], a[0]) == 0, "paused, the picture changed")
    check(max_exr_diff(a[2], a[0]) > 0.1, "the cube did not move from 0.25 to 0.75 s")
    run = "node 'v' (preview): "

    def runs_between(m0, m1):
        i, j = err.find(m0), err.find(m1)
        check(0 <= i < j, "markers %s, %s missing:\n%s" % (m0, m1, err[-3000:]))
        return err[i:j].count(run)

    check(runs_between("PAUSED", "MOVED") == 0,
          "preview ran %d times while paused" % runs_between("PAUSED", "MOVED"))
    check(runs_between("MOVED", "PLAYING") == 1, "time 0.75 did not run preview once")
    check(runs_between("PLAYING", "END") >= 3, "playing, preview did not run every frame")


def t_resize():
    """The render follows the window's framebuffer (docs/viewer.md "Window size"): after a
    scripted resize to 200x120 the shown image is 200x120 and equals `render --size
    200x120`; the window's pixels are that size too; the loaded scene is adopted, not loaded
    again. A 0x0 framebuffer (minimised) renders nothing and does not crash; the window
    back at 120x200 renders at 120x200."""
    g = phong_graph()
    script = ["key H", "wait_frames 2", "resize 200 120", "wait_reload 60", "expect_ok",
              "wait_frames 2", "screenshot r1.exr", "screenshot_window w1.png",
              "resize 0 0", "wait_frames 10", "resize 120 200", "wait_reload 60", "expect_ok",
              "wait_frames 2", "screenshot r2.exr", "quit"]
    rc, out, err = view(g, script, args=["-v", "-v"])
    render(g, os.path.join(TMP, "h1.exr"), ["--size", "200x120"])
    render(g, os.path.join(TMP, "h2.exr"), ["--size", "120x200"])
    for shot, ref, w, h in (("r1.exr", "h1.exr", 200, 120), ("r2.exr", "h2.exr", 120, 200)):
        rows = exr_rows(os.path.join(TMP, shot))
        check(len(rows) == h and len(rows[0]) == w,
              "%s is %dx%d, not %dx%d" % (shot, len(rows[0]), len(rows), w, h))
        d = max_exr_diff(os.path.join(TMP, shot), os.path.join(TMP, ref))
        check(d < 1e-3, "%s differs from render at %dx%d by %g" % (shot, w, h, d))
    render(g, os.path.join(TMP, "h1.png"), ["--size", "200x120"])
    d = max_png_diff(os.path.join(TMP, "w1.png"), os.path.join(TMP, "h1.png"))
    check(d <= 0.019, "the window's pixels are not the 200x120 render (%g)" % d)
    check("render size 200x120" in out and "render size 120x200" in out,
          "the resizes were not reported:\n" + out[-2000:])
    # the mesh loader (no image output, never asks the render size) is kept across sizes
    check("node 'scene' kept from the previous plan" in err,
          "the scene was loaded again at the new size:\n" + err[-3000:])


def main():
    global XV
    name = sys.argv[1] if len(sys.argv) > 1 else ""
    tests = {k[2:]: v for k, v in globals().items() if k.startswith("t_")}
    if name not in tests:
        print("usage: test_viewer.py TEST (%s)" % " ".join(sorted(tests)))
        return 2
    if name != "no_display":
        XV = Xvfb()
    try:
        tests[name]()
    except Fail as e:
        print("FAIL %s: %s" % (name, e))
        return 1
    finally:
        if XV:
            XV.close()
        shutil.rmtree(TMP, ignore_errors=True)
    print("ok %s" % name)
    return 0


if __name__ == "__main__":
    sys.exit(main())
