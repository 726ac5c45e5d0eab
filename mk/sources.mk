# ---------------------------------------------------------------------------------------------------------
# Sources, found by pattern: every src/<module>/*.c builds on every board, except the per-ISA files —
# *_avx2.c and *_neon.c only where BOARD_SIMD names that ISA, *_lanes.c (one kernel source over the lane
# wrappers of src/core/lanes.h) on every SIMD board. A new source file needs no edit here.
#   core     arenas, status, formatter, fixed point, hash + RNG, CRC-32, vec/mat, images + sRGB codes
#   scene    baked format, validating loader, built-in scene, animation, skinning
#   accel    BVH build and traversal (the Embree backend lives in port/embree)
#   render   camera, shading, G-buffer, transparency; recon: the render modes and their reconstruction
#   pattern  integer-only tile orderings, dither maps, masks
#   timing   v-sync model, pacing, latency statistics, the frame loop and its governor; integer-only throughout
SIMD_SUFFIXES := %_avx2.c %_neon.c %_lanes.c
module_srcs = $(filter-out $(SIMD_SUFFIXES),$(wildcard src/$(1)/*.c))
module_simd_srcs = $(filter %_$(BOARD_SIMD).c $(if $(filter scalar,$(BOARD_SIMD)),,%_lanes.c),$(wildcard src/$(1)/*.c))
MODULES := core scene accel render recon pattern timing
CORE_SRCS := $(call module_srcs,core)
SCENE_SRCS := $(call module_srcs,scene)
TIMING_SRCS := $(call module_srcs,timing)
# Integer-only code: no FP/SIMD registers at all (INTEGER_FLAGS), checked on both ISAs.
INTEGER_SRCS := src/core/fixed.c src/core/hash.c src/core/crc32.c $(call module_srcs,pattern) $(TIMING_SRCS)

# with embree in BOARD_ACCEL: the backend's port sources
PORT_SRCS_embree := port/embree/embree_accel.c

# Ports of the timing path (port/linux): `timing` (frame loop, report, `hzrt latency`, simulated display,
# VCD/CSV replay) goes on every board; `fbdev`, `v4l2` and `gpio` where the hardware has them.
PORT_SRCS_timing := port/linux/timebase.c port/linux/vsrc_timeline.c \
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

LIB_SRCS := $(foreach m,$(MODULES),$(call module_srcs,$(m)) $(call module_simd_srcs,$(m)))
LIB_OBJS := $(LIB_SRCS:%.c=$(O)/%.o)
LIB := $(O)/libhz.a

# Ports: each board lists the ones it links (BOARD_PORTS); accel backends come from BOARD_ACCEL.
KNOWN_PORTS := linux timing fbdev v4l2 gpio drm
PORT_SRCS_linux := port/linux/pools.c port/linux/cli.c port/linux/clock.c port/linux/fileio.c port/linux/scenefile.c \
                   port/linux/threads.c port/linux/accel_backend.c \
                   port/linux/render_run.c
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

# The programs (programs/, doc/layout.md), found by pattern: programs/<name>/*.c is one program, its main() in
# main.c (hzbench's in bench.c). programs/opt is the option parser and option forms every program shares. A
# program sees the port's headers and programs/opt; hzrt also sees errtime's metrics (its governor's levels).
PROGRAM_CFLAGS := -Iport/linux -Iprograms/opt
OPT_SRCS := $(wildcard programs/opt/*.c)
OPT_OBJS := $(OPT_SRCS:%.c=$(O)/%.o)
OPT_LIB := $(O)/libhzopt.a
# hzrt: the commands (render, show, latency, accel, info, board); every file but main.c is also the commands'
# archive the unit tests drive them through.
CMD_SRCS := $(filter-out programs/hzrt/main.c,$(wildcard programs/hzrt/*.c))
CMD_OBJS := $(CMD_SRCS:%.c=$(O)/%.o)
$(O)/programs/hzrt/show.o: EXTRA_CFLAGS += -Iprograms/hzerrtime
HZRT_SRCS := programs/hzrt/main.c $(CMD_SRCS)
HZRT_OBJS := $(HZRT_SRCS:%.c=$(O)/%.o)
HZRT := $(O)/bin/hzrt

BENCH_SRCS := $(wildcard programs/hzbench/*.c)
BENCH_OBJS := $(BENCH_SRCS:%.c=$(O)/%.o)
BENCH := $(O)/bin/hzbench

TEST_CFLAGS := $(HOSTED_CFLAGS) -Itest $(if $(BOARD_TEST_LAUNCHER),-DHZ_TEST_EMULATED)
TEST_LIBS := -lcmocka

# errtime (programs/hzerrtime): image metrics (PSNR, SSIM, FLIP), report writers and the error-against-run-time
# driver. Built with the board's compiler, like hzbench: it times the board's renderer. Hosted C99 with libm.
# Its files are prefixed et_ because hzrt and the tests see them beside port/linux.
ERRTIME_SRCS := $(filter-out programs/hzerrtime/main.c,$(wildcard programs/hzerrtime/*.c))
ERRTIME_MAIN_SRCS := programs/hzerrtime/main.c
ERRTIME_OBJS := $(ERRTIME_SRCS:%.c=$(O)/%.o)
ERRTIME_MAIN_OBJS := $(ERRTIME_MAIN_SRCS:%.c=$(O)/%.o)
ERRTIME_LIB := $(O)/liberrtime.a
ERRTIME := $(O)/bin/hzerrtime
# The metric filters' inner loops run over x: vectorising them keeps every pixel's sum in the same order (same
# results) and makes FLIP ~2x faster; -O2's "very cheap" cost model leaves them scalar.
$(O)/programs/hzerrtime/et_flip.o $(O)/programs/hzerrtime/et_metrics.o: HOSTED_CFLAGS += -fvect-cost-model=dynamic

ALL_OBJS := $(LIB_OBJS) $(PORT_OBJS) $(OPT_OBJS) $(HZRT_OBJS) $(BENCH_OBJS) $(ERRTIME_OBJS) $(ERRTIME_MAIN_OBJS)

# Unit tests, found by pattern: every $(TEST_UNIT_DIR)/test_<name>.c is a test binary linked with the core, the
# port, errtime and the commands' library (archives: each binary takes only what it calls). A line
# "hz-test: TAG..." in a test's top comment limits where it runs:
#   native   only on boards whose tests run natively (under qemu-user the same code runs in cheaper tests)
#   embree   only with the Embree backend (BOARD_ACCEL)
#   devices  only with the fbdev or V4L2 port
#   no-vm    not in the system-emulated VM tier (make vmtest: ~10x slower than qemu-user; these run there)
#   manual   built and run by its own rule (test_gpiod2: tools/gpiod2/gpiod2.mk)
TEST_UNIT_DIR ?= test/unit
TEST_SRCS := $(sort $(wildcard $(TEST_UNIT_DIR)/test_*.c))
TEST_TAGS := $(shell awk 'FNR == 1 { n = FILENAME; sub(/.*\//, "", n); sub(/\.c$$/, "", n) } \
	FNR > 40 { nextfile } /hz-test:/ { sub(/.*hz-test: */, ""); \
	for (i = 1; i <= NF && substr($$i, 1, 1) != "\050"; i++) printf "%s:%s ", n, $$i; nextfile }' $(TEST_SRCS) /dev/null)
