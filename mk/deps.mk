# ---------------------------------------------------------------------------------------------------------
# Dependencies (Debian packages). `?pkg` is optional: a failed install warns instead of stopping. The goals that
# install them (run, bench, report, scenes, fuzz, latency-sim) build the rest in a sub-make after `deps`: make 4.3 has no
# .WAIT, and with -j the compiler would otherwise start on headers apt-get has not unpacked yet.
DEPS_TEST_HOST := libcmocka-dev file unzip
# Host tools: the baker (assimp, stb_image, zlib; unzip for the scene zips) and the fuzzers (libFuzzer; the
# import and sidecar targets link the baker, the loader's seeds are baked scenes).
DEPS_BAKE := gcc libc6-dev libassimp-dev libstb-dev zlib1g-dev unzip libcmocka-dev
DEPS_FUZZ := clang libclang-rt-14-dev
DEPS_TEST_CROSS := gcc-aarch64-linux-gnu libc6-dev-arm64-cross binutils-aarch64-linux-gnu qemu-user-static \
                   libcmocka-dev:arm64
deps: ## install the Debian packages BOARD needs to build, run and test (apt-get as root; else print the line)
	$(Q)sh tools/deps.sh $(BOARD_DEPS) $(BOARD_TEST_DEPS) \
		$(if $(filter test stability,$(MAKECMDGOALS)),$(DEPS_TEST_HOST) $(DEPS_TEST_CROSS)) \
		$(if $(filter test scenes bake test-host bench report latency-sim fuzz,$(MAKECMDGOALS)),$(DEPS_BAKE)) \
		$(if $(filter test fuzz test-host,$(MAKECMDGOALS)),$(DEPS_FUZZ)) \
		$(if $(filter test vmtest,$(MAKECMDGOALS)),$(DEPS_VMTEST))
