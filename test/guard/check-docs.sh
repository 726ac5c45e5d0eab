#!/bin/sh
# check-docs [--record DIR] [--root DIR] [FILE.md...]: every command the user documentation shows runs as written.
# For each line of a shell code block (``` with no language, sh, bash, shell or console) in README.md, doc/*.md
# and doc/*/*.md (or the FILEs given), split at |, ;, && and ||:
#  - `make [VAR=value]... [-j N] GOAL...`: each GOAL is a target of the Makefile under --root (read from
#    `make -p` with the same VAR=value assignments, so nothing is built or run), or a file a pattern rule makes;
#  - `hzrt COMMAND ...`, `hzbake ...`, `hzbench ...`, `hzerrtime ...` (any path to them): the command is one
#    hzrt lists, and every option named (`--x`, `--x=v`, `-x`) is in that program's (or command's) --help;
# and in every line of the files: no `issue N` and no 7- or 40-digit hexadecimal word (a commit hash).
# Each problem is printed as FILE:LINE: what is wrong; the guard fails if there is one.
# The programs: $HZ_DOCS_HZRT, $HZ_DOCS_HZBAKE, $HZ_DOCS_HZBENCH, $HZ_DOCS_HZERRTIME (default the host-sim and
# host builds under --root); a program that is missing is a failure, not a skip.
set -u
. "$(dirname "$0")/lib.sh"
root=.
[ "${1:-}" = "--root" ] && { root=$2; shift 2; }
if [ $# -eq 0 ]; then
    set -- "$root"/README.md "$root"/doc/*.md "$root"/doc/*/*.md
fi
hzrt=${HZ_DOCS_HZRT:-$root/build/host-sim/bin/hzrt}
hzbake=${HZ_DOCS_HZBAKE:-$root/build/host/bin/hzbake}
hzbench=${HZ_DOCS_HZBENCH:-$root/build/host-sim/bin/hzbench}
hzerrtime=${HZ_DOCS_HZERRTIME:-$root/build/host-sim/bin/hzerrtime}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
problems=$tmp/problems
: >"$problems"
say() { echo "$1" >>"$problems"; }

# The commands: FILE:LINE<TAB>text, continuation lines joined, comments and prompts removed.
awk '
    FNR == 1 { fence = 0; cont = "" }
    /^[[:space:]]*```/ {
        if (!fence) { lang = $0; sub(/^[[:space:]]*```[[:space:]]*/, "", lang); fence = 1
                      shell = (lang == "" || lang == "sh" || lang == "bash" || lang == "shell" || lang == "console") }
        else fence = 0
        next
    }
    fence && shell {
        line = $0
        if (cont == "") start = FNR
        sub(/^[[:space:]]*\$[[:space:]]+/, "", line)
        if (line ~ /\\$/) { sub(/\\$/, "", line); cont = cont line " "; next }
        line = cont line; cont = ""
        # a comment: "#" at the start of a word (not inside a word such as a URL fragment)
        sub(/(^|[[:space:]])#.*$/, "", line)
        # inside quotes, blanks and | ; & are not separators: hide them (\001) so that splitting keeps one word
        out = ""; q = ""
        for (i = 1; i <= length(line); i++) {
            ch = substr(line, i, 1)
            if (q == "" && (ch == "\"" || ch == "\047")) q = ch
            else if (ch == q) q = ""
            else if (q != "" && (ch == " " || ch == "|" || ch == ";" || ch == "&")) ch = "\001"
            out = out ch
        }
        line = out
        if (line ~ /[^[:space:]]/) printf "%s:%d\t%s\n", FILENAME, start, line
    }
' "$@" >"$tmp/commands"

# help TEXT of a program (and command), cached; 1 when the program is missing or refuses --help.
help_of() { # KEY PROGRAM [ARG...]
    key=$1
    shift
    if [ ! -f "$tmp/help-$key" ]; then
        if [ ! -x "$1" ]; then
            echo "missing" >"$tmp/help-$key.status"
        elif "$@" --help >"$tmp/help-$key" 2>&1; then
            echo "ok" >"$tmp/help-$key.status"
        elif [ "$(od -An -tx1 -j18 -N2 "$1" | tr -d ' ')" = b700 ] && command -v qemu-aarch64-static >/dev/null &&
            qemu-aarch64-static -cpu cortex-a72 -L /usr/aarch64-linux-gnu -E LD_LIBRARY_PATH=/lib:/usr/lib/aarch64-linux-gnu "$@" --help >"$tmp/help-$key" 2>&1; then
            echo "ok" >"$tmp/help-$key.status" # an AArch64 build (e_machine 183), run under qemu as the board launcher does
        else
            echo "refused" >"$tmp/help-$key.status"
        fi
        touch "$tmp/help-$key"
    fi
    [ "$(cat "$tmp/help-$key.status")" = ok ]
}

# make targets for a set of assignments, cached: explicit targets, and pattern targets as %-patterns.
targets_of() { # ASSIGNMENTS...
    key=$(printf '%s\n' "$@" | cksum | cut -d' ' -f1)
    if [ ! -f "$tmp/targets-$key" ]; then
        env -i PATH="$PATH" HOME="${HOME:-/}" make -C "$root" -pq --no-print-directory "$@" .hz-docs-probe \
            2>/dev/null | awk '
            /^# Not a target:/ { skip = 1; next }
            /^[^#\t[:space:]][^=\t]*:([^=]|$)/ {
                t = $0; sub(/:.*/, "", t)
                if (!skip && t != ".hz-docs-probe") { n = split(t, a, " "); for (i = 1; i <= n; i++) print a[i] }
            }
            { skip = 0 }' | sort -u >"$tmp/targets-$key"
    fi
    echo "$tmp/targets-$key"
}

is_target() { # FILE GOAL
    grep -qxF -- "$2" "$1" && return 0
    case $2 in */*) ;; *) return 1 ;; esac
    # a file goal: some pattern rule's target matches it
    for p in $(grep '%' "$1"); do
        pre=${p%%%*} suf=${p#*%}
        case $2 in "$pre"*"$suf") return 0 ;; esac
    done
    return 1
}

check_make() { # WHERE ARGS...
    where=$1
    shift
    assigns= goals=
    while [ $# -gt 0 ]; do
        case $1 in
            -C|-f|-j|-l|-o|-W|-I) shift ;;
            -*) ;;
            *=*) assigns="$assigns $1" ;;
            *) goals="$goals $1" ;;
        esac
        [ $# -gt 0 ] && shift
    done
    # shellcheck disable=SC2086
    file=$(targets_of $assigns)
    if [ ! -s "$file" ]; then
        say "$where: make$assigns: the Makefile under $root does not parse"
        return
    fi
    for g in $goals; do
        is_target "$file" "$g" || say "$where: make $g: no such target"
    done
}

check_prog() { # WHERE KEY PROGRAM ARGS...
    where=$1 key=$2 prog=$3
    shift 3
    name=$(basename "$prog")
    case $key in
        hzrt)
            cmd=
            for a in "$@"; do
                case $a in -*) ;; *) cmd=$a; break ;; esac
            done
            if [ -n "$cmd" ]; then
                help_of hzrt "$prog" || { say "$where: $prog: $(cat "$tmp/help-hzrt.status") (cannot check '$name $*')"; return; }
                # the commands hzrt lists: indented words in its help between "commands:" and the next section
                if ! awk '/^commands:/ { c = 1; next } /^[^ ]/ { c = 0 } c && /^  [a-z]/ { print $1 }' \
                        "$tmp/help-hzrt" | grep -qxF -- "$cmd"; then
                    say "$where: hzrt $cmd: no such command"
                    return
                fi
                help_of "hzrt-$cmd" "$prog" "$cmd" || { say "$where: hzrt $cmd --help: $(cat "$tmp/help-hzrt-$cmd.status")"; return; }
                key=hzrt-$cmd
            else
                help_of hzrt "$prog" || { say "$where: $prog: $(cat "$tmp/help-hzrt.status") (cannot check '$name $*')"; return; }
            fi ;;
        *)
            help_of "$key" "$prog" || { say "$where: $prog: $(cat "$tmp/help-$key.status") (cannot check '$name $*')"; return; }
    esac
    for a in "$@"; do
        case $a in
            --|-|-[0-9]*|-.*) continue ;;
            --help|-h|--version) continue ;;
            --*|-[A-Za-z]*) o=${a%%=*} ;;
            *) continue ;;
        esac
        # the option as a word of the help text: followed by a blank, a comma, '=', ']', '|' or the line's end
        grep -qE -- "(^|[^A-Za-z0-9-])$o([][ ,=|/]|\$)" "$tmp/help-$key" || say "$where: $name: no option $o (not in '${key#hzrt-} --help')"
    done
}

tab=$(printf '\t')
while IFS="$tab" read -r where text; do
    # one simple command per line: split at |, ;, && and ||
    printf '%s\n' "$text" | sed 's/&&/\n/g; s/||/\n/g; s/[|;]/\n/g' | while read -r seg; do
        # shellcheck disable=SC2086
        set -f
        set -- $seg
        set +f
        # leading assignments and wrappers
        while [ $# -gt 0 ]; do
            case $1 in
                [A-Za-z_]*=*) shift ;;
                nice|time|sudo|exec|env) shift ;;
                -n) shift; [ $# -gt 0 ] && shift ;;
                timeout) shift; [ $# -gt 0 ] && shift ;;
                *) break ;;
            esac
        done
        [ $# -gt 0 ] || continue
        case $(basename -- "$1") in
            make) shift; check_make "$where" "$@" ;;
            hzrt) p=$1; shift; check_prog "$where" hzrt "$(case $p in */*) [ -x "$p" ] && echo "$p" || echo "$hzrt" ;; *) echo "$hzrt" ;; esac)" "$@" ;;
            hzbake) shift; check_prog "$where" hzbake "$hzbake" "$@" ;;
            hzbench) shift; check_prog "$where" hzbench "$hzbench" "$@" ;;
            hzerrtime) shift; check_prog "$where" hzerrtime "$hzerrtime" "$@" ;;
        esac
    done
