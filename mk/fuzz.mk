# Fuzz targets (test/fuzz, doc/testing.md): libFuzzer with ASan and UBSan on every parser a user hands hzrt:
# the .hzb loader, VCD and CSV traces, sidecars, the baker's model import (in a child process, as hzbake
# runs it) and the command line of hzrt render, show and latency (checked, never run). Seeds are in test/fuzz/corpus/<target>, the loader's are baked (FUZZ_SEEDS below).
# `make fuzz` runs each target for FUZZ_SECONDS, FUZZ_JOBS at a time, and reports executions, coverage and
# findings (test/fuzz/fuzz-all.sh); `make test` runs FUZZ_RUNS inputs of each (test/fuzz/run-fuzz.sh).
FUZZ_CC ?= clang
FUZZ_O := $(BUILD_ROOT)/fuzz
FUZZ_ALL := hzb vcd ecsv sidecar import opts
FUZZ_TARGETS ?= $(FUZZ_ALL)
FUZZ_SECONDS ?= 60
FUZZ_JOBS ?= $(shell nproc)
FUZZ_RUNS ?= 4000
# The loader's seeds: small baked scenes and the images the import target bakes from its seeds (every section
# kind, a few KB each: a large seed costs its size in every execution).
FUZZ_SEEDS := CornellBox-Original CornellBox-Mirror BoxAnimated AlphaBlendModeTest-small
FUZZ_FLAGS := -std=c99 -O1 -g -fsanitize=fuzzer,address,undefined -fno-sanitize-recover=undefined \
              -ffp-contract=off -fno-math-errno -fno-strict-aliasing -D_POSIX_C_SOURCE=200809L \
              -Iinclude -Itools/host -Iprograms/hzbake -Iport/linux -Iprograms/opt -Isrc/timing
FUZZ_SRCS_hzb := $(CORE_SRCS) $(SCENE_SRCS)
FUZZ_SRCS_vcd := $(CORE_SRCS) $(TIMING_SRCS)
FUZZ_SRCS_ecsv := $(FUZZ_SRCS_vcd)
FUZZ_SRCS_sidecar := $(HOST_LIB_SRCS) $(BAKE_LIB_SRCS)
FUZZ_SRCS_import := $(FUZZ_SRCS_sidecar)
# The commands' entry points link the whole renderer (scalar, the host tools' board.h) and errtime; no device
# ports: their entry points fail with "not built in" (devices_absent.c), and the target runs none of them.
FUZZ_SRCS_opts := $(foreach m,$(MODULES),$(call module_srcs,$(m))) $(PORT_SRCS_linux) $(PORT_SRCS_timing) \
                  $(CMD_SRCS) $(OPT_SRCS) $(ERRTIME_SRCS)
FUZZ_LIBS_opts := -lpthread -lm
$(FUZZ_O)/fuzz_opts: FUZZ_FLAGS += -Iprograms/hzerrtime -Iprograms/hzrt
FUZZ_LIBS_sidecar := $(BAKE_LIBS)
FUZZ_LIBS_import := $(FUZZ_O)/fuzz_counters.o $(FUZZ_O)/fuzz_judge.o $(BAKE_LIBS)
FUZZ := $(FUZZ_TARGETS:%=$(FUZZ_O)/fuzz_%)
define FUZZ_TARGET
$(FUZZ_O)/fuzz_$(1): test/fuzz/fuzz_$(1).c $(FUZZ_SRCS_$(1)) $(filter %.o,$(FUZZ_LIBS_$(1))) \
                     $(wildcard include/hz/*.h src/*/*.h programs/hzbake/*.h test/fuzz/*.h)
	@mkdir -p $$(dir $$@)
	$$(call msg,FUZZCC,$$@)$$(FUZZ_CC) $$(FUZZ_FLAGS) -o $$@ $$< $(FUZZ_SRCS_$(1)) $(FUZZ_LIBS_$(1))
endef
$(foreach t,$(FUZZ_ALL),$(eval $(call FUZZ_TARGET,$(t))))
$(FUZZ_O)/fuzz_counters.o $(FUZZ_O)/fuzz_judge.o: $(FUZZ_O)/%.o: test/fuzz/%.c # not instrumented: see the files
	@mkdir -p $(dir $@)
	$(call msg,FUZZCC,$@)$(FUZZ_CC) -std=c99 -O1 -c -o $@ $<
$(FUZZ_O)/seeds/.stamp: $(FUZZ_SEEDS:%=$(SCENES_O)/%.hzb) $(FUZZ_O)/fuzz_import $(wildcard test/fuzz/corpus/import/*)
	@rm -rf $(dir $@) && mkdir -p $(dir $@)
	$(Q)cp $(filter %.hzb,$^) $(dir $@)
	$(call msg,FUZZSEED,$(dir $@))HZ_FUZZ_IMPORT_SAVE_HZB=$(dir $@) TMPDIR=$(FUZZ_O) $(FUZZ_O)/fuzz_import -rss_limit_mb=0 \
		$(wildcard test/fuzz/corpus/import/*) >$(FUZZ_O)/seeds.log 2>&1 || { cat $(FUZZ_O)/seeds.log; exit 1; }
	@touch $@

fuzz: deps ## fuzz every input parser for FUZZ_SECONDS each, FUZZ_JOBS at once (libFuzzer; report in $(BUILD_ROOT)/fuzz)
	$(Q)$(MAKE) --no-print-directory $(FUZZ) $(if $(filter hzb,$(FUZZ_TARGETS)),$(FUZZ_O)/seeds/.stamp)
	$(Q)sh test/fuzz/fuzz-all.sh $(FUZZ_O) $(FUZZ_SECONDS) $(FUZZ_JOBS) $(FUZZ_TARGETS)
