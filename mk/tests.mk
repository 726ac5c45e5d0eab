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

# Host-side tests (run by `make test`): the baker's tests and a bounded run of each fuzz target, results for the summary.
test-host: $(HOST_TEST_BINS) $(HOST_O)/bin/hzbake $(FUZZ) $(FUZZ_O)/seeds/.stamp scenes
	$(Q)rm -rf $(HOST_O)/test-results && mkdir -p $(HOST_O)/test-results
	$(Q)HZ_BAKE=$(abspath $(HOST_O)/bin/hzbake) HZ_SCENES_SRC=$(abspath $(SCENES_SRC)) \
		HZ_SCENES_UNPACK=$(abspath $(SCENES_UNPACK)) HZ_SCENES_GEN=$(abspath $(BUILD_ROOT)/scenes-gen) \
		sh test/run-tests.sh $(HOST_O)/test-results host "" $(HOST_TEST_BINS)
	$(Q)sh test/fuzz/run-fuzz.sh $(HOST_O)/test-results $(FUZZ_O) $(FUZZ_RUNS) $(FUZZ_TARGETS)
