# host-sim — the host simulation build: x86-64 with AVX2, renders to files against a simulated display clock,
# and carries Embree as the reference backend next to the native one.
BOARD_ARCH := x86_64
BOARD_CROSS_COMPILE :=
# x86-64-v3 = AVX2 + FMA + BMI1/2 + F16C + LZCNT + MOVBE (Haswell and newer, Zen 1 and newer).
BOARD_CFLAGS := -march=x86-64-v3 -mtune=generic
BOARD_LDFLAGS :=
BOARD_SIMD := avx2
BOARD_ACCEL := native embree
BOARD_PORTS := linux timing drm
# Debian packages needed to build this board (make deps).
BOARD_DEPS := gcc make libc6-dev binutils libembree-dev libtbb-dev libpng-dev libdrm-dev
BOARD_TEST_LAUNCHER :=
BOARD_TEST_DEPS := libcmocka-dev
# Scenes `make test` checks this board with (test/boards/fit.sh): the default mode fits the display and the default
# command (`hzrt show`) runs it there.
BOARD_FIT_SCENES := builtin conference
