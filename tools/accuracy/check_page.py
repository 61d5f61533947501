"""check_page.py: what a made accuracy page must hold (the tests accuracy_quick and
accuracy_generator): per section one anchor, one heading, one plot (a PNG that exists) and one
answer line, and a table per study; the head's how-it-was-made and how-to-read."""
import os
import re


def check_page(out, sections):
    """sections: [(name, title, [study ids] or None: those whose tables the page has, at least
    one)]. Returns a list of problems (empty: good)."""
    page = os.path.join(out, "accuracy.md")
    if not os.path.exists(page):
        return ["%s was not written" % page]
    with open(page) as f:
        text = f.read()
    bad = []
    for must in ("**How it was made.**", "**How to read it.**", "Pareto front", "DSSIM",
                 "relative RMSE", "median"):
        if must not in text:
            bad.append("the page's head does not say %r" % must)
    # split at the anchors the generator writes before each section
    parts = re.split(r'^<a id="([a-z0-9_]+)"></a>$', text, flags=re.M)
    found = dict(zip(parts[1::2], parts[2::2]))
    for name, title, ids in sections:
        body = found.get(name)
        if body is None:
            bad.append("section %s: no anchor" % name)
            continue
        if body.count("\n## %s\n" % title) != 1:
            bad.append("section %s: heading '## %s' not there once" % (name, title))
        plots = re.findall(r"^!\[[^\]]*\]\((images/accuracy/[^)]+\.png)\)$", body, re.M)
        if len(plots) != 1:
            bad.append("section %s: %d plots, want 1" % (name, len(plots)))
        for p in plots:
            path = os.path.join(out, p)
            if not os.path.exists(path):
                bad.append("section %s: plot %s does not exist" % (name, path))
            else:
                with open(path, "rb") as f:
                    if f.read(8) != b"\x89PNG\r\n\x1a\n":
                        bad.append("section %s: %s is not a PNG" % (name, path))
        answers = [ln for ln in body.splitlines() if ln.startswith("**Answer:**")]
        if len(answers) != 1:
            bad.append("section %s: %d answer lines, want 1" % (name, len(answers)))
        elif not re.search(r"^\*\*Answer:\*\* (for .+: .+ on (cpu|gl|cl)|no setting swept "
                           r"reaches .+ at .+)", answers[0]):
            bad.append("section %s: answer line malformed: %s" % (name, answers[0]))
        if ids is None:
            # the line under each study's heading: "`id`: technique on backend, against ..."
            ids = re.findall(r"^`([a-z0-9_]+)`: \S+ on [a-z /]+, against ", body, re.M)
            if not ids:
                bad.append("section %s: no study table" % name)
        for sid in ids:
            if "`%s`:" % sid not in body:
                bad.append("section %s: no table of study %s" % (name, sid))
            csvp = os.path.join(out, "images/accuracy/data/%s-%s.csv" % (name, sid))
            if not os.path.exists(csvp):
                bad.append("section %s: %s was not written" % (name, csvp))
        for img in re.findall(r"\]\((images/accuracy/[^)]+)\)", body):
            if not os.path.exists(os.path.join(out, img)):
                bad.append("section %s: links %s, which does not exist" % (name, img))
    extra = set(found) - {n for n, _, _ in sections}
    if extra:
        bad.append("sections on the page that were not expected: %s" % ", ".join(sorted(extra)))
    return bad