done <"$tmp/commands"

# Issue numbers and commit hashes, anywhere in the files.
grep -nHiE '(^|[^A-Za-z])issues?[[:space:]]+#?[0-9]+' "$@" | while IFS= read -r l; do
    say "${l%%:*}:$(echo "$l" | cut -d: -f2): names an issue number: $(echo "$l" | cut -d: -f3- | grep -oiE 'issues?[[:space:]]+#?[0-9]+' | head -n 1)"
done
grep -nHoE '(^|[^0-9A-Za-z])([0-9a-f]{40}|[0-9a-f]{7})([^0-9A-Za-z]|$)' "$@" | while IFS= read -r l; do
    h=$(echo "$l" | cut -d: -f3- | grep -oE '[0-9a-f]{7,40}')
    # a hash mixes digits and letters; an all-digit number or a word like "defaced" is not one
    case $h in *[0-9]*) ;; *) continue ;; esac
    case $h in *[a-f]*) ;; *) continue ;; esac
    say "$(echo "$l" | cut -d: -f1-2): a commit hash: $h"
done

n=$(wc -l <"$tmp/commands")
if [ -s "$problems" ]; then
    echo "check-docs: $(wc -l <"$problems") problem(s) in the documentation:"
    sed 's/^/  /' "$problems"
    record "guard/docs" 0 1
    exit 1
fi
echo "check-docs: ok ($n commands in $# files: make targets exist, program options are in their --help; no issue numbers or commit hashes)"
record "guard/docs" 1 0
exit 0
