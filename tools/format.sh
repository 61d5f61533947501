#!/bin/sh
# The tree's C and C++ formatted with clang-format 14 (Debian 12) and the root's .clang-format
# (docs/style.md says what it does and how it was chosen).
#
#   sh tools/format.sh --check [FILES]  lists each file clang-format would change, with the
#                                       first hunk of its diff; exit 1 if there is one
#   sh tools/format.sh --fix [FILES]    formats those files in place and names each one
#   sh tools/format.sh --list           the files the two above look at
#
# Without FILES: every *.c, *.h, *.cpp, *.hpp and *.cc under host/ sdk/ plugins/ tests/ tools/
# but build directories (build, build-*) and what .clang-format-ignore lists (generated and
# third-party code). Named FILES of another kind, or listed there, are skipped with a note.
# Exit status: 0 all formatted (or fixed), 1 a file is not formatted (--check) or could not
# be written (--fix), 2 bad usage, a missing file, or no clang-format 14.
# CLANG_FORMAT=path picks the binary (default: clang-format-14, else clang-format); another
# major version formats differently, so it is refused rather than trusted.
# -f: the ignore patterns are matched with `case`, never expanded as globs against the disk.
set -uf
ROOT=$(cd "$(dirname "$0")/.." && pwd)
STYLE="$ROOT/.clang-format"
IGNORE="$ROOT/.clang-format-ignore"

usage() {
    echo "usage: sh tools/format.sh --check [FILES] | --fix [FILES] | --list" >&2
    exit 2
}

[ $# -ge 1 ] || usage
mode=$1
shift
case "$mode" in
--check | --fix) ;;
--list) [ $# -eq 0 ] || usage ;;
*) usage ;;
esac

# The glob patterns of .clang-format-ignore, one a line, comments and blanks dropped.
patterns=""
if [ -f "$IGNORE" ]; then
    patterns=$(sed -e 's/#.*//' -e 's/^[[:space:]]*//' -e 's/[[:space:]]*$//' "$IGNORE" |
        grep -v '^$')
fi

# is_ignored REL: true if the path REL (relative to the root) matches a pattern. `case`
# globbing: `*` matches `/` too, so `*/stb_*.h` finds the header at any depth.
is_ignored() {
    [ -n "$patterns" ] || return 1
    old_ifs=$IFS
    IFS='
'
    for p in $patterns; do
        IFS=$old_ifs
        # shellcheck disable=SC2254 # the pattern is meant to glob
        case "$1" in $p) return 0 ;; esac
    done
    IFS=$old_ifs
    return 1
}

is_source() {
    case "$1" in *.c | *.h | *.cpp | *.hpp | *.cc) return 0 ;; esac
    return 1
}

# Every file of the tree the formatter owns, relative to the root, sorted.
tree_files() {
    (cd "$ROOT" && find host sdk plugins tests tools \
        \( -type d \( -name build -o -name 'build-*' -o -name .git \) -prune \) -o \
        -type f \( -name '*.c' -o -name '*.h' -o -name '*.cpp' -o -name '*.hpp' \
        -o -name '*.cc' \) -print) | LC_ALL=C sort | while IFS= read -r f; do
        is_ignored "$f" || printf '%s\n' "$f"
    done
}

if [ "$mode" = --list ]; then
    tree_files
    exit 0
fi

# clang-format 14, or a message that says how to get it.
if [ -n "${CLANG_FORMAT:-}" ]; then
    cf=$CLANG_FORMAT
elif command -v clang-format-14 >/dev/null 2>&1; then
    cf=clang-format-14
else
    cf=clang-format
fi
if ! command -v "$cf" >/dev/null 2>&1; then
    echo "format.sh: '$cf' not found: install Debian's clang-format (14) with 'sh tools/deps.sh'" >&2
    exit 2
fi
version=$("$cf" --version 2>/dev/null)
case "$version" in
*"clang-format version 14."*) ;;
*)
    echo "format.sh: '$cf' is not clang-format 14 ('$version'): other versions format" \
        "differently; install Debian 12's with 'sh tools/deps.sh' or set CLANG_FORMAT" >&2
    exit 2
    ;;
esac
[ -f "$STYLE" ] || {
    echo "format.sh: $STYLE is missing" >&2
    exit 2
}

