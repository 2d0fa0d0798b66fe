# feeddrive — build the FMU, run the main job, test, benchmark.
#   make / make fmu   build build/LinearMotorFeedDrive.fmu (and its copy inside the package,
#                     python/feeddrive/, git-ignored: the package data of installs and wheels)
#                     and the controller FMU build/DriveController.fmu, and the plant as an FMI 3.0
#                     FMU build/LinearMotorFeedDrive3.fmu (same physics; FMI 2.0 stays the default)
#                     and the controller as FMI 3.0, build/DriveController3.fmu
#   make run          set-up, FMU, the paper's closed-loop reproductions, report (prints the tables)
#   make lint         ruff (rules of python/pyproject.toml) over the Python, mypy over the package
#   make test         set-up, lint, FMU, the importers, Chromium (browser), every test
#   make importers    the importers the tests run besides fmpy, from registries only (below)
#   make bench        benchmark table (build/bench.md)
#   make docs         the documentation site (MkDocs, mkdocs.yml) into build/docs/, warnings as errors
#   make wheel        build/feeddrive-*.whl carrying the FMU
# Every FMU carries its Linux binary and, where mingw-w64 is installed (or installable: root and
# apt-get), its Windows x86-64 DLL cross-built from the same sources (win64 / x86_64-windows);
# without mingw-w64 the FMUs carry the Linux binary only and make says why in one line.
MODEL      := LinearMotorFeedDrive
PYTHON     ?= python3
VENV       := .venv
PY         := $(VENV)/bin/python
BUILD      := build
GEN        := $(BUILD)/gen
FMU        := $(BUILD)/$(MODEL).fmu
PKG_FMU    := python/feeddrive/$(MODEL).fmu
SHARED     ?= ../shared
TESTS_C    := $(CURDIR)/$(BUILD)/tests_c
SO         := $(BUILD)/binaries/linux64/$(MODEL).so
CC         ?= cc
# -fno-semantic-interposition: the library's own calls between its files go direct, not through
# the PLT (no FMU function is meant to be replaced by another library's)
FMU_CFLAGS := -std=c99 -O3 -fno-math-errno -fPIC -fno-semantic-interposition -Wall -Wextra -Werror -D_POSIX_C_SOURCE=200809L -D_DEFAULT_SOURCE
# fmu_src/ by concept: fmi/ (the FMI glue), models/plant/ and models/controller/ (the two models),
# physics/ (the plant's equations), solvers/ (integrators and the per-sample scheme),
# generators/ (the XML to C tables)
SRC_DIRS   := fmu_src/fmi fmu_src/models/plant fmu_src/physics fmu_src/solvers
SRC_INC    := $(addprefix -I ,$(SRC_DIRS))
SRC_C      := $(filter-out fmu_src/fmi/fmi3%.c,$(wildcard $(addsuffix /*.c,$(SRC_DIRS))))
# the effect table's list of effects is generated from the XML with the value table (gen_vars.py)
SRC_H      := $(wildcard $(addsuffix /*.h,$(SRC_DIRS))) $(GEN)/model_effects.h
STAMP      := $(VENV)/.installed
# the controller FMU: its own sources and XML (fmu_src/models/controller/: its model of the FMI
# glue, ctrl_model.c, and its law), the one FMI glue (fmu_src/fmi/) it shares with the plant, the
# plant's parameters imported as plant.* (value reference + 1000), the plant's physics files
# compiled in
CTRL       := DriveController
CTRL_FMU   := $(BUILD)/$(CTRL).fmu
PKG_CTRL_FMU := python/feeddrive/$(CTRL).fmu
CTRL_GEN   := $(GEN)/controller
CTRL_SO    := $(BUILD)/controller/binaries/linux64/$(CTRL).so
# (params.c compiles every effect through the effect table: every effect's file is compiled in)
CTRL_SHARED := fmu_src/models/plant/params.c fmu_src/physics/effects.c fmu_src/physics/current_loop.c \
               fmu_src/physics/position_maps.c fmu_src/physics/friction_levels.c fmu_src/physics/friction_gms.c \
               fmu_src/physics/friction_position.c fmu_src/physics/offset_force.c fmu_src/physics/compliance.c
GLUE_C     := $(filter-out fmu_src/fmi/fmi3%.c,$(wildcard fmu_src/fmi/*.c))
GLUE_H     := $(wildcard fmu_src/fmi/*.h)
CTRL_SRC_C := $(filter-out %/ctrl_clock.c,$(wildcard fmu_src/models/controller/*.c)) $(CTRL_SHARED) $(GLUE_C)
CTRL_SHARED_H := fmu_src/models/plant/params.h fmu_src/physics/plant.h fmu_src/physics/effect.h \
                 $(GEN)/model_effects.h $(GLUE_H)
CTRL_SRC_H := $(wildcard fmu_src/models/controller/*.h) $(CTRL_SHARED_H)
# the plant as FMI 3.0: modelDescription and value table generated from the FMI 2.0 XML
# (fmu_src/generators/gen_fmi3.py), the fmi3 glue over the shared fmi2 one; only fmi3* exported
MODEL3     := $(MODEL)3
GEN3       := $(BUILD)/gen3
FMU3       := $(BUILD)/$(MODEL3).fmu
PKG_FMU3   := python/feeddrive/$(MODEL3).fmu
SO3        := $(BUILD)/fmi3/binaries/x86_64-linux/$(MODEL3).so
SRC3_C     := $(wildcard $(addsuffix /*.c,$(SRC_DIRS)))
# the controller as FMI 3.0: the FMI 3.0 glue and its clock, its value table generated as the plant's
CTRL3      := $(CTRL)3
CTRL3_GEN  := $(GEN)/controller3
CTRL3_FMU  := $(BUILD)/$(CTRL3).fmu
PKG_CTRL3_FMU := python/feeddrive/$(CTRL3).fmu
CTRL3_SO   := $(BUILD)/controller3/binaries/x86_64-linux/$(CTRL3).so
GLUE3_C    := $(wildcard fmu_src/fmi/fmi3*.c)
CTRL3_SRC_C := $(CTRL_SRC_C) fmu_src/models/controller/ctrl_clock.c $(GLUE3_C)

# the Windows x86-64 DLLs: mingw-w64 (Debian gcc-mingw-w64-x86-64), the flags of the Linux build
# less -fPIC and the POSIX feature macros (the product code is plain C99), MinGW's C99 printf
# family (%zu, %lld); tools/win_dll.py compiles, exports only the FMI functions and checks that the
# DLL imports only KERNEL32 and the C runtime. $(WIN_TOOLCHAIN) says "ok" or why not (rewritten
# only when that changes; an installation that failed is tried again after `make clean`, a
# mingw-w64 installed by hand is found at once); each DLL's .made stamp stands for the DLL, or for
# its absence.
MINGW_CC   ?= x86_64-w64-mingw32-gcc
WIN_CFLAGS := -std=c99 -O3 -fno-math-errno -Wall -Wextra -Werror -D__USE_MINGW_ANSI_STDIO=1
WIN_TOOLCHAIN := $(BUILD)/win64/toolchain
WIN_DLL    = $(PY) tools/win_dll.py --cc $(MINGW_CC)
DLL        := $(BUILD)/win64/plant/$(MODEL).dll
DLL3       := $(BUILD)/win64/plant3/$(MODEL3).dll
CTRL_DLL   := $(BUILD)/win64/controller/$(CTRL).dll
CTRL3_DLL  := $(BUILD)/win64/controller3/$(CTRL3).dll
# --binary PLATFORM FILE for the FMU packager when the DLL was built
win_binary = $$([ -f $(2) ] && echo --binary $(1) $(2))
# the wine64 program the tests run the win64 binaries with (Debian wine64; make test installs it)
WINE_APT   := wine64

# the importers besides fmpy (the Python ones, libcosimpy and ecospy, are in python[test]):
# * fmi-sim (Rust, crates.io): `cargo install --locked` into IMPORTERS_CACHE, outside the clone
#   and keyed by version, so another clone (or a CI job that keeps ~/.cache) links the binary
#   instead of compiling it again; linked as build/importers/fmi-sim
# * FMI4j (Maven Central): tests/java compiled, its classpath written; the test runs Maven offline
# * fmipp (FMI++, PyPI sdist): swig and boost from Debian (as root), the sdist patched by
#   tools/patch_fmipp.py (no SUNDIALS: Debian's is too new for it; the import module only), built
#   once into a wheel in IMPORTERS_CACHE (per Python), installed into .venv
# Each that cannot be installed writes its one-line reason to build/importers/<name>.skip
# (make goes on; the test skips with that reason).
FMI_SIM_VERSION := 0.7.0
IMPORTERS_CACHE ?= $(HOME)/.cache/feeddrive/importers
FMI_SIM_ROOT    := $(IMPORTERS_CACHE)/fmi-sim-$(FMI_SIM_VERSION)
FMI_SIM         := $(BUILD)/importers/fmi-sim
FMI4J_CP        := $(BUILD)/fmi4j-target/classpath.txt
FMIPP_VERSION   := 2.1.0
FMIPP_SRC       := $(BUILD)/importers/fmipp-src
FMIPP_STAMP     := $(VENV)/.fmipp-installed
FMIPP_APT       := swig libboost-filesystem-dev libboost-system-dev

.PHONY: all fmu run lint test bench wheel clean venv fuzz-tools importers docs wine-tools browser interval-coverage FORCE
all: fmu
fmu: $(FMU) $(PKG_FMU) $(CTRL_FMU) $(PKG_CTRL_FMU) $(FMU3) $(PKG_FMU3) $(CTRL3_FMU) $(PKG_CTRL3_FMU)
venv: $(STAMP)

$(STAMP): python/pyproject.toml
	test -x $(PY) || $(PYTHON) -m venv $(VENV)
	$(PY) -m pip install -q --upgrade pip
	$(PY) -m pip install -q -e 'python[test,docs]'
	touch $@

$(BUILD)/fmi_include: $(STAMP)
	mkdir -p $(BUILD)
	$(PY) -c "import fmpy, os; print(os.path.join(os.path.dirname(fmpy.__file__), 'c-code'))" > $@

$(GEN)/model_vars.h $(GEN)/model_vars.c $(GEN)/model_effects.h: modelDescription.xml fmu_src/generators/gen_vars.py $(STAMP)
	$(PY) fmu_src/generators/gen_vars.py modelDescription.xml $(GEN)

$(SO): $(SRC_C) $(SRC_H) $(GEN)/model_vars.h $(GEN)/model_vars.c $(BUILD)/fmi_include
	mkdir -p $(dir $@)
	$(CC) $(FMU_CFLAGS) $(CFLAGS) -shared -fvisibility=default $(SRC_INC) -I $(GEN) -I "$$(cat $(BUILD)/fmi_include)" \
	    -o $@ $(SRC_C) $(GEN)/model_vars.c -lm
	@! (ldd $@ | grep -v -E 'linux-vdso|libc\.so|libm\.so|ld-linux|not a dynamic' | grep -q .) || \
	    (echo "error: $@ links more than libc/libm:"; ldd $@; exit 1)

$(FMU): $(SO) $(DLL).made modelDescription.xml
	$(PY) tools/package_fmu.py --xml modelDescription.xml --so $(SO) $(call win_binary,win64,$(DLL)) \
	    --sources $(SRC_DIRS) $(GEN) --out $@

$(WIN_TOOLCHAIN): FORCE
	@mkdir -p $(dir $@)
	@if ! command -v $(MINGW_CC) >/dev/null 2>&1 && ! grep -qs '^none' $@ && [ "$$(id -u)" = 0 ] && \
	    command -v apt-get >/dev/null 2>&1; then echo "installing mingw-w64 (Debian gcc-mingw-w64-x86-64) for the win64 binaries"; \
	    apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends \
	    gcc-mingw-w64-x86-64 >/dev/null; fi; \
	if command -v $(MINGW_CC) >/dev/null 2>&1; then echo "ok $(MINGW_CC)" > $@.new; else \
	    echo "none: $(MINGW_CC) (Debian gcc-mingw-w64-x86-64) is not installed and cannot be installed here: the FMUs carry Linux binaries only" > $@.new; \
	    cut -c7- $@.new; fi; \
	if cmp -s $@.new $@; then rm -f $@.new; else mv $@.new $@; fi

$(DLL).made: $(SRC_C) $(SRC_H) $(GEN)/model_vars.h $(GEN)/model_vars.c $(BUILD)/fmi_include $(WIN_TOOLCHAIN) tools/win_dll.py
	@rm -f $(DLL); mkdir -p $(dir $@)
	@! grep -q '^ok' $(WIN_TOOLCHAIN) || $(WIN_DLL) --out $(DLL) --exports fmi2 -- $(WIN_CFLAGS) $(SRC_INC) -I $(GEN) \
	    -I "$$(cat $(BUILD)/fmi_include)" $(SRC_C) $(GEN)/model_vars.c
	@touch $@

$(PKG_FMU): $(FMU)
	cp $< $@

$(GEN3)/modelDescription.xml $(GEN3)/buildDescription.xml $(GEN3)/model_vars3.h $(GEN3)/model_vars3.c: \
    modelDescription.xml fmu_src/generators/gen_fmi3.py $(STAMP)
	$(PY) fmu_src/generators/gen_fmi3.py modelDescription.xml $(GEN3)

$(SO3): $(SRC3_C) $(SRC_H) fmu_src/fmi/fmi3.map $(GEN)/model_vars.h $(GEN)/model_vars.c $(GEN3)/model_vars3.h \
    $(GEN3)/model_vars3.c $(BUILD)/fmi_include
	mkdir -p $(dir $@)
	$(CC) $(FMU_CFLAGS) $(CFLAGS) -shared -fvisibility=default -Wl,--no-undefined -Wl,--version-script=fmu_src/fmi/fmi3.map \
	    $(SRC_INC) -I $(GEN) -I $(GEN3) -I "$$(cat $(BUILD)/fmi_include)" \
	    -o $@ $(SRC3_C) $(GEN)/model_vars.c $(GEN3)/model_vars3.c -lm
	@! (ldd $@ | grep -v -E 'linux-vdso|libc\.so|libm\.so|ld-linux|not a dynamic' | grep -q .) || \
	    (echo "error: $@ links more than libc/libm:"; ldd $@; exit 1)

$(DLL3).made: $(SRC3_C) $(SRC_H) $(GEN)/model_vars.h $(GEN)/model_vars.c $(GEN3)/model_vars3.h $(GEN3)/model_vars3.c \
    $(BUILD)/fmi_include $(WIN_TOOLCHAIN) tools/win_dll.py
	@rm -f $(DLL3); mkdir -p $(dir $@)
	@! grep -q '^ok' $(WIN_TOOLCHAIN) || $(WIN_DLL) --out $(DLL3) --exports fmi3 -- $(WIN_CFLAGS) $(SRC_INC) -I $(GEN) \
	    -I $(GEN3) -I "$$(cat $(BUILD)/fmi_include)" $(SRC3_C) $(GEN)/model_vars.c $(GEN3)/model_vars3.c
	@touch $@

$(FMU3): $(SO3) $(DLL3).made $(GEN3)/modelDescription.xml $(GEN3)/buildDescription.xml
	$(PY) tools/package_fmu.py --xml $(GEN3)/modelDescription.xml --so $(SO3) $(call win_binary,x86_64-windows,$(DLL3)) \
	    --sources $(SRC_DIRS) $(GEN) $(GEN3) $(GEN3)/buildDescription.xml --platform x86_64-linux --out $@

$(PKG_FMU3): $(FMU3)
	cp $< $@

$(CTRL_GEN)/ctrl_vars.h $(CTRL_GEN)/ctrl_vars.c $(CTRL_GEN)/modelDescription.xml: \
    fmu_src/models/controller/modelDescription.xml modelDescription.xml fmu_src/generators/gen_vars.py $(STAMP)
	$(PY) fmu_src/generators/gen_vars.py --prefix CTRL --import modelDescription.xml plant. 1000 \
	    fmu_src/models/controller/modelDescription.xml $(CTRL_GEN)

$(CTRL_SO): $(CTRL_SRC_C) $(CTRL_SRC_H) $(GEN)/model_vars.h $(GEN)/model_vars.c $(CTRL_GEN)/ctrl_vars.h \
    $(CTRL_GEN)/ctrl_vars.c $(BUILD)/fmi_include
	mkdir -p $(dir $@)
	$(CC) $(FMU_CFLAGS) -ffp-contract=off $(CFLAGS) -shared -fvisibility=default -Wl,--no-undefined \
	    -I fmu_src/models/controller $(SRC_INC) -I $(CTRL_GEN) -I $(GEN) -I "$$(cat $(BUILD)/fmi_include)" \
	    -o $@ $(CTRL_SRC_C) $(GEN)/model_vars.c $(CTRL_GEN)/ctrl_vars.c -lm
	@! (ldd $@ | grep -v -E 'linux-vdso|libc\.so|libm\.so|ld-linux|not a dynamic' | grep -q .) || \
	    (echo "error: $@ links more than libc/libm:"; ldd $@; exit 1)

$(CTRL_DLL).made: $(CTRL_SRC_C) $(CTRL_SRC_H) $(GEN)/model_vars.h $(GEN)/model_vars.c $(CTRL_GEN)/ctrl_vars.h \
    $(CTRL_GEN)/ctrl_vars.c $(BUILD)/fmi_include $(WIN_TOOLCHAIN) tools/win_dll.py
	@rm -f $(CTRL_DLL); mkdir -p $(dir $@)
	@! grep -q '^ok' $(WIN_TOOLCHAIN) || $(WIN_DLL) --out $(CTRL_DLL) --exports fmi2 -- $(WIN_CFLAGS) -ffp-contract=off \
	    -I fmu_src/models/controller $(SRC_INC) -I $(CTRL_GEN) -I $(GEN) -I "$$(cat $(BUILD)/fmi_include)" \
	    $(CTRL_SRC_C) $(GEN)/model_vars.c $(CTRL_GEN)/ctrl_vars.c
	@touch $@

$(CTRL_FMU): $(CTRL_SO) $(CTRL_DLL).made $(CTRL_GEN)/modelDescription.xml
	$(PY) tools/package_fmu.py --xml $(CTRL_GEN)/modelDescription.xml --so $(CTRL_SO) $(call win_binary,win64,$(CTRL_DLL)) \
	    --sources fmu_src/models/controller $(CTRL_GEN) $(CTRL_SHARED) $(CTRL_SHARED_H) $(GLUE_C) \
	    $(GEN)/model_vars.h $(GEN)/model_vars.c --out $@

$(PKG_CTRL_FMU): $(CTRL_FMU)
	cp $< $@

$(CTRL3_GEN)/modelDescription.xml $(CTRL3_GEN)/buildDescription.xml $(CTRL3_GEN)/model_vars3.h $(CTRL3_GEN)/model_vars3.c: \
    $(CTRL_GEN)/modelDescription.xml fmu_src/generators/gen_fmi3.py
	$(PY) fmu_src/generators/gen_fmi3.py --controller $(CTRL_GEN)/modelDescription.xml $(CTRL3_GEN)

$(CTRL3_SO): $(CTRL3_SRC_C) $(CTRL_SRC_H) fmu_src/fmi/fmi3.map $(GEN)/model_vars.h $(GEN)/model_vars.c \
    $(CTRL_GEN)/ctrl_vars.h $(CTRL_GEN)/ctrl_vars.c $(CTRL3_GEN)/model_vars3.h $(CTRL3_GEN)/model_vars3.c $(BUILD)/fmi_include
	mkdir -p $(dir $@)
	$(CC) $(FMU_CFLAGS) -ffp-contract=off $(CFLAGS) -shared -fvisibility=default -Wl,--no-undefined \
	    -Wl,--version-script=fmu_src/fmi/fmi3.map -I fmu_src/models/controller $(SRC_INC) -I $(CTRL_GEN) -I $(CTRL3_GEN) \
	    -I $(GEN) -I "$$(cat $(BUILD)/fmi_include)" -o $@ $(CTRL3_SRC_C) $(GEN)/model_vars.c $(CTRL_GEN)/ctrl_vars.c \
	    $(CTRL3_GEN)/model_vars3.c -lm
	@! (ldd $@ | grep -v -E 'linux-vdso|libc\.so|libm\.so|ld-linux|not a dynamic' | grep -q .) || \
	    (echo "error: $@ links more than libc/libm:"; ldd $@; exit 1)

$(CTRL3_DLL).made: $(CTRL3_SRC_C) $(CTRL_SRC_H) $(GEN)/model_vars.h $(GEN)/model_vars.c $(CTRL_GEN)/ctrl_vars.h \
    $(CTRL_GEN)/ctrl_vars.c $(CTRL3_GEN)/model_vars3.h $(CTRL3_GEN)/model_vars3.c $(BUILD)/fmi_include $(WIN_TOOLCHAIN) \
    tools/win_dll.py
	@rm -f $(CTRL3_DLL); mkdir -p $(dir $@)
	@! grep -q '^ok' $(WIN_TOOLCHAIN) || $(WIN_DLL) --out $(CTRL3_DLL) --exports fmi3 -- $(WIN_CFLAGS) -ffp-contract=off \
	    -I fmu_src/models/controller $(SRC_INC) -I $(CTRL_GEN) -I $(CTRL3_GEN) -I $(GEN) -I "$$(cat $(BUILD)/fmi_include)" \
	    $(CTRL3_SRC_C) $(GEN)/model_vars.c $(CTRL_GEN)/ctrl_vars.c $(CTRL3_GEN)/model_vars3.c
	@touch $@

$(CTRL3_FMU): $(CTRL3_SO) $(CTRL3_DLL).made $(CTRL3_GEN)/modelDescription.xml $(CTRL3_GEN)/buildDescription.xml
	$(PY) tools/package_fmu.py --xml $(CTRL3_GEN)/modelDescription.xml --so $(CTRL3_SO) $(call win_binary,x86_64-windows,$(CTRL3_DLL)) \
	    --sources fmu_src/models/controller $(CTRL_GEN) $(CTRL_SHARED) $(CTRL_SHARED_H) $(GLUE_C) $(GLUE3_C) \
	    $(GEN)/model_vars.h $(GEN)/model_vars.c $(CTRL3_GEN)/model_vars3.h $(CTRL3_GEN)/model_vars3.c \
	    $(CTRL3_GEN)/buildDescription.xml \
	    --platform x86_64-linux --out $@

$(PKG_CTRL3_FMU): $(CTRL3_FMU)
	cp $< $@

run: fmu
	$(PY) -m feeddrive.cli run --shared $(SHARED) --force

# the coverage-guided fuzz run of the tests needs clang's libFuzzer (and fmi-sim's build its
# libclang, for bindgen): installed here from Debian's packages when missing and apt-get is usable
# (root); otherwise that test is skipped and says why
fuzz-tools:
	@command -v $${CLANG:-clang} >/dev/null 2>&1 || { [ "$$(id -u)" = 0 ] && command -v apt-get >/dev/null 2>&1 && \
	    apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq clang >/dev/null; } || \
	    echo "note: clang is not installed and cannot be installed here: the libFuzzer run is skipped"

# the browser test of the HTML reports (tests/test_reports_browser.py) drives Debian's headless
# Chromium through its chromedriver: installed here when missing and apt-get is usable (root);
# otherwise that test is skipped and says why
browser:
	@{ command -v chromium >/dev/null 2>&1 && command -v chromedriver >/dev/null 2>&1; } || \
	    { [ "$$(id -u)" = 0 ] && command -v apt-get >/dev/null 2>&1 && apt-get update -qq && \
	    DEBIAN_FRONTEND=noninteractive apt-get install -y -qq chromium chromium-driver >/dev/null; } || \
	    echo "note: chromium and chromium-driver are not installed and cannot be installed here: the browser test is skipped"

importers: $(FMI_SIM) $(FMI4J_CP) $(FMIPP_STAMP)

# Wine runs the FMUs' win64 binaries in the tests (tests/test_win64.py): Debian's wine64, installed
# here when missing and apt-get is usable (root); otherwise that test is skipped and says why
wine-tools:
	@command -v wine64 >/dev/null 2>&1 || command -v wine >/dev/null 2>&1 || [ -x /usr/lib/wine/wine64 ] || \
	    { [ "$$(id -u)" = 0 ] && command -v apt-get >/dev/null 2>&1 && apt-get update -qq && \
	    DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends $(WINE_APT) >/dev/null; } || \
	    echo "note: Wine (Debian $(WINE_APT)) is not installed and cannot be installed here: the win64 run is skipped"

$(FMI_SIM): | fuzz-tools
	@mkdir -p $(dir $@); rm -f $@.skip
	@if [ ! -x $(FMI_SIM_ROOT)/bin/fmi-sim ]; then \
	    if ! command -v cargo >/dev/null 2>&1; then \
	        echo "fmi-sim $(FMI_SIM_VERSION) not installed: cargo (Rust) is not installed" > $@.skip; \
	    else echo "cargo install fmi-sim $(FMI_SIM_VERSION) (crates.io) into $(FMI_SIM_ROOT): once per machine, minutes"; \
	        nice cargo install -q fmi-sim --version $(FMI_SIM_VERSION) --locked --root $(FMI_SIM_ROOT) || \
	        echo "fmi-sim $(FMI_SIM_VERSION) not installed: cargo install from crates.io failed (offline? its fmi-sys build needs libclang: Debian clang)" > $@.skip; fi; fi
	@if [ -x $(FMI_SIM_ROOT)/bin/fmi-sim ]; then ln -sf $(FMI_SIM_ROOT)/bin/fmi-sim $@; else cat $@.skip; fi

$(FMI4J_CP): tests/java/pom.xml $(wildcard tests/java/src/main/java/feeddrive/fmi4j/*.java)
	@mkdir -p $(BUILD)/importers; rm -f $(BUILD)/importers/fmi4j.skip
	@if ! command -v java >/dev/null 2>&1 || ! command -v mvn >/dev/null 2>&1; then \
	    echo "FMI4j not installed: it needs a JDK (java) and Maven (mvn)" | tee $(BUILD)/importers/fmi4j.skip; \
	else mvn -q -B -f tests/java/pom.xml compile dependency:build-classpath -Dmdep.outputFile=$(CURDIR)/$@ || \
	    echo "FMI4j not installed: Maven could not resolve info.laht.fmi4j from Maven Central (offline?)" | \
	    tee $(BUILD)/importers/fmi4j.skip; fi

$(FMIPP_STAMP): $(STAMP) tools/patch_fmipp.py
	@mkdir -p $(BUILD)/importers; rm -f $(BUILD)/importers/fmipp.skip
	@skip=$(BUILD)/importers/fmipp.skip; \
	wheels=$(IMPORTERS_CACHE)/fmipp-$(FMIPP_VERSION)-$$($(PY) -c 'import sys; print(sys.implementation.cache_tag)'); \
	if ! ls $$wheels/fmipp-*.whl >/dev/null 2>&1; then \
	    if ! command -v swig >/dev/null 2>&1 || [ ! -e /usr/include/boost/filesystem.hpp ]; then \
	        [ "$$(id -u)" = 0 ] && command -v apt-get >/dev/null 2>&1 && \
	        apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq $(FMIPP_APT) >/dev/null; fi; \
	    if ! command -v swig >/dev/null 2>&1 || [ ! -e /usr/include/boost/filesystem.hpp ]; then \
	        echo "fmipp $(FMIPP_VERSION) not installed: it needs swig and boost (Debian: $(FMIPP_APT))" > $$skip; \
	    else echo "building fmipp $(FMIPP_VERSION) from its PyPI sdist into $$wheels: once per machine, minutes"; \
	        rm -rf $(FMIPP_SRC) && mkdir -p $(FMIPP_SRC) && \
	        $(PY) -m pip download -q --no-deps --no-binary :all: fmipp==$(FMIPP_VERSION) -d $(FMIPP_SRC) && \
	        tar xzf $(FMIPP_SRC)/fmipp-$(FMIPP_VERSION).tar.gz -C $(FMIPP_SRC) && \
	        $(PY) tools/patch_fmipp.py $(FMIPP_SRC)/fmipp-$(FMIPP_VERSION)/setup.py && \
	        nice $(PY) -m pip wheel -q --no-deps -w $$wheels $(FMIPP_SRC)/fmipp-$(FMIPP_VERSION) >/dev/null || \
	        echo "fmipp $(FMIPP_VERSION) not installed: its PyPI sdist did not download or build (offline?)" > $$skip; fi; fi; \
	if ls $$wheels/fmipp-*.whl >/dev/null 2>&1; then \
	    $(PY) -m pip install -q --no-deps --force-reinstall $$wheels/fmipp-*.whl && touch $@; else cat $$skip; fi

# ruff with the rules of python/pyproject.toml (ruff.toml points there) over the repository's
# Python (the FMU generators included), its formatter in check mode, then mypy over the package
# (strict where the configuration says); all three run and print every problem with its file and
# line, and any fails the target
LINT_PY := python tests tools examples fmu_src
lint: $(STAMP)
	@status=0; $(PY) -m ruff check $(LINT_PY) || status=1; \
	$(PY) -m ruff format --check $(LINT_PY) || status=1; \
	$(PY) -m mypy --config-file python/pyproject.toml python/feeddrive || status=1; exit $$status

# the suite on TEST_WORKERS processes (pytest-xdist; default one per core), the tests of one
# file in one process (their module fixtures and C-host builds stay together), the files handed
# out in collection order, the longest first (tests/conftest.py HEAVY_FIRST; xdist's own order,
# by number of tests, leaves a long file of few tests running alone at the end); TEST_WORKERS=0: one
TEST_WORKERS ?= $(shell nproc 2>/dev/null || echo 2)
test: lint fmu fuzz-tools browser importers wine-tools
	$(PY) -m pytest -q -n $(TEST_WORKERS) --dist loadfile --no-loadscope-reorder tests

# the C benchmark hosts are test code (tests/c); built here and handed to the benchmark
bench: fmu
	$(MAKE) -s -C tests/c $(TESTS_C)/bench_cs $(TESTS_C)/cycles $(TESTS_C)/two_fmus
	$(PY) -m feeddrive.bench --out $(BUILD)/bench.md --bench-cs $(TESTS_C)/bench_cs \
	    --cycles $(TESTS_C)/cycles --library $(SO) --two-fmus $(TESTS_C)/two_fmus \
	    --controller-library $(CTRL_SO)

# the site: docs/*.md, the API pages from the docstrings (mkdocstrings), CHANGELOG.md and LICENSE
# included; --strict turns every warning (a broken link or anchor, an unreadable docstring) into
# an error. tests/test_docs.py builds it too and runs its code examples.
docs: $(STAMP)
	NO_MKDOCS_2_WARNING=1 $(PY) -m mkdocs build --strict --site-dir $(BUILD)/docs
	@echo "the site: $(BUILD)/docs/index.html"

# coverage of identify --bootstrap intervals over 20 FMU campaigns, the parametric
# (bias-corrected) and the whole-run percentile method (docs/intervals.md): about 8 min
# (parametric) and 5 min (runs) of CPU on one core
interval-coverage: fmu
	nice $(PY) -m feeddrive.study.coverage --campaigns 20 --replicates 10 --repeats 2 \
	    --method parametric --out $(BUILD)/coverage_parametric.json
	nice $(PY) -m feeddrive.study.coverage --campaigns 20 --replicates 20 --repeats 2 \
	    --method runs --out $(BUILD)/coverage_runs.json

wheel: $(PKG_FMU) $(PKG_CTRL_FMU) $(PKG_FMU3) $(PKG_CTRL3_FMU)
	rm -rf $(BUILD)/feeddrive-*.whl python/build
	$(PY) -m pip wheel -q --no-deps -w $(BUILD) ./python

clean:
	rm -rf $(BUILD) $(PKG_FMU) $(PKG_CTRL_FMU) $(PKG_FMU3) $(PKG_CTRL3_FMU)
