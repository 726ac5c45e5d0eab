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

# core (src/core): arenas, status, formatter, fixed point, hash + RNG, CRC-32, vec/mat, images + sRGB codes
CORE_SRCS := src/core/arena.c src/core/memplan.c src/core/rgb8.c src/core/status.c src/core/fmt.c src/core/fixed.c src/core/hash.c src/core/vmath.c \
             src/core/crc32.c src/core/image.c src/core/srgb_tables.c src/core/pack.c
CORE_INTEGER_SRCS := src/core/fixed.c src/core/hash.c src/core/crc32.c
CORE_TESTS := arena status fmt fixed hash vmath crc32 image pack rgb8
CORE_PORT_TESTS := zero_alloc imageio config

# scene (src/scene): baked format, validating loader, built-in scene
SCENE_SRCS := src/scene/hzb.c src/scene/write.c src/scene/load.c src/scene/animate.c src/scene/builtin.c \
              src/scene/posekeys.c src/scene/skin.c
SCENE_SRCS_avx2 := src/scene/skin_avx2.c
SCENE_SRCS_neon := src/scene/skin_neon.c
SCENE_TESTS := scene scene_corrupt posekeys skin
SCENE_PORT_TESTS :=

# accel (src/accel): BVH build and traversal; the Embree backend lives in port/embree
ACCEL_SRCS := src/accel/accel.c src/accel/bvh_build.c src/accel/msbvh.c src/accel/trav_scalar.c src/accel/meshgen.c
ACCEL_SRCS_avx2 := src/accel/trav_avx2.c
ACCEL_SRCS_neon := src/accel/trav_neon.c
ACCEL_TESTS := accel_build accel_build_twin accel_trav accel_motion
ACCEL_PORT_TESTS := threads accel_water accel_scenes accel_motion_cli
# The parallel build's determinism test: the builder is scalar C with one operation order (test_accel_build
# checks it on both ISAs), and under qemu-user this test took 270 s of the 20-minute budget; native boards only.
ACCEL_PORT_TESTS_native := accel_par
# with embree in BOARD_ACCEL: the backend's port sources and its cross-check tests
PORT_SRCS_embree := port/embree/embree_accel.c
ACCEL_PORT_TESTS_embree := accel_embree

# render (src/render, src/recon): camera, shading, G-buffer, reconstruction
RENDER_SRCS := src/render/camera.c src/render/texture.c src/render/trace.c src/render/render.c src/recon/taa.c \
               src/recon/full.c src/recon/tdense_mode.c src/recon/modes.c src/render/ladder.c \
               src/render/deflight.c src/render/terminator.c src/render/transp.c \
               src/recon/tdense.c src/recon/adaptive.c src/render/shade_packet.c
RENDER_SRCS_avx2 := src/render/shade_avx2.c src/render/camera_lanes.c src/recon/tdense_lanes.c src/recon/taa_lanes.c
RENDER_SRCS_neon := src/render/shade_neon.c src/render/camera_lanes.c src/recon/tdense_lanes.c src/recon/taa_lanes.c
RENDER_TESTS := tdense
RENDER_PORT_TESTS := render render_tdense render_speckles render_adaptive render_transp leaveout scene_clock render_lanes \
                     render_blur render_skin shade render_overlap render_reconfigure
RENDER_PORT_TESTS_embree := render_backends
# Heavy render tests for boards whose tests run natively (not under emulation).
RENDER_PORT_TESTS_native := render_taa

# pattern (src/pattern): integer-only tile orderings, dither maps, masks
PATTERN_SRCS := src/pattern/tileorder.c src/pattern/adaptive_mask.c src/pattern/dither.c src/pattern/dither_tables.c \
                src/pattern/timeseq.c
PATTERN_TESTS := tileorder adaptive_mask dither timeseq

# timing (src/timing): v-sync model, pacing, latency statistics; integer-only throughout
TIMING_SRCS := src/timing/wide.c src/timing/tstat.c src/timing/vsync.c src/timing/vsynth.c src/timing/pace.c \
               src/timing/frames.c src/timing/marker.c src/timing/pixconv.c src/timing/testpattern.c \
               src/timing/rtmodel.c src/timing/vcd.c src/timing/ecsv.c src/timing/lockv.c src/timing/timebase.c \
               src/timing/frameloop.c src/timing/governor.c
TIMING_INTEGER_SRCS = $(TIMING_SRCS)
TIMING_TESTS := tstat vsync marker traceio lockv governor
TIMING_PORT_TESTS := frameloop latency_cli show
# Ports of the timing path (port/linux): `timing` (frame loop, report, `hzrt latency`, simulated display,
# VCD/CSV replay) goes on every board; `fbdev`, `v4l2` and `gpio` where the hardware has them.
PORT_SRCS_timing := port/linux/timebase.c port/linux/vsrc_timeline.c port/linux/latency_report.c \
                    port/linux/scenesrc.c port/linux/filesink.c port/linux/devices_absent.c port/linux/sysio.c
PORT_SRCS_fbdev := port/linux/fbdev.c
PORT_SRCS_v4l2 := port/linux/v4l2.c
PORT_SRCS_gpio := port/linux/gpio.c
PORT_SRCS_drm := port/linux/drm.c
# drm needs libdrm for the board's architecture (libdrm-dev, libdrm-dev:arm64); without it the port is left out,
# loudly, and the VM's DRM check fails.
LIBDRM_PC ?= /usr/lib/$(BOARD_ARCH)-linux-gnu/pkgconfig/libdrm.pc
ifneq ($(filter drm,$(BOARD_PORTS)),)
ifeq ($(wildcard $(LIBDRM_PC)),)
$(warning BOARD=$(BOARD): the DRM/KMS sink is OFF: no libdrm for $(BOARD_ARCH) ($(LIBDRM_PC) missing); `make deps BOARD=$(BOARD)` installs it (libdrm-dev$(if $(filter aarch64,$(BOARD_ARCH)),:arm64)))
BOARD_PORTS := $(filter-out drm,$(BOARD_PORTS))
else
$(O)/port/linux/drm.o: EXTRA_CFLAGS += -isystem /usr/include/libdrm
PORT_LIBS_drm := -ldrm
endif
endif
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
KNOWN_PORTS := linux timing fbdev v4l2 gpio drm
PORT_SRCS_linux := port/linux/pools.c port/linux/cli.c port/linux/clock.c port/linux/fileio.c port/linux/scenefile.c \
                   port/linux/threads.c port/linux/summary.c port/linux/accel_backend.c \
                   port/linux/render_run.c port/linux/adaptive_cli.c port/linux/transp_opt.c
