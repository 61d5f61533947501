#!/usr/bin/env python3
"""The viewer keeps its state in its own struct: no globals (issue 22, host/viewer/state.h).

    check_no_globals.py LIBRARY [--expect-some CONTROL_LIBRARY]

Reads the symbol table of the compiled static LIBRARY (objdump -t), so that what counts is
what the compiler made, not what a reading of the sources guesses: every data object it
defines must be read-only (.rodata, or .data.rel.ro for a const table of pointers). A
writable one (.data, .bss, thread-local, common) is printed as OBJECT.o: SYMBOL (SECTION)
and the exit status is 1. The one exception the viewer may need is a `volatile
sig_atomic_t` flag for a signal handler, named in ALLOWED with the reason (none today).

--expect-some first runs the same check on CONTROL_LIBRARY, a library known to hold
writable globals (the base layer's lg_verbosity), and fails if it finds none there: a check
that finds nothing cannot pass by accident.
"""
import subprocess
import sys

# symbol -> why it must be a global (only a signal handler's flag qualifies)
ALLOWED = {}


def writable_section(section):
    if section.startswith(".data.rel.ro") or section.startswith(".rodata"):
        return False
    return (section == ".data" or section.startswith(".data.") or section.startswith(".bss")
            or section.startswith(".tdata") or section.startswith(".tbss")
            or section == "*COM*")


def writable_objects(library):
    out = subprocess.run(["objdump", "-t", library], capture_output=True, text=True,
                         check=True).stdout
    found = []
    member = "?"
    for line in out.splitlines():
        if "file format" in line:  # "viewer.c.o:     file format elf64-x86-64"
            member = line.split(":")[0]
            continue
        # "0000000000000208 l     O .bss	0000000000000008 g_viewer"
        parts = line.split()
        if len(parts) < 5 or " O " not in line:
            continue
        name = parts[-1]
        section = parts[-3]
        if writable_section(section) and name not in ALLOWED:
            found.append(f"{member}: {name} ({section})")
    return found


def main(argv):
    if len(argv) not in (2, 4) or (len(argv) == 4 and argv[2] != "--expect-some"):
        print(__doc__, file=sys.stderr)
        return 2
    if len(argv) == 4:
        control = writable_objects(argv[3])
        if not control:
            print(f"self-test: no writable global found in {argv[3]}, which has some: the "
                  "check reads nothing", file=sys.stderr)
            return 1
        print(f"self-test: {len(control)} writable global(s) found in the control library, "
              f"e.g. {control[0]}")
    found = writable_objects(argv[1])
    for f in found:
        print(f"{f}: a writable global in the viewer layer (keep it in the viewer struct, "
              "host/viewer/state.h)")
    if found:
        return 1
    print(f"{argv[1]}: no writable global")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
