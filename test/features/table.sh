#!/bin/sh
# `make features`' table: firmware text and bss of hzrt per board and configuration, and the difference to the
# board's all-on build (what a feature costs, or what leaving it out saves).
#   table.sh LIST MD CSV    LIST: lines "BOARD CONFIG SIZEFILE" (SIZEFILE: `size -B` of hzrt, last line)
set -u
list=$1 md=$2 csv=$3
awk -v md="$md" -v csv="$csv" '
    {
        getline line < $3
        split(line, f, " ")
        board[NR] = $1; conf[NR] = $2; text[NR] = f[1]; data[NR] = f[2]; bss[NR] = f[3]
        if ($2 == "on") { on_text[$1] = f[1]; on_bss[$1] = f[3] }
    }
    function label(c) { return c == "on" ? "all on" : c == "all" ? "all off" : c " off" }
    function delta(v) { return v > 0 ? "+" v : v "" }
    END {
        print "board,configuration,text,data,bss,text_delta,bss_delta" > csv
        print "| board | configuration | text | bss | text vs all on | bss vs all on |" > md
        print "|---|---|---:|---:|---:|---:|" > md
        for (i = 1; i <= NR; i++) {
            dt = text[i] - on_text[board[i]]; db = bss[i] - on_bss[board[i]]
            printf "%s,%s,%s,%s,%s,%s,%s\n", board[i], conf[i], text[i], data[i], bss[i], dt, db > csv
            printf "| %s | %s | %s | %s | %s (%.1f%%) | %s |\n", board[i], label(conf[i]), text[i], bss[i], delta(dt),
                100.0 * dt / on_text[board[i]], delta(db) > md
        }
    }' "$list"
cat "$md"
echo "(also $csv)"