PORT_SRCS_linux += port/linux/phase.c port/linux/modeplan.c port/linux/blur_setup.c port/linux/motion_check.c
$(foreach p,$(BOARD_PORTS),$(if $(filter $(p),$(KNOWN_PORTS)),,$(error $(BOARD_DIR)/board.mk: unknown port '$(p)' (known: $(KNOWN_PORTS)))))
# Image files (port/linux/imageio.c): PNG needs libpng for the target. It is on when the target's compiler links
# -lpng (host builds: libpng-dev is in host-sim's BOARD_DEPS); elsewhere the PNG calls report "not built in".
PORT_SRCS_linux += port/linux/imageio.c
HAVE_PNG := $(shell printf 'int main(void){return 0;}\n' | $(CC) -x c - -o /dev/null -lpng >/dev/null 2>&1 && echo 1 || echo 0)
$(O)/port/linux/imageio.o: EXTRA_CFLAGS += -DHZ_HAVE_PNG=$(HAVE_PNG)
PNG_LIBS := $(if $(filter 1,$(HAVE_PNG)),-lpng)
PORT_SRCS := $(foreach p,$(BOARD_PORTS),$(PORT_SRCS_$(p)))
PORT_LIBS := -lpthread -lm $(PNG_LIBS)
PORT_LIBS += $(foreach p,$(BOARD_PORTS),$(PORT_LIBS_$(p)))
PORT_DEFS := $(foreach p,$(BOARD_PORTS),-DHZ_PORT_$(shell echo $(p) | tr a-z A-Z)=1)
ifneq ($(filter embree,$(BOARD_ACCEL)),)
PORT_SRCS += $(PORT_SRCS_embree)
PORT_LIBS += -lembree3
PORT_DEFS += -DHZ_HAVE_EMBREE=1 -Iport/embree
endif
PORT_OBJS := $(PORT_SRCS:%.c=$(O)/%.o)
PORT_LIB := $(O)/libhzport.a

# The commands (hzrt render, latency, show): option tables and the run of the frame loop; they measure the
# governor's levels with errtime's metrics.
CMD_SRCS := port/linux/render_cmd.c port/linux/latency.c port/linux/show.c port/linux/renderopts.c
CMD_OBJS := $(CMD_SRCS:%.c=$(O)/%.o)
$(O)/port/linux/show.o: EXTRA_CFLAGS += -Itools/errtime
HZRT_SRCS := port/linux/main.c port/linux/accel_cmd.c $(CMD_SRCS)
HZRT_OBJS := $(HZRT_SRCS:%.c=$(O)/%.o)
HZRT := $(O)/bin/hzrt

BENCH_SRCS := tools/bench/bench.c tools/bench/bench_accel.c tools/bench/bench_tdense.c tools/bench/bench_transp.c \
              tools/bench/bench_scene.c tools/bench/bench_adaptive.c tools/bench/bench_blur.c tools/bench/bench_util.c \
              tools/bench/bench_motion.c tools/bench/bench_realtime.c
BENCH_OBJS := $(BENCH_SRCS:%.c=$(O)/%.o)
BENCH := $(O)/bin/hzbench

UNIT_TESTS := $(foreach m,$(MODULES),$($(m)_TESTS))
UNIT_BINS := $(UNIT_TESTS:%=$(O)/test/unit/test_%)
PORT_TESTS := $(foreach m,$(MODULES),$($(m)_PORT_TESTS)) \
              $(if $(filter embree,$(BOARD_ACCEL)),$(ACCEL_PORT_TESTS_embree) $(RENDER_PORT_TESTS_embree)) \
              $(if $(BOARD_TEST_LAUNCHER),,$(ACCEL_PORT_TESTS_native) $(RENDER_PORT_TESTS_native))
PORT_TEST_BINS := $(PORT_TESTS:%=$(O)/test/unit/test_%)
TEST_BINS := $(UNIT_BINS) $(PORT_TEST_BINS)
TEST_CFLAGS := $(HOSTED_CFLAGS) -Itest
TEST_LIBS := -lcmocka
$(O)/test/unit/test_imageio: TEST_CFLAGS += -DHZ_HAVE_PNG=$(HAVE_PNG)

# errtime (tools/errtime): image metrics (PSNR, SSIM, FLIP), report writers and the error-against-run-time driver.
# Built with the board's compiler, like hzbench: it times the board's renderer. Hosted C99 with libm.
# Its files are prefixed et_ because it also sees port/linux (which has report.h, for instance).
ERRTIME_SRCS := tools/errtime/et_metrics.c tools/errtime/et_flip.c tools/errtime/et_report.c \
                tools/errtime/et_progress.c tools/errtime/driver.c tools/errtime/et_synthetic.c \
                tools/errtime/et_methods.c tools/errtime/et_render.c tools/errtime/et_stability.c
ERRTIME_MAIN_SRCS := tools/errtime/main.c
ERRTIME_TESTS := metrics flip et_report errtime et_render
ERRTIME_OBJS := $(ERRTIME_SRCS:%.c=$(O)/%.o)
ERRTIME_MAIN_OBJS := $(ERRTIME_MAIN_SRCS:%.c=$(O)/%.o)
ERRTIME_LIB := $(O)/liberrtime.a
ERRTIME := $(O)/bin/hzerrtime
ERRTIME_TEST_BINS := $(ERRTIME_TESTS:%=$(O)/test/unit/test_%)
# The metric filters' inner loops run over x: vectorising them keeps every pixel's sum in the same order (same
# results) and makes FLIP ~2x faster; -O2's "very cheap" cost model leaves them scalar.
$(O)/tools/errtime/et_flip.o $(O)/tools/errtime/et_metrics.o: HOSTED_CFLAGS += -fvect-cost-model=dynamic
TEST_BINS += $(ERRTIME_TEST_BINS)

ALL_OBJS := $(LIB_OBJS) $(PORT_OBJS) $(HZRT_OBJS) $(BENCH_OBJS) $(ERRTIME_OBJS) $(ERRTIME_MAIN_OBJS)

# ---------------------------------------------------------------------------------------------------------
# Build rules
all: $(HZRT) ## build hzrt for BOARD (default host-sim) into O (default build/<board>)

# Every object depends on the configuration it was compiled with (compiler, flags, the ports found): `make deps`
# can install libdrm or libgpiod between two runs, and objects built before would keep the old answer (a port
# left out) while their sources look up to date. The stamp is rewritten only when the configuration changes.
BUILD_CONFIG := $(CC) $(HOSTCC) | $(LIB_CFLAGS) | $(HOSTED_CFLAGS) | $(PORT_DEFS) | ports $(BOARD_PORTS) | \
                gpiod $(LIBGPIOD_VERSION) | $(PORT_LIBS_drm) $(PORT_LIBS_gpio)
BUILD_STAMP := $(O)/.build-config
ifeq ($(filter clean help,$(MAKECMDGOALS)),)
$(shell mkdir -p $(O))
$(file >$(BUILD_STAMP).new,$(BUILD_CONFIG))
$(shell cmp -s $(BUILD_STAMP).new $(BUILD_STAMP) || mv -f $(BUILD_STAMP).new $(BUILD_STAMP); rm -f $(BUILD_STAMP).new)
endif

$(O)/src/%.o: src/%.c $(BUILD_STAMP)
	@mkdir -p $(dir $@)
	$(call msg,CC,$@)$(CC) $(LIB_CFLAGS) $(EXTRA_CFLAGS) $(DEPFLAGS) -c $< -o $@

$(INTEGER_SRCS:%.c=$(O)/%.o): EXTRA_CFLAGS += $(INTEGER_FLAGS)
# The upscaler's row loops in the vector unit: integer arithmetic, the same bytes on every ISA (test_rgb8).
$(O)/src/core/rgb8.o: EXTRA_CFLAGS += -ftree-vectorize -fvect-cost-model=dynamic
# The board's static pools may exceed 2 GiB: on x86-64 they go to .lbss (medium code model) so that the
# rest of the program keeps the fast small-model addressing.
$(O)/port/linux/pools.o: EXTRA_CFLAGS += $(if $(filter x86_64,$(BOARD_ARCH)),-mcmodel=medium)

