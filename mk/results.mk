# Generated results and the documentation guard.
#
# `make bench` also writes its groups as Markdown tables ($(O)/bench/bench.md: hzbench --md, each table read back
# from the CSV the run wrote); `make report` writes $(REPORT_O)/errtime.md. `make results` runs both and writes
# doc/results.md from those tables (tools/results/results.sh), with the date, the machine and the commands in its
# header: the only way figures get into doc/. BENCH_ARGS and the report's variables pass through (e.g.
# `make results BENCH_ARGS="--only accel" REPORT_SCENES=builtin@240`), and the header names them.
override BENCH_ARGS += --md $(O)/bench/bench.md

RESULTS_MD ?= doc/results.md
results: deps ## run make bench and make report, then write doc/results.md from their Markdown tables
	$(Q)$(MAKE) --no-print-directory bench
	$(Q)$(MAKE) --no-print-directory report
	$(Q)sh tools/results/results.sh $(RESULTS_MD) \
		"make bench$(if $(filter-out --md $(O)/bench/bench.md,$(BENCH_ARGS)), BENCH_ARGS=\"$(filter-out --md $(O)/bench/bench.md,$(BENCH_ARGS))\")" \
		$(O)/bench/bench.md \
		"make report$(if $(filter command line,$(origin REPORT_SCENES)), REPORT_SCENES=$(REPORT_SCENES))$(if $(filter command line,$(origin REPORT_SKIP)), REPORT_SKIP=$(REPORT_SKIP))" \
		$(REPORT_O)/errtime.md

# The documentation guard (test/guard/check-docs.sh; `make test` runs it with the other guards, from
# test/guard/run-guards.sh): every make target and program option that README.md and doc/ show exists, and
# neither names an issue number or a commit hash. It reads the programs' --help, so it needs them built.
DOCS_HOST_SIM := $(BUILD_ROOT)/host-sim$(SAN_SUFFIX)
DOCS_PROGS := $(DOCS_HOST_SIM)/bin/hzrt $(DOCS_HOST_SIM)/bin/hzbench $(DOCS_HOST_SIM)/bin/hzerrtime
export HZ_DOCS_HZRT ?= $(abspath $(DOCS_HOST_SIM)/bin/hzrt)
export HZ_DOCS_HZBENCH ?= $(abspath $(DOCS_HOST_SIM)/bin/hzbench)
export HZ_DOCS_HZERRTIME ?= $(abspath $(DOCS_HOST_SIM)/bin/hzerrtime)
export HZ_DOCS_HZBAKE ?= $(abspath $(HOST_O)/bin/hzbake)
check-docs: deps ## check the commands README.md and doc/ show (make targets, program options); no issue numbers or hashes
	$(Q)$(MAKE) --no-print-directory BOARD=host-sim O=$(DOCS_HOST_SIM) $(DOCS_PROGS)
	$(Q)$(MAKE) --no-print-directory $(HOST_O)/bin/hzbake
	$(Q)sh test/guard/check-docs.sh

.PHONY: results check-docs

