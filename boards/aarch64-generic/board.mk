# aarch64-generic — a Cortex-A72-class AArch64 Linux board with NEON: native backend only (Debian packages
# no arm64 Embree for this role), display through fbdev or V4L2 output, v-sync from a GPIO input.
BOARD_ARCH := aarch64
BOARD_CROSS_COMPILE := aarch64-linux-gnu-
BOARD_CFLAGS := -march=armv8-a -mtune=cortex-a72
BOARD_LDFLAGS :=
BOARD_SIMD := neon
BOARD_ACCEL := native
BOARD_PORTS := linux timing drm fbdev v4l2 gpio
BOARD_DEPS := gcc-aarch64-linux-gnu libc6-dev-arm64-cross binutils-aarch64-linux-gnu ?libgpiod-dev:arm64 ?libdrm-dev:arm64
# Tests of this board run under user-mode emulation on an x86-64 host.
# ld.so and libc.so.6 must come from the same glibc build. With -L alone the cross ld.so (libc6-arm64-cross)
# searched /lib/aarch64-linux-gnu first and found the multiarch libc.so.6 (libc6:arm64, a different 2.36
# build pulled in by libcmocka-dev:arm64): they disagree on ld.so's internal layout and pthread_create spins
# forever. LD_LIBRARY_PATH puts the cross libc (and libubsan for SAN=1) first; cmocka still comes from multiarch.
# -cpu cortex-a72: the core these boards are built for (qemu-user's default "max" adds pointer
# authentication, SVE and more, which the binaries do not use but the libraries' PAC prologues make it
# emulate: the same tests ran about a quarter faster as an A72).
BOARD_TEST_LAUNCHER := qemu-aarch64-static -cpu cortex-a72 -L /usr/aarch64-linux-gnu -E LD_LIBRARY_PATH=/lib:/usr/lib/aarch64-linux-gnu
BOARD_TEST_DEPS := qemu-user-static libcmocka-dev:arm64
# Scenes `make test` checks this board with (test/boards/fit.sh): the default mode fits the display and the default
# command (`hzrt show`) runs it there.
BOARD_FIT_SCENES := builtin sponza
