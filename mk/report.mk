# `make report`: every renderer method of programs/hzerrtime/et_methods.c on the standard scenes, each at its table
# entry's size, length and display rate: the general set (full-frame 1/4/9/16 spp, TAA, adaptive supersampling
# at tau 0.1/0.3/0.6/1) on CornellBox-Mirror, Sponza, Lost Empire, Conference and the built-in scene, and temporally dense rendering against 1 spp and TAA at 60 and
# 240 Hz on a 240 Hz display (the @240 scenes). References cached in $(BUILD_ROOT)/errtime-cache (delete it for
# a cold run). The TAA variants stay out of the chart (within ~2% of the default TAA's FLIP everywhere, they pile
# up on its point): `hzerrtime --methods taa,taa-clip,taa-catmull-rom,taa-clip-cr` compares them.
REPORT_O := $(BUILD_ROOT)/report
REPORT_SCENES := CornellBox-Mirror,sponza,lost-empire,conference,builtin,builtin@240,sponza@240,conference@240
# Transparency (seed 004): every --transparency method with TAA, the still-view stability figure, and std under
# tdense at 240 Hz against + TAA at 60 Hz; crossing: blended objects moving through each other.
REPORT_SCENES := $(REPORT_SCENES),sponza-smoke,AlphaBlendModeTest,builtin-transp,crossing,sponza-smoke@240,AlphaBlendModeTest@240
# Motion blur (seed 002): msbvh, interp, rigid instances and Embree at equal time budget on 30 Hz sequences with the shutter open.
REPORT_BLUR_SCENES := builtin-blur,sponza-rotated-blur
REPORT_SCENES := $(REPORT_SCENES),$(REPORT_BLUR_SCENES)
REPORT_SKIP := taa-clip,taa-catmull-rom,taa-clip-cr
# Adaptive supersampling at its operating point (seed 003, Table 2 at 1024x1024; 640x360 beside it): per scene,
# the largest tau whose PSNR reaches full-frame 9 spp's (hzerrtime --adaptive-search), its time and rays against
# 9 spp's; the tables are appended to errtime.md. REPORT_OP_SIZES= leaves them out.
REPORT_OP_SCENES := conference,sponza,CornellBox-Mirror,lost-empire
REPORT_OP_SIZES := 1024x1024 640x360
report: deps ## error against run time of every method on the standard scenes: build/report/ (CSV, MD, SVG)
	$(Q)$(MAKE) --no-print-directory $(ERRTIME) scenes
	$(Q)t0=$$(date +%s); nice $(ERRTIME) --scene $(REPORT_SCENES) --skip $(REPORT_SKIP) --scenes $(SCENES_O) \
		--cache $(BUILD_ROOT)/errtime-cache --out $(REPORT_O) || exit $$?; \
	for s in $(REPORT_OP_SIZES); do \
		nice $(ERRTIME) --scene $(REPORT_OP_SCENES) --size $$s --frames 5 --warmup 1 \
			--methods full-frame,adaptive,adaptive-bilinear,adaptive-footprint --adaptive-search --scenes $(SCENES_O) \
			--cache $(BUILD_ROOT)/errtime-cache --out $(REPORT_O)/adaptive-op-$$s || exit $$?; \
		{ echo; cat $(REPORT_O)/adaptive-op-$$s/adaptive-search.md; } >>$(REPORT_O)/errtime.md || exit $$?; \
	done; \
	echo "report: $$(( $$(date +%s) - t0 )) s on $$(nproc) cores"
