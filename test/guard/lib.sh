# Shared by the guard scripts: result recording and comment stripping.
# record NAME PASSED FAILED: writes NAME.res into $record_dir when --record was given.
record_dir=""
if [ "${1:-}" = "--record" ]; then
    record_dir=$2
    shift 2
    mkdir -p "$record_dir"
fi
record() {
    [ -n "$record_dir" ] && echo "$1 $2 $3 0" >"$record_dir/$(echo "$1" | tr '/ ' '__').res"
    return 0
}
# Source text without comments and string literals' surroundings intact: gcc's preprocessor in
# "already preprocessed" mode drops comments and expands nothing.
strip_comments() {
    gcc -fpreprocessed -dD -E -P -x c "$1" 2>/dev/null
}