TEST_TAG_NAMES := native embree devices no-vm manual
$(foreach t,$(TEST_TAGS),$(if $(filter $(TEST_TAG_NAMES),$(lastword $(subst :, ,$(t)))),,$(error \
	$(TEST_UNIT_DIR)/$(firstword $(subst :, ,$(t))).c: unknown hz-test tag '$(lastword $(subst :, ,$(t)))' (known: $(TEST_TAG_NAMES)))))
tests_tagged = $(patsubst %:$(1),%,$(filter %:$(1),$(TEST_TAGS)))
TESTS_LEFT_OUT := $(call tests_tagged,manual) \
                  $(if $(BOARD_TEST_LAUNCHER),$(call tests_tagged,native)) \
                  $(if $(filter embree,$(BOARD_ACCEL)),,$(call tests_tagged,embree)) \
                  $(if $(filter fbdev v4l2,$(BOARD_PORTS)),,$(call tests_tagged,devices))
TEST_NAMES := $(filter-out $(TESTS_LEFT_OUT),$(notdir $(TEST_SRCS:.c=)))
TEST_BINS := $(TEST_NAMES:%=$(O)/test/unit/%)
TESTS_NO_VM := $(call tests_tagged,no-vm)

print-tests: ## list the unit tests BOARD builds and runs (found by pattern in test/unit; see mk/sources.mk)
	@echo $(TEST_NAMES)
