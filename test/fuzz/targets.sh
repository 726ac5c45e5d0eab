# Sourced by fuzz-all.sh and run-fuzz.sh: what each fuzz target reads and how libFuzzer runs it.
#   fuzz_seeds TARGET FUZZ_O   the seed directories (committed; the .hzb loader's are also baked, in FUZZ_O/seeds)
#   fuzz_opts TARGET           libFuzzer options beyond the common ones
fuzz_seeds() {
    case $1 in
        hzb) echo "$2/seeds $(dirname "$0")/corpus/hzb" ;;
        *) echo "$(dirname "$0")/corpus/$1" ;;
    esac
}

fuzz_opts() {
    case $1 in
        # Whole scenes: the seeds are up to ~0.5 MB.
        hzb) echo "-max_len=4194304 -rss_limit_mb=4096 -timeout=30" ;;
        # The import runs in a child process (fuzz_import.c): no RSS watcher thread, so that fork() is safe, and
        # a malloc limit above the 3 GiB at which the target's ASan refuses an allocation with a stack trace.
        import) echo "-max_len=65536 -rss_limit_mb=0 -malloc_limit_mb=4096 -timeout=60" \
            "-dict=$(dirname "$0")/import.dict" ;;
        # Every refusal prints a line: output closed (sanitizer reports still come through).
        opts) echo "-rss_limit_mb=2048 -timeout=30 -close_fd_mask=3 -dict=$(dirname "$0")/opts.dict" ;;
        *) echo "-rss_limit_mb=2048 -timeout=30 -dict=$(dirname "$0")/$1.dict" ;;
    esac
}
