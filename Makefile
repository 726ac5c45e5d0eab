# hzrt — the one build entry point. Non-recursive: this file includes mk/*.mk, one per concern; sources and
# tests are found by pattern (mk/sources.mk, mk/tests.mk), so adding a file under src/<module>/ or
# test/unit/test_*.c needs no edit here.
#
#   make [BOARD=name] [CROSS_COMPILE=prefix] [O=dir] [V=1] [SAN=1] [target]
#
#   BOARD          boards/<name>/ (board.mk + board.h); default host-sim
#   CROSS_COMPILE  prefix for gcc/ar/nm/objdump/size; default from the board (aarch64-linux-gnu- for ARM boards)
#   HOSTCC         compiler for host tools (bake, gen, errtime); default gcc
#   O              build directory; default build/<board> (build/<board>-san with SAN=1). `make test`, which
#                  builds two boards, puts each in O/<board>.
#   V=1            show full commands
#   SAN=1          build with -fsanitize=address,undefined (host) / undefined (emulated AArch64)
#
# `make help` lists the targets.
#
#   mk/config.mk     board, tools, flags             mk/scenes.mk     real scenes baked from ../shared/scenes
#   mk/sources.mk    what each board compiles          mk/fuzz.mk       libFuzzer targets
#   mk/build.mk      compile and link rules            mk/deps.mk       Debian packages (make deps)
#   mk/report.mk     make report (error vs time)       mk/run.mk        run, latency-sim, bench, soak, size
#   mk/stability.mk  stiff and extreme cases           mk/gen.mk        generated tables
#   mk/host.mk       host tools: the baker             mk/tests.mk      make test and its tiers
#   mk/vm.mk         the VM tier (qemu-system)         mk/results.mk    doc/results.md from bench and report
#   mk/features.mk   compile-out switches: make features, the all-off check

.DEFAULT_GOAL := all
.SUFFIXES:
.DELETE_ON_ERROR:
MAKEFLAGS += --no-builtin-rules

include mk/config.mk
include mk/sources.mk
include mk/build.mk
include mk/report.mk
include mk/stability.mk
include mk/host.mk
include mk/scenes.mk
include mk/fuzz.mk
include mk/deps.mk
include mk/run.mk
include mk/gen.mk
include mk/tests.mk
include mk/vm.mk
include mk/features.mk
-include mk/results.mk

check-freestanding: $(CHECK_OBJS) ## the core links against nothing but memcpy/memset/memmove; no malloc/printf/FILE/errno in src/
	$(Q)sh test/guard/check-freestanding.sh "$(NM)" $(CHECK_OBJS)

check-integer: ## src/pattern/ and the integer core compile with -mgeneral-regs-only on x86-64 and AArch64
	$(Q)sh test/guard/check-integer.sh gcc x86_64 $(INTEGER_SRCS)
	$(Q)sh test/guard/check-integer.sh aarch64-linux-gnu-gcc aarch64 $(INTEGER_SRCS)

clean: ## remove the build directory of BOARD (O); `make clean O=build` removes all boards
	$(call msg,CLEAN,$(O))rm -rf $(O)

help: ## list the targets
	@echo "usage: make [BOARD=name] [CROSS_COMPILE=prefix] [O=dir] [V=1] [SAN=1] [target]"
	@echo "boards: $(patsubst boards/%/board.mk,%,$(wildcard boards/*/board.mk))"
	@echo "targets:"
	@grep -hE '^[a-z][a-z-]*:.*## ' $(MAKEFILE_LIST) | sed -E 's/^([a-z-]+):.*## (.*)/\1|\2/' | \
		awk -F'|' '{ printf "  %-20s %s\n", $$1, $$2 }'

.PHONY: all deps run bench size tests test-board test check-freestanding check-integer clean help gen-srgb gen-dither errtime \
        bake scenes scenes-baked fuzz test-host report
.PHONY: vmtest vmtest-tier vmtest-board vmtest-build latency-sim
.PHONY: stability stability-tier stability-board board-fit soak
