# hzrt — the one build entry point (non-recursive: every source is listed here).
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

.DEFAULT_GOAL := all
.SUFFIXES:
.DELETE_ON_ERROR:
MAKEFLAGS += --no-builtin-rules

# ---------------------------------------------------------------------------------------------------------
# Board
BOARD ?= host-sim
BOARD_DIR := boards/$(BOARD)
ifeq ($(wildcard $(BOARD_DIR)/board.mk),)
$(error unknown BOARD '$(BOARD)': there is no $(BOARD_DIR)/board.mk (boards: $(notdir $(wildcard boards/*/board.mk)/..)))
endif
ifeq ($(wildcard $(BOARD_DIR)/board.h),)
$(error $(BOARD_DIR)/board.h is missing)
endif
include $(BOARD_DIR)/board.mk
BOARD_REQUIRED := BOARD_ARCH BOARD_CROSS_COMPILE BOARD_CFLAGS BOARD_LDFLAGS BOARD_SIMD BOARD_ACCEL BOARD_PORTS \
                  BOARD_DEPS BOARD_TEST_LAUNCHER BOARD_TEST_DEPS
$(foreach v,$(BOARD_REQUIRED),$(if $(filter undefined,$(origin $(v))),$(error $(BOARD_DIR)/board.mk does not set $(v))))
ifeq ($(filter $(BOARD_SIMD),avx2 neon scalar),)
$(error $(BOARD_DIR)/board.mk: BOARD_SIMD must be avx2, neon or scalar, not '$(BOARD_SIMD)')
endif

# ---------------------------------------------------------------------------------------------------------
# Tools (kernel conventions: CROSS_COMPILE prefixes every target tool; HOSTCC builds host tools)
CROSS_COMPILE ?= $(BOARD_CROSS_COMPILE)
defaulted = $(filter default undefined,$(origin $(1)))
ifneq ($(call defaulted,CC),)
CC := $(CROSS_COMPILE)gcc
endif
ifneq ($(call defaulted,AR),)
AR := $(CROSS_COMPILE)ar
endif
NM ?= $(CROSS_COMPILE)nm
OBJDUMP ?= $(CROSS_COMPILE)objdump
SIZE ?= $(CROSS_COMPILE)size
HOSTCC ?= gcc
SHELL := /bin/sh

ifeq ($(SAN),1)
SAN_SUFFIX := -san
endif
BUILD_ROOT ?= build
O ?= $(BUILD_ROOT)/$(BOARD)$(SAN_SUFFIX)

ifeq ($(V),1)
Q :=
msg =
else
Q := @
msg = @printf '  %-8s %s\n' '$(1)' '$(2)';
endif

# ---------------------------------------------------------------------------------------------------------
# Flags
WARN := -std=c99 -Wall -Wextra -Werror -pedantic
# -ffp-contract=off: no implicit FMA, so x86-64 and AArch64 round alike; -fno-math-errno: sqrt is one
# instruction, never a libm call.
OPT := -O2 -g -ffp-contract=off -fno-math-errno -fno-strict-aliasing
DEPFLAGS = -MMD -MP
BOARD_DEFS := -DHZ_BOARD_SIMD_$(shell echo $(BOARD_SIMD) | tr a-z A-Z)=1
INCLUDES := -Iinclude -I$(BOARD_DIR)

ifeq ($(SAN),1)
ifeq ($(BOARD_ARCH),x86_64)
SAN_FLAGS := -fsanitize=address,undefined -fno-sanitize-recover=all -fno-omit-frame-pointer
else
# AddressSanitizer's shadow memory does not work under qemu user-mode emulation; UBSan does.
SAN_FLAGS := -fsanitize=undefined -fno-sanitize-recover=all -fno-omit-frame-pointer
endif
endif

# src/: the freestanding core (no libc beyond memcpy/memset/memmove; see check-freestanding).
LIB_CFLAGS_BASE := $(WARN) $(OPT) -ffreestanding $(BOARD_CFLAGS) $(BOARD_DEFS) $(INCLUDES)
LIB_CFLAGS := $(LIB_CFLAGS_BASE) $(SAN_FLAGS)
# port/, tools/, test/: hosted C99 with POSIX.
HOSTED_CFLAGS := $(WARN) $(OPT) -D_POSIX_C_SOURCE=200809L $(BOARD_CFLAGS) $(BOARD_DEFS) $(INCLUDES) $(SAN_FLAGS)
LDFLAGS_ALL := $(BOARD_LDFLAGS) $(SAN_FLAGS)
# Integer-only code: no FP/SIMD registers at all, on both ISAs.
INTEGER_FLAGS := -mgeneral-regs-only

# ---------------------------------------------------------------------------------------------------------
# Sources (listed explicitly), one block per module. <M>_SRCS build on every board, <M>_SRCS_<simd> only on
# boards with BOARD_SIMD=<simd> (avx2, neon), <M>_TESTS are test/unit/test_<name>.c linked with libhz.a,
# <M>_PORT_TESTS also link the port library.

# core (src/core): arenas, status, formatter, fixed point, hash + RNG, vec/mat
CORE_SRCS := src/core/arena.c src/core/status.c src/core/fmt.c src/core/fixed.c src/core/hash.c src/core/vmath.c
CORE_INTEGER_SRCS := src/core/fixed.c src/core/hash.c
CORE_TESTS := arena status fmt fixed hash vmath config
CORE_PORT_TESTS := zero_alloc

# scene (src/scene): baked format, validating loader, built-in scene
SCENE_SRCS :=
SCENE_TESTS :=
SCENE_PORT_TESTS :=

# accel (src/accel): BVH build and traversal; the Embree backend lives in port/embree
ACCEL_SRCS :=
ACCEL_SRCS_avx2 :=
ACCEL_SRCS_neon :=
ACCEL_TESTS :=
ACCEL_PORT_TESTS :=

# render (src/render, src/recon): camera, shading, G-buffer, reconstruction
RENDER_SRCS :=
RENDER_TESTS :=
RENDER_PORT_TESTS :=

# pattern (src/pattern): integer-only tile orderings, dither maps, masks
PATTERN_SRCS :=
PATTERN_TESTS :=

# timing (src/timing): v-sync model, pacing, latency statistics; integer-only throughout
TIMING_SRCS := src/timing/wide.c src/timing/tstat.c src/timing/vsync.c src/timing/vsynth.c src/timing/pace.c \
               src/timing/frames.c src/timing/marker.c src/timing/pixconv.c src/timing/testpattern.c \
               src/timing/rtmodel.c src/timing/vcd.c src/timing/ecsv.c
TIMING_INTEGER_SRCS = $(TIMING_SRCS)
TIMING_TESTS := tstat vsync marker traceio
TIMING_PORT_TESTS := frameloop latency_cli
# Ports of the timing path (port/linux): `timing` (frame loop, report, `hzrt latency`, simulated display,
# VCD/CSV replay) goes on every board; `fbdev`, `v4l2` and `gpio` where the hardware has them.
PORT_SRCS_timing := port/linux/timebase.c port/linux/vsrc_timeline.c port/linux/frameloop.c port/linux/report.c \
                    port/linux/latency.c port/linux/scenesrc.c port/linux/devices_absent.c port/linux/sysio.c
PORT_SRCS_fbdev := port/linux/fbdev.c
PORT_SRCS_v4l2 := port/linux/v4l2.c
PORT_SRCS_gpio := port/linux/gpio.c
TIMING_PORT_TESTS += $(if $(filter fbdev,$(BOARD_PORTS))$(filter v4l2,$(BOARD_PORTS)),devices)
# gpio needs libgpiod for the board's architecture (Debian multiarch: libgpiod-dev, libgpiod-dev:arm64). Its
# pkg-config file gives the version (the v1 and v2 APIs differ); without it the port is left out, loudly.
LIBGPIOD_PC ?= /usr/lib/$(BOARD_ARCH)-linux-gnu/pkgconfig/libgpiod.pc
ifneq ($(filter gpio,$(BOARD_PORTS)),)
LIBGPIOD_VERSION := $(shell sed -n 's/^Version: *//p' $(LIBGPIOD_PC) 2>/dev/null)
ifeq ($(LIBGPIOD_VERSION),)
$(warning BOARD=$(BOARD): GPIO v-sync capture is OFF: no libgpiod for $(BOARD_ARCH) ($(LIBGPIOD_PC) missing); `make deps BOARD=$(BOARD)` installs it (libgpiod-dev$(if $(filter aarch64,$(BOARD_ARCH)),:arm64)))
BOARD_PORTS := $(filter-out gpio,$(BOARD_PORTS))
else
LIBGPIOD_PREFIX := $(shell sed -n 's/^prefix=//p' $(LIBGPIOD_PC))
LIBGPIOD_LIBDIR := $(subst $${prefix},$(LIBGPIOD_PREFIX),$(subst $${exec_prefix},$(LIBGPIOD_PREFIX),$(shell sed -n 's/^libdir=//p' $(LIBGPIOD_PC))))
LIBGPIOD_INCDIR := $(subst $${prefix},$(LIBGPIOD_PREFIX),$(shell sed -n 's/^includedir=//p' $(LIBGPIOD_PC)))
$(O)/port/linux/gpio.o: EXTRA_CFLAGS += -DHZ_LIBGPIOD_MAJOR=$(firstword $(subst ., ,$(LIBGPIOD_VERSION))) \
	-DHZ_LIBGPIOD_VERSION='"$(LIBGPIOD_VERSION)"' $(addprefix -I,$(filter-out /usr/include,$(LIBGPIOD_INCDIR)))
PORT_LIBS_gpio := $(addprefix -L,$(filter-out /usr/lib/$(BOARD_ARCH)-linux-gnu,$(LIBGPIOD_LIBDIR))) -lgpiod
endif
endif

MODULES := CORE SCENE ACCEL RENDER PATTERN TIMING
LIB_SRCS := $(foreach m,$(MODULES),$($(m)_SRCS) $($(m)_SRCS_$(BOARD_SIMD)))
LIB_OBJS := $(LIB_SRCS:%.c=$(O)/%.o)
LIB := $(O)/libhz.a
# Integer-only sources: compiled with -mgeneral-regs-only in every build, checked on both ISAs.
INTEGER_SRCS := $(CORE_INTEGER_SRCS) $(PATTERN_SRCS)
INTEGER_SRCS += $(TIMING_INTEGER_SRCS)

# Ports: each board lists the ones it links (BOARD_PORTS); accel backends come from BOARD_ACCEL.
KNOWN_PORTS := linux timing fbdev v4l2 gpio
PORT_SRCS_linux := port/linux/pools.c port/linux/cli.c port/linux/clock.c port/linux/fileio.c
$(foreach p,$(BOARD_PORTS),$(if $(filter $(p),$(KNOWN_PORTS)),,$(error $(BOARD_DIR)/board.mk: unknown port '$(p)' (known: $(KNOWN_PORTS)))))
PORT_SRCS := $(foreach p,$(BOARD_PORTS),$(PORT_SRCS_$(p)))
PORT_OBJS := $(PORT_SRCS:%.c=$(O)/%.o)
PORT_LIB := $(O)/libhzport.a
PORT_LIBS := -lpthread -lm
PORT_LIBS += $(foreach p,$(BOARD_PORTS),$(PORT_LIBS_$(p)))
PORT_DEFS := $(foreach p,$(BOARD_PORTS),-DHZ_PORT_$(shell echo $(p) | tr a-z A-Z)=1)

HZRT_SRCS := port/linux/main.c
HZRT_OBJS := $(HZRT_SRCS:%.c=$(O)/%.o)
HZRT := $(O)/bin/hzrt

BENCH_SRCS := tools/bench/bench.c
BENCH_OBJS := $(BENCH_SRCS:%.c=$(O)/%.o)
BENCH := $(O)/bin/hzbench

UNIT_TESTS := $(foreach m,$(MODULES),$($(m)_TESTS))
UNIT_BINS := $(UNIT_TESTS:%=$(O)/test/unit/test_%)
PORT_TESTS := $(foreach m,$(MODULES),$($(m)_PORT_TESTS))
PORT_TEST_BINS := $(PORT_TESTS:%=$(O)/test/unit/test_%)
TEST_BINS := $(UNIT_BINS) $(PORT_TEST_BINS)
TEST_CFLAGS := $(HOSTED_CFLAGS) -Itest
TEST_LIBS := -lcmocka

ALL_OBJS := $(LIB_OBJS) $(PORT_OBJS) $(HZRT_OBJS) $(BENCH_OBJS)

# ---------------------------------------------------------------------------------------------------------
# Build rules
all: $(HZRT) ## build hzrt for BOARD (default host-sim) into O (default build/<board>)

$(O)/src/%.o: src/%.c
	@mkdir -p $(dir $@)
	$(call msg,CC,$@)$(CC) $(LIB_CFLAGS) $(EXTRA_CFLAGS) $(DEPFLAGS) -c $< -o $@

$(INTEGER_SRCS:%.c=$(O)/%.o): EXTRA_CFLAGS += $(INTEGER_FLAGS)
# The board's static pools may exceed 2 GiB: on x86-64 they go to .lbss (medium code model) so that the
# rest of the program keeps the fast small-model addressing.
$(O)/port/linux/pools.o: EXTRA_CFLAGS += $(if $(filter x86_64,$(BOARD_ARCH)),-mcmodel=medium)

$(O)/port/%.o: port/%.c
	@mkdir -p $(dir $@)
	$(call msg,CC,$@)$(CC) $(HOSTED_CFLAGS) $(PORT_DEFS) $(EXTRA_CFLAGS) $(DEPFLAGS) -c $< -o $@

$(O)/tools/%.o: tools/%.c
	@mkdir -p $(dir $@)
	$(call msg,CC,$@)$(CC) $(HOSTED_CFLAGS) $(PORT_DEFS) -Iport/linux $(DEPFLAGS) -c $< -o $@

$(LIB): $(LIB_OBJS)
	$(call msg,AR,$@)rm -f $@ && $(AR) rcs $@ $^

$(PORT_LIB): $(PORT_OBJS)
	$(call msg,AR,$@)rm -f $@ && $(AR) rcs $@ $^

$(HZRT): $(HZRT_OBJS) $(PORT_LIB) $(LIB)
	@mkdir -p $(dir $@)
	$(call msg,LD,$@)$(CC) $(LDFLAGS_ALL) -o $@ $(HZRT_OBJS) $(PORT_LIB) $(LIB) $(PORT_LIBS)

$(BENCH): $(BENCH_OBJS) $(PORT_LIB) $(LIB)
	@mkdir -p $(dir $@)
	$(call msg,LD,$@)$(CC) $(LDFLAGS_ALL) -o $@ $(BENCH_OBJS) $(PORT_LIB) $(LIB) $(PORT_LIBS)

$(O)/test/unit/test_%: test/unit/test_%.c $(LIB)
	@mkdir -p $(dir $@)
	$(call msg,CCLD,$@)$(CC) $(TEST_CFLAGS) $(DEPFLAGS) $(LDFLAGS_ALL) -o $@ $< $(LIB) $(TEST_LIBS) -lm

$(PORT_TEST_BINS): $(O)/test/unit/test_%: test/unit/test_%.c $(PORT_LIB) $(LIB)
	@mkdir -p $(dir $@)
	$(call msg,CCLD,$@)$(CC) $(TEST_CFLAGS) $(PORT_DEFS) -Iport/linux $(DEPFLAGS) $(LDFLAGS_ALL) -o $@ $< \
		$(PORT_LIB) $(LIB) $(TEST_LIBS) $(PORT_LIBS) -ldl

-include $(ALL_OBJS:.o=.d) $(TEST_BINS:=.d)

# ---------------------------------------------------------------------------------------------------------
# Dependencies (Debian packages). `?pkg` is optional: a failed install warns instead of stopping.
DEPS_TEST_HOST := libcmocka-dev file
DEPS_TEST_CROSS := gcc-aarch64-linux-gnu libc6-dev-arm64-cross binutils-aarch64-linux-gnu qemu-user-static \
                   libcmocka-dev:arm64
deps: ## install the Debian packages BOARD needs to build, run and test (apt-get as root; else print the line)
	$(Q)sh tools/deps.sh $(BOARD_DEPS) $(BOARD_TEST_DEPS) \
		$(if $(filter test,$(MAKECMDGOALS)),$(DEPS_TEST_HOST) $(DEPS_TEST_CROSS)) \
		$(if $(filter test vmtest,$(MAKECMDGOALS)),$(DEPS_VMTEST))

# ---------------------------------------------------------------------------------------------------------
# Run
run: deps $(HZRT) ## build host-sim and run it (renders the built-in scene once the renderer lands)
	$(Q)$(HZRT) board

# The simulated 240 Hz run of issue 7: real time, a simulated display (+-50 us jitter, 1% missed pulses, 0.5%
# glitches, +200 ppm), frames from the hz_framesrc_t hook (the test pattern until the built-in scene lands in
# port/linux/scenesrc.c; then add --render scene), report and files in $(O)/latency-sim.
LATENCY_SIM_ARGS ?= --source sim --hz 240 --jitter-us 50 --miss-pct 1 --glitch-pct 0.5 --drift-ppm 200 \
                    --seconds 20 --size 320x180 --marker
latency-sim: $(HZRT) ## simulated 240 Hz display-locked run: miss rate, latency percentiles, histogram (build/<board>/latency-sim)
	$(Q)$(HZRT) latency $(LATENCY_SIM_ARGS) --out $(O)/latency-sim

bench: $(BENCH) ## measure (side by side, in one run) and print a table; writes $(O)/bench/*.csv
	$(Q)mkdir -p $(O)/bench
	$(Q)$(BENCH) --csv $(O)/bench/bench.csv

size: $(HZRT) ## section sizes of hzrt, its largest symbols and the board's static arenas
	$(Q)$(SIZE) $(HZRT) $(LIB)
	$(Q)echo "largest symbols:"; $(NM) --size-sort -S -r $(HZRT) | head -n 12

# ---------------------------------------------------------------------------------------------------------
# Tests
tests: $(TEST_BINS) $(HZRT) ## build the test binaries of BOARD without running them

# Runs this board's tests and guards; results go to $(O)/test-results/ for the summary (failures are
# recorded there, so the run goes on to the summary line).
test-board: tests
	$(Q)rm -rf $(O)/test-results && mkdir -p $(O)/test-results
	$(Q)sh test/run-tests.sh $(O)/test-results "$(BOARD)" "$(BOARD_TEST_LAUNCHER)" $(TEST_BINS)
	$(Q)HZ_GUARD_LABEL=$(BOARD) sh test/guard/check-freestanding.sh --record $(O)/test-results "$(NM)" \
		$(CHECK_OBJS) || true
	$(Q)sh test/guard/check-integer.sh --record $(O)/test-results "$(CC)" "$(BOARD_ARCH)" $(INTEGER_SRCS) || true

ifeq ($(SAN),1)
# Sanitizer objects reference the sanitizer runtime: check a plain build of the core instead.
CHECK_OBJS := $(LIB_SRCS:%.c=$(O)/check/%.o)
$(O)/check/src/%.o: src/%.c
	@mkdir -p $(dir $@)
	$(call msg,CC,$@)$(CC) $(LIB_CFLAGS_BASE) $(EXTRA_CFLAGS) -c $< -o $@
$(INTEGER_SRCS:%.c=$(O)/check/%.o): EXTRA_CFLAGS += $(INTEGER_FLAGS)
test-board: $(CHECK_OBJS)
else
CHECK_OBJS := $(LIB_OBJS)
endif

TEST_BOARDS := host-sim aarch64-generic
test: deps ## build and run every test: host, then AArch64 under qemu, plus the design guards
	$(Q)for b in $(TEST_BOARDS); do \
		$(MAKE) --no-print-directory BOARD=$$b O=$(BUILD_ROOT)/$$b$(SAN_SUFFIX) test-board || exit 1; \
	done; \
	for t in $(TEST_TIERS); do \
		$(MAKE) --no-print-directory $$t || exit 1; \
	done; \
	rm -rf $(BUILD_ROOT)/guards$(SAN_SUFFIX); \
	sh test/guard/run-guards.sh --record $(BUILD_ROOT)/guards$(SAN_SUFFIX); \
	sh test/summary.sh $(foreach b,$(TEST_BOARDS),$(BUILD_ROOT)/$(b)$(SAN_SUFFIX)/test-results) \
		$(TEST_TIER_RESULTS) $(BUILD_ROOT)/guards$(SAN_SUFFIX)

# ---------------------------------------------------------------------------------------------------------
# VM tier (test/vm): Debian's arm64 kernel under qemu-system-aarch64 (virt, software emulation) runs the
# AArch64 unit tests natively and the device checks (vivid V4L2 loop-back, vivid fbdev, PL061 GPIO pulsed
# from the monitor). Results land next to the boards' for test/summary.sh.
VM_ROOT := $(BUILD_ROOT)/vm
VM_RESULTS := $(BUILD_ROOT)/vmtest$(SAN_SUFFIX)/test-results
DEPS_VMTEST := qemu-system-arm cpio kmod ?libgpiod-dev:arm64
TEST_TIERS += vmtest-tier
TEST_TIER_RESULTS += $(VM_RESULTS)
VM_DEVICE_TEST := $(O)/test/vm/test_vm_devices

vmtest: deps ## boot Debian's arm64 kernel in qemu-system-aarch64: AArch64 unit tests, V4L2 loop-back, GPIO capture
	$(Q)$(MAKE) --no-print-directory vmtest-tier
	$(Q)sh test/summary.sh $(VM_RESULTS)

vmtest-tier:
	$(Q)$(MAKE) --no-print-directory BOARD=aarch64-generic O=$(BUILD_ROOT)/aarch64-generic$(SAN_SUFFIX) vmtest-board

# Runs with BOARD=aarch64-generic (see vmtest-tier): its test binaries, plus a static hzrt and init.
vmtest-board: tests $(VM_DEVICE_TEST) $(VM_ROOT)/init
	$(Q)$(MAKE) --no-print-directory BOARD=aarch64-generic O=$(VM_ROOT)/static BOARD_LDFLAGS=-static SAN= all
	$(Q)sh test/vm/run.sh $(VM_RESULTS) $(VM_ROOT)/kernel $(VM_ROOT)/init $(VM_ROOT)/static/bin/hzrt \
		$(VM_DEVICE_TEST) $(TEST_BINS)

$(VM_DEVICE_TEST): test/vm/test_vm_devices.c $(PORT_LIB) $(LIB)
	@mkdir -p $(dir $@)
	$(call msg,CCLD,$@)$(CC) $(TEST_CFLAGS) $(PORT_DEFS) -Iport/linux $(DEPFLAGS) $(LDFLAGS_ALL) -o $@ $< \
		$(PORT_LIB) $(LIB) $(TEST_LIBS) $(PORT_LIBS)

$(VM_ROOT)/init: test/vm/init.c
	@mkdir -p $(dir $@)
	$(call msg,CCLD,$@)aarch64-linux-gnu-gcc $(WARN) -O2 -static -o $@ $<

check-freestanding: $(CHECK_OBJS) ## the core links against nothing but memcpy/memset/memmove; no malloc/printf/FILE/errno in src/
	$(Q)sh test/guard/check-freestanding.sh "$(NM)" $(CHECK_OBJS)

check-integer: ## src/pattern/ and the integer core compile with -mgeneral-regs-only on x86-64 and AArch64
	$(Q)sh test/guard/check-integer.sh gcc x86_64 $(INTEGER_SRCS)
	$(Q)sh test/guard/check-integer.sh aarch64-linux-gnu-gcc aarch64 $(INTEGER_SRCS)

# ---------------------------------------------------------------------------------------------------------
clean: ## remove the build directory of BOARD (O); `make clean O=build` removes all boards
	$(call msg,CLEAN,$(O))rm -rf $(O)

help: ## list the targets
	@echo "usage: make [BOARD=name] [CROSS_COMPILE=prefix] [O=dir] [V=1] [SAN=1] [target]"
	@echo "boards: $(patsubst boards/%/board.mk,%,$(wildcard boards/*/board.mk))"
	@echo "targets:"
	@grep -hE '^[a-z][a-z-]*:.*## ' $(MAKEFILE_LIST) | sed -E 's/^([a-z-]+):.*## (.*)/\1|\2/' | \
		awk -F'|' '{ printf "  %-20s %s\n", $$1, $$2 }'

.PHONY: all deps run bench size tests test-board test check-freestanding check-integer clean help
.PHONY: vmtest vmtest-tier vmtest-board latency-sim