tmp=$(mktemp "${TMPDIR:-/tmp}/lg-format.XXXXXX") || exit 1
list=$(mktemp "${TMPDIR:-/tmp}/lg-format-list.XXXXXX") || exit 1
trap 'rm -f "$tmp" "$list"' EXIT
trap 'exit 1' INT TERM HUP

# The files to look at, one a line, as the user named them or relative to the root.
if [ $# -eq 0 ]; then
    tree_files | sed "s|^|$ROOT/|" >"$list"
else
    : >"$list"
    for f in "$@"; do
        if [ ! -f "$f" ]; then
            echo "format.sh: $f: no such file" >&2
            exit 2
        fi
        abs=$(realpath "$f")
        rel=${abs#"$ROOT"/}
        if ! is_source "$f"; then
            echo "format.sh: $f: not C or C++ (*.c *.h *.cpp *.hpp *.cc), skipped" >&2
        elif [ "$rel" != "$abs" ] && is_ignored "$rel"; then
            echo "format.sh: $f: listed in .clang-format-ignore, skipped" >&2
        else
            printf '%s\n' "$f" >>"$list"
        fi
    done
fi

# One clang-format over every file (--dry-run names each file it would change, with its
# first violation) instead of one process per file: the whole tree then takes a second, not
# hundreds of process starts. Only the files it names are formatted one by one, for the diff
# or the rewrite.
flagged=$(mktemp "${TMPDIR:-/tmp}/lg-format-flagged.XXXXXX") || exit 1
errs=$(mktemp "${TMPDIR:-/tmp}/lg-format-err.XXXXXX") || exit 1
trap 'rm -f "$tmp" "$tmp.cf" "$list" "$flagged" "$errs"' EXIT
checked=$(wc -l <"$list")
status=0
if [ "$checked" -gt 0 ]; then
    if ! xargs -d '\n' "$cf" --style="file:$STYLE" --dry-run --ferror-limit=1 <"$list" \
        2>"$errs" >/dev/null; then
        grep -v -e "-Wclang-format-violations" "$errs" | grep -iE "error|no such" | head -5 >&2
        echo "format.sh: clang-format failed (above)" >&2
        exit 1
    fi
    sed -n 's/^\(.*\):[0-9]*:[0-9]*: warning: code should be clang-formatted \[-Wclang-format-violations\]$/\1/p' \
        "$errs" | awk '!seen[$0]++' >"$flagged"
fi

unformatted=0
while IFS= read -r f; do
    shown=${f#"$ROOT"/}
    # then tools/comment_align.py: a trailing comment's continuation lines under its
    # opening again (clang-format 14 moves only the opening line of such a comment)
    if ! "$cf" --style="file:$STYLE" "$f" >"$tmp.cf" ||
        ! python3 "$ROOT/tools/comment_align.py" <"$tmp.cf" >"$tmp"; then
        echo "format.sh: $shown: clang-format failed" >&2
        status=1
        continue
    fi
    cmp -s "$f" "$tmp" && continue
    unformatted=$((unformatted + 1))
    if [ "$mode" = --check ]; then
        echo "not formatted: $shown"
        # the first hunk, at most 40 lines of it, indented under the name
        case "$shown" in /*) a=a$shown b=b$shown ;; *) a=a/$shown b=b/$shown ;; esac
        diff -u "$f" "$tmp" | awk -v a="$a" -v b="$b" '
            NR == 1 { print "    --- " a; next }
            NR == 2 { print "    +++ " b; next }
            /^@@/ { if (++h > 1) exit }
            { if (++n > 40) { print "    ..."; exit } print "    " $0 }'
        status=1
    else
        # cat, not mv: the file keeps its mode, owner and links
        if cat "$tmp" >"$f"; then
            echo "formatted: $shown"
        else
            echo "format.sh: $shown: could not be written" >&2
            status=1
        fi
    fi
done <"$flagged"

if [ "$mode" = --check ] && [ $unformatted -gt 0 ]; then
    echo "format.sh: $unformatted of $checked files not formatted; 'sh tools/format.sh --fix' formats them" >&2
elif [ "$mode" = --check ]; then
    echo "format.sh: $checked files formatted" >&2
else
    echo "format.sh: $unformatted of $checked files reformatted" >&2
fi
exit $status