$(O)/port/%.o: port/%.c $(BUILD_STAMP)
	@mkdir -p $(dir $@)
	$(call msg,CC,$@)$(CC) $(HOSTED_CFLAGS) $(PORT_DEFS) $(EXTRA_CFLAGS) $(DEPFLAGS) -c $< -o $@

$(O)/tools/%.o: tools/%.c $(BUILD_STAMP)
	@mkdir -p $(dir $@)
	$(call msg,CC,$@)$(CC) $(HOSTED_CFLAGS) $(PORT_DEFS) -Iport/linux $(DEPFLAGS) -c $< -o $@

$(LIB): $(LIB_OBJS)
	$(call msg,AR,$@)rm -f $@ && $(AR) rcs $@ $^

$(PORT_LIB): $(PORT_OBJS)
	$(call msg,AR,$@)rm -f $@ && $(AR) rcs $@ $^

$(HZRT): $(HZRT_OBJS) $(ERRTIME_LIB) $(PORT_LIB) $(LIB)
	@mkdir -p $(dir $@)
	$(call msg,LD,$@)$(CC) $(LDFLAGS_ALL) -o $@ $(HZRT_OBJS) $(ERRTIME_LIB) $(PORT_LIB) $(LIB) $(PORT_LIBS)

$(BENCH): $(BENCH_OBJS) $(PORT_LIB) $(LIB)
	@mkdir -p $(dir $@)
	$(call msg,LD,$@)$(CC) $(LDFLAGS_ALL) -o $@ $(BENCH_OBJS) $(PORT_LIB) $(LIB) $(PORT_LIBS)

$(O)/test/unit/test_%: test/unit/test_%.c $(LIB) $(BUILD_STAMP)
	@mkdir -p $(dir $@)
	$(call msg,CCLD,$@)$(CC) $(TEST_CFLAGS) $(DEPFLAGS) $(LDFLAGS_ALL) -o $@ $< $(LIB) $(TEST_LIBS) -lm

$(PORT_TEST_BINS): $(O)/test/unit/test_%: test/unit/test_%.c $(PORT_LIB) $(LIB)
	@mkdir -p $(dir $@)
	$(call msg,CCLD,$@)$(CC) $(TEST_CFLAGS) $(PORT_DEFS) -Iport/linux $(DEPFLAGS) $(LDFLAGS_ALL) -o $@ $< \
		$(filter %.o,$^) $(filter %.a,$(TEST_EXTRA_LIBS)) $(PORT_LIB) $(LIB) $(TEST_LIBS) $(PORT_LIBS) -ldl
# `hzrt accel` through its entry point (the command lives in hzrt, not in the port library)
$(O)/test/unit/test_accel_motion_cli: $(O)/port/linux/accel_cmd.o
# `hzrt latency` and `render` through their entry points (the commands live in hzrt)
$(O)/test/unit/test_latency_cli $(O)/test/unit/test_show: $(CMD_OBJS) $(ERRTIME_LIB)
$(O)/test/unit/test_latency_cli $(O)/test/unit/test_show: TEST_EXTRA_LIBS = $(ERRTIME_LIB)

# The sigrok-cli demo traces (test/traces/README.md) as C arrays, for tests that also run in the VM.
TRACE_HDR := $(O)/test/gen/hz_traces.h
$(TRACE_HDR): test/traces/mkheader.sh test/traces/sigrok-demo-200k.vcd test/traces/sigrok-demo-1k.vcd
	@mkdir -p $(dir $@)
	$(call msg,GEN,$@)sh $< $(filter %.vcd,$^) >$@.tmp && mv $@.tmp $@
$(O)/test/unit/test_traceio $(O)/test/unit/test_latency_cli: $(TRACE_HDR)
$(O)/test/unit/test_traceio $(O)/test/unit/test_latency_cli: TEST_CFLAGS += -I$(O)/test/gen

$(ERRTIME_LIB): $(ERRTIME_OBJS)
	$(call msg,AR,$@)rm -f $@ && $(AR) rcs $@ $^

$(ERRTIME): $(ERRTIME_MAIN_OBJS) $(ERRTIME_LIB) $(PORT_LIB) $(LIB)
	@mkdir -p $(dir $@)
	$(call msg,LD,$@)$(CC) $(LDFLAGS_ALL) -o $@ $(ERRTIME_MAIN_OBJS) $(ERRTIME_LIB) $(PORT_LIB) $(LIB) $(PORT_LIBS)

errtime: $(ERRTIME) ## build hzerrtime (error against run time; `hzerrtime --help`) into O/bin
tests: $(ERRTIME)

# `make report`: every renderer method of tools/errtime/et_methods.c on the standard scenes, each at its table
# entry's size, length and display rate: the general set (full-frame 1/4/9/16 spp, TAA, adaptive supersampling
# at tau 0.1/0.3/0.6/1) on CornellBox-Mirror, Sponza, Lost Empire, Conference and the built-in scene, and temporally dense rendering against 1 spp and TAA at 60 and
# 240 Hz on a 240 Hz display (the @240 scenes). References cached in $(BUILD_ROOT)/errtime-cache (delete it for
# a cold run). The TAA variants stay out of the chart (within ~2% of the default TAA's FLIP everywhere, they pile
# up on its point): `hzerrtime --methods taa,taa-clip,taa-catmull-rom,taa-clip-cr` compares them.
REPORT_O := $(BUILD_ROOT)/report
REPORT_SCENES := CornellBox-Mirror,sponza,lost-empire,conference,builtin,builtin@240,sponza@240,conference@240
# Transparency (seed 004): every --transparency method with TAA, the still-view stability figure, and std under
# tdense at 240 Hz against + TAA at 60 Hz.
REPORT_SCENES := $(REPORT_SCENES),sponza-smoke,AlphaBlendModeTest,builtin-transp,sponza-smoke@240,AlphaBlendModeTest@240
# Motion blur (seed 002): msbvh, interp and Embree at equal time budget on 30 Hz sequences with the shutter open.
REPORT_BLUR_SCENES := builtin-blur,sponza-rotated-blur
REPORT_SCENES := $(REPORT_SCENES),$(REPORT_BLUR_SCENES)
REPORT_SKIP := taa-clip,taa-catmull-rom,taa-clip-cr
report: deps ## error against run time of every method on the standard scenes: build/report/ (CSV, MD, SVG)
	$(Q)$(MAKE) --no-print-directory $(ERRTIME) scenes
	$(Q)t0=$$(date +%s); nice $(ERRTIME) --scene $(REPORT_SCENES) --skip $(REPORT_SKIP) --scenes $(SCENES_O) \
		--cache $(BUILD_ROOT)/errtime-cache --out $(REPORT_O) || exit $$?; \
	echo "report: $$(( $$(date +%s) - t0 )) s on $$(nproc) cores"

$(ERRTIME_TEST_BINS): $(O)/test/unit/test_%: test/unit/test_%.c $(ERRTIME_LIB) $(PORT_LIB) $(LIB)
	@mkdir -p $(dir $@)
	$(call msg,CCLD,$@)$(CC) $(TEST_CFLAGS) $(PORT_DEFS) -Itools/errtime -Iport/linux $(DEPFLAGS) \
		 $(LDFLAGS_ALL) -o $@ $< $(ERRTIME_LIB) $(PORT_LIB) $(LIB) $(TEST_LIBS) $(PORT_LIBS)

-include $(ALL_OBJS:.o=.d) $(TEST_BINS:=.d)

