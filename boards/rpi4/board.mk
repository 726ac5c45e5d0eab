# rpi4 — Raspberry Pi 4 Model B (BCM2711, 4x Cortex-A72) with an 800x480 RGB666 DPI panel at 60 Hz; the
# panel's VSYNC (GPIO2 in DPI mode) is looped back to GPIO26 as an input for latency capture. See README.md.
BOARD_ARCH := aarch64
BOARD_CROSS_COMPILE := aarch64-linux-gnu-
BOARD_CFLAGS := -mcpu=cortex-a72
BOARD_LDFLAGS :=
BOARD_SIMD := neon
BOARD_ACCEL := native
BOARD_PORTS := linux timing drm fbdev gpio
BOARD_DEPS := gcc-aarch64-linux-gnu libc6-dev-arm64-cross binutils-aarch64-linux-gnu ?libgpiod-dev:arm64 ?libdrm-dev:arm64
# ld.so and libc.so.6 must come from the same glibc build. With -L alone the cross ld.so (libc6-arm64-cross)
# searched /lib/aarch64-linux-gnu first and found the multiarch libc.so.6 (libc6:arm64, a different 2.36
# build pulled in by libcmocka-dev:arm64): they disagree on ld.so's internal layout and pthread_create spins
# forever. LD_LIBRARY_PATH puts the cross libc (and libubsan for SAN=1) first; cmocka still comes from multiarch.
# -cpu cortex-a72: the Pi 4's core (see aarch64-generic's board.mk).
BOARD_TEST_LAUNCHER := qemu-aarch64-static -cpu cortex-a72 -L /usr/aarch64-linux-gnu -E LD_LIBRARY_PATH=/lib:/usr/lib/aarch64-linux-gnu
BOARD_TEST_DEPS := qemu-user-static libcmocka-dev:arm64
# Scenes `make test` checks this board with (test/boards/fit.sh): the default mode fits the display and the default
# command (`hzrt show`) runs it there.
BOARD_FIT_SCENES := builtin sponza
