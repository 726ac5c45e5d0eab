# aarch64-generic — a Cortex-A72-class AArch64 Linux board with NEON: native backend only (Debian packages
# no arm64 Embree for this role), display through fbdev or V4L2 output, v-sync from a GPIO input.
BOARD_ARCH := aarch64
BOARD_CROSS_COMPILE := aarch64-linux-gnu-
BOARD_CFLAGS := -march=armv8-a -mtune=cortex-a72
BOARD_LDFLAGS :=
BOARD_SIMD := neon
BOARD_ACCEL := native
BOARD_PORTS := linux
BOARD_DEPS := gcc-aarch64-linux-gnu libc6-dev-arm64-cross binutils-aarch64-linux-gnu ?libgpiod-dev:arm64
# Tests of this board run under user-mode emulation on an x86-64 host.
BOARD_TEST_LAUNCHER := qemu-aarch64-static -L /usr/aarch64-linux-gnu
BOARD_TEST_DEPS := qemu-user-static libcmocka-dev:arm64