# stability (test/stability): the catalogue of stiff and extreme cases, one binary per board linked like the port
# tests; `make stability` runs it on host-sim and under qemu-aarch64 and writes $(STAB_O)/report.md and a CSV per
# board; `make test` runs it as a tier (stability-tier). FULL=1 adds the long variants.
STAB_SRCS := test/stability/main.c test/stability/stab_util.c test/stability/geometry.c test/stability/rays.c \
             test/stability/motion.c test/stability/transparency.c test/stability/recon.c \
             test/stability/timing.c test/stability/fixed.c test/stability/memory.c
STAB_SRCS += test/stability/blur.c test/stability/dither.c test/stability/adaptive.c
STAB_OBJS := $(STAB_SRCS:%.c=$(O)/%.o)
STAB := $(O)/test/stability/hzstab
STAB_O := $(BUILD_ROOT)/stability$(SAN_SUFFIX)
STAB_BOARDS := host-sim aarch64-generic
$(O)/test/stability/%.o: test/stability/%.c
	@mkdir -p $(dir $@)
	$(call msg,CC,$@)$(CC) $(TEST_CFLAGS) $(PORT_DEFS) -Iport/linux $(DEPFLAGS) -c $< -o $@
$(STAB): $(STAB_OBJS) $(PORT_LIB) $(LIB)
	@mkdir -p $(dir $@)
	$(call msg,LD,$@)$(CC) $(LDFLAGS_ALL) -o $@ $(STAB_OBJS) $(PORT_LIB) $(LIB) $(PORT_LIBS)
tests: $(STAB)
-include $(STAB_OBJS:.o=.d)

# One board's run (BOARD, O): CSV, notes and the .res line for test/summary.sh.
stability-board: $(STAB)
	@mkdir -p $(STAB_O)/test-results
	$(Q)$(BOARD_TEST_LAUNCHER) $(STAB) $(if $(filter 1,$(FULL)),--full) --label $(BOARD) \
		--csv $(STAB_O)/$(BOARD).csv --notes $(STAB_O)/$(BOARD).notes \
		--res $(STAB_O)/test-results/$(BOARD).res >$(STAB_O)/$(BOARD).log 2>&1; \
		rc=$$?; sed 's/^/  $(BOARD): /' $(STAB_O)/$(BOARD).log | grep -v '^  $(BOARD):   ok ' || true; \
		[ -s $(STAB_O)/test-results/$(BOARD).res ] || echo "$(BOARD)/stability 0 1 0" >$(STAB_O)/test-results/$(BOARD).res; \
		exit 0

stability-tier:
	$(Q)rm -rf $(STAB_O) && mkdir -p $(STAB_O)/test-results
	$(Q)for b in $(STAB_BOARDS); do \
		$(MAKE) --no-print-directory BOARD=$$b O=$(BUILD_ROOT)/$$b$(SAN_SUFFIX) stability-board || exit 1; \
	done
	$(Q)sh test/stability/report.sh $(STAB_O) $(STAB_BOARDS)
TEST_TIERS += stability-tier
TEST_TIER_RESULTS += $(STAB_O)/test-results

stability: deps ## stiff and extreme cases on host-sim and AArch64 (qemu): build/stability/report.md + CSVs; FULL=1 adds long variants
	$(Q)$(MAKE) --no-print-directory stability-tier
	$(Q)sh test/summary.sh $(STAB_O)/test-results

# ---------------------------------------------------------------------------------------------------------
# Host tools: the scene baker (tools/bake), its tests (test/host) and the loader fuzzer (test/fuzz). They are
# built for the build machine with HOSTCC whatever BOARD is, against a host-compiled copy of the core and
# scene sources (tools/host/board.h), into $(BUILD_ROOT)/host (host-san with SAN=1). `make scenes` always
# bakes with the plain build, so SAN=1 does not re-bake every scene.
HOSTAR ?= ar
HOST_CFLAGS := $(WARN) $(OPT) -D_POSIX_C_SOURCE=200809L -Iinclude -Itools/host -Iport/linux
HOST_SAN_FLAGS := -fsanitize=address,undefined -fno-sanitize-recover=all -fno-omit-frame-pointer
HOST_LIB_SRCS := $(CORE_SRCS) $(SCENE_SRCS) port/linux/cli.c port/linux/fileio.c
BAKE_LIB_SRCS := tools/bake/util.c tools/bake/sidecar.c tools/bake/scene.c tools/bake/texture.c \
                 tools/bake/import_assimp.c tools/bake/import_furball.c
BAKE_SRCS := tools/bake/main.c $(BAKE_LIB_SRCS)
BAKE_LIBS := -lassimp -lstb -lz -lm
HOST_TESTS := sidecar bake

# $(1): output directory, $(2): extra compiler/linker flags
define HOST_TREE
$(1)/obj/src/%.o: src/%.c
	@mkdir -p $$(dir $$@)
	$$(call msg,HOSTCC,$$@)$$(HOSTCC) $$(HOST_CFLAGS) -ffreestanding $(2) $$(DEPFLAGS) -c $$< -o $$@
$(1)/obj/%.o: %.c
	@mkdir -p $$(dir $$@)
	$$(call msg,HOSTCC,$$@)$$(HOSTCC) $$(HOST_CFLAGS) $(2) $$(DEPFLAGS) -c $$< -o $$@
$(1)/libhz-host.a: $$(HOST_LIB_SRCS:%.c=$(1)/obj/%.o)
	$$(call msg,AR,$$@)rm -f $$@ && $$(HOSTAR) rcs $$@ $$^
$(1)/libbake.a: $$(BAKE_LIB_SRCS:%.c=$(1)/obj/%.o)
	$$(call msg,AR,$$@)rm -f $$@ && $$(HOSTAR) rcs $$@ $$^
$(1)/bin/hzbake: $(1)/obj/tools/bake/main.o $(1)/libbake.a $(1)/libhz-host.a
	@mkdir -p $$(dir $$@)
	$$(call msg,HOSTLD,$$@)$$(HOSTCC) $(2) -o $$@ $$^ $$(BAKE_LIBS)
$(1)/test/test_%: test/host/test_%.c $(1)/libbake.a $(1)/libhz-host.a
	@mkdir -p $$(dir $$@)
	$$(call msg,HOSTCC,$$@)$$(HOSTCC) $$(HOST_CFLAGS) -Itest -Itools/bake $(2) $$(DEPFLAGS) -o $$@ $$< \
		$(1)/libbake.a $(1)/libhz-host.a $$(BAKE_LIBS) -lcmocka
