# aarch64-generic — a Cortex-A72-class AArch64 Linux board with NEON: native backend only (Debian packages
# no arm64 Embree for this role), display through fbdev or V4L2 output, v-sync from a GPIO input.
BOARD_ARCH := aarch64
BOARD_CROSS_COMPILE := aarch64-linux-gnu-
BOARD_CFLAGS := -march=armv8-a -mtune=cortex-a72
BOARD_LDFLAGS :=
BOARD_SIMD := neon
BOARD_ACCEL := native
BOARD_PORTS := linux timing fbdev v4l2 gpio
BOARD_DEPS := gcc-aarch64-linux-gnu libc6-dev-arm64-cross binutils-aarch64-linux-gnu ?libgpiod-dev:arm64
# Tests of this board run under user-mode emulation on an x86-64 host.
# No -L: the multiarch loader and libc (libc6:arm64, pulled in by libcmocka-dev:arm64) must be used together.
# -L /usr/aarch64-linux-gnu paired the cross toolchain's ld.so (2.36-8cross1) with multiarch libc.so.6 (2.36-9+deb12u*):
# the two disagree on ld.so's internal layout and pthread_create spins forever in its stack cache list.
BOARD_TEST_LAUNCHER := qemu-aarch64-static
BOARD_TEST_DEPS := qemu-user-static libcmocka-dev:arm64
