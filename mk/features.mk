# ---------------------------------------------------------------------------------------------------------
# Compile-out switches (hz/config.h, doc/boards.md). `make FEATURES_OFF="..."` builds a board without some of
# its features (its own folder, see mk/config.mk); `make features` builds hzrt for FEATURES_BOARDS with every
# feature on, each one off alone and all off, and writes what each costs in firmware text and bss
# (test/features/table.sh: build/features/sizes.md and sizes.csv). `make test` builds and checks the all-off
# configuration of host-sim (test-features-off).
FEATURES_BOARDS ?= host-sim aarch64-generic
FEATURES_O := $(BUILD_ROOT)/features
FEATURE_CONFIGS := on $(FEATURE_NAMES) all
features_o = $(BUILD_ROOT)/$(1)$(if $(filter-out on,$(2)),-no-$(subst $(space),-,$(if $(filter all,$(2)),$(FEATURE_NAMES),$(2))))$(SAN_SUFFIX)

features: ## build hzrt for FEATURES_BOARDS with all features on, each off alone and all off; table of text and bss (build/features)
	$(Q)mkdir -p $(FEATURES_O) && rm -f $(FEATURES_O)/list.new # a run stopped half-way left its list
	$(Q)for b in $(FEATURES_BOARDS); do for c in $(FEATURE_CONFIGS); do \
		o=$$(case $$c in on) echo $(BUILD_ROOT)/$$b ;; all) echo $(BUILD_ROOT)/$$b-no-$(subst $(space),-,$(FEATURE_NAMES)) ;; \
			*) echo $(BUILD_ROOT)/$$b-no-$$c ;; esac); \
		echo "  FEATURES $$b $$c ($$o)"; \
		$(MAKE) --no-print-directory BOARD=$$b FEATURES_OFF="$$(echo $$c | sed s/^on$$//)" O=$$o features-size \
			>$(FEATURES_O)/$$b-$$c.log 2>&1 || { tail -n 20 $(FEATURES_O)/$$b-$$c.log; exit 1; }; \
		echo "$$b $$c $$o/hzrt.size" >>$(FEATURES_O)/list.new; \
	done; done; mv -f $(FEATURES_O)/list.new $(FEATURES_O)/list
	$(Q)sh test/features/table.sh $(FEATURES_O)/list $(FEATURES_O)/sizes.md $(FEATURES_O)/sizes.csv

# One configuration (the sub-make of `make features`): hzrt and its size (Berkeley: text data bss).
features-size: $(HZRT)
	$(Q)$(SIZE) -B $(HZRT) | tail -n 1 >$(O)/hzrt.size

# make test: the all-off build of host-sim renders a scene without those features and refuses, by name, a scene
# or an option that needs each (test/features/off.sh; only hzrt is built).
FEATURES_OFF_TEST_O := $(call features_o,host-sim,all)
test-features-off: scenes
	$(Q)mkdir -p $(GUARDS_O)
	$(Q)if $(MAKE) --no-print-directory BOARD=host-sim FEATURES_OFF=all O=$(FEATURES_OFF_TEST_O) \
		$(FEATURES_OFF_TEST_O)/bin/hzrt >$(GUARDS_O)/features-off-build.log 2>&1; then \
		sh test/features/off.sh $(GUARDS_O) $(FEATURES_OFF_TEST_O)/bin/hzrt $(SCENES_O); \
	else echo "  FAIL  features-off: the all-off build of host-sim failed: $(GUARDS_O)/features-off-build.log"; \
		echo "features-off/build 0 1 0" >$(GUARDS_O)/features-off.res; fi
.PHONY: features features-size test-features-off
