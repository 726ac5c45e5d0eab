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
# Features a build leaves out of what its board has (hz/config.h; doc/boards.md): FEATURES_OFF="transparency
# motion", or "all". Such a build has a folder of its own (build/host-sim-no-transparency-motion), so that its
# objects never mix with the board's.
FEATURE_NAMES := textures mirrors transparency motion
FEATURES_OFF ?=
override FEATURES_OFF := $(if $(filter all,$(FEATURES_OFF)),$(FEATURE_NAMES),$(FEATURES_OFF))
$(foreach f,$(FEATURES_OFF),$(if $(filter $(f),$(FEATURE_NAMES)),,$(error FEATURES_OFF: unknown feature '$(f)' (features: $(FEATURE_NAMES), or all))))
FEATURES_OFF_LIST := $(filter $(FEATURES_OFF),$(FEATURE_NAMES))
empty :=
space := $(empty) $(empty)
FEATURES_SUFFIX := $(if $(FEATURES_OFF_LIST),-no-$(subst $(space),-,$(FEATURES_OFF_LIST)))
FEATURES_DEFS := $(foreach f,$(FEATURES_OFF_LIST),-DHZ_FEATURE_OFF_$(shell echo $(f) | tr a-z A-Z)=1)

BUILD_ROOT ?= build
O ?= $(BUILD_ROOT)/$(BOARD)$(FEATURES_SUFFIX)$(SAN_SUFFIX)

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
BOARD_DEFS := -DHZ_BOARD_SIMD_$(shell echo $(BOARD_SIMD) | tr a-z A-Z)=1 $(FEATURES_DEFS)
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
