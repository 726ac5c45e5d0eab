# rpi4 — Raspberry Pi 4 Model B (BCM2711, 4x Cortex-A72) with an 800x480 RGB666 DPI panel at 60 Hz; the
# panel's VSYNC (GPIO2 in DPI mode) is looped back to GPIO26 as an input for latency capture. See README.md.
BOARD_ARCH := aarch64
BOARD_CROSS_COMPILE := aarch64-linux-gnu-
BOARD_CFLAGS := -mcpu=cortex-a72
BOARD_LDFLAGS :=
BOARD_SIMD := neon
BOARD_ACCEL := native
BOARD_PORTS := linux timing fbdev gpio
BOARD_DEPS := gcc-aarch64-linux-gnu libc6-dev-arm64-cross binutils-aarch64-linux-gnu ?libgpiod-dev:arm64
# No -L: the multiarch loader and libc (libc6:arm64, pulled in by libcmocka-dev:arm64) must be used together.
# -L /usr/aarch64-linux-gnu paired the cross toolchain's ld.so (2.36-8cross1) with multiarch libc.so.6 (2.36-9+deb12u*):
# the two disagree on ld.so's internal layout and pthread_create spins forever in its stack cache list.
BOARD_TEST_LAUNCHER := qemu-aarch64-static
BOARD_TEST_DEPS := qemu-user-static libcmocka-dev:arm64
