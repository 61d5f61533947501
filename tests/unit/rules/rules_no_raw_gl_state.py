#!/usr/bin/env python3
"""No raw GL state inside passes, and one `backend` parameter (issue 21, ABI 3.0).

Plugins (plugins/) and the template (sdk/template/) set GL state only through lg_gl_pass:
the depth function in the descriptor (depth_func), sampler state and the seamless-cube
switch in the texture binding (lg_gl_pass_bind_texture_sampled), arrays, mat3 and uniform
blocks through the pass's setters (lg_gl_set_*, lg_gl_pass_uniforms). So none of
`DepthFunc`, `->Enable(`, `->Disable(`, `CreateSamplers`, `SamplerParameter`, `BindSampler`,
`ProgramUniform` appears in their C sources (comments aside). And no plugin declares or reads
the `backend` parameter by hand: LG_PARAM_BACKEND declares it, lg_param_backend() maps it to
the device, so the string "backend" does not appear in plugins/ C sources.

Each hit is printed as file:line: the code, with the rule it breaks. Before the tree is
checked, the same scan runs on a planted file with one line per rule, so that a rule which
no longer matches anything fails here rather than passing forever.

usage: rules_no_raw_gl_state.py SOURCE_ROOT
"""
import os
import re
import sys
import tempfile

GL_RULES = [
    (re.compile(r"DepthFunc"), "glDepthFunc: set lg_gl_pass_desc.depth_func"),
    (re.compile(r"->\s*Enable\s*\("), "glEnable: the pass's descriptor or sampler says it"),
    (re.compile(r"->\s*Disable\s*\("), "glDisable: the pass's descriptor or sampler says it"),
    (re.compile(r"CreateSamplers"), "sampler objects: lg_gl_pass_bind_texture_sampled"),
    (re.compile(r"SamplerParameter"), "sampler objects: lg_gl_pass_bind_texture_sampled"),
    (re.compile(r"BindSampler"), "sampler objects: lg_gl_pass_bind_texture_sampled"),
    (re.compile(r"ProgramUniform"), "raw uniforms: lg_gl_set_* or lg_gl_pass_uniforms"),
]
BACKEND_RULE = (re.compile(r'"backend"'),
                "the backend parameter by hand: LG_PARAM_BACKEND and lg_param_backend()")
SOURCES = (".c", ".h", ".cpp")


def strip_comments(text):
    """The text with /* */ and // comments blanked, line breaks kept (strings are kept:
    "backend" is a string)."""
    out, i, n = [], 0, len(text)
    in_str = None
    while i < n:
        c = text[i]
        if in_str:
            out.append(c)
            if c == "\\" and i + 1 < n:
                out.append(text[i + 1])
                i += 2
                continue
            if c == in_str:
                in_str = None
            i += 1
        elif c in "\"'":
            in_str = c
            out.append(c)
            i += 1
        elif text.startswith("/*", i):
            j = text.find("*/", i + 2)
            j = n if j < 0 else j + 2
            out.append("".join(ch if ch == "\n" else " " for ch in text[i:j]))
            i = j
        elif text.startswith("//", i):
            j = text.find("\n", i)
            j = n if j < 0 else j
            out.append(" " * (j - i))
            i = j
        else:
            out.append(c)
            i += 1
    return "".join(out)


def scan(root, folders, rules):
    hits = []
    for folder in folders:
        top = os.path.join(root, folder)
        for dirpath, dirnames, files in os.walk(top):
            dirnames.sort()
            for f in sorted(files):
                if not f.endswith(SOURCES):
                    continue
                path = os.path.join(dirpath, f)
                with open(path, encoding="utf-8", errors="replace") as fh:
                    code = strip_comments(fh.read())
                for ln, line in enumerate(code.split("\n"), 1):
                    for rx, why in rules:
                        if rx.search(line):
                            hits.append("%s:%d: %s  [%s]" % (os.path.relpath(path, root), ln,
                                                            line.strip(), why))
    return hits


def main():
    if len(sys.argv) != 2:
        print(__doc__.strip().splitlines()[-1])
        return 2
    root = sys.argv[1]
    fail = 0

    # the rules catch what they are about (and not a comment)
    planted = [
        "gl->DepthFunc(GL_ALWAYS);",
        "gl->Enable(GL_TEXTURE_CUBE_MAP_SEAMLESS);",
        "gl -> Disable (GL_BLEND);",
        "gl->CreateSamplers(1, &s);",
        "gl->SamplerParameteri(s, GL_TEXTURE_MIN_FILTER, GL_NEAREST);",
        "gl->BindSampler(0, s);",
        "gl->ProgramUniformMatrix3fv(prog, loc, 1, GL_FALSE, m);",
        '{ .key = "backend", .type = LG_PARAM_ENUM },',
        "/* gl->DepthFunc(GL_ALWAYS) in a comment is fine */",
        "// so is gl->Enable(GL_BLEND) here",
    ]
    with tempfile.TemporaryDirectory() as tmp:
        os.makedirs(os.path.join(tmp, "plugins", "bad"))
        with open(os.path.join(tmp, "plugins", "bad", "bad.c"), "w") as fh:
            fh.write("\n".join(planted) + "\n")
        got = scan(tmp, ["plugins"], GL_RULES + [BACKEND_RULE])
        want = ["plugins/bad/bad.c:%d:" % i for i in range(1, 9)]
        lines = sorted({h.split(" ")[0] for h in got})
        if lines != want:
            print("FAIL: the rules' self-check: planted violations on lines 1..8 (and two in "
                  "comments on 9, 10); found:")
            print("\n".join(got) or "(nothing)")
            fail = 1

    hits = scan(root, ["plugins", os.path.join("sdk", "template")], GL_RULES)
    hits += scan(root, ["plugins"], [BACKEND_RULE])
    if hits:
        print("FAIL: raw GL state or a hand-made backend parameter in plugins (ABI 3.0: "
              "docs/sdk.md \"Migrating from ABI 2\"):")
        print("\n".join(hits))
        fail = 1
    if not fail:
        print("rules_no_raw_gl_state: no raw GL state calls and no hand-made backend "
              "parameter in plugins/ and sdk/template/")
    return fail


if __name__ == "__main__":
    sys.exit(main())
