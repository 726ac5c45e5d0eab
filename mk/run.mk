# ---------------------------------------------------------------------------------------------------------
# Run
RUN_ARGS ?= --mode tdense --frames 240 --hz 240 --size 640x360
run: deps ## build host-sim and render the built-in scene, temporally dense: 240 frames at a simulated 240 Hz into $(O)/run
	$(Q)$(MAKE) --no-print-directory $(HZRT)
	$(Q)$(HZRT) render builtin $(RUN_ARGS) --out $(O)/run
	@echo "outputs: $(O)/run/frames.y4m (mpv/ffplay), $(O)/run/last.png, $(O)/run/summary.json"

# Real-time runs against a simulated 240 Hz display (+-50 us jitter, 1% missed pulses, 0.5% glitches, +200 ppm),
# SCHED_FIFO when permitted, reports in $(O)/latency-sim*: the built-in scene at a size this host sustains; Sponza at 640x360 on 2 threads in every mode with the frame-budget governor on (each used level's error
# against level 0 measured after the run); and a load step, sponza-smoke's camera flying into the smoke, with the
# dithered (std) and the exact transparency. A table of all of them closes the run.
LATENCY_SIM_DISPLAY ?= --source sim --hz 240 --jitter-us 50 --miss-pct 1 --glitch-pct 0.5 --drift-ppm 200 --marker --rt
LATENCY_SIM_SIZE ?= 64x36
LATENCY_SIM_ARGS ?= $(LATENCY_SIM_DISPLAY) --seconds 20 --render scene --size $(LATENCY_SIM_SIZE)
LATENCY_SIM_SPONZA_SIZE ?= 640x360
LATENCY_SIM_SPONZA_THREADS ?= 2
LATENCY_SIM_SECONDS ?= 20
LATENCY_SIM_MODES ?= tdense taa full adaptive
LATENCY_SIM_LEVEL_ERROR ?= 16
LATENCY_SIM_SPONZA_ARGS ?= $(LATENCY_SIM_DISPLAY) --seconds $(LATENCY_SIM_SECONDS) --render scene \
                    --scene $(SCENES_O)/sponza.hzb --threads $(LATENCY_SIM_SPONZA_THREADS) \
                    --size $(LATENCY_SIM_SPONZA_SIZE) --level-error $(LATENCY_SIM_LEVEL_ERROR)
LATENCY_SIM_SMOKE_ARGS ?= $(LATENCY_SIM_DISPLAY) --seconds 8 --render scene --scene $(SCENES_O)/sponza-smoke.hzb \
                    --mode taa --threads $(LATENCY_SIM_SPONZA_THREADS) --size $(LATENCY_SIM_SPONZA_SIZE) \
                    --level-error $(LATENCY_SIM_LEVEL_ERROR)
latency-sim: deps ## real-time runs on a simulated 240 Hz display: built-in scene; Sponza 640x360 in every mode with the governor; the smoke load step (build/<board>/latency-sim*)
	$(Q)$(MAKE) --no-print-directory $(HZRT) scenes-baked
	$(Q)$(HZRT) latency $(LATENCY_SIM_ARGS) --out $(O)/latency-sim
	$(Q)for m in $(LATENCY_SIM_MODES); do \
		echo "== Sponza $(LATENCY_SIM_SPONZA_SIZE), $$m, governor on =="; \
		$(HZRT) latency $(LATENCY_SIM_SPONZA_ARGS) --mode $$m --out $(O)/latency-sim-sponza-$$m || exit $$?; \
	done
	$(Q)for t in std exact; do \
		echo "== sponza-smoke into the smoke, taa, --transparency $$t, governor on =="; \
		$(HZRT) latency $(LATENCY_SIM_SMOKE_ARGS) --transparency $$t --out $(O)/latency-sim-smoke-$$t || exit $$?; \
	done
	$(Q)sh tools/latency/governor-table.sh builtin-64x36=$(O)/latency-sim \
		$(foreach m,$(LATENCY_SIM_MODES),sponza-$(m)=$(O)/latency-sim-sponza-$(m)) \
		smoke-std=$(O)/latency-sim-smoke-std smoke-exact=$(O)/latency-sim-smoke-exact

bench: deps ## measure (side by side, in one run) and print a table; writes $(O)/bench/*.csv
	$(Q)$(MAKE) --no-print-directory $(BENCH) scenes
	$(Q)mkdir -p $(O)/bench
	$(Q)$(BENCH) --csv $(O)/bench/bench.csv --accel-csv $(O)/bench/accel.csv --scenes $(SCENES_O) \
		--transparency-csv $(O)/bench/transparency.csv --adaptive-csv $(O)/bench/adaptive.csv \
		--motion-csv $(O)/bench/motion.csv --realtime-csv $(O)/bench/realtime.csv $(BENCH_ARGS)

# The soak (test/unit/test_soak.c): every mode, motion blur and every transparency method for SOAK_FRAMES frames
# each on a simulated 240 Hz display; zero heap calls after the warm-up, constant arena high-water marks, a scene
# that keeps animating, and the render time of the first and last 10^4 frames. make test runs it with 1000 (natively:
# the loop and the renderer are the same code under qemu, where make test runs their own tests).
SOAK_FRAMES ?= 100000
soak: deps ## 10^5 frames per mode and option on a simulated display: zero heap calls, constant high-water, frame times first vs last 10^4
	$(Q)$(MAKE) --no-print-directory $(O)/test/unit/test_soak
	$(Q)CMOCKA_MESSAGE_OUTPUT=stdout HZ_SOAK_FRAMES=$(SOAK_FRAMES) $(BOARD_TEST_LAUNCHER) $(O)/test/unit/test_soak | \
		grep -E '^  soak |PASSED|FAILED|ERROR'

size: $(HZRT) ## section sizes of hzrt, its largest symbols and the board's static arenas
	$(Q)$(SIZE) $(HZRT) $(LIB)
	$(Q)echo "largest symbols:"; $(NM) --size-sort -S -r $(HZRT) | head -n 12