-include $$(patsubst %.c,$(1)/obj/%.d,$$(HOST_LIB_SRCS) $$(BAKE_SRCS)) $$(HOST_TESTS:%=$(1)/test/test_%.d)
endef
HOST_PLAIN_O := $(BUILD_ROOT)/host
HOST_O := $(BUILD_ROOT)/host$(SAN_SUFFIX)
$(eval $(call HOST_TREE,$(HOST_PLAIN_O),))
ifeq ($(SAN),1)
$(eval $(call HOST_TREE,$(HOST_O),$(HOST_SAN_FLAGS)))
endif
BAKE := $(HOST_PLAIN_O)/bin/hzbake
# The baker warns when a scene fits no board's scene arena: every board's HZ_ARENA_SCENE_BYTES (in MiB).
BOARD_SCENE_ARENAS := $(foreach b,$(wildcard boards/*/board.h),$(patsubst boards/%/board.h,%,$(b))=$(shell \
	sed -n 's/^\#define HZ_ARENA_SCENE_BYTES (\([0-9]*\)ull << 20).*/\1/p' $(b)))
$(HOST_PLAIN_O)/obj/tools/bake/main.o $(HOST_O)/obj/tools/bake/main.o: $(wildcard boards/*/board.h)
$(HOST_PLAIN_O)/obj/tools/bake/main.o $(HOST_O)/obj/tools/bake/main.o: HOST_CFLAGS += \
	-DHZ_BAKE_BOARD_SCENE_ARENAS='"$(BOARD_SCENE_ARENAS)"'
HOST_TEST_BINS := $(HOST_TESTS:%=$(HOST_O)/test/test_%)

bake: $(BAKE) ## build the scene baker tools/bake (hzbake) for the build machine into $(BUILD_ROOT)/host

# Real scenes (../shared/scenes, see SOURCES.md there): zips are unpacked into $(BUILD_ROOT)/scenes-src, each
# scene is baked with its sidecar tools/bake/scenes/<name>.hzs into $(BUILD_ROOT)/scenes/<name>.hzb. A scene is
# re-baked when its model, sidecar or the baker changes. The -small variants are the same models with tiny
# textures and few vertex-key frames: seeds for the fuzzer and images for the exhaustive corruption test.
SCENES_SRC ?= ../shared/scenes
SCENES_O := $(BUILD_ROOT)/scenes
SCENES_UNPACK := $(BUILD_ROOT)/scenes-src
SIDECAR_DIR := tools/bake/scenes
SCENE_ZIPS := CornellBox conference sponza lost-empire pine
SCENE_MODEL_CornellBox-Original := $(SCENES_UNPACK)/CornellBox/CornellBox-Original.obj
SCENE_MODEL_CornellBox-Mirror := $(SCENES_UNPACK)/CornellBox/CornellBox-Mirror.obj
SCENE_MODEL_conference := $(SCENES_UNPACK)/conference/conference.obj
SCENE_MODEL_sponza := $(SCENES_UNPACK)/sponza/sponza.obj
# sponza-smoke: Sponza with a 12000-particle smoke cloud (seed 004), written by tools/gen/smoke_scene.c.
SCENE_MODEL_sponza-smoke := $(SCENES_UNPACK)/sponza/sponza-smoke.obj
SCENE_MODEL_lost-empire := $(SCENES_UNPACK)/lost-empire/lost_empire.obj
SCENE_MODEL_pine := $(SCENES_UNPACK)/pine/scrubPine.obj
SCENE_MODEL_dragon-res4 := $(SCENES_SRC)/dragon/dragon_vrip_res4.ply.gz
SCENE_MODEL_dragon-res4-still := $(SCENE_MODEL_dragon-res4)
SCENE_MODEL_dragon-res3 := $(SCENES_SRC)/dragon/dragon_vrip_res3.ply.gz
SCENE_MODEL_dragon-res2 := $(SCENES_SRC)/dragon/dragon_vrip_res2.ply.gz
SCENE_MODEL_dragon := $(SCENES_SRC)/dragon/dragon_vrip.ply.gz
SCENE_MODEL_furball := $(SCENES_SRC)/furball/furBall_A.xml
SCENE_MODEL_BoxAnimated := $(SCENES_SRC)/gltf/BoxAnimated/glTF/BoxAnimated.gltf
SCENE_MODEL_CesiumMan := $(SCENES_SRC)/gltf/CesiumMan/glTF/CesiumMan.gltf
SCENE_MODEL_AlphaBlendModeTest := $(SCENES_SRC)/gltf/AlphaBlendModeTest/glTF/AlphaBlendModeTest.gltf
SCENE_MODEL_CesiumMan-small := $(SCENE_MODEL_CesiumMan)
SCENE_MODEL_CesiumMan-keys := $(SCENE_MODEL_CesiumMan)
SCENE_MODEL_CesiumMan-skin-small := $(SCENE_MODEL_CesiumMan)
# tentacles: the long skinned test model (48 joints, 61,440 triangles, 35 s), written by tools/gen/skinned_gltf.c.
SCENE_MODEL_tentacles := $(BUILD_ROOT)/scenes-gen/tentacles.gltf
SCENE_MODEL_AlphaBlendModeTest-small := $(SCENE_MODEL_AlphaBlendModeTest)
SCENE_MODEL_furball-sway := $(SCENE_MODEL_furball)
SCENE_MODEL_sponza-rotated := $(SCENE_MODEL_sponza)
SCENES := CornellBox-Original CornellBox-Mirror conference sponza lost-empire pine dragon-res4 dragon-res3 \
          dragon-res2 dragon furball BoxAnimated CesiumMan AlphaBlendModeTest CesiumMan-small \
          AlphaBlendModeTest-small sponza-smoke dragon-res4-still furball-sway sponza-rotated \
          CesiumMan-keys CesiumMan-skin-small tentacles
SCENE_FILES := $(SCENES:%=$(SCENES_O)/%.hzb)
# What each scene reads besides its model: the unpacked zip (its stamp) or every file beside the model.
scene_inputs = $(if $(filter $(SCENES_UNPACK)/%,$(1)),$(dir $(1)).unpacked,$(1) $(wildcard $(dir $(1))*))

$(SCENES_UNPACK)/%/.unpacked: $(SCENES_SRC)/%.zip
	@rm -rf $(dir $@) && mkdir -p $(dir $@)
	$(call msg,UNZIP,$<)unzip -q -o $< -d $(dir $@) && rm -rf $(dir $@)__MACOSX && touch $@

$(SCENES_O)/%.hzb: $(BAKE) $(SIDECAR_DIR)/%.hzs
	@mkdir -p $(dir $@)
	$(call msg,BAKE,$@)$(BAKE) -q -s $(SIDECAR_DIR)/$*.hzs $(SCENE_MODEL_$*) $@
$(foreach s,$(SCENES),$(eval $(SCENES_O)/$(s).hzb: $(call scene_inputs,$(SCENE_MODEL_$(s)))))
$(SCENE_MODEL_sponza-smoke): $(SCENES_UNPACK)/sponza/.unpacked $(BUILD_ROOT)/host/tools/gen/smoke_scene
	$(call msg,GEN,$@)$(BUILD_ROOT)/host/tools/gen/smoke_scene $(SCENES_UNPACK)/sponza
$(SCENES_O)/sponza-smoke.hzb: $(SCENE_MODEL_sponza-smoke)
$(SCENE_MODEL_tentacles): $(BUILD_ROOT)/host/tools/gen/skinned_gltf
	@mkdir -p $(dir $@)
	$(call msg,GEN,$@)$(BUILD_ROOT)/host/tools/gen/skinned_gltf $(dir $@)
$(SCENES_O)/tentacles.hzb: $(SCENE_MODEL_tentacles)

ifeq ($(wildcard $(SCENES_SRC)/SOURCES.md),)
scenes:
	@echo "scenes: no scene sources in '$(SCENES_SRC)' (set SCENES_SRC to the folder with conference.zip, gltf/, ...)" >&2
	@exit 1
else
scenes: deps ## bake every scene of ../shared/scenes (SCENES_SRC) into $(BUILD_ROOT)/scenes/*.hzb
	$(Q)$(MAKE) --no-print-directory scenes-baked
scenes-baked: $(SCENE_FILES)
endif

# Tests read the baked scenes from here (qemu passes the environment to the AArch64 tests too).
HZ_SCENES_DIR ?= $(abspath $(SCENES_O))
export HZ_SCENES_DIR
# test_flip compares with NVIDIA's FLIP on crops of two textures of the unpacked scene zips.
HZ_SCENES_UNPACK ?= $(abspath $(SCENES_UNPACK))
export HZ_SCENES_UNPACK
$(O)/test/unit/test_flip: $(SCENES_UNPACK)/pine/.unpacked $(SCENES_UNPACK)/lost-empire/.unpacked

# Loader fuzzer: libFuzzer (clang -fsanitize=fuzzer) on hz_scene_plan/hz_scene_load, seeded with the small
# real scenes. `make fuzz` runs it for FUZZ_SECONDS; `make test` runs FUZZ_RUNS inputs (seconds).
FUZZ_CC ?= clang
FUZZ_O := $(BUILD_ROOT)/fuzz
FUZZ := $(FUZZ_O)/fuzz_hzb
FUZZ_SECONDS ?= 60
FUZZ_RUNS ?= 4000
FUZZ_SEEDS := CornellBox-Original CornellBox-Mirror BoxAnimated dragon-res4 CesiumMan-small \
              AlphaBlendModeTest-small CesiumMan-skin-small
FUZZ_FLAGS := -std=c99 -O1 -g -fsanitize=fuzzer,address,undefined -fno-sanitize-recover=undefined \
              -ffp-contract=off -fno-math-errno -fno-strict-aliasing -Iinclude -Itools/host
$(FUZZ): test/fuzz/fuzz_hzb.c $(CORE_SRCS) $(SCENE_SRCS) $(wildcard include/hz/*.h src/scene/*.h)
	@mkdir -p $(dir $@)
	$(call msg,FUZZCC,$@)$(FUZZ_CC) $(FUZZ_FLAGS) -o $@ test/fuzz/fuzz_hzb.c $(CORE_SRCS) $(SCENE_SRCS)
$(FUZZ_O)/seeds/.stamp: $(FUZZ_SEEDS:%=$(SCENES_O)/%.hzb)
	@rm -rf $(dir $@) && mkdir -p $(dir $@)
	$(Q)cp $^ $(dir $@) && touch $@

fuzz: deps ## fuzz the .hzb loader for FUZZ_SECONDS (libFuzzer; findings in $(BUILD_ROOT)/fuzz)
	$(Q)$(MAKE) --no-print-directory $(FUZZ) $(FUZZ_O)/seeds/.stamp
	$(Q)mkdir -p $(FUZZ_O)/corpus $(FUZZ_O)/artifacts
	$(Q)$(FUZZ) -max_total_time=$(FUZZ_SECONDS) -max_len=4194304 -rss_limit_mb=4096 \
		-artifact_prefix=$(FUZZ_O)/artifacts/ $(FUZZ_O)/corpus $(FUZZ_O)/seeds

# Host-side tests (run by `make test`): the baker's tests and a bounded fuzzer run, results for the summary.
test-host: $(HOST_TEST_BINS) $(HOST_O)/bin/hzbake $(FUZZ) $(FUZZ_O)/seeds/.stamp scenes
	$(Q)rm -rf $(HOST_O)/test-results && mkdir -p $(HOST_O)/test-results
	$(Q)HZ_BAKE=$(abspath $(HOST_O)/bin/hzbake) HZ_SCENES_SRC=$(abspath $(SCENES_SRC)) \
		HZ_SCENES_UNPACK=$(abspath $(SCENES_UNPACK)) HZ_SCENES_GEN=$(abspath $(BUILD_ROOT)/scenes-gen) \
		sh test/run-tests.sh $(HOST_O)/test-results host "" $(HOST_TEST_BINS)
	$(Q)sh test/fuzz/run-fuzz.sh $(HOST_O)/test-results $(FUZZ) $(FUZZ_O)/seeds $(FUZZ_RUNS)

# ---------------------------------------------------------------------------------------------------------
# Dependencies (Debian packages). `?pkg` is optional: a failed install warns instead of stopping. The goals that
# install them (run, bench, report, scenes, fuzz, latency-sim) build the rest in a sub-make after `deps`: make 4.3 has no
# .WAIT, and with -j the compiler would otherwise start on headers apt-get has not unpacked yet.
DEPS_TEST_HOST := libcmocka-dev file unzip
# Host tools: the baker (assimp, stb_image, zlib; unzip for the scene zips) and the loader fuzzer (libFuzzer).
DEPS_BAKE := gcc libc6-dev libassimp-dev libstb-dev zlib1g-dev unzip libcmocka-dev
DEPS_FUZZ := clang libclang-rt-14-dev
DEPS_TEST_CROSS := gcc-aarch64-linux-gnu libc6-dev-arm64-cross binutils-aarch64-linux-gnu qemu-user-static \
                   libcmocka-dev:arm64
deps: ## install the Debian packages BOARD needs to build, run and test (apt-get as root; else print the line)
	$(Q)sh tools/deps.sh $(BOARD_DEPS) $(BOARD_TEST_DEPS) \
		$(if $(filter test stability,$(MAKECMDGOALS)),$(DEPS_TEST_HOST) $(DEPS_TEST_CROSS)) \
		$(if $(filter test scenes bake test-host bench report latency-sim,$(MAKECMDGOALS)),$(DEPS_BAKE)) \
		$(if $(filter test fuzz test-host,$(MAKECMDGOALS)),$(DEPS_FUZZ)) \
		$(if $(filter test vmtest,$(MAKECMDGOALS)),$(DEPS_VMTEST))

# ---------------------------------------------------------------------------------------------------------
# Run
RUN_ARGS ?= --mode tdense --frames 240 --hz 240 --size 640x360
run: deps ## build host-sim and render the built-in scene, temporally dense: 240 frames at a simulated 240 Hz into $(O)/run
	$(Q)$(MAKE) --no-print-directory $(HZRT)
	$(Q)$(HZRT) render builtin $(RUN_ARGS) --out $(O)/run
	@echo "outputs: $(O)/run/frames.y4m (mpv/ffplay), $(O)/run/last.png, $(O)/run/summary.json"

# Real-time runs against a simulated 240 Hz display (+-50 us jitter, 1% missed pulses, 0.5% glitches, +200 ppm),
# SCHED_FIFO when permitted, reports in $(O)/latency-sim*: the built-in scene at a size this host sustains; Sponza at 640x360 on 2 threads in every mode with the frame-budget governor on (each used level's error
# against level 0 measured after the run); and a load step, sponza-smoke's camera flying into the smoke, with the
# dithered (std) and the exact transparency. A table of all of them closes the run.
LATENCY_SIM_DISPLAY ?= --source sim --hz 240 --jitter-us 50 --miss-pct 1 --glitch-pct 0.5 --drift-ppm 200 --marker --rt
LATENCY_SIM_SIZE ?= 64x36
LATENCY_SIM_ARGS ?= $(LATENCY_SIM_DISPLAY) --seconds 20 --render scene --size $(LATENCY_SIM_SIZE)
LATENCY_SIM_SPONZA_SIZE ?= 640x360
LATENCY_SIM_SPONZA_THREADS ?= 2
LATENCY_SIM_SECONDS ?= 20
LATENCY_SIM_MODES ?= tdense taa full adaptive
LATENCY_SIM_LEVEL_ERROR ?= 16
LATENCY_SIM_SPONZA_ARGS ?= $(LATENCY_SIM_DISPLAY) --seconds $(LATENCY_SIM_SECONDS) --render scene \
                    --scene $(SCENES_O)/sponza.hzb --threads $(LATENCY_SIM_SPONZA_THREADS) \
                    --size $(LATENCY_SIM_SPONZA_SIZE) --level-error $(LATENCY_SIM_LEVEL_ERROR)
LATENCY_SIM_SMOKE_ARGS ?= $(LATENCY_SIM_DISPLAY) --seconds 8 --render scene --scene $(SCENES_O)/sponza-smoke.hzb \
                    --mode taa --threads $(LATENCY_SIM_SPONZA_THREADS) --size $(LATENCY_SIM_SPONZA_SIZE) \
                    --level-error $(LATENCY_SIM_LEVEL_ERROR)
latency-sim: deps ## real-time runs on a simulated 240 Hz display: built-in scene; Sponza 640x360 in every mode with the governor; the smoke load step (build/<board>/latency-sim*)
	$(Q)$(MAKE) --no-print-directory $(HZRT) scenes-baked
	$(Q)$(HZRT) latency $(LATENCY_SIM_ARGS) --out $(O)/latency-sim
	$(Q)for m in $(LATENCY_SIM_MODES); do \
		echo "== Sponza $(LATENCY_SIM_SPONZA_SIZE), $$m, governor on =="; \
		$(HZRT) latency $(LATENCY_SIM_SPONZA_ARGS) --mode $$m --out $(O)/latency-sim-sponza-$$m || exit $$?; \
	done
	$(Q)for t in std exact; do \
		echo "== sponza-smoke into the smoke, taa, --transparency $$t, governor on =="; \
		$(HZRT) latency $(LATENCY_SIM_SMOKE_ARGS) --transparency $$t --out $(O)/latency-sim-smoke-$$t || exit $$?; \
	done
	$(Q)sh tools/latency/governor-table.sh builtin-64x36=$(O)/latency-sim \
		$(foreach m,$(LATENCY_SIM_MODES),sponza-$(m)=$(O)/latency-sim-sponza-$(m)) \
		smoke-std=$(O)/latency-sim-smoke-std smoke-exact=$(O)/latency-sim-smoke-exact

bench: deps ## measure (side by side, in one run) and print a table; writes $(O)/bench/*.csv
	$(Q)$(MAKE) --no-print-directory $(BENCH) scenes
	$(Q)mkdir -p $(O)/bench
	$(Q)$(BENCH) --csv $(O)/bench/bench.csv --accel-csv $(O)/bench/accel.csv --scenes $(SCENES_O) \
		--transparency-csv $(O)/bench/transparency.csv --adaptive-csv $(O)/bench/adaptive.csv \
		--motion-csv $(O)/bench/motion.csv --realtime-csv $(O)/bench/realtime.csv $(BENCH_ARGS)

size: $(HZRT) ## section sizes of hzrt, its largest symbols and the board's static arenas
	$(Q)$(SIZE) $(HZRT) $(LIB)
	$(Q)echo "largest symbols:"; $(NM) --size-sort -S -r $(HZRT) | head -n 12

# ---------------------------------------------------------------------------------------------------------
# Generated tables (host tools under tools/gen; their output is committed and checked by tests)
GEN_BIN := $(BUILD_ROOT)/host/tools/gen
$(GEN_BIN)/srgb_tables: tools/gen/srgb_tables.c
	@mkdir -p $(dir $@)
	$(call msg,HOSTCC,$@)$(HOSTCC) $(WARN) -O2 -o $@ $< -lm

gen-srgb: $(GEN_BIN)/srgb_tables ## regenerate src/core/srgb_tables.c (exact sRGB 8-bit tables; test_image checks them)
	$(Q)$(GEN_BIN)/srgb_tables src/core/srgb_tables.c

$(GEN_BIN)/smoke_scene: tools/gen/smoke_scene.c tools/gen/genio.h
	@mkdir -p $(dir $@)
	$(call msg,HOSTCC,$@)$(HOSTCC) $(WARN) -D_POSIX_C_SOURCE=200809L -O2 -o $@ $< -lm

$(GEN_BIN)/skinned_gltf: tools/gen/skinned_gltf.c tools/gen/genio.h
	@mkdir -p $(dir $@)
	$(call msg,HOSTCC,$@)$(HOSTCC) $(WARN) -D_POSIX_C_SOURCE=200809L -O2 -o $@ $< -lm

$(GEN_BIN)/dither_tables: tools/gen/dither_tables.c tools/gen/vac.h
	@mkdir -p $(dir $@)
	$(call msg,HOSTCC,$@)$(HOSTCC) $(WARN) -O2 -o $@ $< -lm

gen-dither: $(GEN_BIN)/dither_tables ## regenerate src/pattern/dither_tables.c (STD maps, void-and-cluster blue noise; test_dither checks them)
	$(Q)$(GEN_BIN)/dither_tables src/pattern/dither_tables.c

# ---------------------------------------------------------------------------------------------------------
# Tests
tests: $(TEST_BINS) $(HZRT) ## build the test binaries of BOARD without running them

# Runs this board's tests and guards; results go to $(O)/test-results/ for the summary (failures are
# recorded there, so the run goes on to the summary line).
test-board: tests $(if $(BOARD_TEST_LAUNCHER),,$(BENCH))
	$(Q)rm -rf $(O)/test-results && mkdir -p $(O)/test-results
	$(Q)sh test/run-tests.sh $(O)/test-results "$(BOARD)" "$(BOARD_TEST_LAUNCHER)" $(TEST_BINS)
	$(Q)HZ_GUARD_LABEL=$(BOARD) sh test/guard/check-freestanding.sh --record $(O)/test-results "$(NM)" \
		$(CHECK_OBJS) || true
	$(Q)sh test/guard/check-integer.sh --record $(O)/test-results "$(CC)" "$(BOARD_ARCH)" $(INTEGER_SRCS) || true
	$(Q)sh test/guard/check-includes.sh --record $(O)/test-results || true
	$(Q)$(if $(BOARD_TEST_LAUNCHER),true,sh test/cli/run.sh $(O)/test-results $(HZRT) $(BENCH))
	$(Q)$(MAKE) --no-print-directory test-gpiod2

# Fixed memory per board (test/boards/fit.sh, run by `make test` for every board): `hzrt info` of each scene in
# the board's BOARD_FIT_SCENES (board.mk; default builtin) says the default mode fits the display, and one frame
# of it renders (under the board's test launcher: qemu for AArch64).
BOARD_FIT_SCENES ?= builtin
BOARD_FIT_RES ?= $(O)/test-results/board-fit.res
board-fit: $(HZRT) $(foreach s,$(filter-out builtin,$(BOARD_FIT_SCENES)),$(SCENES_O)/$(s).hzb) ## check that the board's default mode fits its display with its reference scenes
	$(Q)mkdir -p $(dir $(BOARD_FIT_RES))
	$(Q)sh test/boards/fit.sh $(BOARD_FIT_RES) "$(BOARD)" "$(BOARD_TEST_LAUNCHER)" $(HZRT) \
		$(foreach s,$(BOARD_FIT_SCENES),$(if $(filter builtin,$(s)),builtin,$(SCENES_O)/$(s).hzb))

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
# Boards make test only builds (their tests are the same code on the same ISAs): x86-kiosk and rpi4 compile with
# HZ_FEATURE_STATS 0 and their own ISA flags, which the tested boards do not.
BUILD_CHECK_BOARDS := x86-kiosk rpi4
test: deps ## build and run every test: scenes, host tools, host-sim, AArch64 under qemu, design guards
	$(Q)$(MAKE) --no-print-directory scenes || exit 1; \
	$(MAKE) --no-print-directory test-host || exit 1; \
	for b in $(TEST_BOARDS); do \
		$(MAKE) --no-print-directory BOARD=$$b O=$(BUILD_ROOT)/$$b$(SAN_SUFFIX) test-board || exit 1; \
	done; \
	for t in $(TEST_TIERS); do \
		$(MAKE) --no-print-directory $$t || exit 1; \
	done; \
	rm -rf $(BUILD_ROOT)/guards$(SAN_SUFFIX); \
	sh test/guard/run-guards.sh --record $(BUILD_ROOT)/guards$(SAN_SUFFIX); \
	for b in $(BUILD_CHECK_BOARDS); do \
		if $(MAKE) --no-print-directory BOARD=$$b O=$(BUILD_ROOT)/$$b$(SAN_SUFFIX) all >$(BUILD_ROOT)/guards$(SAN_SUFFIX)/build-$$b.log 2>&1; \
		then echo "  ok    board $$b builds"; echo "board-build/$$b 1 0 0" >$(BUILD_ROOT)/guards$(SAN_SUFFIX)/build-$$b.res; \
		else echo "  FAIL  board $$b does not build: $(BUILD_ROOT)/guards$(SAN_SUFFIX)/build-$$b.log"; \
			grep -m 5 error $(BUILD_ROOT)/guards$(SAN_SUFFIX)/build-$$b.log | sed 's/^/        /'; \
			echo "board-build/$$b 0 1 0" >$(BUILD_ROOT)/guards$(SAN_SUFFIX)/build-$$b.res; fi; \
	done; \
	for b in $(TEST_BOARDS) $(BUILD_CHECK_BOARDS); do \
		r=$(BUILD_ROOT)/guards$(SAN_SUFFIX)/board-fit-$$b.res; \
		$(MAKE) --no-print-directory BOARD=$$b O=$(BUILD_ROOT)/$$b$(SAN_SUFFIX) BOARD_FIT_RES=$$r board-fit || \
			[ -f $$r ] || echo "board-fit/$$b 0 1 0" >$$r; \
	done; \
	sh test/summary.sh $(HOST_O)/test-results $(foreach b,$(TEST_BOARDS),$(BUILD_ROOT)/$(b)$(SAN_SUFFIX)/test-results) \
		$(TEST_TIER_RESULTS) $(BUILD_ROOT)/guards$(SAN_SUFFIX)

# ---------------------------------------------------------------------------------------------------------
# VM tier (test/vm): Debian's arm64 kernel under qemu-system-aarch64 (virt, software emulation) runs the
# AArch64 unit tests natively and the device checks (vivid V4L2 loop-back, vivid fbdev, PL061 GPIO pulsed
# from the monitor). Results land next to the boards' for test/summary.sh.
VM_ROOT := $(BUILD_ROOT)/vm
VM_RESULTS := $(BUILD_ROOT)/vmtest$(SAN_SUFFIX)/test-results
DEPS_VMTEST := qemu-system-arm cpio kmod ?libgpiod-dev:arm64 ?libdrm-dev:arm64
TEST_TIERS += vmtest-tier
TEST_TIER_RESULTS += $(VM_RESULTS)
VM_DEVICE_TEST := $(O)/test/vm/test_vm_devices
VM_DRM_TEST := $(O)/test/vm/test_vm_drm
# Variables the unit tests read (as exported to them on the host); directories among their values are shared
# into the guest read-only at the same paths.
VM_TEST_ENV := HZ_SCENES_DIR HZ_SCENES_UNPACK
# In the VM (software-emulated CPU, ~10x slower than qemu user mode) run the unit tests that need no scene files
# and take seconds; the heavy ones (BVH builds over 10^5..10^6 triangles, whole-image corruption sweeps,
# rendered sequences) already run on the same AArch64 binaries under qemu-aarch64 in the board stage.
VM_HEAVY_TESTS := scene_corrupt accel_build accel_trav accel_water zero_alloc render render_transp errtime et_render \
                  render_speckles pack leaveout scene_clock accel_motion accel_motion_cli render_blur render_skin shade \
                  accel_par render_lanes render_overlap show render_reconfigure
VM_TEST_BINS := $(filter-out $(VM_HEAVY_TESTS:%=$(O)/test/unit/test_%),$(TEST_BINS))

vmtest: deps ## boot Debian's arm64 kernel in qemu-system-aarch64: AArch64 unit tests, V4L2 loop-back, GPIO capture
	$(Q)$(MAKE) --no-print-directory vmtest-tier
	$(Q)sh test/summary.sh $(VM_RESULTS)

vmtest-tier:
	$(Q)$(MAKE) --no-print-directory BOARD=aarch64-generic O=$(BUILD_ROOT)/aarch64-generic$(SAN_SUFFIX) vmtest-board

# Runs with BOARD=aarch64-generic (see vmtest-tier): its test binaries, plus a static hzrt and init.
vmtest-board: tests $(VM_DEVICE_TEST) $(VM_DRM_TEST) $(VM_ROOT)/init
	$(Q)$(MAKE) --no-print-directory BOARD=aarch64-generic O=$(VM_ROOT)/static BOARD_LDFLAGS=-static SAN= all
	$(Q)mkdir -p $(O)/test-results; $(MAKE) --no-print-directory $(VM_GPIOD2_TEST) >$(O)/test-results/gpiod2-vm-build.log 2>&1 || \
		rm -f $(VM_GPIOD2_TEST)
	$(Q)VM_ENV="$(foreach v,$(VM_TEST_ENV),$(v)=$($(v)))" sh test/vm/run.sh $(VM_RESULTS) $(VM_ROOT)/kernel \
		$(VM_ROOT)/init $(VM_ROOT)/static/bin/hzrt $(VM_DEVICE_TEST) $(VM_TEST_BINS) \
		$(VM_DRM_TEST) $$([ -x $(VM_GPIOD2_TEST) ] && echo $(VM_GPIOD2_TEST))
	$(Q)[ -x $(VM_GPIOD2_TEST) ] || { echo "  FAIL  vm-aarch64 test_vm_gpiod2: libgpiod 2 could not be fetched or linked (see $(O)/test-results/gpiod2-vm-build.log)"; \
		echo "vm-aarch64/test_vm_gpiod2 0 1 0" >$(VM_RESULTS)/test_vm_gpiod2.res; }

include tools/gpiod2/gpiod2.mk

$(VM_DEVICE_TEST): test/vm/test_vm_devices.c $(PORT_LIB) $(LIB)
	@mkdir -p $(dir $@)
	$(call msg,CCLD,$@)$(CC) $(TEST_CFLAGS) $(PORT_DEFS) -Iport/linux $(DEPFLAGS) $(LDFLAGS_ALL) -o $@ $< \
		$(PORT_LIB) $(LIB) $(TEST_LIBS) $(PORT_LIBS)

# The DRM/KMS sink on virtio-gpu: flips, their events, a screendump compared byte for byte (test/vm/test_vm_drm.c).
$(VM_DRM_TEST): test/vm/test_vm_drm.c $(PORT_LIB) $(LIB)
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

.PHONY: all deps run bench size tests test-board test check-freestanding check-integer clean help gen-srgb gen-dither errtime \
        bake scenes scenes-baked fuzz test-host report
.PHONY: vmtest vmtest-tier vmtest-board latency-sim
.PHONY: stability stability-tier stability-board board-fit
